//! The atlas's work units and their parallel driver.
//!
//! A **line** is the points along the last swept axis with the other indices fixed; its
//! points run in order, each warm-started from the previous point's cycle crossing, so a
//! result depends only on the plan and the unit (not on threads or order). A **boundary**
//! unit locates the fold and the critical damping for one combination of the swept axes
//! other than the damping. Units run in parallel (rayon); each finished one is handed to
//! the caller's sink, which journals it (crash safety) and later writes the file.

use std::sync::atomic::AtomicBool;

use serde::{Deserialize, Serialize};
use squeal_core::{LawFamily, Setup};

pub use super::boundary::BoundaryResult;
use super::boundary::{self, Boundary, BoundaryParam, BoundaryStatus};
use super::note::{Note, NoteKind};
use super::point::{PointResult, PointSettings, compute_point};
use super::spec::AtlasPlan;
use crate::error::ScanError;
use crate::executor::{Emit, execute};
use crate::section::ParamRange;

/// One unit of work.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Unit {
    /// Line `i`: points `i * len .. (i + 1) * len` (len = the last axis' length).
    Line(usize),
    /// Boundary search `j` (index into the boundary array).
    Boundary(usize),
}

/// The points of one line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LineResult {
    /// Line index.
    pub line: usize,
    /// Its points, in order.
    pub points: Vec<PointResult>,
}

/// A finished unit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum UnitResult {
    /// A line of points.
    Line(LineResult),
    /// A boundary search.
    Boundary(BoundaryResult),
}

impl UnitResult {
    /// Which unit this is.
    pub fn unit(&self) -> Unit {
        match self {
            UnitResult::Line(l) => Unit::Line(l.line),
            UnitResult::Boundary(b) => Unit::Boundary(b.index),
        }
    }
}

impl AtlasPlan {
    /// Points per line (the last swept axis' length, 1 with no axes).
    pub fn line_len(&self) -> usize {
        self.space.shape().last().copied().unwrap_or(1)
    }

    /// Number of lines.
    pub fn n_lines(&self) -> usize {
        self.space.n_points() / self.line_len()
    }

    /// Every unit: the boundary searches first (the longest), then the lines.
    pub fn units(&self) -> Vec<Unit> {
        (0..self.n_boundaries())
            .map(Unit::Boundary)
            .chain((0..self.n_lines()).map(Unit::Line))
            .collect()
    }
}

/// Point `i` of the plan, computed as the atlas computes it (`warm`: the previous point's
/// section crossing on its line). Laws with true stick check the section search against the
/// landscape. A failure is data: an undecided point with its reason.
pub fn compute_at(plan: &AtlasPlan, i: usize, warm: Option<f64>) -> PointResult {
    let compute = match plan.space.law.family() {
        LawFamily::TrueStick => super::true_stick::compute_point,
        LawFamily::Regularised => compute_point,
    };
    compute(plan.setup_at(i), &plan.settings_at(i), warm).unwrap_or_else(|e| {
        let mut p = super::columns::empty_point();
        p.note = Some(Note::new(NoteKind::Failure, e.to_string()));
        p
    })
}

/// Runs one unit.
pub fn run_unit(plan: &AtlasPlan, unit: Unit) -> Result<UnitResult, ScanError> {
    Ok(match unit {
        Unit::Line(line) => UnitResult::Line(run_line(plan, line)),
        Unit::Boundary(j) => UnitResult::Boundary(run_boundary(plan, j)),
    })
}

/// The points of line `line`, each warm-started from the previous point's crossing.
fn run_line(plan: &AtlasPlan, line: usize) -> LineResult {
    let len = plan.line_len();
    let mut points = Vec::with_capacity(len);
    let mut warm = None;
    for i in line * len..(line + 1) * len {
        let p = compute_at(plan, i, warm);
        warm = p.cycle.map(|c| c.r_section);
        points.push(p);
    }
    LineResult { line, points }
}

