//! Text drawn into images (contact sheets, review sheets, study plots) with the
//! public-domain 8x8 bitmap glyphs of the `font8x8` crate: Latin-1 and Greek cover the
//! captions' accents, degree sign and theta.

use font8x8::{BASIC_FONTS, GREEK_FONTS, LATIN_FONTS, MISC_FONTS, UnicodeFonts};
use image::{Rgb, RgbImage};

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
        let mut img = RgbImage::from_pixel(20, 10, Rgb([32, 32, 36]));
        draw_text(&mut img, 2, 1, "I", 1, Rgb([235, 235, 235]));
        let lit = img.pixels().filter(|p| **p == Rgb([235, 235, 235])).count();
        assert!(lit > 5);
        assert_eq!(*img.get_pixel(19, 9), Rgb([32, 32, 36]));
    }
}
