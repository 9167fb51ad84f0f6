//! The journal `<out>.journal` of a scan or an atlas: an append-only log of finished work.
//! Scans and atlases share this one framing, reader and writer.
//!
//! Every record is written to the file as it comes, so a killed process (a signal, `kill
//! -9`, a SLURM time limit, an out-of-memory kill) loses only the work in flight: the
//! kernel holds what was written. What a crash of the machine itself (power, kernel) can
//! lose is what was not yet synced to disk: block records are synced in groups
//! ([`SYNC_EVERY_BLOCKS`] blocks or [`SYNC_EVERY`], whichever comes first; one fsync per
//! 3 MB block cost the 4096 x 4096 map 22 of its 61 s of cells on the 2-core machine),
//! every other record (header, cycle, withdrawn rules, atlas unit) at once, and all at
//! the end of the run. So at most the blocks of the last [`SYNC_EVERY`] are lost, and
//! `--resume` computes them again.
//!
//! ```text
//! record  = "SQJR" kind:u8 len:u32 payload[len] sum(kind, payload):u64   (little endian;
//!           sum: `record_sum`, 8 bytes at a time)
//! header  = kind 'H' (scan) or 'A' (atlas): format:u32 spec:str shard:str columns:u64
//!           table:str (str = len:u64 bytes; columns = fnv1a64 of the stored columns'
//!           names and widths, `Owner::columns_checksum`; table = the rows of the friction
//!           table the spec's friction_table or friction_csv gave, `s,mu` lines, empty for
//!           other laws; a header of an earlier build ends before it)
//! block   = kind 'B': map:u64 block:u64 n:u64 body:u8 cells (the columns of
//!           squeal_scan::cell::COLUMNS in order, each the n cells' values at its storage
//!           width; body 1: deflated (raw deflate), 0: as they are); in an atlas `map` is
//!           the parameter point
//! cycle   = kind 'C': map:u64 record:str (the cycle search as TOML, see crate::cycle)
//! unit    = kind 'U' (atlas): a finished line of points or boundary search, as the JSON
//!           of crate::atlas::unit_json
//! ```
//! Reading checks every record's checksum. A corrupt or short record is skipped and the
//! reader resynchronises on the next record that checks out, so one damaged record loses
//! only itself; the skipped bytes are reported on stderr with the number of records kept
//! after them. Bytes after the last good record (a write torn by a kill) are cut off; a
//! damaged stretch between good records stays in the file (rewriting the journal could lose
//! it all to a crash), so each later resume skips it and warns again.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use squeal_scan::atlas::columns::{BOUNDARY_COLUMNS, COLUMNS as POINT_COLUMNS};
use squeal_scan::atlas::true_stick::LANDSCAPE_COLUMNS;
use squeal_scan::cell::{COLUMNS, Cell, cell_bytes};
use squeal_scan::column::{Kind, Num};

use crate::StoreError;
use crate::error::{Advice, io};

const MAGIC: &[u8; 4] = b"SQJR";
// 3: cells carry t_squeal (an older journal's records have another width). 4: the header
// carries the columns' checksum, so a new column needs no new format. 5: records are summed
// 8 bytes at a time (`record_sum`), not by FNV-1a a byte at a time. 6: a block's cells are
// stored column by column and deflated (`encode_block`).
const FORMAT: u32 = 6;
pub(crate) const KIND_HEADER: u8 = b'H';
pub(crate) const KIND_ATLAS_HEADER: u8 = b'A';
pub(crate) const KIND_UNIT: u8 = b'U';
pub(crate) const KIND_BLOCK: u8 = b'B';
pub(crate) const KIND_CYCLE: u8 = b'C';
/// Rule groups withdrawn from a map (its census or its audit refuted them).
pub(crate) const KIND_WITHDRAWN: u8 = b'W';
const FRAME: usize = 4 + 1 + 4;
/// Block records are synced to disk at least this often while they come.
pub(crate) const SYNC_EVERY: std::time::Duration = std::time::Duration::from_secs(2);
/// ... and at least every this many block records.
pub(crate) const SYNC_EVERY_BLOCKS: usize = 64;

