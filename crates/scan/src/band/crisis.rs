//! The fold as the crisis of the stick-slip band along one parameter (the damping or the
//! belt speed): where squeal stops lasting ([`super::Lasting`]), with an uncertainty that
//! covers the step and the band's budget. One search for `squeal critical --crisis`,
//! `critical --fold` and the atlas's fold.
//!
//! **The search.**
//! 1. A coarse scan: the verdict at `coarse + 1` geometric steps over the range
//!    ([`crate::section::coarse_changes`] of "squeal does not last"). A bisection assumes
//!    one change; every change the scan sees is returned, and more than one is for the
//!    caller to say loudly. The fold is the *last* change: above it no coarse value squeals
//!    for good (changes closer together than a step can still hide between two values).
//! 2. Two geometric bisections in the last coarse step where squeal lasts and the first one
//!    above it that is quiet: the last value where squeal lasts and the first where it is
//!    quiet (between them the band's verdict is marginal: undecided). Verdicts are
//!    remembered, so the second bisection starts from the tightest bracket the first left.
//! 3. The uncertainty: the verdicts at that bracket's ends again at `dt / 2` and with the
//!    longer horizon ([`super::Budget::Longer`]); an end where any of the three computations
//!    disagrees is moved outwards (steps of a quarter of the bracket's log-width, doubled
//!    each time, at most to the range's end) until all three agree there. The fold is the middle of that interval, the uncertainty
//!    half its width: every one of the three computations has its last squealing value below
//!    the interval's top and its first quiet value above its bottom, if each changes once
//!    inside it (checked on the shipped chart by `scripts/bench/fold-coverage.sh`).
//! 4. Above the crisis the verdict is not monotone: the stretch of an eighth of a coarse
//!    step above that interval is sampled at the setup's step, and the top raised over any
//!    window there that is not quiet, to where all three agree again ([`clear_above`]).

use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use rayon::prelude::*;

use serde::Serialize;
use squeal_core::{Params, Setup};

use super::{Budget, Lasting, lasting_on, lasting_with};
use crate::error::ScanError;
use crate::section::ReturnCache;
use crate::section::{Change, ParamRange, coarse_changes, geometric_bisection, geometric_steps};
use crate::ulc::CycleSettings;

/// Steps of the coarse scan along the parameter before bisecting (`squeal critical`).
pub const COARSE: usize = 64;

/// One of the computations whose crisis the uncertainty covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Variant {
    /// The setup's step, the standard budget.
    Dt,
    /// Half the step.
    HalfDt,
    /// The setup's step, the longer horizon ([`Budget::Longer`]).
    Longer,
}

impl Variant {
    /// All three.
    pub const ALL: [Variant; 3] = [Variant::Dt, Variant::HalfDt, Variant::Longer];

    /// The verdict at `setup` (the step of [`Variant::Dt`]) with cycle settings `cs`, the
    /// budget of [`Variant::Dt`] and [`Variant::HalfDt`] being `base` (a whole search with
    /// [`Budget::Longer`] as its base is the longer horizon's own crisis, what
    /// `scripts/bench/fold-coverage.sh` checks the uncertainty against).
    pub fn lasting(
        self,
        setup: Setup,
        cs: &CycleSettings,
        base: Budget,
    ) -> Result<Lasting, ScanError> {
        self.lasting_sharing(setup, cs, base, &ReturnCache::default())
    }

    /// [`Variant::lasting`], the verdicts at the setup's step ([`Variant::Dt`],
    /// [`Variant::Longer`]) reading and filling `shared`, the returns of `setup`'s stepper
    /// (the same verdicts, [`crate::section::ReturnCache`]); the one at dt/2 has its own.
    pub fn lasting_sharing(
        self,
        setup: Setup,
        cs: &CycleSettings,
        base: Budget,
        shared: &ReturnCache,
    ) -> Result<Lasting, ScanError> {
        match self {
            Variant::Dt => lasting_on(setup, cs, base, shared),
            Variant::HalfDt => lasting_with(setup.half_dt(), cs, base),
            Variant::Longer => lasting_on(setup, cs, Budget::Longer, shared),
        }
    }
}

