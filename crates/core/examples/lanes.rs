//! Would a step that advances `W` independent McMillan runs at once, in vector lanes, be
//! faster than the scalar step? A measurement, not a library change.
//!
//! The scalar step is latency bound (docs/history/benchmarks.md, "Interleaving independent runs
//! does not hide the step's latency"): each Newton iterate waits for the law at the last one. Here
//! the hot path of [`squeal_core::Run::step`] for McMillan's law with the default solver (robust,
//! first-order hold) is written over `[f64; W]` with selects instead of branches, so that the
//! compiler can put the `W` chains side by side in vector registers: the affine update of the
//! propagator, the law on its slip branch (with the library's arctangent table), the first
//! evaluation at the previous force, the certificate of `solver::slip_lipschitz` and the
//! certified Newton iterates. The arithmetic of every lane is the scalar code's, operation for
//! operation (no fused multiply-adds: Rust does not contract them), so a lane's result can be
//! the same bits.
//!
//! A lane whose step leaves that path (an evaluation off the slip branch, a zero acceleration,
//! a certificate that fails, Newton leaving its interval) is stepped by the library's scalar
//! [`Stepper::step`] from the same sample, and counted: that is the fall-back a lane stepper
//! would need. Every lane is then compared with a scalar [`Run`] from the same sample, bit for
//! bit, after all steps.
//!
//! Two situations, Table 1 at `nu = 1e-3`: starts inside the unstable cycle (every step on the
//! slip branch), and states on the stick-slip band (samples of the run from rest after its
//! transient), where the quasi-static branch and the fall-back search occur.
//!
//! `cargo run --release -p squeal-core --example lanes -- [STEPS]` (default 400,000 steps a
//! state; the same with `RUSTFLAGS="-C target-cpu=native"` for the wider vectors).

use std::f64::consts::{FRAC_1_PI, FRAC_2_PI, FRAC_PI_2};
use std::hint::black_box;
use std::time::Instant;

use squeal_core::atan::{self, FIRST, FRAC_PI_2_LO, NODES};
use squeal_core::solver::SolverKind;
use squeal_core::{
    FrictionLaw, Params, Propagator, Run, Sample, Scheme, SolverConfig, SolverStats, State, Stepper,
};

/// One value per lane.
type L<const W: usize> = [f64; W];

/// Residual below which `G(F)` counts as zero: `solver::RESIDUAL_TOL` (private there).
const RESIDUAL_TOL: f64 = 4.0 * f64::EPSILON;
/// Largest certified Lipschitz bound accepted by Newton: `solver::CERTIFIED_K`.
const CERTIFIED_K: f64 = 0.9;
/// The certificate's relative margin: `solver::slip_lipschitz`'s `MARGIN`.
const MARGIN: f64 = 1.0 + 1e-9;
/// Newton iterates the certified path allows: `solver::certified_newton`'s loop.
const NEWTON_CAP: usize = 16;
/// Repetitions of each timing (scalar and lanes alternating); the least time is reported.
const REPEATS: usize = 3;

/// The step's constants, computed as [`Stepper::new`] computes them for the first-order hold
/// (checked against [`Stepper::equation`] in [`Coeffs::new`]).
#[derive(Clone, Copy)]
struct Coeffs {
    c11: f64,
    c12: f64,
    c21: f64,
    c22: f64,
    w_x0: f64,
    w_x1: f64,
    w_v0: f64,
    w_v1: f64,
    qa: f64,
    lambda: f64,
    nu: f64,
    tau: f64,
    /// `law.bound() * (1 + 1e-12)`, the clamp of the previous force in `solve_robust`.
    bound: f64,
    dt: f64,
}

