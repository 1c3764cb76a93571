//! The bounding volume hierarchy: closest hit, any hit and every hit over a tree of `f32`
//! boxes (built binary by [`super::build`], walked 4-wide as collapsed by [`super::wide`]),
//! with unbounded objects (planes) tested apart.
//!
//! It returns exactly what the linear scan returns, bit for bit. Two facts make that so:
//! - every shape's hit does not depend on the `t_max` it is given, except that a hit at or
//!   beyond it is dropped (the contract of [`crate::shape::Shape::intersect`]), so shrinking
//!   `t_max` to the best hit so far, in any order, finds the same `t` for each object;
//! - a tie (two objects at the same `t`) goes to the lower object index, as in the scan,
//!   whose strict `<` keeps the first: an object of lower index than the best so far is
//!   asked for hits up to and including the best `t`, one of higher index strictly below.
//!
//! Traversal tests a node's four child boxes at once and pushes the entered children on a
//! stack, farthest first in the node's order for the ray's octant, so the nearest is taken
//! next. A closest-hit walk keeps each child's entry distance and skips a child entered
//! beyond the best hit so far; an any-hit (or every-hit) walk stops at the first hit. The
//! box tests are conservative (see [`super::wide`]), so no object that holds the answer is
//! ever skipped.
//!
//! Up to [`PACKET`] rays whose directions share an octant (neighbouring camera rays, shadow
//! rays towards one light) can be walked together ([`Bvh::closest_packet`],
//! [`Bvh::any_hit_packet`]): a node is loaded once and its children tested for every ray
//! of the packet at once ([`super::packet`]); a child is pushed with the rays that enter
//! it and taken by those whose best hit does not rule it out, and each ray tests a leaf's
//! objects as its own walk would. Each ray's answer is its single walk's, for the same two
//! reasons. Rays of several octants are walked one by one.
//!
//! A tree of more than 4096 objects with spheres among them keeps a copy of the spheres in
//! leaf order ([`SphereLanes`]): a leaf's spheres are read from one run of memory and
//! sifted all at once in `f32` by a test that drops only spheres the routine misses
//! ([`super::sift`]), and the ones left are tested by the routine itself on their `f64`
//! copies. When every object is a sphere, the leaves hold up to 31
//! ([`LeafTest::Sifted`]). The
//! walks are compiled for AVX-512, AVX2 and baseline x86-64, the widest the processor
//! has chosen at run time (`multiversion`), or the baseline as a [`Kernel`] says. As it
//! pushes a child, a walk asks the caches for the child's node or leaf spheres, which it
//! reads later. The nodes and spheres are on the system's ordinary pages: asking Linux
//! for 2 MiB pages (`madvise`) made the incoherent walks 5 % faster but a render no faster,
//! and where the kernel compacts memory to serve them it stalled the build by 0.1 s.

use super::build::{Built, MAX_SAH_DEPTH, PrimRef, build};
use super::leaf::{Masks, SphereLanes};
use super::node::{stored_box, up};
use super::packet::{PACKET, PacketSlots, each_lane};
use super::sift::NarrowRay;
use super::wide::{F32_RANGE, F32Slots, F64Slots, Node4, RayTerms, SlotTest, WIDTH, collapse, unpack};
use crate::math::Ray;
use crate::scene::Object;
use crate::shape::{Shape, Sphere, SurfaceHit};
use multiversion::multiversion;
use rayon::prelude::*;

/// Deepest possible binary tree: SAH splits up to `MAX_SAH_DEPTH`, then halving
/// (`2^23 > MAX_OBJECTS`); the 4-wide tree is no deeper.
const MAX_DEPTH: usize = MAX_SAH_DEPTH + 24;

/// Most entries a walk's stack holds in a tree of `depth`: each level pushes at most four
/// children and takes one of them.
const fn stack_for(depth: usize) -> usize {
    (WIDTH - 1) * depth + WIDTH
}

/// Stack sizes: the walk takes the smallest that holds its tree, so that shallow trees do
/// not fill a large array on every ray.
const SMALL: usize = 16;
const MEDIUM: usize = 64;
const FULL: usize = stack_for(MAX_DEPTH);

/// Tests object `j` for a closest-hit walk whose best hit so far is `best`, and takes its
/// hit when it wins: nearer, or as near with a lower index. An object of lower index than
/// the best is asked for hits up to and including the best `t` (a tie it wins), one of
/// higher index strictly below. Returns whether it won. `sphere`: the leaf order's copy of
/// the object's sphere, else its shape is read from `objects`.
#[inline(always)]
fn consider(
    objects: &[Object],
    ray: &Ray,
    t_min: f64,
    t_max: f64,
    j: usize,
    sphere: Option<&Sphere>,
    best: &mut Option<(usize, SurfaceHit)>,
) -> bool {
    let limit = match *best {
        None => t_max,
        Some((i, h)) if j < i => h.t.next_up(),
        Some((_, h)) => h.t,
    };
    let hit = match sphere {
        Some(s) => sphere_hit(s, ray, t_min, limit),
        None => object_hit(objects, ray, t_min, limit, j),
    };
    if let Some(h) = hit {
        let wins = best.is_none_or(|(i, b)| h.t < b.t || (h.t == b.t && j < i));
        if wins {
            *best = Some((j, h));
        }
        wins
    } else {
        false
    }
}

