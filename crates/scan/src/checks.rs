//! Consistency checks of a finished map, computed from its cells: where the map's labels,
//! the located cycle and the run-to-settlement audit disagree, gathered with the map's basin
//! stability by [`MapTally`]. The store writes them into the file and the CLI prints them;
//! nothing here is a guess about which one is right.

use serde::{Deserialize, Serialize};
use squeal_core::{Landscape, Reason, Regime, State};

use crate::basin::GridShares;
use crate::cell::{Audit, Cell, NOT_COMPUTED};
use crate::curve::{ClosedCurve, CurveLocator};
use crate::spec::Plan;
use crate::ulc::CycleReport;

/// Decided cells on the wrong side of the located cycle (steady slip outside it, stick-slip
/// inside it), and those of them farther than one cell diagonal from the curve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct WrongSide {
    /// Cells on the wrong side.
    pub cells: u64,
    /// Of those, cells farther than one cell diagonal from the curve.
    pub beyond_pixel: u64,
}

/// The audit's tally (see [`crate::cell::Audit`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct AuditCounts {
    /// Cells audited.
    pub audited: u64,
    /// Same label run to settlement.
    pub agrees: u64,
    /// The other decided label run to settlement.
    pub disagrees: u64,
    /// Undecided when run to settlement (by `t_max`).
    pub undecided: u64,
}

/// The map's label at the grid cell nearest the state at rest `(0, 0)` (the operating
/// point of a machine started from rest) against what the cycle says there (inside: steady
/// slip, outside: stick-slip).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct OriginCheck {
    /// Whether the cycle encloses that cell's state.
    pub encloses: bool,
    /// The stored label value of the nearest cell.
    pub label: u8,
    /// Whether the label is decided and on the other side from the cycle's verdict.
    pub disagrees: bool,
}

/// Decided cells whose label contradicts a landscape that states one regime for every
/// start ([`Landscape::only_regime`]): steady slip where the fixed point repels, stick-slip
/// where no stick-slip cycle exists. Labels are never changed; this only counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct LandscapeCheck {
    /// The regime the landscape states for every start.
    pub regime: Regime,
    /// Decided cells with the other label.
    pub contradictions: u64,
}

/// Cells that no early decision reached: their runs went on until they settled (MODEL.md
/// section 9 says why a map can have none).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Settled {
    /// Steady slip by coming within `fp_radius` of the fixed point (`near_fixed_point`).
    pub steady_slip: u64,
    /// Stick-slip by the band rules, a band of turns off the section or a second stick
    /// (`settled_stick_slip`, `sticking_band`, `lasting_oscillation`, `stick_cycle`).
    pub stick_slip: u64,
}

impl Settled {
    /// Counts `cell` if its run went to settlement.
    fn add(&mut self, cell: &Cell) {
        match Reason::ALL.get(cell.reason as usize) {
            Some(Reason::NearFixedPoint) => self.steady_slip += 1,
            Some(
                Reason::SettledStickSlip
                | Reason::StickingBand
                | Reason::LastingOscillation
                | Reason::StickCycle,
            ) => self.stick_slip += 1,
            _ => {}
        }
    }
}

/// Every check of one map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MapChecks {
    /// Against the located cycle (None when no cycle).
    pub wrong_side: Option<WrongSide>,
    /// The run-to-settlement audit.
    pub audit: AuditCounts,
    /// The state at rest, when it lies in the grid and a cycle is known.
    pub origin: Option<OriginCheck>,
    /// Against the landscape, where it states one regime for every start.
    pub landscape: Option<LandscapeCheck>,
    /// The return map jumps past the cycle ([`crate::section::escape_above`]): starts outside
    /// may end in steady slip, so only stick-slip inside counts as the wrong side.
    #[serde(default)]
    pub escapes: bool,
    /// The inside rules were withdrawn from the map (a run from inside the cycle
    /// did not end at the fixed point), so stick-slip inside is no wrong side either.
    #[serde(default)]
    pub inside_open: bool,
    /// Cells whose runs went to settlement (no early decision reached them).
    #[serde(default)]
    pub settled: Settled,
    /// Cells per reason, indexed by [`Reason`] value (for summaries; not stored per map).
    #[serde(default)]
    pub reasons: [u64; Reason::ALL.len()],
    /// Steady-slip cells that stuck before they settled (`0 < t_squeal < inf`): transient
    /// squeal (for summaries; the per-cell `t_squeal` is stored).
    #[serde(default)]
    pub transient: u64,
}

