//! The image being made: per-pixel radiance, its 8-bit quantisation (clamp to [0, 1], no
//! gamma, as the course's renderer writes; or each colour first divided by its largest
//! channel, SIMRenderer's `division_factor`), the sRGB transfer function for images
//! encoded on request, and atomic PNG output.

use glam::DVec3;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Radiance per pixel, row 0 at the top, and how its colours go to 8 bits.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<DVec3>,
    pub normalization: Normalization,
}

/// How a pixel's colour is brought into [0, 1] before quantisation (SIMRenderer's
/// `color_normalization`, a global setting of its ray tracer, applied when it writes the
/// image): the radiance itself (PFM, EXR, shards) is not changed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Normalization {
    /// Each channel clamped to [0, 1] (the chapter's, and SIMRenderer's default).
    #[default]
    ClampChannel,
    /// The colour divided by its largest channel where that exceeds 1, keeping its hue;
    /// then clamped as above (a negative channel to 0).
    DivisionFactor,
}

impl Normalization {
    /// Whether this is the default, [`Normalization::ClampChannel`] (which files leave out).
    pub fn is_clamp_channel(&self) -> bool {
        *self == Normalization::ClampChannel
    }

    /// `c` as this normalization brings it into [0, 1] before [`quantize`] clamps it.
    pub fn apply(self, c: DVec3) -> DVec3 {
        match self {
            Normalization::ClampChannel => c,
            Normalization::DivisionFactor => {
                let largest = c.max_element();
                if largest > 1.0 { c / largest } else { c }
            }
        }
    }
}

/// A pixel's colour in 8 bits: normalized ([`Normalization::apply`]), then each channel
/// quantised.
pub fn rgb8(c: DVec3, normalization: Normalization) -> [u8; 3] {
    rgb8_encoded(c, normalization, |v| v)
}

/// A pixel's colour in 8 bits with a transfer function: normalized
/// ([`Normalization::apply`]), each channel through `encode` (the identity, or the sRGB
/// curve), then quantised.
#[inline]
pub fn rgb8_encoded(c: DVec3, normalization: Normalization, encode: impl Fn(f64) -> f64) -> [u8; 3] {
    normalization.apply(c).to_array().map(|v| quantize(encode(v)))
}

/// One channel clamped to [0, 1], NaN to 0: the value [`quantize`] rounds.
#[inline]
pub fn clamp_unit(c: f64) -> f64 {
    if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) }
}

/// One channel in 8-bit levels before rounding: clamped to [0, 1] (NaN to 0), times 255.
#[inline]
pub fn unrounded_level(c: f64) -> f64 {
    clamp_unit(c) * 255.0
}

/// One channel to 8 bits: clamp to [0, 1] (NaN to 0), then round to nearest.
#[inline]
pub fn quantize(c: f64) -> u8 {
    // The cast truncates, which is `floor` for the value here (0.5 to 255.5): no call to
    // libm's `floor` (not an instruction on baseline x86-64) for every channel of every lane.
    (unrounded_level(c) + 0.5) as u8
}

/// The value in [0, 1] an 8-bit level stands for, `level / 255`: what [`quantize`] rounds
/// to that level, with no transfer curve.
#[inline]
pub fn level_value(level: u8) -> f64 {
    level as f64 / 255.0
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        Film {
            width,
            height,
            pixels: vec![DVec3::ZERO; width as usize * height as usize],
            normalization: Normalization::ClampChannel,
        }
    }

    pub fn get(&self, x: u32, y: u32) -> DVec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// Interleaved 8-bit RGB ([`rgb8`] of each pixel).
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|&p| rgb8(p, self.normalization)).collect()
    }

    /// PNG-encodes the 8-bit image.
    pub fn encode_png(&self) -> Result<Vec<u8>, image::ImageError> {
        encode_png(self.width, self.height, &self.to_rgb8())
    }
}

/// FNV-1a 64-bit hash of `bytes`: over 8-bit RGB pixels, the "pixel hash" of manifests
/// and snapshots (independent of the PNG encoder, so a student can compare decoded
/// pixels); over a scene file's text or a texture's texels, their identity in provenance,
/// shard headers and scene hashes.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// PNG-encodes interleaved 8-bit RGB.
pub fn encode_png(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, image::ImageError> {
    let mut out = Vec::new();
    let encoder = image::codecs::png::PngEncoder::new(&mut out);
    image::ImageEncoder::write_image(encoder, rgb, width, height, image::ExtendedColorType::Rgb8)?;
    Ok(out)
}

/// A file or folder that could not be written: which, what was being done (`cannot write`,
/// `cannot create the folder`, ...) and the system's error, whose kind tells a bad path
/// (missing folder, permission, read-only file system) from a failed write (disk full).
#[derive(Debug, thiserror::Error)]
#[error("{}: {action}: {io}", path.display())]
pub struct WriteError {
    pub path: PathBuf,
    pub action: &'static str,
    pub io: std::io::Error,
}

impl WriteError {
    pub fn new(path: &Path, action: &'static str, io: std::io::Error) -> Self {
        WriteError {
            path: path.to_path_buf(),
            action,
            io,
        }
    }
}

/// Writes `bytes` to `path` atomically: a temporary file in the same directory, flushed,
/// then renamed over the target. On any error the temporary file is removed, so the target
/// is either the old file or the complete new one, never half-written.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = write_beside(path, bytes)?;
    fs::rename(&tmp, path).inspect_err(|_| {
        let _ = fs::remove_file(&tmp);
    })
}

