//! The `material` and `texture_material` blocks: a material (with a texture material's
//! images) under its name, and the checks lumiere adds (kr + kt at most 1, a refractive
//! index above 0 for a transparent one).

use super::keywords::{MATERIAL, TEXTURE_MATERIAL};
use super::values::{color, number_in};
use super::{At, Reader, at, at_value};
use crate::limits;
use crate::material::Material;
use crate::scene::SceneError;
use crate::scene::simrenderer::lex::{self, Line};

pub(super) struct MaterialEntry {
    pub(super) name: String,
    pub(super) at: At,
    pub(super) material: Material,
    pub(super) metal_given: bool,
}

impl<'a> Reader<'a> {
    /// A `material` block, or with `textured` a `texture_material` block (a material and
    /// its images, SIMRenderer's `SBlinnTextureMaterial`).
    pub(super) fn material(&mut self, open: &Line<'a>, textured: bool) -> Result<Option<MaterialEntry>, SceneError> {
        let block = open.keyword.clone();
        let mut m = Material::default();
        let mut maps = crate::texture::TextureMaps {
            ambient: None,
            diffuse: None,
            specular: None,
            uv_format: crate::texture::UvFormat::default(),
        };
        let mut name: Option<(String, At)> = None;
        let mut plasticity: Option<f64> = None;
        // The line of the later of kr and kt, and which.
        let mut last_weight: Option<(&str, At)> = None;
        // Where the refractive index read is written, and as written.
        let mut ior_at: Option<(At, String)> = None;
        let keywords = if textured { TEXTURE_MATERIAL } else { MATERIAL };
        while let Some((k, l)) = self.next_key(&block, keywords, None)? {
            match k {
                "name" => {
                    if let Some(n) = self.value(&block, &l, lex::name(l.value, l.value_column))? {
                        name = Some((n, at(&l, &block)));
                    }
                }
                "color" => self.set(&block, &l, color(&l, 1.0), &mut m.color)?,
                "shininess" => self.set(&block, &l, number_in(&l, 0.0, 200.0), &mut m.shininess)?,
                "refractive_index" => {
                    let read = number_in(&l, 0.0, limits::MAX_IOR)
                        .and_then(|x| lex::number_as_written(l.value, l.value_column).map(|(_, w)| (x, w)));
                    if let Some((x, written)) = self.value(&block, &l, read)? {
                        m.ior = x;
                        ior_at = Some((at_value(&l, &block, l.value_column), written.to_string()));
                    }
                }
                "texture_ka" | "texture_kd" | "texture_ks" => {
                    let Some(file) = self.value(&block, &l, lex::name(l.value, l.value_column))? else {
                        continue;
                    };
                    // SIMRenderer's name for no image.
                    let texture = if file == "none" {
                        None
                    } else {
                        match crate::texture::Texture::load(&self.dir.join(&file), &file) {
                            Ok(t) => Some(t),
                            Err(message) => {
                                let here = at_value(&l, &block, l.value_column);
                                self.problem(&here, message, "the material keeps its own colour for this term")?;
                                continue;
                            }
                        }
                    };
                    match k {
                        "texture_ka" => maps.ambient = texture,
                        "texture_kd" => maps.diffuse = texture,
                        _ => maps.specular = texture,
                    }
                }
                _ => {
                    let Some(x) = self.value(&block, &l, number_in(&l, 0.0, 1.0))? else {
                        continue;
                    };
                    match k {
                        "ka" => m.ka = x,
                        "kd" => m.kd = x,
                        "ks" => m.ks = x,
                        "kr" | "kt" => {
                            if k == "kr" {
                                m.kr = x;
                            } else {
                                m.kt = x;
                            }
                            last_weight = Some((k, at(&l, &block)));
                        }
                        _ => plasticity = Some(x),
                    }
                }
            }
        }
        if m.kr + m.kt > 1.0
            && let Some((k, place)) = last_weight
        {
            let message = format!(
                "kr + kt must be at most 1 in lumiere (no ray may carry more than its parent), got {} + {}",
                m.kr, m.kt
            );
            self.problem(&place, message, &format!("{k} is set to 0"))?;
            if k == "kr" {
                m.kr = 0.0;
            } else {
                m.kt = 0.0;
            }
        }
        if m.ior == 0.0 {
            if m.kt > 0.0
                && let Some((place, written)) = ior_at
            {
                let message = format!("must be above 0 for a transparent material (kt > 0), got {written}");
                self.problem(&place, message, "n = 1 is used")?;
            }
            // SIMRenderer uses 1 for a material that is not transparent.
            m.ior = 1.0;
        }
        if let Some(p) = plasticity {
            m.metal = 1.0 - p;
        }
        if maps.ambient.is_some() || maps.diffuse.is_some() || maps.specular.is_some() {
            m.term_colors = crate::material::TermColors::of(None, None, Some(maps));
        }
        let (name, at) = name.unwrap_or_else(|| ("none".to_string(), at(open, "scene")));
        Ok(Some(MaterialEntry {
            name,
            at,
            material: m,
            metal_given: plasticity.is_some(),
        }))
    }
}
