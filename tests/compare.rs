//! `lumiere compare` (issue 25, items 1 and 2): every input format read and converted as
//! documented, sizes and unknown files refused, the metrics and the rule by hand on tiny
//! images, the JSON document, the worst pixels, FLIP against values of NVIDIA's FLIP tool,
//! object edges on scenes whose edges are known, and the PFM reader under random bytes.

use crate::common::*;
use glam::DVec3;
use image::ImageEncoder;
use lumiere::compare::pfm::decode_pfm;
use lumiere::compare::read::read_image;
use lumiere::edges::{edge_mask, is_edge, path_at, same_region};
use lumiere::film::{Film, encode_png};
use lumiere::output::{Format, encode, encode_pfm};
use lumiere::world::World;
use proptest::prelude::*;
use std::fs;
use std::path::{Path, PathBuf};

/// Runs `lumiere compare ARGS`: exit code, stdout, stderr.
fn compare(args: &[&str]) -> (i32, String, String) {
    let mut all = vec!["compare"];
    all.extend_from_slice(args);
    let o = lumiere(&all);
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// `lumiere compare ARGS --json`, parsed.
fn compare_json(args: &[&str]) -> (i32, serde_json::Value) {
    let mut all = args.to_vec();
    all.push("--json");
    let (code, out, err) = compare(&all);
    let json = serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out} {err}"));
    (code, json)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A 3 x 2 film with values above 1, below 0, and between levels. (The float files hold
/// f32: a value whose f64 lies at exactly half a level, as 0.9 x 255 = 229.5, can round to
/// the level below once stored as f32; these values do not.)
fn film() -> Film {
    let mut f = Film::new(3, 2);
    f.pixels = vec![
        DVec3::new(0.5, 2.0, -1.0),
        DVec3::new(0.1, 0.2, 0.3),
        DVec3::new(1.0, 0.0, 0.75),
        DVec3::new(0.003, 0.997, 0.5),
        DVec3::new(0.25, 0.25, 0.25),
        DVec3::new(0.875, 0.6, 0.3),
    ];
    f
}

/// Encodes RGB or RGBA pixels (8 or 16 bits) with the image crate's encoder for `format`.
fn encode_with(format: image::ImageFormat, w: u32, h: u32, bytes: &[u8], color: image::ExtendedColorType) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    match format {
        image::ImageFormat::Png => image::codecs::png::PngEncoder::new(&mut out)
            .write_image(bytes, w, h, color)
            .unwrap(),
        image::ImageFormat::Bmp => image::codecs::bmp::BmpEncoder::new(&mut out)
            .write_image(bytes, w, h, color)
            .unwrap(),
        image::ImageFormat::Tga => image::codecs::tga::TgaEncoder::new(&mut out)
            .write_image(bytes, w, h, color)
            .unwrap(),
        image::ImageFormat::Jpeg => image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, 100)
            .write_image(bytes, w, h, color)
            .unwrap(),
        _ => unreachable!(),
    }
    out.into_inner()
}

#[test]
fn every_format_reads_as_the_png_it_stands_for() {
    let dir = temp_dir("compare-formats");
    let f = film();
    let rgb = f.to_rgb8();
    // quantize: 0.5 -> 128, 2 -> 255, -1 -> 0, 0.003 -> 1, 0.997 -> 254.
    assert_eq!(&rgb[..3], &[128, 255, 0]);
    assert_eq!(&rgb[9..12], &[1, 254, 128]);
    let png = dir.join("film.png");
    fs::write(&png, encode_png(3, 2, &rgb).unwrap()).unwrap();
    let ascii = format!(
        "P3\n# a comment\n3 2\n255\n{}\n",
        rgb.iter().map(|v| v.to_string()).collect::<Vec<_>>().join(" ")
    );
    let mut binary = b"P6\n3 2\n255\n".to_vec();
    binary.extend(&rgb);
    let rgba: Vec<u8> = rgb.chunks(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect();
    // 16 bits: each level v as 257 v, which converts back to v exactly.
    let deep: Vec<u8> = rgb.iter().flat_map(|&v| (v as u16 * 257).to_ne_bytes()).collect();
    use image::ExtendedColorType::{Rgb8, Rgb16, Rgba8};
    use image::ImageFormat as F;
    let files: Vec<(&str, Vec<u8>, &str, Option<&str>)> = vec![
        ("a.ppm", ascii.into_bytes(), "PPM", None),
        ("b.ppm", binary, "PPM", None),
        (
            "c.pfm",
            encode_pfm(&f),
            "PFM",
            Some("read as float radiance, clamped to [0, 1] and quantised"),
        ),
        (
            "d.exr",
            encode(&f, Format::Exr, false).unwrap(),
            "EXR",
            Some("read as float radiance, clamped to [0, 1] and quantised"),
        ),
        ("e.bmp", encode_with(F::Bmp, 3, 2, &rgb, Rgb8), "BMP", None),
        ("f.tga", encode_with(F::Tga, 3, 2, &rgb, Rgb8), "TGA", None),
        (
            "g.png",
            encode_with(F::Png, 3, 2, &rgba, Rgba8),
            "PNG",
            Some("alpha channel dropped (every pixel opaque)"),
        ),
        (
            "h.png",
            encode_with(F::Png, 3, 2, &deep, Rgb16),
            "PNG",
            Some("16-bit input converted to 8 bits"),
        ),
    ];
    for (name, bytes, format, note) in files {
        let path = dir.join(name);
        fs::write(&path, bytes).unwrap();
        let img = read_image(&path).unwrap();
        assert_eq!((img.width, img.height, img.format), (3, 2, format), "{name}");
        assert_eq!(img.rgb, rgb, "{name}");
        match note {
            Some(n) => assert!(img.notes.iter().any(|x| x.contains(n)), "{name}: {:?}", img.notes),
            None => assert!(img.notes.is_empty(), "{name}: {:?}", img.notes),
        }
        let (code, json) = compare_json(&[s(&path), s(&png)]);
        assert_eq!((code, &json["metrics"]["max"]), (0, &0.into()), "{name}");
        assert_eq!(json["verdict"], "pass");
        if let Some(n) = note {
            let notes = json["notes"].as_array().unwrap();
            assert!(
                notes.iter().any(|x| x.as_str().unwrap().contains(n)),
                "{name}: {notes:?}"
            );
            assert!(notes[0].as_str().unwrap().starts_with(s(&path)), "{notes:?}");
        }
    }
    // JPEG is lossy: read, within a few levels, and said so.
    let jpeg = dir.join("i.jpg");
    fs::write(&jpeg, encode_with(F::Jpeg, 3, 2, &rgb, Rgb8)).unwrap();
    let (_, json) = compare_json(&[s(&jpeg), s(&png)]);
    assert!(json["notes"][0].as_str().unwrap().contains("JPEG is lossy"), "{json}");
    assert!(json["metrics"]["max"].as_u64().unwrap() < 64, "{json}");
}

#[test]
fn a_jpeg_of_the_oracle_is_said_to_differ_by_tens_of_levels() {
    // The oracle's own image saved as a JPEG at quality 90 (what a lab's ImageIO.write
    // does by default is near): the compression alone moves pixels by tens of levels along
    // the outlines, and the note says so.
    let dir = temp_dir("compare-jpeg");
    let oracle = repo("tests/fixtures/compare/oracle.png");
    let rgb = image::open(&oracle).unwrap().to_rgb8();
    let jpeg = dir.join("mine.jpg");
    let mut bytes = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, 90)
        .encode(rgb.as_raw(), rgb.width(), rgb.height(), image::ExtendedColorType::Rgb8)
        .unwrap();
    fs::write(&jpeg, bytes).unwrap();
    let (code, json) = compare_json(&[s(&jpeg), s(&oracle)]);
    assert_eq!(code, 1);
    let max = json["metrics"]["max"].as_u64().unwrap();
    assert!(max >= 20, "{json}");
    assert_eq!(
        json["notes"][0],
        format!(
            "{}: JPEG is lossy: its compression alone changes pixels, by tens of levels along outlines and where colours change; write a PNG to compare level by level",
            jpeg.display()
        )
    );
}

