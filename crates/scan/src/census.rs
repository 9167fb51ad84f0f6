//! The premise of a map's rules, checked by runs before they decide anything.
//!
//! The start rule ([`crate::scanner::StartRule`]), the trap of the unstable cycle
//! ([`squeal_core::Trap`]) and the band rules ([`squeal_core::Reason::SettledStickSlip`],
//! [`squeal_core::Reason::StickingBand`]) rest on the paper's picture: one unstable cycle
//! around the fixed point, every start inside it ending at the fixed point, every start
//! outside it on a lasting oscillation. The section search that enables them samples one
//! line of the plane for one revolution at a time; it cannot see a picture that is not the
//! paper's. At the README's clamped disc brake (nu = 0.2, 0.375) it found a sign change of the
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
//! [`crate::estimate`] times each map's preparation, so the estimate includes it. Where
//! steady slip attracts, closed turns ([`ClosedTurn`]: one revolution that no run crosses)
//! decide most starts in a revolution or without a run (MODEL.md section 12).

mod turn;

use rayon::prelude::*;
use serde::Serialize;
use squeal_core::orbit::{self, OrbitWatch};
use squeal_core::{
    Classifier, Lasting, Outcome, Reason, Regime, Run, Shortcuts, State, SteadySlip, Stepper,
    TurnWatch,
};

use crate::curve::{ClosedCurve, CurveLocator};
use crate::spec::Plan;
pub use turn::{ClosedTurn, Kept};

/// How many of its crossings of the section a start inside the cycle is followed for, to
/// enter the outermost inside start's inward closed turn, before it is run in full.
pub const ENTRY_CROSSINGS: usize = 32;

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
    /// Starts outside the cycle shown never to reach the fixed point by a closed turn
    /// ([`ClosedTurn`], steady slip attracting): their own first revolution, or another
    /// start's that they lie outside of (no run at all).
    pub kept_outside: usize,
    /// Starts inside the cycle shown to reach the fixed point by the run of the outermost
    /// one, inside whose inward closed turn they lie (no run at all).
    pub kept_inside: usize,
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
/// cycle and 3 inside it (0.9 and 0.5 times). Each with its side of the cycle and whether it
/// lies on the ring.
fn starts(
    plan: &Plan,
    fp: State,
    reach: f64,
    curve: Option<&CurveLocator>,
) -> Vec<(State, Side, bool)> {
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
    let mut out: Vec<(State, Side, bool)> = std::iter::once(State { x: 0.0, v: 0.0 })
        .chain(box_points)
        .map(|p| (p, side(p), false))
        .collect();
    if let Some(c) = curve {
        let cv: &ClosedCurve = c.curve();
        let n = cv.len();
        let scaled = |i: usize, s: f64| State {
            x: fp.x + s * (cv.x[i % n] - fp.x),
            v: fp.v + s * (cv.v[i % n] - fp.v),
        };
        for k in 0..4 {
            out.push((scaled(k * n / 4, RING_OUTSIDE), Side::Outside, true));
        }
        for (i, s) in [(0, 0.9), (n / 2, 0.9), (n / 4, 0.5)] {
            out.push((scaled(i, s), Side::Inside, false));
        }
    }
    out.truncate(MAX_STARTS);
    out
}

/// What a census run did: its own outcome, its last state and, where it was watched with
/// the band rules too, their verdict on the same run if they reached one by its end.
struct Ran {
    own: Outcome,
    end: State,
    band: Option<Outcome>,
}

/// The run from `ic` with `plain` (no trap, no band rules) and the attractors'
/// `certificates` (the fixed point's region, the trapped band) to its `t_max`: its outcome
/// (steady slip where it reached the fixed point or its region, stick-slip where it entered
/// the trapped band, stick-slip or the slip oscillation where its own turns settled on an
/// attractor the orbit certificate holds at `dt` and `dt / 2` with `half`:
/// [`Reason::OnCertifiedOrbit`]; none where `half` is `None`) and its last state. With
/// `band` (the map's classifier without its trap), the same steps are watched by the band
/// rules too: one run gives both verdicts.
fn plain_run(
    (stepper, half, certificates): (&Stepper, Option<&Stepper>, Shortcuts),
    (plain, band): (&Classifier, Option<&Classifier>),
    ic: State,
) -> Ran {
    let p = stepper.params();
    let attracts = SteadySlip::of(p).stability.attracts();
    let mut run = Run::new(stepper, ic);
    let mut watch = plain.watch_with(p, certificates);
    let mut band_watch = band.map(|b| b.watch_with(p, certificates));
    let mut band_said = None;
    let mut turns = TurnWatch::new(p, plain.turn_settings(p));
    let floor = orbit::band_floor(p, plain.fp_radius, attracts);
    let mut orbits = half.map(|h| OrbitWatch::new(h, floor));
    let mut lasting = None;
    let ran = |own: Outcome, run: &Run, band: Option<Outcome>| Ran {
        own,
        end: State {
            x: run.sample().x,
            v: run.sample().v,
        },
        band,
    };
    for _ in 0..run.steps_to(plain.t_max) {
        let step = run.step();
        if band_said.is_none()
            && let Some(w) = band_watch.as_mut()
            && let Some(decision) = w.observe(&run, &step)
        {
            band_said = Some(w.finish(decision, &run));
        }
        if let Some(decision) = watch.observe(&run, &step) {
            return ran(watch.finish(decision, &run), &run, band_said);
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
            return ran(own, &run, band_said);
        }
    }
    let own = watch.finish((Regime::Undecided, Reason::TimeLimit), &run);
    ran(own, &run, band_said)
}

