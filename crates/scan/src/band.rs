//! Is the stick-slip band outside the unstable cycle an attractor, or a long transient?
//!
//! Near the fold of cycles the stick-slip band is chaotic, and past its crisis it leaks: runs
//! spend hundreds or thousands of revolutions on it and then fall inside the unstable cycle
//! and end in steady slip (at Table 1, nu = 0.0242, all ten far starts of `edge_long_runs.csv`
//! were at the fixed point by t = 20000 after looking settled at t = 130). A band that looks
//! settled over a window of crossings is no proof of squeal, so the band rules of the
//! classifier ([`squeal_core::Reason::SettledStickSlip`], [`squeal_core::Reason::StickingBand`])
//! are used only where this module finds the band trapped.
//!
//! **The argument.** At a crossing of the section `x = x*`, `x' = r > 0` the block slips
//! (`v = r - lambda < 0` at the bands considered, `r < lambda`), where the force equation
//! has one root: the state is `(x*, r)` alone and the return map `P` is a map of one
//! variable. Let `r_u` be the unstable cycle's crossing, `P(r) > r` on the window
//! `(r_u, s)` above it, and `P(r) <= r` from `s` (the drop where orbits begin to stick).
//! Let `b = max P` over `(r_u, b]` (the top of the band) and `a = min P` over `[s, b]`. If
//! `a > r_u`, the interval `J = [a, b]` is mapped into itself (on `[a, s)`, `r < P(r) <=
//! b`; on `[s, b]`, `a <= P(r) <= b`): a run whose amplitude enters `J` never falls
//! inside the cycle, and the band is an attractor. If `a < r_u`, part of the band maps
//! inside the cycle: the band has a hole, and (a chaotic band visiting its whole interval)
//! every run on it leaves sooner or later. That is a boundary crisis: `a - r_u` changes sign
//! between nu = 0.0240 (+0.0016) and 0.0242 (-0.0034) at Table 1's values (400 uniform
//! samples on `(r_u, 3]`: `cargo run --release -p squeal-scan --example band_margin -- 400
//! 0.0240 0.0242`).
//!
//! **What is sampled, and the margin.** `P` is known at samples only: [`NSAMPLES`] uniform
//! samples on `(r_u, top]` (`top` 1.1 times the search's first crossing with `D <= 0`
//! above the cycle, widened while the largest return lies above it), then a golden-section refinement of the largest `P` and of the smallest `P`
//! above the window. The verdict is [`Band::Trapped`] only when `a` clears `r_u` by more
//! than the change of `P` over one sample spacing at the smallest sample (or
//! [`crate::section::RESOLUTION`] `r_u`, whichever is larger): a dip of `P` narrower than
//! a sample can still be missed. Where `a` is within that margin of `r_u` the verdict is
//! [`Band::Marginal`], treated as a leak: runs are followed until they reach the fixed point
//! or `t_max` (undecided), never labelled stick-slip by their band.

use serde::Serialize;

use squeal_core::Setup;

use crate::error::ScanError;
use crate::section::CycleSettings;
use crate::section::{
    Precision, RESOLUTION, RISE_FACTOR, ReturnCache, ReturnMap, SectionCycles, Work,
    search_section_to,
};

/// Uniform samples of `P` over the band.
pub const NSAMPLES: usize = 128;

/// Golden-section steps refining the band's top and bottom.
const GOLDEN_STEPS: u32 = 12;

/// The verdict on the band above an unstable cycle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Band {
    /// `[lo, hi]` is mapped into itself above the cycle: the band is an attractor.
    Trapped { lo: f64, hi: f64 },
    /// The start `r` of the band (`r <= hi`) returns to `p < r_u`, inside the cycle: the
    /// band leaks, runs on it end in steady slip sooner or later.
    Leaks { r: f64, p: f64, hi: f64 },
    /// The smallest sampled return `p` above the window clears `r_u` by less than `margin`,
    /// or `unresolved` intervals between samples could still dip below it: not decided,
    /// treated as a leak.
    Marginal {
        p: f64,
        margin: f64,
        unresolved: usize,
    },
    /// `P > r` up to the largest sample: no band top was seen.
    NoTop,
}

