//! Texture materials through the whole library: a rendered pixel is its texel (ambient
//! light 1 and an ambient image: `L_a T_a`), in the corner each uv format puts it; the
//! images a scene names are read relative to it, and every error names the file (missing,
//! not an image, too large), in both scene formats; a material without images keeps its
//! bytes in the scene's serialised form.

use crate::common::*;
use glam::DVec3;
use lumiere::scene::{self, parse};
use std::path::Path;

/// A 3 x 3 PNG: top row red, green, black; middle row blue, white, black; bottom row
/// black. SIMRenderer's texel is column `floor(u (3 - 1))`, row `floor(v (3 - 1))`: the
/// last column and row only at exactly 1, so the 2 x 2 colours fill `[0, 1)^2`.
fn write_quad(path: &Path) {
    let (r, g, b, w, k) = ([255u8, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255], [0, 0, 0]);
    let rgb: Vec<u8> = [r, g, k, b, w, k, k, k, k].concat();
    image::save_buffer(path, &rgb, 3, 3, image::ExtendedColorType::Rgb8).unwrap();
}

/// A 2 x 2 rectangle in the plane y = 0 facing a camera on -y (image right = +x, up = +z),
/// textured in its ambient colour, lit by an ambient light of 1 only.
fn quad_scene(uv_format: &str) -> String {
    format!(
        "[image]\nwidth = 40\nheight = 40\nsamples_per_pixel = 1\n\
         [camera]\nposition = [0, -5, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\nvfov = 20\n\
         [materials.quad]\ntexture_ka = \"quad.png\"\nuv_format = \"{uv_format}\"\n\
         [[shapes]]\ntype = \"rectangle\"\ncorner = [-1, 0, -1]\nedge1 = [2, 0, 0]\nedge2 = [0, 0, 2]\nmaterial = \"quad\"\n\
         [[lights]]\ntype = \"ambient\"\ncolor = [1, 1, 1]\n"
    )
}

#[test]
fn a_pixel_is_its_texel_in_the_corner_the_uv_format_says() {
    let dir = temp_dir("texture-quad");
    write_quad(&dir.join("quad.png"));
    for (format, upper_left, lower_right) in [
        // u runs along +x (edge1), v along +z (edge2): the image's upper left is u < 1/2,
        // v > 1/2, the texture's second row (blue, white) under origin_uv_top_left.
        ("origin_uv_top_left", DVec3::Z, DVec3::Y),
        ("origin_uv_bottom_left", DVec3::X, DVec3::ONE),
    ] {
        let file = dir.join(format!("{format}.toml"));
        std::fs::write(&file, quad_scene(format)).unwrap();
        let s = scene::load(&file).unwrap();
        let film = render_small(&s, 40, 40, 1, 2);
        let at = |x: u32, y: u32| film.pixels[(y * 40 + x) as usize];
        assert_eq!(at(10, 10), upper_left, "{format}");
        assert_eq!(at(30, 30), lower_right, "{format}");
        // Every pixel is exactly one of the four texels.
        let texels = [DVec3::X, DVec3::Y, DVec3::Z, DVec3::ONE];
        assert!(film.pixels.iter().all(|p| texels.contains(p)), "{format}");
    }
}

