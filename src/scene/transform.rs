//! Similarity transforms of whole scenes, `p -> s p + offset` (uniform scale `s > 0`, then
//! a translation), for the invariance tests (`tests/invariance.rs`): a scene moved far from the origin
//! or scaled by 1e3 must render the same image. Directions (normals, axes, light
//! directions, spot orientations, the camera's up) are unchanged; lengths scale by `s`;
//! point and spot attenuation coefficients are rescaled so that `A` at corresponding
//! points is unchanged: `A = 1 / (C_const + C_lin d + C_quad d^2)` with `d' = s d` needs
//! `C_lin' = C_lin / s` and `C_quad' = C_quad / s^2`. Triangles' vertices move (a mesh's
//! shared array once for the whole mesh); a transformed shape's map is followed by the
//! similarity. An aperture light's oscillators move with it, but its wavelength is a length
//! that does not scale: a scaled scene's fringes are not the original's.

use super::{CameraSpec, Scene};
use crate::light::{Attenuation, Light};
use crate::shape::{Disk, Lens, Plane, Rectangle, Shape, Sphere, SphericalCap, Transformed, Triangle};
use glam::DVec3;
use std::collections::HashMap;
use std::sync::Arc;

/// `p -> scale p + offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Similarity {
    pub scale: f64,
    pub offset: DVec3,
}

impl Similarity {
    pub fn translation(offset: DVec3) -> Self {
        Similarity { scale: 1.0, offset }
    }

    /// Uniform scaling about the origin.
    pub fn scaling(scale: f64) -> Self {
        Similarity {
            scale,
            offset: DVec3::ZERO,
        }
    }

    pub fn point(&self, p: DVec3) -> DVec3 {
        p * self.scale + self.offset
    }

    pub fn length(&self, l: f64) -> f64 {
        l * self.scale
    }

    fn attenuation(&self, a: &Attenuation) -> Attenuation {
        Attenuation {
            constant: a.constant,
            linear: a.linear / self.scale,
            quadratic: a.quadratic / (self.scale * self.scale),
        }
    }

    /// The shape moved and scaled. Shapes with an orientation keep their private frame
    /// (a similarity does not rotate), so only their public position and sizes change.
    pub fn shape(&self, shape: &Shape) -> Shape {
        match shape {
            Shape::Plane(p) => Shape::Plane(Box::new(Plane::new(self.point(p.point), p.normal))),
            Shape::Rectangle(r) => Shape::Rectangle(Box::new(Rectangle::new(
                self.point(r.corner),
                r.edge1 * self.scale,
                r.edge2 * self.scale,
            ))),
            Shape::Disk(d) => Shape::Disk(Box::new(Disk::new(
                self.point(d.center),
                d.normal,
                self.length(d.radius),
            ))),
            Shape::Sphere(s) => Shape::Sphere(Sphere::new(self.point(s.center), self.length(s.radius))),
            Shape::Cuboid(b) => Shape::Cuboid(Box::new(b.resized(self.point(b.center), b.half_size * self.scale))),
            Shape::Cylinder(c) => Shape::Cylinder(Box::new(c.resized(
                self.point(c.base),
                self.length(c.height),
                self.length(c.radius),
            ))),
            Shape::Cone(c) => Shape::Cone(Box::new(c.resized(
                self.point(c.base),
                self.length(c.height),
                self.length(c.radius),
            ))),
            Shape::Torus(t) => {
                let mut t = t.clone();
                t.center = self.point(t.center);
                t.major = self.length(t.major);
                t.minor = self.length(t.minor);
                Shape::Torus(t)
            }
            Shape::Triangle(t) => {
                let [p0, p1, p2] = t.points().map(|p| self.point(p));
                Shape::Triangle(Triangle::new(p0, p1, p2))
            }
            Shape::SmoothTriangle(t) => {
                let [p0, p1, p2] = t.triangle.points().map(|p| self.point(p));
                let mut moved = t.clone();
                moved.triangle = Triangle::new(p0, p1, p2);
                Shape::SmoothTriangle(moved)
            }
            Shape::SphericalCap(c) => Shape::SphericalCap(Box::new(SphericalCap::new(
                self.point(c.center),
                c.normal,
                self.length(c.radius),
                self.length(c.curvature),
            ))),
            Shape::Lens(l) => Shape::Lens(Box::new(Lens::new(
                self.point(l.base),
                l.axis,
                self.length(l.thickness),
                self.length(l.radius),
                self.length(l.curvature1),
                self.length(l.curvature2),
            ))),
            Shape::Transformed(t) => Shape::Transformed(Box::new(Transformed::new(
                t.shape.clone(),
                t.transform.then_similarity(self.scale, self.offset),
            ))),
        }
    }

