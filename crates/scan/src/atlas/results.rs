//! Everything an atlas run has computed so far, by index: its points, boundary searches, map
//! blocks and map cycles, with the figures read off them (a map's basin fraction). The store
//! persists it and reads it back; the charts draw it.

use std::collections::BTreeMap;

use crate::atlas::{
    AtlasPlan, AtlasRegime, BoundaryResult, BoundaryStatus, MapFraction, PointResult, Unit,
    UnitResult,
};
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
            points: vec![None; plan.space.n_points()],
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

    /// The points above their fold's stated interval along the bisected axis
    /// (`fold + uncertainty`, where the fold was found with an uncertainty): there no start
    /// squeals for good.
    pub fn above_fold(&self, plan: &AtlasPlan) -> Vec<usize> {
        let (_, Some(dk)) = plan.boundary_axis() else {
            return Vec::new();
        };
        let shape = plan.space.shape();
        let stride: usize = shape[dk + 1..].iter().product();
        let mut out = Vec::new();
        for (j, b) in self.boundaries.iter().enumerate() {
            let Some(f) = b.as_ref().map(|b| b.fold) else {
                continue;
            };
            if f.status != BoundaryStatus::Found || !f.uncertainty.is_finite() {
                continue;
            }
            let (i0, _) = plan.boundary_setup(j);
            out.extend(
                (0..shape[dk])
                    .map(|k| i0 + k * stride)
                    .filter(|&i| {
                        plan.boundary_in.get(&plan.space.params_at(i)) > f.nu + f.uncertainty
                    })
                    .filter(|&i| self.points[i].is_some()),
            );
        }
        out
    }

    /// Points above their fold's interval ([`AtlasResults::above_fold`]) whose stick-slip run
    /// stayed for the attractor's window (bistable labels) contradict the crisis, which says
    /// no start squeals for good there: the run sat on a leaking band (a long transient), or
    /// the regime flips between the coarse steps. Two findings disagree, so the point is
    /// undecided, with a note naming both (never one of them guessed). Returns how many.
    /// Done once all units are in (the file is written from the reconciled results), and
    /// idempotent.
    pub fn reconcile_folds(&mut self, plan: &AtlasPlan) -> usize {
        let mut n = 0;
        for i in self.above_fold(plan) {
            let Some(p) = self.points[i].as_mut() else {
                continue;
            };
            if !matches!(
                p.regime,
                AtlasRegime::BistableQuiet | AtlasRegime::BistableSqueals
            ) {
                continue;
            }
            // Any earlier note is kept before the conflict's words.
            let conflict = super::Note::conflict(format!(
                "conflict: labelled {} by a stick-slip run that stayed for the attractor's window, but the point lies above its fold's interval, where the band leaks (a long transient, or the regime flips between the coarse steps)",
                p.regime.name()
            ));
            p.note = Some(super::Note::add(p.note.take(), conflict));
            p.regime = AtlasRegime::Undecided;
            n += 1;
        }
        n
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atlas::Boundary;
    use crate::atlas::columns::{empty_boundary, empty_point};

    /// No point past its fold may be called bistable: on the shipped chart (`scans/atlas-lambda-
    /// nu.toml` at 280889b) 2 of 880 points above their fold's interval were labelled
    /// bistable by a stick-slip run that stayed for the attractor's window, where the crisis
    /// says no start squeals for good. Here: folds at nu = 0.02 +- 0.001 at each of three
    /// belt speeds, every point bistable; the points at nu = 0.05 (above 0.021) become
    /// undecided with a note, those at 1e-3, 0.0037 and 0.0136 keep their label, and a
    /// second pass changes nothing.
    #[test]
    fn points_above_their_fold_labelled_bistable_become_undecided() {
        let plan = AtlasPlan::from_toml(
            "version = 1\nname = \"f\"\n[model]\nlaw = \"mcmillan\"\n\
             nu = { from = 1e-3, to = 0.05, count = 4, spacing = \"log\" }\n\
             lambda = { from = 1.0, to = 4.0, count = 3 }\n[output]\npath = \"f.h5\"\n",
            "f.toml",
        )
        .unwrap();
        let mut res = AtlasResults::new(&plan);
        for j in 0..plan.n_boundaries() {
            let mut b = empty_boundary(j);
            b.fold = Boundary {
                nu: 0.02,
                uncertainty: 0.001,
                status: BoundaryStatus::Found,
                ..Boundary::none()
            };
            res.add(&plan, UnitResult::Boundary(b));
        }
        for p in res.points.iter_mut() {
            let mut q = empty_point();
            q.regime = AtlasRegime::BistableQuiet;
            *p = Some(q);
        }
        assert_eq!(res.reconcile_folds(&plan), 3);
        let mut seen = 0;
        for (i, p) in res.points.iter().enumerate() {
            let p = p.as_ref().unwrap();
            let nu = plan.space.params_at(i).nu;
            if nu > 0.021 {
                assert_eq!(p.regime, AtlasRegime::Undecided, "nu {nu}");
                let note = p.note.as_ref().unwrap();
                assert_eq!(note.kind, super::super::NoteKind::Conflict);
                assert!(note.text.contains("fold's interval"));
                seen += 1;
            } else {
                assert_eq!(p.regime, AtlasRegime::BistableQuiet, "nu {nu}");
            }
        }
        assert_eq!(seen, 3);
        assert_eq!(res.reconcile_folds(&plan), 0);
    }
}
