//! One parameter point to its figures of merit: the unstable cycle, the stick-slip
//! attractor, the regime, and the basin fraction of steady slip over a disturbance box.
//!
//! The cycle is found as in [`crate::ulc`]: a root of `D(r) = P(r) - r` on the section
//! `x = x*, x' > 0`. The search here adds two things:
//! * a **warm start**: a bracket around a neighbour's crossing, checked (`D <= 0` below,
//!   `D > 0` above) before it is trusted, falling back to the cold search otherwise;
//! * a **tangency check** in the cold search: when every sample of `D` is negative, the
//!   largest sample is refined by golden-section search, so that a narrow window of
//!   `D > 0` just below the fold of cycles (where the unstable cycle and the stick-slip
//!   oscillation are about to meet) is not missed between samples.
//!
//! Once bracketed, [`crate::ulc::locate`] bisects and describes the cycle, so the figures are
//! the same as `squeal ulc` gives.

use squeal_core::{Params, Setup};

use crate::error::ScanError;
use crate::section::{self, Bracket, ReturnMap, Search, SectionCycles, search};

use super::attractor::{StickFail, find_stick_slip};
use super::figures::StickSlipFigures;
pub use super::figures::{AtlasRegime, CycleFigures, PointResult, PointSettings};
use super::geometry::{basin_fraction, min_kick};
use super::note::{Note, NoteKind};
use crate::ulc::{CycleReport, CycleSettings, describe_bracket};

pub use crate::section::Work;

/// The section range searched at these parameters: `r_max` at least `2 lambda` (the
/// stick-slip crossing lies below the belt speed, MODEL.md).
pub fn settings_for(p: &Params, cs: &CycleSettings) -> CycleSettings {
    CycleSettings {
        r_max: cs.r_max.max(2.0 * p.lambda),
        ..*cs
    }
}

/// What the section search and the stick-slip runs show at one point (no dt/2 check).
#[derive(Debug)]
pub struct Analysis {
    /// The parameters analysed.
    pub params: Params,
    /// The search's end.
    pub search: Search,
    /// The located cycle, for a bracket.
    pub cycle: Option<CycleReport>,
    /// The stick-slip attractor, if tried.
    pub stick: Option<Result<StickSlipFigures, StickFail>>,
    /// Work done.
    pub work: Work,
}

impl Analysis {
    /// Whether some start squeals (stick-slip reached); `Err` with the reason when the runs
    /// cannot tell.
    pub fn squeals_somewhere(&self) -> Result<bool, String> {
        match (&self.stick, self.search) {
            (Some(Ok(_)), _) => Ok(true),
            (Some(Err(StickFail::FellInside { .. })), _) => Ok(false),
            (Some(Err(StickFail::Failed(e))), _) => Err(e.clone()),
            (None, Search::NoneBelow { .. }) => Ok(false),
            (None, _) => Err("no stick-slip run".into()),
        }
    }
}

/// Searches the cycle, describes it and (if `stick`) looks for the stick-slip attractor.
pub fn analyse(
    setup: Setup,
    ps: &PointSettings,
    warm: Option<f64>,
    stick: bool,
) -> Result<Analysis, ScanError> {
    let st = setup.stepper()?;
    let cs = settings_for(&setup.params, &ps.cycle);
    let mut work = Work::default();
    let found = search(&st, &cs, ps.tangency_iters, warm, &mut work);
    let mut a = Analysis {
        params: setup.params,
        search: found,
        cycle: None,
        stick: None,
        work: Work::default(),
    };
    match found {
        Search::NoneBelow { .. } => {}
        Search::FixedPointUnstable { .. } => {
            if stick {
                a.stick = Some(find_stick_slip(&st, 0.0, ps, cs.t_return, &mut work.stats));
            }
        }
        Search::Bracket { lo, hi, d, .. } => {
            let rep = describe_bracket(&st, &cs, [lo, hi], d, Work::default())?;
            work.returns += rep.returns;
            work.stats.merge(&rep.solver);
            if stick {
                a.stick = Some(find_stick_slip(
                    &st,
                    rep.r_section,
                    ps,
                    cs.t_return,
                    &mut work.stats,
                ));
            }
            a.cycle = Some(rep);
        }
    }
    a.work = work;
    Ok(a)
}

