//! The linear scans that pass objects by without testing them give the plain scans'
//! answers. Camera rays skip the objects whose cone of directions from the eye they leave
//! ([`World::closest_camera`]): the same object, `t` and normal to the bit as
//! [`World::closest_before`], on rays through a fine grid of image positions and along
//! each object's cone edge, and on rays traced as camera rays from elsewhere. Shadow rays skip the objects whose bounding sphere they miss
//! ([`World::shadow_any_hit`], [`World::shadow_each_hit`], and both in the tracer's one
//! [`World::shadow_scan`]): the same answer and the same
//! objects hit as [`World::any_hit`] and [`World::each_hit`], on rays from the visible
//! points towards every light and in random directions. Reflected and refracted rays skip
//! them too ([`World::closest_secondary`]), with the answer of [`World::closest_before`] to
//! the bit. All on every course scene; each
//! shortcut tests fewer objects when on and every object when the bounding-sphere skip is
//! off.

use crate::common::*;
use glam::DVec3;
use lumiere::light::Light;
use lumiere::math::Ray;
use lumiere::render::camera_ray;
use lumiere::sampling::{Purpose, Stream};
use lumiere::scene::Scene;
use lumiere::shape::{Shape, SurfaceHit};
use lumiere::skips::{Skip, Skips};
use lumiere::world::World;
use std::path::PathBuf;

/// The hit as bits: object, `t` and normal.
fn bits(hit: Option<(usize, SurfaceHit)>) -> Option<(usize, u64, [u64; 3])> {
    hit.map(|(i, h)| (i, h.t.to_bits(), h.normal.to_array().map(f64::to_bits)))
}

/// The course's scene files: every figure's and the reference scene.
fn course_scenes() -> Vec<PathBuf> {
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
    files
}

/// Whether the scene has an object the shortcuts may pass by: a bounded one that is not
/// flat (a flat object's own test is as cheap as a ball's, so it is always tested).
fn has_round_object(scene: &Scene) -> bool {
    scene.objects.iter().any(|o| {
        o.shape.bounding_sphere().is_some()
            && !matches!(o.shape, Shape::Rectangle(_) | Shape::Disk(_) | Shape::Triangle(_))
    })
}

/// `scene` at 160 x 120.
fn small(scene: &Scene) -> Scene {
    let mut scene = scene.clone();
    scene.settings.width = 160;
    scene.settings.height = 120;
    scene
}

/// Checks `ray` on both paths (with the scene's far plane as `t_max`, as camera rays are
/// traced); returns the objects the culled path did not test.
fn check_camera_ray(world: &World, ray: &Ray, what: &str) -> u64 {
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

/// Camera rays through 2 x 2 positions per pixel of `scene` at 160 x 120, and through each
/// bounded object's silhouette: from the eye along directions at the cone of its bounding
/// sphere, just inside, on and just outside it, all around. Returns the objects not tested.
fn check_camera_rays(scene: &Scene, what: &str) -> u64 {
    let scene = small(scene);
    let world = World::new(&scene);
    let mut untested = 0;
    let n = 2;
    for y in 0..scene.settings.height * n {
        for x in 0..scene.settings.width * n {
            let position = ((x as f64 + 0.5) / n as f64, (y as f64 + 0.5) / n as f64);
            untested += check_camera_ray(&world, &camera_ray(&world, position), what);
        }
    }
    // Rays traced as camera rays that do not leave the eye: from the image plane, and
    // from points of the scene's box towards random points.
    let mut random = Stream::new(6, Purpose::Generator, 0);
    let mut coordinate = || 20.0 * random.next_f64() - 10.0;
    for _ in 0..2000 {
        let from = DVec3::new(coordinate(), coordinate(), coordinate());
        let to = DVec3::new(coordinate(), coordinate(), coordinate());
        untested += check_camera_ray(&world, &Ray::new(from, (to - from).normalize()), what);
    }
    for position in [(0.5, 0.5), (80.25, 60.75), (159.5, 119.5)] {
        let ray = camera_ray(&world, position);
        let near = Ray::new(ray.at(1e-3), ray.dir);
        untested += check_camera_ray(&world, &near, what);
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
                untested += check_camera_ray(&world, &Ray::new(eye, dir), what);
            }
        }
    }
    untested
}

