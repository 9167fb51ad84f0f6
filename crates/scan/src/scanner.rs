//! One map's preparation and one block of cells: the pieces the [`crate::driver`] runs in
//! parallel. A block's result depends only on the plan, the map and the block.

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;
use squeal_core::landscape::StickCycle;
use squeal_core::{
    Classifier, FrictionLaw, LandscapeEvidence, LawFamily, Outcome, Params, Reason, Regime, Region,
    Shortcuts, SolverStats, State, Stepper, Trap,
};

use crate::cell::Audit;
pub use crate::cell::Cell;
use crate::census::{self, Census, Rules};
use crate::error::ScanError;
use crate::section::{self, SectionCycles};
use crate::spec::{EarlyStop, Plan};
use crate::ulc::{self, CycleOutcome, CycleSettings};

mod start_rule;
use start_rule::decaying_turns;
pub use start_rule::{StartRule, decaying_turn};

/// Progress callbacks (no-op defaults); called from worker threads (a search's observer
/// is handed to the threads that run its pieces, hence `Send`).
pub trait Observer: Send + Sync {
    /// Map `map` is prepared (its cycle searched, if asked for).
    fn map_prepared(&self, _map: usize) {}
    /// `n` more cells of map `map` finished: reported once per [`CELL_CHUNK`] cells of a
    /// block (counted on the worker, folded here), not per cell, so that an observer costs
    /// nothing per cell (its atomics and locks once serialised the workers).
    fn cells_done(&self, _map: usize, _n: u64) {}
    /// Block `block` of map `map` finished (it goes to the sink next).
    fn block_done(&self, _map: usize, _block: usize) {}
    /// A stage of a one-parameter search began on the observed thread
    /// ([`crate::observe::observed`]): `what`, of `total` parameter values where known.
    fn search_stage(&self, _what: &'static str, _total: Option<u64>) {}
    /// A piece of that search's work is done ([`crate::observe::SearchStep`]).
    fn search_step(&self, _step: crate::observe::SearchStep) {}
}

/// An observer that does nothing.
pub struct NoObserver;
impl Observer for NoObserver {}

/// A finished block: `cells` row-major over the block's rows of `v0` and all `x0`.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockResult {
    /// Map index (sweep value).
    pub map: usize,
    /// Block index within the map.
    pub block: usize,
    /// The cells.
    pub cells: Vec<Cell>,
}

/// The outcome of start `p` decided without a run (fixed point `centre`): at `t = 0`, no
/// steps taken.
fn at_start(p: State, centre: State, (regime, reason): (Regime, Reason)) -> Outcome {
    Outcome {
        regime,
        reason,
        t_decision: 0.0,
        amplitude: f64::NAN,
        distance: (p.x - centre.x).hypot(p.v - centre.v),
        omega: f64::NAN,
        crossings: 0,
        quasi_static: false,
        stats: SolverStats::default(),
        max_residual: 0.0,
        // Inside the cycle or the certified region no revolution sticks (both lie in a slip
        // region of the plane, [`squeal_core::classify::t_squeal`]): 0; outside the cycle
        // the run squeals for good: infinite.
        t_squeal: squeal_core::classify::t_squeal(regime, reason, 0.0),
        lasting: None,
    }
}

