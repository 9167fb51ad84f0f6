//! # squeal-py: the native module `squeal._squeal` of the Python package `squeal`
//!
//! Wiring only: every function here parses a spec with [`squeal_scan::Plan`] (or
//! [`AtlasPlan`]), runs the library's driver into the store's writer (the same calls as
//! `squeal scan` and `squeal atlas`), or calls [`squeal_scan::ulc`]; the Python side
//! (`python/squeal/`) turns the files and reports into xarray Datasets and dataclasses.
//!
//! * The GIL is released while computing: the work runs on a scoped thread while the
//!   calling thread waits with the GIL released and, every [`POLL`], runs Python's signal
//!   handlers. A `KeyboardInterrupt` (Ctrl-C) sets the run's stop flag; the blocks in
//!   flight are journalled, the exception is raised, and `resume=True` finishes the run.
//! * Bad input raises `ValueError` with the command line's message (`error: ...` there).
//! * [`cli`] runs the `squeal` command line itself ([`squeal_cli::run_from`]), so the
//!   wheel's `squeal` command is the same program as the Rust binary.
//!
//! The library's entry points it uses, and nothing below them (they are the library's
//! public face for other programs too): [`Plan::from_toml`] / [`Plan::from_file`],
//! [`AtlasPlan::from_toml`] / [`AtlasPlan::from_file`], [`ScanWriter::create`] /
//! [`ScanWriter::resume`] / [`ScanWriter::finish`] with [`squeal_scan::drive`],
//! [`AtlasWriter::create`] / [`AtlasWriter::resume`] / [`AtlasWriter::finish`] with
//! [`squeal_cli::run_atlas`], [`squeal_scan::ulc::locate`],
//! [`squeal_scan::ulc::critical_nu`], [`squeal_scan::atlas::boundary::both_in`], and for a trajectory [`squeal_core::Stepper`],
//! [`squeal_core::Run`], [`squeal_core::Classifier::watch`] and
//! [`squeal_store::write_trajectory`].
//!
//! The functions (all take the spec as `spec`, a path used in messages, and `text`, its
//! TOML text, or `None` to read the file at `spec`):
//!
//! | function | does |
//! |---|---|
//! | [`spec_toml`] | JSON of a spec's tables → TOML text |
//! | [`scan`] | `squeal scan` into the HDF5 file `out` |
//! | [`atlas`] | `squeal atlas` into the HDF5 file `out` |
//! | [`ulc`] | the unstable limit cycle of one map, as JSON |
//! | [`critical`] | the critical damping of a state, as JSON |
//! | [`boundary`] | the fold of cycles, or a critical value in `nu` or `lambda`, as JSON |
//! | [`trajectory()`] | one run into a trajectory file, and its verdict |
//! | [`cli`] | the command line |
//! | [`laws`] | every law's keys and defaults, and the default law, as JSON |
//! | [`file_kind`] | the kind of a squeal file, checked as `squeal info` checks it |

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use squeal_cli::AtlasRunError;
use squeal_cli::words::{Keywords, store_message};
use squeal_core::error::Number;
use squeal_core::{Setup, State};
use squeal_scan::DriveError;
use squeal_scan::atlas::AtlasPlan;
use squeal_scan::section::ParamRange;
use squeal_scan::ulc::{CycleSettings, critical_nu, locate};
use squeal_scan::{NoObserver, Plan};
use squeal_store::atlas::AtlasWriter;
use squeal_store::{Provenance, ScanWriter, StoreError};

mod run;
pub use run::trajectory;

/// How often the waiting thread runs Python's signal handlers.
pub const POLL: Duration = Duration::from_millis(50);

/// The error as the command line prints it (`{:#}`: the message and its causes).
fn message(e: impl Into<anyhow::Error>) -> String {
    format!("{:#}", e.into())
}

/// A bad spec or argument: `ValueError` with the command line's message.
fn value_error(e: impl Into<anyhow::Error>) -> PyErr {
    PyValueError::new_err(message(e))
}

