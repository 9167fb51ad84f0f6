//! True stick with located events, for laws with a static limit (the Stribeck and cubic laws).
//!
//! ```text
//! x'' + 2 nu x' + x = F,   v = x' - lambda (slip velocity)
//! slip:   F = -sgn(v) mu(|v|)
//! stick:  x' = lambda exactly, F = x + 2 nu lambda (the force that holds x'' = 0),
//!         while |x + 2 nu lambda| <= mu_s
//! ```
//!
//! One step of length `h` is split at its events:
//! * **slip phases** use the step of [`crate::stepper`] (the exact linear step with the force
//!   linear over the step, or held, and the end-of-step force solved implicitly), with the law
//!   of the current slip side `sigma = sgn(v)` ([`crate::friction::Law::sliding`]);
//! * **stick onset**: where a slip sub-step would end with the slip velocity through zero, the
//!   sub-step length `tau` with `v(tau) = 0` is found by safeguarded false position on the
//!   implicit sub-step itself (its end force is then `-sigma mu_s`). If the static limit holds
//!   there the block sticks; otherwise it slips through to the other side (a reversal);
//! * **breakaway**: while stuck `x` grows as `lambda t`, so the holding force reaches `mu_s`
//!   at the exact time `(mu_s - (x + 2 nu lambda)) / lambda`, from the state
//!   `x_b = mu_s - 2 nu lambda`, `x' = lambda`; the block then slides back (`sigma = -1`).
//!
//! No smoothing, no chattering: the stick is a state (`x' = lambda` exactly, stored so in the
//! sample), not a velocity band. Every event is counted in [`SolverStats`] (`stick_onsets`,
//! `breakaways`, `slip_reversals`) and returned per step in [`StickEvents`].
//!
//! After a breakaway every run follows the same orbit (the breakaway state is unique), so a
//! run that sticks again after breaking away is on the stick-slip cycle: see
//! [`crate::landscape::stick_slip_cycle`] and the classifier's [`crate::Reason::StickCycle`].

use serde::Serialize;

use crate::friction::{Branch, Law};
use crate::params::Params;
use crate::propagator::{Propagator, Scheme};
use crate::solver::{Solution, SolverStats};
use crate::state::{Sample, State};

/// The events located inside one step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StickEvents {
    /// Stick onsets in the step.
    pub onsets: u32,
    /// Breakaways in the step.
    pub breakaways: u32,
    /// Passages through zero slip without sticking (static limit exceeded there).
    pub reversals: u32,
    /// Time of the first onset from the step's start (NaN if none).
    pub onset_at: f64,
    /// Time of the first breakaway from the step's start (NaN if none).
    pub breakaway_at: f64,
    /// Whether an onset followed a breakaway inside this step.
    pub onset_after_breakaway: bool,
    /// Whether the block was stuck during any part of the step.
    pub stuck: bool,
}

impl StickEvents {
    /// No event (every step of a law without stick).
    pub const NONE: StickEvents = StickEvents {
        onsets: 0,
        breakaways: 0,
        reversals: 0,
        onset_at: f64::NAN,
        breakaway_at: f64::NAN,
        onset_after_breakaway: false,
        stuck: false,
    };
}

/// The affine end state of a sub-step of length `tau` from `(x0, v0)` with start force `f0`:
/// `x = ax + wx1 F1`, `v = av + wv1 F1`, `F1` the end force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SubStep {
    c11: f64,
    c12: f64,
    c21: f64,
    c22: f64,
    w_x0: f64,
    w_x1: f64,
    w_v0: f64,
    w_v1: f64,
}

impl SubStep {
    /// The sub-step of length `tau > 0` (the same weights as [`crate::stepper::Stepper`]'s full step).
    pub(crate) fn new(nu: f64, tau: f64, scheme: Scheme) -> SubStep {
        let c = Propagator::new(nu, tau).expect("a sub-step inside a valid step");
        SubStep::from_propagator(&c, scheme)
    }

    pub(crate) fn from_propagator(c: &Propagator, scheme: Scheme) -> SubStep {
        let (w_x0, w_x1, w_v0, w_v1) = match scheme {
            Scheme::Zoh => (0.0, 1.0 - c.c11, 0.0, -c.c21),
            Scheme::Foh => (c.q1, 1.0 - c.c11 - c.q1, c.q2, -c.c21 - c.q2),
        };
        SubStep {
            c11: c.c11,
            c12: c.c12,
            c21: c.c21,
            c22: c.c22,
            w_x0,
            w_x1,
            w_v0,
            w_v1,
        }
    }
}

/// The state the event stepper needs beside the stepper's own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct StickStepper {
    /// Static limit `mu_s`.
    mu_s: f64,
    nu: f64,
    lambda: f64,
    scheme: Scheme,
    h: f64,
    full: SubStep,
}

