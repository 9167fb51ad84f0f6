use super::*;

/// The pilot's boundary units are the run's own: each is the unit as the atlas computes
/// it ([`crate::atlas::driver::run_unit`], compared field by field through `Debug`, where
/// NaN equals NaN), so `squeal atlas` journals them rather than computing them again.
#[test]
fn the_pilots_boundary_units_are_the_runs() {
    let spec = "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = [1e-3, 1e-2, 5e-2]\n\
        [cycle]\nhalf_dt = false\n[attractor]\ntransient = 10\nwindow = 10\n\
        [boundaries]\nrtol = 1e-2\n[output]\npath = \"x.h5\"\n";
    let plan = AtlasPlan::from_toml(spec, "x.toml").unwrap();
    let e = atlas_pilot(&plan).unwrap();
    assert_eq!(e.units.len(), 1, "the plan has one boundary unit");
    for r in &e.units {
        let again = crate::atlas::driver::run_unit(&plan, r.unit()).unwrap();
        assert_eq!(format!("{r:?}"), format!("{again:?}"));
    }
}

/// A thread that waits (for the pool, here asleep) is not a thread that gets less of a
/// core: the same 0.3 s of spinning after 0.3 s of waiting, with the wait left out and
/// with it counted. Counted, the wait holds no CPU time and halves the share (the
/// pilot's census wait made an idle machine read "5% of a core" on fig9); left out, the
/// share is the spin's. At the floor of 0.05 (a machine too busy to spin) both read it.
#[test]
fn waiting_is_left_out_of_the_core_share() {
    let spin = |d: Duration| {
        let t = Instant::now();
        let mut x = 0u64;
        while t.elapsed() < d {
            x = std::hint::black_box(x.wrapping_add(1));
        }
    };
    // A fresh thread's clock reads 0 (unknown) until the scheduler has counted it.
    spin(Duration::from_millis(50));
    if thread_cpu_seconds().is_none() {
        return; // No CPU clock: the share is 1 by definition.
    }
    let wait = Duration::from_millis(300);
    // On a shared machine the spin's own share moves between the two measurements (a
    // parallel test starting): up to three pairs, one of which must show the halving.
    let mut seen = Vec::new();
    for _ in 0..3 {
        let left_out = CoreShare::start();
        left_out.excluding(|| std::thread::sleep(wait));
        spin(wait);
        let a = left_out.share();
        let counted = CoreShare::start();
        std::thread::sleep(wait);
        spin(wait);
        let b = counted.share();
        if a > 1.5 * b || a <= 0.1 {
            return;
        }
        seen.push((a, b));
    }
    panic!("left out against counted: {seen:?}");
}

fn cost(map: usize, prepare: f64, cell: f64, audit: f64) -> MapCost {
    MapCost {
        map,
        prepare,
        cell,
        cells: 10,
        audit,
    }
}

#[test]
fn the_estimate_scales_with_cells_threads_and_audits() {
    let e = Estimate {
        prepared: Shelf::default(),
        cells: 10,
        pilot_seconds: 0.1,
        per_map: vec![cost(0, 0.5, 1e-3, 0.0)],
        audited_per_map: 0,
        cells_per_map: 2000,
        core_share: 1.0,
    };
    // 4 maps prepared one at a time (0.5 s each), 4 x 2000 cells at 1 ms over 2 threads.
    assert!((e.seconds(4, |_| 2000, 2) - (2.0 + 4.0)).abs() < 1e-12);
    // 10 of a map's 2000 cells audited at 0.1 s each: 1 s per map over 2 threads; half a
    // map's cells pending: half its audits.
    let e = Estimate {
        prepared: Shelf::default(),
        audited_per_map: 10,
        per_map: vec![cost(0, 0.5, 1e-3, 0.1)],
        ..e
    };
    assert!((e.seconds(1, |_| 2000, 2) - (0.5 + 1.0 + 0.5)).abs() < 1e-12);
    assert!((e.seconds(1, |_| 1000, 2) - (0.5 + 0.5 + 0.25)).abs() < 1e-12);
}

