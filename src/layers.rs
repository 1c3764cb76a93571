//! Per-term layers (`lumiere render --layers`): for each pixel, the terms `lumiere probe`
//! prints for its camera rays, averaged over the pixel's samples as the pixel's radiance is,
//! so that a student can compare their image one term at a time.
//!
//! What each layer holds, per pixel (the mean over its samples; a sample whose camera ray
//! meets nothing adds 0 to every term but `background`):
//! - `ambient`: the camera hit's ambient term `L_a k_a S`, times the local weight of the
//!   conventions (1 in the chapter's);
//! - `diffuse`, `specular`: the sums over the lights (an area light's points each) of the
//!   camera hit's Lambert and Phong / Blinn shares `A C_theta L filter k_d S N.L` and
//!   `A C_theta L filter k_s [m S + (1 - m)] spec`, times the local weight;
//! - `reflected`: `k_r` (plus `k_t` on total internal reflection) times the radiance of the
//!   camera hit's reflected ray (0 where adaptive depth control does not trace it);
//! - `transmitted`: the refracted-ray weight (`k_t`, or `k_t S` entering by SIMRenderer's
//!   convention) times the radiance of the refracted ray;
//! - `caustic`: with caustics, the camera hit's caustic share `E k_d S` of the photons
//!   that land near it, times the local weight;
//! - `background`: the background colour where the camera ray meets nothing;
//! - `filtered`: the part of `diffuse + specular` that arrives through a colour filter (a
//!   shadow ray crossing transparent objects whose filter is neither 0 nor 1);
//! - `shadow_filter` of each light (by its index in the scene): the filter of the camera
//!   hit's shadow ray towards it (1 unshadowed, 0 blocked, the product of the crossed
//!   objects' colours), averaged over the light's points, 0 where no light of it arrives
//!   (surface facing away, outside a spot's cone, background);
//! - `object`: the index of the object the first sample's camera ray hits, -1 for none;
//! - `normal`: the mean outward unit normal at the camera hits (0 for none);
//! - `depth`: the mean distance `t` along the camera rays to their hits, infinite when a
//!   sample sees the background.
//!
//! An aperture light's share counts in `diffuse` (it has no specular term), and so does the
//! diffuse colour `k_d S` that the `no_light` model shows in place of every local term.
//!
//! So `ambient + diffuse + specular + caustic + reflected + transmitted + background` is the pixel's
//! radiance (to rounding: the tracer sums in another order). The terms are gathered by a
//! [`Recorder`] on the renderer's own tracer ([`render_pixel_recorded`]): no formula is
//! evaluated here but the transmission and local weights of the camera hit, through their
//! one definition in [`crate::shading`].

use crate::caustics::Estimate;
use crate::film::{Film, quantize, write_atomic};
use crate::light::Light;
use crate::math::Ray;
use crate::render::render_pixel_recorded;
use crate::shading::{local_weight, transmission_weight};
use crate::trace::{LightShare, RayKind, Recorder, Tracer};
use crate::world::World;
use glam::DVec3;
use rayon::prelude::*;
use std::path::Path;

/// One pixel's layers (see the module's documentation).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PixelLayers {
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
    pub caustic: DVec3,
    pub reflected: DVec3,
    pub transmitted: DVec3,
    pub background: DVec3,
    /// The parts of `diffuse` and `specular` that arrive through colour filters (the
    /// `filtered` layer is their sum).
    pub filtered_diffuse: DVec3,
    pub filtered_specular: DVec3,
    /// Per light of the scene, by index (ambient lights hold 0).
    pub shadow_filters: Vec<DVec3>,
    pub object: i64,
    pub normal: DVec3,
    pub depth: f64,
    /// The pixel's radiance, as the renderer computes it.
    pub radiance: DVec3,
}

impl PixelLayers {
    /// The vector layers averaged over the pixel's samples: the colour terms and the normal.
    fn averaged_mut(&mut self) -> [&mut DVec3; 10] {
        [
            &mut self.ambient,
            &mut self.diffuse,
            &mut self.specular,
            &mut self.caustic,
            &mut self.reflected,
            &mut self.transmitted,
            &mut self.background,
            &mut self.filtered_diffuse,
            &mut self.filtered_specular,
            &mut self.normal,
        ]
    }

    /// `ambient + diffuse + specular + caustic + reflected + transmitted + background`.
    pub fn sum(&self) -> DVec3 {
        self.ambient + self.diffuse + self.specular + self.caustic + self.reflected + self.transmitted + self.background
    }
}