/// Largest number of phases (events + 1) in one step before the step is counted as failed.
const MAX_PHASES: usize = 16;

/// Residual below which the slip force equation counts as solved.
const RESIDUAL_TOL: f64 = 4.0 * f64::EPSILON;

#[derive(Clone, Copy)]
enum Mode {
    Stick,
    Slip(f64),
}

impl StickStepper {
    /// `None` for laws without a static limit.
    pub(crate) fn new(p: &Params, law: &Law, prop: &Propagator, scheme: Scheme) -> Option<Self> {
        if !p.law.family().locates_stick() {
            return None;
        }
        Some(StickStepper {
            mu_s: law.static_limit()?,
            nu: p.nu,
            lambda: p.lambda,
            scheme,
            h: prop.h,
            full: SubStep::from_propagator(prop, scheme),
        })
    }

    /// The holding force at displacement `x` while stuck.
    #[inline]
    fn hold(&self, x: f64) -> f64 {
        x + 2.0 * self.nu * self.lambda
    }

    /// The mode of a state at zero slip: stuck if the static limit holds, else the side it
    /// slides to.
    fn at_zero_slip(&self, x: f64) -> Mode {
        let fs = self.hold(x);
        if fs > self.mu_s {
            Mode::Slip(-1.0)
        } else if fs < -self.mu_s {
            Mode::Slip(1.0)
        } else {
            Mode::Stick
        }
    }

    /// The initial force and acceleration at `s` (the law does not depend on `x''`, so no
    /// equation to solve).
    pub(crate) fn initial(&self, law: &Law, s: State) -> (Sample, Solution) {
        let v = s.v - self.lambda;
        let (force, branch) = if v == 0.0 {
            match self.at_zero_slip(s.x) {
                Mode::Stick => (self.hold(s.x), Branch::Stick),
                Mode::Slip(sigma) => (-sigma * self.mu_s, Branch::Slip),
            }
        } else {
            (law.eval(v, 0.0).force, Branch::Slip)
        };
        let a = if branch == Branch::Stick {
            0.0
        } else {
            force - 2.0 * self.nu * s.v - s.x
        };
        (
            Sample {
                t: 0.0,
                x: s.x,
                v: s.v,
                a,
                force,
            },
            Solution {
                force,
                residual: 0.0,
                converged: true,
                branch,
            },
        )
    }

    /// The end-of-sub-step force on slip side `sigma` from `(x0, v0, f0)`: `F` solves
    /// `F = sliding(sigma, v(F))`, `v(F)` affine. Returns `(F, x, v, residual, converged)`.
    fn slip(
        &self,
        law: &Law,
        sub: &SubStep,
        (x0, v0, f0): (f64, f64, f64),
        sigma: f64,
        stats: &mut SolverStats,
    ) -> (f64, f64, f64, f64, bool) {
        stats.solves += 1;
        let ax = sub.c11 * x0 + sub.c12 * v0 + sub.w_x0 * f0;
        let av = sub.c21 * x0 + sub.c22 * v0 + sub.w_v0 * f0;
        let (pv, qv) = (av - self.lambda, sub.w_v1);
        let g = |f: f64, stats: &mut SolverStats| {
            stats.evaluations += 1;
            let (l, dl) = law.sliding(sigma, pv + qv * f);
            (l - f, dl * qv - 1.0)
        };
        let done = |f: f64, r: f64| r.abs() <= RESIDUAL_TOL * (1.0 + f.abs());
        // Newton from the start force: |dF/dF1| = |mu'| |w_v1| is small for small steps, so
        // two or three steps suffice; a bracket and bisection take over otherwise.
        let mut f = f0;
        let (mut r, mut d) = g(f, stats);
        let mut ok = done(f, r);
        let mut it = 0;
        while !ok && it < 8 {
            stats.newton_steps += 1;
            f -= r / d;
            (r, d) = g(f, stats);
            ok = done(f, r);
            it += 1;
        }
        if !ok {
            // G(F) = sliding - F: a bracket outwards from f0 on both sides, then bisection.
            stats.fallbacks += 1;
            let g0 = g(f0, stats).0;
            let mut step = 1e-3 * (1.0 + f0.abs());
            let mut bracket = None;
            for _ in 0..200 {
                stats.expansions += 1;
                let a = f0 - step;
                let ga = g(a, stats).0;
                if ga.signum() != g0.signum() {
                    bracket = Some((a, ga, f0));
                    break;
                }
                let b = f0 + step;
                let gb = g(b, stats).0;
                if gb.signum() != g0.signum() {
                    bracket = Some((f0, g0, b));
                    break;
                }
                step *= 2.0;
            }
            if let Some((mut lo, mut glo, mut hi)) = bracket {
                for _ in 0..400 {
                    stats.bisections += 1;
                    let m = 0.5 * (lo + hi);
                    let gm = g(m, stats).0;
                    (f, r) = (m, gm);
                    if done(m, gm) || !(m > lo && m < hi) {
                        ok = true;
                        break;
                    }
                    if gm.signum() == glo.signum() {
                        (lo, glo) = (m, gm);
                    } else {
                        hi = m;
                    }
                }
            }
            if !ok {
                stats.failures += 1;
            }
        }
        (f, ax + sub.w_x1 * f, av + sub.w_v1 * f, r.abs(), ok)
    }

