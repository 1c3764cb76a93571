//! `lumiere stress`: a seeded campaign that fires families of hard rays at every shape and
//! compares each f64 hit with a double-double reference ([`reference`](mod@reference)).
//! For each shape and ray family it counts the rays, the hits the reference has, missed
//! hits, false hits, disagreements inside the grazing band, non-finite results, and the
//! median and maximum relative error of `t`.
//!
//! **Grazing band.** A ray is in the band when moving its origin sideways by
//! `delta = max(1e-9 x object size, 16 ulp of the coordinates)` (eight directions
//! perpendicular to the ray) changes the exact answer: hit to miss, or `t` by more than the
//! f64 result is off. No f64 code can be expected to decide those rays, so disagreements
//! there are counted apart (`band`); every other disagreement is a missed or a false hit.
//! A hit whose relative error exceeds 1e-6 and is not explained by the band counts as false.
//!
//! The triangle, the open tube, the ellipsoid (the unit sphere through a random scale,
//! rotation and translation: the instance transform), the spherical cap (convex or
//! concave) and the lens (caps of either sign, with or without an edge) meet the same four
//! families as every shape.

pub mod dd;
pub mod reference;

use crate::math::{Frame, Ray};
use crate::sampling::{Purpose, Stream};
use crate::shape::{Lens, QuarticMethod, Shape, Transform};
use dd::{Dd, Dd3};
use glam::DVec3;
use reference::Spec;

/// The shapes, in table order (a shape's place keys its random streams: new ones go last).
pub const SHAPES: [&str; 13] = [
    "sphere",
    "box",
    "cylinder",
    "cone",
    "torus",
    "disk",
    "rectangle",
    "plane",
    "triangle",
    "tube",
    "ellipsoid",
    "spherical_cap",
    "lens",
];

/// A family of rays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// Origins around the object, aimed at points near it.
    Random,
    /// Within 1e-9 (relative) of the silhouette: tangent to curved surfaces, along edges.
    Grazing,
    /// Origins 1e3 to 1e7 away.
    Far,
    /// Objects of size 1e-3 to 1e3, rays as in `Random`.
    Scale,
    /// Torus only: rays parallel to the axis.
    TorusAxis,
    /// Torus only: rays in (half) or within 1e-12 to 1e-4 rad of (half) the equatorial
    /// plane, from 1e1 to 1e6 sizes away.
    TorusEquator,
    /// Torus only: origins on the surface of a large torus (R = 1e2 to 1e3), leaving it.
    TorusOnSurface,
}

impl Family {
    pub const ALL: [Family; 7] = [
        Family::Random,
        Family::Grazing,
        Family::Far,
        Family::Scale,
        Family::TorusAxis,
        Family::TorusEquator,
        Family::TorusOnSurface,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Family::Random => "random",
            Family::Grazing => "grazing",
            Family::Far => "far",
            Family::Scale => "scale",
            Family::TorusAxis => "torus-axis",
            Family::TorusEquator => "torus-equator",
            Family::TorusOnSurface => "torus-on-surface",
        }
    }

    fn torus_only(self) -> bool {
        matches!(self, Family::TorusAxis | Family::TorusEquator | Family::TorusOnSurface)
    }
}

/// One line of the table.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Row {
    pub shape: &'static str,
    pub family: &'static str,
    pub rays: usize,
    /// Rays the reference says hit.
    pub reference_hits: usize,
    pub missed: usize,
    pub false_hits: usize,
    /// Disagreements inside the grazing band.
    pub band: usize,
    pub non_finite: usize,
    pub median_rel_error: f64,
    pub max_rel_error: f64,
}

/// A random source for the campaign.
struct Gen(Stream);

