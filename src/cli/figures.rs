//! `lumiere figures`: the course's figure sets regenerated (or listed, or checked against
//! their manifests), one line per set written, a signal (Ctrl-C, SIGTERM, SIGHUP) leaving
//! each set wholly old or wholly new, one run at a time in an output folder.

use super::lock::FolderLock;
use super::{CliError, Verbosity, signals, with_threads};
use clap::Args;
use lumiere::figures::{FigureSet, FiguresError, Reuse, generate_until, registry, write_index};
use lumiere::film::WriteError;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct FiguresArgs {
    /// Sets to regenerate (see --list); all when none is given.
    pub sets: Vec<String>,
    /// Output directory.
    #[arg(long, default_value = "figures")]
    pub out: PathBuf,
    /// Image size factor, in (0, 4] (0.25 gives 200 x 150 previews).
    #[arg(long, default_value_t = 1.0)]
    pub scale: f64,
    /// List the sets and their images, render nothing.
    #[arg(long)]
    pub list: bool,
    /// Re-render the sets in memory and compare their pixel hashes with the manifests in
    /// the output directory; write nothing; exit 1 on any difference.
    #[arg(long)]
    pub check: bool,
    /// Worker threads (default: all cores). The images do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
}

pub fn run(args: &FiguresArgs, v: Verbosity) -> Result<(), CliError> {
    let all = registry();
    if args.list {
        for set in &all {
            println!("{}: {}", set.name, set.title);
            for f in (set.figures)() {
                println!("  {}.png  {}", f.stem, f.caption);
            }
        }
        return Ok(());
    }
    if !(args.scale > 0.0 && args.scale <= 4.0) {
        return Err(CliError::BadInput(format!(
            "--scale: must be in (0, 4], got {}",
            args.scale
        )));
    }
    let names: Vec<&str> = all.iter().map(|s| s.name).collect();
    for name in &args.sets {
        if !names.contains(&name.as_str()) {
            return Err(CliError::BadInput(format!(
                "unknown figure set {name:?}; the sets are: {}",
                names.join(", ")
            )));
        }
    }
    let chosen: Vec<_> = all
        .iter()
        .filter(|s| args.sets.is_empty() || args.sets.iter().any(|n| n == s.name))
        .collect();
    if args.check {
        return check(&chosen, args, v);
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| WriteError::new(&args.out, "cannot create the output directory", e))?;
    // Held until the run ends, however it ends: a second run on this folder is refused.
    let _lock = FolderLock::take(&args.out)?;
    let start = std::time::Instant::now();
    // A signal stops the set being rendered and leaves its folder as it was; the sets before
    // it are complete (see `generate_until`). If the handler cannot be installed, the signal
    // ends the process, which also leaves every set whole unless it lands in the
    // milliseconds a set's files take to write.
    let cancel = signals::catch();
    let mut written = Vec::new();
    let mut reuse = Reuse::for_sets(&chosen);
    for set in chosen {
        let report = with_threads(args.threads, || {
            generate_until(set, &args.out, args.scale, cancel, &mut reuse)
        })?
        .map_err(|e| match e {
            FiguresError::Encode(m) => CliError::Failed(m),
            FiguresError::Write(w) => CliError::from(w),
        })?;
        let stopped = signals::received();
        let Some(report) = report else {
            let signal = stopped.unwrap_or(signals::Signal::INT);
            return Err(CliError::InterruptedAt(
                signal,
                format!(
                    "figure set {:?} and the sets after it were left as they were; complete: [{}]",
                    set.name,
                    written.join(", ")
                ),
            ));
        };
        written.push(set.name);
        if v != Verbosity::Quiet {
            println!(
                "{:<12} {:>3} images  {:>7.2} s  {}",
                report.name,
                report.images,
                report.seconds,
                report.dir.display()
            );
        }
        if let Some(signal) = stopped {
            return Err(CliError::InterruptedAt(
                signal,
                format!(
                    "figure sets written: [{}]; the sets after them were left as they were",
                    written.join(", ")
                ),
            ));
        }
    }
    write_index(&args.out)?;
    if v != Verbosity::Quiet {
        println!(
            "total                     {:>7.2} s  {}",
            start.elapsed().as_secs_f64(),
            args.out.join("index.html").display()
        );
    }
    Ok(())
}

/// `--check`: each set re-rendered in memory against its manifest; one line per differing
/// figure, exit 1 if any.
fn check(sets: &[&FigureSet], args: &FiguresArgs, v: Verbosity) -> Result<(), CliError> {
    let mut failures = 0;
    let mut reuse = Reuse::for_sets(sets);
    for set in sets {
        let mismatches = with_threads(args.threads, || lumiere::figures::check(set, &args.out, &mut reuse))?
            .map_err(CliError::BadInput)?;
        for m in &mismatches {
            println!(
                "{}/{}: pixel hash {} (manifest {})",
                set.name, m.file, m.actual, m.expected
            );
        }
        if v != Verbosity::Quiet {
            println!(
                "{:<12} {}",
                set.name,
                if mismatches.is_empty() { "ok" } else { "DIFFERS" }
            );
        }
        failures += mismatches.len();
    }
    if failures > 0 {
        return Err(CliError::Failed(format!(
            "{failures} figures differ from their manifests"
        )));
    }
    Ok(())
}
