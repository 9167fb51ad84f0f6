//! Writes the atlas file: root attributes, coordinates, the points' datasets (one per row
//! of the scan crate's column tables), the maps ([`super::maps`]) and the boundaries'.

use std::path::{Path, PathBuf};

use hdf5::File;
use squeal_core::Scales;
use squeal_scan::atlas::columns::{BOUNDARY_COLUMNS, COLUMNS, boundary_stored, status_meanings};
use squeal_scan::atlas::true_stick::LANDSCAPE_COLUMNS;
use squeal_scan::atlas::{AtlasPlan, AtlasResults, BoundaryParam, BoundaryStatus, PointMap, Units};
use squeal_scan::column::{Column, Kind, Num, Twin};

use super::schema::{
    BOUNDARIES_DONE, BOUNDARY_NOTE, BOUNDARY_NOTE_KIND, FOLD_CHANGES, HALF_DT_FLAGS,
    LANDSCAPE_NOT_COMPUTED, NOTE, NOTE_KIND, Named, POINTS_DONE, REGIME, RegimeH5, SEARCHES,
    StatusH5, half_dt_u8, landscape_flags, note_columns, stored_name,
};
use super::{ATLAS_SCHEMA, maps};
use crate::error::{H5Ctx, io};
use crate::h5out::{Dims, Out, Over, class_type, num_attr, str_attr};
use crate::{Provenance, Shard, StoreError};

/// Writes the atlas file `out` (through `<out>.tmp`, then renamed) from everything stored and
/// what the engine computed from it: each point's map figures ([`squeal_scan::atlas::finish`];
/// none without maps).
pub fn write_atlas(
    out: &Path,
    plan: &AtlasPlan,
    (res, maps): (&AtlasResults, &[PointMap]),
    prov: &Provenance,
    shard: Option<Shard>,
) -> Result<(), StoreError> {
    let mut tmp = out.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    let written = (|| {
        let file = File::create(&tmp).h5(&tmp)?;
        let dims = Dims::new(class_type(&tmp)?);
        let mut o = Out {
            file: &file,
            dims,
            aux: Vec::new(),
        };
        write_all(&mut o, plan, (res, maps), prov, shard).h5(&tmp)?;
        o.dims.finish().h5(&tmp)?;
        file.close().h5(&tmp)
    })();
    if let Err(e) = written {
        // A full disk: leave no partial file; the journal keeps the work for a resume.
        let _ = std::fs::remove_file(&tmp);
        return Err(e);
    }
    std::fs::rename(&tmp, out).map_err(io(out, "cannot rename the finished file to"))?;
    Ok(())
}

fn write_all(
    o: &mut Out,
    plan: &AtlasPlan,
    (res, point_maps): (&AtlasResults, &[PointMap]),
    prov: &Provenance,
    shard: Option<Shard>,
) -> hdf5::Result<()> {
    root_attrs(o.file, plan, prov, shard)?;
    // A physical atlas's table is the measured one, in m/s (AtlasPlan::table).
    let (nd, si) = match plan.space.units {
        Units::Physical => (None, plan.space.table),
        Units::Nondimensional => (plan.space.table, None),
    };
    crate::h5out::friction_table(o.file, &mut o.dims, nd, si)?;
    let scales = plan
        .space
        .axes()
        .iter()
        .map(|a| o.scale(a.key, &a.values, a.long_name, Some(a.units)))
        .collect::<hdf5::Result<Vec<_>>>()?;
    let points = if scales.is_empty() {
        let s = o.index("point", 1, "the single parameter point")?;
        Over {
            shape: vec![1],
            scales: vec![s],
        }
    } else {
        Over {
            shape: plan.space.shape(),
            scales: scales.clone(),
        }
    };
    write_points(o, &points, plan, (res, point_maps))?;
    if plan.n_boundaries() > 0 {
        // The boundaries lie over the swept axes but the bisected one.
        let (_, d) = plan.boundary_axis();
        let rest: Vec<_> = (scales.iter().enumerate())
            .filter(|(k, _)| Some(*k) != d)
            .map(|(_, s)| s.clone())
            .collect();
        let over = if rest.is_empty() {
            let s = o.index("boundary", 1, "the single boundary search")?;
            Over {
                shape: vec![1],
                scales: vec![s],
            }
        } else {
            Over {
                shape: plan.boundary_shape(),
                scales: rest,
            }
        };
        write_boundaries(o, &over, plan, res)?;
    }
    Ok(())
}

