//! The figure sets: every figure pinned as a small PNG snapshot, the committed full-size
//! figures reproduced bit for bit, and what a set writes: images with their provenance,
//! manifests that depend on their set alone, contact sheets and the gallery.

use crate::common::*;
use lumiere::figures::{self, Run, files, provenance, registry, render_figure};
use serde_json::Value;
use std::path::Path;

/// Scale of the snapshot images: 80 x 60 from the 800 x 600 figures.
const SNAPSHOT_SCALE: f64 = 0.1;

#[test]
fn every_figure_matches_its_snapshot() {
    let settings = snapshot_settings();
    let mut count = 0;
    for set in registry().unwrap() {
        for figure in set.figures {
            let name = format!("figure__{}__{}.png", set.name, figure.stem);
            let r = render_figure(figure, SNAPSHOT_SCALE);
            assert_eq!((r.image.width(), r.image.height()), (80, 60));
            let png = lumiere::film::encode_png(80, 60, r.image.as_raw()).unwrap();
            settings.bind(|| insta::assert_binary_snapshot!(name.as_str(), png));
            count += 1;
        }
    }
    // lighting 3 + directional 4 + attenuation 2 + spotlight 2 + soft-shadows 8 +
    // light-shapes 3 + mirrors 13 + prism 21 + shading 25: every figure of the course; and
    // what SIMRenderer adds for the optics labs (optique 5) and what it cannot do
    // (caustics 6).
    assert_eq!(count, 92);
}

#[test]
fn committed_lighting_set_is_reproduced_bit_for_bit() {
    // Full size, 800 x 600 with 4 samples: the PNGs, manifest and contact sheet of
    // figures/lighting. `lumiere figures --check` does the same for every set.
    assert_eq!(committed_set_mismatches("lighting"), Vec::<String>::new());
}

