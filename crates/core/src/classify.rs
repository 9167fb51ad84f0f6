//! One initial condition to a label: which attractor does the run settle on?
//!
//! The phase plane holds the stable steady-slip fixed point `(x*, 0)`, around it an unstable
//! limit cycle, and further out the stable stick-slip oscillation. Runs are watched on the
//! Poincare section `S = { x = x*, x' > 0 }`, which every revolution crosses once, going
//! right; the value `r` of `x'` at a crossing is the run's *section amplitude*.
//!
//! Decisions, checked at every step or crossing:
//! * [`Reason::NearFixedPoint`]: the state is within `fp_radius` of the fixed point:
//!   steady slip (the radius must lie well inside the unstable cycle).
//! * [`Reason::SettledStickSlip`]: over the last `settle_cycles` crossings the section
//!   amplitudes stay in a band of relative width `settle_rtol` and show no trend (a run near
//!   the unstable cycle drifts steadily away, the stick-slip band does not): stick-slip.
//! * With a [`Trap`] (the unstable cycle's crossing `r_u` of `S`, located beforehand): a
//!   crossing below `r_u - margin` is inside the cycle, a crossing above `r_u + margin` is
//!   outside it. In the plane a trajectory cannot cross the cycle, so the label is decided:
//!   [`Reason::InsideCycle`] / [`Reason::OutsideCycle`]. This is the early-stopping rule;
//!   tests check it against runs taken to settlement.
//! * [`Reason::LastingOscillation`]: the last `settle_cycles` turns of the run (maximum of
//!   `x` to maximum, [`crate::turns`]) stay in a band without trend and none crossed the
//!   section: an oscillation the section's rules cannot see (a real brake's swing below
//!   `x*`). Stick-slip; decided only where no turn of the window crossed, so no
//!   label the section rules give changes.
//! * Otherwise, at `t_max`: [`Regime::Undecided`] with [`Reason::TimeLimit`]; never a guess.
//!   A run that blows up or whose robust solve fails is undecided too.
//!
//! Label names the attractor. "Reached belt speed" is not used: with true roots the
//! hysteretic stick-slip loop need not reach `lambda` (crates/core/MODEL.md, section 5).

use std::collections::VecDeque;

use serde::Serialize;

use crate::friction::Branch;
use crate::params::Params;
use crate::run::{Run, Step};
use crate::solver::SolverStats;
use crate::stepper::{State, Stepper};
use crate::turns::{Lasting, TurnSettings, TurnWatch};

pub use crate::section::{Crossing, Half, crossing, section_return};
pub use crate::verdict::{Reason, Regime};

/// Where steady slip does not attract, the turns' band floor is this share of `fp_radius`:
/// no run closes on the point, so a small band is the slip oscillation about it (at lambda
/// 0.35, tau 1, phi 0.9, nu 0.1 its half-range is about 1e-4).
pub const SLIP_FLOOR: f64 = 1e-3;

/// The unstable cycle's crossing of the section, for early stopping.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Trap {
    /// Section amplitudes below this are inside the unstable cycle.
    pub r_inner: f64,
    /// Section amplitudes above this are outside the unstable cycle (infinite where the
    /// outside is not invariant: [`Reason::OutsideCycle`] then never fires).
    pub r_outer: f64,
}

/// Certified early decisions of one parameter point, beside the classifier's settings
/// (MODEL.md section 9). Each one rests on a written argument; `None` where it does not
/// apply. Runs to settlement (audits, `early_stop = "none"`) use [`Shortcuts::NONE`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Shortcuts {
    /// The certified region of attraction of the fixed point: a run that enters it is steady
    /// slip ([`Reason::EnteredRegion`]).
    pub region: Option<crate::Region>,
    /// A law with true stick: the regime the orbit from the breakaway state ends in (the
    /// landscape's stick-slip cycle or its decay), where known. Every stick phase ends at
    /// that state, so a run that sticks ends there too ([`Reason::StuckOntoCycle`],
    /// [`Reason::StuckThenSettles`]).
    pub breakaway: Option<Regime>,
    /// A law of the slip velocity only: stretches of the section whose fate followed starts
    /// certify ([`crate::witness`]); a run is decided at its first crossing inside one.
    pub section: Option<crate::verdict::SectionFates>,
    /// No unstable cycle on the section: `D(r) = P(r) - r < 0` at every sample of the
    /// adaptive search up to its top `r_top`, which resolves any window of growth wider than
    /// its stated resolution. A crossing below this value (`r_top` less the trap's margin)
    /// returns lower, and so does every later one: steady slip
    /// ([`Reason::BelowDecayingSection`]). It rests on the same sampled return map as the
    /// cycle's trap and is audited the same way.
    pub decay_below: Option<f64>,
    /// Where [`Shortcuts::decay_below`] holds: a turn of the orbit from the section's lower
    /// half at `s` (closed by that half between `s` and its return), on the slip branch with
    /// one root all along and below that top, and this value is `s` less the trap's margin.
    /// A crossing of the lower half below it lies inside the turn, which no run leaves:
    /// steady slip ([`Reason::EnteredDecayingTurn`]).
    pub decay_lower_below: Option<f64>,
    /// The stick-slip band's interval `[lo, hi]` on the section that the return map maps
    /// into itself with a margin (a trapped band): a crossing inside it with one root never
    /// leaves it ([`Reason::InTrappedBand`]).
    pub trapped_band: Option<(f64, f64)>,
}