impl Gen {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.0.next_f64()
    }

    /// `10^u` with `u` uniform in `[lo, hi]`.
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        libm::pow(10.0, self.uniform(lo, hi))
    }

    fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.uniform(-1., 1.), self.uniform(-1., 1.), self.uniform(-1., 1.));
            let l = v.length_squared();
            if l > 1e-6 && l <= 1.0 {
                return v / l.sqrt();
            }
        }
    }

    fn in_ball(&mut self) -> DVec3 {
        self.unit() * libm::cbrt(self.0.next_f64())
    }

    /// A unit vector perpendicular to the unit `n`.
    fn perpendicular(&mut self, n: DVec3) -> DVec3 {
        let f = Frame::from_z(n);
        let a = self.uniform(0.0, std::f64::consts::TAU);
        f.to_world(DVec3::new(libm::cos(a), libm::sin(a), 0.0))
    }
}

/// A random shape of kind `shape` with size about `s`, centerd within `spread` of the origin.
fn random_spec(shape: &str, s: f64, spread: f64, g: &mut Gen) -> Spec {
    let c = DVec3::new(g.uniform(-1., 1.), g.uniform(-1., 1.), g.uniform(-1., 1.)) * spread;
    match shape {
        "sphere" => Spec::Sphere {
            c,
            r: s * g.uniform(0.5, 2.0),
        },
        "box" => Spec::Box {
            c,
            half: DVec3::new(g.uniform(0.25, 1.5), g.uniform(0.25, 1.5), g.uniform(0.25, 1.5)) * s,
        },
        "cylinder" => Spec::Cylinder {
            base: c,
            h: s * g.uniform(0.5, 3.0),
            r: s * g.uniform(0.5, 1.5),
        },
        "cone" => {
            let r = s * g.uniform(0.5, 1.5);
            let h = r * [0.5, 1.0, 2.0][(g.0.next_f64() * 3.0) as usize];
            Spec::Cone { base: c, h, r }
        }
        "torus" => {
            let big = s * g.uniform(1.0, 2.0);
            Spec::Torus {
                c,
                big,
                small: big * g.uniform(0.1, 0.6),
            }
        }
        "disk" => Spec::Disk {
            c,
            r: s * g.uniform(0.5, 2.0),
        },
        "rectangle" => Spec::Rect {
            corner: c,
            a: s * g.uniform(0.5, 3.0),
            b: s * g.uniform(0.5, 3.0),
        },
        "triangle" => {
            // Three points in random directions from the center, 0.5 to 1.5 sizes away.
            let mut corner = || c + g.unit() * (s * g.uniform(0.5, 1.5));
            Spec::Triangle {
                p: [corner(), corner(), corner()],
            }
        }
        "tube" => Spec::Tube {
            base: c,
            h: s * g.uniform(0.5, 3.0),
            r: s * g.uniform(0.5, 1.5),
        },
        "ellipsoid" => {
            let scale = DVec3::new(g.uniform(0.3, 2.0), g.uniform(0.3, 2.0), g.uniform(0.3, 2.0)) * s;
            let rotation = DVec3::new(g.uniform(-180., 180.), g.uniform(-180., 180.), g.uniform(-180., 180.));
            Spec::Ellipsoid {
                transform: Transform::from_parts(scale, rotation, c),
            }
        }
        "spherical_cap" => {
            let r = s * g.uniform(0.5, 1.5);
            let sign = if g.0.next_f64() < 0.5 { -1.0 } else { 1.0 };
            Spec::cap(c, r, sign * r * g.uniform(1.0, 3.0))
        }
        "lens" => {
            let r = s * g.uniform(0.5, 1.5);
            let mut curvature = || {
                let sign = if g.0.next_f64() < 0.3 { -1.0 } else { 1.0 };
                sign * r * g.uniform(1.0, 3.0)
            };
            let curvatures = [curvature(), curvature()];
            // The concave caps' depths, then an edge of up to 1.5 sizes beyond them; a
            // quarter of the biconvex lenses have none.
            let hollow = |c: f64| Lens::hollow(r, c);
            let convex = curvatures[0] > 0.0 && curvatures[1] > 0.0;
            let e = if convex && g.0.next_f64() < 0.25 {
                0.0
            } else {
                hollow(curvatures[0]) + hollow(curvatures[1]) + s * g.uniform(0.05, 1.5)
            };
            Spec::lens(c, e, r, curvatures)
        }
        _ => Spec::Plane { p: c },
    }
}

