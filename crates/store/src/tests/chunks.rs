//! Blocks written as whole chunks compressed on the workers (`crate::chunks`) give the file
//! that writing them as selections through HDF5's own deflate gives: every dataset and
//! attribute the same ([`crate::content_digest`], which reads the values back through HDF5,
//! whatever the bytes of the chunks), for one map, a sweep, a physical scan (SI twins) and
//! a last block shorter than its chunk.

use super::*;
use crate::content_digest;

/// A brake-like physical sweep (scans/brake.toml's system, c swept), 5 x 7 in blocks of 2
/// rows: the last block is one row of a 2-row chunk.
fn physical_plan() -> Plan {
    let spec = "version = 1\n[model]\nlaw = \"mcmillan\"\n[physical]\nm = 2.0\nk = 5.0e4\n\
                c = [0.5, 4.0]\nv_belt = 0.05\nmu_k = 0.35\nmu_s = 0.45\ntau = 1e-3\n\
                [grid]\nx0 = { min = -3.0, max = 5.0, count = 5 }\n\
                v0 = { min = -4.0, max = 4.0, count = 7 }\nblock_rows = 2\n\
                [output]\npath = \"t.h5\"\n";
    Plan::from_toml(spec, "t.toml").unwrap()
}

/// Writes every block of `plan` and starts the file at `out`.
fn assembly(plan: &Plan, out: &Path) -> Assembly {
    let mut w = ScanWriter::create(out, plan, None, &prov(), false).unwrap();
    write_cycles(&mut w, plan, None);
    for m in 0..plan.maps.len() {
        for b in 0..plan.map.grid.blocks() {
            w.write_block(&block(plan, m, b)).unwrap();
        }
    }
    w.finishing(&[]).unwrap()
}

#[test]
fn whole_chunks_read_back_as_the_selections_write_them() {
    let dir = tempfile::tempdir().unwrap();
    for (name, plan) in [
        ("one", plan()),
        ("sweep", sweep_plan()),
        ("physical", physical_plan()),
    ] {
        let (a, b) = (
            dir.path().join(format!("{name}-chunks.h5")),
            dir.path().join(format!("{name}-slices.h5")),
        );
        let chunks = assembly(&plan, &a);
        assert!(chunks.writes_whole_chunks(), "{name}");
        let checks_a = squeal_scan::finish::finish(chunks).unwrap();
        let slices = assembly(&plan, &b).by_selections();
        assert!(!slices.writes_whole_chunks(), "{name}");
        let checks_b = squeal_scan::finish::finish(slices).unwrap();
        assert_eq!(checks_a, checks_b, "{name}");
        let (da, db) = (content_digest(&a).unwrap(), content_digest(&b).unwrap());
        assert_eq!(da, db, "{name}: the files differ");
        // The cells read back are the cells written, the padded last row included.
        let g = &plan.map.grid;
        let last = g.blocks() - 1;
        let m = plan.maps.len() - 1;
        let want = block(&plan, m, last).cells;
        let map = read_map(&a, m).unwrap();
        let nx = g.x0.count;
        let start = g.block_rows(last).start * nx;
        assert_eq!(map.labels[start..].len(), want.len(), "{name}");
        for (k, c) in want.iter().enumerate() {
            assert_eq!(map.labels[start + k], c.regime, "{name} cell {k}");
        }
    }
}

/// A value that is no member of its enum is refused by the chunk writer as by the typed
/// write, naming the column.
#[test]
fn whole_chunks_refuse_a_label_outside_the_enum() {
    let dir = tempfile::tempdir().unwrap();
    let plan = plan();
    let out = dir.path().join("bad.h5");
    let mut w = ScanWriter::create(&out, &plan, None, &prov(), false).unwrap();
    write_cycles(&mut w, &plan, None);
    for b in 0..plan.map.grid.blocks() {
        let mut blk = block(&plan, 0, b);
        if b == 1 {
            blk.cells[0].regime = 7;
        }
        w.write_block(&blk).unwrap();
    }
    let f = w.finishing(&[]).unwrap();
    assert!(f.writes_whole_chunks());
    let e = squeal_scan::finish::finish(f).unwrap_err().to_string();
    assert!(e.contains("labels: unknown value 7"), "{e}");
    assert!(!out.exists() && !tmp_path(&out).exists(), "{e}");
}
