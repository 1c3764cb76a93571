//! `lumiere study soft-shadows`: render time against error for an area light (chapter 7.4b,
//! "La source de lumière à multiple points ponctuelles"), over the number of points N, the
//! placement (chapter, uniform, stratified, fibonacci) and the mode (fixed, per_sample).
//!
//! Every configuration renders the scene with the first area light changed to it, and is
//! compared with a converged reference the study renders itself: by default N = 4096
//! `stratified` points drawn afresh for every pixel sample (`per_sample`), at the same size,
//! samples per pixel and seed, so the pixel jitter is the same and only the light's sampling
//! differs. The reference is unbiased (each Latin-hypercube point is uniform over the area)
//! and its random streams are independent of every configuration's: its area light is moved
//! one place down the light list (a black ambient light is inserted before it; the points'
//! streams are keyed by the light's index). `--check-reference` renders a second reference
//! with 2N points and reports their difference: the two are independent, so that difference
//! bounds the reference's own error.
//!
//! The plot is drawn with the `image` crate and the 8x8 bitmap glyphs the contact sheets
//! use (no system fonts): log-log, one line per (placement, mode), colour = placement,
//! solid = fixed, dashed = per_sample.

use crate::area_light::PointMode;
use crate::compare::compare_rgb8;
use crate::film::{Film, clamp_unit, encode_png};
use crate::light::Light;
use crate::placement::Placement;
use crate::render::render;
use crate::scene::Scene;
use crate::text::draw_text;
use crate::world::World;
use glam::DVec3;
use image::{Rgb, RgbImage};
use std::time::Instant;

/// One way of drawing the light's points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Config {
    pub placement: Placement,
    pub mode: PointMode,
    pub points: u32,
}

/// Name of a placement as in scene files.
pub fn placement_name(p: Placement) -> &'static str {
    match p {
        Placement::Chapter => "chapter",
        Placement::Uniform => "uniform",
        Placement::Stratified => "stratified",
        Placement::Fibonacci => "fibonacci",
    }
}

/// Name of a mode as in scene files.
pub fn mode_name(m: PointMode) -> &'static str {
    match m {
        PointMode::Fixed => "fixed",
        PointMode::PerSample => "per_sample",
    }
}

/// The mode of a scene-file name (`fixed`, `per_sample`).
pub fn parse_mode(name: &str) -> Option<PointMode> {
    match name {
        "fixed" => Some(PointMode::Fixed),
        "per_sample" => Some(PointMode::PerSample),
        _ => None,
    }
}

/// Parses a comma-separated list of placements (in the order given, duplicates removed).
pub fn parse_placements(text: &str) -> Result<Vec<Placement>, String> {
    parse_list(
        "placements",
        text,
        Placement::parse,
        "chapter, uniform, stratified, fibonacci",
    )
}

/// Parses a comma-separated list of modes (in the order given, duplicates removed).
pub fn parse_modes(text: &str) -> Result<Vec<PointMode>, String> {
    parse_list("modes", text, parse_mode, "fixed, per_sample")
}

fn parse_list<T: PartialEq>(
    flag: &str,
    text: &str,
    parse: fn(&str) -> Option<T>,
    names: &str,
) -> Result<Vec<T>, String> {
    let mut out = Vec::new();
    for item in text.split(',').map(str::trim) {
        let v = parse(item).ok_or_else(|| format!("--{flag}: unknown {item:?}; expected some of {names}"))?;
        if !out.contains(&v) {
            out.push(v);
        }
    }
    Ok(out)
}

/// Index of the first area light of a scene.
pub fn first_area_light(scene: &Scene) -> Option<usize> {
    scene.lights.iter().position(|l| matches!(l, Light::Area(_)))
}

