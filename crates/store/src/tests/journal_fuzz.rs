//! A damaged journal loses only its damaged records, says so, and lets nothing corrupt
//! through: corrupt records in the middle of scan and atlas journals, a corrupt header,
//! and random byte flips and truncations (a seeded fuzz whose counts are printed).

use squeal_scan::atlas::AtlasPlan;
use squeal_scan::atlas::columns::{BOUNDARY_COLUMNS, empty_boundary, empty_point};
use squeal_scan::atlas::{LineResult, UnitResult};

use super::{Finish, block, cycle, journal_of, plan, prov};
use crate::atlas::AtlasWriter;
use crate::journal::{self, Journal, KIND_BLOCK, Owner, Rec};
use crate::{ScanWriter, StoreError};

/// Offsets of the whole frames (`SQJR` to checksum) of an undamaged journal, header first:
/// `SQJR`, kind, u32 length, payload, 8-byte checksum.
fn frames(path: &std::path::Path) -> Vec<(usize, usize)> {
    let b = std::fs::read(path).unwrap();
    let mut out = Vec::new();
    let mut at = 0;
    while at + 9 <= b.len() {
        let len = u32::from_le_bytes(b[at + 5..at + 9].try_into().unwrap()) as usize;
        out.push((at, at + 9 + len + 8));
        at += 9 + len + 8;
    }
    out
}

