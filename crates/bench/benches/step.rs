//! Cost of one step, for each friction law, solver and scheme, in two situations:
//!
//! * `step/decay`: the common case of a scan, a decaying oscillation near the fixed point
//!   (nu = 1e-3 from (1.2, 0), inside the unstable cycle, after 100 time units);
//! * `step/stick_slip`: the settled stick-slip cycle (nu = 1e-3 from rest, after 1000 time
//!   units), where the hysteretic law sits on its quasi-static branch and the paper's
//!   iteration often fails to converge.
//!
//! Each benchmark steps from every sample of one revolution (between two crossings of the
//! section `x = 1, x' > 0`), recorded with the robust solver on the hysteretic law (the
//! non-hysteretic law on its own runs), so the time per element is the mean time of one step
//! along that revolution. Coulomb's solve is closed form whatever the solver setting. Before
//! timing, each case prints its law evaluations per step (from the solver's counters).
//!
//! `stribeck/*`: the event stepper of the law with true stick (bSTAB's friction case) along
//! one revolution of its stick-slip cycle (`v_d = 1.0`, after 200 time units from rest: each
//! revolution sticks, breaks away and slips) and of a slip-only decay (`v_d = 2.0`, from 0.5
//! right of the fixed point after 10 time units), robust solver, first-order hold.
//!
//! `atan/*`: the latency of the arctangent of McMillan's laws (a chain of dependent calls).
//!
//! `cargo bench -p squeal-bench --bench step -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use squeal_core::classify::crossing;
use squeal_core::{
    FrictionLaw, Params, Run, Sample, Scheme, SolverConfig, SolverKind, SolverStats, State, Stepper,
};

const NU: f64 = 1e-3;
const DT: f64 = squeal_core::defaults::DT;

fn stepper(law: FrictionLaw, kind: SolverKind, scheme: Scheme) -> Stepper {
    let cfg = SolverConfig {
        kind,
        scheme,
        ..Default::default()
    };
    Stepper::new(Params::paper(law, NU), DT, cfg).expect("valid parameters")
}

/// The samples of one revolution after `settle` time units from `ic` (robust solver).
fn revolution(law: FrictionLaw, ic: State, settle: f64) -> Vec<Sample> {
    let st = stepper(law, SolverKind::Robust, Scheme::default());
    revolution_of(&st, ic, settle)
}

/// The samples of one revolution of `st`'s run from `ic` after `settle` time units (between
/// two crossings of the section through its fixed point).
fn revolution_of(st: &Stepper, ic: State, settle: f64) -> Vec<Sample> {
    let x_star = st.params().fixed_point().x;
    let mut run = Run::new(st, ic);
    run.by_ref()
        .take((settle / DT).round() as usize)
        .for_each(drop);
    let mut out = Vec::new();
    let mut crossings = 0;
    for step in run {
        if crossing(x_star, &step.prev, &step.next).is_some() {
            crossings += 1;
        }
        match crossings {
            1 => out.push(step.next),
            2 => break,
            _ => {}
        }
    }
    out
}

fn bench_case(c: &mut Criterion, name: &str, ic: State, settle: f64) {
    let hysteretic = revolution(FrictionLaw::McMillan, ic, settle);
    let nonhysteretic = revolution(FrictionLaw::McMillanNonHysteretic, ic, settle);
    let mut group = c.benchmark_group(format!("step/{name}"));
    for law in FrictionLaw::MCMILLAN {
        let samples = match law {
            FrictionLaw::McMillanNonHysteretic => &nonhysteretic,
            _ => &hysteretic,
        };
        group.throughput(Throughput::Elements(samples.len() as u64));
        for kind in [SolverKind::Robust, SolverKind::Paper] {
            for scheme in [Scheme::Foh, Scheme::Zoh] {
                let st = stepper(law, kind, scheme);
                let mut stats = SolverStats::default();
                for s in samples {
                    st.step(s, &mut stats);
                }
                eprintln!(
                    "step/{name}/{law}/{kind}-{scheme}: {:.2} law evaluations per step, {} fallbacks in {} steps",
                    stats.evaluations as f64 / samples.len() as f64,
                    stats.fallbacks,
                    samples.len()
                );
                let id = BenchmarkId::new(law.name(), format!("{kind}-{scheme}"));
                group.bench_function(id, |b| {
                    let mut stats = SolverStats::default();
                    b.iter(|| {
                        for s in samples {
                            black_box(st.step(black_box(s), &mut stats));
                        }
                    });
                });
            }
        }
    }
    group.finish();
}

