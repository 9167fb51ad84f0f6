use std::path::{Path, PathBuf};

use squeal_scan::Plan;
use squeal_scan::scanner::{BlockResult, Cell};
use squeal_scan::ulc::CycleReport;
use squeal_scan::{MapChecks, Sink};

use super::*;

const SPEC: &str = r#"
version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 5 }
v0 = { min = -4.0, max = 4.0, count = 7 }
block_rows = 2
[output]
path = "t.h5"
"#;

/// A scan's file finished as `squeal scan` finishes it: the engine reads the blocks back
/// through the writer and tallies them ([`squeal_scan::finish::finish`]).
trait Finish: Sized {
    fn finish_with(
        self,
        landscapes: &[Option<squeal_core::LandscapeEvidence>],
    ) -> Result<Vec<MapChecks>, StoreError>;
    fn finish(self) -> Result<Vec<MapChecks>, StoreError> {
        self.finish_with(&[])
    }
}

impl Finish for ScanWriter {
    fn finish_with(
        self,
        landscapes: &[Option<squeal_core::LandscapeEvidence>],
    ) -> Result<Vec<MapChecks>, StoreError> {
        squeal_scan::finish::finish(self.finishing(landscapes)?)
    }
}

/// Shard files joined as `squeal merge` joins them; the merged file's plan.
fn merge(
    shards: &[PathBuf],
    out: &Path,
    force: bool,
    _prov: &Provenance,
) -> Result<Plan, StoreError> {
    let f = merging(shards, out, force)?;
    let plan = squeal_scan::Finishing::plan(&f).clone();
    squeal_scan::finish::finish(f)?;
    Ok(plan)
}

fn plan() -> Plan {
    Plan::from_toml(SPEC, "t.toml").unwrap()
}

fn sweep_plan() -> Plan {
    Plan::from_toml(
        &SPEC.replace("nu = 1e-3", "nu = [1e-3, 2e-3, 5e-3]"),
        "t.toml",
    )
    .unwrap()
}

fn prov() -> Provenance {
    Provenance {
        version: "0.1.0".into(),
        git_revision: "abc".into(),
    }
}

/// A fabricated block: labels by distance from (1, 0), diagnostics from the index.
fn block(plan: &Plan, map: usize, block: usize) -> BlockResult {
    let g = &plan.map.grid;
    let rows = g.block_rows(block);
    let nx = g.x0.count;
    let cells = (0..rows.len() * nx)
        .map(|k| {
            let (x, v) = (g.x0.value(k % nx), g.v0.value(rows.start + k / nx));
            let r = (x - 1.0).hypot(v);
            let regime = if r < 1.5 {
                1
            } else if r < 4.0 {
                2
            } else {
                0
            };
            let i = (map * 1000 + block * 100 + k) as u64;
            Cell {
                regime,
                reason: (i % 7) as u8,
                t_decision: i as f64 * 0.5,
                amplitude: if i % 5 == 0 { f64::NAN } else { r },
                omega: 1.0 + i as f64 * 1e-3,
                quasi_static: (i % 2) as u8,
                evaluations: i * 1000,
                fallbacks: i as u32,
                multi_root: (i / 3) as u32,
                unconverged: (i % 4) as u32,
                max_residual: 1e-12 * i as f64,
                audit: (i % 4) as u8,
                t_squeal: [0.0, f64::INFINITY, -1.0, i as f64 * 0.25][(i % 4) as usize],
                sticks: [0, 1, 255][(i % 3) as usize],
                reverses: [1, 255, 0][(i % 3) as usize],
                x_amplitude: if i % 3 == 1 { f64::NAN } else { 0.1 * i as f64 },
                v_amplitude: if i % 3 == 1 { f64::NAN } else { 0.2 * i as f64 },
            }
        })
        .collect();
    BlockResult { map, block, cells }
}

