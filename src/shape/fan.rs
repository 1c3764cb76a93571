//! Fans of shadow rays: many rays leaving one point (towards the points of an area light),
//! and what quick tests say of each of them before the exact [`Shape::occludes`].
//!
//! A shape's verdicts on a fan come from the same code as its `occludes` (the shortcuts
//! `occludes` takes first), written without branches and run as one loop over the rays,
//! which compiles to vector instructions (four rays at a time with AVX2) and has no branch
//! whose outcome is random from one ray to the next. Where a verdict is [`Verdict::Hit`] or
//! [`Verdict::Miss`], `occludes` answers the same, to the bit of every value it computes on
//! the way. For one ray the shapes keep their early exits, which are cheaper there.

use super::Shape;
use crate::math::Ray;
use glam::DVec3;
use multiversion::multiversion;

/// What a quick test says of one shadow ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Verdict {
    /// It surely misses.
    Miss,
    /// It surely meets the shape.
    Hit,
    /// Undecided: the exact test.
    Test,
}

impl Verdict {
    /// `Hit` when `hit`, else `Miss` when `miss`, else `Test`, as selects.
    #[inline(always)]
    pub(crate) fn of(hit: bool, miss: bool) -> Verdict {
        let undecided = if miss { Verdict::Miss } else { Verdict::Test };
        if hit { Verdict::Hit } else { undecided }
    }
}

/// Shadow rays from one origin: ray `i` goes along the unit direction `(x[i], y[i], z[i])`
/// and is tested on `(0, reach[i])` (its light point's distance).
pub struct Fan<'a> {
    pub origin: DVec3,
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub z: &'a [f64],
    pub reach: &'a [f64],
}

/// A shape whose shortcuts before its exact shadow test run as a fan loop: the part of
/// [`Shape::occludes`] that depends on the origin only, computed once per fan, and the
/// branch-free verdict on one ray from it.
pub(super) trait FanShape {
    type Origin: Copy;
    fn fan_origin(&self, origin: DVec3) -> Self::Origin;
    /// The verdict on the ray from `origin` along the unit `dir`, on `(0, reach)`.
    fn verdict(&self, origin: Self::Origin, dir: DVec3, reach: f64) -> Verdict;
}

/// The verdict of `shape`'s shortcuts on the rays `list` of `fan`: `out[k]` for ray
/// `list[k]`. Shapes without shortcuts of their own get [`Verdict::Test`] throughout.
pub fn fan_verdicts(shape: &Shape, fan: &Fan, list: &[u32], out: &mut [Verdict]) {
    let out = &mut out[..list.len()];
    match shape {
        Shape::Torus(torus) => in_chunks(&**torus, fan, list, out),
        Shape::Cuboid(cuboid) => in_chunks(&**cuboid, fan, list, out),
        Shape::Cone(cone) => in_chunks(&**cone, fan, list, out),
        Shape::Cylinder(cylinder) => in_chunks(&**cylinder, fan, list, out),
        _ => out.fill(Verdict::Test),
    }
}

/// [`Shape::occludes`] on `(0, reach)` for the ray from `fan.origin` along `dir`, which
/// [`fan_verdicts`] left undecided: for the torus, without the shortcuts its verdict
/// already took (`Torus::occludes_undecided`). The same answer, to the bit.
pub fn occludes_undecided(shape: &Shape, fan: &Fan, dir: DVec3, reach: f64) -> bool {
    let ray = Ray::new(fan.origin, dir);
    match shape {
        Shape::Torus(torus) => torus.occludes_undecided(&ray, torus.local_origin(fan.origin), 0.0, reach),
        _ => shape.occludes(&ray, 0.0, reach),
    }
}

/// Rays gathered from a fan, at most [`CHUNK`], in groups of [`LANES`].
const CHUNK: usize = 64;
/// How many rays the verdict loop takes at a time: one AVX-512 vector of `f64`, two of AVX2.
const LANES: usize = 8;
const GROUPS: usize = CHUNK / LANES;
struct Chunk {
    x: [[f64; LANES]; GROUPS],
    y: [[f64; LANES]; GROUPS],
    z: [[f64; LANES]; GROUPS],
    reach: [[f64; LANES]; GROUPS],
}

impl Chunk {
    /// Ray `i` of `fan` into place `k`.
    #[inline(always)]
    fn set(&mut self, k: usize, fan: &Fan, i: usize) {
        let (g, l) = (k / LANES, k % LANES);
        (self.x[g][l], self.y[g][l], self.z[g][l], self.reach[g][l]) = (fan.x[i], fan.y[i], fan.z[i], fan.reach[i]);
    }
}

