//! The atlas journal's records: a finished unit as JSON ([`unit_json`]) and back, and
//! a record of any kind added to the results.

use serde_json::{Value, json};
use squeal_scan::atlas::columns::{
    BOUNDARY_COLUMNS, COLUMNS, empty_boundary, empty_point, finish_point,
};
use squeal_scan::atlas::true_stick::LANDSCAPE_COLUMNS;
use squeal_scan::atlas::{
    AtlasPlan, AtlasRegime, AtlasResults, BoundaryResult, BoundaryStatus, LineResult, PointResult,
    UnitResult,
};

use super::schema::{SEARCHES, note_of, set_landscape};
use crate::error::Advice;
use crate::journal::{KIND_BLOCK, KIND_CYCLE, KIND_UNIT, Unusable, decode_block, decode_cycle};

fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

fn point_json(p: &PointResult) -> Value {
    let mut o = json!({
        "regime": p.regime as u8,
        "note": p.note.as_ref().map(|n| &n.text),
        "note_kind": p.note.as_ref().map(|n| n.kind as u8),
        "v": COLUMNS.iter().map(|c| num(c.value(p))).collect::<Vec<_>>(),
    });
    if let Some(l) = p.landscape {
        // Laws with true stick: the landscape and the numbers it rests on.
        let mut v = vec![json!(l.landscape)];
        v.extend(LANDSCAPE_COLUMNS.iter().map(|c| num(c.value(p))));
        o["l"] = Value::Array(v);
    }
    o
}

fn point_from_json(v: &Value) -> Option<PointResult> {
    let mut p = empty_point();
    p.regime = AtlasRegime::from_u8(v.get("regime")?.as_u64()? as u8)?;
    p.note = note_of(
        v.get("note")?.as_str().map(str::to_string),
        v.get("note_kind").and_then(Value::as_u64).map(|k| k as u8),
    );
    let vals = v.get("v")?.as_array()?;
    if vals.len() != COLUMNS.len() {
        return None;
    }
    for (c, x) in COLUMNS.iter().zip(vals) {
        c.set_value(&mut p, x.as_f64().unwrap_or(f64::NAN));
    }
    if let Some(l) = v.get("l") {
        let l = l.as_array()?;
        if l.len() != LANDSCAPE_COLUMNS.len() + 1 {
            return None;
        }
        for (c, x) in LANDSCAPE_COLUMNS.iter().zip(&l[1..]) {
            c.set_value(&mut p, x.as_f64().unwrap_or(f64::NAN));
        }
        set_landscape(&mut p, l[0].as_u64()? as u8);
    }
    finish_point(&mut p);
    Some(p)
}

fn boundary_json(b: &BoundaryResult) -> Value {
    let mut o = json!({
        "boundary": b.index,
        "fold_changes": b.fold.changes,
        "note": b.note.as_ref().map(|n| &n.text),
        "note_kind": b.note.as_ref().map(|n| n.kind as u8),
        "v": BOUNDARY_COLUMNS.iter().map(|c| num(c.value(b))).collect::<Vec<_>>(),
    });
    for s in &SEARCHES {
        let d = (s.get)(b);
        o[format!("{}_status", s.key)] = json!(d.status as u8);
        o[format!("{}_evaluations", s.key)] = json!(d.evaluations);
        o[format!("{}_half_dt", s.key)] = json!(d.half_dt_holds);
    }
    o
}

fn boundary_from_json(v: &Value) -> Option<BoundaryResult> {
    let mut b = empty_boundary(v.get("boundary")?.as_u64()? as usize);
    for s in &SEARCHES {
        let get = |what: &str| v.get(format!("{}_{what}", s.key));
        let d = (s.get_mut)(&mut b);
        d.status = BoundaryStatus::from_u8(get("status")?.as_u64()? as u8)?;
        d.evaluations = get("evaluations")?.as_u64()? as u32;
        d.half_dt_holds = get("half_dt").and_then(Value::as_bool);
    }
    b.fold.changes = v.get("fold_changes").and_then(Value::as_u64).unwrap_or(0) as u32;
    b.note = note_of(
        v.get("note").and_then(|n| n.as_str()).map(str::to_string),
        v.get("note_kind").and_then(Value::as_u64).map(|k| k as u8),
    );
    let vals = v.get("v")?.as_array()?;
    if vals.len() != BOUNDARY_COLUMNS.len() {
        return None;
    }
    for (c, x) in BOUNDARY_COLUMNS.iter().zip(vals) {
        c.set_value(&mut b, x.as_f64().unwrap_or(f64::NAN));
    }
    Some(b)
}

/// A unit result as one JSON value (NaN as null), for the journal and `--json`.
pub fn unit_json(r: &UnitResult) -> Value {
    match r {
        UnitResult::Line(l) => json!({
            "line": l.line,
            "points": l.points.iter().map(point_json).collect::<Vec<_>>(),
        }),
        UnitResult::Boundary(b) => boundary_json(b),
    }
}

fn unit_from_json(v: &Value) -> Option<UnitResult> {
    let Some(line) = v.get("line") else {
        return boundary_from_json(v).map(UnitResult::Boundary);
    };
    let points = v
        .get("points")?
        .as_array()?
        .iter()
        .map(point_from_json)
        .collect::<Option<Vec<_>>>()?;
    Some(UnitResult::Line(LineResult {
        line: line.as_u64()? as usize,
        points,
    }))
}

