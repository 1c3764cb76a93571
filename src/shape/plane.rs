//! The infinite plane through a point with a given normal.

use super::{Aabb, SurfaceHit};
use super::{gamma, l1};
use crate::math::Ray;
use glam::DVec3;

/// Where the ray meets the plane through `p0` with unit normal `N`, when
/// `t_min < t < t_max`: `t = (p0 - o).N / (v.N)`; rays parallel to the plane never hit.
/// The plane's, the disk's and the rectangle's first step.
#[inline]
pub(crate) fn plane_t(p0: DVec3, normal: DVec3, ray: &Ray, t_min: f64, t_max: f64) -> Option<f64> {
    let denom = ray.dir.dot(normal);
    if denom == 0.0 {
        return None;
    }
    let t = (p0 - ray.origin).dot(normal) / denom;
    (t > t_min && t < t_max).then_some(t)
}

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

    /// The hit where `plane_t` puts it.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        plane_t(self.point, self.normal, ray, t_min, t_max).map(|t| SurfaceHit { t, normal: self.normal })
    }

    /// Whether no segment from `origin` to a point of the ball (`center`, `radius`) can hit
    /// the plane as [`Plane::intersect`] computes it: `origin` is strictly on one side (the
    /// computed numerator `(p0 - o).N` is not zero) and the ball on the same side with a
    /// margin. A direction away from the plane then gives `t < 0` exactly (numerator and
    /// denominator of opposite signs); a direction towards it gives a `t` beyond the ball,
    /// so beyond the segment's end, by far more than the rounding of `t` and of the
    /// segment's length.
    pub fn misses_segments_to(&self, origin: DVec3, center: DVec3, radius: f64) -> bool {
        let numerator = (self.point - origin).dot(self.normal);
        let ball = (center - self.point).dot(self.normal);
        let margin = 1e-9 * (radius + (center - origin).length() + ball.abs());
        if numerator < 0.0 {
            ball - radius > margin
        } else if numerator > 0.0 {
            ball + radius < -margin
        } else {
            false
        }
    }

    /// Bound on the distance from `p` to the plane: `|(p - p0).N|` plus its evaluation error.
    #[inline]
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
    fn segments_to_a_ball_on_the_same_side_miss() {
        let floor = Plane::new(DVec3::ZERO, DVec3::Z);
        let light = (DVec3::new(0.0, 0.0, 10.0), 2.0);
        // From just above the floor: every segment to the ball stays above it.
        assert!(floor.misses_segments_to(DVec3::new(3.0, 1.0, 1e-12), light.0, light.1));
        // From below, or from exactly on the plane: not decided here.
        assert!(!floor.misses_segments_to(DVec3::new(3.0, 1.0, -1e-12), light.0, light.1));
        assert!(!floor.misses_segments_to(DVec3::new(3.0, 1.0, 0.0), light.0, light.1));
        // A ball reaching the plane: not decided either.
        assert!(!floor.misses_segments_to(DVec3::new(3.0, 1.0, 1.0), DVec3::new(0.0, 0.0, 2.0), 2.0));
        // Both below: the same on the other side.
        assert!(floor.misses_segments_to(DVec3::new(3.0, 1.0, -1.0), -light.0, light.1));
        // And the test agrees with `intersect` on rays to points of the ball.
        let o = DVec3::new(3.0, 1.0, 1e-12);
        for k in 0..100 {
            let a = k as f64 * 0.7;
            let q =
                light.0 + light.1 * DVec3::new(a.cos() * (a * 0.3).sin(), a.sin() * (a * 0.3).sin(), (a * 0.3).cos());
            let r = Ray::new(o, (q - o).normalize());
            assert!(floor.intersect(&r, 0.0, (q - o).length()).is_none());
        }
    }

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
