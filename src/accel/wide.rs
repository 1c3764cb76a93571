//! The tree the traversal walks: 4-wide nodes collapsed from the binary SAH tree of
//! [`super::build`], and the test of a ray against a node's four child boxes at once.
//!
//! A binary node tests two boxes per visit; a 4-wide one tests four in one pass of `f32`
//! vector code and visits about half as many levels (the `obvhs` peer is 8-wide). Each
//! node keeps, for each of the eight octants of a ray's direction, its children in
//! front-to-back order (by their centers' projection on the octant's diagonal), so the
//! walk takes them nearest-first without sorting them per ray.
//!
//! The `f32` test is conservative (see [`super::node`]): the ray's origin is rounded
//! outward (the entry plane measured from the bound that makes the entry earlier, the exit
//! plane from the one that makes the exit later), `t_min` is rounded down and `t_max` up,
//! and each slab's entry is computed with the reciprocal direction shrunk by a relative
//! `2^-20`, its exit with it grown by `2^-20`. Five roundings of at most `2^-24` each (the
//! direction to `f32`, the reciprocal, its scaling, the subtraction, the product) cannot
//! undo that: a non-negative entry is computed no later than the exact one, a non-negative
//! exit no earlier. An underflowed product is off by less than `2^-149`, which an absolute
//! `2^-126` on either side covers. The scaling, not a widening of the computed interval,
//! keeps the box test's chain of dependent operations short (the walk waits on it at
//! every node).
//!
//! That holds from `t_min >= 0` on. A negative entry comes out later (nearer 0), but the
//! interval starts at `t_min`, which is no later than the exact entry. A negative exit
//! comes out earlier, but its sign is right (the exit plane is measured from the origin's
//! bound behind the ray, and rounding keeps the sign of a difference and of a product): the
//! box lies behind the origin on that axis and the ray, from `t_min >= 0`, misses it.
//! Rays with `t_min < 0`, and rays for which `f32` cannot hold the test (an origin or a
//! reciprocal direction beyond `2^50`, a reciprocal below `2^-50`, or a tree beyond
//! `2^50`), are tested in `f64` instead.

use super::build::MAX_LEAF;
use super::node::{Node, down, up};
use glam::{BVec4A, Vec4};

// A leaf's count must fit the five bits of a child reference.
const _: () = assert!(MAX_LEAF < 32);

/// Children per node.
pub const WIDTH: usize = 4;

/// A child reference ([`Node4::child`]): bits 27 to 31 hold the object count of a leaf (0
/// for an interior node), bits 0 to 26 the leaf's first entry in the leaf order or the
/// interior node's index.
const COUNT_SHIFT: u32 = 27;
const INDEX_MASK: u32 = (1 << COUNT_SHIFT) - 1;

/// One 4-wide node: its children's boxes side by side per axis and side, so that one vector
/// holds the same bound of all four.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct Node4 {
    /// `bounds[side * 3 + axis][slot]`: side 0 the minimum, 1 the maximum. An empty slot has
    /// the minimum `+inf` and the maximum `-inf`, which no ray enters.
    pub bounds: [[f32; WIDTH]; 6],
    /// Per slot: the child reference (see [`COUNT_SHIFT`]); 0 for an empty slot.
    pub child: [u32; WIDTH],
    /// Per octant of the ray's direction (bit `a` set when its component on axis `a` is
    /// negative): the slots front to back, two bits each, the first in the lowest bits.
    pub order: [u8; 8],
}

/// A leaf: `count` objects from `first` in the leaf order.
pub fn leaf_ref(first: u32, count: u32) -> u32 {
    debug_assert!(first <= INDEX_MASK && (1..32).contains(&count));
    (count << COUNT_SHIFT) | first
}

/// `(first, count)` of a child reference; a count of 0 is an interior node at `first`.
#[inline(always)]
pub fn unpack(child: u32) -> (usize, usize) {
    ((child & INDEX_MASK) as usize, (child >> COUNT_SHIFT) as usize)
}

