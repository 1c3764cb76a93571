//! `lumiere compare`: your image against the oracle's, by a rule (pixels beyond a
//! tolerance, and optionally FLIP's mean), printed as text or JSON, with heat-maps, the
//! worst pixels as `lumiere probe` command lines, and with `--scene` the pixels on object
//! edges reported apart. Exit 0 pass, 1 the images differ beyond the rule, 2 bad input.

use super::{CliError, Overrides, check_output_path, load_scene, resolved};
use clap::Args;
use lumiere::compare::flip::flip_heat_map;
use lumiere::compare::read::{self, Image, read_image};
use lumiere::compare::{Judged, Masks, Report, Rule, Stats, compare, heat_map, undrawn_from_oracle};
use lumiere::edges::edge_mask;
use lumiere::figures::provenance::text_chunks;
use lumiere::film::{WriteError, encode_png, write_atomic};
use lumiere::shell;
use lumiere::world::World;
use serde::Serialize;
use std::borrow::Cow;
use std::path::{Component, Path, PathBuf};

#[derive(Args, Debug)]
pub struct CompareArgs {
    /// Your image: PNG, PPM / PGM / PBM, PFM, EXR, JPEG, BMP or TGA.
    pub a: PathBuf,
    /// The oracle's image (the same size).
    pub b: PathBuf,
    #[arg(
        long,
        default_value_t = 0,
        help = format!("Largest per-channel difference (8-bit levels, in [0, {}]) that still counts as equal", u8::MAX),
        value_parser = super::numbers::levels,
        allow_negative_numbers = true
    )]
    pub tolerance: u8,
    /// Largest fraction (in [0, 1]) of the judged pixels allowed beyond the tolerance
    /// (0.001 = 0.1 %). The default 0 fails on any such pixel.
    #[arg(long, default_value_t = 0.0, value_name = "FRACTION", value_parser = super::numbers::fraction, allow_negative_numbers = true)]
    pub max_fraction: f64,
    /// Also fail when the FLIP mean of the judged pixels exceeds this (in [0, 1]).
    #[arg(long, value_name = "FLIP", value_parser = super::numbers::fraction, allow_negative_numbers = true)]
    pub max_flip: Option<f64>,
    /// The scene both images render: pixels spanning an edge (an object's outline, a crease,
    /// a shadow's edge, also seen in a mirror or through glass) are reported apart
    /// and the rule judges the others. The scene is loaded at the images' size.
    #[arg(long, value_name = "SCENE")]
    pub scene: Option<PathBuf>,
    /// How many of the worst judged pixels to list, each with its `lumiere probe` line.
    #[arg(long, default_value_t = 10, value_name = "N", value_parser = super::numbers::how_many, allow_negative_numbers = true)]
    pub worst: usize,
    /// Write a heat-map of the level differences (black equal, blue small, red, white >= 16 levels).
    #[arg(long, value_name = "PNG")]
    pub heatmap: Option<PathBuf>,
    /// Write FLIP's heat-map (magma: black 0, purple, orange, pale yellow 1).
    #[arg(long, value_name = "PNG")]
    pub flip_heatmap: Option<PathBuf>,
    /// Write the edge mask (white: pixels spanning an edge); needs --scene.
    #[arg(long, value_name = "PNG")]
    pub edge_map: Option<PathBuf>,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
    /// The scene's settings, as `render` takes them, for --scene (the size is the images').
    #[command(flatten)]
    pub overrides: Overrides,
}

/// `compare --json`'s document.
#[derive(Serialize)]
struct Json<'a> {
    a: String,
    b: String,
    width: u32,
    height: u32,
    verdict: &'static str,
    failures: &'a [String],
    undrawn: u64,
    rule: JsonRule,
    metrics: &'a Stats,
    edges: Option<JsonEdges<'a>>,
    worst: Vec<JsonWorst<'a>>,
    notes: &'a [String],
}

#[derive(Serialize)]
struct JsonRule {
    tolerance: u8,
    max_fraction: f64,
    max_flip: Option<f64>,
    judged: Judged,
}

#[derive(Serialize)]
struct JsonEdges<'a> {
    scene: String,
    pixels: u64,
    fraction: f64,
    off_edges: Option<&'a Stats>,
    on_edges: Option<&'a Stats>,
}

#[derive(Serialize)]
struct JsonWorst<'a> {
    #[serde(flatten)]
    pixel: &'a lumiere::compare::WorstPixel,
    probe: String,
}

