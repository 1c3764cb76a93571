//! Renders a world to a film: rows in parallel with rayon, every pixel independent, each
//! sample's jitter from its own stream keyed by (seed, pixel, sample), so the bytes never
//! depend on the thread count or the order rows finish in.

use crate::conventions::{RayOrigin, SamplePosition};
use crate::film::Film;
use crate::math::Ray;
use crate::sampling::{LANES, Purpose, ShortStream};
use crate::scene::SampleGrid;
use crate::trace::formulas::{Chapter, FormulaTable};
use crate::trace::{Formulas, Member, NoRecord, RayCounts, Recorder, Reference, SampleKey, Tracer};
use crate::world::World;
use glam::DVec3;
use rayon::prelude::*;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// What a render measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderStats {
    pub counts: RayCounts,
    pub elapsed: Duration,
    /// A family's members could not all be traced exactly together (see
    /// [`Tracer::diverged`]): the images must be rendered one by one. Never for one member.
    pub diverged: bool,
}

/// The row-major index of pixel `(x, y)`, which keys its random streams.
fn pixel_index(world: &World, x: u32, y: u32) -> u64 {
    y as u64 * world.scene.settings.width as u64 + x as u64
}

/// The jitter stream of pixel `(x, y)`: sample `k` reads its two numbers from words
/// `4k .. 4k + 4`, so reading samples in order and seeking to one sample agree.
fn jitter_stream(world: &World, x: u32, y: u32) -> ShortStream {
    ShortStream::new(
        world.scene.settings.seed,
        Purpose::PixelJitter,
        pixel_index(world, x, y),
    )
}

/// Image position of sample `k` of pixel `(x, y)`, by the scene's sample-position
/// convention, with the jitter stream at sample `k`: for `jittered`, cell
/// `(k mod columns, k div columns)` of the pixel's `grid`, jittered uniformly within the
/// cell (reading the stream's next two numbers); for `regular`, that cell's center; for
/// `center`, the pixel's center; for `corner`, its top-left corner as SIMRenderer places it
/// (the image's center measured with an integer division by 2: half a pixel right of or
/// below the true corner along an odd width or height), and for `top_right`, `bottom_left`
/// and `bottom_right` the corner one pixel right, below, or both. `grid` is the world's
/// [`sample_grid`](World::sample_grid).
#[inline]
fn sample_at(world: &World, rng: &mut ShortStream, grid: SampleGrid, x: u32, y: u32, k: u32) -> (f64, f64) {
    let s = &world.scene.settings;
    let (cx, cy) = ((k % grid.columns) as f64, (k / grid.columns) as f64);
    let across = |t: f64| over_grid_side(t, grid.columns);
    let down = |t: f64| over_grid_side(t, grid.rows);
    let (x, y) = (x as f64, y as f64);
    match s.conventions.sample_position {
        SamplePosition::Jittered => {
            let (jx, jy) = (rng.next_f64(), rng.next_f64());
            (x + across(cx + jx), y + down(cy + jy))
        }
        SamplePosition::Regular => (x + across(cx + 0.5), y + down(cy + 0.5)),
        SamplePosition::Center => (x + 0.5, y + 0.5),
        SamplePosition::Corner
        | SamplePosition::TopRight
        | SamplePosition::BottomLeft
        | SamplePosition::BottomRight => {
            let odd_half = |side: u32| f64::from(side % 2) * 0.5;
            let (right, below) = match s.conventions.sample_position {
                SamplePosition::TopRight => (1.0, 0.0),
                SamplePosition::BottomLeft => (0.0, 1.0),
                SamplePosition::BottomRight => (1.0, 1.0),
                _ => (0.0, 0.0),
            };
            (x + right + odd_half(s.width), y + below + odd_half(s.height))
        }
    }
}

/// `t / n`, a position in cells along a grid side of `n` cells made a fraction of the
/// pixel. For a power of two `n = 2^m` it is `t * 2^-m`, the same bits without waiting on a
/// division.
#[inline]
fn over_grid_side(t: f64, n: u32) -> f64 {
    if n.is_power_of_two() {
        t * f64::from_bits(u64::from(1023 - n.trailing_zeros()) << 52)
    } else {
        t / f64::from(n)
    }
}

