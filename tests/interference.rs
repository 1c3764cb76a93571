//! Interference (aperture) lights on renders: a white screen seen face-on, 1 m from the
//! light, and the positions of its bright and dark fringes measured in a rendered row
//! against the laws of wave optics; one oscillator lights it without fringes; the images do
//! not depend on the thread count. Then both scene formats: each light read, written and
//! read back, and bad values refused with their place.

use crate::common::{render_small, repo, temp_dir};
use glam::DVec3;
use lumiere::interference::{Aperture, wavelength_color};
use lumiere::light::Light;
use lumiere::render::{camera_ray, render, sample_position};
use lumiere::scene::simrenderer::{self, Options};
use lumiere::scene::{self, Scene};
use lumiere::world::World;
use std::f64::consts::TAU;

/// The distance from the light to the screen.
const L: f64 = 1.0;
/// The camera's distance to the screen.
const EYE: f64 = 0.25;

/// A white screen (the plane y = 0, facing -y) seen face-on from `EYE`, `half_width`
/// metres of it on each side of the image's centre across `width` pixels (3 rows), lit by
/// the `[[lights]]` table `light` alone.
fn screen(light: &str, width: u32, half_width: f64) -> Scene {
    screen_with(light, "", width, half_width)
}

/// [`screen`] with the tables `extra` (materials, shapes) added.
fn screen_with(light: &str, extra: &str, width: u32, half_width: f64) -> Scene {
    let height = 3;
    let vfov = 2.0
        * (half_width / EYE * f64::from(height) / f64::from(width))
            .atan()
            .to_degrees();
    let text = format!(
        "[image]\nwidth = {width}\nheight = {height}\nsamples_per_pixel = 1\n\
         [camera]\nposition = [0, {}, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\nvfov = {vfov}\n\
         [render]\ndepth = 1\n[conventions]\nsample_position = \"center\"\n\
         [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, -1, 0]\n{extra}\n\
         [[lights]]\n{light}\n",
        -EYE
    );
    scene::parse(&text, "screen.toml").expect("the screen scene reads")
}

/// A slit light along x, centred at (0, -L, 0), from -length/2 to length/2.
fn slit(length: f64, oscillators: u32, nm: f64, extra: &str) -> String {
    format!(
        "type = \"linear_aperture\"\nstart = [{}, {}, 0]\nend = [{}, {}, 0]\nwavelength = {nm}\noscillators = {oscillators}\n{extra}",
        -length / 2.0,
        -L,
        length / 2.0,
        -L
    )
}

/// The middle row: each pixel's screen x (where its camera ray meets the screen) and its
/// radiance in channel `channel`, from the film's f64 values.
fn row(scene: &Scene, channel: usize) -> Vec<(f64, f64)> {
    let world = World::new(scene);
    let (film, _) = render(&world, &|| {});
    let y = scene.settings.height / 2;
    (0..scene.settings.width)
        .map(|x| {
            let ray = camera_ray(&world, sample_position(&world, x, y, 0));
            let t = -ray.origin.y / ray.dir.y;
            ((ray.origin + t * ray.dir).x, film.get(x, y)[channel])
        })
        .collect()
}

/// The screen x of each local maximum (`maxima`) or minimum of `row` whose value `keep`
/// admits, refined by the parabola through the pixel and its two neighbours, ascending.
fn extrema(row: &[(f64, f64)], maxima: bool, keep: impl Fn(f64) -> bool) -> Vec<f64> {
    let sign = if maxima { 1.0 } else { -1.0 };
    let mut out = Vec::new();
    for i in 1..row.len() - 1 {
        let (a, b, c) = (sign * row[i - 1].1, sign * row[i].1, sign * row[i + 1].1);
        if b > a && b >= c && keep(row[i].1) {
            let delta = 0.5 * (a - c) / (a - 2.0 * b + c);
            out.push(row[i].0 + delta * (row[i + 1].0 - row[i].0));
        }
    }
    out.sort_by(f64::total_cmp);
    out
}

