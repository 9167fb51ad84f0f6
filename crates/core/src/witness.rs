//! Certified fates of whole stretches of the section, from a few followed starts (laws of the
//! slip velocity only; crates/core/MODEL.md section 9, "A monotone return map").
//!
//! **The argument.** For a law whose force depends on the slip velocity only (the Stribeck
//! law), the state is the phase-plane point `(x, x')`: while the block slips the flow is
//! smooth, and a stick phase is a state of the plane too (`x' = v_d` until the one breakaway
//! state). The flow is unique forward in time, so two orbits never cross; they can only
//! merge (at a stick onset, or on the stick segment). The section `x = x*, x' > 0` is
//! crossed left to right by every orbit (`x' > 0`), so the return map `P` on it is
//! non-decreasing (the orbit from `r' > r` stays outside the curve made by the orbit from
//! `r` and the section between `r` and `P(r)`), and so is every iterate `P^k`. Hence:
//!
//! * **Steady slip is a down-set.** If the run from `(x*, s)` reaches the certified region
//!   of attraction at its `k`-th crossing `P^k(s)`, inside the part of the section that the
//!   region holds, then for `r <= s`, `P^k(r) <= P^k(s)`: the run from `r` is in the region
//!   by its `k`-th crossing (or entered it before, or converged to the fixed point without
//!   crossing again). Every crossing of the orbit from `s` is such an `s` too.
//! * **Stick-slip between two sticking starts.** If the runs from `a < b` both stick, each
//!   then follows the orbit from the one breakaway state; where that orbit is the stick-slip
//!   cycle they are on it, so `P^k(a) = P^k(b) = r_c` (the cycle's one crossing) for large
//!   `k`, and `P^k(r) = r_c` for every `r` between: the run from `r` is on the cycle.
//!
//! A run is then labelled at its first crossing that lies at or below the highest settling
//! witness ([`crate::Reason::BelowSettlingStart`]) or between the lowest and the highest
//! sticking witness ([`crate::Reason::BetweenStickingStarts`]). The witnesses are the starts
//! followed here and every crossing of their runs before their decision (each is a start on
//! the same orbit). Only certified decisions make a witness (the region, the orbit from
//! breakaway), never a band rule or `t_max`.
//!
//! **The check.** The argument rests on the monotone map; the scheme approximates the flow.
//! Every pair (crossing, next crossing) the witnesses and a row of one-return samples give
//! is checked: a pair whose return is lower than that of a lower start by more than
//! [`MONOTONE_TOL`] voids the certificate (no shortcut at all), and so does a settling
//! witness above a sticking one. Audited cells run to settlement without it.

use crate::classify::{Classifier, Reason, Regime, Shortcuts, crossing, section_return};
use crate::run::Run;
use crate::solver::SolverStats;
use crate::stepper::{State, Stepper};
pub use crate::verdict::SectionFates;

/// Allowed decrease of the sampled return map between two starts (absolute, section
/// amplitudes are O(1)). The flow's map is monotone; the scheme's can differ from it by the
/// step error, where two orbits merged at a stick and broke away inside different steps
/// (about `dt^2` per revolution, `2.5e-5` at `dt = 0.005`, where the merged orbits do not
/// cross the section while stuck). At bSTAB's 11 belt speeds without an unstable cycle the
/// largest decrease measured is `1.1e-16`, rounding (test
/// `the_sampled_return_map_is_monotone_where_the_certificate_is_used`); a failure of the
/// argument itself would show at the size of the amplitudes.
pub const MONOTONE_TOL: f64 = 1e-4;

/// Starts followed from the bottom of the section (log-spaced), after the top one.
const STARTS: usize = 8;

/// One-return samples that only check the map's monotonicity (log-spaced).
const CHECK_SAMPLES: usize = 16;

/// The lowest start, as a share of the highest (runs that cross the section lower than the
/// lowest sticking witness are run on until they cross higher).
const LOWEST_SHARE: f64 = 2.5e-4;

