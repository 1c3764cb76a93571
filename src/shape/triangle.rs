//! The triangle `p0 p1 p2`: an open flat surface whose outward normal follows the
//! right-hand rule, `(p1 - p0) x (p2 - p0)` (counter-clockwise seen from outside), as
//! SIMRenderer's `triangle` has it.
//!
//! **Storage.** The vertices live in an array shared by every triangle of a mesh (a
//! reference-counted slice) and each triangle holds its three indices: 32 bytes inline in
//! the [`super::Shape`] enum and no allocation of its own. A closed mesh has about half as
//! many vertices as triangles, 12 bytes of vertices a triangle; a soup of separate
//! triangles 72. A lone triangle owns a slice of its three vertices.
//!
//! **Intersection.** The watertight test of Woop, Benthin and Wald ("Watertight
//! Ray/Triangle Intersection", JCGT 2(1), 2013), in the form pbrt-v4's `Triangle::Intersect`
//! gives it: the vertices are moved to the ray's frame (origin subtracted, axes permuted
//! cyclically so the ray's largest direction component is z, then sheared so the ray runs
//! along +z), where the ray meets the triangle iff the 2D edge functions
//! `e_i = x_j y_k - y_j x_k` share a sign. Each transformed vertex depends only on the
//! vertex and the ray, so an edge shared by two triangles gets the same edge function in
//! both, negated: a ray through a shared edge or vertex cannot slip between the two. An
//! edge function that rounds to zero is recomputed with its exact sign (Kahan's
//! difference of products through a fused multiply-add). The parameter is
//! `t = sum_i e_i z_i / sum_i e_i` and is kept only above its own rounding error bound
//! (pbrt-v4's conservative test), so a ray leaving the surface does not find it again.

use super::{Aabb, SurfaceHit, gamma, l1};
use crate::math::Ray;
use glam::{DVec3, Vec3Swizzles};
use std::sync::Arc;

/// A triangle of shared vertices (see the module doc).
#[derive(Clone)]
pub struct Triangle {
    vertices: Arc<[DVec3]>,
    index: [u32; 3],
}

impl Triangle {
    /// A lone triangle. The points must not be on one line (checked when scenes are
    /// validated: see [`Triangle::degenerate`]).
    pub fn new(p0: DVec3, p1: DVec3, p2: DVec3) -> Self {
        Triangle {
            vertices: Arc::from([p0, p1, p2]),
            index: [0, 1, 2],
        }
    }

    /// Triangle `index` of the shared `vertices`; `None` when an index is out of range.
    pub fn in_mesh(vertices: &Arc<[DVec3]>, index: [u32; 3]) -> Option<Self> {
        index.iter().all(|&i| (i as usize) < vertices.len()).then(|| Triangle {
            vertices: Arc::clone(vertices),
            index,
        })
    }

    /// The three vertices, in winding order.
    #[inline(always)]
    pub fn points(&self) -> [DVec3; 3] {
        self.index.map(|i| self.vertices[i as usize])
    }

    /// The shared vertex array and this triangle's indices into it.
    pub fn shared(&self) -> (&Arc<[DVec3]>, [u32; 3]) {
        (&self.vertices, self.index)
    }

