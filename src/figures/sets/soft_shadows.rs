//! Set `soft-shadows` (chapter 7.4b, "Les ombres dures et molles" and "La source de lumière
//! à multiple points ponctuelles"): ambient + one light at (0, 0, 10), `C_quad` 0.005. A
//! point light's hard shadows, then a spherical light of radius 2 made of N = 1, 5, 25,
//! 100, 200, 1000 points placed by the chapter's recipe, fixed for the whole image (N
//! distinct shadows and highlights, not noise). The N points are the first N of one seeded
//! sequence, so the 5 points are among the 25.

use super::{ambient, area_sphere, point, quadratic, reference_with};
use crate::figures::Figure;

/// The light's centre, shared with `light-shapes`.
pub(crate) const CENTRE: [f64; 3] = [0.0, 0.0, 10.0];
/// `C_quad` of every light of the set.
pub(crate) const C_QUAD: f64 = 0.005;

pub fn figures() -> Vec<Figure> {
    let mut figures = vec![
        Figure::new(
            1,
            "hard",
            "Scène avec source de lumière ponctuelle produisant des ombres dures",
            reference_with(vec![ambient(), point(CENTRE, quadratic(C_QUAD))]),
        ),
        Figure::new(
            2,
            "soft-200",
            "Scène avec source de lumière sphérique produisant des ombres molles (N = 200)",
            reference_with(vec![ambient(), area_sphere(200)]),
        ),
    ];
    for (i, n) in [1, 5, 25, 100, 200, 1000].into_iter().enumerate() {
        figures.push(Figure::new(
            i + 3,
            &format!("points-{n}"),
            format!("Source sphérique de N = {n} points de lumière"),
            reference_with(vec![ambient(), area_sphere(n)]),
        ));
    }
    figures
}
