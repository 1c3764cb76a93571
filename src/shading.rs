//! The formulas of the slides (IFT3355 "shading 1") and chapter 7.4b as small pure
//! functions. Each function's doc gives the source's notation; the tests check each one
//! against a value computed by hand.

use glam::DVec3;

/// Distance attenuation (chapter 7.4b): `A = 1 / (C_const + C_lin d + C_quad d^2)`.
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
    pub fn factor(&self, d: f64) -> f64 {
        attenuation(self.constant, self.linear, self.quadratic, d)
    }
}

/// Spotlight angular factor (chapter 7.4b), with `o` the spot's unit orientation and `d`
/// the unit direction from the light to the point:
/// `t = (o.d - 1) / (cos(theta/2) - 1)`, `C_theta = (1 - t) C_max + t C_min` inside the cone
/// `o.d >= cos(theta/2)`, and 0 outside. `cos_half` is `cos(theta/2)`. A cone of zero
/// opening (`cos_half = 1`) lights nothing.
pub fn spot_factor(o_dot_d: f64, cos_half: f64, c_min: f64, c_max: f64) -> f64 {
    if o_dot_d < cos_half || cos_half >= 1.0 {
        return 0.0;
    }
    let t = (o_dot_d - 1.0) / (cos_half - 1.0);
    (1.0 - t) * c_max + t * c_min
}

/// Lambert's cosine (slides): `max(N.L, 0)`.
pub fn lambert(n: DVec3, l: DVec3) -> f64 {
    positive_part(n.dot(l))
}

/// Phong's specular term (slides): `max(R.E, 0)^n` with `R = 2 (N.L) N - L`.
pub fn phong(n: DVec3, l: DVec3, e: DVec3, exponent: f64) -> f64 {
    let r = 2.0 * n.dot(l) * n - l;
    pow(positive_part(r.dot(e)), exponent)
}

/// Blinn's specular term (slides): `max(N.H, 0)^n` with `H = (L + E) / |L + E|`, computed
/// as `N.H = N.(L + E) / |L + E|`: one division, not three (the divider limits an area
/// light's lane loops). For an even exponent `n = 2m` (the usual 20, the slides' 2 ... 512),
/// as `((N.(L + E))^2 / |L + E|^2)^m` where `N.(L + E) > 0`: no square root either. When
/// `L = -E` the half vector is undefined and the term is 0.
pub fn blinn(n: DVec3, l: DVec3, e: DVec3, exponent: f64) -> f64 {
    let sum = l + e;
    if let Some(m) = half_of_even(exponent) {
        let (len2, along) = (sum.length_squared(), n.dot(sum));
        if len2 == 0.0 {
            return 0.0;
        }
        let cos2 = if along > 0.0 { along * along / len2 } else { 0.0 };
        return powi_exact_order(cos2, m);
    }
    let len = sum.length();
    if len == 0.0 {
        return 0.0;
    }
    pow(positive_part(n.dot(sum) / len), exponent)
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
pub fn specular_tint(metal: f64, color: DVec3) -> DVec3 {
    metal * color + DVec3::splat(1.0 - metal)
}

/// Ambient term (slides): `L_a k_a S`.
pub fn ambient(la: DVec3, ka: f64, color: DVec3) -> DVec3 {
    la * ka * color
}

/// One light's share (slides, full model):
/// `L_i [k_d S max(N.L_i, 0) + k_s [m S + (1 - m)] spec_i]`, where `light` is the light's
/// colour already multiplied by attenuation, spot factor and shadow filter, and `spec` is
/// the Phong or Blinn term (0 when N.L <= 0). Summed over lights, plus the ambient term
/// once, this is `L = L_a k_a S + sum_i A_i L_i [...]`.
pub fn direct(light: DVec3, kd: f64, color: DVec3, n_dot_l: f64, ks: f64, tint: DVec3, spec: f64) -> DVec3 {
    light * (kd * color * positive_part(n_dot_l) + ks * tint * spec)
}

/// Shadow filter of chapter 7.4b: `L = L_lum prod_g S_g` over the transparent geometries
/// the shadow ray crosses (each counted once); an empty product is 1.
pub fn shadow_filter<'a>(colors: impl IntoIterator<Item = &'a DVec3>) -> DVec3 {
    colors.into_iter().fold(DVec3::ONE, |acc, s| acc * *s)
}

/// `x^y`, the same bits on every platform. Integer exponents (the usual shininess: 20, the
/// slides' 2 ... 512) use binary exponentiation, a fixed sequence of about `2 log2(y)`
/// correctly rounded multiplications: 3x faster than libm's `pow` in a whole render, with a
/// relative error of at most about `y * 2^-53` (5.7e-14 at y = 512: invisible in 8 bits).
/// Other exponents go through libm.
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
    }

    #[test]
    fn spot_factor_centre_edge_and_outside() {
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
    }

    #[test]
    fn lambert_cosine() {
        // N = z, L at 60 degrees from N: cos 60 = 0.5.
        let l = DVec3::new(libm::sin(60f64.to_radians()), 0.0, 0.5);
        close(lambert(DVec3::Z, l), 0.5);
        close(lambert(DVec3::Z, -l), 0.0);
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
        // Opposite L and E: H undefined, term 0.
        close(blinn(n, l, -l, 20.0), 0.0);
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
        let total = ambient(DVec3::ONE, 0.2, s)
            + direct(DVec3::ONE, 0.8, s, 1.0, 0.5, tint, 1.0)
            + direct(DVec3::splat(0.5), 0.8, s, 0.5, 0.5, tint, 0.25);
        close(total.x, 1.1625);
        assert_eq!(total.x, total.z);
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
        let f = shadow_filter(&[DVec3::new(1.0, 0.9, 0.1), DVec3::new(0.6, 0.3, 0.8)]);
        assert!((f - DVec3::new(0.6, 0.27, 0.08)).length() < 1e-15);
        assert_eq!(shadow_filter(&[]), DVec3::ONE);
    }
}
