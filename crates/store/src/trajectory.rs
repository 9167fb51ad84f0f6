//! The `.h5` of `squeal trajectory`: one run's samples with the time as a coordinate.
//!
//! ```text
//! /            attrs schema = "squeal-trajectory/1", squeal_version, git_revision, and the
//!              run's settings (law, solver text; the law's own parameters, nu, lambda, tau,
//!              phi or xi, v_d, mu_d, mu_sd, v_0, mu_v, then dt, x0, v0, t_end f64; every
//!              u64 and sampling text, the stride in words and how it was chosen (given,
//!              or the default of squeal_scan::trajectory::default_every); the Stribeck law adds <key>_long_name, <key>_units text and the
//!              counts stick_onsets, breakaways, slip_reversals u64; a run given as a
//!              physical system adds physical_<key> f64 with its _long_name and _units for
//!              m, k, c, v_belt, mu_k, mu_s, tau, g (when given or by default),
//!              normal_force (always: m g without one), and length_unit, velocity_unit,
//!              time_unit, damping_unit f64 with their _units: the SI size of one unit;
//!              a run that ended on a lasting oscillation (crates/core/MODEL.md section 10)
//!              adds lasting_omega (angular frequency), lasting_x_min, lasting_x_max,
//!              lasting_v_min, lasting_v_max f64 over its last turns, and for a physical
//!              run their SI twins lasting_<..>_si (lasting_omega_si a frequency in Hz, the
//!              others m and m/s) with lasting_<..>_si_units text)
//! t  (t)       f64 dimension scale: nondimensional time (natural period 2 pi)
//! x, v, a, force (t)   f64, long_name and units "1", attached to t
//! a physical run also: t_si (t) f64 time in s; x_si (t) f64 in m, v_si (t) f64 in m/s;
//!              every variable but t_si names it in its CF `coordinates` attribute
//! ```

use std::path::Path;

use hdf5::File;

use crate::error::H5Ctx;
use crate::h5out::{Dims, class_type, num_attr, str_attr};
use crate::{Provenance, StoreError};
use squeal_scan::si::Si;
use squeal_scan::trajectory::Sampling;

/// The `schema` attribute of trajectory files.
pub const TRAJECTORY_SCHEMA: &str = "squeal-trajectory/1";

/// One sampled quantity: name, long name, values.
pub type Series<'a> = (&'a str, &'a str, &'a [f64]);

