//! The model's tests against closed forms and the paper: one test binary, a module per
//! subject, so that cargo builds and links it once.

mod common;
mod cubic;
mod lasting;
mod orbit;
mod paper;
mod solver;
mod steady;
mod stribeck;
mod table;
