//! `lumiere probe`: why is this pixel this colour? The whole ray tree of one pixel (every
//! ray, hit, light share, shadow ray, cutoff and total internal reflection, with the
//! radiance each ray returned) and the pixel's final colour before and after clamping and
//! quantisation.
//!
//! The numbers are the renderer's own: [`TreeRecorder`] is a [`Recorder`] driven through
//! [`crate::render::render_sample`] / [`crate::render::render_pixel_recorded`], the functions `render`
//! uses, so the probe never recomputes anything the tracer computed.

use crate::accel::AccelChoice;
use crate::caustics::Estimate;
use crate::film::{clamp_unit, rgb8};
use crate::light::Light;
use crate::math::Ray;
use crate::render::{render_pixel_recorded, render_sample};
use crate::scene::Scene;
use crate::shape::{NormalInterpolation, Shape};
use crate::trace::{LightShare, RayCounts, RayKind, Recorder, Tracer};
use crate::world::World;
use glam::DVec3;
use serde::Serialize;
use std::fmt::Write as _;

/// The probe of one pixel (or one sample of it).
#[derive(Clone, Debug, Serialize)]
pub struct PixelProbe {
    pub pixel: [u32; 2],
    /// Caustic photons stored, out of those emitted, when the scene has caustics.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub photons: Option<PhotonCount>,
    pub width: u32,
    pub height: u32,
    pub samples_per_pixel: u32,
    pub seed: u64,
    pub depth: u32,
    pub adaptive_threshold: f64,
    /// The conventions in force: a preset's name, or the switches that differ from the
    /// chapter's ([`crate::conventions::Conventions::summary`]).
    pub conventions: String,
    /// The samples traced: all of them, or only the one asked for.
    pub samples: Vec<SampleTrace>,
    pub color: FinalColor,
    /// Rays traced for this probe, by kind.
    pub counts: RayCounts,
}

/// The caustic pass behind a probe.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct PhotonCount {
    pub emitted: u64,
    pub stored: usize,
}

/// One sample: its jittered image position, its camera ray's tree and its radiance.
#[derive(Clone, Debug, Serialize)]
pub struct SampleTrace {
    pub index: u32,
    /// Image position in pixels (continuous: pixel `x` spans `[x, x + 1)`).
    pub position: [f64; 2],
    pub ray: RayNode,
    /// The radiance entering the pixel mean (a non-finite one is replaced by black).
    pub radiance: [f64; 3],
}

/// The colour written to the image: radiance, clamped to [0, 1], then 8 bits.
#[derive(Clone, Debug, Serialize)]
pub struct FinalColor {
    /// `"mean"` of every sample (the pixel's value) or `"sample"` (one sample alone).
    pub of: &'static str,
    pub radiance: [f64; 3],
    /// Under `color_normalization = "division_factor"`, the radiance divided by its largest
    /// channel where that exceeds 1 (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub divided: Option<[f64; 3]>,
    pub clamped: [f64; 3],
    pub rgb8: [u8; 3],
}

/// A camera, reflected or refracted ray and everything that happened along it.
#[derive(Clone, Debug, Serialize)]
pub struct RayNode {
    /// `camera`, `reflection` or `refraction`.
    pub kind: &'static str,
    /// Recursion level, 1 for the camera ray.
    pub level: u32,
    /// Its weight in the pixel: the product of the `k_r` and `k_t` along the path.
    pub weight: f64,
    pub origin: [f64; 3],
    pub direction: [f64; 3],
    /// The closest hit; `None` when the ray leaves the scene (it returns the background).
    pub hit: Option<Hit>,
    /// Ambient term `k_a L_a S` at the hit, if the model has one.
    pub ambient: Option<[f64; 3]>,
    /// The diffuse colour `k_d S` the hit shows under the `no_light` model, in place of the
    /// ambient term and the lights' shares.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub diffuse_colour: Option<[f64; 3]>,
    /// Every non-ambient light, in scene order.
    pub lights: Vec<LightRecord>,
    /// The caustic share at the hit, when the scene has caustics and the surface a diffuse
    /// term.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub caustic: Option<CausticRecord>,
    /// Local illumination: ambient plus every light's diffuse and specular shares (and the
    /// caustic share).
    pub local: Option<[f64; 3]>,
    /// The refracted ray was impossible: its weight `k_t` went to the reflected ray.
    pub total_internal_reflection: bool,
    /// Reflected and refracted rays traced from the hit, in tracing order.
    pub children: Vec<RayNode>,
    /// Reflected or refracted rays not traced by adaptive depth control.
    pub cutoffs: Vec<Cutoff>,
    /// The radiance this ray returned: local + k_r reflected + k_t refracted.
    pub radiance: [f64; 3],
}

