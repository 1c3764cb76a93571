//! The stress campaign's shapes and their high-precision references. Every shape is built
//! axis-aligned (axis +z, box unrotated, cone height a power-of-two multiple of its radius)
//! so that the f64 shape and the exact shape are the same set: the campaign then measures
//! the root finders and ray set-up, not the rounding of a rotation matrix.
//!
//! Each reference is the shape's own geometric construction evaluated in double-double
//! ([`Dd`]), independent of the f64 code: quadrics by their quadratic with a double-double
//! discriminant, flat shapes by their plane equation, the box by its slabs, and the torus
//! by root bracketing (derivative recursion) and plain bisection on its implicit equation
//! `(|p|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + y^2)` evaluated in double-double. A triangle is
//! its plane and three edge tests (its vertices are f64, so the set is exact); the
//! ellipsoid is the unit sphere through the f64 shape's own map: the reference carries the
//! ray to the local frame with the map's stored inverse, in double-double and without
//! normalising the direction, so both sides intersect the same set and `t` is the same
//! parameter.

use super::dd::{Dd, Dd3};
use crate::shape::{
    Cone, Cuboid, Cylinder, Disk, Lens, Plane, Rectangle, Shape, Sphere, SphericalCap, Torus, Transform, Triangle,
};
use glam::DVec3;

/// A campaign shape, axis-aligned, with its exact parameters.
#[derive(Clone, Copy, Debug)]
pub enum Spec {
    Sphere {
        c: DVec3,
        r: f64,
    },
    Box {
        c: DVec3,
        half: DVec3,
    },
    Cylinder {
        base: DVec3,
        h: f64,
        r: f64,
    },
    /// `h / r` is a power of two so `k = r / h` and `k^2` are exact.
    Cone {
        base: DVec3,
        h: f64,
        r: f64,
    },
    Torus {
        c: DVec3,
        big: f64,
        small: f64,
    },
    Disk {
        c: DVec3,
        r: f64,
    },
    /// Edges `(a, 0, 0)` and `(0, b, 0)`: the unit normal is exactly +z.
    Rect {
        corner: DVec3,
        a: f64,
        b: f64,
    },
    Plane {
        p: DVec3,
    },
    /// Vertices in winding order.
    Triangle {
        p: [DVec3; 3],
    },
    /// The cylinder's side without caps.
    Tube {
        base: DVec3,
        h: f64,
        r: f64,
    },
    /// The unit sphere through `transform` (scale, rotation, translation).
    Ellipsoid {
        transform: Transform,
    },
    /// A spherical cap over the disk of center `c`, normal +z, radius `r`, signed curvature
    /// `curvature`; `sphere` is the f64 shape's own sphere center (so both sides have the
    /// same sphere).
    Cap {
        c: DVec3,
        r: f64,
        curvature: f64,
        sphere: DVec3,
    },
    /// A lens from `base` along +z: edge `e`, radius `r`, curvatures; `spheres` the f64
    /// shape's own caps' sphere centers.
    Lens {
        base: DVec3,
        e: f64,
        r: f64,
        curvatures: [f64; 2],
        spheres: [DVec3; 2],
    },
}

impl Spec {
    /// The cap over the disk (`c`, +z, `r`) with its sphere as the f64 shape computes it.
    pub fn cap(c: DVec3, r: f64, curvature: f64) -> Spec {
        let sphere = SphericalCap::new(c, DVec3::Z, r, curvature).sphere().0;
        Spec::Cap {
            c,
            r,
            curvature,
            sphere,
        }
    }

    /// The lens from `base` along +z with its spheres as the f64 shape computes them.
    pub fn lens(base: DVec3, e: f64, r: f64, curvatures: [f64; 2]) -> Spec {
        let l = Lens::new(base, DVec3::Z, e, r, curvatures[0], curvatures[1]);
        let [(s1, _), (s2, _)] = l.cap_spheres();
        Spec::Lens {
            base,
            e,
            r,
            curvatures,
            spheres: [s1, s2],
        }
    }
}

fn dd(x: f64) -> Dd {
    Dd::new(x)
}

