//! The in-memory scene: what a scene file describes, validated. [`crate::world::World`]
//! builds what rendering needs from it.

mod file;
pub mod generate;
mod locate;
mod overrides;
mod tag;
pub mod transform;

pub use file::{SceneError, load, parse};
pub use overrides::Overrides;

use crate::conventions::Conventions;
use crate::light::Light;
use crate::material::Material;
use crate::shape::Shape;
use glam::DVec3;

/// Which specular term the local illumination model uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Specular {
    None,
    /// Phong: `(R.E)^n`.
    Phong,
    /// Blinn: `(N.H)^n`.
    Blinn,
}

/// The terms of the local illumination model (slides): each can be switched off to draw
/// the slides' "ambient only", "diffuse only", "specular only" figures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct ShadingModel {
    pub ambient: bool,
    pub diffuse: bool,
    pub specular: Specular,
}

impl Default for ShadingModel {
    /// Chapter 7.4b's choice: ambient + Lambert + Blinn.
    fn default() -> Self {
        ShadingModel {
            ambient: true,
            diffuse: true,
            specular: Specular::Blinn,
        }
    }
}

/// Image and tracing settings (the `[image]` and `[render]` tables).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel, a perfect square `n^2` (an `n x n` stratified jittered grid).
    pub samples_per_pixel: u32,
    pub seed: u64,
    /// Recursion depth as counted in the chapter's figures: 1 = no secondary rays.
    pub depth: u32,
    pub shading: ShadingModel,
    /// Cast shadow rays (off: every light reaches every point facing it).
    pub shadows: bool,
    /// Colour of rays that hit nothing.
    pub background: DVec3,
    /// Adaptive depth control: a secondary ray is not traced when the most it could add to
    /// the pixel is below this many 8-bit levels (0 = off).
    pub adaptive_threshold: f64,
    /// Where the chapter's and SIMRenderer's conventions differ, which this scene follows.
    pub conventions: Conventions,
}

impl Settings {
    /// Side `n` of the `n x n` sample grid.
    pub fn grid_side(&self) -> u32 {
        (self.samples_per_pixel as f64).sqrt().round() as u32
    }
}

/// Camera as written in the scene file; the aspect ratio comes from the image size.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CameraSpec {
    pub position: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    pub vfov_deg: f64,
}

/// One object: a shape with a material.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Object {
    /// The name given in the file, or `<kind>#<index>`.
    pub name: String,
    pub shape: Shape,
    /// Index into `Scene::materials`.
    pub material: usize,
}

/// A validated scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Scene {
    pub settings: Settings,
    pub camera: CameraSpec,
    pub materials: Vec<Material>,
    pub material_names: Vec<String>,
    /// Whether each material gives its metal factor `m`; the others take the conventions'
    /// default highlight ([`Scene::set_conventions`]).
    pub metal_given: Vec<bool>,
    pub objects: Vec<Object>,
    pub lights: Vec<Light>,
}

impl Scene {
    /// Follows `conventions` from now on: the materials that give no metal factor take its
    /// default highlight.
    pub fn set_conventions(&mut self, conventions: Conventions) {
        self.settings.conventions = conventions;
        for (material, &given) in self.materials.iter_mut().zip(&self.metal_given) {
            if !given {
                material.metal = conventions.default_highlight.metal();
            }
        }
    }

    /// The sum of the ambient lights' colours, `L_a`.
    pub fn ambient(&self) -> DVec3 {
        self.lights.iter().map(Light::ambient).sum()
    }
}