/// Where a ray met the scene.
#[derive(Clone, Debug, Serialize)]
pub struct Hit {
    pub object: usize,
    pub name: String,
    pub shape: &'static str,
    pub t: f64,
    pub point: [f64; 3],
    /// The surface's outward normal (the shading normal is it or its opposite).
    pub normal: [f64; 3],
    /// Whether the ray enters the object (comes from the side the normal points to).
    pub entering: bool,
    /// On a smooth triangle, how its normal was interpolated from the vertices'.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vertex_normals: Option<VertexNormals>,
    /// The material's reflection and transmission coefficients and index.
    pub kr: f64,
    pub kt: f64,
    pub ior: f64,
    /// The ambient and specular colours of the material's own (SIMRenderer's OpenGL
    /// material: a model's `.mtl`), with its name.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub own_colors: Option<OwnColors>,
}

/// A material's own ambient and specular colours `C_a`, `C_s` (in place of `S` and
/// `m S + (1 - m)`), and the material's name.
#[derive(Clone, Debug, Serialize)]
pub struct OwnColors {
    pub material: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ambient: Option<[f64; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub specular: Option<[f64; 3]>,
}

/// A smooth triangle's normal at a hit: the vertices' weighted by the barycentric
/// coordinates, of `length`, then made unit or kept by its rule (`normalized`, or
/// SIMRenderer's `linear`).
#[derive(Clone, Debug, Serialize)]
pub struct VertexNormals {
    pub interpolation: &'static str,
    pub length: f64,
}

/// One light at one hit.
#[derive(Clone, Debug, Serialize)]
pub struct LightRecord {
    pub index: usize,
    /// `directional`, `point`, `spot`, `area` (one record per point of an area light).
    pub kind: &'static str,
    /// `lit`, `facing_away` (N.L <= 0), `no_light` (outside a spot's cone, black, or at the
    /// light), or `below_horizon` (a whole area light behind the surface: one record).
    pub status: &'static str,
    /// `N.L` with the normal facing the incoming ray (absent for `no_light`).
    pub n_dot_l: Option<f64>,
    /// The numbers of a `lit` light.
    pub share: Option<Share>,
}

/// A lit light's share, as the tracer computed it.
#[derive(Clone, Debug, Serialize)]
pub struct Share {
    /// Unit vector `L` towards the light.
    pub to_light: [f64; 3],
    /// Distance to the light; `None` (null) for a directional light (infinite).
    pub distance: Option<f64>,
    /// Attenuation `A`.
    pub attenuation: f64,
    /// Spot factor `C_theta`.
    pub spot: f64,
    /// `A C_theta L`: the light reaching the point if nothing is in the way.
    pub incident: [f64; 3],
    /// The shadow ray, when one was cast.
    pub shadow_ray: Option<ShadowRay>,
    /// Product of the transparent objects' colours crossed (0 when an opaque one blocks).
    pub filter: [f64; 3],
    pub diffuse: [f64; 3],
    pub specular: [f64; 3],
}

/// The caustic photons' share at a hit.
#[derive(Clone, Debug, Serialize)]
pub struct CausticRecord {
    /// The irradiance `E` of the density estimate.
    pub irradiance: [f64; 3],
    /// The photons in the estimate (within the radius, arriving on the lit side).
    pub photons: usize,
    /// The radius of the estimate.
    pub radius: f64,
    /// The term added to the local illumination, `E k_d S`.
    pub term: [f64; 3],
}

/// A shadow ray towards a light.
#[derive(Clone, Debug, Serialize)]
pub struct ShadowRay {
    pub origin: [f64; 3],
    pub direction: [f64; 3],
    /// Tested up to this distance; `None` (null) for infinity.
    pub t_max: Option<f64>,
    /// `open`, `filtered` or `blocked`.
    pub result: &'static str,
    /// Names of the transparent objects whose colours filter it.
    pub filtered_by: Vec<String>,
}

/// A secondary ray skipped because its weight could not change the 8-bit result.
#[derive(Clone, Debug, Serialize)]
pub struct Cutoff {
    pub kind: &'static str,
    pub weight: f64,
}

fn v3(v: DVec3) -> [f64; 3] {
    v.to_array()
}

fn kind_name(kind: RayKind) -> &'static str {
    match kind {
        RayKind::Camera => "camera",
        RayKind::Shadow => "shadow",
        RayKind::Reflection => "reflection",
        RayKind::Refraction => "refraction",
    }
}