/// A point on the shape's silhouette or edges and, for smooth surfaces, the normal there
/// (grazing rays are then tangent to the surface; otherwise they pass an edge or a rim).
fn silhouette_point(spec: &Spec, g: &mut Gen) -> (DVec3, Option<DVec3>) {
    let angle = g.uniform(0.0, std::f64::consts::TAU);
    let radial = DVec3::new(libm::cos(angle), libm::sin(angle), 0.0);
    let rim_or_side = g.0.next_f64() < 0.5;
    match *spec {
        Spec::Sphere { c, r } => {
            let n = g.unit();
            (c + n * r, Some(n))
        }
        Spec::Torus { c, big, small } => {
            let phi = g.uniform(0.0, std::f64::consts::TAU);
            let n = radial * libm::cos(phi) + DVec3::Z * libm::sin(phi);
            (c + radial * big + n * small, Some(n))
        }
        Spec::Cylinder { base, h, r } => {
            if rim_or_side {
                (base + radial * r + DVec3::Z * g.uniform(0.0, h), Some(radial))
            } else {
                (
                    base + radial * r + DVec3::Z * if g.0.next_f64() < 0.5 { 0.0 } else { h },
                    None,
                )
            }
        }
        Spec::Cone { base, h, r } => {
            if rim_or_side {
                // Along a generatrix; normal (x, y, k^2 (h - z)) normalised, k = r / h.
                let z = g.uniform(0.0, h);
                let k = r / h;
                let n = (radial + DVec3::Z * k).normalize();
                (base + radial * (k * (h - z)) + DVec3::Z * z, Some(n))
            } else {
                (base + radial * r, None)
            }
        }
        Spec::Disk { c, r } => (c + radial * r, None),
        Spec::Rect { corner, a, b } => {
            let u = g.0.next_f64();
            let edge = match (g.0.next_f64() * 4.0) as u32 {
                0 => DVec3::new(u * a, 0.0, 0.0),
                1 => DVec3::new(u * a, b, 0.0),
                2 => DVec3::new(0.0, u * b, 0.0),
                _ => DVec3::new(a, u * b, 0.0),
            };
            (corner + edge, None)
        }
        Spec::Box { c, half } => {
            // A point on a random edge: two coordinates at +-half, the third free.
            let free = (g.0.next_f64() * 3.0) as usize;
            let mut p = DVec3::ZERO;
            for i in 0..3 {
                p[i] = if i == free {
                    g.uniform(-half[i], half[i])
                } else if g.0.next_f64() < 0.5 {
                    -half[i]
                } else {
                    half[i]
                };
            }
            (c + p, None)
        }
        Spec::Plane { p } => (p, Some(DVec3::Z)),
        Spec::Triangle { p } => {
            let k = (g.0.next_f64() * 3.0) as usize % 3;
            (p[k] + (p[(k + 1) % 3] - p[k]) * g.0.next_f64(), None)
        }
        Spec::Tube { base, h, r } => {
            if rim_or_side {
                (base + radial * r + DVec3::Z * g.uniform(0.0, h), Some(radial))
            } else {
                let z = if g.0.next_f64() < 0.5 { 0.0 } else { h };
                (base + radial * r + DVec3::Z * z, None)
            }
        }
        Spec::Cap {
            c,
            r,
            curvature,
            sphere,
        } => {
            if rim_or_side {
                // A point of the cap, tangent rays: the sphere's normal there.
                let bulge = DVec3::Z * curvature.signum();
                let theta = g.uniform(0.0, libm::asin(r / curvature.abs()));
                let n = radial * libm::sin(theta) + bulge * libm::cos(theta);
                (sphere + n * curvature.abs(), Some(n))
            } else {
                (c + radial * r, None)
            }
        }
        Spec::Lens { base, e, r, .. } => {
            if rim_or_side && e > 0.0 {
                (base + radial * r + DVec3::Z * g.uniform(0.0, e), Some(radial))
            } else {
                let z = if g.0.next_f64() < 0.5 { 0.0 } else { e };
                (base + radial * r + DVec3::Z * z, None)
            }
        }
        Spec::Ellipsoid { transform } => {
            // The image of a point of the unit sphere, and the normal there (the local one
            // through the inverse transpose).
            let n = g.unit();
            (
                transform.point(n),
                Some((transform.to_local.transpose() * n).normalize()),
            )
        }
    }
}

