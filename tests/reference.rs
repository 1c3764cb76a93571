//! The fast tracer against the reference tracer: the same radiance to the bit (each
//! pixel's f64 channels, not only its 8-bit value) on every course figure's scene, on the
//! scene files, and on scenes that exercise what the fast tracer groups or skips: per-sample
//! area light points, adaptive depth control, transparent filters, the BVH.

use crate::common::scene;
use glam::DVec3;
use lumiere::figures::{registry, scaled};
use lumiere::film::Film;
use lumiere::render::{render, render_reference};
use lumiere::scene::Scene;
use lumiere::world::World;

/// `scene` at `width x height`, `spp` samples.
fn sized(mut scene: Scene, width: u32, height: u32, spp: u32) -> Scene {
    scene.settings.width = width;
    scene.settings.height = height;
    scene.settings.samples_per_pixel = spp;
    scene
}

/// Renders `scene` with both tracers and asserts every pixel's radiance bits are equal;
/// returns how many pixels are lit (not black), so a caller can check the scene is not
/// trivially dark.
fn assert_tracers_agree(scene: &Scene, name: &str) -> usize {
    let world = World::new(scene);
    let (fast, _) = render(&world, &|| {});
    let (reference, stats) = render_reference(&world, &|| {});
    let s = &scene.settings;
    assert_eq!(
        stats.counts.camera,
        s.width as u64 * s.height as u64 * s.samples_per_pixel as u64
    );
    assert_same_bits(&fast, &reference, name);
    fast.pixels.iter().filter(|p| **p != DVec3::ZERO).count()
}

fn assert_same_bits(fast: &Film, reference: &Film, name: &str) {
    assert_eq!((fast.width, fast.height), (reference.width, reference.height));
    for (i, (a, b)) in fast.pixels.iter().zip(&reference.pixels).enumerate() {
        let bits = |c: &DVec3| c.to_array().map(f64::to_bits);
        assert_eq!(
            bits(a),
            bits(b),
            "{name}: pixel ({}, {}): fast {a} against reference {b}",
            i as u32 % fast.width,
            i as u32 / fast.width
        );
    }
}

#[test]
fn every_course_figure_is_the_reference_image() {
    let mut scenes = 0;
    for set in registry().expect("the figure files load") {
        let mut done: Vec<Scene> = Vec::new();
        for figure in set.figures {
            if done.contains(&figure.scene) {
                continue;
            }
            let s = scaled(figure.scene.clone(), 0.1);
            let (w, h) = (s.settings.width.min(64), s.settings.height.min(48));
            let lit = assert_tracers_agree(&sized(s, w, h, 1), &format!("{}/{}", set.name, figure.stem));
            assert!(lit > 0, "{}/{}: a black image compares nothing", set.name, figure.stem);
            done.push(figure.scene);
            scenes += 1;
        }
    }
    // 84 figures, some sharing a scene.
    assert!(scenes >= 70, "{scenes} scenes compared");
}

#[test]
fn under_simrenderer_conventions_too() {
    use lumiere::conventions::Conventions;
    // Every switch away from the chapter's at once, and each on its own from the chapter's.
    let mut each = vec![Conventions::SIMRENDERER];
    for (key, value) in Conventions::SIMRENDERER.describe() {
        let mut c = Conventions::CHAPTER;
        c.set(key, &value).unwrap();
        each.push(c);
    }
    let mut remaining = Conventions::SIMRENDERER;
    remaining.set("local_weight", "remaining").unwrap();
    each.push(remaining);
    for conventions in each {
        for name in ["reference.toml", "prism.toml", "mirrors.toml", "soft-shadows.toml"] {
            let mut s = sized(scene(name), 40, 30, 4);
            s.settings.depth = s.settings.depth.max(6);
            s.set_conventions(conventions);
            let lit = assert_tracers_agree(&s, &format!("{name} under {}", conventions.summary()));
            assert!(lit > 100, "{name} under {}: {lit} lit pixels", conventions.summary());
        }
    }
}

#[test]
fn the_scene_files_are_the_reference_images() {
    for name in [
        "reference.toml",
        "mirrors.toml",
        "prism.toml",
        "soft-shadows.toml",
        "spheres-1k.toml",
    ] {
        let s = sized(scene(name), 48, 36, 4);
        assert!(assert_tracers_agree(&s, name) > 100, "{name}");
    }
}