/// The certified shortcuts of a map with parameters `params`, landscape `landscape` and
/// section search `found` (MODEL.md section 9); none without early stopping (every run goes
/// to settlement).
pub fn shortcuts(
    plan: &Plan,
    params: &Params,
    landscape: Option<&LandscapeEvidence>,
    found: Option<&SectionCycles>,
) -> Shortcuts {
    if plan.map.early_stop != EarlyStop::Cycle {
        return Shortcuts::NONE;
    }
    // No unstable cycle, and the search's resolution statement holds over its whole range:
    // every crossing below its top returns lower ([`squeal_core::Reason::BelowDecayingSection`]).
    // It rests on the sampled return map and on the force being the one root of a smooth
    // equation at the crossing, so it serves only McMillan's two smooth laws: a law with true
    // stick has the exact shortcuts of the orbit from breakaway and, where it depends on the
    // slip velocity only, of the monotone return map ([`squeal_core::witness`]); Coulomb's
    // set-valued law has no such root, and its runs keep their exact decay to `fp_radius`.
    let smooth = matches!(
        params.kind(),
        FrictionLaw::McMillan | FrictionLaw::McMillanNonHysteretic
    );
    let decay_below = match found {
        Some(&SectionCycles::NoneBelow {
            r_max,
            unresolved: 0,
        }) if smooth => Some(r_max * (1.0 - plan.map.trap_margin)),
        _ => None,
    };
    // The orbit from breakaway decides every run that sticks: a stick-slip cycle where it
    // sticks again, steady slip where it reaches the attracting fixed point first.
    let breakaway = landscape.and_then(|e| match e.cycle {
        StickCycle::Exists { .. } => Some(Regime::StickSlip),
        StickCycle::Absent if e.damping > 0.0 => Some(Regime::SteadySlip),
        StickCycle::Absent | StickCycle::Undecided => None,
    });
    Shortcuts {
        region: Region::of(params),
        breakaway,
        section: None,
        decay_below,
        // Set with the decaying turns, once the map's stepper exists.
        decay_lower_below: None,
        trapped_band: None,
    }
}

/// `base` with the certified fates of stretches of the section
/// ([`squeal_core::witness`]) where they apply: early stopping on (some shortcut), a law of the
/// slip velocity only, and no located unstable cycle (where one is, its trap decides sooner).
fn with_section_fates(
    base: Shortcuts,
    stepper: &Stepper,
    classifier: &Classifier,
    r_max: f64,
) -> Shortcuts {
    if !base.any() || classifier.trap.is_some() {
        return base;
    }
    Shortcuts {
        section: squeal_core::witness::section_fates(stepper, classifier, base, r_max),
        ..base
    }
}

/// Whether the maps of `plan` (of a law of `family`) search the section when prepared:
/// for early stopping, for the located cycle, and for every law whose stick-slip is a band
/// ([`LawFamily::has_band`]), early stopping or not: the classifier's band rules need to
/// know whether the outside of the cycle is invariant ([`Outside`]).
pub(crate) fn searches_section(plan: &Plan, family: LawFamily) -> bool {
    plan.map.early_stop == EarlyStop::Cycle || plan.cycle.locate || family.has_band()
}

/// Which checks of its rules' premise a map is prepared with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Checks {
    /// The census, and the certificates that the audit's runs end at: a map that is scanned.
    Full,
    /// No census (tests of what acts on a rule that was not withdrawn).
    #[cfg(test)]
    NoCensus,
    /// Labels only: no census, no trapped band (only the audit's runs use it,
    /// [`MapContext::settle`]), for a map whose starts are only classified (the sensitivity).
    LabelsOnly,
}

/// What the section search of map `map` found, and the rules it sets up.
#[derive(Default)]
struct Searched {
    section: Option<SectionCycles>,
    cycle: Option<CycleOutcome>,
    start_rule: Option<StartRule>,
    outside: Option<Outside>,
}

