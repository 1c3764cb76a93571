//! `lumiere diagnose SCENE IMAGE...`: what is most likely wrong in a student's image. Prints
//! the gains per term, the verdict, the top mistakes with their evidence and what the image
//! follows within sampling (or JSON), and writes the HTML report with `--report DIR`.
//! Several images of one size (a class's) are diagnosed against one oracle, rendered once.
//! Exit 0 whatever the verdict, 2 bad input.

use super::{CliError, Overrides, load_scene};
use clap::Args;
use lumiere::compare::read::{Image, read_image};
use lumiere::diagnose::mistakes::catalogue;
use lumiere::diagnose::{Diagnosis, Options, Oracle, Score, Verdict, report};
use lumiere::film::WriteError;
use lumiere::limits::MAX_THREADS;
use lumiere::scene::{self, Scene};
use lumiere::shell;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct DiagnoseArgs {
    /// The scene the image renders (TOML or SIMRenderer's format); loaded at the image's
    /// size. Required, except with --list.
    #[arg(required_unless_present = "list")]
    pub scene: Option<PathBuf>,
    /// Your image: PNG, PPM / PGM / PBM, PFM, EXR, JPEG, BMP or TGA. Several images, all of
    /// one size, are each diagnosed against the oracle rendered once: their texts follow one
    /// another, their JSON is one line each, and `--report DIR` writes one folder each, named
    /// after the image's file name. At least one is required, except with --list.
    #[arg(required_unless_present = "list", value_name = "IMAGE")]
    pub images: Vec<PathBuf>,
    /// Print the catalogue of named mistakes instead, one a line: its name, what kind of
    /// change it is (formula, convention, recursion, post-process, or fitted to the image)
    /// and what the wrong code does (JSON with `--json`).
    #[arg(long, conflicts_with_all = ["scene", "images", "report"])]
    pub list: bool,
    #[arg(
        long,
        default_value_t = Options::default().tolerance,
        help = format!("Largest per-channel difference (8-bit levels, in [0, {}]) that counts as equal", u8::MAX),
        value_parser = super::numbers::levels,
        allow_negative_numbers = true
    )]
    pub tolerance: u8,
    /// Largest fraction (in [0, 1]) of the judged pixels beyond the tolerance for the image to
    /// match the oracle ("no mistake found").
    #[arg(long, default_value_t = Options::default().max_fraction, value_name = "FRACTION", value_parser = super::numbers::fraction, allow_negative_numbers = true)]
    pub max_fraction: f64,
    /// Most pixels judged (at least 1); a larger image is judged on a regular grid of every
    /// n-th pixel.
    #[arg(long, default_value_t = Options::default().max_pixels, value_name = "N", value_parser = super::numbers::pixel_count, allow_negative_numbers = true)]
    pub max_pixels: usize,
    /// How many mistakes to print.
    #[arg(long, default_value_t = 3, value_name = "N", value_parser = super::numbers::how_many, allow_negative_numbers = true)]
    pub top: usize,
    /// Write an HTML report (index.html, the images and heat-maps) into this folder (made if
    /// its parent exists); with several images, into a folder of it per image. The reports
    /// an earlier run left there of images not diagnosed now are removed (only folders
    /// lumiere marked as its reports, and in them only the report's files).
    #[arg(long, value_name = "DIR")]
    pub report: Option<PathBuf>,
    /// The oracle's images are sRGB-encoded (as `render --srgb` writes them): compare
    /// yours with those, and fit the gains on it decoded to linear.
    #[arg(long)]
    pub srgb: bool,
    /// Print the diagnosis as JSON.
    #[arg(long)]
    pub json: bool,
    #[arg(
        long,
        help = format!("Worker threads, in [1, {MAX_THREADS}] (default: all cores). The diagnosis does not depend on it"),
        value_parser = super::numbers::threads,
        allow_negative_numbers = true
    )]
    pub threads: Option<usize>,
    /// The oracle's settings, as `render` takes them (the size is the image's).
    #[command(flatten)]
    pub overrides: Overrides,
}

