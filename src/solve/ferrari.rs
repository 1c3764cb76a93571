//! The closed-form quartic of Ferrari (1540), in the textbook form: depress the quartic,
//! take a real root of the resolvent cubic by Cardano's / Viète's formulas, and split the
//! depressed quartic into two quadratics. Kept for the solver comparison (BENCHMARKS.md,
//! `benches/solvers.rs`): it is fast but loses digits to cancellation on badly scaled
//! coefficients, which is why the torus does not use it.

use super::quadratic;

/// Real roots of the monic cubic `x^3 + a x^2 + b x + c` (unsorted): Cardano's formula when
/// the discriminant is positive (one real root), Viète's trigonometric form otherwise.
pub fn cubic_roots(a: f64, b: f64, c: f64) -> Vec<f64> {
    // x = y - a/3 gives y^3 + p y + q.
    let shift = a / 3.0;
    let p = b - a * shift;
    let q = 2.0 * shift * shift * shift - b * shift + c;
    let half_q = 0.5 * q;
    let third_p = p / 3.0;
    let disc = half_q * half_q + third_p * third_p * third_p;
    if disc > 0.0 {
        let s = disc.sqrt();
        // Cancellation-free: take the larger cube root, get the other from u v = -p/3.
        let u = libm::cbrt(-half_q - half_q.signum() * s);
        let v = if u != 0.0 { -third_p / u } else { 0.0 };
        vec![u + v - shift]
    } else if third_p == 0.0 {
        vec![-shift]
    } else {
        let m = 2.0 * (-third_p).sqrt();
        let arg = (3.0 * q / (p * m)).clamp(-1.0, 1.0);
        let theta = libm::acos(arg) / 3.0;
        let third_turn = 2.0 * std::f64::consts::PI / 3.0;
        (0..3)
            .map(|k| m * libm::cos(theta - third_turn * k as f64) - shift)
            .collect()
    }
}

/// Real roots of `c[4] t^4 + c[3] t^3 + c[2] t^2 + c[1] t + c[0]` (unsorted), Ferrari's way.
pub fn quartic_roots(c: &[f64; 5], out: &mut Vec<f64>) {
    let (a, b, cc, d) = (c[3] / c[4], c[2] / c[4], c[1] / c[4], c[0] / c[4]);
    // x = y - a/4: y^4 + p y^2 + q y + r.
    let s = a / 4.0;
    let p = b - 6.0 * s * s;
    let q = cc - 2.0 * b * s + 8.0 * s * s * s;
    let r = d - cc * s + b * s * s - 3.0 * s * s * s * s;
    // y^4 + p y^2 + q y + r = (y^2 + p/2 + m)^2 - (2m y^2 - q y + m^2 + m p + p^2/4 - r);
    // the bracket is a square when 8 m^3 + 8 p m^2 + (2 p^2 - 8 r) m - q^2 = 0.
    let m = cubic_roots(p, 0.25 * p * p - r, -0.125 * q * q)
        .into_iter()
        .fold(f64::NEG_INFINITY, f64::max);
    if m <= 0.0 {
        // q = 0 (biquadratic): y^2 = (-p +- sqrt(p^2 - 4r)) / 2.
        if let Some((u0, u1)) = quadratic(1.0, p, r) {
            for u in [u0, u1] {
                if u >= 0.0 {
                    out.extend([u.sqrt() - s, -u.sqrt() - s]);
                }
            }
        }
        return;
    }
    let w = (2.0 * m).sqrt();
    let k = q / (2.0 * w);
    // (y^2 + p/2 + m) = +-(w y - k).
    for (lin, cst) in [(-w, 0.5 * p + m + k), (w, 0.5 * p + m - k)] {
        if let Some((y0, y1)) = quadratic(1.0, lin, cst) {
            out.extend([y0 - s, y1 - s]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_with_three_and_one_real_roots() {
        // (x-1)(x-2)(x-3) = x^3 - 6x^2 + 11x - 6.
        let mut r = cubic_roots(-6.0, 11.0, -6.0);
        r.sort_by(f64::total_cmp);
        for (g, w) in r.iter().zip([1.0, 2.0, 3.0]) {
            assert!((g - w).abs() < 1e-12, "{r:?}");
        }
        // (x-2)(x^2+1) = x^3 - 2x^2 + x - 2: the single real root 2.
        let r = cubic_roots(-2.0, 1.0, -2.0);
        assert_eq!(r.len(), 1);
        assert!((r[0] - 2.0).abs() < 1e-12);
    }

    #[test]
    fn quartic_with_four_known_roots() {
        // (t-1)(t-2)(t-3)(t-4) = t^4 - 10 t^3 + 35 t^2 - 50 t + 24.
        let mut r = Vec::new();
        quartic_roots(&[24.0, -50.0, 35.0, -10.0, 1.0], &mut r);
        r.sort_by(f64::total_cmp);
        assert_eq!(r.len(), 4, "{r:?}");
        for (g, w) in r.iter().zip([1.0, 2.0, 3.0, 4.0]) {
            assert!((g - w).abs() < 1e-9, "{r:?}");
        }
    }
}
