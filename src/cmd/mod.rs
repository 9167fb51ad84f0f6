//! One module per subcommand; `model` holds the flags shared by several.

pub mod atlas;
pub mod classify;
pub mod common;
pub mod compare;
pub mod critical;
pub mod friction;
pub mod info;
pub mod merge;
pub mod model;
pub mod render;
pub mod scan;
pub mod trajectory;
pub mod ulc;