/// How `diagnose` takes its arguments, for a scene and an image given the wrong way round.
const ORDER: &str = "the scene goes first, then the images (`lumiere diagnose SCENE IMAGE...`)";

pub fn run(args: &DiagnoseArgs) -> Result<(), CliError> {
    if args.list {
        print!("{}", catalogue_listing(args.json)?);
        return Ok(());
    }
    let Some(scene_path) = &args.scene else {
        return Err(CliError::BadInput(
            "diagnose: a scene and an image are needed (or --list)".into(),
        ));
    };
    if let Some(dir) = &args.report {
        let parent = dir
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        if let Some((what, input)) = inputs(scene_path, &args.images).find(|(_, input)| same_file(dir, input)) {
            return Err(CliError::BadInput(format!(
                "{}: --report: is the {what} {}, an input, not a folder for the report",
                dir.display(),
                input.display()
            )));
        }
        if dir.exists() && !dir.is_dir() {
            return Err(CliError::BadInput(format!(
                "{}: --report: is a file, not a folder",
                dir.display()
            )));
        }
        if !dir.exists() && !parent.is_dir() {
            return Err(CliError::BadInput(format!(
                "{}: --report: the folder {} does not exist",
                dir.display(),
                parent.display()
            )));
        }
    }
    let images = read_images(&args.images)?;
    let reports = report_folders(args.report.as_deref(), &args.images)?;
    check_reports_spare_inputs(&reports, scene_path, &args.images, args.top)?;
    let (width, height) = (images[0].width, images[0].height);
    for (given, actual, flag) in [
        (args.overrides.width, width, "--width"),
        (args.overrides.height, height, "--height"),
    ] {
        if let Some(g) = given
            && g != actual
        {
            return Err(CliError::BadInput(format!(
                "{flag} {g}: {} is {width} x {height}; the oracle renders at the image's size",
                args.images[0].display()
            )));
        }
    }
    let (scene, scene_size) = load_at_size(scene_path, &args.overrides, (width, height))
        .map_err(|e| super::compare::scene_error(scene_path, e, ORDER))?;
    let options = Options {
        tolerance: args.tolerance,
        max_fraction: args.max_fraction,
        max_pixels: args.max_pixels,
        srgb: args.srgb,
    };
    let diagnoses = super::with_threads(args.threads, || {
        let oracle = Oracle::new(&scene, &options);
        images
            .iter()
            .map(|image| oracle.diagnose_drawn(&image.rgb, &image.undrawn))
            .collect::<Vec<_>>()
    })?;
    let scene_name = scene_path.display().to_string();
    for (k, (d, path)) in diagnoses.iter().zip(&args.images).enumerate() {
        let image_name = path.display().to_string();
        let size_note = size_note(&image_name, (width, height), scene_size);
        if let Some(dir) = reports.get(k) {
            if !dir.exists() {
                std::fs::create_dir_all(dir)
                    .map_err(|e| WriteError::new(dir, "cannot create the report's folder", e))?;
            }
            let how = if args.images.len() == 1 {
                report::Written::Alone
            } else {
                report::Written::OneOfSeveral
            };
            report::write(dir, d, &scene_name, &image_name, args.top, how)
                .map_err(|e| WriteError::new(dir, "cannot write the report", e))?;
        }
        if args.json {
            let mut value = serde_json::to_value(d).map_err(|e| CliError::Failed(e.to_string()))?;
            value["scene"] = scene_name.as_str().into();
            value["image"] = image_name.into();
            value["top"] = d.top(args.top).map(|c| c.name).collect::<Vec<_>>().into();
            value["size_note"] = size_note.into();
            println!("{value}");
        } else {
            if k > 0 {
                println!();
            }
            if let Some(note) = size_note {
                println!("note: {note}");
            }
            print!("{}", text(d, &scene_name, &image_name, args.top));
            if let Some(next) = next_step(d, args, &scene_name, &image_name) {
                println!("next               {next}");
            }
        }
    }
    if let Some(dir) = &args.report {
        let inputs: Vec<&Path> = inputs(scene_path, &args.images).map(|(_, p)| p).collect();
        let stale = report::remove_stale_reports(dir, &reports, &inputs)
            .map_err(|e| WriteError::new(dir, "cannot remove an earlier report", e))?;
        for s in stale {
            match s {
                report::Stale::Removed(folder) => eprintln!(
                    "lumiere: {}: removed: the report of an image not diagnosed in this run",
                    folder.display()
                ),
                report::Stale::Cleared(folder) => eprintln!(
                    "lumiere: {}: the report files of an image not diagnosed in this run removed; the other files kept",
                    folder.display()
                ),
            }
        }
    }
    Ok(())
}