/// The section search of map `map` ([`section::section_cycles`]), with the unstable cycle
/// located where the plan asks, and the rules it sets: the classifier's band rules and trap
/// (in `classifier`), the start rule.
fn search_map(
    plan: &Plan,
    map: usize,
    (stepper, cs): (&Stepper, &CycleSettings),
    classifier: &mut Classifier,
) -> Result<Searched, ScanError> {
    let params = *stepper.params();
    let (mut cycle, mut start_rule) = (None, None);
    let mut stats = Default::default();
    let mut returns = 0;
    let found = section::section_cycles(stepper, cs, &mut stats, &mut returns);
    if let SectionCycles::Unstable { lo, .. } = found {
        crate::bounds::fp_radius_inside(classifier.fp_radius, lo, map)?;
    }
    // Outside the unstable cycle a run ends on a self-excited oscillation (bounded
    // friction, nu > 0: nothing escapes to infinity, and an attracting cycle out
    // there is stick-slip) unless it falls back inside: where a sampled start does
    // ([`Outside::Escapes`]) no outside rule applies, and the band rules only where
    // the band is trapped ([`crate::band`]).
    let outside = outside_of(stepper, cs, &found);
    if let Some(o) = outside {
        classifier.band_rules = o.band_rules();
    }
    if plan.map.early_stop == EarlyStop::Cycle {
        classifier.trap = trap_of(&found, plan.map.trap_margin);
    }
    if plan.cycle.locate {
        cycle = Some(match ulc::locate_from(stepper, found, cs, stats, returns) {
            Ok(c) => Ok(c),
            Err(ScanError::NoCycle(why)) => Err(why),
            Err(e) => return Err(e),
        });
    }
    if let (Some(_), SectionCycles::Unstable { r, .. }) = (classifier.trap, found) {
        let fp = params.fixed_point();
        let curve = match &cycle {
            Some(Ok(c)) => Some(c.curve.clone()),
            _ => ulc::cycle_curve(stepper, r, cs.t_return, &mut Default::default()).map(|(c, _)| c),
        };
        let invariant = outside == Some(Outside::Invariant);
        start_rule = curve.map(|c| StartRule::new(c, fp, r, plan.map.trap_margin, invariant));
    }
    Ok(Searched {
        section: Some(found),
        cycle,
        start_rule,
        outside,
    })
}

/// Everything one map needs: stepper, classifier with its trap, the located cycle.
#[derive(Clone, Debug)]
pub struct MapContext {
    /// Map index.
    pub map: usize,
    /// Parameters of this map.
    pub params: Params,
    /// The stepper.
    pub stepper: Stepper,
    /// The classifier (with the trap when early stopping is on and a cycle was found).
    pub classifier: Classifier,
    /// The section sign changes, if searched.
    pub section: Option<SectionCycles>,
    /// The located cycle or why there is none, if the plan asks to locate it.
    pub cycle: Option<CycleOutcome>,
    /// Early stopping at the start (with the trap, when the cycle's curve was traced).
    pub start_rule: Option<StartRule>,
    /// The landscape of a law with true stick ([`crate::landscape`]); `None` for others.
    pub landscape: Option<squeal_core::LandscapeEvidence>,
    /// Whether the outside of the unstable cycle was found invariant (`None`: no cycle
    /// found or not searched).
    pub outside: Option<Outside>,
    /// The certified early decisions ([`shortcuts`]).
    pub shortcuts: Shortcuts,
    /// The certificates of the attractors that the runs checking the rules end on (the
    /// census's and the audit's): the certified region of the fixed point and the trapped
    /// stick-slip band. Never withdrawn: each is an argument, not a rule of thumb.
    pub certificates: Shortcuts,
    /// The runs that checked the premise of the start rule, the trap and the band rules
    /// ([`crate::census`]), and the rules they withdrew; `None` where none was taken.
    pub census: Option<Census>,
    /// The rule groups withdrawn from this map, by the census or by an audit, with why.
    pub withdrawn: Vec<Withdrawn>,
    /// How often the cells of each kind of decision are audited ([`AuditRates`]).
    pub audit_rates: AuditRates,
}

/// A rule group withdrawn from a map, and why (as the file and the summary say it).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Withdrawn {
    /// The group.
    pub rules: Rules,
    /// Why: the run that refuted it.
    pub why: String,
}

/// Audited cells per rule group: a rule that mislabels a fraction `p` of the cells it decides
/// goes unseen by `n` audited cells of its own with probability `(1 - p)^n`; with
/// `n = 100` a leak of 5% is missed with probability 0.6%, one of 3% with 4.8%.
pub const AUDIT_PER_RULE: usize = 100;

