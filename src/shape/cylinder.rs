//! A cylinder: base center, unit axis, height, radius; capped (a closed solid), or open (a
//! tube, SIMRenderer's `tube`: the side alone, seen from inside as from outside).

use super::{Aabb, SurfaceHit, Verdict, cap_root, first_root, first_root_in, local_cap, nearer};
use super::{gamma, l1};
use crate::math::{Frame, Ray};
use crate::solve::{quadratic, quadratic_parts};
use glam::DVec3;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Cylinder {
    pub base: DVec3,
    pub axis: DVec3,
    pub height: f64,
    pub radius: f64,
    /// Without caps: an open surface, not a solid.
    #[serde(skip_serializing_if = "is_false")]
    pub open: bool,
    #[serde(skip)]
    frame: Frame,
    /// The bounding sphere ([`Cylinder::bounding_sphere`]), tested before the quadric.
    #[serde(skip)]
    ball: (DVec3, f64),
}

impl Cylinder {
    pub fn new(base: DVec3, axis: DVec3, height: f64, radius: f64) -> Self {
        let axis = axis.normalize();
        Cylinder {
            base,
            axis,
            height,
            radius,
            open: false,
            frame: Frame::from_z(axis),
            ball: Self::ball_of(base, axis, height, radius),
        }
    }

    /// The open tube: the same side, no caps.
    pub fn tube(base: DVec3, axis: DVec3, height: f64, radius: f64) -> Self {
        Cylinder {
            open: true,
            ..Cylinder::new(base, axis, height, radius)
        }
    }

    /// The same cylinder (axis and frame to the bit) with another base, height and radius:
    /// what a similarity transform makes of it.
    pub fn resized(&self, base: DVec3, height: f64, radius: f64) -> Cylinder {
        Cylinder {
            base,
            height,
            radius,
            ball: Self::ball_of(base, self.axis, height, radius),
            ..self.clone()
        }
    }

