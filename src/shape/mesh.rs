//! Triangle meshes from Wavefront `.obj` files, read by the `tobj` crate: every face becomes
//! [`Triangle`]s (a polygon of `n` vertices, `n - 2` of them, fanned from its first vertex,
//! as `tobj` triangulates) over one vertex array shared by the whole mesh.
//!
//! Before `tobj` parses the text, one pass over its lines checks what `tobj` would accept
//! without a word or report without a line or the word at fault: vertex coordinates that
//! are not finite or beyond [`crate::limits::MAX_COORDINATE`], a `v`, `vt` or `vn` line
//! short of numbers or with a word that is none, a colour on some vertices only (`tobj`
//! finds vertex `k`'s at place `k`), faces of fewer than 3 vertices, a face's
//! vertex that is not `v`, `v/vt`, `v//vn` or `v/vt/vn` in whole numbers, line elements
//! (`l`), indices out of range, and more triangles than allowed. Each error is placed
//! on its line and on the column of the word at fault ([`ObjError`]), `tobj`'s own on the
//! keyword of the line it stopped at; a message shows numbers as an OBJ file writes them
//! ([`crate::decimal`]). A reader may skip the statements that make no
//! triangle (a line element, a face of fewer than 3 vertices, a face with a vertex index
//! out of range) instead of refusing them, and keep a face with a texture or normal index
//! out of range without its texture coordinates or normals ([`Tolerated`]): they are
//! recorded ([`Mesh::skipped`]) and left out of what `tobj` reads. The faces with a
//! negative (relative) index are recorded too ([`Mesh::relative`]).
//! Every other statement that draws nothing (`o`, `g`, `s`, `vp`, `p`, ...) is left to
//! `tobj`, which groups by `o` and `g` and ignores the rest. The material libraries
//! (`mtllib`) and each face's material name (`usemtl`, `default` before the first) are
//! recorded, not read: a TOML mesh
//! takes the scene file's material, SIMRenderer's model reader reads them
//! (`scene::simrenderer::read::mtl`). A face gives normals or
//! texture coordinates to all its vertices or to none; they are kept for each triangle
//! ([`Mesh::smooth_shapes`], SIMRenderer's models), and a TOML mesh shades with the face
//! normal ([`Mesh::triangles`]).

use super::{NormalInterpolation, Shape, SmoothTriangle, Transform, Triangle};
use crate::{decimal, limits};
use glam::DVec3;
use std::borrow::Cow;
use std::io::{BufRead, Read};
use std::path::Path;
use std::sync::Arc;

/// A mesh read from a file: vertices, triangles (indices into them, in winding order) and
/// the file's line and column of the face each triangle comes from; for a triangle whose
/// face gives every vertex a normal (`v//vn`, `v/vt/vn`) or texture coordinates (`v/vt`,
/// `v/vt/vn`), those of its three corners.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub vertices: Vec<DVec3>,
    pub faces: Vec<[u32; 3]>,
    /// 1-based line of the face of each triangle.
    pub lines: Vec<usize>,
    /// 1-based column (in characters) of the keyword `f` of each triangle's face.
    pub columns: Vec<usize>,
    /// Each triangle's corner normals (as the file writes them, not made unit), if its
    /// face has them.
    pub normals: Vec<Option<[DVec3; 3]>>,
    /// Each triangle's corner texture coordinates, if its face has them.
    pub uvs: Vec<Option<[[f64; 2]; 3]>>,
    /// The material names the faces use (`usemtl`), `default` first: the name of the faces
    /// before any `usemtl`.
    pub material_names: Vec<String>,
    /// Each triangle's material: its face's index into `material_names`.
    pub materials: Vec<u32>,
    /// The material libraries the file names (`mtllib`), in order, as written.
    pub libraries: Vec<Library>,
    /// The statements skipped (or, for a texture or normal index out of range, kept without
    /// the texture coordinates or normals) under the reader's [`Tolerated`], in file order.
    pub skipped: Vec<StatementAt>,
    /// The faces of 3 vertices or more with a negative index, which counts back from the
    /// last element of its kind read (OBJ's relative index), each with its first such index
    /// ([`Statement::RelativeIndex`]), in file order: whether drawn or skipped.
    pub relative: Vec<StatementAt>,
}

/// Which statements a reader tolerates rather than refuses on their line, recording them in
/// [`Mesh::skipped`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tolerated {
    /// Line elements (`l`), skipped.
    pub line_elements: bool,
    /// Faces of fewer than 3 vertices, skipped.
    pub short_faces: bool,
    /// Faces with an index out of range ([`Statement::BadIndex`]): skipped for a vertex
    /// index, kept without their texture coordinates (or normals) for a texture (or normal)
    /// index.
    pub bad_indices: bool,
}

impl Tolerated {
    /// All refused.
    pub const NONE: Tolerated = Tolerated {
        line_elements: false,
        short_faces: false,
        bad_indices: false,
    };
}

/// What a face's index names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Element {
    /// A vertex (`v`).
    Vertex,
    /// Texture coordinates (`vt`).
    Texture,
    /// A normal (`vn`).
    Normal,
}

impl Element {
    /// The word a message names its index with (`vertex index 4`).
    pub fn name(self) -> &'static str {
        match self {
            Element::Vertex => "vertex",
            Element::Texture => "texture",
            Element::Normal => "normal",
        }
    }

    /// The element itself, as a message names the last one read.
    fn noun(self) -> &'static str {
        match self {
            Element::Vertex => "vertex",
            Element::Texture => "texture coordinates",
            Element::Normal => "normal",
        }
    }
}

/// A statement a reader refuses or tolerates ([`Tolerated`]), or notes
/// ([`Statement::RelativeIndex`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Statement {
    /// A line element (`l`).
    LineElement,
    /// A face (`f`) of this many vertices, fewer than 3.
    ShortFace(usize),
    /// A face's index of an element out of range: 0, beyond the file's `total` of them, or a
    /// negative one that counts back past the `before` of them read before the face.
    BadIndex {
        element: Element,
        index: i64,
        before: usize,
        total: usize,
    },
    /// A face's negative index (in range), which counts back from the last element read.
    RelativeIndex { element: Element, index: i64 },
}

