//! The TOML scene format: deserialisation (unknown fields are errors, so a typo cannot
//! silently change a figure) and validation of every value against its allowed range.
//! Every error names the file, line and column, the field, and what is allowed; a missing
//! required top-level table (`[image]`, `[camera]`) has no place in the file and is named
//! with the file alone. A mesh's `.obj` file is read relative to the scene file's
//! directory, and its errors are placed on the entry's `file` field, naming the `.obj` file
//! and its line.
//! The format is documented in `scenes/README.md`.
//!
//! This module owns [`load`], [`parse`] and their errors ([`SceneError`]), the whole file
//! ([`FileScene`]) and the scene made of it; each table's own fields and checks are in the
//! modules below.

mod check;
mod generate;
mod lights;
mod material;
mod mesh;
mod shapes;
mod tables;
mod transform;

use super::locate::{FieldError, FieldPath, first_given, line_col, locate, path_at, written};
use super::tag;
use super::{CameraSpec, Object, ObjectNames, Scene, Settings, ShadingModel, Specular};
use super::{decimal_comma, serde_words};
use crate::conventions::Highlight;
use crate::film::Normalization;
use crate::light::Light;
use crate::limits;
use crate::material::{Material, TermColors};
use crate::shape::Shape;
use check::{Check, color, direction, fail, in_range, placed, positive, running_total, vec3};
use compact_str::CompactString;
use generate::FileGenerate;
use lights::{FileLight, LIGHT_TYPES};
use material::FileMaterial;
use serde::Deserialize;
use shapes::{FileShape, SHAPE_TYPES};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use tables::{FileCamera, FileCaustics, FileConventions, FileImage, FileRender, MAX_VFOV};
use toml::de::DeTable;

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("{path}: cannot read the scene file: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Syntax, type or unknown-field error, or a value out of range.
    #[error("{file}:{line}:{column}: {field}: {message}")]
    Invalid {
        file: String,
        line: usize,
        column: usize,
        /// The field path (`shapes[2].radius`), or `TOML` for syntax errors.
        field: String,
        message: String,
    },
    /// Required top-level tables that the file does not have (`[camera]`): there is no
    /// place in the file to point at.
    #[error("{file}: the file has {}", absent(.tables))]
    MissingTables { file: String, tables: Vec<&'static str> },
}

/// The top-level keys of the format: the fields of [`FileScene`].
const TOP_LEVEL: [&str; 9] = [
    "image",
    "camera",
    "render",
    "conventions",
    "caustics",
    "materials",
    "shapes",
    "lights",
    "generate",
];
/// The top-level tables every scene file must have, in the order of the format's docs.
const REQUIRED_TABLES: [&str; 2] = ["image", "camera"];

/// `no [image] table and no [camera] table`.
fn absent(tables: &[&str]) -> String {
    tables
        .iter()
        .map(|t| format!("no [{t}] table"))
        .collect::<Vec<_>>()
        .join(" and ")
}

/// Reads and validates a scene file.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let text = crate::scene::read_text(path)?;
    parse(&text, &path.display().to_string())
}

/// Parses and validates scene text; `file` is the name used in error messages.
pub fn parse(text: &str, file: &str) -> Result<Scene, SceneError> {
    parse_as_written(text, text, file)
}