/// One ray of `family` for the shape; returns the shape, the ray and the `t_min` to use.
fn make_case(shape: &str, family: Family, g: &mut Gen) -> (Spec, Ray, f64) {
    let s = match family {
        Family::Scale => g.log_uniform(-3.0, 3.0),
        Family::TorusOnSurface => g.log_uniform(2.0, 3.0),
        _ => g.uniform(0.5, 2.0),
    };
    let spec = random_spec(shape, s, 5.0 * s, g);
    let (c, size) = (spec.center(), spec.size());
    let aim = |g: &mut Gen, o: DVec3| {
        let target = match spec {
            // A flat triangle fills little of its ball: aim at its plane, within the
            // triangle grown by 1.3 about its centroid (a third of the aims miss it).
            Spec::Triangle { p } => {
                let (u, v) = (g.0.next_f64(), g.0.next_f64());
                let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
                c + (p[0] + (p[1] - p[0]) * u + (p[2] - p[0]) * v - c) * 1.3
            }
            _ => c + g.in_ball() * (1.2 * size),
        };
        Ray::new(o, (target - o).normalize())
    };
    match family {
        Family::Random | Family::Scale => {
            let o = c + DVec3::new(g.uniform(-4., 4.), g.uniform(-4., 4.), g.uniform(-4., 4.)) * size;
            (spec, aim(g, o), 0.0)
        }
        Family::Far => {
            let o = c + g.unit() * g.log_uniform(3.0, 7.0);
            (spec, aim(g, o), 0.0)
        }
        Family::Grazing => {
            if let Spec::Plane { p } = spec {
                // Nearly parallel to the plane: elevation 1e-9 to 1e-3 rad, from above.
                let h = size * g.uniform(0.1, 1.0);
                let horizontal = g.perpendicular(DVec3::Z);
                let d = (horizontal - DVec3::Z * g.log_uniform(-9.0, -3.0)).normalize();
                return (spec, Ray::new(p + DVec3::Z * h, d), 0.0);
            }
            let (p, n) = silhouette_point(&spec, g);
            let (d, side) = match n {
                Some(n) => (g.perpendicular(n), n),
                None => {
                    let d = g.unit();
                    (d, g.perpendicular(d))
                }
            };
            let delta = g.uniform(-1e-9, 1e-9) * size;
            let o = p + side * delta - d * (size * g.uniform(2.0, 6.0));
            (spec, Ray::new(o, d), 0.0)
        }
        Family::TorusAxis => {
            let a = g.uniform(0.0, std::f64::consts::TAU);
            // A tenth of the rays exactly on the axis, the rest up to just beyond the tube.
            let rho = if g.0.next_f64() < 0.1 {
                0.0
            } else {
                g.uniform(0.0, 1.1 * size)
            };
            let up = if g.0.next_f64() < 0.5 { 1.0 } else { -1.0 };
            let o = c + DVec3::new(rho * libm::cos(a), rho * libm::sin(a), up * size * g.uniform(2.0, 10.0));
            (spec, Ray::new(o, DVec3::Z * -up), 0.0)
        }
        Family::TorusEquator => {
            let a = g.uniform(0.0, std::f64::consts::TAU);
            let dist = size * g.log_uniform(1.0, 6.0);
            let o = c + DVec3::new(dist * libm::cos(a), dist * libm::sin(a), 0.0);
            let r = 1.1 * size * g.0.next_f64().sqrt();
            let b = g.uniform(0.0, std::f64::consts::TAU);
            let target = c + DVec3::new(r * libm::cos(b), r * libm::sin(b), 0.0);
            let mut d = (target - o).normalize();
            // Half exactly in the plane, half nearly: tilted by 1e-12 to 1e-4 rad.
            d.z = if g.0.next_f64() < 0.5 {
                0.0
            } else {
                g.log_uniform(-12.0, -4.0) * if g.0.next_f64() < 0.5 { -1.0 } else { 1.0 }
            };
            (spec, Ray::new(o, d.normalize()), 0.0)
        }
        Family::TorusOnSurface => {
            let (p, n) = silhouette_point(&spec, g);
            let n = n.unwrap_or(DVec3::Z);
            let mut d = g.unit();
            if d.dot(n) < 0.0 {
                d = -d;
            }
            // The f64 shape gets t_min = 0 (a ray leaving a hit point); the reference skips
            // the root at the origin with t_min = 1e-9 size (see `run_cell`).
            (spec, Ray::new(p, d), 0.0)
        }
    }
}