/// The checks as stored per map (datasets over the map dimension): name, long name. The
/// value -1 means "not applicable" (no cycle located, or `(0, 0)` outside the grid).
pub const CHECK_FIELDS: &[(&str, &str)] = &[
    (
        "wrong_side_cells",
        "decided cells on the wrong side of the located cycle (-1: no cycle)",
    ),
    (
        "wrong_side_beyond_pixel",
        "of those, cells farther than one cell diagonal from the cycle (-1: no cycle)",
    ),
    (
        "audit_cells",
        "cells also run to settlement without early stopping",
    ),
    (
        "audit_agrees",
        "audited cells given the same label by the run to settlement",
    ),
    (
        "audit_disagrees",
        "audited cells given the other decided label by the run to settlement",
    ),
    (
        "audit_undecided",
        "audited cells the run to settlement left undecided by t_max",
    ),
    (
        "origin_disagrees",
        "1 if the label of the cell nearest (0, 0) contradicts whether the cycle encloses (0, 0) (-1: not checked)",
    ),
    (
        "landscape_contradictions",
        "decided cells labelled against the landscape: steady slip where the fixed point repels, stick-slip where no stick-slip cycle exists (-1: the landscape states no single regime)",
    ),
    (
        "settled_steady_slip",
        "cells labelled steady slip by a run taken to within fp_radius of the fixed point (no early decision reached them)",
    ),
    (
        "settled_stick_slip",
        "cells labelled stick-slip by a run taken to a settled band or a second stick (no early decision reached them)",
    ),
];

impl MapChecks {
    /// The values of [`CHECK_FIELDS`], in order.
    pub fn values(&self) -> [i64; 10] {
        let w = |f: fn(&WrongSide) -> u64| self.wrong_side.as_ref().map_or(-1, |w| f(w) as i64);
        [
            w(|w| w.cells),
            w(|w| w.beyond_pixel),
            self.audit.audited as i64,
            self.audit.agrees as i64,
            self.audit.disagrees as i64,
            self.audit.undecided as i64,
            self.origin.map_or(-1, |o| o.disagrees as i64),
            self.landscape.map_or(-1, |l| l.contradictions as i64),
            self.settled.steady_slip as i64,
            self.settled.stick_slip as i64,
        ]
    }

    /// Empty checks for a map whose cycle is `curve` (if any; `escapes` when its outside is
    /// not invariant) and whose landscape is `landscape` (if stated).
    pub fn new(
        curve: Option<&ClosedCurve>,
        landscape: Option<Landscape>,
        escapes: bool,
    ) -> MapChecks {
        MapChecks {
            escapes,
            wrong_side: curve.map(|_| WrongSide::default()),
            landscape: landscape
                .and_then(Landscape::only_regime)
                .map(|regime| LandscapeCheck {
                    regime,
                    contradictions: 0,
                }),
            ..MapChecks::default()
        }
    }