/// Reads an image; errors are bad input, and a scene file given as an image is named so.
fn read(path: &Path) -> Result<Image, CliError> {
    read_image(path).map_err(|e| {
        if looks_like_scene(path) {
            CliError::BadInput(format!(
                "{}: is a scene file, not an image: compare takes two images, yours then the oracle's (`lumiere compare YOURS ORACLE`); `lumiere render {} -o oracle.png --width W --height H` renders the oracle's at your image's size",
                path.display(),
                shell::word(&path.display().to_string())
            ))
        } else {
            CliError::BadInput(e)
        }
    })
}

/// Whether a file that is not an image is a scene file: a file of some bytes (an empty one
/// reads as a SIMRenderer scene of defaults) named `.toml`, or read as a scene (a
/// SIMRenderer scene's `.txt` names text of any kind).
pub(super) fn looks_like_scene(path: &Path) -> bool {
    let toml = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    let written = std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.len() > 0);
    written && (toml || lumiere::scene::load(path).is_ok())
}

/// The error of a scene that does not load, `error`, or when the file is an image (its first
/// bytes say so), that it is one, with `order`: how the command takes its arguments.
pub(super) fn scene_error(path: &Path, error: CliError, order: &str) -> CliError {
    match (&error, read::image_signature(path)) {
        (CliError::BadInput(_), Some(format)) => CliError::BadInput(format!(
            "{}: is a {format} image, not a scene file (TOML or SIMRenderer's format): {order}",
            path.display()
        )),
        _ => error,
    }
}

/// The pixels never drawn (transparent black) in either image, left out of the comparison;
/// empty when there are none.
fn undrawn_pixels(a: &Image, b: &Image) -> Vec<bool> {
    match (a.undrawn.is_empty(), b.undrawn.is_empty()) {
        (true, true) => Vec::new(),
        (false, true) => a.undrawn.clone(),
        (true, false) => b.undrawn.clone(),
        (false, false) => a.undrawn.iter().zip(&b.undrawn).map(|(&x, &y)| x || y).collect(),
    }
}

/// Why no pixel is left to compare: the image with alpha 0 everywhere (with the hint of
/// [`Image::alpha_hint`] when its colours are drawn), or both images when each pixel is
/// undrawn in one or the other.
fn nothing_drawn(args: &CompareArgs, a: &Image, b: &Image) -> String {
    let (pa, pb) = (args.a.display(), args.b.display());
    let nothing = "every pixel is fully transparent (alpha 0): nothing was drawn to compare";
    match (a.nothing_drawn(), b.nothing_drawn()) {
        (true, true) => {
            // One hint, of the first image whose colours are drawn.
            let hint = if a.alpha_hint().is_empty() {
                b.alpha_hint()
            } else {
                a.alpha_hint()
            };
            format!("{pa} and {pb}: {nothing}{hint}")
        }
        (true, false) => format!("{pa}: {nothing}{}", a.alpha_hint()),
        (false, true) => format!("{pb}: {nothing}{}", b.alpha_hint()),
        (false, false) => {
            format!(
                "every pixel is undrawn (transparent black: alpha and colour 0) in {pa} or in {pb}: no pixel drawn in both to compare"
            )
        }
    }
}

/// Checks a heat-map's path: a PNG that overwrites neither input.
fn check_png(path: &Path, inputs: [&Path; 2], option: &str) -> Result<(), CliError> {
    let png = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !png {
        return Err(CliError::BadInput(format!(
            "{}: {option} must be a .png",
            path.display()
        )));
    }
    inputs.into_iter().try_for_each(|input| check_output_path(path, input))
}

/// Whether any scene setting is given, which only --scene uses.
fn any_override(o: &Overrides) -> Option<&'static str> {
    [
        (o.width.is_some(), "--width"),
        (o.height.is_some(), "--height"),
        (o.spp.is_some(), "--spp"),
        (o.seed.is_some(), "--seed"),
        (o.depth.is_some(), "--depth"),
        (o.adaptive_threshold.is_some(), "--adaptive-threshold"),
        (o.conventions.is_some(), "--conventions"),
        (!o.convention.is_empty(), "--convention"),
    ]
    .into_iter()
    .find_map(|(given, name)| given.then_some(name))
}

/// Checks the options that need no file.
fn check_args(args: &CompareArgs) -> Result<(), CliError> {
    let bad = |m: String| Err(CliError::BadInput(m));
    if args.scene.is_none() {
        if let Some(name) = any_override(&args.overrides) {
            return bad(format!("{name} sets the scene of --scene, which is not given"));
        }
        if args.edge_map.is_some() {
            return bad("--edge-map needs --scene (the edges are the scene's)".into());
        }
    }
    Ok(())
}

