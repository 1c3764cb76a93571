//! Limits on what a scene or a command line may ask for, so an absurd request gets a clear
//! error instead of exhausting memory. Shared by scene validation and command-line overrides.

/// Largest image side.
pub const MAX_DIMENSION: u32 = 16_384;
/// Largest pixel count (the film holds 24 bytes a pixel: 32 Mpixel is 768 MiB).
pub const MAX_PIXELS: u64 = 1 << 25;
/// Largest samples per pixel (the sample index must fit 16 bits of the stream index).
pub const MAX_SAMPLES: u32 = 1024;
/// Largest recursion depth.
pub const MAX_DEPTH: u32 = 64;
/// Most shapes in a scene.
pub const MAX_OBJECTS: usize = 4_000_000;
/// Most lights in a scene.
pub const MAX_LIGHTS: usize = 10_000;
/// Most points in one area light (each is a shadow ray per shading point).
pub const MAX_LIGHT_POINTS: u32 = 100_000;
/// Most points over all area lights of a scene: a `fixed` light keeps its points in memory
/// (24 bytes each, so 240 MB at the limit) and every point is a shadow ray per shading point.
/// Without it, 10 000 lights of 100 000 points would ask for about 30 GB.
pub const MAX_TOTAL_LIGHT_POINTS: u64 = 10_000_000;
/// Most oscillators in one aperture light (each is a sine and a cosine per shading point);
/// they count towards [`MAX_TOTAL_LIGHT_POINTS`] too.
pub const MAX_OSCILLATORS: u64 = 100_000;
/// Most instants in an aperture light's time average over one period.
pub const MAX_PERIOD_ITERATION: u32 = 100_000;
/// Largest coordinate magnitude (beyond it f64 hit points lose all sub-unit precision).
pub const MAX_COORDINATE: f64 = 1e9;
/// Most triangles in one mesh file (each is an object, so [`MAX_OBJECTS`] bounds the
/// scene's total too).
pub const MAX_MESH_TRIANGLES: usize = MAX_OBJECTS;
/// Largest mesh file read (a mesh of 4 000 000 triangles is about 250 MB of `.obj`).
pub const MAX_MESH_FILE_BYTES: u64 = 1 << 30;
/// Smallest magnitude of a transform's scale factor (and of the singular values of its
/// matrix): below it a shape's local error bounds and sizes are stretched out of scale.
pub const MIN_SCALE: f64 = 1e-6;
/// Largest magnitude of a transform's scale factor (and of its matrix's entries).
pub const MAX_SCALE: f64 = 1e6;
/// Largest light colour channel.
pub const MAX_LIGHT: f64 = 1e6;
/// Largest specular exponent.
pub const MAX_SHININESS: f64 = 1e6;
/// Largest index of refraction.
pub const MAX_IOR: f64 = 10.0;
/// Most photons of a caustic pass (each is stored in 48 bytes: 480 MB at the limit).
pub const MAX_PHOTONS: u64 = 10_000_000;
/// Most specular bounces of a photon.
pub const MAX_PHOTON_BOUNCES: u32 = 64;
/// Default number of specular bounces of a photon.
pub const DEFAULT_PHOTON_BOUNCES: u32 = 8;
/// Default radius of the caustic estimate (scene units: a tenth of the reference scene's
/// spheres' radius).
pub const DEFAULT_PHOTON_RADIUS: f64 = 0.075;
/// Default adaptive depth control threshold, in 8-bit levels.
pub const DEFAULT_ADAPTIVE_THRESHOLD: f64 = 0.25;

/// Whether every coordinate of `p` is finite and within [`MAX_COORDINATE`].
pub fn within_coordinates(p: glam::DVec3) -> bool {
    p.is_finite() && p.abs().max_element() <= MAX_COORDINATE
}

/// A number as messages show a limit: the shorter of its decimal and exponent forms, the
/// decimal one on a tie (`179`, `0.25`, `1e9`, `1e-6`, `-1e9`).
pub fn short(x: f64) -> String {
    let plain = x.to_string();
    let exponent = format!("{x:e}");
    if exponent.len() < plain.len() { exponent } else { plain }
}

pub fn check_dimension(v: u32) -> Result<(), String> {
    if v == 0 || v > MAX_DIMENSION {
        return Err(format!("must be in [1, {MAX_DIMENSION}] pixels, got {v}"));
    }
    Ok(())
}

pub fn check_pixel_count(w: u32, h: u32) -> Result<(), String> {
    let n = w as u64 * h as u64;
    if n > MAX_PIXELS {
        return Err(format!(
            "width x height must be at most {MAX_PIXELS} pixels, got {w} x {h} = {n}"
        ));
    }
    Ok(())
}

pub fn check_samples(v: u32) -> Result<(), String> {
    let n = (v as f64).sqrt().round() as u32;
    if v == 0 || v > MAX_SAMPLES || n * n != v {
        return Err(format!(
            "must be a perfect square (1, 4, 9, 16, ...) in [1, {MAX_SAMPLES}], got {v}"
        ));
    }
    Ok(())
}

pub fn check_depth(v: u32) -> Result<(), String> {
    if v == 0 || v > MAX_DEPTH {
        return Err(format!("must be in [1, {MAX_DEPTH}] (1 = no secondary rays), got {v}"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_are_shown_short() {
        for (x, shown) in [
            (179.0, "179"),
            (0.25, "0.25"),
            (100.0, "100"),
            (1e6, "1e6"),
            (MAX_COORDINATE, "1e9"),
            (-MAX_COORDINATE, "-1e9"),
            (MIN_SCALE, "1e-6"),
            (1e12, "1e12"),
            (0.0, "0"),
        ] {
            assert_eq!(short(x), shown);
        }
    }
}