impl Spec {
    /// The f64 shape under test.
    pub fn shape(&self) -> Shape {
        match *self {
            Spec::Sphere { c, r } => Shape::Sphere(Sphere::new(c, r)),
            Spec::Box { c, half } => Shape::Cuboid(Box::new(Cuboid::new(c, half * 2.0, DVec3::ZERO))),
            Spec::Cylinder { base, h, r } => Shape::Cylinder(Box::new(Cylinder::new(base, DVec3::Z, h, r))),
            Spec::Cone { base, h, r } => Shape::Cone(Box::new(Cone::new(base, DVec3::Z, h, r))),
            Spec::Torus { c, big, small } => Shape::Torus(Box::new(Torus::new(c, DVec3::Z, big, small))),
            Spec::Disk { c, r } => Shape::Disk(Box::new(Disk::new(c, DVec3::Z, r))),
            Spec::Rect { corner, a, b } => Shape::Rectangle(Box::new(Rectangle::new(
                corner,
                DVec3::new(a, 0.0, 0.0),
                DVec3::new(0.0, b, 0.0),
            ))),
            Spec::Plane { p } => Shape::Plane(Box::new(Plane::new(p, DVec3::Z))),
            Spec::Triangle { p } => Shape::Triangle(Triangle::new(p[0], p[1], p[2])),
            Spec::Tube { base, h, r } => Shape::Cylinder(Box::new(Cylinder::tube(base, DVec3::Z, h, r))),
            Spec::Ellipsoid { transform } => transform.apply(Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0))),
            Spec::Cap { c, r, curvature, .. } => {
                Shape::SphericalCap(Box::new(SphericalCap::new(c, DVec3::Z, r, curvature)))
            }
            Spec::Lens {
                base, e, r, curvatures, ..
            } => Shape::Lens(Box::new(Lens::new(base, DVec3::Z, e, r, curvatures[0], curvatures[1]))),
        }
    }

    /// A point near the middle of the shape.
    pub fn center(&self) -> DVec3 {
        match *self {
            Spec::Sphere { c, .. } | Spec::Box { c, .. } | Spec::Torus { c, .. } | Spec::Disk { c, .. } => c,
            Spec::Cylinder { base, h, .. } | Spec::Cone { base, h, .. } | Spec::Tube { base, h, .. } => {
                base + DVec3::Z * (0.5 * h)
            }
            Spec::Rect { corner, a, b } => corner + DVec3::new(0.5 * a, 0.5 * b, 0.0),
            Spec::Plane { p } => p,
            Spec::Triangle { p } => (p[0] + p[1] + p[2]) / 3.0,
            Spec::Ellipsoid { transform } => transform.to_world.translation,
            Spec::Cap { .. } | Spec::Lens { .. } => self.shape().bounding_sphere().map_or(DVec3::ZERO, |b| b.0),
        }
    }

    /// Radius of a ball around [`Spec::center`] holding the shape (1 for the plane's
    /// region of interest).
    pub fn size(&self) -> f64 {
        match *self {
            Spec::Sphere { r, .. } | Spec::Disk { r, .. } => r,
            Spec::Box { half, .. } => half.length(),
            Spec::Cylinder { h, r, .. } | Spec::Cone { h, r, .. } | Spec::Tube { h, r, .. } => {
                (0.25 * h * h + r * r).sqrt()
            }
            Spec::Torus { big, small, .. } => big + small,
            Spec::Rect { a, b, .. } => 0.5 * (a * a + b * b).sqrt(),
            Spec::Plane { .. } => 1.0,
            Spec::Triangle { p } => {
                let c = self.center();
                p.iter().map(|v| (*v - c).length()).fold(0.0, f64::max)
            }
            Spec::Ellipsoid { transform } => transform.stretch,
            Spec::Cap { .. } | Spec::Lens { .. } => self.shape().bounding_sphere().map_or(1.0, |b| b.1),
        }
    }

    /// First exact hit with `t > t_min`, for the ray `o + t d` given in double-double.
    pub fn reference(&self, o: Dd3, d: Dd3, t_min: Dd) -> Option<Dd> {
        let first = |ts: &mut Vec<Dd>| {
            ts.retain(|t| *t > t_min && t.is_finite());
            ts.iter().copied().reduce(Dd::min)
        };
        match *self {
            Spec::Sphere { c, r } => {
                let f = o - Dd3::from_f64(c);
                let mut ts = quadratic_dd(d.dot(d), f.dot(d), f.dot(f) - dd(r).sqr());
                first(&mut ts)
            }
            Spec::Plane { p } => plane_t(o, d, dd(p.z)).filter(|t| *t > t_min),
            Spec::Disk { c, r } => {
                let t = plane_t(o, d, dd(c.z))?;
                let q = o.along(d, t);
                let (x, y) = (q.x - dd(c.x), q.y - dd(c.y));
                (t > t_min && x.sqr() + y.sqr() <= dd(r).sqr()).then_some(t)
            }
            Spec::Rect { corner, a, b } => {
                let t = plane_t(o, d, dd(corner.z))?;
                let q = o.along(d, t);
                let (u, v) = (q.x - dd(corner.x), q.y - dd(corner.y));
                let inside = u >= Dd::ZERO && u <= dd(a) && v >= Dd::ZERO && v <= dd(b);
                (t > t_min && inside).then_some(t)
            }
            Spec::Box { c, half } => {
                let l = o - Dd3::from_f64(c);
                let (mut near, mut far) = (dd(f64::NEG_INFINITY), dd(f64::INFINITY));
                for (oi, di, hi) in [(l.x, d.x, half.x), (l.y, d.y, half.y), (l.z, d.z, half.z)] {
                    if di.hi == 0.0 {
                        if oi < dd(-hi) || oi > dd(hi) {
                            return None;
                        }
                        continue;
                    }
                    let t0 = (dd(-hi) - oi) / di;
                    let t1 = (dd(hi) - oi) / di;
                    near = near.max(t0.min(t1));
                    far = far.min(t0.max(t1));
                }
                if near > far { None } else { first(&mut vec![near, far]) }
            }
            Spec::Cylinder { base, h, r } => {
                let l = o - Dd3::from_f64(base);
                let mut ts = Vec::new();
                let a = d.x.sqr() + d.y.sqr();
                if a.hi > 0.0 {
                    let cands = quadratic_dd(a, l.x * d.x + l.y * d.y, l.x.sqr() + l.y.sqr() - dd(r).sqr());
                    ts.extend(cands.into_iter().filter(|t| within(l.z + d.z * *t, h)));
                }
                caps(l, d, &[0.0, h], r, &mut ts);
                first(&mut ts)
            }
            Spec::Cone { base, h, r } => {
                let l = o - Dd3::from_f64(base);
                let k2 = dd(r / h).sqr();
                let w = dd(h) - l.z;
                let a = d.x.sqr() + d.y.sqr() - k2 * d.z.sqr();
                let half_b = l.x * d.x + l.y * d.y + k2 * w * d.z;
                let c = l.x.sqr() + l.y.sqr() - k2 * w.sqr();
                let cands = if a.hi == 0.0 {
                    if half_b.hi == 0.0 {
                        vec![]
                    } else {
                        vec![-c / (dd(2.0) * half_b)]
                    }
                } else {
                    quadratic_dd(a, half_b, c)
                };
                let mut ts: Vec<Dd> = cands.into_iter().filter(|t| within(l.z + d.z * *t, h)).collect();
                caps(l, d, &[0.0], r, &mut ts);
                first(&mut ts)
            }
            Spec::Torus { c, big, small } => torus_reference(o - Dd3::from_f64(c), d, big, small, t_min),
            Spec::Triangle { p } => triangle_reference(p, o, d).filter(|t| *t > t_min),
            Spec::Tube { base, h, r } => {
                let l = o - Dd3::from_f64(base);
                let a = d.x.sqr() + d.y.sqr();
                if a.hi == 0.0 {
                    return None;
                }
                let cands = quadratic_dd(a, l.x * d.x + l.y * d.y, l.x.sqr() + l.y.sqr() - dd(r).sqr());
                first(&mut cands.into_iter().filter(|t| within(l.z + d.z * *t, h)).collect())
            }
            Spec::Ellipsoid { transform } => {
                // The local ray `M (o - b) + t M d`, its direction not normalised.
                let m = transform.to_local;
                let row = |i: usize, v: Dd3| {
                    Dd::new(m.x_axis[i]) * v.x + Dd::new(m.y_axis[i]) * v.y + Dd::new(m.z_axis[i]) * v.z
                };
                let f = o - Dd3::from_f64(transform.to_world.translation);
                let (lo, ld) = (
                    Dd3::new(row(0, f), row(1, f), row(2, f)),
                    Dd3::new(row(0, d), row(1, d), row(2, d)),
                );
                first(&mut quadratic_dd(ld.dot(ld), lo.dot(ld), lo.dot(lo) - Dd::new(1.0)))
            }
            Spec::Cap {
                c, curvature, sphere, ..
            } => {
                // The sphere's roots whose points are on the bulge's side of the disk's plane.
                let mut ts = sphere_roots_dd(o, d, sphere, curvature);
                ts.retain(|t| (o.along(d, *t).z - dd(c.z)) * dd(curvature.signum()) >= Dd::ZERO);
                first(&mut ts)
            }
            Spec::Lens {
                base,
                e,
                r,
                curvatures,
                spheres,
            } => {
                let l = o - Dd3::from_f64(base);
                let mut ts = Vec::new();
                // The edge: the tube's side for 0 <= z <= e.
                let a = d.x.sqr() + d.y.sqr();
                if e > 0.0 && a.hi > 0.0 {
                    let cands = quadratic_dd(a, l.x * d.x + l.y * d.y, l.x.sqr() + l.y.sqr() - dd(r).sqr());
                    ts.extend(cands.into_iter().filter(|t| within(l.z + d.z * *t, e)));
                }
                // Cap 1 below z = 0 (convex) or above it (concave); cap 2 beyond z = e or short of it.
                for (i, plane) in [(0, 0.0), (1, e)] {
                    let outward = if i == 0 { -1.0 } else { 1.0 } * curvatures[i].signum();
                    let roots = sphere_roots_dd(o, d, spheres[i], curvatures[i]);
                    ts.extend(
                        roots
                            .into_iter()
                            .filter(|t| (l.z + d.z * *t - dd(plane)) * dd(outward) >= Dd::ZERO),
                    );
                }
                first(&mut ts)
            }
        }
    }
}

