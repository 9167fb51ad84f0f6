//! The implicit force equation and its two solvers.
//!
//! Over a step the end state is affine in the step's force `F` (see [`crate::propagator`]),
//! so the slip velocity and the acceleration at the end of the step are
//! `v(F) = pv + qv F` and `a(F) = pa + qa F`, and the force solves
//!
//! ```text
//! G(F) = L(v(F), a(F)) - F = 0
//! ```
//!
//! * [`SolverKind::Paper`]: the paper's fixed-point iteration `F <- L(v(F), a(F))` warm-started
//!   at the previous force, with an iteration cap. On the quasi-static branch `|dL/dF| > 1`
//!   and it may not converge: such steps keep the last iterate and are counted.
//! * [`SolverKind::Robust`] (default): a true root. It brackets outwards from the previous
//!   force in both directions at once (so the first sign change it finds is the nearest one on
//!   either side, which is the model's hysteresis: the force stays on its branch while the
//!   branch exists), then polishes with Newton on the analytic derivative, falling back to
//!   bisection whenever Newton would leave the bracket. All roots lie in
//!   `[-B, B]` with `B = Params::force_bound`, so the search always ends.
//!
//! Coulomb's law is set-valued at `v = 0`; its equation is solved in closed form: slip with
//! `F = -sgn v`, or stick with the `F` in `[-1, 1]` that keeps `v = 0`.

use serde::{Deserialize, Serialize};

use crate::friction;
use crate::params::{FrictionLaw, Params};

/// Which solver finds the step's force.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum SolverKind {
    /// Bracketed, safeguarded Newton: always a true root, the nearest to the previous force.
    #[default]
    Robust,
    /// The paper's fixed-point iteration with an iteration cap.
    Paper,
}

impl SolverKind {
    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            SolverKind::Robust => "robust",
            SolverKind::Paper => "paper",
        }
    }
}

impl std::str::FromStr for SolverKind {
    type Err = crate::CoreError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "robust" => Ok(SolverKind::Robust),
            "paper" => Ok(SolverKind::Paper),
            _ => Err(crate::CoreError::UnknownSolver(s.to_string())),
        }
    }
}

impl std::fmt::Display for SolverKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Solver settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolverConfig {
    /// Which solver.
    pub kind: SolverKind,
    /// Iteration cap of the paper's fixed-point iteration.
    pub max_iter: u32,
    /// Convergence tolerance of the paper's iteration on `|F_{k+1} - F_k|`.
    pub paper_tol: f64,
}

impl Default for SolverConfig {
    fn default() -> Self {
        SolverConfig {
            kind: SolverKind::Robust,
            max_iter: crate::defaults::MAX_ITER,
            paper_tol: 1e-12,
        }
    }
}

/// What the solver did, summed over steps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SolverStats {
    /// Implicit solves (steps, plus the initial force).
    pub solves: u64,
    /// Friction-law evaluations.
    pub evaluations: u64,
    /// Newton steps accepted inside a bracket (robust).
    pub newton_steps: u64,
    /// Bisection steps taken because Newton would have left the bracket (robust).
    pub bisections: u64,
    /// Solves whose bracket search had to widen beyond the first Newton-sized step (robust).
    pub expansions: u64,
    /// Solves that found sign changes on both sides of the previous force at the same
    /// distance, i.e. several roots; the nearer was taken (robust).
    pub multi_root: u64,
    /// Solves that ended at a jump of `G` rather than a root (only possible at `v = a = 0`).
    pub discontinuities: u64,
    /// Solves that found no root at all (none is expected; counted, never silent).
    pub failures: u64,
    /// Fixed-point iterations (paper).
    pub iterations: u64,
    /// Steps where the paper's iteration hit its cap and kept the last iterate.
    pub unconverged: u64,
    /// Coulomb steps that stuck (`v = 0`, force inside `[-1, 1]`).
    pub sticks: u64,
}

