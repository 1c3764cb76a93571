//! Set `attenuation`: ambient + point light at (0, 0, 10), without attenuation and with
//! `C_quad = 0.01`. The chapter expects A of about 0.1 at d of about 10, but its own formula
//! gives 1 / (1 + 0.01 * 100) = 0.5; the formula is the authority, and the manifest records
//! the measured range of A over visible lit points so the discrepancy is visible.

use super::{ambient, point, quadratic, reference_with};
use crate::figures::{Figure, Measure};
use crate::light::Attenuation;

pub fn figures() -> Vec<Figure> {
    let light = [0.0, 0.0, 10.0];
    vec![
        Figure::new(
            1,
            "no-attenuation",
            "Sans facteur d'atténuation",
            reference_with(vec![ambient(), point(light, Attenuation::NONE)]),
        )
        .measuring(Measure::AttenuationRange),
        Figure::new(
            2,
            "quadratic-0p01",
            "Avec facteur d'atténuation C_quad = 0.01",
            reference_with(vec![ambient(), point(light, quadratic(0.01))]),
        )
        .measuring(Measure::AttenuationRange),
    ]
}
