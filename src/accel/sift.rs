//! The `f32` sift of a leaf's spheres: on all the leaf's lanes at once, it drops a sphere
//! only when the `f64` sphere test would surely miss it at its first step, so the spheres
//! it keeps, tested by their own `f64` routine, give the walk the scalar routine's answer
//! to the bit.
//!
//! The `f64` routine ([`crate::shape::sphere_discriminant`]) computes, for the ray
//! `o + t v` and the sphere of centre `c` and radius `r`, `f = o - c`, `b = f.v`,
//! `p = f - b v` and `D = r^2 - |p|^2`, and misses when the computed `D` is negative. The
//! sift computes the same steps in `f32` from the inputs rounded to nearest `f32` (`o'`,
//! `v'` once per ray, `c'` stored in the leaf): `f'`, `b'`, `p'` and `S' = |p'|^2`. It
//! drops the sphere when
//!
//! `S' > Q + C`, with `Q >= A r^2`, `A = 1 + 2^-8 + 2^-16`, and `C >= 2^16 α^2 + 2^-126`,
//!
//! where `α = u (1 + u) G + 2^-140`, `G = |o|_1 + M` (`|o|_1 = |o_x| + |o_y| + |o_z| >=
//! |o|`), `u = 2^-24` (the unit roundoff of `f32`) and `M` bounds `|c|` over the tree's
//! spheres. `Q` is stored in the leaf in place
//! of the radius (`A r^2` in `f64`, rounded up), `C` is computed once per ray.
//!
//! **Why no sphere that the `f64` test keeps is dropped.** Write `F = |f| <= G` for the
//! exact `f` (quantities without a prime or hat are exact functions of the `f64` inputs),
//! `w = |v| <= 1 + 2^-10` (checked per ray) and `γ3 = 3u / (1 - 3u)`. Each `f32` operation
//! returns `x (1 + δ) + η` with `|δ| <= u` and `|η| <= 2^-150`, `η = 0` for sums
//! (underflow is gradual); the `η`s end in an absolute error below `2^-143` on `p'`,
//! which the `2^-140` of `α` covers, so they are left out below.
//!
//! 1. Rounding `o` and `c`, then the difference: `|f' - f| <= u (1 + u) (|o| + |c|) + u F
//!    <= α + u F =: ε`, so `|f'| <= F + ε`.
//! 2. The dot product of three terms (in any order): `|b' - f'.v'| <= γ3 |f'| |v'|`; with
//!    `|v' - v| <= u w`, `|b' - b| <= γ3 |f'| |v'| + ε |v'| + u F w <= w (4.0001 u F +
//!    1.0001 ε) =: Δb`, and `|b'| <= w F + Δb`.
//! 3. `q' = f' - b' v'` exactly: `q' - p = (f' - f) - b' (v' - v) - (b' - b) v`, so
//!    `|q' - p| <= ε + u w^2 F + w (1 + u) Δb <= 2.003 ε + 5.012 u F`.
//! 4. The computed `p'_i = (f'_i - b' v'_i (1 + δ1)) (1 + δ2)`: `|p' - q'| <= u |q'| +
//!    u (1 + u) |b'| |v'|`; since `|p|^2 = F^2 - b^2 (2 - w^2) <= F^2`, `|q'| <= F +
//!    2.003 ε + 5.012 u F` and `|p' - q'| <= 2.003 u F + 4 u ε`.
//! 5. So `|p' - p| <= 7.02 u F + 2.004 ε <= 9.03 u F + 2.004 α`. The `f64` routine's own
//!    `p^` (steps 1 to 4 with exact inputs and `2^-53`) has `|p^ - p| <= 9.03 2^-53 F`.
//!    As `u F <= u G <= α`, `E := |p' - p| + |p^ - p| <= 11.1 α`.
//! 6. The `f64` test misses when its computed `r^2` is below its computed `|p^|^2`, which
//!    holds when `|p^|^2 (1 - γ3') > r^2 (1 + 2^-53)` (`γ3'` the `f64` `γ3`), that is when
//!    `|p^| > ρ r` with `ρ^2 = (1 + 2^-53) / (1 - γ3')`, and so when `|p'| > ρ r + E`.
//! 7. `(x + y)^2 <= (1 + s) x^2 + (1 + 1/s) y^2` for any `s > 0` (from `2xy <= s x^2 +
//!    y^2 / s`); with `s = 2^-8`, `|p'| > ρ r + E` holds when `|p'|^2 > (1 + s) ρ^2 r^2 +
//!    257 (11.1 α)^2`.
//! 8. In computed values, `|p'|^2 >= (S' - 2^-147) / (1 + γ3)`, and `Q + C` computed in
//!    `f32` is at least `(1 - u)` times its exact value. So the drop test implies step 7
//!    when `Q >= 1.0039064 r^2` (step 7's factor with `(1 + γ3) / (1 - u)`; `A` is
//!    `1.0039215`) and `C >= 31 700 α^2 + 2^-146`.
//!
//! So a dropped sphere's computed `f64` discriminant is negative, and the routine would
//! have missed it. A non-sphere entry has a NaN `Q`, and a comparison with NaN is false:
//! it is kept. The sift does not depend on `t`: any `t_min` and `t_max` may use it.
//!
//! Ranges: the leaf copies are made only for trees whose boxes lie within `2^50` (each
//! centre coordinate and radius too), and a ray is sifted in `f32` only when its origin's
//! coordinates are within `2^50` and `|v|^2 <= 1 + 2^-9`; then no `f32` value exceeds
//! `2^110`. Other rays have every object of a leaf tested by its own routine.