/// The hit of a copied sphere in `(t_min, t_max)`. A call of its own: inlined into a walk,
/// its square root and divisions (the normal) made the closest-hit walks a fifth to a third
/// slower (BENCHMARKS.md, "Against Embree 3").
#[inline(never)]
fn sphere_hit(sphere: &Sphere, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
    sphere.intersect(ray, t_min, t_max)
}

/// Object `j`'s hit in `(t_min, t_max)`, read from `objects`. A call of its own, so that
/// the walk's leaf test stays small enough to be inlined into the walk and run on its
/// instructions.
#[inline(never)]
fn object_hit(objects: &[Object], ray: &Ray, t_min: f64, t_max: f64, j: usize) -> Option<SurfaceHit> {
    match &objects[j].shape {
        Shape::Sphere(s) => s.intersect(ray, t_min, t_max),
        shape => shape.intersect(ray, t_min, t_max),
    }
}

/// Whether object `j` meets the ray with `t_min < t < t_max`, the sphere's test inlined;
/// `sphere` as in [`consider`].
#[inline(always)]
fn occludes(objects: &[Object], ray: &Ray, t_min: f64, t_max: f64, j: usize, sphere: Option<&Sphere>) -> bool {
    match sphere {
        Some(s) => s.occludes(ray, t_min, t_max),
        None => match &objects[j].shape {
            Shape::Sphere(s) => s.occludes(ray, t_min, t_max),
            shape => shape.occludes(ray, t_min, t_max),
        },
    }
}

/// What a walk does with each object of a leaf it enters: `test(j, sphere)` tests object
/// `j` (`sphere`: the leaf order's copy of its sphere, if any) and returns whether the walk
/// stops there. A trait whose implementations are always inlined into the walk: a closure
/// is the compiler's to inline or not, and one it does not inline is compiled apart from
/// the walk, on baseline instructions, every call losing the vector registers.
trait LeafObjects {
    fn test(&mut self, j: usize, sphere: Option<&Sphere>) -> bool;
}

/// A closest-hit walk's objects: each tested by [`consider`]; `closer` records whether one
/// won since it was last cleared. Never stops the walk.
struct Closest<'a> {
    objects: &'a [Object],
    ray: &'a Ray,
    t_min: f64,
    t_max: f64,
    best: Option<(usize, SurfaceHit)>,
    closer: bool,
}

impl LeafObjects for Closest<'_> {
    #[inline(always)]
    fn test(&mut self, j: usize, sphere: Option<&Sphere>) -> bool {
        self.closer |= consider(
            self.objects,
            self.ray,
            self.t_min,
            self.t_max,
            j,
            sphere,
            &mut self.best,
        );
        false
    }
}

/// The objects accepted by `filter` that the ray meets in `(t_min, t_max)`: the walk stops
/// at the first, or, with `each`, passes every one to it and never stops.
struct Hits<'a> {
    objects: &'a [Object],
    ray: &'a Ray,
    t_min: f64,
    t_max: f64,
    filter: &'a dyn Fn(usize) -> bool,
    each: Option<&'a mut dyn FnMut(usize)>,
}

impl LeafObjects for Hits<'_> {
    #[inline(always)]
    fn test(&mut self, j: usize, sphere: Option<&Sphere>) -> bool {
        if !((self.filter)(j) && occludes(self.objects, self.ray, self.t_min, self.t_max, j, sphere)) {
            return false;
        }
        match &mut self.each {
            None => true,
            Some(each) => {
                each(j);
                false
            }
        }
    }
}

/// Which instructions the walks run on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Kernel {
    /// The widest vectors the processor has: AVX-512, AVX2, else baseline x86-64 (chosen
    /// at run time).
    #[default]
    Widest,
    /// Baseline x86-64 (SSE2) on any processor: the same hits, for tests.
    Baseline,
}