/// The roots of the sphere of center `c` and radius `|curvature|` met by `o + t d`.
fn sphere_roots_dd(o: Dd3, d: Dd3, c: DVec3, curvature: f64) -> Vec<Dd> {
    let f = o - Dd3::from_f64(c);
    quadratic_dd(d.dot(d), f.dot(d), f.dot(f) - dd(curvature.abs()).sqr())
}

/// The plane of `p` met by `o + t d`, kept when the point is inside every edge (on an edge
/// counts), in double-double: the edge tests `((b - a) x (q - a)).n >= 0` with the normal
/// `n = (p1 - p0) x (p2 - p0)`.
fn triangle_reference(p: [DVec3; 3], o: Dd3, d: Dd3) -> Option<Dd> {
    let v = p.map(Dd3::from_f64);
    let n = (v[1] - v[0]).cross(v[2] - v[0]);
    let denom = n.dot(d);
    if denom.hi == 0.0 {
        return None;
    }
    let t = n.dot(v[0] - o) / denom;
    let q = o.along(d, t);
    let inside = (0..3).all(|k| {
        let (a, b) = (v[k], v[(k + 1) % 3]);
        (b - a).cross(q - a).dot(n) >= Dd::ZERO
    });
    inside.then_some(t)
}

/// `0 <= z <= h`.
fn within(z: Dd, h: f64) -> bool {
    z >= Dd::ZERO && z <= dd(h)
}

