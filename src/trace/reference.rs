//! The reference tracer: chapter 7.4b's Whitted recursion as the chapter tells it, one ray
//! and one light point at a time, with no shortcut. It is the specification of every pixel
//! ([`super::fast`] computes the same bits faster; tests/reference.rs compares them):
//!
//! 1. find the closest hit of the ray (a ray that hits nothing sees the background);
//! 2. light the hit point locally: the ambient term once, then for each light (an area
//!    light as its N point lights of colour `L / N`) the diffuse and specular shares of the
//!    light that reaches the point through a shadow ray, filtered by the colours of the
//!    transparent objects it crosses; an aperture light adds its arriving light whole
//!    unless its shadow ray is black;
//! 3. below the scene's recursion depth, add `k_r` times the radiance of the reflected ray
//!    and `k_t` times that of the refracted ray, whose energy goes to the reflection on
//!    total internal reflection; adaptive depth control leaves out a secondary ray that
//!    cannot change its pixel's 8-bit value.
//!
//! Where SIMRenderer's conventions differ from the chapter's, the scene's
//! [`crate::conventions::Conventions`] decide: how far a camera ray sees, what weighs the
//! local terms, which objects refract, where the energy of a total internal reflection
//! goes, what weighs a refracted ray and what a transparent object filters shadows by.
//!
//! Each formula is evaluated through a table of functions ([`Formulas`](super::Formulas)): the chapter's
//! ([`Formulas::CHAPTER`](super::Formulas::CHAPTER)) for every render, another for a named mistake of
//! `lumiere diagnose`.

use super::formulas::{AmbientContext, Chapter, FormulaTable};
use super::{SampleKey, Surface, caustic_share, point_light_terms_with};
use crate::light::{Incidence, Light, aperture_share, point_incidence};
use crate::math::Ray;
use crate::shading::{ambient, beneath_notice, faces_away, local_weight, no_light, shadow_filter, transmission_weight};
use crate::world::World;
use glam::DVec3;

/// Traces rays through a world, as the chapter does, evaluating the formulas of `F` (the
/// chapter's, [`Chapter`], unless told otherwise).
pub struct Reference<'w, 's, F: FormulaTable = Chapter> {
    world: &'w World<'s>,
    formulas: F,
}

/// What the lights did at a hit, for the ambient entry of [`Formulas`].
#[derive(Clone, Copy, Default)]
struct Shadowing {
    cast: u32,
    blocked: u32,
}

impl<'w, 's> Reference<'w, 's> {
    pub fn new(world: &'w World<'s>) -> Self {
        Reference::with_formulas(world, Chapter)
    }
}

impl<'w, 's, F: FormulaTable> Reference<'w, 's, F> {
    /// A tracer evaluating `formulas` (a [`super::Formulas`] table with wrong entries, say).
    pub fn with_formulas(world: &'w World<'s>, formulas: F) -> Self {
        Reference { world, formulas }
    }

    /// The world it traces.
    pub fn world(&self) -> &'w World<'s> {
        self.world
    }

    /// Radiance along the camera ray of sample `key`.
    pub fn camera(&self, ray: &Ray, key: SampleKey) -> DVec3 {
        self.radiance(ray, 1, 1.0, key)
    }

    /// Radiance along `ray` at recursion `level` (1 = camera ray), whose contribution to the
    /// pixel is scaled by `weight`, the product of the `k_r` and `k_t` along its path.
    fn radiance(&self, ray: &Ray, level: u32, weight: f64, key: SampleKey) -> DVec3 {
        let settings = &self.world.scene.settings;
        let conventions = &settings.conventions;
        let t_max = if level == 1 { conventions.far } else { f64::INFINITY };
        let Some((object, hit)) = self.formulas.closest(self.world, ray, t_max) else {
            return settings.background;
        };
        let at = Surface::hit(self.world, ray, object, &hit);
        let mat = self.world.material_of(object);
        let mut color = self.local(&at, key) * local_weight(conventions.local_weight, mat.kr, mat.kt);
        if level < settings.depth {
            let mut kr = mat.kr;
            let mut refracted = None;
            let closed = self.world.objects()[object].shape.is_closed();
            if mat.kt > 0.0 && conventions.refracting.admits(closed) {
                match self.formulas.refract(
                    ray.dir,
                    self.formulas.refraction_normal(at.n, at.outward),
                    self.formulas.eta(mat, at.entering),
                ) {
                    Some(t) => refracted = Some(t.normalize()),
                    // Total internal reflection: the transmitted energy is reflected, or lost.
                    None => kr = conventions.total_internal_reflection.reflected_weight(kr, mat.kt),
                }
            }
            if kr > 0.0 {
                let dir = self.formulas.reflect(ray.dir, at.n).normalize();
                color += kr * self.secondary(&at, dir, level, weight * kr, key);
            }
            if let Some(dir) = refracted {
                let kt = transmission_weight(conventions.transmission, mat.kt, mat.color, at.entering);
                color += kt * self.secondary(&at, dir, level, weight * kt.max_element(), key);
            }
        }
        color
    }

    /// The radiance of the reflected or refracted ray leaving `from` along `dir`, or 0 when
    /// adaptive depth control finds it cannot change its pixel.
    fn secondary(&self, from: &Surface, dir: DVec3, level: u32, weight: f64, key: SampleKey) -> DVec3 {
        let bound = self.world.remaining_bound[level as usize + 1];
        if beneath_notice(weight, bound, self.world.scene.settings.adaptive_threshold) {
            return DVec3::ZERO;
        }
        self.radiance(&from.ray_along(dir), level + 1, weight, key)
    }

