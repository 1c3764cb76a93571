//! The `lumiere` command line: clap's types of the top level, dispatch to one module per
//! command, and what the commands share (verbosity, worker threads, scene loading, output
//! paths, and the library's named choices as clap values; signals in [`signals`]). The library's work
//! functions return data; these modules parse, print and choose exit codes.

mod compare;
mod convert;
mod diagnose;
mod error;
mod figures;
mod lock;
mod merge;
mod numbers;
mod probe;
mod render;
mod review;
mod signals;
mod stress;
mod study;

pub use error::CliError;

use clap::builder::{PossibleValue, PossibleValuesParser, StyledStr, TypedValueParser};
use clap::{Args, Parser, Subcommand};
use lumiere::accel::AccelChoice;
use lumiere::conventions::Conventions;
use lumiere::limits::{self, MAX_ADAPTIVE_THRESHOLD, MAX_DEPTH, MAX_DIMENSION, MAX_SAMPLES};
use lumiere::scene::{self, Format, LoadOptions, Loaded, Scene};
use lumiere::skips::Skip;
use std::path::{Path, PathBuf};
use std::str::FromStr;

#[derive(Parser, Debug)]
#[command(
    name = "lumiere",
    version,
    about = "A seeded, deterministic Whitted ray tracer for the course on ray-traced illumination"
)]
pub struct Cli {
    /// Print nothing but results and errors (no progress bar, no summaries).
    #[arg(short, long, global = true)]
    pub quiet: bool,
    /// Also print what is being done (scene summary, threads, files written) on stderr.
    #[arg(short, long, global = true, conflicts_with = "quiet")]
    pub verbose: bool,
    #[command(subcommand)]
    pub command: Command,
}

/// How much the commands print besides their results.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verbosity {
    Quiet,
    Normal,
    Verbose,
}

impl Verbosity {
    fn of(cli: &Cli) -> Self {
        match (cli.quiet, cli.verbose) {
            (true, _) => Verbosity::Quiet,
            (_, true) => Verbosity::Verbose,
            _ => Verbosity::Normal,
        }
    }