fn cycle() -> CycleReport {
    let n = 64;
    let (xs, vs): (Vec<f64>, Vec<f64>) = (0..n)
        .map(|i| {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            (1.0 + 2.0 * a.cos(), 2.0 * a.sin())
        })
        .unzip();
    CycleReport {
        params: squeal_core::Params::paper(squeal_core::FrictionLaw::McMillan, 1e-3),
        dt: 0.01,
        r_section: 2.0,
        bracket: [1.999, 2.001],
        period: 6.5,
        omega: 1.0,
        x_range: [-1.0, 3.0],
        v_range: [-2.0, 2.0],
        distance_plus_x: 2.0,
        area: 12.5,
        multiplier: 1.3,
        encloses_origin: true,
        half_dt: Some(squeal_scan::ulc::HalfStepCheck {
            r_section: 2.0001,
            shift: 1e-4,
        }),
        returns: 120,
        solver: Default::default(),
        stable_above: None,
        escape: None,
        curve: squeal_scan::ClosedCurve::new(xs, vs),
    }
}

fn write_cycles(w: &mut ScanWriter, plan: &Plan, shard: Option<Shard>) {
    for m in 0..plan.maps.len() {
        let owns = (0..plan.map.grid.blocks()).any(|b| shard_owns(shard, plan, m, b));
        if !owns || w.has_cycle(m) {
            continue;
        }
        if m == 1 {
            let why = squeal_scan::NoCycle::Decays {
                r_max: 4.0,
                damping: squeal_scan::error::Damping::Nu(2e-3),
            };
            w.write_cycle(m, Some(&Err(why))).unwrap();
        } else {
            w.write_cycle(m, Some(&Ok(cycle()))).unwrap();
        }
    }
}

fn full_run(plan: &Plan, out: &Path, shard: Option<Shard>) -> Vec<MapChecks> {
    let mut w = ScanWriter::create(out, plan, shard, &prov(), false).unwrap();
    write_cycles(&mut w, plan, shard);
    for m in 0..plan.maps.len() {
        for b in 0..plan.map.grid.blocks() {
            if shard_owns(shard, plan, m, b) {
                w.write_block(&block(plan, m, b)).unwrap();
            }
        }
    }
    w.finish().unwrap()
}

fn journal_of(out: &Path) -> PathBuf {
    journal_path(out)
}

#[test]
fn round_trip_single_map() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.h5");
    let p = plan();
    let ws = full_run(&p, &out, None);
    assert!(!journal_of(&out).exists());
    assert!(!tmp_path(&out).exists());
    let ws = ws[0].wrong_side.expect("a cycle was recorded");
    assert!(ws.cells > 0 && ws.beyond_pixel <= ws.cells);

    let info = read_info(&out).unwrap();
    assert_eq!(info.schema, SCHEMA);
    assert_eq!(info.spec, SPEC);
    assert_eq!(info.version, "0.1.0");
    assert_eq!(info.x0, p.map.grid.x0.values());
    assert_eq!(info.v0, p.map.grid.v0.values());
    assert!(info.sweep.is_none());
    assert!(info.shard.is_none());
    assert_eq!(info.maps, 1);
    let labels = crate::map_labels(&info.path, 0).unwrap();
    assert_eq!(labels.len(), 35);
    assert!(!labels.contains(&squeal_scan::cell::NOT_COMPUTED));
    assert!(
        info.attrs
            .iter()
            .any(|(k, v)| k == "law" && v == "mcmillan")
    );
    assert!(info.attrs.iter().any(|(k, _)| k == "nu"));

    let map = read_map(&out, 0).unwrap();
    let want: Vec<u8> = (0..p.map.grid.blocks())
        .flat_map(|b| block(&p, 0, b).cells)
        .map(|c| c.regime)
        .collect();
    assert_eq!(map.labels, want);
    assert_eq!(map.title, "mcmillan nu = 0.001");
    assert_eq!(map.cycle.as_ref().unwrap().0, cycle().curve.x);
    assert!((map.fixed_point.0 - 1.0).abs() < 1e-12);
    assert_eq!(map_count(&out).unwrap(), 1);
    let s = read_cycle_summary(&out).unwrap();
    assert_eq!(s, vec![(1e-3, 2.0, 2.0, 12.5, true)]);
    assert!(matches!(
        read_map(&out, 1),
        Err(StoreError::NoSuchMap { .. })
    ));

    // Every cell comes back exactly.
    let f = read::open_squeal(&out).unwrap();
    for b in 0..p.map.grid.blocks() {
        let got = read::read_block(&f, false, 0, p.map.grid.block_rows(b)).unwrap();
        let want = block(&p, 0, b).cells;
        assert_eq!(format!("{got:?}"), format!("{want:?}"));
    }
}

