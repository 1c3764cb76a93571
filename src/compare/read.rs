//! Reading the images `compare`, `diagnose` and the figures' review take, as 8-bit RGB,
//! with a note for every conversion. The messages name no command ("lumiere reads ..."):
//! each command that reads an image prints them as they are.
//!
//! The format is told by the file's first bytes (the extension only for TGA, which has no
//! signature). What each converts:
//! - PNG, PPM / PGM / PBM (ASCII or binary), BMP, TGA, JPEG at 8 bits: as stored; a PNG of
//!   indexed colour as its palette's colours, noted;
//! - 16-bit PNG or PPM / PGM: each value `v` to `round(255 v / 65535)`;
//! - grey (PGM, grey PNG, ...): the grey level in R, G and B;
//! - alpha: dropped, the colour compared as stored (not composited), a pixel of alpha 0 with
//!   a colour too; only transparent black pixels, all four channels 0, are marked as never
//!   drawn ([`Image::undrawn`]), which `compare` and `diagnose` leave out. That is how
//!   SIMRenderer's console mode leaves the rows it does not trace (a Java `BufferedImage`
//!   of `TYPE_INT_ARGB` starts at 0 in every channel); a colour under alpha 0 is something
//!   drawn with alpha never set, and an error there must show. An image with alpha 0
//!   everywhere is refused ([`Image::nothing_drawn`]): its alpha tells nothing drawn from
//!   black drawn, and [`Image::alpha_hint`] says why when its colours are there;
//! - PFM and EXR (float radiance, as `lumiere render -o X.pfm` writes): each channel clamped
//!   to [0, 1] and quantised to 8 bits exactly as lumiere's film does
//!   ([`crate::film::quantize`], no gamma), so a float image compares as the PNG it would
//!   make.

use super::pfm::{decode_pfm, looks_like_pfm};
use crate::film::quantize;
use crate::limits;
use image::{DynamicImage, ImageFormat};
use std::path::Path;

/// What lumiere reads as an image, for messages.
pub const ALLOWED: &str = "PNG, PPM / PGM / PBM (ASCII or binary), PFM, EXR, JPEG, BMP, TGA";

/// The note on a JPEG image. Its compression stores colour at half resolution and rounds
/// each 8 x 8 block's frequencies: the oracle's image of the reference scene at 160 x 120
/// saved at quality 90 differs from it by up to 80 levels (p99 43 at quality 75, 35 at 95),
/// along outlines and where colours change.
pub const JPEG_NOTE: &str = "JPEG is lossy: its compression alone changes pixels, by tens of levels along outlines and where colours change; write a PNG to compare level by level";

/// The note on a PNG of indexed colour.
pub const PALETTE_NOTE: &str = "indexed colour (a palette of at most 256 colours): each pixel read as its palette entry's colour; an image saved so has lost the shades its palette lacks, write it as RGB";

/// The note on a JPEG file that does not end with the end-of-image marker: its decoder
/// draws the missing part of the image in grey without an error.
pub const JPEG_CUT_NOTE: &str = "the file does not end with JPEG's end-of-image marker (FF D9): it looks cut short, as by a write that stopped, and the rows it lacks are decoded grey; write it again";

/// The refusal of an image whose file ends before its pixels do: a write that stopped.
fn cut_short(format: &str, size: Option<(u64, u64)>, bytes: usize) -> String {
    let size = size.map_or(String::new(), |(w, h)| format!(" {w} x {h}"));
    format!(
        "cannot decode the {format} image: the file ends before its{size} pixels do, after {bytes} bytes: it was cut short, as by a write that stopped or a copy not finished; write it again"
    )
}

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
    /// Per pixel, whether it was never drawn: transparent black, alpha and colour 0 at 8
    /// bits (SIMRenderer's console mode leaves the last rows of an image wider than tall
    /// so); empty when no pixel is.
    pub undrawn: Vec<bool>,
    /// How many pixels have alpha 0 at 8 bits, black or not.
    pub alpha_zero: usize,
}

impl Image {
    /// Whether every pixel is fully transparent (alpha 0): nothing was drawn, or nothing
    /// tells what was.
    pub fn nothing_drawn(&self) -> bool {
        self.alpha_zero > 0 && self.alpha_zero as u64 == self.width as u64 * self.height as u64
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
        return Err(no_pixels(image.format, image.width.into(), image.height.into()));
    }
    Ok(image)
}