    /// Prints a progress note on stderr in verbose mode.
    fn note(self, text: impl FnOnce() -> String) {
        if self == Verbosity::Verbose {
            eprintln!("lumiere: {}", text());
        }
    }
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene file to an image (PNG, or PFM / EXR float radiance).
    #[command(
        after_help = "Examples:\n  lumiere render scenes/reference.toml -o reference.png\n  lumiere render scenes/reference.toml -o small.png --width 200 --height 150 --spp 1 --stats\n  lumiere render scenes/prism.toml -o prism.exr --depth 20          # float radiance\n  lumiere render scenes/reference.toml -o part0.shard --shard 0/4    # a quarter, for merge\n  lumiere render scenes/reference.toml -o chapter.png --reference   # the chapter's tracer: same bytes\n\nExit codes: 0 ok, 1 the image could not be written (disk full), 2 bad input (scene, option, output path), 130 / 143 / 129 stopped by Ctrl-C / SIGTERM / SIGHUP (nothing written)."
    )]
    Render(render::RenderArgs),
    /// Compare your image with the oracle's: level differences and their percentiles, FLIP,
    /// object edges apart (--scene), the worst pixels with their probe command.
    #[command(
        after_help = "Examples:\n  lumiere compare mine.png figures/lighting/01-ambient.png\n  lumiere compare mine.ppm oracle.png --scene scenes/reference.toml --tolerance 8 --max-fraction 0.001\n  lumiere compare mine.png ref.png --flip-heatmap flip.png --heatmap diff.png --json\n\nReads PNG, PPM / PGM / PBM, PFM, EXR, JPEG, BMP and TGA; PFM and EXR are clamped and quantised as lumiere's film does.\nExit codes: 0 the rule holds, 1 the images differ beyond the rule (--tolerance, --max-fraction, --max-flip), 2 bad input (images, sizes, options, scene, output paths)."
    )]
    Compare(compare::CompareArgs),
    /// What is most likely wrong in your image: gains per term and a catalogue of named
    /// mistakes rendered and ranked against it.
    #[command(
        override_usage = "lumiere diagnose [OPTIONS] <SCENE> <IMAGE>...\n       lumiere diagnose --list [--json]",
        after_help = "Examples:\n  lumiere diagnose scenes/reference.toml mine.png\n  lumiere diagnose scenes/prism.toml mine.ppm --convention sample_position=center --report diagnosis --json\n\nReads PNG, PPM / PGM / PBM, PFM, EXR, JPEG, BMP and TGA; the scene is rendered at the image's size with the given settings.\nExit codes: 0 a diagnosis was made (whatever it says), 2 bad input (image, scene, options, report folder)."
    )]
    Diagnose(diagnose::DiagnoseArgs),
    /// Regenerate the course's figures (all sets when none is named).
    #[command(
        after_help = "Examples:\n  lumiere figures                       # every set into figures/\n  lumiere figures lighting mirrors      # two sets\n  lumiere figures --scale 0.25 --out /tmp/preview\n  lumiere figures --check               # the committed files against a fresh render\n  lumiere figures --list\n\nThe sets are read from scenes/figures/<set>/ (set.toml and one scene file per figure). Each set writes <out>/<set>/NN-name.png (with its provenance in tEXt chunks), manifest.json and contact-sheet.png; <out>/index.html is a gallery of the sets in <out>; the run's times go to <out>/timings.json.\nCtrl-C, SIGTERM or SIGHUP leaves each set wholly old or wholly new. One run at a time writes into an output folder.\nExit codes: 0 ok, 1 a figure could not be written (disk full) or differs (--check), 2 bad input (option, output folder, or another run writing into it), 130 / 143 / 129 stopped by Ctrl-C / SIGTERM / SIGHUP."
    )]
    Figures(figures::FiguresArgs),
    /// Assemble the shard files of a split render (`render --shard K/N`) into one image,
    /// bit-identical to a one-machine render.
    #[command(
        after_help = "Example:\n  for k in 0 1 2; do lumiere render scenes/reference.toml --shard $k/3 -o part$k.shard; done\n  lumiere merge part0.shard part1.shard part2.shard -o reference.png\n\nExit codes: 0 ok, 1 write failed (disk full), 2 bad or incomplete shards or output path, 130 / 143 / 129 stopped by Ctrl-C / SIGTERM / SIGHUP (nothing written)."
    )]
    Merge(merge::MergeArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    #[command(after_help = "Example:\n  lumiere completions bash > ~/.local/share/bash-completion/completions/lumiere")]
    Completions(CompletionsArgs),
    /// Why is this pixel this colour? Print the whole ray tree of one pixel.
    #[command(
        after_help = "Examples:\n  lumiere probe scenes/reference.toml --pixel 400,300\n  lumiere probe scenes/prism.toml --pixel 80,60 --width 160 --height 120 --sample 0 --json\n\nExit codes: 0 ok, 2 bad input (scene, pixel outside the image, sample index)."
    )]
    Probe(probe::ProbeArgs),
    /// Write accepted | new | difference sheets and a review page for pending insta image snapshots.
    #[command(
        after_help = "Examples:\n  lumiere review-snapshots\n  lumiere review-snapshots --dir snapshots --out target/review\n\nSheets go to <out>/snapshots/; <out>/index.html lists them with the figure changes of the last `lumiere figures --check --review <out>`.\nExit codes: 0 ok (whatever changed), 1 a sheet could not be written (disk full), 2 bad input (folders, images)."
    )]
    ReviewSnapshots(review::ReviewArgs),
    /// Translate a scene file between lumiere's TOML format and SIMRenderer's.
    #[command(
        after_help = "Examples:\n  lumiere convert scenes/reference.toml -o reference.txt      # to SIMRenderer\n  lumiere convert lab.txt -o lab.toml                          # to TOML\n  lumiere convert lab.txt -o lab.toml --lenient                # past SIMRenderer's soft errors\n\nThe output is TOML when its name ends in .toml, else SIMRenderer (or as --to says). What the output's format cannot say (a SIMRenderer file has no spot, area light or rectangle) is refused by name, and nothing is written. The output is read back: what does not give the same scene to the bit is named in a warning.\nExit codes: 0 ok, 1 the file could not be written (disk full), 2 bad input (scene, a thing the output's format cannot say, output path)."
    )]
    Convert(convert::ConvertArgs),
    /// Numerical stress campaign: hard rays against every shape, checked against double-double references.
    #[command(after_help = "Example:\n  lumiere stress --rays 2000 --seed 7")]
    Stress(stress::StressArgs),
    /// Measurement studies: render time against error of soft shadows (N, placement, mode) and of caustics (photons, radius).
    #[command(
        after_help = "Examples:\n  lumiere study soft-shadows --width 200 --height 150 --out /tmp/study\n  lumiere study caustics --out /tmp/study-caustics\n\nSee `lumiere study soft-shadows --help` and `lumiere study caustics --help`."
    )]
    Study(study::StudyArgs),
}

#[derive(Args, Debug)]
pub struct CompletionsArgs {
    /// The shell.
    pub shell: clap_complete::Shell,
}