impl Band {
    /// Whether runs may be labelled stick-slip by their band.
    pub fn attracts(&self) -> bool {
        matches!(self, Band::Trapped { .. })
    }
}

/// The band above the unstable cycle crossing at `r_u`, sampled first up to `top` (the
/// search's first crossing with `D <= 0` above the cycle, say) and further out while the
/// largest return exceeds the sampled range. Counted in `w`.
pub fn band_above(map: &ReturnMap, r_u: f64, top: f64, w: &mut Work) -> Band {
    band_above_n(map, r_u, top, NSAMPLES, w)
}

/// [`band_above`] with `n` uniform samples instead of [`NSAMPLES`] (the longer horizon of
/// [`Budget::Longer`]).
pub fn band_above_n(map: &ReturnMap, r_u: f64, top: f64, n: usize, w: &mut Work) -> Band {
    let (mut rs, mut ps) = uniform(map, r_u, top, n, w);
    let Some(s) = (0..rs.len()).find(|&i| ps[i] <= rs[i]) else {
        return Band::NoTop;
    };
    // The band's top: the largest return from the window (and above it, up to the top).
    let h = rs[1] - rs[0];
    let k = (0..rs.len())
        .max_by(|&i, &j| ps[i].total_cmp(&ps[j]))
        .unwrap_or(0);
    let b = ps[k].max(golden(map, rs[k] - h, rs[k] + h, 1.0, w).1);
    // The band's bottom: the returns of the starts in [s, b], refined where a dip below
    // the cycle could hide between two samples.
    let end = rs.iter().rposition(|&r| r <= b).unwrap_or(s).max(s);
    rs.truncate(end + 1);
    ps.truncate(end + 1);
    let (mut rs, mut ps) = (rs.split_off(s), ps.split_off(s));
    let unresolved = refine_dips(map, r_u, (&mut rs, &mut ps), 4 * n, w);
    let m = (0..rs.len())
        .min_by(|&i, &j| ps[i].total_cmp(&ps[j]))
        .unwrap_or(0);
    let (r_a, a) = (rs[m], ps[m]);
    if a < r_u {
        Band::Leaks {
            r: r_a,
            p: a,
            hi: b,
        }
    } else if unresolved > 0 || a - r_u <= RESOLUTION * r_u {
        Band::Marginal {
            p: a,
            margin: RESOLUTION * r_u,
            unresolved,
        }
    } else {
        Band::Trapped { lo: a, hi: b }
    }
}

/// `n` returns `(r, P(r))` uniform on `(r_u, 1.1 top]`, widened (twice at most) while the
/// largest return lies above the range.
fn uniform(map: &ReturnMap, r_u: f64, top: f64, n: usize, w: &mut Work) -> (Vec<f64>, Vec<f64>) {
    let mut top = 1.1 * top.max(r_u);
    for _ in 0..3 {
        let h = (top - r_u) / n as f64;
        let rs: Vec<f64> = (1..=n).map(|i| r_u + h * i as f64).collect();
        let ps: Vec<f64> = rs.iter().map(|&r| r + map.d(r, w)).collect();
        let b = ps.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if b <= top {
            return (rs, ps);
        }
        top = 1.1 * b;
    }
    let h = (top - r_u) / n as f64;
    let rs: Vec<f64> = (1..=n).map(|i| r_u + h * i as f64).collect();
    let ps = rs.iter().map(|&r| r + map.d(r, w)).collect();
    (rs, ps)
}

