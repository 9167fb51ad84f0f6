//! The tables a scan spec and an atlas spec share, each parsed and checked here once:
//! `[integration]`, `[output]`, the spec's `name`, and the key rules of `[model]` (a law's
//! own keys only; the nondimensional model or `[physical]`, not both). The scan
//! ([`crate::spec`]) and the atlas ([`crate::atlas::spec`]) read them into their own shapes.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};
use squeal_core::error::Number;
use squeal_core::{FrictionLaw, Scheme, SolverConfig, SolverKind};

use super::Invalid;
use crate::bounds::{Rules, count};
use crate::error::ScanError;
use crate::ulc::CycleSettings;
use crate::values::Value;

/// The `[model]` table: the law and its own keys, each a number, a list or a range (a scan
/// and an atlas sweep any of them, one map or point per point of the product). The accepted keys are every law's ([`FrictionLaw::keys`]), so a new law's
/// keys need no edit here; an unknown key is refused as serde refuses an unknown field.
#[derive(Debug, Clone)]
pub(crate) struct ModelTable {
    pub(crate) law: FrictionLaw,
    /// The keys given, with their values, in the order written.
    pub(crate) keys: Vec<(&'static str, Value)>,
    /// The table law's rows, `friction_table = [[s, mu], ...]`, as given (each row's length
    /// checked by [`friction_table`]: a third number was dropped without a word).
    pub(crate) friction_table: Option<Vec<Vec<f64>>>,
    /// The table law's CSV file, `friction_csv = "pad.csv"` (relative to the spec's folder).
    pub(crate) friction_csv: Option<String>,
}

/// The table law's keys (not scalars, so not [`FrictionLaw::keys`]).
pub(crate) const TABLE_KEYS: [&str; 2] = ["friction_table", "friction_csv"];

/// Largest friction CSV read, in bytes (10000 rows of two numbers fit in well under 1 MB).
pub const MAX_CSV_BYTES: u64 = 1 << 20;

/// Reads a friction CSV file ([`squeal_core::FrictionTable::from_csv`]); the error is a
/// sentence without the key (the caller names it): the file's trouble or its bad line.
pub fn read_friction_csv(
    path: &std::path::Path,
) -> Result<&'static squeal_core::FrictionTable, String> {
    use std::io::Read;
    crate::files::refuse_non_regular(path)
        .map_err(|e| format!("cannot read {}: it is {}", path.display(), e.what))?;
    let file =
        std::fs::File::open(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let mut bytes = Vec::new();
    file.take(MAX_CSV_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    if bytes.len() as u64 > MAX_CSV_BYTES {
        return Err(format!(
            "{} is longer than {MAX_CSV_BYTES} bytes: not a friction table of at most 10000 rows",
            path.display()
        ));
    }
    let text = String::from_utf8(bytes)
        .map_err(|e| format!("{} is not UTF-8 text: {e}", path.display()))?;
    squeal_core::FrictionTable::from_csv(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The curve of `friction_table` or `friction_csv` (`keys`, as given in the table `table`:
/// `model`, or `physical` where the slip speeds are in m/s), exactly one of them; the CSV is
/// read relative to `folder`; `stored` (the table an output file holds for that key) stands
/// for them when a stored spec is read again. Errors name `<table>.<key>`.
pub(crate) fn friction_table(
    table: &str,
    keys: (Option<&[Vec<f64>]>, Option<&str>),
    folder: &std::path::Path,
    stored: Option<&'static squeal_core::FrictionTable>,
    invalid: Invalid,
) -> Result<&'static squeal_core::FrictionTable, ScanError> {
    let unit = if table == "physical" { " in m/s" } else { "" };
    let how = format!(
        "law = \"table\" needs its curve: friction_table = [[s, mu], ...] (slip speed{unit}, \
         the first row at slip speed 0) or friction_csv = \"file.csv\" (two columns), exactly \
         one of them"
    );
    let key = |k: &str| format!("{table}.{k}");
    match keys {
        (Some(_), Some(_)) => Err(invalid(
            &key("friction_csv"),
            format!("given with {}", key("friction_table")),
            &how,
        )),
        (None, None) => Err(invalid(&key("friction_table"), "missing".into(), &how)),
        _ if stored.is_some() => Ok(stored.expect("some")),
        (Some(rows), None) => pairs(rows)
            .and_then(|rows| squeal_core::FrictionTable::new(&rows))
            .map_err(|e| invalid(&key("friction_table"), "given".into(), &e.to_string())),
        (None, Some(csv)) => read_friction_csv(&folder.join(csv))
            .map_err(|e| invalid(&key("friction_csv"), format!("{csv:?}"), &e)),
    }
}

/// The rows of `friction_table` as pairs, each row two numbers: a row of three was cut to
/// two without a word (a CSV line of three is refused), a row of one failed unnamed.
fn pairs(rows: &[Vec<f64>]) -> Result<Vec<(f64, f64)>, squeal_core::CoreError> {
    rows.iter()
        .enumerate()
        .map(|(i, r)| match r[..] {
            [s, mu] => Ok((s, mu)),
            _ => Err(squeal_core::CoreError::InvalidTable {
                unit: "row",
                row: i + 1,
                reason: format!(
                    "[{}] holds {} number(s), expected two: [slip speed, mu]",
                    r.iter()
                        .map(|x| Number(*x).to_string())
                        .collect::<Vec<_>>()
                        .join(", "),
                    r.len()
                ),
            }),
        })
        .collect()
}

/// The keys a `[model]` table accepts: `law`, then every law's keys, each once.
fn model_fields() -> &'static [&'static str] {
    static FIELDS: std::sync::OnceLock<Vec<&'static str>> = std::sync::OnceLock::new();
    FIELDS.get_or_init(|| {
        let mut f = vec!["law"];
        for k in FrictionLaw::ALL.iter().flat_map(|l| l.keys()) {
            if !f.contains(k) {
                f.push(k);
            }
        }
        f.extend(TABLE_KEYS);
        f
    })
}

impl<'de> Deserialize<'de> for ModelTable {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visit;
        impl<'de> serde::de::Visitor<'de> for Visit {
            type Value = ModelTable;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("the [model] table")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut a: A,
            ) -> Result<ModelTable, A::Error> {
                use serde::de::Error;
                let (mut law, mut keys) = (None, Vec::new());
                let (mut friction_table, mut friction_csv) = (None, None);
                while let Some(k) = a.next_key::<String>()? {
                    let Some(&key) = model_fields().iter().find(|f| **f == k) else {
                        return Err(A::Error::unknown_field(&k, model_fields()));
                    };
                    if key == "law" {
                        law = Some(a.next_value::<FrictionLaw>()?);
                    } else if key == "friction_table" {
                        friction_table = Some(a.next_value::<Vec<Vec<f64>>>()?);
                    } else if key == "friction_csv" {
                        friction_csv = Some(a.next_value::<String>()?);
                    } else {
                        // Every key of every law may be a list or a range (swept).
                        keys.push((key, a.next_value::<Value>()?));
                    }
                }
                let law = law.ok_or_else(|| A::Error::missing_field("law"))?;
                Ok(ModelTable {
                    law,
                    keys,
                    friction_table,
                    friction_csv,
                })
            }
        }
        d.deserialize_map(Visit)
    }
}

impl ModelTable {
    /// Whether the spec gives `key`.
    fn has(&self, key: &str) -> bool {
        self.given(key).is_some()
    }

