//! The Poincaré section `S = { x = x*, x' > 0 }` and its return map, in one place.
//!
//! Every revolution around the fixed point crosses `S` once, going right. `P(r)` is the
//! section amplitude one revolution after a start at `(x*, r)`, and `D(r) = P(r) - r`:
//! `D < 0` where starts spiral in, `D > 0` where they grow, so an unstable cycle crosses
//! `S` at a `-` to `+` sign change of `D`. Everything that looks for the cycle on `S` (the
//! `ulc` command, a scan's per-map preparation, an atlas point, a boundary predicate) asks
//! this module for `D`, its samples and its brackets, and every evaluation is counted here,
//! where it happens ([`Work`]).
//!
//! - [`ReturnMap::d`]: one counted return (a run that does not return within `t_return`
//!   counts as decay, `D = -r`);
//! - [`log_samples`]: the log-spaced amplitudes a search samples;
//! - [`ReturnMap::bisect`]: plain bisection of a bracket (the reference method);
//! - [`ReturnMap::illinois`]: the same bracket narrowed by the Illinois variant of false
//!   position (the atlas's faster method, same tolerance).

use serde::Serialize;
use squeal_core::classify::section_return;
use squeal_core::section::Miss;
use squeal_core::{SolverStats, Stepper};

/// Settings of the cycle search.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CycleSettings {
    /// Smallest section amplitude sampled.
    pub r_min: f64,
    /// Largest section amplitude sampled.
    pub r_max: f64,
    /// Log-spaced samples of `D` on `[r_min, r_max]`.
    pub samples: usize,
    /// Relative bracket width at which bisection stops.
    pub rtol: f64,
    /// Longest time allowed for one return to the section.
    pub t_return: f64,
    /// Also locate the cycle with `dt / 2` and report the shift.
    pub check_half_dt: bool,
}

impl Default for CycleSettings {
    fn default() -> Self {
        CycleSettings {
            r_min: 1e-2,
            r_max: 6.0,
            samples: 96,
            rtol: 1e-10,
            t_return: 200.0,
            check_half_dt: true,
        }
    }
}

/// Work done on the section: section returns and the solver counters over those runs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Work {
    /// Solver counters.
    pub stats: SolverStats,
    /// Section returns (each one revolution).
    pub returns: u64,
    /// Of those, runs stopped on a lasting oscillation that misses the section
    /// ([`squeal_core::section::Miss::Lasting`]): no return, as at the time limit, found early.
    pub lasting: u64,
}

impl Work {
    /// Adds `other`'s counts to these.
    pub fn merge(&mut self, other: &Work) {
        self.stats.merge(&other.stats);
        self.returns += other.returns;
        self.lasting += other.lasting;
    }
}

/// A bracket `[lo, hi]` of a sign change of `D`, with `D(lo) <= 0 < D(hi)` in `d`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bracket {
    /// Lower end (`D <= 0`).
    pub lo: f64,
    /// Upper end (`D > 0`).
    pub hi: f64,
    /// `[D(lo), D(hi)]`.
    pub d: [f64; 2],
}

impl Bracket {
    /// Whether the values show the sign change (`D(lo) <= 0 < D(hi)`).
    pub fn holds(&self) -> bool {
        self.d[0] <= 0.0 && self.d[1] > 0.0
    }

    /// The middle of the bracket.
    pub fn mid(&self) -> f64 {
        0.5 * (self.lo + self.hi)
    }
}

/// `n` amplitudes log-spaced on `[r_min, r_max]`, computed by index (never by adding a step).
pub fn log_samples(r_min: f64, r_max: f64, n: usize) -> Vec<f64> {
    let (a, b) = (r_min.ln(), r_max.ln());
    (0..n)
        .map(|i| (a + (b - a) * i as f64 / (n - 1) as f64).exp())
        .collect()
}

