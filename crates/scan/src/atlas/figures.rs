//! What an atlas point computes, and with which settings: its regime, the unstable cycle's,
//! the stick-slip attractor's and the landscape's figures of merit, gathered in
//! [`PointResult`]. The computations live in [`super::point`], [`super::attractor`] and
//! [`super::true_stick`]; these types sit below all three, so each can name the others'
//! results without a circle of imports.

use serde::{Deserialize, Serialize};
use squeal_core::{Landscape, LandscapeEvidence, State, units::Scales};

use super::geometry::Region;
use super::note::Note;
use crate::landscape::LANDSCAPE_FIELDS;
use crate::ulc::CycleSettings;

/// The regime of one parameter point. Stored as the HDF5 enum `regime`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
#[serde(rename_all = "snake_case")]
pub enum AtlasRegime {
    /// The evidence conflicts (the section method says the operating point squeals but its
    /// own run settles, a cycle but no stick-slip attractor found, or a failed run); the
    /// point's note says which.
    Undecided = 0,
    /// No start squeals: `D(r) < 0` on the whole sampled section range.
    SteadySlipOnly = 1,
    /// Steady slip and stick-slip coexist; the operating point is inside the unstable cycle.
    BistableQuiet = 2,
    /// Steady slip and stick-slip coexist; the operating point is outside: it squeals.
    BistableSqueals = 3,
    /// `D(r_min) > 0`: the fixed point repels, or its unstable cycle is smaller than the
    /// search's resolution `r_min` (the label rests on that): every start squeals.
    FixedPointUnstable = 4,
}

impl AtlasRegime {
    /// All regimes, in value order.
    pub const ALL: [AtlasRegime; 5] = [
        AtlasRegime::Undecided,
        AtlasRegime::SteadySlipOnly,
        AtlasRegime::BistableQuiet,
        AtlasRegime::BistableSqueals,
        AtlasRegime::FixedPointUnstable,
    ];

    /// The name in files and output.
    pub fn name(self) -> &'static str {
        match self {
            AtlasRegime::Undecided => "undecided",
            AtlasRegime::SteadySlipOnly => "steady_slip_only",
            AtlasRegime::BistableQuiet => "bistable_quiet",
            AtlasRegime::BistableSqueals => "bistable_squeals",
            AtlasRegime::FixedPointUnstable => "fixed_point_unstable",
        }
    }

    /// Words for legends.
    pub fn description(self) -> &'static str {
        match self {
            AtlasRegime::Undecided => "undecided",
            AtlasRegime::SteadySlipOnly => "steady slip only (no start squeals)",
            AtlasRegime::BistableQuiet => "bistable, operating point quiet",
            AtlasRegime::BistableSqueals => "bistable, operating point squeals",
            AtlasRegime::FixedPointUnstable => "every start squeals (no cycle above r_min)",
        }
    }

    /// From the stored value.
    pub fn from_u8(v: u8) -> Option<AtlasRegime> {
        AtlasRegime::ALL.into_iter().find(|r| *r as u8 == v)
    }

    /// Whether the operating point squeals, where the regime says.
    pub fn operating_point_squeals(self) -> Option<bool> {
        match self {
            AtlasRegime::Undecided => None,
            AtlasRegime::SteadySlipOnly | AtlasRegime::BistableQuiet => Some(false),
            AtlasRegime::BistableSqueals | AtlasRegime::FixedPointUnstable => Some(true),
        }
    }
}

/// Settings of one point's computation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PointSettings {
    /// Cycle search (`r_max` is raised to `2 lambda` where that is larger).
    pub cycle: CycleSettings,
    /// Golden-section refinements of the largest negative `D` (0: no tangency check).
    pub tangency_iters: u32,
    /// Stick-slip revolutions discarded before the window.
    pub transient: u32,
    /// Stick-slip revolutions in the window.
    pub window: u32,
    /// The operating point (nondimensional).
    pub operating: State,
    /// The disturbance region (nondimensional).
    pub disturbance: Region,
    /// The physical system's scales, in physical plans: notes then state amplitudes and
    /// times in SI units (the computation itself is nondimensional).
    #[serde(skip)]
    pub units: Option<Scales>,
}

impl PointSettings {
    /// A section amplitude `r` (x' at the section) in words: `r = 0.236000`, or in a
    /// physical plan `x' = 2.950e-2 m/s (r = 0.236000)`.
    pub fn amplitude_words(&self, r: f64) -> String {
        match &self.units {
            Some(s) => format!("x' = {:.3e} m/s (r = {r:.6})", r * s.velocity),
            None => format!("r = {r:.6}"),
        }
    }

    /// A lasting oscillation's figures in words: its frequency and half-ranges of `x` and
    /// `x'`, in Hz, m and m/s in a physical plan, and whether it sticks or overtakes the belt.
    pub fn lasting_words(&self, l: &squeal_core::Lasting) -> String {
        let half = |r: [f64; 2]| 0.5 * (r[1] - r[0]);
        let (dx, dv) = (half(l.x_range), half(l.v_range));
        let how = match (l.stuck, l.reversed) {
            (true, true) => ", sticks and overtakes the belt",
            (true, false) => ", sticks",
            (false, true) => ", overtakes the belt",
            (false, false) => "",
        };
        match &self.units {
            Some(s) => format!(
                "{:.1} Hz, x +-{:.3e} m, x' +-{:.3} m/s{how}",
                s.hz(l.omega),
                dx * s.length,
                dv * s.velocity
            ),
            None => format!("omega {:.4}, x +-{dx:.4}, x' +-{dv:.4}{how}", l.omega),
        }
    }

