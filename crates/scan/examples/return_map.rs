//! `D(r) = P(r) - r` of the return map on a plain uniform grid of section amplitudes, at
//! Table 1's lambda, tau and phi: the independent look at the section that
//! `squeal_scan::section`'s adaptive sampling is checked against. The numbers quoted in
//! `section::adaptive_samples` and `crates/scan/tests/scanning/edge.rs` come from
//!
//!     cargo run --release -p squeal-scan --example return_map -- mcmillan-nonhysteretic 0.0403 0.01 2.80 3.10 60
//!     cargo run --release -p squeal-scan --example return_map -- mcmillan-nonhysteretic 0.0403 0.01 2.930 2.940 40
//!
//! Arguments: law, nu, dt, then the grid's lower and upper ends and its number of intervals.

use squeal_core::{FrictionLaw, Params, SolverConfig, Stepper};
use squeal_scan::section::{ReturnMap, Work};

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    assert!(a.len() == 6, "usage: LAW NU DT LO HI N");
    let law: FrictionLaw = a[0].parse().expect("a friction law of McMillan");
    let num = |i: usize| -> f64 { a[i].parse().expect("a number") };
    let (nu, dt, lo, hi, n) = (num(1), num(2), num(3), num(4), num(5) as usize);
    let st = Stepper::new(Params::paper(law, nu), dt, SolverConfig::default()).expect("a model");
    let m = ReturnMap::new(&st, 200.0);
    let mut w = Work::default();
    println!("# {law} nu = {nu} dt = {dt}: r, D(r)");
    for i in 0..=n {
        let r = lo + (hi - lo) * i as f64 / n as f64;
        println!("{r:.5} {:+.6e}", m.d(r, &mut w));
    }
}
