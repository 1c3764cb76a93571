//! The closed set of shapes. Each shape answers three questions: the closest hit in a
//! parameter range (camera, reflection and refraction rays), whether any hit exists in a
//! range (shadow rays: cheaper, may stop at the first root), and its bounding box when it
//! is finite. Normals are unit length and point outward (but a smooth triangle's under
//! SIMRenderer's linear interpolation: [`NormalInterpolation`]); the tracer decides which
//! side the ray is on. Rays that start inside a shape get the exit hit. Open surfaces (plane,
//! rectangle, disk, triangle, tube, spherical cap) bound no solid. Each shape also has
//! texture coordinates ([`Shape::uv`], in `uv`).

mod cone;
mod cuboid;
mod cylinder;
mod disk;
mod fan;
mod lens;
pub mod mesh;
mod plane;
mod rectangle;
mod smooth_triangle;
mod sphere;
mod spherical_cap;
mod torus;
mod transformed;
mod triangle;
mod uv;

pub use cone::Cone;
pub use cuboid::Cuboid;
pub use cylinder::Cylinder;
pub use disk::Disk;
pub use fan::{Fan, Verdict, fan_verdicts, occludes_undecided};
pub use lens::Lens;
pub use plane::Plane;
pub use rectangle::Rectangle;
pub use smooth_triangle::{NormalInterpolation, SmoothTriangle};
pub use sphere::Sphere;
#[cfg(test)]
pub(crate) use sphere::sphere_discriminant;
pub use spherical_cap::SphericalCap;
pub use torus::{QuarticMethod, Torus};
pub use transformed::{Transform, Transformed};
pub use triangle::Triangle;

use crate::math::{Ray, half_diagonal};
use glam::DVec3;

/// A surface hit: ray parameter and the outward unit normal there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    pub t: f64,
    pub normal: DVec3,
}

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: DVec3,
    pub max: DVec3,
}

impl Aabb {
    /// The empty box (union identity).
    pub const EMPTY: Aabb = Aabb {
        min: DVec3::splat(f64::INFINITY),
        max: DVec3::splat(f64::NEG_INFINITY),
    };

    pub fn new(min: DVec3, max: DVec3) -> Self {
        Aabb { min, max }
    }

    /// Box of a sphere of radius `r` around `c`.
    pub fn around(c: DVec3, r: f64) -> Self {
        Aabb::new(c - DVec3::splat(r), c + DVec3::splat(r))
    }

    pub fn union(self, o: Aabb) -> Aabb {
        Aabb::new(self.min.min(o.min), self.max.max(o.max))
    }

    pub fn include(self, p: DVec3) -> Aabb {
        Aabb::new(self.min.min(p), self.max.max(p))
    }

    pub fn centroid(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Slab test: the parameter interval where the ray is inside the box, clipped to
    /// `[t_min, t_max]`.
    pub fn clip(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<(f64, f64)> {
        let inv = ray.dir.recip();
        let t0 = (self.min - ray.origin) * inv;
        let t1 = (self.max - ray.origin) * inv;
        // NaN from 0 * inf (origin on a slab, direction parallel) is ignored by min/max.
        let near = t0.min(t1).max_element().max(t_min);
        let far = t0.max(t1).min_element().min(t_max);
        (near <= far).then_some((near, far))
    }
}

/// Every kind of shape the scene files can hold.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    // Every shape larger than a sphere is boxed: the enum stays at 40 bytes (a sphere and
    // the tag) and an object at 48, so a million spheres take 48 MB and more of them share
    // a cache line.
    Plane(Box<Plane>),
    Rectangle(Box<Rectangle>),
    Disk(Box<Disk>),
    Sphere(Sphere),
    Cuboid(Box<Cuboid>),
    Cylinder(Box<Cylinder>),
    Cone(Box<Cone>),
    Torus(Box<Torus>),
    /// Inline (32 bytes: the shared vertex array and three indices), no allocation per
    /// triangle.
    Triangle(Triangle),
    /// A triangle with vertex normals and texture coordinates.
    SmoothTriangle(Box<SmoothTriangle>),
    /// Any shape through an affine map.
    Transformed(Box<Transformed>),
    /// SIMRenderer's spherical cap: an open piece of a sphere over a disk.
    SphericalCap(Box<SphericalCap>),
    /// SIMRenderer's lens: an edge closed by two spherical caps.
    Lens(Box<Lens>),
}

macro_rules! dispatch {
    ($self:ident, $s:ident => $e:expr) => {
        match $self {
            Shape::Plane($s) => $e,
            Shape::Rectangle($s) => $e,
            Shape::Disk($s) => $e,
            Shape::Sphere($s) => $e,
            Shape::Cuboid($s) => $e,
            Shape::Cylinder($s) => $e,
            Shape::Cone($s) => $e,
            Shape::Torus($s) => $e,
            Shape::Triangle($s) => $e,
            Shape::SmoothTriangle($s) => $e,
            Shape::Transformed($s) => $e,
            Shape::SphericalCap($s) => $e,
            Shape::Lens($s) => $e,
        }
    };
}

impl Shape {
    /// Closest hit with `t_min < t < t_max`.
    ///
    /// `t_max` only filters: for `b < c`, `intersect(ray, a, b)` is `intersect(ray, a, c)`
    /// when that hit has `t < b`, else `None`, to the bit. The intersection cores rely on it
    /// (they shrink `t_max` to the best hit so far, in orders of their own) and
    /// tests/accel.rs checks it for every kind of shape.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        dispatch!(self, s => s.intersect(ray, t_min, t_max))
    }