#[test]
fn round_trip_sweep() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.h5");
    let p = sweep_plan();
    let ws = full_run(&p, &out, None);
    assert!(ws[0].wrong_side.is_some() && ws[1].wrong_side.is_none());
    // The reason for no cycle comes back typed and shown.
    assert!(
        info_no_cycle(&out)[1]
            .as_deref()
            .unwrap()
            .contains("decays")
    );
    let info = read_info(&out).unwrap();
    assert_eq!(info.sweep.as_ref().unwrap().names(), ["nu"]);
    assert_eq!(info.maps, 3);
    assert!(!info.attrs.iter().any(|(k, _)| k == "nu"));
    let m = read_map(&out, 2).unwrap();
    assert_eq!(m.title, "mcmillan nu = 0.005");
    assert!(read_map(&out, 1).unwrap().cycle.is_none());
    let s = read_cycle_summary(&out).unwrap();
    assert!(s[1].1.is_nan() && s[2].1 == 2.0);
    assert_eq!(map_count(&out).unwrap(), 3);
}

#[test]
fn refuses_overwrite_without_force() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.h5");
    let p = plan();
    full_run(&p, &out, None);
    let e = ScanWriter::create(&out, &p, None, &prov(), false).unwrap_err();
    assert!(
        e.to_string().contains("refusing to overwrite") && e.to_string().contains("a.h5"),
        "{e}"
    );
    let e = ScanWriter::resume(&out, &p, None, &prov()).unwrap_err();
    assert!(e.to_string().contains("already complete"), "{e}");
    // Killed after publishing, before removing the journal: complete, journal cleaned up.
    std::fs::write(journal_of(&out), b"stale").unwrap();
    let e = ScanWriter::resume(&out, &p, None, &prov()).unwrap_err();
    assert!(e.to_string().contains("already complete"), "{e}");
    assert!(!journal_of(&out).exists());
    // An interrupted scan is there.
    let out2 = dir.path().join("b.h5");
    drop(ScanWriter::create(&out2, &p, None, &prov(), false).unwrap());
    let e = ScanWriter::create(&out2, &p, None, &prov(), false).unwrap_err();
    assert!(matches!(e, StoreError::Interrupted { .. }), "{e}");
    assert!(e.to_string().contains("the resume option"), "{e}");
    // Force starts over.
    let w = ScanWriter::create(&out, &p, None, &prov(), true).unwrap();
    assert!(!out.exists());
    assert!(matches!(
        w.finish(),
        Err(StoreError::Incomplete { missing: 4, .. })
    ));
    // A missing folder is made, as by every door (`create_parent`); one that cannot be
    // made (a file where a folder should be) is refused naming it.
    let fresh = dir.path().join("no/such/x.h5");
    drop(ScanWriter::create(&fresh, &p, None, &prov(), false).unwrap());
    assert!(dir.path().join("no/such").is_dir());
    std::fs::write(dir.path().join("plain"), b"a file").unwrap();
    let e =
        ScanWriter::create(&dir.path().join("plain/x.h5"), &p, None, &prov(), false).unwrap_err();
    assert!(e.to_string().contains("cannot create folder"), "{e}");
    assert!(e.to_string().contains("plain"), "{e}");
}

