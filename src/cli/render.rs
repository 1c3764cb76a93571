//! `lumiere render`: a scene file to an image or a shard file, with a progress bar on a
//! terminal, and ray counts, skipped work and time by phase with `--stats` / `--json`.

use super::{CliError, Overrides, Verbosity, check_output, check_output_path, noun_for, resolved, signals};
use clap::{ArgGroup, Args};
use indicatif::{ProgressBar, ProgressStyle};
use lumiere::film::{WriteError, write_atomic};
use lumiere::layers::render_layers;
use lumiere::limits::MAX_THREADS;
use lumiere::render::{RenderStats, render_rows, render_rows_reference};
use lumiere::skips::Skip;
use lumiere::world::World;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

// A render writes an image (`-o`), its layers (`--layers`), or both: one of them is
// required, as the usage line shows.
#[derive(Args, Debug)]
#[command(group(ArgGroup::new("written").required(true).multiple(true).args(["output", "layers"])))]
pub struct RenderArgs {
    /// The scene file: TOML, or SIMRenderer's format (see scenes/README.md).
    pub scene: PathBuf,
    /// Output image: .png (8-bit, clamped), .pfm or .exr (32-bit float radiance, unclamped).
    /// Required unless --layers is given.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Also (or only) write the per-term layers of each pixel (ambient, diffuse, specular, caustic,
    /// reflected, transmitted, each light's shadow filter, object, normal, depth): a
    /// multi-channel `.exr`, or a folder ending in `/` of one PNG per layer (and PFM for
    /// the colour layers). See README, "Checking your ray tracer".
    #[arg(long, value_name = "OUT.exr|DIR/", conflicts_with_all = ["shard", "reference"])]
    pub layers: Option<PathBuf>,
    /// Encode PNG output with the sRGB transfer function (default: linear, as the course).
    #[arg(long)]
    pub srgb: bool,
    #[command(flatten)]
    pub overrides: Overrides,
    #[arg(
        long,
        help = format!("Worker threads, in [1, {MAX_THREADS}] (default: all cores). The image does not depend on it"),
        value_parser = super::numbers::threads,
        allow_negative_numbers = true
    )]
    pub threads: Option<usize>,
    /// Print ray counts, work skipped by reason and time by phase after rendering.
    #[arg(long)]
    pub stats: bool,
    /// Switch a shortcut off (repeatable or comma-separated), to measure what it saves: the
    /// image does not change, only ray counts and time.
    #[arg(long, value_name = "NAME", value_delimiter = ',', value_parser = super::skip_values())]
    pub no_skip: Vec<Skip>,
    /// Print the statistics as JSON on stdout (implies --stats).
    #[arg(long)]
    pub json: bool,
    /// Render only shard K of N (0-based rows [K H / N, (K + 1) H / N), N at most the
    /// height H) into a shard file for `lumiere merge`.
    #[arg(long, value_name = "K/N", allow_hyphen_values = true)]
    pub shard: Option<lumiere::shard::ShardSpec>,
    /// Render with the reference tracer (src/trace/reference.rs: the chapter as code, no
    /// shortcut): the same image, bit for bit, more slowly. It counts only camera rays.
    #[arg(long, conflicts_with_all = ["stats", "json", "no_skip"])]
    pub reference: bool,
    /// Render the image a ray tracer with this named mistake writes (the catalogue of
    /// `lumiere diagnose`: `lumiere diagnose --list`), with the reference tracer; PNG only.
    #[arg(
        long,
        value_name = "NAME",
        requires = "output",
        conflicts_with_all = ["layers", "shard", "stats", "json", "no_skip", "reference", "srgb"]
    )]
    pub mistake: Option<String>,
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