    /// Why the points make no triangle, if they do not: two of them equal, or all three
    /// (nearly) on one line (the sine of the angle at `p0` at most 1e-12, the rectangle's
    /// rule for parallel edges).
    pub fn degenerate(p0: DVec3, p1: DVec3, p2: DVec3) -> Option<&'static str> {
        let (e1, e2) = (p1 - p0, p2 - p0);
        if e1.length() == 0.0 || e2.length() == 0.0 || (p2 - p1).length() == 0.0 {
            return Some("two of its points are equal");
        }
        (e1.normalize().cross(e2.normalize()).length() <= 1e-12).then_some("its points are on one line")
    }

    /// Unit normal by the right-hand rule.
    pub fn normal(&self) -> DVec3 {
        let [p0, p1, p2] = self.points();
        (p1 - p0).cross(p2 - p0).normalize()
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let [p0, p1, p2] = self.points();
        let c = watertight(p0, p1, p2, ray, t_min)?;
        (c.t < t_max).then(|| SurfaceHit {
            t: c.t,
            normal: (p1 - p0).cross(p2 - p0).normalize(),
        })
    }

    /// The hit's parameter and barycentric coordinates `(b0, b1, b2)` (the weights of
    /// `p0`, `p1`, `p2` at the hit point, summing to 1), with `t_min < t < t_max`.
    #[inline]
    pub fn crossing(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<(f64, [f64; 3])> {
        let [p0, p1, p2] = self.points();
        let c = watertight(p0, p1, p2, ray, t_min)?;
        (c.t < t_max).then(|| (c.t, c.edges.map(|e| e / c.det)))
    }

    #[inline]
    pub fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        let [p0, p1, p2] = self.points();
        watertight(p0, p1, p2, ray, t_min).is_some_and(|c| c.t < t_max)
    }

    /// The barycentric coordinates `(b1, b2)` of `p` (a point of the triangle's plane): the
    /// solution of `p - p0 = b1 (p1 - p0) + b2 (p2 - p0)` by the normal equations
    /// (Cramer's rule). `b0 = 1 - b1 - b2`.
    pub fn barycentric(&self, p: DVec3) -> (f64, f64) {
        let [p0, p1, p2] = self.points();
        let (e1, e2, d) = (p1 - p0, p2 - p0, p - p0);
        let (a11, a12, a22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (r1, r2) = (d.dot(e1), d.dot(e2));
        let det = a11 * a22 - a12 * a12;
        ((r1 * a22 - r2 * a12) / det, (a11 * r2 - a12 * r1) / det)
    }

    /// Bound on the distance from `p` (a hit inside the triangle) to its plane: the
    /// residual `|(p - p0).n|` plus its evaluation error.
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        let [p0, p1, p2] = self.points();
        let n = (p1 - p0).cross(p2 - p0).normalize();
        let size = l1(p1 - p0) + l1(p2 - p0);
        (p - p0).dot(n).abs() + gamma(16) * (l1(p) + l1(p0) + size)
    }

    pub fn bounds(&self) -> Option<Aabb> {
        let [p0, p1, p2] = self.points();
        Some(Aabb::new(p0, p0).include(p1).include(p2))
    }

    /// A ball around the triangle: the centroid and the farthest vertex from it, widened
    /// by a relative 1e-12 for the rounding of both.
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        let [p0, p1, p2] = self.points();
        let c = (p0 + p1 + p2) / 3.0;
        let r = (p0 - c).length().max((p1 - c).length()).max((p2 - c).length());
        (c, r * (1.0 + 1e-12))
    }
}

/// A ray's crossing of the triangle's plane inside the triangle: the parameter `t` and
/// the edge functions `e_i` (`e_0` of the edge `p1 p2`, opposite `p0`, and so on), whose
/// sum is `det`: `e_i / det` is the barycentric weight of `p_i`.
struct Crossing {
    t: f64,
    edges: [f64; 3],
    det: f64,
}