/// The audit's sampling intervals of one map (0: no audit). Each cell is audited by the hash
/// of its index ([`audited`]) at the interval of the kind of decision it got, so the sample
/// stays deterministic cell by cell (threads, blocks and resumes do not move it): the plan's
/// `audit_every`, shortened for each group of the start rule so that about
/// [`AUDIT_PER_RULE`] of the cells it decides are audited (all of them where it decides
/// fewer), and for cells decided by runs so that about that many of them are audited (the
/// rules that stop runs early share those; which rule a run ends by is not known before it
/// runs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AuditRates {
    /// The plan's interval (`classifier.audit_every`).
    pub every: u64,
    /// For cells decided at the start, by group ([`Rules`] index).
    pub at_start: [u64; 4],
    /// For cells decided by a run.
    pub run: u64,
}

impl AuditRates {
    /// The rates of `ctx`'s map of `plan`: the start rule's decisions counted over the
    /// grid (a test of the start's side, no run).
    fn of_plan(ctx: &MapContext, plan: &Plan) -> AuditRates {
        let (every, g) = (plan.map.audit_every, &plan.map.grid);
        if every == 0 {
            return AuditRates::default();
        }
        // Counted by rows on the pool (a 4096 x 4096 map's 16.8M tests took a second on
        // one thread while the other waited); integer sums, so the same on any thread count.
        let (at_start, run) = (0..g.v0.count)
            .into_par_iter()
            .map(|row| {
                let (mut at_start, mut run) = ([0usize; 4], 0usize);
                for col in 0..g.x0.count {
                    let (x, v) = g.state(row, col);
                    match ctx.decide_at_start(State { x, v }) {
                        Some(o) => {
                            if let Some(r) = Rules::of(o.reason) {
                                at_start[r as usize] += 1;
                            }
                        }
                        None => run += 1,
                    }
                }
                (at_start, run)
            })
            .reduce(
                || ([0usize; 4], 0usize),
                |(a, n), (b, m)| (std::array::from_fn(|i| a[i] + b[i]), n + m),
            );
        let rate = |n: usize| every.min((n / AUDIT_PER_RULE).max(1) as u64);
        AuditRates {
            every,
            at_start: at_start.map(rate),
            run: rate(run),
        }
    }

    /// The interval for a cell decided as `out` (at the start or not).
    fn for_cell(&self, out: &Outcome, at_start: bool) -> u64 {
        match (at_start, Rules::of(out.reason)) {
            (true, Some(r)) => self.at_start[r as usize],
            _ => self.run,
        }
    }
}

pub use crate::band::{Outside, outside_of, outside_on, outside_with};

/// The classifier `base` with its band rules set by the section of `stepper` searched up
/// to `r_max` ([`outside_of`]; the search does not depend on `r_max` beyond its stated
/// resolution, [`crate::section::adaptive_samples`]): what a run from a single start
/// (`squeal trajectory`, the atlas's confirmation run) uses, so that it labels as the scan
/// does. Laws with true stick are returned unchanged (their band rules are not used).
pub fn classifier_for(stepper: &Stepper, base: Classifier, r_max: f64) -> Classifier {
    if !stepper.params().law.family().has_band() {
        return base;
    }
    let cs = CycleSettings {
        r_max: r_max.max(CycleSettings::default().r_max),
        ..CycleSettings::default()
    };
    let (mut stats, mut returns) = (SolverStats::default(), 0);
    // Only the band rules are read: the crossing to `rtol` only where something escapes.
    let precision = section::Precision::Escape;
    let found = section::section_cycles_to(stepper, &cs, precision, &mut stats, &mut returns);
    let band_rules = outside_of(stepper, &cs, &found).is_none_or(|o| o.band_rules());
    Classifier { band_rules, ..base }
}