/// Returns already computed on one stepper, by start amplitude, for reuse by a later search
/// on the same stepper: the crisis's verdict with the longer horizon ([`crate::band::Budget`])
/// samples the section at the same amplitudes as the verdict at the same step, and half of
/// its band's samples too, with twice the return time.
///
/// A run to the section does not depend on its time limit until it stops (the limit only
/// counts its steps), so a return found within one limit is the same return under any
/// longer limit, bit for bit; one not found counts as decay under that same limit only.
/// Never share one between steppers (another step, law or parameter set). Behind a lock so
/// that the verdicts at several parameter values (each with its own cache) can run on
/// several threads.
#[derive(Debug, Default)]
pub struct ReturnCache(std::sync::Mutex<std::collections::HashMap<u64, Cached>>);

/// One cached return: the time limit it ran under, and the returned amplitude (`None`: no
/// return within that limit).
#[derive(Clone, Copy, Debug)]
struct Cached {
    t_return: f64,
    p: Option<f64>,
}

impl ReturnCache {
    /// The return from `r` under the limit `t_return`, if known: `Some(None)` for no return.
    fn get(&self, r: f64, t_return: f64) -> Option<Option<f64>> {
        let c = *self.map().get(&r.to_bits())?;
        match c.p {
            Some(_) if t_return >= c.t_return => Some(c.p),
            None if t_return == c.t_return => Some(None),
            _ => None,
        }
    }

    fn put(&self, r: f64, t_return: f64, p: Option<f64>) {
        self.map().insert(r.to_bits(), Cached { t_return, p });
    }

    /// The returns (a panic elsewhere leaves them valid: each entry is written whole).
    fn map(&self) -> std::sync::MutexGuard<'_, std::collections::HashMap<u64, Cached>> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The return map of one stepper (one law, parameter set, step and solver).
#[derive(Clone, Copy)]
pub struct ReturnMap<'a> {
    st: &'a Stepper,
    t_return: f64,
    cache: Option<&'a ReturnCache>,
}

impl<'a> ReturnMap<'a> {
    /// The return map of `st`; a return that takes longer than `t_return` counts as decay.
    pub fn new(st: &'a Stepper, t_return: f64) -> Self {
        ReturnMap {
            st,
            t_return,
            cache: None,
        }
    }

    /// [`ReturnMap::new`] reading and filling `cache` (which must be `st`'s alone): a
    /// cached return is not run again, nor counted.
    pub fn cached(st: &'a Stepper, t_return: f64, cache: &'a ReturnCache) -> Self {
        ReturnMap {
            st,
            t_return,
            cache: Some(cache),
        }
    }