pub fn run(args: &RenderArgs, v: Verbosity) -> Result<(), CliError> {
    // From here on a signal stops the render at the next row, and nothing is written.
    let cancel = signals::catch();
    let start = std::time::Instant::now();
    let scene = super::load_scene(&args.scene, &args.overrides)?;
    if let Some(spec) = args.shard {
        check_shard_rows(spec, scene.settings.height)?;
    }
    let loaded = start.elapsed();
    let layers = args
        .layers
        .as_deref()
        .map(|p| LayersTarget::check(p, &args.scene))
        .transpose()?;
    let Some(output) = &args.output else {
        let layers = layers.expect("clap asks for -o or --layers");
        return write_layers(&scene, &layers, args, v);
    };
    if let Some(name) = &args.mistake {
        return write_mistake(&scene, name, output, args);
    }
    let format = match args.shard {
        None => Some(check_output(output, &args.scene)?),
        Some(_) => {
            lumiere::shard::check_path(output).map_err(CliError::BadInput)?;
            check_output_path(output, &args.scene)?;
            None
        }
    };
    if let Some(layers) = &layers {
        layers.check_apart(output, &scene.lights)?;
    }
    let mut world = World::with_accel(&scene, args.overrides.accel);
    world.skips = args.no_skip.iter().fold(world.skips, |s, &k| s.without(k));
    let built = start.elapsed();
    let rows = args
        .shard
        .map_or(0..scene.settings.height, |s| s.rows(scene.settings.height));
    let s = &scene.settings;
    v.note(|| {
        format!(
            "{}: {} {}, {} {}; {} x {} pixels, {} samples, depth {}, seed {}; rows {:?}",
            args.scene.display(),
            scene.objects.len(),
            noun_for(scene.objects.len(), "object"),
            scene.lights.len(),
            noun_for(scene.lights.len(), "light"),
            s.width,
            s.height,
            s.samples_per_pixel,
            s.depth,
            s.seed,
            rows
        )
    });
    let bar = progress_bar(rows.len() as u64, v == Verbosity::Quiet);
    let (pixels, stats) = super::with_threads(args.threads, || {
        let progress = || bar.inc(1);
        if args.reference {
            render_rows_reference(&world, rows, &progress, Some(cancel))
        } else {
            render_rows(&world, rows, &progress, Some(cancel))
        }
    })?;
    bar.finish_and_clear();
    if let Some(signal) = signals::received() {
        return Err(CliError::Interrupted(signal));
    }
    let bytes = match (args.shard, format) {
        (Some(spec), _) => lumiere::shard::encode(&scene, spec, &pixels),
        (None, Some(format)) => {
            let film = scene.settings.film(pixels);
            lumiere::output::encode(&film, format, args.srgb)
                .map_err(|e| CliError::Failed(format!("cannot encode the image: {e}")))?
        }
        (None, None) => unreachable!("format is checked when there is no shard"),
    };
    write_atomic(output, &bytes).map_err(|e| WriteError::new(output, "cannot write the image", e))?;
    let phases = Phases {
        load: loaded.as_secs_f64(),
        build: (built - loaded).as_secs_f64(),
        accel: AccelReport::of(&world),
        photons: world
            .photons
            .as_ref()
            .map(|m| (m.emitted(), m.photons().len(), world.photon_seconds)),
        render: stats.elapsed.as_secs_f64(),
        write: (start.elapsed() - built - stats.elapsed).as_secs_f64(),
    };
    v.note(|| {
        format!(
            "wrote {} ({} bytes) in {:.3} s",
            output.display(),
            bytes.len(),
            stats.elapsed.as_secs_f64()
        )
    });
    if args.json {
        println!("{}", stats_json(&stats, &phases));
    } else if args.stats {
        print!("{}", stats_report(&stats, &phases));
    }
    if let Some(layers) = &layers {
        write_layers(&scene, layers, args, v)?;
    }
    if stats.counts.non_finite > 0 {
        eprintln!(
            "warning: {} samples were NaN or infinite and were written as black",
            stats.counts.non_finite
        );
    }
    Ok(())
}

/// Checks that each of the `spec.count` shards of an image of `height` rows has a row: with
/// more shards than rows some would render nothing.
fn check_shard_rows(spec: lumiere::shard::ShardSpec, height: u32) -> Result<(), CliError> {
    if spec.count > height {
        return Err(CliError::BadInput(format!(
            "--shard {}/{}: the image has {height} rows, fewer than its {} shards: a shard would render no row (use at most {height} shards)",
            spec.index, spec.count, spec.count
        )));
    }
    Ok(())
}

