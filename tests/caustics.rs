//! The caustic pass (issue 26): the photons' physics against optics' formulas, the density
//! estimate's energy, the shadow rule that keeps light from being counted twice, the probe's
//! caustic term, determinism across threads, shards and tracers, and the `[caustics]` table's
//! errors.

use crate::common::{lumiere, radiance_bits, repo, scene, temp_dir};
use glam::DVec3;
use lumiere::accel::{Accel, AccelChoice};
use lumiere::caustics::{self, emit::Spread, emit::Start, path};
use lumiere::light::Light;
use lumiere::math::Ray;
use lumiere::probe::{RayNode, TreeRecorder, probe};
use lumiere::render::{render, render_reference, render_sample};
use lumiere::sampling::{Purpose, Stream};
use lumiere::scene::{self, CausticSettings, PhotonFilter, Scene};
use lumiere::trace::Tracer;
use lumiere::world::World;
use std::f64::consts::PI;

/// Index of the glass ball.
const N: f64 = 1.5;
/// Radius of the glass ball, centred at the origin.
const R: f64 = 1.0;

/// The paraxial focal distance of a ball lens from its centre, `f = n R / (2 (n - 1))`
/// (the thick-lens formula for a sphere: both surfaces of radius `R`, thickness `2 R`).
fn paraxial_focus() -> f64 {
    N * R / (2.0 * (N - 1.0))
}

/// A ball of index `N` and radius `R` at the origin (material `ball`: `kr`, `kt`), lit by a
/// white directional light straight down its axis, above the diffuse floor `floor` at
/// height `-depth`, with extra text appended (shapes, a `[caustics]` table).
fn ball_scene(kr: f64, kt: f64, depth: f64, extra: &str) -> Scene {
    scene::parse(&ball_scene_text(kr, kt, depth, extra), "ball.toml").expect("the ball scene parses")
}

/// The text of [`ball_scene`].
fn ball_scene_text(kr: f64, kt: f64, depth: f64, extra: &str) -> String {
    format!(
        r#"
[image]
width = 48
height = 36
samples_per_pixel = 1

[camera]
position = [0, -6, 3]
look_at = [0, 0, -1]

[materials.ball]
color = [1, 1, 1]
ka = 0
kd = 0
ks = 0
kr = {kr}
kt = {kt}
n = {N}

[materials.floor]
color = [1, 1, 1]

[[shapes]]
type = "sphere"
name = "ball"
center = [0, 0, 0]
radius = {R}
material = "ball"

[[shapes]]
type = "plane"
name = "floor"
point = [0, 0, {floor}]
normal = [0, 0, 1]
material = "floor"

[[lights]]
type = "directional"
direction = [0, 0, -1]
color = [1, 1, 1]
{extra}
"#,
        floor = -depth
    )
}

fn caustics_table(photons: u64, radius: f64, filter: &str) -> String {
    format!("\n[caustics]\nphotons = {photons}\nradius = {radius}\nfilter = \"{filter}\"\n")
}

#[test]
fn paraxial_photons_cross_the_axis_at_the_ball_lens_focus() {
    // Two see-through diffuse screens (k_d > 0 stores a photon, k_t = 1 and n = 1 let it go
    // on straight) below the ball: the two points a photon leaves on them give its line,
    // and where the line meets the axis.
    let screens = r#"
[materials.screen]
color = [1, 1, 1]
kt = 1
n = 1

[[shapes]]
type = "plane"
name = "upper screen"
point = [0, 0, -1.25]
normal = [0, 0, 1]
material = "screen"

[[shapes]]
type = "plane"
name = "lower screen"
point = [0, 0, -2.5]
normal = [0, 0, 1]
material = "screen"
"#;
    let scene = ball_scene(0.0, 1.0, 10.0, screens);
    let accel = Accel::build_with(&scene.objects, AccelChoice::Auto);
    let f = paraxial_focus();
    let mut rng = Stream::new(7, Purpose::Generator, 0);
    let mut crossings = 0;
    for k in 0..200 {
        // Heights 0.0005 R .. 0.1 R, in several azimuths.
        let h = 0.1 * R * (k + 1) as f64 / 200.0;
        let phi = 2.0 * PI * rng.next_f64();
        let start = Start {
            ray: Ray::new(DVec3::new(h * phi.cos(), h * phi.sin(), 5.0), -DVec3::Z),
            flux: DVec3::ONE,
            spread: Spread::Parallel,
            target: 0,
        };
        let mut out = Vec::new();
        path::trace(&scene, &accel, start, 8, &mut rng, &mut out);
        // Stored on the upper screen, the lower screen, then the floor.
        assert_eq!(out.len(), 3, "height {h}: {out:?}");
        let (a, b) = (out[0].position, out[1].position);
        assert!((a.z + 1.25).abs() < 1e-9 && (b.z + 2.5).abs() < 1e-9);
        // The line a + s (b - a) at its closest to the z axis (it meets it: a meridional ray).
        let d = b - a;
        let s = -(a.x * d.x + a.y * d.y) / (d.x * d.x + d.y * d.y);
        let cross = a + s * d;
        assert!(
            cross.x.hypot(cross.y) < 1e-9 * R,
            "height {h}: misses the axis by {cross}"
        );
        let distance = -cross.z;
        assert!(
            (distance - f).abs() < 0.01 * f,
            "height {h}: crosses the axis at {distance} from the centre, f = {f}"
        );
        crossings += 1;
    }
    assert_eq!(crossings, 200);
}

