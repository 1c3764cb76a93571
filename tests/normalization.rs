//! SIMRenderer's `color_normalization division_factor`: a pixel whose largest channel
//! exceeds 1 is divided by it before quantisation, in every 8-bit image a render writes
//! (whole, merged from shards), in `probe`'s lines and in `diagnose`'s renders, and read
//! and written in both formats.

use crate::common::{lumiere_ok, temp_dir, write_in};
use lumiere::film::Normalization;
use lumiere::scene;
use std::path::Path;

/// A sphere lit by an ambient light of 4 alone: `L_a k_a S` = 4 x 0.5 x (1, 0.5, 0.25) =
/// (2, 1, 0.5) at every pixel it covers.
fn scene_text(normalization: &str) -> String {
    format!(
        "[image]\nwidth = 20\nheight = 16\nsamples_per_pixel = 1\n\
         [camera]\nposition = [0, -6, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\nvfov = 40\n\
         [render]\ndiffuse = false\nspecular = \"none\"\ncolor_normalization = \"{normalization}\"\n\
         [materials.m]\ncolor = [1, 0.5, 0.25]\nka = 0.5\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n\
         [[lights]]\ntype = \"ambient\"\ncolor = [4, 4, 4]\n"
    )
}

fn middle(png: &Path) -> [u8; 3] {
    image::open(png).unwrap().to_rgb8().get_pixel(10, 8).0
}

#[test]
fn division_factor_keeps_the_hue_where_clamping_does_not() {
    let dir = temp_dir("normalization");
    let divided = write_in(&dir, "divided.toml", &scene_text("division_factor"));
    let clamped = write_in(&dir, "clamped.toml", &scene_text("clamp_channel"));
    assert_eq!(
        scene::load(Path::new(&divided)).unwrap().settings.color_normalization,
        Normalization::DivisionFactor
    );
    // (2, 1, 0.5) / 2 = (1, 0.5, 0.25): 255, 128, 64; clamped: 255, 255, 128.
    let (a, b) = (dir.join("divided.png"), dir.join("clamped.png"));
    lumiere_ok(&["render", &divided, "-o", a.to_str().unwrap(), "-q"]);
    lumiere_ok(&["render", &clamped, "-o", b.to_str().unwrap(), "-q"]);
    assert_eq!(middle(&a), [255, 128, 64]);
    assert_eq!(middle(&b), [255, 255, 128]);
    // Two shards merged: the same bytes as the whole render.
    let (s0, s1, merged) = (dir.join("0.shard"), dir.join("1.shard"), dir.join("merged.png"));
    lumiere_ok(&["render", &divided, "-o", s0.to_str().unwrap(), "--shard", "0/2", "-q"]);
    lumiere_ok(&["render", &divided, "-o", s1.to_str().unwrap(), "--shard", "1/2", "-q"]);
    lumiere_ok(&[
        "merge",
        s0.to_str().unwrap(),
        s1.to_str().unwrap(),
        "-o",
        merged.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(std::fs::read(&merged).unwrap(), std::fs::read(&a).unwrap());
    // probe says the division.
    let text = lumiere_ok(&["probe", &divided, "--pixel", "10,8"]);
    assert!(
        text.contains(
            "  divided by its largest channel above 1 (division_factor) (1.000000, 0.500000, 0.250000)\n  clamped to [0, 1] (1.000000, 0.500000, 0.250000)\n  8-bit (255, 128, 64)\n"
        ),
        "{text}"
    );
    // diagnose writes the oracle and every mistake through the division: the scene's own
    // render is no mistake, and the gamma mistake's image, (1, 0.5, 0.25) divided then
    // sRGB-encoded, (1, 0.7354, 0.5371): 255 188 137 (clamped it would be 255 255 188), is
    // named first.
    let text = lumiere_ok(&["diagnose", &divided, a.to_str().unwrap()]);
    assert!(text.contains("verdict            no mistake found\n"), "{text}");
    let gamma = dir.join("gamma.png");
    lumiere_ok(&[
        "render",
        &divided,
        "--mistake",
        "gamma-applied",
        "-o",
        gamma.to_str().unwrap(),
    ]);
    assert_eq!(middle(&gamma), [255, 188, 137]);
    let text = lumiere_ok(&["diagnose", &divided, gamma.to_str().unwrap()]);
    assert!(
        text.contains("verdict            mistake found\n1. gamma-applied:"),
        "{text}"
    );
}

#[test]
fn simrenderer_division_factor_reads_and_converts() {
    let dir = temp_dir("normalization-simrenderer");
    let lab = write_in(
        &dir,
        "lab.txt",
        "raytracer\ncolor_normalization division_factor\nend\n\
         primitive\nsphere\nend\nend\n",
    );
    let s = scene::load(Path::new(&lab)).unwrap();
    assert_eq!(s.settings.color_normalization, Normalization::DivisionFactor);
    let toml = dir.join("lab.toml");
    lumiere_ok(&["convert", &lab, "-o", toml.to_str().unwrap()]);
    let written = std::fs::read_to_string(&toml).unwrap();
    assert!(
        written.contains("color_normalization = \"division_factor\"\n"),
        "{written}"
    );
    let back = dir.join("back.txt");
    lumiere_ok(&["convert", toml.to_str().unwrap(), "-o", back.to_str().unwrap()]);
    let back = std::fs::read_to_string(&back).unwrap();
    assert!(back.contains("color_normalization division_factor\n"), "{back}");
    // A scene without it writes neither line.
    let plain = write_in(&dir, "plain.txt", "primitive\nsphere\nend\nend\n");
    let plain_toml = dir.join("plain.toml");
    lumiere_ok(&["convert", &plain, "-o", plain_toml.to_str().unwrap()]);
    assert!(
        !std::fs::read_to_string(&plain_toml)
            .unwrap()
            .contains("color_normalization")
    );
}

#[test]
fn an_unknown_normalization_is_named() {
    let dir = temp_dir("normalization-bad");
    let path = write_in(&dir, "bad.toml", &scene_text("divide"));
    let e = scene::load(Path::new(&path)).unwrap_err().to_string();
    assert!(
        e.ends_with("render.color_normalization: must be \"clamp_channel\" or \"division_factor\", got \"divide\""),
        "{e}"
    );
}
