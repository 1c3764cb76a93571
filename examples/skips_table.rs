//! The before/after table of BENCHMARKS.md ("Where the time goes, and what each shortcut
//! saves"): every figure set rendered in-process on one thread, once with every shortcut of
//! `src/skips.rs` off (`Skips::none()`) and once with all on (`Skips::all()`), checking that
//! the 8-bit images are identical, and printing a markdown table.
//!
//! `cargo run --release --example skips_table -- [--area-scale S] [SET ...]`
//!
//! Sets are rendered at full size except the area-light sets (soft-shadows, light-shapes),
//! rendered at `--area-scale` (default 0.5: at full size soft-shadows' N = 1000 figure alone
//! takes minutes). A figure whose scene repeats an earlier one's is rendered once, as
//! `lumiere figures` does.

use lumiere::figures::{registry, scaled};
use lumiere::render::render;
use lumiere::skips::Skips;
use lumiere::world::World;
use std::time::Instant;

const AREA_SETS: [&str; 2] = ["soft-shadows", "light-shapes"];

/// Seconds and shadow rays of one render on the current pool, and its 8-bit pixels.
fn run(scene: &lumiere::scene::Scene, skips: Skips) -> (f64, u64, Vec<u8>) {
    let mut world = World::new(scene);
    world.skips = skips;
    let start = Instant::now();
    let (film, stats) = render(&world, &|| {});
    (start.elapsed().as_secs_f64(), stats.counts.shadow, film.to_rgb8())
}

fn main() {
    let mut args = std::env::args().skip(1);
    let mut area_scale = 0.5;
    let mut only = Vec::new();
    while let Some(a) = args.next() {
        if a == "--area-scale" {
            area_scale = args.next().and_then(|s| s.parse().ok()).expect("--area-scale S");
        } else {
            only.push(a);
        }
    }
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    println!(
        "| set | scale | images | seconds, no skips | seconds, all skips | ratio | shadow rays, no skips | shadow rays, all skips |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let (mut total_off, mut total_on) = (0.0, 0.0);
    for set in registry().expect("run from the repository root: the figure files load") {
        if !only.is_empty() && !only.contains(&set.name) {
            continue;
        }
        let scale = if AREA_SETS.contains(&set.name.as_str()) {
            area_scale
        } else {
            1.0
        };
        let mut scenes: Vec<lumiere::scene::Scene> = Vec::new();
        for f in set.figures {
            if !scenes.contains(&f.scene) {
                scenes.push(f.scene);
            }
        }
        let (mut secs_off, mut secs_on, mut shadow_off, mut shadow_on) = (0.0, 0.0, 0, 0);
        for scene in &scenes {
            let scene = scaled(scene.clone(), scale);
            let (t_off, s_off, rgb_off) = pool.install(|| run(&scene, Skips::none()));
            let (t_on, s_on, rgb_on) = pool.install(|| run(&scene, Skips::all()));
            assert!(rgb_off == rgb_on, "{}: images differ with and without skips", set.name);
            (secs_off, secs_on) = (secs_off + t_off, secs_on + t_on);
            (shadow_off, shadow_on) = (shadow_off + s_off, shadow_on + s_on);
        }
        total_off += secs_off;
        total_on += secs_on;
        println!(
            "| {} | {scale} | {} | {secs_off:.2} | {secs_on:.2} | {:.2}x | {shadow_off} | {shadow_on} |",
            set.name,
            scenes.len(),
            secs_off / secs_on,
        );
    }
    println!(
        "| **total** | | | {total_off:.2} | {total_on:.2} | {:.2}x | | |",
        total_off / total_on
    );
}
