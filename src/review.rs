//! Reviews before accepting a change: pending insta image snapshots, and figures that
//! differ from a fresh render ([`crate::figures::check`]), as labelled sheets and one HTML
//! page listing both.
//!
//! insta 1.49 stores an image snapshot `assert_binary_snapshot!("NAME.png", bytes)` as the
//! metadata file `NAME.snap` with the image `NAME.snap.png` beside it; a snapshot that
//! differs (or is new) is written as `NAME.snap.new` with `NAME.snap.new.png`. For each
//! pending image this module writes a sheet `OUT/snapshots/NAME.png` with three panels, left
//! to right, each labelled above: "accepted", "new", and "difference", the heat-map
//! ([`crate::compare::heat_map`]: black equal, blue small, red, white >= 16 levels), on a
//! grey ground; panels narrower than [`MIN_PANEL_WIDTH`] are enlarged pixel by pixel
//! (nearest neighbour, one whole factor for the sheet). A new snapshot with no accepted one
//! gets a sheet with the new image alone. `OUT/index.html` lists the pending snapshots of
//! the last `review-snapshots` and the figure changes of the last `figures --check` that
//! wrote into `OUT`, each with its sheet ([`write_section`]).

use crate::compare::{Comparison, DifferingBox, compare_rgb8, differing_box, heat_map, load_rgb8};
use crate::film::{WriteError, encode_png, write_atomic};
use crate::text::draw_text;
use serde::{Deserialize, Serialize};
use std::fs;
use std::path::{Path, PathBuf};

/// Why a review stopped.
#[derive(Debug, thiserror::Error)]
pub enum ReviewError {
    /// The snapshot folder or one of its images cannot be read.
    #[error("{0}")]
    Read(String),
    /// A sheet cannot be encoded.
    #[error("{0}")]
    Encode(String),
    /// A sheet cannot be written, or the sheets' folder cannot be made.
    #[error(transparent)]
    Write(#[from] WriteError),
}

/// Margin around and between the panels of a sheet, in pixels.
pub const GAP: u32 = 8;
/// The sheet's ground: mid grey, distinct from the heat-map's black "equal".
pub const GROUND: [u8; 3] = [128, 128, 128];
/// Differences at or above this many levels are white in the heat-map.
pub const HEAT_SCALE: u8 = 16;
/// Panels are enlarged by a whole factor until each is at least this wide.
pub const MIN_PANEL_WIDTH: u32 = 320;
/// Labels are drawn with 8 x 8 glyphs at this scale: 16 pixels tall.
pub const LABEL_SCALE: u32 = 2;
/// The labels' colour.
pub const LABEL_COLOR: [u8; 3] = [255, 255, 255];
/// The sub-folder of the review folder holding the snapshot sheets.
pub const SNAPSHOTS: &str = "snapshots";
/// The sub-folder of the review folder holding the figure sheets.
pub const FIGURES: &str = "figures";

/// An RGB8 image.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgb8 {
    pub width: u32,
    pub height: u32,
    pub data: Vec<u8>,
}

/// What changed in one pending snapshot.
#[derive(Clone, Debug, PartialEq)]
pub enum Change {
    /// No accepted snapshot: the image is new.
    New { width: u32, height: u32 },
    /// Same size: the comparison (tolerance 0) and where the pixels differ.
    Changed(Comparison, Option<DifferingBox>),
    /// The size changed; no difference panel.
    Resized { old: (u32, u32), new: (u32, u32) },
    /// A pending text snapshot (no `.snap.new.png`): nothing to draw.
    Text,
}

/// One pending snapshot reviewed.
#[derive(Clone, Debug, PartialEq)]
pub struct Reviewed {
    pub name: String,
    pub change: Change,
    /// The sheet written, if any.
    pub sheet: Option<PathBuf>,
}

