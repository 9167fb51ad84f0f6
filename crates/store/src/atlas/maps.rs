//! The atlas's basin maps in its file: every column of [`squeal_scan::cell::COLUMNS`] over
//! (the swept parameters..., v0, x0), the per-map checks and cycles, and the basin fraction
//! read off each map (computed by the engine: [`squeal_scan::atlas::PointMap`]); and
//! reading the blocks, cycles and final-state sensitivity back.

use std::path::Path;

use hdf5::types::VarLenUnicode;
use hdf5::{Dataset, File};
use squeal_scan::atlas::{AtlasPlan, AtlasResults, MapFraction, PointMap};
use squeal_scan::cell::{COLUMNS as CELLS, Cell};
use squeal_scan::sensitivity::{Log2Test, SENSITIVITY_FIELDS};
use squeal_scan::ulc::CycleReport;
use squeal_scan::{Grid, Plan};

use super::schema::map_name;
use crate::StoreError;
use crate::error::H5Ctx;
use crate::h5out::{Out, Over, num_attr, str_attr};
use crate::h5write::{column_dataset, write_column};
use crate::read::{rd, rd_n};

/// The maps' datasets, over the points `over` (the maps' own dimensions after them).
pub(super) fn write_maps(
    o: &mut Out,
    over: &Over,
    plan: &AtlasPlan,
    (res, maps): (&AtlasResults, &[PointMap]),
) -> hdf5::Result<()> {
    let Some(mp) = plan.map_plan() else {
        return Ok(());
    };
    let g = mp.map.grid;
    let x0 = o.scale("x0", &g.x0.values(), "initial displacement x(0)", Some("1"))?;
    let v0 = o.scale("v0", &g.v0.values(), "initial velocity x'(0)", Some("1"))?;
    let block = o.index("block", g.blocks(), "block of grid rows")?;
    // A physical atlas's grid in m and m/s beside it (every map has the same units).
    if let Some(ph) = &mp.physical() {
        for (d, name) in crate::h5write::state_si(o, &g, &ph.scales(), [&x0, &v0])? {
            o.aux_coordinate(d, &name);
        }
    }
    map_attrs(o.file, &mp)?;
    if maps.len() != plan.space.n_points() {
        let why = format!(
            "map figures for {} points of {}",
            maps.len(),
            plan.space.n_points()
        );
        return Err(hdf5::Error::from(why));
    }
    let done = write_cells(o, over, (plan, &mp), res, [&v0, &x0])?;
    let blocks = over.and(g.blocks(), &block);
    o.put(
        &blocks,
        ("blocks_done", "1 where the block of map rows is stored"),
        None,
        done,
    )?;
    for (k, (name, long)) in squeal_scan::checks::CHECK_FIELDS.iter().enumerate() {
        let v: Vec<i64> = maps.iter().map(|m| m.checks.values()[k]).collect();
        o.put(over, (&map_name(name), long), Some("1"), v)?;
    }
    write_fractions(o, over, maps)?;
    write_cycles(o, over, res, plan.space.n_points())
}

/// The maps' settings as root attributes.
fn map_attrs(file: &File, mp: &Plan) -> hdf5::Result<()> {
    let (g, cl) = (&mp.map.grid, &mp.map.classifier);
    for (k, v) in [
        ("x0_min", g.x0.min),
        ("x0_max", g.x0.max),
        ("v0_min", g.v0.min),
        ("v0_max", g.v0.max),
    ] {
        num_attr(file, k, v)?;
    }
    num_attr(file, "block_rows", g.block_rows as u64)?;
    num_attr(file, "t_max", cl.t_max)?;
    num_attr(file, "fp_radius", cl.fp_radius)?;
    num_attr(file, "settle_cycles", cl.settle_cycles)?;
    num_attr(file, "settle_rtol", cl.settle_rtol)?;
    str_attr(file, "early_stop", mp.map.early_stop.name())?;
    num_attr(file, "trap_margin", mp.map.trap_margin)?;
    num_attr(file, "audit_every", mp.map.audit_every)?;
    num_attr(file, "sensitivity_samples", mp.map.sensitivity_samples)
}

