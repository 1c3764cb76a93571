//! The quartic solver of Orellana and De Michele, "Algorithm 1010: Boosting Efficiency in
//! Solving Quartic Equations with No Compromise in Accuracy" (ACM TOMS 46(2), 2020), written
//! from the paper's description (no code copied). The monic quartic
//! `x^4 + a x^3 + b x^2 + c x + d` is factored into two real quadratics
//! `(x^2 + alpha1 x + beta1)(x^2 + alpha2 x + beta2)` through an LDL^T decomposition:
//!
//! 1. `phi0`, the largest root of the resolvent cubic
//!    `phi^3 - b phi^2 + (a c - 4 d) phi - (c^2 + a^2 d - 4 b d) = 0`, by a closed form then
//!    Newton's method (it makes `d2 = a^2/4 - b + phi0 >= 0`);
//! 2. `x^4 + ... = (x^2 + a x / 2 + phi0 / 2)^2 - d2 (x + l)^2`, where `l` has two
//!    algebraically equal expressions; both candidates are tried;
//! 3. the factors' coefficients are refined by Newton's method on the four equations
//!    `alpha1 + alpha2 = a`, `beta1 + beta2 + alpha1 alpha2 = b`,
//!    `alpha1 beta2 + alpha2 beta1 = c`, `beta1 beta2 = d` while the relative backward error
//!    decreases, and the candidate with the smaller backward error is kept (a third
//!    candidate, `d2 = 0`, covers quartics that are squares of a quadratic);
//! 4. each quadratic is solved without cancellation.

use super::ferrari::cubic_roots;
use super::quadratic;

/// Relative backward error of the factorisation and the residuals `F(alpha, beta)`.
fn residuals(f: &[f64; 4], coef: &[f64; 4]) -> ([f64; 4], f64) {
    let [a1, b1, a2, b2] = *f;
    let r = [
        a1 + a2 - coef[0],
        b1 + b2 + a1 * a2 - coef[1],
        a1 * b2 + a2 * b1 - coef[2],
        b1 * b2 - coef[3],
    ];
    let err = r
        .iter()
        .zip(coef)
        .map(|(ri, ci)| if *ci != 0.0 { (ri / ci).abs() } else { ri.abs() })
        .sum();
    (r, err)
}

/// Solves the 4x4 system `m x = rhs` by Gaussian elimination with partial pivoting.
fn solve4(mut m: [[f64; 4]; 4], mut rhs: [f64; 4]) -> Option<[f64; 4]> {
    for col in 0..4 {
        let pivot = (col..4).max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))?;
        if m[pivot][col] == 0.0 {
            return None;
        }
        m.swap(col, pivot);
        rhs.swap(col, pivot);
        for row in col + 1..4 {
            let k = m[row][col] / m[col][col];
            let pivot_row = m[col];
            for (x, p) in m[row][col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= k * p;
            }
            rhs[row] -= k * rhs[col];
        }
    }
    let mut x = [0.0; 4];
    for row in (0..4).rev() {
        let s: f64 = (row + 1..4).map(|j| m[row][j] * x[j]).sum();
        x[row] = (rhs[row] - s) / m[row][row];
    }
    Some(x)
}

/// Newton refinement of `(alpha1, beta1, alpha2, beta2)`; returns the refined factors and
/// their backward error.
fn refine(mut f: [f64; 4], coef: &[f64; 4]) -> ([f64; 4], f64) {
    let (mut r, mut err) = residuals(&f, coef);
    for _ in 0..8 {
        if err == 0.0 {
            break;
        }
        let [a1, b1, a2, b2] = f;
        // Jacobian of the residuals with respect to (alpha1, beta1, alpha2, beta2).
        let jac = [
            [1.0, 0.0, 1.0, 0.0],
            [a2, 1.0, a1, 1.0],
            [b2, a2, b1, a1],
            [0.0, b2, 0.0, b1],
        ];
        let Some(step) = solve4(jac, [-r[0], -r[1], -r[2], -r[3]]) else {
            break;
        };
        let next = [a1 + step[0], b1 + step[1], a2 + step[2], b2 + step[3]];
        let (nr, nerr) = residuals(&next, coef);
        if nerr.partial_cmp(&err) != Some(std::cmp::Ordering::Less) {
            break;
        }
        (f, r, err) = (next, nr, nerr);
    }
    (f, err)
}

