//! The atlas as one JSON object (`squeal atlas --json`, `squeal info --json`): every point's
//! figures of merit (and their SI values for physical specs) and every boundary, with the
//! coordinates of each.

use serde_json::{Value, json};
use squeal_scan::atlas::columns::COLUMNS;
use squeal_scan::atlas::{AtlasPlan, BoundaryResult, PointResult};

use squeal_scan::atlas::AtlasResults;

fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

/// Every point and boundary as JSON (nondimensional figures, and SI ones for physical
/// specs), with the coordinates of each.
pub(crate) fn atlas_json(plan: &AtlasPlan, res: &AtlasResults) -> Value {
    let axes: Vec<Value> = plan
        .space.axes()
        .iter()
        .map(|a| json!({"key": a.key, "long_name": a.long_name, "units": a.units, "values": a.values}))
        .collect();
    let fixed: serde_json::Map<String, Value> = plan
        .space
        .fixed()
        .iter()
        .map(|(a, v)| (a.key.to_string(), json!({"value": v, "units": a.units})))
        .collect();
    let points: Vec<Value> = res
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| point_json(plan, res, i, p.as_ref()))
        .collect();
    let boundaries: Vec<Value> = res
        .boundaries
        .iter()
        .enumerate()
        .map(|(j, b)| boundary_json(plan, j, b.as_ref()))
        .collect();
    json!({
        "schema": squeal_store::ATLAS_SCHEMA,
        "name": plan.name,
        "law": plan.space.law.name(),
        "units": plan.space.units.name(),
        "axes": axes,
        "fixed": fixed,
        "operating_point": {"x": plan.point.operating.x, "v": plan.point.operating.v},
        "disturbance": {"x": plan.point.disturbance.x, "v": plan.point.disturbance.v,
            "x_units": plan.disturbance_units()[0], "v_units": plan.disturbance_units()[1]},
        "points": points,
        "boundaries": boundaries,
        "scheme": plan.solver.scheme.name(),
        "maps": plan.maps.map(|m| json!({
            "x0": {"min": m.grid.x0.min, "max": m.grid.x0.max, "count": m.grid.x0.count},
            "v0": {"min": m.grid.v0.min, "max": m.grid.v0.max, "count": m.grid.v0.count},
            "block_rows": m.grid.block_rows,
            "early_stop": m.early_stop.name(),
        })),
    })
}

/// Point `i`: its coordinates, parameters and figures (`not_computed` without `p`).
fn point_json(plan: &AtlasPlan, res: &AtlasResults, i: usize, p: Option<&PointResult>) -> Value {
    let values = plan.space.values_at(i);
    let coords: serde_json::Map<String, Value> = plan
        .space
        .params
        .iter()
        .zip(&values)
        .filter(|(a, _)| a.values.len() > 1)
        .map(|(a, v)| (a.key.to_string(), json!(v)))
        .collect();
    let q = plan.space.params_at(i);
    let mut o = json!({
        "index": i,
        "coords": coords,
        "params": q.named().iter().map(|n| (n.name.to_string(), json!(n.value))).collect::<serde_json::Map<_, _>>(),
    });
    let Some(p) = p else {
        o["regime"] = "not_computed".into();
        return o;
    };
    o["regime"] = p.regime.name().into();
    o["operating_point_squeals"] = json!(p.regime.operating_point_squeals());
    o["note"] = json!(p.note.as_ref().map(|n| &n.text));
    o["note_kind"] = json!(p.note.as_ref().map(|n| n.kind.name()));
    let scales = plan.space.physical_at(i).map(|ph| ph.scales());
    let mut si = serde_json::Map::new();
    for c in COLUMNS {
        o[c.name] = num(c.value(p));
        if let (Some(s), Some((twin, _))) = (scales, c.si_twin()) {
            si.insert(
                c.name.to_string(),
                json!({"value": num(c.si_value(p, &s)), "units": twin.units()}),
            );
        }
    }
    if scales.is_some() {
        o["si"] = Value::Object(si);
    }
    landscape_json(p, &mut o);
    if plan.maps.is_some() {
        map_json(plan, res, i, &mut o);
    }
    o
}

