//! The two intersection cores (linear scan and BVH) agree hit for hit: same object, same
//! `t` and normal to the bit, on randomised scenes of every shape kind (planes, triangles,
//! tubes and transformed shapes included), on meshes (rays through their shared vertices
//! too), random rays, rays grazing box edges and faces, and rays starting on surfaces;
//! any-hit and every-hit agree too. The BVH's structure holds its invariants, every shape honours the
//! `t_max` contract the cores rely on, and whole images are byte-identical with either core.

use crate::common::*;
use glam::DVec3;
use lumiere::accel::{Accel, AccelChoice, Bvh, Kernel};
use lumiere::math::Ray;
use lumiere::render::render;
use lumiere::sampling::{Purpose, Stream};
use lumiere::scene::Object;
use lumiere::shape::{
    Cone, Cuboid, Cylinder, Disk, Lens, NormalInterpolation, Plane, Rectangle, Shape, SmoothTriangle, Sphere,
    SphericalCap, Torus, Transform, Triangle,
};
use lumiere::world::World;

fn object(shape: Shape) -> Object {
    Object {
        name: Default::default(),
        shape,
        material: 0,
    }
}

fn unit(s: &mut Stream) -> DVec3 {
    let z = 2.0 * s.next_f64() - 1.0;
    let phi = std::f64::consts::TAU * s.next_f64();
    let r = (1.0 - z * z).sqrt();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

fn point(s: &mut Stream, half: f64) -> DVec3 {
    DVec3::new(s.next_f64(), s.next_f64(), s.next_f64()) * (2.0 * half) - half
}

/// `n` random objects of every kind in a cube of half-side `half`, with some copies of
/// earlier objects (exact ties, which must go to the lower index) and some axis-aligned
/// boxes on integer coordinates (their faces coincide with their stored boxes' faces).
fn random_scene(seed: u64, n: usize, half: f64) -> Vec<Object> {
    let mut s = Stream::new(seed, Purpose::Generator, 1);
    let mut objects: Vec<Object> = Vec::new();
    for i in 0..n {
        let c = point(&mut s, half);
        let r = 0.05 + 0.6 * s.next_f64();
        let axis = unit(&mut s);
        let kind = (s.next_f64() * 10.0) as usize;
        let shape = match kind {
            0 if i % 7 == 0 => Shape::Plane(Box::new(Plane::new(c, axis))),
            0 | 1 => Shape::Sphere(Sphere::new(c, r)),
            2 => Shape::Rectangle(Box::new(Rectangle::new(c, unit(&mut s) * r, unit(&mut s) * r))),
            3 => Shape::Disk(Box::new(Disk::new(c, axis, r))),
            4 => Shape::Cuboid(Box::new(Cuboid::new(
                c,
                DVec3::new(r, 0.5 * r, 1.5 * r),
                point(&mut s, 180.0),
            ))),
            5 => Shape::Cuboid(Box::new(Cuboid::new(c.round(), DVec3::ONE, DVec3::ZERO))),
            6 => Shape::Cylinder(Box::new(Cylinder::new(c, axis, 2.0 * r, 0.5 * r))),
            7 => Shape::Cone(Box::new(Cone::new(c, axis, 2.0 * r, r))),
            8 => Shape::Torus(Box::new(Torus::new(c, axis, r, 0.3 * r))),
            _ if i > 0 => objects[(s.next_f64() * i as f64) as usize % i].shape.clone(),
            _ => Shape::Sphere(Sphere::new(c, r)),
        };
        objects.push(object(shape));
    }
    objects
}

/// `n` random triangles, tubes and transformed shapes (ellipsoids and boxes scaled, turned,
/// some mirrored, and moved; tori and cones sheared) among spheres, in a cube of half-side
/// `half`, with copies of earlier objects.
fn random_new_shapes(seed: u64, n: usize, half: f64) -> Vec<Object> {
    let mut s = Stream::new(seed, Purpose::Generator, 5);
    let mut objects: Vec<Object> = Vec::new();
    for i in 0..n {
        let c = point(&mut s, half);
        let r = 0.05 + 0.6 * s.next_f64();
        let axis = unit(&mut s);
        let kind = (s.next_f64() * 6.0) as usize;
        let shape = match kind {
            0 => {
                let flat = Triangle::new(c, c + unit(&mut s) * r, c + unit(&mut s) * r);
                if i % 3 == 0 {
                    // Every third a smooth triangle, of either interpolation rule.
                    let normals = [unit(&mut s), unit(&mut s), unit(&mut s)];
                    let rule = [NormalInterpolation::Linear, NormalInterpolation::Normalized][i % 2];
                    let smooth = SmoothTriangle::new(flat, normals, SmoothTriangle::FLAT_UVS, rule);
                    Shape::SmoothTriangle(Box::new(smooth.unwrap()))
                } else {
                    Shape::Triangle(flat)
                }
            }
            1 => Shape::Cylinder(Box::new(Cylinder::tube(c, axis, 2.0 * r, 0.5 * r))),
            2 => {
                // An ellipsoid or a box, scaled, turned and moved.
                let scale = DVec3::new(0.3 + s.next_f64(), 0.3 + s.next_f64(), -0.3 - s.next_f64()) * r;
                let local = if i % 2 == 0 {
                    Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0))
                } else {
                    Shape::Cuboid(Box::new(Cuboid::new(DVec3::ZERO, DVec3::ONE, DVec3::ZERO)))
                };
                Transform::from_parts(scale, point(&mut s, 180.0), c).apply(local)
            }
            3 => {
                // A torus or a cone through a shear.
                let a = point(&mut s, 0.4);
                let rows = [[1.0, a.x, 0.0, c.x], [0.0, 1.0, a.y, c.y], [a.z, 0.0, 1.0, c.z]];
                let local = if i % 2 == 0 {
                    Shape::Torus(Box::new(Torus::new(DVec3::ZERO, axis, r, 0.3 * r)))
                } else {
                    Shape::Cone(Box::new(Cone::new(DVec3::ZERO, axis, 2.0 * r, r)))
                };
                Transform::from_rows(rows).unwrap().apply(local)
            }
            4 if i > 0 => objects[(s.next_f64() * i as f64) as usize % i].shape.clone(),
            _ => Shape::Sphere(Sphere::new(c, r)),
        };
        objects.push(object(shape));
    }
    objects
}

