//! A `mesh` entry of `[[shapes]]`: [`FileMesh`], the triangles of a `.obj` file read
//! relative to the scene file, moved by the entry's transform, one object each.

use super::Listed;
use super::check::{Check, fail, normal_interpolation};
use super::material::resolve_material;
use super::transform::{FileTransform, transform_of};
use crate::scene::locate::{FieldError, FieldPath};
use crate::scene::rules::{self, Syntax};
use crate::shape::Shape;
use crate::shape::mesh::{Mesh, Tolerated};
use serde::Deserialize;
use std::path::Path;

/// The triangles of a `.obj` file (path relative to the scene file); with
/// `normal_interpolation`, a face that gives its vertices normals or texture coordinates
/// makes smooth triangles under that rule (as SIMRenderer's models do, under `"linear"`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileMesh {
    file: String,
    normal_interpolation: Option<String>,
    material: Option<String>,
    name: Option<String>,
    transform: Option<FileTransform>,
}

impl FileMesh {
    /// The mesh's triangles, one object each, named `NAME/K` (`NAME` is `name`, default
    /// `mesh#I`; `K` the triangle's place in the file, from 0).
    pub(super) fn validate(
        self,
        path: &FieldPath,
        index: usize,
        material_names: &[String],
        dir: &Path,
        room: usize,
    ) -> Check<Vec<Listed>> {
        let field = path.key("file");
        let file = dir.join(&self.file);
        let shown = file.display();
        let mut mesh = Mesh::read_into_scene(&file, room, Tolerated::NONE).map_err(|e| FieldError {
            path: field.clone(),
            message: e.in_file(&shown),
            got: None,
        })?;
        let material = resolve_material(path, self.material, material_names)?;
        let interpolation = match &self.normal_interpolation {
            Some(name) => Some(normal_interpolation(&path.key("normal_interpolation"), name)?),
            None => None,
        };
        let transform = transform_of(&path.key("transform"), self.transform)?;
        if let Some(t) = &transform
            && let Err(v) = mesh.transform(t)
        {
            return fail(&path.key("transform"), rules::moved_mesh(&shown, v, Syntax::Toml));
        }
        if let Some(m) = mesh.flat_face_message(&shown, transform.is_some()) {
            return fail(&field, m);
        }
        let base = self.name.unwrap_or_else(|| format!("mesh#{index}"));
        let shapes = match interpolation {
            Some(rule) => mesh.smooth_shapes(rule),
            None => mesh.triangles().into_iter().map(Shape::Triangle).collect(),
        };
        Ok(shapes
            .into_iter()
            .enumerate()
            .map(|(k, shape)| Listed {
                name: compact_str::format_compact!("{base}/{k}"),
                shape,
                material,
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mesh that does not fit in what the scene's other objects leave is refused on the
    /// face that passes the room, saying so.
    #[test]
    fn a_mesh_gets_the_room_the_scene_leaves() {
        let mesh = || FileMesh {
            file: "scenes/icosahedron.obj".to_string(),
            normal_interpolation: None,
            material: None,
            name: None,
            transform: None,
        };
        let path = FieldPath::default().key("shapes").index(2);
        let names = ["default".to_string()];
        let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
        assert_eq!(mesh().validate(&path, 2, &names, dir, 20).unwrap().len(), 20);
        let e = mesh().validate(&path, 2, &names, dir, 19).unwrap_err();
        assert_eq!(e.path.to_string(), "shapes[2].file");
        let obj = dir.join("scenes/icosahedron.obj");
        assert_eq!(
            e.message,
            format!(
                "{}:34:1: the mesh would hold 20 triangles, at most 19 are allowed (the scene's other objects leave \
                 room for 19 of the 4000000 objects it may hold)",
                obj.display()
            )
        );
    }
}
