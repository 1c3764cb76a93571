//! The binary node the builder makes (32 bytes: an `f32` box rounded outward and two
//! `u32`), and the objects' stored boxes.
//!
//! No hit may be lost to rounding, so every step errs outward: the `f64` object bounds are
//! padded by a relative `2^-20` of their largest side (room for a shape whose computed hit
//! lies a little outside its exact bounds, e.g. a grazing root with an error of order
//! `sqrt(eps)` of its size), and converted to `f32` rounding down for the minimum and up for
//! the maximum. The ray-box tests that widen their own rounding are in [`super::wide`].

use crate::shape::Aabb;

/// One node of the binary tree (collapsed to 4-wide nodes by [`super::wide::collapse`]).
/// The two children of an interior node are adjacent (`first`, `first + 1`).
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

    /// Half the surface area of the node's box (see [`half_area`]).
    pub fn half_area(&self) -> f32 {
        half_area([0, 1, 2].map(|a| self.max[a] - self.min[a]))
    }
}

/// Half the surface area of a box of sides `d` (the SAH needs only ratios).
#[inline(always)]
pub fn half_area(d: [f32; 3]) -> f32 {
    d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
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
}
