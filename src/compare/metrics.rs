//! The difference metrics of a set of pixels, from per-pixel differences in 8-bit levels.
//!
//! A pixel's difference `d` is its largest channel difference `max_c |a_c - b_c|`. Over
//! the `n` pixels of a set (all, or those off or on object edges):
//! - `max`: the largest `d`;
//! - `rms`: `sqrt(sum of (a_c - b_c)^2 over the set's channels / 3n)`;
//! - `psnr_db`: `10 log10(255^2 / MSE)`, infinite when the pixels are equal;
//! - `p50`, `p99`, `p999`: nearest-rank percentiles of `d`: the `ceil(q n)`-th smallest;
//! - `beyond_tolerance`: pixels with `d > tolerance`, and their fraction of `n`;
//! - `flip_mean`, `flip_max`: the mean (summed in double precision) and the largest of the
//!   pixels' FLIP values (see [`super::flip`]).

use serde::Serialize;

/// Per-pixel differences of two images of the same size.
#[derive(Clone, Debug, PartialEq)]
pub struct PixelDiffs {
    pub width: u32,
    pub height: u32,
    /// Each pixel's largest channel difference, in levels.
    pub max: Vec<u8>,
    /// Each pixel's sum of squared channel differences.
    pub squares: Vec<u32>,
    /// Each pixel's FLIP value in [0, 1].
    pub flip: Vec<f32>,
}

impl PixelDiffs {
    /// The level differences of interleaved RGB8 buffers (of `width * height` pixels), with
    /// the FLIP values `flip`.
    pub fn new(a: &[u8], b: &[u8], width: u32, height: u32, flip: Vec<f32>) -> Self {
        let n = width as usize * height as usize;
        assert!(a.len() == 3 * n && b.len() == 3 * n && flip.len() == n, "sizes");
        let (mut max, mut squares) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for (pa, pb) in a.chunks_exact(3).zip(b.chunks_exact(3)) {
            let d = [0, 1, 2].map(|c| pa[c].abs_diff(pb[c]));
            max.push(d[0].max(d[1]).max(d[2]));
            squares.push(d.iter().map(|&d| d as u32 * d as u32).sum());
        }
        PixelDiffs {
            width,
            height,
            max,
            squares,
            flip,
        }
    }
}

/// A PSNR in dB, written in JSON as a number, or the string `"inf"` for equal pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Psnr(pub f64);

impl Serialize for Psnr {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        if self.0.is_finite() {
            s.serialize_f64(self.0)
        } else {
            s.serialize_str("inf")
        }
    }
}

impl std::fmt::Display for Psnr {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0.is_finite() {
            write!(f, "{:.2} dB", self.0)
        } else {
            write!(f, "infinite (equal)")
        }
    }
}

/// The metrics of a set of pixels (see the module's documentation).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stats {
    pub pixels: u64,
    pub max: u8,
    pub rms: f64,
    pub psnr_db: Psnr,
    pub p50: u8,
    pub p99: u8,
    pub p999: u8,
    pub tolerance: u8,
    pub beyond_tolerance: u64,
    pub fraction_beyond_tolerance: f64,
    pub flip_mean: f64,
    pub flip_max: f32,
}