/// A scan estimated at 66 s took 323 s at load 8. The pilot's thread got its
/// share of a core there; the estimate at that load is the free-core time over the
/// share. A machine that gives the pilot most of a core is not called busy.
#[test]
fn a_busy_machine_is_named_with_the_time_at_its_load() {
    // One core in five (load about 8 on 2 cores, less the pilot's own): 66 s is 330 s.
    assert_eq!(at_load(66.0, 0.2), Some(330.0));
    assert_eq!(at_load(66.0, 0.9), None);
    assert_eq!(at_load(66.0, 1.0), None);
    assert_eq!(at_load(66.0, f64::NAN), None);
    // Just under the threshold.
    assert!(at_load(10.0, BUSY_SHARE - 1e-9).is_some());
}

#[test]
fn each_map_costs_as_its_nearest_prepared_map() {
    // Two prepared maps of a 9-map sweep, the last 20 times dearer per cell (as above a
    // fold of cycles): maps 0-3 cost as map 0, maps 5-8 as map 8 (map 4 is as near to
    // both; either is a measured cost).
    let e = Estimate {
        prepared: Shelf::default(),
        cells: 20,
        pilot_seconds: 0.1,
        per_map: vec![cost(0, 0.0, 1e-3, 0.0), cost(8, 0.0, 2e-2, 0.0)],
        audited_per_map: 0,
        cells_per_map: 100,
        core_share: 1.0,
    };
    assert_eq!(e.cost_of(3).map, 0);
    assert_eq!(e.cost_of(5).map, 8);
    let only = |k: usize| e.seconds(9, move |m| if m == k { 100 } else { 0 }, 1);
    assert!((only(2) - 0.1).abs() < 1e-12);
    assert!((only(7) - 2.0).abs() < 1e-12);
}

/// McMillan's law over Fig. 9's box at 8 x 8 cells, `nu` as written in the spec.
fn fig9_box(nu: &str) -> Plan {
    let text = format!(
        r#"version = 1
[model]
law = "mcmillan"
nu = {nu}
[grid]
x0 = {{ min = -3.0, max = 5.0, count = 8 }}
v0 = {{ min = -4.0, max = 4.0, count = 8 }}
[output]
path = "t.h5"
"#
    );
    Plan::from_toml(&text, "t.toml").unwrap()
}

#[test]
fn the_pilot_samples_every_prepared_map() {
    let plan = fig9_box("{ from = 1e-3, to = 2e-2, count = 12 }");
    let e = pilot(&plan).unwrap();
    // At most PILOT_MAPS maps at first (fewer when preparing them outlasts the budget),
    // then more where the cost per cell jumps: never more than twice that, nor more than
    // the plan has, each once.
    assert!((1..=(2 * PILOT_MAPS).min(12)).contains(&e.maps()), "{e:?}");
    assert!(e.per_map.windows(2).all(|w| w[0].map < w[1].map), "{e:?}");
    assert!(e.cells >= e.maps(), "{e:?}");
    for c in &e.per_map {
        assert!(c.cells >= 1 && c.cell > 0.0 && c.prepare > 0.0, "{c:?}");
    }
    // The share of a core the pilot got is measured (1 where it cannot be).
    assert!(e.core_share > 0.0 && e.core_share <= 1.0, "{e:?}");
    // The picked maps are spread over the sweep with both ends.
    assert_eq!(e.per_map[0].map, 0);
}

/// The scan takes the maps its pilot prepared (`driver::drive_prepared`), so its estimate
/// leaves their preparation out: at Fig. 9 (one map) the pilot's preparation (its census,
/// about 1.6 s of CPU) was counted again on top of the cells (the main job read "roughly
/// 2 s (1.6 s)" for a run of 1.0 s).
#[test]
fn a_map_the_pilot_prepared_is_not_counted_twice() {
    let plan = fig9_box("1e-3");
    let e = pilot(&plan).unwrap();
    let cells = |_| 64;
    let (all, reusing) = (e.seconds(1, cells, 2), e.seconds_reusing(1, cells, 2));
    let prepare = e.cost_of(0).prepare;
    assert!(prepare > 0.0, "{e:?}");
    assert!(
        (all - reusing - prepare).abs() <= 1e-12 * all,
        "{all} {reusing} {prepare}"
    );
    // Once the run has taken them, they are to be prepared again.
    let _ = e.prepared.take();
    assert_eq!(e.seconds_reusing(1, cells, 2), all);
}