#[test]
fn resume_gives_the_same_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = sweep_plan();
    let single = dir.path().join("single.h5");
    full_run(&p, &single, None);

    let out = dir.path().join("r.h5");
    let mut w = ScanWriter::create(&out, &p, None, &prov(), false).unwrap();
    w.write_cycle(0, Some(&Ok(cycle()))).unwrap();
    for b in 0..3 {
        w.write_block(&block(&p, 0, b)).unwrap();
    }
    drop(w);
    // A torn record: a kill in the middle of a write.
    let j = journal_of(&out);
    let mut bytes = std::fs::read(&j).unwrap();
    let whole = bytes.len();
    bytes.extend_from_slice(b"SQJRB\x10\x00\x00\x00garbage");
    std::fs::write(&j, &bytes).unwrap();

    let mut w = ScanWriter::resume(&out, &p, None, &prov()).unwrap();
    assert_eq!(std::fs::metadata(&j).unwrap().len() as usize, whole);
    assert_eq!(w.done_blocks(), 3);
    assert!(w.is_done(0, 2) && !w.is_done(0, 3));
    assert!(w.has_cycle(0) && !w.has_cycle(1));
    write_cycles(&mut w, &p, None);
    // Rewrite one block too: the latest record wins.
    w.write_block(&block(&p, 0, 1)).unwrap();
    drop(w);
    let mut w = ScanWriter::resume(&out, &p, None, &prov()).unwrap();
    for m in 0..p.maps.len() {
        for b in 0..p.map.grid.blocks() {
            if !w.is_done(m, b) {
                w.write_block(&block(&p, m, b)).unwrap();
            }
        }
    }
    w.finish().unwrap();
    assert_eq!(
        content_digest(&out).unwrap(),
        content_digest(&single).unwrap()
    );

    // Changing the spec or shard is refused.
    let out3 = dir.path().join("m.h5");
    drop(ScanWriter::create(&out3, &p, None, &prov(), false).unwrap());
    let other = plan();
    let e = ScanWriter::resume(&out3, &other, None, &prov()).unwrap_err();
    assert!(
        matches!(e, StoreError::SpecMismatch { .. }) && e.to_string().contains("m.h5.journal"),
        "{e}"
    );
    let e = ScanWriter::resume(&out3, &p, Some(Shard { k: 1, n: 2 }), &prov()).unwrap_err();
    assert!(e.to_string().contains("shard 1/2"), "{e}");
    let e = ScanWriter::resume(&dir.path().join("none.h5"), &p, None, &prov()).unwrap_err();
    assert!(e.to_string().contains("nothing to resume"), "{e}");
    std::fs::write(journal_of(&dir.path().join("g.h5")), b"garbage").unwrap();
    let e = ScanWriter::resume(&dir.path().join("g.h5"), &p, None, &prov()).unwrap_err();
    assert!(matches!(e, StoreError::NotSquealFile { .. }), "{e}");
}

#[test]
fn digests_differ_when_content_differs() {
    let dir = tempfile::tempdir().unwrap();
    let p = plan();
    let a = dir.path().join("a.h5");
    let b = dir.path().join("b.h5");
    full_run(&p, &a, None);
    let mut w = ScanWriter::create(&b, &p, None, &prov(), false).unwrap();
    write_cycles(&mut w, &p, None);
    for blk in 0..p.map.grid.blocks() {
        let mut r = block(&p, 0, blk);
        if blk == 2 {
            r.cells[3].evaluations += 1;
        }
        w.write_block(&r).unwrap();
    }
    w.finish().unwrap();
    assert_ne!(content_digest(&a).unwrap(), content_digest(&b).unwrap());
}

