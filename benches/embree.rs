//! lumiere's BVH against Embree 3 on the million spheres of scenes/spheres-1m.toml, with the
//! same rays: 1000 x 1000 coherent camera rays of the scene's camera, and 1 000 000
//! incoherent rays made as benches/intersect.rs makes them (origins in the slab grown by 2,
//! directions uniform on the sphere). Closest hit and any hit (to infinity), on 1 and 2
//! threads; both kernels one ray a call and, for coherent rays, in packets of 16
//! consecutive rays (lumiere's `closest_packet` and `any_hit_packet`, Embree's
//! `rtcIntersect16` and `rtcOccluded16`).
//!
//! Embree comes from Debian's libembree-dev (3.13.5) through the embree3 crate, behind the
//! `embree` feature (off in CI):
//!
//! ```sh
//! sudo apt-get install libembree-dev
//! cargo bench --features embree --bench embree
//! ```
//!
//! Embree's spheres are f32 (`RTC_GEOMETRY_TYPE_SPHERE_POINT`), lumiere's f64, so the hits
//! are compared by object: the bench prints the share of rays on which both kernels report
//! the same closest object (or both miss), and the same any-hit answer.
//!
//! The two kernels are timed in pairs: in each of [`ROUNDS`] rounds the rays are traced in
//! slices of [`SLICE`], each slice by both kernels one after the other (which goes first
//! alternates from slice to slice), so that both meet the machine in the same state and its
//! drift cancels out of their ratio. A rate is all the rays traced over the kernel's summed
//! time; the last column is the smallest and largest ratio of one round's sums. The table is
//! printed as BENCHMARKS.md holds it.

#[path = "common/rays.rs"]
mod rays;

use embree3::{
    BufferUsage, Device, Format, GeometryKind, Hit16, IntersectContext, Ray as EmbreeRay, Ray16, RayHit, RayHit16,
    Scene, ValidMask, ValidMaskN,
};
use glam::DVec3;
use lumiere::accel::{Accel, AccelChoice};
use lumiere::camera::Camera;
use lumiere::math::Ray;
use lumiere::scene::Object;
use lumiere::shape::Shape;
use rayon::prelude::*;
use rays::{camera_rays, incoherent_rays};
use std::path::Path;
use std::time::Instant;

const SIDE: u32 = 1000;
const INCOHERENT: usize = 1_000_000;
const ROUNDS: usize = 5;
/// Rays the two kernels trace in turn (16 tasks).
const SLICE: usize = 65_536;
/// Rays a task traces in a row (a chunk of [`PACKET`]-ray packets for the packet calls).
const TASK: usize = 4096;
const MISS: u32 = u32::MAX;
/// Rays a packet holds: lumiere's widest and Embree's.
const PACKET: usize = 16;
const _: () = assert!(PACKET == lumiere::accel::PACKET);

/// The spheres of scenes/spheres-1m.toml (its floor plane left out: Embree gets spheres
/// only) and its camera.
fn spheres_and_camera() -> (Vec<Object>, Camera) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/spheres-1m.toml");
    let scene = lumiere::scene::load(&path).expect("scenes/spheres-1m.toml loads");
    let spheres: Vec<Object> = scene
        .objects
        .into_iter()
        .filter(|o| matches!(o.shape, Shape::Sphere(_)))
        .collect();
    let c = &scene.camera;
    (spheres, Camera::new(c.position, c.look_at, c.up, c.vfov_deg, 1.0))
}

fn embree_scene<'a>(device: &Device, spheres: &[Object]) -> Scene<'a> {
    let mut scene = device.create_scene().expect("an Embree scene");
    let mut geometry = device
        .create_geometry(GeometryKind::SPHERE_POINT)
        .expect("an Embree sphere geometry");
    let points: Vec<[f32; 4]> = spheres
        .iter()
        .map(|o| match &o.shape {
            Shape::Sphere(s) => [s.center.x as f32, s.center.y as f32, s.center.z as f32, s.radius as f32],
            _ => unreachable!("spheres only"),
        })
        .collect();
    geometry
        .set_new_buffer::<[f32; 4]>(BufferUsage::VERTEX, 0, Format::FLOAT4, 16, points.len())
        .expect("a vertex buffer")
        .copy_from_slice(&points);
    let geometry = geometry.commit();
    scene.attach_geometry(&geometry);
    scene.commit();
    scene
}

fn f32x3(v: DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// What one kernel answers for one ray: the closest object (or [`MISS`]), or whether
/// anything is hit.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Query {
    Closest,
    Any,
}

struct Kernels<'a, 's> {
    spheres: &'a [Object],
    accel: &'a Accel,
    embree: &'a Scene<'s>,
}

