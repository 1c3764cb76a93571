//! Rays, orthonormal frames, the chapter's reflection and refraction laws, the
//! floating-point-aware offset that keeps secondary rays off the surface they leave, and the
//! few identities of plane geometry the shapes and lights share.

use glam::{DMat3, DVec3};

/// A ray `r(t) = origin + t * dir` (chapter 7.4b: `r = r0 + v t`). `dir` is unit length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: DVec3,
    pub dir: DVec3,
}

impl Ray {
    /// A ray from `origin` along `dir`; `dir` must already be unit length.
    pub fn new(origin: DVec3, dir: DVec3) -> Self {
        Ray { origin, dir }
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + self.dir * t
    }

    /// A ray leaving a surface point `p` (outward normal `n`, absolute error bound `err`)
    /// along the unit `dir`: from `p` pushed past its rounding error to the side `dir` goes
    /// ([`offset_origin`]), so that it never meets the surface it leaves at its start.
    #[inline]
    pub fn leaving(p: DVec3, n: DVec3, err: f64, dir: DVec3) -> Self {
        Ray::new(offset_origin(p, n, err, dir), dir)
    }
}

/// How a ray along `dir` meets a surface of outward normal `outward`: whether it enters
/// (arrives against the normal, `dir.N < 0`), and the normal on the ray's side, `N` when it
/// enters and `-N` when it leaves (the `N` of the laws of reflection and refraction).
#[inline]
pub fn facing_normal(dir: DVec3, outward: DVec3) -> (bool, DVec3) {
    let entering = dir.dot(outward) < 0.0;
    (entering, if entering { outward } else { -outward })
}

/// An orthonormal frame whose third axis is a given unit vector; maps between world space
/// and the canonical space in which shapes with an axis (disk, cylinder, cone, torus) are
/// intersected with their axis along +z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Rows are the local x, y, z axes expressed in world coordinates.
    to_local: DMat3,
}

impl Frame {
    /// A frame with `z` (unit) as its third axis. Uses the branch-free construction of
    /// Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT 2017).
    pub fn from_z(z: DVec3) -> Self {
        let sign = if z.z >= 0.0 { 1.0 } else { -1.0 };
        let a = -1.0 / (sign + z.z);
        let b = z.x * z.y * a;
        let x = DVec3::new(1.0 + sign * z.x * z.x * a, sign * b, -sign * z.x);
        let y = DVec3::new(b, sign + z.y * z.y * a, -z.y);
        Frame::from_axes(x, y, z)
    }

    /// A frame from three orthonormal world-space axes.
    pub fn from_axes(x: DVec3, y: DVec3, z: DVec3) -> Self {
        Frame {
            to_local: DMat3::from_cols(x, y, z).transpose(),
        }
    }

    /// World vector to local coordinates.
    pub fn to_local(&self, v: DVec3) -> DVec3 {
        self.to_local * v
    }

    /// Local vector to world coordinates.
    pub fn to_world(&self, v: DVec3) -> DVec3 {
        self.to_local.transpose() * v
    }
}

/// Law of reflection (chapter 7.4b): `R = v + 2 (E.N) N` with `E = -v`.
/// `v` is the incident direction, `n` the unit normal on the incident side (`E.N >= 0`).
pub fn reflect(v: DVec3, n: DVec3) -> DVec3 {
    let e = -v;
    mirror(v, n, e.dot(n))
}

/// [`reflect`] with `E.N` already known: `R = v + 2 (E.N) N`. Phong's `R = 2 (N.L) N - L`
/// is this law for `v = -L` (see [`crate::shading::phong_cosine`]).
#[inline(always)]
pub fn mirror(v: DVec3, n: DVec3, e_dot_n: f64) -> DVec3 {
    v + 2.0 * e_dot_n * n
}

/// Law of refraction (chapter 7.4b):
/// `T = n v + (n (E.N) - sqrt(1 - n^2 (1 - (E.N)^2))) N`, `E = -v`, `n = n1 / n2`,
/// with `N` on the incident side. `None` on total internal reflection
/// ([`total_internal_reflection`]).
pub fn refract(v: DVec3, n_normal: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = (-v).dot(n_normal);
    if total_internal_reflection(eta, cos_i) {
        return None;
    }
    Some(eta * v + (eta * cos_i - refraction_radicand(eta, cos_i).sqrt()) * n_normal)
}

