//! One-pass families (src/family.rs): images whose scenes differ only in depth, in one
//! fixed area light's count, in shading or (without area lights) in their lights, rendered
//! together, give the bytes and ray counts of separate renders; and only such scenes are
//! grouped.

use crate::common::*;
use lumiere::area_light::PointMode;
use lumiere::family;
use lumiere::figures::{registry, scaled};
use lumiere::light::Light;
use lumiere::render::render;
use lumiere::scene::Scene;
use lumiere::trace::RayCounts;
use lumiere::world::World;
use std::sync::atomic::AtomicBool;

/// The scenes of the figures `stems` of set `set`, at `scale`.
fn figure_scenes(set: &str, stems: &[&str], scale: f64) -> Vec<Scene> {
    let set = registry().unwrap().into_iter().find(|s| s.name == set).unwrap();
    let figures = set.figures;
    stems
        .iter()
        .map(|stem| {
            let f = figures
                .iter()
                .find(|f| f.stem == *stem)
                .unwrap_or_else(|| panic!("{stem}"));
            scaled(f.scene.clone(), scale)
        })
        .collect()
}

/// The counts a figure's manifest records.
fn recorded(c: &RayCounts) -> [u64; 7] {
    [
        c.camera,
        c.shadow,
        c.reflection,
        c.refraction,
        c.total_internal_reflections,
        c.adaptive_cutoffs,
        c.non_finite,
    ]
}

/// Renders `scenes` as one family and each alone: same bytes, same counts, one group.
fn family_equals_separate_renders(scenes: &[Scene]) {
    let refs: Vec<&Scene> = scenes.iter().collect();
    assert_eq!(family::group(&refs), vec![(0..scenes.len()).collect::<Vec<_>>()]);
    let together = family::render(&refs, &AtomicBool::new(false)).expect("no divergence");
    assert_eq!(together.len(), scenes.len());
    for (i, (scene, (rgb, stats))) in scenes.iter().zip(&together).enumerate() {
        let (film, alone) = render(&World::new(scene), &|| {});
        assert!(rgb == &film.to_rgb8(), "image {i}: bytes differ");
        assert_eq!(recorded(&stats.counts), recorded(&alone.counts), "image {i}: counts");
        assert!(!stats.diverged);
    }
}

#[test]
fn area_light_counts_in_one_pass_are_separate_renders() {
    // N = 1, 5, 25, 100 and 200 on the reference scene, with its transparent spheres
    // (refracted rays shaded by every lane) and filtered soft shadows.
    let stems = [
        "03-points-1",
        "04-points-5",
        "05-points-25",
        "06-points-100",
        "02-soft-200",
    ];
    let scenes = figure_scenes("soft-shadows", &stems, 0.08);
    family_equals_separate_renders(&scenes);
    // The members differ: five distinct images.
    let refs: Vec<&Scene> = scenes.iter().collect();
    let images = family::render(&refs, &AtomicBool::new(false)).unwrap();
    for i in 0..images.len() {
        for j in 0..i {
            assert_ne!(images[i].0, images[j].0, "images {i} and {j}");
        }
    }
}

/// Every figure's scene of set `set`, at `scale`.
fn set_scenes(set: &str, scale: f64) -> Vec<Scene> {
    let set = registry().unwrap().into_iter().find(|s| s.name == set).unwrap();
    set.figures.into_iter().map(|f| scaled(f.scene, scale)).collect()
}

#[test]
fn lightings_in_one_pass_are_separate_renders() {
    // The reference scene under the lightings of four sets and soft-shadows' hard shadows:
    // ambient alone, a directional light alone, with ambient, in four orientations, point
    // lights with and without attenuation, two spots. One pass, each lane its own lights'
    // shares and shadow rays (the spots' unlit points cast none).
    let mut scenes: Vec<Scene> = ["lighting", "directional", "attenuation", "spotlight"]
        .into_iter()
        .flat_map(|set| set_scenes(set, 0.08))
        .collect();
    scenes.extend(figure_scenes("soft-shadows", &["01-hard"], 0.08));
    assert_eq!(scenes.len(), 12);
    family_equals_separate_renders(&scenes);
    // Two lights in both orders, one of them twice: the union [a, b, a, b] keeps each
    // lane's order (the union itself is checked in src/family.rs's unit tests).
    let [ambient, a] = [&scenes[2].lights[0], &scenes[2].lights[1]].map(Clone::clone);
    let b = scenes[8].lights[1].clone();
    let mut orders = vec![scenes[2].clone(), scenes[2].clone(), scenes[2].clone()];
    orders[0].lights = vec![ambient.clone(), a.clone(), b.clone()];
    orders[1].lights = vec![b.clone(), ambient, a.clone()];
    orders[2].lights = vec![a.clone(), a, b];
    family_equals_separate_renders(&orders);
}

