//! The grid scan: one classifier run per cell, rayon-parallel inside a block, collected by
//! index, so a block's result depends only on the plan, the map and the block.

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;
use serde::Serialize;
use squeal_core::{Classifier, Outcome, Params, State, Stepper, Trap};

use crate::error::ScanError;
use crate::spec::{EarlyStop, Plan};
use crate::ulc::{self, CycleReport, CycleSettings, SectionCycles};

/// Progress callbacks (no-op defaults); called from worker threads.
pub trait Observer: Sync {
    /// One cell finished.
    fn cell_done(&self) {}
}

/// An observer that does nothing.
pub struct NoObserver;
impl Observer for NoObserver {}

/// One classified cell: the label and the diagnostics stored beside it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Cell {
    /// [`squeal_core::Regime`] value.
    pub regime: u8,
    /// [`squeal_core::Reason`] value.
    pub reason: u8,
    /// Time at the decision.
    pub t_decision: f64,
    /// Last section amplitude (NaN if the run never crossed the section).
    pub amplitude: f64,
    /// Angular frequency of the last revolution (NaN if unknown).
    pub omega: f64,
    /// 1 if the quasi-static branch was entered.
    pub quasi_static: u8,
    /// Friction-law evaluations.
    pub evaluations: u64,
    /// Bisection fallbacks plus bracket expansions (robust solver).
    pub fallbacks: u32,
    /// Solves with several roots.
    pub multi_root: u32,
    /// Paper iterations that hit the cap, plus robust failures and discontinuities.
    pub unconverged: u32,
    /// Largest residual of any solve.
    pub max_residual: f64,
}

impl From<&Outcome> for Cell {
    fn from(o: &Outcome) -> Cell {
        let s = &o.stats;
        let sat = |x: u64| x.min(u32::MAX as u64) as u32;
        Cell {
            regime: o.regime as u8,
            reason: o.reason as u8,
            t_decision: o.t_decision,
            amplitude: o.amplitude,
            omega: o.omega,
            quasi_static: o.quasi_static as u8,
            evaluations: s.evaluations,
            fallbacks: sat(s.bisections + s.expansions),
            multi_root: sat(s.multi_root),
            unconverged: sat(s.unconverged + s.failures + s.discontinuities),
            max_residual: o.max_residual,
        }
    }
}

/// A finished block: `cells` row-major over the block's rows of `v0` and all `x0`.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockResult {
    /// Map index (sweep value).
    pub map: usize,
    /// Block index within the map.
    pub block: usize,
    /// The cells.
    pub cells: Vec<Cell>,
}

/// Everything one map needs: stepper, classifier with its trap, the located cycle.
#[derive(Clone, Debug)]
pub struct MapContext {
    /// Map index.
    pub map: usize,
    /// Parameters of this map.
    pub params: Params,
    /// The stepper.
    pub stepper: Stepper,
    /// The classifier (with the trap when early stopping is on and a cycle was found).
    pub classifier: Classifier,
    /// The section sign changes, if searched.
    pub section: Option<SectionCycles>,
    /// The located cycle, if asked for and found.
    pub cycle: Option<CycleReport>,
    /// Why no cycle was found, if asked for.
    pub cycle_error: Option<String>,
}

/// Cycle-search settings that cover a plan's grid: `r_max` beyond its farthest corner.
pub fn cycle_settings(plan: &Plan, params: &Params) -> CycleSettings {
    let fp = params.fixed_point();
    let g = &plan.grid;
    let far = [g.x0.min, g.x0.max]
        .iter()
        .flat_map(|&x| [g.v0.min, g.v0.max].map(|v| (x - fp.x).hypot(v - fp.v)))
        .fold(0.0f64, f64::max);
    CycleSettings {
        r_max: (1.2 * far).max(4.0),
        ..CycleSettings::default()
    }
}

impl MapContext {
    /// Builds the stepper and, as the plan asks, locates the cycle and sets the trap.
    pub fn prepare(plan: &Plan, map: usize) -> Result<MapContext, ScanError> {
        let params = plan.maps[map];
        let stepper =
            Stepper::new(params, plan.dt, plan.solver).map_err(|e| ScanError::Invalid {
                path: plan.spec_path.clone(),
                key: "integration".into(),
                value: String::new(),
                expected: e.to_string(),
            })?;
        let cs = cycle_settings(plan, &params);
        let mut classifier = plan.classifier;
        let mut section = None;
        if plan.early_stop == EarlyStop::Cycle {
            let mut stats = Default::default();
            let mut returns = 0;
            let found = ulc::section_cycles(&stepper, &cs, &mut stats, &mut returns);
            // Outside the unstable cycle every run ends on a self-excited oscillation: with
            // bounded friction and nu > 0 nothing escapes, and any attracting cycle out there
            // is stick-slip. (The sampled return map also changes sign inside the
            // quasi-periodic stick-slip band; those are not further unstable cycles.)
            if let SectionCycles::Unstable { lo, hi, .. } = found {
                classifier.trap = Some(Trap {
                    r_inner: lo * (1.0 - plan.trap_margin),
                    r_outer: hi * (1.0 + plan.trap_margin),
                });
            }
            section = Some(found);
        }
        let (cycle, cycle_error) = if plan.locate_cycle {
            match ulc::locate(params, plan.dt, plan.solver, &cs) {
                Ok(c) => (Some(c), None),
                Err(e) => (None, Some(e.to_string())),
            }
        } else {
            (None, None)
        };
        Ok(MapContext {
            map,
            params,
            stepper,
            classifier,
            section,
            cycle,
            cycle_error,
        })
    }
}

/// Classifies the cells of one block in parallel. Returns `None` if `stop` was raised
/// before the block finished (the block is then discarded, never stored half-done).
pub fn run_block(
    plan: &Plan,
    ctx: &MapContext,
    block: usize,
    observer: &dyn Observer,
    stop: Option<&AtomicBool>,
) -> Option<BlockResult> {
    let g = &plan.grid;
    let rows = g.block_rows(block);
    let nx = g.x0.count;
    let n = rows.len() * nx;
    let cells: Option<Vec<Cell>> = (0..n)
        .into_par_iter()
        .map(|k| {
            if stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
                return None;
            }
            let (row, col) = (rows.start + k / nx, k % nx);
            let ic = State {
                x: g.x0.value(col),
                v: g.v0.value(row),
            };
            let out = ctx.classifier.classify(&ctx.stepper, ic);
            observer.cell_done();
            Some(Cell::from(&out))
        })
        .collect();
    Some(BlockResult {
        map: ctx.map,
        block,
        cells: cells?,
    })
}
