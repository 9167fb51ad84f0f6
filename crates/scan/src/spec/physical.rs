//! `[physical]`: the table both kinds of spec read ([`PhysicalFile`],
//! converted by [`Physical::params`], McMillan's scaling) read as the nondimensional
//! `[model]` it stands for. `c`, `v_belt`, `mu_s` and `tau` may be swept (then the model's keys
//! they become are, [`crate::space::model_key`]); the other keys are numbers, since a
//! scan's grid has one length and one velocity unit. The
//! grid (or the sample region) of a physical spec is in metres and m/s. `mu_s` and `tau`
//! are McMillan's surfaces: his laws need them, Coulomb refuses them; `law = "table"` takes
//! its measured curve here (`friction_table` or `friction_csv`, slip speed in m/s) and no
//! `mu_k` ([`squeal_core::units::check_friction_keys`]). `normal_force` (N) presses the
//! block on the belt in place of its weight `m g` ([`Load`]); `g` beside it is refused.

use squeal_core::units::{G_STANDARD, SURFACE_KEYS, check_friction_keys, takes_surface};
use squeal_core::{CoreError, FrictionLaw, FrictionTable, Load, Physical};

use super::Invalid;
use crate::bounds::Rules;
use crate::error::ScanError;
use crate::grid::Grid;
use crate::values::Value;
use serde::Deserialize;

/// The `[physical]` table: the physical system in SI units (read by the scan spec and
/// the atlas spec, [`crate::atlas::spec`], and built from the command line's `--m --k --c
/// --v-belt --mu-k --mu-s --tau-s --g --normal-force --friction-csv`).
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(crate) struct PhysicalFile {
    pub(crate) m: Value,
    pub(crate) k: Value,
    pub(crate) c: Value,
    pub(crate) v_belt: Value,
    /// McMillan's laws and Coulomb ([`check_friction_keys`]).
    #[serde(default)]
    pub(crate) mu_k: Option<Value>,
    /// McMillan's laws only ([`check_friction_keys`]).
    #[serde(default)]
    pub(crate) mu_s: Option<Value>,
    /// McMillan's laws only ([`check_friction_keys`]).
    #[serde(default)]
    pub(crate) tau: Option<Value>,
    /// `law = "table"`: the measured curve, `[[s, mu], ...]` with `s` in m/s.
    #[serde(default)]
    pub(crate) friction_table: Option<Vec<Vec<f64>>>,
    /// `law = "table"`: the measured curve as a CSV file (slip speed in m/s, mu), relative
    /// to the spec's folder.
    #[serde(default)]
    pub(crate) friction_csv: Option<String>,
    #[serde(default)]
    pub(crate) g: Option<Value>,
    /// The normal force (N) in place of the weight `m g` ([`Load`]).
    #[serde(default)]
    pub(crate) normal_force: Option<Value>,
}

impl PhysicalFile {
    /// The load of `g` and `normal_force` as given (`g` = [`G_STANDARD`] when neither is):
    /// both given is refused naming `physical.normal_force`.
    pub(crate) fn load(&self, invalid: Invalid) -> Result<Load<Value>, ScanError> {
        Load::of(
            self.g.clone(),
            self.normal_force.clone(),
            Value::One(G_STANDARD),
        )
        .map_err(|e| physical_error(e, invalid))
    }

    /// Refuses a friction key `law` does not use, and asks for one it needs (the error
    /// names the key and the law).
    pub(crate) fn check_friction_keys(
        &self,
        law: FrictionLaw,
        invalid: Invalid,
    ) -> Result<(), ScanError> {
        let table = self.friction_table.is_some() || self.friction_csv.is_some();
        let given = [
            self.mu_k.is_some(),
            self.mu_s.is_some(),
            self.tau.is_some(),
            table,
        ];
        check_friction_keys(law, given).map_err(|e| match e {
            // The curve given as a CSV is named as given.
            CoreError::UnusedPhysicalKey {
                key: "friction_table",
                law,
            } if self.friction_csv.is_some() => physical_error(
                CoreError::UnusedPhysicalKey {
                    key: "friction_csv",
                    law,
                },
                invalid,
            ),
            e => physical_error(e, invalid),
        })
    }

