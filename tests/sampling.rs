//! Any number of samples per pixel in [1, 1024]: the positions of a non-square grid worked
//! out by hand, one jittered sample in each cell, a square count placed to the bit as
//! `x + (k mod n + j) / n`, a SIMRenderer lab's `sampling N`, and a 6-sample render the
//! same for any thread count and merged from shards (the counts the scene file and `--spp`
//! take and refuse: tests/cli.rs).

use crate::common::*;
use lumiere::compare::load_rgb8;
use lumiere::film::Film;
use lumiere::render::{render, sample_position};
use lumiere::sampling::{Purpose, ShortStream};
use lumiere::scene::simrenderer::{self, Options};
use lumiere::scene::{SampleGrid, Scene};
use lumiere::world::World;
use std::fs;

/// The reference scene at 12 x 9 pixels and `samples` per pixel, its samples placed by
/// `position` (a `sample_position` convention).
fn scene_with(samples: u32, position: &str) -> Scene {
    let mut s = scene("reference.toml");
    (s.settings.width, s.settings.height, s.settings.samples_per_pixel) = (12, 9, samples);
    s.settings.conventions.set("sample_position", position).unwrap();
    s
}

/// The position of sample `k` of pixel (1, 2) at `samples` per pixel, placed by `position`.
fn at(samples: u32, position: &str, k: u32) -> (f64, f64) {
    sample_position(&World::new(&scene_with(samples, position)), 1, 2, k)
}

#[test]
fn regular_samples_are_the_cell_centres_worked_out_by_hand() {
    // 2 samples: 1 column x 2 rows, cells 1 x 1/2 of the pixel, centres 1/2 across and
    // 1/4, 3/4 down.
    assert_eq!(SampleGrid::of(2), SampleGrid { columns: 1, rows: 2 });
    assert_eq!([0, 1].map(|k| at(2, "regular", k)), [(1.5, 2.25), (1.5, 2.75)]);
    // 8 samples: 2 x 4, cells 1/2 x 1/4; sample k in column k mod 2, row k div 2.
    assert_eq!(
        [0, 1, 2, 5, 6, 7].map(|k| at(8, "regular", k)),
        [
            (1.25, 2.125),
            (1.75, 2.125),
            (1.25, 2.375),
            (1.75, 2.625),
            (1.25, 2.875),
            (1.75, 2.875)
        ]
    );
    // 6 samples: 2 x 3, cells 1/2 x 1/3, rows centred at 1/6, 1/2, 5/6. A sixth is not a
    // binary fraction: the position is `y + (row + 1/2) / 3` rounded by the division and
    // by the sum, within 1e-15 of the exact value.
    let six: Vec<_> = (0..6).map(|k| at(6, "regular", k)).collect();
    let exact = [
        (1.25, 2.0 + 1.0 / 6.0),
        (1.75, 2.0 + 1.0 / 6.0),
        (1.25, 2.5),
        (1.75, 2.5),
        (1.25, 2.0 + 5.0 / 6.0),
        (1.75, 2.0 + 5.0 / 6.0),
    ];
    for (k, (&(x, y), (ex, ey))) in six.iter().zip(exact).enumerate() {
        assert_eq!(x, ex, "sample {k}");
        assert!((y - ey).abs() <= 1e-15, "sample {k}: {y} against {ey}");
    }
    assert_eq!(six[4].1, 2.0 + 2.5 / 3.0);
    // A prime: 7 samples are 1 x 7, each a seventh of the pixel high.
    assert_eq!(at(7, "regular", 3), (1.5, 2.5));
    // The corner and center ignore the grid: every sample is the same point.
    assert_eq!(at(6, "center", 5), (1.5, 2.5));
    assert_eq!(at(2, "corner", 1), at(1, "corner", 0));
}

#[test]
fn six_jittered_samples_fill_the_two_by_three_cells_of_every_pixel() {
    let s = scene_with(6, "jittered");
    let world = World::new(&s);
    for y in 0..s.settings.height {
        for x in 0..s.settings.width {
            let mut cells = Vec::new();
            for k in 0..6 {
                let (px, py) = sample_position(&world, x, y, k);
                let (u, v) = (px - x as f64, py - y as f64);
                assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v), "({x}, {y}) {k}");
                let cell = ((u * 2.0) as u32, (v * 3.0) as u32);
                assert_eq!(cell, (k % 2, k / 2), "pixel ({x}, {y}) sample {k} at ({px}, {py})");
                cells.push(cell);
            }
            cells.sort();
            cells.dedup();
            assert_eq!(cells.len(), 6, "pixel ({x}, {y})");
        }
    }
}

#[test]
fn square_counts_place_samples_as_x_plus_k_mod_n_plus_jitter_over_n() {
    // The jitter of sample k: the two numbers at words 4k .. 4k + 4 of the pixel's stream
    // (seed, purpose 1, y W + x). Divided by n here, multiplied by 2^-m in the renderer for
    // n = 2^m: the same bits.
    for n in [2u32, 3, 4] {
        let jittered = scene_with(n * n, "jittered");
        let regular = scene_with(n * n, "regular");
        let (w, seed) = (jittered.settings.width, jittered.settings.seed);
        let (jittered, regular) = (World::new(&jittered), World::new(&regular));
        for (x, y) in [(0, 0), (1, 2), (11, 8)] {
            for k in 0..n * n {
                let (col, row) = (f64::from(k % n), f64::from(k / n));
                let side = f64::from(n);
                let mut stream =
                    ShortStream::new(seed, Purpose::PixelJitter, u64::from(y * w + x)).skip_words(4 * u128::from(k));
                let (jx, jy) = (stream.next_f64(), stream.next_f64());
                let (x0, y0) = (f64::from(x), f64::from(y));
                let expected = (x0 + (col + jx) / side, y0 + (row + jy) / side);
                let got = sample_position(&jittered, x, y, k);
                assert_eq!(got.0.to_bits(), expected.0.to_bits(), "n {n} ({x}, {y}) {k}");
                assert_eq!(got.1.to_bits(), expected.1.to_bits(), "n {n} ({x}, {y}) {k}");
                let expected = (x0 + (col + 0.5) / side, y0 + (row + 0.5) / side);
                assert_eq!(sample_position(&regular, x, y, k), expected, "n {n} ({x}, {y}) {k}");
            }
        }
    }
}