/// The scene of `path` with `overrides`, set to the image's size `(width, height)`, and its
/// own size (the file's, which [`size_note`] gives).
fn load_at_size(
    path: &Path,
    overrides: &Overrides,
    (width, height): (u32, u32),
) -> Result<(Scene, (u32, u32)), CliError> {
    let at_own_size = Overrides {
        width: None,
        height: None,
        ..overrides.clone()
    };
    let mut scene = load_scene(path, &at_own_size)?;
    let own_size = (scene.settings.width, scene.settings.height);
    let image_size = scene::Overrides {
        width: Some(width),
        height: Some(height),
        ..scene::Overrides::default()
    };
    image_size.apply(&mut scene).map_err(CliError::BadInput)?;
    Ok((scene, own_size))
}

/// The note for an image whose aspect ratio is not the scene's: the oracle is rendered at
/// the image's size all the same, so the scene's own size is said. `None` for an image of
/// the scene's aspect ratio (a smaller or larger render of the same view).
fn size_note(image: &str, (width, height): (u32, u32), (scene_width, scene_height): (u32, u32)) -> Option<String> {
    let same_aspect = width as u64 * scene_height as u64 == scene_width as u64 * height as u64;
    (!same_aspect).then(|| {
        format!(
            "{image} is {width} x {height}; the scene is {scene_width} x {scene_height}, another aspect ratio: rendered at {width} x {height}"
        )
    })
}

/// The catalogue as `--list` prints it: a line a mistake (name, kind, description), or one
/// JSON array of `{name, kind, description}`.
fn catalogue_listing(json: bool) -> Result<String, CliError> {
    let list = catalogue();
    if json {
        let entries: Vec<_> = list
            .iter()
            .map(|m| serde_json::json!({"name": m.name, "kind": m.change.kind(), "description": m.description}))
            .collect();
        let text = serde_json::to_string(&entries).map_err(|e| CliError::Failed(e.to_string()))?;
        return Ok(text + "\n");
    }
    let width = list.iter().map(|m| m.name.len()).max().unwrap_or(0);
    Ok(list
        .iter()
        .map(|m| format!("{:<width$}  {:<12}  {}\n", m.name, m.change.kind(), m.description))
        .collect())
}

/// Reads every image, all of the first's size and each with something drawn, before
/// anything is rendered.
fn read_images(paths: &[PathBuf]) -> Result<Vec<Image>, CliError> {
    let mut images: Vec<Image> = Vec::with_capacity(paths.len());
    for path in paths {
        let image = read_image(path).map_err(|e| {
            if super::compare::looks_like_scene(path) {
                CliError::BadInput(format!("{}: is a scene file, not an image: {ORDER}", path.display()))
            } else {
                CliError::BadInput(e)
            }
        })?;
        for note in &image.notes {
            eprintln!("lumiere: {}: {note}", path.display());
        }
        if image.nothing_drawn() {
            return Err(CliError::BadInput(format!(
                "{}: every pixel is fully transparent: nothing was drawn{}",
                path.display(),
                image.alpha_hint()
            )));
        }
        if let Some(first) = images.first()
            && (image.width, image.height) != (first.width, first.height)
        {
            return Err(CliError::BadInput(format!(
                "{}: the image is {} x {}, the first image ({}) {} x {}: the images diagnosed together share one size",
                path.display(),
                image.width,
                image.height,
                paths[0].display(),
                first.width,
                first.height
            )));
        }
        images.push(image);
    }
    Ok(images)
}