#[test]
fn textured_scenes_and_lenses_are_the_reference_images() {
    use lumiere::area_light::{AreaLight, AreaShape, PointMode};
    use lumiere::light::{Attenuation, Light};
    use lumiere::placement::Placement;
    use std::sync::Arc;
    let textured = sized(scene("figures/optique/05-textured-sphere.toml"), 48, 36, 4);
    assert!(assert_tracers_agree(&textured, "textured sphere") > 100);
    // Every term from an image (the specular one too), under an area light whose points
    // the fast tracer shades in lanes, and a point light.
    let mut all = textured.clone();
    for m in &mut all.materials {
        if let Some(colors) = &m.term_colors {
            let mut colors = (**colors).clone();
            if let Some(maps) = &mut colors.images {
                maps.specular = maps.diffuse.clone();
            }
            m.term_colors = Some(Arc::new(colors));
        }
    }
    all.lights.push(Light::Area(AreaLight {
        shape: AreaShape::Sphere {
            center: DVec3::new(-2.0, -3.0, 4.0),
            radius: 0.5,
        },
        count: 8,
        placement: Placement::parse("fibonacci").unwrap(),
        mode: PointMode::Fixed,
        color: DVec3::splat(0.6),
        attenuation: Attenuation {
            constant: 1.0,
            linear: 0.0,
            quadratic: 0.0,
        },
    }));
    assert!(assert_tracers_agree(&all, "textured sphere, every term, area light") > 100);
    let lens = sized(scene("figures/optique/04-lens.toml"), 48, 36, 4);
    assert!(assert_tracers_agree(&lens, "lens") > 100);
}

#[test]
fn per_sample_points_adaptive_depth_and_filters_agree() {
    use lumiere::area_light::PointMode;
    use lumiere::light::Light;
    // Soft shadows with points drawn afresh for every sample (each sample its own set).
    let mut soft = sized(scene("soft-shadows.toml"), 40, 30, 4);
    for light in &mut soft.lights {
        if let Light::Area(a) = light {
            a.mode = PointMode::PerSample;
            a.count = 16;
        }
    }
    assert!(assert_tracers_agree(&soft, "per-sample soft shadows") > 100);
    // The prism deep, with adaptive depth control cutting rays off, and without it.
    for threshold in [0.0, 1.0, 8.0] {
        let mut prism = sized(scene("prism.toml"), 40, 30, 1);
        prism.settings.depth = 12;
        prism.settings.adaptive_threshold = threshold;
        assert!(assert_tracers_agree(&prism, &format!("prism, threshold {threshold}")) > 100);
    }
    // The reference scene without shadows, and with Phong highlights.
    let mut flat = sized(scene("reference.toml"), 40, 30, 1);
    flat.settings.shadows = false;
    assert_tracers_agree(&flat, "no shadows");
    let mut phong = sized(scene("reference.toml"), 40, 30, 1);
    phong.settings.shading.specular = lumiere::scene::Specular::Phong;
    assert_tracers_agree(&phong, "phong");
}

#[test]
fn aperture_lights_agree() {
    use lumiere::interference::{Aperture, ApertureLight, Planar};
    use lumiere::light::{Attenuation, Light};
    // The reference scene (opaque objects, two transparent spheres) under a slit, an
    // ellipse and a rectangle of coherent oscillators, with and without shadows.
    let mut s = sized(scene("reference.toml"), 48, 36, 2);
    let planar = Planar {
        center: DVec3::new(0.0, -2.0, 8.0),
        front: DVec3::NEG_Z,
        up: DVec3::Y,
        width: 2e-4,
        height: 1e-4,
    };
    let apertures = [
        (
            Aperture::Linear {
                start: DVec3::new(-5e-5, 0.0, 9.0),
                end: DVec3::new(5e-5, 0.0, 9.0),
            },
            2,
        ),
        (Aperture::Elliptical(planar.clone()), 6),
        (Aperture::Rectangular(planar), 3),
    ];
    for (aperture, n) in apertures {
        let light = ApertureLight::new(aperture, 600.0, n, 10, 1.0, Attenuation::NONE).unwrap();
        s.lights.push(Light::Aperture(light));
    }
    assert!(assert_tracers_agree(&s, "aperture lights") > 100);
    s.settings.shadows = false;
    assert!(assert_tracers_agree(&s, "aperture lights without shadows") > 100);
}

#[test]
fn render_reference_writes_the_same_bytes() {
    let dir = crate::common::temp_dir("reference-cli");
    let (fast, reference) = (dir.join("fast.png"), dir.join("reference.png"));
    let scene = crate::common::repo("scenes/soft-shadows.toml");
    for (out, extra) in [(&fast, None), (&reference, Some("--reference"))] {
        let mut args = vec!["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()];
        args.extend(["--width", "64", "--height", "48", "-q"]);
        args.extend(extra);
        let run = crate::common::lumiere(&args);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    }
    let (a, b) = (std::fs::read(&fast).unwrap(), std::fs::read(&reference).unwrap());
    assert!(a.len() > 1000);
    assert_eq!(a, b, "render --reference must write the bytes of render");
    // The reference counts nothing but camera rays, so it takes no --stats.
    let run = crate::common::lumiere(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        "x.png",
        "--reference",
        "--stats",
    ]);
    assert_eq!(run.status.code(), Some(2));
}