/// The verdicts of `shape` on the rays `list` of `fan`, [`CHUNK`] rays at a time: each
/// chunk's directions and reaches gathered into arrays, so that the loop over them
/// compiles to vector instructions. A chunk whose count is not a multiple of [`LANES`] is
/// filled up with copies of its last ray, whose verdicts are dropped: every ray is then
/// decided on a vector lane, none by a loop over the leftover rays one at a time (for the
/// torus, such a ray costs several times a lane of a vector).
fn in_chunks<S: FanShape>(shape: &S, fan: &Fan, list: &[u32], out: &mut [Verdict]) {
    let origin = shape.fan_origin(fan.origin);
    let mut chunk = Chunk {
        x: [[0.0; LANES]; GROUPS],
        y: [[0.0; LANES]; GROUPS],
        z: [[0.0; LANES]; GROUPS],
        reach: [[0.0; LANES]; GROUPS],
    };
    let mut verdicts = [Verdict::Test; CHUNK];
    for (rays, out) in list.chunks(CHUNK).zip(out.chunks_mut(CHUNK)) {
        for (k, &i) in rays.iter().enumerate() {
            chunk.set(k, fan, i as usize);
        }
        let groups = rays.len().div_ceil(LANES);
        let last = rays[rays.len() - 1] as usize;
        for k in rays.len()..groups * LANES {
            chunk.set(k, fan, last);
        }
        chunk_verdicts(shape, origin, &chunk, &mut verdicts[..groups * LANES]);
        out.copy_from_slice(&verdicts[..rays.len()]);
    }
}

