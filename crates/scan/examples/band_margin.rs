//! The band's margin on a plain uniform grid, independent of `squeal_scan::band`'s
//! refinement: for each damping (Table 1's lambda, tau, phi, hysteretic law, dt 0.005), `n`
//! returns uniform on `(r_u, 3]`, the band's top `b` (largest return) and bottom `a` (the
//! smallest return of the starts in `[s, b]`, `s` the first start with `P(r) <= r`), and
//! `a - r_u`: positive where the band maps into itself, negative where it leaks. The
//! numbers quoted in `crates/scan/src/band.rs` and `crates/scan/tests/scanning/edge.rs` come from
//!
//!     cargo run --release -p squeal-scan --example band_margin -- 400 0.0236 0.024 0.0242 0.0245 0.025

use squeal_core::{FrictionLaw, Params, SolverConfig, Stepper};
use squeal_scan::section::{ReturnMap, SectionCycles, Work, search_section};
use squeal_scan::ulc::CycleSettings;

fn main() {
    let a: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().expect("numbers: n, then dampings"))
        .collect();
    let n = a[0] as usize;
    for &nu in &a[1..] {
        let st = Stepper::new(
            Params::paper(FrictionLaw::McMillan, nu),
            0.005,
            SolverConfig::default(),
        )
        .expect("a valid model");
        let m = ReturnMap::new(&st, 200.0);
        let found = search_section(&m, &CycleSettings::default(), &mut Work::default());
        let SectionCycles::Unstable { r: ru, .. } = found else {
            println!("nu {nu}: no unstable cycle");
            continue;
        };
        let mut w = Work::default();
        let rs: Vec<f64> = (1..=n)
            .map(|i| ru + (3.0 - ru) * i as f64 / n as f64)
            .collect();
        let ps: Vec<f64> = rs.iter().map(|&r| r + m.d(r, &mut w)).collect();
        let b = ps.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let Some(s) = rs.iter().zip(&ps).position(|(r, p)| p <= r) else {
            println!("nu {nu}: P > r up to 3");
            continue;
        };
        let (ia, lo) = (s..n)
            .filter(|&i| rs[i] <= b)
            .map(|i| (i, ps[i]))
            .fold((s, f64::INFINITY), |x, y| if y.1 < x.1 { y } else { x });
        println!(
            "nu {nu}: r_u {ru:.5}, band top {b:.4}, lowest return {lo:.5} (from r = {:.4}), \
             lowest - r_u = {:+.5}",
            rs[ia],
            lo - ru
        );
    }
}