    /// True when the ray hits the surface anywhere with `t_min < t < t_max`.
    pub fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        match self {
            Shape::Sphere(s) => s.occludes(ray, t_min, t_max),
            Shape::Torus(s) => s.occludes(ray, t_min, t_max),
            Shape::Triangle(s) => s.occludes(ray, t_min, t_max),
            Shape::SmoothTriangle(s) => s.occludes(ray, t_min, t_max),
            _ => self.intersect(ray, t_min, t_max).is_some(),
        }
    }

    /// Bound on the absolute distance from `p`, a hit point computed on this shape, to the
    /// shape's surface (pbrt-v4 style per-shape error bound, a posteriori): the residual of
    /// the shape's own equation at `p` in distance units, plus a `gamma(16)` bound on
    /// evaluating it and on the arithmetic the intersection routines do near the surface.
    /// The tracer adds the rounding of `o + t d` ([`crate::math::hit_point_error`]) and
    /// offsets secondary origins by the sum.
    pub fn surface_error(&self, p: DVec3) -> f64 {
        dispatch!(self, s => s.surface_error(p))
    }

    /// The point `r_0 + v t` where `ray` hits this shape at `t` (chapter 7.4b:
    /// `r_inter = r_0 + v t_inter`), with the bound on its rounding error: forming the point
    /// ([`crate::math::hit_point_error`]) plus the shape's own ([`Shape::surface_error`]).
    /// Camera paths and photons both leave their hits from it.
    pub fn hit_point(&self, ray: &Ray, t: f64) -> (DVec3, f64) {
        let point = ray.at(t);
        (point, crate::math::hit_point_error(ray, t) + self.surface_error(point))
    }

    /// Bounding box, `None` for unbounded shapes (planes).
    pub fn bounds(&self) -> Option<Aabb> {
        dispatch!(self, s => s.bounds())
    }

    /// A ball containing the whole shape (center, radius), as small as is simple to say;
    /// `None` for unbounded shapes. Shadow rays that miss it miss the shape.
    pub fn bounding_sphere(&self) -> Option<(DVec3, f64)> {
        Some(match self {
            Shape::Plane(_) => return None,
            Shape::Rectangle(r) => (r.corner + 0.5 * (r.edge1 + r.edge2), half_diagonal(r.edge1, r.edge2)),
            Shape::Disk(d) => (d.center, d.radius),
            Shape::Sphere(s) => (s.center, s.radius),
            Shape::Cuboid(b) => b.bounding_sphere(),
            Shape::Cylinder(c) => c.bounding_sphere(),
            Shape::Cone(c) => c.bounding_sphere(),
            Shape::Torus(t) => (t.center, t.major + t.minor),
            Shape::Triangle(t) => t.bounding_sphere(),
            Shape::SmoothTriangle(t) => t.triangle.bounding_sphere(),
            Shape::Transformed(t) => return t.bounding_sphere(),
            Shape::SphericalCap(c) => c.bounding_sphere(),
            Shape::Lens(l) => l.bounding_sphere(),
        })
    }

    /// A ball inside the solid (center, radius): a segment that starts outside the shape and
    /// passes through it crosses the surface. `None` for surfaces that bound no solid
    /// (plane, rectangle, disk, triangle, tube) and for the torus (its center is in the hole).
    pub fn inner_ball(&self) -> Option<(DVec3, f64)> {
        match self {
            Shape::Plane(_)
            | Shape::Rectangle(_)
            | Shape::Disk(_)
            | Shape::Torus(_)
            | Shape::Triangle(_)
            | Shape::SmoothTriangle(_) => None,
            // The lens's thinnest place depends on its caps: no ball is claimed.
            Shape::SphericalCap(_) | Shape::Lens(_) => None,
            Shape::Sphere(s) => Some((s.center, s.radius)),
            Shape::Cuboid(b) => Some((b.center, b.half_size.min_element())),
            Shape::Cylinder(c) if c.open => None,
            Shape::Cylinder(c) => Some((c.base + 0.5 * c.height * c.axis, c.radius.min(0.5 * c.height))),
            // The inscribed ball touches the base and the side: radius `r h / (r + sqrt(r^2 + h^2))`.
            Shape::Cone(c) => {
                let (h, r) = (c.height, c.radius);
                let rho = r * h / (r + libm::hypot(r, h));
                Some((c.base + rho * c.axis, rho))
            }
            Shape::Transformed(t) => t.inner_ball(),
        }
    }

    /// Whether a ray leaving the surface outward can never meet it again: true of convex
    /// solids, of flat shapes, of the tube (outward is away from its axis) and of the
    /// spherical cap (outward is away from its sphere's center), false of the torus and of
    /// a lens with a concave cap. An affine map keeps it.
    pub fn is_convex(&self) -> bool {
        match self {
            Shape::Torus(_) => false,
            Shape::Lens(l) => l.is_convex(),
            Shape::Transformed(t) => t.shape.is_convex(),
            _ => true,
        }
    }

    /// Whether the shape bounds a convex solid (sphere, box, capped cylinder and cone): a
    /// ray that leaves its surface inward crosses it again on the far side. An affine map
    /// keeps it.
    pub fn is_convex_solid(&self) -> bool {
        match self {
            Shape::Sphere(_) | Shape::Cuboid(_) | Shape::Cone(_) => true,
            Shape::Cylinder(c) => !c.open,
            Shape::Lens(l) => l.is_convex(),
            Shape::Transformed(t) => t.shape.is_convex_solid(),
            _ => false,
        }
    }

    /// Whether the shape bounds a solid (sphere, box, capped cylinder and cone, torus, lens,
    /// and any of them transformed): it has an inside, which a refracted ray can enter.
    /// Planes, rectangles, disks, triangles, tubes and spherical caps are open surfaces (as
    /// SIMRenderer's cap, a disk geometry, does not close its rim).
    pub fn is_closed(&self) -> bool {
        match self {
            Shape::Plane(_)
            | Shape::Rectangle(_)
            | Shape::Disk(_)
            | Shape::Triangle(_)
            | Shape::SmoothTriangle(_)
            | Shape::SphericalCap(_) => false,
            Shape::Cylinder(c) => !c.open,
            Shape::Transformed(t) => t.shape.is_closed(),
            Shape::Sphere(_) | Shape::Cuboid(_) | Shape::Cone(_) | Shape::Torus(_) | Shape::Lens(_) => true,
        }
    }

    /// The shape's kind as written in scene files.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Plane(_) => "plane",
            Shape::Rectangle(_) => "rectangle",
            Shape::Disk(_) => "disk",
            Shape::Sphere(_) => "sphere",
            Shape::Cuboid(_) => "box",
            Shape::Cylinder(c) if c.open => "tube",
            Shape::Cylinder(_) => "cylinder",
            Shape::Cone(_) => "cone",
            Shape::Torus(_) => "torus",
            Shape::Triangle(_) | Shape::SmoothTriangle(_) => "triangle",
            Shape::SphericalCap(_) => "spherical_cap",
            Shape::Lens(_) => "lens",
            // Written as the inner shape's table with a `transform`.
            Shape::Transformed(t) => t.shape.kind(),
        }
    }
}

