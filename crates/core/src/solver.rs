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
//! * [`SolverKind::Robust`] (default): a true root, the nearest to the previous force (the
//!   model's hysteresis: the force stays on its branch while the branch exists). Two paths:
//!   - *certified Newton* (most steps): from the previous force `F0` with Newton step
//!     `d = -G(F0)/G'(F0)`, the interval `I = [F0 - 2|d|, F0 + 2|d|]` is mapped to boxes of
//!     slip velocity and acceleration. If the whole box lies on the slip branch of the law,
//!     the law's partial derivatives are bounded there by closed forms in `min |v|` (see
//!     [`slip_lipschitz`]), which bounds `|dL/dF| <= K`; with `K < 1`, `G = L - F` is strictly
//!     decreasing on `I`, so `I` holds at most one root and every other root is farther from
//!     `F0` than any point of `I`. Newton iterates that stay in `I` and reach a zero residual
//!     have then found the nearest root: usually 2-3 law evaluations per step.
//!   - *full search* ([`solve_full`]), when the certificate does not hold (quasi-static branch,
//!     slip velocity near zero) or Newton leaves `I`: it brackets outwards from the previous
//!     force in both directions at once (so the first sign change it finds is the nearest one
//!     on either side), then polishes with Newton on the analytic derivative, falling back to
//!     bisection whenever Newton would leave the bracket. All roots lie in `[-B, B]` with
//!     `B = Params::force_bound`, so the search always ends. Counted in
//!     [`SolverStats::fallbacks`].
//!
//! Coulomb's law is set-valued at `v = 0`; its equation is solved in closed form: slip with
//! `F = -sgn v`, or stick with the `F` in `[-1, 1]` that keeps `v = 0`.

use serde::{Deserialize, Serialize};

use crate::friction::{Branch, ForceEval, Law};
use crate::params::FrictionLaw;
use crate::propagator::Scheme;

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
    /// How the force varies over a step (first-order hold by default; zero-order hold is the
    /// paper's scheme).
    #[serde(default)]
    pub scheme: Scheme,
}

impl Default for SolverConfig {
    fn default() -> Self {
        SolverConfig {
            kind: SolverKind::Robust,
            max_iter: crate::defaults::MAX_ITER,
            paper_tol: 1e-12,
            scheme: Scheme::default(),
        }
    }
}

/// What the solver did, summed over steps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct SolverStats {
    /// Implicit solves (steps, plus the initial force).
    pub solves: u64,
    /// Friction-law evaluations (counted in [`ForceEquation::law_at`], the only place the
    /// solvers evaluate the law).
    pub evaluations: u64,
    /// Newton steps taken (robust: certified Newton, and Newton inside a bracket).
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
    /// Coulomb steps that stuck (`v = 0`, force inside `[-1, 1]`); with a law with true stick,
    /// steps that were stuck for any part of their length.
    pub sticks: u64,
    /// Robust solves that could not use certified Newton and ran the full two-sided bracket
    /// search (the certificate did not hold, or Newton left the certified interval).
    #[serde(default)]
    pub fallbacks: u64,
    /// Stick onsets located inside steps (laws with true stick, [`crate::stick`]).
    #[serde(default)]
    pub stick_onsets: u64,
    /// Breakaways located inside steps (laws with true stick).
    #[serde(default)]
    pub breakaways: u64,
    /// Passages through zero slip without sticking (laws with true stick).
    #[serde(default)]
    pub slip_reversals: u64,
    /// Iterations of the event location (false position on the sub-step length).
    #[serde(default)]
    pub event_iterations: u64,
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
        self.fallbacks += o.fallbacks;
        self.stick_onsets += o.stick_onsets;
        self.breakaways += o.breakaways;
        self.slip_reversals += o.slip_reversals;
        self.event_iterations += o.event_iterations;
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
    /// The branch of the law at the returned force (from the evaluation that gave it).
    pub branch: Branch,
}

/// One evaluation of `G` and `G'` at `f`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// The force.
    pub f: f64,
    /// `G(f)`.
    pub g: f64,
    /// `G'(f)`.
    pub d: f64,
    /// Branch of the law at `f`.
    pub branch: Branch,
}

impl ForceEquation {
    /// The law at the state the force `f` gives, counting the evaluation.
    #[inline]
    pub fn law_at(&self, law: &Law, f: f64, stats: &mut SolverStats) -> ForceEval {
        stats.evaluations += 1;
        law.eval(self.pv + self.qv * f, self.pa + self.qa * f)
    }