/// The report's folder of each image: `dir` itself for one image, `dir/NAME` for several
/// (NAME the image's file name without its extension, which must differ between images).
fn report_folders(dir: Option<&Path>, images: &[PathBuf]) -> Result<Vec<PathBuf>, CliError> {
    let Some(dir) = dir else {
        return Ok(Vec::new());
    };
    if images.len() == 1 {
        return Ok(vec![dir.to_path_buf()]);
    }
    let mut folders: Vec<PathBuf> = Vec::with_capacity(images.len());
    for image in images {
        let name = image.file_stem().unwrap_or(image.as_os_str());
        let folder = dir.join(name);
        if let Some(same) = folders.iter().position(|f| *f == folder) {
            return Err(CliError::BadInput(format!(
                "--report: {} and {} would both write {}: the images diagnosed together need different file names",
                images[same].display(),
                image.display(),
                folder.display()
            )));
        }
        folders.push(folder);
    }
    Ok(folders)
}

/// The inputs of a diagnosis, each with what it is: the scene, then the images.
fn inputs<'a>(scene: &'a Path, images: &'a [PathBuf]) -> impl Iterator<Item = (&'static str, &'a Path)> {
    std::iter::once(("scene", scene)).chain(images.iter().map(|i| ("image", i.as_path())))
}

/// Whether `a` and `b` name the same existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
}

/// Checks, before anything is rendered, that no file a report may write (in any of the
/// report `folders`) is the scene or one of the images: the report would overwrite its own
/// input.
fn check_reports_spare_inputs(
    folders: &[PathBuf],
    scene: &Path,
    images: &[PathBuf],
    top: usize,
) -> Result<(), CliError> {
    let names = report::file_names(top);
    for folder in folders {
        let Ok(at) = folder.canonicalize() else {
            // A folder still to be made holds no input.
            continue;
        };
        for (what, input) in inputs(scene, images) {
            let Ok(input_at) = input.canonicalize() else {
                continue;
            };
            if let Some(name) = names.iter().find(|n| at.join(n.as_str()) == input_at) {
                return Err(CliError::BadInput(format!(
                    "--report: {} would overwrite the {what} {}: write the report into another folder",
                    folder.join(name).display(),
                    input.display()
                )));
            }
        }
    }
    Ok(())
}

/// What to run next when the catalogue does not explain the image (no mistake of it, or
/// one explaining less than half): render the oracle's image and compare, whose worst
/// pixels off edges come with their probe lines; the scene and image as given, which hold
/// from the working folder. `None` for the other verdicts.
fn next_step(d: &Diagnosis, args: &DiagnoseArgs, scene: &str, image: &str) -> Option<String> {
    if !matches!(d.verdict, Verdict::Unexplained | Verdict::PartlyExplained) {
        return None;
    }
    let settings = super::compare::settings(&args.overrides);
    let srgb = if args.srgb { " --srgb" } else { "" };
    let oracle = oracle_name(Path::new(image));
    let (scene, image) = (shell::word(scene), shell::word(image));
    Some(format!(
        "`lumiere render {scene} -o {oracle} --width {} --height {}{settings}{srgb}`, then `lumiere compare {image} {oracle} --scene {scene}{settings}` lists the worst pixels off edges, each with the probe line of the oracle's ray tree there",
        d.width, d.height
    ))
}