/// The channel where the colour of wavelength `nm` is strongest.
fn channel(nm: f64) -> usize {
    let c = wavelength_color(nm).unwrap();
    (0..3).max_by(|&i, &j| c[i].total_cmp(&c[j])).unwrap()
}

/// The bright fringes of `positions` numbered from the one nearest the centre (m = 0),
/// each against `m spacing`: every one within 1 % (the central one within 1 % of the
/// spacing). Returns how many were checked.
fn assert_law(positions: &[f64], spacing: f64, what: &str) -> usize {
    let centre = (0..positions.len())
        .min_by(|&i, &j| positions[i].abs().total_cmp(&positions[j].abs()))
        .unwrap();
    let mut worst: f64 = 0.0;
    for (i, y) in positions.iter().enumerate() {
        let m = i as f64 - centre as f64;
        let expected = m * spacing;
        let scale = if m == 0.0 { spacing } else { expected.abs() };
        assert!(
            (y - expected).abs() <= 0.01 * scale,
            "{what}: fringe m = {m} at {y:e} m, the law puts it at {expected:e} m"
        );
        worst = worst.max((y - expected).abs() / scale);
    }
    // Shown with --nocapture: how far the measured fringes are from the law.
    eprintln!(
        "{what}: {} fringes, at most {:.4} % from the law",
        positions.len(),
        worst * 100.0
    );
    positions.len()
}

#[test]
fn two_slits_fringes_follow_y_m_equals_m_lambda_l_over_d() {
    let (nm, d) = (633.0, 1e-4);
    let s = screen(&slit(d, 2, nm, ""), 2001, 0.025);
    let r = row(&s, channel(nm));
    let peak = r.iter().map(|p| p.1).fold(0.0, f64::max);
    let maxima = extrema(&r, true, |v| v > 0.5 * peak);
    let spacing = nm * 1e-9 * L / d;
    // 6.33 mm apart over +-25 mm: m = -3 to 3.
    assert_eq!(assert_law(&maxima, spacing, "two slits"), 7);
    // The spacing over the six intervals, measured: within 1 % of λ L / d.
    let measured = (maxima[6] - maxima[0]) / 6.0;
    assert!((measured / spacing - 1.0).abs() < 0.01, "{measured} against {spacing}");
}

#[test]
fn grating_principal_maxima_follow_the_same_law() {
    // 8 oscillators d = 0.1 mm apart: the principal maxima of the two slits' law, with
    // N - 2 = 6 weak maxima between two of them.
    let (nm, d, n) = (532.0, 1e-4, 8);
    let s = screen(&slit(d * f64::from(n - 1), n, nm, ""), 2001, 0.025);
    let r = row(&s, channel(nm));
    let peak = r.iter().map(|p| p.1).fold(0.0, f64::max);
    let principal = extrema(&r, true, |v| v > 0.5 * peak);
    let spacing = nm * 1e-9 * L / d;
    // 5.32 mm apart over +-25 mm: m = -4 to 4.
    assert_eq!(assert_law(&principal, spacing, "grating"), 9);
    let between = extrema(&r, true, |v| v <= 0.5 * peak)
        .into_iter()
        .filter(|y| *y > principal[4] && *y < principal[5])
        .count();
    assert_eq!(between, (n - 2) as usize);
}

