//! Errors of spec handling, scanning and limit-cycle location.

/// What the scan crate refuses or could not do.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ScanError {
    /// The spec is not valid TOML or does not match the schema (the message has the line,
    /// column and key from the TOML parser).
    #[error("{path}: {message}")]
    Parse { path: String, message: String },
    /// A key has a value out of range.
    #[error("{path}: `{key}` = {value}: {expected}")]
    Invalid {
        path: String,
        key: String,
        value: String,
        expected: String,
    },
    /// The limit cycle could not be located.
    #[error("unstable limit cycle not found: {0}")]
    NoCycle(String),
    /// `squeal critical` has nothing to bisect (the point is the fixed point, or there is
    /// no unstable cycle at the low end of the bracket).
    #[error("no critical damping: {0}")]
    NoCriticalDamping(String),
    /// A bad `--shard K/N`.
    #[error("--shard {0}: expected K/N with 1 <= K <= N")]
    Shard(String),
}
