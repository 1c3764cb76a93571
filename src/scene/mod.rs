//! The in-memory scene: what a scene file describes, validated. [`crate::world::World`]
//! builds what rendering needs from it. Scene files are lumiere's TOML format ([`parse`])
//! or SIMRenderer's keyword blocks ([`simrenderer`]); [`load`] tells them apart.

mod decimal_comma;
mod file;
pub mod generate;
mod locate;
mod names;
mod overrides;
mod read_text;
pub mod rules;
mod serde_words;
pub mod simrenderer;
mod tag;
pub mod transform;

pub use file::{SceneError, load as load_toml, parse};
pub use names::{NameKey, ObjectNames};
pub use overrides::Overrides;
pub use read_text::{read_text, text_of};

use crate::conventions::Conventions;
use crate::film::{Film, Normalization};
use crate::light::Light;
use crate::material::Material;
use crate::shape::Shape;
use compact_str::CompactString;
use glam::DVec3;
use serde::ser::SerializeStruct;

/// The two scene file formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// lumiere's TOML format (scenes/README.md).
    Toml,
    /// SIMRenderer's keyword blocks (docs/simrenderer.md).
    SimRenderer,
}

impl Format {
    /// The names the command line takes.
    pub const NAMES: [&'static str; 2] = ["toml", "simrenderer"];

    pub fn name(self) -> &'static str {
        match self {
            Format::Toml => "toml",
            Format::SimRenderer => "simrenderer",
        }
    }
}

impl std::str::FromStr for Format {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "toml" => Ok(Format::Toml),
            "simrenderer" => Ok(Format::SimRenderer),
            other => Err(format!("must be \"toml\" or \"simrenderer\", got {other:?}")),
        }
    }
}

/// How to read a scene file.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LoadOptions {
    /// The format; `None`: told from the file ([`detect`]).
    pub format: Option<Format>,
    /// SIMRenderer files: go on past errors as SIMRenderer does, each reported as a
    /// warning (TOML files have no such mode).
    pub lenient: bool,
    /// SIMRenderer files: the conventions under the file's own settings (default:
    /// SIMRenderer's). TOML files say theirs in `[conventions]`.
    pub conventions: Option<crate::conventions::Conventions>,
}

/// A loaded scene, the format it was read in, and the reader's warnings.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub scene: Scene,
    pub format: Format,
    pub warnings: Vec<simrenderer::Warning>,
}

/// Reads and validates a scene file in either format ([`detect`]), SIMRenderer files under
/// SIMRenderer's conventions; warnings are dropped (see [`load_with`]).
pub fn load(path: &std::path::Path) -> Result<Scene, SceneError> {
    load_with(path, &LoadOptions::default()).map(|l| l.scene)
}

/// Reads and validates a scene file as `options` say.
pub fn load_with(path: &std::path::Path, options: &LoadOptions) -> Result<Loaded, SceneError> {
    let text = read_text(path)?;
    let file = path.display().to_string();
    let format = match options.format {
        Some(f) => f,
        None => detect(path, &text)?,
    };
    match format {
        Format::Toml => match parse(&text, &file) {
            Ok(scene) => Ok(Loaded {
                scene,
                format,
                warnings: Vec::new(),
            }),
            // The wrong guess: a SIMRenderer file named .toml.
            Err(SceneError::Invalid {
                file,
                line,
                column,
                field,
                message,
            }) if options.format.is_none() && first_keyword(&text).is_some_and(|(_, _, k)| is_block(&k)) => {
                Err(SceneError::Invalid {
                    file,
                    line,
                    column,
                    field,
                    message: format!(
                        "{message} (the file starts like a SIMRenderer scene: read it with --format simrenderer, or name it other than .toml)"
                    ),
                })
            }
            Err(e) => Err(e),
        },
        Format::SimRenderer => {
            let o = simrenderer::Options {
                lenient: options.lenient,
                conventions: options
                    .conventions
                    .unwrap_or(crate::conventions::Conventions::SIMRENDERER),
            };
            let parsed = simrenderer::parse(&text, &file, &o)?;
            Ok(Loaded {
                scene: parsed.scene,
                format,
                warnings: parsed.warnings,
            })
        }
    }
}

/// The first keyword of a SIMRenderer file (its line and its lower-case text), comments
/// and blank lines left out.
fn first_keyword(text: &str) -> Option<(usize, usize, String)> {
    simrenderer::lex::items(text).find_map(|i| match i {
        simrenderer::lex::Item::Line(l) => Some((l.number, l.column, l.keyword)),
        simrenderer::lex::Item::Note(_) => None,
    })
}