    /// A triangle moved within its (moved) shared vertex array: `moved` keeps each array's
    /// moved copy, keyed by the original's address.
    fn triangle(&self, t: &Triangle, moved: &mut HashMap<*const DVec3, Arc<[DVec3]>>) -> Shape {
        let (shared, index) = t.shared();
        let copy = moved
            .entry(Arc::as_ptr(shared).cast::<DVec3>())
            .or_insert_with(|| shared.iter().map(|&p| self.point(p)).collect());
        Shape::Triangle(Triangle::in_mesh(copy, index).expect("the same indices into an array of the same length"))
    }

    pub fn light(&self, light: &Light) -> Light {
        match light {
            Light::Ambient { .. } | Light::Directional { .. } => light.clone(),
            Light::Point(p) => {
                let mut p = p.clone();
                p.position = self.point(p.position);
                p.attenuation = self.attenuation(&p.attenuation);
                Light::Point(p)
            }
            Light::Spot(s) => {
                let mut s = s.clone();
                s.position = self.point(s.position);
                s.attenuation = self.attenuation(&s.attenuation);
                Light::Spot(s)
            }
            Light::Area(a) => {
                use crate::area_light::AreaShape;
                let mut a = a.clone();
                a.shape = match a.shape {
                    AreaShape::Sphere { center, radius } => AreaShape::Sphere {
                        center: self.point(center),
                        radius: self.length(radius),
                    },
                    AreaShape::Tube { start, end } => AreaShape::Tube {
                        start: self.point(start),
                        end: self.point(end),
                    },
                    AreaShape::Window { center, edge1, edge2 } => AreaShape::Window {
                        center: self.point(center),
                        edge1: edge1 * self.scale,
                        edge2: edge2 * self.scale,
                    },
                };
                a.attenuation = self.attenuation(&a.attenuation);
                Light::Area(a)
            }
            Light::Aperture(a) => {
                use crate::interference::Aperture;
                let mut a = a.clone();
                let planar = |p: &mut crate::interference::Planar| {
                    p.center = self.point(p.center);
                    p.width = self.length(p.width);
                    p.height = self.length(p.height);
                };
                match &mut a.aperture {
                    Aperture::Linear { start, end } => {
                        *start = self.point(*start);
                        *end = self.point(*end);
                    }
                    Aperture::Rectangular(p) | Aperture::Elliptical(p) | Aperture::Mask { planar: p, .. } => planar(p),
                }
                a.oscillators = a.oscillators.iter().map(|&o| self.point(o)).collect();
                a.attenuation = self.attenuation(&a.attenuation);
                Light::Aperture(a)
            }
        }
    }

    pub fn camera(&self, c: &CameraSpec) -> CameraSpec {
        CameraSpec {
            position: self.point(c.position),
            look_at: self.point(c.look_at),
            up: c.up,
            vfov_deg: c.vfov_deg,
        }
    }

    /// The whole scene transformed (settings and materials unchanged).
    pub fn scene(&self, scene: &Scene) -> Scene {
        let mut out = scene.clone();
        let mut moved = HashMap::new();
        for o in &mut out.objects {
            o.shape = match &o.shape {
                Shape::Triangle(t) => self.triangle(t, &mut moved),
                other => self.shape(other),
            };
        }
        out.lights = scene.lights.iter().map(|l| self.light(l)).collect();
        out.camera = self.camera(&scene.camera);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::PointLight;
    use crate::math::Ray;

    #[test]
    fn attenuation_is_unchanged_at_corresponding_points() {
        // C = (1, 0.1, 0.01) at d = 10: A = 1 / (1 + 1 + 1) = 1/3; scaled by 1e3 at d = 1e4.
        let t = Similarity::scaling(1e3);
        let l = t.light(&Light::Point(PointLight {
            position: DVec3::ZERO,
            color: DVec3::ONE,
            attenuation: Attenuation {
                constant: 1.0,
                linear: 0.1,
                quadratic: 0.01,
            },
        }));
        let inc = l.incidence(DVec3::new(1e4, 0.0, 0.0)).unwrap();
        assert!((inc.attenuation - 1.0 / 3.0).abs() < 1e-15, "{}", inc.attenuation);
    }

    #[test]
    fn hits_scale_with_the_scene() {
        // The torus (R 1.5, r 0.5) at the origin, hit from x = -5 at t = 3; scaled by 1e3 and
        // moved by (1e5, 1e5, 0), the same ray (transformed) hits at t = 3000.
        let torus = Shape::Torus(Box::new(crate::shape::Torus::new(DVec3::ZERO, DVec3::Z, 1.5, 0.5)));
        let t = Similarity {
            scale: 1e3,
            offset: DVec3::new(1e5, 1e5, 0.0),
        };
        let moved = t.shape(&torus);
        let ray = Ray::new(t.point(DVec3::new(-5.0, 0.0, 0.0)), DVec3::X);
        let hit = moved.intersect(&ray, 0.0, f64::INFINITY).unwrap();
        assert!((hit.t - 3000.0).abs() < 1e-9, "{}", hit.t);
        assert!((hit.normal + DVec3::X).length() < 1e-12);
    }
}
