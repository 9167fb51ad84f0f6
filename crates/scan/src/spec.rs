//! Scan specs: the TOML file (a serde mirror, unknown keys rejected) and the checked
//! [`Plan`] the scanner accepts. Validation happens once, here, and names the key.
//!
//! Users' reference: `docs/spec.md` lists every key with its default, range and meaning;
//! `tests/spec_doc.rs` fails when a key is added here without a row there.
//!
//! ```toml
//! version = 1                      # required; this is spec version 1
//! [model]
//! law = "mcmillan"                 # mcmillan | mcmillan-nonhysteretic | coulomb | stribeck | cubic
//! nu = 1e-3                        # a number, a list [1e-3, 2e-3], or
//!                                  # { from = 1e-3, to = 5e-2, count = 8, spacing = "log" }
//! lambda = 3.0                     # default 3; any key may be a list or range: one map
//!                                  # per point of the swept keys' product
//! tau = 0.31622776601683794        # default 0.1 sqrt(10)
//! phi = 1.0                        # default 1
//! # law = "stribeck" takes instead: xi (damping ratio, default 0.05), v_d (belt speed,
//! # default 1.5), mu_d = 0.5, mu_sd = 2, v_0 = 0.5, mu_v = 0
//! [grid]
//! x0 = { min = -3.0, max = 5.0, count = 64 }
//! v0 = { min = -4.0, max = 4.0, count = 64 }
//! block_rows = 8                   # rows of v0 per stored block (default 8)
//! # or, instead of [grid], random initial conditions (bSTAB's basin-stability sampling):
//! # [sample]
//! # kind = "random"
//! # n = 5000
//! # seed = 1
//! # region = { x0 = [-2.0, 2.0], v0 = [0.0, 2.0] }
//! # block = 256                    # samples per stored block (default 256)
//! [integration]
//! dt = 0.005
//! solver = "robust"                # robust | paper
//! scheme = "foh"                    # foh (force linear over a step) | zoh (held: the paper's)
//! max_iter = 100                   # paper iteration cap
//! [classifier]
//! t_max = 5000.0
//! fp_radius = 1e-3
//! settle_cycles = 20
//! settle_rtol = 0.05
//! early_stop = "cycle"             # cycle (stop once inside/outside the located cycle) | none
//! trap_margin = 1e-5               # relative band around the cycle left to run on
//! sensitivity_samples = 4096       # starts near the boundary for the uncertainty exponent
//!                                  # and the step sensitivity (default cells / 32 in
//!                                  # 64..=4096; 0: none)
//! audit_every = 1024               # with early_stop = "cycle": also run about 1 cell in
//!                                  # this many to settlement and count (dis)agreements;
//!                                  # 0 turns the audit off. Default: 1024, or cells / 16
//!                                  # on grids above 16384 cells (about 16 per map)
//! [cycle]                          # one table for scans and atlases (docs/spec.md)
//! locate = true                    # locate the unstable cycle, store and draw it
//! # r_min = 0.01, r_max (default 1.2 x the grid's farthest start from the fixed point, at
//! # least 4), samples = 96, rtol = 1e-10, t_return = 200, half_dt = true: the section search
//! [output]
//! path = "fig9.h5"                 # relative to the working directory
//! ```

use std::path::PathBuf;

use serde::{Deserialize, Serialize};
use squeal_core::error::Number;
use squeal_core::{Classifier, FrictionLaw, Params, Setup, SolverConfig};

use crate::error::ScanError;
use crate::grid::{Axis, Grid, RandomSample, Starts};
use crate::space::{Limit, Space};

mod classifier;
pub(crate) mod physical;
mod tables;

pub use classifier::EarlyStop;
pub(crate) use classifier::{ClassifierPlan, ClassifierSpec};

pub use tables::{CycleOptions, MAX_CSV_BYTES, read_friction_csv};
pub(crate) use tables::{CycleTable, IntegrationTable, ModelTable, OutputTable, Shape, check_name};

