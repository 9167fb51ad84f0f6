//! The parts of a scan's HDF5 file ([`crate::assembly`] puts them together): root
//! attributes, coordinates, the cell columns' datasets, the per-map checks, landscape and
//! basin stability, and the cycles.

use std::path::Path;

use crate::LandscapeInfo;
use hdf5::{Dataset, File, Group};
use squeal_scan::BASIN_FIELDS;
use squeal_scan::cell::COLUMNS;
use squeal_scan::checks::CHECK_FIELDS;
use squeal_scan::finish::{STEADY_SLIP, STEADY_SLIP_GROWTH};
use squeal_scan::sensitivity::Sensitivity;
use squeal_scan::si::Si;
use squeal_scan::space::si_twin;
use squeal_scan::ulc::CycleReport;
use squeal_scan::{Grid, MapFigures, Plan, Starts};

use crate::cycle::CycleRecord;
use crate::cycle::Flat;
use crate::error::H5Ctx;
use crate::h5out::{Out, Over, num_attr, str_attr};
use crate::h5types::LandscapeH5;
use crate::{SCHEMA, StoreError};

/// What goes in the root attributes besides the plan.
pub(crate) struct Meta<'a> {
    pub version: &'a str,
    pub git_revision: &'a str,
    pub shard: Option<String>,
}

use crate::h5columns::si_dataset;
pub(crate) use crate::h5columns::write_si_column;
pub(crate) use crate::h5columns::{column_dataset, is_list, sel, write_column};

/// A physical spec's system (`physical_<key>` with `physical_<key>_units`; a swept key is
/// left out: it is a coordinate over the maps, the SI twin of the model's key, [`si_coordinates`]) and
/// the SI size of one nondimensional unit. A system without McMillan's surfaces (Coulomb)
/// has no `physical_mu_s` and `physical_tau` (files of older versions carry the values they
/// were given, which that law never used). `physical_normal_force` (N) is always there: the
/// force given, or the weight `m g` of a block under its own weight (then `physical_g` is
/// there too).
pub(crate) fn physical_attrs(
    file: &File,
    ph: &squeal_core::Physical,
    swept: &[&str],
) -> hdf5::Result<()> {
    let mut values = ph.values();
    values[8] = Some(ph.normal_force());
    // A swept key's SI twin is a coordinate over the maps, no attribute.
    let skip = |key: &str| (swept.iter()).any(|m| si_twin(m).is_some_and(|(p, _)| p == key));
    for ((key, long, units), v) in squeal_scan::atlas::spec::PHYSICAL.iter().zip(values) {
        let Some(v) = v.filter(|_| !skip(key)) else {
            continue;
        };
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
pub(crate) fn root_attrs(file: &File, plan: &Plan, meta: &Meta) -> hdf5::Result<()> {
    let g = &plan.map.grid;
    let p0 = plan.maps[0];
    str_attr(file, "schema", SCHEMA)?;
    str_attr(file, "squeal_version", meta.version)?;
    str_attr(file, "git_revision", meta.git_revision)?;
    str_attr(file, "spec", &plan.spec_text)?;
    str_attr(file, "name", &plan.name)?;
    str_attr(file, "law", p0.kind().name())?;
    let swept = plan.sweep.as_ref().map_or(Vec::new(), |s| s.names());
    if let Some(s) = plan.sweep.as_ref().filter(|s| !is_legacy(s)) {
        // Readers find the sweep by this list (files before it: by the four names).
        str_attr(file, "swept", &s.names().join(" "))?;
    }
    if p0.law.family().has_own_names() {
        // The law's own parameters, each with its long name and units beside it.
        for n in p0.named() {
            if !swept.contains(&n.name) {
                num_attr(file, n.name, n.value)?;
            }
            str_attr(file, &format!("{}_long_name", n.name), n.long_name)?;
            str_attr(file, &format!("{}_units", n.name), n.units)?;
        }
    } else {
        if let Some(c) = p0.law.surface() {
            for (key, v) in [("tau", c.tau), ("phi", c.phi)] {
                if !swept.contains(&key) {
                    num_attr(file, key, v)?;
                }
            }
        }
        for (key, v) in [("nu", p0.nu), ("lambda", p0.lambda)] {
            if !swept.contains(&key) {
                num_attr(file, key, v)?;
            }
        }
    }
    if let Some(ph) = &plan.physical() {
        physical_attrs(file, ph, &swept)?;
    }
    num_attr(file, "dt", plan.dt)?;
    str_attr(file, "solver", plan.solver.kind.name())?;
    str_attr(file, "scheme", plan.solver.scheme.name())?;
    num_attr(file, "max_iter", plan.solver.max_iter)?;
    num_attr(file, "t_max", plan.map.classifier.t_max)?;
    num_attr(file, "fp_radius", plan.map.classifier.fp_radius)?;
    num_attr(file, "settle_cycles", plan.map.classifier.settle_cycles)?;
    num_attr(file, "settle_rtol", plan.map.classifier.settle_rtol)?;
    str_attr(file, "early_stop", plan.map.early_stop.name())?;
    num_attr(file, "trap_margin", plan.map.trap_margin)?;
    num_attr(file, "locate_cycle", plan.cycle.locate as u8)?;
    num_attr(file, "block_rows", g.block_rows as u64)?;
    match &g.starts {
        Starts::Grid => str_attr(file, "sampling", "grid")?,
        Starts::Sample(smp) => {
            str_attr(file, "sampling", "random")?;
            num_attr(file, "sample_n", smp.n as u64)?;
            num_attr(file, "sample_seed", smp.seed)?;
            num_attr(file, "sample_x0_min", g.x0.min)?;
            num_attr(file, "sample_x0_max", g.x0.max)?;
            num_attr(file, "sample_v0_min", g.v0.min)?;
            num_attr(file, "sample_v0_max", g.v0.max)?;
        }
    }
    num_attr(file, "audit_every", plan.map.audit_every)?;
    num_attr(file, "sensitivity_samples", plan.map.sensitivity_samples)?;
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
            .with_data(&plan.map.grid.x0.values())
            .create("x0")?;
        f.close()
    })()
    .h5(path);
    let _ = std::fs::remove_file(&scratch);
    res
}