/// The plan's cycle search (`[cycle]`) for map parameters `params`: unless the spec gave
/// `r_max`, it reaches beyond the grid's farthest start ([`crate::grid::grid_reach`]).
pub fn cycle_settings(plan: &Plan, params: &Params) -> CycleSettings {
    let search = plan.cycle.search;
    if plan.cycle.r_max_given {
        return search;
    }
    CycleSettings {
        r_max: (1.2 * crate::grid::grid_reach(&plan.map.grid, params)).max(4.0),
        ..search
    }
}

/// Whether cell `index` (row-major within its map) is in the audited sample of about one
/// cell in `every` (0: none): chosen by a hash of the index, so the sample is spread over
/// the grid and the same in every run. Cell 0 is always in it.
pub fn audited(index: u64, every: u64) -> bool {
    // Fibonacci hashing: the top bits of index * 2^64 / phi are spread evenly.
    every > 0 && (index.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 24) % every == 0
}

/// The trap of the unstable cycle `found` on the section, with the relative `margin`: its
/// outside only where no sampled start outside returns inside ([`Outside`]).
fn trap_of(found: &SectionCycles, margin: f64) -> Option<Trap> {
    let SectionCycles::Unstable { lo, hi, escape, .. } = *found else {
        return None;
    };
    Some(Trap {
        r_inner: lo * (1.0 - margin),
        r_outer: match escape {
            None => hi * (1.0 + margin),
            Some(_) => f64::INFINITY,
        },
    })
}

impl MapContext {
    /// Builds the stepper and, as the plan asks, searches the section once: the trap for
    /// early stopping and the located cycle both come from that one search.
    pub fn prepare(plan: &Plan, map: usize) -> Result<MapContext, ScanError> {
        MapContext::prepare_checked(plan, map, Checks::Full)
    }

    /// [`MapContext::prepare`], with the checks `checks` of the rules' premise.
    pub(crate) fn prepare_checked(
        plan: &Plan,
        map: usize,
        checks: Checks,
    ) -> Result<MapContext, ScanError> {
        let params = plan.maps[map];
        let stepper = Stepper::new(params, plan.dt, plan.solver)?;
        let cs = cycle_settings(plan, &params);
        let mut classifier = plan.map.classifier;
        let Searched {
            section,
            cycle,
            mut start_rule,
            outside,
        } = match searches_section(plan, params.law.family()) {
            true => search_map(plan, map, (&stepper, &cs), &mut classifier)?,
            false => Searched::default(),
        };
        let landscape = crate::landscape::of_params(plan, params)?;
        let mut shortcuts = with_section_fates(
            shortcuts(plan, &params, landscape.as_ref(), section.as_ref()),
            &stepper,
            &classifier,
            cs.r_max,
        );
        if let (None, Some(top)) = (&start_rule, shortcuts.decay_below) {
            start_rule = decaying_turns(&stepper, &cs, plan.map.trap_margin, top, &mut shortcuts);
        }
        let mut ctx = MapContext {
            map,
            params,
            stepper,
            classifier,
            section,
            cycle,
            start_rule,
            shortcuts,
            certificates: Shortcuts {
                region: squeal_core::Region::of(&params),
                ..Shortcuts::NONE
            },
            landscape,
            outside,
            census: None,
            withdrawn: Vec::new(),
            audit_rates: AuditRates::default(),
        };
        ctx.withdraw_where_steady_slip_does_not_attract();
        // The census's runs, the audit's count over the grid and the trapped band side by
        // side (the census does not end its runs in the band: it checks it): the count and
        // the band fill the threads that the census's last runs leave idle. The count holds
        // unless the census withdraws a group (then it is counted again).
        let band = |ctx: &MapContext| match (checks, ctx.section) {
            (Checks::LabelsOnly, _) | (_, None) => None,
            (_, Some(found)) => crate::band::trapped(&ctx.stepper, &cs, found, ctx.outside),
        };
        let (found, (rates, band)) = rayon::join(
            || {
                (checks == Checks::Full)
                    .then(|| ctx.census_of(plan, cs.r_max / 1.2))
                    .flatten()
            },
            || {
                // A map prepared for labels only is never audited.
                let rates = || match checks {
                    Checks::LabelsOnly => AuditRates::default(),
                    _ => AuditRates::of_plan(&ctx, plan),
                };
                rayon::join(rates, || band(&ctx))
            },
        );
        ctx.audit_rates = rates;
        ctx.certificates.trapped_band = band;
        if found.is_some_and(|c| ctx.apply_census(c)) {
            ctx.audit_rates = AuditRates::of_plan(&ctx, plan);
        }
        Ok(ctx)
    }

