//! The atlas for the laws with true stick ([`squeal_core::LawFamily::TrueStick`]: the
//! Stribeck, cubic and tabulated laws).
//!
//! Each point is computed twice over, by independent evidence, and labelled only where
//! the two agree:
//!
//! * the **section search** of [`super::point::compute_point`] (the return map `D(r)` on
//!   `x = x*, x' > 0`, the unstable cycle located as `squeal ulc` does, the stick-slip
//!   attractor run for `transient + window` revolutions, the operating point's own run);
//! * the **landscape** ([`squeal_core::landscape::landscape_evidence`], as `squeal scan` stores
//!   per map): the fixed point repels exactly where `2 xi + mu'(v_d) < 0`, and the
//!   stick-slip cycle exists exactly when the orbit from the one breakaway state sticks
//!   again (every stick phase ends there).
//!
//! They agree when `stick_slip_only` goes with `fixed_point_unstable` (every start ends in
//! stick-slip, basin fraction of steady slip 0), `steady_slip_only` with `steady_slip_only`
//! (every start ends in steady slip, fraction 1; this rests on the landscape's assumption
//! of no slip-only cycle, which the section search checks below `r_max`) and `bistable`
//! with `bistable_quiet` or `bistable_squeals` (by the operating point). Anything else is
//! `undecided`, with a note naming both findings.
//!
//! For this law the stick-slip attractor is the cycle through the breakaway state, so its
//! "share of time on the quasi-static branch" is replaced by the share of time stuck per
//! period (`stick_stuck_share`), from the cycle's located stick onset and breakaway.
//!
//! Boundaries ([`both_in`]) bisect the landscape itself: the **fold** is where the
//! stick-slip cycle ends (the landscape turns `steady_slip_only`), the **critical value**
//! where the operating point stops squealing (`steady_slip_only`, or `bistable` with the
//! unstable cycle enclosing the point).

use squeal_core::landscape::{self, LandscapeEvidence, StickCycle};
use squeal_core::{Classifier, Landscape, Setup, State};

use crate::section::{ParamRange, Search};

use super::boundary::{Boundary, BoundaryParam, bisect_nu};
use super::columns::{Column, Kind, Num, Twin};
pub use super::figures::LandscapeRecord;
use super::note::{Note, NoteKind};
use super::point::{self, AtlasRegime, PointResult, PointSettings, analyse};
use crate::error::ScanError;
use crate::landscape::{LANDSCAPE_FIELDS, evidence_words};

fn rec(p: &mut PointResult) -> &mut LandscapeRecord {
    p.landscape.get_or_insert(LandscapeRecord {
        landscape: Landscape::Unknown as u8,
        damping: f64::NAN,
        cycle_period: f64::NAN,
        cycle_stuck: f64::NAN,
    })
}

/// The landscape's numbers as stored per point (Stribeck atlases only), named as the scan
/// stores them per map ([`LANDSCAPE_FIELDS`]). The verdict itself is the enum `landscape`.
pub const LANDSCAPE_COLUMNS: &[Column] = &[
    Column {
        name: LANDSCAPE_FIELDS[0].0,
        long_name: LANDSCAPE_FIELDS[0].1,
        units: "1",
        kind: Kind::F64,
        flags: &[],
        fill: Num::F(f64::NAN),
        get: |p| Num::F(p.landscape.map_or(f64::NAN, |l| l.damping)),
        set: |p, v| rec(p).damping = v.as_f64(),
        si: Twin::None,
    },
    Column {
        name: LANDSCAPE_FIELDS[1].0,
        long_name: LANDSCAPE_FIELDS[1].1,
        units: "1",
        kind: Kind::F64,
        flags: &[],
        fill: Num::F(f64::NAN),
        get: |p| Num::F(p.landscape.map_or(f64::NAN, |l| l.cycle_period)),
        set: |p, v| rec(p).cycle_period = v.as_f64(),
        si: Twin::None,
    },
    Column {
        name: LANDSCAPE_FIELDS[2].0,
        long_name: LANDSCAPE_FIELDS[2].1,
        units: "1",
        kind: Kind::F64,
        flags: &[],
        fill: Num::F(f64::NAN),
        get: |p| Num::F(p.landscape.map_or(f64::NAN, |l| l.cycle_stuck)),
        set: |p, v| rec(p).cycle_stuck = v.as_f64(),
        si: Twin::None,
    },
];