/// The scene file a course figure's PNG names in its provenance (docs/figures.md), if
/// `path` is one, with the scene hash it records (`fnv1a64:` and 16 hex digits).
fn figure_provenance(path: &Path) -> Option<(String, Option<String>)> {
    let bytes = std::fs::read(path).ok()?;
    let chunks = text_chunks(&bytes).ok()?;
    let value = |name: &str| chunks.iter().find(|(key, _)| key == name).map(|(_, v)| v.clone());
    Some((value("Scene")?, value("Scene hash")))
}

/// The scene file a course figure's PNG names in its provenance, if `path` is one.
fn figure_scene(path: &Path) -> Option<String> {
    figure_provenance(path).map(|(scene, _)| scene)
}

/// The scene the command lines of a comparison name.
#[derive(Clone, Debug, PartialEq)]
enum LineScene {
    /// `--scene`, as given.
    Given(String),
    /// The scene a course figure names, found: its path from the working folder.
    Figure(String),
    /// A course figure's scene, as its provenance names it, not found from here.
    Missing(String),
    /// No scene known.
    Unknown,
}

impl LineScene {
    /// The scene of the command lines of `args`: `--scene`, else the one the oracle names
    /// when it is a course figure ([`find_figure_scene`]).
    fn of(args: &CompareArgs) -> LineScene {
        if let Some(scene) = &args.scene {
            return LineScene::Given(scene.display().to_string());
        }
        match figure_provenance(&args.b) {
            None => LineScene::Unknown,
            Some((named, hash)) => match find_figure_scene(&args.b, &named, hash.as_deref()) {
                Some(path) => LineScene::Figure(path),
                None => LineScene::Missing(named),
            },
        }
    }

    /// The scene as a command line names it: its path, or `placeholder` when it is not
    /// known here.
    fn word<'a>(&'a self, placeholder: &'a str) -> Cow<'a, str> {
        match self {
            LineScene::Given(path) | LineScene::Figure(path) => shell::word(path),
            LineScene::Missing(_) | LineScene::Unknown => Cow::Borrowed(placeholder),
        }
    }

    /// The note on a course figure's scene not found, which the command lines name by a
    /// placeholder; `None` for the others.
    fn note(&self, figure: &Path, placeholder: &str) -> Option<String> {
        let LineScene::Missing(named) = self else {
            return None;
        };
        Some(format!(
            "{}: a course figure of {named} (its path from the repository's root), which is found neither in the image's folder, the working folder nor any folder above them: the command lines name {placeholder} in its place; give the scene's path with --scene",
            figure.display()
        ))
    }
}

/// Where the scene file `named` in the provenance of the course figure `image` is, as a
/// path that holds from the working folder; `None` when it is not found. The figures write
/// the path their scene was found by, relative to the folder `lumiere figures` ran in (the
/// repository's root), so a relative `named` is looked for in the folder of the image and
/// each folder above it (a figure under the repository's `figures/`), then in the working
/// folder and each folder above it; the first file whose FNV-1a 64 is the provenance's
/// `hash` is taken, else the first file found. It is printed as `named` when that holds from
/// here, else relative to the working folder when both lie below a common folder but the
/// root, else absolute.
fn find_figure_scene(image: &Path, named: &str, hash: Option<&str>) -> Option<String> {
    let relative = Path::new(named);
    let here = std::env::current_dir().ok()?.canonicalize().ok()?;
    let candidates: Vec<PathBuf> = if relative.is_absolute() {
        vec![relative.to_path_buf()]
    } else {
        let image_dir = image
            .canonicalize()
            .ok()
            .and_then(|p| p.parent().map(Path::to_path_buf));
        let image_bases = image_dir.iter().flat_map(|d| d.ancestors());
        image_bases
            .chain(here.ancestors())
            .map(|base| base.join(relative))
            .collect()
    };
    let files: Vec<PathBuf> = candidates
        .into_iter()
        .filter(|c| c.is_file())
        .filter_map(|c| c.canonicalize().ok())
        .collect();
    let same_bytes = |path: &PathBuf| {
        hash.is_some_and(|h| {
            std::fs::read(path).is_ok_and(|bytes| h == format!("fnv1a64:{:016x}", lumiere::film::fnv1a64(&bytes)))
        })
    };
    let found = files.iter().find(|f| same_bytes(f)).or(files.first())?;
    if !relative.is_absolute() && here.join(relative).canonicalize().ok().as_ref() == Some(found) {
        return Some(named.to_string());
    }
    Some(path_from(&here, found).display().to_string())
}

