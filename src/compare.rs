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
use std::borrow::Cow;
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

/// Where two images differ: the bounding box, in pixels (inclusive), of the pixels where
/// some channel differs by more than a tolerance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DifferingBox {
    pub x: [u32; 2],
    pub y: [u32; 2],
}

impl std::fmt::Display for DifferingBox {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "x {}..{}, y {}..{}", self.x[0], self.x[1], self.y[0], self.y[1])
    }
}

/// The bounding box of the pixels of interleaved RGB8 buffers `a` and `b` (rows of `width`
/// pixels) where some channel differs by more than `tolerance`; `None` where none does.
pub fn differing_box(a: &[u8], b: &[u8], width: u32, tolerance: u8) -> Option<DifferingBox> {
    let mut found: Option<DifferingBox> = None;
    for (i, (pa, pb)) in a.chunks_exact(3).zip(b.chunks_exact(3)).enumerate() {
        if pa.iter().zip(pb).all(|(x, y)| x.abs_diff(*y) <= tolerance) {
            continue;
        }
        let (x, y) = ((i % width.max(1) as usize) as u32, (i / width.max(1) as usize) as u32);
        let r = found.get_or_insert(DifferingBox { x: [x, x], y: [y, y] });
        r.x = [r.x[0].min(x), r.x[1].max(x)];
        r.y = [r.y[0].min(y), r.y[1].max(y)];
    }
    found
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

/// The metrics on and off edges (of the drawn pixels).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EdgeReport {
    /// Drawn pixels spanning an edge.
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
    /// Pixels left out of every metric: transparent black (alpha and colour 0), never drawn.
    pub undrawn: u64,
    /// The metrics of every drawn pixel.
    pub metrics: Stats,
    pub edges: Option<EdgeReport>,
    /// The judged pixels differing most, largest difference first (then top to bottom, left
    /// to right); only pixels that differ.
    pub worst: Vec<WorstPixel>,
    /// Every pixel's FLIP value, row-major (for its heat-map); 0 where undrawn.
    #[serde(skip)]
    pub flip: Vec<f32>,
}

/// The pixels a comparison leaves out or judges apart: row-major masks of one flag a pixel.
#[derive(Clone, Copy, Debug, Default)]
pub struct Masks<'a> {
    /// True on the pixels spanning an edge, when the scene is known.
    pub edges: Option<&'a [bool]>,
    /// True on the pixels never drawn (transparent black, [`read::Image::undrawn`]), as
    /// SIMRenderer's console mode leaves the last rows of an image wider than tall; empty
    /// when every pixel is drawn.
    pub undrawn: &'a [bool],
}

/// Compares `a` (yours) with `b` (the oracle), RGB8 of `width * height` pixels, by `rule`:
/// the undrawn pixels of `masks` are left out of every metric (at least one pixel must be
/// drawn), the others judged off its edges when they are given, and the `worst` judged
/// pixels listed.
pub fn compare(a: &[u8], b: &[u8], width: u32, height: u32, rule: &Rule, masks: Masks, worst: usize) -> Report {
    let Masks { edges, undrawn } = masks;
    let n = width as usize * height as usize;
    assert!(undrawn.is_empty() || undrawn.len() == n, "one undrawn flag a pixel");
    let drawn = |i: usize| undrawn.is_empty() || !undrawn[i];
    let a = &*undrawn_from_oracle(a, b, undrawn);
    let mut flip = flip::flip_map(b, a, width, height);
    for (i, v) in flip.iter_mut().enumerate() {
        if !drawn(i) {
            *v = 0.0;
        }
    }
    let diffs = PixelDiffs::new(a, b, width, height, flip);
    let all = stats(&diffs, rule.tolerance, drawn).expect("at least one drawn pixel");
    let edge_report = edges.map(|e| {
        let on_edges = stats(&diffs, rule.tolerance, |i| drawn(i) && e[i]);
        EdgeReport {
            pixels: on_edges.as_ref().map_or(0, |s| s.pixels),
            off_edges: stats(&diffs, rule.tolerance, |i| drawn(i) && !e[i]),
            on_edges,
        }
    });
    let judged_pixel = |i: usize| drawn(i) && edges.is_none_or(|e| !e[i]);
    let (judged, judged_stats) = match &edge_report {
        Some(e) => (Judged::OffEdges, e.off_edges.as_ref()),
        None => (Judged::All, Some(&all)),
    };
    let undrawn = (n - all.pixels as usize) as u64;
    let mut failures = Vec::new();
    if let Some(s) = judged_stats {
        let which = match (undrawn > 0, judged == Judged::OffEdges) {
            (false, false) => "",
            (false, true) => " non-edge",
            (true, false) => " drawn",
            (true, true) => " drawn non-edge",
        };
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
        undrawn,
        metrics: all,
        edges: edge_report,
        worst,
        flip: diffs.flip,
    }
}

