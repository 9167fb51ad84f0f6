use squeal_core::classify::section_return;
use squeal_core::*;
fn main() {
    let a: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().unwrap())
        .collect();
    let law = if a[1] == 0.0 {
        FrictionLaw::McMillan
    } else {
        FrictionLaw::McMillanNonHysteretic
    };
    let st = Stepper::new(Params::paper(law, a[0]), 0.01, SolverConfig::default()).unwrap();
    let mut stats = SolverStats::default();
    let mut r = 0.02;
    while r < 4.0 {
        let c = section_return(&st, r, 100.0, &mut stats, |_| {});
        if let Some(c) = c {
            println!(
                "r={r:.4} P={:.6} D={:+.3e} ratio={:.5} T={:.3}",
                c.r,
                c.r - r,
                c.r / r,
                c.t
            );
        } else {
            println!("r={r} none");
        }
        r *= 1.15;
    }
    let t = std::time::Instant::now();
    let cl = Classifier {
        t_max: 20000.0,
        ..Default::default()
    };
    for (x0, v0) in [(0.0, 0.0), (1.2, 0.0), (1.0, 0.1), (-2.5, 0.0)] {
        let o = cl.classify(&st, State { x: x0, v: v0 });
        println!(
            "{x0},{v0}: {:?} {:?} t={:.1} amp={:.4} w={:.4}",
            o.regime, o.reason, o.t_decision, o.amplitude, o.omega
        );
    }
    println!("{:?}", t.elapsed());
}
