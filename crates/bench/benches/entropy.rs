//! The basin entropy of a 256 x 256 map (the main job's size): `cargo bench -p squeal-bench
//! --bench entropy`. The labels are Fig. 9's picture in small: a disc of steady slip of
//! radius 0.36 about (1, 0) in the box [-3, 5] x [-4, 4], stick-slip around it.

use criterion::{Criterion, criterion_group, criterion_main};
use squeal_scan::sensitivity::{ENTROPY_BOX, Entropy};

fn entropy(c: &mut Criterion) {
    let n = 256;
    let at = |k: usize, lo: f64, hi: f64| lo + (hi - lo) * k as f64 / (n - 1) as f64;
    let labels: Vec<u8> = (0..n * n)
        .map(|k| {
            let (x, v) = (at(k % n, -3.0, 5.0), at(k / n, -4.0, 4.0));
            if (x - 1.0).hypot(v) < 0.36 { 1 } else { 2 }
        })
        .collect();
    c.bench_function("basin entropy of 256 x 256 labels, boxes of 5", |b| {
        b.iter(|| Entropy::of(std::hint::black_box(&labels), n, ENTROPY_BOX))
    });
}

criterion_group!(benches, entropy);
criterion_main!(benches);