impl Statement {
    /// The keyword that opens it.
    pub fn keyword(self) -> &'static str {
        match self {
            Statement::LineElement => "l",
            Statement::ShortFace(_) | Statement::BadIndex { .. } | Statement::RelativeIndex { .. } => "f",
        }
    }

    /// What is wrong with it (or, for a relative index, what it means); a face short of
    /// vertices with a face's form (`f v1 v2 v3 ...`), a line element with what is read.
    fn why(self) -> String {
        match self {
            Statement::LineElement => "a line element (l) is no surface; only faces (f) are read".to_string(),
            Statement::ShortFace(n) => format!("a face needs at least 3 vertices (f v1 v2 v3 ...), got {n}"),
            Statement::BadIndex {
                element,
                index,
                before,
                total,
            } => {
                let what = element.name();
                if index == 0 {
                    format!("{what} index 0: indices start at 1 (or count back from -1)")
                } else if index > 0 {
                    format!("{what} index {index}, but the file has {total}")
                } else {
                    let come = if before == 1 { "comes" } else { "come" };
                    format!("{what} index {index}, but only {before} {come} before this face")
                }
            }
            Statement::RelativeIndex { element, index } => format!(
                "{} index {index} counts back from the last {} read (a relative index)",
                element.name(),
                element.noun()
            ),
        }
    }
}

/// A statement of [`Statement`], skipped under [`Tolerated`], refused or noted: its line and
/// column (1-based, in characters): its keyword's, or for an index ([`Statement::BadIndex`],
/// [`Statement::RelativeIndex`]) the index's own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StatementAt {
    pub line: usize,
    pub column: usize,
    pub statement: Statement,
}

impl StatementAt {
    /// `FILE:LINE:COLUMN: KEYWORD: MESSAGE`, the message saying what is wrong with the
    /// statement ([`ObjError::in_file`] of the statement refused).
    pub fn in_file(&self, file: &impl std::fmt::Display) -> String {
        ObjError::from(*self).in_file(file)
    }
}

/// A material library named by an `mtllib` line: the rest of the line, as one file name.
#[derive(Clone, Debug, PartialEq)]
pub struct Library {
    pub line: usize,
    pub file: String,
}

/// What a face of the file gives: its line and its keyword's column, its number of
/// vertices, and whether every vertex has a normal and texture coordinates.
#[derive(Clone, Copy)]
struct FaceLine {
    line: usize,
    column: usize,
    corners: usize,
    normals: bool,
    uvs: bool,
    /// Index into the mesh's material names.
    material: u32,
}

/// Why a mesh file was refused: the message, and where in the file when it concerns a line.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjError {
    /// The line and column (1-based, the column in characters) of the word at fault: the first
    /// word that is no number or whose number is out of range, a face's vertex or index, or
    /// the keyword of a statement refused whole; `None` for an error of the whole file.
    pub place: Option<(usize, usize)>,
    pub message: String,
    /// Whether the file has more triangles than it was allowed.
    pub over_limit: bool,
}

impl ObjError {
    /// The message placed in `file` (as both scene readers name it): `FILE:LINE:COLUMN:
    /// MESSAGE`, or `FILE: MESSAGE` for an error of the whole file.
    pub fn in_file(&self, file: &impl std::fmt::Display) -> String {
        match self.place {
            Some((line, column)) => format!("{file}:{line}:{column}: {}", self.message),
            None => format!("{file}: {}", self.message),
        }
    }
}

/// A statement refused: `KEYWORD: MESSAGE` on its place.
impl From<StatementAt> for ObjError {
    fn from(s: StatementAt) -> ObjError {
        at(
            s.line,
            s.column,
            format!("{}: {}", s.statement.keyword(), s.statement.why()),
        )
    }
}

fn at(line: usize, column: usize, message: String) -> ObjError {
    ObjError {
        place: Some((line, column)),
        message,
        over_limit: false,
    }
}

/// An error of the whole file.
fn whole(message: String) -> ObjError {
    ObjError {
        place: None,
        message,
        over_limit: false,
    }
}

impl Mesh {
    /// Reads and checks the file (see the module doc), refusing files larger than
    /// [`limits::MAX_FILE_BYTES`] and meshes of more than `max_triangles`, and skipping
    /// what `tolerated` says.
    pub fn read(path: &Path, max_triangles: usize, tolerated: Tolerated) -> Result<Mesh, ObjError> {
        let cannot = |e: std::io::Error| whole(format!("cannot read the mesh file: {e}"));
        let meta = std::fs::metadata(path).map_err(cannot)?;
        // Not a directory, a device or a pipe, whose length says nothing of what they give.
        if !meta.is_file() {
            return Err(whole("not a regular file".to_string()));
        }
        let bytes = limits::read_file(path).map_err(cannot)?;
        Mesh::parse(&String::from_utf8_lossy(&bytes), max_triangles, tolerated)
    }

    /// Reads the mesh of a scene that has room for `room` more objects: at most
    /// [`limits::MAX_MESH_TRIANGLES`] triangles, fewer when the room is smaller, and then an
    /// error for too many triangles says that the scene's other objects leave too little.
    pub fn read_into_scene(path: &Path, room: usize, tolerated: Tolerated) -> Result<Mesh, ObjError> {
        let most = limits::MAX_MESH_TRIANGLES.min(room);
        Mesh::read(path, most, tolerated).map_err(|mut e| {
            if e.over_limit && most < limits::MAX_MESH_TRIANGLES {
                e.message += &format!(
                    " (the scene's other objects leave room for {most} of the {} objects it may hold)",
                    limits::MAX_OBJECTS
                );
            }
            e
        })
    }

