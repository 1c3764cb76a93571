//! Texture coordinates `(u, v)` of a point on each shape, for texture materials
//! ([`crate::texture`]). SIMRenderer defines them only for the sphere, and leaves even
//! that to the students' lab (`SGeometricUVMapping.sphereUVMapping`); lumiere fixes one
//! mapping per shape, each in the shape's own frame (`Frame::from_z` of its normal or axis)
//! so that it moves with the shape, and with `v = 0` at the top of the image under the
//! default `origin_uv_top_left`:
//!
//! - sphere: longitude and colatitude about `+z` (the spherical wrap of Direct3D's texture
//!   wrapping, DirectX 5 SDK: `u` from the angle of `(x, y, 0)` with `+x`, `v` from the
//!   angle of `(x, y, z)` with `+z`): `u = atan2(y, x) / 2 pi` in `[0, 1)`,
//!   `v = acos(z / r) / pi`, the north pole (`+z`) at `v = 0`;
//! - plane: the point's local `(x, -y)` from the plane's point, one scene unit per image;
//! - disk, spherical cap, lens: the point projected along the normal (the lens's axis) onto
//!   the disk of radius `R`, `u = (1 + x / R) / 2`, `v = (1 - y / R) / 2`;
//! - rectangle: the fractions along `edge1` and `edge2`;
//! - box: on each face, the face's two other local coordinates over `[0, 1]` (`v` down the
//!   `z` axis on the side faces, down `y` on the top and bottom);
//! - cylinder, tube, cone: `u` the angle about the axis as the sphere's, `v = 1 - z / h`
//!   (the far end at the top of the image; a cap takes its rim's values);
//! - torus: `u` the angle about the axis, `v` the angle about the tube, both over `[0, 1)`;
//! - triangle (meshes included): the barycentric coordinates of `p1` and `p2`;
//! - a transformed shape: its inner shape's, at the point carried back to its frame.

use super::Shape;
use crate::math::Frame;
use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// `atan2(y, x) / 2 pi` in `[0, 1)`.
fn turn(y: f64, x: f64) -> f64 {
    let a = libm::atan2(y, x) / TAU;
    if a < 0.0 { a + 1.0 } else { a }
}

/// The disk projection of `d` (local to a frame whose `z` is the normal) over radius `r`.
fn disk(d: DVec3, r: f64) -> (f64, f64) {
    (0.5 * (1.0 + d.x / r), 0.5 * (1.0 - d.y / r))
}