/// Whether `keyword` opens a SIMRenderer top-level block (or ends the scene).
fn is_block(keyword: &str) -> bool {
    simrenderer::canonical(keyword).is_some_and(|k| k == "end" || simrenderer::TOP_BLOCKS.contains(&k))
}

/// The format of a scene file: TOML when its name ends in `.toml`; otherwise SIMRenderer
/// when its first keyword (comments and blank lines left out) opens one of SIMRenderer's
/// blocks or the file has none; otherwise an error at that keyword saying why.
pub fn detect(path: &std::path::Path, text: &str) -> Result<Format, SceneError> {
    let toml = path
        .extension()
        .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case("toml"));
    if toml {
        return Ok(Format::Toml);
    }
    let Some((line, column, keyword)) = first_keyword(text) else {
        return Ok(Format::SimRenderer);
    };
    if is_block(&keyword) {
        return Ok(Format::SimRenderer);
    }
    let looks_toml = keyword.starts_with('[')
        || simrenderer::lex::split_lines(text)
            .get(line - 1)
            .is_some_and(|l| l.contains('='));
    let hint = if looks_toml {
        "it looks like TOML: name it .toml, or pass --format toml"
    } else {
        "pass --format toml or --format simrenderer"
    };
    Err(SceneError::Invalid {
        file: path.display().to_string(),
        line,
        column,
        field: "format".to_string(),
        message: format!(
            "cannot tell the scene's format: the file is not named .toml and its first keyword {keyword:?} opens none of SIMRenderer's blocks ({}); {hint}",
            simrenderer::TOP_BLOCKS.join(", ")
        ),
    })
}

/// Which specular term the local illumination model uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Specular {
    None,
    /// Phong: `(R.E)^n`.
    Phong,
    /// Blinn: `(N.H)^n`.
    Blinn,
}

/// The terms of the local illumination model (slides): each can be switched off to draw
/// the slides' "ambient only", "diffuse only", "specular only" figures. With `no_light`
/// (SIMRenderer's `reflexion_algorithm no_light`) the three are off and a surface shows
/// its diffuse colour `k_d S`, lit by no light and casting no shadow ray
/// ([`crate::shading::no_light`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct ShadingModel {
    pub ambient: bool,
    pub diffuse: bool,
    pub specular: Specular,
    pub no_light: bool,
}

impl ShadingModel {
    /// The diffuse colour `k_d S` alone, no light.
    pub const NO_LIGHT: ShadingModel = ShadingModel {
        ambient: false,
        diffuse: false,
        specular: Specular::None,
        no_light: true,
    };
}

impl Default for ShadingModel {
    /// Chapter 7.4b's choice: ambient + Lambert + Blinn.
    fn default() -> Self {
        ShadingModel {
            ambient: true,
            diffuse: true,
            specular: Specular::Blinn,
            no_light: false,
        }
    }
}

/// Image and tracing settings (the `[image]` and `[render]` tables).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel, in [1, [`MAX_SAMPLES`](crate::limits::MAX_SAMPLES)], one in each
    /// cell of the pixel's [`SampleGrid`].
    pub samples_per_pixel: u32,
    pub seed: u64,
    /// Recursion depth as counted in the chapter's figures: 1 = no secondary rays.
    pub depth: u32,
    pub shading: ShadingModel,
    /// Cast shadow rays (off: every light reaches every point facing it).
    pub shadows: bool,
    /// Colour of rays that hit nothing.
    pub background: DVec3,
    /// How each pixel's colour is brought into [0, 1] for 8-bit images.
    #[serde(skip_serializing_if = "Normalization::is_clamp_channel")]
    pub color_normalization: Normalization,
    /// Adaptive depth control: a secondary ray is not traced when the most it could add to
    /// the pixel is below this many 8-bit levels (0 = off).
    pub adaptive_threshold: f64,
    /// Where the chapter's and SIMRenderer's conventions differ, which this scene follows.
    pub conventions: Conventions,
    /// The caustic pass (the `[caustics]` table); `None`, the default, is the chapter's
    /// Whitted tracer alone.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub caustics: Option<CausticSettings>,
}

impl Settings {
    /// The film of a whole render at these settings: its size and normalization, with
    /// `pixels` (row-major, `width * height` of them).
    pub fn film(&self, pixels: Vec<DVec3>) -> Film {
        Film {
            width: self.width,
            height: self.height,
            pixels,
            normalization: self.color_normalization,
        }
    }
}