    /// Checks and parses `.obj` text, skipping what `tolerated` says.
    pub fn parse(text: &str, max_triangles: usize, tolerated: Tolerated) -> Result<Mesh, ObjError> {
        let written = text;
        let Checked {
            faces,
            material_names,
            libraries,
            skipped,
            relative,
            replaced,
        } = check(text, max_triangles, tolerated)?;
        // The lines replaced (the skipped ones left empty), so that the others keep their
        // numbers.
        let kept: String;
        let text = if replaced.is_empty() {
            text
        } else {
            let mut next = replaced.iter().peekable();
            kept = text
                .split_inclusive('\n')
                .enumerate()
                .map(|(i, line)| match next.next_if(|(n, _)| *n == i + 1) {
                    Some((_, with)) => Cow::Owned(format!("{with}\n")),
                    None => Cow::Borrowed(line),
                })
                .collect();
            &kept
        };
        let mut reader = LineCounter {
            text: text.as_bytes(),
            pos: 0,
        };
        let options = tobj::LoadOptions {
            triangulate: true,
            ..Default::default()
        };
        // Material libraries are not opened; the (ignored) material list records the failure.
        let (models, _) =
            tobj::load_obj_buf(&mut reader, &options, |_| Err(tobj::LoadError::OpenFileFailed)).map_err(|e| {
                let line = reader.line();
                at(line, keyword_column(written, line), e.to_string())
            })?;
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        // Each triangle's corner normals and texture coordinates as tobj gives them (it
        // fills a vertex without them with another's: the face's flags say which to keep).
        let mut corner_normals = Vec::new();
        let mut corner_uvs = Vec::new();
        for m in &models {
            let first = vertices.len() as u32;
            vertices.extend(m.mesh.positions.chunks_exact(3).map(|p| DVec3::new(p[0], p[1], p[2])));
            triangles.extend(
                m.mesh
                    .indices
                    .chunks_exact(3)
                    .map(|f| [first + f[0], first + f[1], first + f[2]]),
            );
            let count = m.mesh.indices.len() / 3;
            let normal = |i: u32| {
                let k = 3 * i as usize;
                m.mesh.normals.get(k..k + 3).map(|n| DVec3::new(n[0], n[1], n[2]))
            };
            let uv = |i: u32| {
                m.mesh
                    .texcoords
                    .get(2 * i as usize..2 * i as usize + 2)
                    .map(|t| [t[0], t[1]])
            };
            for k in 0..count {
                let corners = |indices: &[u32]| indices.get(3 * k..3 * k + 3).map(|c| [c[0], c[1], c[2]]);
                corner_normals.push(
                    corners(&m.mesh.normal_indices).and_then(|[a, b, c]| Some([normal(a)?, normal(b)?, normal(c)?])),
                );
                corner_uvs.push(corners(&m.mesh.texcoord_indices).and_then(|[a, b, c]| Some([uv(a)?, uv(b)?, uv(c)?])));
            }
        }
        // Face `k` of the file gives `n_k - 2` triangles, in the file's order.
        let per_triangle: Vec<FaceLine> = faces
            .iter()
            .flat_map(|f| std::iter::repeat_n(*f, f.corners - 2))
            .collect();
        if per_triangle.len() != triangles.len() || vertices.len() > u32::MAX as usize {
            return Err(whole(format!(
                "the faces give {} triangles, the parser found {}",
                per_triangle.len(),
                triangles.len()
            )));
        }
        let normals = per_triangle
            .iter()
            .zip(corner_normals)
            .map(|(f, n)| n.filter(|_| f.normals))
            .collect();
        let uvs = per_triangle
            .iter()
            .zip(corner_uvs)
            .map(|(f, uv)| uv.filter(|_| f.uvs))
            .collect();
        Ok(Mesh {
            vertices,
            faces: triangles,
            lines: per_triangle.iter().map(|f| f.line).collect(),
            columns: per_triangle.iter().map(|f| f.column).collect(),
            normals,
            uvs,
            material_names,
            materials: per_triangle.iter().map(|f| f.material).collect(),
            libraries,
            skipped,
            relative,
        })
    }

    /// Every coordinate, normal and texture coordinate rounded to the nearest 32-bit float
    /// (SIMRenderer's model reader holds them as `float`s, `SVertex`), as 64-bit values.
    pub fn round_to_f32(&mut self) {
        let round = |x: f64| f64::from(x as f32);
        for v in &mut self.vertices {
            *v = v.to_array().map(round).into();
        }
        for n in self.normals.iter_mut().flatten() {
            *n = n.map(|n| n.to_array().map(round).into());
        }
        for uv in self.uvs.iter_mut().flatten() {
            *uv = uv.map(|c| c.map(round));
        }
    }

    /// Moves every vertex by `t`; where `t` mirrors, swaps each face's winding back so the
    /// normals stay outward. `Err` holds the first vertex it moves beyond the coordinates'
    /// range (the mesh is then only partly moved, and not to be used; the scene readers
    /// word it with [`crate::scene::rules::moved_mesh`]).
    pub fn transform(&mut self, t: &Transform) -> Result<(), DVec3> {
        for v in &mut self.vertices {
            *v = t.point(*v);
        }
        if let Some(&v) = self.vertices.iter().find(|v| !limits::within_coordinates(**v)) {
            return Err(v);
        }
        for n in self.normals.iter_mut().flatten() {
            *n = n.map(|n| t.normal(n));
        }
        if t.mirrors() {
            for f in &mut self.faces {
                f.swap(1, 2);
            }
            for n in self.normals.iter_mut().flatten() {
                n.swap(1, 2);
            }
            for uv in self.uvs.iter_mut().flatten() {
                uv.swap(1, 2);
            }
        }
        Ok(())
    }

    /// The first face that makes no triangle: its line and column (its keyword's) in the
    /// file and why ([`Triangle::degenerate`]).
    pub fn degenerate_face(&self) -> Option<(usize, usize, &'static str)> {
        self.faces
            .iter()
            .zip(self.lines.iter().zip(&self.columns))
            .find_map(|(f, (&line, &column))| self.why_flat(f).map(|why| (line, column, why)))
    }

    /// Why the triangle of corners `face` makes none ([`Triangle::degenerate`]), if it does not.
    fn why_flat(&self, face: &[u32; 3]) -> Option<&'static str> {
        let [a, b, c] = face.map(|i| self.vertices[i as usize]);
        Triangle::degenerate(a, b, c)
    }

    /// Removes the triangles that make none ([`Triangle::degenerate`]) with what the mesh
    /// keeps of each, as SIMRenderer's model reader skips them; returns how many.
    pub fn drop_degenerate(&mut self) -> usize {
        let keep: Vec<bool> = self.faces.iter().map(|f| self.why_flat(f).is_none()).collect();
        fn retain<T>(v: &mut Vec<T>, keep: &[bool]) {
            let mut k = keep.iter();
            v.retain(|_| *k.next().unwrap_or(&true));
        }
        retain(&mut self.faces, &keep);
        retain(&mut self.lines, &keep);
        retain(&mut self.columns, &keep);
        retain(&mut self.normals, &keep);
        retain(&mut self.uvs, &keep);
        retain(&mut self.materials, &keep);
        keep.iter().filter(|k| !**k).count()
    }

    /// [`Mesh::degenerate_face`] said as both scene readers say it, naming `file` (and that
    /// the face was flattened by the transform, when `moved`).
    pub fn flat_face_message(&self, file: &impl std::fmt::Display, moved: bool) -> Option<String> {
        let after = if moved { " after the transform" } else { "" };
        self.degenerate_face()
            .map(|(line, column, why)| format!("{file}:{line}:{column}: the face makes no triangle{after}: {why}"))
    }

    /// The shapes of the triangles: smooth ones ([`SmoothTriangle`], under `interpolation`)
    /// where the face gives normals or texture coordinates, as SIMRenderer's model reader
    /// builds its `SBTriangleGeometry` (a missing normal the face's, missing coordinates
    /// (0, 0)); flat ones over one shared copy of `vertices` elsewhere.
    pub fn smooth_shapes(&self, interpolation: NormalInterpolation) -> Vec<Shape> {
        self.triangles()
            .into_iter()
            .zip(self.normals.iter().zip(&self.uvs))
            .map(|(t, (normals, uvs))| {
                if normals.is_none() && uvs.is_none() {
                    return Shape::Triangle(t);
                }
                let normals = normals.unwrap_or([t.normal(); 3]);
                let uvs = uvs.unwrap_or([[0.0, 0.0]; 3]);
                match SmoothTriangle::new(t.clone(), normals, uvs, interpolation) {
                    Some(s) => Shape::SmoothTriangle(Box::new(s)),
                    // A normal of no direction (`vn 0 0 0`): the face's own.
                    None => Shape::Triangle(t),
                }
            })
            .collect()
    }

    /// The triangles over one shared copy of `vertices`.
    pub fn triangles(&self) -> Vec<Triangle> {
        let shared: Arc<[DVec3]> = Arc::from(self.vertices.as_slice());
        self.faces
            .iter()
            .filter_map(|&f| Triangle::in_mesh(&shared, f))
            .collect()
    }
}