/// The watertight test of the module doc: the crossing with `t > t_min`, if any.
#[inline(always)]
fn watertight(p0: DVec3, p1: DVec3, p2: DVec3, ray: &Ray, t_min: f64) -> Option<Crossing> {
    let d = ray.dir;
    let a = d.abs();
    // The axis of the largest |d| becomes z; the other two follow it cyclically, which
    // keeps the frame right-handed and so the edge functions' signs.
    let kz = if a.x > a.y {
        if a.x > a.z { 0 } else { 2 }
    } else if a.y > a.z {
        1
    } else {
        2
    };
    let permute = |v: DVec3| match kz {
        0 => v.yzx(),
        1 => v.zxy(),
        _ => v,
    };
    let dp = permute(d);
    let (sx, sy, sz) = (-dp.x / dp.z, -dp.y / dp.z, 1.0 / dp.z);
    let o = ray.origin;
    // The same operations for each vertex whatever the triangle: shared vertices are
    // transformed to the same bits.
    let to_ray = |p: DVec3| {
        let q = permute(p - o);
        DVec3::new(q.x + sx * q.z, q.y + sy * q.z, q.z)
    };
    let (q0, q1, q2) = (to_ray(p0), to_ray(p1), to_ray(p2));
    let mut e0 = q1.x * q2.y - q1.y * q2.x;
    let mut e1 = q2.x * q0.y - q2.y * q0.x;
    let mut e2 = q0.x * q1.y - q0.y * q1.x;
    if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
        e0 = difference_of_products(q1.x, q2.y, q1.y, q2.x);
        e1 = difference_of_products(q2.x, q0.y, q2.y, q0.x);
        e2 = difference_of_products(q0.x, q1.y, q0.y, q1.x);
    }
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return None;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return None;
    }
    let (z0, z1, z2) = (sz * q0.z, sz * q1.z, sz * q2.z);
    let t = (e0 * z0 + e1 * z1 + e2 * z2) / det;
    if t <= t_min || t.is_nan() {
        return None;
    }
    // pbrt-v4's bound on the error of `t` (section 6.8.4 of "Physically Based Rendering",
    // 4th edition): a `t` within it of 0 may be a root behind the origin.
    let max_z = z0.abs().max(z1.abs()).max(z2.abs());
    let max_x = q0.x.abs().max(q1.x.abs()).max(q2.x.abs());
    let max_y = q0.y.abs().max(q1.y.abs()).max(q2.y.abs());
    let delta_z = gamma(3) * max_z;
    let delta_x = gamma(5) * (max_x + max_z);
    let delta_y = gamma(5) * (max_y + max_z);
    let delta_e = 2.0 * (gamma(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let max_e = e0.abs().max(e1.abs()).max(e2.abs());
    let delta_t = 3.0 * (gamma(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) / det.abs();
    (t > delta_t).then_some(Crossing {
        t,
        edges: [e0, e1, e2],
        det,
    })
}

/// `a b - c d` to within 1.5 ulp, its sign exact (Kahan's algorithm: the rounding error of
/// `c d` recovered by a fused multiply-add; Jeannerod, Louvet and Muller 2013). Rust's
/// `mul_add` is the correctly rounded fused operation on every platform.
fn difference_of_products(a: f64, b: f64, c: f64, d: f64) -> f64 {
    let cd = c * d;
    let err = (-c).mul_add(d, cd);
    a.mul_add(b, -cd) + err
}

impl PartialEq for Triangle {
    /// Same points in the same order, wherever they are stored.
    fn eq(&self, other: &Self) -> bool {
        self.points() == other.points()
    }
}

impl std::fmt::Debug for Triangle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [p0, p1, p2] = self.points();
        f.debug_struct("Triangle")
            .field("p0", &p0)
            .field("p1", &p1)
            .field("p2", &p2)
            .finish()
    }
}

impl serde::Serialize for Triangle {
    /// As its three points `p0`, `p1`, `p2` (a mesh's shared array is not repeated).
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let [p0, p1, p2] = self.points();
        let mut st = s.serialize_struct("Triangle", 3)?;
        st.serialize_field("p0", &p0)?;
        st.serialize_field("p1", &p1)?;
        st.serialize_field("p2", &p2)?;
        st.end()
    }
}

#[cfg(test)]
mod tests {
    use super::super::Shape;
    use super::super::test_util::*;
    use super::*;
    use crate::sampling::unit_interval;
    use rand_chacha::ChaCha8Rng;
    use rand_core::{Rng, SeedableRng};

    /// The right triangle (0,0,0) (2,0,0) (0,2,0) lifted to z = 1: normal +z.
    fn reference() -> Triangle {
        Triangle::new(DVec3::new(0., 0., 1.), DVec3::new(2., 0., 1.), DVec3::new(0., 2., 1.))
    }

