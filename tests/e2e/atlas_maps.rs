//! End-to-end tests of an atlas's basin maps: stored over the parameters with the cell
//! schema, their basin fractions against the cycle, bad grids, resume after a kill, layout.

use std::path::Path;
use std::process::Command;

use crate::atlas::{json, ok, read_f64, read_u8, records_in, refused, shape, squeal, str_attr};

/// Table 1 at Figs 9 and 10 (nu = 1e-3, 1e-2) with a small basin map per point over the
/// atlas's default disturbance box; no boundary searches (they are not what the test reads,
/// and took 5 of its 18 s of CPU per run).
const MAPS: &str = r#"
version = 1
name = "maps"
[model]
law = "mcmillan"
nu = [1e-3, 1e-2]
[cycle]
half_dt = false
[attractor]
transient = 10
window = 10
[boundaries]
fold = false
critical = false
[grid]
x0 = { min = -2.0, max = 4.0, count = 10 }
v0 = { min = -3.0, max = 3.0, count = 8 }
block_rows = 3
[output]
path = "maps.h5"
"#;

#[test]
#[ignore = "long check (a minute or more on 2 cores): run by scripts/ci/long-checks.sh, which .ci/run calls"]
fn maps_are_stored_over_the_parameters_with_the_cell_schema() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("maps.toml"), MAPS).unwrap();
    let a = json(&ok(squeal(dir.path(), &["atlas", "maps.toml", "--json"])));
    let h5 = dir.path().join("maps.h5");
    // One map per nu, (nu, v0, x0), every column of the scan's cell schema with its words.
    for col in squeal_scan::cell::COLUMNS {
        let name = format!("map_{}", col.name);
        assert_eq!(shape(&h5, &name), [2, 8, 10], "{name}");
        assert_eq!(str_attr(&h5, Some(&name), "long_name"), col.long_name);
        if !col.units.is_empty() {
            assert_eq!(str_attr(&h5, Some(&name), "units"), col.units);
        }
    }
    assert_eq!(
        str_attr(&h5, Some("map_labels"), "flag_meanings"),
        "undecided steady_slip stick_slip slip_oscillation not_computed"
    );
    // Named dimensions: the coordinates are dimension scales, attached in order.
    let f = hdf5::File::open(&h5).unwrap();
    for (c, n) in [("nu", 2), ("v0", 8), ("x0", 10), ("block", 3)] {
        let d = f.dataset(c).unwrap();
        assert_eq!(d.shape(), [n], "{c}");
        assert!(d.attr("CLASS").is_ok(), "{c} is not a dimension scale");
    }
    assert_eq!(
        f.dataset("map_labels")
            .unwrap()
            .attr("DIMENSION_LIST")
            .unwrap()
            .shape(),
        [3]
    );
    assert_eq!(f.dataset("x0").unwrap().read_raw::<f64>().unwrap()[9], 4.0);
    drop(f);
    assert_eq!(read_u8(&h5, "blocks_done"), vec![1; 6]);
    // Every cell decided at these points (the trap of the located cycle decides quickly).
    let labels = read_u8(&h5, "map_labels");
    assert!(labels.iter().all(|&l| l == 1 || l == 2), "{labels:?}");
    assert_eq!(str_attr(&h5, None, "scheme"), "foh");
    assert_eq!(str_attr(&h5, Some("basin_fraction"), "source"), "map");
    // The JSON reports the map's fraction and keeps the cycle's.
    for p in a["points"].as_array().unwrap() {
        assert_eq!(p["basin_fraction_source"], "map");
        assert!((0.0..=1.0).contains(&p["basin_fraction"].as_f64().unwrap()));
        assert!(p["basin_fraction_cycle"].as_f64().is_some());
        assert_eq!(p["map"]["cells"], 80);
    }
    // Fig 10's map shows both attractors; at Fig 9 the unstable cycle (r_section 0.37) is
    // smaller than this grid's cells, so every cell squeals.
    assert!(labels[80..].contains(&1) && labels[80..].contains(&2));
    assert!(labels[..80].iter().all(|&l| l == 2));
    // The chart and the sheet of maps are drawn beside the file.
    assert!(dir.path().join("maps.png").exists());
    assert!(dir.path().join("maps-maps.png").exists());

    shards_merge_into_the_same_maps(dir.path(), &labels);
}

