//! Set `spotlight`: ambient + spot at (0, 0, 10) pointing down, C_max 1, C_min 0, no
//! distance attenuation, opening 70 and 120 degrees.

use super::{ambient, reference_with, spot};
use crate::figures::Figure;

pub fn figures() -> Vec<Figure> {
    [70.0, 120.0]
        .iter()
        .enumerate()
        .map(|(i, &theta)| {
            Figure::new(
                i + 1,
                &format!("theta-{theta}"),
                format!("Avec un angle d'ouverture θ = {theta}°"),
                reference_with(vec![ambient(), spot([0.0, 0.0, 10.0], [0.0, 0.0, -1.0], theta)]),
            )
        })
        .collect()
}