/// Outcome of one ray.
enum Outcome {
    Agree(Option<f64>),
    Missed,
    False(f64),
    Band,
    NonFinite,
}

/// Relative error of `t` against the reference `r`.
fn rel_error(t: f64, r: Dd) -> f64 {
    ((Dd::new(t) - r) / r).abs().to_f64()
}

/// Compares the f64 hit with the reference, with the grazing band of the module doc.
fn judge(spec: &Spec, ray: &Ray, hit: Option<f64>, t_min_ref: f64) -> (Outcome, bool) {
    let o = Dd3::from_f64(ray.origin);
    let d = Dd3::from_f64(ray.dir);
    let t_ref = spec.reference(o, d, Dd::new(t_min_ref));
    let has_ref = t_ref.is_some();
    let delta = (1e-9 * spec.size())
        .max(16.0 * f64::EPSILON * (ray.origin.abs().max_element() + spec.center().abs().max_element()));
    // The exact answers for the origin moved by delta in eight directions around the ray.
    let frame = Frame::from_z(ray.dir);
    let perturbed = || {
        (0..8).map(move |k| {
            let a = k as f64 * std::f64::consts::FRAC_PI_4;
            let u = frame.to_world(DVec3::new(libm::cos(a), libm::sin(a), 0.0));
            let shift = Dd3::new(
                Dd::new(u.x) * Dd::new(delta),
                Dd::new(u.y) * Dd::new(delta),
                Dd::new(u.z) * Dd::new(delta),
            );
            spec.reference(o + shift, d, Dd::new(t_min_ref))
        })
    };
    let outcome = match (hit, t_ref) {
        (Some(t), _) if !t.is_finite() => Outcome::NonFinite,
        (None, None) => Outcome::Agree(None),
        (Some(t), Some(r)) => {
            let err = rel_error(t, r);
            if err <= 1e-9 {
                Outcome::Agree(Some(err))
            } else if perturbed().any(|p| p.is_none_or(|p| (p - r).abs() >= (Dd::new(t) - r).abs())) {
                // The exact t moves more under a band-sized nudge than the f64 t is off.
                Outcome::Band
            } else if err <= 1e-6 {
                Outcome::Agree(Some(err))
            } else {
                Outcome::False(err)
            }
        }
        (None, Some(_)) => {
            if perturbed().any(|p| p.is_none()) {
                Outcome::Band
            } else {
                Outcome::Missed
            }
        }
        (Some(t), None) => {
            if perturbed().any(|p| p.is_some_and(|p| rel_error(t, p) <= 1e-6)) {
                Outcome::Band
            } else {
                Outcome::False(f64::INFINITY)
            }
        }
    };
    (outcome, has_ref)
}