/// Boundary `j`: the fold and the critical value, each through the gate of `critical`
/// ([`gated`]), and the lifetimes above the fold. A failed run inside a bisection leaves
/// that boundary not computed, with the reason: one hard point does not abort the atlas.
fn run_boundary(plan: &AtlasPlan, j: usize) -> BoundaryResult {
    let (i, range) = plan.boundary_setup(j);
    let ps = plan.settings_at(i);
    let mut notes: Option<Note> = None;
    let range = ParamRange {
        lo: range[0],
        hi: range[1],
        rtol: plan.boundary_rtol,
    };
    let (param, setup, which) = (
        plan.boundary_in,
        plan.setup_at(i),
        [plan.fold, plan.critical],
    );
    let [f, c] = shortcut_boundaries(plan, setup, &ps, range);
    let at = ((param, setup), &ps, range);
    // The two gates' runs side by side; their notes in the order fold, critical.
    let ((fold, fold_note), (critical, critical_note)) = rayon::join(
        || gated(at, (which[0], true), f),
        || gated(at, (which[1], false), c),
    );
    for n in [fold_note, critical_note].into_iter().flatten() {
        notes = Some(Note::add(notes.take(), n));
    }
    let mut keep = |what: &str, r: Result<Boundary, ScanError>| match r {
        Ok(b) => b,
        Err(e) => {
            let n = Note::new(NoteKind::Failure, format!("{what}: {e}"));
            notes = Some(Note::add(notes.take(), n));
            Boundary::none()
        }
    };
    let fold = fold.map_or_else(Boundary::none, |r| keep("fold", r));
    let critical = critical.map_or_else(Boundary::none, |r| keep("critical", r));
    if fold.changes > 1 {
        let n = Note::new(
            NoteKind::Finding,
            format!(
                "fold: the regime changes {} times along {} in the coarse scan ({} steps): the fold is the last change",
                fold.changes,
                plan.boundary_words(),
                plan.boundary_coarse
            ),
        );
        notes = Some(Note::add(notes, n));
    }
    let lifetime = match fold_lifetime(plan, setup, &ps, &fold) {
        Ok(l) => l,
        Err(e) => {
            let n = Note::new(NoteKind::Failure, format!("lifetimes: {e}"));
            notes = Some(Note::add(notes.take(), n));
            crate::lifetime::FoldLifetime::none()
        }
    };
    BoundaryResult {
        index: j,
        fold,
        critical,
        lifetime,
        note: notes,
    }
}

/// The shortcuts' answers for the fold and the critical value, as the law's family
/// searches a boundary, where the checked region holds (else not computed: the gate
/// answers by runs without them).
fn shortcut_boundaries(
    plan: &AtlasPlan,
    setup: Setup,
    ps: &PointSettings,
    range: ParamRange,
) -> [Option<Result<Boundary, ScanError>>; 2] {
    let (param, which) = (plan.boundary_in, [plan.fold, plan.critical]);
    let checked = crate::fates::unchecked(&setup.params).is_none();
    match (checked, plan.space.law.family()) {
        (false, _) => [None, None],
        (true, LawFamily::TrueStick) => {
            super::true_stick::both_in(param, setup, ps, ps.operating, range, which)
        }
        (true, LawFamily::Regularised) => {
            let coarse = plan.boundary_coarse;
            boundary::both_with(param, setup, (ps, ps.operating), range, which, coarse)
        }
    }
}

/// The fold (`fold`) or the critical value, where `asked`, through the gate of `critical`
/// ([`crate::fates::decide`]): the shortcut's answer `found` where it holds, else by runs;
/// with the note of an unconfirmed answer or of an answer by runs.
fn gated(
    ((param, setup), ps, range): ((BoundaryParam, Setup), &PointSettings, ParamRange),
    (asked, fold): (bool, bool),
    found: Option<Result<Boundary, ScanError>>,
) -> (Option<Result<Boundary, ScanError>>, Option<Note>) {
    if !asked {
        return (None, None);
    }
    let mut note = None;
    let starts = crate::fates::starts(fold, (param, setup), range.lo, ps.operating);
    let shortcut = || {
        let b = found.unwrap_or_else(|| Ok(Boundary::none()))?;
        let bracket = b.bracket;
        Ok((b, (b.status == BoundaryStatus::Found).then_some(bracket)))
    };
    let what = if fold { "fold" } else { "critical" };
    let d = crate::fates::decide(
        (setup, param),
        &starts,
        (range, range.hi),
        crate::fates::HORIZON,
        shortcut,
    );
    let got = d.map(|d| match d {
        crate::fates::Decided::Shortcut { answer, confirmed } => {
            if let Some(c) = confirmed.filter(|c| !c.confirmed) {
                note = Some(Note::new(
                    NoteKind::Unconfirmed,
                    format!("{what}: {}", c.line),
                ));
            }
            answer
        }
        crate::fates::Decided::Runs { boundary, why } => {
            note = Some(Note::new(
                NoteKind::Finding,
                format!("{what} by runs because {}", why.words()),
            ));
            boundary.as_boundary()
        }
    });
    (Some(got), note)
}