#[test]
fn depths_in_one_pass_are_separate_renders() {
    // Mirrors at 60 degrees, depth 1 to 10 (adaptive cutoffs per lane), and the prism at
    // depth 1 to 12 (16-lane pass: refraction and total internal reflection).
    let stems: Vec<String> = (1..=10).map(|d| format!("{:02}-opening-60-depth-{d:02}", d)).collect();
    let stems: Vec<&str> = stems.iter().map(String::as_str).collect();
    family_equals_separate_renders(&figure_scenes("mirrors", &stems, 0.1));
    let stems: Vec<String> = (1..=12).map(|d| format!("{:02}-depth-{d:02}", d + 1)).collect();
    let stems: Vec<&str> = stems.iter().map(String::as_str).collect();
    let prism = figure_scenes("prism", &stems, 0.1);
    family_equals_separate_renders(&prism);
}

#[test]
fn depth_and_count_together_are_separate_renders() {
    let mut scenes = figure_scenes("soft-shadows", &["04-points-5", "05-points-25", "03-points-1"], 0.06);
    scenes[0].settings.depth = 1;
    scenes[1].settings.depth = 3;
    scenes[2].settings.depth = 2;
    family_equals_separate_renders(&scenes);
}

#[test]
fn shading_models_in_one_pass_are_separate_renders() {
    // The slides' sweeps: terms on and off, Phong and Blinn exponents 2 ... 512, metal
    // factors: one shadow ray per light for all, each lane its own shading.
    let set = registry().unwrap().into_iter().find(|s| s.name == "shading").unwrap();
    let scenes: Vec<Scene> = set
        .figures
        .into_iter()
        .filter(|f| f.stem != "23-metal-0") // the combined figure's scene again
        .map(|f| scaled(f.scene, 0.1))
        .collect();
    assert_eq!(scenes.len(), 24);
    family_equals_separate_renders(&scenes[..16]);
    family_equals_separate_renders(&scenes[16..]);
}

#[test]
fn shading_and_area_counts_together_are_separate_renders() {
    // Area-light lanes with other exponents, another model and another metal factor: the
    // specular terms are computed again per exponent, the sums kept apart per shading.
    let mut scenes = figure_scenes(
        "soft-shadows",
        &["04-points-5", "05-points-25", "05-points-25", "04-points-5"],
        0.06,
    );
    let torus = |s: &mut Scene| {
        let m = s.material_names.iter().position(|n| n == "green").unwrap();
        s.materials[m].shininess = 7.0;
        s.materials[m].metal = 0.5;
    };
    torus(&mut scenes[1]);
    scenes[2].settings.shading.specular = lumiere::scene::Specular::Phong;
    scenes[3].settings.shading.diffuse = false;
    family_equals_separate_renders(&scenes[..3]);
    let refs: Vec<&Scene> = scenes.iter().collect();
    assert_eq!(family::group(&refs), vec![vec![0, 1, 2, 3]]);
    family_equals_separate_renders(&[scenes[3].clone(), scenes[0].clone(), scenes[1].clone()]);
}

#[test]
fn only_scenes_one_pass_can_render_are_grouped() {
    let soft = figure_scenes(
        "soft-shadows",
        &["01-hard", "03-points-1", "08-points-1000", "04-points-5"],
        0.1,
    );
    let refs: Vec<&Scene> = soft.iter().collect();
    // The point light's scene is not an area light's.
    assert_eq!(family::group(&refs), vec![vec![0], vec![1, 2, 3]]);
    // Points drawn per sample are not one sequence's prefixes; a moved camera is another
    // scene; so is another seed (other points, other jitter).
    let mut per_sample = soft[3].clone();
    if let Light::Area(a) = &mut per_sample.lights[1] {
        a.mode = PointMode::PerSample;
    }
    let mut moved = soft[3].clone();
    moved.camera.position.x += 0.5;
    let mut reseeded = soft[3].clone();
    reseeded.settings.seed += 1;
    for other in [per_sample, moved, reseeded] {
        assert_eq!(family::group(&[&soft[1], &other]), vec![vec![0], vec![1]]);
    }
    // Another colour (shadow filters) or another k_t (the ray tree) is another scene.
    let mut recoloured = soft[3].clone();
    recoloured.materials[1].color.x *= 0.5;
    let mut clearer = soft[3].clone();
    clearer.materials[1].kt = 0.3;
    for other in [recoloured, clearer] {
        assert_eq!(family::group(&[&soft[1], &other]), vec![vec![0], vec![1]]);
    }
    // Two lights whose counts both vary cannot share one pass.
    let mut two = soft[1].clone();
    two.lights.push(two.lights[1].clone());
    let mut two_other = two.clone();
    for (index, count) in [(1, 5), (2, 25)] {
        if let Light::Area(a) = &mut two_other.lights[index] {
            a.count = count;
        }
    }
    assert_eq!(family::group(&[&two, &two_other]), vec![vec![0], vec![1]]);
}

