//! Image textures of SIMRenderer's texture materials (`texture_material`): an image file
//! for the ambient, the diffuse and the specular colour, looked up at a surface point's
//! texture coordinates `(u, v)` ([`crate::shape::Shape::uv`]) as SIMRenderer's `STexture`
//! does:
//!
//! - `u` and `v` outside `[0, 1]` are brought back by repetition (`SVectorUV`'s repeat:
//!   above 1, whole units are taken off until the value is at most 1; below 0, whole units
//!   are added until it is at least 0; values in `[0, 1]` are kept, 1 included);
//! - the uv format places the origin: `origin_uv_top_left` (the default: `v` runs down the
//!   image from its top row) or `origin_uv_bottom_left` (`v` replaced by `1 - v`);
//! - the texel is column `floor(u (width - 1))`, row `floor(v (height - 1))` (no
//!   filtering), its 8-bit channels divided by 255 with no gamma.
//!
//! Images are read through the `image` crate (PNG, JPEG, BMP, TGA, PNM, EXR); every error names
//! the file.

use crate::film::level_value;
use glam::DVec3;
use std::path::Path;

/// The most texels an image may hold (a 8192 x 8192 image): larger is refused.
pub const MAX_TEXELS: u64 = 1 << 26;

/// Where the texture coordinates' origin is in the image (SIMRenderer's `uv_format`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum UvFormat {
    /// `(0, 0)` at the image's top-left corner, `v` downwards.
    #[default]
    OriginUvTopLeft,
    /// `(0, 0)` at the image's bottom-left corner, `v` upwards.
    OriginUvBottomLeft,
}

