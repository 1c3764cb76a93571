//! Reading a SIMRenderer scene file into a [`Scene`]: the blocks and keywords of its keyword
//! table (with their French aliases), their defaults and ranges, and the mapping of each
//! setting to lumiere's (docs/simrenderer.md lists them).
//!
//! SIMRenderer logs a bad line and goes on; lumiere stops at the first one with
//! `file:line:column: block.keyword: message`. With [`Options::lenient`] it goes on as
//! SIMRenderer does (the line skipped, the value before it kept, the object dropped) and
//! returns each such error as a [`Warning`] that says what was done. What SIMRenderer does
//! without complaint but may surprise (an unknown material name, a primitive without
//! geometry, text after a top-level `end`) is a warning in both modes.

use super::Warning;
use super::lex::{self, Item, Line, Note, ValueError};
use crate::conventions::Conventions;
use crate::light::Light;
use crate::scene::{Scene, SceneError};
use std::path::Path;

mod build;
mod camera;
mod keywords;
mod lights;
mod materials;
mod mtl;
mod shapes;
mod values;

use camera::{CameraBlock, RaytracerBlock, ViewportBlock};
use keywords::listed;
pub use keywords::{
    DEFAULT_SEED, PIXEL_COORDINATES, REFLEXION_ALGORITHMS, TOP_BLOCKS, canonical, grey_default, shading_of,
};
use materials::MaterialEntry;
use shapes::ShapeEntry;

/// How to read a SIMRenderer file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Go on after an error as SIMRenderer does, reporting it as a warning.
    pub lenient: bool,
    /// The conventions the file's own settings (`pixel_coordinate`, the clipping planes)
    /// are applied over: SIMRenderer's, unless the command line names another preset.
    pub conventions: Conventions,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            lenient: false,
            conventions: Conventions::SIMRENDERER,
        }
    }
}

/// A scene read from a SIMRenderer file and the warnings met on the way.
#[derive(Clone, Debug)]
pub struct Parsed {
    pub scene: Scene,
    pub warnings: Vec<Warning>,
}

/// Reads a SIMRenderer scene file (a model's mesh file is found relative to it).
pub fn load(path: &Path, options: &Options) -> Result<Parsed, SceneError> {
    let text = crate::scene::read_text(path)?;
    parse(&text, &path.display().to_string(), options)
}

/// Reads SIMRenderer scene text; `file` names it in messages, and its folder is where a
/// model's mesh file is looked for.
pub fn parse(text: &str, file: &str, options: &Options) -> Result<Parsed, SceneError> {
    let mut reader = Reader {
        file,
        dir: Path::new(file).parent().unwrap_or(Path::new("")),
        lenient: options.lenient,
        items: lex::items(text),
        warnings: Vec::new(),
        seed: None,
        adaptive_threshold: None,
        objects: 0,
    };
    let raw = reader.scene_body()?;
    if raw.is_empty() {
        let start = At {
            line: 1,
            column: 1,
            field: "scene".to_string(),
        };
        let m = if raw.blocks == 0 {
            "the file holds no block (camera, viewport, raytracer, material, primitive, model or light): an empty scene, which SIMRenderer renders black, 500 x 500"
        } else {
            "every block of the file is dropped (the warnings above say why): an empty scene, rendered black, 500 x 500"
        };
        reader.warn(&start, m.to_string());
    }
    reader.build(raw, options.conventions)
}

/// A place in the file and the field it concerns (`block.keyword`).
#[derive(Clone, Debug)]
struct At {
    line: usize,
    column: usize,
    field: String,
}

/// What the file's blocks say, before the materials are bound.
#[derive(Default)]
struct Raw {
    /// How many top-level blocks the file holds, kept or dropped.
    blocks: usize,
    camera: Option<CameraBlock>,
    viewport: Option<ViewportBlock>,
    raytracer: Option<RaytracerBlock>,
    materials: Vec<MaterialEntry>,
    shapes: Vec<ShapeEntry>,
    lights: Vec<(At, Light)>,
}

impl Raw {
    /// Nothing kept: no block in the file (an empty file, or one of comments and blank
    /// lines), or every block dropped under `--lenient`.
    fn is_empty(&self) -> bool {
        self.camera.is_none()
            && self.viewport.is_none()
            && self.raytracer.is_none()
            && self.materials.is_empty()
            && self.shapes.is_empty()
            && self.lights.is_empty()
    }
}

/// One entry of a block: a keyword of the block (canonical) with its line, or a note.
enum Entry<'a> {
    Key(&'static str, Line<'a>),
    Note(Note<'a>),
    /// A line refused (and reported under `lenient`).
    Skip,
}

struct Reader<'a> {
    file: &'a str,
    dir: &'a Path,
    lenient: bool,
    items: lex::Items<'a>,
    warnings: Vec<Warning>,
    seed: Option<u64>,
    adaptive_threshold: Option<f64>,
    /// Objects read so far (a model's mesh may fill what the others leave of the limit).
    objects: usize,
}