    /// `G(F)` and `G'(F)` (one counted law evaluation).
    #[inline]
    pub fn eval(&self, law: &Law, f: f64, stats: &mut SolverStats) -> Point {
        let e = self.law_at(law, f, stats);
        Point {
            f,
            g: e.force - f,
            d: e.dv * self.qv + e.da * self.qa - 1.0,
            branch: e.branch,
        }
    }
}

/// Residual below which `G(F)` counts as zero: a few ulps of `F`'s size.
const RESIDUAL_TOL: f64 = 4.0 * f64::EPSILON;

#[inline]
fn is_zero(p: &Point) -> bool {
    p.g.abs() <= RESIDUAL_TOL * (1.0 + p.f.abs())
}

#[inline]
fn root(p: &Point) -> Solution {
    Solution {
        force: p.f,
        residual: p.g.abs(),
        converged: true,
        branch: p.branch,
    }
}

/// Solves one implicit force equation, starting from (and, for the robust solver, nearest
/// to) `f_prev`.
pub fn solve(
    law: &Law,
    cfg: &SolverConfig,
    eq: &ForceEquation,
    f_prev: f64,
    stats: &mut SolverStats,
) -> Solution {
    stats.solves += 1;
    if law.kind() == FrictionLaw::Coulomb {
        return solve_coulomb(eq, f_prev, stats);
    }
    match cfg.kind {
        SolverKind::Paper => solve_paper(law, cfg, eq, f_prev, stats),
        SolverKind::Robust => solve_robust(law, eq, f_prev, stats, true),
    }
}

/// The robust solve without the certified-Newton path: always the full two-sided bracket
/// search. Kept callable so tests can check that the cheaper path returns the same root.
pub fn solve_full(law: &Law, eq: &ForceEquation, f_prev: f64, stats: &mut SolverStats) -> Solution {
    stats.solves += 1;
    if law.kind() == FrictionLaw::Coulomb {
        return solve_coulomb(eq, f_prev, stats);
    }
    solve_robust(law, eq, f_prev, stats, false)
}

fn solve_paper(
    law: &Law,
    cfg: &SolverConfig,
    eq: &ForceEquation,
    f_prev: f64,
    stats: &mut SolverStats,
) -> Solution {
    let mut f = f_prev;
    let mut converged = false;
    for _ in 0..cfg.max_iter {
        stats.iterations += 1;
        let next = eq.law_at(law, f, stats).force;
        let done = (next - f).abs() <= cfg.paper_tol * (1.0 + f.abs());
        f = next;
        if done {
            converged = true;
            break;
        }
    }
    if !converged {
        stats.unconverged += 1;
    }
    // The residual at the returned force: one more evaluation, counted.
    let p = eq.eval(law, f, stats);
    Solution {
        force: f,
        residual: p.g.abs(),
        converged,
        branch: p.branch,
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
                branch: Branch::Coulomb,
            }
        }
        None => {
            stats.failures += 1;
            Solution {
                force: f_prev,
                residual: f64::INFINITY,
                converged: false,
                branch: Branch::Coulomb,
            }
        }
    }
}

#[inline]
fn same_sign(a: f64, b: f64) -> bool {
    (a > 0.0 && b > 0.0) || (a < 0.0 && b < 0.0)
}

