//! What a run's label says: the regime it ends in and the reason it was decided, both stored
//! in files as HDF5 enums, and the certified fates of stretches of the section
//! ([`crate::witness`]) that decide runs crossing them.

use serde::{Deserialize, Serialize};

/// The attractor a run settles on. The values are stored in files (HDF5 enum `regime`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
pub enum Regime {
    /// Not settled by `t_max` (or blew up, or the solver failed): never guessed.
    Undecided = 0,
    /// The steady-slip fixed point.
    SteadySlip = 1,
    /// The self-excited stick-slip oscillation ("squeal").
    StickSlip = 2,
    /// A lasting oscillation that never sticks, about a steady slip that does not attract
    /// ([`crate::SteadySlip`]): small, not the squeal (MODEL.md section 5).
    SlipOscillation = 3,
}

impl Regime {
    /// All labels, in value order.
    pub const ALL: [Regime; 4] = [
        Regime::Undecided,
        Regime::SteadySlip,
        Regime::StickSlip,
        Regime::SlipOscillation,
    ];

    /// The label's name in files and output.
    pub fn name(self) -> &'static str {
        match self {
            Regime::Undecided => "undecided",
            Regime::SteadySlip => "steady_slip",
            Regime::StickSlip => "stick_slip",
            Regime::SlipOscillation => "slip_oscillation",
        }
    }

    /// From the stored value.
    pub fn from_u8(v: u8) -> Option<Regime> {
        Regime::ALL.into_iter().find(|r| *r as u8 == v)
    }
}

/// Why the classifier stopped. Stored in files (HDF5 enum `reason`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[repr(u8)]
pub enum Reason {
    /// `t_max` reached without a decision.
    TimeLimit = 0,
    /// Within `fp_radius` of the fixed point.
    NearFixedPoint = 1,
    /// Crossed the section inside the known unstable cycle.
    InsideCycle = 2,
    /// Crossed the section outside the known unstable cycle.
    OutsideCycle = 3,
    /// Section amplitudes settled in the stick-slip band.
    SettledStickSlip = 4,
    /// The state left `|x|, |x'| <= max_radius`.
    Diverged = 5,
    /// The robust solver found no root (counted in the statistics).
    SolverFailure = 6,
    /// Every revolution of the window stuck and the section amplitudes fluctuate without
    /// trend in a bounded band: the (wide, irregular) stick-slip attractor.
    StickingBand = 7,
    /// The start lies inside the located unstable cycle, farther from it than the margin:
    /// steady slip without a run (same planar argument as [`Reason::InsideCycle`]).
    StartInsideCycle = 8,
    /// The start lies outside the located unstable cycle, farther from it than the margin:
    /// stick-slip without a run (same argument as [`Reason::OutsideCycle`]).
    StartOutsideCycle = 9,
    /// A law with true stick: the block stuck again after a breakaway. Every breakaway starts
    /// from the same state, so the orbit from it is the stick-slip cycle and the run is on it.
    StickCycle = 10,
    /// The run entered the certified region of attraction of the fixed point
    /// ([`crate::Region`]): steady slip (MODEL.md section 9).
    EnteredRegion = 11,
    /// The start lies inside the certified region of attraction: steady slip without a run.
    StartInRegion = 12,
    /// A law with true stick: the block stuck, so it breaks away from the one breakaway
    /// state, whose orbit sticks again (the map's landscape): the stick-slip cycle.
    StuckOntoCycle = 13,
    /// A law with true stick: the block stuck, so it breaks away from the one breakaway
    /// state, whose orbit decays to the fixed point without sticking (the landscape).
    StuckThenSettles = 14,
    /// A law of the slip velocity only: the run crossed the section at or below a start whose
    /// run reached the certified region; the return map is monotone, so it settles too
    /// ([`crate::witness`], MODEL.md section 9).
    BelowSettlingStart = 15,
    /// A law of the slip velocity only: the run crossed the section between two starts whose
    /// runs stuck onto the stick-slip cycle; the return map is monotone, so it does too.
    BetweenStickingStarts = 16,
    /// No unstable cycle was found on the section: every sampled amplitude up to the
    /// search's top returns lower, so a run crossing below that top (less the trap's margin)
    /// goes on down to the fixed point ([`Shortcuts::decay_below`], MODEL.md section 9).
    BelowDecayingSection = 17,
    /// No unstable cycle was found on the section and the start lies inside a decaying turn
    /// (from the section or its lower half, below its top), farther from it than the margin:
    /// steady slip without a run (same argument as [`Reason::BelowDecayingSection`], with the
    /// planar one of [`Reason::StartInsideCycle`]).
    StartInsideDecayingTurn = 18,
    /// No unstable cycle was found on the section and the run crossed the section's lower
    /// half (`x = x*, x' < 0`) inside a decaying turn that starts there: it cannot leave the
    /// turn, and its next crossing of the section lies below the decaying section's top
    /// ([`Shortcuts::decay_lower_below`], MODEL.md section 9). Half a revolution before
    /// [`Reason::BelowDecayingSection`] could decide it.
    EnteredDecayingTurn = 19,
    /// The last `settle_cycles` turns of the run (from one maximum of `x` to the next) stay
    /// in a band without trend and none of them crossed the section `x = x*, x' > 0`: a
    /// lasting oscillation the section's rules cannot see ([`crate::turns`], MODEL.md
    /// section 10), stick-slip. Decided only there, so it never changes a label the section
    /// decides.
    LastingOscillation = 20,
    /// Steady slip does not attract ([`crate::SteadySlip`]) and the last `settle_cycles`
    /// turns of the run (or section crossings) stay in a band without trend, none of them
    /// stuck or reversed the slip: the small slip oscillation about it
    /// ([`Regime::SlipOscillation`]).
    SlipOscillation = 21,
    /// The run crossed the section, with one root of the force there, inside the stick-slip
    /// band's interval that the return map maps into itself with a margin (the band is
    /// trapped, MODEL.md section 6 "Stick-slip means it stays"): it never leaves it, so it
    /// squeals for good. A certificate of the attractor, used by the runs that check the
    /// rules (the census, the audit).
    InTrappedBand = 22,
    /// The run's maxima of `x` settled on an attractor of its turn map that the orbit
    /// certificate holds at `dt` and `dt / 2` (an attracting periodic orbit, or a band of
    /// maxima mapped into itself: [`crate::orbit`], MODEL.md section 10): it lasts for good.
    /// Used by the runs that check the rules (the census, the audit).
    OnCertifiedOrbit = 23,
}