    /// Adds the cells of block `block` (row-major over its rows and all `x0`).
    pub fn add_block(
        &mut self,
        plan: &Plan,
        curve: Option<&ClosedCurve>,
        block: usize,
        cells: &[Cell],
    ) {
        let g = &plan.map.grid;
        let nx = g.x0.count;
        let rows = g.block_rows(block);
        // A random sample has no pixel: its mean spacing sqrt(area / n) stands in for one,
        // and no cell sits at the state at rest.
        let (diag, origin) = match &g.starts {
            crate::grid::Starts::Sample(s) => (
                ((g.x0.max - g.x0.min) * (g.v0.max - g.v0.min) / s.n as f64).sqrt()
                    * std::f64::consts::SQRT_2,
                None,
            ),
            crate::grid::Starts::Grid => (
                g.x0.spacing().hypot(g.v0.spacing()),
                nearest(g.x0, 0.0).zip(nearest(g.v0, 0.0)),
            ),
        };
        let locator = curve.map(|c| CurveLocator::new(c.clone()));
        for (k, cell) in cells.iter().enumerate() {
            let (row, col) = (rows.start + k / nx, k % nx);
            let tally = match Audit::from_u8(cell.audit) {
                Some(Audit::Agrees) => Some(&mut self.audit.agrees),
                Some(Audit::Disagrees) => Some(&mut self.audit.disagrees),
                Some(Audit::Undecided) => Some(&mut self.audit.undecided),
                _ => None,
            };
            if let Some(n) = tally {
                *n += 1;
                self.audit.audited += 1;
            }
            self.settled.add(cell);
            if let Some(n) = self.reasons.get_mut(cell.reason as usize) {
                *n += 1;
            }
            if cell.regime() == Some(Regime::SteadySlip)
                && cell.t_squeal > 0.0
                && cell.t_squeal.is_finite()
            {
                self.transient += 1;
            }
            if let (Some(l), Some(r)) = (self.landscape.as_mut(), cell.regime()) {
                if r != Regime::Undecided && r != l.regime {
                    l.contradictions += 1;
                }
            }
            let Some(c) = &locator else { continue };
            let (x, v) = g.state(row, col);
            let p = State { x, v };
            let inside = c.encloses(p);
            let regime = cell.regime();
            let wrong = match regime {
                Some(Regime::SteadySlip) => !inside && !self.escapes,
                Some(Regime::StickSlip) => inside && !self.inside_open,
                _ => false,
            };
            if let Some(w) = self.wrong_side.as_mut().filter(|_| wrong) {
                w.cells += 1;
                if c.curve().distance_to(p) > diag {
                    w.beyond_pixel += 1;
                }
            }
            if origin == Some((col, row)) {
                self.origin = Some(OriginCheck {
                    encloses: inside,
                    label: cell.regime,
                    disagrees: wrong,
                });
            }
        }
    }

    /// Adds the counts of `other`, the checks of other cells of the same map (started
    /// alike: the same cycle, landscape and withdrawn rules). The cell nearest the state at
    /// rest lies in one block, so at most one of the two holds its origin check.
    pub fn add(&mut self, other: &MapChecks) {
        if let (Some(w), Some(o)) = (self.wrong_side.as_mut(), other.wrong_side) {
            w.cells += o.cells;
            w.beyond_pixel += o.beyond_pixel;
        }
        let (a, b) = (&mut self.audit, other.audit);
        a.audited += b.audited;
        a.agrees += b.agrees;
        a.disagrees += b.disagrees;
        a.undecided += b.undecided;
        self.origin = self.origin.or(other.origin);
        if let (Some(l), Some(o)) = (self.landscape.as_mut(), other.landscape) {
            l.contradictions += o.contradictions;
        }
        self.settled.steady_slip += other.settled.steady_slip;
        self.settled.stick_slip += other.settled.stick_slip;
        for (n, k) in self.reasons.iter_mut().zip(other.reasons) {
            *n += k;
        }
        self.transient += other.transient;
    }

    /// Whether any check found a disagreement.
    pub fn any_disagreement(&self) -> bool {
        self.wrong_side.is_some_and(|w| w.cells > 0)
            || self.audit.disagrees > 0
            || self.origin.is_some_and(|o| o.disagrees)
            || self.landscape.is_some_and(|l| l.contradictions > 0)
    }
}
/// What a map's cells add up to, gathered block by block as the blocks arrive (one block in
/// memory at a time per caller, in any order, from any thread): its [`MapChecks`] and its
/// basin stability ([`GridShares`]). A scan's finish ([`crate::finish`]) and an atlas's
/// ([`crate::atlas::map_figures`]) feed it the stored blocks; which figures of the cycle the
/// checks rest on and how the shares are taken is decided here.
pub struct MapTally<'a> {
    /// The checks before any cell: what the cycle, the landscape and the withdrawn rules
    /// make of the map.
    start: MapChecks,
    curve: Option<&'a ClosedCurve>,
    gathered: std::sync::Mutex<Gathered>,
}

