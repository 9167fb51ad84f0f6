//! The `[classifier]` table: its serde mirror ([`ClassifierSpec`]), early stopping
//! ([`EarlyStop`]) and the checked settings ([`ClassifierPlan`]).

use serde::{Deserialize, Serialize};
use squeal_core::Classifier;
use squeal_core::error::Number;

use super::{DEFAULT_AUDIT_EVERY, Invalid};
use crate::bounds::{Rules, count};
use crate::error::ScanError;

/// Early stopping of the classifier.
#[derive(Deserialize, Serialize, Debug, Clone, Copy, PartialEq, Eq, Default)]
#[serde(rename_all = "lowercase")]
pub enum EarlyStop {
    /// Locate the unstable cycle's crossing of the section first, then stop each run at its
    /// first crossing clearly inside or outside it.
    #[default]
    Cycle,
    /// Run every cell to settlement (fixed point reached or stick-slip band settled).
    None,
}

impl EarlyStop {
    /// The name used in specs and files.
    pub fn name(self) -> &'static str {
        match self {
            EarlyStop::Cycle => "cycle",
            EarlyStop::None => "none",
        }
    }
}

/// The `[classifier]` table (also read by the atlas spec, [`crate::atlas::spec`]).
#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct ClassifierSpec {
    t_max: Option<f64>,
    fp_radius: Option<f64>,
    settle_cycles: Option<i64>,
    settle_rtol: Option<f64>,
    #[serde(default)]
    early_stop: EarlyStop,
    trap_margin: Option<f64>,
    audit_every: Option<i64>,
    sensitivity_samples: Option<i64>,
}

/// The checked `[classifier]` table.
pub(crate) struct ClassifierPlan {
    pub classifier: Classifier,
    pub early_stop: EarlyStop,
    pub trap_margin: f64,
    pub audit_every: u64,
    pub sensitivity_samples: u64,
}

impl ClassifierSpec {
    /// The classifier settings for step `dt` on maps of `cells` cells, checked under
    /// [`Rules::Today`]; errors name `classifier.<key>`.
    pub(crate) fn check(
        &self,
        dt: f64,
        cells: usize,
        rules: Rules,
        invalid: Invalid,
    ) -> Result<ClassifierPlan, ScanError> {
        let c = self;
        let d = Classifier::default();
        let settle_cycles = c.settle_cycles.unwrap_or(d.settle_cycles as i64);
        rules.require((4..=100_000).contains(&settle_cycles), || {
            invalid(
                "classifier.settle_cycles",
                settle_cycles.to_string(),
                "a crossing count in 4..=100000",
            )
        })?;
        let key = "classifier.settle_cycles";
        let classifier = Classifier {
            t_max: c.t_max.unwrap_or(d.t_max),
            fp_radius: c.fp_radius.unwrap_or(d.fp_radius),
            settle_cycles: count(key, settle_cycles, "a crossing count", invalid)?,
            settle_rtol: c.settle_rtol.unwrap_or(d.settle_rtol),
            max_radius: d.max_radius,
            trap: None,
            band_rules: true,
        };
        rules.bound(|| classifier_bounds(&classifier, dt, invalid))?;
        Ok(ClassifierPlan {
            classifier,
            early_stop: c.early_stop,
            trap_margin: self.trap_margin(rules, invalid)?,
            audit_every: self.audit_every(cells, rules, invalid)?,
            sensitivity_samples: self.sensitivity_samples(cells, invalid)?,
        })
    }

    /// The `classifier.sensitivity_samples` for maps of `cells` cells: 0 (no extra runs) or
    /// a count in `64..=2^20` ([`crate::sensitivity::samples_for`] by default).
    fn sensitivity_samples(&self, cells: usize, invalid: Invalid) -> Result<u64, ScanError> {
        let key = "classifier.sensitivity_samples";
        let n = self
            .sensitivity_samples
            .unwrap_or(crate::sensitivity::samples_for(cells) as i64);
        if n != 0 && !(64..=1 << 20).contains(&n) {
            return Err(invalid(
                key,
                n.to_string(),
                "0 (no uncertainty exponent nor step sensitivity) or a number of starts in 64..=1048576",
            ));
        }
        count(key, n, "a number of starts", invalid)
    }

    /// The `classifier.trap_margin`, checked under [`Rules::Today`].
    fn trap_margin(&self, rules: Rules, invalid: Invalid) -> Result<f64, ScanError> {
        let trap_margin = self
            .trap_margin
            .unwrap_or(squeal_core::defaults::TRAP_MARGIN);
        let bound = crate::bounds::MIN_TRAP_MARGIN..0.5;
        rules.require(bound.contains(&trap_margin), || {
            invalid(
                "classifier.trap_margin",
                Number(trap_margin).to_string(),
                "a relative margin in [1e-10, 0.5): a narrower band is narrower than the error \
                 of the cycle's located crossing (about 1e-11 at the default step), and below \
                 1.1e-16 it is no band at all in f64",
            )
        })?;
        Ok(trap_margin)
    }

    /// The `classifier.audit_every` for maps of `cells` cells, checked under
    /// [`Rules::Today`].
    fn audit_every(&self, cells: usize, rules: Rules, invalid: Invalid) -> Result<u64, ScanError> {
        // Default: about one cell in 1024, at most about 16 cells per map. A cell run to
        // settlement near the cycle can take all of t_max: measured on 2 threads, the 16
        // audited cells of a 128 x 128 zoom on the fig9 boundary cost about 0.45 s, as much
        // as its 16384 early-stopped cells.
        let audit_every = self.audit_every.unwrap_or_else(|| {
            let cells = cells as i64;
            (DEFAULT_AUDIT_EVERY as i64).max(cells / 16)
        });
        let key = "classifier.audit_every";
        rules.require((0..=1 << 40).contains(&audit_every), || {
            invalid(
                key,
                audit_every.to_string(),
                "0 (no audit) or a sampling interval in 1..=2^40 cells",
            )
        })?;
        count(key, audit_every, "a sampling interval", invalid)
    }
}

/// Today's bounds on the classifier's settings at step `dt` (the core's own check, the
/// fixed point's ball, the steps of a run); errors name `classifier.<key>`.
fn classifier_bounds(classifier: &Classifier, dt: f64, invalid: Invalid) -> Result<(), ScanError> {
    classifier
        .validate()
        .map_err(|e| crate::bounds::core_error("classifier", e, invalid))?;
    if classifier.fp_radius > crate::bounds::MAX_FP_RADIUS {
        return Err(invalid(
            "classifier.fp_radius",
            Number(classifier.fp_radius).to_string(),
            "a radius in [1e-10, 0.01]: the ball must lie inside the unstable cycle, below \
                 the cycle search's first sample",
        ));
    }
    if classifier.fp_radius < crate::bounds::MIN_FP_RADIUS {
        return Err(invalid(
            "classifier.fp_radius",
            Number(classifier.fp_radius).to_string(),
            "a radius in [1e-10, 0.01]: a settled run jitters about the fixed point at the \
                 step's rounding, and a narrower ball is entered by chance or never (at 1e-15 \
                 runs that settle were labelled stick-slip)",
        ));
    }
    if classifier.t_max / dt > crate::bounds::MAX_STEPS {
        return Err(invalid(
            "classifier.t_max",
            Number(classifier.t_max).to_string(),
            &format!(
                "at most 1e10 steps per run (t_max / integration.dt = {:.3e} steps)",
                classifier.t_max / dt
            ),
        ));
    }
    Ok(())
}
