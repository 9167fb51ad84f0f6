//! The premise of a map's rules, checked by runs before they decide anything (issue 31).
//!
//! The start rule ([`crate::scanner::StartRule`]), the trap of the unstable cycle
//! ([`squeal_core::Trap`]) and the band rules ([`squeal_core::Reason::SettledStickSlip`],
//! [`squeal_core::Reason::StickingBand`]) rest on the paper's picture: one unstable cycle
//! around the fixed point, every start inside it ending at the fixed point, every start
//! outside it on a lasting oscillation. The section search that enables them samples one
//! line of the plane for one revolution at a time; it cannot see a picture that is not the
//! paper's. At the disc brake of issue 31 (nu = 0.2, 0.375) it found a sign change of the
//! return map, the start rule labelled 96% of random starts stick-slip, and their runs
//! reached the fixed point by t = 33-55.
//!
//! So, for McMillan's laws, a map first runs a spread of starts ([`starts`]: the state at
//! rest, the corners and edge midpoints of the grid, a ring just outside the located cycle
//! and a few starts inside it) to the horizon [`Census::horizon`] (the classifier's
//! `t_max`: what a run of the scan itself may take) with no rule at all: a run is at the
//! fixed point when it comes within `fp_radius` of it or enters its certified region, on a
//! lasting oscillation when its own maxima settle on an attractor of the turn map that the
//! orbit certificates hold ([`squeal_core::orbit`], [`Reason::OnCertifiedOrbit`]), else
//! still moving at the horizon.
//! A group of rules is withdrawn ([`Withdrawn`]) where a run contradicts its premise:
//! * the outside rules (`start_outside_cycle`, `outside_cycle`), where a start outside the
//!   cycle reaches the fixed point;
//! * the inside rules (`start_inside_cycle`, `inside_cycle`), where a start inside the cycle
//!   has not reached the fixed point by the horizon and lies outside the cycle there, or is
//!   certified on a lasting oscillation;
//! * the rule that labelled a start stick-slip (as every path labels it, or by the band
//!   rules alone) where that start's run reaches the fixed point.
//!
//! Cells are then decided by runs (the fixed point reached, or undecided at `t_max`). The
//! census costs at most [`MAX_STARTS`] runs of `t_max` per map, in parallel; the pilot of
//! [`crate::estimate`] times each map's preparation, so the estimate includes it.

use rayon::prelude::*;
use serde::Serialize;
use squeal_core::orbit::{self, OrbitWatch};
use squeal_core::{
    Classifier, Lasting, Outcome, Reason, Regime, Run, Shortcuts, State, SteadySlip, Stepper,
    TurnWatch,
};

use crate::curve::{ClosedCurve, CurveLocator};
use crate::spec::Plan;

/// At most this many starts per map (1 at rest, 8 on the grid's box, 4 on the ring outside
/// the cycle, 3 inside it).
pub const MAX_STARTS: usize = 16;

/// How far outside the cycle the ring lies: each of its starts is a point of the cycle's
/// curve moved away from the fixed point by this factor (well beyond the start rule's
/// margin, still in the cycle's neighbourhood).
pub const RING_OUTSIDE: f64 = 1.1;

/// A group of rules that rest on one premise.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Rules {
    /// `start_outside_cycle` and `outside_cycle`: outside the cycle, a lasting oscillation.
    Outside,
    /// `start_inside_cycle` and `inside_cycle`: inside the cycle, the fixed point.
    Inside,
    /// `settled_stick_slip` and `sticking_band`: a band that looks settled lasts.
    Band,
    /// The certified shortcuts ([`squeal_core::Shortcuts`]: the region, the decaying
    /// section and turns, the section's certified stretches, the orbit from breakaway).
    Shortcuts,
}

