//! The command line: clap types and dispatch. No rendering logic lives here.

use crate::accel::AccelChoice;
use crate::film::write_atomic;
use crate::limits;
use crate::render::{RenderStats, render_rows};
use crate::scene::{self, Scene};
use crate::world::World;
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

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
        after_help = "Examples:\n  lumiere render scenes/reference.toml -o reference.png\n  lumiere render scenes/reference.toml -o small.png --width 200 --height 150 --spp 1 --stats\n  lumiere render scenes/prism.toml -o prism.exr --depth 20          # float radiance\n  lumiere render scenes/reference.toml -o part0.shard --shard 0/4    # a quarter, for merge\n\nExit codes: 0 ok, 1 render failed, 2 bad input, 130 interrupted (nothing written)."
    )]
    Render(RenderArgs),
    /// Compare two images: max and RMS difference, PSNR, differing pixels, heat-map.
    #[command(
        after_help = "Examples:\n  lumiere compare mine.png figures/lighting/01-ambient.png\n  lumiere compare mine.png ref.png --tolerance 1 --heatmap diff.png --json\n\nExit codes: 0 within tolerance, 1 some pixel differs by more than the tolerance, 2 bad input."
    )]
    Compare(CompareArgs),
    /// Regenerate the course's figures (all sets when none is named).
    #[command(
        after_help = "Examples:\n  lumiere figures                       # every set into figures/\n  lumiere figures lighting mirrors      # two sets\n  lumiere figures --scale 0.25 --out /tmp/preview\n  lumiere figures --list\n\nEach set writes <out>/<set>/NN-name.png, manifest.json and contact-sheet.png; <out>/index.html is a gallery of all sets.\nCtrl-C leaves each set wholly old or wholly new.\nExit codes: 0 ok, 1 a figure could not be written, 2 bad input, 130 interrupted."
    )]
    Figures(FiguresArgs),
    /// Assemble the shard files of a split render (`render --shard K/N`) into one image,
    /// bit-identical to a one-machine render.
    #[command(
        after_help = "Example:\n  for k in 0 1 2; do lumiere render scenes/reference.toml --shard $k/3 -o part$k.shard; done\n  lumiere merge part0.shard part1.shard part2.shard -o reference.png\n\nExit codes: 0 ok, 1 write failed, 2 bad or incomplete shards."
    )]
    Merge(MergeArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    #[command(after_help = "Example:\n  lumiere completions bash > ~/.local/share/bash-completion/completions/lumiere")]
    Completions(CompletionsArgs),
    /// Why is this pixel this colour? Print the whole ray tree of one pixel.
    #[command(
        after_help = "Examples:\n  lumiere probe scenes/reference.toml --pixel 400,300\n  lumiere probe scenes/prism.toml --pixel 80,60 --width 160 --height 120 --sample 0 --json\n\nExit codes: 0 ok, 2 bad input (scene, pixel outside the image, sample index)."
    )]
    Probe(crate::probe::ProbeArgs),
    /// Write old | new | difference sheets for pending insta image snapshots.
    #[command(
        after_help = "Examples:\n  lumiere review-snapshots\n  lumiere review-snapshots --dir snapshots --out target/snapshot-review\n\nExit codes: 0 ok (whatever changed), 1 a sheet could not be written, 2 bad input."
    )]
    ReviewSnapshots(crate::review::ReviewArgs),
    /// Numerical stress campaign: hard rays against every shape, checked against double-double references.
    #[command(after_help = "Example:\n  lumiere stress --rays 2000 --seed 7")]
    Stress(crate::stress::StressArgs),
    /// Measurement studies: soft shadows' render time against error (N, placement, mode).
    #[command(
        after_help = "Example:\n  lumiere study soft-shadows --width 200 --height 150 --out /tmp/study\n\nSee `lumiere study soft-shadows --help`."
    )]
    Study(crate::study::StudyArgs),
}

#[derive(Args, Debug)]
pub struct CompletionsArgs {
    /// The shell.
    pub shell: clap_complete::Shell,
}

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