/// How a start of the census ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ended {
    /// Its own run, with this reason.
    Run(Reason),
    /// Outside an outward closed turn: it never reaches the fixed point (no run past the
    /// turn's, none at all where the turn was another start's).
    KeptOutside,
    /// Inside the inward closed turn of the outermost start inside the cycle, whose run
    /// reached the fixed point: so does its own (no run).
    KeptInside,
}

/// What one start of the census found: the rule groups its run refuted, how it ended and
/// when.
struct Found {
    withdrawn: Vec<Withdrawal>,
    ended: Ended,
    t: f64,
}

impl Found {
    /// A start kept by a closed turn, decided at time `t`: it refutes nothing.
    fn kept(ended: Ended, t: f64) -> Found {
        Found {
            withdrawn: Vec::new(),
            ended,
            t,
        }
    }
}

/// The census of a map of `plan` whose stepper is `stepper`, whose rules label a start as
/// `label` does and whose located cycle (if any) is `curve`; `reach` is the radius of the
/// starts' circle where the grid is a single point. `classifier` is the map's; its runs
/// here have no rule.
///
/// Where steady slip attracts, closed turns ([`ClosedTurn`]) spare most runs:
/// * a start on the ring outside the cycle first tries the turn from its first crossing
///   of the section: an outward one shows that it, and every other start outside the
///   cycle that lies outside that turn, never reaches the fixed point, which is all the
///   outside rules' premise asks of them;
/// * the outermost start inside the cycle tries the same: where its turn is inward and the
///   force has one root everywhere inside it, and its run reaches the fixed point, so does
///   every start inside that turn (no periodic orbit there could let it through), and the
///   band rules cannot label them (their amplitudes fall every revolution, never
///   reversing, and they never stick).
pub fn take(
    plan: &Plan,
    (stepper, certificates): (&Stepper, Shortcuts),
    classifier: &Classifier,
    (curve, reach): (Option<&ClosedCurve>, f64),
    label: impl Fn(State) -> Outcome + Sync,
) -> Census {
    let p = stepper.params();
    let plain = Classifier {
        trap: None,
        band_rules: false,
        ..*classifier
    };
    let locator = curve.map(|c| CurveLocator::new(c.clone()));
    let starts = starts(plan, p.fixed_point(), reach, locator.as_ref());
    let halved = stepper.setup().half_dt();
    let half = halved.stepper().expect("half a valid step is valid");
    let band = Classifier {
        trap: None,
        ..*classifier
    };
    let taker = Taker {
        steppers: (stepper, &half),
        certificates,
        classifiers: (&plain, &band),
        locator: locator.as_ref(),
        label: &label,
        turns: SteadySlip::of(p).stability.attracts() && locator.is_some(),
    };
    let (inside, outside) = rayon::join(|| taker.inside(&starts), || taker.outside(&starts));
    let mut found: Vec<(usize, Found)> = inside.into_iter().chain(outside).collect();
    found.sort_by_key(|f| f.0);
    let count = |e: Ended| found.iter().filter(|f| f.1.ended == e).count();
    let ends = found.iter().map(|f| f.1.t).collect();
    let mut withdrawn: Vec<Withdrawal> = Vec::new();
    for w in found.iter().flat_map(|f| f.1.withdrawn.iter()) {
        if !withdrawn.iter().any(|x| x.rules == w.rules) {
            withdrawn.push(*w);
        }
    }
    Census {
        runs: starts.len(),
        horizon: plain.t_max,
        certified: count(Ended::Run(Reason::OnCertifiedOrbit)),
        at_horizon: count(Ended::Run(Reason::TimeLimit)),
        kept_outside: count(Ended::KeptOutside),
        kept_inside: count(Ended::KeptInside),
        ends,
        withdrawn,
    }
}