impl Rules {
    /// The group's name in files and output.
    pub fn name(self) -> &'static str {
        match self {
            Rules::Outside => "start_outside_cycle+outside_cycle",
            Rules::Inside => "start_inside_cycle+inside_cycle",
            Rules::Band => "settled_stick_slip+sticking_band",
            Rules::Shortcuts => "shortcuts",
        }
    }

    /// Every group, in index order.
    pub const ALL: [Rules; 4] = [Rules::Outside, Rules::Inside, Rules::Band, Rules::Shortcuts];

    /// The group of that name ([`Rules::name`]).
    pub fn from_name(name: &str) -> Option<Rules> {
        Rules::ALL.into_iter().find(|r| r.name() == name)
    }

    /// The group a reason of a stick-slip or steady-slip label belongs to, if any.
    pub fn of(reason: Reason) -> Option<Rules> {
        match reason {
            Reason::StartOutsideCycle | Reason::OutsideCycle => Some(Rules::Outside),
            Reason::StartInsideCycle | Reason::InsideCycle => Some(Rules::Inside),
            Reason::SettledStickSlip | Reason::StickingBand | Reason::InTrappedBand => {
                Some(Rules::Band)
            }
            Reason::EnteredRegion
            | Reason::StartInRegion
            | Reason::StuckOntoCycle
            | Reason::StuckThenSettles
            | Reason::BelowSettlingStart
            | Reason::BetweenStickingStarts
            | Reason::BelowDecayingSection
            | Reason::StartInsideDecayingTurn
            | Reason::EnteredDecayingTurn => Some(Rules::Shortcuts),
            _ => None,
        }
    }
}

/// A rule group withdrawn in a map, and the run that refuted it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Withdrawal {
    /// The group.
    pub rules: Rules,
    /// The start whose run contradicted the premise.
    pub start: State,
    /// What its run did: reached the fixed point at `t` (`steady_slip`), or was still
    /// moving, outside the cycle, at the horizon (`undecided`).
    pub run: Regime,
    /// The time of that finding.
    pub t: f64,
}

impl std::fmt::Display for Withdrawal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let what = match self.run {
            Regime::SteadySlip => format!("reached the fixed point at t = {:.6}", self.t),
            _ => format!("was still outside the cycle at t = {:.6}", self.t),
        };
        write!(
            f,
            "{} withdrawn: the run from ({:.6}, {:.6}) {what}",
            self.rules.name(),
            self.start.x,
            self.start.v
        )
    }
}

/// The census of one map: its starts' runs and the rule groups they refuted.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Census {
    /// Runs made.
    pub runs: usize,
    /// Their horizon (the classifier's `t_max`).
    pub horizon: f64,
    /// Runs that ended on an attractor their own maxima certified
    /// ([`Reason::OnCertifiedOrbit`]) before the horizon.
    pub certified: usize,
    /// Runs that reached the horizon still moving (no certificate held).
    pub at_horizon: usize,
    /// When each run ended (its decision, or the horizon), in start order.
    pub ends: Vec<f64>,
    /// The groups withdrawn, each with its first refuting run (in start order).
    pub withdrawn: Vec<Withdrawal>,
}

impl Census {
    /// Whether the group `rules` was withdrawn.
    pub fn withdraws(&self, rules: Rules) -> bool {
        self.withdrawn.iter().any(|w| w.rules == rules)
    }

    /// One line per withdrawn group (empty when every premise held).
    pub fn lines(&self) -> Vec<String> {
        self.withdrawn.iter().map(|w| w.to_string()).collect()
    }
}

/// Where a start lies against the located cycle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Side {
    Inside,
    Outside,
    /// No cycle located: only the refutation of a stick-slip label applies.
    Unknown,
}