/// The scene with area light `light` drawing its points as `config` says. With `shift`, a
/// black ambient light is inserted before it, so its index, and with it every random stream
/// of its points, differs from the unshifted scene's (the image's distribution does not).
pub fn configured(scene: &Scene, light: usize, config: Config, shift: bool) -> Scene {
    let mut s = scene.clone();
    let Light::Area(area) = &mut s.lights[light] else {
        panic!("light {light} is not an area light");
    };
    area.count = config.points;
    area.placement = config.placement;
    area.mode = config.mode;
    if shift {
        s.lights.insert(light, Light::Ambient { color: DVec3::ZERO });
    }
    s
}

/// Renders `scene` `repeats` times (on the current rayon pool); the film, the median wall
/// time of building the world and rendering, and the shadow rays traced.
pub fn render_timed(scene: &Scene, repeats: u32) -> (Film, f64, u64) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let world = World::new(scene);
        let (film, stats) = render(&world, &|| {});
        times.push(start.elapsed().as_secs_f64());
        last = Some((film, stats.counts.shadow));
    }
    times.sort_by(f64::total_cmp);
    let (film, shadow) = last.expect("at least one render");
    (film, times[times.len() / 2], shadow)
}

/// Differences between an image and the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Error {
    /// RMS of the per-channel 8-bit differences (as `lumiere compare`).
    pub rmse: f64,
    /// RMS of the per-channel differences before rounding to 8 bits (clamped to [0, 1],
    /// in levels): no rounding floor.
    pub rmse_unrounded: f64,
    /// Largest per-channel 8-bit difference.
    pub max_diff: u8,
    /// Fraction of the pixels with every channel within 1 level.
    pub within_one: f64,
}

impl Error {
    /// The CSV columns of an error, as [`Error::csv_fields`] writes them (both studies' CSV
    /// end with them).
    pub const CSV_COLUMNS: [&str; 5] = ["rmse", "rmse_unrounded", "max_diff", "within_1_level", "psnr_db"];

    /// The error's CSV fields, in the order of [`Error::CSV_COLUMNS`]; the PSNR from the
    /// RMS as `lumiere compare` gives it.
    pub fn csv_fields(&self) -> String {
        let psnr = crate::compare::psnr_db(self.rmse * self.rmse);
        format!(
            "{:.6},{:.6},{},{:.6},{:.3}",
            self.rmse, self.rmse_unrounded, self.max_diff, self.within_one, psnr
        )
    }
}

/// `a` against the reference `b` (same size).
pub fn error(a: &Film, b: &Film) -> Error {
    let c = compare_rgb8(&a.to_rgb8(), &b.to_rgb8(), a.width, a.height, 1);
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |i| 255.0 * (clamp_unit(p[i]) - clamp_unit(q[i]))))
        .map(|d| d * d)
        .sum();
    let total = a.pixels.len().max(1) as f64;
    Error {
        rmse: c.rms,
        rmse_unrounded: (sum / (3.0 * total)).sqrt(),
        max_diff: c.max_diff,
        within_one: 1.0 - c.differing_pixels as f64 / total,
    }
}

/// One configuration's measurements.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    pub config: Config,
    /// Median wall time (world + render), seconds.
    pub seconds: f64,
    pub shadow_rays: u64,
    pub error: Error,
}

/// The reference and, with `--check-reference`, how far one with 2N points is from it.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    pub config: Config,
    pub seconds: f64,
    pub check: Option<(u32, Error)>,
}

/// A whole study.
#[derive(Clone, Debug, PartialEq)]
pub struct Study {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub seed: u64,
    pub repeats: u32,
    pub reference: Reference,
    pub rows: Vec<Row>,
}

/// What to measure.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub points: Vec<u32>,
    pub placements: Vec<Placement>,
    pub modes: Vec<PointMode>,
    pub repeats: u32,
    pub reference: Config,
    pub check_reference: bool,
}