/// Every stored block of every map, column by column; returns which blocks are stored
/// (point-major).
fn write_cells(
    o: &mut Out,
    over: &Over,
    (plan, mp): (&AtlasPlan, &Plan),
    res: &AtlasResults,
    [v0, x0]: [&Dataset; 2],
) -> hdf5::Result<Vec<u8>> {
    let g = mp.map.grid;
    let (nx, nv, nb) = (g.x0.count, g.v0.count, g.blocks());
    let cells = over.and(nv, v0).and(nx, x0);
    let rows_per_chunk = g.block_rows.min(nv).min((1usize << 24) / nx.max(1)).max(1);
    let mut chunk = vec![1; over.shape.len()];
    chunk.extend([rows_per_chunk, nx]);
    let vars: Vec<Dataset> = CELLS
        .iter()
        .map(|col| column_dataset(o.file, col, &map_name(col.name), &cells.shape, &chunk))
        .collect::<hdf5::Result<_>>()?;
    let scales: Vec<&Dataset> = cells.scales.iter().collect();
    for v in &vars {
        o.dims.attach(o.file, v, &scales)?;
    }
    let n = plan.space.n_points();
    let mut done = vec![0u8; n * nb];
    for i in 0..n {
        // The point's indices (`[0]`: the single point of a spec that sweeps nothing).
        let prefix = match plan.space.axes().is_empty() {
            true => vec![0],
            false => plan.space.unravel(i),
        };
        for b in 0..nb {
            let Some(cells) = res.blocks.get(&(i, b)) else {
                continue;
            };
            done[i * nb + b] = 1;
            for (ds, col) in vars.iter().zip(CELLS) {
                write_column(ds, col, cells, &prefix, g.block_rows(b), nx)?;
            }
        }
    }
    Ok(done)
}

/// The basin fraction read off each map, with the counts behind its uncertainty.
fn write_fractions(o: &mut Out, over: &Over, maps: &[PointMap]) -> hdf5::Result<()> {
    let fr: Vec<Option<MapFraction>> = maps.iter().map(|m| m.fraction).collect();
    let real = |f: fn(&MapFraction) -> f64| -> Vec<f64> {
        fr.iter().map(|x| x.as_ref().map_or(f64::NAN, f)).collect()
    };
    let count = |f: fn(&MapFraction) -> u64| -> Vec<u64> {
        fr.iter().map(|x| x.as_ref().map_or(0, f)).collect()
    };
    let ds = o.put(
        over,
        (
            "basin_fraction",
            "share of the grid box that returns to steady slip, from the basin map: steady-slip cells over decided cells",
        ),
        Some("1"),
        real(|f| f.fraction),
    )?;
    str_attr(&ds, "source", "map")?;
    let err = (
        "basin_fraction_err",
        "uncertainty of basin_fraction: (undecided cells + decided cells within one cell of the located cycle) over all cells",
    );
    o.put(over, err, Some("1"), real(|f| f.err))?;
    let undecided = (
        "map_undecided_cells",
        "cells of the map left undecided (or not computed)",
    );
    o.put(over, undecided, Some("1"), count(|f| f.undecided))?;
    let near = (
        "map_cells_near_cycle",
        "decided cells within one cell of the located cycle",
    );
    o.put(over, near, Some("1"), count(|f| f.near_cycle))?;
    let sens: Vec<_> = maps.iter().map(|m| m.sensitivity).collect();
    crate::h5write::sensitivity(o, over, "map_", &sens)
}

