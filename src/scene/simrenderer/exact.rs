//! What to write so that a scene file's reader rebuilds a [`crate::scene::Scene`]'s values
//! to the bit, in short decimals where it can: a direction that the reader makes unit, the
//! far end of a cylinder's axis, a box's rotation, a transform's scale, rotation and
//! translation, a plasticity `p = 1 - m`.
//!
//! The scene keeps derived values (unit normals and axes, a box's frame, a transform's
//! matrices), not what a file wrote. Each function here tries candidates, the short ones
//! first (a unit vector scaled to a largest component of 1, values rounded to 12
//! significant digits), and keeps the first that the reader's own arithmetic turns back
//! into the scene's value exactly. When none does, it says so, and the value written is
//! the nearest it found (within rounding of the last digits).

use crate::shape::{Cuboid, Transform};
use glam::{DMat3, DVec3};

/// What both formats make of a written direction: divided by its length (a directional
/// light's direction, the camera's up).
pub fn unit_once(w: DVec3) -> DVec3 {
    w / w.length()
}

/// What both formats make of a written normal or axis: divided by its length, then made
/// unit again by the shape's constructor (plane and disk normals, cylinder, cone and torus
/// axes, a spot's direction).
pub fn unit_twice(w: DVec3) -> DVec3 {
    unit_once(w).normalize()
}

/// The shortest decimal of at most 12 significant digits within `1e-12` of `x` (relative;
/// below `1e-13` in magnitude, 0), or `x`.
pub fn short(x: f64) -> f64 {
    if x.abs() < 1e-13 {
        return 0.0;
    }
    if !x.is_finite() {
        return x;
    }
    for digits in 1..=12 {
        if let Ok(y) = format!("{:.*e}", digits - 1, x).parse::<f64>()
            && (y - x).abs() <= 1e-12 * x.abs()
        {
            return y;
        }
    }
    x
}

fn short3(v: DVec3) -> DVec3 {
    DVec3::new(short(v.x), short(v.y), short(v.z))
}

/// `x` moved by `k` units in the last place (`k` in -1, 0, 1).
fn ulps(x: f64, k: i32) -> f64 {
    match k {
        -1 => x.next_down(),
        1 => x.next_up(),
        _ => x,
    }
}

/// `v` moved by -1, 0 or +1 units in the last place in each component: 27 vectors, `v`
/// first.
fn neighbours(v: DVec3) -> impl Iterator<Item = DVec3> {
    (0..27).map(move |i| {
        let k = |d: i32| [0, -1, 1][((i / 3i32.pow(d as u32)) % 3) as usize];
        DVec3::new(ulps(v.x, k(0)), ulps(v.y, k(1)), ulps(v.z, k(2)))
    })
}

/// A vector to write for the unit vector `target`, which `reads` (the reader's
/// arithmetic: [`unit_once`] or [`unit_twice`]) turns back into `target`; `exact` false
/// when no candidate does (then `target` itself is written).
pub fn direction(target: DVec3, reads: fn(DVec3) -> DVec3) -> (DVec3, bool) {
    let largest = target.abs().max_element();
    let smallest = target
        .to_array()
        .into_iter()
        .map(f64::abs)
        .filter(|c| *c > 1e-3 * largest)
        .fold(f64::INFINITY, f64::min);
    let scaled = [target / largest, target / smallest];
    let candidates = scaled
        .iter()
        .map(|s| short3(*s))
        .chain([short3(target), target])
        .chain(scaled)
        .chain(neighbours(target).skip(1));
    for c in candidates {
        if c.is_finite() && c.length() > 0.0 && reads(c) == target {
            return (c, true);
        }
    }
    (target, false)
}

