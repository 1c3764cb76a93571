//! Every shortcut of `src/skips.rs` is exact: a scene that exercises it renders to the same
//! float pixels (bit for bit) and the same 8-bit bytes with it switched off, the shortcut did
//! save work there (its `saved` count is positive when on and 0 when off), and the rays it
//! avoids are exactly the ones traced without it.
//!
//! Adaptive depth control is not a `Skip` (it is not exact): its error bound at the default
//! threshold (at most 1 level on at most 0.1 % of the pixels) is asserted by
//! `default_adaptive_threshold_changes_at_most_one_level_on_0_1_percent` in
//! tests/recursion.rs and tabled in BENCHMARKS.md ("Adaptive depth control").

use crate::common::scene;
use glam::DVec3;
use lumiere::figures::{registry, scaled};
use lumiere::film::Film;
use lumiere::light::Light;
use lumiere::render::render;
use lumiere::scene::Scene;
use lumiere::skips::{Skip, Skips};
use lumiere::trace::RayCounts;
use lumiere::world::World;

/// Renders `scene` with `skips`.
fn render_with(scene: &Scene, skips: Skips) -> (Film, RayCounts) {
    let mut world = World::new(scene);
    world.skips = skips;
    let (film, stats) = render(&world, &|| {});
    (film, stats.counts)
}

/// Sets the image size and samples per pixel.
fn sized(mut scene: Scene, width: u32, height: u32, spp: u32) -> Scene {
    (
        scene.settings.width,
        scene.settings.height,
        scene.settings.samples_per_pixel,
    ) = (width, height, spp);
    scene
}

/// The figure `stem` of set `set`.
fn figure(set: &str, stem: &str) -> Scene {
    let set = registry()
        .expect("the figure files load")
        .into_iter()
        .find(|s| s.name == set)
        .expect("set exists");
    set.figures
        .into_iter()
        .find(|f| f.stem == stem)
        .unwrap_or_else(|| panic!("no figure {stem}"))
        .scene
}

/// Asserts that the two films are the same, float pixel for float pixel and byte for byte.
fn assert_identical(a: &Film, b: &Film, what: &str) {
    assert_eq!((a.width, a.height), (b.width, b.height), "{what}: size");
    let bits = |f: &Film| -> Vec<[u64; 3]> { f.pixels.iter().map(|p| p.to_array().map(f64::to_bits)).collect() };
    let (fa, fb) = (bits(a), bits(b));
    if let Some(i) = (0..fa.len()).find(|&i| fa[i] != fb[i]) {
        panic!(
            "{what}: float pixel {i} differs: {:?} vs {:?}",
            a.pixels[i], b.pixels[i]
        );
    }
    assert!(a.to_rgb8() == b.to_rgb8(), "{what}: 8-bit bytes differ");
}

/// Renders `scene` with every skip on and with `skip` off; asserts identical images and that
/// the skip saved work only when on. Returns the counts (on, off).
fn on_off(scene: &Scene, skip: Skip) -> (RayCounts, RayCounts) {
    let (film_on, on) = render_with(scene, Skips::all());
    let (film_off, off) = render_with(scene, Skips::all().without(skip));
    let name = skip.name();
    assert_identical(&film_on, &film_off, name);
    assert!(on.saved.get(skip) > 0, "{name}: saved nothing in this scene");
    assert_eq!(off.saved.get(skip), 0, "{name}: counted savings while off");
    assert_eq!(on.camera, off.camera);
    (on, off)
}

/// The soft-shadows scene (spherical light of N = 100 points, a cube, two transparent
/// spheres) at 80 x 60, one sample per pixel.
fn soft_shadows() -> Scene {
    sized(scene("soft-shadows.toml"), 80, 60, 1)
}

#[test]
fn back_facing_skip_saves_exactly_the_shadow_rays_of_lights_behind_the_surface() {
    // Reference scene: a directional light, so every sphere has a side facing away from it.
    let s = sized(scene("reference.toml"), 80, 60, 1);
    let (on, off) = on_off(&s, Skip::BackFacing);
    // With the skip off, each light share with N.L <= 0 casts its shadow ray (and adds 0).
    assert_eq!(off.shadow - on.shadow, on.saved.get(Skip::BackFacing));
    assert_eq!((on.reflection, on.refraction), (off.reflection, off.refraction));
}

