//! Set `directional`: ambient + directional light at four orientations; the specular
//! highlight moves with the orientation (the chapter's remark).

use super::{ambient, directional, reference_with};
use crate::figures::Figure;

pub const ORIENTATIONS: [[f64; 3]; 4] = [[1.0, 1.0, -1.0], [0.5, 1.0, -1.0], [0.0, 1.0, -1.0], [-1.0, 1.0, -1.0]];

pub fn figures() -> Vec<Figure> {
    ORIENTATIONS
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let caption = format!("Orientation de la source : ({}, {}, {})", d[0], d[1], d[2]);
            let short = format!("d-{}-{}-{}", d[0], d[1], d[2]).replace('.', "p");
            Figure::new(i + 1, &short, caption, reference_with(vec![ambient(), directional(*d)]))
        })
        .collect()
}