/// `n` random spherical caps (convex and concave) and lenses (caps of either sign, with and
/// without an edge, some of them turned by a transform) among spheres, in a cube of
/// half-side `half`, with copies of earlier objects.
fn random_caps_and_lenses(seed: u64, n: usize, half: f64) -> Vec<Object> {
    let mut s = Stream::new(seed, Purpose::Generator, 6);
    let mut objects: Vec<Object> = Vec::new();
    for i in 0..n {
        let c = point(&mut s, half);
        let r = 0.05 + 0.6 * s.next_f64();
        let axis = unit(&mut s);
        let kind = (s.next_f64() * 5.0) as usize;
        let curvature = |s: &mut Stream| {
            let sign = if s.next_f64() < 0.3 { -1.0 } else { 1.0 };
            sign * r * (1.0 + 2.0 * s.next_f64())
        };
        let shape = match kind {
            0 => Shape::SphericalCap(Box::new(SphericalCap::new(c, axis, r, curvature(&mut s)))),
            1 | 2 => {
                let (c1, c2) = (curvature(&mut s), curvature(&mut s));
                let hollow = |k: f64| {
                    if k < 0.0 {
                        k.abs() - ((k - r) * (k + r)).max(0.0).sqrt()
                    } else {
                        0.0
                    }
                };
                let e = if kind == 2 && c1 > 0.0 && c2 > 0.0 {
                    0.0
                } else {
                    hollow(c1) + hollow(c2) + r * s.next_f64()
                };
                let lens = Shape::Lens(Box::new(Lens::new(c, axis, e, r, c1, c2)));
                if i % 3 == 0 {
                    Transform::from_parts(DVec3::new(1.0, 0.5, 1.5), point(&mut s, 180.0), DVec3::ZERO).apply(lens)
                } else {
                    lens
                }
            }
            3 if i > 0 => objects[(s.next_f64() * i as f64) as usize % i].shape.clone(),
            _ => Shape::Sphere(Sphere::new(c, r)),
        };
        objects.push(object(shape));
    }
    objects
}

/// Random rays from inside and around the scene, half of them aimed at an object.
fn random_rays(seed: u64, objects: &[Object], count: usize, half: f64) -> Vec<Ray> {
    let mut s = Stream::new(seed, Purpose::Generator, 2);
    (0..count)
        .map(|i| {
            let o = point(&mut s, 1.5 * half);
            let aim = objects[i % objects.len()].shape.bounds();
            let d = match aim {
                Some(b) if i % 2 == 0 && (b.centroid() - o).length() > 1e-9 => (b.centroid() - o).normalize(),
                _ => unit(&mut s),
            };
            Ray::new(o, d)
        })
        .collect()
}

/// Rays along the edges and in the faces of the objects' bounding boxes, from outside,
/// along the axes (zero direction components) and slightly tilted.
fn grazing_rays(objects: &[Object]) -> Vec<Ray> {
    let mut rays = Vec::new();
    for o in objects {
        let Some(b) = o.shape.bounds() else { continue };
        let (lo, hi) = (b.min, b.max);
        for axis in 0..3 {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            for (cu, cv) in [
                (lo[u], lo[v]),
                (hi[u], hi[v]),
                (lo[u], hi[v]),
                (0.5 * (lo[u] + hi[u]), hi[v]),
            ] {
                let mut start = DVec3::ZERO;
                start[axis] = lo[axis] - 1.0;
                start[u] = cu;
                start[v] = cv;
                let mut d = DVec3::ZERO;
                d[axis] = 1.0;
                rays.push(Ray::new(start, d));
                // The same line walked backwards, with -0.0 components.
                let mut back = start;
                back[axis] = hi[axis] + 1.0;
                rays.push(Ray::new(back, -d));
                // Tilted by a hair towards the box.
                let mut tilt = d;
                tilt[u] = 1e-12;
                rays.push(Ray::new(start, tilt.normalize()));
            }
        }
    }
    rays
}

