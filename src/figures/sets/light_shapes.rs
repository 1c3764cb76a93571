//! Set `light-shapes` (beyond the chapter, which only names them): N = 100 points on a
//! sphere (centre (0, 0, 10), radius 2), a tube from (-2, 0, 10) to (2, 0, 10), and a window
//! centred at (0, 0, 10) with edges (4, 0, 0) and (0, 3, 0); `C_quad` 0.005 as in
//! `soft-shadows`, points fixed for the image.

use super::soft_shadows::{C_QUAD, CENTRE};
use super::{ambient, area, area_sphere, quadratic, reference_with};
use crate::area_light::AreaShape;
use crate::figures::Figure;
use glam::DVec3;

const N: u32 = 100;

pub fn figures() -> Vec<Figure> {
    let tube = AreaShape::Tube {
        start: DVec3::new(-2.0, 0.0, 10.0),
        end: DVec3::new(2.0, 0.0, 10.0),
    };
    let window = AreaShape::Window {
        center: DVec3::from(CENTRE),
        edge1: DVec3::new(4.0, 0.0, 0.0),
        edge2: DVec3::new(0.0, 3.0, 0.0),
    };
    vec![
        Figure::new(
            1,
            "sphere",
            "Source sphérique (N = 100)",
            reference_with(vec![ambient(), area_sphere(N)]),
        ),
        Figure::new(
            2,
            "tube",
            "Source en tube (N = 100)",
            reference_with(vec![ambient(), area(tube, N, quadratic(C_QUAD))]),
        ),
        Figure::new(
            3,
            "window",
            "Source en fenêtre (N = 100)",
            reference_with(vec![ambient(), area(window, N, quadratic(C_QUAD))]),
        ),
    ]
}
