//! SIGINT, SIGTERM (SLURM's time limit and preemption) and SIGHUP during `scan` and `atlas`.
//! What a signal does depends on the run's [`Phase`]: while the work is estimated (a
//! pilot, before anything is written) it ends the run at once saying so (a signal there
//! ended the atlas with code 143 and no word); while blocks are computed it stops
//! the run after those in flight; while the data file is written it lets it be written and
//! skips the pictures, whatever signals follow (GNU `timeout` sends its SIGTERM to the run
//! and to its group, two in all: the second quit with the file half written, leaving its
//! temporary file, the lock and the journal); once the data file is complete and only
//! pictures are left
//! it ends the run at once. A picture is one call into the plotting library and cannot
//! stop halfway, and before this a signal there was taken as "stop after the blocks in
//! flight" (there were none), so the drawing went on to the end whatever the signal.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use anyhow::Context;

use super::common::{EXIT_INTERRUPTED, is_drawn};

/// What the run is doing when a signal comes.
#[derive(Clone, Debug, PartialEq)]
enum Phase {
    /// Estimating the work (a pilot) before the output is created: the first signal ends
    /// the run at once; nothing was written.
    Estimating,
    /// Computing: the first signal stops the run after the `what` in flight.
    Computing { what: &'static str },
    /// Every block is stored and the data file `out` is being written: every signal lets it
    /// be written (the first says no picture will be drawn, a later one that the write goes
    /// on).
    Finishing { out: PathBuf },
    /// The data file is complete; the pictures are being drawn.
    Drawing(Drawing),
    /// The data file and its pictures are complete; the summary is being printed. The first
    /// signal lets it finish (the run's exit code stays 0: nothing is left to do).
    Done,
}

/// The drawing phase: what to say, and the pictures a signal may leave cut.
#[derive(Clone, Debug, PartialEq)]
struct Drawing {
    note: String,
    pictures: Vec<PathBuf>,
}

/// What the handler does with one signal.
#[derive(Debug, PartialEq)]
enum Response {
    /// Say how the run stops (after the work in flight), and let it.
    StopAfter(String),
    /// A second signal while computing: exit at once.
    Quit,
    /// A signal while estimating: say that nothing was written, exit at once.
    QuitEstimating,
    /// A signal while drawing: remove the cut pictures, say that the data file is
    /// complete, exit at once.
    QuitDrawing(Drawing),
}

/// The stop flag of a run and its phase, shared with the signal handler.
#[derive(Clone, Debug)]
pub struct Signals {
    stop: Arc<AtomicBool>,
    phase: Arc<Mutex<Phase>>,
}

impl Signals {
    /// A run computing `what` (blocks, units), no handler installed.
    #[cfg(test)]
    fn new(what: &'static str) -> Signals {
        let s = Signals::estimating();
        s.computing(what);
        s
    }

    /// A run estimating its work, no handler installed.
    fn estimating() -> Signals {
        Signals {
            stop: Arc::new(AtomicBool::new(false)),
            phase: Arc::new(Mutex::new(Phase::Estimating)),
        }
    }

    /// Installs the handler before the run estimates its work (a signal then ends it at
    /// once, saying nothing was written); [`Signals::computing`] enters the next phase.
    pub fn install() -> anyhow::Result<Signals> {
        let s = Signals::estimating();
        let handler = s.clone();
        // The "termination" feature of ctrlc routes SIGTERM and SIGHUP here as well as SIGINT.
        ctrlc::set_handler(move || handler.on_signal())
            .context("installing the SIGINT/SIGTERM handler")?;
        Ok(s)
    }

    /// Enters the computing phase of a run computing `what` (blocks, units): a first
    /// signal stops it after the work in flight, a second exits at once (code 130).
    pub fn computing(&self, what: &'static str) {
        *self.phase.lock().unwrap_or_else(|e| e.into_inner()) = Phase::Computing { what };
    }

    /// The flag the computing loops poll.
    pub fn stop(&self) -> &AtomicBool {
        &self.stop
    }

    /// Enters the finishing phase: every block is stored, the data file `out` is to be
    /// written. Every picture the run may draw (`may_draw`) is removed first: they are about
    /// to be drawn again, and one left from an earlier run (`--force` over another spec)
    /// must not survive beside the new data when a signal stops the drawing.
    pub fn finishing(&self, out: &Path, may_draw: &[PathBuf]) -> anyhow::Result<()> {
        *self.phase.lock().unwrap_or_else(|e| e.into_inner()) = Phase::Finishing {
            out: out.to_path_buf(),
        };
        for p in may_draw.iter().filter(|p| p.exists()) {
            std::fs::remove_file(p).with_context(|| {
                format!("removing the picture {} to draw it again", p.display())
            })?;
        }
        test_pause_before_write();
        Ok(())
    }

