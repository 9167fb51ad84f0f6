//! The atlas schema as a table: one row per stored figure (name, long name, units, how to
//! read it from and write it into a [`PointResult`] or a [`BoundaryResult`]), in the one
//! column type of every stored table ([`crate::column::Column`]). The HDF5 writer and reader, the
//! journal and `--json` all walk this table, so adding a figure of merit is one line.

use super::boundary::{Boundary, BoundaryResult, BoundaryStatus};
use super::figures::{AtlasRegime, CycleFigures, PointResult, StickSlipFigures};
use super::spec::AtlasPlan;
pub use crate::column::{Kind, Num, Twin};
pub use crate::si::Si;

/// One stored figure of a point.
pub type Column = crate::column::Column<PointResult>;

/// One stored figure of a boundary search.
pub type BoundaryColumn = crate::column::Column<BoundaryResult>;

/// Members of a point's yes/no figures (`cycle_encloses_operating_point`, `warm_started`).
pub const YES_NO_UNKNOWN: &[(u8, &str)] = &[(0, "no"), (1, "yes"), (UNKNOWN, "unknown")];

/// The flags of `steady_slip_stability`: [`squeal_core::Stability`]'s values and names
/// (a test holds them equal), and unknown.
pub const STABILITY_FLAGS: &[(u8, &str)] = &[
    (1, "attracts"),
    (2, "repels"),
    (3, "attracts_a_sector"),
    (4, "marginal"),
    (UNKNOWN, "unknown"),
];

/// The fill of a point's yes/no figures: not known.
pub(crate) const UNKNOWN: u8 = 255;

/// The SI twin of a point's figure converted by `si`.
const fn twin(si: Si) -> Twin {
    match si {
        Si::None => Twin::None,
        si => Twin::Si(si),
    }
}

/// The units of a point's nondimensional figure converted by `si`.
const fn nd_units(si: Si) -> &'static str {
    match si {
        Si::Frequency => "1 (angular frequency, nondimensional)",
        _ => "1",
    }
}

fn cyc(p: &mut PointResult) -> &mut CycleFigures {
    p.cycle.get_or_insert(CycleFigures {
        r_section: f64::NAN,
        bracket: [f64::NAN; 2],
        half_dt_shift: f64::NAN,
        distance_plus_x: f64::NAN,
        min_distance: f64::NAN,
        min_kick: f64::NAN,
        period: f64::NAN,
        multiplier: f64::NAN,
        area: f64::NAN,
        x_range: [f64::NAN; 2],
        v_range: [f64::NAN; 2],
        encloses_operating: false,
    })
}

fn stk(p: &mut PointResult) -> &mut StickSlipFigures {
    p.stick_slip.get_or_insert(StickSlipFigures {
        r_band: [f64::NAN; 3],
        drift: f64::NAN,
        x_range: [f64::NAN; 2],
        v_range: [f64::NAN; 2],
        overshoot: f64::NAN,
        omega_mean: f64::NAN,
        omega_std: f64::NAN,
        quasi_static_share: f64::NAN,
    })
}

fn flag(b: bool) -> Num {
    Num::U(u64::from(b))
}

macro_rules! cycle_col {
    ($name:literal, $long:literal, $si:expr, $($f:tt)+) => {
        Column {
            name: $name,
            long_name: $long,
            units: nd_units($si),
            kind: Kind::F64,
            flags: &[],
            fill: Num::F(f64::NAN),
            get: |p| Num::F(p.cycle.as_ref().map_or(f64::NAN, |c| c.$($f)+)),
            set: |p, v| cyc(p).$($f)+ = v.as_f64(),
            si: twin($si),
        }
    };
}

macro_rules! stick_col {
    ($name:literal, $long:literal, $si:expr, $($f:tt)+) => {
        Column {
            name: $name,
            long_name: $long,
            units: nd_units($si),
            kind: Kind::F64,
            flags: &[],
            fill: Num::F(f64::NAN),
            get: |p| Num::F(p.stick_slip.as_ref().map_or(f64::NAN, |c| c.$($f)+)),
            set: |p, v| stk(p).$($f)+ = v.as_f64(),
            si: twin($si),
        }
    };
}