    /// A key's value as given: a law's coefficients other than [`sweepable`] ones are
    /// numbers in the table, the others may be lists (refused by a scan, swept by an atlas).
    pub(crate) fn given(&self, key: &str) -> Option<Value> {
        self.keys
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, v)| v.clone())
    }

    /// The table law's table: `friction_table` or `friction_csv` (read relative to
    /// `folder`), exactly one of them, and neither for another law; `stored` (the table an
    /// output file holds) stands for them when a stored spec is read again. `None` for the
    /// other laws.
    pub(crate) fn table(
        &self,
        folder: &std::path::Path,
        stored: Option<&'static squeal_core::FrictionTable>,
        invalid: Invalid,
    ) -> Result<Option<&'static squeal_core::FrictionTable>, ScanError> {
        if self.law != FrictionLaw::Table {
            let given = [self.friction_table.is_some(), self.friction_csv.is_some()];
            if let Some((k, _)) = TABLE_KEYS.into_iter().zip(given).find(|(_, g)| *g) {
                return Err(invalid(
                    &format!("model.{k}"),
                    format!("given with law = \"{}\"", self.law),
                    "no key: only law = \"table\" takes a friction table",
                ));
            }
            return Ok(None);
        }
        let keys = (self.friction_table.as_deref(), self.friction_csv.as_deref());
        friction_table("model", keys, folder, stored, invalid).map(Some)
    }

    /// Refuses a key that is not one of the law's own ([`FrictionLaw::keys`]).
    pub(crate) fn check_law(&self, invalid: Invalid) -> Result<(), ScanError> {
        let own = self.law.keys();
        let foreign = FrictionLaw::ALL
            .iter()
            .flat_map(|l| l.keys())
            .find(|k| !own.contains(k) && self.has(k));
        match foreign {
            None => Ok(()),
            Some(k) => Err(invalid(
                &format!("model.{k}"),
                "given".into(),
                &format!(
                    "a key of law = \"{}\" (its keys: {})",
                    self.law,
                    own.join(", ")
                ),
            )),
        }
    }

    /// With `[physical]`: refuses a law without physical units (the Stribeck and cubic
    /// laws: McMillan's scaling and the table law's are written in mu_k N and N, their
    /// coefficients' speeds would need a unit of their own) and any nondimensional key of
    /// the law, its table among them (the model or the physical system, not both; a table
    /// under `[physical]` has its slip speeds in m/s).
    pub(crate) fn check_physical(&self, invalid: Invalid) -> Result<(), ScanError> {
        if squeal_core::units::friction_keys(self.law).is_err() {
            return Err(invalid(
                "physical",
                format!("given with law = \"{}\"", self.law),
                "a McMillan law, Coulomb or a measured curve (law = \"table\"): the physical \
                 units are McMillan's scaling (x scaled by mu_k N / k, lambda = v_belt sqrt(m k) \
                 / (mu_k N), tau and Phi from the surfaces) or the table's (force unit N), which \
                 the Stribeck and cubic laws do not share (give their nondimensional keys in \
                 [model])",
            ));
        }
        let table = [self.friction_table.is_some(), self.friction_csv.is_some()];
        let given = self.keys.first().map(|(k, _)| *k).or_else(|| {
            TABLE_KEYS
                .into_iter()
                .zip(table)
                .find_map(|(k, g)| g.then_some(k))
        });
        match given {
            None => Ok(()),
            Some(k) => Err(invalid(
                &format!("model.{k}"),
                "given with [physical]".into(),
                "either the nondimensional model ([model] nu, lambda, tau, phi; xi, v_d and the \
                 table of law = \"table\") or the physical system ([physical] m, k, c, v_belt, \
                 g or normal_force, with mu_k, and mu_s, tau for McMillan's two laws, or \
                 friction_table or friction_csv in m/s for law = \"table\"), not both",
            )),
        }
    }
}