/// Runs the study on the current rayon pool; `progress` hears each step.
pub fn run(scene: &Scene, light: usize, plan: &Plan, progress: &mut dyn FnMut(&str)) -> (Study, Film) {
    let s = &scene.settings;
    progress(&format!(
        "reference: {} {} N = {}",
        placement_name(plan.reference.placement),
        mode_name(plan.reference.mode),
        plan.reference.points
    ));
    let (reference, ref_seconds, _) = render_timed(&configured(scene, light, plan.reference, true), 1);
    let check = plan.check_reference.then(|| {
        let twice = Config {
            points: plan.reference.points.saturating_mul(2),
            ..plan.reference
        };
        progress(&format!("reference check: N = {}", twice.points));
        let (film, _, _) = render_timed(&configured(scene, light, twice, true), 1);
        (twice.points, error(&film, &reference))
    });
    let mut rows = Vec::new();
    for &mode in &plan.modes {
        for &placement in &plan.placements {
            for &points in &plan.points {
                let config = Config {
                    placement,
                    mode,
                    points,
                };
                let (film, seconds, shadow_rays) = render_timed(&configured(scene, light, config, false), plan.repeats);
                let row = Row {
                    config,
                    seconds,
                    shadow_rays,
                    error: error(&film, &reference),
                };
                progress(&format!(
                    "{:<10} {:<10} N = {:>5}: {:>8.3} s, RMSE {:.4}, max {}",
                    placement_name(placement),
                    mode_name(mode),
                    points,
                    seconds,
                    row.error.rmse,
                    row.error.max_diff
                ));
                rows.push(row);
            }
        }
    }
    let study = Study {
        width: s.width,
        height: s.height,
        spp: s.samples_per_pixel,
        seed: s.seed,
        repeats: plan.repeats,
        reference: Reference {
            config: plan.reference,
            seconds: ref_seconds,
            check,
        },
        rows,
    };
    (study, reference)
}

/// The CSV columns, in order.
pub const CSV_COLUMNS: [&str; 10] = [
    "placement",
    "mode",
    "points",
    "seconds",
    "shadow_rays",
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
            "{},{},{},{:.6},{},{}\n",
            placement_name(r.config.placement),
            mode_name(r.config.mode),
            r.config.points,
            r.seconds,
            r.shadow_rays,
            r.error.csv_fields()
        );
    }
    out
}

/// The rows of one (placement, mode), in order of N.
fn curve(study: &Study, placement: Placement, mode: PointMode) -> Vec<&Row> {
    let mut rows: Vec<&Row> = study
        .rows
        .iter()
        .filter(|r| r.config.placement == placement && r.config.mode == mode)
        .collect();
    rows.sort_by_key(|r| r.config.points);
    rows
}

/// The (placement, mode) pairs measured, in order of appearance.
fn curves(study: &Study) -> Vec<(Placement, PointMode)> {
    let mut out = Vec::new();
    for r in &study.rows {
        let key = (r.config.placement, r.config.mode);
        if !out.contains(&key) {
            out.push(key);
        }
    }
    out
}

/// When a curve of `(time, error)` points (in order of N) first reaches `target` error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reach {
    /// Interpolated linearly in (log time, log error) between two consecutive points.
    At(f64),
    /// Already at or below the target at its first point (time of that point: an upper bound).
    AtMost(f64),
    /// Never reaches it.
    Never,
}

/// Time at which the curve first comes down to `target`.
pub fn time_to_reach(points: &[(f64, f64)], target: f64) -> Reach {
    let Some(&(t0, e0)) = points.first() else {
        return Reach::Never;
    };
    if e0 <= target {
        return Reach::AtMost(t0);
    }
    for w in points.windows(2) {
        let ((ta, ea), (tb, eb)) = (w[0], w[1]);
        if eb <= target && ea > target {
            if eb <= 0.0 {
                return Reach::AtMost(tb);
            }
            let ln = libm::log;
            let f = (ln(target) - ln(ea)) / (ln(eb) - ln(ea));
            return Reach::At(libm::exp(ln(ta) + f * (ln(tb) - ln(ta))));
        }
    }
    Reach::Never
}