/// The atlas `maps.toml` in `dir` run as two shards, merged, and rendered: the merged file
/// holds the single run's (`maps.h5`) `labels` and figures, and its pictures are drawn.
fn shards_merge_into_the_same_maps(dir: &Path, labels: &[u8]) {
    let h5 = dir.join("maps.h5");
    // Shards (units and map blocks both split) merge into the single run's file.
    for k in ["1/2", "2/2"] {
        let out = format!("s{}.h5", &k[..1]);
        ok(squeal(
            dir,
            &["atlas", "maps.toml", "--shard", k, "-o", &out],
        ));
    }
    let s1 = read_u8(&dir.join("s1.h5"), "blocks_done");
    assert!(s1.contains(&0) && s1.contains(&1), "{s1:?}");
    ok(squeal(dir, &["merge", "s1.h5", "s2.h5", "-o", "merged.h5"]));
    let merged = dir.join("merged.h5");
    assert_eq!(read_u8(&merged, "map_labels"), labels);
    for name in [
        "map_t_decision",
        "basin_fraction",
        "basin_fraction_err",
        "basin_fraction_cycle",
        "map_cycle_x",
        "cycle_r_section",
    ] {
        assert_eq!(read_f64(&h5, name), read_f64(&merged, name), "{name}");
    }
    assert!(dir.join("merged-maps.png").exists());
    // render redraws the pictures, the maps' final-state sensitivity too.
    ok(squeal(dir, &["render", "merged.h5", "-o", "again.png"]));
    assert!(dir.join("again-maps.png").exists());
    assert!(dir.join("again-sensitivity.png").exists());
}

#[test]
fn map_basin_fraction_agrees_with_the_cycle_at_fig_10() {
    // Fig 10 (nu = 1e-2): the unstable cycle lies inside the box, so the share of the box
    // inside it is computed twice independently: the clipped area of the located cycle
    // (with the dt/2 shift and chord error) and the share of map cells that return to
    // steady slip (with undecided cells and cells within one cell of the cycle). Each
    // value comes with its uncertainty; they must agree within the sum.
    let spec = MAPS
        .replace("nu = [1e-3, 1e-2]", "nu = 1e-2")
        .replace("half_dt = false", "half_dt = true")
        .replace("count = 10", "count = 48")
        .replace("count = 8", "count = 48")
        .replace("block_rows = 3", "block_rows = 16");
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("one.toml"), spec).unwrap();
    let a = json(&ok(squeal(
        dir.path(),
        &["atlas", "one.toml", "--json", "--no-render"],
    )));
    let p = &a["points"][0];
    assert_eq!(p["regime"], "bistable_quiet");
    let (fm, em) = (
        p["basin_fraction"].as_f64().unwrap(),
        p["basin_fraction_err"].as_f64().unwrap(),
    );
    let (fc, ec) = (
        p["basin_fraction_cycle"].as_f64().unwrap(),
        p["basin_fraction_cycle_err"].as_f64().unwrap(),
    );
    assert!(fm > 0.05 && fm < 0.95, "{fm}");
    assert!(
        (fm - fc).abs() <= em + ec,
        "map {fm} +- {em}, cycle {fc} +- {ec}"
    );
    // The bound is informative: well below the fraction itself.
    assert!(em < 0.25 && em > 0.0, "{em}");
    // One point, nothing swept: the maps are over (point, v0, x0).
    assert_eq!(
        shape(&dir.path().join("maps.h5"), "map_labels"),
        [1, 48, 48]
    );
    // A one-point atlas drew no chart without a word and printed "1 points over ,".
    // The make-like rerun (up to date) prints the summary in words.
    let words = ok(squeal(dir.path(), &["atlas", "one.toml", "--no-render"]));
    assert!(
        words.contains("1 parameter point (nothing swept: no chart;"),
        "{words}"
    );
    assert!(!words.contains("points over ,"), "{words}");
}

#[test]
fn bad_grids_are_refused_before_computing() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (MAPS.replace("count = 10", "count = 0"), "grid.x0.count"),
        (
            MAPS.replace("block_rows = 3", "block_rows = 3\nrows = 2"),
            "rows",
        ),
        (
            MAPS.replace(
                "[grid]",
                "[disturbance]\nx = [-1.0, 1.0]\nv = [-1.0, 1.0]\n[grid]",
            ),
            "disturbance",
        ),
        (
            MAPS.replace("[output]", "[classifier]\nsettle_cycles = 1\n[output]"),
            "classifier.settle_cycles",
        ),
        (
            MAPS.replace("[output]", "[integration]\nscheme = \"rk4\"\n[output]"),
            "scheme",
        ),
    ];
    for (k, (text, key)) in cases.iter().enumerate() {
        let name = format!("bad{k}.toml");
        std::fs::write(dir.path().join(&name), text).unwrap();
        refused(squeal(dir.path(), &["atlas", &name]), key);
        assert!(!dir.path().join("maps.h5").exists());
        assert!(!dir.path().join("maps.h5.journal").exists());
        assert!(!dir.path().join("maps.h5.lock").exists());
    }
}