fn no_pixels(format: &str, width: u64, height: u64) -> String {
    format!("the {format} image is {width} x {height} pixels: it has no pixel to compare")
}

/// The refusal of a `format` image of `width` x `height` pixels when it has more than
/// [`limits::MAX_PIXELS`], the most lumiere renders; `None` when it has no more.
fn too_many_pixels(format: &str, width: u64, height: u64) -> Option<String> {
    let pixels = width as u128 * height as u128;
    (pixels > limits::MAX_PIXELS as u128).then(|| {
        format!(
            "the {format} image is {width} x {height} = {pixels} pixels: lumiere reads at most {} (as many as it renders)",
            limits::MAX_PIXELS
        )
    })
}

/// The size an image's header declares, before any pixel is decoded: as its decoder reads
/// it, or, for a header the decoder refuses (a side of 0; BMP's sides past 65535, PPM's
/// sides whose bytes pass 64 bits), as [`declared_size`] reads it.
fn header_size(bytes: &[u8], format: ImageFormat) -> Option<(u64, u64)> {
    let reader = image::ImageReader::with_format(std::io::Cursor::new(bytes), format);
    match reader.into_dimensions() {
        Ok((w, h)) => Some((w.into(), h.into())),
        Err(_) => declared_size(bytes, format),
    }
}

/// The size a PNG, BMP, TGA or PPM header declares, read where each format keeps it (PNG's
/// IHDR, big-endian; BMP's info header, whose height is negative for rows stored top down,
/// and a negative width declares no size; TGA's image specification;
/// [`pnm_declared_size`]), for the images their decoders refuse before saying why.
fn declared_size(bytes: &[u8], format: ImageFormat) -> Option<(u64, u64)> {
    let u16_le = |at: usize| Some(u16::from_le_bytes(bytes.get(at..at + 2)?.try_into().ok()?).into());
    let i32_le = |at: usize| Some(i32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?));
    let u32_be = |at: usize| Some(u32::from_be_bytes(bytes.get(at..at + 4)?.try_into().ok()?).into());
    match format {
        ImageFormat::Png => Some((u32_be(16)?, u32_be(20)?)),
        // A 12-byte core header keeps 16-bit sides; the later headers 32-bit ones.
        ImageFormat::Bmp if u16_le(14)? == 12 => Some((u16_le(18)?, u16_le(20)?)),
        ImageFormat::Bmp => Some((u64::try_from(i32_le(18)?).ok()?, i32_le(22)?.unsigned_abs().into())),
        ImageFormat::Tga => Some((u16_le(12)?, u16_le(14)?)),
        ImageFormat::Pnm => pnm_declared_size(bytes),
        _ => None,
    }
}

/// The size a PNM header declares: the two numbers after the magic number (P1 to P6), or
/// the values of WIDTH and HEIGHT (P7, PAM); comments (`#` to the line's end) are skipped.
fn pnm_declared_size(bytes: &[u8]) -> Option<(u64, u64)> {
    let (magic, header) = bytes.split_at_checked(2)?;
    let mut words = header
        .split(|&b| b == b'\n')
        .flat_map(|line| {
            line.split(|&b| b == b'#')
                .next()
                .unwrap_or_default()
                .split(u8::is_ascii_whitespace)
        })
        .filter(|word| !word.is_empty());
    let number = |word: Option<&[u8]>| std::str::from_utf8(word?).ok()?.parse::<u64>().ok();
    if magic != b"P7" {
        return Some((number(words.next())?, number(words.next())?));
    }
    let (mut width, mut height) = (None, None);
    let mut fields = words.take_while(|&word| word != b"ENDHDR");
    while let Some(key) = fields.next() {
        match key {
            b"WIDTH" => width = number(fields.next()),
            b"HEIGHT" => height = number(fields.next()),
            _ => {}
        }
    }
    Some((width?, height?))
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

/// The image format a file's first bytes name (PFM, or one [`format_name`] names), for a
/// file given where a scene is expected; `None` when they name none, or the file cannot be
/// read. TGA, which has no signature, is not told.
pub fn image_signature(path: &Path) -> Option<&'static str> {
    use std::io::Read;
    let mut head = Vec::with_capacity(64);
    std::fs::File::open(path).ok()?.take(64).read_to_end(&mut head).ok()?;
    if looks_like_pfm(&head) {
        return Some("PFM");
    }
    image::guess_format(&head).ok().and_then(format_name)
}

