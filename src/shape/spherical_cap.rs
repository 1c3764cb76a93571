//! SIMRenderer's spherical cap (`spherical_cap`, `calotte_spherique`): the part of a sphere
//! cut off by a disk. The disk is given as a disk is (center `P`, unit normal `n`, radius
//! `R`) with a signed radius of curvature `C`, `|C| >= R`, under the sign convention of
//! spherical refracting surfaces: `C > 0` bulges along `n` (convex), `C < 0` against it
//! (concave). The sphere's center is `P - a sqrt(C^2 - R^2)` with `a = sign(C) n` the
//! direction of the bulge, so the cap is always the smaller piece (at most a hemisphere):
//! the sphere's points `p` with `(p - P).a >= 0`. Its normal is `(p - center) / |C|`,
//! away from the sphere's center, as SIMRenderer's cap computes it.
//!
//! The cap is an open surface: SIMRenderer's cap is a disk geometry that does not say it is
//! closed, so its rim stays open (no flat face), rays pass between the rim and the disk's
//! plane, and under SIMRenderer's conventions a transparent cap does not refract.

use super::sphere::sphere_roots;
use super::{Aabb, SurfaceHit, gamma, l1};
use crate::math::Ray;
use glam::DVec3;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SphericalCap {
    /// The disk's center `P`.
    pub center: DVec3,
    /// The disk's unit normal `n`.
    pub normal: DVec3,
    /// The disk's (the rim's) radius `R`.
    pub radius: f64,
    /// The signed radius of curvature `C`, `|C| >= R`.
    pub curvature: f64,
    /// The sphere's center `P - a sqrt(C^2 - R^2)`.
    #[serde(skip)]
    sphere_center: DVec3,
    /// The direction of the bulge `a = sign(C) n`.
    #[serde(skip)]
    bulge: DVec3,
}

impl SphericalCap {
    /// The cap over the disk (`center`, `normal`, `radius`) with signed radius of curvature
    /// `curvature`; the caller checks `|curvature| >= radius` ([`SphericalCap::check`]).
    pub fn new(center: DVec3, normal: DVec3, radius: f64, curvature: f64) -> Self {
        let normal = normal.normalize();
        let bulge = if curvature > 0.0 { normal } else { -normal };
        SphericalCap {
            center,
            normal,
            radius,
            curvature,
            sphere_center: center - bulge * sphere_offset(radius, curvature),
            bulge,
        }
    }

    /// Why a cap of this rim radius and curvature cannot be built, if it cannot: SIMRenderer
    /// refuses `|C| < R` (no sphere of that radius passes through the rim).
    pub fn check(radius: f64, curvature: f64) -> Option<String> {
        (curvature.is_nan() || curvature.abs() < radius).then(|| {
            format!(
                "the radius of curvature must be at least the rim's radius {radius} in absolute value, got {curvature}"
            )
        })
    }

    /// The sphere the cap is cut from (center, radius `|C|`).
    pub fn sphere(&self) -> (DVec3, f64) {
        (self.sphere_center, self.curvature.abs())
    }

    /// The cap's height `h = |C| - sqrt(C^2 - R^2)`: from the disk's plane to its apex
    /// ([`cap_height`]).
    pub fn height(&self) -> f64 {
        cap_height(self.radius, self.curvature)
    }

    /// Whether the point `p` of the sphere is on the cap's side of the disk's plane.
    fn holds(&self, p: DVec3) -> bool {
        (p - self.center).dot(self.bulge) >= 0.0
    }

    /// The sphere's roots in order; the first whose point is on the cap.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let (c, r) = self.sphere();
        let (t0, t1) = sphere_roots(c, r, ray)?;
        [t0, t1]
            .into_iter()
            .find(|&t| t > t_min && t < t_max && self.holds(ray.at(t)))
            .map(|t| SurfaceHit {
                t,
                normal: ((ray.at(t) - c) / r).normalize(),
            })
    }

    /// Bound on the distance from `p` (a hit) to the cap: the sphere's residual plus its
    /// evaluation error.
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        let (c, r) = self.sphere();
        ((p - c).length() - r).abs() + gamma(16) * (l1(p) + l1(c) + r)
    }

    /// The cap lies in the cylinder of radius `R` over the disk, up to the apex's height
    /// (the rim and the apex alone do not bound it: a tilted hemisphere bulges past both).
    pub fn bounds(&self) -> Option<Aabb> {
        let disk = |at: DVec3| super::cylinder::disk_bounds(at, self.normal, self.radius);
        Some(disk(self.center)?.union(disk(self.center + self.bulge * self.height())?))
    }

    /// The ball of the rim: every point of the cap is within `R` of `P`
    /// (`|p - P|^2 = R^2 - 2 z sqrt(C^2 - R^2)` at height `z >= 0` above the plane).
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        (self.center, self.radius)
    }
}