#[test]
fn single_slit_minima_are_where_a_sin_theta_equals_m_lambda() {
    // A slit a = 0.1 mm wide, 200 oscillators along it, ends included.
    let (nm, a, n) = (633.0, 1e-4, 200);
    let s = screen(&slit(a, n, nm, ""), 2001, 0.025);
    let r = row(&s, channel(nm));
    let peak = r.iter().map(|p| p.1).fold(0.0, f64::max);
    let minima = extrema(&r, false, |v| v < 0.01 * peak);
    let lambda = nm * 1e-9;
    // Sides: m < 0 left of the centre, m > 0 right, numbered outwards from the centre.
    let (left, right): (Vec<f64>, Vec<f64>) = minima.iter().partition(|y| **y < 0.0);
    assert!(left.len() >= 3 && right.len() >= 3, "{minima:?}");
    let (mut worst_a, mut worst_strips): (f64, f64) = (0.0, 0.0);
    for (k, y) in left.iter().rev().enumerate().chain(right.iter().enumerate()) {
        let m = (k + 1) as f64;
        let sin_theta = y.abs() / y.hypot(L);
        let ratio = a * sin_theta / (m * lambda);
        assert!(
            (ratio - 1.0).abs() < 0.01,
            "minimum m = {m} at {y:e}: a sin θ / m λ = {ratio}"
        );
        // Each oscillator stands for a strip a / (N - 1) wide: N of them span
        // N a / (N - 1), the width whose minima the discrete sum has exactly.
        let strips = f64::from(n) * a / f64::from(n - 1);
        let ratio_strips = strips * sin_theta / (m * lambda);
        assert!(
            (ratio_strips - 1.0).abs() < 1e-3,
            "m = {m}: N s sin θ / m λ = {ratio_strips}"
        );
        worst_a = worst_a.max((ratio - 1.0).abs());
        worst_strips = worst_strips.max((ratio_strips - 1.0).abs());
    }
    eprintln!(
        "single slit: {} minima, a sin θ at most {:.4} % from m λ, N s sin θ at most {:.4} %",
        minima.len(),
        worst_a * 100.0,
        worst_strips * 100.0
    );
    // Between the first minima, one central maximum.
    let central = extrema(&r, true, |v| v > 0.5 * peak);
    assert_eq!(central.len(), 1);
    assert!(central[0].abs() < 1e-5, "{central:?}");
}

#[test]
fn one_oscillator_lights_without_fringes() {
    // One oscillator at the slit's middle, quadratic attenuation: each pixel is the
    // light's colour × amplification × A(d) × the time average of sin² over
    // period_iteration instants, whatever the phase.
    let (nm, steps) = (550.0, 10);
    let extra = "period_iteration = 10\namplification = 3\nattenuation = { quadratic = 2 }\n";
    let s = screen(&slit(1e-4, 1, nm, extra), 401, 0.025);
    let color = wavelength_color(nm).unwrap();
    let mean_sin2 = (0..steps)
        .map(|i| (0.3 - TAU * f64::from(i) / f64::from(steps)).sin().powi(2))
        .sum::<f64>()
        / f64::from(steps);
    let c = channel(nm);
    let r = row(&s, c);
    for &(x, v) in &r {
        let d = DVec3::new(x, L, 0.0).length();
        let expected = color[c] * 3.0 * mean_sin2 / (1.0 + 2.0 * d * d);
        assert!((v - expected).abs() <= 1e-12, "x = {x}: {v} against {expected}");
    }
    // No fringe: the row falls off monotonically from its middle.
    let mid = r.len() / 2;
    assert!(r[mid..].windows(2).all(|w| w[1].1 < w[0].1));
    assert!(r[..=mid].windows(2).all(|w| w[1].1 > w[0].1));
}

#[test]
fn glass_shadows_an_aperture_light_only_when_it_leaves_none_of_its_colour() {
    // A glass disk of radius 1 cm halfway between a red light (633 nm, colour (1, 0, 0))
    // and the screen: its shadow on the screen has a radius of 2 cm. Green glass leaves
    // none of the red: the shadow is black. Yellow glass leaves all of it: the light
    // arrives untinted, as if the glass were not there.
    let light = slit(1e-4, 1, 633.0, "");
    let glass = |color: &str| {
        format!(
            "[materials.glass]\ncolor = {color}\nkt = 0.5\n\
             [[shapes]]\ntype = \"disk\"\ncenter = [0, {}, 0]\nnormal = [0, 1, 0]\nradius = 0.01\nmaterial = \"glass\"\n",
            -L / 2.0
        )
    };
    let bare = row(&screen(&light, 101, 0.025), 0);
    let green = row(&screen_with(&light, &glass("[0, 1, 0]"), 101, 0.025), 0);
    let yellow = row(&screen_with(&light, &glass("[1, 1, 0]"), 101, 0.025), 0);
    assert_eq!(yellow, bare);
    for ((x, v), (_, lit)) in green.iter().zip(&bare) {
        assert!(*lit > 0.4, "{x}: {lit}");
        if x.abs() < 0.019 {
            assert_eq!(*v, 0.0, "in the shadow, x = {x}");
        } else if x.abs() > 0.021 {
            assert_eq!(v, lit, "outside the shadow, x = {x}");
        }
    }
}

