//! `lumiere diagnose`: what is most likely wrong in a student's image of a scene.
//!
//! - [`gains`]: the gain of each term of the oracle's layers ([`crate::layers`]) that fits
//!   the image best by least squares ("specular x2.00", "ambient x0").
//! - [`mistakes`]: a catalogue of named mistakes, each rendered by the reference tracer
//!   with a wrong formula table, a convention switched, or a post-process of the oracle's
//!   image (gamma, a flip, red and blue exchanged); and one fitted to each image, the
//!   specular exponent ([`exponent`]).
//! - [`report`]: the HTML report with the images, heat-maps and ranking.
//! - Here: [`diagnose`], which renders the oracle and every mistake on the same pixels,
//!   counts in each the pixels off edges ([`crate::edges`]) that differ from the image by
//!   more than the tolerance, and ranks the mistakes by it; [`Oracle`] holds those renders
//!   to diagnose many images of one scene (a class's) for the price of one.
//!
//! The specular exponent is the one mistake with a value to find: for each image that
//! differs beyond sampling, the factor of every material's exponent is fitted on the pixels
//! beyond the tolerance against the oracle (at most [`MAX_FIT_PIXELS`] of them:
//! [`exponent::fit_factor`]), and the scene rendered with it on the grid is ranked with the
//! other mistakes, before a rendered one only when clearly closer ([`best_first`]): a
//! factor fitted to the image also fits some of what its sampling does. The renders a fit
//! makes depend only on the scene, the factor and the pixels, and the [`Oracle`] keeps them
//! for its next images (`ExponentRenders`).
//!
//! The image matches the oracle, "no mistake found", when at most `max_fraction` of the
//! judged pixels are *beyond any sampling*: some channel lies more than the tolerance
//! outside the range of the oracle's values over the pixel's footprint (the points
//! [`crate::edges`] looks at), so an image sampled at other points of each pixel (another
//! seed, sample count or sample position) matches. A mistake makes no visible difference
//! on a scene when its own render matches the oracle so; when its render still leaves fewer
//! pixels beyond the tolerance than the oracle's and explains at least half of them (an
//! image sampled at each pixel's corner against a centre-sampled oracle), it is named
//! apart, as what the image follows within sampling.
//!
//! On a large image the pixels judged are a regular grid of every `stride`-th pixel of
//! every `stride`-th row, at most [`Options::max_pixels`] of them: a mistake shows on a
//! region, not on a single pixel, and the catalogue renders in seconds so.

pub mod exponent;
pub mod gains;
pub mod mistakes;
pub mod report;

use crate::edges::{footprint, is_edge};
use crate::film::{Normalization, level_value, rgb8_encoded, srgb_decode, srgb_encode, unrounded_level};
use crate::layers::{PixelLayers, pixel_layers};
use crate::limits::MAX_DEPTH;
use crate::render::{camera_ray, render_pixels_with};
use crate::scene::Scene;
use crate::trace::{Formulas, Reference, SampleKey, Tracer};
use crate::world::World;
use exponent::ExponentFit;
use gains::Gain;
use glam::DVec3;
use mistakes::{Change, Mistake, catalogue, convention_value, exponent_scaled, shown_exponents};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::HashMap;
use std::sync::{Mutex, PoisonError};

/// The rule and the budget of a diagnosis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Largest per-channel difference (8-bit levels) that counts as equal.
    pub tolerance: u8,
    /// Largest fraction of the judged pixels beyond the tolerance for the image to match.
    pub max_fraction: f64,
    /// Most pixels judged: beyond, a regular grid of every `stride`-th pixel.
    pub max_pixels: usize,
    /// The oracle's images are sRGB-encoded (`render --srgb`): its renders are encoded so
    /// before quantisation, and the gains fit the image decoded back to linear.
    pub srgb: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            tolerance: 8,
            max_fraction: 0.005,
            max_pixels: 40_000,
            srgb: false,
        }
    }
}

/// The pixels judged: every `stride`-th pixel of every `stride`-th row, from (0, 0).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Grid {
    pub stride: u32,
    /// The grid's size: `ceil(width / stride) x ceil(height / stride)`.
    pub width: u32,
    pub height: u32,
}

impl Grid {
    /// The grid of at most `max_pixels` points over a `width x height` image.
    pub fn new(width: u32, height: u32, max_pixels: usize) -> Grid {
        let area = width as f64 * height as f64;
        let stride = (area / max_pixels.max(1) as f64).sqrt().ceil().max(1.0) as u32;
        Grid {
            stride,
            width: width.div_ceil(stride),
            height: height.div_ceil(stride),
        }
    }

    /// The pixels judged, in words: `every pixel`, or `every 2nd pixel of every 2nd row`
    /// (the text's and the report's wording).
    pub fn describe(&self) -> String {
        if self.stride == 1 {
            return "every pixel".to_string();
        }
        let n = self.stride;
        let suffix = match (n % 10, n % 100) {
            (_, 11..=13) => "th",
            (1, _) => "st",
            (2, _) => "nd",
            (3, _) => "rd",
            _ => "th",
        };
        format!("every {n}{suffix} pixel of every {n}{suffix} row")
    }

    /// The image pixels of the grid, row-major.
    pub fn pixels(&self) -> Vec<(u32, u32)> {
        (0..self.height)
            .flat_map(|j| (0..self.width).map(move |i| (i * self.stride, j * self.stride)))
            .collect()
    }
}

/// How far an image is from another over the judged pixels.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Score {
    /// Judged pixels where some channel differs by more than the tolerance.
    pub beyond: usize,
    pub judged: usize,
    /// `beyond / judged`.
    pub fraction: f64,
    /// Root mean square of the channel differences, in 8-bit levels.
    pub rms: f64,
}

/// Judged pixels a mistake fixes (beyond the tolerance against the oracle, within it
/// against the mistake), with their bounding box in image pixels (inclusive).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Region {
    pub pixels: usize,
    pub x: [u32; 2],
    pub y: [u32; 2],
}