    /// The stepper.
    pub fn stepper(&self) -> &'a Stepper {
        self.st
    }

    /// `D(r) = P(r) - r`, counted in `w`; no return within `t_return` counts as decay
    /// (`D = -r`), and so does a run that settles on a lasting oscillation missing the
    /// section ([`Miss::Lasting`], counted in [`Work::lasting`]): stopped there instead of
    /// at `t_return`.
    pub fn d(&self, r: f64, w: &mut Work) -> f64 {
        let known = self.cache.and_then(|c| c.get(r, self.t_return));
        let p = known.unwrap_or_else(|| {
            w.returns += 1;
            let ret = section_return(self.st, r, self.t_return, &mut w.stats, |_| {});
            w.lasting += u64::from(matches!(ret, Err(Miss::Lasting(_))));
            let p = ret.ok().map(|c| c.r);
            crate::observe::step(crate::observe::SearchStep::Return(r));
            if let Some(c) = self.cache {
                c.put(r, self.t_return, p);
            }
            p
        });
        match p {
            Some(p) => p - r,
            None => -r,
        }
    }

    /// `D` at each amplitude of `rs`.
    pub fn sample(&self, rs: &[f64], w: &mut Work) -> Vec<f64> {
        rs.iter().map(|&r| self.d(r, w)).collect()
    }

    /// Bisects `[lo, hi]` (`D(lo) <= 0 < D(hi)`) to the relative width `rtol` (at most
    /// 200 halvings); returns the final bracket.
    pub fn bisect(&self, lo: f64, hi: f64, rtol: f64, w: &mut Work) -> (f64, f64) {
        self.bisect_while(lo, hi, rtol, w, |_, _| true)
    }

    /// [`ReturnMap::bisect`], stopping early, before each halving, where `go_on(lo, hi)` is
    /// false.
    pub fn bisect_while(
        &self,
        mut lo: f64,
        mut hi: f64,
        rtol: f64,
        w: &mut Work,
        go_on: impl Fn(f64, f64) -> bool,
    ) -> (f64, f64) {
        for _ in 0..200 {
            if hi - lo <= rtol * hi || !go_on(lo, hi) {
                break;
            }
            let mid = 0.5 * (lo + hi);
            if self.d(mid, w) > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        (lo, hi)
    }

    /// Narrows a bracket to the relative width `rtol` by the Illinois variant of false
    /// position; returns the final `(lo, hi)`.
    ///
    /// The bracket is kept at every step, so the result meets the same tolerance as
    /// [`ReturnMap::bisect`]. Where the starting bracket holds one sign change it is the
    /// same root; where it holds several (`D` jumps where the orbit starts to stick) the
    /// two methods may settle on different ones, both sign changes of `D` to the
    /// tolerance: on the 64 x 64 chart (`scans/atlas-lambda-nu.toml`) at 18 of 4096
    /// points, all above the fold (nu >= 0.046) and all "steady slip only" either way.
    /// Near a simple root `D` is smooth and the method converges superlinearly (about 6-8
    /// returns from a 10% bracket instead of bisection's 27 to 1e-9). Each trial point is
    /// kept at least a quarter of the tolerance inside the bracket, so once the estimate
    /// is that close the next trial lands on the other side and closes the bracket; a
    /// step that fails to halve the bracket twice running is followed by a bisection step
    /// (so it never needs more than about twice bisection's count).
    pub fn illinois(&self, b: Bracket, rtol: f64, w: &mut Work) -> (f64, f64) {
        let (mut lo, mut hi) = (b.lo, b.hi);
        let [mut d_lo, mut d_hi] = b.d;
        // -1: the last step moved `lo`, +1: `hi`, 0: none yet.
        let mut side = 0i8;
        let mut slow = 0u32;
        for _ in 0..400 {
            let width = hi - lo;
            let tol = rtol * hi;
            if width <= tol {
                break;
            }
            let mut r = if slow >= 2 || d_hi.partial_cmp(&d_lo) != Some(std::cmp::Ordering::Greater)
            {
                slow = 0;
                0.5 * (lo + hi)
            } else {
                hi - d_hi * (hi - lo) / (d_hi - d_lo)
            };
            let margin = (0.25 * tol).min(0.5 * width);
            r = r.clamp(lo + margin, hi - margin);
            let d = self.d(r, w);
            if d > 0.0 {
                hi = r;
                d_hi = d;
                if side == 1 {
                    // `lo` kept twice: halve its weight (Illinois).
                    d_lo *= 0.5;
                }
                side = 1;
            } else {
                lo = r;
                d_lo = d;
                if side == -1 {
                    d_hi *= 0.5;
                }
                side = -1;
            }
            if hi - lo > 0.5 * width {
                slow += 1;
            } else {
                slow = 0;
            }
        }
        (lo, hi)
    }
}

/// A bracket of a positive parameter to bisect, and the relative width to stop at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamRange {
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
    /// Stop when `hi / lo - 1 <= rtol`.
    pub rtol: f64,
}

impl ParamRange {
    /// `[lo, hi]` to the relative width `rtol`.
    pub fn new(lo: f64, hi: f64, rtol: f64) -> ParamRange {
        ParamRange { lo, hi, rtol }
    }
}

