//! A capped cone: base centre, unit axis towards the apex, height, base radius.

use super::{Aabb, SurfaceHit, cylinder::disk_bounds, first_root_in, local_cap, nearer};
use super::{gamma, l1};
use crate::math::{Frame, Ray};
use crate::solve::quadratic;
use glam::DVec3;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Cone {
    pub base: DVec3,
    pub axis: DVec3,
    pub height: f64,
    pub radius: f64,
    #[serde(skip)]
    frame: Frame,
    /// The bounding ball ([`Cone::ball`]), tested before the quadric.
    #[serde(skip)]
    ball: (DVec3, f64),
}

impl Cone {
    pub fn new(base: DVec3, axis: DVec3, height: f64, radius: f64) -> Self {
        let axis = axis.normalize();
        Cone {
            base,
            axis,
            height,
            radius,
            frame: Frame::from_z(axis),
            ball: Self::smallest_ball(base, axis, height, radius),
        }
    }

    /// The smallest ball through the base rim and the apex (or around the base when the
    /// cone is flatter than that ball), centred on the axis at `z0` above the base.
    fn smallest_ball(base: DVec3, axis: DVec3, h: f64, r: f64) -> (DVec3, f64) {
        if h > r {
            let z0 = (h * h - r * r) / (2.0 * h);
            (base + z0 * axis, h - z0)
        } else {
            (base, r)
        }
    }

    /// The same cone (axis and frame to the bit) with another base, height and radius: what a
    /// similarity transform makes of it.
    pub fn resized(&self, base: DVec3, height: f64, radius: f64) -> Cone {
        Cone {
            base,
            height,
            radius,
            ball: Self::smallest_ball(base, self.axis, height, radius),
            ..self.clone()
        }
    }

    /// A ball around the whole cone (centre, radius).
    pub fn ball(&self) -> (DVec3, f64) {
        self.ball
    }

    /// In the local frame (axis +z, base at the origin, apex at `z = h`), with `k = r / h`:
    /// side `x^2 + y^2 = k^2 (h - z)^2` for `0 <= z <= h`; gradient `(x, y, k^2 (h - z))`.
    /// The base cap is the disk `z = 0`, radius `r`.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        if super::misses_ball(ray, t_min, t_max, self.ball) {
            return None;
        }
        let o = self.frame.to_local(ray.origin - self.base);
        let d = self.frame.to_local(ray.dir);
        // Far origins: solve from the point of the ray nearest the shape (see `recentre`).
        let shift = super::recentre(o, d, DVec3::new(0.0, 0.0, 0.5 * self.height), self.height + self.radius);
        // Solved without `t_max`, which only filters the world-space `t`: the answer must
        // not depend on how far the caller looks (see `Shape::intersect`).
        self.intersect_local(o + d * shift, d, t_min - shift, f64::INFINITY)
            .map(|h| SurfaceHit { t: h.t + shift, ..h })
            .filter(|h| h.t < t_max)
    }

    /// The intersection in the local frame, for the ray `o + t d`.
    fn intersect_local(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let (h, k) = (self.height, self.radius / self.height);
        let k2 = k * k;
        let w = h - o.z;
        let a = d.x * d.x + d.y * d.y - k2 * d.z * d.z;
        let b = 2.0 * (o.x * d.x + o.y * d.y + k2 * w * d.z);
        let c = o.x * o.x + o.y * o.y - k2 * w * w;
        let on_side = |t: f64| {
            let z = o.z + t * d.z;
            t > t_min && t < t_max && (0.0..=h).contains(&z)
        };
        let side = quadratic(a, b, c).and_then(|(t0, t1)| {
            let t0 = if on_side(t0) { t0 } else { f64::INFINITY };
            let t1 = if on_side(t1) { t1 } else { f64::INFINITY };
            first_root_in((t0.min(t1), t0.max(t1)), t_min, t_max)
        });
        let side = side.map(|t| {
            let p = o + d * t;
            let g = DVec3::new(p.x, p.y, k2 * (h - p.z));
            // At the apex the gradient vanishes: use the axis.
            let n = if g.length_squared() > 0.0 {
                g.normalize()
            } else {
                DVec3::Z
            };
            SurfaceHit {
                t,
                normal: self.frame.to_world(n),
            }
        });
        let r2 = self.radius * self.radius;
        let base = local_cap(o, d, 0.0, t_min, t_max, |x, y| x * x + y * y <= r2)
            .map(|t| SurfaceHit { t, normal: -self.axis });
        nearer(side, base)
    }

    /// Bound on the distance from `p` to the cone: the smallest of the distance to the side,
    /// `| sqrt(x^2 + y^2) - k (h - z) | / sqrt(1 + k^2)`, and to the base plane, plus its
    /// evaluation error.
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        let l = self.frame.to_local(p - self.base);
        let k = self.radius / self.height;
        let side = (l.truncate().length() - k * (self.height - l.z)).abs() / (1.0 + k * k).sqrt();
        let residual = side.min(l.z.abs());
        residual + gamma(16) * (l1(p) + l1(self.base) + self.radius + self.height)
    }

    pub fn bounds(&self) -> Option<Aabb> {
        disk_bounds(self.base, self.axis, self.radius).map(|b| b.include(self.base + self.axis * self.height))
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;

    fn reference() -> Cone {
        // The reference cone: base (-3, -3, 0), radius 1, height 2.5, apex +z.
        Cone::new(DVec3::new(-3., -3., 0.), DVec3::Z, 2.5, 1.0)
    }

    #[test]
    fn side_base_and_inside() {
        let c = reference();
        // Horizontal ray at z = 1.25 (half height, radius 0.5) along +x: hits x = -3.5.
        // Slope: normal ~ (1, 0, k) with k = 1/2.5 = 0.4, normalised (-1, 0, 0.4)/sqrt(1.16).
        let n = DVec3::new(-1., 0., 0.4) / 1.16f64.sqrt();
        assert_hit(c.intersect(&ray([-10., -3., 1.25], [1., 0., 0.]), 0.0, 1e9), 6.5, n);
        // Up the axis from below: the base cap at t = 1.
        assert_hit(
            c.intersect(&ray([-3., -3., -1.], [0., 0., 1.]), 0.0, 1e9),
            1.0,
            -DVec3::Z,
        );
        // From inside, up the axis: exits at the apex, t = 2.5 - 0.5 = 2 (normal = axis).
        assert_hit(
            c.intersect(&ray([-3., -3., 0.5], [0., 0., 1.]), 0.0, 1e9),
            2.0,
            DVec3::Z,
        );
        // Above the apex, horizontal: miss (the other nappe is not part of the cone).
        assert!(c.intersect(&ray([-10., -3., 3.0], [1., 0., 0.]), 0.0, 1e9).is_none());
        // Parallel to the base cap, below it: miss.
        assert!(c.intersect(&ray([-10., -3., -0.1], [1., 0., 0.]), 0.0, 1e9).is_none());
    }

    #[test]
    fn upside_down_cone() {
        // Axis -z, base at z = 2: apex at z = 0. A ray down the axis hits the base cap at z = 2.
        let c = Cone::new(DVec3::new(0., 0., 2.), -DVec3::Z, 2.0, 1.0);
        assert_hit(c.intersect(&ray([0., 0., 5.], [0., 0., -1.]), 0.0, 1e9), 3.0, DVec3::Z);
    }
}
