//! The course's figures as data. The registry is read from the figure files
//! (`scenes/figures/<set>/`: [`files`]); a set is rendered with the figures that differ
//! only in depth, lights, an area light's points or shading traced in one pass
//! ([`crate::family`]), and written into `<out>/<set>/` as `NN-name.png` carrying its
//! provenance ([`provenance`]), `manifest.json` and `contact-sheet.png` ([`sheet`]), with
//! `<out>/index.html`, the gallery of the sets present ([`gallery`]). A set's files depend
//! on that set alone: no wall time, nothing of the other sets of the run, so regenerating
//! an unchanged set changes no byte. [`check`] holds the files on disk to a fresh render.
//! What the figures show and the conventions they follow: docs/figures.md.

pub mod check;
pub mod files;
pub mod gallery;
pub mod measure;
pub mod provenance;
pub mod sheet;

pub use files::{DEFAULT_DIR, Figure, FigureSet, RegistryError};

use crate::film::{WriteError, fnv1a64, write_atomic, write_beside};
use crate::render::render_rows;
use crate::scene::{self, Scene};
use crate::trace::RayCounts;
use crate::world::World;
use rayon::prelude::*;
use serde_json::{Map, Value, json};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// The conventions figure scenes follow, as manifests and PNGs record them: the preset's
/// name (`chapter` for every course figure), or the switches that differ from the
/// chapter's ([`crate::conventions::Conventions::summary`]).
fn conventions_of(scene: &Scene) -> String {
    scene.settings.conventions.summary()
}

/// The conventions of a set's figures: the one every figure follows, or `per figure`.
fn set_conventions(figures: &[Figure]) -> String {
    let mut each = figures.iter().map(|f| conventions_of(&f.scene));
    let first = each.next().unwrap_or_else(|| "chapter".to_string());
    if each.all(|c| c == first) {
        first
    } else {
        "per figure".to_string()
    }
}

/// The output folder that `lumiere figures` writes by default.
pub const DEFAULT_OUT: &str = "figures";

/// A fact measured on a rendered figure and recorded in the manifest (besides its share of
/// fully white pixels, measured on every figure).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measure {
    /// Minimum and maximum attenuation `A` over visible lit points.
    AttenuationRange,
    /// Number of cone images seen in the mirrors (red regions minus the real cone).
    ConeImages,
}

/// Every set of the figure files in [`DEFAULT_DIR`] (relative to the working folder: the
/// repository's root), by their order in the course.
pub fn registry() -> Result<Vec<FigureSet>, RegistryError> {
    files::load(Path::new(DEFAULT_DIR))
}

/// Parses one of the base scene files shipped in `scenes/` (embedded in the binary, so the
/// callers do not depend on the working folder).
pub fn base_scene(name: &str) -> Scene {
    let text = match name {
        "reference" => include_str!("../../scenes/reference.toml"),
        "mirrors" => include_str!("../../scenes/mirrors.toml"),
        "prism" => include_str!("../../scenes/prism.toml"),
        "shading" => include_str!("../../scenes/shading.toml"),
        other => panic!("no embedded scene {other}"),
    };
    parse_embedded(text, name)
}

/// Parses embedded scene text; the shipped scenes are tested, so failure is a bug.
pub fn parse_embedded(text: &str, name: &str) -> Scene {
    scene::parse(text, &format!("scenes/{name}.toml")).unwrap_or_else(|e| panic!("embedded scene: {e}"))
}

/// Scales the image size (at least 1 x 1).
pub fn scaled(mut scene: Scene, scale: f64) -> Scene {
    let s = &mut scene.settings;
    s.width = ((s.width as f64 * scale).round() as u32).max(1);
    s.height = ((s.height as f64 * scale).round() as u32).max(1);
    scene
}

/// Where a run reads the figure files and writes the figures, and at what size: what the
/// command that remakes a set says.
#[derive(Clone, Debug)]
pub struct Run {
    pub out: PathBuf,
    pub scenes: PathBuf,
    pub scale: f64,
}

impl Default for Run {
    fn default() -> Self {
        Run {
            out: PathBuf::from(DEFAULT_OUT),
            scenes: PathBuf::from(DEFAULT_DIR),
            scale: 1.0,
        }
    }
}

