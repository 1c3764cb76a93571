//! The HTML report of a diagnosis (`lumiere diagnose --report DIR`): `index.html` with the
//! verdict, the gains and the ranking, and beside it, on the judged grid, the image
//! (`image.png`), the oracle (`oracle.png`), their difference (`heat-oracle.png`), the edge
//! mask (`edges.png`) and for each of the top mistakes its render (`mistake-N.png`) and the
//! image's difference from it (`heat-N.png`). Heat-maps are black where equal, white at
//! 16 levels or more ([`crate::compare::heat_map`]). A folder written before holds only
//! what the last report references: the mistakes' images past its top are removed
//! ([`is_mistake_image`]); no other file is touched.
//!
//! Each report folder holds a marker, [`MARKER`], saying that lumiere wrote it and whether
//! alone (`--report DIR` of one image) or as one of several (`DIR/NAME` of a run of several
//! images). A later run into the same `DIR` removes the reports it finds there that it does
//! not write ([`remove_stale_reports`]), so no report of an image left off the command line
//! is taken for current; it removes only folders that hold lumiere's marker, and in them
//! only the files a report writes.

use super::{Candidate, Diagnosis};
use crate::compare::heat_map;
use crate::film::{encode_png, write_atomic};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Escapes text for HTML.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// The file that marks a folder as a report lumiere wrote ([`Written`] says how).
pub const MARKER: &str = ".lumiere-report";

/// The first line of [`MARKER`], which identifies it.
const MARKER_TITLE: &str = "lumiere diagnose report";

/// How a report folder was written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Written {
    /// `--report DIR` of one image: the folder is `DIR`.
    Alone,
    /// `--report DIR` of several images: the folder is `DIR/NAME`, one of several.
    OneOfSeveral,
}

impl Written {
    /// The marker's second line.
    fn line(self) -> &'static str {
        match self {
            Written::Alone => "written alone",
            Written::OneOfSeveral => "written as one of several, into the folder above",
        }
    }
}

/// The text of the marker of a report of `image` against `scene`, written so.
fn marker_text(written: Written, scene: &str, image: &str) -> String {
    format!(
        "{MARKER_TITLE}\n{}\nimage {image}\nscene {scene}\na later `lumiere diagnose --report` into the same folder removes the report files of a folder so marked when it does not write it\n",
        written.line()
    )
}

/// How the report in `dir` was written, read from its marker; `None` when `dir` holds no
/// marker that lumiere wrote.
pub fn written_as(dir: &Path) -> Option<Written> {
    let text = std::fs::read_to_string(dir.join(MARKER)).ok()?;
    let mut lines = text.lines();
    if lines.next() != Some(MARKER_TITLE) {
        return None;
    }
    let second = lines.next()?;
    [Written::Alone, Written::OneOfSeveral]
        .into_iter()
        .find(|w| w.line() == second)
}

/// The fixed files of every report.
const FIXED: [&str; 6] = [
    "index.html",
    "image.png",
    "oracle.png",
    "heat-oracle.png",
    "edges.png",
    MARKER,
];

/// The names of the files [`write`] may write into its folder with `top` mistakes shown:
/// the fixed ones (the marker among them), and `mistake-N.png` and `heat-N.png` for N up
/// to `top`.
pub fn file_names(top: usize) -> Vec<String> {
    let mut names: Vec<String> = FIXED.map(String::from).to_vec();
    for k in 1..=top {
        names.push(format!("mistake-{k}.png"));
        names.push(format!("heat-{k}.png"));
    }
    names
}

/// Whether `name` is one of the per-mistake images a report writes, for some N:
/// `mistake-N.png` or `heat-N.png`, N a positive integer written without leading zeros.
pub fn is_mistake_image(name: &str) -> bool {
    ["mistake-", "heat-"].iter().any(|prefix| {
        name.strip_prefix(prefix)
            .and_then(|rest| rest.strip_suffix(".png"))
            .is_some_and(|n| !n.is_empty() && !n.starts_with('0') && n.bytes().all(|b| b.is_ascii_digit()))
    })
}

/// Whether `name` is a file some report writes, with any number of mistakes shown.
fn is_report_file(name: &str) -> bool {
    FIXED.contains(&name) || is_mistake_image(name)
}

/// Removes from `dir` the per-mistake images ([`is_mistake_image`]) that are not in
/// `written`: those of an earlier report with more mistakes shown.
fn remove_stale(dir: &Path, written: &[PathBuf]) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let name = entry.file_name();
        let stale = name.to_str().is_some_and(is_mistake_image)
            && entry.file_type()?.is_file()
            && !written.iter().any(|w| w.file_name() == Some(name.as_os_str()));
        if stale {
            std::fs::remove_file(entry.path())?;
        }
    }
    Ok(())
}

