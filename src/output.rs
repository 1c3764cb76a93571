//! Image files, chosen by the output's extension: `.png` (8-bit: clamp to [0, 1], linear by
//! default or sRGB-encoded on request, quantise), `.pfm` and `.exr` (32-bit float radiance,
//! unclamped, for exact comparisons).

use crate::film::{Film, encode_png, rgb8_encoded, srgb_encode};
use std::path::Path;

/// An output file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    /// Portable float map: little-endian f32 RGB, rows bottom to top.
    Pfm,
    /// OpenEXR, f32 RGB.
    Exr,
}

impl Format {
    /// The format named by `path`'s extension.
    pub fn of(path: &Path) -> Result<Format, String> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("png") => Ok(Format::Png),
            Some("pfm") => Ok(Format::Pfm),
            Some("exr") => Ok(Format::Exr),
            _ => Err(format!(
                "{}: the output must end in .png (8-bit), .pfm or .exr (float radiance)",
                path.display()
            )),
        }
    }
}

/// 8-bit RGB of a film with each channel sRGB-encoded before quantisation (after the
/// film's normalization).
pub fn to_srgb8(film: &Film) -> Vec<u8> {
    film.pixels
        .iter()
        .flat_map(|&p| rgb8_encoded(p, film.normalization, srgb_encode))
        .collect()
}

/// The radiance as f32 RGB, row 0 at the top.
fn to_f32(film: &Film) -> Vec<f32> {
    film.pixels
        .iter()
        .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
        .collect()
}

/// PFM bytes: header `PF\n<w> <h>\n-1.0\n` (negative scale: little-endian), then the rows
/// from the bottom of the image to the top.
pub fn encode_pfm(film: &Film) -> Vec<u8> {
    let mut out = format!("PF\n{} {}\n-1.0\n", film.width, film.height).into_bytes();
    let w = film.width as usize;
    for row in film.pixels.chunks(w).rev() {
        for p in row {
            for c in [p.x, p.y, p.z] {
                out.extend_from_slice(&(c as f32).to_le_bytes());
            }
        }
    }
    out
}

/// Encodes a film for `format`; `srgb` applies to PNG only.
pub fn encode(film: &Film, format: Format, srgb: bool) -> Result<Vec<u8>, String> {
    match format {
        Format::Png if srgb => encode_png(film.width, film.height, &to_srgb8(film)).map_err(|e| e.to_string()),
        Format::Png => film.encode_png().map_err(|e| e.to_string()),
        Format::Pfm => Ok(encode_pfm(film)),
        Format::Exr => {
            let img = image::Rgb32FImage::from_raw(film.width, film.height, to_f32(film)).ok_or("film size")?;
            let mut out = std::io::Cursor::new(Vec::new());
            img.write_to(&mut out, image::ImageFormat::OpenExr)
                .map_err(|e| e.to_string())?;
            Ok(out.into_inner())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn pfm_is_bottom_up_and_unclamped() {
        let mut film = Film::new(1, 2);
        film.pixels[0] = DVec3::new(2.5, 0.0, -1.0); // top row, above 1 and below 0
        film.pixels[1] = DVec3::new(0.25, 0.5, 0.75);
        let b = encode_pfm(&film);
        let header = b"PF\n1 2\n-1.0\n";
        assert_eq!(&b[..header.len()], header);
        let f = |i: usize| f32::from_le_bytes(b[header.len() + 4 * i..header.len() + 4 * i + 4].try_into().unwrap());
        // First the bottom row (0.25, 0.5, 0.75), then the top (2.5, 0, -1).
        assert_eq!([f(0), f(1), f(2), f(3), f(5)], [0.25, 0.5, 0.75, 2.5, -1.0]);
    }

    #[test]
    fn exr_round_trips_unclamped_values() {
        let mut film = Film::new(2, 1);
        film.pixels[0] = DVec3::new(3.0, 0.5, 0.0);
        let bytes = encode(&film, Format::Exr, false).unwrap();
        let img = image::load_from_memory(&bytes).unwrap().to_rgb32f();
        assert_eq!(img.get_pixel(0, 0).0, [3.0, 0.5, 0.0]);
    }

    #[test]
    fn formats_by_extension() {
        assert_eq!(Format::of(Path::new("a.PNG")), Ok(Format::Png));
        assert_eq!(Format::of(Path::new("a.exr")), Ok(Format::Exr));
        assert!(Format::of(Path::new("a.jpg")).unwrap_err().contains(".pfm"));
    }
}
