//! Instance transforms: any shape seen through an affine map `world = A local + b`
//! (SIMRenderer's `geometry` wrapper: non-uniform scale, then rotations about x, y and z,
//! then a translation; or a general 3x4 matrix).
//!
//! A ray is carried into the shape's own frame by the inverse map, `o' = A^-1 (o - b)`,
//! `d' = A^-1 d`. The shapes solve for unit directions (their quadratics and ball tests
//! assume `|d| = 1`), so `d'` is divided by its length `L`: the local parameter is
//! `t' = L t`, and the world `t = t' / L`. The normal goes back by the inverse transpose,
//! `n = A^-T n'`, normalised, which keeps it outward even when `A` mirrors. The bounds are
//! the box of the 8 transformed corners of the local box (exact for a sphere, whose
//! ellipsoid's box is known); the error bound is the local one, plus the rounding of `o'`,
//! stretched by at most the largest stretch of `A`.

use super::{Aabb, Shape, SurfaceHit, gamma, l1};
use crate::limits;
use crate::math::Ray;
use glam::{DAffine3, DMat3, DVec3};

/// An affine map `world = A local + b` and bounds on how much it stretches lengths.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Transform {
    /// `A` (as `matrix3`) and `b` (as `translation`).
    #[serde(serialize_with = "rows")]
    pub to_world: DAffine3,
    /// `A^-1`.
    #[serde(skip)]
    pub to_local: DMat3,
    /// At least the largest singular value of `A`: `|A v| <= stretch |v|`.
    #[serde(skip)]
    pub stretch: f64,
    /// At most the smallest singular value of `A`: `|A v| >= shrink |v|`.
    #[serde(skip)]
    pub shrink: f64,
}

/// The 3x4 matrix `[A | b]` as three rows, as scene files write it.
fn rows<S: serde::Serializer>(a: &DAffine3, s: S) -> Result<S::Ok, S::Error> {
    use serde::Serialize;
    let m = a.matrix3.transpose();
    let t = a.translation;
    [
        [m.x_axis.x, m.x_axis.y, m.x_axis.z, t.x],
        [m.y_axis.x, m.y_axis.y, m.y_axis.z, t.y],
        [m.z_axis.x, m.z_axis.y, m.z_axis.z, t.z],
    ]
    .serialize(s)
}

impl Transform {
    /// Scale by `scale` (per axis, nonzero), then rotate by `rotation_deg` about x, then y,
    /// then z (degrees, as the box's `rotation`), then translate: `A = Rz Ry Rx S`.
    pub fn from_parts(scale: DVec3, rotation_deg: DVec3, translation: DVec3) -> Self {
        let r = rotation_deg * (std::f64::consts::PI / 180.0);
        let rotation = DMat3::from_rotation_z(r.z) * DMat3::from_rotation_y(r.y) * DMat3::from_rotation_x(r.x);
        let linear = rotation * DMat3::from_diagonal(scale);
        // The inverse as `S^-1 R^T`: a transpose and a division, not a general inversion.
        let to_local = DMat3::from_diagonal(scale.recip()) * rotation.transpose();
        // The singular values are |s_i|; the rounded rotation is orthogonal to ~1e-16.
        let s = scale.abs();
        Transform {
            to_world: DAffine3::from_mat3_translation(linear, translation),
            to_local,
            stretch: s.max_element() * (1.0 + 1e-12),
            shrink: s.min_element() * (1.0 - 1e-12),
        }
    }

    /// The map of a 3x4 matrix given by rows `[a b c d]`: `world = A local + (d)`. `None`
    /// when `A` has no finite inverse.
    pub fn from_rows(rows: [[f64; 4]; 3]) -> Option<Self> {
        let [r0, r1, r2] = rows;
        let linear =
            DMat3::from_cols_array(&[r0[0], r0[1], r0[2], r1[0], r1[1], r1[2], r2[0], r2[1], r2[2]]).transpose();
        let to_local = linear.try_inverse()?;
        // Frobenius norms bound the singular values: sigma_max(A) <= |A|_F and
        // sigma_min(A) = 1 / sigma_max(A^-1) >= 1 / |A^-1|_F.
        let frobenius =
            |m: DMat3| (m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared()).sqrt();
        Some(Transform {
            to_world: DAffine3::from_mat3_translation(linear, DVec3::new(r0[3], r1[3], r2[3])),
            to_local,
            stretch: frobenius(linear) * (1.0 + 1e-12),
            shrink: 1.0 / frobenius(to_local) * (1.0 - 1e-12),
        })
    }