/// `path` without `.` components, so `./figures/` and `figures` are one folder.
fn tidy(path: &Path) -> PathBuf {
    path.components().filter(|c| *c != Component::CurDir).collect()
}

/// A path as one word of the command line, quoted for a POSIX shell whatever the host
/// ([`crate::shell::Shell::Posix`]): the command goes into the manifests, which are the
/// same bytes on every machine.
fn shell_word(path: &Path) -> String {
    crate::shell::Shell::Posix
        .word(&path.display().to_string())
        .into_owned()
}

impl Run {
    /// The command that remakes set `set` (every set when empty) as this run does, from the
    /// repository's root: options at their defaults are left out.
    pub fn command(&self, set: &str) -> String {
        let mut c = "lumiere figures".to_string();
        if !set.is_empty() {
            c += &format!(" {set}");
        }
        if self.scale != 1.0 {
            c += &format!(" --scale {}", self.scale);
        }
        if tidy(&self.out) != Path::new(DEFAULT_OUT) {
            c += &format!(" --out {}", shell_word(&self.out));
        }
        if tidy(&self.scenes) != Path::new(DEFAULT_DIR) {
            c += &format!(" --scenes {}", shell_word(&self.scenes));
        }
        c
    }
}

/// A rendered figure: its image and the rays it took.
pub struct RenderedFigure {
    pub figure: Figure,
    pub image: image::RgbImage,
    pub counts: RayCounts,
}

/// Renders one figure (at `scale`).
pub fn render_figure(figure: Figure, scale: f64) -> RenderedFigure {
    render_figure_until(figure, scale, &AtomicBool::new(false)).expect("never cancelled")
}

/// [`render_figure`], abandoned (`None`) as soon as `cancel` is true.
pub fn render_figure_until(figure: Figure, scale: f64, cancel: &AtomicBool) -> Option<RenderedFigure> {
    let scene = scaled(figure.scene.clone(), scale);
    let world = World::new(&scene);
    let (w, h) = (scene.settings.width, scene.settings.height);
    let (pixels, stats) = render_rows(&world, 0..h, &|| {}, Some(cancel));
    if cancel.load(Ordering::Relaxed) {
        return None;
    }
    let film = scene.settings.film(pixels);
    let image = image::RgbImage::from_raw(w, h, film.to_rgb8()).expect("film size");
    Some(RenderedFigure {
        figure,
        image,
        counts: stats.counts,
    })
}

/// Renders the figures of one family (see [`crate::family`]) at `scale` in passes of
/// [`crate::family::MEMBERS_PER_PASS`], or one by one if their members diverge; `None` if
/// cancelled. Each image has the bytes and ray counts of its render alone (tests/family.rs).
fn render_family_until(figures: Vec<Figure>, scale: f64, cancel: &AtomicBool) -> Option<Vec<RenderedFigure>> {
    let mut done = Vec::new();
    let mut figures = figures.into_iter().peekable();
    while figures.peek().is_some() {
        let pass: Vec<Figure> = figures.by_ref().take(crate::family::MEMBERS_PER_PASS).collect();
        let scenes: Vec<Scene> = pass.iter().map(|f| scaled(f.scene.clone(), scale)).collect();
        let images = crate::family::render(&scenes.iter().collect::<Vec<_>>(), cancel);
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        let Some(images) = images else {
            for figure in pass {
                done.push(render_figure_until(figure, scale, cancel)?);
            }
            continue;
        };
        for ((figure, scene), (rgb, stats)) in pass.into_iter().zip(&scenes).zip(images) {
            let (w, h) = (scene.settings.width, scene.settings.height);
            done.push(RenderedFigure {
                figure,
                image: image::RgbImage::from_raw(w, h, rgb).expect("film size"),
                counts: stats.counts,
            });
        }
    }
    Some(done)
}

/// Share of the pixels whose three channels are all 255, rounded to 1e-6.
pub fn white_fraction(rgb: &[u8]) -> f64 {
    let pixels = rgb.len() / 3;
    let white = rgb.chunks_exact(3).filter(|p| p == &[255, 255, 255]).count();
    (white as f64 / pixels.max(1) as f64 * 1e6).round() / 1e6
}

