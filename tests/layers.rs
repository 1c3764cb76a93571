//! `lumiere render --layers`: each layer of a one-pixel scene computed by hand; the colour
//! layers summing to the pixel's radiance on the reference and prism scenes; the EXR read
//! back channel by channel; the folder form; the same values for any thread count; bad
//! paths refused with exit code 2.

use crate::common::*;
use glam::DVec3;
use lumiere::compare::pfm::decode_pfm;
use lumiere::film::quantize;
use lumiere::layers::{Layers, pixel_layers, render_layers};
use lumiere::render::render;
use lumiere::scene::{self, Scene};
use lumiere::trace::Tracer;
use lumiere::world::World;

/// One pixel looking straight down at a floor 10 below, sampled at its centre: ambient
/// `(0.5, 0.5, 0.5)`, a white directional light from `L = (1, 0, 1) / sqrt 2` whose shadow
/// ray passes through the centre of a transparent sphere of colour `(0.5, 1, 0.25)`, and a
/// background `(0.1, 0.2, 0.3)` seen in the floor's mirror (`k_r = 0.25`).
const TINY: &str = r#"[image]
width = 1
height = 1
samples_per_pixel = 1
seed = 1

[camera]
position = [0, 0, 10]
look_at = [0, 0, 0]
up = [0, 1, 0]
vfov = 10

[render]
depth = 2
background = [0.1, 0.2, 0.3]

[conventions]
sample_position = "center"

[materials.floor]
color = [0.8, 0.6, 0.4]
ka = 0.2
kd = 0.8
ks = 0.5
shininess = 20
kr = 0.25

[materials.filter]
color = [0.5, 1.0, 0.25]
kt = 0.5

[[shapes]]
type = "plane"
name = "floor"
point = [0, 0, 0]
normal = [0, 0, 1]
material = "floor"

[[shapes]]
type = "sphere"
name = "filter"
center = [3, 0, 3]
radius = 1
material = "filter"

[[lights]]
type = "ambient"
color = [0.5, 0.5, 0.5]

[[lights]]
type = "directional"
direction = [-1, 0, -1]
color = [1, 1, 1]
"#;

fn close(a: DVec3, b: DVec3, what: &str) {
    assert!((a - b).abs().max_element() < 1e-14, "{what}: {a} against {b}");
}

#[test]
fn one_pixel_layers_by_hand() {
    let scene = scene::parse(TINY, "tiny.toml").unwrap();
    let world = World::new(&scene);
    let p = pixel_layers(&mut Tracer::new(&world), 0, 0);
    // L_a k_a S = 0.5 * 0.2 * (0.8, 0.6, 0.4).
    close(p.ambient, DVec3::new(0.08, 0.06, 0.04), "ambient");
    // L filter k_d S N.L = (0.5, 1, 0.25) * 0.8 * (0.8, 0.6, 0.4) / sqrt 2.
    let filter = DVec3::new(0.5, 1.0, 0.25);
    let s2 = std::f64::consts::FRAC_1_SQRT_2;
    close(p.diffuse, filter * 0.8 * DVec3::new(0.8, 0.6, 0.4) * s2, "diffuse");
    close(
        p.diffuse,
        DVec3::new(
            0.226_274_169_979_695_2,
            0.339_411_254_969_542_8,
            0.056_568_542_494_923_8,
        ),
        "diffuse",
    );
    // Blinn: H halves L and E = z, N.H = cos 22.5 deg = 0.92387953, ^20 = 0.20526123;
    // L filter k_s spec = (0.5, 1, 0.25) * 0.5 * 0.20526123 (plastic: white highlight).
    close(
        p.specular,
        DVec3::new(
            0.051_315_306_482_873_67,
            0.102_630_612_965_747_34,
            0.025_657_653_241_436_835,
        ),
        "specular",
    );
    // k_r times the background seen straight up.
    close(p.reflected, DVec3::new(0.025, 0.05, 0.075), "reflected");
    assert_eq!(p.transmitted, DVec3::ZERO);
    assert_eq!(p.background, DVec3::ZERO);
    // All of the light arrives through the sphere's filter.
    close(
        p.filtered_diffuse + p.filtered_specular,
        p.diffuse + p.specular,
        "filtered",
    );
    assert_eq!(p.shadow_filters, vec![DVec3::ZERO, filter]);
    assert_eq!(p.object, 0);
    assert_eq!(p.normal, DVec3::Z);
    assert_eq!(p.depth, 10.0);
    close(p.sum(), p.radiance, "sum");
}

/// `scene` at `w x h` with its own samples and seed.
fn small(name: &str, w: u32, h: u32) -> Scene {
    let mut s = scene(name);
    s.settings.width = w;
    s.settings.height = h;
    s
}