/// What [`check`] finds: what every face gives, the material names, the libraries, the
/// statements skipped, the faces with a relative index, and the lines `tobj` is to read
/// otherwise (by number, in order: empty for a statement skipped, a face without the
/// texture or normal indices it is kept without).
struct Checked {
    faces: Vec<FaceLine>,
    material_names: Vec<String>,
    libraries: Vec<Library>,
    skipped: Vec<StatementAt>,
    relative: Vec<StatementAt>,
    replaced: Vec<(usize, String)>,
}

/// The rest of `line` after its first word `keyword`, without the blanks around it.
fn rest_after<'a>(line: &'a str, keyword: &str) -> &'a str {
    line.trim_start()[keyword.len()..].trim()
}

/// The checks of the module doc; returns what every face gives ([`FaceLine`]), with the
/// material names, the libraries, the statements `tolerated` lets it skip (or keep without
/// texture coordinates or normals) and the faces with a relative index ([`Checked`]).
fn check(text: &str, max_triangles: usize, tolerated: Tolerated) -> Result<Checked, ObjError> {
    // Counts of vertices, texture coordinates and normals in the whole file: `tobj`
    // resolves positive indices against them (relative ones against those read so far).
    let (mut v_total, mut vt_total, mut vn_total) = (0, 0, 0);
    for line in text.lines() {
        match line.split_whitespace().next() {
            Some("v") => v_total += 1,
            Some("vt") => vt_total += 1,
            Some("vn") => vn_total += 1,
            _ => {}
        }
    }
    let (mut v, mut vt, mut vn) = (0, 0, 0);
    let mut first_coloured = None;
    let mut faces = Vec::new();
    let mut triangles = 0usize;
    let mut material_names = vec!["default".to_string()];
    let mut material = 0u32;
    let mut libraries = Vec::new();
    let mut skipped = Vec::new();
    let mut relative = Vec::new();
    let mut replaced = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let number = i + 1;
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        // The column (1-based, in characters) where `word`, a part of this line, starts.
        let column_of = |word: &str| line[..word.as_ptr() as usize - line.as_ptr() as usize].chars().count() + 1;
        // The error `message`, placed on `word`.
        let refused_on = |(message, word): (String, &str)| at(number, column_of(word), message);
        // A statement of this line, placed on `word`.
        let placed_on = |statement: Statement, word: &str| StatementAt {
            line: number,
            column: column_of(word),
            statement,
        };
        // A statement that makes no triangle, placed on its keyword: skipped (and left out of
        // what tobj reads) or refused, as `tolerated` says.
        let mut no_triangle = |statement: Statement, skip: bool| {
            let placed = placed_on(statement, keyword);
            if !skip {
                return Err(ObjError::from(placed));
            }
            skipped.push(placed);
            replaced.push((number, String::new()));
            Ok(())
        };
        match keyword {
            "v" => {
                v += 1;
                let values: Vec<&str> = words.collect();
                check_vertex(keyword, &values, v).map_err(refused_on)?;
                // tobj finds vertex k's colour at place k among the colours given.
                let coloured = values.len() == 6;
                if *first_coloured.get_or_insert(coloured) != coloured {
                    // On the colour given, or on the keyword of the vertex without one.
                    let (has, word) = if coloured { ("a", values[3]) } else { ("no", keyword) };
                    let m = format!(
                        "vertex {v}: {has} colour (r g b), unlike vertex 1: give every vertex a colour or none"
                    );
                    return Err(refused_on((m, word)));
                }
            }
            "vt" => {
                vt += 1;
                let values: Vec<&str> = words.collect();
                numbers(keyword, &values, 2, &format!("texture coordinates {vt}"), "written u v")
                    .map_err(refused_on)?;
            }
            "vn" => {
                vn += 1;
                let values: Vec<&str> = words.collect();
                numbers(keyword, &values, 3, &format!("normal {vn}"), "written x y z").map_err(refused_on)?;
            }
            "usemtl" => {
                let name = rest_after(line, keyword);
                material = match material_names.iter().position(|n| n == name) {
                    Some(k) => k as u32,
                    None => {
                        material_names.push(name.to_string());
                        (material_names.len() - 1) as u32
                    }
                };
            }
            "mtllib" => libraries.push(Library {
                line: number,
                file: rest_after(line, keyword).to_string(),
            }),
            "l" => no_triangle(Statement::LineElement, tolerated.line_elements)?,
            "f" => {
                let corners: Vec<&str> = words.collect();
                if corners.len() < 3 {
                    no_triangle(Statement::ShortFace(corners.len()), tolerated.short_faces)?;
                    continue;
                }
                // Whether each vertex gives texture coordinates, and a normal.
                let mut gives: Vec<[bool; 2]> = Vec::with_capacity(corners.len());
                // The first index out of range of each element (tolerated), and the first
                // negative one, each placed on the index.
                let mut bad: [Option<StatementAt>; 3] = [None; 3];
                let mut first_relative = None;
                for &corner in &corners {
                    let parts: Vec<&str> = corner.split('/').collect();
                    let given = |k: usize| parts.get(k).is_some_and(|p| !p.is_empty());
                    gives.push([given(1), given(2)]);
                    let form = "a face's vertex is v, v/vt, v//vn or v/vt/vn, each a whole number";
                    if parts.len() > 3 || parts[0].is_empty() {
                        return Err(refused_on((format!("`{corner}`: {form}"), corner)));
                    }
                    let whole = parts.len() == 1;
                    for (k, part) in parts.into_iter().enumerate() {
                        let (element, before, total) = [
                            (Element::Vertex, v, v_total),
                            (Element::Texture, vt, vt_total),
                            (Element::Normal, vn, vn_total),
                        ][k];
                        if part.is_empty() {
                            continue;
                        }
                        // As tobj reads an index (a pointer-sized whole number).
                        let index = part.parse::<isize>().map_err(|_| {
                            let word = if whole { String::new() } else { format!("`{corner}`: ") };
                            refused_on((format!("{word}`{part}` is no index: {form}"), part))
                        })?;
                        let index = index as i64;
                        if index < 0 {
                            first_relative.get_or_insert(placed_on(Statement::RelativeIndex { element, index }, part));
                        }
                        if let Some(statement) = check_index(element, index, before, total) {
                            if !tolerated.bad_indices {
                                return Err(placed_on(statement, part).into());
                            }
                            bad[k].get_or_insert(placed_on(statement, part));
                        }
                    }
                }
                // A face SIMRenderer reads with its indices' signs dropped, skipped here or
                // not: it may draw one lumiere skips.
                relative.extend(first_relative);
                if let Some(statement) = bad[0] {
                    skipped.push(statement);
                    replaced.push((number, String::new()));
                    continue;
                }
                skipped.extend(bad[1..].iter().flatten());
                let (keep_uvs, keep_normals) = (bad[1].is_none(), bad[2].is_none());
                if !keep_uvs || !keep_normals {
                    replaced.push((number, face_without(&corners, keep_uvs, keep_normals)));
                }
                triangles += corners.len() - 2;
                if triangles > max_triangles {
                    let m = format!("the mesh would hold {triangles} triangles, at most {max_triangles} are allowed");
                    return Err(ObjError {
                        over_limit: true,
                        ..refused_on((m, keyword))
                    });
                }
                for (k, what) in ["texture coordinates", "a normal"].into_iter().enumerate() {
                    let count = gives.iter().filter(|g| g[k]).count();
                    if count != 0 && count != corners.len() {
                        // On the first vertex that differs from the face's first.
                        let odd = gives.iter().position(|g| g[k] != gives[0][k]).unwrap_or(0);
                        let have = if count == 1 { "has" } else { "have" };
                        let m = format!(
                            "{count} of the face's {} vertices {have} {what}: give it to all of them or none",
                            corners.len()
                        );
                        return Err(refused_on((m, corners[odd])));
                    }
                }
                faces.push(FaceLine {
                    line: number,
                    column: column_of(keyword),
                    corners: corners.len(),
                    normals: gives[0][1] && keep_normals,
                    uvs: gives[0][0] && keep_uvs,
                    material,
                });
            }
            _ => {}
        }
    }
    if faces.is_empty() {
        let skipped_as = |f: fn(&Statement) -> bool| skipped.iter().find(|s| f(&s.statement));
        let short = skipped_as(|s| matches!(s, Statement::ShortFace(_)));
        let bad = skipped_as(|s| {
            matches!(
                s,
                Statement::BadIndex {
                    element: Element::Vertex,
                    ..
                }
            )
        });
        let which = match (short.is_some(), bad.is_some()) {
            (false, false) => "",
            (true, false) => " of 3 vertices or more",
            (false, true) => " whose vertex indices are in range",
            (true, true) => " of 3 vertices or more whose vertex indices are in range",
        };
        let message = format!("the file has no faces (f){which}");
        // Faces were skipped: placed on the first, which says why.
        let first_skipped = [short, bad].into_iter().flatten().min_by_key(|s| (s.line, s.column));
        return Err(match first_skipped {
            Some(s) => at(
                s.line,
                s.column,
                format!("{message}; the first face skipped: {}", s.statement.why()),
            ),
            None => whole(message),
        });
    }
    Ok(Checked {
        faces,
        material_names,
        libraries,
        skipped,
        relative,
        replaced,
    })
}

