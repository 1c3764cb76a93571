//! `lumiere study soft-shadows`: the study's options checked and turned into a plan, its
//! steps noted on stderr, its files written into `--out` and its report printed.

use super::{CliError, Verbosity, with_threads};
use clap::{Args, Subcommand};
use lumiere::film::{WriteError, write_atomic};
use lumiere::limits::{
    self, MAX_COORDINATE, MAX_DIMENSION, MAX_LIGHT_POINTS, MAX_PHOTONS, MAX_SAMPLES, MAX_THREADS, Whole,
};
use lumiere::placement::Placement;
use lumiere::scene;
use lumiere::scene::rules;
use lumiere::study::{Config, Plan, first_area_light, outputs, parse_mode, parse_modes, parse_placements};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct StudyArgs {
    #[command(subcommand)]
    pub kind: StudyKind,
}

#[derive(Subcommand, Debug)]
pub enum StudyKind {
    /// Time against error of an area light for N points x placements x modes.
    #[command(
        after_help = "Examples:\n  lumiere study soft-shadows                       # scenes/soft-shadows.toml, 200 x 150, into study/\n  lumiere study soft-shadows --points 1,16,256 --placements uniform,fibonacci --modes per_sample\n  lumiere study soft-shadows scenes/soft-shadows.toml --width 400 --height 300 --repeats 3 --check-reference --out /tmp/study\n\nWrites <out>/study.csv, study.png (log-log RMSE against time), study.md (tables), reference.png.\nExit codes: 0 ok, 1 an output could not be written (disk full), 2 bad input (no area light, bad list, output folder)."
    )]
    SoftShadows(SoftShadowArgs),
    /// Time against error of the caustic pass for photon counts x estimate radii.
    #[command(
        after_help = "Examples:\n  lumiere study caustics                           # scenes/figures/caustics/01-reference-glass.toml, 200 x 150, into study-caustics/\n  lumiere study caustics --photons 10000,100000,1000000 --radii 0.025,0.05,0.1 --reference-photons 10000000\n\nWrites <out>/study.csv, study.png (log-log RMSE against time, a line per radius), study.md (tables), reference.png.\nExit codes: 0 ok, 1 an output could not be written (disk full), 2 bad input (no [caustics] table, bad list, output folder)."
    )]
    Caustics(CausticStudyArgs),
}

/// The renders of a study: their size, samples and repeats.
#[derive(Args, Debug)]
pub struct StudyImage {
    #[arg(
        long,
        default_value_t = 200,
        help = format!("Image width in pixels, in [1, {MAX_DIMENSION}]"),
        value_parser = super::numbers::dimension,
        allow_negative_numbers = true
    )]
    pub width: u32,
    #[arg(
        long,
        default_value_t = 150,
        help = format!("Image height in pixels, in [1, {MAX_DIMENSION}]"),
        value_parser = super::numbers::dimension,
        allow_negative_numbers = true
    )]
    pub height: u32,
    #[arg(
        long,
        help = format!("Samples per pixel, in [1, {MAX_SAMPLES}]; default: the scene's"),
        value_parser = super::numbers::samples,
        allow_negative_numbers = true
    )]
    pub spp: Option<u32>,
    #[arg(
        long,
        default_value_t = 1,
        help = format!(
            "Renders per configuration, in [1, {MAX_REPEATS}]; the median time is reported (the images are identical)"
        ),
        value_parser = repeats,
        allow_negative_numbers = true
    )]
    pub repeats: u32,
}

#[derive(Args, Debug)]
pub struct CausticStudyArgs {
    /// The scene file; it must have a `[caustics]` table (its filter and bounces are kept).
    #[arg(default_value = "scenes/figures/caustics/01-reference-glass.toml")]
    pub scene: PathBuf,
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "10000,30000,100000,300000,1000000",
        help = format!("Photon counts, comma-separated, each in [1, {MAX_PHOTONS}]"),
        value_parser = photons,
        allow_hyphen_values = true
    )]
    pub photons: Vec<u64>,
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.025,0.05,0.1",
        help = format!("Estimate radii, comma-separated, each in (0, {}]", limits::short(MAX_COORDINATE)),
        value_parser = radius,
        allow_hyphen_values = true
    )]
    pub radii: Vec<f64>,
    #[arg(
        long,
        default_value_t = 10_000_000,
        help = format!("Photons of the reference, in [1, {MAX_PHOTONS}]"),
        value_parser = photons,
        allow_negative_numbers = true
    )]
    pub reference_photons: u64,
    #[arg(
        long,
        default_value_t = 0.025,
        help = format!("Radius of the reference's estimate, in (0, {}]", limits::short(MAX_COORDINATE)),
        value_parser = radius,
        allow_negative_numbers = true
    )]
    pub reference_radius: f64,
    #[command(flatten)]
    pub image: StudyImage,
    #[arg(
        long,
        help = format!("Worker threads, in [1, {MAX_THREADS}] (default: all cores)"),
        value_parser = super::numbers::threads,
        allow_negative_numbers = true
    )]
    pub threads: Option<usize>,
    /// Output directory (created if missing).
    #[arg(long, default_value = "study-caustics")]
    pub out: PathBuf,
}