/// The end of a closest-hit walk's interval: the best hit's `t`, else `t_max`.
#[inline(always)]
fn bound(best: &Option<(usize, SurfaceHit)>, t_max: f64) -> f64 {
    best.map_or(t_max, |(_, h)| h.t)
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    /// The 4-wide nodes, root at 0.
    nodes: Vec<Node4>,
    /// Object indices in leaf order: a leaf holds `prims[first..first + count]`.
    prims: Vec<u32>,
    /// The spheres in leaf order, when the scene has any.
    spheres: Option<SphereLanes>,
    /// The instructions the walks run on, and how their vector comparisons become masks.
    kernel: Kernel,
    masks: Masks,
    /// Objects without bounds (planes), tested before the tree.
    unbounded: Vec<u32>,
    /// Depth of the deepest 4-wide node (the root at 0).
    depth: usize,
    /// Whether every box lies within `F32_RANGE`, so rays can be tested in `f32`.
    fits_f32: bool,
}

impl Bvh {
    pub fn new(objects: &[Object]) -> Self {
        Bvh::with_kernel(objects, Kernel::Widest)
    }

    /// [`Bvh::new`] whose walks run on `kernel`.
    pub fn with_kernel(objects: &[Object], kernel: Kernel) -> Self {
        // An indexed map writes each box in place (a filtered one would collect pieces and
        // join them: a fifth of a 1 000 000-sphere build); the unbounded objects' slots,
        // marked, are dropped after.
        const UNBOUNDED: u32 = u32::MAX;
        let mut refs: Vec<PrimRef> = objects
            .par_iter()
            .enumerate()
            .map(|(i, o)| match o.shape.bounds() {
                Some(b) => {
                    let (min, max) = stored_box(&b);
                    PrimRef::new(i as u32, min, max)
                }
                None => PrimRef::new(UNBOUNDED, [0.0; 3], [0.0; 3]),
            })
            .collect();
        refs.retain(|r| r.index != UNBOUNDED);
        // The unbounded objects are the gaps in `refs`, which is in object order.
        let mut unbounded = Vec::new();
        let mut next = 0;
        for i in refs.iter().map(|r| r.index as usize).chain([objects.len()]) {
            unbounded.extend(next as u32..i as u32);
            next = i + 1;
        }
        let fits_f32 = refs
            .par_iter()
            .all(|r| r.min.iter().chain(&r.max).all(|x| x.abs() <= F32_RANGE));
        let leaf_test = SphereLanes::leaf_test(objects, &refs, fits_f32);
        let Built {
            nodes: binary,
            order: prims,
            ..
        } = build(refs, leaf_test);
        let (nodes, depth) = collapse(&binary);
        // The binary tree is freed before the spheres are copied: the two are never held
        // at once.
        drop(binary);
        let masks = match kernel {
            Kernel::Widest => Masks::fastest(),
            Kernel::Baseline => Masks::Portable,
        };
        let spheres = SphereLanes::new(
            objects,
            &prims,
            leaf_test,
            fits_f32,
            || {
                let leaves = || {
                    nodes
                        .iter()
                        .flat_map(|n| n.child)
                        .map(unpack)
                        .filter(|&(_, count)| count > 0)
                        .map(|(first, count)| (first as u32, count as u32))
                };
                // Counted first, so that the list takes no more than it holds.
                let mut list = Vec::with_capacity(leaves().count());
                list.extend(leaves());
                list
            },
            masks,
        );
        Bvh {
            depth,
            nodes,
            prims,
            spheres,
            kernel,
            masks,
            unbounded,
            fits_f32,
        }
    }

    /// Number of (4-wide) nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Depth of the deepest node (the root at 0): which traversal stack a ray gets.
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// Memory held by the structure: nodes, leaf order and its spheres, unbounded list.
    pub fn bytes(&self) -> usize {
        self.nodes.len() * size_of::<Node4>()
            + (self.prims.len() + self.unbounded.len()) * size_of::<u32>()
            + self.spheres.as_ref().map_or(0, SphereLanes::bytes)
    }

    /// Asks the caches for what visiting `child` reads first (its node's two lines, or its
    /// leaf's spheres), as it is pushed: the walk takes the nearest child next and the
    /// farther ones later, and the loads of a million-object tree mostly miss the caches.
    #[inline(always)]
    fn prefetch(&self, child: u32) {
        let (first, count) = unpack(child);
        let line: *const u8 = if count == 0 {
            self.nodes.as_ptr().wrapping_add(first).cast()
        } else if let Some(spheres) = &self.spheres {
            spheres.first_byte(first)
        } else {
            self.prims.as_ptr().wrapping_add(first).cast()
        };
        prefetch_line(line);
        prefetch_line(line.wrapping_add(64));
    }

