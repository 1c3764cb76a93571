//! SIMRenderer's lens (`lens`, `lentille`): a cylinder of radius `R` from `P1` to `P2`
//! (its edge, absent when `P1 = P2`) closed at each end by a spherical cap over the end's
//! disk ([`super::SphericalCap`]): at `P1` with the disk's normal pointing away from `P2`
//! and curvature `C1`, at `P2` with the normal pointing away from `P1` and curvature `C2`.
//! A positive curvature bulges out of the cylinder (convex), a negative one is hollowed
//! into it (concave); the hollows must leave the edge a length `e >= 0` (SIMRenderer's
//! check). The lens is a closed solid; its normals point out of it: away from a convex
//! cap's sphere center, towards a concave cap's.
//!
//! In the local frame (axis `+z`, `P1` at the origin, `P2` at `z = e`) the surface is the
//! side `x^2 + y^2 = R^2` for `0 <= z <= e`, the sphere of cap 1 where `z <= 0` (convex)
//! or `z >= 0` (concave), and the sphere of cap 2 where `z >= e` (convex) or `z <= e`
//! (concave). Each piece is solved exactly (the spheres by the stable quadratic of
//! [`super::sphere::sphere_roots`], the side as the open tube) and the nearest hit kept.

use super::sphere::sphere_roots;
use super::spherical_cap::{cap_height, sphere_offset};
use super::{Aabb, Cylinder, SurfaceHit, gamma, l1, nearer};
use crate::math::Ray;
use glam::DVec3;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Lens {
    /// `P1`, the center of the first cap's disk.
    pub base: DVec3,
    /// The unit axis from `P1` towards `P2`.
    pub axis: DVec3,
    /// The edge's length `e = |P2 - P1|` (0: no edge).
    pub thickness: f64,
    /// The radius `R` of the edge and of both caps' disks.
    pub radius: f64,
    /// The signed radius of curvature `C1` of the cap at `P1`.
    pub curvature1: f64,
    /// The signed radius of curvature `C2` of the cap at `P2`.
    pub curvature2: f64,
    /// The edge, an open tube (`None` when `e = 0`).
    #[serde(skip)]
    edge: Option<Cylinder>,
    /// The caps' spheres: center and signed curvature.
    #[serde(skip)]
    caps: [(DVec3, f64); 2],
}

impl Lens {
    /// The lens from `base` along the unit `axis`; the caller checks the values
    /// ([`Lens::check`]).
    pub fn new(base: DVec3, axis: DVec3, thickness: f64, radius: f64, curvature1: f64, curvature2: f64) -> Self {
        let axis = axis.normalize();
        let end = base + axis * thickness;
        // Cap 1's disk normal is -axis: convex (C1 > 0) puts its sphere's center towards +axis.
        let center1 = base + axis * sphere_offset(radius, curvature1) * curvature1.signum();
        let center2 = end - axis * sphere_offset(radius, curvature2) * curvature2.signum();
        Lens {
            base,
            axis,
            thickness,
            radius,
            curvature1,
            curvature2,
            edge: (thickness > 0.0).then(|| Cylinder::tube(base, axis, thickness, radius)),
            caps: [(center1, curvature1), (center2, curvature2)],
        }
    }

    /// Why a lens of these dimensions cannot be built, if it cannot: each cap's curvature at
    /// least `R` in absolute value (a sphere through the rim), and the concave caps' depths
    /// `|C| - sqrt(C^2 - R^2)` at most the edge's length (SIMRenderer's checks).
    pub fn check(thickness: f64, radius: f64, curvature1: f64, curvature2: f64) -> Option<(usize, String)> {
        for (i, c) in [curvature1, curvature2].into_iter().enumerate() {
            if c.is_nan() || c.abs() < radius {
                return Some((
                    i,
                    format!(
                        "the radius of curvature must be at least the lens's radius {radius} in absolute value, got {c}"
                    ),
                ));
            }
        }
        let hollow = |c: f64| Lens::hollow(radius, c);
        let left = thickness - hollow(curvature1) - hollow(curvature2);
        (left < 0.0).then(|| {
            (
                1,
                format!(
                    "the concave caps are {} deep in all, more than the edge's length {thickness}: the lens would be {left} thick at its center",
                    hollow(curvature1) + hollow(curvature2)
                ),
            )
        })
    }

    /// The caps' spheres: center and signed curvature, cap 1's then cap 2's.
    pub fn cap_spheres(&self) -> [(DVec3, f64); 2] {
        self.caps
    }

    /// How deep a cap of rim radius `radius` and curvature `c` hollows the lens: a concave
    /// cap's height `|C| - sqrt(C^2 - R^2)` ([`cap_height`]), 0 for a convex one.
    pub fn hollow(radius: f64, c: f64) -> f64 {
        if c < 0.0 { cap_height(radius, c) } else { 0.0 }
    }

