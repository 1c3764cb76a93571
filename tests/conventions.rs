//! Each convention where the chapter and SIMRenderer differ, pinned on a pixel computed by
//! hand: the chapter's value, then the other's.

use glam::DVec3;
use lumiere::conventions::Conventions;
use lumiere::math::Ray;
use lumiere::render::sample_position;
use lumiere::scene::{Scene, parse};
use lumiere::trace::{NoRecord, Tracer};
use lumiere::world::World;

/// A scene of `body` (shapes, lights, materials) with a 2 x 2 image looking along +y from
/// the origin, and `conventions` lines for its `[conventions]` table.
fn scene(body: &str, conventions: &str, depth: u32) -> Scene {
    let text = format!(
        "[image]\nwidth = 2\nheight = 2\nsamples_per_pixel = 1\n\
         [camera]\nposition = [0, 0, 0]\nlook_at = [0, 1, 0]\nvfov = 60\n\
         [render]\ndepth = {depth}\nbackground = [0.1, 0.1, 0.1]\n\
         [conventions]\n{conventions}\n{body}"
    );
    parse(&text, "s.toml").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The radiance along `ray` as a camera ray.
fn radiance(scene: &Scene, ray: Ray) -> DVec3 {
    let world = World::new(scene);
    Tracer::new(&world).trace_camera(&ray, &mut NoRecord)
}

/// The radiance of the camera ray of sample 0 of pixel (1, 1): through the image's center
/// with the `corner` sample position.
fn center_pixel(scene: &Scene) -> DVec3 {
    let world = World::new(scene);
    let (w, h) = (scene.settings.width, scene.settings.height);
    let mut film = lumiere::render::render(&world, &|| {}).0;
    film.pixels.swap_remove((h as usize / 2) * w as usize + w as usize / 2)
}

fn close(a: DVec3, b: DVec3) {
    assert!((a - b).abs().max_element() < 1e-12, "{a} against {b}");
}

const AMBIENT: &str = "[[lights]]\ntype = \"ambient\"\ncolor = [1, 1, 1]\n";

#[test]
fn sample_positions_by_hand() {
    // A 4 x 3 image, 4 samples (a 2 x 2 grid): pixel (1, 2).
    let at = |conventions: &str, k: u32| {
        let mut s = scene("", conventions, 1);
        (s.settings.width, s.settings.height, s.settings.samples_per_pixel) = (4, 3, 4);
        sample_position(&World::new(&s), 1, 2, k)
    };
    assert_eq!(at("sample_position = \"regular\"", 0), (1.25, 2.25));
    assert_eq!(at("sample_position = \"regular\"", 3), (1.75, 2.75));
    assert_eq!(at("sample_position = \"center\"", 2), (1.5, 2.5));
    // SIMRenderer's corner: the image's center at (4 div 2, 3 div 2) = (2, 1) pixels from
    // the top-left, so along the odd height half a pixel below the true corner.
    assert_eq!(at("sample_position = \"corner\"", 1), (1.0, 2.5));
    // SIMRenderer's other corners: one pixel right, below, or both.
    assert_eq!(at("sample_position = \"top_right\"", 1), (2.0, 2.5));
    assert_eq!(at("sample_position = \"bottom_left\"", 1), (1.0, 3.5));
    assert_eq!(at("sample_position = \"bottom_right\"", 1), (2.0, 3.5));
    // The chapter's: sample 0 anywhere in the top-left cell, sample 3 in the bottom-right.
    let (x, y) = at("", 0);
    assert!((1.0..1.5).contains(&x) && (2.0..2.5).contains(&y), "({x}, {y})");
    let (x, y) = at("", 3);
    assert!((1.5..2.0).contains(&x) && (2.5..3.0).contains(&y), "({x}, {y})");
}

#[test]
fn camera_rays_from_the_near_plane_up_to_far() {
    // A sphere of radius 0.25 at distance 0.5, ambient-lit (k_a = 1, S = (0.2, 0.4, 0.6)),
    // and a white wall at y = 10 behind it.
    let body = format!(
        "{AMBIENT}[materials.ball]\ncolor = [0.2, 0.4, 0.6]\nka = 1\nkd = 0\nks = 0\n\
         [materials.wall]\nka = 1\nkd = 0\nks = 0\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0.5, 0]\nradius = 0.25\nmaterial = \"ball\"\n\
         [[shapes]]\ntype = \"plane\"\npoint = [0, 10, 0]\nnormal = [0, -1, 0]\nmaterial = \"wall\"\n"
    );
    let corner = "sample_position = \"corner\"\n";
    // From the eye the sphere is seen.
    close(center_pixel(&scene(&body, corner, 1)), DVec3::new(0.2, 0.4, 0.6));
    // From the near plane at 1 it is behind the ray's origin: the wall is seen.
    let near = format!("{corner}ray_origin = \"near_plane\"\nnear = 1\n");
    close(center_pixel(&scene(&body, &near, 1)), DVec3::ONE);
    // The wall is 9 past the near plane: a far limit of 5 leaves the background.
    close(
        center_pixel(&scene(&body, &format!("{near}far = 5\n"), 1)),
        DVec3::splat(0.1),
    );
    close(
        center_pixel(&scene(&body, &format!("{near}far = 9.5\n"), 1)),
        DVec3::ONE,
    );
}

/// A white floor (k_d = 1 only) under a white point light at (0, 0, 10), with a transparent
/// sphere of colour (1, 0.5, 0.25) and `k_t` 0.5 between them; the floor's point (0, 0, 0)
/// seen from the side.
fn filtered_floor(conventions: &str) -> DVec3 {
    let body = "[materials.floor]\nka = 0\nkd = 1\nks = 0\n\
         [materials.glass]\ncolor = [1, 0.5, 0.25]\nka = 0\nkd = 0\nks = 0\nkt = 0.5\n\
         [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nmaterial = \"floor\"\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 5]\nradius = 1\nmaterial = \"glass\"\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 0, 10]\ncolor = [1, 1, 1]\n";
    let s = scene(body, conventions, 1);
    let from = DVec3::new(3.0, 0.0, 1.0);
    radiance(&s, Ray::new(from, (DVec3::ZERO - from).normalize()))
}

#[test]
fn shadows_filtered_by_the_colour_or_by_kt_times_the_colour() {
    // N.L = 1, A = 1, k_d S_floor = 1: the pixel is the filter.
    close(filtered_floor(""), DVec3::new(1.0, 0.5, 0.25));
    close(
        filtered_floor("shadow_filter = \"kt_color\""),
        DVec3::new(0.5, 0.25, 0.125),
    );
}

/// A camera ray along +y through a transparent unlit sphere (or disk, `shape`) of colour
/// (1, 0.5, 0.25), `k_t` 0.5, `n` 1, onto a white ambient-lit wall at y = 10.
fn through_glass(shape: &str, conventions: &str, depth: u32) -> DVec3 {
    let body = format!(
        "{AMBIENT}[materials.glass]\ncolor = [1, 0.5, 0.25]\nka = 0\nkd = 0\nks = 0\nkt = 0.5\nn = 1\n\
         [materials.wall]\nka = 1\nkd = 0\nks = 0\n\
         [[shapes]]\n{shape}material = \"glass\"\n\
         [[shapes]]\ntype = \"plane\"\npoint = [0, 10, 0]\nnormal = [0, -1, 0]\nmaterial = \"wall\"\n"
    );
    radiance(&scene(&body, conventions, depth), Ray::new(DVec3::ZERO, DVec3::Y))
}

const BALL: &str = "type = \"sphere\"\ncenter = [0, 5, 0]\nradius = 1\n";
const DISK: &str = "type = \"disk\"\ncenter = [0, 5, 0]\nnormal = [0, 1, 0]\nradius = 1\n";

#[test]
fn refracted_rays_weighed_by_kt_or_by_kt_times_the_colour_entering() {
    // In, out, to the wall: k_t k_t W = 0.25.
    close(through_glass(BALL, "", 3), DVec3::splat(0.25));
    // k_t S entering, k_t leaving: 0.25 S.
    close(
        through_glass(BALL, "transmission = \"kt_color_entering\"", 3),
        DVec3::new(0.25, 0.125, 0.0625),
    );
}

#[test]
fn open_shapes_refract_or_not() {
    // The disk seen through: k_t W = 0.5.
    close(through_glass(DISK, "", 2), DVec3::splat(0.5));
    // Only closed shapes refract: the unlit disk is black.
    close(through_glass(DISK, "refracting = \"closed\"", 2), DVec3::ZERO);
    // The sphere is closed: seen through either way.
    close(through_glass(BALL, "refracting = \"closed\"", 3), DVec3::splat(0.25));
}

/// A ray inside an ambient-lit glass sphere (k_a = 1, S = (0.2, 0.4, 0.6), k_r 0.25, k_t
/// 0.5, n 1.5) meeting its surface at sin i = 0.9 > 1 / 1.5: total internal reflection.
fn inside_glass(conventions: &str) -> DVec3 {
    let body = format!(
        "{AMBIENT}[materials.glass]\ncolor = [0.2, 0.4, 0.6]\nka = 1\nkd = 0\nks = 0\nkr = 0.25\nkt = 0.5\nn = 1.5\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"glass\"\n"
    );
    radiance(
        &scene(&body, conventions, 2),
        Ray::new(DVec3::new(0.9, 0.0, 0.0), DVec3::Y),
    )
}

#[test]
fn total_internal_reflection_reflects_or_drops_the_refracted_energy() {
    let s = DVec3::new(0.2, 0.4, 0.6);
    // S at the first hit, then (k_r + k_t) S at the second.
    close(inside_glass(""), s * 1.75);
    // Dropped: k_r S only.
    close(inside_glass("total_internal_reflection = \"dropped\""), s * 1.25);
}

#[test]
fn local_terms_weighed_by_one_or_by_what_the_rays_leave() {
    // At depth 1 only the first hit's local term: S, or (1 - 0.25 - 0.5) S.
    let body = format!(
        "{AMBIENT}[materials.glass]\ncolor = [0.2, 0.4, 0.6]\nka = 1\nkd = 0\nks = 0\nkr = 0.25\nkt = 0.5\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 5, 0]\nradius = 1\nmaterial = \"glass\"\n"
    );
    let ray = Ray::new(DVec3::ZERO, DVec3::Y);
    close(radiance(&scene(&body, "", 1), ray), DVec3::new(0.2, 0.4, 0.6));
    close(
        radiance(&scene(&body, "local_weight = \"remaining\"", 1), ray),
        DVec3::new(0.05, 0.1, 0.15),
    );
}

#[test]
fn highlights_in_the_light_or_the_material_colour() {
    // A specular-only floor (k_s = 1) of colour (1, 0.5, 0.25) under a white light at
    // (0, 0, 10), seen straight down: H = N, spec = 1, the pixel is the tint.
    let floor = |conventions: &str, m: &str| {
        let body = format!(
            "[materials.floor]\ncolor = [1, 0.5, 0.25]\nka = 0\nkd = 0\nks = 1\n{m}\
             [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nmaterial = \"floor\"\n\
             [[lights]]\ntype = \"point\"\nposition = [0, 0, 10]\ncolor = [1, 1, 1]\n"
        );
        let s = scene(&body, conventions, 1);
        radiance(&s, Ray::new(DVec3::new(0.0, 0.0, 5.0), -DVec3::Z))
    };
    close(floor("", ""), DVec3::ONE);
    close(floor("default_highlight = \"metal\"", ""), DVec3::new(1.0, 0.5, 0.25));
    // A material that gives m keeps it: m = 0.5 is (1, 0.75, 0.625) either way.
    close(
        floor("default_highlight = \"metal\"", "m = 0.5\n"),
        DVec3::new(1.0, 0.75, 0.625),
    );
    close(floor("", "m = 0.5\n"), DVec3::new(1.0, 0.75, 0.625));
    // The preset sets every switch.
    let preset = scene("", "preset = \"simrenderer\"", 1);
    assert_eq!(preset.settings.conventions, Conventions::SIMRENDERER);
    assert_eq!(preset.materials[0].metal, 1.0);
    // A preset, then a switch of its own.
    let mixed = scene("", "preset = \"simrenderer\"\nfar = inf", 1);
    assert_eq!(mixed.settings.conventions.far, f64::INFINITY);
    assert_eq!(mixed.settings.conventions.summary(), "simrenderer with far = inf");
}

#[test]
fn bad_conventions_are_located() {
    let text = "[image]\nwidth = 2\nheight = 2\n[camera]\nposition = [0, 0, 0]\nlook_at = [0, 1, 0]\n\
                [conventions]\npreset = \"simrenderer\"\nrefracting = \"open\"\n";
    assert_eq!(
        parse(text, "s.toml").unwrap_err().to_string(),
        "s.toml:9:14: conventions.refracting: must be \"transparent\" or \"closed\", got \"open\""
    );
    let text = text.replace("refracting = \"open\"", "gamma = 2.2");
    let e = parse(&text, "s.toml").unwrap_err().to_string();
    assert!(
        e.starts_with("s.toml:9:1: conventions.gamma: unknown field `gamma`"),
        "{e}"
    );
}

#[test]
fn the_command_line_sets_presets_and_switches_and_probe_prints_them() {
    let scene = crate::common::repo("scenes/reference.toml");
    let probe = |extra: &[&str]| {
        let mut args = vec![
            "probe",
            scene.to_str().unwrap(),
            "--pixel",
            "10,10",
            "--width",
            "20",
            "--height",
            "15",
        ];
        args.extend(extra);
        crate::common::lumiere(&args)
    };
    let out = probe(&["--conventions", "simrenderer", "--convention", "far=inf"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.lines().any(|l| l == "conventions simrenderer with far = inf"),
        "{text}"
    );
    // SIMRenderer's corner of pixel (10, 10) in a 20 x 15 image: half a pixel down along
    // the odd height.
    assert!(
        text.contains("sample 0 at image position (10.000000, 10.500000)"),
        "{text}"
    );
    let out = probe(&["--convention", "refracting=open"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "lumiere: error: --convention refracting: must be \"transparent\" or \"closed\", got \"open\"\n"
    );
}

#[test]
fn a_pixels_bottom_right_corner_is_the_next_pixels_top_left() {
    // A sphere and a floor seen at 9 x 7: pixel (x, y) under `bottom_right` traces the ray
    // of pixel (x + 1, y + 1) under `corner`, to the bit; `top_right` that of (x + 1, y),
    // `bottom_left` that of (x, y + 1).
    let body = "[[shapes]]\ntype = \"sphere\"\ncenter = [0, 4, 0]\nradius = 1\n\
                [[shapes]]\ntype = \"plane\"\npoint = [0, 0, -1]\nnormal = [0, 0, 1]\n\
                [[lights]]\ntype = \"point\"\nposition = [2, 0, 3]\ncolor = [1, 1, 1]\n";
    let film = |position: &str| {
        let mut s = scene(body, &format!("sample_position = \"{position}\""), 1);
        (s.settings.width, s.settings.height) = (9, 7);
        lumiere::render::render(&World::new(&s), &|| {}).0
    };
    let corner = film("corner");
    let at =
        |f: &lumiere::film::Film, x: u32, y: u32| f.pixels[(y * f.width + x) as usize].to_array().map(f64::to_bits);
    for (position, (dx, dy)) in [("top_right", (1, 0)), ("bottom_left", (0, 1)), ("bottom_right", (1, 1))] {
        let f = film(position);
        for y in 0..6 {
            for x in 0..8 {
                assert_eq!(at(&f, x, y), at(&corner, x + dx, y + dy), "{position} ({x}, {y})");
            }
        }
    }
    // Not a blank image: the sphere and the lit floor differ.
    assert_ne!(at(&corner, 4, 3), at(&corner, 4, 6));
}