/// Names `NAME` of the pending snapshots (`NAME.snap.new`) in `dir`, sorted.
pub fn pending_names(dir: &Path) -> Result<Vec<String>, String> {
    let entries = fs::read_dir(dir).map_err(|e| format!("{}: cannot read the folder: {e}", dir.display()))?;
    let mut names: Vec<String> = entries
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            e.file_name()
                .to_str()
                .and_then(|n| n.strip_suffix(".snap.new"))
                .map(str::to_owned)
        })
        .collect();
    names.sort();
    Ok(names)
}

/// The whole factor that makes a panel `width` pixels wide at least [`MIN_PANEL_WIDTH`].
pub fn enlargement(width: u32) -> u32 {
    MIN_PANEL_WIDTH.div_ceil(width.max(1)).max(1)
}

/// `img` enlarged `factor` times, each pixel a `factor` x `factor` square.
pub fn enlarge(img: &Rgb8, factor: u32) -> Rgb8 {
    let (w, h) = (img.width * factor, img.height * factor);
    let mut data = Vec::with_capacity((w * h * 3) as usize);
    for y in 0..h {
        let row = ((y / factor) * img.width * 3) as usize;
        for x in 0..w {
            let at = row + ((x / factor) * 3) as usize;
            data.extend_from_slice(&img.data[at..at + 3]);
        }
    }
    Rgb8 {
        width: w,
        height: h,
        data,
    }
}

/// Labelled panels side by side: each enlarged by the factor that makes the narrowest at
/// least [`MIN_PANEL_WIDTH`] wide, its label above it, with [`GAP`] pixels of [`GROUND`]
/// around and between them.
pub fn sheet(panels: &[(&str, &Rgb8)]) -> Rgb8 {
    let factor = enlargement(panels.iter().map(|(_, p)| p.width).min().unwrap_or(1));
    let big: Vec<Rgb8> = panels.iter().map(|(_, p)| enlarge(p, factor)).collect();
    let label_h = 8 * LABEL_SCALE + GAP;
    let width = GAP + big.iter().map(|p| p.width + GAP).sum::<u32>();
    let height = 2 * GAP + label_h + big.iter().map(|p| p.height).max().unwrap_or(0);
    let mut canvas = image::RgbImage::from_pixel(width, height, image::Rgb(GROUND));
    let mut left = GAP;
    for ((label, _), p) in panels.iter().zip(&big) {
        draw_text(&mut canvas, left, GAP, label, LABEL_SCALE, image::Rgb(LABEL_COLOR));
        let img = image::RgbImage::from_raw(p.width, p.height, p.data.clone()).expect("panel size");
        image::imageops::replace(&mut canvas, &img, left as i64, (GAP + label_h) as i64);
        left += p.width + GAP;
    }
    Rgb8 {
        width,
        height,
        data: canvas.into_raw(),
    }
}

/// Where the top-left pixel of panel `index` of a [`sheet`] of `panels` lands (the pixel
/// `(x, y)` of the panel covers the square from there plus `factor * (x, y)`), and the factor.
pub fn panel_origin(panels: &[&Rgb8], index: usize) -> ((u32, u32), u32) {
    let factor = enlargement(panels.iter().map(|p| p.width).min().unwrap_or(1));
    let x = GAP + panels[..index].iter().map(|p| p.width * factor + GAP).sum::<u32>();
    ((x, GAP + 8 * LABEL_SCALE + GAP), factor)
}

/// Loads an image file as [`Rgb8`].
pub fn load(path: &Path) -> Result<Rgb8, String> {
    let (width, height, data) = load_rgb8(path)?;
    Ok(Rgb8 { width, height, data })
}

/// Encodes `image` as PNG into `path`, its folder made if missing.
pub fn write_png(path: &Path, image: &Rgb8) -> Result<(), ReviewError> {
    if let Some(dir) = path.parent() {
        fs::create_dir_all(dir).map_err(|e| WriteError::new(dir, "cannot create the folder", e))?;
    }
    let png = encode_png(image.width, image.height, &image.data)
        .map_err(|e| ReviewError::Encode(format!("{}: cannot encode: {e}", path.display())))?;
    write_atomic(path, &png).map_err(|e| WriteError::new(path, "cannot write", e))?;
    Ok(())
}

