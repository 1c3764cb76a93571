//! The flattened BVH node (32 bytes: an `f32` box rounded outward and two `u32`) and the
//! conservative ray-box slab test the traversal runs on it.
//!
//! No hit may be lost to rounding, so every step errs outward: the `f64` object bounds are
//! padded by a relative `2^-20` of their largest side (room for a shape whose computed hit
//! lies a little outside its exact bounds, e.g. a grazing root with an error of order
//! `sqrt(eps)` of its size), converted to `f32` rounding down for the minimum and up for the
//! maximum, and the slab test widens its computed interval by `2 gamma(3)` (pbrt-v4,
//! `Bounds3::IntersectP`: the subtraction, the product and the reciprocal each round once).

use crate::math::Ray;
use crate::shape::Aabb;

/// One node of the flattened tree. The two children of an interior node are adjacent
/// (`first`, `first + 1`) so that one 64-byte cache line holds both of them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub struct Node {
    pub min: [f32; 3],
    /// Interior: index of the first child. Leaf: index of its first entry in `Bvh::prims`.
    pub first: u32,
    pub max: [f32; 3],
    /// 0 for an interior node, else the number of objects in the leaf.
    pub count: u32,
}

impl Node {
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }

    /// Whether this node's box contains `other`'s.
    pub fn contains(&self, min: [f32; 3], max: [f32; 3]) -> bool {
        (0..3).all(|a| self.min[a] <= min[a] && max[a] <= self.max[a])
    }
}

/// Relative padding of object boxes, as a fraction of their largest side.
const PAD: f64 = 1.0 / (1u64 << 20) as f64;

/// The `f32` box stored for an object with exact bounds `b`: padded (see the module doc)
/// and rounded outward, so it contains `b`.
pub fn stored_box(b: &Aabb) -> ([f32; 3], [f32; 3]) {
    let pad = (b.max - b.min).max_element() * PAD;
    let lo = b.min - pad;
    let hi = b.max + pad;
    ([down(lo.x), down(lo.y), down(lo.z)], [up(hi.x), up(hi.y), up(hi.z)])
}

/// The largest `f32` not above `x`.
pub fn down(x: f64) -> f32 {
    let f = x as f32;
    // A select, not a branch: which way `x` rounded is random (a million boxes are built
    // in about 0.3 s, and a mispredicted branch per coordinate took a twentieth of it).
    let below = f.next_down();
    if f as f64 > x { below } else { f }
}

/// The smallest `f32` not below `x`.
pub fn up(x: f64) -> f32 {
    let f = x as f32;
    // A select, as in `down`.
    let above = f.next_up();
    if (f as f64) < x { above } else { f }
}

/// `2 gamma(3)`: the relative widening that makes the slab test's computed interval contain
/// the exact one.
const WIDEN: f64 = 2.0 * (3.0 * f64::EPSILON * 0.5) / (1.0 - 3.0 * f64::EPSILON * 0.5);

/// A ray prepared for slab tests: origin, reciprocal direction (infinite for a zero
/// component) and which end of each slab it enters by.
pub struct RaySlabs {
    origin: [f64; 3],
    inv: [f64; 3],
    negative: [bool; 3],
}

impl RaySlabs {
    pub fn new(ray: &Ray) -> Self {
        let d = ray.dir.to_array();
        RaySlabs {
            origin: ray.origin.to_array(),
            inv: d.map(|x| 1.0 / x),
            // -0.0 counts as negative so that its reciprocal, -inf, pairs with the max side.
            negative: d.map(|x| x.is_sign_negative()),
        }
    }

    /// Where the ray enters the node's box within `[t_min, t_max]` (widened outward), or
    /// `None` when it misses it there.
    ///
    /// A zero direction component gives `(bound - o) * inf`: +-inf outside the slab, which
    /// rejects or does not restrict as it should, and NaN for an origin exactly on the
    /// slab's plane, which the comparisons below ignore (`NaN > near` is false), so such a
    /// ray counts as inside the slab.
    #[inline(always)]
    pub fn enter(&self, n: &Node, t_min: f64, t_max: f64) -> Option<f64> {
        let (mut near, mut far) = (t_min, t_max);
        for a in 0..3 {
            let (lo, hi) = if self.negative[a] {
                (n.max[a], n.min[a])
            } else {
                (n.min[a], n.max[a])
            };
            let t0 = (lo as f64 - self.origin[a]) * self.inv[a];
            let t1 = (hi as f64 - self.origin[a]) * self.inv[a];
            near = if t0 > near { t0 } else { near };
            far = if t1 < far { t1 } else { far };
        }
        let near = near - near.abs() * WIDEN;
        let far = far + far.abs() * WIDEN;
        (near <= far).then_some(near)
    }