/// The `[integration]` table.
#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct IntegrationTable {
    dt: Option<f64>,
    #[serde(default)]
    solver: SolverKind,
    #[serde(default)]
    scheme: Scheme,
    max_iter: Option<i64>,
}

/// Largest iteration cap of the `paper` solver.
pub const MAX_ITER_CAP: i64 = 100_000;

impl IntegrationTable {
    /// The step and the solver; under [`Rules::Today`] checked: `0 < dt <= 1`, `max_iter`
    /// in `1..=100000`.
    pub(crate) fn check(
        &self,
        rules: Rules,
        invalid: Invalid,
    ) -> Result<(f64, SolverConfig), ScanError> {
        let dt = self.dt.unwrap_or(squeal_core::defaults::DT);
        rules.require(dt.is_finite() && dt > 0.0 && dt <= 1.0, || {
            invalid(
                "integration.dt",
                Number(dt).to_string(),
                "a finite step in (0, 1]",
            )
        })?;
        let max_iter = self
            .max_iter
            .unwrap_or(squeal_core::defaults::MAX_ITER as i64);
        rules.require((1..=MAX_ITER_CAP).contains(&max_iter), || {
            invalid(
                "integration.max_iter",
                max_iter.to_string(),
                "an iteration cap in 1..=100000",
            )
        })?;
        let solver = SolverConfig {
            kind: self.solver,
            scheme: self.scheme,
            max_iter: count(
                "integration.max_iter",
                max_iter,
                "an iteration cap",
                invalid,
            )?,
            ..SolverConfig::default()
        };
        Ok((dt, solver))
    }
}

/// The `[cycle]` table, one for both kinds of spec: whether to locate the unstable cycle
/// (scans only: an atlas's figures are the cycle's) and the section search's settings
/// ([`crate::ulc::CycleSettings`]), each checked once here ([`crate::bounds::cycle_search`]).
#[derive(Deserialize, Debug, Default, Clone)]
#[serde(deny_unknown_fields)]
pub(crate) struct CycleTable {
    locate: Option<bool>,
    r_min: Option<f64>,
    r_max: Option<f64>,
    samples: Option<i64>,
    rtol: Option<f64>,
    t_return: Option<f64>,
    half_dt: Option<bool>,
    tangency_iters: Option<i64>,
}

