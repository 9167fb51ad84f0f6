//! The one executor: every kind of work (a scan's map preparations and blocks, an atlas's
//! lines of points and boundary searches) runs through [`execute`] or, where a job adds
//! jobs (a prepared map its blocks), [`execute_growing`].
//!
//! Jobs run with as many threads as the caller's rayon context has: the global pool (the
//! CLI sizes it with `--threads`), or, for a call inside `ThreadPool::install`, a pool of
//! the same size built for the call (the calling worker waits on the sink meanwhile). Each
//! job emits its finished results over a bounded channel ([`in_flight`] results) to the
//! thread that called [`execute`], the only one that calls the sink. So the journal's
//! writes and fsyncs stay off the workers' path, whichever engine runs (before, the atlas
//! called its sink from the workers behind a lock). Raising `stop` hands out no further
//! job; the jobs in flight finish and their results still reach the sink. The first error
//! from a job or from the sink raises `stop` too, and is returned once the jobs in flight
//! are done (their results are not handed to a sink that has failed).

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, mpsc};

/// What a job sends to the sink's thread: a result, or the error that ends the run.
pub enum Emit<M, E> {
    /// A finished result.
    Done(M),
    /// A failure: the run stops and returns it.
    Failed(E),
}

/// Runs `work` on every job in parallel, started in the order given (a shared queue: put the
/// longest first); `work` hands its results to `emit`, and `sink`
/// receives them, one at a time, on the calling thread. Returns the first failure (from a
/// job, `JE`, or from the sink, `E`) after the jobs in flight are done.
pub fn execute<J, M, JE, E>(
    jobs: Vec<J>,
    stop: &AtomicBool,
    work: impl Fn(J, &dyn Fn(Emit<M, JE>)) + Sync,
    sink: impl FnMut(M) -> Result<(), E>,
) -> Result<(), E>
where
    J: Send,
    M: Send,
    JE: Send,
    E: From<JE>,
{
    execute_growing(jobs, stop, |j, emit, _more| work(j, emit), sink)
}

/// [`execute`] where a job may add jobs to the queue (its third argument, `more`): they
/// join the end of the queue, and threads that found the queue empty and left are called
/// back for them. No thread ever waits for a job inside the pool (a worker blocked on
/// another job's result can deadlock rayon, whose waiting threads run stolen work), so work
/// that depends on a job (a map's blocks on its preparation) is added by that job when it
/// is done, and never waits for it.
pub fn execute_growing<J, M, JE, E>(
    jobs: Vec<J>,
    stop: &AtomicBool,
    work: impl Fn(J, &dyn Fn(Emit<M, JE>), &dyn Fn(Vec<J>)) + Sync,
    mut sink: impl FnMut(M) -> Result<(), E>,
) -> Result<(), E>
where
    J: Send,
    M: Send,
    JE: Send,
    E: From<JE>,
{
    // Bounded: a worker whose result finds the channel full waits for the sink, so a sink
    // slower than the workers (a slow disk) holds at most `in_flight` results in memory,
    // not every finished block of the run.
    let (tx, rx) = mpsc::sync_channel::<Emit<M, JE>>(in_flight());
    let mut failure = None;
    // The jobs are handed out from a helper thread, which is no worker of an installed pool:
    // inside one, they get a pool of its size (without, the global pool's size applied).
    let pool = rayon::current_thread_index().and_then(|_| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(rayon::current_num_threads())
            .build()
            .ok()
    });
    std::thread::scope(|scope| {
        let work = &work;
        let workers = scope.spawn(move || {
            let run = move || take_in_order(jobs, stop, work, tx);
            match pool {
                Some(pool) => pool.install(run),
                None => run(),
            }
        });
        for msg in rx {
            if failure.is_some() {
                continue;
            }
            let res = match msg {
                Emit::Done(m) => sink(m),
                Emit::Failed(e) => Err(E::from(e)),
            };
            if let Err(e) = res {
                stop.store(true, Ordering::SeqCst);
                failure = Some(e);
            }
        }
        if let Err(panic) = workers.join() {
            std::panic::resume_unwind(panic);
        }
    });
    failure.map_or(Ok(()), Err)
}

/// How many finished results may wait for the sink: four per thread of the current pool.
pub fn in_flight() -> usize {
    4 * rayon::current_num_threads().max(1)
}

/// The jobs not yet taken, and how many loops ([`job_loop`]) are taking them.
struct Queue<J> {
    jobs: VecDeque<J>,
    live: usize,
}

/// What every loop of one [`take_in_order`] shares.
struct Shared<'a, J, M, JE, W> {
    queue: Mutex<Queue<J>>,
    threads: usize,
    stop: &'a AtomicBool,
    work: &'a W,
    tx: mpsc::SyncSender<Emit<M, JE>>,
}