/// The facts measured on `rgb`, the image of `figure` rendered as `scene` (its scene at the
/// run's scale): its white fraction, whether saturation is its point or why it is kept,
/// and its own measures.
pub fn facts(figure: &Figure, scene: &Scene, rgb: &[u8]) -> Map<String, Value> {
    let (w, h) = (scene.settings.width as usize, scene.settings.height as usize);
    let mut facts = Map::new();
    facts.insert("white_fraction".into(), json!(white_fraction(rgb)));
    if figure.saturation_intended {
        facts.insert("saturation_intended".into(), json!(true));
    }
    if let Some(why) = &figure.saturation_accepted {
        facts.insert("saturation_accepted".into(), json!(why));
    }
    for m in &figure.measures {
        match m {
            Measure::AttenuationRange => {
                let range = measure::attenuation_range(&World::new(scene));
                facts.insert("attenuation_min".into(), json!(range.map(|r| r.0)));
                facts.insert("attenuation_max".into(), json!(range.map(|r| r.1)));
            }
            Measure::ConeImages => {
                let regions = measure::red_regions(rgb, w, h);
                facts.insert("cone_images".into(), json!(regions.saturating_sub(1)));
            }
        }
    }
    facts
}

/// What one run of several sets shares between them. Figures that one run renders for an
/// earlier set and uses again in a later one (light-shapes' sphere is soft-shadows'
/// N = 100): same scene and seed, same pixels, so they are rendered once per run. And
/// figures of later sets that can join a family of an earlier set's (the reference scene's
/// eleven lightings across five sets): rendered in its pass, and kept until their set is
/// generated. What a set writes does not depend on it.
#[derive(Default)]
pub struct Reuse {
    /// Scenes that appear in more than one set of the run.
    wanted: Vec<Scene>,
    /// Rendered figures of those scenes.
    kept: Vec<Kept>,
    /// The sets of the run not generated yet, in order, with their figures.
    later: Vec<(String, Vec<Figure>)>,
    /// Figures of later sets rendered in an earlier set's pass: set name, scale, figure.
    ahead: Vec<(String, f64, RenderedFigure)>,
}

/// A figure kept for later sets: its scene and scale, image and ray counts.
struct Kept {
    scene: Scene,
    scale: f64,
    image: image::RgbImage,
    counts: RayCounts,
}

impl Reuse {
    /// For a run over `sets`, in that order.
    pub fn for_sets(sets: &[&FigureSet]) -> Self {
        let later: Vec<(String, Vec<Figure>)> = sets.iter().map(|s| (s.name.clone(), s.figures.clone())).collect();
        let mut wanted: Vec<Scene> = Vec::new();
        for (i, (_, own)) in later.iter().enumerate() {
            for scene in own.iter().map(|f| &f.scene) {
                let again = later[i + 1..]
                    .iter()
                    .any(|(_, other)| other.iter().any(|f| f.scene == *scene));
                if again && !wanted.contains(scene) {
                    wanted.push(scene.clone());
                }
            }
        }
        Reuse {
            wanted,
            later,
            ..Reuse::default()
        }
    }

    /// The figure an earlier set of the run rendered with `scene` at `scale`.
    fn find(&self, scene: &Scene, scale: f64) -> Option<&Kept> {
        self.kept.iter().find(|k| k.scene == *scene && k.scale == scale)
    }

    /// Keeps `r` (rendered at `scale`) if a later set wants its scene.
    fn offer(&mut self, r: &RenderedFigure, scale: f64) {
        if self.wanted.contains(&r.figure.scene) && self.find(&r.figure.scene, scale).is_none() {
            self.kept.push(Kept {
                scene: r.figure.scene.clone(),
                scale,
                image: r.image.clone(),
                counts: r.counts,
            });
        }
    }

    /// Marks `set` as being generated: from now on only the sets after it are later.
    fn start(&mut self, set: &str) {
        if let Some(i) = self.later.iter().position(|(name, _)| name == set) {
            self.later.drain(..=i);
        }
    }