#[test]
fn grey_translucent_and_scaled_inputs_say_how_they_were_read() {
    let dir = temp_dir("compare-notes");
    let pgm = dir.join("grey.pgm");
    fs::write(&pgm, b"P5\n2 1\n255\n\x07\xc8").unwrap();
    let img = read_image(&pgm).unwrap();
    assert_eq!(img.rgb, [7, 7, 7, 200, 200, 200]);
    assert_eq!(img.notes, ["grey input: its level used for R, G and B"]);
    let rgba = dir.join("half.png");
    let px = [10, 20, 30, 255, 40, 50, 60, 128];
    fs::write(
        &rgba,
        encode_with(image::ImageFormat::Png, 2, 1, &px, image::ExtendedColorType::Rgba8),
    )
    .unwrap();
    let img = read_image(&rgba).unwrap();
    assert_eq!(img.rgb, [10, 20, 30, 40, 50, 60]);
    assert_eq!(
        img.notes,
        ["alpha channel dropped: 1 pixels partly transparent, their colour compared as stored (not composited)"]
    );
    // A grey PFM, big-endian, scale 2 (not applied), one NaN.
    let pfm = dir.join("grey.pfm");
    let mut b = b"Pf\n2 1\n2.0\n".to_vec();
    for v in [f32::NAN, 0.5] {
        b.extend(v.to_be_bytes());
    }
    fs::write(&pfm, b).unwrap();
    let img = read_image(&pfm).unwrap();
    assert_eq!(img.rgb, [0, 0, 0, 128, 128, 128]);
    assert_eq!(img.notes.len(), 4, "{:?}", img.notes);
    assert!(img.notes[1].starts_with("grey input (Pf)"));
    assert!(img.notes[2].starts_with("PFM scale 2: only its sign"));
    assert_eq!(
        img.notes[3],
        "1 channel values NaN or infinite: NaN read as 0, infinity clamped"
    );
}

#[test]
fn bad_inputs_are_refused_with_exit_2_and_a_clear_message() {
    let dir = temp_dir("compare-bad");
    let a = dir.join("a.png");
    let b = dir.join("b.ppm");
    fs::write(&a, encode_png(2, 1, &[0; 6]).unwrap()).unwrap();
    fs::write(&b, b"P3\n1 2\n255\n0 0 0 0 0 0\n").unwrap();
    let (code, _, err) = compare(&[s(&a), s(&b)]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "lumiere: error: the images differ in size: {} is 2 x 1, {} is 1 x 2; render the oracle's image at your image's size: `lumiere render SCENE -o oracle.png --width 2 --height 1`\n",
            a.display(),
            b.display()
        )
    );
    // The scene named: --scene's, else the one a course figure's provenance names.
    let figure = repo("figures/lighting/03-ambient-directional.png");
    let (code, _, err) = compare(&[s(&a), s(&figure)]);
    assert_eq!(code, 2);
    assert!(
        err.ends_with(
            "is 800 x 600; render the oracle's image at your image's size: `lumiere render scenes/figures/lighting/03-ambient-directional.toml -o oracle.png --width 2 --height 1`\n"
        ),
        "{err}"
    );
    let (code, _, err) = compare(&[s(&a), s(&b), "--scene", "scenes/reference.toml"]);
    assert_eq!(code, 2);
    assert!(
        err.ends_with("`lumiere render scenes/reference.toml -o oracle.png --width 2 --height 1`\n"),
        "{err}"
    );
    let text = dir.join("notes.txt");
    fs::write(&text, "not an image").unwrap();
    let (code, _, err) = compare(&[s(&a), s(&text)]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "lumiere: error: {}: not an image lumiere reads (neither its first bytes nor its extension .txt name a known format); it reads PNG, PPM / PGM / PBM (ASCII or binary), PFM, EXR, JPEG, BMP, TGA\n",
            text.display()
        )
    );
    // An empty file (a ray tracer that stopped before writing), and text named .png.
    let blank = dir.join("blank.png");
    fs::write(&blank, b"").unwrap();
    let (code, _, err) = compare(&[s(&blank), s(&a)]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "lumiere: error: {}: the file is empty (0 bytes): no image was written to it\n",
            blank.display()
        )
    );
    let named = dir.join("notes.png");
    fs::write(&named, "not an image").unwrap();
    let (code, _, err) = compare(&[s(&a), s(&named)]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "lumiere: error: {}: its extension .png names PNG, but its first bytes are not a PNG file's: not an image, or one cut short or written as something else; lumiere reads PNG, PPM / PGM / PBM (ASCII or binary), PFM, EXR, JPEG, BMP, TGA\n",
            named.display()
        )
    );
    let pfm = dir.join("cut.pfm");
    fs::write(&pfm, b"PF\n2 1\n-1.0\n\0\0\0\0").unwrap();
    let (code, _, err) = compare(&[s(&pfm), s(&a)]);
    assert_eq!(code, 2);
    assert!(
        err.contains(
            "cut.pfm: PFM pixel data: 2 x 1 pixels of 3 float(s) take 24 bytes after the header, the file has 4"
        ),
        "{err}"
    );
    // An image of no pixels, alone or against itself, is refused by name, never a panic.
    let empty = dir.join("empty.ppm");
    fs::write(&empty, b"P3\n0 0\n255\n").unwrap();
    for args in [[s(&empty), s(&empty)], [s(&a), s(&empty)]] {
        let (code, out, err) = compare(&args);
        assert_eq!(code, 2);
        assert_eq!(
            err,
            format!(
                "lumiere: error: {}: the PPM image is 0 x 0 pixels: it has no pixel to compare\n",
                empty.display()
            )
        );
        assert!(out.is_empty());
    }
    // A header claiming more pixels than lumiere renders is refused before any is decoded
    // (the IHDR of a 1 x 1 PNG set to 100000 x 100000, its checksum redone).
    let mut huge = encode_png(1, 1, &[0; 3]).unwrap();
    huge[16..24].copy_from_slice(&[100_000u32.to_be_bytes(), 100_000u32.to_be_bytes()].concat());
    let crc = crc32fast::hash(&huge[12..29]);
    huge[29..33].copy_from_slice(&crc.to_be_bytes());
    let bomb = dir.join("bomb.png");
    fs::write(&bomb, &huge).unwrap();
    let (code, out, err) = compare(&[s(&a), s(&bomb)]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "lumiere: error: {}: the PNG image is 100000 x 100000 = 10000000000 pixels: lumiere reads at most 33554432 (as many as it renders)\n",
            bomb.display()
        )
    );
    assert!(out.is_empty());
    // BMP and PPM headers alike, which their decoders refuse in their own words (a BMP side
    // past 65535, PPM sides whose bytes pass 64 bits): a BMP file and info header of
    // 100000 x 100000 pixels at 24 bits, and a PPM header with no pixel after it.
    let mut bmp = b"BM".to_vec();
    for field in [54u32, 0, 54, 40, 100_000, 100_000] {
        bmp.extend(field.to_le_bytes());
    }
    bmp.extend([1, 0, 24, 0]);
    bmp.extend([0; 24]);
    let ppm = b"P6\n4294967295 4294967295\n255\n".to_vec();
    for (name, bytes, size) in [
        ("bomb.bmp", bmp, "BMP image is 100000 x 100000 = 10000000000"),
        (
            "bomb.ppm",
            ppm,
            "PPM image is 4294967295 x 4294967295 = 18446744065119617025",
        ),
    ] {
        let bomb = dir.join(name);
        fs::write(&bomb, bytes).unwrap();
        let (code, out, err) = compare(&[s(&bomb), s(&a)]);
        assert_eq!((code, out.as_str()), (2, ""));
        assert_eq!(
            err,
            format!(
                "lumiere: error: {}: the {size} pixels: lumiere reads at most 33554432 (as many as it renders)\n",
                bomb.display()
            )
        );
    }
    // A decoder's message that ends in a line break is still one line.
    let cut = dir.join("cut.jpg");
    fs::write(&cut, b"\xff\xd8\xff\xe0\x00\x10JFIF\x00").unwrap();
    let (code, _, err) = compare(&[s(&a), s(&cut)]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "lumiere: error: {}: cannot decode the JPEG image: Format error decoding Jpeg: I/O errors Not enough bytes, expected 1 but found 0\n",
            cut.display()
        )
    );
    // Two maps into one file: refused before either is written.
    let map = dir.join("map.png");
    let again = format!("{}/./map.png", dir.display());
    let (code, out, err) = compare(&[s(&a), s(&a), "--heatmap", s(&map), "--flip-heatmap", &again]);
    assert_eq!((code, out.as_str()), (2, ""));
    assert_eq!(
        err,
        format!(
            "lumiere: error: {again}: --heatmap and --flip-heatmap name the same file: one map would replace the other\n"
        )
    );
    assert!(!map.exists());
    let missing = dir.join("missing.png");
    let (code, _, err) = compare(&[s(&missing), s(&a)]);
    assert_eq!(code, 2);
    assert!(err.contains("missing.png: cannot read the file"), "{err}");
    for (args, message) in [
        (
            vec!["--max-fraction", "1.5"],
            "invalid value '1.5' for '--max-fraction <FRACTION>': must be a finite number in [0, 1], got 1.5",
        ),
        (
            vec!["--max-flip=-0.1"],
            "invalid value '-0.1' for '--max-flip <FLIP>': must be a finite number in [0, 1], got -0.1",
        ),
        (
            vec!["--spp", "4"],
            "--spp sets the scene of --scene, which is not given",
        ),
        (vec!["--edge-map", "e.png"], "--edge-map needs --scene"),
        (vec!["--flip-heatmap", "f.jpg"], "f.jpg: --flip-heatmap must be a .png"),
    ] {
        let mut all = vec![s(&a), s(&a)];
        all.extend(args);
        let (code, _, err) = compare(&all);
        assert_eq!(code, 2, "{message}");
        assert!(err.contains(message), "{err}");
    }
}