#[test]
fn unlit_skip_saves_the_shadow_rays_of_black_lights_and_outside_a_spot_cone() {
    // Figure spotlight 01 (a 70 degree spot: most of the floor is outside the cone) plus a
    // black directional light that lights everything with nothing.
    let mut s = sized(figure("spotlight", "01-theta-70"), 80, 60, 1);
    s.lights.push(Light::Directional {
        direction: DVec3::new(0.0, 0.0, -1.0),
        color: DVec3::ZERO,
    });
    let (on, off) = on_off(&s, Skip::Unlit);
    // Without it, a black share facing away is the back-facing skip's instead; every other
    // one casts its shadow ray.
    let back_facing = off.saved.get(Skip::BackFacing) - on.saved.get(Skip::BackFacing);
    assert!(back_facing > 0);
    assert_eq!(off.shadow - on.shadow + back_facing, on.saved.get(Skip::Unlit));

    // Each cause alone: only the black light, and only the cone (the spot's own figure).
    let mut black = sized(figure("lighting", "02-directional"), 40, 30, 1);
    black.lights.push(Light::Directional {
        direction: DVec3::new(0.0, 0.0, -1.0),
        color: DVec3::ZERO,
    });
    on_off(&black, Skip::Unlit);
    on_off(&sized(figure("spotlight", "01-theta-70"), 40, 30, 1), Skip::Unlit);
}

#[test]
fn opaque_only_skip_stops_at_the_first_hit_and_walks_only_when_something_is_transparent() {
    // The mirrors: nothing is transparent, so no unblocked shadow ray needs the filtered walk.
    let s = sized(figure("mirrors", "05-opening-60-depth-05"), 80, 60, 1);
    let (on, off) = on_off(&s, Skip::OpaqueOnly);
    // Same rays either way; the count is of shadow rays that found no opaque blocker.
    assert_eq!(on.shadow, off.shadow);
    assert!(on.saved.get(Skip::OpaqueOnly) <= on.shadow);
    // With transparent objects (the reference scene's glass sphere) the walk is needed and
    // nothing is saved, but any-hit against visiting every opaque hit is still exact.
    let glass = sized(scene("reference.toml"), 80, 60, 1);
    let (film_on, c_on) = render_with(&glass, Skips::all());
    let (film_off, c_off) = render_with(&glass, Skips::all().without(Skip::OpaqueOnly));
    assert_identical(&film_on, &film_off, "opaque-only, transparent scene");
    assert_eq!(c_on.saved.get(Skip::OpaqueOnly), 0);
    assert_eq!(c_on.shadow, c_off.shadow);
}

#[test]
fn zero_weight_skip_saves_exactly_the_secondary_rays_of_weight_0() {
    for (what, mut s) in [
        ("mirrors", figure("mirrors", "05-opening-60-depth-05")),
        ("prism", figure("prism", "11-depth-10")),
    ] {
        s = sized(s, 80, 60, 1);
        // Without adaptive depth control, every ray of weight 0 is traced.
        s.settings.adaptive_threshold = 0.0;
        let (on, off) = on_off(&s, Skip::ZeroWeight);
        let secondary = |c: &RayCounts| c.reflection + c.refraction;
        // Each saved ray is traced without the skip (a refraction of weight 0 that meets
        // total internal reflection excepted), and its subtree adds more.
        let extra_tir = off.total_internal_reflections - on.total_internal_reflections;
        assert!(
            secondary(&off) - secondary(&on) + extra_tir >= on.saved.get(Skip::ZeroWeight),
            "{what}"
        );
        assert!(off.shadow >= on.shadow, "{what}");
        // With it (the default), each of them is cut at once instead (weight 0 is below any
        // threshold), except a refraction of weight 0 that meets total internal reflection,
        // which is no ray at all; the rest of the tree is the same.
        s.settings.adaptive_threshold = lumiere::limits::DEFAULT_ADAPTIVE_THRESHOLD;
        let (on, off) = on_off(&s, Skip::ZeroWeight);
        let extra_tir = off.total_internal_reflections - on.total_internal_reflections;
        assert_eq!(
            off.adaptive_cutoffs - on.adaptive_cutoffs + extra_tir,
            on.saved.get(Skip::ZeroWeight),
            "{what}"
        );
        assert_eq!(secondary(&on), secondary(&off), "{what}");
        assert_eq!(on.shadow, off.shadow, "{what}");
    }
}