/// The census starts of a map of `plan` with fixed point `fp` and located cycle `curve`:
/// the state at rest, the corners and edge midpoints of the grid's box (of a circle of
/// radius `reach` around `fp` where the grid is a single point, as for `squeal classify`
/// and `trajectory`), and, with a cycle, 4 points of the ring [`RING_OUTSIDE`] times the
/// cycle and 3 inside it (0.9 and 0.5 times). Each with its side of the cycle.
fn starts(plan: &Plan, fp: State, reach: f64, curve: Option<&CurveLocator>) -> Vec<(State, Side)> {
    let g = &plan.map.grid;
    let (x0, v0) = (g.x0, g.v0);
    let mid = |a: f64, b: f64| 0.5 * (a + b);
    let mut box_points = Vec::new();
    if x0.max > x0.min || v0.max > v0.min {
        for x in [x0.min, mid(x0.min, x0.max), x0.max] {
            for v in [v0.min, mid(v0.min, v0.max), v0.max] {
                if !(x == mid(x0.min, x0.max) && v == mid(v0.min, v0.max)) {
                    box_points.push(State { x, v });
                }
            }
        }
    } else {
        for k in 0..8 {
            let a = k as f64 * std::f64::consts::FRAC_PI_4;
            box_points.push(State {
                x: fp.x + reach * a.cos(),
                v: fp.v + reach * a.sin(),
            });
        }
    }
    let side = |p: State| match curve {
        None => Side::Unknown,
        Some(c) if c.encloses(p) => Side::Inside,
        Some(_) => Side::Outside,
    };
    let mut out: Vec<(State, Side)> = std::iter::once(State { x: 0.0, v: 0.0 })
        .chain(box_points)
        .map(|p| (p, side(p)))
        .collect();
    if let Some(c) = curve {
        let cv: &ClosedCurve = c.curve();
        let n = cv.len();
        let scaled = |i: usize, s: f64| State {
            x: fp.x + s * (cv.x[i % n] - fp.x),
            v: fp.v + s * (cv.v[i % n] - fp.v),
        };
        for k in 0..4 {
            out.push((scaled(k * n / 4, RING_OUTSIDE), Side::Outside));
        }
        for (i, s) in [(0, 0.9), (n / 2, 0.9), (n / 4, 0.5)] {
            out.push((scaled(i, s), Side::Inside));
        }
    }
    out.truncate(MAX_STARTS);
    out
}

/// The run from `ic` with `plain` (no trap, no band rules) and the attractors'
/// `certificates` (the fixed point's region, the trapped band) to its `t_max`: its outcome
/// (steady slip where it reached the fixed point or its region, stick-slip where it entered
/// the trapped band, stick-slip or the slip oscillation where its own turns settled on an
/// attractor the orbit certificate holds at `dt` and `dt / 2` with `half`:
/// [`Reason::OnCertifiedOrbit`]; none where `half` is `None`) and its last state.
fn plain_run(
    (stepper, half, certificates): (&Stepper, Option<&Stepper>, Shortcuts),
    plain: &Classifier,
    ic: State,
) -> (Outcome, State) {
    let p = stepper.params();
    let attracts = SteadySlip::of(p).stability.attracts();
    let mut run = Run::new(stepper, ic);
    let mut watch = plain.watch_with(p, certificates);
    let mut turns = TurnWatch::new(p, plain.turn_settings(p));
    let floor = orbit::band_floor(p, plain.fp_radius, attracts);
    let mut orbits = half.map(|h| OrbitWatch::new(h, floor));
    let mut lasting = None;
    let end = |run: &Run| State {
        x: run.sample().x,
        v: run.sample().v,
    };
    for _ in 0..run.steps_to(plain.t_max) {
        let step = run.step();
        if let Some(decision) = watch.observe(&run, &step) {
            return (watch.finish(decision, &run), end(&run));
        }
        if turns.observe_step(&run, &step).is_some() {
            lasting = turns.lasting();
        }
        // Certificates are tried once the turns pass a band test (a lasting oscillation).
        if let Some(w) = orbits.as_mut()
            && w.observe(&run, &step, lasting.is_some()).is_some()
        {
            let regime = Lasting::regime(lasting.as_ref(), attracts);
            let own = watch.finish((regime, Reason::OnCertifiedOrbit), &run);
            return (own, end(&run));
        }
    }
    (
        watch.finish((Regime::Undecided, Reason::TimeLimit), &run),
        end(&run),
    )
}