#[test]
fn killed_maps_resume_to_the_same_file_and_the_output_is_locked() {
    // Slow enough to be killed midway: no early stopping, one thread.
    let spec = MAPS
        .replace("count = 10", "count = 16")
        .replace("count = 8", "count = 12")
        .replace("block_rows = 3", "block_rows = 2")
        .replace(
            "[output]",
            "[classifier]\nt_max = 400.0\nearly_stop = \"none\"\n[output]",
        );
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("slow.toml"), &spec).unwrap();
    ok(squeal(
        dir.path(),
        &["atlas", "slow.toml", "-o", "full.h5", "--no-render"],
    ));
    let stored = killed_after_a_map_block_while_locked(dir.path());
    let out = ok(squeal(
        dir.path(),
        &[
            "atlas",
            "slow.toml",
            "-o",
            "cut.h5",
            "--resume",
            "--no-render",
            "--json",
        ],
    ));
    // Only the missing blocks were computed: 2 maps x 6 blocks in all, `stored` of them (or
    // more, written before the kill) kept from the killed run.
    let computed = json(&out)["map_blocks_computed"].as_u64().unwrap() as usize;
    assert!(
        computed <= 12 - stored,
        "{computed} computed, {stored} were stored"
    );
    assert_eq!(blocks_in_file(&dir.path().join("cut.h5")), 12);
    let (a, b) = (dir.path().join("full.h5"), dir.path().join("cut.h5"));
    assert_eq!(read_u8(&a, "map_labels"), read_u8(&b, "map_labels"));
    assert_eq!(read_u8(&a, "map_reason"), read_u8(&b, "map_reason"));
    for name in [
        "map_t_decision",
        "map_amplitude",
        "basin_fraction",
        "basin_fraction_err",
        "map_cycle_x",
        "cycle_r_section",
    ] {
        assert_eq!(read_f64(&a, name), read_f64(&b, name), "{name}");
    }
    let journal = dir.path().join("cut.h5.journal");
    assert!(!journal.exists() && !dir.path().join("cut.h5.lock").exists());
}

/// Runs the atlas `slow.toml` in `dir` to `cut.h5` on one thread, checks that a second run
/// or a resume is refused while it runs, and kills it once a map block is in its journal;
/// the blocks stored by then.
fn killed_after_a_map_block_while_locked(dir: &Path) -> usize {
    let mut child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args([
            "atlas",
            "slow.toml",
            "-o",
            "cut.h5",
            "--threads",
            "1",
            "--no-render",
        ])
        .current_dir(dir)
        .spawn()
        .unwrap();
    // Wait for a map block record (kind `B`), then kill without warning.
    let journal = dir.join("cut.h5.journal");
    let blocks_in = || records_in(&journal, b'B');
    let t0 = std::time::Instant::now();
    while blocks_in() == 0 && t0.elapsed().as_secs() < 300 {
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let stored = blocks_in();
    assert!(
        stored > 0,
        "no map block reached the journal before the kill"
    );
    // While it runs, a second run or a resume on the same output is refused, naming it.
    let pid = child.id().to_string();
    for extra in ["--force", "--resume"] {
        let o = squeal(
            dir,
            &["atlas", "slow.toml", "-o", "cut.h5", "--no-render", extra],
        );
        refused(o.clone(), "being written by process");
        assert!(String::from_utf8_lossy(&o.stderr).contains(&pid));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!dir.join("cut.h5").exists(), "killed before the end");
    // SIGKILL leaves the lock; its process is gone, so the resume takes it over.
    assert!(dir.join("cut.h5.lock").exists());
    stored
}

/// Map blocks stored in a file.
fn blocks_in_file(p: &Path) -> usize {
    read_u8(p, "blocks_done")
        .iter()
        .filter(|&&d| d == 1)
        .count()
}

/// Width and height of a PNG (its IHDR chunk: bytes 16..24, big-endian).
fn png_size(p: &Path) -> (u32, u32) {
    let b = std::fs::read(p).unwrap();
    let be = |k: usize| u32::from_be_bytes(b[k..k + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn a_2d_atlas_lays_its_maps_out_over_both_parameters() {
    let spec = MAPS
        .replace(
            "nu = [1e-3, 1e-2]",
            "nu = [1e-3, 1e-2]\nlambda = [2.5, 3.0, 3.5]",
        )
        .replace("count = 10", "count = 6")
        .replace("count = 8", "count = 5");
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("two.toml"), spec).unwrap();
    ok(squeal(dir.path(), &["atlas", "two.toml"]));
    let h5 = dir.path().join("maps.h5");
    assert_eq!(shape(&h5, "map_labels"), [2, 3, 5, 6]);
    assert_eq!(shape(&h5, "blocks_done"), [2, 3, 2]);
    // Rows: nu (2), columns: lambda (3); panels 440 x 420 plus a 245-pixel legend
    // (crates/plot/src/lib.rs, basin_sheet).
    let (w, h) = png_size(&dir.path().join("maps-maps.png"));
    assert_eq!(w, 3 * 440 + 245);
    assert!(h > 2 * 420 && h < 3 * 420, "{h}");
    assert!(dir.path().join("maps.png").exists());
    // The maps' final-state sensitivity over both parameters, read from the file
    // (crates/plot/src/atlas_sensitivity.rs: two panels of 2000 x 1000 in all).
    assert_eq!(
        png_size(&dir.path().join("maps-sensitivity.png")),
        (2000, 1000)
    );
}