/// Image position of sample `k` of pixel `(x, y)` (see `sample_at`).
pub fn sample_position(world: &World, x: u32, y: u32, k: u32) -> (f64, f64) {
    let mut rng = jitter_stream(world, x, y).skip_words(4 * k as u128);
    sample_at(world, &mut rng, world.sample_grid, x, y, k)
}

/// The camera ray through image position `(px, py)`: from the eye, or from the image plane
/// at the conventions' `near`.
pub fn camera_ray(world: &World, (px, py): (f64, f64)) -> Ray {
    let s = &world.scene.settings;
    match s.conventions.ray_origin {
        RayOrigin::Eye => world.camera.ray(px, py, s.width, s.height),
        RayOrigin::NearPlane => world
            .camera
            .ray_from_plane(px, py, s.width, s.height, s.conventions.near),
    }
}

/// The jitter streams of the pixels `x .. x + LANES` of row `y` (those past the row's end
/// unread): with jittered samples, their first blocks computed side by side.
fn jitter_streams(world: &World, x: u32, y: u32) -> [ShortStream; LANES] {
    let s = &world.scene.settings;
    if s.conventions.sample_position == SamplePosition::Jittered {
        let indices = std::array::from_fn(|l| pixel_index(world, x + l as u32, y));
        ShortStream::first_blocks(s.seed, Purpose::PixelJitter, &indices)
    } else {
        std::array::from_fn(|l| jitter_stream(world, x + l as u32, y))
    }
}

/// How many of a pixel's samples have their positions and camera rays made before any of
/// them is traced. Each ray is a chain of divisions and a square root that the next steps
/// wait for; made side by side, the chains of a batch overlap instead of each stalling the
/// start of its sample's trace.
const BATCH: usize = 4;

/// A pixel's radiance (the box filter): the mean of its samples, each traced by
/// `trace(position, camera ray, sample key)` at its position ([`sample_at`]), read in sample
/// order from the pixel's jitter stream `rng` (the same numbers as [`sample_position`] for
/// each sample), with its ray ([`camera_ray`]). Samples are made [`BATCH`] at a time, then
/// traced in order.
fn pixel_mean<const K: usize>(
    world: &World,
    x: u32,
    y: u32,
    mut rng: ShortStream,
    mut trace: impl FnMut((f64, f64), &Ray, SampleKey) -> [DVec3; K],
) -> [DVec3; K] {
    let settings = &world.scene.settings;
    let (spp, grid) = (settings.samples_per_pixel, world.sample_grid);
    let pixel = pixel_index(world, x, y);
    let mut sum = [DVec3::ZERO; K];
    let mut positions = [(0.0, 0.0); BATCH];
    let mut rays = [Ray::new(DVec3::ZERO, DVec3::ZERO); BATCH];
    for first in (0..spp).step_by(BATCH) {
        let batch = (spp - first).min(BATCH as u32) as usize;
        let (positions, rays) = (&mut positions[..batch], &mut rays[..batch]);
        for (b, position) in positions.iter_mut().enumerate() {
            *position = sample_at(world, &mut rng, grid, x, y, first + b as u32);
        }
        for (ray, &position) in rays.iter_mut().zip(positions.iter()) {
            *ray = camera_ray(world, position);
        }
        for (b, (&position, ray)) in positions.iter().zip(rays.iter()).enumerate() {
            let key = SampleKey {
                pixel,
                sample: first + b as u32,
            };
            let c = trace(position, ray, key);
            for j in 0..K {
                sum[j] += c[j];
            }
        }
    }
    sum.map(|s| s / spp as f64)
}