/// Removes the files a report writes ([`is_report_file`]) from `folder`, but the files
/// `keep` (canonical paths), the marker last (a folder half cleared is still known as a
/// report); then the folder itself when `remove_folder` and nothing else is left in it.
/// Returns whether the folder was removed.
fn clear(folder: &Path, remove_folder: bool, keep: &[PathBuf]) -> std::io::Result<bool> {
    for entry in std::fs::read_dir(folder)? {
        let entry = entry?;
        let name = entry.file_name();
        let ours = name.to_str().is_some_and(|n| is_report_file(n) && n != MARKER);
        let kept = || entry.path().canonicalize().is_ok_and(|p| keep.contains(&p));
        if ours && entry.file_type()?.is_file() && !kept() {
            std::fs::remove_file(entry.path())?;
        }
    }
    std::fs::remove_file(folder.join(MARKER))?;
    if !remove_folder || std::fs::read_dir(folder)?.next().is_some() {
        return Ok(false);
    }
    std::fs::remove_dir(folder)?;
    Ok(true)
}

/// What [`remove_stale_reports`] did to an earlier report.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Stale {
    /// The folder and its files removed.
    Removed(PathBuf),
    /// The report's files removed; the folder kept, with files of someone else's in it.
    Cleared(PathBuf),
}

/// Removes the reports an earlier `--report dir` left in `dir` that this run, which wrote
/// the report folders `current`, does not write: each folder of `dir` written as one of
/// several ([`Written::OneOfSeveral`]) that is not in `current`, and the report of one
/// image written into `dir` itself when `dir` is not in `current`. Only folders whose
/// marker lumiere wrote are touched, and in them only the files a report writes, but the
/// run's `inputs` (a report's `image.png` diagnosed again stays); a folder is removed when
/// nothing else is left in it, and kept (without its marker) otherwise. Symbolic links are
/// not followed. Returns what it did, folders in name order.
pub fn remove_stale_reports(dir: &Path, current: &[PathBuf], inputs: &[&Path]) -> std::io::Result<Vec<Stale>> {
    let keep: Vec<PathBuf> = inputs.iter().filter_map(|i| i.canonicalize().ok()).collect();
    let mut stale = Vec::new();
    if !current.iter().any(|c| c == dir) && written_as(dir) == Some(Written::Alone) {
        clear(dir, false, &keep)?;
        stale.push(Stale::Cleared(dir.to_path_buf()));
    }
    let mut folders = Vec::new();
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let folder = entry.path();
        if entry.file_type()?.is_dir()
            && !current.contains(&folder)
            && written_as(&folder) == Some(Written::OneOfSeveral)
        {
            folders.push(folder);
        }
    }
    folders.sort();
    for folder in folders {
        stale.push(if clear(&folder, true, &keep)? {
            Stale::Removed(folder)
        } else {
            Stale::Cleared(folder)
        });
    }
    Ok(stale)
}

