//! The scan journal across a resume: what survives it (the file's start time, withdrawn
//! rules), what it refuses by name (an older format, other columns, a changed friction
//! table) and what it counts (damaged trailing records).

use super::*;

/// `t_squeal` (a finite time, 0, inf for stick-slip, -1 unknown) of blocks written before an
/// interruption comes back from the journal into the finished file unchanged, beside the
/// blocks written after the resume. (Before the column existed a cell had no `t_squeal`.)
#[test]
fn t_squeal_survives_a_journal_resume() {
    let dir = tempfile::tempdir().unwrap();
    let p = plan();
    let out = dir.path().join("t.h5");
    let mut w = ScanWriter::create(&out, &p, None, &prov(), false).unwrap();
    w.write_block(&block(&p, 0, 0)).unwrap();
    w.write_block(&block(&p, 0, 1)).unwrap();
    drop(w);
    let mut w = ScanWriter::resume(&out, &p, None, &prov()).unwrap();
    assert!(w.is_done(0, 1) && !w.is_done(0, 2));
    for b in 2..p.map.grid.blocks() {
        w.write_block(&block(&p, 0, b)).unwrap();
    }
    w.finish().unwrap();
    let want: Vec<f64> = (0..p.map.grid.blocks())
        .flat_map(|b| block(&p, 0, b).cells.into_iter().map(|c| c.t_squeal))
        .collect();
    assert!(want.iter().any(|t| t.is_infinite()) && want.contains(&-1.0));
    let f = hdf5::File::open(&out).unwrap();
    let ds = f.dataset("t_squeal").unwrap();
    assert_eq!(read::str_attr(&ds, "units").unwrap(), "1");
    let got: Vec<f64> = ds.read_raw().unwrap();
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(&want) {
        assert!(g == w, "{g} != {w}");
    }
}

/// A journal of format 2 (cells without `t_squeal`, another record width) is refused on
/// resume with words that say why, instead of "unknown journal format".
#[test]
fn an_older_journal_format_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let p = plan();
    let out = dir.path().join("o.h5");
    drop(ScanWriter::create(&out, &p, None, &prov(), false).unwrap());
    let j = journal_of(&out);
    let mut bytes = std::fs::read(&j).unwrap();
    // The header record: "SQJR", kind, len (u32), payload (format u32 first), checksum.
    let len = u32::from_le_bytes(bytes[5..9].try_into().unwrap()) as usize;
    bytes[9..13].copy_from_slice(&2u32.to_le_bytes());
    let sum = crate::journal::record_sum(bytes[4], &bytes[9..9 + len]);
    bytes[9 + len..17 + len].copy_from_slice(&sum.to_le_bytes());
    std::fs::write(&j, &bytes).unwrap();
    let e = ScanWriter::resume(&out, &p, None, &prov()).unwrap_err();
    assert!(e.to_string().contains("journal format 2"), "{e}");
    assert!(e.to_string().contains("older squeal"), "{e}");
}

/// A journal whose header names other columns (written by a build that stored another
/// column list, for instance one column more of the same width elsewhere) is refused on
/// resume with words that say why, instead of its records being read into the wrong
/// columns or refused as "a malformed block record".
#[test]
fn a_journal_of_other_columns_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let p = plan();
    let out = dir.path().join("o.h5");
    drop(ScanWriter::create(&out, &p, None, &prov(), false).unwrap());
    let j = journal_of(&out);
    let mut bytes = std::fs::read(&j).unwrap();
    // The header record: "SQJR", kind, len (u32), payload (the columns' checksum, then the
    // friction table's rows: an empty string, its length u64 0, for this law), checksum.
    // One flipped bit of the columns' checksum stands for another column list.
    let len = u32::from_le_bytes(bytes[5..9].try_into().unwrap()) as usize;
    bytes[9 + len - 16] ^= 1;
    let sum = crate::journal::record_sum(bytes[4], &bytes[9..9 + len]);
    bytes[9 + len..17 + len].copy_from_slice(&sum.to_le_bytes());
    std::fs::write(&j, &bytes).unwrap();
    let e = ScanWriter::resume(&out, &p, None, &prov()).unwrap_err();
    assert!(e.to_string().contains("other columns"), "{e}");
    assert!(
        matches!(
            e,
            StoreError::NotSquealFile {
                advice: Some(crate::Advice::OtherVersionOrStartOver),
                ..
            }
        ),
        "{e}"
    );
}

