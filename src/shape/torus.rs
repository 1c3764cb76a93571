//! The torus: centre, unit axis, major radius `R` (centre to tube centre) and minor
//! radius `r` (tube). In its local frame (axis +z) it is the quartic surface
//! `f(p) = (|p|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + y^2) = 0`.
//!
//! Robustness (as POV-Ray does): the ray is first clipped against the bounding sphere
//! `|p| <= R + r` and the slab `|z| <= r`, and its origin moved to the clip entry, so the
//! quartic is solved for a ray starting next to the torus (no coefficient blow-up for far
//! origins). Roots are isolated and refined on `f` evaluated directly at the point, not on
//! the expanded coefficients, so a hit point lies on the surface to rounding precision.

use super::{Aabb, SurfaceHit, gamma, l1};
use crate::math::{Frame, Ray};
use crate::solve::{ferrari, horner, orellana, poly_roots_with};
use glam::DVec3;

/// Which quartic solver the torus uses (see BENCHMARKS.md, "Numerical stability"); the
/// renderer always uses [`QuarticMethod::Isolator`], the others are kept for comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QuarticMethod {
    /// Derivative-recursion root isolation with Newton-bisection on the implicit equation.
    Isolator,
    /// Textbook Ferrari closed form, then Newton polish.
    Ferrari,
    /// Orellana and De Michele (ACM TOMS Algorithm 1010), then Newton polish.
    OrellanaDeMichele,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Torus {
    pub center: DVec3,
    pub axis: DVec3,
    pub major: f64,
    pub minor: f64,
    #[serde(skip)]
    frame: Frame,
}

impl Torus {
    pub fn new(center: DVec3, axis: DVec3, major: f64, minor: f64) -> Self {
        let axis = axis.normalize();
        Torus {
            center,
            axis,
            major,
            minor,
            frame: Frame::from_z(axis),
        }
    }

    /// `f(p)` of the module doc, in local coordinates.
    fn implicit(&self, p: DVec3) -> f64 {
        let (big, small) = (self.major, self.minor);
        let s = p.length_squared() + big * big - small * small;
        s * s - 4.0 * big * big * (p.x * p.x + p.y * p.y)
    }

    /// All roots in `(t_min, t_max)`, increasing, calling `visit` until it returns true.
    fn roots(&self, ray: &Ray, t_min: f64, t_max: f64, visit: &mut dyn FnMut(f64, DVec3, DVec3) -> bool) {
        self.roots_with(QuarticMethod::Isolator, ray, t_min, t_max, visit)
    }

    /// As [`Torus::roots`] with a chosen quartic solver (the solver comparison uses the others).
    fn roots_with(
        &self,
        method: QuarticMethod,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        visit: &mut dyn FnMut(f64, DVec3, DVec3) -> bool,
    ) {
        let o = self.frame.to_local(ray.origin - self.center);
        let d = self.frame.to_local(ray.dir);
        // Clipped without `t_max`: the shifted origin, and so every root's bits, must not
        // depend on how far the caller looks, or a closest-hit search that shrinks `t_max`
        // as it goes would get other bits for this torus in another visiting order (the
        // linear scan and the BVH must agree to the bit). `t_max` only filters the roots.
        let Some((enter, exit)) = self.clip(o, d, t_min, f64::INFINITY) else {
            return;
        };
        // Every root is at `enter + s >= enter`: none can be below `t_max`.
        if enter >= t_max {
            return;
        }
        // Shift the origin to the clip entry: p(s) = o' + s d, s in [0, exit - enter].
        let o2 = o + d * enter;
        let (big, small) = (self.major, self.minor);
        let k = o2.length_squared() + big * big - small * small;
        let n = o2.dot(d);
        let m = d.length_squared();
        let four_r2 = 4.0 * big * big;
        let rho2 = o2.x * o2.x + o2.y * o2.y;
        let mut coeffs = [
            k * k - four_r2 * rho2,
            4.0 * n * k - 2.0 * four_r2 * (o2.x * d.x + o2.y * d.y),
            4.0 * n * n + 2.0 * m * k - four_r2 * (d.x * d.x + d.y * d.y),
            4.0 * m * n,
            m * m,
        ];
        // A ray starting on the surface (a secondary ray from a hit on this torus, with no
        // clip shift): `f(o)` is zero up to its own rounding error, and any sign it has is
        // noise that would make a spurious root next to `s = 0`. Force the constant
        // coefficient to exactly zero so that root is exactly 0 and excluded by `t > t_min`.
        // Bound on the rounding of `k^2 - 4 R^2 rho^2`: gamma(8) (k^2 + 4 R^2 rho^2).
        let on_surface = enter == t_min && coeffs[0].abs() <= gamma(8) * (k * k + four_r2 * rho2);
        if on_surface {
            coeffs[0] = 0.0;
        }
        let f = |s: f64| {
            if on_surface && s == 0.0 {
                0.0
            } else {
                self.implicit(o2 + d * s)
            }
        };
        let mut found = Vec::with_capacity(4);
        let len = exit - enter;
        match method {
            QuarticMethod::Isolator => poly_roots_with(&coeffs, 0.0, len, &f, &mut found),
            QuarticMethod::Ferrari | QuarticMethod::OrellanaDeMichele => {
                if coeffs[0] == 0.0 {
                    // On the surface: deflate, s = 0 exactly and the cubic's roots.
                    found.push(0.0);
                    let c4 = coeffs[4];
                    found.extend(ferrari::cubic_roots(coeffs[3] / c4, coeffs[2] / c4, coeffs[1] / c4));
                } else if method == QuarticMethod::Ferrari {
                    ferrari::quartic_roots(&coeffs, &mut found);
                } else {
                    orellana::quartic_roots(&coeffs, &mut found);
                }
                // Newton polish on the original (unexpanded) equation: two steps, each kept
                // only if it lowers the residual.
                let deriv = [coeffs[1], 2.0 * coeffs[2], 3.0 * coeffs[3], 4.0 * coeffs[4]];
                for s in found.iter_mut() {
                    for _ in 0..2 {
                        let (fs, ds) = (f(*s), horner(&deriv, *s));
                        if fs == 0.0 || ds == 0.0 {
                            break;
                        }
                        let next = *s - fs / ds;
                        if f(next).abs() < fs.abs() {
                            *s = next;
                        } else {
                            break;
                        }
                    }
                }
                found.retain(|s| s.is_finite() && *s >= 0.0 && *s <= len);
                found.sort_by(f64::total_cmp);
            }
        }
        for s in found {
            let t = enter + s;
            if t > t_min && t < t_max && visit(t, o, d) {
                return;
            }
        }
    }