/// What the followed starts and the samples showed: witnesses with their certified fate,
/// and pairs `(r, P(r))` of the return map.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Evidence {
    /// Section amplitudes whose runs end in steady slip by a certified decision.
    pub settling: Vec<f64>,
    /// Section amplitudes whose runs stick onto the stick-slip cycle.
    pub sticking: Vec<f64>,
    /// Pairs `(r, P(r))` of the sampled return map.
    pub returns: Vec<(f64, f64)>,
}

impl Evidence {
    /// The certificate, or `None` where the samples contradict the argument (a decreasing
    /// pair of the return map, or a settling witness at or above a sticking one) or no
    /// witness decided.
    pub fn certify(self) -> Option<SectionFates> {
        if self.largest_decrease() > MONOTONE_TOL {
            return None;
        }
        let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
        let settles_up_to = Some(max(&self.settling)).filter(|s| s.is_finite());
        let sticks_within = Some((min(&self.sticking), max(&self.sticking)))
            .filter(|(lo, hi)| lo.is_finite() && hi.is_finite());
        if let (Some(s), Some((lo, _))) = (settles_up_to, sticks_within) {
            if s >= lo {
                return None;
            }
        }
        let fates = SectionFates {
            settles_up_to,
            sticks_within,
        };
        fates.any().then_some(fates)
    }

    /// Follows the run from `(x*, r)` with the classifier `cl` and `shortcuts` to its
    /// decision; a certified one makes the start and every crossing before it a witness,
    /// and consecutive crossings are pairs of the return map. Returns the certified regime.
    pub fn follow(
        &mut self,
        stepper: &Stepper,
        cl: &Classifier,
        shortcuts: Shortcuts,
        r: f64,
    ) -> Option<Regime> {
        let fp = stepper.params().fixed_point();
        let mut run = Run::new(stepper, State { x: fp.x, v: r });
        let mut watch = cl.watch_with(stepper.params(), shortcuts);
        let mut points = vec![r];
        let mut decision = None;
        for _ in 0..run.steps_to(cl.t_max) {
            let step = run.step();
            if let Some(c) = crossing(fp.x, &step.prev, &step.next) {
                points.push(c.r);
            }
            if let Some(d) = watch.observe(&run, &step) {
                decision = Some(d);
                break;
            }
        }
        self.returns.extend(points.windows(2).map(|w| (w[0], w[1])));
        let fate = match decision?.1 {
            Reason::EnteredRegion | Reason::StuckThenSettles => Regime::SteadySlip,
            Reason::StuckOntoCycle | Reason::StickCycle => Regime::StickSlip,
            _ => return None,
        };
        match fate {
            Regime::SteadySlip => self.settling.extend(&points),
            _ => self.sticking.extend(&points),
        }
        Some(fate)
    }

    /// Whether the certificate so far already decides amplitude `r` (no need to follow it).
    fn covers(&self, r: f64) -> bool {
        self.clone()
            .certify()
            .is_some_and(|f| f.decide(r).is_some())
    }
}

/// The certified fates of the section for the map of `stepper` (a law of the slip velocity
/// only), with the classifier `cl` and its certified `shortcuts` (region, orbit from
/// breakaway), from starts up to `r_max` ([`section_evidence`]).
pub fn section_fates(
    stepper: &Stepper,
    cl: &Classifier,
    shortcuts: Shortcuts,
    r_max: f64,
) -> Option<SectionFates> {
    let mut fates = section_evidence(stepper, cl, shortcuts, r_max)?.certify()?;
    // The down-set needs runs in the region to keep crossing the section: a focus, whose
    // linear damping `2 xi + mu'(v_d)` is below 2 (a node's runs may converge without
    // crossing again).
    if !stepper
        .params()
        .fixed_point_damping()
        .is_some_and(|d| d < 2.0)
    {
        fates.settles_up_to = None;
    }
    fates.any().then_some(fates)
}