/// Rays starting exactly at hit points (no offset), leaving in random directions, and from
/// the offset origin the tracer would use.
fn surface_rays(objects: &[Object], seeds: &[Ray]) -> Vec<Ray> {
    let linear = Accel::build_with(objects, AccelChoice::Linear);
    let mut s = Stream::new(9, Purpose::Generator, 3);
    let mut rays = Vec::new();
    for r in seeds {
        if let Some((j, h)) = linear.closest(objects, r, 0.0, f64::INFINITY) {
            let p = r.at(h.t);
            let d = unit(&mut s);
            rays.push(Ray::new(p, d));
            rays.push(Ray::new(p, -r.dir));
            let err = lumiere::math::hit_point_error(r, h.t) + objects[j].shape.surface_error(p);
            rays.push(Ray::new(lumiere::math::offset_origin(p, h.normal, err, d), d));
        }
    }
    rays
}

/// Asserts the cores agree on `ray` for closest, any and every hit, over several ranges and
/// filters. Returns whether the ray hit anything.
fn assert_agree(objects: &[Object], linear: &Accel, bvh: &Accel, ray: &Ray, what: &str) -> bool {
    let a = linear.closest(objects, ray, 0.0, f64::INFINITY);
    let b = bvh.closest(objects, ray, 0.0, f64::INFINITY);
    let bits = |h: Option<(usize, lumiere::shape::SurfaceHit)>| {
        h.map(|(j, h)| (j, h.t.to_bits(), h.normal.to_array().map(f64::to_bits)))
    };
    assert_eq!(bits(a), bits(b), "{what}: closest differs for {ray:?}");
    let t_hit = a.map_or(f64::INFINITY, |(_, h)| h.t);
    let filters: [&dyn Fn(usize) -> bool; 3] = [&|_| true, &|j| j % 2 == 0, &|j| j % 3 == 1];
    for t_max in [f64::INFINITY, t_hit, 0.5 * t_hit, 1e-9] {
        let (t_min, t_max) = if t_max.is_finite() || t_hit.is_infinite() {
            (0.0, t_max)
        } else {
            (0.0, 40.0)
        };
        let (a, b) = (
            linear.closest(objects, ray, t_min, t_max),
            bvh.closest(objects, ray, t_min, t_max),
        );
        assert_eq!(bits(a), bits(b), "{what}: closest below {t_max} for {ray:?}");
        for f in filters {
            assert_eq!(
                linear.any_hit(objects, ray, t_min, t_max, f),
                bvh.any_hit(objects, ray, t_min, t_max, f),
                "{what}: any_hit below {t_max} for {ray:?}"
            );
            let every = |accel: &Accel| {
                let mut v = Vec::new();
                accel.each_hit(objects, ray, t_min, t_max, f, &mut |j| v.push(j));
                v.sort_unstable();
                v
            };
            let all = every(linear);
            assert_eq!(all, every(bvh), "{what}: each_hit below {t_max} for {ray:?}");
            let mut dedup = all.clone();
            dedup.dedup();
            assert_eq!(all, dedup, "{what}: an object visited twice");
        }
    }
    a.is_some()
}

fn check_scene(seed: u64, n: usize) {
    let half = 2.0 + (n as f64).cbrt();
    check_objects(seed, &random_scene(seed, n, half), half);
}

/// The linear scan and the BVH on both kernels over the same objects.
struct Cores {
    linear: Accel,
    kernels: [Accel; 2],
}

impl Cores {
    fn new(objects: &[Object]) -> Self {
        Cores {
            linear: Accel::build_with(objects, AccelChoice::Linear),
            kernels: [Kernel::Widest, Kernel::Baseline].map(|k| Accel::Bvh(Bvh::with_kernel(objects, k))),
        }
    }
}

/// [`assert_agree`] on random, grazing and surface rays (and their far and tiny-component
/// variants) for `objects` within a cube of half-side `half`.
fn check_objects(seed: u64, objects: &[Object], half: f64) {
    let objects = objects.to_vec();
    let Cores { linear, kernels } = Cores::new(&objects);
    Bvh::new(&objects).check(&objects).unwrap();
    // The walks on the widest vectors the processor has, and on baseline x86-64.
    for bvh in &kernels {
        let random = random_rays(seed, &objects, 300, half);
        let mut hits = 0;
        for r in &random {
            hits += assert_agree(&objects, &linear, bvh, r, "random") as usize;
        }
        assert!(hits > 100, "only {hits} of 300 random rays hit something");
        for r in grazing_rays(&objects).iter().take(600) {
            assert_agree(&objects, &linear, bvh, r, "grazing");
        }
        for r in &surface_rays(&objects, &random) {
            assert_agree(&objects, &linear, bvh, r, "from a surface");
        }
        // Rays the `f32` box test cannot carry, tested in `f64`: a direction component too
        // small for it (but not zero), and an origin beyond `2^50` (the same line, from far
        // back).
        for r in random.iter().take(60) {
            let tiny = Ray::new(r.origin, DVec3::new(1e-20, r.dir.y, r.dir.z));
            let far = Ray::new(r.origin - r.dir * 3e15, r.dir);
            assert_agree(&objects, &linear, bvh, &tiny, "a tiny component");
            assert_agree(&objects, &linear, bvh, &far, "from far away");
        }
    }
}