/// The verdicts on the first `out.len()` rays of `chunk` (a multiple of [`LANES`]), in
/// versions for AVX-512 and AVX2 chosen at run time (the same IEEE operations on every
/// lane, so the same verdicts).
#[multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn chunk_verdicts<S: FanShape>(shape: &S, origin: S::Origin, chunk: &Chunk, out: &mut [Verdict]) {
    let (groups, _) = out.as_chunks_mut::<LANES>();
    for (g, out) in groups.iter_mut().enumerate() {
        let (x, y, z, reach) = (&chunk.x[g], &chunk.y[g], &chunk.z[g], &chunk.reach[g]);
        for l in 0..LANES {
            out[l] = shape.verdict(origin, DVec3::new(x[l], y[l], z[l]), reach[l]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Ray;
    use crate::sampling::unit_interval;
    use crate::shape::{Aabb, Cone, Cuboid, Cylinder, Torus};
    use rand_chacha::ChaCha8Rng;
    use rand_core::{Rng, SeedableRng};

    /// What a test of its own says of a shadow ray (origin, direction, reach): occluded or
    /// not, or `None` where it cannot tell apart from rounding.
    type Oracle<'a> = &'a dyn Fn(&Ray, f64) -> Option<bool>;

    /// How many rays `check_fans` saw decided each way, left undecided, and checked against
    /// the oracle.
    #[derive(Debug, Default)]
    struct Counts {
        hits: usize,
        misses: usize,
        undecided: usize,
        by_oracle: usize,
    }

    /// Fans from around, inside, on and far from `shape`: directions towards random points
    /// near it and along the axes (zero components), reaches short and long, rays listed
    /// out of order and more than a chunk at a time, and the list's first rays alone. Every
    /// decided verdict is `occludes`'s answer, and the oracle's where it has one.
    fn check_fans(shape: &Shape, center: DVec3, size: f64, seed: u64, oracle: Oracle) -> Counts {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut u = move || unit_interval(rng.next_u64()) * 2.0 - 1.0;
        let mut counts = Counts::default();
        for f in 0..120 {
            let mut point = |half: f64| center + half * DVec3::new(u(), u(), u());
            let origin = match f % 4 {
                0 | 1 => point(2.0 * size),
                // on the surface: the first hit of a ray from outside
                2 => {
                    let from = point(3.0 * size) + DVec3::splat(4.0 * size);
                    let ray = Ray::new(from, (point(0.5 * size) - from).normalize());
                    shape.intersect(&ray, 0.0, f64::INFINITY).map_or(from, |h| ray.at(h.t))
                }
                _ => center + DVec3::new(1e4, -3e3, 2e3) * size,
            };
            let mut dirs = Vec::new();
            let mut reach = Vec::new();
            for k in 0..150 {
                let (dir, length) = if k % 10 == 9 {
                    let axis = [DVec3::X, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z][k / 10 % 4];
                    (axis, 3.0 * size)
                } else {
                    let to = point(1.2 * size) - origin;
                    let scale = [0.3, 1.0, 2.0][k % 3];
                    (to.normalize(), to.length() * scale)
                };
                dirs.push(dir);
                reach.push(length);
            }
            let (x, y, z): (Vec<f64>, Vec<f64>, Vec<f64>) = dirs.iter().map(|d| (d.x, d.y, d.z)).collect();
            let fan = Fan {
                origin,
                x: &x,
                y: &y,
                z: &z,
                reach: &reach,
            };
            let list: Vec<u32> = (0..150).rev().filter(|i| i % 7 != 3).collect();
            let mut out = vec![Verdict::Test; list.len() + 5];
            fan_verdicts(shape, &fan, &list, &mut out);
            // The list's first rays alone, a chunk filled up with copies or not: the same
            // verdicts.
            for len in [1, 7, 8, 9, 63, 64, 65, 71] {
                let mut part = vec![Verdict::Test; len];
                fan_verdicts(shape, &fan, &list[..len], &mut part);
                assert_eq!(part, out[..len], "fan {f}, the first {len} rays");
            }
            for (&i, &verdict) in list.iter().zip(&out) {
                let i = i as usize;
                let ray = Ray::new(origin, dirs[i]);
                let occluded = shape.occludes(&ray, 0.0, reach[i]);
                match verdict {
                    Verdict::Hit => assert!(occluded, "fan {f}, ray {i}: {ray:?} up to {}", reach[i]),
                    Verdict::Miss => assert!(!occluded, "fan {f}, ray {i}: {ray:?} up to {}", reach[i]),
                    Verdict::Test => assert_eq!(
                        occludes_undecided(shape, &fan, dirs[i], reach[i]),
                        occluded,
                        "fan {f}, ray {i}: {ray:?} up to {}",
                        reach[i]
                    ),
                }
                match verdict {
                    Verdict::Hit => counts.hits += 1,
                    Verdict::Miss => counts.misses += 1,
                    Verdict::Test => counts.undecided += 1,
                }
                if let Some(expected) = oracle(&ray, reach[i]) {
                    assert_eq!(occluded, expected, "fan {f}, ray {i}: {ray:?} up to {}", reach[i]);
                    counts.by_oracle += 1;
                }
            }
        }
        counts
    }

    #[test]
    fn fan_verdicts_are_the_answers_of_occludes() {
        let center = DVec3::new(4.0, 3.0, 2.0);
        let none: Oracle = &|_, _| None;
        // The axis-aligned box, also against `Aabb`'s own slab test (reciprocals, not
        // quotients): occluded where the ray enters or leaves the box inside `(0, reach)`.
        let half = DVec3::new(1.0, 0.5, 1.5);
        let aabb = Aabb::new(center - half, center + half);
        let slab_oracle = |ray: &Ray, reach: f64| {
            // Along a face's plane the two tests may disagree (a face grazed end to end).
            let along_face = (0..3).any(|a| {
                ray.dir[a] == 0.0
                    && [aabb.min[a], aabb.max[a]]
                        .iter()
                        .any(|&p| (ray.origin[a] - p).abs() < 1e-9)
            });
            if along_face {
                return None;
            }
            let Some((near, far)) = aabb.clip(ray, f64::NEG_INFINITY, f64::INFINITY) else {
                return Some(false);
            };
            let clear = |t: f64| t.abs() > 1e-9 && (t - reach).abs() > 1e-9;
            (clear(near) && clear(far)).then_some((near > 0.0 && near < reach) || (far > 0.0 && far < reach))
        };
        let upright = Shape::Cuboid(Box::new(Cuboid::new(center, 2.0 * half, DVec3::ZERO)));
        let turned = Shape::Cuboid(Box::new(Cuboid::new(center, 2.0 * half, DVec3::new(20.0, -35.0, 70.0))));
        let cones =
            [DVec3::Z, DVec3::new(0.3, -0.5, 1.0)].map(|axis| Shape::Cone(Box::new(Cone::new(center, axis, 2.5, 1.0))));
        let tori = [DVec3::Z, DVec3::new(0.2, -0.1, 1.0)]
            .map(|axis| Shape::Torus(Box::new(Torus::new(center, axis, 1.5, 0.5))));
        let counts = check_fans(&upright, center, 2.0, 0, &slab_oracle);
        assert!(
            counts.hits > 2000 && counts.misses > 2000 && counts.by_oracle > 10_000,
            "{counts:?}"
        );
        let base = center - DVec3::new(0.0, 0.0, 1.0);
        let tilt = DVec3::new(0.3, -0.5, 1.0);
        let cylinders = [
            Cylinder::new(base, DVec3::Z, 2.0, 1.0),
            Cylinder::new(base, tilt, 2.0, 1.0),
            Cylinder::tube(base, DVec3::Z, 2.0, 1.0),
            Cylinder::tube(base, tilt, 2.0, 1.0),
        ]
        .map(|c| Shape::Cylinder(Box::new(c)));
        let shapes = [&turned, &cones[0], &cones[1]].into_iter().chain(&cylinders);
        for (k, shape) in shapes.enumerate() {
            let counts = check_fans(shape, center, 2.0, 1 + k as u64, none);
            assert!(counts.hits > 2000 && counts.misses > 2000, "shape {k}: {counts:?}");
        }
        for (k, torus) in tori.iter().enumerate() {
            let counts = check_fans(torus, center, 2.0, 10 + k as u64, none);
            assert!(
                counts.hits > 1000 && counts.misses > 1000 && counts.undecided > 100,
                "torus {k}: {counts:?}"
            );
        }
    }
}
