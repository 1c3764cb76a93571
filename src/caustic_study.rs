//! `lumiere study caustics`: render time against error of the caustic pass, over the number
//! of photons and the estimate's radius. Each configuration renders the scene with its
//! `[caustics]` table changed to it (its filter and bounces kept), and is compared with a
//! converged reference the study renders itself: by default 10^7 photons and the smallest
//! radius studied, at the same size, samples per pixel and seed, so the pixel jitter and
//! every ray are the same and only the photons differ. The reference's photons draw from
//! streams of their own (the photons' `seed` is the image's plus one), so its noise is
//! independent of every configuration's.
//!
//! A larger radius averages more photons (less noise) over a wider disk (more blur: bias);
//! more photons lower the noise at any radius and cost time in the photon pass and in every
//! estimate. The plot draws RMSE against time on log-log axes, one line per radius.

use crate::film::Film;
use crate::scene::{CausticSettings, Scene};
use crate::study::{BLACK, Error, LogLog, WHITE, dot, error, line, render_timed, study_files};
use crate::text::draw_text;
use image::{Rgb, RgbImage};

/// One setting of the caustic pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    pub photons: u64,
    pub radius: f64,
}

/// One configuration's measurements.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    pub config: Config,
    /// Median wall time (photon pass, world and render), seconds.
    pub seconds: f64,
    pub error: Error,
}

/// What to measure.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub photons: Vec<u64>,
    pub radii: Vec<f64>,
    pub repeats: u32,
    pub reference: Config,
}

/// A whole study.
#[derive(Clone, Debug, PartialEq)]
pub struct Study {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub seed: u64,
    pub repeats: u32,
    pub reference: Config,
    pub reference_seconds: f64,
    pub rows: Vec<Row>,
}

/// `scene` (which has a `[caustics]` table) with its caustic pass set to `config`; for the
/// reference, the photons' streams seeded apart from every configuration's.
pub fn configured(scene: &Scene, base: &CausticSettings, config: Config, reference: bool) -> Scene {
    let mut s = scene.clone();
    s.settings.caustics = Some(CausticSettings {
        photons: config.photons,
        radius: config.radius,
        seed: reference.then(|| base.seed.unwrap_or(scene.settings.seed).wrapping_add(1)),
        ..*base
    });
    s
}

/// Runs the study on the current rayon pool; `progress` hears each step. The scene must have
/// a `[caustics]` table (its filter and bounces are kept).
pub fn run(scene: &Scene, plan: &Plan, progress: &mut dyn FnMut(&str)) -> Result<(Study, Film), String> {
    let base = scene
        .settings
        .caustics
        .ok_or("the scene has no [caustics] table: nothing to study")?;
    let s = &scene.settings;
    progress(&format!(
        "reference: {} photons, radius {}",
        plan.reference.photons, plan.reference.radius
    ));
    let (reference, reference_seconds, _) = render_timed(&configured(scene, &base, plan.reference, true), 1);
    let mut rows = Vec::new();
    for &radius in &plan.radii {
        for &photons in &plan.photons {
            let config = Config { photons, radius };
            let (film, seconds, _) = render_timed(&configured(scene, &base, config, false), plan.repeats);
            let row = Row {
                config,
                seconds,
                error: error(&film, &reference),
            };
            progress(&format!(
                "radius {radius:<8} {photons:>9} photons: {seconds:>8.3} s, RMSE {:.4}, max {}, {:.3} % within 1 level",
                row.error.rmse,
                row.error.max_diff,
                100.0 * row.error.within_one
            ));
            rows.push(row);
        }
    }
    let study = Study {
        width: s.width,
        height: s.height,
        spp: s.samples_per_pixel,
        seed: s.seed,
        repeats: plan.repeats,
        reference: plan.reference,
        reference_seconds,
        rows,
    };
    Ok((study, reference))
}

