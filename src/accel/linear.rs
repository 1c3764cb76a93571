//! The linear scan: every object, every ray. Best for the course's handful of objects.

use crate::math::Ray;
use crate::scene::Object;
use crate::shape::SurfaceHit;

#[derive(Clone, Debug)]
pub struct Linear {
    count: usize,
}

impl Linear {
    pub fn new(count: usize) -> Self {
        Linear { count }
    }

    pub fn closest(&self, objects: &[Object], ray: &Ray, t_min: f64, mut t_max: f64) -> Option<(usize, SurfaceHit)> {
        let mut best = None;
        for (i, o) in objects[..self.count].iter().enumerate() {
            if let Some(h) = o.shape.intersect(ray, t_min, t_max) {
                t_max = h.t;
                best = Some((i, h));
            }
        }
        best
    }

    pub fn any_hit(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
    ) -> bool {
        objects[..self.count]
            .iter()
            .enumerate()
            .any(|(i, o)| filter(i) && o.shape.occludes(ray, t_min, t_max))
    }

    pub fn each_hit(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
        visit: &mut dyn FnMut(usize),
    ) {
        for (i, o) in objects[..self.count].iter().enumerate() {
            if filter(i) && o.shape.occludes(ray, t_min, t_max) {
                visit(i);
            }
        }
    }
}