/// One mistake rendered and scored against the image.
#[derive(Clone, Debug, Serialize)]
pub struct Candidate {
    pub name: &'static str,
    pub description: &'static str,
    /// What kind of change the mistake makes ([`Change::kind`]): `post-process` for one
    /// applied to the finished image (gamma, a flip, red and blue exchanged).
    pub kind: &'static str,
    /// For the mistake fitted to the image, the specular exponent, what the fit found.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fitted: Option<ExponentFit>,
    /// The image against this mistake's render.
    pub score: Score,
    /// The pixels it fixes; `None` when it fixes none.
    pub fixes: Option<Region>,
    /// Whether its render differs from the oracle's beyond the rule (else it makes no
    /// visible difference on this scene, and cannot be told from a correct image).
    pub visible: bool,
    /// The mistake's render on the grid, 8-bit RGB.
    #[serde(skip)]
    pub rgb: Vec<u8>,
}

/// What the diagnosis concludes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// The image matches the oracle within the rule.
    NoMistakeFound,
    /// The best mistake of the catalogue brings the image closer than the oracle and explains
    /// at least half of the pixels beyond the tolerance.
    MistakeFound,
    /// Mistakes of the catalogue bring the image closer, but the best explains less than
    /// half of the pixels beyond: the image holds something the catalogue does not name
    /// (grey output, several mistakes at once).
    PartlyExplained,
    /// The image differs and no mistake of the catalogue brings it closer.
    Unexplained,
}

impl Verdict {
    /// The verdict in words, as the text and the report print it.
    pub fn words(self) -> &'static str {
        match self {
            Verdict::NoMistakeFound => "no mistake found",
            Verdict::MistakeFound => "mistake found",
            Verdict::PartlyExplained => {
                "the image differs; the closest mistakes of the catalogue explain less than half of it"
            }
            Verdict::Unexplained => "the image differs; no mistake of the catalogue explains it",
        }
    }

    /// Whether the diagnosis names mistakes (the closest ones) for the image.
    pub fn names_mistakes(self) -> bool {
        matches!(self, Verdict::MistakeFound | Verdict::PartlyExplained)
    }
}

/// A diagnosis.
#[derive(Clone, Debug, Serialize)]
pub struct Diagnosis {
    pub width: u32,
    pub height: u32,
    pub grid: Grid,
    pub tolerance: u8,
    pub max_fraction: f64,
    /// Grid pixels on an edge (left out of every score).
    pub edges: usize,
    /// Grid pixels the image leaves undrawn (transparent black: the mask given to
    /// [`Oracle::diagnose_drawn`]), left out of every score.
    pub undrawn: usize,
    /// The image against the oracle.
    pub oracle: Score,
    /// Whether the image is black, every drawn pixel 0 in every channel, where some drawn
    /// pixel of the oracle's (on the grid) is not: the ranking then only says which mistake
    /// draws the darkest image.
    pub black: bool,
    /// Judged pixels of the image beyond any sampling of the oracle (see the module's
    /// documentation): what the verdict counts.
    pub beyond_sampling: usize,
    pub verdict: Verdict,
    /// With a mistake found, whether something else differs too ([`differs_besides`]): the
    /// first mistake leaves beyond the tolerance at least half as many pixels as it
    /// explains, and more than the rule lets sampling leave, at more than
    /// [`CLEARLY_CLOSER_RMS`] of the oracle's RMS.
    pub also_differs: bool,
    pub gains: Vec<Gain>,
    /// Sentences read from the gains; none when the image matches the oracle within
    /// sampling (a gain fitted to sampling differences alone says nothing of the shading).
    pub findings: Vec<String>,
    /// Whether the text and the report print the findings: not when the first mistake
    /// named is a post-process (`kind` `post-process`), since the gains fit the image as
    /// written, before that post-process is undone (a flipped image's lit pixels face the
    /// oracle's unlit ones).
    pub findings_shown: bool,
    /// The visible mistakes, best first (fewest pixels beyond, then smallest RMS; ties in
    /// catalogue order), the fitted specular exponent before the first rendered mistake it is
    /// clearly closer than: fewer pixels beyond by more than sampling may leave, or at most
    /// three quarters of its RMS.
    pub ranking: Vec<Candidate>,
    /// The mistakes within sampling of the oracle on this scene whose render brings the
    /// image no closer: nothing tells them from a correct image here.
    pub not_visible: Vec<&'static str>,
    /// The mistakes within sampling of the oracle whose render leaves fewer pixels beyond
    /// the tolerance than the oracle's and explains at least half of the oracle's (an
    /// image with gamma applied, a grey or a JPEG image is a few pixels nearer some of
    /// them, by chance), best first: what the image follows within sampling, such as
    /// SIMRenderer's sample position.
    pub within_sampling: Vec<Candidate>,
    /// The mistakes that do not apply (a convention the oracle already follows).
    pub not_applicable: Vec<&'static str>,
    /// The image and the oracle on the grid, and the grid's edge mask.
    #[serde(skip)]
    pub image_rgb: Vec<u8>,
    #[serde(skip)]
    pub oracle_rgb: Vec<u8>,
    #[serde(skip)]
    pub edge_mask: Vec<bool>,
}

impl Diagnosis {
    /// The best `n` mistakes that bring the image closer than the oracle.
    pub fn top(&self, n: usize) -> impl Iterator<Item = &Candidate> {
        self.ranking
            .iter()
            .filter(|c| c.fixes.is_some() && closer(&c.score, &self.oracle))
            .take(n)
    }
}

/// Whether `score` is closer than `than`: fewer pixels beyond, or as many and a smaller RMS.
fn closer(score: &Score, than: &Score) -> bool {
    (score.beyond, score.rms) < (than.beyond, than.rms)
}

