//! Facts measured on rendered figures and recorded in manifests: the range of the
//! attenuation factor over visible lit points, and the number of cone images seen in the
//! mirrors. Both read the renderer's own output (the recorder or the pixels).

use crate::render::render_sample;
use crate::trace::{LightShare, RayKind, Recorder, Tracer};
use crate::world::World;
use glam::DVec3;
use rayon::prelude::*;

/// Records `A` for every light reaching a camera ray's hit (not in shadow).
struct LitAttenuation {
    level: u32,
    min: f64,
    max: f64,
}

impl Recorder for LitAttenuation {
    fn ray(&mut self, _kind: RayKind, _ray: &crate::math::Ray, level: u32, _weight: f64) {
        self.level = level;
    }
    fn light(&mut self, share: &LightShare) {
        // Local illumination of a hit runs before its secondary rays, so `level` is the hit's.
        if self.level == 1 && share.filter != DVec3::ZERO {
            self.min = self.min.min(share.incidence.attenuation);
            self.max = self.max.max(share.incidence.attenuation);
        }
    }
}

/// Minimum and maximum of the attenuation `A` over the points seen by the camera (sample 0
/// of every pixel) that some positioned light reaches; `None` when no such point exists.
pub fn attenuation_range(world: &World) -> Option<(f64, f64)> {
    let s = &world.scene.settings;
    let (min, max) = (0..s.height)
        .into_par_iter()
        .with_max_len(1) // one row per task, as `render_rows_members` does
        .map(|y| {
            let mut tracer = Tracer::new(world);
            let mut rec = LitAttenuation {
                level: 0,
                min: f64::INFINITY,
                max: f64::NEG_INFINITY,
            };
            for x in 0..s.width {
                render_sample(&mut tracer, x, y, 0, &mut rec);
            }
            (rec.min, rec.max)
        })
        .reduce(
            || (f64::INFINITY, f64::NEG_INFINITY),
            |a, b| (a.0.min(b.0), a.1.max(b.1)),
        );
    (min <= max).then_some((min, max))
}

/// Connected regions (8-neighbourhood) of at least `min_size` pixels of an RGB8 image where
/// `pred` holds for the pixel.
pub fn count_regions(rgb: &[u8], width: usize, height: usize, min_size: usize, pred: impl Fn(&[u8]) -> bool) -> usize {
    let mut seen = vec![false; width * height];
    let mut count = 0;
    let mut stack = Vec::new();
    for start in 0..width * height {
        if seen[start] || !pred(&rgb[start * 3..start * 3 + 3]) {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        let mut size = 0;
        while let Some(i) = stack.pop() {
            size += 1;
            let (x, y) = ((i % width) as i64, (i / width) as i64);
            for (dx, dy) in [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= width as i64 || ny >= height as i64 {
                    continue;
                }
                let j = ny as usize * width + nx as usize;
                if !seen[j] && pred(&rgb[j * 3..j * 3 + 3]) {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
        if size >= min_size {
            count += 1;
        }
    }
    count
}

/// Red regions of a mirrors figure: the real cone plus its images. A pixel is the cone's
/// red (0.9, 0.1, 0.1) — dimmed by 0.9 per bounce and greyed by the mirrors' own diffuse term
/// — when its red exceeds green and blue by at least 30 levels (floor and mirrors are grey).
/// Regions smaller than 1/20000 of the image (at least 3 pixels) are noise.
pub fn red_regions(rgb: &[u8], width: usize, height: usize) -> usize {
    let red = |p: &[u8]| p[0] as i32 - (p[1].max(p[2]) as i32) >= 30;
    count_regions(rgb, width, height, (width * height / 20_000).max(3), red)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_by_hand() {
        // 4 x 3, red at (0,0), (3,0), (1,1), (3,1): {(0,0), (1,1)} touch diagonally and
        // {(3,0), (3,1)} vertically, so 2 regions of 2 pixels each.
        let r = [200u8, 0, 0];
        let k = [0u8, 0, 0];
        let img: Vec<u8> = [r, k, k, r, k, r, k, r, k, k, k, k].concat();
        assert_eq!(count_regions(&img, 4, 3, 1, |p| p[0] > 100), 2);
        assert_eq!(count_regions(&img, 4, 3, 2, |p| p[0] > 100), 2);
        assert_eq!(count_regions(&img, 4, 3, 3, |p| p[0] > 100), 0);
    }
}
