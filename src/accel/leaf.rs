//! The BVH's spheres side by side in leaf order, so that a leaf's spheres are read from one
//! run of memory and sifted four at a time.
//!
//! A walk through a million-sphere tree waits on memory: the objects, met in leaf order,
//! lie scattered, and reading an object's first byte costs more than its sphere test. So
//! the tree keeps its own copy of each sphere, per leaf in one run: for the leaf of entries
//! `first..first + count` (at most [`MAX_LEAF`] of them), from `12 * first` on (in `f32`
//! slots, 48 bytes an entry),
//! - the sift's `f32` values: `count` centre `x`s, then `count` `y`s, `count` `z`s and
//!   `count` radius terms ([`radius_term`]), which a leaf of four holds in 64 bytes;
//! - then the spheres in `f64`, in the same order (`x`s, `y`s, `z`s, radii), each value in
//!   two slots (its low 32 bits first).
//!
//! The object indices stay in the tree's leaf order; an entry that is not a sphere holds
//! NaNs and is tested as its object. Only trees of more than [`FINE_LEAVES_UP_TO`] objects
//! whose boxes fit `f32` have the copies: a smaller tree's objects stay in the caches, and
//! its fine leaves already take up to 56 bytes an object (BENCHMARKS.md, "Memory and node
//! cost").
//!
//! [`SphereLanes::candidates`] drops the lanes whose sphere the ray surely misses: by the
//! `f32` sift of [`super::sift`], which drops a sphere only when the `f64` sphere test
//! would miss it at its first step, or, for a ray beyond the sift's range, by that first
//! step itself ([`sphere_discriminant`]) on the `f64` copies. Every lane kept is tested by
//! the sphere's own `f64` routine on the `f64` copy, so the walk's answer is the scalar
//! walk's to the bit; the walk reads a leaf's `f64` half only for the lanes kept.

use super::build::{FINE_LEAVES_UP_TO, MAX_LEAF};
use super::sift::{NarrowRay, radius_term};
use crate::math::Ray;
use crate::scene::Object;
use crate::shape::{Shape, Sphere, sphere_discriminant};
use glam::{DVec3, Vec4};
use rayon::prelude::*;

const LANES: usize = 4;
const _: () = assert!(MAX_LEAF <= LANES, "a leaf's spheres are tested in one pass");

/// `f32` slots an entry takes: four `f32` values and four `f64` ones.
const STRIDE: usize = 12;

/// The spheres of the leaf order, per leaf as one run (see the module doc).
#[derive(Clone, Debug, Default)]
pub struct SphereLanes {
    /// `STRIDE * entries` slots, then `LANES - 1` of padding, so that every lane load of
    /// the last leaf stays in the array.
    values: Vec<f32>,
    /// The largest distance of a sphere's centre from the world's origin.
    center_reach: f64,
}