/// `target` as a path from the folder `from` (both canonical): relative, with `..` to
/// climb, when they share a folder below the root; else `target` itself.
fn path_from(from: &Path, target: &Path) -> PathBuf {
    let (a, b): (Vec<_>, Vec<_>) = (from.components().collect(), target.components().collect());
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let roots = a.iter().take_while(|c| !matches!(c, Component::Normal(_))).count();
    if common <= roots {
        return target.to_path_buf();
    }
    let mut path: PathBuf = a[common..].iter().map(|_| Component::ParentDir).collect();
    path.extend(&b[common..]);
    path
}

/// A warning when the first image is a course figure and the second is not: the oracle's
/// image goes second, and the text's `yours` and `oracle` would be the wrong way round.
fn warn_if_swapped(args: &CompareArgs) {
    if let (Some(scene), None) = (figure_scene(&args.a), figure_scene(&args.b)) {
        eprintln!(
            "lumiere: warning: {} is a course figure (of {scene}) and {} is not: the oracle's image goes second, `lumiere compare YOURS ORACLE`; below, yours is {} and the oracle {}",
            args.a.display(),
            args.b.display(),
            args.a.display(),
            args.b.display()
        );
    }
}

/// The placeholder the command lines name for a scene not known here.
const SCENE_PLACEHOLDER: &str = "SCENE.toml";

/// The `lumiere probe` command line of pixel `(x, y)` of `scene` with the settings given.
fn probe_line(args: &CompareArgs, scene: &LineScene, width: u32, height: u32, x: u32, y: u32) -> String {
    format!(
        "lumiere probe {} --pixel {x},{y} --width {width} --height {height}{}",
        scene.word(SCENE_PLACEHOLDER),
        settings(&args.overrides)
    )
}

/// The `lumiere diagnose` command line of the first image against `scene` with the
/// settings given: what a failed comparison runs next.
fn diagnose_line(args: &CompareArgs, scene: &LineScene) -> String {
    format!(
        "lumiere diagnose {} {}{}",
        scene.word(SCENE_PLACEHOLDER),
        shell::word(&args.a.display().to_string()),
        settings(&args.overrides)
    )
}

/// The scene settings given (but the size), as options: ` --spp 1 --seed 7`.
pub(super) fn settings(o: &Overrides) -> String {
    let mut line = String::new();
    let mut add = |name: &str, value: Option<String>| {
        if let Some(v) = value {
            line.push_str(&format!(" --{name} {}", shell::word(&v)));
        }
    };
    add("spp", o.spp.map(|v| v.to_string()));
    add("seed", o.seed.map(|v| v.to_string()));
    add("depth", o.depth.map(|v| v.to_string()));
    add("adaptive-threshold", o.adaptive_threshold.map(|v| v.to_string()));
    add("conventions", o.conventions.clone());
    for c in &o.convention {
        add("convention", Some(c.clone()));
    }
    line
}

/// The edge mask of `scene` at the images' size.
fn edges_of(args: &CompareArgs, scene: &Path, width: u32, height: u32) -> Result<Vec<bool>, CliError> {
    for (given, side, name) in [
        (args.overrides.width, width, "width"),
        (args.overrides.height, height, "height"),
    ] {
        if let Some(v) = given
            && v != side
        {
            return Err(CliError::BadInput(format!(
                "--{name} {v}: {} and {} are {width} x {height}; the scene is loaded at the images' size",
                args.a.display(),
                args.b.display()
            )));
        }
    }
    let overrides = Overrides {
        width: Some(width),
        height: Some(height),
        ..args.overrides.clone()
    };
    let scene = load_scene(scene, &overrides).map_err(|e| {
        scene_error(
            scene,
            e,
            "--scene names the scene the images render (`lumiere compare YOURS ORACLE --scene SCENE`)",
        )
    })?;
    let world = World::with_accel(&scene, args.overrides.accel);
    Ok(edge_mask(&world))
}