    /// The measured curve in SI (slip speed in m/s) of `friction_table` or `friction_csv`
    /// (read relative to `folder`; `stored`, the SI curve a file stores, stands for them);
    /// `None` where the law takes none (checked by [`PhysicalFile::check_friction_keys`]).
    pub(crate) fn table(
        &self,
        folder: &std::path::Path,
        stored: Option<&'static FrictionTable>,
        invalid: Invalid,
    ) -> Result<Option<&'static FrictionTable>, ScanError> {
        if self.friction_table.is_none() && self.friction_csv.is_none() {
            return Ok(None);
        }
        let keys = (self.friction_table.as_deref(), self.friction_csv.as_deref());
        super::tables::friction_table("physical", keys, folder, stored, invalid).map(Some)
    }

    /// A spec read back from a file written before Coulomb's physical system lost `mu_s` and
    /// `tau` (they were required, then ignored): the keys its law does not use are dropped,
    /// as that code dropped them, so the file still reads. A key given several values is
    /// refused instead: that version made each value a point of the atlas (the same physics
    /// repeated), so the file holds more points than the spec without the key, and read as
    /// this version's its stored figures would land on the wrong points.
    pub(crate) fn forget_unused(
        &mut self,
        law: FrictionLaw,
        invalid: Invalid,
    ) -> Result<(), ScanError> {
        if takes_surface(law) != Ok(false) {
            return Ok(());
        }
        for (key, v) in SURFACE_KEYS.into_iter().zip([&self.mu_s, &self.tau]) {
            let n = match v {
                Some(Value::List(xs)) => xs.len(),
                Some(Value::Range(r)) => usize::try_from(r.count).unwrap_or(0),
                Some(Value::One(_)) | None => 1,
            };
            if n > 1 {
                return Err(invalid(
                    &format!("physical.{key}"),
                    format!("{n} values"),
                    &format!(
                        "at most one value: this file was written by an older squeal, and its \
                         spec swept {key}, which law = \"{law}\" does not use; that version made \
                         each value a point of its own, so its points cannot be read as this \
                         version's (rerun the spec without {key})"
                    ),
                ));
            }
        }
        (self.mu_s, self.tau) = (None, None);
        Ok(())
    }
}

/// A [`Physical::params`] error as a spec error naming the `[physical]` key it comes from
/// (a derived value names its sources, [`physical_key`]) and, for a surface key missing or
/// not used, the law.
pub(crate) fn physical_error(e: CoreError, invalid: Invalid) -> ScanError {
    let key = |k: &str| format!("physical.{}", physical_key(k));
    let meaning = squeal_core::units::friction_key_meaning;
    match e {
        CoreError::InvalidParameter {
            name,
            value,
            expected,
        } => invalid(
            &key(name),
            squeal_core::error::Number(value).to_string(),
            expected,
        ),
        // A figure made of several keys, named by the key at fault with its value.
        CoreError::Source { key: k, value, why } => {
            invalid(&key(k), squeal_core::error::Number(value).to_string(), &why)
        }
        CoreError::MissingPhysicalKey { key: k, law } => invalid(
            &key(k),
            "missing".into(),
            &format!("a value: law = \"{law}\" needs {k} ({})", meaning(k)),
        ),
        CoreError::UnusedPhysicalKey { key: k, law } => invalid(
            &key(k),
            "given".into(),
            &format!(
                "no such key under law = \"{law}\": it does not use {k} ({})",
                meaning(k)
            ),
        ),
        CoreError::BothLoads => invalid(
            &key("normal_force"),
            "given with g".into(),
            "no g beside it: the normal force N replaces the block's weight m g in the law \
             (friction is mu N); give normal_force for a pressed block, or g for one under its \
             own weight",
        ),
        // A measured curve whose speeds no f64 holds in the model's units.
        e @ CoreError::InvalidTable { .. } => {
            invalid(&key("friction_table"), "given".into(), &e.to_string())
        }
        e => invalid("physical", String::new(), &e.to_string()),
    }
}

/// The physical key a [`Physical::params`] error names: a derived nondimensional value
/// names the physical keys it comes from.
pub(crate) fn physical_key(name: &str) -> &str {
    match name {
        "nu" => "c (nu = c / (2 sqrt(m k)))",
        "lambda" => "v_belt (lambda = v_belt sqrt(m k) / (mu_k N), N = m g or normal_force)",
        // A measured curve's model (MODEL.md section 8).
        "xi" => "c (xi = c / (2 sqrt(m k)))",
        "v_d" => "v_belt (v_d = v_belt sqrt(m k) / N, N = m g or normal_force)",
        "phi" => "mu_s",
        n => n,
    }
}