/// A store error: a bad request (`ValueError`: the output exists, an interrupted run is
/// there, nothing to resume, ...) or a failing file system (`OSError`), in Python's words
/// ([`squeal_cli::words::Keywords`]: `force=True` where the command line says `--force`).
fn store_error(e: StoreError) -> PyErr {
    store_error_after("", e)
}

/// [`store_error`] with `before` said first (what failed).
fn store_error_after(before: &str, e: StoreError) -> PyErr {
    let m = format!("{before}{}", store_message(&e, &Keywords));
    match e {
        StoreError::Io { ref source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
            pyo3::exceptions::PyFileNotFoundError::new_err(m)
        }
        StoreError::Io { .. } | StoreError::Hdf5 { .. } => PyOSError::new_err(m),
        _ => PyValueError::new_err(m),
    }
}

/// What produced a file: this version and the git revision it was built from, as the
/// command line records them.
fn provenance() -> Provenance {
    squeal_cli::provenance()
}

/// Runs `work` on a scoped thread while this thread holds no GIL, running Python's signal
/// handlers every [`POLL`]. If a handler raises (Ctrl-C: `KeyboardInterrupt`), `stop` is
/// set, the work is awaited (it stops at its next clean point) and the exception returned.
fn interruptible<T: Send>(
    py: Python<'_>,
    stop: &AtomicBool,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    std::thread::scope(|s| {
        let handle = s.spawn(work);
        let mut raised = None;
        while !handle.is_finished() {
            py.detach(|| std::thread::sleep(POLL));
            if raised.is_none() {
                if let Err(e) = py.check_signals() {
                    stop.store(true, Ordering::SeqCst);
                    raised = Some(e);
                }
            }
        }
        let out = handle
            .join()
            .unwrap_or_else(|p| std::panic::resume_unwind(p));
        raised.map_or(Ok(out), Err)
    })
}

fn plan_of(spec: &str, text: Option<&str>) -> PyResult<Plan> {
    let plan = match text {
        Some(t) => Plan::from_toml(t, spec),
        None => Plan::from_file(Path::new(spec)),
    }
    .map_err(value_error)?;
    warn_space(&plan.space)?;
    Ok(plan)
}

/// Says what in a spec looks like a slip of units (a friction coefficient in percent,
/// speeds in mm/s: [`squeal_scan::space::Space::warnings`]) as a Python `UserWarning` each,
/// before anything runs, as the command line says it on stderr (an error where the
/// caller's warning filter makes it one).
fn warn_space(space: &squeal_scan::space::Space) -> PyResult<()> {
    Python::attach(|py| {
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        for w in space.warnings() {
            let text = std::ffi::CString::new(w).unwrap_or_default();
            PyErr::warn(py, &category, &text, 1)?;
        }
        Ok(())
    })
}

/// The TOML text of a spec given as JSON (a dict's `json.dumps`): the tables of a spec file.
#[pyfunction]
pub fn spec_toml(json: &str) -> PyResult<String> {
    let v: toml::Value = serde_json::from_str(json).map_err(value_error)?;
    toml::to_string(&v).map_err(value_error)
}

/// Like make, by the command line's rule ([`squeal_store::OutputState::up_to_date`]): a
/// finished `out` of the same spec is up to date (`true`), with or without `resume`; a file
/// of another spec or kind is refused unless `force`.
fn up_to_date<P: squeal_store::Recorded>(out: &Path, plan: &P, force: bool) -> PyResult<bool> {
    squeal_store::output_state(out, plan, None)
        .and_then(|state| state.up_to_date(out, force))
        .map_err(store_error)
}

/// Work estimated at the documented rates over the command line's limit is refused before
/// anything is created or run, unless `allow_long` ([`squeal_scan::estimate::refused_as_long`]).
fn refuse_long(kind: &str, seconds: f64, threads: usize, allow_long: bool) -> PyResult<()> {
    if squeal_scan::estimate::refused_as_long(seconds, allow_long) {
        return Err(PyValueError::new_err(format!(
            "this {kind} would take roughly {:.0} days on {threads} thread(s) at the documented \
             rate: shrink it, or pass allow_long=True",
            seconds / 86_400.0
        )));
    }
    Ok(())
}

