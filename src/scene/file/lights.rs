//! The `[[lights]]` entries: [`FileLight`] and the table of each type, their serde defaults
//! (SIMRenderer's for the aperture lights), attenuation, and the checks that make a
//! [`Light`].

use super::check::{
    Check, Whole, Xyz, color, direction, fail, in_range, one, placed, plus_z, positive, spanning_edges, vec3,
};
use crate::area_light::{AreaLight, AreaShape, PointMode};
use crate::interference::{Aperture, ApertureLight, Invalid, Mask, Planar};
use crate::light::{Attenuation, Light, PointLight, SpotLight};
use crate::limits;
use crate::placement::Placement;
use crate::scene::locate::FieldPath;
use serde::Deserialize;
use std::path::Path;

/// The values of `type` in `[[lights]]`, in the order of [`FileLight`]'s variants.
pub(super) const LIGHT_TYPES: &[&str] = &[
    "ambient",
    "directional",
    "point",
    "spot",
    "area",
    "linear_aperture",
    "rectangular_aperture",
    "elliptical_aperture",
    "aperture_mask",
];

/// One `[[lights]]` entry, tagged by its `type` (lifted to an outer key by `tag::lift`, so that
/// errors keep their positions).
#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum FileLight {
    Ambient(FileAmbientLight),
    Directional(FileDirectionalLight),
    Point(FilePointLight),
    Spot(FileSpotLight),
    Area(FileAreaLight),
    LinearAperture(FileLinearAperture),
    RectangularAperture(FilePlanarAperture),
    EllipticalAperture(FilePlanarAperture),
    ApertureMask(FilePlanarAperture),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileAmbientLight {
    #[serde(default = "one")]
    color: Xyz,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileDirectionalLight {
    direction: Xyz,
    #[serde(default = "one")]
    color: Xyz,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FilePointLight {
    position: Xyz,
    #[serde(default = "one")]
    color: Xyz,
    #[serde(default)]
    attenuation: FileAttenuation,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileSpotLight {
    position: Xyz,
    direction: Xyz,
    angle: f64,
    #[serde(default)]
    c_min: f64,
    #[serde(default = "one_f")]
    c_max: f64,
    #[serde(default = "one")]
    color: Xyz,
    #[serde(default)]
    attenuation: FileAttenuation,
}

/// N point lights on a sphere (`center`, `radius`), a tube (`start`, `end`) or a window
/// (`center`, `edge1`, `edge2`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileAreaLight {
    shape: String,
    center: Option<Xyz>,
    radius: Option<f64>,
    start: Option<Xyz>,
    end: Option<Xyz>,
    edge1: Option<Xyz>,
    edge2: Option<Xyz>,
    points: Whole,
    #[serde(default = "chapter")]
    placement: String,
    #[serde(default = "fixed")]
    mode: String,
    #[serde(default = "one")]
    color: Xyz,
    #[serde(default)]
    attenuation: FileAttenuation,
}

/// SIMRenderer's slit (`linear_aperture_light`): oscillators from `start` to `end`, with
/// SIMRenderer's defaults (`crate::interference`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileLinearAperture {
    #[serde(default)]
    start: Xyz,
    #[serde(default = "slit_end")]
    end: Xyz,
    #[serde(default = "green_nm")]
    wavelength: f64,
    #[serde(default = "two")]
    oscillators: Whole,
    #[serde(default = "ten")]
    period_iteration: Whole,
    #[serde(default = "one_f")]
    amplification: f64,
    #[serde(default)]
    attenuation: FileAttenuation,
}

/// SIMRenderer's planar apertures (rectangle, ellipse, mask), with its defaults; `mask`
/// only for `aperture_mask`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FilePlanarAperture {
    #[serde(default)]
    center: Xyz,
    #[serde(default = "plus_z")]
    front: Xyz,
    #[serde(default = "plus_y")]
    up: Xyz,
    #[serde(default = "millimetre")]
    width: f64,
    #[serde(default = "millimetre")]
    height: f64,
    mask: Option<String>,
    #[serde(default = "green_nm")]
    wavelength: f64,
    #[serde(default = "two")]
    oscillators: Whole,
    #[serde(default = "ten")]
    period_iteration: Whole,
    #[serde(default = "one_f")]
    amplification: f64,
    #[serde(default)]
    attenuation: FileAttenuation,
}

/// A light's `attenuation` table, `A = 1 / (constant + linear d + quadratic d^2)`: constant 1
/// and the others 0 unless given.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
struct FileAttenuation {
    constant: Option<f64>,
    linear: f64,
    quadratic: f64,
}

fn slit_end() -> Xyz {
    Xyz([0.0, 1e-4, 0.0])
}

fn green_nm() -> f64 {
    550.0
}

