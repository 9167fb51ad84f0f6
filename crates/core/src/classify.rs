//! One initial condition to a label: which attractor does the run settle on?
//!
//! The phase plane holds the stable steady-slip fixed point `(x*, 0)`, around it an unstable
//! limit cycle, and further out the stable stick-slip oscillation. Runs are watched on the
//! Poincare section `S = { x = x*, x' > 0 }`, which every revolution crosses once, going
//! right; the value `r` of `x'` at a crossing is the run's *section amplitude*.
//!
//! Decisions, checked at every step or crossing:
//! * [`Reason::NearFixedPoint`]: the state is within `fp_radius` of the fixed point:
//!   steady slip (the radius must lie well inside the unstable cycle).
//! * [`Reason::SettledStickSlip`]: over the last `settle_cycles` crossings the section
//!   amplitudes stay in a band of relative width `settle_rtol` and show no trend (a run near
//!   the unstable cycle drifts steadily away, the stick-slip band does not): stick-slip.
//! * With a [`Trap`] (the unstable cycle's crossing `r_u` of `S`, located beforehand): a
//!   crossing below `r_u - margin` is inside the cycle, a crossing above `r_u + margin` is
//!   outside it. In the plane a trajectory cannot cross the cycle, so the label is decided:
//!   [`Reason::InsideCycle`] / [`Reason::OutsideCycle`]. This is the early-stopping rule;
//!   tests check it against runs taken to settlement.
//! * Otherwise, at `t_max`: [`Regime::Undecided`] with [`Reason::TimeLimit`]; never a guess.
//!   A run that blows up or whose robust solve fails is undecided too.
//!
//! Label names the attractor. "Reached belt speed" is not used: with true roots the
//! hysteretic stick-slip loop need not reach `lambda` (crates/core/MODEL.md, section 5).

use serde::Serialize;

use crate::friction;
use crate::solver::SolverStats;
use crate::stepper::{Sample, State, Stepper};

/// The attractor a run settles on. The values are stored in files (HDF5 enum `regime`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[repr(u8)]
pub enum Regime {
    /// Not settled by `t_max` (or blew up, or the solver failed): never guessed.
    Undecided = 0,
    /// The steady-slip fixed point.
    SteadySlip = 1,
    /// The self-excited stick-slip oscillation ("squeal").
    StickSlip = 2,
}

impl Regime {
    /// All labels, in value order.
    pub const ALL: [Regime; 3] = [Regime::Undecided, Regime::SteadySlip, Regime::StickSlip];

    /// The label's name in files and output.
    pub fn name(self) -> &'static str {
        match self {
            Regime::Undecided => "undecided",
            Regime::SteadySlip => "steady_slip",
            Regime::StickSlip => "stick_slip",
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
}

impl Reason {
    /// All reasons, in value order.
    pub const ALL: [Reason; 7] = [
        Reason::TimeLimit,
        Reason::NearFixedPoint,
        Reason::InsideCycle,
        Reason::OutsideCycle,
        Reason::SettledStickSlip,
        Reason::Diverged,
        Reason::SolverFailure,
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
        }
    }
}

/// The unstable cycle's crossing of the section, for early stopping.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Trap {
    /// Section amplitudes below this are inside the unstable cycle.
    pub r_inner: f64,
    /// Section amplitudes above this are outside the unstable cycle.
    pub r_outer: f64,
}

/// Classifier settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Classifier {
    /// Give up (undecided) at this time.
    pub t_max: f64,
    /// Steady slip once this close to the fixed point.
    pub fp_radius: f64,
    /// Crossings in the window of the stick-slip settling test.
    pub settle_cycles: u32,
    /// Relative band width of the stick-slip settling test.
    pub settle_rtol: f64,
    /// Undecided (diverged) beyond this `|x|` or `|x'|`.
    pub max_radius: f64,
    /// Early stopping on the located unstable cycle, if any.
    pub trap: Option<Trap>,
}

impl Default for Classifier {
    fn default() -> Self {
        Classifier {
            t_max: crate::defaults::T_MAX,
            fp_radius: 1e-3,
            settle_cycles: 20,
            settle_rtol: 0.05,
            max_radius: 1e6,
            trap: None,
        }
    }
}