/// Runs the scan of `spec` into the HDF5 file `out`: a new file (`force` overwrites one),
/// or with `resume` the rest of an interrupted run. Returns the number of cells computed,
/// `None` where `out` is up to date (a finished file of the same spec: nothing computed).
#[pyfunction]
#[pyo3(signature = (spec, text, out, resume=false, force=false, allow_long=false))]
pub fn scan(
    py: Python<'_>,
    spec: &str,
    text: Option<&str>,
    out: PathBuf,
    resume: bool,
    force: bool,
    allow_long: bool,
) -> PyResult<Option<usize>> {
    let plan = plan_of(spec, text)?;
    if up_to_date(&out, &plan, force)? {
        return Ok(None);
    }
    let threads = rayon::current_num_threads();
    let pending = squeal_scan::Pending::of(&plan, None, &squeal_scan::MemorySink::default());
    let rough = squeal_scan::estimate::documented_seconds(&plan, &pending, threads);
    refuse_long("scan", rough, threads, allow_long)?;
    let prov = provenance();
    let mut writer = if resume {
        ScanWriter::resume(&out, &plan, None, &prov)
    } else {
        ScanWriter::create(&out, &plan, None, &prov, force)
    }
    .map_err(store_error)?;
    let plan = writer.plan().clone();
    let stop = AtomicBool::new(false);
    let report = interruptible(py, &stop, || {
        squeal_scan::drive(&plan, None, &mut writer, &NoObserver, &stop)
    })?;
    let report = report.map_err(|e| match e {
        DriveError::Scan(e) => value_error(e),
        DriveError::Sink(e) => store_error(e),
    })?;
    // The audit acts before the file is written, as `squeal scan` makes it.
    if !report.interrupted {
        py.detach(|| {
            squeal_scan::redo::act_on_audits(&plan, None, &mut writer, Some(&report.computed))
        })
        .map_err(|e| match e {
            DriveError::Scan(e) => value_error(e),
            DriveError::Sink(e) => store_error(e),
        })?;
    }
    py.detach(|| squeal_cli::finish_scan(writer))
        .map_err(|e| match e {
            squeal_cli::FinishError::Scan(e) => value_error(e),
            squeal_cli::FinishError::Store(e) => store_error(e),
        })?;
    Ok(Some(report.cells))
}

/// Runs the atlas of `spec` into the HDF5 file `out` (`resume` and `force` as for [`scan`]).
/// Returns the number of units and map blocks computed, `None` where `out` is up to date.
#[pyfunction]
#[pyo3(signature = (spec, text, out, resume=false, force=false, allow_long=false))]
pub fn atlas(
    py: Python<'_>,
    spec: &str,
    text: Option<&str>,
    out: PathBuf,
    resume: bool,
    force: bool,
    allow_long: bool,
) -> PyResult<Option<usize>> {
    let plan = match text {
        Some(t) => AtlasPlan::from_toml(t, spec),
        None => AtlasPlan::from_file(Path::new(spec)),
    }
    .map_err(value_error)?;
    warn_space(&plan.space)?;
    if up_to_date(&out, &plan, force)? {
        return Ok(None);
    }
    let threads = rayon::current_num_threads();
    let rough = squeal_scan::estimate::atlas_documented_seconds(&plan, threads);
    refuse_long("atlas", rough, threads, allow_long)?;
    let prov = provenance();
    let writer = if resume {
        AtlasWriter::resume(&out, &plan, None, &prov)
    } else {
        AtlasWriter::create(&out, &plan, None, &prov, force)
    }
    .map_err(store_error)?;
    let todo = writer.missing().len() + writer.missing_blocks().len();
    let stop = AtomicBool::new(false);
    let (writer, left) = interruptible(py, &stop, || {
        squeal_cli::run_atlas(&plan, None, writer, &stop, &|| {}, &NoObserver)
    })?
    .map_err(|e| match e {
        AtlasRunError::Store(e) => store_error(e),
        AtlasRunError::Maps(DriveError::Sink(e)) => store_error_after("basin maps: ", e),
        e => value_error(e),
    })?;
    if left > 0 {
        return Err(PyOSError::new_err(format!(
            "{}: {left} units and map blocks were not computed",
            out.display()
        )));
    }
    py.detach(|| squeal_cli::finish_atlas(writer))
        .map_err(store_error)?;
    Ok(Some(todo))
}

