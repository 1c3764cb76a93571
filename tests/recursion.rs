//! Secondary rays (chapter 7.4b, "Illumination indirecte"): the physics of the two-mirror
//! and prism figures checked on the tracer's own rays and on rendered images.

use crate::common::*;
use glam::DVec3;
use lumiere::math::Ray;
use lumiere::render::render;
use lumiere::scene::{self, Scene};
use lumiere::trace::{RayKind, Recorder, Tracer};
use lumiere::world::World;

/// Records every ray and every total internal reflection, in order.
#[derive(Default)]
struct Rays {
    rays: Vec<(RayKind, Ray, u32, f64)>,
    tir_levels: Vec<u32>,
    current_level: u32,
}

impl Recorder for Rays {
    fn ray(&mut self, kind: RayKind, ray: &Ray, level: u32, weight: f64) {
        self.rays.push((kind, *ray, level, weight));
        self.current_level = level;
    }
    fn total_internal_reflection(&mut self) {
        self.tir_levels.push(self.current_level);
    }
}

/// A scene with one glass box of index `n`, centerd at the origin, of size `size`, no lights
/// (only the rays matter here).
fn glass_box(size: [f64; 3], n: f64, kr: f64, kt: f64, depth: u32) -> Scene {
    let text = format!(
        r#"[image]
width = 8
height = 8
samples_per_pixel = 1
[camera]
position = [0, -10, 0]
look_at = [0, 0, 0]
[render]
depth = {depth}
adaptive_threshold = 0
[materials.glass]
ka = 0
kd = 0
ks = 0
kr = {kr}
kt = {kt}
n = {n}
[[shapes]]
type = "box"
center = [0, 0, 0]
size = {size:?}
material = "glass"
"#
    );
    scene::parse(&text, "glass_box").unwrap()
}

fn trace(scene: &Scene, ray: Ray) -> Rays {
    let world = World::new(scene);
    let mut rec = Rays::default();
    Tracer::new(&world).trace_camera(&ray, &mut rec);
    rec
}

#[test]
fn slab_shifts_the_ray_sideways_and_keeps_its_direction() {
    // A slab 1 thick (faces z = +-0.5) of n = 1.5; incidence 40 degrees.
    // sin(theta_t) = sin 40 / 1.5 = 0.428525, theta_t = 25.3740 degrees;
    // lateral shift = thickness sin(theta_i - theta_t) / cos(theta_t)
    //               = sin(14.6260) / cos(25.3740) = 0.252509 / 0.903530 = 0.279469.
    let scene = glass_box([1000.0, 1000.0, 1.0], 1.5, 0.0, 1.0, 5);
    let (s, c) = (libm::sin(40f64.to_radians()), libm::cos(40f64.to_radians()));
    let incident = Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::new(s, 0.0, -c));
    let rec = trace(&scene, incident);
    let exit = rec
        .rays
        .iter()
        .find(|r| r.0 == RayKind::Refraction && r.2 == 3)
        .expect("an exit ray");
    assert!(
        (exit.1.dir - incident.dir).length() < 1e-12,
        "exit {} vs {}",
        exit.1.dir,
        incident.dir
    );
    let offset = exit.1.origin - incident.origin;
    let shift = (offset - offset.dot(incident.dir) * incident.dir).length();
    let theta_t = libm::asin(s / 1.5);
    let expected = libm::sin(40f64.to_radians() - theta_t) / libm::cos(theta_t);
    assert!((expected - 0.279_469).abs() < 1e-6);
    assert!((shift - expected).abs() < 1e-9, "shift {shift} expected {expected}");
}

/// Traces a ray from inside a slab of n = 1.66 hitting its top face at `deg` from the normal.
fn from_inside(deg: f64) -> Rays {
    let scene = glass_box([10.0, 10.0, 2.0], 1.66, 0.1, 0.9, 2);
    let a = deg.to_radians();
    trace(
        &scene,
        Ray::new(DVec3::ZERO, DVec3::new(libm::sin(a), 0.0, libm::cos(a))),
    )
}

#[test]
fn total_internal_reflection_switches_at_the_critical_angle() {
    // Critical angle for n = 1.66: asin(1 / 1.66) = 37.0427 degrees.
    let critical = libm::asin(1.0 / 1.66).to_degrees();
    let below = from_inside(critical - 1.0);
    assert!(below.tir_levels.is_empty());
    assert!(below.rays.iter().any(|r| r.0 == RayKind::Refraction && r.2 == 2));
    let above = from_inside(critical + 1.0);
    assert_eq!(above.tir_levels, vec![1]);
    assert!(!above.rays.iter().any(|r| r.0 == RayKind::Refraction));
    // The whole weight (kr + kt = 1) goes to the reflected ray.
    let reflected = above.rays.iter().find(|r| r.0 == RayKind::Reflection).unwrap();
    assert_eq!(reflected.3, 1.0);
    assert!((reflected.1.dir.z + libm::cos((critical + 1.0).to_radians())).abs() < 1e-12);
}