    /// Enters the last phase: the data file and its pictures are complete.
    pub fn done(&self) {
        *self.phase.lock().unwrap_or_else(|e| e.into_inner()) = Phase::Done;
    }

    /// Enters the drawing phase: the data file is complete, `pictures` are to be drawn, and
    /// `note` says so and how to draw them. Returns `false` if a signal came after the
    /// blocks and before this (the caller then says `note` and draws nothing); from here on
    /// a signal removes the cut pictures, says `note` and exits with code 130.
    pub fn drawing(&self, note: String, pictures: &[PathBuf]) -> bool {
        // The flag is read under the phase's lock, as the handler sets it: a signal is
        // either seen here (nothing drawn) or answered as one while drawing, never neither.
        let mut phase = self.phase.lock().unwrap_or_else(|e| e.into_inner());
        *phase = Phase::Drawing(Drawing {
            note,
            pictures: pictures.to_vec(),
        });
        !self.stop.load(Ordering::SeqCst)
    }

    /// What one signal does now (and marks the run stopped).
    fn respond(&self) -> Response {
        let guard = self.phase.lock().unwrap_or_else(|e| e.into_inner());
        let phase = guard.clone();
        let again = self.stop.swap(true, Ordering::SeqCst);
        drop(guard);
        match phase {
            Phase::Drawing(d) => Response::QuitDrawing(d),
            Phase::Estimating => Response::QuitEstimating,
            Phase::Finishing { out } => Response::StopAfter(finishing_words(&out, again)),
            Phase::Computing { .. } | Phase::Done if again => Response::Quit,
            Phase::Computing { what } => Response::StopAfter(format!(
                "stopping after the {what} in flight (signal again to quit at once)"
            )),
            Phase::Done => Response::StopAfter(
                "the data file and its pictures are complete; finishing the summary (signal \
                 again to quit at once)"
                    .into(),
            ),
        }
    }

