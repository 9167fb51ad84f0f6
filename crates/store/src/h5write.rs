//! Writes the HDF5 file from a source of blocks and cycles (the journal, or shard files).

use std::path::Path;

use crate::LandscapeInfo;
use hdf5::types::{FixedAscii, VarLenArray, VarLenUnicode};
use hdf5::{Dataset, File, Group, H5Type, Location, ObjectReference1};
use ndarray::{Array1, Array2};
use squeal_scan::cell::{COLUMNS, Cell};
use squeal_scan::checks::CHECK_FIELDS;
use squeal_scan::ulc::CycleReport;
use squeal_scan::{BASIN_FIELDS, GridShares};
use squeal_scan::{MapChecks, Plan};

use crate::cycle::Flat;
use crate::error::H5Ctx;
use crate::h5types::{LandscapeH5, RefEntry};
use crate::journal::CycleRecord;
use crate::{SCHEMA, StoreError};

/// Where the writer gets its blocks and cycles from.
pub(crate) trait Source {
    /// The cells of a block, if stored.
    fn block(&mut self, map: usize, block: usize) -> Result<Option<Vec<Cell>>, StoreError>;
    /// The recorded cycle of a map, if any.
    fn cycle(&mut self, map: usize) -> Result<Option<CycleRecord>, StoreError>;
}

/// What goes in the root attributes besides the plan.
pub(crate) struct Meta<'a> {
    pub version: &'a str,
    pub git_revision: &'a str,
    pub shard: Option<String>,
}

pub(crate) fn str_attr(loc: &Location, name: &str, value: &str) -> hdf5::Result<()> {
    let v: VarLenUnicode = value
        .parse()
        .map_err(|e| hdf5::Error::from(format!("{e}")))?;
    loc.new_attr::<VarLenUnicode>()
        .create(name)?
        .write_scalar(&v)
}

pub(crate) fn num_attr<T: H5Type>(loc: &Location, name: &str, value: T) -> hdf5::Result<()> {
    loc.new_attr::<T>().create(name)?.write_scalar(&value)
}

/// Records dimension-scale attachments; `REFERENCE_LIST`s are written at the end.
pub(crate) struct Dims {
    pub(crate) scales: Vec<(Dataset, Vec<RefEntry>)>,
    /// The type of `CLASS`: a 16-byte null-terminated ASCII string, as `H5DSis_scale` demands.
    pub(crate) class_type: hdf5::Datatype,
}

/// A tiny HDF5 file (written with h5py) whose root attribute `CLASS` has the type the
/// dimension-scale API requires (fixed 16-byte ASCII, `H5T_STR_NULLTERM`). hdf5-metno can
/// only make null-padded fixed strings without `unsafe`, so the type is copied from here.
/// (Made with h5py: `t = h5py.h5t.C_S1.copy(); t.set_size(16);
/// t.set_strpad(h5py.h5t.STR_NULLTERM); f.attrs.create("CLASS", b"DIMENSION_SCALE",
/// dtype=h5py.Datatype(t))`, `libver="earliest"`. Named `.bin` because `.gitignore` drops `*.h5`.)
const CLASS_TEMPLATE: &[u8] = include_bytes!("dimension_scale_class.bin");

/// Reads the `CLASS` type from the template, written beside `path` for the moment.
pub(crate) fn class_type(path: &Path) -> Result<hdf5::Datatype, StoreError> {
    let mut s = path.as_os_str().to_owned();
    s.push(".class");
    let tpl = std::path::PathBuf::from(s);
    std::fs::write(&tpl, CLASS_TEMPLATE).map_err(crate::error::io(&tpl, "cannot write"))?;
    let t = (|| -> hdf5::Result<hdf5::Datatype> {
        let f = File::open(&tpl)?;
        let t = f.attr("CLASS")?.dtype()?;
        f.close()?;
        Ok(t)
    })()
    .h5(&tpl);
    let _ = std::fs::remove_file(&tpl);
    t
}

