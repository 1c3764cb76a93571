//! Root finders for the shape equations: the numerically stable quadratic (spheres,
//! cylinders, cones) and a real-root isolator for polynomials up to degree 4 (the torus).
//!
//! The quartic solver does not use a closed form (Ferrari and friends lose whole digits to
//! cancellation on badly scaled coefficients). It isolates roots on a finite interval by
//! recursion on derivatives: the roots of `p'` split `[a, b]` into pieces where `p` is
//! monotone, and each piece holding a sign change is solved by safeguarded Newton-bisection
//! to full precision. The caller passes the exact function to bracket on (for the torus, its
//! implicit equation evaluated directly, which has no coefficient cancellation). The pieces
//! are taken in increasing order as the derivative's roots bound them, and [`visit_roots`]
//! stops at the root its caller needs (a closest hit's first root in its interval): the
//! pieces after it are neither bounded nor refined, and the roots before it are the bits a
//! full search finds.
//!
//! The closed-form alternatives measured against it live in [`ferrari`] (textbook Ferrari)
//! and [`orellana`] (Orellana and De Michele 2020); see BENCHMARKS.md, "Numerical stability".

pub mod ferrari;
pub mod orellana;

/// Real roots of `a t^2 + b t + c = 0` in increasing order, computed without catastrophic
/// cancellation: `q = -(b + sign(b) sqrt(b^2 - 4ac)) / 2`, roots `q / a` and `c / q`
/// (Numerical Recipes 5.6). Degenerate `a = 0` falls back to the linear root.
pub fn quadratic(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    if a == 0.0 {
        // Degenerate: the linear root.
        let t = -c / b;
        return (b != 0.0).then_some((t, t));
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    Some(quadratic_roots(a, b, c, disc))
}

/// [`quadratic`] without a branch (for loops over many rays, see `shape::fan`; for one
/// equation the branches are cheaper): the roots, and whether there are any (the roots are
/// meaningless when not).
#[inline(always)]
// `!(disc < 0.0)`: a NaN discriminant gives NaN roots, as in `quadratic`.
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn quadratic_parts(a: f64, b: f64, c: f64) -> (f64, f64, bool) {
    let flat = a == 0.0;
    let linear = -c / b;
    let disc = b * b - 4.0 * a * c;
    let (t0, t1) = quadratic_roots(a, b, c, disc);
    let real = if flat { b != 0.0 } else { !(disc < 0.0) };
    (if flat { linear } else { t0 }, if flat { linear } else { t1 }, real)
}

/// The roots of [`quadratic`] for `a != 0` and the discriminant `disc = b^2 - 4ac >= 0`,
/// in increasing order.
#[inline(always)]
fn quadratic_roots(a: f64, b: f64, c: f64, disc: f64) -> (f64, f64) {
    let root = disc.sqrt();
    let q = if b < 0.0 { -0.5 * (b - root) } else { -0.5 * (b + root) };
    // `q = 0` when b = 0 and c = 0: a double root at zero.
    let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
    if t0 <= t1 { (t0, t1) } else { (t1, t0) }
}

/// Evaluates `sum c[i] t^i` by Horner's rule (coefficients in increasing degree).
pub fn horner(c: &[f64], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ci| acc * t + ci)
}

/// Pushes into `out`, in increasing order, the real roots in `[lo, hi]` of the polynomial
/// with coefficients `c` (increasing degree, at most degree 4). Double roots are reported
/// when the polynomial reaches exactly zero at a critical point; grazing roots that round
/// to a near miss are lost, which is the expected behaviour within the grazing band.
pub fn poly_roots_in(c: &[f64], lo: f64, hi: f64, out: &mut Vec<f64>) {
    poly_roots_with(c, lo, hi, &|t| horner(c, t), out)
}

/// As [`poly_roots_in`], but brackets and refines the roots on `f`, an accurate evaluation
/// of the same polynomial (for example an unexpanded implicit equation). The expanded
/// coefficients `c` are only used to find the critical points that split the interval.
pub fn poly_roots_with(c: &[f64], lo: f64, hi: f64, f: &dyn Fn(f64) -> f64, out: &mut Vec<f64>) {
    for &t in poly_roots(c, lo, hi, f).as_slice() {
        push_unique(out, t);
    }
}