/// Intersects with the shape's own solver (or, for the torus, the chosen quartic method).
fn solve(shape: &Shape, method: QuarticMethod, ray: &Ray, t_min: f64) -> Option<SurfaceHitT> {
    let hit = match (shape, method) {
        (Shape::Torus(t), m) if m != QuarticMethod::Isolator => t.intersect_with(m, ray, t_min, f64::INFINITY),
        _ => shape.intersect(ray, t_min, f64::INFINITY),
    };
    hit.map(|h| if h.normal.is_finite() { h.t } else { f64::NAN })
}

type SurfaceHitT = f64;

/// The seeded rays of one (shape, family) cell: the shape, the ray and the `t_min` the f64
/// code gets. Also used by `benches/solvers.rs`.
pub fn cases(shape: &'static str, family: Family, n: usize, seed: u64) -> Vec<(Spec, Ray, f64)> {
    let cell = SHAPES.iter().position(|&s| s == shape).unwrap_or(0) as u64 * 16
        + Family::ALL.iter().position(|&f| f == family).unwrap_or(0) as u64;
    let mut g = Gen(Stream::new(seed, Purpose::Generator, (1 << 40) | cell));
    (0..n).map(|_| make_case(shape, family, &mut g)).collect()
}

/// Runs `n` rays of one family against one shape kind (the torus with quartic `method`).
pub fn run_cell(shape: &'static str, family: Family, n: usize, seed: u64, method: QuarticMethod) -> Row {
    let mut row = Row {
        shape,
        family: family.name(),
        rays: n,
        reference_hits: 0,
        missed: 0,
        false_hits: 0,
        band: 0,
        non_finite: 0,
        median_rel_error: 0.0,
        max_rel_error: 0.0,
    };
    let mut errors = Vec::with_capacity(n);
    for (spec, ray, t_min) in cases(shape, family, n, seed) {
        let t_min_ref = if family == Family::TorusOnSurface {
            1e-9 * spec.size()
        } else {
            t_min
        };
        let hit = solve(&spec.shape(), method, &ray, t_min);
        let (outcome, has_ref) = judge(&spec, &ray, hit, t_min_ref);
        row.reference_hits += has_ref as usize;
        match outcome {
            Outcome::Agree(Some(e)) => errors.push(e),
            Outcome::Agree(None) => {}
            Outcome::Missed => row.missed += 1,
            Outcome::False(e) => {
                row.false_hits += 1;
                if e.is_finite() {
                    errors.push(e);
                }
            }
            Outcome::Band => row.band += 1,
            Outcome::NonFinite => row.non_finite += 1,
        }
    }
    errors.sort_by(f64::total_cmp);
    if !errors.is_empty() {
        row.median_rel_error = errors[errors.len() / 2];
        row.max_rel_error = *errors.last().unwrap();
    }
    row
}

/// The whole campaign: every shape with every family that applies to it.
pub fn campaign(n: usize, seed: u64) -> Vec<Row> {
    let mut rows = Vec::new();
    for shape in SHAPES {
        for family in Family::ALL {
            if family.torus_only() && shape != "torus" {
                continue;
            }
            rows.push(run_cell(shape, family, n, seed, QuarticMethod::Isolator));
        }
    }
    rows
}

/// The table as Markdown.
pub fn table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| shape | family | rays | ref hits | missed | false | band | NaN/Inf | median rel err t | max rel err t |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:.2e} | {:.2e} |\n",
            r.shape,
            r.family,
            r.rays,
            r.reference_hits,
            r.missed,
            r.false_hits,
            r.band,
            r.non_finite,
            r.median_rel_error,
            r.max_rel_error
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_lists_every_cell() {
        // 4 shared families x 13 shapes + 3 torus-only families.
        let rows = campaign(2, 1);
        assert_eq!(rows.len(), 55);
        let t = table(&rows);
        assert_eq!(t.lines().count(), 2 + 55);
        assert!(t.contains("| lens | grazing | 2 |"));
        assert!(t.contains("| ellipsoid | far | 2 |"));
        assert!(t.contains("| torus | torus-equator | 2 |"));
    }
}