/// Every stored figure of a point, in file order.
pub const COLUMNS: &[Column] = &[
    cycle_col!(
        "cycle_r_section",
        "unstable cycle: x' where it crosses x = x* going right",
        Si::Velocity,
        r_section
    ),
    cycle_col!(
        "cycle_bracket_lo",
        "unstable cycle: lower end of the bisection bracket on r_section",
        Si::Velocity,
        bracket[0]
    ),
    cycle_col!(
        "cycle_bracket_hi",
        "unstable cycle: upper end of the bisection bracket on r_section",
        Si::Velocity,
        bracket[1]
    ),
    cycle_col!(
        "cycle_half_dt_shift",
        "unstable cycle: change of r_section when dt halves",
        Si::Velocity,
        half_dt_shift
    ),
    cycle_col!(
        "cycle_distance_plus_x",
        "unstable cycle: distance from the fixed point along +x",
        Si::Length,
        distance_plus_x
    ),
    cycle_col!(
        "cycle_min_distance",
        "unstable cycle: smallest distance from the fixed point (smallest disturbance that squeals)",
        Si::None,
        min_distance
    ),
    cycle_col!(
        "cycle_min_kick",
        "unstable cycle: smallest pure velocity kick from steady slip that squeals",
        Si::Velocity,
        min_kick
    ),
    cycle_col!("cycle_period", "unstable cycle: period", Si::Time, period),
    cycle_col!(
        "cycle_multiplier",
        "unstable cycle: Floquet multiplier (growth per revolution)",
        Si::None,
        multiplier
    ),
    cycle_col!(
        "cycle_area",
        "unstable cycle: enclosed phase-plane area",
        Si::Area,
        area
    ),
    cycle_col!(
        "cycle_x_min",
        "unstable cycle: smallest x",
        Si::Length,
        x_range[0]
    ),
    cycle_col!(
        "cycle_x_max",
        "unstable cycle: largest x",
        Si::Length,
        x_range[1]
    ),
    cycle_col!(
        "cycle_v_min",
        "unstable cycle: smallest x'",
        Si::Velocity,
        v_range[0]
    ),
    cycle_col!(
        "cycle_v_max",
        "unstable cycle: largest x'",
        Si::Velocity,
        v_range[1]
    ),
    Column {
        name: "cycle_encloses_operating_point",
        long_name: "unstable cycle encloses the operating point (1: it does not squeal)",
        units: "",
        kind: Kind::Enum,
        flags: YES_NO_UNKNOWN,
        fill: Num::U(UNKNOWN as u64),
        get: |p| {
            p.cycle
                .as_ref()
                .map_or(Num::U(UNKNOWN as u64), |c| flag(c.encloses_operating))
        },
        set: |p, v| {
            if v.as_u64() != UNKNOWN as u64 {
                cyc(p).encloses_operating = v.as_u64() == 1
            }
        },
        si: Twin::None,
    },
    stick_col!(
        "stick_r_min",
        "stick-slip: smallest section amplitude in the window",
        Si::Velocity,
        r_band[0]
    ),
    stick_col!(
        "stick_r_mean",
        "stick-slip: mean section amplitude in the window",
        Si::Velocity,
        r_band[1]
    ),
    stick_col!(
        "stick_r_max",
        "stick-slip: largest section amplitude in the window",
        Si::Velocity,
        r_band[2]
    ),
    stick_col!(
        "stick_drift",
        "stick-slip: relative change of the mean section amplitude over the window",
        Si::None,
        drift
    ),
    stick_col!(
        "stick_x_min",
        "stick-slip: smallest x",
        Si::Length,
        x_range[0]
    ),
    stick_col!(
        "stick_x_max",
        "stick-slip: largest x",
        Si::Length,
        x_range[1]
    ),
    stick_col!(
        "stick_v_min",
        "stick-slip: smallest x'",
        Si::Velocity,
        v_range[0]
    ),
    stick_col!(
        "stick_v_max",
        "stick-slip: largest x'",
        Si::Velocity,
        v_range[1]
    ),
    stick_col!(
        "stick_overshoot",
        "stick-slip: largest x' minus the belt speed",
        Si::Velocity,
        overshoot
    ),
    stick_col!(
        "stick_omega_mean",
        "stick-slip: mean angular frequency",
        Si::Frequency,
        omega_mean
    ),
    stick_col!(
        "stick_omega_std",
        "stick-slip: standard deviation of the per-revolution angular frequency",
        Si::Frequency,
        omega_std
    ),
    stick_col!(
        "stick_quasi_static_share",
        "stick-slip: share of time on the quasi-static branch",
        Si::None,
        quasi_static_share
    ),
    Column {
        name: "basin_fraction",
        long_name: "share of the disturbance box that returns to steady slip",
        units: "1",
        kind: Kind::F64,
        flags: &[],
        fill: Num::F(f64::NAN),
        get: |p| Num::F(p.basin_fraction),
        set: |p, v| p.basin_fraction = v.as_f64(),
        si: Twin::None,
    },
    Column {
        name: "basin_fraction_err",
        long_name: "uncertainty of basin_fraction (dt/2 shift of the cycle plus polygon chord error)",
        units: "1",
        kind: Kind::F64,
        flags: &[],
        fill: Num::F(f64::NAN),
        get: |p| Num::F(p.basin_fraction_err),
        set: |p, v| p.basin_fraction_err = v.as_f64(),
        si: Twin::None,
    },
    Column {
        name: "warm_started",
        long_name: "1 if the cycle search kept the neighbour's bracket",
        units: "",
        kind: Kind::Enum,
        flags: YES_NO_UNKNOWN,
        fill: Num::U(UNKNOWN as u64),
        get: |p| flag(p.warm_started),
        set: |p, v| p.warm_started = v.as_u64() == 1,
        si: Twin::None,
    },
    Column {
        name: "steady_slip_stability",
        long_name: "steady slip's own stability from the law linearised at the fixed point",
        units: "",
        kind: Kind::Enum,
        flags: STABILITY_FLAGS,
        fill: Num::U(UNKNOWN as u64),
        get: |p| Num::U(p.steady_slip as u64),
        set: |p, v| p.steady_slip = v.as_u64() as u8,
        si: Twin::None,
    },
    Column {
        name: "steady_slip_growth",
        long_name: "growth rate of small motions about steady slip (negative: they decay; NaN: runs near it jump)",
        units: "1",
        kind: Kind::F64,
        flags: &[],
        fill: Num::F(f64::NAN),
        get: |p| Num::F(p.steady_slip_growth),
        set: |p, v| p.steady_slip_growth = v.as_f64(),
        si: twin(Si::Rate),
    },
    Column {
        name: "returns",
        long_name: "section returns computed (each one revolution)",
        units: "",
        kind: Kind::U64,
        flags: &[],
        fill: Num::U(0),
        get: |p| Num::U(p.returns),
        set: |p, v| p.returns = v.as_u64(),
        si: Twin::None,
    },
    Column {
        name: "evaluations",
        long_name: "friction-law evaluations",
        units: "",
        kind: Kind::U64,
        flags: &[],
        fill: Num::U(0),
        get: |p| Num::U(p.evaluations),
        set: |p, v| p.evaluations = v.as_u64(),
        si: Twin::None,
    },
    Column {
        name: "failures",
        long_name: "solver failures",
        units: "",
        kind: Kind::U64,
        flags: &[],
        fill: Num::U(0),
        get: |p| Num::U(p.failures),
        set: |p, v| p.failures = v.as_u64(),
        si: Twin::None,
    },
];

