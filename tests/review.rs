//! `lumiere review-snapshots` on a fake snapshot folder laid out as insta 1.49 lays out
//! image snapshots: `NAME.snap` + `NAME.snap.png` accepted, `NAME.snap.new` +
//! `NAME.snap.new.png` pending; labelled, enlarged sheets and the review page. And the
//! review page of `lumiere figures --check` for a set whose contact sheet differs.

use crate::common::*;
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
    assert_eq!(lines.len(), 5, "{stdout}");
    // Differences 20 and 4 levels on 36 channels: RMS sqrt((400 + 16) / 36) = 3.3993; the
    // two pixels, (1, 2) and (3, 0), span x 1..3, y 0..2.
    assert!(
        lines[0].starts_with(
            "changed: max difference 20 levels, 2 of 12 pixels differ in x 1..3, y 0..2, RMS 3.3993 levels -> "
        ),
        "{stdout}"
    );
    assert!(
        lines[1].starts_with("fresh: new snapshot, 5 x 2, no accepted one -> "),
        "{stdout}"
    );
    assert!(lines[2].starts_with("words: text snapshot"), "{stdout}");
    // Where to look, and how to accept or reject.
    assert_eq!(lines[3], format!("review page: {}", out.join("index.html").display()));
    assert_eq!(
        lines[4],
        format!(
            "accept them: `cargo insta accept` (without cargo-insta: README, \"Reviewing snapshot changes\"); reject them: `rm {}/*.snap.new*`",
            dir.display()
        )
    );

    // Three 4 x 3 panels enlarged 80 times to 320 x 240, labels 16 pixels tall above them,
    // 8 pixels around and between: (8 + 3 x 328) x (8 + 16 + 8 + 240 + 8) = 992 x 280.
    let (w, h, sheet) = load_rgb8(&out.join("snapshots/changed.png")).unwrap();
    assert_eq!((w, h), (992, 280));
    let px = |x: u32, y: u32| sheet[((y * w + x) * 3) as usize..][..3].to_vec();
    // Pixel (x, y) of panel p covers the 80 x 80 square from (8 + 328 p + 80 x, 32 + 80 y).
    let at = |p: u32, x: u32, y: u32| px(8 + 328 * p + 80 * x + 40, 32 + 80 * y + 40);
    assert_eq!(px(0, 0), [128, 128, 128]); // the grey ground
    assert_eq!(at(0, 1, 2), [100, 100, 100]); // accepted
    assert_eq!(at(1, 1, 2), [120, 100, 100]); // new
    assert_eq!(at(1, 3, 0), [100, 100, 104]);
    assert_eq!(at(2, 0, 0), [0, 0, 0]); // difference: equal is black
    assert_eq!(at(2, 1, 2), [255, 255, 255]); // 20 >= 16 levels: white
    // 4 levels of 16: x = 0.25, blue to red halfway: (64 + 0.5 x 191, 0, 64 + 0.5 x 191).
    assert_eq!(at(2, 3, 0), [160, 0, 160]);
    // Each panel is labelled above: white glyph pixels in the band 8 to 24 over each panel.
    let label = |p: u32| {
        (8..24)
            .flat_map(|y| (8 + 328 * p..8 + 328 * p + 320).map(move |x| (x, y)))
            .filter(|&(x, y)| px(x, y) == [255, 255, 255])
            .count()
    };
    assert!(label(0) > 0 && label(1) > 0 && label(2) > 0);
    // "difference" (10 glyphs) takes more ink than "new" (3).
    assert!(label(2) > 2 * label(1));

    // The new snapshot alone, 5 x 2 enlarged 64 times: (8 + 320 + 8) x (8 + 24 + 128 + 8).
    let (w, h, fresh) = load_rgb8(&out.join("snapshots/fresh.png")).unwrap();
    assert_eq!((w, h), (336, 168));
    assert_eq!(fresh[((32 * w + 8) * 3) as usize], 7);
    assert_eq!(fresh[((159 * w + 327) * 3) as usize], 7);
    assert!(!out.join("snapshots/words.png").exists());

    // The review page lists the three, with the sheets of the two images.
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(page.contains("<h2>Pending snapshots (3)</h2>"), "{page}");
    for name in ["changed", "fresh", "words"] {
        assert!(page.contains(&format!("<h3>{name}</h3>")), "{name}");
    }
    assert!(page.contains("<img src=\"snapshots/changed.png\""));
    assert!(page.contains("<img src=\"snapshots/fresh.png\""));
    assert!(!page.contains("snapshots/words.png"));
    assert!(page.contains("Not reviewed yet: run <code>lumiere figures --check</code>"));
    assert!(page.contains(
        "<p>To accept them: <code>cargo insta accept</code> (without cargo-insta: README, \"Reviewing snapshot changes\"); \
         to reject them: delete the pending <code>*.snap.new*</code> files.</p>"
    ));
}