    /// `p -> scale p + offset` applied after this map (a similarity of the whole scene).
    pub fn then_similarity(&self, scale: f64, offset: DVec3) -> Self {
        Transform {
            to_world: DAffine3::from_mat3_translation(
                self.to_world.matrix3 * scale,
                self.to_world.translation * scale + offset,
            ),
            to_local: self.to_local * (1.0 / scale),
            stretch: self.stretch * scale,
            shrink: self.shrink * scale,
        }
    }

    /// Whether the map is the identity, to the bit.
    pub fn is_identity(&self) -> bool {
        self.to_world == DAffine3::IDENTITY
    }

    /// Whether the map mirrors (`det A < 0`): a triangle's winding then flips.
    pub fn mirrors(&self) -> bool {
        self.to_world.matrix3.determinant() < 0.0
    }

    pub fn point(&self, p: DVec3) -> DVec3 {
        self.to_world.transform_point3(p)
    }

    /// A normal seen through the map, `A^-T n`, of the same length as `n` when the map
    /// is a rotation (and not unit in general).
    pub fn normal(&self, n: DVec3) -> DVec3 {
        self.to_local.transpose() * n
    }

    /// The vertices `[p0, p1, p2]` moved, in the order that keeps the winding outward
    /// (`p1` and `p2` swapped when the map mirrors), with the order's permutation.
    fn triangle_points(&self, points: [DVec3; 3]) -> ([DVec3; 3], [usize; 3]) {
        let order = if self.mirrors() { [0, 2, 1] } else { [0, 1, 2] };
        (order.map(|i| self.point(points[i])), order)
    }

    /// The shape seen through the map: a triangle's vertices are moved (its winding kept
    /// outward: swapped when the map mirrors), and a smooth triangle's vertex normals with
    /// them; any other shape is wrapped.
    pub fn apply(&self, shape: Shape) -> Shape {
        match shape {
            Shape::Triangle(t) => {
                let ([p0, p1, p2], _) = self.triangle_points(t.points());
                Shape::Triangle(super::Triangle::new(p0, p1, p2))
            }
            Shape::SmoothTriangle(s) => {
                let ([p0, p1, p2], order) = self.triangle_points(s.triangle.points());
                let normals = order.map(|i| self.normal(s.normals[i]));
                let uvs = order.map(|i| s.uvs[i]);
                let flat = super::Triangle::new(p0, p1, p2);
                // An invertible map keeps a normal's direction non-zero.
                match super::SmoothTriangle::new(flat, normals, uvs, s.interpolation) {
                    Some(moved) => Shape::SmoothTriangle(Box::new(moved)),
                    None => Shape::Transformed(Box::new(Transformed::new(Shape::SmoothTriangle(s), *self))),
                }
            }
            other => Shape::Transformed(Box::new(Transformed::new(other, *self))),
        }
    }

    /// [`Transform::apply`], refused (in words that follow "the transform") when the moved
    /// shape leaves the coordinates' range ([`limits::within_coordinates`]: its bounds, an
    /// unbounded plane's point, a triangle's vertices) or, for a triangle, when rounding
    /// made it degenerate.
    pub fn apply_within_limits(&self, shape: Shape) -> Result<Shape, String> {
        let moved = self.apply(shape);
        let inside = match &moved {
            Shape::Transformed(s) => match s.bounds() {
                Some(b) => limits::within_coordinates(b.min) && limits::within_coordinates(b.max),
                None => limits::within_coordinates(self.point(match &s.shape {
                    Shape::Plane(p) => p.point,
                    _ => DVec3::ZERO,
                })),
            },
            Shape::Triangle(t) => t.points().iter().all(|p| limits::within_coordinates(*p)),
            Shape::SmoothTriangle(t) => t.triangle.points().iter().all(|p| limits::within_coordinates(*p)),
            _ => true,
        };
        if !inside {
            let m = limits::MAX_COORDINATE;
            return Err(format!("moves the shape beyond the coordinates' range [-{m:e}, {m:e}]"));
        }
        let flat = match &moved {
            Shape::Triangle(t) => Some(t),
            Shape::SmoothTriangle(t) => Some(&t.triangle),
            _ => None,
        };
        if let Some(t) = flat
            && let [a, b, c] = t.points()
            && let Some(why) = super::Triangle::degenerate(a, b, c)
        {
            return Err(format!("makes the triangle degenerate: {why}"));
        }
        Ok(moved)
    }
}