    /// The extent along the axis from `P1`: from the apex of a convex cap 1 (below 0) to
    /// that of a convex cap 2 (beyond `e`).
    fn extent(&self) -> (f64, f64) {
        let bulge = |c: f64| if c > 0.0 { cap_height(self.radius, c) } else { 0.0 };
        (-bulge(self.curvature1), self.thickness + bulge(self.curvature2))
    }

    /// Whether `p`, a point of cap `i`'s sphere, is on that cap: on the cap's side of its
    /// disk's plane (up to a rounding band, which adds to the sphere only points within it
    /// of the rim).
    fn on_cap(&self, i: usize, p: DVec3) -> bool {
        let (z, c) = ((p - self.base).dot(self.axis), self.caps[i].1);
        let band = 1e-12 * (self.radius + self.thickness + c.abs());
        match (i, c > 0.0) {
            (0, true) => z <= band,
            (0, false) => z >= -band,
            (_, true) => z >= self.thickness - band,
            (_, false) => z <= self.thickness + band,
        }
    }

    /// The first hit on cap `i` in `(t_min, t_max)`, with the normal out of the lens.
    fn cap_hit(&self, i: usize, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let (center, c) = self.caps[i];
        let (t0, t1) = sphere_roots(center, c.abs(), ray)?;
        [t0, t1]
            .into_iter()
            .find(|&t| t > t_min && t < t_max && self.on_cap(i, ray.at(t)))
            .map(|t| SurfaceHit {
                t,
                // Away from a convex cap's center, towards a concave one's: `(p - center) / C`.
                normal: ((ray.at(t) - center) / c).normalize(),
            })
    }

    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        if super::misses_bounding_sphere(ray, t_min, t_max, self.bounding_sphere()) {
            return None;
        }
        let edge = self.edge.as_ref().and_then(|e| e.intersect(ray, t_min, t_max));
        nearer(
            nearer(edge, self.cap_hit(0, ray, t_min, t_max)),
            self.cap_hit(1, ray, t_min, t_max),
        )
    }

    /// Bound on the distance from `p` (a hit) to the lens: the smallest residual of the
    /// pieces' equations, plus its evaluation error.
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        let sphere = |(c, r): (DVec3, f64)| ((p - c).length() - r.abs()).abs();
        let mut residual = sphere(self.caps[0]).min(sphere(self.caps[1]));
        if self.edge.is_some() {
            let q = p - self.base;
            let radial = q - self.axis * q.dot(self.axis);
            residual = residual.min((radial.length() - self.radius).abs());
        }
        let size = self.radius + self.thickness + self.curvature1.abs() + self.curvature2.abs();
        residual + gamma(16) * (l1(p) + l1(self.base) + size)
    }

    /// The cylinder of radius `R` over the whole extent holds the lens.
    pub fn bounds(&self) -> Option<Aabb> {
        let (lo, hi) = self.extent();
        let disk = |z: f64| super::cylinder::disk_bounds(self.base + self.axis * z, self.axis, self.radius);
        Some(disk(lo)?.union(disk(hi)?))
    }

    /// The ball around that cylinder.
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        let (lo, hi) = self.extent();
        (
            self.base + self.axis * (0.5 * (lo + hi)),
            libm::hypot(self.radius, 0.5 * (hi - lo)),
        )
    }

    /// Both caps convex: the lens is a convex solid.
    pub fn is_convex(&self) -> bool {
        self.curvature1 > 0.0 && self.curvature2 > 0.0
    }

    /// The focal length of the lens in air by the lensmaker's formula for a thick lens,
    /// for the index `n`: `1/f = (n - 1) [1/R1 - 1/R2 + (n - 1) d / (n R1 R2)]`, with the
    /// optics sign convention along the axis from `P1` to `P2` (`R1 = C1`, `R2 = -C2`) and
    /// `d` the thickness on the axis (Hecht, "Optics", 6.2).
    pub fn focal_length(&self, n: f64) -> f64 {
        let (r1, r2) = (self.curvature1, -self.curvature2);
        let (lo, hi) = self.extent();
        // The hollows of concave caps take from the thickness on the axis.
        let hollow = |c: f64| Lens::hollow(self.radius, c);
        let d = hi - lo - hollow(self.curvature1) - hollow(self.curvature2);
        1.0 / ((n - 1.0) * (1.0 / r1 - 1.0 / r2 + (n - 1.0) * d / (n * r1 * r2)))
    }
}

#[cfg(test)]
mod tests {
    use super::super::Shape;
    use super::super::test_util::*;
    use super::*;

    /// Radius 3, edge 2 along z from the origin, caps of curvature 5 (each 1 high: the
    /// spheres' centers are 4 from the disks).
    fn biconvex() -> Lens {
        Lens::new(DVec3::ZERO, DVec3::Z, 2.0, 3.0, 5.0, 5.0)
    }