    /// Calls `leaf.test(j, sphere)` for the objects of the leaf of entries `first..first +
    /// count` in leaf order, until it returns true; returns whether it did. With `sift` (the
    /// ray prepared for the tree's sphere copies), the spheres it rules out are passed by
    /// ([`SphereLanes::candidates`]) and the others tested on their copies (`sphere`).
    #[inline(always)]
    fn leaf_until(&self, first: usize, count: usize, sift: Option<&NarrowRay>, leaf: &mut impl LeafObjects) -> bool {
        // Plain loops, not `Iterator::any`, whose closure the compiler may compile apart.
        let (Some(spheres), Some(ray)) = (&self.spheres, sift) else {
            for &j in &self.prims[first..first + count] {
                if leaf.test(j as usize, None) {
                    return true;
                }
            }
            return false;
        };
        let mut lanes = spheres.candidates(first, count, ray);
        while lanes != 0 {
            let l = lanes.trailing_zeros() as usize;
            lanes &= lanes - 1;
            if leaf.test(self.prims[first + l] as usize, spheres.sphere(first + l)) {
                return true;
            }
        }
        false
    }

    /// The ray prepared for sifting this tree's leaves, if it has sphere copies and the ray
    /// is within the sift's range.
    #[inline(always)]
    fn sift(&self, ray: &Ray) -> Option<NarrowRay> {
        self.spheres.as_ref().and_then(|s| s.narrow(ray))
    }

