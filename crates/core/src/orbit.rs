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
//!
//! **A band of the turn map** ([`certify_band`]). Where a run sticks (or nearly sticks, as
//! under McMillan's laws), the stick phase forgets where the turn began: the exact turn map
//! is nearly flat, and what the step adds is a sawtooth of the stick's phase against the
//! step grid (at Fig. 9, maxima scattered over 0.02 around 4.07, with excursions to 4.43,
//! at dt = 0.005). Such maxima never converge, and three samples are in no order; yet they
//! stay in a band, which is what "it lasts" needs. The band certificate takes the hull
//! `[lo, hi]` of the run's last [`WINDOW`] maxima, stationary (the later half inside the
//! earlier half's hull widened by half its width), and starts from `J = [lo - w, hi + w]`
//! (`w` its width). It runs one turn from each of [`BAND_SAMPLES`] evenly spaced points of
//! `J`, each with one root of the force at its start (so `(x, 0)` is the whole state), at
//! `dt` and at `dt / 2`. The premise, sampled: between two samples the map strays beyond
//! their images by no more than `e`, the larger of the run's own scatter `w` and the largest
//! deviation of an image from the chord of its neighbours' images (a smooth part bends by
//! less than that, and the step's sawtooth is what the deviations measure). So the images'
//! hull widened by `e`, inside `J` by the margin at both steps, means `J` is mapped into
//! itself: the run, whose maxima lie in `J`, never leaves it. Where it does not fit, the side
//! that failed grows past the images by half `J`'s width, [`BAND_GROWTHS`] intervals at
//! most. `J` must lie above the caller's floor ([`band_floor`]: the fixed point's radius
//! where steady slip attracts), so the band is no spiral onto it. An oscillation whose band
//! is certified lasts for good; its period and shape come from the run's own turns, its
//! "multiplier" is the secant slope over `J`. Checked against the run itself in
//! crates/core/tests/model/orbit.rs (every maximum to t = 5000 inside `J`, at two steps).

use serde::Serialize;

use crate::run::{Run, Step};
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

/// What a certificate proved about the turn map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum OrbitKind {
    /// The maxima converged and an interval around them is mapped into itself, monotone:
    /// an attracting periodic orbit ([`certify`]).
    Periodic,
    /// The maxima stay scattered (the step's sawtooth on a sticking loop, or an irregular
    /// motion) inside an interval mapped into itself ([`certify_band`]): an attracting band
    /// of the turn map, which the run never leaves.
    Band,
}

/// A certified attractor of the turn map: a periodic orbit, or a band of maxima.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Orbit {
    /// Which certificate holds.
    pub kind: OrbitKind,
    /// The maximum of `x` the certificate is centred on.
    pub x_max: f64,
    /// The half-width `d` of the interval mapped into itself.
    pub half_width: f64,
    /// The period of one turn (nondimensional).
    pub period: f64,
    /// The Floquet multiplier `T'` at `dt`, and at `dt / 2` (for a band: the secant slope
    /// of `T` over the interval).
    pub multiplier: [f64; 2],
    /// The width of the sampled images of the interval at `dt` and at `dt / 2`: how far the
    /// maxima scatter (0 for a periodic orbit, where it is not measured).
    pub spread: [f64; 2],
}

