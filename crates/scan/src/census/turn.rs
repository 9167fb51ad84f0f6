//! A closed turn: one revolution of a run from the section `S = {x = x*, x' > 0}` back to it,
//! with the piece of `S` between its two crossings, a closed curve that no run crosses
//! (crates/core/MODEL.md section 12, "Closed turns").
//!
//! **The argument.** Let a revolution leave `S` at amplitude `r0` and return at `r1`, and let
//! every state along it have exactly one root of the force equation
//! ([`squeal_core::region::one_root`], a closed-form bound). Its orbit `T` and the segment
//! `[r0, r1]` of `S` bound a region `I` around the fixed point (the turn winds once about
//! it, checked). A run that starts in one of the two regions and reaches the other must
//! meet the curve:
//! * on `T`, at a state with one root, so `(x, x')` is the whole state there and the run
//!   is the turn's own orbit from then on: it stays on the curve, then leaves it where the
//!   orbit does;
//! * on the segment, where `x' > 0` moves every run to `x > x*`: the segment is crossed from
//!   its left side to its right only. For an outward turn (`r1 > r0`) the left side is `I`:
//!   no run enters `I` from outside, so the outside of the curve is invariant. For an
//!   inward turn (`r1 < r0`) the left side is the outside: `I` is invariant.
//!
//! So a start outside an outward turn never comes nearer to the fixed point than the
//! curve: it never reaches the fixed point's radius or its certified region (both checked
//! to lie inside `I`). That is the premise of the outside rules, shown for every such start
//! at the cost of one revolution. What it does not say is which oscillation the run ends
//! on: only that it is not steady slip.
//!
//! **The step.** The turn is run at `dt` and at `dt / 2` from the same state on `S`; both
//! must turn the same way by more than four times the shift of `r1` between the steps, and
//! a start counts as outside only when it keeps a distance from the polygon larger than
//! that margin and than the polygon's longest side (which bounds how far the turn's orbit
//! strays from its chords).

use squeal_core::region::{one_root, one_root_within};
use squeal_core::section::section_return;
use squeal_core::{Params, Region, SolverStats, State, Stepper};

use crate::curve::{ClosedCurve, CurveLocator};

/// The longest a turn may take, in units of the linear period `2 pi`; a revolution that
/// has not come back to the section by then gives no turn.
pub(super) const MAX_PERIODS: f64 = 8.0;

/// How many times the step's shift of `r1` the turn's growth and a start's distance from it
/// must exceed.
const STEP_MARGIN: f64 = 4.0;

/// Which side of a closed turn no run leaves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kept {
    /// An outward turn (`r1 > r0`): its outside.
    Outside,
    /// An inward turn (`r1 < r0`): its inside.
    Inside,
}

/// A closed turn whose premise held at `dt` and `dt / 2`.
#[derive(Clone, Debug)]
pub struct ClosedTurn {
    /// The polygon of the revolution at `dt`, from `(x*, r0)` to `(x*, r1)`.
    curve: CurveLocator,
    /// The amplitudes on the section where the turn leaves and returns.
    pub r0: f64,
    /// See `r0`.
    pub r1: f64,
    /// The distance a start must keep from the polygon to be on one side of it.
    pub margin: f64,
    /// The largest `x'` and `|sigma| = |x - x* + 2 nu x'|` on the polygon: their bounds over
    /// the region inside it too (both are linear in the state).
    extremes: (f64, f64),
}

impl ClosedTurn {
    /// The side no run leaves.
    pub fn kept(&self) -> Kept {
        if self.r1 > self.r0 {
            Kept::Outside
        } else {
            Kept::Inside
        }
    }

    /// Whether the force equation of `p` has one root at every state inside the turn
    /// ([`one_root_within`]): the flow is planar there.
    pub fn one_root_inside(&self, p: &Params) -> bool {
        // The orbit strays from the polygon's chords by less than the margin.
        let (v_max, sigma_max) = self.extremes;
        one_root_within(p, v_max + self.margin, sigma_max + self.margin)
    }

