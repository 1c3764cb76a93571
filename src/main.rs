//! The `lumiere` binary: parse the command line, run, print errors on stderr, exit with
//! the documented code (0 ok, 1 render or comparison failed, 2 bad input).

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = lumiere::cli::Cli::parse();
    match lumiere::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("lumiere: error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