use super::node::up;
use crate::math::Ray;
use glam::DVec3;

/// The factor `A` of `r^2` in `Q` (see the module doc).
const RADIUS_FACTOR: f64 = 1.0 + 1.0 / 256.0 + 1.0 / 65536.0;
/// The factor of `α^2` in the per-ray term `C`.
const ROUNDING_FACTOR: f64 = 65536.0;
/// The absolute floor of `α`, which covers underflow: `2^-140`.
const ALPHA_FLOOR: f64 = 1.0 / (1u128 << 120) as f64 / (1u64 << 20) as f64;
/// The absolute term of `C`: `2^-126`, the smallest normal `f32`.
const C_FLOOR: f64 = f32::MIN_POSITIVE as f64;
/// Unit roundoff of `f32`.
const U: f64 = 1.0 / (1u64 << 24) as f64;
/// Relative margin for the `f64` rounding of the per-ray terms (a few `2^-53` each).
const MARGIN: f64 = 1.0 + 1.0 / (1u64 << 20) as f64;
/// Largest origin coordinate the sift takes (as the box test, [`super::wide::F32_RANGE`]).
const RANGE: f64 = (1u64 << 50) as f64;
// Step 8's factors fit under the constants.
const _: () = assert!(1.0039064 < RADIUS_FACTOR && 31_700.0 < ROUNDING_FACTOR);

/// Largest `|v|^2` the sift takes (the proof assumes `|v| <= 1 + 2^-10`).
const MAX_DIR_NORM2: f64 = 1.0 + 1.0 / 512.0;

/// The value stored for a sphere of radius `r` in place of its radius: `Q`, the smallest
/// `f32` not below `A r^2` (NaN stays NaN).
pub fn radius_term(r: f64) -> f32 {
    up(RADIUS_FACTOR * MARGIN * r * r)
}

/// A ray prepared for the `f32` sift: its origin and direction rounded to `f32`, and the
/// per-ray term `C`.
#[derive(Clone, Copy, Debug)]
pub struct NarrowRay {
    origin: [f32; 3],
    dir: [f32; 3],
    slack: f32,
}

impl NarrowRay {
    /// The sift for `ray` over spheres whose centres lie within `center_reach` of the
    /// world's origin, or `None` when the ray is beyond its range (see the module doc).
    #[inline(always)]
    pub fn new(ray: &Ray, center_reach: f64) -> Option<Self> {
        let (o, v) = (ray.origin, ray.dir);
        // Written so that a NaN fails.
        let fits = o.abs().cmple(DVec3::splat(RANGE)).all() && v.length_squared() <= MAX_DIR_NORM2;
        if !fits {
            return None;
        }
        // `|o|_1 >= |o|`, without a square root.
        let alpha = (o.abs().element_sum() + center_reach) * U * MARGIN + ALPHA_FLOOR;
        // At least `2^-126`, a normal `f32`: rounding to nearest loses less than the
        // `2^-19` added.
        let slack = ((ROUNDING_FACTOR * alpha * alpha + C_FLOOR) * (1.0 + 2f64.powi(-19))) as f32;
        Some(NarrowRay {
            origin: [o.x as f32, o.y as f32, o.z as f32],
            dir: [v.x as f32, v.y as f32, v.z as f32],
            slack,
        })
    }

