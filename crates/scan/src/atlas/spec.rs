//! Atlas specs: the TOML file (a serde mirror, unknown keys rejected) and the checked
//! [`AtlasPlan`]. Every value is checked here, naming the key, before any computing.
//!
//! ```toml
//! version = 1
//! name = "atlas-lambda-nu"           # optional, used in titles
//! [model]
//! law = "mcmillan"                   # mcmillan | mcmillan-nonhysteretic | coulomb | stribeck | cubic
//! # Nondimensional parameters (paper Section 4), each a number, a list, or a range
//! # { from = .., to = .., count = .., spacing = "linear" | "log" }:
//! nu = { from = 1e-3, to = 0.06, count = 64, spacing = "log" }
//! lambda = { from = 0.5, to = 6.0, count = 64 }
//! tau = 0.31622776601683794          # default 0.1 sqrt(10)
//! phi = 1.0                          # default 1
//! # ... or, instead of nu/lambda/tau/phi, the physical system (SI units), same forms:
//! # [physical]
//! # m = 1.0        # kg            k = 1e4      # N/m         c = 2.0   # N s/m
//! # v_belt = 0.1   # m/s           mu_k = 0.3   mu_s = 0.4    tau = 3e-3  # s
//! # g = 9.81       # m/s^2, default
//! # law = "stribeck" takes instead xi (default 0.05) and v_d (default 1.5), each a number,
//! # list or range, and the numbers mu_d = 0.5, mu_sd = 2, v_0 = 0.5, mu_v = 0 (the scan
//! # spec's defaults); no McMillan key and no [physical] (McMillan's scaling)
//! [integration]
//! dt = 0.01
//! solver = "robust"                  # robust | paper
//! scheme = "foh"                     # foh (force linear over a step) | zoh (held: the paper's)
//! [cycle]                            # the section search (crate::ulc)
//! r_min = 0.01                       # smallest section amplitude sampled
//! r_max = 6.0                        # largest (raised to 2 lambda where that is larger)
//! samples = 96
//! rtol = 1e-9                        # relative bisection width
//! half_dt = true                     # locate again with dt/2 (accuracy of each point)
//! [attractor]
//! transient = 40                     # stick-slip revolutions discarded
//! window = 40                        # revolutions measured
//! [operating_point]                  # default the state at rest; SI (m, m/s) in physical specs
//! x = 0.0
//! v = 0.0
//! [disturbance]                      # the box of the basin fraction; SI in physical specs
//! x = [-2.0, 4.0]
//! v = [-3.0, 3.0]
//! [boundaries]
//! in = "nu"                          # bisect in nu or lambda; default nu if nu (c) is
//!                                    # swept, else lambda if lambda (v_belt) is, else nu
//!                                    # (law = "stribeck": xi or v_d, ranges xi_lo, ...)
//! fold = true                        # the value above which no start squeals
//! critical = true                    # the value at which the operating point stops squealing
//! nu_lo = 1e-4                       # bisection range when nu is not swept
//! nu_hi = 0.2
//! lambda_lo = 0.1                    # bisection range when lambda is not swept
//! lambda_hi = 10.0
//! rtol = 1e-3
//! [grid]                             # optional: one basin map per point (scan spec keys)
//! x0 = { min = -2.0, max = 4.0, count = 64 }   # the box its cells cover is the
//!                                              # disturbance box (no [disturbance] then)
//! v0 = { min = -3.0, max = 3.0, count = 64 }
//! block_rows = 8
//! [classifier]                       # optional, only with [grid]: as in the scan spec
//! t_max = 5000.0
//! [output]
//! path = "atlas.h5"
//! ```
//!
//! The swept parameters (more than one value) are the axes, in the fixed order
//! `nu, lambda, tau, phi` (or `m, k, c, v_belt, mu_k, mu_s, tau, g`, without `mu_s, tau`
//! under Coulomb, or for the Stribeck
//! law `xi, v_d, mu_d, mu_sd, v_0, mu_v`); points are their
//! Cartesian product in C order (the last axis fastest).

use std::path::PathBuf;

mod parse;
pub use parse::FOLD_COARSE;

