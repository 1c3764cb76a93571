//! `lumiere figures --check` holds the files on disk to a fresh render: a swapped, an
//! edited, a missing and an extra figure each fail with what differs, the differing
//! figures get a heat-map and a place on the review page, and the error says which command
//! regenerates the sets and which files and folders, no set's, are to be removed.

use crate::common::*;
use std::path::Path;

/// A freshly generated set, changed by `tamper`, then checked: exit code and stdout with
/// the folder's path replaced by `D`.
fn tampered(name: &str, tamper: impl Fn(&Path)) -> (i32, String) {
    let dir = temp_dir(name);
    generate_lighting(&dir);
    tamper(&dir.join("figures/lighting"));
    let (o, stdout) = check_lighting(&dir);
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("problems: the figures on disk differ from their sets"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    (
        o.status.code().unwrap(),
        stdout.replace(&dir.display().to_string(), "D"),
    )
}

#[test]
fn an_untouched_set_passes() {
    let dir = temp_dir("check-untouched");
    generate_lighting(&dir);
    let (o, stdout) = check_lighting(&dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(stdout, "lighting     ok (at scale 0.05, as its manifest records)\n");
    // Nothing to review, so no review folder.
    assert!(!dir.join("review").exists());
}

#[test]
fn a_swapped_figure_fails() {
    let (code, out) = tampered("check-swapped", |d| {
        std::fs::copy(d.join("02-directional.png"), d.join("01-ambient.png")).unwrap();
    });
    assert_eq!(code, 1);
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[0].starts_with("lighting/01-ambient.png: pixel hash fnv1a64:")
            && lines[0].contains(", its manifest says fnv1a64:"),
        "{out}"
    );
    assert!(
        lines[1].starts_with("lighting/01-ambient.png: ")
            && lines[1].contains(" of 1200 pixels differ from a fresh render, in x ")
            && lines[1].contains(", largest difference ")
            && lines[1].ends_with("; heat map D/review/figures/lighting/01-ambient.heat.png"),
        "{out}"
    );
    assert_eq!(
        lines[2],
        "lighting/01-ambient.png: provenance \"Title\" is \"lighting/02-directional\", a fresh render's is \"lighting/01-ambient\""
    );
    assert_eq!(
        lines[lines.len() - 2..],
        [
            "lighting     DIFFERS (at scale 0.05, as its manifest records)",
            "review page: D/review/index.html"
        ]
    );
}

#[test]
fn an_edited_figure_fails_and_is_shown_on_the_review_page() {
    let dir = temp_dir("check-edited");
    generate_lighting(&dir);
    // Pixel (3, 2) of the ambient figure gets 7 more levels of red; the provenance stays.
    let path = dir.join("figures/lighting/01-ambient.png");
    let png = std::fs::read(&path).unwrap();
    edit_png_keeping_provenance(&path, |rgb, w| {
        let at = ((2 * w + 3) * 3) as usize;
        rgb[at] = if rgb[at] > 200 { rgb[at] - 7 } else { rgb[at] + 7 };
    });
    let (o, stdout) = check_lighting(&dir);
    assert_eq!(o.status.code(), Some(1));
    let d = dir.display().to_string();
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(lines[0].starts_with("lighting/01-ambient.png: pixel hash "), "{stdout}");
    assert_eq!(
        lines[1],
        format!(
            "lighting/01-ambient.png: 1 of 1200 pixels differ from a fresh render, in x 3..3, y 2..2, largest difference 7 levels; heat map {d}/review/figures/lighting/01-ambient.heat.png"
        )
    );
    assert_eq!(
        lines[2],
        "lighting     DIFFERS (at scale 0.05, as its manifest records)"
    );
    assert_eq!(lines[3], format!("review page: {d}/review/index.html"));
    assert_eq!(lines.len(), 4);
    // The heat-map: black but the edited pixel (7 of 16 levels: between blue and red).
    let (hw, hh, heat) = lumiere::compare::load_rgb8(&dir.join("review/figures/lighting/01-ambient.heat.png")).unwrap();
    assert_eq!((hw, hh), (40, 30));
    let lit: Vec<usize> = (0..(hw * hh) as usize)
        .filter(|&i| heat[i * 3..i * 3 + 3] != [0, 0, 0])
        .collect();
    assert_eq!(lit, [(2 * 40 + 3) as usize]);
    // The sheet: on disk | fresh render | difference, each 40 x 30 enlarged 8 times.
    let (sw, sh, _) = lumiere::compare::load_rgb8(&dir.join("review/figures/lighting/01-ambient.png")).unwrap();
    assert_eq!((sw, sh), (8 + 3 * (320 + 8), 8 + 24 + 240 + 8));
    let page = std::fs::read_to_string(dir.join("review/index.html")).unwrap();
    assert!(
        page.contains("<h2>Figures that differ from a fresh render (1)</h2>"),
        "{page}"
    );
    assert!(page.contains("<img src=\"figures/lighting/01-ambient.png\""));
    assert!(page.contains("1 of 1200 pixels differ"));
    assert!(page.contains("Not reviewed yet: run <code>lumiere review-snapshots</code>"));
    assert!(page.contains(
        "<p>To accept them: regenerate the sets with the command <code>lumiere figures --check</code> ends with, \
         accept the figures' snapshots, and commit both (docs/figures.md, \"Changing a figure on purpose\"); \
         to reject them: restore the scene files.</p>"
    ));
    // Put back, the next check passes and empties the page's list.
    std::fs::write(&path, &png).unwrap();
    let (o, _) = check_lighting(&dir);
    assert_eq!(o.status.code(), Some(0));
    let page = std::fs::read_to_string(dir.join("review/index.html")).unwrap();
    assert!(page.contains("<h2>Figures that differ from a fresh render (0)</h2>"));
    assert!(!dir.join("review/figures/lighting/01-ambient.heat.png").exists());
}

#[test]
fn a_missing_figure_fails() {
    let (code, out) = tampered("check-missing", |d| {
        std::fs::remove_file(d.join("03-ambient-directional.png")).unwrap();
    });
    assert_eq!(code, 1);
    assert_eq!(
        out,
        "lighting/03-ambient-directional.png: missing\nlighting     DIFFERS (at scale 0.05, as its manifest records)\nreview page: D/review/index.html\n"
    );
}

#[test]
fn an_extra_figure_fails_and_regenerating_leaves_it_with_a_warning() {
    let dir = temp_dir("check-extra");
    generate_lighting(&dir);
    let set = dir.join("figures/lighting");
    std::fs::copy(set.join("01-ambient.png"), set.join("04-extra.png")).unwrap();
    let extra_line =
        "lighting/04-extra.png: extra file: no figure of the set makes it; remove it (regenerating the set leaves it)";
    let d = dir.display().to_string();
    let (o, stdout) = check_lighting(&dir);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        stdout,
        format!(
            "{extra_line}\nlighting     DIFFERS (at scale 0.05, as its manifest records)\nreview page: {d}/review/index.html\n"
        )
    );
    // No command is offered that would leave the check failing.
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        "lumiere: error: 1 problems: the figures on disk differ from their sets; 1 extra file(s) or folder(s) listed above, which regenerating leaves: remove them\n"
    );
    // Regenerating the set writes it whole, says the file is left, and the check still fails.
    let o = generate_lighting(&dir);
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        format!(
            "lumiere: warning: {d}/figures/lighting/04-extra.png: no figure of the set \"lighting\" makes this file; remove it (`lumiere figures --check` reports it)\n"
        )
    );
    assert!(set.join("04-extra.png").is_file());
    let (o, stdout) = check_lighting(&dir);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(stdout.lines().next(), Some(extra_line));
    // Removed, the set passes.
    std::fs::remove_file(set.join("04-extra.png")).unwrap();
    assert_eq!(check_lighting(&dir).0.status.code(), Some(0));
}

