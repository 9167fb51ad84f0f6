//! The atlas: scans over the design space (`nu`, `lambda`, `tau`, `phi`, or the physical
//! parameters) with figures of merit per parameter point and boundaries located by
//! bisection.
//!
//! * [`spec`]: the atlas TOML spec (a Cartesian product of values, lists and ranges; either
//!   nondimensional or physical) and its checked [`AtlasPlan`].
//! * [`point`]: one parameter point to a [`PointResult`]: the unstable cycle, the
//!   stick-slip attractor, the [`AtlasRegime`] and the basin fraction of steady slip.
//! * [`boundary`]: the fold of cycles and the critical damping of the operating point, by
//!   bisection in `nu`.
//! * [`columns`]: the stored figures as one table (HDF5, journal and JSON walk it).
//! * [`driver`]: the work units (lines of points along the last axis, warm-started from the
//!   previous point; boundary searches), run in parallel, results by index.

pub mod boundary;
pub mod columns;
pub mod driver;
pub mod point;
pub mod spec;

pub use boundary::{Boundary, BoundaryStatus};
pub use driver::{BoundaryResult, LineResult, Unit, UnitResult};
pub use point::{AtlasRegime, PointResult, PointSettings, Region};
pub use spec::{AtlasAxis, AtlasPlan, Units};