/// What the census's starts are run and judged with.
struct Taker<'a, L> {
    /// The map's stepper and the same at half the step.
    steppers: (&'a Stepper, &'a Stepper),
    /// The certificates the runs end at.
    certificates: Shortcuts,
    /// The runs' classifier (no rule) and the band rules' (no trap).
    classifiers: (&'a Classifier, &'a Classifier),
    locator: Option<&'a CurveLocator>,
    label: &'a L,
    /// Whether closed turns may decide (steady slip attracts, a cycle was located).
    turns: bool,
}

impl<L: Fn(State) -> Outcome + Sync> Taker<'_, L> {
    /// The run of start `ic` (on `side` of the cycle) and what it refutes.
    fn run(&self, ic: State, side: Side) -> Found {
        let (stepper, half) = self.steppers;
        let (plain, band) = self.classifiers;
        let ran = plain_run(
            (stepper, Some(half), self.certificates),
            (plain, Some(band)),
            ic,
        );
        let band_only = || {
            ran.band
                .unwrap_or_else(|| band.classify_with(stepper, ic, self.certificates))
        };
        refutations((ic, side, &ran), band_only, self.locator, self.label)
    }

    /// The closed turn from the first crossing of the section by the run from `ic`, and the
    /// time of that crossing.
    fn turn_from(&self, ic: State) -> Option<(f64, ClosedTurn)> {
        let (stepper, half) = self.steppers;
        let (t, r) = first_crossing(stepper, ic, self.near())?;
        Some((t, ClosedTurn::certify((stepper, half), r, self.near())?))
    }

    /// The fixed point's radius and certified region: where a run is at the fixed point.
    fn near(&self) -> (f64, Option<&squeal_core::Region>) {
        (
            self.classifiers.0.fp_radius,
            self.certificates.region.as_ref(),
        )
    }

    /// The starts outside the cycle (or with no cycle): the ring's first, each with its own
    /// outward turn where it has one, then the others, kept outside any such turn or run.
    fn outside(&self, starts: &[(State, Side, bool)]) -> Vec<(usize, Found)> {
        let index: Vec<usize> = (0..starts.len()).collect();
        let ring: Vec<(usize, Found, Option<ClosedTurn>)> = index
            .par_iter()
            .filter(|&&i| starts[i].2)
            .map(|&i| {
                let (ic, side, _) = starts[i];
                let outward = self.turns.then(|| self.turn_from(ic)).flatten();
                match outward.filter(|(_, turn)| turn.kept() == Kept::Outside) {
                    Some((t, turn)) => (i, Found::kept(Ended::KeptOutside, t), Some(turn)),
                    None => (i, self.run(ic, side), None),
                }
            })
            .collect();
        let turns: Vec<&ClosedTurn> = ring.iter().filter_map(|r| r.2.as_ref()).collect();
        let rest: Vec<(usize, Found)> = index
            .par_iter()
            .filter(|&&i| starts[i].1 != Side::Inside && !starts[i].2)
            .map(|&i| {
                let (ic, side, _) = starts[i];
                let kept = side == Side::Outside && turns.iter().any(|t| t.keeps(ic));
                match kept {
                    true => (i, Found::kept(Ended::KeptOutside, 0.0)),
                    false => (i, self.run(ic, side)),
                }
            })
            .collect();
        let ring = ring.into_iter().map(|(i, f, _)| (i, f));
        ring.chain(rest).collect()
    }

    /// The starts inside the cycle: the outermost one's run, and every other one inside its
    /// inward closed turn decided by it where it reached the fixed point; the rest run.
    fn inside(&self, starts: &[(State, Side, bool)]) -> Vec<(usize, Found)> {
        let inner: Vec<usize> = (0..starts.len())
            .filter(|&i| starts[i].1 == Side::Inside)
            .collect();
        let Some((&outer, others)) = inner.split_first() else {
            return Vec::new();
        };
        let p = self.steppers.0.params();
        let inward = self
            .turns
            .then(|| self.turn_from(starts[outer].0))
            .flatten()
            .filter(|(_, turn)| turn.kept() == Kept::Inside && turn.one_root_inside(p));
        // Labelled steady slip by the map (a stick-slip label is refuted by its own run, so
        // that start runs), and inside the turn from the start or from one of its first
        // crossings of the section (the run to it never came near the fixed point): the
        // time it entered.
        let covered = |i: usize| -> Option<f64> {
            let (stepper, ic) = (self.steppers.0, starts[i].0);
            let (_, turn) = inward.as_ref()?;
            if (self.label)(ic).regime == Regime::StickSlip {
                return None;
            }
            if turn.keeps(ic) {
                return Some(0.0);
            }
            let x_star = p.fixed_point().x;
            let inside = |r: f64| turn.keeps(State { x: x_star, v: r });
            crossing_where(stepper, ic, self.near(), ENTRY_CROSSINGS, inside).map(|(t, _)| t)
        };
        // The outermost start's run, beside the others' entries into its turn (or their own
        // runs where they do not enter).
        let (outer_found, others_found) = rayon::join(
            || self.run(starts[outer].0, starts[outer].1),
            || {
                others
                    .par_iter()
                    .map(|&i| match covered(i) {
                        Some(t) => (i, Err(t)),
                        None => (i, Ok(self.run(starts[i].0, starts[i].1))),
                    })
                    .collect::<Vec<_>>()
            },
        );
        let settled = matches!(
            outer_found.ended,
            Ended::Run(Reason::EnteredRegion | Reason::NearFixedPoint)
        );
        let mut found = vec![(outer, outer_found)];
        let rest: Vec<(usize, Found)> = others_found
            .into_par_iter()
            .map(|(i, f)| match (f, settled) {
                (Ok(f), _) => (i, f),
                (Err(t), true) => (i, Found::kept(Ended::KeptInside, t)),
                (Err(_), false) => (i, self.run(starts[i].0, starts[i].1)),
            })
            .collect();
        found.extend(rest);
        found
    }
}