/// Hits of the caps `z = h_i` (local frame) within radius `r`.
fn caps(l: Dd3, d: Dd3, heights: &[f64], r: f64, ts: &mut Vec<Dd>) {
    if d.z.hi == 0.0 {
        return;
    }
    for &h in heights {
        let t = (dd(h) - l.z) / d.z;
        let q = l.along(d, t);
        if q.x.sqr() + q.y.sqr() <= dd(r).sqr() {
            ts.push(t);
        }
    }
}

/// Parameter where the ray meets the plane `z = h`, if it is not parallel.
fn plane_t(o: Dd3, d: Dd3, h: Dd) -> Option<Dd> {
    (d.z.hi != 0.0).then(|| (h - o.z) / d.z)
}

/// Real roots of `a t^2 + 2 b t + c` in double-double (the stable form, `q = -(b + sign(b) sqrt(disc))`).
fn quadratic_dd(a: Dd, b: Dd, c: Dd) -> Vec<Dd> {
    let disc = b.sqr() - a * c;
    if disc.hi < 0.0 {
        return vec![];
    }
    let q = -(b + disc.sqrt() * dd(if b.hi < 0.0 { -1.0 } else { 1.0 }));
    if q.hi == 0.0 {
        return vec![Dd::ZERO];
    }
    vec![q / a, c / q]
}