impl<J, M, JE, W> Shared<'_, J, M, JE, W> {
    fn lock(&self) -> std::sync::MutexGuard<'_, Queue<J>> {
        self.queue.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// Runs `work` on every job of `jobs` (and every job a job adds) on the current rayon pool,
/// handing its results to `tx`: one shared queue, taken in the jobs' order by as many loops
/// as the pool has threads, so the first jobs (the atlas puts its longest units first) start
/// first and each thread takes the next job when it is free. Before, rayon split the list
/// into contiguous halves, so the atlas's long boundary searches bunched on a few threads
/// while the others ran out of lines. Raising `stop` hands out no further job.
fn take_in_order<J, M, JE, W>(
    jobs: Vec<J>,
    stop: &AtomicBool,
    work: &W,
    tx: mpsc::SyncSender<Emit<M, JE>>,
) where
    J: Send,
    M: Send,
    JE: Send,
    W: Fn(J, &dyn Fn(Emit<M, JE>), &dyn Fn(Vec<J>)) + Sync,
{
    let threads = rayon::current_num_threads();
    let live = threads.min(jobs.len());
    let shared = Shared {
        queue: Mutex::new(Queue {
            jobs: jobs.into(),
            live,
        }),
        threads,
        stop,
        work,
        tx,
    };
    let shared = &shared;
    rayon::scope(|s| {
        for _ in 0..live {
            s.spawn(move |s| job_loop(s, shared));
        }
    });
}