/// The root's argument of the law of refraction, `1 - n^2 (1 - (E.N)^2)`.
pub fn refraction_radicand(eta: f64, e_dot_n: f64) -> f64 {
    1.0 - eta * eta * (1.0 - e_dot_n * e_dot_n)
}

/// Criterion of total internal reflection (chapter 7.4b): the refracted ray does not exist
/// when the law of refraction's root has a negative argument, `1 - n^2 (1 - (E.N)^2) < 0`,
/// that is `(v.N)^2 + (n2 / n1)^2 < 1`. At equality (the critical angle itself) the ray is
/// refracted, grazing the surface. `eta` is `n = n1 / n2`, `e_dot_n` is `E.N`.
pub fn total_internal_reflection(eta: f64, e_dot_n: f64) -> bool {
    refraction_radicand(eta, e_dot_n) < 0.0
}

/// The length `|v| = sqrt(v.v)`, as `DVec3::length` computes it (the same correctly rounded
/// square root), through the square-root instruction rather than glam's `libm` call: a
/// loop over many vectors then compiles to vector instructions.
#[inline(always)]
pub fn length(v: DVec3) -> f64 {
    v.dot(v).sqrt()
}

/// `sqrt(max(1 - x^2, 0))`: the other leg of a right triangle of hypotenuse 1 and leg `x`,
/// the sine of an angle in `[0, pi]` from its cosine (or the cosine of one in
/// `[-pi/2, pi/2]` from its sine); 0 where rounding puts `|x|` above 1.
#[inline]
pub fn other_leg(x: f64) -> f64 {
    (1.0 - x * x).max(0.0).sqrt()
}

/// Half the longer diagonal of the parallelogram of edges `a` and `b`,
/// `max(|a + b|, |a - b|) / 2`: the radius of the ball about its centre that holds it.
pub fn half_diagonal(a: DVec3, b: DVec3) -> f64 {
    0.5 * (a + b).length().max((a - b).length())
}

/// Largest absolute component.
pub fn max_abs(v: DVec3) -> f64 {
    v.abs().max_element()
}

/// Bound on the rounding error of forming the hit point `origin + t dir` in f64: each
/// component is one product and one sum, `gamma(2) (|o| + |t d|)`, taken as `gamma(4)` of
/// the largest components for margin (pbrt-v4, section 6.8.1). The error of `t` itself
/// (how far the exact point `o + t d` is from the surface) is the shape's part, bounded by
/// [`crate::shape::Shape::surface_error`]; the tracer offsets secondary rays by the sum.
pub fn hit_point_error(ray: &Ray, t: f64) -> f64 {
    let u = f64::EPSILON * 0.5;
    let gamma4 = 4.0 * u / (1.0 - 4.0 * u);
    gamma4 * (max_abs(ray.origin) + max_abs(ray.dir * t)) + f64::MIN_POSITIVE
}

/// Origin for a ray leaving a surface at `p` (absolute error bound `err`) in direction `dir`:
/// pushed along the normal, to the side `dir` goes, by the error bound projected on the
/// normal, so the new ray can never re-hit the surface it left (pbrt-v4, section 6.8.6).
pub fn offset_origin(p: DVec3, n: DVec3, err: f64, dir: DVec3) -> DVec3 {
    let d = err * n.abs().element_sum();
    let offset = if dir.dot(n) >= 0.0 { n * d } else { -n * d };
    p + offset
}

