//! The non-finite guard end to end (issue 7): a light of NaN colour (impossible from a scene
//! file, forced here) makes every lit sample NaN. A release build renders, counts each such
//! sample and writes black; a debug build stops at the assertion.

use glam::DVec3;
use lumiere::light::Light;
use lumiere::render::render;
use lumiere::world::World;

#[test]
#[cfg_attr(debug_assertions, should_panic(expected = "non-finite radiance"))]
fn nan_light_is_counted_and_never_reaches_a_pixel() {
    let mut scene = lumiere::scene::load(std::path::Path::new("scenes/reference.toml")).unwrap();
    scene.settings.width = 40;
    scene.settings.height = 30;
    scene.settings.samples_per_pixel = 1;
    scene.lights = vec![Light::Directional {
        direction: DVec3::new(1.0, 1.0, -1.0).normalize(),
        color: DVec3::splat(f64::NAN),
    }];
    let world = World::new(&scene);
    let (film, stats) = render(&world, &|| {});
    assert!(film.pixels.iter().all(|p| p.is_finite()));
    // Every sample that hits something facing the light is NaN; the sky (background) is not.
    let black = film.pixels.iter().filter(|p| **p == DVec3::ZERO).count() as u64;
    assert!(stats.counts.non_finite > 100, "{}", stats.counts.non_finite);
    assert!(stats.counts.non_finite <= black);
    assert!(stats.counts.non_finite < 40 * 30);
}