/// `render --mistake NAME`: the scene as a ray tracer with that mistake renders it, written
/// as PNG; nothing is written when the name is unknown, the mistake does not apply to the
/// scene (a convention it already follows) or a signal stops the render.
fn write_mistake(scene: &lumiere::scene::Scene, name: &str, output: &Path, args: &RenderArgs) -> Result<(), CliError> {
    if check_output(output, &args.scene)? != lumiere::output::Format::Png {
        return Err(CliError::BadInput(format!(
            "{}: --mistake writes PNG only (an 8-bit image, as a student's ray tracer writes)",
            output.display()
        )));
    }
    let list = lumiere::diagnose::mistakes::catalogue();
    let Some(mistake) = list.iter().find(|m| m.name == name) else {
        return Err(CliError::BadInput(format!(
            "--mistake: no mistake named {name:?} (`lumiere diagnose --list` lists the {})",
            list.len()
        )));
    };
    let rgb = super::with_threads(args.threads, || lumiere::diagnose::render_mistake(scene, mistake))?;
    let Some(rgb) = rgb else {
        let why = match mistake.change {
            lumiere::diagnose::mistakes::Change::Depth(_) => format!(
                "its depth is {}, which the mistake would take out of [1, {}]",
                scene.settings.depth,
                lumiere::limits::MAX_DEPTH
            ),
            lumiere::diagnose::mistakes::Change::SpecularExponent(_) => {
                "it shows no highlight (no object's material has k_s > 0, or the specular term is off)".to_string()
            }
            _ => "it already follows this convention".to_string(),
        };
        return Err(CliError::BadInput(format!(
            "--mistake {name}: nothing to render on {}: {why}",
            args.scene.display()
        )));
    };
    if let Some(signal) = signals::received() {
        return Err(CliError::Interrupted(signal));
    }
    let bytes = lumiere::film::encode_png(scene.settings.width, scene.settings.height, &rgb)
        .map_err(|e| CliError::Failed(format!("cannot encode the image: {e}")))?;
    write_atomic(output, &bytes).map_err(|e| WriteError::new(output, "cannot write the image", e))?;
    Ok(())
}

/// Where `--layers` writes: one EXR file, or a folder of PNG and PFM files.
enum LayersTarget {
    Exr(PathBuf),
    Folder(PathBuf),
}

impl LayersTarget {
    /// Checks `--layers PATH` before any work: a folder when it ends in `/` or is one (created
    /// if its parent exists), else a file ending in `.exr` in an existing folder.
    fn check(path: &Path, scene: &Path) -> Result<LayersTarget, CliError> {
        let bad = |m: &str| Err(CliError::BadInput(format!("{}: --layers: {m}", path.display())));
        let as_folder = path.as_os_str().to_string_lossy().ends_with('/') || path.is_dir();
        // Without its trailing `/`, which makes a file look absent.
        let path = path.components().as_path();
        if as_folder {
            if path.exists() && !path.is_dir() {
                return bad("is a file, not a folder");
            }
            if !path.exists() {
                let parent = path
                    .parent()
                    .filter(|p| !p.as_os_str().is_empty())
                    .unwrap_or(Path::new("."));
                if !parent.is_dir() {
                    return bad(&format!("the folder {} does not exist", parent.display()));
                }
            }
            return Ok(LayersTarget::Folder(path.to_path_buf()));
        }
        let exr = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
        if !exr {
            return bad("must end in .exr (one multi-channel file) or / (a folder of PNG and PFM files)");
        }
        check_output_path(path, scene)?;
        Ok(LayersTarget::Exr(path.to_path_buf()))
    }

    /// Checks that the image `-o output` is none of the files the layers write (which
    /// would replace it): not the layers' EXR file, nor in the layers' folder under the
    /// name of a layer's file.
    fn check_apart(&self, output: &Path, lights: &[lumiere::light::Light]) -> Result<(), CliError> {
        let Some(image) = resolved(output) else {
            return Ok(());
        };
        let clash = match self {
            LayersTarget::Exr(path) => resolved(path).is_some_and(|p| p == image),
            LayersTarget::Folder(dir) => {
                let name = image.file_name().and_then(|n| n.to_str()).unwrap_or("");
                image.parent().map(Path::to_path_buf) == resolved(dir)
                    && lumiere::layers::Layers::folder_files(lights).iter().any(|f| f == name)
            }
        };
        if clash {
            let layers = match self {
                LayersTarget::Exr(path) => path,
                LayersTarget::Folder(dir) => dir,
            };
            return Err(CliError::BadInput(format!(
                "{}: -o names a file --layers {} writes: the layers would replace the image; give the image another name",
                output.display(),
                layers.display()
            )));
        }
        Ok(())
    }
}