/// The spec version this build reads.
pub const SPEC_VERSION: u32 = 1;

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SpecFile {
    version: u32,
    #[serde(default)]
    name: Option<String>,
    model: ModelTable,
    /// The physical system in SI units instead of `[model]`'s nondimensional keys.
    #[serde(default)]
    physical: Option<physical::PhysicalFile>,
    #[serde(default)]
    grid: Option<GridSpec>,
    #[serde(default)]
    sample: Option<SampleSpec>,
    #[serde(default)]
    integration: IntegrationTable,
    #[serde(default)]
    classifier: ClassifierSpec,
    #[serde(default)]
    cycle: CycleTable,
    output: OutputTable,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(crate) struct AxisSpec {
    min: f64,
    max: f64,
    count: i64,
}

/// The `[grid]` table (also read by the atlas spec, [`crate::atlas::spec`]).
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(crate) struct GridSpec {
    x0: AxisSpec,
    v0: AxisSpec,
    #[serde(default)]
    block_rows: Option<i64>,
}

/// How `[sample]` draws its initial conditions.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
enum SampleKind {
    /// Uniform at random in the region (bSTAB's default).
    Random,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct RegionSpec {
    // Lists, not `[f64; 2]`: a third element is refused by the check, not dropped.
    x0: Vec<f64>,
    v0: Vec<f64>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SampleSpec {
    kind: SampleKind,
    n: i64,
    seed: u64,
    region: RegionSpec,
    #[serde(default)]
    block: Option<i64>,
}

/// Default samples per stored block of a `[sample]` spec.
pub const DEFAULT_SAMPLE_BLOCK: i64 = 256;
/// Largest number of random samples per map.
pub const MAX_SAMPLES: i64 = 1 << 26;

/// Largest spec file read, in bytes. The shipped specs are under 3 kB; a spec is a few
/// tables of numbers. The cap keeps a wrong path (`/dev/zero`, a data file) from filling
/// memory: reading `/dev/zero` grew by about 250 MB/s until killed.
pub const MAX_SPEC_BYTES: u64 = 1 << 20;

/// Reads a spec file (scan or atlas) of at most [`MAX_SPEC_BYTES`].
pub(crate) fn read_spec(path: &std::path::Path) -> Result<String, ScanError> {
    use std::io::Read;
    let parse = |message: String| ScanError::Parse {
        path: path.display().to_string(),
        message,
    };
    // A FIFO at the spec's path blocked the open for ever.
    crate::files::refuse_non_regular(path)
        .map_err(|e| parse(format!("cannot read the spec: it is {}", e.what)))?;
    let file =
        std::fs::File::open(path).map_err(|e| parse(format!("cannot read the spec: {e}")))?;
    let mut bytes = Vec::new();
    file.take(MAX_SPEC_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| parse(format!("cannot read the spec: {e}")))?;
    if bytes.len() as u64 > MAX_SPEC_BYTES {
        return Err(parse(format!(
            "longer than {MAX_SPEC_BYTES} bytes: not a spec (a spec is a few tables of numbers)"
        )));
    }
    String::from_utf8(bytes).map_err(|e| parse(format!("not UTF-8 text: {e}")))
}

pub use crate::bounds::Invalid;
use crate::bounds::Rules;

impl GridSpec {
    /// The grid, its ends checked under [`Rules::Today`] (its shape under any rules);
    /// errors name `grid.<key>`.
    pub(crate) fn check(&self, rules: Rules, invalid: Invalid) -> Result<Grid, ScanError> {
        let axis = |a: &AxisSpec, key: &str| -> Result<Axis, ScanError> {
            for (end, v) in [("min", a.min), ("max", a.max)] {
                let key = format!("{key}.{end}");
                rules.bound(|| crate::bounds::state(&key, v, invalid).map(|_| ()))?;
            }
            if a.count < 1 || a.count > MAX_AXIS {
                return Err(invalid(
                    &format!("{key}.count"),
                    a.count.to_string(),
                    "a count in 1..=65536",
                ));
            }
            if a.min > a.max {
                return Err(invalid(
                    key,
                    format!("[{}, {}]", Number(a.min), Number(a.max)),
                    "min <= max (the range is inverted)",
                ));
            }
            if a.min == a.max && a.count > 1 {
                return Err(invalid(
                    key,
                    format!("[{}, {}]", Number(a.min), Number(a.max)),
                    "an empty range holds one value: use count = 1 or widen it",
                ));
            }
            if a.min != a.max && a.count == 1 {
                // One point cannot stand for a range: `max` would be ignored.
                return Err(invalid(
                    &format!("{key}.count"),
                    format!("1 on [{}, {}]", Number(a.min), Number(a.max)),
                    "count >= 2 for a range, or min = max for a single value",
                ));
            }
            let axis = Axis {
                min: a.min,
                max: a.max,
                count: a.count as usize,
            };
            // Cells at distinct states: `[1.0, 1.0000000000000002]` with 8 cells gave
            // neighbours at one coordinate (the spacing below the numbers' resolution).
            if axis.values().windows(2).any(|w| w[1] <= w[0]) {
                return Err(invalid(
                    key,
                    format!("[{:?}, {:?}] with {} cells", a.min, a.max, a.count),
                    "cells at distinct coordinates: the spacing (max - min) / (count - 1) is \
                     below the resolution of the numbers there; widen the range or lower the \
                     count",
                ));
            }
            Ok(axis)
        };
        let x0 = axis(&self.x0, "grid.x0")?;
        let v0 = axis(&self.v0, "grid.v0")?;
        if (x0.count as i64) * (v0.count as i64) > MAX_CELLS {
            return Err(invalid(
                "grid",
                format!("{} x {} cells", x0.count, v0.count),
                "at most 2^26 cells per map",
            ));
        }
        let block_rows = self.block_rows.unwrap_or(8);
        if !(1..=MAX_AXIS).contains(&block_rows) {
            return Err(invalid(
                "grid.block_rows",
                block_rows.to_string(),
                "a row count in 1..=65536",
            ));
        }
        Ok(Grid {
            x0,
            v0,
            block_rows: block_rows as usize,
            starts: Starts::Grid,
        })
    }
}

/// One swept key of a scan: its name and its values (a list or a range in the spec, even
/// of one value).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepAxis {
    /// A key of the law (`nu`, `lambda`, `tau`, `phi`; `xi`, `v_d`, ...), in the model's units.
    pub name: &'static str,
    /// The values, strictly monotone.
    pub values: Vec<f64>,
    /// In a physical scan, the `[physical]` key given and its values (`None` in a
    /// nondimensional one).
    pub si: Option<crate::si::SweptSi>,
}

/// The swept keys of a scan: one basin map per point of their product, in the law's key
/// order with the last key fastest (C order, as an atlas's points, [`crate::AtlasPlan::unravel`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sweep {
    /// The swept keys, at least one.
    pub axes: Vec<SweepAxis>,
}

impl Sweep {
    /// The number of values of each swept key.
    pub fn shape(&self) -> Vec<usize> {
        self.axes.iter().map(|a| a.values.len()).collect()
    }

    /// The number of maps (the product of [`Sweep::shape`]).
    pub fn maps(&self) -> usize {
        self.shape().iter().product()
    }

    /// Each swept key's value at map `map`, in axis order.
    pub fn values_at(&self, mut map: usize) -> Vec<f64> {
        let mut out = vec![0.0; self.axes.len()];
        for (d, a) in self.axes.iter().enumerate().rev() {
            out[d] = a.values[map % a.values.len()];
            map /= a.values.len();
        }
        out
    }

    /// The value of key `name` at every map, in map order (`None`: not swept).
    pub fn per_map(&self, name: &str) -> Option<Vec<f64>> {
        let d = self.axes.iter().position(|a| a.name == name)?;
        Some((0..self.maps()).map(|m| self.values_at(m)[d]).collect())
    }

    /// The SI twin of key `name` at every map, in map order, with its words (`None`: not
    /// swept, or not in a physical scan).
    pub fn si_per_map(&self, name: &str) -> Option<(&crate::si::SweptSi, Vec<f64>)> {
        let d = self.axes.iter().position(|a| a.name == name)?;
        let si = self.axes[d].si.as_ref()?;
        let n = self.axes[d].values.len();
        let stride: usize = self.shape()[d + 1..].iter().product();
        Some((
            si,
            (0..self.maps())
                .map(|m| si.values[(m / stride) % n])
                .collect(),
        ))
    }

    /// The names of the swept keys.
    pub fn names(&self) -> Vec<&'static str> {
        self.axes.iter().map(|a| a.name).collect()
    }

    /// The single swept key, if only one is swept (its values are then the maps').
    pub fn single(&self) -> Option<&SweepAxis> {
        match self.axes.as_slice() {
            [a] => Some(a),
            _ => None,
        }
    }
}

