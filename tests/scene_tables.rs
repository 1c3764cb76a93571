//! Top-level tables of a scene file: a file without `[image]` or `[camera]` (the tables the
//! format requires) is refused with an error naming the file and each missing table, from
//! the library and from the command line (exit 2, nothing written); a misspelt table is
//! pointed at instead; a file without any of the optional tables (`[render]`,
//! `[materials.*]`, `[[shapes]]`, `[[lights]]`, `[[generate]]`) is a scene.

use crate::common::*;
use lumiere::scene::{SceneError, parse};

fn reference_text() -> String {
    std::fs::read_to_string(repo("scenes/reference.toml")).unwrap()
}

/// `text` without the tables whose header line `drop` picks: each such header and every
/// line up to the next header go.
fn without(text: &str, drop: impl Fn(&str) -> bool) -> String {
    let mut keep = true;
    let mut out = String::new();
    for line in text.lines() {
        let header = line.trim_start();
        if header.starts_with('[') {
            keep = !drop(header.split('#').next().unwrap_or_default().trim());
        }
        if keep {
            out += line;
            out.push('\n');
        }
    }
    out
}

fn error(text: &str) -> String {
    match parse(text, "reference.toml") {
        Ok(_) => panic!("parsed without error:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_reference_scene_has_every_table_kind() {
    // The cases below drop tables from this file: each kind must be there to be dropped.
    let text = reference_text();
    for header in [
        "[image]",
        "[camera]",
        "[render]",
        "[materials.",
        "[[shapes]]",
        "[[lights]]",
    ] {
        assert!(text.lines().any(|l| l.starts_with(header)), "{header}");
    }
    let scene = parse(&text, "reference.toml").unwrap();
    assert!(!scene.objects.is_empty() && !scene.lights.is_empty());
}

#[test]
fn a_scene_without_image_names_the_missing_table() {
    let text = without(&reference_text(), |h| h == "[image]");
    assert!(text.contains("[camera]") && !text.contains("[image]"));
    assert_eq!(error(&text), "reference.toml: the file has no [image] table");
}

#[test]
fn a_scene_without_camera_names_the_missing_table() {
    let text = without(&reference_text(), |h| h == "[camera]");
    assert!(text.contains("[image]") && !text.contains("[camera]"));
    assert_eq!(error(&text), "reference.toml: the file has no [camera] table");
}

#[test]
fn a_file_starting_with_shapes_is_not_blamed_on_its_first_shape() {
    // `[[shapes]]` first and no `[image]`: the error is the missing table, not `shapes[0]`.
    let text = "[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n\n\
                [camera]\nposition = [0, -5, 0]\nlook_at = [0, 0, 0]\n";
    assert_eq!(error(text), "reference.toml: the file has no [image] table");
    // `[image]` and no `[camera]`: not blamed on `image`.
    let text = "[image]\nwidth = 4\nheight = 3\n\n[[lights]]\ntype = \"ambient\"\n";
    assert_eq!(error(text), "reference.toml: the file has no [camera] table");
}

#[test]
fn a_file_without_either_names_both() {
    let both = "reference.toml: the file has no [image] table and no [camera] table";
    assert_eq!(error(""), both);
    assert_eq!(error("# only a comment\n"), both);
    assert_eq!(
        error(&without(&reference_text(), |h| h == "[image]" || h == "[camera]")),
        both
    );
    match parse("", "reference.toml") {
        Err(SceneError::MissingTables { file, tables }) => {
            assert_eq!((file.as_str(), tables), ("reference.toml", vec!["image", "camera"]));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_misspelt_required_table_is_pointed_at() {
    // `[kamera]` for `[camera]`: the unknown key is located, not reported as a missing table.
    let text = reference_text().replacen("[camera]", "[kamera]", 1);
    let line = text.lines().position(|l| l == "[kamera]").unwrap() + 1;
    let e = error(&text);
    assert!(
        e.starts_with(&format!(
            "reference.toml:{line}:2: kamera: unknown field `kamera`, expected one of `image`, `camera`"
        )),
        "{e}"
    );
}

#[test]
fn a_required_key_that_is_not_a_table_is_a_located_type_error() {
    let text = format!("camera = 5\n{}", without(&reference_text(), |h| h == "[camera]"));
    let e = error(&text);
    assert!(
        e.starts_with("reference.toml:1:10: camera: invalid type: integer `5`"),
        "{e}"
    );
}

#[test]
fn optional_tables_may_be_absent() {
    let reference = reference_text();
    // No [render]: its defaults (depth 1).
    let s = parse(&without(&reference, |h| h == "[render]"), "reference.toml").unwrap();
    assert_eq!(s.settings.depth, 1);
    // No [[lights]], no [[shapes]], no [[generate]].
    assert!(
        parse(&without(&reference, |h| h == "[[lights]]"), "r.toml")
            .unwrap()
            .lights
            .is_empty()
    );
    assert!(
        parse(&without(&reference, |h| h == "[[shapes]]"), "r.toml")
            .unwrap()
            .objects
            .is_empty()
    );
    assert!(!reference.contains("[[generate]]"));
    // No [materials.*] (and no shape naming one): every shape has the default material.
    let plain: String = without(&reference, |h| h.starts_with("[materials."))
        .lines()
        .filter(|l| !l.trim_start().starts_with("material ="))
        .map(|l| format!("{l}\n"))
        .collect();
    let s = parse(&plain, "r.toml").unwrap();
    assert_eq!(s.materials.len(), 1);
    // Only the two required tables.
    let minimal = "[image]\nwidth = 4\nheight = 3\n[camera]\nposition = [0, -5, 0]\nlook_at = [0, 0, 0]\n";
    let s = parse(minimal, "r.toml").unwrap();
    assert_eq!((s.settings.width, s.objects.len(), s.lights.len()), (4, 0, 0));
}

#[test]
fn the_command_line_refuses_a_scene_without_camera() {
    let dir = temp_dir("nocamera");
    let scene = dir.join("nocamera.toml");
    std::fs::write(&scene, without(&reference_text(), |h| h == "[camera]")).unwrap();
    let out = dir.join("out.png");
    let o = lumiere(&["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        format!("lumiere: error: {}: the file has no [camera] table\n", scene.display())
    );
    assert!(!out.exists());
}