#[test]
fn texture_errors_name_the_file() {
    let dir = temp_dir("texture-errors");
    std::fs::write(dir.join("junk.png"), b"this is not an image").unwrap();
    // A PNM header of 9000 x 9000 texels, more than 2^26: refused from the header.
    std::fs::write(dir.join("huge.ppm"), b"P6\n9000 9000\n255\n").unwrap();
    let head = "[image]\nwidth = 4\nheight = 4\n[camera]\nposition = [0, -5, 0]\nlook_at = [0, 0, 0]\n";
    let error = |material: &str| {
        let file = dir.join("t.toml");
        std::fs::write(&file, format!("{head}[materials.m]\n{material}\n")).unwrap();
        scene::load(&file).unwrap_err().to_string()
    };
    let shown = |name: &str| dir.join(name).display().to_string();
    let t = dir.join("t.toml").display().to_string();
    assert_eq!(
        error("texture_kd = \"missing.png\""),
        format!(
            "{t}:8:14: materials.m.texture_kd: {}: cannot read the texture: No such file or directory (os error 2)",
            shown("missing.png")
        )
    );
    let junk = error("texture_ka = \"junk.png\"");
    assert!(
        junk.starts_with(&format!(
            "{t}:8:14: materials.m.texture_ka: {}: not an image lumiere reads (PNG, JPEG, BMP, TGA, PNM, EXR): ",
            shown("junk.png")
        )),
        "{junk}"
    );
    // A PNG cut short is a damaged PNG, not a file of another format.
    let mut cut = lumiere::film::encode_png(2, 2, &[7; 12]).unwrap();
    cut.truncate(cut.len() - 20);
    std::fs::write(dir.join("cut.png"), cut).unwrap();
    assert_eq!(
        error("texture_kd = \"cut.png\""),
        format!(
            "{t}:8:14: materials.m.texture_kd: {}: cannot decode the PNG texture: unexpected end of file",
            shown("cut.png")
        )
    );
    assert_eq!(
        error("texture_ks = \"huge.ppm\""),
        format!(
            "{t}:8:14: materials.m.texture_ks: {}: the texture is 9000 x 9000: it must hold between 1 and 67108864 texels",
            shown("huge.ppm")
        )
    );
    assert_eq!(
        error("uv_format = \"origin_uv_top_right\""),
        format!(
            "{t}:8:13: materials.m.uv_format: must be \"origin_uv_top_left\" or \"origin_uv_bottom_left\", got \"origin_uv_top_right\""
        )
    );
    assert_eq!(
        error("uv_format = \"origin_uv_top_left\""),
        format!(
            "{t}:8:13: materials.m.uv_format: applies to a material's textures: give texture_ka, texture_kd or texture_ks"
        )
    );
}

#[test]
fn simrenderer_texture_materials_read_and_convert() {
    let dir = temp_dir("texture-simrenderer");
    write_quad(&dir.join("quad.png"));
    let text = "camera\nposition 0 -5 0\nlook_at 0 0 0\nup 0 0 1\nend\n\
        texture_materiel\nnom damier\ntexture_ka quad.png\ntexture_kd quad.png\ntexture_ks none\nend\n\
        primitive\nmaterial_name damier\nsphere\nend\nend\n";
    let file = dir.join("lab.txt");
    std::fs::write(&file, text).unwrap();
    let s = scene::load(&file).unwrap();
    let m = &s.materials[s.objects[0].material()];
    let maps = m.images().expect("a texture material");
    assert!(maps.ambient.is_some() && maps.diffuse.is_some() && maps.specular.is_none());
    assert_eq!(maps.diffuse.as_ref().unwrap().file, "quad.png");
    // To TOML beside it, and back: the same scene.
    let toml = scene::simrenderer::to_toml(&s, "lab.txt").unwrap();
    assert!(toml.text.contains("texture_kd = \"quad.png\""), "{}", toml.text);
    let back_file = dir.join("back.toml");
    std::fs::write(&back_file, &toml.text).unwrap();
    let back = scene::load(&back_file).unwrap();
    assert_eq!(back.materials, s.materials);
    // A missing image, on its line and column, naming the file.
    std::fs::write(&file, text.replace("texture_kd quad.png", "texture_kd nowhere.png")).unwrap();
    let e = scene::load(&file).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "{}:9:12: texture_materiel.texture_kd: {}: cannot read the texture: No such file or directory (os error 2)",
            file.display(),
            dir.join("nowhere.png").display()
        )
    );
}

