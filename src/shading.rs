//! The formulas of the slides (IFT3355 "shading 1") and chapter 7.4b as small pure
//! functions, each written once: the reference tracer, the fast tracer's vector lanes, the
//! one-pass families and the probe all call these. Each function's doc gives the source's
//! notation; the tests check each one against a value computed by hand.
//!
//! The colour terms are generic over [`Channels`]: a whole colour ([`DVec3`]) or one of its
//! channels (`f64`). Every channel is computed by the same IEEE operations in the same
//! order either way, so a lane loop over one channel of many light points gives the bits
//! of the colour formula applied point by point.

use crate::conventions::{LocalWeight, ShadowFilter, Transmission};
use crate::math::{length, mirror};
use glam::DVec3;
use std::ops::{Add, Mul};

/// A colour or one channel of a colour: what the colour terms are computed on.
pub trait Channels: Copy + Add<Output = Self> + Mul<Output = Self> + Mul<f64, Output = Self> {
    /// Every channel `x`.
    fn splat(x: f64) -> Self;
}

impl Channels for f64 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
}

impl Channels for DVec3 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        DVec3::splat(x)
    }
}

/// Distance attenuation (chapter 7.4b): `A = 1 / (C_const + C_lin d + C_quad d^2)`.
#[inline(always)]
pub fn attenuation(c_const: f64, c_lin: f64, c_quad: f64, d: f64) -> f64 {
    1.0 / (c_const + c_lin * d + c_quad * d * d)
}

/// Distance attenuation coefficients `C_const, C_lin, C_quad` (each >= 0, not all 0).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Attenuation {
    pub constant: f64,
    pub linear: f64,
    pub quadratic: f64,
}

impl Attenuation {
    /// No attenuation: `A = 1` everywhere.
    pub const NONE: Attenuation = Attenuation {
        constant: 1.0,
        linear: 0.0,
        quadratic: 0.0,
    };

    /// `A` at distance `d` ([`attenuation`]).
    #[inline(always)]
    pub fn factor(&self, d: f64) -> f64 {
        attenuation(self.constant, self.linear, self.quadratic, d)
    }

    /// The largest `A` at any distance: `1 / C_const`, its value at `d = 0` (the
    /// coefficients are not negative), unbounded (infinite) when `C_const = 0`.
    pub fn largest(&self) -> f64 {
        if self.constant > 0.0 {
            1.0 / self.constant
        } else {
            f64::INFINITY
        }
    }
}

/// Spotlight angular factor (chapter 7.4b), with `o` the spot's unit orientation and `d`
/// the unit direction from the light to the point:
/// `t = (o.d - 1) / (cos(theta/2) - 1)`, `C_theta = (1 - t) C_max + t C_min` inside the cone
/// `o.d >= cos(theta/2)`, and 0 outside. `cos_half` is `cos(theta/2)`. A cone of zero
/// opening (`cos_half = 1`) lights nothing.
pub fn spot_factor(o_dot_d: f64, cos_half: f64, c_min: f64, c_max: f64) -> f64 {
    if outside_spot_cone(o_dot_d, cos_half) {
        return 0.0;
    }
    let t = (o_dot_d - 1.0) / (cos_half - 1.0);
    (1.0 - t) * c_max + t * c_min
}

/// The largest [`spot_factor`] in the cone: `max(C_max, C_min)`, at the axis or at the
/// edge (the factor is linear in `t` between them).
#[inline]
pub fn largest_spot_factor(c_min: f64, c_max: f64) -> f64 {
    c_max.max(c_min)
}

/// Whether the unit direction `d` from a spotlight to a point is outside its cone
/// (chapter 7.4b): `o.d < cos(theta/2)`, from `o.d` and `cos(theta/2)`; a cone of zero
/// opening (`cos(theta/2) = 1`) holds no direction.
#[inline]
pub fn outside_spot_cone(o_dot_d: f64, cos_half: f64) -> bool {
    o_dot_d < cos_half || cos_half >= 1.0
}