    /// The `f32` test for this ray when it and the tree fit it, else `None`.
    #[inline(always)]
    fn f32_slots(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<F32Slots> {
        if !self.fits_f32 {
            return None;
        }
        F32Slots::new(ray.origin.to_array(), ray.dir.to_array(), t_min, t_max)
    }

    /// Closest hit: see the module doc for why it equals the linear scan's.
    pub fn closest(&self, objects: &[Object], ray: &Ray, t_min: f64, t_max: f64) -> Option<(usize, SurfaceHit)> {
        match self.kernel {
            Kernel::Widest => closest_widest(self, objects, ray, t_min, t_max),
            Kernel::Baseline => self.closest_walk(objects, ray, t_min, t_max),
        }
    }

    /// [`Bvh::closest`] on the instructions of the function it is inlined into.
    #[inline(always)]
    fn closest_walk(&self, objects: &[Object], ray: &Ray, t_min: f64, t_max: f64) -> Option<(usize, SurfaceHit)> {
        match self.f32_slots(ray, t_min, t_max) {
            Some(s) if stack_for(self.depth) <= SMALL => self.closest_with::<_, SMALL>(objects, ray, t_min, t_max, s),
            Some(s) if stack_for(self.depth) <= MEDIUM => self.closest_with::<_, MEDIUM>(objects, ray, t_min, t_max, s),
            Some(s) => self.closest_with::<_, FULL>(objects, ray, t_min, t_max, s),
            None => {
                let s = F64Slots::new(ray.origin.to_array(), ray.dir.to_array(), t_min, t_max);
                self.closest_with::<_, FULL>(objects, ray, t_min, t_max, s)
            }
        }
    }

    /// [`Bvh::closest`] with the test `slots` and a stack of `S` entries.
    #[inline(always)]
    fn closest_with<T: SlotTest, const S: usize>(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut slots: T,
    ) -> Option<(usize, SurfaceHit)> {
        let mut leaf = Closest {
            objects,
            ray,
            t_min,
            t_max,
            best: None,
            closer: false,
        };
        for &j in &self.unbounded {
            leaf.test(j as usize, None);
        }
        if self.nodes.is_empty() {
            return leaf.best;
        }
        if leaf.best.is_some() {
            slots.set_t_max(bound(&leaf.best, t_max));
        }
        let sift = self.sift(ray);
        let mut stack = [(0u32, 0.0f32); S];
        let mut depth = 0;
        let mut at = 0usize;
        loop {
            let n = &self.nodes[at];
            let (entries, entered) = slots.enter(n);
            let order = n.order[slots.octant()];
            // Farthest first, so that the nearest is on top.
            for k in (0..WIDTH).rev() {
                let s = (order >> (2 * k)) as usize & 3;
                if entered >> s & 1 == 1 {
                    stack[depth] = (n.child[s], entries[s]);
                    depth += 1;
                    self.prefetch(n.child[s]);
                }
            }
            // The next waiting child that the best hit so far does not rule out (an entry
            // equal to the best `t` may still hold a tie of lower index): leaves are tested
            // as they come, an interior node is the next visit.
            loop {
                if depth == 0 {
                    return leaf.best;
                }
                depth -= 1;
                let (child, entry) = stack[depth];
                if entry as f64 > bound(&leaf.best, t_max) {
                    continue;
                }
                let (first, count) = unpack(child);
                if count == 0 {
                    at = first;
                    break;
                }
                leaf.closer = false;
                self.leaf_until(first, count, sift.as_ref(), &mut leaf);
                if leaf.closer {
                    slots.set_t_max(bound(&leaf.best, t_max));
                }
            }
        }
    }

    /// Calls `leaf.test(j, sphere)` for objects whose boxes the ray meets in `[t_min,
    /// t_max]` (`sphere`: the leaf order's copy of object `j`'s sphere, if any), until it
    /// returns true; returns whether it did. The spheres that the first step of their test
    /// rules out are passed by ([`SphereLanes::candidates`]). Generic over `leaf`, so each
    /// caller's test is inlined into the walk (no call through a pointer per object).
    #[inline(always)]
    fn visit(&self, ray: &Ray, t_min: f64, t_max: f64, mut leaf: impl LeafObjects) -> bool {
        match self.f32_slots(ray, t_min, t_max) {
            Some(s) if stack_for(self.depth) <= SMALL => self.visit_with::<_, SMALL>(ray, s, &mut leaf),
            Some(s) if stack_for(self.depth) <= MEDIUM => self.visit_with::<_, MEDIUM>(ray, s, &mut leaf),
            Some(s) => self.visit_with::<_, FULL>(ray, s, &mut leaf),
            None => self.visit_with::<_, FULL>(
                ray,
                F64Slots::new(ray.origin.to_array(), ray.dir.to_array(), t_min, t_max),
                &mut leaf,
            ),
        }
    }

    /// [`Bvh::visit`] with the test `slots` and a stack of `S` entries.
    #[inline(always)]
    fn visit_with<T: SlotTest, const S: usize>(&self, ray: &Ray, slots: T, leaf: &mut impl LeafObjects) -> bool {
        for &j in &self.unbounded {
            if leaf.test(j as usize, None) {
                return true;
            }
        }
        if self.nodes.is_empty() {
            return false;
        }
        let sift = self.sift(ray);
        let mut stack = [0u32; S];
        let mut depth = 0;
        let mut at = 0usize;
        loop {
            let n = &self.nodes[at];
            let (_, entered) = slots.enter(n);
            let order = n.order[slots.octant()];
            for k in (0..WIDTH).rev() {
                let s = (order >> (2 * k)) as usize & 3;
                if entered >> s & 1 == 1 {
                    stack[depth] = n.child[s];
                    depth += 1;
                    self.prefetch(n.child[s]);
                }
            }
            loop {
                if depth == 0 {
                    return false;
                }
                depth -= 1;
                let (first, count) = unpack(stack[depth]);
                if count == 0 {
                    at = first;
                    break;
                }
                if self.leaf_until(first, count, sift.as_ref(), leaf) {
                    return true;
                }
            }
        }
    }

    /// True when some object accepted by `filter` is hit with `t_min < t < t_max`; stops at
    /// the first.
    pub fn any_hit(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
    ) -> bool {
        match self.kernel {
            Kernel::Widest => any_hit_widest(self, objects, ray, t_min, t_max, filter),
            Kernel::Baseline => self.any_hit_walk(objects, ray, t_min, t_max, filter),
        }
    }

    /// [`Bvh::any_hit`] on the instructions of the function it is inlined into.
    #[inline(always)]
    fn any_hit_walk(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
    ) -> bool {
        self.visit_hits(objects, ray, t_min, t_max, filter, None)
    }

    /// [`Bvh::visit`] for [`Hits`]: stops at the first object accepted by `filter` that
    /// the ray meets in `(t_min, t_max)`, or passes every one to `each`.
    #[inline(always)]
    fn visit_hits<'a>(
        &self,
        objects: &'a [Object],
        ray: &'a Ray,
        t_min: f64,
        t_max: f64,
        filter: &'a dyn Fn(usize) -> bool,
        each: Option<&'a mut dyn FnMut(usize)>,
    ) -> bool {
        let hits = Hits {
            objects,
            ray,
            t_min,
            t_max,
            filter,
            each,
        };
        self.visit(ray, t_min, t_max, hits)
    }

    /// Calls `visit` for every object accepted by `filter` hit in `(t_min, t_max)`, in tree
    /// order (callers that combine the objects sort them first).
    pub fn each_hit(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
        visit: &mut dyn FnMut(usize),
    ) {
        self.visit_hits(objects, ray, t_min, t_max, filter, Some(visit));
    }

    /// The packet test for `rays` (at least 2, at most [`PACKET`]) when they and the tree fit
    /// the `f32` test and share an octant, else `None` (they are then walked one by one).
    #[inline(always)]
    fn packet_slots(&self, rays: &[Ray], t_min: f64, t_max: f64) -> Option<PacketSlots> {
        if !self.fits_f32 || !(2..=PACKET).contains(&rays.len()) {
            return None;
        }
        // Rays of several octants (most incoherent packets) are told apart by their signs
        // alone, before any term is computed.
        let signs = |r: &Ray| r.dir.to_array().map(f64::is_sign_negative);
        if rays.iter().any(|r| signs(r) != signs(&rays[0])) {
            return None;
        }
        PacketSlots::new(rays.len(), |l| {
            RayTerms::new(rays[l].origin.to_array(), rays[l].dir.to_array(), t_min, t_max)
        })
    }

