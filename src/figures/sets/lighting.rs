//! Set `lighting`: ambient only, directional only, both (d = (1, 1, -1)).

use super::{ambient, directional, reference_with};
use crate::figures::Figure;

pub fn figures() -> Vec<Figure> {
    let d = [1.0, 1.0, -1.0];
    vec![
        Figure::new(
            1,
            "ambient",
            "Avec source de lumière ambiante",
            reference_with(vec![ambient()]),
        ),
        Figure::new(
            2,
            "directional",
            "Avec source de lumière directionnelle",
            reference_with(vec![directional(d)]),
        ),
        Figure::new(
            3,
            "ambient-directional",
            "Avec source de lumière ambiante et directionnelle",
            reference_with(vec![ambient(), directional(d)]),
        ),
    ]
}
