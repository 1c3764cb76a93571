//! The BVH's spheres side by side in leaf order, so that a leaf's spheres are read from one
//! run of memory and tested 4, 8, 16 or 32 at a time.
//!
//! A walk through a million-sphere tree waits on memory: the objects, met in leaf order,
//! lie scattered, and reading an object's first byte costs more than its sphere test. So
//! the tree keeps its own copy of each sphere: for the leaf of entries `first..first +
//! count` (at most [`MAX_LEAF`] of them), `count` centre `x`s, then `count` `y`s, `count`
//! `z`s and `count` radii, from `4 * first` on (32 bytes an entry, no more than the
//! spheres themselves). The object indices stay in the tree's leaf order; an entry that is
//! not a sphere holds a NaN radius and is tested as its object. Only trees of more than
//! [`FINE_LEAVES_UP_TO`] objects have the copies: a smaller tree's objects stay in the
//! caches, and its fine leaves already take up to 56 bytes an object, which the copies would
//! take past the tree's budget of 64 (BENCHMARKS.md, "Memory and node cost").
//!
//! [`SphereLanes::candidates`] computes, for the lanes of a leaf at once (the fewest of 4,
//! 8, 16 or 32 that hold it: a sifted tree's leaves hold up to [`MAX_LEAF`],
//! [`super::build::LeafTest::Sifted`]), the discriminant of the sphere's test
//! ([`sphere_discriminant`], the first step of `sphere_roots`) lane by lane (no fused
//! multiply-add, nothing reassociated), so each lane has the scalar routine's bits, and
//! drops the lanes whose discriminant is negative: those
//! the scalar routine misses at its first test. With AVX-512 the mask of the lanes kept is
//! made by one comparison into a mask register per eight lanes ([`Masks`]); for the portable
//! loop the compiler builds the mask bit by bit, storing the discriminants and reading them
//! back at other offsets, which the processor cannot forward. Every other lane is tested by
//! the sphere's own routine, which gives its hit, so the walk's answer is the scalar walk's
//! to the bit.

use super::build::{FINE_LEAVES_UP_TO, LeafTest, MAX_LEAF, PrimRef};
use crate::math::Ray;
use crate::scene::Object;
use crate::shape::{Shape, Sphere, sphere_discriminant};
use glam::DVec3;
use rayon::prelude::*;

/// Lanes of the widest sift, and the values of padding past the last leaf's run (one
/// fewer).
const LANES: usize = 32;
const _: () = assert!(MAX_LEAF <= LANES, "a leaf's spheres fit the widest sift");

/// The spheres of the leaf order, per leaf as four runs (see the module doc).
#[derive(Clone, Debug, Default)]
pub struct SphereLanes {
    /// `4 * entries` values, then `LANES - 1` of padding, so that every lane load of the
    /// last leaf stays in the array.
    values: Vec<f64>,
    masks: Masks,
}

/// How a sift turns its lanes' discriminants into the bit mask of the lanes kept.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Masks {
    /// Lane by lane, on any processor.
    #[default]
    Portable,
    /// Up to eight lanes a comparison into a mask register (AVX-512 F and VL), on a
    /// processor that has them: the compiler builds the portable mask from single bits.
    Avx512,
}

impl Masks {
    /// [`Masks::Avx512`] where the processor has it, else [`Masks::Portable`].
    pub fn fastest() -> Masks {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx512f") && std::arch::is_x86_feature_detected!("avx512vl") {
            return Masks::Avx512;
        }
        Masks::Portable
    }

    /// The lanes of `disc` (bit `l` for lane `l`) that are not negative: a NaN (a
    /// non-sphere's radius) is kept, `-0` too.
    #[inline(always)]
    fn not_negative<const N: usize>(self, disc: &[f64; N]) -> u32 {
        #[cfg(target_arch = "x86_64")]
        if self == Masks::Avx512 {
            use std::arch::x86_64::{
                _CMP_NLT_UQ, _mm256_cmp_pd_mask, _mm256_loadu_pd, _mm256_setzero_pd, _mm512_cmp_pd_mask,
                _mm512_loadu_pd, _mm512_setzero_pd,
            };
            // A plain loop, not a closure: a closure is compiled apart from the walk, without
            // its instructions, and would call each intrinsic.
            let mut keep = 0;
            // SAFETY: `Masks::Avx512` is chosen only where the processor has AVX-512 F and
            // VL, and every load is within `disc` (`N` is 4 or a multiple of 8).
            unsafe {
                if N == 4 {
                    keep = u32::from(_mm256_cmp_pd_mask::<_CMP_NLT_UQ>(
                        _mm256_loadu_pd(disc.as_ptr()),
                        _mm256_setzero_pd(),
                    ));
                } else {
                    for k in 0..N / 8 {
                        let lanes = _mm512_loadu_pd(disc.as_ptr().add(8 * k));
                        keep |= u32::from(_mm512_cmp_pd_mask::<_CMP_NLT_UQ>(lanes, _mm512_setzero_pd())) << (8 * k);
                    }
                }
            }
            return keep;
        }
        let mut keep = 0;
        for (l, &x) in disc.iter().enumerate() {
            keep |= u32::from((x >= 0.0) | x.is_nan()) << l;
        }
        keep
    }
}