/// An empty point (undecided, nothing located), to be filled by the setters.
pub fn empty_point() -> PointResult {
    PointResult {
        regime: AtlasRegime::Undecided,
        cycle: None,
        stick_slip: None,
        basin_fraction: f64::NAN,
        basin_fraction_err: f64::NAN,
        warm_started: false,
        returns: 0,
        evaluations: 0,
        failures: 0,
        note: None,
        landscape: None,
        steady_slip: UNKNOWN,
        steady_slip_growth: f64::NAN,
    }
}

/// Drops the cycle or stick-slip figures that the setters created from fills.
pub fn finish_point(p: &mut PointResult) {
    if p.cycle.is_some_and(|c| c.r_section.is_nan()) {
        p.cycle = None;
    }
    if p.stick_slip.is_some_and(|s| s.r_band[1].is_nan()) {
        p.stick_slip = None;
    }
}

macro_rules! boundary_col {
    ($name:literal, $long:literal, $twin:expr, $($f:tt)+) => {
        BoundaryColumn {
            name: $name,
            long_name: $long,
            units: "1",
            kind: Kind::F64,
            flags: &[],
            fill: Num::F(f64::NAN),
            get: |b| Num::F(b.$($f)+),
            set: |b, v| b.$($f)+ = v.as_f64(),
            si: $twin,
        }
    };
}

