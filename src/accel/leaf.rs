//! The BVH's spheres side by side in leaf order, so that a leaf's spheres are read from one
//! run of memory and sifted 4, 8, 16 or 32 at a time in `f32`.
//!
//! A walk through a million-sphere tree waits on memory: the objects, met in leaf order,
//! lie scattered, and reading an object's first byte costs more than its sphere test. So
//! the tree keeps its own copies of the spheres, in leaf order:
//! - for the sift, per leaf of entries `first..first + count` (at most [`MAX_LEAF`] of
//!   them), `count` centre `x`s rounded to `f32`, then `count` `y`s, `count` `z`s and
//!   `count` radius terms ([`radius_term`]), from `4 * first` on (16 bytes an entry);
//! - for the test of the lanes the sift keeps, in a tree of spheres only (a sifted tree),
//!   each entry's sphere in `f64` (32 bytes); another tree's spheres are read from their
//!   objects, which keeps it within 64 bytes an object.
//!
//! The object indices stay in the tree's leaf order; an entry that is not a sphere holds
//! NaNs and is tested as its object. Only trees of more than [`FINE_LEAVES_UP_TO`] objects
//! whose boxes fit `f32` have the copies: a smaller tree's objects stay in the caches.
//!
//! [`SphereLanes::candidates`] runs the `f32` sift of [`super::sift`] on the lanes of a
//! leaf at once (the fewest of 4, 8, 16 or 32 that hold it: a sifted tree's leaves hold up
//! to [`MAX_LEAF`], [`super::build::LeafTest::Sifted`]) and drops the spheres it proves the
//! `f64` sphere test misses at its first step: a walk reads 16 bytes of each sphere of a
//! leaf it enters and 32 more of the few the sift keeps. The mask of the lanes kept is
//! made by one comparison per sixteen lanes into a mask register with AVX-512, per eight
//! lanes with AVX2 and per four with SSE, then its sign bits ([`Masks`]). Every lane
//! kept is tested by the sphere's own `f64` routine, so the walk's answer is the scalar
//! walk's to the bit; a ray beyond the sift's range has every entry of a leaf tested so.

use super::build::{FINE_LEAVES_UP_TO, LeafTest, MAX_LEAF, PrimRef};
use super::sift::{NarrowRay, radius_term};
use crate::math::Ray;
use crate::scene::Object;
use crate::shape::{Shape, Sphere};
use glam::DVec3;
use rayon::prelude::*;

/// Lanes of the widest sift, and the values of padding past the last leaf's run (one
/// fewer).
const LANES: usize = 32;
const _: () = assert!(MAX_LEAF <= LANES, "a leaf's spheres fit the widest sift");

/// The spheres of the leaf order: per leaf four `f32` runs for the sift, and in a sifted tree
/// each sphere in `f64` (see the module doc).
#[derive(Clone, Debug, Default)]
pub struct SphereLanes {
    /// `4 * entries` values, then `LANES - 1` of padding, so that every lane load of the
    /// last leaf stays in the array.
    values: Vec<f32>,
    /// The largest distance of a sphere's centre from the world's origin, rounded up.
    center_reach: f64,
    /// In a sifted tree, per entry of the leaf order, its sphere in `f64`: the walk tests
    /// the lanes the sift keeps on these, which lie with the leaf's other entries, not on
    /// the scattered objects. Empty in other trees.
    exact: Vec<Sphere>,
    masks: Masks,
}

/// How a sift turns its lanes' discriminants into the bit mask of the lanes kept.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Masks {
    /// Four lanes a comparison on x86-64 (SSE, which every x86-64 processor has), lane by
    /// lane elsewhere: the compiler's own mask, built from single bits, takes two
    /// instructions a lane.
    #[default]
    Portable,
    /// Eight lanes a comparison and its sign bits (AVX), where the walks run on AVX2.
    Avx,
    /// Up to sixteen lanes a comparison into a mask register (AVX-512 F and VL), on a
    /// processor that has them.
    Avx512,
}