pub fn run(args: &CompareArgs) -> Result<(), CliError> {
    check_args(args)?;
    let inputs = [args.a.as_path(), args.b.as_path()];
    let mut written: Vec<(&Path, &str)> = Vec::new();
    for (path, option) in [
        (&args.heatmap, "--heatmap"),
        (&args.flip_heatmap, "--flip-heatmap"),
        (&args.edge_map, "--edge-map"),
    ] {
        if let Some(path) = path {
            check_png(path, inputs, option)?;
            if let Some((_, before)) = written
                .iter()
                .find(|(p, _)| resolved(p).is_some_and(|p| Some(p) == resolved(path)))
            {
                return Err(CliError::BadInput(format!(
                    "{}: {before} and {option} name the same file: one map would replace the other",
                    path.display()
                )));
            }
            written.push((path, option));
        }
    }
    let a = read(&args.a)?;
    let b = read(&args.b)?;
    warn_if_swapped(args);
    let scene = LineScene::of(args);
    if (a.width, a.height) != (b.width, b.height) {
        let missing = scene
            .note(&args.b, "SCENE")
            .map_or(String::new(), |note| format!(" ({note})"));
        return Err(CliError::BadInput(format!(
            "the images differ in size: {} is {} x {}, {} is {} x {}; render the oracle's image at your image's size: `lumiere render {} -o oracle.png --width {} --height {}`{missing}",
            args.a.display(),
            a.width,
            a.height,
            args.b.display(),
            b.width,
            b.height,
            scene.word("SCENE"),
            a.width,
            a.height
        )));
    }
    let (w, h) = (a.width, a.height);
    let edges = match &args.scene {
        Some(scene) => Some(edges_of(args, scene, w, h)?),
        None => None,
    };
    let rule = Rule {
        tolerance: args.tolerance,
        max_fraction: args.max_fraction,
        max_flip: args.max_flip,
    };
    let undrawn = undrawn_pixels(&a, &b);
    if a.nothing_drawn() || b.nothing_drawn() || (!undrawn.is_empty() && undrawn.iter().all(|&u| u)) {
        return Err(CliError::BadInput(nothing_drawn(args, &a, &b)));
    }
    let masks = Masks {
        edges: edges.as_deref(),
        undrawn: &undrawn,
    };
    let report = compare(&a.rgb, &b.rgb, w, h, &rule, masks, args.worst);
    let notes: Vec<String> = [(&args.a, &a), (&args.b, &b)]
        .iter()
        .flat_map(|(path, img)| img.notes.iter().map(move |n| format!("{}: {n}", path.display())))
        .chain(scene.note(&args.b, SCENE_PLACEHOLDER))
        .collect();

    let write_png = |path: &Option<PathBuf>, rgb: &dyn Fn() -> Vec<u8>| -> Result<(), CliError> {
        if let Some(path) = path {
            let png = encode_png(w, h, &rgb())
                .map_err(|e| CliError::Failed(format!("cannot encode {}: {e}", path.display())))?;
            write_atomic(path, &png).map_err(|e| WriteError::new(path, "cannot write", e))?;
        }
        Ok(())
    };
    write_png(&args.heatmap, &|| {
        heat_map(&undrawn_from_oracle(&a.rgb, &b.rgb, &undrawn), &b.rgb, 16)
    })?;
    write_png(&args.flip_heatmap, &|| flip_heat_map(&report.flip, w, h))?;
    if let Some(mask) = &edges {
        write_png(&args.edge_map, &|| {
            mask.iter().flat_map(|&e| [if e { 255 } else { 0 }; 3]).collect()
        })?;
    }

    if args.json {
        print_json(args, &scene, &report, &notes)?;
    } else {
        print_text(args, &scene, &a, &b, &report, &notes);
    }
    if !report.pass {
        return Err(CliError::Failed(report.failures.join("; ")));
    }
    Ok(())
}

fn print_json(args: &CompareArgs, scene: &LineScene, r: &Report, notes: &[String]) -> Result<(), CliError> {
    let json = Json {
        a: args.a.display().to_string(),
        b: args.b.display().to_string(),
        width: r.width,
        height: r.height,
        verdict: if r.pass { "pass" } else { "fail" },
        failures: &r.failures,
        undrawn: r.undrawn,
        rule: JsonRule {
            tolerance: r.rule.tolerance,
            max_fraction: r.rule.max_fraction,
            max_flip: r.rule.max_flip,
            judged: r.judged,
        },
        metrics: &r.metrics,
        edges: r.edges.as_ref().map(|e| JsonEdges {
            scene: args.scene.as_ref().map(|s| s.display().to_string()).unwrap_or_default(),
            pixels: e.pixels,
            fraction: e.pixels as f64 / r.metrics.pixels as f64,
            off_edges: e.off_edges.as_ref(),
            on_edges: e.on_edges.as_ref(),
        }),
        worst: r
            .worst
            .iter()
            .map(|p| JsonWorst {
                pixel: p,
                probe: probe_line(args, scene, r.width, r.height, p.x, p.y),
            })
            .collect(),
        notes,
    };
    let text =
        serde_json::to_string_pretty(&json).map_err(|e| CliError::Failed(format!("cannot write the JSON: {e}")))?;
    println!("{text}");
    Ok(())
}