    /// [`Bvh::closest`] for each of `rays` (at most [`PACKET`]), into `out`: rays of one
    /// octant are walked together, loading and testing each node once for all of them
    /// ([`PacketSlots`]); each ray's answer is its own walk's, to the bit.
    pub fn closest_packet(
        &self,
        objects: &[Object],
        rays: &[Ray],
        t_min: f64,
        t_max: f64,
        out: &mut [Option<(usize, SurfaceHit)>],
    ) {
        assert!(
            rays.len() <= PACKET && out.len() == rays.len(),
            "a packet of at most {PACKET} rays and answers"
        );
        match self.kernel {
            Kernel::Widest => closest_packet_widest(self, objects, rays, t_min, t_max, out),
            Kernel::Baseline => self.closest_packet_walk(objects, rays, t_min, t_max, out),
        }
    }

    /// [`Bvh::closest_packet`] on the instructions of the function it is inlined into.
    #[inline(always)]
    fn closest_packet_walk(
        &self,
        objects: &[Object],
        rays: &[Ray],
        t_min: f64,
        t_max: f64,
        out: &mut [Option<(usize, SurfaceHit)>],
    ) {
        let Some(slots) = self.packet_slots(rays, t_min, t_max) else {
            // One walk at a time, each through the call that picks its instructions: inlined
            // here, the single walk ran slower.
            for (ray, out) in rays.iter().zip(out) {
                *out = self.closest(objects, ray, t_min, t_max);
            }
            return;
        };
        if stack_for(self.depth) <= MEDIUM {
            self.closest_packet_with::<MEDIUM>(objects, rays, t_min, t_max, slots, out);
        } else {
            self.closest_packet_with::<FULL>(objects, rays, t_min, t_max, slots, out);
        }
    }

