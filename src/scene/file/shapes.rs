//! The `[[shapes]]` entries other than a mesh: [`FileShape`] and the table of each type,
//! and the checks that make each entry's objects (a mirror pair makes two), moved by its
//! transform.

use super::Listed;
use super::check::{
    Check, Xyz, angles, between, direction, fail, in_range, normal_interpolation, placed, plus_z, positive,
    spanning_edges, vec3,
};
use super::material::resolve_material;
use super::mesh::FileMesh;
use super::transform::{FileTransform, moved, transform_of};
use crate::limits;
use crate::scene::locate::FieldPath;
use crate::scene::rules;
use crate::shape::{
    Cone, Cuboid, Cylinder, Disk, Lens, NormalInterpolation, Plane, Rectangle, Shape, SmoothTriangle, Sphere,
    SphericalCap, Torus, Triangle,
};
use glam::DVec3;
use serde::Deserialize;
use std::path::Path;

/// The values of `type` in `[[shapes]]`, in the order of [`FileShape`]'s variants.
pub(super) const SHAPE_TYPES: &[&str] = &[
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
pub(super) enum FileShape {
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
pub(super) struct FilePlane {
    point: Xyz,
    normal: Xyz,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileRectangle {
    corner: Xyz,
    edge1: Xyz,
    edge2: Xyz,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileDisk {
    center: Xyz,
    normal: Xyz,
    radius: f64,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileSphere {
    center: Xyz,
    radius: f64,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileBox {
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
pub(super) struct FileCapped {
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
pub(super) struct FileMirrorPair {
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
pub(super) struct FileTorus {
    center: Xyz,
    #[serde(default = "plus_z")]
    axis: Xyz,
    major_radius: f64,
    minor_radius: f64,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

/// Three points; the normal by the right-hand rule `(p1 - p0) x (p2 - p0)`. With vertex
/// `normals` or `uvs` (texture coordinates) it is a smooth triangle
/// ([`crate::shape::SmoothTriangle`]): the missing normals are the face's, the missing
/// coordinates `(0, 0), (1, 0), (0, 1)`, and `normal_interpolation` says what becomes of
/// the interpolated normal's length (`"normalized"`, or SIMRenderer's `"linear"`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileTriangle {
    p0: Xyz,
    p1: Xyz,
    p2: Xyz,
    normals: Option<[Xyz; 3]>,
    uvs: Option<[[f64; 2]; 3]>,
    normal_interpolation: Option<String>,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

/// SIMRenderer's spherical cap: the disk (`center`, `normal`, `radius`) and the signed
/// radius of curvature (positive: bulging along the normal).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileSphericalCap {
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
pub(super) struct FileLens {
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
pub(super) struct FileTube {
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

/// The smooth triangle over `flat` of the triangle entry at `path` (see [`FileTriangle`]).
fn smooth_triangle(
    path: &FieldPath,
    flat: Triangle,
    normals: Option<[Xyz; 3]>,
    uvs: Option<[[f64; 2]; 3]>,
    interpolation: Option<String>,
) -> Check<SmoothTriangle> {
    let interpolation = match interpolation {
        None => NormalInterpolation::default(),
        Some(name) => normal_interpolation(&path.key("normal_interpolation"), &name)?,
    };
    let normals = match normals {
        None => [flat.normal(); 3],
        Some(ns) => {
            let mut out = [DVec3::ZERO; 3];
            for (i, n) in ns.into_iter().enumerate() {
                out[i] = placed(
                    &path.key("normals").index(i),
                    rules::direction(n.0, rules::Syntax::Toml),
                )?;
            }
            out
        }
    };
    let uvs = match uvs {
        None => SmoothTriangle::FLAT_UVS,
        Some(uvs) => {
            let m = limits::MAX_COORDINATE;
            for (i, uv) in uvs.iter().enumerate() {
                for (j, &x) in uv.iter().enumerate() {
                    in_range(&path.key("uvs").index(i).index(j), x, -m, m)?;
                }
            }
            uvs
        }
    };
    SmoothTriangle::new(flat, normals, uvs, interpolation)
        .map_or_else(|| fail(&path.key("normals"), "each normal must have a direction"), Ok)
}

impl FileShape {
    /// The objects this entry describes (one, two for a mirror pair, a mesh's triangles);
    /// `room` is how many objects the scene may still hold.
    pub(super) fn validate(
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
                normals,
                uvs,
                normal_interpolation,
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
                let flat = Triangle::new(a, b, c);
                let shape = if normals.is_none() && uvs.is_none() {
                    if normal_interpolation.is_some() {
                        return fail(
                            &path.key("normal_interpolation"),
                            "applies to a triangle with vertex normals or uvs; this one has neither",
                        );
                    }
                    Shape::Triangle(flat)
                } else {
                    Shape::SmoothTriangle(Box::new(smooth_triangle(
                        path,
                        flat,
                        normals,
                        uvs,
                        normal_interpolation,
                    )?))
                };
                (shape, material, name, transform)
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
    let opening = between(&path.key("opening"), opening, 0.0, 180.0)?;
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
