//! The command line's errors and their exit codes.

use super::signals::Signal;

/// Exit codes: 0 success, 1 the work failed (render, write, comparison), 2 bad input,
/// 128 + the signal's number when a signal stopped the work (130 for Ctrl-C, 143 for
/// SIGTERM, 129 for SIGHUP).
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// The input was wrong: scene file, option value, paths.
    #[error("{0}")]
    BadInput(String),
    /// The input was fine but the work failed (e.g. the output could not be written).
    #[error("{0}")]
    Failed(String),
    /// A signal stopped the work: nothing was written.
    #[error("{}; no output was written", .0.interrupted())]
    Interrupted(Signal),
    /// A signal stopped a command that writes several outputs: what was and was not written.
    #[error("{how}; {1}", how = .0.interrupted())]
    InterruptedAt(Signal, String),
}

impl CliError {
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::BadInput(_) => 2,
            CliError::Failed(_) => 1,
            CliError::Interrupted(s) | CliError::InterruptedAt(s, _) => s.exit_code(),
        }
    }
}

/// Whether a failed write is the path's fault: a folder that is missing or is a file, an
/// output that is a folder, no permission, a read-only file system, a bad name. Anything
/// else (disk full, quota, file-size limit, I/O error) is the work failing.
pub fn is_path_error(e: &std::io::Error) -> bool {
    use std::io::ErrorKind::*;
    matches!(
        e.kind(),
        NotFound
            | PermissionDenied
            | AlreadyExists
            | IsADirectory
            | NotADirectory
            | ReadOnlyFilesystem
            | InvalidFilename
            | InvalidInput
    )
}

impl From<lumiere::film::WriteError> for CliError {
    /// Bad input (exit 2) when the path is at fault, else failed work (exit 1).
    fn from(e: lumiere::film::WriteError) -> Self {
        if is_path_error(&e.io) {
            CliError::BadInput(e.to_string())
        } else {
            CliError::Failed(e.to_string())
        }
    }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use lumiere::film::WriteError;
    use std::path::Path;

    /// The exit code of a write of `out.png` failing with the system error `errno`.
    fn exit_code(errno: i32) -> u8 {
        let e = WriteError::new(
            Path::new("out.png"),
            "cannot write",
            std::io::Error::from_raw_os_error(errno),
        );
        CliError::from(e).exit_code()
    }

    #[test]
    fn path_errors_are_bad_input_and_a_full_disk_is_failed_work() {
        for errno in [
            libc::ENOENT,
            libc::EACCES,
            libc::EPERM,
            libc::EEXIST,
            libc::EISDIR,
            libc::ENOTDIR,
            libc::EROFS,
            libc::ENAMETOOLONG,
        ] {
            assert_eq!(exit_code(errno), 2, "errno {errno}");
        }
        for errno in [libc::ENOSPC, libc::EDQUOT, libc::EFBIG, libc::EIO] {
            assert_eq!(exit_code(errno), 1, "errno {errno}");
        }
        let e = WriteError::new(
            Path::new("out.png"),
            "cannot write",
            std::io::Error::from_raw_os_error(libc::ENOSPC),
        );
        assert_eq!(
            CliError::from(e).to_string(),
            "out.png: cannot write: No space left on device (os error 28)"
        );
    }
}