#[test]
fn shards_merge_to_the_single_file() {
    let dir = tempfile::tempdir().unwrap();
    for p in [plan(), sweep_plan()] {
        let single = dir.path().join("single.h5");
        let ws_single = full_run(&p, &single, None);
        let n = 3;
        let shards: Vec<PathBuf> = (1..=n)
            .map(|k| {
                let path = dir.path().join(format!("s{k}.h5"));
                full_run(&p, &path, Some(Shard { k, n }));
                path
            })
            .collect();
        let info = read_info(&shards[1]).unwrap();
        assert_eq!(info.shard.as_deref(), Some("2/3"));
        let labels = crate::map_labels(&info.path, 0).unwrap();
        assert!(labels.contains(&squeal_scan::cell::NOT_COMPUTED));
        let merged = dir.path().join("merged.h5");
        merge(&shards, &merged, false, &prov()).unwrap();
        assert_eq!(
            content_digest(&merged).unwrap(),
            content_digest(&single).unwrap()
        );
        assert!(ws_single[0].wrong_side.is_some());

        // Errors.
        let e = merge(&shards, &merged, false, &prov()).unwrap_err();
        assert!(e.to_string().contains("refusing to overwrite"), "{e}");
        let e = merge(&shards[..2], &dir.path().join("x.h5"), false, &prov()).unwrap_err();
        assert!(e.to_string().contains("missing shard 3/3"), "{e}");
        let dup = vec![shards[0].clone(), shards[0].clone(), shards[1].clone()];
        let e = merge(&dup, &dir.path().join("x.h5"), false, &prov()).unwrap_err();
        assert!(e.to_string().contains("overlap"), "{e}");
        let e = merge(
            std::slice::from_ref(&single),
            &dir.path().join("x.h5"),
            false,
            &prov(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("not a shard file"), "{e}");
        std::fs::remove_file(&single).unwrap();
        std::fs::remove_file(&merged).unwrap();
        for s in &shards {
            std::fs::remove_file(s).unwrap();
        }
    }
    // Different spec text, and different N.
    let p = plan();
    let a = dir.path().join("a.h5");
    full_run(&p, &a, Some(Shard { k: 1, n: 2 }));
    let q = Plan::from_toml(&SPEC.replace("count = 5", "count = 6"), "t.toml").unwrap();
    let b = dir.path().join("b.h5");
    full_run(&q, &b, Some(Shard { k: 2, n: 2 }));
    let e = merge(&[a.clone(), b], &dir.path().join("x.h5"), false, &prov()).unwrap_err();
    assert!(
        e.to_string().contains("do not belong together") && e.to_string().contains("spec"),
        "{e}"
    );
    let c = dir.path().join("c.h5");
    full_run(&p, &c, Some(Shard { k: 2, n: 3 }));
    let e = merge(&[a.clone(), c], &dir.path().join("x.h5"), false, &prov()).unwrap_err();
    assert!(e.to_string().contains("do not belong together"), "{e}");
    // An incomplete shard cannot be finished in the first place.
    let w = ScanWriter::create(
        &dir.path().join("i.h5"),
        &p,
        Some(Shard { k: 2, n: 2 }),
        &prov(),
        false,
    )
    .unwrap();
    assert!(matches!(w.finish(), Err(StoreError::Incomplete { .. })));
}

#[test]
fn shard_parsing() {
    assert_eq!("2/4".parse::<Shard>().unwrap(), Shard { k: 2, n: 4 });
    for bad in ["0/4", "5/4", "x", "1/0", "1/", "/2", "1/2/3"] {
        let e = bad.parse::<Shard>().unwrap_err();
        assert!(e.to_string().contains("K/N"), "{e}");
    }
    let p = plan();
    let owners: Vec<usize> = (0..p.map.grid.blocks())
        .map(|b| {
            (1..=3)
                .filter(|&k| shard_owns(Some(Shard { k, n: 3 }), &p, 0, b))
                .count()
        })
        .collect();
    assert!(owners.iter().all(|&c| c == 1));
}

#[test]
fn bad_files_give_errors_naming_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.h5");
    let e = read_info(&missing).unwrap_err();
    assert!(e.to_string().contains("missing.h5"), "{e}");

    let text = dir.path().join("text.h5");
    std::fs::write(&text, "hello, not hdf5").unwrap();
    let e = read_info(&text).unwrap_err();
    assert!(
        e.to_string().contains("text.h5") && e.to_string().contains("not an HDF5 file"),
        "{e}"
    );

    let foreign = dir.path().join("foreign.h5");
    {
        let f = hdf5::File::create(&foreign).unwrap();
        f.new_dataset::<f64>().shape(3).create("data").unwrap();
    }
    let e = read_info(&foreign).unwrap_err();
    assert!(
        e.to_string().contains("foreign.h5") && e.to_string().contains("schema"),
        "{e}"
    );

    let good = dir.path().join("good.h5");
    full_run(&plan(), &good, None);
    let bytes = std::fs::read(&good).unwrap();
    for cut in [bytes.len() / 2, 600, 100] {
        let trunc = dir.path().join(format!("trunc{cut}.h5"));
        std::fs::write(&trunc, &bytes[..cut]).unwrap();
        let e = read_info(&trunc).unwrap_err();
        assert!(e.to_string().contains(&format!("trunc{cut}.h5")), "{e}");
        assert!(read_map(&trunc, 0).is_err());
    }
    assert!(
        read_map(&text, 0)
            .unwrap_err()
            .to_string()
            .contains("text.h5")
    );
    assert!(
        map_count(&foreign)
            .unwrap_err()
            .to_string()
            .contains("foreign.h5")
    );
}