#[test]
fn committed_prism_set_is_reproduced_bit_for_bit_in_one_pass() {
    // Full size, depth 1 to 20 in two passes (16 + 4 lanes) and the top view alone.
    assert_eq!(committed_set_mismatches("prism"), Vec::<String>::new());
}

#[test]
fn lanes_that_cannot_share_light_points_are_refused() {
    // A light of colour 1e-300 behind an attenuation of at most 6e-22 (C_quad 1e20, every
    // surface 4 or more from the light points): each of the N = 1000
    // points carries 1e-303 and arrives below 6e-325, which rounds to 0 (black: no shadow ray),
    // while the lone point of N = 1 arrives as 1e-323 or more, not 0. The lanes would need
    // different shadow rays, so the pass reports it and the images are rendered one by one.
    let mut scenes = figure_scenes("soft-shadows", &["03-points-1", "08-points-1000"], 0.03);
    for s in &mut scenes {
        if let Light::Area(a) = &mut s.lights[1] {
            a.color = glam::DVec3::splat(1e-300);
            a.attenuation.quadratic = 1e20;
        }
    }
    let refs: Vec<&Scene> = scenes.iter().collect();
    assert_eq!(family::group(&refs), vec![vec![0, 1]]);
    assert!(family::render(&refs, &AtomicBool::new(false)).is_none());
    // Alone, N = 1000 casts no shadow ray at all and N = 1 casts some.
    let shadow = |s: &Scene| render(&World::new(s), &|| {}).1.counts.shadow;
    assert_eq!(shadow(&scenes[1]), 0);
    assert!(shadow(&scenes[0]) > 0);
}

#[test]
fn the_families_are_found_from_the_figure_files() {
    // Every figure of every set's files, grouped as one run over all sets groups them: by
    // the scenes alone, whatever code or file order made them.
    let sets = registry().unwrap();
    let named: Vec<(String, &Scene)> = sets
        .iter()
        .flat_map(|s| {
            s.figures
                .iter()
                .map(move |f| (format!("{}/{}", s.name, f.stem), &f.scene))
        })
        .collect();
    let scenes: Vec<&Scene> = named.iter().map(|(_, s)| *s).collect();
    let groups: Vec<Vec<&str>> = family::group(&scenes)
        .into_iter()
        .filter(|g| g.len() > 1)
        .map(|g| g.into_iter().map(|i| named[i].0.as_str()).collect())
        .collect();
    let range = |set: &str, stems: &[&str]| stems.iter().map(|s| format!("{set}/{s}")).collect::<Vec<_>>();
    // The reference scene under its eleven lightings (directional/01 is lighting/03's scene).
    let mut lightings = range("lighting", &["01-ambient", "02-directional", "03-ambient-directional"]);
    lightings.extend(range(
        "directional",
        &["01-d-1-1--1", "02-d-0p5-1--1", "03-d-0-1--1", "04-d--1-1--1"],
    ));
    lightings.extend(range("attenuation", &["01-no-attenuation", "02-quadratic-0p01"]));
    lightings.extend(range("spotlight", &["01-theta-70", "02-theta-120"]));
    lightings.extend(range("soft-shadows", &["01-hard"]));
    // The spherical light's N = 1 ... 1000 (and light-shapes' sphere, N = 100).
    let mut sphere = range(
        "soft-shadows",
        &[
            "02-soft-200",
            "03-points-1",
            "04-points-5",
            "05-points-25",
            "06-points-100",
            "07-points-200",
            "08-points-1000",
        ],
    );
    sphere.push("light-shapes/01-sphere".into());
    let mirrors: Vec<String> = (1..=10)
        .map(|d| format!("mirrors/{d:02}-opening-60-depth-{d:02}"))
        .collect();
    let prism: Vec<String> = (1..=20).map(|d| format!("prism/{:02}-depth-{d:02}", d + 1)).collect();
    let shading: Vec<String> = sets[8].figures.iter().map(|f| format!("shading/{}", f.stem)).collect();
    assert_eq!(shading.len(), 25);
    // The slits: one screen under three lights.
    let optique: Vec<String> = ["01-two-slits", "02-grating", "03-single-slit"]
        .map(|f| format!("optique/{f}"))
        .into();
    assert_eq!(groups, [lightings, sphere, mirrors, prism, shading, optique]);
}
