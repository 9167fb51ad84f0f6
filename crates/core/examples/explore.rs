use squeal_core::*;
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().unwrap())
        .collect();
    let (nu, x0, v0, tmax, law, kind) = (
        args[0],
        args[1],
        args[2],
        args[3],
        args[4] as i32,
        args[5] as i32,
    );
    let law = [
        FrictionLaw::McMillan,
        FrictionLaw::McMillanNonHysteretic,
        FrictionLaw::Coulomb,
    ][law as usize];
    let kind = if kind == 0 {
        SolverKind::Robust
    } else {
        SolverKind::Paper
    };
    let dt = args.get(6).copied().unwrap_or(0.01);
    let st = Stepper::new(
        Params::paper(law, nu),
        dt,
        SolverConfig {
            kind,
            ..Default::default()
        },
    )
    .unwrap();
    let mut stats = SolverStats::default();
    let (mut s, _) = st.initial(State { x: x0, v: v0 }, &mut stats);
    let mut last_t = 0.0;
    let mut vmax: f64 = -1e9;
    let mut k = 0;
    let t0 = std::time::Instant::now();
    while s.t < tmax {
        let (n, _) = st.step(&s, &mut stats);
        vmax = vmax.max(n.v);
        if s.x < 1.0 && n.x >= 1.0 && n.v > 0.0 {
            let th = (1.0 - s.x) / (n.x - s.x);
            let vc = s.v + th * (n.v - s.v);
            let tc = s.t + th * dt;
            k += 1;
            if k < 10 || k % 50 == 0 {
                println!(
                    "cross {k} t={tc:.3} r={vc:.8} T={:.5} w={:.5} vmax={vmax:.4}",
                    tc - last_t,
                    2.0 * std::f64::consts::PI / (tc - last_t)
                );
            }
            last_t = tc;
            vmax = -1e9;
        }
        s = n;
    }
    println!("final {s:?} {stats:?} {:?}", t0.elapsed());
}
#[allow(dead_code)]
fn unused() {}