/// The dimension scales of a scan file.
pub(crate) struct Scales {
    /// The grid's columns, or a random sample's index.
    pub x0: Dataset,
    /// The grid's rows, or a random sample's index.
    pub v0: Dataset,
    /// The swept parameter, or the map index.
    pub map: Dataset,
    pub block: Dataset,
}

/// Coordinates: a grid's axes x0 (columns) and v0 (rows), or a random sample's index with
/// the points' x0 and v0 as variables over it; the sweep or map index; the blocks.
pub(crate) fn scales(o: &mut Out, plan: &Plan) -> hdf5::Result<Scales> {
    let g = &plan.map.grid;
    let (x0, v0) = match g.starts {
        Starts::Sample(_) => sample_scales(o, g)?,
        Starts::Grid => (
            o.scale("x0", &g.x0.values(), "initial displacement x(0)", Some("1"))?,
            o.scale("v0", &g.v0.values(), "initial velocity x'(0)", Some("1"))?,
        ),
    };
    let map = match &plan.sweep {
        Some(s) => sweep_scales(o, plan, s)?,
        None => o.index("map", plan.maps.len(), "map index")?,
    };
    let block = match g.starts {
        Starts::Sample(_) => "block of random samples",
        Starts::Grid => "block of grid rows",
    };
    let block = o.index("block", g.blocks(), block)?;
    if let Some(ph) = &plan.physical() {
        si_coordinates(o, plan, &ph.scales(), [&x0, &v0, &map])?;
    }
    Ok(Scales { x0, v0, map, block })
}

/// Whether a sweep is stored as files before sweeps of every key were: one of `nu`,
/// `lambda`, `xi`, `v_d` swept alone (readers find it by that name, with no `swept` list).
fn is_legacy(s: &squeal_scan::Sweep) -> bool {
    s.single()
        .is_some_and(|a| ["nu", "lambda", "xi", "v_d"].contains(&a.name))
}