/// Boundary search `j`: where it searched, and the fold and the critical value it found.
fn boundary_json(plan: &AtlasPlan, j: usize, b: Option<&BoundaryResult>) -> Value {
    let (i, range) = plan.boundary_setup(j);
    let values = plan.space.values_at(i);
    let (dkey, _) = plan.boundary_axis();
    let bkey = plan.boundary_key();
    let coords: serde_json::Map<String, Value> = plan
        .space
        .params
        .iter()
        .zip(&values)
        .filter(|(a, _)| a.values.len() > 1 && a.key != dkey)
        .map(|(a, v)| (a.key.to_string(), json!(v)))
        .collect();
    let mut o = json!({"index": j, "coords": coords, "in": bkey,
        format!("{bkey}_range"): range});
    if let Some(b) = b {
        o["note"] = json!(b.note.as_ref().map(|n| &n.text));
        o["note_kind"] = json!(b.note.as_ref().map(|n| n.kind.name()));
        for (name, bd) in [("fold", b.fold), ("critical", b.critical)] {
            let mut e = json!({
                "status": bd.status.name(),
                bkey: num(bd.nu),
                "bracket": [num(bd.bracket[0]), num(bd.bracket[1])],
                "evaluations": bd.evaluations,
                "half_dt_holds": bd.half_dt_holds,
                "uncertainty": num(bd.uncertainty),
                "changes": bd.changes,
            });
            if let Some((v, units)) = plan.boundary_si(i, bd.nu) {
                let si = |x| plan.boundary_si(i, x).map_or(f64::NAN, |(y, _)| y);
                e[format!("{dkey}_si")] = json!({"value": num(v), "units": units,
                    "bracket": [num(si(bd.bracket[0])), num(si(bd.bracket[1]))],
                    "uncertainty": num(si(bd.uncertainty))});
            }
            o[name] = e;
        }
        // The transient lifetimes above the fold, where measured (times nondimensional).
        if plan.lifetime_starts > 0 {
            o["fold"]["lifetime"] = json!(b.lifetime);
        }
    }
    o
}

/// Laws with true stick: the landscape beside the section search's figures, and the share of
/// time stuck under its own name.
fn landscape_json(p: &PointResult, o: &mut Value) {
    if let Some(l) = p.landscape {
        use squeal_scan::atlas::true_stick::{LANDSCAPE_COLUMNS, STUCK_SHARE};
        let mut e = serde_json::Map::new();
        e.insert(
            "landscape".into(),
            l.verdict().map_or("unknown", |v| v.name()).into(),
        );
        for c in LANDSCAPE_COLUMNS {
            e.insert(c.name.into(), num(c.value(p)));
        }
        o["landscape"] = Value::Object(e);
        if let Some(v) = o
            .as_object_mut()
            .and_then(|m| m.remove("stick_quasi_static_share"))
        {
            o[STUCK_SHARE.0] = v;
        }
    }
}

/// With maps, the reported basin fraction is the map's; the cycle's is kept beside it.
fn map_json(plan: &AtlasPlan, res: &AtlasResults, i: usize, o: &mut Value) {
    o["basin_fraction_cycle"] = o["basin_fraction"].clone();
    o["basin_fraction_cycle_err"] = o["basin_fraction_err"].clone();
    let f = res.map_fraction(plan, i);
    o["basin_fraction"] = num(f.map_or(f64::NAN, |f| f.fraction));
    o["basin_fraction_err"] = num(f.map_or(f64::NAN, |f| f.err));
    o["basin_fraction_source"] = "map".into();
    if let Some(f) = f {
        o["map"] = json!({
            "cells": f.cells,
            "steady_slip": f.steady,
            "stick_slip": f.stick,
            "undecided": f.undecided,
            "near_cycle": f.near_cycle,
            "cycle_r_section": num(res.map_cycle(i).map_or(f64::NAN, |r| r.r_section)),
        });
    }
}