/// `gamma(n) = n u / (1 - n u)`, the relative error bound of `n` rounded operations
/// (Higham, "Accuracy and Stability of Numerical Algorithms", 3.1), `u = 2^-53`.
pub(crate) fn gamma(n: u32) -> f64 {
    let nu = n as f64 * f64::EPSILON * 0.5;
    nu / (1.0 - nu)
}

/// Sum of the absolute components: the magnitude that bounds rounding errors of sums.
pub(crate) fn l1(v: DVec3) -> f64 {
    v.abs().element_sum()
}

/// Keeps the smaller of two optional hits.
pub(crate) fn nearer(a: Option<SurfaceHit>, b: Option<SurfaceHit>) -> Option<SurfaceHit> {
    match (a, b) {
        (Some(x), Some(y)) => Some(if y.t < x.t { y } else { x }),
        (x, None) => x,
        (None, y) => y,
    }
}

/// The first of the two quadratic roots inside `(t_min, t_max)`.
pub(crate) fn first_root_in(roots: (f64, f64), t_min: f64, t_max: f64) -> Option<f64> {
    let t = first_root(roots, t_min, t_max);
    (t < f64::INFINITY).then_some(t)
}

/// [`first_root_in`] without a branch (see [`fan`]): the root, or infinity for none.
#[inline(always)]
pub(crate) fn first_root((t0, t1): (f64, f64), t_min: f64, t_max: f64) -> f64 {
    let later = if (t1 > t_min) & (t1 < t_max) { t1 } else { f64::INFINITY };
    if (t0 > t_min) & (t0 < t_max) { t0 } else { later }
}