/// Reviews the pending snapshot `name` of `dir`, writing its sheet into `out/snapshots/`.
pub fn review_one(dir: &Path, name: &str, out: &Path) -> Result<Reviewed, ReviewError> {
    let new_path = dir.join(format!("{name}.snap.new.png"));
    if !new_path.exists() {
        return Ok(Reviewed {
            name: name.to_owned(),
            change: Change::Text,
            sheet: None,
        });
    }
    let new = load(&new_path).map_err(ReviewError::Read)?;
    let old_path = dir.join(format!("{name}.snap.png"));
    let old = if old_path.exists() {
        Some(load(&old_path).map_err(ReviewError::Read)?)
    } else {
        None
    };
    let (change, image) = match &old {
        None => (
            Change::New {
                width: new.width,
                height: new.height,
            },
            sheet(&[("new", &new)]),
        ),
        Some(old) if (old.width, old.height) != (new.width, new.height) => (
            Change::Resized {
                old: (old.width, old.height),
                new: (new.width, new.height),
            },
            sheet(&[("accepted", old), ("new", &new)]),
        ),
        Some(old) => {
            let diff = Rgb8 {
                width: new.width,
                height: new.height,
                data: heat_map(&old.data, &new.data, HEAT_SCALE),
            };
            (
                Change::Changed(
                    compare_rgb8(&old.data, &new.data, new.width, new.height, 0),
                    differing_box(&old.data, &new.data, new.width, 0),
                ),
                sheet(&[("accepted", old), ("new", &new), ("difference", &diff)]),
            )
        }
    };
    let sheet_path = out.join(SNAPSHOTS).join(format!("{name}.png"));
    write_png(&sheet_path, &image)?;
    Ok(Reviewed {
        name: name.to_owned(),
        change,
        sheet: Some(sheet_path),
    })
}

/// Reviews every pending snapshot of `dir`: sheets in `out/snapshots/` (the old ones
/// removed), and the review page `out/index.html`. With nothing pending and no `out`
/// folder, writes nothing.
pub fn review(dir: &Path, out: &Path) -> Result<Vec<Reviewed>, ReviewError> {
    let names = pending_names(dir).map_err(ReviewError::Read)?;
    if names.is_empty() && !out.is_dir() {
        return Ok(Vec::new());
    }
    clear_sheets(&out.join(SNAPSHOTS))?;
    let reviewed: Vec<Reviewed> = names
        .iter()
        .map(|n| review_one(dir, n, out))
        .collect::<Result<_, _>>()?;
    let items: Vec<PageItem> = reviewed
        .iter()
        .map(|r| PageItem {
            name: r.name.clone(),
            summary: summary(r),
            sheet: r.sheet.as_ref().map(|_| format!("{SNAPSHOTS}/{}.png", r.name)),
        })
        .collect();
    write_section(out, Section::Snapshots, &items)?;
    Ok(reviewed)
}

/// Removes the PNG files of a sheets folder (what an earlier review wrote there).
pub fn clear_sheets(folder: &Path) -> Result<(), ReviewError> {
    let Ok(entries) = fs::read_dir(folder) else {
        return Ok(());
    };
    let mut pngs: Vec<PathBuf> = Vec::new();
    for e in entries.filter_map(Result::ok) {
        let path = e.path();
        if path.is_dir() {
            clear_sheets(&path)?;
        } else if path.extension().is_some_and(|x| x == "png") {
            pngs.push(path);
        }
    }
    for path in pngs {
        fs::remove_file(&path).map_err(|e| WriteError::new(&path, "cannot remove the old sheet", e))?;
    }
    Ok(())
}