    /// A ball around the whole cylinder: centerd half-way up the axis, through the rims.
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        self.ball
    }

    fn ball_of(base: DVec3, axis: DVec3, height: f64, radius: f64) -> (DVec3, f64) {
        (base + 0.5 * height * axis, libm::hypot(radius, 0.5 * height))
    }

    /// In the local frame (axis = +z, base at the origin): side `x^2 + y^2 = r^2` for
    /// `0 <= z <= h`, and (unless open) the caps `z = 0`, `z = h` within radius `r`.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        if super::misses_bounding_sphere(ray, t_min, t_max, self.bounding_sphere()) {
            return None;
        }
        let o = self.frame.to_local(ray.origin - self.base);
        let d = self.frame.to_local(ray.dir);
        // Far origins: solve from the point of the ray nearest the shape (see `recenter`).
        let shift = super::recenter(o, d, DVec3::new(0.0, 0.0, 0.5 * self.height), self.height + self.radius);
        // Solved without `t_max`, which only filters the world-space `t`: the answer must
        // not depend on how far the caller looks (see `Shape::intersect`).
        self.intersect_local(o + d * shift, d, t_min - shift, f64::INFINITY)
            .map(|h| SurfaceHit { t: h.t + shift, ..h })
            .filter(|h| h.t < t_max)
    }

    /// The intersection in the local frame, for the ray `o + t d`.
    fn intersect_local(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let r2 = self.radius * self.radius;
        let a = d.x * d.x + d.y * d.y;
        let on_side = |t: f64| {
            let z = o.z + t * d.z;
            t > t_min && t < t_max && (0.0..=self.height).contains(&z)
        };
        // A ray parallel to the axis (a = 0) never meets the side, only the caps.
        let side = (a > 0.0)
            .then(|| quadratic(a, 2.0 * (o.x * d.x + o.y * d.y), o.x * o.x + o.y * o.y - r2))
            .flatten()
            .and_then(|(t0, t1)| {
                let t0 = if on_side(t0) { t0 } else { f64::INFINITY };
                let t1 = if on_side(t1) { t1 } else { f64::INFINITY };
                first_root_in((t0.min(t1), t0.max(t1)), t_min, t_max)
            });
        let side = side.map(|t| {
            let p = o + d * t;
            SurfaceHit {
                t,
                normal: self.frame.to_world(DVec3::new(p.x, p.y, 0.0) / self.radius).normalize(),
            }
        });
        if self.open {
            return side;
        }
        let in_disk = |x: f64, y: f64| x * x + y * y <= r2;
        let bottom = local_cap(o, d, 0.0, t_min, t_max, in_disk).map(|t| SurfaceHit { t, normal: -self.axis });
        let top = local_cap(o, d, self.height, t_min, t_max, in_disk).map(|t| SurfaceHit { t, normal: self.axis });
        nearer(nearer(side, bottom), top)
    }

    /// Whether the shadow ray from `origin` along `dir` meets the cylinder on `(0, reach)`:
    /// `intersect(..).is_some()`, every step of it evaluated and selected without a branch
    /// (see [`super::fan`]). For `a > 0` the quadratic's branch-free form gives the same
    /// roots; the hit's `t` is the least of the side's and the caps' roots, infinity for
    /// none, as `nearer` keeps it.
    #[inline(always)]
    fn shadow_hit(&self, origin: DVec3, dir: DVec3, reach: f64) -> bool {
        const NONE: f64 = f64::INFINITY;
        let ray = Ray::new(origin, dir);
        let missed = super::misses_bounding_sphere(&ray, 0.0, reach, self.bounding_sphere());
        let o = self.frame.to_local(ray.origin - self.base);
        let d = self.frame.to_local(ray.dir);
        let shift = super::recenter(o, d, DVec3::new(0.0, 0.0, 0.5 * self.height), self.height + self.radius);
        let (o, t_min) = (o + d * shift, 0.0 - shift);
        let r2 = self.radius * self.radius;
        let a = d.x * d.x + d.y * d.y;
        let on_side = |t: f64| {
            let z = o.z + t * d.z;
            (t > t_min) & (t < NONE) & (z >= 0.0) & (z <= self.height)
        };
        let (t0, t1, real) = quadratic_parts(a, 2.0 * (o.x * d.x + o.y * d.y), o.x * o.x + o.y * o.y - r2);
        let t0 = if on_side(t0) { t0 } else { NONE };
        let t1 = if on_side(t1) { t1 } else { NONE };
        let side = first_root((t0.min(t1), t0.max(t1)), t_min, NONE);
        let side = if (a > 0.0) & real { side } else { NONE };
        let in_disk = |x: f64, y: f64| x * x + y * y <= r2;
        let bottom = cap_root(o, d, 0.0, t_min, NONE, in_disk);
        let top = cap_root(o, d, self.height, t_min, NONE, in_disk);
        let caps = if top < bottom { top } else { bottom };
        let closed = if caps < side { caps } else { side };
        let t = if self.open { side } else { closed };
        !missed & (t < NONE) & (t + shift < reach)
    }

    /// Bound on the distance from `p` to the cylinder: the smallest of the distances to the
    /// side `| sqrt(x^2 + y^2) - r |` and (unless open) to the cap planes, plus its
    /// evaluation error.
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        let l = self.frame.to_local(p - self.base);
        let side = (l.truncate().length() - self.radius).abs();
        let residual = if self.open {
            side
        } else {
            side.min(l.z.abs()).min((l.z - self.height).abs())
        };
        residual + gamma(16) * (l1(p) + l1(self.base) + self.radius + self.height)
    }

    pub fn bounds(&self) -> Option<Aabb> {
        disk_bounds(self.base, self.axis, self.radius)
            .map(|b| b.union(disk_bounds(self.base + self.axis * self.height, self.axis, self.radius).unwrap()))
    }
}

