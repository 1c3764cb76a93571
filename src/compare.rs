//! Image comparison for students checking their render against the oracle, and for
//! reviews: per-channel 8-bit differences, their maximum and RMS, PSNR, the count of
//! differing pixels, and a heat-map of the difference.

use std::path::Path;

/// Differences between two images of the same size.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Comparison {
    pub width: u32,
    pub height: u32,
    /// Largest per-channel difference, in 8-bit levels.
    pub max_diff: u8,
    /// Root mean square of the per-channel differences, in 8-bit levels.
    pub rms: f64,
    /// Peak signal-to-noise ratio `10 log10(255^2 / MSE)` in dB (infinite when identical).
    pub psnr_db: f64,
    /// Pixels where some channel differs by more than the tolerance.
    pub differing_pixels: u64,
    /// The tolerance used for `differing_pixels`, in levels.
    pub tolerance: u8,
}

/// Compares interleaved RGB8 buffers; `tolerance` is the largest difference not counted.
pub fn compare_rgb8(a: &[u8], b: &[u8], width: u32, height: u32, tolerance: u8) -> Comparison {
    assert_eq!(a.len(), b.len());
    let mut max_diff = 0u8;
    let mut sum_sq = 0u64;
    let mut differing = 0u64;
    for (pa, pb) in a.chunks(3).zip(b.chunks(3)) {
        let mut pixel_max = 0u8;
        for (x, y) in pa.iter().zip(pb) {
            let d = x.abs_diff(*y);
            pixel_max = pixel_max.max(d);
            sum_sq += d as u64 * d as u64;
        }
        max_diff = max_diff.max(pixel_max);
        differing += (pixel_max > tolerance) as u64;
    }
    let mse = sum_sq as f64 / a.len().max(1) as f64;
    Comparison {
        width,
        height,
        max_diff,
        rms: mse.sqrt(),
        psnr_db: if mse == 0.0 {
            f64::INFINITY
        } else {
            10.0 * libm::log10(255.0 * 255.0 / mse)
        },
        differing_pixels: differing,
        tolerance,
    }
}

/// Heat-map of the per-pixel largest channel difference: black = equal, then blue, to red,
/// to white at `scale_max` levels or more.
pub fn heat_map(a: &[u8], b: &[u8], scale_max: u8) -> Vec<u8> {
    a.chunks(3)
        .zip(b.chunks(3))
        .flat_map(|(pa, pb)| {
            let d = pa.iter().zip(pb).map(|(x, y)| x.abs_diff(*y)).max().unwrap_or(0);
            heat_color(d, scale_max.max(1))
        })
        .collect()
}

/// The heat-map colour of a difference `d` on a scale saturating at `max`.
fn heat_color(d: u8, max: u8) -> [u8; 3] {
    if d == 0 {
        return [0, 0, 0];
    }
    let x = (d as f64 / max as f64).min(1.0);
    // 0 -> dark blue, 0.5 -> red, 1 -> white.
    let (r, g, b) = if x < 0.5 {
        (2.0 * x, 0.0, 1.0 - 2.0 * x)
    } else {
        (1.0, 2.0 * x - 1.0, 2.0 * x - 1.0)
    };
    let q = |v: f64| (64.0 + v * 191.0).round() as u8;
    [q(r), if g > 0.0 { q(g) } else { 0 }, if b > 0.0 { q(b) } else { 0 }]
}

/// Loads an image file as RGB8, with the path in the error.
pub fn load_rgb8(path: &Path) -> Result<(u32, u32, Vec<u8>), String> {
    let img = image::open(path).map_err(|e| format!("{}: cannot read the image: {e}", path.display()))?;
    let rgb = img.to_rgb8();
    Ok((rgb.width(), rgb.height(), rgb.into_raw()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_by_hand() {
        // Two pixels; the second differs by (3, 0, 4): max 4, MSE = (9 + 16) / 6 = 4.1667,
        // RMS 2.0412, PSNR = 10 log10(65025 / 4.1667) = 41.933 dB.
        let a = [10, 20, 30, 100, 100, 100];
        let b = [10, 20, 30, 103, 100, 96];
        let c = compare_rgb8(&a, &b, 2, 1, 0);
        assert_eq!(c.max_diff, 4);
        assert!((c.rms - (25.0f64 / 6.0).sqrt()).abs() < 1e-12);
        assert!((c.psnr_db - 41.933).abs() < 1e-3, "{}", c.psnr_db);
        assert_eq!(c.differing_pixels, 1);
        // With a tolerance of 4 levels nothing counts as differing.
        assert_eq!(compare_rgb8(&a, &b, 2, 1, 4).differing_pixels, 0);
        let same = compare_rgb8(&a, &a, 2, 1, 0);
        assert!(same.psnr_db.is_infinite() && same.max_diff == 0);
    }

    #[test]
    fn heat_map_scale() {
        assert_eq!(heat_color(0, 10), [0, 0, 0]);
        assert_eq!(heat_color(10, 10), [255, 255, 255]);
        assert_eq!(heat_color(200, 10), [255, 255, 255]);
        // Half scale: pure red.
        assert_eq!(heat_color(5, 10), [255, 0, 0]);
    }
}
