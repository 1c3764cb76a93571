//! The formulas the reference tracer ([`super::Reference`]) evaluates, through the trait
//! [`FormulaTable`]: [`Chapter`] calls the chapter's own functions (each the one definition
//! in [`crate::shading`], [`crate::math`] or [`crate::light`]) and is what the reference
//! tracer uses unless told otherwise, compiled as direct calls; [`Formulas`] is the same
//! table as function pointers, [`Formulas::CHAPTER`] holding the same functions, and a copy
//! with some entries replaced by a wrong formula, or with every specular exponent scaled, is
//! how `lumiere diagnose` renders a named mistake (src/diagnose/mistakes.rs) without a
//! second tracer. An entry that is the
//! identity in the chapter's table (`light_share`, `ambient`) is applied only where it
//! changes the value, so the chapter's table gives the reference tracer's bits exactly.

use super::specular_term;
use crate::conventions::ShadowFilter;
use crate::material::Material;
use crate::math::{Ray, offset_origin, reflect, refract};
use crate::scene::Specular;
use crate::shading::{faces_away, spot_factor, transparent_filter};
use crate::shape::SurfaceHit;
use crate::world::World;
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
    /// The closest hit of a camera or secondary ray before `t_max` (object index and
    /// hit): [`World::closest_before`].
    pub closest: fn(&World<'_>, &Ray, f64) -> Option<(usize, SurfaceHit)>,
    /// The specular term `spec` of a model: [`specular_term`].
    pub specular: fn(Specular, DVec3, DVec3, DVec3, f64) -> f64,
    /// The factor a material's specular exponent `n` is multiplied by before the specular
    /// entry reads it: 1, which leaves every exponent's bits as they are.
    pub exponent_scale: f64,
    /// The law of reflection of an incident direction about the normal on its side:
    /// [`reflect`].
    pub reflect: fn(DVec3, DVec3) -> DVec3,
    /// The law of refraction (`None`: total internal reflection): [`refract`].
    pub refract: fn(DVec3, DVec3, f64) -> Option<DVec3>,
    /// The normal the law of refraction is given, from the normal on the incident ray's side
    /// and the outward one: the one on the ray's side.
    pub refraction_normal: fn(DVec3, DVec3) -> DVec3,
    /// The ratio `n1 / n2` at a material's surface for a ray entering or not:
    /// [`Material::eta`].
    pub eta: fn(&Material, bool) -> f64,
    /// The filter colour of one transparent object crossed by a shadow ray:
    /// [`transparent_filter`].
    pub transparent_filter: fn(ShadowFilter, f64, DVec3) -> DVec3,
    /// The origin of a shadow ray from a point (point, outward normal, error bound,
    /// direction): [`offset_origin`].
    pub shadow_origin: fn(DVec3, DVec3, f64, DVec3) -> DVec3,
    /// How far a shadow ray looks for blockers, from the light's distance: the identity.
    pub shadow_reach: fn(f64) -> f64,
    /// The direction `L` used for a light, from the unit direction towards it: the identity.
    pub light_direction: fn(DVec3) -> DVec3,
    /// Whether a point, spot or directional light, or one point of an area light, is left
    /// out at a hit from its `N.L` (no shadow ray, neither diffuse nor specular term):
    /// [`faces_away`], `N.L <= 0`. An aperture light's own test of `N.L` towards its
    /// centre does not read it: its share is its arriving light whole, with no specular
    /// term.
    pub faces_away: fn(f64) -> bool,
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

fn normal_on_the_rays_side(facing: DVec3, _outward: DVec3) -> DVec3 {
    facing
}

fn closest_before(world: &World<'_>, ray: &Ray, t_max: f64) -> Option<(usize, SurfaceHit)> {
    world.closest_before(ray, t_max)
}

fn same_distance(distance: f64) -> f64 {
    distance
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
        closest: closest_before,
        specular: specular_term,
        exponent_scale: 1.0,
        reflect,
        refract,
        refraction_normal: normal_on_the_rays_side,
        eta: Material::eta,
        transparent_filter,
        shadow_origin: offset_origin,
        shadow_reach: same_distance,
        light_direction: same_direction,
        faces_away,
        spot_factor,
        light_share: same_share,
        ambient: same_ambient,
    };
}