/// A checked scan: what the scanner and the store accept.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Plan {
    /// The spec's text, verbatim (stored in every output).
    pub spec_text: String,
    /// Where the spec came from (for messages).
    pub spec_path: String,
    /// A short name (spec `name`, else the file stem).
    pub name: String,
    /// Parameters of each map (one unless swept).
    pub maps: Vec<Params>,
    /// The swept parameter, if any.
    pub sweep: Option<Sweep>,
    /// The parameter space the maps are the points of (an atlas's too: one reader,
    /// [`Space::read`]); `maps` and `sweep` are read off it once.
    #[serde(flatten)]
    pub space: Space,
    /// The grid (or sample) of initial conditions and how each cell is classified.
    #[serde(flatten)]
    pub map: MapSettings,
    /// Time step.
    pub dt: f64,
    /// Solver settings.
    pub solver: SolverConfig,
    /// `[cycle]`: whether to locate, store and draw the unstable cycle, and the search.
    pub cycle: CycleOptions,
    /// The output file.
    pub output: PathBuf,
}

/// The basin maps of a plan: the grid (or random sample) of initial conditions and the
/// classifier of each cell, read from `[grid]` or `[sample]` and `[classifier]` by the same
/// code in a scan spec and an atlas spec (whose maps are one per parameter point).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MapSettings {
    /// The grid of initial conditions (an atlas's: its box is also the disturbance box).
    pub grid: Grid,
    /// Classifier settings (the trap is filled in per map from its located cycle).
    pub classifier: Classifier,
    /// Early-stopping rule.
    pub early_stop: EarlyStop,
    /// Relative half-width of the band around the cycle where runs go on.
    pub trap_margin: f64,
    /// With early stopping: about one cell in `audit_every` is also run to settlement
    /// (classifier without the trap) and the agreement stored; 0: no audit.
    pub audit_every: u64,
    /// Starts sampled near each map's boundary for the uncertainty exponent and the step
    /// sensitivity ([`crate::sensitivity`]); 0: none.
    pub sensitivity_samples: u64,
}