/// Writes the 2 x 2 pair whose pixels differ by (0,0,0), (3,0,4), (0,10,0), (1,1,1).
fn two_by_two(dir: &Path) -> (String, String) {
    let (a, b) = (dir.join("a.png"), dir.join("b.png"));
    fs::write(
        &a,
        encode_png(2, 2, &[10, 20, 30, 100, 100, 100, 50, 50, 50, 0, 0, 0]).unwrap(),
    )
    .unwrap();
    fs::write(
        &b,
        encode_png(2, 2, &[10, 20, 30, 103, 100, 96, 50, 60, 50, 1, 1, 1]).unwrap(),
    )
    .unwrap();
    (s(&a).to_string(), s(&b).to_string())
}

#[test]
fn metrics_rule_and_json_by_hand() {
    let dir = temp_dir("compare-metrics");
    let (a, b) = two_by_two(&dir);
    let (code, j) = compare_json(&[&a, &b, "--tolerance", "1", "--worst", "2"]);
    assert_eq!(code, 1);
    assert_eq!((j["a"].as_str(), j["b"].as_str()), (Some(a.as_str()), Some(b.as_str())));
    assert_eq!((j["width"].as_u64(), j["height"].as_u64()), (Some(2), Some(2)));
    assert_eq!(j["verdict"], "fail");
    assert_eq!(
        j["rule"],
        serde_json::json!({"tolerance": 1, "max_fraction": 0.0, "max_flip": null, "judged": "all"})
    );
    let m = &j["metrics"];
    // Differences 0, 4, 10, 1: max 10; MSE (25 + 100 + 3) / 12; p50 the 2nd smallest (1),
    // p99 and p99.9 the 4th (10); beyond 1 level: 2 of 4.
    assert_eq!(m["pixels"], 4);
    assert_eq!(m["max"], 10);
    assert_eq!(m["rms"].as_f64().unwrap(), (128.0f64 / 12.0).sqrt());
    assert!((m["psnr_db"].as_f64().unwrap() - 37.850_516).abs() < 1e-6);
    assert_eq!(
        (m["p50"].as_u64(), m["p99"].as_u64(), m["p999"].as_u64()),
        (Some(1), Some(10), Some(10))
    );
    assert_eq!(m["beyond_tolerance"], 2);
    assert_eq!(m["fraction_beyond_tolerance"], 0.5);
    assert!(m["flip_mean"].as_f64().unwrap() > 0.0);
    assert_eq!(j["edges"], serde_json::Value::Null);
    assert_eq!(
        j["failures"],
        serde_json::json!(["2 of 4 pixels (50.0000 %) differ by more than 1 levels; allowed: 0 % (--max-fraction 0)"])
    );
    // The worst two: (0, 1) by 10 levels, then (1, 0) by 4.
    let w = j["worst"].as_array().unwrap();
    assert_eq!(w.len(), 2);
    assert_eq!(
        (&w[0]["x"], &w[0]["y"], &w[0]["difference"]),
        (&0.into(), &1.into(), &10.into())
    );
    assert_eq!(w[0]["a"], serde_json::json!([50, 50, 50]));
    assert_eq!(w[0]["b"], serde_json::json!([50, 60, 50]));
    assert_eq!(
        w[0]["probe"],
        "lumiere probe SCENE.toml --pixel 0,1 --width 2 --height 2"
    );
    assert_eq!((&w[1]["x"], &w[1]["y"]), (&1.into(), &0.into()));
    // An oracle that is a course figure's PNG names its scene, from its provenance.
    let figure = dir.join("figure.png");
    let tagged = lumiere::figures::provenance::with_text(
        &fs::read(&b).unwrap(),
        &[("Scene", "scenes/figures/lighting/03-ambient-directional.toml")],
    )
    .unwrap();
    fs::write(&figure, tagged).unwrap();
    let (_, j) = compare_json(&[&a, s(&figure), "--tolerance", "1", "--worst", "1"]);
    assert_eq!(
        j["worst"][0]["probe"],
        "lumiere probe scenes/figures/lighting/03-ambient-directional.toml --pixel 0,1 --width 2 --height 2"
    );
    // The figure given first, where yours goes: a warning, the comparison as given.
    let (code, _, err) = compare(&[s(&figure), &a, "--tolerance", "1"]);
    assert_eq!(code, 1);
    assert!(
        err.starts_with(&format!(
            "lumiere: warning: {} is a course figure (of scenes/figures/lighting/03-ambient-directional.toml) and {a} is not: the oracle's image goes second, `lumiere compare YOURS ORACLE`; below, yours is {} and the oracle {a}\n",
            s(&figure),
            s(&figure)
        )),
        "{err}"
    );
    let (_, _, err) = compare(&[&a, s(&figure), "--tolerance", "1"]);
    assert!(!err.contains("warning"), "{err}");
    // The fraction rule: half the pixels beyond 1 level pass at 0.5, fail just below.
    assert_eq!(compare(&[&a, &b, "--tolerance", "1", "--max-fraction", "0.5"]).0, 0);
    assert_eq!(compare(&[&a, &b, "--tolerance", "1", "--max-fraction", "0.49"]).0, 1);
    // Beyond 4 levels only the pixel of 10: 1 of 4.
    assert_eq!(compare(&[&a, &b, "--tolerance", "4", "--max-fraction", "0.25"]).0, 0);
    // The FLIP rule on top: a bound below the mean fails.
    let flip = m["flip_mean"].as_f64().unwrap();
    let below = format!("{}", flip * 0.99);
    let above = format!("{}", flip * 1.01);
    let (code, j) = compare_json(&[&a, &b, "--tolerance", "10", "--max-flip", &below]);
    assert_eq!((code, &j["verdict"]), (1, &"fail".into()));
    assert!(
        j["failures"][0]
            .as_str()
            .unwrap()
            .starts_with("the FLIP mean of the pixels is")
    );
    assert_eq!(compare(&[&a, &b, "--tolerance", "10", "--max-flip", &above]).0, 0);
    // Identical images: PSNR "inf", never null; nothing in the worst list.
    let (code, j) = compare_json(&[&a, &a]);
    assert_eq!((code, &j["metrics"]["psnr_db"]), (0, &"inf".into()));
    assert_eq!(j["verdict"], "pass");
    assert_eq!(j["worst"], serde_json::json!([]));
    assert_eq!(j["metrics"]["flip_mean"], 0.0);
}