/// Lambert's cosine (slides): `max(N.L, 0)`, from `N.L`.
#[inline(always)]
pub fn lambert(n_dot_l: f64) -> f64 {
    positive_part(n_dot_l)
}

/// Whether a surface faces away from a light, from `N.L`: `N.L <= 0`, where the slides
/// count neither the light's diffuse term nor its specular one (and cast no shadow ray).
#[inline(always)]
pub fn faces_away(n_dot_l: f64) -> bool {
    n_dot_l <= 0.0
}

/// Phong's specular term (slides): `max(R.E, 0)^n` with `R = 2 (N.L) N - L`.
pub fn phong(n: DVec3, l: DVec3, e: DVec3, exponent: f64) -> f64 {
    pow(phong_cosine(n, l, e, n.dot(l)), exponent)
}

/// Phong's cosine `max(R.E, 0)`, with `R = 2 (N.L) N - L` the law of reflection applied
/// to `-L` ([`mirror`]), from `N.L`.
#[inline(always)]
pub fn phong_cosine(n: DVec3, l: DVec3, e: DVec3, n_dot_l: f64) -> f64 {
    positive_part(mirror(-l, n, n_dot_l).dot(e))
}

/// Blinn's specular term (slides): `max(N.H, 0)^n` with `H = (L + E) / |L + E|`. When
/// `L = -E` the half vector is undefined and the term is 0. For an even exponent `n = 2m`
/// (the usual 20, the slides' 2 ... 512) it is `(cos^2)^m` ([`blinn_cosine_squared`]): no
/// square root; otherwise `max(N.H, 0)^n` ([`blinn_cosine`]).
pub fn blinn(n: DVec3, l: DVec3, e: DVec3, exponent: f64) -> f64 {
    let sum = l + e;
    if let Some(m) = half_of_even(exponent) {
        return powi_exact_order(blinn_cosine_squared(n, sum), m);
    }
    let spec = pow(blinn_cosine(n, sum), exponent);
    if half_vector_test_needed(exponent) {
        blinn_defined(sum, spec)
    } else {
        spec
    }
}

/// Blinn's cosine `N.H = N.(L + E) / |L + E|` (one division, not three), clamped to
/// `max(N.H, 0)`, and 0 when `|L + E| = 0`, from `sum = L + E`. Selects, not branches: the
/// area lights' lane loops compile to vector instructions only so.
#[inline(always)]
pub fn blinn_cosine(n: DVec3, sum: DVec3) -> f64 {
    let len = length(sum);
    let n_dot_h = n.dot(sum) / len;
    if (len != 0.0) & (n_dot_h > 0.0) { n_dot_h } else { 0.0 }
}

/// The square of Blinn's cosine, `(N.(L + E))^2 / |L + E|^2` where `N.(L + E) > 0`, else 0
/// (and 0 when `|L + E| = 0`), from `sum = L + E`: `max(N.H, 0)^2` without a square root.
#[inline(always)]
pub fn blinn_cosine_squared(n: DVec3, sum: DVec3) -> f64 {
    let (len2, along) = (sum.length_squared(), n.dot(sum));
    let cos2 = along * along / len2;
    if (len2 != 0.0) & (along > 0.0) { cos2 } else { 0.0 }
}

/// Blinn's term `spec` where the half vector exists, 0 where it does not (`L + E = 0`).
#[inline(always)]
pub fn blinn_defined(sum: DVec3, spec: f64) -> f64 {
    if length(sum) == 0.0 { 0.0 } else { spec }
}

/// Whether a power `exponent` of [`blinn_cosine`] needs [`blinn_defined`]: the cosine is
/// already 0 where the half vector is undefined, and so is its positive power; only an
/// exponent `<= 0` (`0^0 = 1`) or NaN can make it nonzero there.
#[inline(always)]
pub fn half_vector_test_needed(exponent: f64) -> bool {
    exponent <= 0.0 || exponent.is_nan()
}

/// `m` when `y = 2m` is an even integer exponent of 2 or more (Blinn's term then needs no
/// square root: see [`blinn`]).
pub fn half_of_even(y: f64) -> Option<u32> {
    integer_exponent(y).filter(|&n| n >= 2 && n % 2 == 0).map(|n| n / 2)
}