impl Coeffs {
    fn new(st: &Stepper) -> Coeffs {
        let p = st.params();
        assert!(st.scheme() == Scheme::Foh && st.solver().kind == SolverKind::Robust);
        assert!(p.kind() == FrictionLaw::McMillan && !st.locates_stick());
        let c = Propagator::new(p.nu, st.dt()).expect("the stepper's own step");
        let (w_x1, w_v1) = (1.0 - c.c11 - c.q1, -c.c21 - c.q2);
        let k = Coeffs {
            c11: c.c11,
            c12: c.c12,
            c21: c.c21,
            c22: c.c22,
            w_x0: c.q1,
            w_x1,
            w_v0: c.q2,
            w_v1,
            qa: 1.0 - 2.0 * p.nu * w_v1 - w_x1,
            lambda: p.lambda,
            nu: p.nu,
            tau: st.law().tau().expect("McMillan's law has a surface time"),
            bound: st.law().bound() * (1.0 + 1e-12),
            dt: st.dt(),
        };
        // The equation of a step, ours against the library's, bit for bit.
        let s = Sample {
            t: 0.0,
            x: 0.7,
            v: -0.3,
            a: 0.1,
            force: 0.9,
        };
        let eq = st.equation(&s);
        let (pv, pa) = k.free_equation(s.x, s.v, s.force);
        assert_eq!(
            [pv, k.w_v1, pa, k.qa].map(f64::to_bits),
            [eq.pv, eq.qv, eq.pa, eq.qa].map(f64::to_bits)
        );
        k
    }

    /// `(pv, pa)` of the step from `(x, v, F)` (`Stepper::free` and `equation_from`).
    #[inline(always)]
    fn free_equation(&self, x: f64, v: f64, force: f64) -> (f64, f64) {
        let (x_free, v_free) = self.free(x, v, force);
        (v_free - self.lambda, -2.0 * self.nu * v_free - x_free)
    }

    #[inline(always)]
    fn free(&self, x: f64, v: f64, force: f64) -> (f64, f64) {
        (
            self.c11 * x + self.c12 * v + self.w_x0 * force,
            self.c21 * x + self.c22 * v + self.w_v0 * force,
        )
    }
}

/// One value per lane. Every operation is a loop over the lanes with nothing else in it, so
/// that the compiler makes it one vector instruction (or two, or four, by the target's width).
#[derive(Clone, Copy)]
struct V<const W: usize>(L<W>);

/// A lane mask: all ones or all zeros per lane (selects are bit operations).
#[derive(Clone, Copy)]
struct M<const W: usize>([u64; W]);

