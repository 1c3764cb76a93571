//! The balls of a linearly scanned world seen along a directional light: every shadow ray
//! towards such a light leaves along the same unit direction `L` and has no end, so each
//! ball's centre is written once in a frame `(e1, e2, L)` and a ray's test against a ball
//! costs two differences and a distance in the plane across `L`, where the test of
//! [`misses_bounding_sphere`](crate::shape::misses_bounding_sphere) works in space.

use glam::DVec3;

/// Relative padding of the reach: the test passes a ball by only when the ray stays farther
/// from its centre than `r (1 + 1e-9) + PAD (|o|_1 + |c|_1)`. The frame and the coordinates
/// are within a few ulps of `|o|_1 + |c|_1` of their exact values (about 1e-15 of it),
/// and `misses_bounding_sphere` pads by `1e-9 |o - c|_1 <= 1e-9 (|o|_1 + |c|_1)`: twice
/// that covers both, so a ball is passed by here only where `misses_bounding_sphere`
/// would pass it by in exact arithmetic, with its margin.
const PAD: f64 = 2e-9;

/// One directional light's view of the balls of [`super::World::shadow_scan`]'s two lists.
#[derive(Clone, Debug)]
pub(super) struct BallsAlong {
    /// The direction of the shadow rays, `L` (unit).
    pub(super) l: DVec3,
    /// Two unit vectors perpendicular to `L` and to each other.
    e1: DVec3,
    e2: DVec3,
    /// Per ball of the opaque list, then of the see-through list: the centre's coordinates
    /// `(c.e1, c.e2, c.L)` and its part of the reach, `r (1 + 1e-9) + PAD |c|_1` (infinite
    /// for a ball of infinite radius, which is never passed by).
    pub(super) opaque: Vec<[f64; 4]>,
    pub(super) see_through: Vec<[f64; 4]>,
}

/// A ray's origin `o` in a [`BallsAlong`] frame: `(o.e1, o.e2, o.L)` and its part of the
/// reach, `PAD |o|_1`.
#[derive(Clone, Copy, Debug)]
pub(super) struct OriginAlong {
    u: f64,
    v: f64,
    w: f64,
    pad: f64,
}

impl BallsAlong {
    /// The view along `l` of the balls of the two lists; `None` when `l` is not a unit
    /// vector to within 1e-12 (the frame's error bound needs it).
    pub(super) fn new(
        l: DVec3,
        opaque: &[(usize, (DVec3, f64))],
        see_through: &[(usize, (DVec3, f64))],
    ) -> Option<Self> {
        if (l.length_squared() - 1.0).abs() > 1e-12 {
            return None;
        }
        let (e1, e2) = l.any_orthonormal_pair();
        let view = |&(_, (c, r)): &(usize, (DVec3, f64))| {
            let reach = r * (1.0 + 1e-9) + PAD * c.abs().element_sum();
            [c.dot(e1), c.dot(e2), c.dot(l), reach]
        };
        Some(BallsAlong {
            l,
            e1,
            e2,
            opaque: opaque.iter().map(view).collect(),
            see_through: see_through.iter().map(view).collect(),
        })
    }

    /// The origin `o` of a ray along `L` in this frame.
    #[inline(always)]
    pub(super) fn origin(&self, o: DVec3) -> OriginAlong {
        OriginAlong {
            u: o.dot(self.e1),
            v: o.dot(self.e2),
            w: o.dot(self.l),
            pad: PAD * o.abs().element_sum(),
        }
    }
}

impl OriginAlong {
    /// Whether the ray from this origin along `L`, `t` in `(0, inf)`, misses the ball `ball`
    /// (an entry of [`BallsAlong`]) by the padded reach: its distance across `L` from the
    /// centre exceeds the reach, or the whole ball is behind the origin
    /// (`(c - o).L + reach < 0`).
    #[inline(always)]
    pub(super) fn misses(&self, &[u, v, w, reach]: &[f64; 4]) -> bool {
        let reach = reach + self.pad;
        let (du, dv) = (self.u - u, self.v - v);
        (du * du + dv * dv > reach * reach) | (w - self.w + reach < 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_along_l_misses_exactly_the_balls_off_its_line_beyond_the_padding() {
        // L = (0, 0, 1) from the origin; a unit ball centred 2 across L (its edge 1 from the
        // line) is missed, one centred 0.999 across is met, one ahead on the line is met,
        // one behind the origin (centre at z = -3) is missed, one behind but reaching
        // past the origin (z = -0.5) is met, and an unbounded one is never missed.
        let balls = [
            (0, (DVec3::new(2.0, 0.0, 5.0), 1.0)),
            (1, (DVec3::new(0.0, 0.999, 5.0), 1.0)),
            (2, (DVec3::new(0.0, 0.0, 5.0), 1.0)),
            (3, (DVec3::new(0.0, 0.0, -3.0), 1.0)),
            (4, (DVec3::new(0.0, 0.0, -0.5), 1.0)),
            (5, (DVec3::ZERO, f64::INFINITY)),
        ];
        let along = BallsAlong::new(DVec3::Z, &balls, &[]).unwrap();
        let o = along.origin(DVec3::ZERO);
        let missed: Vec<bool> = along.opaque.iter().map(|b| o.misses(b)).collect();
        assert_eq!(missed, [true, false, false, true, false, false]);
        // A ball whose edge touches the line (centre 1 across, radius 1): not passed by.
        let tangent = BallsAlong::new(DVec3::Z, &[(0, (DVec3::new(1.0, 0.0, 5.0), 1.0))], &[]).unwrap();
        assert!(!tangent.origin(DVec3::ZERO).misses(&tangent.opaque[0]));
        // A direction that is not unit gives no view.
        assert!(BallsAlong::new(DVec3::new(0.0, 0.0, 1.001), &balls, &[]).is_none());
    }
}