/// A record whose checksum holds but that this build cannot decode: it was written whole, so
/// by another version of squeal (a unit record of a journal from before the transient
/// lifetimes lacks their six values), not torn by a crash.
fn unreadable(what: &str) -> Unusable {
    let why = format!(
        "a {what} record this squeal ({}) cannot read; its checksum holds, so another \
         version of squeal wrote it",
        env!("CARGO_PKG_VERSION")
    );
    (why, Some(Advice::OtherVersionOrStartOver))
}

/// Adds one journal record to `results`: a unit, or a map's block or cycle search. A record
/// that checks out but does not fit the plan is an error (not a torn write).
pub(super) fn add_record(
    plan: &AtlasPlan,
    results: &mut AtlasResults,
    kind: u8,
    payload: &[u8],
) -> Result<(), Unusable> {
    let plain = |why: String| (why, None);
    let grid = plan.maps.as_ref().map(|m| m.grid);
    match (kind, grid) {
        (KIND_UNIT, _) => {
            let unit = serde_json::from_slice::<Value>(payload)
                .ok()
                .and_then(|v| unit_from_json(&v))
                .ok_or_else(|| unreadable("unit"))?;
            results.add(plan, unit);
        }
        (KIND_BLOCK, Some(_)) => {
            let (m, b, cells) = decode_block(payload).ok_or_else(|| unreadable("block"))?;
            if !super::block_fits(plan, m, b, cells.len()) {
                return Err(plain("a map block that does not fit the spec".into()));
            }
            results.blocks.insert((m, b), cells);
        }
        (KIND_CYCLE, Some(_)) => {
            let (m, c) = decode_cycle(payload).ok_or_else(|| unreadable("cycle"))?;
            if m >= plan.space.n_points() {
                return Err(plain("a map cycle that does not fit the spec".into()));
            }
            results.map_cycles.insert(m, c);
        }
        (k, _) => {
            let why = format!("a record of kind {k} that an atlas does not write");
            return Err(plain(why));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use squeal_scan::atlas::{Note, NoteKind};

    /// A two-point atlas (one line of two dampings, no boundaries).
    fn plan() -> AtlasPlan {
        AtlasPlan::from_toml(
            "version = 1\n[model]\nlaw = \"mcmillan\"\nnu = [0.01, 0.02]\n\
             [boundaries]\nfold = false\ncritical = false\n[output]\npath = \"n.h5\"\n",
            "n.toml",
        )
        .unwrap()
    }

    fn line() -> UnitResult {
        let mut a = empty_point();
        a.note = Some(Note::conflict("conflict: the run ends steady_slip"));
        let mut b = empty_point();
        b.regime = AtlasRegime::BistableSqueals;
        b.note = Some(Note::new(NoteKind::Unconfirmed, "the run did not settle"));
        UnitResult::Line(LineResult {
            line: 0,
            points: vec![a, b],
        })
    }

    fn notes_of(r: &AtlasResults) -> Vec<Option<Note>> {
        r.points.iter().map(|p| p.as_ref()?.note.clone()).collect()
    }

    #[test]
    fn a_record_of_another_version_says_so() {
        // A unit record from before the lifetimes (its boundary lacks them) was refused as "a
        // malformed unit record", which did not name the cause.
        let plan = plan();
        let mut v = unit_json(&line());
        v.as_object_mut().unwrap().remove("line");
        let payload = serde_json::to_vec(&v).unwrap();
        let mut res = AtlasResults::new(&plan);
        let (why, advice) = add_record(&plan, &mut res, KIND_UNIT, &payload).unwrap_err();
        assert!(
            why.contains("unit record") && why.contains("another version"),
            "{why}"
        );
        assert_eq!(advice, Some(Advice::OtherVersionOrStartOver));
    }

    #[test]
    fn note_kinds_survive_the_journal_and_the_file() {
        // Before, a note was a string: the kind of "the run did not settle" (an unconfirmed
        // label) could not be told from a finding without reading its words.
        let plan = plan();
        let want = match line() {
            UnitResult::Line(l) => l.points.into_iter().map(|p| p.note).collect::<Vec<_>>(),
            _ => unreachable!(),
        };
        let back = unit_from_json(&unit_json(&line())).unwrap();
        let mut res = AtlasResults::new(&plan);
        res.add(&plan, back);
        assert_eq!(notes_of(&res), want);
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("n.h5");
        let prov = crate::Provenance {
            version: "test".into(),
            git_revision: "test".into(),
        };
        let maps = squeal_scan::atlas::point_maps(&plan, &res);
        crate::atlas::write_atlas(&out, &plan, (&res, &maps), &prov, None).unwrap();
        let (_, read, _) = crate::atlas::read_atlas(&out).unwrap();
        assert_eq!(notes_of(&read), want);
    }

    #[test]
    fn records_without_kinds_read_their_first_word() {
        // Journals and files from before the kinds were stored: a conflict and an unconfirmed
        // label always began with that word; other notes read as findings.
        assert_eq!(
            note_of(Some("conflict: a".into()), None).unwrap().kind,
            NoteKind::Conflict
        );
        let u = note_of(Some("unconfirmed: b".into()), None).unwrap();
        assert_eq!(u.kind, NoteKind::Unconfirmed);
        let f = note_of(Some("the landscape says x".into()), None).unwrap();
        assert_eq!(f.kind, NoteKind::Finding);
        // A stored kind wins over the words, and empty words are no note.
        let k = note_of(Some("conflict: a".into()), Some(NoteKind::Failure as u8)).unwrap();
        assert_eq!(k.kind, NoteKind::Failure);
        assert_eq!(note_of(Some(String::new()), Some(4)), None);
    }
}
