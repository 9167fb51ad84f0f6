//! Writes the HDF5 file from a source of blocks and cycles (the journal, or shard files).

use std::path::Path;

use hdf5::types::{FixedAscii, VarLenArray, VarLenUnicode};
use hdf5::{Dataset, File, Group, H5Type, Location, ObjectReference1};
use ndarray::{Array1, Array2};
use squeal_scan::Plan;
use squeal_scan::scanner::Cell;

use crate::error::H5Ctx;
use crate::h5types::{Label, ReasonH5, RefEntry};
use crate::journal::{CycleData, CycleRecord};
use crate::{SCHEMA, StoreError, WrongSide};

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
            .write_raw(&list)?;
        let names: Vec<String> = scales.iter().map(|s| leaf(&s.name())).collect();
        str_attr(var, "dimensions", &names.join(" "))
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

/// A per-map cycle series: dataset name, value, long name.
type Series = (&'static str, fn(&CycleData) -> f64, &'static str);

fn leaf(name: &str) -> String {
    name.rsplit('/').next().unwrap_or(name).to_string()
}

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

struct Vars {
    labels: Dataset,
    reason: Dataset,
    t_decision: Dataset,
    amplitude: Dataset,
    omega: Dataset,
    quasi_static: Dataset,
    evaluations: Dataset,
    fallbacks: Dataset,
    multi_root: Dataset,
    unconverged: Dataset,
    max_residual: Dataset,
}

impl Vars {
    fn all(&self) -> [&Dataset; 11] {
        [
            &self.labels,
            &self.reason,
            &self.t_decision,
            &self.amplitude,
            &self.omega,
            &self.quasi_static,
            &self.evaluations,
            &self.fallbacks,
            &self.multi_root,
            &self.unconverged,
            &self.max_residual,
        ]
    }
}

fn var<T: H5Type>(
    file: &File,
    name: &str,
    shape: &[usize],
    chunk: &[usize],
    fill: T,
    long_name: &str,
) -> hdf5::Result<Dataset> {
    let ds = file
        .new_dataset::<T>()
        .obj_track_times(false)
        .shape(shape)
        .chunk(chunk)
        .deflate(4)
        .fill_value(fill)
        .create(name)?;
    str_attr(&ds, "long_name", long_name)?;
    Ok(ds)
}

/// The rows `rows` of map `map` (sweep) or of the single map: a hyperslab over `(.., v0, x0)`.
pub(crate) fn sel(map: Option<usize>, rows: std::ops::Range<usize>) -> hdf5::Hyperslab {
    let mut v: Vec<hdf5::SliceOrIndex> = Vec::with_capacity(3);
    if let Some(m) = map {
        v.push(m.into());
    }
    v.push(rows.into());
    v.push((..).into());
    hdf5::Hyperslab::from(v)
}

fn write_rows<T: H5Type>(
    ds: &Dataset,
    data: Vec<T>,
    sweep: bool,
    map: usize,
    rows: std::ops::Range<usize>,
    nx: usize,
) -> hdf5::Result<()> {
    let a = Array2::from_shape_vec((rows.len(), nx), data)
        .map_err(|e| hdf5::Error::from(e.to_string()))?;
    if sweep {
        ds.write_slice(&a, sel(Some(map), rows))
    } else {
        ds.write_slice(&a, sel(None, rows))
    }
}

