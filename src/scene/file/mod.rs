//! The TOML scene format: deserialisation (unknown fields are errors, so a typo cannot
//! silently change a figure) and validation of every value against its allowed range.
//! Every error names the file, line and column, the field, and what is allowed; a missing
//! required top-level table (`[image]`, `[camera]`) has no place in the file and is named
//! with the file alone. A mesh's `.obj` file is read relative to the scene file's
//! directory, and its errors are placed on the entry's `file` field, naming the `.obj` file
//! and its line.
//! The format is documented in `scenes/README.md`.

mod check;
mod generate;
mod lights;
mod material;
mod mesh;
mod tables;
mod transform;

use super::locate::{FieldError, FieldPath, line_col, locate, path_at, written};
use super::tag;
use super::{CameraSpec, Object, ObjectNames, Scene, Settings, ShadingModel, Specular};
use super::{decimal_comma, serde_words};
use crate::conventions::Highlight;
use crate::light::Light;
use crate::limits;
use crate::material::Material;
use crate::shape::{
    Cone, Cuboid, Cylinder, Disk, Lens, Plane, Rectangle, Shape, Sphere, SphericalCap, Torus, Triangle,
};
use check::{
    Check, Xyz, angles, color, direction, fail, in_range, plus_z, positive, running_total, spanning_edges, vec3,
};
use compact_str::CompactString;
use generate::FileGenerate;
use glam::DVec3;
use lights::{FileLight, LIGHT_TYPES};
use material::{FileMaterial, resolve_material};
use mesh::FileMesh;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use tables::{FileCamera, FileCaustics, FileConventions, FileImage, FileRender, MAX_VFOV};
use toml::de::DeTable;
use transform::{FileTransform, moved, transform_of};

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
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse(&text, &path.display().to_string())
}