/// A bound `K` on `|dL(v(F), a(F))/dF|` for all `F` in `[f0 - w, f0 + w]`, or `None` when
/// that interval is not provably on the slip branch of the law.
///
/// On the slip branch of McMillan's law (`s v < 0` or `s v > 2 |a| tau`, `s = sgn a`) the
/// denominator `d = v - a tau` of `F2 = -|a| tau / d` satisfies `|d| >= |a| tau` and
/// `|d| >= |v| / 2`, and `b / (b^2 + v^2) <= 1 / (2 |v|)`, so
///
/// ```text
/// |dF/dv| <= (1/pi + 2) / |v|,      |dF/da| <= (2/pi + 4) tau / |v|
/// ```
///
/// (the non-hysteretic slip branch, `|v| > |a| tau`, satisfies the same bounds with room to
/// spare). The law is continuous on the slip branch, including across `a = 0` where it takes
/// the Coulomb limit, so these bound its Lipschitz constant along the segment, and
/// `K = bound_v |qv| + bound_a |qa|` with `|v|` at its minimum over the interval.
pub fn slip_lipschitz(law: &Law, eq: &ForceEquation, f0: f64, w: f64) -> Option<f64> {
    let (vc, ac) = (eq.pv + eq.qv * f0, eq.pa + eq.qa * f0);
    let (dv, da) = (eq.qv.abs() * w, eq.qa.abs() * w);
    let (vlo, vhi, alo, ahi) = (vc - dv, vc + dv, ac - da, ac + da);
    if !(vlo.is_finite() && vhi.is_finite() && alo.is_finite() && ahi.is_finite()) {
        return None;
    }
    // A relative margin covers the rounding of v(F), a(F) and of the law's branch test.
    const MARGIN: f64 = 1.0 + 1e-9;
    let v_min = if vlo > 0.0 {
        vlo
    } else if vhi < 0.0 {
        -vhi
    } else {
        return None;
    } / MARGIN;
    let a_max = alo.abs().max(ahi.abs()) * MARGIN;
    // Only McMillan's laws have the slip branch this bound is for (and a surface time).
    let tau = law.tau()?;
    let slip = match law.kind() {
        FrictionLaw::McMillan => {
            v_min > 2.0 * tau * a_max || (alo >= 0.0 && vhi < 0.0) || (ahi <= 0.0 && vlo > 0.0)
        }
        FrictionLaw::McMillanNonHysteretic => v_min > tau * a_max,
        // No bound for any other law: the solver then takes its bracketed path, which is
        // always sound (the bound only certifies the faster Newton path).
        _ => false,
    };
    if !slip {
        return None;
    }
    let bound_v = (std::f64::consts::FRAC_1_PI + 2.0) / v_min;
    let bound_a = (std::f64::consts::FRAC_2_PI + 4.0) * tau / v_min;
    Some(bound_v * eq.qv.abs() + bound_a * eq.qa.abs())
}

/// Largest certified Lipschitz bound accepted by the Newton path (`G' <= K - 1 < 0`).
const CERTIFIED_K: f64 = 0.9;

/// Newton from `start` inside the certified interval `[f0 - w, f0 + w]` (see the module
/// docs); `None` if the certificate does not hold or an iterate leaves the interval.
fn certified_newton(
    law: &Law,
    eq: &ForceEquation,
    start: &Point,
    stats: &mut SolverStats,
) -> Option<Solution> {
    let delta = -start.g / start.d;
    if !delta.is_finite() || delta == 0.0 {
        return None;
    }
    let w = 2.0 * delta.abs();
    if slip_lipschitz(law, eq, start.f, w)? >= CERTIFIED_K {
        return None;
    }
    let (lo, hi) = (start.f - w, start.f + w);
    let mut x = start.f + delta;
    stats.newton_steps += 1;
    for _ in 0..16 {
        let p = eq.eval(law, x, stats);
        if is_zero(&p) {
            return Some(root(&p));
        }
        let n = x - p.g / p.d;
        if !(n > lo && n < hi) || n == x {
            return None;
        }
        x = n;
        stats.newton_steps += 1;
    }
    None
}

fn solve_robust(
    law: &Law,
    eq: &ForceEquation,
    f_prev: f64,
    stats: &mut SolverStats,
    fast: bool,
) -> Solution {
    let bound = law.bound() * (1.0 + 1e-12);
    let f0 = if f_prev.is_finite() {
        f_prev.clamp(-bound, bound)
    } else {
        0.0
    };
    let p0 = eq.eval(law, f0, stats);
    if is_zero(&p0) {
        return root(&p0);
    }
    if !p0.g.is_finite() {
        stats.failures += 1;
        return Solution {
            force: f0,
            residual: f64::INFINITY,
            converged: false,
            branch: p0.branch,
        };
    }
    if fast {
        if let Some(sol) = certified_newton(law, eq, &p0, stats) {
            return sol;
        }
        stats.fallbacks += 1;
    }
    full_search(law, eq, &p0, bound, stats)
}