/// The file the next step renders the oracle's image into, in the working folder:
/// `oracle.png`, or `lumiere-oracle.png` when the image diagnosed is that file, which the
/// render would overwrite.
fn oracle_name(image: &Path) -> &'static str {
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    if same(image, Path::new("oracle.png")) {
        "lumiere-oracle.png"
    } else {
        "oracle.png"
    }
}

/// `B of J pixels beyond T levels (F %), RMS R`.
fn score_line(s: &Score, tolerance: u8) -> String {
    format!(
        "{} of {} pixels beyond {tolerance} levels ({:.4} %), RMS {:.4}",
        s.beyond,
        s.judged,
        100.0 * s.fraction,
        s.rms
    )
}

/// The verdict in words; with a mistake found and something else differing too, what is
/// left after the first mistake and what to do.
fn verdict_words(d: &Diagnosis) -> String {
    match d.top(1).next() {
        Some(first) if d.also_differs => format!(
            "{}, and something else differs too: {} of {} pixels ({:.4} %) stay beyond {} levels after {}; fix it, render again and diagnose again",
            d.verdict.words(),
            first.score.beyond,
            first.score.judged,
            100.0 * first.score.fraction,
            d.tolerance,
            first.name
        ),
        _ => d.verdict.words().to_string(),
    }
}

/// The diagnosis as text.
fn text(d: &Diagnosis, scene: &str, image: &str, top: usize) -> String {
    let mut out = String::new();
    let judged = if d.grid.stride == 1 {
        format!("{} judged", d.grid.describe())
    } else {
        format!("{} judged ({} x {})", d.grid.describe(), d.grid.width, d.grid.height)
    };
    let _ = writeln!(
        out,
        "diagnosis          {image} against {scene} at {} x {}: {judged}, {} on edges apart",
        d.width, d.height, d.edges
    );
    if d.undrawn > 0 {
        let _ = writeln!(
            out,
            "undrawn            {} pixels left out: transparent black (alpha and colour 0), never drawn (SIMRenderer's console mode leaves the last rows of a wide image so)",
            d.undrawn
        );
    }
    let _ = writeln!(
        out,
        "oracle             {}; {} beyond any sampling of the pixel",
        score_line(&d.oracle, d.tolerance),
        d.beyond_sampling
    );
    if d.black {
        let _ = writeln!(
            out,
            "black              the image is black (every pixel 0) where the oracle's is not"
        );
    }
    let gains: Vec<String> = d.gains.iter().map(|g| format!("{} {}", g.term, g.label())).collect();
    let _ = writeln!(out, "gains              {}", gains.join(", "));
    if d.findings_shown {
        for f in &d.findings {
            let _ = writeln!(out, "finding            {f}");
        }
    }
    let _ = writeln!(out, "verdict            {}", verdict_words(d));
    if d.verdict.names_mistakes() {
        for (k, c) in d.top(top).enumerate() {
            let _ = writeln!(out, "{}. {}: {}", k + 1, c.name, c.description);
            if let Some(fit) = &c.fitted {
                let _ = writeln!(out, "     fitted        {}", fit.words);
            }
            let _ = writeln!(out, "     after         {}", score_line(&c.score, d.tolerance));
            if let Some(r) = &c.fixes {
                let _ = writeln!(
                    out,
                    "     explains      {} pixels, x {}..{}, y {}..{}",
                    r.pixels, r.x[0], r.x[1], r.y[0], r.y[1]
                );
            }
        }
    }
    for c in d.within_sampling.iter().take(top) {
        let _ = writeln!(
            out,
            "within sampling    closer with {}: {} (after: {})",
            c.name,
            c.description,
            score_line(&c.score, d.tolerance)
        );
    }
    if !d.not_visible.is_empty() {
        let _ = writeln!(out, "no visible difference on this scene: {}", d.not_visible.join(", "));
    }
    if !d.not_applicable.is_empty() {
        let _ = writeln!(out, "not applicable: {}", d.not_applicable.join(", "));
    }
    out
}