/// Rays tangent to spheres, and passing a few units in the last place inside and outside
/// the tangent, through a dense pile of spheres: the BVH's leaf test, which sifts a leaf's
/// spheres (up to 31 in this tree of spheres only) in `f32`, 4 to 32 lanes at a time, and
/// tests the ones it keeps in `f64`, gives the linear scan's object, `t` and normal to the
/// bit with either kernel, and rays both hit and miss.
#[test]
fn sphere_lanes_agree_with_the_scan_on_tangent_rays() {
    let mut s = Stream::new(31, Purpose::Generator, 4);
    // More than `FINE_LEAVES_UP_TO` (4096), so that the tree has the sphere copies; as
    // dense as 2000 in a cube of side 6.
    let objects: Vec<Object> = (0..5000)
        .map(|_| {
            let r = 0.05 + 0.2 * s.next_f64();
            object(Shape::Sphere(Sphere::new(point(&mut s, 4.1), r)))
        })
        .collect();
    let back = |i: usize| 2.0 + i as f64 * 1e-3;
    let ((hits, misses), _) = rim_rays(
        &objects,
        &Cores::new(&objects),
        &mut s,
        300,
        &[-4, -1, 0, 1, 4],
        back,
        "tangent",
    );
    assert!(hits > 500 && misses > 100, "{hits} hits, {misses} misses");
}

/// For each of the first `take` spheres of `objects`, a random direction `d` and a unit
/// vector `across` it, and rays along `d` through the sphere's rim, `ulps` units in the last
/// place of its radius inside or outside it, from `back(i)` behind: both BVH kernels of
/// `cores` give the linear scan's hits. Returns the rays that hit and missed, and per
/// sphere its `d` and `across`.
fn rim_rays(
    objects: &[Object],
    cores: &Cores,
    s: &mut Stream,
    take: usize,
    ulps: &[i64],
    back: impl Fn(usize) -> f64,
    what: &str,
) -> ((u32, u32), Vec<(DVec3, DVec3)>) {
    let Cores { linear, kernels } = cores;
    let (mut hits, mut misses) = (0, 0);
    let mut directions = Vec::new();
    for (i, o) in objects.iter().enumerate().take(take) {
        let Shape::Sphere(sphere) = &o.shape else {
            unreachable!()
        };
        let d = unit(s);
        let across = d.cross(unit(s)).normalize();
        for &u in ulps {
            let reach = f64::from_bits((sphere.radius.to_bits() as i64 + u) as u64);
            let ray = Ray::new(sphere.center + across * reach - d * back(i), d);
            for bvh in kernels {
                match assert_agree(objects, linear, bvh, &ray, what) {
                    true => hits += 1,
                    false => misses += 1,
                }
            }
        }
        directions.push((d, across));
    }
    ((hits, misses), directions)
}

/// The `f32` sift of a leaf's spheres where rounding to `f32` matters most: 5000 spheres
/// of radius `1e-4` to `1e-2` a million units from the world's origin, some tiny
/// (`1e-9`), and rays grazing them from near, from `1e12` away (still sifted in `f32`),
/// from `3e15` away (beyond the sift: every object of a leaf tested), and a few starting
/// inside with `t_min < 0`: the BVH gives the linear scan's hits to the bit, on both
/// kernels.
#[test]
fn sphere_sift_agrees_with_the_scan_far_from_the_origin() {
    let mut s = Stream::new(47, Purpose::Generator, 5);
    let centre = DVec3::new(1e6, -2e6, 5e5);
    let objects: Vec<Object> = (0..5000)
        .map(|i| {
            let r = if i % 50 == 0 { 1e-9 } else { 1e-4 + 1e-2 * s.next_f64() };
            object(Shape::Sphere(Sphere::new(centre + point(&mut s, 0.5), r)))
        })
        .collect();
    Bvh::new(&objects).check(&objects).unwrap();
    let back = |i: usize| [1.0, 1e12, 3e15][i % 3];
    let cores = Cores::new(&objects);
    let ((hits, misses), directions) =
        rim_rays(&objects, &cores, &mut s, 400, &[-2, 0, 2], back, "far from the origin");
    assert!(hits > 1000 && misses > 200, "{hits} hits, {misses} misses");
    // From inside the sphere, the interval starting behind the origin.
    let Cores { linear, kernels } = &cores;
    for (o, (d, across)) in objects.iter().zip(directions) {
        let Shape::Sphere(sphere) = &o.shape else {
            unreachable!()
        };
        let inside = Ray::new(sphere.center + across * 0.5 * sphere.radius, d);
        for (t_min, t_max) in [(-1.0, 1.0), (-1e-3, f64::INFINITY)] {
            let key = |a: &Accel| {
                a.closest(&objects, &inside, t_min, t_max)
                    .map(|(j, h)| (j, h.t.to_bits()))
            };
            for bvh in kernels {
                assert_eq!(key(linear), key(bvh), "t_min {t_min}: {inside:?}");
            }
        }
    }
}

#[test]
fn cores_agree_on_small_random_scenes() {
    for (seed, n) in [(1, 1), (2, 2), (3, 5), (4, 9), (5, 17), (6, 40)] {
        check_scene(seed, n);
    }
}