/// The kind of a light as written in scene files (an area light has one entry per point).
fn light_kind(light: &Light) -> &'static str {
    match light {
        Light::Ambient { .. } => "ambient",
        Light::Directional { .. } => "directional",
        Light::Point(_) => "point",
        Light::Spot(_) => "spot",
        Light::Area(_) => "area",
        Light::Aperture(a) => match a.aperture {
            crate::interference::Aperture::Linear { .. } => "linear_aperture",
            crate::interference::Aperture::Rectangular(_) => "rectangular_aperture",
            crate::interference::Aperture::Elliptical(_) => "elliptical_aperture",
            crate::interference::Aperture::Mask { .. } => "aperture_mask",
        },
    }
}

/// Builds the ray tree from the tracer's events: `ray` pushes a node, `done` pops it into
/// its parent (or, for the camera ray, into the sample).
pub struct TreeRecorder<'s> {
    scene: &'s Scene,
    /// The caustic estimate's radius (0 without caustics).
    radius: f64,
    stack: Vec<RayNode>,
    root: Option<RayNode>,
    sample: Option<(u32, [f64; 2])>,
    shadow: Option<ShadowRay>,
    pub samples: Vec<SampleTrace>,
}

impl<'s> TreeRecorder<'s> {
    pub fn new(scene: &'s Scene) -> Self {
        TreeRecorder {
            scene,
            radius: scene.settings.caustics.map_or(0.0, |c| c.radius),
            stack: Vec::new(),
            root: None,
            sample: None,
            shadow: None,
            samples: Vec::new(),
        }
    }

    fn top(&mut self) -> &mut RayNode {
        self.stack.last_mut().expect("a tracer event outside any ray")
    }
}

