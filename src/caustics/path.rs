//! One photon's path: from its light, through reflections and refractions, to the diffuse
//! surfaces where it is stored. It meets objects through the scene's intersection core and
//! bends by the laws rays bend by ([`reflect`], [`refract`], [`total_internal_reflection`](crate::math::total_internal_reflection)
//! through `refract`), under the scene's conventions (which objects refract, where a total
//! internal reflection's weight goes, what weighs a refracted ray).
//!
//! Where a Whitted ray splits into a reflected ray of weight `k_r` and a refracted ray of
//! weight `k_t`, a photon takes one of them (Russian roulette, Jensen 2001, section 5.2):
//! it goes on with probability `p = min(k_r + k_t, 1)`, reflected with probability
//! `k_r / (k_r + k_t)` of that, else refracted, its flux multiplied by `(k_r + k_t) / p` and,
//! when refracted, by the colour part of the transmission weight (`transmission / k_t`).
//! The expected flux of each branch is then the Whitted weight times the flux.
//!
//! A photon is stored at every hit on a surface with `k_d > 0` that does not bend light
//! itself (not glass of an index other than 1: its light is what it lets through) once it has
//! made at least one bounce that turned it: a reflection, or a refraction into or out of an
//! index other than 1. Light that only crossed objects of index 1 goes straight, and the
//! shadow rays' colour filter already brings it.

use super::emit::Start;
use super::map::Photon;
use crate::accel::Accel;
use crate::math::{Ray, facing_normal, reflect, refract};
use crate::sampling::Stream;
use crate::scene::Scene;
use crate::shading::transmission_weight;

/// Traces the photon `start` for at most `bounces` specular bounces, drawing its roulette
/// from `rng`, and pushes the photons it stores onto `out`.
pub fn trace(scene: &Scene, accel: &Accel, start: Start, bounces: u32, rng: &mut Stream, out: &mut Vec<Photon>) {
    let conventions = &scene.settings.conventions;
    let mut ray = start.ray;
    let mut flux = start.flux;
    let mut travelled = 0.0;
    let mut turned = false;
    for bounce in 0..=bounces {
        let Some((object, hit)) = accel.closest(&scene.objects, &ray, 0.0, f64::INFINITY) else {
            return;
        };
        if bounce == 0 && object != start.target {
            return;
        }
        let shape = &scene.objects[object].shape;
        let mat = &scene.materials[scene.objects[object].material()];
        let (point, err) = shape.hit_point(&ray, hit.t);
        travelled += hit.t;
        let (entering, n) = facing_normal(ray.dir, hit.normal);
        if turned && mat.receives_photons() {
            out.push(Photon::new(point, ray.dir, flux * start.spread.factor(travelled)));
        }
        if bounce == bounces {
            return;
        }
        let mut kr = mat.kr;
        let mut kt = 0.0;
        let mut refracted = None;
        if mat.kt > 0.0 && conventions.refracting.admits(shape.is_closed()) {
            match refract(ray.dir, n, mat.eta(entering)) {
                Some(t) => {
                    refracted = Some(t.normalize());
                    kt = mat.kt;
                }
                None => kr = conventions.total_internal_reflection.reflected_weight(kr, mat.kt),
            }
        }
        let k = kr + kt;
        let go_on = k.min(1.0);
        let u = rng.next_f64();
        if u >= go_on {
            return;
        }
        flux *= k / go_on;
        // The same number, rescaled to [0, k): below k_r reflects.
        let dir = match refracted {
            Some(t) if u / go_on * k >= kr => {
                flux *= transmission_weight(conventions.transmission, mat.kt, mat.color, entering) / mat.kt;
                turned |= mat.ior != 1.0;
                t
            }
            _ => {
                turned = true;
                reflect(ray.dir, n).normalize()
            }
        };
        ray = Ray::leaving(point, hit.normal, err, dir);
    }
}
