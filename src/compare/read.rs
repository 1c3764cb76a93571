//! Reading the images `compare` takes, as 8-bit RGB, with a note for every conversion.
//!
//! The format is told by the file's first bytes (the extension only for TGA, which has no
//! signature). What each converts:
//! - PNG, PPM / PGM / PBM (ASCII or binary), BMP, TGA, JPEG at 8 bits: as stored;
//! - 16-bit PNG or PPM / PGM: each value `v` to `round(255 v / 65535)`;
//! - grey (PGM, grey PNG, ...): the grey level in R, G and B;
//! - alpha: dropped, the colour compared as stored (not composited); the fully transparent
//!   pixels are marked ([`Image::transparent`]), which `compare` and `diagnose` leave out
//!   (an image with every pixel so is refused, with [`Image::alpha_hint`] when its colours
//!   are drawn);
//! - PFM and EXR (float radiance, as `lumiere render -o X.pfm` writes): each channel clamped
//!   to [0, 1] and quantised to 8 bits exactly as lumiere's film does
//!   ([`crate::film::quantize`], no gamma), so a float image compares as the PNG it would
//!   make.

use super::pfm::{decode_pfm, looks_like_pfm};
use crate::film::quantize;
use crate::limits;
use image::{DynamicImage, ImageFormat};
use std::path::Path;

/// What `compare` reads, for messages.
pub const ALLOWED: &str = "PNG, PPM / PGM / PBM (ASCII or binary), PFM, EXR, JPEG, BMP, TGA";

/// An image read for comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    /// Interleaved 8-bit RGB, row 0 at the top.
    pub rgb: Vec<u8>,
    /// The format read (`PNG`, `PPM`, `PFM`, ...).
    pub format: &'static str,
    /// Every conversion made on the way to 8-bit RGB, in words.
    pub notes: Vec<String>,
    /// Per pixel, whether its alpha is 0 (never drawn: SIMRenderer's console mode leaves
    /// the last rows of an image wider than tall so); empty when no pixel is.
    pub transparent: Vec<bool>,
}

impl Image {
    /// Whether every pixel is fully transparent: nothing was drawn.
    pub fn nothing_drawn(&self) -> bool {
        !self.transparent.is_empty() && self.transparent.iter().all(|&t| t)
    }

    /// What to add to the refusal of an image with nothing drawn: when its colours are not
    /// all zero, they were drawn with alpha left at 0, the likely cause and its fix; else
    /// nothing.
    pub fn alpha_hint(&self) -> &'static str {
        if self.nothing_drawn() && self.rgb.iter().any(|&v| v != 0) {
            "; the colours are there but alpha is 0 everywhere, as in an image written as ARGB with alpha never set (Java's BufferedImage.TYPE_INT_ARGB filled by setRGB(x, y, rgb) without 0xFF000000): write TYPE_INT_RGB, or set alpha to 255"
        } else {
            ""
        }
    }
}

/// Reads an image file; errors name the file, what is wrong and what is read.
pub fn read_image(path: &Path) -> Result<Image, String> {
    let bytes = limits::read_file(path).map_err(|e| format!("{}: cannot read the file: {e}", path.display()))?;
    let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    decode(&bytes, extension).map_err(|e| format!("{}: {e}", path.display()))
}

/// Decodes an image from its bytes; `extension` (without the dot) names TGA files. An
/// image without pixels (a side of 0, which PPM and BMP headers can say) is refused: there
/// is nothing to compare.
pub fn decode(bytes: &[u8], extension: &str) -> Result<Image, String> {
    if bytes.is_empty() {
        return Err("the file is empty (0 bytes): no image was written to it".into());
    }
    let image = decode_any(bytes, extension)?;
    if image.width == 0 || image.height == 0 {
        return Err(no_pixels(image.format, image.width, image.height));
    }
    Ok(image)
}

fn no_pixels(format: &str, width: u32, height: u32) -> String {
    format!("the {format} image is {width} x {height} pixels: it has no pixel to compare")
}