/// The census of a map of `plan` whose stepper is `stepper`, whose rules label a start as
/// `label` does and whose located cycle (if any) is `curve`; `reach` is the radius of the
/// starts' circle where the grid is a single point. `classifier` is the map's; its runs
/// here have no rule.
pub fn take(
    plan: &Plan,
    (stepper, certificates): (&Stepper, Shortcuts),
    classifier: &Classifier,
    (curve, reach): (Option<&ClosedCurve>, f64),
    label: impl Fn(State) -> Outcome + Sync,
) -> Census {
    let fp = stepper.params().fixed_point();
    let plain = Classifier {
        trap: None,
        band_rules: false,
        ..*classifier
    };
    let locator = curve.map(|c| CurveLocator::new(c.clone()));
    let starts = starts(plan, fp, reach, locator.as_ref());
    let halved = stepper.setup().half_dt();
    let half = halved.stepper().expect("half a valid step is valid");
    let found: Vec<(Vec<Withdrawal>, Reason, f64)> = starts
        .par_iter()
        .map(|&(ic, side)| {
            let (own, end) = plain_run((stepper, Some(&half), certificates), &plain, ic);
            // Quiet: the fixed point, or the slip oscillation about a steady slip that does
            // not attract; either refutes a stick-slip label.
            let quiet = matches!(own.regime, Regime::SteadySlip | Regime::SlipOscillation);
            let refuted = |rules| Withdrawal {
                rules,
                start: ic,
                run: own.regime,
                t: own.t_decision,
            };
            let mut w = Vec::new();
            if quiet {
                // The label every path gives the start, and the run's own verdict with the
                // band rules alone (no trap, no shortcut): each rule that said stick-slip is
                // refuted by this run.
                let band_only = Classifier {
                    trap: None,
                    ..*classifier
                }
                .classify(stepper, ic);
                for l in [label(ic), band_only] {
                    if l.regime == Regime::StickSlip {
                        w.extend(Rules::of(l.reason).map(refuted));
                    }
                }
                if side == Side::Outside {
                    w.push(refuted(Rules::Outside));
                }
            }
            let left = locator.as_ref().is_some_and(|c| !c.encloses(end));
            // Inside the cycle: a run still moving outside it at the horizon, or certified on
            // a lasting oscillation, refutes the inside rules.
            let lasts = own.reason == Reason::OnCertifiedOrbit;
            if side == Side::Inside && !quiet && (own.reason == Reason::TimeLimit && left || lasts)
            {
                w.push(refuted(Rules::Inside));
            }
            (w, own.reason, own.t_decision)
        })
        .collect();
    let count = |r: Reason| found.iter().filter(|f| f.1 == r).count();
    let (certified, at_horizon) = (count(Reason::OnCertifiedOrbit), count(Reason::TimeLimit));
    let ends = found.iter().map(|f| f.2).collect();
    let mut withdrawn: Vec<Withdrawal> = Vec::new();
    for w in found.into_iter().flat_map(|f| f.0) {
        if !withdrawn.iter().any(|x| x.rules == w.rules) {
            withdrawn.push(w);
        }
    }
    Census {
        runs: starts.len(),
        horizon: plain.t_max,
        certified,
        at_horizon,
        ends,
        withdrawn,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MapContext;

    /// The disc brake of issue 31 at c = 300 N s/m: nu = c / 800 = 0.375, lambda = 0.21053,
    /// tau = 0.65789, phi = 0.91353, on a 3 x 3 grid over x0 in [-1, 2], x'0 in [-0.5, 0.5].
    fn brake() -> Plan {
        Plan::from_toml(
            r#"version = 1
[model]
law = "mcmillan"
nu = 0.375
lambda = 0.21053
tau = 0.65789
phi = 0.91353
[grid]
x0 = { min = -1.0, max = 2.0, count = 3 }
v0 = { min = -0.5, max = 0.5, count = 3 }
[classifier]
t_max = 2000.0
[output]
path = "t.h5"
"#,
            "t.toml",
        )
        .unwrap()
    }

    /// Issue 31: at the brake's c = 300, `classify` and `scan` on 48d225a labelled these
    /// starts stick_slip by `start_outside_cycle` without a run, while their runs end quiet
    /// (on d424b26: "near_fixed_point at t = 35.8 from (0, 0), 21.4 from (2, 0.5), 38.3 from
    /// (-1, -0.5)", a radius crossing). The census withdrew the outside rules there. Steady slip
    /// itself repels at this brake (k = (1 - 2/pi) tau / lambda = 1.1355 > 1, MODEL.md
    /// section 5): the runs end on the slip oscillation about it (half-range of x 1.6e-4), the
    /// section search finds no cycle, and no rule of the paper's picture applies. The truth
    /// here is each start's own run with no rule to t = 2000; the map's label must be the same.
    #[test]
    fn brake_labels_match_their_runs() {
        let plan = brake();
        let ctx = MapContext::prepare(&plan, 0).unwrap();
        let plain = Classifier {
            trap: None,
            band_rules: false,
            ..plan.map.classifier
        };
        for (x, v) in [(0.0, 0.0), (2.0, 0.5), (-1.0, -0.5), (2.0, -0.5)] {
            let ic = State { x, v };
            let (truth, _) = plain_run((&ctx.stepper, None, Shortcuts::NONE), &plain, ic);
            assert_eq!(truth.regime, Regime::SlipOscillation, "{ic:?}: {truth:?}");
            let label = ctx.classify(ic);
            assert_eq!(label.regime, truth.regime, "{ic:?}: {label:?}");
        }
        assert!(
            ctx.start_rule.is_none() && ctx.classifier.trap.is_none(),
            "{ctx:?}"
        );
    }

    /// Fig. 9 (the main job's map, its grid's box): every run of the census that does not
    /// enter the fixed point's region ends on a certified attractor of its own turn map
    /// before t_max = 5000 (the stick-slip band, whose maxima never converge: section 10's
    /// band certificate), and no rule is withdrawn. Before the band certificate, the 13 starts
    /// outside the cycle all ran to t_max (measured: 13 at the horizon, 0 certified). Each
    /// certificate is checked against its own run in crates/core/tests/model/orbit.rs.
    #[test]
    fn fig9_census_runs_end_on_certified_attractors_not_at_the_horizon() {
        let plan = Plan::from_toml(
            r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
lambda = 3.0
[grid]
x0 = { min = -3.0, max = 5.0, count = 4 }
v0 = { min = -4.0, max = 4.0, count = 4 }
[classifier]
t_max = 5000.0
early_stop = "cycle"
[cycle]
locate = true
[output]
path = "t.h5"
"#,
            "t.toml",
        )
        .unwrap();
        let ctx = MapContext::prepare(&plan, 0).unwrap();
        let census = ctx.census.expect("McMillan's law takes a census");
        assert_eq!(census.runs, MAX_STARTS, "{census:?}");
        assert_eq!(census.at_horizon, 0, "{census:?}");
        // 1 at rest, 8 on the box, 4 on the ring outside the cycle; the 3 inside settle.
        assert_eq!(census.certified, 13, "{census:?}");
        assert!(census.withdrawn.is_empty(), "{census:?}");
        // When each run ended (printed with --nocapture; MODEL.md section 12 quotes them):
        // rest and the box by a few hundred time units, the ring and the inside later.
        println!("census run ends at Fig. 9: {:?}", census.ends);
        assert!(census.ends[..9].iter().all(|&t| t < 1000.0), "{census:?}");
        assert!(census.ends.iter().all(|&t| t < 5000.0), "{census:?}");
    }
}