/// As [`poly_roots_with`], returning the roots on the stack (the torus calls it once per
/// ray: no heap allocation).
pub fn poly_roots<F: Fn(f64) -> f64 + ?Sized>(c: &[f64], lo: f64, hi: f64, f: &F) -> Few {
    debug_assert!(c.len() <= 5, "degree at most 4");
    let mut few = Few::default();
    roots_into(c, lo, hi, f, &mut few);
    few
}

/// A handful of distinct roots, increasing, on the stack.
#[derive(Default)]
pub struct Few {
    v: [f64; 6],
    n: usize,
}

impl Few {
    fn push_unique(&mut self, t: f64) {
        if (self.n == 0 || self.v[self.n - 1] != t) && self.n < self.v.len() {
            self.v[self.n] = t;
            self.n += 1;
        }
    }

    pub fn as_slice(&self) -> &[f64] {
        &self.v[..self.n]
    }
}

/// The isolator proper (see the module doc), for at most 5 coefficients, every root into
/// `out`.
fn roots_into<F: Fn(f64) -> f64 + ?Sized>(c: &[f64], lo: f64, hi: f64, f: &F, out: &mut Few) {
    visit_roots(c, lo, hi, f, &mut |t| {
        out.push_unique(t);
        false
    });
}

/// The roots [`poly_roots`] finds, in the same increasing order and to the same bits,
/// each passed to `visit` as it is found until `visit` returns true: the roots after it
/// are not refined (a closest hit needs the first root in its interval, an occlusion test
/// any), and the critical points after its piece are not looked for. Generic over `f`, so
/// that a caller's evaluation (the torus's implicit equation) is inlined into the
/// bracketing and refinement that call it dozens of times per root.
pub fn visit_roots<F: Fn(f64) -> f64 + ?Sized, V: FnMut(f64) -> bool + ?Sized>(
    c: &[f64],
    lo: f64,
    hi: f64,
    f: &F,
    visit: &mut V,
) {
    let mut len = c.len().min(5);
    while len > 1 && c[len - 1] == 0.0 {
        len -= 1;
    }
    let degree = len.saturating_sub(1);
    if degree == 0 {
        return;
    }
    // Coefficients of the derivative (increasing degree).
    let mut deriv = [0.0; 4];
    for i in 1..len {
        deriv[i - 1] = c[i] * i as f64;
    }
    let deriv = &deriv[..degree];
    // Equal consecutive roots are passed once, as [`Few`] keeps them.
    let mut last = None;
    let mut found = |t: f64| {
        let new = last != Some(t);
        last = Some(t);
        new && visit(t)
    };
    // The root of a piece `[a, b]` where the polynomial is monotone: `a` when `f(a)` is 0,
    // else the refined sign change. Whether `visit` has what it needs.
    let mut piece = |a: f64, b: f64| {
        let (fa, fb) = (f(a), f(b));
        if fa == 0.0 {
            found(a)
        } else {
            fa.signum() != fb.signum() && fb != 0.0 && found(refine(f, deriv, a, b, fa))
        }
    };
    // The pieces run between the critical points inside `(lo, hi)` (the roots of the
    // derivative, found in increasing order), from `lo` to `hi`.
    let mut start = lo;
    // A derivative whose coefficients all have the sign of its (non-zero) constant term
    // keeps that sign on `[0, inf)`, exactly also in Horner's floating-point evaluation (a
    // sum of products of one sign): no critical point there, nothing to search for. For the
    // torus this is most rays leaving its surface away from it.
    let monotone_from_zero = lo >= 0.0
        && deriv[0] != 0.0
        && deriv
            .iter()
            .all(|&c| c == 0.0 || c.is_sign_positive() == deriv[0].is_sign_positive());
    if degree >= 2 && !monotone_from_zero {
        let mut stopped = false;
        let mut split = |t: f64| {
            if t > lo && t < hi {
                stopped = piece(start, t);
                start = t;
            }
            stopped
        };
        visit_horner_roots(deriv, lo, hi, &mut split);
        if stopped {
            return;
        }
    }
    if !piece(start, hi) && f(hi) == 0.0 {
        found(hi);
    }
}

