//! What is at a path before squeal opens it. A FIFO at a spec, an output, a lock or a
//! journal blocked the open for ever with no message; a directory or a socket
//! gave the file system's or HDF5's words, or a Rust debug dump of the file type. Every
//! path squeal reads or writes is judged here first ([`refuse_non_regular`]), and named in
//! words ([`what_is`]).

use std::fs::FileType;
use std::path::{Path, PathBuf};

/// Something other than a regular file where squeal reads or writes one.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{} is {what}, not a regular file", path.display())]
pub struct NotRegular {
    /// The path.
    pub path: PathBuf,
    /// What is there, in words ([`what_is`]).
    pub what: &'static str,
}

/// A file type in words: "a directory", "a FIFO (named pipe)", ...
pub fn what_is(ft: FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ft.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if ft.is_socket() {
            return "a socket";
        }
        if ft.is_char_device() {
            return "a character device";
        }
        if ft.is_block_device() {
            return "a block device";
        }
    }
    if ft.is_dir() {
        "a directory"
    } else if ft.is_symlink() {
        "a symbolic link"
    } else if ft.is_file() {
        "a regular file"
    } else {
        "not a file"
    }
}

/// Refuses `path` when something other than a regular file is there (symbolic links
/// followed): opening a FIFO would wait for a writer for ever. Nothing there, or a path that
/// cannot be looked at, is left to the caller's open (which names its own error).
pub fn refuse_non_regular(path: &Path) -> Result<(), NotRegular> {
    match std::fs::metadata(path) {
        Ok(md) if !md.is_file() => Err(NotRegular {
            path: path.to_path_buf(),
            what: what_is(md.file_type()),
        }),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A folder of its own under the system's temporary folder (this crate has no
    /// dev-dependency on tempfile).
    fn folder(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("squeal-files-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn a_fifo_and_a_directory_are_refused_in_words_and_a_file_or_nothing_passes() {
        let d = folder("kinds");
        let fifo = d.join("p");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.map(|s| s.success()).unwrap_or(false) {
            let e = refuse_non_regular(&fifo).unwrap_err();
            assert_eq!(e.what, "a FIFO (named pipe)");
            assert!(
                e.to_string()
                    .ends_with("is a FIFO (named pipe), not a regular file")
            );
        } else {
            eprintln!("skipping the FIFO case: mkfifo did not run");
        }
        assert_eq!(refuse_non_regular(&d).unwrap_err().what, "a directory");
        let f = d.join("f");
        std::fs::write(&f, "x").unwrap();
        assert!(refuse_non_regular(&f).is_ok());
        assert!(refuse_non_regular(&d.join("absent")).is_ok());
        std::fs::remove_dir_all(&d).unwrap();
    }
}