#[derive(Args, Debug)]
pub struct SoftShadowArgs {
    /// The scene file; its first area light is studied.
    #[arg(default_value = "scenes/soft-shadows.toml")]
    pub scene: PathBuf,
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1,4,16,64,256,1024",
        help = format!("Numbers of points N, comma-separated, each in [1, {MAX_LIGHT_POINTS}]"),
        value_parser = light_points,
        allow_hyphen_values = true
    )]
    pub points: Vec<u32>,
    /// Placements, comma-separated: chapter, uniform, stratified, fibonacci.
    #[arg(long, default_value = "chapter,uniform,stratified,fibonacci")]
    pub placements: String,
    /// Modes, comma-separated: fixed, per_sample.
    #[arg(long, default_value = "fixed,per_sample")]
    pub modes: String,
    #[command(flatten)]
    pub image: StudyImage,
    #[arg(
        long,
        help = format!("Seed, in [0, {}] (default: the scene's)", u64::MAX),
        value_parser = super::numbers::seed,
        allow_negative_numbers = true
    )]
    pub seed: Option<u64>,
    #[arg(
        long,
        default_value_t = 4096,
        help = format!(
            "Points of the reference, in [1, {MAX_LIGHT_POINTS}] (in [1, {MAX_CHECKED_REFERENCE_POINTS}] with --check-reference)"
        ),
        value_parser = light_points,
        allow_negative_numbers = true
    )]
    pub reference_points: u32,
    /// Placement of the reference's points.
    #[arg(long, default_value = "stratified")]
    pub reference_placement: String,
    /// Mode of the reference's points.
    #[arg(long, default_value = "per_sample")]
    pub reference_mode: String,
    /// Also render a reference with twice the points and report how much the two differ.
    #[arg(long)]
    pub check_reference: bool,
    #[arg(
        long,
        help = format!("Worker threads, in [1, {MAX_THREADS}] (default: all cores)"),
        value_parser = super::numbers::threads,
        allow_negative_numbers = true
    )]
    pub threads: Option<usize>,
    /// Output directory (created if missing).
    #[arg(long, default_value = "study")]
    pub out: PathBuf,
}

pub fn run(args: &StudyArgs, v: Verbosity) -> Result<(), CliError> {
    match &args.kind {
        StudyKind::SoftShadows(a) => soft_shadows(a, v),
        StudyKind::Caustics(a) => caustics(a, v),
    }
}

/// Most renders per configuration.
const MAX_REPEATS: u32 = 100;

/// `--repeats`' value parser.
fn repeats(text: &str) -> Result<u32, String> {
    limits::check_count(Whole::parse(text), MAX_REPEATS)
}

/// Most points of the reference with `--check-reference`, which renders a second reference
/// with twice its points.
const MAX_CHECKED_REFERENCE_POINTS: u32 = MAX_LIGHT_POINTS / 2;

/// A number of points of an area light (`--points`' elements, `--reference-points`).
fn light_points(text: &str) -> Result<u32, String> {
    limits::check_count(Whole::parse(text), MAX_LIGHT_POINTS)
}

/// A number of photons (`--photons`' elements, `--reference-photons`).
fn photons(text: &str) -> Result<u64, String> {
    limits::check_count(Whole::parse(text), MAX_PHOTONS)
}

/// A radius of the caustic estimate (`--radii`' elements, `--reference-radius`).
fn radius(text: &str) -> Result<f64, String> {
    super::numbers::real(text, |r| rules::positive(r, MAX_COORDINATE))
}

/// `list` without its repeated values, in the order given.
fn distinct<T: PartialEq + Copy>(list: &[T]) -> Vec<T> {
    let mut out = Vec::new();
    for &x in list {
        if !out.contains(&x) {
            out.push(x);
        }
    }
    out
}