use serde::{Deserialize, Serialize};
use squeal_core::{
    Classifier, FrictionLaw, LawFamily, Load, Params, Physical, Setup, SolverConfig, SurfaceSi,
};

use super::boundary::BoundaryParam;
use super::figures::PointSettings;
use super::geometry::Region;
use crate::bounds::Rules;
use crate::error::{ScanError, Shown};
use crate::grid::Grid;
use crate::spec::EarlyStop;
pub(crate) use crate::spec::physical::{PhysicalFile, physical_error};
use crate::values::Value;

/// The atlas spec version this build reads.
pub const ATLAS_VERSION: u32 = 1;
/// Largest number of parameter points in one atlas.
pub const MAX_POINTS: usize = 1_000_000;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct AtlasFile {
    version: u32,
    #[serde(default)]
    name: Option<String>,
    model: crate::spec::ModelTable,
    #[serde(default)]
    physical: Option<PhysicalFile>,
    #[serde(default)]
    integration: crate::spec::IntegrationTable,
    #[serde(default)]
    cycle: Option<crate::spec::CycleTable>,
    #[serde(default)]
    attractor: Option<AttractorFile>,
    #[serde(default)]
    operating_point: Option<PointFile>,
    #[serde(default)]
    disturbance: Option<BoxFile>,
    #[serde(default)]
    boundaries: Option<BoundariesFile>,
    /// Basin maps: the scan spec's `[grid]` and `[classifier]` tables.
    #[serde(default)]
    grid: Option<crate::spec::GridSpec>,
    #[serde(default)]
    classifier: Option<crate::spec::ClassifierSpec>,
    output: crate::spec::OutputTable,
}

#[derive(Deserialize, Debug, Default, Clone)]
#[serde(deny_unknown_fields)]
struct AttractorFile {
    transient: Option<i64>,
    window: Option<i64>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct PointFile {
    // Each key has its default (the state at rest) when left out.
    x: Option<f64>,
    v: Option<f64>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct BoxFile {
    // Lists, not `[f64; 2]`: a third element is refused by the check, not dropped. Each key
    // has its default (the box of `PointSettings::default`) when left out.
    x: Option<Vec<f64>>,
    v: Option<Vec<f64>>,
}

#[derive(Deserialize, Debug, Default, Clone)]
#[serde(deny_unknown_fields)]
struct BoundariesFile {
    #[serde(rename = "in")]
    in_: Option<String>,
    fold: Option<bool>,
    critical: Option<bool>,
    nu_lo: Option<f64>,
    nu_hi: Option<f64>,
    lambda_lo: Option<f64>,
    lambda_hi: Option<f64>,
    // The Stribeck law's names of the same ranges.
    xi_lo: Option<f64>,
    xi_hi: Option<f64>,
    v_d_lo: Option<f64>,
    v_d_hi: Option<f64>,
    rtol: Option<f64>,
    coarse: Option<i64>,
    lifetime_starts: Option<i64>,
}

/// Whether the spec describes the nondimensional model or the physical system.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Units {
    /// `nu, lambda, tau, phi` (paper Section 4).
    Nondimensional,
    /// `m, k, c, v_belt, mu_k, mu_s, tau, g` in SI units (no `mu_s, tau` under Coulomb).
    Physical,
}

impl Units {
    /// The name in files.
    pub fn name(self) -> &'static str {
        match self {
            Units::Nondimensional => "nondimensional",
            Units::Physical => "physical",
        }
    }
}

/// One parameter of the spec: its key, words, units and values.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AtlasAxis {
    /// The key (`nu`, `v_belt`, ...), also the dataset name of the coordinate.
    pub key: &'static str,
    /// Words for axes and `long_name`.
    pub long_name: &'static str,
    /// Units (`"1"` for nondimensional).
    pub units: &'static str,
    /// The values (one: fixed; more: swept).
    pub values: Vec<f64>,
}

/// `(key, long name, units)` of the nondimensional parameters, in axis order.
pub const NONDIMENSIONAL: [(&str, &str, &str); 4] = [
    ("nu", "damping ratio nu", "1"),
    ("lambda", "belt speed lambda (nondimensional)", "1"),
    ("tau", "surface time tau' (nondimensional)", "1"),
    ("phi", "Phi = arcsin(mu_k / mu_s)", "rad"),
];