    /// Whether `p` lies on the kept side, farther than the margin from the turn.
    pub fn keeps(&self, p: State) -> bool {
        let inside = self.curve.side(p, self.margin);
        match self.kept() {
            Kept::Outside => inside == Some(false),
            Kept::Inside => inside == Some(true),
        }
    }

    /// The closed turn from `(x*, r)` on the section, run with `stepper` and checked with
    /// `half` (the same model at half the step); `fp_radius` and the certified `region` of
    /// the fixed point must lie inside it. `None` where any premise fails: a state without
    /// the one-root bound, no return within [`MAX_PERIODS`] periods, a turn that does not
    /// wind once about the fixed point, growth within the step's margin, or the fixed
    /// point's neighbourhood not inside.
    pub fn certify(
        (stepper, half): (&Stepper, &Stepper),
        r: f64,
        (fp_radius, region): (f64, Option<&Region>),
    ) -> Option<ClosedTurn> {
        let (x, v, r1) = revolution(stepper, r)?;
        let (_, _, r1_half) = revolution(half, r)?;
        let shift = (r1 - r1_half).abs();
        let margin = STEP_MARGIN * shift;
        let same_way = (r1 - r) * (r1_half - r) > 0.0;
        if !same_way || (r1 - r).abs() <= margin || (r1_half - r).abs() <= margin {
            return None;
        }
        let fp = stepper.params().fixed_point();
        if !winds_once(&x, &v, fp) {
            return None;
        }
        let side = (1..x.len())
            .map(|i| (x[i] - x[i - 1]).hypot(v[i] - v[i - 1]))
            .fold(0.0f64, f64::max);
        let margin = margin.max(side);
        let p = stepper.params();
        let v_max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let sigma_max = (0..x.len())
            .map(|i| (x[i] - fp.x + 2.0 * p.nu * v[i]).abs())
            .fold(0.0f64, f64::max);
        let curve = CurveLocator::new(ClosedCurve::new(x, v));
        let near = fp_radius.max(region.map_or(0.0, Region::outer_radius));
        if curve.side(fp, near + margin) != Some(true) {
            return None;
        }
        Some(ClosedTurn {
            curve,
            r0: r,
            r1,
            margin,
            extremes: (v_max, sigma_max),
        })
    }
}

/// One revolution from `(x*, r)` on the section ([`section_return`]): the states of the run
/// (the crossings included) and the amplitude it returns at; `None` where a state lacks the
/// one-root bound or the run has not returned within [`MAX_PERIODS`] periods.
fn revolution(stepper: &Stepper, r: f64) -> Option<(Vec<f64>, Vec<f64>, f64)> {
    let p = stepper.params();
    let x_star = p.fixed_point().x;
    let (mut x, mut v, mut one) = (Vec::new(), Vec::new(), true);
    let limit = MAX_PERIODS * std::f64::consts::TAU;
    let back = section_return(stepper, r, limit, &mut SolverStats::default(), |s| {
        one &= one_root(p, s.x, s.v);
        x.push(s.x);
        v.push(s.v);
    })
    .ok()?;
    // The last sample is past the section: the crossing ends the polygon instead.
    x.pop();
    v.pop();
    x.push(x_star);
    v.push(back.r);
    (one && one_root(p, x_star, back.r)).then_some((x, v, back.r))
}

/// Whether the polygon `(x, v)` winds once about `fp`, clockwise (the flow's sense), its
/// angle about `fp` never turning back: a simple curve around the fixed point.
fn winds_once(x: &[f64], v: &[f64], fp: State) -> bool {
    let angle = |i: usize| (v[i] - fp.v).atan2(x[i] - fp.x);
    let mut total = 0.0;
    for i in 1..x.len() {
        let mut d = angle(i) - angle(i - 1);
        if d > std::f64::consts::PI {
            d -= std::f64::consts::TAU;
        } else if d < -std::f64::consts::PI {
            d += std::f64::consts::TAU;
        }
        if d > 0.0 {
            return false;
        }
        total += d;
    }
    (total + std::f64::consts::TAU).abs() < 0.5
}
