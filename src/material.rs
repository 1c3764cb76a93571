//! Surface materials with the course's parameters. Ranges are checked where scenes are
//! built (see `scene::file`); this type only holds valid values.

use crate::shading::specular_tint;
use crate::texture::{Texture, TextureMaps};
use glam::DVec3;
use std::sync::Arc;

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
    /// The terms' colours where they are not the slides' ([`TermColors`]). Absent, the
    /// `term_colors` key is left out of the serialised material.
    #[serde(skip_serializing_if = "Option::is_none", serialize_with = "shared")]
    pub term_colors: Option<Arc<TermColors>>,
}

fn shared<S: serde::Serializer>(c: &Option<Arc<TermColors>>, s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&c.as_deref(), s)
}

/// A material's term colours other than the slides' `S` and `m S + (1 - m)`: the ambient and
/// specular colours of its own (SIMRenderer's OpenGL material, whose terms each have their
/// colour: a model's `.mtl`), and images that give a term's whole colour at each point
/// (SIMRenderer's texture materials). Shared between the materials that use the same
/// (cheap to clone).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct TermColors {
    /// The ambient term's colour `C_a` in place of `S` (the OpenGL material's `Ka`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ambient: Option<DVec3>,
    /// The specular term's colour `C_s` in place of `m S + (1 - m)` (its `Ks`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub specular: Option<DVec3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub images: Option<TextureMaps>,
}

impl TermColors {
    /// The term colours of these parts, `None` when they give none.
    pub fn of(ambient: Option<DVec3>, specular: Option<DVec3>, images: Option<TextureMaps>) -> Option<Arc<TermColors>> {
        let c = TermColors {
            ambient,
            specular,
            images,
        };
        (c != TermColors::default()).then(|| Arc::new(c))
    }
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
            term_colors: None,
        }
    }
}

impl Material {
    /// The coefficients and colours of the shading terms at a point whose texture
    /// coordinates `uv` gives (asked only of a material with images). Without
    /// [`Material::term_colors`]: `k_a S`, `k_d S` and `k_s [m S + (1 - m)]` (slides). With
    /// them, the ambient and specular colours the material's own where it gives them, and
    /// SIMRenderer's texture material (`SBlinnTextureMaterial`): each term that has an image
    /// takes the texel's colour as its whole colour, the coefficient not applied (white
    /// times the texel), and a term without an image keeps the material's own.
    #[inline]
    pub fn reflectance(&self, uv: impl FnOnce() -> (f64, f64)) -> Reflectance {
        match &self.term_colors {
            None => self.plain_reflectance(),
            Some(colors) => self.colored_reflectance(colors, uv),
        }
    }

    /// [`Material::reflectance`] without term colours: the slides'.
    #[inline]
    fn plain_reflectance(&self) -> Reflectance {
        Reflectance {
            ka: self.ka,
            ambient: self.color,
            kd: self.kd,
            diffuse: self.color,
            ks: self.ks,
            tint: specular_tint(self.metal, self.color),
        }
    }

    /// [`Material::reflectance`] with the term colours `colors`, the images' at texture
    /// coordinates `uv`.
    #[inline(never)]
    fn colored_reflectance(&self, colors: &TermColors, uv: impl FnOnce() -> (f64, f64)) -> Reflectance {
        let plain = self.plain_reflectance();
        let own = Reflectance {
            ambient: colors.ambient.unwrap_or(plain.ambient),
            tint: colors.specular.unwrap_or(plain.tint),
            ..plain
        };
        let Some(maps) = &colors.images else {
            return own;
        };
        let uv = uv();
        let texel = |t: &Option<Texture>| t.as_ref().map(|t| t.color(uv, maps.uv_format));
        let (a, d, s) = (texel(&maps.ambient), texel(&maps.diffuse), texel(&maps.specular));
        Reflectance {
            ka: if a.is_some() { 1.0 } else { own.ka },
            ambient: a.unwrap_or(own.ambient),
            kd: if d.is_some() { 1.0 } else { own.kd },
            diffuse: d.unwrap_or(own.diffuse),
            ks: if s.is_some() { 1.0 } else { own.ks },
            tint: s.unwrap_or(own.tint),
        }
    }

    /// The largest coefficient each term can take at any point, `[k_a, k_d, k_s]`: the
    /// material's own, or 1 for a term an image gives its whole colour
    /// ([`Material::reflectance`]; a texel's channels are at most 1).
    pub fn largest_coefficients(&self) -> [f64; 3] {
        let own = [self.ka, self.kd, self.ks];
        let Some(maps) = self.images() else {
            return own;
        };
        let imaged = [&maps.ambient, &maps.diffuse, &maps.specular].map(Option::is_some);
        std::array::from_fn(|t| if imaged[t] { 1.0 } else { own[t] })
    }

    /// The largest channel of the diffuse colour `k_d S` at any point: 1 under a diffuse
    /// image (its texel taken whole), else `k_d max(S)`.
    pub fn largest_diffuse(&self) -> f64 {
        match self.images().is_some_and(|maps| maps.diffuse.is_some()) {
            true => 1.0,
            false => self.kd * self.color.max_element(),
        }
    }

    /// The images of the terms' colours, if the material has any.
    pub fn images(&self) -> Option<&TextureMaps> {
        self.term_colors.as_ref()?.images.as_ref()
    }

    /// The ambient term's own colour `C_a`, if the material gives one.
    pub fn ambient_color(&self) -> Option<DVec3> {
        self.term_colors.as_ref()?.ambient
    }

    /// The specular term's own colour `C_s`, if the material gives one.
    pub fn specular_color(&self) -> Option<DVec3> {
        self.term_colors.as_ref()?.specular
    }

    /// Transparent for shadow rays: the chapter's "géométrie strictement transparente".
    pub fn is_transparent(&self) -> bool {
        self.kt > 0.0
    }

    /// Where a caustic photon lands and stays: a surface with a diffuse term (`k_d > 0`, or
    /// a diffuse image) that does not bend light itself (its light is what it lets through).
    pub fn receives_photons(&self) -> bool {
        self.largest_coefficients()[1] > 0.0 && !self.bends_light()
    }

    /// Transparent with an index other than the air's: it bends the light it lets through
    /// (a lens, a prism). With caustics on, its light arrives as photons, and it receives
    /// none itself ([`crate::scene::CausticSettings`]).
    pub fn bends_light(&self) -> bool {
        self.kt > 0.0 && self.ior != 1.0
    }
}
