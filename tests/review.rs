//! `lumiere review-snapshots` on a fake snapshot folder laid out as insta 1.49 lays out
//! image snapshots: `NAME.snap` + `NAME.snap.png` accepted, `NAME.snap.new` +
//! `NAME.snap.new.png` pending.

mod common;
use common::*;
use lumiere::compare::load_rgb8;
use lumiere::film::encode_png;
use std::fs;
use std::path::Path;

fn write_png(path: &Path, w: u32, h: u32, rgb: &[u8]) {
    fs::write(path, encode_png(w, h, rgb).unwrap()).unwrap();
}

#[test]
fn sheets_show_old_new_and_difference() {
    let dir = temp_dir("review");
    let out = dir.join("sheets");
    // "changed": a 4 x 3 mid-grey image whose pixel (1, 2) goes from 100 to 120 in red
    // (20 levels, beyond the heat-map's white at 16) and pixel (3, 0) by 4 in blue.
    let old = [100u8; 4 * 3 * 3].to_vec();
    let mut new = old.clone();
    new[(2 * 4 + 1) * 3] = 120;
    new[3 * 3 + 2] = 104;
    for (name, text) in [("changed.snap", "---\n---\n"), ("changed.snap.new", "---\n---\n")] {
        fs::write(dir.join(name), text).unwrap();
    }
    write_png(&dir.join("changed.snap.png"), 4, 3, &old);
    write_png(&dir.join("changed.snap.new.png"), 4, 3, &new);
    // "fresh": a new 5 x 2 snapshot with no accepted one.
    fs::write(dir.join("fresh.snap.new"), "---\n---\n").unwrap();
    write_png(&dir.join("fresh.snap.new.png"), 5, 2, &[7u8; 5 * 2 * 3]);
    // "words": a pending text snapshot: listed, no sheet.
    fs::write(dir.join("words.snap.new"), "---\n---\nhello\n").unwrap();

    let o = lumiere(&[
        "review-snapshots",
        "--dir",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8(o.stdout).unwrap();
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 3, "{stdout}");
    // Differences 20 and 4 levels on 36 channels: RMS sqrt((400 + 16) / 36) = 3.3993.
    assert!(
        lines[0].starts_with("changed: max difference 20 levels, 2 of 12 pixels differ, RMS 3.3993 levels -> "),
        "{stdout}"
    );
    assert!(
        lines[1].starts_with("fresh: new snapshot, 5 x 2, no accepted one -> "),
        "{stdout}"
    );
    assert!(lines[2].starts_with("words: text snapshot"), "{stdout}");

    // Three 4 x 3 panels with 8 pixels around and between: (8 + 3 x 12) x (3 + 16) = 44 x 19.
    let (w, h, sheet) = load_rgb8(&out.join("changed.png")).unwrap();
    assert_eq!((w, h), (44, 19));
    let px = |x: u32, y: u32| sheet[((y * w + x) * 3) as usize..][..3].to_vec();
    assert_eq!(px(0, 0), [128, 128, 128]); // the grey ground
    assert_eq!(px(8 + 1, 8 + 2), [100, 100, 100]); // old panel at x = 8
    assert_eq!(px(20 + 1, 8 + 2), [120, 100, 100]); // new panel at x = 20
    assert_eq!(px(20 + 3, 8), [100, 100, 104]);
    assert_eq!(px(32, 8), [0, 0, 0]); // difference panel at x = 32: equal is black
    assert_eq!(px(32 + 1, 8 + 2), [255, 255, 255]); // 20 >= 16 levels: white
    // 4 levels of 16: x = 0.25, blue to red halfway: (64 + 0.5 x 191, 0, 64 + 0.5 x 191).
    assert_eq!(px(32 + 3, 8), [160, 0, 160]);

    // The new snapshot alone: (8 + 5 + 8) x (2 + 16) = 21 x 18.
    let (w, h, fresh) = load_rgb8(&out.join("fresh.png")).unwrap();
    assert_eq!((w, h), (21, 18));
    assert_eq!(fresh[((8 * w + 8) * 3) as usize], 7);
    assert!(!out.join("words.png").exists());
}

#[test]
fn no_pending_snapshots_and_missing_folder() {
    let dir = temp_dir("review-empty");
    let o = lumiere(&["review-snapshots", "--dir", dir.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8(o.stdout).unwrap().starts_with("no pending snapshots"));
    let o = lumiere(&["review-snapshots", "--dir", dir.join("nope").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("cannot read the folder"));
}