/// The report: the measurements, the reference, and the two derived tables (speed-up over
/// `chapter`/`fixed` at equal RMSE, and the N needed to stay within 1 level), as Markdown.
pub fn report(study: &Study) -> String {
    let r = &study.reference;
    let mut out = format!(
        "{} x {} pixels, {} samples per pixel, seed {}, median of {} run(s) per configuration.\n\
         Reference: {} {} N = {} ({:.3} s).\n",
        study.width,
        study.height,
        study.spp,
        study.seed,
        study.repeats,
        placement_name(r.config.placement),
        mode_name(r.config.mode),
        r.config.points,
        r.seconds
    );
    if let Some((n, e)) = &r.check {
        out += &format!(
            "Reference check: the reference with N = {n} differs from it by RMSE {:.4} levels \
             ({:.4} before rounding), max {} levels, {:.3} % of pixels within 1 level.\n",
            e.rmse,
            e.rmse_unrounded,
            e.max_diff,
            100.0 * e.within_one
        );
    }
    out += "\n| placement | mode | N | time (s) | shadow rays | RMSE | RMSE unrounded | max diff | within 1 level |\n";
    out += "|---|---|---|---|---|---|---|---|---|\n";
    for row in &study.rows {
        let e = &row.error;
        out += &format!(
            "| {} | {} | {} | {:.3} | {} | {:.4} | {:.4} | {} | {:.3} % |\n",
            placement_name(row.config.placement),
            mode_name(row.config.mode),
            row.config.points,
            row.seconds,
            row.shadow_rays,
            e.rmse,
            e.rmse_unrounded,
            e.max_diff,
            100.0 * e.within_one
        );
    }
    let keys = curves(study);
    out += &speedups(study, "wall time", &|r| r.seconds, &|c| format!("{c:.3} s"));
    out += &speedups(
        study,
        "shadow rays (a cost that does not depend on the machine's load; it leaves out the \
         cost of drawing per_sample points)",
        &|r| r.shadow_rays as f64,
        &|c| format!("{c:.0}"),
    );
    out += "\nN needed (smallest measured) for max 8-bit difference <= 1, and for 99.9 % of the \
            pixels within 1 level, with the time of that render:\n\n";
    out += "| placement | mode | N for max <= 1 | N for 99.9 % within 1 |\n|---|---|---|---|\n";
    for (p, m) in &keys {
        let c = curve(study, *p, *m);
        let first = |ok: &dyn Fn(&Error) -> bool| {
            c.iter().find(|r| ok(&r.error)).map_or("not reached".to_string(), |r| {
                format!("{} ({:.3} s)", r.config.points, r.seconds)
            })
        };
        out += &format!(
            "| {} | {} | {} | {} |\n",
            placement_name(*p),
            mode_name(*m),
            first(&|e| e.max_diff <= 1),
            first(&|e| e.within_one >= 0.999)
        );
    }
    out
}

/// The speed-up table over chapter/fixed at equal RMSE, with `cost` (time or rays) as the
/// price of a render: for each chapter/fixed point, the cost each curve needs to come down
/// to its RMSE, interpolated in (log cost, log RMSE) between measured points.
fn speedups(study: &Study, what: &str, cost: &dyn Fn(&Row) -> f64, show: &dyn Fn(f64) -> String) -> String {
    let keys = curves(study);
    let base = curve(study, Placement::Chapter, PointMode::Fixed);
    if base.is_empty() || keys.len() < 2 {
        return String::new();
    }
    let mut out = format!(
        "\nSpeed-up over chapter/fixed at equal RMSE, by {what}: for each chapter/fixed point, \
         chapter's cost / the cost each curve needs to come down to its RMSE (interpolated in \
         log cost - log RMSE between measured points; \">=\" when a curve's first point is \
         already below it).\n\n"
    );
    out += "| chapter/fixed N | RMSE | cost |";
    for (p, m) in &keys {
        out += &format!(" {}/{} |", placement_name(*p), mode_name(*m));
    }
    out += "\n|---|---|---|";
    out += &"---|".repeat(keys.len());
    out += "\n";
    for b in &base {
        out += &format!("| {} | {:.4} | {} |", b.config.points, b.error.rmse, show(cost(b)));
        for (p, m) in &keys {
            let c: Vec<(f64, f64)> = curve(study, *p, *m).iter().map(|r| (cost(r), r.error.rmse)).collect();
            out += &match time_to_reach(&c, b.error.rmse) {
                Reach::At(t) => format!(" x{:.2} |", cost(b) / t),
                Reach::AtMost(t) => format!(" >= x{:.2} |", cost(b) / t),
                Reach::Never => " not reached |".to_string(),
            };
        }
        out += "\n";
    }
    out
}