    /// A time `t` in words: `t = 134.2` (`decimals` after the point), or in a physical plan
    /// `t = 0.8491 s`.
    pub fn time_words(&self, t: f64, decimals: usize) -> String {
        match &self.units {
            Some(s) => format!("t = {:.4} s", t * s.time),
            None => format!("t = {t:.decimals$}"),
        }
    }
}

impl Default for PointSettings {
    fn default() -> Self {
        // The atlas's `[cycle]` defaults, from the one table.
        let cycle = crate::spec::CycleOptions::atlas();
        PointSettings {
            cycle: cycle.search,
            tangency_iters: cycle.tangency_iters,
            transient: 40,
            window: 40,
            operating: State { x: 0.0, v: 0.0 },
            disturbance: Region {
                x: [-2.0, 4.0],
                v: [-3.0, 3.0],
            },
            units: None,
        }
    }
}

/// The unstable cycle's figures of merit (nondimensional).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CycleFigures {
    /// `x'` where the cycle crosses `x = x*` going right.
    pub r_section: f64,
    /// Final bisection bracket.
    pub bracket: [f64; 2],
    /// How `r_section` moves when `dt` halves (NaN if not checked or not found).
    pub half_dt_shift: f64,
    /// Distance from the fixed point to the cycle along `+x`.
    pub distance_plus_x: f64,
    /// Smallest distance from the fixed point to the cycle (smallest disturbance that squeals).
    pub min_distance: f64,
    /// Smallest pure velocity kick from steady slip that leaves the cycle.
    pub min_kick: f64,
    /// Period of one revolution.
    pub period: f64,
    /// Floquet multiplier `P'(r_u)`.
    pub multiplier: f64,
    /// Enclosed area.
    pub area: f64,
    /// Extent in `x`.
    pub x_range: [f64; 2],
    /// Extent in `x'`.
    pub v_range: [f64; 2],
    /// Whether the cycle encloses the operating point.
    pub encloses_operating: bool,
}

/// Everything computed at one parameter point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointResult {
    /// The regime.
    pub regime: AtlasRegime,
    /// The unstable cycle, where there is one.
    pub cycle: Option<CycleFigures>,
    /// The stick-slip attractor, where it was reached.
    pub stick_slip: Option<StickSlipFigures>,
    /// Share of the disturbance box from which the system returns to steady slip.
    pub basin_fraction: f64,
    /// Its uncertainty (see [`basin_fraction`]).
    pub basin_fraction_err: f64,
    /// Whether the cycle search started from the neighbour's bracket and kept it.
    pub warm_started: bool,
    /// Section returns computed (each one revolution).
    pub returns: u64,
    /// Friction-law evaluations.
    pub evaluations: u64,
    /// Solver failures met.
    pub failures: u64,
    /// Why the point is undecided, or the caveat its label rests on ([`Note`]).
    pub note: Option<Note>,
    /// The landscape and its evidence, for laws with true stick ([`super::true_stick`]).
    #[serde(default)]
    pub landscape: Option<LandscapeRecord>,
    /// Steady slip's own stability ([`squeal_core::Stability`] value; 255: unknown).
    #[serde(default = "unknown_stability")]
    pub steady_slip: u8,
    /// The growth rate of small motions about steady slip ([`squeal_core::SteadySlip`]).
    #[serde(default = "nan")]
    pub steady_slip_growth: f64,
}

fn unknown_stability() -> u8 {
    super::columns::UNKNOWN
}

fn nan() -> f64 {
    f64::NAN
}

/// The stick-slip attractor's figures of merit over a window of revolutions.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct StickSlipFigures {
    /// Section amplitudes over the window: min, mean, max.
    pub r_band: [f64; 3],
    /// Relative change of the mean section amplitude from the window's first half to its
    /// second half (near 0 when settled).
    pub drift: f64,
    /// Extent in `x`.
    pub x_range: [f64; 2],
    /// Extent in `x'`.
    pub v_range: [f64; 2],
    /// `max x' - lambda`: how far the block overtakes the belt (negative: it never does).
    pub overshoot: f64,
    /// Mean angular frequency over the window's revolutions.
    pub omega_mean: f64,
    /// Standard deviation of the per-revolution angular frequency.
    pub omega_std: f64,
    /// Share of the window's steps on the quasi-static branch of the law.
    pub quasi_static_share: f64,
}

/// The landscape of one point as stored: the verdict and the numbers it rests on.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LandscapeRecord {
    /// The verdict ([`Landscape`] as stored, `landscape` in files).
    pub landscape: u8,
    /// The fixed point's effective damping `2 xi + mu'(v_d)` (negative: it repels).
    pub damping: f64,
    /// Period of the stick-slip cycle, breakaway to breakaway (NaN: none found).
    pub cycle_period: f64,
    /// Time stuck per period of that cycle (NaN: none found).
    pub cycle_stuck: f64,
}

impl LandscapeRecord {
    /// From the evidence (the numbers of [`LANDSCAPE_FIELDS`]).
    pub fn from_evidence(e: &LandscapeEvidence) -> LandscapeRecord {
        LandscapeRecord {
            landscape: e.landscape as u8,
            damping: (LANDSCAPE_FIELDS[0].3)(e),
            cycle_period: (LANDSCAPE_FIELDS[1].3)(e),
            cycle_stuck: (LANDSCAPE_FIELDS[2].3)(e),
        }
    }

    /// The verdict (`None` for a value no build wrote).
    pub fn verdict(&self) -> Option<Landscape> {
        Landscape::from_u8(self.landscape)
    }
}
