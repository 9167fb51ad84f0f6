//! Errors of spec handling, scanning and limit-cycle location, in the model's terms.

use serde::{Deserialize, Serialize};

/// The damping of the model under its law's own name: `nu` for McMillan's laws, `xi` for
/// the Stribeck law. Stored flattened (`nu = 0.001` or `xi = 0.05`) and printed so.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Damping {
    /// McMillan's damping ratio `nu`.
    Nu(f64),
    /// The Stribeck law's damping ratio `xi`.
    Xi(f64),
}

impl Damping {
    /// The damping of `p` under its law's name.
    pub fn of(p: &squeal_core::Params) -> Damping {
        if p.damping_key() == "xi" {
            Damping::Xi(p.nu)
        } else {
            Damping::Nu(p.nu)
        }
    }

    /// The value.
    pub fn value(self) -> f64 {
        match self {
            Damping::Nu(v) | Damping::Xi(v) => v,
        }
    }

    /// The key (`nu` or `xi`).
    pub fn key(self) -> &'static str {
        match self {
            Damping::Nu(_) => "nu",
            Damping::Xi(_) => "xi",
        }
    }
}

impl std::fmt::Display for Damping {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // Exponent form for a huge or tiny value: `nu = 1e-300` was printed with 300 zeros.
        write!(
            f,
            "{} = {}",
            self.key(),
            squeal_core::error::Number(self.value())
        )
    }
}

/// Why no unstable limit cycle was located (a result about the model, not a failure of the
/// program: the scan stores it beside the map).
#[derive(Clone, Debug, PartialEq, thiserror::Error, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum NoCycle {
    /// `D(r) = P(r) - r < 0` at every sampled amplitude: no unstable cycle below `r_max`,
    /// every start inside it decays to steady slip.
    #[error(
        "the return map decays at every sampled section amplitude up to r = {} ({damping}; samples refined where a window of growth could hide, down to a relative width of 1e-3): no unstable cycle, no squeal below it", squeal_core::error::Number(*r_max)
    )]
    Decays {
        /// Largest amplitude sampled.
        r_max: f64,
        /// Damping of the model (`nu` or `xi`).
        #[serde(flatten)]
        damping: Damping,
    },
    /// `D > 0` already at `r_min`: the steady-slip fixed point repels.
    #[error(
        "the steady-slip fixed point repels or attracts no whole neighbourhood ({damping}): its linearisation says so, or the return map grows already at r = {}", squeal_core::error::Number(*r_min)
    )]
    FixedPointRepels {
        /// Smallest amplitude sampled.
        r_min: f64,
        /// Damping of the model (`nu` or `xi`).
        #[serde(flatten)]
        damping: Damping,
    },
    /// The run from the bisected crossing did not come back to the section.
    #[error(
        "the run from the section amplitude r = {} did not return within t = {}",
        squeal_core::error::Number(*r),
        squeal_core::error::Number(*t_return)
    )]
    NoReturn {
        /// The crossing.
        r: f64,
        /// Time allowed.
        t_return: f64,
    },
}

/// A refused value as an error message shows it ([`ScanError::Invalid`]'s `value`).
/// Deliberately not implemented for `f64`: a number goes through
/// [`squeal_core::error::Number`], so that a huge or tiny one reads `1e-300`, not `0.` and
/// 300 zeros, and a call site that passes a bare float does not compile.
pub trait Shown {
    /// The text of the value.
    fn shown(&self) -> String;
}

macro_rules! shown_by_display {
    ($($t:ty),*) => {$(
        impl Shown for $t {
            fn shown(&self) -> String {
                self.to_string()
            }
        }
    )*};
}
shown_by_display!(
    str,
    String,
    i64,
    u64,
    u32,
    usize,
    squeal_core::error::Number,
    squeal_core::CoreError
);

impl<T: Shown + ?Sized> Shown for &T {
    fn shown(&self) -> String {
        (**self).shown()
    }
}

