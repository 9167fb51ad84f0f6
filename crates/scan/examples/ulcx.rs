use squeal_core::*;
use squeal_scan::ulc::*;
fn main() {
    for (law, nu) in [
        (FrictionLaw::McMillan, 1e-3),
        (FrictionLaw::McMillanNonHysteretic, 1e-3),
        (FrictionLaw::McMillan, 1e-2),
    ] {
        let t = std::time::Instant::now();
        let r = locate(
            Params::paper(law, nu),
            0.01,
            SolverConfig::default(),
            &CycleSettings::default(),
        )
        .unwrap();
        println!(
            "{law} {nu}: r={:.6} period={:.4} mult={:.5} dist={:.4} area={:.4} enc0={} half={:?} returns={} {:?}",
            r.r_section,
            r.period,
            r.multiplier,
            r.distance_plus_x,
            r.area,
            r.encloses_origin,
            r.half_dt,
            r.returns,
            t.elapsed()
        );
    }
    let plan = squeal_scan::Plan::from_toml(
        r#"
version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 64 }
v0 = { min = -4.0, max = 4.0, count = 64 }
[output]
path = "x.h5"
"#,
        "x.toml",
    )
    .unwrap();
    let t = std::time::Instant::now();
    let ctx = squeal_scan::scanner::MapContext::prepare(&plan, 0).unwrap();
    println!("prepare {:?} trap {:?}", t.elapsed(), ctx.classifier.trap);
    let t = std::time::Instant::now();
    let mut counts = [0usize; 3];
    let mut reasons = [0usize; 7];
    for b in 0..plan.grid.blocks() {
        let r = squeal_scan::scanner::run_block(
            &plan,
            &ctx,
            b,
            &squeal_scan::scanner::NoObserver,
            None,
        )
        .unwrap();
        for c in &r.cells {
            counts[c.regime as usize] += 1;
            reasons[c.reason as usize] += 1;
        }
    }
    let dt = t.elapsed().as_secs_f64();
    println!(
        "counts {counts:?} reasons {reasons:?} {dt:.3}s {:.0} cells/s",
        4096.0 / dt
    );
}