    /// Parameter interval inside both the bounding sphere and the slab `|z| <= r`.
    fn clip(&self, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<(f64, f64)> {
        let bound = self.major + self.minor;
        let b = o.dot(d);
        let perp = (o - b * d).length_squared();
        let disc = bound * bound - perp;
        if disc < 0.0 {
            return None;
        }
        let h = disc.sqrt();
        let (mut lo, mut hi) = ((-b - h).max(t_min), (-b + h).min(t_max));
        if d.z != 0.0 {
            let (a, c) = ((-self.minor - o.z) / d.z, (self.minor - o.z) / d.z);
            lo = lo.max(a.min(c));
            hi = hi.min(a.max(c));
        } else if o.z.abs() > self.minor {
            return None;
        }
        // Widen by a hair so roots on the clip boundary are not lost to rounding.
        let pad = 1e-9 * (hi - lo).abs().max(bound);
        (lo <= hi).then_some(((lo - pad).max(t_min), (hi + pad).min(t_max)))
    }

    /// Outward normal: gradient of `f`, `4 s p - 8 R^2 (x, y, 0)` with `s = |p|^2 + R^2 - r^2`.
    fn normal_at(&self, p: DVec3) -> DVec3 {
        let (big, small) = (self.major, self.minor);
        let s = p.length_squared() + big * big - small * small;
        let g = 4.0 * s * p - 8.0 * big * big * DVec3::new(p.x, p.y, 0.0);
        self.frame.to_world(g).normalize()
    }

    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let mut hit = None;
        self.roots(ray, t_min, t_max, &mut |t, o, d| {
            hit = Some(SurfaceHit {
                t,
                normal: self.normal_at(o + d * t),
            });
            true
        });
        hit
    }

    /// Closest hit computed with a chosen quartic solver (solver comparison and stress tests).
    pub fn intersect_with(&self, method: QuarticMethod, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let mut hit = None;
        self.roots_with(method, ray, t_min, t_max, &mut |t, o, d| {
            hit = Some(SurfaceHit {
                t,
                normal: self.normal_at(o + d * t),
            });
            true
        });
        hit
    }