/// `max(x, 0)`, the clamp of every cosine of the shading formulas, with a NaN taken as 0:
/// written as a comparison and a select, which vectorizes where `f64::max` (with its NaN
/// rule) does not. Same value as `x.max(0.0)` for every `x` except `-0.0`, which gives
/// `+0.0` here; a zero's sign never reaches a pixel (it is multiplied, then added to a
/// non-negative sum).
#[inline(always)]
pub fn positive_part(x: f64) -> f64 {
    if x > 0.0 { x } else { 0.0 }
}

/// Specular colour factor of the slides' metal/plastic model: `m S + (1 - m)`.
#[inline(always)]
pub fn specular_tint<C: Channels>(metal: f64, color: C) -> C {
    color * metal + C::splat(1.0 - metal)
}

/// Ambient term (slides): `L_a k_a S`.
pub fn ambient(la: DVec3, ka: f64, color: DVec3) -> DVec3 {
    la * ka * color
}

/// The diffuse colour `S_d = k_d S` of a surface lit by no light: what SIMRenderer's
/// `reflexion_algorithm no_light` shows at a hit, in place of every local term.
pub fn no_light(kd: f64, color: DVec3) -> DVec3 {
    color * kd
}

/// One light's diffuse share (slides, Lambert): `L k_d S max(N.L, 0)`, where `L` is the
/// light arriving at the point (`A C_theta L_lum`, times the shadow filter).
#[inline(always)]
pub fn diffuse<C: Channels>(light: C, kd: f64, color: C, n_dot_l: f64) -> C {
    light * (color * kd * lambert(n_dot_l))
}

/// One light's specular share (slides): `L k_s [m S + (1 - m)] spec`, where `tint` is
/// [`specular_tint`] and `spec` the Phong or Blinn term (0 where `N.L <= 0`: the slides
/// count no highlight on a surface facing away). The full model sums, over lights, the
/// diffuse and specular shares, plus the ambient term once:
/// `L = L_a k_a S + sum_i A_i L_i [k_d S max(N.L_i, 0) + k_s [m S + (1 - m)] spec_i]`.
#[inline(always)]
pub fn specular<C: Channels>(light: C, ks: f64, tint: C, spec: f64) -> C {
    light * (tint * ks * spec)
}

/// The caustic share at a point of a diffuse surface: `E k_d S`, the diffuse term of the
/// slides with the light's `L max(N.L, 0)` replaced by the irradiance `E` the caustic
/// photons bring (their density already counts the cosine: a beam of cross-section `A` spreads
/// over `A / cos(theta)`).
pub fn caustic(irradiance: DVec3, kd: f64, color: DVec3) -> DVec3 {
    irradiance * (color * kd)
}

/// Shadow filter of chapter 7.4b: `L = L_lum prod_g S_g` over the transparent geometries
/// the shadow ray crosses (each counted once, in ascending object order so the bits do
/// not depend on the order they are found in); an empty product is 1.
pub fn shadow_filter(colors: impl IntoIterator<Item = DVec3>) -> DVec3 {
    colors.into_iter().fold(DVec3::ONE, filter_through)
}

/// One factor of [`shadow_filter`]'s product: the filter so far, through one more
/// transparent geometry of colour `S_g`.
#[inline(always)]
pub fn filter_through(filter: DVec3, s_g: DVec3) -> DVec3 {
    filter * s_g
}

/// The colour `S_g` a transparent geometry of colour `S` and transmission `k_t` filters a
/// shadow ray's light by: `S` (chapter 7.4b), or `k_t S` (SIMRenderer).
#[inline(always)]
pub fn transparent_filter(rule: ShadowFilter, kt: f64, s: DVec3) -> DVec3 {
    match rule {
        ShadowFilter::Color => s,
        ShadowFilter::KtColor => s * kt,
    }
}