/// Values that replace the scene file's own.
#[derive(Args, Debug, Default, Clone)]
pub struct Overrides {
    #[arg(
        long,
        help = format!("Image width in pixels, in [1, {MAX_DIMENSION}]"),
        value_parser = numbers::dimension,
        allow_negative_numbers = true
    )]
    pub width: Option<u32>,
    #[arg(
        long,
        help = format!("Image height in pixels, in [1, {MAX_DIMENSION}]"),
        value_parser = numbers::dimension,
        allow_negative_numbers = true
    )]
    pub height: Option<u32>,
    #[arg(
        long,
        help = format!(
            "Samples per pixel, in [1, {MAX_SAMPLES}]: one in each cell of the pixel's most nearly square grid (6: 2 columns by 3 rows)"
        ),
        value_parser = numbers::samples,
        allow_negative_numbers = true
    )]
    pub spp: Option<u32>,
    #[arg(
        long,
        help = format!("Seed of every random stream, in [0, {}]", u64::MAX),
        value_parser = numbers::seed,
        allow_negative_numbers = true
    )]
    pub seed: Option<u64>,
    #[arg(
        long,
        help = format!("Recursion depth, in [1, {MAX_DEPTH}] (1 = no secondary rays)"),
        value_parser = numbers::depth,
        allow_negative_numbers = true
    )]
    pub depth: Option<u32>,
    #[arg(
        long,
        help = format!(
            "Adaptive depth control threshold in 8-bit levels, in [0, {}] (0 = off)",
            limits::short(MAX_ADAPTIVE_THRESHOLD)
        ),
        value_parser = numbers::adaptive_threshold,
        allow_negative_numbers = true
    )]
    pub adaptive_threshold: Option<f64>,
    /// Conventions where the chapter and SIMRenderer differ: a preset, `chapter` or
    /// `simrenderer` (see scenes/README.md, "Conventions").
    #[arg(long, value_name = "PRESET")]
    pub conventions: Option<String>,
    /// One convention set after the preset, e.g. `shadow_filter=kt_color` (repeatable).
    #[arg(long, value_name = "KEY=VALUE")]
    pub convention: Vec<String>,
    #[command(flatten)]
    pub reading: Reading,
    /// Intersection core: the linear scan, the BVH, or auto (the BVH from a measured number
    /// of objects on). The image does not depend on it, only the time.
    #[arg(long, value_parser = accel_values(), default_value = "auto")]
    pub accel: AccelChoice,
}

/// How a scene file is read.
#[derive(Args, Debug, Default, Clone)]
pub struct Reading {
    /// The scene file's format (default: TOML when its name ends in .toml, else
    /// SIMRenderer when its first keyword opens one of SIMRenderer's blocks).
    #[arg(long, value_parser = format_values())]
    pub format: Option<Format>,
    /// SIMRenderer files: go on past an error as SIMRenderer does (the line skipped, the
    /// value before it kept, the object dropped), printing it as a warning.
    #[arg(long)]
    pub lenient: bool,
}

impl Overrides {
    /// The scene settings these options replace.
    fn settings(&self) -> scene::Overrides {
        scene::Overrides {
            width: self.width,
            height: self.height,
            spp: self.spp,
            seed: self.seed,
            depth: self.depth,
            adaptive_threshold: self.adaptive_threshold,
            conventions: self.conventions.clone(),
            convention: self.convention.clone(),
        }
    }
}

