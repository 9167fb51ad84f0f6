//! The atlas: scans over the design space (`nu`, `lambda`, `tau`, `phi`, or the physical
//! parameters, or the Stribeck law's `xi`, `v_d`) with figures of merit per parameter point and boundaries located by
//! bisection.
//!
//! * [`spec`]: the atlas TOML spec (a Cartesian product of values, lists and ranges; either
//!   nondimensional or physical) and its checked [`AtlasPlan`].
//! * [`point`]: one parameter point to a [`PointResult`]: the unstable cycle, the
//!   stick-slip attractor, the [`AtlasRegime`] and the basin fraction of steady slip.
//! * [`boundary`]: the fold of cycles and the critical damping (or belt speed) of the
//!   operating point, by bisection in `nu` or `lambda` ([`BoundaryParam`]).
//! * [`columns`]: the stored figures as one table (HDF5, journal and JSON walk it).
//! * [`maps`]: optional basin maps, one per point, made by the scan's spine
//!   ([`AtlasPlan::map_plan`]), and the basin fraction read off a map ([`maps::map_fraction`]).
//! * [`true_stick`]: laws with true stick: each point's section search checked against the
//!   landscape (undecided where they disagree), boundaries bisected on the landscape.
//! * [`driver`]: the work units (lines of points along the last axis, warm-started from the
//!   previous point; boundary searches), run in parallel, results by index.
//!
//! The per-point regime rests on the section method of [`crate::ulc`]: the unstable cycle
//! and the stick-slip oscillation are found where they cross `x = x*, x' > 0`. An
//! oscillation that does not surround the fixed point (seen at low belt speed) is not
//! measured: such points are undecided, with a note saying so, as are points where the
//! section method and the operating point's own run disagree. Boundaries are found by
//! bisection in `nu` or `lambda`, which assumes one crossing in the bracketed range.
//!
//! ```
//! use squeal_core::{FrictionLaw, Params, Setup, SolverConfig};
//! use squeal_scan::atlas::{AtlasRegime, PointSettings, point::compute_point};
//! // The paper's Fig 10 (nu = 1e-2): the unstable cycle encloses the state at rest.
//! let setup = Setup::new(Params::paper(FrictionLaw::McMillan, 1e-2), 0.01, SolverConfig::default());
//! let p = compute_point(setup, &PointSettings::default(), None).unwrap();
//! assert_eq!(p.regime, AtlasRegime::BistableQuiet);
//! assert!(p.cycle.unwrap().r_section > 2.0 && p.stick_slip.unwrap().omega_mean < 1.0);
//! ```

pub mod attractor;
pub mod boundary;
pub mod columns;
pub mod driver;
pub mod figures;
pub mod geometry;
pub mod maps;
pub mod note;
pub mod point;
mod results;
pub mod spec;
pub mod true_stick;

pub use boundary::{Boundary, BoundaryParam, BoundaryStatus};
pub use driver::{BoundaryResult, LineResult, Unit, UnitResult};
pub use geometry::Region;
pub use maps::{MapFraction, PointMap, finish, map_fraction, point_maps};
pub use note::{Note, NoteKind};
pub use point::{AtlasRegime, PointResult, PointSettings};
pub use results::AtlasResults;
pub use spec::{AtlasPlan, MapSettings, ParamAxis, Units};
