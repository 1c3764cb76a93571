//! A box: center, full size along its three axes, optional rotation (the reference cube).

use super::{Aabb, SurfaceHit};
use super::{gamma, l1};
use crate::math::{Frame, Ray};
use glam::{DMat3, DVec3};

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Cuboid {
    pub center: DVec3,
    pub half_size: DVec3,
    /// Local axes: the box's edges are along the frame's x, y, z.
    #[serde(skip)]
    frame: Frame,
    /// World-space axes (columns), kept for the bounding box.
    #[serde(skip)]
    axes: DMat3,
    /// The bounding sphere ([`Cuboid::bounding_sphere`]), tested before the slabs.
    #[serde(skip)]
    ball: (DVec3, f64),
}

impl Cuboid {
    /// The box's local frame: its edges along the frame's axes.
    pub(crate) fn frame(&self) -> &Frame {
        &self.frame
    }

    /// `rotation_deg` rotates about x, then y, then z (degrees), around the center.
    pub fn new(center: DVec3, size: DVec3, rotation_deg: DVec3) -> Self {
        let r = rotation_deg * (std::f64::consts::PI / 180.0);
        let axes = DMat3::from_rotation_z(r.z) * DMat3::from_rotation_y(r.y) * DMat3::from_rotation_x(r.x);
        Cuboid {
            center,
            half_size: size * 0.5,
            frame: Frame::from_axes(axes.x_axis, axes.y_axis, axes.z_axis),
            axes,
            ball: (center, (size * 0.5).length()),
        }
    }

    /// The same box (axes and frame to the bit) with another center and half size: what a
    /// similarity transform makes of it.
    pub fn resized(&self, center: DVec3, half_size: DVec3) -> Cuboid {
        Cuboid {
            center,
            half_size,
            ball: (center, half_size.length()),
            ..self.clone()
        }
    }

    /// A ball around the whole box: its center and half-diagonal.
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        self.ball
    }

    /// Slab test in the box's frame; the face normal is the axis whose slab was entered
    /// (or, from inside, left) last.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        if super::misses_bounding_sphere(ray, t_min, t_max, self.bounding_sphere()) {
            return None;
        }
        let o = self.frame.to_local(ray.origin - self.center);
        let d = self.frame.to_local(ray.dir);
        let slabs = self.slabs(o, d);
        let (t, axis) = if slabs.near_hit(t_min, t_max) {
            (slabs.near, slabs.near_axis)
        } else if slabs.far_hit(t_min, t_max) {
            (slabs.far, slabs.far_axis)
        } else {
            return None;
        };
        let mut local_n = DVec3::ZERO;
        local_n[axis] = (o[axis] + t * d[axis]).signum();
        Some(SurfaceHit {
            t,
            normal: self.frame.to_world(local_n),
        })
    }

    /// The slab test of the ray `o + t d` in the box's frame, without a branch (see
    /// [`super::fan`]).
    #[inline(always)]
    fn slabs(&self, o: DVec3, d: DVec3) -> Slabs {
        let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
        let (mut near_axis, mut far_axis) = (0usize, 0usize);
        let mut shut = false;
        for axis in 0..3 {
            let (oi, di, hi) = (o[axis], d[axis], self.half_size[axis]);
            // Parallel to the slab: inside it everywhere or nowhere (the quotients below
            // are then unused).
            let parallel = di == 0.0;
            shut |= parallel & ((oi < -hi) | (oi > hi));
            let inv = 1.0 / di;
            let (t0, t1) = ((-hi - oi) * inv, (hi - oi) * inv);
            let (t0, t1) = if t0 > t1 { (t1, t0) } else { (t0, t1) };
            let enters = !parallel & (t0 > near);
            near = if enters { t0 } else { near };
            near_axis = if enters { axis } else { near_axis };
            let leaves = !parallel & (t1 < far);
            far = if leaves { t1 } else { far };
            far_axis = if leaves { axis } else { far_axis };
        }
        Slabs {
            near,
            far,
            near_axis,
            far_axis,
            // Never NaN: each starts infinite and takes only quotients that compare.
            open: !shut & (near <= far),
        }
    }

    /// Whether the shadow ray from `o` (local frame) along the world direction `dir` meets
    /// the box on `(0, reach)`: `intersect(..).is_some()`, without a branch.
    #[inline(always)]
    fn shadow_hit(&self, o: DVec3, origin: DVec3, dir: DVec3, reach: f64) -> bool {
        let missed = super::misses_bounding_sphere(&Ray::new(origin, dir), 0.0, reach, self.bounding_sphere());
        let slabs = self.slabs(o, self.frame.to_local(dir));
        !missed & (slabs.near_hit(0.0, reach) | slabs.far_hit(0.0, reach))
    }

    /// Bound on the distance from `p` (a hit on a face) to the box: the distance to the
    /// nearest face plane in the box's frame, plus its evaluation error.
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        let l = self.frame.to_local(p - self.center);
        let residual = (l.abs() - self.half_size).abs().min_element();
        residual + gamma(16) * (l1(p) + l1(self.center) + l1(self.half_size))
    }

    /// Box of the rotated box: each world axis extends `sum_j |A_ij| h_j`.
    pub fn bounds(&self) -> Option<Aabb> {
        let abs = DMat3::from_cols(self.axes.x_axis.abs(), self.axes.y_axis.abs(), self.axes.z_axis.abs());
        let ext = abs * self.half_size;
        Some(Aabb::new(self.center - ext, self.center + ext))
    }
}

