//! A lasting oscillation certified as an attracting periodic orbit, so a run on it can stop
//! (crates/core/MODEL.md section 10, "A run ends when its attractor is certified").
//!
//! **The turn map.** At a maximum of `x` the velocity is zero, so the slip velocity is
//! `-lambda < 0`: the block slips. Where the force equation has one root there, the state
//! is `(x, 0)` alone, and the next maximum is a function `T(x)` of it: a map of one variable,
//! whatever the oscillation's shape (it need not cross the section `x = x*`: the slip
//! oscillation about an unstable steady slip, and a clamped brake's stick-slip swing below
//! it, do not).
//!
//! **The certificate.** A run's maxima `c = x_n` that have converged (`|T(c) - c|` small)
//! sit on a periodic orbit if an interval `J = [c - d, c + d]` is mapped into itself. `T` is
//! evaluated at `c - d`, `c` and `c + d` by runs from those maxima (one turn each): where it
//! is monotone on `J` (its three values in order: the premise, sampled), `T(J)` lies
//! between `T(c - d)` and `T(c + d)`, and both inside `J` by the margin `(1 - MARGIN) d`
//! mean `T(J)` is inside `J`: every later maximum of the run stays in `J`, the run lasts on
//! the oscillation for good. The slope `(T(c + d) - T(c - d)) / (2 d)` is the orbit's
//! Floquet multiplier. The same three turns are run at `dt / 2` and must map `J` into itself
//! too: the margin covers the step's error (`d` is at least four times the shift of `T(c)`
//! between the steps). Each of the six runs must restart on the run's own root: the
//! acceleration at its start equals the run's at the maximum (else the force has several
//! roots there and `(x, 0)` is not the whole state): the certificate is refused.

use serde::Serialize;

use crate::run::Run;
use crate::section::{hermite, hermite_root};
use crate::solver::SolverStats;
use crate::state::Sample;
use crate::stepper::{State, Stepper};

/// The share of `d` the images must keep clear of `J`'s ends.
pub const MARGIN: f64 = 0.1;

/// A maximum of `x` inside the step from `prev` to `next` (`x'` from positive to not
/// positive): its time and `x` on the cubic Hermite interpolants (error `O(dt^4)`), and the
/// force there (linear: the root to restart near).
#[inline]
pub fn maximum(prev: &Sample, next: &Sample) -> Option<(f64, f64, f64)> {
    if !(prev.v > 0.0 && next.v <= 0.0) {
        return None;
    }
    let h = next.t - prev.t;
    let c = [-prev.v, -h * prev.a, -next.v, -h * next.a];
    let th = hermite_root(c, prev.v / (prev.v - next.v));
    let x = hermite([prev.x, h * prev.v, next.x, h * next.v], th);
    let force = prev.force + th * (next.force - prev.force);
    Some((prev.t + th * h, x, force))
}

/// One turn from the maximum `(x, 0)` on the root nearest the force `near`: the next
/// maximum's `x`, the turn's period, and the force at the start (`None`: no maximum by
/// `t_max`, or the run failed).
pub fn turn(
    stepper: &Stepper,
    (x, near): (f64, f64),
    t_max: f64,
    stats: &mut SolverStats,
) -> Option<(f64, f64, f64)> {
    let mut run = Run::new_near(stepper, State { x, v: 0.0 }, Some(near));
    let out = turn_of(&mut run, t_max);
    stats.merge(run.stats());
    out
}

/// [`turn`] on the run `run` just started.
fn turn_of(run: &mut Run, t_max: f64) -> Option<(f64, f64, f64)> {
    let f0 = run.sample().force;
    // The start is a maximum itself: wait for the velocity to turn negative first.
    let mut left = false;
    for _ in 0..run.steps_to(t_max) {
        let step = run.step();
        if run.failed() || !step.next.x.is_finite() {
            return None;
        }
        left |= step.next.v < 0.0;
        if left && let Some((t, xm, _)) = maximum(&step.prev, &step.next) {
            return Some((xm, t, f0));
        }
    }
    None
}