/// `a` (yours) with its `undrawn` pixels (a row-major mask, or empty) in the oracle's
/// colour from `b`: they differ by nothing, and FLIP's filters see no difference spreading
/// from them into the drawn pixels around them.
pub fn undrawn_from_oracle<'a>(a: &'a [u8], b: &[u8], undrawn: &[bool]) -> Cow<'a, [u8]> {
    if !undrawn.contains(&true) {
        return Cow::Borrowed(a);
    }
    let mut filled = a.to_vec();
    for (i, _) in undrawn.iter().enumerate().filter(|(_, u)| **u) {
        filled[3 * i..3 * i + 3].copy_from_slice(&b[3 * i..3 * i + 3]);
    }
    Cow::Owned(filled)
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
    fn undrawn_pixels_are_left_out_of_every_metric() {
        // Four pixels; yours leaves the last undrawn (black), where the oracle is
        // (200, 100, 50), and the first differs by (2, 0, 0). Drawn: 3 pixels, max 2,
        // MSE = 4 / 9, RMS 0.6667, one beyond 0 levels.
        let a = [10, 10, 10, 20, 20, 20, 30, 30, 30, 0, 0, 0];
        let b = [12, 10, 10, 20, 20, 20, 30, 30, 30, 200, 100, 50];
        let undrawn = [false, false, false, true];
        let masks = Masks {
            edges: None,
            undrawn: &undrawn,
        };
        let r = compare(&a, &b, 2, 2, &Rule::default(), masks, 10);
        assert_eq!((r.undrawn, r.metrics.pixels, r.metrics.max), (1, 3, 2));
        assert!((r.metrics.rms - 2.0 / 3.0).abs() < 1e-12, "{}", r.metrics.rms);
        assert_eq!(r.metrics.beyond_tolerance, 1);
        assert_eq!(r.worst.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>(), [(0, 0)]);
        assert_eq!(
            r.failures,
            ["1 of 3 drawn pixels (33.3333 %) differ by more than 0 levels; allowed: 0 % (--max-fraction 0)"]
        );
        assert_eq!(r.flip[3], 0.0);
        // Read as drawn, the black pixel is 200 levels off.
        let whole = compare(&a, &b, 2, 2, &Rule::default(), Masks::default(), 10);
        assert_eq!((whole.undrawn, whole.metrics.pixels, whole.metrics.max), (0, 4, 200));
        // With edges, an undrawn edge pixel is in neither set.
        let edges = [true, false, false, true];
        let masks = Masks {
            edges: Some(&edges),
            undrawn: &undrawn,
        };
        let e = compare(&a, &b, 2, 2, &Rule::default(), masks, 10).edges.unwrap();
        assert_eq!(e.pixels, 1);
        assert_eq!(e.on_edges.map(|s| (s.pixels, s.max)), Some((1, 2)));
        assert_eq!(e.off_edges.map(|s| (s.pixels, s.max)), Some((2, 0)));
        // The level heat-map's input: the undrawn pixel in the oracle's colour.
        assert_eq!(&undrawn_from_oracle(&a, &b, &undrawn)[9..], [200, 100, 50]);
        assert!(matches!(undrawn_from_oracle(&a, &b, &[]), Cow::Borrowed(_)));
    }

    #[test]
    fn the_differing_box_bounds_the_pixels_beyond_the_tolerance() {
        // A 4 x 3 image: (1, 0) differs by 5 levels, (3, 2) by 1, (2, 1) by 9.
        let a = [0u8; 36];
        let mut b = a;
        b[3] = 5;
        b[(2 * 4 + 3) * 3 + 2] = 1;
        b[(4 + 2) * 3 + 1] = 9;
        let all = differing_box(&a, &b, 4, 0).unwrap();
        assert_eq!(all, DifferingBox { x: [1, 3], y: [0, 2] });
        assert_eq!(all.to_string(), "x 1..3, y 0..2");
        assert_eq!(differing_box(&a, &b, 4, 4).unwrap().to_string(), "x 1..2, y 0..1");
        assert_eq!(differing_box(&a, &b, 4, 5).unwrap().to_string(), "x 2..2, y 1..1");
        assert_eq!(differing_box(&a, &b, 4, 9), None);
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