impl Dims {
    /// No scales yet; `class_type` from [`class_type`].
    pub(crate) fn new(class_type: hdf5::Datatype) -> Dims {
        Dims {
            scales: Vec::new(),
            class_type,
        }
    }

    /// Makes `ds` a dimension scale named `name` (netCDF-4 / HDF5 DS convention).
    pub(crate) fn scale(&mut self, ds: &Dataset, name: &str) -> hdf5::Result<()> {
        let class: FixedAscii<16> = FixedAscii::from_ascii("DIMENSION_SCALE")
            .map_err(|e| hdf5::Error::from(format!("{e}")))?;
        ds.new_attr_builder()
            .empty_as(&self.class_type)
            .create("CLASS")?
            .write_scalar(&class)?;
        let n: FixedAscii<16> =
            FixedAscii::from_ascii(name).map_err(|e| hdf5::Error::from(format!("{e}")))?;
        ds.new_attr::<FixedAscii<16>>()
            .create("NAME")?
            .write_scalar(&n)?;
        self.scales.push((ds.clone(), Vec::new()));
        Ok(())
    }

    /// Attaches scales (by dataset name) to the dimensions of `var`, in order.
    pub(crate) fn attach(
        &mut self,
        file: &File,
        var: &Dataset,
        scales: &[&Dataset],
    ) -> hdf5::Result<()> {
        let me: ObjectReference1 = file.reference(&var.name())?;
        let mut list = Vec::new();
        for (i, s) in scales.iter().enumerate() {
            let r: ObjectReference1 = file.reference(&s.name())?;
            list.push(VarLenArray::from_slice(&[r]));
            let entry = self
                .scales
                .iter_mut()
                .find(|(d, _)| d.name() == s.name())
                .ok_or_else(|| hdf5::Error::from("not a dimension scale"))?;
            entry.1.push(RefEntry {
                dataset: me,
                dimension: i as i32,
            });
        }
        var.new_attr::<VarLenArray<ObjectReference1>>()
            .shape(list.len())
            .create("DIMENSION_LIST")?
            .write_raw(&list)
    }

    pub(crate) fn finish(self) -> hdf5::Result<()> {
        for (ds, refs) in self.scales {
            if !refs.is_empty() {
                ds.new_attr::<RefEntry>()
                    .shape(refs.len())
                    .create("REFERENCE_LIST")?
                    .write_raw(&refs)?;
            }
        }
        Ok(())
    }
}

/// A per-map variable over the map dimension, with its long name and units.
fn per_map<T: H5Type>(
    file: &File,
    dims: &mut Dims,
    map_dim: &Dataset,
    name: &str,
    vals: &Array1<T>,
    long_name: &str,
    units: &str,
) -> hdf5::Result<()> {
    let ds = file
        .new_dataset_builder()
        .obj_track_times(false)
        .with_data(vals)
        .create(name)?;
    str_attr(&ds, "long_name", long_name)?;
    str_attr(&ds, "units", units)?;
    dims.attach(file, &ds, &[map_dim])
}

/// A per-map cycle series: dataset name, value, long name.
type Series = (&'static str, fn(&CycleReport) -> f64, &'static str);

fn coord(
    g: &Group,
    dims: &mut Dims,
    name: &str,
    values: &[f64],
    long_name: &str,
) -> hdf5::Result<Dataset> {
    let ds = g
        .new_dataset_builder()
        .obj_track_times(false)
        .with_data(values)
        .create(name)?;
    str_attr(&ds, "long_name", long_name)?;
    str_attr(&ds, "units", "1")?;
    dims.scale(&ds, name)?;
    Ok(ds)
}

