//! BVH construction: binned surface area heuristic (SAH) on object centroids, into the
//! flattened node array of [`super::Bvh`].
//!
//! Each node bins its objects' centroids into up to [`BINS`] slots along the axis where they
//! spread most (along all three axes, the cheapest kept, in trees of at most
//! [`ALL_AXES_UP_TO`] objects, except the large nodes at the top binned by all threads),
//! sweeps the bins for the split with the least SAH cost (a node visit costs
//! [`FINE_TRAVERSE_COST`] object tests in trees of at most [`FINE_LEAVES_UP_TO`] objects,
//! [`TRAVERSE_COST`] in larger ones), and partitions in place.
//! Large ranges at the top are binned by all threads; below a size fixed by the object count
//! alone, subtrees are built as independent tasks, one per thread at a time, and spliced
//! into the array afterwards. Every reduction is exact (min, max and integer counts) and the
//! task size does not depend on the thread count, so the tree is the same for any number of
//! threads.

use super::node::Node;
use glam::Vec3A;
use rayon::prelude::*;

/// Bins per axis.
pub const BINS: usize = 32;
/// Most objects in a leaf whose objects are tested one after another.
const MAX_SCANNED_LEAF: usize = 4;
/// Most objects in a leaf of a sifted tree ([`LeafTest::Sifted`]), and in any leaf.
pub const MAX_LEAF: usize = 31;
/// Below this depth nodes split by the SAH; deeper ones (degenerate inputs only) split at
/// the middle of their range, so no tree is deeper than this plus `log2(MAX_OBJECTS)`.
pub const MAX_SAH_DEPTH: usize = 64;
/// Trees over at most this many objects bin each node along all three axes and keep the
/// cheapest split, but for the nodes above the task size (4096 objects up to 262 144), which
/// all threads bin together along one axis; larger trees bin every node only along the axis
/// where its centroids spread most, which keeps the build of 1 000 000 objects within its
/// budget of 0.3 s.
const ALL_AXES_UP_TO: usize = 200_000;
/// Cost of visiting an interior node relative to one object test, in trees over more than
/// [`FINE_LEAVES_UP_TO`] objects: fuller leaves, 26 to 27 bytes per object for the nodes
/// and the leaf order's indices (BENCHMARKS.md, "Memory and node cost", where a cost of 1
/// takes 62.4 bytes and a build of 276 ms at 1 000 000 spheres, near the 64-byte and 0.3 s
/// budgets). A tree of spheres adds 32 bytes an object: their copies ([`super::leaf`]).
const TRAVERSE_COST: f32 = 3.0;
/// The node cost in trees over at most [`FINE_LEAVES_UP_TO`] objects. With 4-wide nodes,
/// whose four boxes are tested at once, smaller leaves cull more object tests (BENCHMARKS.md,
/// "Memory and node cost").
const FINE_TRAVERSE_COST: f32 = 1.0;
/// The node cost in sifted trees ([`LeafTest::Sifted`]): their leaves' spheres are sifted
/// in vector passes, so an object in a leaf costs a small fraction of a node visit. Leaves
/// of up to [`MAX_LEAF`] at this cost make the tree of 1 000 000 spheres 38.8 MB instead of
/// 58.3 with leaves of at most 4, and the Embree bench's rates 16 to 48 % higher than with
/// leaves of up to 7 at a cost of 5, themselves as fast as leaves of at most 4
/// (BENCHMARKS.md, "Memory and node cost", where leaves of up to 15 and 63 are measured
/// too).
const SIFTED_TRAVERSE_COST: f32 = 20.0;
/// Trees over at most this many objects take [`FINE_TRAVERSE_COST`]. Their many small leaves
/// leave nodes less full: 44 to 56 bytes per object at N = 64 to 4096 on the bench's scenes
/// (spheres and mixed), but 61 to 63 at 10 000 and 65 to 67 at 100 000, at or beyond the
/// 64-byte budget.
pub const FINE_LEAVES_UP_TO: usize = 4096;

/// How the walks test a leaf's objects, which sets what the SAH charges for them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LeafTest {
    /// One object after another.
    Scanned,
    /// All of a leaf's entries a vector at a time, then the few it keeps one by one: the
    /// sift of the sphere copies ([`super::leaf`]), for trees of spheres only over
    /// [`FINE_LEAVES_UP_TO`] objects. A sifted tree's leaves hold up to [`MAX_LEAF`].
    Sifted,
}

