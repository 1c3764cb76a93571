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