/// The CSV columns, in order.
pub const CSV_COLUMNS: [&str; 8] = [
    "photons",
    "radius",
    "seconds",
    Error::CSV_COLUMNS[0],
    Error::CSV_COLUMNS[1],
    Error::CSV_COLUMNS[2],
    Error::CSV_COLUMNS[3],
    Error::CSV_COLUMNS[4],
];

/// The measurements as CSV, one row per configuration.
pub fn csv(study: &Study) -> String {
    let mut out = CSV_COLUMNS.join(",") + "\n";
    for r in &study.rows {
        out += &format!(
            "{},{},{:.6},{}\n",
            r.config.photons,
            r.config.radius,
            r.seconds,
            r.error.csv_fields()
        );
    }
    out
}

/// The settings that keep 99.9 % of the pixels within 1 level of the reference, cheapest
/// first.
pub fn within_one_level(study: &Study) -> Vec<&Row> {
    let mut ok: Vec<&Row> = study.rows.iter().filter(|r| r.error.within_one >= 0.999).collect();
    ok.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
    ok
}

/// The report as Markdown: the measurements, then the settings within 1 level on 99.9 % of
/// the pixels and their cost.
pub fn report(study: &Study) -> String {
    let mut out = format!(
        "{} x {} pixels, {} samples per pixel, seed {}, median of {} run(s) per configuration.\n\
         Reference: {} photons, radius {} ({:.3} s), its photons seeded apart.\n",
        study.width,
        study.height,
        study.spp,
        study.seed,
        study.repeats,
        study.reference.photons,
        study.reference.radius,
        study.reference_seconds
    );
    out += "\n| photons | radius | time (s) | RMSE | RMSE unrounded | max diff | within 1 level |\n";
    out += "|---|---|---|---|---|---|---|\n";
    for row in &study.rows {
        let e = &row.error;
        out += &format!(
            "| {} | {} | {:.3} | {:.4} | {:.4} | {} | {:.3} % |\n",
            row.config.photons,
            row.config.radius,
            row.seconds,
            e.rmse,
            e.rmse_unrounded,
            e.max_diff,
            100.0 * e.within_one
        );
    }
    let ok = within_one_level(study);
    out += "\nSettings with 99.9 % of the pixels within 1 level of the reference, cheapest first:\n\n";
    if ok.is_empty() {
        out += "none of the settings measured.\n";
    } else {
        out += "| photons | radius | time (s) |\n|---|---|---|\n";
        for r in ok {
            out += &format!("| {} | {} | {:.3} |\n", r.config.photons, r.config.radius, r.seconds);
        }
    }
    out
}

/// A colour per radius, in the order the radii were measured.
const PALETTE: [Rgb<u8>; 6] = [
    Rgb([31, 119, 180]),
    Rgb([214, 39, 40]),
    Rgb([44, 160, 44]),
    Rgb([148, 103, 189]),
    Rgb([255, 127, 14]),
    Rgb([140, 86, 75]),
];

/// The radii measured, in order of appearance.
fn radii(study: &Study) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for r in &study.rows {
        if !out.contains(&r.config.radius) {
            out.push(r.config.radius);
        }
    }
    out
}

