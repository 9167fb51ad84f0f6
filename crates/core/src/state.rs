//! The state of the oscillator: a point of the phase plane and the full sample of a run.

use serde::Serialize;

/// A point of the phase plane: displacement `x` and velocity `x'` (nondimensional).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct State {
    /// Displacement `x`.
    pub x: f64,
    /// Velocity `x'` (the block's, not the slip velocity).
    pub v: f64,
}

/// The full state of a run at one instant.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Sample {
    /// Time.
    pub t: f64,
    /// Displacement.
    pub x: f64,
    /// Velocity `x'`.
    pub v: f64,
    /// Acceleration `x''`.
    pub a: f64,
    /// Friction force `F`.
    pub force: f64,
}

impl Sample {
    /// The phase-plane point.
    pub fn state(&self) -> State {
        State {
            x: self.x,
            v: self.v,
        }
    }
}
