//! The course's figures: a registry of figure sets (one file each in `sets/`), each a list
//! of scenes with the chapter's captions, and the generator that renders a set into
//! `<out>/<set>/NN-name.png`, `manifest.json` and `contact-sheet.png`, plus
//! `<out>/index.html`, a gallery of every set. The specifications are shared/FIGURES.md.

pub mod measure;
pub mod sets;
pub mod sheet;

use crate::film::{WriteError, pixel_hash, write_atomic};
use crate::render::render_rows;
use crate::scene::{self, Scene};
use crate::world::World;
use rayon::prelude::*;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// A fact measured on a rendered figure and recorded in the manifest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measure {
    /// Minimum and maximum attenuation `A` over visible lit points.
    AttenuationRange,
    /// Number of cone images seen in the mirrors (red regions minus the real cone).
    ConeImages,
}

/// One image of a set.
#[derive(Clone, Debug)]
pub struct Figure {
    /// File name without extension: `NN-short-name`.
    pub stem: String,
    /// The chapter's caption (French), drawn on the contact sheet.
    pub caption: String,
    pub scene: Scene,
    pub measures: Vec<Measure>,
}

impl Figure {
    pub fn new(number: usize, short: &str, caption: impl Into<String>, scene: Scene) -> Self {
        Figure {
            stem: format!("{number:02}-{short}"),
            caption: caption.into(),
            scene,
            measures: Vec::new(),
        }
    }

    pub fn measuring(mut self, m: Measure) -> Self {
        self.measures.push(m);
        self
    }
}

/// A named set of figures.
pub struct FigureSet {
    pub name: &'static str,
    /// Title of the contact sheet and gallery section.
    pub title: &'static str,
    pub figures: fn() -> Vec<Figure>,
}

/// Every set of FIGURES.md, in the order of the course.
pub fn registry() -> Vec<FigureSet> {
    sets::all()
}

/// Parses one of the scene files shipped in `scenes/` (embedded in the binary, so the
/// figures do not depend on the working directory).
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

/// A rendered figure and what was measured.
pub struct RenderedFigure {
    pub figure: Figure,
    pub image: image::RgbImage,
    pub manifest: Value,
}

/// Renders one figure (at `scale`) and measures its facts.
pub fn render_figure(figure: Figure, scale: f64) -> RenderedFigure {
    render_figure_until(figure, scale, &AtomicBool::new(false)).expect("never cancelled")
}

/// [`render_figure`], abandoned (`None`) as soon as `cancel` is true.
pub fn render_figure_until(figure: Figure, scale: f64, cancel: &AtomicBool) -> Option<RenderedFigure> {
    let scene = scaled(figure.scene.clone(), scale);
    let world = World::new(&scene);
    let start = Instant::now();
    let (w, h) = (scene.settings.width, scene.settings.height);
    let (pixels, stats) = render_rows(&world, 0..h, &|| {}, Some(cancel));
    if cancel.load(Ordering::Relaxed) {
        return None;
    }
    let film = crate::film::Film {
        width: w,
        height: h,
        pixels,
    };
    let seconds = start.elapsed().as_secs_f64();
    Some(finish(figure, &scene, film.to_rgb8(), &stats.counts, seconds))
}

/// Renders the figures of one family (see [`crate::family`]) at `scale` in passes of
/// [`crate::family::MEMBERS_PER_PASS`], or one by one if their members diverge; `None` if cancelled.
/// Each manifest records the images of its pass (`one_pass_with`: each figure's `label`,
/// its file name, or `set/file` when the family spans sets) and an equal share of the
/// pass's time.
fn render_family_until(figures: Vec<(Figure, String)>, scale: f64, cancel: &AtomicBool) -> Option<Vec<RenderedFigure>> {
    let mut done = Vec::new();
    let mut figures = figures.into_iter().peekable();
    while figures.peek().is_some() {
        let (pass, labels): (Vec<Figure>, Vec<String>) = figures.by_ref().take(crate::family::MEMBERS_PER_PASS).unzip();
        let scenes: Vec<Scene> = pass.iter().map(|f| scaled(f.scene.clone(), scale)).collect();
        let start = Instant::now();
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
        let share = start.elapsed().as_secs_f64() / pass.len() as f64;
        for (j, ((figure, scene), (rgb, stats))) in pass.into_iter().zip(&scenes).zip(images).enumerate() {
            let mut r = finish(figure, scene, rgb, &stats.counts, share);
            let others: Vec<&String> = labels
                .iter()
                .enumerate()
                .filter(|&(k, _)| k != j)
                .map(|(_, l)| l)
                .collect();
            r.manifest["one_pass_with"] = json!(others);
            done.push(r);
        }
    }
    Some(done)
}

