//! # squeal-scan: basin maps, the unstable limit cycle, sweeps
//!
//! * [`spec`]: the TOML scan spec (versioned, unknown keys rejected) and its checked [`Plan`].
//! * [`grid`]: the grid of initial conditions `(x0, v0)` and its blocks.
//! * [`scanner`]: the rayon-parallel loop over cells, one [`squeal_core::Classifier`] run per
//!   cell, collected by index so the result depends only on the plan and the cell.
//! * [`atlas`]: design-space scans with figures of merit per parameter point, regimes, the
//!   fold of cycles and critical damping by bisection, physical units.
//! * [`ulc`]: the unstable limit cycle located as a fixed point of the Poincare return map
//!   on `x = x*, x' > 0`, its curve, period, Floquet multiplier, size; critical damping.
//!
//! ```
//! let plan = squeal_scan::Plan::from_toml(r#"
//! version = 1
//! [model]
//! law = "mcmillan"
//! nu = 1e-2
//! [grid]
//! x0 = { min = -0.5, max = 0.5, count = 2 }
//! v0 = { min = 0.0, max = 0.0, count = 1 }
//! [integration]
//! dt = 0.01
//! [classifier]
//! t_max = 3000.0
//! [output]
//! path = "doc.h5"
//! "#, "doc.toml").unwrap();
//! let ctx = squeal_scan::scanner::MapContext::prepare(&plan, 0).unwrap();
//! let block = squeal_scan::scanner::run_block(&plan, &ctx, 0, &squeal_scan::scanner::NoObserver, None).unwrap();
//! assert_eq!(block.cells.len(), 2);
//! ```

pub mod atlas;
pub mod error;
pub mod grid;
pub mod scanner;
pub mod spec;
pub mod ulc;

pub use error::ScanError;
pub use grid::{Axis, Grid};
pub use spec::{EarlyStop, Plan, Sweep};
