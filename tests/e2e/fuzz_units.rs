//! Fuzz families "unit slips" and "extreme physical values" (drawn by `fuzz.rs`'s
//! `fuzz_specs_flags_and_files`, and a fixed handful in the quick suite): a brake given in
//! SI flags, one to three of its values set across the whole range of f64 (5e-324 to
//! 1.8e308, and values off by the factors of a unit slip: 1000, 100), on a measured curve
//! given in m/s, mm/s or percent. Each run must be refused naming a flag the user gave, or
//! run with its slips warned of, and never report nonsense: a run that goes ahead has a
//! belt speed the step resolves (lambda, v_d >= dt, crates/core's `Params::check_step`)
//! and a finite final state.

use std::fmt::Write as _;

use super::fuzz::{Case, Rng};

/// The pad's curve of scans/data/pad-mu.csv, as (slip speed m/s, mu).
const CURVE: [(f64, f64); 8] = [
    (0.0, 0.48),
    (0.05, 0.45),
    (0.1, 0.43),
    (0.2, 0.41),
    (0.3, 0.40),
    (0.5, 0.385),
    (1.0, 0.37),
    (2.0, 0.36),
];

/// A value across the decades of f64: a mantissa of 1, 2 or 5 (or the extremes, or a
/// plausible value slipped by a unit's factor) times a power of ten from 1e-323 to 1e308.
fn decade_value(rng: &mut Rng, plausible: f64) -> String {
    match rng.below(6) {
        0 => rng
            .pick(&["5e-324", "1e308", "1.7976931348623157e308", "2.2e-308"])
            .to_string(),
        1 => format!("{:e}", plausible * rng.pick(&[1000.0, 100.0, 1e-3, 1e-2])),
        _ => {
            let e = -323 + rng.below(632) as i32;
            let m = rng.pick(&[1.0, 2.0, 5.0]);
            format!("{m}e{e}")
        }
    }
}

/// The flags a case may set, with a plausible value for each (README section 4's brake).
const FLAGS: [(&str, f64); 8] = [
    ("--m", 0.8),
    ("--k", 2e5),
    ("--c", 20.0),
    ("--v-belt", 0.3),
    ("--normal-force", 1500.0),
    ("--mu-k", 0.38),
    ("--mu-s", 0.48),
    ("--tau-s", 5e-4),
];

/// A case of the families: the brake under McMillan's law or on its measured curve, one to
/// three flags at extreme or slipped values, its expectations in `check`.
pub(crate) fn case(rng: &mut Rng) -> Case {
    let table = rng.below(2) == 0;
    let (speed, mu) = *rng.pick(&[(1.0, 1.0), (1000.0, 1.0), (1.0, 100.0), (1000.0, 100.0)]);
    let own: &[(&str, f64)] = if table { &FLAGS[..5] } else { &FLAGS };
    let mut values: Vec<(&str, String)> = own.iter().map(|(f, v)| (*f, format!("{v:?}"))).collect();
    for _ in 0..1 + rng.below(3) {
        let i = rng.below(values.len());
        values[i].1 = decade_value(rng, own[i].1);
    }
    let mut args: Vec<String> = vec!["trajectory".into(), "--t-end".into(), "5".into()];
    let mut files = Vec::new();
    if table {
        let mut csv = String::from("slip_speed,mu\n");
        for (s, m) in CURVE {
            let _ = writeln!(csv, "{:?},{:?}", s * speed, m * mu);
        }
        files.push(("curve.csv".to_string(), csv.into_bytes()));
        args.extend(["--law", "table", "--friction-csv", "curve.csv"].map(String::from));
    }
    for (f, v) in &values {
        args.extend([f.to_string(), v.clone()]);
    }
    let slipped_curve = table && (speed != 1.0 || mu != 1.0);
    let given: Vec<String> = args
        .iter()
        .filter(|a| a.starts_with("--"))
        .cloned()
        .collect();
    let mu_flags: Vec<String> = (values.iter())
        .filter(|(f, v)| f.starts_with("--mu") && v.parse::<f64>().is_ok_and(|x| x > 2.0))
        .map(|(f, _)| f.to_string())
        .collect();
    let check = move |code: Option<i32>, output: &str| -> Result<(), String> {
        expect(code, output, (&given, slipped_curve, &mu_flags))
    };
    Case {
        what: format!(
            "unit slips: {} curve x{speed} speeds x{mu} mu",
            if table { "table" } else { "mcmillan" }
        ),
        args,
        files,
        announces: false,
        fifos: Vec::new(),
        check: Some(Box::new(check)),
    }
}

/// What a case of the families must do: refused naming a flag given (`given`), or run
/// with a curve in mm/s or percent (`slipped_curve`) and mu flags above 2 (`mu_flags`)
/// warned of, a belt speed of at least the step and a finite final state.
fn expect(
    code: Option<i32>,
    output: &str,
    (given, slipped_curve, mu_flags): (&[String], bool, &[String]),
) -> Result<(), String> {
    if code != Some(0) {
        let line = output
            .lines()
            .find(|l| l.starts_with("error: "))
            .unwrap_or("");
        let named = given
            .iter()
            .any(|f| line.contains(&format!("{f}:")) || line.contains(&format!("{f} ")));
        return match named {
            true => Ok(()),
            false => Err(format!("refused without naming a flag given: {line:?}")),
        };
    }
    if slipped_curve && !output.contains("warning: --friction-csv curve.csv: ") {
        return Err("a curve in mm/s or percent ran without a warning".into());
    }
    for f in mu_flags {
        if !output.contains(&format!("warning: {f} = ")) {
            return Err(format!("{f} above 2 ran without a warning"));
        }
    }
    // The run's line: "run: LAW nu=.. lambda=.. ... dt=0.005 ...".
    let run = output
        .lines()
        .find(|l| l.starts_with("run: "))
        .unwrap_or("");
    let field = |name: &str| {
        run.split_whitespace()
            .find_map(|w| w.strip_prefix(name)?.parse::<f64>().ok())
    };
    let speed = field("lambda=").or_else(|| field("v_d="));
    match (speed, field("dt=")) {
        (Some(s), Some(dt)) if s >= dt => {}
        _ => return Err(format!("a belt speed the step cannot resolve ran: {run:?}")),
    }
    let last = output
        .lines()
        .find(|l| l.starts_with("final state: "))
        .unwrap_or("NaN");
    if last.contains("NaN") || last.contains("inf") {
        return Err(format!("nonsense final state: {last:?}"));
    }
    Ok(())
}

/// A fixed handful of the families' cases in the quick suite (the fuzz run draws more):
/// seeds 1 to 24 of the family, each judged by the fuzz run's rules and the family's.
#[test]
fn unit_slips_and_extreme_values_are_refused_by_name_or_warned() {
    let root = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for k in 0..24u64 {
        let mut rng = Rng::new(50, k);
        let case = case(&mut rng);
        let dir = root.path().join(format!("case-{k}"));
        std::fs::create_dir_all(&dir).unwrap();
        if let Err(why) = super::fuzz::judge(&case, &dir) {
            failures.push(format!("case {k}: squeal {}\n  {why}", case.args.join(" ")));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