/// `(key, long name, units)` of the physical parameters, in axis order.
pub const PHYSICAL: [(&str, &str, &str); 9] = [
    ("m", "mass m", "kg"),
    ("k", "stiffness k", "N/m"),
    ("c", "damping coefficient c", "N s/m"),
    ("v_belt", "belt speed v_belt", "m/s"),
    ("mu_k", "kinetic friction coefficient mu_k", "1"),
    ("mu_s", "static friction coefficient mu_s", "1"),
    ("tau", "surface time tau", "s"),
    ("g", "gravitational acceleration g", "m/s^2"),
    (
        "normal_force",
        "normal force N pressing the block on the belt (friction is mu N)",
        "N",
    ),
];

/// `(key, long name, units)` of a law's parameters in axis order ([`FrictionLaw::keys`];
/// the words of [`Params::named`]), for the laws with true stick. All are nondimensional
/// (`"1"`, as [`NONDIMENSIONAL`]'s): velocities in units of the natural-frequency velocity
/// scale.
pub fn law_params(law: FrictionLaw) -> Vec<(&'static str, &'static str, &'static str)> {
    Params::defaults(law)
        .named()
        .into_iter()
        .map(|n| (n.name, n.long_name, "1"))
        .collect()
}

/// Default bisection range of the damping (`nu` or `xi`) when it is not swept.
pub const DAMPING_RANGE: [f64; 2] = [1e-4, 0.2];
/// Default bisection range of the belt speed (`lambda` or `v_d`) when it is not swept.
pub const SPEED_RANGE: [f64; 2] = [0.1, 10.0];

/// The checked atlas plan.
#[derive(Clone, Debug, Serialize)]
pub struct AtlasPlan {
    /// Name for titles.
    pub name: String,
    /// Friction law.
    pub law: FrictionLaw,
    /// The table law's table (`friction_table` or `friction_csv`); `None` for other laws.
    /// In a physical plan its slip speeds are in m/s (as `[physical]` gives them; each
    /// point's model has them over its own velocity unit, [`AtlasPlan::params_at`]).
    pub table: Option<&'static squeal_core::FrictionTable>,
    /// Nondimensional or physical.
    pub units: Units,
    /// Every parameter in axis order (fixed ones have one value).
    pub params: Vec<AtlasAxis>,
    /// Time step.
    pub dt: f64,
    /// Solver.
    pub solver: SolverConfig,
    /// Per-point settings; in physical plans `operating` and `disturbance` are in SI units
    /// (see [`AtlasPlan::settings_at`]).
    pub point: PointSettings,
    /// In a physical plan, whether the disturbance box is the default one, kept in
    /// nondimensional units at every point (so it scales with each point's system: a box in
    /// metres would be the same for a 1 um and a 1 mm oscillator); false when the spec
    /// gives `[disturbance]` (SI units) and in nondimensional plans.
    pub disturbance_nondimensional: bool,
    /// Locate the fold of cycles.
    pub fold: bool,
    /// Locate the critical damping of the operating point.
    pub critical: bool,
    /// Bisection range in `nu` when the damping is not swept.
    pub nu_range: [f64; 2],
    /// The parameter the boundaries are bisected in (`[boundaries] in`).
    pub boundary_in: BoundaryParam,
    /// Bisection range in `lambda` when the belt speed is not swept.
    pub lambda_range: [f64; 2],
    /// Relative bracket width of the boundaries.
    pub boundary_rtol: f64,
    /// Steps of the fold's coarse scan along the bisected parameter (`[boundaries] coarse`).
    pub boundary_coarse: usize,
    /// Starts on the band per damping for the transient lifetimes above each fold
    /// (`[boundaries] lifetime_starts`; 0: not measured).
    pub lifetime_starts: usize,
    /// Output file.
    pub out: PathBuf,
    /// Basin maps, one per point (the spec's `[grid]`), if asked for.
    pub maps: Option<MapSettings>,
    /// The spec file's text.
    pub spec_text: String,
    /// Where it was read from.
    pub spec_path: String,
}