/// The far end to write for the segment from `base` along the unit `axis` for `height` (a
/// cylinder's, cone's or tube's second point), from which the readers compute
/// `height = |end - base|` and `axis` by [`unit_twice`] of `end - base`; `exact` false
/// when no candidate gives both back.
pub fn far_end(base: DVec3, axis: DVec3, height: f64) -> (DVec3, bool) {
    let end = base + axis * height;
    let reads = |e: DVec3| {
        let d = e - base;
        let h = d.length();
        (d / h).normalize() == axis && h == height
    };
    for c in std::iter::once(short3(end)).chain(neighbours(end)) {
        if reads(c) {
            return (c, true);
        }
    }
    (end, false)
}

/// The two sets of angles (degrees, about x then y then z, as
/// [`Transform::from_parts`] and [`Cuboid::new`] take them) of the rotation `r`, each
/// with every variant of its angles by a turn that stays in [-360, 360].
fn euler_candidates(r: DMat3) -> Vec<DVec3> {
    // r = Rz(c) Ry(b) Rx(a): r[2][0] = -sin b, r[2][1] = sin a cos b, r[2][2] = cos a cos b,
    // r[1][0] = sin c cos b, r[0][0] = cos c cos b (rows, columns).
    let (r00, r10, r20) = (r.x_axis.x, r.x_axis.y, r.x_axis.z);
    let (r01, r11) = (r.y_axis.x, r.y_axis.y);
    let (r21, r22) = (r.y_axis.z, r.z_axis.z);
    let b = libm::atan2(-r20, libm::hypot(r00, r10));
    let (a, c) = if libm::hypot(r00, r10) > 1e-12 {
        (libm::atan2(r21, r22), libm::atan2(r10, r00))
    } else {
        (0.0, libm::atan2(-r01, r11))
    };
    let first = DVec3::new(a.to_degrees(), b.to_degrees(), c.to_degrees());
    let wrap = |x: f64| if x > 180.0 { x - 360.0 } else { x };
    let second = DVec3::new(wrap(first.x + 180.0), 180.0 - first.y, wrap(first.z + 180.0));
    let turns = |x: f64| [x, x + 360.0, x - 360.0].into_iter().filter(|y| y.abs() <= 360.0);
    let mut out = Vec::new();
    for s in [first, second] {
        for x in turns(s.x) {
            for y in turns(s.y) {
                for z in turns(s.z) {
                    out.push(DVec3::new(x, y, z));
                }
            }
        }
    }
    out
}

/// A transform as SIMRenderer's `geometry` and the TOML `transform` write it: scale factors,
/// angles (degrees) and a translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Parts {
    pub scale: DVec3,
    pub rotation: DVec3,
    pub translation: DVec3,
    /// Whether [`Transform::from_parts`] gives the transform back to the bit.
    pub exact: bool,
}

/// The scale, rotation and translation of `t`, or `None` when its matrix is not a rotation
/// times a scaling (a shear, from a general matrix): then the product of the parts found
/// differs from it by more than `1e-9` of its largest entry.
pub fn parts(t: &Transform) -> Option<Parts> {
    let a = t.to_world.matrix3;
    let translation = t.to_world.translation;
    let cols = [a.x_axis, a.y_axis, a.z_axis];
    let norms = DVec3::new(cols[0].length(), cols[1].length(), cols[2].length());
    let mut nearest: Option<Parts> = None;
    for signs in 0..8 {
        let sign = |k: i32| if signs & (1 << k) != 0 { -1.0 } else { 1.0 };
        let scale = norms * DVec3::new(sign(0), sign(1), sign(2));
        let r = DMat3::from_cols(cols[0] / scale.x, cols[1] / scale.y, cols[2] / scale.z);
        if r.determinant() <= 0.0 {
            continue;
        }
        for angles in euler_candidates(r) {
            for (s, g) in [
                (short3(scale), short3(angles)),
                (scale, angles),
                (short3(scale), angles),
                (scale, short3(angles)),
            ] {
                if Transform::from_parts(s, g, translation) == *t {
                    return Some(Parts {
                        scale: s,
                        rotation: g,
                        translation,
                        exact: true,
                    });
                }
            }
            nearest.get_or_insert(Parts {
                scale: short3(scale),
                rotation: short3(angles),
                translation,
                exact: false,
            });
        }
    }
    let p = nearest?;
    let rebuilt = Transform::from_parts(p.scale, p.rotation, p.translation)
        .to_world
        .matrix3;
    let largest = a.to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let off = (rebuilt - a).to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    (off <= 1e-9 * largest).then_some(p)
}