/// The opt-in caustic pass of the `[caustics]` table (see [`crate::caustics`]): photons
/// leave the lights towards the objects that reflect or refract, bounce off and through
/// them, and are stored where they land on diffuse surfaces; at each hit of a camera path
/// their density is read back as light.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct CausticSettings {
    /// Photons emitted in all, shared among the lights by the power their specular targets
    /// intercept.
    pub photons: u64,
    /// Radius of the density estimate's disk around a shading point (scene units).
    pub radius: f64,
    /// How a photon's flux is weighed by its distance from the shading point.
    pub filter: PhotonFilter,
    /// Most specular bounces a photon makes before it is dropped.
    pub bounces: u32,
    /// The seed of the photons' streams; `None`: the image's seed.
    pub seed: Option<u64>,
}

/// The density estimate's filter (Jensen, "Realistic Image Synthesis Using Photon Mapping",
/// 2001, section 7.2): the weight of a photon at distance `d` within the radius `r`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PhotonFilter {
    /// Every photon in the disk weighs 1.
    Flat,
    /// Jensen's cone filter with `k = 1`: `1 - d / r`.
    Cone,
    /// Epanechnikov's kernel: `1 - d^2 / r^2`.
    Epanechnikov,
}

impl PhotonFilter {
    /// The names the `[caustics]` table takes.
    pub const NAMES: [&'static str; 3] = ["flat", "cone", "epanechnikov"];
}

impl Settings {
    /// The pixel's sample grid, [`SampleGrid::of`] the sample count.
    pub fn sample_grid(&self) -> SampleGrid {
        SampleGrid::of(self.samples_per_pixel)
    }
}

/// The cells a pixel is cut into, one sample in each: `columns` across, `rows` down, in
/// row-major order (sample `k` is cell `(k mod columns, k div columns)`), so jittered
/// samples are stratified, one in each cell, and their mean stays unbiased.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SampleGrid {
    pub columns: u32,
    pub rows: u32,
}

impl SampleGrid {
    /// The most nearly square grid of `samples` cells: `columns` the largest divisor of
    /// `samples` not above its square root, `rows = samples / columns` (2 samples are
    /// 1 column x 2 rows, 6 are 2 x 3, 8 are 2 x 4, a prime `p` is 1 x `p`, a square `n^2`
    /// is `n x n`).
    ///
    /// Of a non-square count's two shapes the longer side runs down the pixel: a floor
    /// seen from above its horizon, and the horizontal edges of objects standing on it,
    /// change faster down the image than across it. At 400 x 300 against a 256-sample
    /// render (a 16 x 16 grid), seeds 42, 7 and 99, the RMS error in 8-bit levels of the
    /// reference scene is 3.64 to 3.66 with 2 samples as 1 x 2 where 2 x 1 gives 4.18 to
    /// 4.26, and 1.30 with 8 as 2 x 4 where 4 x 2 gives 1.46 to 1.52; the geometry scene's
    /// 2.85 to 3.05 against 3.04 to 3.15, and 1.01 to 1.04 against 1.12 to 1.18; the mirrors
    /// scene's are the same either way within the seeds' spread.
    pub fn of(samples: u32) -> SampleGrid {
        let columns = (1..=samples.isqrt())
            .rev()
            .find(|&c| samples.is_multiple_of(c))
            .unwrap_or(1);
        SampleGrid {
            columns,
            rows: samples / columns,
        }
    }
}

/// Camera as written in the scene file; the aspect ratio comes from the image size.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CameraSpec {
    pub position: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    pub vfov_deg: f64,
}

/// One object: a shape with a material, and the key of its name in [`Scene::names`]
/// (48 bytes: a million spheres take 48 MB).
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    pub shape: Shape,
    /// Index into `Scene::materials`.
    pub material: u32,
    /// The name given in the file, or `<kind>#<index>`, is `Scene::names.get(name)`.
    pub name: NameKey,
}

impl Object {
    /// Index into `Scene::materials`.
    #[inline]
    pub fn material(&self) -> usize {
        self.material as usize
    }
}

