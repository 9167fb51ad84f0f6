//! The landscape of each map of a law with true stick: which attractors exist at its
//! parameters, stated from two facts before any basin is mapped (MODEL.md section 8):
//!
//! * the steady-slip fixed point repels where its effective damping `2 xi + mu'(v_d)` is
//!   negative: then every start ends in stick-slip;
//! * every stick phase ends at the one breakaway state, so the stick-slip cycle exists
//!   exactly when the orbit from there sticks again ([`squeal_core::landscape::stick_slip_cycle`]);
//!   if it decays to the fixed point instead, every start ends in steady slip (assuming no
//!   slip-only cycle).
//!
//! [`of_map`] computes it with the plan's step, solver, `t_max` and `fp_radius`;
//! [`LANDSCAPE_FIELDS`] is the table of its per-map values that files, `info` and `--json`
//! follow. McMillan's laws have no landscape here (`None`): their attractors are found by
//! the cycle search instead.

use rayon::prelude::*;
use squeal_core::landscape::{self, LandscapeEvidence, StickCycle};
use squeal_core::{Landscape, Params, Stepper};

use crate::error::ScanError;
use crate::spec::Plan;

/// The landscape of parameters `params` with the plan's step and classifier settings
/// (`None` for laws without true stick).
pub fn of_params(plan: &Plan, params: Params) -> Result<Option<LandscapeEvidence>, ScanError> {
    if !params.law.family().has_landscape() {
        return Ok(None);
    }
    let stepper = Stepper::new(params, plan.dt, plan.solver)?;
    Ok(landscape::landscape_evidence(
        &stepper,
        plan.map.classifier.t_max,
        plan.map.classifier.fp_radius,
    ))
}

/// The landscape of every map of `plan` (`None` per map for laws without true stick),
/// computed before the scan's file is written: the writer only stores it. The maps are
/// computed on the rayon pool (each one's orbit from breakaway is independent of the
/// others); the first error in map order is returned.
pub fn of_plan(plan: &Plan) -> Result<Vec<Option<LandscapeEvidence>>, ScanError> {
    let each: Vec<_> = (0..plan.maps.len())
        .into_par_iter()
        .map(|m| of_map(plan, m))
        .collect();
    each.into_iter().collect()
}

/// The landscape of map `map` of `plan`.
pub fn of_map(plan: &Plan, map: usize) -> Result<Option<LandscapeEvidence>, ScanError> {
    of_params(plan, plan.maps[map])
}

/// The name and long name of the stored landscape (an enum per map; `not_applicable` for
/// laws without true stick).
pub const LANDSCAPE: (&str, &str) = (
    "landscape",
    "attractors stated before mapping: stick_slip_only (the fixed point repels), bistable, \
     steady_slip_only (the orbit from breakaway decays without sticking; assumes no \
     slip-only cycle), unknown (undecided by t_max)",
);

/// A per-map number of the landscape's evidence: name, long name, units, value.
pub type Field = (
    &'static str,
    &'static str,
    &'static str,
    fn(&LandscapeEvidence) -> f64,
);

/// The evidence stored per map beside [`LANDSCAPE`] (NaN where not applicable).
pub const LANDSCAPE_FIELDS: &[Field] = &[
    (
        "fixed_point_damping",
        "effective damping 2 xi + mu'(v_d) of the steady-slip fixed point (negative: it repels)",
        "1",
        |e| e.damping,
    ),
    (
        "stick_cycle_period",
        "period of the stick-slip cycle, breakaway to breakaway (NaN: none found)",
        "1",
        |e| match e.cycle {
            StickCycle::Exists { period, .. } => period,
            _ => f64::NAN,
        },
    ),
    (
        "stick_cycle_stuck",
        "time stuck per period of the stick-slip cycle (NaN: none found)",
        "1",
        |e| match e.cycle {
            StickCycle::Exists { stuck, .. } => stuck,
            _ => f64::NAN,
        },
    ),
];

/// The stored value of the `landscape` enum where no landscape applies.
pub const NOT_APPLICABLE: u8 = 255;

/// The flags of the stored `landscape` enum (value, name).
pub fn flags() -> Vec<(u8, &'static str)> {
    Landscape::ALL
        .iter()
        .map(|l| (*l as u8, l.name()))
        .chain([(NOT_APPLICABLE, "not_applicable")])
        .collect()
}

/// What the landscape's verdict rests on, in words (for summaries).
pub fn evidence_words(e: &LandscapeEvidence) -> String {
    let cycle = match e.cycle {
        StickCycle::Exists { period, stuck } => format!(
            "the orbit from breakaway sticks again (stick-slip cycle of period {period:.4}, \
             stuck {stuck:.4} per period)"
        ),
        StickCycle::Absent => {
            "the orbit from breakaway reaches the fixed point without sticking".into()
        }
        StickCycle::Undecided => "the orbit from breakaway decided nothing by t_max".into(),
    };
    format!(
        "fixed point damping 2 xi + mu'(v_d) = {:.6} ({}); {cycle}",
        e.damping,
        if e.damping < 0.0 {
            "repels"
        } else {
            "attracts"
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(v_d: &str) -> Plan {
        Plan::from_toml(
            &format!(
                r#"version = 1
[model]
law = "stribeck"
v_d = {v_d}
[grid]
x0 = {{ min = -2.0, max = 2.0, count = 2 }}
v0 = {{ min = 0.0, max = 2.0, count = 2 }}
[output]
path = "t.h5"
"#
            ),
            "t.toml",
        )
        .unwrap()
    }

    #[test]
    fn bstab_speeds_give_the_three_landscapes() {
        // bSTAB's case (xi = 0.05, mu_d = 0.5, mu_sd = 2, v_0 = 0.5): the fixed point repels
        // below v_d = v_0 ln(mu_d (mu_sd - 1) / (2 xi v_0)) = 0.5 ln 10 = 1.151 (closed form
        // of 2 xi + mu'(v_d) = 0); the stick-slip cycle exists up to between 1.8 and 2.0
        // (MODEL.md section 8, measured with landscape::landscape).
        let p = plan("[1.0, 1.5, 2.2]");
        let got: Vec<_> = (0..3).map(|m| of_map(&p, m).unwrap().unwrap()).collect();
        assert_eq!(got[0].landscape, Landscape::StickSlipOnly);
        assert_eq!(got[1].landscape, Landscape::Bistable);
        assert_eq!(got[2].landscape, Landscape::SteadySlipOnly);
        // The stored damping is the closed form: 2 xi - mu_d (mu_sd - 1) e^{-v_d/v_0} / v_0.
        for (e, v_d) in got.iter().zip([1.0, 1.5, 2.2f64]) {
            let want = 0.1 - (-v_d / 0.5).exp();
            assert!((e.damping - want).abs() < 1e-15, "{v_d}: {}", e.damping);
        }
        let period = LANDSCAPE_FIELDS[1].3;
        assert!(period(&got[1]) > 0.0);
        assert!(period(&got[2]).is_nan());
        assert!(evidence_words(&got[0]).contains("repels"));
    }

    #[test]
    fn mcmillan_has_none() {
        let mut p = plan("1.5");
        p.maps[0] = Params::paper(squeal_core::FrictionLaw::McMillan, 1e-3);
        assert_eq!(of_map(&p, 0).unwrap(), None);
    }

    #[test]
    fn flags_cover_every_value() {
        let f = flags();
        for l in Landscape::ALL {
            assert_eq!(Landscape::from_u8(l as u8), Some(l));
            assert!(f.contains(&(l as u8, l.name())));
        }
        assert_eq!(Landscape::from_u8(NOT_APPLICABLE), None);
    }
}