/// Provenance, the spec and the settings every point shares.
fn root_attrs(
    file: &File,
    plan: &AtlasPlan,
    prov: &Provenance,
    shard: Option<Shard>,
) -> hdf5::Result<()> {
    for (k, v) in [
        ("schema", ATLAS_SCHEMA),
        ("squeal_version", &prov.version),
        ("git_revision", &prov.git_revision),
        ("spec", &plan.spec_text),
        ("name", &plan.name),
        ("law", plan.space.law.name()),
        ("units", plan.space.units.name()),
        ("solver", plan.solver.kind.name()),
        ("scheme", plan.solver.scheme.name()),
    ] {
        str_attr(file, k, v)?;
    }
    num_attr(file, "dt", plan.dt)?;
    for (a, v) in plan.space.fixed() {
        num_attr(file, a.key, v)?;
        str_attr(file, &format!("{}_units", a.key), a.units)?;
    }
    let ps = &plan.point;
    let op_units = match plan.space.units {
        Units::Physical => ["m", "m/s"],
        Units::Nondimensional => ["1", "1"],
    };
    for ((k, v), u) in [("x", ps.operating.x), ("v", ps.operating.v)]
        .into_iter()
        .zip(op_units)
    {
        num_attr(file, &format!("operating_point_{k}"), v)?;
        str_attr(file, &format!("operating_point_{k}_units"), u)?;
    }
    for ((k, r), u) in [
        ("disturbance_x", ps.disturbance.x),
        ("disturbance_v", ps.disturbance.v),
    ]
    .into_iter()
    .zip(plan.disturbance_units())
    {
        file.new_attr::<f64>().shape(2).create(k)?.write_raw(&r)?;
        str_attr(file, &format!("{k}_units"), u)?;
    }
    if let Some(s) = shard {
        str_attr(file, "shard", &s.to_string())?;
    }
    Ok(())
}

/// Every dataset over the parameter points (the maps' included).
fn write_points(
    o: &mut Out,
    over: &Over,
    plan: &AtlasPlan,
    (res, point_maps): (&AtlasResults, &[PointMap]),
) -> hdf5::Result<()> {
    let pts = &res.points;
    let regimes = pts
        .iter()
        .map(|p| RegimeH5::from(p.as_ref().map(|p| p.regime)));
    let (meanings, values) = RegimeH5::flags();
    o.put_flags(over, REGIME, regimes.collect(), (&meanings, &values))?;
    let scales: Vec<Option<Scales>> = (0..plan.space.n_points())
        .map(|i| plan.space.physical_at(i).map(|p| p.scales()))
        .collect();
    for c in COLUMNS {
        put_column(o, (over, plan), c, stored_name(plan, c), (pts, &scales))?;
    }
    if plan.space.units == Units::Physical {
        // The nondimensional parameters of each point, beside the physical axes.
        let nd = squeal_scan::atlas::spec::NONDIMENSIONAL;
        let ps: Vec<squeal_core::Params> = (0..plan.space.n_points())
            .map(|i| plan.space.params_at(i))
            .collect();
        // The law's own keys only (Coulomb has no tau and phi).
        for (key, long, units) in nd
            .iter()
            .filter(|(k, ..)| plan.space.law.keys().contains(k))
        {
            let value = |p: &squeal_core::Params| {
                let n = p.named().into_iter().find(|n| n.name == *key);
                n.expect("a key of the law").value
            };
            let v: Vec<f64> = ps.iter().map(value).collect();
            o.put(over, (&format!("nondim_{key}"), long), Some(units), v)?;
        }
        // A block under its own weight: its normal force m g at each point (one given is an
        // axis of its own).
        if !plan.space.params.iter().any(|a| a.key == "normal_force") {
            let n: Vec<f64> = (0..plan.space.n_points())
                .filter_map(|i| plan.space.physical_at(i).map(|p| p.normal_force()))
                .collect();
            let long = "normal force N = m g (the block's weight; friction is mu N)";
            o.put(over, ("normal_force", long), Some("N"), n)?;
        }
    }
    if plan.space.law.family().has_landscape() {
        write_landscape(o, (over, plan), (res, &scales))?;
    }
    let (notes, kinds) = note_columns(pts.iter().map(|p| p.as_ref().and_then(|p| p.note.as_ref())));
    o.put_notes(over, NOTE, notes.into_iter())?;
    put_note_kinds(o, over, NOTE_KIND, kinds)?;
    if plan.maps.is_some() {
        maps::write_maps(o, over, plan, (res, point_maps))?;
    }
    let done: Vec<u8> = pts.iter().map(|p| u8::from(p.is_some())).collect();
    o.put(over, POINTS_DONE, None, done)?;
    Ok(())
}