fn index_coord(
    g: &Group,
    dims: &mut Dims,
    name: &str,
    n: usize,
    long_name: &str,
) -> hdf5::Result<Dataset> {
    let values: Vec<u64> = (0..n as u64).collect();
    let ds = g
        .new_dataset_builder()
        .obj_track_times(false)
        .with_data(&values)
        .create(name)?;
    str_attr(&ds, "long_name", long_name)?;
    dims.scale(&ds, name)?;
    Ok(ds)
}

pub(crate) use crate::h5columns::{column_dataset, is_list, sel, write_column};

/// A physical spec's system (`physical_<key>` with `physical_<key>_units`; the swept one of
/// `c` and `v_belt` is left out: its maps' values are `nu` or `lambda` times the unit) and
/// the SI size of one nondimensional unit.
fn physical_attrs(
    file: &File,
    ph: &squeal_core::Physical,
    swept: Option<&str>,
) -> hdf5::Result<()> {
    let values = [ph.m, ph.k, ph.c, ph.v_belt, ph.mu_k, ph.mu_s, ph.tau, ph.g];
    let skip = match swept {
        Some("nu") => "c",
        Some("lambda") => "v_belt",
        _ => "",
    };
    for ((key, long, units), v) in squeal_scan::atlas::spec::PHYSICAL.iter().zip(values) {
        if *key == skip {
            continue;
        }
        num_attr(file, &format!("physical_{key}"), v)?;
        str_attr(file, &format!("physical_{key}_long_name"), long)?;
        str_attr(file, &format!("physical_{key}_units"), units)?;
    }
    let s = ph.scales();
    for (key, v, units) in [
        ("length_unit", s.length, "m"),
        ("velocity_unit", s.velocity, "m/s"),
        ("time_unit", s.time, "s"),
        ("damping_unit", s.damping, "N s/m"),
    ] {
        num_attr(file, key, v)?;
        str_attr(file, &format!("{key}_units"), units)?;
    }
    Ok(())
}

/// The root attributes: provenance, the spec and every setting of the plan.
fn root_attrs(file: &File, plan: &Plan, meta: &Meta) -> hdf5::Result<()> {
    let g = &plan.grid;
    let p0 = plan.maps[0];
    str_attr(file, "schema", SCHEMA)?;
    str_attr(file, "squeal_version", meta.version)?;
    str_attr(file, "git_revision", meta.git_revision)?;
    str_attr(file, "spec", &plan.spec_text)?;
    str_attr(file, "name", &plan.name)?;
    str_attr(file, "law", p0.law.name())?;
    let swept = plan.sweep.as_ref().map(|s| s.name);
    if p0.law.has_true_stick() {
        // The law's own parameters, each with its long name and units beside it.
        for n in p0.named() {
            if swept != Some(n.name) {
                num_attr(file, n.name, n.value)?;
            }
            str_attr(file, &format!("{}_long_name", n.name), n.long_name)?;
            str_attr(file, &format!("{}_units", n.name), n.units)?;
        }
    } else {
        num_attr(file, "tau", p0.tau)?;
        num_attr(file, "phi", p0.phi)?;
        if swept != Some("nu") {
            num_attr(file, "nu", p0.nu)?;
        }
        if swept != Some("lambda") {
            num_attr(file, "lambda", p0.lambda)?;
        }
    }
    if let Some(ph) = &plan.physical {
        physical_attrs(file, ph, plan.sweep.as_ref().map(|s| s.name))?;
    }
    num_attr(file, "dt", plan.dt)?;
    str_attr(file, "solver", plan.solver.kind.name())?;
    str_attr(file, "scheme", plan.solver.scheme.name())?;
    num_attr(file, "max_iter", plan.solver.max_iter)?;
    num_attr(file, "t_max", plan.classifier.t_max)?;
    num_attr(file, "fp_radius", plan.classifier.fp_radius)?;
    num_attr(file, "settle_cycles", plan.classifier.settle_cycles)?;
    num_attr(file, "settle_rtol", plan.classifier.settle_rtol)?;
    str_attr(file, "early_stop", plan.early_stop.name())?;
    num_attr(file, "trap_margin", plan.trap_margin)?;
    num_attr(file, "locate_cycle", plan.locate_cycle as u8)?;
    num_attr(file, "block_rows", g.block_rows as u64)?;
    match &g.sample {
        None => str_attr(file, "sampling", "grid")?,
        Some(smp) => {
            str_attr(file, "sampling", "random")?;
            num_attr(file, "sample_n", smp.n as u64)?;
            num_attr(file, "sample_seed", smp.seed)?;
            num_attr(file, "sample_x0_min", g.x0.min)?;
            num_attr(file, "sample_x0_max", g.x0.max)?;
            num_attr(file, "sample_v0_min", g.v0.min)?;
            num_attr(file, "sample_v0_max", g.v0.max)?;
        }
    }
    num_attr(file, "audit_every", plan.audit_every)?;
    if let Some(s) = &meta.shard {
        str_attr(file, "shard", s)?;
    }
    Ok(())
}