    /// [`Bvh::closest_packet`] with the test `slots` and a stack of `S` entries: a child is
    /// pushed with the lanes that enter it and their entries, and taken by the lanes whose
    /// best hit so far does not rule it out.
    #[inline(always)]
    fn closest_packet_with<const S: usize>(
        &self,
        objects: &[Object],
        rays: &[Ray],
        t_min: f64,
        t_max: f64,
        mut slots: PacketSlots,
        out: &mut [Option<(usize, SurfaceHit)>],
    ) {
        let mut leaves: [Closest; PACKET] = std::array::from_fn(|l| Closest {
            objects,
            ray: &rays[l.min(rays.len() - 1)],
            t_min,
            t_max,
            best: None,
            closer: false,
        });
        let all = u32::MAX >> (32 - rays.len());
        for (l, leaf) in leaves.iter_mut().enumerate().take(rays.len()) {
            for &j in &self.unbounded {
                leaf.test(j as usize, None);
            }
            if leaf.best.is_some() {
                slots.set_t_max(l, up(bound(&leaf.best, t_max)));
            }
        }
        if !self.nodes.is_empty() {
            let sifts: [Option<NarrowRay>; PACKET] = std::array::from_fn(|l| self.sift(&rays[l.min(rays.len() - 1)]));
            // Left unset: a packet's entries are 40 bytes, and clearing the whole stack for
            // each packet cost more than its walk's pushes.
            let mut stack = [const { std::mem::MaybeUninit::<(u32, u32, [f32; PACKET])>::uninit() }; S];
            let mut depth = 0;
            let mut at = 0usize;
            let mut lanes = all;
            'walk: loop {
                let n = &self.nodes[at];
                let order = n.order[slots.octant()];
                // Farthest first, so that the nearest is on top.
                for k in (0..WIDTH).rev() {
                    let s = (order >> (2 * k)) as usize & 3;
                    let (entries, entered) = slots.enter(n, s, self.masks);
                    let entered = entered & lanes;
                    if entered != 0 {
                        stack[depth].write((n.child[s], entered, entries));
                        depth += 1;
                        self.prefetch(n.child[s]);
                    }
                }
                loop {
                    if depth == 0 {
                        break 'walk;
                    }
                    depth -= 1;
                    // SAFETY: entries below `depth` were written by the pushes above.
                    let (child, entered, entries) = unsafe { stack[depth].assume_init() };
                    let live = entered & slots.within(&entries, self.masks);
                    if live == 0 {
                        continue;
                    }
                    let (first, count) = unpack(child);
                    if count == 0 {
                        at = first;
                        lanes = live;
                        break;
                    }
                    for l in each_lane(live) {
                        let leaf = &mut leaves[l];
                        leaf.closer = false;
                        self.leaf_until(first, count, sifts[l].as_ref(), leaf);
                        if leaf.closer {
                            slots.set_t_max(l, up(bound(&leaf.best, t_max)));
                        }
                    }
                }
            }
        }
        for (out, leaf) in out.iter_mut().zip(leaves) {
            *out = leaf.best;
        }
    }

    /// [`Bvh::any_hit`] for each of `rays` (at most [`PACKET`]): bit `l` of the answer is
    /// ray `l`'s. Rays of one octant are walked together, as in [`Bvh::closest_packet`];
    /// a ray leaves the walk at its first hit.
    pub fn any_hit_packet(
        &self,
        objects: &[Object],
        rays: &[Ray],
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
    ) -> u32 {
        assert!(rays.len() <= PACKET, "a packet of at most {PACKET} rays");
        match self.kernel {
            Kernel::Widest => any_hit_packet_widest(self, objects, rays, t_min, t_max, filter),
            Kernel::Baseline => self.any_hit_packet_walk(objects, rays, t_min, t_max, filter),
        }
    }

    /// [`Bvh::any_hit_packet`] on the instructions of the function it is inlined into.
    #[inline(always)]
    fn any_hit_packet_walk(
        &self,
        objects: &[Object],
        rays: &[Ray],
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
    ) -> u32 {
        let Some(slots) = self.packet_slots(rays, t_min, t_max) else {
            // As in `closest_packet_walk`.
            let mut hits = 0;
            for (l, ray) in rays.iter().enumerate() {
                hits |= u32::from(self.any_hit(objects, ray, t_min, t_max, filter)) << l;
            }
            return hits;
        };
        if stack_for(self.depth) <= MEDIUM {
            self.any_hit_packet_with::<MEDIUM>(objects, rays, t_min, t_max, filter, slots)
        } else {
            self.any_hit_packet_with::<FULL>(objects, rays, t_min, t_max, filter, slots)
        }
    }

    /// [`Bvh::any_hit_packet`] with the test `slots` and a stack of `S` entries.
    #[inline(always)]
    fn any_hit_packet_with<const S: usize>(
        &self,
        objects: &[Object],
        rays: &[Ray],
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
        slots: PacketSlots,
    ) -> u32 {
        let mut leaves: [Hits; PACKET] = std::array::from_fn(|l| Hits {
            objects,
            ray: &rays[l.min(rays.len() - 1)],
            t_min,
            t_max,
            filter,
            each: None,
        });
        let all = u32::MAX >> (32 - rays.len());
        let mut hits = 0;
        for (l, leaf) in leaves.iter_mut().enumerate().take(rays.len()) {
            for &j in &self.unbounded {
                if leaf.test(j as usize, None) {
                    hits |= 1 << l;
                    break;
                }
            }
        }
        if hits == all || self.nodes.is_empty() {
            return hits;
        }
        let sifts: [Option<NarrowRay>; PACKET] = std::array::from_fn(|l| self.sift(&rays[l.min(rays.len() - 1)]));
        let mut stack = [(0u32, 0u32); S];
        let mut depth = 0;
        let mut at = 0usize;
        let mut lanes = all & !hits;
        loop {
            let n = &self.nodes[at];
            let order = n.order[slots.octant()];
            for k in (0..WIDTH).rev() {
                let s = (order >> (2 * k)) as usize & 3;
                let entered = slots.enter(n, s, self.masks).1 & lanes;
                if entered != 0 {
                    stack[depth] = (n.child[s], entered);
                    depth += 1;
                    self.prefetch(n.child[s]);
                }
            }
            loop {
                if depth == 0 {
                    return hits;
                }
                depth -= 1;
                let (child, entered) = stack[depth];
                let live = entered & !hits;
                if live == 0 {
                    continue;
                }
                let (first, count) = unpack(child);
                if count == 0 {
                    at = first;
                    lanes = live;
                    break;
                }
                for l in each_lane(live) {
                    if self.leaf_until(first, count, sifts[l].as_ref(), &mut leaves[l]) {
                        hits |= 1 << l;
                    }
                }
                if hits == all {
                    return hits;
                }
            }
        }
    }

    /// Checks the structure against `objects`: every bounded object in exactly one leaf and
    /// every unbounded one in the separate list, each slot's box containing its child's
    /// slots (a leaf's, the stored boxes of its objects), the occupied slots first and each
    /// octant's order a permutation of the slots, each leaf entry's sphere copies those of
    /// its object, and the depth as recorded. For tests.
    pub fn check(&self, objects: &[Object]) -> Result<(), String> {
        let mut seen = vec![0u32; objects.len()];
        for &j in &self.unbounded {
            if objects[j as usize].shape.bounds().is_some() {
                return Err(format!("object {j} is bounded but in the unbounded list"));
            }
            seen[j as usize] += 1;
        }
        let contains = |outer: ([f32; 3], [f32; 3]), inner: ([f32; 3], [f32; 3])| {
            (0..3).all(|a| outer.0[a] <= inner.0[a] && inner.1[a] <= outer.1[a])
        };
        let mut stack = vec![(0usize, 0usize, None)];
        let mut deepest = 0;
        while let Some((at, depth, parent)) = stack.pop() {
            if self.nodes.is_empty() {
                break;
            }
            deepest = deepest.max(depth);
            if depth > MAX_DEPTH {
                return Err(format!("node {at} at depth {depth} is beyond the stack"));
            }
            let n = &self.nodes[at];
            let used = (0..WIDTH).take_while(|&s| n.occupied(s)).count();
            if used == 0 || (used..WIDTH).any(|s| n.occupied(s) || n.child[s] != 0) {
                return Err(format!("node {at}: the occupied slots are not the first ones"));
            }
            for (octant, &order) in n.order.iter().enumerate() {
                let mut slots: Vec<u8> = (0..WIDTH).map(|k| (order >> (2 * k)) & 3).collect();
                slots.sort();
                if slots != [0, 1, 2, 3] {
                    return Err(format!("node {at}: order of octant {octant} is not a permutation"));
                }
            }
            for s in 0..used {
                let b = n.slot_box(s);
                if let Some(p) = parent
                    && !contains(p, b)
                {
                    return Err(format!("node {at}: slot {s} is outside its parent's box"));
                }
                let (first, count) = unpack(n.child[s]);
                if count == 0 {
                    if first >= self.nodes.len() {
                        return Err(format!("node {at}: slot {s} points past the nodes"));
                    }
                    stack.push((first, depth + 1, Some(b)));
                    continue;
                }
                for (l, &j) in self.prims[first..first + count].iter().enumerate() {
                    if let Some(spheres) = &self.spheres
                        && !spheres.holds(first, count, l, &objects[j as usize].shape)
                    {
                        return Err(format!("the copies of leaf entry {} are not object {j}'s", first + l));
                    }
                    let o = stored_box(&objects[j as usize].shape.bounds().ok_or("unbounded in a leaf")?);
                    if !contains(b, o) {
                        return Err(format!("node {at}: slot {s} does not contain object {j}"));
                    }
                    seen[j as usize] += 1;
                }
            }
        }
        if deepest != self.depth {
            return Err(format!("deepest node at {deepest}, recorded {}", self.depth));
        }
        match seen.iter().position(|&s| s != 1) {
            Some(j) => Err(format!("object {j} is in {} leaves", seen[j])),
            None => Ok(()),
        }
    }
}