/// The summary line of one reviewed snapshot.
pub fn summary(r: &Reviewed) -> String {
    let sheet = r
        .sheet
        .as_ref()
        .map_or(String::new(), |p| format!(" -> {}", p.display()));
    match &r.change {
        Change::New { width, height } => {
            format!("{}: new snapshot, {width} x {height}, no accepted one{sheet}", r.name)
        }
        Change::Changed(c, within) => format!(
            "{}: max difference {} levels, {} of {} pixels differ{}, RMS {:.4} levels{sheet}",
            r.name,
            c.max_diff,
            c.differing_pixels,
            c.width as u64 * c.height as u64,
            within.map_or(String::new(), |b| format!(" in {b}")),
            c.rms
        ),
        Change::Resized { old, new } => format!(
            "{}: size changed from {} x {} to {} x {}{sheet}",
            r.name, old.0, old.1, new.0, new.1
        ),
        Change::Text => format!(
            "{}: text snapshot, compare {0}.snap with {0}.snap.new (or `cargo insta review`)",
            r.name
        ),
    }
}

/// One entry of the review page: what it is, what changed, and its sheet (a path relative
/// to the page's folder).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PageItem {
    pub name: String,
    pub summary: String,
    pub sheet: Option<String>,
}

/// The two lists of the review page, each written by its own command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Section {
    /// Pending snapshots, from `lumiere review-snapshots`.
    Snapshots,
    /// Figures that differ from a fresh render, from `lumiere figures --check`.
    Figures,
}

impl Section {
    /// The file in the review folder holding the section's list.
    pub fn file(self) -> &'static str {
        match self {
            Section::Snapshots => "snapshots.json",
            Section::Figures => "figures.json",
        }
    }

    fn heading(self) -> &'static str {
        match self {
            Section::Snapshots => "Pending snapshots",
            Section::Figures => "Figures that differ from a fresh render",
        }
    }

    /// How the changes of the section are accepted or rejected, as the page says it (HTML).
    fn acceptance(self) -> &'static str {
        match self {
            Section::Snapshots => {
                "To accept them: <code>cargo insta accept</code> (without cargo-insta: README, \"Reviewing snapshot changes\"); \
                 to reject them: delete the pending <code>*.snap.new*</code> files."
            }
            Section::Figures => {
                "To accept them: regenerate the sets with the command <code>lumiere figures --check</code> ends with, \
                 accept the figures' snapshots, and commit both (docs/figures.md, \"Changing a figure on purpose\"); \
                 to reject them: restore the scene files."
            }
        }
    }

    fn source(self) -> &'static str {
        match self {
            Section::Snapshots => "lumiere review-snapshots",
            Section::Figures => "lumiere figures --check",
        }
    }
}

