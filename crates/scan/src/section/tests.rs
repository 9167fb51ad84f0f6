use super::*;

fn table1(nu: f64) -> Stepper {
    let p = squeal_core::Params::paper(squeal_core::FrictionLaw::McMillan, nu);
    Stepper::new(p, 0.005, squeal_core::SolverConfig::default()).unwrap()
}

#[test]
fn a_cached_return_is_the_same_return_under_a_longer_limit() {
    // Table 1 near the crisis: a small start (a slip revolution, period about 2 pi), one
    // on the band and one far out; each return cached under the limit 200 is the return
    // an uncached map gives under 400, bit for bit, and is not run (nor counted) again.
    let st = table1(0.024);
    let cache = ReturnCache::default();
    let (mut w, mut w_cached) = (Work::default(), Work::default());
    for r in [0.5, 2.7, 5.0] {
        let short = ReturnMap::cached(&st, 200.0, &cache).d(r, &mut w_cached);
        let long = ReturnMap::cached(&st, 400.0, &cache).d(r, &mut w_cached);
        let plain = ReturnMap::new(&st, 400.0).d(r, &mut w);
        assert!(short > -r, "{r}: a return within 200");
        assert_eq!(long.to_bits(), plain.to_bits(), "{r}");
        assert_eq!(short.to_bits(), plain.to_bits(), "{r}");
    }
    assert_eq!(w_cached.returns, 3);
    // No return within 1 time unit (a revolution takes about 2 pi): decay under that
    // limit only; under 200 the run is made again and returns.
    let r = 0.5;
    let cut = ReturnMap::cached(&st, 1.0, &cache);
    let cache_cut = ReturnCache::default();
    assert_eq!(ReturnMap::cached(&st, 1.0, &cache_cut).d(r, &mut w), -r);
    assert_eq!(
        cut.d(r, &mut w_cached),
        -r,
        "the return cached under 200 is not reused"
    );
    let again = ReturnMap::cached(&st, 200.0, &cache_cut).d(r, &mut w_cached);
    assert_eq!(
        again.to_bits(),
        ReturnMap::new(&st, 200.0).d(r, &mut w).to_bits()
    );
}

#[test]
fn the_escape_precision_keeps_the_answer_of_the_full_bisection() {
    // Table 1 at nu = 0.01 (paper Fig 10: every sampled start above the cycle returns
    // above it) and at 0.0242 (past the crisis, crates/scan/src/band.rs: the band leaks,
    // so some start escapes): the same kind, stable crossing and escape; the crossing
    // bit for bit where something escapes, else a wider bracket holding it, for fewer
    // returns.
    for (nu, escapes) in [(0.01, false), (0.0242, true)] {
        let st = table1(nu);
        let cs = CycleSettings::default();
        let map = ReturnMap::new(&st, cs.t_return);
        let (mut wf, mut we) = (Work::default(), Work::default());
        let full = search_section(&map, &cs, &mut wf);
        let lazy = search_section_to(&map, &cs, Precision::Escape, &mut we);
        let (
            SectionCycles::Unstable {
                r,
                stable_above,
                escape,
                ..
            },
            SectionCycles::Unstable {
                r: r2,
                lo: lo2,
                hi: hi2,
                stable_above: s2,
                escape: e2,
            },
        ) = (full, lazy)
        else {
            panic!("{nu}: {full:?} {lazy:?}");
        };
        assert_eq!(escape.is_some(), escapes, "{nu}: {full:?}");
        assert_eq!((stable_above, escape), (s2, e2), "{nu}");
        if escapes {
            assert_eq!((r.to_bits(), wf.returns), (r2.to_bits(), we.returns));
        } else {
            assert!(lo2 <= r && r <= hi2, "{nu}: {r} outside [{lo2}, {hi2}]");
            assert!(
                we.returns < wf.returns,
                "{nu}: {} vs {}",
                we.returns,
                wf.returns
            );
        }
    }
}

#[test]
fn log_samples_hit_both_ends() {
    let rs = log_samples(1e-2, 6.0, 96);
    assert_eq!(rs.len(), 96);
    assert!((rs[0] - 1e-2).abs() < 1e-15);
    assert!((rs[95] - 6.0).abs() < 1e-12);
    // Log-spaced: constant ratio (6 / 0.01)^(1/95).
    let q = (6.0f64 / 1e-2).powf(1.0 / 95.0);
    assert!(rs.windows(2).all(|p| (p[1] / p[0] / q - 1.0).abs() < 1e-12));
}

#[test]
fn coarse_changes_finds_every_flip() {
    // True on [2, 3) and from 5 on: three changes over [1, 8] in 7 geometric steps
    // (values 1, 1.346, 1.811, 2.438, 3.281, 4.416, 5.944, 8).
    let pred = |v: f64| Ok::<_, ()>((2.0..3.0).contains(&v) || v >= 5.0);
    let c = coarse_changes(pred, (1.0, 8.0), 7).unwrap();
    let to: Vec<bool> = c.iter().map(|c| c.to).collect();
    assert_eq!(to, [true, false, true]);
    assert!(c[0].lo < 2.0 && c[0].hi >= 2.0 && c[2].lo < 5.0 && c[2].hi >= 5.0);
}

#[test]
fn geometric_bisection_finds_a_known_threshold() {
    // Predicate true above sqrt(2): the bracket closes on it.
    let t = 2f64.sqrt();
    let ((lo, hi), n) =
        geometric_bisection(|v| Ok::<_, ()>(v > t), (1e-3, 10.0), 1e-9, 200).unwrap();
    assert!(lo <= t && t <= hi && hi / lo - 1.0 <= 1e-9);
    // ln(1e4) / ln(1 + 1e-9) halvings: ceil(log2(9.21 / 1e-9)) = 34, plus the two ends.
    assert_eq!(n, 36);
}