impl Node4 {
    const EMPTY: Node4 = Node4 {
        bounds: [
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ],
        child: [0; WIDTH],
        order: [0b11_10_01_00; 8],
    };

    /// The box of `slot` as (minimum, maximum).
    pub fn slot_box(&self, slot: usize) -> ([f32; 3], [f32; 3]) {
        (
            [0, 1, 2].map(|a| self.bounds[a][slot]),
            [0, 1, 2].map(|a| self.bounds[3 + a][slot]),
        )
    }

    /// Whether `slot` holds a child (its box is not the empty one).
    pub fn occupied(&self, slot: usize) -> bool {
        self.bounds[0][slot] <= self.bounds[3][slot]
    }
}

/// The 4-wide tree of a binary one (`binary[0]` its root, children of an interior node at
/// `first` and `first + 1`): each node takes its binary node's children, then replaces the
/// interior child of largest surface area by its two children while it has fewer than four.
/// Returns the nodes (root at 0, in depth-first order) and the depth of the deepest one.
pub fn collapse(binary: &[Node]) -> (Vec<Node4>, usize) {
    if binary.is_empty() {
        return (Vec::new(), 0);
    }
    let mut nodes = Vec::with_capacity(binary.len() / 3 + 1);
    let mut deepest = 0;
    // (binary node whose slots make the wide node, wide index to fill, depth)
    let mut pending = vec![(0usize, 0usize, 0usize)];
    nodes.push(Node4::EMPTY);
    while let Some((from, to, depth)) = pending.pop() {
        deepest = deepest.max(depth);
        let (slots, used) = gather(binary, from);
        let mut node = Node4::EMPTY;
        for (s, &b) in slots[..used].iter().enumerate() {
            let n = &binary[b];
            for a in 0..3 {
                node.bounds[a][s] = n.min[a];
                node.bounds[3 + a][s] = n.max[a];
            }
            node.child[s] = if n.is_leaf() {
                leaf_ref(n.first, n.count)
            } else {
                let index = nodes.len();
                assert!(
                    index <= INDEX_MASK as usize,
                    "more wide nodes than a child reference holds"
                );
                nodes.push(Node4::EMPTY);
                pending.push((b, index, depth + 1));
                index as u32
            };
        }
        node.order = octant_orders(&node, used);
        nodes[to] = node;
    }
    (nodes, deepest)
}

/// The binary nodes that become the slots of the wide node made from `from` (the first
/// `len` of the array): its children (itself when it is a leaf, the root of a tree of one
/// leaf), opened largest first.
fn gather(binary: &[Node], from: usize) -> ([usize; WIDTH], usize) {
    let root = &binary[from];
    if root.is_leaf() {
        return ([from, 0, 0, 0], 1);
    }
    let mut slots = [root.first as usize, root.first as usize + 1, 0, 0];
    let mut len = 2;
    while len < WIDTH {
        let mut largest = None;
        let mut largest_area = f32::NEG_INFINITY;
        for (k, &b) in slots[..len].iter().enumerate() {
            let area = binary[b].half_area();
            // The first of equal areas, as a stable sort would pick.
            if !binary[b].is_leaf() && area > largest_area {
                (largest, largest_area) = (Some(k), area);
            }
        }
        let Some(k) = largest else { break };
        let first = binary[slots[k]].first as usize;
        slots.copy_within(k + 1..len, k + 2);
        slots[k] = first;
        slots[k + 1] = first + 1;
        len += 1;
    }
    (slots, len)
}