#[test]
fn no_ray_weight_exceeds_one() {
    let scene = scene("prism.toml");
    let world = World::new(&scene);
    let mut tracer = Tracer::new(&world);
    let mut rec = Rays::default();
    for y in (0..scene.settings.height).step_by(40) {
        for x in (0..scene.settings.width).step_by(40) {
            lumiere::render::render_sample(&mut tracer, x, y, 0, &mut rec);
        }
    }
    assert!(rec.rays.iter().any(|r| r.0 == RayKind::Refraction));
    assert!(
        !rec.tir_levels.is_empty(),
        "the prism view must show total internal reflection"
    );
    assert!(rec.rays.iter().all(|r| r.3 <= 1.0 && r.3 > 0.0));
}

#[test]
fn perfect_mirrors_at_depth_50_terminate_finite() {
    // Two parallel perfect mirrors (kr = 1) facing each other, a camera between them.
    let text = r#"[image]
width = 24
height = 18
samples_per_pixel = 1
[camera]
position = [0, 0, 1]
look_at = [1, 0.3, 1]
[render]
depth = 50
[materials.mirror]
kr = 1
[[shapes]]
type = "plane"
point = [2, 0, 0]
normal = [-1, 0, 0]
material = "mirror"
[[shapes]]
type = "plane"
point = [-2, 0, 0]
normal = [1, 0, 0]
material = "mirror"
[[lights]]
type = "ambient"
[[lights]]
type = "point"
position = [0, 0, 1.5]
"#;
    let scene = scene::parse(text, "mirrors").unwrap();
    let world = World::new(&scene);
    let (film, stats) = render(&world, &|| {});
    assert!(film.pixels.iter().all(|p| p.is_finite()));
    assert_eq!(stats.counts.non_finite, 0);
    // Every camera ray bounces 49 times: 24 x 18 x 49 reflection rays.
    assert_eq!(stats.counts.reflection, 24 * 18 * 49);
}

/// Cone images seen for a mirror opening: red regions in the render minus the real cone.
fn cone_images(opening: u32) -> usize {
    let file = match opening {
        60 => "10-opening-60-depth-10",
        90 => "11-opening-90-depth-04",
        45 => "12-opening-45-depth-08",
        _ => "13-opening-30-depth-10",
    };
    let mut scene = scene(&format!("figures/mirrors/{file}.toml"));
    scene.settings.depth = 12;
    let (w, h) = (480, 360);
    let film = render_small(&scene, w, h, 1, 2);
    lumiere::figures::measure::red_regions(&film.to_rgb8(), w as usize, h as usize) - 1
}

#[test]
fn mirror_images_follow_floor_360_over_angle_minus_1() {
    // N = floor(360 / opening - 1): 90 -> 3, 60 -> 5, 45 -> 7, 30 -> 11; counted on the image.
    for (opening, expected) in [(90, 3), (60, 5), (45, 7), (30, 11)] {
        assert_eq!(cone_images(opening), expected, "opening {opening}");
    }
}

#[test]
fn default_adaptive_threshold_changes_at_most_one_level_on_0_1_percent() {
    let small = |threshold: f64| {
        let mut s = scene("prism.toml");
        // Depth 20, as the chapter's last prism figure; affordable without cutoffs at this size.
        s.settings.depth = 20;
        s.settings.adaptive_threshold = threshold;
        (s.settings.width, s.settings.height, s.settings.samples_per_pixel) = (160, 120, 1);
        s
    };
    let exact = small(0.0);
    let adaptive = small(lumiere::limits::DEFAULT_ADAPTIVE_THRESHOLD);
    let (film_a, stats_a) = render(&World::new(&exact), &|| {});
    let (film_b, stats_b) = render(&World::new(&adaptive), &|| {});
    let (a, b) = (film_a.to_rgb8(), film_b.to_rgb8());
    let diffs: Vec<u8> = a.iter().zip(&b).map(|(x, y)| x.abs_diff(*y)).collect();
    let max = *diffs.iter().max().unwrap();
    let differing = diffs.chunks(3).filter(|p| p.iter().any(|&d| d > 0)).count();
    assert!(max <= 1, "max difference {max} levels");
    assert!(differing as f64 <= 0.001 * (160.0 * 120.0), "{differing} pixels differ");
    // And it did cut branches and save rays (otherwise the test proves nothing).
    assert_eq!(stats_a.counts.adaptive_cutoffs, 0);
    assert!(stats_b.counts.adaptive_cutoffs > 0);
    let (ra, rb) = (stats_a.counts.total_rays(), stats_b.counts.total_rays());
    assert!((rb as f64) < 0.8 * ra as f64, "{rb} rays with cutoffs vs {ra} without");
}