/// Six damaged records at the journal's end were reported as "a torn last record"; the
/// warning counts them.
#[test]
fn damaged_trailing_records_are_counted() {
    let dir = tempfile::tempdir().unwrap();
    let p = sweep_plan();
    let out = dir.path().join("d.h5");
    let mut w = ScanWriter::create(&out, &p, None, &prov(), false).unwrap();
    let mut written = 0;
    'all: for m in 0..p.maps.len() {
        for b in 0..p.map.grid.blocks() {
            w.write_block(&block(&p, m, b)).unwrap();
            written += 1;
            if written == 6 {
                break 'all;
            }
        }
    }
    drop(w);
    let j = journal_of(&out);
    let mut bytes = std::fs::read(&j).unwrap();
    let starts: Vec<usize> = (0..bytes.len())
        .filter(|&i| bytes[i..].starts_with(b"SQJR"))
        .collect();
    assert_eq!(starts.len(), 7, "the header and six blocks");
    // One byte of each block's payload flipped (past the 9-byte frame head).
    for &s in &starts[1..] {
        bytes[s + 20] ^= 0xff;
    }
    std::fs::write(&j, &bytes).unwrap();
    let (_, _, recs, damage) = journal::Journal::open_counted(&j, journal::Owner::Scan).unwrap();
    assert!(recs.is_empty());
    assert_eq!(damage.tail_records, 6);
    let w = damage.warning(&j).unwrap();
    assert!(w.contains("6 damaged records"), "{w}");
    assert!(!w.contains("torn last record"), "{w}");
}

/// Rule groups withdrawn from a map (journal record `W`) survive a resume, a
/// block stored again replaces the one before, and the file says which groups and why
/// (root attribute `rules_withdrawn`, one line per group).
#[test]
fn withdrawn_rules_survive_a_resume_and_reach_the_file() {
    use squeal_scan::census::Rules;
    use squeal_scan::scanner::Withdrawn;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("w.h5");
    let p = plan();
    let w = Withdrawn {
        rules: Rules::Outside,
        why: "start_outside_cycle+outside_cycle withdrawn: because".into(),
    };
    {
        let mut s = ScanWriter::create(&out, &p, None, &prov(), false).unwrap();
        write_cycles(&mut s, &p, None);
        for b in 0..p.map.grid.blocks() {
            s.write_block(&block(&p, 0, b)).unwrap();
        }
        Sink::write_withdrawn(&mut s, 0, std::slice::from_ref(&w)).unwrap();
        // A block redone: stored again, with every label steady slip.
        let mut again = block(&p, 0, 1);
        for c in &mut again.cells {
            c.regime = 1;
        }
        s.write_block(&again).unwrap();
    }
    let mut s = ScanWriter::resume(&out, &p, None, &prov()).unwrap();
    assert_eq!(Sink::withdrawn(&mut s, 0).unwrap(), vec![w.clone()]);
    let cells = Sink::stored_block(&mut s, 0, 1).unwrap().unwrap();
    assert!(cells.iter().all(|c| c.regime == 1));
    assert_eq!(s.withdrawn_lines(), vec![(0, w.why.clone())]);
    s.finish().unwrap();
    let info = read_info(&out).unwrap();
    let attr = info
        .attrs
        .iter()
        .find(|(k, _)| k == "rules_withdrawn")
        .map(|(_, v)| v.clone());
    assert_eq!(attr, Some(format!("map 0: {}", w.why)));
}

/// A journal records the rows of the friction table its spec stood on, not only
/// the CSV's name in the spec text. A CSV changed since the run started is refused at the
/// resume, naming `friction_csv` (before, the same spec text resumed, and the file would
/// have mixed cells of two curves); unchanged, it resumes. Both where the curve is the
/// model's (`[model]`) and where it is the physical system's, in m/s (`[physical]`).
#[test]
fn a_journal_refuses_a_friction_csv_changed_since_it_started() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("pad.csv");
    let model = "law = \"table\"\nxi = 0.05\nv_d = 1.5\nfriction_csv = \"pad.csv\"\n";
    let physical = "law = \"table\"\n[physical]\nm = 0.8\nk = 2e5\nc = 20.0\nv_belt = 0.3\n\
                    normal_force = 1500.0\nfriction_csv = \"pad.csv\"\n";
    for (i, (model, grid)) in [(model, "1.0"), (physical, "0.003")]
        .into_iter()
        .enumerate()
    {
        std::fs::write(&csv, "s,mu\n0,0.6\n0.5,0.45\n2,0.4\n").unwrap();
        let spec = format!(
            "version = 1\n[model]\n{model}[grid]\nx0 = {{ min = 0.0, max = {grid}, count = 3 }}\n\
             v0 = {{ min = 0.0, max = {grid}, count = 2 }}\n[output]\npath = \"t.h5\"\n"
        );
        let path = dir.path().join("t.toml").display().to_string();
        let p = Plan::from_toml(&spec, &path).unwrap();
        let out = dir.path().join(format!("t{i}.h5"));
        drop(ScanWriter::create(&out, &p, None, &prov(), false).unwrap());
        // Unchanged: the resume goes on.
        let same = Plan::from_toml(&spec, &path).unwrap();
        drop(ScanWriter::resume(&out, &same, None, &prov()).unwrap());
        std::fs::write(&csv, "s,mu\n0,0.6\n0.5,0.44\n2,0.4\n").unwrap();
        let changed = Plan::from_toml(&spec, &path).unwrap();
        let e = ScanWriter::resume(&out, &changed, None, &prov()).unwrap_err();
        assert!(
            matches!(e, StoreError::SpecMismatch { .. }) && e.to_string().contains("friction_csv"),
            "{e}"
        );
    }
}

