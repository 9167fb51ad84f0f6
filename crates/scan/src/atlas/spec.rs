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
use squeal_core::{LawFamily, Setup, SolverConfig};

use super::boundary::BoundaryParam;
use super::figures::PointSettings;
use super::geometry::Region;
use crate::bounds::Rules;
use crate::error::{ScanError, Shown};
pub(crate) use crate::spec::physical::PhysicalFile;

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

use crate::space::{Limit, Space};
pub use crate::space::{NONDIMENSIONAL, PHYSICAL, ParamAxis, Units, law_params};
pub use crate::spec::MapSettings;

/// Default bisection range of the damping (`nu` or `xi`) when it is not swept.
pub const DAMPING_RANGE: [f64; 2] = [1e-4, 0.2];
/// Default bisection range of the belt speed (`lambda` or `v_d`) when it is not swept.
pub const SPEED_RANGE: [f64; 2] = [0.1, 10.0];

/// The checked atlas plan.
#[derive(Clone, Debug, Serialize)]
pub struct AtlasPlan {
    /// Name for titles.
    pub name: String,
    /// The parameter space: the law and every key, one point per element of the product.
    #[serde(flatten)]
    pub space: Space,
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
        let folder = std::path::Path::new(path)
            .parent()
            .unwrap_or(std::path::Path::new(""));
        let limit = Limit {
            per_key: 100_000,
            points: MAX_POINTS,
            noun: "parameter points",
        };
        let space = Space::read(&f.model, f.physical.as_ref(), (folder, stored), limit, &inv)?;
        let units = space.units;
        let (dt, solver) = f.integration.check(rules, &inv)?;
        rules.bound(|| space.check_step(dt, &inv))?;
        let mut ps = parse::point_settings(&f, path, rules, &inv)?;
        let maps = parse::map_settings(&f, path, dt, &mut ps, rules, &inv)?;
        let b = parse::boundaries(&f, path, units, &space.params, rules, &inv)?;
        // A physical spec's own box is in SI units: [disturbance], or the [grid]'s cells.
        let si_box = f.disturbance.is_some() || maps.is_some();
        let mut plan = AtlasPlan {
            name: crate::spec::check_name(f.name.as_deref(), path, "atlas", &inv)?,
            space,
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
        for i in 0..plan.space.n_points() {
            parse::check_point(&plan, i, path, rules)?;
        }
        parse::physical_grid(&mut plan, rules, &inv)?;
        Ok(plan)
    }

    /// The first setting (top-level field of the plan) in which `other` would compute
    /// something different, or `None`: as [`crate::Plan::differs_from`], the spec text, its
    /// path and the output path apart.
    pub fn differs_from(&self, other: &AtlasPlan) -> Option<String> {
        crate::spec::first_difference(self, other, &["spec_text", "spec_path", "out"])
    }

    /// The integration setting at point `i`: its parameters with the plan's step and solver.
    pub fn setup_at(&self, i: usize) -> Setup {
        Setup::new(self.space.params_at(i), self.dt, self.solver)
    }

    /// The point settings at `i`, operating point and disturbance box in nondimensional
    /// units (converted with the point's scales in physical plans).
    pub fn settings_at(&self, i: usize) -> PointSettings {
        let mut ps = self.point;
        if let Some(ph) = self.space.physical_at(i) {
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
    /// `disturbance_v`), in words. The default box of a physical plan is in the model's
    /// units at each point: of `mu_k N` (`N` the normal force, `m g` without one), or of
    /// `N` for a measured curve, which has no `mu_k` (crates/core/MODEL.md section 8).
    pub fn disturbance_units(&self) -> [&'static str; 2] {
        let curve = self.space.law.family().in_normal_load();
        if self.space.units == Units::Physical && !self.disturbance_nondimensional {
            ["m", "m/s"]
        } else if self.space.units == Units::Physical && curve {
            [
                "1 (the default box, nondimensional at each point: units of N / k, N the \
                 normal force, m g without one)",
                "1 (the default box, nondimensional at each point: units of N / sqrt(m k))",
            ]
        } else if self.space.units == Units::Physical {
            [
                "1 (the default box, nondimensional at each point: units of mu_k N / k, N \
                 the normal force, m g without one)",
                "1 (the default box, nondimensional at each point: units of mu_k N / sqrt(m k))",
            ]
        } else {
            ["1", "1"]
        }
    }

    /// The damping parameter's key (`nu` or `c`) and its position among the swept axes.
    pub fn damping_axis(&self) -> (&'static str, Option<usize>) {
        let key = match self.space.units {
            Units::Nondimensional => self.space.law.keys()[0],
            Units::Physical => "c",
        };
        (key, self.space.axes().iter().position(|a| a.key == key))
    }

    /// The bisected parameter's nondimensional key under the law's names (`nu`, `lambda`;
    /// Stribeck: `xi`, `v_d`), also the suffix of the stored boundary datasets.
    pub fn boundary_key(&self) -> &'static str {
        match self.boundary_in {
            BoundaryParam::Nu => self.space.law.keys()[0],
            BoundaryParam::Lambda => self.space.law.keys()[1],
        }
    }

    /// Words for the bisected parameter (`damping ratio nu`, `belt speed v_d`, ...).
    pub fn boundary_words(&self) -> &'static str {
        match (self.space.law.family().has_own_names(), self.boundary_in) {
            (true, BoundaryParam::Nu) => "damping ratio xi",
            (true, BoundaryParam::Lambda) => "belt speed v_d",
            (false, b) => b.words(),
        }
    }

    /// The bisected parameter's key (`nu`/`c` or `lambda`/`v_belt`) and its position among
    /// the swept axes: the boundary array spans the other swept axes.
    pub fn boundary_axis(&self) -> (&'static str, Option<usize>) {
        let key = match self.space.units {
            Units::Nondimensional => self.boundary_key(),
            Units::Physical => self.boundary_in.physical_key(),
        };
        (key, self.space.axes().iter().position(|a| a.key == key))
    }

    /// A boundary value `v` (nondimensional, in the bisected parameter) in SI units at point
    /// `i` of a physical plan, with the units; `None` in nondimensional plans.
    pub fn boundary_si(&self, i: usize, v: f64) -> Option<(f64, &'static str)> {
        let (unit, units) = self.boundary_in.si(&self.space.physical_at(i)?.scales());
        Some((v * unit, units))
    }

    /// The stored name of a boundary column (`fold_nu` -> `fold_lambda` when bisecting in
    /// lambda) and its long name.
    pub fn boundary_dataset(&self, name: &str, long_name: &str) -> (String, String) {
        // A long name that cites a dataset (`fold_nu -+ fold_nu_err`) cites it by its name here.
        let cited = format!("fold_{}", self.boundary_key());
        let long_name = &long_name.replace("fold_nu", &cited);
        if self.space.law.family() == LawFamily::TrueStick {
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
        self.space
            .shape()
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
        let shape = self.space.shape();
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
                let a = bp.get(&self.space.params_at(i));
                let z = bp.get(&self.space.params_at(i + (n - 1) * stride));
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