#[test]
fn renders_are_the_same_bytes_for_one_and_two_threads() {
    for file in [
        "scenes/figures/optique/01-two-slits.toml",
        "scenes/figures/optique/02-grating.toml",
        "scenes/figures/optique/03-single-slit.toml",
    ] {
        let s = scene::load(&repo(file)).unwrap();
        let one = render_small(&s, 160, 120, 1, 1).encode_png().unwrap();
        let two = render_small(&s, 160, 120, 1, 2).encode_png().unwrap();
        assert_eq!(one, two, "{file}");
        assert!(
            render_small(&s, 160, 120, 1, 2).to_rgb8().iter().any(|&c| c > 200),
            "{file} is lit"
        );
    }
}

/// The SIMRenderer file `text` read, then written in each format and read back: the same
/// scene every time.
fn round_trips(text: &str, dir: &std::path::Path) -> Scene {
    let file = dir.join("lab.txt");
    let options = Options::default();
    let first = simrenderer::parse(text, file.to_str().unwrap(), &options)
        .unwrap()
        .scene;
    let toml = simrenderer::to_toml(&first, "lab.txt").unwrap().text;
    let from_toml = scene::parse(&toml, dir.join("lab.toml").to_str().unwrap()).unwrap();
    assert_eq!(from_toml.lights, first.lights, "{toml}");
    let sim = simrenderer::to_simrenderer(&from_toml, "lab.toml", "image")
        .unwrap()
        .text;
    let back = simrenderer::parse(&sim, file.to_str().unwrap(), &options)
        .unwrap()
        .scene;
    assert_eq!(back.lights, first.lights, "{sim}");
    first
}

#[test]
fn simrenderer_lights_read_with_their_defaults_and_convert_both_ways() {
    let dir = temp_dir("interference-formats");
    // A 3 x 3 mask: white on the top row and the middle column (a T), black elsewhere.
    let white = [255u8, 255, 255];
    let mut img = image::RgbImage::new(3, 3);
    for (x, y, p) in img.enumerate_pixels_mut() {
        p.0 = if y == 0 || x == 1 { white } else { [0, 0, 0] };
    }
    img.save(dir.join("t.png")).unwrap();
    let text = "linear_aperture_light\nwave_length 650 nm\nend\n\
                linear_aperture_light\nposition 0 0 0\npoint 0.001 0 0\nnb_oscillator 5\nlongueur_onde 500\nend\n\
                rectangular_aperture_light\nposition 0 0 2\nwidth 0.002\nhauteur 0.001\nnb_oscillator 3\nend\n\
                elliptical_aperture_light\ndevant 0 0 -1\nhaut 1 0 0\nend\n\
                aperture_mask_light\nmasque t.png\nnb_oscillator 3\nend\n";
    let s = round_trips(text, &dir);
    let lights: Vec<_> = s
        .lights
        .iter()
        .map(|l| match l {
            Light::Aperture(a) => a,
            other => panic!("{other:?}"),
        })
        .collect();
    // SIMRenderer's defaults: a slit from the origin to (0, 0.0001, 0), 2 oscillators,
    // period_iteration 10, 550 nm unless given.
    assert_eq!(
        lights[0].aperture,
        Aperture::Linear {
            start: DVec3::ZERO,
            end: DVec3::new(0.0, 1e-4, 0.0)
        }
    );
    assert_eq!(
        (
            lights[0].wavelength_nm,
            lights[0].oscillator_count,
            lights[0].period_iteration
        ),
        (650.0, 2, 10)
    );
    assert_eq!(lights[0].color, wavelength_color(650.0).unwrap());
    assert_eq!(lights[1].oscillators.len(), 5);
    assert_eq!(lights[1].oscillators[4], DVec3::new(0.001, 0.0, 0.0));
    // 0.002 x 0.001, 3 along the height: spacing 0.0005, ceil(0.002 / 0.0005) + 1 = 5
    // across.
    assert_eq!(lights[2].oscillators.len(), 15);
    // The default 0.001 x 0.001 ellipse with 2 per side: its 4 corners lie outside.
    assert_eq!(lights[3].oscillators.len(), 0);
    // The T mask on a 3 x 3 grid: texel (column i, row j) for grid point (i, j); the
    // image's top row lies on the aperture's lower edge (j = 0). Kept: j = 0 (3) and
    // i = 1 (2 more).
    assert_eq!(lights[4].oscillators.len(), 5);
    let lower = lights[4].oscillators.iter().filter(|o| o.y < -1e-4).count();
    assert_eq!(lower, 3, "{:?}", lights[4].oscillators);
}

