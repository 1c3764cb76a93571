//! Whitted recursion (chapter 7.4b): at each hit, local illumination with colour-filtered
//! shadow rays, then a reflected ray (weight `k_r`) and a refracted ray (weight `k_t`), total
//! internal reflection sending the refracted weight to the reflection, down to the scene's
//! recursion depth, with adaptive depth control.
//!
//! Two tracers compute it, to the same bits:
//! - [`reference`](mod@reference): the chapter as it reads, one ray and one light point at a time, with no
//!   shortcut. Read it first: it is the specification of every pixel.
//! - [`fast`]: what renders. It traces the images of a one-pass family together
//!   ([`crate::family`]), takes an area light's points together in vector lanes and groups
//!   their shadow tests (src/trace/fast/area.rs), and skips the work that cannot change a pixel
//!   ([`crate::skips`]). Each of its parts names the reference function it equals, and
//!   tests/reference.rs holds the two tracers to the same image bytes on every course scene.
//!
//! Every step of the fast tracer can be reported to a [`Recorder`]; the renderer passes
//! [`NoRecord`], which compiles to nothing, and `probe` passes a recorder that keeps the
//! whole ray tree, so both see the same numbers. Both tracers evaluate every formula through
//! its one definition in [`crate::shading`], [`crate::light`] and [`crate::math`].

use crate::caustics::Estimate;
use crate::light::Incidence;
use crate::material::{Material, Reflectance};
use crate::math::{Ray, facing_normal};
use crate::scene::{ShadingModel, Specular};
use crate::shading::{blinn, caustic, diffuse, phong, specular};
use crate::shape::SurfaceHit;
use crate::skips::Saved;
use crate::world::World;
use glam::DVec3;

pub mod fast;
pub mod formulas;
pub mod reference;

pub use fast::{Member, Tracer};
pub use formulas::Formulas;
pub use reference::Reference;

/// One point light's diffuse and specular shares at `at` (slides, full model):
/// `L k_d S max(N.L, 0)` and `L k_s [m S + (1 - m)] spec`, `spec` Phong's or Blinn's term as
/// `model` says, for the light `light` arriving through its shadow filter (`A C_theta L`
/// times the filter) from direction `inc.to_light`; a texture material's images give the
/// point's colours ([`Surface::reflectance`]). Both tracers shade every point light so.
#[inline(always)]
pub(crate) fn point_light_terms(
    model: ShadingModel,
    mat: &Material,
    at: &Surface,
    to_light: DVec3,
    n_dot_l: f64,
    light: DVec3,
) -> (DVec3, DVec3) {
    point_light_terms_with(specular_term, model, mat, at, to_light, n_dot_l, light)
}

/// The specular term `spec` of the model `specular` asks for (slides): 0, Phong's
/// `max(R.E, 0)^n` or Blinn's `max(N.H, 0)^n`, for the unit normal `n`, direction to the
/// light `l`, direction to the eye `e` and exponent `n`.
#[inline(always)]
pub fn specular_term(specular: Specular, n: DVec3, l: DVec3, e: DVec3, exponent: f64) -> f64 {
    match specular {
        Specular::None => 0.0,
        Specular::Phong => phong(n, l, e, exponent),
        Specular::Blinn => blinn(n, l, e, exponent),
    }
}

/// [`point_light_terms`] with the specular term computed by `spec_term` (a
/// [`formulas::FormulaTable`] entry: [`specular_term`] or a mistake's).
#[inline(always)]
pub(crate) fn point_light_terms_with(
    spec_term: impl Fn(Specular, DVec3, DVec3, DVec3, f64) -> f64,
    model: ShadingModel,
    mat: &Material,
    at: &Surface,
    to_light: DVec3,
    n_dot_l: f64,
    light: DVec3,
) -> (DVec3, DVec3) {
    let spec = spec_term(model.specular, at.n, to_light, at.eye, mat.shininess);
    let r = at.reflectance(mat);
    (
        diffuse(light, diffuse_coefficient(model, &r), r.diffuse, n_dot_l),
        specular(light, r.ks, r.tint, spec),
    )
}