impl Orbit {
    /// Words for reports.
    pub fn words(&self) -> String {
        match self.kind {
            OrbitKind::Periodic => format!(
                "certified as a periodic orbit (multiplier {:.4})",
                self.multiplier[0]
            ),
            OrbitKind::Band => format!(
                "certified as a band of its maxima (x_max in {:.6} +- {:.2e}, scattered over \
                 {:.2e} at dt and {:.2e} at dt/2)",
                self.x_max, self.half_width, self.spread[0], self.spread[1]
            ),
        }
    }
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
        kind: OrbitKind::Periodic,
        x_max: c,
        half_width: d,
        period,
        multiplier,
        spread: [0.0; 2],
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

/// Points of `J` a band certificate runs a turn from, at each step.
pub const BAND_SAMPLES: usize = 9;

/// Maxima of `x` a [`OrbitWatch`] keeps: the band certificate's window.
pub const WINDOW: usize = 16;

/// Certificates a [`OrbitWatch`] tries, at most, before the run is left to its horizon.
pub const TRIES: u32 = 8;

/// How close two successive maxima of `x` must be (relative) before the periodic
/// certificate is tried.
pub const CONVERGED: f64 = 1e-6;

/// Intervals a band certificate tries, at most, each grown from the last one's images.
pub const BAND_GROWTHS: usize = 8;

/// Certifies the band of maxima `[lo, hi]` (a run's stationary window, see the module's
/// argument) with `steppers` at `dt` and `dt / 2`, each turn run to at most `t_turn`; `J`
/// must lie above `above`. `J` starts as the window widened by its width at both ends; where
/// its images do not fit, it grows to hold them (with their jumps and the margin), at most
/// [`BAND_GROWTHS`] intervals in all. Returns the band (`None`: not certified) and the
/// solver's counts over its turns.
pub fn certify_band(
    steppers: (&Stepper, &Stepper),
    (lo, hi): (f64, f64),
    above: f64,
    t_turn: f64,
) -> (Option<Orbit>, SolverStats) {
    let mut stats = SolverStats::default();
    let w = (hi - lo).max(1e-9 * (1.0 + hi.abs()));
    let (mut a, mut b) = (lo - w, hi + w);
    let scatter = w;
    for _ in 0..BAND_GROWTHS {
        if a <= above {
            break;
        }
        let Some(images) = band_images(steppers, (a, b), t_turn, &mut stats) else {
            break;
        };
        let m = MARGIN * 0.5 * (b - a);

        let e = images.jump.max(scatter);
        let (ylo, yhi) = (images.lo - e, images.hi + e);
        if ylo >= a + m && yhi <= b - m {
            let orbit = Orbit {
                kind: OrbitKind::Band,
                x_max: 0.5 * (a + b),
                half_width: 0.5 * (b - a),
                period: images.period,
                multiplier: images.slope,
                spread: images.spread,
            };
            return (Some(orbit), stats);
        }
        // Grow each side that does not hold the images with their excursions, past them by
        // half the width (room for the margin, and for images that grow with the interval).
        let grow = (b - a) / 2.0;
        if ylo < a + m {
            a = ylo - grow;
        }
        if yhi > b - m {
            b = yhi + grow;
        }
    }
    (None, stats)
}

/// The images of [`BAND_SAMPLES`] evenly spaced points of `[a, b]` by one turn at `dt` and
/// at `dt / 2`.
struct Images {
    /// Their hull over both steps.
    lo: f64,
    hi: f64,
    /// The largest deviation of an image from the chord of its neighbours' images, over
    /// both steps.
    jump: f64,
    /// The secant slope over `[a, b]` at each step.
    slope: [f64; 2],
    /// The width of the images at each step.
    spread: [f64; 2],
    /// The mean period of the turns at `dt`.
    period: f64,
}

/// [`Images`] of `[a, b]` (`None`: a turn failed, or started where the force has several
/// roots).
fn band_images(
    (dt, half): (&Stepper, &Stepper),
    (a, b): (f64, f64),
    t_turn: f64,
    stats: &mut SolverStats,
) -> Option<Images> {
    let mut out = Images {
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
        jump: 0.0,
        slope: [0.0; 2],
        spread: [0.0; 2],
        period: 0.0,
    };
    for (k, st) in [dt, half].into_iter().enumerate() {
        let mut images = [0.0; BAND_SAMPLES];
        for (i, y) in images.iter_mut().enumerate() {
            let x = a + (b - a) * i as f64 / (BAND_SAMPLES - 1) as f64;
            let mut run = Run::new(st, State { x, v: 0.0 });
            let one_root = run.stats().multi_root == 0;
            let turned = turn_of(&mut run, t_turn);
            stats.merge(run.stats());
            let (xm, t, _) = turned.filter(|_| one_root)?;
            *y = xm;
            if k == 0 {
                out.period += t / BAND_SAMPLES as f64;
            }
        }
        // The largest deviation of an image from the chord of its neighbours' images: the
        // step's sawtooth (or a bend of the map) at the samples' spacing.
        let jump = images
            .windows(3)
            .map(|p| (p[1] - 0.5 * (p[0] + p[2])).abs())
            .fold(0.0, f64::max);
        let (ylo, yhi) = images
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &y| {
                (l.min(y), h.max(y))
            });
        out.lo = out.lo.min(ylo);
        out.hi = out.hi.max(yhi);
        out.jump = out.jump.max(jump);
        out.slope[k] = (images[BAND_SAMPLES - 1] - images[0]) / (b - a);
        out.spread[k] = yhi - ylo;
    }
    Some(out)
}