/// FNV-1a, 64 bits.
pub(crate) fn fnv64(parts: &[&[u8]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in parts {
        for &b in *p {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

/// The checksum of a record: FNV-1a's basis and prime over the payload's 8-byte
/// little-endian words (the last one zero-padded; the kind and the length start the sum),
/// each product folded (`h ^= h >> 29`) so that the high bits of a word reach the low
/// bits of the sum. Each step is a bijection of the sum for a given word and of the word
/// for a given sum, so a change within any one word always changes the checksum. One
/// multiply per 8 bytes: FNV-1a a byte at a time (journal format 4) took 4% of the CPU of
/// a 4096 x 4096 scan, on the sink's one thread.
pub(crate) fn record_sum(kind: u8, payload: &[u8]) -> u64 {
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let step = |h: u64, w: u64| {
        let h = (h ^ w).wrapping_mul(PRIME);
        h ^ (h >> 29)
    };
    let mut h = step(
        0xcbf2_9ce4_8422_2325,
        kind as u64 | (payload.len() as u64) << 8,
    );
    let mut words = payload.chunks_exact(8);
    for w in &mut words {
        h = step(h, u64::from_le_bytes(w.try_into().unwrap_or_default()));
    }
    let tail = words.remainder();
    if !tail.is_empty() {
        let mut w = [0u8; 8];
        w[..tail.len()].copy_from_slice(tail);
        h = step(h, u64::from_le_bytes(w));
    }
    h
}

pub(crate) use crate::cycle::CycleRecord;

#[derive(Default)]
pub(crate) struct Enc(pub Vec<u8>);

impl Enc {
    pub fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    pub fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    pub fn f64(&mut self, v: f64) {
        self.0.extend_from_slice(&v.to_bits().to_le_bytes());
    }
    pub fn str(&mut self, s: &str) {
        self.u64(s.len() as u64);
        self.0.extend_from_slice(s.as_bytes());
    }
}

pub(crate) struct Dec<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> Dec<'a> {
    pub fn new(b: &'a [u8]) -> Self {
        Dec { b, at: 0 }
    }
    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let end = self.at.checked_add(n)?;
        let s = self.b.get(self.at..end)?;
        self.at = end;
        Some(s)
    }
    pub fn u8(&mut self) -> Option<u8> {
        self.take(1).map(|s| s[0])
    }
    pub fn u32(&mut self) -> Option<u32> {
        self.take(4)
            .map(|s| u32::from_le_bytes(s.try_into().unwrap_or_default()))
    }
    pub fn u64(&mut self) -> Option<u64> {
        self.take(8)
            .map(|s| u64::from_le_bytes(s.try_into().unwrap_or_default()))
    }
    pub fn f64(&mut self) -> Option<f64> {
        self.u64().map(f64::from_bits)
    }
    pub fn str(&mut self) -> Option<String> {
        let n = usize::try_from(self.u64()?).ok()?;
        String::from_utf8(self.take(n)?.to_vec()).ok()
    }
    pub fn done(&self) -> bool {
        self.at == self.b.len()
    }
}

/// Appends value `v` of a column of kind `kind` at its storage width.
#[inline]
fn put(e: &mut Enc, kind: Kind, v: Num) {
    match kind {
        Kind::Enum | Kind::U8 => e.u8(v.as_u64() as u8),
        Kind::U32 => e.u32(v.as_u64() as u32),
        Kind::U64 => e.u64(v.as_u64()),
        Kind::F64 => e.f64(v.as_f64()),
    }
}

/// The next value of a column of kind `kind`.
#[inline]
fn take(d: &mut Dec, kind: Kind) -> Option<Num> {
    Some(match kind {
        Kind::Enum | Kind::U8 => Num::U(d.u8()? as u64),
        Kind::U32 => Num::U(d.u32()? as u64),
        Kind::U64 => Num::U(d.u64()?),
        Kind::F64 => Num::F(d.f64()?),
    })
}

/// How a block record's body is stored.
const BODY_RAW: u8 = 0;
const BODY_DEFLATE: u8 = 1;
/// The largest body a block record may claim (a hostile or damaged length is refused
/// before anything is allocated for it).
const MAX_BODY: usize = 1 << 31;

/// A block's record: `map:u64 block:u64 n:u64 body:u8` and the cells column by column
/// (each of [`COLUMNS`] in order, its `n` values at their storage width), deflated
/// (`body` 1: raw deflate, the fastest level) or as they are (`body` 0). Column by column,
/// a map's runs of equal labels, reasons and fill values compress to a few percent: the
/// journal of Fig. 9 at 4096 x 4096 is 17 MB, not 1.4 GB, and the sink's one thread does
/// not spend seconds copying it into the kernel. Deflated on the worker
/// that made the block.
pub(crate) fn encode_block(map: usize, block: usize, cells: &[Cell]) -> Vec<u8> {
    let mut raw = Enc(Vec::with_capacity(cells.len() * cell_bytes()));
    for col in COLUMNS {
        for c in cells {
            put(&mut raw, col.kind, (col.get)(c));
        }
    }
    let head = |body: u8, capacity: usize| {
        let mut e = Enc(Vec::with_capacity(25 + capacity));
        e.u64(map as u64);
        e.u64(block as u64);
        e.u64(cells.len() as u64);
        e.u8(body);
        e.0
    };
    let out = head(BODY_DEFLATE, raw.0.len() / 8);
    let mut z = flate2::write::DeflateEncoder::new(out, flate2::Compression::fast());
    match z.write_all(&raw.0).and_then(|_| z.finish()) {
        Ok(out) => out,
        // Deflating into memory does not fail; were it to, the block is kept as it is.
        Err(_) => [head(BODY_RAW, 0), raw.0].concat(),
    }
}

/// A block's whole record, framed ([`framed`] of [`encode_block`]): what a scan's and an
/// atlas's writer append, made on the worker that computed the block.
pub(crate) fn block_record(b: &squeal_scan::BlockResult) -> Vec<u8> {
    framed(KIND_BLOCK, encode_block(b.map, b.block, &b.cells))
}

/// `(map, block, cells)` of a block payload ([`encode_block`]); `None` for a malformed one
/// (a body that does not inflate to exactly its cells' bytes).
pub(crate) fn decode_block(p: &[u8]) -> Option<(usize, usize, Vec<Cell>)> {
    let mut d = Dec::new(p);
    let map = usize::try_from(d.u64()?).ok()?;
    let block = usize::try_from(d.u64()?).ok()?;
    let n = usize::try_from(d.u64()?).ok()?;
    let size = n.checked_mul(cell_bytes()).filter(|&s| s <= MAX_BODY)?;
    let codec = d.u8()?;
    let rest = &p[d.at..];
    let inflated;
    let body = match codec {
        BODY_RAW => rest,
        BODY_DEFLATE => {
            let mut out = Vec::with_capacity(size);
            let mut z = flate2::read::DeflateDecoder::new(rest).take(size as u64 + 1);
            z.read_to_end(&mut out).ok()?;
            inflated = out;
            &inflated[..]
        }
        _ => return None,
    };
    if body.len() != size {
        return None;
    }
    let mut cells = vec![Cell::fill(); n];
    let mut d = Dec::new(body);
    for col in COLUMNS {
        for c in cells.iter_mut() {
            (col.set)(c, take(&mut d, col.kind)?);
        }
    }
    Some((map, block, cells))
}

pub(crate) fn encode_cycle(map: usize, rec: &CycleRecord) -> Vec<u8> {
    let mut e = Enc::default();
    e.u64(map as u64);
    e.str(&crate::cycle::to_text(rec, true));
    e.0
}

pub(crate) fn encode_withdrawn(map: usize, w: &[squeal_scan::scanner::Withdrawn]) -> Vec<u8> {
    let mut e = Enc::default();
    e.u64(map as u64);
    e.u64(w.len() as u64);
    for x in w {
        e.str(x.rules.name());
        e.str(&x.why);
    }
    e.0
}

pub(crate) fn decode_withdrawn(p: &[u8]) -> Option<(usize, Vec<squeal_scan::scanner::Withdrawn>)> {
    let mut d = Dec::new(p);
    let map = usize::try_from(d.u64()?).ok()?;
    let n = d.u64()?;
    let mut w = Vec::new();
    for _ in 0..n {
        let rules = squeal_scan::census::Rules::from_name(&d.str()?)?;
        w.push(squeal_scan::scanner::Withdrawn {
            rules,
            why: d.str()?,
        });
    }
    d.done().then_some((map, w))
}

pub(crate) fn decode_cycle(p: &[u8]) -> Option<(usize, CycleRecord)> {
    let mut d = Dec::new(p);
    let map = usize::try_from(d.u64()?).ok()?;
    let rec = crate::cycle::from_text(&d.str()?, None).ok()?;
    d.done().then_some((map, rec))
}

/// Whose journal it is: the kind of its header record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Owner {
    Scan,
    Atlas,
}

impl Owner {
    /// The checksum of the columns this owner's records carry, in order: their names and
    /// storage widths (cells), their names (atlas points, landscapes and boundary searches,
    /// stored as JSON arrays in [`COLUMNS`] order). A journal written by a build with other
    /// columns is refused at its header, so adding, removing or reordering a column in
    /// those tables needs no edit here.
    pub(crate) fn columns_checksum(self) -> u64 {
        let mut parts: Vec<Vec<u8>> = COLUMNS
            .iter()
            .map(|c| [c.name.as_bytes(), &[b':', c.kind.bytes() as u8, b';'][..]].concat())
            .collect();
        if self == Owner::Atlas {
            let atlas = POINT_COLUMNS
                .iter()
                .chain(LANDSCAPE_COLUMNS)
                .map(|c| c.name);
            let names = atlas.chain(BOUNDARY_COLUMNS.iter().map(|c| c.name));
            parts.extend(names.map(|n| [n.as_bytes(), &b";"[..]].concat()));
        }
        fnv64(&parts.iter().map(Vec::as_slice).collect::<Vec<_>>())
    }
    fn header_kind(self) -> u8 {
        match self {
            Owner::Scan => KIND_HEADER,
            Owner::Atlas => KIND_ATLAS_HEADER,
        }
    }
    fn words(self) -> &'static str {
        match self {
            Owner::Scan => "a scan's",
            Owner::Atlas => "an atlas's",
        }
    }
}