/// For each octant, the occupied slots (the first `used`) sorted by their centers'
/// projection on the octant's diagonal (ties by slot), then the empty ones.
fn octant_orders(node: &Node4, used: usize) -> [u8; 8] {
    let centers: [[f32; 3]; WIDTH] = std::array::from_fn(|s| {
        let (min, max) = node.slot_box(s);
        [0, 1, 2].map(|a| 0.5 * (min[a] + max[a]))
    });
    std::array::from_fn(|octant| {
        let key = |s: usize| -> f32 {
            (0..3)
                .map(|a| {
                    if octant >> a & 1 == 1 {
                        -centers[s][a]
                    } else {
                        centers[s][a]
                    }
                })
                .sum()
        };
        let keys: [f32; WIDTH] = std::array::from_fn(key);
        let mut slots = [0usize, 1, 2, 3];
        // Insertion sort of at most four: stable, so ties keep the slot order.
        for i in 1..used {
            let mut k = i;
            while k > 0 && keys[slots[k]] < keys[slots[k - 1]] {
                slots.swap(k, k - 1);
                k -= 1;
            }
        }
        slots
            .iter()
            .enumerate()
            .fold(0u8, |acc, (k, &s)| acc | (s as u8) << (2 * k))
    })
}

/// A ray prepared for testing nodes, with its current `[t_min, t_max]`.
pub trait SlotTest {
    /// The slots of `n` the ray enters within its interval (bit `s` of the mask), and for
    /// each a distance not beyond its entry.
    fn enter(&self, n: &Node4) -> ([f32; WIDTH], u32);
    /// Narrows the interval's end (a closer hit was found).
    fn set_t_max(&mut self, t_max: f64);
    /// The octant of the ray's direction ([`Node4::order`]).
    fn octant(&self) -> usize;
}

/// Largest magnitude of a coordinate, reciprocal direction or tree bound for the `f32` test
/// (and the inverse of the smallest reciprocal): products stay far from `f32` overflow.
pub const F32_RANGE: f32 = (1u64 << 50) as f32;

/// Relative scaling of the reciprocal direction in the `f32` test (see the module doc).
const WIDEN32: f32 = 1.0 / (1u32 << 20) as f32;

/// The rows of `Node4::bounds` by which a ray enters and leaves the slab of `axis`: the
/// minimum first, unless its direction component is `negative` (`-0` included, whose
/// reciprocal `-inf` pairs with the maximum).
#[inline(always)]
fn slab_rows(axis: usize, negative: bool) -> (usize, usize) {
    if negative { (3 + axis, axis) } else { (axis, 3 + axis) }
}

/// Which octant the direction `d` points into ([`Node4::order`]); `-0` counts as negative,
/// as in the slab tests.
#[inline(always)]
fn octant_of(d: [f64; 3]) -> usize {
    d[0].is_sign_negative() as usize | (d[1].is_sign_negative() as usize) << 1 | (d[2].is_sign_negative() as usize) << 2
}

/// The `f32` test. The per-ray values a node's test combines with its bounds are kept
/// splat across the four lanes.
pub struct F32Slots {
    /// Per axis, the row of `Node4::bounds` by which the ray enters the slab and the one by
    /// which it leaves.
    entry_row: [usize; 3],
    exit_row: [usize; 3],
    /// Per axis, the origin's `f32` bound that makes the entry earlier, and the exit later.
    entry_origin: [Vec4; 3],
    exit_origin: [Vec4; 3],
    /// Per axis, the reciprocal direction shrunk by `WIDEN32` (for entries) and grown by it
    /// (for exits).
    entry_inv: [Vec4; 3],
    exit_inv: [Vec4; 3],
    /// `t_min` rounded down and `t_max` rounded up.
    t_min: Vec4,
    t_max: Vec4,
    octant: usize,
}

/// One ray's terms of the `f32` test, per axis in `x, y, z` order: what [`F32Slots`] splats
/// across a node's slots and [`super::packet::PacketSlots`] lays across a packet's rays.
#[derive(Clone, Copy, Debug)]
pub struct RayTerms {
    /// The origin's `f32` bound that makes the entry earlier, and the exit later.
    pub entry_origin: [f32; 3],
    pub exit_origin: [f32; 3],
    /// The reciprocal direction shrunk by `WIDEN32` (for entries) and grown by it (for
    /// exits).
    pub entry_inv: [f32; 3],
    pub exit_inv: [f32; 3],
    /// `t_min` rounded down and `t_max` rounded up.
    pub t_min: f32,
    pub t_max: f32,
    pub octant: usize,
}