/// A run's settings stored as root attributes.
#[derive(Clone, Debug, Default)]
pub struct RunAttrs<'a> {
    /// Text settings (law, solver).
    pub text: Vec<(&'a str, &'a str)>,
    /// Numbers (parameters, step, start, end).
    pub numbers: Vec<(&'a str, f64)>,
    /// Counts (sampling stride).
    pub counts: Vec<(&'a str, u64)>,
    /// The physical system the run was given in, if any: stored as a physical scan stores it
    /// (the system and the SI size of one unit), with the other attributes in the one open.
    pub physical: Option<&'a squeal_core::Physical>,
    /// The table law's table (stored as [`crate::h5out::friction_table`] stores it).
    pub table: Option<&'static squeal_core::FrictionTable>,
}

/// Writes a trajectory file: `time` is the coordinate `t`, each series a variable over it.
pub fn write_trajectory(
    path: &Path,
    force: bool,
    prov: &Provenance,
    attrs: &RunAttrs,
    time: &[f64],
    series: &[Series],
) -> Result<(), StoreError> {
    crate::refuse_existing(path, force)?;
    let file = if force {
        File::create(path)
    } else {
        File::create_excl(path)
    }
    .h5(path)?;
    let mut dims = Dims::new(class_type(path)?);
    (|| -> hdf5::Result<()> {
        trajectory_attrs(&file, &mut dims, prov, attrs)?;
        let t = file
            .new_dataset_builder()
            .obj_track_times(false)
            .with_data(time)
            .create("t")?;
        str_attr(
            &t,
            "long_name",
            "time (nondimensional, natural period 2 pi)",
        )?;
        str_attr(&t, "units", "1")?;
        dims.scale(&t, "t")?;
        trajectory_series(&file, &mut dims, &t, attrs, time, series)?;
        dims.finish()
    })()
    .h5(path)?;
    file.close().h5(path)
}

/// A trajectory file's root attributes: schema, provenance, the run's settings, the
/// physical system if any, and the friction table.
fn trajectory_attrs(
    file: &File,
    dims: &mut Dims,
    prov: &Provenance,
    attrs: &RunAttrs,
) -> hdf5::Result<()> {
    str_attr(file, "schema", TRAJECTORY_SCHEMA)?;
    str_attr(file, "squeal_version", &prov.version)?;
    str_attr(file, "git_revision", &prov.git_revision)?;
    for (k, v) in &attrs.text {
        str_attr(file, k, v)?;
    }
    for (k, v) in &attrs.numbers {
        num_attr(file, k, *v)?;
    }
    for (k, v) in &attrs.counts {
        num_attr(file, k, *v)?;
    }
    if let Some(ph) = attrs.physical {
        crate::h5write::physical_attrs(file, ph, &[])?;
    }
    let si = attrs.physical.and_then(|ph| ph.friction.table());
    crate::h5out::friction_table(file, dims, attrs.table, si)
}

/// A trajectory file's variables over `t`. A physical run: the time in seconds and the
/// series of [`SI_SERIES`] in SI units beside the nondimensional ones; `t_si` a CF auxiliary
/// coordinate of every variable.
fn trajectory_series(
    file: &File,
    dims: &mut Dims,
    t: &hdf5::Dataset,
    attrs: &RunAttrs,
    time: &[f64],
    series: &[Series],
) -> hdf5::Result<()> {
    let scales = attrs.physical.map(|ph| ph.scales());
    let mut all: Vec<(String, &str, Vec<f64>, &str)> = series
        .iter()
        .map(|(name, long, data)| (name.to_string(), *long, data.to_vec(), "1"))
        .collect();
    if let Some(s) = &scales {
        for (name, si, long) in SI_SERIES {
            if let Some((_, _, data)) = series.iter().find(|(n, ..)| *n == name) {
                let v = data.iter().map(|&x| si.convert(x, s)).collect();
                all.push((format!("{name}_si"), long, v, si.units()));
            }
        }
        let ts = time.iter().map(|&x| Si::Time.convert(x, s)).collect();
        all.push(("t_si".into(), "time (seconds)", ts, "s"));
    }
    for (name, long, data, units) in &all {
        if data.len() != time.len() {
            return Err(hdf5::Error::from(format!(
                "{name} has {} samples, t has {}",
                data.len(),
                time.len()
            )));
        }
        let ds = file
            .new_dataset_builder()
            .obj_track_times(false)
            .with_data(data.as_slice())
            .create(name.as_str())?;
        str_attr(&ds, "long_name", long)?;
        str_attr(&ds, "units", units)?;
        dims.attach(file, &ds, &[t])?;
        if scales.is_some() && name != "t_si" {
            str_attr(&ds, "coordinates", "t_si")?;
        }
    }
    Ok(())
}

/// A trajectory file's summary for `squeal info`.
#[derive(Clone, Debug)]
pub struct TrajectoryInfo {
    /// Root attributes as text.
    pub attrs: Vec<(String, String)>,
    /// Samples.
    pub samples: usize,
    /// First and last time.
    pub t_range: Option<(f64, f64)>,
    /// Variables besides `t`.
    pub variables: Vec<String>,
}

/// Reads a trajectory file's summary.
pub fn read_trajectory_info(path: &Path) -> Result<TrajectoryInfo, StoreError> {
    let file = crate::read::open_with_schema(path, TRAJECTORY_SCHEMA)?;
    (|| -> hdf5::Result<TrajectoryInfo> {
        let t: Vec<f64> = file.dataset("t")?.read_raw()?;
        let mut variables = file.member_names()?;
        // The friction table's datasets are over its rows, not over t.
        variables.retain(|n| n != "t" && n != "table_row" && !n.starts_with("friction_table"));
        Ok(TrajectoryInfo {
            attrs: crate::read::root_attrs_text(&file)?,
            samples: t.len(),
            t_range: t.first().copied().zip(t.last().copied()),
            variables,
        })
    })()
    .h5(path)
}

/// The figures of a run's lasting oscillation ([`squeal_core::Lasting`]) stored as root
/// attributes of its trajectory file: name, how its SI twin converts, value.
fn lasting_figures(l: &squeal_core::Lasting) -> [(&'static str, Si, f64); 5] {
    [
        ("lasting_omega", Si::Frequency, l.omega),
        ("lasting_x_min", Si::Length, l.x_range[0]),
        ("lasting_x_max", Si::Length, l.x_range[1]),
        ("lasting_v_min", Si::Velocity, l.v_range[0]),
        ("lasting_v_max", Si::Velocity, l.v_range[1]),
    ]
}

/// The series of [`write_samples`] that a physical run also stores in SI units, as
/// `<name>_si`: how each converts, and the twin's long name.
const SI_SERIES: [(&str, Si, &str); 2] = [
    ("x", Si::Length, "displacement x (metres)"),
    ("v", Si::Velocity, "velocity x' (m/s)"),
];

/// Writes a run's samples ([`squeal_core::Samples`]) to a trajectory file: time as the
/// dimension, `x`, `v`, `a` and `force` with their long names (the file's schema, in this
/// one place for `squeal trajectory --out` and the Python package).
pub fn write_samples(
    path: &Path,
    force: bool,
    prov: &Provenance,
    attrs: &RunAttrs,
    s: &squeal_core::Samples,
) -> Result<(), StoreError> {
    write_trajectory(
        path,
        force,
        prov,
        attrs,
        &s.t,
        &[
            ("x", "displacement x (nondimensional)", &s.x),
            ("v", "velocity x' (nondimensional)", &s.v),
            ("a", "acceleration x'' (nondimensional)", &s.a),
            ("force", "friction force F (nondimensional)", &s.force),
        ],
    )
}

/// Writes the run `traj` of `stepper` over `span` ([`squeal_scan::trajectory::run`]) with
/// the stride given by the caller: [`write_run_sampled`] with [`Sampling::Given`].
pub fn write_run(
    path: &Path,
    force: bool,
    prov: &Provenance,
    stepper: &squeal_core::Stepper,
    span: squeal_scan::trajectory::Span,
    traj: &squeal_scan::trajectory::Trajectory,
    physical: Option<&squeal_core::Physical>,
) -> Result<(), StoreError> {
    let sampled = (span, Sampling::Given);
    write_run_sampled(path, force, prov, stepper, sampled, traj, physical)
}

/// Writes the run `traj` of `stepper` over `span` ([`squeal_scan::trajectory::run`]): its
/// samples with the settings as root attributes (the law and its parameters, the solver, the
/// step, the start, the end, the stride and how it was chosen, `sampling`, in words; under a
/// law with true stick the parameters' long names and units and the counts of stick onsets,
/// breakaways and slip reversals). One place for `squeal trajectory --out` and the Python
/// `squeal.trajectory`. A run of a physical system (`physical`) also stores it and the SI
/// size of one unit, as a physical scan does, and its samples in SI units beside the
/// model's: without these an engineer's `--x0` in metres came back as a bare number in
/// other units.
pub fn write_run_sampled(
    path: &Path,
    force: bool,
    prov: &Provenance,
    stepper: &squeal_core::Stepper,
    (span, sampling): (squeal_scan::trajectory::Span, Sampling),
    traj: &squeal_scan::trajectory::Trajectory,
    physical: Option<&squeal_core::Physical>,
) -> Result<(), StoreError> {
    crate::create_parent(path)?;
    let p = stepper.params();
    let named = p.named();
    let keys: Vec<(String, String)> = named
        .iter()
        .map(|n| (format!("{}_long_name", n.name), format!("{}_units", n.name)))
        .collect();
    let sampling = sampling.words(span.every, stepper.dt());
    let mut text = vec![
        ("law", p.kind().name()),
        ("solver", stepper.solver().kind.name()),
        ("scheme", stepper.scheme().name()),
        ("sampling", sampling.as_str()),
    ];
    if traj.stick.is_some() {
        for ((long, units), n) in keys.iter().zip(&named) {
            text.push((long.as_str(), n.long_name));
            text.push((units.as_str(), n.units));
        }
    }
    let mut numbers: Vec<(&str, f64)> = named.iter().map(|n| (n.name, n.value)).collect();
    numbers.extend([
        ("dt", stepper.dt()),
        ("x0", span.ic.x),
        ("v0", span.ic.v),
        ("t_end", span.t_end),
    ]);
    // The lasting oscillation the run ended on, if the turn watch identified one: its
    // figures in the model's units, and in SI beside them for a physical system.
    let si_names = lasting_attrs(traj, physical, &mut numbers);
    let si_units: Vec<String> = si_names
        .iter()
        .map(|(n, ..)| format!("{n}_units"))
        .collect();
    for ((name, value, units), units_key) in si_names.iter().zip(&si_units) {
        numbers.push((name.as_str(), *value));
        text.push((units_key.as_str(), units));
    }
    let mut counts = vec![("every", span.every)];
    if let Some(sp) = &traj.stick {
        counts.extend([
            ("stick_onsets", sp.onsets),
            ("breakaways", sp.breakaways),
            ("slip_reversals", sp.reversals),
        ]);
    }
    let attrs = RunAttrs {
        text,
        numbers,
        counts,
        physical,
        table: p.law.table(),
    };
    write_samples(path, force, prov, &attrs, &traj.samples)
}

/// The figures of the run's lasting oscillation, if any, pushed onto `numbers`; their SI
/// twins (name, value, units) for a physical system returned.
fn lasting_attrs(
    traj: &squeal_scan::trajectory::Trajectory,
    physical: Option<&squeal_core::Physical>,
    numbers: &mut Vec<(&str, f64)>,
) -> Vec<(String, f64, &'static str)> {
    let scales = physical.map(|ph| ph.scales());
    let mut si_names = Vec::new();
    if let Some(l) = &traj.lasting {
        for (name, si, value) in lasting_figures(l) {
            numbers.push((name, value));
            if let Some(sc) = &scales {
                si_names.push((format!("{name}_si"), si.convert(value, sc), si.units()));
            }
        }
    }
    si_names
}