/// Default of `classifier.audit_every`: the audit then costs a few percent of an
/// early-stopped scan (a cell run to settlement near the cycle can take `t_max`).
pub const DEFAULT_AUDIT_EVERY: u64 = 1024;

/// Largest count along one grid axis.
pub const MAX_AXIS: i64 = 1 << 16;
/// Largest number of cells in one map.
pub const MAX_CELLS: i64 = 1 << 26;
/// Largest number of maps in a sweep.
pub const MAX_MAPS: i64 = 10_000;

/// Refuses a given `cycle.r_max` that does not reach every start of the grid on every map:
/// the start rule and the band's fates are read off the searched stretch of the section.
fn check_reach(
    cycle: &CycleOptions,
    maps: &[Params],
    grid: &Grid,
    invalid: Invalid,
) -> Result<(), ScanError> {
    if !cycle.r_max_given {
        return Ok(());
    }
    let reach = maps
        .iter()
        .map(|p| crate::grid::grid_reach(grid, p))
        .fold(0.0f64, f64::max);
    if cycle.search.r_max < reach {
        return Err(invalid(
            "cycle.r_max",
            format!("{:?}", cycle.search.r_max),
            &format!(
                "an amplitude reaching the grid's farthest start from the fixed point \
                 ({reach:.4}), or no key (then 1.2 times that, at least 4)"
            ),
        ));
    }
    Ok(())
}