/// [`parse`] of `text`, whose numbers are shown in messages as `written` writes them: the
/// same text, or the same with a real too large for a double (`1e400`, which the `toml`
/// crate refuses without a range) read as an infinity, so that its field's rule names
/// its range and the number as written ([`infinity_in_place`]).
fn parse_as_written(text: &str, written_text: &str, file: &str) -> Result<Scene, SceneError> {
    let at = |offset: usize, field: String, message: String| {
        let (line, column) = line_col(text, offset);
        SceneError::Invalid {
            file: file.to_string(),
            line,
            column,
            field,
            message,
        }
    };
    let located = |e: FieldError| {
        let message = match e.got {
            Some(x) => format!("{}, got {}", e.message, written(written_text, &e.path, x)),
            None => e.message,
        };
        at(locate(text, &e.path), e.path.to_string(), message)
    };
    let mut root = DeTable::parse(text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        let message = match (e.message().trim(), e.span()) {
            // The span is the second key: name it as written.
            ("duplicate key", Some(span)) => {
                let key = text.get(span.clone()).unwrap_or_default();
                match first_given(text, span) {
                    Some(line) => {
                        format!("duplicate key `{key}`: given first at line {line}; a key is given once in its table")
                    }
                    None => format!("duplicate key `{key}`: a key is given once in its table"),
                }
            }
            (message, _) => message.to_string(),
        };
        let message = match decimal_comma::toml_hint(text, offset) {
            Some(hint) => format!("{message}; {hint}"),
            None => message,
        };
        at(offset, "TOML".to_string(), message)
    })?;
    // A missing required table has no place in the file to point at: it is named instead. A
    // file with an unknown top-level key (`[kamera]`) gets the located unknown-field error
    // below, which points at the likely misspelling.
    let top = root.get_ref();
    let missing: Vec<&'static str> = REQUIRED_TABLES.into_iter().filter(|t| !top.contains_key(*t)).collect();
    if !missing.is_empty() && top.keys().all(|k| TOP_LEVEL.contains(&k.get_ref().as_ref())) {
        return Err(SceneError::MissingTables {
            file: file.to_string(),
            tables: missing,
        });
    }
    tag::lift(root.get_mut(), "shapes", SHAPE_TYPES).map_err(located)?;
    tag::lift(root.get_mut(), "lights", LIGHT_TYPES).map_err(located)?;
    let raw = FileScene::deserialize(toml::de::Deserializer::from(root));
    if let Err(e) = &raw
        && e.message().trim() == "floating-point number overflowed"
        && let Some(read_as) = e.span().and_then(|span| infinity_in_place(text, span))
    {
        return parse_as_written(&read_as, written_text, file);
    }
    let raw = raw.map_err(|e| {
        // A type, length or unknown-field error knows its span only: name the field there.
        let (offset, path) = e
            .span()
            .map_or((0, FieldPath::default()), |span| (span.start, path_at(text, span)));
        let field = if path.0.is_empty() {
            "TOML".to_string()
        } else {
            path.to_string()
        };
        let mut message = serde_words::plain(e.message().trim());
        // A value the message quotes as read (`inf`) is quoted as written (`1e400`).
        if let Some(span) = e.span()
            && let (Some(read), Some(given)) = (number_at(text, span.start), number_at(written_text, span.start))
            && read != given
        {
            message = message.replace(&format!("`{read}`"), &format!("`{given}`"));
        }
        at(offset, field, message)
    })?;
    // Mesh files are read relative to the scene file.
    let dir = Path::new(file).parent().unwrap_or(Path::new(""));
    raw.validate(dir).map_err(located)
}

/// `text` with the real at `span` written as an infinity of its sign, padded with spaces to
/// its length (so every place in the text stays where it was); `None` when the span holds no
/// number that long.
fn infinity_in_place(text: &str, span: std::ops::Range<usize>) -> Option<String> {
    let number = number_at(text, span.start).filter(|n| n.len() == span.len())?;
    let infinity = if number.starts_with('-') { "-inf" } else { "inf" };
    let padding = " ".repeat(number.len().checked_sub(infinity.len())?);
    Some(format!(
        "{}{infinity}{padding}{}",
        &text[..span.start],
        &text[span.end..]
    ))
}

/// The number written at byte `start` of `text` (digits, letters, signs, points and
/// underscores), if any.
fn number_at(text: &str, start: usize) -> Option<&str> {
    let rest = text.get(start..)?;
    let end = rest
        .find(|c: char| !(c.is_ascii_alphanumeric() || "+-._".contains(c)))
        .unwrap_or(rest.len());
    (end > 0).then(|| &rest[..end])
}

/// A whole scene file as serde reads it: one field per top-level key ([`TOP_LEVEL`]).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileScene {
    image: FileImage,
    camera: FileCamera,
    #[serde(default)]
    render: FileRender,
    #[serde(default)]
    conventions: FileConventions,
    caustics: Option<FileCaustics>,
    #[serde(default)]
    materials: BTreeMap<String, FileMaterial>,
    #[serde(default)]
    shapes: Vec<FileShape>,
    #[serde(default)]
    lights: Vec<FileLight>,
    #[serde(default)]
    generate: Vec<FileGenerate>,
}

/// An object as the file lists it, its name not yet set aside in the scene's
/// [`ObjectNames`].
#[derive(Debug)]
struct Listed {
    name: CompactString,
    shape: Shape,
    material: usize,
}

