//! The intersection cores on the same rays: the linear scan, our BVH, and the `obvhs`
//! crate's compressed wide BVH (CWBVH) traversed with our own shape intersection, so every
//! report carries a ratio against a well-known peer. For N = 8 to 1 000 000 objects
//! (spheres, and a mix of spheres, tori and cones), coherent camera rays and incoherent
//! random rays, closest hit and any hit; BVH build time (ours and obvhs's); and the
//! crossover N on course-like scenes (a floor plane and N mixed shapes).
//!
//! `cargo bench --bench intersect -- --warm-up-time 1 --measurement-time 2`, then
//! `cargo run --release --example intersect_table` prints the BENCHMARKS.md tables from
//! `target/criterion`.
//!
//! The scenes are the slab of scenes/spheres-1k.toml: centers in [-10, 10]^2 x [0, 1],
//! radii scaled by sqrt(1000 / N) so that a ray crosses about as many objects at every N.
//! The linear scan at large N traces fewer rays (its throughput is still per ray).

#[path = "common/rays.rs"]
mod rays;

use criterion::{BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main};
use glam::{DVec3, Vec3A};
use lumiere::accel::{Accel, AccelChoice, Bvh};
use lumiere::camera::Camera;
use lumiere::math::Ray;
use lumiere::scene::Object;
use lumiere::scene::generate::{Generate, GenerateKind};
use lumiere::shape::{Plane, Shape, SurfaceHit};
use obvhs::cwbvh::{CwBvh, builder::build_cwbvh};
use obvhs::{Boundable, BvhBuildParams};
use rays::{camera_rays, incoherent_rays};
use std::hint::black_box;
use std::time::Duration;

const SIZES: [usize; 5] = [8, 64, 1_000, 100_000, 1_000_000];
const RAYS: usize = 64 * 64;
/// Object tests the linear scan may spend per timed iteration (bounds its ray count).
const LINEAR_BUDGET: usize = 20_000_000;

fn objects(kind: GenerateKind, n: usize) -> Vec<Object> {
    let scale = (1000.0 / n as f64).sqrt();
    Generate {
        kind,
        count: n,
        seed: 6,
        min: DVec3::new(-10.0, -10.0, 0.0),
        max: DVec3::new(10.0, 10.0, 1.0),
        radius: (0.2 * scale, 0.4 * scale),
        materials: vec![0],
    }
    .objects(0)
}

/// 64 x 64 camera rays of the scenes/spheres-1k.toml camera.
fn coherent_rays() -> Vec<Ray> {
    let cam = Camera::new(DVec3::new(0.0, -16.0, 8.0), DVec3::ZERO, DVec3::Z, 50.0, 1.0);
    camera_rays(&cam, 64)
}

/// An object's box for obvhs: our f64 bounds, widened by a relative 1e-6 and converted to
/// f32 (obvhs's own ray-box test is f32 too).
struct Boxed(obvhs::aabb::Aabb);

impl Boundable for Boxed {
    fn aabb(&self) -> obvhs::aabb::Aabb {
        self.0
    }
}

fn obvhs_build(objects: &[Object]) -> CwBvh {
    let boxes: Vec<Boxed> = objects
        .iter()
        .map(|o| {
            let b = o.shape.bounds().expect("bounded objects only");
            let pad = (b.max - b.min).max_element() * 1e-6 + 1e-6 * b.max.abs().max(b.min.abs()).max_element();
            let f = |v: DVec3| Vec3A::new(v.x as f32, v.y as f32, v.z as f32);
            Boxed(obvhs::aabb::Aabb::new(f(b.min - pad), f(b.max + pad)))
        })
        .collect();
    build_cwbvh(&boxes, BvhBuildParams::medium_build(), &mut Duration::default())
}

fn obvhs_ray(ray: &Ray) -> obvhs::ray::Ray {
    let f = |v: DVec3| Vec3A::new(v.x as f32, v.y as f32, v.z as f32);
    obvhs::ray::Ray::new_inf(f(ray.origin), f(ray.dir))
}