/// The map `map` of a plan, or `ValueError` naming how many the spec has.
fn setup_of(plan: &Plan, map: usize) -> PyResult<Setup> {
    if map >= plan.maps.len() {
        return Err(PyValueError::new_err(format!(
            "map {map}: the spec has {} map(s)",
            plan.maps.len()
        )));
    }
    Ok(plan.setup(map))
}

/// Locates the unstable limit cycle of map `map` of `spec` ([`squeal_scan::ulc::locate`]) and returns
/// its report ([`squeal_scan::ulc::CycleReport`]) as JSON.
#[pyfunction]
#[pyo3(signature = (spec, text, map=0, r_max=6.0, rtol=1e-10, check_half_dt=true))]
pub fn ulc(
    py: Python<'_>,
    spec: &str,
    text: Option<&str>,
    map: usize,
    r_max: f64,
    rtol: f64,
    check_half_dt: bool,
) -> PyResult<String> {
    let setup = setup_of(&plan_of(spec, text)?, map)?;
    let cs = CycleSettings {
        r_max,
        rtol,
        check_half_dt,
        ..Default::default()
    };
    // The command line's checks of `--r-max`, `--rtol`, named as the keywords.
    squeal_scan::bounds::cycle_search(&cs, &|f| f.to_string(), &keyword("ulc"))
        .map_err(value_error)?;
    let rep = py.detach(|| locate(setup, &cs)).map_err(value_error)?;
    serde_json::to_string(&rep).map_err(value_error)
}

/// A refusal of helper `helper`'s keyword argument, in Python's words (`x0=`, `rtol=`).
fn keyword(helper: &'static str) -> impl Fn(&str, String, &str) -> squeal_scan::ScanError {
    move |key: &str, value: String, expected: &str| squeal_scan::ScanError::Invalid {
        path: format!("squeal.{helper}"),
        key: key.into(),
        value,
        expected: expected.into(),
    }
}

/// The start `(x, v)` a helper was given, in the model's units: in m and m/s for a
/// physical system (as the command line's `--x0 --v0` with `--m ...`), scaled by its units;
/// refused as the command line refuses `--x0`/`--v0` (finite, within the escape radius).
fn start(plan: &Plan, (x, v): (f64, f64), helper: &'static str) -> PyResult<State> {
    let given = State { x, v };
    let scales = plan.physical().map(|ph| ph.scales());
    let point = scales.map_or(given, |s| s.state(given));
    // The value as given, in m and m/s, as the command line reports it.
    let si = scales.map(|s| (given, s));
    let inv = squeal_scan::bounds::start_invalid(format!("squeal.{helper}"), si);
    squeal_scan::bounds::state("x0", point.x, &inv).map_err(value_error)?;
    squeal_scan::bounds::state("v0", point.v, &inv).map_err(value_error)?;
    Ok(point)
}