/// Which spec a table is read for: the keys that mean something and the defaults differ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Shape {
    /// A scan spec ([`crate::spec::Plan`]).
    Scan,
    /// An atlas spec ([`crate::atlas::AtlasPlan`]).
    Atlas,
}

impl CycleTable {
    /// The settings, checked under [`Rules::Today`]. Defaults: [`CycleOptions::scan`] and
    /// [`CycleOptions::atlas`].
    pub(crate) fn check(
        &self,
        shape: Shape,
        rules: Rules,
        invalid: Invalid,
    ) -> Result<CycleOptions, ScanError> {
        let mut o = match shape {
            Shape::Scan => CycleOptions::scan(),
            Shape::Atlas => CycleOptions::atlas(),
        };
        match (shape, self.locate, self.tangency_iters) {
            (Shape::Atlas, Some(false), _) => {
                return Err(invalid(
                    "cycle.locate",
                    "false".into(),
                    "true or no key: an atlas always locates the cycle (its figures are the \
                     cycle's)",
                ));
            }
            (Shape::Scan, _, Some(t)) => {
                return Err(invalid(
                    "cycle.tangency_iters",
                    t.to_string(),
                    "no key in a scan spec: only an atlas point refines a tangency of the \
                     return map",
                ));
            }
            _ => {}
        }
        o.locate = self.locate.unwrap_or(o.locate);
        let c = &mut o.search;
        c.r_min = self.r_min.unwrap_or(c.r_min);
        c.r_max = self.r_max.unwrap_or(c.r_max);
        o.r_max_given = self.r_max.is_some();
        c.rtol = self.rtol.unwrap_or(c.rtol);
        c.t_return = self.t_return.unwrap_or(c.t_return);
        c.check_half_dt = self.half_dt.unwrap_or(c.check_half_dt);
        let samples = self.samples.unwrap_or(c.samples as i64);
        rules.require(
            (3..=crate::bounds::MAX_CYCLE_SAMPLES as i64).contains(&samples),
            || {
                invalid(
                    "cycle.samples",
                    samples.to_string(),
                    "a count in 3..=100000",
                )
            },
        )?;
        c.samples = count("cycle.samples", samples, "a count of samples", invalid)?;
        rules.bound(|| crate::bounds::cycle_search(c, &|k| format!("cycle.{k}"), invalid))?;
        let ti = self.tangency_iters.unwrap_or(o.tangency_iters as i64);
        rules.require((0..=200).contains(&ti), || {
            invalid("cycle.tangency_iters", ti.to_string(), "a count in 0..=200")
        })?;
        o.tangency_iters = count(
            "cycle.tangency_iters",
            ti,
            "a count of refinements",
            invalid,
        )?;
        Ok(o)
    }
}

/// The checked `[cycle]` table.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CycleOptions {
    /// Locate, store and draw the unstable cycle (a scan may leave it out; an atlas never).
    pub locate: bool,
    /// The section search. A scan's `r_max` follows its grid unless `r_max_given`
    /// ([`crate::scanner::cycle_settings`]); an atlas point raises it to `2 lambda`.
    pub search: CycleSettings,
    /// Whether the spec gave `cycle.r_max`.
    pub r_max_given: bool,
    /// Golden-section refinements of the largest negative `D` at an atlas point (0: none).
    pub tangency_iters: u32,
}

impl CycleOptions {
    /// A scan's defaults: [`CycleSettings::default`], the cycle located.
    pub fn scan() -> CycleOptions {
        CycleOptions {
            locate: true,
            search: CycleSettings::default(),
            r_max_given: false,
            tangency_iters: 0,
        }
    }

    /// An atlas's defaults: bisection to `rtol = 1e-9` (each point bisects once; its
    /// accuracy is the dt/2 shift, far larger) and 24 tangency refinements.
    pub fn atlas() -> CycleOptions {
        CycleOptions {
            search: CycleSettings {
                rtol: 1e-9,
                ..CycleSettings::default()
            },
            tangency_iters: 24,
            ..CycleOptions::scan()
        }
    }
}

/// The `[output]` table.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(crate) struct OutputTable {
    path: PathBuf,
}

impl OutputTable {
    /// The output path, checked not empty.
    pub(crate) fn check(&self, invalid: Invalid) -> Result<PathBuf, ScanError> {
        if self.path.as_os_str().is_empty() {
            return Err(invalid(
                "output.path",
                "\"\"".into(),
                "a file name ending in .h5",
            ));
        }
        Ok(self.path.clone())
    }
}