impl super::fan::FanShape for Cylinder {
    type Origin = DVec3;
    fn fan_origin(&self, origin: DVec3) -> DVec3 {
        origin
    }
    #[inline(always)]
    fn verdict(&self, origin: DVec3, dir: DVec3, reach: f64) -> Verdict {
        let hit = self.shadow_hit(origin, dir, reach);
        Verdict::of(hit, !hit)
    }
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// Box of a disk (shared by cylinder and cone caps).
pub(crate) fn disk_bounds(center: DVec3, normal: DVec3, radius: f64) -> Option<Aabb> {
    super::Disk::new(center, normal, radius).bounds()
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;

    fn reference() -> Cylinder {
        // The reference cylinder: base (-5, 9, 0), radius 1, height 3, axis +z.
        Cylinder::new(DVec3::new(-5., 9., 0.), DVec3::Z, 3.0, 1.0)
    }

    #[test]
    fn side_caps_and_inside() {
        let c = reference();
        assert_hit(c.intersect(&ray([-5., 0., 1.], [0., 1., 0.]), 0.0, 1e9), 8.0, -DVec3::Y);
        assert_hit(
            c.intersect(&ray([-5., 9., 10.], [0., 0., -1.]), 0.0, 1e9),
            7.0,
            DVec3::Z,
        );
        assert_hit(
            c.intersect(&ray([-5.5, 9., -4.], [0., 0., 1.]), 0.0, 1e9),
            4.0,
            -DVec3::Z,
        );
        // From inside, along +x: exits through the side at t = 1.
        assert_hit(c.intersect(&ray([-5., 9., 1.5], [1., 0., 0.]), 0.0, 1e9), 1.0, DVec3::X);
        // Parallel to the caps above the top: miss.
        assert!(c.intersect(&ray([-5., 0., 3.5], [0., 1., 0.]), 0.0, 1e9).is_none());
        // Tangent to the side: double root at x = -4.
        assert_hit(c.intersect(&ray([-4., 0., 1.], [0., 1., 0.]), 0.0, 1e9), 9.0, DVec3::X);
    }

    #[test]
    fn rays_in_a_cap_plane_and_along_the_side() {
        let c = reference();
        // In the top cap's plane z = 3, along +x through the axis from x = -10: the caps'
        // plane contains the ray (d.z = 0, skipped); the side's roots x = -5 -+ 1 are at
        // z = 3, its closed top edge: the rim is hit at t = 4 with the side's normal -x.
        assert_hit(
            c.intersect(&ray([-10., 9., 3.], [1., 0., 0.]), 0.0, 1e9),
            4.0,
            -DVec3::X,
        );
        // Up the line x = -4, which lies in the side: a = d.x^2 + d.y^2 = 0, so the side is
        // not intersected; the bottom cap takes the ray at its rim point (-4, 9, 0)
        // (x^2 + y^2 = 1 <= r^2, exact), t = 2, normal -z.
        assert_hit(
            c.intersect(&ray([-4., 9., -2.], [0., 0., 1.]), 0.0, 1e9),
            2.0,
            -DVec3::Z,
        );
        // From inside the cylinder up the same kind of line (x = -4.5): the top cap, t = 2.
        assert_hit(c.intersect(&ray([-4.5, 9., 1.], [0., 0., 1.]), 0.0, 1e9), 2.0, DVec3::Z);
    }

    #[test]
    fn an_open_tube_is_seen_from_inside() {
        // The reference cylinder without caps.
        let c = Cylinder::tube(DVec3::new(-5., 9., 0.), DVec3::Z, 3.0, 1.0);
        // Down the axis from above: through both open ends, no hit (the capped one is hit
        // at t = 7).
        assert!(c.intersect(&ray([-5., 9., 10.], [0., 0., -1.]), 0.0, 1e9).is_none());
        // From the axis outwards: the inner wall at t = 1, normal +x (outward; the tracer
        // turns it to the ray's side).
        assert_hit(c.intersect(&ray([-5., 9., 1.5], [1., 0., 0.]), 0.0, 1e9), 1.0, DVec3::X);
        // Down the slant (1, 0, -1) / sqrt(2) from (-5.5, 9, 4): through the top opening at
        // x = -4.5 (t = sqrt(2)), then the inner wall x = -4 at z = 2.5, t = 1.5 sqrt(2).
        assert_hit(
            c.intersect(&ray([-5.5, 9., 4.], [1., 0., -1.]), 0.0, 1e9),
            1.5 * 2f64.sqrt(),
            DVec3::X,
        );
        // From outside through the side: the outer wall first, at t = 8 (as the capped one).
        assert_hit(c.intersect(&ray([-5., 0., 1.], [0., 1., 0.]), 0.0, 1e9), 8.0, -DVec3::Y);
        // The far wall from inside the first: t = 10.
        assert_hit(c.intersect(&ray([-5., 0., 1.], [0., 1., 0.]), 8.0, 1e9), 10.0, DVec3::Y);
        // The error bound near an open end measures the side, not the missing cap's plane.
        assert!(c.surface_error(DVec3::new(-5.5, 9., 0.0)) > 0.4);
    }

    #[test]
    fn tilted_axis() {
        // Axis along +x from the origin: a ray down -z hits the side at z = 1.
        let c = Cylinder::new(DVec3::ZERO, DVec3::X, 4.0, 1.0);
        assert_hit(c.intersect(&ray([2., 0., 5.], [0., 0., -1.]), 0.0, 1e9), 4.0, DVec3::Z);
        assert_hit(c.intersect(&ray([-3., 0., 0.], [1., 0., 0.]), 0.0, 1e9), 3.0, -DVec3::X);
    }
}