#[test]
fn an_extra_folder_and_a_missing_figure_name_both_remedies() {
    // A figure folder of the lighting set alone, so that checking every set is quick.
    let dir = temp_dir("check-extra-folder");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(scenes.join("lighting")).unwrap();
    for e in std::fs::read_dir(repo("scenes/figures/lighting")).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), scenes.join("lighting").join(e.file_name())).unwrap();
    }
    let (out, review) = (dir.join("figures"), dir.join("review"));
    let args = |more: &[&str]| -> Vec<String> {
        let mut a: Vec<String> = ["figures", "--scale", "0.05", "--out", out.to_str().unwrap()]
            .iter()
            .map(|s| s.to_string())
            .collect();
        a.extend(["--scenes".to_string(), scenes.display().to_string()]);
        a.extend(more.iter().map(|s| s.to_string()));
        a
    };
    let run = |more: &[&str]| {
        let a = args(more);
        lumiere(&a.iter().map(String::as_str).collect::<Vec<_>>())
    };
    assert_eq!(run(&["--quiet"]).status.code(), Some(0));
    std::fs::create_dir(out.join("old-set")).unwrap();
    std::fs::remove_file(out.join("lighting/02-directional.png")).unwrap();
    let o = run(&["--check", "--review", review.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("\nold-set/: extra folder: no figure set has this name; remove it (regenerating leaves it)\n"),
        "{stdout}"
    );
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        format!(
            "lumiere: error: 2 problems: the figures on disk differ from their sets (`lumiere figures lighting --scale 0.05 --out {} --scenes {}` regenerates them; a change made on purpose is accepted as docs/figures.md, \"Changing a figure on purpose\", says); 1 extra file(s) or folder(s) listed above, which regenerating leaves: remove them\n",
            out.display(),
            scenes.display()
        )
    );
}

