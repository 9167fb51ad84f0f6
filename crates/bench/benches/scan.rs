//! A small scan through the library driver: `cargo bench -p squeal-bench --bench scan`.
//! (Figures go in BENCHMARKS.md with the command and machine, never in tests.)

use std::sync::atomic::AtomicBool;

use criterion::{Criterion, criterion_group, criterion_main};
use squeal_scan::{MemorySink, NoObserver, Plan, drive};

fn small_scan(c: &mut Criterion) {
    let plan = Plan::from_toml(
        r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 16 }
v0 = { min = -4.0, max = 4.0, count = 16 }
[cycle]
locate = false
[output]
path = "bench.h5"
"#,
        "bench.toml",
    )
    .expect("valid spec");
    let mut g = c.benchmark_group("scan");
    g.sample_size(10);
    g.bench_function("fig9 16x16, early stop on the cycle", |b| {
        b.iter(|| {
            let mut sink = MemorySink::default();
            drive(&plan, None, &mut sink, &NoObserver, &AtomicBool::new(false)).expect("scan runs");
            sink
        })
    });
    g.finish();
}

criterion_group!(benches, small_scan);
criterion_main!(benches);
