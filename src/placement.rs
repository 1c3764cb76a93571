//! Where the N point lights of an area light go (chapter 7.4b, "La source de lumière à
//! multiple points ponctuelles"). Every strategy is seeded: it reads its random numbers from
//! the stream it is given, two per point, in point order, so for `chapter` and `uniform` the
//! first N points of a larger set are exactly the N-point set (the 5 points are among the 25).
//! Points are returned for the unit shape (unit sphere, segment [0, 1], unit square
//! [0, 1]^2); `area_light` maps them onto the light's shape.

use crate::math::other_leg;
use crate::sampling::Stream;
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// A placement strategy.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Placement {
    /// The chapter's recipe: `theta` uniform in [0, 180], `phi` uniform in [0, 360],
    /// `(cos phi sin theta, sin phi sin theta, cos theta)`. Not uniform over the area: it
    /// crowds points at the poles. On tubes and windows, the same as `uniform`.
    Chapter,
    /// Uniform over the area: `z` uniform in [-1, 1], `phi` uniform in [0, 360].
    Uniform,
    /// Latin hypercube (N rooks): each of N equal-area bands of the first coordinate and
    /// each of N equal slices of the second holds exactly one point, jittered inside.
    Stratified,
    /// Low discrepancy: the spherical Fibonacci lattice (`z_i = 1 - (2i + 1)/N`,
    /// `phi_i = 2 pi i / golden ratio`), the golden-ratio sequence on a segment, the
    /// Fibonacci lattice on a square; turned or shifted by one seeded random offset.
    Fibonacci,
}

impl Placement {
    pub fn parse(name: &str) -> Option<Placement> {
        Some(match name {
            "chapter" => Placement::Chapter,
            "uniform" => Placement::Uniform,
            "stratified" => Placement::Stratified,
            "fibonacci" => Placement::Fibonacci,
            _ => return None,
        })
    }
}

/// `1 / golden ratio`.
const INV_PHI: f64 = 0.618_033_988_749_894_9;

/// Point `i` of the golden-ratio sequence shifted by `offset`: `frac(offset + i / phi)`.
fn golden(offset: f64, i: usize) -> f64 {
    (offset + i as f64 * INV_PHI).fract()
}

/// `n` pairs `(u, v)` in [0, 1)^2 for the strategy (the chapter's recipe is applied by
/// the sphere mapping, not here).
fn unit_pairs(placement: Placement, n: usize, rng: &mut Stream) -> Vec<DVec2> {
    match placement {
        Placement::Chapter | Placement::Uniform => (0..n).map(|_| DVec2::new(rng.next_f64(), rng.next_f64())).collect(),
        Placement::Stratified => {
            // A seeded permutation of the second coordinate's slices (Fisher-Yates).
            let mut perm: Vec<usize> = (0..n).collect();
            for i in (1..n).rev() {
                let j = ((rng.next_f64() * (i + 1) as f64) as usize).min(i);
                perm.swap(i, j);
            }
            (0..n)
                .map(|i| {
                    let (a, b) = (rng.next_f64(), rng.next_f64());
                    DVec2::new((i as f64 + a) / n as f64, (perm[i] as f64 + b) / n as f64)
                })
                .collect()
        }
        Placement::Fibonacci => {
            let offset = rng.next_f64();
            (0..n)
                .map(|i| DVec2::new((i as f64 + 0.5) / n as f64, golden(offset, i)))
                .collect()
        }
    }
}