impl Shortcuts {
    /// No shortcut: every run goes to settlement.
    pub const NONE: Shortcuts = Shortcuts {
        region: None,
        breakaway: None,
        section: None,
        decay_below: None,
        decay_lower_below: None,
        trapped_band: None,
    };

    /// Whether any shortcut applies.
    pub fn any(&self) -> bool {
        self.region.is_some()
            || self.breakaway.is_some()
            || self.section.is_some()
            || self.decay_below.is_some()
            || self.decay_lower_below.is_some()
            || self.trapped_band.is_some()
    }

    /// The decision for a run that stuck, from the fate of the orbit from breakaway.
    fn after_stick(&self) -> Option<(Regime, Reason)> {
        match self.breakaway? {
            Regime::StickSlip => Some((Regime::StickSlip, Reason::StuckOntoCycle)),
            Regime::SteadySlip => Some((Regime::SteadySlip, Reason::StuckThenSettles)),
            Regime::Undecided | Regime::SlipOscillation => None,
        }
    }
}

/// Classifier settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Classifier {
    /// Give up (undecided) at this time.
    pub t_max: f64,
    /// Steady slip once this close to the fixed point.
    pub fp_radius: f64,
    /// Crossings in the window of the stick-slip settling test.
    pub settle_cycles: u32,
    /// Relative band width of the stick-slip settling test.
    pub settle_rtol: f64,
    /// Undecided (diverged) beyond this `|x|` or `|x'|`.
    pub max_radius: f64,
    /// Early stopping on the located unstable cycle, if any.
    pub trap: Option<Trap>,
    /// Whether a run may be labelled stick-slip by its section amplitudes
    /// ([`Reason::SettledStickSlip`], [`Reason::StickingBand`]). Off where the return map
    /// jumps past the unstable cycle and no stick-slip attractor was found outside it: a
    /// long transient there looks like a band and still ends in steady slip.
    pub band_rules: bool,
}

impl Default for Classifier {
    fn default() -> Self {
        Classifier {
            t_max: crate::defaults::T_MAX,
            fp_radius: 1e-3,
            settle_cycles: 20,
            settle_rtol: 0.05,
            max_radius: 1e6,
            trap: None,
            band_rules: true,
        }
    }
}

/// The label and diagnostics of one run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Outcome {
    /// The attractor.
    pub regime: Regime,
    /// Why the run stopped.
    pub reason: Reason,
    /// Time at the decision.
    pub t_decision: f64,
    /// The last section amplitude (`x'` at the last crossing of `x = x*`), NaN if none;
    /// for [`Reason::LastingOscillation`] (no crossing in its window), the oscillation's
    /// largest `x'` over the window ([`Lasting::v_range`]).
    pub amplitude: f64,
    /// Distance from the fixed point at the decision.
    pub distance: f64,
    /// Angular frequency of the last revolution, `2 pi / (t_k - t_{k-1})`, NaN if unknown;
    /// for [`Reason::LastingOscillation`], that of the window's turns ([`Lasting::omega`]).
    pub omega: f64,
    /// Crossings of the section.
    pub crossings: u32,
    /// Whether any step was on the quasi-static branch of the law.
    pub quasi_static: bool,
    /// Solver counters.
    pub stats: SolverStats,
    /// Largest residual `|G(F)|` of any solve.
    pub max_residual: f64,
    /// Time spent on stick-slip before the run settled ([`t_squeal`]): the end of the last
    /// step on which the block stuck, 0 if it never stuck; infinite for stick-slip;
    /// [`T_SQUEAL_UNKNOWN`] where it is not known.
    pub t_squeal: f64,
    /// The lasting oscillation the run was identified on ([`Lasting`]: frequency, extent,
    /// whether it sticks and reverses its slip), where the label is stick-slip and the turn
    /// watch closed a window on it; `None` otherwise.
    pub lasting: Option<Lasting>,
}