/// Writes `yours` (RGBA) and `oracle` (RGB), both `w x h`, as `dir/yours.png` and
/// `dir/oracle.png`.
fn write_rgba_against_rgb(dir: &Path, w: u32, h: u32, yours: &[u8], oracle: &[u8]) -> (PathBuf, PathBuf) {
    let (a, b) = (dir.join("yours.png"), dir.join("oracle.png"));
    let rgba = encode_with(image::ImageFormat::Png, w, h, yours, image::ExtendedColorType::Rgba8);
    fs::write(&a, rgba).unwrap();
    fs::write(&b, encode_png(w, h, oracle).unwrap()).unwrap();
    (a, b)
}

#[test]
fn fully_transparent_pixels_are_left_out_as_undrawn() {
    // An 8 x 6 oracle, and yours drawn on its first 4 rows (one pixel there 9 levels off)
    // with the last 2 rows left fully transparent and black, as SIMRenderer's console mode
    // leaves a wide image: 16 pixels undrawn, 1 of the 32 drawn beyond 0 levels.
    let dir = temp_dir("compare-undrawn");
    let (w, h) = (8u32, 6u32);
    let oracle: Vec<u8> = (0..w * h).flat_map(|i| [(5 * i) as u8, 100, 200]).collect();
    let mut yours: Vec<u8> = oracle
        .chunks(3)
        .enumerate()
        .flat_map(|(i, p)| if i >= 32 { [0, 0, 0, 0] } else { [p[0], p[1], p[2], 255] })
        .collect();
    yours[4 * 9] += 9;
    let (a, b) = write_rgba_against_rgb(&dir, w, h, &yours, &oracle);
    let heat = dir.join("heat.png");
    let (code, out, err) = compare(&[s(&a), s(&b), "--heatmap", s(&heat)]);
    assert_eq!(code, 1, "{out} {err}");
    for line in [
        "undrawn            16 pixels left out",
        "alpha channel dropped (every pixel opaque or transparent black)",
        "differing pixels   1 of 32 (3.1250 %) beyond 0 levels",
        "max difference     9 levels",
        "rule               at most 0 % of the drawn pixels beyond 0 levels",
    ] {
        assert!(out.contains(line), "{line}: {out}");
    }
    assert!(
        err.contains("1 of 32 drawn pixels (3.1250 %) differ by more than 0 levels"),
        "{err}"
    );
    // The heat-map shows the drawn difference and nothing on the undrawn rows.
    let map = image::open(&heat).unwrap().to_rgb8();
    assert_ne!(map.get_pixel(1, 1).0, [0, 0, 0]);
    assert!((4..6).all(|y| (0..w).all(|x| map.get_pixel(x, y).0 == [0, 0, 0])));
    // Transparent in the oracle's place counts too; the JSON says how many.
    let (code, j) = compare_json(&[s(&b), s(&a), "--tolerance", "9"]);
    assert_eq!(
        (code, &j["undrawn"], &j["metrics"]["pixels"]),
        (0, &16.into(), &32.into())
    );
    // Opaque, the same black rows are 16 more pixels beyond the tolerance.
    let opaque: Vec<u8> = yours.chunks(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    let c = dir.join("opaque.png");
    fs::write(&c, encode_png(w, h, &opaque).unwrap()).unwrap();
    let (_, j) = compare_json(&[s(&c), s(&b)]);
    assert_eq!(
        (&j["undrawn"], &j["metrics"]["beyond_tolerance"]),
        (&0.into(), &17.into())
    );
    // Nothing drawn at all: bad input, exit 2.
    let clear = dir.join("clear.png");
    let none = vec![0u8; 4 * (w * h) as usize];
    fs::write(
        &clear,
        encode_with(image::ImageFormat::Png, w, h, &none, image::ExtendedColorType::Rgba8),
    )
    .unwrap();
    let (code, _, err) = compare(&[s(&clear), s(&b)]);
    assert_eq!(code, 2);
    assert_eq!(
        err.trim(),
        format!(
            "lumiere: error: {}: every pixel is fully transparent (alpha 0): nothing was drawn to compare",
            clear.display()
        )
    );
    // Nothing drawn but colours written (alpha 0 everywhere, the colours kept): still
    // refused, exit 2, with the hint of an ARGB image whose alpha was never set; against
    // another such image, the one hint after both names.
    let argb = dir.join("argb.png");
    let coloured: Vec<u8> = (0..w * h).flat_map(|i| [200, (3 * i) as u8, 10, 0]).collect();
    fs::write(
        &argb,
        encode_with(
            image::ImageFormat::Png,
            w,
            h,
            &coloured,
            image::ExtendedColorType::Rgba8,
        ),
    )
    .unwrap();
    let hint = "; the colours are there but alpha is 0 everywhere, as in an image written as ARGB with alpha never set (Java's BufferedImage.TYPE_INT_ARGB filled by setRGB(x, y, rgb) without 0xFF000000): write TYPE_INT_RGB, or set alpha to 255";
    let (code, _, err) = compare(&[s(&argb), s(&b)]);
    assert_eq!(code, 2);
    assert_eq!(
        err.trim(),
        format!(
            "lumiere: error: {}: every pixel is fully transparent (alpha 0): nothing was drawn to compare{hint}",
            argb.display()
        )
    );
    let (code, _, err) = compare(&[s(&clear), s(&argb)]);
    assert_eq!(code, 2);
    assert_eq!(
        err.trim(),
        format!(
            "lumiere: error: {} and {}: every pixel is fully transparent (alpha 0): nothing was drawn to compare{hint}",
            clear.display(),
            argb.display()
        )
    );
    // Each image drawn only where the other is not (transparent black where the other is
    // drawn, opaque black where the other is undrawn): both named.
    let flipped: Vec<u8> = yours.chunks(4).flat_map(|p| [0, 0, 0, 255 - p[3]]).collect();
    let other = dir.join("other-half.png");
    fs::write(
        &other,
        encode_with(image::ImageFormat::Png, w, h, &flipped, image::ExtendedColorType::Rgba8),
    )
    .unwrap();
    let (code, _, err) = compare(&[s(&a), s(&other)]);
    assert_eq!(code, 2);
    assert_eq!(
        err.trim(),
        format!(
            "lumiere: error: every pixel is undrawn (transparent black: alpha and colour 0) in {} or in {}: no pixel drawn in both to compare",
            a.display(),
            other.display()
        )
    );
}

#[test]
fn alpha_zero_pixels_with_a_colour_are_compared_as_stored() {
    // An 8 x 6 oracle and yours: rows 0-1 opaque and right; rows 2-3 at alpha 0 with a
    // colour, right on row 2 and 40 levels off in red on row 3 (alpha never set there);
    // rows 4-5 transparent black, as SIMRenderer's console mode leaves the rows it does not
    // trace. Only the 16 transparent black pixels are left out: the 8 wrong ones of row 3
    // are found, the note counts the 16 coloured pixels of alpha 0.
    let dir = temp_dir("compare-alpha-colour");
    let (w, h) = (8u32, 6u32);
    let oracle: Vec<u8> = (0..w * h).flat_map(|i| [(5 * i) as u8, 100, 200]).collect();
    let yours: Vec<u8> = oracle
        .chunks(3)
        .enumerate()
        .flat_map(|(i, p)| match i / w as usize {
            0 | 1 => [p[0], p[1], p[2], 255],
            2 => [p[0], p[1], p[2], 0],
            3 => [p[0] + 40, p[1], p[2], 0],
            _ => [0, 0, 0, 0],
        })
        .collect();
    let (a, b) = write_rgba_against_rgb(&dir, w, h, &yours, &oracle);
    let note = "alpha channel dropped: 16 pixels fully transparent (alpha 0) but not black, their colour compared as stored (drawn with alpha never set?); only transparent black pixels (alpha and colour 0) are left out as never drawn";
    let img = read_image(&a).unwrap();
    assert_eq!(img.notes, [note]);
    assert_eq!(img.undrawn.iter().filter(|&&u| u).count(), 16);
    assert_eq!(img.alpha_zero, 32);
    assert!(!img.nothing_drawn());
    let (code, out, err) = compare(&[s(&a), s(&b)]);
    assert_eq!(code, 1, "{out} {err}");
    for line in [
        format!("note               {}: {note}", a.display()),
        "undrawn            16 pixels left out: transparent black (alpha and colour 0), never drawn; the rest are compared".into(),
        "differing pixels   8 of 32 (25.0000 %) beyond 0 levels".into(),
        "max difference     40 levels".into(),
    ] {
        assert!(out.contains(&line), "{line}: {out}");
    }
    let (_, j) = compare_json(&[s(&a), s(&b), "--worst", "20"]);
    assert_eq!(
        (
            &j["undrawn"],
            &j["metrics"]["pixels"],
            &j["metrics"]["beyond_tolerance"]
        ),
        (&16.into(), &32.into(), &8.into())
    );
    let worst: Vec<(u64, u64)> = j["worst"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p["x"].as_u64().unwrap(), p["y"].as_u64().unwrap()))
        .collect();
    assert_eq!(worst, (0..8).map(|x| (x, 3)).collect::<Vec<_>>());
    // Grey with alpha: a black pixel of alpha 0 (undrawn), a grey one of alpha 0 and an
    // opaque one (both compared).
    let grey = dir.join("grey.png");
    let px = [0, 0, 90, 0, 50, 255];
    fs::write(
        &grey,
        encode_with(image::ImageFormat::Png, 3, 1, &px, image::ExtendedColorType::La8),
    )
    .unwrap();
    let img = read_image(&grey).unwrap();
    assert_eq!((&img.undrawn[..], img.alpha_zero), (&[true, false, false][..], 2));
    assert!(img.notes[1].starts_with("alpha channel dropped: 1 pixels fully transparent (alpha 0) but not black"));
    assert!(!img.nothing_drawn());
}

