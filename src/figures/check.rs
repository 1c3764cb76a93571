//! `figures --check`: the files of a set on disk held to the set rendered again in memory.
//! Each image (a figure's PNG, the contact sheet) is decoded and compared with the fresh
//! render, pixel by pixel, and its provenance and bytes with a fresh encoding, a figure's
//! pixels also with its manifest's pixel hash; the manifest is compared with its
//! regenerated self value by value, and any file of the set's folder that the set does not
//! make is reported. Differing images get a heat-map and a labelled sheet (on disk, fresh
//! render, difference) in the review folder, and every differing file a place on its page
//! ([`crate::review`]).

use super::{BuiltSet, CONTACT_SHEET, FigureSet, FiguresError, Reuse, Run, build_set, provenance};
use crate::compare::{DifferingBox, compare_rgb8, differing_box, heat_map};
use crate::film::fnv1a64;
use crate::review::{self, HEAT_SCALE, PageItem, ReviewError, Rgb8};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// One thing wrong with a set's files.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// The file, `set/name` (or `index.html`, or a folder of the output).
    pub file: String,
    pub what: What,
}

/// What is wrong with a file.
#[derive(Clone, Debug, PartialEq)]
pub enum What {
    /// The set makes this file, and it is not there.
    Missing,
    /// The file is there, and the set does not make it (regenerating the set leaves it).
    Extra,
    /// The folder of the output is no set's (regenerating leaves it).
    ExtraFolder,
    /// The file cannot be read or decoded.
    Unreadable(String),
    /// Its pixels differ from the fresh render's, within `within`.
    Pixels {
        differing: u64,
        total: u64,
        within: Option<DifferingBox>,
        largest: u8,
        heat_map: Option<PathBuf>,
    },
    /// Its size differs from the fresh render's.
    Size { found: (u32, u32), fresh: (u32, u32) },
    /// Its pixels' hash differs from the one its manifest on disk records (`None`: the
    /// manifest does not list it).
    ManifestHash { found: String, manifest: Option<String> },
    /// A provenance text differs from a fresh encoding's (`None`: absent).
    Provenance {
        keyword: String,
        found: Option<String>,
        fresh: Option<String>,
    },
    /// Same pixels and provenance, other bytes than a fresh encoding.
    Encoding,
    /// A text file differs from its regenerated self from this line on (1-based).
    Text { line: usize, found: String, fresh: String },
    /// A JSON file (a manifest) differs from its regenerated self in these values, each
    /// named by its path ([`json_changes`]).
    Json { changes: Vec<String> },
    /// A binary file differs from its regenerated self.
    Bytes,
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let file = &self.file;
        match &self.what {
            What::Missing => write!(f, "{file}: missing"),
            What::Extra => write!(
                f,
                "{file}: extra file: no figure of the set makes it; remove it (regenerating the set leaves it)"
            ),
            What::ExtraFolder => write!(
                f,
                "{file}: extra folder: no figure set has this name; remove it (regenerating leaves it)"
            ),
            What::Unreadable(why) => write!(f, "{file}: cannot be read: {why}"),
            What::Pixels {
                differing,
                total,
                within,
                largest,
                heat_map,
            } => {
                write!(f, "{file}: {differing} of {total} pixels differ from a fresh render")?;
                if let Some(within) = within {
                    write!(f, ", in {within}")?;
                }
                write!(f, ", largest difference {largest} levels")?;
                match heat_map {
                    Some(p) => write!(f, "; heat map {}", p.display()),
                    None => Ok(()),
                }
            }
            What::Size { found, fresh } => write!(
                f,
                "{file}: {} x {} pixels, a fresh render has {} x {}",
                found.0, found.1, fresh.0, fresh.1
            ),
            What::ManifestHash { found, manifest } => match manifest {
                Some(m) => write!(f, "{file}: pixel hash {found}, its manifest says {m}"),
                None => write!(f, "{file}: pixel hash {found}, its manifest does not list it"),
            },
            What::Provenance { keyword, found, fresh } => {
                let show = |v: &Option<String>| v.as_ref().map_or("absent".to_string(), |s| format!("{s:?}"));
                write!(
                    f,
                    "{file}: provenance {keyword:?} is {}, a fresh render's is {}",
                    show(found),
                    show(fresh)
                )
            }
            What::Encoding => write!(
                f,
                "{file}: same pixels and provenance, other bytes than a fresh encoding"
            ),
            What::Text { line, found, fresh } => write!(
                f,
                "{file}: differs from its regenerated self at line {line}: {found:?}, regenerated {fresh:?}"
            ),
            What::Json { changes } => {
                write!(f, "{file}: differs from its regenerated self in ")?;
                let shown = changes.len().min(MOST_CHANGES_SHOWN);
                write!(f, "{}", changes[..shown].join(", "))?;
                match changes.len() - shown {
                    0 => Ok(()),
                    more => write!(f, " and {more} more"),
                }
            }
            What::Bytes => write!(f, "{file}: differs from its regenerated self"),
        }
    }
}

