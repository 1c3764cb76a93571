//! Edges: the pixels whose footprint spans a boundary of what the tracer sees, where another
//! sampling of the pixel (another seed, sample count or sample position, or anti-aliasing)
//! gives another colour with no shading error.
//!
//! Each point of a pixel's footprint has a *path*: what the tracer meets from it, as the
//! reference tracer ([`crate::trace::reference`]) follows it: the camera ray's hit (object
//! and normal, or the background), then at that hit each light's state (facing away; or
//! whether its light arrives, blocked by an opaque object, or filtered by which transparent
//! ones), then the reflected and the refracted rays' paths below the recursion depth (with
//! the scene's conventions on which objects refract, total internal reflection and adaptive
//! depth control). Two points are in one region when their paths have the same objects and
//! light states in the same order, with normals less than [`CREASE_DEGREES`] apart (a light
//! the surface faces away from at one point and not at the other is no boundary: the
//! shading fades to it). A pixel is an *edge* when some points of its footprint are not in
//! the first one's region: an object's silhouette, a box's or a cylinder's edge, a shadow's
//! edge, a spotlight's cone, and all of these seen in a mirror or through a transparent
//! object.
//!
//! The points: a 4 x 4 grid spanning the closed pixel square, `(x + i / 3, y + j / 3)` for
//! `i, j` in 0..=3 (its corners included, where a renderer sampling the pixel's corner
//! looks), and every sample position of the scene's own render
//! ([`render::sample_position`]). Camera rays follow the conventions as the render's do:
//! from the eye or from the image plane at `near`, up to `far`. Area lights' shadows are not
//! followed (a penumbra changes by one light point's share at a time).
//!
//! This module traces the scene's rays, so it sits above [`crate::world`] and
//! [`crate::render`] in the module map, unlike the rest of [`crate::compare`].

use crate::conventions::{InternalReflection, RayOrigin};
use crate::light::Light;
use crate::math::{Ray, reflect, refract};
use crate::render;
use crate::shading::{beneath_notice, transmission_weight};
use crate::trace::Surface;
use crate::world::World;
use glam::DVec3;
use rayon::prelude::*;

/// The angle between two normals of one object beyond which the surface has a crease.
pub const CREASE_DEGREES: f64 = 30.0;

/// The grid's offsets within the pixel, along each axis.
const GRID: [f64; 4] = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0];

/// What one light does at a hit.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LightState {
    /// The surface faces away from the light, or the point is at it: not compared.
    Away,
    /// Black before any shadow (outside a spotlight's cone).
    Dark,
    /// An opaque object blocks the shadow ray.
    Blocked,
    /// The light arrives through these transparent objects (ascending; none: unshadowed).
    Through(Vec<usize>),
}

/// One hit of a path.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// The object hit; `None` for the background.
    pub object: Option<usize>,
    /// The unit normal on the ray's side (zero for the background).
    pub normal: DVec3,
    /// Each light's state, in light order (empty for the background, or without shadows).
    pub lights: Vec<LightState>,
}

/// The camera ray through image position `(px, py)` under the scene's conventions.
fn camera_ray(world: &World, px: f64, py: f64) -> Ray {
    let s = &world.scene.settings;
    match s.conventions.ray_origin {
        RayOrigin::Eye => world.camera.ray(px, py, s.width, s.height),
        RayOrigin::NearPlane => world
            .camera
            .ray_from_plane(px, py, s.width, s.height, s.conventions.near),
    }
}

/// The path of image position `(px, py)` (see the module's documentation).
pub fn path_at(world: &World, px: f64, py: f64) -> Vec<Node> {
    let mut path = Vec::new();
    follow(world, &camera_ray(world, px, py), 1, 1.0, &mut path);
    path
}