/// The basin maps of an atlas: the grid and classifier of the scan spec (same keys, same
/// checks), one map per parameter point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MapSettings {
    /// The grid of initial conditions (its box is also the disturbance box).
    pub grid: Grid,
    /// Classifier settings (the trap is filled in per map from its located cycle).
    pub classifier: Classifier,
    /// Early-stopping rule.
    pub early_stop: EarlyStop,
    /// Relative half-width of the band around the cycle where runs go on.
    pub trap_margin: f64,
    /// About one cell in this many is also run to settlement (0: none).
    pub audit_every: u64,
}

/// The atlas spec text parsed into its tables (a TOML error names the file).
fn parse_atlas(text: &str, path: &str) -> Result<AtlasFile, ScanError> {
    toml::from_str(text).map_err(|e| ScanError::Parse {
        path: path.to_string(),
        // A float for an integer key is written by serde in full (309 digits for 1e308).
        message: squeal_core::error::readable_numbers(&e.to_string()),
    })
}

/// `value` is any [`Shown`] value: not a bare `f64`, which would print 1e-300 with 300 zeros
/// (wrap it in [`squeal_core::error::Number`]).
fn invalid(path: &str, key: &str, value: impl Shown, expected: &str) -> ScanError {
    ScanError::Invalid {
        path: path.to_string(),
        key: key.to_string(),
        value: value.shown(),
        expected: expected.to_string(),
    }
}

fn expand(path: &str, key: &str, v: &Value) -> Result<Vec<f64>, ScanError> {
    crate::values::expand(v, key, 100_000, &|key, value, expected| {
        invalid(path, key, value, expected)
    })
}

impl AtlasPlan {
    /// Reads and checks a spec file.
    pub fn from_file(path: &std::path::Path) -> Result<AtlasPlan, ScanError> {
        let text = crate::spec::read_spec(path)?;
        AtlasPlan::from_toml(&text, &path.display().to_string())
    }

    /// Checks a spec's text; `path` names it in errors.
    pub fn from_toml(text: &str, path: &str) -> Result<AtlasPlan, ScanError> {
        AtlasPlan::from_parsed(parse_atlas(text, path)?, text, path, None, Rules::Today)
    }

    /// Reads the spec stored in an atlas file this or an older squeal wrote, as the plan of
    /// what was run ([`Rules::Stored`], as [`crate::Plan::from_stored_toml`]): a value
    /// outside a bound of today reads as stored, and only what the plan cannot be built
    /// without is refused, as "this file's stored spec" naming the key. `[physical]` keys
    /// the law does not use, which older versions required and then ignored (`mu_s`, `tau`
    /// under Coulomb), are dropped rather than refused; one swept is refused (that version
    /// made each of its values a point, so the file holds more points than this plan).
    pub fn from_stored_toml(text: &str, path: &str) -> Result<AtlasPlan, ScanError> {
        AtlasPlan::from_stored_toml_table(text, path, None)
    }

    /// [`AtlasPlan::from_stored_toml`] with the friction table the file stores (`table`),
    /// which stands for the spec's `friction_table` or `friction_csv`.
    pub fn from_stored_toml_table(
        text: &str,
        path: &str,
        table: Option<&'static squeal_core::FrictionTable>,
    ) -> Result<AtlasPlan, ScanError> {
        let read = || {
            let mut f = parse_atlas(text, path)?;
            if let Some(ph) = &mut f.physical {
                ph.forget_unused(f.model.law, &|key, value, expected| {
                    invalid(path, key, value, expected)
                })?;
            }
            AtlasPlan::from_parsed(f, text, path, table, Rules::Stored)
        };
        read().map_err(crate::bounds::in_stored_spec)
    }

