//! Errors of the numerical core.

/// What the core refuses.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum CoreError {
    /// A model or integration parameter is out of range.
    #[error("invalid {name} = {value}: expected {expected}")]
    InvalidParameter {
        name: &'static str,
        value: f64,
        expected: &'static str,
    },
    /// Parameters of another law given to this one.
    #[error("law {law} takes none of {keys}")]
    ForeignParameters {
        law: &'static str,
        keys: &'static str,
    },
    /// A law's own parameters are missing.
    #[error("law {law} needs its parameters {keys}")]
    MissingParameters {
        law: &'static str,
        keys: &'static str,
    },
    /// A friction-law name that is not one of ours.
    #[error(
        "unknown friction law '{0}' (expected mcmillan, mcmillan-nonhysteretic, coulomb or stribeck)"
    )]
    UnknownLaw(String),
    /// A scheme name that is not one of ours.
    #[error("unknown scheme '{0}' (expected foh or zoh)")]
    UnknownScheme(String),
    /// A solver name that is not one of ours.
    #[error("unknown solver '{0}' (expected robust or paper)")]
    UnknownSolver(String),
}
