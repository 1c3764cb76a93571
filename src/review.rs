//! `lumiere review-snapshots`: before accepting changed image snapshots, see what changed.
//!
//! insta 1.49 stores an image snapshot `assert_binary_snapshot!("NAME.png", bytes)` as the
//! metadata file `NAME.snap` with the image `NAME.snap.png` beside it; a snapshot that
//! differs (or is new) is written as `NAME.snap.new` with `NAME.snap.new.png`. For each
//! pending image this module writes a sheet `OUT/NAME.png` with three panels, left to
//! right: the accepted image | the new image | the difference heat-map
//! ([`crate::compare::heat_map`]: black equal, blue small, red, white >= 16 levels), on a grey
//! ground. A new snapshot with no accepted one gets a sheet with the new image alone.

use crate::compare::{Comparison, compare_rgb8, heat_map, load_rgb8};
use crate::film::{WriteError, encode_png, write_atomic};
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
    /// Same size: the comparison (tolerance 0).
    Changed(Comparison),
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

/// Panels side by side with [`GAP`] pixels of [`GROUND`] around and between them.
pub fn sheet(panels: &[&Rgb8]) -> Rgb8 {
    let width = GAP + panels.iter().map(|p| p.width + GAP).sum::<u32>();
    let height = 2 * GAP + panels.iter().map(|p| p.height).max().unwrap_or(0);
    let mut data = GROUND.repeat(width as usize * height as usize);
    let mut left = GAP;
    for p in panels {
        for y in 0..p.height {
            let src = (y * p.width * 3) as usize;
            let dst = (((y + GAP) * width + left) * 3) as usize;
            let row = (p.width * 3) as usize;
            data[dst..dst + row].copy_from_slice(&p.data[src..src + row]);
        }
        left += p.width + GAP;
    }
    Rgb8 { width, height, data }
}

fn load(path: &Path) -> Result<Rgb8, String> {
    let (width, height, data) = load_rgb8(path)?;
    Ok(Rgb8 { width, height, data })
}

/// Reviews the pending snapshot `name` of `dir`, writing its sheet into `out`.
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
            sheet(&[&new]),
        ),
        Some(old) if (old.width, old.height) != (new.width, new.height) => (
            Change::Resized {
                old: (old.width, old.height),
                new: (new.width, new.height),
            },
            sheet(&[old, &new]),
        ),
        Some(old) => {
            let diff = Rgb8 {
                width: new.width,
                height: new.height,
                data: heat_map(&old.data, &new.data, HEAT_SCALE),
            };
            (
                Change::Changed(compare_rgb8(&old.data, &new.data, new.width, new.height, 0)),
                sheet(&[old, &new, &diff]),
            )
        }
    };
    let sheet_path = out.join(format!("{name}.png"));
    let png = encode_png(image.width, image.height, &image.data)
        .map_err(|e| ReviewError::Encode(format!("cannot encode the sheet of {name}: {e}")))?;
    write_atomic(&sheet_path, &png).map_err(|e| WriteError::new(&sheet_path, "cannot write the sheet", e))?;
    Ok(Reviewed {
        name: name.to_owned(),
        change,
        sheet: Some(sheet_path),
    })
}

/// Reviews every pending snapshot of `dir`.
pub fn review(dir: &Path, out: &Path) -> Result<Vec<Reviewed>, ReviewError> {
    let names = pending_names(dir).map_err(ReviewError::Read)?;
    if !names.is_empty() {
        fs::create_dir_all(out).map_err(|e| WriteError::new(out, "cannot create the folder", e))?;
    }
    names.iter().map(|n| review_one(dir, n, out)).collect()
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
        Change::Changed(c) => format!(
            "{}: max difference {} levels, {} of {} pixels differ, RMS {:.4} levels{sheet}",
            r.name,
            c.max_diff,
            c.differing_pixels,
            c.width as u64 * c.height as u64,
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sheet_layout() {
        // Panels 2 x 1 (red) and 1 x 2 (blue): width 8 + (2 + 8) + (1 + 8) = 27, height 8 + 2 + 8 = 18.
        let a = Rgb8 {
            width: 2,
            height: 1,
            data: vec![255, 0, 0, 255, 0, 0],
        };
        let b = Rgb8 {
            width: 1,
            height: 2,
            data: vec![0, 0, 255, 0, 0, 255],
        };
        let s = sheet(&[&a, &b]);
        assert_eq!((s.width, s.height), (27, 18));
        let px = |x: u32, y: u32| &s.data[((y * s.width + x) * 3) as usize..][..3];
        assert_eq!(px(8, 8), [255, 0, 0]);
        assert_eq!(px(9, 8), [255, 0, 0]);
        assert_eq!(px(8, 9), GROUND);
        assert_eq!(px(18, 8), [0, 0, 255]);
        assert_eq!(px(18, 9), [0, 0, 255]);
        assert_eq!(px(0, 0), GROUND);
    }
}
