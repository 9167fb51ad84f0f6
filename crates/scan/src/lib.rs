//! # squeal-scan: basin maps, the unstable limit cycle, sweeps
//!
//! * [`spec`]: the TOML scan spec (versioned, unknown keys rejected) and its checked [`Plan`].
//! * [`files`]: what is at a path before squeal opens it (a FIFO, a directory... refused).
//! * [`grid`]: the grid of initial conditions `(x0, v0)` and its blocks.
//! * [`cell`]: one classified [`Cell`] and [`cell::COLUMNS`], the one table of its stored
//!   columns (name, long name, units, type, fill) that every writer and reader follows.
//! * [`column`]: the one [`column::Column`] type of the stored tables, a scan's cells and an
//!   atlas's points and boundary searches alike.
//! * [`scanner`]: a map's preparation ([`scanner::MapContext`]: the section searched once,
//!   the trap and the located cycle) and one block of cells, classified in parallel.
//! * [`executor`]: the one executor of every kind of work (a scan's map blocks, an atlas's
//!   lines and boundary searches): jobs on the rayon pool, results to the sink on one thread.
//! * [`driver`]: [`drive`] runs every pending `(map, block)` pair of a plan through the
//!   executor and hands finished work to a [`Sink`]; an [`Observer`] sees progress.
//! * [`observe`]: the [`Observer`] of the one-parameter searches on one thread (`critical`,
//!   the fold, the crisis, a cycle's location): their stages, values and section returns.
//! * [`section`]: the return map on the section `x = x*, x' > 0`, in one place: samples,
//!   cold and warm brackets, bisection and Illinois, counted where they run ([`section::Work`]);
//!   `ulc`, a map's preparation, atlas points and boundary predicates all use it.
//! * [`estimate`]: how long a scan or an atlas will take, from a pilot of its own work.
//! * [`trajectory`]: one run to `t_end` with its samples, verdict, final oscillation and
//!   stick phases: the loop behind `squeal trajectory` and Python's `squeal.trajectory`.
//! * [`atlas`]: design-space scans with figures of merit per parameter point, regimes, the
//!   fold of cycles and critical damping by bisection, physical units.
//! * [`ulc`]: the unstable limit cycle located as a fixed point of the Poincare return map
//!   on `x = x*, x' > 0`, its [`ClosedCurve`], period, Floquet multiplier, size; critical
//!   damping.
//! * [`landscape`]: for laws with true stick, which attractors a map's parameters have,
//!   stated before the map (every start stick-slip, bistable, every start steady slip).
//! * [`basin`]: basin stability as bSTAB defines it: each regime's share with its standard
//!   error, and a grid's shares on nested coarser grids ([`GridShares`]).
//! * [`sensitivity`]: final-state sensitivity per map: basin entropy and the log 2 test, the
//!   uncertainty exponent and the share of fates that move when the step halves.
//! * [`checks`]: where labels, cycle, landscape and the run-to-settlement audit disagree in
//!   a map.
//!
//! ```
//! use std::sync::atomic::AtomicBool;
//! use squeal_scan::{MemorySink, NoObserver, Plan, drive};
//! let plan = Plan::from_toml(r#"
//! version = 1
//! [model]
//! law = "mcmillan"
//! nu = 1e-2
//! [grid]
//! x0 = { min = -0.5, max = 0.5, count = 2 }
//! v0 = { min = 0.0, max = 0.0, count = 1 }
//! [integration]
//! dt = 0.005
//! [classifier]
//! t_max = 3000.0
//! [output]
//! path = "doc.h5"
//! "#, "doc.toml").unwrap();
//! let mut sink = MemorySink::default();
//! let done = drive(&plan, None, &mut sink, &NoObserver, &AtomicBool::new(false)).unwrap();
//! assert!(!done.interrupted);
//! assert_eq!(sink.map_cells(&plan, 0).unwrap().len(), 2);
//! // nu = 1e-2: the cycle encloses the state at rest (paper Fig. 10).
//! assert!(sink.cycles[&0].as_ref().unwrap().as_ref().unwrap().encloses_origin);
//! ```

pub mod atlas;
pub mod band;
pub mod basin;
pub mod bounds;
pub mod cell;
pub mod census;
pub mod checks;
pub mod column;
pub mod compare;
pub mod curve;
pub mod driver;
pub mod error;
pub mod estimate;
pub mod executor;
pub mod fates;
pub mod files;
pub mod finish;
pub mod grid;
pub mod landscape;
pub mod lifetime;
pub mod observe;
pub mod redo;
pub mod scanner;
pub mod section;
pub mod sensitivity;
pub mod si;
pub mod space;
pub mod spec;
pub mod trajectory;
pub mod ulc;
mod values;

pub use basin::{BASIN_FIELDS, GridShares, MapSummary, Share, Shares};
pub use cell::{COLUMNS, Cell, Column};
pub use checks::{LandscapeCheck, MapChecks, MapTally, WrongSide};
pub use curve::ClosedCurve;
pub use driver::{
    Computed, DriveError, DriveReport, MemorySink, Pending, Shard, Shared, Sink, drive, shard_owns,
};
pub use error::{NoCycle, ScanError};
pub use finish::{Finishing, MapFigures};
pub use grid::{Axis, Grid, Starts};
pub use scanner::{BlockResult, MapContext, NoObserver, Observer};
pub use spec::{EarlyStop, MapSettings, Plan, Sweep};
pub use ulc::{CycleOutcome, CycleReport};