impl Masks {
    /// The masks of the walks' widest instructions on this processor (see
    /// [`super::Kernel::Widest`]): [`Masks::Avx512`], [`Masks::Avx`] where it has AVX2, else
    /// [`Masks::Portable`].
    pub fn fastest() -> Masks {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx512f") && std::arch::is_x86_feature_detected!("avx512vl") {
            return Masks::Avx512;
        } else if std::arch::is_x86_feature_detected!("avx2") {
            return Masks::Avx;
        }
        Masks::Portable
    }

    /// The lanes of `margin` (bit `l` for lane `l`) that are not negative: a NaN (a
    /// non-sphere's lane) is kept, `-0` too.
    #[inline(always)]
    pub fn not_negative<const N: usize>(self, margin: &[f32; N]) -> u32 {
        #[cfg(target_arch = "x86_64")]
        if self == Masks::Avx512 {
            use std::arch::x86_64::{
                _CMP_NLT_UQ, _mm_cmp_ps_mask, _mm_loadu_ps, _mm_setzero_ps, _mm256_cmp_ps_mask, _mm256_loadu_ps,
                _mm256_setzero_ps, _mm512_cmp_ps_mask, _mm512_loadu_ps, _mm512_setzero_ps,
            };
            // A plain loop, not a closure: a closure is compiled apart from the walk, without
            // its instructions, and would call each intrinsic.
            let mut keep = 0;
            // SAFETY: `Masks::Avx512` is chosen only where the processor has AVX-512 F and
            // VL, and every load is within `margin` (`N` is 4, 8 or a multiple of 16).
            unsafe {
                let at = margin.as_ptr();
                if N == 4 {
                    keep = u32::from(_mm_cmp_ps_mask::<_CMP_NLT_UQ>(_mm_loadu_ps(at), _mm_setzero_ps()));
                } else if N == 8 {
                    keep = u32::from(_mm256_cmp_ps_mask::<_CMP_NLT_UQ>(
                        _mm256_loadu_ps(at),
                        _mm256_setzero_ps(),
                    ));
                } else {
                    for k in 0..N / 16 {
                        let lanes = _mm512_loadu_ps(at.add(16 * k));
                        keep |= u32::from(_mm512_cmp_ps_mask::<_CMP_NLT_UQ>(lanes, _mm512_setzero_ps())) << (16 * k);
                    }
                }
            }
            return keep;
        }
        #[cfg(target_arch = "x86_64")]
        if self == Masks::Avx && N >= 8 {
            use std::arch::x86_64::{
                _CMP_NLT_UQ, _mm256_cmp_ps, _mm256_loadu_ps, _mm256_movemask_ps, _mm256_setzero_ps,
            };
            let mut keep = 0;
            for k in 0..N / 8 {
                // SAFETY: `Masks::Avx` is chosen only where the processor has AVX2 (and so
                // AVX), and the load is within `margin` (`N` is 8 or a multiple of 16).
                let lanes = unsafe {
                    _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_NLT_UQ>(
                        _mm256_loadu_ps(margin.as_ptr().add(8 * k)),
                        _mm256_setzero_ps(),
                    ))
                };
                keep |= (lanes as u32) << (8 * k);
            }
            return keep;
        }
        let mut keep = 0;
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_mm_cmpnlt_ps, _mm_loadu_ps, _mm_movemask_ps, _mm_setzero_ps};
            for k in 0..N / 4 {
                // SAFETY: SSE is part of x86-64, and the load is within `margin` (`N` is 4, 8
                // or a multiple of 16).
                let lanes = unsafe {
                    _mm_movemask_ps(_mm_cmpnlt_ps(
                        _mm_loadu_ps(margin.as_ptr().add(4 * k)),
                        _mm_setzero_ps(),
                    ))
                };
                keep |= (lanes as u32) << (4 * k);
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        for (l, &x) in margin.iter().enumerate() {
            keep |= u32::from((x >= 0.0) | x.is_nan()) << l;
        }
        keep
    }
}

impl PartialEq for SphereLanes {
    /// The same bits (the NaN of a non-sphere entry equals itself).
    fn eq(&self, other: &Self) -> bool {
        let bits = |s: &Sphere| [s.center.x, s.center.y, s.center.z, s.radius].map(f64::to_bits);
        self.center_reach == other.center_reach
            && self.values.len() == other.values.len()
            && self
                .values
                .iter()
                .zip(&other.values)
                .all(|(a, b)| a.to_bits() == b.to_bits())
            && self.exact.len() == other.exact.len()
            && self.exact.iter().zip(&other.exact).all(|(a, b)| bits(a) == bits(b))
    }
}

