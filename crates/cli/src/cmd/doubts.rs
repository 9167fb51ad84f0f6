//! Warnings about values that look like a slip of units (a friction coefficient in percent,
//! speeds in mm/s; [`squeal_core::units::Doubt`]), said before anything runs. One path for
//! every command: standard error, `warning: ` and one sentence, each sentence once per
//! process (the flags are read into a system more than once on the way to a run).

use std::sync::Mutex;

/// The sentences said so far.
static SAID: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// Says `sentence` on standard error as a warning, unless it was said already.
pub fn warn(sentence: &str) {
    let mut said = SAID.lock().unwrap_or_else(|p| p.into_inner());
    if !said.iter().any(|s| s == sentence) {
        eprintln!("warning: {sentence}");
        said.push(sentence.to_string());
    }
}

/// The flag a physical key is given by (`v_belt` is `--v-belt`), the curve as
/// `--friction-csv FILE`.
pub fn flag_name(key: &str, csv: Option<&std::path::Path>) -> String {
    match (key, csv) {
        ("friction_table", Some(path)) => format!("--friction-csv {}", path.display()),
        ("friction_table", None) => "--friction-csv".into(),
        _ => format!("--{}", key.replace('_', "-")),
    }
}

/// Says the doubts about the system of the physical flags, named by the flags.
pub fn warn_system(ph: &squeal_core::Physical, csv: Option<&std::path::Path>) {
    for d in ph.doubts() {
        warn(&d.sentence(&|key| flag_name(key, csv)));
    }
}

/// Says the doubts about a curve in the model's units (`--friction-csv` without the
/// physical flags): its mu alone.
pub fn warn_curve(t: &squeal_core::FrictionTable, csv: Option<&std::path::Path>) {
    for d in squeal_core::units::curve_doubts(t, false) {
        warn(&d.sentence(&|key| flag_name(key, csv)));
    }
}

/// Says the doubts about a spec's parameter space, named by its keys.
pub fn warn_space(space: &squeal_scan::space::Space) {
    for w in space.warnings() {
        warn(&w);
    }
}