/// A certified attracting periodic orbit, by its turn map.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Orbit {
    /// The maximum of `x` the certificate is centred on.
    pub x_max: f64,
    /// The half-width `d` of the interval mapped into itself.
    pub half_width: f64,
    /// The period of one turn (nondimensional).
    pub period: f64,
    /// The Floquet multiplier `T'` at `dt`, and at `dt / 2`.
    pub multiplier: [f64; 2],
}

/// Certifies the orbit through the maximum `(c, 0)`, where the run had force `a`,
/// with `steppers` at `dt` and `dt / 2` and each turn run to at most `t_turn` (see the
/// module's argument). `last` is the previous maximum of the run (its change sets `d`).
/// Returns the orbit (`None`: not certified) and the solver's counts over its turns.
pub fn certify(
    steppers: (&Stepper, &Stepper),
    (c, a, last): (f64, f64, f64),
    t_turn: f64,
) -> (Option<Orbit>, SolverStats) {
    let mut stats = SolverStats::default();
    let orbit = certify_counted(steppers, (c, a, last), t_turn, &mut stats);
    (orbit, stats)
}

fn certify_counted(
    steppers: (&Stepper, &Stepper),
    (c, a, last): (f64, f64, f64),
    t_turn: f64,
    stats: &mut SolverStats,
) -> Option<Orbit> {
    let same_root = |f0: f64| (f0 - a).abs() <= 1e-4 * (1.0 + a.abs());
    let mut at = |st: &Stepper, x: f64| turn(st, (x, a), t_turn, stats);
    let (tc, period, a0) = at(steppers.0, c)?;
    let (th, _, ah) = at(steppers.1, c)?;
    if !same_root(a0) || !same_root(ah) {
        return None;
    }
    let scale = 1e-9 * (1.0 + c.abs());
    let d0 = (20.0 * (tc - c).abs())
        .max(20.0 * (c - last).abs())
        .max(4.0 * (th - tc).abs())
        .max(scale);
    // The orbit at dt / 2 lies (th - tc) / (1 - T') from the one at dt: where J is too
    // narrow to hold both, it is widened (four times at most).
    let mut found = None;
    for d in [d0, 2.0 * d0, 4.0 * d0, 8.0 * d0] {
        if let Some(m) = maps_into_itself(&mut at, (steppers, c, d), (tc, th))? {
            found = Some((d, m));
            break;
        }
    }
    let (d, multiplier) = found?;
    Some(Orbit {
        x_max: c,
        half_width: d,
        period,
        multiplier,
    })
}

/// Whether `J = [c - d, c + d]` is mapped into itself at both steps (the turns' images of its
/// ends and of `c`, `tc` and `th`, in order and inside `J` by the margin): the multipliers
/// where it is (`Some(None)`: it is not; `None`: a turn failed).
fn maps_into_itself(
    at: &mut impl FnMut(&Stepper, f64) -> Option<(f64, f64, f64)>,
    ((dt, half), c, d): ((&Stepper, &Stepper), f64, f64),
    (tc, th): (f64, f64),
) -> Option<Option<[f64; 2]>> {
    let inside = |y: f64| (y - c).abs() <= (1.0 - MARGIN) * d;
    let mut multiplier = [0.0; 2];
    for (k, (st, mid)) in [(dt, tc), (half, th)].into_iter().enumerate() {
        let (lo, _, _) = at(st, c - d)?;
        let (hi, _, _) = at(st, c + d)?;
        let monotone = (lo <= mid && mid <= hi) || (hi <= mid && mid <= lo);
        if !(monotone && inside(lo) && inside(hi) && inside(mid)) {
            return Some(None);
        }
        multiplier[k] = (hi - lo) / (2.0 * d);
    }
    Some(Some(multiplier))
}