/// Why a file that no format's signature starts is not read: its extension names a
/// format lumiere reads and its bytes are not that format's, or neither names one.
fn unrecognised(extension: &str) -> String {
    let named = if extension.eq_ignore_ascii_case("pfm") {
        Some("PFM")
    } else {
        ImageFormat::from_extension(extension).and_then(format_name)
    };
    match named {
        Some(format) => format!(
            "its extension .{extension} names {format}, but its first bytes are not a {format} file's: not an image, or one cut short or written as something else; lumiere reads {ALLOWED}"
        ),
        None => {
            let ext = if extension.is_empty() {
                "no extension".to_string()
            } else {
                format!("extension .{extension}")
            };
            format!(
                "not an image lumiere reads (neither its first bytes nor its {ext} name a known format); it reads {ALLOWED}"
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
            undrawn: Vec::new(),
            alpha_zero: 0,
        });
    }
    let format = match image::guess_format(bytes) {
        Ok(f) => f,
        Err(_) if extension.eq_ignore_ascii_case("tga") => ImageFormat::Tga,
        Err(_) => return Err(unrecognised(extension)),
    };
    let Some(name) = format_name(format) else {
        return Err(format!(
            "a {} image, which lumiere does not read; it reads {ALLOWED}",
            format
                .extensions_str()
                .first()
                .map_or("other".into(), |e| e.to_ascii_uppercase())
        ));
    };
    // The size from the header, before any pixel is decoded: a header may claim more than
    // memory holds.
    let size = header_size(bytes, format);
    if let Some(refusal) = size.and_then(|(w, h)| too_many_pixels(name, w, h)) {
        return Err(refusal);
    }
    let img = image::load_from_memory_with_format(bytes, format).map_err(|e| match (size, e) {
        (Some((w, h)), _) if w == 0 || h == 0 => no_pixels(name, w, h),
        (size, image::ImageError::IoError(e)) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
            cut_short(name, size, bytes.len())
        }
        (_, e) => format!("cannot decode the {name} image: {e}"),
    })?;
    let mut notes = Vec::new();
    // IHDR's colour type, the 26th byte of a PNG file: 3 is indexed colour, which the
    // decoder expands to its palette's colours.
    if format == ImageFormat::Png && bytes.get(25) == Some(&3) {
        notes.push(PALETTE_NOTE.into());
    }
    if format == ImageFormat::Jpeg {
        notes.push(JPEG_NOTE.into());
        if !bytes.ends_with(&[0xFF, 0xD9]) {
            notes.push(JPEG_CUT_NOTE.into());
        }
    }
    let (width, height) = (img.width(), img.height());
    let clear = alpha_is_zero(&img);
    let (rgb, not_opaque) = to_rgb8(img, name, &mut notes);
    let alpha_zero = clear.iter().filter(|&&c| c).count();
    let mut undrawn: Vec<bool> = clear
        .iter()
        .zip(rgb.chunks_exact(3))
        .map(|(&c, p)| c && p == [0, 0, 0])
        .collect();
    let undrawn_count = undrawn.iter().filter(|&&u| u).count();
    if undrawn_count == 0 {
        undrawn = Vec::new();
    }
    if let Some(not_opaque) = not_opaque {
        notes.push(alpha_note(
            not_opaque.saturating_sub(alpha_zero),
            alpha_zero - undrawn_count,
            undrawn_count,
        ));
    }
    Ok(Image {
        width,
        height,
        rgb,
        format: name,
        notes,
        undrawn,
        alpha_zero,
    })
}

