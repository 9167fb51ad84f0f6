//! A seeded fuzz run of the binary: the shipped specs of `scans/` made small and
//! mutated (numbers set to hostile values, keys dropped, added or given the wrong type), and
//! command lines with hostile flag values and input files, and a brake's SI flags at
//! extreme values or slipped units (`fuzz_units`: refused by a flag given, or warned, never
//! nonsense), each run under a time limit in a fresh folder. A case fails on a panic (exit
//! 101 or "panicked"), a hang (the time limit reached with nothing said: a long run
//! announces its estimate first) or a lost file (a file there before the run missing or
//! changed after it; no case passes `--force` but those of [`fifos`], whose only target is
//! the FIFO). The family [`fifos`] puts a FIFO at one path of a command; it must be refused
//! within seconds.
//!
//! Ignored by the quick suite; `scripts/ci/fuzz.sh` runs it by exact name (`.ci/run` calls it):
//!
//! ```text
//! SQUEAL_FUZZ_SEED=7 SQUEAL_FUZZ_SECONDS=60 scripts/ci/fuzz.sh
//! ```
//!
//! The seed (default 32) fixes every case: case `k` draws from the seed and `k` alone, so a
//! failure printed as `case k` comes back with the same seed whatever the time budget
//! (default 100 s, two cases at a time).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use squeal_mutate::{Shipped, Step, at, shipped};

mod fifos;
use toml::Value;

const BIN: &str = env!("CARGO_BIN_EXE_squeal");

/// Most CPU time a case may use (on Linux, where /proc tells it; wall time elsewhere): the
/// machine running the suite may be shared, and a case of 5 s of CPU took 30 s of wall
/// time there. A case that reaches it having printed something (a scan's or an atlas's
/// estimate) is a long run, counted; one that printed nothing hangs.
const CASE_LIMIT: Duration = Duration::from_secs(20);

/// Longest wall time a case may take, whatever its CPU time (a run blocked on a read uses
/// none).
const WALL_LIMIT: Duration = Duration::from_secs(90);

/// CPU seconds used so far by process `pid` (user and system, from /proc/PID/stat at 100
/// ticks a second); `None` where /proc does not tell.
fn cpu_seconds(pid: u32) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The fields after the command name (which may hold spaces) in parentheses.
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    // utime and stime are fields 14 and 15 of the line, 12 and 13 after the name.
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// xorshift64*: small, seeded, the same on every machine.
pub(crate) struct Rng(u64);

impl Rng {
    pub(crate) fn new(seed: u64, case: u64) -> Rng {
        // splitmix64 of the pair: neighbouring cases draw unrelated streams.
        let mut z = seed ^ case.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        Rng((z ^ (z >> 31)) | 1)
    }

    pub(crate) fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    pub(crate) fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }
}

/// Hostile numbers for any key or flag: each was, at some point, accepted and wrong, or a
/// crash, somewhere in the project's history.
const HOSTILE: [&str; 14] = [
    "0", "-1", "nan", "inf", "-inf", "1e308", "-1e308", "5e307", "1e-320", "-1e-300", "2.5", "3",
    "1e300", "0.5",
];

/// Values for flags that set an amount of work (a time, a count): the hostile ones that are
/// refused or cheap, not a legitimately long run (`--t-end 1e6` is minutes, not a bug).
const WORK: [&str; 10] = [
    "0", "-1", "nan", "inf", "-inf", "1e308", "-1e308", "1e-320", "abc", "",
];

/// Words in a flag's name that make it an amount of work.
const WORK_WORDS: [&str; 13] = [
    "t-end",
    "t-max",
    "t-return",
    "samples",
    "starts",
    "count",
    "steps",
    "rays",
    "window",
    "transient",
    "periods",
    "revolutions",
    "every",
];

/// What a run did.
struct Run {
    code: Option<i32>,
    output: String,
    timed_out: bool,
}

fn run(dir: &Path, args: &[String]) -> Run {
    run_within(dir, args, WALL_LIMIT)
}

/// [`run`] killed after `wall` of wall time.
fn run_within(dir: &Path, args: &[String], wall: Duration) -> Run {
    let (out, err) = (dir.join(".stdout"), dir.join(".stderr"));
    let mut child = Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .expect("the squeal binary runs");
    let t0 = Instant::now();
    let (status, timed_out) = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break (Some(s), false);
        }
        let used = cpu_seconds(child.id()).map_or(t0.elapsed(), Duration::from_secs_f64);
        if used >= CASE_LIMIT || t0.elapsed() >= wall {
            let _ = child.kill();
            let _ = child.wait();
            break (None, true);
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let output = [out, err]
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap_or_default())
        .collect::<Vec<_>>()
        .join("\n");
    Run {
        code: status.and_then(|s| s.code()),
        output,
        timed_out,
    }
}