/// The stored `t_squeal` of a run whose time on stick-slip before settling is not known: it
/// did not settle (undecided), or an early decision does not bound its later sticking
/// ([`Reason::StuckThenSettles`], [`Reason::BelowSettlingStart`]). Negative, so no time.
pub const T_SQUEAL_UNKNOWN: f64 = -1.0;

/// A run's time on stick-slip before it settled, from its decision and the end `last_stuck`
/// of the last step on which it stuck (0 if none), as stored per cell (crates/core/MODEL.md,
/// section 6, "t_squeal"):
/// * stick-slip: infinite. The label is an attractor the run never leaves (a trapped band,
///   the located cycle's outside, a stick-slip cycle).
/// * steady slip: `last_stuck`, where no revolution can stick after the decision. Near the
///   fixed point, inside the unstable cycle and in the certified region the run stays in a
///   slip region of the plane (the cycle lies on the slip branch; the region's box keeps
///   `x'` below the belt speed); nothing more is to come. Starts decided there without a run
///   have 0.
/// * [`T_SQUEAL_UNKNOWN`] for undecided runs and for the shortcuts that stop a run before
///   its last stick is seen: [`Reason::StuckThenSettles`] decides at a stick onset (the
///   stick phase, and its breakaway, are still to come); [`Reason::BelowSettlingStart`] and
///   [`Reason::BelowDecayingSection`] bound the run's amplitudes, not its sticking (a
///   crossing below the decaying section's top may still be above the belt speed); and
///   [`Reason::StartInsideDecayingTurn`] and [`Reason::EnteredDecayingTurn`] know that the
///   turn around the state never sticks, not that the states inside it cannot.
pub fn t_squeal(regime: Regime, reason: Reason, last_stuck: f64) -> f64 {
    match (regime, reason) {
        (Regime::StickSlip, _) => f64::INFINITY,
        (Regime::Undecided | Regime::SlipOscillation, _)
        | (_, Reason::StuckThenSettles)
        | (_, Reason::BelowSettlingStart)
        | (_, Reason::BelowDecayingSection)
        | (_, Reason::StartInsideDecayingTurn)
        | (_, Reason::EnteredDecayingTurn) => T_SQUEAL_UNKNOWN,
        (Regime::SteadySlip, _) => last_stuck,
    }
}

/// What a stored `t_squeal` says, for output (JSON has no infinity).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Squeal {
    /// The run never stuck before it settled (`t_squeal = 0`).
    Never,
    /// It squealed until `t_squeal` and then settled in steady slip.
    Transient { t_squeal: f64 },
    /// It squeals for good (stick-slip).
    Lasting,
    /// Not known ([`T_SQUEAL_UNKNOWN`], or not computed).
    Unknown,
}

impl Squeal {
    /// From a stored `t_squeal`.
    pub fn of(t_squeal: f64) -> Squeal {
        match t_squeal {
            t if t == f64::INFINITY => Squeal::Lasting,
            0.0 => Squeal::Never,
            t if t > 0.0 && t.is_finite() => Squeal::Transient { t_squeal: t },
            _ => Squeal::Unknown,
        }
    }

    /// In words (nondimensional time).
    pub fn words(self) -> String {
        match self {
            Squeal::Never => "never stuck before settling (t_squeal = 0)".into(),
            Squeal::Transient { t_squeal } => {
                format!("squealed until t_squeal = {t_squeal:.6}, then settled")
            }
            Squeal::Lasting => "squeals for good (t_squeal = inf)".into(),
            Squeal::Unknown => "time on stick-slip not known (t_squeal = -1)".into(),
        }
    }
}

impl Classifier {
    /// Validates the settings; the error names the setting.
    pub fn validate(&self) -> Result<(), crate::CoreError> {
        let bad = crate::CoreError::invalid::<()>;
        if !self.t_max.is_finite() || self.t_max <= 0.0 {
            return bad("t_max", self.t_max, "a finite time > 0");
        }
        if !self.fp_radius.is_finite() || self.fp_radius <= 0.0 {
            return bad("fp_radius", self.fp_radius, "a finite radius > 0");
        }
        if self.settle_cycles < 4 {
            return bad(
                "settle_cycles",
                self.settle_cycles as f64,
                "at least 4 crossings",
            );
        }
        if !self.settle_rtol.is_finite() || self.settle_rtol <= 0.0 || self.settle_rtol >= 1.0 {
            return bad(
                "settle_rtol",
                self.settle_rtol,
                "a relative width in (0, 1)",
            );
        }
        if !self.max_radius.is_finite() || self.max_radius <= 0.0 {
            return bad("max_radius", self.max_radius, "a finite radius > 0");
        }
        Ok(())
    }