#[test]
fn text_output_and_heat_maps() {
    let dir = temp_dir("compare-text");
    let (a, b) = two_by_two(&dir);
    let (heat, flip) = (dir.join("heat.png"), dir.join("flip.png"));
    let (code, out, err) = compare(&[
        &a,
        &b,
        "--heatmap",
        s(&heat),
        "--flip-heatmap",
        s(&flip),
        "--worst",
        "1",
    ]);
    assert_eq!(code, 1);
    for line in [
        "size               2 x 2",
        "max difference     10 levels",
        "RMS difference     3.2660 levels",
        "PSNR               37.85 dB",
        "percentiles        p50 1 / p99 10 / p99.9 10 levels",
        "differing pixels   3 of 4 (75.0000 %) beyond 0 levels",
        "rule               at most 0 % of all pixels beyond 0 levels",
        "verdict            fail",
    ] {
        assert!(out.lines().any(|l| l == line), "{line}\n{out}");
    }
    assert!(
        out.contains("lumiere probe SCENE.toml --pixel 0,1 --width 2 --height 2"),
        "{out}"
    );
    // A failed comparison says what to run next.
    let next = format!(
        "next               `lumiere diagnose SCENE.toml {a}` names what is most likely wrong; each probe line below prints the oracle's ray tree at a pixel, to hold against your code's"
    );
    assert!(out.lines().any(|l| l == next), "{out}");
    assert_eq!(
        err,
        "lumiere: error: 3 of 4 pixels (75.0000 %) differ by more than 0 levels; allowed: 0 % (--max-fraction 0)\n"
    );
    // With --scene and the oracle's settings, the diagnose line takes them; without worst
    // pixels listed, it stands alone.
    let scene = repo("scenes/reference.toml");
    let srgb = repo("tests/fixtures/compare/srgb.png");
    let oracle = repo("tests/fixtures/compare/oracle.png");
    let (code, out, _) = compare(&[
        s(&srgb),
        s(&oracle),
        "--scene",
        s(&scene),
        "--spp",
        "1",
        "--seed",
        "7",
        "--worst",
        "0",
    ]);
    assert_eq!(code, 1);
    let next = format!(
        "next               `lumiere diagnose {} {} --spp 1 --seed 7` names what is most likely wrong",
        scene.display(),
        srgb.display()
    );
    assert!(out.lines().any(|l| l == next), "{out}");
    // A comparison that passes has no next step.
    let (code, out, _) = compare(&[&a, &a]);
    assert_eq!(code, 0);
    assert!(!out.contains("next "), "{out}");
    // Heat-maps: black where equal; FLIP's magma black at 0 too.
    let heat = image::open(&heat).unwrap().to_rgb8();
    assert_eq!(heat.get_pixel(0, 0).0, [0, 0, 0]);
    assert_ne!(heat.get_pixel(0, 1).0, [0, 0, 0]);
    let flip = image::open(&flip).unwrap().to_rgb8();
    assert_eq!(flip.dimensions(), (2, 2));
    assert_ne!(flip.get_pixel(0, 1).0, flip.get_pixel(0, 0).0);
}

/// FLIP against NVIDIA's FLIP tool: the fixtures are the reference scene at 96 x 72, 1
/// sample per pixel, seed 42 (`oracle.png`), seed 7 (`seed7.png`) and with the sRGB
/// transfer applied (`srgb.png`). The expected values were computed by NVIDIA's
/// `flip-evaluator` 1.7 (its Python package, which runs its C++ code; LDR, default 67.02
/// pixels per degree, the oracle as reference): the mean of its per-pixel map summed in
/// double precision (the tool itself prints 0.055014 and 0.564855), the largest value and
/// two pixels' values.
#[test]
fn flip_matches_nvidias_tool_on_the_fixtures() {
    let read = |name: &str| read_image(&repo(&format!("tests/fixtures/compare/{name}"))).unwrap();
    let oracle = read("oracle.png");
    let cases = [
        (
            "seed7.png",
            0.055_014_513,
            0.530_905_604,
            (57, 30),
            0.136_686_429,
            0.001_333_001_54,
        ),
        (
            "srgb.png",
            0.564_855_529,
            0.862_733_662,
            (30, 15),
            0.595_236_659,
            0.586_030_364,
        ),
    ];
    for (name, mean, max, (mx, my), at_40_30, at_10_5) in cases {
        let test = read(name);
        let map = lumiere::compare::flip::flip_map(&oracle.rgb, &test.rgb, 96, 72);
        let at = |x: usize, y: usize| map[y * 96 + x] as f64;
        let m = map.iter().map(|&v| v as f64).sum::<f64>() / map.len() as f64;
        assert!((m - mean).abs() < 1e-8, "{name}: mean {m}");
        let largest = map.iter().cloned().fold(0.0f32, f32::max) as f64;
        assert!((largest - max).abs() < 1e-8, "{name}: max {largest}");
        assert_eq!(at(mx, my), largest, "{name}");
        assert!((at(40, 30) - at_40_30).abs() < 1e-8, "{name}: {}", at(40, 30));
        assert!((at(10, 5) - at_10_5).abs() < 1e-8, "{name}: {}", at(10, 5));
    }
}