/// The journal's header.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Header {
    pub owner: Owner,
    pub spec: String,
    pub shard: String,
    /// The rows of the friction table the spec stood on when the run started
    /// ([`table_text`]); `None` in a journal of an earlier build, which did not record it.
    pub table: Option<String>,
}

/// A friction table's rows as a journal header records them: `s,mu` lines, each number
/// written so that it reads back to the same bits; empty for no table.
pub(crate) fn table_text(t: Option<&squeal_core::FrictionTable>) -> String {
    t.map(|t| {
        t.rows()
            .iter()
            .map(|(s, mu)| format!("{s:?},{mu:?}\n"))
            .collect()
    })
    .unwrap_or_default()
}

/// What a reading of the journal skipped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Damage {
    /// Stretches of corrupt bytes between good records.
    pub regions: usize,
    /// Bytes in those stretches.
    pub bytes: u64,
    /// Good records read after the first corrupt stretch (kept).
    pub kept_after: usize,
    /// Bytes after the last good record (a torn write), cut off.
    pub tail: u64,
    /// Records begun in those bytes (their magic `SQJR`): one for a torn write, more when
    /// several trailing records were damaged.
    pub tail_records: usize,
}

impl Damage {
    /// The warning printed for it, if any.
    pub fn warning(&self, path: &Path) -> Option<String> {
        let mut parts = Vec::new();
        if self.regions > 0 {
            parts.push(format!(
                "{} corrupt stretch(es) of {} bytes skipped (their records will be computed \
                 again); {} good records after them kept",
                self.regions, self.bytes, self.kept_after
            ));
        }
        if self.tail > 0 && self.tail_records > 1 {
            // Six damaged trailing records were called "a torn last record".
            parts.push(format!(
                "{} bytes after the last good record dropped: {} damaged records there (a \
                 write cut short damages only the last; their work will be computed again)",
                self.tail, self.tail_records
            ));
        } else if self.tail > 0 {
            parts.push(format!(
                "{} bytes of a torn last record (a write cut short) dropped",
                self.tail
            ));
        }
        (!parts.is_empty())
            .then(|| format!("squeal: warning: {}: {}", path.display(), parts.join("; ")))
    }
}