impl PartialEq for SphereLanes {
    /// The same bits (the NaN of a non-sphere entry equals itself).
    fn eq(&self, other: &Self) -> bool {
        self.center_reach == other.center_reach
            && self.values.len() == other.values.len()
            && self
                .values
                .iter()
                .zip(&other.values)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

/// What [`SphereLanes::entry`] finds at an entry.
#[derive(Clone, Debug, PartialEq)]
pub enum LaneEntry {
    Sphere(Sphere),
    /// Not a sphere: tested as its object.
    Object,
}

/// A ray prepared for sifting leaves: in `f32` when the sift takes it, else by the `f64`
/// test's first step.
pub enum LeafRay<'r> {
    Narrow(NarrowRay),
    Exact(&'r Ray),
}

/// Where the `f64` value `k` (0 to 3: `x`, `y`, `z`, radius) of lane `lane` starts in the
/// run of a leaf of `count` entries.
#[inline(always)]
fn wide_slot(count: usize, k: usize, lane: usize) -> usize {
    LANES * count + 2 * (k * count + lane)
}

impl SphereLanes {
    /// The copies for the leaf order `prims`; `None` when no object is a sphere, the tree
    /// holds at most [`FINE_LEAVES_UP_TO`] objects or its boxes do not fit `f32`
    /// (`fits_f32`). `leaves` lists the leaves (first entry and count, in any order), asked
    /// for only when there are copies to make.
    pub fn new(
        objects: &[Object],
        prims: &[u32],
        fits_f32: bool,
        leaves: impl FnOnce() -> Vec<(u32, u32)>,
    ) -> Option<Self> {
        if !fits_f32 || prims.len() <= FINE_LEAVES_UP_TO || !objects.iter().any(|o| matches!(o.shape, Shape::Sphere(_)))
        {
            return None;
        }
        Some(Self::copied(objects, prims, leaves()))
    }

    /// The copies for the leaf order `prims`, whose leaves (first entry and count, in any
    /// order) are `leaves`.
    fn copied(objects: &[Object], prims: &[u32], mut leaves: Vec<(u32, u32)>) -> Self {
        let len = STRIDE * prims.len() + LANES - 1;
        let mut values = Vec::with_capacity(len);
        values.resize(len, f32::NAN);
        // The leaves are disjoint and cover the leaf order: in order, their runs follow
        // one another.
        leaves.par_sort_unstable();
        let center_reach = fill(&mut values, 0, &leaves, prims, objects);
        SphereLanes { values, center_reach }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.values.len() * size_of::<f32>()
    }

    /// The address of the run of the leaf whose first entry is `first` (for a prefetch).
    #[inline(always)]
    pub fn first_byte(&self, first: usize) -> *const u8 {
        self.values.as_ptr().wrapping_add(STRIDE * first).cast()
    }

    /// Entry `first + lane` of the leaf of entries `first..first + count`, from its `f64`
    /// copy.
    #[inline(always)]
    pub fn entry(&self, first: usize, count: usize, lane: usize) -> LaneEntry {
        let run = &self.values[STRIDE * first..STRIDE * (first + count)];
        let wide = |k: usize| {
            let at = wide_slot(count, k, lane);
            f64::from_bits(u64::from(run[at].to_bits()) | u64::from(run[at + 1].to_bits()) << 32)
        };
        // A non-sphere's run holds `f32` NaNs, whose pairs are no `f64` NaN: its radius
        // term tells it.
        if run[3 * count + lane].is_nan() {
            return LaneEntry::Object;
        }
        LaneEntry::Sphere(Sphere::new(DVec3::new(wide(0), wide(1), wide(2)), wide(3)))
    }

    /// Whether the sift's `f32` values of entry `first + lane` of the leaf of entries
    /// `first..first + count` are those of `shape`: its sphere's centre rounded to `f32`
    /// and its [`radius_term`], or NaNs for another shape. For tests.
    pub fn sifts_as(&self, first: usize, count: usize, lane: usize, shape: &Shape) -> bool {
        let at = |k: usize| self.values[STRIDE * first + k * count + lane];
        match shape {
            Shape::Sphere(s) => {
                (0..3).all(|k| at(k).to_bits() == (s.center[k] as f32).to_bits())
                    && at(3).to_bits() == radius_term(s.radius).to_bits()
            }
            _ => at(3).is_nan(),
        }
    }

    /// The ray prepared for [`SphereLanes::candidates`].
    #[inline(always)]
    pub fn prepare<'r>(&self, ray: &'r Ray) -> LeafRay<'r> {
        match NarrowRay::new(ray, self.center_reach) {
            Some(n) => LeafRay::Narrow(n),
            None => LeafRay::Exact(ray),
        }
    }

    /// The lanes (bit `l` for entry `first + l`) of the leaf of entries `first..first +
    /// count` that the ray may hit: every entry but the spheres that the `f32` sift, or
    /// for a ray beyond it the `f64` test's first step, rules out (see the module doc).
    #[inline(always)]
    pub fn candidates(&self, first: usize, count: usize, ray: &LeafRay) -> u32 {
        let all = (1 << count) - 1;
        match ray {
            LeafRay::Narrow(sift) => {
                let v = &self.values[STRIDE * first..STRIDE * first + 3 * count + LANES];
                let lanes = |k: usize| Vec4::from_slice(&v[k * count..k * count + LANES]);
                !sift.misses(lanes(0), lanes(1), lanes(2), lanes(3)) & all
            }
            LeafRay::Exact(ray) => self.exact_candidates(first, count, ray),
        }
    }

    /// [`SphereLanes::candidates`] for a ray beyond the sift: the lanes whose discriminant
    /// (the `f64` routine's own) is not negative, and the non-spheres. Out of line: few
    /// rays take it.
    #[inline(never)]
    fn exact_candidates(&self, first: usize, count: usize, ray: &Ray) -> u32 {
        (0..count).fold(0, |keep, l| {
            let dropped = match self.entry(first, count, l) {
                LaneEntry::Sphere(s) => sphere_discriminant(s.center, s.radius, ray).0 < 0.0,
                LaneEntry::Object => false,
            };
            keep | u32::from(!dropped) << l
        })
    }
}