/// The layers of a whole image, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Layers {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<PixelLayers>,
}

/// Gathers the camera rays' terms of one sample from the tracer's events.
struct LayerRecorder<'w, 's> {
    world: &'w World<'s>,
    /// The kind and level of each open ray.
    open: Vec<(RayKind, u32, f64)>,
    /// The camera hit: object and whether the ray enters it.
    hit: Option<(usize, bool)>,
    sample: PixelLayers,
    /// Per light: the sum of its points' filters and their number.
    filters: Vec<(DVec3, u32)>,
    normal: DVec3,
    t: f64,
    /// The sums of the samples' layers so far, and their number.
    total: PixelLayers,
    samples: u32,
}

impl<'w, 's> LayerRecorder<'w, 's> {
    fn new(world: &'w World<'s>) -> Self {
        let lights = world.scene.lights.len();
        LayerRecorder {
            world,
            open: Vec::new(),
            hit: None,
            sample: PixelLayers::default(),
            filters: vec![(DVec3::ZERO, 0); lights],
            normal: DVec3::ZERO,
            t: f64::INFINITY,
            total: PixelLayers {
                shadow_filters: vec![DVec3::ZERO; lights],
                object: -1,
                ..PixelLayers::default()
            },
            samples: 0,
        }
    }

    /// Whether the innermost open ray is the camera ray.
    fn at_camera(&self) -> bool {
        self.open.last().is_some_and(|&(_, level, _)| level == 1)
    }

    fn start(&mut self) {
        self.open.clear();
        self.hit = None;
        let lights = self.filters.len();
        self.sample = PixelLayers {
            shadow_filters: vec![DVec3::ZERO; lights],
            object: -1,
            ..PixelLayers::default()
        };
        self.filters.iter_mut().for_each(|f| *f = (DVec3::ZERO, 0));
        self.normal = DVec3::ZERO;
        self.t = f64::INFINITY;
    }

    /// The local weight of the camera hit (1 in the chapter's conventions).
    fn local_weight(&self) -> f64 {
        let Some((object, _)) = self.hit else {
            return 1.0;
        };
        let mat = self.world.material_of(object);
        local_weight(self.world.scene.settings.conventions.local_weight, mat.kr, mat.kt)
    }
}

impl Recorder for LayerRecorder<'_, '_> {
    fn sample(&mut self, _k: u32, _px: f64, _py: f64) {
        self.start();
    }

    fn ray(&mut self, kind: RayKind, _ray: &Ray, level: u32, weight: f64) {
        self.open.push((kind, level, weight));
    }

    fn hit(&mut self, object: usize, t: f64, _point: DVec3, normal: DVec3, entering: bool) {
        if self.at_camera() {
            self.hit = Some((object, entering));
            self.sample.object = object as i64;
            self.normal = normal;
            self.t = t;
        }
    }

    fn ambient(&mut self, color: DVec3) {
        if self.at_camera() {
            self.sample.ambient = color;
        }
    }

    fn no_light(&mut self, color: DVec3) {
        if self.at_camera() {
            self.sample.diffuse += color;
        }
    }

    fn light(&mut self, share: &LightShare) {
        if !self.at_camera() {
            return;
        }
        self.sample.diffuse += share.diffuse;
        self.sample.specular += share.specular;
        let f = share.filter;
        if f != DVec3::ZERO && f != DVec3::ONE {
            self.sample.filtered_diffuse += share.diffuse;
            self.sample.filtered_specular += share.specular;
        }
        let entry = &mut self.filters[share.light];
        *entry = (entry.0 + f, entry.1 + 1);
    }

    fn caustic(&mut self, term: DVec3, _estimate: &Estimate) {
        if self.at_camera() {
            self.sample.caustic = term;
        }
    }

    fn unlit(&mut self, light: usize, _n_dot_l: Option<f64>) {
        if self.at_camera() {
            self.filters[light].1 += 1;
        }
    }

    fn below_horizon(&mut self, light: usize) {
        if self.at_camera() {
            self.filters[light].1 += 1;
        }
    }

    fn done(&mut self, color: DVec3) {
        let Some((kind, level, weight)) = self.open.pop() else {
            return;
        };
        match (level, kind) {
            (1, _) if self.hit.is_none() => self.sample.background = color,
            (2, RayKind::Reflection) => self.sample.reflected = weight * color,
            (2, RayKind::Refraction) => {
                let (object, entering) = self.hit.expect("a refracted ray leaves a hit");
                let mat = self.world.material_of(object);
                let rule = self.world.scene.settings.conventions.transmission;
                self.sample.transmitted = transmission_weight(rule, mat.kt, mat.color, entering) * color;
            }
            _ => {}
        }
    }