#[test]
fn shadow_candidates_skip_is_exact() {
    let (on, off) = on_off(&soft_shadows(), Skip::ShadowCandidates);
    assert_eq!(on.shadow, off.shadow);
    // Never more objects left out per shadow ray than the scene has.
    let objects = scene("soft-shadows.toml").objects.len() as u64;
    assert!(on.saved.get(Skip::ShadowCandidates) <= on.shadow * objects);
}

#[test]
fn horizon_skip_passes_over_exactly_the_points_that_would_face_away() {
    for (what, s) in [
        ("soft-shadows.toml", soft_shadows()),
        (
            "light-shapes 03-window",
            sized(figure("light-shapes", "03-window"), 80, 60, 1),
        ),
    ] {
        let (on, off) = on_off(&s, Skip::Horizon);
        // Every point of a light below the horizon has N.L < 0: without the skip, each is
        // looked at and left out by the back-facing skip, with no shadow ray either way.
        let back_facing = off.saved.get(Skip::BackFacing) - on.saved.get(Skip::BackFacing);
        assert_eq!(back_facing, on.saved.get(Skip::Horizon), "{what}");
        assert_eq!(on.shadow, off.shadow, "{what}");
    }
}

#[test]
fn bounding_spheres_skip_is_exact() {
    // The soft-shadows scene has a cube (a costly shape) between the area light and the
    // floor. The skip acts on area lights' candidate lists (direction cones); other shadow
    // rays go through the acceleration structure.
    for (what, s) in [
        ("soft-shadows.toml", soft_shadows()),
        (
            "light-shapes 02-tube",
            sized(figure("light-shapes", "02-tube"), 80, 60, 1),
        ),
    ] {
        let (on, off) = on_off(&s, Skip::BoundingSpheres);
        assert_eq!(on.shadow, off.shadow, "{what}");
        assert_eq!(
            on.saved.get(Skip::ShadowCandidates),
            off.saved.get(Skip::ShadowCandidates),
            "{what}"
        );
    }
}

#[test]
fn blocked_shading_skip_is_exact() {
    for (what, s) in [
        ("soft-shadows.toml", soft_shadows()),
        ("reference.toml", sized(scene("reference.toml"), 80, 60, 1)),
    ] {
        let (on, off) = on_off(&s, Skip::BlockedShading);
        assert_eq!(on.shadow, off.shadow, "{what}");
        // Counted once per fully blocked shadow ray, so never more than the shadow rays.
        assert!(on.saved.get(Skip::BlockedShading) <= on.shadow, "{what}");
    }
}

#[test]
fn every_skip_is_tested_here() {
    // A new `Skip` needs a test of its own above.
    assert_eq!(Skip::ALL.len(), 8);
}

#[test]
fn every_figure_is_identical_with_no_skips_and_with_all() {
    for set in registry().expect("the figure files load") {
        let mut done: Vec<Scene> = Vec::new();
        for f in set.figures {
            if done.contains(&f.scene) {
                continue;
            }
            let s = scaled(f.scene.clone(), 0.1);
            let s = sized(s.clone(), s.settings.width.min(80), s.settings.height.min(60), 1);
            let (film_none, none) = render_with(&s, Skips::none());
            let (film_all, all) = render_with(&s, Skips::all());
            assert_identical(&film_none, &film_all, &format!("{}/{}", set.name, f.stem));
            assert!(Skip::ALL.iter().all(|&k| none.saved.get(k) == 0));
            assert!(none.shadow >= all.shadow, "{}/{}", set.name, f.stem);
            done.push(f.scene);
        }
    }
}