impl RayTerms {
    /// The terms for `origin + t dir`, `t` in `[t_min, t_max]`, or `None` when `f32` cannot
    /// carry the test or `t_min` is negative (see the module doc).
    #[inline(always)]
    pub fn new(origin: [f64; 3], dir: [f64; 3], t_min: f64, t_max: f64) -> Option<Self> {
        // The three axes in the first three lanes (the fourth is a harmless 0 and 1).
        let o = Vec4::new(origin[0] as f32, origin[1] as f32, origin[2] as f32, 0.0);
        let d = Vec4::new(dir[0] as f32, dir[1] as f32, dir[2] as f32, 1.0);
        let range = Vec4::splat(F32_RANGE);
        // A tiny component may have become 0: the test is on the exact one.
        let zero = BVec4A::new(dir[0] == 0.0, dir[1] == 0.0, dir[2] == 0.0, false);
        let fits = o.abs().cmple(range) & d.abs().cmple(range) & (d.abs().cmpge(range.recip()) | zero);
        // `-0` passes as a `t_min`.
        if !fits.all() || t_min < 0.0 || t_min.is_nan() || t_max.is_nan() {
            return None;
        }
        // Below and above the origin: `o` rounded to nearest is within half a step of it,
        // `o -+ |o| 2^-23` one to two steps away (and the smallest normal number covers an
        // origin that rounded to zero or to a subnormal).
        let step = o.abs() * (1.0 / (1u32 << 23) as f32) + Vec4::splat(f32::MIN_POSITIVE);
        let (lo, hi) = ((o - step).to_array(), (o + step).to_array());
        // `1 / d` rounds twice (`d` to `f32`, the quotient), the scaling a third time;
        // `d = -0` keeps its sign and an infinite reciprocal stays infinite.
        let inv = d.recip();
        let (shrunk, grown) = ((inv * (1.0 - WIDEN32)).to_array(), (inv * (1.0 + WIDEN32)).to_array());
        let octant = octant_of(dir);
        let mut t = RayTerms {
            entry_origin: [0.0; 3],
            exit_origin: [0.0; 3],
            entry_inv: [0.0; 3],
            exit_inv: [0.0; 3],
            t_min: down(t_min),
            t_max: up(t_max),
            octant,
        };
        // Plain loops: `array::map` with closures is not inlined here, and the copies of
        // its results stall the walk.
        for a in 0..3 {
            let negative = octant >> a & 1 == 1;
            t.entry_origin[a] = if negative { lo[a] } else { hi[a] };
            t.exit_origin[a] = if negative { hi[a] } else { lo[a] };
            t.entry_inv[a] = shrunk[a];
            t.exit_inv[a] = grown[a];
        }
        Some(t)
    }

    /// The rows of [`Node4::bounds`] by which the ray enters and leaves each axis' slab.
    #[inline(always)]
    pub fn rows(&self) -> ([usize; 3], [usize; 3]) {
        let mut rows = ([0; 3], [0; 3]);
        for a in 0..3 {
            (rows.0[a], rows.1[a]) = slab_rows(a, self.octant >> a & 1 == 1);
        }
        rows
    }
}

/// The absolute `2^-126` on either side (see the module doc): the entry is early by it, the
/// exit late, so whether a slot is entered compares `near` with `far` plus it twice.
pub const TINY: f32 = f32::MIN_POSITIVE;