/// The maps' dimension of a sweep: one swept key is the dimension scale itself (`nu` over
/// its values); several make the index `map` (C order, the last key fastest) with each
/// key's value at every map as an auxiliary coordinate over it.
fn sweep_scales(o: &mut Out, plan: &Plan, s: &squeal_scan::Sweep) -> hdf5::Result<Dataset> {
    let named = plan.maps[0].named();
    // Units "1": every swept key is in the model's units (as files before sweeps of
    // every key stored `nu`, `lambda`, `xi` and `v_d`).
    let words = |key: &'static str| {
        (named.iter().find(|n| n.name == key)).map_or((key, "1"), |n| (n.long_name, "1"))
    };
    if let Some(a) = s.single() {
        let (long, units) = words(a.name);
        return o.scale(a.name, &a.values, long, Some(units));
    }
    let long = "map index (one map per point of the swept keys' product, the last fastest)";
    let map = o.index("map", plan.maps.len(), long)?;
    let over = Over {
        shape: vec![plan.maps.len()],
        scales: vec![map.clone()],
    };
    for a in &s.axes {
        let (long, units) = words(a.name);
        let per_map = s.per_map(a.name).expect("a swept key");
        o.put(&over, (a.name, long), Some(units), per_map)?;
        o.aux_coordinate(&map, a.name);
    }
    Ok(map)
}

/// A physical scan's coordinates in SI units beside the nondimensional ones (CF auxiliary
/// coordinates, named in the `coordinates` attribute of every variable over their
/// dimension): `x0_si` (m) and `v0_si` (m/s) over the grid's axes (or the random sample's
/// index), and each swept `[physical]` key as given (`c` in N s/m, `v_belt` in m/s, `mu_s`,
/// `tau_si` in s) over the maps, beside the model's key it became (`nu` or `xi`, `lambda`
/// or `v_d`, `phi`, `tau`; [`squeal_scan::space::si_twin`]). One nondimensional unit is
/// the same length, velocity, time and damping at every map (the units depend on m, k,
/// mu_k and the load, which a scan does not sweep).
fn si_coordinates(
    o: &mut Out,
    plan: &Plan,
    s: &squeal_core::Scales,
    [x0, v0, map]: [&Dataset; 3],
) -> hdf5::Result<()> {
    let over = |d: &Dataset| Over {
        shape: vec![d.size()],
        scales: vec![d.clone()],
    };
    let mut aux = state_si(o, &plan.map.grid, s, [x0, v0])?;
    for sw in plan.sweep.iter() {
        for a in &sw.axes {
            let Some((si, per_map)) = sw.si_per_map(a.name) else {
                continue;
            };
            let (_, name) = si_twin(a.name).expect("a physical scan's swept key has a twin");
            o.put(&over(map), (&name, si.long_name), Some(si.units), per_map)?;
            aux.push((map, name));
        }
    }
    for (d, name) in aux {
        o.aux_coordinate(d, &name);
    }
    Ok(())
}

/// The SI twins `x0_si` (m) and `v0_si` (m/s) of the starts of `g` over their scales `x0`
/// and `v0` (a random sample's: both its index), by the scales `s`; returns each scale
/// with its twin's name, to declare as auxiliary coordinates once every twin is written.
pub(crate) fn state_si<'d>(
    o: &mut Out,
    g: &Grid,
    s: &squeal_core::Scales,
    [x0, v0]: [&'d Dataset; 2],
) -> hdf5::Result<Vec<(&'d Dataset, String)>> {
    let (xs, vs): (Vec<f64>, Vec<f64>) = match g.starts {
        Starts::Sample(_) => (0..g.v0.count).map(|i| g.state(i, 0)).unzip(),
        Starts::Grid => (g.x0.values(), g.v0.values()),
    };
    let mut aux = Vec::new();
    for (name, d, vals, unit, units, long) in [
        (
            "x0_si",
            x0,
            xs,
            s.length,
            "m",
            "initial displacement x(0) (metres)",
        ),
        (
            "v0_si",
            v0,
            vs,
            s.velocity,
            "m/s",
            "initial velocity x'(0) (m/s)",
        ),
    ] {
        let over = Over {
            shape: vec![d.size()],
            scales: vec![d.clone()],
        };
        let si = vals.iter().map(|v| v * unit).collect();
        o.put(&over, (name, long), Some(units), si)?;
        aux.push((d, name.to_string()));
    }
    Ok(aux)
}

