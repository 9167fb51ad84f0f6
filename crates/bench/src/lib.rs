//! No code: the crate holds squeal's Criterion benchmarks (`benches/step.rs`, one step of
//! each law; `benches/scan.rs`, a small scan through the library driver). Run them with
//! `cargo bench -p squeal-bench --bench step` (or `--bench scan`); BENCHMARKS.md records
//! their results with machine and date.
