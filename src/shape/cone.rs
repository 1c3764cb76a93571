//! A capped cone: base center, unit axis towards the apex, height, base radius.

use super::{Aabb, SurfaceHit, cap_root, cylinder::disk_bounds, first_root};
use super::{gamma, l1};
use crate::math::{Frame, Ray};
use crate::solve::quadratic_parts;
use glam::DVec3;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Cone {
    pub base: DVec3,
    pub axis: DVec3,
    pub height: f64,
    pub radius: f64,
    #[serde(skip)]
    frame: Frame,
    /// The bounding sphere ([`Cone::bounding_sphere`]), tested before the quadric.
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
    /// cone is flatter than that ball), centerd on the axis at `z0` above the base.
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

    /// A ball around the whole cone (center, radius).
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        self.ball
    }

    /// In the local frame (axis +z, base at the origin, apex at `z = h`), with `k = r / h`:
    /// side `x^2 + y^2 = k^2 (h - z)^2` for `0 <= z <= h`; gradient `(x, y, k^2 (h - z))`.
    /// The base cap is the disk `z = 0`, radius `r`.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        if super::misses_bounding_sphere(ray, t_min, t_max, self.ball) {
            return None;
        }
        let (o, d, shift) = self.local_ray(ray);
        let (side, base) = self.local_roots(o, d, t_min - shift);
        // The nearer root, the side's on a tie.
        let t = if base < side { base } else { side };
        // Solved without `t_max`, which only filters the world-space `t`: the answer must
        // not depend on how far the caller looks (see `Shape::intersect`).
        if !(t < f64::INFINITY && t + shift < t_max) {
            return None;
        }
        let normal = if base < side {
            -self.axis
        } else {
            let (h, k) = (self.height, self.radius / self.height);
            let p = o + d * t;
            let g = DVec3::new(p.x, p.y, k * k * (h - p.z));
            // At the apex the gradient vanishes: use the axis.
            let n = if g.length_squared() > 0.0 {
                g.normalize()
            } else {
                DVec3::Z
            };
            self.frame.to_world(n)
        };
        Some(SurfaceHit { t: t + shift, normal })
    }

    /// The ray in the local frame, its origin moved by `shift` along it: far origins are
    /// solved from the point of the ray nearest the shape (see `recenter`).
    #[inline(always)]
    fn local_ray(&self, ray: &Ray) -> (DVec3, DVec3, f64) {
        let o = self.frame.to_local(ray.origin - self.base);
        let d = self.frame.to_local(ray.dir);
        let shift = super::recenter(o, d, DVec3::new(0.0, 0.0, 0.5 * self.height), self.height + self.radius);
        (o + d * shift, d, shift)
    }

    /// The first root above `t_min` of the ray `o + t d` (local frame) on the side and on the
    /// base, infinity where there is none, without a branch (see [`super::fan`]).
    #[inline(always)]
    fn local_roots(&self, o: DVec3, d: DVec3, t_min: f64) -> (f64, f64) {
        const NONE: f64 = f64::INFINITY;
        let (h, k) = (self.height, self.radius / self.height);
        let k2 = k * k;
        let w = h - o.z;
        let a = d.x * d.x + d.y * d.y - k2 * d.z * d.z;
        let b = 2.0 * (o.x * d.x + o.y * d.y + k2 * w * d.z);
        let c = o.x * o.x + o.y * o.y - k2 * w * w;
        let on_side = |t: f64| {
            let z = o.z + t * d.z;
            (t > t_min) & (t < NONE) & (z >= 0.0) & (z <= h)
        };
        let (t0, t1, real) = quadratic_parts(a, b, c);
        let t0 = if on_side(t0) { t0 } else { NONE };
        let t1 = if on_side(t1) { t1 } else { NONE };
        let side = first_root((t0.min(t1), t0.max(t1)), t_min, NONE);
        let r2 = self.radius * self.radius;
        let base = cap_root(o, d, 0.0, t_min, NONE, |x, y| x * x + y * y <= r2);
        (if real { side } else { NONE }, base)
    }

    /// Whether the shadow ray from `origin` along `dir` meets the cone on `(0, reach)`:
    /// `intersect(..).is_some()`, without a branch.
    #[inline(always)]
    fn shadow_hit(&self, origin: DVec3, dir: DVec3, reach: f64) -> bool {
        let ray = Ray::new(origin, dir);
        let missed = super::misses_bounding_sphere(&ray, 0.0, reach, self.ball);
        let (o, d, shift) = self.local_ray(&ray);
        let (side, base) = self.local_roots(o, d, 0.0 - shift);
        let t = if base < side { base } else { side };
        !missed & (t < f64::INFINITY) & (t + shift < reach)
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

impl super::fan::FanShape for Cone {
    type Origin = DVec3;
    fn fan_origin(&self, origin: DVec3) -> DVec3 {
        origin
    }
    #[inline(always)]
    fn verdict(&self, origin: DVec3, dir: DVec3, reach: f64) -> super::Verdict {
        let hit = self.shadow_hit(origin, dir, reach);
        super::Verdict::of(hit, !hit)
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

    /// A cone whose slope `k = r / h = 1/2` and `k^2 = 1/4` are exact in binary, so the
    /// quadratic's coefficients below are exact and tangencies are decided exactly.
    fn half_slope() -> Cone {
        // Base (1, 2, 0), axis +z, height 2, radius 1: the side is
        // (x - 1)^2 + (y - 2)^2 = (2 - z)^2 / 4, a circle of radius (2 - z) / 2 at height z.
        Cone::new(DVec3::new(1., 2., 0.), DVec3::Z, 2.0, 1.0)
    }

    #[test]
    fn tangent_to_a_circle_of_the_side() {
        let c = half_slope();
        // At z = 1 the side is the circle of radius 1/2. A ray along +x at y = 2 + 1/2 touches
        // it at (1, 2.5, 1): in the local frame o = (-5, 0.5, 1), d = (1, 0, 0), so
        // a = 1, b = 2 (-5) = -10, c = 25 + 0.25 - (1/4)(2 - 1)^2 = 25: b^2 - 4ac = 0 exactly,
        // a double root t = 5. Normal: gradient (x, y, k^2 (h - z)) = (0, 1/2, 1/4), i.e.
        // (0, 2, 1) / sqrt(5).
        let n = DVec3::new(0., 2., 1.) / 5f64.sqrt();
        assert_hit(c.intersect(&ray([-4., 2.5, 1.], [1., 0., 0.]), 0.0, 1e9), 5.0, n);
        // One ulp of y further out (4.4e-16) the line misses the circle by 4.4e-16, but c
        // would exceed 25 by 4.4e-16, less than half an ulp of 25.25 (1.8e-15): it rounds to
        // 25 again and the ray still touches at t = 5. That is the grazing band of this
        // quadratic; 1e-12 out, c = 25 + 1e-12 to its rounding, b^2 - 4ac < 0: a miss.
        let one_ulp = c.intersect(&ray([-4., 2.5f64.next_up(), 1.], [1., 0., 0.]), 0.0, 1e9);
        assert_eq!(one_ulp.map(|h| h.t), Some(5.0));
        assert!(
            c.intersect(&ray([-4., 2.5 + 1e-12, 1.], [1., 0., 0.]), 0.0, 1e9)
                .is_none()
        );
        // 1e-6 inside, it crosses the circle twice: y - 2 = 0.5 - 1e-6 gives
        // (x - 1)^2 = 0.25 - (0.5 - 1e-6)^2 = 1e-6 - 1e-12, the first crossing at
        // x - 1 = -sqrt(1e-6 - 1e-12), about 1e-3 before the tangent point.
        let h = c
            .intersect(&ray([-4., 2.5 - 1e-6, 1.], [1., 0., 0.]), 0.0, 1e9)
            .unwrap();
        let want = 5.0 - (1e-6f64 - 1e-12).sqrt();
        assert!((h.t - want).abs() < 1e-9, "t = {} expected {want}", h.t);
    }

    #[test]
    fn ray_parallel_to_a_generator_and_in_its_tangent_plane() {
        // Local frame = world frame shifted by the base (1, 2, 0); the generator from the
        // apex (0, 0, 2) to the rim point (1, 0, 0) has direction g = (1, 0, -2) / sqrt(5).
        // `normalize` scales by one rounded 1/|g|, so d.z = -2 d.x exactly and
        // a = d.x^2 - (1/4) d.z^2 is exactly 0: the quadratic is linear, b t + c = 0.
        let c = half_slope();
        let g = [1., 0., -2.];
        // Parallel to g through the axis point (0, 0, 1), from o = (-1, 0, 3): w = h - o.z = -1,
        // b = 2 (o.x d.x + k^2 w d.z) = 2 (-d.x + d.x / 2) = -d.x, c = 1 - (1/4)(1) = 3/4, so
        // t = -c / b = (3/4) sqrt(5), at (-1/4, 0, 3/2) on the opposite generator. A line
        // parallel to a generator meets the double cone once: this is that crossing.
        // Normal: (x, y, k^2 (h - z)) = (-1/4, 0, 1/8), i.e. (-2, 0, 1) / sqrt(5).
        let n = DVec3::new(-2., 0., 1.) / 5f64.sqrt();
        assert_hit(c.intersect(&ray([0., 2., 3.], g), 0.0, 1e9), 0.75 * 5f64.sqrt(), n);
        // From o = (-1, 1/2, 4) along g (w = -2): the line lies in the tangent plane along
        // that generator (spanned by g and the circle's tangent +y), which touches the cone
        // only on the generator. Then b = 2 (-d.x + 0 + (1/4)(-2) d.z) = 0 exactly and
        // c = 1 + 1/4 - 1 = 1/4: no root. It reaches the base plane at local (1, 1/2, 0),
        // outside the base disk (1 + 1/4 > 1).
        assert!(c.intersect(&ray([0., 2.5, 4.], g), 0.0, 1e9).is_none());
    }

    #[test]
    fn rays_parallel_to_the_base_cap() {
        let c = half_slope();
        // At z = 1/2 the side's radius is 3/4: along +x through the axis, from x - 1 = -5, the
        // side at x - 1 = -3/4, t = 4.25; every side normal along one generator is the same,
        // (-3/4, 0, (1/4)(3/2)) ~ (-2, 0, 1) / sqrt(5). The cap (d.z = 0) is never hit.
        let n = DVec3::new(-2., 0., 1.) / 5f64.sqrt();
        assert_hit(c.intersect(&ray([-4., 2., 0.5], [1., 0., 0.]), 0.0, 1e9), 4.25, n);
        // In the base plane itself: the cap's plane contains the ray (skipped: d.z = 0), and
        // the side's roots x - 1 = -+1 are at z = 0, the rim, inside [0, h]: the hit is the
        // rim, with the side's normal, at t = 4.
        assert_hit(c.intersect(&ray([-4., 2., 0.], [1., 0., 0.]), 0.0, 1e9), 4.0, n);
        // From inside, parallel to the base: the exit through the side at x - 1 = +3/4, with
        // normal (3/4, 0, 3/8) ~ (2, 0, 1) / sqrt(5).
        let exit = DVec3::new(2., 0., 1.) / 5f64.sqrt();
        assert_hit(c.intersect(&ray([1., 2., 0.5], [1., 0., 0.]), 0.0, 1e9), 0.75, exit);
    }

    #[test]
    fn upside_down_cone() {
        // Axis -z, base at z = 2: apex at z = 0. A ray down the axis hits the base cap at z = 2.
        let c = Cone::new(DVec3::new(0., 0., 2.), -DVec3::Z, 2.0, 1.0);
        assert_hit(c.intersect(&ray([0., 0., 5.], [0., 0., -1.]), 0.0, 1e9), 3.0, DVec3::Z);
    }
}