/// Each map's cycle search: the record (TOML, exact) and the closed curve, NaN-padded.
fn write_cycles(o: &mut Out, over: &Over, res: &AtlasResults, n: usize) -> hdf5::Result<()> {
    let texts: Vec<String> = (0..n)
        .map(|i| {
            let r = res.map_cycles.get(&i);
            r.map_or(String::new(), |c| crate::cycle::to_text(c, false))
        })
        .collect();
    o.put_notes(
        over,
        (
            "map_cycle_record",
            "cycle search of the map (TOML; empty: not recorded)",
        ),
        texts.iter().map(|t| Some(t.as_str())),
    )?;
    let len = (0..n)
        .filter_map(|i| res.map_cycle(i).map(|r| r.curve.x.len()))
        .max()
        .unwrap_or(0);
    if len == 0 {
        return Ok(());
    }
    let point = o.index("cycle_point", len, "step along the closed curve")?;
    let curve = over.and(len, &point);
    for (name, long, get) in [
        (
            "map_cycle_x",
            "displacement x on the located cycle of the map (NaN-padded)",
            (|r: &CycleReport| &r.curve.x) as fn(&_) -> &Vec<f64>,
        ),
        (
            "map_cycle_v",
            "velocity x' on the located cycle of the map (NaN-padded)",
            |r: &CycleReport| &r.curve.v,
        ),
    ] {
        let mut v = vec![f64::NAN; n * len];
        for i in 0..n {
            if let Some(r) = res.map_cycle(i) {
                let c = get(r);
                v[i * len..i * len + c.len()].copy_from_slice(c);
            }
        }
        o.put(&curve, (name, long), Some("1"), v)?;
    }
    Ok(())
}

/// Reads the stored map blocks and cycle searches of an atlas file with maps.
pub(super) fn read_maps(
    file: &File,
    path: &Path,
    plan: &AtlasPlan,
    res: &mut AtlasResults,
) -> Result<(), StoreError> {
    let Some(g) = plan.maps.as_ref().map(|m| m.grid) else {
        return Ok(());
    };
    let n = plan.space.n_points();
    let done: Vec<u8> = rd(file, path, "blocks_done")?;
    if done.len() != n * g.blocks() {
        return Err(not_atlas(
            path,
            format!(
                "blocks_done holds {} values, expected {}",
                done.len(),
                n * g.blocks()
            ),
        ));
    }
    let maps = if done.contains(&1) {
        read_cells(file, path, &g, n)?
    } else {
        Vec::new()
    };
    let nb = g.blocks();
    for (k, _) in done.iter().enumerate().filter(|(_, d)| **d == 1) {
        let (i, b) = (k / nb, k % nb);
        let rows = g.block_rows(b);
        let cells = maps[i][rows.start * g.x0.count..rows.end * g.x0.count].to_vec();
        res.blocks.insert((i, b), cells);
    }
    read_cycles(file, path, res, n)
}

fn not_atlas(path: &Path, why: String) -> StoreError {
    StoreError::NotSquealFile {
        path: path.to_path_buf(),
        why,
        advice: None,
    }
}

/// Every cell of the `n` maps, column by column, point-major.
fn read_cells(file: &File, path: &Path, g: &Grid, n: usize) -> Result<Vec<Vec<Cell>>, StoreError> {
    let per_map = g.x0.count * g.v0.count;
    let mut maps = vec![vec![Cell::fill(); per_map]; n];
    for col in CELLS {
        let name = map_name(col.name);
        let vals = (file.dataset(&name))
            .and_then(|ds| crate::h5columns::read_nums(&ds, col.kind, None))
            .h5(path)?;
        if vals.len() != n * per_map {
            let why = format!(
                "{name} holds {} values, expected {}",
                vals.len(),
                n * per_map
            );
            return Err(not_atlas(path, why));
        }
        for (k, v) in vals.into_iter().enumerate() {
            (col.set)(&mut maps[k / per_map][k % per_map], v);
        }
    }
    Ok(maps)
}