/// Radiance of one sample of one pixel, recorded by `rec`.
pub fn render_sample<R: Recorder>(tracer: &mut Tracer, x: u32, y: u32, k: u32, rec: &mut R) -> DVec3 {
    let position = sample_position(tracer.world, x, y, k);
    let key = SampleKey {
        pixel: pixel_index(tracer.world, x, y),
        sample: k,
    };
    let ray = camera_ray(tracer.world, position);
    trace_at(tracer, position, &ray, key, rec)[0]
}

/// Radiance of every member along `ray`, the camera ray through image position
/// `(px, py)`; a NaN or infinity is counted and replaced by black (and is a bug: debug
/// builds stop on it).
fn trace_at<R: Recorder, const K: usize>(
    tracer: &mut Tracer<K>,
    (px, py): (f64, f64),
    ray: &Ray,
    key: SampleKey,
    rec: &mut R,
) -> [DVec3; K] {
    rec.sample(key.sample, px, py);
    tracer.sample_key = key;
    let mut c = tracer.trace_camera_members(ray, rec);
    for (j, c) in c.iter_mut().enumerate() {
        debug_assert!(
            c.is_finite(),
            "non-finite radiance {c} at pixel {} sample {}",
            key.pixel,
            key.sample
        );
        *c = finite_or_black(*c, tracer.member_counts_mut(j));
    }
    rec.sample_done(c[0]);
    c
}

/// The guard between the tracer and the film: a NaN or infinite sample becomes black and is
/// counted in `counts.non_finite` (reported by `render --stats` and as a warning), so no
/// non-finite value ever reaches a pixel. Debug builds assert before calling it.
pub fn finite_or_black(c: DVec3, counts: &mut RayCounts) -> DVec3 {
    if c.is_finite() {
        c
    } else {
        counts.non_finite += 1;
        DVec3::ZERO
    }
}

/// Radiance of a pixel: the mean of its samples.
pub fn render_pixel(tracer: &mut Tracer, x: u32, y: u32) -> DVec3 {
    render_pixel_recorded(tracer, x, y, &mut NoRecord)
}

/// [`render_pixel`] with every sample recorded by `rec` (what `lumiere probe` uses).
pub fn render_pixel_recorded<R: Recorder>(tracer: &mut Tracer, x: u32, y: u32, rec: &mut R) -> DVec3 {
    let rng = jitter_stream(tracer.world, x, y);
    render_pixel_members(tracer, x, y, rng, rec)[0]
}

/// [`render_pixel_recorded`] for every member of a family, with the pixel's jitter stream.
fn render_pixel_members<R: Recorder, const K: usize>(
    tracer: &mut Tracer<K>,
    x: u32,
    y: u32,
    rng: ShortStream,
    rec: &mut R,
) -> [DVec3; K] {
    let world = tracer.world;
    pixel_mean(world, x, y, rng, |position, ray, key| {
        trace_at(tracer, position, ray, key, rec)
    })
}

/// Renders the whole image on the current rayon pool. `progress` is called once per
/// finished row (from any thread).
pub fn render(world: &World, progress: &(dyn Fn() + Sync)) -> (Film, RenderStats) {
    let s = &world.scene.settings;
    let (pixels, stats) = render_rows(world, 0..s.height, progress, None);
    (s.film(pixels), stats)
}

/// Renders the rows `rows` (row-major pixels of those rows). When `cancel` becomes true,
/// the remaining rows are skipped (left black); the caller checks the flag and discards.
pub fn render_rows(
    world: &World,
    rows: Range<u32>,
    progress: &(dyn Fn() + Sync),
    cancel: Option<&AtomicBool>,
) -> (Vec<DVec3>, RenderStats) {
    let (pixels, [stats]) = render_rows_members(world, [Member::of(world)], rows, progress, cancel, |[c]| c);
    (pixels, stats)
}

/// [`render_rows`] for the members of a one-pass family (see [`crate::family`]) over the
/// world of its deepest, largest member: each pixel's member radiances go through `keep` (an
/// 8-bit quantisation, say, so K images cost no more memory than one), with each member's
/// stats. The wall time is the family's.
pub fn render_rows_members<T: Send + Clone, const K: usize>(
    world: &World,
    members: [Member; K],
    rows: Range<u32>,
    progress: &(dyn Fn() + Sync),
    cancel: Option<&AtomicBool>,
    keep: impl Fn([DVec3; K]) -> T + Sync,
) -> (Vec<T>, [RenderStats; K]) {
    render_rows_with(
        world,
        rows,
        progress,
        cancel,
        || Tracer::with_members(world, members),
        keep,
    )
}

