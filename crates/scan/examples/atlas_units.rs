//! The CPU time of each work unit of an atlas spec (boundary searches and lines of points),
//! run one at a time on one thread: where an atlas's time goes, and how evenly its units
//! share two cores (the longest unit bounds the wall clock from below).
//!
//!     cargo run --release -p squeal-scan --example atlas_units -- SPEC [boundary|line|all]

use std::time::Instant;

use squeal_scan::atlas::driver::run_unit;
use squeal_scan::atlas::{AtlasPlan, Unit};

/// CPU time of this thread, in seconds (NaN where the system does not tell it).
fn cpu() -> f64 {
    squeal_scan::estimate::thread_cpu_seconds().unwrap_or(f64::NAN)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.first().expect("an atlas spec");
    let text = std::fs::read_to_string(path).expect("a readable spec");
    let plan = AtlasPlan::from_toml(&text, path).expect("a valid spec");
    let which = args.get(1).map_or("all", String::as_str);
    let units: Vec<Unit> = plan
        .units()
        .into_iter()
        .filter(|u| {
            matches!(
                (which, u),
                ("boundary", Unit::Boundary(_)) | ("line", Unit::Line(_)) | ("all", _)
            )
        })
        .collect();
    let (mut total_b, mut total_l) = (0.0, 0.0);
    for u in units {
        let (c0, w0) = (cpu(), Instant::now());
        let r = run_unit(&plan, u).expect("a unit that runs");
        let (c, w) = (cpu() - c0, w0.elapsed().as_secs_f64());
        let what = match &r {
            squeal_scan::atlas::UnitResult::Boundary(b) => format!(
                "fold {:.6} +- {:.6} ({} verdicts), critical {:.6} ({} evaluations)",
                b.fold.nu,
                b.fold.uncertainty,
                b.fold.evaluations,
                b.critical.nu,
                b.critical.evaluations
            ),
            squeal_scan::atlas::UnitResult::Line(l) => {
                format!("{} points", l.points.len())
            }
        };
        match u {
            Unit::Boundary(_) => total_b += c,
            Unit::Line(_) => total_l += c,
        }
        println!("{u:?}\tcpu {c:.2} s\twall {w:.2} s\t{what}");
    }
    println!("total cpu: boundaries {total_b:.1} s, lines {total_l:.1} s");
}