/// Writes sample files for checking with Python: `SQUEAL_DEMO_DIR=/tmp/d cargo test -p squeal-store -- --ignored`.
#[test]
#[ignore]
fn demo_files() {
    let dir = PathBuf::from(std::env::var("SQUEAL_DEMO_DIR").unwrap());
    for (name, p) in [("single.h5", plan()), ("sweep.h5", sweep_plan())] {
        let out = dir.join(name);
        let _ = std::fs::remove_file(&out);
        let _ = std::fs::remove_file(journal_path(&out));
        full_run(&p, &out, None);
    }
}

fn info_no_cycle(out: &Path) -> Vec<Option<String>> {
    read_info(out).unwrap().no_cycle
}

#[test]
fn a_second_writer_is_refused_while_the_first_holds_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.h5");
    let p = plan();
    let w = ScanWriter::create(&out, &p, None, &prov(), false).unwrap();
    for e in [
        ScanWriter::create(&out, &p, None, &prov(), true).unwrap_err(),
        ScanWriter::resume(&out, &p, None, &prov()).unwrap_err(),
    ] {
        assert!(matches!(e, StoreError::Locked { .. }), "{e}");
        assert!(
            e.to_string().contains(&std::process::id().to_string()),
            "{e}"
        );
    }
    // The first writer's journal is intact: it finishes.
    let mut w = w;
    write_cycles(&mut w, &p, None);
    for b in 0..p.map.grid.blocks() {
        Sink::write_block(&mut w, &block(&p, 0, b)).unwrap();
    }
    w.finish().unwrap();
    assert!(!lock_path(&out).exists());
}

