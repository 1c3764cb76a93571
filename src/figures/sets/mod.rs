//! One file per figure set of shared/FIGURES.md, and the light constructors they share.

mod attenuation;
mod directional;
mod light_shapes;
mod lighting;
mod mirrors;
pub use mirrors::mirrors_scene;
mod prism;
mod shading;
mod soft_shadows;
mod spotlight;

use super::FigureSet;
use crate::area_light::{AreaLight, AreaShape, PointMode};
use crate::light::{Attenuation, Light, PointLight, SpotLight};
use crate::placement::Placement;
use crate::scene::Scene;
use glam::DVec3;

/// Every set, in the order of the course.
pub fn all() -> Vec<FigureSet> {
    vec![
        FigureSet {
            name: "lighting",
            title: "Sources de lumière ambiante et directionnelle",
            figures: lighting::figures,
        },
        FigureSet {
            name: "directional",
            title: "Orientation de la source directionnelle",
            figures: directional::figures,
        },
        FigureSet {
            name: "attenuation",
            title: "Source ponctuelle et atténuation",
            figures: attenuation::figures,
        },
        FigureSet {
            name: "spotlight",
            title: "Source ponctuelle orientée (spotlight)",
            figures: spotlight::figures,
        },
        FigureSet {
            name: "soft-shadows",
            title: "Ombres dures et molles : source sphérique de N points",
            figures: soft_shadows::figures,
        },
        FigureSet {
            name: "light-shapes",
            title: "Formes de sources : sphère, tube, fenêtre (N = 100)",
            figures: light_shapes::figures,
        },
        FigureSet {
            name: "mirrors",
            title: "Deux miroirs plans",
            figures: mirrors::figures,
        },
        FigureSet {
            name: "prism",
            title: "Prisme rectangulaire transparent (n = 1.66)",
            figures: prism::figures,
        },
        FigureSet {
            name: "shading",
            title: "IFT3355 : illumination locale",
            figures: shading::figures,
        },
    ]
}

/// White ambient light.
pub(crate) fn ambient() -> Light {
    Light::Ambient { color: DVec3::ONE }
}

/// White directional light of orientation `d` (normalised here).
pub(crate) fn directional(d: [f64; 3]) -> Light {
    Light::Directional {
        direction: DVec3::from(d).normalize(),
        color: DVec3::ONE,
    }
}

/// White point light.
pub(crate) fn point(position: [f64; 3], attenuation: Attenuation) -> Light {
    Light::Point(PointLight {
        position: DVec3::from(position),
        color: DVec3::ONE,
        attenuation,
    })
}

/// White spotlight with `C_max = 1`, `C_min = 0` and no distance attenuation.
pub(crate) fn spot(position: [f64; 3], orientation: [f64; 3], angle_deg: f64) -> Light {
    Light::Spot(SpotLight::new(
        DVec3::from(position),
        DVec3::from(orientation),
        angle_deg,
        0.0,
        1.0,
        DVec3::ONE,
        Attenuation::NONE,
    ))
}

/// White area light of `n` points on `shape`, placed by the chapter's recipe and fixed for
/// the whole image (the figures' look: N distinct shadows).
pub(crate) fn area(shape: AreaShape, n: u32, attenuation: Attenuation) -> Light {
    Light::Area(AreaLight {
        shape,
        count: n,
        placement: Placement::Chapter,
        mode: PointMode::Fixed,
        color: DVec3::ONE,
        attenuation,
    })
}

/// The spherical light of the soft-shadow figures: `n` points, centre (0, 0, 10), radius
/// 2, `C_quad` 0.005.
pub(crate) fn area_sphere(n: u32) -> Light {
    let shape = AreaShape::Sphere {
        center: DVec3::from(soft_shadows::CENTRE),
        radius: 2.0,
    };
    area(shape, n, quadratic(soft_shadows::C_QUAD))
}

/// Quadratic attenuation `C_const = 1`, `C_quad = q`.
pub(crate) fn quadratic(q: f64) -> Attenuation {
    Attenuation {
        constant: 1.0,
        linear: 0.0,
        quadratic: q,
    }
}

/// The reference scene of the chapter with the given lights.
pub(crate) fn reference_with(lights: Vec<Light>) -> Scene {
    let mut s = super::base_scene("reference");
    s.lights = lights;
    s
}