/// Each map's cycle search: its record and its closed curve (NaN padding dropped).
fn read_cycles(
    file: &File,
    path: &Path,
    res: &mut AtlasResults,
    n: usize,
) -> Result<(), StoreError> {
    let recs: Vec<VarLenUnicode> = rd_n(file, path, "map_cycle_record", n)?;
    let curves = match (file.dataset("map_cycle_x"), file.dataset("map_cycle_v")) {
        (Ok(x), Ok(v)) => Some((x.read_raw::<f64>().h5(path)?, v.read_raw::<f64>().h5(path)?)),
        _ => None,
    };
    for (i, r) in recs.iter().enumerate() {
        if r.as_str().is_empty() {
            continue;
        }
        let curve = curves.as_ref().and_then(|(x, v)| {
            let len = x.len() / n.max(1);
            let xs: Vec<f64> = x[i * len..(i + 1) * len]
                .iter()
                .copied()
                .take_while(|a| !a.is_nan())
                .collect();
            let vs: Vec<f64> = v[i * len..(i + 1) * len][..xs.len()].to_vec();
            (!xs.is_empty()).then_some(squeal_scan::ClosedCurve { x: xs, v: vs })
        });
        let rec = crate::cycle::from_text(r.as_str(), curve)
            .map_err(|e| not_atlas(path, format!("map_cycle_record of point {i}: {e}")))?;
        res.map_cycles.insert(i, rec);
    }
    Ok(())
}

/// Each point's final-state sensitivity as an atlas file stores it: the `map_` datasets of
/// [`SENSITIVITY_FIELDS`] and `map_log2_test` (written by `crate::h5write::sensitivity`).
#[derive(Clone, Debug, PartialEq)]
pub struct MapSensitivity {
    /// Per point (C order over the swept axes), the figures of [`SENSITIVITY_FIELDS`] in
    /// their order (NaN: no complete map, not measured, or a figure the file predates), as
    /// [`squeal_scan::sensitivity::words`] takes them.
    pub values: Vec<Vec<f64>>,
    /// Per point, the log 2 test's verdict (`None`: no complete map).
    pub log2_test: Vec<Option<Log2Test>>,
}

impl MapSensitivity {
    /// Figure `name` of [`SENSITIVITY_FIELDS`] per point (NaN where absent; every value NaN
    /// for a name not in the table).
    pub fn field(&self, name: &str) -> Vec<f64> {
        let k = SENSITIVITY_FIELDS.iter().position(|f| f.0 == name);
        (self.values.iter())
            .map(|v| k.and_then(|k| v.get(k).copied()).unwrap_or(f64::NAN))
            .collect()
    }
}

/// Reads the final-state sensitivity of every point's map back from the atlas file at
/// `path` of `plan` (its stored plan, [`super::read_atlas`]). `None` for an atlas without
/// maps or a file written before the sensitivity was stored (no
/// `map_boundary_basin_entropy`); a figure added later and absent is NaN.
pub fn read_map_sensitivity(
    path: &Path,
    plan: &AtlasPlan,
) -> Result<Option<MapSensitivity>, StoreError> {
    if plan.maps.is_none() {
        return Ok(None);
    }
    let file = crate::read::open_with_schema(path, crate::ATLAS_SCHEMA)?;
    if !file.link_exists(&map_name("boundary_basin_entropy")) {
        return Ok(None);
    }
    let n = plan.space.n_points();
    let mut values = vec![vec![f64::NAN; SENSITIVITY_FIELDS.len()]; n];
    for (k, (name, ..)) in SENSITIVITY_FIELDS.iter().enumerate() {
        let v: Vec<f64> = crate::read::rd_new_n(&file, path, &map_name(name), n)?;
        for (point, x) in values.iter_mut().zip(v) {
            point[k] = x;
        }
    }
    let stored: Vec<u8> = crate::read::rd_new_n(&file, path, &map_name("log2_test"), n)?;
    let boxes = SENSITIVITY_FIELDS
        .iter()
        .position(|f| f.0 == "basin_entropy_boxes");
    // A point without a complete map holds no_boundary: told apart by its boxes (NaN).
    let log2_test = (0..n)
        .map(|i| {
            let mapped = boxes.is_some_and(|b| values[i][b].is_finite());
            let test = Log2Test::ALL
                .into_iter()
                .find(|t| Some(&(*t as u8)) == stored.get(i));
            test.filter(|_| mapped)
        })
        .collect();
    Ok(Some(MapSensitivity { values, log2_test }))
}

#[cfg(test)]
mod tests;