fn flip(path: &std::path::Path, at: usize) {
    let mut bytes = std::fs::read(path).unwrap();
    bytes[at] ^= 0x10;
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn a_corrupt_block_in_the_middle_loses_only_itself() {
    let dir = tempfile::tempdir().unwrap();
    let p = plan();
    let out = dir.path().join("r.h5");
    let mut w = ScanWriter::create(&out, &p, None, &prov(), false).unwrap();
    w.write_cycle(0, Some(&Ok(cycle()))).unwrap();
    for b in 0..3 {
        w.write_block(&block(&p, 0, b)).unwrap();
    }
    drop(w);
    // Frames: header, cycle, blocks 0, 1, 2. A flipped byte in block 1's payload.
    let f = frames(&journal_of(&out));
    flip(&journal_of(&out), f[3].0 + 30);
    let w = ScanWriter::resume(&out, &p, None, &prov()).unwrap();
    // Before: reading stopped at block 1, so block 2 was dropped as well.
    assert!(w.is_done(0, 0) && !w.is_done(0, 1) && w.is_done(0, 2));
    assert!(w.has_cycle(0));
}

#[test]
fn a_corrupt_cycle_record_keeps_the_blocks_after_it() {
    let dir = tempfile::tempdir().unwrap();
    let p = plan();
    let out = dir.path().join("c.h5");
    let mut w = ScanWriter::create(&out, &p, None, &prov(), false).unwrap();
    w.write_cycle(0, Some(&Ok(cycle()))).unwrap();
    for b in 0..p.map.grid.blocks() {
        w.write_block(&block(&p, 0, b)).unwrap();
    }
    drop(w);
    let f = frames(&journal_of(&out));
    flip(&journal_of(&out), f[1].0 + 40);
    let mut w = ScanWriter::resume(&out, &p, None, &prov()).unwrap();
    // Before: every block after the cycle record was discarded.
    assert_eq!(w.done_blocks(), p.map.grid.blocks());
    assert!(!w.has_cycle(0));
    // The cycle is searched again and the file is the one a clean run writes.
    w.write_cycle(0, Some(&Ok(cycle()))).unwrap();
    w.finish().unwrap();
    let clean = dir.path().join("clean.h5");
    super::full_run(&p, &clean, None);
    assert_eq!(
        crate::content_digest(&out).unwrap(),
        crate::content_digest(&clean).unwrap()
    );
}

#[test]
fn a_corrupt_header_says_what_is_not_kept() {
    let dir = tempfile::tempdir().unwrap();
    let p = plan();
    let out = dir.path().join("h.h5");
    let mut w = ScanWriter::create(&out, &p, None, &prov(), false).unwrap();
    w.write_block(&block(&p, 0, 0)).unwrap();
    drop(w);
    flip(&journal_of(&out), 20);
    let e = ScanWriter::resume(&out, &p, None, &prov()).unwrap_err();
    let msg = e.to_string();
    assert!(
        matches!(
            e,
            StoreError::NotSquealFile {
                advice: Some(crate::Advice::StartOver),
                ..
            }
        ),
        "{msg}"
    );
    assert!(
        msg.contains("header record is corrupt") && msg.contains("1 intact later record"),
        "{msg}"
    );
}

const ATLAS: &str = r#"version = 1
[model]
law = "mcmillan"
nu = [1e-3, 2e-3]
[output]
path = "a.h5"
"#;

/// A flipped digit: `fold_nu` = 0.0202 with one digit changed was once accepted by `--resume`
/// from the JSON-lines journal and landed in the file as 9.0202.
#[test]
fn a_flipped_digit_in_an_atlas_record_is_detected() {
    let dir = tempfile::tempdir().unwrap();
    let plan = AtlasPlan::from_toml(ATLAS, "a.toml").unwrap();
    assert_eq!((plan.n_boundaries(), plan.units().len()), (1, 2));
    let out = dir.path().join("a.h5");
    let mut w = AtlasWriter::create(&out, &plan, None, &prov(), false).unwrap();
    let mut b = empty_boundary(0);
    let fold = BOUNDARY_COLUMNS
        .iter()
        .find(|c| c.name == "fold_nu")
        .unwrap();
    fold.set_value(&mut b, 0.0202);
    w.record(UnitResult::Boundary(b)).unwrap();
    w.record(UnitResult::Line(LineResult {
        line: 0,
        points: vec![empty_point(), empty_point()],
    }))
    .unwrap();
    drop(w);
    let j = journal_of(&out);
    let mut bytes = std::fs::read(&j).unwrap();
    let at = bytes.windows(6).position(|s| s == b"0.0202").unwrap();
    bytes[at] = b'9';
    std::fs::write(&j, bytes).unwrap();
    let w = AtlasWriter::resume(&out, &plan, None, &prov()).unwrap();
    // The damaged boundary is to be computed again; the line after it is kept.
    assert!(w.results.boundaries[0].is_none());
    assert!(w.results.points.iter().all(Option::is_some));
}

/// An atlas resumes by the scan's rule: a comment edit does not block it (it did: the
/// texts were compared) and the file records the spec it started with; another spec is
/// refused naming the key that differs.
#[test]
fn a_comment_edit_does_not_block_an_atlas_resume() {
    let dir = tempfile::tempdir().unwrap();
    let plan = AtlasPlan::from_toml(ATLAS, "a.toml").unwrap();
    let out = dir.path().join("a.h5");
    drop(AtlasWriter::create(&out, &plan, None, &prov(), false).unwrap());
    let other = AtlasPlan::from_toml(&ATLAS.replace("2e-3", "3e-3"), "a.toml").unwrap();
    let Err(e) = AtlasWriter::resume(&out, &other, None, &prov()) else {
        panic!("another spec resumed");
    };
    assert!(
        matches!(e, StoreError::SpecMismatch { .. }) && e.to_string().contains("params differs"),
        "{e}"
    );
    let edited = AtlasPlan::from_toml(&format!("# requeued\n{ATLAS}"), "a.toml").unwrap();
    let w = AtlasWriter::resume(&out, &edited, None, &prov()).unwrap();
    assert_eq!(w.missing().len(), plan.units().len());
    drop(w);
    let w = AtlasWriter::resume(&out, &edited, None, &prov()).unwrap();
    assert_eq!(w.plan().spec_text, ATLAS);
}

#[test]
fn a_scan_does_not_resume_from_an_atlas_journal() {
    let dir = tempfile::tempdir().unwrap();
    let plan = AtlasPlan::from_toml(ATLAS, "a.toml").unwrap();
    let out = dir.path().join("x.h5");
    drop(AtlasWriter::create(&out, &plan, None, &prov(), false).unwrap());
    let e = ScanWriter::resume(&out, &super::plan(), None, &prov()).unwrap_err();
    assert!(
        e.to_string().contains("an atlas's journal, not a scan's"),
        "{e}"
    );
}

/// SplitMix64 (Steele, Lea and Flood 2014): a seeded stream, so every case can be rerun.
struct Mix(u64);
impl Mix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// A journal as written: its records with their payloads, and its bytes.
type Base = (Vec<(Rec, Vec<u8>)>, Vec<u8>);

/// Counts of the fuzz.
#[derive(Debug, Default)]
struct Counts {
    cases: usize,
    records_damaged: usize,
    records_kept: usize,
    dropped_silently: usize,
    cut_whole: usize,
    intact_lost: usize,
    corrupt_through: usize,
    warned: usize,
}

/// A journal of 12 records of random sizes written through the writer, as read back.
fn write_base(path: &std::path::Path, k: usize, rng: &mut Mix) -> Base {
    let _ = std::fs::remove_file(path);
    let header = journal::Header {
        owner: Owner::Scan,
        spec: format!("spec {k}"),
        shard: String::new(),
        table: None,
    };
    let mut j = Journal::create(path, &header).unwrap();
    let mut written = Vec::new();
    for _ in 0..12 {
        let len = rng.below(300);
        // Payloads that hold the frame's magic make resynchronisation harder.
        let payload: Vec<u8> = (0..len)
            .map(|i| {
                if i % 50 < 4 {
                    b"SQJR"[i % 50]
                } else {
                    rng.next() as u8
                }
            })
            .collect();
        written.push((j.append(KIND_BLOCK, &payload).unwrap(), payload));
    }
    drop(j);
    (written, std::fs::read(path).unwrap())
}

/// `bytes` after the header with one to three bits flipped and, one time in three, cut
/// short; returns the flipped positions.
fn damage(bytes: &mut Vec<u8>, header_end: usize, rng: &mut Mix) -> Vec<usize> {
    let mut hit = Vec::new();
    for _ in 0..1 + rng.below(3) {
        // Damage after the header (a damaged header is refused, tested above).
        let at = header_end + rng.below(bytes.len() - header_end);
        bytes[at] ^= 1 << rng.below(8);
        hit.push(at);
    }
    if rng.below(3) == 0 {
        bytes.truncate(header_end + rng.below(bytes.len() - header_end));
    }
    hit
}

/// The whole frame of a record: from `SQJR` to the end of its checksum.
fn frame(r: &Rec) -> (usize, usize) {
    (
        r.offset as usize - 9,
        r.offset as usize + r.len as usize + 8,
    )
}

/// Counts what a reading of the damaged `bytes` did with each record `written`.
fn tally(
    n: &mut Counts,
    written: &[(Rec, Vec<u8>)],
    bytes: &[u8],
    hit: &[usize],
    read: &[Rec],
    warned: bool,
) {
    n.cases += 1;
    n.warned += warned as usize;
    for (r, _) in written {
        let (a, b) = frame(r);
        if a >= bytes.len() {
            // Cut off whole at a frame boundary: the file reads as one whose run stopped
            // before this record (as after a kill), nothing to warn about.
            n.cut_whole += 1;
            continue;
        }
        let intact = b <= bytes.len() && !hit.iter().any(|&h| (a..b).contains(&h));
        let back = read.iter().any(|x| x.offset == r.offset && x.len == r.len);
        n.records_damaged += !intact as usize;
        match (intact, back) {
            (true, false) => n.intact_lost += 1,
            (false, false) if !warned => n.dropped_silently += 1,
            (_, true) => n.records_kept += 1,
            _ => {}
        }
    }
    // Everything read back is a record as written, byte for byte.
    for x in read {
        let (a, b) = frame(x);
        let same = written
            .iter()
            .any(|(r, p)| r.offset == x.offset && *p == bytes[x.offset as usize..b - 8]);
        if !same || hit.iter().any(|&h| (a..b).contains(&h)) {
            n.corrupt_through += 1;
        }
    }
}

/// Random byte flips and truncations of journals of 12 records of random sizes: every
/// record left intact is read back, every record read back is one that was written, and a
/// record that is lost comes with a warning.
#[test]
fn fuzzed_journals_lose_only_damaged_records_and_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("f.journal");
    let mut rng = Mix(19);
    let mut n = Counts::default();
    // Twenty journals (each append is fsynced, so they are written once), each damaged in
    // 75 ways.
    let bases: Vec<Base> = (0..20).map(|k| write_base(&path, k, &mut rng)).collect();
    for case in 0..1500 {
        let (written, base) = &bases[case % bases.len()];
        let mut bytes = base.clone();
        let header_end = written[0].0.offset as usize - 9;
        let hit = damage(&mut bytes, header_end, &mut rng);
        std::fs::write(&path, &bytes).unwrap();
        let (_, _, read, skipped) = Journal::open_counted(&path, Owner::Scan).unwrap();
        let warned = skipped.warning(&path).is_some();
        tally(&mut n, written, &bytes, &hit, &read, warned);
        // The file is cut after the last good record: appends continue from a clean end.
        let end = read.last().map_or(header_end, |r| frame(r).1);
        let len = std::fs::metadata(&path).unwrap().len() as usize;
        assert_eq!(len, end, "case {case}");
    }
    eprintln!("journal fuzz: {n:?}");
    let failures = (n.intact_lost, n.dropped_silently, n.corrupt_through);
    assert_eq!(failures, (0, 0, 0), "{n:?}");
    assert!(
        n.records_damaged > 1000 && n.warned > 1000,
        "the fuzz damages records: {n:?}"
    );
}