/// How the cycle's crossing moves when `dt` halves (NaN if not found at `dt / 2`): the
/// crossing at `dt / 2` bracketed in `r (1 -+ 2%)` and narrowed by [`ReturnMap::illinois`] to the same
/// tolerance as at `dt`; the whole search range when that bracket does not hold.
fn half_dt_shift(setup: Setup, cs: &CycleSettings, r: f64, w: &mut Work) -> Result<f64, ScanError> {
    let st2 = setup.half_dt().stepper()?;
    let (lo, hi) = (r * 0.98, r * 1.02);
    let map = ReturnMap::new(&st2, cs.t_return);
    let d = [map.d(lo, w), map.d(hi, w)];
    let bracket = Bracket { lo, hi, d };
    if bracket.holds() {
        let (lo, hi) = map.illinois(bracket, cs.rtol, w);
        return Ok(0.5 * (lo + hi) - r);
    }
    Ok(match section::search_section(&map, cs, w) {
        SectionCycles::Unstable { r: r2, .. } => r2 - r,
        _ => f64::NAN,
    })
}

/// All figures at one point; `warm` is a neighbour's section crossing, if known.
pub fn compute_point(
    setup: Setup,
    ps: &PointSettings,
    warm: Option<f64>,
) -> Result<PointResult, ScanError> {
    let mut a = analyse(setup, ps, warm, true)?;
    let steady = squeal_core::SteadySlip::of(&setup.params);
    let cs = settings_for(&setup.params, &ps.cycle);
    let fp = setup.params.fixed_point();
    let mut res = PointResult {
        regime: AtlasRegime::Undecided,
        cycle: None,
        stick_slip: None,
        basin_fraction: f64::NAN,
        basin_fraction_err: f64::NAN,
        warm_started: matches!(a.search, Search::Bracket { warm: true, .. }),
        returns: 0,
        evaluations: 0,
        failures: 0,
        note: None,
        landscape: None,
        steady_slip: steady.stability as u8,
        steady_slip_growth: steady.growth,
    };
    if let Some(rep) = &a.cycle {
        let r = rep.r_section;
        let shift = if cs.check_half_dt {
            half_dt_shift(setup, &cs, r, &mut a.work)?
        } else {
            f64::NAN
        };
        res.cycle = Some(CycleFigures {
            r_section: r,
            bracket: rep.bracket,
            half_dt_shift: shift,
            distance_plus_x: rep.distance_plus_x,
            min_distance: rep.distance_to(fp.x, fp.v),
            min_kick: min_kick(rep, fp.x),
            period: rep.period,
            multiplier: rep.multiplier,
            area: rep.area,
            x_range: rep.x_range,
            v_range: rep.v_range,
            encloses_operating: rep.encloses(ps.operating.x, ps.operating.v),
        });
        let (f, e) = basin_fraction(rep, shift, &ps.disturbance, fp);
        res.basin_fraction = f;
        res.basin_fraction_err = e;
    }
    label(&mut res, &a, ps);
    if res.regime == AtlasRegime::BistableSqueals {
        confirm_operating_point(setup, ps, &mut res, &mut a.work)?;
    }
    if let Some(w) = crate::fates::unchecked(&setup.params) {
        runs_landscape(setup, ps, &mut res, (&w, &mut a.work))?;
    }
    res.returns = a.work.returns;
    res.evaluations = a.work.stats.evaluations;
    res.failures = a.work.stats.failures;
    Ok(res)
}