    #[test]
    fn hits_a_known_point_from_either_side() {
        let tri = reference();
        // Down through (0.5, 0.5, 1) from z = 4: t = 3, normal +z (the right-hand rule of
        // (2,0,0) x (0,2,0) = (0,0,4)).
        assert_hit(
            tri.intersect(&ray([0.5, 0.5, 4.], [0., 0., -1.]), 0.0, 1e9),
            3.0,
            DVec3::Z,
        );
        // Up from below: the same normal, whichever side the ray comes from.
        assert_hit(
            tri.intersect(&ray([0.5, 0.5, -2.], [0., 0., 1.]), 0.0, 1e9),
            3.0,
            DVec3::Z,
        );
        // Slanted: from (4, 4, 5) towards (0.5, 1, 1), a point inside (x + y = 1.5 < 2).
        // The direction (-3.5, -3, -4) has length sqrt(12.25 + 9 + 16) = sqrt(37.25).
        let from = DVec3::new(4., 4., 5.);
        let to = DVec3::new(0.5, 1., 1.);
        let r = Ray::new(from, (to - from).normalize());
        assert_hit(tri.intersect(&r, 0.0, 1e9), 37.25f64.sqrt(), DVec3::Z);
        // Outside the hypotenuse x + y = 2: (1.2, 1, 1) misses, and so do the other sides.
        assert!(tri.intersect(&ray([1.2, 1., 4.], [0., 0., -1.]), 0.0, 1e9).is_none());
        assert!(tri.intersect(&ray([-0.1, 1., 4.], [0., 0., -1.]), 0.0, 1e9).is_none());
        assert!(tri.intersect(&ray([1., -0.1, 4.], [0., 0., -1.]), 0.0, 1e9).is_none());
        // In the triangle's plane: no hit (det = 0).
        assert!(tri.intersect(&ray([-1., 0.5, 1.], [1., 0., 0.]), 0.0, 1e9).is_none());
        // Behind the origin and beyond t_max: no hit.
        assert!(tri.intersect(&ray([0.5, 0.5, 4.], [0., 0., 1.]), 0.0, 1e9).is_none());
        assert!(tri.intersect(&ray([0.5, 0.5, 4.], [0., 0., -1.]), 0.0, 3.0).is_none());
        // The opposite winding flips the normal.
        let flipped = Triangle::new(DVec3::new(0., 0., 1.), DVec3::new(0., 2., 1.), DVec3::new(2., 0., 1.));
        assert_hit(
            flipped.intersect(&ray([0.5, 0.5, 4.], [0., 0., -1.]), 0.0, 1e9),
            3.0,
            -DVec3::Z,
        );
    }

    #[test]
    fn edges_and_vertices_belong_to_the_triangle() {
        // Every number exact: the edge x = 0, the hypotenuse's midpoint (1, 1), a vertex.
        let tri = reference();
        for (x, y) in [(0.0, 0.5), (1.0, 1.0), (0.5, 0.0), (2.0, 0.0), (0.0, 0.0)] {
            assert_hit(tri.intersect(&ray([x, y, 3.], [0., 0., -1.]), 0.0, 1e9), 2.0, DVec3::Z);
        }
        // One ulp outside the edge x = 0.
        let out = -(0.0f64.next_up());
        assert!(tri.intersect(&ray([out, 0.5, 3.], [0., 0., -1.]), 0.0, 1e9).is_none());
    }