impl UvFormat {
    /// The names scene files use, in SIMRenderer's order after its `default` (index 0).
    pub const NAMES: [&'static str; 2] = ["origin_uv_top_left", "origin_uv_bottom_left"];

    pub fn parse(name: &str) -> Option<UvFormat> {
        match name {
            "origin_uv_top_left" => Some(UvFormat::OriginUvTopLeft),
            "origin_uv_bottom_left" => Some(UvFormat::OriginUvBottomLeft),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// An image as texels, with the file name it was read from (as the scene file wrote it).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub file: String,
    pub width: u32,
    pub height: u32,
    /// Row-major from the top row, each channel in `[0, 1]` (the 8-bit value / 255).
    texels: Vec<DVec3>,
}

/// The 8-bit RGB texels of the image at `path`, row-major from the top row, with its width
/// and height; `what` (a texture, a mask image) names it in errors, which name the file and
/// say what is wrong: missing, unreadable, not an image, or of a size [`Texture::check_size`]
/// refuses (checked on the header, before any texel is decoded).
pub fn read_rgb8(path: &Path, what: &str) -> Result<(u32, u32, Vec<u8>), String> {
    let shown = path.display();
    let meta = std::fs::metadata(path).map_err(|e| format!("{shown}: cannot read the {what}: {e}"))?;
    if !meta.is_file() {
        return Err(format!("{shown}: cannot read the {what}: not a regular file"));
    }
    let open = || {
        image::ImageReader::open(path)
            .and_then(|r| r.with_guessed_format())
            .map_err(|e| format!("{shown}: cannot read the {what}: {e}"))
    };
    // A file of a format read, told by its first bytes (not its name), that does not decode
    // is said to be damaged, not to be of another format.
    let signature = std::fs::File::open(path)
        .map(std::io::BufReader::new)
        .and_then(|r| image::ImageReader::new(r).with_guessed_format())
        .map_err(|e| format!("{shown}: cannot read the {what}: {e}"))?;
    let known = signature.format().and_then(crate::compare::read::format_name);
    let not_an_image = |e: image::ImageError| match known {
        Some(format) => format!("{shown}: cannot decode the {format} {what}: {e}"),
        None => format!("{shown}: not an image lumiere reads (PNG, JPEG, BMP, TGA, PNM, EXR): {e}"),
    };
    let (width, height) = open()?.into_dimensions().map_err(not_an_image)?;
    Texture::check_size(width, height, what).map_err(|m| format!("{shown}: {m}"))?;
    let image = open()?.decode().map_err(not_an_image)?.to_rgb8();
    Ok((image.width(), image.height(), image.into_raw()))
}

impl Texture {
    /// Reads the image at `path`; `file` is its name as the scene wrote it. The error names
    /// the file and says what is wrong: missing, unreadable, or of a bad size.
    pub fn load(path: &Path, file: &str) -> Result<Texture, String> {
        let (width, height, rgb) = read_rgb8(path, "texture")?;
        Ok(Texture::from_rgb8(file, width, height, &rgb))
    }

    /// Why an image of this size is refused as `what` (a texture, a mask image), if it is:
    /// no texel, or more than [`MAX_TEXELS`].
    pub fn check_size(width: u32, height: u32, what: &str) -> Result<(), String> {
        let texels = width as u64 * height as u64;
        if texels == 0 || texels > MAX_TEXELS {
            return Err(format!(
                "the {what} is {width} x {height}: it must hold between 1 and {MAX_TEXELS} texels"
            ));
        }
        Ok(())
    }

    /// A texture from 8-bit RGB texels, row-major from the top row.
    pub fn from_rgb8(file: &str, width: u32, height: u32, rgb: &[u8]) -> Texture {
        Texture {
            file: file.to_string(),
            width,
            height,
            texels: rgb
                .chunks_exact(3)
                .map(|c| DVec3::new(level_value(c[0]), level_value(c[1]), level_value(c[2])))
                .collect(),
        }
    }

    /// The colour at texture coordinates `(u, v)` under `format` (module doc).
    pub fn color(&self, (u, v): (f64, f64), format: UvFormat) -> DVec3 {
        let (u, v) = (repeat(u), repeat(v));
        let v = match format {
            UvFormat::OriginUvTopLeft => v,
            UvFormat::OriginUvBottomLeft => 1.0 - v,
        };
        self.texels[texel_index(self.width, self.height, (u, v))]
    }

    /// FNV-1a 64 over the texels' bits: the identity of the image in a scene's hash.
    fn hash(&self) -> u64 {
        let bytes: Vec<u8> = self
            .texels
            .iter()
            .flat_map(|t| t.to_array())
            .flat_map(|c| c.to_bits().to_le_bytes())
            .collect();
        crate::film::fnv1a64(&bytes)
    }
}

impl serde::Serialize for Texture {
    /// The file, the size and the texels' hash.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut st = s.serialize_struct("Texture", 4)?;
        st.serialize_field("file", &self.file)?;
        st.serialize_field("width", &self.width)?;
        st.serialize_field("height", &self.height)?;
        st.serialize_field("texels_fnv1a64", &format!("{:016x}", self.hash()))?;
        st.end()
    }
}

/// The place, row-major from the top-left texel, of the texel that SIMRenderer's
/// `STexture.getSColor` reads at coordinates `(u, v)` of `[0, 1]` with the top-left
/// origin: column `(int) (u (width - 1))`, row `(int) (v (height - 1))` (`as` truncates
/// towards zero, as Java's `(int)` does; NaN gives 0).
pub fn texel_index(width: u32, height: u32, (u, v): (f64, f64)) -> usize {
    let column = ((u * (width - 1) as f64) as u32).min(width - 1);
    let row = ((v * (height - 1) as f64) as u32).min(height - 1);
    row as usize * width as usize + column as usize
}

/// SIMRenderer's repetition of a texture coordinate into `[0, 1]` (`SVectorUV.cropRepeat`):
/// above 1, `u - k` for the least whole `k` that brings it to at most 1; below 0, `u + k`
/// for the least whole `k` that brings it to at least 0 (each step exact, as one
/// subtraction of the whole part is); `[0, 1]` as it is.
pub fn repeat(u: f64) -> f64 {
    if u > 1.0 {
        u - (u.ceil() - 1.0)
    } else if u < 0.0 {
        u + (-u).ceil()
    } else if u.is_nan() {
        0.0
    } else {
        u
    }
}

/// The textures of a texture material (any of them may be absent: that term keeps the
/// material's own colour) and how their coordinates are read.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TextureMaps {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ambient: Option<Texture>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub diffuse: Option<Texture>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub specular: Option<Texture>,
    pub uv_format: UvFormat,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 x 2 image: top row red, green, blue; bottom row white, grey 51, black.
    fn six() -> Texture {
        let rgb = [255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255, 51, 51, 51, 0, 0, 0];
        Texture::from_rgb8("six.png", 3, 2, &rgb)
    }

    #[test]
    fn texels_by_hand() {
        let t = six();
        let top = UvFormat::OriginUvTopLeft;
        // Column floor(u * 2), row floor(v * 1).
        assert_eq!(t.color((0.0, 0.0), top), DVec3::X);
        assert_eq!(t.color((0.49, 0.0), top), DVec3::X);
        assert_eq!(t.color((0.5, 0.0), top), DVec3::Y);
        assert_eq!(t.color((1.0, 0.0), top), DVec3::Z);
        // The last column and row only at exactly 1 (SIMRenderer's `(int)(v (height - 1))`).
        assert_eq!(t.color((0.99, 0.99), top), DVec3::Y);
        assert_eq!(t.color((0.5, 1.0), top), DVec3::splat(51.0 / 255.0));
        assert_eq!(t.color((1.0, 1.0), top), DVec3::ZERO);
        // Bottom-left origin: v = 0 is the bottom row.
        let bottom = UvFormat::OriginUvBottomLeft;
        assert_eq!(t.color((0.0, 0.0), bottom), DVec3::ONE);
        assert_eq!(t.color((0.0, 1.0), bottom), DVec3::X);
        // Repetition: 1.25 -> 0.25, -0.75 -> 0.25, 2 -> 1, -1 -> 0.
        assert_eq!(t.color((1.25, 0.0), top), DVec3::X);
        assert_eq!(t.color((-0.25, 0.0), top), DVec3::Y);
        assert_eq!(t.color((2.0, 0.0), top), DVec3::Z);
        assert_eq!(t.color((-1.0, 0.0), top), DVec3::X);
    }

    #[test]
    fn texel_places_truncate_as_java_does() {
        // 3 x 2 texels: column (int) (2 u), row (int) (v).
        for (uv, want) in [
            ((0.0, 0.0), 0),
            ((0.49, 0.99), 0),
            ((0.5, 0.5), 1),
            ((0.999, 0.0), 1),
            ((1.0, 0.0), 2),
            ((1.0, 1.0), 5),
            ((f64::NAN, 1.0), 3),
        ] {
            assert_eq!(texel_index(3, 2, uv), want, "{uv:?}");
        }
    }

    #[test]
    fn repetition_as_simrenderer() {
        for (u, want) in [
            (0.0, 0.0),
            (1.0, 1.0),
            (1.23, 1.23 - 1.0),
            (3.0, 1.0),
            (-2.8, -2.8 + 3.0),
            (-1.0, 0.0),
            (0.5, 0.5),
        ] {
            assert_eq!(repeat(u), want, "{u}");
        }
    }

    #[test]
    fn sizes_refused_by_name() {
        assert!(Texture::check_size(1, 1, "texture").is_ok());
        assert_eq!(
            Texture::check_size(0, 5, "texture").unwrap_err(),
            "the texture is 0 x 5: it must hold between 1 and 67108864 texels"
        );
        assert!(Texture::check_size(8193, 8192, "mask image").is_err());
    }
}
