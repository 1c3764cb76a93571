//! A flat disk: centre, unit normal, radius.

use super::{Aabb, SurfaceHit};
use super::{gamma, l1};
use crate::math::Ray;
use glam::DVec3;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Disk {
    pub center: DVec3,
    pub normal: DVec3,
    pub radius: f64,
}

impl Disk {
    pub fn new(center: DVec3, normal: DVec3, radius: f64) -> Self {
        Disk {
            center,
            normal: normal.normalize(),
            radius,
        }
    }

    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let denom = ray.dir.dot(self.normal);
        if denom == 0.0 {
            return None;
        }
        let t = (self.center - ray.origin).dot(self.normal) / denom;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let inside = (ray.at(t) - self.center).length_squared() <= self.radius * self.radius;
        inside.then_some(SurfaceHit { t, normal: self.normal })
    }

    /// Bound on the distance from `p` (a hit inside the disk) to the disk's plane.
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        (p - self.center).dot(self.normal).abs() + gamma(16) * (l1(p) + l1(self.center) + self.radius)
    }

    /// Tight box: along each axis the disk extends `r sqrt(1 - n_i^2)`.
    pub fn bounds(&self) -> Option<Aabb> {
        let e = (DVec3::ONE - self.normal * self.normal).max(DVec3::ZERO);
        let ext = DVec3::new(e.x.sqrt(), e.y.sqrt(), e.z.sqrt()) * self.radius;
        Some(Aabb::new(self.center - ext, self.center + ext))
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;

    #[test]
    fn hits_within_the_radius_only() {
        let d = Disk::new(DVec3::new(0., 0., 1.), DVec3::Z, 2.0);
        assert_hit(d.intersect(&ray([1.9, 0., 3.], [0., 0., -1.]), 0.0, 1e9), 2.0, DVec3::Z);
        assert!(d.intersect(&ray([2.1, 0., 3.], [0., 0., -1.]), 0.0, 1e9).is_none());
        let b = d.bounds().unwrap();
        assert_eq!(b.min, DVec3::new(-2., -2., 1.));
        assert_eq!(b.max, DVec3::new(2., 2., 1.));
    }
}