impl FileScene {
    fn validate(self, dir: &Path) -> Check<Scene> {
        let root = FieldPath::default();
        let settings = self.settings(&root)?;
        let camera = self.camera(&root.key("camera"))?;
        let highlight = settings.conventions.default_highlight;
        let (materials, material_names, metal_given) = self.materials(&root.key("materials"), highlight, dir)?;
        let path = root.key("shapes");
        if self.shapes.len() > limits::MAX_OBJECTS {
            return fail(
                &path,
                format!("at most {} shapes, got {}", limits::MAX_OBJECTS, self.shapes.len()),
            );
        }
        let mut objects: Vec<Object> = Vec::new();
        let mut names = ObjectNames::default();
        for (i, s) in self.shapes.into_iter().enumerate() {
            // A mesh may fill what the scene's other objects leave of the limit.
            let room = limits::MAX_OBJECTS.saturating_sub(objects.len());
            let listed = s.validate(&path.index(i), i, &material_names, dir, room)?;
            objects.extend(listed.into_iter().map(|l| Object {
                shape: l.shape,
                material: l.material as u32,
                name: names.add(l.name),
            }));
        }
        let path = root.key("generate");
        let tables = self
            .generate
            .iter()
            .enumerate()
            .map(|(i, g)| g.validate(&path.index(i), &material_names))
            .collect::<Check<Vec<_>>>()?;
        running_total(
            &path,
            "count",
            objects.len() as u64,
            tables.iter().map(|g| g.count as u64),
            limits::MAX_OBJECTS as u64,
            "objects with this table",
        )?;
        objects.reserve_exact(tables.iter().map(|g| g.count).sum());
        for (i, g) in tables.iter().enumerate() {
            g.append_to(i, names.add_table(g.count), &mut objects);
        }
        let path = root.key("lights");
        if self.lights.len() > limits::MAX_LIGHTS {
            return fail(
                &path,
                format!("at most {} lights, got {}", limits::MAX_LIGHTS, self.lights.len()),
            );
        }
        let lights = self
            .lights
            .into_iter()
            .enumerate()
            .map(|(i, l)| l.validate(&path.index(i), dir))
            .collect::<Check<Vec<_>>>()?;
        // Each point of a fixed light is kept in memory and every point is a shadow ray per
        // shading point: bound the sum, not only each light.
        running_total(
            &path,
            "points",
            0,
            lights.iter().map(|l| match l {
                Light::Area(a) => a.count as u64,
                Light::Aperture(a) => a.oscillators.len() as u64,
                _ => 0,
            }),
            limits::MAX_TOTAL_LIGHT_POINTS,
            "light points with this light",
        )?;
        Ok(Scene {
            settings,
            camera,
            materials,
            material_names,
            metal_given,
            objects,
            names,
            lights,
        })
    }

    fn settings(&self, root: &FieldPath) -> Check<Settings> {
        let img = root.key("image");
        let r = root.key("render");
        let width = placed(&img.key("width"), limits::check_dimension(self.image.width))?;
        let height = placed(&img.key("height"), limits::check_dimension(self.image.height))?;
        placed(&img.key("width"), limits::check_pixel_count(width, height))?;
        let samples_per_pixel = placed(
            &img.key("samples_per_pixel"),
            limits::check_samples(self.image.samples_per_pixel),
        )?;
        let depth = placed(&r.key("depth"), limits::check_depth(self.render.depth))?;
        let specular = match self.render.specular.as_str() {
            "blinn" => Specular::Blinn,
            "phong" => Specular::Phong,
            "none" => Specular::None,
            other => {
                return fail(
                    &r.key("specular"),
                    format!("must be \"blinn\", \"phong\" or \"none\", got {other:?}"),
                );
            }
        };
        let shading = ShadingModel {
            ambient: self.render.ambient,
            diffuse: self.render.diffuse,
            specular,
            no_light: self.render.no_light,
        };
        if shading.no_light && shading != ShadingModel::NO_LIGHT {
            return fail(
                &r.key("no_light"),
                "shows the diffuse colour in place of every local term: set ambient = false, diffuse = false and specular = \"none\" with it".to_string(),
            );
        }
        let color_normalization = match self.render.color_normalization.as_str() {
            "clamp_channel" => Normalization::ClampChannel,
            "division_factor" => Normalization::DivisionFactor,
            other => {
                return fail(
                    &r.key("color_normalization"),
                    format!("must be \"clamp_channel\" or \"division_factor\", got {other:?}"),
                );
            }
        };
        Ok(Settings {
            width,
            height,
            samples_per_pixel,
            seed: self.image.seed,
            depth,
            shading,
            shadows: self.render.shadows,
            background: color(&r.key("background"), self.render.background, limits::MAX_LIGHT)?,
            color_normalization,
            adaptive_threshold: in_range(
                &r.key("adaptive_threshold"),
                self.render.adaptive_threshold,
                0.0,
                limits::MAX_ADAPTIVE_THRESHOLD,
            )?,
            conventions: self.conventions.validate(&root.key("conventions"))?,
            caustics: self
                .caustics
                .as_ref()
                .map(|c| c.validate(&root.key("caustics")))
                .transpose()?,
        })
    }