/// The boundary figures in `nu` (physical plans also store `<name>` with `nu` replaced by
/// `c`, in N s/m). The statuses are stored separately as enums. The `fold_lifetime*`
/// figures are stored only where a plan measures them ([`boundary_stored`]).
pub const BOUNDARY_COLUMNS: &[BoundaryColumn] = &[
    boundary_col!(
        "fold_nu",
        "fold of cycles: damping ratio above which no start squeals",
        Twin::Bisected,
        fold.nu
    ),
    boundary_col!(
        "fold_nu_lo",
        "fold of cycles: lower end of the bracket (squeal possible)",
        Twin::Bisected,
        fold.bracket[0]
    ),
    boundary_col!(
        "fold_nu_hi",
        "fold of cycles: upper end of the bracket (no start squeals)",
        Twin::Bisected,
        fold.bracket[1]
    ),
    boundary_col!(
        "fold_nu_err",
        "fold of cycles: uncertainty, half the width of the interval that holds the fold at dt, dt/2 and the longer horizon (fold_nu -+ fold_nu_err; NaN: not estimated)",
        Twin::Bisected,
        fold.uncertainty
    ),
    boundary_col!(
        "fold_lifetime_nu",
        "transient lifetimes above the fold: the damping ratio of the nearest measurement, about 1% above fold_nu ([boundaries] lifetime_starts; NaN: not measured)",
        Twin::Bisected,
        lifetime.nu
    ),
    boundary_col!(
        "fold_lifetime",
        "transient lifetimes above the fold: mean time a start on the leaking stick-slip band squeals before it settles, at fold_lifetime_nu (nondimensional time; the natural period is 2 pi)",
        Twin::Seconds,
        lifetime.mean
    ),
    boundary_col!(
        "fold_lifetime_err",
        "transient lifetimes above the fold: standard error of fold_lifetime",
        Twin::Seconds,
        lifetime.se
    ),
    boundary_col!(
        "fold_lifetime_censored",
        "transient lifetimes above the fold: share of the starts at fold_lifetime_nu still squealing at the time limit (censored)",
        Twin::None,
        lifetime.censored
    ),
    boundary_col!(
        "fold_lifetime_exponent",
        "transient lifetimes above the fold: exponent gamma of mean lifetime ~ (nu - fold_nu)^(-gamma), fitted over 1% to 7.5% above the fold",
        Twin::None,
        lifetime.exponent
    ),
    boundary_col!(
        "fold_lifetime_exponent_err",
        "transient lifetimes above the fold: standard error of fold_lifetime_exponent",
        Twin::None,
        lifetime.exponent_se
    ),
    boundary_col!(
        "critical_nu",
        "critical damping ratio: the operating point stops squealing above it",
        Twin::Bisected,
        critical.nu
    ),
    boundary_col!(
        "critical_nu_lo",
        "critical damping: lower end of the bracket (operating point squeals)",
        Twin::Bisected,
        critical.bracket[0]
    ),
    boundary_col!(
        "critical_nu_hi",
        "critical damping: upper end of the bracket (operating point quiet)",
        Twin::Bisected,
        critical.bracket[1]
    ),
];

/// The names of the boundary figures of the transient lifetimes above the fold.
const LIFETIME: &str = "fold_lifetime";

/// Whether a plan stores a boundary figure: the lifetimes only where measured
/// (`[boundaries] lifetime_starts` above 0).
pub fn boundary_stored(plan: &AtlasPlan, c: &BoundaryColumn) -> bool {
    !c.name.starts_with(LIFETIME) || plan.lifetime_starts > 0
}

/// An empty boundary result for index `j`.
pub fn empty_boundary(j: usize) -> BoundaryResult {
    BoundaryResult {
        index: j,
        fold: Boundary::none(),
        critical: Boundary::none(),
        lifetime: Default::default(),
        note: None,
    }
}

/// The statuses' names in value order, for CF `flag_meanings`.
pub fn status_meanings() -> String {
    BoundaryStatus::ALL
        .iter()
        .map(|s| s.name())
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_round_trip_a_point() {
        let mut p = empty_point();
        p.regime = AtlasRegime::BistableQuiet;
        let want = |k: usize, c: &Column| match c.kind {
            Kind::F64 => k as f64 + 0.5,
            Kind::Enum => 1.0,
            _ => k as f64,
        };
        for (k, c) in COLUMNS.iter().enumerate() {
            c.set_value(&mut p, want(k, c));
        }
        finish_point(&mut p);
        for (k, c) in COLUMNS.iter().enumerate() {
            assert_eq!(c.value(&p), want(k, c), "{}", c.name);
        }
    }

    /// The stored flags of `steady_slip_stability` are the verdicts' values and names.
    #[test]
    fn stability_flags_are_the_verdicts() {
        let verdicts: Vec<(u8, &str)> = squeal_core::Stability::ALL
            .iter()
            .map(|s| (*s as u8, s.name()))
            .chain([(UNKNOWN, "unknown")])
            .collect();
        assert_eq!(STABILITY_FLAGS, &verdicts[..]);
    }
}
