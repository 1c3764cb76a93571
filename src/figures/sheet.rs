//! Contact sheets: every image of a set as a thumbnail with its caption from the chapter,
//! under the set's title ([`crate::text`] draws the captions).

use crate::text::{draw_text, wrap};
use image::{Rgb, RgbImage, imageops};
use rayon::prelude::*;

const BACKGROUND: Rgb<u8> = Rgb([32, 32, 36]);
const TEXT: Rgb<u8> = Rgb([235, 235, 235]);
/// Thumbnail width in pixels (a quarter of the figures' 800 at full size... or less).
const THUMB_WIDTH: u32 = 320;
const MARGIN: u32 = 12;
const LINE: u32 = 11;

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