    /// The figures of later sets that an earlier set's pass at `scale` may render: each of
    /// a scene that is not one of `own` nor an earlier candidate's, nor rendered ahead
    /// already, nor kept from an earlier set (its set will copy that image).
    fn candidates(&self, own: &[&Scene], scale: f64) -> Vec<(String, Figure)> {
        let mut out: Vec<(String, Figure)> = Vec::new();
        for (set, figures) in &self.later {
            for f in figures {
                let seen = own.contains(&&f.scene)
                    || out.iter().any(|(_, g)| g.scene == f.scene)
                    || self.ahead.iter().any(|(_, _, r)| r.figure.scene == f.scene)
                    || self.find(&f.scene, scale).is_some();
                if !seen {
                    out.push((set.clone(), f.clone()));
                }
            }
        }
        out
    }

    /// The figure `stem` of `set` rendered ahead at `scale`, if it was.
    fn take_ahead(&mut self, set: &str, stem: &str, scale: f64) -> Option<RenderedFigure> {
        let i = self
            .ahead
            .iter()
            .position(|(s, at, r)| s == set && *at == scale && r.figure.stem == stem)?;
        Some(self.ahead.remove(i).2)
    }
}

/// Renders every figure of `set` at `scale`, in the set's order: a figure whose scene is an
/// earlier one's is rendered once (soft-shadows 02 is 07, shown beside the hard shadows:
/// same scene and seed, same pixels), as is one an earlier set of the run rendered
/// (`reuse`), and figures that differ only in depth, in an area light's count, in shading
/// or (without area lights) in their lights are rendered in one pass ([`crate::family`]),
/// with the figures of the run's later sets that can join that pass (kept in `reuse`).
/// `None` if cancelled.
pub fn render_set(set: &FigureSet, scale: f64, cancel: &AtomicBool, reuse: &mut Reuse) -> Option<Vec<RenderedFigure>> {
    reuse.start(&set.name);
    let figures = &set.figures;
    let twin_of = twins(figures);
    let mut firsts: Vec<usize> = (0..figures.len()).filter(|&i| twin_of[i] == i).collect();
    let mut rendered: Vec<Option<RenderedFigure>> = (0..figures.len()).map(|_| None).collect();
    for &i in &firsts {
        if let Some(r) = reuse.take_ahead(&set.name, &figures[i].stem, scale) {
            rendered[i] = Some(r);
        } else if let Some(k) = reuse.find(&figures[i].scene, scale) {
            rendered[i] = Some(RenderedFigure {
                figure: figures[i].clone(),
                image: k.image.clone(),
                counts: k.counts,
            });
        }
    }
    firsts.retain(|&i| rendered[i].is_none());
    // This set's scenes, then the later sets' figures that may join their families.
    let own: Vec<&Scene> = firsts.iter().map(|&i| &figures[i].scene).collect();
    let candidates = reuse.candidates(&own, scale);
    let scenes: Vec<&Scene> = own
        .iter()
        .copied()
        .chain(candidates.iter().map(|(_, f)| &f.scene))
        .collect();
    for group in crate::family::group(&scenes) {
        if group.iter().all(|&g| g >= own.len()) {
            continue;
        }
        // Each member: the figure and its set (`None`: this one).
        let (members, sets): (Vec<Figure>, Vec<Option<String>>) = group
            .iter()
            .map(|&g| match g.checked_sub(own.len()) {
                None => (figures[firsts[g]].clone(), None),
                Some(c) => (candidates[c].1.clone(), Some(candidates[c].0.clone())),
            })
            .unzip();
        let done = if members.len() == 1 {
            vec![render_figure_until(
                members.into_iter().next().expect("one member"),
                scale,
                cancel,
            )?]
        } else {
            render_family_until(members, scale, cancel)?
        };
        for ((g, r), other) in group.into_iter().zip(done).zip(sets) {
            reuse.offer(&r, scale);
            match other {
                None => rendered[firsts[g]] = Some(r),
                Some(other) => reuse.ahead.push((other, scale, r)),
            }
        }
    }
    let mut out: Vec<RenderedFigure> = Vec::new();
    for (i, figure) in figures.iter().enumerate() {
        let r = match rendered[i].take() {
            Some(r) => r,
            None => {
                let twin = &out[twin_of[i]];
                RenderedFigure {
                    figure: figure.clone(),
                    image: twin.image.clone(),
                    counts: twin.counts,
                }
            }
        };
        out.push(r);
    }
    Some(out)
}