// ---------------------------------------------------------------------------------------
// The plot.
// ---------------------------------------------------------------------------------------

pub(crate) const WHITE: Rgb<u8> = Rgb([255, 255, 255]);
pub(crate) const BLACK: Rgb<u8> = Rgb([0, 0, 0]);
pub(crate) const GRID: Rgb<u8> = Rgb([225, 225, 225]);
pub(crate) const MINOR: Rgb<u8> = Rgb([242, 242, 242]);

/// Colour of a placement's lines.
fn placement_color(p: Placement) -> Rgb<u8> {
    match p {
        Placement::Chapter => Rgb([214, 39, 40]),
        Placement::Uniform => Rgb([31, 119, 180]),
        Placement::Stratified => Rgb([44, 160, 44]),
        Placement::Fibonacci => Rgb([148, 103, 189]),
    }
}

/// Draws a 2-pixel-wide line; `dash` = (on, off) lengths in pixels for dashed lines.
pub(crate) fn line(img: &mut RgbImage, a: (f64, f64), b: (f64, f64), color: Rgb<u8>, dash: Option<(f64, f64)>) {
    let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
    let steps = (len * 2.0).ceil().max(1.0) as usize;
    for i in 0..=steps {
        let s = i as f64 / steps as f64;
        if let Some((on, off)) = dash
            && (s * len) % (on + off) >= on
        {
            continue;
        }
        let (x, y) = (a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1));
        dot(img, x, y, 1, color);
    }
}

/// A filled square of half-side `r` around `(x, y)`.
pub(crate) fn dot(img: &mut RgbImage, x: f64, y: f64, r: i64, color: Rgb<u8>) {
    let (cx, cy) = (x.round() as i64, y.round() as i64);
    for dy in -r..=r {
        for dx in -r..=r {
            let (px, py) = (cx + dx, cy + dy);
            if px >= 0 && py >= 0 && (px as u32) < img.width() && (py as u32) < img.height() {
                img.put_pixel(px as u32, py as u32, color);
            }
        }
    }
}

/// A decade's label: 0.001 ... 1000, else 1e-5 style.
pub(crate) fn decade_label(e: i32) -> String {
    if (-3..=3).contains(&e) {
        let v = 10f64.powi(e);
        if e < 0 {
            format!("{v:.*}", (-e) as usize)
        } else {
            format!("{v:.0}")
        }
    } else {
        format!("1e{e}")
    }
}

/// The frame of a log-log plot: whole decades around the points, mapped onto the pixels
/// `left..right` and `bottom..top`.
pub(crate) struct LogLog {
    x0: i32,
    x1: i32,
    y0: i32,
    y1: i32,
    frame: (f64, f64, f64, f64),
}

