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
        let decided = |l: u8| Regime::from_u8(l).is_some_and(|r| r != Regime::Undecided);
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

    /// Cells decided in at least one map: the cells agreement is counted over (a cell
    /// undecided in both says nothing about either map's labels).
    pub fn decided(&self) -> u64 {
        self.cells - self.undecided_both
    }

    /// The share of [`Agreement::decided`] cells with the same label in both maps (a cell
    /// left undecided by one map only counts against it); NaN when no cell is decided.
    pub fn share(&self) -> f64 {
        self.agree as f64 / self.decided() as f64
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
        // Over the 6 cells decided in at least one map (the one undecided in both is out).
        assert_eq!(g.decided(), 6);
        assert_eq!(g.share(), 2.0 / 6.0);
    }

    /// Two identical maps with every cell undecided: nothing decided, so no share of
    /// agreement (was 0 of 4 cells agreeing).
    #[test]
    fn maps_undecided_in_both_have_no_share() {
        let g = Agreement::of(&[0; 4], &[0; 4]);
        assert_eq!((g.cells, g.undecided_both, g.decided()), (4, 4, 0));
        assert!(g.share().is_nan());
    }
}