/// Writes the whole file at `path` (which must not exist). Memory: one block at a time.
pub(crate) fn assemble(
    path: &Path,
    plan: &Plan,
    meta: &Meta,
    src: &mut dyn Source,
) -> Result<Vec<Option<WrongSide>>, StoreError> {
    let file = File::create_excl(path).h5(path)?;
    let out = write_all(&file, plan, meta, src, path);
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
) -> Result<Vec<Option<WrongSide>>, StoreError> {
    let g = &plan.grid;
    let (nx, nv, nmaps, nblocks) = (g.x0.count, g.v0.count, plan.maps.len(), g.blocks());
    let sweep = plan.sweep.is_some();
    let mut dims = Dims {
        scales: Vec::new(),
        class_type: class_type(path)?,
    };

    // Root attributes.
    let p0 = plan.maps[0];
    (|| -> hdf5::Result<()> {
        str_attr(file, "schema", SCHEMA)?;
        str_attr(file, "squeal_version", meta.version)?;
        str_attr(file, "git_revision", meta.git_revision)?;
        str_attr(file, "spec", &plan.spec_text)?;
        str_attr(file, "name", &plan.name)?;
        str_attr(file, "law", p0.law.name())?;
        num_attr(file, "tau", p0.tau)?;
        num_attr(file, "phi", p0.phi)?;
        let swept = plan.sweep.as_ref().map(|s| s.name);
        if swept != Some("nu") {
            num_attr(file, "nu", p0.nu)?;
        }
        if swept != Some("lambda") {
            num_attr(file, "lambda", p0.lambda)?;
        }
        num_attr(file, "dt", plan.dt)?;
        str_attr(file, "solver", plan.solver.kind.name())?;
        num_attr(file, "max_iter", plan.solver.max_iter)?;
        num_attr(file, "t_max", plan.classifier.t_max)?;
        num_attr(file, "fp_radius", plan.classifier.fp_radius)?;
        num_attr(file, "settle_cycles", plan.classifier.settle_cycles)?;
        num_attr(file, "settle_rtol", plan.classifier.settle_rtol)?;
        str_attr(file, "early_stop", plan.early_stop.name())?;
        num_attr(file, "trap_margin", plan.trap_margin)?;
        num_attr(file, "locate_cycle", plan.locate_cycle as u8)?;
        num_attr(file, "block_rows", g.block_rows as u64)?;
        if let Some(s) = &meta.shard {
            str_attr(file, "shard", s)?;
        }
        Ok(())
    })()
    .h5(path)?;

    // Coordinates and variables.
    let x0 = coord(
        file,
        &mut dims,
        "x0",
        &g.x0.values(),
        "initial displacement x(0)",
    )
    .h5(path)?;
    let v0 = coord(
        file,
        &mut dims,
        "v0",
        &g.v0.values(),
        "initial velocity x'(0)",
    )
    .h5(path)?;
    let sw = match &plan.sweep {
        Some(s) => {
            let long = if s.name == "nu" {
                "damping ratio nu"
            } else {
                "belt speed lambda"
            };
            Some(coord(file, &mut dims, s.name, &s.values, long).h5(path)?)
        }
        None => None,
    };
    let map_dim = match &sw {
        Some(d) => d.clone(),
        None => index_coord(file, &mut dims, "map", nmaps, "map index").h5(path)?,
    };
    let block_dim =
        index_coord(file, &mut dims, "block", nblocks, "block of grid rows").h5(path)?;

    let rows_per_chunk = g.block_rows.min(nv).min((1usize << 24) / nx.max(1)).max(1);
    let (shape, chunk): (Vec<usize>, Vec<usize>) = if sweep {
        (vec![nmaps, nv, nx], vec![1, rows_per_chunk, nx])
    } else {
        (vec![nv, nx], vec![rows_per_chunk, nx])
    };
    let vars = (|| -> hdf5::Result<Vars> {
        let labels = var(
            file,
            "labels",
            &shape,
            &chunk,
            Label::NotComputed,
            "attractor reached",
        )?;
        let names: Vec<&str> = squeal_core::Regime::ALL.iter().map(|r| r.name()).collect();
        str_attr(
            &labels,
            "flag_meanings",
            &format!("{} not_computed", names.join(" ")),
        )?;
        labels
            .new_attr::<u8>()
            .shape(4)
            .create("flag_values")?
            .write_raw(&[0u8, 1, 2, 255])?;
        Ok(Vars {
            labels,
            reason: var(
                file,
                "reason",
                &shape,
                &chunk,
                ReasonH5::NotComputed,
                "why the run stopped",
            )?,
            t_decision: var(
                file,
                "t_decision",
                &shape,
                &chunk,
                f64::NAN,
                "time at the decision",
            )?,
            amplitude: var(
                file,
                "amplitude",
                &shape,
                &chunk,
                f64::NAN,
                "last section amplitude",
            )?,
            omega: var(
                file,
                "omega",
                &shape,
                &chunk,
                f64::NAN,
                "angular frequency of the last revolution",
            )?,
            quasi_static: var(
                file,
                "quasi_static",
                &shape,
                &chunk,
                0u8,
                "1 if the quasi-static branch was entered",
            )?,
            evaluations: var(
                file,
                "evaluations",
                &shape,
                &chunk,
                0u64,
                "friction-law evaluations",
            )?,
            fallbacks: var(
                file,
                "fallbacks",
                &shape,
                &chunk,
                0u32,
                "bisection fallbacks and bracket expansions",
            )?,
            multi_root: var(
                file,
                "multi_root",
                &shape,
                &chunk,
                0u32,
                "solves with several roots",
            )?,
            unconverged: var(
                file,
                "unconverged",
                &shape,
                &chunk,
                0u32,
                "unconverged or failed solves",
            )?,
            max_residual: var(
                file,
                "max_residual",
                &shape,
                &chunk,
                f64::NAN,
                "largest solver residual",
            )?,
        })
    })()
    .h5(path)?;
    for v in vars.all() {
        let d: Vec<&Dataset> = if sweep {
            vec![&map_dim, &v0, &x0]
        } else {
            vec![&v0, &x0]
        };
        dims.attach(file, v, &d).h5(path)?;
    }

    let mut done = vec![0u8; nmaps * nblocks];
    let mut wrong = Vec::with_capacity(nmaps);
    let mut cycles: Vec<Option<CycleRecord>> = Vec::with_capacity(nmaps);
    let diag = g.x0.spacing().hypot(g.v0.spacing());
    for m in 0..nmaps {
        let cyc = src.cycle(m)?;
        let curve = cyc.as_ref().and_then(|c| c.report.as_ref());
        let mut ws = curve.map(|_| WrongSide {
            cells: 0,
            beyond_pixel: 0,
        });
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
            if let (Some(c), Some(w)) = (curve, ws.as_mut()) {
                for (k, cell) in cells.iter().enumerate() {
                    let (x, v) = (g.x0.value(k % nx), g.v0.value(rows.start + k / nx));
                    let inside = c.encloses(x, v);
                    let bad = (cell.regime == 1 && !inside) || (cell.regime == 2 && inside);
                    if bad {
                        w.cells += 1;
                        if c.distance_to(x, v) > diag {
                            w.beyond_pixel += 1;
                        }
                    }
                }
            }
            let bad = |what: &str, v: u8| StoreError::BadBlock {
                path: path.to_path_buf(),
                why: format!("map {m} block {b}: unknown {what} value {v}"),
            };
            let labels = cells
                .iter()
                .map(|c| Label::from_u8(c.regime).ok_or_else(|| bad("regime", c.regime)))
                .collect::<Result<Vec<_>, _>>()?;
            let reasons = cells
                .iter()
                .map(|c| ReasonH5::from_u8(c.reason).ok_or_else(|| bad("reason", c.reason)))
                .collect::<Result<Vec<_>, _>>()?;
            (|| -> hdf5::Result<()> {
                let r = rows.clone();
                write_rows(&vars.labels, labels, sweep, m, r.clone(), nx)?;
                write_rows(&vars.reason, reasons, sweep, m, r.clone(), nx)?;
                let f = |get: fn(&Cell) -> f64| cells.iter().map(get).collect::<Vec<f64>>();
                write_rows(
                    &vars.t_decision,
                    f(|c| c.t_decision),
                    sweep,
                    m,
                    r.clone(),
                    nx,
                )?;
                write_rows(&vars.amplitude, f(|c| c.amplitude), sweep, m, r.clone(), nx)?;
                write_rows(&vars.omega, f(|c| c.omega), sweep, m, r.clone(), nx)?;
                write_rows(
                    &vars.max_residual,
                    f(|c| c.max_residual),
                    sweep,
                    m,
                    r.clone(),
                    nx,
                )?;
                let u = |get: fn(&Cell) -> u32| cells.iter().map(get).collect::<Vec<u32>>();
                write_rows(&vars.fallbacks, u(|c| c.fallbacks), sweep, m, r.clone(), nx)?;
                write_rows(
                    &vars.multi_root,
                    u(|c| c.multi_root),
                    sweep,
                    m,
                    r.clone(),
                    nx,
                )?;
                write_rows(
                    &vars.unconverged,
                    u(|c| c.unconverged),
                    sweep,
                    m,
                    r.clone(),
                    nx,
                )?;
                let qs: Vec<u8> = cells.iter().map(|c| c.quasi_static).collect();
                write_rows(&vars.quasi_static, qs, sweep, m, r.clone(), nx)?;
                let ev: Vec<u64> = cells.iter().map(|c| c.evaluations).collect();
                write_rows(&vars.evaluations, ev, sweep, m, r, nx)
            })()
            .h5(path)?;
        }
        wrong.push(ws);
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

        // Cycles.
        let write_cycle = |grp: &Group,
                           dims: &mut Dims,
                           c: &CycleRecord,
                           w: Option<WrongSide>|
         -> hdf5::Result<()> {
            if let Some(e) = &c.error {
                str_attr(grp, "error", e)?;
            }
            if let Some(r) = &c.report {
                for (name, v) in r.scalars() {
                    num_attr(grp, name, v)?;
                }
                num_attr(grp, "encloses_origin", r.encloses_origin as u8)?;
                if let Some(v) = r.half_dt_r_section {
                    num_attr(grp, "half_dt_r_section", v)?;
                }
                if let Some(v) = r.half_dt_shift {
                    num_attr(grp, "half_dt_shift", v)?;
                }
                num_attr(grp, "returns", r.returns)?;
                if let Some(v) = r.stable_above {
                    num_attr(grp, "stable_above", v)?;
                }
                if let Some(w) = w {
                    num_attr(grp, "wrong_side_cells", w.cells)?;
                    num_attr(grp, "wrong_side_beyond_pixel", w.beyond_pixel)?;
                }
                let pt = index_coord(grp, dims, "point", r.x.len(), "step along the closed curve")?;
                let x = grp
                    .new_dataset_builder()
                    .obj_track_times(false)
                    .with_data(&r.x)
                    .create("x")?;
                str_attr(&x, "long_name", "cycle x")?;
                let v = grp
                    .new_dataset_builder()
                    .obj_track_times(false)
                    .with_data(&r.v)
                    .create("v")?;
                str_attr(&v, "long_name", "cycle x'")?;
                dims.attach(file, &x, &[&pt])?;
                dims.attach(file, &v, &[&pt])?;
            }
            Ok(())
        };
        let has = |c: &Option<CycleRecord>| {
            c.as_ref()
                .is_some_and(|c| c.report.is_some() || c.error.is_some())
        };
        if sweep {
            if cycles.iter().any(has) {
                let top = file.create_group("cycles")?;
                for (m, c) in cycles.iter().enumerate() {
                    if let Some(c) = c.as_ref().filter(|_| has(&cycles[m])) {
                        let grp = top.create_group(&format!("map_{m:04}"))?;
                        write_cycle(&grp, &mut dims, c, wrong[m])?;
                    }
                }
            }
            let pick = |f: fn(&CycleData) -> f64| -> Array1<f64> {
                cycles
                    .iter()
                    .map(|c| {
                        c.as_ref()
                            .and_then(|c| c.report.as_ref())
                            .map_or(f64::NAN, f)
                    })
                    .collect()
            };
            let series: [Series; 5] = [
                (
                    "cycle_r_section",
                    |c| c.r_section,
                    "cycle crossing of the section",
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
                dims.attach(file, &ds, &[&map_dim])?;
            }
            let enc: Vec<u8> = cycles
                .iter()
                .map(|c| {
                    c.as_ref()
                        .and_then(|c| c.report.as_ref())
                        .map_or(0, |r| r.encloses_origin as u8)
                })
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
            write_cycle(&grp, &mut dims, c, wrong[0])?;
        }
        dims.finish()
    })()
    .h5(path)?;
    Ok(wrong)
}
