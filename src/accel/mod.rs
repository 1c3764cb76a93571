//! Ray queries over a scene's objects: the closest hit (camera, reflection and refraction
//! rays), any hit among objects a filter accepts (opaque shadow tests), and every object hit
//! in a range (transparent shadow filtering). The linear scan is the only core so far.

mod linear;

pub use linear::Linear;

use crate::math::Ray;
use crate::scene::Object;
use crate::shape::SurfaceHit;

/// The acceleration structure chosen for a scene.
#[derive(Clone, Debug)]
pub enum Accel {
    Linear(Linear),
}

impl Accel {
    pub fn build(objects: &[Object]) -> Self {
        Accel::Linear(Linear::new(objects.len()))
    }

    /// Closest hit with `t_min < t < t_max`: object index and surface hit.
    pub fn closest(&self, objects: &[Object], ray: &Ray, t_min: f64, t_max: f64) -> Option<(usize, SurfaceHit)> {
        match self {
            Accel::Linear(l) => l.closest(objects, ray, t_min, t_max),
        }
    }

    /// True when some object accepted by `filter` is hit with `t_min < t < t_max`.
    pub fn any_hit(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
    ) -> bool {
        match self {
            Accel::Linear(l) => l.any_hit(objects, ray, t_min, t_max, filter),
        }
    }

    /// Calls `visit` once for every object accepted by `filter` that the ray hits in
    /// `(t_min, t_max)`, in no particular order.
    pub fn each_hit(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
        visit: &mut dyn FnMut(usize),
    ) {
        match self {
            Accel::Linear(l) => l.each_hit(objects, ray, t_min, t_max, filter, visit),
        }
    }
}