/// The answer of [`squeal_scan::fates::decide`] as JSON: `value`, `bracket`, `evaluations`
/// and `half_dt_holds` read from the shortcut's answer by `figures`, or the runs' (the
/// interval covering dt/2 as the bracket), with `by` ("shortcut" or "runs"), `why` and the
/// runs' `confirmation`; the step sensitivity of the runs at the bracket's ends (the
/// runs' own, or the confirmation's) as `squeal critical --json` names it
/// (`step_sensitivity`, `_se`, `_changed`, `_compared`).
fn decided_json<T: serde::Serialize>(
    d: squeal_scan::fates::Decided<T>,
    figures: impl Fn(&T) -> (f64, [f64; 2], u32, Option<bool>, &'static str),
) -> PyResult<String> {
    use squeal_scan::fates::Decided;
    let v = match d {
        Decided::Shortcut { answer, confirmed } => {
            let (value, bracket, evaluations, half, status) = figures(&answer);
            serde_json::json!({
                "status": status,
                "value": value,
                "bracket": bracket,
                "evaluations": evaluations,
                "half_dt_holds": half,
                "by": "shortcut",
                "confirmed": confirmed.as_ref().map(|c| c.confirmed),
                "confirmation": confirmed.as_ref().map(|c| c.line.clone()),
                "step_sensitivity": confirmed.as_ref().map(|c| c.step.share),
                "step_sensitivity_se": confirmed.as_ref().map(|c| c.step.se),
                "step_sensitivity_changed": confirmed.as_ref().map(|c| c.step.changed),
                "step_sensitivity_compared": confirmed.as_ref().map(|c| c.step.compared),
            })
        }
        Decided::Runs { boundary, why } => serde_json::json!({
            "status": boundary.status.name(),
            "value": boundary.value(),
            "bracket": boundary.interval,
            "evaluations": boundary.runs,
            "half_dt_holds": boundary.half_dt_holds,
            "by": "runs",
            "why": why.words(),
            "horizon": boundary.horizon,
            "undecided": boundary.undecided,
            "step_sensitivity": boundary.step.map(|s| s.share),
            "step_sensitivity_se": boundary.step.map(|s| s.se),
            "step_sensitivity_changed": boundary.step.map(|s| s.changed),
            "step_sensitivity_compared": boundary.step.map(|s| s.compared),
        }),
    };
    serde_json::to_string(&v).map_err(value_error)
}

/// The critical value of `param` for the state `point = (x, v)` (`search = (param, false,
/// rtol)`: above it that start is quiet) or the fold (`(param, true, rtol)`: above it no
/// start of the spread squeals) of map `map` of `spec`, over `bracket` (raised up to
/// `ceiling` by the runs' search while a start squeals at its top), through the one gate
/// [`squeal_scan::fates::decide`] the command line takes: the shortcut (the cycle's critical
/// damping in `nu`, else the atlas's boundary search
/// [`squeal_scan::atlas::boundary::both_in`]) confirmed by runs to `horizon`, or the runs'
/// answer; as JSON ([`decided_json`]).
#[pyfunction]
#[pyo3(signature = (spec, text, map, point, search, bracket, horizon))]
#[allow(clippy::too_many_arguments)]
pub fn boundary(
    py: Python<'_>,
    spec: &str,
    text: Option<&str>,
    map: usize,
    point: (f64, f64),
    search: (String, bool, f64),
    bracket: Option<(f64, f64)>,
    horizon: f64,
) -> PyResult<String> {
    use squeal_scan::atlas::{BoundaryParam, PointSettings, boundary::both_in};
    use squeal_scan::fates::decide;
    let plan = plan_of(spec, text)?;
    let setup = setup_of(&plan, map)?;
    let (key, fold, rtol) = search;
    let param = bisected(&key, plan.maps[map].law.kind())?;
    let point = start(&plan, point, "critical")?;
    let inv = keyword("critical");
    squeal_scan::bounds::bisection_rtol("rtol", rtol, &inv).map_err(value_error)?;
    squeal_scan::bounds::horizon("horizon", horizon, setup.dt, &inv).map_err(value_error)?;
    let range = critical_range(param, bracket, rtol)?;
    // As the command line: a given top is the ceiling, a default one is raised by the runs.
    let ceiling = param.ceiling(range, bracket.is_some());
    let starts = squeal_scan::fates::starts(fold, (param, setup), range.lo, point);
    let gate = (setup, param);
    let d = py.detach(|| -> Result<_, squeal_scan::ScanError> {
        if param == BoundaryParam::Nu && !fold {
            // As the command line: the critical damping by cycle locations.
            let cs = CycleSettings::default();
            let d = decide(gate, &starts, (range, ceiling), horizon, || {
                let rep = critical_nu(setup, &cs, point, range)?;
                let bracket = rep.bracket;
                Ok((rep, Some(bracket)))
            })?;
            return Ok(Err(d));
        }
        let ps = PointSettings {
            operating: point,
            ..PointSettings::default()
        };
        let d = decide(gate, &starts, (range, ceiling), horizon, || {
            let [f, c] = both_in(param, setup, &ps, point, range, [fold, !fold]);
            let b = f.or(c).expect("one boundary asked for")?;
            // Above the range, the runs raise a default top, as on the command line.
            b.gated(point, (range, ceiling))
        })?;
        Ok(Ok(d))
    });
    let json = match d.map_err(value_error)? {
        Err(d) => decided_json(d, |r| (r.nu, r.bracket, r.evaluations, None, "found")),
        Ok(d) => decided_json(d, |b| {
            (
                b.nu,
                b.bracket,
                b.evaluations,
                b.half_dt_holds,
                b.status.name(),
            )
        }),
    }?;
    // The range searched, for the refusals that name its ends.
    let mut v: serde_json::Value = serde_json::from_str(&json).map_err(value_error)?;
    v["range"] = serde_json::json!([range.lo, range.hi]);
    // Steady slip's own stability at the answer (at the range's low end without one), as
    // `squeal critical` prints it first.
    let at = v["value"].as_f64().or(v["nu"].as_f64()).unwrap_or(range.lo);
    let steady = squeal_core::SteadySlip::of(&param.with(setup.params, at));
    v["steady_slip"] = serde_json::to_value(steady).map_err(value_error)?;
    Ok(v.to_string())
}

/// The bisected parameter of `critical(parameter=)` under `law`, as `squeal critical --in`
/// takes it: `xi` and `v_d` are `nu` and `lambda` under the laws with true stick, and no
/// name of another law's.
fn bisected(
    key: &str,
    law: squeal_core::FrictionLaw,
) -> PyResult<squeal_scan::atlas::BoundaryParam> {
    use squeal_scan::atlas::BoundaryParam;
    let own = law.family().has_own_names();
    let nd = match (key, own) {
        ("xi" | "v_d", false) => {
            return Err(PyValueError::new_err(format!(
                "squeal.critical: parameter= '{key}': a name under the laws with true stick \
                 (stribeck, cubic, table); with law {} use 'nu' or 'lambda'",
                law.name()
            )));
        }
        ("xi", true) => "nu",
        ("v_d", true) => "lambda",
        (k, _) => k,
    };
    BoundaryParam::from_key(nd).ok_or_else(|| {
        PyValueError::new_err(format!(
            "squeal.critical: parameter= '{key}': expected one of 'nu', 'lambda', 'xi', 'v_d'"
        ))
    })
}

/// The range `bracket` of `critical(bracket=)`, or the library's default for `param`
/// ([`squeal_scan::atlas::BoundaryParam::default_bracket`], as `squeal critical`'s),
/// checked as the command line checks it: 0 < lo < hi, finite.
fn critical_range(
    param: squeal_scan::atlas::BoundaryParam,
    bracket: Option<(f64, f64)>,
    rtol: f64,
) -> PyResult<ParamRange> {
    let (lo, hi) = bracket.unwrap_or(param.default_bracket());
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        let (lo, hi) = (Number(lo), Number(hi));
        return Err(PyValueError::new_err(format!(
            "squeal.critical: bracket= ({lo}, {hi}): expected 0 < low < high, finite"
        )));
    }
    Ok(ParamRange::new(lo, hi, rtol))
}

