//! One module per subcommand; `model` and `physical` hold the flags shared by several,
//! `common` the run flags and helpers, `atlas_words` the atlas summary that `atlas` and
//! `info` print.

pub mod atlas;
pub mod atlas_words;
pub mod classify;
pub mod common;
pub mod compare;
pub mod critical;
pub mod critical_report;
pub mod friction;
pub mod info;
pub mod lifetimes;
pub mod map_words;
pub mod merge;
pub mod model;
pub mod physical;
pub mod pictures;
pub mod progress;
pub mod render;
pub mod scan;
pub mod scan_bars;
pub mod scan_report;
pub mod trajectory;
pub mod trajectory_report;
pub mod transient;
pub mod ulc;
