//! Camera rays in a linearly scanned world skip the objects whose cone of directions from
//! the eye they leave ([`World::closest_camera`]): the answer is the linear scan's to the
//! bit (object, `t`, normal), on every course scene, on rays through a fine grid of image
//! positions and on rays that graze each object's cone, and the shortcut tests fewer objects
//! when on and none fewer when the bounding-sphere skip is off.

mod common;
use common::*;
use lumiere::math::Ray;
use lumiere::render::camera_ray;
use lumiere::scene::Scene;
use lumiere::shape::SurfaceHit;
use lumiere::skips::{Skip, Skips};
use lumiere::world::World;

/// The hit as bits: object, `t` and normal.
fn bits(hit: Option<(usize, SurfaceHit)>) -> Option<(usize, u64, [u64; 3])> {
    hit.map(|(i, h)| (i, h.t.to_bits(), h.normal.to_array().map(f64::to_bits)))
}

/// Checks `ray` on both paths (with the scene's far plane as `t_max`, as camera rays are
/// traced); returns the objects the culled path did not test.
fn check_ray(world: &World, ray: &Ray, what: &str) -> u64 {
    let far = world.scene.settings.conventions.far;
    let mut untested = 0;
    let culled = world.closest_camera(ray, far, &mut untested);
    assert_eq!(
        bits(culled),
        bits(world.closest_before(ray, far)),
        "{what}: ray {ray:?}"
    );
    untested
}

/// Rays through a grid of `n x n` positions per pixel of a `width x height` image, and
/// through each bounded object's silhouette: from the eye along directions at the cone of
/// its bounding sphere, just inside and just outside it, all around. Returns the objects not
/// tested.
fn check_scene(scene: &Scene, what: &str) -> u64 {
    let mut scene = scene.clone();
    scene.settings.width = 160;
    scene.settings.height = 120;
    let world = World::new(&scene);
    let mut untested = 0;
    let n = 2;
    for y in 0..scene.settings.height * n {
        for x in 0..scene.settings.width * n {
            let position = ((x as f64 + 0.5) / n as f64, (y as f64 + 0.5) / n as f64);
            untested += check_ray(&world, &camera_ray(&world, position), what);
        }
    }
    let eye = world.camera.position;
    for object in world.objects() {
        let Some((center, radius)) = object.shape.bounding_sphere() else {
            continue;
        };
        let to_center = center - eye;
        let dist = to_center.length();
        if radius >= dist {
            continue;
        }
        let axis = to_center / dist;
        let side = axis.any_orthonormal_vector();
        let half_angle = (radius / dist).asin();
        for k in 0..64 {
            let around = std::f64::consts::TAU * k as f64 / 64.0;
            let across = side * around.cos() + axis.cross(side) * around.sin();
            for angle in [half_angle * (1.0 - 1e-6), half_angle, half_angle * (1.0 + 1e-6)] {
                let dir = (axis * angle.cos() + across * angle.sin()).normalize();
                untested += check_ray(&world, &Ray::new(eye, dir), what);
            }
        }
    }
    untested
}

#[test]
fn camera_rays_meet_what_the_linear_scan_meets_on_every_course_scene() {
    let mut files: Vec<_> = std::fs::read_dir(repo("scenes/figures"))
        .unwrap()
        .flat_map(|set| std::fs::read_dir(set.unwrap().path()).unwrap())
        .map(|f| f.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml") && p.file_name().is_some_and(|n| n != "set.toml"))
        .collect();
    files.sort();
    files.push(repo("scenes/reference.toml"));
    assert!(
        files.len() > 80,
        "the course's figure scenes are found: {}",
        files.len()
    );
    let mut culled_scenes = 0;
    for file in &files {
        let scene = lumiere::scene::load(file).expect("scene loads");
        let untested = check_scene(&scene, &file.display().to_string());
        let bounded = scene.objects.iter().any(|o| o.shape.bounding_sphere().is_some());
        assert_eq!(
            untested > 0,
            bounded,
            "{}: objects not tested {untested}",
            file.display()
        );
        culled_scenes += usize::from(untested > 0);
    }
    // Every course scene with a bounded object (all but the optique set's, a plane and an
    // aperture light) has some that camera rays pass by.
    assert!(culled_scenes >= files.len() - 3, "{culled_scenes} of {}", files.len());
}

#[test]
fn the_bounding_sphere_skip_switches_the_culling_off() {
    let scene = scene("reference.toml");
    let mut world = World::new(&scene);
    let ray = camera_ray(&world, (400.0, 300.0));
    let mut untested = 0;
    world.closest_camera(&ray, f64::INFINITY, &mut untested);
    // The ray through the image's centre, from (0, -8, 5) along (0, 9, -5) / sqrt(106),
    // passes every bounded object's sphere by: the nearest, the cube's (centre (0, 0, 3),
    // radius sqrt(3) = 1.73), at |(0, 8, -2) x (0, 9, -5)| / sqrt(106) = 22 / 10.30 = 2.14.
    assert_eq!(untested, 6, "objects not tested");
    world.skips = Skips::all().without(Skip::BoundingSpheres);
    let mut untested = 0;
    let off = world.closest_camera(&ray, f64::INFINITY, &mut untested);
    assert_eq!(untested, 0);
    assert_eq!(bits(off), bits(world.closest(&ray)));
    // It meets the floor (object 0, z = 0) at t = 5 / (5 / sqrt(106)) = sqrt(106).
    let (object, hit) = off.unwrap();
    assert_eq!(object, 0);
    assert!((hit.t - 106f64.sqrt()).abs() < 1e-12, "t = {}", hit.t);
}
