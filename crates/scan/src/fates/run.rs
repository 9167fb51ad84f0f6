//! One run to its fate ([`fate`]): it ends where it reaches the fixed point, where the
//! oscillation it settled on is certified as an attracting periodic orbit
//! ([`squeal_core::orbit`]), or at the horizon.

use std::sync::atomic::{AtomicBool, Ordering};

use squeal_core::orbit::{self, Orbit, OrbitWatch};
use squeal_core::{
    Classifier, Lasting, Outcome, Regime, Run, Setup, Shortcuts, SolverStats, State, SteadySlip,
    TurnWatch,
};

use serde::Serialize;

use crate::error::ScanError;

/// Where one run ends by its horizon.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "fate", rename_all = "snake_case")]
pub enum Fate {
    /// Reached the fixed point (steady slip) at `t`.
    Settles {
        /// When.
        t: f64,
    },
    /// Still oscillating at the horizon, on an oscillation the band test identified at
    /// `t` (and never reached the fixed point): it squeals for as long as was run.
    Lasts {
        /// When the oscillation was identified.
        t: f64,
        /// Its figures (frequency, extent, stick, slip reversal), where the turn watch
        /// closed a window on it.
        lasting: Option<Lasting>,
        /// The periodic orbit it was certified on, where it was (the run then stopped:
        /// it lasts for good).
        certified: Option<Orbit>,
    },
    /// Steady slip does not attract ([`squeal_core::SteadySlip`]), and the run ends on the
    /// small oscillation about it that never sticks ([`Regime::SlipOscillation`]): quiet, as
    /// far as the squeal goes (its figures, where the turn watch closed a window on it).
    SlipOscillation {
        /// When it was identified.
        t: f64,
        /// Its figures (frequency, extent) in the last window of the run.
        lasting: Option<Lasting>,
        /// The periodic orbit it was certified on, where it was.
        certified: Option<Orbit>,
    },
    /// Neither by the horizon (or the run failed).
    Undecided,
    /// Not run to its end: another start at the same value had already not settled, which
    /// decided the value.
    Stopped,
}

impl Fate {
    /// Whether the run settled.
    pub fn settles(&self) -> bool {
        matches!(self, Fate::Settles { .. })
    }

    /// Whether the run ends without squeal: at the fixed point, or on the slip oscillation
    /// about an unstable steady slip. What a boundary bisects.
    pub fn quiet(&self) -> bool {
        matches!(self, Fate::Settles { .. } | Fate::SlipOscillation { .. })
    }

    /// Whether the run lasted.
    pub fn lasts(&self) -> bool {
        matches!(self, Fate::Lasts { .. })
    }

    /// Words for reports.
    pub fn words(&self, horizon: f64) -> String {
        match self {
            Fate::Settles { t } => format!("reaches the fixed point at t = {t:.1}"),
            Fate::Lasts {
                t,
                certified: Some(o),
                ..
            } => format!(
                "on a lasting oscillation from t = {t:.1}, {}: it lasts for good",
                o.words()
            ),
            Fate::Lasts { t, .. } => format!(
                "on an irregular oscillation from t = {t:.1} to the horizon {horizon} (neither a \
                 period nor a band of its maxima certified; {} tries at most)",
                orbit::TRIES
            ),
            Fate::SlipOscillation {
                t,
                certified: Some(o),
                ..
            } => format!(
                "on the small slip oscillation about the unstable steady slip from t = {t:.1}, \
                 {} (never sticks)",
                o.words()
            ),
            Fate::SlipOscillation { t, .. } => format!(
                "on the small slip oscillation about the unstable steady slip from t = {t:.1} to \
                 the horizon {horizon} (never sticks)"
            ),
            Fate::Undecided => format!("neither settles nor lasts identifiably by t = {horizon}"),
            Fate::Stopped => "was stopped (another start had decided the value)".into(),
        }
    }
}