/// The metrics of the pixels `i` for which `keep(i)` holds; `None` when there are none.
pub fn stats(d: &PixelDiffs, tolerance: u8, keep: impl Fn(usize) -> bool) -> Option<Stats> {
    let mut histogram = [0u64; 256];
    let (mut n, mut sum_sq, mut beyond, mut flip_sum, mut flip_max) = (0u64, 0u64, 0u64, 0f64, 0f32);
    for i in (0..d.max.len()).filter(|&i| keep(i)) {
        n += 1;
        histogram[d.max[i] as usize] += 1;
        sum_sq += d.squares[i] as u64;
        beyond += (d.max[i] > tolerance) as u64;
        flip_sum += d.flip[i] as f64;
        flip_max = flip_max.max(d.flip[i]);
    }
    if n == 0 {
        return None;
    }
    let mse = sum_sq as f64 / (3 * n) as f64;
    // The `ceil(q n)`-th smallest difference, q = per_mille / 1000.
    let percentile = |per_mille: u64| {
        let rank = (n * per_mille).div_ceil(1000).max(1);
        let mut seen = 0;
        (0..=255u8)
            .find(|&v| {
                seen += histogram[v as usize];
                seen >= rank
            })
            .unwrap_or(255)
    };
    Some(Stats {
        pixels: n,
        max: (0..=255u8).rev().find(|&v| histogram[v as usize] > 0).unwrap_or(0),
        rms: mse.sqrt(),
        psnr_db: Psnr(super::psnr_db(mse)),
        p50: percentile(500),
        p99: percentile(990),
        p999: percentile(999),
        tolerance,
        beyond_tolerance: beyond,
        fraction_beyond_tolerance: beyond as f64 / n as f64,
        flip_mean: flip_sum / n as f64,
        flip_max,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 x 2 pair whose pixels differ by (0,0,0), (3,0,4), (0,10,0), (1,1,1).
    fn two_by_two() -> PixelDiffs {
        let a = [10, 20, 30, 100, 100, 100, 50, 50, 50, 0, 0, 0];
        let b = [10, 20, 30, 103, 100, 96, 50, 60, 50, 1, 1, 1];
        PixelDiffs::new(&a, &b, 2, 2, vec![0.0, 0.25, 0.5, 0.125])
    }

    #[test]
    fn metrics_by_hand() {
        let d = two_by_two();
        assert_eq!(d.max, [0, 4, 10, 1]);
        assert_eq!(d.squares, [0, 25, 100, 3]);
        let s = stats(&d, 1, |_| true).unwrap();
        assert_eq!((s.pixels, s.max), (4, 10));
        // MSE = (25 + 100 + 3) / 12 = 10.6667; RMS 3.2660; PSNR 10 log10(65025 / 10.6667)
        // = 10 log10(6096.09) = 37.8505 dB.
        assert_eq!(s.rms, (128.0f64 / 12.0).sqrt());
        assert!((s.psnr_db.0 - 37.850_5).abs() < 1e-4, "{:?}", s.psnr_db);
        // Sorted differences 0, 1, 4, 10: p50 is the 2nd (ceil(0.5 x 4)), p99 and p99.9 the 4th.
        assert_eq!((s.p50, s.p99, s.p999), (1, 10, 10));
        // Beyond 1 level: the pixels of 4 and 10.
        assert_eq!((s.beyond_tolerance, s.fraction_beyond_tolerance), (2, 0.5));
        assert_eq!((s.flip_mean, s.flip_max), (0.21875, 0.5));
        // The pixels with no difference above 4: 0 and 1 (indices 0 and 3).
        let low = stats(&d, 0, |i| d.max[i] <= 1).unwrap();
        assert_eq!((low.pixels, low.max, low.p50, low.beyond_tolerance), (2, 1, 0, 1));
        assert_eq!(low.rms, (3.0f64 / 6.0).sqrt());
        assert!(stats(&d, 0, |_| false).is_none());
    }

    #[test]
    fn equal_images_have_infinite_psnr_written_inf() {
        let a = [7u8; 12];
        let s = stats(&PixelDiffs::new(&a, &a, 2, 2, vec![0.0; 4]), 0, |_| true).unwrap();
        assert_eq!((s.max, s.rms, s.p999, s.beyond_tolerance), (0, 0.0, 0, 0));
        assert!(s.psnr_db.0.is_infinite());
        assert_eq!(serde_json::to_value(s.psnr_db).unwrap(), "inf");
        assert_eq!(serde_json::to_value(Psnr(31.5)).unwrap(), 31.5);
        assert_eq!(s.psnr_db.to_string(), "infinite (equal)");
    }

    #[test]
    fn percentiles_of_a_thousand_pixels() {
        // Differences 0..=9, each on 100 pixels but 9 on 99 and 200 on one.
        let mut max: Vec<u8> = (0..1000).map(|i| (i / 100) as u8).collect();
        max[999] = 200;
        let d = PixelDiffs {
            width: 1000,
            height: 1,
            squares: max.iter().map(|&m| m as u32 * m as u32).collect(),
            max,
            flip: vec![0.0; 1000],
        };
        let s = stats(&d, 0, |_| true).unwrap();
        // 500th smallest: 4; 990th: 9; 999th: 9; the 1000th (the max) is 200.
        assert_eq!((s.p50, s.p99, s.p999, s.max), (4, 9, 9, 200));
    }
}