impl Kernels<'_, '_> {
    fn lumiere(&self, query: Query, rays: &[Ray], out: &mut [u32]) {
        for (ray, out) in rays.iter().zip(out) {
            *out = match query {
                Query::Closest => self
                    .accel
                    .closest(self.spheres, ray, 0.0, f64::INFINITY)
                    .map_or(MISS, |(i, _)| i as u32),
                Query::Any => self.accel.any_hit(self.spheres, ray, 0.0, f64::INFINITY, &|_| true) as u32,
            };
        }
    }

    fn embree_single(&self, query: Query, coherent: bool, rays: &[Ray], out: &mut [u32]) {
        let mut ctx = if coherent {
            IntersectContext::coherent()
        } else {
            IntersectContext::incoherent()
        };
        for (ray, out) in rays.iter().zip(out) {
            let mut r = EmbreeRay::segment(f32x3(ray.origin), f32x3(ray.dir), 0.0, f32::INFINITY);
            *out = match query {
                Query::Closest => {
                    let mut hit = RayHit::from(r);
                    self.embree.intersect(&mut ctx, &mut hit);
                    if hit.hit.is_valid() { hit.hit.primID } else { MISS }
                }
                Query::Any => self.embree.occluded(&mut ctx, &mut r) as u32,
            };
        }
    }

    /// lumiere's answers by packets of [`PACKET`] consecutive rays.
    fn lumiere_packets(&self, query: Query, rays: &[Ray], out: &mut [u32]) {
        let mut hits = [None; PACKET];
        for (rays, out) in rays.chunks(PACKET).zip(out.chunks_mut(PACKET)) {
            match query {
                Query::Closest => {
                    let hits = &mut hits[..rays.len()];
                    self.accel.closest_packet(self.spheres, rays, 0.0, f64::INFINITY, hits);
                    for (out, hit) in out.iter_mut().zip(hits) {
                        *out = hit.map_or(MISS, |(i, _)| i as u32);
                    }
                }
                Query::Any => {
                    let any = self
                        .accel
                        .any_hit_packet(self.spheres, rays, 0.0, f64::INFINITY, &|_| true);
                    for (k, out) in out.iter_mut().enumerate() {
                        *out = any >> k & 1;
                    }
                }
            }
        }
    }

    /// Embree's answers by packets of [`PACKET`] consecutive rays.
    fn embree_packets(&self, query: Query, rays: &[Ray], out: &mut [u32]) {
        let mut ctx = IntersectContext::coherent();
        for (rays, out) in rays.chunks(PACKET).zip(out.chunks_mut(PACKET)) {
            let mut valid = AlignedMask(ValidMaskN::new([ValidMask::Invalid; PACKET]));
            let mut packet = RayHit16 {
                ray: Ray16::default(),
                hit: Hit16::new(),
            };
            for (k, ray) in rays.iter().enumerate() {
                valid.0.lanes_mut()[k] = ValidMask::Valid;
                let (o, d) = (f32x3(ray.origin), f32x3(ray.dir));
                let p = &mut packet.ray;
                (p.org_x[k], p.org_y[k], p.org_z[k]) = (o[0], o[1], o[2]);
                (p.dir_x[k], p.dir_y[k], p.dir_z[k]) = (d[0], d[1], d[2]);
                (p.tnear[k], p.tfar[k], p.mask[k]) = (0.0, f32::INFINITY, u32::MAX);
            }
            match query {
                Query::Closest => {
                    self.embree.intersect16(&mut ctx, &mut packet, &valid.0);
                    for (k, out) in out.iter_mut().enumerate() {
                        *out = if packet.hit.geomID[k] == MISS {
                            MISS
                        } else {
                            packet.hit.primID[k]
                        };
                    }
                }
                Query::Any => {
                    // An occluded ray comes back with `tfar = -inf`.
                    self.embree.occluded16(&mut ctx, &mut packet.ray, &valid.0);
                    for (k, out) in out.iter_mut().enumerate() {
                        *out = u32::from(packet.ray.tfar[k] == f32::NEG_INFINITY);
                    }
                }
            }
        }
    }
}

/// Embree reads a 16-wide valid mask at 64-byte alignment.
#[repr(C, align(64))]
struct AlignedMask(ValidMaskN<PACKET>);

/// Wall time of `trace` over every ray on `pool`, one task per [`TASK`] rays.
fn timed(pool: &rayon::ThreadPool, rays: &[Ray], out: &mut [u32], trace: &(dyn Fn(&[Ray], &mut [u32]) + Sync)) -> f64 {
    let start = Instant::now();
    pool.install(|| {
        rays.par_chunks(TASK)
            .zip(out.par_chunks_mut(TASK))
            .for_each(|(rays, out)| trace(rays, out))
    });
    start.elapsed().as_secs_f64()
}