    /// The plan of the parsed spec `f` of text `text`, read under `rules`.
    fn from_parsed(
        f: AtlasFile,
        text: &str,
        path: &str,
        stored: Option<&'static squeal_core::FrictionTable>,
        rules: Rules,
    ) -> Result<AtlasPlan, ScanError> {
        if f.version != ATLAS_VERSION {
            return Err(invalid(
                path,
                "version",
                f.version,
                "1 (the atlas spec version this build reads)",
            ));
        }
        let inv = |key: &str, value: String, expected: &str| invalid(path, key, value, expected);
        let m = &f.model;
        m.check_law(&inv)?;
        let folder = std::path::Path::new(path)
            .parent()
            .unwrap_or(std::path::Path::new(""));
        let table = match &f.physical {
            Some(ph) => {
                m.check_physical(&inv)?;
                ph.check_friction_keys(m.law, &inv)?;
                ph.table(folder, stored, &inv)?
            }
            None => m.table(folder, stored, &inv)?,
        };
        let (units, params) = parse::model_axes(&f, path)?;
        let (dt, solver) = f.integration.check(rules, &inv)?;
        let mut ps = parse::point_settings(&f, path, rules, &inv)?;
        let maps = parse::map_settings(&f, path, dt, &mut ps, rules, &inv)?;
        let b = parse::boundaries(&f, path, units, &params, rules, &inv)?;
        // A physical spec's own box is in SI units: [disturbance], or the [grid]'s cells.
        let si_box = f.disturbance.is_some() || maps.is_some();
        let mut plan = AtlasPlan {
            name: crate::spec::check_name(f.name.as_deref(), path, "atlas", &inv)?,
            law: m.law,
            table,
            units,
            params,
            dt,
            solver,
            point: ps,
            disturbance_nondimensional: units == Units::Physical && !si_box,
            fold: b.fold,
            critical: b.critical,
            nu_range: b.nu_range,
            boundary_in: b.boundary_in,
            lambda_range: b.lambda_range,
            boundary_rtol: b.boundary_rtol,
            boundary_coarse: b.boundary_coarse,
            lifetime_starts: b.lifetime_starts,
            maps,
            out: f.output.check(&inv)?,
            spec_text: text.to_string(),
            spec_path: path.to_string(),
        };
        // Every point's model, checked before any computing.
        for i in 0..plan.n_points() {
            parse::check_point(&plan, i, path, rules)?;
        }
        parse::physical_grid(&mut plan, path, rules, &inv)?;
        Ok(plan)
    }

    /// The first setting (top-level field of the plan) in which `other` would compute
    /// something different, or `None`: as [`crate::Plan::differs_from`], the spec text, its
    /// path and the output path apart.
    pub fn differs_from(&self, other: &AtlasPlan) -> Option<String> {
        crate::spec::first_difference(self, other, &["spec_text", "spec_path", "out"])
    }

    /// The swept parameters (more than one value), in axis order.
    pub fn axes(&self) -> Vec<&AtlasAxis> {
        self.params.iter().filter(|a| a.values.len() > 1).collect()
    }

    /// The fixed parameters with their value.
    pub fn fixed(&self) -> Vec<(&AtlasAxis, f64)> {
        self.params
            .iter()
            .filter(|a| a.values.len() == 1)
            .map(|a| (a, a.values[0]))
            .collect()
    }

    /// Shape of the point array (the swept axes' lengths).
    pub fn shape(&self) -> Vec<usize> {
        self.axes().iter().map(|a| a.values.len()).collect()
    }

    /// Number of parameter points.
    pub fn n_points(&self) -> usize {
        self.shape().iter().product()
    }

    /// The index of each swept axis at point `i` (C order).
    pub fn unravel(&self, mut i: usize) -> Vec<usize> {
        let shape = self.shape();
        let mut idx = vec![0; shape.len()];
        for d in (0..shape.len()).rev() {
            idx[d] = i % shape[d];
            i /= shape[d];
        }
        idx
    }

    /// Every parameter's value at point `i`, in `params` order.
    pub fn values_at(&self, i: usize) -> Vec<f64> {
        let idx = self.unravel(i);
        let mut k = 0;
        self.params
            .iter()
            .map(|a| {
                if a.values.len() > 1 {
                    k += 1;
                    a.values[idx[k - 1]]
                } else {
                    a.values[0]
                }
            })
            .collect()
    }