/// `lumiere render scenes/NAME` at `width x height` with `extra` arguments; it must succeed.
fn render_small_cli(name: &str, (width, height): (u32, u32), extra: &[&str]) {
    let scene = repo(&format!("scenes/{name}"));
    let (width, height) = (width.to_string(), height.to_string());
    let args = [
        "render",
        scene.to_str().unwrap(),
        "--width",
        &width,
        "--height",
        &height,
    ];
    let o = lumiere(&[&args[..], extra].concat());
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn terms_sum_to_the_rendered_radiance() {
    for name in [
        "reference.toml",
        "prism.toml",
        "mirrors.toml",
        "figures/caustics/04-ball-lens-1e4.toml",
        "figures/optique/02-grating.toml",
    ] {
        let scene = small(name, 80, 60);
        let world = World::new(&scene);
        let layers = render_layers(&world);
        let (film, _) = render(&world, &|| {});
        let mut worst = 0.0f64;
        let mut terms = [0usize; 5];
        for (p, &radiance) in layers.pixels.iter().zip(&film.pixels) {
            // The radiance is the renderer's, to the bit.
            assert_eq!(p.radiance, radiance, "{name}");
            worst = worst.max((p.sum() - radiance).abs().max_element() / radiance.max_element().max(1.0));
            terms[0] += usize::from(p.reflected != DVec3::ZERO);
            terms[1] += usize::from(p.transmitted != DVec3::ZERO);
            terms[2] += usize::from(p.filtered_diffuse != DVec3::ZERO);
            terms[3] += usize::from(p.caustic != DVec3::ZERO);
            terms[4] += usize::from(p.diffuse != DVec3::ZERO);
        }
        assert!(
            worst < 1e-12,
            "{name}: the layers' sum is {worst} away from the radiance"
        );
        // Each scene exercises the terms it is about.
        match name {
            "reference.toml" => assert!(terms[1] > 100 && terms[2] > 100, "{terms:?}"),
            "prism.toml" => assert!(terms[0] > 100 && terms[1] > 100, "{terms:?}"),
            "mirrors.toml" => assert!(terms[0] > 1000, "{terms:?}"),
            // The ball lens's photons land on the floor behind it.
            "figures/caustics/04-ball-lens-1e4.toml" => assert!(terms[3] > 50, "{terms:?}"),
            // The grating's screen is lit by the aperture light alone: its share is diffuse.
            _ => assert!(terms[4] > 1000, "{terms:?}"),
        }
    }
}

#[test]
fn same_layers_for_any_thread_count() {
    let scene = small("reference.toml", 40, 30);
    let world = World::new(&scene);
    let run = |threads| -> Layers {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| render_layers(&world))
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
    let dir = temp_dir("layers-threads");
    for t in ["1", "2"] {
        let out = dir.join(format!("t{t}.exr"));
        render_small_cli(
            "reference.toml",
            (40, 30),
            &["--threads", t, "--layers", out.to_str().unwrap()],
        );
    }
    assert_eq!(
        std::fs::read(dir.join("t1.exr")).unwrap(),
        std::fs::read(dir.join("t2.exr")).unwrap()
    );
}

#[test]
fn exr_reads_back_channel_by_channel() {
    let dir = temp_dir("layers-exr");
    let out = dir.join("layers.exr");
    let png = dir.join("image.png");
    render_small_cli(
        "reference.toml",
        (40, 30),
        &["-o", png.to_str().unwrap(), "--layers", out.to_str().unwrap()],
    );
    let scene = small("reference.toml", 40, 30);
    let layers = render_layers(&World::new(&scene));
    let planes = layers.planes(&scene.lights);
    let image = exr::prelude::read_all_flat_layers_from_file(&out).unwrap();
    let channels = &image.layer_data[0].channel_data.list;
    let mut expected = Vec::new();
    for plane in &planes {
        let n = plane.channels.len();
        for (c, channel) in plane.channels.iter().enumerate() {
            let values: Vec<f32> = plane.values.iter().skip(c).step_by(n).map(|&v| v as f32).collect();
            expected.push((format!("{}.{channel}", plane.name), values));
        }
    }
    // 9 colour layers, one shadow filter (the directional light), object, normal, depth.
    assert_eq!(expected.len(), 9 * 3 + 3 + 1 + 3 + 1);
    assert_eq!(channels.len(), expected.len());
    for (name, values) in &expected {
        let channel = channels
            .iter()
            .find(|c| c.name.to_string() == *name)
            .unwrap_or_else(|| panic!("no channel {name}"));
        let read: Vec<f32> = channel.sample_data.values_as_f32().collect();
        assert_eq!(&read, values, "{name}");
    }
    // The radiance channels are the PNG's pixels before quantisation.
    let rgb = image::open(&png).unwrap().to_rgb8().into_raw();
    let radiance: Vec<u8> = layers
        .pixels
        .iter()
        .flat_map(|p| p.radiance.to_array().map(quantize))
        .collect();
    assert_eq!(rgb, radiance);
}

#[test]
fn folder_form_writes_a_png_per_layer_and_pfm_floats() {
    let dir = temp_dir("layers-folder");
    let out = format!("{}/layers/", dir.display());
    render_small_cli("prism.toml", (32, 24), &["--layers", &out]);
    let scene = small("prism.toml", 32, 24);
    let layers = render_layers(&World::new(&scene));
    let folder = dir.join("layers");
    let mut names: Vec<String> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    for layer in ["ambient", "diffuse", "specular", "reflected", "transmitted", "radiance"] {
        assert!(names.contains(&format!("{layer}.png")), "{names:?}");
        assert!(names.contains(&format!("{layer}.pfm")), "{names:?}");
    }
    for extra in ["object.png", "normal.png", "depth.png", "shadow_filter_light1.png"] {
        assert!(names.contains(&extra.to_string()), "{names:?}");
    }
    let transmitted = image::open(folder.join("transmitted.png"))
        .unwrap()
        .to_rgb8()
        .into_raw();
    let expected: Vec<u8> = layers
        .pixels
        .iter()
        .flat_map(|p| p.transmitted.to_array().map(quantize))
        .collect();
    assert_eq!(transmitted, expected);
    let pfm = decode_pfm(&std::fs::read(folder.join("reflected.pfm")).unwrap()).unwrap();
    let floats: Vec<f32> = layers
        .pixels
        .iter()
        .flat_map(|p| p.reflected.to_array().map(|c| c as f32))
        .collect();
    assert_eq!(pfm.rgb, floats);
    // The object layer: level index + 1, 0 where the camera ray sees the background.
    let object = image::open(folder.join("object.png")).unwrap().to_rgb8().into_raw();
    for (p, level) in layers.pixels.iter().zip(object.chunks(3)) {
        assert_eq!(level[0] as i64, p.object + 1);
    }
}

#[test]
fn bad_layer_paths_are_refused() {
    let dir = temp_dir("layers-bad");
    let file = dir.join("file.txt");
    std::fs::write(&file, "x").unwrap();
    let cases = [
        (
            dir.join("layers.png").display().to_string(),
            "--layers: must end in .exr",
        ),
        (format!("{}/missing/deeper/", dir.display()), "does not exist"),
        (format!("{}/", file.display()), "is a file, not a folder"),
        (dir.join("missing/out.exr").display().to_string(), "does not exist"),
    ];
    for (path, message) in cases {
        let o = lumiere(&[
            "render",
            repo("scenes/reference.toml").to_str().unwrap(),
            "--layers",
            &path,
        ]);
        assert_eq!(o.status.code(), Some(2), "{path}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(message), "{path}: {err}");
    }
    // Nothing was written.
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
}

/// An image `-o` that the layers would write over (their EXR file, or a layer's file in
/// their folder) is refused before rendering, and nothing is written.
#[test]
fn an_image_the_layers_would_replace_is_refused() {
    let dir = temp_dir("layers-clash");
    let scene = repo("scenes/reference.toml");
    let d = dir.display();
    let cases = [
        (
            format!("{d}/both.exr"),
            format!("{d}/both.exr"),
            format!("{d}/both.exr"),
        ),
        (
            format!("{d}/./both.exr"),
            format!("{d}/both.exr"),
            format!("{d}/both.exr"),
        ),
        (format!("{d}/radiance.png"), format!("{d}/"), d.to_string()),
        (format!("{d}/diffuse.pfm"), d.to_string(), d.to_string()),
        (format!("{d}/shadow_filter_light1.png"), format!("{d}/"), d.to_string()),
    ];
    for (image, layers, shown) in cases {
        let o = lumiere(&["render", scene.to_str().unwrap(), "-o", &image, "--layers", &layers]);
        assert_eq!(o.status.code(), Some(2), "{image}");
        assert_eq!(
            String::from_utf8_lossy(&o.stderr),
            format!(
                "lumiere: error: {image}: -o names a file --layers {shown} writes: the layers would replace the image; give the image another name\n"
            )
        );
    }
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    // An image beside the layers' files, of a name they do not use, is written with them.
    let image = format!("{d}/image.png");
    render_small_cli("reference.toml", (8, 6), &["-o", &image, "--layers", &format!("{d}/")]);
    assert!(dir.join("image.png").is_file() && dir.join("radiance.png").is_file());
}