    fn on_signal(&self) {
        match self.respond() {
            Response::StopAfter(how) => eprintln!("\nsqueal: {how}"),
            Response::Quit => std::process::exit(EXIT_INTERRUPTED.into()),
            Response::QuitEstimating => {
                eprintln!("\nsqueal: {ESTIMATE_INTERRUPTED}");
                std::process::exit(EXIT_INTERRUPTED.into())
            }
            Response::QuitDrawing(d) => {
                for p in d.pictures.iter().filter(|p| p.exists() && !is_drawn(p)) {
                    let _ = std::fs::remove_file(p);
                }
                eprintln!("\nsqueal: {}", d.note);
                std::process::exit(EXIT_INTERRUPTED.into())
            }
        }
    }
}

/// What a signal while the data file `out` is written says: the first, that the run stops
/// once it is written and draws no picture; a later one (`again`), that the write goes on.
/// Neither quits: a quit there left the file's temporary file, the lock and the journal
/// (for `--resume`) instead of the file the first signal announced.
fn finishing_words(out: &Path, again: bool) -> String {
    let out = out.display();
    match again {
        false => format!(
            "stopping once the data file {out} is written; its pictures are not drawn (the \
             write is finished whatever signals follow)"
        ),
        true => format!(
            "still writing the data file {out}: the run stops once it is written (SIGKILL \
             would leave its temporary file and journal, which --resume finishes)"
        ),
    }
}

/// Variable of the environment naming milliseconds to wait once every block is stored,
/// before the data file is written: a test's small file is written in milliseconds, too
/// short to aim a signal at (the end-to-end test of a signal during the write sets it).
pub const TEST_PAUSE_VAR: &str = "SQUEAL_TEST_PAUSE_BEFORE_WRITE_MS";

/// The wait [`TEST_PAUSE_VAR`] asks for, said on stderr (a test waits for the line).
fn test_pause_before_write() {
    let Some(ms) = std::env::var(TEST_PAUSE_VAR)
        .ok()
        .and_then(|v| v.parse::<u64>().ok())
    else {
        return;
    };
    eprintln!("squeal: {TEST_PAUSE_VAR}: waiting {ms} ms before writing the data file");
    std::thread::sleep(std::time::Duration::from_millis(ms));
}

/// What a run stopped while its work is estimated says.
pub const ESTIMATE_INTERRUPTED: &str = "interrupted while estimating the work (the pilot), \
     before the output was created: nothing was computed or written; run the command again";

/// What a run stopped while (or before) drawing says: the data file `out` is complete, the
/// pictures are not, and `redraw` draws them.
pub fn drawing_note(out: &std::path::Path, redraw: &str) -> String {
    format!(
        "interrupted while drawing the pictures; the data file {} is complete (every block \
         stored, the file finished). Draw the pictures with: {redraw}",
        out.display()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// While computing, the first signal stops the run after the work in flight and the
    /// second quits; once drawing (the data file complete) the first signal quits with the
    /// note naming the file. Before the drawing phase existed, a signal during the drawing
    /// was the first signal of the computing phase and only printed "stopping after the
    /// blocks in flight": the picture was drawn to the end.
    #[test]
    fn a_signal_while_drawing_quits_at_once_and_names_the_complete_file() {
        let after = |how: &str| Response::StopAfter(how.to_string());
        let s = Signals::new("blocks");
        assert_eq!(
            s.respond(),
            after("stopping after the blocks in flight (signal again to quit at once)")
        );
        assert!(s.stop().load(Ordering::SeqCst));
        assert_eq!(s.respond(), Response::Quit);

        let s = Signals::new("blocks");
        let pics = vec![PathBuf::from("x.png")];
        let note = drawing_note(
            std::path::Path::new("x.h5"),
            "squeal scan x.toml -o x.h5 --resume",
        );
        assert!(s.drawing(note.clone(), &pics));
        match s.respond() {
            Response::QuitDrawing(d) => {
                assert_eq!(d.pictures, pics);
                assert!(
                    d.note.contains("the data file x.h5 is complete"),
                    "{}",
                    d.note
                );
                assert!(d.note.ends_with("squeal scan x.toml -o x.h5 --resume"));
            }
            other => panic!("{other:?}"),
        }

        // A signal after the blocks and before the drawing: the file is written, nothing
        // is drawn.
        let s = Signals::new("blocks");
        s.finishing(Path::new("x.h5"), &[]).unwrap();
        match s.respond() {
            Response::StopAfter(how) => assert!(how.contains("pictures are not drawn"), "{how}"),
            other => panic!("{other:?}"),
        }
        assert!(!s.drawing(note, &pics));
    }

    /// Once the pictures are drawn, a signal lets the summary finish: it was answered as
    /// one while drawing (exit 130, "interrupted while drawing the pictures") although
    /// every picture was whole. A second one quits.
    /// While the work is estimated (the pilot, before the output exists) a signal quits
    /// at once, saying nothing was written: the handler was installed only after the
    /// pilot, and a signal there ended the atlas with code 143 and no word.
    #[test]
    fn a_signal_while_estimating_quits_saying_nothing_was_written() {
        let s = Signals::estimating();
        assert_eq!(s.respond(), Response::QuitEstimating);
        let s = Signals::estimating();
        s.computing("units");
        assert_eq!(
            s.respond(),
            Response::StopAfter(
                "stopping after the units in flight (signal again to quit at once)".into()
            )
        );
    }

    #[test]
    fn a_signal_after_the_drawing_lets_the_summary_finish() {
        let s = Signals::new("blocks");
        assert!(s.drawing("note".into(), &[PathBuf::from("x.png")]));
        s.done();
        match s.respond() {
            Response::StopAfter(how) => assert!(how.contains("are complete"), "{how}"),
            other => panic!("{other:?}"),
        }
        assert_eq!(s.respond(), Response::Quit);
    }

    /// Entering the finishing phase removes the pictures the run is about to draw: one of
    /// an earlier spec (`--force`) must not outlive a drawing that a signal stops.
    #[test]
    fn finishing_removes_the_pictures_about_to_be_drawn() {
        let d = tempfile::tempdir().unwrap();
        let (old, absent) = (d.path().join("x.png"), d.path().join("x-cycle.png"));
        std::fs::write(&old, b"an earlier picture").unwrap();
        let s = Signals::new("blocks");
        s.finishing(Path::new("x.h5"), &[old.clone(), absent.clone()])
            .unwrap();
        assert!(!old.exists() && !absent.exists());
    }

    /// While the data file is written, a second signal (GNU `timeout` sends two: to the
    /// run and to its group) and a third let the write finish, naming the file: the second
    /// quit at once, leaving the temporary file, the lock and the journal.
    #[test]
    fn signals_while_the_data_file_is_written_let_it_be_written() {
        let s = Signals::new("blocks");
        s.finishing(Path::new("x.h5"), &[]).unwrap();
        for (n, words) in [
            (1, "stopping once the data file x.h5 is written"),
            (2, "still writing the data file x.h5"),
            (3, "still writing"),
        ] {
            match s.respond() {
                Response::StopAfter(how) => assert!(how.contains(words), "signal {n}: {how}"),
                other => panic!("signal {n}: {other:?}"),
            }
        }
        assert!(s.stop().load(Ordering::SeqCst));
    }
}