/// The face of `corners` as a line without their texture indices (unless `uvs`) and normal
/// indices (unless `normals`).
fn face_without(corners: &[&str], uvs: bool, normals: bool) -> String {
    let mut line = String::from("f");
    for corner in corners {
        let mut parts = corner.split('/');
        let v = parts.next().unwrap_or_default();
        let vt = parts.next().filter(|_| uvs).unwrap_or_default();
        let vn = parts.next().filter(|_| normals).unwrap_or_default();
        line += &match (vt.is_empty(), vn.is_empty()) {
            (true, true) => format!(" {v}"),
            (false, true) => format!(" {v}/{vt}"),
            (_, false) => format!(" {v}/{vt}/{vn}"),
        };
    }
    line
}

/// Why a line is refused, and the word of the line the message is placed on.
type Refusal<'a> = (String, &'a str);

/// The first `n` of `words`, the words after `keyword`, as numbers (as tobj reads them), or
/// why not, placed on the first word that is none or, short of numbers, on `keyword`:
/// `what` (`vertex 3`) names the element and `form` (`written x y z`) says how it is written.
fn numbers<'a>(keyword: &'a str, words: &[&'a str], n: usize, what: &str, form: &str) -> Result<Vec<f64>, Refusal<'a>> {
    let mut values = Vec::with_capacity(n);
    for &word in words.iter().take(n) {
        let value = word
            .parse()
            .map_err(|_| (format!("{what}: `{word}` is not a number ({form})"), word))?;
        values.push(value);
    }
    if values.len() < n {
        let s = if values.len() == 1 { "" } else { "s" };
        return Err((format!("{what}: {} number{s}, {form}", values.len()), keyword));
    }
    Ok(values)
}

/// Vertex number `n`, the words `values` after its `keyword`, is `x y z`, `x y z w` or
/// `x y z r g b`, every word a number; its coordinates (divided by `w`, as `tobj` applies
/// it, so not 0) must be finite and at most `MAX_COORDINATE` in magnitude. Else why, placed
/// on `keyword` for a count of numbers, on `w` when 0, on the first coordinate out of range
/// (on `w` when its division takes a coordinate there), and shown as the file writes numbers
/// ([`decimal::numbers`]).
fn check_vertex<'a>(keyword: &'a str, values: &[&'a str], n: usize) -> Result<(), Refusal<'a>> {
    let what = format!("vertex {n}");
    let form = "written x y z, x y z w or x y z r g b";
    if values.len() == 5 || values.len() > 6 {
        return Err((format!("{what}: {} numbers, {form}", values.len()), keyword));
    }
    let parsed = numbers(keyword, values, values.len().max(3), &what, form)?;
    let w = (values.len() == 4).then(|| parsed[3]);
    if w == Some(0.0) {
        return Err((format!("{what}: w is 0, and x y z are divided by it"), values[3]));
    }
    let divisor = w.unwrap_or(1.0);
    let xyz = [parsed[0] / divisor, parsed[1] / divisor, parsed[2] / divisor];
    let m = limits::MAX_COORDINATE;
    let fine = |c: f64| c.is_finite() && c.abs() <= m;
    let Some(k) = xyz.iter().position(|c| !fine(*c)) else {
        return Ok(());
    };
    let (word, divided) = match w {
        Some(_) if fine(parsed[k]) => (values[3], " (x y z divided by w)"),
        Some(_) => (values[k], " (x y z divided by w)"),
        None => (values[k], ""),
    };
    Err((
        format!(
            "{what}: coordinates must be finite numbers in [-{m:e}, {m:e}], got {}{divided}",
            decimal::numbers(&xyz, "inf")
        ),
        word,
    ))
}

/// The column (1-based, in characters) of the first word of `text`'s line `line` (1-based),
/// 1 when it has none.
fn keyword_column(text: &str, line: usize) -> usize {
    let this = text.lines().nth(line.saturating_sub(1)).unwrap_or_default();
    this.chars().take_while(|c| c.is_whitespace()).count() + 1
}

/// A face's index of an `element`: from 1 to `total`, or from -1 back to the first of the
/// `before` read so far; else the statement of it out of range.
fn check_index(element: Element, index: i64, before: usize, total: usize) -> Option<Statement> {
    let fine = if index > 0 {
        index as u64 <= total as u64
    } else {
        index < 0 && index.unsigned_abs() <= before as u64
    };
    (!fine).then_some(Statement::BadIndex {
        element,
        index,
        before,
        total,
    })
}

/// The text as `tobj` reads it, counting how far it got: on an error, the line it stopped
/// at is the one it could not parse.
struct LineCounter<'a> {
    text: &'a [u8],
    pos: usize,
}

impl LineCounter<'_> {
    /// The 1-based line of the last byte read.
    fn line(&self) -> usize {
        let end = self.pos.saturating_sub(1).min(self.text.len());
        self.text[..end].iter().filter(|&&b| b == b'\n').count() + 1
    }
}

