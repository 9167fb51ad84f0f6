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
    /// The physical units are McMillan's scaling; this law has none.
    #[error(
        "law {0} has no physical units (they are McMillan's scaling): give its nondimensional \
         parameters"
    )]
    NoPhysicalUnits(&'static str),
    /// A friction-law name that is not one of ours, with the names that are
    /// ([`crate::FrictionLaw::names`], so the next law needs no edit here).
    #[error("unknown friction law '{name}' (expected one of {expected})")]
    UnknownLaw {
        /// The name given.
        name: String,
        /// Every law's name.
        expected: String,
    },
    /// A scheme name that is not one of ours.
    #[error("unknown scheme '{0}' (expected foh or zoh)")]
    UnknownScheme(String),
    /// A solver name that is not one of ours.
    #[error("unknown solver '{0}' (expected robust or paper)")]
    UnknownSolver(String),
}

impl CoreError {
    /// `Err(InvalidParameter)`: a value out of its range, naming the key and what it must be.
    pub fn invalid<T>(
        name: &'static str,
        value: f64,
        expected: &'static str,
    ) -> Result<T, CoreError> {
        Err(CoreError::InvalidParameter {
            name,
            value,
            expected,
        })
    }
}
