//! Same scene and seed, same bytes: for any thread count, run after run, debug or release
//! (the pinned hash below is checked in both profiles: by `cargo test --release`, and by
//! .ci/run in a debug build, README "Tests and CI").

mod common;
use common::*;
use lumiere::film::fnv1a64;

#[test]
fn reference_scene_is_identical_with_one_and_two_threads() {
    let scene = scene("reference.toml");
    let one = render_small(&scene, 160, 120, 4, 1).to_rgb8();
    let two = render_small(&scene, 160, 120, 4, 2).to_rgb8();
    assert_eq!(one, two);
    // Not a blank image: the floor, the objects and the shadows make many distinct colours.
    let mut colours: Vec<&[u8]> = one.chunks(3).collect();
    colours.sort();
    colours.dedup();
    assert!(colours.len() > 500, "only {} distinct colours", colours.len());
}

#[test]
fn reference_scene_hash_is_pinned() {
    // A change of this hash is a change of the oracle's output: review it on purpose.
    let scene = scene("reference.toml");
    let film = render_small(&scene, 160, 120, 4, 2);
    common::snapshot_settings().bind(|| {
        insta::assert_snapshot!("reference_160x120_hash", format!("{:016x}", fnv1a64(&film.to_rgb8())));
    });
}

#[test]
fn different_seeds_give_different_jitter() {
    let mut scene = scene("reference.toml");
    let a = render_small(&scene, 64, 48, 4, 2).to_rgb8();
    scene.settings.seed = 43;
    let b = render_small(&scene, 64, 48, 4, 2).to_rgb8();
    assert_ne!(a, b);
}

#[test]
fn a_pixel_is_the_mean_of_its_replayable_samples() {
    // render_pixel reads the jitter stream in order; render_sample seeks to sample k (as
    // `probe --sample K` does). Both must see the same numbers, so the mean is bit-identical.
    use lumiere::render::{render_pixel, render_sample};
    use lumiere::trace::{NoRecord, Tracer};
    use lumiere::world::World;
    let mut scene = scene("reference.toml");
    scene.settings.samples_per_pixel = 9;
    let world = World::new(&scene);
    let mut tracer = Tracer::new(&world);
    for (x, y) in [(0, 0), (400, 300), (523, 401), (799, 599)] {
        let sum: glam::DVec3 = (0..9).map(|k| render_sample(&mut tracer, x, y, k, &mut NoRecord)).sum();
        assert_eq!(render_pixel(&mut tracer, x, y), sum / 9.0, "pixel ({x}, {y})");
    }
}