    /// The physical system at point `i` (physical plans only).
    pub fn physical_at(&self, i: usize) -> Option<Physical> {
        if self.units != Units::Physical {
            return None;
        }
        let v = self.values_at(i);
        // Axes by key: a Coulomb system has no mu_s and tau axes.
        let at = |key: &str| self.params.iter().position(|a| a.key == key).map(|j| v[j]);
        let need = |key: &str| {
            at(key).expect("every physical key but mu_s, tau and a table's mu_k has an axis")
        };
        Some(Physical {
            m: need("m"),
            k: need("k"),
            c: need("c"),
            v_belt: need("v_belt"),
            friction: match self.table {
                Some(friction_table) => squeal_core::FrictionSi::Table { friction_table },
                None => squeal_core::FrictionSi::Kinetic {
                    mu_k: need("mu_k"),
                    surface: match (at("mu_s"), at("tau")) {
                        (Some(mu_s), Some(tau)) => Some(SurfaceSi { mu_s, tau }),
                        _ => None,
                    },
                },
            },
            load: match at("normal_force") {
                Some(n) => Load::NormalForce(n),
                None => Load::Weight(need("g")),
            },
        })
    }

    /// The integration setting at point `i`: its parameters with the plan's step and solver.
    pub fn setup_at(&self, i: usize) -> Setup {
        Setup::new(self.params_at(i), self.dt, self.solver)
    }

    /// The model parameters at point `i`.
    pub fn params_at(&self, i: usize) -> Params {
        if let Some(ph) = self.physical_at(i) {
            return ph
                .nondimensional(self.law)
                .expect("a physical plan has a McMillan law (checked when it was read)");
        }
        // Axis order is the law's keys (FrictionLaw::keys).
        let v = self.values_at(i);
        let keys = self.law.keys();
        Params::from_named_table(self.law, self.table, |k| {
            keys.iter().position(|x| *x == k).map(|j| v[j])
        })
        .expect("every key of the law has an axis")
    }

    /// The point settings at `i`, operating point and disturbance box in nondimensional
    /// units (converted with the point's scales in physical plans).
    pub fn settings_at(&self, i: usize) -> PointSettings {
        let mut ps = self.point;
        if let Some(ph) = self.physical_at(i) {
            let s = ph.scales();
            ps.units = Some(s);
            ps.operating = s.state(ps.operating);
            if !self.disturbance_nondimensional {
                ps.disturbance = Region {
                    x: ps.disturbance.x.map(|x| x / s.length),
                    v: ps.disturbance.v.map(|v| v / s.velocity),
                };
            }
        }
        ps
    }

    /// The units of the disturbance box (`[disturbance]`, stored as `disturbance_x`,
    /// `disturbance_v`), in words.
    pub fn disturbance_units(&self) -> [&'static str; 2] {
        if self.units == Units::Physical && !self.disturbance_nondimensional {
            ["m", "m/s"]
        } else if self.units == Units::Physical {
            [
                "1 (the default box, nondimensional at each point: units of mu_k g / omega_0^2)",
                "1 (the default box, nondimensional at each point: units of mu_k g / omega_0)",
            ]
        } else {
            ["1", "1"]
        }
    }

    /// The damping parameter's key (`nu` or `c`) and its position among the swept axes.
    pub fn damping_axis(&self) -> (&'static str, Option<usize>) {
        let key = match self.units {
            Units::Nondimensional => self.law.keys()[0],
            Units::Physical => "c",
        };
        (key, self.axes().iter().position(|a| a.key == key))
    }