/// A shape and the map from its frame to the world (see the module doc).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Transformed {
    pub shape: Shape,
    pub transform: Transform,
    /// `A^-T`: normals back to the world.
    #[serde(skip)]
    normal_matrix: DMat3,
    #[serde(skip)]
    bounds: Option<Aabb>,
    #[serde(skip)]
    ball: Option<(DVec3, f64)>,
}

impl Transformed {
    pub fn new(shape: Shape, transform: Transform) -> Self {
        let bounds = world_bounds(&shape, &transform);
        let ball = shape.bounding_sphere().map(|(c, r)| {
            // The image of the local ball, or the box's ball when that is smaller.
            let mapped = (transform.point(c), r * transform.stretch);
            match bounds {
                Some(b) if 0.5 * (b.max - b.min).length() < mapped.1 => (b.centroid(), 0.5 * (b.max - b.min).length()),
                _ => mapped,
            }
        });
        Transformed {
            normal_matrix: transform.to_local.transpose(),
            shape,
            transform,
            bounds,
            ball,
        }
    }

    /// Local ray origin, unit local direction and the length `L = |A^-1 d|`.
    #[inline(always)]
    fn local_ray(&self, ray: &Ray) -> (Ray, f64) {
        let m = &self.transform.to_local;
        let o = *m * (ray.origin - self.transform.to_world.translation);
        let d = *m * ray.dir;
        let len = d.length();
        (Ray::new(o, d / len), len)
    }

    /// The first hit with `t_min < t` (no upper limit: `t_max` only filters, see
    /// [`Shape::intersect`]).
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        if let Some(ball) = self.ball
            && super::misses_bounding_sphere(ray, t_min, t_max, ball)
        {
            return None;
        }
        let (local, len) = self.local_ray(ray);
        // Start the local search a few ulps before `t_min L` and skip the local hits whose
        // world `t` is not above `t_min`: no hit is lost to the rounding of `t_min L`.
        let mut from = if t_min == 0.0 {
            0.0
        } else {
            t_min * len * (1.0 - 4.0 * f64::EPSILON)
        };
        // At most four surfaces of one shape (the torus) lie along a line.
        for _ in 0..8 {
            let hit = self.shape.intersect(&local, from, f64::INFINITY)?;
            let t = hit.t / len;
            if t > t_min {
                return (t < t_max).then(|| SurfaceHit {
                    t,
                    normal: (self.normal_matrix * hit.normal).normalize(),
                });
            }
            from = hit.t;
        }
        None
    }

    /// Bound on the distance from `p` to the transformed surface: the local bound at
    /// `A^-1 (p - b)`, plus the rounding of that point (`gamma(8)` of `|A^-1| (|p| + |b|)`),
    /// times the largest stretch of `A`.
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        let m = &self.transform.to_local;
        let b = self.transform.to_world.translation;
        let local = *m * (p - b);
        let rounding = gamma(8) * l1(m.abs() * (p.abs() + b.abs()));
        self.transform.stretch * (self.shape.surface_error(local) + rounding)
    }

    pub fn bounds(&self) -> Option<Aabb> {
        self.bounds
    }

    pub fn bounding_sphere(&self) -> Option<(DVec3, f64)> {
        self.ball
    }

    /// The image of the shape's inner ball holds the ball of `r shrink` around the image of
    /// its center (narrowed by a relative 1e-9 for rounding).
    pub fn inner_ball(&self) -> Option<(DVec3, f64)> {
        let (c, r) = self.shape.inner_ball()?;
        Some((self.transform.point(c), r * self.transform.shrink * (1.0 - 1e-9)))
    }
}

