//! Each door's words for what the library's refusals advise ([`squeal_store::Remedy`]):
//! the command line names its flags ([`Flags`]), the Python package its keyword arguments
//! ([`Keywords`]). The library's errors carry the remedy as data and say it in plain words;
//! a door words the same error with [`squeal_store::StoreError::worded`]. Both doors' words
//! are here, beside the command line's wiring that the Python package shares, so that one
//! test holds them to the same errors.

use std::path::Path;

use squeal_scan::DriveError;
use squeal_store::{Remedy, StoreError, Words};

use crate::AtlasRunError;

/// The command line's words: its flags.
#[derive(Debug, Clone, Copy, Default)]
pub struct Flags;

impl Words for Flags {
    fn remedy(&self, remedy: Remedy) -> &'static str {
        match remedy {
            Remedy::Force => "--force",
            Remedy::Resume => "--resume",
            Remedy::OtherOutput => "-o",
        }
    }
    fn show(&self, path: &Path) -> Option<String> {
        Some(format!(
            "draw its picture with: squeal render {}",
            path.display()
        ))
    }
}

/// The Python package's words: the keyword arguments of `squeal.scan`, `squeal.atlas` and
/// `squeal.trajectory`.
#[derive(Debug, Clone, Copy, Default)]
pub struct Keywords;

impl Words for Keywords {
    fn remedy(&self, remedy: Remedy) -> &'static str {
        match remedy {
            Remedy::Force => "force=True",
            Remedy::Resume => "resume=True",
            Remedy::OtherOutput => "another out=",
        }
    }
    fn show(&self, path: &Path) -> Option<String> {
        Some(format!(
            "open it with: squeal.open({:?})",
            path.display().to_string()
        ))
    }
}

/// The store's error that `e` (one of the chain of an error the command line prints) is or
/// shows as its own message (the errors that wrap one transparently).
fn store_error<'e>(e: &'e (dyn std::error::Error + 'static)) -> Option<&'e StoreError> {
    if let Some(s) = e.downcast_ref::<StoreError>() {
        return Some(s);
    }
    if let Some(DriveError::Sink(s)) = e.downcast_ref::<DriveError<StoreError>>() {
        return Some(s);
    }
    match e.downcast_ref::<AtlasRunError>()? {
        AtlasRunError::Store(s) => Some(s),
        _ => None,
    }
}

/// The error `e` and its causes as the command line prints them (`{:#}`: each after a
/// colon), with the store's errors in `words`.
pub fn message(e: &anyhow::Error, words: &dyn Words) -> String {
    e.chain()
        .map(|c| store_error(c).map_or_else(|| c.to_string(), |s| s.worded(words)))
        .collect::<Vec<_>>()
        .join(": ")
}

/// The store's error `e` and its causes in `words`, each cause after a colon (as
/// [`message`] prints them).
pub fn store_message(e: &StoreError, words: &dyn Words) -> String {
    let mut out = e.worded(words);
    let mut cause = std::error::Error::source(e);
    while let Some(c) = cause {
        out.push_str(": ");
        out.push_str(&c.to_string());
        cause = c.source();
    }
    out
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use anyhow::Context;
    use squeal_store::{Advice, Plain};

    use super::*;

    /// One refusal of each kind that advises something.
    fn refusals() -> Vec<StoreError> {
        let path = PathBuf::from("out.h5");
        vec![
            StoreError::Exists { path: path.clone() },
            StoreError::OtherSpec {
                path: path.clone(),
                key: "model.nu".into(),
            },
            StoreError::Interrupted {
                path: PathBuf::from("out.h5.journal"),
            },
            StoreError::SpecMismatch {
                path: PathBuf::from("out.h5.journal"),
                why: "the journal was written for another spec (model.nu differs)".into(),
                advice: Some(Advice::StartOver),
            },
        ]
    }

    #[test]
    fn the_same_refusal_is_worded_by_each_door() {
        let e = StoreError::OtherSpec {
            path: PathBuf::from("out.h5"),
            key: "model.nu".into(),
        };
        let head = "out.h5 exists and was made from a different spec (`model.nu` differs): ";
        assert_eq!(
            e.worded(&Flags),
            format!("{head}use --force to overwrite it, or -o for another output")
        );
        assert_eq!(
            e.worded(&Keywords),
            format!("{head}use force=True to overwrite it, or another out= for another output")
        );
        assert_eq!(
            e.to_string(),
            format!(
                "{head}use the force option to overwrite it, or another path for another output"
            )
        );
        let e = StoreError::Interrupted {
            path: PathBuf::from("out.h5.journal"),
        };
        let head = "an interrupted scan is there (out.h5.journal): ";
        assert_eq!(
            e.worded(&Flags),
            format!("{head}use --resume, or --force to start over")
        );
        assert_eq!(
            e.worded(&Keywords),
            format!("{head}use resume=True, or force=True to start over")
        );
    }

    #[test]
    fn no_door_reads_another_doors_words() {
        for e in refusals() {
            let (flags, keywords, plain) = (e.worded(&Flags), e.worded(&Keywords), e.to_string());
            assert_eq!(plain, e.worded(&Plain));
            assert!(
                flags.contains("--force") && !flags.contains("=True"),
                "{flags}"
            );
            assert!(
                keywords.contains("force=True") && !keywords.contains("--"),
                "{keywords}"
            );
            assert!(!plain.contains("--") && !plain.contains("=True"), "{plain}");
        }
    }

    #[test]
    fn the_command_line_words_a_store_error_inside_its_chain() {
        // As `squeal scan` prints a refusal that a context wraps, and an atlas run's.
        let e = anyhow::Error::new(StoreError::Exists {
            path: PathBuf::from("out.h5"),
        });
        let e = Err::<(), _>(e)
            .context("cannot start the scan")
            .unwrap_err();
        assert_eq!(
            message(&e, &Flags),
            "cannot start the scan: refusing to overwrite out.h5: use --force"
        );
        let maps = AtlasRunError::Maps(DriveError::Sink(StoreError::Exists {
            path: PathBuf::from("a.h5"),
        }));
        assert_eq!(
            message(&anyhow::Error::new(maps), &Flags),
            "basin maps: refusing to overwrite a.h5: use --force"
        );
    }
}