    /// [`RaySlabs::enter`] of two sibling nodes at once (the same operations on each, so
    /// the same results), written lane by lane so that the pair is tested with vector
    /// instructions.
    #[inline(always)]
    pub fn enter_pair(&self, pair: [&Node; 2], t_min: f64, t_max: f64) -> [Option<f64>; 2] {
        let (mut near, mut far) = ([t_min; 2], [t_max; 2]);
        for a in 0..3 {
            let (o, inv, negative) = (self.origin[a], self.inv[a], self.negative[a]);
            for k in 0..2 {
                let (lo, hi) = if negative {
                    (pair[k].max[a], pair[k].min[a])
                } else {
                    (pair[k].min[a], pair[k].max[a])
                };
                let t0 = (lo as f64 - o) * inv;
                let t1 = (hi as f64 - o) * inv;
                near[k] = if t0 > near[k] { t0 } else { near[k] };
                far[k] = if t1 < far[k] { t1 } else { far[k] };
            }
        }
        [0, 1].map(|k| {
            let near = near[k] - near[k].abs() * WIDEN;
            let far = far[k] + far[k].abs() * WIDEN;
            (near <= far).then_some(near)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn outward_rounding_contains_the_value() {
        for x in [0.1, -0.1, 1.0, -1.0, 0.0, 1e9 + 0.3, -1e9 - 0.3, 1e-40, -1e-40] {
            assert!(down(x) as f64 <= x, "{x}");
            assert!(up(x) as f64 >= x, "{x}");
        }
        // Exact values stay put; inexact ones move one f32 step at most.
        assert_eq!(down(1.0), 1.0);
        assert!((up(0.1) as f64) - 0.1 < 1e-8 && 0.1 - (down(0.1) as f64) < 1e-8);
    }

    #[test]
    fn stored_box_contains_the_bounds() {
        let b = Aabb::new(DVec3::new(-0.3, 0.0, 1e6 + 0.1), DVec3::new(0.7, 1e-30, 1e6 + 0.2));
        let (lo, hi) = stored_box(&b);
        for a in 0..3 {
            assert!((lo[a] as f64) < b.min[a] && (hi[a] as f64) > b.max[a], "axis {a}");
        }
    }

    fn unit_node() -> Node {
        Node {
            min: [0.0; 3],
            max: [1.0; 3],
            first: 0,
            count: 1,
        }
    }

    /// `enter_pair` is `enter` on each node, to the bit, whatever the signs and zeros of the
    /// direction and wherever the origin lies (on a box's plane included).
    #[test]
    fn enter_pair_is_enter_on_each_node() {
        use rand_chacha::ChaCha8Rng;
        use rand_core::{Rng, SeedableRng};
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut pick = |choices: &[f64]| choices[(rng.next_u64() % choices.len() as u64) as usize];
        let coords = [-2.0, -1.0, -0.5, -0.0, 0.0, 0.25, 1.0, 3.0];
        let dirs = [-1.0, -0.3, -0.0, 0.0, 0.6, 1.0];
        let bits = |e: Option<f64>| e.map(f64::to_bits);
        for _ in 0..4000 {
            let mut node = || {
                let (a, b) = (
                    [0; 3].map(|_| pick(&coords) as f32),
                    [0; 3].map(|_| pick(&coords) as f32),
                );
                Node {
                    min: [0, 1, 2].map(|k| a[k].min(b[k])),
                    max: [0, 1, 2].map(|k| a[k].max(b[k])),
                    first: 0,
                    count: 1,
                }
            };
            let (n0, n1) = (node(), node());
            let origin = DVec3::new(pick(&coords), pick(&coords), pick(&coords));
            let dir = DVec3::new(pick(&dirs), pick(&dirs), pick(&dirs));
            let s = RaySlabs::new(&Ray::new(origin, dir));
            for (t_min, t_max) in [(0.0, f64::INFINITY), (0.5, 2.0), (-1.0, 0.0)] {
                let pair = s.enter_pair([&n0, &n1], t_min, t_max);
                assert_eq!(bits(pair[0]), bits(s.enter(&n0, t_min, t_max)));
                assert_eq!(bits(pair[1]), bits(s.enter(&n1, t_min, t_max)));
            }
        }
    }

    #[test]
    fn grazing_an_edge_and_lying_in_a_face_count_as_hits() {
        let n = unit_node();
        // Along the edge y = 0, z = 0 of the unit box.
        let s = RaySlabs::new(&Ray::new(DVec3::new(-1.0, 0.0, 0.0), DVec3::X));
        assert!(s.enter(&n, 0.0, f64::INFINITY).is_some());
        // Along the opposite edge y = 1, z = 1, direction -x with zero (and -0) components.
        let s = RaySlabs::new(&Ray::new(DVec3::new(2.0, 1.0, 1.0), DVec3::new(-1.0, -0.0, 0.0)));
        assert!(s.enter(&n, 0.0, f64::INFINITY).is_some());
        // Just outside the face: a miss.
        let s = RaySlabs::new(&Ray::new(DVec3::new(-1.0, 1.0 + 1e-6, 0.5), DVec3::X));
        assert!(s.enter(&n, 0.0, f64::INFINITY).is_none());
        // Through a corner diagonally.
        let d = DVec3::new(1.0, 1.0, 1.0).normalize();
        let s = RaySlabs::new(&Ray::new(DVec3::new(-1.0, -1.0, -1.0), d));
        let near = s.enter(&n, 0.0, f64::INFINITY).unwrap();
        assert!((near - 3f64.sqrt()).abs() < 1e-12);
        // Starting inside: enters at t_min.
        let s = RaySlabs::new(&Ray::new(DVec3::splat(0.5), DVec3::Z));
        assert!(s.enter(&n, 0.0, 0.1).unwrap() <= 0.0);
        // Behind the origin, or beyond t_max: misses.
        let s = RaySlabs::new(&Ray::new(DVec3::new(2.0, 0.5, 0.5), DVec3::X));
        assert!(s.enter(&n, 0.0, f64::INFINITY).is_none());
        let s = RaySlabs::new(&Ray::new(DVec3::new(-2.0, 0.5, 0.5), DVec3::X));
        assert!(s.enter(&n, 0.0, 1.5).is_none());
    }
}