/// Box of the transformed shape: for a sphere `(c, r)` the ellipsoid's own box, center
/// `A c + b` and half-sides `r |row_i(A)|`; for other shapes the box of the 8 transformed
/// corners of the local box.
fn world_bounds(shape: &Shape, transform: &Transform) -> Option<Aabb> {
    if let Shape::Sphere(s) = shape {
        let rows = transform.to_world.matrix3.transpose();
        let half = DVec3::new(rows.x_axis.length(), rows.y_axis.length(), rows.z_axis.length()) * s.radius;
        let c = transform.point(s.center);
        return Some(Aabb::new(c - half, c + half));
    }
    let b = shape.bounds()?;
    let mut out = Aabb::EMPTY;
    for k in 0..8 {
        let corner = DVec3::new(
            if k & 1 == 0 { b.min.x } else { b.max.x },
            if k & 2 == 0 { b.min.y } else { b.max.y },
            if k & 4 == 0 { b.min.z } else { b.max.z },
        );
        out = out.include(transform.point(corner));
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::super::{Cuboid, Cylinder, Sphere, Torus};
    use super::*;

    fn ellipsoid() -> Shape {
        // The unit sphere scaled by (2, 1, 0.5), then moved to (1, 2, 3).
        Transform::from_parts(DVec3::new(2., 1., 0.5), DVec3::ZERO, DVec3::new(1., 2., 3.))
            .apply(Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0)))
    }

    #[test]
    fn a_move_beyond_the_coordinates_range_is_refused() {
        let out = "moves the shape beyond the coordinates' range [-1e9, 1e9]";
        let far = Transform::from_parts(DVec3::ONE, DVec3::ZERO, DVec3::new(0.0, 0.0, 9.99e8));
        // A unit sphere whose centre moves to z = 9.99e8 reaches z = 9.99e8 + 1: inside.
        let inside = far.apply_within_limits(Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0)));
        assert!(matches!(inside, Ok(Shape::Transformed(_))));
        // Of radius 2e6 it reaches 1.001e9: outside.
        let beyond = far.apply_within_limits(Shape::Sphere(Sphere::new(DVec3::ZERO, 2e6)));
        assert_eq!(beyond.unwrap_err(), out);
        // An unbounded plane by its point: z = 9.99e8 + 2e6 is outside.
        let plane = Shape::Plane(Box::new(super::super::Plane::new(DVec3::new(0.0, 0.0, 2e6), DVec3::Z)));
        assert_eq!(far.apply_within_limits(plane).unwrap_err(), out);
        // A triangle by its vertices, moved rather than wrapped.
        let tri = |z| {
            Shape::Triangle(super::super::Triangle::new(
                DVec3::ZERO,
                DVec3::X,
                DVec3::new(0.0, 1.0, z),
            ))
        };
        assert!(matches!(far.apply_within_limits(tri(0.0)), Ok(Shape::Triangle(_))));
        assert_eq!(far.apply_within_limits(tri(2e6)).unwrap_err(), out);
    }

    #[test]
    fn a_scaled_sphere_is_hit_where_the_ellipsoid_is() {
        let e = ellipsoid();
        // Along -x from x = 10 through the center's line: the vertex (3, 2, 3), t = 7,
        // normal +x.
        assert_hit(e.intersect(&ray([10., 2., 3.], [-1., 0., 0.]), 0.0, 1e9), 7.0, DVec3::X);
        // Down -z through the center: the top (1, 2, 3.5), t = 6.5.
        assert_hit(e.intersect(&ray([1., 2., 10.], [0., 0., -1.]), 0.0, 1e9), 6.5, DVec3::Z);
        // Off the axes: x/a = 1/2 in the plane z = 3 (y = 2 + sqrt(3)/2 on the ellipse
        // ((x-1)/2)^2 + (y-2)^2 = 1 at x = 2). The gradient there, (2 (x-1)/4, 2 (y-2), 0) =
        // (1/2, sqrt(3), 0), normalised, is the analytic normal.
        let y = 2.0 + 3f64.sqrt() / 2.0;
        let n = DVec3::new(0.5, 3f64.sqrt(), 0.0).normalize();
        assert_hit(e.intersect(&ray([2., 10., 3.], [0., -1., 0.]), 0.0, 1e9), 10.0 - y, n);
        // A slanted ray from the center: leaves at the point where |A^-1 (p - c)| = 1. Along
        // the unit direction (2, 1, 0.5) / |(2, 1, 0.5)|, local direction (1, 1, 1) / ... has
        // the exit at local distance 1: world t = |(2, 1, 0.5)| / sqrt(3) = sqrt(5.25 / 3).
        let d = DVec3::new(2., 1., 0.5);
        let exit = e
            .intersect(&Ray::new(DVec3::new(1., 2., 3.), d.normalize()), 0.0, 1e9)
            .unwrap();
        assert!((exit.t - (5.25f64 / 3.0).sqrt()).abs() < 1e-14, "{}", exit.t);
        // Normal at local (1, 1, 1)/sqrt(3): A^-T n' = (1/2, 1, 2) normalised.
        assert!((exit.normal - DVec3::new(0.5, 1., 2.).normalize()).length() < 1e-14);
        // Just past the tip along x: a miss.
        assert!(e.intersect(&ray([10., 2., 3.5001], [-1., 0., 0.]), 0.0, 1e9).is_none());
        // Its box is the ellipsoid's.
        let b = e.bounds().unwrap();
        assert_eq!((b.min, b.max), (DVec3::new(-1., 1., 2.5), DVec3::new(3., 3., 3.5)));
    }

    #[test]
    fn rotation_is_about_x_then_y_then_z() {
        // A box of size (4, 2, 2) turned 90 degrees about z: its long side along y.
        let t = Transform::from_parts(DVec3::ONE, DVec3::new(0., 0., 90.), DVec3::ZERO);
        let b = t.apply(Shape::Cuboid(Box::new(Cuboid::new(
            DVec3::ZERO,
            DVec3::new(4., 2., 2.),
            DVec3::ZERO,
        ))));
        assert_hit(b.intersect(&ray([0., 10., 0.], [0., -1., 0.]), 0.0, 1e9), 8.0, DVec3::Y);
        assert_hit(b.intersect(&ray([10., 0., 0.], [-1., 0., 0.]), 0.0, 1e9), 9.0, DVec3::X);
        // x then z: the x turn leaves +x alone, the z turn takes it to +y; the other order
        // (z then x) would take +x to +y and then to +z.
        let t = Transform::from_parts(DVec3::ONE, DVec3::new(90., 0., 90.), DVec3::ZERO);
        assert!((t.point(DVec3::X) - DVec3::Y).length() < 1e-15);
        // Scale before rotation: (2, 1, 1) scaling then 90 about z sends x to 2 y.
        let t = Transform::from_parts(DVec3::new(2., 1., 1.), DVec3::new(0., 0., 90.), DVec3::new(0., 0., 5.));
        assert!((t.point(DVec3::X) - DVec3::new(0., 2., 5.)).length() < 1e-15);
    }

    #[test]
    fn a_mirror_keeps_normals_outward() {
        // Scale -1 in x: the sphere is the same set, and its normals still point out.
        let t = Transform::from_parts(DVec3::new(-1., 1., 1.), DVec3::ZERO, DVec3::ZERO);
        assert!(t.mirrors());
        let s = t.apply(Shape::Sphere(Sphere::new(DVec3::new(1., 0., 0.), 1.0)));
        assert_hit(s.intersect(&ray([-5., 0., 0.], [1., 0., 0.]), 0.0, 1e9), 3.0, -DVec3::X);
        // A triangle's vertices are moved and its winding swapped: the normal stays the
        // image of the outward one (+z stays +z under x -> -x).
        let tri = Shape::Triangle(super::super::Triangle::new(DVec3::ZERO, DVec3::X, DVec3::Y));
        let moved = t.apply(tri);
        assert_hit(
            moved.intersect(&ray([-0.2, 0.2, 1.], [0., 0., -1.]), 0.0, 1e9),
            1.0,
            DVec3::Z,
        );
    }

    #[test]
    fn a_matrix_shears() {
        // x' = x + z: the cube [-0.5, 0.5]^3 leans towards +x. A vertical line at x' = 1.5
        // would need local x = 1.5 - z <= 0.5, so z >= 1, above the cube: a miss.
        let t = Transform::from_rows([[1., 0., 1., 0.], [0., 1., 0., 0.], [0., 0., 1., 0.]]).unwrap();
        let cube = t.apply(Shape::Cuboid(Box::new(Cuboid::new(
            DVec3::ZERO,
            DVec3::ONE,
            DVec3::ZERO,
        ))));
        assert!(cube.intersect(&ray([1.5, 0., 10.], [0., 0., -1.]), 0.0, 1e9).is_none());
        // At x' = 0.8 it meets the top face z = 0.5 at the local point (0.3, 0, 0.5): t = 9.5.
        // The normal is A^-T (0, 0, 1) with A^-T = [[1, 0, 0], [0, 1, 0], [-1, 0, 1]]
        // (rows): (0, 0, 1), the top's plane being unchanged by the shear.
        let h = cube.intersect(&ray([0.8, 0., 10.], [0., 0., -1.]), 0.0, 1e9).unwrap();
        assert!(
            (h.t - 9.5).abs() < 1e-14 && (h.normal - DVec3::Z).length() < 1e-15,
            "{h:?}"
        );
        // From +x at z = 0: the slanted side x' = 0.5 + z at t = 4.5, its normal
        // A^-T (1, 0, 0) = (1, 0, -1), normalised.
        let n = DVec3::new(1., 0., -1.).normalize();
        assert_hit(cube.intersect(&ray([5., 0., 0.], [-1., 0., 0.]), 0.0, 1e9), 4.5, n);
        // A singular matrix has no inverse.
        assert!(Transform::from_rows([[1., 0., 0., 0.], [0., 1., 0., 0.], [1., 1., 0., 0.]]).is_none());
    }

    #[test]
    fn t_min_is_honoured_through_the_scale() {
        // The ellipsoid from outside along -x: entry t = 7, exit t = 11 (x = -1); from
        // t_min = 7 the exit.
        let e = ellipsoid();
        let r = ray([10., 2., 3.], [-1., 0., 0.]);
        assert_hit(e.intersect(&r, 7.0, 1e9), 11.0, -DVec3::X);
        assert!(e.intersect(&r, 11.0, 1e9).is_none());
    }

    #[test]
    fn occludes_agrees_with_intersect() {
        let tilt = Transform::from_parts(
            DVec3::new(1.5, 0.7, 1.2),
            DVec3::new(20., -35., 70.),
            DVec3::new(1., -5., 3.),
        );
        for shape in [
            Shape::Sphere(Sphere::new(DVec3::ZERO, 0.75)),
            Shape::Torus(Box::new(Torus::new(DVec3::ZERO, DVec3::Z, 1.0, 0.3))),
            Shape::Cylinder(Box::new(Cylinder::tube(DVec3::ZERO, DVec3::Z, 1.0, 0.5))),
        ] {
            let s = tilt.apply(shape);
            let (hits, misses) = check_occludes_agrees(&s, &random_rays(23, DVec3::new(1., -5., 3.), 1.5, 400));
            assert!(hits > 50 && misses > 50, "{}: {hits} hits, {misses} misses", s.kind());
        }
    }

    #[test]
    fn balls_bound_and_fit() {
        let e = ellipsoid();
        let (c, r) = e.bounding_sphere().unwrap();
        assert_eq!(c, DVec3::new(1., 2., 3.));
        assert!((r - 2.0).abs() < 1e-9, "{r}");
        let (c, r) = e.inner_ball().unwrap();
        assert_eq!(c, DVec3::new(1., 2., 3.));
        assert!((r - 0.5).abs() < 1e-8 && r < 0.5, "{r}");
        // The surface error grows with the stretch: a point 1e-6 outside the tip along x
        // (local 5e-7) is reported at least 1e-6 away.
        assert!(e.surface_error(DVec3::new(3.0 + 1e-6, 2., 3.)) >= 1e-6);
        // On the surface, only rounding: gamma(16) (|p'| + |c| + r) locally, plus gamma(8) of
        // |A^-1| (|p| + |b|) = (2, 4, 12), stretched by 2: about 4e-14.
        assert!(e.surface_error(DVec3::new(3.0, 2., 3.)) < 1e-13);
    }
}