/// The transient lifetimes above `fold` where the plan asks for them (`[boundaries]
/// lifetime_starts`; the spec allows it only for a crisis in the damping): the table
/// `squeal critical --fold --lifetimes` prints ([`crate::lifetime::lifetime_table`]), with
/// the plan's starts per damping, stored as its nearest row and its fit.
fn fold_lifetime(
    plan: &AtlasPlan,
    setup: squeal_core::Setup,
    ps: &super::point::PointSettings,
    fold: &Boundary,
) -> Result<crate::lifetime::FoldLifetime, ScanError> {
    use crate::lifetime::{DISTANCE_FACTORS, FoldLifetime, LifetimeSettings, lifetime_table};
    if plan.lifetime_starts == 0 || fold.status != super::boundary::BoundaryStatus::Found {
        return Ok(FoldLifetime::none());
    }
    let ls = LifetimeSettings {
        starts: plan.lifetime_starts,
        ..LifetimeSettings::default()
    };
    let cs = super::point::settings_for(&setup.params, &ps.cycle);
    let t = lifetime_table(
        setup,
        &cs,
        &ls,
        (fold.nu, fold.uncertainty),
        &DISTANCE_FACTORS,
    )?;
    Ok(FoldLifetime::of(&t))
}

/// Runs `units` through the one executor ([`crate::executor::execute`]), handing each
/// finished one to `sink` on the calling thread. Stops at the first error or when `stop` is
/// raised (units in flight finish and are handed over). The sink's own error type `E` (the
/// journal's, say) comes back as it is, its sources kept.
pub fn run<E: From<ScanError>>(
    plan: &AtlasPlan,
    units: &[Unit],
    stop: &AtomicBool,
    sink: impl FnMut(UnitResult) -> Result<(), E>,
) -> Result<(), E> {
    let work = |u: Unit, emit: &dyn Fn(Emit<UnitResult, ScanError>)| {
        emit(match run_unit(plan, u) {
            Ok(r) => Emit::Done(r),
            Err(e) => Emit::Failed(e),
        })
    };
    execute(units.to_vec(), stop, work, sink)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_line_and_its_boundary() {
        let plan = AtlasPlan::from_toml(
            r#"
version = 1
[model]
law = "mcmillan"
nu = [1e-3, 1e-2, 5e-2]
[cycle]
half_dt = false
[attractor]
transient = 10
window = 10
[boundaries]
rtol = 1e-2
[output]
path = "x.h5"
"#,
            "x.toml",
        )
        .unwrap();
        assert_eq!(plan.units(), vec![Unit::Boundary(0), Unit::Line(0)]);
        let mut got = Vec::new();
        run(&plan, &plan.units(), &AtomicBool::new(false), |r| {
            got.push(r);
            Ok::<(), ScanError>(())
        })
        .unwrap();
        assert_eq!(got.len(), 2);
        for r in got {
            match r {
                UnitResult::Line(l) => {
                    use super::super::point::AtlasRegime::*;
                    let regimes: Vec<_> = l.points.iter().map(|p| p.regime).collect();
                    // Figs 9 and 10 of the paper, then above the fold (MODEL.md: < 0.031).
                    assert_eq!(
                        regimes,
                        vec![BistableSqueals, BistableQuiet, SteadySlipOnly]
                    );
                    // The second point was warm-started from the first.
                    assert!(!l.points[0].warm_started);
                }
                UnitResult::Boundary(b) => {
                    assert!(b.fold.nu > 0.019 && b.fold.nu < 0.031, "{:?}", b.fold);
                    assert!(b.critical.nu > 1e-3 && b.critical.nu < b.fold.nu);
                }
            }
        }
    }
}