/// Renders the whole image with the reference tracer ([`Reference`]): the image
/// [`render`] makes, to the radiance bits, computed as the chapter reads with no shortcut
/// (slower; for checking the fast tracer, and for reading). Only camera rays and
/// non-finite samples are counted.
pub fn render_reference(world: &World, progress: &(dyn Fn() + Sync)) -> (Film, RenderStats) {
    let s = &world.scene.settings;
    let (pixels, stats) = render_rows_reference(world, 0..s.height, progress, None);
    (s.film(pixels), stats)
}

/// [`render_rows`] with the reference tracer (see [`render_reference`]).
pub fn render_rows_reference(
    world: &World,
    rows: Range<u32>,
    progress: &(dyn Fn() + Sync),
    cancel: Option<&AtomicBool>,
) -> (Vec<DVec3>, RenderStats) {
    let new = || ReferencePixels {
        tracer: Reference::new(world),
        counts: RayCounts::default(),
    };
    let (pixels, [stats]) = render_rows_with(world, rows, progress, cancel, new, |[c]| c);
    (pixels, stats)
}

/// The radiance of each pixel of `pixels` (`(x, y)` pairs), as [`render_reference`]
/// renders it but with the reference tracer evaluating `formulas` (see
/// [`crate::trace::Formulas`]), in parallel on the current rayon pool: the same values for
/// any thread count. `lumiere diagnose` renders its mistakes so, on a subset of pixels.
pub fn render_pixels_with(world: &World, formulas: Formulas, pixels: &[(u32, u32)]) -> Vec<DVec3> {
    pixels
        .par_iter()
        .with_min_len(64)
        .map_init(
            || ReferencePixels {
                tracer: Reference::with_formulas(world, formulas),
                counts: RayCounts::default(),
            },
            |tracer, &(x, y)| tracer.pixel(x, y, jitter_stream(world, x, y))[0],
        )
        .collect()
}

/// What renders the pixels of a row: the fast tracer's members, or the reference tracer.
trait PixelTracer<const K: usize> {
    /// Every member's radiance of pixel `(x, y)`, whose jitter stream is `rng`.
    fn pixel(&mut self, x: u32, y: u32, rng: ShortStream) -> [DVec3; K];
    /// Each member's counts so far, and whether the members diverged.
    fn totals(&self) -> ([RayCounts; K], bool);
}

impl<const K: usize> PixelTracer<K> for Tracer<'_, '_, K> {
    fn pixel(&mut self, x: u32, y: u32, rng: ShortStream) -> [DVec3; K] {
        render_pixel_members(self, x, y, rng, &mut NoRecord)
    }

    fn totals(&self) -> ([RayCounts; K], bool) {
        (self.member_totals(), self.diverged)
    }
}

/// The reference tracer with the counts it keeps: camera rays and non-finite samples.
struct ReferencePixels<'w, 's, F: FormulaTable = Chapter> {
    tracer: Reference<'w, 's, F>,
    counts: RayCounts,
}

impl<F: FormulaTable> PixelTracer<1> for ReferencePixels<'_, '_, F> {
    fn pixel(&mut self, x: u32, y: u32, rng: ShortStream) -> [DVec3; 1] {
        let world = self.tracer.world();
        let counts = &mut self.counts;
        let tracer = &self.tracer;
        pixel_mean(world, x, y, rng, |_, ray, key| {
            counts.camera += 1;
            [finite_or_black(tracer.camera(ray, key), counts)]
        })
    }

    fn totals(&self) -> ([RayCounts; 1], bool) {
        ([self.counts], false)
    }
}