impl Problem {
    /// Whether regenerating the file's set makes the file right (not so for a file or
    /// folder that no set makes).
    pub fn regenerating_fixes(&self) -> bool {
        !matches!(self.what, What::Extra | What::ExtraFolder)
    }
}

/// Why a check could not be made.
#[derive(Debug, thiserror::Error)]
pub enum CheckError {
    /// The set could not be rendered or encoded.
    #[error(transparent)]
    Figures(#[from] FiguresError),
    /// A heat-map, sheet or the review page could not be written.
    #[error(transparent)]
    Review(#[from] ReviewError),
}

/// A checked set: what is wrong, the review page's items, and the manifest regenerated
/// (for the gallery's check).
pub struct SetCheck {
    pub problems: Vec<Problem>,
    pub review: Vec<PageItem>,
    pub manifest: Value,
}

/// The scale set `set` of `out` was generated at, as its manifest on disk records it
/// (`None` without a manifest or a scale in (0, 4]).
pub fn manifest_scale(out: &Path, set: &str) -> Option<f64> {
    std::fs::read_to_string(out.join(set).join("manifest.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok())
        .and_then(|m| m["scale"].as_f64())
        .filter(|s| *s > 0.0 && *s <= 4.0)
}

/// The scale a set was generated at: its manifest's on disk, else `fallback`.
pub fn recorded_scale(out: &Path, set: &str, fallback: f64) -> f64 {
    manifest_scale(out, set).unwrap_or(fallback)
}

/// The first line where two texts differ (1-based) and that line of each.
fn first_difference(found: &str, fresh: &str) -> (usize, String, String) {
    let (mut a, mut b) = (found.lines(), fresh.lines());
    let mut line = 1;
    loop {
        match (a.next(), b.next()) {
            (Some(x), Some(y)) if x == y => line += 1,
            (x, y) => {
                let show = |s: Option<&str>| s.map_or("(end of file)".to_string(), str::to_string);
                return (line, show(x), show(y));
            }
        }
    }
}

/// The bytes of a file compared with its regenerated self.
/// Most of a JSON file's differing values a problem names.
const MOST_CHANGES_SHOWN: usize = 8;

/// The paths of the values that differ between JSON values `found` and `fresh`, in key
/// order: `key.key` into objects; in an array of objects that each name their `file` (a
/// manifest's images), `images[01-ambient.png].pixel_hash`; an array otherwise, or a value
/// of another type, is named whole.
fn json_changes(found: &Value, fresh: &Value, path: &str, changes: &mut Vec<String>) {
    if found == fresh {
        return;
    }
    let file_of = |v: &Value| v.get("file").and_then(Value::as_str).map(str::to_string);
    match (found, fresh) {
        (Value::Object(a), Value::Object(b)) => {
            let mut keys: Vec<&String> = a.keys().chain(b.keys()).collect();
            keys.sort();
            keys.dedup();
            for key in keys {
                let inner = if path.is_empty() {
                    key.clone()
                } else {
                    format!("{path}.{key}")
                };
                json_changes(
                    a.get(key).unwrap_or(&Value::Null),
                    b.get(key).unwrap_or(&Value::Null),
                    &inner,
                    changes,
                );
            }
        }
        (Value::Array(a), Value::Array(b))
            if a.len() == b.len()
                && a.iter()
                    .zip(b)
                    .all(|(x, y)| file_of(x).is_some() && file_of(x) == file_of(y)) =>
        {
            for (x, y) in a.iter().zip(b) {
                let name = file_of(x).unwrap_or_default();
                json_changes(x, y, &format!("{path}[{name}]"), changes);
            }
        }
        _ => changes.push(path.to_string()),
    }
}

fn compare_file(file: String, found: &[u8], fresh: &[u8]) -> Option<Problem> {
    if found == fresh {
        return None;
    }
    let json = |bytes: &[u8]| serde_json::from_slice::<Value>(bytes).ok();
    if file.ends_with(".json")
        && let (Some(a), Some(b)) = (json(found), json(fresh))
    {
        let mut changes = Vec::new();
        json_changes(&a, &b, "", &mut changes);
        if !changes.is_empty() {
            return Some(Problem {
                file,
                what: What::Json { changes },
            });
        }
    }
    let what = match (std::str::from_utf8(found), std::str::from_utf8(fresh)) {
        (Ok(a), Ok(b)) => {
            let (line, found, fresh) = first_difference(a, b);
            What::Text { line, found, fresh }
        }
        _ => What::Bytes,
    };
    Some(Problem { file, what })
}

/// The pixel hashes the manifest on disk records, by file name.
fn manifest_hashes(out: &Path, set: &str) -> Vec<(String, String)> {
    let Some(m) = std::fs::read_to_string(out.join(set).join("manifest.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok())
    else {
        return Vec::new();
    };
    m["images"]
        .as_array()
        .map(|a| {
            a.iter()
                .map(|i| {
                    let s = |k: &str| i[k].as_str().unwrap_or_default().to_string();
                    (s("file"), s("pixel_hash"))
                })
                .collect()
        })
        .unwrap_or_default()
}

/// Checks set `set` in `run.out` (rendered at `run.scale`: see [`recorded_scale`]). Each
/// image of the set (its figures and its contact sheet) that differs gets a sheet in
/// `review_dir/figures/<set>/` under its own name: on disk | fresh render | difference
/// (with the heat map beside it, `<stem>.heat.png`), on disk | fresh render when the sizes
/// differ, the fresh render alone when the file is missing or not a PNG image.
pub fn check_set(set: &FigureSet, run: &Run, reuse: &mut Reuse, review_dir: &Path) -> Result<SetCheck, CheckError> {
    let built = build_set(set, run, &AtomicBool::new(false), reuse)?.expect("never cancelled");
    let dir = run.out.join(&set.name);
    let hashes = manifest_hashes(&run.out, &set.name);
    let mut problems = Vec::new();
    let mut review_items = Vec::new();
    let BuiltSet {
        rendered,
        contact_sheet,
        files,
        manifest,
    } = built;
    let sheets_folder = review_dir.join(review::FIGURES).join(&set.name);
    for (name, fresh) in &files {
        let file = format!("{}/{name}", set.name);
        let figure = rendered.iter().find(|r| format!("{}.png", r.figure.stem) == *name);
        let fresh_image = match figure {
            Some(r) => Some(&r.image),
            None if name == CONTACT_SHEET => Some(&contact_sheet),
            None => None,
        };
        let sheet_path = sheets_folder.join(name);
        let before = problems.len();
        match (std::fs::read(dir.join(name)), fresh_image) {
            (Err(e), _) => {
                let what = if e.kind() == std::io::ErrorKind::NotFound {
                    What::Missing
                } else {
                    What::Unreadable(e.to_string())
                };
                problems.push(Problem {
                    file: file.clone(),
                    what,
                });
                if let Some(fresh_image) = fresh_image {
                    review::write_png(&sheet_path, &review::sheet(&[("fresh render", &rgb8(fresh_image))]))?;
                }
            }
            (Ok(found), None) => problems.extend(compare_file(file.clone(), &found, fresh)),
            (Ok(found), Some(fresh_image)) => match image::load_from_memory(&found) {
                Err(e) => {
                    problems.push(Problem {
                        file: file.clone(),
                        what: What::Unreadable(format!("not a PNG image: {e}")),
                    });
                    review::write_png(&sheet_path, &review::sheet(&[("fresh render", &rgb8(fresh_image))]))?;
                }
                Ok(decoded) => {
                    let decoded = decoded.to_rgb8();
                    // Only the figures have their pixel hash in the manifest.
                    if figure.is_some() {
                        let found_hash = format!("fnv1a64:{:016x}", fnv1a64(decoded.as_raw()));
                        let recorded = hashes.iter().find(|(f, _)| f == name).map(|(_, h)| h.clone());
                        if recorded.as_ref() != Some(&found_hash) {
                            problems.push(Problem {
                                file: file.clone(),
                                what: What::ManifestHash {
                                    found: found_hash,
                                    manifest: recorded,
                                },
                            });
                        }
                    }
                    problems.extend(compare_pixels(&file, &decoded, fresh_image, &sheet_path)?);
                    problems.extend(provenance_problems(&file, &found, fresh));
                    if problems.len() == before && found != *fresh {
                        problems.push(Problem {
                            file: file.clone(),
                            what: What::Encoding,
                        });
                    }
                }
            },
        }
        if problems.len() > before {
            let summary = problems[before..]
                .iter()
                .map(|p| p.to_string())
                .collect::<Vec<_>>()
                .join("; ");
            let sheet = format!("{}/{}/{name}", review::FIGURES, set.name);
            review_items.push(PageItem {
                name: file,
                summary,
                sheet: sheet_path.is_file().then_some(sheet),
            });
        }
    }
    for name in super::extra_files(&dir, &files) {
        let p = Problem {
            file: format!("{}/{name}", set.name),
            what: What::Extra,
        };
        review_items.push(PageItem {
            name: p.file.clone(),
            summary: p.to_string(),
            sheet: None,
        });
        problems.push(p);
    }
    Ok(SetCheck {
        problems,
        review: review_items,
        manifest,
    })
}

/// The pixels of image `found` (file `file`, decoded from disk) against its fresh render:
/// a size or pixel problem, if any, with the sheet written to `sheet_path` and, for
/// differing pixels, the heat map beside it.
fn compare_pixels(
    file: &str,
    found: &image::RgbImage,
    fresh: &image::RgbImage,
    sheet_path: &Path,
) -> Result<Option<Problem>, ReviewError> {
    let (disk_img, fresh_img) = (rgb8(found), rgb8(fresh));
    if found.dimensions() != fresh.dimensions() {
        review::write_png(
            sheet_path,
            &review::sheet(&[("on disk", &disk_img), ("fresh render", &fresh_img)]),
        )?;
        return Ok(Some(Problem {
            file: file.to_string(),
            what: What::Size {
                found: found.dimensions(),
                fresh: fresh.dimensions(),
            },
        }));
    }
    if found.as_raw() == fresh.as_raw() {
        return Ok(None);
    }
    let c = compare_rgb8(&disk_img.data, &fresh_img.data, disk_img.width, disk_img.height, 0);
    let heat = Rgb8 {
        width: disk_img.width,
        height: disk_img.height,
        data: heat_map(&disk_img.data, &fresh_img.data, HEAT_SCALE),
    };
    let heat_path = sheet_path.with_extension("heat.png");
    review::write_png(&heat_path, &heat)?;
    let sheet = review::sheet(&[
        ("on disk", &disk_img),
        ("fresh render", &fresh_img),
        ("difference", &heat),
    ]);
    review::write_png(sheet_path, &sheet)?;
    Ok(Some(Problem {
        file: file.to_string(),
        what: What::Pixels {
            differing: c.differing_pixels,
            total: c.width as u64 * c.height as u64,
            within: differing_box(&disk_img.data, &fresh_img.data, disk_img.width, 0),
            largest: c.max_diff,
            heat_map: Some(heat_path),
        },
    }))
}

fn rgb8(img: &image::RgbImage) -> Rgb8 {
    Rgb8 {
        width: img.width(),
        height: img.height(),
        data: img.as_raw().clone(),
    }
}

/// The provenance texts of a PNG on disk against a fresh encoding's.
fn provenance_problems(file: &str, found: &[u8], fresh: &[u8]) -> Vec<Problem> {
    let found = provenance::text_chunks(found).unwrap_or_default();
    let fresh = provenance::text_chunks(fresh).unwrap_or_default();
    let keywords: Vec<&String> = fresh.iter().chain(&found).map(|(k, _)| k).collect();
    let mut seen: Vec<&String> = Vec::new();
    let mut out = Vec::new();
    for k in keywords {
        if seen.contains(&k) {
            continue;
        }
        seen.push(k);
        let of = |list: &[(String, String)]| list.iter().find(|(key, _)| key == k).map(|(_, v)| v.clone());
        let (a, b) = (of(&found), of(&fresh));
        if a != b {
            out.push(Problem {
                file: file.to_string(),
                what: What::Provenance {
                    keyword: k.clone(),
                    found: a,
                    fresh: b,
                },
            });
        }
    }
    out
}

/// The gallery `out/index.html` against the one regenerated from `manifests` (set name,
/// regenerated manifest) and, for the sets not checked, the manifests on disk.
pub fn check_index(out: &Path, sets: &[FigureSet], manifests: &[(String, Value)]) -> Option<Problem> {
    let fresh = super::gallery::index_html(out, sets, manifests);
    match std::fs::read(out.join("index.html")) {
        Ok(found) => compare_file("index.html".into(), &found, fresh.as_bytes()),
        Err(_) => Some(Problem {
            file: "index.html".into(),
            what: What::Missing,
        }),
    }
}

/// Folders of `out` that are no set of `sets` (checked when every set is).
pub fn extra_folders(out: &Path, sets: &[FigureSet]) -> Vec<Problem> {
    let Ok(entries) = std::fs::read_dir(out) else {
        return Vec::new();
    };
    let mut names: Vec<String> = entries
        .filter_map(Result::ok)
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !sets.iter().any(|s| s.name == *n))
        .collect();
    names.sort();
    names
        .into_iter()
        .map(|n| Problem {
            file: format!("{n}/"),
            what: What::ExtraFolder,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn json_changes_name_the_values_by_path() {
        let found = json!({
            "scale": 1.0,
            "images": [
                {"file": "a.png", "pixel_hash": "1", "family": ["b.png"]},
                {"file": "b.png", "pixel_hash": "2", "facts": {"white": 0.5}}
            ],
            "sets": [1, 2]
        });
        let mut fresh = found.clone();
        fresh["images"][0]["family"] = json!([]);
        fresh["images"][1]["facts"]["white"] = json!(0.25);
        fresh["images"][1]["seed"] = json!(7);
        fresh["sets"] = json!([1, 3]);
        let mut changes = Vec::new();
        json_changes(&found, &fresh, "", &mut changes);
        assert_eq!(
            changes,
            [
                "images[a.png].family",
                "images[b.png].facts.white",
                "images[b.png].seed",
                "sets"
            ]
        );
        // Images in another order: the array is named whole.
        let mut swapped = found.clone();
        swapped["images"] = json!([found["images"][1], found["images"][0]]);
        changes.clear();
        json_changes(&found, &swapped, "", &mut changes);
        assert_eq!(changes, ["images"]);
        // The display names the first eight.
        let many = What::Json {
            changes: (0..10).map(|i| format!("k{i}")).collect(),
        };
        let problem = Problem {
            file: "m.json".into(),
            what: many,
        };
        assert_eq!(
            problem.to_string(),
            "m.json: differs from its regenerated self in k0, k1, k2, k3, k4, k5, k6, k7 and 2 more"
        );
    }
}
