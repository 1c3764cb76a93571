//! Edges: the pixels whose footprint spans a boundary of what the tracer sees, where another
//! sampling of the pixel (another seed, sample count or sample position, or anti-aliasing)
//! gives another colour with no shading error (`lumiere compare --scene` judges them apart).
//!
//! Each point of a pixel's footprint has a *path*: what the tracer meets along the camera
//! ray through it, recorded from the tracer itself ([`crate::trace::Recorder`]): each hit
//! (object and shading normal, or the background), and at each hit each point light's state
//! (facing away, black, blocked by an opaque object, or filtered by which transparent ones),
//! down the reflected and refracted rays the scene's depth, conventions and adaptive depth
//! control let the tracer follow. Two points are in one region when their paths have the
//! same objects and light states in the same order, with normals less than
//! [`CREASE_DEGREES`] apart (a light the surface faces away from at one point and not at the
//! other is no boundary: the shading fades to it). A pixel is an *edge* when some points of
//! its footprint are not in the first one's region: an object's silhouette, a box's or a
//! cylinder's edge, a shadow's edge, a spotlight's cone, and all of these seen in a mirror
//! or through a transparent object. Area lights' shadows are not followed (a penumbra
//! changes by one light point's share at a time).
//!
//! The points: a 4 x 4 grid spanning the closed pixel square, `(x + i / 3, y + j / 3)` for
//! `i, j` in 0..=3 (its corners included, where a renderer sampling the pixel's corner
//! looks), and every sample position of the scene's own render
//! ([`render::sample_position`]), each through the render's camera ray
//! ([`render::camera_ray`]).

use crate::light::Light;
use crate::render;
use crate::trace::{LightShare, Recorder, Tracer};
use crate::world::World;
use glam::DVec3;
use rayon::prelude::*;

/// The angle between two normals of one object beyond which the surface has a crease.
pub const CREASE_DEGREES: f64 = 30.0;

/// The grid's offsets within the pixel, along each axis.
const GRID: [f64; 4] = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0];

/// What one point light does at a hit.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LightState {
    /// The surface faces away from the light: not compared.
    Away,
    /// No light arrives before any shadow (outside a spotlight's cone).
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
    /// The state of each point light (by its index in the scene), in light order.
    pub lights: Vec<(usize, LightState)>,
}

/// Builds a path from the tracer's events.
struct PathRecorder<'a> {
    lights: &'a [Light],
    path: Vec<Node>,
    /// The transparent objects the last shadow ray crossed.
    crossed: Vec<usize>,
}

impl PathRecorder<'_> {
    /// Records `state` for light `index` at the current hit, unless it is an area light.
    fn light_state(&mut self, index: usize, state: LightState) {
        if matches!(self.lights.get(index), Some(Light::Area(_))) {
            return;
        }
        if let Some(node) = self.path.last_mut() {
            node.lights.push((index, state));
        }
    }
}

impl Recorder for PathRecorder<'_> {
    fn hit(&mut self, object: usize, _t: f64, _point: DVec3, normal: DVec3, entering: bool) {
        self.path.push(Node {
            object: Some(object),
            normal: if entering { normal } else { -normal },
            lights: Vec::new(),
        });
    }

    fn miss(&mut self) {
        self.path.push(Node {
            object: None,
            normal: DVec3::ZERO,
            lights: Vec::new(),
        });
    }

    fn unlit(&mut self, light: usize, n_dot_l: Option<f64>) {
        let state = if n_dot_l.is_some() {
            LightState::Away
        } else {
            LightState::Dark
        };
        self.light_state(light, state);
    }

    fn shadow_ray(&mut self, _ray: &crate::math::Ray, _t_max: f64) {
        self.crossed.clear();
    }

    fn shadow_crossed(&mut self, objects: &[usize]) {
        self.crossed = objects.to_vec();
    }

    fn light(&mut self, share: &LightShare) {
        // The tracer reports the crossed objects only when no opaque object blocks the ray.
        let state = if share.filter == DVec3::ZERO && self.crossed.is_empty() {
            LightState::Blocked
        } else {
            LightState::Through(std::mem::take(&mut self.crossed))
        };
        self.light_state(share.light, state);
    }
}

/// The path of image position `(px, py)` (see the module's documentation).
pub fn path_at(world: &World, px: f64, py: f64) -> Vec<Node> {
    let mut rec = PathRecorder {
        lights: &world.scene.lights,
        path: Vec::new(),
        crossed: Vec::new(),
    };
    Tracer::new(world).trace_camera(&render::camera_ray(world, (px, py)), &mut rec);
    rec.path
}

/// Whether two paths are in one region: the same objects and light states, normals less
/// than [`CREASE_DEGREES`] apart (the angle between their directions: a smooth triangle's
/// normal need not be unit).
pub fn same_region(a: &[Node], b: &[Node]) -> bool {
    let cos_crease = libm::cos(CREASE_DEGREES.to_radians());
    a.len() == b.len()
        && a.iter().zip(b).all(|(p, q)| {
            p.object == q.object
                && (p.object.is_none()
                    || p.normal.dot(q.normal) >= cos_crease * (p.normal.length() * q.normal.length()))
                && p.lights.len() == q.lights.len()
                && p.lights.iter().zip(&q.lights).all(|((i, l), (j, m))| {
                    i == j && (matches!((l, m), (LightState::Away, _) | (_, LightState::Away)) || l == m)
                })
        })
}

/// The points of pixel `(x, y)`'s footprint: the grid, then the render's samples.
pub fn footprint<'a>(world: &'a World<'a>, x: u32, y: u32) -> impl Iterator<Item = (f64, f64)> + 'a {
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