/// Torus reference in its local frame (`o` relative to the center): clip to the bounding
/// sphere, shift the origin there, bracket the roots of the quartic by the critical points
/// of its derivatives, and bisect each bracket on the implicit equation.
fn torus_reference(o: Dd3, d: Dd3, big: f64, small: f64, t_min: Dd) -> Option<Dd> {
    let bound = big + small;
    // The clip interval only needs to contain the roots: f64 with a generous pad.
    let (of, df) = (o.to_f64(), d.to_f64());
    let a = df.length_squared();
    let tc = -of.dot(df) / a;
    let perp2 = (of + df * tc).length_squared();
    let pad = 1e-6 * bound;
    let disc = (bound + pad) * (bound + pad) - perp2;
    if disc < 0.0 {
        return None;
    }
    let half = (disc / a).sqrt();
    let lo = (tc - half - pad).max(t_min.to_f64() - pad);
    let hi = tc + half + pad;
    if hi < lo {
        return None;
    }
    // p(s) = o' + s d with o' = o + lo d, exactly in double-double.
    let o2 = o.along(d, dd(lo));
    let (r2, s2) = (dd(big).sqr(), dd(small).sqr());
    let k = o2.dot(o2) + r2 - s2;
    let n = o2.dot(d);
    let m = d.dot(d);
    let four_r2 = dd(4.0) * r2;
    let coeffs = [
        k.sqr() - four_r2 * (o2.x.sqr() + o2.y.sqr()),
        dd(4.0) * n * k - dd(2.0) * four_r2 * (o2.x * d.x + o2.y * d.y),
        dd(4.0) * n.sqr() + dd(2.0) * m * k - four_r2 * (d.x.sqr() + d.y.sqr()),
        dd(4.0) * m * n,
        m.sqr(),
    ];
    let implicit = |s: Dd| {
        let p = o2.along(d, s);
        let q = p.dot(p) + r2 - s2;
        q.sqr() - four_r2 * (p.x.sqr() + p.y.sqr())
    };
    let mut roots = Vec::new();
    bisect_roots(&coeffs, Dd::ZERO, dd(hi - lo), &implicit, &mut roots);
    roots
        .into_iter()
        .map(|s| dd(lo) + s)
        .filter(|t| *t > t_min)
        .reduce(Dd::min)
}

fn horner_dd(c: &[Dd], t: Dd) -> Dd {
    c.iter().rev().fold(Dd::ZERO, |acc, &ci| acc * t + ci)
}