#[test]
fn cores_agree_on_triangles_tubes_and_transformed_shapes() {
    for (seed, n) in [(31, 3), (32, 17), (33, 150), (34, 600)] {
        let half = 2.0 + (n as f64).cbrt();
        check_objects(seed, &random_new_shapes(seed, n, half), half);
    }
}

#[test]
fn cores_agree_on_spherical_caps_and_lenses() {
    for (seed, n) in [(41, 3), (42, 17), (43, 150), (44, 600)] {
        let half = 2.0 + (n as f64).cbrt();
        check_objects(seed, &random_caps_and_lenses(seed, n, half), half);
    }
}

#[test]
fn cores_agree_on_larger_random_scenes() {
    // 4200 objects: beyond `FINE_LEAVES_UP_TO`, with the sphere copies of the tree's leaves
    // (and NaN-radius entries for its tori and cones).
    for (seed, n) in [(7, 150), (8, 600), (9, 4200)] {
        check_scene(seed, n);
    }
}

#[test]
fn ties_go_to_the_lowest_index() {
    // Three identical spheres on the ray, the middle one first in the BVH's eyes as much as
    // in any order: the hit is object 1, the first of the identical three.
    let s = Shape::Sphere(Sphere::new(DVec3::new(0.0, 0.0, 5.0), 1.0));
    let objects: Vec<Object> = [
        Shape::Sphere(Sphere::new(DVec3::new(0.0, 0.0, 9.0), 1.0)),
        s.clone(),
        s.clone(),
        s,
    ]
    .into_iter()
    .chain((0..40).map(|i| Shape::Sphere(Sphere::new(DVec3::new(10.0 + i as f64, 0.0, 0.0), 0.5))))
    .map(object)
    .collect();
    let ray = Ray::new(DVec3::ZERO, DVec3::Z);
    for choice in [AccelChoice::Linear, AccelChoice::Bvh] {
        let (j, h) = Accel::build_with(&objects, choice)
            .closest(&objects, &ray, 0.0, f64::INFINITY)
            .unwrap();
        assert_eq!((j, h.t), (1, 4.0), "{choice:?}");
    }
}

#[test]
fn hand_checked_hits() {
    // A floor plane, a unit cube [0, 1]^3 on it, a sphere above, and 30 far spheres so the
    // BVH has a tree.
    let objects: Vec<Object> = [
        Shape::Plane(Box::new(Plane::new(DVec3::ZERO, DVec3::Z))),
        Shape::Cuboid(Box::new(Cuboid::new(DVec3::splat(0.5), DVec3::ONE, DVec3::ZERO))),
        Shape::Sphere(Sphere::new(DVec3::new(0.5, 0.5, 3.0), 0.5)),
    ]
    .into_iter()
    .chain((0..30).map(|i| Shape::Sphere(Sphere::new(DVec3::new(50.0, i as f64, 1.0), 0.4))))
    .map(object)
    .collect();
    let bvh = Accel::build_with(&objects, AccelChoice::Bvh);
    let linear = Accel::build_with(&objects, AccelChoice::Linear);
    let cases = [
        // Along the cube's bottom edge y = 0, z = 0 from x = -1: the cube's face x = 0 at t = 1
        // (the plane z = 0 contains the ray and is not hit).
        (Ray::new(DVec3::new(-1.0, 0.0, 0.0), DVec3::X), Some((1, 1.0))),
        // Along the top edge y = 1, z = 1: the cube again, at t = 1.
        (Ray::new(DVec3::new(-1.0, 1.0, 1.0), DVec3::X), Some((1, 1.0))),
        // Down onto the sphere's top from z = 5: t = 1.5.
        (Ray::new(DVec3::new(0.5, 0.5, 5.0), -DVec3::Z), Some((2, 1.5))),
        // Down past the sphere (x = 1.5): the floor at t = 5.
        (Ray::new(DVec3::new(1.5, 0.5, 5.0), -DVec3::Z), Some((0, 5.0))),
        // Starting on the cube's top face, going up: the sphere's bottom at z = 2.5.
        (Ray::new(DVec3::new(0.5, 0.5, 1.0), DVec3::Z), Some((2, 1.5))),
        // Upwards from above everything: nothing.
        (Ray::new(DVec3::new(0.5, 0.5, 4.0), DVec3::Z), None),
    ];
    for (ray, want) in cases {
        for accel in [&linear, &bvh] {
            let got = accel.closest(&objects, &ray, 0.0, f64::INFINITY).map(|(j, h)| (j, h.t));
            assert_eq!(got, want, "{} for {ray:?}", accel.name());
        }
    }
    // Any-hit stops short of the light: a shadow ray from the floor under the sphere to a
    // light at z = 10 is blocked (by the sphere), one to z = 2 is not.
    let up = Ray::new(DVec3::new(0.5, 0.5, 1.0 + 1e-9), DVec3::Z);
    assert!(bvh.any_hit(&objects, &up, 0.0, 9.0, &|_| true));
    assert!(!bvh.any_hit(&objects, &up, 0.0, 1.0, &|_| true));
    assert!(!bvh.any_hit(&objects, &up, 0.0, 9.0, &|j| j != 2));
}