impl SolverStats {
    /// Adds another run's counters.
    pub fn merge(&mut self, o: &SolverStats) {
        self.solves += o.solves;
        self.evaluations += o.evaluations;
        self.newton_steps += o.newton_steps;
        self.bisections += o.bisections;
        self.expansions += o.expansions;
        self.multi_root += o.multi_root;
        self.discontinuities += o.discontinuities;
        self.failures += o.failures;
        self.iterations += o.iterations;
        self.unconverged += o.unconverged;
        self.sticks += o.sticks;
    }
}

/// The implicit equation of one solve: `v(F) = pv + qv F`, `a(F) = pa + qa F`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceEquation {
    /// Slip velocity at `F = 0`.
    pub pv: f64,
    /// `dv/dF`.
    pub qv: f64,
    /// Acceleration at `F = 0`.
    pub pa: f64,
    /// `da/dF`.
    pub qa: f64,
}

/// The result of one solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solution {
    /// The force.
    pub force: f64,
    /// `|G(F)|` at the returned force (0 for a Coulomb stick, which solves the inclusion).
    pub residual: f64,
    /// False when the paper's iteration hit its cap or the robust solver failed.
    pub converged: bool,
}

impl ForceEquation {
    /// `G(F)` and `G'(F)`.
    #[inline]
    pub fn eval(&self, p: &Params, f: f64) -> (f64, f64) {
        let e = friction::force(p, self.pv + self.qv * f, self.pa + self.qa * f);
        (e.force - f, e.dv * self.qv + e.da * self.qa - 1.0)
    }
}

/// Residual below which `G(F)` counts as zero: a few ulps of `F`'s size.
const RESIDUAL_TOL: f64 = 4.0 * f64::EPSILON;

/// Solves one implicit force equation, starting from (and, for the robust solver, nearest
/// to) `f_prev`.
pub fn solve(
    p: &Params,
    cfg: &SolverConfig,
    eq: &ForceEquation,
    f_prev: f64,
    stats: &mut SolverStats,
) -> Solution {
    stats.solves += 1;
    if p.law == FrictionLaw::Coulomb {
        return solve_coulomb(eq, f_prev, stats);
    }
    match cfg.kind {
        SolverKind::Paper => solve_paper(p, cfg, eq, f_prev, stats),
        SolverKind::Robust => solve_robust(p, eq, f_prev, stats),
    }
}

fn solve_paper(
    p: &Params,
    cfg: &SolverConfig,
    eq: &ForceEquation,
    f_prev: f64,
    stats: &mut SolverStats,
) -> Solution {
    let mut f = f_prev;
    for _ in 0..cfg.max_iter {
        stats.iterations += 1;
        stats.evaluations += 1;
        let next = friction::force(p, eq.pv + eq.qv * f, eq.pa + eq.qa * f).force;
        let done = (next - f).abs() <= cfg.paper_tol * (1.0 + f.abs());
        f = next;
        if done {
            let residual = eq.eval(p, f).0.abs();
            return Solution {
                force: f,
                residual,
                converged: true,
            };
        }
    }
    stats.unconverged += 1;
    let residual = eq.eval(p, f).0.abs();
    Solution {
        force: f,
        residual,
        converged: false,
    }
}