#[test]
fn the_caustic_on_the_focal_plane_is_brightest_near_the_axis() {
    let f = paraxial_focus();
    let scene = ball_scene(0.0, 1.0, f, &caustics_table(200_000, 0.01, "cone"));
    let world = World::new(&scene);
    let map = world.photons.as_ref().expect("a photon map");
    // Along a radius of the floor, every 0.005 R from the axis to 1.5 R.
    let at = |x: f64| map.estimate(DVec3::new(x, 0.0, -f), DVec3::Z).irradiance.x;
    let samples: Vec<(f64, f64)> = (0..=300)
        .map(|i| (i as f64 * 0.005 * R, at(i as f64 * 0.005 * R)))
        .collect();
    let (x_max, e_max) = samples
        .iter()
        .copied()
        .fold((0.0, 0.0), |m, s| if s.1 > m.1 { s } else { m });
    assert!(x_max < 0.1 * R, "brightest at {x_max} from the axis ({e_max})");
    // Focused: far brighter than the light's own irradiance (1) and than the rim.
    assert!(e_max > 20.0, "{e_max}");
    let rim: Vec<f64> = samples.iter().filter(|s| s.0 >= 0.5 * R).map(|s| s.1).collect();
    let rim_mean = rim.iter().sum::<f64>() / rim.len() as f64;
    assert!(e_max > 10.0 * rim_mean, "{e_max} against {rim_mean} beyond R / 2");
}

/// The fraction of the photons entering the ball (uniform over its disk) that leave it
/// downwards. A ray entering at incidence `i` (height `R sin i`) leaves after two
/// refractions turned by `D = 2 (i - r)`, `sin r = sin i / n`; it goes up past `D = 90`
/// degrees, beyond `i0`, where `i0 - asin(sin(i0) / n) = 45` degrees (bisection). The
/// heights below `R sin(i0)` are the fraction `sin(i0)^2` of the disk.
fn fraction_leaving_downwards() -> f64 {
    let turned = |i: f64| i - (i.sin() / N).asin() - PI / 4.0;
    let (mut lo, mut hi) = (PI / 4.0, PI / 2.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if turned(mid) < 0.0 { lo = mid } else { hi = mid }
    }
    lo.sin().powi(2)
}

/// The integral of the estimated irradiance over the floor square `[-half, half]^2` at
/// height `z`, by the midpoint rule on cells of side `step`.
fn integrated(world: &World, z: f64, half: f64, step: f64) -> DVec3 {
    let map = world.photons.as_ref().unwrap();
    let n = (2.0 * half / step).round() as i64;
    let mut sum = DVec3::ZERO;
    for i in 0..n {
        for j in 0..n {
            let p = DVec3::new(-half + (i as f64 + 0.5) * step, -half + (j as f64 + 0.5) * step, z);
            sum += map.estimate(p, DVec3::Z).irradiance;
        }
    }
    sum * step * step
}

