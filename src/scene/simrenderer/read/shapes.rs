//! The `primitive` and `model` blocks and the geometry blocks a primitive holds (each shape's
//! defaults, a `geometry` wrapper's transform): an object's shapes, refused with the reason
//! when degenerate, beyond the coordinates' range or not supported.

use super::keywords::{GEOMETRIES, MODEL, UV_FORMATS, WRAPPER, canonical};
use super::mtl;
use super::values::{angles, direction, number_in, point, positive, scale_factors, unit, uv};
use super::{At, Reader, at, at_value};
use crate::limits;
use crate::material::Material;
use crate::scene::SceneError;
use crate::scene::rules::{self, Syntax::SimRenderer};
use crate::scene::simrenderer::lex::{self, Item, Line};
use crate::shape::mesh::{Element, Mesh, Statement, StatementAt, Tolerated};
use crate::shape::{
    Cone, Cuboid, Cylinder, Disk, Lens, NormalInterpolation, Plane, Shape, SmoothTriangle, Sphere, SphericalCap, Torus,
    Transform, Triangle,
};
use crate::texture::UvFormat;
use glam::DVec3;
use std::collections::BTreeMap;
use std::path::Path;

/// A primitive (one shape) with the material name it binds, or a model (its triangles)
/// with its own materials.
pub(super) struct ShapeEntry {
    pub(super) at: At,
    /// The name of a `# lumiere: name` note.
    pub(super) name: Option<String>,
    pub(super) material: String,
    pub(super) material_at: At,
    pub(super) shapes: Vec<Shape>,
    pub(super) model: Option<ModelMaterials>,
}

/// A model's materials ([`super::mtl`]): each under its name in the model's libraries,
/// and each shape's index among them.
pub(super) struct ModelMaterials {
    pub(super) materials: Vec<(String, Material)>,
    pub(super) of_shape: Vec<u32>,
}

impl<'a> Reader<'a> {
    pub(super) fn primitive(&mut self, open: &Line<'a>) -> Result<Option<ShapeEntry>, SceneError> {
        let block = open.keyword.clone();
        let mut material = ("none".to_string(), at(open, "scene"));
        let mut name = None;
        let mut shape: Option<(Shape, At)> = None;
        // The first geometry's keyword, as written.
        let mut geometry_seen: Option<String> = None;
        let mut keywords = vec!["material_name"];
        keywords.extend_from_slice(GEOMETRIES);
        while let Some((k, l)) = self.next_key(&block, &keywords, Some(&mut name))? {
            if k == "material_name" {
                if let Some(n) = self.value(&block, &l, lex::name(l.value, l.value_column))? {
                    material = (n, at(&l, &block));
                }
                continue;
            }
            let place = at(&l, &block);
            if let Some(first) = &geometry_seen {
                let m = format!("a primitive has one geometry; this is a second one (after a {first})");
                self.problem(&place, m, "this geometry is skipped")?;
                self.skip_geometry(k);
                continue;
            }
            geometry_seen = Some(l.keyword.clone());
            if let Some(s) = self.geometry(&block, &l, k)? {
                shape = Some((s, place));
            }
        }
        let place = at(open, "scene");
        let Some((shape, _)) = shape else {
            if geometry_seen.is_none() {
                self.warn(&place, "a primitive without geometry draws nothing".to_string());
            }
            return Ok(None);
        };
        self.objects += 1;
        Ok(Some(ShapeEntry {
            at: place,
            name,
            material: material.0,
            material_at: material.1,
            shapes: vec![shape],
            model: None,
        }))
    }

    /// Skips a geometry block (with the blocks a `geometry` wrapper holds).
    fn skip_geometry(&mut self, kind: &str) {
        while let Some(item) = self.body() {
            if kind == "geometry"
                && let Item::Line(l) = item
                && canonical(&l.keyword).is_some_and(|k| GEOMETRIES.contains(&k))
            {
                self.skip_geometry(canonical(&l.keyword).unwrap_or_default());
            }
        }
    }