/// The size a PNG, BMP or TGA header declares, read where each format keeps it (PNG's
/// IHDR, big-endian; BMP's info header, whose height is negative for rows stored top down;
/// TGA's image specification), for the images their decoders refuse before saying why.
fn declared_size(bytes: &[u8], format: ImageFormat) -> Option<(u32, u32)> {
    let u16_le = |at: usize| Some(u16::from_le_bytes(bytes.get(at..at + 2)?.try_into().ok()?) as u32);
    let i32_le = |at: usize| Some(i32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?).unsigned_abs());
    let u32_be = |at: usize| Some(u32::from_be_bytes(bytes.get(at..at + 4)?.try_into().ok()?));
    match format {
        ImageFormat::Png => Some((u32_be(16)?, u32_be(20)?)),
        // A 12-byte core header keeps 16-bit sides; the later headers 32-bit ones.
        ImageFormat::Bmp if u16_le(14)? == 12 => Some((u16_le(18)?, u16_le(20)?)),
        ImageFormat::Bmp => Some((i32_le(18)?, i32_le(22)?)),
        ImageFormat::Tga => Some((u16_le(12)?, u16_le(14)?)),
        _ => None,
    }
}

/// The name messages give a format lumiere reads through the `image` crate (`PPM` for the
/// whole PNM family); `None` for the others.
pub fn format_name(format: ImageFormat) -> Option<&'static str> {
    match format {
        ImageFormat::Png => Some("PNG"),
        ImageFormat::Pnm => Some("PPM"),
        ImageFormat::OpenExr => Some("EXR"),
        ImageFormat::Jpeg => Some("JPEG"),
        ImageFormat::Bmp => Some("BMP"),
        ImageFormat::Tga => Some("TGA"),
        _ => None,
    }
}

/// Why a file that no format's signature starts is not read: its extension names a
/// format compare reads and its bytes are not that format's, or neither names one.
fn unrecognised(extension: &str) -> String {
    let named = if extension.eq_ignore_ascii_case("pfm") {
        Some("PFM")
    } else {
        ImageFormat::from_extension(extension).and_then(format_name)
    };
    match named {
        Some(format) => format!(
            "its extension .{extension} names {format}, but its first bytes are not a {format} file's: not an image, or one cut short or written as something else; compare reads {ALLOWED}"
        ),
        None => {
            let ext = if extension.is_empty() {
                "no extension".to_string()
            } else {
                format!("extension .{extension}")
            };
            format!(
                "not an image compare reads (neither its first bytes nor its {ext} name a known format); it reads {ALLOWED}"
            )
        }
    }
}

/// [`decode`], whatever the image's size.
fn decode_any(bytes: &[u8], extension: &str) -> Result<Image, String> {
    if looks_like_pfm(bytes) {
        let pfm = decode_pfm(bytes)?;
        let mut notes = vec![float_note("PFM")];
        if pfm.channels == 1 {
            notes.push("grey input (Pf): its value used for R, G and B".into());
        }
        if pfm.scale.abs() != 1.0 {
            notes.push(format!(
                "PFM scale {}: only its sign (the byte order) is used, the values are not multiplied",
                pfm.scale
            ));
        }
        let (rgb, non_finite) = quantize_floats(&pfm.rgb);
        // A grey value stands in all three channels.
        let non_finite = non_finite / (3 / pfm.channels as usize);
        if non_finite > 0 {
            notes.push(non_finite_note(non_finite));
        }
        return Ok(Image {
            width: pfm.width,
            height: pfm.height,
            rgb,
            format: "PFM",
            notes,
            transparent: Vec::new(),
        });
    }
    let format = match image::guess_format(bytes) {
        Ok(f) => f,
        Err(_) if extension.eq_ignore_ascii_case("tga") => ImageFormat::Tga,
        Err(_) => return Err(unrecognised(extension)),
    };
    let Some(name) = format_name(format) else {
        return Err(format!(
            "a {} image, which compare does not read; it reads {ALLOWED}",
            format
                .extensions_str()
                .first()
                .map_or("other".into(), |e| e.to_ascii_uppercase())
        ));
    };
    // The size from the header, before any pixel is decoded: a header may claim more than
    // memory holds.
    if let Ok((w, h)) = image::ImageReader::with_format(std::io::Cursor::new(bytes), format).into_dimensions()
        && w as u64 * h as u64 > limits::MAX_PIXELS
    {
        return Err(format!(
            "the {name} image is {w} x {h} = {} pixels: compare reads at most {} (as many as lumiere renders)",
            w as u64 * h as u64,
            limits::MAX_PIXELS
        ));
    }
    let img = image::load_from_memory_with_format(bytes, format).map_err(|e| match declared_size(bytes, format) {
        Some((w, h)) if w == 0 || h == 0 => no_pixels(name, w, h),
        _ => format!("cannot decode the {name} image: {e}"),
    })?;
    let mut notes = Vec::new();
    if format == ImageFormat::Jpeg {
        notes.push("JPEG is lossy: its compression alone changes pixels by a few levels".into());
    }
    let (width, height) = (img.width(), img.height());
    let transparent = fully_transparent(&img);
    let clear = transparent.iter().filter(|&&t| t).count();
    let rgb = to_rgb8(img, name, clear, &mut notes);
    Ok(Image {
        width,
        height,
        rgb,
        format: name,
        notes,
        transparent,
    })
}