/// The initial conditions: `[grid]` or `[sample]`, exactly one of them.
fn initial_conditions(
    grid: Option<&GridSpec>,
    sample: Option<&SampleSpec>,
    rules: Rules,
    invalid: Invalid,
) -> Result<Grid, ScanError> {
    let grid = match (grid, sample) {
        (Some(_), Some(_)) => {
            return Err(invalid(
                "sample",
                "both [grid] and [sample]".into(),
                "one of [grid] (a grid of initial conditions) or [sample] (random ones)",
            ));
        }
        (None, None) => {
            return Err(invalid(
                "grid",
                "neither [grid] nor [sample]".into(),
                "one of [grid] (a grid of initial conditions) or [sample] (random ones)",
            ));
        }
        (Some(gs), None) => gs.check(rules, &invalid)?,
        (None, Some(ss)) => {
            let SampleKind::Random = ss.kind;
            if !(1..=MAX_SAMPLES).contains(&ss.n) {
                return Err(invalid(
                    "sample.n",
                    ss.n.to_string(),
                    "a sample count in 1..=2^26",
                ));
            }
            let bound = |b: &[f64], key: &str| -> Result<Axis, ScanError> {
                use crate::bounds::{Width, pair, state_range};
                let [min, max] = match rules {
                    Rules::Today => state_range(key, b, Width::MayBeEmpty, &invalid)?,
                    Rules::Stored => pair(key, b, &invalid)?,
                };
                Ok(Axis { min, max, count: 1 })
            };
            let x0 = bound(&ss.region.x0, "sample.region.x0")?;
            let mut v0 = bound(&ss.region.v0, "sample.region.v0")?;
            v0.count = ss.n as usize;
            let block = ss.block.unwrap_or(DEFAULT_SAMPLE_BLOCK);
            if !(1..=MAX_AXIS).contains(&block) {
                return Err(invalid(
                    "sample.block",
                    block.to_string(),
                    "a sample count per stored block in 1..=65536",
                ));
            }
            Grid {
                x0,
                v0,
                block_rows: block as usize,
                starts: Starts::Sample(RandomSample {
                    n: ss.n as usize,
                    seed: ss.seed,
                }),
            }
        }
    };
    Ok(grid)
}

/// The spec text parsed into its tables (a TOML error names the file).
fn parse_spec(text: &str, path: &str) -> Result<SpecFile, ScanError> {
    toml::from_str(text).map_err(|e| ScanError::Parse {
        path: path.to_string(),
        // A float for an integer key is written by serde in full (309 digits for 1e308).
        message: squeal_core::error::readable_numbers(&e.to_string()),
    })
}

impl Plan {
    /// The integration setting of map `map`: its parameters with the plan's step and solver.
    pub fn setup(&self, map: usize) -> Setup {
        Setup::new(self.maps[map], self.dt, self.solver)
    }

    /// Reads and checks a spec file.
    pub fn from_file(path: &std::path::Path) -> Result<Plan, ScanError> {
        Plan::from_toml(&read_spec(path)?, &path.display().to_string())
    }

    /// Parses and checks spec text; `path` is used in messages and for the default name.
    pub fn from_toml(text: &str, path: &str) -> Result<Plan, ScanError> {
        Plan::from_parsed(parse_spec(text, path)?, text, path, None, Rules::Today)
    }

