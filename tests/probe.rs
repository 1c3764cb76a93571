//! `lumiere probe`: snapshots of the ray trees of pixels chosen for each feature (checked
//! by hand before the snapshot is taken), the probe agreeing bit for bit with the
//! renderer, the JSON output and the errors.

use crate::common::*;
use glam::DVec3;
use lumiere::film::{Film, quantize};
use lumiere::probe::{PixelProbe, RayNode, format_text, probe};
use lumiere::render::render_sample;
use lumiere::scene::{self, Scene};
use lumiere::trace::{NoRecord, Tracer};
use lumiere::world::World;

const YELLOW: DVec3 = DVec3::new(1.0, 0.9, 0.1);
const MAUVE: DVec3 = DVec3::new(0.6, 0.3, 0.8);

/// A spotlight 5 above a floor, pointing down, opening 60 degrees (cone radius 5 tan 30 =
/// 2.887 on the floor), C_theta from 1 on the axis down to c_min = 0.2 at the edge.
const SPOT: &str = r#"[image]
width = 160
height = 120
samples_per_pixel = 1
seed = 7

[camera]
position = [0, -10, 10]
look_at = [0, 0, 0]
up = [0, 0, 1]
vfov = 40

[materials.grey]
color = [0.8, 0.8, 0.8]

[[shapes]]
type = "plane"
name = "floor"
point = [0, 0, 0]
normal = [0, 0, 1]
material = "grey"

[[lights]]
type = "ambient"
color = [0.2, 0.2, 0.2]

[[lights]]
type = "spot"
position = [0, 0, 5]
direction = [0, 0, -1]
angle = 60
c_min = 0.2
c_max = 1
"#;

fn spot_scene() -> Scene {
    scene::parse(SPOT, "spot.toml").unwrap()
}

/// `scene` at 160 x 120, one sample per pixel, with `depth` if given.
fn small(name: &str, depth: Option<u32>) -> Scene {
    let mut s = if name == "spot" { spot_scene() } else { scene(name) };
    s.settings.width = 160;
    s.settings.height = 120;
    s.settings.samples_per_pixel = 1;
    if let Some(d) = depth {
        s.settings.depth = d;
    }
    s
}

/// Probes the pixel and snapshots its text tree as `probe_NAME`.
fn snap(name: &str, scene: &Scene, x: u32, y: u32) -> PixelProbe {
    let p = probe(scene, x, y, None).unwrap();
    snapshot_settings().bind(|| insta::assert_snapshot!(format!("probe_{name}"), format_text(&p)));
    p
}