    /// Runs from `ic` until a decision or `t_max`.
    pub fn classify(&self, stepper: &Stepper, ic: State) -> Outcome {
        self.classify_with(stepper, ic, Shortcuts::NONE)
    }

    /// Runs from `ic` until a decision or `t_max`, with the certified `shortcuts`.
    pub fn classify_with(&self, stepper: &Stepper, ic: State, shortcuts: Shortcuts) -> Outcome {
        let mut run = Run::new(stepper, ic);
        let mut watch = self.watch_with(stepper.params(), shortcuts);
        for _ in 0..run.steps_to(self.t_max) {
            let step = run.step();
            if let Some(decision) = watch.observe(&run, &step) {
                return watch.finish(decision, &run);
            }
        }
        watch.finish((Regime::Undecided, Reason::TimeLimit), &run)
    }

    /// The classifier's state for one run of a model with parameters `p`: feed it every step
    /// with [`Watch::observe`] until it decides, then [`Watch::finish`].
    pub fn watch(&self, p: &Params) -> Watch<'_> {
        self.watch_with(p, Shortcuts::NONE)
    }

    /// [`Classifier::watch`] with the certified `shortcuts`.
    pub fn watch_with(&self, p: &Params, shortcuts: Shortcuts) -> Watch<'_> {
        let steady = crate::steady::SteadySlip::of(p);
        let turn_settings = self.turn_settings_with(steady.stability.attracts());
        Watch {
            cl: self,
            shortcuts,
            fp: p.fixed_point(),
            fp_r2: self.fp_radius * self.fp_radius,
            ring: VecDeque::with_capacity(self.settle_cycles as usize),
            stuck: VecDeque::with_capacity(self.settle_cycles as usize),
            stuck_now: false,
            sticks: 0,
            multi_root: 0,
            true_stick: p.law.family().locates_stick(),
            broke_away: false,
            steady,
            crossings: 0,
            last_t: f64::NAN,
            omega: f64::NAN,
            amplitude: f64::NAN,
            last_stuck: 0.0,
            turns: TurnWatch::new(p, turn_settings),
            lasting: None,
        }
    }

    /// The turns' band test for runs of the model `p`: [`TurnSettings::of`] this classifier,
    /// with the floor at [`SLIP_FLOOR`] `fp_radius` where steady slip does not attract (no run
    /// closes on it, so a small band is an oscillation about it, not a decay).
    pub fn turn_settings(&self, p: &Params) -> TurnSettings {
        self.turn_settings_with(crate::steady::SteadySlip::of(p).stability.attracts())
    }

    /// [`Classifier::turn_settings`] where steady slip `attracts` or not.
    fn turn_settings_with(&self, attracts: bool) -> TurnSettings {
        let mut s = TurnSettings::of(self);
        if !attracts {
            s.floor = SLIP_FLOOR * self.fp_radius;
        }
        s
    }

    /// The stick-slip settling test on a full window of section amplitudes
    /// ([`narrow_band`] with this classifier's band width and floor).
    fn settled(&self, ring: &[f64]) -> bool {
        narrow_band(ring, self.settle_rtol, self.band_floor())
    }

    /// The smallest amplitude a band may reach: `10 fp_radius`. A window that dips to it
    /// is a run closing on the fixed point, not a band.
    pub fn band_floor(&self) -> f64 {
        10.0 * self.fp_radius
    }
}

