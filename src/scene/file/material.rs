//! A `[materials.NAME]` table ([`FileMaterial`]) and its texture images, and the lookup of
//! a material named by a shape or a `[[generate]]` table.

use super::check::{Check, Xyz, fail, one};
use crate::scene::locate::FieldPath;
use serde::Deserialize;
use std::path::Path;

/// A `[materials.NAME]` table; a factor not given (`None`) takes its default, `m` that of
/// the conventions' highlight.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileMaterial {
    #[serde(default = "one")]
    pub(super) color: Xyz,
    pub(super) ka: Option<f64>,
    pub(super) kd: Option<f64>,
    pub(super) ks: Option<f64>,
    pub(super) shininess: Option<f64>,
    pub(super) m: Option<f64>,
    pub(super) kr: Option<f64>,
    pub(super) kt: Option<f64>,
    pub(super) n: Option<f64>,
    /// The ambient and specular terms' own colours, in place of `S` and `m S + (1 - m)`
    /// (SIMRenderer's OpenGL material, a model's `.mtl`).
    pub(super) ambient_color: Option<Xyz>,
    pub(super) specular_color: Option<Xyz>,
    /// SIMRenderer's texture material: image files (relative to the scene file) for the
    /// ambient, diffuse and specular colours, and where their coordinates' origin is.
    texture_ka: Option<String>,
    texture_kd: Option<String>,
    texture_ks: Option<String>,
    uv_format: Option<String>,
}

impl FileMaterial {
    /// The texture maps of a texture material, `None` when it names no image (a
    /// `uv_format` alone is refused: it would say nothing).
    pub(super) fn textures(&self, path: &FieldPath, dir: &Path) -> Check<Option<crate::texture::TextureMaps>> {
        use crate::texture::{Texture, TextureMaps, UvFormat};
        let load = |key: &str, file: &Option<String>| -> Check<Option<Texture>> {
            file.as_ref()
                .map(|f| Texture::load(&dir.join(f), f).or_else(|m| fail(&path.key(key), m)))
                .transpose()
        };
        let maps = TextureMaps {
            ambient: load("texture_ka", &self.texture_ka)?,
            diffuse: load("texture_kd", &self.texture_kd)?,
            specular: load("texture_ks", &self.texture_ks)?,
            uv_format: match &self.uv_format {
                None => UvFormat::default(),
                Some(name) => UvFormat::parse(name).map_or_else(
                    || {
                        fail(
                            &path.key("uv_format"),
                            format!("must be \"origin_uv_top_left\" or \"origin_uv_bottom_left\", got {name:?}"),
                        )
                    },
                    Ok,
                )?,
            },
        };
        if maps.ambient.is_none() && maps.diffuse.is_none() && maps.specular.is_none() {
            if self.uv_format.is_some() {
                return fail(
                    &path.key("uv_format"),
                    "applies to a material's textures: give texture_ka, texture_kd or texture_ks",
                );
            }
            return Ok(None);
        }
        Ok(Some(maps))
    }
}

/// Index of the named material (`None`: the default material, index 0).
pub(super) fn resolve_material(path: &FieldPath, material: Option<String>, names: &[String]) -> Check<usize> {
    match material {
        None => Ok(0),
        Some(m) => material_index(&path.key("material"), &m, names),
    }
}

/// Index of material `m`; an unknown name is an error at `field`.
pub(super) fn material_index(field: &FieldPath, m: &str, names: &[String]) -> Check<usize> {
    match names.iter().position(|n| n == m) {
        Some(i) => Ok(i),
        None => fail(field, format!("unknown material {m:?}; defined: {}", names.join(", "))),
    }
}