/// Real roots of `c[4] t^4 + ... + c[0]` (unsorted), by the LDL^T factorisation above.
pub fn quartic_roots(c: &[f64; 5], out: &mut Vec<f64>) {
    let (a, b, cc, d) = (c[3] / c[4], c[2] / c[4], c[1] / c[4], c[0] / c[4]);
    let coef = [a, b, cc, d];
    // 1. phi0: largest resolvent root, polished by Newton while the residual drops.
    let res = |p: f64| ((p - b) * p + (a * cc - 4.0 * d)) * p - (cc * cc + a * a * d - 4.0 * b * d);
    let dres = |p: f64| (3.0 * p - 2.0 * b) * p + (a * cc - 4.0 * d);
    let mut phi0 = cubic_roots(-b, a * cc - 4.0 * d, -(cc * cc + a * a * d - 4.0 * b * d))
        .into_iter()
        .fold(f64::NEG_INFINITY, f64::max);
    for _ in 0..8 {
        let (fp, dp) = (res(phi0), dres(phi0));
        if fp == 0.0 || dp == 0.0 {
            break;
        }
        let next = phi0 - fp / dp;
        if res(next).abs().partial_cmp(&fp.abs()) != Some(std::cmp::Ordering::Less) {
            break;
        }
        phi0 = next;
    }
    // 2. LDL^T: d2 (x + l)^2 with 2 d2 l = a phi0 / 2 - c and d2 l^2 = phi0^2 / 4 - d.
    let d2 = (0.25 * a * a - b + phi0).max(0.0);
    let d3 = 0.25 * phi0 * phi0 - d;
    let e = 0.5 * a * phi0 - cc;
    let s = d2.sqrt();
    let mut candidates = Vec::with_capacity(2);
    if d2 > 0.0 {
        // s l from either expression: e / (2 s), or sign(e) sqrt(d3).
        candidates.push(e / (2.0 * s));
        candidates.push(if e < 0.0 { -1.0 } else { 1.0 } * d3.max(0.0).sqrt());
    }
    // When d2 is zero up to rounding (a quartic that is the square of a quadratic, e.g. a
    // ray down the axis of a torus), e / (2 s) is noise over noise: also try s = 0.
    let flat = [
        0.5 * a,
        0.5 * phi0 + d3.max(0.0).sqrt(),
        0.5 * a,
        0.5 * phi0 - d3.max(0.0).sqrt(),
    ];
    let mut best: Option<([f64; 4], f64)> = Some(refine(flat, &coef));
    for sl in candidates {
        let f = [0.5 * a + s, 0.5 * phi0 + sl, 0.5 * a - s, 0.5 * phi0 - sl];
        let (f, err) = refine(f, &coef);
        if best.is_none_or(|(_, e)| err < e) {
            best = Some((f, err));
        }
    }
    let Some(([a1, b1, a2, b2], _)) = best else { return };
    for (alpha, beta) in [(a1, b1), (a2, b2)] {
        if let Some((x0, x1)) = quadratic(1.0, alpha, beta) {
            out.extend([x0, x1]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quartic_with_four_known_roots() {
        // (t-1)(t-2)(t-3)(t-4) = t^4 - 10 t^3 + 35 t^2 - 50 t + 24.
        let mut r = Vec::new();
        quartic_roots(&[24.0, -50.0, 35.0, -10.0, 1.0], &mut r);
        r.sort_by(f64::total_cmp);
        assert_eq!(r.len(), 4, "{r:?}");
        for (g, w) in r.iter().zip([1.0, 2.0, 3.0, 4.0]) {
            assert!((g - w).abs() < 1e-13, "{r:?}");
        }
    }

    #[test]
    fn widely_spread_roots() {
        // (t - 1e-6)(t - 1)(t - 1e3)(t - 1e6): coefficients span 24 orders of magnitude.
        let roots = [1e-6, 1.0, 1e3, 1e6];
        let c = crate::solve::from_roots(&roots);
        let mut r = Vec::new();
        quartic_roots(&[c[0], c[1], c[2], c[3], c[4]], &mut r);
        r.sort_by(f64::total_cmp);
        assert_eq!(r.len(), 4, "{r:?}");
        for (g, w) in r.iter().zip(roots) {
            assert!(((g - w) / w).abs() < 1e-10, "{r:?}");
        }
    }
}
