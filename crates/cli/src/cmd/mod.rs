//! One module per subcommand; `model` and `physical` hold the flags shared by several,
//! `common` the run flags and helpers, `out_files` the files `trajectory` and `friction`
//! write, `atlas_words` the atlas summary that `atlas` and `info` print, `map_words` the
//! words about a scan's maps that `scan` and `info` print. A command's progress and report
//! have their own modules beside it (`scan_bars`, `scan_report`, `critical_args`,
//! `critical_report`, `trajectory_report`).

pub mod atlas;
pub mod atlas_words;
pub mod classify;
pub mod common;
pub mod compare;
pub mod critical;
pub mod critical_args;
pub mod critical_report;
pub mod critical_runs;
pub mod doubts;
pub mod friction;
pub mod info;
pub mod law_flags;
pub mod lifetimes;
pub mod map_words;
pub mod merge;
pub mod model;
pub mod out_files;
pub mod physical;
pub mod pictures;
pub mod progress;
pub mod render;
pub mod report;
pub mod scan;
pub mod scan_bars;
pub mod scan_report;
pub mod signals;
pub mod timings;
pub mod trajectory;
pub mod trajectory_report;
pub mod transient;
pub mod ulc;