/// Every column of `a` and `b`, bit for bit (NaN's bits included).
fn same_cells(a: &[Cell], b: &[Cell]) -> bool {
    let bits = |v: squeal_scan::column::Num| match v {
        squeal_scan::column::Num::U(u) => u,
        squeal_scan::column::Num::F(f) => f.to_bits(),
    };
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            squeal_scan::cell::COLUMNS
                .iter()
                .all(|c| bits((c.get)(x)) == bits((c.get)(y)))
        })
}

/// Journal format 6: a block's record holds its cells column by column,
/// deflated. They come back bit for bit (NaN, infinities, every column), from a deflated
/// body and from one stored as it is; a body that inflates to one byte more or less than
/// its cells', or an unknown body kind, is refused; and a block whose cells are alike (a
/// map decided at its start) takes a few percent of its cells' bytes. Before format 6 a
/// record was its 24 bytes of head and `n * cell_bytes()` bytes, always.
#[test]
fn a_block_record_holds_its_cells_deflated_column_by_column() {
    use squeal_scan::cell::cell_bytes;
    use std::io::Read;
    let p = plan();
    let b = block(&p, 0, 1);
    let payload = journal::encode_block(b.map, b.block, &b.cells);
    let (m, k, cells) = journal::decode_block(&payload).unwrap();
    assert_eq!((m, k), (0, 1));
    assert!(same_cells(&cells, &b.cells));
    assert!(cells.iter().any(|c| c.amplitude.is_nan()));
    // The same cells with the body as it is (kind 0).
    let head = &payload[..24];
    assert_eq!(payload[24], 1, "a deflated body");
    let mut raw = Vec::new();
    flate2::read::DeflateDecoder::new(&payload[25..])
        .read_to_end(&mut raw)
        .unwrap();
    assert_eq!(raw.len(), b.cells.len() * cell_bytes());
    let plain = [head, &[0u8], &raw].concat();
    assert!(same_cells(
        &journal::decode_block(&plain).unwrap().2,
        &b.cells
    ));
    // A body one byte short or long, or of an unknown kind, is malformed.
    for bad in [
        [head, &[0u8], &raw[1..]].concat(),
        [head, &[0u8], &raw, &[0u8]].concat(),
        [head, &[2u8], &raw].concat(),
    ] {
        assert!(journal::decode_block(&bad).is_none());
    }
    // A deflated body one cell short.
    let short = journal::encode_block(0, 1, &b.cells[1..]);
    let lying = [head, &short[24..]].concat();
    assert!(journal::decode_block(&lying).is_none());
    // A block of alike cells: 4096 of them in under 2% of their bytes.
    let alike = vec![b.cells[0]; 4096];
    let small = journal::encode_block(0, 0, &alike);
    assert!(
        small.len() * 50 < alike.len() * cell_bytes(),
        "{}",
        small.len()
    );
    assert!(same_cells(
        &journal::decode_block(&small).unwrap().2,
        &alike
    ));
}

/// A journal changed on disk by another process while a run writes it (a block record's
/// bytes overwritten, or the journal cut short) is named as the run's journal that
/// changed, not as "not a squeal file" (and a changed record whose bytes still decode is
/// not written into the file as if it were the run's).
#[test]
fn a_journal_changed_under_a_live_run_is_named_as_changed() {
    for cut in [false, true] {
        let dir = tempfile::tempdir().unwrap();
        let p = plan();
        let out = dir.path().join("c.h5");
        let mut w = ScanWriter::create(&out, &p, None, &prov(), false).unwrap();
        for b in 0..p.map.grid.blocks() {
            w.write_block(&block(&p, 0, b)).unwrap();
        }
        let j = journal_of(&out);
        let mut bytes = std::fs::read(&j).unwrap();
        let n = bytes.len();
        if cut {
            bytes.truncate(n - 40);
        } else {
            // A byte inside the last block record's payload (its 8-byte checksum last).
            bytes[n - 20] ^= 0x55;
        }
        std::fs::write(&j, &bytes).unwrap();
        let e = w.finish().unwrap_err().to_string();
        assert!(
            e.contains(&j.display().to_string()) && e.contains("changed on disk while this run"),
            "cut {cut}: {e}"
        );
        assert!(!e.contains("not a squeal file"), "cut {cut}: {e}");
    }
}