impl LogLog {
    /// Draws the grid (minor lines at 2..9 of each decade, decades labelled) and the frame
    /// that hold `pts` (positive `(x, y)`) into `img`, inside `(left, right, top, bottom)`.
    pub(crate) fn draw(img: &mut RgbImage, pts: &[(f64, f64)], frame: (f64, f64, f64, f64)) -> LogLog {
        let (left, right, top, bottom) = frame;
        let span = |v: &mut dyn Iterator<Item = f64>| {
            let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
            if lo.is_finite() {
                let (a, b) = (libm::floor(libm::log10(lo)), libm::ceil(libm::log10(hi)));
                (a as i32, (b as i32).max(a as i32 + 1))
            } else {
                (-1, 1)
            }
        };
        let (x0, x1) = span(&mut pts.iter().map(|p| p.0));
        let (y0, y1) = span(&mut pts.iter().map(|p| p.1));
        let axes = LogLog { x0, x1, y0, y1, frame };
        let (px, py) = (|t: f64| axes.x(t), |e: f64| axes.y(e));
        for d in x0..x1 {
            for k in 2..10 {
                let x = px(k as f64 * 10f64.powi(d));
                line(img, (x, top), (x, bottom), MINOR, None);
            }
        }
        for d in y0..y1 {
            for k in 2..10 {
                let y = py(k as f64 * 10f64.powi(d));
                line(img, (left, y), (right, y), MINOR, None);
            }
        }
        for d in x0..=x1 {
            let x = px(10f64.powi(d));
            line(img, (x, top), (x, bottom), GRID, None);
            let label = decade_label(d);
            let lx = (x - 4.0 * label.len() as f64).max(0.0) as u32;
            draw_text(img, lx, bottom as u32 + 8, &label, 1, BLACK);
        }
        for d in y0..=y1 {
            let y = py(10f64.powi(d));
            line(img, (left, y), (right, y), GRID, None);
            let label = decade_label(d);
            let lx = (left as u32).saturating_sub(8 * label.len() as u32 + 8);
            draw_text(img, lx, (y - 4.0).max(0.0) as u32, &label, 1, BLACK);
        }
        for (a, b) in [
            ((left, top), (right, top)),
            ((left, bottom), (right, bottom)),
            ((left, top), (left, bottom)),
            ((right, top), (right, bottom)),
        ] {
            line(img, a, b, BLACK, None);
        }
        axes
    }

    /// The pixel column of `t`.
    pub(crate) fn x(&self, t: f64) -> f64 {
        let (left, right, _, _) = self.frame;
        left + (libm::log10(t) - self.x0 as f64) / (self.x1 - self.x0) as f64 * (right - left)
    }

    /// The pixel row of `e`.
    pub(crate) fn y(&self, e: f64) -> f64 {
        let (_, _, top, bottom) = self.frame;
        bottom - (libm::log10(e) - self.y0 as f64) / (self.y1 - self.y0) as f64 * (bottom - top)
    }
}