/// A ball's radius padded so that rounding never rejects a ray that meets it, seen from a
/// point `offset` away from its centre: `r (1 + 1e-9) + 1e-9 |offset|_1` (the 1-norm, at
/// least the length, pads without a square root).
#[inline(always)]
pub(crate) fn padded_radius(radius: f64, offset: DVec3) -> f64 {
    radius * (1.0 + 1e-9) + 1e-9 * l1(offset)
}

/// Whether the ray misses the ball (`center`, `radius`) within `(t_min, t_max)` by a clear
/// margin (relative 1e-9 of the radius and of the distance): then it misses every shape
/// inside the ball, whatever that shape's own routine would compute, so the routine need not
/// run. The perpendicular distance uses `|f - (f.d) d|` (Ray Tracing Gems, ch. 7), accurate
/// for far origins.
#[inline(always)]
pub(crate) fn misses_bounding_sphere(ray: &Ray, t_min: f64, t_max: f64, (center, radius): (DVec3, f64)) -> bool {
    let f = ray.origin - center;
    let b = f.dot(ray.dir);
    let reach = padded_radius(radius, f);
    let perp = f - b * ray.dir;
    // Every comparison made, no branch (see `fan`).
    (perp.length_squared() > reach * reach) | (-b + reach < t_min) | (-b - reach > t_max)
}

/// Parameter shift that moves a far ray origin `o` (local frame) to the point of the ray
/// nearest `mid`, the middle of a shape of radius about `size`: `s = (mid - o).d` when `o`
/// is more than `16 size` away, else 0. A quadric's constant coefficient grows with `|o|^2`
/// and its rounding error with it (relative errors of `t` near 1e-9 from 1e7 away); from the
/// shifted origin the coefficients are of the shape's own size. The shifted origin itself is
/// exact to one rounding of `|o|`, which the hit point error bound covers.
#[inline(always)]
pub(crate) fn recenter(o: DVec3, d: DVec3, mid: DVec3, size: f64) -> f64 {
    let to_mid = mid - o;
    // A select, not a branch (see [`fan`]).
    let along = to_mid.dot(d);
    if to_mid.length_squared() > 256.0 * size * size {
        along
    } else {
        0.0
    }
}