/// Geometric bisection of a predicate in a positive parameter: false at `lo`, true at
/// `hi`; halves `ln(hi / lo)` until `hi / lo - 1 <= rtol` (at most `max_evaluations`
/// calls in all, counting the two ends the caller already evaluated). Returns the final
/// bracket and the number of evaluations including those two.
pub fn geometric_bisection<E>(
    mut pred: impl FnMut(f64) -> Result<bool, E>,
    (mut lo, mut hi): (f64, f64),
    rtol: f64,
    max_evaluations: u32,
) -> Result<((f64, f64), u32), E> {
    let mut evaluations = 2u32;
    // The halvings of ln(hi / lo) down to ln(1 + rtol), within the evaluations allowed.
    let halvings = ((hi / lo).ln() / rtol.ln_1p()).log2().ceil();
    let total = halvings.clamp(0.0, f64::from(max_evaluations.saturating_sub(2)));
    crate::observe::stage("bisection", Some(total as u64));
    while hi / lo - 1.0 > rtol && evaluations < max_evaluations {
        let mid = (lo * hi).sqrt();
        evaluations += 1;
        let above = pred(mid)?;
        crate::observe::step(crate::observe::SearchStep::Value(mid));
        if above {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(((lo, hi), evaluations))
}

/// One change of a boolean predicate between two neighbouring values of a coarse scan.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Change {
    /// The lower value.
    pub lo: f64,
    /// The upper value.
    pub hi: f64,
    /// The predicate at `hi` (so `!to` at `lo`).
    pub to: bool,
}

/// Every change of `pred` between neighbours of `n` geometric steps over `[lo, hi]` (`n +
/// 1` values, both ends included). A bisection assumes one change; where the coarse scan
/// finds more, the regime flips back and forth along the parameter and the bisected value
/// is one of several (as along the damping of `scans/brake.toml`, where nothing warned).
/// Changes closer together than a step can still hide between two values.
pub fn coarse_changes<E>(
    mut pred: impl FnMut(f64) -> Result<bool, E>,
    (lo, hi): (f64, f64),
    n: usize,
) -> Result<Vec<Change>, E> {
    let n = n.max(1);
    let vs = geometric_steps((lo, hi), n);
    let mut at = Vec::with_capacity(vs.len());
    crate::observe::stage("coarse scan", Some(vs.len() as u64));
    for &v in &vs {
        at.push(pred(v)?);
        crate::observe::step(crate::observe::SearchStep::Value(v));
    }
    Ok((0..n)
        .filter(|&i| at[i] != at[i + 1])
        .map(|i| Change {
            lo: vs[i],
            hi: vs[i + 1],
            to: at[i + 1],
        })
        .collect())
}

/// `n + 1` values over `[lo, hi]` in `n` equal steps of `ln v`, both ends included: the
/// values [`coarse_changes`] evaluates.
pub fn geometric_steps((lo, hi): (f64, f64), n: usize) -> Vec<f64> {
    (0..=n)
        .map(|i| (lo.ln() + (hi.ln() - lo.ln()) * i as f64 / n as f64).exp())
        .collect()
}

/// Where the return map changes sign.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SectionCycles {
    /// An unstable cycle crosses `S` in `[lo, hi]`; `stable_above` is the first sampled
    /// crossing further out, if the sampled range shows one; `escape` the smallest sampled
    /// start outside the cycle whose return lands inside (see [`escape_above`]), if any.
    Unstable {
        r: f64,
        lo: f64,
        hi: f64,
        stable_above: Option<f64>,
        escape: Option<f64>,
    },
    /// `D <= 0` at every sample: no unstable cycle below `r_max` was seen. `unresolved`:
    /// intervals the refinement budget left wider than the stated resolution
    /// ([`SectionSamples::unresolved`]); 0 where the resolution statement holds.
    NoneBelow { r_max: f64, unresolved: usize },
    /// `D > 0` already at `r_min`: the fixed point repels.
    FixedPointUnstable { r_min: f64 },
}

/// Relative width (of `r`) below which [`adaptive_samples`] stops refining an interval: the
/// search's resolution. A window of `D > 0` narrower than `RESOLUTION r` can be missed.
pub const RESOLUTION: f64 = 1e-3;