/// Halves the intervals of the band's samples where `P` could dip below `r_u` between two
/// samples, down to the relative width [`RESOLUTION`] or `budget` extra returns; returns how
/// many such intervals are left (budget spent, or at the resolution).
///
/// `P` jumps where orbits begin to stick, so no slope bounds it across an interval with a
/// jump; between jumps it is smooth. An interval is cleared when
/// `(P_i + P_{i+1} - L h) / 2 > r_u`, `L` being [`RISE_FACTOR`] times the steeper of its two neighbours' sampled
/// slopes: the lowest a smooth `P` that steep could reach between the samples (a jump
/// inside the interval then lies between its samples' values and cannot dip).
fn refine_dips(
    map: &ReturnMap,
    r_u: f64,
    (rs, ps): (&mut Vec<f64>, &mut Vec<f64>),
    budget: usize,
    w: &mut Work,
) -> usize {
    let slope = |rs: &[f64], ps: &[f64], j: usize| (ps[j + 1] - ps[j]).abs() / (rs[j + 1] - rs[j]);
    let (mut extra, mut unresolved) = (0usize, 0usize);
    let mut i = 0;
    while i + 1 < rs.len() {
        let left = if i > 0 { slope(rs, ps, i - 1) } else { 0.0 };
        let right = if i + 2 < rs.len() {
            slope(rs, ps, i + 1)
        } else {
            0.0
        };
        let h = rs[i + 1] - rs[i];
        let floor = 0.5 * (ps[i] + ps[i + 1] - RISE_FACTOR * left.max(right) * h);
        // Both ends without a return (`P = 0`, the least `P` there is: a time-out, or a run
        // settled on an oscillation off the section): no sample between them can lower the
        // band's bottom, nor come before the first of them, so the verdict and its values
        // are those of the unrefined interval (at a real brake every start of the
        // band falls into such an oscillation, and halving them spent the whole budget).
        if floor > r_u || (ps[i] <= 0.0 && ps[i + 1] <= 0.0) {
            i += 1;
            continue;
        }
        if h <= RESOLUTION * rs[i] || extra >= budget {
            unresolved += 1;
            i += 1;
            continue;
        }
        let mid = 0.5 * (rs[i] + rs[i + 1]);
        extra += 1;
        rs.insert(i + 1, mid);
        ps.insert(i + 1, mid + map.d(mid, w));
    }
    unresolved
}

/// Golden-section search on `[lo, hi]` for the largest (`sign = 1`) or smallest
/// (`sign = -1`) return `P`; returns the best `(r, P(r))` evaluated.
fn golden(map: &ReturnMap, mut lo: f64, mut hi: f64, sign: f64, w: &mut Work) -> (f64, f64) {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let p = |r: f64, w: &mut Work| r + map.d(r, w);
    let (mut c, mut e) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut pc, mut pe) = (p(c, w), p(e, w));
    let mut best = if sign * pc >= sign * pe {
        (c, pc)
    } else {
        (e, pe)
    };
    for _ in 0..GOLDEN_STEPS {
        if sign * pc >= sign * pe {
            hi = e;
            e = c;
            pe = pc;
            c = hi - g * (hi - lo);
            pc = p(c, w);
            if sign * pc > sign * best.1 {
                best = (c, pc);
            }
        } else {
            lo = c;
            c = e;
            pc = pe;
            e = lo + g * (hi - lo);
            pe = p(e, w);
            if sign * pe > sign * best.1 {
                best = (e, pe);
            }
        }
    }
    best
}

/// What the section says of lasting squeal at one parameter set (the scan's rule,
/// [`crate::scanner::outside_of`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Lasting {
    /// Some start squeals for good: the fixed point repels, or the outside of the unstable
    /// cycle is invariant, or the band above it is trapped.
    Squeals,
    /// The band's verdict is marginal (or its top was not seen): not decided.
    Undecided,
    /// No start squeals for good: no unstable cycle, or the band above it leaks.
    Quiet,
}

/// How hard the band's verdict looks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Budget {
    /// [`NSAMPLES`] uniform samples of the band, the settings' `t_return`.
    Standard,
    /// The longer horizon: twice the samples (and twice the refinement budget) and twice
    /// `t_return` (the longest single revolution). The verdict is a property of the return
    /// map, not of a run's length; these are what it does depend on.
    Longer,
}

impl Budget {
    /// Uniform samples of the band.
    pub fn samples(self) -> usize {
        match self {
            Budget::Standard => NSAMPLES,
            Budget::Longer => 2 * NSAMPLES,
        }
    }

    /// The cycle settings `cs` with this budget's `t_return`.
    pub fn settings(self, cs: &CycleSettings) -> CycleSettings {
        match self {
            Budget::Standard => *cs,
            Budget::Longer => CycleSettings {
                t_return: 2.0 * cs.t_return,
                ..*cs
            },
        }
    }
}