/// The `k_d` a point light's diffuse term is computed with: the reflectance's, or 0 under
/// a shading model without the diffuse term.
#[inline(always)]
pub(crate) fn diffuse_coefficient(model: ShadingModel, r: &Reflectance) -> f64 {
    if model.diffuse { r.kd } else { 0.0 }
}

/// The caustic share at a hit of a camera path, `E k_d S` ([`caustic`]) for the irradiance
/// `E` of the photon map's estimate there, `k_d S` the diffuse term's colour at the point
/// (the texel under a diffuse image), with the estimate; `None` when the scene has no
/// caustics, the model no diffuse term, or the surface receives no photon
/// ([`Material::receives_photons`]). Both tracers add it to the local illumination, after
/// every light's share.
pub(crate) fn caustic_share(
    world: &World,
    model: ShadingModel,
    mat: &Material,
    at: &Surface,
) -> Option<(DVec3, Estimate)> {
    let map = world.photons.as_ref()?;
    if !model.diffuse || !mat.receives_photons() {
        return None;
    }
    let estimate = map.estimate(at.point, at.n);
    let r = at.reflectance(mat);
    Some((caustic(estimate.irradiance, r.kd, r.diffuse), estimate))
}

/// Which pixel sample a ray belongs to: the pixel's index (row-major) and the sample's.
/// The points of an area light drawn afresh for each sample depend on it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SampleKey {
    pub pixel: u64,
    pub sample: u32,
}

/// What a ray is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayKind {
    Camera,
    Shadow,
    Reflection,
    Refraction,
}

/// Rays traced, by kind, and work skipped, by reason (left out of the serialised form,
/// which `probe --json` prints).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct RayCounts {
    pub camera: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
    /// Refractions turned into reflections by total internal reflection.
    pub total_internal_reflections: u64,
    /// Secondary rays not traced because their weight could not change the 8-bit result.
    pub adaptive_cutoffs: u64,
    /// Samples whose radiance was NaN or infinite (replaced by black).
    pub non_finite: u64,
    /// Work left out, by shortcut (see [`crate::skips`]).
    #[serde(skip)]
    pub saved: Saved,
}

impl RayCounts {
    pub fn add(&mut self, o: &RayCounts) {
        self.camera += o.camera;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
        self.total_internal_reflections += o.total_internal_reflections;
        self.adaptive_cutoffs += o.adaptive_cutoffs;
        self.non_finite += o.non_finite;
        self.saved.add(&o.saved);
    }

    pub fn total_rays(&self) -> u64 {
        self.camera + self.shadow + self.reflection + self.refraction
    }
}

/// One light's share at a hit, as the tracer computed it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightShare {
    /// Index of the light in the scene's list.
    pub light: usize,
    pub incidence: Incidence,
    /// `N.L` with the normal facing the incoming ray.
    pub n_dot_l: f64,
    /// Whether a shadow ray was cast (not when N.L <= 0 or shadows are off).
    pub shadow_ray: bool,
    /// Product of the transparent objects' colours crossed (0 if an opaque one blocks).
    pub filter: DVec3,
    /// The diffuse term; for an aperture light, its whole share (it has no highlight).
    pub diffuse: DVec3,
    pub specular: DVec3,
}