#[test]
fn no_pending_snapshots_and_missing_folder() {
    let dir = temp_dir("review-empty");
    let out = dir.join("review");
    let o = lumiere(&[
        "review-snapshots",
        "--dir",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8(o.stdout).unwrap().starts_with("no pending snapshots"));
    // Nothing to review and no review folder yet: nothing written.
    assert!(!out.exists());
    // With a review folder, its page says there is nothing pending.
    std::fs::create_dir(&out).unwrap();
    let o = lumiere(&[
        "review-snapshots",
        "--dir",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0));
    let page = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(page.contains("<h2>Pending snapshots (0)</h2>"), "{page}");
    let o = lumiere(&["review-snapshots", "--dir", dir.join("nope").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("cannot read the folder"));
}

#[test]
fn a_differing_contact_sheet_is_shown_on_the_review_page() {
    let dir = temp_dir("review-contact-sheet");
    generate_lighting(&dir);
    // Two pixels of the contact sheet changed, its provenance kept: (20, 5) by 7 levels of
    // red, (100, 60) by 3 levels of blue.
    let path = dir.join("figures/lighting/contact-sheet.png");
    let at = |x: u32, y: u32, w: u32| ((y * w + x) * 3) as usize;
    let shift = |v: &mut u8, by: u8| *v = if *v > 200 { *v - by } else { *v + by };
    let (w, h, fresh, edited) = edit_png_keeping_provenance(&path, |rgb, w| {
        shift(&mut rgb[at(20, 5, w)], 7);
        shift(&mut rgb[at(100, 60, w) + 2], 3);
    });
    let at = |x: u32, y: u32| at(x, y, w);
    let review = dir.join("review");
    let (o, stdout) = check_lighting(&dir);
    assert_eq!(o.status.code(), Some(1));
    let d = dir.display();
    // The box spans both pixels: x 20..100, y 5..60.
    assert_eq!(
        stdout,
        format!(
            "lighting/contact-sheet.png: 2 of {} pixels differ from a fresh render, in x 20..100, y 5..60, largest difference 7 levels; heat map {d}/review/figures/lighting/contact-sheet.heat.png\n\
             lighting     DIFFERS (at scale 0.05, as its manifest records)\n\
             review page: {d}/review/index.html\n",
            w * h
        )
    );

    // The heat map: black where equal, blue to red to white at 16 levels; 7 levels is
    // x = 7 / 16, red 2x and blue 1 - 2x: (64 + 0.875 x 191, 0, 64 + 0.125 x 191) =
    // (231, 0, 88) rounded; 3 levels, x = 3 / 16: (64 + 0.375 x 191, 0, 64 + 0.625 x 191)
    // = (136, 0, 183).
    let (hw, hh, heat) = load_rgb8(&review.join("figures/lighting/contact-sheet.heat.png")).unwrap();
    assert_eq!((hw, hh), (w, h));
    assert_eq!(heat[at(20, 5)..at(20, 5) + 3], [231, 0, 88]);
    assert_eq!(heat[at(100, 60)..at(100, 60) + 3], [136, 0, 183]);
    assert_eq!(heat[at(21, 5)..at(21, 5) + 3], [0, 0, 0]);
    // The sheet: on disk | fresh render | difference. The contact sheet of three 40 x 30
    // thumbnails is 12 + 3 x (40 + 12) = 168 wide, enlarged twice to 336; pixel (x, y) of
    // panel p covers the 2 x 2 square from (8 + 344 p + 2 x, 32 + 2 y).
    assert_eq!(w, 168);
    let (sw, sh, sheet) = load_rgb8(&review.join("figures/lighting/contact-sheet.png")).unwrap();
    assert_eq!((sw, sh), (8 + 3 * (336 + 8), 8 + 24 + 2 * h + 8));
    let panel = |p: u32, x: u32, y: u32| {
        let i = (((32 + 2 * y) * sw + 8 + 344 * p + 2 * x) * 3) as usize;
        sheet[i..i + 3].to_vec()
    };
    assert_eq!(panel(0, 20, 5), edited[at(20, 5)..at(20, 5) + 3]);
    assert_eq!(panel(1, 20, 5), fresh[at(20, 5)..at(20, 5) + 3]);
    assert_eq!(panel(2, 20, 5), [231, 0, 88]);
    assert_eq!(panel(0, 100, 60), edited[at(100, 60)..at(100, 60) + 3]);
    assert_eq!(panel(1, 100, 60), fresh[at(100, 60)..at(100, 60) + 3]);

    // The page shows the sheet, and says where the pixels differ.
    let page = fs::read_to_string(review.join("index.html")).unwrap();
    assert!(
        page.contains("<h2>Figures that differ from a fresh render (1)</h2>"),
        "{page}"
    );
    assert!(page.contains("<h3>lighting/contact-sheet.png</h3>"), "{page}");
    assert!(
        page.contains("<img src=\"figures/lighting/contact-sheet.png\""),
        "{page}"
    );
    assert!(page.contains(&format!(
        "2 of {} pixels differ from a fresh render, in x 20..100, y 5..60",
        w * h
    )));
}