/// How much faster than over the sampled interval to its left `D / r` may rise (per unit of
/// `ln r`) before [`adaptive_samples`] looks inside an interval.
pub const RISE_FACTOR: f64 = 3.0;

/// The samples of `D` a search rests on, sorted by amplitude.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SectionSamples {
    /// Amplitudes, increasing.
    pub rs: Vec<f64>,
    /// `D` at each.
    pub ds: Vec<f64>,
    /// Intervals left unrefined because the refinement budget ran out (0: every interval
    /// meets the resolution statement of [`adaptive_samples`]).
    pub unresolved: usize,
}

impl SectionSamples {
    /// Every sampled sign change of `D`: `(lo, hi, rising)` with `rising` for `-` to `+`
    /// (an unstable cycle) and not for `+` to `-` (a stable crossing, or a drop where
    /// orbits begin to stick).
    pub fn sign_changes(&self) -> Vec<(f64, f64, bool)> {
        (0..self.rs.len().saturating_sub(1))
            .filter(|&i| (self.ds[i] > 0.0) != (self.ds[i + 1] > 0.0))
            .map(|i| (self.rs[i], self.rs[i + 1], self.ds[i + 1] > 0.0))
            .collect()
    }
}

/// Samples `D` on `[r_min, r_max]`: `samples` log-spaced amplitudes, then refined where a
/// window of `D > 0` could hide between two samples of `D <= 0`.
///
/// Why: `D` is smooth on the slip branch, but where orbits begin to stick it drops steeply.
/// Near the fold of cycles the window where `D > 0`, between the unstable cycle and that
/// drop, is narrow (at Table 1, nu = 0.024, `r` in `[2.626, 2.77]`, a ratio of 1.055), and
/// fixed log samples step over it or not depending on `r_max`: `squeal ulc --nu 0.024` found
/// the cycle with `--r-max 6` and 20 and not with 11.38 and 50. In `u = ln r` write `g =
/// D / r`; a window needs `g` to rise to 0 from a negative sample. The interval `[r_i,
/// r_{i+1}]` (both `D <= 0`) is excluded when `|g_i| >= RISE_FACTOR * s * (u_{i+1} - u_i)`,
/// `s` the rise rate of `g` over the interval to its left (smooth rises continue at a
/// similar rate); otherwise it is halved, down to the relative width [`RESOLUTION`]. The
/// intervals on both sides of a sampled peak of `D` below zero ([`peak`]) are halved too,
/// whatever the rate to the left: where orbits begin to touch zero slip `D` has a kink and
/// can jump up between two samples. At McMillan's non-hysteretic law (Table 1's lambda, tau,
/// phi, nu = 0.0403, dt 0.01) `D` climbs from -0.17 at r = 2.915 to -0.058 at 2.92 and is
/// positive only on about [2.9346, 2.9458] (an unstable cycle under a stick-slip orbit at
/// 2.946); the rise rule alone found that window with `--r-max 20` and not with 3.5, 6 or
/// 10. So the statement is: every sign change of `D` is found unless it lies in a window
/// narrower than `RESOLUTION r`, or is reached by a rise of `g` steeper than `RISE_FACTOR`
/// times its sampled rate to the left with no sampled peak beside it. At most `4 samples`
/// extra returns are spent; intervals left over are counted in
/// [`SectionSamples::unresolved`].
pub fn adaptive_samples(map: &ReturnMap, cs: &CycleSettings, w: &mut Work) -> SectionSamples {
    let n = cs.samples.max(2);
    let mut rs = log_samples(cs.r_min, cs.r_max, n);
    let mut ds = map.sample(&rs, w);
    let (mut extra, mut unresolved) = (0usize, 0usize);
    let g = |r: f64, d: f64| d / r;
    let mut i = 1;
    while i + 1 < rs.len() {
        let (r0, r1) = (rs[i], rs[i + 1]);
        let du = r1.ln() - r0.ln();
        let rise = (g(r0, ds[i]) - g(rs[i - 1], ds[i - 1])) / (r0.ln() - rs[i - 1].ln());
        let steep = -g(r0, ds[i]) < RISE_FACTOR * rise.max(0.0) * du;
        let hidden = ds[i] <= 0.0
            && ds[i + 1] <= 0.0
            && r1 - r0 > RESOLUTION * r0
            && (steep || peak(&ds, i) || peak(&ds, i + 1));
        if !hidden {
            i += 1;
            continue;
        }
        if extra >= 4 * n {
            unresolved += 1;
            i += 1;
            continue;
        }
        let mid = (0.5 * (r0.ln() + r1.ln())).exp();
        extra += 1;
        rs.insert(i + 1, mid);
        ds.insert(i + 1, map.d(mid, w));
    }
    SectionSamples { rs, ds, unresolved }
}