/// `n` points on the unit sphere.
pub fn on_sphere(placement: Placement, n: usize, rng: &mut Stream) -> Vec<DVec3> {
    unit_pairs(placement, n, rng)
        .into_iter()
        .map(|uv| {
            let phi = 2.0 * PI * uv.y;
            let (sin_phi, cos_phi) = (libm::sin(phi), libm::cos(phi));
            match placement {
                Placement::Chapter => {
                    // theta uniform in [0, pi]: x = cos phi sin theta, y = sin phi sin theta, z = cos theta.
                    let theta = PI * uv.x;
                    let (sin_t, cos_t) = (libm::sin(theta), libm::cos(theta));
                    DVec3::new(cos_phi * sin_t, sin_phi * sin_t, cos_t)
                }
                _ => {
                    // z uniform in [-1, 1] (Archimedes: equal z bands have equal areas).
                    let z = 1.0 - 2.0 * uv.x;
                    let r = other_leg(z);
                    DVec3::new(r * cos_phi, r * sin_phi, z)
                }
            }
        })
        .collect()
}

/// `n` parameters in [0, 1) along a segment.
pub fn on_segment(placement: Placement, n: usize, rng: &mut Stream) -> Vec<f64> {
    match placement {
        Placement::Fibonacci => {
            let offset = rng.next_f64();
            (0..n).map(|i| golden(offset, i)).collect()
        }
        _ => unit_pairs(placement, n, rng).into_iter().map(|uv| uv.x).collect(),
    }
}

/// `n` points in the unit square [0, 1)^2.
pub fn on_square(placement: Placement, n: usize, rng: &mut Stream) -> Vec<DVec2> {
    unit_pairs(placement, n, rng)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Purpose;

    fn rng(seed: u64) -> Stream {
        Stream::new(seed, Purpose::LightPoints, 0)
    }

    #[test]
    fn points_are_on_the_unit_sphere() {
        for p in [
            Placement::Chapter,
            Placement::Uniform,
            Placement::Stratified,
            Placement::Fibonacci,
        ] {
            for q in on_sphere(p, 50, &mut rng(1)) {
                assert!((q.length() - 1.0).abs() < 1e-12, "{p:?} {q}");
            }
        }
    }

    #[test]
    fn first_n_points_are_a_prefix() {
        for p in [Placement::Chapter, Placement::Uniform] {
            let five = on_sphere(p, 5, &mut rng(9));
            let twenty_five = on_sphere(p, 25, &mut rng(9));
            assert_eq!(five[..], twenty_five[..5]);
        }
    }

    #[test]
    fn stratified_has_one_point_per_band_and_slice() {
        let pairs = unit_pairs(Placement::Stratified, 16, &mut rng(2));
        let mut bands: Vec<usize> = pairs.iter().map(|p| (p.x * 16.0) as usize).collect();
        let mut slices: Vec<usize> = pairs.iter().map(|p| (p.y * 16.0) as usize).collect();
        bands.sort();
        slices.sort();
        assert_eq!(bands, (0..16).collect::<Vec<_>>());
        assert_eq!(slices, (0..16).collect::<Vec<_>>());
    }

    #[test]
    fn golden_ratio_sequence_by_hand() {
        // frac(0.25 + 0 / phi) = 0.25; frac(0.5 + 1 / phi) = 0.118033988749895;
        // frac(0.5 + 2 / phi) = frac(1.736067977499790) = 0.736067977499790.
        assert_eq!(golden(0.25, 0), 0.25);
        assert!((golden(0.5, 1) - 0.118_033_988_749_895).abs() < 1e-15);
        assert!((golden(0.5, 2) - 0.736_067_977_499_790).abs() < 1e-14);
        // The segment's points are the sequence itself, from the stream's one offset.
        let offset = rng(4).next_f64();
        let t = on_segment(Placement::Fibonacci, 3, &mut rng(4));
        assert_eq!(t, (0..3).map(|i| golden(offset, i)).collect::<Vec<_>>());
    }

    #[test]
    fn fibonacci_lattice_bands() {
        // z_i = 1 - (2i + 1)/N: for N = 4, z = 0.75, 0.25, -0.25, -0.75.
        let z: Vec<f64> = on_sphere(Placement::Fibonacci, 4, &mut rng(3))
            .iter()
            .map(|p| p.z)
            .collect();
        for (a, b) in z.iter().zip([0.75, 0.25, -0.25, -0.75]) {
            assert!((a - b).abs() < 1e-15);
        }
    }
}
