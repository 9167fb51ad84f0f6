//! Phase timings on stderr for `scripts/bench/bench-scaling.sh`: with `SQUEAL_TIMINGS=1` in
//! the environment, each phase of a scan or an atlas prints one line
//! `squeal timing: PHASE SECONDS` when it ends, measured where it happens (nothing is
//! printed, and nothing but a clock read is spent, without it).

use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// Whether `SQUEAL_TIMINGS` asks for the phase timings (read once).
pub fn on() -> bool {
    static ON: OnceLock<bool> = OnceLock::new();
    *ON.get_or_init(|| {
        std::env::var_os("SQUEAL_TIMINGS").is_some_and(|v| v != "0" && !v.is_empty())
    })
}

/// Prints the time of phase `name`, `d`.
pub fn report(name: &str, d: Duration) {
    if on() {
        eprintln!("squeal timing: {name} {:.3}", d.as_secs_f64());
    }
}

/// A clock for consecutive phases: each [`Phases::end`] reports the time since the last.
pub struct Phases(Instant);

impl Phases {
    /// Starts the first phase now.
    pub fn start() -> Phases {
        Phases(Instant::now())
    }

    /// Ends phase `name` (reported) and starts the next.
    pub fn end(&mut self, name: &str) {
        let now = Instant::now();
        report(name, now - self.0);
        self.0 = now;
    }
}
