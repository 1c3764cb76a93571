//! The formulas the reference tracer ([`super::Reference`]) evaluates, as a table of
//! functions. [`Formulas::CHAPTER`] holds the chapter's own (each the one definition in
//! [`crate::shading`], [`crate::math`] or [`crate::light`]), and is what every render uses.
//! Another table replaces some entries by a wrong formula: that is how `lumiere diagnose`
//! renders a named mistake (src/diagnose/mistakes.rs) without a second tracer. An entry
//! that is the identity in the chapter's table ([`Formulas::light_share`],
//! [`Formulas::ambient`]) is applied only where it changes the value, so the chapter's
//! table gives the reference tracer's bits exactly.

use super::specular_term;
use crate::conventions::ShadowFilter;
use crate::material::Material;
use crate::math::{offset_origin, reflect, refract};
use crate::scene::Specular;
use crate::shading::{spot_factor, transparent_filter};
use glam::DVec3;

/// What the ambient entry knows of a hit besides its ambient term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AmbientContext {
    /// At least one shadow ray was cast at the hit and every one was blocked.
    pub in_shadow: bool,
    /// The attenuation `A` of the scene's first point or spot light at the hit (1 when
    /// there is none).
    pub attenuation: f64,
}

/// The table of formulas of one rendering.
#[derive(Clone, Copy, Debug)]
pub struct Formulas {
    /// The specular term `spec` of a model: [`specular_term`].
    pub specular: fn(Specular, DVec3, DVec3, DVec3, f64) -> f64,
    /// The law of reflection of an incident direction about the normal on its side:
    /// [`reflect`].
    pub reflect: fn(DVec3, DVec3) -> DVec3,
    /// The law of refraction (`None`: total internal reflection): [`refract`].
    pub refract: fn(DVec3, DVec3, f64) -> Option<DVec3>,
    /// The ratio `n1 / n2` at a material's surface for a ray entering or not:
    /// [`Material::eta`].
    pub eta: fn(&Material, bool) -> f64,
    /// The filter colour of one transparent object crossed by a shadow ray:
    /// [`transparent_filter`].
    pub transparent_filter: fn(ShadowFilter, f64, DVec3) -> DVec3,
    /// The origin of a shadow ray from a point (point, outward normal, error bound,
    /// direction): [`offset_origin`].
    pub shadow_origin: fn(DVec3, DVec3, f64, DVec3) -> DVec3,
    /// The direction `L` used for a light, from the unit direction towards it: the identity.
    pub light_direction: fn(DVec3) -> DVec3,
    /// A spotlight's angular factor `C_theta` (`o.d`, `cos(theta/2)`, `C_min`, `C_max`):
    /// [`spot_factor`].
    pub spot_factor: fn(f64, f64, f64, f64) -> f64,
    /// One light's share (diffuse plus specular) as it is added: the identity.
    pub light_share: fn(DVec3) -> DVec3,
    /// The ambient term `L_a k_a S` as it is added: the identity.
    pub ambient: fn(DVec3, AmbientContext) -> DVec3,
}

fn same_direction(l: DVec3) -> DVec3 {
    l
}

fn same_share(share: DVec3) -> DVec3 {
    share
}

fn same_ambient(term: DVec3, _: AmbientContext) -> DVec3 {
    term
}

impl Formulas {
    /// Chapter 7.4b's and the slides' formulas: what lumiere renders.
    pub const CHAPTER: Formulas = Formulas {
        specular: specular_term,
        reflect,
        refract,
        eta: Material::eta,
        transparent_filter,
        shadow_origin: offset_origin,
        light_direction: same_direction,
        spot_factor,
        light_share: same_share,
        ambient: same_ambient,
    };
}

impl Default for Formulas {
    fn default() -> Self {
        Formulas::CHAPTER
    }
}