impl Recorder for TreeRecorder<'_> {
    fn ray(&mut self, kind: RayKind, ray: &Ray, level: u32, weight: f64) {
        self.stack.push(RayNode {
            kind: kind_name(kind),
            level,
            weight,
            origin: v3(ray.origin),
            direction: v3(ray.dir),
            hit: None,
            ambient: None,
            diffuse_colour: None,
            lights: Vec::new(),
            caustic: None,
            local: None,
            total_internal_reflection: false,
            children: Vec::new(),
            cutoffs: Vec::new(),
            radiance: [0.0; 3],
        });
    }

    fn hit(&mut self, object: usize, t: f64, point: DVec3, normal: DVec3, entering: bool) {
        let scene = self.scene;
        let o = &scene.objects[object];
        let m = &scene.materials[o.material()];
        self.top().hit = Some(Hit {
            object,
            name: scene.name_of(o).to_string(),
            shape: o.shape.kind(),
            t,
            point: v3(point),
            normal: v3(normal),
            entering,
            vertex_normals: match &o.shape {
                Shape::SmoothTriangle(s) => Some(VertexNormals {
                    interpolation: s.interpolation.name(),
                    length: s.normal_at_point(point, NormalInterpolation::Linear).length(),
                }),
                _ => None,
            },
            kr: m.kr,
            kt: m.kt,
            ior: m.ior,
            own_colors: (m.ambient_color().is_some() || m.specular_color().is_some()).then(|| OwnColors {
                material: scene.material_names[o.material()].clone(),
                ambient: m.ambient_color().map(v3),
                specular: m.specular_color().map(v3),
            }),
        });
    }

    fn ambient(&mut self, color: DVec3) {
        self.top().ambient = Some(v3(color));
    }

    fn no_light(&mut self, color: DVec3) {
        self.top().diffuse_colour = Some(v3(color));
    }

    fn unlit(&mut self, light: usize, n_dot_l: Option<f64>) {
        let kind = light_kind(&self.scene.lights[light]);
        self.top().lights.push(LightRecord {
            index: light,
            kind,
            status: if n_dot_l.is_some() { "facing_away" } else { "no_light" },
            n_dot_l,
            share: None,
        });
    }

    fn below_horizon(&mut self, light: usize) {
        let kind = light_kind(&self.scene.lights[light]);
        self.top().lights.push(LightRecord {
            index: light,
            kind,
            status: "below_horizon",
            n_dot_l: None,
            share: None,
        });
    }

    fn shadow_ray(&mut self, ray: &Ray, t_max: f64) {
        self.shadow = Some(ShadowRay {
            origin: v3(ray.origin),
            direction: v3(ray.dir),
            t_max: t_max.is_finite().then_some(t_max),
            result: "open",
            filtered_by: Vec::new(),
        });
    }

    fn shadow_crossed(&mut self, objects: &[usize]) {
        let names = objects
            .iter()
            .map(|&i| self.scene.name_of(&self.scene.objects[i]).to_string())
            .collect();
        if let Some(s) = &mut self.shadow {
            s.filtered_by = names;
        }
    }

    fn light(&mut self, share: &LightShare) {
        let kind = light_kind(&self.scene.lights[share.light]);
        let mut shadow = if share.shadow_ray { self.shadow.take() } else { None };
        if let Some(s) = &mut shadow {
            s.result = if share.filter == DVec3::ZERO {
                "blocked"
            } else if share.filter == DVec3::ONE {
                "open"
            } else {
                "filtered"
            };
        }
        let inc = &share.incidence;
        self.top().lights.push(LightRecord {
            index: share.light,
            kind,
            status: "lit",
            n_dot_l: Some(share.n_dot_l),
            share: Some(Share {
                to_light: v3(inc.to_light),
                distance: inc.distance.is_finite().then_some(inc.distance),
                attenuation: inc.attenuation,
                spot: inc.spot,
                incident: v3(inc.color),
                shadow_ray: shadow,
                filter: v3(share.filter),
                diffuse: v3(share.diffuse),
                specular: v3(share.specular),
            }),
        });
    }

    fn caustic(&mut self, term: DVec3, estimate: &Estimate) {
        let radius = self.radius;
        self.top().caustic = Some(CausticRecord {
            irradiance: v3(estimate.irradiance),
            photons: estimate.photons,
            radius,
            term: v3(term),
        });
    }

    fn local(&mut self, color: DVec3) {
        self.top().local = Some(v3(color));
    }

    fn cutoff(&mut self, kind: RayKind, weight: f64) {
        self.top().cutoffs.push(Cutoff {
            kind: kind_name(kind),
            weight,
        });
    }

    fn total_internal_reflection(&mut self) {
        self.top().total_internal_reflection = true;
    }

    fn done(&mut self, color: DVec3) {
        let mut node = self.stack.pop().expect("done without a ray");
        node.radiance = v3(color);
        match self.stack.last_mut() {
            Some(parent) => parent.children.push(node),
            None => self.root = Some(node),
        }
    }

    fn sample(&mut self, k: u32, px: f64, py: f64) {
        self.sample = Some((k, [px, py]));
    }

    fn sample_done(&mut self, radiance: DVec3) {
        let (index, position) = self.sample.take().expect("sample_done without sample");
        let ray = self.root.take().expect("a sample without a camera ray");
        self.samples.push(SampleTrace {
            index,
            position,
            ray,
            radiance: v3(radiance),
        });
    }
}

/// Probes pixel `(x, y)` of `scene`: every sample (the pixel's mean, exactly as
/// [`crate::render::render_pixel`] computes it) or only sample `sample`.
pub fn probe(scene: &Scene, x: u32, y: u32, sample: Option<u32>) -> Result<PixelProbe, String> {
    probe_with(scene, x, y, sample, AccelChoice::Auto)
}

/// [`probe`] with a chosen intersection core (the tree does not depend on it).
pub fn probe_with(
    scene: &Scene,
    x: u32,
    y: u32,
    sample: Option<u32>,
    accel: AccelChoice,
) -> Result<PixelProbe, String> {
    let s = &scene.settings;
    if x >= s.width || y >= s.height {
        return Err(format!(
            "--pixel {x},{y} is outside the {} x {} image (x in [0, {}], y in [0, {}])",
            s.width,
            s.height,
            s.width - 1,
            s.height - 1
        ));
    }
    if let Some(k) = sample
        && k >= s.samples_per_pixel
    {
        return Err(format!(
            "--sample {k}: the pixel has {} samples (K in [0, {}])",
            s.samples_per_pixel,
            s.samples_per_pixel - 1
        ));
    }
    let world = World::with_accel(scene, accel);
    let mut tracer = Tracer::new(&world);
    let mut rec = TreeRecorder::new(scene);
    let (of, radiance) = match sample {
        Some(k) => ("sample", render_sample(&mut tracer, x, y, k, &mut rec)),
        None => ("mean", render_pixel_recorded(&mut tracer, x, y, &mut rec)),
    };
    let c = &tracer.counts;
    Ok(PixelProbe {
        pixel: [x, y],
        photons: world.photons.as_ref().map(|m| PhotonCount {
            emitted: m.emitted(),
            stored: m.photons().len(),
        }),
        width: s.width,
        height: s.height,
        samples_per_pixel: s.samples_per_pixel,
        seed: s.seed,
        depth: s.depth,
        adaptive_threshold: s.adaptive_threshold,
        conventions: s.conventions.summary(),
        samples: rec.samples,
        color: {
            let normalized = s.color_normalization.apply(radiance);
            FinalColor {
                of,
                radiance: v3(radiance),
                divided: (!s.color_normalization.is_clamp_channel()).then(|| v3(normalized)),
                clamped: normalized.to_array().map(clamp_unit),
                rgb8: rgb8(radiance, s.color_normalization),
            }
        },
        counts: *c,
    })
}

