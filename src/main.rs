//! The `lumiere` binary: parse the command line, run, print errors on stderr, exit with
//! the documented code (0 ok, 1 the work failed, 2 bad input, 128 + N stopped by signal N;
//! README.md's table). The command line lives here and in `cli/`; the library
//! (`src/lib.rs`) holds the work.

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // A closed stdout (`lumiere figures --list | head`) ends the program quietly, as for
    // other command-line tools, instead of a panic on the next print. A write past the
    // file-size limit (`ulimit -f`) fails with EFBIG, an error like a full disk's (exit 1,
    // the temporary file removed, every set or image old or whole), instead of SIGXFSZ
    // ending the process there.
    #[cfg(unix)]
    // SAFETY: called first thing, before any other thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    let args = cli::Cli::parse();
    // glibc serves blocks under a threshold from its heap, and raises that threshold to the
    // size of each large block freed (up to 32 MiB): a million objects' arrays (boxes,
    // subtrees, sort keys) then stay resident after they are freed. A fixed 1 MiB keeps
    // every large array in its own mapping, returned when freed. `figures` keeps glibc's
    // rule: its worlds are small, and it allocates an image's films again and again, which
    // then come back from the heap instead of new mappings paid page by page (the nine
    // course sets: 0.3 s of system time, 1.5 % of the wall time; BENCHMARKS.md).
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    if !matches!(args.command, cli::Command::Figures(_)) {
        // SAFETY: called before any allocation made by another thread.
        unsafe {
            libc::mallopt(libc::M_MMAP_THRESHOLD, 1 << 20);
        }
    }
    match cli::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: a decoder's message may end in a line break of its own (JPEG's does).
            eprintln!("lumiere: error: {}", e.to_string().trim_end());
            let mut source = std::error::Error::source(&e);
            while let Some(cause) = source {
                eprintln!("  caused by: {cause}");
                source = cause.source();
            }
            ExitCode::from(e.exit_code())
        }
    }
}
