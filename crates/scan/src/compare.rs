//! Two label maps of the same grid compared cell by cell: how far a scan agrees with
//! another of the same starts (a smaller step, runs to settlement, another rule).

use serde::Serialize;
use squeal_core::Regime;

use crate::cell::NOT_COMPUTED;

/// Cell-by-cell agreement of two label maps (stored label values).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Agreement {
    /// Cells compared (computed in both maps).
    pub cells: u64,
    /// Same decided label in both.
    pub agree: u64,
    /// Decided in both, different labels.
    pub disagree: u64,
    /// Decided in the first map only (the second left it undecided).
    pub undecided_second: u64,
    /// Decided in the second map only.
    pub undecided_first: u64,
    /// Undecided in both.
    pub undecided_both: u64,
    /// Cells not computed in one map or both (left out of `cells`).
    pub not_computed: u64,
    /// Row-major indices of the first disagreeing cells (at most [`Agreement::LISTED`]).
    pub first_disagreements: Vec<usize>,
}

impl Agreement {
    /// How many disagreeing cells are listed.
    pub const LISTED: usize = 20;

    /// Compares `a` with `b` (same length, row-major over the same grid).
    pub fn of(a: &[u8], b: &[u8]) -> Agreement {
        assert_eq!(a.len(), b.len(), "maps of one grid");
        let decided = |l: u8| l == Regime::SteadySlip as u8 || l == Regime::StickSlip as u8;
        let mut g = Agreement::default();
        for (k, (&x, &y)) in a.iter().zip(b).enumerate() {
            if x == NOT_COMPUTED || y == NOT_COMPUTED {
                g.not_computed += 1;
                continue;
            }
            g.cells += 1;
            match (decided(x), decided(y)) {
                (true, true) if x == y => g.agree += 1,
                (true, true) => {
                    g.disagree += 1;
                    if g.first_disagreements.len() < Self::LISTED {
                        g.first_disagreements.push(k);
                    }
                }
                (true, false) => g.undecided_second += 1,
                (false, true) => g.undecided_first += 1,
                (false, false) => g.undecided_both += 1,
            }
        }
        g
    }

    /// The share of compared cells with the same decided label in both maps (cells left
    /// undecided by either map count against it); NaN with no cells.
    pub fn share(&self) -> f64 {
        self.agree as f64 / self.cells as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every combination once: 0 undecided, 1 steady, 2 stick-slip, 255 not computed.
    #[test]
    fn counts_every_combination() {
        let a = [1, 2, 1, 2, 1, 0, 0, 255, 1];
        let b = [1, 2, 2, 1, 0, 1, 0, 1, 255];
        let g = Agreement::of(&a, &b);
        assert_eq!((g.cells, g.agree, g.disagree, g.not_computed), (7, 2, 2, 2));
        assert_eq!(
            (g.undecided_second, g.undecided_first, g.undecided_both),
            (1, 1, 1)
        );
        assert_eq!(g.first_disagreements, [2, 3]);
        assert_eq!(g.share(), 2.0 / 7.0);
    }
}