/// Fills the runs of `leaves` (in order, the first starting at entry `base`) in `values`,
/// which starts at that leaf's run: halves of the leaves in parallel, down to blocks of
/// [`FILL_BLOCK`] leaves. Returns the largest `|c|` of the spheres copied (0 for none),
/// rounded up.
fn fill(values: &mut [f32], base: usize, leaves: &[(u32, u32)], prims: &[u32], objects: &[Object]) -> f64 {
    if leaves.len() > FILL_BLOCK {
        let (low, high) = leaves.split_at(leaves.len() / 2);
        let middle = high[0].0 as usize;
        let (a, b) = values.split_at_mut(STRIDE * (middle - base));
        let (x, y) = rayon::join(
            || fill(a, base, low, prims, objects),
            || fill(b, middle, high, prims, objects),
        );
        return x.max(y);
    }
    let mut reach = 0.0f64;
    for &(first, count) in leaves {
        let (first, n) = (first as usize, count as usize);
        let run = &mut values[STRIDE * (first - base)..][..STRIDE * n];
        for (l, &j) in prims[first..first + n].iter().enumerate() {
            if let Shape::Sphere(s) = &objects[j as usize].shape {
                let (c, r) = (s.center, s.radius);
                for (k, x) in [c.x as f32, c.y as f32, c.z as f32, radius_term(r)]
                    .into_iter()
                    .enumerate()
                {
                    run[k * n + l] = x;
                }
                for (k, x) in [c.x, c.y, c.z, r].into_iter().enumerate() {
                    let at = wide_slot(n, k, l);
                    run[at] = f32::from_bits(x.to_bits() as u32);
                    run[at + 1] = f32::from_bits((x.to_bits() >> 32) as u32);
                }
                // `length` is within a few `2^-53` of `|c|`: one step up covers it.
                reach = reach.max(c.length() * (1.0 + f64::EPSILON * 4.0));
            }
        }
    }
    reach
}