/// The height `h = |C| - sqrt(C^2 - R^2)` of a cap of rim radius `R` cut from a sphere of
/// signed curvature radius `C` (`|C| >= R`): from the rim's plane to the apex.
pub fn cap_height(radius: f64, curvature: f64) -> f64 {
    curvature.abs() - sphere_offset(radius, curvature)
}

/// `sqrt(C^2 - R^2)`: the distance from the disk's plane to the sphere's center (0 when
/// rounding makes `|C|` a hair below `R`).
pub(crate) fn sphere_offset(radius: f64, curvature: f64) -> f64 {
    ((curvature - radius) * (curvature + radius)).max(0.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::super::Shape;
    use super::super::test_util::*;
    use super::*;

    /// Rim radius 3, curvature 5: the sphere's center is 4 below the disk, the cap 1 high.
    fn convex() -> SphericalCap {
        SphericalCap::new(DVec3::new(0.0, 0.0, 1.0), DVec3::Z, 3.0, 5.0)
    }

    #[test]
    fn geometry_by_hand() {
        let cap = convex();
        assert_eq!(cap.sphere(), (DVec3::new(0.0, 0.0, -3.0), 5.0));
        assert_eq!(cap.height(), 1.0);
        // Concave: the sphere's center 4 above the disk, the cap 1 deep below it.
        let concave = SphericalCap::new(DVec3::new(0.0, 0.0, 1.0), DVec3::Z, 3.0, -5.0);
        assert_eq!(concave.sphere(), (DVec3::new(0.0, 0.0, 5.0), 5.0));
        let b = concave.bounds().unwrap();
        assert_eq!((b.min, b.max), (DVec3::new(-3.0, -3.0, 0.0), DVec3::new(3.0, 3.0, 1.0)));
        assert!(SphericalCap::check(3.0, -2.5).is_some());
        assert_eq!(SphericalCap::check(3.0, 3.0), None);
    }

    #[test]
    fn hits_the_cap_and_not_the_rest_of_the_sphere() {
        let cap = convex();
        // Down the axis: the apex (0, 0, 2) at t = 8, normal +z.
        assert_hit(
            cap.intersect(&ray([0., 0., 10.], [0., 0., -1.]), 0.0, 1e9),
            8.0,
            DVec3::Z,
        );
        // From below the disk's plane, up the axis: the sphere's lower part is not the cap,
        // and the disk is open: the first hit is the apex from inside, at t = 12.
        assert_hit(
            cap.intersect(&ray([0., 0., -10.], [0., 0., 1.]), 0.0, 1e9),
            12.0,
            DVec3::Z,
        );
        // At x = 4 the sphere's surface is at z = -3 + 3 = 0, below the plane z = 1: a miss.
        assert!(cap.intersect(&ray([4., 0., 10.], [0., 0., -1.]), 0.0, 1e9).is_none());
        // Through the rim's plane between the rim and the apex, sideways at z = 1.5: the
        // sphere's points at x = +-sqrt(25 - 4.5^2) = +-sqrt(4.75), both on the cap.
        let x = 4.75f64.sqrt();
        let h = cap.intersect(&ray([-10., 0., 1.5], [1., 0., 0.]), 0.0, 1e9).unwrap();
        assert!((h.t - (10.0 - x)).abs() < 1e-12);
        assert!((h.normal - DVec3::new(-x, 0.0, 4.5) / 5.0).length() < 1e-12);
    }

    #[test]
    fn occludes_agrees_with_intersect() {
        let s = Shape::SphericalCap(Box::new(SphericalCap::new(
            DVec3::new(1., -2., 0.5),
            DVec3::new(0.3, -0.5, 1.0),
            1.0,
            -1.6,
        )));
        let (hits, misses) = check_occludes_agrees(&s, &random_rays(8, DVec3::new(1., -2., 0.5), 1.0, 400));
        assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
    }
}