/// A rendered figure's image, measured facts and manifest entry.
fn finish(figure: Figure, scene: &Scene, rgb: Vec<u8>, c: &crate::trace::RayCounts, seconds: f64) -> RenderedFigure {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let mut facts = serde_json::Map::new();
    for m in &figure.measures {
        match m {
            Measure::AttenuationRange => {
                let range = measure::attenuation_range(&World::new(scene));
                facts.insert("attenuation_min".into(), json!(range.map(|r| r.0)));
                facts.insert("attenuation_max".into(), json!(range.map(|r| r.1)));
            }
            Measure::ConeImages => {
                let regions = measure::red_regions(&rgb, w as usize, h as usize);
                facts.insert("cone_images".into(), json!(regions.saturating_sub(1)));
            }
        }
    }
    let manifest = json!({
        "file": format!("{}.png", figure.stem),
        "caption": figure.caption,
        "width": w,
        "height": h,
        "samples_per_pixel": scene.settings.samples_per_pixel,
        "seed": scene.settings.seed,
        "renderer": format!("lumiere {}", crate::VERSION),
        "pixel_hash": format!("fnv1a64:{:016x}", pixel_hash(&rgb)),
        "render_seconds": (seconds * 1000.0).round() / 1000.0,
        "rays": {
            "camera": c.camera,
            "shadow": c.shadow,
            "reflection": c.reflection,
            "refraction": c.refraction,
            "total_internal_reflections": c.total_internal_reflections,
            "adaptive_cutoffs": c.adaptive_cutoffs,
            "non_finite_samples": c.non_finite,
        },
        "facts": facts,
        "scene": scene,
    });
    let image = image::RgbImage::from_raw(w, h, rgb).expect("film size");
    RenderedFigure {
        figure,
        image,
        manifest,
    }
}