macro_rules! lane_op {
    ($trait:ident, $f:ident, $op:tt) => {
        impl<const W: usize> std::ops::$trait for V<W> {
            type Output = V<W>;
            #[inline(always)]
            fn $f(self, o: V<W>) -> V<W> {
                let mut r = [0.0; W];
                for i in 0..W {
                    r[i] = self.0[i] $op o.0[i];
                }
                V(r)
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl<const W: usize> std::ops::Neg for V<W> {
    type Output = V<W>;
    #[inline(always)]
    fn neg(self) -> V<W> {
        self.map(|x| -x)
    }
}

macro_rules! lane_cmp {
    ($f:ident, $op:tt) => {
        #[inline(always)]
        fn $f(self, o: V<W>) -> M<W> {
            let mut r = [0u64; W];
            for i in 0..W {
                r[i] = if self.0[i] $op o.0[i] { !0 } else { 0 };
            }
            M(r)
        }
    };
}

impl<const W: usize> V<W> {
    #[inline(always)]
    fn splat(x: f64) -> V<W> {
        V([x; W])
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> V<W> {
        let mut r = [0.0; W];
        for (i, r) in r.iter_mut().enumerate() {
            *r = f(self.0[i]);
        }
        V(r)
    }
    #[inline(always)]
    fn abs(self) -> V<W> {
        self.map(f64::abs)
    }
    #[inline(always)]
    fn max(self, o: V<W>) -> V<W> {
        let mut r = [0.0; W];
        for (i, r) in r.iter_mut().enumerate() {
            *r = self.0[i].max(o.0[i]);
        }
        V(r)
    }
    /// The sign of `y` on the magnitude of `self`.
    #[inline(always)]
    fn copysign(self, y: V<W>) -> V<W> {
        let mut r = [0.0; W];
        for (i, r) in r.iter_mut().enumerate() {
            *r = self.0[i].copysign(y.0[i]);
        }
        V(r)
    }
    #[inline(always)]
    fn is_finite(self) -> M<W> {
        self.abs().lt(V::splat(f64::INFINITY))
    }
    lane_cmp!(lt, <);
    lane_cmp!(le, <=);
    lane_cmp!(gt, >);
    lane_cmp!(ge, >=);
    lane_cmp!(eq, ==);
}

impl<const W: usize> M<W> {
    #[inline(always)]
    fn and(self, o: M<W>) -> M<W> {
        let mut r = [0u64; W];
        for (i, r) in r.iter_mut().enumerate() {
            *r = self.0[i] & o.0[i];
        }
        M(r)
    }
    #[inline(always)]
    fn or(self, o: M<W>) -> M<W> {
        let mut r = [0u64; W];
        for (i, r) in r.iter_mut().enumerate() {
            *r = self.0[i] | o.0[i];
        }
        M(r)
    }
    #[inline(always)]
    fn not(self) -> M<W> {
        M(self.0.map(|m| !m))
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0.iter().fold(0, |acc, m| acc | m) != 0
    }
    /// `a` where the mask is set, `b` elsewhere, bit for bit.
    #[inline(always)]
    fn select(self, a: V<W>, b: V<W>) -> V<W> {
        let mut r = [0.0; W];
        for (i, r) in r.iter_mut().enumerate() {
            let m = self.0[i];
            *r = f64::from_bits((a.0[i].to_bits() & m) | (b.0[i].to_bits() & !m));
        }
        V(r)
    }
}

/// `atan_ratio(y, x)` of `squeal_core::atan` in every lane: both reductions and both
/// approximations computed and selected, the same operations as `atan_unit`.
#[inline(always)]
fn atan_ratio<const W: usize>(y: V<W>, x: V<W>) -> V<W> {
    const ROUND: f64 = 4_503_599_627_370_496.0; // 2^52, as in atan_unit
    let s = V::splat;
    let n = y.abs();
    let small = n.le(x);
    // The operands selected, then one division: the same quotient as either branch.
    let t = small.select(n, x) / small.select(x, n);
    let sum = t * s(NODES as f64) + s(ROUND);
    let mut k = [0usize; W];
    for (i, k) in k.iter_mut().enumerate() {
        *k = ((sum.0[i].to_bits() & 0x1ff) as usize).min(NODES);
    }
    let z = t * t;
    let z2 = z * z;
    let lo = s(-1.0 / 3.0) + z * s(1.0 / 5.0) + z2 * s(-1.0 / 7.0);
    let hi = s(1.0 / 9.0) + z * s(-1.0 / 11.0) + z2 * s(1.0 / 13.0);
    let series = t + t * z * (lo + (z2 * z) * hi);
    // The node's coefficients, gathered lane by lane.
    let table = atan::table();
    let c = |j: usize| {
        let mut r = [0.0; W];
        for i in 0..W {
            r[i] = table[k[i]][j];
        }
        V(r)
    };
    let h = t - (sum - s(ROUND)) * s(1.0 / NODES as f64);
    let h2 = h * h;
    let p01 = c(1) + c(2) * h;
    let p23 = c(3) + c(4) * h;
    let p45 = c(5) + c(6) * h;
    let node = c(0) + h * (p01 + h2 * (p23 + h2 * p45));
    let mut near_zero = [0u64; W];
    for i in 0..W {
        near_zero[i] = if k[i] < FIRST { !0 } else { 0 };
    }
    let u = M(near_zero).select(series, node);
    let r = small.select(u, s(FRAC_PI_2) - (u - s(FRAC_PI_2_LO)));
    r.copysign(y)
}

/// `G`, `G'` at `f` in every lane (`ForceEquation::eval`), with whether the law was on its
/// slip branch there (`a != 0` and `s v < 0` or `s v > 2 |a| tau`; `mcmillan_k`'s formulas).
struct Points<const W: usize> {
    g: V<W>,
    d: V<W>,
    slip: M<W>,
}

#[inline(always)]
fn eval<const W: usize>(k: &Coeffs, pv: V<W>, pa: V<W>, f: V<W>) -> Points<W> {
    let s = V::splat;
    let tau = s(k.tau);
    let v = pv + s(k.w_v1) * f;
    let a = pa + s(k.qa) * f;
    let b = a.abs() * tau;
    let sg = a.gt(s(0.0)).select(s(1.0), s(-1.0));
    let den1 = b * b + v * v;
    let f1 = s(-FRAC_2_PI) * atan_ratio(v, b);
    let f1_dv = s(-FRAC_2_PI) * b / den1;
    let f1_da = s(FRAC_2_PI) * v * sg * tau / den1;
    let sv = sg * v;
    let d = v - a * tau;
    let f2 = -b / d;
    let dv = f1_dv + b / (d * d);
    let da = f1_da - sg * tau / d - b * tau / (d * d);
    let on_slip = sv.lt(s(0.0)).or(sv.gt(s(2.0) * b));
    Points {
        g: f1 + f2 - f,
        d: dv * s(k.w_v1) + da * s(k.qa) - s(1.0),
        slip: a.eq(s(0.0)).not().and(on_slip),
    }
}

/// `is_zero` of the solver.
#[inline(always)]
fn is_zero<const W: usize>(g: V<W>, f: V<W>) -> M<W> {
    g.abs()
        .le(V::splat(RESIDUAL_TOL) * (V::splat(1.0) + f.abs()))
}

/// Whether `solver::slip_lipschitz` certifies `[f0 - w, f0 + w]` with `K < CERTIFIED_K`.
#[inline(always)]
fn certified<const W: usize>(k: &Coeffs, pv: V<W>, pa: V<W>, f0: V<W>, w: V<W>) -> M<W> {
    let s = V::splat;
    let (qv, qa, tau) = (s(k.w_v1), s(k.qa), s(k.tau));
    let (vc, ac) = (pv + qv * f0, pa + qa * f0);
    let (dv, da) = (qv.abs() * w, qa.abs() * w);
    let (vlo, vhi, alo, ahi) = (vc - dv, vc + dv, ac - da, ac + da);
    let finite = vlo.is_finite().and(vhi.is_finite());
    let finite = finite.and(alo.is_finite()).and(ahi.is_finite());
    let (pos, neg) = (vlo.gt(s(0.0)), vhi.lt(s(0.0)));
    let v_min = pos.select(vlo, -vhi) / s(MARGIN);
    let a_max = alo.abs().max(ahi.abs()) * s(MARGIN);
    let slip = v_min.gt(s(2.0 * k.tau) * a_max);
    let slip = slip.or(alo.ge(s(0.0)).and(neg));
    let slip = slip.or(ahi.le(s(0.0)).and(pos));
    let bound_v = s(FRAC_1_PI + 2.0) / v_min;
    let bound_a = s(FRAC_2_PI + 4.0) * tau / v_min;
    let kk = bound_v * qv.abs() + bound_a * qa.abs();
    finite.and(pos.or(neg)).and(slip).and(kk.lt(s(CERTIFIED_K)))
}

/// `solve_robust` with its certified Newton, for the lanes that stay on that path: the
/// forces, the residuals `|G|` there, and the mask of the lanes that left it (the scalar
/// fall-back's).
#[inline(always)]
fn solve<const W: usize>(k: &Coeffs, pv: V<W>, pa: V<W>, prev: V<W>) -> (V<W>, V<W>, M<W>) {
    let s = V::splat;
    let clamped = prev.max(s(-k.bound)).map(|f| f.min(k.bound));
    let f0 = prev.is_finite().select(clamped, s(0.0));
    let p0 = eval(k, pv, pa, f0);
    let delta = -p0.g / p0.d;
    let w = s(2.0) * delta.abs();
    let cert = certified(k, pv, pa, f0, w);
    let (lo, hi) = (f0 - w, f0 + w);
    let zero0 = p0.slip.and(is_zero(p0.g, f0));
    let newton = p0.g.is_finite().and(delta.is_finite());
    let newton = newton.and(delta.eq(s(0.0)).not()).and(cert);
    let mut active = p0.slip.and(zero0.not()).and(newton);
    let mut fallback = p0.slip.not().or(zero0.not().and(newton.not()));
    let (mut force, mut res) = (f0, p0.g.abs());
    let mut x = f0 + delta;
    for _ in 0..NEWTON_CAP {
        if !active.any() {
            break;
        }
        let p = eval(k, pv, pa, x);
        let n = x - p.g / p.d;
        let zero = active.and(p.slip).and(is_zero(p.g, x));
        force = zero.select(x, force);
        res = zero.select(p.g.abs(), res);
        let inside = n.gt(lo).and(n.lt(hi)).and(n.eq(x).not());
        let leave = active.and(p.slip.not().or(zero.not().and(inside.not())));
        fallback = fallback.or(leave);
        active = active.and(zero.not()).and(leave.not());
        x = active.select(n, x);
    }
    (force, res, fallback.or(active))
}

/// `W` runs stepped together.
struct Lanes<const W: usize> {
    x: L<W>,
    v: L<W>,
    a: L<W>,
    force: L<W>,
    max_residual: L<W>,
    t: f64,
    steps: u64,
    /// Lane-steps the scalar fall-back took.
    fallbacks: u64,
    /// Steps of all lanes in which at least one lane fell back.
    mixed: u64,
    stats: SolverStats,
}

impl<const W: usize> Lanes<W> {
    fn new(samples: &[Sample; W]) -> Lanes<W> {
        Lanes {
            x: samples.map(|s| s.x),
            v: samples.map(|s| s.v),
            a: samples.map(|s| s.a),
            force: samples.map(|s| s.force),
            max_residual: [0.0; W],
            t: 0.0,
            steps: 0,
            fallbacks: 0,
            mixed: 0,
            stats: SolverStats::default(),
        }
    }

    fn sample(&self, i: usize) -> Sample {
        Sample {
            t: self.t,
            x: self.x[i],
            v: self.v[i],
            a: self.a[i],
            force: self.force[i],
        }
    }

    /// One step of every lane (`Run::step`'s state and largest residual).
    #[inline(never)]
    fn step(&mut self, k: &Coeffs, st: &Stepper) {
        let s = V::splat;
        let (x, v, force) = (V(self.x), V(self.v), V(self.force));
        let x_free = s(k.c11) * x + s(k.c12) * v + s(k.w_x0) * force;
        let v_free = s(k.c21) * x + s(k.c22) * v + s(k.w_v0) * force;
        let pv = v_free - s(k.lambda);
        let pa = s(-2.0 * k.nu) * v_free - x_free;
        let (f, res, fallback) = solve(k, pv, pa, force);
        let x = x_free + s(k.w_x1) * f;
        let v = v_free + s(k.w_v1) * f;
        let a = f - s(2.0 * k.nu) * v - x;
        let keep = fallback;
        let m = V(self.max_residual).max(res);
        if keep.any() {
            self.mixed += 1;
            self.fall_back(st, keep);
        }
        self.x = keep.select(V(self.x), x).0;
        self.v = keep.select(V(self.v), v).0;
        self.a = keep.select(V(self.a), a).0;
        self.force = keep.select(V(self.force), f).0;
        self.max_residual = keep.select(V(self.max_residual), m).0;
        self.steps += 1;
        self.t = self.steps as f64 * k.dt;
    }

    /// The library's scalar step for the lanes in `lanes`.
    #[cold]
    fn fall_back(&mut self, st: &Stepper, lanes: M<W>) {
        for i in 0..W {
            if lanes.0[i] != 0 {
                let (n, sol) = st.step(&self.sample(i), &mut self.stats);
                self.fallbacks += 1;
                (self.x[i], self.v[i], self.a[i], self.force[i]) = (n.x, n.v, n.a, n.force);
                self.max_residual[i] = self.max_residual[i].max(sol.residual);
            }
        }
    }
}

/// One timing of both ways on the same states: (scalar ns/step, lanes ns/step, lanes after
/// the steps, the scalar runs' ends and their robust solver's fall-backs).
fn time_once<const W: usize>(
    st: &Stepper,
    k: &Coeffs,
    starts: &[Sample; W],
    steps: usize,
) -> (f64, f64, Lanes<W>, Vec<(Sample, f64)>, u64) {
    let t0 = Instant::now();
    let mut ends = Vec::with_capacity(W);
    let mut fallbacks = 0;
    for s in starts {
        let mut run = Run::from_sample(st, *s);
        for _ in 0..steps {
            run.step();
        }
        ends.push((*run.sample(), run.max_residual()));
        fallbacks += run.stats().fallbacks;
    }
    let scalar = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let mut lanes = Lanes::new(starts);
    for _ in 0..steps {
        lanes.step(k, st);
    }
    black_box(&lanes.x);
    let lane = t0.elapsed().as_secs_f64();
    let per = |s: f64| s / (W * steps) as f64 * 1e9;
    (per(scalar), per(lane), lanes, ends, fallbacks)
}

/// Times both ways `REPEATS` times, checks the lanes against the scalar runs and prints a row.
fn measure<const W: usize>(
    st: &Stepper,
    k: &Coeffs,
    what: &str,
    starts: &[Sample; W],
    steps: usize,
) {
    let (mut scalar, mut lane) = (f64::INFINITY, f64::INFINITY);
    let mut all = Vec::new();
    let mut last = None;
    for _ in 0..REPEATS {
        let (s, l, lanes, ends, fb) = time_once(st, k, starts, steps);
        (scalar, lane) = (scalar.min(s), lane.min(l));
        all.push(format!("{s:.1}/{l:.1}"));
        last = Some((lanes, ends, fb));
    }
    let (lanes, ends, scalar_fallbacks) = last.expect("REPEATS > 0");
    let differ = (0..W)
        .filter(|&i| {
            let (e, r) = ends[i];
            let got = lanes.sample(i);
            [got.x, got.v, got.a, got.force, lanes.max_residual[i]].map(f64::to_bits)
                != [e.x, e.v, e.a, e.force, r].map(f64::to_bits)
        })
        .count();
    let lane_steps = (W * steps) as f64;
    println!(
        "| {what} | {W} | {scalar:.1} | {lane:.1} | {:.2} | {:.2}% | {:.2}% | {:.1}% | {differ} of {W} | {} |",
        scalar / lane,
        100.0 * lanes.fallbacks as f64 / lane_steps,
        100.0 * scalar_fallbacks as f64 / lane_steps,
        100.0 * lanes.mixed as f64 / steps as f64,
        all.join(", ")
    );
}

/// `n` samples of the run from `ic`: after `skip` steps, then every `every` steps.
fn samples<const W: usize>(st: &Stepper, ic: State, skip: usize, every: usize) -> [Sample; W] {
    let mut run = Run::new(st, ic);
    run.by_ref().take(skip).for_each(drop);
    std::array::from_fn(|_| {
        let s = *run.sample();
        run.by_ref().take(every).for_each(drop);
        s
    })
}

/// Starts inside the unstable cycle (it crosses the section at about 0.37 from the fixed point
/// (1, 0), docs/history/benchmarks.md "Scan speed with early stopping"), at radii 0.05-0.26, their
/// initial force solved by the library.
fn inside<const W: usize>(st: &Stepper) -> [Sample; W] {
    std::array::from_fn(|i| {
        let (r, th) = (0.05 + 0.03 * i as f64, 0.7 * i as f64);
        *Run::new(
            st,
            State {
                x: 1.0 + r * th.cos(),
                v: r * th.sin(),
            },
        )
        .sample()
    })
}

fn both<const W: usize>(st: &Stepper, k: &Coeffs, steps: usize) {
    measure::<W>(st, k, "inside the cycle", &inside(st), steps);
    // The run from rest squeals (Fig. 9); after t = 200 it is on the band. Samples 1,237
    // steps apart (not a multiple of the period's steps) take it at different phases.
    let band = samples::<W>(st, State { x: 0.0, v: 0.0 }, 40_000, 1_237);
    measure::<W>(st, k, "stick-slip band", &band, steps);
}

fn main() {
    let steps: usize = match std::env::args().nth(1).map(|s| s.parse()) {
        None => 400_000,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => panic!("expected the number of steps per state, a positive integer"),
    };
    let params = Params::paper(FrictionLaw::McMillan, 1e-3);
    let st = Stepper::new(params, squeal_core::defaults::DT, SolverConfig::default())
        .expect("Table 1's parameters are valid");
    let k = Coeffs::new(&st);
    println!("{steps} steps a state; ns per state-step, least of {REPEATS} (all: scalar/lanes)\n");
    println!(
        "| states | W | scalar | lanes | ratio | lane fall-backs | scalar fall-backs | steps with a fall-back | lanes differing | all |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---|---|");
    both::<4>(&st, &k, steps);
    both::<8>(&st, &k, steps);
}
