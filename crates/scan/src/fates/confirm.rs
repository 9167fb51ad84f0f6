//! The runs at a shortcut's answer: [`confirm`] runs the starts at the ends of its bracket
//! (at `dt`, and at `dt / 2` for the step sensitivity) and says whether they confirm it,
//! refute it, or leave it unconfirmed ([`Unconfirmed`], named); [`unchecked`] says where a
//! shortcut is not asked at all.

use serde::Serialize;
use squeal_core::error::Number;
use squeal_core::validated::Validity;
use squeal_core::{Params, Setup, State};

use super::{Ends, Fate, fates, step_share};
use crate::atlas::BoundaryParam;
use crate::error::ScanError;
use crate::sensitivity::StepShare;

/// Why the runs at a shortcut's answer did not confirm it (the answer stands, unconfirmed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Unconfirmed {
    /// A start above the answer neither reached the fixed point nor was certified on an
    /// oscillation by the horizon (irregular motion, or a transient longer than it).
    UndecidedAbove,
    /// Every start below the answer settles: the squeal the shortcut found there (a fold's
    /// band) lies where none of the starts goes.
    SettlesBelow,
}

impl Unconfirmed {
    /// The name in notes and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Unconfirmed::UndecidedAbove => "undecided_above",
            Unconfirmed::SettlesBelow => "settles_below",
        }
    }
}

/// What the runs at a shortcut's answer said.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Confirmation {
    /// What contradicted the answer (`None`: no run did).
    pub refuted: Option<String>,
    /// Whether the runs confirmed it: below it a start lasts, above it every start settles
    /// (`false` with no contradiction: a run was undecided by the horizon).
    pub confirmed: bool,
    /// Why not, where they did not (and no run refuted it).
    pub unconfirmed: Option<Unconfirmed>,
    /// The runs in words.
    pub line: String,
    /// The runs below the answer and above it.
    pub ends: [Ends; 2],
    /// The share of the starts at the two ends whose fate at `dt / 2` differs from the
    /// one at `dt` ([`step_share`]).
    pub step: StepShare,
}

/// Confirms a shortcut's bracket `[lo, hi]` by runs of `starts` (the start of a critical
/// value, the [`super::Spread`] of a fold) at its ends: below it some start must not settle,
/// above it every start must. Refuted where a start lasts above it, or where the one start
/// of a critical value settles below it. The same runs at `dt / 2` give the answer's step
/// sensitivity (they decide nothing else: the shortcut's own `dt / 2` check stands).
pub fn confirm(
    setup: Setup,
    param: BoundaryParam,
    starts: &[State],
    [lo, hi]: [f64; 2],
    horizon: f64,
) -> Result<Confirmation, ScanError> {
    let ([below, above], step) = runs_at(setup, param, starts, [lo, hi], horizon)?;
    let k = param.key();
    let start = |i: usize| format!("({}, {})", Number(starts[i].x), Number(starts[i].v));
    // A contradiction: one start lasts above the answer, or the one start of a critical
    // value settles below it. Every start of a fold's spread settling below it is none: the
    // shortcut's squeal there (the band the crisis found) may lie where no start of the
    // spread goes. An undecided run is none either: the answer stands, unconfirmed, and
    // says so.
    let refuted = if below.all_settle() && starts.len() == 1 {
        Some(format!(
            "at {k} = {lo:.6e}, below the answer, every start reaches the fixed point by t = {horizon}"
        ))
    } else {
        above.first_lasting().map(|(i, f)| {
            format!(
                "at {k} = {hi:.6e}, above the answer, the run from {} {}",
                start(i),
                f.words(horizon)
            )
        })
    };
    let last = above
        .fates
        .iter()
        .filter_map(|f| match f {
            Fate::Settles { t } => Some(*t),
            _ => None,
        })
        .fold(0.0, f64::max);
    let confirmed = below.first_lasting().is_some() && above.all_settle();
    // Unconfirmed and not refuted: a start above was undecided, or every start below
    // settled (a start lasting above refutes the answer).
    let unconfirmed = match (confirmed || refuted.is_some(), above.first_unsettled()) {
        (true, _) => None,
        (false, Some(_)) => Some(Unconfirmed::UndecidedAbove),
        (false, None) => Some(Unconfirmed::SettlesBelow),
    };
    let named = unconfirmed.map_or(String::new(), |u| format!(" ({})", u.name()));
    let line = match (below.first_unsettled(), above.first_unsettled()) {
        (Some((i, f)), None) => format!(
            "confirmed by runs: at {k} = {lo:.6e} the run from {} {}; at {hi:.6e} every start reaches the fixed point (the last at t = {last:.1})",
            start(i),
            f.words(horizon)
        ),
        (_, Some((i, f))) => format!(
            "NOT confirmed by runs{named}: at {k} = {hi:.6e}, above the answer, the run from {} {}",
            start(i),
            f.words(horizon)
        ),
        (None, None) => format!(
            "NOT confirmed by runs{named}: at {k} = {lo:.6e}, below the answer, every start settles by t = {horizon}"
        ),
    };
    Ok(Confirmation {
        refuted,
        confirmed,
        unconfirmed,
        line,
        ends: [below, above],
        step,
    })
}