/// Takes the next job from the queue until it is empty or `stop` is raised; the jobs a job
/// adds go to the end of the queue, with a loop started for each thread that has none.
fn job_loop<'s, J, M, JE, W>(s: &rayon::Scope<'s>, shared: &'s Shared<'s, J, M, JE, W>)
where
    J: Send,
    M: Send,
    JE: Send,
    W: Fn(J, &dyn Fn(Emit<M, JE>), &dyn Fn(Vec<J>)) + Sync,
{
    loop {
        let job = {
            let mut q = shared.lock();
            let next = if shared.stop.load(Ordering::SeqCst) {
                None
            } else {
                q.jobs.pop_front()
            };
            match next {
                Some(j) => j,
                None => {
                    // Leaving is decided under the lock, so a job added meanwhile sees
                    // this loop gone and starts another.
                    q.live -= 1;
                    return;
                }
            }
        };
        let emit = |m| {
            let _ = shared.tx.send(m);
        };
        let more = |jobs: Vec<J>| {
            let start = {
                let mut q = shared.lock();
                let n = jobs.len();
                q.jobs.extend(jobs);
                let start = n.min(shared.threads.saturating_sub(q.live));
                q.live += start;
                start
            };
            for _ in 0..start {
                s.spawn(move |s| job_loop(s, shared));
            }
        };
        (shared.work)(job, &emit, &more);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_result_reaches_the_sink_on_the_calling_thread() {
        let caller = std::thread::current().id();
        let mut got = Vec::new();
        let stop = AtomicBool::new(false);
        execute(
            (0..100u32).collect(),
            &stop,
            |j, emit: &dyn Fn(Emit<u32, ()>)| emit(Emit::Done(j * j)),
            |m| {
                assert_eq!(std::thread::current().id(), caller);
                got.push(m);
                Ok::<(), ()>(())
            },
        )
        .unwrap();
        got.sort_unstable();
        assert_eq!(got, (0..100u32).map(|j| j * j).collect::<Vec<_>>());
    }

    /// Called inside a pool of 1 and of 3 threads, the jobs see as many (the driver's
    /// thread-independence test relies on it). Before, they ran on the global pool whatever
    /// pool was installed around the call, so both saw the machine's count.
    #[test]
    fn jobs_run_with_the_threads_of_the_installed_pool() {
        for threads in [1usize, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let seen = std::sync::Mutex::new(std::collections::BTreeSet::new());
            let mut counts = Vec::new();
            pool.install(|| {
                execute(
                    (0..64u32).collect(),
                    &AtomicBool::new(false),
                    |_, emit: &dyn Fn(Emit<usize, ()>)| {
                        seen.lock()
                            .unwrap()
                            .insert(rayon::current_thread_index().unwrap());
                        emit(Emit::Done(rayon::current_num_threads()))
                    },
                    |n| {
                        counts.push(n);
                        Ok::<(), ()>(())
                    },
                )
                .unwrap()
            });
            assert_eq!(counts.len(), 64);
            assert!(counts.iter().all(|&n| n == threads), "{counts:?}");
            assert!(seen.into_inner().unwrap().len() <= threads);
        }
    }

    #[test]
    fn a_failure_stops_the_run_and_is_returned() {
        let stop = AtomicBool::new(false);
        let mut sunk = 0;
        let r = execute(
            (0..50u32).collect(),
            &stop,
            |j, emit: &dyn Fn(Emit<u32, String>)| {
                if j == 3 {
                    emit(Emit::Failed(format!("job {j}")));
                } else {
                    emit(Emit::Done(j));
                }
            },
            |_| {
                sunk += 1;
                Ok::<(), String>(())
            },
        );
        assert_eq!(r, Err("job 3".to_string()));
        assert!(stop.load(Ordering::SeqCst));
        assert!(sunk < 50, "{sunk}");
    }

    #[test]
    fn a_failing_sink_stops_the_run() {
        let stop = AtomicBool::new(false);
        let r = execute(
            (0..50u32).collect(),
            &stop,
            |j, emit: &dyn Fn(Emit<u32, u32>)| emit(Emit::Done(j)),
            Err::<(), u32>,
        );
        assert!(r.is_err());
        assert!(stop.load(Ordering::SeqCst));
    }

    #[test]
    fn a_raised_stop_hands_out_no_job() {
        let stop = AtomicBool::new(true);
        let mut sunk = 0;
        execute(
            (0..10u32).collect(),
            &stop,
            |j, emit: &dyn Fn(Emit<u32, ()>)| emit(Emit::Done(j)),
            |_| {
                sunk += 1;
                Ok::<(), ()>(())
            },
        )
        .unwrap();
        assert_eq!(sunk, 0);
    }
    /// Jobs a job adds all run, their results reach the sink, and they run while the job
    /// that added them is still running: job 0 adds job 1 and does not finish until job 1
    /// has run (it gives up after 20 s), on a pool of 2 threads whose other loop had left the
    /// empty queue. Before `execute_growing` a job could add none: a map's blocks waited
    /// for every map's preparation.
    #[test]
    fn a_job_adds_jobs_that_run_beside_it() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let ran = AtomicBool::new(false);
        let mut got = Vec::new();
        pool.install(|| {
            execute_growing(
                vec![0u32],
                &AtomicBool::new(false),
                |j, emit: &dyn Fn(Emit<(u32, bool), ()>), more: &dyn Fn(Vec<u32>)| {
                    if j == 0 {
                        more(vec![1]);
                        let until = std::time::Instant::now() + std::time::Duration::from_secs(20);
                        while !ran.load(Ordering::SeqCst) && std::time::Instant::now() < until {
                            std::thread::sleep(std::time::Duration::from_millis(1));
                        }
                        emit(Emit::Done((0, ran.load(Ordering::SeqCst))));
                        more((2..40).collect());
                    } else {
                        ran.store(true, Ordering::SeqCst);
                        emit(Emit::Done((j, true)));
                    }
                },
                |m| {
                    got.push(m);
                    Ok::<(), ()>(())
                },
            )
            .unwrap()
        });
        got.sort_unstable();
        assert_eq!(got, (0..40).map(|j| (j, true)).collect::<Vec<_>>());
    }

    /// A raised stop hands out none of the jobs a job adds.
    #[test]
    fn a_raised_stop_hands_out_no_added_job() {
        let stop = AtomicBool::new(false);
        let mut sunk = Vec::new();
        execute_growing(
            vec![0u32],
            &stop,
            |j, emit: &dyn Fn(Emit<u32, ()>), more: &dyn Fn(Vec<u32>)| {
                stop.store(true, Ordering::SeqCst);
                more(vec![j + 1]);
                emit(Emit::Done(j));
            },
            |m| {
                sunk.push(m);
                Ok::<(), ()>(())
            },
        )
        .unwrap();
        assert_eq!(sunk, vec![0]);
    }
    /// The channel to the sink is bounded: with a sink that takes 2 ms per
    /// result and jobs that take none, the results sent and not yet sunk never exceed the
    /// bound and the one the sink holds. With the unbounded channel of before, all 300
    /// were sent while the sink was on its first few.
    #[test]
    fn a_slow_sink_holds_back_the_workers() {
        use std::sync::atomic::AtomicUsize;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let (sent, sunk, most) = (
            AtomicUsize::new(0),
            AtomicUsize::new(0),
            AtomicUsize::new(0),
        );
        let bound = pool.install(in_flight);
        pool.install(|| {
            execute(
                (0..300u32).collect(),
                &AtomicBool::new(false),
                |j, emit: &dyn Fn(Emit<u32, ()>)| {
                    emit(Emit::Done(j));
                    let ahead =
                        sent.fetch_add(1, Ordering::SeqCst) + 1 - sunk.load(Ordering::SeqCst);
                    most.fetch_max(ahead, Ordering::SeqCst);
                },
                |_| {
                    std::thread::sleep(std::time::Duration::from_millis(2));
                    sunk.fetch_add(1, Ordering::SeqCst);
                    Ok::<(), ()>(())
                },
            )
            .unwrap()
        });
        assert_eq!(sunk.into_inner(), 300);
        let most = most.into_inner();
        assert!(
            most <= bound + 1 + 2,
            "{most} results ahead of the sink, bound {bound}"
        );
    }
}
