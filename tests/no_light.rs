//! The `no_light` shading model (SIMRenderer's `reflexion_algorithm no_light`): every hit
//! shows its diffuse colour `k_d S`, no light shades it and no shadow ray is cast, and
//! reflected rays are traced as usual.

use crate::common::{lumiere, temp_dir, write_in};
use glam::DVec3;
use lumiere::render::{render, render_reference};
use lumiere::scene::{self, ShadingModel};
use lumiere::world::World;
use std::path::Path;

/// An orange sphere (`k_d` 0.8, `S` (1, 0.5, 0.25)) on a half-mirror floor (white, `k_d`
/// 0.5, `k_r` 0.5), under a point light and an ambient light that `no_light` ignores.
const SCENE: &str = r#"
[image]
width = 40
height = 30
samples_per_pixel = 1

[camera]
position = [0, -6, 2]
look_at = [0, 0, 0.5]
up = [0, 0, 1]
vfov = 50

[render]
depth = 2
ambient = false
diffuse = false
specular = "none"
no_light = true

[conventions]
sample_position = "center"

[materials.orange]
color = [1.0, 0.5, 0.25]
kd = 0.8

[materials.floor]
color = [1, 1, 1]
kd = 0.5
kr = 0.5

[[shapes]]
type = "sphere"
center = [0, 0, 1]
radius = 1
material = "orange"

[[shapes]]
type = "plane"
point = [0, 0, 0]
normal = [0, 0, 1]
material = "floor"

[[lights]]
type = "ambient"
color = [0.3, 0.3, 0.3]

[[lights]]
type = "point"
position = [2, -4, 6]
color = [1, 1, 1]
"#;

#[test]
fn every_hit_shows_its_diffuse_colour_and_its_reflections() {
    let dir = temp_dir("no-light");
    let scene = scene::load(Path::new(&write_in(&dir, "flat.toml", SCENE))).unwrap();
    assert_eq!(scene.settings.shading, ShadingModel::NO_LIGHT);
    let world = World::new(&scene);
    let (film, stats) = render(&world, &|| {});
    let (reference, _) = render_reference(&world, &|| {});
    // k_d S of the sphere and of the floor; the floor adds k_r times what its reflected ray
    // sees: the sphere, or the black background.
    let sphere = DVec3::new(0.8, 0.4, 0.2);
    let floor = DVec3::splat(0.5);
    let floor_reflecting_sphere = DVec3::new(0.9, 0.7, 0.6);
    let mut seen = [0usize; 4];
    for (p, r) in film.pixels.iter().zip(&reference.pixels) {
        assert_eq!(p.to_array().map(f64::to_bits), r.to_array().map(f64::to_bits));
        let kind = [DVec3::ZERO, sphere, floor, floor_reflecting_sphere]
            .iter()
            .position(|c| (*p - *c).abs().max_element() < 1e-12)
            .unwrap_or_else(|| panic!("a pixel of {p}: neither background, sphere nor floor"));
        seen[kind] += 1;
    }
    // Each kind covers some of the 1200 pixels (the background above the horizon).
    assert!(seen.iter().all(|&n| n > 20), "{seen:?}");
    assert_eq!(stats.counts.shadow, 0);
    assert!(stats.counts.reflection > 0);
}

#[test]
fn simrenderer_no_light_reads_writes_and_renders() {
    let dir = temp_dir("no-light-simrenderer");
    let text = "camera\nposition 0 -6 2\nlook_at 0 0 0.5\nup 0 0 1\nend\n\
                viewport\nwidth 40\nheight 30\nend\n\
                raytracer\nreflexion_algorithm no_light\npixel_coordinate center\nend\n\
                material\nname orange\ncolor 1 0.5 0.25\nkd 0.8\nend\n\
                primitive\nmaterial_name orange\nsphere\nposition 0 0 1\nray 1\nend\nend\n\
                point_light\nposition 2 -4 6\nend\n";
    let lab = write_in(&dir, "lab.txt", text);
    let scene = scene::load(Path::new(&lab)).unwrap();
    assert_eq!(scene.settings.shading, ShadingModel::NO_LIGHT);
    // The middle of the sphere shows k_d S: (0.8, 0.4, 0.2) quantised, 204 102 51.
    let out = dir.join("lab.png");
    let o = lumiere(&["render", &lab, "-o", out.to_str().unwrap(), "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let image = image::open(&out).unwrap().to_rgb8();
    assert_eq!(image.get_pixel(20, 15).0, [204, 102, 51]);
    // To a lumiere scene and back: `no_light = true`, then `reflexion_algorithm no_light`.
    let toml = dir.join("lab.toml");
    let o = lumiere(&["convert", &lab, "-o", toml.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let written = std::fs::read_to_string(&toml).unwrap();
    assert!(written.contains("no_light = true\n"), "{written}");
    assert_eq!(scene::load(&toml).unwrap().settings.shading, ShadingModel::NO_LIGHT);
    let back = dir.join("back.txt");
    let o = lumiere(&["convert", toml.to_str().unwrap(), "-o", back.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let back = std::fs::read_to_string(&back).unwrap();
    assert!(back.contains("reflexion_algorithm no_light\n"), "{back}");
}

#[test]
fn probe_names_the_diffuse_colour() {
    let dir = temp_dir("no-light-probe");
    let path = write_in(&dir, "flat.toml", SCENE);
    let o = lumiere(&["probe", &path, "--pixel", "20,12"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("no light: diffuse colour k_d S (0.800000, 0.400000, 0.200000)\n"),
        "{text}"
    );
    assert!(text.contains("8-bit (204, 102, 51)\n"), "{text}");
    assert!(text.contains("rays: camera 1, shadow 0,"), "{text}");
}

#[test]
fn no_light_with_a_local_term_on_is_refused() {
    let dir = temp_dir("no-light-refused");
    let text = SCENE.replace("diffuse = false\n", "");
    let path = write_in(&dir, "both.toml", &text);
    let e = scene::load(Path::new(&path)).unwrap_err().to_string();
    assert!(
        e.ends_with(
            "render.no_light: shows the diffuse colour in place of every local term: set ambient = false, diffuse = false and specular = \"none\" with it"
        ),
        "{e}"
    );
    assert!(e.contains("both.toml:"), "{e}");
}
