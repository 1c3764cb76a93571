//! The closed set of shapes. Each shape answers three questions: the closest hit in a
//! parameter range (camera, reflection and refraction rays), whether any hit exists in a
//! range (shadow rays: cheaper, may stop at the first root), and its bounding box when it
//! is finite. Normals are unit length and point outward; the tracer decides which side the
//! ray is on. Rays that start inside a shape get the exit hit.

mod cone;
mod cuboid;
mod cylinder;
mod disk;
mod plane;
mod rectangle;
mod sphere;
mod torus;

pub use cone::Cone;
pub use cuboid::Cuboid;
pub use cylinder::Cylinder;
pub use disk::Disk;
pub use plane::Plane;
pub use rectangle::Rectangle;
pub use sphere::Sphere;
pub use torus::{QuarticMethod, Torus};

use crate::math::Ray;
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
    Plane(Plane),
    Rectangle(Rectangle),
    Disk(Disk),
    Sphere(Sphere),
    Cuboid(Cuboid),
    Cylinder(Cylinder),
    Cone(Cone),
    Torus(Torus),
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

    /// Bounding box, `None` for unbounded shapes (planes).
    pub fn bounds(&self) -> Option<Aabb> {
        dispatch!(self, s => s.bounds())
    }

    /// The shape's kind as written in scene files.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Plane(_) => "plane",
            Shape::Rectangle(_) => "rectangle",
            Shape::Disk(_) => "disk",
            Shape::Sphere(_) => "sphere",
            Shape::Cuboid(_) => "box",
            Shape::Cylinder(_) => "cylinder",
            Shape::Cone(_) => "cone",
            Shape::Torus(_) => "torus",
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
    let (t0, t1) = roots;
    if t0 > t_min && t0 < t_max {
        Some(t0)
    } else if t1 > t_min && t1 < t_max {
        Some(t1)
    } else {
        None
    }
}

/// Parameter shift that moves a far ray origin `o` (local frame) to the point of the ray
/// nearest `mid`, the middle of a shape of radius about `size`: `s = (mid - o).d` when `o`
/// is more than `16 size` away, else 0. A quadric's constant coefficient grows with `|o|^2`
/// and its rounding error with it (relative errors of `t` near 1e-9 from 1e7 away); from the
/// shifted origin the coefficients are of the shape's own size. The shifted origin itself is
/// exact to one rounding of `|o|`, which the hit point error bound covers.
pub(crate) fn recentre(o: DVec3, d: DVec3, mid: DVec3, size: f64) -> f64 {
    let to_mid = mid - o;
    if to_mid.length_squared() > 256.0 * size * size {
        to_mid.dot(d)
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
    if d.z == 0.0 {
        return None;
    }
    let t = (h - o.z) / d.z;
    if !(t > t_min && t < t_max) {
        return None;
    }
    let p = o + d * t;
    inside(p.x, p.y).then_some(t)
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
}