/// One [`ReturnCache`] per parameter value: what a verdict function passed to [`crisis_in`]
/// shares between the verdicts at one value ([`Variant::lasting_sharing`]). Behind a lock:
/// [`crisis_in`] runs the verdicts at several values on several threads.
#[derive(Debug, Default)]
pub struct SharedReturns(Mutex<HashMap<u64, Arc<ReturnCache>>>);

impl SharedReturns {
    /// The returns at value `v`.
    pub fn at(&self, v: f64) -> Arc<ReturnCache> {
        let mut m = self.0.lock().unwrap_or_else(|e| e.into_inner());
        m.entry(v.to_bits()).or_default().clone()
    }
}

/// How the search ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CrisisStatus {
    /// Located.
    Found,
    /// Squeal lasts at no coarse value: the crisis lies below the range.
    BelowRange,
    /// Squeal still lasts at the range's top, or no value above the last squealing one is
    /// quiet: the crisis lies above the range.
    AboveRange,
}

/// The crisis along one parameter.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Crisis {
    /// How the search ended.
    pub status: CrisisStatus,
    /// At the setup's step: the last value where squeal lasts and the first where it is
    /// quiet (NaN unless found).
    pub interval: [f64; 2],
    /// The middle of the interval where all three computations agree at both ends.
    pub nu: f64,
    /// Half that interval's width: the stated uncertainty.
    pub uncertainty: f64,
    /// Whether `interval`'s ends get the same verdicts at `dt / 2`.
    pub half_dt_holds: bool,
    /// ... and with the longer horizon.
    pub longer_holds: bool,
    /// Every change of "squeal does not last" the coarse scan found.
    pub changes: Vec<Change>,
    /// Verdicts computed (each computation once per value).
    pub evaluations: u32,
}

impl Crisis {
    fn not_found(status: CrisisStatus, changes: Vec<Change>, evaluations: u32) -> Crisis {
        Crisis {
            status,
            interval: [f64::NAN; 2],
            nu: f64::NAN,
            uncertainty: f64::NAN,
            half_dt_holds: false,
            longer_holds: false,
            changes,
            evaluations,
        }
    }
}

/// Remembered verdicts: `verdict(v, variant)` computed once per value and variant.
///
/// A verdict depends on its value and variant only (the returns two verdicts at one value
/// share are the same returns, [`ReturnCache`]), so verdicts known to be needed are computed
/// on several threads at once ([`Verdicts::fill`]): the coarse scan's, the samples above the
/// interval, the other computations at the interval's ends. The search then reads them in
/// its own order and finds what it found one verdict at a time, bit for bit; only its wall
/// clock changes. Nothing is computed that the search one at a time would not compute,
/// except where a verdict at an interval's end would have cut the others short.
struct Verdicts<F> {
    verdict: F,
    memo: RefCell<HashMap<(u64, Variant), Lasting>>,
}

/// A verdict function as [`crisis_in`] takes it: called from several threads at once.
pub trait VerdictFn: Fn(f64, Variant) -> Result<Lasting, ScanError> + Sync {}
impl<F: Fn(f64, Variant) -> Result<Lasting, ScanError> + Sync> VerdictFn for F {}

impl<F: VerdictFn> Verdicts<F> {
    fn new(verdict: F) -> Verdicts<F> {
        Verdicts {
            verdict,
            memo: RefCell::new(HashMap::new()),
        }
    }