/// For each figure, the first figure of the set with the same scene (itself if none).
fn twins(figures: &[Figure]) -> Vec<usize> {
    (0..figures.len())
        .map(|i| (0..=i).find(|&f| figures[f].scene == figures[i].scene).unwrap_or(i))
        .collect()
}

/// Why a set could not be generated.
#[derive(Debug, thiserror::Error)]
pub enum FiguresError {
    /// An image, contact sheet or manifest could not be encoded.
    #[error("{0}")]
    Encode(String),
    /// The set's folder or one of its files could not be written.
    #[error(transparent)]
    Write(#[from] WriteError),
}

/// A set rendered and encoded in memory: what generating it writes, and what checking it
/// compares with the files on disk.
pub struct BuiltSet {
    pub rendered: Vec<RenderedFigure>,
    /// The contact sheet's pixels, as [`CONTACT_SHEET`] of `files` encodes them.
    pub contact_sheet: image::RgbImage,
    /// Each file of the set's folder by name, with its bytes: the figures in order, the
    /// contact sheet, the manifest last.
    pub files: Vec<(String, Vec<u8>)>,
    pub manifest: Value,
}

/// The name of a set's contact sheet in its folder.
pub const CONTACT_SHEET: &str = "contact-sheet.png";

/// The provenance of figure `figure` of `set`, as its PNG's `tEXt` chunks carry it.
pub fn provenance_texts(set: &str, figure: &Figure, run: &Run) -> Vec<(&'static str, String)> {
    let values = [
        format!("{set}/{}", figure.stem),
        format!("lumiere {}", crate::VERSION),
        figure.scene_file.clone(),
        format!("fnv1a64:{:016x}", figure.scene_hash),
        figure.scene.settings.seed.to_string(),
        conventions_of(&figure.scene),
        run.command(set),
    ];
    provenance::KEYWORDS.into_iter().zip(values).collect()
}

/// PNG bytes of `img` with the `tEXt` chunks `texts`.
fn png_bytes(img: &image::RgbImage, texts: &[(&str, String)]) -> Result<Vec<u8>, String> {
    let png = crate::film::encode_png(img.width(), img.height(), img.as_raw()).map_err(|e| e.to_string())?;
    let texts: Vec<(&str, &str)> = texts.iter().map(|(k, v)| (*k, v.as_str())).collect();
    provenance::with_text(&png, &texts).ok_or_else(|| "the PNG encoder wrote no header chunk".to_string())
}

/// The manifest entry of figure `i` of `rendered` (rendered at `scale`): `family` are the
/// files of the set's figures one pass can render with it, `same_as` the file of an earlier
/// figure of the set with the same scene.
fn entry(r: &RenderedFigure, scale: f64, family: Vec<String>, same_as: Option<String>) -> Value {
    let scene = scaled(r.figure.scene.clone(), scale);
    let s = &scene.settings;
    let c = &r.counts;
    let f = &r.figure;
    let mut e = json!({
        "file": format!("{}.png", f.stem),
        "caption": f.caption,
        "scene": f.scene_file,
        "scene_hash": format!("fnv1a64:{:016x}", f.scene_hash),
        "parameters": f.parameters.iter().cloned().collect::<Map<String, Value>>(),
        "width": s.width,
        "height": s.height,
        "samples_per_pixel": s.samples_per_pixel,
        "seed": s.seed,
        "depth": s.depth,
        "conventions": conventions_of(&scene),
        "renderer": format!("lumiere {}", crate::VERSION),
        "pixel_hash": format!("fnv1a64:{:016x}", fnv1a64(r.image.as_raw())),
        "rays": {
            "camera": c.camera,
            "shadow": c.shadow,
            "reflection": c.reflection,
            "refraction": c.refraction,
            "total_internal_reflections": c.total_internal_reflections,
            "adaptive_cutoffs": c.adaptive_cutoffs,
            "non_finite_samples": c.non_finite,
        },
        "facts": facts(f, &scene, r.image.as_raw()),
    });
    if !family.is_empty() {
        e["family"] = json!(family);
    }
    if let Some(same_as) = same_as {
        e["same_image_as"] = json!(same_as);
    }
    e
}

/// Renders `set` as `run` says and encodes every file of its folder in memory; `None` if
/// cancelled.
pub fn build_set(
    set: &FigureSet,
    run: &Run,
    cancel: &AtomicBool,
    reuse: &mut Reuse,
) -> Result<Option<BuiltSet>, FiguresError> {
    let Some(rendered) = render_set(set, run.scale, cancel, reuse) else {
        return Ok(None);
    };
    let files_of =
        |ids: &[usize]| -> Vec<String> { ids.iter().map(|&i| format!("{}.png", set.figures[i].stem)).collect() };
    let scenes: Vec<&Scene> = set.figures.iter().map(|f| &f.scene).collect();
    let groups = crate::family::group(&scenes);
    let twin_of = twins(&set.figures);
    // Facts, most of all the attenuation range's extra pass, on every core; the order, and
    // so the bytes, are fixed.
    let entries: Vec<Value> = rendered
        .par_iter()
        .enumerate()
        .map(|(i, r)| {
            let group = groups.iter().find(|g| g.contains(&i)).map_or(&[][..], |g| &g[..]);
            let others: Vec<usize> = group.iter().copied().filter(|&g| g != i).collect();
            let same_as = (twin_of[i] != i).then(|| format!("{}.png", set.figures[twin_of[i]].stem));
            entry(r, run.scale, files_of(&others), same_as)
        })
        .collect();
    // Encoded on every core, the contact sheet beside them.
    let sheet_items: Vec<(&image::RgbImage, &str)> =
        rendered.iter().map(|r| (&r.image, r.figure.caption.as_str())).collect();
    let (pngs, sheet) = rayon::join(
        || {
            rendered
                .par_iter()
                .map(|r| {
                    let texts = provenance_texts(&set.name, &r.figure, run);
                    Ok((format!("{}.png", r.figure.stem), png_bytes(&r.image, &texts)?))
                })
                .collect::<Result<Vec<_>, String>>()
        },
        || {
            let img = sheet::contact_sheet(&set.title, &sheet_items);
            let texts = [
                ("Software", format!("lumiere {}", crate::VERSION)),
                ("Command", run.command(&set.name)),
            ];
            png_bytes(&img, &texts).map(|bytes| (img, bytes))
        },
    );
    let mut files = pngs.map_err(FiguresError::Encode)?;
    let (contact_sheet, sheet_bytes) = sheet.map_err(FiguresError::Encode)?;
    files.push((CONTACT_SHEET.to_string(), sheet_bytes));
    let manifest = json!({
        "set": set.name,
        "title": set.title,
        "definition": set.definition,
        "documentation": "docs/figures.md",
        "scale": run.scale,
        "command": run.command(&set.name),
        "conventions": set_conventions(&set.figures),
        "renderer": format!("lumiere {}", crate::VERSION),
        "pixel_hash": "FNV-1a 64 over the 8-bit RGB pixels, row 0 at the top",
        "scene_hash": "FNV-1a 64 over the bytes of the scene file",
        "family": "the files of this set that differ from the figure only in depth, lights, an area light's points or shading: one pass renders them",
        "white_fraction": "the share of pixels whose three channels are all 255",
        "images": entries,
    });
    let text = serde_json::to_string_pretty(&manifest).map_err(|e| FiguresError::Encode(e.to_string()))? + "\n";
    files.push(("manifest.json".to_string(), text.into_bytes()));
    Ok(Some(BuiltSet {
        rendered,
        contact_sheet,
        files,
        manifest,
    }))
}

/// The names in set folder `dir` that are none of `files` (the set's files, as
/// [`BuiltSet::files`] names them), sorted: what an earlier version of the set or someone
/// else left there.
pub fn extra_files(dir: &Path, files: &[(String, Vec<u8>)]) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut extra: Vec<String> = entries
        .filter_map(Result::ok)
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !files.iter().any(|(f, _)| f == n))
        .collect();
    extra.sort();
    extra
}

