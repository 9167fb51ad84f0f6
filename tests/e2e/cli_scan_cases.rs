//! End-to-end scans through the real binary for cases the other tests do not reach: a sweep
//! of the belt speed lambda, scans where no unstable cycle exists, and starts inside the
//! trap band around the cycle. Each file is reopened with the hdf5 crate, as a user would.

use std::path::Path;
use std::process::{Command, Output};

fn squeal(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the squeal binary runs")
}

fn ok(o: Output) -> String {
    assert!(
        o.status.success(),
        "failed: {}\nstdout: {}",
        String::from_utf8_lossy(&o.stderr),
        String::from_utf8_lossy(&o.stdout)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn json(o: Output) -> serde_json::Value {
    serde_json::from_str(&ok(o)).expect("one JSON object")
}

/// Writes `spec` as `name.toml` and scans it into `name.h5`; returns the open file.
fn scan(dir: &Path, name: &str, spec: &str) -> hdf5::File {
    std::fs::write(dir.join(format!("{name}.toml")), spec).unwrap();
    ok(squeal(
        dir,
        &[
            "scan",
            &format!("{name}.toml"),
            "-o",
            &format!("{name}.h5"),
            "--quiet",
        ],
    ));
    hdf5::File::open(dir.join(format!("{name}.h5"))).unwrap()
}

fn f64_attr(loc: &hdf5::Location, name: &str) -> f64 {
    loc.attr(name).unwrap().read_scalar().unwrap()
}

fn text_attr(loc: &hdf5::Location, name: &str) -> String {
    let s: hdf5::types::VarLenUnicode = loc.attr(name).unwrap().read_scalar().unwrap();
    s.as_str().to_string()
}

/// Reason codes of the file's `reason` enum (crates/store schema).
const INSIDE_CYCLE: u8 = 2;
const OUTSIDE_CYCLE: u8 = 3;
const START_INSIDE: u8 = 8;
const START_OUTSIDE: u8 = 9;
const NEAR_FIXED_POINT: u8 = 1;
/// `Reason::EnteredRegion` and `Reason::StartInRegion`: the run entered (or started in) the
/// certified region of attraction around the fixed point (crates/core/MODEL.md section 9),
/// which proves it settles there.
const IN_CERTIFIED_REGION: [u8; 2] = [11, 12];
/// `Reason::BelowDecayingSection`, `Reason::StartInsideDecayingTurn` and
/// `Reason::EnteredDecayingTurn`: McMillan's smooth laws with no unstable cycle found
/// (crates/core/MODEL.md section 9, "A decaying section").
const DECAYING_SECTION: [u8; 3] = [17, 18, 19];

#[test]
#[ignore = "long check (a minute or more on 2 cores): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn a_lambda_sweep_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    // 9 x 9 cells on the paper's window, so (0, 0) (the state at rest) is a cell.
    let spec = "version = 1\nname = \"lambda-sweep\"\n[model]\nlaw = \"mcmillan\"\nnu = 1e-3\n\
                lambda = [2.0, 3.0]\n[grid]\nx0 = { min = -3.0, max = 5.0, count = 9 }\n\
                v0 = { min = -4.0, max = 4.0, count = 9 }\n[output]\npath = \"x.h5\"\n";
    let f = scan(dir.path(), "sweep", spec);
    // lambda is the swept coordinate, nu a scalar attribute.
    let lambda: Vec<f64> = f.dataset("lambda").unwrap().read_raw().unwrap();
    assert_eq!(lambda, [2.0, 3.0]);
    assert_eq!(f64_attr(&f, "nu"), 1e-3);
    assert!(
        f.attr("lambda").is_err(),
        "lambda is a coordinate, not an attribute"
    );
    let labels = f.dataset("labels").unwrap();
    assert_eq!(labels.shape(), [2, 9, 9]);
    let l: Vec<u8> = labels.read_raw().unwrap();
    assert!(l.iter().all(|&v| v == 1 || v == 2), "every cell decided");
    let info = squeal_store::read_info(&dir.path().join("sweep.h5")).unwrap();
    let sweep = info.sweep.expect("a lambda sweep");
    assert_eq!(sweep.single(), Some(("lambda", &[2.0, 3.0][..])));
    // Each map used its own lambda: its stored cycle is the one `squeal ulc --lambda L`
    // locates, and its label at rest (cell x0 = 0, v0 = 0: column 3, row 4) is the one
    // `squeal classify --lambda L` gives. The cycles differ (0.164 vs 0.365 at the section).
    std::fs::write(dir.path().join("rest.csv"), "x0,v0\n0,0\n").unwrap();
    let mut rs = Vec::new();
    for (m, lam) in lambda.iter().enumerate() {
        let g = f.group(&format!("cycles/map_{m:04}")).unwrap();
        let r = f64_attr(&g, "r_section");
        let j = json(squeal(
            dir.path(),
            &[
                "ulc",
                "--lambda",
                &lam.to_string(),
                "--no-half-dt",
                "--json",
            ],
        ));
        assert!(
            (r - j["r_section"].as_f64().unwrap()).abs() < 1e-9,
            "lambda {lam}: {r} vs {}",
            j["r_section"]
        );
        rs.push(r);
        let out = format!("rest{m}.csv");
        ok(squeal(
            dir.path(),
            &[
                "classify",
                "--lambda",
                &lam.to_string(),
                "--ics",
                "rest.csv",
                "--out",
                &out,
            ],
        ));
        let csv = std::fs::read_to_string(dir.path().join(&out)).unwrap();
        let label = csv.lines().nth(1).unwrap().split(',').nth(2).unwrap();
        let want = match label {
            "steady_slip" => 1,
            "stick_slip" => 2,
            other => panic!("rest at lambda {lam}: {other}"),
        };
        assert_eq!(l[m * 81 + 4 * 9 + 3], want, "lambda {lam}");
    }
    assert!((rs[0] - rs[1]).abs() > 0.1, "{rs:?}");
    // The sweep's summary datasets, one value per map.
    let cyc: Vec<f64> = f.dataset("cycle_r_section").unwrap().read_raw().unwrap();
    assert_eq!(cyc, rs);
}

/// Coulomb friction with nu = 1e-2: no unstable cycle (every oscillation below the belt
/// speed is a linear one decaying as e^(-nu t) about x* = 1, and one that sticks leaves the
/// belt at x = 1 + 2 nu lambda and then decays). The file must say there is no cycle, and no
/// cell may claim to be inside or outside one.
#[test]
fn a_scan_without_an_unstable_cycle_says_so() {
    let dir = tempfile::tempdir().unwrap();
    for (name, law, nu) in [("coulomb", "coulomb", 1e-2), ("damped", "mcmillan", 5e-2)] {
        let spec = format!(
            "version = 1\n[model]\nlaw = \"{law}\"\nnu = {nu:?}\n[grid]\n\
             x0 = {{ min = -3.0, max = 5.0, count = 9 }}\nv0 = {{ min = -4.0, max = 4.0, count = 9 }}\n\
             [output]\npath = \"x.h5\"\n"
        );
        let f = scan(dir.path(), name, &spec);
        let g = f.group("cycle").unwrap();
        let why = text_attr(&g, "error");
        assert!(why.contains("decays at every"), "{name}: {why}");
        assert!(g.dataset("x").is_err(), "{name}: no curve without a cycle");
        assert!(g.attr("r_section").is_err(), "{name}");
        let labels: Vec<u8> = f.dataset("labels").unwrap().read_raw().unwrap();
        let reason: Vec<u8> = f.dataset("reason").unwrap().read_raw().unwrap();
        for (k, (&l, &r)) in labels.iter().zip(&reason).enumerate() {
            assert!(
                r != INSIDE_CYCLE && r != OUTSIDE_CYCLE,
                "{name} cell {k}: {r}"
            );
            // Every start settles on the fixed point (Coulomb: the argument above; McMillan at
            // nu = 5e-2: above the critical damping for the whole window). McMillan's law has
            // a certified region of attraction and a decaying section, so its runs are decided
            // on entering the region, at their first crossing below the section's top or of the
            // lower half inside a decaying turn (or at the start, inside such a turn); Coulomb's has neither, and its runs are
            // followed to fp_radius.
            let settles = if law == "coulomb" {
                r == NEAR_FIXED_POINT
            } else {
                r == NEAR_FIXED_POINT
                    || IN_CERTIFIED_REGION.contains(&r)
                    || DECAYING_SECTION.contains(&r)
            };
            assert!(l == 1 && settles, "{name} cell {k}: label {l}, reason {r}");
        }
        if law == "coulomb" {
            // From rest (cell x0 = 0, v0 = 0) the distance to the fixed point is e^(-nu t), so
            // it comes within fp_radius = 1e-3 at t = ln(1000) / nu = 690.8.
            let t: Vec<f64> = f.dataset("t_decision").unwrap().read_raw().unwrap();
            let t_rest = t[4 * 9 + 3];
            let want = 1000f64.ln() / nu;
            assert!((t_rest - want).abs() < 0.01 * want, "{t_rest} vs {want}");
        }
    }
}

/// Starts inside the trap band (within trap_margin = 1e-3 of the cycle's section crossing)
/// are not decided by the cycle at once: they run until their own crossing leaves the band,
/// and then land on the side they started on. nu = 1e-2: multiplier 1.16 per revolution,
/// so a deviation of 5e-4 leaves the 1e-3 band after about ln 2 / ln 1.16 = 4.7
/// revolutions, while one of 5e-3 lies clear of the band and of the curve's margin and is
/// decided at the start, without a run, on the same side.
#[test]
fn starts_inside_the_trap_band_run_until_they_leave_it() {
    let dir = tempfile::tempdir().unwrap();
    let j = json(squeal(
        dir.path(),
        &["ulc", "--nu", "1e-2", "--no-half-dt", "--json"],
    ));
    let (r_u, period) = (
        j["r_section"].as_f64().unwrap(),
        j["period"].as_f64().unwrap(),
    );
    // Two columns straddling the section x = x* = 1 by 1e-7, so the first crossing comes
    // at once; two rows at r_u (1 -+ d).
    let spec = |d: f64| {
        format!(
            "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 1e-2\n[grid]\n\
             x0 = {{ min = 0.9999999, max = 1.0000001, count = 2 }}\n\
             v0 = {{ min = {:?}, max = {:?}, count = 2 }}\n\
             [classifier]\ntrap_margin = 1e-3\n[output]\npath = \"x.h5\"\n",
            r_u * (1.0 - d),
            r_u * (1.0 + d)
        )
    };
    for (name, d) in [("band", 5e-4), ("clear", 5e-3)] {
        let f = scan(dir.path(), name, &spec(d));
        let labels: Vec<u8> = f.dataset("labels").unwrap().read_raw().unwrap();
        let reason: Vec<u8> = f.dataset("reason").unwrap().read_raw().unwrap();
        let t: Vec<f64> = f.dataset("t_decision").unwrap().read_raw().unwrap();
        // Row 0 (below r_u): steady slip, inside; row 1: stick-slip, outside.
        assert_eq!(labels, [1, 1, 2, 2], "{name}");
        // The outside rules rest on the paper's picture (everything outside the cycle
        // squeals). The map's census (crates/core/MODEL.md, section 12) runs starts around the
        // grid and the cycle with no rule: here its start (1, 2.090245), 5e-4 outside the
        // cycle, reaches the fixed point at t = 1376 (the band leaks back inside near the
        // cycle), so in both grids the outside rules are withdrawn and the outside cells are
        // decided by their runs. The file says so; then they must not carry the withdrawn
        // reasons.
        let withdrawn = text_attr(&f, "rules_withdrawn");
        let outside_withdrawn = withdrawn.contains("outside_cycle withdrawn");
        let inside = if name == "band" {
            INSIDE_CYCLE
        } else {
            START_INSIDE
        };
        let outside = if outside_withdrawn {
            assert!(withdrawn.contains("reached the fixed point"), "{withdrawn}");
            assert!(
                reason[2..]
                    .iter()
                    .all(|&r| r != OUTSIDE_CYCLE && r != START_OUTSIDE),
                "{reason:?}"
            );
            [reason[2], reason[3]]
        } else if name == "band" {
            [OUTSIDE_CYCLE, OUTSIDE_CYCLE]
        } else {
            [START_OUTSIDE, START_OUTSIDE]
        };
        let want = [inside, inside, outside[0], outside[1]];
        assert_eq!(reason, want, "{name}: {withdrawn}");
        for (k, &tk) in t
            .iter()
            .enumerate()
            .take(if outside_withdrawn { 2 } else { 4 })
        {
            if name == "band" {
                assert!(tk > 3.0 * period, "{name} cell {k}: decided at {tk}");
                assert!(tk < 12.0 * period, "{name} cell {k}: decided at {tk}");
            } else {
                assert_eq!(tk, 0.0, "{name} cell {k}: decided at {tk}");
            }
        }
    }
}

/// A shard with no rows of the map (`--shard 5/8` of a 4-row grid) said "basin stability of
/// 0 cells: steady_slip NaN (2h NaN, change NaN) ...", which reads as a failed computation.
#[test]
fn a_shard_without_rows_says_so_instead_of_nan() {
    let dir = tempfile::tempdir().unwrap();
    let spec = "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = 1e-3\n[grid]\n\
                x0 = { min = -3.0, max = 5.0, count = 4 }\n\
                v0 = { min = -4.0, max = 4.0, count = 4 }\n[output]\npath = \"e.h5\"\n";
    std::fs::write(dir.path().join("e.toml"), spec).unwrap();
    let out = ok(squeal(
        dir.path(),
        &["scan", "e.toml", "-o", "e.h5", "--shard", "5/8"],
    ));
    assert!(!out.contains("NaN"), "{out}");
    assert!(out.contains("no cell of this map computed here"), "{out}");
}