    /// One step of length `h` from `s`, split at its events: a stick or slip phase at a
    /// time until the step's end, each phase ending at the step's end or at an event.
    pub(crate) fn step(
        &self,
        law: &Law,
        s: &Sample,
        stats: &mut SolverStats,
    ) -> (Sample, Solution, StickEvents) {
        let lam = self.lambda;
        let mut ph = Phases {
            x: s.x,
            v: s.v,
            f: s.force,
            elapsed: 0.0,
            residual: 0.0,
            converged: true,
            mode: if s.v == lam {
                self.at_zero_slip(s.x)
            } else {
                Mode::Slip((s.v - lam).signum())
            },
            ev: StickEvents::NONE,
        };
        let mut finished = false;
        for _ in 0..MAX_PHASES {
            let left = self.h - ph.elapsed;
            let end = left <= 0.0
                || match ph.mode {
                    Mode::Stick => self.stick_phase(&mut ph, left, stats),
                    Mode::Slip(sigma) => self.slip_phase(law, &mut ph, (sigma, left), stats),
                };
            if end {
                finished = true;
                break;
            }
        }
        self.step_end(s, ph, finished, stats)
    }

    /// A stick phase of at most `left`: stuck to the step's end (true), or up to the
    /// breakaway at its exact time, from where the block slides back (false).
    #[inline(always)]
    fn stick_phase(&self, ph: &mut Phases, left: f64, stats: &mut SolverStats) -> bool {
        let lam = self.lambda;
        ph.ev.stuck = true;
        ph.f = self.hold(ph.x);
        let t_b = (self.mu_s - ph.f) / lam;
        if t_b >= left {
            // Stuck to the end of the step: x is linear in t.
            ph.x += lam * left;
            ph.f = self.hold(ph.x);
            ph.v = lam;
            return true;
        }
        // Breakaway at the exact time, from the breakaway state.
        ph.elapsed += t_b;
        ph.x = self.mu_s - 2.0 * self.nu * lam;
        ph.v = lam;
        ph.f = self.mu_s;
        ph.ev.breakaways += 1;
        stats.breakaways += 1;
        if ph.ev.breakaway_at.is_nan() {
            ph.ev.breakaway_at = ph.elapsed;
        }
        ph.mode = Mode::Slip(-1.0);
        false
    }

    /// A slip phase on side `sigma` of at most `left`: slipping to the step's end (true, also
    /// when the zero of the slip velocity cannot be located), or up to zero slip (false).
    #[inline(always)]
    fn slip_phase(
        &self,
        law: &Law,
        ph: &mut Phases,
        (sigma, left): (f64, f64),
        stats: &mut SolverStats,
    ) -> bool {
        let lam = self.lambda;
        let sub = if left == self.h {
            self.full
        } else {
            SubStep::new(self.nu, left, self.scheme)
        };
        let (f1, x1, v1, r, ok) = self.slip(law, &sub, (ph.x, ph.v, ph.f), sigma, stats);
        ph.residual = ph.residual.max(r);
        ph.converged &= ok;
        if sigma * (v1 - lam) > 0.0 {
            (ph.x, ph.v, ph.f) = (x1, v1, f1);
            return true;
        }
        // The slip velocity reaches zero inside (0, left]: locate it.
        let start = (ph.x, ph.v, ph.f);
        let mut side = |tau: f64, stats: &mut SolverStats| {
            let sub = SubStep::new(self.nu, tau, self.scheme);
            let (_, xe, ve, r, ok) = self.slip(law, &sub, start, sigma, stats);
            (sigma * (ve - lam), xe, r, ok)
        };
        let Some((tau, xe, r, ok)) = locate(&mut side, left, stats) else {
            stats.failures += 1;
            ph.converged = false;
            (ph.x, ph.v, ph.f) = (x1, v1, f1);
            return true;
        };
        ph.residual = ph.residual.max(r);
        ph.converged &= ok;
        ph.elapsed += tau;
        ph.x = xe;
        ph.v = lam;
        self.zero_slip_event(ph, sigma, stats);
        false
    }