/// What generating a set wrote.
pub struct SetReport {
    pub name: String,
    pub images: usize,
    /// Wall time of the set (with the figures of later sets rendered in its passes).
    pub seconds: f64,
    pub dir: PathBuf,
    /// The files of the set's folder that the set does not make, left as they were
    /// ([`extra_files`]).
    pub extra: Vec<String>,
}

/// Renders every figure of `set` into `run.out/<set>/`, with its manifest and contact sheet.
pub fn generate(set: &FigureSet, run: &Run) -> Result<SetReport, FiguresError> {
    generate_until(set, run, &AtomicBool::new(false), &mut Reuse::default()).map(|r| r.expect("never cancelled"))
}

/// [`generate`], abandoned as soon as `cancel` is true (Ctrl-C or another signal): then it
/// returns `Ok(None)` and the set's folder is as it was. Every image is rendered, and every
/// file encoded, in memory before the first file is written, so a set on disk is wholly old
/// or wholly new: the writes take milliseconds, and a signal only sets `cancel` (the
/// caller's handler), which is looked at again after the set is written. A write that
/// fails leaves the set as it was too ([`write_set_files`]).
pub fn generate_until(
    set: &FigureSet,
    run: &Run,
    cancel: &AtomicBool,
    reuse: &mut Reuse,
) -> Result<Option<SetReport>, FiguresError> {
    let start = Instant::now();
    let dir = run.out.join(&set.name);
    let Some(built) = build_set(set, run, cancel, reuse)? else {
        return Ok(None);
    };
    if cancel.load(Ordering::Relaxed) {
        return Ok(None);
    }
    std::fs::create_dir_all(&dir).map_err(|e| WriteError::new(&dir, "cannot create", e))?;
    write_set_files(&dir, &built.files)?;
    Ok(Some(SetReport {
        name: set.name.clone(),
        images: built.rendered.len(),
        seconds: start.elapsed().as_secs_f64(),
        extra: extra_files(&dir, &built.files),
        dir,
    }))
}

