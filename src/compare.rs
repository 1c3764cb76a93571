//! Image comparison for students checking their render against the oracle, and for
//! reviews.
//!
//! - [`read`]: the image files read (PNG, PPM / PGM, PFM, EXR, JPEG, BMP, TGA) and what
//!   each converts on the way to 8-bit RGB; [`pfm`] the PFM reader.
//! - [`metrics`]: per-pixel differences in 8-bit levels and their statistics over a set of
//!   pixels: max, RMS, PSNR, percentiles, the fraction beyond a tolerance, FLIP's mean.
//! - [`flip`]: the perceptual metric FLIP per pixel, and its heat-map.
//! - The edges a comparison may judge apart (the pixels whose footprint spans an outline, a
//!   crease or a shadow's edge, so a sampling or anti-aliasing difference there is reported
//!   apart from shading errors) come from the scene, through [`crate::edges`], which traces
//!   it and so sits in a layer above this one.
//! - Here: [`compare`], which judges two images by a [`Rule`] into a [`Report`] with the
//!   worst pixels; and the plain statistics ([`compare_rgb8`]) and level heat-map
//!   ([`heat_map`]) that reviews and studies use.

pub mod flip;
pub mod metrics;
pub mod pfm;
pub mod read;

pub use metrics::{PixelDiffs, Psnr, Stats, stats};
pub use read::{Image, read_image};

use serde::Serialize;
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
/// Peak signal-to-noise ratio of 8-bit images whose mean squared difference is `mse`:
/// `10 log10(255^2 / MSE)` dB, infinite when they are equal.
pub fn psnr_db(mse: f64) -> f64 {
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * libm::log10(255.0 * 255.0 / mse)
    }
}

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
        psnr_db: psnr_db(mse),
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

/// When two images count as equal enough: at most `max_fraction` of the judged pixels
/// differ by more than `tolerance` levels (pbrt's `imgtool diff --difftol` judges so too),
/// and, when `max_flip` is set, their FLIP mean is at most it. The judged pixels are those
/// off edges when edges are known, else all.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Rule {
    pub tolerance: u8,
    pub max_fraction: f64,
    pub max_flip: Option<f64>,
}

impl Default for Rule {
    /// Any pixel beyond 0 levels fails: equal images only.
    fn default() -> Self {
        Rule {
            tolerance: 0,
            max_fraction: 0.0,
            max_flip: None,
        }
    }
}

/// One of the worst pixels.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WorstPixel {
    pub x: u32,
    pub y: u32,
    /// Its colour in the first image (yours) and in the second (the oracle).
    pub a: [u8; 3],
    pub b: [u8; 3],
    /// Its largest channel difference, in levels.
    pub difference: u8,
    pub flip: f32,
}

/// The pixels judged by the rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Judged {
    /// Every pixel (no scene given).
    All,
    /// The pixels off edges.
    OffEdges,
}

/// The metrics on and off edges.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EdgeReport {
    /// Pixels spanning an edge.
    pub pixels: u64,
    /// The metrics of the pixels off edges (`None` when every pixel is an edge).
    pub off_edges: Option<Stats>,
    /// The metrics of the edge pixels (`None` when there are none).
    pub on_edges: Option<Stats>,
}

/// What [`compare`] found.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    pub width: u32,
    pub height: u32,
    pub rule: Rule,
    pub judged: Judged,
    pub pass: bool,
    /// Why the images fail (empty when they pass).
    pub failures: Vec<String>,
    /// The metrics of every pixel.
    pub metrics: Stats,
    pub edges: Option<EdgeReport>,
    /// The judged pixels differing most, largest difference first (then top to bottom, left
    /// to right); only pixels that differ.
    pub worst: Vec<WorstPixel>,
    /// Every pixel's FLIP value, row-major (for its heat-map).
    #[serde(skip)]
    pub flip: Vec<f32>,
}

/// Compares `a` (yours) with `b` (the oracle), RGB8 of `width * height` pixels (at least
/// one), by `rule`, judging the pixels off `edges` when given (a row-major mask, true on
/// edges), and lists the `worst` judged pixels.
pub fn compare(
    a: &[u8],
    b: &[u8],
    width: u32,
    height: u32,
    rule: &Rule,
    edges: Option<&[bool]>,
    worst: usize,
) -> Report {
    let diffs = PixelDiffs::new(a, b, width, height, flip::flip_map(b, a, width, height));
    let all = stats(&diffs, rule.tolerance, |_| true).expect("at least one pixel");
    let edge_report = edges.map(|e| EdgeReport {
        pixels: e.iter().filter(|&&e| e).count() as u64,
        off_edges: stats(&diffs, rule.tolerance, |i| !e[i]),
        on_edges: stats(&diffs, rule.tolerance, |i| e[i]),
    });
    let judged_pixel = |i: usize| edges.is_none_or(|e| !e[i]);
    let (judged, judged_stats) = match &edge_report {
        Some(e) => (Judged::OffEdges, e.off_edges.as_ref()),
        None => (Judged::All, Some(&all)),
    };
    let mut failures = Vec::new();
    if let Some(s) = judged_stats {
        let which = if judged == Judged::OffEdges { " non-edge" } else { "" };
        if s.fraction_beyond_tolerance > rule.max_fraction {
            failures.push(format!(
                "{} of {}{which} pixels ({:.4} %) differ by more than {} levels; allowed: {} % (--max-fraction {})",
                s.beyond_tolerance,
                s.pixels,
                100.0 * s.fraction_beyond_tolerance,
                rule.tolerance,
                100.0 * rule.max_fraction,
                rule.max_fraction
            ));
        }
        if let Some(max_flip) = rule.max_flip
            && s.flip_mean > max_flip
        {
            failures.push(format!(
                "the FLIP mean of the{which} pixels is {:.6}; allowed: {max_flip} (--max-flip)",
                s.flip_mean
            ));
        }
    }
    let mut order: Vec<usize> = (0..diffs.max.len())
        .filter(|&i| judged_pixel(i) && diffs.max[i] > 0)
        .collect();
    // Largest difference first; the row-major index breaks ties (top to bottom, left to right).
    order.sort_by_key(|&i| (std::cmp::Reverse(diffs.max[i]), i));
    let pixel = |rgb: &[u8], i: usize| [rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]];
    let worst = order
        .into_iter()
        .take(worst)
        .map(|i| WorstPixel {
            x: (i % width as usize) as u32,
            y: (i / width as usize) as u32,
            a: pixel(a, i),
            b: pixel(b, i),
            difference: diffs.max[i],
            flip: diffs.flip[i],
        })
        .collect();
    Report {
        width,
        height,
        rule: *rule,
        judged,
        pass: failures.is_empty(),
        failures,
        metrics: all,
        edges: edge_report,
        worst,
        flip: diffs.flip,
    }
}

/// Loads an image file as RGB8 (any format [`read_image`] reads, converted as it says),
/// with the path in the error.
pub fn load_rgb8(path: &Path) -> Result<(u32, u32, Vec<u8>), String> {
    let image = read_image(path)?;
    Ok((image.width, image.height, image.rgb))
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