#[test]
fn an_edited_manifest_sheet_or_gallery_fails() {
    let (code, out) = tampered("check-manifest", |d| {
        let m = std::fs::read_to_string(d.join("manifest.json")).unwrap();
        std::fs::write(d.join("manifest.json"), m.replace("\"seed\": 42", "\"seed\": 43")).unwrap();
        std::fs::write(d.join("contact-sheet.png"), b"not a sheet").unwrap();
        let index = d.parent().unwrap().join("index.html");
        let html = std::fs::read_to_string(&index).unwrap();
        std::fs::write(&index, html.replace("<h1>", "<h1>!")).unwrap();
    });
    assert_eq!(code, 1);
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[0].starts_with("lighting/contact-sheet.png: cannot be read: not a PNG image: "),
        "{out}"
    );
    // The values that differ, by their paths in the manifest.
    assert_eq!(
        lines[1],
        "lighting/manifest.json: differs from its regenerated self in images[01-ambient.png].seed, images[02-directional.png].seed, images[03-ambient-directional.png].seed"
    );
    assert_eq!(
        lines[2],
        "lighting     DIFFERS (at scale 0.05, as its manifest records)"
    );
    assert!(
        lines[3].starts_with("index.html: differs from its regenerated self at line 9"),
        "{out}"
    );
}

#[test]
fn nothing_to_check_is_refused_before_rendering() {
    let dir = temp_dir("check-nothing");
    let (missing, file, review) = (dir.join("none"), dir.join("a-file"), dir.join("review"));
    std::fs::write(&file, "a file").unwrap();
    let run = |out: &Path, review: &Path| {
        let (o, stdout) = check_lighting_in(out, review);
        assert!(stdout.is_empty());
        (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
    };
    let (m, f) = (missing.display(), file.display());
    assert_eq!(
        run(&missing, &review),
        (
            Some(2),
            format!(
                "lumiere: error: --out: {m} does not exist, so it holds no figure to check (`lumiere figures lighting --out {m}` writes them)\n"
            )
        )
    );
    assert_eq!(
        run(&file, &review),
        (Some(2), format!("lumiere: error: --out: {f} is a file, not a folder\n"))
    );
    generate_lighting(&dir);
    assert_eq!(
        run(&dir.join("figures"), &file),
        (
            Some(2),
            format!("lumiere: error: --review: {f} is a file, not a folder\n")
        )
    );
    // Nothing was made: neither the missing folder nor a review folder.
    assert!(!missing.exists() && !review.exists());
}

#[test]
fn the_scale_of_a_set_on_disk_is_said() {
    // Full-size figures replaced by previews (`--scale` without `--out`) are said before the
    // run, and a check says the scale it held the previews to.
    let dir = temp_dir("check-scale");
    generate_lighting(&dir);
    let out = dir.join("figures");
    let at_a_tenth = || {
        lumiere(&[
            "figures",
            "lighting",
            "--scale",
            "0.1",
            "-q",
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let o = at_a_tenth();
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        format!(
            "lumiere: warning: {}/lighting holds the set at scale 0.05; this run writes it at scale 0.1\n",
            out.display()
        )
    );
    let (o, stdout) = check_lighting(&dir);
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(stdout, "lighting     ok (at scale 0.1, as its manifest records)\n");
    // At the same scale, no warning; a set with no manifest is checked at --scale.
    let o = at_a_tenth();
    assert!(o.stderr.is_empty());
    std::fs::remove_dir_all(out.join("lighting")).unwrap();
    let o = lumiere(&[
        "figures",
        "lighting",
        "--check",
        "--scale",
        "0.5",
        "--out",
        out.to_str().unwrap(),
        "--review",
        dir.join("review").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("\nlighting     DIFFERS (at scale 0.5)\n"), "{stdout}");
}
