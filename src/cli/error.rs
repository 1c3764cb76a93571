//! The command line's errors and their exit codes.

/// Exit codes: 0 success, 1 the work failed (render, write, comparison), 2 bad input,
/// 130 interrupted by Ctrl-C.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// The input was wrong: scene file, option value, paths.
    #[error("{0}")]
    BadInput(String),
    /// The input was fine but the work failed (e.g. the output could not be written).
    #[error("{0}")]
    Failed(String),
    /// Ctrl-C: nothing was written (exit 130, the shell's convention for SIGINT).
    #[error("interrupted; no output was written")]
    Interrupted,
    /// Ctrl-C during a command that writes several outputs: what was and was not written.
    #[error("interrupted; {0}")]
    InterruptedAt(String),
}

impl CliError {
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::BadInput(_) => 2,
            CliError::Failed(_) => 1,
            CliError::Interrupted | CliError::InterruptedAt(_) => 130,
        }
    }
}