/// The spec's `name` (default: the spec file's name without `.toml`, or `fallback`), checked
/// printable: it goes into file attributes and picture titles, an HDF5 string cannot hold a
/// NUL, and the run would be lost at the final write.
pub(crate) fn check_name(
    name: Option<&str>,
    spec_path: &str,
    fallback: &str,
    invalid: Invalid,
) -> Result<String, ScanError> {
    let name = name.map(str::to_string).unwrap_or_else(|| {
        std::path::Path::new(spec_path)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| fallback.to_string())
    });
    if name.chars().any(char::is_control) || name.chars().count() > 200 {
        return Err(invalid(
            "name",
            format!("{name:?}"),
            "printable text of at most 200 characters (no control characters such as NUL)",
        ));
    }
    Ok(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn invalid(key: &str, value: String, expected: &str) -> ScanError {
        ScanError::Invalid {
            path: "t.toml".into(),
            key: key.into(),
            value,
            expected: expected.into(),
        }
    }

    #[test]
    fn one_integration_check_for_both_kinds_of_spec() {
        // The scan refused max_iter above 100000 and the atlas accepted up to 1000000: one
        // table, one rule now.
        let t: IntegrationTable = toml::from_str("max_iter = 200000").unwrap();
        let e = t.check(Rules::Today, &invalid).unwrap_err().to_string();
        assert!(e.contains("integration.max_iter"), "{e}");
        let t: IntegrationTable = toml::from_str("dt = 0.0").unwrap();
        assert!(
            t.check(Rules::Today, &invalid)
                .unwrap_err()
                .to_string()
                .contains("integration.dt")
        );
        let (dt, s) = IntegrationTable::default()
            .check(Rules::Today, &invalid)
            .unwrap();
        assert_eq!(dt, squeal_core::defaults::DT);
        assert_eq!(s.max_iter, squeal_core::defaults::MAX_ITER);
    }

    #[test]
    fn names_are_printable_and_default_to_the_file() {
        assert_eq!(
            check_name(None, "dir/fig9.toml", "x", &invalid).unwrap(),
            "fig9"
        );
        assert_eq!(check_name(None, "", "atlas", &invalid).unwrap(), "atlas");
        let e = check_name(Some("a\0b"), "a.toml", "x", &invalid).unwrap_err();
        assert!(e.to_string().contains("name"), "{e}");
    }

    #[test]
    fn both_kinds_of_spec_share_the_checks() {
        // An atlas took any name (a NUL was refused only by the scan) and any max_iter up
        // to 1e6; a scan read `tau = [...]` as a type error of the TOML parser. One table
        // each now, one rule, the key named.
        let atlas = |extra: &str| {
            format!(
                "version = 1\n{extra}\n[model]\nlaw = \"mcmillan\"\nnu = 0.01\n[output]\npath = \"a.h5\"\n"
            )
        };
        let e = crate::atlas::AtlasPlan::from_toml(&atlas("name = \"a\\u0000b\""), "a.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("`name`"), "{e}");
        let text = atlas("").replace("[output]", "[integration]\nmax_iter = 500000\n[output]");
        let e = crate::atlas::AtlasPlan::from_toml(&text, "a.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("integration.max_iter"), "{e}");
        // A scan sweeps any key of [model], but of [physical] only those that leave its
        // grid's units alone: the mass is swept by an atlas.
        let scan = "version = 1\n[model]\nlaw = \"mcmillan\"\n[physical]\nm = [1.0, 2.0]\n\
                    k = 5e4\nc = 5.0\nv_belt = 0.05\nmu_k = 0.35\nmu_s = 0.45\ntau = 1e-3\n\
                    [grid]\nx0 = { min = -1e-4, max = 1e-4, count = 2 }\n\
                    v0 = { min = -0.01, max = 0.01, count = 2 }\n[output]\npath = \"s.h5\"\n";
        let e = crate::Plan::from_toml(scan, "s.toml")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("physical.m") && e.contains("squeal atlas"),
            "{e}"
        );
    }

    #[test]
    fn one_cycle_table_for_both_kinds_of_spec() {
        // A scan's `[cycle]` had `locate` only, an atlas's the search keys only, parsed by two
        // structs with two checks: `samples = 200` in a scan spec was an unknown field.
        let scan = |cycle: &str| {
            format!(
                "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 0.01\n\
                 [grid]\nx0 = {{ min = -3.0, max = 5.0, count = 2 }}\n\
                 v0 = {{ min = -4.0, max = 4.0, count = 2 }}\n[cycle]\n{cycle}\n\
                 [output]\npath = \"s.h5\"\n"
            )
        };
        let atlas = |cycle: &str| {
            format!(
                "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 0.01\n[cycle]\n{cycle}\n\
                 [output]\npath = \"a.h5\"\n"
            )
        };
        let plan =
            crate::Plan::from_toml(&scan("samples = 200\nrtol = 1e-9\nr_max = 12.0"), "s").unwrap();
        assert_eq!(plan.cycle.search.samples, 200);
        assert_eq!(plan.cycle.search.rtol, 1e-9);
        let cs = crate::scanner::cycle_settings(&plan, &plan.maps[0]);
        assert_eq!((cs.r_max, cs.samples), (12.0, 200));
        // Without `r_max` the search follows the grid: 1.2 times its farthest start from the
        // fixed point (1, 0) (at rest on the belt the force is F(-lambda, 0) = 1, the Coulomb
        // limit): (-3, 4) and (-3, -4), sqrt(4^2 + 4^2) away.
        let plan = crate::Plan::from_toml(&scan("samples = 200"), "s").unwrap();
        let cs = crate::scanner::cycle_settings(&plan, &plan.maps[0]);
        let reach = crate::grid::grid_reach(&plan.map.grid, &plan.maps[0]);
        assert!((reach - 32f64.sqrt()).abs() < 1e-12, "{reach}");
        assert_eq!(cs.r_max, 1.2 * reach);
        // An r_max short of the grid is refused, naming the key.
        let e = crate::Plan::from_toml(&scan("r_max = 3.0"), "s")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("cycle.r_max") && e.contains("farthest start"),
            "{e}"
        );
        // The same bad value gives the same message in both kinds of spec.
        let bad = "rtol = 0.0";
        let a = crate::atlas::AtlasPlan::from_toml(&atlas(bad), "x").unwrap_err();
        let s = crate::Plan::from_toml(&scan(bad), "x").unwrap_err();
        assert_eq!(a.to_string(), s.to_string());
        assert!(a.to_string().contains("cycle.rtol"), "{a}");
        // What one kind cannot use, it refuses by name.
        let e = crate::atlas::AtlasPlan::from_toml(&atlas("locate = false"), "x").unwrap_err();
        assert!(e.to_string().contains("cycle.locate"), "{e}");
        let e = crate::Plan::from_toml(&scan("tangency_iters = 8"), "x").unwrap_err();
        assert!(e.to_string().contains("cycle.tangency_iters"), "{e}");
        // The atlas's own defaults come from the same table.
        let a = crate::atlas::AtlasPlan::from_toml(&atlas("samples = 120"), "x").unwrap();
        assert_eq!(a.point.cycle.samples, 120);
        assert_eq!(a.point.cycle.rtol, CycleOptions::atlas().search.rtol);
        assert_eq!(a.point.tangency_iters, 24);
    }

    /// A key that is not the law's own is refused by scans and atlases alike, naming it:
    /// Coulomb's force has no surface time, so `tau` under `law = "coulomb"` is refused (it
    /// was read and ignored before the laws carried their own parameters), and each law's
    /// keys are accepted.
    #[test]
    fn a_key_of_another_law_is_refused() {
        let scan = |model: &str| {
            format!(
                "version = 1\n[model]\n{model}\n[grid]\nx0 = {{ min = -1.0, max = 1.0, count = 2 }}\n\
                 v0 = {{ min = -1.0, max = 1.0, count = 2 }}\n[output]\npath = \"s.h5\"\n"
            )
        };
        for (model, key) in [
            ("law = \"coulomb\"\nnu = 0.01\ntau = 0.1", "model.tau"),
            ("law = \"mcmillan\"\nnu = 0.01\nmu_d = 0.4", "model.mu_d"),
            ("law = \"stribeck\"\nphi = 1.0", "model.phi"),
        ] {
            let e = crate::Plan::from_toml(&scan(model), "s.toml")
                .unwrap_err()
                .to_string();
            assert!(e.contains(key) && e.contains("its keys:"), "{model}: {e}");
        }
        for model in [
            "law = \"coulomb\"\nnu = 0.01",
            "law = \"stribeck\"\nxi = 0.1",
        ] {
            assert!(
                crate::Plan::from_toml(&scan(model), "s.toml").is_ok(),
                "{model}"
            );
        }
    }
}