    /// Reads the spec stored in a file (or journal) this or an older squeal wrote, as the
    /// plan of what was run ([`Rules::Stored`]): a value outside a bound of today reads as
    /// stored, and only what the plan cannot be built without is refused, as "this file's
    /// stored spec" naming the key. `[physical]` keys the law does not use, which older
    /// versions required and then ignored (`mu_s`, `tau` under Coulomb), are dropped rather
    /// than refused (one swept is refused: that version made each of its values a point of
    /// an atlas).
    pub fn from_stored_toml(text: &str, path: &str) -> Result<Plan, ScanError> {
        Plan::from_stored_toml_table(text, path, None)
    }

    /// [`Plan::from_stored_toml`] with the friction table the file stores (`table`), which
    /// stands for the spec's `friction_table` or `friction_csv` (the CSV need not be where
    /// it was).
    pub fn from_stored_toml_table(
        text: &str,
        path: &str,
        table: Option<&'static squeal_core::FrictionTable>,
    ) -> Result<Plan, ScanError> {
        let read = || {
            let mut spec = parse_spec(text, path)?;
            if let Some(ph) = &mut spec.physical {
                ph.forget_unused(spec.model.law, &|key, value, expected| ScanError::Invalid {
                    path: path.to_string(),
                    key: key.to_string(),
                    value,
                    expected: expected.to_string(),
                })?;
            }
            Plan::from_parsed(spec, text, path, table, Rules::Stored)
        };
        read().map_err(crate::bounds::in_stored_spec)
    }

    /// The plan of the parsed spec `spec` of text `text`, read under `rules`.
    fn from_parsed(
        spec: SpecFile,
        text: &str,
        path: &str,
        stored: Option<&'static squeal_core::FrictionTable>,
        rules: Rules,
    ) -> Result<Plan, ScanError> {
        let invalid = |key: &str, value: String, expected: &str| ScanError::Invalid {
            path: path.to_string(),
            key: key.to_string(),
            value,
            expected: expected.to_string(),
        };
        if spec.version != SPEC_VERSION {
            return Err(invalid(
                "version",
                spec.version.to_string(),
                "this squeal reads spec version 1",
            ));
        }
        let folder = std::path::Path::new(path)
            .parent()
            .unwrap_or(std::path::Path::new(""));
        let limit = Limit {
            per_key: MAX_MAPS,
            points: MAX_MAPS as usize,
            noun: "maps",
        };
        let ph = spec.physical.as_ref();
        let space = Space::read(&spec.model, ph, (folder, stored), limit, &invalid)?;
        space.check_map_units(&invalid)?;
        physical::scan_sweeps_keys_with_a_model_twin(&space, &invalid)?;
        space.check_points(rules, &invalid)?;
        // The belt speed against the step before the grid: a clamp of 1e308 N makes both
        // the belt speed and the grid's cells vanish in the model's units, and it is the
        // clamp's key that the refusal should name.
        let (dt, solver) = spec.integration.check(rules, &invalid)?;
        rules.bound(|| space.check_step(dt, &invalid))?;
        let maps: Vec<Params> = (0..space.n_points()).map(|i| space.params_at(i)).collect();
        let (sweep, physical) = (space.sweep(), space.physical_at(0));
        let (grid, sample) = (spec.grid.as_ref(), spec.sample.as_ref());
        let mut grid = initial_conditions(grid, sample, rules, &invalid)?;
        if let Some(ph) = &physical {
            physical::grid_to_nondimensional(&mut grid, ph, rules, &invalid)?;
        }
        let ClassifierPlan {
            classifier,
            early_stop,
            trap_margin,
            audit_every,
            sensitivity_samples,
        } = spec.classifier.check(dt, grid.cells(), rules, &invalid)?;
        let cycle = spec.cycle.check(Shape::Scan, rules, &invalid)?;
        rules.bound(|| check_reach(&cycle, &maps, &grid, &invalid))?;
        let output = spec.output.check(&invalid)?;
        let name = tables::check_name(spec.name.as_deref(), path, "", &invalid)?;
        Ok(Plan {
            spec_text: text.to_string(),
            spec_path: path.to_string(),
            name,
            maps,
            sweep,
            space,
            map: MapSettings {
                grid,
                classifier,
                early_stop,
                trap_margin,
                audit_every,
                sensitivity_samples,
            },
            dt,
            solver,
            cycle,
            output,
        })
    }

