//! The turn map's certificates ([`squeal_core::orbit`]) against the runs they speak for:
//! a band certificate holds a run's maxima for as long as it is run, and a run that spirals
//! onto an attracting steady slip is never certified.

use squeal_core::orbit::{self, OrbitKind, OrbitWatch};
use squeal_core::{FrictionLaw, Params, Run, SolverConfig, State, Stepper};

/// The watch over the run from `ic` (band floor: `fp_radius` 1e-3 above the fixed point),
/// trying from the first maximum on: the first certificate, when it came, and the maxima
/// of the whole run to `t_end` after it.
fn watched(p: Params, dt: f64, ic: State, t_end: f64) -> (Option<(f64, orbit::Orbit)>, Vec<f64>) {
    let st = Stepper::new(p, dt, SolverConfig::default()).unwrap();
    let half = Stepper::new(p, dt / 2.0, SolverConfig::default()).unwrap();
    let mut watch = OrbitWatch::new(&half, orbit::band_floor(&p, 1e-3, true));
    let mut run = Run::new(&st, ic);
    let (mut found, mut after) = (None, Vec::new());
    for _ in 0..run.steps_to(t_end) {
        let step = run.step();
        if found.is_none() {
            if let Some(o) = watch.observe(&run, &step, true) {
                found = Some((run.sample().t, o));
            }
        } else if let Some((_, x, _)) = orbit::maximum(&step.prev, &step.next) {
            after.push(x);
        }
    }
    assert_eq!(run.stats().failures, 0);
    (found, after)
}

/// Fig. 9 (McMillan's hysteretic law, nu = 1e-3, Table 1): from (5, 4) the run sticks and
/// slips with maxima scattered over about 0.02 (the stick's phase against the step grid),
/// which never converge. The band certificate holds early (the time is printed with
/// --nocapture),
/// and every maximum of the same run to t = 5000 (about 740 of them) lies inside the
/// certified interval: what it claims, checked by the run itself. At dt = 0.0025 too.
#[test]
fn a_band_certificate_holds_the_maxima_of_a_sticking_run_to_the_horizon() {
    let p = Params::paper(FrictionLaw::McMillan, 1e-3);
    for dt in [0.005, 0.0025] {
        let (found, after) = watched(p, dt, State { x: 5.0, v: 4.0 }, 5000.0);
        let (t, o) = found.unwrap_or_else(|| panic!("no certificate at dt = {dt}"));
        println!("dt = {dt}: certified at t = {t}: {}", o.words());
        assert!(t < 1000.0, "certified only at t = {t} (dt = {dt})");
        assert!(
            after.len() > 500,
            "{} maxima after the certificate",
            after.len()
        );
        let (lo, hi) = (o.x_max - o.half_width, o.x_max + o.half_width);
        for x in &after {
            assert!(
                lo <= *x && *x <= hi,
                "maximum {x} outside [{lo}, {hi}] (dt = {dt})"
            );
        }
        // The scatter is the step's: a band, not a converged periodic orbit.
        assert_eq!(o.kind, OrbitKind::Band, "{o:?}");
        let spread = after.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - after.iter().cloned().fold(f64::INFINITY, f64::min);
        assert!(spread > 1e-3, "maxima scatter over {spread}");
    }
}

/// Fig. 9 from inside the unstable cycle ((1, 0.3): section amplitude 0.3 < 0.3667): the run
/// spirals onto the fixed point (multiplier 0.9937 per revolution), its maxima falling turn
/// by turn. No certificate may hold, at either step, before it is within 1e-3 of it.
#[test]
fn a_run_that_spirals_onto_steady_slip_is_never_certified() {
    let p = Params::paper(FrictionLaw::McMillan, 1e-3);
    for dt in [0.005, 0.0025] {
        let (found, _) = watched(p, dt, State { x: 1.0, v: 0.3 }, 3000.0);
        assert!(found.is_none(), "certified {found:?} at dt = {dt}");
    }
}