/// Parses and validates scene text; `file` is the name used in error messages.
pub fn parse(text: &str, file: &str) -> Result<Scene, SceneError> {
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
            Some(x) => format!("{}, got {}", e.message, written(text, &e.path, x)),
            None => e.message,
        };
        at(locate(text, &e.path), e.path.to_string(), message)
    };
    let mut root = DeTable::parse(text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        let message = match (e.message().trim(), e.span()) {
            // The span is the second key: name it as written.
            ("duplicate key", Some(span)) => format!(
                "duplicate key `{}`: a key is given once in its table",
                text.get(span).unwrap_or_default()
            ),
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
    let raw = FileScene::deserialize(toml::de::Deserializer::from(root)).map_err(|e| {
        // A type, length or unknown-field error knows its span only: name the field there.
        let (offset, path) = e
            .span()
            .map_or((0, FieldPath::default()), |span| (span.start, path_at(text, span)));
        let field = if path.0.is_empty() {
            "TOML".to_string()
        } else {
            path.to_string()
        };
        at(offset, field, serde_words::plain(e.message().trim()))
    })?;
    // Mesh files are read relative to the scene file.
    let dir = Path::new(file).parent().unwrap_or(Path::new(""));
    raw.validate(dir).map_err(located)
}

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

/// The values of `type` in `[[shapes]]`, in the order of [`FileShape`]'s variants.
const SHAPE_TYPES: &[&str] = &[
    "plane",
    "rectangle",
    "disk",
    "sphere",
    "box",
    "cylinder",
    "cone",
    "mirror_pair",
    "torus",
    "triangle",
    "tube",
    "mesh",
    "spherical_cap",
    "lens",
];

/// One `[[shapes]]` entry, tagged by its `type` (lifted to an outer key by `tag::lift`, so that
/// errors keep their positions).
#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
enum FileShape {
    Plane(FilePlane),
    Rectangle(FileRectangle),
    Disk(FileDisk),
    Sphere(FileSphere),
    Box(FileBox),
    Cylinder(FileCapped),
    Cone(FileCapped),
    MirrorPair(FileMirrorPair),
    Torus(FileTorus),
    Triangle(FileTriangle),
    Tube(FileTube),
    Mesh(FileMesh),
    SphericalCap(FileSphericalCap),
    Lens(FileLens),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FilePlane {
    point: Xyz,
    normal: Xyz,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileRectangle {
    corner: Xyz,
    edge1: Xyz,
    edge2: Xyz,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileDisk {
    center: Xyz,
    normal: Xyz,
    radius: f64,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileSphere {
    center: Xyz,
    radius: f64,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileBox {
    center: Xyz,
    size: Xyz,
    #[serde(default)]
    rotation: Xyz,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

/// A cylinder or a cone: the same fields, checked the same way ([`FileCapped::frame`]).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileCapped {
    base: Xyz,
    #[serde(default = "plus_z")]
    axis: Xyz,
    height: f64,
    radius: f64,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileMirrorPair {
    #[serde(default)]
    hinge: Xyz,
    #[serde(default = "minus_y")]
    bisector: Xyz,
    opening: f64,
    length: f64,
    height: f64,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileTorus {
    center: Xyz,
    #[serde(default = "plus_z")]
    axis: Xyz,
    major_radius: f64,
    minor_radius: f64,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

/// Three points; the normal by the right-hand rule `(p1 - p0) x (p2 - p0)`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileTriangle {
    p0: Xyz,
    p1: Xyz,
    p2: Xyz,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

/// SIMRenderer's spherical cap: the disk (`center`, `normal`, `radius`) and the signed
/// radius of curvature (positive: bulging along the normal).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileSphericalCap {
    center: Xyz,
    #[serde(default = "plus_z")]
    normal: Xyz,
    radius: f64,
    curvature: f64,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

/// SIMRenderer's lens: the edge from `base` along `axis` for `thickness` (0: none), of
/// radius `radius`, closed by caps of signed radii of curvature `curvature1` (at `base`)
/// and `curvature2` (at the far end); positive is convex.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileLens {
    base: Xyz,
    #[serde(default = "plus_z")]
    axis: Xyz,
    thickness: f64,
    radius: f64,
    curvature1: f64,
    curvature2: f64,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

/// A cylinder without caps from `start` to `end`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileTube {
    start: Xyz,
    end: Xyz,
    radius: f64,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

fn minus_y() -> Xyz {
    Xyz([0.0, -1.0, 0.0])
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
        let check = |path: FieldPath, res: Result<(), String>| res.or_else(|m| fail(&path, m));
        check(img.key("width"), limits::check_dimension(self.image.width))?;
        check(img.key("height"), limits::check_dimension(self.image.height))?;
        check(
            img.key("width"),
            limits::check_pixel_count(self.image.width, self.image.height),
        )?;
        check(
            img.key("samples_per_pixel"),
            limits::check_samples(self.image.samples_per_pixel),
        )?;
        check(r.key("depth"), limits::check_depth(self.render.depth))?;
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
        Ok(Settings {
            width: self.image.width,
            height: self.image.height,
            samples_per_pixel: self.image.samples_per_pixel,
            seed: self.image.seed,
            depth: self.render.depth,
            shading: ShadingModel {
                ambient: self.render.ambient,
                diffuse: self.render.diffuse,
                specular,
            },
            shadows: self.render.shadows,
            background: color(&r.key("background"), self.render.background, limits::MAX_LIGHT)?,
            adaptive_threshold: in_range(&r.key("adaptive_threshold"), self.render.adaptive_threshold, 0.0, 255.0)?,
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
                texture: m.textures(&p, dir)?,
            };
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

impl FileShape {
    /// The objects this entry describes (one, two for a mirror pair, a mesh's triangles);
    /// `room` is how many objects the scene may still hold.
    fn validate(
        self,
        path: &FieldPath,
        index: usize,
        material_names: &[String],
        dir: &Path,
        room: usize,
    ) -> Check<Vec<Listed>> {
        let size = |key: &str, x: f64| positive(&path.key(key), x, limits::MAX_COORDINATE);
        let (shape, material, name, transform) = match self {
            FileShape::Plane(FilePlane {
                point,
                normal,
                material,
                name,
                transform,
            }) => (
                Shape::Plane(Box::new(Plane::new(
                    vec3(&path.key("point"), point)?,
                    direction(&path.key("normal"), normal)?,
                ))),
                material,
                name,
                transform,
            ),
            FileShape::Rectangle(FileRectangle {
                corner,
                edge1,
                edge2,
                material,
                name,
                transform,
            }) => {
                let (e1, e2) = spanning_edges(path, edge1, edge2)?;
                (
                    Shape::Rectangle(Box::new(Rectangle::new(vec3(&path.key("corner"), corner)?, e1, e2))),
                    material,
                    name,
                    transform,
                )
            }
            FileShape::Disk(FileDisk {
                center,
                normal,
                radius,
                material,
                name,
                transform,
            }) => (
                Shape::Disk(Box::new(Disk::new(
                    vec3(&path.key("center"), center)?,
                    direction(&path.key("normal"), normal)?,
                    size("radius", radius)?,
                ))),
                material,
                name,
                transform,
            ),
            FileShape::Sphere(FileSphere {
                center,
                radius,
                material,
                name,
                transform,
            }) => (
                Shape::Sphere(Sphere::new(vec3(&path.key("center"), center)?, size("radius", radius)?)),
                material,
                name,
                transform,
            ),
            FileShape::Box(FileBox {
                center,
                size: s,
                rotation,
                material,
                name,
                transform,
            }) => {
                let sz = vec3(&path.key("size"), s)?;
                if sz.min_element() <= 0.0 {
                    return fail(&path.key("size"), format!("each side must be > 0, got {s:?}"));
                }
                let rot = angles(&path.key("rotation"), rotation)?;
                (
                    Shape::Cuboid(Box::new(Cuboid::new(vec3(&path.key("center"), center)?, sz, rot))),
                    material,
                    name,
                    transform,
                )
            }
            FileShape::Cylinder(c) => {
                let (base, axis, height, radius) = c.frame(path)?;
                (
                    Shape::Cylinder(Box::new(Cylinder::new(base, axis, height, radius))),
                    c.material,
                    c.name,
                    c.transform,
                )
            }
            FileShape::Cone(c) => {
                let (base, axis, height, radius) = c.frame(path)?;
                (
                    Shape::Cone(Box::new(Cone::new(base, axis, height, radius))),
                    c.material,
                    c.name,
                    c.transform,
                )
            }
            FileShape::MirrorPair(FileMirrorPair {
                hinge,
                bisector,
                opening,
                length,
                height,
                material,
                name,
                transform,
            }) => {
                let pair = mirror_pair(
                    path,
                    index,
                    hinge,
                    bisector,
                    opening,
                    length,
                    height,
                    material,
                    name,
                    material_names,
                )?;
                let Some(t) = transform_of(&path.key("transform"), transform)? else {
                    return Ok(pair);
                };
                return pair
                    .into_iter()
                    .map(|o| {
                        Ok(Listed {
                            shape: moved(&path.key("transform"), &t, o.shape)?,
                            ..o
                        })
                    })
                    .collect();
            }
            FileShape::Torus(FileTorus {
                center,
                axis,
                major_radius,
                minor_radius,
                material,
                name,
                transform,
            }) => {
                let major = size("major_radius", major_radius)?;
                let minor = size("minor_radius", minor_radius)?;
                if minor > major {
                    return fail(
                        &path.key("minor_radius"),
                        format!(
                            "must be at most major_radius ({major}) (a self-intersecting spindle torus is not supported), got {minor}"
                        ),
                    );
                }
                (
                    Shape::Torus(Box::new(Torus::new(
                        vec3(&path.key("center"), center)?,
                        direction(&path.key("axis"), axis)?,
                        major,
                        minor,
                    ))),
                    material,
                    name,
                    transform,
                )
            }
            FileShape::Triangle(FileTriangle {
                p0,
                p1,
                p2,
                material,
                name,
                transform,
            }) => {
                let (a, b, c) = (
                    vec3(&path.key("p0"), p0)?,
                    vec3(&path.key("p1"), p1)?,
                    vec3(&path.key("p2"), p2)?,
                );
                if let Some(why) = Triangle::degenerate(a, b, c) {
                    return fail(
                        &path.key("p2"),
                        format!("p0 {p0:?}, p1 {p1:?} and p2 {p2:?} make no triangle: {why}"),
                    );
                }
                (Shape::Triangle(Triangle::new(a, b, c)), material, name, transform)
            }
            FileShape::Tube(FileTube {
                start,
                end,
                radius,
                material,
                name,
                transform,
            }) => {
                let (from, to) = (vec3(&path.key("start"), start)?, vec3(&path.key("end"), end)?);
                let height = (to - from).length();
                let axis = (to - from) / height;
                // Two different finite points differ by a vector of non-zero length unless it
                // underflows (coordinates 1e-320 apart).
                if !axis.is_finite() {
                    return fail(
                        &path.key("end"),
                        format!("must differ from start {start:?} (a tube needs a length), got {end:?}"),
                    );
                }
                (
                    Shape::Cylinder(Box::new(Cylinder::tube(from, axis, height, size("radius", radius)?))),
                    material,
                    name,
                    transform,
                )
            }
            FileShape::Mesh(m) => return m.validate(path, index, material_names, dir, room),
            FileShape::SphericalCap(FileSphericalCap {
                center,
                normal,
                radius,
                curvature,
                material,
                name,
                transform,
            }) => {
                let radius = size("radius", radius)?;
                let curvature = in_range(
                    &path.key("curvature"),
                    curvature,
                    -limits::MAX_COORDINATE,
                    limits::MAX_COORDINATE,
                )?;
                if let Some(why) = SphericalCap::check(radius, curvature) {
                    return fail(&path.key("curvature"), why);
                }
                (
                    Shape::SphericalCap(Box::new(SphericalCap::new(
                        vec3(&path.key("center"), center)?,
                        direction(&path.key("normal"), normal)?,
                        radius,
                        curvature,
                    ))),
                    material,
                    name,
                    transform,
                )
            }
            FileShape::Lens(FileLens {
                base,
                axis,
                thickness,
                radius,
                curvature1,
                curvature2,
                material,
                name,
                transform,
            }) => {
                let thickness = in_range(&path.key("thickness"), thickness, 0.0, limits::MAX_COORDINATE)?;
                let radius = size("radius", radius)?;
                let curvature =
                    |key: &str, c: f64| in_range(&path.key(key), c, -limits::MAX_COORDINATE, limits::MAX_COORDINATE);
                let (c1, c2) = (
                    curvature("curvature1", curvature1)?,
                    curvature("curvature2", curvature2)?,
                );
                if let Some((i, why)) = Lens::check(thickness, radius, c1, c2) {
                    return fail(&path.key(["curvature1", "curvature2"][i]), why);
                }
                (
                    Shape::Lens(Box::new(Lens::new(
                        vec3(&path.key("base"), base)?,
                        direction(&path.key("axis"), axis)?,
                        thickness,
                        radius,
                        c1,
                        c2,
                    ))),
                    material,
                    name,
                    transform,
                )
            }
        };
        let shape = match transform_of(&path.key("transform"), transform)? {
            Some(t) => moved(&path.key("transform"), &t, shape)?,
            None => shape,
        };
        let material_index = resolve_material(path, material, material_names)?;
        Ok(vec![Listed {
            name: name.map_or_else(|| compact_str::format_compact!("{}#{index}", shape.kind()), Into::into),
            shape,
            material: material_index,
        }])
    }
}

impl FileCapped {
    /// The checked base, unit axis, height and radius.
    fn frame(&self, path: &FieldPath) -> Check<(DVec3, DVec3, f64, f64)> {
        let size = |key: &str, x: f64| positive(&path.key(key), x, limits::MAX_COORDINATE);
        Ok((
            vec3(&path.key("base"), self.base)?,
            direction(&path.key("axis"), self.axis)?,
            size("height", self.height)?,
            size("radius", self.radius)?,
        ))
    }
}

/// Two vertical rectangular mirrors of `length` x `height` hinged on a vertical line through
/// `hinge`, opening `opening` degrees symmetrically about the horizontal `bisector` (the
/// chapter's two-mirror figures). Named `<name> A` (rotated +opening/2 about z from the
/// bisector) and `<name> B` (-opening/2).
#[allow(clippy::too_many_arguments)]
fn mirror_pair(
    path: &FieldPath,
    index: usize,
    hinge: Xyz,
    bisector: Xyz,
    opening: f64,
    length: f64,
    height: f64,
    material: Option<String>,
    name: Option<String>,
    names: &[String],
) -> Check<Vec<Listed>> {
    let hinge = vec3(&path.key("hinge"), hinge)?;
    let b = vec3(&path.key("bisector"), bisector)?;
    let b = DVec3::new(b.x, b.y, 0.0);
    if b.length() <= 1e-12 {
        return fail(&path.key("bisector"), "must have a non-zero horizontal (x, y) part");
    }
    let b = b.normalize();
    let opening = in_range(&path.key("opening"), opening, 0.0, 180.0)?;
    if opening == 0.0 || opening == 180.0 {
        return fail(&path.key("opening"), "must be in (0, 180) degrees");
    }
    let length = positive(&path.key("length"), length, limits::MAX_COORDINATE)?;
    let height = positive(&path.key("height"), height, limits::MAX_COORDINATE)?;
    let material = resolve_material(path, material, names)?;
    let base = name.unwrap_or_else(|| format!("mirror_pair#{index}"));
    let half = (opening * 0.5).to_radians();
    let (sin, cos) = (libm::sin(half), libm::cos(half));
    // b rotated by +half and -half about z.
    let side = |s: f64| DVec3::new(b.x * cos - b.y * s, b.x * s + b.y * cos, 0.0);
    let up = DVec3::new(0.0, 0.0, height);
    Ok([("A", sin), ("B", -sin)]
        .into_iter()
        .map(|(tag, s)| Listed {
            name: compact_str::format_compact!("{base} {tag}"),
            shape: Shape::Rectangle(Box::new(Rectangle::new(hinge, side(s) * length, up))),
            material,
        })
        .collect())
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