/// The narrow-band test on a full window of amplitudes `ring` (section amplitudes for the
/// classifier's [`Reason::SettledStickSlip`], turn amplitudes for
/// [`crate::turns::TurnWatch`]): a band of relative width `rtol` above `floor` that goes up
/// and down, with no trend. Near the unstable cycle the amplitudes drift monotonically (the
/// return map of the planar slip-branch flow is monotone), slowly at first and then faster,
/// so a window can fit a 5% band with a small half-to-half trend: the reversals tell it
/// from the stick-slip band (measured at Table 1, nu = 1e-2: starts just inside the cycle
/// drifted from 2.087 to 1.99 in 20 crossings and were labelled stick-slip without this
/// check). Near the fixed point they shrink geometrically; on the stick-slip loop they
/// jitter inside a quasi-periodic band. A window whose spread is below `1e-9` of its mean
/// is a settled periodic orbit (nothing left to reverse).
pub fn narrow_band(ring: &[f64], rtol: f64, floor: f64) -> bool {
    let (lo, hi, mean) = extent(ring);
    if lo.is_nan() || lo <= floor || hi - lo > rtol * mean {
        return false;
    }
    let spread = hi - lo;
    if spread <= 1e-9 * mean {
        return true;
    }
    no_trend(ring, mean, spread, 0.5)
}

/// The converging-band test on a full window of amplitudes `ring` (turn amplitudes for
/// [`crate::turns::TurnWatch`]; not a section rule): within the relative width `rtol` above
/// `floor`, and either no monotone trend across its thirds (the means of its first, middle
/// and last third do not move the same way twice) or a trend that slows down geometrically
/// toward a limit inside the band: with `d1`, `d2` the changes of the thirds' means and
/// `q = d2 / d1` in `[0, 1)`, the rest of the trend, `d2 q / (1 - q)`, is at most `rtol`
/// times the last third's mean. A run settling onto a cycle whose changes have shrunk below
/// [`narrow_band`]'s reversal threshold (`1e-4` of the mean: measured at the README's disc
/// brake, the turns' half-ranges converge to 0.066782 with changes of `1e-6` and no counted
/// reversal) passes. A decay to a point does not, however slow: for `a_k = A q^k` the rest
/// of the trend is the whole last mean. Nor does a drift away from an unstable orbit (`q >=
/// 1`).
pub fn converging_band(ring: &[f64], rtol: f64, floor: f64) -> bool {
    let (lo, hi, mean) = extent(ring);
    if lo.is_nan() || lo <= floor || hi - lo > rtol * mean || ring.len() < 3 {
        return false;
    }
    let k = ring.len() / 3;
    let third = |a: usize| ring[a..a + k].iter().sum::<f64>() / k as f64;
    let (m1, m2, m3) = (third(0), third((ring.len() - k) / 2), third(ring.len() - k));
    let (d1, d2) = (m2 - m1, m3 - m2);
    if d1 * d2 <= 0.0 {
        return true;
    }
    let q = d2 / d1;
    q < 1.0 && (d2 * q / (1.0 - q)).abs() <= rtol * m3
}

/// The wide-band test of [`Reason::StickingBand`] on a full window of amplitudes `ring`
/// (whether the oscillation sticks is checked by the caller): bounded above `floor`, spread
/// no wider than the mean, reversing, no trend.
pub fn wide_band(ring: &[f64], floor: f64) -> bool {
    let (lo, hi, mean) = extent(ring);
    let spread = hi - lo;
    if lo.is_nan() || lo <= floor || spread > mean {
        return false;
    }
    no_trend(ring, mean, spread, 0.25)
}

/// Smallest, largest and mean value of a window.
fn extent(ring: &[f64]) -> (f64, f64, f64) {
    let (lo, hi) = ring
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &r| {
            (l.min(r), h.max(r))
        });
    (lo, hi, ring.iter().sum::<f64>() / ring.len() as f64)
}

/// At least one reversal in four values, and half-to-half means apart by at most `trend`
/// times the spread.
fn no_trend(ring: &[f64], mean: f64, spread: f64, trend: f64) -> bool {
    if 4 * reversals(ring, mean) < ring.len() {
        return false;
    }
    let half = ring.len() / 2;
    let m1 = ring[..half].iter().sum::<f64>() / half as f64;
    let m2 = ring[ring.len() - half..].iter().sum::<f64>() / half as f64;
    (m2 - m1).abs() <= trend * spread
}

/// Reversals of direction in a window of section amplitudes: consecutive changes of opposite
/// sign, each larger than `1e-4 mean` (smaller ones are within the rounding of the crossing's
/// interpolation inside a step, which can jitter a run sitting on the unstable cycle).
fn reversals(ring: &[f64], mean: f64) -> usize {
    let tol = 1e-4 * mean;
    ring.windows(3)
        .filter(|w| {
            let (d1, d2) = (w[1] - w[0], w[2] - w[1]);
            d1 * d2 < 0.0 && d1.abs() > tol && d2.abs() > tol
        })
        .count()
}