/// The stored name and long name of the point column `stick_quasi_static_share` for laws
/// with true stick: the share of time stuck.
pub const STUCK_SHARE: (&str, &str) = (
    "stick_stuck_share",
    "stick-slip: share of time stuck (x' = v_d) per period of the stick-slip cycle, from its \
     located stick onset and breakaway (the Stribeck law's counterpart of the share of time \
     on the quasi-static branch)",
);

/// The landscape of `params` with the classifier's default `t_max` and `fp_radius` (the
/// values `squeal scan` uses unless its spec sets them).
pub fn evidence(setup: Setup) -> Result<LandscapeEvidence, ScanError> {
    let st = setup.stepper()?;
    let cl = Classifier::default();
    landscape::landscape_evidence(&st, cl.t_max, cl.fp_radius).ok_or_else(|| {
        ScanError::Undetermined(format!(
            "law {} has no true stick: no landscape",
            setup.params.law
        ))
    })
}

/// Whether the section search's regime and the landscape agree (`None`: the search itself
/// is undecided).
pub fn agrees(landscape: Landscape, regime: AtlasRegime) -> Option<bool> {
    use AtlasRegime as R;
    match (landscape, regime) {
        (_, R::Undecided) => None,
        (Landscape::StickSlipOnly, R::FixedPointUnstable)
        | (Landscape::SteadySlipOnly, R::SteadySlipOnly)
        | (Landscape::Bistable, R::BistableQuiet | R::BistableSqueals) => Some(true),
        _ => Some(false),
    }
}

/// All figures at one point of a law with true stick: the section search's
/// ([`point::compute_point`]) checked against the landscape (module docs).
pub fn compute_point(
    setup: Setup,
    ps: &PointSettings,
    warm: Option<f64>,
) -> Result<PointResult, ScanError> {
    let ev = evidence(setup)?;
    let mut res = point::compute_point(setup, ps, warm)?;
    reconcile(&mut res, &ev);
    Ok(res)
}

/// Stores the landscape in `res`, replaces the quasi-static share by the share of time
/// stuck, and makes the point undecided (with both findings in its note) where the section
/// search and the landscape disagree.
pub fn reconcile(res: &mut PointResult, ev: &LandscapeEvidence) {
    res.landscape = Some(LandscapeRecord::from_evidence(ev));
    if let Some(s) = res.stick_slip.as_mut() {
        s.quasi_static_share = match ev.cycle {
            StickCycle::Exists { period, stuck } => stuck / period,
            _ => f64::NAN,
        };
    }
    let landscape = format!(
        "the landscape says {} ({})",
        ev.landscape.name(),
        evidence_words(ev)
    );
    match agrees(ev.landscape, res.regime) {
        Some(true) => {}
        None => {
            let words = Note::new(NoteKind::Finding, landscape);
            res.note = Some(Note::add(res.note.take(), words));
        }
        Some(false) => {
            let search = match res.cycle {
                Some(c) => format!(
                    "{} (unstable cycle at r = {:.6})",
                    res.regime.name(),
                    c.r_section
                ),
                None => res.regime.name().to_string(),
            };
            let extra = res
                .note
                .take()
                .map_or(String::new(), |n| format!("; its note: {n}"));
            res.note = Some(Note::conflict(format!(
                "conflict: the section search says {search} but {landscape}{extra}"
            )));
            res.regime = AtlasRegime::Undecided;
        }
    }
}