/// Whether sample `k` is a sampled local maximum of `D` below zero that rises above a
/// neighbour by at least `|D_k| / PEAK_FACTOR`: a peak whose top could reach `D > 0` between
/// the samples (where `D` has a kink, near orbits that touch zero slip, no slope to the
/// left bounds the rise). Gentle maxima far below zero (numerical jitter on a smooth stretch)
/// are not peaks.
fn peak(ds: &[f64], k: usize) -> bool {
    k >= 1
        && k + 1 < ds.len()
        && ds[k] <= 0.0
        && ds[k] >= ds[k - 1]
        && ds[k] >= ds[k + 1]
        && -ds[k] < PEAK_FACTOR * (ds[k] - ds[k - 1]).max(ds[k] - ds[k + 1])
}

/// How high a sampled local maximum of `D` below zero must rise above a neighbour, as a
/// fraction of its distance from zero, for [`adaptive_samples`] to look on both sides of it:
/// `-D_k < PEAK_FACTOR * rise`.
pub const PEAK_FACTOR: f64 = 4.0;

/// Finds the sign changes of `D` on the section and bisects the first unstable one.
pub fn section_cycles(
    st: &Stepper,
    cs: &CycleSettings,
    stats: &mut SolverStats,
    returns: &mut u64,
) -> SectionCycles {
    section_cycles_to(st, cs, Precision::Rtol, stats, returns)
}

/// [`section_cycles`] with the crossing bisected to `precision`.
pub fn section_cycles_to(
    st: &Stepper,
    cs: &CycleSettings,
    precision: Precision,
    stats: &mut SolverStats,
    returns: &mut u64,
) -> SectionCycles {
    let mut w = Work::default();
    let found = search_section_to(&ReturnMap::new(st, cs.t_return), cs, precision, &mut w);
    stats.merge(&w.stats);
    *returns += w.returns;
    found
}

/// [`section_cycles`] on a return map, counted in `w`: the samples of [`adaptive_samples`],
/// the first `-` to `+` sign change bisected to `rtol`.
pub fn search_section(map: &ReturnMap, cs: &CycleSettings, w: &mut Work) -> SectionCycles {
    search_section_to(map, cs, Precision::Rtol, w)
}

/// How far a section search bisects the unstable cycle's crossing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// To the settings' `rtol`: the crossing itself is wanted.
    Rtol,
    /// Only as far as [`escape_above`] needs: while some sampled return above the cycle
    /// lies below the bracket's upper end (it could fall below the crossing), and to `rtol`
    /// once one lies below its lower end (an escape: the band above is then sampled from
    /// the crossing). Where every sampled return above lies at or above the upper end, no
    /// narrower bracket can give an escape (the crossing's lower end only rises toward
    /// it): the outside is invariant whatever the crossing to `rtol` is, and the bisection
    /// stops there, `r`, `lo` and `hi` then being that wider bracket. For callers that use
    /// only the kind of the answer where nothing escapes ([`crate::band::lasting`],
    /// [`crate::scanner::classifier_for`]'s band rules).
    Escape,
}