    /// Whether every [`Variant`] gives `want` at `x` (the one at the setup's step first; only
    /// where it agrees are the two others computed, side by side).
    fn agree(&self, x: f64, want: Lasting) -> Result<bool, ScanError> {
        if self.at(x, Variant::Dt)? != want {
            return Ok(false);
        }
        self.fill(&[(x, Variant::HalfDt), (x, Variant::Longer)])?;
        for w in Variant::ALL {
            if self.at(x, w)? != want {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Computes the verdicts at `wanted` (value, variant) not yet remembered, in parallel on
    /// the current rayon pool, and remembers them. Returns the first failure in the order of
    /// `wanted`: the one a loop over them would stop at.
    fn fill(&self, wanted: &[(f64, Variant)]) -> Result<(), ScanError> {
        let mut todo: Vec<(f64, Variant)> = Vec::with_capacity(wanted.len());
        {
            let memo = self.memo.borrow();
            for &(x, w) in wanted {
                let key = (x.to_bits(), w);
                if !memo.contains_key(&key) && !todo.iter().any(|&(y, u)| (y.to_bits(), u) == key) {
                    todo.push((x, w));
                }
            }
        }
        if todo.len() < 2 {
            return todo
                .first()
                .map_or(Ok(()), |&(x, w)| self.at(x, w).map(|_| ()));
        }
        let (verdict, observer) = (&self.verdict, crate::observe::current());
        let got: Vec<Result<Lasting, ScanError>> = todo
            .par_iter()
            .map(|&(x, w)| crate::observe::observed_by(observer.as_ref(), || verdict(x, w)))
            .collect();
        let mut memo = self.memo.borrow_mut();
        for (&(x, w), l) in todo.iter().zip(got) {
            memo.insert((x.to_bits(), w), l?);
        }
        Ok(())
    }

    fn at(&self, v: f64, which: Variant) -> Result<Lasting, ScanError> {
        if let Some(l) = self.memo.borrow().get(&(v.to_bits(), which)) {
            return Ok(*l);
        }
        let l = (self.verdict)(v, which)?;
        self.memo.borrow_mut().insert((v.to_bits(), which), l);
        Ok(l)
    }

    /// The values already seen at the setup's step with verdict `pred`, in `(lo, hi)`.
    fn seen(&self, (lo, hi): (f64, f64), pred: impl Fn(Lasting) -> bool) -> Vec<f64> {
        self.memo
            .borrow()
            .iter()
            .filter(|((_, w), l)| *w == Variant::Dt && pred(**l))
            .map(|((b, _), _)| f64::from_bits(*b))
            .filter(|v| *v > lo && *v < hi)
            .collect()
    }

    fn count(&self) -> u32 {
        self.memo.borrow().len() as u32
    }
}

/// The crisis in `nu` at `setup` over `range` (cycle settings `cs`, `coarse` steps).
pub fn crisis_nu(
    setup: Setup,
    cs: &CycleSettings,
    range: ParamRange,
    coarse: usize,
) -> Result<Crisis, ScanError> {
    let at = |nu: f64| setup.with_params(Params { nu, ..setup.params });
    let shared = SharedReturns::default();
    crisis_in(
        |v, which| which.lasting_sharing(at(v), cs, Budget::Standard, &shared.at(v)),
        range,
        coarse,
    )
}

/// The crisis over `range` of the parameter that `verdict(v, variant)` moves: see the
/// module's comment. `coarse` steps of the coarse scan; the bisections stop at
/// `range.rtol`.
pub fn crisis_in(
    verdict: impl VerdictFn,
    range: ParamRange,
    coarse: usize,
) -> Result<Crisis, ScanError> {
    let v = Verdicts::new(verdict);
    let (lo, hi) = (range.lo, range.hi);
    let coarse = coarse.max(1);
    // The coarse values side by side; the scan below reads them.
    let steps: Vec<(f64, Variant)> = geometric_steps((lo, hi), coarse)
        .into_iter()
        .map(|x| (x, Variant::Dt))
        .collect();
    crate::observe::stage("coarse scan", Some(steps.len() as u64));
    v.fill(&steps)?;
    let changes = coarse_changes(
        |x| Ok::<_, ScanError>(v.at(x, Variant::Dt)? != Lasting::Squeals),
        (lo, hi),
        coarse,
    )?;
    let vs = geometric_steps((lo, hi), coarse);
    let ls: Vec<Lasting> = vs
        .iter()
        .map(|&x| v.at(x, Variant::Dt))
        .collect::<Result<_, _>>()?;
    let Some(k) = ls.iter().rposition(|l| *l == Lasting::Squeals) else {
        return Ok(Crisis::not_found(
            CrisisStatus::BelowRange,
            changes,
            v.count(),
        ));
    };
    let Some(m) = (k + 1..ls.len()).find(|&i| ls[i] == Lasting::Quiet) else {
        return Ok(Crisis::not_found(
            CrisisStatus::AboveRange,
            changes,
            v.count(),
        ));
    };
    let interval = bisect_both(&v, (vs[k], vs[k + 1], vs[m]), range.rtol)?;
    crate::observe::stage("checks at dt/2 and a longer horizon", None);
    let (mut outer, holds) = widen(&v, interval, (lo, hi, range.rtol))?;
    crate::observe::stage("clearing the stretch above", None);
    outer[1] = clear_above(&v, outer[1], (hi, (hi / lo).ln() / coarse as f64))?;
    Ok(Crisis {
        status: CrisisStatus::Found,
        interval,
        nu: 0.5 * (outer[0] + outer[1]),
        uncertainty: 0.5 * (outer[1] - outer[0]),
        half_dt_holds: holds[0],
        longer_holds: holds[1],
        changes,
        evaluations: v.count(),
    })
}

/// The last value where squeal lasts (bisected in `(s, next)`, squeal lasting at `s` and
/// not at `next`) and the first where it is quiet (below `quiet`, where it is).
fn bisect_both<F: VerdictFn>(
    v: &Verdicts<F>,
    (s, next, quiet): (f64, f64, f64),
    rtol: f64,
) -> Result<[f64; 2], ScanError> {
    let ((a, _), _) = geometric_bisection(
        |x| Ok::<_, ScanError>(v.at(x, Variant::Dt)? != Lasting::Squeals),
        (s, next),
        rtol,
        200,
    )?;
    // The tightest bracket of "quiet" already seen: the first quiet value above `a`, and
    // below it the last value that is not.
    let hi = v
        .seen((a, quiet), |l| l == Lasting::Quiet)
        .into_iter()
        .fold(quiet, f64::min);
    let lo = v
        .seen((a, hi), |l| l != Lasting::Quiet)
        .into_iter()
        .fold(a, f64::max);
    let ((_, b), _) = geometric_bisection(
        |x| Ok::<_, ScanError>(v.at(x, Variant::Dt)? == Lasting::Quiet),
        (lo, hi),
        rtol,
        200,
    )?;
    Ok([a, b])
}

/// Widens `[a, b]` until every [`Variant`] says squeal lasts at its lower end and is quiet
/// at its upper end (at most to the range's ends); returns it and whether `[a, b]` held at
/// dt/2 and with the longer horizon as it was.
fn widen<F: VerdictFn>(
    v: &Verdicts<F>,
    [a, b]: [f64; 2],
    (lo, hi, rtol): (f64, f64, f64),
) -> Result<([f64; 2], [bool; 2]), ScanError> {
    // The ends at dt/2 and with the longer horizon side by side (the step out from each end
    // asks for them too, unless a verdict at dt/2 already disagrees).
    v.fill(&[
        (a, Variant::HalfDt),
        (b, Variant::HalfDt),
        (a, Variant::Longer),
        (b, Variant::Longer),
    ])?;
    let holds = |w: Variant| -> Result<bool, ScanError> {
        Ok(v.at(a, w)? == Lasting::Squeals && v.at(b, w)? == Lasting::Quiet)
    };
    let held = [holds(Variant::HalfDt)?, holds(Variant::Longer)?];
    // Outward in steps of a quarter of the bracket's log-width (at least rtol), doubled each
    // time: a few verdicts where the computations nearly agree, the range's end at worst.
    let first = ((b / a).ln() / 4.0).max(rtol.ln_1p());
    let x = step_out(a, lo, -first, |x| v.agree(x, Lasting::Squeals))?;
    let y = step_out(b, hi, first, |y| v.agree(y, Lasting::Quiet))?;
    Ok(([x, y], held))
}

/// Samples at the setup's step over the stretch above the interval's top ([`clear_above`]).
pub const ABOVE_SAMPLES: usize = 12;

/// Raises the top `y` of the interval where every [`Variant`] agrees until the
/// verdict at the setup's step is quiet at every one of [`ABOVE_SAMPLES`] geometric samples
/// over the stretch above it, an eighth of a coarse step wide (log-width `coarse_log / 8`),
/// at most to `hi`: over any sample that is not quiet, to the first value above it where
/// every [`Variant`] says quiet (outward from it in steps of the samples' spacing, doubled
/// each time). Returns the new top.
///
/// Why: above the crisis the verdict is not monotone. Narrow windows where the band is
/// undecided again, or trapped (squeal lasts), lie between the coarse values, and a search
/// at dt/2 or with the longer horizon can land its bisection in one (`scripts/bench/fold-coverage.sh`
/// on `scans/atlas-lambda-nu.toml`: lambda = 0.6590, undecided at dt on about
/// [0.02271, 0.02291] and at dt/2 on [0.02283, 0.02311] above a top of 0.022674; lambda =
/// 4.9261, squeal lasting at all three on [0.02061, 0.02070] above 0.020472; lambda = 4.7356,
/// trapped at 0.021403 and 0.021494 above 0.020984; `cargo run --release -p squeal-scan
/// --example fold_verdicts -- scans/atlas-lambda-nu.toml J LO HI N`, J the belt speed's
/// index: 7, 58, 57). There the windows lie within 2.6% above the top, the last one
/// [0.02144, 0.02152] at lambda = 4.7356 only 0.4% wide with a quiet gap inside; samples a
/// quarter of a coarse step wide at 0.45% spacing stepped over it, an eighth (2.7% at 0.22%)
/// does not. Windows narrower than the spacing, farther above than the stretch, or seen at
/// dt/2 or with the longer horizon only, can still hide: the samples are at dt, the
/// cheapest verdict (about 0.06 s where quiet on that chart, against 0.12 s at dt/2).
fn clear_above<F: VerdictFn>(
    v: &Verdicts<F>,
    y: f64,
    (hi, coarse_log): (f64, f64),
) -> Result<f64, ScanError> {
    let d = coarse_log / 8.0 / ABOVE_SAMPLES as f64;
    let sample = |top: f64, j: usize| (top * (j as f64 * d).exp()).min(hi);
    let mut top = y;
    while top < hi {
        // The samples side by side (up to the first at `hi`); the loop below reads them.
        let mut samples = Vec::with_capacity(ABOVE_SAMPLES);
        for j in 1..=ABOVE_SAMPLES {
            samples.push((sample(top, j), Variant::Dt));
            if sample(top, j) >= hi {
                break;
            }
        }
        v.fill(&samples)?;
        let mut last = None;
        for j in 1..=ABOVE_SAMPLES {
            let s = sample(top, j);
            if v.at(s, Variant::Dt)? != Lasting::Quiet {
                last = Some(s);
            }
            if s >= hi {
                break;
            }
        }
        let Some(z) = last else { break };
        top = step_out(z, hi, d, |t| v.agree(t, Lasting::Quiet))?;
    }
    Ok(top)
}

/// From `x` towards `limit` in geometric steps (log-step `first`, its sign the direction,
/// doubled each time) until `done` holds there or `limit` is reached; returns that value.
fn step_out(
    mut x: f64,
    limit: f64,
    first: f64,
    mut done: impl FnMut(f64) -> Result<bool, ScanError>,
) -> Result<f64, ScanError> {
    let down = first < 0.0;
    let mut step = first;
    while (if down { x > limit } else { x < limit }) && !done(x)? {
        x = match down {
            true => (x * step.exp()).max(limit),
            false => (x * step.exp()).min(limit),
        };
        step *= 2.0;
    }
    Ok(x)
}

/// Raises the top of the crisis's stated interval `[nu - uncertainty, nu + uncertainty]`
/// to the first value at or above `at` (stepping as the interval is widened, at most to
/// `hi`) where every [`Variant`] says quiet; returns the new `(nu, uncertainty)` and the
/// verdicts computed.
///
/// Why: the crisis's search sees the regime at its coarse values and along its bisections
/// only. Above the crisis the band's verdict can return to undecided over narrow windows
/// of the parameter (its bottom comes back to within the resolution of the cycle; at
/// lambda = 0.5628 of `scans/atlas-lambda-nu.toml`, Table 1's tau and phi, quiet from nu
/// = 0.02111 but undecided again on about [0.02128, 0.02158] and [0.02207, 0.02225]),
/// where squeal may still last. When another search finds such a value above the interval
/// (the critical damping of a start, whose bisection counts an undecided band as
/// squealing), the fold's interval must reach above it to cover the truth.
pub fn raise_top(
    verdict: impl VerdictFn,
    (nu, uncertainty): (f64, f64),
    at: f64,
    (hi, rtol): (f64, f64),
) -> Result<((f64, f64), u32), ScanError> {
    let v = Verdicts::new(verdict);
    let bottom = nu - uncertainty;
    let first = ((at / bottom).ln() / 4.0).max(rtol.ln_1p());
    let top = step_out(at, hi, first, |y| v.agree(y, Lasting::Quiet))?;
    if top <= nu + uncertainty {
        return Ok(((nu, uncertainty), v.count()));
    }
    Ok(((0.5 * (bottom + top), 0.5 * (top - bottom)), v.count()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A verdict with known thresholds: squeal lasts below `s`, is quiet from `q`, undecided
    /// between; at dt/2 both thresholds are `shift` times higher, with the longer horizon
    /// `shift` times lower.
    fn verdict(s: f64, q: f64, shift: f64) -> impl Fn(f64, Variant) -> Result<Lasting, ScanError> {
        move |v, which| {
            let f = match which {
                Variant::Dt => 1.0,
                Variant::HalfDt => shift,
                Variant::Longer => 1.0 / shift,
            };
            Ok(if v < s * f {
                Lasting::Squeals
            } else if v >= q * f {
                Lasting::Quiet
            } else {
                Lasting::Undecided
            })
        }
    }

    #[test]
    fn the_uncertainty_covers_every_computations_crisis() {
        // Thresholds 0.024 and 0.0242 at dt, 1% higher at dt/2 and 1% lower with the
        // longer horizon: the stated interval must hold all three [s, q] brackets, and the
        // bracket at dt is the bisected one, to rtol.
        let c = crisis_in(
            verdict(0.024, 0.0242, 1.01),
            ParamRange::new(1e-3, 0.05, 1e-4),
            64,
        )
        .unwrap();
        assert_eq!(c.status, CrisisStatus::Found);
        assert!(c.interval[0] < 0.024 && 0.024 / c.interval[0] - 1.0 <= 1e-4);
        assert!(c.interval[1] >= 0.0242 && c.interval[1] / 0.0242 - 1.0 <= 1e-4);
        assert!(!c.half_dt_holds && !c.longer_holds, "{c:?}");
        let (lo, hi) = (c.nu - c.uncertainty, c.nu + c.uncertainty);
        for f in [1.0, 1.01, 1.0 / 1.01] {
            assert!(lo < 0.024 * f && 0.0242 * f <= hi, "{f}: {c:?}");
        }
        assert_eq!(c.changes.len(), 1);
        // Where all three agree the interval is the bracket at dt.
        let c = crisis_in(
            verdict(0.024, 0.0242, 1.0),
            ParamRange::new(1e-3, 0.05, 1e-4),
            64,
        )
        .unwrap();
        assert!(c.half_dt_holds && c.longer_holds);
        assert_eq!([c.nu - c.uncertainty, c.nu + c.uncertainty], c.interval);
    }

    #[test]
    fn a_window_above_the_crisis_is_covered_when_another_search_finds_it() {
        // Squeals below 0.024, quiet from 0.0242 but undecided again on [0.0250, 0.0255): a
        // window narrower than the coarse step (ratio 1.063) the crisis can step over. From
        // a value found inside it (0.0252, as the critical damping's bisection finds one),
        // the interval's top is raised to where all three computations say quiet again,
        // at or above the window's end, and its bottom stays where squeal last lasts.
        let v = |x: f64, _: Variant| {
            Ok(if x < 0.024 {
                Lasting::Squeals
            } else if x < 0.0242 || (0.025..0.0255).contains(&x) {
                Lasting::Undecided
            } else {
                Lasting::Quiet
            })
        };
        let c = crisis_in(v, ParamRange::new(1e-3, 0.05, 1e-4), 64).unwrap();
        assert!(c.nu + c.uncertainty < 0.025, "{c:?}");
        let ((nu, u), n) = raise_top(v, (c.nu, c.uncertainty), 0.0252, (0.05, 1e-4)).unwrap();
        assert!(nu + u >= 0.0255 && v(nu + u, Variant::Dt).unwrap() == Lasting::Quiet);
        assert!((nu - u - (c.nu - c.uncertainty)).abs() < 1e-15);
        assert!(n >= 3, "{n}");
        // Already covered: nothing moves.
        let ((nu, u), _) = raise_top(v, (0.03, 0.01), 0.0256, (0.05, 1e-4)).unwrap();
        assert_eq!((nu, u), (0.03, 0.01));
    }

    #[test]
    fn a_window_just_above_the_crisis_is_covered_by_the_stretch_above() {
        // Squeals below 0.024, undecided on [0.024, 0.0242), quiet from 0.0242 but squeal
        // lasting again on [0.02432, 0.02436) at dt and dt/2 only, and on [0.026, 0.0262):
        // 64 coarse steps over [1e-3, 0.05] (log-step ln(50) / 64 = 0.0611) step over both,
        // and so do the bisections (their values near the first window: 0.024287 and
        // 0.024380). The stretch above the interval is an eighth of that (0.76%, 12
        // samples 0.064% apart): the first window (0.5% above the top, 0.16% wide) lies in
        // it, the second (7% above) does not and stays outside, as `clear_above` says.
        let v = |x: f64, w: Variant| {
            Ok(if x < 0.024 {
                Lasting::Squeals
            } else if x < 0.0242 {
                Lasting::Undecided
            } else if ((0.02432..0.02436).contains(&x) && w != Variant::Longer)
                || (0.026..0.0262).contains(&x)
            {
                Lasting::Squeals
            } else {
                Lasting::Quiet
            })
        };
        let c = crisis_in(v, ParamRange::new(1e-3, 0.05, 1e-4), 64).unwrap();
        let (lo, hi) = (c.nu - c.uncertainty, c.nu + c.uncertainty);
        assert!(c.interval[0] < 0.024 && 0.0242 <= c.interval[1], "{c:?}");
        assert!(c.interval[1] / 0.0242 - 1.0 <= 1e-4, "{c:?}");
        assert!(
            lo == c.interval[0] && (0.02436..0.026).contains(&hi),
            "{c:?}"
        );
        for w in Variant::ALL {
            assert_eq!(v(hi, w).unwrap(), Lasting::Quiet);
        }
    }

    /// `verdict` of `crisis_in`'s tests, slowed down (a millisecond a verdict, so that idle
    /// threads steal work) and logging the threads it ran on.
    fn slow_verdict(
        threads: &Mutex<std::collections::HashSet<std::thread::ThreadId>>,
    ) -> impl Fn(f64, Variant) -> Result<Lasting, ScanError> + Sync + '_ {
        let v = verdict(0.024, 0.0242, 1.01);
        move |x, w| {
            threads.lock().unwrap().insert(std::thread::current().id());
            std::thread::sleep(std::time::Duration::from_millis(1));
            v(x, w)
        }
    }

    #[test]
    fn the_verdicts_run_side_by_side_and_give_the_same_crisis() {
        // The same search in a pool of 1 thread and of 4: the same crisis, field by field
        // (its verdicts count included), its verdicts computed on more than one thread in
        // the second (one thread before they were computed side by side).
        let mut seen = Vec::new();
        let mut crises = Vec::new();
        for n in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap();
            let threads = Mutex::new(std::collections::HashSet::new());
            let c = pool.install(|| {
                crisis_in(
                    slow_verdict(&threads),
                    ParamRange::new(1e-3, 0.05, 1e-4),
                    64,
                )
                .unwrap()
            });
            seen.push(threads.into_inner().unwrap().len());
            crises.push(c);
        }
        assert_eq!(format!("{:?}", crises[0]), format!("{:?}", crises[1]));
        assert_eq!(seen[0], 1);
        assert!(seen[1] > 1, "{seen:?}");
    }

    #[test]
    fn a_failing_verdict_fails_the_search_with_the_lowest_failure() {
        // Verdicts fail at two coarse values: the error is the one at the lower, which a
        // scan one value after the other stops at.
        let v = |x: f64, _: Variant| {
            if x > 0.01 && x < 0.02 {
                Err(ScanError::Undetermined(format!("at {x}")))
            } else {
                Ok(Lasting::Squeals)
            }
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        let e = pool
            .install(|| crisis_in(v, ParamRange::new(1e-3, 0.05, 1e-4), 64))
            .unwrap_err();
        let first = geometric_steps((1e-3, 0.05), 64)
            .into_iter()
            .find(|x| *x > 0.01)
            .unwrap();
        assert_eq!(
            e.to_string(),
            ScanError::Undetermined(format!("at {first}")).to_string()
        );
    }

    #[test]
    fn every_change_of_regime_is_reported_and_the_fold_is_the_last() {
        // Squeals below 0.01, undecided on [0.01, 0.015), squeals again on [0.015, 0.02),
        // quiet from 0.02: three changes of "squeal does not last" over [1e-3, 0.05] in 64
        // geometric steps (ratio 1.063 per step: each piece spans several), the fold at 0.02.
        let v = |x: f64, _: Variant| {
            Ok(if x < 0.01 || (0.015..0.02).contains(&x) {
                Lasting::Squeals
            } else if x >= 0.02 {
                Lasting::Quiet
            } else {
                Lasting::Undecided
            })
        };
        let c = crisis_in(v, ParamRange::new(1e-3, 0.05, 1e-4), 64).unwrap();
        let to: Vec<bool> = c.changes.iter().map(|c| c.to).collect();
        assert_eq!(to, [true, false, true], "{c:?}");
        assert!(c.interval[0] < 0.02 && 0.02 <= c.interval[1], "{c:?}");
        assert!(c.interval[1] / c.interval[0] - 1.0 <= 1e-4);
        // No squeal anywhere, or squeal up to the top: not found, said so.
        let quiet = |_: f64, _: Variant| Ok(Lasting::Quiet);
        let c = crisis_in(quiet, ParamRange::new(1e-3, 0.05, 1e-4), 8).unwrap();
        assert_eq!(c.status, CrisisStatus::BelowRange);
        let loud = |_: f64, _: Variant| Ok(Lasting::Squeals);
        let c = crisis_in(loud, ParamRange::new(1e-3, 0.05, 1e-4), 8).unwrap();
        assert_eq!(c.status, CrisisStatus::AboveRange);
    }
}