/// What the scan crate refuses or could not do.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ScanError {
    /// The spec is not valid TOML or does not match the schema (the message has the line,
    /// column and key from the TOML parser).
    #[error("{path}: {message}")]
    Parse {
        /// The spec file.
        path: String,
        /// What the parser said.
        message: String,
    },
    /// A key has a value out of range.
    #[error("{path}: `{key}` = {value}: {expected}")]
    Invalid {
        /// The spec file.
        path: String,
        /// The TOML key.
        key: String,
        /// The value given, as the message shows it: a number in
        /// [`squeal_core::error::Number`]'s form (`1e-300`, not 300 zeros), which every call
        /// site that refuses an `f64` formats it with.
        value: String,
        /// What is accepted.
        expected: String,
    },
    /// The model or step were refused by the core crate.
    #[error(transparent)]
    Model(#[from] squeal_core::CoreError),
    /// The limit cycle could not be located.
    #[error("unstable limit cycle not found: {0}")]
    NoCycle(NoCycle),
    /// `squeal critical` has nothing to bisect (the point is the fixed point, or there is
    /// no unstable cycle at the low end of the bracket).
    #[error("no critical damping: {0}")]
    NoCriticalDamping(String),
    /// A design-space figure or boundary could not be decided (the reason in words).
    #[error("{0}")]
    Undetermined(String),
    /// The ray check of a located cycle cannot be run as asked.
    #[error("ray verification: {0}")]
    RayCheck(String),
    /// A shard that is not `K/N` with `1 <= K <= N`.
    #[error("bad shard {0:?}: expected K/N with 1 <= K <= N, e.g. 2/4")]
    Shard(String),
    /// The curve of the cycle does not meet a ray from the fixed point.
    #[error("the cycle's curve does not cross the ray at angle {angle} rad from the fixed point")]
    RayMissesCurve {
        /// Angle from `+x`.
        angle: f64,
    },
    /// A damping bracket that does not straddle the critical damping.
    #[error(
        "damping bracket [{}, {}] for ({}, {}): {}",
        squeal_core::error::Number(*nu_lo),
        squeal_core::error::Number(*nu_hi),
        squeal_core::error::Number(*x),
        squeal_core::error::Number(*v),
        match problem {
            BracketProblem::Order => "need 0 < lower bound < upper bound",
            BracketProblem::EnclosedAtLow => "the cycle already encloses the point at the lower bound: lower it",
            BracketProblem::NotEnclosedAtHigh => "the cycle does not enclose the point yet at the upper bound: raise it",
            BracketProblem::SquealsAtHigh => "a start still squeals at the upper bound: raise it",
        }
    )]
    Bracket {
        /// Lower damping.
        nu_lo: f64,
        /// Upper damping.
        nu_hi: f64,
        /// The point to be enclosed, `x`.
        x: f64,
        /// The point to be enclosed, `x'`.
        v: f64,
        /// What is wrong with the bracket.
        problem: BracketProblem,
    },
}

/// What is wrong with a damping bracket of [`crate::ulc::critical_nu`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BracketProblem {
    /// Not `0 < nu_lo < nu_hi < inf`.
    Order,
    /// Enclosed already at `nu_lo`.
    EnclosedAtLow,
    /// Not enclosed at `nu_hi`.
    NotEnclosedAtHigh,
    /// A boundary's predicate (no start squeals, the start settles) not true yet at the
    /// top of its range: the boundary lies above it.
    SquealsAtHigh,
}

impl BracketProblem {
    /// Where the boundary lies above the range, what the shortcut saw at its top (the runs
    /// may raise it, [`crate::fates::decide`]); `None` for the other problems.
    pub fn at_high(self) -> Option<&'static str> {
        match self {
            BracketProblem::NotEnclosedAtHigh => {
                Some("the unstable cycle does not enclose the start yet at the top")
            }
            BracketProblem::SquealsAtHigh => Some("a start still squeals at the top"),
            BracketProblem::Order | BracketProblem::EnclosedAtLow => None,
        }
    }
}

impl From<NoCycle> for ScanError {
    fn from(e: NoCycle) -> ScanError {
        ScanError::NoCycle(e)
    }
}
