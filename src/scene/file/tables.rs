//! The scene's single tables: `[image]`, `[camera]`, `[render]`, `[caustics]` and
//! `[conventions]`, with their defaults; the caustics and conventions tables checked here.

use super::check::{Check, Whole, Xyz, fail, placed, plus_z, positive};
use crate::conventions::Conventions;
use crate::limits;
use crate::scene::locate::FieldPath;
use crate::scene::{CausticSettings, PhotonFilter};
use serde::Deserialize;

/// The `[image]` table: the picture's size, samples per pixel and seed.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileImage {
    pub(super) width: Whole,
    pub(super) height: Whole,
    #[serde(default = "default_spp")]
    pub(super) samples_per_pixel: Whole,
    #[serde(default = "default_seed")]
    pub(super) seed: u64,
}

fn default_spp() -> Whole {
    4
}

fn default_seed() -> u64 {
    42
}

/// The `[camera]` table: at `position`, looking at `look_at`, `vfov` degrees high.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileCamera {
    pub(super) position: Xyz,
    pub(super) look_at: Xyz,
    #[serde(default = "plus_z")]
    pub(super) up: Xyz,
    #[serde(default = "default_fov")]
    pub(super) vfov: f64,
}

/// Largest vertical field of view, in degrees: the camera's range is (0, MAX_VFOV].
pub(super) const MAX_VFOV: f64 = 179.0;

fn default_fov() -> f64 {
    60.0
}

/// The `[render]` table: recursion depth, shading terms, shadows, background and the
/// adaptive threshold, each with its default.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, default)]
pub(super) struct FileRender {
    pub(super) depth: Whole,
    pub(super) ambient: bool,
    pub(super) diffuse: bool,
    /// "blinn", "phong" or "none".
    pub(super) specular: String,
    /// The diffuse colour `k_d S` alone, no light (with the three terms above off).
    pub(super) no_light: bool,
    pub(super) shadows: bool,
    pub(super) background: Xyz,
    /// "clamp_channel" or "division_factor" ([`crate::film::Normalization`]).
    pub(super) color_normalization: String,
    pub(super) adaptive_threshold: f64,
}

impl Default for FileRender {
    fn default() -> Self {
        FileRender {
            depth: 1,
            ambient: true,
            diffuse: true,
            specular: "blinn".to_string(),
            no_light: false,
            shadows: true,
            background: Xyz([0.0; 3]),
            color_normalization: "clamp_channel".to_string(),
            adaptive_threshold: limits::DEFAULT_ADAPTIVE_THRESHOLD,
        }
    }
}

/// The `[caustics]` table (scenes/README.md): `photons` is required, the estimate's
/// parameters have defaults.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileCaustics {
    photons: Whole,
    #[serde(default = "default_photon_radius")]
    radius: f64,
    #[serde(default = "default_photon_filter")]
    filter: String,
    #[serde(default = "default_photon_bounces")]
    bounces: Whole,
    seed: Option<u64>,
}

fn default_photon_radius() -> f64 {
    limits::DEFAULT_PHOTON_RADIUS
}

fn default_photon_filter() -> String {
    "cone".to_string()
}

fn default_photon_bounces() -> Whole {
    limits::DEFAULT_PHOTON_BOUNCES.into()
}

impl FileCaustics {
    pub(super) fn validate(&self, path: &FieldPath) -> Check<CausticSettings> {
        let photons = placed(
            &path.key("photons"),
            limits::check_count(self.photons, limits::MAX_PHOTONS),
        )?;
        let filter = match self.filter.as_str() {
            "flat" => PhotonFilter::Flat,
            "cone" => PhotonFilter::Cone,
            "epanechnikov" => PhotonFilter::Epanechnikov,
            other => {
                return fail(
                    &path.key("filter"),
                    format!("must be one of {:?}, got {other:?}", PhotonFilter::NAMES),
                );
            }
        };
        let bounces = placed(
            &path.key("bounces"),
            limits::check_count(self.bounces, limits::MAX_PHOTON_BOUNCES),
        )?;
        Ok(CausticSettings {
            photons,
            radius: positive(&path.key("radius"), self.radius, limits::MAX_COORDINATE)?,
            filter,
            bounces,
            seed: self.seed,
        })
    }
}

/// The `[conventions]` table: a preset, then any switch set on its own (see
/// [`Conventions::set`]).
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct FileConventions {
    preset: Option<String>,
    sample_position: Option<String>,
    ray_origin: Option<String>,
    near: Option<f64>,
    far: Option<f64>,
    shadow_filter: Option<String>,
    transmission: Option<String>,
    refracting: Option<String>,
    total_internal_reflection: Option<String>,
    local_weight: Option<String>,
    default_highlight: Option<String>,
}

impl FileConventions {
    pub(super) fn validate(&self, path: &FieldPath) -> Check<Conventions> {
        let mut c = match &self.preset {
            Some(name) => Conventions::preset(name).or_else(|m| fail(&path.key("preset"), m))?,
            None => Conventions::CHAPTER,
        };
        let number = |x: &Option<f64>| {
            x.map(|x| {
                if x.is_infinite() && x > 0.0 {
                    "inf".to_string()
                } else {
                    x.to_string()
                }
            })
        };
        let switches = [
            ("sample_position", self.sample_position.clone()),
            ("ray_origin", self.ray_origin.clone()),
            ("near", number(&self.near)),
            ("far", number(&self.far)),
            ("shadow_filter", self.shadow_filter.clone()),
            ("transmission", self.transmission.clone()),
            ("refracting", self.refracting.clone()),
            ("total_internal_reflection", self.total_internal_reflection.clone()),
            ("local_weight", self.local_weight.clone()),
            ("default_highlight", self.default_highlight.clone()),
        ];
        for (key, value) in switches {
            if let Some(value) = value {
                c.set(key, &value).or_else(|m| fail(&path.key(key), m))?;
            }
        }
        Ok(c)
    }
}
