//! Gains per term: the least-squares fit of an image as a weighted sum of the oracle's
//! layers ([`crate::layers`]), `image ~ background + sum_i g_i layer_i`, each pixel's
//! channel an equation. The terms: ambient, diffuse and specular (the light that arrives
//! through colour filters apart), the light through colour filters (its diffuse and
//! specular), reflected, transmitted and, with caustics, the caustic share. A gain of 1 is the oracle's term; "specular x2.00"
//! is a highlight twice too strong, "through colour filters x0" a shadow filter opaque
//! where the oracle filters by colour.

use crate::layers::PixelLayers;
use glam::DVec3;
use serde::Serialize;

/// The terms fitted, in the order of [`Gain`]s.
pub const TERMS: [&str; 7] = [
    "ambient",
    "diffuse",
    "specular",
    "through colour filters",
    "reflected",
    "transmitted",
    "caustic",
];

/// One term's fitted gain.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Gain {
    pub term: &'static str,
    /// `None` when the term is absent from the judged pixels (nothing to fit).
    pub gain: Option<f64>,
}

/// How far from 1 a gain may be and still count as the oracle's.
pub const GAIN_TOLERANCE: f64 = 0.05;

impl Gain {
    /// `x2.00`, `x0` (below 0.005 in size), `-` when absent.
    pub fn label(&self) -> String {
        match self.gain {
            None => "-".into(),
            Some(g) if g.abs() < 0.005 => "x0".into(),
            Some(g) => format!("x{g:.2}"),
        }
    }

    /// Whether the gain is away from 1 by more than [`GAIN_TOLERANCE`].
    pub fn is_off(&self) -> bool {
        self.gain.is_some_and(|g| (g - 1.0).abs() > GAIN_TOLERANCE)
    }
}

/// The regressors of one pixel: the layers of [`TERMS`], per channel.
fn regressors(p: &PixelLayers) -> [DVec3; TERMS.len()] {
    [
        p.ambient,
        p.diffuse - p.filtered_diffuse,
        p.specular - p.filtered_specular,
        p.filtered_diffuse + p.filtered_specular,
        p.reflected,
        p.transmitted,
        p.caustic,
    ]
}

/// Fits the gains on the pixels given as (layers, the image's linear value): channels
/// that the image or the oracle clip (an image value of 1, an oracle radiance of 1 or more)
/// are left out, as is a term whose layer is 0 on every equation.
pub fn fit(pixels: &[(&PixelLayers, DVec3)]) -> Vec<Gain> {
    const N: usize = TERMS.len();
    let mut ata = [[0.0f64; N]; N];
    let mut atb = [0.0f64; N];
    for (layers, image) in pixels {
        let x = regressors(layers);
        for c in 0..3 {
            let (y, oracle) = (image[c], layers.radiance[c]);
            if y >= 1.0 || oracle >= 1.0 {
                continue;
            }
            let y = y - layers.background[c];
            for i in 0..N {
                atb[i] += x[i][c] * y;
                for j in 0..N {
                    ata[i][j] += x[i][c] * x[j][c];
                }
            }
        }
    }
    let scale = (0..N).map(|i| ata[i][i]).fold(0.0, f64::max);
    let present: Vec<usize> = (0..N)
        .filter(|&i| ata[i][i] > 1e-9 * scale && ata[i][i] > 0.0)
        .collect();
    let solved = solve(
        present
            .iter()
            .map(|&i| present.iter().map(|&j| ata[i][j]).collect())
            .collect(),
        present.iter().map(|&i| atb[i]).collect(),
    );
    TERMS
        .iter()
        .enumerate()
        .map(|(i, &term)| Gain {
            term,
            gain: present
                .iter()
                .position(|&k| k == i)
                .and_then(|k| solved.as_ref().map(|s| s[k])),
        })
        .collect()
}

/// Solves `a x = b` by Gaussian elimination with partial pivoting; `None` when singular.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for col in 0..n {
        let pivot = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[pivot][col].abs() < 1e-300 {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let pivot_row = a[col].clone();
        for row in col + 1..n {
            let f = a[row][col] / pivot_row[col];
            for (x, p) in a[row][col..].iter_mut().zip(&pivot_row[col..]) {
                *x -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let tail: f64 = (row + 1..n).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - tail) / a[row][row];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pixel(ambient: f64, diffuse: f64, specular: f64) -> PixelLayers {
        PixelLayers {
            ambient: DVec3::splat(ambient),
            diffuse: DVec3::new(diffuse, diffuse * 0.5, diffuse * 0.25),
            specular: DVec3::splat(specular),
            radiance: DVec3::splat(ambient + diffuse + specular),
            ..PixelLayers::default()
        }
    }

    #[test]
    fn recovers_exact_gains_and_leaves_absent_terms_out() {
        let layers: Vec<PixelLayers> = (0..20)
            .map(|i| pixel(0.05, 0.02 * i as f64, 0.01 * (i % 7) as f64))
            .collect();
        // The image: ambient x0, diffuse x1, specular x2.
        let pairs: Vec<(&PixelLayers, DVec3)> = layers.iter().map(|p| (p, p.diffuse + 2.0 * p.specular)).collect();
        let gains = fit(&pairs);
        let g = |i: usize| gains[i].gain.unwrap();
        assert!(g(0).abs() < 1e-12, "{gains:?}");
        assert!((g(1) - 1.0).abs() < 1e-12);
        assert!((g(2) - 2.0).abs() < 1e-12);
        assert_eq!(gains[3].gain, None);
        assert_eq!(gains[4].gain, None);
        assert_eq!(
            (gains[0].label(), gains[2].label(), gains[4].label()),
            ("x0".into(), "x2.00".into(), "-".into())
        );
        assert!(gains[2].is_off() && !gains[1].is_off());
    }

    #[test]
    fn fits_the_caustic_share_apart() {
        // A caustic on the diffuse pixels, weighed x0.5 in the image (half the photons'
        // power): its gain is 0.5, the others 1.
        let layers: Vec<PixelLayers> = (0..20)
            .map(|i| {
                let mut p = pixel(0.05, 0.02 * i as f64, 0.01 * (i % 7) as f64);
                p.caustic = DVec3::new(0.3, 0.2, 0.1) * ((i % 3) as f64);
                p.radiance += p.caustic;
                p
            })
            .collect();
        let pairs: Vec<(&PixelLayers, DVec3)> = layers
            .iter()
            .map(|p| (p, p.ambient + p.diffuse + p.specular + 0.5 * p.caustic))
            .collect();
        let gains = fit(&pairs);
        assert_eq!(gains[6].term, "caustic");
        assert!((gains[6].gain.unwrap() - 0.5).abs() < 1e-12, "{gains:?}");
        for g in &gains[..3] {
            assert!((g.gain.unwrap() - 1.0).abs() < 1e-12, "{gains:?}");
        }
    }

    #[test]
    fn solves_a_pivoting_system() {
        // 0 x + 2 y = 4, 3 x + y = 5: x = 1, y = 2.
        let x = solve(vec![vec![0.0, 2.0], vec![3.0, 1.0]], vec![4.0, 5.0]).unwrap();
        assert_eq!(x, vec![1.0, 2.0]);
        assert_eq!(solve(vec![vec![1.0, 2.0], vec![2.0, 4.0]], vec![1.0, 2.0]), None);
    }
}
