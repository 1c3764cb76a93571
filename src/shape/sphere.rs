//! The sphere `|p - c| = r`.

use super::{Aabb, SurfaceHit, first_root_in};
use super::{gamma, l1};
use crate::math::Ray;
use crate::solve::quadratic;
use glam::DVec3;

/// Roots of `|o + t v - c|^2 = r^2` for unit `v`: `t^2 + 2 b t + c = 0` with
/// `b = (o - c).v`. The discriminant is computed as `r^2 - |f - b v|^2` with `f = o - c`
/// (Haines et al., Ray Tracing Gems ch. 7), which keeps precision for far-away origins.
/// Shared by the sphere and the shapes cut from spheres (spherical cap, lens).
#[inline(always)]
pub(crate) fn sphere_roots(center: DVec3, radius: f64, ray: &Ray) -> Option<(f64, f64)> {
    let (disc, f, b) = sphere_discriminant(center, radius, ray);
    if disc < 0.0 {
        return None;
    }
    let c = f.length_squared() - radius * radius;
    // Equivalent to the stable quadratic with a = 1, using the accurate discriminant.
    let q = -b - b.signum() * disc.sqrt();
    if q == 0.0 {
        return quadratic(1.0, 2.0 * b, c);
    }
    let (t0, t1) = (q, c / q);
    Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
}

/// [`sphere_roots`]' discriminant `r^2 - |f - b v|^2`, with `f = o - c` and `b = f.v`;
/// negative where the ray's line misses the sphere.
#[inline(always)]
pub(crate) fn sphere_discriminant(center: DVec3, radius: f64, ray: &Ray) -> (f64, DVec3, f64) {
    let f = ray.origin - center;
    let b = f.dot(ray.dir);
    let perp = f - b * ray.dir;
    (radius * radius - perp.length_squared(), f, b)
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Sphere {
    pub center: DVec3,
    pub radius: f64,
}

impl Sphere {
    pub fn new(center: DVec3, radius: f64) -> Self {
        Sphere { center, radius }
    }

    /// The two roots of the sphere's equation ([`sphere_roots`]).
    #[inline(always)]
    fn roots(&self, ray: &Ray) -> Option<(f64, f64)> {
        sphere_roots(self.center, self.radius, ray)
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let t = first_root_in(self.roots(ray)?, t_min, t_max)?;
        let normal = (ray.at(t) - self.center) / self.radius;
        Some(SurfaceHit {
            t,
            normal: normal.normalize(),
        })
    }

    #[inline(always)]
    pub fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.roots(ray).and_then(|r| first_root_in(r, t_min, t_max)).is_some()
    }

    /// Bound on the distance from `p` (a computed hit point) to the sphere: the residual
    /// `| |p - c| - r |` plus its own evaluation error (see [`super::surface_error`]).
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        let residual = ((p - self.center).length() - self.radius).abs();
        residual + gamma(16) * (l1(p) + l1(self.center) + self.radius)
    }

    pub fn bounds(&self) -> Option<Aabb> {
        Some(Aabb::around(self.center, self.radius))
    }
}

#[cfg(test)]
mod tests {
    use super::super::Shape;
    use super::super::test_util::*;
    use super::*;

    #[test]
    fn outside_inside_and_tangent() {
        let s = Sphere::new(DVec3::new(0., 0., 3.), 1.0);
        // From z = 10 down the axis: hit the top at t = 6, normal +z.
        assert_hit(s.intersect(&ray([0., 0., 10.], [0., 0., -1.]), 0.0, 1e9), 6.0, DVec3::Z);
        // From the center: the exit hit at t = 1.
        assert_hit(s.intersect(&ray([0., 0., 3.], [1., 0., 0.]), 0.0, 1e9), 1.0, DVec3::X);
        // Tangent at x = 1: double root t = 5, normal +x.
        assert_hit(s.intersect(&ray([1., -5., 3.], [0., 1., 0.]), 0.0, 1e9), 5.0, DVec3::X);
        // Just outside the tangent: a miss.
        assert!(s.intersect(&ray([1.000001, -5., 3.], [0., 1., 0.]), 0.0, 1e9).is_none());
    }

    #[test]
    fn occludes_agrees_with_intersect() {
        let s = Shape::Sphere(Sphere::new(DVec3::new(1., -5., 3.), 0.75));
        let (hits, misses) = check_occludes_agrees(&s, &random_rays(21, DVec3::new(1., -5., 3.), 0.75, 400));
        // Both answers are exercised, and second hits (the exit after the entry) too.
        assert!(hits > 300 && misses > 100, "{hits} hits, {misses} misses");
    }

    #[test]
    fn far_origin_keeps_precision() {
        // Origin 1e7 away: the hit is at t = 1e7 - 1 exactly.
        let s = Sphere::new(DVec3::ZERO, 1.0);
        let h = s.intersect(&ray([0., 0., 1e7], [0., 0., -1.]), 0.0, 1e99).unwrap();
        assert_eq!(h.t, 1e7 - 1.0);
    }
}
