//! The harness of benches/paired/run: the working tree's BVH (`lumiere`) against a base
//! revision's (`lumiere_base`) in one process, on the million spheres of
//! scenes/spheres-1m.toml (its floor left out, as benches/embree.rs does) with the rays of
//! benches/embree.rs: 1000 x 1000 coherent camera rays and the 1 000 000 incoherent rays of
//! benches/common/rays.rs; closest hit and any hit, one thread.
//!
//! It first checks that the two builds give the same hits (the same object and `t` to the
//! bit, the same any-hit answers). Then in each round the rays are traced in pairs of
//! slices of [`SLICE`], each slice by both builds one after the other, each build going
//! first on one slice of the pair (and the order turning from pair to pair and round to
//! round). The table gives each build's rate (all the rays over its summed time), this
//! tree's speed over the base's, and the median and middle half (the quartiles) of the
//! pairs' ratios: a burst of the machine's other work moves a few pairs, not the median.

mod rays;

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

const SIDE: u32 = 1000;
const INCOHERENT: usize = 1_000_000;
/// Rays the two builds trace in turn (about 2.5 ms of one build's walk).
const SLICE: usize = 5_000;

/// The rays of one set, as origins and directions (each build makes its own `Ray`s).
type Rays = Vec<(glam::DVec3, glam::DVec3)>;

/// Loads scenes/spheres-1m.toml with crate `$c`: its spheres, their BVH and its camera.
macro_rules! spheres_and_tree {
    ($c:ident, $path:expr) => {{
        let scene = match $c::scene::load($path) {
            Ok(scene) => scene,
            Err(e) => {
                eprintln!("paired: {}: {e}", stringify!($c));
                return ExitCode::FAILURE;
            }
        };
        let spheres: Vec<$c::scene::Object> = scene
            .objects
            .into_iter()
            .filter(|o| matches!(o.shape, $c::shape::Shape::Sphere(_)))
            .collect();
        let tree = $c::accel::Accel::build_with(&spheres, $c::accel::AccelChoice::Bvh);
        (spheres, tree, scene.camera)
    }};
}

/// Traces `$rays` with crate `$c`'s tree: a sum of the answers (the closest object's
/// index, or 1 for a ray that hits anything), so that no query is optimised away.
macro_rules! trace {
    ($c:ident, $spheres:expr, $tree:expr, $rays:expr, $any:expr) => {{
        let mut sum = 0u64;
        for &(origin, dir) in $rays {
            let ray = $c::math::Ray::new(origin, dir);
            sum += if $any {
                $tree.any_hit($spheres, &ray, 0.0, f64::INFINITY, &|_| true) as u64
            } else {
                $tree
                    .closest($spheres, &ray, 0.0, f64::INFINITY)
                    .map_or(0, |(i, _)| i as u64 + 1)
            };
        }
        sum
    }};
}

fn main() -> ExitCode {
    let rounds = match std::env::args().nth(1).map(|a| a.parse::<usize>()) {
        None => 6,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => {
            eprintln!("paired: the number of rounds must be a whole number from 1 on");
            return ExitCode::FAILURE;
        }
    };
    let path = Path::new("scenes/spheres-1m.toml");
    let (these, this_tree, c) = spheres_and_tree!(lumiere, path);
    let (base_spheres, base_tree, _) = spheres_and_tree!(lumiere_base, path);
    let camera = lumiere::camera::Camera::new(c.position, c.look_at, c.up, c.vfov_deg, 1.0);
    let coherent: Rays = rays::camera_rays(&camera, SIDE)
        .into_iter()
        .map(|r| (r.origin, r.dir))
        .collect();
    let incoherent: Rays = rays::incoherent_rays(INCOHERENT)
        .into_iter()
        .map(|r| (r.origin, r.dir))
        .collect();

    let mut differ = 0;
    for rays in [&coherent, &incoherent] {
        for &(origin, dir) in rays {
            let (a, b) = (
                lumiere::math::Ray::new(origin, dir),
                lumiere_base::math::Ray::new(origin, dir),
            );
            let this = this_tree
                .closest(&these, &a, 0.0, f64::INFINITY)
                .map(|(i, h)| (i, h.t.to_bits()));
            let base = base_tree
                .closest(&base_spheres, &b, 0.0, f64::INFINITY)
                .map(|(i, h)| (i, h.t.to_bits()));
            let this_any = this_tree.any_hit(&these, &a, 0.0, f64::INFINITY, &|_| true);
            let base_any = base_tree.any_hit(&base_spheres, &b, 0.0, f64::INFINITY, &|_| true);
            differ += usize::from(this != base) + usize::from(this_any != base_any);
        }
    }
    println!(
        "hits: {differ} of {} rays' answers (closest and any) differ between this tree and the base\n",
        2 * (coherent.len() + incoherent.len())
    );

    println!(
        "| rays | query | this tree (Mrays/s) | base (Mrays/s) | this / base | slices' median | slices' middle half |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|");
    let mut check = 0u64;
    for (name, rays) in [("coherent", &coherent), ("incoherent", &incoherent)] {
        for (query, any) in [("closest", false), ("any", true)] {
            // The summed seconds of this tree and of the base, and each slice's ratio.
            let mut total = [0.0f64; 2];
            let mut ratios = Vec::new();
            for round in 0..rounds {
                // Two slices in turn, each build going first once: the pair's ratio.
                for (k, pair) in rays.chunks(2 * SLICE).enumerate() {
                    let mut seconds = [0.0f64; 2];
                    for (half, slice) in pair.chunks(SLICE).enumerate() {
                        for turn in 0..2 {
                            let which = (turn + half + k + round) % 2;
                            let start = Instant::now();
                            check += if which == 0 {
                                trace!(lumiere, &these, this_tree, slice, any)
                            } else {
                                trace!(lumiere_base, &base_spheres, base_tree, slice, any)
                            };
                            seconds[which] += start.elapsed().as_secs_f64();
                        }
                    }
                    total[0] += seconds[0];
                    total[1] += seconds[1];
                    ratios.push(seconds[1] / seconds[0]);
                }
            }
            ratios.sort_by(f64::total_cmp);
            let quantile = |q: f64| ratios[((ratios.len() - 1) as f64 * q).round() as usize];
            let rate = |which: usize| (rays.len() * rounds) as f64 / total[which] / 1e6;
            println!(
                "| {name} | {query} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} – {:.3} |",
                rate(0),
                rate(1),
                total[1] / total[0],
                quantile(0.5),
                quantile(0.25),
                quantile(0.75)
            );
        }
    }
    // Printed so that the traces are not optimised away; equal builds print equal halves.
    eprintln!("answers' sum: {check}");
    if differ > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
