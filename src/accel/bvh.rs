//! The bounding volume hierarchy: closest hit, any hit and every hit over a binary tree of
//! `f32` boxes (built by [`super::build`]), with unbounded objects (planes) tested apart.
//!
//! It returns exactly what the linear scan returns, bit for bit. Two facts make that so:
//! - every shape's hit does not depend on the `t_max` it is given, except that a hit at or
//!   beyond it is dropped (the contract of [`crate::shape::Shape::intersect`]), so shrinking
//!   `t_max` to the best hit so far, in any order, finds the same `t` for each object;
//! - a tie (two objects at the same `t`) goes to the lower object index, as in the scan,
//!   whose strict `<` keeps the first: an object of lower index than the best so far is
//!   asked for hits up to and including the best `t`, one of higher index strictly below.
//!
//! Traversal tests both children of a node. A closest-hit walk descends into the nearer
//! first, the farther waiting on a stack with its entry distance; an entry beyond the best
//! hit is skipped. An any-hit (or every-hit) walk takes them in stored order. The
//! box tests are conservative (see [`super::node`]), so no object that holds the answer is
//! ever skipped.

use super::build::{MAX_SAH_DEPTH, PrimRef, build};
use super::node::{Node, RaySlabs, stored_box};
use crate::math::Ray;
use crate::scene::Object;
use crate::shape::SurfaceHit;
use rayon::prelude::*;

/// Deepest possible tree: SAH splits up to `MAX_SAH_DEPTH`, then halving (`2^23 > MAX_OBJECTS`).
const STACK: usize = MAX_SAH_DEPTH + 24;
/// A traversal stack for trees at most this deep (most of them): a smaller array to
/// initialise on every ray (the full one is 1.4 KB for a closest hit).
const SHALLOW: usize = 24;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    /// Root at 0 (index 1 unused); children of an interior node at `first` and `first + 1`.
    nodes: Vec<Node>,
    /// Object indices in leaf order: a leaf holds `prims[first..first + count]`.
    prims: Vec<u32>,
    /// Objects without bounds (planes), tested before the tree.
    unbounded: Vec<u32>,
    /// Depth of the deepest node (the root at 0).
    depth: usize,
}

impl Bvh {
    pub fn new(objects: &[Object]) -> Self {
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
        let (nodes, depth) = build(&mut refs);
        Bvh {
            depth,
            nodes,
            prims: refs.par_iter().map(|r| r.index).collect(),
            unbounded,
        }
    }

    /// Number of nodes, including the unused slot 1 and alignment padding.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Depth of the deepest node (the root at 0): which traversal stack a ray gets.
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// Memory held by the structure: nodes, leaf order, unbounded list.
    pub fn bytes(&self) -> usize {
        self.nodes.len() * size_of::<Node>() + (self.prims.len() + self.unbounded.len()) * size_of::<u32>()
    }

    /// Closest hit: see the module doc for why it equals the linear scan's.
    pub fn closest(&self, objects: &[Object], ray: &Ray, t_min: f64, t_max: f64) -> Option<(usize, SurfaceHit)> {
        if self.depth < SHALLOW {
            self.closest_with::<SHALLOW>(objects, ray, t_min, t_max)
        } else {
            self.closest_with::<STACK>(objects, ray, t_min, t_max)
        }
    }

    /// [`Bvh::closest`] with a stack of `S` entries (more than the tree's depth).
    fn closest_with<const S: usize>(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
    ) -> Option<(usize, SurfaceHit)> {
        let mut best: Option<(usize, SurfaceHit)> = None;
        let consider = |j: usize, best: &mut Option<(usize, SurfaceHit)>| {
            let limit = match *best {
                None => t_max,
                Some((i, h)) if j < i => h.t.next_up(),
                Some((_, h)) => h.t,
            };
            if let Some(h) = objects[j].shape.intersect(ray, t_min, limit) {
                let wins = best.is_none_or(|(i, b)| h.t < b.t || (h.t == b.t && j < i));
                if wins {
                    *best = Some((j, h));
                }
            }
        };
        for &j in &self.unbounded {
            consider(j as usize, &mut best);
        }
        let bound = |best: &Option<(usize, SurfaceHit)>| best.map_or(t_max, |(_, h)| h.t);
        let Some(root) = self.nodes.first() else {
            return best;
        };
        let slabs = RaySlabs::new(ray);
        if slabs.enter(root, t_min, bound(&best)).is_none() {
            return best;
        }
        let mut stack = [(0u32, 0.0f64); S];
        let mut depth = 0;
        let mut at = 0usize;
        loop {
            let n = &self.nodes[at];
            if n.is_leaf() {
                let first = n.first as usize;
                for &j in &self.prims[first..first + n.count as usize] {
                    consider(j as usize, &mut best);
                }
            } else if let (Some(near), far) = self.children(&slabs, n, t_min, bound(&best)) {
                if let Some((far, t_far)) = far {
                    stack[depth] = (far as u32, t_far);
                    depth += 1;
                }
                at = near;
                continue;
            }
            // Next waiting node that the best hit so far does not rule out (an entry equal
            // to the best `t` may still hold a tie of lower index).
            loop {
                if depth == 0 {
                    return best;
                }
                depth -= 1;
                let (node, entry) = stack[depth];
                if entry <= bound(&best) {
                    at = node as usize;
                    break;
                }
            }
        }
    }

