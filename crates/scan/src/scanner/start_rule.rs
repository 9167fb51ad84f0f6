//! The start rule: starts labelled without a run by the side of a closed curve they lie on
//! (the located unstable cycle, or a decaying turn), with its margin.

use squeal_core::classify::Half;
use squeal_core::{Reason, Regime, Shortcuts, SolverStats, State, Stepper};

use crate::curve::{ClosedCurve, CurveLocator};
use crate::ulc::{self, CycleSettings};

/// Early stopping at the start: a start farther than `margin` from the located unstable
/// cycle is labelled by the side of the cycle it lies on, without a run.
///
/// This is the argument of the classifier's trap ([`Reason::InsideCycle`],
/// [`Reason::OutsideCycle`]) applied to the whole closed curve instead of its crossing of
/// the section: the flow near the cycle is planar, so a trajectory cannot cross it; inside
/// it the runs settle on the fixed point, outside it on stick-slip. It rests on the same
/// assumption (one unstable cycle, found as the first sign change of the sampled return
/// map), and the same audit checks it: audited cells are also run to settlement.
///
/// Where no unstable cycle was found and the whole sampled section decays
/// ([`Shortcuts::decay_below`]), the curves are decaying turns ([`decaying_turn`]): one
/// revolution from a half of the line `x = x*`, closed by the piece of that half between
/// its start and its return ([`StartRule::decaying`]). A start inside one cannot leave it
/// (MODEL.md section 9), and its next crossing of the section lies below the top, where the
/// return map decays: steady slip ([`Reason::StartInsideDecayingTurn`]).
///
/// The margin is the trap's band at the section, `trap_margin r_u`, plus a bound on how far
/// the polygon of one revolution's steps strays from the smooth curve between its points:
/// for each segment, its length times the larger turning angle at its ends (for a circle
/// of `N` points this is 8 times the true sagitta `L theta / 8`). The closing piece of a
/// decaying turn lies on the section itself, so it and its corners add nothing. Starts
/// within the margin are run as before.
#[derive(Clone, Debug)]
pub struct StartRule {
    pub(super) curve: CurveLocator,
    pub(super) margin: f64,
    /// A second curve, with its margin, whose inside is decided too (the lower decaying
    /// turn).
    pub(super) also: Option<(CurveLocator, f64)>,
    pub(super) centre: State,
    /// The reason for a start inside the curve.
    pub(super) inside: Reason,
    /// Whether starts outside the cycle are decided (off where the return map jumps past
    /// the cycle: [`crate::section::escape_above`], and for a decaying turn).
    pub(super) outside: bool,
}

impl StartRule {
    /// The rule for `curve` around the fixed point `centre` with the trap's relative margin
    /// at the section crossing `r_section`.
    pub fn new(
        curve: ClosedCurve,
        centre: State,
        r_section: f64,
        trap_margin: f64,
        outside: bool,
    ) -> StartRule {
        let n = curve.len();
        let margin = trap_margin * r_section + polygon_sag(&curve, 0..n, |_| true);
        StartRule {
            margin,
            curve: CurveLocator::new(curve),
            also: None,
            centre,
            inside: Reason::StartInsideCycle,
            outside,
        }
    }

    /// The rule for a decaying section: the decaying turns `upper` and `lower`
    /// ([`decaying_turn`]), each with the margin `trap_margin r` plus the polygon's sag
    /// (without the closing piece, which lies on the line `x = x*`); only starts inside are
    /// decided. `None` without either turn.
    pub fn decaying(
        centre: State,
        upper: Option<(f64, ClosedCurve)>,
        lower: Option<(f64, ClosedCurve)>,
        trap_margin: f64,
    ) -> Option<StartRule> {
        let with_margin = |(r, curve): (f64, ClosedCurve)| {
            let n = curve.len();
            // Segments 0..n-1 are steps of the orbit; the closing one lies on the line
            // `x = x*`, and its two corners are not turns of the orbit.
            let sag = polygon_sag(&curve, 0..n - 1, |i| i > 0 && i < n - 1);
            (CurveLocator::new(curve), trap_margin * r + sag)
        };
        let (mut upper, mut lower) = (upper.map(with_margin), lower.map(with_margin));
        let (curve, margin) = upper.take().or_else(|| lower.take())?;
        Some(StartRule {
            curve,
            margin,
            also: lower,
            centre,
            inside: Reason::StartInsideDecayingTurn,
            outside: false,
        })
    }

