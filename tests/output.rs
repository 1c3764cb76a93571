//! Output files as a user gets them: float radiance (PFM, EXR), sRGB PNG, split renders that
//! merge to the one-machine bytes, shard files named as such, and Ctrl-C leaving nothing
//! half-written (a render writes nothing, `figures` leaves each set wholly old or new).

use crate::common::*;
use std::fs;

fn reference() -> String {
    repo("scenes/reference.toml").to_str().unwrap().to_string()
}

const SMALL: [&str; 6] = ["--width", "64", "--height", "48", "--spp", "1"];

fn render(out: &std::path::Path, extra: &[&str]) -> std::process::Output {
    let r = reference();
    let mut args = vec!["render", r.as_str(), "-o", out.to_str().unwrap(), "--quiet"];
    args.extend_from_slice(&SMALL);
    args.extend_from_slice(extra);
    lumiere(&args)
}

#[test]
fn sharded_renders_merge_to_the_same_bytes() {
    let dir = temp_dir("shards");
    let whole = dir.join("whole.png");
    assert_eq!(render(&whole, &[]).status.code(), Some(0));
    for n in [1, 3, 7] {
        let mut parts = Vec::new();
        // Render the shards in reverse order, as a batch system might.
        for k in (0..n).rev() {
            let part = dir.join(format!("part-{k}-of-{n}.shard"));
            let spec = format!("{k}/{n}");
            assert_eq!(render(&part, &["--shard", &spec]).status.code(), Some(0));
            parts.push(part.to_str().unwrap().to_string());
        }
        let merged = dir.join(format!("merged-{n}.png"));
        let mut args = vec!["merge"];
        args.extend(parts.iter().map(String::as_str));
        args.extend(["-o", merged.to_str().unwrap()]);
        let o = lumiere(&args);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(fs::read(&merged).unwrap(), fs::read(&whole).unwrap(), "N = {n}");
    }
}

#[test]
fn shard_output_must_end_in_shard() {
    // `-o x.png --shard 0/1` would write a shard file (not a PNG) under an image's name.
    let dir = temp_dir("shardname");
    let o = render(&dir.join("x.png"), &["--shard", "0/1"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("x.png: with --shard") && err.contains("must end in .shard"),
        "{err}"
    );
    assert_eq!(fs::read_dir(&dir).unwrap().count(), 0);
    // The same render named .shard is accepted.
    assert_eq!(render(&dir.join("x.shard"), &["--shard", "0/1"]).status.code(), Some(0));
}

#[test]
fn more_shards_than_rows_are_refused() {
    // 48 rows (SMALL): 48 shards of a row each are fine, 49 would leave one without a row.
    let dir = temp_dir("shardrows");
    let out = dir.join("x.shard");
    for spec in ["0/49", "48/49", "0/65536"] {
        let o = render(&out, &["--shard", spec]);
        assert_eq!(o.status.code(), Some(2), "{spec}");
        let n = spec.split('/').nth(1).unwrap();
        assert_eq!(
            String::from_utf8_lossy(&o.stderr),
            format!(
                "lumiere: error: --shard {spec}: the image has 48 rows, fewer than its {n} shards: a shard would render \
                 no row (use at most 48 shards)\n"
            )
        );
        assert!(!out.exists());
    }
    assert_eq!(render(&out, &["--shard", "47/48"]).status.code(), Some(0));
}

#[test]
fn merge_refuses_incomplete_or_mixed_shards() {
    let dir = temp_dir("badshards");
    let a = dir.join("a.shard");
    let b = dir.join("b.shard");
    let other = dir.join("other.shard");
    render(&a, &["--shard", "0/2"]);
    render(&b, &["--shard", "1/2"]);
    render(&other, &["--shard", "1/2", "--seed", "7"]);
    let out = dir.join("m.png");
    let (sa, sb, so, o) = (
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        other.to_str().unwrap(),
        out.to_str().unwrap(),
    );
    let missing = lumiere(&["merge", sa, "-o", o]);
    assert_eq!(missing.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("shard 1/2 is missing"));
    let mixed = lumiere(&["merge", sa, so, "-o", o]);
    assert_eq!(mixed.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&mixed.stderr).contains("belongs to another render"));
    let twice = lumiere(&["merge", sa, sa, sb, "-o", o]);
    assert!(String::from_utf8_lossy(&twice.stderr).contains("given twice"));
    let not_shard = lumiere(&["merge", reference().as_str(), "-o", o]);
    assert!(String::from_utf8_lossy(&not_shard.stderr).contains("not a lumiere shard file"));
    assert!(!out.exists());
}