/// Log-log plot of RMSE (8-bit levels) against time, one line per (placement, mode).
/// Configurations whose RMSE is 0 (identical to the reference) cannot be drawn and are left out.
pub fn plot(study: &Study) -> RgbImage {
    let (w, h) = (960u32, 600u32);
    let (left, right, top, bottom) = (80.0, 700.0, 50.0, 530.0);
    let mut img = RgbImage::from_pixel(w, h, WHITE);
    let pts: Vec<(f64, f64)> = study
        .rows
        .iter()
        .filter(|r| r.error.rmse > 0.0 && r.seconds > 0.0)
        .map(|r| (r.seconds, r.error.rmse))
        .collect();
    let axes = LogLog::draw(&mut img, &pts, (left, right, top, bottom));
    let (px, py) = (|t: f64| axes.x(t), |e: f64| axes.y(e));
    let title = format!(
        "Soft shadows: RMSE against render time ({} x {}, {} spp; reference {} {} N = {})",
        study.width,
        study.height,
        study.spp,
        placement_name(study.reference.config.placement),
        mode_name(study.reference.config.mode),
        study.reference.config.points
    );
    draw_text(&mut img, 10, 12, &title, 1, BLACK);
    draw_text(&mut img, 10, 30, "RMSE (8-bit levels, log)", 1, BLACK);
    draw_text(&mut img, 300, bottom as u32 + 28, "render time (s, log)", 1, BLACK);
    // Curves and legend.
    let mut ly = top as u32 + 10;
    draw_text(&mut img, right as u32 + 20, ly, "placement / mode", 1, BLACK);
    ly += 20;
    for (p, m) in curves(study) {
        let color = placement_color(p);
        let dash = (m == PointMode::PerSample).then_some((8.0, 5.0));
        let c: Vec<(f64, f64)> = curve(study, p, m)
            .iter()
            .filter(|r| r.error.rmse > 0.0 && r.seconds > 0.0)
            .map(|r| (px(r.seconds), py(r.error.rmse)))
            .collect();
        for s in c.windows(2) {
            line(&mut img, s[0], s[1], color, dash);
        }
        for &(x, y) in &c {
            dot(&mut img, x, y, 3, color);
            if m == PointMode::PerSample {
                dot(&mut img, x, y, 1, WHITE);
            }
        }
        let (lx, lyf) = (right + 20.0, ly as f64 + 4.0);
        line(&mut img, (lx, lyf), (lx + 40.0, lyf), color, dash);
        dot(&mut img, lx + 20.0, lyf, 3, color);
        if m == PointMode::PerSample {
            dot(&mut img, lx + 20.0, lyf, 1, WHITE);
        }
        draw_text(
            &mut img,
            right as u32 + 70,
            ly,
            &format!("{} / {}", placement_name(p), mode_name(m)),
            1,
            BLACK,
        );
        ly += 18;
    }
    let ns: Vec<String> = {
        let mut n: Vec<u32> = study.rows.iter().map(|r| r.config.points).collect();
        n.sort_unstable();
        n.dedup();
        n.iter().map(u32::to_string).collect()
    };
    ly += 10;
    draw_text(&mut img, right as u32 + 20, ly, "points along each line:", 1, BLACK);
    // The list of N, wrapped to the legend's width (8-pixel glyphs).
    let columns = ((w - right as u32 - 24) / 8) as usize;
    let mut lines = vec![String::from("N =")];
    for n in ns {
        let last = lines.last_mut().expect("one line at least");
        if last.len() + n.len() + 2 > columns {
            lines.push(format!("    {n},"));
        } else {
            last.push_str(&format!(" {n},"));
        }
    }
    if let Some(last) = lines.last_mut() {
        last.pop();
    }
    for line in &lines {
        ly += 14;
        draw_text(&mut img, right as u32 + 20, ly, line, 1, BLACK);
    }
    draw_text(&mut img, right as u32 + 20, ly + 20, "solid, filled: fixed", 1, BLACK);
    draw_text(
        &mut img,
        right as u32 + 20,
        ly + 34,
        "dashed, hollow: per_sample",
        1,
        BLACK,
    );
    img
}

/// The files of a study, in the order they are written: `study.csv`, `study.png` (the
/// plot), `study.md` (the report) and `reference.png`, each with its bytes.
pub fn outputs(study: &Study, reference: &Film) -> Result<Vec<(&'static str, Vec<u8>)>, String> {
    study_files(csv(study), &plot(study), report(study), reference)
}