    /// The census of [`crate::census`] for McMillan's laws where the start rule, the trap
    /// or the band rules could decide a cell (`None`: none is taken). `reach` is the radius
    /// of its starts around the fixed point where the grid is a single point.
    fn census_of(&self, plan: &Plan, reach: f64) -> Option<Census> {
        let smooth = matches!(
            self.params.kind(),
            FrictionLaw::McMillan | FrictionLaw::McMillanNonHysteretic
        );
        let cycle_rule = self
            .start_rule
            .as_ref()
            .filter(|r| r.inside == Reason::StartInsideCycle);
        let rules_on =
            cycle_rule.is_some() || self.classifier.trap.is_some() || self.classifier.band_rules;
        if !smooth || !rules_on {
            return None;
        }
        let curve = cycle_rule.map(|r| r.curve().clone());
        // The census checks the band's premise too, so its runs end at the fixed point's
        // region only: a trapped band of the sampled return map can be wrong (at lambda 0.5,
        // nu 0.0195 it is, and the census's runs find the leak).
        let region_only = Shortcuts {
            region: self.certificates.region,
            ..Shortcuts::NONE
        };
        Some(census::take(
            plan,
            (&self.stepper, region_only),
            &self.classifier,
            (curve.as_ref(), reach),
            |ic| self.classify(ic),
        ))
    }

    /// Where steady slip does not attract ([`squeal_core::SteadySlip`]), every rule that
    /// concludes steady slip from where a run is (the inside of a cycle, the certified
    /// shortcuts) rests on a false premise: those groups are withdrawn, saying why, and the
    /// runs decide (the slip oscillation about the point, stick-slip, or the sector's runs
    /// that close on it).
    fn withdraw_where_steady_slip_does_not_attract(&mut self) {
        let steady = squeal_core::SteadySlip::of(&self.params);
        if steady.stability.attracts() {
            return;
        }
        let why = |rules: Rules| format!("{} withdrawn: {}", rules.name(), steady.words(None));
        self.withdraw(Rules::Inside);
        self.withdrawn.push(Withdrawn {
            rules: Rules::Inside,
            why: why(Rules::Inside),
        });
        // Of the certified shortcuts, those that conclude steady slip; the ones that conclude
        // stick-slip (the orbit from breakaway sticks again, a stretch between sticking
        // starts) stand.
        let s = &mut self.shortcuts;
        let steady_ones = s.region.is_some()
            || s.decay_below.is_some()
            || s.decay_lower_below.is_some()
            || s.section.is_some_and(|f| f.settles_up_to.is_some())
            || s.breakaway == Some(Regime::SteadySlip);
        s.region = None;
        s.decay_below = None;
        s.decay_lower_below = None;
        if let Some(f) = s.section.as_mut() {
            f.settles_up_to = None;
        }
        s.breakaway = s.breakaway.filter(|r| *r == Regime::StickSlip);
        let steady_start = self
            .start_rule
            .as_ref()
            .is_some_and(|r| r.inside != Reason::StartInsideCycle);
        if steady_start {
            self.start_rule = None;
        }
        if steady_ones || steady_start {
            self.withdrawn.push(Withdrawn {
                rules: Rules::Shortcuts,
                why: format!(
                    "the shortcuts that conclude steady slip withdrawn: {}",
                    steady.words(None)
                ),
            });
        }
    }