/// [`Lasting`] at `setup`, from the section searched with `cs`.
pub fn lasting(setup: Setup, cs: &CycleSettings) -> Result<Lasting, ScanError> {
    lasting_with(setup, cs, Budget::Standard)
}

/// [`lasting`] with the band looked at with `budget`.
pub fn lasting_with(
    setup: Setup,
    cs: &CycleSettings,
    budget: Budget,
) -> Result<Lasting, ScanError> {
    lasting_on(setup, cs, budget, &ReturnCache::default())
}

/// [`lasting_with`] reading and filling `cache`, the returns of `setup`'s stepper (the
/// verdict with the longer horizon reuses those of the verdict at the same step). The
/// cycle's crossing is bisected only as far as the verdict needs ([`Precision::Escape`]):
/// the verdict is the one [`Precision::Rtol`] gives.
pub fn lasting_on(
    setup: Setup,
    cs: &CycleSettings,
    budget: Budget,
    cache: &ReturnCache,
) -> Result<Lasting, ScanError> {
    let st = setup.stepper()?;
    let cs = &budget.settings(cs);
    let map = ReturnMap::cached(&st, cs.t_return, cache);
    let found = search_section_to(&map, cs, Precision::Escape, &mut Work::default());
    Ok(match found {
        SectionCycles::FixedPointUnstable { .. } => Lasting::Squeals,
        SectionCycles::NoneBelow { .. } => Lasting::Quiet,
        SectionCycles::Unstable { .. } => match outside_on(&map, &found, budget.samples()) {
            Some(Outside::Escapes { band, .. }) => match band {
                Band::Trapped { .. } => Lasting::Squeals,
                Band::Leaks { .. } => Lasting::Quiet,
                Band::Marginal { .. } | Band::NoTop => Lasting::Undecided,
            },
            _ => Lasting::Squeals,
        },
    })
}

mod crisis;
mod outside;
/// The stick-slip band above the unstable cycle where it is trapped
/// ([`Band::Trapped`]: an interval of the section mapped into itself with a
/// margin): the certificate that a run on it squeals for good, for the runs that check the
/// rules. Where the outside escapes, the band was already examined; where it is invariant
/// it is examined here (128 returns and their refinement).
pub(crate) fn trapped(
    stepper: &squeal_core::Stepper,
    cs: &CycleSettings,
    found: SectionCycles,
    outside: Option<Outside>,
) -> Option<(f64, f64)> {
    let SectionCycles::Unstable {
        r, stable_above, ..
    } = found
    else {
        return None;
    };
    let band = match outside? {
        Outside::Escapes { band, .. } => band,
        Outside::Invariant => {
            let map = crate::section::ReturnMap::new(stepper, cs.t_return);
            let top = stable_above.unwrap_or(2.0 * r);
            band_above(&map, r, top, &mut crate::section::Work::default())
        }
    };
    match band {
        Band::Trapped { lo, hi } => Some((lo, hi)),
        _ => None,
    }
}

pub use crisis::{
    COARSE, Crisis, CrisisStatus, SharedReturns, Variant, crisis_in, crisis_nu, raise_top,
};
pub use outside::{Outside, outside_of, outside_on, outside_with};

/// The stick-slip band above the unstable cycle crossing at `r_u`, as the sampled interval
/// `[s, b]` of the section ([`band_above`]'s samples): `s` the first sampled start above the
/// cycle that does not rise (`P(s) <= s`, the drop where orbits begin to stick), `b` the
/// largest sampled return (the band's top). `None` if every sample rises. The starts of the
/// transient lifetimes ([`crate::lifetime`]).
pub fn band_span(map: &ReturnMap, r_u: f64, top: f64, w: &mut Work) -> Option<(f64, f64)> {
    let (rs, ps) = uniform(map, r_u, top, NSAMPLES, w);
    let s = (0..rs.len()).find(|&i| ps[i] <= rs[i])?;
    let b = ps.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (b > rs[s]).then_some((rs[s], b))
}