/// Roots in `[lo, hi]` of the polynomial `c` (increasing degree): its derivative's roots
/// split the interval into monotone pieces, each piece with a sign change is bisected on
/// `f` until the bracket is below 2^-100 of its position.
fn bisect_roots(c: &[Dd], lo: Dd, hi: Dd, f: &dyn Fn(Dd) -> Dd, out: &mut Vec<Dd>) {
    let degree = c.len() - 1;
    if degree == 0 {
        return;
    }
    let mut splits = vec![lo];
    if degree >= 2 {
        let deriv: Vec<Dd> = c.iter().enumerate().skip(1).map(|(i, &ci)| ci * dd(i as f64)).collect();
        let mut crit = Vec::new();
        bisect_roots(&deriv, lo, hi, &|t| horner_dd(&deriv, t), &mut crit);
        splits.extend(crit.into_iter().filter(|t| *t > lo && *t < hi));
    }
    splits.push(hi);
    for w in splits.windows(2) {
        let (mut a, mut b) = (w[0], w[1]);
        let (fa, fb) = (f(a), f(b));
        if fa.hi == 0.0 {
            out.push(a);
            continue;
        }
        if fa.signum() == fb.signum() || fb.hi == 0.0 {
            continue;
        }
        let neg_a = fa.hi < 0.0;
        for _ in 0..200 {
            let mid = (a + b) * dd(0.5);
            let width = (b - a).to_f64();
            if width <= 1e-30 * mid.to_f64().abs().max(1e-300) {
                break;
            }
            let fm = f(mid);
            if fm.hi == 0.0 {
                a = mid;
                b = mid;
                break;
            }
            if (fm.hi < 0.0) == neg_a {
                a = mid;
            } else {
                b = mid;
            }
        }
        out.push((a + b) * dd(0.5));
    }
    if f(hi).hi == 0.0 {
        out.push(hi);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray_dd(o: [f64; 3], d: [f64; 3]) -> (Dd3, Dd3) {
        (Dd3::from_f64(DVec3::from(o)), Dd3::from_f64(DVec3::from(d)))
    }

    #[test]
    fn references_on_hand_computed_rays() {
        // Sphere r = 1 at the origin from z = 10 down: t = 9.
        let (o, d) = ray_dd([0., 0., 10.], [0., 0., -1.]);
        let s = Spec::Sphere { c: DVec3::ZERO, r: 1.0 };
        assert_eq!(s.reference(o, d, Dd::ZERO).unwrap().to_f64(), 9.0);
        // Torus R = 1.5, r = 0.5 from x = -5 along +x: walls at x = -2, -1, 1, 2 (t = 3, 4, 6, 7).
        let (o, d) = ray_dd([-5., 0., 0.], [1., 0., 0.]);
        let t = Spec::Torus {
            c: DVec3::ZERO,
            big: 1.5,
            small: 0.5,
        };
        for (t_min, want) in [(0.0, 3.0), (3.5, 4.0), (4.5, 6.0), (6.5, 7.0)] {
            let got = t.reference(o, d, dd(t_min)).unwrap();
            assert!((got - dd(want)).abs().to_f64() < 1e-28, "{got:?} vs {want}");
        }
        // Down the torus axis: through the hole, no hit.
        let (o, d) = ray_dd([0., 0., 5.], [0., 0., -1.]);
        assert!(t.reference(o, d, Dd::ZERO).is_none());
        // Cone base (0,0,0), h = 2, r = 1 (k = 1/2): horizontal ray at z = 1 meets the side
        // at radius 0.5, from x = -5: t = 4.5.
        let c = Spec::Cone {
            base: DVec3::ZERO,
            h: 2.0,
            r: 1.0,
        };
        let (o, d) = ray_dd([-5., 0., 1.], [1., 0., 0.]);
        assert_eq!(c.reference(o, d, Dd::ZERO).unwrap().to_f64(), 4.5);
        // Box half (1, 2, 3) from inside at the center along +y: exit at t = 2.
        let b = Spec::Box {
            c: DVec3::ZERO,
            half: DVec3::new(1., 2., 3.),
        };
        let (o, d) = ray_dd([0., 0., 0.], [0., 1., 0.]);
        assert_eq!(b.reference(o, d, Dd::ZERO).unwrap().to_f64(), 2.0);
        // Triangle (0,0,1) (2,0,1) (0,2,1) from (0.5, 0.5, 4) down: t = 3; through the
        // hypotenuse's midpoint (1, 1) too (an edge counts); beyond it at (1.1, 1), none.
        let tri = Spec::Triangle {
            p: [DVec3::new(0., 0., 1.), DVec3::new(2., 0., 1.), DVec3::new(0., 2., 1.)],
        };
        for (x, y, want) in [(0.5, 0.5, Some(3.0)), (1.0, 1.0, Some(3.0)), (1.1, 1.0, None)] {
            let (o, d) = ray_dd([x, y, 4.], [0., 0., -1.]);
            assert_eq!(tri.reference(o, d, Dd::ZERO).map(Dd::to_f64), want, "({x}, {y})");
        }
        // Tube r = 1, h = 3 at the origin: down its axis, nothing; from the axis along +x,
        // the inner wall at t = 1.
        let tube = Spec::Tube {
            base: DVec3::ZERO,
            h: 3.0,
            r: 1.0,
        };
        let (o, d) = ray_dd([0., 0., 5.], [0., 0., -1.]);
        assert!(tube.reference(o, d, Dd::ZERO).is_none());
        let (o, d) = ray_dd([0., 0., 1.], [1., 0., 0.]);
        assert_eq!(tube.reference(o, d, Dd::ZERO).unwrap().to_f64(), 1.0);
        // The unit sphere scaled by (2, 1, 0.5): from x = 10 along -x, the tip x = 2 at t = 8,
        // then x = -2 at t = 12.
        let e = Spec::Ellipsoid {
            transform: Transform::from_parts(DVec3::new(2., 1., 0.5), DVec3::ZERO, DVec3::ZERO),
        };
        let (o, d) = ray_dd([10., 0., 0.], [-1., 0., 0.]);
        assert_eq!(e.reference(o, d, Dd::ZERO).unwrap().to_f64(), 8.0);
        assert_eq!(e.reference(o, d, dd(9.0)).unwrap().to_f64(), 12.0);
    }
}