/// What [`section_fates`] certifies from: the top start first (in a map where every start
/// settles it decides the whole section below it), then starts from the bottom up, skipping
/// those the witnesses so far already decide; then one-return samples for the monotonicity
/// check. `None` for a law that depends on more than the slip velocity.
pub fn section_evidence(
    stepper: &Stepper,
    cl: &Classifier,
    shortcuts: Shortcuts,
    r_max: f64,
) -> Option<Evidence> {
    if !stepper.params().law.family().has_section_witnesses() || r_max.is_nan() || r_max <= 0.0 {
        return None;
    }
    let mut ev = Evidence::default();
    let r_min = LOWEST_SHARE * r_max;
    let log = |k: usize, n: usize| r_min * (r_max / r_min).powf(k as f64 / (n - 1) as f64);
    ev.follow(stepper, cl, shortcuts, r_max);
    for k in 0..STARTS - 1 {
        let r = log(k, STARTS);
        if !ev.covers(r) {
            ev.follow(stepper, cl, shortcuts, r);
        }
    }
    let t_return = cl.t_max.min(100.0);
    let mut stats = SolverStats::default();
    for k in 0..CHECK_SAMPLES {
        let r = log(k, CHECK_SAMPLES);
        if let Ok(c) = section_return(stepper, r, t_return, &mut stats, |_| {}) {
            ev.returns.push((r, c.r));
        }
    }
    Some(ev)
}

impl Evidence {
    /// The largest decrease of the sampled return map: over pairs sorted by start, how far
    /// a return lies below the highest return of a lower start (0 for a monotone sample).
    pub fn largest_decrease(&self) -> f64 {
        let mut pairs = self.returns.clone();
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut highest = f64::NEG_INFINITY;
        let mut worst = 0.0f64;
        for &(_, p) in &pairs {
            worst = worst.max(highest - p);
            highest = highest.max(p);
        }
        worst
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn evidence(settling: &[f64], sticking: &[f64], returns: &[(f64, f64)]) -> Evidence {
        Evidence {
            settling: settling.to_vec(),
            sticking: sticking.to_vec(),
            returns: returns.to_vec(),
        }
    }

    /// The certificate's stretches: at or below the highest settling witness, and between
    /// the lowest and highest sticking one; nothing elsewhere.
    #[test]
    fn stretches_are_the_down_set_and_the_hull() {
        let f = evidence(&[0.1, 0.4], &[0.9, 2.0, 1.5], &[(0.1, 0.05), (0.9, 1.2)])
            .certify()
            .unwrap();
        assert_eq!(f.settles_up_to, Some(0.4));
        assert_eq!(f.sticks_within, Some((0.9, 2.0)));
        let regime = |r| f.decide(r).map(|d| d.0);
        assert_eq!(regime(0.4), Some(Regime::SteadySlip));
        assert_eq!(regime(1e-6), Some(Regime::SteadySlip));
        assert_eq!(regime(0.6), None);
        assert_eq!(regime(1.0), Some(Regime::StickSlip));
        assert_eq!(regime(2.0), Some(Regime::StickSlip));
        assert_eq!(regime(2.01), None);
        assert_eq!(evidence(&[], &[], &[]).certify(), None);
    }

    /// A sampled return map that decreases by more than the tolerance, or a settling
    /// witness above a sticking one, voids the certificate: the argument does not hold
    /// there, so nothing is decided by it.
    #[test]
    fn contradictions_void_the_certificate() {
        let monotone = [(0.5, 0.4), (1.0, 0.8), (2.0, 0.8)];
        assert!(evidence(&[2.0], &[], &monotone).certify().is_some());
        let bent = [(0.5, 0.4), (1.0, 0.8), (2.0, 0.8 - 2.0 * MONOTONE_TOL)];
        assert_eq!(evidence(&[2.0], &[], &bent).certify(), None);
        let jitter = [(1.0, 0.8), (2.0, 0.8 - 0.5 * MONOTONE_TOL)];
        assert!(evidence(&[2.0], &[], &jitter).certify().is_some());
        assert_eq!(evidence(&[1.0], &[0.9, 2.0], &[]).certify(), None);
    }
}