#[derive(Args, Debug)]
pub struct CompareArgs {
    /// Your image.
    pub a: PathBuf,
    /// The reference image (same size).
    pub b: PathBuf,
    /// Largest per-channel difference (8-bit levels) that still counts as equal.
    #[arg(long, default_value_t = 0)]
    pub tolerance: u8,
    /// Write a heat-map of the differences (black equal, blue small, red, white >= 16 levels).
    #[arg(long)]
    pub heatmap: Option<PathBuf>,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
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
    /// Intersection core: the linear scan, the BVH, or auto (the BVH from a measured number
    /// of objects on). The image does not depend on it, only the time.
    #[arg(long, value_enum, default_value_t = AccelChoice::Auto)]
    pub accel: AccelChoice,
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
    /// Output image: .png (8-bit, clamped), .pfm or .exr (32-bit float radiance, unclamped).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Encode PNG output with the sRGB transfer function (default: linear, as the course).
    #[arg(long)]
    pub srgb: bool,
    #[command(flatten)]
    pub overrides: Overrides,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print ray counts, work skipped by reason and time by phase after rendering.
    #[arg(long)]
    pub stats: bool,
    /// Switch a shortcut off (repeatable or comma-separated), to measure what it saves: the
    /// image does not change, only ray counts and time.
    #[arg(long, value_name = "NAME", value_delimiter = ',')]
    pub no_skip: Vec<crate::skips::Skip>,
    /// Print the statistics as JSON on stdout (implies --stats).
    #[arg(long)]
    pub json: bool,
    /// Render only shard K of N (0-based rows [K H / N, (K + 1) H / N)) into a shard file
    /// for `lumiere merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<crate::shard::ShardSpec>,
}

#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The shard files (any order), all N of one render.
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// Output image: .png, .pfm or .exr.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Encode PNG output with the sRGB transfer function.
    #[arg(long)]
    pub srgb: bool,
}

pub fn run(cli: Cli) -> Result<(), CliError> {
    let v = Verbosity::of(&cli);
    match cli.command {
        Command::Render(args) => render_command(&args, v),
        Command::Compare(args) => compare_command(&args),
        Command::Figures(args) => figures_command(&args, v),
        Command::Merge(args) => merge_command(&args, v),
        Command::Completions(args) => {
            clap_complete::generate(
                args.shell,
                &mut <Cli as clap::CommandFactory>::command(),
                "lumiere",
                &mut std::io::stdout(),
            );
            Ok(())
        }
        Command::Probe(args) => crate::probe::probe_command(&args),
        Command::ReviewSnapshots(args) => crate::review::review_command(&args),
        Command::Stress(args) => crate::stress::run(&args),
        Command::Study(args) => crate::study::study_command(&args, v),
    }
}

/// Loads a scene file and applies overrides; errors are bad input.
pub fn load_scene(path: &Path, overrides: &Overrides) -> Result<Scene, CliError> {
    let mut scene = scene::load(path).map_err(|e| CliError::BadInput(e.to_string()))?;
    overrides.apply(&mut scene)?;
    Ok(scene)
}

/// Checks that `output` can be written in a known format without touching `input`.
pub fn check_output(output: &Path, input: &Path) -> Result<crate::output::Format, CliError> {
    let format = crate::output::Format::of(output).map_err(CliError::BadInput)?;
    check_output_path(output, input)?;
    Ok(format)
}