/// A box seen face-on: its front face spans pixels 15.42 ..= 24.58 across and down in a
/// 40 x 30 image (half-width 1 at distance 9, `tan(20 deg) = 0.36397` for 15 pixels:
/// `1 / 9 / 0.36397 x 15 = 4.579` pixels from the center 20, 15).
const BOX: &str = r#"[image]
width = 40
height = 30
samples_per_pixel = 4
seed = 1

[camera]
position = [0, -10, 0]
look_at = [0, 0, 0]
up = [0, 0, 1]
vfov = 40

[materials.grey]
color = [0.8, 0.8, 0.8]

[[shapes]]
type = "box"
center = [0, 0, 0]
size = [2, 2, 2]
material = "grey"

[[lights]]
type = "directional"
direction = [1, 1, -1]
color = [1, 1, 1]
"#;

fn scene_file(dir: &Path, text: &str) -> std::path::PathBuf {
    let path = dir.join("scene.toml");
    fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_box_face_on_has_its_outline_as_edges() {
    let dir = temp_dir("compare-box");
    let scene = lumiere::scene::load(&scene_file(&dir, BOX)).unwrap();
    let world = World::new(&scene);
    let mask = edge_mask(&world);
    let edges: Vec<(u32, u32)> = (0..30u32)
        .flat_map(|y| (0..40u32).map(move |x| (x, y)))
        .filter(|&(x, y)| mask[(y * 40 + x) as usize])
        .collect();
    // The outline: rows 10 and 19 from column 15 to 24, columns 15 and 24 between.
    let outline = |(x, y): (u32, u32)| {
        ((y == 10 || y == 19) && (15..=24).contains(&x)) || ((x == 15 || x == 24) && (10..=19).contains(&y))
    };
    assert_eq!(edges.len(), 36, "{edges:?}");
    assert!(edges.iter().all(|&p| outline(p)), "{edges:?}");
    assert!(!is_edge(&world, 20, 15) && !is_edge(&world, 0, 0));
}

/// A floor under a box lit from straight above: the box's shadow on the floor has edges,
/// found by a fine scan of the image (every change of region between two points a twentieth
/// of a pixel apart on a grid column is inside an edge pixel), and a scene without shadows
/// has none of them.
#[test]
fn shadow_edges_are_edges() {
    let dir = temp_dir("compare-shadow");
    let text = BOX
        .replace("position = [0, -10, 0]", "position = [0, -10, 6]")
        .replace("look_at = [0, 0, 0]", "look_at = [0, 0, -1]")
        .replace("center = [0, 0, 0]", "center = [0, 0, 1.5]")
        .replace("direction = [1, 1, -1]", "direction = [0.3, 0, -1]")
        + "\n[[shapes]]\ntype = \"plane\"\npoint = [0, 0, -1]\nnormal = [0, 0, 1]\nmaterial = \"grey\"\n";
    let scene = lumiere::scene::load(&scene_file(&dir, &text)).unwrap();
    let world = World::new(&scene);
    let mask = edge_mask(&world);
    let mut shadow_changes = 0;
    for column in [8u32, 17, 20, 31] {
        let px = column as f64 + 1.0 / 3.0;
        let mut last = path_at(&world, px, 0.0);
        for step in 1..=30 * 20 {
            let py = step as f64 / 20.0;
            let path = path_at(&world, px, py);
            if !same_region(&last, &path) {
                let row = ((py - 0.025).floor() as u32).min(29);
                assert!(mask[(row * 40 + column) as usize], "({column}, {row}) at y {py}");
                // A change on the floor alone is a shadow's edge.
                if last[0].object == Some(1) && path[0].object == Some(1) {
                    shadow_changes += 1;
                }
            }
            last = path;
        }
    }
    assert!(shadow_changes >= 2, "{shadow_changes}");
    let no_shadows = lumiere::scene::load(&scene_file(
        &dir,
        &text.replacen("[[shapes]]", "[render]\nshadows = false\n\n[[shapes]]", 1),
    ))
    .unwrap();
    let unshadowed = edge_mask(&World::new(&no_shadows));
    let count = |m: &[bool]| m.iter().filter(|&&e| e).count();
    assert!(
        count(&unshadowed) < count(&mask),
        "{} {}",
        count(&unshadowed),
        count(&mask)
    );
}

/// Two cases at 160 x 120 and 1 sample per pixel: another seed (a sampling
/// difference) against the sRGB transfer applied (a real bug). Beyond 16 levels off edges,
/// the seed's image stays under 1 % of pixels and the bug's exceeds 80 %; FLIP's means are
/// far apart; and the seed's largest difference off edges is well under its largest on
/// them. (At this small size a pixel spans more of each shading gradient than at 800 x 600,
/// where 8 levels separate them: README, "Comparing your image with the oracle".)
#[test]
fn edges_and_flip_separate_a_sampling_difference_from_a_bug() {
    let dir = temp_dir("compare-issue");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "render",
            "scenes/reference.toml",
            "-o",
            s(&out),
            "--width",
            "160",
            "--height",
            "120",
            "--spp",
            "1",
            "-q",
        ];
        args.extend_from_slice(extra);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_lumiere"))
            .args(&args)
            .current_dir(repo(""))
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(0));
        out
    };
    let oracle = render("oracle.png", &[]);
    let seed = render("seed.png", &["--seed", "7"]);
    let srgb = render("srgb.png", &["--srgb"]);
    let scene = repo("scenes/reference.toml");
    let rule = [
        "--scene",
        s(&scene),
        "--spp",
        "1",
        "--tolerance",
        "16",
        "--max-fraction",
        "0.01",
    ];
    let run = |mine: &Path| {
        let mut args = vec![s(mine), s(&oracle)];
        args.extend_from_slice(&rule);
        compare_json(&args)
    };
    let (code, seed) = run(&seed);
    assert_eq!((code, &seed["verdict"]), (0, &"pass".into()), "{seed}");
    let (code, bug) = run(&srgb);
    assert_eq!((code, &bug["verdict"]), (1, &"fail".into()));
    assert_eq!(seed["rule"]["judged"], "off-edges");
    let off = |j: &serde_json::Value, key: &str| j["edges"]["off_edges"][key].as_f64().unwrap();
    let on = |j: &serde_json::Value, key: &str| j["edges"]["on_edges"][key].as_f64().unwrap();
    assert!(off(&seed, "fraction_beyond_tolerance") < 0.01);
    assert!(off(&bug, "fraction_beyond_tolerance") > 0.8, "{bug}");
    assert!(off(&seed, "max") < on(&seed, "max"), "{seed}");
    assert!(off(&seed, "flip_mean") < 0.05 && off(&bug, "flip_mean") > 0.3);
    assert!(seed["edges"]["pixels"].as_u64().unwrap() > 0);
    let probe = seed["worst"][0]["probe"].as_str().unwrap();
    assert!(probe.ends_with("--width 160 --height 120 --spp 1"), "{probe}");
    assert!(probe.starts_with(&format!("lumiere probe {} --pixel ", scene.display())));
    // A scene size that is not the images' is refused.
    let (code, _, err) = compare(&[s(&oracle), s(&oracle), "--scene", s(&scene), "--width", "80"]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "lumiere: error: --width 80: {} and {} are 160 x 120; the scene is loaded at the images' size\n",
            oracle.display(),
            oracle.display()
        )
    );
}