/// What one run of several sets shares between them. Figures that one run renders for an
/// earlier set and uses again in a later one (light-shapes' sphere is soft-shadows'
/// N = 100): same scene and seed, same bytes, so they are rendered once per run; only the
/// figures a later set wants are kept. And figures of later sets that can join a family of
/// an earlier set's (the reference scene's eleven lightings across five sets): rendered in
/// its pass, and kept until their set is generated.
#[derive(Default)]
pub struct Reuse {
    /// Scenes that appear in more than one set of the run.
    wanted: Vec<Scene>,
    /// Rendered figures of those scenes.
    kept: Vec<Kept>,
    /// The sets of the run not generated yet, in order, with their figures.
    later: Vec<(&'static str, Vec<Figure>)>,
    /// Figures of later sets rendered in an earlier set's pass: set name, scale, figure.
    ahead: Vec<(&'static str, f64, RenderedFigure)>,
}

/// A figure kept for later sets: its scene and scale, `set/file`, image and manifest entry.
struct Kept {
    scene: Scene,
    scale: f64,
    file: String,
    image: image::RgbImage,
    manifest: Value,
}

impl Reuse {
    /// For a run over `sets`, in that order.
    pub fn for_sets(sets: &[&FigureSet]) -> Self {
        let later: Vec<(&'static str, Vec<Figure>)> = sets.iter().map(|s| (s.name, (s.figures)())).collect();
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

    /// Keeps `r` (of set `set`, rendered at `scale`) if a later set wants its scene.
    fn offer(&mut self, set: &str, r: &RenderedFigure, scale: f64) {
        if self.wanted.contains(&r.figure.scene) && self.find(&r.figure.scene, scale).is_none() {
            let file = r.manifest["file"].as_str().unwrap_or_default();
            self.kept.push(Kept {
                scene: r.figure.scene.clone(),
                scale,
                file: format!("{set}/{file}"),
                image: r.image.clone(),
                manifest: r.manifest.clone(),
            });
        }
    }

    /// Marks `set` as being generated: from now on only the sets after it are later.
    fn start(&mut self, set: &str) {
        if let Some(i) = self.later.iter().position(|(name, _)| *name == set) {
            self.later.drain(..=i);
        }
    }

    /// The figures of later sets that an earlier set's pass at `scale` may render: each of
    /// a scene that is not one of `own` nor an earlier candidate's, nor rendered ahead
    /// already, nor kept from an earlier set (its set will copy that image).
    fn candidates(&self, own: &[&Scene], scale: f64) -> Vec<(&'static str, Figure)> {
        let mut out: Vec<(&'static str, Figure)> = Vec::new();
        for (set, figures) in &self.later {
            for f in figures {
                let seen = own.contains(&&f.scene)
                    || out.iter().any(|(_, g)| g.scene == f.scene)
                    || self.ahead.iter().any(|(_, _, r)| r.figure.scene == f.scene)
                    || self.find(&f.scene, scale).is_some();
                if !seen {
                    out.push((set, f.clone()));
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
            .position(|(s, at, r)| *s == set && *at == scale && r.figure.stem == stem)?;
        Some(self.ahead.remove(i).2)
    }
}

/// The manifest entry and image of `figure`, a copy of the image `twin` (file name
/// `same_as`) that was rendered with the same scene.
fn copy_of(figure: Figure, image: &image::RgbImage, twin: &Value, same_as: &str) -> RenderedFigure {
    let mut manifest = twin.clone();
    manifest["file"] = json!(format!("{}.png", figure.stem));
    manifest["caption"] = json!(figure.caption);
    manifest["same_image_as"] = json!(same_as);
    manifest["render_seconds"] = json!(0.0);
    if let Some(m) = manifest.as_object_mut() {
        m.remove("one_pass_with");
    }
    RenderedFigure {
        figure,
        image: image.clone(),
        manifest,
    }
}

/// Renders every figure of `set` at `scale`, in the set's order: a figure whose scene is an
/// earlier one's is rendered once (soft-shadows 02 is 07, shown beside the hard shadows:
/// same scene and seed, same bytes), as is one an earlier set of the run rendered
/// (`reuse`), and figures that differ only in depth, in an area light's count, in shading
/// or (without area lights) in their lights are rendered in one pass ([`crate::family`]),
/// with the figures of the run's later sets that can join that pass (kept in `reuse`).
/// `None` if cancelled.
pub fn render_set(set: &FigureSet, scale: f64, cancel: &AtomicBool, reuse: &mut Reuse) -> Option<Vec<RenderedFigure>> {
    reuse.start(set.name);
    let figures = (set.figures)();
    // The first figure of each distinct scene, and which of them each figure is.
    let mut firsts: Vec<usize> = Vec::new();
    let twin_of: Vec<usize> = (0..figures.len())
        .map(
            |i| match firsts.iter().find(|&&f| figures[f].scene == figures[i].scene) {
                Some(&f) => f,
                None => {
                    firsts.push(i);
                    i
                }
            },
        )
        .collect();
    let mut rendered: Vec<Option<RenderedFigure>> = (0..figures.len()).map(|_| None).collect();
    for &i in &firsts {
        if let Some(r) = reuse.take_ahead(set.name, &figures[i].stem, scale) {
            rendered[i] = Some(r);
        } else if let Some(k) = reuse.find(&figures[i].scene, scale) {
            rendered[i] = Some(copy_of(figures[i].clone(), &k.image, &k.manifest, &k.file));
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
        // Each member: the figure, its set (`None`: this one) and its label in manifests.
        let members: Vec<(Figure, Option<&'static str>)> = group
            .iter()
            .map(|&g| match g.checked_sub(own.len()) {
                None => (figures[firsts[g]].clone(), None),
                Some(c) => (candidates[c].1.clone(), Some(candidates[c].0)),
            })
            .collect();
        let sets: Vec<Option<&'static str>> = members.iter().map(|m| m.1).collect();
        let done = if members.len() == 1 {
            vec![render_figure_until(members[0].0.clone(), scale, cancel)?]
        } else {
            // A family over several sets names every file with its set (in each of its
            // passes, should it need more than one).
            let across = sets.iter().any(Option::is_some);
            let labelled = members
                .into_iter()
                .map(|(f, other)| {
                    let label = match across {
                        false => format!("{}.png", f.stem),
                        true => format!("{}/{}.png", other.unwrap_or(set.name), f.stem),
                    };
                    (f, label)
                })
                .collect();
            render_family_until(labelled, scale, cancel)?
        };
        for ((g, r), other) in group.into_iter().zip(done).zip(sets) {
            reuse.offer(other.unwrap_or(set.name), &r, scale);
            match other {
                None => rendered[firsts[g]] = Some(r),
                Some(other) => reuse.ahead.push((other, scale, r)),
            }
        }
    }
    let mut out: Vec<RenderedFigure> = Vec::new();
    for (i, figure) in figures.into_iter().enumerate() {
        if twin_of[i] == i {
            out.push(rendered[i].take().expect("rendered"));
            continue;
        }
        let twin = &out[twin_of[i]];
        let same_as = twin.manifest["file"].as_str().unwrap_or_default().to_string();
        let copy = copy_of(figure, &twin.image, &twin.manifest, &same_as);
        out.push(copy);
    }
    Some(out)
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

/// What generating a set wrote.
pub struct SetReport {
    pub name: &'static str,
    pub images: usize,
    pub seconds: f64,
    pub dir: PathBuf,
}

fn png_bytes(img: &image::RgbImage) -> Result<Vec<u8>, String> {
    crate::film::encode_png(img.width(), img.height(), img.as_raw()).map_err(|e| e.to_string())
}

/// Renders every figure of `set` into `out/<set>/`, with its manifest and contact sheet.
pub fn generate(set: &FigureSet, out: &Path, scale: f64) -> Result<SetReport, FiguresError> {
    generate_until(set, out, scale, &AtomicBool::new(false), &mut Reuse::default()).map(|r| r.expect("never cancelled"))
}

/// [`generate`], abandoned as soon as `cancel` is true (Ctrl-C or another signal): then it
/// returns `Ok(None)` and the set's folder is as it was. Every image is rendered, and every
/// file encoded, in memory before the first file is written, so a set on disk is wholly old
/// or wholly new: the writes take milliseconds, and a signal only sets `cancel` (the
/// caller's handler), which is looked at again after the set is written. Each file is written atomically, the
/// manifest last.
pub fn generate_until(
    set: &FigureSet,
    out: &Path,
    scale: f64,
    cancel: &AtomicBool,
    reuse: &mut Reuse,
) -> Result<Option<SetReport>, FiguresError> {
    let start = Instant::now();
    let dir = out.join(set.name);
    let Some(rendered) = render_set(set, scale, cancel, reuse) else {
        return Ok(None);
    };
    // Encoded on every core (about 10 ms an image), the contact sheet (about 0.1 s, most of
    // it thumbnails) beside them; the order, and so the bytes, are fixed.
    let sheet_items: Vec<(&image::RgbImage, &str)> =
        rendered.iter().map(|r| (&r.image, r.figure.caption.as_str())).collect();
    let (files, sheet) = rayon::join(
        || {
            rendered
                .par_iter()
                .map(|r| Ok((format!("{}.png", r.figure.stem), png_bytes(&r.image)?)))
                .collect::<Result<Vec<_>, String>>()
        },
        || png_bytes(&sheet::contact_sheet(set.title, &sheet_items)),
    );
    let mut files = files.map_err(FiguresError::Encode)?;
    files.push(("contact-sheet.png".to_string(), sheet.map_err(FiguresError::Encode)?));
    let manifest = json!({
        "set": set.name,
        "title": set.title,
        "scale": scale,
        "specification": "shared/FIGURES.md",
        "pixel_hash": "FNV-1a 64 over the 8-bit RGB pixels, row 0 at the top",
        "images": rendered.iter().map(|r| r.manifest.clone()).collect::<Vec<_>>(),
    });
    let text = serde_json::to_string_pretty(&manifest).map_err(|e| FiguresError::Encode(e.to_string()))? + "\n";
    files.push(("manifest.json".to_string(), text.into_bytes()));
    if cancel.load(Ordering::Relaxed) {
        return Ok(None);
    }
    std::fs::create_dir_all(&dir).map_err(|e| WriteError::new(&dir, "cannot create", e))?;
    for (name, bytes) in &files {
        let path = dir.join(name);
        write_atomic(&path, bytes).map_err(|e| WriteError::new(&path, "cannot write", e))?;
    }
    Ok(Some(SetReport {
        name: set.name,
        images: rendered.len(),
        seconds: start.elapsed().as_secs_f64(),
        dir,
    }))
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `out/index.html`: every set of the registry with its contact sheet and captioned images.
pub fn write_index(out: &Path) -> Result<(), WriteError> {
    let mut html = String::from(
        "<!doctype html>\n<html lang=\"fr\">\n<head>\n<meta charset=\"utf-8\">\n<title>lumiere: figures du cours</title>\n\
         <style>body{font-family:sans-serif;background:#202024;color:#eee;margin:2em}\
         figure{display:inline-block;margin:0.5em;width:260px;vertical-align:top}\
         img{max-width:100%}figcaption{font-size:0.85em}a{color:#9cf}</style>\n</head>\n<body>\n\
         <h1>Figures du chapitre 7.4b et des diapositives IFT3355</h1>\n\
         <p>Regenerated by <code>lumiere figures</code>; specifications in shared/FIGURES.md.</p>\n",
    );
    for set in registry() {
        html += &format!(
            "<h2 id=\"{0}\">{1} <small>(<a href=\"{0}/manifest.json\">manifest</a>, <a href=\"{0}/contact-sheet.png\">contact sheet</a>)</small></h2>\n",
            set.name,
            html_escape(set.title)
        );
        for f in (set.figures)() {
            html += &format!(
                "<figure><a href=\"{0}/{1}.png\"><img src=\"{0}/{1}.png\" alt=\"{2}\" loading=\"lazy\"></a><figcaption>{2}</figcaption></figure>\n",
                set.name,
                f.stem,
                html_escape(&f.caption)
            );
        }
    }
    html += "</body>\n</html>\n";
    let path = out.join("index.html");
    write_atomic(&path, html.as_bytes()).map_err(|e| WriteError::new(&path, "cannot write", e))
}

/// A figure whose regenerated pixels differ from its committed manifest.
#[derive(Debug, PartialEq)]
pub struct Mismatch {
    pub file: String,
    pub expected: String,
    pub actual: String,
}

/// Re-renders `set` at the scale recorded in `out/<set>/manifest.json` and compares every
/// image's pixel hash with the manifest's. Renders in memory; writes nothing.
pub fn check(set: &FigureSet, out: &Path, reuse: &mut Reuse) -> Result<Vec<Mismatch>, String> {
    let path = out.join(set.name).join("manifest.json");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let manifest: Value = serde_json::from_str(&text).map_err(|e| format!("{}: not JSON: {e}", path.display()))?;
    let scale = manifest["scale"].as_f64().unwrap_or(1.0);
    let expected: Vec<(String, String)> = manifest["images"]
        .as_array()
        .map(|a| {
            a.iter()
                .map(|i| {
                    let s = |k: &str| i[k].as_str().unwrap_or_default().to_string();
                    (s("file"), s("pixel_hash"))
                })
                .collect()
        })
        .unwrap_or_default();
    let mut mismatches = Vec::new();
    let figures = (set.figures)();
    if figures.len() != expected.len() {
        return Err(format!(
            "{}: lists {} images, the set has {}",
            path.display(),
            expected.len(),
            figures.len()
        ));
    }
    let rendered = render_set(set, scale, &AtomicBool::new(false), reuse).expect("never cancelled");
    for (r, (file, hash)) in rendered.into_iter().zip(expected) {
        let actual = r.manifest["pixel_hash"].as_str().unwrap_or_default().to_string();
        if actual != hash || r.manifest["file"] != file.as_str() {
            mismatches.push(Mismatch {
                file,
                expected: hash,
                actual,
            });
        }
    }
    Ok(mismatches)
}
