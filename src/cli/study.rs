//! `lumiere study soft-shadows`: the study's options checked and turned into a plan, its
//! steps noted on stderr, its files written into `--out` and its report printed.

use super::{CliError, Verbosity, with_threads};
use clap::{Args, Subcommand};
use lumiere::film::{WriteError, write_atomic};
use lumiere::limits;
use lumiere::placement::Placement;
use lumiere::scene;
use lumiere::study::{
    Config, Plan, first_area_light, outputs, parse_mode, parse_modes, parse_placements, parse_points,
};
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

#[derive(Args, Debug)]
pub struct CausticStudyArgs {
    /// The scene file; it must have a `[caustics]` table (its filter and bounces are kept).
    #[arg(default_value = "scenes/figures/caustics/01-reference-glass.toml")]
    pub scene: PathBuf,
    /// Photon counts, comma-separated, each in [1, 10000000].
    #[arg(long, default_value = "10000,30000,100000,300000,1000000")]
    pub photons: String,
    /// Estimate radii, comma-separated, each > 0.
    #[arg(long, default_value = "0.025,0.05,0.1")]
    pub radii: String,
    /// Photons of the reference.
    #[arg(long, default_value_t = 10_000_000)]
    pub reference_photons: u64,
    /// Radius of the reference's estimate.
    #[arg(long, default_value_t = 0.025)]
    pub reference_radius: f64,
    /// Image width in pixels.
    #[arg(long, default_value_t = 200)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 150)]
    pub height: u32,
    /// Samples per pixel (a perfect square); default: the scene's.
    #[arg(long)]
    pub spp: Option<u32>,
    /// Renders per configuration; the median time is reported (the images are identical).
    #[arg(long, default_value_t = 1)]
    pub repeats: u32,
    /// Worker threads, in [1, 1024] (default: all cores).
    #[arg(long, value_parser = super::numbers::threads, allow_negative_numbers = true)]
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
    /// Numbers of points N, comma-separated, each in [1, 100000].
    #[arg(long, default_value = "1,4,16,64,256,1024")]
    pub points: String,
    /// Placements, comma-separated: chapter, uniform, stratified, fibonacci.
    #[arg(long, default_value = "chapter,uniform,stratified,fibonacci")]
    pub placements: String,
    /// Modes, comma-separated: fixed, per_sample.
    #[arg(long, default_value = "fixed,per_sample")]
    pub modes: String,
    /// Image width in pixels.
    #[arg(long, default_value_t = 200)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 150)]
    pub height: u32,
    /// Samples per pixel (a perfect square); default: the scene's.
    #[arg(long)]
    pub spp: Option<u32>,
    /// Seed (default: the scene's).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Renders per configuration; the median time is reported (the images are identical).
    #[arg(long, default_value_t = 1)]
    pub repeats: u32,
    /// Points of the reference.
    #[arg(long, default_value_t = 4096)]
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
    /// Worker threads, in [1, 1024] (default: all cores).
    #[arg(long, value_parser = super::numbers::threads, allow_negative_numbers = true)]
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

/// A comma-separated list of `what` (named `flag` in messages), each checked by `check`.
fn parse_numbers<T: std::str::FromStr + PartialOrd + Copy>(
    flag: &str,
    text: &str,
    check: &dyn Fn(T) -> Result<(), String>,
) -> Result<Vec<T>, String> {
    let mut out: Vec<T> = Vec::new();
    for item in text.split(',').map(str::trim) {
        let x: T = item
            .parse()
            .map_err(|_| format!("--{flag}: {item:?} is not a number"))?;
        check(x).map_err(|m| format!("--{flag}: {m}"))?;
        if !out.contains(&x) {
            out.push(x);
        }
    }
    Ok(out)
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
    let max = limits::MAX_PHOTONS;
    let count = |n: u64| {
        if n == 0 || n > max {
            Err(format!("each count must be in [1, {max}], got {n}"))
        } else {
            Ok(())
        }
    };
    let radius = |r: f64| {
        if r.is_finite() && r > 0.0 && r <= limits::MAX_COORDINATE {
            Ok(())
        } else {
            Err(format!(
                "each radius must be in (0, {}], got {r}",
                limits::MAX_COORDINATE
            ))
        }
    };
    let photons = parse_numbers("photons", &args.photons, &count).map_err(bad)?;
    let radii = parse_numbers("radii", &args.radii, &radius).map_err(bad)?;
    count(args.reference_photons).map_err(|m| bad(format!("--reference-photons: {m}")))?;
    radius(args.reference_radius).map_err(|m| bad(format!("--reference-radius: {m}")))?;
    if args.repeats == 0 || args.repeats > 100 {
        return Err(bad(format!("--repeats: must be in [1, 100], got {}", args.repeats)));
    }
    let size = scene::Overrides {
        width: Some(args.width),
        height: Some(args.height),
        spp: args.spp,
        ..scene::Overrides::default()
    };
    size.apply(&mut scene).map_err(bad)?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| WriteError::new(&args.out, "cannot create the output directory", e))?;
    let plan = lumiere::caustic_study::Plan {
        photons,
        radii,
        repeats: args.repeats,
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
    let points = parse_points(&args.points).map_err(bad)?;
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
        limits::MAX_LIGHT_POINTS / 2
    } else {
        limits::MAX_LIGHT_POINTS
    };
    if reference.points == 0 || reference.points > max_ref {
        return Err(bad(format!(
            "--reference-points: must be in [1, {max_ref}], got {}",
            reference.points
        )));
    }
    if args.repeats == 0 || args.repeats > 100 {
        return Err(bad(format!("--repeats: must be in [1, 100], got {}", args.repeats)));
    }
    let size = scene::Overrides {
        width: Some(args.width),
        height: Some(args.height),
        spp: args.spp,
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
        repeats: args.repeats,
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