/// Writes the report into `dir` (which must exist), marked as `how` it is written, and
/// removes the per-mistake images an earlier report left there that this one does not
/// reference; returns the files written, each named in [`file_names`].
pub fn write(
    dir: &Path,
    d: &Diagnosis,
    scene: &str,
    image: &str,
    top: usize,
    how: Written,
) -> std::io::Result<Vec<PathBuf>> {
    let (w, h) = (d.grid.width, d.grid.height);
    let mut written = Vec::new();
    let marker = dir.join(MARKER);
    write_atomic(&marker, marker_text(how, scene, image).as_bytes())?;
    written.push(marker);
    let mut png = |name: &str, rgb: &[u8]| -> std::io::Result<()> {
        let bytes = encode_png(w, h, rgb).map_err(std::io::Error::other)?;
        let path = dir.join(name);
        write_atomic(&path, &bytes)?;
        written.push(path);
        Ok(())
    };
    png("image.png", &d.image_rgb)?;
    png("oracle.png", &d.oracle_rgb)?;
    png("heat-oracle.png", &heat_map(&d.image_rgb, &d.oracle_rgb, 16))?;
    let edges: Vec<u8> = d.edge_mask.iter().flat_map(|&e| [if e { 255 } else { 0 }; 3]).collect();
    png("edges.png", &edges)?;
    let best: Vec<_> = d.top(top).collect();
    for (k, c) in best.iter().enumerate() {
        png(&format!("mistake-{}.png", k + 1), &c.rgb)?;
        png(&format!("heat-{}.png", k + 1), &heat_map(&d.image_rgb, &c.rgb, 16))?;
    }

    let mut html = String::new();
    let verdict = d.verdict.words();
    let _ = write!(
        html,
        "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>lumiere diagnose</title>\n\
         <style>body{{font-family:sans-serif;margin:2em}}img{{image-rendering:pixelated;width:320px;border:1px solid #888}}\
         td,th{{padding:2px 8px;text-align:left}}figure{{display:inline-block;margin:4px}}</style></head><body>\n\
         <h1>Diagnosis of {} against {}</h1>\n<p>{} x {} pixels; judged on {} ({} x {}), {} on edges apart, {} undrawn (transparent black) apart; \
         tolerance {} levels, at most {:.4} % beyond.</p>\n<p><b>Verdict: {}</b>. The oracle: {} of {} pixels beyond the tolerance \
         ({:.4} %), RMS {:.4}; {} beyond any sampling of the pixel.</p>\n",
        escape(image),
        escape(scene),
        d.width,
        d.height,
        d.grid.describe(),
        w,
        h,
        d.edges,
        d.undrawn,
        d.tolerance,
        100.0 * d.max_fraction,
        verdict,
        d.oracle.beyond,
        d.oracle.judged,
        100.0 * d.oracle.fraction,
        d.oracle.rms,
        d.beyond_sampling
    );
    if d.also_differs
        && let Some(first) = d.top(1).next()
    {
        let _ = writeln!(
            html,
            "<p><b>Something else differs too</b>: {} of {} pixels stay beyond the tolerance after {}; fix it, render again and diagnose again.</p>",
            first.score.beyond, first.score.judged, first.name
        );
    }
    if d.black {
        html += "<p><b>The image is black (every pixel 0) where the oracle's is not.</b></p>\n";
    }
    html += "<h2>Gains per term</h2>\n<table><tr><th>term</th><th>gain</th></tr>\n";
    for g in &d.gains {
        let _ = writeln!(html, "<tr><td>{}</td><td>{}</td></tr>", escape(g.term), g.label());
    }
    html += "</table>\n";
    if d.findings_shown {
        for f in &d.findings {
            let _ = writeln!(html, "<p>{}</p>", escape(f));
        }
    }
    html += "<h2>Images</h2>\n";
    for (file, caption) in [
        ("image.png", "the image"),
        ("oracle.png", "the oracle"),
        ("heat-oracle.png", "image against oracle"),
        ("edges.png", "edges (left out)"),
    ] {
        let _ = writeln!(
            html,
            "<figure><img src=\"{file}\"><figcaption>{caption}</figcaption></figure>"
        );
    }
    html += "<h2>Ranking</h2>\n<table><tr><th>#</th><th>mistake</th><th>what it does</th><th>pixels beyond</th><th>RMS</th><th>pixels it fixes</th><th>region</th></tr>\n";
    for (k, c) in d.ranking.iter().enumerate() {
        let region = c.fixes.as_ref().map_or(String::from("-"), |r| {
            format!("x {}..{}, y {}..{}", r.x[0], r.x[1], r.y[0], r.y[1])
        });
        let _ = writeln!(
            html,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.4}</td><td>{}</td><td>{}</td></tr>",
            k + 1,
            c.name,
            escape(&what_it_does(c)),
            c.score.beyond,
            c.score.rms,
            c.fixes.as_ref().map_or(0, |r| r.pixels),
            region
        );
    }
    html += "</table>\n";
    for (k, c) in best.iter().enumerate() {
        let _ = writeln!(
            html,
            "<h3>{}. {}</h3>\n<figure><img src=\"mistake-{n}.png\"><figcaption>rendered with the mistake</figcaption></figure>\
             <figure><img src=\"heat-{n}.png\"><figcaption>image against it</figcaption></figure>",
            k + 1,
            c.name,
            n = k + 1
        );
    }
    for c in &d.within_sampling {
        let _ = writeln!(
            html,
            "<p>Within sampling, the image is closer with {}: {} ({} pixels beyond, RMS {:.4}).</p>",
            c.name,
            escape(&what_it_does(c)),
            c.score.beyond,
            c.score.rms
        );
    }
    if !d.not_visible.is_empty() {
        let _ = writeln!(
            html,
            "<p>No visible difference on this scene: {}.</p>",
            d.not_visible.join(", ")
        );
    }
    html += "</body></html>\n";
    let path = dir.join("index.html");
    write_atomic(&path, html.as_bytes())?;
    written.push(path);
    remove_stale(dir, &written)?;
    Ok(written)
}

/// A candidate's description, and for the fitted one what the fit found.
fn what_it_does(c: &Candidate) -> String {
    match &c.fitted {
        Some(fit) => format!("{}; fitted: {}", c.description, fit.words),
        None => c.description.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mistake_images_are_named_as_written() {
        for name in ["mistake-1.png", "heat-3.png", "mistake-12.png"] {
            assert!(is_mistake_image(name), "{name}");
        }
        for name in [
            "heat-oracle.png",
            "mistake-0.png",
            "mistake-01.png",
            "mistake-.png",
            "mistake-1.jpg",
            "mistake-1.png.bak",
            "my-mistake-1.png",
            "image.png",
        ] {
            assert!(!is_mistake_image(name), "{name}");
        }
    }
}