fn two() -> Whole {
    2
}

fn ten() -> Whole {
    10
}

fn plus_y() -> Xyz {
    Xyz([0.0, 1.0, 0.0])
}

fn millimetre() -> f64 {
    1e-3
}

fn chapter() -> String {
    "chapter".to_string()
}

fn fixed() -> String {
    "fixed".to_string()
}

fn one_f() -> f64 {
    1.0
}

impl FileAttenuation {
    fn validate(&self, path: &FieldPath) -> Check<Attenuation> {
        let a = Attenuation {
            constant: in_range(&path.key("constant"), self.constant.unwrap_or(1.0), 0.0, 1e12)?,
            linear: in_range(&path.key("linear"), self.linear, 0.0, 1e12)?,
            quadratic: in_range(&path.key("quadratic"), self.quadratic, 0.0, 1e12)?,
        };
        if a.constant + a.linear + a.quadratic == 0.0 {
            return fail(
                path,
                "constant, linear and quadratic cannot all be 0 (A would be infinite)",
            );
        }
        Ok(a)
    }
}

impl FileLight {
    /// The light; a mask image is read relative to `dir`, the scene file's folder.
    pub(super) fn validate(self, path: &FieldPath, dir: &Path) -> Check<Light> {
        let light_color = |c: Xyz| color(&path.key("color"), c, limits::MAX_LIGHT);
        Ok(match self {
            FileLight::Ambient(FileAmbientLight { color }) => Light::Ambient {
                color: light_color(color)?,
            },
            FileLight::Directional(FileDirectionalLight { direction: d, color }) => Light::Directional {
                direction: direction(&path.key("direction"), d)?,
                color: light_color(color)?,
            },
            FileLight::Point(FilePointLight {
                position,
                color,
                attenuation,
            }) => Light::Point(PointLight {
                position: vec3(&path.key("position"), position)?,
                color: light_color(color)?,
                attenuation: attenuation.validate(&path.key("attenuation"))?,
            }),
            FileLight::Spot(FileSpotLight {
                position,
                direction: d,
                angle,
                c_min,
                c_max,
                color,
                attenuation,
            }) => Light::Spot(SpotLight::new(
                vec3(&path.key("position"), position)?,
                direction(&path.key("direction"), d)?,
                in_range(&path.key("angle"), angle, 0.0, 180.0)?,
                in_range(&path.key("c_min"), c_min, 0.0, 1.0)?,
                in_range(&path.key("c_max"), c_max, 0.0, 1.0)?,
                light_color(color)?,
                attenuation.validate(&path.key("attenuation"))?,
            )),
            FileLight::Area(FileAreaLight {
                shape,
                center,
                radius,
                start,
                end,
                edge1,
                edge2,
                points,
                placement,
                mode,
                color,
                attenuation,
            }) => {
                // Which geometry fields each shape takes; any other one is an error.
                let given = [
                    ("center", center.is_some()),
                    ("radius", radius.is_some()),
                    ("start", start.is_some()),
                    ("end", end.is_some()),
                    ("edge1", edge1.is_some()),
                    ("edge2", edge2.is_some()),
                ];
                let wanted: &[&str] = match shape.as_str() {
                    "sphere" => &["center", "radius"],
                    "tube" => &["start", "end"],
                    "window" => &["center", "edge1", "edge2"],
                    other => {
                        return fail(
                            &path.key("shape"),
                            format!("must be \"sphere\", \"tube\" or \"window\", got {other:?}"),
                        );
                    }
                };
                for (field, present) in given {
                    if present != wanted.contains(&field) {
                        let why = if present {
                            "does not apply to"
                        } else {
                            "is required for"
                        };
                        return fail(&path.key(field), format!("{field} {why} a {shape} light"));
                    }
                }
                let at = |key: &str, v: Option<Xyz>| vec3(&path.key(key), v.unwrap_or_default());
                let area_shape = match shape.as_str() {
                    "sphere" => AreaShape::Sphere {
                        center: at("center", center)?,
                        radius: in_range(
                            &path.key("radius"),
                            radius.unwrap_or_default(),
                            0.0,
                            limits::MAX_COORDINATE,
                        )?,
                    },
                    "tube" => {
                        let (start, end) = (at("start", start)?, at("end", end)?);
                        // Exact: two different finite points always differ by a non-zero vector.
                        if start == end {
                            return fail(
                                &path.key("end"),
                                format!(
                                    "must differ from start {:?} (a tube of zero length is a point: use a sphere of radius 0)",
                                    start.to_array()
                                ),
                            );
                        }
                        AreaShape::Tube { start, end }
                    }
                    _ => {
                        let (edge1, edge2) =
                            spanning_edges(path, edge1.unwrap_or_default(), edge2.unwrap_or_default())?;
                        AreaShape::Window {
                            center: at("center", center)?,
                            edge1,
                            edge2,
                        }
                    }
                };
                let points = placed(
                    &path.key("points"),
                    limits::check_count(points, limits::MAX_LIGHT_POINTS),
                )?;
                let Some(placement) = Placement::parse(&placement) else {
                    return fail(
                        &path.key("placement"),
                        format!("must be \"chapter\", \"uniform\", \"stratified\" or \"fibonacci\", got {placement:?}"),
                    );
                };
                let mode = match mode.as_str() {
                    "fixed" => PointMode::Fixed,
                    "per_sample" => PointMode::PerSample,
                    other => {
                        return fail(
                            &path.key("mode"),
                            format!("must be \"fixed\" or \"per_sample\", got {other:?}"),
                        );
                    }
                };
                Light::Area(AreaLight {
                    shape: area_shape,
                    count: points,
                    placement,
                    mode,
                    color: light_color(color)?,
                    attenuation: attenuation.validate(&path.key("attenuation"))?,
                })
            }
            FileLight::LinearAperture(f) => {
                let (start, end) = (vec3(&path.key("start"), f.start)?, vec3(&path.key("end"), f.end)?);
                if start == end {
                    return fail(
                        &path.key("end"),
                        format!("must differ from start {:?} (a slit has two ends)", start.to_array()),
                    );
                }
                let wave = Wave {
                    wavelength: f.wavelength,
                    oscillators: f.oscillators,
                    period_iteration: f.period_iteration,
                    amplification: f.amplification,
                    attenuation: f.attenuation,
                };
                wave.light(path, Aperture::Linear { start, end })?
            }
            FileLight::RectangularAperture(f) => f.light(path, dir, "rectangular_aperture")?,
            FileLight::EllipticalAperture(f) => f.light(path, dir, "elliptical_aperture")?,
            FileLight::ApertureMask(f) => f.light(path, dir, "aperture_mask")?,
        })
    }
}