/// The rotation (degrees, about x then y then z) with which
/// `Cuboid::new(b.center, 2 b.half_size, rotation)` is `b`, and whether it is `b` to the bit.
/// The box's frame is not public: its axes are read from the normals of the faces that
/// rays from its center leave through.
pub fn box_rotation(b: &Cuboid) -> (DVec3, bool) {
    let size = b.half_size * 2.0;
    if Cuboid::new(b.center, size, DVec3::ZERO) == *b {
        return (DVec3::ZERO, true);
    }
    let exit = |dir: DVec3| {
        let ray = crate::math::Ray::new(b.center, dir);
        b.intersect(&ray, 0.0, f64::INFINITY).map(|h| (h.normal, h.t))
    };
    let Some(axes) = box_axes(&exit) else {
        return (DVec3::ZERO, false);
    };
    let mut nearest: Option<(f64, DVec3)> = None;
    for perm in [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]] {
        for signs in 0..8 {
            let sign = |k: usize| if signs & (1 << k) != 0 { -1.0 } else { 1.0 };
            let col = |k: usize| axes[perm[k]].0 * sign(k);
            let r = DMat3::from_cols(col(0), col(1), col(2));
            if r.determinant() <= 0.0 {
                continue;
            }
            let candidates = euler_candidates(r);
            for angles in &candidates {
                for g in [short3(*angles), *angles] {
                    if Cuboid::new(b.center, size, g) == *b {
                        return (g, true);
                    }
                }
            }
            // How far the exits along the axes are from the half sizes this order gives them.
            let mismatch: f64 = (0..3).map(|k| (axes[perm[k]].1 - b.half_size[k]).abs()).sum();
            if nearest.is_none_or(|(m, _)| mismatch < m) {
                nearest = Some((mismatch, short3(candidates[0])));
            }
        }
    }
    (nearest.map_or(DVec3::ZERO, |(_, g)| g), false)
}

/// Three face normals of a box, each with the distance from the center to that face, found
/// with `exit` (the normal and distance where a ray from the center leaves); `None` if the
/// probes do not find three orthogonal ones.
fn box_axes(exit: &dyn Fn(DVec3) -> Option<(DVec3, f64)>) -> Option<[(DVec3, f64); 3]> {
    let (n1, _) = exit(DVec3::new(0.48, 0.36, 0.8))?;
    let helper = if n1.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let (n2, _) = exit(n1.cross(helper).normalize())?;
    let (n3, _) = exit(n1.cross(n2).normalize())?;
    let mut out = [(n1, 0.0), (n2, 0.0), (n3, 0.0)];
    for (n, t) in &mut out {
        *t = exit(*n)?.1;
    }
    let orthogonal = n1.dot(n2).abs() < 1e-9 && n1.dot(n3).abs() < 1e-9 && n2.dot(n3).abs() < 1e-9;
    orthogonal.then_some(out)
}