fn v(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

fn camera_ray(p: &PixelProbe) -> &RayNode {
    &p.samples[0].ray
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

#[test]
fn lit_floor() {
    let p = snap("reference_lit_floor", &small("reference.toml", None), 64, 45);
    let r = camera_ray(&p);
    assert_eq!(r.hit.as_ref().unwrap().name, "floor");
    let light = &r.lights[0];
    assert_eq!((light.index, light.kind, light.status), (1, "directional", "lit"));
    let share = light.share.as_ref().unwrap();
    let shadow = share.shadow_ray.as_ref().unwrap();
    assert_eq!(shadow.result, "open");
    assert_eq!(shadow.t_max, None); // directional: tested to infinity
    assert_eq!(share.filter, [1.0; 3]);
    // N = z, L = (-1, -1, 1)/sqrt 3: N.L = 0.577350; ambient k_a L_a S = 0.2 x 0.85 = 0.17;
    // diffuse k_d S N.L = 0.8 x 0.85 x 0.577350 = 0.392598.
    assert!((light.n_dot_l.unwrap() - 1.0 / 3f64.sqrt()).abs() < 1e-15);
    assert!(close(v(r.ambient.unwrap()), DVec3::splat(0.17), 1e-15));
    assert!(close(v(share.diffuse), DVec3::splat(0.8 * 0.85 / 3f64.sqrt()), 1e-15));
    // The floor neither reflects nor transmits: the radiance is the local colour.
    assert!(r.children.is_empty());
    assert_eq!(r.radiance, r.local.unwrap());
}

#[test]
fn ambient_only_where_the_cone_faces_away() {
    // The cone's side turned to +x: N.L < 0, no share and no shadow ray; only the ambient
    // 0.2 x (0.9, 0.1, 0.1) = (0.18, 0.02, 0.02), 8-bit (46, 5, 5).
    let p = snap("reference_ambient_only", &small("reference.toml", None), 45, 83);
    let r = camera_ray(&p);
    assert_eq!(r.hit.as_ref().unwrap().name, "cone");
    assert_eq!(r.lights[0].status, "facing_away");
    assert!(r.lights[0].n_dot_l.unwrap() < 0.0);
    assert!(r.lights[0].share.is_none());
    assert_eq!(r.local, r.ambient);
    assert!(close(v(r.radiance), DVec3::new(0.18, 0.02, 0.02), 1e-15));
    assert_eq!(p.color.rgb8, [46, 5, 5]);
    assert_eq!(p.counts.shadow, 0);
}

#[test]
fn opaque_shadow_of_the_cone() {
    // Floor near (-1.5, -1.5, 0): its shadow ray passes through the red cone. Only the
    // ambient 0.17 is left: 8-bit 43.
    let p = snap("reference_opaque_shadow", &small("reference.toml", None), 60, 75);
    let r = camera_ray(&p);
    assert_eq!(r.hit.as_ref().unwrap().name, "floor");
    let share = r.lights[0].share.as_ref().unwrap();
    assert_eq!(share.shadow_ray.as_ref().unwrap().result, "blocked");
    assert_eq!(share.filter, [0.0; 3]);
    assert_eq!(share.diffuse, [0.0; 3]);
    assert_eq!(share.specular, [0.0; 3]);
    assert_eq!(p.color.rgb8, [43, 43, 43]);
}

#[test]
fn shadow_filtered_by_the_yellow_sphere() {
    // The pixel sees the floor near (4, -2, 0) (tests/shadows.rs): filter S_yellow exactly.
    let p = snap("reference_yellow_shadow", &small("reference.toml", None), 134, 79);
    let share = camera_ray(&p).lights[0].share.clone().unwrap();
    let shadow = share.shadow_ray.unwrap();
    assert_eq!(shadow.result, "filtered");
    assert_eq!(shadow.filtered_by, ["yellow sphere"]);
    assert_eq!(v(share.filter), YELLOW);
}

#[test]
fn shadow_filtered_by_both_spheres() {
    // Near (4.5, -1.5, 0): filter S_yellow S_mauve = (0.6, 0.27, 0.08), each sphere once.
    let p = snap("reference_double_shadow", &small("reference.toml", None), 137, 75);
    let share = camera_ray(&p).lights[0].share.clone().unwrap();
    assert_eq!(share.shadow_ray.unwrap().filtered_by, ["yellow sphere", "mauve sphere"]);
    assert_eq!(v(share.filter), YELLOW * MAUVE);
}

/// `C_theta` by hand for the spot of [`SPOT`] at floor point `p`: `o.d = 5 / |p - r_lum|`,
/// `t = (o.d - 1) / (cos 30 - 1)`, `C = (1 - t) 1 + t 0.2`, or 0 when `o.d < cos 30`.
fn spot_by_hand(p: DVec3) -> f64 {
    let od = 5.0 / (p - DVec3::new(0.0, 0.0, 5.0)).length();
    let cos_half = 30f64.to_radians().cos();
    if od < cos_half {
        return 0.0;
    }
    let t = (od - 1.0) / (cos_half - 1.0);
    (1.0 - t) + t * 0.2
}

#[test]
fn spot_center_edge_and_outside() {
    let s = small("spot", None);
    // Center: on the axis, C_theta close to 1.
    let center = probe(&s, 80, 60, None).unwrap();
    let share = camera_ray(&center).lights[0].share.clone().unwrap();
    assert!(share.spot > 0.99, "{}", share.spot);
    // Near the edge of the cone (x = 2.8 of 2.887): C_theta just above c_min = 0.2.
    let edge = snap("spot_edge", &s, 113, 60);
    let r = camera_ray(&edge);
    let point = v(r.hit.as_ref().unwrap().point);
    let share = r.lights[0].share.clone().unwrap();
    assert!((0.2..0.3).contains(&share.spot), "{}", share.spot);
    assert!((share.spot - spot_by_hand(point)).abs() < 1e-12);
    assert!((share.attenuation - 1.0).abs() == 0.0);
    // Just outside: no light arrives, no share, no shadow ray; only the ambient
    // 0.2 x 0.2 x 0.8 = 0.032.
    let outside = snap("spot_outside", &s, 114, 60);
    let r = camera_ray(&outside);
    assert_eq!(spot_by_hand(v(r.hit.as_ref().unwrap().point)), 0.0);
    assert_eq!((r.lights[0].status, r.lights[0].n_dot_l), ("no_light", None));
    assert!(close(v(r.radiance), DVec3::splat(0.032), 1e-15));
    assert_eq!(outside.counts.shadow, 0);
}

#[test]
fn mirror_depth_3() {
    // Mirror A shows mirror B, which shows the cone: camera, reflection, reflection.
    let p = snap("mirrors_depth_3", &small("mirrors.toml", Some(3)), 98, 48);
    let l1 = camera_ray(&p);
    let l2 = &l1.children[0];
    let l3 = &l2.children[0];
    let names: Vec<&str> = [l1, l2, l3]
        .iter()
        .map(|r| r.hit.as_ref().unwrap().name.as_str())
        .collect();
    assert_eq!(names, ["mirror A", "mirror B", "cone"]);
    assert_eq!([l2.kind, l3.kind], ["reflection", "reflection"]);
    assert_eq!([l1.level, l2.level, l3.level], [1, 2, 3]);
    // Weights: 1, k_r = 0.9, k_r^2 = 0.81.
    assert_eq!([l1.weight, l2.weight, l3.weight], [1.0, 0.9, 0.9 * 0.9]);
    // Depth 3 reached: the cone's ray has no children; each mirror's radiance is its local
    // colour plus k_r times what its reflected ray returned, to the bit.
    assert!(l3.children.is_empty());
    assert_eq!(v(l2.radiance), v(l2.local.unwrap()) + 0.9 * v(l3.radiance));
    assert_eq!(v(l1.radiance), v(l1.local.unwrap()) + 0.9 * v(l2.radiance));
    // Each reflection obeys R = D - 2 (D.N) N.
    for (a, b) in [(l1, l2), (l2, l3)] {
        let d = v(a.direction);
        let h = a.hit.as_ref().unwrap();
        let n = v(h.normal);
        let r = d - 2.0 * d.dot(n) * n;
        assert!(close(v(b.direction), r.normalize(), 1e-12));
    }
}

#[test]
fn prism_refraction() {
    // Into the glass (n = 1.66) and out again onto the red sphere.
    let p = snap("prism_refraction", &small("prism.toml", Some(4)), 76, 46);
    let l1 = camera_ray(&p);
    let inside = l1.children.iter().find(|c| c.kind == "refraction").unwrap();
    let out = inside.children.iter().find(|c| c.kind == "refraction").unwrap();
    assert!(l1.hit.as_ref().unwrap().entering);
    assert!(!inside.hit.as_ref().unwrap().entering);
    assert_eq!(out.hit.as_ref().unwrap().name, "sphere");
    // Weights k_t = 0.9 then 0.81.
    assert_eq!([inside.weight, out.weight], [0.9, 0.9 * 0.9]);
    // Snell at both faces: sin(theta_t) = sin(theta_i) n1 / n2, with |N x D| = sin.
    let sin = |d: [f64; 3], n: [f64; 3]| v(d).cross(v(n)).length();
    let n_in = l1.hit.as_ref().unwrap().normal;
    assert!((sin(inside.direction, n_in) - sin(l1.direction, n_in) / 1.66).abs() < 1e-12);
    let n_out = inside.hit.as_ref().unwrap().normal;
    assert!((sin(out.direction, n_out) - sin(inside.direction, n_out) * 1.66).abs() < 1e-12);
}

#[test]
fn prism_total_internal_reflection() {
    let p = snap("prism_total_internal_reflection", &small("prism.toml", Some(4)), 85, 40);
    let inside = camera_ray(&p).children.iter().find(|c| c.kind == "refraction").unwrap();
    let tir = &inside.children[0];
    assert!(tir.total_internal_reflection);
    assert!(!tir.hit.as_ref().unwrap().entering);
    // Beyond the critical angle asin(1 / 1.66) = 37.04 degrees: sin(theta_i) > 1 / 1.66.
    let sin_i = v(tir.direction).cross(v(tir.hit.as_ref().unwrap().normal)).length();
    assert!(sin_i > 1.0 / 1.66, "{sin_i}");
    // No refracted child; the reflected one carries k_r + k_t = 1.0 of the weight.
    assert!(tir.children.iter().all(|c| c.kind == "reflection"));
    assert_eq!(tir.children[0].weight, tir.weight * (0.1 + 0.9));
    assert_eq!(p.counts.total_internal_reflections, 1);
}

/// Every node of a tree.
fn nodes(r: &RayNode) -> Vec<&RayNode> {
    let mut all = vec![r];
    for c in &r.children {
        all.extend(nodes(c));
    }
    all
}

#[test]
fn adaptive_cutoffs_are_recorded() {
    // At depth 20 the rays bouncing inside the prism lose weight until the most they can
    // add is below 0.25 of a level: the probe lists each skipped ray, as many as counted.
    let p = probe(&small("prism.toml", None), 82, 34, None).unwrap();
    let cutoffs: Vec<_> = nodes(camera_ray(&p)).iter().flat_map(|n| n.cutoffs.clone()).collect();
    assert!(!cutoffs.is_empty());
    assert_eq!(cutoffs.len() as u64, p.counts.adaptive_cutoffs);
    // Each cut-off ray's weight is a product of the glass's k_r = 0.1 and k_t = 0.9 (or
    // k_r + k_t = 1 after total internal reflection): at most 0.9 x 0.1 below the camera ray.
    assert!(cutoffs.iter().all(|c| c.weight <= 0.09 + 1e-15));
}

/// Renders `scene` and checks the probe of every 7th pixel against it: the mean to the bit,
/// the 8-bit value, and each sample (`--sample K`) against `render_sample`.
fn check_agreement(scene: &Scene) {
    let film: Film = render_small(
        scene,
        scene.settings.width,
        scene.settings.height,
        scene.settings.samples_per_pixel,
        2,
    );
    let rgb = film.to_rgb8();
    let world = World::new(scene);
    let mut tracer = Tracer::new(&world);
    let (w, h) = (scene.settings.width, scene.settings.height);
    for y in (0..h).step_by(7) {
        for x in (0..w).step_by(7) {
            let p = probe(scene, x, y, None).unwrap();
            let pixel = film.get(x, y);
            assert_eq!(
                v(p.color.radiance).to_array().map(f64::to_bits),
                pixel.to_array().map(f64::to_bits)
            );
            let i = ((y * w + x) * 3) as usize;
            assert_eq!(p.color.rgb8, [rgb[i], rgb[i + 1], rgb[i + 2]]);
            assert_eq!(p.color.rgb8, pixel.to_array().map(quantize));
            assert_eq!(p.samples.len() as u32, scene.settings.samples_per_pixel);
            for k in 0..scene.settings.samples_per_pixel {
                let alone = probe(scene, x, y, Some(k)).unwrap();
                let rendered = render_sample(&mut tracer, x, y, k, &mut NoRecord);
                assert_eq!(v(alone.color.radiance), rendered, "({x}, {y}) sample {k}");
                assert_eq!(v(p.samples[k as usize].radiance), rendered);
                assert_eq!(alone.samples.len(), 1);
            }
        }
    }
}

#[test]
fn soft_shadow_penumbra() {
    // scenes/soft-shadows.toml with N = 5 fixed points: a floor point behind the cube where
    // 4 of the 5 shadow rays are blocked by the cube and 1 reaches its point.
    let mut s = small("soft-shadows.toml", None);
    let lumiere::light::Light::Area(area) = &mut s.lights[1] else {
        panic!("light 1 of soft-shadows.toml is the area light");
    };
    area.count = 5;
    let p = snap("soft_shadows_penumbra", &s, 75, 72);
    let r = camera_ray(&p);
    assert_eq!(r.hit.as_ref().unwrap().name, "floor");
    assert_eq!(r.lights.len(), 5, "one record per point");
    let results: Vec<&str> = r
        .lights
        .iter()
        .map(|l| l.share.as_ref().unwrap().shadow_ray.as_ref().unwrap().result)
        .collect();
    assert_eq!(results.iter().filter(|&&r| r == "blocked").count(), 4, "{results:?}");
    assert_eq!(results.iter().filter(|&&r| r == "open").count(), 1, "{results:?}");
    // Each point carries L / N = 0.2 before attenuation: incident = 0.2 A.
    let mut sum = DVec3::ZERO;
    for l in &r.lights {
        let share = l.share.as_ref().unwrap();
        assert_eq!((l.index, l.kind), (1, "area"));
        assert_eq!(v(share.incident), DVec3::splat(0.2 * share.attenuation));
        sum += v(share.diffuse) + v(share.specular);
    }
    // Local colour = ambient 0.2 x 0.85 + the one open point's share, summed in point order.
    assert_eq!(v(r.local.unwrap()), v(r.ambient.unwrap()) + sum);
    assert!(close(v(r.ambient.unwrap()), DVec3::splat(0.17), 1e-15));
}

#[test]
fn probe_and_render_agree_bit_for_bit() {
    for (name, depth) in [
        ("reference.toml", None),
        ("mirrors.toml", None),
        ("prism.toml", None),
        ("spot", None),
        ("soft-shadows.toml", None),
    ] {
        let mut s = small(name, depth);
        s.settings.width = 48;
        s.settings.height = 36;
        s.settings.samples_per_pixel = 4;
        check_agreement(&s);
    }
}

#[test]
fn json_output_has_the_documented_fields() {
    let o = lumiere(&[
        "probe",
        repo("scenes/reference.toml").to_str().unwrap(),
        "--pixel",
        "137,75",
        "--width",
        "160",
        "--height",
        "120",
        "--spp",
        "1",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["pixel"], serde_json::json!([137, 75]));
    assert_eq!((j["width"].as_u64(), j["height"].as_u64()), (Some(160), Some(120)));
    assert_eq!(j["samples_per_pixel"], 1);
    let sample = &j["samples"][0];
    assert_eq!(sample["index"], 0);
    assert_eq!(sample["position"].as_array().unwrap().len(), 2);
    let ray = &sample["ray"];
    for field in [
        "kind",
        "level",
        "weight",
        "origin",
        "direction",
        "hit",
        "ambient",
        "lights",
        "local",
    ] {
        assert!(ray.get(field).is_some(), "missing {field}");
    }
    for field in ["total_internal_reflection", "children", "cutoffs", "radiance"] {
        assert!(ray.get(field).is_some(), "missing {field}");
    }
    assert_eq!(ray["kind"], "camera");
    assert_eq!(ray["hit"]["name"], "floor");
    assert_eq!(ray["hit"]["entering"], true);
    let light = &ray["lights"][0];
    assert_eq!(
        (light["index"].as_u64(), light["kind"].as_str()),
        (Some(1), Some("directional"))
    );
    let share = &light["share"];
    for field in ["attenuation", "spot", "incident", "filter", "diffuse", "specular"] {
        assert!(share.get(field).is_some(), "missing {field}");
    }
    assert_eq!(share["distance"], serde_json::Value::Null);
    assert_eq!(share["shadow_ray"]["result"], "filtered");
    assert_eq!(
        share["shadow_ray"]["filtered_by"],
        serde_json::json!(["yellow sphere", "mauve sphere"])
    );
    // The same numbers as the library probe.
    let p = probe(&small("reference.toml", None), 137, 75, None).unwrap();
    assert_eq!(j["color"]["of"], "mean");
    assert_eq!(j["color"]["rgb8"], serde_json::json!(p.color.rgb8));
    for c in 0..3 {
        let x = j["color"]["radiance"][c].as_f64().unwrap();
        assert!((x - p.color.radiance[c]).abs() <= 1e-15, "{x}");
    }
    assert_eq!(j["counts"]["camera"], 1);
    assert_eq!(j["counts"]["shadow"], 1);
}

#[test]
fn text_output_names_the_scene() {
    let scene_path = repo("scenes/reference.toml");
    let o = lumiere(&["probe", scene_path.to_str().unwrap(), "--pixel", "0,0", "--spp", "1"]);
    assert_eq!(o.status.code(), Some(0));
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.starts_with(&format!("scene {}\npixel (0, 0) of 800 x 600", scene_path.display())));
    assert!(text.contains("  8-bit ("));
}

#[test]
fn bad_pixel_or_sample_is_bad_input() {
    let scene_path = repo("scenes/reference.toml");
    let scene_path = scene_path.to_str().unwrap();
    let run = |args: &[&str]| {
        let mut all = vec!["probe", scene_path, "--width", "160", "--height", "120"];
        all.extend_from_slice(args);
        let o = lumiere(&all);
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(!err.contains("panicked"), "{err}");
        (o.status.code(), err)
    };
    let (code, err) = run(&["--pixel", "160,0"]);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("outside the 160 x 120 image (x in [0, 159], y in [0, 119])"),
        "{err}"
    );
    let (code, _) = run(&["--pixel", "0,120"]);
    assert_eq!(code, Some(2));
    let (code, err) = run(&["--pixel", "3,4", "--spp", "4", "--sample", "4"]);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("--sample 4: the pixel has 4 samples (K in [0, 3])"),
        "{err}"
    );
    let (code, _) = run(&["--pixel", "3"]);
    assert_eq!(code, Some(2));
}