/// The least `x` a band certificate's interval may reach for a model with parameters `p`
/// whose fixed point's radius is `fp_radius`: above that radius where steady slip `attracts`
/// (a spiral onto it is no band), above the fixed point's `x` where it does not (the slip
/// oscillation about it may be smaller than the radius).
pub fn band_floor(p: &crate::Params, fp_radius: f64, attracts: bool) -> f64 {
    let x = p.fixed_point().x;
    match attracts {
        true => x + fp_radius,
        false => x,
    }
}

/// Watches a run's maxima of `x` for an attractor it can certify ([`certify`] where
/// successive maxima converge, [`certify_band`] where a stationary window of them does
/// not): at most [`TRIES`] certificates, the band's only once a fresh window has passed
/// since the last try. Maxima where the step saw several roots of the force restart the
/// window (their `(x, 0)` is not the whole state).
#[derive(Debug)]
pub struct OrbitWatch<'s> {
    half: &'s Stepper,
    above: f64,
    maxima: std::collections::VecDeque<(f64, f64)>,
    fresh: usize,
    tries: u32,
    multi_root: u64,
    stats: SolverStats,
}

impl<'s> OrbitWatch<'s> {
    /// A watch that certifies with `half` (the stepper at `dt / 2`) bands above `above`.
    pub fn new(half: &'s Stepper, above: f64) -> OrbitWatch<'s> {
        OrbitWatch {
            half,
            above,
            maxima: std::collections::VecDeque::with_capacity(WINDOW),
            fresh: 0,
            tries: 0,
            multi_root: 0,
            stats: SolverStats::default(),
        }
    }

    /// Observes a step of `run`; the certified attractor once a certificate holds. `try_now`
    /// false records the maximum without trying (the caller's own premise not yet met).
    pub fn observe(&mut self, run: &Run, step: &Step, try_now: bool) -> Option<Orbit> {
        let multi_root = run.stats().multi_root;
        let one_root = multi_root == self.multi_root;
        self.multi_root = multi_root;
        let (t, x, a) = maximum(&step.prev, &step.next)?;
        if !one_root {
            self.maxima.clear();
            self.fresh = 0;
            return None;
        }
        let last = self.maxima.back().map_or(f64::NAN, |m| m.1);
        let t_turn = 4.0 * self.maxima.back().map_or(f64::NAN, |m| t - m.0);
        if self.maxima.len() == WINDOW {
            self.maxima.pop_front();
        }
        self.maxima.push_back((t, x));
        self.fresh += 1;
        if !try_now || self.tries >= TRIES || !t_turn.is_finite() {
            return None;
        }
        let steppers = (run.stepper(), self.half);
        if (x - last).abs() <= CONVERGED * (1.0 + x.abs()) {
            self.tries += 1;
            let (orbit, stats) = certify(steppers, (x, a, last), t_turn);
            self.stats.merge(&stats);
            return orbit;
        }
        let (lo, hi) = self.stationary()?;
        self.tries += 1;
        self.fresh = 0;
        let t_turn = 4.0
            * self
                .maxima
                .iter()
                .zip(self.maxima.iter().skip(1))
                .map(|(a, b)| b.0 - a.0)
                .fold(0.0, f64::max);
        let (orbit, stats) = certify_band(steppers, (lo, hi), self.above, t_turn);

        self.stats.merge(&stats);
        orbit
    }

    /// The hull of the window where it is full, fresh since the last try and stationary.
    fn stationary(&self) -> Option<(f64, f64)> {
        if self.maxima.len() < WINDOW || self.fresh < WINDOW {
            return None;
        }
        let hull = |it: &mut dyn Iterator<Item = f64>| {
            it.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
                (a.min(y), b.max(y))
            })
        };
        let h = WINDOW / 2;
        let (a0, a1) = hull(&mut self.maxima.iter().take(h).map(|m| m.1));
        let (b0, b1) = hull(&mut self.maxima.iter().skip(h).map(|m| m.1));
        let slack = 0.5 * (a1 - a0);
        (b0 >= a0 - slack && b1 <= a1 + slack).then_some((a0.min(b0), a1.max(b1)))
    }

    /// The solver's counts over the certificates' turns.
    pub fn stats(&self) -> &SolverStats {
        &self.stats
    }
}