/// Per pixel, whether its alpha is 0 once at 8 bits; empty when the image has no alpha
/// channel or no such pixel.
fn fully_transparent(img: &DynamicImage) -> Vec<bool> {
    if !img.color().has_alpha() {
        return Vec::new();
    }
    let mask: Vec<bool> = img.to_rgba8().pixels().map(|p| p.0[3] == 0).collect();
    if mask.contains(&true) { mask } else { Vec::new() }
}

fn float_note(format: &str) -> String {
    format!(
        "{format}: read as float radiance, clamped to [0, 1] and quantised to 8 bits as lumiere's film does (no gamma): compared as the PNG it would make"
    )
}

fn non_finite_note(n: usize) -> String {
    format!("{n} channel values NaN or infinite: NaN read as 0, infinity clamped")
}

/// Each float clamped to [0, 1] and quantised as the film does, with the count of
/// non-finite values.
fn quantize_floats(values: &[f32]) -> (Vec<u8>, usize) {
    let non_finite = values.iter().filter(|v| !v.is_finite()).count();
    (values.iter().map(|&v| quantize(v as f64)).collect(), non_finite)
}

/// A 16-bit value to 8 bits, rounded to nearest: `round(255 v / 65535)`.
pub fn level_from_16(v: u16) -> u8 {
    ((v as u32 * 255 + 32767) / 65535) as u8
}

/// The note on a dropped alpha channel, of which `not_opaque` pixels are not opaque and
/// `clear` of those fully transparent (alpha 0 once at 8 bits, [`Image::transparent`], left
/// to the commands that leave them out): the others, partly transparent, are compared as
/// stored.
fn alpha_note(not_opaque: usize, clear: usize) -> String {
    match (not_opaque.saturating_sub(clear), clear) {
        (0, 0) => "alpha channel dropped (every pixel opaque)".into(),
        (0, _) => "alpha channel dropped (every pixel opaque or fully transparent)".into(),
        (partly, _) => format!(
            "alpha channel dropped: {partly} pixels partly transparent, their colour compared as stored (not composited)"
        ),
    }
}

