//! The atlas journal's records: a finished unit as JSON ([`unit_json`]) and back, and
//! a record of any kind added to the results.

use serde_json::{Value, json};
use squeal_scan::atlas::columns::{
    BOUNDARY_COLUMNS, COLUMNS, empty_boundary, empty_point, finish_point,
};
use squeal_scan::atlas::stribeck::LANDSCAPE_COLUMNS;
use squeal_scan::atlas::{
    AtlasPlan, AtlasRegime, AtlasResults, BoundaryResult, BoundaryStatus, LineResult, PointResult,
    UnitResult,
};

use super::schema::{SEARCHES, set_landscape};
use crate::journal::{KIND_BLOCK, KIND_CYCLE, KIND_UNIT, decode_block, decode_cycle};

fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

fn point_json(p: &PointResult) -> Value {
    let mut o = json!({
        "regime": p.regime as u8,
        "note": p.note,
        "v": COLUMNS.iter().map(|c| num((c.get)(p))).collect::<Vec<_>>(),
    });
    if let Some(l) = p.landscape {
        // Laws with true stick: the landscape and the numbers it rests on.
        let mut v = vec![json!(l.landscape)];
        v.extend(LANDSCAPE_COLUMNS.iter().map(|c| num((c.get)(p))));
        o["l"] = Value::Array(v);
    }
    o
}

fn point_from_json(v: &Value) -> Option<PointResult> {
    let mut p = empty_point();
    p.regime = AtlasRegime::from_u8(v.get("regime")?.as_u64()? as u8)?;
    p.note = v.get("note")?.as_str().map(str::to_string);
    let vals = v.get("v")?.as_array()?;
    if vals.len() != COLUMNS.len() {
        return None;
    }
    for (c, x) in COLUMNS.iter().zip(vals) {
        (c.set)(&mut p, x.as_f64().unwrap_or(f64::NAN));
    }
    if let Some(l) = v.get("l") {
        let l = l.as_array()?;
        if l.len() != LANDSCAPE_COLUMNS.len() + 1 {
            return None;
        }
        for (c, x) in LANDSCAPE_COLUMNS.iter().zip(&l[1..]) {
            (c.set)(&mut p, x.as_f64().unwrap_or(f64::NAN));
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
        "note": b.note,
        "v": BOUNDARY_COLUMNS.iter().map(|c| num((c.get)(b))).collect::<Vec<_>>(),
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
    b.note = v.get("note").and_then(|n| n.as_str()).map(str::to_string);
    let vals = v.get("v")?.as_array()?;
    if vals.len() != BOUNDARY_COLUMNS.len() {
        return None;
    }
    for (c, x) in BOUNDARY_COLUMNS.iter().zip(vals) {
        (c.set)(&mut b, x.as_f64().unwrap_or(f64::NAN));
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

/// Adds one journal record to `results`: a unit, or a map's block or cycle search. A record
/// that checks out but does not fit the plan is an error (not a torn write).
pub(super) fn add_record(
    plan: &AtlasPlan,
    results: &mut AtlasResults,
    kind: u8,
    payload: &[u8],
) -> Result<(), String> {
    let grid = plan.maps.as_ref().map(|m| m.grid);
    match (kind, grid) {
        (KIND_UNIT, _) => {
            let unit = serde_json::from_slice::<Value>(payload)
                .ok()
                .and_then(|v| unit_from_json(&v))
                .ok_or("a malformed unit record")?;
            results.add(plan, unit);
        }
        (KIND_BLOCK, Some(_)) => {
            let (m, b, cells) = decode_block(payload).ok_or("a malformed block record")?;
            if !super::block_fits(plan, m, b, cells.len()) {
                return Err("a map block that does not fit the spec".into());
            }
            results.blocks.insert((m, b), cells);
        }
        (KIND_CYCLE, Some(_)) => {
            let (m, c) = decode_cycle(payload).ok_or("a malformed cycle record")?;
            if m >= plan.n_points() {
                return Err("a map cycle that does not fit the spec".into());
            }
            results.map_cycles.insert(m, c);
        }
        (k, _) => return Err(format!("a record of kind {k} that an atlas does not write")),
    }
    Ok(())
}