/// One column of the points or the boundary searches, as its [`Kind`] stores it with its
/// CF attributes (`rows`: one record each, the fill where `None`: not computed), and its SI
/// twin in a physical plan (`scales`: each record's, `None` in nondimensional plans).
fn put_column<R>(
    o: &mut Out,
    (over, plan): (&Over, &AtlasPlan),
    c: &Column<R>,
    (name, long): (String, String),
    (rows, scales): (&[Option<R>], &[Option<Scales>]),
) -> hdf5::Result<()> {
    let vals: Vec<Num> = (rows.iter())
        .map(|r| r.as_ref().map_or(c.fill, |r| (c.get)(r)))
        .collect();
    let named = (name.as_str(), long.as_str());
    let units = (!c.units.is_empty()).then_some(c.units);
    let u = || vals.iter().map(|v| v.as_u64());
    match c.kind {
        Kind::F64 => o.put(
            over,
            named,
            units,
            vals.iter().map(|v| v.as_f64()).collect(),
        )?,
        Kind::Enum => {
            let meanings: Vec<&str> = c.flags.iter().map(|(_, n)| *n).collect();
            let values: Vec<u8> = c.flags.iter().map(|(v, _)| *v).collect();
            let v = u().map(|v| v as u8).collect();
            o.put_flags(over, named, v, (&meanings.join(" "), &values))?
        }
        Kind::U8 => o.put(over, named, units, u().map(|v| v as u8).collect())?,
        Kind::U32 => o.put(over, named, units, u().map(|v| v as u32).collect())?,
        Kind::U64 => o.put(over, named, units, u().collect())?,
    };
    if plan.space.units == Units::Physical {
        let x: Vec<f64> = vals.iter().map(|v| v.as_f64()).collect();
        put_twin(o, (over, plan), c, named, (&x, scales))?;
    }
    Ok(())
}

/// The SI twin of a column of a physical plan ([`Twin`]), `x` its values.
fn put_twin<R>(
    o: &mut Out,
    (over, plan): (&Over, &AtlasPlan),
    c: &Column<R>,
    (name, long): (&str, &str),
    (x, scales): (&[f64], &[Option<Scales>]),
) -> hdf5::Result<()> {
    match c.si {
        Twin::None => {}
        Twin::Named(..) | Twin::Si(_) => {
            let (si, si_long) = c.si_twin().expect("a column with an SI twin");
            let v: Vec<f64> = (x.iter().zip(scales))
                .map(|(&v, s)| s.map_or(f64::NAN, |s| c.si_of(v, &s)))
                .collect();
            o.put(
                over,
                (&format!("{}_si", c.name), &si_long),
                Some(si.units()),
                v,
            )?;
        }
        Twin::Bisected => write_boundary_si(o, over, plan, (name, long), x)?,
        Twin::Seconds => write_boundary_seconds(o, over, (name, long), (x, scales))?,
    }
    Ok(())
}

/// Laws with true stick: the landscape of each point (as `squeal scan` stores per map) and
/// its evidence.
fn write_landscape(
    o: &mut Out,
    (over, plan): (&Over, &AtlasPlan),
    (res, scales): (&AtlasResults, &[Option<Scales>]),
) -> hdf5::Result<()> {
    let v: Vec<u8> = (res.points.iter())
        .map(|p| p.as_ref().and_then(|p| p.landscape))
        .map(|l| l.map_or(LANDSCAPE_NOT_COMPUTED, |l| l.landscape))
        .collect();
    let (meanings, values) = landscape_flags();
    let landscape = squeal_scan::landscape::LANDSCAPE;
    o.put_flags(over, landscape, v, (&meanings, &values))?;
    for c in LANDSCAPE_COLUMNS {
        let named = (c.name.to_string(), c.long_name.to_string());
        put_column(o, (over, plan), c, named, (&res.points, scales))?;
    }
    Ok(())
}