/// Every plain file under `dir` (its run's own output captures left out) and its bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
            let (p, t) = (e.path(), e.file_type().unwrap());
            if t.is_dir() {
                todo.push(p);
            } else if t.is_file() && !p.file_name().unwrap().to_string_lossy().starts_with(".std") {
                out.insert(p.clone(), std::fs::read(&p).unwrap_or_default());
            }
        }
    }
    out
}

/// What a family expects of a run beyond the rules of every case: given its exit code and
/// output, why it failed.
pub(crate) type Check = Box<dyn Fn(Option<i32>, &str) -> Result<(), String>>;

/// A case: its command line, in a folder prepared by `prepare`.
pub(crate) struct Case {
    pub(crate) what: String,
    pub(crate) args: Vec<String>,
    pub(crate) files: Vec<(String, Vec<u8>)>,
    /// Whether a timeout after some output is a long run (scans and atlases announce their
    /// estimate, critical and ulc their search's progress) rather than a hang.
    pub(crate) announces: bool,
    /// Paths made FIFOs before the run ([`fifos`]): the run must be refused, naming one,
    /// within [`fifos::LIMIT`].
    pub(crate) fifos: Vec<String>,
    /// The family's own expectations of a run that ended (`fuzz_units`: refused by a flag
    /// given, or warned, never nonsense).
    pub(crate) check: Option<Check>,
}

/// Why a case failed, if it did.
pub(crate) fn judge(case: &Case, dir: &Path) -> Result<&'static str, String> {
    for (name, bytes) in &case.files {
        let p = dir.join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).unwrap();
        }
        std::fs::write(p, bytes).unwrap();
    }
    if !case.fifos.is_empty() {
        return fifos::judge(case, dir);
    }
    let before = snapshot(dir);
    let r = run(dir, &case.args);
    let after = snapshot(dir);
    if r.code == Some(101) || r.output.contains("panicked") {
        return Err(format!("panic: {}", tail(&r.output)));
    }
    let silent = !case.announces || r.output.trim().is_empty();
    if r.timed_out && silent {
        return Err(format!(
            "hang: nothing said in {} s of CPU time: {}",
            CASE_LIMIT.as_secs(),
            tail(&r.output)
        ));
    }
    for (p, bytes) in &before {
        match after.get(p) {
            None => return Err(format!("lost file: {} is gone", p.display())),
            Some(b) if b != bytes => {
                return Err(format!("lost file: {} was changed", p.display()));
            }
            _ => {}
        }
    }
    if let (Some(check), false) = (&case.check, r.timed_out) {
        check(r.code, &r.output)?;
    }
    Ok(match (r.timed_out, r.code) {
        (true, _) => "long",
        (false, Some(0)) => "accepted",
        _ => "refused",
    })
}

fn tail(s: &str) -> String {
    let s = s.trim();
    let start = s.char_indices().rev().nth(600).map_or(0, |(i, _)| i);
    s[start..].to_string()
}

/// The spec made cheap to run: counts at most 3, lists at most 2 values, samples at most 16,
/// no transient lifetimes; the output `out.h5` in the case's folder.
fn shrink(v: &mut Value) {
    match v {
        Value::Table(t) => {
            for (k, x) in t.iter_mut() {
                match (k.as_str(), &mut *x) {
                    ("count", Value::Integer(n)) => *n = (*n).min(3),
                    ("n", Value::Integer(n)) => *n = (*n).min(16),
                    ("lifetime_starts", Value::Integer(n)) => *n = 0,
                    _ => shrink(x),
                }
            }
        }
        Value::Array(a) => {
            a.truncate(2);
            a.iter_mut().for_each(shrink);
        }
        _ => {}
    }
}

