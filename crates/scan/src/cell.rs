//! One classified cell and the table of its stored columns.
//!
//! [`COLUMNS`] is the one place where a per-cell quantity is declared: its name, long name,
//! units, storage type, fill value (for cells not computed) and how to get and set it on a
//! [`Cell`]. The journal, the HDF5 file (create, write, read), the CSV of `squeal classify`
//! and `squeal info` all loop over it; adding a figure of merit is one entry here plus the
//! field.

use serde::Serialize;
use squeal_core::{Outcome, Regime};

use crate::column::{Kind, Num, Twin};
use crate::si::Si;

/// One classified cell: the label and the diagnostics stored beside it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Cell {
    /// [`squeal_core::Regime`] value.
    pub regime: u8,
    /// [`squeal_core::Reason`] value.
    pub reason: u8,
    /// Time at the decision.
    pub t_decision: f64,
    /// Last section amplitude (NaN if the run never crossed the section).
    pub amplitude: f64,
    /// Angular frequency of the last revolution (NaN if unknown).
    pub omega: f64,
    /// 1 if the quasi-static branch was entered.
    pub quasi_static: u8,
    /// Friction-law evaluations.
    pub evaluations: u64,
    /// Bisection fallbacks plus bracket expansions (robust solver).
    pub fallbacks: u32,
    /// Solves with several roots.
    pub multi_root: u32,
    /// Paper iterations that hit the cap, plus robust failures and discontinuities.
    pub unconverged: u32,
    /// Largest residual of any solve.
    pub max_residual: f64,
    /// [`Audit`] value: how the run-to-settlement rule labels this cell, if audited.
    pub audit: u8,
    /// Time on stick-slip before the run settled ([`squeal_core::classify::t_squeal`]):
    /// infinite for stick-slip, [`squeal_core::T_SQUEAL_UNKNOWN`] where not known.
    pub t_squeal: f64,
    /// Whether the lasting oscillation reached sticks ([`YES_NO_FLAGS`]: 255 where none was
    /// identified).
    pub sticks: u8,
    /// Whether it reverses its slip, overtaking the belt (`x' > lambda`).
    pub reverses: u8,
    /// Half the range of `x` over its window (NaN where none was identified).
    pub x_amplitude: f64,
    /// Half the range of `x'` over its window.
    pub v_amplitude: f64,
}

impl Cell {
    /// The label as an enum (`None` for a value no build writes).
    pub fn regime(&self) -> Option<Regime> {
        Regime::from_u8(self.regime)
    }

    /// The cell with every column at its fill value (what a file holds where nothing was
    /// computed).
    pub fn fill() -> Cell {
        let mut c = Cell {
            regime: 0,
            reason: 0,
            t_decision: 0.0,
            amplitude: 0.0,
            omega: 0.0,
            quasi_static: 0,
            evaluations: 0,
            fallbacks: 0,
            multi_root: 0,
            unconverged: 0,
            max_residual: 0.0,
            audit: 0,
            t_squeal: 0.0,
            sticks: 0,
            reverses: 0,
            x_amplitude: 0.0,
            v_amplitude: 0.0,
        };
        for col in COLUMNS {
            (col.set)(&mut c, col.fill);
        }
        c
    }
}

impl From<&Outcome> for Cell {
    fn from(o: &Outcome) -> Cell {
        let s = &o.stats;
        let sat = |x: u64| x.min(u32::MAX as u64) as u32;
        Cell {
            regime: o.regime as u8,
            reason: o.reason as u8,
            t_decision: o.t_decision,
            amplitude: o.amplitude,
            omega: o.omega,
            quasi_static: o.quasi_static as u8,
            evaluations: s.evaluations,
            fallbacks: sat(s.bisections + s.expansions),
            multi_root: sat(s.multi_root),
            unconverged: sat(s.unconverged + s.failures + s.discontinuities),
            max_residual: o.max_residual,
            audit: Audit::NotAudited as u8,
            t_squeal: o.t_squeal,
            sticks: o.lasting.map_or(NOT_IDENTIFIED, |l| u8::from(l.stuck)),
            reverses: o.lasting.map_or(NOT_IDENTIFIED, |l| u8::from(l.reversed)),
            x_amplitude: o.lasting.map_or(f64::NAN, |l| half(l.x_range)),
            v_amplitude: o.lasting.map_or(f64::NAN, |l| half(l.v_range)),
        }
    }
}

/// The run-to-settlement audit of an early-stopped cell (`early_stop = "cycle"`): a
/// deterministic sample of cells is also run with the classifier without the trap.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[repr(u8)]
pub enum Audit {
    /// Not in the audited sample.
    NotAudited = 0,
    /// The run to settlement gives the same label.
    Agrees = 1,
    /// The run to settlement gives the other decided label.
    Disagrees = 2,
    /// The run to settlement did not decide by `t_max`.
    Undecided = 3,
}