#[test]
fn materials_without_images_keep_their_serialised_bytes() {
    // The serialised form (the scene hash of shards) has no texture field at all.
    let s = parse(
        "[image]\nwidth = 4\nheight = 4\n[camera]\nposition = [0, -5, 0]\nlook_at = [0, 0, 0]\n[materials.m]\nkd = 0.5\n",
        "t.toml",
    )
    .unwrap();
    let json = serde_json::to_string(&s.materials).unwrap();
    assert!(!json.contains("texture"), "{json}");
    assert_eq!(
        json,
        r#"[{"color":[1.0,1.0,1.0],"ka":0.2,"kd":0.8,"ks":0.5,"shininess":20.0,"metal":0.0,"kr":0.0,"kt":0.0,"ior":1.0},{"color":[1.0,1.0,1.0],"ka":0.2,"kd":0.5,"ks":0.5,"shininess":20.0,"metal":0.0,"kr":0.0,"kt":0.0,"ior":1.0}]"#
    );
}

#[test]
fn textured_renders_are_the_same_bytes_for_any_thread_count() {
    let s = scene("figures/optique/05-textured-sphere.toml");
    let one = render_small(&s, 64, 48, 4, 1);
    let three = render_small(&s, 64, 48, 4, 3);
    assert_eq!(one.encode_png().unwrap(), three.encode_png().unwrap());
    // The image shows the texture: the blue cap's texel (40, 70, 200) lit, bluer than red.
    assert!(one.pixels.iter().any(|p| p.z > 2.0 * p.x && p.z > 0.2));
}

#[test]
fn adaptive_depth_control_counts_an_image_whole_in_its_bound() {
    // A mirror ball (k_r = 0.01) reflects a plane behind the camera whose diffuse colour is
    // a white image over `kd = 0.001`: the image takes the diffuse term whole, so the
    // reflected ray brings 0.01 x 1 x N.L, 1.8 levels at N.L = 1 / sqrt 2. Bounded by the plane's `kd`
    // (0.001), the ray would weigh 0.01 x 0.001, below the default threshold of 0.25 levels,
    // and be cut; bounded by the image's 1, it is traced, and the image is the one traced
    // with adaptive depth control off, to the bit. The built-in default material (kd 0.8),
    // in the bound's maximum over materials, is replaced by a black one.
    let dir = temp_dir("texture-adaptive");
    image::save_buffer(dir.join("white.png"), &[255u8; 3], 1, 1, image::ExtendedColorType::Rgb8).unwrap();
    let text = "[image]\nwidth = 32\nheight = 32\nsamples_per_pixel = 1\n\
         [camera]\nposition = [0, -5, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\nvfov = 30\n\
         [render]\ndepth = 2\n\
         [materials.mirror]\nka = 0\nkd = 0\nks = 0\nkr = 0.01\n\
         [materials.default]\nka = 0\nkd = 0\nks = 0\n\
         [materials.wall]\nka = 0\nkd = 0.001\nks = 0\ntexture_kd = \"white.png\"\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"mirror\"\n\
         [[shapes]]\ntype = \"plane\"\npoint = [0, -10, 0]\nnormal = [0, 1, 0]\nmaterial = \"wall\"\n\
         [[lights]]\ntype = \"directional\"\ndirection = [0, -1, -1]\ncolor = [1, 1, 1]\n";
    let file = dir.join("mirror.toml");
    std::fs::write(&file, text).unwrap();
    let adaptive = scene::load(&file).unwrap();
    assert_eq!(adaptive.settings.adaptive_threshold, 0.25);
    let mut exact = adaptive.clone();
    exact.settings.adaptive_threshold = 0.0;
    let (a, e) = (
        render_small(&adaptive, 32, 32, 1, 2),
        render_small(&exact, 32, 32, 1, 2),
    );
    // The ball's centre reflects the wall head-on, lit at 45 degrees past the ball:
    // 0.01 of the white texel times N.L = 1 / sqrt 2.
    let centre = e.pixels[16 * 32 + 16];
    assert!(
        (centre - DVec3::splat(0.01 * std::f64::consts::FRAC_1_SQRT_2))
            .abs()
            .max_element()
            < 1e-15,
        "{centre}"
    );
    let differing = a.pixels.iter().zip(&e.pixels).filter(|(x, y)| x != y).count();
    assert_eq!(differing, 0);
}