/// The 8-bit RGB of a decoded image, noting each conversion; `clear` of its pixels are
/// fully transparent.
fn to_rgb8(img: DynamicImage, format: &str, clear: usize, notes: &mut Vec<String>) -> Vec<u8> {
    let grey = "grey input: its level used for R, G and B";
    let sixteen = "16-bit input converted to 8 bits (round(255 v / 65535))";
    match img {
        DynamicImage::ImageRgb8(i) => i.into_raw(),
        DynamicImage::ImageRgba8(i) => {
            notes.push(alpha_note(i.pixels().filter(|p| p.0[3] != u8::MAX).count(), clear));
            i.pixels().flat_map(|p| [p.0[0], p.0[1], p.0[2]]).collect()
        }
        DynamicImage::ImageLuma8(i) => {
            notes.push(grey.into());
            i.into_raw().into_iter().flat_map(|v| [v; 3]).collect()
        }
        DynamicImage::ImageLumaA8(i) => {
            notes.push(grey.into());
            notes.push(alpha_note(i.pixels().filter(|p| p.0[1] != u8::MAX).count(), clear));
            i.pixels().flat_map(|p| [p.0[0]; 3]).collect()
        }
        DynamicImage::ImageRgb16(i) => {
            notes.push(sixteen.into());
            i.into_raw().into_iter().map(level_from_16).collect()
        }
        DynamicImage::ImageRgba16(i) => {
            notes.push(sixteen.into());
            notes.push(alpha_note(i.pixels().filter(|p| p.0[3] != u16::MAX).count(), clear));
            i.pixels()
                .flat_map(|p| [0, 1, 2].map(|c| level_from_16(p.0[c])))
                .collect()
        }
        DynamicImage::ImageLuma16(i) => {
            notes.push(sixteen.into());
            notes.push(grey.into());
            i.into_raw().into_iter().flat_map(|v| [level_from_16(v); 3]).collect()
        }
        DynamicImage::ImageLumaA16(i) => {
            notes.push(sixteen.into());
            notes.push(grey.into());
            notes.push(alpha_note(i.pixels().filter(|p| p.0[1] != u16::MAX).count(), clear));
            i.pixels().flat_map(|p| [level_from_16(p.0[0]); 3]).collect()
        }
        DynamicImage::ImageRgb32F(i) => float_rgb(i.as_raw(), 3, format, notes),
        DynamicImage::ImageRgba32F(i) => {
            let rgb = float_rgb(i.as_raw(), 4, format, notes);
            notes.push(alpha_note(i.pixels().filter(|p| p.0[3] != 1.0).count(), clear));
            rgb
        }
        other => {
            notes.push(format!("{:?} pixels converted to 8-bit RGB", other.color()));
            other.to_rgb8().into_raw()
        }
    }
}