/// A number at the text format's fixed precision (6 decimals; no "-0.000000").
fn num(x: f64) -> String {
    let s = format!("{x:.6}");
    if s.trim_start_matches(['-', '0', '.']).is_empty() {
        s.trim_start_matches('-').to_owned()
    } else {
        s
    }
}

fn vec(v: &[f64]) -> String {
    let parts: Vec<String> = v.iter().map(|&x| num(x)).collect();
    format!("({})", parts.join(", "))
}

/// The probe as an indented tree for people, numbers at 6 decimals.
pub fn format_text(p: &PixelProbe) -> String {
    let mut out = String::new();
    let o = &mut out;
    let _ = writeln!(
        o,
        "pixel ({}, {}) of {} x {}, {} sample(s) per pixel, seed {}, depth {}, adaptive threshold {} levels",
        p.pixel[0],
        p.pixel[1],
        p.width,
        p.height,
        p.samples_per_pixel,
        p.seed,
        p.depth,
        num(p.adaptive_threshold)
    );
    let _ = writeln!(o, "conventions {}", p.conventions);
    if let Some(n) = &p.photons {
        let _ = writeln!(o, "caustics: {} photon(s) stored of {} emitted", n.stored, n.emitted);
    }
    for s in &p.samples {
        let _ = writeln!(o, "sample {} at image position {}", s.index, vec(&s.position));
        write_ray(o, &s.ray, 1);
        let _ = writeln!(o, "  sample radiance {}", vec(&s.radiance));
    }
    let c = &p.color;
    let what = if c.of == "mean" {
        format!("mean of {} sample(s)", p.samples.len())
    } else {
        format!("sample {} alone", p.samples.first().map_or(0, |s| s.index))
    };
    let _ = writeln!(o, "colour ({what}) {}", vec(&c.radiance));
    if let Some(d) = &c.divided {
        let _ = writeln!(
            o,
            "  divided by its largest channel above 1 (division_factor) {}",
            vec(d)
        );
    }
    let _ = writeln!(o, "  clamped to [0, 1] {}", vec(&c.clamped));
    let _ = writeln!(o, "  8-bit ({}, {}, {})", c.rgb8[0], c.rgb8[1], c.rgb8[2]);
    let n = &p.counts;
    let _ = writeln!(
        o,
        "rays: camera {}, shadow {}, reflection {}, refraction {}; total internal reflections {}, adaptive cutoffs {}, non-finite samples {}",
        n.camera, n.shadow, n.reflection, n.refraction, n.total_internal_reflections, n.adaptive_cutoffs, n.non_finite
    );
    out
}