fn solve_coulomb(eq: &ForceEquation, f_prev: f64, stats: &mut SolverStats) -> Solution {
    let mut best: Option<(f64, bool)> = None;
    let mut consider = |f: f64, stick: bool| {
        if best.is_none_or(|(b, _)| (f - f_prev).abs() < (b - f_prev).abs()) {
            best = Some((f, stick));
        }
    };
    // Slip at F = -1 needs v(-1) > 0; slip at F = +1 needs v(1) < 0.
    if eq.pv - eq.qv > 0.0 {
        consider(-1.0, false);
    }
    if eq.pv + eq.qv < 0.0 {
        consider(1.0, false);
    }
    if eq.qv != 0.0 {
        let f = -eq.pv / eq.qv;
        if f.abs() <= 1.0 {
            consider(f, true);
        }
    } else if eq.pv == 0.0 {
        // Initial force at zero slip: the force in [-1, 1] that makes a = 0 if it can.
        let f = if eq.qa != 0.0 {
            (-eq.pa / eq.qa).clamp(-1.0, 1.0)
        } else {
            0.0
        };
        consider(f, true);
    }
    match best {
        Some((f, stick)) => {
            if stick {
                stats.sticks += 1;
            }
            Solution {
                force: f,
                residual: 0.0,
                converged: true,
            }
        }
        None => {
            stats.failures += 1;
            Solution {
                force: f_prev,
                residual: f64::INFINITY,
                converged: false,
            }
        }
    }
}

#[inline]
fn same_sign(a: f64, b: f64) -> bool {
    (a > 0.0 && b > 0.0) || (a < 0.0 && b < 0.0)
}

fn solve_robust(p: &Params, eq: &ForceEquation, f_prev: f64, stats: &mut SolverStats) -> Solution {
    let bound = p.force_bound() * (1.0 + 1e-12);
    let f0 = if f_prev.is_finite() {
        f_prev.clamp(-bound, bound)
    } else {
        0.0
    };
    let (g0, d0) = eq.eval(p, f0);
    stats.evaluations += 1;
    if g0.abs() <= RESIDUAL_TOL * (1.0 + f0.abs()) {
        return Solution {
            force: f0,
            residual: g0.abs(),
            converged: true,
        };
    }
    if !g0.is_finite() {
        stats.failures += 1;
        return Solution {
            force: f0,
            residual: f64::INFINITY,
            converged: false,
        };
    }
    let newton = -g0 / d0;
    let mut delta = if newton.is_finite() && newton != 0.0 {
        (2.0 * newton.abs()).clamp(1e-12, 2.0 * bound)
    } else {
        1e-3
    };
    // Outward search: consecutive intervals on the right [r_in, r_out] and on the left.
    // An interval without a sign change can still hold a pair of roots: `hidden_pair` looks
    // for it when the slopes at the ends say `|G|` has a minimum inside.
    let (mut r_in, mut gr_in, mut dr_in) = (f0, g0, d0);
    let (mut l_in, mut gl_in, mut dl_in) = (f0, g0, d0);
    let mut first = true;
    loop {
        let r_out = (f0 + delta).min(bound);
        let l_out = (f0 - delta).max(-bound);
        let mut right = None;
        let mut left = None;
        if r_in < bound {
            let (g, d) = eq.eval(p, r_out);
            stats.evaluations += 1;
            if !same_sign(g, gr_in) {
                right = Some((r_in, gr_in, r_out, g));
            } else {
                right = hidden_pair(p, eq, (r_in, gr_in, dr_in), (r_out, g, d), stats);
            }
            (r_in, gr_in, dr_in) = (r_out, g, d);
        }
        if l_in > -bound {
            let (g, d) = eq.eval(p, l_out);
            stats.evaluations += 1;
            if !same_sign(g, gl_in) {
                left = Some((l_out, g, l_in, gl_in));
            } else if let Some((near, g_near, far, g_far)) =
                hidden_pair(p, eq, (l_in, gl_in, dl_in), (l_out, g, d), stats)
            {
                left = Some((far, g_far, near, g_near));
            }
            (l_in, gl_in, dl_in) = (l_out, g, d);
        }
        if !first && (right.is_some() || left.is_some()) {
            stats.expansions += 1;
        }
        let start = if first { Some((f0, g0, d0)) } else { None };
        match (right, left) {
            (Some(r), Some(l)) => {
                stats.multi_root += 1;
                let a = polish(p, eq, r, start, stats);
                let b = polish(p, eq, l, start, stats);
                return if (a.force - f0).abs() <= (b.force - f0).abs() {
                    a
                } else {
                    b
                };
            }
            (Some(r), None) => return polish(p, eq, r, start, stats),
            (None, Some(l)) => return polish(p, eq, l, start, stats),
            (None, None) => {}
        }
        if r_in >= bound && l_in <= -bound {
            stats.failures += 1;
            return Solution {
                force: f0,
                residual: g0.abs(),
                converged: false,
            };
        }
        first = false;
        delta *= 4.0;
    }
}