fn caustics(args: &CausticStudyArgs, v: Verbosity) -> Result<(), CliError> {
    let bad = CliError::BadInput;
    super::check_out_folder(&args.out, "--out")?;
    let mut scene = scene::load(&args.scene).map_err(|e| bad(e.to_string()))?;
    if scene.settings.caustics.is_none() {
        return Err(bad(format!(
            "{}: the scene has no [caustics] table to study",
            args.scene.display()
        )));
    }
    let photons = distinct(&args.photons);
    let radii = distinct(&args.radii);
    let size = scene::Overrides {
        width: Some(args.image.width),
        height: Some(args.image.height),
        spp: args.image.spp,
        ..scene::Overrides::default()
    };
    size.apply(&mut scene).map_err(bad)?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| WriteError::new(&args.out, "cannot create the output directory", e))?;
    let plan = lumiere::caustic_study::Plan {
        photons,
        radii,
        repeats: args.image.repeats,
        reference: lumiere::caustic_study::Config {
            photons: args.reference_photons,
            radius: args.reference_radius,
        },
    };
    let quiet = v == Verbosity::Quiet;
    let (study, reference_film) = with_threads(args.threads, || {
        lumiere::caustic_study::run(&scene, &plan, &mut |line| {
            if !quiet {
                eprintln!("lumiere: {line}");
            }
        })
    })?
    .map_err(bad)?;
    let files = lumiere::caustic_study::outputs(&study, &reference_film).map_err(CliError::Failed)?;
    for (name, bytes) in files {
        let path = args.out.join(name);
        write_atomic(&path, &bytes).map_err(|e| WriteError::new(&path, "cannot write", e))?;
    }
    print!("{}", lumiere::caustic_study::report(&study));
    Ok(())
}

fn soft_shadows(args: &SoftShadowArgs, v: Verbosity) -> Result<(), CliError> {
    let bad = CliError::BadInput;
    super::check_out_folder(&args.out, "--out")?;
    let mut scene = scene::load(&args.scene).map_err(|e| bad(e.to_string()))?;
    let light = first_area_light(&scene).ok_or_else(|| {
        bad(format!(
            "{}: the scene has no area light ([[lights]] type = \"area\") to study",
            args.scene.display()
        ))
    })?;
    let mut points = args.points.clone();
    points.sort_unstable();
    points.dedup();
    let placements = parse_placements(&args.placements).map_err(bad)?;
    let modes = parse_modes(&args.modes).map_err(bad)?;
    let reference = Config {
        placement: Placement::parse(&args.reference_placement).ok_or_else(|| {
            bad(format!(
                "--reference-placement: unknown {:?}; expected chapter, uniform, stratified or fibonacci",
                args.reference_placement
            ))
        })?,
        mode: parse_mode(&args.reference_mode).ok_or_else(|| {
            bad(format!(
                "--reference-mode: unknown {:?}; expected fixed or per_sample",
                args.reference_mode
            ))
        })?,
        points: args.reference_points,
    };
    let max_ref = if args.check_reference {
        MAX_CHECKED_REFERENCE_POINTS
    } else {
        MAX_LIGHT_POINTS
    };
    limits::check_count(reference.points, max_ref).map_err(|m| bad(format!("--reference-points: {m}")))?;
    let size = scene::Overrides {
        width: Some(args.image.width),
        height: Some(args.image.height),
        spp: args.image.spp,
        seed: args.seed,
        ..scene::Overrides::default()
    };
    size.apply(&mut scene).map_err(bad)?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| WriteError::new(&args.out, "cannot create the output directory", e))?;
    let plan = Plan {
        points,
        placements,
        modes,
        repeats: args.image.repeats,
        reference,
        check_reference: args.check_reference,
    };
    let quiet = v == Verbosity::Quiet;
    let (study, reference_film) = with_threads(args.threads, || {
        lumiere::study::run(&scene, light, &plan, &mut |line| {
            if !quiet {
                eprintln!("lumiere: {line}");
            }
        })
    })?;
    for (name, bytes) in outputs(&study, &reference_film).map_err(CliError::Failed)? {
        let path = args.out.join(name);
        write_atomic(&path, &bytes).map_err(|e| WriteError::new(&path, "cannot write", e))?;
    }
    print!("{}", lumiere::study::report(&study));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each parser's lowest and highest value, and the values one beyond each.
    #[test]
    fn edges() {
        assert_eq!((repeats("1"), repeats("100")), (Ok(1), Ok(100)));
        for bad in ["0", "101"] {
            assert_eq!(repeats(bad), Err(format!("must be in [1, 100], got {bad}")));
        }
        assert_eq!((light_points("1"), light_points("100000")), (Ok(1), Ok(100_000)));
        for bad in ["0", "100001"] {
            assert_eq!(light_points(bad), Err(format!("must be in [1, 100000], got {bad}")));
        }
        assert_eq!((photons("1"), photons("10000000")), (Ok(1), Ok(10_000_000)));
        for bad in ["0", "10000001"] {
            assert_eq!(photons(bad), Err(format!("must be in [1, 10000000], got {bad}")));
        }
        assert_eq!((radius("5e-324"), radius("1e9")), (Ok(5e-324), Ok(1e9)));
        for bad in ["0", "1000000000.0000001", "-1"] {
            assert_eq!(
                radius(bad),
                Err(format!("must be a finite number in (0, 1e9], got {bad}"))
            );
        }
    }

    #[test]
    fn lists_keep_their_first_order_without_repeats() {
        assert_eq!(distinct(&[0.1, 0.025, 0.1, 0.05]), vec![0.1, 0.025, 0.05]);
    }
}