/// [`visit_roots`] bracketing on the polynomial itself (Horner's rule on `c`): the
/// derivatives' roots. Not generic, so that its one instance of [`visit_roots`], with
/// Horner's rule inlined into the refinement, serves every level of the recursion (a
/// closure type of each level would instantiate the next one without end).
fn visit_horner_roots(c: &[f64], lo: f64, hi: f64, visit: &mut dyn FnMut(f64) -> bool) {
    visit_roots(c, lo, hi, &|t| horner(c, t), visit);
}

fn push_unique(out: &mut Vec<f64>, t: f64) {
    if out.last() != Some(&t) {
        out.push(t);
    }
}

/// Safeguarded Newton-bisection on a bracket `[a, b]` where `f` changes sign (`fa = f(a)`).
/// Newton steps use the expanded derivative; a step leaving the bracket is replaced by
/// bisection. Stops when the bracket cannot shrink further in floating point.
fn refine<F: Fn(f64) -> f64 + ?Sized>(f: &F, deriv: &[f64], mut a: f64, mut b: f64, fa: f64) -> f64 {
    let neg_at_a = fa < 0.0;
    let mut t = 0.5 * (a + b);
    for _ in 0..200 {
        let ft = f(t);
        if ft == 0.0 {
            return t;
        }
        if (ft < 0.0) == neg_at_a {
            a = t;
        } else {
            b = t;
        }
        let mid = 0.5 * (a + b);
        if mid <= a || mid >= b {
            break;
        }
        let d = horner(deriv, t);
        let newton = t - ft / d;
        // Newton from one side never moves the far end of the bracket, so bisection would
        // spend ~50 steps shrinking it. Once the step is a few ulps, probe one more step
        // past the Newton point: a sign change there brackets the root within two steps.
        let step = newton - t;
        if d != 0.0 && step != 0.0 && step.abs() <= 8.0 * f64::EPSILON * t.abs() {
            let probe = newton + step;
            if probe > a && probe < b && (f(probe) < 0.0) != (ft < 0.0) {
                return newton;
            }
        }
        t = if d != 0.0 && newton > a && newton < b {
            newton
        } else {
            mid
        };
        // Newton converged to a fixed point inside the bracket: one more bisection check.
        if t == a || t == b {
            t = mid;
        }
    }
    // The bracket is a few ulps wide: return the end with the smaller residual.
    if f(a).abs() <= f(b).abs() { a } else { b }
}