impl PartialEq for SphereLanes {
    /// The same bits (the NaN of a non-sphere entry equals itself).
    fn eq(&self, other: &Self) -> bool {
        self.values.len() == other.values.len()
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

impl SphereLanes {
    /// The copies for the leaf order `prims`; `None` when no object is a sphere or the
    /// tree holds at most [`FINE_LEAVES_UP_TO`] objects. `leaves` lists the leaves (first
    /// entry and count, in any order), asked for only when there are copies to make.
    /// Its sifts make their masks as `masks` says.
    pub fn new(
        objects: &[Object],
        prims: &[u32],
        leaves: impl FnOnce() -> Vec<(u32, u32)>,
        masks: Masks,
    ) -> Option<Self> {
        if prims.len() <= FINE_LEAVES_UP_TO || !objects.iter().any(|o| matches!(o.shape, Shape::Sphere(_))) {
            return None;
        }
        Some(Self::copied(objects, prims, leaves(), masks))
    }

    /// How the walks will test the leaves of the tree over `refs`: sifted whole when the
    /// tree will have copies ([`SphereLanes::new`]) and every entry is a sphere.
    pub fn leaf_test(objects: &[Object], refs: &[PrimRef]) -> LeafTest {
        let all_spheres = || {
            refs.par_iter()
                .all(|r| matches!(objects[r.index as usize].shape, Shape::Sphere(_)))
        };
        if refs.len() > FINE_LEAVES_UP_TO && all_spheres() {
            LeafTest::Sifted
        } else {
            LeafTest::Scanned
        }
    }

    /// The copies for the leaf order `prims`, whose leaves (first entry and count, in any
    /// order) are `leaves`.
    fn copied(objects: &[Object], prims: &[u32], mut leaves: Vec<(u32, u32)>, masks: Masks) -> Self {
        let len = 4 * prims.len() + LANES - 1;
        let mut values = Vec::with_capacity(len);
        values.resize(len, f64::NAN);
        // The leaves are disjoint and cover the leaf order: in order, their runs follow
        // one another.
        leaves.par_sort_unstable();
        fill(&mut values, 0, &leaves, prims, objects);
        SphereLanes { values, masks }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.values.len() * size_of::<f64>()
    }

    /// The address of the run of the leaf whose first entry is `first` (for a prefetch).
    #[inline(always)]
    pub fn first_byte(&self, first: usize) -> *const u8 {
        self.values.as_ptr().wrapping_add(4 * first).cast()
    }

    /// Entry `first + lane` of the leaf of entries `first..first + count`.
    #[inline(always)]
    pub fn entry(&self, first: usize, count: usize, lane: usize) -> LaneEntry {
        let v = &self.values[4 * first..];
        let r = v[3 * count + lane];
        if r.is_nan() {
            return LaneEntry::Object;
        }
        LaneEntry::Sphere(Sphere::new(
            DVec3::new(v[lane], v[count + lane], v[2 * count + lane]),
            r,
        ))
    }

    /// The lanes (bit `l` for entry `first + l`) of the leaf of entries `first..first +
    /// count` that the ray may hit: every entry but the spheres whose discriminant is
    /// negative (see the module doc).
    /// A leaf is sifted on the fewest of 4, 8, 16 or 32 lanes that hold it.
    #[inline(always)]
    pub fn candidates(&self, first: usize, count: usize, ray: &Ray) -> u32 {
        let keep = if count <= 4 {
            self.sift::<4>(first, count, ray)
        } else if count <= 8 {
            self.sift::<8>(first, count, ray)
        } else if count <= 16 {
            self.sift::<16>(first, count, ray)
        } else {
            self.sift::<LANES>(first, count, ray)
        };
        keep & ((1 << count) - 1)
    }

    /// The discriminant test of [`SphereLanes::candidates`] on `N` lanes from the leaf's
    /// first entry (lanes past its count read the next run or the padding; the caller
    /// masks them).
    #[inline(always)]
    fn sift<const N: usize>(&self, first: usize, count: usize, ray: &Ray) -> u32 {
        let v = &self.values[4 * first..4 * first + 3 * count + N];
        let (cx, cy, cz, r) = (
            run::<N>(v, 0),
            run::<N>(v, count),
            run::<N>(v, 2 * count),
            run::<N>(v, 3 * count),
        );
        // A plain loop over the lanes, vectorised by the compiler: the sphere test's own
        // discriminant, lane by lane.
        let mut disc = [0.0f64; N];
        for l in 0..N {
            disc[l] = sphere_discriminant(DVec3::new(cx[l], cy[l], cz[l]), r[l], ray).0;
        }
        self.masks.not_negative(&disc)
    }
}

/// The `N` values of `v` from `start`: a function, not a closure, so that it is inlined into
/// the walk (the compiler may compile a closure apart from it).
#[inline(always)]
fn run<const N: usize>(v: &[f64], start: usize) -> &[f64; N] {
    v[start..start + N]
        .try_into()
        .expect("a sift's lanes lie in the values")
}

/// Fills the runs of `leaves` (in order, the first starting at entry `base`) in `values`,
/// which starts at that leaf's run: halves of the leaves in parallel, down to blocks of
/// [`FILL_BLOCK`] leaves.
fn fill(values: &mut [f64], base: usize, leaves: &[(u32, u32)], prims: &[u32], objects: &[Object]) {
    if leaves.len() > FILL_BLOCK {
        let (low, high) = leaves.split_at(leaves.len() / 2);
        let middle = high[0].0 as usize;
        let (a, b) = values.split_at_mut(4 * (middle - base));
        rayon::join(
            || fill(a, base, low, prims, objects),
            || fill(b, middle, high, prims, objects),
        );
        return;
    }
    for &(first, count) in leaves {
        let (first, n) = (first as usize, count as usize);
        let run = &mut values[4 * (first - base)..][..4 * n];
        for (l, &j) in prims[first..first + n].iter().enumerate() {
            if let Shape::Sphere(s) = &objects[j as usize].shape {
                run[l] = s.center.x;
                run[n + l] = s.center.y;
                run[2 * n + l] = s.center.z;
                run[3 * n + l] = s.radius;
            }
        }
    }
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
    /// coordinates axis by axis, the cuboid reads as an object.
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
        let lanes = SphereLanes::copied(&objects, &prims, vec![(4, 4), (0, 3), (3, 1)], Masks::Portable);
        assert_eq!(lanes.bytes(), (4 * 8 + LANES - 1) * 8);
        assert_eq!(
            &lanes.values[..12],
            &[7.0, 6.0, 5.0, 17.0, 16.0, 15.0, 27.0, 26.0, 25.0, 7.5, 6.5, 5.5]
        );
        assert!(lanes.values[12..16].iter().all(|v| v.is_nan()));
        assert_eq!(lanes.entry(3, 1, 0), LaneEntry::Object);
        for (k, &j) in prims.iter().enumerate() {
            let (first, count) = if k < 3 {
                (0, 3)
            } else if k == 3 {
                (3, 1)
            } else {
                (4, 4)
            };
            match (lanes.entry(first, count, k - first), &objects[j as usize].shape) {
                (LaneEntry::Sphere(s), Shape::Sphere(o)) => assert_eq!(&s, o, "entry {k}"),
                (LaneEntry::Object, Shape::Cuboid(_)) => {}
                (e, _) => panic!("entry {k}: {e:?}"),
            }
        }
        // Without a sphere, or in a tree of at most `FINE_LEAVES_UP_TO` objects, there are
        // no copies.
        assert!(SphereLanes::new(&objects, &prims, || vec![(4, 4), (0, 3), (3, 1)], Masks::Portable).is_none());
        let many = vec![objects[3].clone(); FINE_LEAVES_UP_TO + 1];
        let order: Vec<u32> = (0..many.len() as u32).collect();
        assert!(SphereLanes::new(&many, &order, || vec![(0, 1)], Masks::Portable).is_none());
        let many = vec![objects[0].clone(); FINE_LEAVES_UP_TO + 1];
        let leaves = (0..many.len() as u32).map(|i| (i, 1)).collect();
        assert!(SphereLanes::new(&many, &order, || leaves, Masks::Portable).is_some());
    }

    /// A lane is dropped only when its discriminant is negative: `-0`, NaNs of either sign
    /// and `+inf` are kept, `-inf` and the smallest negative subnormal dropped, by both
    /// masks and on every width.
    #[test]
    fn masks_drop_only_negative_lanes() {
        let pattern = [
            -1.0,
            -0.0,
            0.0,
            f64::NAN,
            -f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            -5e-324,
        ];
        // Kept: lanes 1 to 5 of each group of eight.
        let want = |n: usize| {
            (0..n)
                .filter(|l| (1..=5).contains(&(l % 8)))
                .fold(0u32, |m, l| m | 1 << l)
        };
        for masks in [Masks::Portable, Masks::fastest()] {
            let four: [f64; 4] = std::array::from_fn(|l| pattern[l]);
            assert_eq!(masks.not_negative(&four), want(4), "{masks:?}");
            let eight: [f64; 8] = std::array::from_fn(|l| pattern[l % 8]);
            assert_eq!(masks.not_negative(&eight), want(8), "{masks:?}");
            let sixteen: [f64; 16] = std::array::from_fn(|l| pattern[l % 8]);
            assert_eq!(masks.not_negative(&sixteen), want(16), "{masks:?}");
            let mut wide: [f64; 32] = std::array::from_fn(|l| pattern[l % 8]);
            assert_eq!(masks.not_negative(&wide), want(32), "{masks:?}");
            wide[31] = -2.0;
            wide[30] = 3.0;
            assert_eq!(masks.not_negative(&wide), want(32) & !(1 << 31) | 1 << 30, "{masks:?}");
        }
    }

    /// Rays along the rim of a leaf's spheres, a few units in the last place inside and
    /// outside it: a lane is dropped only when the sphere's own test misses, at any `t`,
    /// and near the rim both outcomes occur. Lanes past the leaf's count are never kept.
    #[test]
    fn only_misses_are_dropped() {
        let mut s = crate::sampling::Stream::new(5, crate::sampling::Purpose::Generator, 0);
        let mut next = || s.next_f64();
        let (mut dropped, mut kept) = (0, 0);
        for trial in 0..2000 {
            let count = 1 + trial % MAX_LEAF;
            let spheres: Vec<Sphere> = (0..count)
                .map(|_| {
                    let c = DVec3::new(next(), next(), next()) * 20.0 - 10.0;
                    Sphere::new(c, 0.01 + next())
                })
                .collect();
            let objects: Vec<Object> = spheres.iter().map(|s| object(Shape::Sphere(s.clone()))).collect();
            let prims: Vec<u32> = (0..count as u32).collect();
            let lanes = SphereLanes::copied(&objects, &prims, vec![(0, count as u32)], Masks::Portable);
            let fastest = SphereLanes::copied(&objects, &prims, vec![(0, count as u32)], Masks::fastest());
            // Along a random direction past sphere 0's rim.
            let d = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let across = d.any_orthonormal_vector();
            let ulps = [-3i64, -1, 0, 1, 3][trial % 5];
            let reach = f64::from_bits((spheres[0].radius.to_bits() as i64 + ulps) as u64);
            let ray = Ray::new(spheres[0].center + across * reach - 30.0 * d, d);
            let keep = lanes.candidates(0, count, &ray);
            assert_eq!(keep >> count, 0, "lanes past the leaf");
            assert_eq!(fastest.candidates(0, count, &ray), keep, "{:?}", Masks::fastest());
            for (l, sphere) in spheres.iter().enumerate() {
                if keep >> l & 1 == 0 {
                    let hit = sphere.intersect(&ray, f64::NEG_INFINITY, f64::INFINITY);
                    assert!(hit.is_none(), "lane {l} dropped, hit {hit:?}, {ray:?}");
                    dropped += (l == 0) as u32;
                } else {
                    kept += (l == 0) as u32;
                }
            }
        }
        assert!(dropped > 300 && kept > 800, "rim lanes: {dropped} dropped, {kept} kept");
    }
}