impl Reason {
    /// All reasons, in value order.
    pub const ALL: [Reason; 24] = [
        Reason::TimeLimit,
        Reason::NearFixedPoint,
        Reason::InsideCycle,
        Reason::OutsideCycle,
        Reason::SettledStickSlip,
        Reason::Diverged,
        Reason::SolverFailure,
        Reason::StickingBand,
        Reason::StartInsideCycle,
        Reason::StartOutsideCycle,
        Reason::StickCycle,
        Reason::EnteredRegion,
        Reason::StartInRegion,
        Reason::StuckOntoCycle,
        Reason::StuckThenSettles,
        Reason::BelowSettlingStart,
        Reason::BetweenStickingStarts,
        Reason::BelowDecayingSection,
        Reason::StartInsideDecayingTurn,
        Reason::EnteredDecayingTurn,
        Reason::LastingOscillation,
        Reason::SlipOscillation,
        Reason::InTrappedBand,
        Reason::OnCertifiedOrbit,
    ];

    /// The reason's name in files and output.
    pub fn name(self) -> &'static str {
        match self {
            Reason::TimeLimit => "time_limit",
            Reason::NearFixedPoint => "near_fixed_point",
            Reason::InsideCycle => "inside_cycle",
            Reason::OutsideCycle => "outside_cycle",
            Reason::SettledStickSlip => "settled_stick_slip",
            Reason::Diverged => "diverged",
            Reason::SolverFailure => "solver_failure",
            Reason::StickingBand => "sticking_band",
            Reason::StartInsideCycle => "start_inside_cycle",
            Reason::StartOutsideCycle => "start_outside_cycle",
            Reason::StickCycle => "stick_cycle",
            Reason::EnteredRegion => "entered_region",
            Reason::StartInRegion => "start_in_region",
            Reason::StuckOntoCycle => "stuck_onto_cycle",
            Reason::StuckThenSettles => "stuck_then_settles",
            Reason::BelowSettlingStart => "below_settling_start",
            Reason::BetweenStickingStarts => "between_sticking_starts",
            Reason::BelowDecayingSection => "below_decaying_section",
            Reason::StartInsideDecayingTurn => "start_inside_decaying_turn",
            Reason::EnteredDecayingTurn => "entered_decaying_turn",
            Reason::LastingOscillation => "lasting_oscillation",
            Reason::SlipOscillation => "slip_oscillation",
            Reason::InTrappedBand => "in_trapped_band",
            Reason::OnCertifiedOrbit => "on_certified_orbit",
        }
    }
}

/// The certified fates of stretches of the section `x = x*, x' > 0` ([`crate::witness`]'s
/// argument).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SectionFates {
    /// Every crossing at or below this amplitude ends in steady slip.
    pub settles_up_to: Option<f64>,
    /// Every crossing in this closed interval of amplitudes ends on the stick-slip cycle.
    pub sticks_within: Option<(f64, f64)>,
}

impl SectionFates {
    /// The decision for a run crossing the section at amplitude `r`, if certified.
    #[inline]
    pub fn decide(&self, r: f64) -> Option<(Regime, Reason)> {
        if self.settles_up_to.is_some_and(|s| r <= s) {
            return Some((Regime::SteadySlip, Reason::BelowSettlingStart));
        }
        if self
            .sticks_within
            .is_some_and(|(lo, hi)| lo <= r && r <= hi)
        {
            return Some((Regime::StickSlip, Reason::BetweenStickingStarts));
        }
        None
    }

    /// Whether any stretch is certified.
    pub fn any(&self) -> bool {
        self.settles_up_to.is_some() || self.sticks_within.is_some()
    }
}