    /// A geometry block opened by `open`, of canonical kind `kind`; `None` when it is
    /// dropped.
    fn geometry(&mut self, parent: &str, open: &Line<'a>, kind: &'static str) -> Result<Option<Shape>, SceneError> {
        let block = open.keyword.clone();
        let place = at(open, parent);
        if kind == "btriangle" && canonical(parent) == Some("geometry") {
            let m = "SIMRenderer does not transform a btriangle (its SBTriangleGeometry.transform is not implemented); give its points and normals where they are".to_string();
            self.problem(&place, m, "the geometry is skipped")?;
            self.skip_geometry(kind);
            return Ok(None);
        }
        let keywords: &[&'static str] = match kind {
            "sphere" => &["position", "ray"],
            "plane" => &["position", "normal"],
            "disk" => &["position", "normal", "ray"],
            "triangle" => &["point"],
            "btriangle" => &["point", "normal", "uv"],
            "tube" | "cylinder" | "cone" => &["point", "position", "ray"],
            "cube" => &["position", "size"],
            "torus" => &["position", "normal", "major_radius", "minor_radius"],
            "spherical_cap" => &["position", "normal", "ray", "curvature"],
            "lens" => &["point", "position", "ray", "curvature"],
            _ => WRAPPER,
        };
        let mut position = DVec3::ZERO;
        let mut normal = DVec3::Z;
        let mut ray = 1.0;
        let mut size = 1.0;
        let (mut major, mut minor) = (1.0, 0.2);
        // A cap's curvature, or a lens's two (cap 1's then cap 2's); SIMRenderer's default
        // is the default radius, 1.
        let mut curvatures: Vec<(f64, At)> = Vec::new();
        let mut points: Vec<(DVec3, At)> = Vec::new();
        // A btriangle's vertex normals and texture coordinates, in vertex order.
        let mut normals: Vec<DVec3> = Vec::new();
        let mut uvs: Vec<[f64; 2]> = Vec::new();
        let (mut scale, mut rotation, mut translation) = (DVec3::ONE, DVec3::ZERO, DVec3::ZERO);
        let mut inner: Option<Shape> = None;
        let mut inner_seen = false;
        let mut lines: BTreeMap<&str, At> = BTreeMap::new();
        while let Some((k, l)) = self.next_key(&block, keywords, None)? {
            let here = at(&l, &block);
            match k {
                "point" | "position" if triangle_kind(kind) || points_kind(kind) => {
                    let most = if triangle_kind(kind) { 3 } else { 2 };
                    if points.len() == most {
                        let m = format!("a {kind} takes {most} points; this is one more");
                        self.problem(&here, m, "the line is skipped")?;
                    } else if let Some(p) = self.value(&block, &l, point(&l))? {
                        points.push((p, here.clone()));
                    }
                }
                "position" => self.set(&block, &l, point(&l), &mut position)?,
                "normal" | "uv" if kind == "btriangle" => {
                    let full = if k == "normal" { normals.len() } else { uvs.len() };
                    if full == 3 {
                        let m = format!("a btriangle takes 3 {k}s (one a vertex); this is one more");
                        self.problem(&here, m, "the line is skipped")?;
                    } else if k == "normal" {
                        if let Some(n) = self.value(&block, &l, direction(&l))? {
                            normals.push(n);
                        }
                    } else if let Some(uv) = self.value(&block, &l, uv(&l))? {
                        uvs.push(uv);
                    }
                }
                "normal" => self.set(&block, &l, direction(&l), &mut normal)?,
                "ray" => self.set(&block, &l, positive(&l, limits::MAX_COORDINATE), &mut ray)?,
                "size" => self.set(&block, &l, positive(&l, limits::MAX_COORDINATE), &mut size)?,
                "major_radius" => self.set(&block, &l, positive(&l, limits::MAX_COORDINATE), &mut major)?,
                "minor_radius" => self.set(&block, &l, positive(&l, limits::MAX_COORDINATE), &mut minor)?,
                "curvature" => {
                    let most = if kind == "lens" { 2 } else { 1 };
                    let c = self.value(
                        &block,
                        &l,
                        number_in(&l, -limits::MAX_COORDINATE, limits::MAX_COORDINATE),
                    )?;
                    if let Some(c) = c {
                        if kind == "lens" && curvatures.len() == most {
                            let m = "a lens takes 2 curvatures (cap 1's, then cap 2's); this is one more".to_string();
                            self.problem(&here, m, "the line is skipped")?;
                        } else {
                            // A cap's second curvature replaces the first, as any value does.
                            curvatures.truncate(most - 1);
                            curvatures.push((c, here.clone()));
                        }
                    }
                }
                "scale" => self.set(&block, &l, scale_factors(&l), &mut scale)?,
                "rotation" => self.set(&block, &l, angles(&l), &mut rotation)?,
                "translation" => self.set(&block, &l, point(&l), &mut translation)?,
                geometry => {
                    if inner_seen {
                        let m = "a geometry block holds one geometry; this is a second one".to_string();
                        self.problem(&here, m, "this geometry is skipped")?;
                        self.skip_geometry(geometry);
                        continue;
                    }
                    inner_seen = true;
                    inner = self.geometry(&block, &l, geometry)?;
                }
            }
            lines.insert(k, here);
        }
        let line = |k: &str| lines.get(k).cloned().unwrap_or_else(|| place.clone());
        let dropped = "the geometry is dropped";
        let shape = match kind {
            "sphere" => Shape::Sphere(Sphere::new(position, ray)),
            "plane" => Shape::Plane(Box::new(Plane::new(position, unit(normal)))),
            "disk" => Shape::Disk(Box::new(Disk::new(position, unit(normal), ray))),
            "cube" => Shape::Cuboid(Box::new(Cuboid::new(position, DVec3::splat(size), DVec3::ZERO))),
            "torus" => {
                if minor > major {
                    let m = format!(
                        "must be at most major_radius ({major}) (a self-intersecting spindle torus is not supported), got {minor}"
                    );
                    self.problem(&line("minor_radius"), m, dropped)?;
                    return Ok(None);
                }
                Shape::Torus(Box::new(Torus::new(position, unit(normal), major, minor)))
            }
            "triangle" | "btriangle" => {
                let defaults = [DVec3::ZERO, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)];
                let p: Vec<DVec3> = (0..3).map(|i| points.get(i).map_or(defaults[i], |(p, _)| *p)).collect();
                if let Some(why) = Triangle::degenerate(p[0], p[1], p[2]) {
                    let m = format!(
                        "the points {}, {} and {} make no triangle: {why}",
                        SimRenderer.vector(&p[0].to_array()),
                        SimRenderer.vector(&p[1].to_array()),
                        SimRenderer.vector(&p[2].to_array())
                    );
                    let here = points.last().map_or(place.clone(), |(_, a)| a.clone());
                    self.problem(&here, m, dropped)?;
                    return Ok(None);
                }
                let flat = Triangle::new(p[0], p[1], p[2]);
                if kind == "triangle" {
                    Shape::Triangle(flat)
                } else {
                    // SIMRenderer's defaults: the face's normal, and (0, 0) at each vertex.
                    let face = flat.normal();
                    let normals = [0, 1, 2].map(|i| normals.get(i).copied().unwrap_or(face));
                    let uvs = [0, 1, 2].map(|i| uvs.get(i).copied().unwrap_or([0.0, 0.0]));
                    // Every normal read has a direction (`direction` refuses one without).
                    match SmoothTriangle::new(flat, normals, uvs, NormalInterpolation::Linear) {
                        Some(t) => Shape::SmoothTriangle(Box::new(t)),
                        None => return Ok(None),
                    }
                }
            }
            "spherical_cap" => {
                let (curvature, curvature_at) = curvatures.pop().unwrap_or((1.0, place.clone()));
                if let Some(why) = SphericalCap::check(ray, curvature) {
                    self.problem(&curvature_at, why, dropped)?;
                    return Ok(None);
                }
                Shape::SphericalCap(Box::new(SphericalCap::new(position, unit(normal), ray, curvature)))
            }
            "tube" | "cylinder" | "cone" | "lens" => {
                let from = points.first().map_or(DVec3::ZERO, |(p, _)| *p);
                let to = points.get(1).map_or(DVec3::Z, |(p, _)| *p);
                let height = (to - from).length();
                let axis = (to - from) / height;
                // Two different finite points differ by a vector of non-zero length unless
                // it underflows.
                if !axis.is_finite() {
                    let m = format!(
                        "the two points {} and {} must differ (a {kind} needs a length)",
                        SimRenderer.vector(&from.to_array()),
                        SimRenderer.vector(&to.to_array())
                    );
                    let here = points.last().map_or(place.clone(), |(_, a)| a.clone());
                    self.problem(&here, m, dropped)?;
                    return Ok(None);
                }
                if kind == "lens" {
                    let curvature = |i: usize| curvatures.get(i).map_or((1.0, place.clone()), |(c, a)| (*c, a.clone()));
                    let (c1, c2) = (curvature(0), curvature(1));
                    if let Some((i, why)) = Lens::check(height, ray, c1.0, c2.0) {
                        self.problem(&[c1.1, c2.1][i], why, dropped)?;
                        return Ok(None);
                    }
                    return Ok(Some(Shape::Lens(Box::new(Lens::new(
                        from, axis, height, ray, c1.0, c2.0,
                    )))));
                }
                match kind {
                    "tube" => Shape::Cylinder(Box::new(Cylinder::tube(from, axis, height, ray))),
                    "cylinder" => Shape::Cylinder(Box::new(Cylinder::new(from, axis, height, ray))),
                    _ => Shape::Cone(Box::new(Cone::new(from, axis, height, ray))),
                }
            }
            _ => {
                let Some(inner) = inner else {
                    if !inner_seen {
                        let m = "a geometry block needs one geometry inside it (sphere, plane, ...)".to_string();
                        self.problem(&place, m, dropped)?;
                    }
                    return Ok(None);
                };
                let t = Transform::from_parts(scale, rotation, translation);
                if t.is_identity() {
                    inner
                } else {
                    match t.apply_within_limits(inner) {
                        Ok(s) => s,
                        Err(m) => {
                            self.problem(&place, format!("the transform {m}"), dropped)?;
                            return Ok(None);
                        }
                    }
                }
            }
        };
        Ok(Some(shape))
    }

    pub(super) fn model(&mut self, open: &Line<'a>) -> Result<Option<ShapeEntry>, SceneError> {
        let block = open.keyword.clone();
        let place = at(open, "scene");
        let mut file: Option<(String, At)> = None;
        let mut name = None;
        let (mut scale, mut rotation, mut translation) = (DVec3::ONE, DVec3::ZERO, DVec3::ZERO);
        let mut uv_format = UvFormat::default();
        while let Some((k, l)) = self.next_key(&block, MODEL, Some(&mut name))? {
            match k {
                "file" => {
                    if let Some(f) = self.value(&block, &l, lex::name(l.value, l.value_column))? {
                        file = Some((f, at_value(&l, &block, l.value_column)));
                    }
                }
                "scale" => self.set(&block, &l, scale_factors(&l), &mut scale)?,
                "rotation" => self.set(&block, &l, angles(&l), &mut rotation)?,
                "translation" => self.set(&block, &l, point(&l), &mut translation)?,
                _ => {
                    // SIMRenderer's `default` (0) keeps the images' own format: the top-left
                    // origin.
                    let read = lex::enumeration(l.value, l.value_column, &UV_FORMATS).map(|i| match i {
                        2 => UvFormat::OriginUvBottomLeft,
                        _ => UvFormat::OriginUvTopLeft,
                    });
                    self.set(&block, &l, read, &mut uv_format)?;
                }
            }
        }
        let dropped = "the model is dropped";
        let Some((file, file_at)) = file else {
            self.problem(&place, "a model needs a file (fichier)".to_string(), dropped)?;
            return Ok(None);
        };
        let path = self.dir.join(&file);
        let shown = path.display().to_string();
        let room = limits::MAX_OBJECTS.saturating_sub(self.objects);
        // SIMRenderer's model reader skips a line element without a word (its keyword table
        // has no `l`), a face of fewer than 3 vertices or with a vertex index past the file's
        // count with a message (`SModelOBJLoader.load`), and keeps a face with a texture or
        // normal index past it without them (`SPolygonOBJ`).
        let tolerated = Tolerated {
            line_elements: true,
            short_faces: self.lenient,
            bad_indices: self.lenient,
        };
        let mut mesh = match Mesh::read_into_scene(&path, room, tolerated) {
            Ok(mesh) => mesh,
            Err(e) => {
                self.problem(&file_at, e.in_file(&shown), dropped)?;
                return Ok(None);
            }
        };
        self.report_skipped(&mesh, &shown, &file_at)?;
        self.report_relative(&mesh, &shown, &file_at);
        mesh.round_to_f32();
        let t = Transform::from_parts(scale, rotation, translation);
        let moved = !t.is_identity();
        if moved && let Err(v) = mesh.transform(&t) {
            let m = rules::moved_mesh(&shown, v, SimRenderer);
            self.problem(&place, format!("the transform {m}"), dropped)?;
            return Ok(None);
        }
        if let Some(m) = mesh.flat_face_message(&shown, moved) {
            // SIMRenderer skips such a triangle and builds the others.
            let n = mesh.drop_degenerate();
            self.problem(
                &file_at,
                m,
                &format!("the {n} triangle(s) that make none are skipped, as SIMRenderer skips them"),
            )?;
        }
        let folder = path.parent().unwrap_or(Path::new(""));
        let materials = self.model_materials(&mesh, folder, &shown, &file_at, uv_format)?;
        let shapes = mesh.smooth_shapes(NormalInterpolation::Linear);
        self.objects += shapes.len();
        Ok(Some(ShapeEntry {
            at: place.clone(),
            name,
            material: String::new(),
            material_at: place,
            shapes,
            model: Some(materials),
        }))
    }

    /// The statements of `mesh`'s file that were skipped, the first of each kind located:
    /// line elements a warning; short faces, and faces with an index out of range (skipped,
    /// or kept without texture coordinates or normals), a problem (tolerated under `lenient`
    /// only).
    fn report_skipped(&mut self, mesh: &Mesh, shown: &str, file_at: &At) -> Result<(), SceneError> {
        if let Some((first, n)) = first_of(&mesh.skipped, |s| *s == Statement::LineElement) {
            let m = format!(
                "{}; the file's {n} line element(s) are skipped, as SIMRenderer's model reader skips them",
                first.in_file(&shown)
            );
            self.warn(file_at, m);
        }
        // Each kind of face tolerated, short (`None`) or with an index of `Some(element)` out of
        // range, and what was done with it.
        let bad_index = |element: Element, done: &str| {
            let what = element.name();
            let done = format!("with a {what} index out of range {done} whose {what} index passes the file's count");
            (Some(element), done)
        };
        let faces = [
            (
                None,
                "of fewer than 3 vertices are skipped and its others kept, as SIMRenderer's model reader skips them"
                    .to_string(),
            ),
            bad_index(
                Element::Vertex,
                "are skipped and its others kept, as SIMRenderer's model reader skips a face",
            ),
            bad_index(
                Element::Texture,
                "are kept without texture coordinates, as SIMRenderer's model reader keeps a face",
            ),
            bad_index(
                Element::Normal,
                "are kept without normals, as SIMRenderer's model reader keeps a face",
            ),
        ];
        for (kind, done) in faces {
            let is = |s: &Statement| match (kind, s) {
                (None, Statement::ShortFace(_)) => true,
                (Some(element), Statement::BadIndex { element: e, .. }) => element == *e,
                _ => false,
            };
            if let Some((first, n)) = first_of(&mesh.skipped, is) {
                self.problem(
                    file_at,
                    first.in_file(&shown),
                    &format!("the file's {n} face(s) {done}"),
                )?;
            }
        }
        Ok(())
    }

    /// A warning, in both modes, at the first face of `mesh`'s file with a negative
    /// (relative) index: SIMRenderer's model reader reads it without its sign
    /// (`SFace.parseFaceIndexToken` splits on `-`), so its image of the model differs.
    fn report_relative(&mut self, mesh: &Mesh, shown: &str, file_at: &At) {
        let Some(first) = mesh.relative.first() else {
            return;
        };
        let Statement::RelativeIndex { index, .. } = first.statement else {
            return;
        };
        let m = format!(
            "{}; SIMRenderer's model reader reads an index without its sign ({index} as {}), so its image of this model differs from lumiere's, which reads the file's {} face(s) with a negative index as OBJ defines them",
            first.in_file(&shown),
            index.unsigned_abs(),
            mesh.relative.len()
        );
        self.warn(file_at, m);
    }

    /// The materials of `mesh`'s faces ([`super::mtl`]): its libraries read from `folder`
    /// (the `.obj` file's, named `shown`), each line in error a problem at `file_at`.
    fn model_materials(
        &mut self,
        mesh: &Mesh,
        folder: &Path,
        shown: &str,
        file_at: &At,
        uv_format: UvFormat,
    ) -> Result<ModelMaterials, SceneError> {
        // Each material read, with its library's folder and name as shown.
        let mut read: Vec<(mtl::LibraryMaterial, std::path::PathBuf, String)> = Vec::new();
        for library in &mesh.libraries {
            let path = folder.join(&library.file);
            let named = format!("{shown}:{}: mtllib {:?}", library.line, library.file);
            let skipped = "the library is skipped";
            if !path.extension().is_some_and(|e| e.eq_ignore_ascii_case("mtl")) {
                let m = format!("{named}: a material library is a .mtl file");
                self.problem(file_at, m, skipped)?;
                continue;
            }
            let library_shown = path.display().to_string();
            let text = match limits::read_file(&path) {
                Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
                Err(e) => {
                    self.problem(file_at, format!("{named}: cannot read it: {e}"), skipped)?;
                    continue;
                }
            };
            let (materials, errors) = mtl::parse_library(&text);
            for e in errors {
                self.problem(file_at, e.in_file(&library_shown), "the value before it is kept")?;
            }
            let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
            read.extend(materials.into_iter().map(|m| (m, dir.clone(), library_shown.clone())));
        }
        if read.is_empty() {
            read.push((mtl::LibraryMaterial::default(), folder.to_path_buf(), String::new()));
        }
        // Each name the faces use, in the order of first use, with the material it gets.
        let mut used: Vec<Option<u32>> = vec![None; mesh.material_names.len()];
        let mut materials = Vec::new();
        let mut of_shape = Vec::with_capacity(mesh.materials.len());
        for &k in &mesh.materials {
            let slot = &mut used[k as usize];
            if slot.is_none() {
                let name = &mesh.material_names[k as usize];
                // The first material of a name, over the libraries in order.
                let material = match read.iter().find(|(m, _, _)| m.name == *name) {
                    Some((m, dir, library)) => {
                        let (material, errors) = mtl::library_material(m, dir, self.dir, uv_format);
                        for (line, keyword, message) in errors {
                            let m = format!("{library}:{line}: {keyword}: {message}");
                            self.problem(file_at, m, "the term keeps its colour")?;
                        }
                        material
                    }
                    None => {
                        self.warn(
                            file_at,
                            format!(
                                "{shown}: no material library of the model has the material {name:?}; its faces get SIMRenderer's default OpenGL material (ambient 0.1, diffuse (0.3, 0.7, 0.3), specular 0.05, shininess 5)"
                            ),
                        );
                        mtl::missing_material()
                    }
                };
                *slot = Some(materials.len() as u32);
                materials.push((name.clone(), material));
            }
            of_shape.push(slot.unwrap_or(0));
        }
        Ok(ModelMaterials { materials, of_shape })
    }
}

/// The geometries of three `point`s.
fn triangle_kind(kind: &str) -> bool {
    matches!(kind, "triangle" | "btriangle")
}

/// Whether a geometry of this kind takes its two points from `point` or `position` lines.
fn points_kind(kind: &str) -> bool {
    matches!(kind, "tube" | "cylinder" | "cone" | "lens")
}

/// The first of `statements` that `is` picks, with how many it picks.
fn first_of(statements: &[StatementAt], is: impl Fn(&Statement) -> bool) -> Option<(&StatementAt, usize)> {
    let mut picked = statements.iter().filter(|s| is(&s.statement));
    let first = picked.next()?;
    Some((first, 1 + picked.count()))
}