    fn sample_done(&mut self, radiance: DVec3) {
        let w = self.local_weight();
        let s = &mut self.sample;
        s.ambient *= w;
        s.diffuse *= w;
        s.specular *= w;
        s.caustic *= w;
        s.filtered_diffuse *= w;
        s.filtered_specular *= w;
        s.radiance = radiance;
        s.normal = self.normal;
        s.depth = self.t;
        for (filter, &(sum, count)) in s.shadow_filters.iter_mut().zip(&self.filters) {
            *filter = if count == 0 { DVec3::ZERO } else { sum / count as f64 };
        }
        let t = &mut self.total;
        for (sum, value) in t.averaged_mut().into_iter().zip(s.averaged_mut()) {
            *sum += *value;
        }
        t.depth += s.depth;
        for (a, b) in t.shadow_filters.iter_mut().zip(&s.shadow_filters) {
            *a += *b;
        }
        if self.samples == 0 {
            t.object = s.object;
        }
        self.samples += 1;
    }
}

/// The layers of pixel `(x, y)`, traced by `tracer` (the renderer's own).
pub fn pixel_layers(tracer: &mut Tracer, x: u32, y: u32) -> PixelLayers {
    let world = tracer.world;
    let mut rec = LayerRecorder::new(world);
    let radiance = render_pixel_recorded(tracer, x, y, &mut rec);
    let n = world.scene.settings.samples_per_pixel as f64;
    let mut t = rec.total;
    for v in t.averaged_mut() {
        *v /= n;
    }
    t.shadow_filters.iter_mut().for_each(|f| *f /= n);
    t.depth /= n;
    t.radiance = radiance;
    t
}

/// The layers of the whole image, rows in parallel on the current rayon pool (the values do
/// not depend on the thread count: each pixel is traced alone).
pub fn render_layers(world: &World) -> Layers {
    let s = &world.scene.settings;
    let (w, h) = (s.width, s.height);
    let pixels = (0..h)
        .into_par_iter()
        .flat_map_iter(|y| {
            let mut tracer = Tracer::new(world);
            (0..w).map(move |x| pixel_layers(&mut tracer, x, y)).collect::<Vec<_>>()
        })
        .collect();
    Layers {
        width: w,
        height: h,
        pixels,
    }
}

/// One named layer's values: its name and 1 (grey) or 3 (RGB, XYZ) channels per pixel.
pub struct Plane {
    pub name: String,
    /// The channels' names, e.g. `["R", "G", "B"]`.
    pub channels: Vec<&'static str>,
    /// Channel-interleaved values, row-major.
    pub values: Vec<f64>,
}

impl Plane {
    /// The files of this plane in the folder form ([`Layers::write_folder`]):
    /// `<layer>.png`, and `<layer>.pfm` for a colour layer.
    pub fn file_names(&self) -> Vec<String> {
        let mut names = vec![format!("{}.png", self.name)];
        if self.channels == ["R", "G", "B"] {
            names.push(format!("{}.pfm", self.name));
        }
        names
    }
}

impl Layers {
    /// Every layer as a plane: the colour layers, then `shadow_filter_light<i>` for each
    /// non-ambient light `i`, `object`, `normal` and `depth`.
    pub fn planes(&self, lights: &[Light]) -> Vec<Plane> {
        let rgb = || vec!["R", "G", "B"];
        let colour = |name: &str, get: &dyn Fn(&PixelLayers) -> DVec3| Plane {
            name: name.to_string(),
            channels: rgb(),
            values: self.pixels.iter().flat_map(|p| get(p).to_array()).collect(),
        };
        let mut planes = vec![
            colour("ambient", &|p: &PixelLayers| p.ambient),
            colour("diffuse", &|p: &PixelLayers| p.diffuse),
            colour("specular", &|p: &PixelLayers| p.specular),
            colour("caustic", &|p: &PixelLayers| p.caustic),
            colour("reflected", &|p: &PixelLayers| p.reflected),
            colour("transmitted", &|p: &PixelLayers| p.transmitted),
            colour("background", &|p: &PixelLayers| p.background),
            colour("filtered", &|p: &PixelLayers| p.filtered_diffuse + p.filtered_specular),
            colour("radiance", &|p: &PixelLayers| p.radiance),
        ];
        for (i, light) in lights.iter().enumerate() {
            if !matches!(light, Light::Ambient { .. }) {
                planes.push(colour(&format!("shadow_filter_light{i}"), &|p: &PixelLayers| {
                    p.shadow_filters[i]
                }));
            }
        }
        planes.push(Plane {
            name: "object".into(),
            channels: vec!["Y"],
            values: self.pixels.iter().map(|p| p.object as f64).collect(),
        });
        planes.push(Plane {
            name: "normal".into(),
            channels: vec!["X", "Y", "Z"],
            values: self.pixels.iter().flat_map(|p| p.normal.to_array()).collect(),
        });
        planes.push(Plane {
            name: "depth".into(),
            channels: vec!["Z"],
            values: self.pixels.iter().map(|p| p.depth).collect(),
        });
        planes
    }