    /// The physical system of the first map when the spec gives `[physical]` (SI units; a
    /// swept key's values are the sweep's SI twins, [`crate::si::SweptSi`]). The grid is
    /// stored nondimensional: its spec values were metres and m/s.
    pub fn physical(&self) -> Option<squeal_core::Physical> {
        self.space.physical_at(0)
    }

    /// The first setting (top-level field of the plan) in which `other` would compute
    /// something different, or `None` if both plans give the same results. The spec text,
    /// its path and the output path do not count (a comment edit or `-o` changes nothing).
    pub fn differs_from(&self, other: &Plan) -> Option<String> {
        first_difference(self, other, &["spec_text", "spec_path", "output"])
    }

    /// A rough time for `cells` cells on `threads` threads, in seconds, from documented rates
    /// (docs/history/benchmarks.md, "Basin scans": about 25 000 cells/s on 2 threads with
    /// `early_stop = "cycle"` on the paper's grids; without early stopping a cell may run to
    /// `t_max`, at up to about 250 ns per step with the robust solver, "Time per step").
    /// An order of magnitude, not a promise: cells near the boundary and off-paper
    /// parameters take longer.
    ///
    /// With early stopping the rate is scaled by the surfaces' time `tau` relative to the
    /// paper's (McMillan's laws): a run settles over a few of the slowest times of the
    /// model, and with `tau = 1e300` a 4-row block took 20 s where the rate promised
    /// "roughly 0 s". No cell costs more than its run to `t_max`, the bound used then.
    pub fn estimate_seconds(&self, cells: usize, threads: usize) -> f64 {
        let to_t_max = (self.map.classifier.t_max / self.dt) * 250e-9;
        let per_cell = match self.map.early_stop {
            EarlyStop::Cycle => {
                let slowest = self
                    .maps
                    .iter()
                    .filter_map(|p| p.law.surface())
                    .map(|c| c.tau / squeal_core::defaults::TAU)
                    .fold(1.0f64, f64::max);
                (2.0 / 25_000.0 * slowest).min(to_t_max)
            }
            EarlyStop::None => to_t_max,
        };
        cells as f64 * per_cell / threads.max(1) as f64
    }

    /// Blocks in the whole scan (all maps).
    pub fn total_blocks(&self) -> usize {
        self.maps.len() * self.map.grid.blocks()
    }

    /// Cells in the whole scan.
    pub fn total_cells(&self) -> usize {
        self.maps.len() * self.map.grid.cells()
    }

    /// The law (the same for every map).
    pub fn law(&self) -> FrictionLaw {
        self.maps[0].kind()
    }
}

/// The first top-level field (in name order) in which two serialised plans differ, the
/// fields `ignore` apart: how a scan and an atlas judge whether a stored spec computes the
/// same thing as the one given (comments and layout do not count).
pub fn first_difference<T: Serialize>(a: &T, b: &T, ignore: &[&str]) -> Option<String> {
    let table = |p: &T| {
        let mut t = toml::Table::try_from(p).unwrap_or_default();
        for k in ignore {
            t.remove(*k);
        }
        t
    };
    let (a, b) = (table(a), table(b));
    let mut keys: Vec<&String> = a.keys().chain(b.keys()).collect();
    keys.sort();
    keys.dedup();
    keys.into_iter()
        .find(|k| a.get(*k) != b.get(*k))
        .map(|k| k.to_string())
}

#[cfg(test)]
mod tests;