    /// Keeps census `c` and withdraws the rule groups whose premise a run of it
    /// contradicted; whether it withdrew any.
    fn apply_census(&mut self, c: Census) -> bool {
        for w in &c.withdrawn {
            self.withdraw(w.rules);
            self.withdrawn.push(Withdrawn {
                rules: w.rules,
                why: w.to_string(),
            });
        }
        let withdrew = !c.withdrawn.is_empty();
        self.census = Some(c);
        withdrew
    }

    /// Withdraws the rule group `rules` from this map: its cells are then decided by runs
    /// (or by the rules that remain).
    pub fn withdraw(&mut self, rules: Rules) {
        let cycle_rule = |r: &StartRule| r.inside == Reason::StartInsideCycle;
        match rules {
            Rules::Band => self.classifier.band_rules = false,
            Rules::Outside => {
                if let Some(t) = self.classifier.trap.as_mut() {
                    t.r_outer = f64::INFINITY;
                }
                if let Some(r) = self.start_rule.as_mut().filter(|r| cycle_rule(r)) {
                    r.outside = false;
                }
            }
            Rules::Inside => {
                if let Some(t) = self.classifier.trap.as_mut() {
                    t.r_inner = f64::NEG_INFINITY;
                }
                if self.start_rule.as_ref().is_some_and(cycle_rule) {
                    self.start_rule = None;
                }
            }
            Rules::Shortcuts => {
                self.shortcuts = Shortcuts::NONE;
                if self.start_rule.as_ref().is_some_and(|r| !cycle_rule(r)) {
                    self.start_rule = None;
                }
            }
        }
        let idle = |t: &Trap| t.r_inner == f64::NEG_INFINITY && t.r_outer == f64::INFINITY;
        if self.classifier.trap.is_some_and(|t| idle(&t)) {
            self.classifier.trap = None;
        }
    }

    /// The map of `plan` prepared as [`MapContext::prepare`] does, with the rule groups
    /// `withdrawn` (each with why) withdrawn too: what an audit that found them wrong
    /// decides the map's cells again with ([`crate::redo`]).
    pub fn prepare_without(
        plan: &Plan,
        map: usize,
        withdrawn: &[Withdrawn],
    ) -> Result<MapContext, ScanError> {
        let mut ctx = MapContext::prepare(plan, map)?;
        let mut changed = false;
        for w in withdrawn {
            if !ctx.withdrawn.iter().any(|x| x.rules == w.rules) {
                ctx.withdraw(w.rules);
                ctx.withdrawn.push(w.clone());
                changed = true;
            }
        }
        // The rates [`MapContext::prepare`] counted hold unless a group was withdrawn here.
        if changed {
            ctx.audit_rates = AuditRates::of_plan(&ctx, plan);
        }
        Ok(ctx)
    }

    /// Classifies one start: by the start rule or the certified region when they decide,
    /// else by a run (with the certified shortcuts).
    pub fn classify(&self, ic: State) -> Outcome {
        self.decide_at_start(ic).unwrap_or_else(|| {
            self.classifier
                .classify_with(&self.stepper, ic, self.shortcuts)
        })
    }

    /// The label of start `ic` without a run, where the start rule or the certified region
    /// decides it (the first step of [`MapContext::classify`]; `squeal trajectory` reports
    /// it beside its run's own verdict).
    pub fn decide_at_start(&self, ic: State) -> Option<Outcome> {
        if let Some(rule) = &self.start_rule {
            if let Some(decision) = rule.decide(ic) {
                return Some(at_start(ic, rule.centre, decision));
            }
        }
        let r = self.shortcuts.region.filter(|r| r.contains(ic.x, ic.v))?;
        Some(at_start(
            ic,
            r.centre,
            (Regime::SteadySlip, Reason::StartInRegion),
        ))
    }