/// A shipped spec, shrunk, with one to three mutations.
fn spec_case(rng: &mut Rng, specs: &[Shipped]) -> Case {
    let sh = rng.pick(specs);
    let mut v = sh.spec.clone();
    let mut did = Vec::new();
    for _ in 0..1 + rng.below(3) {
        let path = rng.pick(&sh.paths).clone();
        let name = path
            .iter()
            .map(|s| match s {
                Step::Key(k) => k.clone(),
                Step::Index(i) => i.to_string(),
            })
            .collect::<Vec<_>>()
            .join(".");
        let new = match rng.below(10) {
            0 => Value::String("x".into()),
            1 => Value::Boolean(true),
            2 => Value::Array(vec![]),
            3 => Value::Integer(rng.next() as i64),
            4 => Value::Float(f64::from_bits(rng.next())),
            _ => {
                let h = rng.pick(&HOSTILE);
                match h.parse::<i64>() {
                    Ok(i) if rng.below(2) == 0 => Value::Integer(i),
                    _ => Value::Float(h.parse().unwrap()),
                }
            }
        };
        did.push(format!("{name} = {new}"));
        *at(&mut v, &path) = new;
    }
    shrink(&mut v);
    // Now and then a key dropped or an unknown one added.
    if let Some(t) = v.as_table_mut() {
        match rng.below(8) {
            0 => {
                let keys: Vec<String> = t.keys().cloned().collect();
                let k = rng.pick(&keys).clone();
                if k != "output" {
                    t.remove(&k);
                    did.push(format!("no [{k}]"));
                }
            }
            1 => {
                t.insert("bogus".into(), Value::Integer(1));
                did.push("bogus = 1".into());
            }
            _ => {}
        }
        if let Some(o) = t.get_mut("output").and_then(Value::as_table_mut) {
            o.insert("path".into(), Value::String("out.h5".into()));
        }
    }
    let text = toml::to_string(&v).unwrap_or_default();
    let mut files = vec![("case.toml".to_string(), text.into_bytes())];
    // A third of the cases find something at the output already (never to be lost).
    if rng.below(3) == 0 {
        files.push(("out.h5".into(), b"not an HDF5 file".to_vec()));
    }
    let cmd = if sh.atlas { "atlas" } else { "scan" };
    Case {
        what: format!("{cmd} {} with {}", sh.name, did.join(", ")),
        args: vec![cmd.into(), "case.toml".into()],
        files,
        announces: true,
        fifos: Vec::new(),
        check: None,
    }
}

/// The flags of `squeal CMD` that take a value, from its `--help`.
fn value_flags(cmd: &str) -> Vec<String> {
    let out = Command::new(BIN).args([cmd, "--help"]).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    text.lines()
        .filter_map(|l| {
            let l = l.trim_start();
            let l = l
                .strip_prefix("-")
                .and_then(|l| l.split_once(", ").map(|x| x.1))
                .unwrap_or(l);
            let rest = l.strip_prefix("--")?;
            let (name, after) = rest.split_once(' ')?;
            after.starts_with('<').then(|| format!("--{name}"))
        })
        .collect()
}

/// Commands run with hostile flags, and the arguments each needs to run at all (files in
/// the case's folder).
const FLAG_COMMANDS: [(&str, &[&str]); 5] = [
    ("trajectory", &[]),
    ("friction", &["--out-dir", "fr"]),
    ("ulc", &[]),
    // A coarse bracket: the default locates the cycle 18 times (5 s of CPU).
    ("critical", &["--rtol", "1e-2"]),
    ("classify", &["--ics", "ics.csv", "--out", "labels.csv"]),
];

/// A command with one to three flags set to hostile values.
fn flag_case(rng: &mut Rng, flags: &BTreeMap<&str, Vec<String>>) -> Case {
    let (cmd, base) = *rng.pick(&FLAG_COMMANDS);
    let mut args: Vec<String> = std::iter::once(cmd)
        .chain(base.iter().copied())
        .map(String::from)
        .collect();
    let own = &flags[cmd];
    let taken: Vec<&str> = base
        .iter()
        .copied()
        .filter(|a| a.starts_with("--"))
        .collect();
    for _ in 0..1 + rng.below(3) {
        let f = rng.pick(own);
        if taken.contains(&f.as_str()) {
            continue;
        }
        let work = WORK_WORDS.iter().any(|w| f.contains(w));
        let v = if work {
            *rng.pick(&WORK)
        } else {
            *rng.pick(&HOSTILE)
        };
        args.push(f.clone());
        args.push(v.into());
    }
    let bom = if rng.below(2) == 0 { "\u{feff}" } else { "" };
    let ics = format!("{bom}x0,v0\n0.5,0.0\n-1.0,0.25\n");
    Case {
        what: args.join(" "),
        args,
        files: vec![
            ("ics.csv".into(), ics.into_bytes()),
            ("keep.txt".into(), b"keep".to_vec()),
        ],
        // critical and ulc say where their search is, off a terminal too (a plain line
        // after 2 s, then every 10 s): a run-based critical of 36 s is a long run, not a
        // hang (`critical --rtol 1e-2 --lambda 0.5` printed nothing before).
        announces: matches!(cmd, "critical" | "ulc"),
        fifos: Vec::new(),
        check: None,
    }
}