/// Whether `point` does not squeal at `params`, read from the landscape: steady slip only
/// (quiet), stick-slip only (squeals), bistable (quiet exactly when the unstable cycle the
/// section search locates encloses it). `Err` with both findings where they cannot tell.
fn point_quiet(
    setup: Setup,
    ps: &PointSettings,
    point: State,
    ev: &LandscapeEvidence,
) -> Result<bool, String> {
    match ev.landscape {
        Landscape::SteadySlipOnly => Ok(true),
        Landscape::StickSlipOnly => Ok(false),
        Landscape::Unknown => Err(format!("the landscape is unknown ({})", evidence_words(ev))),
        Landscape::Bistable => {
            let a = analyse(setup, ps, None, false).map_err(|e| e.to_string())?;
            match (&a.search, &a.cycle) {
                (Search::Bracket { .. }, Some(rep)) => Ok(rep.encloses(point.x, point.v)),
                (s, _) => Err(format!(
                    "conflict: the landscape says bistable ({}) but the section search found no \
                     unstable cycle ({s:?})",
                    evidence_words(ev)
                )),
            }
        }
    }
}

/// Both boundaries of one combination of the other parameters for a law with true stick
/// (the counterpart of [`super::boundary::both_in`]): the fold, where the landscape turns
/// `steady_slip_only` (the stick-slip cycle ends), and the critical value of `point`.
/// Each value's landscape is computed once and answers both.
pub fn both_in(
    param: BoundaryParam,
    setup: Setup,
    ps: &PointSettings,
    point: State,
    range: ParamRange,
    [fold, critical]: [bool; 2],
) -> [Option<Result<Boundary, ScanError>>; 2] {
    use std::cell::RefCell;
    use std::collections::HashMap;
    type Answers = (Result<bool, String>, Result<bool, String>);
    let memo: RefCell<HashMap<(u64, u64), Answers>> = RefCell::new(HashMap::new());
    let eval_at = |v: f64, at: Setup| -> Result<Answers, ScanError> {
        if let Some(a) = memo.borrow().get(&(v.to_bits(), at.dt.to_bits())) {
            return Ok(a.clone());
        }
        let here_setup = at.with_params(param.with(at.params, v));
        let p = here_setup.params;
        let ev = evidence(here_setup)?;
        let here = |e: String| format!("xi = {}, v_d = {}: {e}", p.nu, p.lambda);
        let everywhere = match ev.landscape {
            Landscape::SteadySlipOnly => Ok(true),
            Landscape::StickSlipOnly | Landscape::Bistable => Ok(false),
            Landscape::Unknown => Err(here(format!(
                "cannot tell whether anything squeals: {}",
                evidence_words(&ev)
            ))),
        };
        let at_point = if critical {
            point_quiet(here_setup, ps, point, &ev).map_err(here)
        } else {
            Ok(false)
        };
        let ans = (everywhere, at_point);
        memo.borrow_mut()
            .insert((v.to_bits(), at.dt.to_bits()), ans.clone());
        Ok(ans)
    };
    let pick = |which: usize, (e, c): Answers| if which == 0 { e } else { c };
    let run = |which: usize| {
        bisect_nu(
            |v| pick(which, eval_at(v, setup)?).map_err(ScanError::Undetermined),
            range,
        )
    };
    let mut out = [fold.then(|| run(0)), critical.then(|| run(1))];
    // Each bracket checked at dt / 2, as for McMillan's laws.
    super::boundary::check_half_dt(&mut out, |which, v| {
        eval_at(v, setup.half_dt())
            .ok()
            .and_then(|a| pick(which, a).ok())
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atlas::boundary::BoundaryStatus;
    use crate::atlas::driver::{Unit, UnitResult, run_unit};
    use crate::atlas::spec::AtlasPlan;
    use crate::ulc::{self, CycleSettings};
    use squeal_core::Stepper;

    /// bSTAB's friction case (xi = 0.05, mu_d = 0.5, mu_sd = 2, v_0 = 0.5, mu_v = 0, the
    /// defaults) at the given belt speeds, disturbance box = bSTAB's region.
    fn plan(v_d: &str) -> AtlasPlan {
        AtlasPlan::from_toml(
            &format!(
                r#"version = 1
[model]
law = "stribeck"
v_d = {v_d}
[disturbance]
x = [-2.0, 2.0]
v = [0.0, 2.0]
[boundaries]
rtol = 1e-3
[output]
path = "s.h5"
"#
            ),
            "s.toml",
        )
        .unwrap()
    }

    fn line(p: &AtlasPlan) -> Vec<PointResult> {
        match run_unit(p, Unit::Line(0)).unwrap() {
            UnitResult::Line(l) => l.points,
            u => panic!("{u:?}"),
        }
    }

    #[test]
    fn bstab_speeds_give_the_three_regimes_agreeing_with_the_landscape() {
        // MODEL.md section 8 and crate::landscape's test: at xi = 0.05 the fixed point
        // repels below v_d = 0.5 ln 10 = 1.151 (closed form of 2 xi + mu'(v_d) = 0), the
        // stick-slip cycle exists up to between 1.8 and 2.0.
        let p = plan("[1.0, 1.5, 2.2]");
        let pts = line(&p);
        let regimes: Vec<AtlasRegime> = pts.iter().map(|q| q.regime).collect();
        assert_eq!(regimes[0], AtlasRegime::FixedPointUnstable, "{:?}", pts[0]);
        assert!(
            matches!(
                regimes[1],
                AtlasRegime::BistableQuiet | AtlasRegime::BistableSqueals
            ),
            "{:?}",
            pts[1]
        );
        assert_eq!(regimes[2], AtlasRegime::SteadySlipOnly, "{:?}", pts[2]);
        // The stored landscape is the one `squeal scan` computes for the same parameters
        // (crate::landscape, the scan's own path).
        let want = [
            Landscape::StickSlipOnly,
            Landscape::Bistable,
            Landscape::SteadySlipOnly,
        ];
        for (i, (q, w)) in pts.iter().zip(want).enumerate() {
            let scan = crate::Plan::from_toml(
                &format!(
                    "version = 1\n[model]\nlaw = \"stribeck\"\nv_d = {}\n[grid]\nx0 = {{ min = -2.0, max = 2.0, count = 2 }}\nv0 = {{ min = 0.0, max = 2.0, count = 2 }}\n[output]\npath = \"t.h5\"\n",
                    p.space.params_at(i).lambda
                ),
                "t.toml",
            )
            .unwrap();
            let l = crate::landscape::of_map(&scan, 0).unwrap().unwrap();
            assert_eq!(l.landscape, w);
            let r = q.landscape.unwrap();
            assert_eq!(r.verdict(), Some(w));
            // Bit for bit (NaN where no cycle: compared as text).
            assert_eq!(
                format!("{r:?}"),
                format!("{:?}", LandscapeRecord::from_evidence(&l))
            );
            assert!(q.note.is_none(), "{:?}", q.note);
        }
        // Every start squeals / none does: fractions 0 and 1, stated with no error.
        assert_eq!(
            (pts[0].basin_fraction, pts[0].basin_fraction_err),
            (0.0, 0.0)
        );
        assert_eq!(
            (pts[2].basin_fraction, pts[2].basin_fraction_err),
            (1.0, 0.0)
        );
        // Stick-slip at 1.0 and 1.5, none at 2.2; its stuck share is the cycle's.
        for q in &pts[..2] {
            let s = q.stick_slip.unwrap();
            let l = q.landscape.unwrap();
            assert_eq!(s.quasi_static_share, l.cycle_stuck / l.cycle_period);
            assert!(s.quasi_static_share > 0.0 && s.quasi_static_share < 1.0);
            // The attractor's mean period over its window is the cycle's period from
            // breakaway to breakaway (the same orbit), to a few steps.
            let period = std::f64::consts::TAU / s.omega_mean;
            assert!(
                (period - l.cycle_period).abs() < 4.0 * p.dt,
                "{period} vs {}",
                l.cycle_period
            );
        }
        assert!(pts[2].stick_slip.is_none() && pts[2].cycle.is_none());
    }

    #[test]
    fn basin_fraction_at_bstabs_case_matches_the_published_value() {
        // tests/data/bstab_friction_published.json, case1 (pyBasin's repository, the MATLAB
        // bSTAB run): v_d = 1.5, steady slip ("FP") 0.304 with standard error 0.0065 over
        // x in [-2, 2], x' in [0, 2] (5000 uniform random starts).
        // (No JSON parser in this crate: the numbers are read after the "case1" key.)
        let doc = include_str!("../../../../tests/data/bstab_friction_published.json");
        let case1 = &doc[doc.find("\"case1\"").unwrap()..];
        let num = |key: &str| -> f64 {
            let at = case1.find(&format!("\"{key}\":")).unwrap() + key.len() + 3;
            let rest = case1[at..].trim_start();
            let end = rest.find([',', '\n', '}']).unwrap();
            rest[..end].trim().parse().unwrap()
        };
        assert_eq!(num("v_d"), 1.5);
        let (bs, se) = (num("bs_FP"), num("se_FP"));
        assert!((bs - 0.304).abs() < 1e-12 && (se - 0.0065).abs() < 1e-4);
        let p = plan("1.5");
        let q = &line(&p)[0];
        assert!(q.basin_fraction_err.is_finite() && q.basin_fraction_err < 0.02);
        assert!(
            (q.basin_fraction - bs).abs() <= 3.0 * se + q.basin_fraction_err,
            "atlas {} +- {} vs published {bs} +- {se}",
            q.basin_fraction,
            q.basin_fraction_err
        );
    }

    #[test]
    fn the_cycle_at_a_bistable_point_is_ulcs() {
        // `squeal ulc --law stribeck --v-d 1.5` (crate::ulc::locate, bisection to rtol 1e-10)
        // against the atlas's (false position to rtol 1e-9): the same root of D.
        let p = plan("[1.4, 1.5, 1.7]");
        for (i, q) in line(&p).iter().enumerate() {
            let params = p.space.params_at(i);
            let rep = ulc::locate(
                Setup::new(params, p.dt, p.solver),
                &CycleSettings::default(),
            )
            .unwrap();
            let c = q.cycle.unwrap();
            assert!(
                (c.r_section - rep.r_section).abs() <= 2e-9 * rep.r_section,
                "v_d = {}: {} vs {}",
                params.lambda,
                c.r_section,
                rep.r_section
            );
            assert!((c.period - rep.period).abs() < 1e-6);
            assert!((c.area - rep.area).abs() < 1e-6 * rep.area);
            // And the dt/2 check moved it little.
            assert!(c.half_dt_shift.abs() < 1e-3 * c.r_section, "{c:?}");
        }
    }

    #[test]
    fn boundaries_in_v_d_lie_where_the_labels_flip() {
        let p = plan("[1.0, 2.2]");
        let ps = p.settings_at(0);
        let [fold, crit] = both_in(
            BoundaryParam::Lambda,
            p.setup_at(0),
            &ps,
            ps.operating,
            ParamRange::new(1.0, 2.2, 1e-3),
            [true, true],
        );
        let (fold, crit) = (fold.unwrap().unwrap(), crit.unwrap().unwrap());
        assert_eq!(fold.status, BoundaryStatus::Found);
        assert_eq!(crit.status, BoundaryStatus::Found);
        // MODEL.md section 8: the stick-slip cycle ends between v_d = 1.8 and 2.0.
        assert!(fold.nu > 1.8 && fold.nu < 2.0, "{fold:?}");
        // Rest squeals at least where the fixed point repels (v_d < 1.151).
        assert!(crit.nu > 1.151 && crit.nu <= fold.nu, "{crit:?}");
        section_method_agrees(&p, fold, crit);
        labels_flip_across(&p, fold, crit);
    }

    /// `squeal critical --fold` / `squeal critical --in lambda` bisect the section
    /// method's predicates instead (super::boundary: stick-slip runs outside the located
    /// cycle; the cycle enclosing the point): independent evidence, the same brackets to
    /// their width as `fold` and `crit` of plan `p`.
    fn section_method_agrees(p: &AtlasPlan, fold: Boundary, crit: Boundary) {
        let ps = p.settings_at(0);
        let base = p.space.params_at(0);
        for (ours, theirs) in [
            (
                fold,
                super::super::boundary::fold_in(
                    BoundaryParam::Lambda,
                    Setup::new(base, p.dt, p.solver),
                    &ps,
                    ParamRange::new(1.0, 2.2, 1e-3),
                )
                .unwrap(),
            ),
            (
                crit,
                super::super::boundary::critical_in(
                    BoundaryParam::Lambda,
                    Setup::new(base, p.dt, p.solver),
                    &ps,
                    ps.operating,
                    ParamRange::new(1.0, 2.2, 1e-3),
                )
                .unwrap(),
            ),
        ] {
            assert_eq!(theirs.status, BoundaryStatus::Found);
            assert!(
                ours.bracket[0] <= theirs.bracket[1] && theirs.bracket[0] <= ours.bracket[1],
                "{:?} vs {:?}",
                ours.bracket,
                theirs.bracket
            );
        }
    }

    /// The atlas's own labels (section search and landscape together) flip across the
    /// brackets of `fold` and `crit` of plan `p`, 1% either side, and so does the operating
    /// point's own run to settlement.
    fn labels_flip_across(p: &AtlasPlan, fold: Boundary, crit: Boundary) {
        let ps = p.settings_at(0);
        let base = p.space.params_at(0);
        let at = |v_d: f64| {
            compute_point(
                Setup::new(BoundaryParam::Lambda.with(base, v_d), p.dt, p.solver),
                &ps,
                None,
            )
            .unwrap()
        };
        let below = at(0.99 * fold.bracket[0]);
        let above = at(1.01 * fold.bracket[1]);
        assert!(
            matches!(
                below.regime,
                AtlasRegime::BistableQuiet | AtlasRegime::BistableSqueals
            ),
            "{below:?}"
        );
        assert_eq!(above.regime, AtlasRegime::SteadySlipOnly, "{above:?}");
        let below = at(0.99 * crit.bracket[0]);
        let above = at(1.01 * crit.bracket[1]);
        assert_eq!(
            below.regime.operating_point_squeals(),
            Some(true),
            "{below:?}"
        );
        assert_eq!(
            above.regime.operating_point_squeals(),
            Some(false),
            "{above:?}"
        );
        // Independent of the section method: the operating point's own run to settlement
        // (the classifier of `squeal classify`) flips there too.
        let cl = Classifier::default();
        for (v_d, steady) in [
            (0.99 * crit.bracket[0], false),
            (1.01 * crit.bracket[1], true),
        ] {
            let st = Stepper::new(BoundaryParam::Lambda.with(base, v_d), p.dt, p.solver).unwrap();
            let o = cl.classify(&st, ps.operating);
            assert_eq!(
                o.regime == squeal_core::Regime::SteadySlip,
                steady,
                "v_d = {v_d}: {o:?}"
            );
        }
    }

    #[test]
    fn disagreement_is_undecided_with_both_findings() {
        // The landscape of v_d = 1.5 (bistable) against a section search that (say) found
        // nothing: the point is undecided and its note names both.
        let p = plan("1.5");
        let ev = evidence(Setup::new(p.space.params_at(0), p.dt, p.solver)).unwrap();
        assert_eq!(ev.landscape, Landscape::Bistable);
        let mut r = crate::atlas::columns::empty_point();
        r.regime = AtlasRegime::SteadySlipOnly;
        reconcile(&mut r, &ev);
        assert_eq!(r.regime, AtlasRegime::Undecided);
        let note = r.note.unwrap();
        assert_eq!(note.kind, NoteKind::Conflict, "{note}");
        let note = note.text;
        assert!(
            note.contains("steady_slip_only") && note.contains("says bistable"),
            "{note}"
        );
        // Agreement leaves the label alone.
        let mut r = crate::atlas::columns::empty_point();
        r.regime = AtlasRegime::BistableQuiet;
        reconcile(&mut r, &ev);
        assert_eq!(r.regime, AtlasRegime::BistableQuiet);
        assert!(r.note.is_none());
    }
}
