//! `lumiere diagnose` on an image of another aspect ratio than its scene's: the oracle is
//! rendered at the image's size, and a first line (`size_note` in JSON) gives the scene's
//! own size.

use crate::common::*;
use std::path::Path;

/// Renders the reference scene (800 x 600) at `width` x `height`, 1 sample, to `out`.
fn render(out: &Path, width: &str, height: &str) {
    let scene = repo("scenes/reference.toml");
    let o = lumiere(&[
        "render",
        scene.to_str().unwrap(),
        "--width",
        width,
        "--height",
        height,
        "--spp",
        "1",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `lumiere diagnose` of `image` against the reference scene at 1 sample: its stdout.
fn diagnose(image: &Path, more: &[&str]) -> String {
    let scene = repo("scenes/reference.toml");
    let mut args = vec![
        "diagnose",
        scene.to_str().unwrap(),
        image.to_str().unwrap(),
        "--spp",
        "1",
    ];
    args.extend_from_slice(more);
    let o = lumiere(&args);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn another_aspect_ratio_is_noted_with_the_scenes_size() {
    let dir = temp_dir("diagnose-size");
    let square = dir.join("square.png");
    render(&square, "8", "8");
    let note = format!(
        "{} is 8 x 8; the scene is 800 x 600, another aspect ratio: rendered at 8 x 8",
        square.display()
    );
    let text = diagnose(&square, &[]);
    assert_eq!(text.lines().next(), Some(format!("note: {note}").as_str()), "{text}");
    assert!(text.lines().nth(1).unwrap().starts_with("diagnosis "), "{text}");
    let json: serde_json::Value = serde_json::from_str(&diagnose(&square, &["--json"])).unwrap();
    assert_eq!(json["size_note"], note.as_str());
    assert_eq!((&json["width"], &json["height"]), (&8.into(), &8.into()));
    // --width given as the image's: the scene's own size is still the file's.
    assert_eq!(diagnose(&square, &["--width", "8"]), text);
}

#[test]
fn the_scenes_aspect_ratio_at_another_size_is_no_note() {
    let dir = temp_dir("diagnose-same-aspect");
    let small = dir.join("small.png");
    render(&small, "8", "6");
    let text = diagnose(&small, &[]);
    assert!(text.starts_with("diagnosis "), "{text}");
    assert!(!text.contains("note:"), "{text}");
    let json: serde_json::Value = serde_json::from_str(&diagnose(&small, &["--json"])).unwrap();
    assert_eq!(json["size_note"], serde_json::Value::Null);
}