#[test]
fn float_outputs_hold_the_unclamped_radiance() {
    let dir = temp_dir("float");
    let (png, pfm, exr) = (dir.join("a.png"), dir.join("a.pfm"), dir.join("a.exr"));
    for p in [&png, &pfm, &exr] {
        assert_eq!(render(p, &[]).status.code(), Some(0));
    }
    let png = image::open(&png).unwrap().to_rgb8();
    let exr = image::open(&exr).unwrap().to_rgb32f();
    let pfm = fs::read(&pfm).unwrap();
    let header = b"PF\n64 48\n-1.0\n";
    assert_eq!(&pfm[..header.len()], header);
    assert_eq!(pfm.len(), header.len() + 64 * 48 * 12);
    // The transparent spheres' local term plus the refracted light exceeds 1 somewhere.
    assert!(exr.pixels().any(|p| p.0.iter().any(|&c| c > 1.0)));
    for (x, y) in [(5, 40), (32, 24), (50, 10)] {
        let f = exr.get_pixel(x, y).0;
        // PFM rows run bottom to top.
        let at = header.len() + ((47 - y as usize) * 64 + x as usize) * 12;
        let g = f32::from_le_bytes(pfm[at..at + 4].try_into().unwrap());
        assert_eq!(f[0], g);
        // The PNG is the clamped, quantised radiance (f64 before the f32 conversion: +-1 level).
        let q = (f[0].clamp(0.0, 1.0) * 255.0 + 0.5).floor() as i32;
        assert!((q - png.get_pixel(x, y).0[0] as i32).abs() <= 1);
    }
}

#[test]
fn srgb_png_is_brighter_in_the_mid_tones() {
    let dir = temp_dir("srgb");
    let (lin, srgb) = (dir.join("lin.png"), dir.join("srgb.png"));
    render(&lin, &[]);
    render(&srgb, &["--srgb"]);
    let (lin, srgb) = (
        image::open(&lin).unwrap().to_rgb8(),
        image::open(&srgb).unwrap().to_rgb8(),
    );
    for (a, b) in lin.pixels().zip(srgb.pixels()) {
        for c in 0..3 {
            // sRGB encoding never darkens and keeps full white (a linear 0 may be a tiny
            // radiance that the 12.92 c segment lifts to a few levels).
            assert!(b.0[c] >= a.0[c]);
            if a.0[c] == 255 {
                assert_eq!(b.0[c], 255);
            }
        }
    }
    assert_ne!(lin.as_raw(), srgb.as_raw());
}

#[cfg(unix)]
#[test]
fn ctrl_c_leaves_no_output() {
    use std::process::{Command, Stdio};
    let dir = temp_dir("interrupt");
    let out = dir.join("big.png");
    // A render long enough to be interrupted: the prism at depth 20, full size, 16 spp.
    let child = Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args([
            "render",
            repo("scenes/prism.toml").to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .args(["--spp", "64", "--quiet"])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(700));
    // SAFETY: sending a signal to our own child process.
    unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("interrupted; no output was written"));
    assert_eq!(fs::read_dir(&dir).unwrap().count(), 0);
}

/// Every file of a figure set folder, by name.
#[cfg(unix)]
fn set_files(dir: &std::path::Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    fs::read_dir(dir)
        .unwrap()
        .map(|f| {
            let f = f.unwrap();
            (f.file_name().into_string().unwrap(), fs::read(f.path()).unwrap())
        })
        .collect()
}

#[cfg(unix)]
#[test]
fn ctrl_c_during_figures_leaves_each_set_wholly_old_or_wholly_new() {
    use std::io::BufRead;
    use std::process::{Command, Stdio};
    let out = temp_dir("figures-interrupt");
    let o = lumiere(&[
        "figures",
        "lighting",
        "mirrors",
        "--scale",
        "0.05",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let old_lighting = set_files(&out.join("lighting"));
    let old_mirrors = set_files(&out.join("mirrors"));
    // Again at 200 x 150: the lighting set takes about 0.1 s, the mirrors (13 images at
    // depth 10) about a second. Ctrl-C as soon as the lighting set is reported written lands
    // while the mirrors render.
    let mut child = Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args([
            "figures",
            "lighting",
            "mirrors",
            "--scale",
            "0.25",
            "--out",
            out.to_str().unwrap(),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = std::io::BufReader::new(child.stdout.take().unwrap()).lines();
    let first = lines.next().unwrap().unwrap();
    assert!(first.starts_with("lighting "), "{first}");
    // SAFETY: sending a signal to our own child process.
    unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(
        err.contains(
            "interrupted; figure set \"mirrors\" and the sets after it were left as they were; complete: [lighting]"
        ),
        "{err}"
    );
    // The mirrors set is the old one, byte for byte, with no stray temporary file.
    assert_eq!(set_files(&out.join("mirrors")), old_mirrors);
    // The lighting set is wholly new: same files, every one changed, and the manifest
    // describes the new images (scale, size and the pixel hash of each PNG).
    let new_lighting = set_files(&out.join("lighting"));
    assert!(new_lighting.keys().eq(old_lighting.keys()));
    assert!(new_lighting.iter().all(|(name, bytes)| old_lighting[name] != *bytes));
    let manifest: serde_json::Value = serde_json::from_slice(&new_lighting["manifest.json"]).unwrap();
    assert_eq!(manifest["scale"], 0.25);
    for entry in manifest["images"].as_array().unwrap() {
        let png = image::load_from_memory(&new_lighting[entry["file"].as_str().unwrap()])
            .unwrap()
            .to_rgb8();
        assert_eq!((png.width(), png.height()), (200, 150));
        let hash = format!("fnv1a64:{:016x}", lumiere::film::fnv1a64(png.as_raw()));
        assert_eq!(entry["pixel_hash"], hash.as_str());
    }
    // Nothing else beside the sets, the gallery and the times of the set written: no
    // temporary file left in the output folder.
    let names: Vec<_> = fs::read_dir(&out).unwrap().map(|f| f.unwrap().file_name()).collect();
    assert_eq!(names.len(), 4, "{names:?}");
    assert!(out.join("timings.json").is_file());
}