/// Every law's keys and defaults, as JSON: `{"default": law, "laws": {name: {"keys": [...],
/// "defaults": {key: value}}}}` ([`squeal_core::FrictionLaw::DEFAULT`],
/// [`squeal_core::Params::defaults`]): the defaults the command line's flags take, read by
/// Python's helpers from the one place they are defined.
#[pyfunction]
pub fn laws() -> PyResult<String> {
    use squeal_core::{FrictionLaw, Params};
    let mut laws = serde_json::Map::new();
    for law in FrictionLaw::ALL {
        let defaults: serde_json::Map<String, serde_json::Value> = Params::defaults(law)
            .named()
            .iter()
            .map(|n| (n.name.to_string(), n.value.into()))
            .collect();
        let v = serde_json::json!({ "keys": law.keys(), "defaults": defaults });
        laws.insert(law.name().into(), v);
    }
    let v = serde_json::json!({ "default": FrictionLaw::DEFAULT.name(), "laws": laws });
    serde_json::to_string(&v).map_err(value_error)
}

/// The kind of the squeal file at `path` (`"scan"`, `"atlas"`, `"trajectory"`), checked as
/// `squeal info` checks it before anything reads it ([`squeal_store::file_kind`]): a FIFO
/// or other non-regular file, a file that is not HDF5, a truncated one and an HDF5 file
/// without squeal's schema are refused (`ValueError`) in the command line's words.
#[pyfunction]
pub fn file_kind(path: PathBuf) -> PyResult<&'static str> {
    use squeal_store::FileKind;
    Ok(match squeal_store::file_kind(&path).map_err(store_error)? {
        FileKind::Scan => "scan",
        FileKind::Atlas => "atlas",
        FileKind::Trajectory => "trajectory",
    })
}