    /// Per lane, `(Q + C) - S'` for the sphere of centre `(cx, cy, cz)` (rounded to `f32`)
    /// and radius term `q` ([`radius_term`]): negative where `S' > Q + C`, the spheres the
    /// ray surely misses; a NaN `q` gives a NaN. A plain loop over the lanes, vectorised by
    /// the compiler (no fused multiply-add: each step is the proof's).
    #[inline(always)]
    pub fn margins<const N: usize>(&self, cx: &[f32; N], cy: &[f32; N], cz: &[f32; N], q: &[f32; N]) -> [f32; N] {
        let [ox, oy, oz] = self.origin;
        let [vx, vy, vz] = self.dir;
        let mut margin = [0.0f32; N];
        for l in 0..N {
            let fx = ox - cx[l];
            let fy = oy - cy[l];
            let fz = oz - cz[l];
            let b = fx * vx + fy * vy + fz * vz;
            let px = fx - b * vx;
            let py = fy - b * vy;
            let pz = fz - b * vz;
            let perp2 = px * px + py * py + pz * pz;
            margin[l] = (q[l] + self.slack) - perp2;
        }
        margin
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Purpose, Stream};
    use crate::shape::sphere_discriminant;
    use proptest::prelude::*;

    #[test]
    fn constants_are_the_proofs() {
        assert_eq!(ALPHA_FLOOR, 2f64.powi(-140));
        assert_eq!(C_FLOOR, 2f64.powi(-126));
        assert_eq!(RADIUS_FACTOR, 1.0 + 2f64.powi(-8) + 2f64.powi(-16));
    }

    /// Whether the sift drops the sphere `(c, r)` for `ray` (`None`: the ray is beyond it),
    /// and whether the `f64` routine's first test keeps it (a discriminant `>= 0`).
    fn verdicts(ray: &Ray, c: DVec3, r: f64) -> Option<(bool, bool)> {
        let sift = NarrowRay::new(ray, c.length())?;
        let [margin] = sift.margins(&[c.x as f32], &[c.y as f32], &[c.z as f32], &[radius_term(r)]);
        let dropped = margin < 0.0;
        Some((dropped, sphere_discriminant(c, r, ray).0 >= 0.0))
    }

    /// A ray along the unit `d` passing at distance `reach` from `c` (across `d` by the unit
    /// `across`), its origin `back` behind its closest approach.
    fn passing(c: DVec3, d: DVec3, across: DVec3, reach: f64, back: f64) -> Ray {
        Ray::new(c + across * reach - d * back, d)
    }

    /// The largest reach (in steps of the radius' ulps from `r`) at which the `f64` test
    /// still keeps the sphere: the rim as the `f64` routine sees it.
    fn rim(c: DVec3, r: f64, d: DVec3, across: DVec3, back: f64) -> f64 {
        let keeps = |reach: f64| sphere_discriminant(c, r, &passing(c, d, across, reach, back)).0 >= 0.0;
        let mut reach = r;
        let mut step = r * 2f64.powi(-52);
        // Where the origin's rounding swamps the reach, there may be no rim to find.
        let mut tries = 0;
        while !keeps(reach) {
            reach -= step;
            step *= 2.0;
            tries += 1;
            if tries > 60 {
                return r;
            }
        }
        while keeps(reach + step) && tries < 120 {
            reach += step;
            step *= 2.0;
            tries += 1;
        }
        // Up to the last kept reach, one halving at a time.
        while step > r * 2f64.powi(-53) {
            step *= 0.5;
            if keeps(reach + step) {
                reach += step;
            }
        }
        reach
    }

    /// Adversarial spheres: grazing rays at the exact reach where the `f64` discriminant
    /// turns negative, radii from `1e-40` (below `f32`'s normal range) to `1e12`, centres
    /// up to `1e14` from the world's origin, origins from `1e-3` to `1e14` away. No sphere
    /// the `f64` test keeps is dropped; a sphere missed by 1 % of its radius is dropped
    /// whenever the radius is well above the rounding of the coordinates (`2^-10` of them).
    #[test]
    fn no_sphere_the_f64_test_keeps_is_dropped() {
        let mut s = Stream::new(27, Purpose::Generator, 2);
        let mut next = || s.next_f64();
        let (mut kept_at_rim, mut dropped_past_rim, mut clear_misses) = (0, 0, 0);
        for trial in 0..20_000 {
            let radius = [1e-40, 1e-20, 1e-6, 1e-2, 1.0, 3e3, 1e6, 1e12][trial % 8] * (0.5 + next());
            let offset = [0.0, 1.0, 1e4, 1e9, 1e14][trial / 8 % 5];
            let back = [1e-3, 1.0, 1e3, 1e7, 1e14][trial / 40 % 5] * (1.0 + next());
            let unit = |a: f64, b: f64, c: f64| DVec3::new(a - 0.5, b - 0.5, c - 0.5).normalize();
            let c = unit(next(), next(), next()) * offset * next();
            let d = unit(next(), next(), next());
            let across = d.cross(unit(next(), next(), next())).normalize();
            let edge = rim(c, radius, d, across, back);
            // At the rim, one and two ulps past it, and 1 % past the radius.
            for (k, reach) in [edge, edge.next_up(), edge.next_up().next_up(), 1.01 * radius.max(edge)]
                .into_iter()
                .enumerate()
            {
                let ray = passing(c, d, across, reach, back);
                let Some((dropped, keeps)) = verdicts(&ray, c, radius) else {
                    continue;
                };
                assert!(
                    !(dropped && keeps),
                    "dropped a sphere the f64 test keeps: c {c:?} r {radius:e} {ray:?}"
                );
                kept_at_rim += (k == 0 && keeps) as u32;
                dropped_past_rim += (k > 0 && dropped) as u32;
                let coordinates = c.length() + ray.origin.length();
                if k == 3 && radius > coordinates * 2f64.powi(-10) {
                    assert!(dropped, "kept a clear miss: c {c:?} r {radius:e} {ray:?}");
                    clear_misses += 1;
                }
            }
        }
        assert!(
            kept_at_rim > 12_000 && clear_misses > 5_000 && dropped_past_rim > 5_000,
            "{kept_at_rim} rims, {clear_misses} clear misses, {dropped_past_rim} dropped past the rim"
        );
    }