/// Checks a shadow ray on both paths with every filter a shadow ray uses (all objects, the
/// opaque ones, the transparent ones); returns the objects the culled path did not test.
fn check_shadow_ray(world: &World, ray: &Ray, t_max: f64, what: &str) -> u64 {
    let mut untested = 0;
    let see_through = |i: usize| world.filters_shadows(i);
    let filters: [&dyn Fn(usize) -> bool; 3] = [&|_| true, &|i| !see_through(i), &see_through];
    for filter in filters {
        let plain = world.any_hit(ray, t_max, filter);
        assert_eq!(
            world.shadow_any_hit(ray, t_max, filter, &mut untested),
            plain,
            "{what}: any hit, ray {ray:?} to {t_max}"
        );
        let (mut culled_hits, mut plain_hits) = (Vec::new(), Vec::new());
        world.shadow_each_hit(ray, t_max, filter, |i| culled_hits.push(i), &mut untested);
        world.each_hit(ray, t_max, filter, &mut |i| plain_hits.push(i));
        plain_hits.sort();
        assert_eq!(culled_hits, plain_hits, "{what}: every hit, ray {ray:?} to {t_max}");
    }
    if world.scans_balls() {
        // The tracer's one scan: the opaque scan's answer, then the see-through objects
        // met, with the objects passed by counted as the two scans count them.
        let (mut crossed, mut one_scan_untested) = (Vec::new(), 0);
        let blocked = world.shadow_scan(ray, t_max, &mut crossed, &mut one_scan_untested);
        let mut two_scans_untested = 0;
        let opaque = |i: usize| !see_through(i);
        assert_eq!(
            blocked,
            world.shadow_any_hit(ray, t_max, opaque, &mut two_scans_untested),
            "{what}: one scan, ray {ray:?} to {t_max}"
        );
        if !blocked {
            let mut plain_crossed = Vec::new();
            world.shadow_each_hit(
                ray,
                t_max,
                see_through,
                |i| plain_crossed.push(i),
                &mut two_scans_untested,
            );
            assert_eq!(crossed, plain_crossed, "{what}: one scan, ray {ray:?} to {t_max}");
        }
        // Along a directional light the balls are seen across the light, padded a little
        // more: some objects may be tested that the two scans pass by, never the reverse.
        let along_a_light = t_max == f64::INFINITY
            && world.scene.lights.iter().any(|light| {
                matches!(light, Light::Directional { .. })
                    && light.incidence(ray.origin).is_some_and(|inc| inc.to_light == ray.dir)
            });
        if along_a_light {
            assert!(one_scan_untested <= two_scans_untested, "{what}: one scan, ray {ray:?}");
        } else {
            assert_eq!(
                one_scan_untested, two_scans_untested,
                "{what}: one scan, ray {ray:?} to {t_max}"
            );
        }
        untested += one_scan_untested;
    }
    untested
}