/// How a tree is built (see [`ALL_AXES_UP_TO`], [`FINE_LEAVES_UP_TO`], [`LeafTest`]).
#[derive(Clone, Copy, Debug)]
struct Policy {
    /// Whether nodes are binned along all three axes.
    all_axes: bool,
    /// Cost of a node visit relative to one object test, in the SAH.
    traverse_cost: f32,
    /// Most objects in a leaf.
    max_leaf: usize,
}

impl Policy {
    fn for_tree(n: usize, leaf_test: LeafTest) -> Self {
        let (traverse_cost, max_leaf) = match leaf_test {
            _ if n <= FINE_LEAVES_UP_TO => (FINE_TRAVERSE_COST, MAX_SCANNED_LEAF),
            LeafTest::Scanned => (TRAVERSE_COST, MAX_SCANNED_LEAF),
            LeafTest::Sifted => (SIFTED_TRAVERSE_COST, MAX_LEAF),
        };
        Policy {
            all_axes: n <= ALL_AXES_UP_TO,
            traverse_cost,
            max_leaf,
        }
    }
}

/// An object's stored box and index, as the builder sorts them.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct PrimRef {
    pub min: [f32; 3],
    pub index: u32,
    pub max: [f32; 3],
    pad: u32,
}

impl PrimRef {
    pub fn new(index: u32, min: [f32; 3], max: [f32; 3]) -> Self {
        PrimRef {
            min,
            index,
            max,
            pad: 0,
        }
    }

    /// Twice the centroid (the factor 2 is the same for every object, so it is left out).
    #[inline(always)]
    fn centroid2(&self) -> Vec3A {
        Vec3A::from_array(self.min) + Vec3A::from_array(self.max)
    }
}