    /// Rays the sift cannot take: an origin beyond `2^50`, a NaN, a direction far from unit
    /// length.
    #[test]
    fn rays_beyond_the_sift_are_refused() {
        let ray = |o: [f64; 3], d: [f64; 3]| Ray::new(DVec3::from(o), DVec3::from(d));
        assert!(NarrowRay::new(&ray([1e15, 0.0, 0.0], [1.0, 0.0, 0.0]), 1.0).is_some());
        assert!(NarrowRay::new(&ray([2e15, 0.0, 0.0], [1.0, 0.0, 0.0]), 1.0).is_none());
        assert!(NarrowRay::new(&ray([0.0, f64::NAN, 0.0], [1.0, 0.0, 0.0]), 1.0).is_none());
        assert!(NarrowRay::new(&ray([0.0; 3], [1.0009, 0.0, 0.0]), 1.0).is_some());
        assert!(NarrowRay::new(&ray([0.0; 3], [1.01, 0.0, 0.0]), 1.0).is_none());
        assert!(NarrowRay::new(&ray([0.0; 3], [f64::INFINITY, 0.0, 0.0]), 1.0).is_none());
        // A NaN radius (a non-sphere entry) is never dropped.
        let sift = NarrowRay::new(&ray([0.0; 3], [1.0, 0.0, 0.0]), 1.0).unwrap();
        let far = [1e6f32; 4];
        let margins = sift.margins(&far, &far, &far, &[radius_term(f64::NAN), radius_term(1.0), 0.0, 3e12]);
        assert!(margins[0].is_nan());
        // The line misses by 1e6 * sqrt(2) (the `x` axis through the origin): `(Q + C) - S'`
        // is `r^2`-ish minus 2e12.
        assert!(margins[1] < -1.9e12 && margins[2] < -1.9e12, "{margins:?}");
        assert!(margins[3] > 0.9e12, "{margins:?}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4000))]

        /// Random spheres and rays over many scales, each ray passing the sphere at a
        /// reach a few ulps either side of the `f64` test's rim, or anywhere up to twice
        /// the radius: the sift never drops a sphere the `f64` test keeps.
        #[test]
        fn the_sift_never_drops_a_kept_sphere(
            centre in prop::array::uniform3(-1.0f64..1.0),
            centre_scale in -10i32..45,
            radius_mantissa in 0.5f64..1.0,
            radius_scale in -130i32..40,
            dir in prop::array::uniform3(-1.0f64..1.0),
            side in prop::array::uniform3(-1.0f64..1.0),
            back_scale in -10i32..45,
            ulps in -8i64..8,
            spread in 0.0f64..2.0,
            at_rim in any::<bool>(),
        ) {
            let c = DVec3::from(centre) * 2f64.powi(centre_scale);
            let r = radius_mantissa * 2f64.powi(radius_scale);
            let d = DVec3::from(dir);
            prop_assume!(d.length() > 0.1);
            let d = d.normalize();
            let across = d.cross(DVec3::from(side));
            prop_assume!(across.length() > 0.1);
            let across = across.normalize();
            let back = 2f64.powi(back_scale);
            let reach = if at_rim {
                let edge = rim(c, r, d, across, back);
                f64::from_bits((edge.to_bits() as i64 + ulps) as u64)
            } else {
                r * spread
            };
            let ray = passing(c, d, across, reach, back);
            if let Some((dropped, keeps)) = verdicts(&ray, c, r) {
                prop_assert!(!(dropped && keeps), "c {:?} r {:e} {:?}", c, r, ray);
            }
        }
    }
}