/// The classifier's view of one run: what it has seen of the section crossings.
#[derive(Clone, Debug)]
pub struct Watch<'c> {
    cl: &'c Classifier,
    shortcuts: Shortcuts,
    fp: State,
    fp_r2: f64,
    ring: VecDeque<f64>,
    /// For each crossing in `ring`: whether the revolution that ended there stuck.
    stuck: VecDeque<bool>,
    /// Whether the revolution in progress has stuck.
    stuck_now: bool,
    /// The run's Coulomb stick count at the last step.
    sticks: u64,
    /// The run's count of steps with several roots, at the last step.
    multi_root: u64,
    /// The law sticks with located events ([`Reason::StickCycle`] applies).
    true_stick: bool,
    /// The run has broken away from a stick phase.
    broke_away: bool,
    /// Steady slip's linearisation. Where it does not attract every start near the point
    /// (it repels, attracts a sector only, or is marginal), coming near it decides nothing,
    /// except inside the sector it attracts ([`crate::SteadySlip::closes_in_sector`]).
    steady: crate::steady::SteadySlip,
    crossings: u32,
    last_t: f64,
    omega: f64,
    amplitude: f64,
    /// End of the last step on which the block stuck (0 if none yet).
    last_stuck: f64,
    /// The run's turns ([`Reason::LastingOscillation`]).
    turns: TurnWatch,
    /// The lasting oscillation of the last closed turn's window, if its band test passed.
    lasting: Option<Lasting>,
}