/// Hit of the plane `z = h` in a local frame, kept when `inside(x, y)` holds.
pub(crate) fn local_cap(
    o: DVec3,
    d: DVec3,
    h: f64,
    t_min: f64,
    t_max: f64,
    inside: impl Fn(f64, f64) -> bool,
) -> Option<f64> {
    let t = cap_root(o, d, h, t_min, t_max, inside);
    (t < f64::INFINITY).then_some(t)
}

/// [`local_cap`] without a branch (see [`fan`]): the root, or infinity for none.
#[inline(always)]
pub(crate) fn cap_root(o: DVec3, d: DVec3, h: f64, t_min: f64, t_max: f64, inside: impl Fn(f64, f64) -> bool) -> f64 {
    // A ray parallel to the cap's plane never meets it (the quotient is then unused).
    let t = (h - o.z) / d.z;
    let p = o + d * t;
    let hit = (d.z != 0.0) & (t > t_min) & (t < t_max) & inside(p.x, p.y);
    if hit { t } else { f64::INFINITY }
}

#[cfg(test)]
pub(crate) mod test_util {
    use super::*;

    /// Asserts a hit at `t` with normal `n` (both within 1e-9).
    pub fn assert_hit(hit: Option<SurfaceHit>, t: f64, n: DVec3) {
        let h = hit.unwrap_or_else(|| panic!("expected a hit at t = {t}"));
        assert!((h.t - t).abs() < 1e-9, "t = {} expected {t}", h.t);
        assert!((h.normal - n).length() < 1e-9, "normal {} expected {n}", h.normal);
    }

    pub fn ray(o: [f64; 3], d: [f64; 3]) -> Ray {
        Ray::new(DVec3::from(o), DVec3::from(d).normalize())
    }

    /// `count` seeded rays from points of the cube of half-side `2 size` around `center`
    /// (some inside the shape) towards points of the cube of half-side `1.2 size`.
    pub fn random_rays(seed: u64, center: DVec3, size: f64, count: usize) -> Vec<Ray> {
        use crate::sampling::unit_interval;
        use rand_chacha::ChaCha8Rng;
        use rand_core::{Rng, SeedableRng};
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut point = |half: f64| {
            let mut u = || unit_interval(rng.next_u64()) * 2.0 - 1.0;
            center + half * DVec3::new(u(), u(), u())
        };
        (0..count)
            .map(|_| {
                let from = point(2.0 * size);
                let to = point(1.2 * size);
                Ray::new(from, (to - from).normalize())
            })
            .collect()
    }