/// The label and diagnostics of one run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Outcome {
    /// The attractor.
    pub regime: Regime,
    /// Why the run stopped.
    pub reason: Reason,
    /// Time at the decision.
    pub t_decision: f64,
    /// The last section amplitude (`x'` at the last crossing of `x = x*`), NaN if none.
    pub amplitude: f64,
    /// Distance from the fixed point at the decision.
    pub distance: f64,
    /// Angular frequency of the last revolution, `2 pi / (t_k - t_{k-1})`, NaN if unknown.
    pub omega: f64,
    /// Crossings of the section.
    pub crossings: u32,
    /// Whether any step was on the quasi-static branch of the law.
    pub quasi_static: bool,
    /// Solver counters.
    pub stats: SolverStats,
    /// Largest residual `|G(F)|` of any solve.
    pub max_residual: f64,
}

/// A crossing of the section `x = x*` going right.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Time (linear interpolation inside the step).
    pub t: f64,
    /// `x'` at the crossing.
    pub r: f64,
}

/// Detects section crossings between consecutive samples.
#[inline]
pub fn crossing(x_star: f64, prev: &Sample, next: &Sample) -> Option<Crossing> {
    if prev.x < x_star && next.x >= x_star && next.v > 0.0 {
        let th = (x_star - prev.x) / (next.x - prev.x);
        Some(Crossing {
            t: prev.t + th * (next.t - prev.t),
            r: prev.v + th * (next.v - prev.v),
        })
    } else {
        None
    }
}

impl Classifier {
    /// Validates the settings; the error names the setting.
    pub fn validate(&self) -> Result<(), crate::CoreError> {
        let bad = |name: &'static str, value: f64, expected: &'static str| {
            Err(crate::CoreError::InvalidParameter {
                name,
                value,
                expected,
            })
        };
        if !self.t_max.is_finite() || self.t_max <= 0.0 {
            return bad("t_max", self.t_max, "a finite time > 0");
        }
        if !self.fp_radius.is_finite() || self.fp_radius <= 0.0 {
            return bad("fp_radius", self.fp_radius, "a finite radius > 0");
        }
        if self.settle_cycles < 4 {
            return bad(
                "settle_cycles",
                self.settle_cycles as f64,
                "at least 4 crossings",
            );
        }
        if !self.settle_rtol.is_finite() || self.settle_rtol <= 0.0 || self.settle_rtol >= 1.0 {
            return bad(
                "settle_rtol",
                self.settle_rtol,
                "a relative width in (0, 1)",
            );
        }
        if !self.max_radius.is_finite() || self.max_radius <= 0.0 {
            return bad("max_radius", self.max_radius, "a finite radius > 0");
        }
        Ok(())
    }

    /// Runs from `ic` until a decision or `t_max`.
    pub fn classify(&self, stepper: &Stepper, ic: State) -> Outcome {
        self.classify_with(stepper, ic, |_| {})
    }

