//! The figure sets: every figure pinned as a small PNG snapshot, the committed full-size
//! figures reproduced bit for bit, and the gallery and contact sheets written.

mod common;
use common::*;
use lumiere::figures::{self, registry, render_figure};

/// Scale of the snapshot images: 80 x 60 from the 800 x 600 figures.
const SNAPSHOT_SCALE: f64 = 0.1;

#[test]
fn every_figure_matches_its_snapshot() {
    let settings = snapshot_settings();
    let mut count = 0;
    for set in registry() {
        for figure in (set.figures)() {
            let name = format!("figure__{}__{}.png", set.name, figure.stem);
            let r = render_figure(figure, SNAPSHOT_SCALE);
            assert_eq!((r.image.width(), r.image.height()), (80, 60));
            let png = lumiere::film::encode_png(80, 60, r.image.as_raw()).unwrap();
            settings.bind(|| insta::assert_binary_snapshot!(name.as_str(), png));
            count += 1;
        }
    }
    // lighting 3 + directional 4 + attenuation 2 + spotlight 2 + soft-shadows 8 +
    // light-shapes 3 + mirrors 13 + prism 21 + shading 25: every figure of FIGURES.md.
    assert_eq!(count, 81);
}

#[test]
fn committed_lighting_set_is_reproduced_bit_for_bit() {
    // Full size, 800 x 600 with 4 samples: the pixel hashes of figures/lighting/manifest.json.
    // `lumiere figures --check` does the same for every set.
    assert_eq!(committed_set_mismatches("lighting"), vec![]);
}

#[test]
fn generate_writes_images_manifest_sheet_and_gallery() {
    let out = temp_dir("figures");
    let set = registry().into_iter().find(|s| s.name == "spotlight").unwrap();
    let report = figures::generate(&set, &out, 0.05).unwrap();
    assert_eq!(report.images, 2);
    for f in [
        "01-theta-70.png",
        "02-theta-120.png",
        "contact-sheet.png",
        "manifest.json",
    ] {
        assert!(out.join("spotlight").join(f).is_file(), "{f}");
    }
    let img = image::open(out.join("spotlight/01-theta-70.png")).unwrap();
    assert_eq!((img.width(), img.height()), (40, 30));
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("spotlight/manifest.json")).unwrap()).unwrap();
    let first = &manifest["images"][0];
    assert_eq!(first["caption"], "Avec un angle d'ouverture θ = 70°");
    assert_eq!(first["seed"], 42);
    assert_eq!(first["samples_per_pixel"], 4);
    assert_eq!(first["rays"]["camera"], 40 * 30 * 4);
    assert_eq!(first["scene"]["lights"][1]["angle_deg"], 70.0);
    assert!(first["pixel_hash"].as_str().unwrap().starts_with("fnv1a64:"));
    figures::write_index(&out).unwrap();
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    for set in registry() {
        assert!(html.contains(&format!("id=\"{}\"", set.name)), "{}", set.name);
    }
    assert!(html.contains("Niveau de récursivité : 3"));
}

#[test]
fn attenuation_range_is_measured() {
    // Point light at (0, 0, 10) with C_quad = 0.01: the highest lit point seen is the cube's top
    // (z = 4, d = 6): A = 1 / (1 + 0.36) = 0.7353; the far floor drives the minimum to ~0.
    let set = registry().into_iter().find(|s| s.name == "attenuation").unwrap();
    let quad = (set.figures)().pop().unwrap();
    let r = render_figure(quad, 0.2);
    let max = r.manifest["facts"]["attenuation_max"].as_f64().unwrap();
    assert!((max - 1.0 / 1.36).abs() < 1e-3, "{max}");
    assert!(r.manifest["facts"]["attenuation_min"].as_f64().unwrap() < 0.01);
}