/// Renders the layers of `scene` and writes them to `target`.
fn write_layers(
    scene: &lumiere::scene::Scene,
    target: &LayersTarget,
    args: &RenderArgs,
    v: Verbosity,
) -> Result<(), CliError> {
    let world = World::with_accel(scene, args.overrides.accel);
    let layers = super::with_threads(args.threads, || render_layers(&world))?;
    if let Some(signal) = signals::received() {
        return Err(CliError::Interrupted(signal));
    }
    match target {
        LayersTarget::Exr(path) => {
            let bytes = layers
                .encode_exr(&scene.lights)
                .map_err(|e| CliError::Failed(format!("cannot encode the layers: {e}")))?;
            write_atomic(path, &bytes).map_err(|e| WriteError::new(path, "cannot write the layers", e))?;
            v.note(|| format!("wrote the layers into {}", path.display()));
        }
        LayersTarget::Folder(dir) => {
            if !dir.exists() {
                std::fs::create_dir(dir).map_err(|e| WriteError::new(dir, "cannot create the layers' folder", e))?;
            }
            let files = layers
                .write_folder(dir, &scene.lights)
                .map_err(|e| WriteError::new(dir, "cannot write the layers", e))?;
            v.note(|| format!("wrote {} layer files into {}", files.len(), dir.display()));
        }
    }
    Ok(())
}

/// Wall time of each phase of a render command, in seconds.
struct Phases {
    /// Reading and validating the scene file.
    load: f64,
    /// Building the world (acceleration structure, light points, bounds).
    build: f64,
    /// The acceleration structure, part of `build`.
    accel: AccelReport,
    /// With caustics: photons emitted, photons stored, and the seconds of the photon pass
    /// (part of `build`).
    photons: Option<(u64, usize, f64)>,
    /// Tracing every pixel.
    render: f64,
    /// Encoding and writing the output.
    write: f64,
}

/// The intersection core a render used: its name, size and build time.
struct AccelReport {
    name: &'static str,
    objects: usize,
    bytes: usize,
    seconds: f64,
}

impl AccelReport {
    fn of(world: &World) -> Self {
        AccelReport {
            name: world.accel().name(),
            objects: world.scene.objects.len(),
            bytes: world.accel().bytes(),
            seconds: world.accel_seconds,
        }
    }
}

/// Work each shortcut saved, by name, as JSON.
fn skipped_json(c: &lumiere::trace::RayCounts) -> serde_json::Value {
    Skip::ALL
        .iter()
        .map(|&s| (s.name().to_string(), serde_json::json!(c.saved.get(s))))
        .collect::<serde_json::Map<_, _>>()
        .into()
}

/// The statistics as JSON, for programs.
fn stats_json(stats: &RenderStats, phases: &Phases) -> String {
    let c = &stats.counts;
    let mut json = serde_json::json!({
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
    });
    if let Some((emitted, stored, seconds)) = phases.photons {
        json["caustics"] = serde_json::json!({ "emitted": emitted, "stored": stored, "seconds": seconds });
    }
    json.to_string()
}

/// Human-readable ray counts, skipped work and time by phase.
fn stats_report(stats: &RenderStats, phases: &Phases) -> String {
    let c = &stats.counts;
    let mut skipped = String::from("skipped (switch off with --no-skip NAME):\n");
    for s in Skip::ALL {
        skipped += &format!("  {:<18} {:>14}  {}\n", s.name(), c.saved.get(s), s.unit());
    }
    let a = &phases.accel;
    let caustics = phases.photons.map_or(String::new(), |(emitted, stored, seconds)| {
        format!("caustic photons: {emitted} emitted, {stored} stored, in {seconds:.3} s (part of build)\n")
    });
    let phases = format!(
        "time by phase: load {:.3} s, build {:.3} s, render {:.3} s, write {:.3} s\n\
         intersection core: {} over {} {}, {} bytes ({:.1} bytes/object), built in {:.3} s\n",
        phases.load,
        phases.build,
        phases.render,
        phases.write,
        a.name,
        a.objects,
        noun_for(a.objects, "object"),
        a.bytes,
        a.bytes as f64 / a.objects.max(1) as f64,
        a.seconds
    );
    phases
        + &caustics
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