/// [`search_section`] with the bisection of the crossing to `precision`.
pub fn search_section_to(
    map: &ReturnMap,
    cs: &CycleSettings,
    precision: Precision,
    w: &mut Work,
) -> SectionCycles {
    if !attracts(map.stepper()) {
        return SectionCycles::FixedPointUnstable { r_min: cs.r_min };
    }
    let SectionSamples {
        rs, ds, unresolved, ..
    } = adaptive_samples(map, cs, w);
    let n = rs.len();
    if ds[0] > 0.0 {
        return SectionCycles::FixedPointUnstable { r_min: cs.r_min };
    }
    let up: Vec<usize> = (0..n - 1)
        .filter(|&i| ds[i] <= 0.0 && ds[i + 1] > 0.0)
        .collect();
    let Some(&i) = up.first() else {
        return SectionCycles::NoneBelow {
            r_max: cs.r_max,
            unresolved,
        };
    };
    let stable_above = (i + 1..n - 1)
        .find(|&j| ds[j] > 0.0 && ds[j + 1] <= 0.0)
        .map(|j| rs[j + 1]);
    // The lowest sampled return from above the cycle.
    let lowest = (i + 1..n)
        .map(|j| rs[j] + ds[j])
        .fold(f64::INFINITY, f64::min);
    let go_on = |_lo: f64, hi: f64| match precision {
        Precision::Rtol => true,
        Precision::Escape => lowest < hi,
    };
    let (lo, hi) = map.bisect_while(rs[i], rs[i + 1], cs.rtol, w, go_on);
    SectionCycles::Unstable {
        r: 0.5 * (lo + hi),
        lo,
        hi,
        stable_above,
        escape: escape_above(&rs, &ds, i + 1, lo),
    }
}

/// The smallest sampled start outside the unstable cycle whose return falls back inside.
///
/// `rs[first..]` are the samples above the cycle, whose section crossing is `r_u`. A
/// sample whose return `P(r) = r + D(r)` lands below `r_u` has jumped past the cycle:
/// where the orbit starts to stick the return map falls steeply (McMillan's hysteretic
/// law above the fold of cycles at lambda = 0.5: at nu = 0.0223 starts at r = 0.91 and 2.19
/// return to 0.231 and 0.228, inside the cycle's 0.236). Then the outside of the cycle is
/// not invariant: a start outside may end in steady slip, and no rule may label a start
/// stick-slip for lying outside. Sampled, so an escape narrower than the sample spacing
/// can be missed; the audit (runs to settlement) checks the labels that rest on it.
pub fn escape_above(rs: &[f64], ds: &[f64], first: usize, r_u: f64) -> Option<f64> {
    (first..rs.len())
        .find(|&j| rs[j] + ds[j] < r_u)
        .map(|j| rs[j])
}

/// How the search ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Search {
    /// A bracket `[lo, hi]` with `D(lo) <= 0 < D(hi)` (the values in `d`); `warm` if from
    /// the neighbour's.
    Bracket {
        lo: f64,
        hi: f64,
        d: [f64; 2],
        warm: bool,
    },
    /// `D < 0` at every sample (and at the refined maximum): no cycle below `r_max`.
    NoneBelow { r_max: f64 },
    /// `D(r_min) > 0`: the fixed point repels at that resolution.
    FixedPointUnstable { r_min: f64 },
}

/// Whether steady slip attracts every start near it ([`squeal_core::SteadySlip`]): where it
/// does not, there is no unstable cycle around it to search for, whatever the return map's
/// samples say (a run near it jumps, or closes on it from one sector only).
fn attracts(st: &Stepper) -> bool {
    squeal_core::SteadySlip::of(st.params())
        .stability
        .attracts()
}