proptest! {
    /// Random bytes behind a PFM magic, and valid files cut or with bytes changed: an image
    /// or an error, never a panic; a valid file's image has its header's size.
    #[test]
    fn pfm_reader_never_panics(
        magic in prop::sample::select(vec!["PF", "Pf", "PF\n", "Pf ", "PF\n3 2\n", "PF\n2 1\n-1.0\n"]),
        tail in prop::collection::vec(any::<u8>(), 0..64),
        w in 1u32..5, h in 1u32..5, cut in 0usize..200, flip_at in 0usize..200, flip_to in any::<u8>(),
    ) {
        let _ = decode_pfm(&[magic.as_bytes(), &tail].concat());
        let mut f = Film::new(w, h);
        f.pixels.iter_mut().enumerate().for_each(|(i, p)| *p = DVec3::splat(i as f64 / 7.0));
        let good = encode_pfm(&f);
        let p = decode_pfm(&good).unwrap();
        prop_assert_eq!((p.width, p.height, p.rgb.len()), (w, h, (3 * w * h) as usize));
        let _ = decode_pfm(&good[..cut.min(good.len())]);
        let mut bad = good.clone();
        let i = flip_at % bad.len();
        bad[i] = flip_to;
        if let Ok(p) = decode_pfm(&bad) {
            prop_assert_eq!(p.rgb.len(), 3 * p.width as usize * p.height as usize);
        }
    }
}

#[test]
fn a_scene_given_as_an_image_or_an_image_as_the_scene_is_named_so() {
    // A student's first try: the scene file where the oracle's image goes, and an image
    // given to --scene. Each is named for what it is, with the order the command takes.
    let oracle = repo("tests/fixtures/compare/oracle.png");
    for scene in [
        repo("scenes/reference.toml"),
        repo("tests/fixtures/simrenderer/reference.txt"),
    ] {
        let (code, out, err) = compare(&[s(&oracle), s(&scene)]);
        assert_eq!((code, out.as_str()), (2, ""));
        assert_eq!(
            err,
            format!(
                "lumiere: error: {0}: is a scene file, not an image: compare takes two images, yours then the oracle's (`lumiere compare YOURS ORACLE`); `lumiere render {0} -o oracle.png --width W --height H` renders the oracle's at your image's size\n",
                scene.display()
            )
        );
    }
    let (code, out, err) = compare(&[s(&oracle), s(&oracle), "--scene", s(&oracle)]);
    assert_eq!((code, out.as_str()), (2, ""));
    assert_eq!(
        err,
        format!(
            "lumiere: error: {}: is a PNG image, not a scene file (TOML or SIMRenderer's format): --scene names the scene the images render (`lumiere compare YOURS ORACLE --scene SCENE`)\n",
            oracle.display()
        )
    );
}

#[test]
fn a_file_cut_short_is_named_so() {
    // The oracle's image written by a program that stopped half-way: each format that
    // reports the missing bytes is refused as cut short, naming its size; a JPEG, whose
    // decoder draws the missing rows grey without an error, is compared with a note saying
    // the file lacks its end marker.
    let dir = temp_dir("compare-cut");
    let oracle = repo("tests/fixtures/compare/oracle.png");
    let image = image::open(&oracle).unwrap();
    for (format, extension) in [
        (image::ImageFormat::Png, "png"),
        (image::ImageFormat::Bmp, "bmp"),
        (image::ImageFormat::Tga, "tga"),
        (image::ImageFormat::Pnm, "ppm"),
    ] {
        let mut bytes = std::io::Cursor::new(Vec::new());
        image.write_to(&mut bytes, format).unwrap();
        let bytes = bytes.into_inner();
        let cut = dir.join(format!("cut.{extension}"));
        fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
        let (code, out, err) = compare(&[s(&cut), s(&oracle)]);
        assert_eq!((code, out.as_str()), (2, ""), "{extension}");
        assert_eq!(
            err,
            format!(
                "lumiere: error: {}: cannot decode the {} image: the file ends before its 96 x 72 pixels do, after {} bytes: it was cut short, as by a write that stopped or a copy not finished; write it again\n",
                cut.display(),
                if extension == "ppm" {
                    "PPM".to_string()
                } else {
                    extension.to_uppercase()
                },
                bytes.len() / 2
            )
        );
    }
    let mut jpeg = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 95)
        .encode(image.to_rgb8().as_raw(), 96, 72, image::ExtendedColorType::Rgb8)
        .unwrap();
    let (whole, cut) = (dir.join("whole.jpg"), dir.join("cut.jpg"));
    fs::write(&whole, &jpeg).unwrap();
    fs::write(&cut, &jpeg[..jpeg.len() / 2]).unwrap();
    let marker = "the file does not end with JPEG's end-of-image marker (FF D9): it looks cut short, as by a write that stopped, and the rows it lacks are decoded grey; write it again";
    let (_, json) = compare_json(&[s(&cut), s(&oracle)]);
    assert_eq!(json["notes"][1], format!("{}: {marker}", cut.display()), "{json}");
    let (_, json) = compare_json(&[s(&whole), s(&oracle)]);
    assert_eq!(json["notes"].as_array().unwrap().len(), 1, "{json}");
}

/// A PNG of `width` x 1 pixels of indexed colour (8 bits a pixel) with `palette` (RGB
/// triples) and the pixels' `indices`, written chunk by chunk (its pixels in a stored,
/// uncompressed deflate block).
fn indexed_png(palette: &[[u8; 3]], indices: &[u8]) -> Vec<u8> {
    let chunk = |kind: &[u8], data: &[u8]| {
        let mut c = (data.len() as u32).to_be_bytes().to_vec();
        let body = [kind, data].concat();
        c.extend(&body);
        c.extend(crc32fast::hash(&body).to_be_bytes());
        c
    };
    let mut ihdr = (indices.len() as u32).to_be_bytes().to_vec();
    ihdr.extend(1u32.to_be_bytes());
    ihdr.extend([8, 3, 0, 0, 0]);
    let row = [&[0u8][..], indices].concat();
    let (mut a, mut b) = (1u32, 0u32);
    for &x in &row {
        a = (a + x as u32) % 65521;
        b = (b + a) % 65521;
    }
    let len = row.len() as u16;
    let mut zlib = vec![0x78, 0x01, 0x01];
    zlib.extend(len.to_le_bytes());
    zlib.extend((!len).to_le_bytes());
    zlib.extend(&row);
    zlib.extend(((b << 16) | a).to_be_bytes());
    [
        b"\x89PNG\r\n\x1a\n".to_vec(),
        chunk(b"IHDR", &ihdr),
        chunk(b"PLTE", palette.concat().as_slice()),
        chunk(b"IDAT", &zlib),
        chunk(b"IEND", &[]),
    ]
    .concat()
}

#[test]
fn an_indexed_png_is_read_as_its_palette_and_noted() {
    // An image saved with a palette (GIMP's "indexed", a converter's 256 colours): read
    // as its palette's colours, with a note, as every conversion is.
    let dir = temp_dir("compare-indexed");
    let indexed = dir.join("indexed.png");
    fs::write(&indexed, indexed_png(&[[10, 20, 30], [200, 100, 0]], &[1, 0, 1])).unwrap();
    let rgb = dir.join("rgb.png");
    fs::write(&rgb, encode_png(3, 1, &[200, 100, 0, 10, 20, 30, 200, 100, 0]).unwrap()).unwrap();
    let (code, json) = compare_json(&[s(&indexed), s(&rgb)]);
    assert_eq!(code, 0, "{json}");
    assert_eq!(json["metrics"]["max"], 0);
    assert_eq!(
        json["notes"],
        serde_json::json!([format!(
            "{}: indexed colour (a palette of at most 256 colours): each pixel read as its palette entry's colour; an image saved so has lost the shades its palette lacks, write it as RGB",
            indexed.display()
        )])
    );
    // An RGB PNG has no such note.
    let (_, json) = compare_json(&[s(&rgb), s(&rgb)]);
    assert_eq!(json["notes"], serde_json::json!([]));
}

