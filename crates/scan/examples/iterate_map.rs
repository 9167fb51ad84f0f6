//! Iterates the return map `P` of the section `x = x*` from a section amplitude: the
//! sequence a run's crossings follow where the crossing's force is the one root there.
//!
//!     cargo run --release -p squeal-scan --example iterate_map -- mcmillan 1e-3 0.005 3.0 60
//!
//! Arguments: law, nu, dt, the first amplitude and the number of returns (Table 1's lambda,
//! tau and phi).

use squeal_core::{FrictionLaw, Params, SolverConfig, Stepper};
use squeal_scan::section::{ReturnMap, Work};

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    assert!(a.len() == 5, "usage: LAW NU DT R0 N");
    let law: FrictionLaw = a[0].parse().expect("a friction law of McMillan");
    let num = |i: usize| -> f64 { a[i].parse().expect("a number") };
    let (nu, dt, mut r, n) = (num(1), num(2), num(3), num(4) as usize);
    let st = Stepper::new(Params::paper(law, nu), dt, SolverConfig::default()).expect("a model");
    let m = ReturnMap::new(&st, 200.0);
    let mut w = Work::default();
    println!("# {law} nu = {nu} dt = {dt}: n, r_n, r_n+1 - r_n");
    for i in 0..n {
        let d = m.d(r, &mut w);
        println!("{i} {r:.10} {d:+.3e}");
        r += d;
    }
}