/// Shadow rays of `scene` at 160 x 120: from every visible point (lifted off the surface
/// along its normal) towards every light as the tracer aims them (to 8 random points of an
/// area light's ball), and in 4 random directions, unbounded and to distance 3; and
/// reflected or refracted rays from it ([`World::closest_secondary`] against
/// [`World::closest_before`]). Returns the objects not tested.
fn check_shadow_rays(scene: &Scene, what: &str) -> u64 {
    let scene = small(scene);
    let world = World::new(&scene);
    let mut random = Stream::new(5, Purpose::Generator, 0);
    let mut unit = || {
        let z = 2.0 * random.next_f64() - 1.0;
        let phi = std::f64::consts::TAU * random.next_f64();
        let r = (1.0 - z * z).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    };
    let mut untested = 0;
    for y in 0..scene.settings.height {
        for x in 0..scene.settings.width {
            let ray = camera_ray(&world, (x as f64 + 0.5, y as f64 + 0.5));
            let Some((_, hit)) = world.closest(&ray) else {
                continue;
            };
            let normal = if ray.dir.dot(hit.normal) < 0.0 {
                hit.normal
            } else {
                -hit.normal
            };
            let q = ray.at(hit.t);
            let p = q + normal * 1e-9 * (1.0 + q.abs().max_element());
            for light in &scene.lights {
                let mut targets = Vec::new();
                if let Light::Area(area) = light {
                    let (center, radius) = area.bounding_sphere();
                    targets.extend((0..8).map(|_| center + radius * unit()));
                } else if let Some(inc) = light.incidence(p) {
                    let ray = Ray::new(p, inc.to_light);
                    untested += check_shadow_ray(&world, &ray, inc.distance, what);
                }
                for target in targets {
                    let to = target - p;
                    untested += check_shadow_ray(&world, &Ray::new(p, to.normalize()), to.length(), what);
                }
            }
            for _ in 0..4 {
                let ray = Ray::new(p, unit());
                untested += check_shadow_ray(&world, &ray, f64::INFINITY, what);
                untested += check_shadow_ray(&world, &ray, 3.0, what);
            }
            // Secondary rays: the mirror direction, and random ones, unbounded as the tracer
            // traces them and to distance 3.
            let mirror = ray.dir - 2.0 * ray.dir.dot(normal) * normal;
            for dir in [mirror.normalize(), unit(), unit()] {
                for t_max in [f64::INFINITY, 3.0] {
                    let ray = Ray::new(p, dir);
                    let culled = world.closest_secondary(&ray, t_max, &mut untested);
                    let plain = world.closest_before(&ray, t_max);
                    assert_eq!(bits(culled), bits(plain), "{what}: secondary ray {ray:?} to {t_max}");
                }
            }
        }
    }
    untested
}

/// Runs `check` (which returns how many object tests its shortcuts left out) on every
/// course scene: some are left out exactly on the scenes with a round object, each small
/// enough in the picture that some rays pass it by.
fn on_every_course_scene(check: fn(&Scene, &str) -> u64) {
    for file in &course_scenes() {
        let scene = lumiere::scene::load(file).expect("scene loads");
        let untested = check(&scene, &file.display().to_string());
        assert_eq!(untested > 0, has_round_object(&scene), "{}: {untested}", file.display());
    }
}

#[test]
fn camera_rays_meet_what_the_linear_scan_meets_on_every_course_scene() {
    on_every_course_scene(check_camera_rays);
}

#[test]
fn shadow_and_secondary_rays_meet_what_the_linear_scan_meets_on_every_course_scene() {
    on_every_course_scene(check_shadow_rays);
}

#[test]
fn the_bounding_sphere_skip_switches_the_camera_culling_off() {
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

#[test]
fn the_bounding_sphere_skip_switches_the_shadow_culling_off() {
    let scene = scene("reference.toml");
    let mut world = World::new(&scene);
    // Straight up from the floor at (0, -6): the round objects nearest the line, the
    // cube (centre (0, 0, 3), radius sqrt(3)) and the yellow sphere (centre (1, -5, 3),
    // radius 0.75), lie 6 and 1.41 from it; all 6 balls are passed by (the floor has none).
    let up = Ray::new(DVec3::new(0.0, -6.0, 1e-9), DVec3::Z);
    let mut untested = 0;
    assert!(!world.shadow_any_hit(&up, f64::INFINITY, |_| true, &mut untested));
    assert_eq!(untested, 6);
    // Towards the cube's centre, from the same point: the cube is hit.
    let to_cube = Ray::new(DVec3::new(0.0, -6.0, 1e-9), DVec3::new(0.0, 6.0, 3.0).normalize());
    let mut hits = Vec::new();
    world.shadow_each_hit(&to_cube, f64::INFINITY, |_| true, |i| hits.push(i), &mut untested);
    assert!(hits.contains(&1), "the cube: {hits:?}");
    world.skips = Skips::all().without(Skip::BoundingSpheres);
    let mut untested = 0;
    assert!(!world.shadow_any_hit(&up, f64::INFINITY, |_| true, &mut untested));
    world.shadow_each_hit(&to_cube, f64::INFINITY, |_| true, |_| {}, &mut untested);
    let hit = world.closest_secondary(&to_cube, f64::INFINITY, &mut untested);
    assert_eq!(hit.map(|(i, _)| i), Some(1), "the cube");
    assert_eq!(untested, 0);
}