#[test]
fn the_toml_format_reads_every_key_and_refuses_bad_values_in_place() {
    let base = "[image]\nwidth = 4\nheight = 3\n[camera]\nposition = [0, -1, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\n[[lights]]\n";
    let ok = format!(
        "{base}type = \"elliptical_aperture\"\ncenter = [0, 0, 1]\nfront = [0, 0, 2]\nup = [1, 0, 0]\nwidth = 0.002\nheight = 0.002\n\
         wavelength = 480\noscillators = 5\nperiod_iteration = 4\namplification = 0.5\nattenuation = {{ linear = 1 }}\n"
    );
    let s = scene::parse(&ok, "t.toml").unwrap();
    let Light::Aperture(a) = &s.lights[0] else { panic!() };
    assert_eq!(
        (a.wavelength_nm, a.oscillator_count, a.period_iteration, a.amplification),
        (480.0, 5, 4, 0.5)
    );
    // A 5 x 5 grid of spacing 0.0005 on a circle of radius 0.001: with (i, j) in [-2, 2]²
    // from the centre, i² + j² <= 4 keeps 5 + 2 × 3 + 2 = 13.
    assert_eq!(a.oscillators.len(), 13);
    let cases = [
        (
            "type = \"linear_aperture\"\nwavelength = 300\n",
            "t.toml:10:14: lights[0].wavelength: must be a visible wavelength, in [380, 780] nm, got 300",
        ),
        (
            "type = \"linear_aperture\"\nstart = [1, 2, 3]\nend = [1, 2, 3]\n",
            "t.toml:11:7: lights[0].end: must differ from start [1.0, 2.0, 3.0] (a slit has two ends)",
        ),
        (
            "type = \"rectangular_aperture\"\noscillators = 0\n",
            "t.toml:10:15: lights[0].oscillators: must be in [1, 100000], got 0",
        ),
        (
            "type = \"rectangular_aperture\"\nwidth = 65536\nheight = 1\noscillators = 3\n",
            "t.toml:12:15: lights[0].oscillators: 3 along the shorter side make a grid of 393219 oscillators over this aperture, at most 100000 are allowed",
        ),
        (
            "type = \"elliptical_aperture\"\nup = [0, 0, 3]\n",
            "t.toml:10:6: lights[0].up: must not be parallel to front",
        ),
        (
            "type = \"rectangular_aperture\"\nmask = \"m.png\"\n",
            "t.toml:10:8: lights[0].mask: mask applies to an aperture_mask light only, not to a rectangular_aperture light",
        ),
        (
            "type = \"linear_aperture\"\nperiod_iteration = 0\n",
            "t.toml:10:20: lights[0].period_iteration: must be in [1, 100000], got 0",
        ),
    ];
    for (light, expected) in cases {
        let e = scene::parse(&format!("{base}{light}"), "t.toml").unwrap_err();
        assert_eq!(e.to_string(), expected);
    }
    let e = scene::parse(
        &format!("{base}type = \"aperture_mask\"\nmask = \"absent.png\"\n"),
        "t.toml",
    )
    .unwrap_err();
    let m = e.to_string();
    assert!(
        m.starts_with("t.toml:10:8: lights[0].mask: absent.png: cannot read the mask image: "),
        "{m}"
    );
    // A PNM header may say 0 x 0, which the image crate decodes to no pixel at all: refused
    // by its size, as a texture is, before the grid looks up a texel.
    let dir = temp_dir("empty-mask");
    std::fs::write(dir.join("empty.ppm"), "P3\n0 0\n255\n").unwrap();
    let file = dir.join("t.toml");
    std::fs::write(&file, format!("{base}type = \"aperture_mask\"\nmask = \"empty.ppm\"\n")).unwrap();
    let e = scene::load(&file).unwrap_err().to_string();
    let empty = dir.join("empty.ppm");
    assert_eq!(
        e,
        format!(
            "{}:10:8: lights[0].mask: {}: the mask image is 0 x 0: it must hold between 1 and 67108864 texels",
            file.display(),
            empty.display()
        )
    );
}