/// The plasticity `p` to write for the metal factor `m` (the reader takes `m = 1 - p`), and
/// whether it gives `m` back to the bit.
pub fn plasticity(m: f64) -> (f64, bool) {
    let p = 1.0 - m;
    for c in [short(p), p, p.next_down(), p.next_up()] {
        if (0.0..=1.0).contains(&c) && 1.0 - c == m {
            return (c, true);
        }
    }
    (short(p), false)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_decimals() {
        assert_eq!(short(35.00000000000001), 35.0);
        assert_eq!(short(0.1 + 0.2), 0.3);
        assert_eq!(short(1e-15), 0.0);
        // 12 significant digits, within 1e-12: 2/3 is 3.3e-13 from 0.666666666667.
        assert_eq!(short(2.0 / 3.0), 0.666666666667);
        // 13 digits, 1.000000000023, has no 12-digit decimal within 1e-12: it stays.
        assert_eq!(short(1.000000000023), 1.000000000023);
    }

    #[test]
    fn directions_come_back_to_the_bit() {
        // (0, 1, -1) / |.| is not a fixed point of a second division by the length: the
        // vector written is (0, 1, -1) itself.
        let d = unit_once(DVec3::new(0.0, 1.0, -1.0));
        assert_ne!(unit_once(d), d);
        assert_eq!(direction(d, unit_once), (DVec3::new(0.0, 1.0, -1.0), true));
        let a = unit_twice(DVec3::new(0.3, -1.0, 0.4));
        assert_eq!(direction(a, unit_twice), (DVec3::new(0.3, -1.0, 0.4), true));
        let n = unit_twice(DVec3::new(1.0, 2.0, 3.0));
        assert_eq!(direction(n, unit_twice), (DVec3::new(1.0, 2.0, 3.0), true));
    }

    #[test]
    fn far_ends_and_plasticity() {
        let axis = unit_twice(DVec3::new(0.0, 0.0, 1.0));
        assert_eq!(
            far_end(DVec3::new(-5.0, 9.0, 0.0), axis, 3.0),
            (DVec3::new(-5.0, 9.0, 3.0), true)
        );
        let tilted = unit_twice(DVec3::new(0.3, -0.5, 1.0));
        let (end, exact) = far_end(DVec3::new(1.0, 2.0, 3.0), tilted, 2.5);
        let d = end - DVec3::new(1.0, 2.0, 3.0);
        if exact {
            assert_eq!((d.length(), unit_twice(d)), (2.5, tilted));
        }
        assert!((d.length() - 2.5).abs() < 1e-14);
        assert_eq!(plasticity(0.0), (1.0, true));
        assert_eq!(plasticity(0.5), (0.5, true));
        assert_eq!(plasticity(1.0), (0.0, true));
        // 1 - p has no value equal to 0.1 for p near 0.9.
        assert_eq!(plasticity(0.1), (0.9, false));
    }

    #[test]
    fn transforms_and_boxes_are_taken_apart() {
        let t = Transform::from_parts(
            DVec3::new(1.6, 1.0, 3.0),
            DVec3::new(0.0, 0.0, 35.0),
            DVec3::new(0.0, 0.0, 1.52),
        );
        let p = parts(&t).unwrap();
        assert!(p.exact);
        assert_eq!(Transform::from_parts(p.scale, p.rotation, p.translation), t);
        let t = Transform::from_parts(DVec3::new(0.5, -1.0, 1.5), DVec3::new(10.0, 20.0, 30.0), DVec3::ONE);
        let p = parts(&t).unwrap();
        assert!(p.exact, "{p:?}");
        assert_eq!(Transform::from_parts(p.scale, p.rotation, p.translation), t);
        // A shear is no rotation times a scaling.
        let shear = Transform::from_rows([[1.0, 0.5, 0.0, 3.0], [0.0, 1.0, 0.0, -3.0], [0.0, 0.0, 2.0, 1.0]]).unwrap();
        assert_eq!(parts(&shear), None);
        let b = Cuboid::new(
            DVec3::new(0.0, 0.0, 1.52),
            DVec3::new(1.6, 1.0, 3.0),
            DVec3::new(0.0, 0.0, 35.0),
        );
        assert_eq!(box_rotation(&b), (DVec3::new(0.0, 0.0, 35.0), true));
        let b = Cuboid::new(
            DVec3::new(0.0, 0.0, 3.0),
            DVec3::splat(2.0),
            DVec3::new(10.0, 20.0, 30.0),
        );
        assert_eq!(box_rotation(&b), (DVec3::new(10.0, 20.0, 30.0), true));
        let b = Cuboid::new(DVec3::ONE, DVec3::new(1.0, 2.0, 3.0), DVec3::ZERO);
        assert_eq!(box_rotation(&b), (DVec3::ZERO, true));
    }
}