/// The first half of [`write_atomic`]: `bytes` written and flushed to the temporary file
/// beside `path`, whose path it returns; renaming that file over `path` is the second half.
/// On any error the temporary file is removed.
pub fn write_beside(path: &Path, bytes: &[u8]) -> std::io::Result<PathBuf> {
    let tmp = temp_path(path);
    let result = (|| {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()
    })();
    match result {
        Ok(()) => Ok(tmp),
        Err(e) => {
            let _ = fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// `dir/.name.tmp-PID` next to `path`.
fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

/// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1]:
/// `12.92 c` for `c <= 0.0031308`, else `1.055 c^(1/2.4) - 0.055`.
pub fn srgb_encode(c: f64) -> f64 {
    let c = clamp_unit(c);
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * libm::pow(c, 1.0 / 2.4) - 0.055
    }
}

/// The inverse of [`srgb_encode`] (IEC 61966-2-1), from an encoded value in [0, 1] back to
/// linear: `c / 12.92` for `c <= 0.04045`, else `((c + 0.055) / 1.055)^2.4`.
pub fn srgb_decode(c: f64) -> f64 {
    let c = clamp_unit(c);
    if c <= 0.040_45 {
        c / 12.92
    } else {
        libm::pow((c + 0.055) / 1.055, 2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantisation_clamps_and_rounds() {
        assert_eq!(quantize(-0.5), 0);
        assert_eq!(quantize(0.0), 0);
        // 0.5 * 255 = 127.5 rounds up to 128; 1/255 maps to exactly 1.
        assert_eq!(quantize(0.5), 128);
        assert_eq!(quantize(1.0 / 255.0), 1);
        assert_eq!(quantize(1.0), 255);
        assert_eq!(quantize(7.3), 255);
        assert_eq!(quantize(f64::NAN), 0);
        // Division by the largest channel above 1 keeps the hue; at most 1, nothing changes.
        let bright = DVec3::new(2.0, 1.0, 0.5);
        assert_eq!(Normalization::DivisionFactor.apply(bright), DVec3::new(1.0, 0.5, 0.25));
        assert_eq!(rgb8(bright, Normalization::DivisionFactor), [255, 128, 64]);
        assert_eq!(rgb8(bright, Normalization::ClampChannel), [255, 255, 128]);
        let dim = DVec3::new(0.5, 0.2, -0.1);
        assert_eq!(Normalization::DivisionFactor.apply(dim), dim);
        assert_eq!(rgb8(dim, Normalization::DivisionFactor), [128, 51, 0]);
        // Rounding half up at every level's boundary `(k + 0.5) / 255` and one ulp either
        // side: the cast gives `floor`'s result.
        for k in 0..255 {
            let b = (k as f64 + 0.5) / 255.0;
            for c in [b.next_down(), b, b.next_up()] {
                assert_eq!(quantize(c), (c * 255.0 + 0.5).floor() as u8, "{c}");
            }
        }
    }

    #[test]
    fn levels_before_rounding_and_the_values_levels_stand_for() {
        // 0.5 is 127.5 levels before rounding; clamped above 1 and below 0, NaN to 0.
        assert_eq!(unrounded_level(0.5), 127.5);
        assert_eq!(unrounded_level(1.5), 255.0);
        assert_eq!(unrounded_level(f64::NAN), 0.0);
        // Level 51 stands for 51 / 255 = 0.2, and every level's value quantises back to it.
        assert_eq!(level_value(51), 0.2);
        for k in 0..=255 {
            assert_eq!(quantize(level_value(k)), k);
        }
        // A transfer applied per channel after the normalization: squaring (0.5, 0.2, 2)
        // gives (0.25, 0.04, 1) after clamping, 64, 10 and 255 levels.
        let c = DVec3::new(0.5, 0.2, 2.0);
        assert_eq!(rgb8_encoded(c, Normalization::ClampChannel, |v| v * v), [64, 10, 255]);
        // Divided by its largest channel first: (0.25, 0.1, 1), squared (0.0625, 0.01, 1).
        assert_eq!(rgb8_encoded(c, Normalization::DivisionFactor, |v| v * v), [16, 3, 255]);
    }

    #[test]
    fn fnv1a_reference_values() {
        // Published FNV-1a 64 test vectors: "" and "a".
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn atomic_write_leaves_nothing_on_failure() {
        let dir = std::env::temp_dir().join(format!("lumiere-film-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let missing = dir.join("no-such-dir").join("out.png");
        assert!(write_atomic(&missing, b"x").is_err());
        let ok = dir.join("out.bin");
        write_atomic(&ok, b"hello").unwrap();
        assert_eq!(fs::read(&ok).unwrap(), b"hello");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn srgb_by_hand() {
        // Decoding undoes encoding: 0.5 encodes to 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357.
        assert!((srgb_encode(0.5) - 0.735_356_983).abs() < 1e-9);
        for x in [0.0, 0.002, 0.0031308, 0.2, 0.5, 1.0] {
            assert!((srgb_decode(srgb_encode(x)) - x).abs() < 1e-12, "{x}");
        }
        assert_eq!(srgb_encode(0.0), 0.0);
        // 1.055 - 0.055 = 1 up to one rounding: 0.9999999999999999, which quantises to 255.
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-15);
        assert_eq!(quantize(srgb_encode(1.0)), 255);
        // Linear segment: 0.002 * 12.92 = 0.02584.
        assert!((srgb_encode(0.002) - 0.02584).abs() < 1e-15);
        // 0.5: 1.055 * 0.5^(1/2.4) - 0.055 = 1.055 * 0.749154 - 0.055 = 0.735357.
        assert!((srgb_encode(0.5) - 0.735_357).abs() < 1e-6);
    }
}