/// The blocks added so far: the sum of their checks, and every cell's label, row-major
/// `(v0, x0)` (not computed until its block arrives).
struct Gathered {
    checks: MapChecks,
    labels: Vec<u8>,
}

impl<'a> MapTally<'a> {
    /// Nothing gathered yet, for a map of `plan` whose located cycle is `cycle` (if any)
    /// and whose landscape is `landscape` (laws with true stick, if stated).
    pub fn new(
        plan: &Plan,
        cycle: Option<&'a CycleReport>,
        landscape: Option<Landscape>,
    ) -> MapTally<'a> {
        let curve = cycle.map(|r| &r.curve);
        let escapes = cycle.is_some_and(|r| r.escape.is_some());
        let start = MapChecks::new(curve, landscape, escapes);
        MapTally {
            start,
            curve,
            gathered: std::sync::Mutex::new(Gathered {
                checks: start,
                labels: vec![NOT_COMPUTED; plan.map.grid.cells()],
            }),
        }
    }

    /// The rule groups withdrawn from the map (before any block is added): where
    /// the census or the audit refuted the cycle's outside (inside) rules, its cells decided
    /// by runs may end in steady slip outside it (stick-slip inside it), and the wrong-side
    /// check no longer counts them.
    pub fn withdrawn(&mut self, groups: &[crate::census::Rules]) {
        use crate::census::Rules;
        self.start.escapes |= groups.contains(&Rules::Outside);
        self.start.inside_open |= groups.contains(&Rules::Inside);
        let g = self.gathered.get_mut().unwrap_or_else(|e| e.into_inner());
        g.checks.escapes = self.start.escapes;
        g.checks.inside_open = self.start.inside_open;
    }

    /// Adds the cells of block `block` (row-major over its rows and all `x0`): checked on
    /// the calling thread, then summed in (the sums do not depend on the order).
    pub fn add_block(&self, plan: &Plan, block: usize, cells: &[Cell]) {
        let mut checks = self.start;
        checks.add_block(plan, self.curve, block, cells);
        let start = plan.map.grid.block_rows(block).start * plan.map.grid.x0.count;
        let mut g = self.gathered.lock().unwrap_or_else(|e| e.into_inner());
        g.checks.add(&checks);
        for (l, c) in g.labels[start..].iter_mut().zip(cells) {
            *l = c.regime;
        }
    }

    /// The checks, the basin stability (a random sample's shares without sub-grids) and
    /// the map's labels.
    pub fn finish(self, plan: &Plan) -> (MapChecks, GridShares, Vec<u8>) {
        let g = self
            .gathered
            .into_inner()
            .unwrap_or_else(|e| e.into_inner());
        let shares = match plan.map.grid.starts {
            crate::grid::Starts::Sample(_) => GridShares::random(&g.labels),
            crate::grid::Starts::Grid => GridShares::of(&g.labels, plan.map.grid.x0.count),
        };
        (g.checks, shares, g.labels)
    }
}

