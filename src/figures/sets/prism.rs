//! Set `prism`: the transparent block of n = 1.66 (scenes/prism.toml), a top view at depth
//! 1, then recursion depth 1 to 20. Rays meeting the side faces from inside beyond 37.04
//! degrees are totally reflected; adaptive depth control keeps depth 20 affordable.

use crate::figures::{Figure, base_scene};
use glam::DVec3;

pub fn figures() -> Vec<Figure> {
    let mut top = base_scene("prism");
    top.settings.depth = 1;
    top.camera.position = DVec3::new(0.0, 0.0, 14.0);
    top.camera.look_at = DVec3::ZERO;
    top.camera.up = DVec3::Y;
    let mut figures = vec![Figure::new(1, "top-depth-01", "Récursivité : 1 (vue de haut)", top)];
    for depth in 1..=20 {
        let mut scene = base_scene("prism");
        scene.settings.depth = depth;
        figures.push(Figure::new(
            figures.len() + 1,
            &format!("depth-{depth:02}"),
            format!("Récursivité : {depth}"),
            scene,
        ));
    }
    figures
}