/// The good records of a journal's bytes, resynchronising after corrupt ones; the end of
/// the last good record; what was skipped.
pub(crate) fn scan(bytes: &[u8]) -> (Vec<Rec>, usize, Damage) {
    let mut recs = Vec::new();
    let mut damage = Damage::default();
    let (mut at, mut end) = (0usize, 0usize);
    let mut first_damage: Option<usize> = None;
    while at < bytes.len() {
        if let Some(r) = frame_at(bytes, at) {
            recs.push(r);
            at = r.offset as usize + r.len as usize + 8;
            end = at;
            continue;
        }
        // The next place where a record checks out; none: the rest is a torn tail.
        let next = (at + 1..bytes.len())
            .filter(|&p| bytes[p..].starts_with(MAGIC))
            .find(|&p| frame_at(bytes, p).is_some());
        let Some(p) = next else { break };
        damage.regions += 1;
        damage.bytes += (p - at) as u64;
        first_damage.get_or_insert(recs.len());
        at = p;
    }
    damage.tail = (bytes.len() - end) as u64;
    damage.tail_records = (end..bytes.len())
        .filter(|&p| bytes[p..].starts_with(MAGIC))
        .count();
    damage.kept_after = first_damage.map_or(0, |k| recs.len() - k);
    (recs, end, damage)
}

