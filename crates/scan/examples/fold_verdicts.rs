//! The band's verdict of the fold ([`squeal_scan::band::Variant`]: at dt, at dt/2 and with
//! the longer horizon) along the damping at one belt speed of an atlas spec: where the
//! three computations say squeal lasts, quiet or undecided, on a fine geometric grid (the
//! windows above a fold's interval that a coarse scan can step over). With `unit`, also the
//! atlas's own boundary unit there (fold and uncertainty).
//!
//!     cargo run --release -p squeal-scan --example fold_verdicts -- SPEC J NU_LO NU_HI N [unit]

use squeal_scan::atlas::point::settings_for;
use squeal_scan::atlas::{AtlasPlan, Unit, UnitResult, driver::run_unit};
use squeal_scan::band::{Budget, Lasting, Variant};

/// CPU time of this thread, in seconds (NaN where the system does not tell it).
fn cpu() -> f64 {
    squeal_scan::estimate::thread_cpu_seconds().unwrap_or(f64::NAN)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = &args[0];
    let text = std::fs::read_to_string(path).expect("a readable spec");
    let plan = AtlasPlan::from_toml(&text, path).expect("a valid spec");
    let j: usize = args[1].parse().expect("a boundary index");
    let (lo, hi): (f64, f64) = (args[2].parse().unwrap(), args[3].parse().unwrap());
    let n: usize = args[4].parse().expect("a number of values");
    let (i, _) = plan.boundary_setup(j);
    let (setup, ps) = (plan.setup_at(i), plan.settings_at(i));
    println!("lambda {}", setup.params.lambda);
    if args.get(5).is_some_and(|a| a == "unit") {
        if let Ok(UnitResult::Boundary(b)) = run_unit(&plan, Unit::Boundary(j)) {
            let f = b.fold;
            println!(
                "fold {:.6} +- {:.6}: [{:.6}, {:.6}], bracket [{:.6}, {:.6}]",
                f.nu,
                f.uncertainty,
                f.nu - f.uncertainty,
                f.nu + f.uncertainty,
                f.bracket[0],
                f.bracket[1]
            );
        }
    }
    let word = |l: Lasting| match l {
        Lasting::Squeals => "squeals",
        Lasting::Quiet => "quiet",
        Lasting::Undecided => "undecided",
    };
    for k in 0..n {
        let nu = lo * (hi / lo).powf(k as f64 / (n - 1).max(1) as f64);
        let s = setup.with_params(squeal_core::Params { nu, ..setup.params });
        let cs = settings_for(&s.params, &ps.cycle);
        // Each verdict alone (no returns shared), with its CPU time.
        let v: Vec<String> = Variant::ALL
            .iter()
            .map(|w| {
                let c0 = cpu();
                let l = w.lasting(s, &cs, Budget::Standard).map_or("error", word);
                format!("{l} {:.3}", cpu() - c0)
            })
            .collect();
        println!("{nu:.6}\t{}\t{}\t{}", v[0], v[1], v[2]);
    }
}