/// The wave of an aperture light, as its table gives it.
struct Wave {
    wavelength: f64,
    oscillators: Whole,
    period_iteration: Whole,
    amplification: f64,
    attenuation: FileAttenuation,
}

impl Wave {
    /// The light over `aperture`, each value checked and an error placed on its field.
    fn light(self, path: &FieldPath, aperture: Aperture) -> Check<Light> {
        let amplification = in_range(&path.key("amplification"), self.amplification, 0.0, limits::MAX_LIGHT)?;
        let attenuation = self.attenuation.validate(&path.key("attenuation"))?;
        match ApertureLight::new(
            aperture,
            self.wavelength,
            self.oscillators,
            self.period_iteration,
            amplification,
            attenuation,
        ) {
            Ok(light) => Ok(Light::Aperture(light)),
            Err(Invalid::Wavelength(m)) => fail(&path.key("wavelength"), m),
            Err(Invalid::Oscillators(m)) => fail(&path.key("oscillators"), m),
            Err(Invalid::PeriodIteration(m)) => fail(&path.key("period_iteration"), m),
            Err(Invalid::Up(m)) => fail(&path.key("up"), m),
        }
    }
}

impl FilePlanarAperture {
    /// The light of type `kind`; its mask image read relative to `dir`.
    fn light(self, path: &FieldPath, dir: &Path, kind: &str) -> Check<Light> {
        let size = |key: &str, x: f64| positive(&path.key(key), x, limits::MAX_COORDINATE);
        let planar = Planar {
            center: vec3(&path.key("center"), self.center)?,
            front: direction(&path.key("front"), self.front)?,
            up: direction(&path.key("up"), self.up)?,
            width: size("width", self.width)?,
            height: size("height", self.height)?,
        };
        let aperture = match (kind, self.mask) {
            ("rectangular_aperture", None) => Aperture::Rectangular(planar),
            ("elliptical_aperture", None) => Aperture::Elliptical(planar),
            (_, None) => Aperture::Mask { planar, mask: None },
            ("aperture_mask", Some(file)) => {
                let mask = if file == "none" {
                    None
                } else {
                    Some(Mask::read(&dir.join(&file), &file).or_else(|m| fail(&path.key("mask"), m))?)
                };
                Aperture::Mask { planar, mask }
            }
            (_, Some(_)) => {
                return fail(
                    &path.key("mask"),
                    format!("mask applies to an aperture_mask light only, not to a {kind} light"),
                );
            }
        };
        let wave = Wave {
            wavelength: self.wavelength,
            oscillators: self.oscillators,
            period_iteration: self.period_iteration,
            amplification: self.amplification,
            attenuation: self.attenuation,
        };
        wave.light(path, aperture)
    }
}