#[test]
fn a_clear_ball_sends_the_floor_the_power_it_intercepts() {
    // k_t = 1, k_r = 0, white: the ball intercepts pi R^2 from a light of irradiance 1 along
    // its axis, and the floor receives it, but for the grazing rays turned upwards.
    let intercepted = PI * R * R;
    let landing = fraction_leaving_downwards();
    assert!(landing > 0.99 && landing < 1.0, "{landing}");
    for filter in PhotonFilter::NAMES {
        let scene = ball_scene(0.0, 1.0, 1.2, &caustics_table(100_000, 0.04, filter));
        let world = World::new(&scene);
        let map = world.photons.as_ref().unwrap();
        let stored: DVec3 = map.photons().iter().map(|p| p.flux()).sum();
        assert!(
            (stored.x - intercepted).abs() < 0.01 * intercepted,
            "{filter}: {stored}"
        );
        // Each landing photon carries pi R^2 / 100 000: the count is binomial around the
        // landing fraction (standard deviation 0.02 % of it here).
        let expected = landing * intercepted;
        assert!(
            (stored.x - expected).abs() < 0.002 * expected,
            "{filter}: {stored} against {expected}"
        );
        // The density estimate gives the flux back: its integral over a floor square equals
        // the flux of the photons stored in it, within 1 %.
        let half = 2.0;
        let inside: f64 = map
            .photons()
            .iter()
            .filter(|p| p.position.x.abs() < half && p.position.y.abs() < half)
            .map(|p| p.flux().x)
            .sum();
        assert!(inside > 0.9 * intercepted, "{inside}");
        let power = integrated(&world, -1.2, half, 0.01);
        assert!(
            (power.x - inside).abs() < 0.01 * inside,
            "{filter}: the estimate integrates to {} against {inside}",
            power.x
        );
    }
}

#[test]
fn russian_roulette_keeps_the_expected_power() {
    // k_t = 0.5: half the photons are absorbed at the first surface, the others go on at
    // full flux (and, 0.5 again, at the second): the floor receives 0.5^2 of what it
    // receives with k_t = 1 in expectation. 200 000 photons: the binomial standard deviation
    // of the fraction kept, sqrt((1 - 0.25) / (0.25 x 200 000)), is 0.4 % of it.
    let scene = ball_scene(0.0, 0.5, 1.2, &caustics_table(200_000, 0.04, "cone"));
    let world = World::new(&scene);
    let map = world.photons.as_ref().unwrap();
    let stored: DVec3 = map.photons().iter().map(|p| p.flux()).sum();
    let expected = 0.25 * fraction_leaving_downwards() * PI * R * R;
    assert!(
        (stored.x - expected).abs() < 0.015 * expected,
        "{stored} against {expected}"
    );
}

#[test]
fn photons_from_a_point_light_carry_its_attenuation_along_the_unfolded_path() {
    // A point light 3 above a mirror disk (k_r = 1) facing up, under a diffuse ceiling at
    // height 4. The reflected photons reach the ceiling as if from the light's mirror image
    // (0, 0, -3): at the point above the light, after a path of length 3 + 7 - 3 = 7, at
    // normal incidence. The chapter's point light, of colour 1 and attenuation
    // A(d) = 1 / (1 + 0.02 d^2), gives irradiance A(7) = 1 / 1.98 there.
    let text = r#"
[image]
width = 32
height = 24
samples_per_pixel = 1

[camera]
position = [0, -6, 1]
look_at = [0, 0, 1]

[materials.mirror]
ka = 0
kd = 0
ks = 0
kr = 1

[materials.ceiling]
color = [1, 1, 1]

[[shapes]]
type = "disk"
name = "mirror"
center = [0, 0, 0]
normal = [0, 0, 1]
radius = 0.5
material = "mirror"

[[shapes]]
type = "plane"
name = "ceiling"
point = [0, 0, 4]
normal = [0, 0, -1]
material = "ceiling"

[[lights]]
type = "point"
position = [0, 0, 3]
color = [1, 1, 1]
attenuation = { quadratic = 0.02 }

[caustics]
photons = 1000000
radius = 0.15
filter = "epanechnikov"
"#;
    let scene = scene::parse(text, "mirror.toml").expect("parses");
    let world = World::new(&scene);
    let map = world.photons.as_ref().unwrap();
    let attenuation = |d: f64| 1.0 / (1.0 + 0.02 * d * d);
    let e = map.estimate(DVec3::new(0.0, 0.0, 4.0), -DVec3::Z).irradiance.x;
    assert!(
        (e - attenuation(7.0)).abs() < 0.03 * attenuation(7.0),
        "{e} against {}",
        attenuation(7.0)
    );
    // Off the axis, x = 0.6: distance sqrt(49.36) from the image, cosine 7 / sqrt(49.36).
    let d = 49.36f64.sqrt();
    let expected = attenuation(d) * 7.0 / d;
    let e = map.estimate(DVec3::new(0.6, 0.0, 4.0), -DVec3::Z).irradiance.x;
    assert!((e - expected).abs() < 0.03 * expected, "{e} against {expected}");
}

