//! A box: centre, full size along its three axes, optional rotation (the reference cube).

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
}

impl Cuboid {
    /// `rotation_deg` rotates about x, then y, then z (degrees), around the centre.
    pub fn new(center: DVec3, size: DVec3, rotation_deg: DVec3) -> Self {
        let r = rotation_deg * (std::f64::consts::PI / 180.0);
        let axes = DMat3::from_rotation_z(r.z) * DMat3::from_rotation_y(r.y) * DMat3::from_rotation_x(r.x);
        Cuboid {
            center,
            half_size: size * 0.5,
            frame: Frame::from_axes(axes.x_axis, axes.y_axis, axes.z_axis),
            axes,
        }
    }

    /// A ball around the whole box: its centre and half-diagonal.
    pub fn ball(&self) -> (DVec3, f64) {
        (self.center, self.half_size.length())
    }

    /// Slab test in the box's frame; the face normal is the axis whose slab was entered
    /// (or, from inside, left) last.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        if super::misses_ball(ray, t_min, t_max, self.ball()) {
            return None;
        }
        let o = self.frame.to_local(ray.origin - self.center);
        let d = self.frame.to_local(ray.dir);
        let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
        let (mut near_axis, mut far_axis) = (0usize, 0usize);
        for axis in 0..3 {
            let (oi, di, hi) = (o[axis], d[axis], self.half_size[axis]);
            if di == 0.0 {
                if oi < -hi || oi > hi {
                    return None;
                }
                continue;
            }
            let inv = 1.0 / di;
            let (mut t0, mut t1) = ((-hi - oi) * inv, (hi - oi) * inv);
            if t0 > t1 {
                std::mem::swap(&mut t0, &mut t1);
            }
            if t0 > near {
                near = t0;
                near_axis = axis;
            }
            if t1 < far {
                far = t1;
                far_axis = axis;
            }
        }
        if near > far {
            return None;
        }
        let (t, axis) = if near > t_min && near < t_max {
            (near, near_axis)
        } else if far > t_min && far < t_max {
            (far, far_axis)
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

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;

    #[test]
    fn axis_aligned_cube_from_outside_and_inside() {
        // The reference cube: centre (0, 0, 3), side 2.
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
    fn rotated_box() {
        // Unit cube rotated 45 degrees about z: its corner points along +x at x = sqrt(2)/2.
        let c = Cuboid::new(DVec3::ZERO, DVec3::ONE, DVec3::new(0., 0., 45.));
        let h = c.intersect(&ray([5., 0., 0.], [-1., 0., 0.]), 0.0, 1e9).unwrap();
        assert!((h.t - (5.0 - 0.5f64.sqrt())).abs() < 1e-12);
        let b = c.bounds().unwrap();
        assert!((b.max.x - 0.5f64.sqrt()).abs() < 1e-12 && (b.max.z - 0.5).abs() < 1e-12);
    }
}