fn at(line: &Line, block: &str) -> At {
    At {
        line: line.number,
        column: line.column,
        field: format!("{block}.{}", line.keyword),
    }
}

fn at_value(line: &Line, block: &str, column: usize) -> At {
    At {
        column,
        ..at(line, block)
    }
}

impl<'a> Reader<'a> {
    /// A warning, in both modes.
    fn warn(&mut self, at: &At, message: String) {
        self.warnings.push(Warning {
            file: self.file.to_string(),
            line: at.line,
            column: at.column,
            field: at.field.clone(),
            message,
        });
    }

    /// An error; under `lenient`, a warning saying what is done instead (`then`).
    fn problem(&mut self, at: &At, message: String, then: &str) -> Result<(), SceneError> {
        if self.lenient {
            self.warn(at, format!("{message}; {then}"));
            Ok(())
        } else {
            Err(SceneError::Invalid {
                file: self.file.to_string(),
                line: at.line,
                column: at.column,
                field: at.field.clone(),
                message,
            })
        }
    }

    fn next_item(&mut self) -> Option<Item<'a>> {
        self.items.next()
    }

    /// The next item of the open block, `None` at its `end` (or the end of the file, which
    /// SIMRenderer accepts as the end of every open block).
    fn body(&mut self) -> Option<Item<'a>> {
        match self.next_item()? {
            Item::Line(l) if canonical(&l.keyword) == Some("end") => None,
            item => Some(item),
        }
    }

    /// The next line of block `block` (its keyword as written) with a keyword of `keywords`,
    /// the notes and refused lines before it dealt with; `None` at the block's `end`. With
    /// `name`, a `lumiere:name` note sets it (primitives and models are named so).
    fn next_key(
        &mut self,
        block: &str,
        keywords: &[&'static str],
        mut name: Option<&mut Option<String>>,
    ) -> Result<Option<(&'static str, Line<'a>)>, SceneError> {
        while let Some(item) = self.body() {
            match self.entry(block, item, keywords)? {
                Entry::Key(k, l) => return Ok(Some((k, l))),
                Entry::Note(n) => {
                    if let Some(read) = self.note(&n, block, name.is_some())?
                        && let Some(slot) = name.as_deref_mut()
                    {
                        *slot = Some(read);
                    }
                }
                Entry::Skip => {}
            }
        }
        Ok(None)
    }

    /// Sorts an item of block `block` (its keyword as written): a keyword of `keywords`, a
    /// note, or a problem.
    fn entry(&mut self, block: &str, item: Item<'a>, keywords: &[&'static str]) -> Result<Entry<'a>, SceneError> {
        let l = match item {
            Item::Note(n) => return Ok(Entry::Note(n)),
            Item::Line(l) => l,
        };
        let place = at(&l, block);
        match canonical(&l.keyword) {
            Some(k) if keywords.contains(&k) => return Ok(Entry::Key(k, l)),
            Some(_) => {
                let message = format!(
                    "{:?} is not a keyword of {block} (a forgotten `end` before it?); {block}'s keywords are {}",
                    l.written,
                    listed(keywords)
                );
                self.problem(&place, message, "the line is skipped")?;
            }
            None => {
                let message = format!(
                    "unknown keyword {:?}; {block}'s keywords are {}",
                    l.written,
                    listed(keywords)
                );
                self.problem(&place, message, "the line is skipped")?;
            }
        }
        Ok(Entry::Skip)
    }

    /// A note outside a primitive or model: the seed or the adaptive threshold.
    fn note(&mut self, n: &Note, block: &str, named: bool) -> Result<Option<String>, SceneError> {
        let place = At {
            line: n.number,
            column: n.column,
            field: format!("{block}.lumiere:{}", n.key),
        };
        let value_at = At {
            column: n.value_column,
            ..place.clone()
        };
        match n.key {
            "name" if named => match serde_json::from_str::<String>(n.value) {
                Ok(name) => return Ok(Some(name)),
                Err(_) => {
                    let m = format!("expects a quoted name such as \"floor\", got {:?}", n.value);
                    self.problem(&value_at, m, "the note is skipped")?;
                }
            },
            "name" => {
                let m = "a name note belongs in a primitive or model block".to_string();
                self.problem(&place, m, "the note is skipped")?;
            }
            "seed" => match n.value.parse::<u64>() {
                Ok(seed) => self.seed = Some(seed),
                Err(_) => {
                    let m = format!("expects an integer in [0, {}], got {:?}", u64::MAX, n.value);
                    self.problem(&value_at, m, "the note is skipped")?;
                }
            },
            "adaptive_threshold" => match lex::java_double(n.value).filter(|t| (0.0..=255.0).contains(t)) {
                Some(t) => self.adaptive_threshold = Some(t),
                None => {
                    let m = format!("expects a number of 8-bit levels in [0, 255], got {:?}", n.value);
                    self.problem(&value_at, m, "the note is skipped")?;
                }
            },
            other => {
                let m = format!("unknown lumiere note {other:?}; the notes are name, seed, adaptive_threshold");
                self.problem(&place, m, "the note is skipped")?;
            }
        }
        Ok(None)
    }

    /// The value read from `line`, or `None` after a problem (under `lenient`, the value
    /// before it stays). A number that looks written with a decimal comma
    /// ([`lex::decimal_comma`]) is warned about, or named in the problem.
    fn value<T>(&mut self, block: &str, line: &Line, read: Result<T, ValueError>) -> Result<Option<T>, SceneError> {
        let comma = lex::decimal_comma(line.value, line.value_column);
        match read {
            Ok(v) => {
                if let Some((column, hint)) = comma {
                    self.warn(&at_value(line, block, column), hint);
                }
                Ok(Some(v))
            }
            Err(e) => {
                let place = at_value(line, block, e.column);
                let message = match comma {
                    Some((_, hint)) => format!("{}; {hint}", e.message),
                    None => e.message,
                };
                self.problem(&place, message, "the value before it is kept")?;
                Ok(None)
            }
        }
    }

    /// Sets `slot` to the value read from `line`, or leaves it after a problem
    /// ([`Reader::value`]).
    fn set<T>(
        &mut self,
        block: &str,
        line: &Line,
        read: Result<T, ValueError>,
        slot: &mut T,
    ) -> Result<(), SceneError> {
        if let Some(v) = self.value(block, line, read)? {
            *slot = v;
        }
        Ok(())
    }

    /// The top level of the file, up to a top-level `end` or the end of the file.
    fn scene_body(&mut self) -> Result<Raw, SceneError> {
        let mut raw = Raw::default();
        while let Some(item) = self.next_item() {
            let l = match item {
                Item::Note(n) => {
                    self.note(&n, "scene", false)?;
                    continue;
                }
                Item::Line(l) => l,
            };
            let place = at(&l, "scene");
            let keyword = canonical(&l.keyword);
            if keyword == Some("end") {
                if let Some(rest) = self.items.find_map(|i| match i {
                    Item::Line(l) => Some(l),
                    Item::Note(_) => None,
                }) {
                    let m = format!(
                        "SIMRenderer stops reading the scene at this top-level end: everything after it is ignored, from line {} ({:?}) on",
                        rest.number, rest.written
                    );
                    self.warn(&place, m);
                }
                return Ok(raw);
            }
            raw.blocks += 1;
            let block = l.keyword.clone();
            match keyword {
                Some("camera") => {
                    if let Some(c) = self.camera(&l)? {
                        raw.camera = Some(c);
                    }
                }
                Some("viewport") => {
                    if let Some(v) = self.viewport(&l)? {
                        raw.viewport = Some(v);
                    }
                }
                Some("raytracer") => raw.raytracer = Some(self.raytracer(&l)?),
                Some(kind @ ("material" | "texture_material")) => {
                    if let Some(m) = self.material(&l, kind == "texture_material")? {
                        raw.materials.push(m);
                    }
                }
                Some("primitive") => {
                    if let Some(p) = self.primitive(&l)? {
                        raw.shapes.push(p);
                    }
                }
                Some("model") => {
                    if let Some(m) = self.model(&l)? {
                        raw.shapes.push(m);
                    }
                }
                Some(kind @ ("ambient_light" | "directional_light" | "point_light")) => {
                    if let Some(light) = self.light(&l, kind)? {
                        raw.lights.push((place, light));
                    }
                }
                Some(
                    kind @ ("linear_aperture_light"
                    | "rectangular_aperture_light"
                    | "elliptical_aperture_light"
                    | "aperture_mask_light"),
                ) => {
                    if let Some(light) = self.aperture_light(&l, kind)? {
                        raw.lights.push((place, light));
                    }
                }
                Some(_) => {
                    let m = format!(
                        "{:?} is not a top-level block; the blocks are {}",
                        l.written,
                        listed(TOP_BLOCKS)
                    );
                    self.problem(&place, m, "the line is skipped")?;
                }
                None => {
                    let m = format!("unknown keyword {block:?}; the blocks are {}", listed(TOP_BLOCKS));
                    self.problem(&place, m, "the line is skipped")?;
                }
            }
        }
        self.warn_open_comment();
        Ok(raw)
    }

    /// A warning at a block comment the file never closes, when lines are written inside it:
    /// SIMRenderer, and lumiere as it, reads them as a comment.
    fn warn_open_comment(&mut self) {
        let Some(open) = self.items.open_comment() else {
            return;
        };
        let Some((first, last)) = open.held else {
            return;
        };
        let lines = if first == last {
            format!("line {first} is")
        } else {
            format!("lines {first} to {last} are")
        };
        let not_this = if open.closed_on_its_line {
            ", not the */ later on this line"
        } else {
            ""
        };
        let m = format!(
            "this block comment is never closed, so {lines} read as a comment, as SIMRenderer reads them: only a line whose first word is */ closes it{not_this}"
        );
        let place = At {
            line: open.line,
            column: open.column,
            field: "scene./*".to_string(),
        };
        self.warn(&place, m);
    }
}