/// Writes a set's `files` into its folder `dir`, leaving the folder as it was on any error:
/// a folder in the place of a file is refused before anything is written; then every file
/// is written and flushed beside its place ([`write_beside`]), where a full disk stops it;
/// only when all are written are they renamed into place, in order (the manifest last),
/// which takes no space. On an error the temporary files are removed.
fn write_set_files(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<(), WriteError> {
    for (name, _) in files {
        let path = dir.join(name);
        if path.is_dir() {
            let in_the_way = std::io::Error::new(std::io::ErrorKind::IsADirectory, "a folder is in its place");
            return Err(WriteError::new(&path, "cannot write", in_the_way));
        }
    }
    let discard = |staged: &[(PathBuf, PathBuf)]| {
        for (tmp, _) in staged {
            let _ = std::fs::remove_file(tmp);
        }
    };
    let mut staged: Vec<(PathBuf, PathBuf)> = Vec::new();
    for (name, bytes) in files {
        let path = dir.join(name);
        match write_beside(&path, bytes) {
            Ok(tmp) => staged.push((tmp, path)),
            Err(e) => {
                discard(&staged);
                return Err(WriteError::new(&path, "cannot write", e));
            }
        }
    }
    for (i, (tmp, path)) in staged.iter().enumerate() {
        if let Err(e) = std::fs::rename(tmp, path) {
            discard(&staged[i..]);
            return Err(WriteError::new(path, "cannot write", e));
        }
    }
    Ok(())
}

/// `out/index.html`: the gallery of the sets of `sets` whose manifest is in `out`.
pub fn write_index(out: &Path, sets: &[FigureSet]) -> Result<(), WriteError> {
    let html = gallery::index_html(out, sets, &[]);
    let path = out.join("index.html");
    write_atomic(&path, html.as_bytes()).map_err(|e| WriteError::new(&path, "cannot write", e))
}
