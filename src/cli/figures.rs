//! `lumiere figures`: the course's figure sets, read from their scene files, regenerated
//! (or listed, or checked against the files on disk), one line per set written with its
//! time, the times also in `<out>/timings.json`, a signal (Ctrl-C, SIGTERM, SIGHUP)
//! leaving each set wholly old or wholly new, one run at a time in an output folder.

use super::lock::FolderLock;
use super::{CliError, Verbosity, noun_for, signals, with_threads};
use clap::Args;
use lumiere::figures::check::{Problem, check_index, check_set, extra_folders, manifest_scale};
use lumiere::figures::{FigureSet, FiguresError, Reuse, Run, files, generate_until, write_index};
use lumiere::film::{WriteError, write_atomic};
use lumiere::limits::{self, MAX_FIGURE_SCALE, MAX_THREADS};
use lumiere::review::{self, PageItem, Section};
use lumiere::scene::{Format, simrenderer};
use serde_json::json;
use std::path::{Path, PathBuf};

/// The file of the output folder that the last run's times go to (not a figure: the
/// figures' own files hold no time, so that they change only when a pixel or a scene does).
pub const TIMINGS: &str = "timings.json";

#[derive(Args, Debug)]
pub struct FiguresArgs {
    /// Sets to regenerate (see --list); all when none is given.
    pub sets: Vec<String>,
    /// Output directory.
    #[arg(long, default_value = lumiere::figures::DEFAULT_OUT)]
    pub out: PathBuf,
    /// The figure files: one folder per set, with its set.toml and one scene file per figure.
    #[arg(long, default_value = lumiere::figures::DEFAULT_DIR)]
    pub scenes: PathBuf,
    #[arg(
        long,
        default_value_t = 1.0,
        help = format!("Image size factor, in (0, {}] (0.25 gives 200 x 150 previews)", limits::short(MAX_FIGURE_SCALE)),
        value_parser = super::numbers::figure_scale,
        allow_negative_numbers = true
    )]
    pub scale: f64,
    /// List the sets (those named, else all) and their images, render nothing.
    #[arg(long, conflicts_with = "check")]
    pub list: bool,
    /// Check the sets' files in the output directory: each figure against its manifest's
    /// pixel hash and a fresh render (at the manifest's scale), each contact sheet against a
    /// fresh one, pixel by pixel, the manifests and index.html against their regenerated
    /// selves; write nothing there; exit 1 on any difference.
    #[arg(long)]
    pub check: bool,
    /// With --check: the folder for the heat-maps, sheets and review page of the figures
    /// that differ (index.html, shared with `lumiere review-snapshots`).
    #[arg(long, default_value = "target/review")]
    pub review: PathBuf,
    #[arg(
        long,
        help = format!("Worker threads, in [1, {MAX_THREADS}] (default: all cores). The images do not depend on it"),
        value_parser = super::numbers::threads,
        allow_negative_numbers = true
    )]
    pub threads: Option<usize>,
    /// Write each figure's scene into DIR/<set>/ (in --format), render nothing: a
    /// student renders each figure with their own SIMRenderer lab. The figures SIMRenderer
    /// cannot express are listed as skipped, with the reason.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["check", "list"])]
    pub export_scenes: Option<PathBuf>,
    /// The format of --export-scenes: `simrenderer` (NN-name.txt) or `toml` (the figure's
    /// own file, NN-name.toml).
    #[arg(long, value_parser = super::format_values(), default_value = "simrenderer", requires = "export_scenes")]
    pub format: Format,
}

fn registry_error(e: files::RegistryError) -> CliError {
    match e {
        files::RegistryError::Io { ref source, .. } if super::error::is_path_error(source) => {
            CliError::BadInput(format!("{e} (run from the repository's root, or give --scenes)"))
        }
        files::RegistryError::Io { .. } => CliError::Failed(e.to_string()),
        other => CliError::BadInput(other.to_string()),
    }
}