impl Shape {
    /// The texture coordinates of `p`, a point of the shape (module doc).
    pub fn uv(&self, p: DVec3) -> (f64, f64) {
        match self {
            Shape::Sphere(s) => {
                let d = (p - s.center) / s.radius;
                (turn(d.y, d.x), libm::acos(d.z.clamp(-1.0, 1.0)) / PI)
            }
            Shape::Plane(pl) => {
                let d = Frame::from_z(pl.normal).to_local(p - pl.point);
                (d.x, -d.y)
            }
            Shape::Disk(d) => disk(Frame::from_z(d.normal).to_local(p - d.center), d.radius),
            Shape::SphericalCap(c) => disk(Frame::from_z(c.normal).to_local(p - c.center), c.radius),
            Shape::Lens(l) => disk(Frame::from_z(l.axis).to_local(p - l.base), l.radius),
            Shape::Rectangle(r) => {
                let d = p - r.corner;
                (
                    d.dot(r.edge1) / r.edge1.length_squared(),
                    d.dot(r.edge2) / r.edge2.length_squared(),
                )
            }
            Shape::Cuboid(b) => {
                let l = b.frame().to_local(p - b.center) / b.half_size;
                let a = l.abs();
                let (x, y) = if a.x >= a.y && a.x >= a.z {
                    (l.y, -l.z)
                } else if a.y >= a.z {
                    (l.x, -l.z)
                } else {
                    (l.x, -l.y)
                };
                (0.5 * (1.0 + x), 0.5 * (1.0 + y))
            }
            Shape::Cylinder(c) => {
                let l = Frame::from_z(c.axis).to_local(p - c.base);
                (turn(l.y, l.x), 1.0 - l.z / c.height)
            }
            Shape::Cone(c) => {
                let l = Frame::from_z(c.axis).to_local(p - c.base);
                (turn(l.y, l.x), 1.0 - l.z / c.height)
            }
            Shape::Torus(t) => {
                let l = Frame::from_z(t.axis).to_local(p - t.center);
                let rho = libm::hypot(l.x, l.y);
                (turn(l.y, l.x), turn(l.z, rho - t.major))
            }
            Shape::Triangle(t) => t.barycentric(p),
            Shape::SmoothTriangle(t) => t.uv(p),
            Shape::Transformed(t) => {
                let local = t.transform.to_local * (p - t.transform.to_world.translation);
                t.shape.uv(local)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::*;
    use super::*;

    fn close(a: (f64, f64), b: (f64, f64)) -> bool {
        (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12
    }

    /// Hand-computed points of every shape, in frames where `Frame::from_z` is the identity
    /// (normal or axis +z).
    #[test]
    fn uv_by_hand() {
        let s = Shape::Sphere(Sphere::new(DVec3::new(1.0, 2.0, 3.0), 2.0));
        // North pole: v = 0; on the equator at +x: u = 0, v = 1/2; at +y: u = 1/4; at -y: 3/4.
        assert!(close(s.uv(DVec3::new(1.0, 2.0, 5.0)), (0.0, 0.0)));
        assert!(close(s.uv(DVec3::new(3.0, 2.0, 3.0)), (0.0, 0.5)));
        assert!(close(s.uv(DVec3::new(1.0, 4.0, 3.0)), (0.25, 0.5)));
        assert!(close(s.uv(DVec3::new(1.0, 0.0, 3.0)), (0.75, 0.5)));
        // 45 degrees below the equator towards -x: u = 1/2, v = 3/4.
        let q = DVec3::new(1.0 - 2f64.sqrt(), 2.0, 3.0 - 2f64.sqrt());
        assert!(close(s.uv(q), (0.5, 0.75)));
        let pl = Shape::Plane(Box::new(Plane::new(DVec3::new(0.0, 0.0, 1.0), DVec3::Z)));
        assert!(close(pl.uv(DVec3::new(2.5, 1.25, 1.0)), (2.5, -1.25)));
        let d = Shape::Disk(Box::new(Disk::new(DVec3::ZERO, DVec3::Z, 2.0)));
        assert!(close(d.uv(DVec3::new(1.0, 1.0, 0.0)), (0.75, 0.25)));
        let cap = Shape::SphericalCap(Box::new(SphericalCap::new(DVec3::ZERO, DVec3::Z, 2.0, 3.0)));
        assert!(close(cap.uv(DVec3::new(-2.0, 0.0, 0.0)), (0.0, 0.5)));
        let lens = Shape::Lens(Box::new(Lens::new(DVec3::ZERO, DVec3::Z, 1.0, 2.0, 3.0, 3.0)));
        assert!(close(lens.uv(DVec3::new(0.0, -2.0, 0.5)), (0.5, 1.0)));
        let r = Shape::Rectangle(Box::new(Rectangle::new(
            DVec3::ZERO,
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(0.0, 0.0, 2.0),
        )));
        assert!(close(r.uv(DVec3::new(1.0, 0.0, 1.5)), (0.25, 0.75)));
        let b = Shape::Cuboid(Box::new(Cuboid::new(
            DVec3::ZERO,
            DVec3::new(2.0, 4.0, 6.0),
            DVec3::ZERO,
        )));
        // Face +x at (1, 1, 1.5): (y, -z) / half = (0.5, -0.5) -> (0.75, 0.25).
        assert!(close(b.uv(DVec3::new(1.0, 1.0, 1.5)), (0.75, 0.25)));
        // Top face z = 3 at (0.5, -1, 3): (x, -y) / half = (0.5, 0.5) -> (0.75, 0.75).
        assert!(close(b.uv(DVec3::new(0.5, -1.0, 3.0)), (0.75, 0.75)));
        let c = Shape::Cylinder(Box::new(Cylinder::new(DVec3::ZERO, DVec3::Z, 4.0, 1.0)));
        assert!(close(c.uv(DVec3::new(0.0, 1.0, 1.0)), (0.25, 0.75)));
        let cone = Shape::Cone(Box::new(Cone::new(DVec3::ZERO, DVec3::Z, 2.0, 1.0)));
        assert!(close(cone.uv(DVec3::new(-0.5, 0.0, 1.0)), (0.5, 0.5)));
        let t = Shape::Torus(Box::new(Torus::new(DVec3::ZERO, DVec3::Z, 2.0, 0.5)));
        // Outer equator at +x: (0, 0); top of the tube at +y: (1/4, 1/4); inner equator at -x: (1/2, 1/2).
        assert!(close(t.uv(DVec3::new(2.5, 0.0, 0.0)), (0.0, 0.0)));
        assert!(close(t.uv(DVec3::new(0.0, 2.0, 0.5)), (0.25, 0.25)));
        assert!(close(t.uv(DVec3::new(-1.5, 0.0, 0.0)), (0.5, 0.5)));
        let tri = Shape::Triangle(Triangle::new(
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 4.0, 0.0),
        ));
        assert!(close(tri.uv(DVec3::new(0.5, 1.0, 0.0)), (0.25, 0.25)));
        // A sphere moved by 10 along x: the same coordinates as the unmoved one.
        let moved = Transform::from_parts(DVec3::ONE, DVec3::ZERO, DVec3::new(10.0, 0.0, 0.0))
            .apply(Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0)));
        assert!(close(moved.uv(DVec3::new(10.0, 1.0, 0.0)), (0.25, 0.5)));
    }
}
