//! Renders a world to a film: rows in parallel with rayon, every pixel independent, each
//! sample's jitter from its own stream keyed by (seed, pixel, sample), so the bytes never
//! depend on the thread count or the order rows finish in.

use crate::film::Film;
use crate::sampling::{Purpose, Stream, sample_index};
use crate::scene::World;
use crate::trace::{NoRecord, RayCounts, Recorder, Tracer};
use glam::DVec3;
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// What a render measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderStats {
    pub counts: RayCounts,
    pub elapsed: Duration,
}

/// Image position of sample `k` of pixel `(x, y)`: cell `(k mod n, k div n)` of the pixel's
/// `n x n` grid, jittered uniformly within the cell.
pub fn sample_position(world: &World, x: u32, y: u32, k: u32) -> (f64, f64) {
    let s = &world.scene.settings;
    let n = s.grid_side();
    let pixel = y as u64 * s.width as u64 + x as u64;
    let mut rng = Stream::new(s.seed, Purpose::PixelJitter, sample_index(pixel, k));
    let (jx, jy) = (rng.next_f64(), rng.next_f64());
    let (cx, cy) = ((k % n) as f64, (k / n) as f64);
    (x as f64 + (cx + jx) / n as f64, y as f64 + (cy + jy) / n as f64)
}

/// Radiance of one sample of one pixel, recorded by `rec`.
pub fn render_sample<R: Recorder>(tracer: &mut Tracer, x: u32, y: u32, k: u32, rec: &mut R) -> DVec3 {
    let world = tracer.world;
    let s = &world.scene.settings;
    let (px, py) = sample_position(world, x, y, k);
    rec.sample(k, px, py);
    let ray = world.camera.ray(px, py, s.width, s.height);
    let c = tracer.trace_camera(&ray, rec);
    let c = if c.is_finite() {
        c
    } else {
        debug_assert!(false, "non-finite radiance {c} at pixel ({x}, {y}) sample {k}");
        tracer.counts.non_finite += 1;
        DVec3::ZERO
    };
    rec.sample_done(c);
    c
}

/// Radiance of a pixel: the mean of its samples.
pub fn render_pixel(tracer: &mut Tracer, x: u32, y: u32) -> DVec3 {
    render_pixel_recorded(tracer, x, y, &mut NoRecord)
}

/// [`render_pixel`] with every sample recorded by `rec` (what `lumiere probe` uses).
pub fn render_pixel_recorded<R: Recorder>(tracer: &mut Tracer, x: u32, y: u32, rec: &mut R) -> DVec3 {
    let spp = tracer.world.scene.settings.samples_per_pixel;
    let sum: DVec3 = (0..spp).map(|k| render_sample(tracer, x, y, k, rec)).sum();
    sum / spp as f64
}

/// Renders the whole image on the current rayon pool. `progress` is called once per
/// finished row (from any thread).
pub fn render(world: &World, progress: &(dyn Fn() + Sync)) -> (Film, RenderStats) {
    let start = Instant::now();
    let s = &world.scene.settings;
    let mut film = Film::new(s.width, s.height);
    let counts = film
        .pixels
        .par_chunks_mut(s.width as usize)
        .enumerate()
        .map(|(y, row)| {
            let mut tracer = Tracer::new(world);
            for (x, px) in row.iter_mut().enumerate() {
                *px = render_pixel(&mut tracer, x as u32, y as u32);
            }
            progress();
            tracer.counts
        })
        .reduce(RayCounts::default, |mut a, b| {
            a.add(&b);
            a
        });
    let stats = RenderStats {
        counts,
        elapsed: start.elapsed(),
    };
    (film, stats)
}
