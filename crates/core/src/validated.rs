//! Where squeal's labels have been checked against long runs (crates/core/MODEL.md section
//! 11, "Where squeal has been checked"), and the warning for a run whose parameters leave
//! that region. One table, [`REGIONS`]; every command that prints or stores the warning asks
//! [`Validity::of`].

use serde::Serialize;

use crate::error::Number;
use crate::params::{FrictionLaw, Params};

/// The checked range of one named parameter ([`Params::named`]'s keys).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Range {
    /// The key (`lambda`, `tau`, `v_d`, ...).
    pub key: &'static str,
    /// Smallest value checked.
    pub lo: f64,
    /// Largest value checked.
    pub hi: f64,
}

/// The region of one law where its labels have been checked against long runs, and the
/// checks that did it (by name: the script and test to run).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CheckedRegion {
    /// The law.
    pub law: FrictionLaw,
    /// Its checked ranges; a key not listed was checked wherever it is valid.
    pub ranges: &'static [Range],
    /// The checks, by name.
    pub checks: &'static str,
}

const fn r(key: &'static str, lo: f64, hi: f64) -> Range {
    Range { key, lo, hi }
}

/// Table 1's surface time `0.1 sqrt(10)`, to the digits the checks used.
const TAU_1: f64 = 0.316_227_766_016_837_94;

/// The checked regions (crates/core/MODEL.md section 11 gives the measurements).
pub const REGIONS: &[CheckedRegion] = &[
    CheckedRegion {
        law: FrictionLaw::McMillan,
        ranges: &[
            r("lambda", 0.5, 5.0),
            r("tau", 0.05, 1.0),
            r("phi", 0.3, 1.4),
        ],
        checks: "scripts/long-checks.sh (off_paper \
                 early_stopping_agrees_with_settlement_off_the_paper) and \
                 scripts/edge-long-runs.sh",
    },
    CheckedRegion {
        law: FrictionLaw::McMillanNonHysteretic,
        ranges: &[
            r("lambda", 3.0, 3.0),
            r("tau", TAU_1, TAU_1),
            r("phi", 1.0, 1.0),
        ],
        checks: "crates/core/tests/model/paper.rs (Table 1 only)",
    },
    CheckedRegion {
        law: FrictionLaw::Stribeck,
        ranges: &[
            r("xi", 0.05, 0.05),
            r("v_d", 0.8, 2.225),
            r("mu_d", 0.5, 0.5),
            r("mu_sd", 2.0, 2.0),
            r("v_0", 0.5, 0.5),
            r("mu_v", 0.0, 0.0),
        ],
        checks: "scripts/long-checks.sh (bstab_friction \
                 squeal_matches_the_published_basin_stability)",
    },
];

/// A parameter of a run outside its law's checked range.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Unchecked {
    /// The key.
    pub key: &'static str,
    /// The run's value.
    pub value: f64,
    /// The checked range `[lo, hi]`.
    pub checked: [f64; 2],
}

/// Whether a run's parameters lie where its law's labels were checked against long runs.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Validity {
    /// Inside the checked region.
    pub checked: bool,
    /// The parameters outside it (empty inside; empty too for a law with no checked region).
    pub outside: Vec<Unchecked>,
    /// The checks that define the region (`null` for a law without one).
    pub checks: Option<&'static str>,
}

impl Validity {
    /// The validity of parameters `p`.
    pub fn of(p: &Params) -> Validity {
        let Some(region) = REGIONS.iter().find(|g| g.law == p.kind()) else {
            return Validity {
                checked: false,
                outside: Vec::new(),
                checks: None,
            };
        };
        let named = p.named();
        let outside: Vec<Unchecked> = region
            .ranges
            .iter()
            .filter_map(|g| {
                let v = named.iter().find(|n| n.name == g.key)?.value;
                // Relative slack for values given to fewer digits than the table's.
                let tol = 1e-9 * g.lo.abs().max(g.hi.abs());
                (v < g.lo - tol || v > g.hi + tol).then_some(Unchecked {
                    key: g.key,
                    value: v,
                    checked: [g.lo, g.hi],
                })
            })
            .collect();
        Validity {
            checked: outside.is_empty(),
            outside,
            checks: Some(region.checks),
        }
    }

    /// The warning to print, naming the parameters and the check; `None` inside the region.
    pub fn warning(&self) -> Option<String> {
        if self.checked {
            return None;
        }
        let Some(checks) = self.checks else {
            return Some(
                "warning: this law's labels have not been checked against long runs \
                 anywhere (crates/core/MODEL.md section 11): take them as unverified"
                    .into(),
            );
        };
        let what: Vec<String> = self
            .outside
            .iter()
            .map(|u| {
                // Numbers in the project's form: tau = 1e-300 was printed with 300 zeros.
                let (value, lo, hi) = (Number(u.value), Number(u.checked[0]), Number(u.checked[1]));
                if u.checked[0] == u.checked[1] {
                    format!("{} = {value} (checked only at {lo})", u.key)
                } else {
                    format!("{} = {value} (checked in [{lo}, {hi}])", u.key)
                }
            })
            .collect();
        Some(format!(
            "warning: outside the region where squeal's labels were checked against long runs: \
             {}; the check: {checks} (crates/core/MODEL.md section 11)",
            what.join(", ")
        ))
    }
}

/// The warning for a set of maps (a scan's or an atlas's): how many leave the checked
/// region, and the first one's warning; `None` if all lie inside.
pub fn maps_warning(maps: &[Params]) -> Option<String> {
    let mut outside = maps.iter().filter_map(|p| Validity::of(p).warning());
    let first = outside.next()?;
    let k = 1 + outside.count();
    Some(match maps.len() {
        1 => first,
        n => format!("{k} of {n} maps: {first}"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Friction, Surface};

    /// Table 1 is inside; the README's disc brake (lambda = 0.21053) is outside by its belt
    /// speed alone, and the warning names the key, the range and the check; a law without a
    /// checked region always warns.
    #[test]
    fn the_brake_leaves_the_checked_region_by_its_belt_speed() {
        assert!(Validity::of(&Params::paper(FrictionLaw::McMillan, 1e-3)).checked);
        assert!(Validity::of(&Params::bstab()).checked);
        let brake = Params {
            law: Friction::McMillan(Surface {
                tau: 0.65789,
                phi: 0.91353,
            }),
            nu: 0.025,
            lambda: 0.21053,
        };
        let v = Validity::of(&brake);
        assert_eq!(v.outside.len(), 1, "{v:?}");
        let w = v.warning().unwrap();
        assert!(
            w.contains("lambda = 0.21053 (checked in [0.5, 5])") && w.contains("off_paper"),
            "{w}"
        );
        let coulomb = Validity::of(&Params::paper(FrictionLaw::Coulomb, 1e-3));
        assert!(!coulomb.checked && coulomb.warning().unwrap().contains("not been checked"));
    }
}