    /// The children of interior node `n` whose boxes the ray enters in `[t_min, t_max]`: the
    /// nearer (or only) one, and the farther one with its entry distance.
    #[inline(always)]
    fn children(&self, slabs: &RaySlabs, n: &Node, t_min: f64, t_max: f64) -> (Option<usize>, Option<(usize, f64)>) {
        let (a, b) = (n.first as usize, n.first as usize + 1);
        match slabs.enter_pair([&self.nodes[a], &self.nodes[b]], t_min, t_max).into() {
            (Some(ta), Some(tb)) if tb < ta => (Some(b), Some((a, ta))),
            (Some(_), Some(tb)) => (Some(a), Some((b, tb))),
            (Some(_), None) => (Some(a), None),
            (None, Some(_)) => (Some(b), None),
            (None, None) => (None, None),
        }
    }

    /// Calls `hit(j)` for objects whose boxes the ray meets in `[t_min, t_max]`, until it
    /// returns true; returns whether it did.
    /// Generic over `hit`, so each caller's test is inlined into the walk (no call through
    /// a pointer per object).
    fn visit(&self, ray: &Ray, t_min: f64, t_max: f64, hit: impl FnMut(usize) -> bool) -> bool {
        if self.depth < SHALLOW {
            self.visit_with::<SHALLOW>(ray, t_min, t_max, hit)
        } else {
            self.visit_with::<STACK>(ray, t_min, t_max, hit)
        }
    }

    /// [`Bvh::visit`] with a stack of `S` entries (more than the tree's depth).
    #[inline(always)]
    fn visit_with<const S: usize>(
        &self,
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        mut hit: impl FnMut(usize) -> bool,
    ) -> bool {
        if self.unbounded.iter().any(|&j| hit(j as usize)) {
            return true;
        }
        let Some(root) = self.nodes.first() else {
            return false;
        };
        let slabs = RaySlabs::new(ray);
        if slabs.enter(root, t_min, t_max).is_none() {
            return false;
        }
        let mut stack = [0u32; S];
        let mut depth = 0;
        let mut at = 0usize;
        loop {
            let n = &self.nodes[at];
            if n.is_leaf() {
                let first = n.first as usize;
                if self.prims[first..first + n.count as usize]
                    .iter()
                    .any(|&j| hit(j as usize))
                {
                    return true;
                }
            } else {
                // The children in stored order (the lower side of the split first), not the
                // nearer first as for a closest hit: any hit ends the walk, and on the
                // intersect bench's any-hit rows this order was 1 to 20 % faster than
                // nearer-first, and faster than ordering by the ray's direction along the
                // axis that separates the children (BENCHMARKS.md, "Eighth session: any-hit
                // in stored order").
                let (a, b) = (n.first as usize, n.first as usize + 1);
                match slabs.enter_pair([&self.nodes[a], &self.nodes[b]], t_min, t_max) {
                    [Some(_), Some(_)] => {
                        stack[depth] = b as u32;
                        depth += 1;
                        at = a;
                        continue;
                    }
                    [Some(_), None] => {
                        at = a;
                        continue;
                    }
                    [None, Some(_)] => {
                        at = b;
                        continue;
                    }
                    [None, None] => {}
                }
            }
            if depth == 0 {
                return false;
            }
            depth -= 1;
            at = stack[depth] as usize;
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
        self.visit(ray, t_min, t_max, |j| {
            filter(j) && objects[j].shape.occludes(ray, t_min, t_max)
        })
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
        self.visit(ray, t_min, t_max, |j| {
            if filter(j) && objects[j].shape.occludes(ray, t_min, t_max) {
                visit(j);
            }
            false
        });
    }

    /// Checks the structure against `objects`: every bounded object in exactly one leaf and
    /// every unbounded one in the separate list, each node's box containing its children's
    /// (and a leaf's the stored boxes of its objects), sibling pairs on even indices, and
    /// depth within the traversal stack and as recorded. For tests.
    pub fn check(&self, objects: &[Object]) -> Result<(), String> {
        let mut seen = vec![0u32; objects.len()];
        for &j in &self.unbounded {
            if objects[j as usize].shape.bounds().is_some() {
                return Err(format!("object {j} is bounded but in the unbounded list"));
            }
            seen[j as usize] += 1;
        }
        let mut stack = vec![(0usize, 0usize)];
        let mut deepest = 0;
        while let Some((at, depth)) = stack.pop() {
            if self.nodes.is_empty() {
                break;
            }
            deepest = deepest.max(depth);
            if depth >= STACK {
                return Err(format!("node {at} at depth {depth} is beyond the stack"));
            }
            let n = &self.nodes[at];
            if n.is_leaf() {
                let first = n.first as usize;
                for &j in &self.prims[first..first + n.count as usize] {
                    let (min, max) = stored_box(&objects[j as usize].shape.bounds().ok_or("unbounded in a leaf")?);
                    if !n.contains(min, max) {
                        return Err(format!("leaf {at} does not contain object {j}"));
                    }
                    seen[j as usize] += 1;
                }
            } else {
                let c = n.first as usize;
                if !c.is_multiple_of(2) || c + 1 >= self.nodes.len() {
                    return Err(format!("node {at}: children at {c}"));
                }
                for k in [c, c + 1] {
                    if !n.contains(self.nodes[k].min, self.nodes[k].max) {
                        return Err(format!("node {at} does not contain its child {k}"));
                    }
                    stack.push((k, depth + 1));
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