impl Watch<'_> {
    /// Observes one step of `run` (the step just taken); returns the decision, if any.
    pub fn observe(&mut self, run: &Run, step: &Step) -> Option<(Regime, Reason)> {
        let n = &step.next;
        if run.failed() {
            return Some((Regime::Undecided, Reason::SolverFailure));
        }
        if !n.x.is_finite() || !n.v.is_finite() {
            return Some((Regime::Undecided, Reason::Diverged));
        }
        let (dx, dv) = (n.x - self.fp.x, n.v - self.fp.v);
        if dx * dx + dv * dv < self.fp_r2
            && (self.steady.stability.attracts() || self.steady.closes_in_sector(dx, dv, n.a))
        {
            return Some((Regime::SteadySlip, Reason::NearFixedPoint));
        }
        if self.shortcuts.region.is_some_and(|r| r.contains(n.x, n.v)) {
            return Some((Regime::SteadySlip, Reason::EnteredRegion));
        }
        if n.x.abs() > self.cl.max_radius || n.v.abs() > self.cl.max_radius {
            return Some((Regime::Undecided, Reason::Diverged));
        }
        // Stuck on this step: the quasi-static branch of McMillan's laws, a Coulomb stick
        // counted by the solver, or a located stick phase of a law with true stick.
        // (The band rules' "revolution stuck" keeps its own test, the first two.)
        let sticks = run.stats().sticks;
        let slip_stuck = step.solution.branch == Branch::QuasiStatic || sticks > self.sticks;
        self.sticks = sticks;
        if slip_stuck || step.events.stuck || step.events.onsets > 0 {
            self.last_stuck = n.t;
        }
        if self.true_stick {
            if let Some(decision) = self.stick_events(&step.events) {
                return Some(decision);
            }
        }
        self.stuck_now |= slip_stuck;
        // A lasting oscillation off the section: its turns' band, none crossing.
        if self.turns.observe_step(run, step).is_some() {
            self.lasting = self.turns.lasting();
            if !self.steady.stability.attracts()
                && self.lasting.is_some_and(|l| !l.stuck && !l.reversed)
            {
                return Some((Regime::SlipOscillation, Reason::SlipOscillation));
            }
            if self.lasting.is_some_and(|l| l.misses_section()) {
                return Some((Regime::StickSlip, Reason::LastingOscillation));
            }
        }
        let multi_root = run.stats().multi_root;
        let one_root = multi_root == self.multi_root;
        self.multi_root = multi_root;
        // Inside the lower decaying turn with one root: the run from here is the run from a
        // start there, which the turn holds (MODEL.md section 9).
        if let Some(below) = self.shortcuts.decay_lower_below.filter(|_| one_root) {
            if Half::Lower
                .crossing(self.fp.x, &step.prev, n)
                .is_some_and(|c| c.r < below)
            {
                return Some((Regime::SteadySlip, Reason::EnteredDecayingTurn));
            }
        }
        let c = crossing(self.fp.x, &step.prev, n)?;
        self.at_crossing(&c, one_root)
    }

    /// The decision at a crossing `c` of the section (counted here): a certified stretch of
    /// the section, the decaying section, the unstable cycle's trap, or the band rules over
    /// the last `settle_cycles` crossings.
    fn at_crossing(&mut self, c: &Crossing, one_root: bool) -> Option<(Regime, Reason)> {
        self.crossings += 1;
        if self.last_t.is_finite() {
            self.omega = std::f64::consts::TAU / (c.t - self.last_t);
        }
        self.last_t = c.t;
        self.amplitude = c.r;
        if let Some(d) = self.shortcuts.section.and_then(|s| s.decide(c.r)) {
            return Some(d);
        }
        // The crossing's state determines its future only where its force is the one root
        // there (with several, the branch is history): then it is the sampled start at `r`.
        if one_root && self.shortcuts.decay_below.is_some_and(|top| c.r < top) {
            return Some((Regime::SteadySlip, Reason::BelowDecayingSection));
        }
        if one_root
            && self
                .shortcuts
                .trapped_band
                .is_some_and(|(lo, hi)| lo <= c.r && c.r <= hi)
        {
            return Some((Regime::StickSlip, Reason::InTrappedBand));
        }
        if let Some(trap) = self.cl.trap {
            if c.r < trap.r_inner {
                return Some((Regime::SteadySlip, Reason::InsideCycle));
            }
            if c.r > trap.r_outer {
                return Some((Regime::StickSlip, Reason::OutsideCycle));
            }
        }
        let window = self.cl.settle_cycles as usize;
        if self.ring.len() == window {
            self.ring.pop_front();
            self.stuck.pop_front();
        }
        self.ring.push_back(c.r);
        self.stuck.push_back(std::mem::take(&mut self.stuck_now));
        if self.ring.len() == window && self.cl.band_rules {
            let ring = self.ring.make_contiguous();
            let stuck = self.stuck.iter().any(|&s| s);
            if !self.steady.stability.attracts()
                && !stuck
                && narrow_band(ring, self.cl.settle_rtol, 0.0)
            {
                return Some((Regime::SlipOscillation, Reason::SlipOscillation));
            }
            if self.cl.settled(ring) {
                return Some((Regime::StickSlip, Reason::SettledStickSlip));
            }
            if self.stuck.iter().any(|&s| s) && self.cl.sticking_band(ring) {
                return Some((Regime::StickSlip, Reason::StickingBand));
            }
        }
        None
    }

    /// The decision a step's stick events give (laws with true stick): a stick after a
    /// breakaway is the stick-slip cycle; any stick, where the fate of the orbit from
    /// breakaway is known, ends as that orbit does.
    fn stick_events(&mut self, e: &crate::StickEvents) -> Option<(Regime, Reason)> {
        if e.onsets > 0 && (self.broke_away || e.onset_after_breakaway) {
            return Some((Regime::StickSlip, Reason::StickCycle));
        }
        self.broke_away |= e.breakaways > 0;
        if e.onsets > 0 {
            return self.shortcuts.after_stick();
        }
        None
    }

    /// The lasting oscillation seen at the last closed turn (its window's band test passed),
    /// whether or not it crossed the section.
    pub fn lasting(&self) -> Option<Lasting> {
        self.lasting
    }

    /// The outcome of `run` stopped with `decision` at its current sample.
    pub fn finish(&self, (regime, reason): (Regime, Reason), run: &Run) -> Outcome {
        let s = run.sample();
        let (amplitude, omega) = match (reason, self.lasting) {
            (Reason::LastingOscillation | Reason::SlipOscillation, Some(l)) => {
                (l.v_range[1], l.omega)
            }
            _ => (self.amplitude, self.omega),
        };
        Outcome {
            regime,
            reason,
            t_decision: s.t,
            amplitude,
            distance: (s.x - self.fp.x).hypot(s.v - self.fp.v),
            omega,
            crossings: self.crossings,
            quasi_static: run.quasi_static(),
            stats: *run.stats(),
            max_residual: run.max_residual(),
            t_squeal: t_squeal(regime, reason, self.last_stuck),
            lasting: self
                .lasting
                .filter(|_| matches!(regime, Regime::StickSlip | Regime::SlipOscillation)),
        }
    }
}

impl Classifier {
    /// The wide-band test of [`Reason::StickingBand`] on a full window of section amplitudes
    /// ([`wide_band`] with this classifier's floor; the sticking of the revolutions is
    /// checked by the caller).
    fn sticking_band(&self, ring: &[f64]) -> bool {
        wide_band(ring, self.band_floor())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FrictionLaw, SolverConfig};