/// Closest hit through obvhs's traversal, our intersection in f64 (the f32 `t` handed back
/// for its pruning is rounded up so an equal hit is never pruned).
fn obvhs_closest(bvh: &CwBvh, objects: &[Object], ray: &Ray) -> Option<(usize, SurfaceHit)> {
    let mut best: Option<(usize, SurfaceHit)> = None;
    let mut hit = obvhs::ray::RayHit::none();
    bvh.ray_traverse(obvhs_ray(ray), &mut hit, |_, id| {
        let j = bvh.primitive_indices[id] as usize;
        let limit = best.map_or(f64::INFINITY, |(_, h)| h.t);
        match objects[j].shape.intersect(ray, 0.0, limit) {
            Some(h) => {
                best = Some((j, h));
                let t = h.t as f32;
                if (t as f64) < h.t { t * (1.0 + f32::EPSILON) } else { t }
            }
            None => f32::INFINITY,
        }
    });
    best
}

fn obvhs_any(bvh: &CwBvh, objects: &[Object], ray: &Ray) -> bool {
    !bvh.ray_traverse_miss(obvhs_ray(ray), |_, id| {
        let j = bvh.primitive_indices[id] as usize;
        if objects[j].shape.occludes(ray, 0.0, f64::INFINITY) {
            0.0
        } else {
            f32::INFINITY
        }
    })
}

fn kind_name(k: GenerateKind) -> &'static str {
    match k {
        GenerateKind::Spheres => "spheres",
        GenerateKind::Mixed => "mixed",
        GenerateKind::Triangles => "triangles",
    }
}

/// Checks once, untimed, that the three cores agree on `rays`, and says how many hit.
fn agreement(label: &str, objects: &[Object], linear: &Accel, bvh: &Accel, peer: &CwBvh, rays: &[Ray]) {
    let key = |h: Option<(usize, SurfaceHit)>| h.map(|(j, h)| (j, h.t.to_bits()));
    let (mut hits, mut peer_differs) = (0, 0);
    for r in rays {
        let a = bvh.closest(objects, r, 0.0, f64::INFINITY);
        assert_eq!(key(a), key(linear.closest(objects, r, 0.0, f64::INFINITY)), "{label}");
        hits += a.is_some() as usize;
        peer_differs += (key(a) != key(obvhs_closest(peer, objects, r))) as usize;
    }
    eprintln!(
        "{label}: {hits} of {} rays hit; linear = bvh on all; obvhs differs on {peer_differs}",
        rays.len()
    );
}

fn cores(c: &mut Criterion) {
    let ray_sets = [("coherent", coherent_rays()), ("incoherent", incoherent_rays(RAYS))];
    for kind in [GenerateKind::Spheres, GenerateKind::Mixed] {
        for n in SIZES {
            let objects = objects(kind, n);
            let linear = Accel::build_with(&objects, AccelChoice::Linear);
            let bvh = Accel::build_with(&objects, AccelChoice::Bvh);
            let peer = obvhs_build(&objects);
            for (rays_name, rays) in &ray_sets {
                // Every k-th ray, so that the subset covers the whole image or volume.
                let few: Vec<Ray> = rays.iter().step_by(RAYS.div_ceil(LINEAR_BUDGET / n)).copied().collect();
                let few = &few[..];
                agreement(
                    &format!("{}/{n}/{rays_name}", kind_name(kind)),
                    &objects,
                    &linear,
                    &bvh,
                    &peer,
                    few,
                );
                for query in ["closest", "any"] {
                    let mut g = c.benchmark_group(format!("{query}/{}/{n}/{rays_name}", kind_name(kind)));
                    g.sample_size(10).sampling_mode(SamplingMode::Flat);
                    let run = |accel: &Accel, r: &Ray| match query {
                        "closest" => accel.closest(&objects, r, 0.0, f64::INFINITY).is_some(),
                        _ => accel.any_hit(&objects, r, 0.0, f64::INFINITY, &|_| true),
                    };
                    g.throughput(Throughput::Elements(few.len() as u64));
                    g.bench_function("linear", |b| {
                        b.iter(|| few.iter().filter(|r| run(&linear, black_box(r))).count())
                    });
                    g.throughput(Throughput::Elements(rays.len() as u64));
                    g.bench_function("bvh", |b| {
                        b.iter(|| rays.iter().filter(|r| run(&bvh, black_box(r))).count())
                    });
                    g.bench_function("obvhs", |b| {
                        b.iter(|| {
                            rays.iter()
                                .filter(|r| match query {
                                    "closest" => obvhs_closest(&peer, &objects, black_box(r)).is_some(),
                                    _ => obvhs_any(&peer, &objects, black_box(r)),
                                })
                                .count()
                        })
                    });
                    g.finish();
                }
            }
            let mut g = c.benchmark_group(format!("build/{}", kind_name(kind)));
            g.sample_size(10).sampling_mode(SamplingMode::Flat);
            g.throughput(Throughput::Elements(n as u64));
            g.bench_with_input(BenchmarkId::new("bvh", n), &objects, |b, o| b.iter(|| Bvh::new(o)));
            g.bench_with_input(BenchmarkId::new("obvhs", n), &objects, |b, o| b.iter(|| obvhs_build(o)));
            g.finish();
            eprintln!(
                "memory/{}/{n}: bvh {} bytes ({:.1} bytes/object), {} nodes",
                kind_name(kind),
                bvh.bytes(),
                bvh.bytes() as f64 / n as f64,
                Bvh::new(&objects).node_count()
            );
        }
    }
}

