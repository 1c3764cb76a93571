//! Chapter 7.4b's shadow rays on exact points of the reference scene, with its directional
//! light d = (1, 1, -1): the shadow ray from a floor point goes along L = (-1, -1, 1)/sqrt 3.

use crate::common::*;
use glam::DVec3;
use lumiere::light::Light;
use lumiere::trace::Tracer;
use lumiere::world::World;

const YELLOW: DVec3 = DVec3::new(1.0, 0.9, 0.1);
const MAUVE: DVec3 = DVec3::new(0.6, 0.3, 0.8);

/// The filter the floor point `p` receives from the directional light.
fn filter_at(p: DVec3) -> DVec3 {
    let scene = scene("reference.toml");
    let world = World::new(&scene);
    let light = scene
        .lights
        .iter()
        .find(|l| matches!(l, Light::Directional { .. }))
        .unwrap();
    let inc = light.incidence(p).unwrap();
    Tracer::new(&world).shadow_filter(p, DVec3::Z, 1e-12, &inc)
}

#[test]
fn open_floor_receives_the_whole_light() {
    assert_eq!(filter_at(DVec3::new(-2.0, 5.0, 0.0)), DVec3::ONE);
}

#[test]
fn shadow_of_the_yellow_sphere_alone() {
    // (4, -2, 0) is the yellow center (1, -5, 3) moved 3 along d. Its shadow ray passes
    // 0.816 from the mauve center (> 0.75): only yellow filters. L = 1 * S_yellow.
    assert_eq!(filter_at(DVec3::new(4.0, -2.0, 0.0)), YELLOW);
}

#[test]
fn overlap_of_both_spheres_shadows() {
    // (4.5, -1.5, 0): the ray passes 0.408 from both centers: L = S_yellow * S_mauve
    // = (0.6, 0.27, 0.08), each sphere counted once although the ray crosses two surfaces of each.
    let f = filter_at(DVec3::new(4.5, -1.5, 0.0));
    assert!((f - DVec3::new(0.6, 0.27, 0.08)).length() < 1e-15, "{f}");
    assert_eq!(f, YELLOW * MAUVE);
}

#[test]
fn behind_the_opaque_cube_is_dark() {
    // (3, 3, 0): the shadow ray passes through the cube's center (0, 0, 3).
    assert_eq!(filter_at(DVec3::new(3.0, 3.0, 0.0)), DVec3::ZERO);
}