impl Read for LineCounter<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = buf.len().min(self.text.len() - self.pos);
        buf[..n].copy_from_slice(&self.text[self.pos..self.pos + n]);
        self.pos += n;
        Ok(n)
    }
}

impl BufRead for LineCounter<'_> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        Ok(&self.text[self.pos..])
    }

    fn consume(&mut self, amount: usize) {
        self.pos = (self.pos + amount).min(self.text.len());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: &str = "# a unit square in z = 0, as a quad and as two triangles\n\
        v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
        o quad\nf 1 2 3 4\n\
        o pair\nf 1/1 2/1 3/1\nf -4 -2 -1\nvt 0 0\n";

    #[test]
    fn each_triangle_keeps_its_faces_material_in_file_order() {
        // Materials that come back (a, b, a) and a group between: tobj starts a new model
        // at each change, and the triangles stay in the file's order with their materials.
        let text = "mtllib one.mtl\nmtllib two words.mtl\n\
            v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
            f 1 2 3\nusemtl a\nf 2 4 3\nusemtl b\nf 1 2 4\ng side\nusemtl  a \nf 1 4 3\n";
        let m = Mesh::parse(text, 100, Tolerated::NONE).unwrap();
        assert_eq!(m.material_names, ["default", "a", "b"]);
        assert_eq!(m.materials, [0, 1, 2, 1]);
        assert_eq!(m.lines, [7, 9, 11, 14]);
        assert_eq!(
            m.faces
                .iter()
                .map(|f| f.map(|i| m.vertices[i as usize]))
                .collect::<Vec<_>>(),
            {
                let v = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)];
                [[0, 1, 2], [1, 3, 2], [0, 1, 3], [0, 3, 2]]
                    .map(|f| f.map(|i| v[i]))
                    .to_vec()
            }
        );
        let libraries: Vec<(usize, &str)> = m.libraries.iter().map(|l| (l.line, l.file.as_str())).collect();
        assert_eq!(libraries, [(1, "one.mtl"), (2, "two words.mtl")]);
    }

    #[test]
    fn faces_become_triangles_with_their_lines() {
        let m = Mesh::parse(SQUARE, 100, Tolerated::NONE).unwrap();
        // The quad fans into (1 2 3) (1 3 4); the pair's second face is (1 3 4) by relative
        // indices. Each model keeps its own vertices (tobj re-indexes per model).
        assert_eq!(m.faces.len(), 4);
        let points: Vec<[DVec3; 3]> = m.triangles().iter().map(|t| t.points()).collect();
        let (a, b, c, d) = (DVec3::ZERO, DVec3::X, DVec3::new(1., 1., 0.), DVec3::Y);
        assert_eq!(points, vec![[a, b, c], [a, c, d], [a, b, c], [a, c, d]]);
        assert_eq!(m.lines, vec![7, 7, 9, 10]);
        // Every triangle's normal is +z (counter-clockwise from above).
        assert!(m.triangles().iter().all(|t| t.normal() == DVec3::Z));
    }

    #[test]
    fn a_mirroring_transform_keeps_the_normals_outward() {
        let mut m = Mesh::parse(SQUARE, 100, Tolerated::NONE).unwrap();
        // x -> -x, then up by 2: the square lands on [-1, 0] x [0, 1] at z = 2.
        let t = Transform::from_parts(DVec3::new(-1.0, 1.0, 1.0), DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0));
        assert_eq!(m.transform(&t), Ok(()));
        assert_eq!(m.faces[0], [0, 2, 1]);
        let t0 = m.triangles()[0].points();
        assert_eq!(
            t0,
            [
                DVec3::new(0.0, 0.0, 2.0),
                DVec3::new(-1.0, 1.0, 2.0),
                DVec3::new(-1.0, 0.0, 2.0)
            ]
        );
        assert!(m.triangles().iter().all(|t| t.normal() == DVec3::Z));
        // A move beyond the coordinates' range names the first vertex it takes there.
        let far = Transform::from_parts(DVec3::ONE, DVec3::ZERO, DVec3::new(limits::MAX_COORDINATE, 0.0, 0.0));
        let mut m = Mesh::parse(SQUARE, 100, Tolerated::NONE).unwrap();
        assert_eq!(
            m.transform(&far),
            Err(DVec3::new(limits::MAX_COORDINATE + 1.0, 0.0, 0.0))
        );
    }

    #[test]
    fn the_first_flat_face_is_named_with_its_line() {
        let m = Mesh::parse(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 1 3\n",
            100,
            Tolerated::NONE,
        )
        .unwrap();
        assert_eq!(m.degenerate_face(), Some((6, 1, "its points are on one line")));
        assert_eq!(
            m.flat_face_message(&"m.obj", true).unwrap(),
            "m.obj:6:1: the face makes no triangle after the transform: its points are on one line"
        );
        let m = Mesh::parse(SQUARE, 100, Tolerated::NONE).unwrap();
        assert_eq!(m.degenerate_face(), None);
    }

    #[test]
    fn statements_that_make_no_triangle_are_refused_or_skipped() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n l 1 2 3\nf 1 2 3\nf 1 2\nf\nf 2 4 3\nl 1 4\n";
        let e = Mesh::parse(text, 100, Tolerated::NONE).unwrap_err();
        assert_eq!(
            e.in_file(&"m.obj"),
            "m.obj:5:2: l: a line element (l) is no surface; only faces (f) are read"
        );
        let lines_only = Tolerated {
            line_elements: true,
            ..Tolerated::NONE
        };
        let e = Mesh::parse(text, 100, lines_only).unwrap_err();
        assert_eq!(
            e.in_file(&"m.obj"),
            "m.obj:7:1: f: a face needs at least 3 vertices (f v1 v2 v3 ...), got 2"
        );
        // Skipped: the other faces kept on their lines, the skipped statements recorded.
        let both = Tolerated {
            line_elements: true,
            short_faces: true,
            bad_indices: false,
        };
        let m = Mesh::parse(text, 100, both).unwrap();
        assert_eq!(m.lines, [6, 9]);
        let points: Vec<[DVec3; 3]> = m.triangles().iter().map(|t| t.points()).collect();
        let corner = DVec3::new(1.0, 1.0, 0.0);
        assert_eq!(
            points,
            [[DVec3::ZERO, DVec3::X, DVec3::Y], [DVec3::X, corner, DVec3::Y]]
        );
        let skipped: Vec<(usize, usize, Statement)> =
            m.skipped.iter().map(|s| (s.line, s.column, s.statement)).collect();
        assert_eq!(
            skipped,
            [
                (5, 2, Statement::LineElement),
                (7, 1, Statement::ShortFace(2)),
                (8, 1, Statement::ShortFace(0)),
                (10, 1, Statement::LineElement),
            ]
        );
        // A file whose faces are all skipped has none to draw.
        let e = Mesh::parse("v 0 0 0\nv 1 0 0\nl 1 2\n  f 1 2\nf 2\n", 100, both).unwrap_err();
        assert_eq!(
            e.in_file(&"m.obj"),
            "m.obj:4:3: the file has no faces (f) of 3 vertices or more; the first face skipped: \
             a face needs at least 3 vertices (f v1 v2 v3 ...), got 2"
        );
    }

    #[test]
    fn faces_with_an_index_out_of_range_are_refused_or_tolerated() {
        // Five vertices, one texture coordinate, one normal; line 9 a vertex index past the
        // count, line 10 a texture index past it, line 11 a normal index 0, line 12 a
        // relative vertex index past the first vertex, line 13 both a texture and a vertex
        // index out of range, line 14 a texture and a normal one.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 0 0\nvt 0.5 0.5\nvn 0 0 1\n\
            f 1 2 3\nf 2 4 6\nf 1/1 2/1 4/2\n  f 1//1 4//1 3//0\nf 2 5 -6\n\
            f 1/2 2/1 7/1\nf 2/1/1 5/9/1 4/1/-2\n";
        let e = Mesh::parse(text, 100, Tolerated::NONE).unwrap_err();
        assert_eq!(e.in_file(&"m.obj"), "m.obj:9:7: f: vertex index 6, but the file has 5");
        let tolerant = Tolerated {
            bad_indices: true,
            ..Tolerated::NONE
        };
        let m = Mesh::parse(text, 100, tolerant).unwrap();
        let bad = |line, column, element, index, before, total| StatementAt {
            line,
            column,
            statement: Statement::BadIndex {
                element,
                index,
                before,
                total,
            },
        };
        assert_eq!(
            m.skipped,
            [
                bad(9, 7, Element::Vertex, 6, 5, 5),
                bad(10, 13, Element::Texture, 2, 1, 1),
                bad(11, 18, Element::Normal, 0, 1, 1),
                bad(12, 7, Element::Vertex, -6, 5, 5),
                bad(13, 11, Element::Vertex, 7, 5, 5),
                bad(14, 11, Element::Texture, 9, 1, 1),
                bad(14, 19, Element::Normal, -2, 1, 1),
            ]
        );
        // The faces of lines 9, 12 and 13 skipped; those of lines 10, 11 and 14 kept without
        // texture coordinates or normals (14 without either: a flat triangle).
        assert_eq!(m.lines, [8, 10, 11, 14]);
        let (a, b, c, d, e) = (
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
        );
        let points: Vec<[DVec3; 3]> = m.triangles().iter().map(|t| t.points()).collect();
        assert_eq!(points, [[a, b, c], [a, b, d], [a, d, c], [b, e, d]]);
        assert_eq!(m.uvs, [None; 4]);
        assert_eq!(m.normals, [None, None, None, None]);
        // The relative index of line 12 is recorded, and line 14's (a normal index).
        let relative: Vec<(usize, Statement)> = m.relative.iter().map(|s| (s.line, s.statement)).collect();
        assert_eq!(
            relative,
            [
                (
                    12,
                    Statement::RelativeIndex {
                        element: Element::Vertex,
                        index: -6
                    }
                ),
                (
                    14,
                    Statement::RelativeIndex {
                        element: Element::Normal,
                        index: -2
                    }
                ),
            ]
        );
        // A texture index out of range keeps the normals, and a normal index the texture
        // coordinates.
        let m = Mesh::parse(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/2/1\nf 1/1/1 2/1/1 3/1/3\n",
            100,
            tolerant,
        )
        .unwrap();
        assert_eq!(m.normals, [Some([DVec3::Z; 3]), None]);
        assert_eq!(m.uvs, [None, Some([[0.0, 0.0]; 3])]);
        // A file whose faces are all skipped has none to draw.
        let e = Mesh::parse("v 0 0 0\nv 1 0 0\nf 1 2 3\n", 100, tolerant).unwrap_err();
        assert_eq!(
            e.in_file(&"m.obj"),
            "m.obj:3:7: the file has no faces (f) whose vertex indices are in range; the first face \
             skipped: vertex index 3, but the file has 2"
        );
        // In range, a relative index is recorded and read as OBJ reads it.
        let m = Mesh::parse("v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n", 100, Tolerated::NONE).unwrap();
        assert_eq!(m.triangles()[0].points(), [a, b, c]);
        assert_eq!(
            m.relative[0].in_file(&"m.obj"),
            "m.obj:5:3: f: vertex index -3 counts back from the last vertex read (a relative index)"
        );
    }

    #[test]
    fn only_regular_files_are_read() {
        let device = if cfg!(unix) { "/dev/zero" } else { "." };
        for path in [device, "."] {
            let e = Mesh::read(Path::new(path), 100, Tolerated::NONE).unwrap_err();
            assert_eq!(e.in_file(&path), format!("{path}: not a regular file"));
        }
    }

    #[test]
    fn each_error_is_placed_on_the_word_at_fault() {
        let err = |text: &str| Mesh::parse(text, 100, Tolerated::NONE).unwrap_err().in_file(&"m.obj");
        let xyz = "written x y z, x y z w or x y z r g b";
        let range = "coordinates must be finite numbers in [-1e9, 1e9]";
        let colour = "unlike vertex 1: give every vertex a colour or none";
        // Vertices: the first bad number's word (w's when only its division takes a
        // coordinate out of range), the keyword for a count of numbers; the coordinates as
        // an OBJ file writes them.
        for (text, message) in [
            (
                "v 0 0 0\nv nan 0 0\n",
                format!("m.obj:2:3: vertex 2: {range}, got NaN 0 0"),
            ),
            (
                "v 0 -2e9 0\n",
                format!("m.obj:1:5: vertex 1: {range}, got 0 -2000000000 0"),
            ),
            (
                "v 0.1 0 -inf\n",
                format!("m.obj:1:9: vertex 1: {range}, got 0.1 0 -inf"),
            ),
            (
                "v 6e8 0 0 0.5\n",
                format!("m.obj:1:11: vertex 1: {range}, got 1200000000 0 0 (x y z divided by w)"),
            ),
            (
                "v 0 inf 0 2\n",
                format!("m.obj:1:5: vertex 1: {range}, got 0 inf 0 (x y z divided by w)"),
            ),
            (
                "v 0 0 0 0\n",
                "m.obj:1:9: vertex 1: w is 0, and x y z are divided by it".to_string(),
            ),
            ("v 0 1 x\n", format!("m.obj:1:7: vertex 1: `x` is not a number ({xyz})")),
            // The column counts characters: the no-break space between words is 2 bytes.
            (
                "v\u{a0}0 1 x\n",
                format!("m.obj:1:7: vertex 1: `x` is not a number ({xyz})"),
            ),
            ("v 0 0\n", format!("m.obj:1:1: vertex 1: 2 numbers, {xyz}")),
            ("  v 0 0 0 1 1\n", format!("m.obj:1:3: vertex 1: 5 numbers, {xyz}")),
            (
                "v 0 0 0 1 0 0\nv 1 0 0\n",
                format!("m.obj:2:1: vertex 2: no colour (r g b), {colour}"),
            ),
            (
                "v 0 0 0\nv 1 0 0 1 0 0\n",
                format!("m.obj:2:9: vertex 2: a colour (r g b), {colour}"),
            ),
            (
                "v 0 0 0 1 0 0\nv 1 0 0 1 red 0\n",
                format!("m.obj:2:11: vertex 2: `red` is not a number ({xyz})"),
            ),
            (
                "vt 0.5\n",
                "m.obj:1:1: texture coordinates 1: 1 number, written u v".to_string(),
            ),
            (
                "vt 0 0\nvt 0 y\n",
                "m.obj:2:6: texture coordinates 2: `y` is not a number (written u v)".to_string(),
            ),
            (
                "vn 0 0 z\n",
                "m.obj:1:8: normal 1: `z` is not a number (written x y z)".to_string(),
            ),
            ("vn 0 0\n", "m.obj:1:1: normal 1: 2 numbers, written x y z".to_string()),
        ] {
            assert_eq!(err(text), message, "{text:?}");
        }
        // Faces: the vertex word for its form, the index word for an index, the keyword for
        // a statement refused whole.
        let square = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        let form = "a face's vertex is v, v/vt, v//vn or v/vt/vn, each a whole number";
        for (face, message) in [
            (
                "f 1 2 99999999999999999999",
                format!("m.obj:4:7: `99999999999999999999` is no index: {form}"),
            ),
            ("f 1 2 3/x", format!("m.obj:4:9: `3/x`: `x` is no index: {form}")),
            ("f 1 2 1.5", format!("m.obj:4:7: `1.5` is no index: {form}")),
            ("f 1 2 3/1/1/1", format!("m.obj:4:7: `3/1/1/1`: {form}")),
            ("f  /1 2 3", format!("m.obj:4:4: `/1`: {form}")),
            (
                "f 1 2 4",
                "m.obj:4:7: f: vertex index 4, but the file has 3".to_string(),
            ),
            (
                "f 1 2 -4",
                "m.obj:4:7: f: vertex index -4, but only 3 come before this face".to_string(),
            ),
            // One before: said in the singular.
            (
                "vt 0 0\nf 1/1 2/1 3/-2",
                "m.obj:5:13: f: texture index -2, but only 1 comes before this face".to_string(),
            ),
            (
                "f 0 1 2",
                "m.obj:4:3: f: vertex index 0: indices start at 1 (or count back from -1)".to_string(),
            ),
            (
                "vt 0 0\nf 1/1 2/1 3/2",
                "m.obj:5:13: f: texture index 2, but the file has 1".to_string(),
            ),
            (
                "vt 0 0\nf 1/1 2 3/1",
                "m.obj:5:7: 2 of the face's 3 vertices have texture coordinates: give it to all of them or none"
                    .to_string(),
            ),
            (
                "vn 0 0 1\nf 1 2 3//1",
                "m.obj:5:7: 1 of the face's 3 vertices has a normal: give it to all of them or none".to_string(),
            ),
            (
                " l 1 2",
                "m.obj:4:2: l: a line element (l) is no surface; only faces (f) are read".to_string(),
            ),
            (
                "\tf 1 2",
                "m.obj:4:2: f: a face needs at least 3 vertices (f v1 v2 v3 ...), got 2".to_string(),
            ),
            // tobj's own refusal (a material name after a tab, not a space), on the keyword.
            ("\tusemtl\nf 1 2 3", "m.obj:4:2: material parse error".to_string()),
        ] {
            assert_eq!(err(&format!("{square}{face}\n")), message, "{face}");
        }
        assert_eq!(err("v 0 0 0\n"), "m.obj: the file has no faces (f)");
        let limited = Mesh::parse(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\n  f 1 2 3 4 2 3\n",
            4,
            Tolerated::NONE,
        );
        assert_eq!(
            limited.unwrap_err().in_file(&"m.obj"),
            "m.obj:6:3: the mesh would hold 5 triangles, at most 4 are allowed"
        );
    }

    #[test]
    fn what_tobj_reads_is_accepted() {
        // Empty texture or normal indices, a sign.
        let square = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        for face in ["f 1 2 3/", "f 1 2 3//", "f +1 2 3", "f 1// 2 3"] {
            assert!(
                Mesh::parse(&format!("{square}{face}\n"), 100, Tolerated::NONE).is_ok(),
                "{face}"
            );
        }
        // A colour (unused) on every vertex.
        assert!(
            Mesh::parse(
                "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n",
                100,
                Tolerated::NONE
            )
            .is_ok()
        );
        // w divides x y z.
        let m = Mesh::parse("v 3 0 0 0.25\nv 0 0 0\nv 0 1 0\nf 1 2 3\n", 100, Tolerated::NONE).unwrap();
        assert_eq!(m.vertices[0], DVec3::new(12.0, 0.0, 0.0));
    }
}