/// Trees deeper than the medium traversal stack (spheres of radius `0.1 x` at `x = r^k`: the
/// splits peel them off a few at a time) are traversed with the full one, and agree with the
/// linear scan: with ratio 3, whose far spheres lie beyond `f32`'s range for the slot test
/// (`2^50`), so that every ray is tested in `f64`; and with ratio 1.1, within it.
#[test]
fn deep_trees_agree_with_the_linear_scan() {
    for (ratio, count) in [(3f64, 60), (1.1, 360)] {
        let objects: Vec<Object> = (0..count)
            .map(|i| {
                object(Shape::Sphere(Sphere::new(
                    DVec3::X * ratio.powi(i),
                    0.1 * ratio.powi(i),
                )))
            })
            .collect();
        let tree = Bvh::new(&objects);
        tree.check(&objects).unwrap();
        // The medium stack holds 64 entries, enough for a depth of 20 (the `f64` test
        // always takes the full one).
        assert!(
            ratio > 2.0 || tree.depth() > 20,
            "ratio {ratio}: depth {}",
            tree.depth()
        );
        let (linear, bvh) = (
            Accel::build_with(&objects, AccelChoice::Linear),
            Accel::build_with(&objects, AccelChoice::Bvh),
        );
        let mut hits = 0;
        for i in 0..count {
            // Along the line from beyond its far end, and across it at each sphere.
            let x = ratio.powi(i);
            let along = Ray::new(DVec3::new(-1.0, 0.05, 0.0), DVec3::X);
            let across = Ray::new(DVec3::new(x, -(0.2 * x + 1.0), 0.0), DVec3::Y);
            hits += assert_agree(&objects, &linear, &bvh, &along, "along") as usize;
            hits += assert_agree(&objects, &linear, &bvh, &across, "across") as usize;
        }
        assert_eq!(hits, 2 * count as usize);
    }
}

#[test]
fn bvh_invariants_on_degenerate_inputs() {
    let same = |n: usize| -> Vec<Object> {
        (0..n)
            .map(|_| object(Shape::Sphere(Sphere::new(DVec3::ONE, 1.0))))
            .collect()
    };
    let planes: Vec<Object> = (0..20)
        .map(|i| object(Shape::Plane(Box::new(Plane::new(DVec3::Z * i as f64, DVec3::Z)))))
        .collect();
    let line: Vec<Object> = (0..1000)
        .map(|i| object(Shape::Sphere(Sphere::new(DVec3::X * (1.5f64).powi(i % 60), 0.1))))
        .collect();
    for objects in [
        Vec::new(),
        same(1),
        same(2),
        same(100),
        planes,
        line,
        random_scene(11, 3000, 6.0),
    ] {
        let bvh = Bvh::new(&objects);
        bvh.check(&objects).unwrap();
        // 64 bytes an object at most, past the root node (a tree of one object has one),
        // and with spheres their copies in leaf order: at most 48 bytes an object and 31
        // `f32` values of padding.
        let spheres = objects.iter().any(|o| matches!(o.shape, Shape::Sphere(_)));
        let copies = if spheres { 48 * objects.len() + 124 } else { 0 };
        assert!(
            bvh.bytes() <= 64 * objects.len() + 128 + copies,
            "{} bytes",
            bvh.bytes()
        );
    }
    // Rays through a pile of identical spheres hit the first.
    let objects = same(100);
    let ray = Ray::new(DVec3::new(1.0, 1.0, -5.0), DVec3::Z);
    let (j, h) = Bvh::new(&objects).closest(&objects, &ray, 0.0, f64::INFINITY).unwrap();
    assert_eq!((j, h.t), (0, 5.0));
}

#[test]
fn the_tree_does_not_depend_on_the_thread_count() {
    let objects = random_scene(12, 20_000, 25.0);
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let three = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
    let a = one.install(|| Bvh::new(&objects));
    let b = three.install(|| Bvh::new(&objects));
    assert!(a == b, "the trees differ");
    // Subtrees built as tasks (of 4096 objects here) and spliced in: a sound tree.
    a.check(&objects).unwrap();
}

#[test]
fn every_shape_honours_the_t_max_contract() {
    // intersect(ray, a, b) for b below the full hit's t is None; for b above it, the same
    // hit to the bit.
    let mut objects = random_scene(13, 400, 4.0);
    objects.extend(random_new_shapes(14, 200, 4.0));
    objects.extend(random_caps_and_lenses(15, 200, 4.0));
    let rays = random_rays(13, &objects, 1200, 4.0);
    let mut checked = [0usize; 12];
    for o in &objects {
        for r in &rays {
            let Some(full) = o.shape.intersect(r, 0.0, f64::INFINITY) else {
                continue;
            };
            let kind = [
                "plane",
                "rectangle",
                "disk",
                "sphere",
                "box",
                "cylinder",
                "cone",
                "torus",
                "triangle",
                "tube",
                "spherical_cap",
                "lens",
            ]
            .iter()
            .position(|k| *k == o.shape.kind())
            .unwrap();
            checked[kind] += 1;
            for b in [full.t * 1.5, full.t + 1e-9, f64::from_bits(full.t.to_bits() + 1)] {
                assert_eq!(
                    o.shape.intersect(r, 0.0, b),
                    Some(full),
                    "{:?} {r:?} below {b}",
                    o.shape
                );
            }
            for b in [full.t, 0.5 * full.t] {
                assert_eq!(o.shape.intersect(r, 0.0, b), None, "{:?} {r:?} below {b}", o.shape);
            }
        }
    }
    assert!(checked.iter().all(|&c| c > 5), "hits by kind: {checked:?}");
}

