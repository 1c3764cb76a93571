//! A flat disk: center, unit normal, radius.

use super::plane::plane_t;
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

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let t = plane_t(self.center, self.normal, ray, t_min, t_max)?;
        let inside = (ray.at(t) - self.center).length_squared() <= self.radius * self.radius;
        inside.then_some(SurfaceHit { t, normal: self.normal })
    }

    /// Bound on the distance from `p` (a hit inside the disk) to the disk's plane.
    #[inline]
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

    #[test]
    fn edge_on_rays_never_hit() {
        // A ray in the disk's plane crosses its interior (here through the center) without
        // crossing the plane: d.n = 0, no hit, rather than a division by zero.
        let d = Disk::new(DVec3::new(0., 0., 1.), DVec3::Z, 2.0);
        assert!(d.intersect(&ray([-5., 0., 1.], [1., 0., 0.]), 0.0, 1e9).is_none());
        // Tilted disk, normal (1, 1, 0) / sqrt(2), and an in-plane direction (1, -1, 0) /
        // sqrt(2): both normalised by one rounded factor, so d.n = s^2 - s^2 = 0 exactly.
        let tilted = Disk::new(DVec3::new(1., 2., 3.), DVec3::new(1., 1., 0.), 2.0);
        assert!(tilted.intersect(&ray([0., 3., 3.], [1., -1., 0.]), 0.0, 1e9).is_none());
        // Control: from (0, 3, 3) moved 1e-3 off the plane along n, a ray aimed at the center
        // crosses the plane there, at t = sqrt(|(0, 3, 3) - c|^2 + 1e-6) = sqrt(2 + 1e-6)
        // ((0, 3, 3) - c = (-1, 1, 0) is perpendicular to n).
        let n = DVec3::new(1., 1., 0.).normalize();
        let start = DVec3::new(0., 3., 3.) + 1e-3 * n;
        let dir = (DVec3::new(1., 2., 3.) - start).normalize();
        let h = tilted.intersect(&Ray::new(start, dir), 0.0, 1e9).unwrap();
        assert!((h.t - (2.0f64 + 1e-6).sqrt()).abs() < 1e-12, "{}", h.t);
        assert!((h.normal - n).length() < 1e-15);
    }

    #[test]
    fn the_rim_belongs_to_the_disk() {
        // Center (0, 0, 1), radius 2: a vertical ray through the rim point (2, 0, 1) hits it
        // (|p - c|^2 = 4 <= 4, every number exact), at t = 3 - 1 = 2 from above and from
        // below alike: the normal is the disk's, whichever side the ray comes from.
        let d = Disk::new(DVec3::new(0., 0., 1.), DVec3::Z, 2.0);
        assert_hit(d.intersect(&ray([2., 0., 3.], [0., 0., -1.]), 0.0, 1e9), 2.0, DVec3::Z);
        assert_hit(d.intersect(&ray([2., 0., -4.], [0., 0., 1.]), 0.0, 1e9), 5.0, DVec3::Z);
        // One ulp outside the rim along x: |p - c|^2 = (2 + 2^-51)^2 rounds above 4.
        let outside = 2f64.next_up();
        assert!(d.intersect(&ray([outside, 0., 3.], [0., 0., -1.]), 0.0, 1e9).is_none());
    }
}