impl F32Slots {
    /// The test for `origin + t dir`, `t` in `[t_min, t_max]`, or `None` when `f32` cannot
    /// carry it or `t_min` is negative (see the module doc).
    #[inline(always)]
    pub fn new(origin: [f64; 3], dir: [f64; 3], t_min: f64, t_max: f64) -> Option<Self> {
        let t = RayTerms::new(origin, dir, t_min, t_max)?;
        let (entry_row, exit_row) = t.rows();
        let mut slots = F32Slots {
            entry_row,
            exit_row,
            entry_origin: [Vec4::ZERO; 3],
            exit_origin: [Vec4::ZERO; 3],
            entry_inv: [Vec4::ZERO; 3],
            exit_inv: [Vec4::ZERO; 3],
            t_min: Vec4::splat(t.t_min),
            t_max: Vec4::splat(t.t_max),
            octant: t.octant,
        };
        for a in 0..3 {
            slots.entry_origin[a] = Vec4::splat(t.entry_origin[a]);
            slots.exit_origin[a] = Vec4::splat(t.exit_origin[a]);
            slots.entry_inv[a] = Vec4::splat(t.entry_inv[a]);
            slots.exit_inv[a] = Vec4::splat(t.exit_inv[a]);
        }
        Some(slots)
    }
}

impl SlotTest for F32Slots {
    #[inline(always)]
    fn enter(&self, n: &Node4) -> ([f32; WIDTH], u32) {
        let (mut near, mut far) = (self.t_min, self.t_max);
        for a in 0..3 {
            let entry = Vec4::from_array(n.bounds[self.entry_row[a]]);
            let exit = Vec4::from_array(n.bounds[self.exit_row[a]]);
            let t0 = (entry - self.entry_origin[a]) * self.entry_inv[a];
            let t1 = (exit - self.exit_origin[a]) * self.exit_inv[a];
            // `0 * inf = NaN` only for a slab the ray runs along whose plane lies exactly
            // at one of the origin's bounds, which are strictly outside the origin: the
            // ray is outside that slab, so a miss or a hit there are both sound. (`maxps`
            // and `minps` return their second operand, the interval so far.)
            near = t0.max(near);
            far = t1.min(far);
        }
        let tiny = Vec4::splat(TINY);
        let entered = near.cmple(far + 2.0 * tiny).bitmask();
        ((near - tiny).to_array(), entered)
    }

    #[inline(always)]
    fn set_t_max(&mut self, t_max: f64) {
        self.t_max = Vec4::splat(up(t_max));
    }

    #[inline(always)]
    fn octant(&self) -> usize {
        self.octant
    }
}

/// `2 gamma(3)` in `f64`: the relative widening of the `f64` test (as in [`super::node`]).
const WIDEN64: f64 = 2.0 * (3.0 * f64::EPSILON * 0.5) / (1.0 - 3.0 * f64::EPSILON * 0.5);

/// The `f64` test, for the rays [`F32Slots`] cannot carry.
pub struct F64Slots {
    origin: [f64; 3],
    inv: [f64; 3],
    entry_row: [usize; 3],
    exit_row: [usize; 3],
    t_min: f64,
    t_max: f64,
    octant: usize,
}

impl F64Slots {
    pub fn new(origin: [f64; 3], dir: [f64; 3], t_min: f64, t_max: f64) -> Self {
        let rows: [(usize, usize); 3] = std::array::from_fn(|a| slab_rows(a, dir[a].is_sign_negative()));
        F64Slots {
            origin,
            inv: dir.map(|x| 1.0 / x),
            entry_row: rows.map(|r| r.0),
            exit_row: rows.map(|r| r.1),
            t_min,
            t_max,
            octant: octant_of(dir),
        }
    }
}

impl SlotTest for F64Slots {
    fn enter(&self, n: &Node4) -> ([f32; WIDTH], u32) {
        let mut entries = [0.0; WIDTH];
        let mut mask = 0;
        for (s, entry) in entries.iter_mut().enumerate() {
            let (mut near, mut far) = (self.t_min, self.t_max);
            for a in 0..3 {
                let t0 = (n.bounds[self.entry_row[a]][s] as f64 - self.origin[a]) * self.inv[a];
                let t1 = (n.bounds[self.exit_row[a]][s] as f64 - self.origin[a]) * self.inv[a];
                near = if t0 > near { t0 } else { near };
                far = if t1 < far { t1 } else { far };
            }
            let near = near - near.abs() * WIDEN64;
            let far = far + far.abs() * WIDEN64;
            *entry = down(near);
            mask |= ((near <= far) as u32) << s;
        }
        (entries, mask)
    }