/// Asks the caches for the line holding `p` (a hint: it faults on no address).
#[inline(always)]
fn prefetch_line(p: *const u8) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing the program sees and faults on no address.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(p.cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// [`Bvh::closest`] on the widest vectors the processor has.
#[multiversion(targets("x86_64+avx512f+avx512vl", "x86_64+avx2"))]
fn closest_widest(bvh: &Bvh, objects: &[Object], ray: &Ray, t_min: f64, t_max: f64) -> Option<(usize, SurfaceHit)> {
    bvh.closest_walk(objects, ray, t_min, t_max)
}

/// [`Bvh::any_hit`] on the widest vectors the processor has.
#[multiversion(targets("x86_64+avx512f+avx512vl", "x86_64+avx2"))]
fn any_hit_widest(
    bvh: &Bvh,
    objects: &[Object],
    ray: &Ray,
    t_min: f64,
    t_max: f64,
    filter: &dyn Fn(usize) -> bool,
) -> bool {
    bvh.any_hit_walk(objects, ray, t_min, t_max, filter)
}

/// [`Bvh::closest_packet`] on the widest vectors the processor has.
#[multiversion(targets("x86_64+avx512f+avx512vl", "x86_64+avx2"))]
fn closest_packet_widest(
    bvh: &Bvh,
    objects: &[Object],
    rays: &[Ray],
    t_min: f64,
    t_max: f64,
    out: &mut [Option<(usize, SurfaceHit)>],
) {
    bvh.closest_packet_walk(objects, rays, t_min, t_max, out)
}

/// [`Bvh::any_hit_packet`] on the widest vectors the processor has.
#[multiversion(targets("x86_64+avx512f+avx512vl", "x86_64+avx2"))]
fn any_hit_packet_widest(
    bvh: &Bvh,
    objects: &[Object],
    rays: &[Ray],
    t_min: f64,
    t_max: f64,
    filter: &dyn Fn(usize) -> bool,
) -> u32 {
    bvh.any_hit_packet_walk(objects, rays, t_min, t_max, filter)
}
