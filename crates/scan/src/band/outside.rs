//! The outside of the unstable cycle: whether every sampled start outside it stays outside
//! ([`Outside::Invariant`]), or some fall back inside and the band above the cycle is then
//! checked for a trap ([`Outside::Escapes`]). The one rule of every path that labels a run.

use squeal_core::Stepper;

use super::{Band, band_above_n};
use crate::section::{self, CycleSettings, SectionCycles};

/// What the section search says of the outside of the unstable cycle, and what the scan
/// does about it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outside {
    /// No sampled start outside the cycle returns inside: starts outside end in stick-slip,
    /// and the trap and the start rule may say so without a run.
    Invariant,
    /// The start `r_escape` (and maybe others) returns inside ([`crate::section::escape_above`]):
    /// the trap and the start rule decide only inside the cycle. `band`: whether the
    /// stick-slip band above the cycle is trapped ([`super::band_above`]); if not,
    /// no run is labelled stick-slip by its section band either (runs end at the fixed
    /// point or undecided at `t_max`).
    Escapes { r_escape: f64, band: Band },
}

impl Outside {
    /// Whether a run may be labelled stick-slip by its section band
    /// ([`squeal_core::Classifier::band_rules`]).
    pub fn band_rules(&self) -> bool {
        match self {
            Outside::Invariant => true,
            Outside::Escapes { band, .. } => band.attracts(),
        }
    }
}

/// What the section search `found` on `stepper` says of the outside of the unstable cycle
/// (`None`: no unstable cycle found). The one rule of every path that labels a run: the
/// scan's maps, `classify`, `trajectory` ([`crate::scanner::classifier_for`]) and the atlas's confirmation
/// runs.
pub fn outside_of(stepper: &Stepper, cs: &CycleSettings, found: &SectionCycles) -> Option<Outside> {
    outside_with(stepper, cs, found, super::NSAMPLES)
}

/// [`outside_of`] with the band sampled at `samples` uniform points
/// ([`band_above_n`]).
pub fn outside_with(
    stepper: &Stepper,
    cs: &CycleSettings,
    found: &SectionCycles,
    samples: usize,
) -> Option<Outside> {
    outside_on(
        &section::ReturnMap::new(stepper, cs.t_return),
        found,
        samples,
    )
}

/// [`outside_with`] on the return map `map` (its stepper and return time).
pub fn outside_on(
    map: &section::ReturnMap,
    found: &SectionCycles,
    samples: usize,
) -> Option<Outside> {
    let SectionCycles::Unstable {
        r,
        stable_above,
        escape,
        ..
    } = *found
    else {
        return None;
    };
    Some(match escape {
        None => Outside::Invariant,
        Some(r_escape) => {
            let top = stable_above.unwrap_or(2.0 * r);
            Outside::Escapes {
                r_escape,
                band: band_above_n(map, r, top, samples, &mut section::Work::default()),
            }
        }
    })
}
