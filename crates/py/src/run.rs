//! `squeal.trajectory`: one run from `(x0, x'0)` to `t_end` into a trajectory file (the
//! store's schema, as `squeal trajectory --out run.h5` writes), and the classifier's verdict
//! on the same run (as `squeal trajectory` reports it: the run goes on to `t_end` after the
//! decision).

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

use pyo3::prelude::*;
use squeal_core::{Classifier, Reason, Regime, Run, Samples, State, Stepper};
use squeal_store::{RunAttrs, write_samples};

use crate::{interruptible, plan_of, provenance, setup_of, store_error, value_error};

/// The run's start, end and stride.
#[derive(Clone, Copy)]
struct Span {
    ic: State,
    t_end: f64,
    every: u64,
}

/// Integrates the run, keeping every `every`-th sample, until `t_end` or `stop`; returns
/// them and the verdict `(regime, reason, t_decision)` of the classifier with
/// `t_max = t_end`.
fn integrate(
    stepper: &Stepper,
    classifier: &Classifier,
    Span { ic, t_end, every }: Span,
    stop: &AtomicBool,
) -> (Samples, (&'static str, &'static str, f64)) {
    let p = *stepper.params();
    // The band rules as every other path sets them (squeal_scan::scanner::classifier_for).
    let fp = p.fixed_point();
    let cl = squeal_scan::scanner::classifier_for(
        stepper,
        Classifier {
            t_max: t_end,
            ..*classifier
        },
        1.2 * (ic.x - fp.x).hypot(ic.v - fp.v),
    );
    let mut watch = cl.watch(&p);
    let mut run = Run::new(stepper, ic);
    let mut cols = Samples::default();
    cols.push(run.sample());
    let mut outcome = None;
    let steps = (t_end / stepper.dt()).ceil() as u64;
    for k in 1..=steps {
        let step = run.step();
        if outcome.is_none() {
            if let Some(d) = watch.observe(&run, &step) {
                outcome = Some(watch.finish(d, &run));
            }
        }
        if k % every == 0 {
            cols.push(&step.next);
        }
        if !step.next.x.is_finite() || !step.next.v.is_finite() {
            break;
        }
        if k % 4096 == 0 && stop.load(Ordering::Relaxed) {
            break;
        }
    }
    let o = outcome.unwrap_or_else(|| watch.finish((Regime::Undecided, Reason::TimeLimit), &run));
    (cols, (o.regime.name(), o.reason.name(), o.t_decision))
}

/// Runs map `map` of `spec` from `point = (x0, v0)`, `run = (t_end, every)`, to `t_end` and
/// writes every `every`-th
/// sample (t, x, v, a, force) to the trajectory file `out`. Returns the classifier's
/// `(regime, reason, t_decision)`.
#[pyfunction]
#[pyo3(signature = (spec, text, map, point, run, out))]
pub fn trajectory(
    py: Python<'_>,
    spec: &str,
    text: Option<&str>,
    map: usize,
    point: (f64, f64),
    run: (f64, u64),
    out: PathBuf,
) -> PyResult<(&'static str, &'static str, f64)> {
    let (t_end, every) = run;
    let plan = plan_of(spec, text)?;
    let stepper = setup_of(&plan, map)?.stepper().map_err(value_error)?;
    if !(point.0.is_finite() && point.1.is_finite()) {
        return Err(value_error(anyhow::anyhow!(
            "x0/v0: expected finite values"
        )));
    }
    if !t_end.is_finite() || t_end <= 0.0 {
        return Err(value_error(anyhow::anyhow!(
            "t_end: invalid t_end = {t_end}: expected a finite time > 0"
        )));
    }
    if every == 0 {
        return Err(value_error(anyhow::anyhow!(
            "every: invalid every = 0: expected a decimation factor >= 1"
        )));
    }
    let ic = State {
        x: point.0,
        v: point.1,
    };
    let stop = AtomicBool::new(false);
    let span = Span { ic, t_end, every };
    let (cols, verdict) = interruptible(py, &stop, || {
        integrate(&stepper, &plan.classifier, span, &stop)
    })?;
    let p = stepper.params();
    let named = p.named();
    let mut numbers: Vec<(&str, f64)> = named.iter().map(|n| (n.name, n.value)).collect();
    numbers.extend([
        ("dt", plan.dt),
        ("x0", ic.x),
        ("v0", ic.v),
        ("t_end", t_end),
    ]);
    let attrs = RunAttrs {
        text: vec![
            ("law", p.law.name()),
            ("solver", plan.solver.kind.name()),
            ("scheme", plan.solver.scheme.name()),
        ],
        numbers,
        counts: vec![("every", every)],
    };
    write_samples(&out, true, &provenance(), &attrs, &cols).map_err(store_error)?;
    Ok(verdict)
}