/// Observer of the tracer's steps; every method does nothing by default.
pub trait Recorder {
    /// False for a recorder that ignores every event, so the tracer can skip gathering
    /// what only the events need.
    const RECORDS: bool = true;
    fn ray(&mut self, _kind: RayKind, _ray: &Ray, _level: u32, _weight: f64) {}
    fn hit(&mut self, _object: usize, _t: f64, _point: DVec3, _normal: DVec3, _entering: bool) {}
    fn miss(&mut self) {}
    fn ambient(&mut self, _color: DVec3) {}
    /// The diffuse colour `k_d S` a hit shows with no light (the `no_light` shading model),
    /// in place of the ambient term and every light's share.
    fn no_light(&mut self, _color: DVec3) {}
    fn light(&mut self, _share: &LightShare) {}
    /// A light that adds nothing at this hit and casts no shadow ray: `n_dot_l` is `None`
    /// when no light arrives at all (outside a spot's cone, or exactly at the light), else
    /// the `N.L <= 0` of a surface facing away from it.
    fn unlit(&mut self, _light: usize, _n_dot_l: Option<f64>) {}
    /// An area light wholly below the surface's horizon: none of its points is looked at.
    fn below_horizon(&mut self, _light: usize) {}
    /// A shadow ray towards a light, tested up to `t_max` (infinite for directional
    /// lights), before the [`Recorder::light`] event of the same light.
    fn shadow_ray(&mut self, _ray: &Ray, _t_max: f64) {}
    /// The transparent objects (indices, ascending) whose colours filter the last shadow
    /// ray; not reported when an opaque object blocks it or nothing is transparent.
    fn shadow_crossed(&mut self, _objects: &[usize]) {}
    /// The caustic share of the current hit (`caustic_share`): the term added, and the
    /// estimate (irradiance, photons) it comes from.
    fn caustic(&mut self, _term: DVec3, _estimate: &Estimate) {}
    /// The local illumination of the current hit (ambient + every light's share).
    fn local(&mut self, _color: DVec3) {}
    fn cutoff(&mut self, _kind: RayKind, _weight: f64) {}
    fn total_internal_reflection(&mut self) {}
    /// The radiance the ray at the innermost open level returned.
    fn done(&mut self, _color: DVec3) {}
    /// Sample `k` of a pixel starts, at image position `(px, py)` (before its camera ray).
    fn sample(&mut self, _k: u32, _px: f64, _py: f64) {}
    /// The sample's radiance as it enters the pixel mean (non-finite replaced by black).
    fn sample_done(&mut self, _radiance: DVec3) {}
}

/// The recorder that records nothing.
pub struct NoRecord;
impl Recorder for NoRecord {
    const RECORDS: bool = false;
}

/// A shaded surface point: position, shading normal `n` (facing the incoming ray), outward
/// normal and rounding-error bound (for the origins of the rays that leave it), direction
/// to the eye, object, and texture coordinates when its material has images.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Surface {
    pub(crate) point: DVec3,
    pub(crate) n: DVec3,
    pub(crate) outward: DVec3,
    pub(crate) err: f64,
    pub(crate) eye: DVec3,
    pub(crate) object: usize,
    /// Whether the ray arrives from the outside (against the outward normal).
    pub(crate) entering: bool,
    /// The point's texture coordinates ([`crate::shape::Shape::uv`]); `(0, 0)`, unused,
    /// on an object whose material has no images.
    pub(crate) uv: (f64, f64),
}

impl Surface {
    /// The surface point where `ray` hits `object` (chapter 7.4b:
    /// `r_inter = r_0 + v t_inter`), with the bound on its rounding error: forming the point
    /// ([`hit_point_error`]) plus the shape's own ([`crate::shape::Shape::surface_error`]).
    #[inline]
    pub(crate) fn hit(world: &World, ray: &Ray, object: usize, hit: &SurfaceHit) -> Surface {
        let (point, err) = world.objects()[object].shape.hit_point(ray, hit.t);
        let (entering, n) = facing_normal(ray.dir, hit.normal);
        // A family's members share the scene's textures (their keys hold them), so the
        // world's material says whether the point needs coordinates.
        let uv = if world.has_textures && world.material_of(object).images().is_some() {
            world.objects()[object].shape.uv(point)
        } else {
            (0.0, 0.0)
        };
        Surface {
            point,
            n,
            outward: hit.normal,
            err,
            eye: -ray.dir,
            object,
            entering,
            uv,
        }
    }

    /// The colours `mat` reflects at this point: the one texture lookup of both tracers
    /// ([`Material::reflectance`] at the point's coordinates).
    #[inline]
    pub(crate) fn reflectance(&self, mat: &Material) -> Reflectance {
        mat.reflectance(|| self.uv)
    }

    /// A ray leaving this point along `dir` (a shadow, reflected or refracted ray): from the
    /// point, offset past its rounding error to the side `dir` goes ([`Ray::leaving`]).
    pub(crate) fn ray_along(&self, dir: DVec3) -> Ray {
        Ray::leaving(self.point, self.outward, self.err, dir)
    }
}