    /// At zero slip after slipping on side `sigma`: a stick onset if the static limit holds,
    /// else a reversal to the other side.
    #[inline(always)]
    fn zero_slip_event(&self, ph: &mut Phases, sigma: f64, stats: &mut SolverStats) {
        match self.at_zero_slip(ph.x) {
            Mode::Stick => {
                ph.ev.onsets += 1;
                stats.stick_onsets += 1;
                if ph.ev.onset_at.is_nan() {
                    ph.ev.onset_at = ph.elapsed;
                }
                ph.ev.onset_after_breakaway |= ph.ev.breakaways > 0;
                ph.ev.stuck = true;
                ph.mode = Mode::Stick;
                ph.f = self.hold(ph.x);
            }
            Mode::Slip(_) => {
                ph.ev.reversals += 1;
                stats.slip_reversals += 1;
                ph.mode = Mode::Slip(-sigma);
                ph.f = sigma * self.mu_s;
            }
        }
    }

    /// The step's end sample, solution and events from the last phase (`finished`: the
    /// phases reached the step's end within [`MAX_PHASES`]).
    #[inline(always)]
    fn step_end(
        &self,
        s: &Sample,
        ph: Phases,
        finished: bool,
        stats: &mut SolverStats,
    ) -> (Sample, Solution, StickEvents) {
        let mut converged = ph.converged;
        if !finished {
            stats.failures += 1;
            converged = false;
        }
        if ph.ev.stuck {
            stats.sticks += 1;
        }
        let (x, v, f) = (ph.x, ph.v, ph.f);
        let stuck_at_end = v == self.lambda && matches!(ph.mode, Mode::Stick);
        let a = if stuck_at_end {
            0.0
        } else {
            f - 2.0 * self.nu * v - x
        };
        (
            Sample {
                t: s.t + self.h,
                x,
                v,
                a,
                force: f,
            },
            Solution {
                force: f,
                residual: ph.residual,
                converged,
                branch: if stuck_at_end {
                    Branch::Stick
                } else {
                    Branch::Slip
                },
            },
            ph.ev,
        )
    }
}

/// The state of a step between its phases: the state and force reached, the time elapsed,
/// the largest residual, whether every solve converged, the current mode and the events.
struct Phases {
    x: f64,
    v: f64,
    f: f64,
    elapsed: f64,
    residual: f64,
    converged: bool,
    mode: Mode,
    ev: StickEvents,
}

/// The zero of `side(tau)` in `(0, left]`, with `side(0+) > 0` and `side(left) <= 0`:
/// false position with the Illinois modification, kept inside the bracket. Returns the
/// sub-step length and the end state's `x`, residual and convergence. `None` if no positive
/// side can be found (a grazing start at zero slip that does not leave it).
fn locate(
    side: &mut impl FnMut(f64, &mut SolverStats) -> (f64, f64, f64, bool),
    left: f64,
    stats: &mut SolverStats,
) -> Option<(f64, f64, f64, bool)> {
    let mut hi = left;
    let (mut ghi, mut xhi, mut rhi, mut okhi) = side(hi, stats);
    if ghi == 0.0 {
        return Some((hi, xhi, rhi, okhi));
    }
    // A positive side near 0: the phase starts off zero slip, or departs from it.
    let mut lo = 0.5 * left;
    let mut glo = f64::NAN;
    for _ in 0..60 {
        let (g, x, r, ok) = side(lo, stats);
        if g > 0.0 {
            glo = g;
            break;
        }
        if g == 0.0 {
            return Some((lo, x, r, ok));
        }
        (hi, ghi, xhi, rhi, okhi) = (lo, g, x, r, ok);
        lo *= 0.5;
    }
    if glo.is_nan() {
        return None;
    }
    let mut last = 0i8;
    for _ in 0..200 {
        if hi - lo <= 2.0 * f64::EPSILON * hi {
            break;
        }
        stats.event_iterations += 1;
        let mut m = hi - ghi * (hi - lo) / (ghi - glo);
        if !(m > lo && m < hi) {
            m = 0.5 * (lo + hi);
        }
        let (g, x, r, ok) = side(m, stats);
        if g == 0.0 {
            return Some((m, x, r, ok));
        }
        if g > 0.0 {
            lo = m;
            glo = g;
            if last == 1 {
                ghi *= 0.5;
            }
            last = 1;
        } else {
            hi = m;
            ghi = g;
            (xhi, rhi, okhi) = (x, r, ok);
            if last == -1 {
                glo *= 0.5;
            }
            last = -1;
        }
    }
    Some((hi, xhi, rhi, okhi))
}