/// A validated scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub settings: Settings,
    pub camera: CameraSpec,
    pub materials: Vec<Material>,
    pub material_names: Vec<String>,
    /// Whether each material gives its metal factor `m`; the others take the conventions'
    /// default highlight ([`Scene::set_conventions`]).
    pub metal_given: Vec<bool>,
    pub objects: Vec<Object>,
    /// The objects' names, by their [`Object::name`] keys.
    pub names: ObjectNames,
    pub lights: Vec<Light>,
}

/// An object as serialized: its name, shape and material.
#[derive(serde::Serialize)]
struct NamedObject<'a> {
    name: CompactString,
    shape: &'a Shape,
    material: usize,
}

impl serde::Serialize for Scene {
    /// The fields in order, each object with its name.
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let objects: Vec<NamedObject> = self
            .objects
            .iter()
            .map(|o| NamedObject {
                name: self.name_of(o),
                shape: &o.shape,
                material: o.material(),
            })
            .collect();
        let mut s = serializer.serialize_struct("Scene", 7)?;
        s.serialize_field("settings", &self.settings)?;
        s.serialize_field("camera", &self.camera)?;
        s.serialize_field("materials", &self.materials)?;
        s.serialize_field("material_names", &self.material_names)?;
        s.serialize_field("metal_given", &self.metal_given)?;
        s.serialize_field("objects", &objects)?;
        s.serialize_field("lights", &self.lights)?;
        s.end()
    }
}

impl Scene {
    /// The name of `object`, one of this scene's objects.
    pub fn name_of(&self, object: &Object) -> CompactString {
        self.names.get(object.name)
    }

    /// Appends an object named `name`.
    pub fn push_object(&mut self, name: &str, shape: Shape, material: usize) {
        let name = self.names.add(name);
        self.objects.push(Object {
            shape,
            material: material as u32,
            name,
        });
    }

    /// Follows `conventions` from now on: the materials that give no metal factor take its
    /// default highlight.
    pub fn set_conventions(&mut self, conventions: Conventions) {
        self.settings.conventions = conventions;
        for (material, &given) in self.materials.iter_mut().zip(&self.metal_given) {
            if !given {
                material.metal = conventions.default_highlight.metal();
            }
        }
    }

    /// The sum of the ambient lights' colours, `L_a`.
    pub fn ambient(&self) -> DVec3 {
        self.lights.iter().map(Light::ambient).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::SampleGrid;

    /// Columns and rows of `samples`, as a pair.
    fn shape(samples: u32) -> (u32, u32) {
        let g = SampleGrid::of(samples);
        (g.columns, g.rows)
    }

    /// The grids of 1 to 36 samples, worked out on paper (columns, rows), then a prime and
    /// the most samples.
    #[test]
    fn the_grid_is_the_most_nearly_square_factorisation() {
        #[rustfmt::skip]
        let by_hand = [
            (1, 1), (1, 2), (1, 3), (2, 2), (1, 5), (2, 3), (1, 7), (2, 4), (3, 3),
            (2, 5), (1, 11), (3, 4), (1, 13), (2, 7), (3, 5), (4, 4), (1, 17), (3, 6),
            (1, 19), (4, 5), (3, 7), (2, 11), (1, 23), (4, 6), (5, 5), (2, 13), (3, 9),
            (4, 7), (1, 29), (5, 6), (1, 31), (4, 8), (3, 11), (2, 17), (5, 7), (6, 6),
        ];
        for (samples, expected) in (1..=36).zip(by_hand) {
            assert_eq!(shape(samples), expected, "{samples}");
        }
        assert_eq!(shape(1021), (1, 1021));
        assert_eq!(shape(1000), (25, 40));
        assert_eq!(shape(crate::limits::MAX_SAMPLES), (32, 32));
    }

    /// Every count the scene takes: one cell a sample, rows at least columns, and no
    /// divisor between the columns and the square root (so no squarer grid).
    #[test]
    fn every_grid_is_whole_and_as_square_as_its_count_allows() {
        for samples in 1..=crate::limits::MAX_SAMPLES {
            let (columns, rows) = shape(samples);
            assert_eq!(columns * rows, samples, "{samples}");
            assert!(columns <= rows, "{samples}: {columns} x {rows}");
            let squarer = (columns + 1..=samples.isqrt()).find(|&c| samples.is_multiple_of(c));
            assert_eq!(squarer, None, "{samples}: {columns} x {rows}");
        }
        // A perfect square is its side both ways.
        for side in 1..=32 {
            assert_eq!(shape(side * side), (side, side));
        }
        // No sample, no panic: one column of no row.
        assert_eq!(shape(0), (1, 0));
    }
}