/// What multiplies a refracted ray's radiance at a surface of colour `S` and transmission
/// `k_t`: `k_t` (chapter 7.4b), or `k_t S` where the ray enters and `k_t` where it leaves
/// (SIMRenderer).
pub fn transmission_weight(rule: Transmission, kt: f64, s: DVec3, entering: bool) -> DVec3 {
    match (rule, entering) {
        (Transmission::KtColorEntering, true) => s * kt,
        _ => DVec3::splat(kt),
    }
}

/// What weighs a hit's local illumination: 1 (chapter 7.4b, SIMRenderer), or
/// `1 - k_r - k_t`, what the reflected and refracted rays do not carry.
pub fn local_weight(rule: LocalWeight, kr: f64, kt: f64) -> f64 {
    match rule {
        LocalWeight::One => 1.0,
        LocalWeight::Remaining => 1.0 - kr - kt,
    }
}

/// Adaptive depth control: whether a secondary ray of path weight `weight` (the product of
/// the `k_r` and `k_t` along its path), whose radiance is at most `bound`, can add less
/// than `threshold` 8-bit levels to its pixel (`weight bound 255 < threshold`), so that it
/// is not traced. A threshold of 0 traces every ray.
#[inline(always)]
pub fn beneath_notice(weight: f64, bound: f64, threshold: f64) -> bool {
    threshold > 0.0 && weight * bound * 255.0 < threshold
}

/// `x^y`, the same bits on every platform. Integer exponents (the usual shininess: 20, the
/// slides' 2 ... 512) use binary exponentiation, a fixed sequence of about `2 log2(y)`
/// correctly rounded multiplications, cheaper than libm's `pow`, with a relative error of
/// at most about `y * 2^-53` (5.7e-14 at y = 512: invisible in 8 bits). Other exponents go
/// through libm.
pub fn pow(x: f64, y: f64) -> f64 {
    match integer_exponent(y) {
        Some(n) => powi_exact_order(x, n),
        None => libm::pow(x, y),
    }
}

/// `y` as a `u32` if it is one (a conversion and a comparison: `f64::fract` is a call to
/// libm's `trunc` on baseline x86-64, at every shading of every light).
#[inline(always)]
fn integer_exponent(y: f64) -> Option<u32> {
    (y >= 0.0 && y <= u32::MAX as f64 && (y as u32) as f64 == y).then_some(y as u32)
}

/// [`pow`] of every element of `xs` with the same exponent `y`, in place: the same
/// operations on each element as [`pow`], arranged so that the integer case (one squaring
/// chain shared by all elements) runs as vector instructions. Always inlined, so that it
/// takes the vector width of its caller's `multiversion` target.
#[inline(always)]
pub fn pow_each(xs: &mut [f64], y: f64) {
    if let Some(n) = integer_exponent(y) {
        for chunk in xs.chunks_mut(64) {
            // `powi_exact_order` with the loop over the bits of `n` outside the elements'.
            let mut acc = [1.0; 64];
            let acc = &mut acc[..chunk.len()];
            let mut n = n;
            while n > 0 {
                if n & 1 == 1 {
                    acc.iter_mut().zip(chunk.iter()).for_each(|(a, x)| *a *= x);
                }
                n >>= 1;
                if n > 0 {
                    chunk.iter_mut().for_each(|x| *x *= *x);
                }
            }
            chunk.copy_from_slice(acc);
        }
    } else {
        xs.iter_mut().for_each(|x| *x = libm::pow(*x, y));
    }
}

/// `pow(f(i), y)` into each `out[i]`: [`pow_each`] of the values `f(i)`. For the integer
/// exponents 1 to 16 the power is taken in the loop that computes `f(i)`, its
/// multiplications written out for that exponent (`powi_unrolled`): the values stay in
/// registers instead of going through memory once per bit of `y`. Always inlined, as
/// [`pow_each`].
#[inline(always)]
pub fn pow_each_of(out: &mut [f64], y: f64, f: impl Fn(usize) -> f64) {
    macro_rules! unrolled {
        ($($n:literal)*) => {
            match integer_exponent(y) {
                $(Some($n) => {
                    for (i, o) in out.iter_mut().enumerate() {
                        *o = powi_unrolled::<$n>(f(i));
                    }
                    return;
                })*
                _ => {}
            }
        };
    }
    unrolled!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16);
    for (i, o) in out.iter_mut().enumerate() {
        *o = f(i);
    }
    pow_each(out, y);
}