/// Candidates sorted best first: the rendered mistakes by fewest pixels beyond, then
/// smallest RMS, ties in catalogue order (the sort is stable); the fitted one, the specular
/// exponent, before the first of them it is clearly closer than ([`clearly_closer`]), else
/// last.
fn best_first(candidates: &mut Vec<Candidate>, allowance: usize) {
    let fitted = candidates
        .iter()
        .position(|c| c.fitted.is_some())
        .map(|i| candidates.remove(i));
    candidates.sort_by(|a, b| {
        (a.score.beyond, a.score.rms)
            .partial_cmp(&(b.score.beyond, b.score.rms))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    if let Some(fitted) = fitted {
        let at = candidates
            .iter()
            .position(|c| clearly_closer(&fitted.score, &c.score, allowance))
            .unwrap_or(candidates.len());
        candidates.insert(at, fitted);
    }
}

/// The largest ratio of a fitted mistake's RMS to a rendered one's at which it counts as
/// clearly closer ([`clearly_closer`]).
const CLEARLY_CLOSER_RMS: f64 = 0.75;

/// Whether a fitted mistake's `score` is clearly closer than a rendered mistake's `than`:
/// fewer pixels beyond by more than `allowance` (what the rule lets sampling leave), or
/// closer ([`closer`]) at no more than [`CLEARLY_CLOSER_RMS`] of its RMS. A factor fitted
/// to the image also fits what the image's sampling does: on the reference scene at 96 x 72,
/// a 2 x 2 jittered image made with Phong's term for Blinn's leaves 11 pixels beyond at RMS
/// 0.77 with Blinn's term at 4.24 times the exponent, 13 at 0.79 with Phong's; the image
/// made with four times the exponent gives 11 at 0.76 and 13 at 0.81. Nothing there tells
/// the two apart, and the mistake with nothing fitted is named first.
fn clearly_closer(score: &Score, than: &Score, allowance: usize) -> bool {
    score.beyond + allowance < than.beyond || (closer(score, than) && score.rms <= CLEARLY_CLOSER_RMS * than.rms)
}

/// The squared differences, in 8-bit levels, between the channels of `radiance` as the film
/// writes them before rounding (normalized, encoded, clamped to [0, 1]) and `levels`: a cost
/// that moves with the radiance where the rounded levels move by steps.
fn squared_level_error(radiance: DVec3, levels: &[u8], output: Output) -> f64 {
    output
        .normalization
        .apply(radiance)
        .to_array()
        .into_iter()
        .zip(levels)
        .map(|(c, &level)| (unrounded_level((output.encode)(c)) - level as f64).powi(2))
        .sum()
}

/// 8-bit RGB of radiances, as the film writes them ([`Output::rgb8`]).
fn to_rgb8(radiance: &[DVec3], output: Output) -> Vec<u8> {
    radiance.iter().flat_map(|&p| output.rgb8(p)).collect()
}

fn linear(c: f64) -> f64 {
    c
}

/// How the oracle writes a radiance in 8 bits, as the film does: the scene's colour
/// normalization ([`Normalization::apply`]: SIMRenderer's `division_factor` divides a colour
/// by its largest channel above 1), then a transfer on each channel (none, or sRGB's), then
/// clamping and rounding ([`quantize`](crate::film::quantize)).
#[derive(Clone, Copy)]
struct Output {
    normalization: Normalization,
    encode: fn(f64) -> f64,
}

impl Output {
    /// The oracle's: the scene's normalization, and the sRGB transfer with `srgb`.
    fn of(scene: &Scene, srgb: bool) -> Output {
        Output {
            normalization: scene.settings.color_normalization,
            encode: if srgb { srgb_encode } else { linear },
        }
    }

    fn rgb8(self, c: DVec3) -> [u8; 3] {
        rgb8_encoded(c, self.normalization, self.encode)
    }
}

/// The largest channel difference of pixel `i`.
fn pixel_diff(a: &[u8], b: &[u8], i: usize) -> u8 {
    (0..3).map(|c| a[3 * i + c].abs_diff(b[3 * i + c])).max().unwrap_or(0)
}

/// Per pixel of `pixels`, the oracle's 8-bit values over its footprint: the lowest and the
/// highest of each channel, one camera sample at each point ([`footprint`]).
fn footprint_ranges(world: &World, pixels: &[(u32, u32)], output: Output) -> Vec<[[u8; 3]; 2]> {
    let width = world.scene.settings.width as u64;
    pixels
        .par_iter()
        .with_min_len(16)
        .map_init(
            || Reference::new(world),
            |tracer, &(x, y)| {
                let key = SampleKey {
                    pixel: y as u64 * width + x as u64,
                    sample: 0,
                };
                footprint(world, x, y).fold([[u8::MAX; 3], [0; 3]], |[lo, hi], position| {
                    let c = tracer.camera(&camera_ray(world, position), key);
                    let q = output.rgb8(c);
                    [
                        std::array::from_fn(|i| lo[i].min(q[i])),
                        std::array::from_fn(|i| hi[i].max(q[i])),
                    ]
                })
            },
        )
        .collect()
}

/// Judged pixels of `image` some channel of which is more than `tolerance` outside its
/// pixel's range in `ranges`.
fn beyond_ranges(image: &[u8], ranges: &[[[u8; 3]; 2]], judged: &[bool], tolerance: u8) -> usize {
    ranges
        .iter()
        .enumerate()
        .filter(|&(i, [lo, hi])| {
            judged[i]
                && (0..3).any(|c| {
                    let v = image[3 * i + c];
                    v < lo[c].saturating_sub(tolerance) || v > hi[c].saturating_add(tolerance)
                })
        })
        .count()
}

/// `a` against `b` over the pixels where `judged` holds.
fn score(a: &[u8], b: &[u8], judged: &[bool], tolerance: u8) -> Score {
    let (mut beyond, mut count, mut sum_sq) = (0, 0, 0u64);
    for (i, _) in judged.iter().enumerate().filter(|(_, j)| **j) {
        count += 1;
        beyond += usize::from(pixel_diff(a, b, i) > tolerance);
        sum_sq += (0..3)
            .map(|c| (a[3 * i + c].abs_diff(b[3 * i + c]) as u64).pow(2))
            .sum::<u64>();
    }
    Score {
        beyond,
        judged: count,
        fraction: beyond as f64 / count.max(1) as f64,
        rms: (sum_sq as f64 / (3 * count).max(1) as f64).sqrt(),
    }
}

/// Radiances and the [`Output`] their 8-bit values go through.
type Encoded = (Vec<DVec3>, Output);

/// The radiance of the grid's pixels as the scene renders with `change` (`None`: the
/// oracle's, given as `oracle`); `None` when the change does not apply to this scene.
fn render_change(
    scene: &Scene,
    world: &World,
    pixels: &[(u32, u32)],
    oracle: &[DVec3],
    change: Change,
    srgb: bool,
) -> Option<Encoded> {
    let output = Output::of(scene, srgb);
    match change {
        Change::Formulas(f) => Some((render_pixels_with(world, f, pixels), output)),
        // An image the oracle writes sRGB-encoded already has its gamma.
        Change::Gamma => (!srgb).then(|| {
            let gamma = Output {
                encode: srgb_encode,
                ..output
            };
            (oracle.to_vec(), gamma)
        }),
        Change::FlipVertical | Change::FlipHorizontal => {
            let (w, h) = (scene.settings.width, scene.settings.height);
            let flipped: Vec<(u32, u32)> = pixels.iter().map(|&p| change.source_pixel(p, w, h)).collect();
            Some((render_pixels_with(world, Formulas::CHAPTER, &flipped), output))
        }
        Change::SwapRedBlue => Some((oracle.iter().map(|&c| change.written_colour(c)).collect(), output)),
        Change::SpecularExponent(factor) => {
            let shows = !shown_exponents(scene).is_empty();
            shows.then(|| (render_pixels_with(world, exponent_scaled(factor), pixels), output))
        }
        Change::Depth(step) => {
            let depth = scene
                .settings
                .depth
                .checked_add_signed(step)
                .filter(|d| (1..=MAX_DEPTH).contains(d))?;
            Some((render_changed(scene, pixels, |s| s.settings.depth = depth), output))
        }
        Change::Convention(key) => {
            let value = convention_value(&scene.settings.conventions, key)?;
            let mut conventions = scene.settings.conventions;
            conventions.set(key, &value).ok()?;
            Some((
                render_changed(scene, pixels, |s| s.set_conventions(conventions)),
                output,
            ))
        }
    }
}

/// The radiance of `pixels` with the chapter's formulas on a copy of `scene` whose settings
/// `change` sets as the mistake does (a convention, the depth).
fn render_changed(scene: &Scene, pixels: &[(u32, u32)], change: impl FnOnce(&mut Scene)) -> Vec<DVec3> {
    let mut changed = scene.clone();
    change(&mut changed);
    render_pixels_with(&World::new(&changed), Formulas::CHAPTER, pixels)
}

/// The whole image of `scene` rendered with `mistake`, 8-bit RGB (what a student's ray
/// tracer with that mistake writes); `None` when the mistake does not apply to the scene.
pub fn render_mistake(scene: &Scene, mistake: &Mistake) -> Option<Vec<u8>> {
    let s = &scene.settings;
    let pixels = Grid::new(s.width, s.height, usize::MAX).pixels();
    let world = World::new(scene);
    let oracle = match mistake.change {
        Change::Gamma | Change::SwapRedBlue => render_pixels_with(&world, Formulas::CHAPTER, &pixels),
        _ => Vec::new(),
    };
    render_change(scene, &world, &pixels, &oracle, mistake.change, false).map(|(r, output)| to_rgb8(&r, output))
}

/// The judged pixels beyond the tolerance against the oracle and within it against the
/// mistake, as a region of image pixels.
fn fixed_region(
    image: &[u8],
    oracle: &[u8],
    mistake: &[u8],
    judged: &[bool],
    pixels: &[(u32, u32)],
    tolerance: u8,
) -> Option<Region> {
    let mut region: Option<Region> = None;
    for (i, &(x, y)) in pixels.iter().enumerate() {
        if judged[i] && pixel_diff(image, oracle, i) > tolerance && pixel_diff(image, mistake, i) <= tolerance {
            let r = region.get_or_insert(Region {
                pixels: 0,
                x: [x, x],
                y: [y, y],
            });
            r.pixels += 1;
            r.x = [r.x[0].min(x), r.x[1].max(x)];
            r.y = [r.y[0].min(y), r.y[1].max(y)];
        }
    }
    region
}

/// Whether the image differs from the render of the mistake found, `first`, by more than
/// that mistake: by the verdict's rule of half ([`explains_half`]) turned on what is left,
/// it leaves beyond the tolerance at least half as many pixels as it explains (and more
/// than the `allowance` the rule lets sampling leave), and by the rule of a clearly closer
/// candidate ([`clearly_closer`]), its RMS is still more than [`CLEARLY_CLOSER_RMS`] of the
/// `oracle`'s. The reference scene at 160 x 120 with gamma applied and flipped vertically
/// leaves 7595 pixels after gamma-applied for 10078 explained, at 0.78 of the RMS; of the
/// single mistakes of the catalogue on the eight scenes of `tests/diagnose.rs`, centred or
/// jittered, the one leaving most pixels (shadow acne, jittered: 276 for 297) keeps 0.49 of
/// the RMS, and none keeps more than 0.60.
fn differs_besides(first: &Candidate, oracle: &Score, allowance: usize) -> bool {
    let left = first.score.beyond;
    let explained = first.fixes.as_ref().map_or(0, |r| r.pixels);
    2 * left >= explained && left > allowance && first.score.rms > CLEARLY_CLOSER_RMS * oracle.rms
}

/// The kind of the mistakes applied to the finished image ([`Change::kind`]).
pub const POST_PROCESS: &str = "post-process";

/// Whether a mistake fixing `fixes` explains at least half of the `beyond` judged pixels
/// the image leaves beyond the tolerance against the oracle.
fn explains_half(fixes: Option<&Region>, beyond: usize) -> bool {
    2 * fixes.map_or(0, |r| r.pixels) >= beyond
}

/// The sentences the gains say: each term off its oracle's value, and a shadow filter
/// opaque (or weakened) where the oracle filters by colour.
fn findings(gains: &[Gain]) -> Vec<String> {
    gains
        .iter()
        .filter(|g| g.is_off())
        .map(|g| match (g.term, g.gain) {
            ("through colour filters", Some(x)) if x.abs() < 0.1 => format!(
                "shadow filter opaque where the oracle filters by colour (light through transparent objects {})",
                g.label()
            ),
            (term, _) => format!("{term} {}", g.label()),
        })
        .collect()
}

/// Diagnoses `image` (8-bit RGB, row-major, at the scene's size) against the scene's
/// oracle render with every mistake of the catalogue, on the current rayon pool.
pub fn diagnose(scene: &Scene, image: &[u8], options: &Options) -> Diagnosis {
    Oracle::new(scene, options).diagnose(image)
}

/// Most pixels the specular exponent is fitted on: beyond, an evenly spread subset of the
/// judged pixels beyond the tolerance. Each factor tried renders them all, and one factor
/// needs no more: at 800 x 600 the exponent doubled on the reference scene leaves 1 521
/// pixels beyond, and 500 of them give the same factor within 0.1 %.
const MAX_FIT_PIXELS: usize = 500;

/// At most `most` of `items`, evenly spread over them; all of them when there are no more.
fn evenly_spread(items: Vec<usize>, most: usize) -> Vec<usize> {
    if items.len() <= most {
        return items;
    }
    (0..most).map(|k| items[k * items.len() / most]).collect()
}

/// The renders of the scene with every specular exponent scaled that an [`Oracle`] keeps
/// for the images after the first: a render depends only on the scene, the factor and the
/// pixel, and the fits of images of one scene meet the same factors again. Every fit tries
/// the same half-octave steps; fits whose best step is the same try the same first
/// golden-section factors, on pixel sets that overlap where the images differ alike; and
/// identical images find the same factor, whose render of the whole grid is then kept.
/// Past [`MOST_KEPT_TRIAL_RADIANCES`] radiances and [`MOST_KEPT_FITTED`] renders, what the
/// next images render is not kept.
#[derive(Default)]
struct ExponentRenders {
    trials: Mutex<KeptTrials>,
    /// The whole grid's 8-bit RGB at each factor fitted, by its bits.
    fitted: Mutex<HashMap<u64, Vec<u8>>>,
}

/// The radiance of the grid pixels the fits rendered.
#[derive(Default)]
struct KeptTrials {
    /// By the factor's bits, then the pixel's index on the grid.
    by_factor: HashMap<u64, HashMap<usize, DVec3>>,
    /// How many radiances `by_factor` holds.
    count: usize,
}

/// Most trial radiances an [`Oracle`] keeps, some 40 bytes each (the pixel's index, its
/// radiance and the hash table's share): 40 MB at most. Thirty-six images of the reference
/// scene at 800 x 600 (thirty of one mistake at other seeds, six others) leave 85 255, at
/// 87 factors.
const MOST_KEPT_TRIAL_RADIANCES: usize = 1 << 20;
/// Most fitted renders of the grid an [`Oracle`] keeps, 3 bytes a grid pixel each: 7.7 MB
/// at most on the default grid of at most 40 000 pixels.
const MOST_KEPT_FITTED: usize = 64;

/// What a diagnosis needs of the scene alone, rendered once for any number of images: the
/// world, the grid and its edges, the oracle's render and the range of each pixel's
/// footprint, the oracle's layers, and the render of every mistake of the catalogue but the
/// specular exponent, which is fitted to each image (its renders kept for the next ones).
pub struct Oracle<'s> {
    options: Options,
    world: World<'s>,
    width: u32,
    height: u32,
    grid: Grid,
    pixels: Vec<(u32, u32)>,
    edge_mask: Vec<bool>,
    oracle_rgb: Vec<u8>,
    ranges: Vec<[[u8; 3]; 2]>,
    layers: Vec<PixelLayers>,
    /// The specular exponents the scene's highlights show ([`shown_exponents`]).
    exponents: Vec<f64>,
    /// Per grid pixel, whether the scene's colour normalization divides the oracle's colour
    /// (`division_factor`, a channel above 1): left out of the gains' fit.
    divided: Vec<bool>,
    /// Each mistake of the catalogue as prepared for every image.
    mistakes: Vec<(Mistake, Prepared)>,
    exponent_renders: ExponentRenders,
}

/// A mistake of the catalogue as the oracle holds it before any image.
enum Prepared {
    /// Its render on the grid, 8-bit RGB.
    Rendered(Vec<u8>),
    /// Fitted to each image that differs beyond sampling: the specular exponent.
    Fitted,
    /// It does not apply to the scene.
    NotApplicable,
}

impl<'s> Oracle<'s> {
    /// Renders the scene's oracle and every mistake on the grid, on the current rayon pool.
    pub fn new(scene: &'s Scene, options: &Options) -> Oracle<'s> {
        let s = &scene.settings;
        let (width, height) = (s.width, s.height);
        let grid = Grid::new(width, height, options.max_pixels);
        let pixels = grid.pixels();
        let world = World::new(scene);
        let edge_mask: Vec<bool> = pixels.par_iter().map(|&(x, y)| is_edge(&world, x, y)).collect();
        let oracle = render_pixels_with(&world, Formulas::CHAPTER, &pixels);
        let output = Output::of(scene, options.srgb);
        let oracle_rgb = to_rgb8(&oracle, output);
        let ranges = footprint_ranges(&world, &pixels, output);
        // Where the normalization divides the oracle's colour, the image is no sum of the
        // terms: the gains are fitted on the other pixels.
        let divides = !output.normalization.is_clamp_channel();
        let divided: Vec<bool> = oracle
            .iter()
            .map(|&c| divides && output.normalization.apply(c) != c)
            .collect();
        let layers: Vec<PixelLayers> = pixels
            .par_iter()
            .with_min_len(64)
            .map_init(|| Tracer::new(&world), |tracer, &(x, y)| pixel_layers(tracer, x, y))
            .collect();
        let exponents = shown_exponents(scene);
        let list: Vec<Mistake> = catalogue();
        let prepared: Vec<Prepared> = list
            .par_iter()
            .map(|m| match m.change {
                Change::SpecularExponent(_) if !exponents.is_empty() => Prepared::Fitted,
                change => render_change(scene, &world, &pixels, &oracle, change, options.srgb)
                    .map_or(Prepared::NotApplicable, |(r, output)| {
                        Prepared::Rendered(to_rgb8(&r, output))
                    }),
            })
            .collect();
        Oracle {
            options: *options,
            world,
            width,
            height,
            grid,
            pixels,
            edge_mask,
            oracle_rgb,
            ranges,
            layers,
            exponents,
            divided,
            mistakes: list.into_iter().zip(prepared).collect(),
            exponent_renders: ExponentRenders::default(),
        }
    }

    /// Diagnoses `image` (8-bit RGB, row-major, at the scene's size).
    pub fn diagnose(&self, image: &[u8]) -> Diagnosis {
        self.diagnose_drawn(image, &[])
    }

    /// The factor of the specular exponent that brings the scene's render closest to
    /// `image` (on the grid, 8-bit RGB) on the judged pixels beyond the tolerance against the
    /// oracle (at most [`MAX_FIT_PIXELS`] of them, evenly spread), with the render at that factor on the whole grid; `None` when no judged pixel
    /// is beyond the tolerance, leaving nothing to fit.
    fn fit_exponent(&self, image: &[u8], judged: &[bool]) -> Option<(Vec<u8>, ExponentFit)> {
        let tolerance = self.options.tolerance;
        let differing: Vec<usize> = (0..self.pixels.len())
            .filter(|&i| judged[i] && pixel_diff(image, &self.oracle_rgb, i) > tolerance)
            .collect();
        let differing = evenly_spread(differing, MAX_FIT_PIXELS);
        if differing.is_empty() {
            return None;
        }
        let output = Output::of(self.world.scene, self.options.srgb);
        let factor = exponent::fit_factor(|factor| {
            let radiance = self.trial_radiance(factor, &differing);
            radiance
                .iter()
                .zip(&differing)
                .map(|(&r, &i)| squared_level_error(r, &image[3 * i..3 * i + 3], output))
                .sum()
        });
        Some((self.fitted_rgb(factor), ExponentFit::new(factor, &self.exponents)))
    }

    /// The radiance of the grid pixels `indices` with every specular exponent multiplied by
    /// `factor`: those an earlier fit rendered at this factor as they were, the others
    /// rendered and kept.
    fn trial_radiance(&self, factor: f64, indices: &[usize]) -> Vec<DVec3> {
        let trials = &self.exponent_renders.trials;
        let mut known: Vec<Option<DVec3>> = {
            let trials = trials.lock().unwrap_or_else(PoisonError::into_inner);
            let at_factor = trials.by_factor.get(&factor.to_bits());
            indices
                .iter()
                .map(|i| at_factor.and_then(|m| m.get(i).copied()))
                .collect()
        };
        let missing: Vec<usize> = indices
            .iter()
            .zip(&known)
            .filter(|(_, k)| k.is_none())
            .map(|(&i, _)| i)
            .collect();
        if !missing.is_empty() {
            let at: Vec<(u32, u32)> = missing.iter().map(|&i| self.pixels[i]).collect();
            let rendered = render_pixels_with(&self.world, exponent_scaled(factor), &at);
            let mut trials = trials.lock().unwrap_or_else(PoisonError::into_inner);
            if trials.count + missing.len() <= MOST_KEPT_TRIAL_RADIANCES {
                trials.count += missing.len();
                trials
                    .by_factor
                    .entry(factor.to_bits())
                    .or_default()
                    .extend(missing.iter().copied().zip(rendered.iter().copied()));
            }
            for (k, r) in known.iter_mut().filter(|k| k.is_none()).zip(rendered) {
                *k = Some(r);
            }
        }
        known.into_iter().flatten().collect()
    }

    /// The whole grid's 8-bit RGB with every specular exponent multiplied by `factor`,
    /// rendered once for all the images fitted to it.
    fn fitted_rgb(&self, factor: f64) -> Vec<u8> {
        let fitted = &self.exponent_renders.fitted;
        if let Some(rgb) = fitted
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .get(&factor.to_bits())
        {
            return rgb.clone();
        }
        let rgb = to_rgb8(
            &render_pixels_with(&self.world, exponent_scaled(factor), &self.pixels),
            Output::of(self.world.scene, self.options.srgb),
        );
        let mut fitted = fitted.lock().unwrap_or_else(PoisonError::into_inner);
        if fitted.len() < MOST_KEPT_FITTED {
            fitted.insert(factor.to_bits(), rgb.clone());
        }
        rgb
    }

    /// Diagnoses `image` with the pixels `transparent` marks (one per image pixel, or none
    /// at all) left out: never drawn, as SIMRenderer's console mode leaves the last rows of
    /// an image wider than tall ([`crate::compare::read::Image::undrawn`]).
    pub fn diagnose_drawn(&self, image: &[u8], transparent: &[bool]) -> Diagnosis {
        let (width, height, options) = (self.width, self.height, &self.options);
        assert_eq!(
            image.len(),
            width as usize * height as usize * 3,
            "image at the scene's size"
        );
        assert!(
            transparent.is_empty() || transparent.len() == width as usize * height as usize,
            "a transparency mask at the scene's size"
        );
        let pixels = &self.pixels;
        let undrawn: Vec<bool> = pixels
            .iter()
            .map(|&(x, y)| !transparent.is_empty() && transparent[y as usize * width as usize + x as usize])
            .collect();
        // The pixels judged: off edges and drawn.
        let judged: Vec<bool> = self.edge_mask.iter().zip(&undrawn).map(|(&e, &u)| !e && !u).collect();
        let judged = &judged;
        let image_rgb: Vec<u8> = pixels
            .iter()
            .flat_map(|&(x, y)| {
                let i = 3 * (y as usize * width as usize + x as usize);
                [image[i], image[i + 1], image[i + 2]]
            })
            .collect();
        let drawn_black = image
            .chunks(3)
            .enumerate()
            .all(|(i, p)| p == [0, 0, 0] || (!transparent.is_empty() && transparent[i]));
        let black = drawn_black
            && self
                .oracle_rgb
                .chunks(3)
                .zip(&undrawn)
                .any(|(p, &u)| !u && p != [0, 0, 0]);
        let tol = options.tolerance;
        let oracle_score = score(&image_rgb, &self.oracle_rgb, judged, tol);
        let judged_count = judged.iter().filter(|j| **j).count().max(1) as f64;
        let matches =
            |rgb: &[u8]| beyond_ranges(rgb, &self.ranges, judged, tol) as f64 / judged_count <= options.max_fraction;
        let beyond_sampling = beyond_ranges(&image_rgb, &self.ranges, judged, tol);
        let within_sampling_of_oracle = beyond_sampling as f64 / judged_count <= options.max_fraction;

        let fit_pixels: Vec<(&PixelLayers, DVec3)> = self
            .layers
            .iter()
            .enumerate()
            .filter(|(i, _)| judged[*i] && !self.divided[*i])
            .map(|(i, l)| {
                let rgb = &image_rgb[3 * i..3 * i + 3];
                let decode = |level: u8| {
                    let v = level_value(level);
                    if options.srgb { srgb_decode(v) } else { v }
                };
                (l, DVec3::new(decode(rgb[0]), decode(rgb[1]), decode(rgb[2])))
            })
            .collect();
        let gains = gains::fit(&fit_pixels);

        let mut ranking = Vec::new();
        let (mut not_visible, mut within_sampling, mut not_applicable) = (Vec::new(), Vec::new(), Vec::new());
        for (m, prepared) in &self.mistakes {
            let (rgb, fitted) = match prepared {
                Prepared::Rendered(rgb) => (rgb.clone(), None),
                // An image within sampling of the oracle leaves no exponent to fit: the
                // mistake is not judged.
                Prepared::Fitted if within_sampling_of_oracle => continue,
                Prepared::Fitted => match self.fit_exponent(&image_rgb, judged) {
                    Some((rgb, fit)) => (rgb, Some(fit)),
                    None => continue,
                },
                Prepared::NotApplicable => {
                    not_applicable.push(m.name);
                    continue;
                }
            };
            let visible = !matches(&rgb);
            let candidate = Candidate {
                name: m.name,
                description: m.description,
                kind: m.change.kind(),
                fitted,
                score: score(&image_rgb, &rgb, judged, tol),
                fixes: fixed_region(&image_rgb, &self.oracle_rgb, &rgb, judged, pixels, tol),
                visible,
                rgb,
            };
            if visible {
                ranking.push(candidate);
            } else if candidate.score.beyond < oracle_score.beyond
                && explains_half(candidate.fixes.as_ref(), oracle_score.beyond)
            {
                within_sampling.push(candidate);
            } else {
                not_visible.push(m.name);
            }
        }
        // The pixels beyond the tolerance the rule lets sampling leave.
        let allowance = (options.max_fraction * judged_count) as usize;
        best_first(&mut ranking, allowance);
        best_first(&mut within_sampling, allowance);
        let mut diagnosis = Diagnosis {
            width,
            height,
            grid: self.grid.clone(),
            tolerance: tol,
            max_fraction: options.max_fraction,
            edges: self.edge_mask.iter().filter(|e| **e).count(),
            undrawn: undrawn.iter().filter(|u| **u).count(),
            oracle: oracle_score,
            black,
            beyond_sampling,
            verdict: Verdict::Unexplained,
            also_differs: false,
            findings: Vec::new(),
            findings_shown: true,
            gains,
            ranking,
            not_visible,
            within_sampling,
            not_applicable,
            image_rgb,
            oracle_rgb: self.oracle_rgb.clone(),
            edge_mask: self.edge_mask.clone(),
        };
        diagnosis.verdict = if within_sampling_of_oracle {
            Verdict::NoMistakeFound
        } else if let Some(best) = diagnosis.top(1).next() {
            if explains_half(best.fixes.as_ref(), diagnosis.oracle.beyond) {
                Verdict::MistakeFound
            } else {
                Verdict::PartlyExplained
            }
        } else {
            Verdict::Unexplained
        };
        diagnosis.also_differs = diagnosis.verdict == Verdict::MistakeFound
            && diagnosis
                .top(1)
                .next()
                .is_some_and(|best| differs_besides(best, &diagnosis.oracle, allowance));
        if diagnosis.verdict != Verdict::NoMistakeFound {
            diagnosis.findings = findings(&diagnosis.gains);
        }
        diagnosis.findings_shown =
            !(diagnosis.verdict.names_mistakes() && diagnosis.top(1).next().is_some_and(|c| c.kind == POST_PROCESS));
        diagnosis
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kept_exponent_renders_are_the_renders() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/reference.toml");
        let mut scene = crate::scene::load(&path).unwrap();
        (scene.settings.width, scene.settings.height) = (32, 24);
        scene.settings.samples_per_pixel = 1;
        let oracle = Oracle::new(&scene, &Options::default());
        let render_at = |factor: f64, indices: &[usize]| {
            let at: Vec<(u32, u32)> = indices.iter().map(|&i| oracle.pixels[i]).collect();
            render_pixels_with(&oracle.world, exponent_scaled(factor), &at)
        };
        // Pixels 5 and 9 kept by the first trial, 100 and 200 rendered among them.
        let (first, second) = ([0, 5, 9], [5, 100, 9, 200]);
        assert_eq!(oracle.trial_radiance(2.0, &first), render_at(2.0, &first));
        assert_eq!(oracle.trial_radiance(2.0, &second), render_at(2.0, &second));
        assert_eq!(oracle.trial_radiance(0.5, &first), render_at(0.5, &first));
        {
            let kept = oracle.exponent_renders.trials.lock().unwrap();
            assert_eq!((kept.count, kept.by_factor.len()), (3 + 2 + 3, 2));
            assert_eq!(kept.by_factor[&2f64.to_bits()].len(), 5);
        }
        // The whole grid at a fitted factor, rendered once, the same the second time.
        let all: Vec<usize> = (0..32 * 24).collect();
        let fitted = to_rgb8(&render_at(0.5, &all), Output::of(&scene, false));
        assert_eq!(oracle.fitted_rgb(0.5), fitted);
        assert_eq!(oracle.exponent_renders.fitted.lock().unwrap().len(), 1);
        assert_eq!(oracle.fitted_rgb(0.5), fitted);
        assert_eq!(oracle.exponent_renders.fitted.lock().unwrap().len(), 1);
    }

    #[test]
    fn grid_keeps_within_its_budget() {
        let g = Grid::new(800, 600, 40_000);
        // 480000 / 40000 = 12, sqrt 3.46: every 4th pixel, 200 x 150.
        assert_eq!((g.stride, g.width, g.height), (4, 200, 150));
        assert_eq!(g.pixels()[201], (4, 4));
        let small = Grid::new(160, 120, 40_000);
        assert_eq!((small.stride, small.width, small.height), (1, 160, 120));
    }

    #[test]
    fn the_judged_grid_in_words_has_english_ordinals() {
        let words = |stride| {
            Grid {
                stride,
                width: 1,
                height: 1,
            }
            .describe()
        };
        assert_eq!(words(1), "every pixel");
        assert_eq!(words(2), "every 2nd pixel of every 2nd row");
        assert_eq!(words(3), "every 3rd pixel of every 3rd row");
        assert_eq!(words(4), "every 4th pixel of every 4th row");
        assert_eq!(words(11), "every 11th pixel of every 11th row");
        assert_eq!(words(12), "every 12th pixel of every 12th row");
        assert_eq!(words(13), "every 13th pixel of every 13th row");
        assert_eq!(words(21), "every 21st pixel of every 21st row");
        assert_eq!(words(22), "every 22nd pixel of every 22nd row");
        assert_eq!(words(23), "every 23rd pixel of every 23rd row");
        assert_eq!(words(111), "every 111th pixel of every 111th row");
    }

    /// A candidate of `beyond` pixels beyond at `rms`, fitted or not.
    fn candidate(name: &'static str, beyond: usize, rms: f64, fitted: bool) -> Candidate {
        Candidate {
            name,
            description: "",
            kind: if fitted { "fitted" } else { "formula" },
            fitted: fitted.then(|| ExponentFit::new(2.0, &[20.0])),
            score: Score {
                beyond,
                judged: 6000,
                fraction: beyond as f64 / 6000.0,
                rms,
            },
            fixes: None,
            visible: true,
            rgb: Vec::new(),
        }
    }

    #[test]
    fn the_fitted_mistake_ranks_first_only_when_clearly_closer() {
        // The scores of the reference scene at 96 x 72 (tests/diagnose.rs), with the rule's
        // allowance of 30 pixels (0.5 % of 6011).
        let order = |mut list: Vec<Candidate>| {
            best_first(&mut list, 30);
            list.iter().map(|c| c.name).collect::<Vec<_>>()
        };
        // A jittered image of Phong's term for Blinn's: 2 pixels and 3 % of RMS apart.
        assert_eq!(
            order(vec![
                candidate("exponent", 11, 0.7691, true),
                candidate("phong", 13, 0.7935, false)
            ]),
            ["phong", "exponent"]
        );
        // The exponent doubled: 106 pixels fewer.
        assert_eq!(
            order(vec![
                candidate("phong", 106, 2.0177, false),
                candidate("exponent", 0, 0.0149, true)
            ]),
            ["exponent", "phong"]
        );
        // Four times the exponent: as many pixels, at no RMS against 0.15.
        assert_eq!(
            order(vec![
                candidate("phong", 0, 0.1526, false),
                candidate("exponent", 0, 0.0, true)
            ]),
            ["exponent", "phong"]
        );
        // Not clearly closer than the first, clearly closer than the second: between them.
        assert_eq!(
            order(vec![
                candidate("eye", 445, 4.3679, false),
                candidate("exponent", 8, 0.7909, true),
                candidate("phong", 9, 0.6116, false),
            ]),
            ["phong", "exponent", "eye"]
        );
        // Farther than every rendered mistake: last.
        assert_eq!(
            order(vec![
                candidate("exponent", 3, 0.55, true),
                candidate("phong", 0, 0.0, false)
            ]),
            ["phong", "exponent"]
        );
    }

    #[test]
    fn scores_and_regions_by_hand() {
        // Three pixels: equal, 9 levels off, 20 levels off in one channel.
        let a = [0, 0, 0, 10, 10, 10, 50, 0, 0];
        let b = [0, 0, 0, 19, 10, 10, 30, 0, 0];
        let s = score(&a, &b, &[true, true, true], 8);
        assert_eq!((s.beyond, s.judged), (2, 3));
        // Squares 81 + 400 over 9 channels.
        assert!((s.rms - (481.0f64 / 9.0).sqrt()).abs() < 1e-12);
        let s = score(&a, &b, &[true, true, false], 8);
        assert_eq!((s.beyond, s.judged), (1, 2));
        let region = fixed_region(&a, &b, &a, &[true; 3], &[(0, 0), (5, 1), (2, 7)], 8).unwrap();
        assert_eq!(
            region,
            Region {
                pixels: 2,
                x: [2, 5],
                y: [1, 7]
            }
        );
    }
}
