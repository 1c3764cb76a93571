//! The `camera`, `viewport` and `raytracer` blocks: what each holds once read (the settings
//! the scene is built with); `task`, `space` and `image_file_name` are read and checked but
//! change nothing (lumiere picks its threads and intersection core, and `-o` names the image).

use super::keywords::{
    CAMERA, COLOR_NORMALIZATIONS, PIXEL_COORDINATES, RAYTRACER, REFLEXION_ALGORITHMS, SPACES, VIEWPORT, shading_of,
};
use super::values::{direction, far, int_in, number_in, point, positive, unit};
use super::{At, Reader, at};
use crate::conventions::SamplePosition;
use crate::film::Normalization;
use crate::limits;
use crate::scene::simrenderer::lex::{self, Line};
use crate::scene::{CameraSpec, SceneError, ShadingModel};
use glam::DVec3;
use std::collections::BTreeMap;

pub(super) struct CameraBlock {
    pub(super) spec: CameraSpec,
    pub(super) near: Option<f64>,
    pub(super) far: Option<f64>,
}

impl Default for CameraBlock {
    fn default() -> Self {
        CameraBlock {
            spec: CameraSpec {
                position: DVec3::ZERO,
                look_at: DVec3::Z,
                up: DVec3::Y,
                vfov_deg: 60.0,
            },
            near: None,
            far: None,
        }
    }
}

pub(super) struct ViewportBlock {
    pub(super) width: u32,
    pub(super) height: u32,
    at: At,
}

#[derive(Default)]
pub(super) struct RaytracerBlock {
    pub(super) sampling: Option<(u32, At)>,
    pub(super) depth: Option<u32>,
    pub(super) shading: Option<ShadingModel>,
    pub(super) pixel_coordinate: Option<SamplePosition>,
    pub(super) color_normalization: Normalization,
}

impl<'a> Reader<'a> {
    pub(super) fn camera(&mut self, open: &Line<'a>) -> Result<Option<CameraBlock>, SceneError> {
        let block = open.keyword.clone();
        let mut c = CameraBlock::default();
        let mut lines: BTreeMap<&str, At> = BTreeMap::new();
        while let Some((k, l)) = self.next_key(&block, CAMERA, None)? {
            let read = match k {
                "position" | "look_at" => self.value(&block, &l, point(&l))?.map(|p| {
                    if k == "position" {
                        c.spec.position = p;
                    } else {
                        c.spec.look_at = p;
                    }
                }),
                "up" => self.value(&block, &l, direction(&l))?.map(|d| c.spec.up = unit(d)),
                "angle" => self
                    .value(&block, &l, number_in(&l, 10.0, 170.0))?
                    .map(|a| c.spec.vfov_deg = a),
                "near_clipping_plane" => self
                    .value(&block, &l, positive(&l, limits::MAX_COORDINATE))?
                    .map(|x| c.near = Some(x)),
                _ => self.value(&block, &l, far(&l))?.map(|x| c.far = Some(x)),
            };
            if read.is_some() {
                lines.insert(k, at(&l, &block));
            }
        }
        let place = |k: &str| lines.get(k).cloned().unwrap_or_else(|| at(open, "scene"));
        let s = &c.spec;
        let forward = s.look_at - s.position;
        let problem = if forward.length() <= 1e-12 {
            Some(("look_at", "must differ from the camera position".to_string()))
        } else if forward.normalize().cross(s.up).length() < 1e-9 {
            Some((
                "up",
                "must not be parallel to the viewing direction (look_at - position)".to_string(),
            ))
        } else {
            let (near, far) = (c.near.unwrap_or(1.0), c.far.unwrap_or(100.0));
            (far < near).then(|| {
                (
                    if c.far.is_some() {
                        "far_clipping_plane"
                    } else {
                        "near_clipping_plane"
                    },
                    format!("far_clipping_plane ({far}) must be at least near_clipping_plane ({near})"),
                )
            })
        };
        if let Some((k, message)) = problem {
            self.problem(&place(k), message, "the camera is dropped")?;
            return Ok(None);
        }
        Ok(Some(c))
    }

    pub(super) fn viewport(&mut self, open: &Line<'a>) -> Result<Option<ViewportBlock>, SceneError> {
        let block = open.keyword.clone();
        let mut v = ViewportBlock {
            width: 500,
            height: 500,
            at: at(open, "scene"),
        };
        while let Some((k, l)) = self.next_key(&block, VIEWPORT, None)? {
            match k {
                "width" | "height" => {
                    let read = int_in(&l, 1, limits::MAX_DIMENSION as i32);
                    if let Some(n) = self.value(&block, &l, read)? {
                        if k == "width" {
                            v.width = n as u32;
                        } else {
                            v.height = n as u32;
                        }
                        v.at = at(&l, &block);
                    }
                }
                // The image is written where the command line says.
                _ => {
                    self.value(&block, &l, lex::name(l.value, l.value_column))?;
                }
            }
        }
        if let Err(m) = limits::check_pixel_count(v.width, v.height) {
            self.problem(&v.at.clone(), m, "the viewport is dropped")?;
            return Ok(None);
        }
        Ok(Some(v))
    }

    pub(super) fn raytracer(&mut self, open: &Line<'a>) -> Result<RaytracerBlock, SceneError> {
        let block = open.keyword.clone();
        let mut r = RaytracerBlock::default();
        while let Some((k, l)) = self.next_key(&block, RAYTRACER, None)? {
            match k {
                // lumiere picks its own threads and intersection structure.
                "task" => {
                    self.value(&block, &l, int_in(&l, 1, i32::MAX))?;
                }
                "space" => {
                    self.value(&block, &l, lex::enumeration(l.value, l.value_column, &SPACES))?;
                }
                "sampling" => {
                    let most = limits::MAX_SAMPLES as i32;
                    if let Some(n) = self.value(&block, &l, int_in(&l, 1, most))? {
                        r.sampling = Some((n as u32, at(&l, &block)));
                    }
                }
                "recursive_level" => {
                    if let Some(n) = self.value(&block, &l, int_in(&l, 1, limits::MAX_DEPTH as i32))? {
                        r.depth = Some(n as u32);
                    }
                }
                "reflexion_algorithm" => {
                    let read = lex::enumeration(l.value, l.value_column, &REFLEXION_ALGORITHMS);
                    if let Some(i) = self.value(&block, &l, read)? {
                        r.shading = shading_of(i);
                    }
                }
                "pixel_coordinate" => {
                    let read = lex::enumeration(l.value, l.value_column, &PIXEL_COORDINATES);
                    if let Some(i) = self.value(&block, &l, read)? {
                        r.pixel_coordinate = Some(match i {
                            0 => SamplePosition::Corner,
                            1 => SamplePosition::TopRight,
                            2 => SamplePosition::BottomLeft,
                            3 => SamplePosition::BottomRight,
                            4 => SamplePosition::Center,
                            _ => SamplePosition::Jittered,
                        });
                    }
                }
                _ => {
                    let read = lex::enumeration(l.value, l.value_column, &COLOR_NORMALIZATIONS);
                    if let Some(i) = self.value(&block, &l, read)? {
                        r.color_normalization = if i == 1 {
                            Normalization::DivisionFactor
                        } else {
                            Normalization::ClampChannel
                        };
                    }
                }
            }
        }
        Ok(r)
    }
}