/// A clap value parser for a library choice known by name: `values` are its names with
/// their help lines, and the chosen name is parsed back with `FromStr`.
fn named<T, H>(values: impl IntoIterator<Item = (&'static str, H)>) -> impl TypedValueParser<Value = T>
where
    T: FromStr<Err = String> + Clone + Send + Sync + 'static,
    H: Into<StyledStr>,
{
    PossibleValuesParser::new(
        values
            .into_iter()
            .map(|(name, help)| PossibleValue::new(name).help(help)),
    )
    .try_map(|name| name.parse::<T>())
}

/// `--accel`'s values.
fn accel_values() -> impl TypedValueParser<Value = AccelChoice> {
    named(AccelChoice::ALL.map(|c| (c.name(), c.help())))
}

/// `--format`'s values.
fn format_values() -> impl TypedValueParser<Value = Format> {
    named([
        ("toml", "lumiere's TOML scene format (scenes/README.md)"),
        ("simrenderer", "SIMRenderer's keyword blocks (docs/simrenderer.md)"),
    ])
}

/// `--no-skip`'s values.
fn skip_values() -> impl TypedValueParser<Value = Skip> {
    named(Skip::ALL.map(|s| (s.name(), s.help())))
}

pub fn run(cli: Cli) -> Result<(), CliError> {
    let v = Verbosity::of(&cli);
    match cli.command {
        Command::Render(args) => render::run(&args, v),
        Command::Compare(args) => compare::run(&args),
        Command::Diagnose(args) => diagnose::run(&args),
        Command::Figures(args) => figures::run(&args, v),
        Command::Merge(args) => merge::run(&args, v),
        Command::Completions(args) => {
            clap_complete::generate(
                args.shell,
                &mut <Cli as clap::CommandFactory>::command(),
                "lumiere",
                &mut std::io::stdout(),
            );
            Ok(())
        }
        Command::Probe(args) => probe::run(&args),
        Command::Convert(args) => convert::run(&args, v),
        Command::ReviewSnapshots(args) => review::run(&args),
        Command::Stress(args) => stress::run(&args),
        Command::Study(args) => study::run(&args, v),
    }
}

/// `noun` (a regular English noun) as `n` of them are said: `1 object`, `2 objects`,
/// `0 objects`, without the number.
fn noun_for(n: usize, noun: &str) -> String {
    if n == 1 { noun.to_string() } else { format!("{noun}s") }
}

/// Loads a scene file and applies overrides; errors are bad input. A SIMRenderer file's
/// own settings (`pixel_coordinate`, the clipping planes) apply over `--conventions`'
/// preset, then each `--convention`.
fn load_scene(path: &Path, overrides: &Overrides) -> Result<Scene, CliError> {
    let mut settings = overrides.settings();
    let preset = preset(settings.conventions.as_deref())?;
    let loaded = read_scene(path, &overrides.reading, preset)?;
    if loaded.format == Format::SimRenderer {
        settings.conventions = None;
    }
    let mut scene = loaded.scene;
    settings.apply(&mut scene).map_err(CliError::BadInput)?;
    Ok(scene)
}

/// The conventions preset named by `--conventions`, if any.
fn preset(name: Option<&str>) -> Result<Option<Conventions>, CliError> {
    name.map(Conventions::preset)
        .transpose()
        .map_err(|m| CliError::BadInput(format!("--conventions: {m}")))
}

/// Reads a scene file as `reading` says (SIMRenderer files over `conventions`), printing
/// the reader's warnings on stderr; errors are bad input.
fn read_scene(path: &Path, reading: &Reading, conventions: Option<Conventions>) -> Result<Loaded, CliError> {
    let options = LoadOptions {
        format: reading.format,
        lenient: reading.lenient,
        conventions,
    };
    let loaded = scene::load_with(path, &options).map_err(|e| CliError::BadInput(e.to_string()))?;
    for w in &loaded.warnings {
        eprintln!("lumiere: warning: {w}");
    }
    Ok(loaded)
}

/// Checks that `output` can be written in a known format without touching `input`.
fn check_output(output: &Path, input: &Path) -> Result<lumiere::output::Format, CliError> {
    let format = lumiere::output::Format::of(output).map_err(CliError::BadInput)?;
    check_output_path(output, input)?;
    Ok(format)
}

/// Checks, before any work, that `output` is not `input`, is not a directory, and that its
/// directory exists. Whether the directory can be written is known only by writing: a
/// write refused there is bad input too (see [`CliError::from`]).
fn check_output_path(output: &Path, input: &Path) -> Result<(), CliError> {
    let bad = |m: String| Err(CliError::BadInput(format!("{}: {m}", output.display())));
    if let (Ok(a), Ok(b)) = (output.canonicalize(), input.canonicalize())
        && a == b
    {
        return bad("the output would overwrite the input".into());
    }
    if output.is_dir() {
        return bad("the output is a directory; name a file in it".into());
    }
    let parent = output
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if parent.exists() && !parent.is_dir() {
        return bad(format!("{} is not a directory", parent.display()));
    }
    if !parent.is_dir() {
        return bad(format!("the output directory {} does not exist", parent.display()));
    }
    Ok(())
}

/// `path` made absolute, its links followed, whether or not it exists (its folder must):
/// two paths of one file resolve alike.
pub(super) fn resolved(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = path.canonicalize() {
        return Some(p);
    }
    let parent = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    Some(parent.canonicalize().ok()?.join(path.file_name()?))
}

/// Checks, before any work, that the output folder `dir` (of option `option`) can be made
/// or written into: neither it nor a folder above it is a file.
fn check_out_folder(dir: &Path, option: &str) -> Result<(), CliError> {
    let file = dir
        .ancestors()
        .filter(|a| !a.as_os_str().is_empty())
        .find(|a| a.exists())
        .filter(|a| !a.is_dir());
    match file {
        Some(file) => Err(CliError::BadInput(format!(
            "{option}: {} is a file, not a folder",
            file.display()
        ))),
        None => Ok(()),
    }
}

/// Runs `f` on a rayon pool of `threads` workers (all cores when `None`), a number
/// `--threads`' parser ([`numbers::threads`]) has checked.
fn with_threads<T: Send>(threads: Option<usize>, f: impl FnOnce() -> T + Send) -> Result<T, CliError> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        builder = builder.num_threads(n);
    }
    let pool = builder
        .build()
        .map_err(|e| CliError::Failed(format!("cannot start worker threads: {e}")))?;
    Ok(pool.install(f))
}