/// A random sample's index (as both x0 and v0 scales), with its points' x0 and v0.
fn sample_scales(o: &mut Out, g: &Grid) -> hdf5::Result<(Dataset, Dataset)> {
    let nv = g.v0.count;
    let idx = o.index("sample", nv, "random sample index")?;
    let pts: Vec<(f64, f64)> = (0..nv).map(|i| g.state(i, 0)).collect();
    let over = Over {
        shape: vec![nv],
        scales: vec![idx.clone()],
    };
    let x = ("x0", "initial displacement x(0) of the sample");
    o.put(&over, x, Some("1"), pts.iter().map(|p| p.0).collect())?;
    let v = ("v0", "initial velocity x'(0) of the sample");
    o.put(&over, v, Some("1"), pts.iter().map(|p| p.1).collect())?;
    Ok((idx.clone(), idx))
}

/// The datasets of the cell columns, empty (filled block by block), over (map, v0, x0):
/// without the map for one map, without x0 for a random sample (a list over `sample`).
/// A physical scan also has each column's SI twin ([`si_dataset`]), after the columns.
pub(crate) fn cell_vars(o: &mut Out, plan: &Plan, sc: &Scales) -> hdf5::Result<CellVars> {
    let g = &plan.map.grid;
    let (nx, nv) = (g.x0.count, g.v0.count);
    let rows_per_chunk = g.block_rows.min(nv).min((1usize << 24) / nx.max(1)).max(1);
    let mut over = Over {
        shape: Vec::new(),
        scales: Vec::new(),
    };
    let mut chunk = Vec::new();
    if plan.sweep.is_some() {
        over = over.and(plan.maps.len(), &sc.map);
        chunk.push(1);
    }
    over = over.and(nv, &sc.v0);
    chunk.push(rows_per_chunk);
    if !g.is_sample() {
        over = over.and(nx, &sc.x0);
        chunk.push(nx);
    }
    let vars: Vec<Dataset> = COLUMNS
        .iter()
        .map(|col| column_dataset(o.file, col, col.name, &over.shape, &chunk))
        .collect::<hdf5::Result<_>>()?;
    let mut si = Vec::new();
    if plan.physical().is_some() {
        for col in COLUMNS {
            if let Some(ds) = si_dataset(o.file, col, &over.shape, &chunk)? {
                si.push((ds, col));
            }
        }
    }
    let scales: Vec<&Dataset> = over.scales.iter().collect();
    for v in vars.iter().chain(si.iter().map(|(d, _)| d)) {
        o.dims.attach(o.file, v, &scales)?;
        o.declare_coordinates(v, &over)?;
    }
    let scales = plan.physical().as_ref().map(|ph| ph.scales());
    Ok(CellVars {
        vars,
        si,
        scales,
        chunk_rows: rows_per_chunk,
    })
}

