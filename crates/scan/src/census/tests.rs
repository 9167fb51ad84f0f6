use super::*;
use crate::MapContext;

/// The plan of a spec's text (the fixtures below).
fn plan(toml: &str) -> Plan {
    Plan::from_toml(toml, "t.toml").unwrap()
}

/// The README's clamped disc brake at c = 300 N s/m: nu = c / 800 = 0.375, lambda = 0.21053,
/// tau = 0.65789, phi = 0.91353, on a 3 x 3 grid over x0 in [-1, 2], x'0 in [-0.5, 0.5].
fn brake() -> Plan {
    plan(
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
    )
}

/// At the brake's c = 300, `classify` and `scan` on 48d225a labelled these
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
        let truth = plain_run((&ctx.stepper, None, Shortcuts::NONE), (&plain, None), ic).own;
        assert_eq!(truth.regime, Regime::SlipOscillation, "{ic:?}: {truth:?}");
        let label = ctx.classify(ic);
        assert_eq!(label.regime, truth.regime, "{ic:?}: {label:?}");
    }
    assert!(
        ctx.start_rule.is_none() && ctx.classifier.trap.is_none(),
        "{ctx:?}"
    );
}

/// Fig. 9's plan (the main job's map, its grid's box) on a 4 x 4 grid.
fn fig9() -> Plan {
    plan(
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
    )
}

/// Fig. 9: the closed turns decide every start but the outermost inside the cycle, and
/// what they decide agrees with each start's own run with no rule to t_max. The four
/// starts on the ring make an outward turn at their first crossing (t < 7); the state at
/// rest and the box's eight lie outside those turns, so no run is made for them; their
/// own runs end on the stick-slip band's certificate instead (t = 129-370). The
/// outermost start inside makes an inward turn with one root everywhere inside it and
/// its run enters the region at t = 4059; the start at half the cycle, inside that turn,
/// is decided by that run (its own enters the region at t = 1884). The other start at 0.9
/// times the cycle lies on the turn's level, not inside it by the margin; it is followed
/// until a crossing of the section falls inside (t = 66, ten revolutions) and is then
/// decided by the same run (its own enters the region at t = 4059). Before closed turns
/// every start ran: 13 certified on the band by t = 130-2270, 3 in the region by
/// t = 1880-4060 (MODEL.md section 12).
#[test]
fn fig9_census_closed_turns_agree_with_each_start_run() {
    let plan = fig9();
    let ctx = MapContext::prepare(&plan, 0).unwrap();
    let census = ctx.census.clone().expect("McMillan's law takes a census");
    assert_eq!(census.runs, MAX_STARTS, "{census:?}");
    assert_eq!(
        (census.kept_outside, census.kept_inside, census.at_horizon),
        (13, 2, 0),
        "{census:?}"
    );
    assert!(
        census.ends[14] > 0.0 && census.ends[14] < 100.0,
        "{census:?}"
    );
    assert!(census.withdrawn.is_empty(), "{census:?}");
    assert!(census.ends[9..13].iter().all(|&t| t < 7.0), "{census:?}");
    assert!(census.ends[..9].iter().all(|&t| t == 0.0), "{census:?}");
    let plain = Classifier {
        trap: None,
        band_rules: false,
        ..plan.map.classifier
    };
    let fp = ctx.params.fixed_point();
    let reach = crate::scanner::cycle_settings(&plan, &ctx.params).r_max / 1.2;
    let curve = ctx
        .start_rule
        .as_ref()
        .map(|r| CurveLocator::new(r.curve().clone()));
    let half = ctx.stepper.setup().half_dt();
    let half = half.stepper().unwrap();
    for (i, (ic, side, _)) in starts(&plan, fp, reach, curve.as_ref())
        .into_iter()
        .enumerate()
    {
        let certs = (&ctx.stepper, Some(&half), ctx.certificates);
        let own = plain_run(certs, (&plain, None), ic).own;
        match side {
            Side::Outside => assert_eq!(own.regime, Regime::StickSlip, "{i}: {own:?}"),
            _ => assert_eq!(own.reason, Reason::EnteredRegion, "{i}: {own:?}"),
        }
    }
}

/// The closed turn's own numbers at Fig. 9: from just outside the cycle's crossing
/// `r_u = 0.4028` (the located cycle) the turn grows, from just inside it shrinks, each by
/// about `(P'(r_u) - 1) (r - r_u)` with `P'(r_u) = 1.0064` (MODEL.md section 12). At
/// `lambda = 0.5`, `nu = 0.0223`, whose return map jumps past its cycle (MODEL.md
/// section 6), the one-root bound fails on the small cycle's turns: no closed turn.
#[test]
fn closed_turns_grow_outside_the_cycle_shrink_inside_and_need_one_root() {
    let plan = fig9();
    let ctx = MapContext::prepare(&plan, 0).unwrap();
    let half = ctx.stepper.setup().half_dt();
    let half = half.stepper().unwrap();
    let near = (1e-3, ctx.certificates.region.as_ref());
    let r_u = match &ctx.cycle {
        Some(Ok(c)) => c.r_section,
        other => panic!("no located cycle: {other:?}"),
    };
    for (r, kept) in [(1.1 * r_u, Kept::Outside), (0.9 * r_u, Kept::Inside)] {
        let turn = ClosedTurn::certify((&ctx.stepper, &half), r, near).expect("a turn");
        assert_eq!(turn.kept(), kept, "{turn:?}");
        let slope = (turn.r1 - r_u) / (turn.r0 - r_u);
        assert!((slope - 1.0064).abs() < 1.5e-3, "{slope} {turn:?}");
        assert!(turn.one_root_inside(&ctx.params));
    }
    let mut slow = ctx.params;
    slow.lambda = 0.5;
    slow.nu = 0.0223;
    let st = Stepper::new(slow, plan.dt, plan.solver).unwrap();
    let half = st.setup().half_dt();
    let half = half.stepper().unwrap();
    for r in [0.2, 0.26, 0.5] {
        assert!(
            ClosedTurn::certify((&st, &half), r, (1e-3, None)).is_none(),
            "{r}"
        );
    }
}