/// A study's files from its CSV, plot, report and reference image: the names
/// [`outputs`] lists, the images encoded as PNG.
pub fn study_files(
    csv: String,
    plot: &RgbImage,
    report: String,
    reference: &Film,
) -> Result<Vec<(&'static str, Vec<u8>)>, String> {
    let plot_png =
        encode_png(plot.width(), plot.height(), plot.as_raw()).map_err(|e| format!("cannot encode the plot: {e}"))?;
    let reference_png = reference
        .encode_png()
        .map_err(|e| format!("cannot encode the reference: {e}"))?;
    Ok(vec![
        ("study.csv", csv.into_bytes()),
        ("study.png", plot_png),
        ("study.md", report.into_bytes()),
        ("reference.png", reference_png),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_csv_fields_by_hand() {
        // RMS 2 levels: PSNR = 20 log10(255 / 2) = 42.1102 dB.
        let e = Error {
            rmse: 2.0,
            rmse_unrounded: 1.5,
            max_diff: 7,
            within_one: 0.25,
        };
        assert_eq!(e.csv_fields(), "2.000000,1.500000,7,0.250000,42.110");
        assert_eq!(
            crate::caustic_study::CSV_COLUMNS.join(","),
            "photons,radius,seconds,rmse,rmse_unrounded,max_diff,within_1_level,psnr_db"
        );
    }

    #[test]
    fn placement_and_mode_lists() {
        assert_eq!(
            parse_placements("fibonacci, chapter,fibonacci"),
            Ok(vec![Placement::Fibonacci, Placement::Chapter])
        );
        assert_eq!(
            parse_placements("uniform,grid"),
            Err("--placements: unknown \"grid\"; expected some of chapter, uniform, stratified, fibonacci".into())
        );
        assert_eq!(parse_modes("per_sample"), Ok(vec![PointMode::PerSample]));
        assert_eq!(
            parse_modes("fixed,"),
            Err("--modes: unknown \"\"; expected some of fixed, per_sample".into())
        );
    }

    #[test]
    fn outputs_are_the_four_files_in_order() {
        let config = Config {
            placement: Placement::Uniform,
            mode: PointMode::Fixed,
            points: 4,
        };
        let error = Error {
            rmse: 2.0,
            rmse_unrounded: 1.9,
            max_diff: 9,
            within_one: 0.5,
        };
        let study = Study {
            width: 3,
            height: 2,
            spp: 1,
            seed: 7,
            repeats: 1,
            reference: Reference {
                config,
                seconds: 0.5,
                check: None,
            },
            rows: vec![Row {
                config,
                seconds: 0.25,
                shadow_rays: 24,
                error,
            }],
        };
        let mut film = Film::new(3, 2);
        film.pixels[4] = DVec3::new(1.0, 0.5, 0.0);
        let files = outputs(&study, &film).unwrap();
        let names: Vec<&str> = files.iter().map(|f| f.0).collect();
        assert_eq!(names, ["study.csv", "study.png", "study.md", "reference.png"]);
        assert_eq!(files[0].1, csv(&study).into_bytes());
        assert_eq!(files[2].1, report(&study).into_bytes());
        let decoded = |bytes: &[u8]| image::load_from_memory(bytes).unwrap().to_rgb8();
        assert_eq!(decoded(&files[1].1).dimensions(), (960, 600));
        let reference = decoded(&files[3].1);
        assert_eq!(reference.dimensions(), (3, 2));
        assert_eq!(reference.get_pixel(1, 1).0, [255, 128, 0]);
    }

    #[test]
    fn points_lists() {}

    #[test]
    fn interpolation_in_log_log() {
        // Error halves from 1 s to 4 s: e = 2 at 1 s, 1 at 4 s. In log-log, e = 2 t^(-1/2),
        // so e = sqrt(2) is reached at t = 2 s.
        let c = [(1.0, 2.0), (4.0, 1.0), (16.0, 0.5)];
        let Reach::At(t) = time_to_reach(&c, 2f64.sqrt()) else {
            panic!()
        };
        assert!((t - 2.0).abs() < 1e-12, "{t}");
        assert_eq!(time_to_reach(&c, 3.0), Reach::AtMost(1.0));
        assert_eq!(time_to_reach(&c, 0.1), Reach::Never);
        // 0.5 is reached exactly at the last point.
        let Reach::At(t) = time_to_reach(&c, 0.5) else { panic!() };
        assert!((t - 16.0).abs() < 1e-9);
    }

    #[test]
    fn decade_labels() {
        assert_eq!(decade_label(-2), "0.01");
        assert_eq!(decade_label(0), "1");
        assert_eq!(decade_label(2), "100");
        assert_eq!(decade_label(5), "1e5");
    }
}
