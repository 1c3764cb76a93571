//! A parallelogram given by a corner and two edges: `corner + u e1 + v e2`, `u, v in [0, 1]`
//! (the finite mirrors of the `mirrors` figures).

use super::plane::plane_t;
use super::{Aabb, SurfaceHit};
use super::{gamma, l1};
use crate::math::Ray;
use glam::DVec3;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Rectangle {
    pub corner: DVec3,
    pub edge1: DVec3,
    pub edge2: DVec3,
    /// `e1 x e2`, not normalised (used for the barycentric solve).
    #[serde(skip)]
    cross: DVec3,
    /// Unit normal, along `e1 x e2`.
    #[serde(skip)]
    normal: DVec3,
}

impl Rectangle {
    /// The edges must not be parallel (checked when the scene is validated).
    pub fn new(corner: DVec3, edge1: DVec3, edge2: DVec3) -> Self {
        let cross = edge1.cross(edge2);
        Rectangle {
            corner,
            edge1,
            edge2,
            cross,
            normal: cross.normalize(),
        }
    }

    /// Plane hit, then `u = ((p - c) x e2).n / |n|^2`, `v = (e1 x (p - c)).n / |n|^2`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let t = plane_t(self.corner, self.normal, ray, t_min, t_max)?;
        let w = ray.at(t) - self.corner;
        let n2 = self.cross.length_squared();
        let u = w.cross(self.edge2).dot(self.cross) / n2;
        let v = self.edge1.cross(w).dot(self.cross) / n2;
        ((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)).then_some(SurfaceHit { t, normal: self.normal })
    }

    /// Bound on the distance from `p` (a hit inside the rectangle) to its plane.
    #[inline]
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        let size = l1(self.edge1) + l1(self.edge2);
        (p - self.corner).dot(self.normal).abs() + gamma(16) * (l1(p) + l1(self.corner) + size)
    }

    pub fn bounds(&self) -> Option<Aabb> {
        let c = self.corner;
        Some(
            Aabb::new(c, c)
                .include(c + self.edge1)
                .include(c + self.edge2)
                .include(c + self.edge1 + self.edge2),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;

    #[test]
    fn hits_inside_and_misses_outside() {
        // Unit square in the plane x = 0 spanning y in [0, 2], z in [0, 1]; normal = Y x Z = +x.
        let r = Rectangle::new(DVec3::ZERO, DVec3::new(0., 2., 0.), DVec3::Z);
        assert_hit(r.intersect(&ray([3., 1., 0.5], [-1., 0., 0.]), 0.0, 1e9), 3.0, DVec3::X);
        assert!(r.intersect(&ray([3., 2.5, 0.5], [-1., 0., 0.]), 0.0, 1e9).is_none());
        assert!(r.intersect(&ray([3., 1., 1.5], [-1., 0., 0.]), 0.0, 1e9).is_none());
        // Edge-on ray: parallel to the plane, no hit.
        assert!(r.intersect(&ray([0., -1., 0.5], [0., 1., 0.]), 0.0, 1e9).is_none());
    }
}