/// Times of lumiere and of Embree over every ray, round by round: each slice of [`SLICE`]
/// rays traced by both, the first to go alternating.
fn paired(
    pool: &rayon::ThreadPool,
    rays: &[Ray],
    ours: &mut [u32],
    theirs: &mut [u32],
    lumiere: &(dyn Fn(&[Ray], &mut [u32]) + Sync),
    embree: &(dyn Fn(&[Ray], &mut [u32]) + Sync),
) -> Vec<(f64, f64)> {
    (0..ROUNDS)
        .map(|round| {
            let (mut a, mut b) = (0.0, 0.0);
            for (k, start) in (0..rays.len()).step_by(SLICE).enumerate() {
                let slice = start..(start + SLICE).min(rays.len());
                let mut trace_ours = || a += timed(pool, &rays[slice.clone()], &mut ours[slice.clone()], lumiere);
                let mut trace_theirs = || b += timed(pool, &rays[slice.clone()], &mut theirs[slice.clone()], embree);
                if (k + round) % 2 == 0 {
                    trace_ours();
                    trace_theirs();
                } else {
                    trace_theirs();
                    trace_ours();
                }
            }
            (a, b)
        })
        .collect()
}

fn agreement(a: &[u32], b: &[u32]) -> f64 {
    a.iter().zip(b).filter(|(a, b)| a == b).count() as f64 / a.len() as f64
}

fn main() {
    // `cargo bench` passes `--bench`; this harness takes no options.
    let (spheres, camera) = spheres_and_camera();
    let start = Instant::now();
    let accel = Accel::build_with(&spheres, AccelChoice::Bvh);
    let lumiere_build = start.elapsed().as_secs_f64();
    let device = Device::new().expect("an Embree device");
    let start = Instant::now();
    let embree = embree_scene(&device, &spheres);
    let embree_build = start.elapsed().as_secs_f64();
    let kernels = Kernels {
        spheres: &spheres,
        accel: &accel,
        embree: &embree,
    };
    println!(
        "{} spheres; build: lumiere {:.0} ms, Embree {:.0} ms",
        spheres.len(),
        lumiere_build * 1e3,
        embree_build * 1e3
    );
    println!();
    println!(
        "| rays | query | lumiere call | Embree call | threads | lumiere (Mrays/s) | Embree (Mrays/s) | lumiere / Embree | rounds' range | same answer |"
    );
    println!("|---|---|---|---|---:|---:|---:|---:|---:|---:|");
    let sets = [
        ("coherent", true, camera_rays(&camera, SIDE)),
        ("incoherent", false, incoherent_rays(INCOHERENT)),
    ];
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        for (name, coherent, rays) in &sets {
            let mut calls = vec![
                ("closest", "closest", "rtcIntersect1", Query::Closest, false),
                ("any", "any_hit", "rtcOccluded1", Query::Any, false),
            ];
            if *coherent {
                calls.push(("closest", "closest_packet", "rtcIntersect16", Query::Closest, true));
                calls.push(("any", "any_hit_packet", "rtcOccluded16", Query::Any, true));
            }
            for (query_name, ours_call, call, query, packets) in calls {
                let (mut ours, mut theirs) = (vec![0; rays.len()], vec![0; rays.len()]);
                let rounds = paired(
                    &pool,
                    rays,
                    &mut ours,
                    &mut theirs,
                    &|r, o| {
                        if packets {
                            kernels.lumiere_packets(query, r, o)
                        } else {
                            kernels.lumiere(query, r, o)
                        }
                    },
                    &|r, o| {
                        if packets {
                            kernels.embree_packets(query, r, o)
                        } else {
                            kernels.embree_single(query, *coherent, r, o)
                        }
                    },
                );
                let (a, b) = rounds.iter().fold((0.0, 0.0), |(a, b), r| (a + r.0, b + r.1));
                let ratios = rounds.iter().map(|r| r.1 / r.0);
                let (low, high) = ratios.fold((f64::INFINITY, 0.0f64), |(l, h), x| (l.min(x), h.max(x)));
                let rate = |t: f64| (ROUNDS * rays.len()) as f64 / t / 1e6;
                println!(
                    "| {name} | {query_name} | {ours_call} | {call} | {threads} | {:.2} | {:.2} | {:.2} | {low:.2} – {high:.2} | {:.4} % |",
                    rate(a),
                    rate(b),
                    b / a,
                    100.0 * agreement(&ours, &theirs)
                );
            }
        }
    }
}
