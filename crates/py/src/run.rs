//! `squeal.trajectory`: one run from `(x0, x'0)` to `t_end` into a trajectory file (the
//! store's schema, as `squeal trajectory --out run.h5` writes), and the classifier's verdict
//! on the same run (as `squeal trajectory` reports it: the run goes on to `t_end` after the
//! decision).

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use pyo3::prelude::*;
use squeal_scan::trajectory::{Sampling, Span, default_every};
use squeal_store::write_run_sampled;

use crate::{interruptible, plan_of, provenance, setup_of, store_error, value_error};

/// Runs map `map` of `spec` from `point = (x0, v0)`, `run = (t_end, every)`, to `t_end` and
/// writes every `every`-th (`None`: the stride `squeal trajectory` takes without `--every`)
/// sample (t, x, v, a, force) to the trajectory file `out` (an existing one only with
/// `force`). Returns the classifier's
/// `(regime, reason, t_decision, t_squeal)` (`t_squeal` as a scan stores it per cell:
/// infinite for stick-slip, -1 where not known).
#[pyfunction]
#[pyo3(signature = (spec, text, map, point, run, out, force=false))]
#[allow(clippy::too_many_arguments)]
pub fn trajectory(
    py: Python<'_>,
    spec: &str,
    text: Option<&str>,
    map: usize,
    point: (f64, f64),
    run: (f64, Option<u64>),
    out: PathBuf,
    force: bool,
) -> PyResult<(&'static str, &'static str, f64, f64)> {
    let (t_end, every) = run;
    let plan = plan_of(spec, text)?;
    let dt = setup_of(&plan, map)?.stepper().map_err(value_error)?.dt();
    let (every, sampling) = match every {
        Some(n) => (n, Sampling::Given),
        None => (default_every(dt, t_end), Sampling::Default),
    };
    if every == 0 {
        return Err(value_error(anyhow::anyhow!(
            "every: invalid every = 0: expected a decimation factor >= 1"
        )));
    }
    // A physical system: the start is in m and m/s (as `squeal trajectory --m ...`).
    let ic = crate::start(&plan, point, "trajectory")?;
    let span = Span { ic, t_end, every };
    // The checks of `squeal trajectory`: a start beyond the escape radius was labelled by
    // the start rule without a run, and t_end had no bound on its steps.
    let invalid = |key: &str, value: String, expected: &str| squeal_scan::ScanError::Invalid {
        path: "squeal.trajectory".into(),
        key: key.into(),
        value,
        expected: expected.into(),
    };
    span.check(dt, ["x0", "v0", "t_end"], &invalid)
        .map_err(value_error)?;
    // The command line's bound on the samples kept (`--every`): t_end = 1e6 kept 2e8.
    let rows = (t_end / dt).ceil() as u64 / every + 1;
    if rows > squeal_scan::trajectory::MAX_ROWS {
        return Err(value_error(anyhow::anyhow!(
            "squeal.trajectory: every= {every}: {rows} samples would be kept (at most {}): \
             raise every= or lower t_end=",
            squeal_scan::trajectory::MAX_ROWS
        )));
    }
    // An existing `out` is refused before the run, unless `force`.
    squeal_store::refuse_existing(&out, force).map_err(store_error)?;
    // The map's context, as `squeal classify` prepares it: the label is the one every path
    // gives this start ([`squeal_scan::trajectory::run_in`]).
    let ctx = squeal_scan::scanner::MapContext::prepare(&plan, map).map_err(value_error)?;
    let stepper = &ctx.stepper;
    let stop = AtomicBool::new(false);
    // The library's run, as `squeal trajectory` makes it (one loop, one labelling rule).
    let t = interruptible(py, &stop, || {
        squeal_scan::trajectory::run_in(&ctx, span, Some(&stop))
    })?;
    let physical = plan.physical();
    // An existing `out` is refused unless `force` (it overwrote a finished scan's file).
    write_run_sampled(
        &out,
        force,
        &provenance(),
        stepper,
        (span, sampling),
        &t,
        physical.as_ref(),
    )
    .map_err(store_error)?;
    let o = &t.outcome;
    let verdict = (o.regime.name(), o.reason.name(), o.t_decision, o.t_squeal);
    Ok(verdict)
}