    /// `section_return` once read the caller's cumulative `stats.failures`: one failure in an
    /// earlier run turned every later return into "no return" (the cycle search then saw a
    /// decaying return map everywhere). A return from r = 0.5 at nu = 1e-3 comes back after
    /// about one revolution (period about 2 pi) whatever the caller's counters hold.
    #[test]
    fn section_return_ignores_earlier_failures() {
        let st = Stepper::new(
            Params::paper(FrictionLaw::McMillan, 1e-3),
            0.01,
            SolverConfig::default(),
        )
        .unwrap();
        let mut stats = SolverStats {
            failures: 1,
            ..SolverStats::default()
        };
        let c = section_return(&st, 0.5, 100.0, &mut stats, |_| {}).expect("a return");
        assert!((c.t - std::f64::consts::TAU).abs() < 0.5, "{c:?}");
        assert!(stats.solves > 600 && stats.failures == 1, "{stats:?}");
    }

    /// The classifier's run and a `Run` observed by hand give the same outcome: one loop.
    #[test]
    fn classify_is_a_watch_over_a_run() {
        let st = Stepper::new(
            Params::paper(FrictionLaw::McMillan, 1e-3),
            0.01,
            SolverConfig::default(),
        )
        .unwrap();
        let cl = Classifier::default();
        let ic = State { x: 1.1, v: 0.0 };
        let out = cl.classify(&st, ic);
        assert_eq!(out.regime, Regime::SteadySlip, "{out:?}");
        let mut run = Run::new(&st, ic);
        let mut w = cl.watch(st.params());
        let d = loop {
            let step = run.step();
            if let Some(d) = w.observe(&run, &step) {
                break d;
            }
        };
        assert_eq!(w.finish(d, &run), out);
    }

    /// The wide-band test on synthetic windows of 20 section amplitudes: an irregular band of
    /// +-25% (as measured at lambda <= 1) passes; a run drifting away from the unstable cycle
    /// (0.64% per revolution, monotone) and a sticking run decaying by 2% per revolution with
    /// jitter do not; nor does a band wider than its mean.
    #[test]
    fn sticking_band_accepts_irregular_bands_only() {
        let cl = Classifier::default();
        // Deterministic irregular sequence in [0.75, 1.25] (a logistic map, chaotic).
        let mut z = 0.3f64;
        let band: Vec<f64> = (0..20)
            .map(|_| {
                z = 3.9 * z * (1.0 - z);
                0.75 + 0.5 * z
            })
            .collect();
        assert!(cl.sticking_band(&band), "{band:?}");
        assert!(!cl.settled(&band));
        let growth: Vec<f64> = (0..20).map(|k| 0.37 * 1.0064f64.powi(k)).collect();
        assert!(!cl.sticking_band(&growth));
        let decay: Vec<f64> = band
            .iter()
            .enumerate()
            .map(|(k, r)| 2.0 * 0.98f64.powi(k as i32) + 0.02 * (r - 1.0))
            .collect();
        assert!(!cl.sticking_band(&decay), "{decay:?}");
        let wide: Vec<f64> = band.iter().map(|r| (r - 1.0) * 5.0 + 1.0).collect();
        assert!(!cl.sticking_band(&wide));
    }

    /// The settling test refuses a run drifting away from the unstable cycle at an
    /// accelerating pace inside a 5% band (the shape measured at Table 1, nu = 1e-2, from
    /// starts just inside the cycle: 2.087 -> 1.99 in 20 crossings), which the half-to-half
    /// trend test alone accepted; it accepts a jittering band of +-2%.
    #[test]
    fn settling_refuses_an_accelerating_drift() {
        let cl = Classifier::default();
        let drift: Vec<f64> = (0..20)
            .map(|k| 2.09 - 0.1 * (1.2f64.powi(k) - 1.0) / (1.2f64.powi(19) - 1.0))
            .collect();
        let half = |v: &[f64], a: usize| v[a..a + 10].iter().sum::<f64>() / 10.0;
        // The old trend test passes it: half-means differ by less than half the spread.
        assert!((half(&drift, 0) - half(&drift, 10)).abs() <= 0.5 * (drift[0] - drift[19]));
        assert!(!cl.settled(&drift) && !cl.sticking_band(&drift));
        let mut z = 0.3f64;
        let band: Vec<f64> = (0..20)
            .map(|_| {
                z = 3.9 * z * (1.0 - z);
                2.8 * (0.98 + 0.04 * z)
            })
            .collect();
        assert!(cl.settled(&band), "{band:?}");
    }
}