/// Checks before any computing that the final write will succeed: writes the root
/// attributes and coordinates into a scratch file beside `path` and removes it.
pub(crate) fn preflight(path: &Path, plan: &Plan, meta: &Meta) -> Result<(), StoreError> {
    let mut s = path.as_os_str().to_owned();
    s.push(".preflight");
    let scratch = std::path::PathBuf::from(s);
    let _ = std::fs::remove_file(&scratch);
    let res = (|| -> hdf5::Result<()> {
        let f = File::create_excl(&scratch)?;
        root_attrs(&f, plan, meta)?;
        f.new_dataset_builder()
            .with_data(&plan.grid.x0.values())
            .create("x0")?;
        f.close()
    })()
    .h5(path);
    let _ = std::fs::remove_file(&scratch);
    res
}

/// Writes the whole file at `path` (which must not exist). Memory: one block at a time.
pub(crate) fn assemble(
    path: &Path,
    plan: &Plan,
    meta: &Meta,
    src: &mut dyn Source,
    landscapes: &[Option<LandscapeInfo>],
) -> Result<Vec<MapChecks>, StoreError> {
    let file = File::create_excl(path).h5(path)?;
    let out = write_all(&file, plan, meta, src, path, landscapes);
    let closed = file.close().h5(path);
    let out = out?;
    closed?;
    Ok(out)
}