fn encode_header(h: &Header) -> Vec<u8> {
    let mut e = Enc::default();
    e.u32(FORMAT);
    e.str(&h.spec);
    e.str(&h.shard);
    e.u64(h.owner.columns_checksum());
    e.str(h.table.as_deref().unwrap_or_default());
    e.0
}

/// One record's place in the journal.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rec {
    pub kind: u8,
    /// Offset of the payload.
    pub offset: u64,
    pub len: u32,
}

/// An open journal, positioned at its end for appending.
pub(crate) struct Journal {
    pub path: PathBuf,
    file: File,
    end: u64,
    /// Block records written since the last sync, and when that was.
    unsynced: usize,
    synced_at: std::time::Instant,
}

impl Drop for Journal {
    /// The blocks written since the last sync reach the disk when the run ends, whatever
    /// way it ends short of a crash (an error here has nobody left to tell: a later resume
    /// reads what made it).
    fn drop(&mut self) {
        if self.unsynced > 0 {
            let _ = self.file.sync_data();
        }
    }
}

impl Journal {
    /// Creates a new journal (fails if it exists) and writes the header.
    pub fn create(path: &Path, h: &Header) -> Result<Journal, StoreError> {
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(io(path, "cannot create the journal"))?;
        let mut j = Journal {
            path: path.to_path_buf(),
            file,
            end: 0,
            unsynced: 0,
            synced_at: std::time::Instant::now(),
        };
        j.append(h.owner.header_kind(), &encode_header(h))?;
        Ok(j)
    }

    /// Opens `owner`'s journal, checks the header, skips corrupt records (with a warning
    /// on stderr), cuts a torn tail; returns the records after the header.
    pub fn open(path: &Path, owner: Owner) -> Result<(Journal, Header, Vec<Rec>), StoreError> {
        let (j, h, recs, damage) = Journal::open_counted(path, owner)?;
        if let Some(w) = damage.warning(path) {
            eprintln!("{w}");
        }
        Ok((j, h, recs))
    }

    /// [`Journal::open`], returning what was skipped instead of printing it.
    pub fn open_counted(
        path: &Path,
        owner: Owner,
    ) -> Result<(Journal, Header, Vec<Rec>, Damage), StoreError> {
        let mut file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .open(path)
            .map_err(io(path, "cannot open the journal"))?;
        let mut bytes = Vec::new();
        file.read_to_end(&mut bytes)
            .map_err(io(path, "cannot read the journal"))?;
        let (mut recs, at, damage) = scan(&bytes);
        let header = read_header(&bytes, &recs, owner).map_err(|(why, advice)| {
            StoreError::NotSquealFile {
                path: path.to_path_buf(),
                why,
                advice,
            }
        })?;
        if (at as u64) < bytes.len() as u64 {
            // A torn last record: drop it so appends continue from a clean end.
            file.set_len(at as u64)
                .and_then(|_| file.sync_data())
                .map_err(io(path, "cannot truncate the journal"))?;
        }
        file.seek(SeekFrom::Start(at as u64))
            .map_err(io(path, "cannot seek in the journal"))?;
        recs.remove(0);
        Ok((
            Journal {
                path: path.to_path_buf(),
                file,
                end: at as u64,
                unsynced: 0,
                synced_at: std::time::Instant::now(),
            },
            header,
            recs,
            damage,
        ))
    }