    pub fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        let mut any = false;
        self.roots(ray, t_min, t_max, &mut |_, _, _| {
            any = true;
            true
        });
        any
    }

    /// Bound on the distance from `p` to the torus: the exact distance
    /// `| sqrt((rho - R)^2 + z^2) - r |` plus the distance-equivalent of the rounding of the
    /// quartic the intersection evaluates, `gamma(16) (k^2 + 4 R^2 rho^2) / |grad f|`, which
    /// grows like `R^2 / r` for thin tubes: a secondary ray must start farther out than the
    /// quartic's noise for its sign at the origin to be right.
    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        let l = self.frame.to_local(p - self.center);
        let (big, small) = (self.major, self.minor);
        let rho = l.truncate().length();
        let residual = ((rho - big).hypot(l.z) - small).abs();
        let k = l.length_squared() + big * big - small * small;
        let grad = (4.0 * k * l - 8.0 * big * big * DVec3::new(l.x, l.y, 0.0)).length();
        let noise = gamma(16) * (k * k + 4.0 * big * big * rho * rho) / grad.max(f64::MIN_POSITIVE);
        residual + noise.min(small) + gamma(16) * (l1(p) + l1(self.center) + big + small)
    }

    pub fn bounds(&self) -> Option<Aabb> {
        // The swept tube: the disk of radius R in the equatorial plane, thickened by r.
        let ring = super::Disk::new(self.center, self.axis, self.major).bounds()?;
        let r = DVec3::splat(self.minor);
        Some(Aabb::new(ring.min - r, ring.max + r))
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::*;
    use super::*;

    fn reference() -> Torus {
        // The reference torus: centre (4, 3, 2), R = 1.5, r = 0.5, axis +z.
        Torus::new(DVec3::new(4., 3., 2.), DVec3::Z, 1.5, 0.5)
    }

    #[test]
    fn from_outside_through_the_tube() {
        // Along +x through the centre plane: the outer wall at x = 4 - 2 = 2, from x = -6.
        let t = reference();
        assert_hit(t.intersect(&ray([-6., 3., 2.], [1., 0., 0.]), 0.0, 1e9), 8.0, -DVec3::X);
    }

    #[test]
    fn from_the_hole() {
        // Starting at the centre (in the hole), along +y: the inner wall at y = 3 + 1 = 4,
        // where the outward normal of the tube points back towards the axis (-y).
        let t = reference();
        assert_hit(t.intersect(&ray([4., 3., 2.], [0., 1., 0.]), 0.0, 1e9), 1.0, -DVec3::Y);
        // Straight down the axis through the hole: no hit.
        assert!(t.intersect(&ray([4., 3., 10.], [0., 0., -1.]), 0.0, 1e9).is_none());
    }

    #[test]
    fn from_inside_the_tube() {
        // Inside the tube at its centre circle (x = 5.5), going up: exits at z = 2.5.
        let t = reference();
        assert_hit(t.intersect(&ray([5.5, 3., 2.], [0., 0., 1.]), 0.0, 1e9), 0.5, DVec3::Z);
    }

    #[test]
    fn tangent_on_top() {
        // Along +x on the top z = 2.5: touches the tube tops at x = 2.5 and x = 5.5 (double
        // roots, t = 8.5 and 11.5); the polynomial is zero there only up to rounding, so
        // accept a hit at either tangent point or a miss, but never a hit elsewhere.
        let t = reference();
        if let Some(h) = t.intersect(&ray([-6., 3., 2.5], [1., 0., 0.]), 0.0, 1e9) {
            assert!((h.t - 8.5).abs() < 1e-4 || (h.t - 11.5).abs() < 1e-4, "{}", h.t);
        }
    }

    #[test]
    fn far_origin_equatorial_ray() {
        // From 1e6 away in the equatorial plane: the outer wall at distance 1e6 - 2.
        let t = Torus::new(DVec3::ZERO, DVec3::Z, 1.5, 0.5);
        let h = t.intersect(&ray([-1e6, 0., 0.], [1., 0., 0.]), 0.0, 1e99).unwrap();
        assert!((h.t - (1e6 - 2.0)).abs() <= 1e-9 * 1e6, "{}", h.t);
    }

    #[test]
    fn four_roots_along_a_diameter() {
        // Along x through the centre: walls at x = -2, -1, 1, 2; the second hit after
        // t_min just past the first is at -1.
        let t = Torus::new(DVec3::ZERO, DVec3::Z, 1.5, 0.5);
        let r = ray([-5., 0., 0.], [1., 0., 0.]);
        assert_hit(t.intersect(&r, 0.0, 1e9), 3.0, -DVec3::X);
        assert_hit(t.intersect(&r, 3.5, 1e9), 4.0, DVec3::X);
        assert_hit(t.intersect(&r, 4.5, 1e9), 6.0, -DVec3::X);
        assert_hit(t.intersect(&r, 6.5, 1e9), 7.0, DVec3::X);
    }

    #[test]
    fn ray_leaving_a_large_torus_does_not_hit_its_origin() {
        // R = 1e3, r = 250: points on the surface (computed in f64, so off it by rounding)
        // with rays leaving along the normal tilted in 8 ways, t_min = 0. The constant
        // coefficient is forced to zero there, so the only roots are real crossings at least
        // the tube's scale away, never a spurious one at t ~ 1e-13.
        let (big, small) = (1e3, 250.0);
        let t = Torus::new(DVec3::ZERO, DVec3::Z, big, small);
        for i in 0..16 {
            let (theta, phi) = (0.4 * i as f64, 0.9 * i as f64 + 0.1);
            let radial = DVec3::new(libm::cos(theta), libm::sin(theta), 0.0);
            let n = radial * libm::cos(phi) + DVec3::Z * libm::sin(phi);
            let p = radial * big + n * small;
            for k in 0..8 {
                let tilt = DVec3::new(libm::cos(k as f64), libm::sin(k as f64), 0.3).normalize();
                let d = (n + tilt * 0.9).normalize();
                if d.dot(n) <= 0.0 {
                    continue;
                }
                if let Some(h) = t.intersect(&Ray::new(p, d), 0.0, f64::INFINITY) {
                    assert!(h.t > 1.0, "spurious root at t = {} from {p} along {d}", h.t);
                }
            }
        }
    }
}