/// Runs `lumiere ARGS` in the folder `cwd`: exit code, stdout, stderr.
fn lumiere_in(cwd: &Path, args: &[&str]) -> (i32, String, String) {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("lumiere runs");
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// The words of a command line as a POSIX shell splits it (blanks, single quotes and the
/// `'\''` of a quote inside them), without the leading `lumiere`.
fn words(line: &str) -> Vec<String> {
    let (mut words, mut word, mut quoted, mut any) = (Vec::new(), String::new(), false, false);
    let mut chars = line.chars();
    while let Some(c) = chars.next() {
        match c {
            '\'' => (quoted, any) = (!quoted, true),
            '\\' if !quoted => word.extend(chars.next()),
            ' ' if !quoted => {
                if any || !word.is_empty() {
                    words.push(std::mem::take(&mut word));
                }
                any = false;
            }
            c => word.push(c),
        }
    }
    if any || !word.is_empty() {
        words.push(word);
    }
    assert_eq!(words.first().map(String::as_str), Some("lumiere"), "{line}");
    words.split_off(1)
}

/// Runs a printed command line in `cwd`, which must succeed; its stdout.
fn run_line_in(cwd: &Path, line: &str) -> String {
    let words = words(line);
    let args: Vec<&str> = words.iter().map(String::as_str).collect();
    let (code, out, err) = lumiere_in(cwd, &args);
    assert_eq!(code, 0, "`{line}` in {}: {err}", cwd.display());
    out
}

#[test]
fn printed_command_lines_hold_from_the_working_folder() {
    // A course figure names its scene by its path from the repository's root. Compared
    // from another folder, the probe, diagnose and render lines name the scene by a path
    // that holds from there: found above the image, or above the working folder; a copy of
    // the figure out of the repository names a placeholder and says why.
    let dir = temp_dir("compare-lines");
    let figure = repo("figures/lighting/03-ambient-directional.png");
    let scene = repo("scenes/figures/lighting/03-ambient-directional.toml")
        .canonicalize()
        .unwrap();
    let (w, h, mut rgb) = lumiere::compare::load_rgb8(&figure).unwrap();
    let i = 3 * (20 * w as usize + 10);
    rgb[i] = rgb[i].wrapping_add(50);
    let yours = dir.join("yours.png");
    fs::write(&yours, encode_png(w, h, &rgb).unwrap()).unwrap();
    let copy = dir.join("copy.png");
    fs::copy(&figure, &copy).unwrap();
    let probe_of = |cwd: &Path, oracle: &Path| {
        let (code, out, err) = lumiere_in(cwd, &["compare", s(&yours), s(oracle), "--worst", "1", "--json"]);
        assert_eq!(code, 1, "{err}");
        let j: serde_json::Value = serde_json::from_str(&out).unwrap();
        (j["worst"][0]["probe"].as_str().unwrap().to_string(), j["notes"].clone())
    };
    let tail = "--pixel 10,20 --width 800 --height 600";

    // Below the repository's root, the figure by its path from there: `../../scenes/...`.
    let lighting = repo("figures/lighting");
    let (probe, _) = probe_of(&lighting, Path::new("03-ambient-directional.png"));
    assert_eq!(
        probe,
        format!("lumiere probe ../../scenes/figures/lighting/03-ambient-directional.toml {tail}")
    );
    let out = run_line_in(&lighting, &probe);
    assert!(
        out.starts_with("scene ../../scenes/figures/lighting/03-ambient-directional.toml\npixel (10, 20) of 800 x 600"),
        "{out}"
    );
    // A copy of the figure, from a folder of the repository: found above the working folder.
    let src = repo("src");
    let (probe, _) = probe_of(&src, &copy);
    assert_eq!(
        probe,
        format!("lumiere probe ../scenes/figures/lighting/03-ambient-directional.toml {tail}")
    );
    run_line_in(&src, &probe);
    // Out of the repository, the figure in it: found above the image, a path that holds
    // from the working folder (the probe line, and the text's diagnose line).
    let (probe, notes) = probe_of(&dir, &figure);
    assert_eq!(notes, serde_json::json!([]));
    let path = words(&probe)[1].clone();
    assert_eq!(dir.join(&path).canonicalize().unwrap(), scene);
    assert_eq!(probe, format!("lumiere probe {path} {tail}"));
    run_line_in(&dir, &probe);
    let (_, out, _) = lumiere_in(&dir, &["compare", "yours.png", s(&figure), "--worst", "1"]);
    assert!(
        out.contains(&format!("next               `lumiere diagnose {path} yours.png` names")),
        "{out}"
    );
    // Images of two sizes: the render line makes the oracle's image at yours, from here.
    let small = dir.join("small.png");
    fs::write(&small, encode_png(2, 1, &[0; 6]).unwrap()).unwrap();
    let (code, _, err) = lumiere_in(&dir, &["compare", "small.png", s(&figure)]);
    assert_eq!(code, 2);
    let render = err.split('`').nth(1).unwrap();
    assert_eq!(
        render,
        format!("lumiere render {path} -o oracle.png --width 2 --height 1")
    );
    run_line_in(&dir, render);
    assert_eq!(lumiere::compare::load_rgb8(&dir.join("oracle.png")).unwrap().0, 2);
    // The copy, out of the repository and compared from there: its scene is not found, said
    // in a note; the lines name the placeholder.
    let (probe, notes) = probe_of(&dir, &copy);
    assert_eq!(probe, format!("lumiere probe SCENE.toml {tail}"));
    assert_eq!(
        notes,
        serde_json::json!([format!(
            "{}: a course figure of scenes/figures/lighting/03-ambient-directional.toml (its path from the repository's root), which is found neither in the image's folder, the working folder nor any folder above them: the command lines name SCENE.toml in its place; give the scene's path with --scene",
            copy.display()
        )])
    );
    let (_, _, err) = lumiere_in(&dir, &["compare", "small.png", "copy.png"]);
    assert!(
        err.contains("`lumiere render SCENE -o oracle.png --width 2 --height 1` (copy.png: a course figure of scenes/figures/lighting/03-ambient-directional.toml (its path from the repository's root), which is found neither"),
        "{err}"
    );
}

#[cfg(unix)]
#[test]
fn printed_paths_with_blanks_are_quoted() {
    // A scene and images in a folder whose name holds a blank and a quote: the probe and
    // diagnose lines quote them, and the probe line runs as printed.
    let dir = temp_dir("compare-quoted");
    let folder = dir.join("my 'lab' images");
    fs::create_dir_all(&folder).unwrap();
    let scene = folder.join("ref scene.toml");
    fs::copy(repo("scenes/reference.toml"), &scene).unwrap();
    let (yours, oracle) = (folder.join("my image.png"), folder.join("oracle.png"));
    let o = lumiere(&["render", s(&scene), "-o", s(&oracle), "--width", "16", "--height", "12"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    fs::write(&yours, encode_png(16, 12, &[255; 3 * 16 * 12]).unwrap()).unwrap();
    let rel = |p: &Path| p.strip_prefix(&*dir).unwrap().to_str().unwrap().to_string();
    let (code, out, err) = lumiere_in(
        &dir,
        &[
            "compare",
            &rel(&yours),
            &rel(&oracle),
            "--scene",
            &rel(&scene),
            "--worst",
            "1",
        ],
    );
    assert_eq!(code, 1, "{err}");
    let quoted_scene = r#"'my '\''lab'\'' images/ref scene.toml'"#;
    assert!(
        out.contains(&format!(
            "next               `lumiere diagnose {quoted_scene} 'my '\\''lab'\\'' images/my image.png'` names"
        )),
        "{out}"
    );
    let probe = out.lines().last().unwrap().split("  ").last().unwrap().trim();
    assert!(
        probe.starts_with(&format!("lumiere probe {quoted_scene} --pixel ")),
        "{out}"
    );
    let text = run_line_in(&dir, probe);
    assert!(text.starts_with("scene my 'lab' images/ref scene.toml\n"), "{text}");
}
