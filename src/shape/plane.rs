//! The infinite plane through a point with a given normal.

use super::{Aabb, SurfaceHit};
use super::{gamma, l1};
use crate::math::Ray;
use glam::DVec3;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Plane {
    pub point: DVec3,
    /// Unit normal; the "outward" side.
    pub normal: DVec3,
}

impl Plane {
    pub fn new(point: DVec3, normal: DVec3) -> Self {
        Plane {
            point,
            normal: normal.normalize(),
        }
    }

    /// `t = (p0 - o).N / (v.N)`; rays parallel to the plane never hit.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let denom = ray.dir.dot(self.normal);
        if denom == 0.0 {
            return None;
        }
        let t = (self.point - ray.origin).dot(self.normal) / denom;
        (t > t_min && t < t_max).then_some(SurfaceHit { t, normal: self.normal })
    }

    /// Bound on the distance from `p` to the plane: `|(p - p0).N|` plus its evaluation error.
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        (p - self.point).dot(self.normal).abs() + gamma(16) * (l1(p) + l1(self.point))
    }

    pub fn bounds(&self) -> Option<Aabb> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;

    #[test]
    fn hits_from_either_side_and_misses_parallel() {
        let p = Plane::new(DVec3::ZERO, DVec3::Z);
        assert_hit(p.intersect(&ray([0., 0., 5.], [0., 0., -1.]), 0.0, 1e9), 5.0, DVec3::Z);
        assert_hit(p.intersect(&ray([1., 2., -2.], [0., 0., 1.]), 0.0, 1e9), 2.0, DVec3::Z);
        assert!(p.intersect(&ray([0., 0., 1.], [1., 0., 0.]), 0.0, 1e9).is_none());
        // Behind the origin, or beyond t_max: no hit.
        assert!(p.intersect(&ray([0., 0., 5.], [0., 0., 1.]), 0.0, 1e9).is_none());
        assert!(p.intersect(&ray([0., 0., 5.], [0., 0., -1.]), 0.0, 4.0).is_none());
    }
}
