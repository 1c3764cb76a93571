//! Surface materials with the course's parameters. Ranges are checked where scenes are
//! built (see `scene::file`); this type only holds valid values.

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
        }
    }
}

impl Material {
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