/// A mesh scene: the committed icosahedron at five places (turned, scaled, one mirrored),
/// a generated soup of 3000 triangles, and a floor.
fn mesh_objects() -> Vec<Object> {
    let mut text =
        String::from("[image]\nwidth = 8\nheight = 6\n[camera]\nposition = [0, -8, 5]\nlook_at = [0, 0, 0]\n");
    text += "[[shapes]]\ntype = \"plane\"\npoint = [0, 0, -3]\nnormal = [0, 0, 1]\n";
    for k in 0..5 {
        let x = 2.5 * k as f64 - 5.0;
        let mirror = if k == 3 { -1.0 } else { 1.0 };
        text += &format!(
            "[[shapes]]\ntype = \"mesh\"\nfile = \"scenes/icosahedron.obj\"\n\
             transform = {{ scale = [{mirror}, 1, {}], rotation = [{}, 10, 20], translation = [{x}, 0, 0] }}\n",
            1.0 + 0.2 * k as f64,
            17 * k
        );
    }
    text += "[[generate]]\nkind = \"triangles\"\ncount = 3000\nseed = 4\nmin = [-6, -6, -2]\nmax = [6, 6, 2]\nradius = [0.05, 0.4]\n";
    lumiere::scene::parse(&text, "mesh.toml").unwrap().objects
}

#[test]
fn cores_agree_on_meshes() {
    let objects = mesh_objects();
    assert_eq!(objects.len(), 1 + 5 * 20 + 3000);
    check_objects(21, &objects, 6.0);
    // Rays through the icosahedra's vertices (each shared by five triangles) and their
    // edges' midpoints, from points outside roughly along the way out from the
    // icosahedron's center (so that the ray goes on into the solid): the cores agree, and
    // none of these rays slips between the mesh's triangles.
    let linear = Accel::build_with(&objects, AccelChoice::Linear);
    let bvh = Accel::build_with(&objects, AccelChoice::Bvh);
    let meshes = &objects[1..101];
    let mesh_scan = Accel::build_with(meshes, AccelChoice::Linear);
    let mut s = Stream::new(22, Purpose::Generator, 4);
    let mut aimed = 0;
    for (k, o) in meshes.iter().enumerate() {
        let Shape::Triangle(t) = &o.shape else { panic!("{o:?}") };
        let center = DVec3::new(2.5 * (k / 20) as f64 - 5.0, 0.0, 0.0);
        let [a, b, c] = t.points();
        for target in [a, 0.5 * (a + b), b, 0.5 * (b + c), c] {
            let out = ((target - center).normalize() + unit(&mut s) * 0.3).normalize();
            let from = target + out * 3.0;
            let ray = Ray::new(from, (target - from).normalize());
            assert_agree(&objects, &linear, &bvh, &ray, "through a mesh vertex or edge");
            aimed += 1;
            let hit = mesh_scan.closest(meshes, &ray, 0.0, f64::INFINITY);
            assert!(hit.is_some(), "{ray:?} slipped through the mesh at {target}");
        }
    }
    assert_eq!(aimed, 500);
}

/// Renders `scene` with both cores; the float pixels must be identical.
fn assert_same_image(scene: &lumiere::scene::Scene) {
    let film = |choice| render(&World::with_accel(scene, choice), &|| {}).0;
    let (a, b) = (film(AccelChoice::Linear), film(AccelChoice::Bvh));
    let bits = |f: &lumiere::film::Film| -> Vec<u64> {
        f.pixels.iter().flat_map(|p| p.to_array().map(f64::to_bits)).collect()
    };
    assert!(bits(&a) == bits(&b), "the images differ");
}

#[test]
fn images_are_identical_with_either_core() {
    // The reference scene at full size, and a generated scene of mixed shapes.
    assert_same_image(&scene("reference.toml"));
    let mut mixed = scene("spheres-1k.toml");
    mixed.settings.width = 200;
    mixed.settings.height = 150;
    assert_same_image(&mixed);
    let text = std::fs::read_to_string(repo("scenes/spheres-1k.toml"))
        .unwrap()
        .replace("kind = \"spheres\"", "kind = \"mixed\"")
        .replace("count = 1000", "count = 300")
        .replace("width = 800", "width = 160")
        .replace("height = 600", "height = 120")
        .replace("depth = 1", "depth = 3");
    let mut mixed = lumiere::scene::parse(&text, "mixed.toml").unwrap();
    mixed.materials[1].kr = 0.5;
    assert_same_image(&mixed);
    // A triangle, a tube, an ellipsoid and a mesh, with reflections.
    let mut geometry = scene("geometry.toml");
    geometry.settings.width = 160;
    geometry.settings.height = 120;
    assert_same_image(&geometry);
}