/// The list of `section` in review folder `dir`, as its command last wrote it (`None` if
/// it never did).
pub fn read_section(dir: &Path, section: Section) -> Option<Vec<PageItem>> {
    let text = fs::read_to_string(dir.join(section.file())).ok()?;
    serde_json::from_str(&text).ok()
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Writes `items` as `section`'s list in review folder `dir`, and the page `dir/index.html`
/// with both sections (the other as its command last wrote it).
pub fn write_section(dir: &Path, section: Section, items: &[PageItem]) -> Result<(), ReviewError> {
    fs::create_dir_all(dir).map_err(|e| WriteError::new(dir, "cannot create the folder", e))?;
    let json = serde_json::to_string_pretty(items).map_err(|e| ReviewError::Encode(e.to_string()))? + "\n";
    let path = dir.join(section.file());
    write_atomic(&path, json.as_bytes()).map_err(|e| WriteError::new(&path, "cannot write", e))?;
    let mut html = String::from(
        "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>lumiere: review</title>\n\
         <style>body{font-family:sans-serif;background:#202024;color:#eee;margin:2em}\
         section{margin:1em 0 2em}img{max-width:100%;image-rendering:pixelated}a{color:#9cf}</style>\n\
         </head>\n<body>\n<h1>Changes to review</h1>\n",
    );
    for s in [Section::Snapshots, Section::Figures] {
        let list = if s == section {
            Some(items.to_vec())
        } else {
            read_section(dir, s)
        };
        let Some(list) = list else {
            html += &format!(
                "<h2>{}</h2>\n<p>Not reviewed yet: run <code>{}</code>.</p>\n",
                s.heading(),
                s.source()
            );
            continue;
        };
        html += &format!("<h2>{} ({})</h2>\n", s.heading(), list.len());
        if list.is_empty() {
            html += &format!("<p>None at the last <code>{}</code>.</p>\n", s.source());
        } else {
            html += &format!("<p>{}</p>\n", s.acceptance());
        }
        for item in &list {
            html += &format!(
                "<section><h3>{}</h3>\n<p>{}</p>\n",
                escape(&item.name),
                escape(&item.summary)
            );
            if let Some(sheet) = &item.sheet {
                html += &format!(
                    "<a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a>\n",
                    escape(sheet),
                    escape(&item.name)
                );
            }
            html += "</section>\n";
        }
    }
    html += "</body>\n</html>\n";
    let page = dir.join("index.html");
    write_atomic(&page, html.as_bytes()).map_err(|e| WriteError::new(&page, "cannot write", e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(width: u32, height: u32, rgb: [u8; 3]) -> Rgb8 {
        Rgb8 {
            width,
            height,
            data: rgb.repeat((width * height) as usize),
        }
    }

    #[test]
    fn sheet_layout() {
        // Panels 80 x 60 (red) and 80 x 40 (blue) enlarged 4 times to 320 x 240 and 320 x 160;
        // labels 16 tall above: width 8 + (320 + 8) x 2 = 664, height 8 + 24 + 240 + 8 = 280.
        let (a, b) = (flat(80, 60, [255, 0, 0]), flat(80, 40, [0, 0, 255]));
        let s = sheet(&[("accepted", &a), ("new", &b)]);
        assert_eq!((s.width, s.height), (664, 280));
        let px = |x: u32, y: u32| &s.data[((y * s.width + x) * 3) as usize..][..3];
        assert_eq!(panel_origin(&[&a, &b], 0), ((8, 32), 4));
        assert_eq!(panel_origin(&[&a, &b], 1), ((336, 32), 4));
        assert_eq!(px(8, 32), [255, 0, 0]);
        assert_eq!(px(8 + 319, 32 + 239), [255, 0, 0]);
        assert_eq!(px(8 + 320, 32), GROUND);
        assert_eq!(px(336, 32 + 159), [0, 0, 255]);
        assert_eq!(px(336, 32 + 160), GROUND);
        assert_eq!(px(0, 0), GROUND);
        // The label "accepted": white glyph pixels in the band above the first panel only.
        let lit = |x0: u32, x1: u32| {
            (GAP..GAP + 16)
                .flat_map(|y| (x0..x1).map(move |x| (x, y)))
                .filter(|&(x, y)| px(x, y) == LABEL_COLOR)
                .count()
        };
        assert!(lit(8, 8 + 8 * 16) > 100);
        assert_eq!(lit(8 + 8 * 16, 336), 0);
        assert!(lit(336, 336 + 3 * 16) > 40);
    }

    #[test]
    fn enlargement_reaches_320_pixels() {
        assert_eq!(enlargement(80), 4);
        assert_eq!(enlargement(100), 4);
        assert_eq!(enlargement(320), 1);
        assert_eq!(enlargement(800), 1);
        let big = enlarge(
            &Rgb8 {
                width: 2,
                height: 1,
                data: vec![1, 2, 3, 4, 5, 6],
            },
            2,
        );
        assert_eq!(
            big.data,
            vec![1, 2, 3, 1, 2, 3, 4, 5, 6, 4, 5, 6, 1, 2, 3, 1, 2, 3, 4, 5, 6, 4, 5, 6]
        );
    }
}
