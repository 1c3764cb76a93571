//! Contact sheets: every image of a set as a thumbnail with its caption from the chapter,
//! under the set's title. Text is drawn with the public-domain 8x8 bitmap glyphs of the
//! `font8x8` crate (Latin-1 and Greek cover the captions' accents, degree sign and theta).

use font8x8::{BASIC_FONTS, GREEK_FONTS, LATIN_FONTS, MISC_FONTS, UnicodeFonts};
use image::{Rgb, RgbImage, imageops};
use rayon::prelude::*;

const BACKGROUND: Rgb<u8> = Rgb([32, 32, 36]);
const TEXT: Rgb<u8> = Rgb([235, 235, 235]);
/// Thumbnail width in pixels (a quarter of the figures' 800 at full size... or less).
const THUMB_WIDTH: u32 = 320;
const MARGIN: u32 = 12;
const LINE: u32 = 11;

/// The 8x8 glyph of `c`, or of '?' when the font has none.
fn glyph(c: char) -> [u8; 8] {
    BASIC_FONTS
        .get(c)
        .or_else(|| LATIN_FONTS.get(c))
        .or_else(|| GREEK_FONTS.get(c))
        .or_else(|| MISC_FONTS.get(c))
        .or_else(|| BASIC_FONTS.get('?'))
        .unwrap_or([0; 8])
}

/// Draws `text` with its top-left corner at `(x, y)`, each font pixel `scale` x `scale`.
pub fn draw_text(img: &mut RgbImage, x: u32, y: u32, text: &str, scale: u32, color: Rgb<u8>) {
    for (i, c) in text.chars().enumerate() {
        let g = glyph(c);
        for (row, bits) in g.iter().enumerate() {
            for col in 0..8 {
                if bits & (1 << col) == 0 {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        let px = x + (i as u32 * 8 + col) * scale + dx;
                        let py = y + row as u32 * scale + dy;
                        if px < img.width() && py < img.height() {
                            img.put_pixel(px, py, color);
                        }
                    }
                }
            }
        }
    }
}

/// Splits `text` into lines of at most `max_chars` characters at spaces.
pub fn wrap(text: &str, max_chars: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > max_chars {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// A contact sheet: `title`, then the images in a grid of up to 4 columns, each with its
/// caption (wrapped to the thumbnail's width).
pub fn contact_sheet(title: &str, images: &[(&RgbImage, &str)]) -> RgbImage {
    let cols = images.len().clamp(1, 4) as u32;
    let rows = (images.len() as u32).div_ceil(cols);
    let (w0, h0) = images.first().map_or((4, 3), |(i, _)| (i.width(), i.height()));
    let tw = THUMB_WIDTH.min(w0);
    let th = (tw as f64 * h0 as f64 / w0 as f64).round().max(1.0) as u32;
    let max_chars = (tw / 8) as usize;
    let caption_lines = images
        .iter()
        .map(|(_, c)| wrap(c, max_chars).len() as u32)
        .max()
        .unwrap_or(1);
    let cell_w = tw + MARGIN;
    let cell_h = th + 6 + caption_lines * LINE + MARGIN;
    let title_h = 16 + 2 * MARGIN;
    let mut sheet = RgbImage::from_pixel(MARGIN + cols * cell_w, title_h + rows * cell_h, BACKGROUND);
    draw_text(&mut sheet, MARGIN, MARGIN, title, 2, TEXT);
    // The thumbnails on every core: resizing is most of a sheet's time.
    let thumbs: Vec<RgbImage> = images
        .par_iter()
        .map(|(img, _)| imageops::resize(*img, tw, th, imageops::FilterType::Triangle))
        .collect();
    for (i, ((_, caption), thumb)) in images.iter().zip(&thumbs).enumerate() {
        let (cx, cy) = (i as u32 % cols, i as u32 / cols);
        let (x, y) = (MARGIN + cx * cell_w, title_h + cy * cell_h);
        imageops::replace(&mut sheet, thumb, x as i64, y as i64);
        for (l, line) in wrap(caption, max_chars).iter().enumerate() {
            draw_text(&mut sheet, x, y + th + 6 + l as u32 * LINE, line, 1, TEXT);
        }
    }
    sheet
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn captions_have_glyphs() {
        // Accents, degree sign and theta of the chapter's captions all exist in the font.
        for c in "éèàçù°θ'".chars() {
            assert_ne!(glyph(c), glyph('?'), "{c}");
        }
    }

    #[test]
    fn wrapping_keeps_words() {
        assert_eq!(
            wrap("Niveau de récursivité : 3", 12),
            vec!["Niveau de", "récursivité", ": 3"]
        );
    }

    #[test]
    fn text_is_drawn_where_asked() {
        let mut img = RgbImage::from_pixel(20, 10, BACKGROUND);
        draw_text(&mut img, 2, 1, "I", 1, TEXT);
        let lit = img.pixels().filter(|p| **p == TEXT).count();
        assert!(lit > 5);
        assert_eq!(*img.get_pixel(19, 9), BACKGROUND);
    }
}