pub fn run(args: &FiguresArgs, v: Verbosity) -> Result<(), CliError> {
    let all = files::load(&args.scenes).map_err(registry_error)?;
    let names: Vec<&str> = all.iter().map(|s| s.name.as_str()).collect();
    for name in &args.sets {
        if !names.contains(&name.as_str()) {
            return Err(CliError::BadInput(format!(
                "unknown figure set {name:?}; the sets are: {}",
                names.join(", ")
            )));
        }
    }
    let chosen: Vec<&FigureSet> = all
        .iter()
        .filter(|s| args.sets.is_empty() || args.sets.contains(&s.name))
        .collect();
    if args.list {
        for set in &chosen {
            println!("{}: {}", set.name, set.title);
            for f in &set.figures {
                println!("  {}.png  {}", f.stem, f.caption);
            }
        }
        return Ok(());
    }
    if args.check {
        return check(&all, &chosen, args, v);
    }
    if let Some(dir) = &args.export_scenes {
        super::check_out_folder(dir, "--export-scenes")?;
        return export(&chosen, dir, args.format, v);
    }
    super::check_out_folder(&args.out, "--out")?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| WriteError::new(&args.out, "cannot create the output directory", e))?;
    // Held until the run ends, however it ends: a second run on this folder is refused.
    let _lock = FolderLock::take(&args.out)?;
    let start = std::time::Instant::now();
    // A signal stops the set being rendered and leaves its folder as it was; the sets before
    // it are complete (see `generate_until`). A second signal is a request too: ending the
    // process in the milliseconds a set's files take to write would leave it part old. If
    // the handler cannot be installed, the signal ends the process, which also leaves every
    // set whole unless it lands in those milliseconds.
    // A set on disk at another scale is replaced all the same: said before the run, so that
    // previews written over full-size figures (`--scale 0.25` without `--out`) are seen.
    for set in &chosen {
        if let Some(scale) = manifest_scale(&args.out, &set.name).filter(|s| *s != args.scale) {
            eprintln!(
                "lumiere: warning: {} holds the set at scale {scale}; this run writes it at scale {}",
                args.out.join(&set.name).display(),
                args.scale
            );
        }
    }
    let cancel = signals::catch_first_only();
    let mut written: Vec<&str> = Vec::new();
    let mut times: Vec<serde_json::Value> = Vec::new();
    let mut reuse = Reuse::for_sets(&chosen);
    let run = Run {
        out: args.out.clone(),
        scenes: args.scenes.clone(),
        scale: args.scale,
    };
    for set in &chosen {
        v.note(|| {
            format!(
                "{}: rendering {} figure(s) at scale {} on {} thread(s)",
                set.name,
                set.figures.len(),
                args.scale,
                args.threads.unwrap_or_else(rayon::current_num_threads)
            )
        });
        let report =
            with_threads(args.threads, || generate_until(set, &run, cancel, &mut reuse))?.map_err(|e| match e {
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
        for name in &report.extra {
            eprintln!(
                "lumiere: warning: {}: no figure of the set {:?} makes this file; remove it (`lumiere figures --check` reports it)",
                report.dir.join(name).display(),
                report.name
            );
        }
        // The gallery of the sets in the folder, this one's included, whatever stops the run
        // after it.
        write_index(&args.out, &all)?;
        v.note(|| {
            format!(
                "{}: wrote {} image(s), its manifest and contact sheet into {}",
                report.name,
                report.images,
                report.dir.display()
            )
        });
        written.push(&set.name);
        times.push(json!({"set": report.name, "images": report.images, "seconds": round_ms(report.seconds)}));
        write_timings(args, &times, start.elapsed().as_secs_f64())?;
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
    let total = start.elapsed().as_secs_f64();
    write_timings(args, &times, total)?;
    if v != Verbosity::Quiet {
        println!(
            "total                     {:>7.2} s  {}",
            total,
            args.out.join("index.html").display()
        );
    }
    Ok(())
}

/// `--export-scenes`: each figure's scene into `dir/<set>/`, one line per set written and
/// one per figure skipped.
fn export(sets: &[&FigureSet], dir: &Path, format: Format, v: Verbosity) -> Result<(), CliError> {
    for set in sets {
        let folder = dir.join(&set.name);
        let (mut written, mut skipped) = (0, 0);
        for f in &set.figures {
            let (name, bytes) = match format {
                Format::Toml => {
                    let bytes = std::fs::read(&f.scene_file).map_err(|e| {
                        CliError::BadInput(format!("{}: cannot read the scene file: {e}", f.scene_file))
                    })?;
                    (format!("{}.toml", f.stem), bytes)
                }
                Format::SimRenderer => match simrenderer::to_simrenderer(&f.scene, &f.scene_file, &f.stem) {
                    Ok(w) => (format!("{}.txt", f.stem), w.text.into_bytes()),
                    Err(refused) => {
                        println!("skipped {}/{}: {refused}", set.name, f.stem);
                        skipped += 1;
                        continue;
                    }
                },
            };
            std::fs::create_dir_all(&folder)
                .map_err(|e| WriteError::new(&folder, "cannot create the output directory", e))?;
            let path = folder.join(name);
            write_atomic(&path, &bytes).map_err(|e| CliError::from(WriteError::new(&path, "cannot write", e)))?;
            written += 1;
        }
        if v != Verbosity::Quiet {
            // A set of which no scene is written gets no folder.
            let place = if written > 0 {
                folder.display().to_string()
            } else {
                "(no folder made)".to_string()
            };
            println!(
                "{:<12} {written:>3} {} written, {skipped} skipped  {place}",
                set.name,
                noun_for(written, "scene")
            );
        }
    }
    Ok(())
}

fn round_ms(seconds: f64) -> f64 {
    (seconds * 1000.0).round() / 1000.0
}

/// `<out>/timings.json`: the run's sets with their images and wall times so far.
fn write_timings(args: &FiguresArgs, sets: &[serde_json::Value], total: f64) -> Result<(), CliError> {
    let threads = args.threads.unwrap_or_else(rayon::current_num_threads);
    let text = serde_json::to_string_pretty(&json!({
        "renderer": format!("lumiere {}", lumiere::VERSION),
        "scale": args.scale,
        "threads": threads,
        "sets": sets,
        "total_seconds": round_ms(total),
        "note": "wall times of the last run of `lumiere figures` in this folder; a set's time includes the figures of later sets rendered in its passes",
    }))
    .map_err(|e| CliError::Failed(e.to_string()))?
        + "\n";
    let path = args.out.join(TIMINGS);
    write_atomic(&path, text.as_bytes()).map_err(|e| CliError::from(WriteError::new(&path, "cannot write", e)))
}

/// `--check`: each chosen set rendered again in memory and held to its files on disk, then
/// the gallery, and with every set chosen, the output's folders; one line per problem,
/// heat-maps and the review page in `--review` when a figure differs, exit 1 if any.
fn check(all: &[FigureSet], sets: &[&FigureSet], args: &FiguresArgs, v: Verbosity) -> Result<(), CliError> {
    // Refused before anything is rendered: an output with nothing to check, a review folder
    // that cannot be made.
    super::check_out_folder(&args.out, "--out")?;
    super::check_out_folder(&args.review, "--review")?;
    if !args.out.is_dir() {
        let generate = Run {
            out: args.out.clone(),
            scenes: args.scenes.clone(),
            scale: args.scale,
        };
        return Err(CliError::BadInput(format!(
            "--out: {} does not exist, so it holds no figure to check (`{}` writes them)",
            args.out.display(),
            generate.command(&args.sets.join(" "))
        )));
    }
    let review_dir = &args.review;
    let figures_dir = review_dir.join(review::FIGURES);
    review::clear_sheets(&figures_dir).map_err(review_error)?;
    let mut problems: Vec<Problem> = Vec::new();
    let mut items: Vec<PageItem> = Vec::new();
    let mut manifests = Vec::new();
    let mut reuse = Reuse::for_sets(sets);
    // The sets that differ, and the command that regenerates them.
    let mut differing: Vec<&str> = Vec::new();
    let mut remake = Run {
        out: args.out.clone(),
        scenes: args.scenes.clone(),
        scale: args.scale,
    };
    for set in sets {
        let recorded = manifest_scale(&args.out, &set.name);
        let run = Run {
            out: args.out.clone(),
            scenes: args.scenes.clone(),
            scale: recorded.unwrap_or(args.scale),
        };
        // The scale checked, when it is not the figures' own size.
        let scale_note = match recorded {
            Some(s) if s != 1.0 => format!(" (at scale {s}, as its manifest records)"),
            None if args.scale != 1.0 => format!(" (at scale {})", args.scale),
            _ => String::new(),
        };
        let checked = with_threads(args.threads, || check_set(set, &run, &mut reuse, review_dir))?
            .map_err(|e| CliError::Failed(e.to_string()))?;
        for p in &checked.problems {
            println!("{p}");
        }
        if v != Verbosity::Quiet {
            let verdict = if checked.problems.is_empty() { "ok" } else { "DIFFERS" };
            println!("{:<12} {verdict}{scale_note}", set.name);
        }
        if checked.problems.iter().any(Problem::regenerating_fixes) {
            differing.push(&set.name);
            remake.scale = run.scale;
        }
        problems.extend(checked.problems);
        items.extend(checked.review);
        manifests.push((set.name.clone(), checked.manifest));
    }
    let mut rest: Vec<Problem> = check_index(&args.out, all, &manifests).into_iter().collect();
    if sets.len() == all.len() {
        rest.extend(extra_folders(&args.out, all));
    }
    for p in &rest {
        println!("{p}");
        items.push(PageItem {
            name: p.file.clone(),
            summary: p.to_string(),
            sheet: None,
        });
    }
    problems.extend(rest);
    if !items.is_empty() || review_dir.is_dir() {
        review::write_section(review_dir, Section::Figures, &items).map_err(review_error)?;
    }
    if problems.is_empty() {
        return Ok(());
    }
    if v != Verbosity::Quiet && !items.is_empty() {
        println!("review page: {}", review_dir.join("index.html").display());
    }
    Err(CliError::Failed(check_failure(&problems, &differing, sets, &remake)))
}

/// The error of a check that found `problems`: how many, the command that regenerates the
/// sets whose files it fixes (`differing`, or any set when the gallery alone differs), and
/// the files and folders to remove, which no regeneration does.
fn check_failure(problems: &[Problem], differing: &[&str], sets: &[&FigureSet], remake: &Run) -> String {
    let extra = problems.iter().filter(|p| !p.regenerating_fixes()).count();
    let mut message = format!(
        "{} problems: the figures on disk differ from their sets",
        problems.len()
    );
    if extra < problems.len() {
        let names = if differing.is_empty() {
            sets[0].name.clone()
        } else {
            differing.join(" ")
        };
        message += &format!(
            " (`{}` regenerates them; a change made on purpose is accepted as docs/figures.md, \"Changing a figure on purpose\", says)",
            remake.command(&names)
        );
    }
    if extra > 0 {
        message +=
            &format!("; {extra} extra file(s) or folder(s) listed above, which regenerating leaves: remove them");
    }
    message
}

fn review_error(e: review::ReviewError) -> CliError {
    match e {
        review::ReviewError::Write(w) => CliError::from(w),
        other => CliError::Failed(other.to_string()),
    }
}