/// [`powi_exact_order`] for a constant exponent `N`: the same multiplications in the same
/// order, the loop over the bits of `N` unrolled by the compiler.
#[inline(always)]
fn powi_unrolled<const N: u32>(mut x: f64) -> f64 {
    let mut acc = 1.0;
    let mut bit = 0;
    while bit < u32::BITS && N >> bit > 0 {
        if (N >> bit) & 1 == 1 {
            acc *= x;
        }
        if N.checked_shr(bit + 1).unwrap_or(0) > 0 {
            x *= x;
        }
        bit += 1;
    }
    acc
}

/// `x^n` by squaring, from the lowest bit of `n` up.
fn powi_exact_order(mut x: f64, mut n: u32) -> f64 {
    let mut acc = 1.0;
    while n > 0 {
        if n & 1 == 1 {
            acc *= x;
        }
        n >>= 1;
        if n > 0 {
            x *= x;
        }
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) {
        assert!((a - b).abs() < 1e-12, "{a} vs {b}");
    }

    #[test]
    fn attenuation_of_the_chapter() {
        // C = (1, 0, 0.01), d = 10: A = 1 / (1 + 0.01 * 100) = 0.5 (not the chapter's 0.1).
        close(attenuation(1.0, 0.0, 0.01, 10.0), 0.5);
        // C = (1, 0.5, 0.25), d = 2: 1 / (1 + 1 + 1) = 1/3.
        close(attenuation(1.0, 0.5, 0.25, 2.0), 1.0 / 3.0);
        // No attenuation: A = 1 at any distance.
        close(attenuation(1.0, 0.0, 0.0, 1234.5), 1.0);
        // The largest A, at d = 0: 1 / C_const = 1 / 0.5 = 2; unbounded without C_const.
        let a = Attenuation {
            constant: 0.5,
            linear: 0.25,
            quadratic: 0.125,
        };
        assert_eq!(a.largest(), 2.0);
        assert_eq!(a.largest(), a.factor(0.0));
        let unbounded = Attenuation { constant: 0.0, ..a };
        assert_eq!(unbounded.largest(), f64::INFINITY);
    }

    #[test]
    fn spot_factor_center_edge_and_outside() {
        // theta = 120: cos 60 = 0.5. On the axis (o.d = 1): t = 0, C = C_max = 1.
        close(spot_factor(1.0, 0.5, 0.0, 1.0), 1.0);
        // o.d = 0.75: t = (0.75 - 1)/(0.5 - 1) = 0.5, C = 0.5 * 1 + 0.5 * 0 = 0.5.
        close(spot_factor(0.75, 0.5, 0.0, 1.0), 0.5);
        // With C_min = 0.2: C = 0.5 + 0.5 * 0.2 = 0.6.
        close(spot_factor(0.75, 0.5, 0.2, 1.0), 0.6);
        // At the edge o.d = cos(theta/2): t = 1, C = C_min.
        close(spot_factor(0.5, 0.5, 0.2, 1.0), 0.2);
        // Outside the cone: 0 whatever C_min.
        close(spot_factor(0.49, 0.5, 0.2, 1.0), 0.0);
        // Zero opening: dark even on the axis.
        close(spot_factor(1.0, 1.0, 0.0, 1.0), 0.0);
        // The cone itself: the edge is inside, below it outside, nothing in a zero opening.
        assert!(!outside_spot_cone(0.5, 0.5));
        assert!(outside_spot_cone(0.49, 0.5));
        assert!(outside_spot_cone(1.0, 1.0));
        // The largest factor: C_max on the axis, or C_min at the edge when it is larger.
        assert_eq!(largest_spot_factor(0.2, 1.0), 1.0);
        assert_eq!(largest_spot_factor(0.8, 0.5), 0.8);
    }

    #[test]
    fn no_light_is_the_diffuse_colour() {
        // k_d 0.8, S (0.5, 0.25, 1): S_d = (0.4, 0.2, 0.8), each an exact product.
        assert_eq!(no_light(0.8, DVec3::new(0.5, 0.25, 1.0)), DVec3::new(0.4, 0.2, 0.8));
        assert_eq!(no_light(0.0, DVec3::ONE), DVec3::ZERO);
    }

    #[test]
    fn lambert_cosine() {
        // N = z, L at 60 degrees from N: cos 60 = 0.5.
        let l = DVec3::new(libm::sin(60f64.to_radians()), 0.0, 0.5);
        close(lambert(DVec3::Z.dot(l)), 0.5);
        close(lambert(DVec3::Z.dot(-l)), 0.0);
    }

    #[test]
    fn phong_and_blinn_by_hand() {
        // N = z, L = (0.6, 0, 0.8), E = (0, 0.6, 0.8).
        // R = 2 * 0.8 * z - L = (-0.6, 0, 0.8); R.E = 0.64; 0.64^2 = 0.4096.
        let (n, l, e) = (DVec3::Z, DVec3::new(0.6, 0.0, 0.8), DVec3::new(0.0, 0.6, 0.8));
        close(phong(n, l, e, 2.0), 0.4096);
        // H = (0.6, 0.6, 1.6)/|.|, |.| = sqrt(0.36 + 0.36 + 2.56) = sqrt(3.28);
        // N.H = 1.6/sqrt(3.28) = 0.883452...; squared = 2.56/3.28 = 0.780487804878...
        close(blinn(n, l, e, 2.0), 2.56 / 3.28);
        // Mirror direction: R = E gives 1 for any exponent.
        close(phong(n, l, DVec3::new(-0.6, 0.0, 0.8), 512.0), 1.0);
        // Opposite L and E: H undefined, term 0, for an even, an odd and a zero exponent
        // (where a power of 0 would be 1).
        for exponent in [20.0, 21.0, 0.0] {
            assert_eq!(blinn(n, l, -l, exponent), 0.0, "{exponent}");
        }
        assert_eq!(blinn(n, l, e, 0.0), 1.0);
        // Phong's R is the law of reflection of the ray arriving along -L.
        let r = crate::math::reflect(-l, n);
        assert_eq!(r, DVec3::new(-0.6, 0.0, 0.8));
        assert_eq!(phong_cosine(n, l, e, n.dot(l)), r.dot(e));
    }

    #[test]
    fn even_blinn_exponents_skip_the_square_root_with_the_same_value() {
        assert_eq!(half_of_even(20.0), Some(10));
        assert_eq!(half_of_even(2.0), Some(1));
        assert_eq!(half_of_even(7.0), None);
        assert_eq!(half_of_even(0.0), None);
        assert_eq!(half_of_even(20.5), None);
        // Same hand case as above: (N.H)^20 = (2.56 / 3.28)^10 = 0.0838...; the
        // odd exponent 21 (the square-root route) divided by one N.H agrees within 1e-12.
        let (n, l, e) = (DVec3::Z, DVec3::new(0.6, 0.0, 0.8), DVec3::new(0.0, 0.6, 0.8));
        close(blinn(n, l, e, 20.0), libm::pow(2.56 / 3.28, 10.0));
        let odd = blinn(n, l, e, 21.0) / (1.6 / 3.28f64.sqrt());
        close(blinn(n, l, e, 20.0), odd);
        // Below the horizon of N (N.(L + E) < 0) the term is 0, as max(N.H, 0)^n.
        assert_eq!(
            blinn(n, DVec3::new(0.0, 0.0, -1.0), DVec3::new(0.6, 0.0, 0.0), 20.0),
            0.0
        );
    }

    #[test]
    fn metal_and_plastic_tint() {
        let s = DVec3::new(1.0, 0.5, 0.0);
        // Plastic (m = 0): the light's colour, (1, 1, 1).
        assert_eq!(specular_tint(0.0, s), DVec3::ONE);
        // Metal (m = 1): the surface colour.
        assert_eq!(specular_tint(1.0, s), s);
        // m = 0.5: 0.5 S + 0.5 = (1, 0.75, 0.5).
        assert_eq!(specular_tint(0.5, s), DVec3::new(1.0, 0.75, 0.5));
    }

    #[test]
    fn multi_light_sum_counts_ambient_once() {
        // S = (0.5, 0.5, 0.5), ka 0.2, kd 0.8, ks 0.5, plastic, La = 1.
        // Light 1: L = 1, N.L = 1, spec 1  -> 0.8 * 0.5 * 1 + 0.5 * 1 * 1 = 0.9.
        // Light 2: L = 0.5, N.L = 0.5, spec 0.25 -> 0.5 * (0.8 * 0.5 * 0.5 + 0.5 * 0.25) = 0.1625.
        // Ambient once: 1 * 0.2 * 0.5 = 0.1. Total 0.1 + 0.9 + 0.1625 = 1.1625 (above 1:
        // clamped only at output).
        let s = DVec3::splat(0.5);
        let tint = specular_tint(0.0, s);
        let share =
            |light: DVec3, n_dot_l: f64, spec: f64| diffuse(light, 0.8, s, n_dot_l) + specular(light, 0.5, tint, spec);
        let total = ambient(DVec3::ONE, 0.2, s) + share(DVec3::ONE, 1.0, 1.0) + share(DVec3::splat(0.5), 0.5, 0.25);
        close(total.x, 1.1625);
        assert_eq!(total.x, total.z);
        // A surface facing away gets no diffuse share: max(N.L, 0) = 0.
        assert_eq!(diffuse(DVec3::ONE, 0.8, s, -0.3), DVec3::ZERO);
    }

    #[test]
    fn colour_terms_channel_by_channel_are_the_colour_terms() {
        // The lane loops compute one channel at a time: the same bits as the colour.
        let (light, s, m) = (DVec3::new(0.3, 0.7, 0.11), DVec3::new(0.85, 0.5, 0.2), 0.35);
        let tint = specular_tint(m, s);
        let (d, sp) = (diffuse(light, 0.8, s, 0.61), specular(light, 0.5, tint, 0.123));
        for c in 0..3 {
            assert_eq!(specular_tint(m, s[c]), tint[c]);
            assert_eq!(diffuse(light[c], 0.8, s[c], 0.61), d[c]);
            assert_eq!(specular(light[c], 0.5, tint[c], 0.123), sp[c]);
        }
        // By hand, channel 0: 0.3 * 0.85 * 0.8 * 0.61 = 0.124440; tint 0.35 * 0.85 + 0.65 =
        // 0.9475, specular 0.3 * 0.9475 * 0.5 * 0.123 = 0.017481375.
        close(d.x, 0.124_44);
        close(sp.x, 0.017_481_375);
    }

    #[test]
    fn conventions_of_filters_and_weights() {
        let s = DVec3::new(1.0, 0.5, 0.25);
        // SIMRenderer filters by kt S: kt = 0.8 gives (0.8, 0.4, 0.2); the chapter by S.
        assert_eq!(
            transparent_filter(ShadowFilter::KtColor, 0.8, s),
            DVec3::new(0.8, 0.4, 0.2)
        );
        assert_eq!(transparent_filter(ShadowFilter::Color, 0.8, s), s);
        // A refracted ray: kt S entering, kt leaving (a crossed sphere weighs kt^2 S).
        let enter = transmission_weight(Transmission::KtColorEntering, 0.5, s, true);
        let leave = transmission_weight(Transmission::KtColorEntering, 0.5, s, false);
        assert_eq!(enter * leave, DVec3::new(0.25, 0.125, 0.0625));
        assert_eq!(transmission_weight(Transmission::Kt, 0.5, s, true), DVec3::splat(0.5));
        assert_eq!(local_weight(LocalWeight::Remaining, 0.25, 0.5), 0.25);
        assert_eq!(local_weight(LocalWeight::One, 0.25, 0.5), 1.0);
    }

    #[test]
    fn adaptive_depth_control_threshold() {
        // weight 0.01, bound 0.3: at most 0.01 * 0.3 * 255 = 0.765 levels.
        assert!(beneath_notice(0.01, 0.3, 1.0));
        assert!(!beneath_notice(0.01, 0.3, 0.5));
        // Threshold 0 traces everything, even a zero weight.
        assert!(!beneath_notice(0.0, 0.3, 0.0));
    }

    /// [`pow_each_of`] gives the bits of [`pow`] for every integer exponent it unrolls
    /// (1 to 16), those around them (0, 17, 20, 512) and non-integer ones, on values in
    /// [0, 1] (as cosines are), above 1, and 0.
    #[test]
    fn pow_each_of_is_pow_bit_for_bit() {
        let xs: Vec<f64> = (0..45)
            .map(|i| [i as f64 / 36.0, 1.0 + i as f64 / 7.0][i % 2])
            .collect();
        let exponents = (0..=17).map(f64::from).chain([20.0, 512.0, 7.5, 0.25]);
        for y in exponents {
            let want: Vec<u64> = xs.iter().map(|&x| pow(x, y).to_bits()).collect();
            let mut out = vec![f64::NAN; xs.len()];
            pow_each_of(&mut out, y, |i| xs[i]);
            assert_eq!(out.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), want, "y = {y}");
        }
        // By hand: 0.5^10 = 2^-10, 3^5 = 243 exactly.
        let mut out = [0.0; 2];
        pow_each_of(&mut out, 10.0, |_| 0.5);
        assert_eq!(out, [1.0 / 1024.0; 2]);
        pow_each_of(&mut out, 5.0, |_| 3.0);
        assert_eq!(out, [243.0; 2]);
    }

    #[test]
    fn pow_each_is_pow_bit_for_bit() {
        for y in [0.0, 1.0, 2.0, 20.0, 512.0, 7.5] {
            let mut xs: Vec<f64> = (0..37).map(|i| i as f64 / 36.0).collect();
            let want: Vec<f64> = xs.iter().map(|&x| pow(x, y)).collect();
            pow_each(&mut xs, y);
            assert_eq!(xs, want, "y = {y}");
        }
    }

    #[test]
    fn integer_powers_by_squaring() {
        // 0.5^20 = 2^-20 exactly; 0.9^2 = 0.81 (one rounding, as x * x).
        assert_eq!(pow(0.5, 20.0), 1.0 / 1_048_576.0);
        assert_eq!(pow(0.9, 2.0), 0.9 * 0.9);
        assert_eq!(pow(0.7, 0.0), 1.0);
        assert_eq!(pow(0.0, 512.0), 0.0);
        // Within n * 2^-53 (relative) of libm for every exponent of the slides' sweep.
        for n in [2.0, 4.0, 8.0, 16.0, 20.0, 32.0, 64.0, 128.0, 256.0, 512.0] {
            for x in [0.999, 0.95, 0.8, 0.3] {
                let (a, b) = (pow(x, n), libm::pow(x, n));
                assert!((a - b).abs() <= n * f64::EPSILON * 0.5 * b, "{x}^{n}: {a} vs {b}");
            }
        }
        // Non-integer exponents use libm.
        assert_eq!(pow(0.8, 2.5), libm::pow(0.8, 2.5));
    }

    #[test]
    fn filtered_shadow_product() {
        // Yellow (1, 0.9, 0.1) then mauve (0.6, 0.3, 0.8): (0.6, 0.27, 0.08).
        let (yellow, mauve) = (DVec3::new(1.0, 0.9, 0.1), DVec3::new(0.6, 0.3, 0.8));
        let f = shadow_filter([yellow, mauve]);
        assert!((f - DVec3::new(0.6, 0.27, 0.08)).length() < 1e-15);
        assert_eq!(f, filter_through(filter_through(DVec3::ONE, yellow), mauve));
        assert_eq!(shadow_filter([]), DVec3::ONE);
    }
}