/// The datasets of the cell columns ([`cell_vars`]) and, in a physical scan, their SI twins
/// with the scales that convert them.
pub(crate) struct CellVars {
    pub vars: Vec<Dataset>,
    pub si: Vec<(Dataset, &'static squeal_scan::Column)>,
    pub scales: Option<squeal_core::Scales>,
    /// Rows of the grid per chunk.
    pub chunk_rows: usize,
}

/// The per-map datasets over `over` (the map dimension): the blocks stored (with `block`),
/// the checks, the landscape and its evidence (laws with true stick), basin stability.
pub(crate) fn per_map<'l>(
    o: &mut Out,
    plan: &Plan,
    (over, block): (&Over, &Dataset),
    (done, figures): (Vec<u8>, &[MapFigures]),
    landscape: &dyn Fn(usize) -> Option<&'l LandscapeInfo>,
) -> hdf5::Result<()> {
    let nmaps = plan.maps.len();
    let blocks = over.and(plan.map.grid.blocks(), block);
    let named = ("blocks_done", "1 where the block of rows is stored");
    o.put(&blocks, named, None, done)?;
    for (i, named) in CHECK_FIELDS.iter().enumerate() {
        let vals: Vec<i64> = figures.iter().map(|f| f.checks.values()[i]).collect();
        o.put(over, *named, Some("1"), vals)?;
    }
    if plan.maps[0].law.family().has_landscape() {
        let vals: Vec<LandscapeH5> = (0..nmaps)
            .map(|m| LandscapeH5::of(landscape(m).map(|l| l.landscape)))
            .collect();
        let flags = squeal_scan::landscape::flags();
        let values: Vec<u8> = flags.iter().map(|(v, _)| *v).collect();
        let names: Vec<&str> = flags.iter().map(|(_, n)| *n).collect();
        let named = squeal_scan::landscape::LANDSCAPE;
        o.put_flags(over, named, vals, (&names.join(" "), &values))?;
        for (k, (name, long, units, _)) in
            squeal_scan::landscape::LANDSCAPE_FIELDS.iter().enumerate()
        {
            let vals: Vec<f64> = (0..nmaps)
                .map(|m| landscape(m).map_or(f64::NAN, |l| l.evidence[k].1))
                .collect();
            o.put(over, (name, long), Some(units), vals)?;
        }
    }
    // Steady slip's own stability (squeal_core::steady), and its growth rate in 1/s in a
    // physical scan.
    let values: Vec<u8> = squeal_core::Stability::ALL
        .iter()
        .map(|s| *s as u8)
        .collect();
    let names: Vec<&str> = squeal_core::Stability::ALL
        .iter()
        .map(|s| s.name())
        .collect();
    let stab: Vec<u8> = figures.iter().map(|f| f.steady.stability as u8).collect();
    o.put_flags(over, STEADY_SLIP, stab, (&names.join(" "), &values))?;
    let growth: Vec<f64> = figures.iter().map(|f| f.steady.growth).collect();
    o.put(over, STEADY_SLIP_GROWTH, Some("1"), growth.clone())?;
    if let Some(s) = plan.physical().map(|ph| ph.scales()) {
        let (name, long) = STEADY_SLIP_GROWTH;
        let si = growth.iter().map(|&g| Si::Rate.convert(g, &s)).collect();
        let named = (
            &format!("{name}_si") as &str,
            &format!("{long} (1/s)") as &str,
        );
        o.put(over, named, Some(Si::Rate.units()), si)?;
    }
    // Basin stability (squeal_scan::basin).
    for (i, named) in BASIN_FIELDS.iter().enumerate() {
        let vals: Vec<f64> = figures.iter().map(|f| f.shares.values()[i]).collect();
        o.put(over, *named, Some("1"), vals)?;
    }
    let maps: Vec<Option<Sensitivity>> = figures.iter().map(|f| Some(f.sensitivity)).collect();
    sensitivity(o, over, "", &maps)
}

/// The final-state sensitivity per map (squeal_scan::sensitivity): its table of figures,
/// the log 2 test's verdict, and the changed starts per perturbation size; each name
/// after `prefix` (an atlas's `map_`). A map without one (not complete) holds NaN, the
/// test `no_boundary` and no count.
pub(crate) fn sensitivity(
    o: &mut Out,
    over: &Over,
    prefix: &str,
    maps: &[Option<Sensitivity>],
) -> hdf5::Result<()> {
    use squeal_scan::sensitivity::{EPS_LEVELS, Log2Test, SENSITIVITY_FIELDS, eps_levels};
    let name = |n: &str| format!("{prefix}{n}");
    for (i, (n, long, units, _)) in SENSITIVITY_FIELDS.iter().enumerate() {
        let vals: Vec<f64> = maps
            .iter()
            .map(|s| s.map_or(f64::NAN, |s| s.values()[i]))
            .collect();
        o.put(over, (&name(n), long), Some(units), vals)?;
    }
    let names: Vec<&str> = Log2Test::ALL.iter().map(|t| t.name()).collect();
    let values: Vec<u8> = Log2Test::ALL.iter().map(|t| *t as u8).collect();
    let verdicts: Vec<u8> = maps
        .iter()
        .map(|s| s.map_or(Log2Test::NoBoundary, |s| s.log2_test()) as u8)
        .collect();
    let long = "log 2 test of the boundary (Puy et al. 2021): fractal where boundary_basin_entropy > ln 2; inconclusive otherwise (always so with two labels); no_boundary where no box holds two labels";
    o.put_flags(
        over,
        (&name("log2_test"), long),
        verdicts,
        (&names.join(" "), &values),
    )?;
    let scale = o.scale(
        "uncertainty_eps",
        &eps_levels(),
        "perturbation size eps of the uncertainty exponent, as a share of the box's sides",
        Some("1"),
    )?;
    let changed: Vec<u64> = maps
        .iter()
        .flat_map(|s| s.map_or([0; EPS_LEVELS], |s| s.changed()))
        .collect();
    let long = "sampled starts whose fate changes when moved by eps in a random direction (of uncertainty_samples)";
    o.put(
        &over.and(EPS_LEVELS, &scale),
        (&name("uncertainty_changed"), long),
        Some("1"),
        changed,
    )?;
    Ok(())
}