/// Per pixel, whether its alpha is 0 once at 8 bits; empty when the image has no alpha
/// channel.
fn alpha_is_zero(img: &DynamicImage) -> Vec<bool> {
    if !img.color().has_alpha() {
        return Vec::new();
    }
    img.to_rgba8().pixels().map(|p| p.0[3] == 0).collect()
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

/// The note on a dropped alpha channel: `partly` pixels partly transparent and `coloured`
/// of alpha 0 with a colour, both compared as stored; `undrawn` transparent black, never
/// drawn ([`Image::undrawn`], left to the commands that leave them out).
fn alpha_note(partly: usize, coloured: usize, undrawn: usize) -> String {
    let mut kept = Vec::new();
    if partly > 0 {
        kept.push(format!(
            "{partly} pixels partly transparent, their colour compared as stored (not composited)"
        ));
    }
    if coloured > 0 {
        kept.push(format!(
            "{coloured} pixels fully transparent (alpha 0) but not black, their colour compared as stored (drawn with alpha never set?); only transparent black pixels (alpha and colour 0) are left out as never drawn"
        ));
    }
    match (kept.is_empty(), undrawn) {
        (true, 0) => "alpha channel dropped (every pixel opaque)".into(),
        (true, _) => "alpha channel dropped (every pixel opaque or transparent black)".into(),
        (false, _) => format!("alpha channel dropped: {}", kept.join("; ")),
    }
}

/// The 8-bit RGB of a decoded image, noting each conversion but the alpha channel's, and,
/// when it has one, how many pixels are not opaque at its own depth.
fn to_rgb8(img: DynamicImage, format: &str, notes: &mut Vec<String>) -> (Vec<u8>, Option<usize>) {
    let grey = "grey input: its level used for R, G and B";
    let sixteen = "16-bit input converted to 8 bits (round(255 v / 65535))";
    match img {
        DynamicImage::ImageRgb8(i) => (i.into_raw(), None),
        DynamicImage::ImageRgba8(i) => (
            i.pixels().flat_map(|p| [p.0[0], p.0[1], p.0[2]]).collect(),
            Some(i.pixels().filter(|p| p.0[3] != u8::MAX).count()),
        ),
        DynamicImage::ImageLuma8(i) => {
            notes.push(grey.into());
            (i.into_raw().into_iter().flat_map(|v| [v; 3]).collect(), None)
        }
        DynamicImage::ImageLumaA8(i) => {
            notes.push(grey.into());
            (
                i.pixels().flat_map(|p| [p.0[0]; 3]).collect(),
                Some(i.pixels().filter(|p| p.0[1] != u8::MAX).count()),
            )
        }
        DynamicImage::ImageRgb16(i) => {
            notes.push(sixteen.into());
            (i.into_raw().into_iter().map(level_from_16).collect(), None)
        }
        DynamicImage::ImageRgba16(i) => {
            notes.push(sixteen.into());
            (
                i.pixels()
                    .flat_map(|p| [0, 1, 2].map(|c| level_from_16(p.0[c])))
                    .collect(),
                Some(i.pixels().filter(|p| p.0[3] != u16::MAX).count()),
            )
        }
        DynamicImage::ImageLuma16(i) => {
            notes.push(sixteen.into());
            notes.push(grey.into());
            (
                i.into_raw().into_iter().flat_map(|v| [level_from_16(v); 3]).collect(),
                None,
            )
        }
        DynamicImage::ImageLumaA16(i) => {
            notes.push(sixteen.into());
            notes.push(grey.into());
            (
                i.pixels().flat_map(|p| [level_from_16(p.0[0]); 3]).collect(),
                Some(i.pixels().filter(|p| p.0[1] != u16::MAX).count()),
            )
        }
        DynamicImage::ImageRgb32F(i) => (float_rgb(i.as_raw(), 3, format, notes), None),
        DynamicImage::ImageRgba32F(i) => (
            float_rgb(i.as_raw(), 4, format, notes),
            Some(i.pixels().filter(|p| p.0[3] != 1.0).count()),
        ),
        other => {
            notes.push(format!("{:?} pixels converted to 8-bit RGB", other.color()));
            let alpha = other
                .color()
                .has_alpha()
                .then(|| other.to_rgba8().pixels().filter(|p| p.0[3] != u8::MAX).count());
            (other.to_rgb8().into_raw(), alpha)
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
        let image = |rgb: Vec<u8>, undrawn: Vec<bool>, alpha_zero: usize| Image {
            width: 2,
            height: 1,
            rgb,
            format: "PNG",
            notes: Vec::new(),
            undrawn,
            alpha_zero,
        };
        // Both pixels at alpha 0, one of them red: colours drawn, alpha never set.
        let unset = image(vec![0, 0, 0, 255, 0, 0], vec![true, false], 2);
        assert!(unset.nothing_drawn());
        assert!(unset.alpha_hint().contains("TYPE_INT_ARGB"));
        // Both at alpha 0 and black: nothing drawn, no hint.
        let clear = image(vec![0; 6], vec![true, true], 2);
        assert!(clear.nothing_drawn());
        assert_eq!(clear.alpha_hint(), "");
        // One pixel drawn, or none transparent: no hint either.
        assert_eq!(image(vec![255, 0, 0, 0, 0, 0], vec![false, true], 1).alpha_hint(), "");
        assert_eq!(image(vec![255; 6], Vec::new(), 0).alpha_hint(), "");
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
            "not an image lumiere reads (neither its first bytes nor its extension .txt name a known format); it reads PNG, PPM / PGM / PBM (ASCII or binary), PFM, EXR, JPEG, BMP, TGA"
        );
        for ext in ["png", "tga", ""] {
            assert_eq!(
                decode(b"", ext).unwrap_err(),
                "the file is empty (0 bytes): no image was written to it"
            );
        }
        assert_eq!(
            decode(b"hello, world", "png").unwrap_err(),
            "its extension .png names PNG, but its first bytes are not a PNG file's: not an image, or one cut short or written as something else; lumiere reads PNG, PPM / PGM / PBM (ASCII or binary), PFM, EXR, JPEG, BMP, TGA"
        );
        let e = decode(b"hello, world", "PFM").unwrap_err();
        assert!(
            e.starts_with("its extension .PFM names PFM, but its first bytes are not a PFM file's"),
            "{e}"
        );
        let e = decode(b"GIF89a\x01\x00\x01\x00", "gif").unwrap_err();
        assert!(e.starts_with("a GIF image, which lumiere does not read"), "{e}");
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
        let bmp = bmp_header(5, 0);
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

    /// The file and info headers of a 24-bit BMP of `width` x `height` pixels (a negative
    /// height for rows stored top down), without its pixels.
    fn bmp_header(width: i32, height: i32) -> Vec<u8> {
        let mut bmp = b"BM".to_vec();
        bmp.extend([54u32, 0, 54].iter().flat_map(|v| v.to_le_bytes()));
        bmp.extend(40u32.to_le_bytes());
        bmp.extend(width.to_le_bytes());
        bmp.extend(height.to_le_bytes());
        bmp.extend([1u8, 0, 24, 0]);
        bmp.extend([0u8; 24]);
        bmp
    }

    /// Headers claiming more pixels than lumiere renders, which BMP's and PPM's decoders
    /// refuse in their own words (a side past 65535; sides whose bytes pass 64 bits), are
    /// refused naming the size, as PNG's are.
    #[test]
    fn huge_bmp_and_ppm_headers_are_refused_naming_their_size() {
        let mut core = b"BM".to_vec();
        core.extend([26u32, 0, 26].iter().flat_map(|v| v.to_le_bytes()));
        core.extend(12u32.to_le_bytes());
        core.extend([65535u16, 65535, 1, 24].iter().flat_map(|v| v.to_le_bytes()));
        let bmp = |w, h| (bmp_header(w, h), "bmp");
        let ppm = |text: &'static str| (text.as_bytes().to_vec(), "ppm");
        for ((bytes, extension), message) in [
            (
                bmp(100_000, 100_000),
                "the BMP image is 100000 x 100000 = 10000000000 pixels",
            ),
            (
                bmp(100_000, -100_000),
                "the BMP image is 100000 x 100000 = 10000000000 pixels",
            ),
            (bmp(1, i32::MIN), "the BMP image is 1 x 2147483648 = 2147483648 pixels"),
            ((core, "bmp"), "the BMP image is 65535 x 65535 = 4294836225 pixels"),
            (
                ppm("P6\n4294967295 4294967295\n255\n"),
                "the PPM image is 4294967295 x 4294967295 = 18446744065119617025 pixels",
            ),
            (
                ppm("P3 # made by hand\n# a whole line of comment\n4294967295\r\n4294967295 255\n"),
                "the PPM image is 4294967295 x 4294967295 = 18446744065119617025 pixels",
            ),
            (
                ppm("P5\n4294967296 1\n255\n"),
                "the PPM image is 4294967296 x 1 = 4294967296 pixels",
            ),
            (
                ppm("P7\nWIDTH 4294967295\nHEIGHT 4294967295\nDEPTH 3\nMAXVAL 255\nTUPLTYPE RGB\nENDHDR\n"),
                "the PPM image is 4294967295 x 4294967295 = 18446744065119617025 pixels",
            ),
        ] {
            assert_eq!(
                decode(&bytes, extension).unwrap_err(),
                format!("{message}: lumiere reads at most 33554432 (as many as it renders)")
            );
        }
    }
}