/// Index of the axis value nearest `x`, if `x` lies within the axis range.
fn nearest(a: crate::grid::Axis, x: f64) -> Option<usize> {
    if x < a.min || x > a.max {
        return None;
    }
    let s = a.spacing();
    if s == 0.0 {
        return Some(0);
    }
    Some((((x - a.min) / s).round() as usize).min(a.count - 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_cells_against_a_square_cycle() {
        // A 3 x 3 grid on [-1, 1]^2 and a square of half-width 0.5 around (0, 0): only the
        // centre cell is inside. Label everything stick-slip but the centre steady slip,
        // then flip one corner to steady slip: one wrong-side cell, beyond a pixel? The
        // corner (1, 1) is 0.707 from the square; the cell diagonal is 1.414: not beyond.
        let mut plan = crate::Plan::from_toml(
            r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -1.0, max = 1.0, count = 3 }
v0 = { min = -1.0, max = 1.0, count = 3 }
block_rows = 3
[output]
path = "t.h5"
"#,
            "t.toml",
        )
        .unwrap();
        plan.map.grid.block_rows = 3;
        let sq = ClosedCurve::new(vec![-0.5, 0.5, 0.5, -0.5], vec![-0.5, -0.5, 0.5, 0.5]);
        let mut cell = Cell::fill();
        cell.regime = 2;
        let mut cells = vec![cell; 9];
        cells[4].regime = 1;
        cells[8].regime = 1;
        cells[0].audit = Audit::Disagrees as u8;
        cells[1].audit = Audit::Agrees as u8;
        let mut c = MapChecks::new(Some(&sq), None, false);
        c.add_block(&plan, Some(&sq), 0, &cells);
        assert_eq!(
            c.wrong_side,
            Some(WrongSide {
                cells: 1,
                beyond_pixel: 0
            })
        );
        assert_eq!(c.audit.audited, 2);
        assert_eq!(c.audit.disagrees, 1);
        let o = c.origin.unwrap();
        assert!(o.encloses && !o.disagrees);
        assert!(c.any_disagreement());
        assert_eq!(c.landscape, None);
        assert_eq!(c.values()[7], -1);
    }

    #[test]
    fn counts_labels_against_the_landscape() {
        // One block of 3 cells labelled steady slip, stick-slip and undecided: a landscape
        // of stick-slip only finds one contradiction, steady slip only one, bistable none
        // (not checked: -1).
        let plan = crate::Plan::from_toml(
            r#"version = 1
[model]
law = "stribeck"
[grid]
x0 = { min = -1.0, max = 1.0, count = 3 }
v0 = { min = 0.0, max = 0.0, count = 1 }
[output]
path = "t.h5"
"#,
            "t.toml",
        )
        .unwrap();
        let mut cells = vec![Cell::fill(); 3];
        cells[0].regime = Regime::SteadySlip as u8;
        cells[1].regime = Regime::StickSlip as u8;
        cells[2].regime = Regime::Undecided as u8;
        for (l, want) in [
            (Landscape::StickSlipOnly, 1),
            (Landscape::SteadySlipOnly, 1),
            (Landscape::Bistable, -1),
            (Landscape::Unknown, -1),
        ] {
            let mut c = MapChecks::new(None, Some(l), false);
            c.add_block(&plan, None, 0, &cells);
            assert_eq!(c.values()[7], want, "{l:?}");
            assert_eq!(c.any_disagreement(), want > 0, "{l:?}");
        }
        let mut c = MapChecks::new(None, Some(Landscape::StickSlipOnly), false);
        c.add_block(&plan, None, 0, &cells[1..]);
        assert_eq!(c.values()[7], 0);
    }

    #[test]
    fn a_tally_places_each_block_where_its_rows_lie() {
        // A 3 x 3 grid in blocks of one row; row 1 (the middle, block 1) steady slip, rows
        // 0 and 2 stick-slip, the blocks added out of order. On the grid 3 of 9 cells are
        // steady slip; the 2h sub-grid (rows and columns 0 and 2) holds none of them. A
        // tally that put block 1's labels anywhere but row 1 would find 2 of 4 there.
        let mut plan = crate::Plan::from_toml(
            r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -1.0, max = 1.0, count = 3 }
v0 = { min = -1.0, max = 1.0, count = 3 }
[output]
path = "t.h5"
"#,
            "t.toml",
        )
        .unwrap();
        plan.map.grid.block_rows = 1;
        let row = |regime: Regime| {
            let mut c = Cell::fill();
            c.regime = regime as u8;
            vec![c; 3]
        };
        let t = MapTally::new(&plan, None, None);
        t.add_block(&plan, 2, &row(Regime::StickSlip));
        t.add_block(&plan, 1, &row(Regime::SteadySlip));
        t.add_block(&plan, 0, &row(Regime::StickSlip));
        let (checks, shares, _) = t.finish(&plan);
        assert_eq!(shares.h.get(Regime::SteadySlip).count, 3);
        assert_eq!(shares.h.get(Regime::SteadySlip).p, 3.0 / 9.0);
        assert_eq!(shares.h2.get(Regime::SteadySlip).count, 0);
        assert_eq!(shares.h2.get(Regime::StickSlip).count, 4);
        assert_eq!(checks.wrong_side, None);
    }
}