/// Appends the path of `ray` at recursion `level` (1: the camera ray), whose contribution
/// is scaled by `weight`, as the reference tracer recurses.
fn follow(world: &World, ray: &Ray, level: u32, weight: f64, path: &mut Vec<Node>) {
    let settings = &world.scene.settings;
    let conventions = &settings.conventions;
    let t_max = if level == 1 { conventions.far } else { f64::INFINITY };
    let Some((object, hit)) = world.closest_before(ray, t_max) else {
        path.push(Node {
            object: None,
            normal: DVec3::ZERO,
            lights: Vec::new(),
        });
        return;
    };
    let at = Surface::hit(world, ray, object, &hit);
    let lights = if settings.shadows {
        world.scene.lights.iter().map(|l| light_state(world, l, &at)).collect()
    } else {
        Vec::new()
    };
    path.push(Node {
        object: Some(object),
        normal: at.n,
        lights,
    });
    if level >= settings.depth {
        return;
    }
    let mat = world.material_of(object);
    let mut kr = mat.kr;
    let mut refracted = None;
    if mat.kt > 0.0 && conventions.refracting.admits(world.objects()[object].shape.is_closed()) {
        match refract(ray.dir, at.n, mat.eta(at.entering)) {
            Some(t) => refracted = Some(t.normalize()),
            None if conventions.total_internal_reflection == InternalReflection::Reflected => kr += mat.kt,
            None => {}
        }
    }
    let secondary = |dir: DVec3, w: f64, path: &mut Vec<Node>| {
        let bound = world.remaining_bound[level as usize + 1];
        if !beneath_notice(w, bound, settings.adaptive_threshold) {
            follow(world, &at.ray_along(dir), level + 1, w, path);
        }
    };
    if kr > 0.0 {
        secondary(reflect(ray.dir, at.n).normalize(), weight * kr, path);
    }
    if let Some(dir) = refracted {
        let kt = transmission_weight(conventions.transmission, mat.kt, mat.color, at.entering);
        secondary(dir, weight * kt.max_element(), path);
    }
}

/// What `light` does at the hit `at`.
fn light_state(world: &World, light: &Light, at: &Surface) -> LightState {
    let Some(inc) = light.incidence(at.point) else {
        return LightState::Away;
    };
    if at.n.dot(inc.to_light) <= 0.0 {
        return LightState::Away;
    }
    if inc.color == DVec3::ZERO {
        return LightState::Dark;
    }
    let ray = at.ray_along(inc.to_light);
    let transparent = |i: usize| world.material_of(i).is_transparent();
    if world.any_hit(&ray, inc.distance, &|i| !transparent(i)) {
        return LightState::Blocked;
    }
    let mut crossed = Vec::new();
    world.each_hit(&ray, inc.distance, &transparent, &mut |i| crossed.push(i));
    crossed.sort_unstable();
    crossed.dedup();
    LightState::Through(crossed)
}

/// Whether two paths are in one region: the same objects and light states, normals less
/// than [`CREASE_DEGREES`] apart.
pub fn same_region(a: &[Node], b: &[Node]) -> bool {
    let cos_crease = libm::cos(CREASE_DEGREES.to_radians());
    a.len() == b.len()
        && a.iter().zip(b).all(|(p, q)| {
            p.object == q.object
                && (p.object.is_none() || p.normal.dot(q.normal) >= cos_crease)
                && p.lights
                    .iter()
                    .zip(&q.lights)
                    .all(|(l, m)| matches!((l, m), (LightState::Away, _) | (_, LightState::Away)) || l == m)
        })
}

/// The points of pixel `(x, y)`'s footprint: the grid, then the render's samples.
fn footprint<'a>(world: &'a World<'a>, x: u32, y: u32) -> impl Iterator<Item = (f64, f64)> + 'a {
    let (fx, fy) = (x as f64, y as f64);
    let spp = world.scene.settings.samples_per_pixel;
    GRID.iter()
        .flat_map(move |&j| GRID.iter().map(move |&i| (fx + i, fy + j)))
        .chain((0..spp).map(move |k| render::sample_position(world, x, y, k)))
}

/// Whether pixel `(x, y)` is an edge (see the module's documentation).
pub fn is_edge(world: &World, x: u32, y: u32) -> bool {
    let mut points = footprint(world, x, y);
    let Some((px, py)) = points.next() else {
        return false;
    };
    let first = path_at(world, px, py);
    points.any(|(px, py)| !same_region(&first, &path_at(world, px, py)))
}

/// The edge mask of the scene's image, row-major, rows in parallel on the current rayon
/// pool (the result does not depend on the thread count).
pub fn edge_mask(world: &World) -> Vec<bool> {
    let s = &world.scene.settings;
    let (w, h) = (s.width, s.height);
    (0..h)
        .into_par_iter()
        .flat_map_iter(|y| (0..w).map(move |x| is_edge(world, x, y)))
        .collect()
}
