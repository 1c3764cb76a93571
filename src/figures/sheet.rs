//! Contact sheets: every image of a set as a thumbnail with its caption from the chapter,
//! under the set's title ([`crate::text`] draws the captions).

use crate::text::{draw_text, wrap};
use image::{Rgb, RgbImage, imageops};
use rayon::prelude::*;

const BACKGROUND: Rgb<u8> = Rgb([32, 32, 36]);
const TEXT: Rgb<u8> = Rgb([235, 235, 235]);
/// Thumbnail width in pixels (the images' own width when they are narrower).
const THUMB_WIDTH: u32 = 320;
const MARGIN: u32 = 12;
const LINE: u32 = 11;
/// The title's glyphs are 8 x 8 drawn at this scale: 16 pixels tall, 16 wide.
const TITLE_SCALE: u32 = 2;
/// Height of a title line, its glyphs and the space under them.
const TITLE_LINE: u32 = 8 * TITLE_SCALE + 4;

/// A contact sheet: `title` (wrapped to the sheet's width), then the images in a grid of up
/// to 4 columns, each with its caption (wrapped to the thumbnail's width).
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
    let width = MARGIN + cols * cell_w;
    let title_lines = wrap(title, ((width - 2 * MARGIN) / (8 * TITLE_SCALE)) as usize);
    let title_h = title_lines.len().max(1) as u32 * TITLE_LINE - 4 + 2 * MARGIN;
    let mut sheet = RgbImage::from_pixel(width, title_h + rows * cell_h, BACKGROUND);
    for (l, line) in title_lines.iter().enumerate() {
        draw_text(
            &mut sheet,
            MARGIN,
            MARGIN + l as u32 * TITLE_LINE,
            line,
            TITLE_SCALE,
            TEXT,
        );
    }
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

    /// The rows of `sheet` between `y0` and `y1` holding a pixel of the text's colour.
    fn text_rows(sheet: &RgbImage, y0: u32, y1: u32) -> Vec<u32> {
        (y0..y1)
            .filter(|&y| (0..sheet.width()).any(|x| *sheet.get_pixel(x, y) == TEXT))
            .collect()
    }

    #[test]
    fn a_title_wider_than_the_sheet_wraps() {
        // Three 200 x 150 previews make a sheet 12 + 3 x 212 = 648 pixels wide, room for 39
        // title glyphs of 16 pixels: the 45 of the lighting set's title take two lines.
        let img = RgbImage::from_pixel(200, 150, Rgb([0, 0, 0]));
        let images = [(&img, "a"), (&img, "b"), (&img, "c")];
        let sheet = contact_sheet("Sources de lumière ambiante et directionnelle", &images);
        // Title band: 12 + 2 x 20 - 4 + 12 = 60 rows; then one row of cells 150 + 6 + 11 + 12.
        assert_eq!((sheet.width(), sheet.height()), (648, 60 + 179));
        let rows = text_rows(&sheet, 0, 60);
        assert!(
            rows.iter().any(|&y| y < 12 + 16) && rows.iter().any(|&y| y >= 12 + 20),
            "{rows:?}"
        );
        assert!(
            rows.iter()
                .all(|&y| (12..12 + 16).contains(&y) || (32..32 + 16).contains(&y))
        );
        // "directionnelle" (14 glyphs) on the second line: nothing is cut at the right edge.
        let second_line_right = (32..48).flat_map(|y| (12 + 14 * 16..648).map(move |x| (x, y)));
        assert!(second_line_right.clone().all(|(x, y)| *sheet.get_pixel(x, y) != TEXT));
        assert!((32..48).any(|y| (12 + 13 * 16..12 + 14 * 16).any(|x| *sheet.get_pixel(x, y) == TEXT)));
    }

    #[test]
    fn a_title_that_fits_takes_one_line() {
        // Four 320 x 240 thumbnails: 1340 pixels, 82 glyphs a line; the title band is
        // 12 + 16 + 12 = 40 rows.
        let img = RgbImage::from_pixel(800, 600, Rgb([0, 0, 0]));
        let images = [(&img, "a"), (&img, "b"), (&img, "c"), (&img, "d")];
        let sheet = contact_sheet("Sources de lumière ambiante et directionnelle", &images);
        assert_eq!((sheet.width(), sheet.height()), (1340, 40 + 240 + 6 + 11 + 12));
        let rows = text_rows(&sheet, 0, 40);
        assert!(rows.iter().all(|&y| (12..28).contains(&y)), "{rows:?}");
    }
}