/// Course-like scenes: a floor plane and N mixed shapes in a 6 x 6 x 2 box, the reference
/// scene's camera; camera rays (closest hit) and rays towards a light (any hit).
fn crossover(c: &mut Criterion) {
    let cam = Camera::new(
        DVec3::new(0.0, -8.0, 5.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::Z,
        60.0,
        4.0 / 3.0,
    );
    let rays: Vec<Ray> = (0..64 * 48)
        .map(|i| cam.ray((i % 64) as f64 + 0.5, (i / 64) as f64 + 0.5, 64, 48))
        .collect();
    for n in [2, 4, 8, 12, 16, 24, 32, 48, 64] {
        let mut objects = vec![Object {
            name: Default::default(),
            shape: Shape::Plane(Box::new(Plane::new(DVec3::ZERO, DVec3::Z))),
            material: 0,
        }];
        objects.extend(
            Generate {
                kind: GenerateKind::Mixed,
                count: n,
                seed: 3,
                min: DVec3::new(-3.0, -2.0, 0.5),
                max: DVec3::new(3.0, 4.0, 2.5),
                radius: (0.5, 1.0),
                materials: vec![0],
            }
            .objects(0),
        );
        let linear = Accel::build_with(&objects, AccelChoice::Linear);
        let bvh = Accel::build_with(&objects, AccelChoice::Bvh);
        // Shadow rays from the camera rays' hits towards a point light at (2, -2, 8).
        let shadows: Vec<(Ray, f64)> = rays
            .iter()
            .filter_map(|r| {
                let (_, h) = linear.closest(&objects, r, 0.0, f64::INFINITY)?;
                let p = r.at(h.t) + h.normal * 1e-6;
                let to = DVec3::new(2.0, -2.0, 8.0) - p;
                Some((Ray::new(p, to.normalize()), to.length()))
            })
            .collect();
        let mut g = c.benchmark_group(format!("crossover/{n}"));
        g.sample_size(10).sampling_mode(SamplingMode::Flat);
        g.throughput(Throughput::Elements((rays.len() + shadows.len()) as u64));
        for accel in [&linear, &bvh] {
            g.bench_function(accel.name(), |b| {
                b.iter(|| {
                    let hits = rays
                        .iter()
                        .filter(|r| accel.closest(&objects, black_box(r), 0.0, f64::INFINITY).is_some())
                        .count();
                    let blocked = shadows
                        .iter()
                        .filter(|(r, t)| accel.any_hit(&objects, black_box(r), 0.0, *t, &|_| true))
                        .count();
                    hits + blocked
                })
            });
        }
        g.finish();
    }
}

criterion_group!(benches, crossover, cores);
criterion_main!(benches);