#[test]
fn a_comment_edit_does_not_block_resume() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.h5");
    let p = plan();
    let mut w = ScanWriter::create(&out, &p, None, &prov(), false).unwrap();
    w.write_block(&block(&p, 0, 0)).unwrap();
    drop(w);
    let edited = Plan::from_toml(&format!("# rerun on the cluster\n{SPEC}"), "t.toml").unwrap();
    let mut w = ScanWriter::resume(&out, &edited, None, &prov()).unwrap();
    assert!(w.is_done(0, 0));
    // The file records the spec the scan started with.
    assert_eq!(w.plan().spec_text, SPEC);
    write_cycles(&mut w, &p, None);
    for b in 1..p.map.grid.blocks() {
        w.write_block(&block(&p, 0, b)).unwrap();
    }
    w.finish().unwrap();
    assert_eq!(
        output_state(&out, &edited, None).unwrap(),
        OutputState::Complete
    );
    let other = Plan::from_toml(&SPEC.replace("nu = 1e-3", "nu = 2e-3"), "t.toml").unwrap();
    assert_eq!(
        output_state(&out, &other, None).unwrap(),
        OutputState::Different("maps".into())
    );
    assert_eq!(
        output_state(&out, &p, Some(Shard { k: 1, n: 2 })).unwrap(),
        OutputState::Different("shard".into())
    );
}

#[test]
fn merge_refuses_to_write_over_an_input() {
    let dir = tempfile::tempdir().unwrap();
    let p = plan();
    let shards: Vec<PathBuf> = (1..=2)
        .map(|k| {
            let path = dir.path().join(format!("s{k}.h5"));
            full_run(&p, &path, Some(Shard { k, n: 2 }));
            path
        })
        .collect();
    let before = std::fs::read(&shards[0]).unwrap();
    // The same file by another spelling.
    let alias = dir.path().join(".").join("s1.h5");
    let e = merge(&shards, &alias, true, &prov()).unwrap_err();
    assert!(matches!(e, StoreError::OutputIsInput { .. }), "{e}");
    assert_eq!(std::fs::read(&shards[0]).unwrap(), before);
}

#[test]
fn variables_carry_cf_attributes_and_no_dimensions_string() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.h5");
    full_run(&plan(), &out, None);
    let f = hdf5::File::open(&out).unwrap();
    for col in squeal_scan::COLUMNS {
        let ds = f.dataset(col.name).unwrap();
        let names = ds.attr_names().unwrap();
        assert!(names.iter().any(|n| n == "long_name"), "{}", col.name);
        assert!(!names.iter().any(|n| n == "dimensions"), "{}", col.name);
        if col.kind == squeal_scan::column::Kind::Enum {
            assert!(names.iter().any(|n| n == "flag_values"), "{}", col.name);
            let m = read::str_attr(&ds, "flag_meanings").unwrap();
            assert_eq!(m.split(' ').count(), col.flags.len(), "{}", col.name);
        } else {
            assert!(names.iter().any(|n| n == "units"), "{}", col.name);
        }
    }
    let reason = f.dataset("reason").unwrap();
    let m = read::str_attr(&reason, "flag_meanings").unwrap();
    assert!(m.starts_with("time_limit near_fixed_point"), "{m}");
    let t = f.dataset("t_decision").unwrap();
    assert_eq!(read::str_attr(&t, "units").unwrap(), "1");
    // The cycle group: scalars flattened, record kept.
    let g = f.group("cycle").unwrap();
    assert_eq!(
        g.attr("params_nu").unwrap().read_scalar::<f64>().unwrap(),
        1e-3
    );
    assert!(read::str_attr(&g, "record").unwrap().contains("r_section"));
    let wrong: Vec<i64> = f.dataset("wrong_side_cells").unwrap().read_raw().unwrap();
    assert_eq!(wrong.len(), 1);
}

#[test]
fn a_plan_the_file_cannot_hold_is_refused_before_any_computing() {
    // Validation refuses a NUL in `name`; a plan built in code can still carry one, and
    // the writer must refuse it at create, not at finish (when the blocks are computed).
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.h5");
    let mut p = plan();
    p.name = "a\0b".into();
    let e = ScanWriter::create(&out, &p, None, &prov(), false).unwrap_err();
    assert!(e.to_string().contains("a.h5"), "{e}");
    assert!(!journal_of(&out).exists());
    assert!(!lock_path(&out).exists());
}