/// Refuses a physical key given as a list or a range in a scan spec (even of one value)
/// that no model key stands for: a scan's maps are indexed by the model's keys (files store
/// their values, with the physical keys as SI twins, [`crate::space::model_key`]), and the
/// keys that set the grid's units are such keys ([`crate::space::SCALE_KEYS`]; swept, they
/// are refused first by [`crate::space::Space::check_map_units`]).
pub(crate) fn scan_sweeps_keys_with_a_model_twin(
    space: &crate::space::Space,
    invalid: Invalid,
) -> Result<(), ScanError> {
    let other = (space.params.iter())
        .find(|a| a.listed && crate::space::model_key(space.law, a.key).is_none());
    match (space.units, other) {
        (crate::space::Units::Physical, Some(a)) => Err(invalid(
            &format!("physical.{}", a.key),
            "a list or range".into(),
            &format!(
                "a number: a scan sweeps {}, which leave the units of its grid (in m and \
                 m/s) alone (sweep the others with squeal atlas)",
                crate::space::scan_keys_in_words()
            ),
        )),
        _ => Ok(()),
    }
}

/// The grid (or sample region) given in metres and m/s, in nondimensional units, checked
/// there under [`Rules::Today`] as a nondimensional one is (the atlas's box likewise):
/// with `m = 1e300` a grid 0.4 mm wide became 6e-300 units wide, 36 cells at one state;
/// with x0 in +-3 km (length unit 69 um) its starts lay beyond the classifier's escape
/// radius.
pub(crate) fn grid_to_nondimensional(
    grid: &mut Grid,
    ph: &Physical,
    rules: Rules,
    invalid: Invalid,
) -> Result<(), ScanError> {
    use crate::bounds::{Width, state_range};
    let s = ph.scales();
    let (table, x_key, v_key) = if grid.is_sample() {
        ("sample.region", "sample.region.x0", "sample.region.v0")
    } else {
        ("grid", "grid.x0", "grid.v0")
    };
    let inv = |key: &str, value: String, expected: &str| {
        invalid(
            key,
            value,
            &format!(
                "{expected}, in the model's units (the {table} in m and m/s scaled by \
                 [physical] m, k, mu_k and g or normal_force)"
            ),
        )
    };
    for (axis, unit, key) in [
        (&mut grid.x0, s.length, x_key),
        (&mut grid.v0, s.velocity, v_key),
    ] {
        let width = if axis.min < axis.max {
            Width::Positive
        } else {
            Width::MayBeEmpty
        };
        let scaled = [axis.min / unit, axis.max / unit];
        [axis.min, axis.max] = match rules {
            Rules::Today => state_range(key, &scaled, width, &inv)?,
            Rules::Stored => scaled,
        };
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::Plan;

    /// The brake of `scans/brake.toml`: 2 kg, 50 kN/m, mu_k 0.35, mu_s 0.45, 1 ms, 0.05 m/s.
    const BRAKE: &str = r#"
version = 1
[model]
law = "mcmillan"
[physical]
m = 2.0
k = 5.0e4
c = [5.0, 10.0]
v_belt = 0.05
mu_k = 0.35
mu_s = 0.45
tau = 1e-3
[grid]
x0 = { min = -1e-4, max = 2e-4, count = 4 }
v0 = { min = -0.01, max = 0.01, count = 3 }
[output]
path = "b.h5"
"#;

    #[test]
    fn physical_spec_is_the_scaled_model_and_grid() {
        let p = Plan::from_toml(BRAKE, "b.toml").unwrap();
        let ph = p.physical().expect("the physical system is kept");
        let s = ph.scales();
        // omega_0 = sqrt(5e4 / 2) = 158.1 rad/s; c = 2 sqrt(m k) nu = 632.5 nu.
        assert!((s.damping - 2.0 * (1.0e5f64).sqrt()).abs() < 1e-9);
        let sweep = p.sweep.as_ref().expect("c swept: nu swept");
        assert_eq!(sweep.names(), ["nu"]);
        for (nu, c) in sweep.axes[0].values.iter().zip([5.0, 10.0]) {
            assert!((nu * s.damping - c).abs() < 1e-12, "{nu}");
        }
        let want = ph.params(squeal_core::FrictionLaw::McMillan).unwrap();
        assert!((p.maps[0].lambda - want.lambda).abs() < 1e-12);
        let (got, want) = (
            p.maps[0].law.surface().unwrap(),
            want.law.surface().unwrap(),
        );
        assert!((got.tau - want.tau).abs() < 1e-12);
        assert!((got.phi - want.phi).abs() < 1e-12);
        // The grid was given in metres and m/s.
        assert!((p.map.grid.x0.max * s.length - 2e-4).abs() < 1e-15);
        assert!((p.map.grid.v0.min * s.velocity + 0.01).abs() < 1e-15);
    }

    #[test]
    fn bad_physical_specs_name_the_key() {
        let cases = [
            (BRAKE.replace("m = 2.0", "m = [1.0, 2.0]"), "physical.m"),
            (BRAKE.replace("mu_s = 0.45", "mu_s = 0.3"), "physical.mu_s"),
            (BRAKE.replace("k = 5.0e4", "k = -1.0"), "physical.k"),
            // c and v_belt may be swept together; a range of v_belt with one bad value
            // is named by its key.
            (
                BRAKE.replace("v_belt = 0.05", "v_belt = [0.05, -0.1]"),
                "physical.v_belt",
            ),
            (
                BRAKE.replace("[physical]", "nu = 0.01\n[physical]"),
                "model.nu",
            ),
            (
                BRAKE.replace("law = \"mcmillan\"", "law = \"stribeck\""),
                "`physical`",
            ),
            (BRAKE.replace("v_belt", "v_B"), "unknown field `v_B`"),
        ];
        for (text, key) in cases {
            let e = Plan::from_toml(&text, "b.toml").unwrap_err().to_string();
            assert!(e.contains(key), "{key}: {e}");
        }
    }

    /// The README's clamped pad (0.8 kg, 200 kN/m, 1.5 kN) with `normal_force` reads as
    /// the g-hack `g = N / m = 1875` read (the only way to state it before the key), map
    /// for map; `g` beside it, or a force <= 0 or not finite, is refused naming the key.
    #[test]
    fn a_normal_force_is_read_as_the_weight_it_replaces() {
        let pad = BRAKE
            .replace("m = 2.0", "m = 0.8")
            .replace("k = 5.0e4", "k = 2e5");
        let clamped = pad.replace("tau = 1e-3\n", "tau = 1e-3\nnormal_force = 1500.0\n");
        let hack = pad.replace("tau = 1e-3\n", "tau = 1e-3\ng = 1875.0\n");
        let (p, h) = (
            Plan::from_toml(&clamped, "b.toml").unwrap(),
            Plan::from_toml(&hack, "b.toml").unwrap(),
        );
        assert_eq!(p.maps, h.maps);
        assert_eq!(p.map.grid.x0.max, h.map.grid.x0.max);
        let ph = p.physical().unwrap();
        assert_eq!(ph.load, squeal_core::Load::NormalForce(1500.0));
        assert_eq!(ph.normal_force(), 1500.0);
        let bad = [
            "normal_force = 0.0",
            "normal_force = -1.0",
            "normal_force = nan",
            "normal_force = inf",
            "normal_force = [1000.0, 1500.0]",
            "normal_force = 1500.0\ng = 9.81",
        ];
        for b in bad {
            let text = pad.replace("tau = 1e-3\n", &format!("tau = 1e-3\n{b}\n"));
            let e = Plan::from_toml(&text, "b.toml").unwrap_err().to_string();
            assert!(e.contains("`physical.normal_force`"), "{b}: {e}");
        }
    }

    /// The brake's oscillator under Coulomb: Coulomb's force has no static peak and no
    /// surface time, so its `[physical]` table is m, k, c, v_belt, mu_k (and g).
    fn coulomb() -> String {
        BRAKE
            .replace("law = \"mcmillan\"", "law = \"coulomb\"")
            .replace("mu_s = 0.45\ntau = 1e-3\n", "")
    }

    /// A Coulomb system without mu_s and tau is read (before, both were required, then
    /// ignored: `missing field mu_s`); its maps are the same scaling's nu and lambda.
    #[test]
    fn a_coulomb_system_needs_no_surfaces() {
        let p = Plan::from_toml(&coulomb(), "c.toml").unwrap();
        let ph = p.physical().expect("the physical system is kept");
        assert_eq!(ph.friction.surface(), None);
        assert_eq!(p.maps[0].law, squeal_core::Friction::Coulomb);
        // nu = c / (2 sqrt(m k)) = 5 / (2 sqrt(1e5)) (README, "Units").
        assert!((p.maps[0].nu - 5.0 / (2.0 * 1e5f64.sqrt())).abs() < 1e-15);
    }

    /// mu_s or tau under Coulomb is refused by name, with the law (before, it was read and
    /// ignored); McMillan's laws without either are refused naming the missing one.
    #[test]
    fn surface_keys_follow_the_law() {
        let c = coulomb();
        let cases = [
            (
                c.replace("mu_k = 0.35", "mu_k = 0.35\nmu_s = 0.45"),
                "physical.mu_s",
            ),
            (
                c.replace("mu_k = 0.35", "mu_k = 0.35\ntau = 1e-3"),
                "physical.tau",
            ),
            (BRAKE.replace("mu_s = 0.45\n", ""), "physical.mu_s"),
            (BRAKE.replace("tau = 1e-3\n", ""), "physical.tau"),
            (
                BRAKE
                    .replace("\"mcmillan\"", "\"mcmillan-nonhysteretic\"")
                    .replace("tau = 1e-3\n", ""),
                "physical.tau",
            ),
        ];
        for (i, (text, key)) in cases.iter().enumerate() {
            let e = Plan::from_toml(text, "b.toml").unwrap_err().to_string();
            let law = if i < 2 { "coulomb" } else { "mcmillan" };
            assert!(
                e.contains(&format!("`{key}`")) && e.contains(&format!("law = \"{law}")),
                "{key}: {e}"
            );
        }
    }

    /// A spec stored by an older squeal in a Coulomb file or journal carries the mu_s and
    /// tau that version required: read back from the file it still validates (its law never
    /// used them), to the plan of the spec without them; given by a user it is refused.
    #[test]
    fn an_old_coulomb_spec_stored_in_a_file_still_reads() {
        let old = coulomb().replace("mu_k = 0.35", "mu_k = 0.35\nmu_s = 0.45\ntau = 1e-3");
        assert!(Plan::from_toml(&old, "c.toml").is_err());
        let stored = Plan::from_stored_toml(&old, "c.toml").unwrap();
        let now = Plan::from_toml(&coulomb(), "c.toml").unwrap();
        assert_eq!(stored.differs_from(&now), None);
        assert_eq!(stored.physical().unwrap().friction.surface(), None);
        // McMillan's laws use them: a stored spec without them is refused as before.
        assert!(Plan::from_stored_toml(&BRAKE.replace("tau = 1e-3\n", ""), "b.toml").is_err());
    }

    /// An older squeal's Coulomb atlas that swept mu_s made each value a point (c 2 values
    /// times mu_s 2 values: 4 points, the same physics twice); dropping the list would read
    /// the file as the 2 points of the spec without it, its figures on the wrong points. It
    /// is refused naming the key; a single value is still dropped.
    #[test]
    fn an_old_coulomb_atlas_that_swept_a_surface_is_refused() {
        use crate::atlas::AtlasPlan;
        let atlas = |surfaces: &str| {
            format!(
                "version = 1\n[model]\nlaw = \"coulomb\"\n[physical]\nm = 2.0\nk = 5.0e4\n\
                 c = [5.0, 10.0]\nv_belt = 0.05\nmu_k = 0.35\n{surfaces}\n[boundaries]\n\
                 fold = false\ncritical = false\n[output]\npath = \"a.h5\"\n"
            )
        };
        let one = AtlasPlan::from_stored_toml(&atlas("mu_s = 0.45\ntau = 1e-3"), "a.toml");
        assert_eq!(one.unwrap().space.n_points(), 2);
        for (surfaces, key) in [
            ("mu_s = [0.45, 0.5]\ntau = 1e-3", "physical.mu_s"),
            (
                "mu_s = 0.45\ntau = { from = 1e-3, to = 2e-3, count = 3 }",
                "physical.tau",
            ),
        ] {
            let e = AtlasPlan::from_stored_toml(&atlas(surfaces), "a.toml")
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(&format!("`{key}`")) && e.contains("older squeal"),
                "{e}"
            );
        }
    }

    /// The README's clamped pad on a measured curve under `[physical]` (slip speed in
    /// m/s): 0.8 kg, 200 kN/m, c = 20 N s/m, 0.3 m/s, N = 1500 N.
    const PAD: &str = r#"
version = 1
[model]
law = "table"
[physical]
m = 0.8
k = 2e5
c = 20.0
v_belt = 0.3
normal_force = 1500.0
friction_table = [[0.0, 0.48], [0.1, 0.43], [0.3, 0.4], [1.0, 0.37]]
[grid]
x0 = { min = -3e-3, max = 6e-3, count = 4 }
v0 = { min = -0.3, max = 0.3, count = 3 }
[output]
path = "p.h5"
"#;

    /// The pad's spec reads as the nondimensional table law it stands for (MODEL.md
    /// section 8: xi = c / (2 sqrt(m k)) = 0.025, v_d = v_B sqrt(m k) / N = 0.08, the
    /// curve's speeds over N / sqrt(m k) = 3.75 m/s, the grid over N / k = 7.5 mm and 3.75
    /// m/s), and as the g-hack g = N / m = 1875 map for map. Fails on fdec01a, where
    /// `[physical]` was refused with law = "table" and had no friction_table key.
    #[test]
    fn a_measured_curve_in_si_reads_as_the_model_it_stands_for() {
        let p = Plan::from_toml(PAD, "p.toml").unwrap();
        let nd = Plan::from_toml(
            r#"
version = 1
[model]
law = "table"
xi = 0.025
v_d = 0.08
friction_table = [[0.0, 0.48], [0.02666666666666667, 0.43], [0.08, 0.4], [0.26666666666666666, 0.37]]
[grid]
x0 = { min = -0.4, max = 0.8, count = 4 }
v0 = { min = -0.08, max = 0.08, count = 3 }
[output]
path = "p.h5"
"#,
            "p.toml",
        )
        .unwrap();
        let (a, b) = (p.maps[0], nd.maps[0]);
        assert!((a.nu - b.nu).abs() < 1e-15 && (a.lambda - b.lambda).abs() < 1e-15);
        let (ta, tb) = (a.law.table().unwrap().rows(), b.law.table().unwrap().rows());
        for ((s1, m1), (s2, m2)) in ta.iter().zip(&tb) {
            assert!((s1 - s2).abs() < 1e-16 && m1 == m2, "{s1} vs {s2}");
        }
        assert!(
            (p.map.grid.x0.max - 0.8).abs() < 1e-15 && (p.map.grid.v0.min + 0.08).abs() < 1e-15
        );
        let hack = Plan::from_toml(
            &PAD.replace("normal_force = 1500.0", "g = 1875.0"),
            "p.toml",
        );
        assert_eq!(hack.unwrap().maps, p.maps);
        let ph = p.physical().unwrap();
        assert_eq!(ph.friction.table().unwrap().rows()[3], (1.0, 0.37));
    }

    /// A measured curve in m/s refused by name: a negative or unordered speed (the row
    /// named), `mu_k` or surfaces beside it, no curve, both keys, the curve in `[model]`
    /// beside `[physical]`, a curve under another law. Fails on fdec01a (every case was
    /// refused as `physical` with law = "table", or as an unknown field).
    #[test]
    fn a_bad_measured_curve_in_si_is_named() {
        let cases = [
            (
                PAD.replace("[0.1, 0.43]", "[-0.1, 0.43]"),
                "`physical.friction_table`",
                "row 2",
            ),
            (
                PAD.replace("[0.0, 0.48]", "[-0.05, 0.48]"),
                "`physical.friction_table`",
                "row 1",
            ),
            (
                PAD.replace("normal_force", "mu_k = 0.4\nnormal_force"),
                "`physical.mu_k`",
                "does not use mu_k",
            ),
            (
                PAD.replace("normal_force", "mu_s = 0.5\nnormal_force"),
                "`physical.mu_s`",
                "table",
            ),
            (
                PAD.replace(
                    "friction_table = [[0.0, 0.48], [0.1, 0.43], [0.3, 0.4], [1.0, 0.37]]\n",
                    "",
                ),
                "`physical.friction_table`",
                "needs friction_table",
            ),
            (
                PAD.replace("normal_force", "friction_csv = \"pad.csv\"\nnormal_force"),
                "`physical.friction_csv`",
                "exactly one",
            ),
            (
                PAD.replace(
                    "law = \"table\"",
                    "law = \"table\"\nfriction_csv = \"pad.csv\"",
                ),
                "`model.friction_csv`",
                "m/s",
            ),
            (
                PAD.replace("law = \"table\"", "law = \"coulomb\"")
                    .replace("normal_force", "mu_k = 0.4\nnormal_force"),
                "`physical.friction_table`",
                "coulomb",
            ),
        ];
        for (text, key, words) in cases {
            let e = Plan::from_toml(&text, "p.toml").unwrap_err().to_string();
            assert!(e.contains(key) && e.contains(words), "{key}: {e}");
        }
    }

    /// A row of three numbers, or of one, is refused naming the key, the row and what a
    /// row holds, in `[physical]` and in `[model]` alike: the third number was dropped
    /// without a word (and a CSV row of three numbers was refused).
    #[test]
    fn a_table_row_of_other_than_two_numbers_is_refused_naming_the_row() {
        let nd = PAD.replace(
            "[physical]\nm = 0.8\nk = 2e5\nc = 20.0\nv_belt = 0.3\nnormal_force = 1500.0\n",
            "xi = 0.025\nv_d = 0.08\n",
        );
        assert!(Plan::from_toml(&nd, "p.toml").is_ok(), "{nd}");
        for (text, key) in [
            (PAD.to_string(), "`physical.friction_table`"),
            (nd, "`model.friction_table`"),
        ] {
            for (row, words) in [("[0.1, 0.43, 7.0]", "row 2"), ("[0.1]", "row 2")] {
                let bad = text.replace("[0.1, 0.43]", row);
                let e = Plan::from_toml(&bad, "p.toml").unwrap_err().to_string();
                assert!(
                    e.contains(key) && e.contains(words) && e.contains("slip speed, mu"),
                    "{row}: {e}"
                );
            }
        }
    }

    /// The pad's curve in percent, in mm/s, or under a belt speed in mm/s reads (each can be
    /// meant), with one sentence each naming the key as given, before anything runs; the
    /// curve as measured has none. Fails on d424b26, which had no warnings to give.
    #[test]
    fn a_measured_curve_in_percent_or_mm_per_s_is_warned_of() {
        let rows = "[[0.0, 0.48], [0.1, 0.43], [0.3, 0.4], [1.0, 0.37]]";
        let warnings = |text: &str| Plan::from_toml(text, "p.toml").unwrap().space.warnings();
        assert_eq!(warnings(PAD), Vec::<String>::new());
        let percent = PAD.replace(rows, "[[0.0, 48.0], [0.1, 43.0], [0.3, 40.0], [1.0, 37.0]]");
        let w = warnings(&percent);
        assert!(
            w.len() == 1 && w[0].starts_with("`physical.friction_table`: mu reaches 48"),
            "{w:?}"
        );
        let mm = PAD.replace(
            rows,
            "[[0.0, 0.48], [100.0, 0.43], [300.0, 0.4], [1000.0, 0.37]]",
        );
        let w = warnings(&mm);
        assert!(
            w.len() == 1 && w[0].contains("run to 1000 m/s") && w[0].contains("mm/s"),
            "{w:?}"
        );
        let fast = warnings(&PAD.replace("v_belt = 0.3", "v_belt = 300.0"));
        assert!(
            fast.len() == 1
                && fast[0].starts_with("`physical.v_belt` = 300 m/s is beyond")
                && fast[0].ends_with("give 0.3 m/s"),
            "{fast:?}"
        );
    }

    /// A clamp of 1e308 N makes the pad's belt speed v_d = 1.2e-306 in the model's units,
    /// below the step (Params::check_step): refused naming `physical.normal_force` with the
    /// value given; a belt of 1e-12 m/s names `physical.v_belt`. Fails on d424b26, which
    /// ran both.
    #[test]
    fn a_belt_speed_below_the_step_is_refused_by_its_key() {
        let given = "v_belt = 0.3\nnormal_force = 1500.0";
        for (edit, key) in [
            (
                "v_belt = 0.3\nnormal_force = 1e308",
                "`physical.normal_force` = 1e308",
            ),
            (
                "v_belt = 1e-12\nnormal_force = 1500.0",
                "`physical.v_belt` = 1e-12",
            ),
        ] {
            let text = PAD.replace(given, edit);
            let e = Plan::from_toml(&text, "p.toml").unwrap_err().to_string();
            assert!(e.contains(key) && e.contains("dt = 0.005"), "{e}");
        }
    }
}