/// Runs the `squeal` command line with `argv` (the program name first) and returns its
/// exit status (the `squeal` command of the wheel).
#[pyfunction]
pub fn cli(argv: Vec<String>) -> u8 {
    let code = squeal_cli::run_from(argv);
    let _ = std::io::stdout().flush();
    (0..=255u8)
        .find(|&n| ExitCode::from(n) == code)
        .unwrap_or(1)
}

/// The `[physical]` key a model's swept key `model` stands for in a physical scan's file,
/// and the dataset that holds its values as given (`("c", "c")` for `nu`, `("tau",
/// "tau_si")` for `tau`); `None` for a key no physical key becomes.
#[pyfunction]
pub fn si_twin(model: &str) -> Option<(&'static str, String)> {
    squeal_scan::space::si_twin(model)
}

/// Writes the interactive page of a squeal file (`squeal report`): `out` (default: beside
/// `file`, `.html`), refused if there without `force`; returns its path. Store refusals in
/// Python's words (`force=True`), as every other door.
#[pyfunction]
#[pyo3(signature = (file, out=None, force=false))]
pub fn report(file: PathBuf, out: Option<PathBuf>, force: bool) -> PyResult<String> {
    match squeal_report::write(&file, out.as_deref(), force, env!("CARGO_PKG_VERSION")) {
        Ok(p) => Ok(p.display().to_string()),
        Err(squeal_report::ReportError::Store(e)) => Err(store_error(e)),
        Err(squeal_report::ReportError::Exists(p)) => Err(PyValueError::new_err(format!(
            "{} exists (pass force=True to overwrite it)",
            p.display()
        ))),
        Err(e @ squeal_report::ReportError::Write { .. }) => Err(PyOSError::new_err(e.to_string())),
        Err(e) => Err(value_error(e)),
    }
}

/// The module `squeal._squeal`.
#[pymodule]
fn _squeal(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(spec_toml, m)?)?;
    m.add_function(wrap_pyfunction!(scan, m)?)?;
    m.add_function(wrap_pyfunction!(atlas, m)?)?;
    m.add_function(wrap_pyfunction!(ulc, m)?)?;
    m.add_function(wrap_pyfunction!(boundary, m)?)?;
    m.add_function(wrap_pyfunction!(trajectory, m)?)?;
    m.add_function(wrap_pyfunction!(cli, m)?)?;
    m.add_function(wrap_pyfunction!(si_twin, m)?)?;
    m.add_function(wrap_pyfunction!(report, m)?)?;
    m.add_function(wrap_pyfunction!(laws, m)?)?;
    m.add_function(wrap_pyfunction!(file_kind, m)?)?;
    Ok(())
}