/// A sweep's per-map cycle figures: dataset name, value, long name, and how a physical
/// scan's SI twin `<name>_si` converts it.
type Series = (&'static str, fn(&CycleReport) -> f64, &'static str, Si);

const SERIES: [Series; 5] = [
    (
        "cycle_r_section",
        |c| c.r_section,
        "cycle crossing of the section x = x*: x' there",
        Si::Velocity,
    ),
    (
        "cycle_distance_plus_x",
        |c| c.distance_plus_x,
        "distance from the fixed point to the cycle along +x",
        Si::Length,
    ),
    (
        "cycle_area",
        |c| c.area,
        "area enclosed by the cycle",
        Si::Area,
    ),
    (
        "cycle_period",
        |c| c.period,
        "period of the cycle",
        Si::Time,
    ),
    (
        "cycle_multiplier",
        |c| c.multiplier,
        "Floquet multiplier of the cycle",
        Si::None,
    ),
];

/// The cycles: group `/cycle` (one map) or `/cycles/map_NNNN` (a sweep, with the figures
/// of [`SERIES`] over the maps, and their SI twins by `scales` in a physical scan), for the
/// maps whose search was recorded.
pub(crate) fn write_cycles(
    o: &mut Out,
    over: &Over,
    cycles: &[Option<CycleRecord>],
    (sweep, scales): (bool, Option<&squeal_core::Scales>),
) -> hdf5::Result<()> {
    let recorded = |m: usize| cycles[m].as_ref().filter(|c| c.is_some());
    if !sweep {
        if let Some(c) = recorded(0) {
            let grp = o.file.create_group("cycle")?;
            write_cycle(o, &grp, c)?;
        }
        return Ok(());
    }
    if (0..cycles.len()).any(|m| recorded(m).is_some()) {
        let top = o.file.create_group("cycles")?;
        for m in 0..cycles.len() {
            if let Some(c) = recorded(m) {
                write_cycle(o, &top.create_group(&format!("map_{m:04}"))?, c)?;
            }
        }
    }
    for (name, f, long, si) in SERIES {
        let v: Vec<f64> = (cycles.iter().map(|c| report_of(c).map_or(f64::NAN, f))).collect();
        o.put(over, (name, long), Some("1"), v.clone())?;
        if let (Some(s), false) = (scales, si == Si::None) {
            let v = v.iter().map(|&x| si.convert(x, s)).collect();
            let named = (&format!("{name}_si"), &format!("{long} ({})", si.units()));
            o.put(over, (named.0, named.1), Some(si.units()), v)?;
        }
    }
    let enc = cycles
        .iter()
        .map(|c| report_of(c).map_or(0, |r| r.encloses_origin as u8));
    let named = (
        "cycle_encloses_origin",
        "1 if the cycle encloses the state at rest",
    );
    o.put(over, named, None, enc.collect())?;
    Ok(())
}

/// One map's cycle search in `grp`: the record (TOML, exact) and every scalar of it as
/// attributes, and the closed curve if one was located.
fn write_cycle(o: &mut Out, grp: &Group, c: &CycleRecord) -> hdf5::Result<()> {
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
        let n = r.curve.len();
        let pt = o.index_in(grp, "point", n, "step along the closed curve")?;
        let over = Over {
            shape: vec![n],
            scales: vec![pt],
        };
        for (name, data, long) in [
            ("x", &r.curve.x, "displacement x on the cycle"),
            ("v", &r.curve.v, "velocity x' on the cycle"),
        ] {
            o.put_in(grp, &over, (name, long), Some("1"), data.clone())?;
        }
    }
    Ok(())
}

/// The located cycle in a stored record, if any.
pub(crate) fn report_of(c: &Option<CycleRecord>) -> Option<&CycleReport> {
    match c {
        Some(Some(Ok(r))) => Some(r),
        _ => None,
    }
}