/// The coefficients, lowest degree first, of the monic polynomial with `roots`: the product
/// of the `(t - r)`.
#[cfg(test)]
pub(crate) fn from_roots(roots: &[f64]) -> Vec<f64> {
    let mut c = vec![1.0];
    for r in roots {
        let mut next = vec![0.0; c.len() + 1];
        for (i, &ci) in c.iter().enumerate() {
            next[i] -= r * ci;
            next[i + 1] += ci;
        }
        c = next;
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stable_quadratic_keeps_the_small_root() {
        // t^2 - 1e8 t + 1 = 0: roots 1e8 and 1e-8 (1e-8 + 1e-24 to first order). The naive
        // formula loses every digit of the small root to cancellation.
        let (t0, t1) = quadratic(1.0, -1e8, 1.0).unwrap();
        assert!((t0 - 1e-8).abs() < 1e-22, "{t0}");
        assert!((t1 - 1e8).abs() < 1e-6);
    }

    #[test]
    fn quadratic_without_real_roots() {
        assert_eq!(quadratic(1.0, 0.0, 1.0), None);
        // (t - 2)^2: a double root.
        assert_eq!(quadratic(1.0, -4.0, 4.0), Some((2.0, 2.0)));
    }

    #[test]
    fn quartic_with_four_known_roots() {
        // (t-1)(t-2)(t-3)(t-4) = t^4 - 10 t^3 + 35 t^2 - 50 t + 24.
        let c = [24.0, -50.0, 35.0, -10.0, 1.0];
        let mut r = Vec::new();
        poly_roots_in(&c, 0.0, 10.0, &mut r);
        assert_eq!(r.len(), 4, "{r:?}");
        for (got, want) in r.iter().zip([1.0, 2.0, 3.0, 4.0]) {
            // Horner on expanded coefficients is accurate to a few ulps of the largest term.
            assert!((got - want).abs() < 1e-13, "{got} vs {want}");
        }
        r.clear();
        poly_roots_in(&c, 2.5, 3.5, &mut r);
        assert_eq!(r.len(), 1);
        assert!((r[0] - 3.0).abs() < 1e-13);
    }

    #[test]
    fn increasing_quartic_has_its_one_root() {
        // s^4 + 2 s^3 + 3 s^2 + 4 s - 5: the derivative 4 s^3 + 6 s^2 + 6 s + 4 has only
        // positive coefficients, so there is no critical point on [0, inf) and exactly one
        // root, between f(0) = -5 and f(1) = 5. Bisection to the last bit agrees with it.
        let c = [-5.0, 4.0, 3.0, 2.0, 1.0];
        let mut r = Vec::new();
        poly_roots_in(&c, 0.0, 10.0, &mut r);
        assert_eq!(r.len(), 1, "{r:?}");
        let (mut a, mut b) = (0.0f64, 1.0f64);
        while b - a > 4.0 * f64::EPSILON {
            let m = 0.5 * (a + b);
            if horner(&c, m) < 0.0 { a = m } else { b = m }
        }
        assert!((r[0] - a).abs() < 1e-14, "{} vs {a}", r[0]);
        // Shifted so the root is outside the interval: nothing.
        r.clear();
        poly_roots_in(&c, 1.0, 10.0, &mut r);
        assert_eq!(r, Vec::<f64>::new());
    }

    #[test]
    fn quartic_with_clustered_roots() {
        // (t - 1)(t - 1.000001)(t - 5)(t - 7): two roots 1e-6 apart are still separated.
        let roots = [1.0, 1.000_001, 5.0, 7.0];
        let c = from_roots(&roots);
        let mut r = Vec::new();
        poly_roots_in(&c, 0.0, 10.0, &mut r);
        assert_eq!(r.len(), 4, "{r:?}");
        for (got, want) in r.iter().zip(roots) {
            assert!((got - want).abs() < 1e-9, "{got} vs {want}");
        }
    }

    #[test]
    fn visiting_stops_refining_at_the_root_it_needs() {
        // (t-1)(t-2)(t-3)(t-4) on [0, 10], bracketed on the expanded polynomial with each
        // evaluation counted: every root visited is `poly_roots`' root to the bit, in
        // order; stopping at the first root leaves the three others unrefined, so `f` is
        // evaluated fewer times than for all four.
        let c = [24.0, -50.0, 35.0, -10.0, 1.0];
        let calls = std::cell::Cell::new(0);
        let f = |t: f64| {
            calls.set(calls.get() + 1);
            horner(&c, t)
        };
        let all = poly_roots(&c, 0.0, 10.0, &f);
        let calls_for_all = calls.replace(0);
        assert_eq!(all.as_slice().len(), 4);
        let mut visited = Vec::new();
        visit_roots(&c, 0.0, 10.0, &f, &mut |t| {
            visited.push(t);
            false
        });
        assert_eq!(
            visited.iter().map(|t| t.to_bits()).collect::<Vec<_>>(),
            all.as_slice().iter().map(|t| t.to_bits()).collect::<Vec<_>>()
        );
        assert_eq!(calls.replace(0), calls_for_all);
        let mut first = Vec::new();
        visit_roots(&c, 0.0, 10.0, &f, &mut |t| {
            first.push(t);
            true
        });
        assert_eq!(first, [all.as_slice()[0]]);
        assert!((first[0] - 1.0).abs() < 1e-13);
        assert!(
            calls.get() < calls_for_all,
            "{} of {calls_for_all} evaluations",
            calls.get()
        );
        // Skipping the first two (a caller's `t <= t_min`), stopping at the third.
        let mut third = Vec::new();
        visit_roots(&c, 0.0, 10.0, &f, &mut |t| {
            third.push(t);
            t > 2.5
        });
        assert_eq!(third, all.as_slice()[..3]);
    }

    /// The isolator as it reads in the module doc, every step done in full: all critical
    /// points first (recursively), then every piece refined. The reference the lazy
    /// [`visit_roots`] is held to.
    fn eager_roots(c: &[f64], lo: f64, hi: f64, f: &dyn Fn(f64) -> f64) -> Vec<f64> {
        let mut len = c.len();
        while len > 1 && c[len - 1] == 0.0 {
            len -= 1;
        }
        if len <= 1 {
            return Vec::new();
        }
        let deriv: Vec<f64> = (1..len).map(|i| c[i] * i as f64).collect();
        let monotone_from_zero = lo >= 0.0
            && deriv[0] != 0.0
            && deriv
                .iter()
                .all(|&c| c == 0.0 || c.is_sign_positive() == deriv[0].is_sign_positive());
        let mut splits = vec![lo];
        if len >= 3 && !monotone_from_zero {
            let crit = eager_roots(&deriv, lo, hi, &|t| horner(&deriv, t));
            splits.extend(crit.into_iter().filter(|&t| t > lo && t < hi));
        }
        splits.push(hi);
        let mut out = Vec::new();
        for w in splits.windows(2) {
            let (fa, fb) = (f(w[0]), f(w[1]));
            if fa == 0.0 {
                push_unique(&mut out, w[0]);
            } else if fa.signum() != fb.signum() && fb != 0.0 {
                push_unique(&mut out, refine(f, &deriv, w[0], w[1], fa));
            }
        }
        if f(hi) == 0.0 {
            push_unique(&mut out, hi);
        }
        out
    }

    #[test]
    fn visited_roots_are_the_eager_isolators() {
        // 20 000 random polynomials of degree 1 to 4 with roots spread over [-2, 12] (some
        // outside [0, 10], some clustered, some double), scaled by a random factor, on
        // [0, 10] and on a random sub-interval: every root visited, and the visits stopped
        // after the k-th, give the eager isolator's roots to the bit.
        use crate::sampling::unit_interval;
        use rand_chacha::ChaCha8Rng;
        use rand_core::{Rng, SeedableRng};
        let mut draw = ChaCha8Rng::seed_from_u64(4);
        let mut uniform = move || unit_interval(draw.next_u64());
        let mut roots_seen = 0;
        for case in 0..20_000 {
            let degree = 1 + case % 4;
            let lead = 1.0 + 9.0 * uniform();
            let mut previous: f64 = -2.0 + 14.0 * uniform();
            let mut roots = Vec::new();
            for _ in 0..degree {
                let r = match case % 3 {
                    0 => previous,
                    1 => previous + 1e-6 * uniform(),
                    _ => -2.0 + 14.0 * uniform(),
                };
                previous = r;
                roots.push(r);
            }
            let c: Vec<f64> = from_roots(&roots).iter().map(|x| lead * x).collect();
            let (lo, hi) = if case % 2 == 0 {
                (0.0, 10.0)
            } else {
                (5.0 * uniform(), 5.0 + 5.0 * uniform())
            };
            let f = |t: f64| horner(&c, t);
            let want = eager_roots(&c, lo, hi, &f);
            roots_seen += want.len();
            for stop_after in 1..=want.len() + 1 {
                let mut got = Vec::new();
                visit_roots(&c, lo, hi, &f, &mut |t| {
                    got.push(t);
                    got.len() == stop_after
                });
                let n = stop_after.min(want.len());
                assert_eq!(
                    got.iter().map(|t| t.to_bits()).collect::<Vec<_>>(),
                    want[..n].iter().map(|t| t.to_bits()).collect::<Vec<_>>(),
                    "case {case}: {c:?} on [{lo}, {hi}]"
                );
            }
        }
        // The cases are not all empty: 16 449 roots in the 20 000 intervals.
        assert!(roots_seen > 15_000, "{roots_seen}");
    }
}