fn write_ray(o: &mut String, r: &RayNode, depth: usize) {
    let pad = "  ".repeat(depth);
    let _ = writeln!(o, "{pad}{} ray, level {}, weight {}", r.kind, r.level, num(r.weight));
    let _ = writeln!(o, "{pad}  origin {}, direction {}", vec(&r.origin), vec(&r.direction));
    match &r.hit {
        None => {
            let _ = writeln!(o, "{pad}  misses: background");
        }
        Some(h) => {
            let _ = writeln!(
                o,
                "{pad}  hit object {} \"{}\" ({}), t {}, {}",
                h.object,
                h.name,
                h.shape,
                num(h.t),
                if h.entering { "entering" } else { "leaving" }
            );
            let _ = writeln!(o, "{pad}    point {}, normal {}", vec(&h.point), vec(&h.normal));
            if let Some(v) = &h.vertex_normals {
                let kept = if v.interpolation == NormalInterpolation::Linear.name() {
                    "kept, as SIMRenderer's btriangle keeps it"
                } else {
                    "made 1"
                };
                // `length L, kept ...` or `length L, made 1`.
                let _ = writeln!(
                    o,
                    "{pad}    normal interpolated from the vertices' ({}): length {}, {kept}",
                    v.interpolation,
                    num(v.length)
                );
            }
            let _ = writeln!(o, "{pad}    k_r {}, k_t {}, n {}", num(h.kr), num(h.kt), num(h.ior));
            if let Some(c) = &h.own_colors {
                let part = |what: &str, symbol: &str, v: &Option<[f64; 3]>| {
                    v.as_ref().map(|v| format!(", {what} colour {symbol} {}", vec(v)))
                };
                let _ = writeln!(
                    o,
                    "{pad}    material \"{}\" has its own colours (SIMRenderer's OpenGL material){}{}",
                    c.material,
                    part("ambient", "C_a", &c.ambient).unwrap_or_default(),
                    part("specular", "C_s", &c.specular).unwrap_or_default()
                );
            }
        }
    }
    if let Some(a) = &r.ambient {
        let _ = writeln!(o, "{pad}  ambient {}", vec(a));
    }
    if let Some(c) = &r.diffuse_colour {
        let _ = writeln!(o, "{pad}  no light: diffuse colour k_d S {}", vec(c));
    }
    for l in &r.lights {
        write_light(o, l, &pad);
    }
    if let Some(c) = &r.caustic {
        let _ = writeln!(
            o,
            "{pad}  caustic: {} photon(s) within {}, irradiance E {}, E k_d S {}",
            c.photons,
            num(c.radius),
            vec(&c.irradiance),
            vec(&c.term)
        );
    }
    if let Some(l) = &r.local {
        let _ = writeln!(o, "{pad}  local {}", vec(l));
    }
    if r.total_internal_reflection {
        let _ = writeln!(o, "{pad}  total internal reflection: k_t is added to k_r");
    }
    for child in &r.children {
        write_ray(o, child, depth + 1);
    }
    for c in &r.cutoffs {
        let _ = writeln!(
            o,
            "{pad}  {} ray not traced: adaptive cutoff at weight {}",
            c.kind,
            num(c.weight)
        );
    }
    let _ = writeln!(o, "{pad}  radiance {}", vec(&r.radiance));
}

fn write_light(o: &mut String, l: &LightRecord, pad: &str) {
    let head = format!("{pad}  light {} ({})", l.index, l.kind);
    let Some(s) = &l.share else {
        let _ = match l.n_dot_l {
            Some(nl) => writeln!(o, "{head}: faces away, N.L {}: no share, no shadow ray", num(nl)),
            None if l.kind == "spot" => writeln!(o, "{head}: outside the cone (C_theta = 0): no share"),
            None => writeln!(o, "{head}: no light arrives (the point is at the light): no share"),
        };
        return;
    };
    let _ = writeln!(
        o,
        "{head}: N.L {}, A {}, C_theta {}, L {}, distance {}",
        num(l.n_dot_l.unwrap_or(0.0)),
        num(s.attenuation),
        num(s.spot),
        vec(&s.to_light),
        s.distance.map_or("infinite".to_owned(), num)
    );
    let _ = writeln!(o, "{pad}    incident A C_theta L {}", vec(&s.incident));
    match &s.shadow_ray {
        None => {
            let _ = writeln!(o, "{pad}    no shadow ray (shadows off)");
        }
        Some(sr) => {
            let by = if sr.filtered_by.is_empty() {
                String::new()
            } else {
                let names: Vec<String> = sr.filtered_by.iter().map(|n| format!("\"{n}\"")).collect();
                format!(" by {}", names.join(", "))
            };
            let _ = writeln!(
                o,
                "{pad}    shadow ray from {} towards {} up to {}: {}{by}, filter {}",
                vec(&sr.origin),
                vec(&sr.direction),
                sr.t_max.map_or("infinity".to_owned(), num),
                sr.result,
                vec(&s.filter)
            );
        }
    }
    let _ = writeln!(o, "{pad}    diffuse {}, specular {}", vec(&s.diffuse), vec(&s.specular));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_precision_numbers() {
        assert_eq!(num(0.5), "0.500000");
        assert_eq!(num(-0.0), "0.000000");
        assert_eq!(num(-1e-12), "0.000000");
        assert_eq!(num(-0.25), "-0.250000");
        assert_eq!(vec(&[1.0, 2.0, 3.0]), "(1.000000, 2.000000, 3.000000)");
    }
}