/// Float pixels of `stride` channels (RGB first) clamped and quantised.
fn float_rgb(values: &[f32], stride: usize, format: &str, notes: &mut Vec<String>) -> Vec<u8> {
    notes.insert(0, float_note(format));
    let rgb: Vec<f32> = values.chunks_exact(stride).flat_map(|p| [p[0], p[1], p[2]]).collect();
    let (out, non_finite) = quantize_floats(&rgb);
    if non_finite > 0 {
        notes.push(non_finite_note(non_finite));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alpha_hint_only_when_nothing_drawn_holds_colours() {
        let image = |rgb: Vec<u8>, transparent: Vec<bool>| Image {
            width: 2,
            height: 1,
            rgb,
            format: "PNG",
            notes: Vec::new(),
            transparent,
        };
        // Both pixels at alpha 0, one of them red: colours drawn, alpha never set.
        let unset = image(vec![0, 0, 0, 255, 0, 0], vec![true, true]);
        assert!(unset.nothing_drawn());
        assert!(unset.alpha_hint().contains("TYPE_INT_ARGB"));
        // Both at alpha 0 and black: nothing drawn, no hint.
        let clear = image(vec![0; 6], vec![true, true]);
        assert!(clear.nothing_drawn());
        assert_eq!(clear.alpha_hint(), "");
        // One pixel drawn, or none transparent: no hint either.
        assert_eq!(image(vec![255, 0, 0, 0, 0, 0], vec![false, true]).alpha_hint(), "");
        assert_eq!(image(vec![255; 6], Vec::new()).alpha_hint(), "");
    }

    #[test]
    fn sixteen_bits_round_to_nearest() {
        assert_eq!(level_from_16(0), 0);
        assert_eq!(level_from_16(65535), 255);
        // 257 = 65535 / 255 is one level; 128 / 257 = 0.498 rounds down, 129 / 257 up.
        assert_eq!(level_from_16(257), 1);
        assert_eq!(level_from_16(128), 0);
        assert_eq!(level_from_16(129), 1);
        assert_eq!(level_from_16(32896), 128);
    }

    #[test]
    fn ascii_and_binary_pnm() {
        let ascii = decode(b"P3\n2 1\n255\n10 20 30 40 50 60\n", "ppm").unwrap();
        assert_eq!((ascii.width, ascii.height, ascii.format), (2, 1, "PPM"));
        assert_eq!(ascii.rgb, [10, 20, 30, 40, 50, 60]);
        assert!(ascii.notes.is_empty());
        let binary = decode(b"P6\n2 1\n255\n\x0a\x14\x1e\x28\x32\x3c", "ppm").unwrap();
        assert_eq!(binary.rgb, ascii.rgb);
        let grey = decode(b"P2\n2 1\n255\n7 200\n", "pgm").unwrap();
        assert_eq!(grey.rgb, [7, 7, 7, 200, 200, 200]);
        assert_eq!(grey.notes, ["grey input: its level used for R, G and B"]);
        // 16-bit binary PPM: big-endian values, maxval 65535.
        let deep = decode(b"P6\n1 1\n65535\n\xff\xff\x01\x01\x00\x80", "ppm").unwrap();
        assert_eq!(deep.rgb, [255, 1, 0]);
        assert!(deep.notes[0].starts_with("16-bit input converted to 8 bits"));
    }

    #[test]
    fn unknown_formats_are_named() {
        let e = decode(b"hello, world", "txt").unwrap_err();
        assert_eq!(
            e,
            "not an image compare reads (neither its first bytes nor its extension .txt name a known format); it reads PNG, PPM / PGM / PBM (ASCII or binary), PFM, EXR, JPEG, BMP, TGA"
        );
        for ext in ["png", "tga", ""] {
            assert_eq!(
                decode(b"", ext).unwrap_err(),
                "the file is empty (0 bytes): no image was written to it"
            );
        }
        assert_eq!(
            decode(b"hello, world", "png").unwrap_err(),
            "its extension .png names PNG, but its first bytes are not a PNG file's: not an image, or one cut short or written as something else; compare reads PNG, PPM / PGM / PBM (ASCII or binary), PFM, EXR, JPEG, BMP, TGA"
        );
        let e = decode(b"hello, world", "PFM").unwrap_err();
        assert!(
            e.starts_with("its extension .PFM names PFM, but its first bytes are not a PFM file's"),
            "{e}"
        );
        let e = decode(b"GIF89a\x01\x00\x01\x00", "gif").unwrap_err();
        assert!(e.starts_with("a GIF image, which compare does not read"), "{e}");
        let e = decode(b"\x89PNG\r\n\x1a\n", "png").unwrap_err();
        assert!(e.starts_with("cannot decode the PNG image: "), "{e}");
    }

    #[test]
    fn images_without_pixels_are_refused() {
        for (bytes, size) in [
            (&b"P3\n0 0\n255\n"[..], "0 x 0"),
            (b"P3\n0 2\n255\n", "0 x 2"),
            (b"P2\n3 0\n255\n", "3 x 0"),
        ] {
            let e = decode(bytes, "ppm").unwrap_err();
            assert_eq!(e, format!("the PPM image is {size} pixels: it has no pixel to compare"));
        }
        // Headers whose decoders refuse a 0 side in their own words (BMP's says "too large").
        let png = [
            &b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR"[..],
            &[0, 0, 0, 0, 0, 0, 0, 4, 8, 2, 0, 0, 0],
        ]
        .concat();
        let mut bmp = b"BM".to_vec();
        bmp.extend([54u32, 0, 54].iter().flat_map(|v| v.to_le_bytes()));
        bmp.extend(40u32.to_le_bytes());
        bmp.extend(5i32.to_le_bytes());
        bmp.extend(0i32.to_le_bytes());
        bmp.extend([1u8, 0, 24, 0]);
        bmp.extend([0u8; 24]);
        let tga = [0u8, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 4, 0, 24, 0];
        for (bytes, extension, message) in [
            (&png[..], "png", "the PNG image is 0 x 4 pixels"),
            (&bmp, "bmp", "the BMP image is 5 x 0 pixels"),
            (&tga, "tga", "the TGA image is 0 x 4 pixels"),
        ] {
            assert_eq!(
                decode(bytes, extension).unwrap_err(),
                format!("{message}: it has no pixel to compare")
            );
        }
    }
}