/// Cold search: log-spaced samples of `D`, the first `-` to `+` sign change; if none, the
/// tangency check around the largest `D`.
pub fn search_cold(st: &Stepper, cs: &CycleSettings, tangency_iters: u32, w: &mut Work) -> Search {
    if !attracts(st) {
        return Search::FixedPointUnstable { r_min: cs.r_min };
    }
    let map = ReturnMap::new(st, cs.t_return);
    let n = cs.samples.max(3);
    let rs = log_samples(cs.r_min, cs.r_max, n);
    let mut ds = Vec::with_capacity(n);
    for (i, &r) in rs.iter().enumerate() {
        let d = map.d(r, w);
        if i == 0 && d > 0.0 {
            return Search::FixedPointUnstable { r_min: cs.r_min };
        }
        if d > 0.0 {
            return Search::Bracket {
                lo: rs[i - 1],
                hi: r,
                d: [ds[i - 1], d],
                warm: false,
            };
        }
        ds.push(d);
    }
    if tangency_iters > 0
        && let Some(found) = tangency(&map, &rs, &ds, tangency_iters, w)
    {
        return found;
    }
    Search::NoneBelow { r_max: cs.r_max }
}

/// The tangency check of [`search_cold`]: golden-section search for the largest `D / r`
/// around the sample where it is largest (`D` is a smooth function of `r` on the slip
/// branch, so near a tangency its maximum lies within one sample spacing), returning a
/// bracket as soon as a trial point shows `D > 0`.
fn tangency(map: &ReturnMap, rs: &[f64], ds: &[f64], iters: u32, w: &mut Work) -> Option<Search> {
    let n = rs.len();
    let i = (1..n - 1)
        .max_by(|&i, &j| (ds[i] / rs[i]).total_cmp(&(ds[j] / rs[j])))
        .unwrap_or(1);
    let up = |r: f64, d: f64| {
        (d > 0.0).then_some(Search::Bracket {
            lo: rs[i - 1],
            hi: r,
            d: [ds[i - 1], d],
            warm: false,
        })
    };
    let (mut lo, mut hi) = (rs[i - 1], rs[i + 1]);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = hi - g * (hi - lo);
    let mut e = lo + g * (hi - lo);
    let (mut dc, mut de) = (map.d(c, w), map.d(e, w));
    for k in 0..=iters {
        if let Some(found) = up(c, dc).or_else(|| up(e, de)) {
            return Some(found);
        }
        if k == iters {
            break;
        }
        if dc > de {
            hi = e;
            e = c;
            de = dc;
            c = hi - g * (hi - lo);
            dc = map.d(c, w);
        } else {
            lo = c;
            c = e;
            dc = de;
            e = lo + g * (hi - lo);
            de = map.d(e, w);
        }
    }
    None
}

/// Warm search around a neighbour's crossing `r0`: the first `-` to `+` sign change of `D`
/// among 6 log-spaced samples in `[r0 / q, r0 q]`, q = 1.25 then 2; the cold search if
/// neither shows one (a warm bracket is only kept once checked).
pub fn search(
    st: &Stepper,
    cs: &CycleSettings,
    tangency_iters: u32,
    warm: Option<f64>,
    w: &mut Work,
) -> Search {
    let map = ReturnMap::new(st, cs.t_return);
    if let Some(r0) = warm.filter(|r| r.is_finite() && *r > cs.r_min) {
        for q in [1.25f64, 2.0] {
            let (lo, hi) = ((r0 / q).max(cs.r_min), (r0 * q).min(cs.r_max));
            if lo >= hi {
                continue;
            }
            let mut prev = (lo, map.d(lo, w));
            if prev.1 > 0.0 {
                continue;
            }
            for i in 1..6 {
                let r = (lo.ln() + (hi.ln() - lo.ln()) * i as f64 / 5.0).exp();
                let d = map.d(r, w);
                if d > 0.0 {
                    return Search::Bracket {
                        lo: prev.0,
                        hi: r,
                        d: [prev.1, d],
                        warm: true,
                    };
                }
                prev = (r, d);
            }
        }
    }
    search_cold(st, cs, tangency_iters, w)
}

#[cfg(test)]
mod tests;