/// What the reference tracer evaluates: one method per entry of [`Formulas`].
pub trait FormulaTable: Copy + Send + Sync {
    /// Whether the `ambient` entry reads its [`AmbientContext`] (the tracer gathers it
    /// only then): false for the chapter's, whose entry is the identity.
    const AMBIENT_CONTEXT: bool = true;
    fn closest(&self, world: &World<'_>, ray: &Ray, t_max: f64) -> Option<(usize, SurfaceHit)>;
    fn specular(&self, model: Specular, n: DVec3, l: DVec3, e: DVec3, exponent: f64) -> f64;
    fn reflect(&self, v: DVec3, n: DVec3) -> DVec3;
    fn refract(&self, v: DVec3, n: DVec3, eta: f64) -> Option<DVec3>;
    fn refraction_normal(&self, facing: DVec3, outward: DVec3) -> DVec3;
    fn eta(&self, mat: &Material, entering: bool) -> f64;
    fn transparent_filter(&self, rule: ShadowFilter, kt: f64, s: DVec3) -> DVec3;
    fn shadow_origin(&self, point: DVec3, outward: DVec3, err: f64, dir: DVec3) -> DVec3;
    fn shadow_reach(&self, distance: f64) -> f64;
    fn light_direction(&self, l: DVec3) -> DVec3;
    fn faces_away(&self, n_dot_l: f64) -> bool;
    fn spot_factor(&self) -> fn(f64, f64, f64, f64) -> f64;
    fn light_share(&self, share: DVec3) -> DVec3;
    fn ambient(&self, term: DVec3, context: AmbientContext) -> DVec3;
}

/// The chapter's formulas as direct calls: the entries of [`Formulas::CHAPTER`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Chapter;

impl FormulaTable for Chapter {
    const AMBIENT_CONTEXT: bool = false;
    #[inline(always)]
    fn closest(&self, world: &World<'_>, ray: &Ray, t_max: f64) -> Option<(usize, SurfaceHit)> {
        closest_before(world, ray, t_max)
    }
    #[inline(always)]
    fn specular(&self, model: Specular, n: DVec3, l: DVec3, e: DVec3, exponent: f64) -> f64 {
        specular_term(model, n, l, e, exponent)
    }
    #[inline(always)]
    fn reflect(&self, v: DVec3, n: DVec3) -> DVec3 {
        reflect(v, n)
    }
    #[inline(always)]
    fn refract(&self, v: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
        refract(v, n, eta)
    }
    #[inline(always)]
    fn refraction_normal(&self, facing: DVec3, outward: DVec3) -> DVec3 {
        normal_on_the_rays_side(facing, outward)
    }
    #[inline(always)]
    fn eta(&self, mat: &Material, entering: bool) -> f64 {
        mat.eta(entering)
    }
    #[inline(always)]
    fn transparent_filter(&self, rule: ShadowFilter, kt: f64, s: DVec3) -> DVec3 {
        transparent_filter(rule, kt, s)
    }
    #[inline(always)]
    fn shadow_origin(&self, point: DVec3, outward: DVec3, err: f64, dir: DVec3) -> DVec3 {
        offset_origin(point, outward, err, dir)
    }
    #[inline(always)]
    fn shadow_reach(&self, distance: f64) -> f64 {
        same_distance(distance)
    }
    #[inline(always)]
    fn light_direction(&self, l: DVec3) -> DVec3 {
        same_direction(l)
    }
    #[inline(always)]
    fn faces_away(&self, n_dot_l: f64) -> bool {
        faces_away(n_dot_l)
    }
    #[inline(always)]
    fn spot_factor(&self) -> fn(f64, f64, f64, f64) -> f64 {
        spot_factor
    }
    #[inline(always)]
    fn light_share(&self, share: DVec3) -> DVec3 {
        same_share(share)
    }
    #[inline(always)]
    fn ambient(&self, term: DVec3, context: AmbientContext) -> DVec3 {
        same_ambient(term, context)
    }
}

impl FormulaTable for Formulas {
    fn closest(&self, world: &World<'_>, ray: &Ray, t_max: f64) -> Option<(usize, SurfaceHit)> {
        (self.closest)(world, ray, t_max)
    }
    fn specular(&self, model: Specular, n: DVec3, l: DVec3, e: DVec3, exponent: f64) -> f64 {
        (self.specular)(model, n, l, e, exponent * self.exponent_scale)
    }
    fn reflect(&self, v: DVec3, n: DVec3) -> DVec3 {
        (self.reflect)(v, n)
    }
    fn refract(&self, v: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
        (self.refract)(v, n, eta)
    }
    fn refraction_normal(&self, facing: DVec3, outward: DVec3) -> DVec3 {
        (self.refraction_normal)(facing, outward)
    }
    fn eta(&self, mat: &Material, entering: bool) -> f64 {
        (self.eta)(mat, entering)
    }
    fn transparent_filter(&self, rule: ShadowFilter, kt: f64, s: DVec3) -> DVec3 {
        (self.transparent_filter)(rule, kt, s)
    }
    fn shadow_origin(&self, point: DVec3, outward: DVec3, err: f64, dir: DVec3) -> DVec3 {
        (self.shadow_origin)(point, outward, err, dir)
    }
    fn shadow_reach(&self, distance: f64) -> f64 {
        (self.shadow_reach)(distance)
    }
    fn light_direction(&self, l: DVec3) -> DVec3 {
        (self.light_direction)(l)
    }
    fn faces_away(&self, n_dot_l: f64) -> bool {
        (self.faces_away)(n_dot_l)
    }
    fn spot_factor(&self) -> fn(f64, f64, f64, f64) -> f64 {
        self.spot_factor
    }
    fn light_share(&self, share: DVec3) -> DVec3 {
        (self.light_share)(share)
    }
    fn ambient(&self, term: DVec3, context: AmbientContext) -> DVec3 {
        (self.ambient)(term, context)
    }
}

impl Default for Formulas {
    fn default() -> Self {
        Formulas::CHAPTER
    }
}