    /// The names of the files [`Layers::write_folder`] writes for a scene of these lights.
    pub fn folder_files(lights: &[Light]) -> Vec<String> {
        let none = Layers {
            width: 0,
            height: 0,
            pixels: Vec::new(),
        };
        none.planes(lights).iter().flat_map(Plane::file_names).collect()
    }

    /// A multi-channel OpenEXR file (32-bit float) of every plane: channel
    /// `<layer>.<channel>`, e.g. `diffuse.R`, `shadow_filter_light1.G`, `normal.X`,
    /// `depth.Z`.
    pub fn encode_exr(&self, lights: &[Light]) -> Result<Vec<u8>, String> {
        use exr::prelude::*;
        let mut list = Vec::new();
        for plane in self.planes(lights) {
            let n = plane.channels.len();
            for (c, channel) in plane.channels.iter().enumerate() {
                let values: Vec<f32> = plane.values.iter().skip(c).step_by(n).map(|&v| v as f32).collect();
                list.push(AnyChannel::new(
                    format!("{}.{channel}", plane.name).as_str(),
                    FlatSamples::F32(values),
                ));
            }
        }
        let size = (self.width as usize, self.height as usize);
        let layer = Layer::new(
            size,
            LayerAttributes::default(),
            Encoding::SMALL_LOSSLESS,
            AnyChannels::sort(list.into()),
        );
        let mut out = std::io::Cursor::new(Vec::new());
        Image::from_layer(layer)
            .write()
            .to_buffered(&mut out)
            .map_err(|e| e.to_string())?;
        Ok(out.into_inner())
    }

    /// The folder form: for each plane, `<layer>.png` (8-bit; colours clamped and quantised
    /// as the film is, normals as `(N + 1) / 2`, the object as level `index + 1` (0 for
    /// none), depth as `255 t / t_max` with `t_max` the largest finite depth and the
    /// background white), and for the colour layers `<layer>.pfm` (the float values).
    /// Each file is written whole or not at all.
    pub fn write_folder(&self, dir: &Path, lights: &[Light]) -> std::io::Result<Vec<std::path::PathBuf>> {
        let mut written = Vec::new();
        let max_depth = self
            .pixels
            .iter()
            .map(|p| p.depth)
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max);
        for plane in self.planes(lights) {
            let rgb: Vec<u8> = match plane.name.as_str() {
                "object" => plane
                    .values
                    .iter()
                    .flat_map(|&id| [((id + 1.0) as i64).clamp(0, 255) as u8; 3])
                    .collect(),
                "normal" => plane.values.iter().map(|&c| quantize((c + 1.0) * 0.5)).collect(),
                "depth" => plane
                    .values
                    .iter()
                    .flat_map(|&d| {
                        let v = if d.is_finite() && max_depth > 0.0 {
                            d / max_depth
                        } else {
                            1.0
                        };
                        [quantize(v); 3]
                    })
                    .collect(),
                _ => plane.values.iter().map(|&c| quantize(c)).collect(),
            };
            let png = crate::film::encode_png(self.width, self.height, &rgb).map_err(std::io::Error::other)?;
            let names = plane.file_names();
            let path = dir.join(&names[0]);
            write_atomic(&path, &png)?;
            written.push(path);
            if let Some(pfm) = names.get(1) {
                let film = Film {
                    width: self.width,
                    height: self.height,
                    pixels: plane.values.chunks(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect(),
                    normalization: crate::film::Normalization::ClampChannel,
                };
                let path = dir.join(pfm);
                write_atomic(&path, &crate::output::encode_pfm(&film))?;
                written.push(path);
            }
        }
        Ok(written)
    }
}
