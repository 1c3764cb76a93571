//! The command line: clap types and dispatch. No rendering logic lives here.

use crate::film::write_atomic;
use crate::limits;
use crate::render::{RenderStats, render};
use crate::scene::{self, Scene, World};
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

/// Exit codes: 0 success, 1 the work failed (render, write, comparison), 2 bad input.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// The input was wrong: scene file, option value, paths.
    #[error("{0}")]
    BadInput(String),
    /// The input was fine but the work failed (e.g. the output could not be written).
    #[error("{0}")]
    Failed(String),
}

impl CliError {
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::BadInput(_) => 2,
            CliError::Failed(_) => 1,
        }
    }
}

#[derive(Parser, Debug)]
#[command(
    name = "lumiere",
    version,
    about = "A seeded, deterministic Whitted ray tracer for the course on ray-traced illumination"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene file to a PNG image.
    #[command(
        after_help = "Examples:\n  lumiere render scenes/reference.toml -o reference.png\n  lumiere render scenes/reference.toml -o small.png --width 200 --height 150 --spp 1\n\nExit codes: 0 ok, 1 render failed, 2 bad input."
    )]
    Render(RenderArgs),
    /// Numerical stress campaign: hard rays against every shape, checked against double-double references.
    #[command(after_help = "Example:\n  lumiere stress --rays 2000 --seed 7")]
    Stress(crate::stress::StressArgs),
}

/// Values that replace the scene file's own.
#[derive(Args, Debug, Default, Clone)]
pub struct Overrides {
    /// Image width in pixels.
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels.
    #[arg(long)]
    pub height: Option<u32>,
    /// Samples per pixel: a perfect square (1, 4, 9, ...), an n x n stratified grid.
    #[arg(long)]
    pub spp: Option<u32>,
    /// Seed of every random stream.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Recursion depth (1 = no secondary rays).
    #[arg(long)]
    pub depth: Option<u32>,
    /// Adaptive depth control threshold in 8-bit levels (0 = off).
    #[arg(long)]
    pub adaptive_threshold: Option<f64>,
}

impl Overrides {
    /// Applies the overrides to a loaded scene, checking each against its limits.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), CliError> {
        let bad = |flag: &str, m: String| CliError::BadInput(format!("--{flag}: {m}"));
        let s = &mut scene.settings;
        if let Some(w) = self.width {
            limits::check_dimension(w).map_err(|m| bad("width", m))?;
            s.width = w;
        }
        if let Some(h) = self.height {
            limits::check_dimension(h).map_err(|m| bad("height", m))?;
            s.height = h;
        }
        limits::check_pixel_count(s.width, s.height).map_err(|m| bad("width/--height", m))?;
        if let Some(n) = self.spp {
            limits::check_samples(n).map_err(|m| bad("spp", m))?;
            s.samples_per_pixel = n;
        }
        if let Some(seed) = self.seed {
            s.seed = seed;
        }
        if let Some(d) = self.depth {
            limits::check_depth(d).map_err(|m| bad("depth", m))?;
            s.depth = d;
        }
        if let Some(t) = self.adaptive_threshold {
            if !(0.0..=255.0).contains(&t) {
                return Err(bad(
                    "adaptive-threshold",
                    format!("must be in [0, 255] levels, got {t}"),
                ));
            }
            s.adaptive_threshold = t;
        }
        Ok(())
    }
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The scene file (TOML; see scenes/README.md).
    pub scene: PathBuf,
    /// Output PNG path.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub overrides: Overrides,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress bar.
    #[arg(short, long)]
    pub quiet: bool,
    /// Print ray counts and time after rendering.
    #[arg(long)]
    pub stats: bool,
}

pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Render(args) => render_command(&args),
        Command::Stress(args) => crate::stress::run(&args),
    }
}

/// Loads a scene file and applies overrides; errors are bad input.
pub fn load_scene(path: &Path, overrides: &Overrides) -> Result<Scene, CliError> {
    let mut scene = scene::load(path).map_err(|e| CliError::BadInput(e.to_string()))?;
    overrides.apply(&mut scene)?;
    Ok(scene)
}

/// Checks that `output` can be written as a PNG without touching `input`.
pub fn check_output(output: &Path, input: &Path) -> Result<(), CliError> {
    let ext = output.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if ext.as_deref() != Some("png") {
        return Err(CliError::BadInput(format!(
            "{}: the output must be a .png file",
            output.display()
        )));
    }
    if let (Ok(a), Ok(b)) = (output.canonicalize(), input.canonicalize())
        && a == b
    {
        return Err(CliError::BadInput(format!(
            "{}: the output would overwrite the input scene",
            output.display()
        )));
    }
    let parent = output
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(CliError::BadInput(format!(
            "{}: the output directory {} does not exist",
            output.display(),
            parent.display()
        )));
    }
    Ok(())
}

/// Runs `f` on a rayon pool of `threads` workers (all cores when `None`).
pub fn with_threads<T: Send>(threads: Option<usize>, f: impl FnOnce() -> T + Send) -> Result<T, CliError> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        if n == 0 || n > 1024 {
            return Err(CliError::BadInput(format!("--threads: must be in [1, 1024], got {n}")));
        }
        builder = builder.num_threads(n);
    }
    let pool = builder
        .build()
        .map_err(|e| CliError::Failed(format!("cannot start worker threads: {e}")))?;
    Ok(pool.install(f))
}

fn progress_bar(rows: u64, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(rows);
    if let Ok(style) = ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} rows") {
        bar.set_style(style);
    }
    bar
}

fn render_command(args: &RenderArgs) -> Result<(), CliError> {
    let scene = load_scene(&args.scene, &args.overrides)?;
    check_output(&args.output, &args.scene)?;
    let world = World::new(&scene);
    let bar = progress_bar(scene.settings.height as u64, args.quiet);
    let (film, stats) = with_threads(args.threads, || render(&world, &|| bar.inc(1)))?;
    bar.finish_and_clear();
    let png = film
        .encode_png()
        .map_err(|e| CliError::Failed(format!("cannot encode the PNG: {e}")))?;
    write_atomic(&args.output, &png)
        .map_err(|e| CliError::Failed(format!("{}: cannot write the image: {e}", args.output.display())))?;
    if args.stats {
        print!("{}", stats_report(&stats));
    }
    if stats.counts.non_finite > 0 {
        eprintln!(
            "warning: {} samples were NaN or infinite and were written as black",
            stats.counts.non_finite
        );
    }
    Ok(())
}

/// Human-readable ray counts and time.
pub fn stats_report(stats: &RenderStats) -> String {
    let c = &stats.counts;
    format!(
        "time          {:.3} s\ncamera rays   {}\nshadow rays   {}\nreflection    {}\nrefraction    {}\ntotal rays    {}\ntotal internal reflections {}\nadaptive cutoffs {}\nnon-finite samples {}\n",
        stats.elapsed.as_secs_f64(),
        c.camera,
        c.shadow,
        c.reflection,
        c.refraction,
        c.total_rays(),
        c.total_internal_reflections,
        c.adaptive_cutoffs,
        c.non_finite
    )
}