/// The rule groups that the run `ran` of the start `ic` (on `side` of the cycle) refutes;
/// `band_only` gives the start's verdict with the band rules alone (no trap).
fn refutations(
    (ic, side, ran): (State, Side, &Ran),
    band_only: impl FnOnce() -> Outcome,
    locator: Option<&CurveLocator>,
    label: &impl Fn(State) -> Outcome,
) -> Found {
    let own = ran.own;
    // Quiet: the fixed point, or the slip oscillation about a steady slip that does not
    // attract; either refutes a stick-slip label.
    let quiet = matches!(own.regime, Regime::SteadySlip | Regime::SlipOscillation);
    let refuted = |rules| Withdrawal {
        rules,
        start: ic,
        run: own.regime,
        t: own.t_decision,
    };
    let mut w = Vec::new();
    if quiet {
        // The label every path gives the start, and the run's own verdict with the band
        // rules alone (no trap; the region ends it, where the band rules cannot fire):
        // each rule that said stick-slip is refuted by this run.
        for l in [label(ic), band_only()] {
            if l.regime == Regime::StickSlip {
                w.extend(Rules::of(l.reason).map(refuted));
            }
        }
        if side == Side::Outside {
            w.push(refuted(Rules::Outside));
        }
    }
    let left = locator.is_some_and(|c| !c.encloses(ran.end));
    // Inside the cycle: a run still moving outside it at the horizon, or certified on a
    // lasting oscillation, refutes the inside rules.
    let lasts = own.reason == Reason::OnCertifiedOrbit;
    if side == Side::Inside && !quiet && (own.reason == Reason::TimeLimit && left || lasts) {
        w.push(refuted(Rules::Inside));
    }
    Found {
        withdrawn: w,
        ended: Ended::Run(own.reason),
        t: own.t_decision,
    }
}

/// The time and amplitude of the first crossing of the section by the run from `ic` (no
/// rule), within [`turn::MAX_PERIODS`] periods; `None` where it comes first within
/// `fp_radius` of the fixed point or into its `region`, or does not cross by then.
fn first_crossing(
    stepper: &Stepper,
    ic: State,
    near: (f64, Option<&squeal_core::Region>),
) -> Option<(f64, f64)> {
    crossing_where(stepper, ic, near, 1, |_| true)
}

/// The time and amplitude of the first of the first `crossings` crossings of the section by
/// the run from `ic` (no rule) at which `stop` holds; `None` where none does, where the run
/// comes first within `fp_radius` of the fixed point or into its `region`, or where it
/// does not cross within [`turn::MAX_PERIODS`] periods of the last crossing.
fn crossing_where(
    stepper: &Stepper,
    ic: State,
    (fp_radius, region): (f64, Option<&squeal_core::Region>),
    crossings: usize,
    mut stop: impl FnMut(f64) -> bool,
) -> Option<(f64, f64)> {
    let fp = stepper.params().fixed_point();
    let mut run = Run::new(stepper, ic);
    let per_turn = run.steps_to(turn::MAX_PERIODS * std::f64::consts::TAU);
    let mut since = 0;
    for _ in 0..crossings {
        loop {
            let step = run.step();
            let s = step.next;
            let near = (s.x - fp.x).hypot(s.v - fp.v) <= fp_radius;
            if near || region.is_some_and(|r| r.contains(s.x, s.v)) || run.failed() {
                return None;
            }
            since += 1;
            if let Some(c) = squeal_core::section::crossing(fp.x, &step.prev, &step.next) {
                since = 0;
                if stop(c.r) {
                    return Some((c.t, c.r));
                }
                break;
            }
            if since > per_turn {
                return None;
            }
        }
    }
    None
}

#[cfg(test)]
mod tests;