impl Audit {
    /// All values, in value order.
    pub const ALL: [Audit; 4] = [
        Audit::NotAudited,
        Audit::Agrees,
        Audit::Disagrees,
        Audit::Undecided,
    ];

    /// The name in files and output.
    pub fn name(self) -> &'static str {
        match self {
            Audit::NotAudited => "not_audited",
            Audit::Agrees => "agrees",
            Audit::Disagrees => "disagrees",
            Audit::Undecided => "undecided",
        }
    }

    /// From the stored value.
    pub fn from_u8(v: u8) -> Option<Audit> {
        Audit::ALL.into_iter().find(|a| *a as u8 == v)
    }
}

/// One stored per-cell quantity.
pub type Column = crate::column::Column<Cell>;

/// Value of the `regime` (labels) fill: not computed.
pub const NOT_COMPUTED: u8 = 255;

/// Members of the stored `labels` enum: [`Regime`] plus `not_computed`.
pub const REGIME_FLAGS: &[(u8, &str)] = &[
    (0, "undecided"),
    (1, "steady_slip"),
    (2, "stick_slip"),
    (3, "slip_oscillation"),
    (NOT_COMPUTED, "not_computed"),
];

/// Members of the stored `reason` enum: [`squeal_core::Reason`] plus `not_computed`.
pub const REASON_FLAGS: &[(u8, &str)] = &[
    (0, "time_limit"),
    (1, "near_fixed_point"),
    (2, "inside_cycle"),
    (3, "outside_cycle"),
    (4, "settled_stick_slip"),
    (5, "diverged"),
    (6, "solver_failure"),
    (7, "sticking_band"),
    (8, "start_inside_cycle"),
    (9, "start_outside_cycle"),
    (10, "stick_cycle"),
    (11, "entered_region"),
    (12, "start_in_region"),
    (13, "stuck_onto_cycle"),
    (14, "stuck_then_settles"),
    (15, "below_settling_start"),
    (16, "between_sticking_starts"),
    (17, "below_decaying_section"),
    (18, "start_inside_decaying_turn"),
    (19, "entered_decaying_turn"),
    (20, "lasting_oscillation"),
    (21, "slip_oscillation"),
    (22, "in_trapped_band"),
    (23, "on_certified_orbit"),
    (NOT_COMPUTED, "not_computed"),
];

/// Value of the attractor's yes/no columns where no lasting oscillation was identified.
pub const NOT_IDENTIFIED: u8 = 255;

/// Members of the stored `sticks` and `reverses` enums.
pub const YES_NO_FLAGS: &[(u8, &str)] =
    &[(0, "no"), (1, "yes"), (NOT_IDENTIFIED, "not_identified")];

/// Half the width of a range.
fn half(r: [f64; 2]) -> f64 {
    0.5 * (r[1] - r[0])
}

/// Members of the stored `audit` enum: [`Audit`] (its fill is `not_audited`).
pub const AUDIT_FLAGS: &[(u8, &str)] = &[
    (0, "not_audited"),
    (1, "agrees"),
    (2, "disagrees"),
    (3, "undecided"),
];

macro_rules! col {
    ($name:ident, $long:expr, $units:expr, $kind:ident, $flags:expr, $fill:expr, u) => {
        Column {
            name: stringify!($name),
            long_name: $long,
            units: $units,
            kind: Kind::$kind,
            flags: $flags,
            fill: Num::U($fill),
            get: |c| Num::U(c.$name as u64),
            set: |c, v| c.$name = v.as_u64() as _,
            si: Twin::None,
        }
    };
    ($name:ident, $long:expr, $units:expr, F64, f) => {
        col!($name, $long, $units, F64, f, Twin::None)
    };
    ($name:ident, $long:expr, $units:expr, F64, f, $si:expr) => {
        Column {
            name: stringify!($name),
            long_name: $long,
            units: $units,
            kind: Kind::F64,
            flags: &[],
            fill: Num::F(f64::NAN),
            get: |c| Num::F(c.$name),
            set: |c, v| c.$name = v.as_f64(),
            si: $si,
        }
    };
}