    fn camera(&self, path: &FieldPath) -> Check<CameraSpec> {
        let c = &self.camera;
        let position = vec3(&path.key("position"), c.position)?;
        let look_at = vec3(&path.key("look_at"), c.look_at)?;
        let up = direction(&path.key("up"), c.up)?;
        let forward = look_at - position;
        if forward.length() <= 1e-12 {
            return fail(&path.key("look_at"), "must differ from the camera position");
        }
        if forward.normalize().cross(up).length() < 1e-9 {
            return fail(
                &path.key("up"),
                "must not be parallel to the viewing direction (look_at - position)",
            );
        }
        let vfov_deg = positive(&path.key("vfov"), c.vfov, MAX_VFOV)?;
        Ok(CameraSpec {
            position,
            look_at,
            up,
            vfov_deg,
        })
    }

    /// The materials, their names and whether each gives its metal factor (the others take
    /// `highlight`'s).
    fn materials(
        &self,
        path: &FieldPath,
        highlight: Highlight,
        dir: &Path,
    ) -> Check<(Vec<Material>, Vec<String>, Vec<bool>)> {
        let mut materials = vec![Material {
            metal: highlight.metal(),
            ..Material::default()
        }];
        let mut names = vec!["default".to_string()];
        let mut metal_given = vec![false];
        for (name, m) in &self.materials {
            let p = path.key(name);
            let d = Material::default();
            let unit = |key: &str, v: Option<f64>, default: f64| in_range(&p.key(key), v.unwrap_or(default), 0.0, 1.0);
            let mat = Material {
                color: color(&p.key("color"), m.color, 1.0)?,
                ka: unit("ka", m.ka, d.ka)?,
                kd: unit("kd", m.kd, d.kd)?,
                ks: unit("ks", m.ks, d.ks)?,
                shininess: in_range(
                    &p.key("shininess"),
                    m.shininess.unwrap_or(d.shininess),
                    0.0,
                    limits::MAX_SHININESS,
                )?,
                metal: unit("m", m.m, highlight.metal())?,
                kr: unit("kr", m.kr, d.kr)?,
                kt: unit("kt", m.kt, d.kt)?,
                ior: positive(&p.key("n"), m.n.unwrap_or(d.ior), limits::MAX_IOR)?,
                term_colors: TermColors::of(
                    m.ambient_color
                        .map(|c| color(&p.key("ambient_color"), c, 1.0))
                        .transpose()?,
                    m.specular_color
                        .map(|c| color(&p.key("specular_color"), c, 1.0))
                        .transpose()?,
                    m.textures(&p, dir)?,
                ),
            };
            if m.m.is_some() && mat.specular_color().is_some() {
                return fail(
                    &p.key("m"),
                    "shapes the specular colour m S + (1 - m), which specular_color gives: give one of them",
                );
            }
            if mat.kr + mat.kt > 1.0 {
                return fail(
                    &p.key("kt"),
                    format!(
                        "kr + kt must be at most 1 (no ray may carry more than its parent), got {} + {}",
                        mat.kr, mat.kt
                    ),
                );
            }
            if name == "default" {
                materials[0] = mat;
                metal_given[0] = m.m.is_some();
            } else {
                materials.push(mat);
                names.push(name.clone());
                metal_given.push(m.m.is_some());
            }
        }
        Ok((materials, names, metal_given))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every listed `type` is a variant the deserialiser knows: a listed name that serde
    /// did not know would pass `tag::lift` and fail as an unknown variant.
    #[test]
    fn the_type_lists_match_the_enums() {
        for (array, types) in [("shapes", SHAPE_TYPES), ("lights", LIGHT_TYPES)] {
            for t in types {
                let text = format!(
                    "[image]\nwidth = 1\nheight = 1\n[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n[[{array}]]\ntype = \"{t}\"\n"
                );
                if let Err(e) = parse(&text, "t.toml") {
                    assert!(!e.to_string().contains("variant"), "{t}: {e}");
                }
            }
        }
    }

    /// `TOP_LEVEL` lists the keys serde knows at the top level, in its order: with a key
    /// left out, a file that has that key and no `[camera]` would get serde's missing-field
    /// error, pointed at the wrong place, instead of the missing table named.
    #[test]
    fn the_top_level_list_matches_the_file_scene() {
        let e = parse("[image]\nwidth = 1\nheight = 1\n[kamera]\n", "t.toml").unwrap_err();
        let listed = TOP_LEVEL.map(|k| format!("`{k}`")).join(", ");
        assert_eq!(
            e.to_string(),
            format!("t.toml:4:2: kamera: unknown field `kamera`, expected one of {listed}")
        );
        for required in REQUIRED_TABLES {
            assert!(TOP_LEVEL.contains(&required));
        }
    }
}