/// Shards whose stored spec reads back to another grid than their cells (one more x0
/// column: the same blocks, so `blocks_done` agrees) are refused, naming both shapes; their
/// rows read against the spec's grid would have been laid out wrong.
#[test]
fn shards_whose_spec_gives_another_grid_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = plan();
    let other = SPEC.replace("count = 5", "count = 6");
    let shards: Vec<PathBuf> = (1..=2)
        .map(|k| {
            let path = dir.path().join(format!("s{k}.h5"));
            full_run(&p, &path, Some(Shard { k, n: 2 }));
            let f = hdf5::File::open_rw(&path).unwrap();
            f.delete_attr("spec").unwrap();
            let v: hdf5::types::VarLenUnicode = other.parse().unwrap();
            f.new_attr::<hdf5::types::VarLenUnicode>()
                .create("spec")
                .unwrap()
                .write_scalar(&v)
                .unwrap();
            path
        })
        .collect();
    let e = merge(&shards, &dir.path().join("m.h5"), false, &prov()).unwrap_err();
    // The cells are 7 rows (v0) of 5 (x0); the stored spec says 7 of 6.
    assert!(
        e.to_string().contains("[7, 5]") && e.to_string().contains("[7, 6]"),
        "{e}"
    );
}

/// Python's `scan` and `atlas` write through the writers: an output not ending in `.h5` was
/// accepted there (only the CLI refused it). Refused by the store, for every door.
#[test]
fn an_output_not_ending_in_h5_is_refused_by_the_writers() {
    let dir = tempfile::tempdir().unwrap();
    let p = plan();
    let out = dir.path().join("x.txt");
    let e = ScanWriter::create(&out, &p, None, &prov(), false).unwrap_err();
    assert!(matches!(e, StoreError::NotH5 { .. }), "{e}");
    assert!(
        e.to_string()
            .ends_with("x.txt: expected a file name ending in .h5"),
        "{e}"
    );
    assert!(!lock_path(&out).exists() && !journal_path(&out).exists());
}

#[cfg(test)]
mod chunks;
#[cfg(test)]
mod journal_fuzz;
#[cfg(test)]
mod journal_resume;

/// The store must not run the model (`landscape::of_map`) while writing: the landscape is
/// computed by the caller and only stored: a Stribeck scan finished without it is refused,
/// and what the caller gives is what the file holds (the damping 0.125 and period 7.5 below
/// are made up; no run of the model gives them at these parameters).
#[test]
fn the_landscape_is_given_to_the_writer_not_computed_by_it() {
    let spec = SPEC.replace(
        "law = \"mcmillan\"\nnu = 1e-3",
        "law = \"stribeck\"\nv_d = 1.5",
    );
    let plan = Plan::from_toml(&spec, "t.toml").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let run = |out: &Path| {
        let mut w = ScanWriter::create(out, &plan, None, &prov(), false).unwrap();
        w.write_cycle(0, Some(&Ok(cycle()))).unwrap();
        for b in 0..plan.map.grid.blocks() {
            w.write_block(&block(&plan, 0, b)).unwrap();
        }
        w
    };
    let out = dir.path().join("refused.h5");
    assert!(matches!(
        run(&out).finish(),
        Err(StoreError::Landscape { .. })
    ));
    let given = squeal_core::LandscapeEvidence {
        landscape: squeal_core::Landscape::Bistable,
        damping: 0.125,
        cycle: squeal_core::landscape::StickCycle::Exists {
            period: 7.5,
            stuck: 1.0,
        },
    };
    let out = dir.path().join("given.h5");
    run(&out).finish_with(&[Some(given)]).unwrap();
    let info = read_info(&out).unwrap();
    let l = info.landscapes[0].as_ref().expect("a landscape is stored");
    assert_eq!(l.landscape, squeal_core::Landscape::Bistable);
    let value = |name: &str| l.evidence.iter().find(|(n, _)| *n == name).unwrap().1;
    assert_eq!(value("fixed_point_damping"), 0.125);
    assert_eq!(value("stick_cycle_period"), 7.5);
}