/// True when every component is finite.
pub fn is_finite3(v: DVec3) -> bool {
    v.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn reflection_mirrors_the_normal_component() {
        // v = (1, -1, 0)/sqrt2 onto N = +y: E.N = 1/sqrt2, R = v + 2 (1/sqrt2) y = (1, 1, 0)/sqrt2.
        let s = 0.5f64.sqrt();
        let r = reflect(DVec3::new(s, -s, 0.0), DVec3::Y);
        assert!(close(r, DVec3::new(s, s, 0.0)), "{r}");
    }

    #[test]
    fn refraction_obeys_snell() {
        // 45 degrees from air into n2 = 1.5: sin t = sin 45 / 1.5 = 0.471404520791...
        let s = 0.5f64.sqrt();
        let t = refract(DVec3::new(s, -s, 0.0), DVec3::Y, 1.0 / 1.5).unwrap();
        assert!((t.length() - 1.0).abs() < 1e-15);
        assert!((t.x - 0.471_404_520_791_031_7).abs() < 1e-15, "{}", t.x);
        assert!(t.y < 0.0);
    }

    #[test]
    fn total_internal_reflection_at_the_critical_angle() {
        // n = 1.66 to air: critical angle asin(1/1.66) = 37.0427 degrees (the prism figures: 37.04).
        let crit = libm::asin(1.0 / 1.66);
        assert!((crit.to_degrees() - 37.042_671).abs() < 1e-6);
        let dir = |deg: f64| {
            let a = deg.to_radians();
            DVec3::new(libm::sin(a), -libm::cos(a), 0.0)
        };
        let below = crit.to_degrees() - 1.0;
        let above = crit.to_degrees() + 1.0;
        assert!(refract(dir(below), DVec3::Y, 1.66).is_some());
        assert!(refract(dir(above), DVec3::Y, 1.66).is_none());
        // The chapter's form of the criterion, (v.N)^2 + (n2 / n1)^2 < 1, on both sides.
        for (deg, tir) in [(below, false), (above, true)] {
            let v_dot_n = dir(deg).dot(DVec3::Y);
            assert_eq!(v_dot_n * v_dot_n + (1.0 / 1.66f64).powi(2) < 1.0, tir);
            assert_eq!(total_internal_reflection(1.66, -v_dot_n), tir, "{deg}");
        }
    }

    #[test]
    fn a_ray_enters_against_the_outward_normal_and_is_given_the_normal_on_its_side() {
        let down = DVec3::new(0.6, 0.0, -0.8);
        assert_eq!(facing_normal(down, DVec3::Z), (true, DVec3::Z));
        assert_eq!(facing_normal(-down, DVec3::Z), (false, -DVec3::Z));
        // Grazing (dir.N = 0): not entering.
        assert_eq!(facing_normal(DVec3::X, DVec3::Z), (false, -DVec3::Z));
    }

    #[test]
    fn other_legs_and_half_diagonals() {
        // cos = 0.6: sin = sqrt(1 - 0.36) = 0.8 (to one rounding); |c| a hair above 1: 0.
        assert!((other_leg(0.6) - 0.8).abs() < 1e-15);
        assert_eq!(other_leg(1.0), 0.0);
        assert_eq!(other_leg(1.0 + f64::EPSILON), 0.0);
        // A 6 x 8 rectangle: diagonal 10, half 5; a parallelogram (3, 0) and (1, 1): the
        // longer diagonal (4, 1) of length sqrt(17).
        assert_eq!(half_diagonal(DVec3::new(6.0, 0.0, 0.0), DVec3::new(0.0, 8.0, 0.0)), 5.0);
        assert_eq!(
            half_diagonal(DVec3::new(3.0, 0.0, 0.0), DVec3::new(1.0, 1.0, 0.0)),
            0.5 * 17f64.sqrt()
        );
    }

    #[test]
    fn frame_is_orthonormal_and_round_trips() {
        for z in [DVec3::Z, -DVec3::Z, DVec3::new(1.0, 2.0, -3.0).normalize()] {
            let f = Frame::from_z(z);
            assert!(close(f.to_local(z), DVec3::Z));
            let v = DVec3::new(0.3, -1.2, 2.5);
            assert!(close(f.to_world(f.to_local(v)), v));
        }
    }

    #[test]
    fn offset_goes_to_the_side_of_the_new_direction() {
        let p = DVec3::new(0.0, 0.0, 1.0);
        let up = offset_origin(p, DVec3::Z, 1e-9, DVec3::new(0.0, 1.0, 0.5));
        let down = offset_origin(p, DVec3::Z, 1e-9, DVec3::new(0.0, 1.0, -0.5));
        assert!(up.z > 1.0 && down.z < 1.0);
        // A ray leaving along the offset's side: its origin is `offset_origin`'s, pushed by
        // err |n|_1 = 1e-9 along +z.
        let ray = Ray::leaving(p, DVec3::Z, 1e-9, DVec3::Z);
        assert_eq!((ray.origin, ray.dir), (up, DVec3::Z));
        assert_eq!(ray.origin, DVec3::new(0.0, 0.0, 1.0 + 1e-9));
    }
}