/// Checks that `output` is not `input` and that its directory exists.
pub fn check_output_path(output: &Path, input: &Path) -> Result<(), CliError> {
    if let (Ok(a), Ok(b)) = (output.canonicalize(), input.canonicalize())
        && a == b
    {
        return Err(CliError::BadInput(format!(
            "{}: the output would overwrite the input",
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

/// Set by Ctrl-C; renders stop at the next row and write nothing.
static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

fn render_command(args: &RenderArgs, v: Verbosity) -> Result<(), CliError> {
    let start = std::time::Instant::now();
    let scene = load_scene(&args.scene, &args.overrides)?;
    let loaded = start.elapsed();
    let format = match args.shard {
        None => Some(check_output(&args.output, &args.scene)?),
        Some(_) => {
            crate::shard::check_path(&args.output).map_err(CliError::BadInput)?;
            check_output_path(&args.output, &args.scene)?;
            None
        }
    };
    let mut world = World::with_accel(&scene, args.overrides.accel);
    world.skips = args.no_skip.iter().fold(world.skips, |s, &k| s.without(k));
    let built = start.elapsed();
    let rows = args
        .shard
        .map_or(0..scene.settings.height, |s| s.rows(scene.settings.height));
    let s = &scene.settings;
    v.note(|| {
        format!(
            "{}: {} objects, {} lights; {} x {} pixels, {} samples, depth {}, seed {}; rows {:?}",
            args.scene.display(),
            scene.objects.len(),
            scene.lights.len(),
            s.width,
            s.height,
            s.samples_per_pixel,
            s.depth,
            s.seed,
            rows
        )
    });
    let bar = progress_bar(rows.len() as u64, v == Verbosity::Quiet);
    // If the handler cannot be installed (one already is), Ctrl-C keeps its default
    // behaviour, which also leaves no partial output: files are only written at the end.
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, std::sync::atomic::Ordering::Relaxed));
    let (pixels, stats) = with_threads(args.threads, || {
        render_rows(&world, rows, &|| bar.inc(1), Some(&INTERRUPTED))
    })?;
    bar.finish_and_clear();
    if INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
        return Err(CliError::Interrupted);
    }
    let bytes = match (args.shard, format) {
        (Some(spec), _) => crate::shard::encode(&scene, spec, &pixels),
        (None, Some(format)) => {
            let film = crate::film::Film {
                width: scene.settings.width,
                height: scene.settings.height,
                pixels,
            };
            crate::output::encode(&film, format, args.srgb)
                .map_err(|e| CliError::Failed(format!("cannot encode the image: {e}")))?
        }
        (None, None) => unreachable!("format is checked when there is no shard"),
    };
    write_atomic(&args.output, &bytes)
        .map_err(|e| CliError::Failed(format!("{}: cannot write the image: {e}", args.output.display())))?;
    let phases = Phases {
        load: loaded.as_secs_f64(),
        build: (built - loaded).as_secs_f64(),
        accel: AccelReport::of(&world),
        render: stats.elapsed.as_secs_f64(),
        write: (start.elapsed() - built - stats.elapsed).as_secs_f64(),
    };
    v.note(|| {
        format!(
            "wrote {} ({} bytes) in {:.3} s",
            args.output.display(),
            bytes.len(),
            stats.elapsed.as_secs_f64()
        )
    });
    if args.json {
        println!("{}", stats_json(&stats, &phases));
    } else if args.stats {
        print!("{}", stats_report(&stats, &phases));
    }
    if stats.counts.non_finite > 0 {
        eprintln!(
            "warning: {} samples were NaN or infinite and were written as black",
            stats.counts.non_finite
        );
    }
    Ok(())
}

/// Wall time of each phase of a render command, in seconds.
pub struct Phases {
    /// Reading and validating the scene file.
    pub load: f64,
    /// Building the world (acceleration structure, light points, bounds).
    pub build: f64,
    /// The acceleration structure, part of `build`.
    pub accel: AccelReport,
    /// Tracing every pixel.
    pub render: f64,
    /// Encoding and writing the output.
    pub write: f64,
}

/// The intersection core a render used: its name, size and build time.
pub struct AccelReport {
    pub name: &'static str,
    pub objects: usize,
    pub bytes: usize,
    pub seconds: f64,
}

impl AccelReport {
    pub fn of(world: &World) -> Self {
        AccelReport {
            name: world.accel().name(),
            objects: world.scene.objects.len(),
            bytes: world.accel().bytes(),
            seconds: world.accel_seconds,
        }
    }
}

/// Work each shortcut saved, by name, as JSON.
fn skipped_json(c: &crate::trace::RayCounts) -> serde_json::Value {
    crate::skips::Skip::ALL
        .iter()
        .map(|&s| (s.name().to_string(), serde_json::json!(c.saved.get(s))))
        .collect::<serde_json::Map<_, _>>()
        .into()
}

/// The statistics as JSON, for programs.
pub fn stats_json(stats: &RenderStats, phases: &Phases) -> String {
    let c = &stats.counts;
    serde_json::json!({
        "seconds": stats.elapsed.as_secs_f64(),
        "phases": { "load": phases.load, "build": phases.build, "render": phases.render, "write": phases.write },
        "accel": {
            "core": phases.accel.name,
            "objects": phases.accel.objects,
            "bytes": phases.accel.bytes,
            "build_seconds": phases.accel.seconds,
        },
        "skipped": skipped_json(c),
        "rays": {
            "camera": c.camera,
            "shadow": c.shadow,
            "reflection": c.reflection,
            "refraction": c.refraction,
            "total": c.total_rays(),
        },
        "total_internal_reflections": c.total_internal_reflections,
        "adaptive_cutoffs": c.adaptive_cutoffs,
        "non_finite_samples": c.non_finite,
    })
    .to_string()
}

fn merge_command(args: &MergeArgs, v: Verbosity) -> Result<(), CliError> {
    let format = check_output(&args.output, &args.shards[0])?;
    let mut shards = Vec::new();
    for path in &args.shards {
        let name = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|e| CliError::BadInput(format!("{name}: cannot read: {e}")))?;
        let (header, pixels) = crate::shard::decode(&bytes, &name).map_err(CliError::BadInput)?;
        shards.push((name, header, pixels));
    }
    let film = crate::shard::merge(shards).map_err(CliError::BadInput)?;
    v.note(|| {
        format!(
            "merged {} shards into {} x {}",
            args.shards.len(),
            film.width,
            film.height
        )
    });
    let bytes = crate::output::encode(&film, format, args.srgb)
        .map_err(|e| CliError::Failed(format!("cannot encode the image: {e}")))?;
    write_atomic(&args.output, &bytes)
        .map_err(|e| CliError::Failed(format!("{}: cannot write the image: {e}", args.output.display())))
}

/// Human-readable ray counts, skipped work and time by phase.
pub fn stats_report(stats: &RenderStats, phases: &Phases) -> String {
    let c = &stats.counts;
    let mut skipped = String::from("skipped (switch off with --no-skip NAME):\n");
    for s in crate::skips::Skip::ALL {
        skipped += &format!("  {:<18} {:>14}  {}\n", s.name(), c.saved.get(s), s.unit());
    }
    let a = &phases.accel;
    let phases = format!(
        "time by phase: load {:.3} s, build {:.3} s, render {:.3} s, write {:.3} s\n\
         intersection core: {} over {} objects, {} bytes ({:.1} bytes/object), built in {:.3} s\n",
        phases.load,
        phases.build,
        phases.render,
        phases.write,
        a.name,
        a.objects,
        a.bytes,
        a.bytes as f64 / a.objects.max(1) as f64,
        a.seconds
    );
    phases
        + &skipped
        + &format!(
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

fn compare_command(args: &CompareArgs) -> Result<(), CliError> {
    use crate::compare::{compare_rgb8, heat_map, load_rgb8};
    let (wa, ha, a) = load_rgb8(&args.a).map_err(CliError::BadInput)?;
    let (wb, hb, b) = load_rgb8(&args.b).map_err(CliError::BadInput)?;
    if (wa, ha) != (wb, hb) {
        return Err(CliError::BadInput(format!(
            "the images differ in size: {} is {wa} x {ha}, {} is {wb} x {hb}",
            args.a.display(),
            args.b.display()
        )));
    }
    let c = compare_rgb8(&a, &b, wa, ha, args.tolerance);
    if let Some(path) = &args.heatmap {
        if check_output(path, &args.a)? != crate::output::Format::Png {
            return Err(CliError::BadInput(format!(
                "{}: the heat-map must be a .png",
                path.display()
            )));
        }
        let png = crate::film::encode_png(wa, ha, &heat_map(&a, &b, 16))
            .map_err(|e| CliError::Failed(format!("cannot encode the heat-map: {e}")))?;
        write_atomic(path, &png).map_err(|e| CliError::Failed(format!("{}: cannot write: {e}", path.display())))?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&c).unwrap_or_default());
    } else {
        let total = wa as u64 * ha as u64;
        println!("size               {wa} x {ha}");
        println!("max difference     {} levels", c.max_diff);
        println!("RMS difference     {:.4} levels", c.rms);
        println!("PSNR               {:.2} dB", c.psnr_db);
        println!(
            "differing pixels   {} of {total} ({:.4} %) beyond {} levels",
            c.differing_pixels,
            100.0 * c.differing_pixels as f64 / total as f64,
            c.tolerance
        );
    }
    if c.differing_pixels > 0 {
        return Err(CliError::Failed(format!(
            "{} pixels differ by more than {} levels",
            c.differing_pixels, args.tolerance
        )));
    }
    Ok(())
}

fn figures_command(args: &FiguresArgs, v: Verbosity) -> Result<(), CliError> {
    use crate::figures::{generate_until, registry, write_index};
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
        return check_figures(&chosen, args, v);
    }
    std::fs::create_dir_all(&args.out).map_err(|e| {
        CliError::BadInput(format!(
            "{}: cannot create the output directory: {e}",
            args.out.display()
        ))
    })?;
    let start = std::time::Instant::now();
    // Ctrl-C stops the set being rendered and leaves its folder as it was; the sets before
    // it are complete (see `generate_until`). If the handler cannot be installed, Ctrl-C
    // kills the process, which also leaves every set whole unless it lands in the
    // milliseconds a set's files take to write.
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, std::sync::atomic::Ordering::Relaxed));
    let mut written = Vec::new();
    let mut reuse = crate::figures::Reuse::for_sets(&chosen);
    for set in chosen {
        let report = with_threads(args.threads, || {
            generate_until(set, &args.out, args.scale, &INTERRUPTED, &mut reuse)
        })?
        .map_err(CliError::Failed)?;
        let stopped = INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed);
        let Some(report) = report else {
            return Err(CliError::InterruptedAt(format!(
                "figure set {:?} and the sets after it were left as they were; complete: [{}]",
                set.name,
                written.join(", ")
            )));
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
        if stopped {
            return Err(CliError::InterruptedAt(format!(
                "figure sets written: [{}]; the sets after them were left as they were",
                written.join(", ")
            )));
        }
    }
    write_index(&args.out).map_err(CliError::Failed)?;
    if v != Verbosity::Quiet {
        println!(
            "total                     {:>7.2} s  {}",
            start.elapsed().as_secs_f64(),
            args.out.join("index.html").display()
        );
    }
    Ok(())
}

fn check_figures(sets: &[&crate::figures::FigureSet], args: &FiguresArgs, v: Verbosity) -> Result<(), CliError> {
    let mut failures = 0;
    let mut reuse = crate::figures::Reuse::for_sets(sets);
    for set in sets {
        let mismatches = with_threads(args.threads, || crate::figures::check(set, &args.out, &mut reuse))?
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