    /// Appends one record; returns where its payload is. A block record is synced to disk
    /// with the others of its group, any other record at once (with the blocks before it).
    pub fn append(&mut self, kind: u8, payload: &[u8]) -> Result<Rec, StoreError> {
        let buf = framed(kind, payload.to_vec());
        self.append_framed(&buf)
    }

    /// Appends a record [`framed`] elsewhere (on a worker thread); returns where its
    /// payload is. Syncs as [`Journal::append`] does.
    pub fn append_framed(&mut self, buf: &[u8]) -> Result<Rec, StoreError> {
        let (kind, len) = (buf[4], u32::from_le_bytes([buf[5], buf[6], buf[7], buf[8]]));
        if (len as usize).checked_add(FRAME + 8) != Some(buf.len()) {
            return Err(StoreError::BadBlock {
                path: self.path.clone(),
                why: "a record above 4 GiB".into(),
            });
        }
        self.file
            .seek(SeekFrom::Start(self.end))
            .and_then(|_| self.file.write_all(buf))
            .map_err(io(&self.path, "cannot write to the journal"))?;
        let rec = Rec {
            kind,
            offset: self.end + FRAME as u64,
            len,
        };
        self.end += buf.len() as u64;
        self.unsynced += 1;
        if kind != KIND_BLOCK
            || self.unsynced >= SYNC_EVERY_BLOCKS
            || self.synced_at.elapsed() >= SYNC_EVERY
        {
            self.sync()?;
        }
        Ok(rec)
    }

    /// Syncs every record written so far to disk.
    pub fn sync(&mut self) -> Result<(), StoreError> {
        self.file
            .sync_data()
            .map_err(io(&self.path, "cannot write to the journal"))?;
        self.unsynced = 0;
        self.synced_at = std::time::Instant::now();
        Ok(())
    }

    /// Reads a record's payload ([`Journal::read_at`]; appends seek to the end themselves).
    pub fn read(&mut self, r: &Rec) -> Result<Vec<u8>, StoreError> {
        self.read_at(r)
    }

    /// The payload of record `r`, read at its offset without moving the journal's position
    /// (from any thread, while others read; [`Journal::checked`]).
    pub fn read_at(&self, r: &Rec) -> Result<Vec<u8>, StoreError> {
        let mut buf = vec![0u8; r.len as usize + 8];
        let read = read_exact_at(&self.file, &mut buf, r.offset);
        self.checked(r, read, buf)
    }

    /// The payload of `r` read (with its checksum after it) into `buf`, as written: a
    /// record cut short or whose checksum no longer holds was changed on disk by another
    /// process while this run used the journal ([`StoreError::JournalChanged`]; a change
    /// that still decoded went into the file as the run's own).
    fn checked(
        &self,
        r: &Rec,
        read: std::io::Result<()>,
        mut buf: Vec<u8>,
    ) -> Result<Vec<u8>, StoreError> {
        let changed = || StoreError::JournalChanged {
            path: self.path.clone(),
            what: record_word(r.kind).into(),
        };
        match read {
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => return Err(changed()),
            r => r.map_err(io(&self.path, "cannot read the journal"))?,
        }
        let sum = buf.split_off(r.len as usize);
        if u64::from_le_bytes(sum.try_into().expect("8 bytes")) != record_sum(r.kind, &buf) {
            return Err(changed());
        }
        Ok(buf)
    }
}

/// A record's kind in words.
fn record_word(kind: u8) -> &'static str {
    match kind {
        KIND_HEADER | KIND_ATLAS_HEADER => "header",
        KIND_UNIT => "unit",
        KIND_BLOCK => "block",
        KIND_CYCLE => "cycle",
        KIND_WITHDRAWN => "withdrawn rules",
        _ => "unknown",
    }
}

#[cfg(unix)]
fn read_exact_at(f: &File, buf: &mut [u8], offset: u64) -> std::io::Result<()> {
    std::os::unix::fs::FileExt::read_exact_at(f, buf, offset)
}