    fn set_t_max(&mut self, t_max: f64) {
        self.t_max = t_max;
    }

    fn octant(&self) -> usize {
        self.octant
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::unit_interval;
    use rand_chacha::ChaCha8Rng;
    use rand_core::{Rng, SeedableRng};

    #[test]
    fn child_references_round_trip() {
        assert_eq!(unpack(leaf_ref(12345, 4)), (12345, 4));
        assert_eq!(unpack(INDEX_MASK), (INDEX_MASK as usize, 0));
        assert_eq!(unpack(7), (7, 0));
    }

    fn leaf(x: f32, first: u32) -> Node {
        Node {
            min: [x, 0.0, 0.0],
            first,
            max: [x + 0.5, 1.0, 1.0],
            count: 1,
        }
    }

    fn interior(min: [f32; 3], max: [f32; 3], first: u32) -> Node {
        Node {
            min,
            first,
            max,
            count: 0,
        }
    }

    /// Four leaves at x = 0, 1, 2, 3 under two interior nodes become one node of four slots,
    /// ordered by x for the octants of positive x and backwards for the others.
    #[test]
    fn a_two_level_binary_tree_collapses_to_one_node() {
        let binary = vec![
            interior([0.0; 3], [3.5, 1.0, 1.0], 2),
            Node::default(),
            interior([0.0; 3], [1.5, 1.0, 1.0], 4),
            interior([2.0, 0.0, 0.0], [3.5, 1.0, 1.0], 6),
            leaf(0.0, 0),
            leaf(1.0, 1),
            leaf(2.0, 2),
            leaf(3.0, 3),
        ];
        let (nodes, depth) = collapse(&binary);
        assert_eq!((nodes.len(), depth), (1, 0));
        let n = &nodes[0];
        for s in 0..4 {
            assert_eq!(unpack(n.child[s]), (s, 1));
            assert_eq!(n.slot_box(s).0[0], s as f32);
        }
        let forward = 0b11_10_01_00;
        let backward = 0b00_01_10_11;
        for octant in 0..8 {
            let want = if octant & 1 == 0 { forward } else { backward };
            assert_eq!(n.order[octant], want, "octant {octant}");
        }
    }

    /// A root with two leaves keeps two slots; the others are empty, last in every order,
    /// and never entered.
    #[test]
    fn unused_slots_are_empty_and_never_entered() {
        let binary = vec![
            interior([0.0; 3], [1.5, 1.0, 1.0], 2),
            Node::default(),
            leaf(0.0, 0),
            leaf(1.0, 1),
        ];
        let (nodes, _) = collapse(&binary);
        let n = &nodes[0];
        assert!(n.occupied(0) && n.occupied(1) && !n.occupied(2) && !n.occupied(3));
        for order in n.order {
            assert_eq!(order >> 4, 0b11_10, "empty slots last");
        }
        // Along z through the first leaf's face x = 0.5; along x through both leaves.
        for (o, d, want) in [
            ([0.5, 0.5, -1.0], [0.0, 0.0, 1.0], 0b01),
            ([-1.0, 0.5, 0.5], [1.0, -0.0, 0.0], 0b11),
        ] {
            let s = F32Slots::new(o, d, 0.0, f64::INFINITY).unwrap();
            assert_eq!(s.enter(n).1, want, "{o:?} {d:?}");
            let s = F64Slots::new(o, d, 0.0, f64::INFINITY);
            assert_eq!(s.enter(n).1, want, "{o:?} {d:?}");
        }
    }

    #[test]
    fn rays_beyond_f32_are_left_to_f64() {
        let ok = |o: [f64; 3], d: [f64; 3], t_min: f64| F32Slots::new(o, d, t_min, f64::INFINITY).is_some();
        assert!(ok([1e9, -1e9, 0.1], [0.0, -0.0, 1.0], 1e-9));
        assert!(ok([0.0; 3], [1e-15, 1.0, 1e15], 0.0));
        assert!(!ok([2e15, 0.0, 0.0], [1.0, 0.0, 0.0], 0.0));
        assert!(
            !ok([0.0; 3], [1e-20, 1.0, 0.0], 0.0),
            "a tiny component that rounds to 0"
        );
        assert!(!ok([0.0; 3], [1.0, 2e15, 0.0], 0.0));
        assert!(!ok([0.0; 3], [1.0, 0.0, 0.0], f64::NAN));
        // Its entries are shrunk toward 0, which is early only from `t = 0` on.
        assert!(!ok([0.0; 3], [1.0, 0.0, 0.0], -1e-300));
        assert!(ok([0.0; 3], [1.0, 0.0, 0.0], -0.0));
    }

    /// The slab test in `f64` without widening: where the ray enters `[min, max]` within
    /// `[t_min, t_max]`, if it does (a NaN, an origin on the plane of a slab the ray runs
    /// along, counts as inside).
    fn reference(o: [f64; 3], d: [f64; 3], min: [f64; 3], max: [f64; 3], t_min: f64, t_max: f64) -> Option<f64> {
        let (mut near, mut far) = (t_min, t_max);
        for a in 0..3 {
            let inv = 1.0 / d[a];
            let (t0, t1) = ((min[a] - o[a]) * inv, (max[a] - o[a]) * inv);
            let (t0, t1) = if inv < 0.0 { (t1, t0) } else { (t0, t1) };
            if t0 > near {
                near = t0;
            }
            if t1 < far {
                far = t1;
            }
        }
        (near <= far).then_some(near)
    }

    /// Both tests enter every box the ray meets (with an entry no later than the exact one)
    /// and no box it misses by more than `1e-5`, for origins on the boxes' planes, zero and
    /// negative-zero components, origins an `f32` cannot hold, and several intervals.
    #[test]
    fn both_tests_enter_every_box_the_ray_meets_and_little_more() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut uniform = move || unit_interval(rng.next_u64());
        let coords = [
            -2.0,
            -1.0,
            -0.5,
            -0.0,
            0.0,
            0.25,
            1.0,
            3.0,
            0.1,
            1.0 / 3.0,
            1e-38,
            -3e-38,
        ];
        let dirs = [-1.0, -0.3, -0.0, 0.0, 0.6, 1.0, 1e-3, -0.5, 1e10, -3e12];
        // Near 0 the absolute widening is all there is: intervals of a few `2^-126`.
        let intervals = [
            (0.0, f64::INFINITY),
            (0.5, 2.0),
            (-1.0, 0.0),
            (1e-9, 1e30),
            (0.0, 0.0),
            (0.0, 1e-38),
            (1e-38, 3e-38),
        ];
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..20_000 {
            let mut pick = |set: &[f64]| {
                let k = (uniform() * (set.len() + 1) as f64) as usize;
                set.get(k).copied().unwrap_or(4.0 * uniform() - 2.0)
            };
            let mut node = Node4::EMPTY;
            let mut boxes = Vec::new();
            for s in 0..WIDTH {
                let (p, q) = (
                    [0; 3].map(|_| pick(&coords) as f32),
                    [0; 3].map(|_| pick(&coords) as f32),
                );
                let (min, max) = ([0, 1, 2].map(|a| p[a].min(q[a])), [0, 1, 2].map(|a| p[a].max(q[a])));
                for a in 0..3 {
                    node.bounds[a][s] = min[a];
                    node.bounds[3 + a][s] = max[a];
                }
                boxes.push((min.map(f64::from), max.map(f64::from)));
            }
            let o = [0; 3].map(|_| pick(&coords));
            let d = [0; 3].map(|_| pick(&dirs));
            if d == [0.0; 3] {
                // No ray has a zero direction (and the reference would enter at t = inf).
                continue;
            }
            for (t_min, t_max) in intervals {
                let f32_slots = F32Slots::new(o, d, t_min, t_max);
                assert_eq!(f32_slots.is_some(), t_min >= 0.0, "f32 from t_min = 0 on");
                let f64_slots = F64Slots::new(o, d, t_min, t_max);
                let mut tests: Vec<&dyn SlotTest> = vec![&f64_slots];
                tests.extend(f32_slots.as_ref().map(|s| s as &dyn SlotTest));
                for (which, test) in tests.iter().enumerate() {
                    let (entries, mask) = test.enter(&node);
                    for (s, (min, max)) in boxes.iter().enumerate() {
                        let entered = mask >> s & 1 == 1;
                        match reference(o, d, *min, *max, t_min, t_max) {
                            Some(near) => {
                                assert!(entered, "test {which} missed box {s} {min:?} {max:?}: {o:?} {d:?}");
                                let entry = entries[s] as f64;
                                assert!(entry <= near + near.abs() * 1e-12, "entry {entry} after {near}");
                                hits += 1;
                            }
                            None => {
                                let grown = (min.map(|x| x - 1e-5), max.map(|x| x + 1e-5));
                                let near_miss = reference(o, d, grown.0, grown.1, t_min - 1e-5, t_max + 1e-5);
                                assert!(!entered || near_miss.is_some(), "test {which} entered box {s}");
                                misses += 1;
                            }
                        }
                    }
                }
            }
        }
        assert!(hits > 20_000 && misses > 20_000, "{hits} hits, {misses} misses");
    }