#[test]
fn figures_command_rejects_bad_requests() {
    let o = lumiere(&["figures", "no-such-set", "--out", "/tmp/lumiere-nothing"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("the sets are: lighting"));
    let o = lumiere(&["figures", "--scale", "0", "--out", "/tmp/lumiere-nothing"]);
    assert_eq!(o.status.code(), Some(2));
    let o = lumiere(&["figures", "--list"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stdout).contains("01-top-depth-01.png  Récursivité : 1 (vue de haut)"));
}

/// Runs `lumiere figures` on `sets` at scale 0.05 into `out`, quietly; asserts it succeeds.
fn generate_sets(out: &std::path::Path, sets: &[&str]) {
    let mut args = vec!["figures", "--scale", "0.05", "--out", out.to_str().unwrap(), "--quiet"];
    args.extend_from_slice(sets);
    let o = lumiere(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `<dir>/<set>/manifest.json`, parsed.
fn set_manifest(dir: &std::path::Path, set: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join(set).join("manifest.json")).unwrap()).unwrap()
}

/// A manifest entry's `one_pass_with` list.
fn one_pass_with(image: &serde_json::Value) -> Vec<&str> {
    image["one_pass_with"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect()
}

#[test]
fn a_run_renders_the_lightings_of_several_sets_in_one_pass() {
    // The reference scene under lighting's, directional's and spotlight's lights: one pass
    // in a run over the three sets, each image the bytes of its set rendered alone.
    let (run, alone) = (temp_dir("figures-lightings"), temp_dir("figures-lightings-alone"));
    let sets = ["lighting", "directional", "spotlight"];
    generate_sets(&run, &sets);
    for set in sets {
        generate_sets(&alone, &[set]);
    }
    for set in sets {
        for image in set_manifest(&alone, set)["images"].as_array().unwrap() {
            let file = image["file"].as_str().unwrap();
            let read = |dir: &std::path::Path| std::fs::read(dir.join(set).join(file)).unwrap();
            assert!(read(&run) == read(&alone), "{set}/{file}");
        }
    }
    // Directional's first figure is lighting's third (same scene): a copy. The other eight
    // distinct scenes were one pass, and each manifest names the others with their set.
    let directional = set_manifest(&run, "directional");
    assert_eq!(
        directional["images"][0]["same_image_as"],
        "lighting/03-ambient-directional.png"
    );
    assert_eq!(
        one_pass_with(&directional["images"][1]),
        [
            "lighting/01-ambient.png",
            "lighting/02-directional.png",
            "lighting/03-ambient-directional.png",
            "directional/03-d-0-1--1.png",
            "directional/04-d--1-1--1.png",
            "spotlight/01-theta-70.png",
            "spotlight/02-theta-120.png"
        ]
    );
    // Rendered alone, a set's family names its own files only.
    let alone_with = &set_manifest(&alone, "directional")["images"][1]["one_pass_with"];
    assert_eq!(
        alone_with,
        &serde_json::json!(["01-d-1-1--1.png", "03-d-0-1--1.png", "04-d--1-1--1.png"])
    );
}

#[test]
fn a_run_renders_a_scene_two_sets_share_once_and_families_in_one_pass() {
    // Light-shapes' sphere is soft-shadows' N = 100: in a run over both it is copied, with
    // the same bytes as when light-shapes is rendered alone.
    let (both, alone) = (temp_dir("figures-both"), temp_dir("figures-alone"));
    generate_sets(&both, &["soft-shadows", "light-shapes"]);
    generate_sets(&alone, &["light-shapes"]);
    let sphere = |dir: &std::path::Path| std::fs::read(dir.join("light-shapes/01-sphere.png")).unwrap();
    assert_eq!(sphere(&both), sphere(&alone));
    let shared = &set_manifest(&both, "light-shapes")["images"][0];
    assert_eq!(shared["same_image_as"], "soft-shadows/06-points-100.png");
    assert_eq!(shared["render_seconds"], 0.0);
    assert!(
        set_manifest(&alone, "light-shapes")["images"][0]
            .get("same_image_as")
            .is_none()
    );
    // The soft-shadows N = 1 ... 1000 figures were one pass: each lists the others.
    let soft = set_manifest(&both, "soft-shadows");
    let last = &soft["images"][7];
    assert_eq!(last["file"], "08-points-1000.png");
    assert_eq!(
        one_pass_with(last),
        [
            "02-soft-200.png",
            "03-points-1.png",
            "04-points-5.png",
            "05-points-25.png",
            "06-points-100.png"
        ]
    );
    // The hard-shadow figure (a point light) is its own render.
    assert!(soft["images"][0].get("one_pass_with").is_none());
}