    /// Whether audited cells of this map are checked: only where an early decision could
    /// apply (the cycle's trap or a certified shortcut).
    pub fn audits(&self) -> bool {
        self.classifier.trap.is_some() || self.shortcuts.any()
    }

    /// The audit's reference for a cell labelled `label`: the run from `ic` until it reaches
    /// a certified attractor ([`MapContext::certificates`]: the fixed point's region, the
    /// trapped band) or settles, with no shortcut. A cell the start rule labelled keeps the
    /// section's trap: the run's own crossing of the section checks the traced curve the
    /// rule decided by. A cell a run labelled has no trap (its crossing decided it).
    pub fn settle(&self, ic: State, label: &Outcome) -> Outcome {
        let inside_by_start = label.reason == Reason::StartInsideCycle;
        // Only the trap's inner side: the outside's premise is what an audit of a stick-slip
        // cell checks, so its run may not assume it.
        let trap = self
            .classifier
            .trap
            .filter(|_| inside_by_start)
            .map(|t| Trap {
                r_outer: f64::INFINITY,
                ..t
            });
        // The trapped band, only where the band rules stand (the census did not refute them)
        // and the outside of the cycle is invariant.
        let band = self.classifier.band_rules && self.outside == Some(Outside::Invariant);
        let certificates = Shortcuts {
            trapped_band: self.certificates.trapped_band.filter(|_| band),
            ..self.certificates
        };
        Classifier {
            trap,
            ..self.classifier
        }
        .classify_with(&self.stepper, ic, certificates)
    }

    /// Classifies one cell (and audits it when it is in the sample and an early decision
    /// could apply: the cycle's trap or a certified shortcut).
    pub fn cell(&self, plan: &Plan, row: usize, col: usize) -> Cell {
        let g = &plan.map.grid;
        let (x, v) = g.state(row, col);
        let ic = State { x, v };
        let at = self.decide_at_start(ic);
        let started = at.is_some();
        let out = at.unwrap_or_else(|| {
            self.classifier
                .classify_with(&self.stepper, ic, self.shortcuts)
        });
        let mut cell = Cell::from(&out);
        let every = self.audit_rates.for_cell(&out, started);
        if self.audits() && audited((row * g.x0.count + col) as u64, every) {
            let reference = self.settle(ic, &out).regime;
            cell.audit = match reference {
                Regime::Undecided => Audit::Undecided,
                r if r == out.regime => Audit::Agrees,
                _ => Audit::Disagrees,
            } as u8;
        }
        cell
    }
}

/// Cells of a block classified one after the other by one worker, and counted to the
/// observer at once: small enough that a block's cells still spread over the threads (a
/// 4096-cell row makes 64 chunks), large enough that the count costs nothing per cell.
pub const CELL_CHUNK: usize = 64;

/// Classifies the cells of one block in parallel. Returns `None` if `stop` was raised
/// before the block finished (the block is then discarded, never stored half-done).
pub fn run_block(
    plan: &Plan,
    ctx: &MapContext,
    block: usize,
    observer: &dyn Observer,
    stop: Option<&AtomicBool>,
) -> Option<BlockResult> {
    let g = &plan.map.grid;
    let rows = g.block_rows(block);
    let nx = g.x0.count;
    let n = rows.len() * nx;
    let chunks: Option<Vec<Vec<Cell>>> = (0..n.div_ceil(CELL_CHUNK))
        .into_par_iter()
        .map(|c| {
            if stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
                return None;
            }
            let cells: Vec<Cell> = (c * CELL_CHUNK..n.min((c + 1) * CELL_CHUNK))
                .map(|k| ctx.cell(plan, rows.start + k / nx, k % nx))
                .collect();
            observer.cells_done(ctx.map, cells.len() as u64);
            Some(cells)
        })
        .collect();
    Some(BlockResult {
        map: ctx.map,
        block,
        cells: chunks?.concat(),
    })
}
