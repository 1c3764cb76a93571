//! The HTML report of a diagnosis (`lumiere diagnose --report DIR`): `index.html` with the
//! verdict, the gains and the ranking, and beside it, on the judged grid, the image
//! (`image.png`), the oracle (`oracle.png`), their difference (`heat-oracle.png`), the edge
//! mask (`edges.png`) and for each of the top mistakes its render (`mistake-N.png`) and the
//! image's difference from it (`heat-N.png`). Heat-maps are black where equal, white at
//! 16 levels or more ([`crate::compare::heat_map`]). A folder written before holds only
//! what the last report references: the mistakes' images past its top are removed
//! ([`is_mistake_image`]); no other file is touched.

use super::{Candidate, Diagnosis};
use crate::compare::heat_map;
use crate::film::{encode_png, write_atomic};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Escapes text for HTML.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// The names of the files [`write`] may write into its folder with `top` mistakes shown:
/// the fixed ones, and `mistake-N.png` and `heat-N.png` for N up to `top`.
pub fn file_names(top: usize) -> Vec<String> {
    let fixed = ["index.html", "image.png", "oracle.png", "heat-oracle.png", "edges.png"];
    let mut names: Vec<String> = fixed.map(String::from).to_vec();
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

/// Writes the report into `dir` (which must exist) and removes the per-mistake images an
/// earlier report left there that this one does not reference; returns the files written,
/// each named in [`file_names`].
pub fn write(dir: &Path, d: &Diagnosis, scene: &str, image: &str, top: usize) -> std::io::Result<Vec<PathBuf>> {
    let (w, h) = (d.grid.width, d.grid.height);
    let mut written = Vec::new();
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
        if d.grid.stride == 1 {
            "every pixel".to_string()
        } else {
            format!("every {}th pixel of every {}th row", d.grid.stride, d.grid.stride)
        },
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