/// The per-cell columns, in storage order. `labels` is the dataset of the `regime` field.
pub const COLUMNS: &[Column] = &[
    Column {
        name: "labels",
        long_name: "attractor reached",
        units: "",
        kind: Kind::Enum,
        flags: REGIME_FLAGS,
        fill: Num::U(NOT_COMPUTED as u64),
        get: |c| Num::U(c.regime as u64),
        set: |c, v| c.regime = v.as_u64() as u8,
        si: Twin::None,
    },
    col!(
        reason,
        "why the run stopped",
        "",
        Enum,
        REASON_FLAGS,
        NOT_COMPUTED as u64,
        u
    ),
    col!(
        t_decision,
        "time at the decision (nondimensional time, natural period 2 pi)",
        "1",
        F64,
        f,
        Twin::Named(Si::Time, "time at the decision (seconds)")
    ),
    col!(
        amplitude,
        "last section amplitude: x' at the last crossing of x = x*",
        "1",
        F64,
        f,
        Twin::Named(
            Si::Velocity,
            "last section amplitude: x' at the last crossing of x = x* (m/s)"
        )
    ),
    col!(
        omega,
        "angular frequency of the last revolution (natural frequency 1)",
        "1",
        F64,
        f,
        Twin::Named(Si::Frequency, "frequency of the last revolution (Hz)")
    ),
    col!(
        quasi_static,
        "1 if the quasi-static branch of the law was entered",
        "1",
        U8,
        &[],
        0,
        u
    ),
    col!(evaluations, "friction-law evaluations", "1", U64, &[], 0, u),
    col!(
        fallbacks,
        "bisection steps and bracket expansions of the robust solver",
        "1",
        U32,
        &[],
        0,
        u
    ),
    col!(
        multi_root,
        "force solves with several roots",
        "1",
        U32,
        &[],
        0,
        u
    ),
    col!(
        unconverged,
        "unconverged or failed force solves",
        "1",
        U32,
        &[],
        0,
        u
    ),
    col!(
        max_residual,
        "largest residual |G(F)| of any force solve",
        "1",
        F64,
        f
    ),
    col!(
        audit,
        "label of the same run taken to settlement (sampled cells of early-stopped scans)",
        "",
        Enum,
        AUDIT_FLAGS,
        0,
        u
    ),
    col!(
        t_squeal,
        "time on stick-slip before the run settled: end of its last stuck step (nondimensional \
         time, natural period 2 pi; seconds: times the file's time_unit); 0 never stuck, inf \
         stick-slip for good, -1 not known (undecided, or stopped before its last stick)",
        "1",
        F64,
        f,
        Twin::Named(
            Si::Time,
            "time on stick-slip before the run settled: end of its last stuck step (seconds); 0 \
             never stuck, inf stick-slip for good, -1 not known (undecided, or stopped before \
             its last stick)"
        )
    ),
    col!(
        sticks,
        "whether the lasting oscillation the run reached sticks (x' = lambda for a while)",
        "",
        Enum,
        YES_NO_FLAGS,
        NOT_IDENTIFIED as u64,
        u
    ),
    col!(
        reverses,
        "whether the lasting oscillation the run reached overtakes the belt (x' > lambda)",
        "",
        Enum,
        YES_NO_FLAGS,
        NOT_IDENTIFIED as u64,
        u
    ),
    col!(
        x_amplitude,
        "half the range of x over the lasting oscillation the run reached (nondimensional; \
         metres: times the file's length_unit); NaN where none was identified",
        "1",
        F64,
        f,
        Twin::Named(
            Si::Length,
            "half the range of x over the lasting oscillation the run reached (metres); NaN \
             where none was identified"
        )
    ),
    col!(
        v_amplitude,
        "half the range of x' over the lasting oscillation the run reached (nondimensional; \
         m/s: times the file's velocity_unit); NaN where none was identified",
        "1",
        F64,
        f,
        Twin::Named(
            Si::Velocity,
            "half the range of x' over the lasting oscillation the run reached (m/s); NaN \
             where none was identified"
        )
    ),
];

/// Bytes of one cell in the journal.
pub fn cell_bytes() -> usize {
    COLUMNS.iter().map(|c| c.kind.bytes()).sum()
}

/// The column called `name`.
pub fn column(name: &str) -> Option<&'static Column> {
    COLUMNS.iter().find(|c| c.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use squeal_core::Reason;

    #[test]
    fn enum_tables_match_the_core_enums() {
        for r in Regime::ALL {
            assert!(REGIME_FLAGS.contains(&(r as u8, r.name())), "{r:?}");
        }
        for r in Reason::ALL {
            assert!(REASON_FLAGS.contains(&(r as u8, r.name())), "{r:?}");
        }
        for a in Audit::ALL {
            assert!(AUDIT_FLAGS.contains(&(a as u8, a.name())), "{a:?}");
        }
        assert_eq!(REGIME_FLAGS.len(), Regime::ALL.len() + 1);
        assert_eq!(REASON_FLAGS.len(), Reason::ALL.len() + 1);
        assert_eq!(AUDIT_FLAGS.len(), Audit::ALL.len());
    }

    #[test]
    fn every_column_round_trips_through_get_and_set() {
        let mut names: Vec<&str> = COLUMNS.iter().map(|c| c.name).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), COLUMNS.len(), "duplicate column names");
        let mut a = Cell::fill();
        assert_eq!(a.regime, NOT_COMPUTED);
        assert!(a.t_decision.is_nan());
        for (i, col) in COLUMNS.iter().enumerate() {
            let v = match col.kind {
                Kind::F64 => Num::F(i as f64 + 0.5),
                _ => Num::U(i as u64 + 1),
            };
            (col.set)(&mut a, v);
            assert_eq!((col.get)(&a), v, "{}", col.name);
        }
        assert_eq!(column("labels").unwrap().text(&a), "steady_slip");
    }
}