/// The reference scene with its two transparent spheres made glass (n = 1.5), caustics on,
/// at `width x height`, 1 sample.
fn glass_reference(width: u32, height: u32, photons: u64) -> Scene {
    let mut s = scene("reference.toml");
    for m in &mut s.materials {
        if m.kt > 0.0 {
            m.ior = 1.5;
        }
    }
    s.settings.width = width;
    s.settings.height = height;
    s.settings.samples_per_pixel = 1;
    s.settings.caustics = Some(CausticSettings {
        photons,
        radius: 0.1,
        filter: PhotonFilter::Cone,
        bounces: 8,
        seed: None,
    });
    s
}

#[test]
fn one_and_two_threads_give_the_same_photons_and_image() {
    let scene = glass_reference(64, 48, 50_000);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let world = World::new(&scene);
            let map = world.photons.as_ref().unwrap();
            let photons: Vec<u64> = map
                .photons()
                .iter()
                .flat_map(|p| p.position.to_array())
                .map(f64::to_bits)
                .collect();
            (photons, radiance_bits(&render(&world, &|| {}).0.pixels))
        })
    };
    let (one, two) = (run(1), run(2));
    assert!(!one.0.is_empty());
    assert_eq!(one.0, two.0, "the photon maps differ");
    assert_eq!(one.1, two.1, "the images differ");
}

#[test]
fn both_tracers_give_the_same_bits_with_caustics() {
    let scene = glass_reference(64, 48, 50_000);
    let world = World::new(&scene);
    let (fast, _) = render(&world, &|| {});
    let (reference, _) = render_reference(&world, &|| {});
    assert_eq!(radiance_bits(&fast.pixels), radiance_bits(&reference.pixels));
    // The caustics change the image: without them the same glass scene differs.
    let mut plain = scene.clone();
    plain.settings.caustics = None;
    let (without, _) = render(&World::new(&plain), &|| {});
    assert_ne!(radiance_bits(&fast.pixels), radiance_bits(&without.pixels));
}

