//! The box test of a packet: up to [`PACKET`] rays whose directions share an octant,
//! tested against one slot of a 4-wide node at once, one ray a vector lane.
//!
//! Neighbouring camera rays (a pixel's samples, a run of pixels) enter mostly the same
//! nodes: walked together, they load and test each node once, where one ray at a time
//! loads it again and repeats the walk's bookkeeping per ray. Each lane computes exactly
//! [`super::wide::F32Slots`]' test from the same [`RayTerms`], so a lane enters a slot when
//! its ray alone would, and the walk's answers stay the scalar walk's.

use super::leaf::Masks;
use super::wide::{Node4, RayTerms, TINY};

/// Most rays a packet holds: one 512-bit vector of `f32` (two 256-bit ones with AVX2), and
/// Embree's widest packet. Wider packets walk neighbouring camera rays faster still
/// (BENCHMARKS.md, "Against Embree 3").
pub const PACKET: usize = 16;

/// The per-ray terms of [`RayTerms`] laid across the lanes, for rays of one octant.
pub struct PacketSlots {
    entry_row: [usize; 3],
    exit_row: [usize; 3],
    entry_origin: [[f32; PACKET]; 3],
    exit_origin: [[f32; PACKET]; 3],
    entry_inv: [[f32; PACKET]; 3],
    exit_inv: [[f32; PACKET]; 3],
    t_min: [f32; PACKET],
    t_max: [f32; PACKET],
    octant: usize,
}

impl PacketSlots {
    /// The test for `len` rays (at least one, at most [`PACKET`]) whose terms are `terms(l)`
    /// for lane `l`, or `None` when one of them has none or their directions do not share
    /// an octant. Lanes from `len` on repeat the first (the walk never reads them).
    #[inline(always)]
    pub fn new(len: usize, terms: impl Fn(usize) -> Option<RayTerms>) -> Option<Self> {
        if !(1..=PACKET).contains(&len) {
            return None;
        }
        let first = terms(0)?;
        let (entry_row, exit_row) = first.rows();
        let mut p = PacketSlots {
            entry_row,
            exit_row,
            entry_origin: [[0.0; PACKET]; 3],
            exit_origin: [[0.0; PACKET]; 3],
            entry_inv: [[0.0; PACKET]; 3],
            exit_inv: [[0.0; PACKET]; 3],
            t_min: [0.0; PACKET],
            t_max: [0.0; PACKET],
            octant: first.octant,
        };
        for l in 0..PACKET {
            let t = if l == 0 || l >= len { first } else { terms(l)? };
            if t.octant != first.octant {
                return None;
            }
            for a in 0..3 {
                p.entry_origin[a][l] = t.entry_origin[a];
                p.exit_origin[a][l] = t.exit_origin[a];
                p.entry_inv[a][l] = t.entry_inv[a];
                p.exit_inv[a][l] = t.exit_inv[a];
            }
            p.t_min[l] = t.t_min;
            p.t_max[l] = t.t_max;
        }
        Some(p)
    }

    /// The lanes that enter slot `s` of `n` within their intervals (bit `l` for lane `l`),
    /// and for each a distance not beyond its entry: [`super::wide::SlotTest::enter`]'s
    /// operations, lane by lane. `masks` makes the mask of the lanes whose `far + 2 TINY -
    /// near` is not negative, which is `near <= far + 2 TINY` (a difference of floats is
    /// negative exactly when the first is smaller; `near` never falls below `t_min` nor
    /// `far` rises above `t_max`, so the one NaN, `inf - inf`, comes where both say entered).
    #[inline(always)]
    pub fn enter(&self, n: &Node4, s: usize, masks: Masks) -> ([f32; PACKET], u32) {
        let (mut near, mut far) = (self.t_min, self.t_max);
        for a in 0..3 {
            let entry = n.bounds[self.entry_row[a]][s];
            let exit = n.bounds[self.exit_row[a]][s];
            for l in 0..PACKET {
                let t0 = (entry - self.entry_origin[a][l]) * self.entry_inv[a][l];
                let t1 = (exit - self.exit_origin[a][l]) * self.exit_inv[a][l];
                // As `maxps` and `minps`: the interval so far where a product is NaN.
                near[l] = if t0 > near[l] { t0 } else { near[l] };
                far[l] = if t1 < far[l] { t1 } else { far[l] };
            }
        }
        let mut room = [0.0; PACKET];
        let mut entries = [0.0; PACKET];
        for l in 0..PACKET {
            room[l] = (far[l] + 2.0 * TINY) - near[l];
            entries[l] = near[l] - TINY;
        }
        (entries, masks.not_negative(&room))
    }

    /// The lanes of `entries` (entry distances of a child) not beyond their rays' interval
    /// ends: the children a lane's best hit so far does not rule out. `t_max` is rounded up,
    /// so a lane may take a child its own walk would skip, never skip one it would take.
    #[inline(always)]
    pub fn within(&self, entries: &[f32; PACKET], masks: Masks) -> u32 {
        let mut room = [0.0; PACKET];
        for l in 0..PACKET {
            room[l] = self.t_max[l] - entries[l];
        }
        masks.not_negative(&room)
    }

    /// Narrows lane `l`'s interval to end at `t_max` (a closer hit was found).
    #[inline(always)]
    pub fn set_t_max(&mut self, l: usize, t_max: f32) {
        self.t_max[l] = t_max;
    }

    /// The rays' octant ([`Node4::order`]).
    #[inline(always)]
    pub fn octant(&self) -> usize {
        self.octant
    }
}

/// The lanes of `mask` (bit `l` for lane `l`), lowest first.
#[inline(always)]
pub fn each_lane(mask: u32) -> Lanes {
    Lanes(mask)
}

/// The iterator of [`each_lane`]: a struct, not a closure, so that it is inlined into the walks.
pub struct Lanes(u32);

impl Iterator for Lanes {
    type Item = usize;

    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let l = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(l)
    }
}