/// The runs of `starts` at `lo` and `hi`, at `dt` and at `dt / 2`, all side by side: the
/// ends at `dt`, and the share of starts whose fate the step moved ([`step_share`]). A
/// failure at `lo` is the one returned, as one after the other.
fn runs_at(
    setup: Setup,
    param: BoundaryParam,
    starts: &[State],
    [lo, hi]: [f64; 2],
    horizon: f64,
) -> Result<([Ends; 2], StepShare), ScanError> {
    let at = |v: f64, half: bool| -> Result<Ends, ScanError> {
        let mut s = setup.with_params(param.with(setup.params, v));
        if half {
            s = s.half_dt();
        }
        let out = fates(s, starts, horizon, true)?;
        Ok(Ends {
            value: v,
            fates: out.into_iter().map(|(f, _)| f).collect(),
        })
    };
    let ends = |half: bool| rayon::join(|| at(lo, half), || at(hi, half));
    let ((below, above), (half_below, half_above)) = rayon::join(|| ends(false), || ends(true));
    let (below, above) = (below?, above?);
    let step = step_share(&[(&below, &half_below?), (&above, &half_above?)]);
    Ok(([below, above], step))
}

/// Where `p` lies outside the region the shortcuts were checked in, the parameters outside
/// it in a few words ([`Validity`]); `None` inside. McMillan's laws only: their shortcuts
/// (the unstable cycle on the section, the band above it, its crisis) rest on the paper's
/// picture, which fails at low belt speed. The laws with true stick decide by the orbit from
/// the one breakaway state every stick phase ends at (an exact argument, MODEL.md section
/// 8), and Coulomb's answers are closed forms (no cycle): their shortcuts are confirmed by
/// runs where they give a bracket, never replaced wholesale.
pub fn unchecked(p: &Params) -> Option<String> {
    use squeal_core::FrictionLaw::{McMillan, McMillanNonHysteretic};
    if !matches!(p.kind(), McMillan | McMillanNonHysteretic) {
        return None;
    }
    let v = Validity::of(p);
    if v.checked {
        return None;
    }
    if v.outside.is_empty() {
        return Some(format!("law {} is checked nowhere", p.law.name()));
    }
    let what: Vec<String> = (v.outside.iter())
        .map(|u| {
            let (lo, hi) = (Number(u.checked[0]), Number(u.checked[1]));
            format!("{} = {:.4} outside [{lo}, {hi}]", u.key, u.value)
        })
        .collect();
    Some(format!("{}; MODEL.md section 11", what.join(", ")))
}