/// The event stepper (`Stepper::advance`) along one revolution of bSTAB's friction case.
fn bench_stribeck(c: &mut Criterion) {
    let mut group = c.benchmark_group("stribeck");
    // (name, belt speed, start relative to the fixed point or absolute, settling time)
    for (name, v_d, from_fp, settle) in [
        ("stick_slip", 1.0, None, 200.0),
        ("decay", 2.0, Some(0.5), 10.0),
    ] {
        let p = squeal_core::Params::stribeck(0.05, v_d, squeal_core::Stribeck::default());
        let st = Stepper::new(p, DT, SolverConfig::default()).expect("valid parameters");
        let fp = p.fixed_point();
        let x = from_fp.map_or(0.0, |dx| fp.x + dx);
        let samples = revolution_of(&st, State { x, v: 0.0 }, settle);
        let mut stats = SolverStats::default();
        for s in &samples {
            st.advance(s, &mut stats);
        }
        eprintln!(
            "stribeck/{name}: {:.2} law evaluations per step, {} stick onsets, {} breakaways in {} steps",
            stats.evaluations as f64 / samples.len() as f64,
            stats.stick_onsets,
            stats.breakaways,
            samples.len()
        );
        group.throughput(Throughput::Elements(samples.len() as u64));
        group.bench_function(name, |b| {
            let mut stats = SolverStats::default();
            b.iter(|| {
                for s in &samples {
                    black_box(st.advance(black_box(s), &mut stats));
                }
            });
        });
    }
    group.finish();
}

/// Latency of the arctangent in McMillan's laws: a chain of 1000 calls, each argument from the
/// last result (as the Newton iterates of a solve), the C library's `atan` against
/// [`squeal_core::atan::atan_ratio`].
fn bench_atan(c: &mut Criterion) {
    let mut group = c.benchmark_group("atan");
    group.throughput(Throughput::Elements(1000));
    group.bench_function("library", |b| {
        b.iter(|| {
            let mut y = black_box(0.3f64);
            for _ in 0..1000 {
                y = (y / 0.7).atan() * 1.5 - 0.2;
            }
            y
        });
    });
    group.bench_function("atan_ratio", |b| {
        b.iter(|| {
            let mut y = black_box(0.3f64);
            for _ in 0..1000 {
                y = squeal_core::atan::atan_ratio(y, 0.7) * 1.5 - 0.2;
            }
            y
        });
    });
    group.finish();
}

/// The README's clamped disc brake (crates/core/MODEL.md section 13: lambda = 120 / 570,
/// tau = 0.25 / 0.38, phi = arcsin(0.38 / 0.48), nu = 140 / 800, c = 140 N s/m) along one
/// turn of its lasting oscillation from rest (after 1600 time units: identified at t = 1528),
/// which overtakes the belt and never crosses the section `x = 1`: turns are taken from one
/// maximum of `x` to the next. Beside it Table 1's stick-slip cycle with the same solver and
/// scheme (`step/stick_slip/mcmillan/robust-foh`): the ratio is the cost of a step here
/// against elsewhere, in one run.
fn bench_brake(c: &mut Criterion) {
    let p = Params {
        lambda: 120.0 / 570.0,
        law: squeal_core::Friction::McMillan(squeal_core::Surface {
            tau: 0.25 / 0.38,
            phi: (0.38f64 / 0.48).asin(),
        }),
        ..Params::paper(FrictionLaw::McMillan, 140.0 / 800.0)
    };
    let st = Stepper::new(p, DT, SolverConfig::default()).expect("valid parameters");
    let mut run = Run::new(&st, State { x: 0.0, v: 0.0 });
    run.by_ref()
        .take((1600.0 / DT).round() as usize)
        .for_each(drop);
    // One turn: from a maximum of x (x' turns negative) to the next.
    let mut samples = Vec::new();
    let mut maxima = 0;
    for step in run {
        if step.prev.v > 0.0 && step.next.v <= 0.0 {
            maxima += 1;
        }
        match maxima {
            1 => samples.push(step.next),
            2 => break,
            _ => {}
        }
    }
    let mut stats = SolverStats::default();
    for s in &samples {
        st.step(s, &mut stats);
    }
    eprintln!(
        "step/brake: {:.2} law evaluations per step, {} fallbacks, {} with several roots in {} steps",
        stats.evaluations as f64 / samples.len() as f64,
        stats.fallbacks,
        stats.multi_root,
        samples.len()
    );
    let mut group = c.benchmark_group("step/brake");
    group.throughput(Throughput::Elements(samples.len() as u64));
    group.bench_function("mcmillan/robust-foh", |b| {
        let mut stats = SolverStats::default();
        b.iter(|| {
            for s in &samples {
                black_box(st.step(black_box(s), &mut stats));
            }
        });
    });
    group.finish();
}

fn steps(c: &mut Criterion) {
    if std::env::var_os("STEP_BENCH_BRAKE_ONLY").is_some() {
        // The brake against Table 1's cycle alone (docs/history/benchmarks.md, "A step at the
        // brake").
        bench_brake(c);
        bench_case(c, "stick_slip", State { x: 0.0, v: 0.0 }, 1000.0);
        return;
    }
    bench_brake(c);
    bench_atan(c);
    bench_case(c, "decay", State { x: 1.2, v: 0.0 }, 100.0);
    bench_case(c, "stick_slip", State { x: 0.0, v: 0.0 }, 1000.0);
    bench_stribeck(c);
}

criterion_group!(benches, steps);
criterion_main!(benches);