    /// Local illumination at a hit (slides' full model):
    /// `L = L_a k_a S + sum_i A_i L_i [k_d S max(N.L_i, 0) + k_s [m S + (1 - m)] spec_i]`,
    /// an area light counting as its N points of colour `L / N`, summed in light order and
    /// an area light's points in their order; then, with caustics, the caustic share
    /// `E k_d S` of the photons that land near the point.
    fn local(&self, at: &Surface, key: SampleKey) -> DVec3 {
        let world = self.world;
        let f = &self.formulas;
        let (model, mat) = (world.scene.settings.shading, world.material_of(at.object));
        let mut color = DVec3::ZERO;
        let r = at.reflectance(mat);
        if model.no_light {
            return no_light(r.kd, r.diffuse);
        }
        let ambient_term = ambient(world.ambient, r.ka, r.ambient);
        if model.ambient {
            color += ambient_term;
        }
        let mut shadowing = Shadowing::default();
        let mut attenuation = None;
        for (index, light) in world.scene.lights.iter().enumerate() {
            match light {
                Light::Ambient { .. } => {}
                Light::Area(area) => {
                    for q in world.area_points(index, key.pixel, key.sample).iter() {
                        let incidence = point_incidence(q, area.point_color(), &area.attenuation, at.point, 1.0);
                        color += self.light_share(incidence, at, &mut shadowing);
                    }
                }
                Light::Aperture(a) => color += self.aperture_light(a.color, light.incidence(at.point), at),
                _ => {
                    let incidence = light.incidence_with(at.point, f.spot_factor());
                    if F::AMBIENT_CONTEXT && matches!(light, Light::Point(_) | Light::Spot(_)) && attenuation.is_none()
                    {
                        attenuation = incidence.map(|inc| inc.attenuation);
                    }
                    color += self.light_share(incidence, at, &mut shadowing);
                }
            }
        }
        if let Some((term, _)) = caustic_share(world, model, mat, at) {
            color += term;
        }
        if F::AMBIENT_CONTEXT && model.ambient {
            let context = AmbientContext {
                in_shadow: shadowing.cast > 0 && shadowing.blocked == shadowing.cast,
                attenuation: attenuation.unwrap_or(1.0),
            };
            let added = f.ambient(ambient_term, context);
            // Where the entry is the identity the sum is left as it is, to the bit.
            if added != ambient_term {
                color += added - ambient_term;
            }
        }
        color
    }

    /// One point light's share, `A L filter [k_d S max(N.L, 0) + k_s [m S + (1 - m)] spec]`:
    /// nothing when no light arrives (the point is at the light) or the surface faces away
    /// (the `faces_away` entry: `N.L <= 0`, where the slides count neither term); otherwise
    /// the light that the shadow ray lets through.
    fn light_share(&self, incidence: Option<Incidence>, at: &Surface, shadowing: &mut Shadowing) -> DVec3 {
        let world = self.world;
        let f = &self.formulas;
        let Some(mut inc) = incidence else {
            return DVec3::ZERO;
        };
        inc.to_light = f.light_direction(inc.to_light);
        let n_dot_l = at.n.dot(inc.to_light);
        if f.faces_away(n_dot_l) {
            return DVec3::ZERO;
        }
        let filter = if world.scene.settings.shadows {
            let filter = self.shadow_filter(at, &inc);
            if F::AMBIENT_CONTEXT {
                shadowing.cast += 1;
                shadowing.blocked += u32::from(filter == DVec3::ZERO);
            }
            filter
        } else {
            DVec3::ONE
        };
        let (model, mat) = (world.scene.settings.shading, world.material_of(at.object));
        let (diffuse, specular) = point_light_terms_with(
            |model, n, l, e, exponent| f.specular(model, n, l, e, exponent),
            model,
            mat,
            at,
            inc.to_light,
            n_dot_l,
            inc.color * filter,
        );
        f.light_share(diffuse + specular)
    }

    /// The share of an aperture light of colour `light` ([`aperture_share`]): nothing when
    /// no light arrives or the surface faces away from the aperture's centre (`N.L <= 0`,
    /// [`faces_away`] itself, not the table's entry: this share has no specular term), else
    /// its arriving light unless the shadow ray towards the centre blackens it.
    fn aperture_light(&self, light: DVec3, incidence: Option<Incidence>, at: &Surface) -> DVec3 {
        let Some(inc) = incidence else {
            return DVec3::ZERO;
        };
        if faces_away(at.n.dot(inc.to_light)) {
            return DVec3::ZERO;
        }
        let filter = if self.world.scene.settings.shadows {
            self.shadow_filter(at, &inc)
        } else {
            DVec3::ONE
        };
        aperture_share(light, filter, inc.color)
    }

    /// Chapter 7.4b's shadow ray towards the light of incidence `inc`, up to the light
    /// (`t_max` = its distance): 0 if it meets an opaque object, else the product of the
    /// filters of the transparent objects it crosses (their colours, or `k_t S` by the
    /// conventions), each counted once, in object order.
    fn shadow_filter(&self, at: &Surface, inc: &Incidence) -> DVec3 {
        let world = self.world;
        let f = &self.formulas;
        let ray = Ray::new(
            f.shadow_origin(at.point, at.outward, at.err, inc.to_light),
            inc.to_light,
        );
        let reach = f.shadow_reach(inc.distance);
        let transparent = |i: usize| world.filters_shadows(i);
        if world.any_hit(&ray, reach, &|i| !transparent(i)) {
            return DVec3::ZERO;
        }
        let mut crossed = Vec::new();
        world.each_hit(&ray, reach, &transparent, &mut |i| crossed.push(i));
        crossed.sort_unstable();
        let rule = world.scene.settings.conventions.shadow_filter;
        shadow_filter(crossed.into_iter().map(|i| {
            let mat = world.material_of(i);
            f.transparent_filter(rule, mat.kt, mat.color)
        }))
    }
}