/// Log-log plot of RMSE (8-bit levels) against time, one line per radius, its points in
/// order of the photon count. Configurations identical to the reference cannot be drawn.
pub fn plot(study: &Study) -> RgbImage {
    let (w, h) = (960u32, 600u32);
    let (left, right, top, bottom) = (80.0, 700.0, 50.0, 530.0);
    let mut img = RgbImage::from_pixel(w, h, WHITE);
    let drawable = |r: &&Row| r.error.rmse > 0.0 && r.seconds > 0.0;
    let pts: Vec<(f64, f64)> = study
        .rows
        .iter()
        .filter(drawable)
        .map(|r| (r.seconds, r.error.rmse))
        .collect();
    let axes = LogLog::draw(&mut img, &pts, (left, right, top, bottom));
    let title = format!(
        "Caustics: RMSE against render time ({} x {}, {} spp; reference {} photons, radius {})",
        study.width, study.height, study.spp, study.reference.photons, study.reference.radius
    );
    draw_text(&mut img, 10, 12, &title, 1, BLACK);
    draw_text(&mut img, 10, 30, "RMSE (8-bit levels, log)", 1, BLACK);
    draw_text(&mut img, 300, bottom as u32 + 28, "render time (s, log)", 1, BLACK);
    let mut ly = top as u32 + 10;
    draw_text(&mut img, right as u32 + 20, ly, "estimate radius", 1, BLACK);
    ly += 20;
    for (k, radius) in radii(study).into_iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let mut c: Vec<&Row> = study
            .rows
            .iter()
            .filter(|r| r.config.radius == radius)
            .filter(drawable)
            .collect();
        c.sort_by_key(|r| r.config.photons);
        let c: Vec<(f64, f64)> = c.iter().map(|r| (axes.x(r.seconds), axes.y(r.error.rmse))).collect();
        for s in c.windows(2) {
            line(&mut img, s[0], s[1], color, None);
        }
        for &(x, y) in &c {
            dot(&mut img, x, y, 3, color);
        }
        let (lx, lyf) = (right + 20.0, ly as f64 + 4.0);
        line(&mut img, (lx, lyf), (lx + 40.0, lyf), color, None);
        dot(&mut img, lx + 20.0, lyf, 3, color);
        draw_text(&mut img, right as u32 + 70, ly, &format!("r = {radius}"), 1, BLACK);
        ly += 18;
    }
    let mut counts: Vec<u64> = study.rows.iter().map(|r| r.config.photons).collect();
    counts.sort_unstable();
    counts.dedup();
    ly += 10;
    draw_text(&mut img, right as u32 + 20, ly, "photons along each line:", 1, BLACK);
    for n in counts {
        ly += 14;
        draw_text(&mut img, right as u32 + 28, ly, &n.to_string(), 1, BLACK);
    }
    img
}

/// The files of a study, in the order they are written: `study.csv`, `study.png` (the
/// plot), `study.md` (the report) and `reference.png`, each with its bytes.
pub fn outputs(study: &Study, reference: &Film) -> Result<Vec<(&'static str, Vec<u8>)>, String> {
    study_files(csv(study), &plot(study), report(study), reference)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(photons: u64, radius: f64, seconds: f64, within_one: f64) -> Row {
        Row {
            config: Config { photons, radius },
            seconds,
            error: Error {
                rmse: 1.0,
                rmse_unrounded: 0.9,
                max_diff: 3,
                within_one,
            },
        }
    }

    #[test]
    fn the_settings_within_one_level_are_listed_cheapest_first() {
        let study = Study {
            width: 4,
            height: 3,
            spp: 1,
            seed: 42,
            repeats: 1,
            reference: Config {
                photons: 1000,
                radius: 0.1,
            },
            reference_seconds: 1.0,
            rows: vec![
                row(10, 0.1, 0.5, 0.99),
                row(100, 0.1, 0.9, 0.9995),
                row(100, 0.2, 0.7, 0.999),
            ],
        };
        let ok: Vec<(u64, f64)> = within_one_level(&study)
            .iter()
            .map(|r| (r.config.photons, r.config.radius))
            .collect();
        assert_eq!(ok, [(100, 0.2), (100, 0.1)]);
        let report = report(&study);
        assert!(
            report.contains("| 100 | 0.2 | 0.700 |\n| 100 | 0.1 | 0.900 |\n"),
            "{report}"
        );
        assert_eq!(
            csv(&study).lines().nth(1),
            Some("10,0.1,0.500000,1.000000,0.900000,3,0.990000,48.131")
        );
        let files = outputs(&study, &Film::new(4, 3)).unwrap();
        let names: Vec<&str> = files.iter().map(|f| f.0).collect();
        assert_eq!(names, ["study.csv", "study.png", "study.md", "reference.png"]);
    }
}