/// The SIMRenderer reference scene of the fixtures with the `raytracer` lines
/// `sampling {samples}` and `pixel_coordinate {pixel_coordinate}`.
fn lab_text(samples: u32, pixel_coordinate: &str) -> String {
    let text = fs::read_to_string(repo("tests/fixtures/simrenderer/reference.txt")).unwrap();
    text.replace("sampling            1", &format!("sampling {samples}"))
        .replace(
            "pixel_coordinate    center",
            &format!("pixel_coordinate {pixel_coordinate}"),
        )
}

/// [`lab_text`] rendered at 40 x 30.
fn lab_render(samples: u32, pixel_coordinate: &str) -> Film {
    let text = lab_text(samples, pixel_coordinate);
    let mut s = simrenderer::parse(&text, "lab.txt", &Options::default()).unwrap().scene;
    assert_eq!(s.settings.samples_per_pixel, samples);
    (s.settings.width, s.settings.height) = (40, 30);
    render(&World::new(&s), &|| {}).0
}

#[test]
fn a_lab_samples_any_count_and_its_corner_samples_are_one_ray() {
    // At random, 2 and 8 samples are jittered in their 1 x 2 and 2 x 4 grids: images of
    // their own.
    let one = lab_render(1, "random");
    for samples in [2, 8] {
        let film = lab_render(samples, "random");
        assert_ne!(film.to_rgb8(), one.to_rgb8(), "{samples}");
        assert!(film.pixels.iter().all(|p| p.is_finite()), "{samples}");
    }
    // At the corner every sample is the same ray, so the same radiance v. Two are v + v =
    // 2v exactly (a doubling only moves the exponent), and 2v / 2 = v: the radiances and
    // the bytes are those of 1 sample.
    let one = lab_render(1, "top_left");
    let two = lab_render(2, "top_left");
    assert_eq!(radiance_bits(&two.pixels), radiance_bits(&one.pixels));
    assert_eq!(two.to_rgb8(), one.to_rgb8());
    // Six are summed as v, 2v, 3v, ..., 6v: from 3v on a partial sum k v may be rounded,
    // by at most EPSILON k v / 2, so 6v is off by at most (3 + 4 + 5 + 6) EPSILON v / 2 =
    // 9 EPSILON v and the mean, with its division's rounding, by 9/6 + 1/2 = 2 EPSILON v
    // (to first order; asserted within 3). The mean need not be v to the bit, so neither
    // need the bytes be equal: a channel within an ulp of a quantisation step may round
    // the other way.
    let six = lab_render(6, "top_left");
    for (mean, v) in six.pixels.iter().zip(&one.pixels) {
        for (m, v) in mean.to_array().into_iter().zip(v.to_array()) {
            assert!((m - v).abs() <= 3.0 * f64::EPSILON * v.abs(), "{m} against {v}");
        }
    }
}

#[test]
fn a_lab_with_sampling_2_renders_on_the_command_line() {
    let dir = temp_dir("sampling-lab");
    let lab = dir.join("lab.txt");
    fs::write(&lab, lab_text(2, "random")).unwrap();
    let out = dir.join("lab.png");
    let o = lumiere(&[
        "render",
        lab.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "16",
        "--height",
        "12",
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.exists());
}

#[test]
fn six_jittered_samples_are_the_same_bits_for_any_thread_count_and_from_shards() {
    let s = scene_with(6, "jittered");
    let film = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| render(&World::new(&s), &|| {})).0
    };
    let one = film(1);
    assert_eq!(radiance_bits(&film(2).pixels), radiance_bits(&one.pixels));
    assert_eq!(radiance_bits(&film(3).pixels), radiance_bits(&one.pixels));
    // Against 1 sample: another image.
    let mut single = s.clone();
    single.settings.samples_per_pixel = 1;
    assert_ne!(
        radiance_bits(&render(&World::new(&single), &|| {}).0.pixels),
        radiance_bits(&one.pixels)
    );
    // The binary's whole render and its three shards merged: the same bytes.
    let dir = temp_dir("sampling-shards");
    let path = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let reference = repo("scenes/reference.toml");
    let run_render = |out: &str, more: &[&str]| {
        let size = ["--width", "12", "--height", "9", "--spp", "6", "--quiet"];
        let args = [&["render", reference.to_str().unwrap(), "-o", out][..], &size, more].concat();
        let o = lumiere(&args);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    };
    run_render(&path("whole.png"), &[]);
    let shards: Vec<String> = (0..3).map(|k| path(&format!("part{k}.shard"))).collect();
    for (k, shard) in shards.iter().enumerate() {
        run_render(shard, &["--shard", &format!("{k}/3")]);
    }
    let merged = path("merged.png");
    let mut merge = vec!["merge", "-o", &merged, "--quiet"];
    merge.extend(shards.iter().map(String::as_str));
    let o = lumiere(&merge);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let rgb8 = |name: &str| load_rgb8(std::path::Path::new(&path(name))).unwrap();
    assert_eq!(rgb8("merged.png"), rgb8("whole.png"));
    assert_eq!(rgb8("whole.png"), (12, 9, one.to_rgb8()));
}