/// An axis-aligned box in `f32` (object boxes, their unions, or centroid bounds).
#[derive(Clone, Copy, Debug)]
struct Bounds {
    min: Vec3A,
    max: Vec3A,
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        min: Vec3A::splat(f32::INFINITY),
        max: Vec3A::splat(f32::NEG_INFINITY),
    };

    #[inline(always)]
    fn grow(&mut self, min: Vec3A, max: Vec3A) {
        self.min = self.min.min(min);
        self.max = self.max.max(max);
    }

    fn union(self, o: Bounds) -> Bounds {
        Bounds {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// Half the surface area (the SAH needs only ratios); 0 for the empty box.
    fn half_area(&self) -> f32 {
        super::node::half_area((self.max - self.min).max(Vec3A::ZERO).to_array())
    }

    fn of(refs: &[PrimRef]) -> (Bounds, Bounds) {
        let mut boxes = Bounds::EMPTY;
        let mut centroids = Bounds::EMPTY;
        for r in refs {
            boxes.grow(Vec3A::from_array(r.min), Vec3A::from_array(r.max));
            let c = r.centroid2();
            centroids.grow(c, c);
        }
        (boxes, centroids)
    }
}

#[derive(Clone, Copy)]
struct Bin {
    /// The union of the objects' boxes, and the bounds of their (doubled) centroids.
    bounds: Bounds,
    centroids: Bounds,
    count: u32,
}

const EMPTY_BIN: Bin = Bin {
    bounds: Bounds::EMPTY,
    centroids: Bounds::EMPTY,
    count: 0,
};

/// The bins of one node along its split axis; only the first `used` count.
#[derive(Clone)]
struct Bins {
    row: [Bin; BINS],
    used: usize,
}

impl Bins {
    fn new(used: usize) -> Self {
        Bins {
            row: [EMPTY_BIN; BINS],
            used,
        }
    }

    /// Empties the first `used` bins, for reuse by another node.
    fn reset(&mut self, used: usize) {
        self.used = used;
        self.row[..used].fill(EMPTY_BIN);
    }

    fn merge(mut self, o: Bins) -> Bins {
        for (x, y) in self.row[..self.used].iter_mut().zip(o.row.iter()) {
            x.bounds = x.bounds.union(y.bounds);
            x.centroids = x.centroids.union(y.centroids);
            x.count += y.count;
        }
        self
    }
}

/// Bins for a node of `n` objects: 32 for large nodes, fewer near the leaves, where
/// the per-node cost of resetting and sweeping them would dominate the build.
fn bin_count(n: usize) -> usize {
    (n / 2).clamp(4, BINS)
}

/// The axis along which the centroids spread most (the first on ties).
fn widest_axis(centroids: &Bounds) -> usize {
    let extent = (centroids.max - centroids.min).to_array();
    (1..3).fold(0, |a, b| if extent[b] > extent[a] { b } else { a })
}

/// Maps a (doubled) centroid to its bin along one axis: the one where the centroids spread
/// most in large trees (binning one axis instead of three saves a fifth of the build and
/// loses little), each in turn in small ones, whose build takes microseconds anyway.
#[derive(Clone, Copy)]
struct Binner {
    axis: usize,
    origin: f32,
    scale: f32,
    used: usize,
}

impl Binner {
    /// Along the widest axis; `None` when every centroid is the same point.
    fn new(centroids: &Bounds, used: usize) -> Option<Self> {
        Self::on_axis(centroids, used, widest_axis(centroids))
    }

    /// Along `axis`; `None` when the centroids do not spread along it.
    fn on_axis(centroids: &Bounds, used: usize, axis: usize) -> Option<Self> {
        let extent = (centroids.max - centroids.min).to_array();
        // Slightly under used / extent so that the largest centroid lands in the last bin.
        let scale = used as f32 * (1.0 - 1e-6) / extent[axis];
        (extent[axis] > 0.0 && scale.is_finite()).then_some(Binner {
            axis,
            origin: centroids.min[axis],
            scale,
            used,
        })
    }

    #[inline(always)]
    fn bin(&self, r: &PrimRef) -> usize {
        let c = r.min[self.axis] + r.max[self.axis];
        // `as` saturates: a negative (rounding) goes to 0; the top is clamped.
        (((c - self.origin) * self.scale) as usize).min(self.used - 1)
    }

    fn fill(&self, refs: &[PrimRef], bins: &mut Bins) {
        for r in refs {
            let bin = &mut bins.row[self.bin(r)];
            bin.bounds.grow(Vec3A::from_array(r.min), Vec3A::from_array(r.max));
            let c = r.centroid2();
            bin.centroids.grow(c, c);
            bin.count += 1;
        }
    }
}

/// The chosen split: objects whose centroid falls in bins `0..=last_left` go left.
struct Split {
    last_left: usize,
    cost: f32,
    /// Each side's box and centroid bounds.
    left: (Bounds, Bounds),
    right: (Bounds, Bounds),
}

/// The cheapest split by the SAH (`A_L N_L + A_R N_R`), the first bin on ties.
fn best_split(bins: &Bins) -> Option<Split> {
    let (row, used) = (&bins.row[..bins.used], bins.used);
    // `A_L N_L` and `N_L` for the split after bin i, from the left: a few bytes per bin
    // (every node sweeps its bins; most nodes are small).
    let mut left_cost = [0f32; BINS];
    let mut left_n = [0u32; BINS];
    let (mut acc, mut n) = (Bounds::EMPTY, 0);
    for i in 0..used - 1 {
        acc = acc.union(row[i].bounds);
        n += row[i].count;
        left_cost[i] = acc.half_area() * n as f32;
        left_n[i] = n;
    }
    // From the right, keeping the cheapest (the last seen, so the first bin, on ties).
    let mut best: Option<(usize, f32)> = None;
    let (mut acc, mut n) = (Bounds::EMPTY, 0);
    for i in (0..used - 1).rev() {
        acc = acc.union(row[i + 1].bounds);
        n += row[i + 1].count;
        if left_n[i] == 0 || n == 0 {
            continue;
        }
        let cost = left_cost[i] + acc.half_area() * n as f32;
        if best.is_none_or(|(_, b)| cost <= b) {
            best = Some((i, cost));
        }
    }
    let (last_left, cost) = best?;
    let side = |bins: &[Bin]| {
        bins.iter().fold((Bounds::EMPTY, Bounds::EMPTY), |(b, c), bin| {
            (b.union(bin.bounds), c.union(bin.centroids))
        })
    };
    Some(Split {
        last_left,
        cost,
        left: side(&row[..=last_left]),
        right: side(&row[last_left + 1..]),
    })
}

/// Moves the objects going left to the front; returns their count. Without a branch per
/// object (which side an object goes is random in object order): each object is swapped
/// with the first one of the right side so far, and that side's start moves on when the
/// object goes left.
fn partition(refs: &mut [PrimRef], binner: &Binner, split: &Split) -> usize {
    let mut first_right = 0;
    for k in 0..refs.len() {
        let left = binner.bin(&refs[k]) <= split.last_left;
        // `first_right <= k`: everything in `first_right..k` goes right.
        refs.swap(first_right, k);
        first_right += usize::from(left);
    }
    first_right
}

/// What to do with a node's range.
enum Decision {
    Leaf,
    /// Split at `count` objects, with the children's boxes and centroid bounds.
    Split {
        count: usize,
        left: (Bounds, Bounds),
        right: (Bounds, Bounds),
    },
}

/// Decides a node: leaf, SAH split, or (no usable split, or too deep) a split in the
/// middle of the range. `parallel` bins with every thread (large ranges at the top);
/// `policy` says along which axes to bin and what a node visit costs; `scratch` holds the
/// bins.
fn decide(
    refs: &mut [PrimRef],
    boxes: &Bounds,
    centroids: &Bounds,
    depth: usize,
    parallel: bool,
    policy: Policy,
    scratch: &mut Bins,
) -> Decision {
    let n = refs.len();
    if n == 1 {
        return Decision::Leaf;
    }
    let split = if depth >= MAX_SAH_DEPTH {
        None
    } else if parallel {
        Binner::new(centroids, bin_count(n)).and_then(|binner| {
            *scratch = refs
                .par_chunks(16 * 1024)
                .map(|c| {
                    let mut bins = Bins::new(binner.used);
                    binner.fill(c, &mut bins);
                    bins
                })
                .reduce(|| Bins::new(binner.used), Bins::merge);
            best_split(scratch).map(|s| (s, binner))
        })
    } else {
        // The cheapest split along the axes tried (the first axis on ties).
        let widest = widest_axis(centroids);
        let axes = if policy.all_axes { 0..3 } else { widest..widest + 1 };
        let mut best: Option<(Split, Binner)> = None;
        for axis in axes {
            let Some(binner) = Binner::on_axis(centroids, bin_count(n), axis) else {
                continue;
            };
            scratch.reset(binner.used);
            binner.fill(refs, scratch);
            if let Some(split) = best_split(scratch)
                && best.as_ref().is_none_or(|(b, _)| split.cost < b.cost)
            {
                best = Some((split, binner));
            }
        }
        best
    };
    let leaf_cost = n as f32;
    match split {
        Some((s, binner)) => {
            let split_cost = policy.traverse_cost + s.cost / boxes.half_area().max(f32::MIN_POSITIVE);
            if n <= policy.max_leaf && leaf_cost <= split_cost {
                return Decision::Leaf;
            }
            let count = partition(refs, &binner, &s);
            Decision::Split {
                count,
                left: s.left,
                right: s.right,
            }
        }
        None if n <= policy.max_leaf => Decision::Leaf,
        None => {
            // Identical centroids (or the depth guard): halve by position.
            let count = n / 2;
            Decision::Split {
                count,
                left: Bounds::of(&refs[..count]),
                right: Bounds::of(&refs[count..]),
            }
        }
    }
}

fn node(boxes: &Bounds, first: usize, count: usize) -> Node {
    Node {
        min: boxes.min.to_array(),
        max: boxes.max.to_array(),
        first: first as u32,
        count: count as u32,
    }
}

/// A subtree left for a task: the top-level node slot it fills and its range.
struct Task {
    slot: usize,
    start: usize,
    len: usize,
    boxes: Bounds,
    centroids: Bounds,
    depth: usize,
}

/// A built binary tree.
pub struct Built {
    /// The nodes: root at 0, index 1 unused so that sibling pairs start at even indices.
    pub nodes: Vec<Node>,
    /// The objects' indices in leaf order: a leaf's `first .. first + count`.
    pub order: Vec<u32>,
}

/// Builds the tree over `refs`, whose leaves the walks test as `leaf_test` says. The boxes
/// are freed once the subtrees are built, before they are spliced into one array, so a
/// large tree's boxes, subtrees and final array are never all held at once.
pub fn build(mut refs: Vec<PrimRef>, leaf_test: LeafTest) -> Built {
    if refs.is_empty() {
        return Built {
            nodes: Vec::new(),
            order: Vec::new(),
        };
    }
    let (boxes, centroids) = refs.par_chunks(16 * 1024).map(Bounds::of).reduce(
        || (Bounds::EMPTY, Bounds::EMPTY),
        |a, b| (a.0.union(b.0), a.1.union(b.1)),
    );
    // Ranges up to this size are one task; it depends on the object count only.
    let policy = Policy::for_tree(refs.len(), leaf_test);
    let mut top = Builder::new(vec![Node::default(); 2], (refs.len() / 64).max(4096), policy);
    top.grow(&mut refs, 0, boxes, centroids, 0, 0);
    let (mut nodes, tasks) = (top.nodes, top.tasks);
    // Build the tasks' subtrees in parallel, each in its own array with its root at 0.
    let mut slices = Vec::with_capacity(tasks.len());
    let mut rest = &mut refs[..];
    for t in &tasks {
        let (head, tail) = rest.split_at_mut(t.len);
        slices.push(head);
        rest = tail;
    }
    let subtrees: Vec<Vec<Node>> = slices
        .into_par_iter()
        .zip(tasks.par_iter())
        .map(|(s, t)| {
            // About one node per object (leaves average two objects): no regrowth.
            let mut nodes = Vec::with_capacity(t.len + 1);
            nodes.push(Node::default());
            let mut b = Builder::new(nodes, 0, policy);
            b.grow(s, t.start, t.boxes, t.centroids, t.depth, 0);
            // Leaves hold two objects on average: a third of the reserve is spare.
            b.nodes.shrink_to_fit();
            b.nodes
        })
        .collect();
    let order = refs.par_iter().map(|r| r.index).collect();
    drop(refs);
    // Splice ([`global_index`]): the top part holds its root, the unused slot and pairs,
    // and each task adds pairs, so every offset is even.
    let mut offsets = Vec::with_capacity(tasks.len());
    let mut end = nodes.len();
    for local in &subtrees {
        offsets.push(end);
        end += local.len() - 1;
    }
    debug_assert!(offsets.iter().all(|o| o % 2 == 0));
    for ((t, local), &offset) in tasks.iter().zip(&subtrees).zip(&offsets) {
        nodes[t.slot] = relocated(local[0], t.slot, offset);
    }
    // The rest in parallel, written in place: the pages of a large tree's array are first
    // touched here, by all threads.
    let start = nodes.len();
    nodes.par_extend((start..end).into_par_iter().map(|k| {
        // The last task starting at or before `k`.
        let task = offsets.partition_point(|&o| o <= k) - 1;
        let slot = tasks[task].slot;
        relocated(subtrees[task][k - offsets[task] + 1], slot, offsets[task])
    }));
    Built { nodes, order }
}

/// Where node `i` of a subtree built on its own (its root at 0) goes in the tree it joins:
/// its root to `slot`, node `i >= 1` to `offset + i - 1` (`offset` even, so that its
/// sibling pairs (1, 2), (3, 4), ... stay on even starts).
fn global_index(i: usize, slot: usize, offset: usize) -> usize {
    if i == 0 { slot } else { offset + i - 1 }
}

/// A node of such a subtree with its children's index moved by [`global_index`].
fn relocated(mut n: Node, slot: usize, offset: usize) -> Node {
    if !n.is_leaf() {
        n.first = global_index(n.first as usize, slot, offset) as u32;
    }
    n
}

/// Builds subtrees into `nodes`. Ranges larger than `task_size` are binned by all threads;
/// a range of at most `task_size` objects is left in `tasks` (0: no tasks, one thread).
struct Builder {
    nodes: Vec<Node>,
    tasks: Vec<Task>,
    task_size: usize,
    policy: Policy,
    scratch: Bins,
}

impl Builder {
    fn new(nodes: Vec<Node>, task_size: usize, policy: Policy) -> Self {
        Builder {
            nodes,
            tasks: Vec::new(),
            task_size,
            policy,
            scratch: Bins::new(BINS),
        }
    }

    /// The subtree of `refs` (objects `start..` in leaf order), its root at `slot`.
    fn grow(
        &mut self,
        refs: &mut [PrimRef],
        start: usize,
        boxes: Bounds,
        centroids: Bounds,
        depth: usize,
        slot: usize,
    ) {
        if refs.len() <= self.task_size {
            self.tasks.push(Task {
                slot,
                start,
                len: refs.len(),
                boxes,
                centroids,
                depth,
            });
            return;
        }
        let parallel = self.task_size > 0;
        match decide(
            refs,
            &boxes,
            &centroids,
            depth,
            parallel,
            self.policy,
            &mut self.scratch,
        ) {
            Decision::Leaf => self.nodes[slot] = node(&boxes, start, refs.len()),
            Decision::Split { count, left, right } => {
                let first = self.nodes.len();
                self.nodes.extend([Node::default(); 2]);
                self.nodes[slot] = node(&boxes, first, 0);
                let (l, r) = refs.split_at_mut(count);
                if parallel {
                    // Above the task size, both children at once, each into a builder of
                    // its own (its root at 0), appended as this one would have built them:
                    // the left subtree, then the right, so the tree and the tasks' order do
                    // not depend on the threads.
                    let (task_size, policy) = (self.task_size, self.policy);
                    let child = |refs: &mut [PrimRef], start: usize, (boxes, centroids): (Bounds, Bounds)| {
                        let mut b = Builder::new(vec![Node::default()], task_size, policy);
                        b.grow(refs, start, boxes, centroids, depth + 1, 0);
                        b
                    };
                    let (lb, rb) = rayon::join(|| child(l, start, left), || child(r, start + count, right));
                    self.append(lb, first);
                    self.append(rb, first + 1);
                } else {
                    self.grow(l, start, left.0, left.1, depth + 1, first);
                    self.grow(r, start + count, right.0, right.1, depth + 1, first + 1);
                }
            }
        }
    }

    /// Appends the subtree `sub` built on its own, its root filling `slot` and the rest at
    /// the current length ([`global_index`]).
    fn append(&mut self, sub: Builder, slot: usize) {
        let offset = self.nodes.len();
        self.nodes[slot] = relocated(sub.nodes[0], slot, offset);
        self.nodes
            .extend(sub.nodes[1..].iter().map(|&n| relocated(n, slot, offset)));
        self.tasks.extend(sub.tasks.into_iter().map(|t| Task {
            slot: global_index(t.slot, slot, offset),
            ..t
        }));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two rows of small boxes, 7 long along x and 3 apart along y: the centroids spread
    /// most along x, but the cheaper split is between the rows. A small tree tries every
    /// axis and takes it.
    #[test]
    fn small_nodes_split_along_the_cheapest_axis() {
        let refs: Vec<PrimRef> = (0..16)
            .map(|i| {
                let (x, y) = ((i % 8) as f32, if i < 8 { 0.0 } else { 3.0 });
                PrimRef::new(i, [x - 0.1, y - 0.1, -0.1], [x + 0.1, y + 0.1, 0.1])
            })
            .collect();
        let nodes = build(refs, LeafTest::Scanned).nodes;
        let first = nodes[0].first as usize;
        let (a, b) = (&nodes[first], &nodes[first + 1]);
        let (low, high) = if a.min[1] < b.min[1] { (a, b) } else { (b, a) };
        assert_eq!((low.min[1], low.max[1]), (-0.1, 0.1));
        assert_eq!((high.min[1], high.max[1]), (2.9, 3.1));
        assert_eq!(
            (low.min[0], low.max[0], high.min[0], high.max[0]),
            (-0.1, 7.1, -0.1, 7.1)
        );
    }

    /// `n` boxes of side 0.2 centred uniformly at random in a cube of side 20: the largest
    /// leaf and the mean.
    fn leaf_sizes(n: u32, leaf_test: LeafTest) -> (u32, f64) {
        let mut s = crate::sampling::Stream::new(3, crate::sampling::Purpose::Generator, 0);
        let refs: Vec<PrimRef> = (0..n)
            .map(|i| {
                let c = [(); 3].map(|_| 20.0 * s.next_f64() as f32);
                PrimRef::new(i, c.map(|x| x - 0.1), c.map(|x| x + 0.1))
            })
            .collect();
        let nodes = build(refs, leaf_test).nodes;
        let counts: Vec<u32> = nodes.iter().skip(2).filter(|n| n.is_leaf()).map(|n| n.count).collect();
        assert_eq!(counts.iter().sum::<u32>(), n, "every object in one leaf");
        let largest = *counts.iter().max().unwrap();
        (largest, n as f64 / counts.len() as f64)
    }

    /// A sifted tree over more than `FINE_LEAVES_UP_TO` objects takes leaves of up to
    /// `MAX_LEAF`; a scanned one, and any tree of at most `FINE_LEAVES_UP_TO`, up to four.
    #[test]
    fn sifted_trees_take_fuller_leaves() {
        let (largest, mean) = leaf_sizes(8192, LeafTest::Sifted);
        assert!(
            largest == MAX_LEAF as u32 && mean > 4.0,
            "sifted: largest {largest}, mean {mean}"
        );
        for (n, leaf_test) in [(8192, LeafTest::Scanned), (4096, LeafTest::Sifted)] {
            let (largest, mean) = leaf_sizes(n, leaf_test);
            assert!(
                largest <= 4 && mean <= 4.0,
                "{n} {leaf_test:?}: largest {largest}, mean {mean}"
            );
        }
    }
}
