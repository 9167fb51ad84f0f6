//! The atlas schema as a table: one row per stored figure (name, long name, units, how to
//! read it from and write it into a [`PointResult`]). The HDF5 writer and reader, the
//! journal and `--json` all walk this table, so adding a figure of merit is one line.

use super::boundary::{Boundary, BoundaryResult, BoundaryStatus};
use super::figures::{AtlasRegime, CycleFigures, PointResult, StickSlipFigures};
use super::spec::AtlasPlan;
pub use crate::si::Si;

/// How a column is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// f64, fill NaN.
    Real,
    /// u8 0/1, fill 255 (unknown).
    Flag,
    /// u64 count, fill 0.
    Count,
}

/// One stored figure of a point.
pub struct Column {
    /// Dataset name.
    pub name: &'static str,
    /// `long_name`.
    pub long_name: &'static str,
    /// Storage.
    pub kind: Kind,
    /// SI conversion (physical plans also store `<name>_si`).
    pub si: Si,
    /// Reads the value (NaN where absent).
    pub get: fn(&PointResult) -> f64,
    /// Writes the value (see [`finish_point`]).
    pub set: fn(&mut PointResult, f64),
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

fn flag(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

macro_rules! cycle_col {
    ($name:literal, $long:literal, $si:expr, $($f:tt)+) => {
        Column {
            name: $name,
            long_name: $long,
            kind: Kind::Real,
            si: $si,
            get: |p| p.cycle.as_ref().map_or(f64::NAN, |c| c.$($f)+),
            set: |p, v| cyc(p).$($f)+ = v,
        }
    };
}

macro_rules! stick_col {
    ($name:literal, $long:literal, $si:expr, $($f:tt)+) => {
        Column {
            name: $name,
            long_name: $long,
            kind: Kind::Real,
            si: $si,
            get: |p| p.stick_slip.as_ref().map_or(f64::NAN, |c| c.$($f)+),
            set: |p, v| stk(p).$($f)+ = v,
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
        kind: Kind::Flag,
        si: Si::None,
        get: |p| {
            p.cycle
                .as_ref()
                .map_or(f64::NAN, |c| flag(c.encloses_operating))
        },
        set: |p, v| {
            if !v.is_nan() {
                cyc(p).encloses_operating = v == 1.0
            }
        },
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
        kind: Kind::Real,
        si: Si::None,
        get: |p| p.basin_fraction,
        set: |p, v| p.basin_fraction = v,
    },
    Column {
        name: "basin_fraction_err",
        long_name: "uncertainty of basin_fraction (dt/2 shift of the cycle plus polygon chord error)",
        kind: Kind::Real,
        si: Si::None,
        get: |p| p.basin_fraction_err,
        set: |p, v| p.basin_fraction_err = v,
    },
    Column {
        name: "warm_started",
        long_name: "1 if the cycle search kept the neighbour's bracket",
        kind: Kind::Flag,
        si: Si::None,
        get: |p| flag(p.warm_started),
        set: |p, v| p.warm_started = v == 1.0,
    },
    Column {
        name: "returns",
        long_name: "section returns computed (each one revolution)",
        kind: Kind::Count,
        si: Si::None,
        get: |p| p.returns as f64,
        set: |p, v| p.returns = v as u64,
    },
    Column {
        name: "evaluations",
        long_name: "friction-law evaluations",
        kind: Kind::Count,
        si: Si::None,
        get: |p| p.evaluations as f64,
        set: |p, v| p.evaluations = v as u64,
    },
    Column {
        name: "failures",
        long_name: "solver failures",
        kind: Kind::Count,
        si: Si::None,
        get: |p| p.failures as f64,
        set: |p, v| p.failures = v as u64,
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

/// One stored figure of a boundary search.
pub struct BoundaryColumn {
    /// Dataset name.
    pub name: &'static str,
    /// `long_name`.
    pub long_name: &'static str,
    /// Reads the value.
    pub get: fn(&BoundaryResult) -> f64,
    /// Writes it.
    pub set: fn(&mut BoundaryResult, f64),
    /// Its SI twin in a physical plan.
    pub si: BoundarySi,
    /// Whether a plan stores it (the lifetimes only where measured).
    pub stored: fn(&AtlasPlan) -> bool,
}

/// The SI twin of a boundary figure in a physical plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoundarySi {
    /// A value of the bisected parameter: `<name>` with `nu` replaced by `c` (N s/m), or
    /// `lambda` by `v_belt` (m/s).
    Bisected,
    /// A nondimensional time: `<name>_s`, in seconds.
    Time,
    /// A ratio or exponent: no twin.
    None,
}

/// The boundary figures in `nu` (physical plans also store `<name>` with `nu` replaced by
/// `c`, in N s/m). The statuses are stored separately as enums.
pub const BOUNDARY_COLUMNS: &[BoundaryColumn] = &[
    BoundaryColumn {
        name: "fold_nu",
        long_name: "fold of cycles: damping ratio above which no start squeals",
        get: |b| b.fold.nu,
        set: |b, v| b.fold.nu = v,
        si: BoundarySi::Bisected,
        stored: |_| true,
    },
    BoundaryColumn {
        name: "fold_nu_lo",
        long_name: "fold of cycles: lower end of the bracket (squeal possible)",
        get: |b| b.fold.bracket[0],
        set: |b, v| b.fold.bracket[0] = v,
        si: BoundarySi::Bisected,
        stored: |_| true,
    },
    BoundaryColumn {
        name: "fold_nu_hi",
        long_name: "fold of cycles: upper end of the bracket (no start squeals)",
        get: |b| b.fold.bracket[1],
        set: |b, v| b.fold.bracket[1] = v,
        si: BoundarySi::Bisected,
        stored: |_| true,
    },
    BoundaryColumn {
        name: "fold_nu_err",
        long_name: "fold of cycles: uncertainty, half the width of the interval that holds the fold at dt, dt/2 and the longer horizon (fold_nu -+ fold_nu_err; NaN: not estimated)",
        get: |b| b.fold.uncertainty,
        set: |b, v| b.fold.uncertainty = v,
        si: BoundarySi::Bisected,
        stored: |_| true,
    },
    BoundaryColumn {
        name: "fold_lifetime_nu",
        long_name: "transient lifetimes above the fold: the damping ratio of the nearest measurement, about 1% above fold_nu ([boundaries] lifetime_starts; NaN: not measured)",
        get: |b| b.lifetime.nu,
        set: |b, v| b.lifetime.nu = v,
        si: BoundarySi::Bisected,
        stored: |p| p.lifetime_starts > 0,
    },
    BoundaryColumn {
        name: "fold_lifetime",
        long_name: "transient lifetimes above the fold: mean time a start on the leaking stick-slip band squeals before it settles, at fold_lifetime_nu (nondimensional time; the natural period is 2 pi)",
        get: |b| b.lifetime.mean,
        set: |b, v| b.lifetime.mean = v,
        si: BoundarySi::Time,
        stored: |p| p.lifetime_starts > 0,
    },
    BoundaryColumn {
        name: "fold_lifetime_err",
        long_name: "transient lifetimes above the fold: standard error of fold_lifetime",
        get: |b| b.lifetime.se,
        set: |b, v| b.lifetime.se = v,
        si: BoundarySi::Time,
        stored: |p| p.lifetime_starts > 0,
    },
    BoundaryColumn {
        name: "fold_lifetime_censored",
        long_name: "transient lifetimes above the fold: share of the starts at fold_lifetime_nu still squealing at the time limit (censored)",
        get: |b| b.lifetime.censored,
        set: |b, v| b.lifetime.censored = v,
        si: BoundarySi::None,
        stored: |p| p.lifetime_starts > 0,
    },
    BoundaryColumn {
        name: "fold_lifetime_exponent",
        long_name: "transient lifetimes above the fold: exponent gamma of mean lifetime ~ (nu - fold_nu)^(-gamma), fitted over 1% to 7.5% above the fold",
        get: |b| b.lifetime.exponent,
        set: |b, v| b.lifetime.exponent = v,
        si: BoundarySi::None,
        stored: |p| p.lifetime_starts > 0,
    },
    BoundaryColumn {
        name: "fold_lifetime_exponent_err",
        long_name: "transient lifetimes above the fold: standard error of fold_lifetime_exponent",
        get: |b| b.lifetime.exponent_se,
        set: |b, v| b.lifetime.exponent_se = v,
        si: BoundarySi::None,
        stored: |p| p.lifetime_starts > 0,
    },
    BoundaryColumn {
        name: "critical_nu",
        long_name: "critical damping ratio: the operating point stops squealing above it",
        get: |b| b.critical.nu,
        set: |b, v| b.critical.nu = v,
        si: BoundarySi::Bisected,
        stored: |_| true,
    },
    BoundaryColumn {
        name: "critical_nu_lo",
        long_name: "critical damping: lower end of the bracket (operating point squeals)",
        get: |b| b.critical.bracket[0],
        set: |b, v| b.critical.bracket[0] = v,
        si: BoundarySi::Bisected,
        stored: |_| true,
    },
    BoundaryColumn {
        name: "critical_nu_hi",
        long_name: "critical damping: upper end of the bracket (operating point quiet)",
        get: |b| b.critical.bracket[1],
        set: |b, v| b.critical.bracket[1] = v,
        si: BoundarySi::Bisected,
        stored: |_| true,
    },
];

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
        for (k, c) in COLUMNS.iter().enumerate() {
            let v = match c.kind {
                Kind::Flag => 1.0,
                _ => k as f64 + 0.5,
            };
            (c.set)(&mut p, if c.kind == Kind::Count { k as f64 } else { v });
        }
        finish_point(&mut p);
        for (k, c) in COLUMNS.iter().enumerate() {
            let want = match c.kind {
                Kind::Flag => 1.0,
                Kind::Count => k as f64,
                Kind::Real => k as f64 + 0.5,
            };
            assert_eq!((c.get)(&p), want, "{}", c.name);
        }
        let names: std::collections::HashSet<_> = COLUMNS.iter().map(|c| c.name).collect();
        assert_eq!(names.len(), COLUMNS.len(), "duplicate column names");
    }
}