#[test]
fn cli_accel_choice_gives_the_same_bytes() {
    let dir = temp_dir("accel-cli");
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let scene = repo("scenes/spheres-1k.toml");
    for core in ["linear", "bvh", "auto"] {
        let o = lumiere(&[
            "render",
            scene.to_str().unwrap(),
            "-o",
            &out(&format!("{core}.png")),
            "--width",
            "120",
            "--height",
            "90",
            "--accel",
            core,
            "--stats",
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        let stdout = String::from_utf8_lossy(&o.stdout);
        let want = if core == "linear" { "linear" } else { "bvh" };
        assert!(
            stdout.contains(&format!("intersection core: {want} over 1001 objects")),
            "{stdout}"
        );
    }
    let bytes = |name: &str| std::fs::read(dir.join(name)).unwrap();
    assert_eq!(bytes("linear.png"), bytes("bvh.png"));
    assert_eq!(bytes("linear.png"), bytes("auto.png"));
    let o = lumiere(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        &out("x.png"),
        "--accel",
        "kd-tree",
    ]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn auto_keeps_the_course_scenes_on_the_linear_scan() {
    for name in [
        "reference.toml",
        "mirrors.toml",
        "prism.toml",
        "shading.toml",
        "soft-shadows.toml",
    ] {
        let s = scene(name);
        assert_eq!(World::new(&s).accel().name(), "linear", "{name}");
    }
    assert_eq!(World::new(&scene("spheres-1k.toml")).accel().name(), "bvh");
}

/// Packets of 1 to `lumiere::accel::PACKET` (16) rays from one origin, their directions
/// spread by `spread` around the axis to an object (narrow ones share an octant and are walked
/// together, wide ones mostly do not and fall back to single walks), with rays the `f32`
/// test cannot carry among them: on both kernels, each ray's closest hit is the linear
/// scan's to the bit (object, `t` and normal), below several `t_max`, and each any-hit
/// answer too, under several filters.
fn check_packets(objects: &[Object], seed: u64, half: f64) -> (usize, usize) {
    let Cores { linear, kernels } = Cores::new(objects);
    let mut s = Stream::new(seed, Purpose::Generator, 6);
    let bits = |h: Option<(usize, lumiere::shape::SurfaceHit)>| {
        h.map(|(j, h)| (j, h.t.to_bits(), h.normal.to_array().map(f64::to_bits)))
    };
    let filters: [&dyn Fn(usize) -> bool; 2] = [&|_| true, &|j| j % 3 != 1];
    let (mut hits, mut lanes) = (0, 0);
    for p in 0..160 {
        let origin = point(&mut s, 1.5 * half);
        // Aimed at an object, so that narrow packets hit it.
        let target = objects[(p * 7) % objects.len()]
            .shape
            .bounds()
            .map_or(DVec3::ZERO, |b| b.centroid());
        let axis = (target - origin).normalize();
        let spread = [0.002, 0.03, 1.0][p % 3];
        let len = 1 + p % lumiere::accel::PACKET;
        let mut rays: Vec<Ray> = (0..len)
            .map(|_| Ray::new(origin, (axis + unit(&mut s) * spread).normalize()))
            .collect();
        if p % 16 == 5 {
            // A direction component too small for the `f32` test (not zero).
            rays[len - 1] = Ray::new(origin, DVec3::new(1e-20, axis.y, axis.z).normalize());
        }
        for t_max in [f64::INFINITY, 0.6 * half, 1e-9] {
            let mut want = Vec::new();
            for r in &rays {
                want.push(bits(linear.closest(objects, r, 0.0, t_max)));
            }
            for bvh in &kernels {
                let mut out = vec![None; len];
                bvh.closest_packet(objects, &rays, 0.0, t_max, &mut out);
                let got: Vec<_> = out.into_iter().map(bits).collect();
                assert_eq!(got, want, "packet {p} below {t_max}");
                for f in filters {
                    let want = linear.any_hit_packet(objects, &rays, 0.0, t_max, f);
                    assert_eq!(bvh.any_hit_packet(objects, &rays, 0.0, t_max, f), want, "packet {p}");
                }
            }
            hits += want.iter().filter(|h| h.is_some()).count();
            lanes += len;
        }
    }
    (hits, lanes)
}

#[test]
fn packets_agree_with_the_linear_scan() {
    // Every shape kind, planes (tested before the tree) among them.
    let half = 2.0 + 60f64.cbrt();
    let (hits, lanes) = check_packets(&random_scene(12, 60, half), 12, half);
    assert!(hits > lanes / 5 && hits < lanes, "{hits} hits of {lanes}");
    // A pile of spheres large enough for the tree's sifted leaves of up to 31.
    let mut s = Stream::new(33, Purpose::Generator, 4);
    let pile: Vec<Object> = (0..6000)
        .map(|_| {
            object(Shape::Sphere(Sphere::new(
                point(&mut s, 5.0),
                0.05 + 0.2 * s.next_f64(),
            )))
        })
        .collect();
    let (hits, lanes) = check_packets(&pile, 34, 5.0);
    assert!(hits > lanes / 3 && hits < lanes, "{hits} hits of {lanes}");
}