fn write_all(
    file: &File,
    plan: &Plan,
    meta: &Meta,
    src: &mut dyn Source,
    path: &Path,
    landscapes: &[Option<LandscapeInfo>],
) -> Result<Vec<MapChecks>, StoreError> {
    let g = &plan.grid;
    let (nx, nv, nmaps, nblocks) = (g.x0.count, g.v0.count, plan.maps.len(), g.blocks());
    let sweep = plan.sweep.is_some();
    let mut dims = Dims {
        scales: Vec::new(),
        class_type: class_type(path)?,
    };

    root_attrs(file, plan, meta).h5(path)?;

    // Coordinates and variables: a grid's axes x0 (columns) and v0 (rows), or a random
    // sample's index with the points' x0 and v0 as variables over it.
    let sample = g.sample.is_some();
    let (x0, v0) = if sample {
        let idx = index_coord(file, &mut dims, "sample", nv, "random sample index").h5(path)?;
        let pts: Vec<(f64, f64)> = (0..nv).map(|i| g.state(i, 0)).collect();
        let var = |name: &str, vals: Vec<f64>, long: &str| -> hdf5::Result<Dataset> {
            let ds = file
                .new_dataset_builder()
                .obj_track_times(false)
                .with_data(&vals)
                .create(name)?;
            str_attr(&ds, "long_name", long)?;
            str_attr(&ds, "units", "1")?;
            Ok(ds)
        };
        let xs = var(
            "x0",
            pts.iter().map(|p| p.0).collect(),
            "initial displacement x(0) of the sample",
        )
        .h5(path)?;
        let vs = var(
            "v0",
            pts.iter().map(|p| p.1).collect(),
            "initial velocity x'(0) of the sample",
        )
        .h5(path)?;
        dims.attach(file, &xs, &[&idx]).h5(path)?;
        dims.attach(file, &vs, &[&idx]).h5(path)?;
        (idx.clone(), idx)
    } else {
        (
            coord(
                file,
                &mut dims,
                "x0",
                &g.x0.values(),
                "initial displacement x(0)",
            )
            .h5(path)?,
            coord(
                file,
                &mut dims,
                "v0",
                &g.v0.values(),
                "initial velocity x'(0)",
            )
            .h5(path)?,
        )
    };
    let sw = match &plan.sweep {
        Some(s) => {
            let named = plan.maps[0].named();
            let long = named
                .iter()
                .find(|n| n.name == s.name)
                .map_or(s.name, |n| n.long_name);
            Some(coord(file, &mut dims, s.name, &s.values, long).h5(path)?)
        }
        None => None,
    };
    let map_dim = match &sw {
        Some(d) => d.clone(),
        None => index_coord(file, &mut dims, "map", nmaps, "map index").h5(path)?,
    };
    let block_dim = index_coord(
        file,
        &mut dims,
        "block",
        nblocks,
        if sample {
            "block of random samples"
        } else {
            "block of grid rows"
        },
    )
    .h5(path)?;

    let rows_per_chunk = g.block_rows.min(nv).min((1usize << 24) / nx.max(1)).max(1);
    // A random sample is a list over `sample` (nx = 1): one dimension less.
    let (shape, chunk): (Vec<usize>, Vec<usize>) = match (sweep, sample) {
        (true, false) => (vec![nmaps, nv, nx], vec![1, rows_per_chunk, nx]),
        (false, false) => (vec![nv, nx], vec![rows_per_chunk, nx]),
        (true, true) => (vec![nmaps, nv], vec![1, rows_per_chunk]),
        (false, true) => (vec![nv], vec![rows_per_chunk]),
    };
    let vars: Vec<Dataset> = COLUMNS
        .iter()
        .map(|col| column_dataset(file, col, col.name, &shape, &chunk))
        .collect::<hdf5::Result<_>>()
        .h5(path)?;
    for v in &vars {
        let d: Vec<&Dataset> = match (sweep, sample) {
            (true, false) => vec![&map_dim, &v0, &x0],
            (false, false) => vec![&v0, &x0],
            (true, true) => vec![&map_dim, &v0],
            (false, true) => vec![&v0],
        };
        dims.attach(file, v, &d).h5(path)?;
    }

    // The landscape of each map (laws with true stick), computed before the writer: one
    // per map, or none at all for laws without it.
    let landscape = |m: usize| landscapes.get(m).and_then(Option::as_ref);

    let mut done = vec![0u8; nmaps * nblocks];
    let mut checks = Vec::with_capacity(nmaps);
    let mut basins = Vec::with_capacity(nmaps);
    let mut cycles: Vec<Option<CycleRecord>> = Vec::with_capacity(nmaps);
    for m in 0..nmaps {
        let cyc = src.cycle(m)?;
        let curve = report_of(&cyc).map(|r| &r.curve);
        let escapes = report_of(&cyc).is_some_and(|r| r.escape.is_some());
        let mut ck = MapChecks::new(curve, landscape(m).map(|l| l.landscape), escapes);
        let mut labels = vec![squeal_scan::cell::NOT_COMPUTED; nx * nv];
        for b in 0..nblocks {
            let Some(cells) = src.block(m, b)? else {
                continue;
            };
            let rows = g.block_rows(b);
            if cells.len() != rows.len() * nx {
                return Err(StoreError::BadBlock {
                    path: path.to_path_buf(),
                    why: format!(
                        "map {m} block {b} holds {} cells, expected {}",
                        cells.len(),
                        rows.len() * nx
                    ),
                });
            }
            done[m * nblocks + b] = 1;
            ck.add_block(plan, curve, b, &cells);
            for (k, c) in cells.iter().enumerate() {
                labels[rows.start * nx + k] = c.regime;
            }
            for (ds, col) in vars.iter().zip(COLUMNS) {
                write_column(
                    ds,
                    col,
                    &cells,
                    if sweep { std::slice::from_ref(&m) } else { &[] },
                    rows.clone(),
                    nx,
                )
                .map_err(|e| StoreError::BadBlock {
                    path: path.to_path_buf(),
                    why: format!("map {m} block {b}: {e}"),
                })?;
            }
        }
        checks.push(ck);
        basins.push(if sample {
            GridShares::random(&labels)
        } else {
            GridShares::of(&labels, nx)
        });
        cycles.push(cyc);
    }

    (|| -> hdf5::Result<()> {
        let bd = Array2::from_shape_vec((nmaps, nblocks), done)
            .map_err(|e| hdf5::Error::from(e.to_string()))?;
        let ds = file
            .new_dataset_builder()
            .obj_track_times(false)
            .with_data(&bd)
            .create("blocks_done")?;
        str_attr(&ds, "long_name", "1 where the block of rows is stored")?;
        dims.attach(file, &ds, &[&map_dim, &block_dim])?;

        // Per-map consistency checks.
        for (i, (name, long)) in CHECK_FIELDS.iter().enumerate() {
            let vals: Array1<i64> = checks.iter().map(|c| c.values()[i]).collect();
            per_map(file, &mut dims, &map_dim, name, &vals, long, "1")?;
        }

        // The landscape and its evidence, for laws with true stick.
        if plan.maps[0].law.has_true_stick() {
            let (name, long) = squeal_scan::landscape::LANDSCAPE;
            let vals: Array1<LandscapeH5> = (0..nmaps)
                .map(|m| LandscapeH5::of(landscape(m).map(|l| l.landscape)))
                .collect();
            let ds = file
                .new_dataset_builder()
                .obj_track_times(false)
                .with_data(&vals)
                .create(name)?;
            str_attr(&ds, "long_name", long)?;
            let flags = squeal_scan::landscape::flags();
            let values: Vec<u8> = flags.iter().map(|(v, _)| *v).collect();
            ds.new_attr::<u8>()
                .shape(values.len())
                .create("flag_values")?
                .write_raw(&values)?;
            let names: Vec<&str> = flags.iter().map(|(_, n)| *n).collect();
            str_attr(&ds, "flag_meanings", &names.join(" "))?;
            dims.attach(file, &ds, &[&map_dim])?;
            for (k, (name, long, units, _)) in
                squeal_scan::landscape::LANDSCAPE_FIELDS.iter().enumerate()
            {
                let vals: Array1<f64> = (0..nmaps)
                    .map(|m| landscape(m).map_or(f64::NAN, |l| l.evidence[k].1))
                    .collect();
                per_map(file, &mut dims, &map_dim, name, &vals, long, units)?;
            }
        }

        // Per-map basin stability (squeal_scan::basin).
        for (i, (name, long)) in BASIN_FIELDS.iter().enumerate() {
            let vals: Array1<f64> = basins.iter().map(|b| b.values()[i]).collect();
            per_map(file, &mut dims, &map_dim, name, &vals, long, "1")?;
        }

        // Cycles.
        let write_cycle = |grp: &Group, dims: &mut Dims, c: &CycleRecord| -> hdf5::Result<()> {
            if let Some(Err(e)) = c {
                str_attr(grp, "error", &e.to_string())?;
            }
            str_attr(grp, "record", &crate::cycle::to_text(c, false))?;
            for (name, v) in crate::cycle::flatten(c) {
                match v {
                    Flat::F64(x) => num_attr(grp, &name, x)?,
                    Flat::I64(x) => num_attr(grp, &name, x)?,
                    Flat::Bool(x) => num_attr(grp, &name, x as u8)?,
                    Flat::Text(x) => str_attr(grp, &name, &x)?,
                    Flat::F64s(x) => grp
                        .new_attr::<f64>()
                        .shape(x.len())
                        .create(name.as_str())?
                        .write_raw(&x)?,
                }
            }
            if let Some(Ok(r)) = c {
                let pt = index_coord(
                    grp,
                    dims,
                    "point",
                    r.curve.len(),
                    "step along the closed curve",
                )?;
                for (name, data, long) in [
                    ("x", &r.curve.x, "displacement x on the cycle"),
                    ("v", &r.curve.v, "velocity x' on the cycle"),
                ] {
                    let ds = grp
                        .new_dataset_builder()
                        .obj_track_times(false)
                        .with_data(data.as_slice())
                        .create(name)?;
                    str_attr(&ds, "long_name", long)?;
                    str_attr(&ds, "units", "1")?;
                    dims.attach(file, &ds, &[&pt])?;
                }
            }
            Ok(())
        };
        let has = |c: &Option<CycleRecord>| matches!(c, Some(Some(_)));
        if sweep {
            if cycles.iter().any(has) {
                let top = file.create_group("cycles")?;
                for (m, c) in cycles.iter().enumerate() {
                    if let Some(c) = c.as_ref().filter(|_| has(&cycles[m])) {
                        let grp = top.create_group(&format!("map_{m:04}"))?;
                        write_cycle(&grp, &mut dims, c)?;
                    }
                }
            }
            let pick = |f: fn(&CycleReport) -> f64| -> Array1<f64> {
                cycles
                    .iter()
                    .map(|c| report_of(c).map_or(f64::NAN, f))
                    .collect()
            };
            let series: [Series; 5] = [
                (
                    "cycle_r_section",
                    |c| c.r_section,
                    "cycle crossing of the section x = x*: x' there",
                ),
                (
                    "cycle_distance_plus_x",
                    |c| c.distance_plus_x,
                    "distance from the fixed point to the cycle along +x",
                ),
                ("cycle_area", |c| c.area, "area enclosed by the cycle"),
                ("cycle_period", |c| c.period, "period of the cycle"),
                (
                    "cycle_multiplier",
                    |c| c.multiplier,
                    "Floquet multiplier of the cycle",
                ),
            ];
            for (name, f, long) in series {
                let ds = file
                    .new_dataset_builder()
                    .obj_track_times(false)
                    .with_data(&pick(f))
                    .create(name)?;
                str_attr(&ds, "long_name", long)?;
                str_attr(&ds, "units", "1")?;
                dims.attach(file, &ds, &[&map_dim])?;
            }
            let enc: Vec<u8> = cycles
                .iter()
                .map(|c| report_of(c).map_or(0, |r| r.encloses_origin as u8))
                .collect();
            let ds = file
                .new_dataset_builder()
                .obj_track_times(false)
                .with_data(&enc)
                .create("cycle_encloses_origin")?;
            str_attr(
                &ds,
                "long_name",
                "1 if the cycle encloses the state at rest",
            )?;
            dims.attach(file, &ds, &[&map_dim])?;
        } else if let Some(c) = cycles[0].as_ref().filter(|_| has(&cycles[0])) {
            let grp = file.create_group("cycle")?;
            write_cycle(&grp, &mut dims, c)?;
        }
        dims.finish()
    })()
    .h5(path)?;
    Ok(checks)
}

/// The located cycle in a stored record, if any.
pub(crate) fn report_of(c: &Option<CycleRecord>) -> Option<&CycleReport> {
    match c {
        Some(Some(Ok(r))) => Some(r),
        _ => None,
    }
}