    /// As [`Classifier::classify`], calling `visit` on every sample (for trajectories).
    pub fn classify_with(
        &self,
        stepper: &Stepper,
        ic: State,
        mut visit: impl FnMut(&Sample),
    ) -> Outcome {
        let p = *stepper.params();
        let fp = p.fixed_point();
        let mut stats = SolverStats::default();
        let (mut s, sol) = stepper.initial(ic, &mut stats);
        visit(&s);
        let mut max_residual = sol.residual;
        let mut quasi_static = friction::on_quasi_static_branch(&p, s.v - p.lambda, s.a);
        let window = self.settle_cycles as usize;
        let mut ring: Vec<f64> = Vec::with_capacity(window);
        let mut crossings = 0u32;
        let (mut last_t, mut omega, mut amplitude) = (f64::NAN, f64::NAN, f64::NAN);
        let fp_r2 = self.fp_radius * self.fp_radius;
        let n_max = (self.t_max / stepper.dt()).ceil() as u64;
        let finish =
            |regime, reason, s: &Sample, amplitude, omega, crossings, qs, stats, res| Outcome {
                regime,
                reason,
                t_decision: s.t,
                amplitude,
                distance: (s.x - fp.x).hypot(s.v - fp.v),
                omega,
                crossings,
                quasi_static: qs,
                stats,
                max_residual: res,
            };
        for _ in 0..n_max {
            let (n, sol) = stepper.step(&s, &mut stats);
            visit(&n);
            max_residual = max_residual.max(sol.residual);
            quasi_static |= friction::on_quasi_static_branch(&p, n.v - p.lambda, n.a);
            if stats.failures > 0 || !n.x.is_finite() || !n.v.is_finite() {
                let reason = if stats.failures > 0 {
                    Reason::SolverFailure
                } else {
                    Reason::Diverged
                };
                return finish(
                    Regime::Undecided,
                    reason,
                    &n,
                    amplitude,
                    omega,
                    crossings,
                    quasi_static,
                    stats,
                    max_residual,
                );
            }
            let (dx, dv) = (n.x - fp.x, n.v - fp.v);
            if dx * dx + dv * dv < fp_r2 {
                return finish(
                    Regime::SteadySlip,
                    Reason::NearFixedPoint,
                    &n,
                    amplitude,
                    omega,
                    crossings,
                    quasi_static,
                    stats,
                    max_residual,
                );
            }
            if n.x.abs() > self.max_radius || n.v.abs() > self.max_radius {
                return finish(
                    Regime::Undecided,
                    Reason::Diverged,
                    &n,
                    amplitude,
                    omega,
                    crossings,
                    quasi_static,
                    stats,
                    max_residual,
                );
            }
            if let Some(c) = crossing(fp.x, &s, &n) {
                crossings += 1;
                if last_t.is_finite() {
                    omega = std::f64::consts::TAU / (c.t - last_t);
                }
                last_t = c.t;
                amplitude = c.r;
                if let Some(trap) = self.trap {
                    if c.r < trap.r_inner {
                        return finish(
                            Regime::SteadySlip,
                            Reason::InsideCycle,
                            &n,
                            amplitude,
                            omega,
                            crossings,
                            quasi_static,
                            stats,
                            max_residual,
                        );
                    }
                    if c.r > trap.r_outer {
                        return finish(
                            Regime::StickSlip,
                            Reason::OutsideCycle,
                            &n,
                            amplitude,
                            omega,
                            crossings,
                            quasi_static,
                            stats,
                            max_residual,
                        );
                    }
                }
                if ring.len() == window {
                    ring.remove(0);
                }
                ring.push(c.r);
                if ring.len() == window && self.settled(&ring) {
                    return finish(
                        Regime::StickSlip,
                        Reason::SettledStickSlip,
                        &n,
                        amplitude,
                        omega,
                        crossings,
                        quasi_static,
                        stats,
                        max_residual,
                    );
                }
            }
            s = n;
        }
        finish(
            Regime::Undecided,
            Reason::TimeLimit,
            &s,
            amplitude,
            omega,
            crossings,
            quasi_static,
            stats,
            max_residual,
        )
    }

    /// The stick-slip settling test on a full window of section amplitudes: a narrow band
    /// with no trend. Near the unstable cycle the amplitudes drift monotonically (trend close
    /// to the spread); near the fixed point they shrink geometrically; on the stick-slip
    /// loop they jitter inside a quasi-periodic band.
    fn settled(&self, ring: &[f64]) -> bool {
        let (lo, hi) = ring
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &r| {
                (l.min(r), h.max(r))
            });
        let mean = ring.iter().sum::<f64>() / ring.len() as f64;
        if lo.is_nan() || lo <= 10.0 * self.fp_radius || hi - lo > self.settle_rtol * mean {
            return false;
        }
        let half = ring.len() / 2;
        let m1 = ring[..half].iter().sum::<f64>() / half as f64;
        let m2 = ring[ring.len() - half..].iter().sum::<f64>() / half as f64;
        let spread = hi - lo;
        (m2 - m1).abs() <= 0.5 * spread || spread <= 1e-9 * mean
    }
}

/// One return to the section from `(x*, r)`: the next crossing's amplitude and time, or
/// `None` if the run does not come back by `t_max` (or fails). `visit` sees every sample.
pub fn section_return(
    stepper: &Stepper,
    r: f64,
    t_max: f64,
    stats: &mut SolverStats,
    mut visit: impl FnMut(&Sample),
) -> Option<Crossing> {
    let fp = stepper.params().fixed_point();
    let (mut s, _) = stepper.initial(State { x: fp.x, v: r }, stats);
    visit(&s);
    let n_max = (t_max / stepper.dt()).ceil() as u64;
    for _ in 0..n_max {
        let (n, _) = stepper.step(&s, stats);
        visit(&n);
        if stats.failures > 0 || !n.x.is_finite() {
            return None;
        }
        if let Some(c) = crossing(fp.x, &s, &n) {
            return Some(c);
        }
        s = n;
    }
    None
}