/// The regime of a point from its section search and stick-slip runs, with the note where
/// they leave it undecided (the cycle's figures already in `res`).
fn label(res: &mut PointResult, a: &Analysis, ps: &PointSettings) {
    match (&a.search, &a.stick) {
        (Search::NoneBelow { .. }, _) => {
            res.regime = AtlasRegime::SteadySlipOnly;
            res.basin_fraction = 1.0;
            res.basin_fraction_err = 0.0;
        }
        (Search::FixedPointUnstable { .. }, Some(Ok(s))) => {
            res.regime = AtlasRegime::FixedPointUnstable;
            res.stick_slip = Some(*s);
            res.basin_fraction = 0.0;
            res.basin_fraction_err = 0.0;
        }
        (Search::Bracket { .. }, Some(Ok(s))) => {
            res.stick_slip = Some(*s);
            res.regime = if res.cycle.is_some_and(|c| c.encloses_operating) {
                AtlasRegime::BistableQuiet
            } else {
                AtlasRegime::BistableSqueals
            };
        }
        (Search::Bracket { .. }, Some(Err(StickFail::FellInside { t }))) => {
            // An unstable periodic orbit, but no attractor outside it: every start tried
            // falls back inside (the return map jumps past the cycle), so steady slip only.
            res.regime = AtlasRegime::SteadySlipOnly;
            res.basin_fraction = 1.0;
            res.basin_fraction_err = 0.0;
            res.note = Some(Note::new(
                NoteKind::Finding,
                format!(
                    "an unstable cycle at {} but starts outside it fall back inside ({}): no stick-slip attractor",
                    ps.amplitude_words(res.cycle.map_or(f64::NAN, |c| c.r_section)),
                    ps.time_words(*t, 1)
                ),
            ));
        }
        (_, Some(Err(StickFail::FellInside { t }))) => {
            res.note = Some(Note::conflict(format!(
                "D(r_min) > 0 but the run from outside reached the fixed point ({})",
                ps.time_words(*t, 1)
            )));
        }
        (_, Some(Err(StickFail::Failed(e)))) => {
            res.note = Some(Note::new(NoteKind::Failure, e.clone()))
        }
        (_, None) => res.note = Some(Note::new(NoteKind::Failure, "no stick-slip run")),
    }
}

/// The horizon of the spread's runs at a point outside the checked region (nondimensional):
/// shorter than [`crate::fates::HORIZON`], as an atlas runs many points. At the brake of
/// crates/core/MODEL.md section 13 the start at rest is identified on its lasting
/// oscillation by t = 400-460 near the critical damping, and settles by t = 600.
pub const LANDSCAPE_HORIZON: f64 = 3000.0;

/// Outside the region where the section's picture was checked (crates/core/MODEL.md
/// section 11), the point's landscape from runs: the operating point and the spread of
/// [`crate::fates::Spread`] run to [`LANDSCAPE_HORIZON`] (stopped once one lasts). A start
/// that lasts where the section saw no squeal (or no verdict) makes the point squeal (the
/// operating point's own run says whether it is the one), with the oscillation's figures in
/// the note; every start settling where the section's stick-slip run lasted is a conflict
/// (undecided). Where a start lasts, the basin fraction is withdrawn (NaN), also when the
/// runs agree with the section's label: it is the area inside the section's unstable cycle,
/// which is what is not checked here; the note says runs decided.
fn runs_landscape(
    setup: Setup,
    ps: &PointSettings,
    res: &mut PointResult,
    (warning, w): (&str, &mut Work),
) -> Result<(), ScanError> {
    use crate::fates::{Fate, Spread, fates};
    let mut starts = vec![ps.operating];
    starts.extend(Spread::of(&setup.params).starts);
    let out = fates(setup, &starts, LANDSCAPE_HORIZON, true)?;
    for (_, st) in &out {
        w.stats.merge(st);
    }
    let lasting = out.iter().enumerate().find(|(_, (f, _))| f.lasts());
    let all_settle = out.iter().all(|(f, _)| f.quiet());
    let operating_lasts = out[0].0.lasts();
    let section_squeals = matches!(
        res.regime,
        AtlasRegime::BistableQuiet | AtlasRegime::BistableSqueals | AtlasRegime::FixedPointUnstable
    );
    let why = format!("the section's picture is not checked here ({warning})");
    match lasting {
        Some((i, (Fate::Lasts { t, lasting: l, .. }, _)))
            if !section_squeals || operating_lasts =>
        {
            let figures = l.map_or("its figures not measured".into(), |l| ps.lasting_words(&l));
            let who = if i == 0 {
                "the operating point".to_string()
            } else {
                format!("the start ({:.4}, {:.4})", starts[i].x, starts[i].v)
            };
            res.regime = if operating_lasts {
                AtlasRegime::BistableSqueals
            } else {
                AtlasRegime::BistableQuiet
            };
            res.basin_fraction = f64::NAN;
            res.basin_fraction_err = f64::NAN;
            res.note = Some(Note::new(
                NoteKind::Finding,
                format!(
                    "squeal found by runs: {who} is on a lasting oscillation from {} ({figures}); runs decide here because {why}",
                    ps.time_words(*t, 1)
                ),
            ));
        }
        _ if all_settle && section_squeals => {
            res.regime = AtlasRegime::Undecided;
            res.note = Some(Note::conflict(format!(
                "conflict: the section method finds stick-slip, but the operating point and all {} starts of the spread reach the fixed point by {} ({why})",
                starts.len() - 1,
                ps.time_words(LANDSCAPE_HORIZON, 0)
            )));
        }
        _ => {}
    }
    Ok(())
}