#[test]
fn shards_merge_to_the_whole_caustic_image() {
    let dir = temp_dir("caustic-shards");
    let text = std::fs::read_to_string(repo("scenes/figures/caustics/01-reference-glass.toml")).unwrap();
    let file = dir.join("glass.toml");
    std::fs::write(&file, text).unwrap();
    let f = file.to_str().unwrap();
    let small = ["--width", "64", "--height", "48", "--quiet"];
    let whole = dir.join("whole.png");
    let o = lumiere(&[&["render", f, "-o", whole.to_str().unwrap()][..], &small[..]].concat());
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let mut shards = Vec::new();
    for k in 0..2 {
        let out = dir.join(format!("part{k}.shard"));
        let spec = format!("{k}/2");
        let o = lumiere(
            &[
                &["render", f, "--shard", &spec, "-o", out.to_str().unwrap()][..],
                &small[..],
            ]
            .concat(),
        );
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        shards.push(out.to_str().unwrap().to_string());
    }
    let merged = dir.join("merged.png");
    let o = lumiere(&["merge", &shards[0], &shards[1], "-o", merged.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let (a, b) = (
        lumiere::compare::load_rgb8(&whole).unwrap(),
        lumiere::compare::load_rgb8(&merged).unwrap(),
    );
    assert_eq!(a, b);
}

#[test]
fn with_caustics_only_glass_of_index_other_than_1_blocks_shadow_rays() {
    // A point on the floor in the shadow of the reference scene's yellow sphere (index 1,
    // k_t 0.7) under the directional light d = (1, 1, -1): below its centre (1, -5, 3) along
    // d, (1, -5, 3) + 3 d. The ray back to the light passes the mauve sphere (2, -4, 3) at
    // sqrt(17 - 49 / 3) = 0.82 > 0.75 from its centre: the yellow sphere alone filters it.
    let floor_point = DVec3::new(4.0, -2.0, 0.0);
    let filter_of = |scene: &Scene| {
        let world = World::new(scene);
        let light = scene
            .lights
            .iter()
            .find(|l| matches!(l, Light::Directional { .. }))
            .unwrap();
        let inc = light.incidence(floor_point).unwrap();
        Tracer::new(&world).shadow_filter(floor_point, DVec3::Z, 1e-12, &inc)
    };
    let base = scene("reference.toml");
    let yellow = base.materials[base.material_names.iter().position(|n| n == "yellow").unwrap()].color;
    // Index 1, caustics off and on: the chapter's colour filter.
    assert_eq!(filter_of(&base), yellow);
    let mut on = base.clone();
    on.settings.caustics = glass_reference(8, 8, 10).settings.caustics;
    assert_eq!(filter_of(&on), yellow);
    // Index 1.5: the colour filter without caustics, blocked with them.
    let glass = glass_reference(8, 8, 10);
    let mut off = glass.clone();
    off.settings.caustics = None;
    assert_eq!(filter_of(&off), yellow);
    assert_eq!(filter_of(&glass), DVec3::ZERO);
}

/// The first hit along a recorded camera ray, with its caustic record.
/// The object a recorded camera ray hits (`""` when it misses), the sum of the caustic term
/// there, and whether some light reaches the point directly.
fn camera_hit(node: &RayNode) -> (&str, f64, bool) {
    let name = node.hit.as_ref().map_or("", |h| h.name.as_str());
    let caustic = node.caustic.as_ref().map_or(0.0, |c| c.term.iter().sum());
    let lit = node
        .lights
        .iter()
        .any(|l| l.share.as_ref().is_some_and(|s| s.filter != [0.0; 3]));
    (name, caustic, lit)
}

#[test]
fn the_prism_casts_a_caustic_on_its_disk_where_no_direct_light_arrives() {
    let mut scene = scene("prism.toml");
    scene.settings.width = 80;
    scene.settings.height = 60;
    scene.settings.samples_per_pixel = 1;
    scene.settings.caustics = Some(CausticSettings {
        photons: 200_000,
        radius: 0.1,
        filter: PhotonFilter::Cone,
        bounces: 8,
        seed: None,
    });
    let world = World::new(&scene);
    let mut tracer = Tracer::new(&world);
    let mut found = None;
    'scan: for y in 0..60 {
        for x in 0..80 {
            let mut rec = TreeRecorder::new(&scene);
            render_sample(&mut tracer, x, y, 0, &mut rec);
            let (name, caustic, lit) = camera_hit(&rec.samples[0].ray);
            if name == "disk" && caustic > 0.0 && !lit {
                found = Some((x, y));
                break 'scan;
            }
        }
    }
    let (x, y) = found.expect("a disk pixel in the prism's shadow with caustic light");
    // The probe, as `lumiere probe` runs it, reports the same.
    let p = probe(&scene, x, y, Some(0)).unwrap();
    let ray = &p.samples[0].ray;
    let (name, caustic, lit) = camera_hit(ray);
    assert!(name == "disk" && caustic > 0.0 && !lit);
    let c = ray.caustic.as_ref().unwrap();
    assert!(c.photons > 0 && c.radius == 0.1);
    let counts = p.photons.expect("the photon counts");
    assert_eq!(counts.emitted, 200_000);
    assert!(counts.stored > 0);
    let text = lumiere::probe::format_text(&p);
    assert!(
        text.contains(&format!("caustic: {} photon(s) within 0.100000", c.photons)),
        "{text}"
    );
    assert!(text.contains(&format!(
        "caustics: {} photon(s) stored of 200000 emitted",
        counts.stored
    )));
}

#[test]
fn without_a_caustics_table_nothing_changes() {
    let s = scene("reference.toml");
    assert_eq!(s.settings.caustics, None);
    let world = World::new(&s);
    assert!(world.photons.is_none());
    // The probe's JSON has no caustic fields.
    let p = probe(&s, 400, 500, Some(0)).unwrap();
    let json = serde_json::to_string(&p).unwrap();
    assert!(!json.contains("caustic") && !json.contains("photons"), "{json}");
}

#[test]
fn the_caustics_table_is_checked_with_located_errors() {
    let base = "[image]\nwidth = 8\nheight = 8\n\n[camera]\nposition = [0, -5, 0]\nlook_at = [0, 0, 0]\n\n[caustics]\n";
    let cases = [
        (
            "photons = 0\n",
            "x.toml:10:11: caustics.photons: must be in [1, 10000000], got 0",
        ),
        (
            "photons = 10\nradius = -1\n",
            "x.toml:11:10: caustics.radius: must be a finite number in (0, 1e9], got -1",
        ),
        (
            "photons = 10\nfilter = \"gauss\"\n",
            "x.toml:11:10: caustics.filter: must be one of [\"flat\", \"cone\", \"epanechnikov\"], got \"gauss\"",
        ),
        (
            "photons = 10\nbounces = 0\n",
            "x.toml:11:11: caustics.bounces: must be in [1, 64], got 0",
        ),
    ];
    for (table, message) in cases {
        let e = scene::parse(&format!("{base}{table}"), "x.toml").expect_err(table);
        assert_eq!(e.to_string(), message);
    }
    // An unknown key and a missing count are refused too.
    let e = scene::parse(&format!("{base}photons = 10\nradious = 1\n"), "x.toml").unwrap_err();
    assert!(
        e.to_string()
            .starts_with("x.toml:11:1: caustics.radious: unknown field"),
        "{e}"
    );
    let e = scene::parse(&format!("{base}radius = 1\n"), "x.toml").unwrap_err();
    assert!(e.to_string().contains("missing field `photons`"), "{e}");
    // The command line exits 2 and writes nothing.
    let dir = temp_dir("caustic-errors");
    let file = dir.join("x.toml");
    std::fs::write(&file, format!("{base}photons = 0\n")).unwrap();
    let out = dir.join("x.png");
    let o = lumiere(&["render", file.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("caustics.photons: must be in [1, 10000000], got 0"));
    assert!(!out.exists());
}

#[test]
fn photon_streams_are_keyed_by_seed_and_index() {
    // The map is built from photon i's own stream: a different seed moves the photons.
    let scene = glass_reference(8, 8, 20_000);
    let mut other = scene.clone();
    other.settings.seed += 1;
    let map = |s: &Scene| {
        let accel = Accel::build_with(&s.objects, AccelChoice::Auto);
        caustics::build(s, &accel, s.settings.caustics.as_ref().unwrap())
    };
    let (a, b, c) = (map(&scene), map(&scene), map(&other));
    let pos = |m: &caustics::PhotonMap| m.photons().iter().map(|p| p.position.to_array()).collect::<Vec<_>>();
    assert_eq!(pos(&a), pos(&b));
    assert_ne!(pos(&a), pos(&c));
}

#[test]
fn a_diffuse_image_colours_the_caustic_as_it_colours_the_diffuse_term() {
    // The ball lens over a floor whose diffuse colour is an image of one red texel, with
    // `kd = 0`: the image takes the diffuse term whole (texel 255 / 255 = 1 exactly, `k_d`
    // not applied), so the floor reflects as a plain red floor of `kd = 1` does, and the
    // caustic on it, `E k_d S`, is `E (1, 0, 0)` in both. A floor whose `kd` alone decided
    // would receive no photon and show no caustic.
    let dir = temp_dir("caustic-texture");
    image::save_buffer(
        dir.join("red.png"),
        &[255u8, 0, 0],
        1,
        1,
        image::ExtendedColorType::Rgb8,
    )
    .unwrap();
    let scene_with = |floor_material: &str| {
        let text = ball_scene_text(0.0, 1.0, 1.2, &caustics_table(20_000, 0.05, "cone"))
            .replace("[materials.floor]\ncolor = [1, 1, 1]\n", floor_material);
        let file = dir.join("ball.toml");
        std::fs::write(&file, text).unwrap();
        scene::load(&file).unwrap()
    };
    let textured = scene_with("[materials.floor]\nka = 0\nkd = 0\nks = 0\ntexture_kd = \"red.png\"\n");
    let red = scene_with("[materials.floor]\ncolor = [1, 0, 0]\nka = 0\nkd = 1\nks = 0\n");
    let image = |s: &Scene| radiance_bits(&render(&World::new(s), &|| {}).0.pixels);
    let differing = |a: &[u64], b: &[u64]| a.iter().zip(b).filter(|(x, y)| x != y).count();
    assert_eq!(differing(&image(&textured), &image(&red)), 0);
    let mut dark = red.clone();
    dark.settings.caustics = None;
    assert!(
        differing(&image(&red), &image(&dark)) > 0,
        "the caustic shows on the floor"
    );
    // The photons land on the textured floor as on the red one.
    let landed = |s: &Scene| World::new(s).photons.as_ref().unwrap().photons().len();
    assert!(landed(&textured) > 1000);
    assert_eq!(landed(&textured), landed(&red));
}