/// Leaves whose runs [`fill`] writes in one task.
const FILL_BLOCK: usize = 4096;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::NameKey;

    fn object(shape: Shape) -> Object {
        Object {
            shape,
            material: 0,
            name: NameKey::UNNAMED,
        }
    }

    /// Leaves of 3, 1 and 4 entries, the second not a sphere: each run holds its spheres'
    /// `f32` coordinates axis by axis, then their radius terms, then the `f64` spheres;
    /// the cuboid reads as an object.
    #[test]
    fn runs_hold_each_leaf_axis_by_axis() {
        let sphere = |i: f64| object(Shape::Sphere(Sphere::new(DVec3::new(i, 10.0 + i, 20.0 + i), 0.5 + i)));
        let mut objects: Vec<Object> = (0..8).map(|i| sphere(i as f64)).collect();
        objects[3] = object(Shape::Cuboid(Box::new(crate::shape::Cuboid::new(
            DVec3::ZERO,
            DVec3::ONE,
            DVec3::ZERO,
        ))));
        // Leaf order: objects 7, 6, 5 | 3 | 0, 1, 2, 4.
        let prims = [7, 6, 5, 3, 0, 1, 2, 4];
        let lanes = SphereLanes::copied(&objects, &prims, vec![(4, 4), (0, 3), (3, 1)]);
        assert_eq!(lanes.bytes(), (12 * 8 + 3) * 4);
        assert_eq!(&lanes.values[..9], &[7.0, 6.0, 5.0, 17.0, 16.0, 15.0, 27.0, 26.0, 25.0]);
        // `A r^2` rounded up: 7.5^2 = 56.25 times 1 + 2^-8 + 2^-16 (and the margin).
        assert!(lanes.values[9] >= 56.25 * (1.0 + 1.0 / 256.0) && lanes.values[9] < 56.25 * 1.004);
        // The first `f64` value of the run: 7.0 in two halves, low first.
        let seven = 7.0f64.to_bits();
        assert_eq!(lanes.values[12].to_bits(), seven as u32);
        assert_eq!(lanes.values[13].to_bits(), (seven >> 32) as u32);
        assert!(lanes.values[36..48].iter().all(|v| v.is_nan()), "the cuboid's run");
        assert!(lanes.values[3 * 12 + 3].is_nan(), "the cuboid's radius term");
        assert_eq!(lanes.entry(3, 1, 0), LaneEntry::Object);
        assert_eq!(
            lanes.center_reach,
            objects[7].shape.bounds().map_or(0.0, |_| {
                let Shape::Sphere(s) = &objects[7].shape else {
                    unreachable!()
                };
                s.center.length() * (1.0 + 4.0 * f64::EPSILON)
            })
        );
        for (k, &j) in prims.iter().enumerate() {
            let (first, count) = if k < 3 {
                (0, 3)
            } else if k == 3 {
                (3, 1)
            } else {
                (4, 4)
            };
            assert!(
                lanes.sifts_as(first, count, k - first, &objects[j as usize].shape),
                "entry {k}"
            );
            match (lanes.entry(first, count, k - first), &objects[j as usize].shape) {
                (LaneEntry::Sphere(s), Shape::Sphere(o)) => assert_eq!(&s, o, "entry {k}"),
                (LaneEntry::Object, Shape::Cuboid(_)) => {}
                (e, _) => panic!("entry {k}: {e:?}"),
            }
        }
        // Without a sphere, or in a tree of at most `FINE_LEAVES_UP_TO` objects, there are
        // no copies.
        // Nor in a tree beyond `f32`.
        assert!(SphereLanes::new(&objects, &prims, true, || vec![(4, 4), (0, 3), (3, 1)]).is_none());
        let many = vec![objects[3].clone(); FINE_LEAVES_UP_TO + 1];
        let order: Vec<u32> = (0..many.len() as u32).collect();
        assert!(SphereLanes::new(&many, &order, true, || vec![(0, 1)]).is_none());
        let many = vec![objects[0].clone(); FINE_LEAVES_UP_TO + 1];
        let leaves = || (0..many.len() as u32).map(|i| (i, 1)).collect();
        assert!(SphereLanes::new(&many, &order, false, leaves).is_none());
        assert!(SphereLanes::new(&many, &order, true, leaves).is_some());
    }

    /// Rays along the rim of a leaf's spheres, a few units in the last place inside and
    /// outside it, and 1 % outside: a lane is dropped only when the sphere's own test
    /// misses, at any `t`, by the `f32` sift and by the `f64` one; near the rim both
    /// outcomes of the `f64` sift occur, and the `f32` sift drops the misses by 1 %. Lanes
    /// past the leaf's count are never kept.
    #[test]
    fn only_misses_are_dropped() {
        let mut s = crate::sampling::Stream::new(5, crate::sampling::Purpose::Generator, 0);
        let mut next = || s.next_f64();
        let (mut dropped, mut kept, mut sifted) = (0, 0, 0);
        for trial in 0..3000 {
            let count = 1 + trial % 4;
            let spheres: Vec<Sphere> = (0..count)
                .map(|_| {
                    let c = DVec3::new(next(), next(), next()) * 20.0 - 10.0;
                    Sphere::new(c, 0.01 + next())
                })
                .collect();
            let objects: Vec<Object> = spheres.iter().map(|s| object(Shape::Sphere(s.clone()))).collect();
            let prims: Vec<u32> = (0..count as u32).collect();
            let lanes = SphereLanes::copied(&objects, &prims, vec![(0, count as u32)]);
            // Along a random direction past sphere 0's rim.
            let d = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let across = d.any_orthonormal_vector();
            let r = spheres[0].radius;
            let reach = match trial % 6 {
                5 => 1.01 * r,
                k => f64::from_bits((r.to_bits() as i64 + [-3i64, -1, 0, 1, 3][k]) as u64),
            };
            let ray = Ray::new(spheres[0].center + across * reach - 30.0 * d, d);
            let narrow = lanes.prepare(&ray);
            assert!(matches!(narrow, LeafRay::Narrow(_)));
            for (which, keep) in [
                lanes.candidates(0, count, &narrow),
                lanes.candidates(0, count, &LeafRay::Exact(&ray)),
            ]
            .into_iter()
            .enumerate()
            {
                assert_eq!(keep >> count, 0, "lanes past the leaf");
                for (l, sphere) in spheres.iter().enumerate() {
                    if keep >> l & 1 == 0 {
                        let hit = sphere.intersect(&ray, f64::NEG_INFINITY, f64::INFINITY);
                        assert!(hit.is_none(), "sift {which}: lane {l} dropped, hit {hit:?}, {ray:?}");
                    }
                }
                let rim = keep & 1;
                match (which, trial % 6) {
                    (0, 5) => sifted += 1 - rim,
                    (1, k) if k < 5 => (dropped, kept) = (dropped + 1 - rim, kept + rim),
                    _ => {}
                }
            }
        }
        assert!(
            dropped > 300 && kept > 1200,
            "rim lanes: {dropped} dropped, {kept} kept"
        );
        assert_eq!(sifted, 500, "lanes 1 % outside the rim dropped in f32");
    }
}
