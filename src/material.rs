//! Surface materials with the course's parameters. Ranges are checked where scenes are
//! built (see `scene::file`); this type only holds valid values.

use crate::shading::specular_tint;
use crate::texture::SharedMaps;
use glam::DVec3;

/// The course's material parameters (slides IFT3355 and chapter 7.4b).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Material {
    /// Surface colour `S` (each channel in [0, 1]).
    pub color: DVec3,
    /// Ambient reflectance `k_a`.
    pub ka: f64,
    /// Diffuse (Lambert) reflectance `k_d`.
    pub kd: f64,
    /// Specular reflectance `k_s`.
    pub ks: f64,
    /// Specular exponent `n` (roughness: large is smooth).
    pub shininess: f64,
    /// Metal factor `m` of the slides' `[m S + (1 - m)]`: 1 metal, 0 plastic.
    pub metal: f64,
    /// Weight of the reflected ray `k_r`.
    pub kr: f64,
    /// Weight of the refracted ray `k_t`; `k_t > 0` makes the object transparent for
    /// shadow rays (it filters light by `S` instead of blocking it).
    pub kt: f64,
    /// Index of refraction of the object's interior (the outside is air, n = 1).
    pub ior: f64,
    /// SIMRenderer's texture material: images that give the ambient, diffuse and specular
    /// colours at each point ([`Material::reflectance`]). Absent, the `texture` key is left
    /// out of the serialised material.
    #[serde(skip_serializing_if = "Option::is_none", serialize_with = "maps")]
    pub texture: Option<SharedMaps>,
    /// The ambient term's colour `C_a` where it is not `S`: SIMRenderer's OpenGL material
    /// (a model's `.mtl` `Ka`), whose terms each have their own colour.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ambient_color: Option<DVec3>,
    /// The specular term's colour `C_s` where it is not `m S + (1 - m)`: the OpenGL
    /// material's `Ks`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub specular_color: Option<DVec3>,
}

fn maps<S: serde::Serializer>(m: &Option<SharedMaps>, s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&m.as_deref(), s)
}

/// What a surface point reflects: each term's coefficient and colour, as the shading
/// formulas take them (`L_a k_a C_a`, `L k_d C_d max(N.L, 0)`, `L k_s C_s spec`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reflectance {
    pub ka: f64,
    pub ambient: DVec3,
    pub kd: f64,
    pub diffuse: DVec3,
    pub ks: f64,
    /// The highlight's colour `C_s`.
    pub tint: DVec3,
}

impl Material {
    /// The ratio `n = n1 / n2` of the law of refraction at this material's surface: `1 / n`
    /// for a ray entering from the air, `n` for one leaving into it.
    pub fn eta(&self, entering: bool) -> f64 {
        if entering { 1.0 / self.ior } else { self.ior }
    }
}

impl Default for Material {
    /// The default material of the course's figures (docs/figures.md): ka 0.2, kd 0.8, ks 0.5, shininess 20, plastic,
    /// no reflection or transmission, n 1, white.
    fn default() -> Self {
        Material {
            color: DVec3::ONE,
            ka: 0.2,
            kd: 0.8,
            ks: 0.5,
            shininess: 20.0,
            metal: 0.0,
            kr: 0.0,
            kt: 0.0,
            ior: 1.0,
            texture: None,
            ambient_color: None,
            specular_color: None,
        }
    }
}

impl Material {
    /// The coefficients and colours of the shading terms at a point whose texture
    /// coordinates `uv` gives (asked only of a textured material). Without a texture:
    /// `k_a S`, `k_d S` and `k_s [m S + (1 - m)]` (slides), the ambient and specular colours
    /// replaced by [`Material::ambient_color`] and [`Material::specular_color`] where they are
    /// given. With one, SIMRenderer's texture
    /// material (`SBlinnTextureMaterial`): each term that has an image takes the texel's
    /// colour as its whole colour, the coefficient not applied (white times the texel), and
    /// a term without an image keeps the material's own.
    #[inline]
    pub fn reflectance(&self, uv: impl FnOnce() -> (f64, f64)) -> Reflectance {
        match &self.texture {
            None => self.plain_reflectance(),
            Some(maps) => self.textured_reflectance(maps, uv()),
        }
    }

    /// [`Material::reflectance`] without images: the material's own colours.
    #[inline]
    fn plain_reflectance(&self) -> Reflectance {
        Reflectance {
            ka: self.ka,
            ambient: self.ambient_color.unwrap_or(self.color),
            kd: self.kd,
            diffuse: self.color,
            ks: self.ks,
            tint: self
                .specular_color
                .unwrap_or_else(|| specular_tint(self.metal, self.color)),
        }
    }

    /// [`Material::reflectance`] with the images `maps`, at texture coordinates `uv`.
    #[inline(never)]
    fn textured_reflectance(&self, maps: &crate::texture::TextureMaps, uv: (f64, f64)) -> Reflectance {
        let plain = self.plain_reflectance();
        let texel = |t: &Option<crate::texture::Texture>| t.as_ref().map(|t| t.color(uv, maps.uv_format));
        let (a, d, s) = (texel(&maps.ambient), texel(&maps.diffuse), texel(&maps.specular));
        Reflectance {
            ka: if a.is_some() { 1.0 } else { plain.ka },
            ambient: a.unwrap_or(plain.ambient),
            kd: if d.is_some() { 1.0 } else { plain.kd },
            diffuse: d.unwrap_or(plain.diffuse),
            ks: if s.is_some() { 1.0 } else { plain.ks },
            tint: s.unwrap_or(plain.tint),
        }
    }

    /// Transparent for shadow rays: the chapter's "géométrie strictement transparente".
    pub fn is_transparent(&self) -> bool {
        self.kt > 0.0
    }

    /// Transparent with an index other than the air's: it bends the light it lets through
    /// (a lens, a prism). With caustics on, its light arrives as photons, and it receives
    /// none itself ([`crate::scene::CausticSettings`]).
    pub fn bends_light(&self) -> bool {
        self.kt > 0.0 && self.ior != 1.0
    }
}