    #[test]
    fn geometry_by_hand() {
        let l = biconvex();
        assert_eq!(l.caps, [(DVec3::new(0., 0., 4.), 5.0), (DVec3::new(0., 0., -2.), 5.0)]);
        assert_eq!(l.extent(), (-1.0, 3.0));
        let b = l.bounds().unwrap();
        assert_eq!((b.min, b.max), (DVec3::new(-3., -3., -1.), DVec3::new(3., 3., 3.)));
        // Concave at P1, curvature -5: its hollow is 5 - sqrt(25 - 9) = 1 deep (a convex
        // cap hollows nothing); an edge of 0.5 is too short.
        assert_eq!((Lens::hollow(3.0, -5.0), Lens::hollow(3.0, 5.0)), (1.0, 0.0));
        assert!(Lens::check(0.5, 3.0, -5.0, 5.0).is_some());
        assert_eq!(Lens::check(1.0, 3.0, -5.0, 5.0), None);
        assert_eq!(Lens::check(0.0, 3.0, 5.0, 5.0), None);
        assert_eq!(Lens::check(1.0, 3.0, 2.0, 5.0).map(|e| e.0), Some(0));
    }

    #[test]
    fn hits_caps_and_edge_with_outward_normals() {
        let l = biconvex();
        // Down the axis: the apex of cap 2 at z = 3 (t = 7, normal +z), then from inside
        // the apex of cap 1 at z = -1 (t = 4 from z = 3).
        assert_hit(l.intersect(&ray([0., 0., 10.], [0., 0., -1.]), 0.0, 1e9), 7.0, DVec3::Z);
        assert_hit(l.intersect(&ray([0., 0., 3.], [0., 0., -1.]), 0.0, 1e9), 4.0, -DVec3::Z);
        // Sideways at z = 1: the edge at x = -3 (t = 7), normal -x.
        assert_hit(
            l.intersect(&ray([-10., 0., 1.], [1., 0., 0.]), 0.0, 1e9),
            7.0,
            -DVec3::X,
        );
        // Sideways at z = 2.5, above the edge: cap 2's sphere at x = -sqrt(25 - 4.5^2).
        let x = 4.75f64.sqrt();
        let h = l.intersect(&ray([-10., 0., 2.5], [1., 0., 0.]), 0.0, 1e9).unwrap();
        assert!((h.t - (10.0 - x)).abs() < 1e-12);
        assert!((h.normal - DVec3::new(-x, 0.0, 4.5) / 5.0).length() < 1e-12);
        // Concave cap 1 (curvature -5, 1 deep), edge 2: up the axis from below, the hollow's
        // bottom at z = 1, its normal towards the sphere's center (0, 0, -4): -z.
        let c = Lens::new(DVec3::ZERO, DVec3::Z, 2.0, 3.0, -5.0, 5.0);
        assert_hit(
            c.intersect(&ray([0., 0., -10.], [0., 0., 1.]), 0.0, 1e9),
            11.0,
            -DVec3::Z,
        );
    }

    #[test]
    fn without_an_edge() {
        // Edge 0: two caps of curvature 5 meet at the rim z = 0; sideways at z = 0.5 the
        // ray meets cap 2's sphere (center (0, 0, -4)) at x = -sqrt(25 - 4.5^2).
        let l = Lens::new(DVec3::ZERO, DVec3::Z, 0.0, 3.0, 5.0, 5.0);
        let x = 4.75f64.sqrt();
        let h = l.intersect(&ray([-10., 0., 0.5], [1., 0., 0.]), 0.0, 1e9).unwrap();
        assert!((h.t - (10.0 - x)).abs() < 1e-12);
        // Sideways at z = 0, exactly through the rim: hits at x = -3, no gap between caps.
        let h = l.intersect(&ray([-10., 0., 0.], [1., 0., 0.]), 0.0, 1e9).unwrap();
        assert!((h.t - 7.0).abs() < 1e-12, "{}", h.t);
    }

    #[test]
    fn lensmaker_by_hand() {
        // Thin symmetric biconvex, n = 1.5: 1/f = 0.5 (2/5 + 0.5 d / (1.5 * -25)), d = 4.
        let f = biconvex().focal_length(1.5);
        let expected = 1.0 / (0.5 * (0.4 - 0.5 * 4.0 / 37.5));
        assert!((f - expected).abs() < 1e-12, "{f} {expected}");
    }

    #[test]
    fn occludes_agrees_with_intersect() {
        for l in [
            biconvex(),
            Lens::new(DVec3::new(1., 0., 0.), DVec3::new(0.3, 1., 0.2), 1.5, 1.0, -1.2, 2.0),
        ] {
            let s = Shape::Lens(Box::new(l));
            let (hits, misses) = check_occludes_agrees(&s, &random_rays(9, DVec3::new(1., 0., 0.), 2.0, 400));
            assert!(hits > 100 && misses > 50, "{hits} hits, {misses} misses");
        }
    }
}