    /// The bisected parameter's nondimensional key under the law's names (`nu`, `lambda`;
    /// Stribeck: `xi`, `v_d`), also the suffix of the stored boundary datasets.
    pub fn boundary_key(&self) -> &'static str {
        match self.boundary_in {
            BoundaryParam::Nu => self.law.keys()[0],
            BoundaryParam::Lambda => self.law.keys()[1],
        }
    }

    /// Words for the bisected parameter (`damping ratio nu`, `belt speed v_d`, ...).
    pub fn boundary_words(&self) -> &'static str {
        match (self.law.family().has_own_names(), self.boundary_in) {
            (true, BoundaryParam::Nu) => "damping ratio xi",
            (true, BoundaryParam::Lambda) => "belt speed v_d",
            (false, b) => b.words(),
        }
    }

    /// The bisected parameter's key (`nu`/`c` or `lambda`/`v_belt`) and its position among
    /// the swept axes: the boundary array spans the other swept axes.
    pub fn boundary_axis(&self) -> (&'static str, Option<usize>) {
        let key = match self.units {
            Units::Nondimensional => self.boundary_key(),
            Units::Physical => self.boundary_in.physical_key(),
        };
        (key, self.axes().iter().position(|a| a.key == key))
    }

    /// A boundary value `v` (nondimensional, in the bisected parameter) in SI units at point
    /// `i` of a physical plan, with the units; `None` in nondimensional plans.
    pub fn boundary_si(&self, i: usize, v: f64) -> Option<(f64, &'static str)> {
        let (unit, units) = self.boundary_in.si(&self.physical_at(i)?.scales());
        Some((v * unit, units))
    }

    /// The stored name of a boundary column (`fold_nu` -> `fold_lambda` when bisecting in
    /// lambda) and its long name.
    pub fn boundary_dataset(&self, name: &str, long_name: &str) -> (String, String) {
        // A long name that cites a dataset (`fold_nu -+ fold_nu_err`) cites it by its name here.
        let cited = format!("fold_{}", self.boundary_key());
        let long_name = &long_name.replace("fold_nu", &cited);
        if self.law.family() == LawFamily::TrueStick {
            // The words of the laws with true stick: the fold is where the stick-slip cycle
            // ends.
            let name = name.replace("_nu", &format!("_{}", self.boundary_key()));
            let long = long_name.replace(
                "fold of cycles",
                "fold (the stick-slip cycle ends: the orbit from breakaway no longer sticks again)",
            );
            let long = match self.boundary_in {
                BoundaryParam::Nu => long
                    .replace("damping ratio", "damping ratio xi")
                    .replace("critical damping:", "critical damping ratio xi:"),
                BoundaryParam::Lambda => long
                    .replace("critical damping ratio", "critical belt speed v_d")
                    .replace("critical damping", "critical belt speed v_d")
                    .replace("damping ratio", "belt speed v_d"),
            };
            return (name, long);
        }
        match self.boundary_in {
            BoundaryParam::Nu => (name.to_string(), long_name.to_string()),
            BoundaryParam::Lambda => (
                name.replace("_nu", "_lambda"),
                long_name
                    .replace("critical damping ratio", "critical belt speed lambda")
                    .replace("critical damping", "critical belt speed")
                    .replace("damping ratio", "belt speed lambda"),
            ),
        }
    }

    /// Shape of the boundary array: the swept axes except the bisected one.
    pub fn boundary_shape(&self) -> Vec<usize> {
        let (_, d) = self.boundary_axis();
        self.shape()
            .into_iter()
            .enumerate()
            .filter(|(k, _)| Some(*k) != d)
            .map(|(_, n)| n)
            .collect()
    }

    /// Number of boundary searches (0 when neither boundary is asked for).
    pub fn n_boundaries(&self) -> usize {
        if self.fold || self.critical {
            self.boundary_shape().iter().product()
        } else {
            0
        }
    }

    /// For boundary search `j`: a representative point (index 0 along the bisected axis)
    /// and the bisection range in the bisected parameter (the swept axis' range there, or
    /// `nu_range` / `lambda_range`).
    pub fn boundary_setup(&self, j: usize) -> (usize, [f64; 2]) {
        let shape = self.shape();
        let (_, d) = self.boundary_axis();
        let bshape = self.boundary_shape();
        let mut rem = j;
        let mut bidx = vec![0; bshape.len()];
        for k in (0..bshape.len()).rev() {
            bidx[k] = rem % bshape[k];
            rem /= bshape[k];
        }
        let mut idx = Vec::with_capacity(shape.len());
        let mut b = bidx.into_iter();
        for k in 0..shape.len() {
            idx.push(if Some(k) == d {
                0
            } else {
                b.next().unwrap_or(0)
            });
        }
        let i = idx.iter().zip(&shape).fold(0, |acc, (x, n)| acc * n + x);
        let bp = self.boundary_in;
        let range = match d {
            Some(dk) => {
                let n = shape[dk];
                let stride: usize = shape[dk + 1..].iter().product();
                let a = bp.get(&self.params_at(i));
                let z = bp.get(&self.params_at(i + (n - 1) * stride));
                [a.min(z), a.max(z)]
            }
            None => match bp {
                BoundaryParam::Nu => self.nu_range,
                BoundaryParam::Lambda => self.lambda_range,
            },
        };
        (i, range)
    }
}

#[cfg(test)]
mod tests;