    /// Checks that `occludes` answers as `intersect` does. For each ray, the first hit `t`
    /// and the next one after it (`t_min = t`): the segment ending one ulp past the hit is
    /// occluded, the segments ending at it or one ulp before it are not (no earlier root),
    /// and `intersect` limited to just past `t` returns the same hit to the bit. A ray with
    /// no (further) hit is occluded nowhere. Returns how many hits and misses were checked.
    pub fn check_occludes_agrees(shape: &Shape, rays: &[Ray]) -> (usize, usize) {
        let (mut hits, mut misses) = (0, 0);
        for ray in rays {
            let mut t_min = 0.0;
            for _ in 0..2 {
                let Some(hit) = shape.intersect(ray, t_min, f64::INFINITY) else {
                    assert!(!shape.occludes(ray, t_min, f64::INFINITY), "{ray:?} from {t_min}");
                    misses += 1;
                    break;
                };
                let t = hit.t;
                assert!(shape.occludes(ray, t_min, t.next_up()), "{ray:?}: hit at {t} not seen");
                assert!(!shape.occludes(ray, t_min, t), "{ray:?}: occluded before {t}");
                assert!(
                    !shape.occludes(ray, t_min, t.next_down()),
                    "{ray:?}: occluded before {t}"
                );
                assert_eq!(shape.intersect(ray, t_min, t.next_up()), Some(hit), "{ray:?}");
                assert_eq!(shape.intersect(ray, t_min, t), None, "{ray:?}");
                hits += 1;
                t_min = t;
            }
        }
        (hits, misses)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::unit_interval;
    use rand_chacha::ChaCha8Rng;
    use rand_core::{Rng, SeedableRng};

    /// One shape of each bounded kind, tilted or rotated, and the hand-computed balls of the
    /// simple ones.
    fn shapes() -> Vec<Shape> {
        let tilt = DVec3::new(0.3, -0.5, 1.0);
        vec![
            Shape::Sphere(Sphere::new(DVec3::new(1.0, -5.0, 3.0), 0.75)),
            Shape::Cuboid(Box::new(Cuboid::new(
                DVec3::new(0.0, 0.0, 3.0),
                DVec3::new(2.0, 1.0, 3.0),
                DVec3::new(10.0, 20.0, 30.0),
            ))),
            Shape::Cylinder(Box::new(Cylinder::new(DVec3::new(-5.0, 9.0, 0.0), tilt, 3.0, 1.0))),
            Shape::Cone(Box::new(Cone::new(DVec3::new(-3.0, -3.0, 0.0), tilt, 2.5, 1.0))),
            Shape::Cone(Box::new(Cone::new(DVec3::ZERO, -tilt, 0.5, 2.0))),
            Shape::Torus(Box::new(Torus::new(DVec3::new(4.0, 3.0, 2.0), tilt, 1.5, 0.5))),
            Shape::Disk(Box::new(Disk::new(DVec3::new(1.0, 2.0, 3.0), tilt, 2.0))),
            Shape::Rectangle(Box::new(Rectangle::new(
                DVec3::ZERO,
                DVec3::new(4.0, 0.0, 0.0),
                DVec3::new(0.0, 3.0, 1.0),
            ))),
            Shape::Triangle(Triangle::new(
                DVec3::new(1.0, 2.0, 3.0),
                DVec3::new(4.0, 0.0, 2.0),
                DVec3::new(-1.0, -2.0, 0.5),
            )),
            Shape::Cylinder(Box::new(Cylinder::tube(DVec3::new(2.0, -1.0, 0.0), tilt, 3.0, 1.0))),
            Transform::from_parts(
                DVec3::new(2.0, 0.5, 1.0),
                DVec3::new(10.0, 20.0, 30.0),
                DVec3::new(3.0, 1.0, -2.0),
            )
            .apply(Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0))),
            Transform::from_rows([[1.0, 0.3, 0.0, 1.0], [0.0, 1.0, -0.4, 2.0], [0.2, 0.0, 0.8, 0.0]])
                .unwrap()
                .apply(Shape::Torus(Box::new(Torus::new(DVec3::ZERO, tilt, 1.5, 0.5)))),
            Transform::from_parts(DVec3::new(1.0, 3.0, 0.5), DVec3::new(-40.0, 0.0, 15.0), DVec3::ONE).apply(
                Shape::Cuboid(Box::new(Cuboid::new(DVec3::ZERO, DVec3::ONE, DVec3::ZERO))),
            ),
            Shape::SphericalCap(Box::new(SphericalCap::new(DVec3::new(1.0, 2.0, 0.0), tilt, 1.5, 2.0))),
            Shape::SphericalCap(Box::new(SphericalCap::new(DVec3::new(1.0, 2.0, 0.0), tilt, 1.5, -1.5))),
            Shape::Lens(Box::new(Lens::new(
                DVec3::new(-1.0, 0.0, 2.0),
                tilt,
                0.5,
                1.0,
                1.5,
                3.0,
            ))),
            Shape::Lens(Box::new(Lens::new(
                DVec3::new(-1.0, 0.0, 2.0),
                -tilt,
                0.8,
                1.0,
                -2.0,
                1.0,
            ))),
        ]
    }

    /// The enum stays at the size of its largest inline shape (a sphere, 32 bytes) plus the
    /// tag, and an object (shape, material, name key) at 48 bytes: a million spheres are
    /// benchmarked.
    #[test]
    fn shapes_and_objects_keep_their_size() {
        let (shape, object) = (size_of::<Shape>(), size_of::<crate::scene::Object>());
        assert_eq!((shape, object), (40, 48), "size_of::<Shape>(), size_of::<Object>()");
        assert_eq!(size_of::<Sphere>(), 32);
        assert_eq!(size_of::<Triangle>(), 32);
    }

    #[test]
    fn a_ball_is_padded_by_a_relative_1e_9_of_its_radius_and_distance() {
        // Radius 2 seen from (3, -4, 0) away: 2 (1 + 1e-9) + 1e-9 (3 + 4) = 2 + 9e-9.
        let r = padded_radius(2.0, DVec3::new(3.0, -4.0, 0.0));
        assert!((r - (2.0 + 9e-9)).abs() < 1e-15, "{r}");
        assert_eq!(padded_radius(0.0, DVec3::ZERO), 0.0);
    }

    #[test]
    fn balls_by_hand() {
        // Cone of height 2.5 and radius 1: the ball through the rim and the apex has its
        // center at z0 = (6.25 - 1) / 5 = 1.05 and radius 2.5 - 1.05 = 1.45; the inscribed
        // ball has radius 2.5 / (1 + sqrt(7.25)) = 0.6771...
        let cone = Shape::Cone(Box::new(Cone::new(DVec3::ZERO, DVec3::Z, 2.5, 1.0)));
        let (c, r) = cone.bounding_sphere().unwrap();
        assert!((c - DVec3::new(0.0, 0.0, 1.05)).length() < 1e-15 && (r - 1.45).abs() < 1e-15);
        let (c, r) = cone.inner_ball().unwrap();
        let rho = 2.5 / (1.0 + 7.25f64.sqrt());
        assert!((c - DVec3::new(0.0, 0.0, rho)).length() < 1e-15 && (r - rho).abs() < 1e-15);
        // The reference cube (side 2): sqrt(3) around, 1 inside; the torus: R + r = 2.
        let cube = Shape::Cuboid(Box::new(Cuboid::new(
            DVec3::new(0.0, 0.0, 3.0),
            DVec3::splat(2.0),
            DVec3::ZERO,
        )));
        assert!((cube.bounding_sphere().unwrap().1 - 3f64.sqrt()).abs() < 1e-15);
        assert_eq!(cube.inner_ball().unwrap(), (DVec3::new(0.0, 0.0, 3.0), 1.0));
        let torus = Shape::Torus(Box::new(Torus::new(DVec3::ZERO, DVec3::Z, 1.5, 0.5)));
        assert_eq!(torus.bounding_sphere().unwrap().1, 2.0);
        assert_eq!(torus.inner_ball(), None);
        assert_eq!(
            Shape::Plane(Box::new(Plane::new(DVec3::ZERO, DVec3::Z))).bounding_sphere(),
            None
        );
    }

    #[test]
    fn bounding_spheres_hold_every_hit_and_inner_balls_are_inside() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut unit = move || unit_interval(rng.next_u64());
        for shape in shapes() {
            let (center, radius) = shape.bounding_sphere().unwrap();
            let mut direction = || {
                let (z, phi) = (2.0 * unit() - 1.0, std::f64::consts::TAU * unit());
                let s = (1.0 - z * z).sqrt();
                (DVec3::new(s * phi.cos(), s * phi.sin(), z), unit())
            };
            let mut hits = 0;
            for _ in 0..4000 {
                // Rays from a sphere around the shape towards points near it.
                let (d0, _) = direction();
                let (d1, u) = direction();
                let from = center + 3.0 * radius * d0;
                let to = center + 1.2 * radius * u * d1;
                let ray = Ray::new(from, (to - from).normalize());
                if let Some(h) = shape.intersect(&ray, 0.0, f64::INFINITY) {
                    hits += 1;
                    let p = ray.at(h.t);
                    assert!(
                        (p - center).length() <= radius * (1.0 + 1e-12),
                        "{} hit outside its ball",
                        shape.kind()
                    );
                }
            }
            assert!(hits > 500, "{}: {hits}", shape.kind());
            if let Some((c, r)) = shape.inner_ball() {
                // From any point of the inner ball, every ray leaves the solid through its
                // surface (an inside point), and not before the ball's own edge.
                for _ in 0..2000 {
                    let (d0, u) = direction();
                    let (d1, _) = direction();
                    let start = c + 0.999 * r * u.cbrt() * d0;
                    let ray = Ray::new(start, d1);
                    let exit = shape.intersect(&ray, 0.0, f64::INFINITY);
                    let exit = exit.unwrap_or_else(|| panic!("{}: no exit from {start}", shape.kind()));
                    assert!((ray.at(exit.t) - c).length() >= r * (1.0 - 1e-9), "{}", shape.kind());
                }
            }
        }
    }
}