impl SphereLanes {
    /// The copies for the leaf order `prims` of a tree whose leaves are tested as
    /// `leaf_test` says; `None` when no object is a sphere, the tree holds at most
    /// [`FINE_LEAVES_UP_TO`] objects or its boxes do not fit `f32` (`fits_f32`). The `f64`
    /// spheres are copied only for a sifted tree: in another, they would take it past its
    /// budget of 64 bytes an object, and the spheres the sift keeps are read from their
    /// objects. `leaves` lists the leaves (first entry and count, in any order), asked for
    /// only when there are copies to make. Its sifts make their masks as `masks` says.
    pub fn new(
        objects: &[Object],
        prims: &[u32],
        leaf_test: LeafTest,
        fits_f32: bool,
        leaves: impl FnOnce() -> Vec<(u32, u32)>,
        masks: Masks,
    ) -> Option<Self> {
        if !fits_f32 || prims.len() <= FINE_LEAVES_UP_TO || !objects.iter().any(|o| matches!(o.shape, Shape::Sphere(_)))
        {
            return None;
        }
        Some(Self::copied(objects, prims, leaf_test, leaves(), masks))
    }

    /// How the walks will test the leaves of the tree over `refs`: sifted whole when the
    /// tree will have copies ([`SphereLanes::new`]: more than [`FINE_LEAVES_UP_TO`] objects,
    /// boxes that fit `f32`) and every entry is a sphere.
    pub fn leaf_test(objects: &[Object], refs: &[PrimRef], fits_f32: bool) -> LeafTest {
        let sphere = |r: &PrimRef| matches!(objects[r.index as usize].shape, Shape::Sphere(_));
        if fits_f32 && refs.len() > FINE_LEAVES_UP_TO && refs.par_iter().all(sphere) {
            LeafTest::Sifted
        } else {
            LeafTest::Scanned
        }
    }

    /// The copies for the leaf order `prims`, whose leaves (first entry and count, in any
    /// order) are `leaves`.
    fn copied(
        objects: &[Object],
        prims: &[u32],
        leaf_test: LeafTest,
        mut leaves: Vec<(u32, u32)>,
        masks: Masks,
    ) -> Self {
        let len = 4 * prims.len() + LANES - 1;
        let mut values = Vec::with_capacity(len);
        values.resize(len, f32::NAN);
        // The leaves are disjoint and cover the leaf order: in order, their runs follow
        // one another.
        leaves.par_sort_unstable();
        let center_reach = fill(&mut values, 0, &leaves, prims, objects);
        let exact = match leaf_test {
            LeafTest::Sifted => prims
                .par_iter()
                .map(|&j| match &objects[j as usize].shape {
                    Shape::Sphere(s) => s.clone(),
                    _ => Sphere::new(DVec3::ZERO, f64::NAN),
                })
                .collect(),
            LeafTest::Scanned => Vec::new(),
        };
        SphereLanes {
            values,
            center_reach,
            exact,
            masks,
        }
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.values.len() * size_of::<f32>() + self.exact.len() * size_of::<Sphere>()
    }

    /// The address of the run of the leaf whose first entry is `first` (for a prefetch).
    #[inline(always)]
    pub fn first_byte(&self, first: usize) -> *const u8 {
        self.values.as_ptr().wrapping_add(4 * first).cast()
    }

    /// The sphere of entry `entry` of the leaf order in `f64`, or `None` when the entry is
    /// not a sphere or the tree is not sifted (it is tested as its object).
    #[inline(always)]
    pub fn sphere(&self, entry: usize) -> Option<&Sphere> {
        self.exact.get(entry).filter(|s| !s.radius.is_nan())
    }

    /// The ray prepared for [`SphereLanes::candidates`], or `None` when it is beyond the
    /// sift's range (its leaves' objects are then all tested).
    #[inline(always)]
    pub fn narrow(&self, ray: &Ray) -> Option<NarrowRay> {
        NarrowRay::new(ray, self.center_reach)
    }

