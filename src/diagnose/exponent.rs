//! The specular exponent an image follows: the factor of every material's exponent `n`
//! that brings the scene's render closest to the image, and the words that say it ("the
//! specular exponent n: yours looks like 40, the scene's is 20").
//!
//! The factor is searched over `log2` of it, in `[-4, 4]` (1/16 to 16: the exponent
//! halved, doubled, a quarter of it as Phong's exponent kept for Blinn's term, four times
//! it), first at every half octave, then by golden section between the best step's
//! neighbours. The cost is the caller's: [`super::Oracle`] renders only the pixels where the
//! image differs from the oracle, a few per cent of the grid, at each factor tried.

use serde::Serialize;

/// The largest `|log2|` of the factor searched.
const LOG2_RANGE: f64 = 4.0;
/// The coarse search's step in `log2` of the factor: half an octave.
const COARSE_STEP: f64 = 0.5;
/// The width of `log2` of the factor at which the golden section stops: 0.005, the factor
/// known within 0.35 %.
const LOG2_TOLERANCE: f64 = 0.005;

/// The fitted factor of the specular exponent, and what it says of the image.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ExponentFit {
    /// The factor every material's specular exponent is multiplied by.
    pub factor: f64,
    /// In words: "the specular exponent n: yours looks like 40, the scene's is 20".
    pub words: String,
}

impl ExponentFit {
    /// The fit of `factor` on a scene whose highlights show the exponents `shown`.
    pub fn new(factor: f64, shown: &[f64]) -> ExponentFit {
        ExponentFit {
            factor,
            words: words(factor, shown),
        }
    }
}

/// The factor in `[1/16, 16]` of least `cost`: the best of the half-octave steps, refined
/// by golden section between its neighbours; the best factor evaluated, should the cost
/// have several minima there.
pub fn fit_factor(cost: impl Fn(f64) -> f64) -> f64 {
    let cost_at = |t: f64| (cost(t.exp2()), t);
    let steps = (2.0 * LOG2_RANGE / COARSE_STEP).round() as i32;
    let coarse = (0..=steps)
        .map(|k| cost_at(-LOG2_RANGE + k as f64 * COARSE_STEP))
        .fold((f64::INFINITY, 0.0), least);
    let (low, high) = (
        (coarse.1 - COARSE_STEP).max(-LOG2_RANGE),
        (coarse.1 + COARSE_STEP).min(LOG2_RANGE),
    );
    golden_section(cost_at, low, high, LOG2_TOLERANCE, coarse).1.exp2()
}

/// Of two `(cost, t)`, the one of smaller cost, the first on a tie (a NaN cost is never the
/// smaller).
fn least(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    if b.0 < a.0 { b } else { a }
}

/// The `(cost, t)` of least cost that golden section finds on `[a, b]` until it is narrower
/// than `tolerance`, or `best` when nothing evaluated is below it.
fn golden_section(
    cost_at: impl Fn(f64) -> (f64, f64),
    mut a: f64,
    mut b: f64,
    tolerance: f64,
    best: (f64, f64),
) -> (f64, f64) {
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let mut left = cost_at(b - ratio * (b - a));
    let mut right = cost_at(a + ratio * (b - a));
    let mut best = least(least(best, left), right);
    while b - a > tolerance {
        if left.0 <= right.0 {
            (b, right) = (right.1, left);
            left = cost_at(b - ratio * (b - a));
            best = least(best, left);
        } else {
            (a, left) = (left.1, right);
            right = cost_at(a + ratio * (b - a));
            best = least(best, right);
        }
    }
    best
}

/// The words of a fit: the exponent the image looks like against the scene's, or, where the
/// scene's highlights show several, the factor and each exponent it gives.
fn words(factor: f64, shown: &[f64]) -> String {
    match shown {
        [n] => format!(
            "the specular exponent n: yours looks like {}, the scene's is {}",
            exponent_text(factor * n),
            exponent_text(*n)
        ),
        _ => {
            let pairs: Vec<String> = shown
                .iter()
                .map(|n| format!("{} for {}", exponent_text(factor * n), exponent_text(*n)))
                .collect();
            format!(
                "the specular exponents n: yours look like {factor:.2} times the scene's ({})",
                pairs.join(", ")
            )
        }
    }
}

/// An exponent as a student writes it: a whole number from 10 on, else with one decimal
/// where it has one (2.5, 5).
fn exponent_text(n: f64) -> String {
    if n >= 10.0 {
        format!("{n:.0}")
    } else {
        let text = format!("{n:.1}");
        text.strip_suffix(".0").map_or(text.clone(), str::to_string)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    #[test]
    fn the_search_finds_a_minimum_within_its_tolerance() {
        // A cost whose minimum is at factor 2 (log2 1) and one at 0.3 (log2 -1.737), between
        // the half-octave steps: both found within 0.35 %, in 17 coarse and at most 14
        // golden-section evaluations.
        for target in [2.0, 0.3, 1.0 / 16.0, 12.0] {
            let calls = Cell::new(0);
            let found = fit_factor(|f: f64| {
                calls.set(calls.get() + 1);
                (f.log2() - f64::log2(target)).powi(2)
            });
            assert!((found / target - 1.0).abs() < 0.0035, "{target}: {found}");
            assert!(calls.get() <= 17 + 14, "{target}: {} evaluations", calls.get());
        }
        // A flat cost keeps the first step of least cost: 1/16.
        assert_eq!(fit_factor(|_| 1.0), 1.0 / 16.0);
    }

    #[test]
    fn exponents_in_words() {
        assert_eq!(
            ExponentFit::new(1.998, &[20.0]).words,
            "the specular exponent n: yours looks like 40, the scene's is 20"
        );
        assert_eq!(
            ExponentFit::new(0.251, &[20.0]).words,
            "the specular exponent n: yours looks like 5, the scene's is 20"
        );
        assert_eq!(
            ExponentFit::new(0.5, &[5.0, 100.0]).words,
            "the specular exponents n: yours look like 0.50 times the scene's (2.5 for 5, 50 for 100)"
        );
        assert_eq!(exponent_text(9.96), "10");
        assert_eq!(exponent_text(0.3), "0.3");
    }
}
