//! The lock that keeps two `lumiere figures` runs from writing one output folder at once:
//! an exclusive lock on `<out>/.lumiere-figures.lock`, which holds the holder's pid and
//! command line, so a second run can say who holds it. The lock is the operating system's
//! (released when the holder's process ends, however it ends); the file is removed when
//! the holder releases it.

use super::CliError;
use lumiere::film::WriteError;
use std::fs::{self, File, OpenOptions, TryLockError};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The lock file's name in the output folder.
pub const LOCK_FILE: &str = ".lumiere-figures.lock";

/// A held lock on a folder; dropping it removes the lock file, then releases the lock.
pub struct FolderLock {
    path: PathBuf,
    /// Kept open: the lock lasts as long as the file is open.
    _file: File,
}

impl FolderLock {
    /// Takes the lock of `dir` (which must exist) for this process, or says who holds it
    /// (bad input: the folder is in use).
    pub fn take(dir: &Path) -> Result<FolderLock, CliError> {
        let path = dir.join(LOCK_FILE);
        let failed = |what: &str, e: std::io::Error| CliError::Failed(format!("{}: {what}: {e}", path.display()));
        loop {
            let file = OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(&path)
                .map_err(|e| WriteError::new(&path, "cannot create the lock file", e))?;
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    let holder = fs::read_to_string(&path).unwrap_or_default();
                    return Err(CliError::BadInput(held_message(dir, holder.trim())));
                }
                Err(TryLockError::Error(e)) => return Err(failed("cannot lock", e)),
            }
            // The holder before us removes the file before it releases the lock: if it did
            // so between our open and our lock, we hold a removed file, so start again.
            if !is_at(&file, &path) {
                continue;
            }
            let mut writer = &file;
            file.set_len(0).map_err(|e| failed("cannot write", e))?;
            writer
                .write_all(holder_line().as_bytes())
                .map_err(|e| failed("cannot write", e))?;
            return Ok(FolderLock { path, _file: file });
        }
    }
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        // Removed while still locked (see `take`); the lock goes with the file handle.
        let _ = fs::remove_file(&self.path);
    }
}

/// What the lock file holds: `pid N: the command line`.
fn holder_line() -> String {
    let args: Vec<String> = std::env::args_os().map(|a| a.to_string_lossy().into_owned()).collect();
    format!("pid {}: {}\n", std::process::id(), args.join(" "))
}

/// The error of a run that finds `dir` locked by `holder` (the lock file's text).
fn held_message(dir: &Path, holder: &str) -> String {
    let holder = if holder.is_empty() {
        "it has not written its pid yet".to_string()
    } else {
        holder.to_string()
    };
    format!(
        "{}: another lumiere figures run is writing into this folder ({holder}); run again when it has ended, or choose another --out",
        dir.display()
    )
}

/// Whether the open `file` is the file at `path`.
#[cfg(unix)]
fn is_at(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), fs::metadata(path)) {
        (Ok(a), Ok(b)) => (a.dev(), a.ino()) == (b.dev(), b.ino()),
        _ => false,
    }
}

/// Whether the open `file` is the file at `path` (here: whether a file is there).
#[cfg(not(unix))]
fn is_at(_file: &File, path: &Path) -> bool {
    path.exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_message_names_the_holder() {
        let m = held_message(Path::new("out"), "pid 7: lumiere figures lighting");
        assert_eq!(
            m,
            "out: another lumiere figures run is writing into this folder (pid 7: lumiere figures lighting); \
             run again when it has ended, or choose another --out"
        );
        assert!(held_message(Path::new("out"), "").contains("(it has not written its pid yet)"));
    }

    #[test]
    fn one_holder_at_a_time_and_no_file_after() {
        let dir = std::env::temp_dir().join(format!("lumiere-lock-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let lock = FolderLock::take(&dir).unwrap();
        let text = fs::read_to_string(dir.join(LOCK_FILE)).unwrap();
        assert!(text.starts_with(&format!("pid {}: ", std::process::id())), "{text}");
        // A second lock through another open file of the same process is refused too
        // (the lock belongs to the open file, not to the process).
        let Err(CliError::BadInput(m)) = FolderLock::take(&dir) else {
            panic!("the folder was locked twice");
        };
        assert!(m.contains(text.trim()), "{m}");
        drop(lock);
        assert!(!dir.join(LOCK_FILE).exists());
        // Free again.
        drop(FolderLock::take(&dir).unwrap());
        fs::remove_dir_all(&dir).unwrap();
    }
}
