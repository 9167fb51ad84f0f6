//! Progress of the one-parameter searches that run on one thread for minutes (`squeal
//! critical`, its `--fold` and `--crisis`, `squeal ulc`): the [`Observer`] of the search
//! running on the calling thread, set for the span of one call by [`observed`] (as
//! `tracing` scopes its dispatcher), so that the loops where the work is counted (a coarse
//! scan's values and a bisection's in [`crate::section`], a return of the section map in
//! [`crate::section::ReturnMap::d`]) report it without an observer threaded through every
//! search's signature. Threads without one (the atlas's and a scan's workers, whose
//! progress is their units) report nothing.

use std::cell::RefCell;
use std::sync::Arc;

use crate::scanner::Observer;

/// One piece of a search's work, as [`Observer::search_step`] sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SearchStep {
    /// The search's verdict at one value of its parameter (a coarse scan's value, a
    /// bisection's midpoint).
    Value(f64),
    /// One return of the section map computed, from section amplitude `r` (the unit of a
    /// cycle's search; many of them make one value's verdict).
    Return(f64),
}

thread_local! {
    static CURRENT: RefCell<Option<Arc<dyn Observer>>> = const { RefCell::new(None) };
}

/// Runs `f` with `obs` as the observer of the searches on this thread (the one before is
/// restored after, also when `f` panics).
pub fn observed<R>(obs: Arc<dyn Observer>, f: impl FnOnce() -> R) -> R {
    struct Restore(Option<Arc<dyn Observer>>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let before = self.0.take();
            CURRENT.with(|c| *c.borrow_mut() = before);
        }
    }
    let _restore = Restore(CURRENT.with(|c| c.replace(Some(obs))));
    f()
}

/// This thread's observer, if it has one: for the pieces of a search this thread hands to
/// other threads ([`observed_by`]).
pub(crate) fn current() -> Option<Arc<dyn Observer>> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Runs `f` with `obs` (if any) as this thread's observer: a piece of a search run on
/// another thread reports to the observer of the thread that started the search.
pub(crate) fn observed_by<R>(obs: Option<&Arc<dyn Observer>>, f: impl FnOnce() -> R) -> R {
    match obs {
        Some(o) => observed(o.clone(), f),
        None => f(),
    }
}

/// Calls `f` with this thread's observer, if it has one (cloned out of the cell first, so an
/// observer may start a search of its own).
fn with(f: impl FnOnce(&dyn Observer)) {
    if let Some(o) = CURRENT.with(|c| c.borrow().clone()) {
        f(&*o);
    }
}

/// A stage of the search begins: `what` ("coarse scan", "bisection", ...), of `total`
/// parameter values where that is known beforehand (an upper bound for a bisection).
pub(crate) fn stage(what: &'static str, total: Option<u64>) {
    with(|o| o.search_stage(what, total));
}

/// One piece of the search's work is done.
pub(crate) fn step(s: SearchStep) {
    with(|o| o.search_step(s));
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    #[derive(Default)]
    struct Log(Mutex<Vec<String>>);
    impl Observer for Log {
        fn search_stage(&self, what: &'static str, total: Option<u64>) {
            self.0.lock().unwrap().push(format!("{what} {total:?}"));
        }
        fn search_step(&self, s: SearchStep) {
            if let SearchStep::Value(v) = s {
                self.0.lock().unwrap().push(format!("{v}"));
            }
        }
    }

    fn log_after(l: &Log) -> Vec<String> {
        l.0.lock().unwrap().clone()
    }

    /// A coarse scan and a bisection report their stage and each value to the observer of
    /// the thread that runs them, and to nobody once the call is over.
    #[test]
    fn a_search_reports_its_stages_and_values() {
        let log = Arc::new(Log::default());
        let changes = observed(log.clone(), || {
            let c = crate::section::coarse_changes(|v| Ok::<_, ()>(v > 2.5), (1.0, 4.0), 3);
            // ln(4) / ln(1.01) = 139.3: 8 halvings of the log-width at most.
            let b = crate::section::geometric_bisection(
                |v| Ok::<_, ()>(v > 2.0),
                (1.0, 4.0),
                0.01,
                200,
            );
            (c, b)
        });
        assert_eq!(changes.0.unwrap().len(), 1);
        let log_handle = log;
        let log = std::mem::take(&mut *log_handle.0.lock().unwrap());
        assert_eq!(log[0], "coarse scan Some(4)");
        // The coarse values 1, 4^(1/3), 4^(2/3), 4, each reported once (the bisection's
        // stage follows the fourth).
        assert_eq!(log[1], "1");
        assert_eq!(log[4], "4");
        assert_eq!(log[5], "bisection Some(8)");
        let (_, evaluations) = changes.1.unwrap();
        // Every midpoint reported (the two ends count as evaluated, not run).
        assert_eq!(log.len() - 6, evaluations as usize - 2);
        // Outside `observed`, nothing is reported: the observer is gone with the call.
        crate::section::coarse_changes(|v| Ok::<_, ()>(v > 2.5), (1.0, 4.0), 3).unwrap();
        assert!(log_after(&log_handle).is_empty());
    }
}
