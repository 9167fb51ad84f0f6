//! Everything an atlas run has computed so far, by index: its points, boundary searches, map
//! blocks and map cycles, with the figures read off them (a map's basin fraction). The store
//! persists it and reads it back; the charts draw it.

use std::collections::BTreeMap;

use crate::atlas::{AtlasPlan, BoundaryResult, MapFraction, PointResult, Unit, UnitResult};
use crate::cell::Cell;
use crate::ulc::CycleOutcome;

/// Everything computed so far, by index.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasResults {
    /// Per point (C order over the swept axes); `None` where not computed.
    pub points: Vec<Option<PointResult>>,
    /// Per boundary search; `None` where not computed.
    pub boundaries: Vec<Option<BoundaryResult>>,
    /// Basin-map blocks by `(point, block)` (specs with a `[grid]`): cells row-major over
    /// the block's rows of `v0` and all `x0`.
    pub blocks: BTreeMap<(usize, usize), Vec<Cell>>,
    /// The cycle search of each map (`None` inside: not located), by point.
    pub map_cycles: BTreeMap<usize, Option<CycleOutcome>>,
}

impl AtlasResults {
    /// Nothing computed yet.
    pub fn new(plan: &AtlasPlan) -> AtlasResults {
        AtlasResults {
            points: vec![None; plan.n_points()],
            boundaries: vec![None; plan.n_boundaries()],
            blocks: BTreeMap::new(),
            map_cycles: BTreeMap::new(),
        }
    }

    /// The cells of point `i`'s map, row-major over `(v0, x0)`, if every block is stored.
    pub fn map_cells(&self, plan: &AtlasPlan, i: usize) -> Option<Vec<Cell>> {
        let g = plan.maps.as_ref()?.grid;
        let mut out = Vec::with_capacity(g.cells());
        for b in 0..g.blocks() {
            out.extend_from_slice(self.blocks.get(&(i, b))?);
        }
        Some(out)
    }

    /// The located cycle of point `i`'s map, if there is one.
    pub fn map_cycle(&self, i: usize) -> Option<&crate::ulc::CycleReport> {
        match self.map_cycles.get(&i) {
            Some(Some(Ok(r))) => Some(r),
            _ => None,
        }
    }

    /// The basin fraction of steady slip read off point `i`'s map
    /// ([`crate::atlas::map_fraction`]), if the map is complete.
    pub fn map_fraction(&self, plan: &AtlasPlan, i: usize) -> Option<MapFraction> {
        let g = plan.maps.as_ref()?.grid;
        let cells = self.map_cells(plan, i)?;
        Some(crate::atlas::map_fraction(
            &g,
            &cells,
            self.map_cycle(i).map(|r| &r.curve),
        ))
    }

    /// The basin fraction of point `i` and its uncertainty as reported: from the map when
    /// the spec makes maps, else the point's own (from its cycle).
    pub fn basin_fraction(&self, plan: &AtlasPlan, i: usize) -> (f64, f64) {
        if plan.maps.is_some() {
            return self
                .map_fraction(plan, i)
                .map_or((f64::NAN, f64::NAN), |f| (f.fraction, f.err));
        }
        self.points[i].as_ref().map_or((f64::NAN, f64::NAN), |p| {
            (p.basin_fraction, p.basin_fraction_err)
        })
    }

    /// Stores a finished unit.
    pub fn add(&mut self, plan: &AtlasPlan, r: UnitResult) {
        match r {
            UnitResult::Line(l) => {
                let len = plan.line_len();
                for (k, p) in l.points.into_iter().enumerate() {
                    if let Some(slot) = self.points.get_mut(l.line * len + k) {
                        *slot = Some(p);
                    }
                }
            }
            UnitResult::Boundary(b) => {
                if let Some(slot) = self.boundaries.get_mut(b.index) {
                    *slot = Some(b);
                }
            }
        }
    }

    /// Whether a unit is stored.
    pub fn is_done(&self, plan: &AtlasPlan, u: Unit) -> bool {
        match u {
            Unit::Line(i) => {
                let len = plan.line_len();
                self.points[i * len..(i + 1) * len]
                    .iter()
                    .all(Option::is_some)
            }
            Unit::Boundary(j) => self.boundaries[j].is_some(),
        }
    }
}
