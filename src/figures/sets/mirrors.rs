//! Set `mirrors`: two plane mirrors on a vertical hinge (scenes/mirrors.toml), opening 60
//! degrees at recursion depth 1 to 10, then 90 / depth 4, 45 / depth 8, 30 / depth 10. Each
//! manifest entry records the cone images counted on the image; with enough depth the count
//! is floor(360 / opening - 1): 3, 5, 7, 11.

use crate::figures::{Figure, Measure, parse_embedded};
use crate::scene::Scene;

/// scenes/mirrors.toml with its opening angle replaced.
pub fn mirrors_scene(opening: u32, depth: u32) -> Scene {
    let text = include_str!("../../../scenes/mirrors.toml");
    assert!(
        text.contains("opening = 60\n"),
        "scenes/mirrors.toml must keep `opening = 60`"
    );
    let mut scene = parse_embedded(
        &text.replace("opening = 60\n", &format!("opening = {opening}\n")),
        "mirrors",
    );
    scene.settings.depth = depth;
    scene
}

pub fn figures() -> Vec<Figure> {
    let mut figures: Vec<Figure> = (1..=10)
        .map(|depth| {
            Figure::new(
                depth as usize,
                &format!("opening-60-depth-{depth:02}"),
                format!("Niveau de récursivité : {depth}"),
                mirrors_scene(60, depth),
            )
        })
        .collect();
    for (opening, depth) in [(90, 4), (45, 8), (30, 10)] {
        figures.push(Figure::new(
            figures.len() + 1,
            &format!("opening-{opening}-depth-{depth:02}"),
            format!("Angle d'ouverture : {opening}°, récursivité : {depth}"),
            mirrors_scene(opening, depth),
        ));
    }
    figures.into_iter().map(|f| f.measuring(Measure::ConeImages)).collect()
}