/// Where a ray is inside a box's three slabs: from `near` (entering the slab of axis
/// `near_axis`) to `far` (leaving that of `far_axis`), when `open`.
struct Slabs {
    near: f64,
    far: f64,
    near_axis: usize,
    far_axis: usize,
    open: bool,
}

impl Slabs {
    /// Whether the ray enters the box inside `(t_min, t_max)`.
    #[inline(always)]
    fn near_hit(&self, t_min: f64, t_max: f64) -> bool {
        self.open & (self.near > t_min) & (self.near < t_max)
    }

    /// Whether the ray leaves the box inside `(t_min, t_max)`.
    #[inline(always)]
    fn far_hit(&self, t_min: f64, t_max: f64) -> bool {
        self.open & (self.far > t_min) & (self.far < t_max)
    }
}

impl super::fan::FanShape for Cuboid {
    /// The origin in the world, and in the box's frame.
    type Origin = (DVec3, DVec3);
    fn fan_origin(&self, origin: DVec3) -> (DVec3, DVec3) {
        (origin, self.frame.to_local(origin - self.center))
    }
    #[inline(always)]
    fn verdict(&self, (origin, o): (DVec3, DVec3), dir: DVec3, reach: f64) -> super::Verdict {
        let hit = self.shadow_hit(o, origin, dir, reach);
        super::Verdict::of(hit, !hit)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;

    #[test]
    fn axis_aligned_cube_from_outside_and_inside() {
        // The reference cube: center (0, 0, 3), side 2.
        let c = Cuboid::new(DVec3::new(0., 0., 3.), DVec3::splat(2.), DVec3::ZERO);
        assert_hit(c.intersect(&ray([0., -8., 3.], [0., 1., 0.]), 0.0, 1e9), 7.0, -DVec3::Y);
        assert_hit(c.intersect(&ray([0., 0., 3.], [0., 0., 1.]), 0.0, 1e9), 1.0, DVec3::Z);
        // A ray parallel to a face, outside its slab: miss; inside it: hit.
        assert!(c.intersect(&ray([0., -8., 4.5], [0., 1., 0.]), 0.0, 1e9).is_none());
        assert_hit(
            c.intersect(&ray([0.5, -8., 3.9], [0., 1., 0.]), 0.0, 1e9),
            7.0,
            -DVec3::Y,
        );
    }

    #[test]
    fn grazing_an_edge_and_a_face() {
        // The reference cube: center (0, 0, 3), side 2, so x, y in [-1, 1] and z in [2, 4].
        let c = Cuboid::new(DVec3::new(0., 0., 3.), DVec3::splat(2.), DVec3::ZERO);
        // Along the top edge x = 1, z = 4 (parallel to y): the slabs of x and z hold the ray
        // on their boundary (closed slabs), so it enters at the corner (1, -1, 4) through the
        // y slab: t = -1 - (-8) = 7, normal -y.
        assert_hit(c.intersect(&ray([1., -8., 4.], [0., 1., 0.]), 0.0, 1e9), 7.0, -DVec3::Y);
        // Across the same edge: from (0, 0, 5) along (1, 0, -1) / sqrt(2), touching the edge
        // at (1, 0, 4). In the box's frame o = (0, 0, 2); the x slab gives [-1, 1] / d.x and
        // the z slab [1, 3] / d.x (d.z = -d.x exactly), so near = far = 1 / d.x = sqrt(2): a
        // hit at the edge, entering through the z slab last (axis order breaks the tie):
        // normal +z.
        assert_hit(
            c.intersect(&ray([0., 0., 5.], [1., 0., -1.]), 0.0, 1e9),
            2f64.sqrt(),
            DVec3::Z,
        );
        // Started 1e-9 higher, the parallel ray passes over the edge: the z slab becomes
        // [1 + 1e-9, 3 + 1e-9] / d.x, entered after the x slab is left.
        assert!(
            c.intersect(&ray([0., 0., 5. + 1e-9], [1., 0., -1.]), 0.0, 1e9)
                .is_none()
        );
        // Along the top face, z = 4, through its middle: enters through the front face's top
        // edge at t = 7, normal -y; one ulp above the face, a miss.
        assert_hit(
            c.intersect(&ray([0.5, -8., 4.], [0., 1., 0.]), 0.0, 1e9),
            7.0,
            -DVec3::Y,
        );
        assert!(
            c.intersect(&ray([0.5, -8., 4f64.next_up()], [0., 1., 0.]), 0.0, 1e9)
                .is_none()
        );
        // From inside, along the top face: leaves through the back face at y = 1, t = 1.
        assert_hit(c.intersect(&ray([0.5, 0., 4.], [0., 1., 0.]), 0.0, 1e9), 1.0, DVec3::Y);
    }

    #[test]
    fn rotated_box_hit_has_the_rotated_normal() {
        // Cube of side 2 at the origin turned 30 degrees about z: local axes
        // x' = (cos 30, sin 30, 0) = (sqrt(3)/2, 1/2, 0) and y' = (-1/2, sqrt(3)/2, 0).
        let c = Cuboid::new(DVec3::ZERO, DVec3::splat(2.), DVec3::new(0., 0., 30.));
        let x_axis = DVec3::new(3f64.sqrt() / 2.0, 0.5, 0.0);
        // From (5, 0, 0) along -x. Local origin (5 sqrt(3)/2, -5/2, 0), local direction
        // (-sqrt(3)/2, 1/2, 0): the x' slab [-1, 1] is crossed for t in
        // [5 - 2/sqrt(3), 5 + 2/sqrt(3)] = [3.845, 6.155], the y' slab for t in [3, 7]; the
        // ray enters at t = 5 - 2/sqrt(3) through the +x' face, whose normal is x' (not the
        // reversed ray direction +x).
        assert_hit(
            c.intersect(&ray([5., 0., 0.], [-1., 0., 0.]), 0.0, 1e9),
            5.0 - 2.0 / 3f64.sqrt(),
            x_axis,
        );
        // A box of size (2, 4, 6) turned 90 degrees about x: its local y (half-size 2) is
        // world z, its local z (half-size 3) is world -y. Straight down onto it from z = 10:
        // the top face at z = 2, t = 8, normal (0, cos 90, sin 90) = +z to rounding; an
        // unturned box would be hit at z = 3.
        let b = Cuboid::new(DVec3::ZERO, DVec3::new(2., 4., 6.), DVec3::new(90., 0., 0.));
        assert_hit(b.intersect(&ray([0., 0., 10.], [0., 0., -1.]), 0.0, 1e9), 8.0, DVec3::Z);
        // Along +y from y = -10 at the height of the center: the face at y = -3, t = 7,
        // normal -y.
        assert_hit(
            b.intersect(&ray([0., -10., 0.], [0., 1., 0.]), 0.0, 1e9),
            7.0,
            -DVec3::Y,
        );
    }

    #[test]
    fn rotated_box() {
        // Unit cube rotated 45 degrees about z: its corner points along +x at x = sqrt(2)/2.
        let c = Cuboid::new(DVec3::ZERO, DVec3::ONE, DVec3::new(0., 0., 45.));
        let h = c.intersect(&ray([5., 0., 0.], [-1., 0., 0.]), 0.0, 1e9).unwrap();
        assert!((h.t - (5.0 - 0.5f64.sqrt())).abs() < 1e-12);
        let b = c.bounds().unwrap();
        assert!((b.max.x - 0.5f64.sqrt()).abs() < 1e-12 && (b.max.z - 0.5).abs() < 1e-12);
    }
}