/// `dir/name`, parsed as JSON.
fn json_file(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn generate_writes_images_manifest_sheet_and_gallery() {
    let out = temp_dir("figures");
    let sets = registry().unwrap();
    let set = sets.iter().find(|s| s.name == "spotlight").unwrap();
    let run = Run {
        out: out.to_path_buf(),
        scale: 0.05,
        ..Run::default()
    };
    let report = figures::generate(set, &run).unwrap();
    assert_eq!(report.images, 2);
    for f in [
        "01-theta-70.png",
        "02-theta-120.png",
        "contact-sheet.png",
        "manifest.json",
    ] {
        assert!(out.join("spotlight").join(f).is_file(), "{f}");
    }
    let img = image::open(out.join("spotlight/01-theta-70.png")).unwrap();
    assert_eq!((img.width(), img.height()), (40, 30));
    let manifest = json_file(&out.join("spotlight/manifest.json"));
    assert_eq!(manifest["definition"], "scenes/figures/spotlight/set.toml");
    assert_eq!(manifest["scale"], 0.05);
    let first = &manifest["images"][0];
    assert_eq!(first["caption"], "Avec un angle d'ouverture θ = 70°");
    assert_eq!(first["scene"], "scenes/figures/spotlight/01-theta-70.toml");
    let scene_bytes = std::fs::read(repo("scenes/figures/spotlight/01-theta-70.toml")).unwrap();
    let scene_hash = format!("fnv1a64:{:016x}", lumiere::film::fnv1a64(&scene_bytes));
    assert_eq!(first["scene_hash"], scene_hash.as_str());
    assert_eq!(first["parameters"]["lights[1].angle"], 70);
    assert_eq!(first["seed"], 42);
    assert_eq!(first["samples_per_pixel"], 4);
    assert_eq!(first["conventions"], "chapter");
    assert_eq!(first["rays"]["camera"], 40 * 30 * 4);
    assert_eq!(first["family"], serde_json::json!(["02-theta-120.png"]));
    assert!(first["pixel_hash"].as_str().unwrap().starts_with("fnv1a64:"));
    assert!(first["facts"]["white_fraction"].as_f64().unwrap() < 0.01);
    for absent in ["render_seconds", "one_pass_with", "same_image_as"] {
        assert!(first.get(absent).is_none(), "{absent}");
    }
    // The PNG's provenance, in the order written.
    let png = std::fs::read(out.join("spotlight/01-theta-70.png")).unwrap();
    let command = format!("lumiere figures spotlight --scale 0.05 --out {}", out.display());
    let expected: Vec<(String, String)> = [
        ("Title", "spotlight/01-theta-70"),
        ("Software", &format!("lumiere {}", lumiere::VERSION)),
        ("Scene", "scenes/figures/spotlight/01-theta-70.toml"),
        ("Scene hash", &scene_hash),
        ("Seed", "42"),
        ("Conventions", "chapter"),
        ("Command", &command),
    ]
    .iter()
    .map(|(k, v)| (k.to_string(), v.to_string()))
    .collect();
    assert_eq!(provenance::text_chunks(&png).unwrap(), expected);
    assert_eq!(manifest["command"], command.as_str());
    figures::write_index(&out, &sets).unwrap();
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    // Only the set present in the folder.
    assert!(html.contains("id=\"spotlight\""));
    for other in sets.iter().filter(|s| s.name != "spotlight") {
        assert!(!html.contains(&format!("id=\"{}\"", other.name)), "{}", other.name);
    }
    assert!(html.contains("Avec un angle d'ouverture θ = 70°"));
    assert!(html.contains("lights[1].angle = 120"));
}

#[test]
fn attenuation_range_is_measured() {
    // Point light at (0, 0, 10) with C_quad = 0.01: the highest lit point seen is the cube's top
    // (z = 4, d = 6): A = 1 / (1 + 0.36) = 0.7353; the far floor drives the minimum to ~0.
    let set = registry()
        .unwrap()
        .into_iter()
        .find(|s| s.name == "attenuation")
        .unwrap();
    let quad = set.figures[1].clone();
    let r = render_figure(quad, 0.2);
    let scene = figures::scaled(r.figure.scene.clone(), 0.2);
    let facts = figures::facts(&r.figure, &scene, r.image.as_raw());
    let max = facts["attenuation_max"].as_f64().unwrap();
    assert!((max - 1.0 / 1.36).abs() < 1e-3, "{max}");
    assert!(facts["attenuation_min"].as_f64().unwrap() < 0.01);
    assert!(facts.get("saturation_intended").is_none());
}

#[test]
fn figures_command_rejects_bad_requests() {
    let o = lumiere(&["figures", "no-such-set", "--out", "/tmp/lumiere-nothing"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("the sets are: lighting"));
    let o = lumiere(&["figures", "--scale", "0", "--out", "/tmp/lumiere-nothing"]);
    assert_eq!(o.status.code(), Some(2));
    let o = lumiere(&["figures", "--list"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stdout).contains("01-top-depth-01.png  Récursivité : 1 (vue de haut)"));
    // Sets named: those alone; an unknown one is refused as for a render.
    let o = lumiere(&["figures", "--list", "spotlight", "attenuation"]);
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(
        String::from_utf8_lossy(&o.stdout),
        "attenuation: Source ponctuelle et atténuation\n  01-no-attenuation.png  Sans facteur d'atténuation\n  \
         02-quadratic-0p01.png  Avec facteur d'atténuation C_quad = 0.01\nspotlight: Source ponctuelle orientée (spotlight)\n  \
         01-theta-70.png  Avec un angle d'ouverture θ = 70°\n  02-theta-120.png  Avec un angle d'ouverture θ = 120°\n"
    );
    let o = lumiere(&["figures", "--list", "lightning"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr)
            .starts_with("lumiere: error: unknown figure set \"lightning\"; the sets are: lighting,")
    );
    // --list and --check do not go together.
    let o = lumiere(&["figures", "--list", "--check"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr).starts_with("error: the argument '--list' cannot be used with '--check'"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = lumiere(&["figures", "--list", "--scenes", "/tmp/lumiere-no-figure-files"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("/tmp/lumiere-no-figure-files: cannot read the folder of figure files"),
        "{err}"
    );
    assert!(!Path::new("/tmp/lumiere-nothing").exists());
    // --out naming a file, or a folder under a file: the file is named, and left as it was.
    let dir = temp_dir("figures-out-file");
    let file = dir.join("taken");
    std::fs::write(&file, "a file").unwrap();
    for out in [file.clone(), file.join("sub")] {
        let o = lumiere(&["figures", "lighting", "--out", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{}", out.display());
        assert_eq!(
            String::from_utf8_lossy(&o.stderr),
            format!("lumiere: error: --out: {} is a file, not a folder\n", file.display())
        );
    }
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "a file");
}

/// Runs `lumiere figures` with `args` in folder `cwd`, reading the repository's figure files,
/// quietly; asserts it succeeds.
fn figures_in(cwd: &Path, args: &[&str]) {
    let scenes = repo("scenes/figures");
    let mut all = vec!["figures", "--quiet", "--scenes", scenes.to_str().unwrap()];
    all.extend_from_slice(args);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(&all)
        .current_dir(cwd)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// The files of a folder (not its folders), sorted, with their bytes.
fn folder_bytes(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().is_file())
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect();
    files.sort();
    files
}

/// The names of a folder's entries, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_folder_in_the_place_of_a_file_leaves_the_set_as_it_was() {
    // The lighting set at 40 x 30, then its manifest.json replaced by a folder, then the set
    // again at 80 x 60: refused before any file is written, so the images and the contact
    // sheet stay the 40 x 30 ones.
    let dir = temp_dir("figures-folder-in-the-way");
    figures_in(&dir, &["lighting", "--scale", "0.05"]);
    let set = dir.join("figures/lighting");
    std::fs::remove_file(set.join("manifest.json")).unwrap();
    std::fs::create_dir(set.join("manifest.json")).unwrap();
    let before = folder_bytes(&set);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(["figures", "lighting", "--scale", "0.1", "--scenes"])
        .arg(repo("scenes/figures"))
        .current_dir(&*dir)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        "lumiere: error: figures/lighting/manifest.json: cannot write: a folder is in its place\n"
    );
    assert!(o.stdout.is_empty());
    assert_eq!(folder_bytes(&set), before);
    assert_eq!(
        names(&set),
        [
            "01-ambient.png",
            "02-directional.png",
            "03-ambient-directional.png",
            "contact-sheet.png",
            "manifest.json"
        ]
    );
}

#[cfg(unix)]
#[test]
fn a_full_disk_leaves_the_set_as_it_was() {
    use std::os::unix::process::CommandExt;
    // The lighting set at 40 x 30, then at 200 x 150 under a file-size limit of 20 KB, as a
    // full disk: the three images (5 to 15 KB) can be written, the contact sheet (about 41
    // KB) cannot, and the set stays the 40 x 30 one, manifest and images alike, with no
    // temporary file. Failed work: exit 1.
    let dir = temp_dir("figures-full-disk");
    figures_in(&dir, &["lighting", "--scale", "0.05"]);
    let set = dir.join("figures/lighting");
    let before = folder_bytes(&set);
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_lumiere"));
    command
        .args(["figures", "lighting", "--scale", "0.25", "--scenes"])
        .arg(repo("scenes/figures"))
        .current_dir(&*dir);
    // SAFETY: only async-signal-safe calls between fork and exec. SIGXFSZ at its default
    // action (ending the process): lumiere ignores it itself, so that a write past the
    // limit fails with EFBIG.
    unsafe {
        command.pre_exec(|| {
            libc::signal(libc::SIGXFSZ, libc::SIG_DFL);
            let limit = libc::rlimit {
                rlim_cur: 20_000,
                rlim_max: 20_000,
            };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let o = command.output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.starts_with(
            "lumiere: warning: figures/lighting holds the set at scale 0.05; this run writes it at scale 0.25\n\
             lumiere: error: figures/lighting/contact-sheet.png: cannot write: File too large"
        ),
        "{err}"
    );
    assert_eq!(folder_bytes(&set), before);
    assert_eq!(names(&set).len(), 5, "{:?}", names(&set));
}

#[test]
fn a_set_writes_the_same_bytes_alone_or_with_others() {
    // The reference scene's lightings of three sets share one pass in a run over the three,
    // and soft-shadows' N = 100 is light-shapes' sphere: a run over all five renders less,
    // yet each set's folder is byte for byte what the set alone writes.
    let (together, alone) = (temp_dir("figures-together"), temp_dir("figures-alone"));
    let sets = ["lighting", "directional", "spotlight", "soft-shadows", "light-shapes"];
    let mut args = vec!["--scale", "0.05"];
    args.extend_from_slice(&sets);
    figures_in(&together, &args);
    for set in sets {
        figures_in(&alone, &["--scale", "0.05", set]);
    }
    for set in sets {
        let (a, b) = (
            folder_bytes(&together.join("figures").join(set)),
            folder_bytes(&alone.join("figures").join(set)),
        );
        assert_eq!(a.len(), b.len(), "{set}");
        for ((name, x), (_, y)) in a.iter().zip(&b) {
            assert!(x == y, "{set}/{name} differs");
        }
    }
    let read = |dir: &Path| std::fs::read(dir.join("figures/index.html")).unwrap();
    assert_eq!(read(&together), read(&alone));
    // The gallery lists the five sets present and no other, and every image it shows is there.
    let html = String::from_utf8(read(&together)).unwrap();
    let shown: Vec<&str> = html
        .split("<img src=\"")
        .skip(1)
        .map(|s| s.split('"').next().unwrap())
        .collect();
    assert_eq!(shown.len(), 3 + 4 + 2 + 8 + 3);
    for src in &shown {
        assert!(together.join("figures").join(src).is_file(), "{src}");
    }
    for set in registry().unwrap() {
        assert_eq!(
            html.contains(&format!("id=\"{}\"", set.name)),
            sets.contains(&set.name.as_str())
        );
    }
    // Manifests name no other set's file, only figures of their own set.
    let directional = json_file(&together.join("figures/directional/manifest.json"));
    assert_eq!(
        directional["images"][1]["family"],
        serde_json::json!(["01-d-1-1--1.png", "03-d-0-1--1.png", "04-d--1-1--1.png"])
    );
    let soft = json_file(&together.join("figures/soft-shadows/manifest.json"));
    assert_eq!(soft["images"][6]["same_image_as"], "02-soft-200.png");
    assert!(soft["images"][0].get("family").is_none());
    let shapes = json_file(&together.join("figures/light-shapes/manifest.json"));
    assert!(shapes["images"][0].get("same_image_as").is_none());
    // Timings go to the run's own file, which `figures/.gitignore` keeps out of git.
    let timings = json_file(&together.join("figures/timings.json"));
    assert_eq!(timings["sets"].as_array().unwrap().len(), 5);
    assert_eq!(timings["sets"][3]["set"], "soft-shadows");
    assert!(timings["sets"][3]["seconds"].as_f64().unwrap() > 0.0);
    let ignored = std::fs::read_to_string(repo("figures/.gitignore")).unwrap();
    assert!(ignored.lines().any(|l| l == "timings.json"));
}

/// Copies `from` into `to`, folders included.
fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.path().is_dir() {
            copy_tree(&e.path(), &to.join(e.file_name()));
        } else {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

#[test]
fn regenerating_an_unchanged_set_changes_no_committed_byte() {
    // A copy of the repository's figure files and committed figures; `lumiere figures
    // lighting` run there as from the repository's root, at full size. Every committed file
    // of figures/ (the set, the others, the gallery made from all manifests) keeps its bytes.
    let root = temp_dir("figures-regenerate");
    copy_tree(&repo("scenes/figures"), &root.join("scenes/figures"));
    copy_tree(&repo("figures"), &root.join("figures"));
    let _ = std::fs::remove_file(root.join("figures/timings.json"));
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(["figures", "lighting", "--quiet"])
        .current_dir(&root)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut compared = 0;
    for set in ["", "lighting", "directional", "mirrors"] {
        for (name, bytes) in folder_bytes(&repo("figures").join(set)) {
            if name == "timings.json" {
                continue;
            }
            let regenerated = std::fs::read(root.join("figures").join(set).join(&name)).unwrap();
            assert!(regenerated == bytes, "figures/{set}/{name} changed");
            compared += 1;
        }
    }
    // index.html and .gitignore, lighting's 3 figures, sheet and manifest, and two other sets.
    assert!(compared >= 2 + 5 + 6 + 15, "{compared} files compared");
    assert!(root.join("figures/timings.json").is_file());
}

#[test]
fn a_figure_file_renders_as_any_scene_into_the_committed_figure() {
    // `lumiere render` reads a figure's scene file like any scene, and gives the committed
    // figure's pixels: the scene the manifest names can be rendered again.
    let dir = temp_dir("figure-render");
    let png = dir.join("03.png");
    let o = lumiere(&[
        "render",
        repo("scenes/figures/lighting/03-ambient-directional.toml")
            .to_str()
            .unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rendered = lumiere::compare::load_rgb8(&png).unwrap();
    assert_eq!(rendered, committed_rgb("lighting", "03-ambient-directional.png"));
    let manifest = json_file(&repo("figures/lighting/manifest.json"));
    assert_eq!(
        manifest["images"][2]["pixel_hash"],
        format!("fnv1a64:{:016x}", lumiere::film::fnv1a64(&rendered.2)).as_str()
    );
    assert_eq!(
        manifest["images"][2]["scene"],
        "scenes/figures/lighting/03-ambient-directional.toml"
    );
}

#[test]
fn committed_figures_carry_their_provenance() {
    for set in registry().unwrap() {
        for f in &set.figures {
            let png = std::fs::read(repo(&format!("figures/{}/{}.png", set.name, f.stem))).unwrap();
            let texts = provenance::text_chunks(&png).unwrap();
            let get = |k: &str| texts.iter().find(|(key, _)| key == k).map(|(_, v)| v.as_str());
            let scene = std::fs::read(repo(&f.scene_file)).unwrap();
            let hash = format!("fnv1a64:{:016x}", lumiere::film::fnv1a64(&scene));
            assert_eq!(get("Scene"), Some(f.scene_file.as_str()));
            assert_eq!(get("Scene hash"), Some(hash.as_str()), "{}", f.scene_file);
            assert_eq!(get("Seed"), Some("42"));
            assert_eq!(get("Conventions"), Some("chapter"));
            assert_eq!(get("Software"), Some(format!("lumiere {}", lumiere::VERSION).as_str()));
            assert_eq!(get("Command"), Some(format!("lumiere figures {}", set.name).as_str()));
        }
    }
}

/// The committed PNG of `set/file`, decoded.
fn committed_rgb(set: &str, file: &str) -> (u32, u32, Vec<u8>) {
    lumiere::compare::load_rgb8(&repo(&format!("figures/{set}/{file}"))).unwrap()
}

#[test]
fn no_committed_figure_is_washed_out_unless_its_manifest_says_why() {
    // Fully white pixels (255, 255, 255) counted on every committed PNG: at most 1 %, but
    // for figures whose manifest says saturation is intended (their point) or kept (and
    // why); the manifest's fact is the count of the PNG on disk.
    let (mut intended, mut kept) = (Vec::new(), Vec::new());
    let mut worst = (0.0, String::new());
    for set in registry().unwrap() {
        let manifest = json_file(&repo(&format!("figures/{}/manifest.json", set.name)));
        for image in manifest["images"].as_array().unwrap() {
            let file = image["file"].as_str().unwrap();
            let name = format!("{}/{file}", set.name);
            let (w, h, rgb) = committed_rgb(&set.name, file);
            let white = rgb.chunks(3).filter(|p| p == &[255, 255, 255]).count() as f64 / (w * h) as f64;
            let recorded = image["facts"]["white_fraction"].as_f64().unwrap();
            assert!(
                (white - recorded).abs() <= 1e-6,
                "{name}: {white} on disk, {recorded} recorded"
            );
            if image["facts"]["saturation_intended"] == true {
                intended.push(name);
            } else if image["facts"]["saturation_accepted"].is_string() {
                kept.push(name);
            } else {
                assert!(white <= 0.01, "{name}: {:.2} % fully white", white * 100.0);
                if white > worst.0 {
                    worst = (white, name);
                }
            }
        }
    }
    assert_eq!(intended, ["attenuation/01-no-attenuation.png"]);
    assert_eq!(
        kept,
        [
            "spotlight/02-theta-120.png",
            "prism/01-top-depth-01.png",
            "caustics/04-ball-lens-1e4.png"
        ]
    );
    // Those are saturated indeed (no figure is excused for nothing), and some other figure
    // has white highlights: the count sees white where there is some.
    for (set, file, at_least) in [
        ("attenuation", "01-no-attenuation.png", 0.10),
        ("spotlight", "02-theta-120.png", 0.04),
        ("prism", "01-top-depth-01.png", 0.015),
        ("caustics", "04-ball-lens-1e4.png", 0.011),
    ] {
        let (w, h, rgb) = committed_rgb(set, file);
        let white = rgb.chunks(3).filter(|p| p == &[255, 255, 255]).count() as f64;
        assert!(white > at_least * (w * h) as f64, "{set}/{file}");
    }
    assert!(worst.0 > 0.0, "no figure has a white pixel");
}

#[test]
fn the_mirrors_count_their_cone_images_on_the_committed_figures() {
    // floor(360 / opening - 1) once the depth lets every image through: 5 at 60 degrees from
    // depth 4 on, 3 at 90, 7 at 45, 11 at 30; fewer at depths 1 to 3.
    let manifest = json_file(&repo("figures/mirrors/manifest.json"));
    let counts: Vec<u64> = manifest["images"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["facts"]["cone_images"].as_u64().unwrap())
        .collect();
    assert_eq!(counts, [0, 2, 4, 5, 5, 5, 5, 5, 5, 5, 3, 7, 11]);
    for (i, image) in manifest["images"].as_array().unwrap().iter().enumerate() {
        let file = image["file"].as_str().unwrap();
        let (w, h, rgb) = committed_rgb("mirrors", file);
        let regions = lumiere::figures::measure::red_regions(&rgb, w as usize, h as usize);
        assert_eq!(regions as u64 - 1, counts[i], "{file}");
    }
}

#[test]
fn the_gallery_links_each_scene_file_and_shows_its_facts() {
    let html = std::fs::read_to_string(repo("figures/index.html")).unwrap();
    for set in registry().unwrap() {
        assert!(
            html.contains(&format!("href=\"../{}\"", set.definition)),
            "{}",
            set.definition
        );
        for f in &set.figures {
            assert!(
                html.contains(&format!("href=\"../{}\"", f.scene_file)),
                "{}",
                f.scene_file
            );
            assert!(repo(&f.scene_file).is_file());
            assert!(html.contains(&format!("src=\"{}/{}.png\"", set.name, f.stem)));
        }
    }
    assert!(html.contains("render.depth = 10; shapes[1].opening = 30"));
    assert!(html.contains("fully white pixels 11.84 %; saturation intended"));
    assert!(html.contains("cone images 11"));
    assert!(html.contains("href=\"../docs/figures.md\""));
}

#[test]
fn nothing_points_outside_the_repository() {
    // The specification the figures follow is docs/figures.md and the scene files' comments.
    fn scan(dir: &Path, found: &mut Vec<String>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                scan(&path, found);
            } else if let Ok(text) = std::fs::read_to_string(&path) {
                for word in ["FIGURES.md", "shared/"] {
                    if text.contains(word) {
                        found.push(format!("{}: {word}", path.display()));
                    }
                }
            }
        }
    }
    let mut found = Vec::new();
    for dir in ["src", "tests", "scenes", "docs", "figures", "examples", "benches"] {
        scan(&repo(dir), &mut found);
    }
    let readme = std::fs::read_to_string(repo("README.md")).unwrap();
    if readme.contains("FIGURES.md") || readme.contains("shared/") {
        found.push("README.md".into());
    }
    // This file names them to look for them.
    found.retain(|f| !f.contains("tests/figures.rs"));
    assert_eq!(found, Vec::<String>::new());
    assert!(repo("docs/figures.md").is_file());
}

#[test]
fn adding_a_figure_is_adding_a_file() {
    // A copy of the lighting set with a fourth figure: its scene file and its entry.
    let dir = temp_dir("figure-files");
    copy_tree(&repo("scenes/figures/lighting"), &dir.join("lighting"));
    std::fs::copy(
        repo("scenes/figures/directional/04-d--1-1--1.toml"),
        dir.join("lighting/04-from-the-left.toml"),
    )
    .unwrap();
    let set_toml = dir.join("lighting/set.toml");
    let mut text = std::fs::read_to_string(&set_toml).unwrap();
    text += "\n[figures.04-from-the-left]\ncaption = \"De la gauche\"\n";
    std::fs::write(&set_toml, &text).unwrap();
    let sets = files::load(&dir).unwrap();
    assert_eq!(sets.len(), 1);
    let stems: Vec<&str> = sets[0].figures.iter().map(|f| f.stem.as_str()).collect();
    assert_eq!(
        stems,
        [
            "01-ambient",
            "02-directional",
            "03-ambient-directional",
            "04-from-the-left"
        ]
    );
    assert_eq!(sets[0].figures[3].caption, "De la gauche");
    let o = lumiere(&["figures", "--list", "--scenes", dir.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("  04-from-the-left.png  De la gauche"));
}

#[test]
fn figure_files_that_do_not_go_together_are_refused() {
    let error = |change: &dyn Fn(&Path)| {
        let dir = temp_dir("figure-files-bad");
        copy_tree(&repo("scenes/figures/spotlight"), &dir.join("spotlight"));
        change(&dir.join("spotlight"));
        let message = files::load(&dir).unwrap_err().to_string();
        let o = lumiere(&["figures", "--list", "--scenes", dir.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{message}");
        assert_eq!(
            String::from_utf8_lossy(&o.stderr).trim(),
            format!("lumiere: error: {message}")
        );
        message.replace(&format!("{}/", dir.display()), "")
    };
    assert_eq!(
        error(
            &|d| std::fs::copy(d.join("01-theta-70.toml"), d.join("03-theta-90.toml"))
                .map(drop)
                .unwrap()
        ),
        "spotlight/03-theta-90.toml: no entry [figures.03-theta-90] in spotlight/set.toml gives this figure its caption"
    );
    assert_eq!(
        error(&|d| std::fs::remove_file(d.join("02-theta-120.toml")).unwrap()),
        "spotlight/set.toml:16:10: figures.02-theta-120: no scene file 02-theta-120.toml beside this file"
    );
    assert_eq!(
        error(&|d| {
            std::fs::rename(d.join("02-theta-120.toml"), d.join("03-theta-120.toml")).unwrap();
            let t = std::fs::read_to_string(d.join("set.toml")).unwrap();
            std::fs::write(d.join("set.toml"), t.replace("02-theta-120", "03-theta-120")).unwrap();
        }),
        "spotlight/set.toml:16:10: figures.03-theta-120: figures are numbered 01, 02, ... without a gap: expected number 02, got 03"
    );
    assert_eq!(
        error(&|d| {
            let t = std::fs::read_to_string(d.join("01-theta-70.toml")).unwrap();
            std::fs::write(d.join("01-theta-70.toml"), t.replace("angle = 70", "angle = 270")).unwrap();
        }),
        "spotlight/01-theta-70.toml:114:9: lights[1].angle: must be a finite number in [0, 180], got 270"
    );
}

#[test]
fn every_caption_and_title_is_drawn_with_its_own_glyphs() {
    // The contact sheets draw captions and titles with 8 x 8 glyphs, and a character the
    // font lacks as '?': each character of the course's captions and titles has its own.
    use image::{Rgb, RgbImage};
    let drawn = |c: char| {
        let mut img = RgbImage::new(8, 8);
        lumiere::text::draw_text(&mut img, 0, 0, &c.to_string(), 1, Rgb([255, 255, 255]));
        img.into_raw()
    };
    let unknown = drawn('?');
    let mut missing: Vec<String> = Vec::new();
    for set in registry().unwrap() {
        let texts = std::iter::once(set.title.clone()).chain(set.figures.iter().map(|f| f.caption.clone()));
        for text in texts {
            for c in text.chars().filter(|&c| c != '?' && drawn(c) == unknown) {
                missing.push(format!("{}: {c:?} in {text:?}", set.name));
            }
        }
    }
    assert_eq!(missing, Vec::<String>::new());
}

#[test]
fn verbose_figures_says_each_set_as_it_starts_and_ends() {
    let dir = temp_dir("figures-verbose");
    let out = dir.join("out");
    let o = lumiere(&[
        "-v",
        "figures",
        "lighting",
        "spotlight",
        "--scale",
        "0.1",
        "--threads",
        "1",
        "--scenes",
        repo("scenes/figures").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    let expected = [
        "lumiere: lighting: rendering 3 figure(s) at scale 0.1 on 1 thread(s)".to_string(),
        format!(
            "lumiere: lighting: wrote 3 image(s), its manifest and contact sheet into {}",
            out.join("lighting").display()
        ),
        "lumiere: spotlight: rendering 2 figure(s) at scale 0.1 on 1 thread(s)".to_string(),
        format!(
            "lumiere: spotlight: wrote 2 image(s), its manifest and contact sheet into {}",
            out.join("spotlight").display()
        ),
    ];
    assert_eq!(err.lines().collect::<Vec<_>>(), expected);
    // Without -v, none of these lines.
    let o = lumiere(&[
        "figures",
        "lighting",
        "--scale",
        "0.1",
        "--scenes",
        repo("scenes/figures").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    assert_eq!(String::from_utf8_lossy(&o.stderr), "");
}