    /// The square (0,0) (1,0) (1,1) (0,1) in the plane z = 0 as four triangles around its
    /// center (0.5, 0.5), each pair of neighbours sharing an edge from the center to a
    /// corner, all four sharing the center: rays aimed at random points of the shared edges
    /// (some nudged a few ulps off them) and at the center, from random points above and
    /// below at any slant, never miss all four.
    #[test]
    fn shared_edges_and_vertices_let_no_ray_through() {
        let v: Arc<[DVec3]> = Arc::from([
            DVec3::new(0.5, 0.5, 0.),
            DVec3::new(0., 0., 0.),
            DVec3::new(1., 0., 0.),
            DVec3::new(1., 1., 0.),
            DVec3::new(0., 1., 0.),
        ]);
        let fan: Vec<Triangle> = (0..4u32)
            .map(|k| Triangle::in_mesh(&v, [0, 1 + k, 1 + (k + 1) % 4]).unwrap())
            .collect();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut u = move || unit_interval(rng.next_u64());
        let mut hits_by_count = [0; 5];
        for k in 0..200_000 {
            // The center, or a point of one of the four shared edges (center to a corner,
            // short of both ends), sometimes nudged a few ulps.
            let corner = v[1 + k % 4];
            let s = if k % 40 == 0 { 0.0 } else { 0.001 + 0.998 * u() };
            let mut p = v[0] + (corner - v[0]) * s;
            if k % 3 == 0 {
                p.x = f64::from_bits(p.x.to_bits() + (k % 7) as u64);
                p.y = f64::from_bits(p.y.to_bits() - (k % 5) as u64);
            }
            let side = if k % 2 == 0 { 1.0 } else { -1.0 };
            let from = DVec3::new(4.0 * u() - 1.5, 4.0 * u() - 1.5, side * (0.01 + 3.0 * u()));
            let r = Ray::new(from, (p - from).normalize());
            let hits: Vec<SurfaceHit> = fan.iter().filter_map(|t| t.intersect(&r, 0.0, f64::INFINITY)).collect();
            assert!(!hits.is_empty(), "ray {k} slipped through at {p}: {r:?}");
            // Triangles that all claim the ray agree on where it crosses the plane.
            assert!(hits.iter().all(|h| (h.t - hits[0].t).abs() <= 1e-14 * h.t), "{hits:?}");
            hits_by_count[hits.len()] += 1;
        }
        // A ray whose edge function on the shared edge is exactly zero (the edge passes
        // through the origin of the ray's frame, in the frame's own rounded coordinates) is
        // claimed by both neighbours, at the same point; any other by one. Measured: 167 115
        // by one, 31 168 by two, 1 717 (through the center) by all four.
        assert_eq!(hits_by_count[0], 0);
        assert!(
            hits_by_count[1] > 100_000 && hits_by_count[2] > 1000,
            "{hits_by_count:?}"
        );
    }

    #[test]
    fn a_zero_edge_function_gets_its_exact_sign() {
        // 1e-160 squared underflows to 0: the plain products give e = 0, the recomputed ones
        // the true sign. Kahan's difference of products on numbers whose products are exact.
        assert_eq!(difference_of_products(3.0, 5.0, 2.0, 7.0), 1.0);
        assert_eq!(difference_of_products(0.1, 0.3, 0.3, 0.1), 0.0);
        let tiny = 1e-170;
        assert_eq!(tiny * tiny, 0.0);
        assert!(difference_of_products(tiny, tiny, 0.0, 1.0) >= 0.0);
        // (1 + 2^-30)^2 - (1 + 2^-29) = 2^-60 exactly, lost by the plain formula.
        let a = 1.0 + 2f64.powi(-30);
        assert_eq!(a * a - (1.0 + 2f64.powi(-29)), 0.0);
        assert_eq!(difference_of_products(a, a, 1.0 + 2f64.powi(-29), 1.0), 2f64.powi(-60));
    }

    #[test]
    fn occludes_agrees_with_intersect() {
        let tri = Shape::Triangle(Triangle::new(
            DVec3::new(1., -5., 3.),
            DVec3::new(2., -4.5, 3.5),
            DVec3::new(0.5, -4., 2.),
        ));
        let (hits, misses) = check_occludes_agrees(&tri, &random_rays(22, DVec3::new(1., -4.5, 3.), 1.0, 400));
        assert!(hits > 50 && misses > 100, "{hits} hits, {misses} misses");
    }

    #[test]
    fn degenerate_points_are_named() {
        let (a, b) = (DVec3::ZERO, DVec3::X);
        assert_eq!(Triangle::degenerate(a, b, 2.0 * b), Some("its points are on one line"));
        assert_eq!(Triangle::degenerate(a, a, b), Some("two of its points are equal"));
        assert_eq!(Triangle::degenerate(a, b, DVec3::Y), None);
        assert_eq!(Triangle::in_mesh(&Arc::from([a, b, DVec3::Y]), [0, 1, 3]), None);
    }

    #[test]
    fn far_origin_keeps_precision() {
        // From 1e7 away along the normal: t = 1e7 - 1 exactly.
        let h = reference()
            .intersect(&ray([0.5, 0.5, 1e7], [0., 0., -1.]), 0.0, 1e99)
            .unwrap();
        assert_eq!(h.t, 1e7 - 1.0);
    }
}