/// The rows `rows` rendered in parallel, one row per task, each by a [`PixelTracer`] made
/// by `new`; each pixel's radiances through `keep`, with each member's stats. A row left
/// when `cancel` becomes true stays black. The wall time is the whole render's.
fn render_rows_with<T: Send + Clone, const K: usize, P: PixelTracer<K>>(
    world: &World,
    rows: Range<u32>,
    progress: &(dyn Fn() + Sync),
    cancel: Option<&AtomicBool>,
    new: impl Fn() -> P + Sync,
    keep: impl Fn([DVec3; K]) -> T + Sync,
) -> (Vec<T>, [RenderStats; K]) {
    let start = Instant::now();
    let width = world.scene.settings.width as usize;
    // What a cancelled row is left as: black.
    let mut pixels = vec![keep([DVec3::ZERO; K]); width * rows.len()];
    let (counts, diverged) = pixels
        .par_chunks_mut(width)
        // One row per task: rayon otherwise splits only as far as it has threads, then
        // again only when work is stolen, so a thread left with a run of costly rows (the
        // mirrors' lower half) renders them alone while the other waits. A row is enough
        // work (hundreds of pixels) for the task's overhead not to show.
        .with_max_len(1)
        .enumerate()
        .map(|(i, row)| {
            let mut tracer = new();
            if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                return (tracer.totals().0, false);
            }
            let y = rows.start + i as u32;
            for (chunk, pixels) in row.chunks_mut(LANES).enumerate() {
                let x = (chunk * LANES) as u32;
                for ((l, px), rng) in pixels.iter_mut().enumerate().zip(jitter_streams(world, x, y)) {
                    *px = keep(tracer.pixel(x + l as u32, y, rng));
                }
            }
            progress();
            tracer.totals()
        })
        .reduce(
            || ([RayCounts::default(); K], false),
            |(mut a, da), (b, db)| {
                a.iter_mut().zip(&b).for_each(|(a, b)| a.add(b));
                (a, da || db)
            },
        );
    let elapsed = start.elapsed();
    let stats = counts.map(|counts| RenderStats {
        counts,
        elapsed,
        diverged,
    });
    (pixels, stats)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::unit_interval;

    #[test]
    fn grid_fractions_are_divisions_to_the_bit() {
        // Cell 1 plus jitter 0.75 over a 2 x 2 grid: 0.875; over 4 x 4: 0.4375.
        assert_eq!(over_grid_side(1.75, 2), 0.875);
        assert_eq!(over_grid_side(1.75, 4), 0.4375);
        // Every grid side up to 64 and some longer ones (powers of two multiplied, the
        // others divided), on cell positions plus jitters of 53 random bits, the largest
        // jitter below 1 and 0.
        let mut bits = 0x9e37_79b9_7f4a_7c15_u64;
        for n in (1..=64u32).chain([128, 256, 512, 1021, 1024]) {
            for i in 0..2000 {
                bits ^= bits << 13;
                bits ^= bits >> 7;
                bits ^= bits << 17;
                let jitter = match i {
                    0 => 0.0,
                    1 => 1.0 - f64::EPSILON / 2.0,
                    _ => unit_interval(bits),
                };
                let t = f64::from(i % n) + jitter;
                assert_eq!(
                    over_grid_side(t, n).to_bits(),
                    (t / f64::from(n)).to_bits(),
                    "{t} / {n}"
                );
            }
        }
    }

    #[test]
    fn non_finite_samples_become_black_and_are_counted() {
        let mut counts = RayCounts::default();
        let c = DVec3::new(0.25, 0.5, 1.0);
        assert_eq!(finite_or_black(c, &mut counts), c);
        assert_eq!(counts.non_finite, 0);
        for bad in [
            DVec3::new(f64::NAN, 0.5, 0.5),
            DVec3::new(0.1, f64::INFINITY, 0.0),
            DVec3::splat(f64::NEG_INFINITY),
        ] {
            assert_eq!(finite_or_black(bad, &mut counts), DVec3::ZERO);
        }
        assert_eq!(counts.non_finite, 3);
    }
}