#[test]
fn simrenderer_values_out_of_range_are_placed_on_their_line() {
    let cases = [
        (
            "linear_aperture_light\nwave_length 800\nend\n",
            "lab.txt:2:13: linear_aperture_light.wave_length: must be a finite number in [380, 780], got 800",
        ),
        (
            "linear_aperture_light\nnb_oscillator 0\nend\n",
            "lab.txt:2:15: linear_aperture_light.nb_oscillator: must be an integer in [1, 100000], got 0",
        ),
        (
            "linear_aperture_light\nposition 1 1 1\nposition 1 1 1\nend\n",
            "lab.txt:3:1: linear_aperture_light.position: the second end must differ from the first, 1 1 1",
        ),
        (
            "rectangular_aperture_light\nfront 0 1 0\nup 0 2 0\nend\n",
            "lab.txt:3:1: rectangular_aperture_light.up: up must not be parallel to front",
        ),
        (
            "aperture_mask_light\nmask absent.png\nend\n",
            "lab.txt:2:6: aperture_mask_light.mask: absent.png: cannot read the mask image: ",
        ),
    ];
    for (text, expected) in cases {
        let e = simrenderer::parse(text, "lab.txt", &Options::default()).unwrap_err();
        assert!(e.to_string().starts_with(expected), "{e}\nexpected {expected}");
    }
    // A colour is SIMRenderer's to replace: a warning, and the wavelength's colour.
    let p = simrenderer::parse(
        "linear_aperture_light\ncolor 1 0 0\nend\n",
        "lab.txt",
        &Options::default(),
    )
    .unwrap();
    assert_eq!(p.warnings.len(), 1);
    assert!(
        p.warnings[0]
            .to_string()
            .starts_with("lab.txt:2:1: linear_aperture_light.color: ")
    );
    let Light::Aperture(a) = &p.scene.lights[0] else {
        panic!()
    };
    assert_eq!(a.color, wavelength_color(550.0).unwrap());
}

#[test]
fn a_bad_light_on_the_command_line_exits_2_and_writes_nothing() {
    let dir = temp_dir("interference-cli");
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        "[image]\nwidth = 4\nheight = 3\n[camera]\nposition = [0, -1, 0]\nlook_at = [0, 0, 0]\n[[lights]]\ntype = \"linear_aperture\"\nwavelength = 900\n",
    )
    .unwrap();
    let out = dir.join("x.png");
    let run = crate::common::lumiere(&["render", bad.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
    assert_eq!(run.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        stderr.contains("bad.toml:9:14: lights[0].wavelength: must be a visible wavelength, in [380, 780] nm, got 900"),
        "{stderr}"
    );
    assert!(!out.exists());
}