/// One line of a set's metrics, for the edge rows.
fn summary(s: &Stats) -> String {
    format!(
        "{} pixels: max {}, RMS {:.4}, PSNR {}, p50 / p99 / p99.9 {} / {} / {}, beyond {} levels {} ({:.4} %), FLIP mean {:.4}",
        s.pixels,
        s.max,
        s.rms,
        s.psnr_db,
        s.p50,
        s.p99,
        s.p999,
        s.tolerance,
        s.beyond_tolerance,
        100.0 * s.fraction_beyond_tolerance,
        s.flip_mean
    )
}

fn print_text(args: &CompareArgs, scene: &LineScene, a: &Image, b: &Image, r: &Report, notes: &[String]) {
    let m = &r.metrics;
    println!("yours              {} ({})", args.a.display(), a.format);
    println!("oracle             {} ({})", args.b.display(), b.format);
    for n in notes {
        println!("note               {n}");
    }
    println!("size               {} x {}", r.width, r.height);
    if r.undrawn > 0 {
        println!(
            "undrawn            {} pixels left out: transparent black (alpha and colour 0), never drawn; the rest are compared",
            r.undrawn
        );
    }
    println!("max difference     {} levels", m.max);
    println!("RMS difference     {:.4} levels", m.rms);
    println!("PSNR               {}", m.psnr_db);
    println!(
        "percentiles        p50 {} / p99 {} / p99.9 {} levels",
        m.p50, m.p99, m.p999
    );
    println!(
        "differing pixels   {} of {} ({:.4} %) beyond {} levels",
        m.beyond_tolerance,
        m.pixels,
        100.0 * m.fraction_beyond_tolerance,
        m.tolerance
    );
    println!("FLIP mean          {:.4} (max {:.4})", m.flip_mean, m.flip_max);
    if let (Some(e), Some(scene)) = (&r.edges, &args.scene) {
        println!(
            "edges              {} of {} pixels ({:.4} %) span an edge (outline, crease, shadow) in {}",
            e.pixels,
            m.pixels,
            100.0 * e.pixels as f64 / m.pixels as f64,
            scene.display()
        );
        let none = |what: &str| format!("no {what} pixels");
        println!(
            "  off edges        {}",
            e.off_edges.as_ref().map_or_else(|| none("non-edge"), summary)
        );
        println!(
            "  on edges         {}",
            e.on_edges.as_ref().map_or_else(|| none("edge"), summary)
        );
    }
    let judged = match (r.judged, r.undrawn > 0) {
        (Judged::All, false) => "all pixels",
        (Judged::All, true) => "the drawn pixels",
        (Judged::OffEdges, false) => "the pixels off edges",
        (Judged::OffEdges, true) => "the drawn pixels off edges",
    };
    let flip_rule = r
        .rule
        .max_flip
        .map_or(String::new(), |f| format!(" and FLIP mean <= {f}"));
    println!(
        "rule               at most {} % of {judged} beyond {} levels{flip_rule}",
        100.0 * r.rule.max_fraction,
        r.rule.tolerance
    );
    println!("verdict            {}", if r.pass { "pass" } else { "fail" });
    if !r.pass {
        let probes = if r.worst.is_empty() {
            ""
        } else {
            "; each probe line below prints the oracle's ray tree at a pixel, to hold against your code's"
        };
        println!(
            "next               `{}` names what is most likely wrong{probes}",
            diagnose_line(args, scene)
        );
    }
    if !r.worst.is_empty() {
        let which = if r.judged == Judged::OffEdges { " off edges" } else { "" };
        println!("worst pixels{which} (yours, oracle, largest channel difference, FLIP):");
        for p in &r.worst {
            println!(
                "  {:>4},{:<4}  ({:>3}, {:>3}, {:>3})  ({:>3}, {:>3}, {:>3})  {:>3}  {:.4}  {}",
                p.x,
                p.y,
                p.a[0],
                p.a[1],
                p.a[2],
                p.b[0],
                p.b[1],
                p.b[2],
                p.difference,
                p.flip,
                probe_line(args, scene, r.width, r.height, p.x, p.y)
            );
        }
    }
}