    /// The margin: starts closer than this to the curve are run.
    pub fn margin(&self) -> f64 {
        self.margin
    }

    /// The closed curve whose sides the rule decides (the located cycle, or the upper
    /// decaying turn).
    pub fn curve(&self) -> &ClosedCurve {
        self.curve.curve()
    }

    /// The label of start `p`, if it lies farther than the margin from the curve.
    pub fn decide(&self, p: State) -> Option<(Regime, Reason)> {
        let inside = (Regime::SteadySlip, self.inside);
        match self.curve.side(p, self.margin) {
            Some(true) => return Some(inside),
            Some(false) if self.outside => {
                return Some((Regime::StickSlip, Reason::StartOutsideCycle));
            }
            _ => {}
        }
        let (also, margin) = self.also.as_ref()?;
        also.side(p, *margin)?.then_some(inside)
    }
}

/// A decaying turn below `top` (a map with [`Shortcuts::decay_below`] = `top`): the first
/// revolution from amplitude `r` on `half`, for the highest `r` of `from, 0.85 from,
/// 0.85^2 from, ...` (16 tries), whose states all have one root on the slip branch
/// ([`ulc::Turn::slip_only`]: where the force's branch is history two orbits can pass each
/// other and the argument fails), that returns lower (else the flow would leave through the
/// closing piece instead of entering) and that stays at or below `top` (so its crossing of the
/// section decays, and so does every crossing inside it); with that `r`. `None` if no try
/// qualifies.
pub fn decaying_turn(
    st: &Stepper,
    half: Half,
    from: f64,
    top: f64,
    t_return: f64,
) -> Option<(f64, ClosedCurve)> {
    std::iter::successors(Some(from), |r| Some(0.85 * r))
        .take(16)
        .find_map(|r| {
            let t = ulc::turn(st, half, r, t_return, &mut SolverStats::default())?;
            let below = t.curve.v_range()[1] <= top;
            (t.slip_only && t.returns_to < r && below).then_some((r, t.curve))
        })
}

/// The start rule of a map whose section decays below `top`, with `shortcuts`'s threshold
/// for the lower half set: the turn from the section's own top, and one from its lower
/// half, which may start far lower than `-top` where the orbit from there stays below it
/// (MODEL.md section 9, "A decaying section").
pub(super) fn decaying_turns(
    stepper: &Stepper,
    cs: &CycleSettings,
    trap_margin: f64,
    top: f64,
    shortcuts: &mut Shortcuts,
) -> Option<StartRule> {
    let upper = decaying_turn(stepper, Half::Upper, top, top, cs.t_return);
    let lower = decaying_turn(stepper, Half::Lower, cs.r_max, top, cs.t_return);
    shortcuts.decay_lower_below = lower.as_ref().map(|(s, _)| s * (1.0 - trap_margin));
    let fp = stepper.params().fixed_point();
    StartRule::decaying(fp, upper, lower, trap_margin)
}

/// The largest of `segment length x larger turning angle at its ends` over the segments
/// `segs` of the closed polygon `curve`, counting the turn at vertex `i` only where
/// `is_turn(i)`.
fn polygon_sag(
    curve: &ClosedCurve,
    segs: std::ops::Range<usize>,
    is_turn: impl Fn(usize) -> bool,
) -> f64 {
    let n = curve.len();
    let seg = |i: usize| {
        let j = (i + 1) % n;
        (curve.x[j] - curve.x[i], curve.v[j] - curve.v[i])
    };
    // Turning angle at vertex i, between segments i - 1 and i.
    let turn = |i: usize| {
        if !is_turn(i) {
            return 0.0;
        }
        let (a, b) = (seg((i + n - 1) % n), seg(i));
        (a.0 * b.1 - a.1 * b.0).atan2(a.0 * b.0 + a.1 * b.1).abs()
    };
    segs.map(|i| {
        let (dx, dv) = seg(i);
        dx.hypot(dv) * turn(i).max(turn((i + 1) % n))
    })
    .fold(0.0f64, f64::max)
}