/// Looks for a pair of roots between `inner` and `outer` (each `(F, G, G')`, `G` of the same
/// sign at both): if `|G|` falls going outward at `inner` and rises at `outer`, it has a minimum
/// in between, found by bisection on the slope. Returns the bracket `(near, g_near, far, g_far)`
/// of the first sign change met on the way, the nearer of the pair to `inner`, or `None` if the
/// minimum does not reach zero. Without this the outward search steps over two roots that fall
/// in one interval and returns a farther root.
fn hidden_pair(
    p: &Params,
    eq: &ForceEquation,
    inner: (f64, f64, f64),
    outer: (f64, f64, f64),
    stats: &mut SolverStats,
) -> Option<(f64, f64, f64, f64)> {
    let dir = (outer.0 - inner.0).signum();
    let falling = |g: f64, d: f64| g * d * dir < 0.0;
    if !falling(inner.1, inner.2) || falling(outer.1, outer.2) {
        return None;
    }
    let (mut a, mut ga, mut b) = (inner.0, inner.1, outer.0);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if m == a || m == b {
            break;
        }
        let (g, d) = eq.eval(p, m);
        stats.evaluations += 1;
        if !same_sign(g, ga) {
            return Some((a, ga, m, g));
        }
        if falling(g, d) {
            (a, ga) = (m, g);
        } else {
            b = m;
        }
    }
    None
}

/// Safeguarded Newton inside a sign-change bracket `[lo, hi]`.
fn polish(
    p: &Params,
    eq: &ForceEquation,
    (mut lo, mut glo, mut hi, mut ghi): (f64, f64, f64, f64),
    start: Option<(f64, f64, f64)>,
    stats: &mut SolverStats,
) -> Solution {
    if glo == 0.0 {
        return Solution {
            force: lo,
            residual: 0.0,
            converged: true,
        };
    }
    if ghi == 0.0 {
        return Solution {
            force: hi,
            residual: 0.0,
            converged: true,
        };
    }
    // First iterate: Newton from the previous force when it is an endpoint, else the middle.
    let mut x = match start {
        Some((f0, g0, d0)) => {
            let n = f0 - g0 / d0;
            if n > lo && n < hi {
                stats.newton_steps += 1;
                n
            } else {
                stats.bisections += 1;
                0.5 * (lo + hi)
            }
        }
        None => 0.5 * (lo + hi),
    };
    for _ in 0..200 {
        let (g, d) = eq.eval(p, x);
        stats.evaluations += 1;
        if g.abs() <= RESIDUAL_TOL * (1.0 + x.abs()) {
            return Solution {
                force: x,
                residual: g.abs(),
                converged: true,
            };
        }
        if same_sign(g, glo) {
            (lo, glo) = (x, g);
        } else {
            (hi, ghi) = (x, g);
        }
        if hi - lo <= 2.0 * f64::EPSILON * lo.abs().max(hi.abs()).max(1e-300) {
            break;
        }
        let n = x - g / d;
        x = if n > lo && n < hi && n.is_finite() {
            stats.newton_steps += 1;
            n
        } else {
            stats.bisections += 1;
            0.5 * (lo + hi)
        };
    }
    // The bracket has shrunk to adjacent floats: a root to rounding, or a jump of G.
    let (x, g) = if glo.abs() <= ghi.abs() {
        (lo, glo)
    } else {
        (hi, ghi)
    };
    if g.abs() > 1e-9 {
        stats.discontinuities += 1;
    }
    Solution {
        force: x,
        residual: g.abs(),
        converged: true,
    }
}