/// A file command on hostile files: none, empty, text, a truncated or whole scan file.
fn file_case(rng: &mut Rng, good: &[u8]) -> Case {
    let kinds: [(&str, Vec<u8>); 5] = [
        ("empty.h5", Vec::new()),
        ("text.h5", b"x0,v0\n1,2\n".to_vec()),
        ("cut.h5", good[..good.len() / 2].to_vec()),
        ("good.h5", good.to_vec()),
        ("zeros.h5", vec![0u8; 4096]),
    ];
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    let mut pick = |rng: &mut Rng| {
        let (name, bytes) = rng.pick(&kinds);
        if rng.below(8) == 0 {
            return "missing.h5".to_string();
        }
        files.push((name.to_string(), bytes.clone()));
        name.to_string()
    };
    let args: Vec<String> = match rng.below(4) {
        0 => vec!["info".into(), pick(rng)],
        1 => vec!["render".into(), pick(rng), "-o".into(), "pic.png".into()],
        2 => vec!["compare".into(), pick(rng), pick(rng)],
        _ => vec![
            "merge".into(),
            pick(rng),
            pick(rng),
            "-o".into(),
            "all.h5".into(),
        ],
    };
    Case {
        what: args.join(" "),
        args,
        files,
        announces: false,
        fifos: Vec::new(),
        check: None,
    }
}

/// A small good scan file for the file commands.
fn good_file(dir: &Path) -> Vec<u8> {
    let spec = r#"version = 1
[model]
law = "mcmillan"
nu = 1e-3
[grid]
x0 = { min = -3.0, max = 5.0, count = 4 }
v0 = { min = -4.0, max = 4.0, count = 3 }
[output]
path = "good.h5"
"#;
    std::fs::write(dir.join("good.toml"), spec).unwrap();
    let r = run(dir, &["scan".into(), "good.toml".into(), "--quiet".into()]);
    assert_eq!(r.code, Some(0), "{}", r.output);
    std::fs::read(dir.join("good.h5")).unwrap()
}

#[test]
#[ignore = "a fuzz run of about 100 s: scripts/ci/fuzz.sh (in .ci/run) runs it by exact name"]
fn fuzz_specs_flags_and_files() {
    let env = |k: &str, d: u64| {
        std::env::var(k)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(d)
    };
    let (seed, budget) = (env("SQUEAL_FUZZ_SEED", 32), env("SQUEAL_FUZZ_SECONDS", 100));
    let scans = Path::new(env!("CARGO_MANIFEST_DIR")).join("scans");
    let specs = shipped(&scans);
    let root = tempfile::tempdir().unwrap();
    let good = good_file(root.path());
    let flags: BTreeMap<&str, Vec<String>> = FLAG_COMMANDS
        .iter()
        .map(|(c, _)| (*c, value_flags(c)))
        .collect();
    for (c, f) in &flags {
        assert!(!f.is_empty(), "no flags found in `squeal {c} --help`");
    }
    let t0 = Instant::now();
    let next = AtomicUsize::new(0);
    let tally: Mutex<BTreeMap<&'static str, usize>> = Mutex::new(BTreeMap::new());
    let failures: Mutex<Vec<String>> = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                // A case is started only with a case's time left in the budget.
                while t0.elapsed() + CASE_LIMIT <= Duration::from_secs(budget) {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let mut rng = Rng::new(seed, k as u64);
                    let case = match rng.below(13) {
                        0..=3 => spec_case(&mut rng, &specs),
                        4..=7 => flag_case(&mut rng, &flags),
                        8 | 9 => file_case(&mut rng, &good),
                        10 => fifos::fifo_case(&mut rng, &good),
                        _ => super::fuzz_units::case(&mut rng),
                    };
                    let dir = root.path().join(format!("case-{k}"));
                    std::fs::create_dir_all(&dir).unwrap();
                    match judge(&case, &dir) {
                        Ok(kind) => *tally.lock().unwrap().entry(kind).or_default() += 1,
                        Err(why) => failures.lock().unwrap().push(format!(
                            "case {k} (seed {seed}): squeal {}\n  {}\n  {why}",
                            case.args.join(" "),
                            case.what
                        )),
                    }
                    let _ = std::fs::remove_dir_all(&dir);
                }
            });
        }
    });
    let failures = failures.into_inner().unwrap();
    eprintln!(
        "fuzz: seed {seed}, {} cases in {:.0} s: {:?}, {} failed",
        next.load(Ordering::Relaxed),
        t0.elapsed().as_secs_f64(),
        tally.into_inner().unwrap(),
        failures.len()
    );
    for f in &failures {
        eprintln!("{f}");
    }
    assert!(failures.is_empty(), "{} fuzz cases failed", failures.len());
}