/// The fate of the run from `start` with `setup` by `horizon`, and the solver's counts;
/// `stop` raised stops the run ([`Fate::Stopped`]). The run ends early where it reaches the
/// fixed point, or where the oscillation it settled on is certified as an attracting
/// periodic orbit at `dt` and `dt / 2` ([`squeal_core::orbit`]: it lasts for good, the
/// horizon has nothing to add); else at the horizon.
pub fn fate(
    setup: Setup,
    start: State,
    horizon: f64,
    stop: Option<&AtomicBool>,
) -> Result<(Fate, SolverStats), ScanError> {
    let st = setup.stepper()?;
    let half = setup.half_dt().stepper()?;
    let p = *st.params();
    let (own_cl, rest_cl) = watchers(horizon);
    // The run settles where it comes within the fixed point's radius or enters its
    // certified region of attraction (squeal_core::Region: every run inside it converges).
    let region = Shortcuts {
        region: squeal_core::Region::of(&p),
        ..Shortcuts::NONE
    };
    let (mut own_w, mut rest_w) = (own_cl.watch(&p), rest_cl.watch_with(&p, region));
    let mut turns = TurnWatch::new(&p, own_cl.turn_settings(&p));
    let attracts = SteadySlip::of(&p).stability.attracts();
    let mut orbits = OrbitWatch::new(&half, orbit::band_floor(&p, own_cl.fp_radius, attracts));
    let mut run = Run::new(&st, start);
    let (mut own, mut lasting): (Option<Outcome>, Option<Lasting>) = (None, None);
    let lasting_fate =
        |own: &Outcome, lasting, certified| lasting_fate(own, (lasting, certified), attracts);
    for k in 1..=run.steps_to(horizon) {
        let step = run.step();
        if own.is_none() {
            own = own_w.observe(&run, &step).map(|d| own_w.finish(d, &run));
        }
        if let Some((Regime::SteadySlip, _)) = rest_w.observe(&run, &step) {
            let t = run.sample().t;
            return Ok((Fate::Settles { t }, merged(run.stats(), orbits.stats())));
        }
        if turns.observe_step(&run, &step).is_some() {
            lasting = turns.lasting();
        }
        // A certificate is tried once the run's own watch has identified an oscillation.
        let ready = own.is_some() && lasting.is_some();
        if let Some(orb) = orbits.observe(&run, &step, ready)
            && let Some(f) = own.and_then(|o| lasting_fate(&o, lasting, Some(orb)))
        {
            return Ok((f, merged(run.stats(), orbits.stats())));
        }
        if !step.next.x.is_finite() || run.failed() {
            break;
        }
        if k % 4096 == 0 && stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
            let f = match run.sample().t + setup.dt < horizon {
                true => Fate::Stopped,
                false => Fate::Undecided,
            };
            return Ok((f, merged(run.stats(), orbits.stats())));
        }
    }
    let f = own
        .and_then(|o| lasting_fate(&o, lasting, None))
        .unwrap_or(Fate::Undecided);
    Ok((f, merged(run.stats(), orbits.stats())))
}

/// The fate of a run whose own watch decided `own` and whose last window of turns is
/// `lasting` (certified as `certified`, where it was), where steady slip `attracts` or not:
/// the squeal where a turn of the window stuck (or steady slip attracts: the oscillation is
/// then no slip oscillation about it), else the slip oscillation; `None` where `own` is no
/// oscillation.
fn lasting_fate(
    own: &Outcome,
    (lasting, certified): (Option<Lasting>, Option<Orbit>),
    attracts: bool,
) -> Option<Fate> {
    if !matches!(own.regime, Regime::StickSlip | Regime::SlipOscillation) {
        return None;
    }
    let t = own.t_decision;
    Some(match Lasting::regime(lasting.as_ref(), attracts) {
        Regime::SlipOscillation => Fate::SlipOscillation {
            t,
            lasting,
            certified,
        },
        _ => Fate::Lasts {
            t,
            lasting,
            certified,
        },
    })
}

/// The two watchers of a fate's run to `horizon`: its own (band rules, no trap) and the one
/// that only sees the fixed point.
fn watchers(horizon: f64) -> (Classifier, Classifier) {
    let own = Classifier {
        t_max: horizon,
        trap: None,
        band_rules: true,
        ..Classifier::default()
    };
    let rest = Classifier {
        band_rules: false,
        ..own
    };
    (own, rest)
}

/// The run's solver counts with those of the certificates' turns added.
fn merged(run: &SolverStats, extra: &SolverStats) -> SolverStats {
    let mut s = *run;
    s.merge(extra);
    s
}
