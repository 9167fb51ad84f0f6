//! The line `x = x*` through the fixed point, cut into its two halves: the Poincare section
//! `S = { x = x*, x' > 0 }` that every revolution crosses once going right, and the lower
//! half `{ x = x*, x' < 0 }` that it crosses once going left. Each half is crossed in one
//! direction only, because `x` moves with the sign of `x'` there. Crossings are located on
//! cubic Hermite interpolants inside a step.

use serde::Serialize;

use crate::run::Run;
use crate::solver::SolverStats;
use crate::stepper::{Sample, State, Stepper};
use crate::turns::{Lasting, TurnSettings, TurnWatch};

/// A half of the line `x = x*` (crates/core/MODEL.md section 9, "A decaying section").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Half {
    /// The section `x = x*, x' > 0`, crossed going right.
    Upper,
    /// `x = x*, x' < 0`, crossed going left: half a revolution from the section.
    Lower,
}

impl Half {
    /// The crossing of this half between two consecutive samples; its `r` is `|x'|` there.
    #[inline]
    pub fn crossing(self, x_star: f64, prev: &Sample, next: &Sample) -> Option<Crossing> {
        match self {
            Half::Upper => crossing(x_star, prev, next),
            // The lower half is the upper one of the plane turned by half a turn about
            // `(x*, 0)`: the turned samples cross it going right with `x' = |x'|`.
            Half::Lower => crossing(x_star, &turned(x_star, prev), &turned(x_star, next)),
        }
    }

    /// The state on this half at amplitude `r = |x'|`.
    pub fn state(self, x_star: f64, r: f64) -> State {
        let v = match self {
            Half::Upper => r,
            Half::Lower => -r,
        };
        State { x: x_star, v }
    }
}

/// Sample `s` turned by half a turn about `(x*, 0)`: `x -> 2 x* - x`, `x' -> -x'`,
/// `x'' -> -x''` (the Hermite interpolants turn with it).
#[inline]
fn turned(x_star: f64, s: &Sample) -> Sample {
    Sample {
        x: 2.0 * x_star - s.x,
        v: -s.v,
        a: -s.a,
        ..*s
    }
}

/// A crossing of the section `x = x*` going right.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Time (cubic Hermite interpolation inside the step).
    pub t: f64,
    /// `x'` at the crossing.
    pub r: f64,
}

/// Detects section crossings between consecutive samples.
///
/// The crossing is located on the cubic Hermite interpolants of `x` (through `x`, `x'` at
/// both ends) and `x'` (through `x'`, `x''`), so its error is `O(dt^4)`. Linear
/// interpolation errs by up to `dt^2 |x'''| / 8` (about `1e-6` at `dt = 0.005` on the
/// unstable cycle at `nu = 1e-3`), and the error depends on where in the step the section
/// falls: the return map then jitters by that much from one revolution to the next, and
/// its fixed point, the cycle's crossing, moves by that error over `P'(r_u) - 1` (0.0064
/// there): about `1.6e-4`, as far as the trap's margin reached (crates/core/MODEL.md).
#[inline]
pub fn crossing(x_star: f64, prev: &Sample, next: &Sample) -> Option<Crossing> {
    if prev.x < x_star && next.x >= x_star && next.v > 0.0 {
        let h = next.t - prev.t;
        let th = hermite_root(
            [prev.x - x_star, h * prev.v, next.x - x_star, h * next.v],
            (x_star - prev.x) / (next.x - prev.x),
        );
        Some(Crossing {
            t: prev.t + th * h,
            r: hermite([prev.v, h * prev.a, next.v, h * next.a], th),
        })
    } else {
        None
    }
}

/// The cubic Hermite interpolant on `[0, 1]` with end values `y0`, `y1` and end slopes
/// `d0`, `d1` (per unit of `th`), given as `[y0, d0, y1, d1]`, at `th`.
#[inline]
pub(crate) fn hermite([y0, d0, y1, d1]: [f64; 4], th: f64) -> f64 {
    let (t2, t3) = (th * th, th * th * th);
    (2.0 * t3 - 3.0 * t2 + 1.0) * y0
        + (t3 - 2.0 * t2 + th) * d0
        + (3.0 * t2 - 2.0 * t3) * y1
        + (t3 - t2) * d1
}

/// The root in `[0, 1]` of the Hermite interpolant `c` (with `y0 < 0 <= y1`), by Newton from
/// `th` (the linear root), safeguarded by bisection: `[lo, hi]` always holds a sign change.
#[inline]
pub(crate) fn hermite_root(c: [f64; 4], mut th: f64) -> f64 {
    let [y0, d0, y1, d1] = c;
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let y = hermite(c, th);
        if y < 0.0 {
            lo = th;
        } else {
            hi = th;
        }
        let t2 = th * th;
        let dy = (6.0 * t2 - 6.0 * th) * y0
            + (3.0 * t2 - 4.0 * th + 1.0) * d0
            + (6.0 * th - 6.0 * t2) * y1
            + (3.0 * t2 - 2.0 * th) * d1;
        let newton = th - y / dy;
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - th).abs() <= 1e-14 || hi - lo <= 1e-14 {
            return next;
        }
        th = next;
    }
    th
}
/// Why a run from a half of the line `x = x*` did not come back to it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Miss {
    /// Not by the time limit.
    TimeLimit,
    /// The run's own solve failed, or its state stopped being finite.
    Failed,
    /// It settled on a lasting oscillation whose turns do not reach the section
    /// ([`crate::turns`]): stopped there, before the time limit. Under the same limit it
    /// would have run to the limit without a return (unless the oscillation was a
    /// transient after all: crates/core/MODEL.md section 10).
    Lasting(Lasting),
}

/// One return to the section from `(x*, r)`: the next crossing's amplitude and time, or why
/// the run does not come back by `t_max` ([`Miss`]). `visit` sees every sample; this run's
/// counters are added to `stats`.
pub fn section_return(
    stepper: &Stepper,
    r: f64,
    t_max: f64,
    stats: &mut SolverStats,
    visit: impl FnMut(&Sample),
) -> Result<Crossing, Miss> {
    half_return(stepper, Half::Upper, r, t_max, stats, visit)
}

/// [`section_return`] on either half: the run from amplitude `r` on `half` to its next
/// crossing of the same half. A run that settles on a lasting oscillation missing the
/// section (the default classifier's window of turns, [`TurnSettings::default`]) stops
/// there: [`Miss::Lasting`].
pub fn half_return(
    stepper: &Stepper,
    half: Half,
    r: f64,
    t_max: f64,
    stats: &mut SolverStats,
    mut visit: impl FnMut(&Sample),
) -> Result<Crossing, Miss> {
    let fp = stepper.params().fixed_point();
    let mut run = Run::new(stepper, half.state(fp.x, r));
    let mut turns = TurnWatch::new(stepper.params(), TurnSettings::default());
    visit(run.sample());
    let mut found = Err(Miss::TimeLimit);
    for _ in 0..run.steps_to(t_max) {
        let step = run.step();
        visit(&step.next);
        // This run's own failures: the caller's `stats` sum earlier runs.
        if run.failed() || !step.next.x.is_finite() {
            found = Err(Miss::Failed);
            break;
        }
        if let Some(c) = half.crossing(fp.x, &step.prev, &step.next) {
            found = Ok(c);
            break;
        }
        if turns.observe_step(&run, &step).is_some()
            && let Some(l) = turns.lasting().filter(Lasting::misses_section)
        {
            found = Err(Miss::Lasting(l));
            break;
        }
    }
    stats.merge(run.stats());
    found
}