    #[test]
    fn grazing_an_edge_and_lying_in_a_face_count_as_hits() {
        let binary = vec![
            interior([0.0; 3], [1.0; 3], 2),
            Node::default(),
            leaf(0.0, 0),
            leaf(3.0, 1),
        ];
        let (nodes, _) = collapse(&binary);
        let mut unit = nodes[0];
        for a in 0..3 {
            unit.bounds[a][0] = 0.0;
            unit.bounds[3 + a][0] = 1.0;
        }
        let enters = |o: [f64; 3], d: [f64; 3], t_min: f64, t_max: f64| {
            let f32_says = F32Slots::new(o, d, t_min, t_max).unwrap().enter(&unit);
            let f64_says = F64Slots::new(o, d, t_min, t_max).enter(&unit);
            assert_eq!(f32_says.1 & 1, f64_says.1 & 1, "{o:?} {d:?}");
            (f32_says.1 & 1 == 1).then_some(f32_says.0[0])
        };
        let inf = f64::INFINITY;
        // Along the edge y = 0, z = 0, and along y = 1, z = 1 the other way with -0.
        assert!(enters([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], 0.0, inf).is_some());
        assert!(enters([2.0, 1.0, 1.0], [-1.0, -0.0, 0.0], 0.0, inf).is_some());
        // Just outside a face.
        assert!(enters([-1.0, 1.0 + 1e-6, 0.5], [1.0, 0.0, 0.0], 0.0, inf).is_none());
        // Through a corner diagonally: enters at sqrt(3), to f32's widening.
        let d = 1.0 / 3f64.sqrt();
        let near = enters([-1.0; 3], [d; 3], 0.0, inf).unwrap() as f64;
        assert!(near <= 3f64.sqrt() && near > 3f64.sqrt() * (1.0 - 4e-6), "{near}");
        // Starting inside: enters at t_min or before.
        assert!(enters([0.5; 3], [0.0, 0.0, 1.0], 0.0, 0.1).unwrap() <= 0.0);
        // Behind the origin, or beyond t_max.
        assert!(enters([2.0, 0.5, 0.5], [1.0, 0.0, 0.0], 0.0, inf).is_none());
        assert!(enters([-2.0, 0.5, 0.5], [1.0, 0.0, 0.0], 0.0, 1.5).is_none());
    }
}