/// Checks a "bistable, operating point squeals" label by running the operating point
/// itself to settlement ([`squeal_core::Classifier`], the rules of `squeal classify`).
///
/// The label rests on two section-method findings: the operating point lies outside the
/// unstable cycle, and a run started outside the cycle stayed there for the attractor's
/// `transient + window` revolutions. Just above the fold of cycles that run can sit for
/// that long on the ghost of the vanished stable cycle (a bottleneck where `D` is barely
/// negative) and still end in steady slip: at nu = 0.0299, lambda = 0.803
/// (`scans/atlas-lambda-nu.toml`) rest and big starts all reach the fixed point by
/// t = 450 at dt = 0.005 and 0.0025 while the section method saw a band at r = 0.7968.
/// When the run from the operating point does not end in stick-slip, the evidence
/// conflicts: the point is undecided, with a note naming both findings (never a guess).
fn confirm_operating_point(
    setup: Setup,
    ps: &PointSettings,
    res: &mut PointResult,
    w: &mut Work,
) -> Result<(), ScanError> {
    let st = setup.stepper()?;
    // Band rules as every other path sets them (crate::scanner::classifier_for).
    let fp = setup.params.fixed_point();
    let far = 1.2 * (ps.operating.x - fp.x).hypot(ps.operating.v - fp.v);
    let o = crate::scanner::classifier_for(&st, squeal_core::Classifier::default(), far)
        .classify(&st, ps.operating);
    w.stats.merge(&o.stats);
    if o.regime == squeal_core::Regime::Undecided {
        // No verdict within the classifier's t_max (seen at low damping, where the run from
        // near the fixed point grows slowly): no evidence against the label, but it is not
        // confirmed either, and the note says so.
        res.note = Some(Note::new(
            NoteKind::Unconfirmed,
            format!(
                "unconfirmed: the operating point's own run did not settle by {} ({})",
                ps.time_words(o.t_decision, 0),
                o.reason.name()
            ),
        ));
    } else if o.regime != squeal_core::Regime::StickSlip {
        let band = res.stick_slip.map_or(f64::NAN, |s| s.r_band[1]);
        res.note = Some(Note::conflict(format!(
            "conflict: the section method says the operating point squeals (outside the unstable cycle at {}, stick-slip band at {} for {} revolutions) but its own run ends {} ({} at {})",
            ps.amplitude_words(res.cycle.map_or(f64::NAN, |c| c.r_section)),
            ps.amplitude_words(band),
            ps.transient + ps.window,
            o.regime.name(),
            o.reason.name(),
            ps.time_words(o.t_decision, 1)
        )));
        res.regime = AtlasRegime::Undecided;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use squeal_core::{FrictionLaw, SolverConfig};

    fn point(law: FrictionLaw, nu: f64, warm: Option<f64>) -> PointResult {
        compute_point(
            Setup::new(Params::paper(law, nu), 0.01, SolverConfig::default()),
            &PointSettings::default(),
            warm,
        )
        .unwrap()
    }

    #[test]
    fn paper_points_reproduce_ulc() {
        for (law, nu, enclosed) in [
            // Paper Figs 9 and 10: the cycle does not enclose rest at 1e-3, does at 1e-2.
            (FrictionLaw::McMillan, 1e-3, false),
            (FrictionLaw::McMillan, 1e-2, true),
            (FrictionLaw::McMillanNonHysteretic, 1e-3, false),
        ] {
            let p = point(law, nu, None);
            let rep = crate::ulc::locate(
                Setup::new(Params::paper(law, nu), 0.01, SolverConfig::default()),
                &CycleSettings::default(),
            )
            .unwrap();
            let c = p.cycle.unwrap();
            // Both bisect the same D to relative widths 1e-9 and 1e-10.
            assert!(
                (c.r_section - rep.r_section).abs() < 2e-9 * rep.r_section,
                "{law} {nu}: {} vs {}",
                c.r_section,
                rep.r_section
            );
            assert!((c.period - rep.period).abs() < 1e-6);
            assert!((c.area - rep.area).abs() < 1e-6 * rep.area);
            assert_eq!(c.encloses_operating, enclosed);
            let want = if enclosed {
                AtlasRegime::BistableQuiet
            } else {
                AtlasRegime::BistableSqueals
            };
            assert_eq!(p.regime, want, "{law} {nu}");
            // The smallest disturbance is no larger than the distance along +x.
            assert!(c.min_distance <= c.distance_plus_x + 1e-12);
            assert!(c.min_kick <= c.r_section);
            let s = p.stick_slip.unwrap();
            // Stick-slip lies outside the unstable cycle.
            assert!(s.r_band[0] > c.r_section);
            assert!(p.basin_fraction > 0.0 && p.basin_fraction < 1.0);
        }
    }

    #[test]
    fn pitch_is_flattened_as_in_the_paper() {
        // Paper Section 5: stick-slip angular frequency about 0.96 at nu = 1e-3 (Fig 9).
        let s = point(FrictionLaw::McMillan, 1e-3, None).stick_slip.unwrap();
        assert!((s.omega_mean - 0.96).abs() < 0.02, "{}", s.omega_mean);
        // The hysteretic law spends time on its quasi-static branch on the loop.
        assert!(s.quasi_static_share > 0.0);
    }

    #[test]
    fn warm_and_cold_starts_agree() {
        for law in [FrictionLaw::McMillan, FrictionLaw::McMillanNonHysteretic] {
            for nu in [2e-3, 1e-2, 1.8e-2] {
                let cold = point(law, nu, None);
                let rc = cold.cycle.unwrap().r_section;
                // A neighbour 10% away.
                let warm = point(law, nu, Some(1.1 * rc));
                assert!(warm.warm_started, "{law} {nu}");
                assert!(!cold.warm_started);
                let rw = warm.cycle.unwrap().r_section;
                // Both brackets end narrower than rtol = 1e-9 relative.
                assert!((rw - rc).abs() <= 2e-9 * rc, "{law} {nu}: {rw} vs {rc}");
                assert!(warm.returns < cold.returns);
            }
        }
    }

    #[test]
    fn regimes_at_the_extremes() {
        // Far above the fold (MODEL.md: between 0.019 and 0.031): no start squeals.
        let p = point(FrictionLaw::McMillan, 0.08, None);
        assert_eq!(p.regime, AtlasRegime::SteadySlipOnly);
        assert_eq!(p.basin_fraction, 1.0);
        // nu = 0: the fixed point repels (MODEL.md), every start squeals.
        let p = point(FrictionLaw::McMillan, 0.0, None);
        assert_eq!(p.regime, AtlasRegime::FixedPointUnstable);
        assert!(p.stick_slip.is_some());
    }

    /// The scales of the brake of scans/brake.toml (2 kg, 50 kN/m, mu_k 0.35).
    fn brake_scales() -> squeal_core::Scales {
        squeal_core::Physical {
            m: 2.0,
            k: 5.0e4,
            c: 10.0,
            v_belt: 0.05,
            friction: squeal_core::FrictionSi::Kinetic {
                mu_k: 0.35,
                surface: Some(squeal_core::SurfaceSi {
                    mu_s: 0.45,
                    tau: 1e-3,
                }),
            },
            load: squeal_core::Load::Weight(9.80665),
        }
        .scales()
    }

    #[test]
    fn conflicting_evidence_is_undecided() {
        // `scans/atlas-lambda-nu.toml` at nu index 52, lambda index 12, warm-started from
        // the previous point of its line (lambda index 11, crossing 0.52686, as stored by
        // that run at dt = 0.005): the section method found an unstable cycle and a
        // stick-slip band outside it for 80 revolutions, but `squeal trajectory --nu
        // 0.029935772947 --lambda 0.802653930857 --x0 0 --v0 0 --t-end 4000` reaches the
        // fixed point at dt = 0.005 (t = 334) and 0.0025 (t = 451), as do starts at
        // (-4, 0), (1, 2), (-2, -3), (4, 3): evidence that conflicts.
        let p = Params {
            nu: 0.029_935_772_947_204_92,
            lambda: 0.802_653_930_857_430_8,
            ..Params::paper(FrictionLaw::McMillan, 0.0)
        };
        let r = compute_point(
            Setup::new(p, 0.005, SolverConfig::default()),
            &PointSettings::default(),
            Some(0.526_863_078_829_873_4),
        )
        .unwrap();
        assert_eq!(r.regime, AtlasRegime::Undecided, "{r:?}");
        let note = r.note.clone().unwrap();
        assert_eq!(note.kind, NoteKind::Conflict, "{note}");
        let note = note.text;
        assert!(note.contains("steady_slip"), "{note}");
        assert!(!note.contains("m/s"), "{note}");
        // The same point in a physical plan (notes of physical files must not give r and t
        // nondimensionally): the note states the cycle's crossing in m/s and the time in s,
        // each the nondimensional value times the system's scale.
        let units = brake_scales();
        let ps = PointSettings {
            units: Some(units),
            ..PointSettings::default()
        };
        let si = compute_point(
            Setup::new(p, 0.005, SolverConfig::default()),
            &ps,
            Some(0.526_863_078_829_873_4),
        )
        .unwrap();
        let si_note = si.note.unwrap().text;
        let r_cycle = r.cycle.unwrap().r_section;
        let crossing = format!(
            "x' = {:.3e} m/s (r = {r_cycle:.6})",
            r_cycle * units.velocity
        );
        assert!(si_note.contains(&crossing), "{si_note} lacks {crossing}");
        let t = note.rsplit("t = ").next().unwrap().trim_end_matches(')');
        let t: f64 = t.parse().unwrap();
        let t_si = format!("t = {:.4} s", t * units.time);
        // The nondimensional note rounds t to 0.1: compare the SI time to that precision.
        let t_si_got: f64 = si_note
            .rsplit("t = ")
            .next()
            .unwrap()
            .trim_end_matches(" s)")
            .parse()
            .unwrap();
        assert!(
            (t_si_got - t * units.time).abs() <= 0.05 * units.time,
            "{si_note} vs {t_si}"
        );
        // Where the evidence agrees (paper Fig 9, nu = 1e-3: rest squeals), the label stands.
        let r = compute_point(
            Setup::new(
                Params::paper(FrictionLaw::McMillan, 1e-3),
                0.005,
                SolverConfig::default(),
            ),
            &PointSettings::default(),
            None,
        )
        .unwrap();
        assert_eq!(r.regime, AtlasRegime::BistableSqueals);
        assert!(r.note.is_none());
    }
}