    /// Whether the copies of entry `first + lane` of the leaf of entries `first..first +
    /// count` are those of `shape`: its sphere's centre rounded to `f32`, its
    /// [`radius_term`] and the sphere itself, or NaNs for another shape. For tests.
    pub fn holds(&self, first: usize, count: usize, lane: usize, shape: &Shape) -> bool {
        let at = |k: usize| self.values[4 * first + k * count + lane];
        match shape {
            Shape::Sphere(s) => {
                (0..3).all(|k| at(k).to_bits() == (s.center[k] as f32).to_bits())
                    && at(3).to_bits() == radius_term(s.radius).to_bits()
                    && (self.exact.is_empty() || self.sphere(first + lane) == Some(s))
            }
            _ => (0..4).all(|k| at(k).is_nan()) && self.sphere(first + lane).is_none(),
        }
    }

    /// The lanes (bit `l` for entry `first + l`) of the leaf of entries `first..first +
    /// count` that the ray (prepared by [`SphereLanes::narrow`]) may hit: every entry but
    /// the spheres the `f32` sift rules out (see the module doc). A leaf is sifted on the
    /// fewest of 4, 8, 16 or 32 lanes that hold it.
    #[inline(always)]
    pub fn candidates(&self, first: usize, count: usize, ray: &NarrowRay) -> u32 {
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

    /// The sift of [`SphereLanes::candidates`] on `N` lanes from the leaf's first entry
    /// (lanes past its count read the next run or the padding; the caller masks them).
    #[inline(always)]
    fn sift<const N: usize>(&self, first: usize, count: usize, ray: &NarrowRay) -> u32 {
        let v = &self.values[4 * first..4 * first + 3 * count + N];
        let margin = ray.margins(
            run::<N>(v, 0),
            run::<N>(v, count),
            run::<N>(v, 2 * count),
            run::<N>(v, 3 * count),
        );
        self.masks.not_negative(&margin)
    }
}

/// The `N` values of `v` from `start`: a function, not a closure, so that it is inlined into
/// the walk (the compiler may compile a closure apart from it).
#[inline(always)]
fn run<const N: usize>(v: &[f32], start: usize) -> &[f32; N] {
    v[start..start + N]
        .try_into()
        .expect("a sift's lanes lie in the values")
}

/// Fills the runs of `leaves` (in order, the first starting at entry `base`) in `values`,
/// which starts at that leaf's run: halves of the leaves in parallel, down to blocks of
/// [`FILL_BLOCK`] leaves. Returns the largest `|c|` of the spheres copied (0 for none),
/// rounded up.
fn fill(values: &mut [f32], base: usize, leaves: &[(u32, u32)], prims: &[u32], objects: &[Object]) -> f64 {
    if leaves.len() > FILL_BLOCK {
        let (low, high) = leaves.split_at(leaves.len() / 2);
        let middle = high[0].0 as usize;
        let (a, b) = values.split_at_mut(4 * (middle - base));
        let (x, y) = rayon::join(
            || fill(a, base, low, prims, objects),
            || fill(b, middle, high, prims, objects),
        );
        return x.max(y);
    }
    let mut reach = 0.0f64;
    for &(first, count) in leaves {
        let (first, n) = (first as usize, count as usize);
        let run = &mut values[4 * (first - base)..][..4 * n];
        for (l, &j) in prims[first..first + n].iter().enumerate() {
            if let Shape::Sphere(s) = &objects[j as usize].shape {
                let c = s.center;
                run[l] = c.x as f32;
                run[n + l] = c.y as f32;
                run[2 * n + l] = c.z as f32;
                run[3 * n + l] = radius_term(s.radius);
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
    /// centres in `f32` axis by axis, then their radius terms; the cuboid's lane is NaNs.
    #[test]
    fn runs_hold_each_leaf_axis_by_axis() {
        let sphere = |i: f64| object(Shape::Sphere(Sphere::new(DVec3::new(i, 10.0 + i, -20.0 - i), 0.5 + i)));
        let mut objects: Vec<Object> = (0..8).map(|i| sphere(i as f64)).collect();
        objects[3] = object(Shape::Cuboid(Box::new(crate::shape::Cuboid::new(
            DVec3::ZERO,
            DVec3::ONE,
            DVec3::ZERO,
        ))));
        // Leaf order: objects 7, 6, 5 | 3 | 0, 1, 2, 4.
        let prims = [7, 6, 5, 3, 0, 1, 2, 4];
        let leaves = || vec![(4, 4), (0, 3), (3, 1)];
        let lanes = SphereLanes::copied(&objects, &prims, LeafTest::Scanned, leaves(), Masks::Portable);
        // A tree with a cuboid is scanned: no `f64` copies.
        assert_eq!(lanes.bytes(), (4 * 8 + LANES - 1) * 4);
        assert_eq!(lanes.sphere(0), None);
        assert_eq!(
            &lanes.values[..9],
            &[7.0, 6.0, 5.0, 17.0, 16.0, 15.0, -27.0, -26.0, -25.0]
        );
        // `Q`: `A r^2` (`A = 1 + 2^-8 + 2^-16`) grown by `2^-20` for the `f64` rounding and
        // rounded up to `f32`.
        assert_eq!(lanes.values[9], radius_term(7.5));
        let q = 56.25 * (1.0 + 1.0 / 256.0 + 1.0 / 65536.0) * (1.0 + 1.0 / (1 << 20) as f64);
        assert!(lanes.values[9] as f64 >= q && lanes.values[9] as f64 <= q * (1.0 + 1.0 / (1 << 23) as f64));
        assert!(lanes.values[12..16].iter().all(|v| v.is_nan()));
        // The largest `|c|` (object 7, at `(7, 17, -27)`), rounded up by a few ulps.
        let reach = (49.0f64 + 289.0 + 729.0).sqrt();
        assert!(lanes.center_reach >= reach && lanes.center_reach < reach * (1.0 + 1e-15));
        for (k, &j) in prims.iter().enumerate() {
            let (first, count) = match k {
                0..3 => (0, 3),
                3 => (3, 1),
                _ => (4, 4),
            };
            assert!(
                lanes.holds(first, count, k - first, &objects[j as usize].shape),
                "entry {k}"
            );
            assert!(
                !lanes.holds(first, count, k - first, &objects[(j as usize + 1) % 8].shape),
                "entry {k}"
            );
        }
        // Without a sphere, in a tree of at most `FINE_LEAVES_UP_TO` objects or beyond
        // `f32`, there are no copies.
        let scanned = LeafTest::Scanned;
        assert!(SphereLanes::new(&objects, &prims, scanned, true, leaves, Masks::Portable).is_none());
        let many = vec![objects[3].clone(); FINE_LEAVES_UP_TO + 1];
        let order: Vec<u32> = (0..many.len() as u32).collect();
        assert!(SphereLanes::new(&many, &order, scanned, true, || vec![(0, 1)], Masks::Portable).is_none());
        let many = vec![objects[0].clone(); FINE_LEAVES_UP_TO + 1];
        let leaves = || (0..many.len() as u32).map(|i| (i, 1)).collect();
        assert!(SphereLanes::new(&many, &order, scanned, false, leaves, Masks::Portable).is_none());
        assert!(SphereLanes::new(&many, &order, scanned, true, leaves, Masks::Portable).is_some());
    }

    /// A sifted tree (spheres only) also holds each entry's `f64` sphere, in leaf order.
    #[test]
    fn sifted_trees_hold_the_spheres_in_leaf_order() {
        let objects: Vec<Object> = (0..6)
            .map(|i| {
                object(Shape::Sphere(Sphere::new(
                    DVec3::new(i as f64, 0.5, -1.0),
                    0.25 * i as f64,
                )))
            })
            .collect();
        let prims = [5, 3, 1, 0, 2, 4];
        let lanes = SphereLanes::copied(
            &objects,
            &prims,
            LeafTest::Sifted,
            vec![(0, 2), (2, 4)],
            Masks::Portable,
        );
        assert_eq!(lanes.bytes(), (4 * 6 + LANES - 1) * 4 + 6 * 32);
        assert_eq!(lanes.sphere(0), Some(&Sphere::new(DVec3::new(5.0, 0.5, -1.0), 1.25)));
        assert_eq!(lanes.sphere(3), Some(&Sphere::new(DVec3::new(0.0, 0.5, -1.0), 0.0)));
        assert_eq!(lanes.sphere(6), None);
        for (k, &j) in prims.iter().enumerate() {
            let (first, count) = if k < 2 { (0, 2) } else { (2, 4) };
            assert!(
                lanes.holds(first, count, k - first, &objects[j as usize].shape),
                "entry {k}"
            );
        }
        assert!(!lanes.holds(0, 2, 0, &objects[4].shape));
    }

    /// The masks this processor can run: the portable one and those of its vector
    /// extensions.
    fn runnable_masks() -> impl Iterator<Item = Masks> {
        let fastest = Masks::fastest();
        [Masks::Portable, Masks::Avx, Masks::Avx512]
            .into_iter()
            .filter(move |&m| m == Masks::Portable || m == fastest || (m == Masks::Avx && fastest == Masks::Avx512))
    }

    /// A lane is dropped only when its margin is negative: `-0`, NaNs of either sign and
    /// `+inf` are kept, `-inf` and the smallest negative subnormal dropped, by every mask
    /// this processor runs and on every width.
    #[test]
    fn masks_drop_only_negative_lanes() {
        let pattern = [
            -1.0,
            -0.0,
            0.0,
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -1e-45,
        ];
        // Kept: lanes 1 to 5 of each group of eight.
        let want = |n: usize| {
            (0..n)
                .filter(|l| (1..=5).contains(&(l % 8)))
                .fold(0u32, |m, l| m | 1 << l)
        };
        for masks in runnable_masks() {
            let four: [f32; 4] = std::array::from_fn(|l| pattern[l]);
            assert_eq!(masks.not_negative(&four), want(4), "{masks:?}");
            let eight: [f32; 8] = std::array::from_fn(|l| pattern[l % 8]);
            assert_eq!(masks.not_negative(&eight), want(8), "{masks:?}");
            let sixteen: [f32; 16] = std::array::from_fn(|l| pattern[l % 8]);
            assert_eq!(masks.not_negative(&sixteen), want(16), "{masks:?}");
            let mut wide: [f32; 32] = std::array::from_fn(|l| pattern[l % 8]);
            assert_eq!(masks.not_negative(&wide), want(32), "{masks:?}");
            wide[31] = -2.0;
            wide[30] = 3.0;
            wide[17] = 5.0;
            let changed = want(32) & !(1 << 31) | 1 << 30 | 1 << 17;
            assert_eq!(masks.not_negative(&wide), changed, "{masks:?}");
        }
    }

    /// Rays along the rim of a leaf's first sphere, two units in the last place inside and
    /// outside it, and a tenth and a whole radius past it: a lane is dropped only when the
    /// sphere's own test misses, at any `t`; the first sphere is kept at its rim and dropped
    /// past it. Lanes past the leaf's count are never kept, and every mask this processor
    /// runs keeps the portable one's lanes.
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
            let leaf = || vec![(0, count as u32)];
            let lanes = SphereLanes::copied(&objects, &prims, LeafTest::Sifted, leaf(), Masks::Portable);
            let others: Vec<SphereLanes> = runnable_masks()
                .filter(|&m| m != Masks::Portable)
                .map(|m| SphereLanes::copied(&objects, &prims, LeafTest::Sifted, leaf(), m))
                .collect();
            // Along a random direction past sphere 0's rim.
            let d = DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let across = d.any_orthonormal_vector();
            let r = spheres[0].radius;
            let reach = match trial % 5 {
                0 => r.next_down().next_down(),
                1 => r,
                2 => r.next_up().next_up(),
                3 => 1.1 * r,
                _ => 2.0 * r,
            };
            let ray = Ray::new(spheres[0].center + across * reach - 30.0 * d, d);
            let narrow = lanes.narrow(&ray).expect("a ray within the sift");
            let keep = lanes.candidates(0, count, &narrow);
            assert_eq!(keep >> count, 0, "lanes past the leaf");
            for other in &others {
                assert_eq!(other.candidates(0, count, &narrow), keep, "{:?}", other.masks);
            }
            for (l, sphere) in spheres.iter().enumerate() {
                if keep >> l & 1 == 0 {
                    let hit = sphere.intersect(&ray, f64::NEG_INFINITY, f64::INFINITY);
                    assert!(hit.is_none(), "lane {l} dropped, hit {hit:?}, {ray:?}");
                    dropped += (l == 0) as u32;
                } else {
                    kept += (l == 0) as u32;
                }
            }
            // Lane 0 is kept at its rim (the `f64` test's margin is far below the sift's) and
            // dropped a tenth of its radius past it.
            assert_eq!(keep & 1, u32::from(trial % 5 < 3), "trial {trial}: {ray:?}");
        }
        assert!(dropped == 800 && kept == 1200, "lane 0: {dropped} dropped, {kept} kept");
    }
}
