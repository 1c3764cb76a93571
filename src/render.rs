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
    let ray = world.camera.ray(px, py, s.width, s.height);
    let c = tracer.trace_camera(&ray, rec);
    debug_assert!(c.is_finite(), "non-finite radiance {c} at pixel ({x}, {y}) sample {k}");
    finite_or_black(c, &mut tracer.counts)
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
    let spp = tracer.world.scene.settings.samples_per_pixel;
    let sum: DVec3 = (0..spp).map(|k| render_sample(tracer, x, y, k, &mut NoRecord)).sum();
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

#[cfg(test)]
mod tests {
    use super::*;

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