/// The two-sided outward bracket search from `p0`, then a safeguarded Newton polish.
fn full_search(
    law: &Law,
    eq: &ForceEquation,
    p0: &Point,
    bound: f64,
    stats: &mut SolverStats,
) -> Solution {
    let f0 = p0.f;
    let newton = -p0.g / p0.d;
    let mut delta = if newton.is_finite() && newton != 0.0 {
        (2.0 * newton.abs()).clamp(1e-12, 2.0 * bound)
    } else {
        1e-3
    };
    // Outward search: consecutive intervals on the right [r_in, r_out] and on the left.
    // An interval without a sign change can still hold a pair of roots: `hidden_pair` looks
    // for it when the slopes at the ends say `|G|` has a minimum inside.
    let (mut r_in, mut l_in) = (*p0, *p0);
    let mut first = true;
    loop {
        let r_out = (f0 + delta).min(bound);
        let l_out = (f0 - delta).max(-bound);
        let mut right = None;
        let mut left = None;
        if r_in.f < bound {
            let p = eq.eval(law, r_out, stats);
            if !same_sign(p.g, r_in.g) {
                right = Some((r_in, p));
            } else {
                right = hidden_pair(law, eq, &r_in, &p, stats);
            }
            r_in = p;
        }
        if l_in.f > -bound {
            let p = eq.eval(law, l_out, stats);
            if !same_sign(p.g, l_in.g) {
                left = Some((p, l_in));
            } else if let Some((near, far)) = hidden_pair(law, eq, &l_in, &p, stats) {
                left = Some((far, near));
            }
            l_in = p;
        }
        if !first && (right.is_some() || left.is_some()) {
            stats.expansions += 1;
        }
        let start = if first { Some(p0) } else { None };
        match (right, left) {
            (Some(r), Some(l)) => {
                stats.multi_root += 1;
                let a = polish(law, eq, r, start, stats);
                let b = polish(law, eq, l, start, stats);
                return if (a.force - f0).abs() <= (b.force - f0).abs() {
                    a
                } else {
                    b
                };
            }
            (Some(r), None) => return polish(law, eq, r, start, stats),
            (None, Some(l)) => return polish(law, eq, l, start, stats),
            (None, None) => {}
        }
        if r_in.f >= bound && l_in.f <= -bound {
            stats.failures += 1;
            return Solution {
                force: f0,
                residual: p0.g.abs(),
                converged: false,
                branch: p0.branch,
            };
        }
        first = false;
        delta *= 4.0;
    }
}

/// Looks for a pair of roots between `inner` and `outer` (`G` of the same sign at both): if
/// `|G|` falls going outward at `inner` and rises at `outer`, it has a minimum in between,
/// found by bisection on the slope. Returns the bracket `(near, far)` of the first sign change
/// met on the way, the nearer of the pair to `inner`, or `None` if the minimum does not reach
/// zero. Without this the outward search steps over two roots that fall in one interval and
/// returns a farther root.
fn hidden_pair(
    law: &Law,
    eq: &ForceEquation,
    inner: &Point,
    outer: &Point,
    stats: &mut SolverStats,
) -> Option<(Point, Point)> {
    let dir = (outer.f - inner.f).signum();
    let falling = |p: &Point| p.g * p.d * dir < 0.0;
    if !falling(inner) || falling(outer) {
        return None;
    }
    let (mut a, mut b) = (*inner, outer.f);
    for _ in 0..200 {
        let m = 0.5 * (a.f + b);
        if m == a.f || m == b {
            break;
        }
        let p = eq.eval(law, m, stats);
        if !same_sign(p.g, a.g) {
            return Some((a, p));
        }
        if falling(&p) {
            a = p;
        } else {
            b = m;
        }
    }
    None
}

/// Safeguarded Newton inside a sign-change bracket `(lo, hi)` (in either order of `f`; the
/// first is the one with `f` smaller).
fn polish(
    law: &Law,
    eq: &ForceEquation,
    (mut lo, mut hi): (Point, Point),
    start: Option<&Point>,
    stats: &mut SolverStats,
) -> Solution {
    if lo.g == 0.0 {
        return root(&lo);
    }
    if hi.g == 0.0 {
        return root(&hi);
    }
    // First iterate: Newton from the previous force when it is an endpoint, else the middle.
    let mut x = match start {
        Some(p0) => {
            let n = p0.f - p0.g / p0.d;
            if n > lo.f && n < hi.f {
                stats.newton_steps += 1;
                n
            } else {
                stats.bisections += 1;
                0.5 * (lo.f + hi.f)
            }
        }
        None => 0.5 * (lo.f + hi.f),
    };
    for _ in 0..200 {
        let p = eq.eval(law, x, stats);
        if is_zero(&p) {
            return root(&p);
        }
        if same_sign(p.g, lo.g) {
            lo = p;
        } else {
            hi = p;
        }
        if hi.f - lo.f <= 2.0 * f64::EPSILON * lo.f.abs().max(hi.f.abs()).max(1e-300) {
            break;
        }
        let n = x - p.g / p.d;
        x = if n > lo.f && n < hi.f && n.is_finite() {
            stats.newton_steps += 1;
            n
        } else {
            stats.bisections += 1;
            0.5 * (lo.f + hi.f)
        };
    }
    // The bracket has shrunk to adjacent floats: a root to rounding, or a jump of G.
    let best = if lo.g.abs() <= hi.g.abs() { lo } else { hi };
    if best.g.abs() > 1e-9 {
        stats.discontinuities += 1;
    }
    root(&best)
}
