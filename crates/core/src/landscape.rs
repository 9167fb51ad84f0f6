//! What is known about the attractors of a law with true stick before any basin is mapped:
//! the stick-slip cycle, found from its one entry (the breakaway state, [`crate::stick`]),
//! and the fixed point's linear stability, combined into a [`Landscape`].

use serde::Serialize;

use crate::stepper::{State, Stepper};

/// Whether the stick-slip cycle exists, found from its one possible entry: every stick phase
/// ends at the breakaway state `(mu_s - 2 nu lambda, lambda)`, so the cycle exists exactly
/// when the orbit from there sticks again.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum StickCycle {
    /// The orbit from breakaway sticks again after `period`: the stick-slip cycle, with
    /// the time it spends stuck per period.
    Exists {
        /// Period of the cycle (breakaway to breakaway).
        period: f64,
        /// Time stuck per period.
        stuck: f64,
    },
    /// The orbit from breakaway reaches the fixed point's `fp_radius` without sticking: no
    /// stick-slip cycle.
    Absent,
    /// Neither by `t_max`.
    Undecided,
}

/// The stick-slip cycle of a law with true stick (`None` for other laws): from the breakaway
/// state, run until the block sticks again and breaks away again (the period), or comes
/// within `fp_radius` of the fixed point.
pub fn stick_slip_cycle(stepper: &Stepper, t_max: f64, fp_radius: f64) -> Option<StickCycle> {
    let p = stepper.params();
    let mu_s = stepper.law().static_limit()?;
    if !p.law.family().has_landscape() {
        return None;
    }
    let fp = p.fixed_point();
    let ic = State {
        x: mu_s - 2.0 * p.nu * p.lambda,
        v: p.lambda,
    };
    let mut run = crate::Run::new(stepper, ic);
    let (mut first_break, mut onset) = (f64::NAN, f64::NAN);
    for _ in 0..run.steps_to(t_max) {
        let st = run.step();
        let e = st.events;
        if e.breakaways > 0 {
            let tb = st.prev.t + e.breakaway_at;
            if first_break.is_nan() {
                first_break = tb;
            } else if onset.is_finite() {
                return Some(StickCycle::Exists {
                    period: tb - first_break,
                    stuck: tb - onset,
                });
            }
        }
        if e.onsets > 0 && first_break.is_finite() && onset.is_nan() {
            onset = st.prev.t + e.onset_at;
        }
        let n = st.next;
        if onset.is_nan() && (n.x - fp.x).hypot(n.v - fp.v) < fp_radius {
            return Some(StickCycle::Absent);
        }
        if run.failed() || !n.x.is_finite() {
            break;
        }
    }
    Some(StickCycle::Undecided)
}

/// What is known about the attractors of a law with true stick before any basin is mapped.
/// The values are stable: files store them (`landscape`, an HDF5 enum).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[repr(u8)]
pub enum Landscape {
    /// The fixed point repels (`2 xi + mu'(v_d) < 0`): every start ends in stick-slip (no
    /// other attractor is known for this law; runs are still labelled one by one).
    StickSlipOnly = 1,
    /// A stable fixed point and a stick-slip cycle: the basins are mapped.
    Bistable = 2,
    /// A stable fixed point and no stick-slip cycle (the orbit from breakaway decays to the
    /// fixed point): every start ends in steady slip (assuming no slip-only cycle).
    SteadySlipOnly = 3,
    /// The orbit from breakaway decided nothing by the time limit.
    Unknown = 0,
}

impl Landscape {
    /// Every landscape, by stored value.
    pub const ALL: [Landscape; 4] = [
        Landscape::Unknown,
        Landscape::StickSlipOnly,
        Landscape::Bistable,
        Landscape::SteadySlipOnly,
    ];

    /// The landscape of a stored value.
    pub fn from_u8(v: u8) -> Option<Landscape> {
        Landscape::ALL.into_iter().find(|l| *l as u8 == v)
    }

    /// The regime every start must end in, where the landscape states one.
    pub fn only_regime(self) -> Option<crate::Regime> {
        match self {
            Landscape::StickSlipOnly => Some(crate::Regime::StickSlip),
            Landscape::SteadySlipOnly => Some(crate::Regime::SteadySlip),
            Landscape::Bistable | Landscape::Unknown => None,
        }
    }

    /// The name in files and output.
    pub fn name(self) -> &'static str {
        match self {
            Landscape::StickSlipOnly => "stick_slip_only",
            Landscape::Bistable => "bistable",
            Landscape::SteadySlipOnly => "steady_slip_only",
            Landscape::Unknown => "unknown",
        }
    }

    /// A sentence for summaries.
    pub fn note(self) -> &'static str {
        match self {
            Landscape::StickSlipOnly => {
                "the fixed point repels (2 xi + mu'(v_d) < 0): every start ends in stick-slip"
            }
            Landscape::Bistable => {
                "stable fixed point and a stick-slip cycle (the orbit from breakaway sticks \
                 again): bistable"
            }
            Landscape::SteadySlipOnly => {
                "stable fixed point and no stick-slip cycle (the orbit from breakaway decays \
                 to the fixed point without sticking): every start ends in steady slip"
            }
            Landscape::Unknown => "the orbit from breakaway decided nothing by t_max",
        }
    }
}

/// A landscape with the evidence it rests on.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LandscapeEvidence {
    /// The verdict.
    pub landscape: Landscape,
    /// The fixed point's effective damping `2 xi + mu'(v_d)` (negative: it repels).
    pub damping: f64,
    /// What the orbit from the breakaway state did.
    pub cycle: StickCycle,
}

/// The landscape of a law with true stick with its evidence (`None` for other laws): the
/// fixed point's linear stability and whether the stick-slip cycle exists, the orbit from
/// breakaway run to `t_max` or to within `fp_radius` of the fixed point.
pub fn landscape_evidence(
    stepper: &Stepper,
    t_max: f64,
    fp_radius: f64,
) -> Option<LandscapeEvidence> {
    let damping = stepper.params().fixed_point_damping()?;
    let cycle = stick_slip_cycle(stepper, t_max, fp_radius)?;
    let landscape = if damping < 0.0 {
        Landscape::StickSlipOnly
    } else {
        match cycle {
            StickCycle::Exists { .. } => Landscape::Bistable,
            StickCycle::Absent => Landscape::SteadySlipOnly,
            StickCycle::Undecided => Landscape::Unknown,
        }
    };
    Some(LandscapeEvidence {
        landscape,
        damping,
        cycle,
    })
}

/// The landscape of a law with true stick (`None` for other laws): the fixed point's
/// linear stability and whether the stick-slip cycle exists.
pub fn landscape(stepper: &Stepper, t_max: f64, fp_radius: f64) -> Option<Landscape> {
    landscape_evidence(stepper, t_max, fp_radius).map(|e| e.landscape)
}
