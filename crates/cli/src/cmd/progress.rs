//! Progress of long runs: the terminal bar, plain lines off a terminal, and the time left
//! weighed by the pilot's cost per cell.

use std::io::IsTerminal;

/// Whether progress bars should be drawn.
pub fn show_progress(quiet: bool) -> bool {
    !quiet && std::io::stderr().is_terminal()
}

/// The average rate so far, `done` units over `secs` seconds ("-" before the first second:
/// a rate from a few units in a few milliseconds is noise).
pub fn rate_words(done: u64, secs: f64, unit: &str) -> String {
    if secs < 1.0 || done == 0 {
        return "-".into();
    }
    let r = done as f64 / secs;
    if r >= 10.0 {
        format!("{r:.0} {unit}/s")
    } else {
        format!("{:.1} s/{unit}", 1.0 / r)
    }
}

/// The time left at the average rate so far ("estimating" before the first second and the
/// first unit: indicatif's own estimate starts from a few samples and can say hours for a
/// job of a second).
pub fn eta_words(done: u64, total: u64, secs: f64) -> String {
    if secs < 1.0 || done == 0 {
        return "estimating".into();
    }
    let left = total.saturating_sub(done) as f64 * secs / done as f64;
    short_duration(left)
}

/// "45 s", "12 min", "3.2 h".
pub fn short_duration(s: f64) -> String {
    if s < 90.0 {
        format!("{s:.0} s")
    } else if s < 5400.0 {
        format!("{:.0} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

/// A bar over `total` units drawn with `template` ([`bar_style`]; `unit` names what is
/// counted), hidden when quiet or when stderr is not a terminal.
pub fn bar(total: u64, quiet: bool, template: &str, unit: &'static str) -> indicatif::ProgressBar {
    use indicatif::{ProgressBar, ProgressDrawTarget};
    let target = match show_progress(quiet) {
        true => ProgressDrawTarget::stderr(),
        false => ProgressDrawTarget::hidden(),
    };
    ProgressBar::with_draw_target(Some(total), target).with_style(bar_style(template, unit))
}

/// A bar style whose `{avg_rate}` and `{avg_eta}` are [`rate_words`] and [`eta_words`]
/// (`unit` names what is counted).
pub fn bar_style(template: &str, unit: &'static str) -> indicatif::ProgressStyle {
    use indicatif::ProgressState;
    let secs = |s: &ProgressState| s.elapsed().as_secs_f64();
    indicatif::ProgressStyle::with_template(template)
        .expect("static template")
        .with_key(
            "avg_rate",
            move |s: &ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = w.write_str(&rate_words(s.pos(), secs(s), unit));
            },
        )
        .with_key(
            "avg_eta",
            move |s: &ProgressState, w: &mut dyn std::fmt::Write| {
                let total = s.len().unwrap_or(0);
                let _ = w.write_str(&eta_words(s.pos(), total, secs(s)));
            },
        )
        .progress_chars("=> ")
}

/// [`bar_style`] whose `{avg_eta}` is the time left by `meter` (weighed units) instead of
/// the bar's own count.
pub fn metered_bar_style(
    template: &str,
    unit: &'static str,
    meter: std::sync::Arc<WorkMeter>,
) -> indicatif::ProgressStyle {
    use indicatif::ProgressState;
    bar_style(template, unit).with_key(
        "avg_eta",
        move |s: &ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = w.write_str(&meter.eta_words(s.elapsed().as_secs_f64()));
        },
    )
}

/// The work done so far, each unit weighed by its expected cost: the time left is the rest at
/// the rate so far. A sweep's maps above a fold of cycles cost far more per cell than those
/// below it (`nu-sweep`'s last two maps took about 80 s of its 100 s), so counting cells
/// alone promised "5 s left" 80 s before the end; the scan's pilot gives each map's cost per
/// cell.
pub struct WorkMeter {
    /// Expected cost of one unit of each kind (a map's cells), relative; empty: all alike.
    weights: Vec<f64>,
    total: f64,
    units: u64,
    /// Units done, and their expected cost (f64 bits).
    done: std::sync::atomic::AtomicU64,
    work: std::sync::atomic::AtomicU64,
}

impl WorkMeter {
    /// `total` units, all alike.
    pub fn uniform(total: u64) -> Self {
        WorkMeter {
            weights: Vec::new(),
            total: total as f64,
            units: total,
            done: 0.into(),
            work: 0f64.to_bits().into(),
        }
    }

    /// `counts[k]` units of kind `k`, each weighing `weights[k]` (a weight that is not finite
    /// and positive counts as the mean of the others).
    pub fn weighted(weights: Vec<f64>, counts: &[u64]) -> Self {
        let good = |w: &f64| *w > 0.0 && w.is_finite();
        let known: Vec<f64> = weights.iter().copied().filter(good).collect();
        let mean = known.iter().sum::<f64>() / known.len().max(1) as f64;
        let weights: Vec<f64> = weights
            .into_iter()
            .map(|w| {
                if good(&w) {
                    w
                } else {
                    mean.max(f64::MIN_POSITIVE)
                }
            })
            .collect();
        WorkMeter {
            total: counts
                .iter()
                .zip(&weights)
                .map(|(n, w)| *n as f64 * w)
                .sum(),
            units: counts.iter().sum(),
            weights,
            done: 0.into(),
            work: 0f64.to_bits().into(),
        }
    }

    /// Counts one unit of kind `kind`; returns the units done.
    pub fn add(&self, kind: usize) -> u64 {
        self.add_n(kind, 1)
    }

    /// Counts `n` units of kind `kind` at once (a chunk of a block's cells); returns the
    /// units done.
    pub fn add_n(&self, kind: usize, n: u64) -> u64 {
        use std::sync::atomic::Ordering;
        let w = self.weights.get(kind).copied().unwrap_or(1.0) * n as f64;
        let _ = self
            .work
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |b| {
                Some((f64::from_bits(b) + w).to_bits())
            });
        self.done.fetch_add(n, Ordering::Relaxed) + n
    }

    /// Units done.
    pub fn done(&self) -> u64 {
        self.done.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Seconds left after `secs` seconds: the expected work left at the rate so far.
    pub fn left_seconds(&self, secs: f64) -> f64 {
        let work = f64::from_bits(self.work.load(std::sync::atomic::Ordering::Relaxed));
        (self.total - work).max(0.0) * secs / work.max(f64::MIN_POSITIVE)
    }

    /// The time left in words ("estimating" before the first second and the first unit).
    pub fn eta_words(&self, secs: f64) -> String {
        if secs < 1.0 || self.done() == 0 {
            return "estimating".into();
        }
        short_duration(self.left_seconds(secs))
    }
}

/// Progress as plain lines on stderr when it is not a terminal (a batch or SLURM log, where
/// a bar draws nothing): one line every 5 % of the work, with the average rate and the time
/// left ([`WorkMeter`]), and at least one a minute; none in the first second (a rate from a
/// few units in a few milliseconds is noise: the line said "19 s left" of a 0.3 s scan).
pub struct PlainLines {
    what: &'static str,
    unit: &'static str,
    meter: std::sync::Arc<WorkMeter>,
    /// The last 5 % step printed, and the elapsed second of the last line.
    printed: std::sync::Mutex<(u64, f64)>,
    started: std::time::Instant,
}

impl PlainLines {
    /// Lines for `total` units of `what` (e.g. "cells"), counted as `unit`; `None` with
    /// `--quiet`, on a terminal (the bar shows it) or for no work.
    pub fn new(what: &'static str, unit: &'static str, total: u64, quiet: bool) -> Option<Self> {
        Self::with_meter(
            what,
            unit,
            std::sync::Arc::new(WorkMeter::uniform(total)),
            quiet,
        )
    }

    /// Lines that read `meter`, which the caller counts ([`WorkMeter::add`], then
    /// [`PlainLines::report`]).
    pub fn with_meter(
        what: &'static str,
        unit: &'static str,
        meter: std::sync::Arc<WorkMeter>,
        quiet: bool,
    ) -> Option<Self> {
        (!quiet && !std::io::stderr().is_terminal() && meter.units > 0).then(|| PlainLines {
            what,
            unit,
            meter,
            printed: std::sync::Mutex::new((0, 0.0)),
            started: std::time::Instant::now(),
        })
    }

    /// Counts one unit (of kind `kind`) on its meter and reports.
    pub fn inc(&self, kind: usize) {
        self.meter.add(kind);
        self.report();
    }

    /// Prints a line at each 5 % step of the meter's units (or after a minute without one),
    /// from the first second on.
    pub fn report(&self) {
        let done = self.meter.done();
        let total = self.meter.units.max(1);
        let step = done * 20 / total;
        let secs = self.started.elapsed().as_secs_f64();
        let Ok(mut last) = self.printed.lock() else {
            return;
        };
        if secs >= 1.0 && (step > last.0 || secs - last.1 >= 60.0) {
            *last = (step, secs);
            eprintln!(
                "squeal: {:.0}% ({done}/{total} {}) after {}, {}, about {} left",
                100.0 * done as f64 / total as f64,
                self.what,
                short_duration(secs),
                rate_words(done, secs, self.unit),
                short_duration(self.meter.left_seconds(secs)),
            );
        }
    }
}

/// The estimate's words for a busy machine ("" when it is not): the share of a core the
/// pilot's thread got and the time `secs` (on free cores) at that load
/// ([`squeal_scan::estimate::at_load`]). Printed after the estimate it qualifies.
pub fn busy_words(secs: f64, core_share: f64) -> String {
    match squeal_scan::estimate::at_load(secs, core_share) {
        Some(loaded) => format!(
            "; the machine is busy (the pilot got {:.0}% of a core): at this load rather {}",
            100.0 * core_share,
            super::common::duration(loaded)
        ),
        None => String::new(),
    }
}

/// What a one-parameter search has done so far, as its observer
/// ([`squeal_scan::observe`]) counts it: the stage, its values (of how many, where known),
/// the last value and the section returns computed.
#[derive(Debug, Default)]
pub struct SearchTally {
    stage: &'static str,
    total: Option<u64>,
    values: u64,
    last: Option<f64>,
    returns: u64,
}

impl SearchTally {
    /// The line's words, the parameter named `param`: "coarse scan 12/65, nu = 0.02431,
    /// 5123 section returns".
    pub fn words(&self, param: &str) -> String {
        let mut w = self.stage.to_string();
        match (self.values, self.total) {
            (0, _) => {}
            (n, Some(t)) => w.push_str(&format!(" {n}/{t}")),
            (n, None) => w.push_str(&format!(" {n}")),
        }
        if let Some(v) = self.last {
            w.push_str(&format!(", {param} = {}", squeal_plot::fmt_value(v)));
        }
        if self.returns > 0 {
            w.push_str(&format!(", {} section returns", self.returns));
        }
        w
    }

    fn stage(&mut self, what: &'static str, total: Option<u64>) {
        (self.stage, self.total, self.values, self.last) = (what, total, 0, None);
    }

    fn step(&mut self, s: squeal_scan::observe::SearchStep) {
        use squeal_scan::observe::SearchStep;
        match s {
            SearchStep::Value(v) => {
                self.values += 1;
                self.last = Some(v);
            }
            SearchStep::Return(_) => self.returns += 1,
        }
    }
}

/// The progress line of a long one-parameter search on a terminal (`critical`, its
/// `--fold` and `--crisis`, `ulc`): a spinner with [`SearchTally::words`] and the time so
/// far, fed by the library's observer of the search ([`squeal_scan::observe::observed`]).
/// Hidden as the other bars are ([`show_progress`]).
pub struct SearchBar {
    /// The spinner on a terminal; `None` off one, where plain lines are printed instead.
    bar: Option<indicatif::ProgressBar>,
    what: &'static str,
    param: String,
    tally: std::sync::Mutex<SearchTally>,
    /// When the search started, and when the last plain line was printed.
    started: std::time::Instant,
    last_line: std::sync::Mutex<Option<std::time::Instant>>,
}

/// Off a terminal (a batch log), a plain line says where the search is once it has run
/// [`PLAIN_AFTER`], then at most every [`PLAIN_EVERY`]: a run-based `critical` took 36 s
/// without a word, which a log reader (and the fuzz run's hang rule) cannot tell from a hang.
const PLAIN_AFTER: std::time::Duration = std::time::Duration::from_secs(2);
const PLAIN_EVERY: std::time::Duration = std::time::Duration::from_secs(10);

impl SearchBar {
    /// The line of command `what` searching in `param`: a spinner on a terminal, plain
    /// lines off one; `None` under `--quiet`.
    pub fn new(what: &'static str, param: &str, quiet: bool) -> Option<std::sync::Arc<SearchBar>> {
        if quiet {
            return None;
        }
        let bar = show_progress(quiet).then(|| {
            let bar = indicatif::ProgressBar::new_spinner();
            bar.set_style(
                indicatif::ProgressStyle::with_template("{spinner} {prefix}: {msg} [{elapsed}]")
                    .expect("static template"),
            );
            bar.set_prefix(what);
            bar.enable_steady_tick(std::time::Duration::from_millis(250));
            bar
        });
        Some(std::sync::Arc::new(SearchBar {
            bar,
            what,
            param: param.to_string(),
            tally: Default::default(),
            started: std::time::Instant::now(),
            last_line: Default::default(),
        }))
    }

    /// A stage the command itself names (between the library's searches).
    pub fn stage(&self, what: &'static str) {
        self.update(|t| t.stage(what, None));
    }

    fn update(&self, f: impl FnOnce(&mut SearchTally)) {
        let Ok(mut t) = self.tally.lock() else {
            return;
        };
        f(&mut t);
        match &self.bar {
            Some(bar) => bar.set_message(t.words(&self.param)),
            None => {
                let Ok(mut last) = self.last_line.lock() else {
                    return;
                };
                let due = match *last {
                    None => self.started.elapsed() >= PLAIN_AFTER,
                    Some(at) => at.elapsed() >= PLAIN_EVERY,
                };
                if due {
                    *last = Some(std::time::Instant::now());
                    eprintln!(
                        "squeal {}: {} after {}",
                        self.what,
                        t.words(&self.param),
                        short_duration(self.started.elapsed().as_secs_f64())
                    );
                }
            }
        }
    }
}

impl Drop for SearchBar {
    fn drop(&mut self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

impl squeal_scan::Observer for SearchBar {
    fn search_stage(&self, what: &'static str, total: Option<u64>) {
        self.update(|t| t.stage(what, total));
    }
    fn search_step(&self, s: squeal_scan::observe::SearchStep) {
        self.update(|t| t.step(s));
    }
}

/// Runs `f` with `bar` (if shown) as the observer of the searches it runs on this thread;
/// the line is cleared when the last handle to `bar` goes.
pub fn searching<R>(bar: Option<&std::sync::Arc<SearchBar>>, f: impl FnOnce() -> R) -> R {
    match bar {
        Some(b) => squeal_scan::observe::observed(b.clone(), f),
        None => f(),
    }
}

#[cfg(test)]
mod tests {
    use super::WorkMeter;

    /// The search line counts what the library's loops report through the observer: a
    /// coarse scan's values of their total, the last value, the section returns.
    #[test]
    fn the_search_line_follows_the_librarys_search() {
        use squeal_scan::observe::SearchStep;
        let mut t = super::SearchTally::default();
        t.stage("coarse scan", Some(65));
        for nu in [0.01, 0.02] {
            t.step(SearchStep::Return(1.0));
            t.step(SearchStep::Value(nu));
        }
        assert_eq!(
            t.words("nu"),
            "coarse scan 2/65, nu = 0.02, 2 section returns"
        );
        t.stage("bisection", None);
        assert_eq!(t.words("nu"), "bisection, 2 section returns");
    }

    /// An estimate of 66 s on a machine where the pilot got a fifth of a core says
    /// the machine is busy and gives the time at that load; on a free machine it says nothing.
    #[test]
    fn the_estimate_says_when_the_machine_is_busy() {
        let w = super::busy_words(66.0, 0.2);
        assert_eq!(
            w,
            "; the machine is busy (the pilot got 20% of a core): at this load rather 6 min"
        );
        assert_eq!(super::busy_words(66.0, 0.95), "");
    }

    #[test]
    fn time_left_weighs_each_maps_cells_by_their_cost() {
        // Two maps of 100 cells, the second 20 times dearer per cell (above a fold): after
        // the first map in 10 s, 20 times that is left, not as much again.
        let m = WorkMeter::weighted(vec![1.0, 20.0], &[100, 100]);
        for _ in 0..100 {
            m.add(0);
        }
        assert_eq!(m.done(), 100);
        assert!((m.left_seconds(10.0) - 200.0).abs() < 1e-9);
        // Unweighted, the same progress promises 10 s.
        let u = WorkMeter::uniform(200);
        for _ in 0..100 {
            u.add(0);
        }
        assert!((u.left_seconds(10.0) - 10.0).abs() < 1e-9);
        // A weight the pilot could not measure counts as the mean of the others.
        let m = WorkMeter::weighted(vec![2.0, f64::NAN, 4.0], &[100, 100, 100]);
        assert!((m.total - 900.0).abs() < 1e-9);
        // No estimate before the first second.
        assert_eq!(m.eta_words(0.5), "estimating");
    }
}