/// Every dataset over the boundary searches.
fn write_boundaries(
    o: &mut Out,
    over: &Over,
    plan: &AtlasPlan,
    res: &AtlasResults,
) -> hdf5::Result<()> {
    let bs = &res.boundaries;
    let statuses = status_meanings();
    for s in &SEARCHES {
        let v = bs.iter().map(|b| {
            StatusH5::from(
                b.as_ref()
                    .map_or(BoundaryStatus::NotComputed, |b| (s.get)(b).status),
            )
        });
        let named = (s.status_name(), (s.status_long)(plan));
        o.put_flags(
            over,
            (&named.0, named.1),
            v.collect(),
            (&statuses, &[0, 1, 2, 255]),
        )?;
    }
    for s in &SEARCHES {
        let v = bs
            .iter()
            .map(|b| half_dt_u8(b.as_ref().and_then(|b| (s.get)(b).half_dt_holds)));
        o.put_flags(
            over,
            (&s.half_dt_name(), s.half_dt_long),
            v.collect(),
            HALF_DT_FLAGS,
        )?;
    }
    // Each search's scales: those of the point it starts from.
    let scales: Vec<Option<Scales>> = (0..bs.len())
        .map(|j| {
            plan.space
                .physical_at(plan.boundary_setup(j).0)
                .map(|p| p.scales())
        })
        .collect();
    for c in BOUNDARY_COLUMNS.iter().filter(|c| boundary_stored(plan, c)) {
        let named = plan.boundary_dataset(c.name, c.long_name);
        put_column(o, (over, plan), c, named, (bs, &scales))?;
    }
    let (notes, kinds) = note_columns(bs.iter().map(|b| b.as_ref().and_then(|b| b.note.as_ref())));
    o.put_notes(over, BOUNDARY_NOTE, notes.into_iter())?;
    put_note_kinds(o, over, BOUNDARY_NOTE_KIND, kinds)?;
    let changes: Vec<u32> = bs
        .iter()
        .map(|b| b.as_ref().map_or(0, |b| b.fold.changes))
        .collect();
    o.put(over, FOLD_CHANGES, Some("1"), changes)?;
    let done: Vec<u8> = bs.iter().map(|b| u8::from(b.is_some())).collect();
    o.put(over, BOUNDARIES_DONE, None, done)?;
    Ok(())
}

/// A boundary figure of a physical spec in SI units: `fold_c` (N s/m) for `fold_nu`,
/// `fold_v_belt` (m/s) for `fold_lambda`.
fn write_boundary_si(
    o: &mut Out,
    over: &Over,
    plan: &AtlasPlan,
    (name, long): (&str, &str),
    v: &[f64],
) -> hdf5::Result<()> {
    let mut units = "";
    let si: Vec<f64> = (v.iter().enumerate())
        .map(|(j, &x)| {
            let (i, _) = plan.boundary_setup(j);
            plan.boundary_si(i, x).map_or(f64::NAN, |(y, u)| {
                units = u;
                y
            })
        })
        .collect();
    let (key, _) = plan.boundary_axis();
    let long = match plan.boundary_in {
        BoundaryParam::Nu => long
            .replace("damping ratio xi", "damping coefficient c")
            .replace("damping ratio", "damping coefficient c"),
        BoundaryParam::Lambda => long
            .replace("belt speed lambda", "belt speed v_belt")
            .replace("belt speed v_d", "belt speed v_belt"),
    };
    // The stored name carries the law's key (`critical_xi` for a table law): its SI twin
    // the physical key (`critical_c`).
    let name = name.replace(&format!("_{}", plan.boundary_key()), &format!("_{key}"));
    o.put(over, (&name, &long), Some(units), si)?;
    Ok(())
}

/// A boundary figure of a physical spec that is a nondimensional time, in seconds:
/// `<name>_s` (the time unit at each boundary's parameters, `scales`).
fn write_boundary_seconds(
    o: &mut Out,
    over: &Over,
    (name, long): (&str, &str),
    (v, scales): (&[f64], &[Option<Scales>]),
) -> hdf5::Result<()> {
    let s: Vec<f64> = (v.iter().zip(scales))
        .map(|(&x, s)| s.map_or(f64::NAN, |s| x * s.time))
        .collect();
    let long = long.replace("nondimensional time; the natural period is 2 pi", "seconds");
    o.put(over, (&format!("{name}_s"), &long), Some("s"), s)?;
    Ok(())
}

/// The kinds of the notes ([`squeal_scan::atlas::NoteKind`]) as flags, 0 where there is none.
fn put_note_kinds(o: &mut Out, over: &Over, named: Named, kinds: Vec<u8>) -> hdf5::Result<()> {
    let flags = squeal_scan::atlas::NoteKind::flags();
    let values: Vec<u8> = flags.iter().map(|(v, _)| *v).collect();
    let names: Vec<&str> = flags.iter().map(|(_, n)| *n).collect();
    o.put_flags(over, named, kinds, (&names.join(" "), &values))?;
    Ok(())
}