#[cfg(windows)]
fn read_exact_at(f: &File, buf: &mut [u8], offset: u64) -> std::io::Result<()> {
    use std::os::windows::fs::FileExt;
    let mut done = 0;
    while done < buf.len() {
        match f.seek_read(&mut buf[done..], offset + done as u64)? {
            0 => return Err(std::io::ErrorKind::UnexpectedEof.into()),
            n => done += n,
        }
    }
    Ok(())
}

/// Record `kind` of `payload` as the journal stores it: magic, kind, length, payload and
/// checksum ([`record_sum`]). Pure, so that it runs on the worker that made the payload. A
/// payload above 4 GiB gets a length that does not match and is refused by
/// [`Journal::append_framed`].
pub(crate) fn framed(kind: u8, payload: Vec<u8>) -> Vec<u8> {
    let len = u32::try_from(payload.len()).unwrap_or(0);
    let mut buf = Vec::with_capacity(FRAME + payload.len() + 8);
    buf.extend_from_slice(MAGIC);
    buf.push(kind);
    buf.extend_from_slice(&len.to_le_bytes());
    buf.extend_from_slice(&payload);
    buf.extend_from_slice(&record_sum(kind, &payload).to_le_bytes());
    buf
}

/// Why a journal cannot be used, and what the user can do about it.
pub(crate) type Unusable = (String, Option<Advice>);

/// The header of `owner`'s journal: the first record, which must be intact (it says which
/// spec the records belong to).
fn read_header(bytes: &[u8], recs: &[Rec], owner: Owner) -> Result<Header, Unusable> {
    let plain = |why: String| (why, None);
    let first = recs.first().copied().filter(|r| r.offset == FRAME as u64);
    let Some(first) = first else {
        if bytes.first() == Some(&b'{') {
            return Err((
                "a JSON-lines atlas journal of an earlier squeal (starting over discards its \
                 records)"
                    .into(),
                Some(Advice::OtherVersionOrStartOver),
            ));
        }
        return Err((
            format!(
                "the journal's header record is corrupt or missing, so its {} intact later \
                 record(s) cannot be matched to a spec and are not used (starting over \
                 removes the journal)",
                recs.len()
            ),
            Some(Advice::StartOver),
        ));
    };
    let found = match first.kind {
        KIND_HEADER => Owner::Scan,
        KIND_ATLAS_HEADER => Owner::Atlas,
        _ => {
            return Err(plain(
                "the journal does not start with a header record".into(),
            ));
        }
    };
    if found != owner {
        return Err(plain(format!(
            "{} journal, not {}",
            found.words(),
            owner.words()
        )));
    }
    let mut d = Dec::new(&bytes[first.offset as usize..][..first.len as usize]);
    match d.u32() {
        Some(FORMAT) => {}
        // Formats 2 and 3 have no columns' checksum; format 2 cells had no t_squeal.
        Some(f) if f < FORMAT => {
            return Err((
                format!(
                    "journal format {f}, written by an older squeal (this one writes {FORMAT})"
                ),
                Some(Advice::OtherVersionOrStartOver),
            ));
        }
        _ => return Err(plain("unknown journal format".into())),
    }
    let (Some(spec), Some(shard), Some(columns)) = (d.str(), d.str(), d.u64()) else {
        return Err(plain("the journal header is malformed".into()));
    };
    if columns != owner.columns_checksum() {
        return Err((
            "the journal's records carry other columns than this squeal stores (it was \
             written by another version)"
                .into(),
            Some(Advice::OtherVersionOrStartOver),
        ));
    }
    // A header of a build before the table was recorded ends here.
    let table = d.str();
    Ok(Header {
        owner,
        spec,
        shard,
        table,
    })
}

fn frame_at(bytes: &[u8], at: usize) -> Option<Rec> {
    let head = bytes.get(at..at + FRAME)?;
    if &head[..4] != MAGIC {
        return None;
    }
    let kind = head[4];
    let len = u32::from_le_bytes(head[5..9].try_into().ok()?);
    let start = at + FRAME;
    let end = start.checked_add(len as usize)?;
    let payload = bytes.get(start..end)?;
    let sum = u64::from_le_bytes(bytes.get(end..end + 8)?.try_into().ok()?);
    if sum != record_sum(kind, payload) {
        return None;
    }
    Some(Rec {
        kind,
        offset: start as u64,
        len,
    })
}
