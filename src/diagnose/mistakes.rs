//! The catalogue of named mistakes `lumiere diagnose` renders and ranks. Each is one of:
//! - a change of the reference tracer's formula table ([`Formulas`]): an entry replaced by
//!   the wrong formula written here, the chapter's own functions left alone;
//! - a convention switch ([`crate::conventions`]) set to SIMRenderer's value where the
//!   oracle follows the chapter's (and to the chapter's where it follows SIMRenderer's);
//! - the recursion depth one level short or over;
//! - every material's specular exponent multiplied by a factor, which the diagnosis fits
//!   to each image ([`super::exponent`]) instead of rendering it once;
//! - a post-process of the oracle's image (the sRGB transfer, a vertical or horizontal
//!   flip, red and blue exchanged).
//!
//! Nothing outside this module and its parent knows about mistakes.

use crate::conventions::{Conventions, ShadowFilter};
use crate::material::Material;
use crate::math::{Ray, mirror, refract, refraction_radicand};
use crate::scene::{Scene, Specular};
use crate::shading::{outside_spot_cone, phong, positive_part, pow, transparent_filter};
use crate::shape::{NormalInterpolation, Shape, SmoothTriangle, SurfaceHit};
use crate::trace::Formulas;
use crate::trace::formulas::AmbientContext;
use crate::trace::specular_term;
use crate::world::World;
use glam::DVec3;

/// How a mistake changes the oracle's render.
#[derive(Clone, Copy, Debug)]
pub enum Change {
    /// The reference tracer evaluates these formulas.
    Formulas(Formulas),
    /// The convention switch `key` takes the other preset's value.
    Convention(&'static str),
    /// The recursion depth off by this many levels: the depth test compared one way where
    /// the other is meant, or the levels counted from 0.
    Depth(i32),
    /// Every material's specular exponent `n` multiplied by this factor. The diagnosis fits
    /// the factor to the image; this one is what `render --mistake` draws.
    SpecularExponent(f64),
    /// The sRGB transfer function applied before quantisation.
    Gamma,
    /// The image upside down.
    FlipVertical,
    /// The image mirrored left-right.
    FlipHorizontal,
    /// The red and blue channels exchanged.
    SwapRedBlue,
}

impl Change {
    /// What kind of change it makes to the oracle's render, as `diagnose --list` names it:
    /// `formula`, `convention`, `recursion`, `fitted` or `post-process`.
    pub fn kind(self) -> &'static str {
        match self {
            Change::Formulas(_) => "formula",
            Change::Convention(_) => "convention",
            Change::Depth(_) => "recursion",
            Change::SpecularExponent(_) => "fitted",
            Change::Gamma | Change::FlipVertical | Change::FlipHorizontal | Change::SwapRedBlue => super::POST_PROCESS,
        }
    }

    /// The pixel of the oracle's `width x height` image that an image with this change
    /// shows at `(x, y)`: mirrored by a flip, the same pixel otherwise.
    pub fn source_pixel(self, (x, y): (u32, u32), width: u32, height: u32) -> (u32, u32) {
        match self {
            Change::FlipVertical => (x, height - 1 - y),
            Change::FlipHorizontal => (width - 1 - x, y),
            _ => (x, y),
        }
    }

    /// The colour an image with this change writes for the oracle's `colour`: red and blue
    /// exchanged by [`Change::SwapRedBlue`], as it is otherwise.
    pub fn written_colour(self, colour: DVec3) -> DVec3 {
        match self {
            Change::SwapRedBlue => DVec3::new(colour.z, colour.y, colour.x),
            _ => colour,
        }
    }
}

/// A named mistake.
#[derive(Clone, Copy, Debug)]
pub struct Mistake {
    /// A short name, as printed and in JSON (`phong-for-blinn`).
    pub name: &'static str,
    /// What the wrong code does, in a line.
    pub description: &'static str,
    pub change: Change,
}

/// Phong's `(R.E)^n` where the model asks for Blinn's `(N.H)^n`.
fn phong_for_blinn(model: Specular, n: DVec3, l: DVec3, e: DVec3, exponent: f64) -> f64 {
    match model {
        Specular::Blinn => phong(n, l, e, exponent),
        other => specular_term(other, n, l, e, exponent),
    }
}

/// Blinn's term with the half vector left unnormalised: `max(N.(L + E), 0)^n`.
fn unnormalised_half_vector(model: Specular, n: DVec3, l: DVec3, e: DVec3, exponent: f64) -> f64 {
    match model {
        Specular::Blinn => pow(positive_part(n.dot(l + e)), exponent),
        other => specular_term(other, n, l, e, exponent),
    }
}

/// The specular term with `E` taken along the ray (`v`) instead of towards the eye (`-v`).
fn eye_reversed(model: Specular, n: DVec3, l: DVec3, e: DVec3, exponent: f64) -> f64 {
    specular_term(model, n, l, -e, exponent)
}

/// Whether SIMRenderer's lab has the student write the shape's intersection: the sphere,
/// the tube and cylinder, the cone and the torus, also through a transform (an ellipsoid),
/// which SIMRenderer meets by the shape's own routine on the ray taken into its frame.
fn lab_written(shape: &Shape) -> bool {
    match shape {
        Shape::Sphere(_) | Shape::Cylinder(_) | Shape::Cone(_) | Shape::Torus(_) => true,
        Shape::Transformed(t) => lab_written(&t.shape),
        _ => false,
    }
}

/// Most hits a ray has on one of the lab's shapes: a torus's four roots, a capped shape's
/// side and caps.
const MOST_HITS: usize = 4;

/// The closest hit before `t_max` with each of the lab's shapes met at the hit `pick`
/// finds for it along the whole ray (kept when it is in `(0, t_max)` and nearer than the
/// best so far, as a student's routine keeps the root it chose), every other shape as the
/// chapter meets it: the objects scanned in order, the nearest kept, the lowest index on
/// equal `t`.
fn closest_with_lab_hit(
    world: &World<'_>,
    ray: &Ray,
    t_max: f64,
    pick: fn(&Shape, &Ray) -> Option<SurfaceHit>,
) -> Option<(usize, SurfaceHit)> {
    let mut best: Option<(usize, SurfaceHit)> = None;
    for (j, object) in world.objects().iter().enumerate() {
        let limit = best.map_or(t_max, |(_, h)| h.t);
        let hit = if lab_written(&object.shape) {
            pick(&object.shape, ray).filter(|h| h.t > 0.0 && h.t < limit)
        } else {
            object.shape.intersect(ray, 0.0, limit)
        };
        if let Some(h) = hit {
            best = Some((j, h));
        }
    }
    best
}

/// The last of the shape's hits with `t > 0`, each hit searched beyond the one before (the
/// larger root of a sphere's quadratic).
fn last_hit(shape: &Shape, ray: &Ray) -> Option<SurfaceHit> {
    let mut last: Option<SurfaceHit> = None;
    for _ in 0..MOST_HITS {
        match shape.intersect(ray, last.map_or(0.0, |h| h.t), f64::INFINITY) {
            Some(h) => last = Some(h),
            None => break,
        }
    }
    last
}

/// The shape's first hit along the whole line, behind the ray's origin or not (the smaller
/// root of a sphere's quadratic, however negative).
fn first_hit_on_the_line(shape: &Shape, ray: &Ray) -> Option<SurfaceHit> {
    shape.intersect(ray, f64::NEG_INFINITY, f64::INFINITY)
}

/// The lab's shapes met at their last hit: a sphere in front of the eye is seen from
/// inside, its far side.
fn far_root(world: &World<'_>, ray: &Ray, t_max: f64) -> Option<(usize, SurfaceHit)> {
    closest_with_lab_hit(world, ray, t_max, last_hit)
}

/// The lab's shapes met at their first hit on the ray's line only, none when it is behind
/// the origin: a ray inside a sphere (refracted into glass) never finds its way out.
fn near_root_only(world: &World<'_>, ray: &Ray, t_max: f64) -> Option<(usize, SurfaceHit)> {
    closest_with_lab_hit(world, ray, t_max, first_hit_on_the_line)
}

/// The chapter's closest hit with a sphere's normal left as `P - C`, of length `r`: every
/// term that reads the normal scaled (the diffuse term by `r`, Blinn's by `r^n`).
fn sphere_normal_unnormalised(world: &World<'_>, ray: &Ray, t_max: f64) -> Option<(usize, SurfaceHit)> {
    let (j, hit) = world.closest_before(ray, t_max)?;
    let normal = match &world.objects()[j].shape {
        Shape::Sphere(s) => hit.normal * s.radius,
        _ => hit.normal,
    };
    Some((j, SurfaceHit { t: hit.t, normal }))
}

/// The chapter's closest hit with a smooth triangle's normal replaced by `other(triangle,
/// hit point)`.
fn smooth_normal_replaced(
    world: &World<'_>,
    ray: &Ray,
    t_max: f64,
    other: fn(&SmoothTriangle, DVec3) -> DVec3,
) -> Option<(usize, SurfaceHit)> {
    let (j, hit) = world.closest_before(ray, t_max)?;
    let normal = match &world.objects()[j].shape {
        Shape::SmoothTriangle(s) => other(s, ray.at(hit.t)),
        _ => hit.normal,
    };
    Some((j, SurfaceHit { t: hit.t, normal }))
}

/// A smooth triangle's interpolated normal by the other rule: made unit where the triangle
/// keeps its length (SIMRenderer's `btriangle`), its length kept where it is made unit.
fn smooth_normal_other_length(world: &World<'_>, ray: &Ray, t_max: f64) -> Option<(usize, SurfaceHit)> {
    smooth_normal_replaced(world, ray, t_max, |s, p| {
        let other = match s.interpolation {
            NormalInterpolation::Linear => NormalInterpolation::Normalized,
            NormalInterpolation::Normalized => NormalInterpolation::Linear,
        };
        s.normal_at_point(p, other)
    })
}

/// A smooth triangle shaded with its face's normal, its vertex normals ignored.
fn smooth_face_normal(world: &World<'_>, ray: &Ray, t_max: f64) -> Option<(usize, SurfaceHit)> {
    smooth_normal_replaced(world, ray, t_max, |s, _| s.triangle.normal())
}

/// Shadow rays not stopped at a point light: an object beyond the light shadows the point.
fn past_the_light(_distance: f64) -> f64 {
    f64::INFINITY
}

/// The law of reflection with the sign of its normal term flipped: `R = v - 2 (E.N) N`.
fn reflection_wrong_sign(v: DVec3, n: DVec3) -> DVec3 {
    mirror(v, n, -(-v).dot(n))
}

/// The ratio of indices inverted: `n2 / n1` where the law takes `n1 / n2`.
fn inverted_index(mat: &Material, entering: bool) -> f64 {
    1.0 / mat.eta(entering)
}

/// The entering ratio `n1 / n2 = 1 / n` on both sides: a ray leaving glass bends as if it
/// entered it (the ratio not inverted on the way out).
fn exit_index_not_inverted(mat: &Material, _entering: bool) -> f64 {
    mat.eta(true)
}

/// The outward normal given to the law of refraction whichever side the ray comes from:
/// a ray leaving glass is refracted about the normal on the far side, and turns back in.
fn outward_refraction_normal(_facing: DVec3, outward: DVec3) -> DVec3 {
    outward
}

/// The law of refraction with `E.N` taken as `v.N` in its linear term:
/// `T = n v + (n (v.N) - sqrt(1 - n^2 (1 - (E.N)^2))) N`, the chapter's `T` less
/// `2 n (E.N) N`. At `n = 1` the chapter's ray goes straight on, this one turns.
fn refraction_cosine_sign(v: DVec3, n_normal: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = (-v).dot(n_normal);
    refract(v, n_normal, eta).map(|t| t - 2.0 * eta * cos_i * n_normal)
}

/// The law of refraction with no total internal reflection: the root's argument taken as
/// its absolute value, `T = n v + (n (E.N) - sqrt(|1 - n^2 (1 - (E.N)^2)|)) N`, so a ray
/// is always refracted.
fn refract_always(v: DVec3, n_normal: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = (-v).dot(n_normal);
    let radicand = refraction_radicand(eta, cos_i);
    Some(eta * v + (eta * cos_i - radicand.abs().sqrt()) * n_normal)
}

/// Transparent objects block shadow rays as opaque ones do.
fn black_filter(_: ShadowFilter, _: f64, _: DVec3) -> DVec3 {
    DVec3::ZERO
}

/// A transparent object's filter applied at each of its surfaces a shadow ray crosses:
/// twice for a closed object it passes through, `S^2`.
fn filter_twice(rule: ShadowFilter, kt: f64, s: DVec3) -> DVec3 {
    let f = transparent_filter(rule, kt, s);
    f * f
}

/// A shadow ray starting on the surface point itself, with no offset.
fn no_offset(point: DVec3, _outward: DVec3, _err: f64, _dir: DVec3) -> DVec3 {
    point
}

/// `L` pointing from the light to the point instead of towards the light.
fn reversed_direction(l: DVec3) -> DVec3 {
    -l
}

/// No surface facing away from a light: its share computed at any `N.L`, the shadow ray
/// cast, the diffuse term 0 through `max(N.L, 0)` but Phong's `max(R.E, 0)^n` or Blinn's
/// `max(N.H, 0)^n` not. Seen where the shadow ray gets through: an open surface lit from
/// behind, a transparent object's far side.
fn never_faces_away(_n_dot_l: f64) -> bool {
    false
}

/// A spotlight falling off as the cosine, `C_theta = C_max (o.d)`, inside the cone.
fn cosine_spot(o_dot_d: f64, cos_half: f64, _c_min: f64, c_max: f64) -> f64 {
    if outside_spot_cone(o_dot_d, cos_half) {
        return 0.0;
    }
    c_max * o_dot_d
}

/// Each light's share clamped to [0, 1] before the sum, instead of the pixel at output.
fn clamp_each(share: DVec3) -> DVec3 {
    share.clamp(DVec3::ZERO, DVec3::ONE)
}

/// No ambient term where every shadow ray is blocked.
fn ambient_lit_only(term: DVec3, context: AmbientContext) -> DVec3 {
    if context.in_shadow { DVec3::ZERO } else { term }
}

/// The ambient term attenuated by the first point or spot light's `A`.
fn ambient_attenuated(term: DVec3, context: AmbientContext) -> DVec3 {
    term * context.attenuation
}

/// The chapter's formulas with every material's specular exponent multiplied by `factor`.
pub fn exponent_scaled(factor: f64) -> Formulas {
    Formulas {
        exponent_scale: factor,
        ..Formulas::CHAPTER
    }
}

/// The specular exponents a render of `scene` shows, each once, ascending: those of the
/// materials of its objects with a highlight (`k_s > 0`); none when its model has no
/// specular term, where no exponent changes the image.
pub fn shown_exponents(scene: &Scene) -> Vec<f64> {
    if scene.settings.shading.specular == Specular::None {
        return Vec::new();
    }
    let mut exponents: Vec<f64> = scene
        .objects
        .iter()
        .map(|o| &scene.materials[o.material()])
        .filter(|m| m.ks > 0.0)
        .map(|m| m.shininess)
        .collect();
    exponents.sort_by(f64::total_cmp);
    exponents.dedup();
    exponents
}

/// The chapter's formulas with some entries replaced.
fn with(change: fn(Formulas) -> Formulas) -> Change {
    Change::Formulas(change(Formulas::CHAPTER))
}

/// The conventions where the oracle's `conventions` and the other preset differ: the
/// chapter's against SIMRenderer's, or SIMRenderer's against the chapter's.
pub fn convention_value(conventions: &Conventions, key: &str) -> Option<String> {
    let other = if conventions.describe() == Conventions::SIMRENDERER.describe() {
        Conventions::CHAPTER
    } else {
        Conventions::SIMRENDERER
    };
    let mine = conventions.describe().into_iter().find(|(k, _)| *k == key)?.1;
    let theirs = other.describe().into_iter().find(|(k, _)| *k == key)?.1;
    (mine != theirs).then_some(theirs)
}

/// Every mistake, in the order ties are broken.
pub fn catalogue() -> Vec<Mistake> {
    let m = |name, description, change| Mistake {
        name,
        description,
        change,
    };
    vec![
        m(
            "phong-for-blinn",
            "Phong's (R.E)^n where the scene asks for Blinn's (N.H)^n",
            with(|f| Formulas {
                specular: phong_for_blinn,
                ..f
            }),
        ),
        m(
            "unnormalised-half-vector",
            "Blinn's term with H = L + E not normalised",
            with(|f| Formulas {
                specular: unnormalised_half_vector,
                ..f
            }),
        ),
        m(
            "eye-direction-reversed",
            "E taken along the ray (v) instead of towards the eye (-v) in the specular term",
            with(|f| Formulas {
                specular: eye_reversed,
                ..f
            }),
        ),
        m(
            "specular-exponent",
            "a specular exponent other than the scene's n, by a factor fitted to the image: 2n, n/2, or n/4 (Phong's exponent kept where Blinn's term takes four times it)",
            Change::SpecularExponent(2.0),
        ),
        m(
            "reflection-wrong-sign",
            "the reflected ray R = v - 2 (E.N) N instead of v + 2 (E.N) N",
            with(|f| Formulas {
                reflect: reflection_wrong_sign,
                ..f
            }),
        ),
        m(
            "far-root",
            "spheres, tubes, cylinders, cones and tori, plain or transformed, met at their last root: seen from inside",
            with(|f| Formulas { closest: far_root, ..f }),
        ),
        m(
            "near-root-only",
            "spheres, tubes, cylinders, cones and tori, plain or transformed, met at their first root only, none when behind: no way out of glass",
            with(|f| Formulas {
                closest: near_root_only,
                ..f
            }),
        ),
        m(
            "sphere-normal-unnormalised",
            "a sphere's normal left as P - C, of length r, not divided by the radius",
            with(|f| Formulas {
                closest: sphere_normal_unnormalised,
                ..f
            }),
        ),
        m(
            "smooth-normal-length",
            "a smooth triangle's interpolated normal made unit where its length is kept (SIMRenderer's btriangle), or kept where it is made unit",
            with(|f| Formulas {
                closest: smooth_normal_other_length,
                ..f
            }),
        ),
        m(
            "smooth-face-normal",
            "a smooth triangle (btriangle) shaded with its face's normal, its vertex normals ignored",
            with(|f| Formulas {
                closest: smooth_face_normal,
                ..f
            }),
        ),
        m(
            "light-direction-reversed",
            "L taken from the light to the point instead of towards the light",
            with(|f| Formulas {
                light_direction: reversed_direction,
                ..f
            }),
        ),
        m(
            "specular-facing-away",
            "a light's share computed where N.L <= 0: max(N.L, 0) zeroes the diffuse term, not the specular one",
            with(|f| Formulas {
                faces_away: never_faces_away,
                ..f
            }),
        ),
        m(
            "inverted-refraction-index",
            "the law of refraction given n2 / n1 instead of n1 / n2",
            with(|f| Formulas {
                eta: inverted_index,
                ..f
            }),
        ),
        m(
            "exit-index-not-inverted",
            "the ratio 1 / n used leaving glass too, where the law takes n: the ray bends as if entering",
            with(|f| Formulas {
                eta: exit_index_not_inverted,
                ..f
            }),
        ),
        m(
            "refraction-normal-not-flipped",
            "the outward normal given to the law of refraction as a ray leaves glass: it turns back inside",
            with(|f| Formulas {
                refraction_normal: outward_refraction_normal,
                ..f
            }),
        ),
        m(
            "refraction-cosine-sign",
            "the law of refraction with E.N taken as v.N in its term n (E.N) N",
            with(|f| Formulas {
                refract: refraction_cosine_sign,
                ..f
            }),
        ),
        m(
            "no-total-internal-reflection",
            "no total internal reflection: the refracted ray always traced",
            with(|f| Formulas {
                refract: refract_always,
                ..f
            }),
        ),
        m(
            "transparent-black-shadows",
            "transparent objects cast black shadows (shadow filter opaque)",
            with(|f| Formulas {
                transparent_filter: black_filter,
                ..f
            }),
        ),
        m(
            "filter-counted-twice",
            "a transparent object's filter counted at each surface crossed (S^2 for a sphere)",
            with(|f| Formulas {
                transparent_filter: filter_twice,
                ..f
            }),
        ),
        m(
            "shadow-ray-past-the-light",
            "shadow rays not stopped at a point light's distance: objects beyond it cast shadows",
            with(|f| Formulas {
                shadow_reach: past_the_light,
                ..f
            }),
        ),
        m(
            "shadow-acne",
            "shadow rays start on the surface with no offset (shadow acne)",
            with(|f| Formulas {
                shadow_origin: no_offset,
                ..f
            }),
        ),
        m(
            "ambient-dropped-in-shadow",
            "no ambient term where every shadow ray is blocked",
            with(|f| Formulas {
                ambient: ambient_lit_only,
                ..f
            }),
        ),
        m(
            "attenuation-on-ambient",
            "the ambient term multiplied by the light's attenuation A",
            with(|f| Formulas {
                ambient: ambient_attenuated,
                ..f
            }),
        ),
        m(
            "clamp-per-light",
            "each light's share clamped to [0, 1] instead of the pixel at output",
            with(|f| Formulas {
                light_share: clamp_each,
                ..f
            }),
        ),
        m(
            "spot-cosine-falloff",
            "a spotlight falling off as C_max (o.d) instead of the chapter's linear C_theta",
            with(|f| Formulas {
                spot_factor: cosine_spot,
                ..f
            }),
        ),
        m(
            "depth-one-short",
            "secondary rays stopped one level early: depth - 1 levels traced",
            Change::Depth(-1),
        ),
        m(
            "depth-one-over",
            "one level more than the scene's depth traced: depth + 1 levels",
            Change::Depth(1),
        ),
        m(
            "gamma-applied",
            "the sRGB transfer (gamma) applied before quantisation",
            Change::Gamma,
        ),
        m(
            "image-flipped-vertically",
            "the image upside down (row 0 at the bottom)",
            Change::FlipVertical,
        ),
        m(
            "image-flipped-horizontally",
            "the image mirrored left-right (column 0 at the right): the camera's horizontal axis reversed, up x forward for forward x up",
            Change::FlipHorizontal,
        ),
        m(
            "red-blue-swapped",
            "red and blue exchanged: colours written in BGR order (a Java int packed as 0xBBGGRR, or bytes written B, G, R)",
            Change::SwapRedBlue,
        ),
        m(
            "sample-position",
            "camera rays through the pixel's top-left corner (SIMRenderer's sample_position)",
            Change::Convention("sample_position"),
        ),
        m(
            "ray-origin",
            "camera rays from the near plane (SIMRenderer's ray_origin)",
            Change::Convention("ray_origin"),
        ),
        m(
            "far-plane",
            "nothing seen beyond the far plane at 100 (SIMRenderer's far)",
            Change::Convention("far"),
        ),
        m(
            "shadow-filter-kt",
            "shadows filtered by k_t S instead of S (SIMRenderer's shadow_filter)",
            Change::Convention("shadow_filter"),
        ),
        m(
            "transmission-kt-color",
            "refracted rays weighed by k_t S entering (SIMRenderer's transmission)",
            Change::Convention("transmission"),
        ),
        m(
            "closed-only-refract",
            "only closed shapes refract (SIMRenderer's refracting)",
            Change::Convention("refracting"),
        ),
        m(
            "internal-reflection-dropped",
            "the refracted energy lost on total internal reflection (SIMRenderer's total_internal_reflection)",
            Change::Convention("total_internal_reflection"),
        ),
        m(
            "highlight-in-material-colour",
            "highlights in the material's colour, m = 1 by default (SIMRenderer's default_highlight)",
            Change::Convention("default_highlight"),
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose::render_mistake;
    use crate::math::reflect;

    /// The `width x height` image (row-major) a post-process makes of `image`.
    fn post_processed(change: Change, image: &[DVec3], width: u32, height: u32) -> Vec<DVec3> {
        (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|p| {
                let (x, y) = change.source_pixel(p, width, height);
                change.written_colour(image[(y * width + x) as usize])
            })
            .collect()
    }

    #[test]
    fn post_processes_by_hand() {
        // A 3 x 2 image, each pixel's colour its own: (1, 2, 3) at the top left, (4, 5, 6)
        // beside it, ..., (16, 17, 18) at the bottom right.
        let px = |k: u32| DVec3::new((3 * k + 1) as f64, (3 * k + 2) as f64, (3 * k + 3) as f64);
        let image: Vec<DVec3> = (0..6).map(px).collect();
        // Upside down: the bottom row (pixels 3, 4, 5) on top.
        assert_eq!(
            post_processed(Change::FlipVertical, &image, 3, 2),
            [3, 4, 5, 0, 1, 2].map(px)
        );
        // Mirrored: each row read from the right.
        assert_eq!(
            post_processed(Change::FlipHorizontal, &image, 3, 2),
            [2, 1, 0, 5, 4, 3].map(px)
        );
        // Red and blue exchanged in place, green kept.
        let swapped = post_processed(Change::SwapRedBlue, &image, 3, 2);
        assert_eq!(swapped[0], DVec3::new(3.0, 2.0, 1.0));
        assert_eq!(swapped[5], DVec3::new(18.0, 17.0, 16.0));
        assert_eq!(post_processed(Change::SwapRedBlue, &swapped, 3, 2), image);
        // The other changes move and recolour nothing.
        assert_eq!(post_processed(Change::Gamma, &image, 3, 2), image);
    }

    #[test]
    fn wrong_formulas_by_hand() {
        // v = (1, -1, 0) / sqrt 2 onto the floor N = +z... here N = +y: E.N = 1/sqrt 2.
        let v = DVec3::new(1.0, -1.0, 0.0).normalize();
        let n = DVec3::Y;
        assert!((reflect(v, n) - DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-15);
        // v - 2 (E.N) N = (0.7071, -0.7071 - 1.4142, 0): goes on into the surface.
        let wrong = reflection_wrong_sign(v, n);
        assert!((wrong - DVec3::new(0.5f64.sqrt(), -3.0 * 0.5f64.sqrt(), 0.0)).length() < 1e-15);
        // N = L = E = z: |L + E| = 2, so the unnormalised cosine is 2 and 2^20 = 1048576.
        let z = DVec3::Z;
        assert_eq!(unnormalised_half_vector(Specular::Blinn, z, z, z, 20.0), 1_048_576.0);
        assert_eq!(phong_for_blinn(Specular::Blinn, z, z, z, 20.0), 1.0);
        // Glass of n = 1.5 entered: 1 / 1.5 becomes 1.5.
        let glass = Material {
            ior: 1.5,
            ..Material::default()
        };
        assert_eq!(inverted_index(&glass, true), 1.5);
        // Leaving it, the law takes 1.5; the exit not inverted keeps 1 / 1.5. At 30 degrees
        // from the normal the refracted ray's sine is 1.5 x 0.5 = 0.75 by the law, 0.5 / 1.5
        // = 1/3 with the mistake.
        assert_eq!(exit_index_not_inverted(&glass, false), 1.0 / 1.5);
        assert_eq!(exit_index_not_inverted(&glass, true), glass.eta(true));
        let thirty = DVec3::new(0.5, -0.75f64.sqrt(), 0.0);
        let sine = |eta: f64| refract(thirty, n, eta).unwrap().normalize().x;
        assert!((sine(glass.eta(false)) - 0.75).abs() < 1e-15);
        assert!((sine(exit_index_not_inverted(&glass, false)) - 1.0 / 3.0).abs() < 1e-15);
        // The same ray given the outward normal -y: T = 1.5 v + (1.5 (-0.8660) - 0.6614)(-y)
        // = (0.75, +0.6614, 0), the law's ray (0.75, -0.6614, 0) mirrored back inside.
        let outward = outward_refraction_normal(n, -n);
        assert_eq!(outward, -n);
        let back = refract(thirty, outward, 1.5).unwrap();
        assert!(
            (back - DVec3::new(0.75, 0.4375f64.sqrt(), 0.0)).length() < 1e-15,
            "{back}"
        );
        assert!((refract(thirty, n, 1.5).unwrap() - DVec3::new(0.75, -0.4375f64.sqrt(), 0.0)).length() < 1e-15);
        // Past the critical angle (eta 1.5, 60 degrees: 1 - 2.25 * 0.75 = -0.6875) the
        // chapter's law has no ray, this one has.
        let grazing = DVec3::new(60f64.to_radians().sin(), -60f64.to_radians().cos(), 0.0);
        assert!(refract(grazing, n, 1.5).is_none());
        assert!(refract_always(grazing, n, 1.5).is_some());
        assert_eq!(refraction_cosine_sign(grazing, n, 1.5), None);
        // At n = 1 the chapter's ray goes on as v = (sin 60, -cos 60, 0); with v.N for E.N
        // it gains -2 cos 60 N: (0.8660, -1.5, 0).
        assert!((refract(grazing, n, 1.0).unwrap() - grazing).length() < 1e-15);
        let turned = refraction_cosine_sign(grazing, n, 1.0).unwrap();
        assert!(
            (turned - DVec3::new(0.75f64.sqrt(), -1.5, 0.0)).length() < 1e-15,
            "{turned}"
        );
        let s = DVec3::new(0.5, 0.25, 1.0);
        assert_eq!(filter_twice(ShadowFilter::Color, 0.7, s), DVec3::new(0.25, 0.0625, 1.0));
        assert_eq!(cosine_spot(0.9, 0.8, 0.0, 1.0), 0.9);
        assert_eq!(cosine_spot(0.7, 0.8, 0.0, 1.0), 0.0);
        assert_eq!(clamp_each(DVec3::new(1.5, -0.0, 0.25)), DVec3::new(1.0, 0.0, 0.25));
    }

    #[test]
    fn eye_reversed_and_past_the_light_by_hand() {
        // N = z, L = (1, 0, 1) / sqrt 2, E = (-1, 0, 1) / sqrt 2: the mirror position, where
        // H = N and R = E (both terms 1). With -E, L - E = (sqrt 2, 0, 0) is perpendicular
        // to N and R.(-E) = -1: both terms 0.
        let (n, l, e) = (
            DVec3::Z,
            DVec3::new(1.0, 0.0, 1.0).normalize(),
            DVec3::new(-1.0, 0.0, 1.0).normalize(),
        );
        for model in [Specular::Blinn, Specular::Phong] {
            assert!((specular_term(model, n, l, e, 20.0) - 1.0).abs() < 1e-12, "{model:?}");
            assert_eq!(eye_reversed(model, n, l, e, 20.0), 0.0, "{model:?}");
        }
        assert_eq!(past_the_light(5.0), f64::INFINITY);
    }

    #[test]
    fn specular_facing_away_by_hand() {
        // An open plane z = 0 seen from the eye at (0, -3, 4), lit from behind by a point
        // light of colour 2 at (0, 12, -5); k_s = 0.5, m = 0.25, S = (0.5, 0.25, 1), n = 4.
        // At P = 0: N = z (the eye's side), E = (0, -3, 4) / 5, L = (0, 12, -5) / 13, so
        // N.L = -5/13: the chapter counts nothing. The mistake's shadow ray meets nothing
        // below the plane, max(N.L, 0) = 0 leaves no diffuse term, and the specular share is
        // L k_s [m S + (1 - m)] spec = 1 x (0.875, 0.8125, 1) x spec, with
        // - Blinn: L + E = (0, 21, 27) / 65, N.H = 27 / sqrt(1170), spec = (729 / 1170)^2;
        // - Phong: R = 2 (N.L) N - L = (0, -12, -5) / 13, R.E = (36 - 20) / 65 = 16/65,
        //   spec = (16/65)^4.
        // Blinn's share is (0.340, 0.315, 0.388), 99 levels of 255 in blue; Phong's at most
        // 0.0037, under one level.
        use crate::shading::diffuse;
        use crate::trace::{Reference, SampleKey};
        let scene = |specular: &str| {
            crate::scene::parse(
                &format!(
                    r#"
[image]
width = 8
height = 6

[camera]
position = [0, -3, 4]
look_at = [0, 0, 0]
up = [0, 0, 1]

[render]
specular = "{specular}"

[materials.shiny]
color = [0.5, 0.25, 1]
ka = 0
kd = 0.8
ks = 0.5
shininess = 4
m = 0.25

[[shapes]]
type = "plane"
point = [0, 0, 0]
normal = [0, 0, 1]
material = "shiny"

[[lights]]
type = "point"
position = [0, 12, -5]
color = [2, 2, 2]
"#
                ),
                "behind.toml",
            )
            .unwrap()
        };
        let list = catalogue();
        let Change::Formulas(wrong) = list.iter().find(|m| m.name == "specular-facing-away").unwrap().change else {
            panic!("specular-facing-away is a formula");
        };
        let ray = Ray::new(DVec3::new(0.0, -3.0, 4.0), DVec3::new(0.0, 3.0, -4.0).normalize());
        let tint = DVec3::new(0.875, 0.8125, 1.0);
        for (specular, spec) in [
            ("blinn", (729.0f64 / 1170.0).powi(2)),
            ("phong", (16.0f64 / 65.0).powi(4)),
        ] {
            let scene = scene(specular);
            let world = World::new(&scene);
            assert_eq!(Reference::new(&world).camera(&ray, SampleKey::default()), DVec3::ZERO);
            let seen = Reference::with_formulas(&world, wrong).camera(&ray, SampleKey::default());
            assert!(
                (seen - tint * spec).length() < 1e-15,
                "{specular}: {seen} {}",
                tint * spec
            );
        }
        // The diffuse term at N.L = -5/13 is 0, not negative: L k_d S max(N.L, 0).
        assert_eq!(
            diffuse(DVec3::splat(2.0), 0.8, DVec3::new(0.5, 0.25, 1.0), -5.0 / 13.0),
            DVec3::ZERO
        );
        let chapter = Formulas::CHAPTER.faces_away;
        assert!(chapter(-5.0 / 13.0) && chapter(0.0) && !chapter(1e-300));
        assert!(!never_faces_away(-5.0 / 13.0));
    }

    /// A scene of `shapes` (TOML `[[shapes]]` tables) with a camera at z = -5, for the
    /// hand tests of the closest-hit entries.
    fn scene_of(shapes: &str) -> crate::scene::Scene {
        let header = "[image]\nwidth = 8\nheight = 6\n\n[camera]\nposition = [0, 0, -5]\n\
                      look_at = [0, 0, 0]\nup = [0, 1, 0]\nvfov = 40\n";
        crate::scene::parse(&format!("{header}{shapes}"), "shapes.toml").unwrap()
    }

    #[test]
    fn sphere_roots_by_hand() {
        // A unit sphere at the origin behind a plane z = 3 facing it.
        let scene = scene_of(
            r#"
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1

[[shapes]]
type = "plane"
point = [0, 0, 3]
normal = [0, 0, -1]
"#,
        );
        let world = World::new(&scene);
        let hit = |closest: fn(&World<'_>, &Ray, f64) -> Option<(usize, SurfaceHit)>, o: [f64; 3], t_max: f64| {
            closest(&world, &Ray::new(DVec3::from(o), DVec3::Z), t_max).map(|(j, h)| (j, h.t, h.normal))
        };
        let chapter = Formulas::CHAPTER.closest;
        // From z = -5 along +z: the roots are t = 4 and 6 (z = -1 and z = 1).
        assert_eq!(hit(chapter, [0.0, 0.0, -5.0], f64::INFINITY), Some((0, 4.0, -DVec3::Z)));
        assert_eq!(hit(far_root, [0.0, 0.0, -5.0], f64::INFINITY), Some((0, 6.0, DVec3::Z)));
        assert_eq!(
            hit(near_root_only, [0.0, 0.0, -5.0], f64::INFINITY),
            Some((0, 4.0, -DVec3::Z))
        );
        // The far root beyond t_max: the plane is not reached either.
        assert_eq!(hit(far_root, [0.0, 0.0, -5.0], 5.0), None);
        // From the centre (inside, as a refracted ray): the roots are -1 and 1; the chapter
        // and the far root leave at t = 1, the near root only finds the plane at t = 3.
        assert_eq!(hit(chapter, [0.0; 3], f64::INFINITY), Some((0, 1.0, DVec3::Z)));
        assert_eq!(hit(far_root, [0.0; 3], f64::INFINITY), Some((0, 1.0, DVec3::Z)));
        assert_eq!(hit(near_root_only, [0.0; 3], f64::INFINITY), Some((1, 3.0, -DVec3::Z)));
    }

    #[test]
    fn torus_cylinder_and_ellipsoid_roots_by_hand() {
        // A torus about z (major radius 2, minor 0.5) at the origin, a capped cylinder
        // (radius 1, z from 10 to 12) on the axis x = 10, and an ellipsoid (a unit sphere
        // scaled by 2 along x: semi-axes 2, 1, 1) centred at (0, 20, 0).
        let scene = scene_of(
            r#"
[[shapes]]
type = "torus"
center = [0, 0, 0]
axis = [0, 0, 1]
major_radius = 2
minor_radius = 0.5

[[shapes]]
type = "cylinder"
base = [10, 0, 10]
axis = [0, 0, 1]
height = 2
radius = 1

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
transform = { scale = [2, 1, 1], translation = [0, 20, 0] }
"#,
        );
        let world = World::new(&scene);
        let t = |closest: fn(&World<'_>, &Ray, f64) -> Option<(usize, SurfaceHit)>, o: [f64; 3], d: DVec3| {
            closest(&world, &Ray::new(DVec3::from(o), d), f64::INFINITY).map(|(j, h)| (j, h.t))
        };
        let chapter = Formulas::CHAPTER.closest;
        let close =
            |a: Option<(usize, f64)>, b: (usize, f64)| a.is_some_and(|(j, t)| j == b.0 && (t - b.1).abs() < 1e-9);
        // Along x from x = -5 the torus is met at x = -2.5, -1.5, 1.5 and 2.5.
        assert!(close(t(chapter, [-5.0, 0.0, 0.0], DVec3::X), (0, 2.5)));
        assert!(close(t(far_root, [-5.0, 0.0, 0.0], DVec3::X), (0, 7.5)));
        assert!(close(t(near_root_only, [-5.0, 0.0, 0.0], DVec3::X), (0, 2.5)));
        // From the centre the line's first root is behind (x = -2.5): the torus is missed.
        assert!(close(t(chapter, [0.0; 3], DVec3::X), (0, 1.5)));
        assert!(close(t(far_root, [0.0; 3], DVec3::X), (0, 2.5)));
        assert_eq!(t(near_root_only, [0.0; 3], DVec3::X), None);
        // Up the cylinder's axis from z = 5: the bottom cap at t = 5, the top cap at t = 7.
        assert!(close(t(chapter, [10.0, 0.0, 5.0], DVec3::Z), (1, 5.0)));
        assert!(close(t(far_root, [10.0, 0.0, 5.0], DVec3::Z), (1, 7.0)));
        // Along x from x = -5 the ellipsoid is met at x = -2 and x = 2: t = 3 and 7; from
        // its centre the line's first root is behind (t = -2), so near-root-only misses it.
        assert_eq!(t(chapter, [-5.0, 20.0, 0.0], DVec3::X), Some((2, 3.0)));
        assert_eq!(t(far_root, [-5.0, 20.0, 0.0], DVec3::X), Some((2, 7.0)));
        assert_eq!(t(near_root_only, [-5.0, 20.0, 0.0], DVec3::X), Some((2, 3.0)));
        assert_eq!(t(chapter, [0.0, 20.0, 0.0], DVec3::X), Some((2, 2.0)));
        assert_eq!(t(far_root, [0.0, 20.0, 0.0], DVec3::X), Some((2, 2.0)));
        assert_eq!(t(near_root_only, [0.0, 20.0, 0.0], DVec3::X), None);
    }

    #[test]
    fn depth_off_by_one_by_hand() {
        // The eye at z = -5 looks at a perfect mirror (k_r = 1, nothing else) at z = 1; the
        // reflected rays meet a wall at z = -10 lit by the ambient light alone, k_a = 1,
        // S = 0.4. At depth 2 every pixel is 1 x 0.4 -> level 102; one level short (depth 1)
        // the mirror shows its own black; one level over, the wall reflects nothing more.
        let scene = |depth: u32| {
            scene_of(&format!(
                r#"
[render]
depth = {depth}

[materials.mirror]
color = [1, 1, 1]
ka = 0
kd = 0
ks = 0
kr = 1

[materials.wall]
color = [0.4, 0.4, 0.4]
ka = 1
kd = 0
ks = 0

[[shapes]]
type = "plane"
point = [0, 0, 1]
normal = [0, 0, -1]
material = "mirror"

[[shapes]]
type = "plane"
point = [0, 0, -10]
normal = [0, 0, 1]
material = "wall"

[[lights]]
type = "ambient"
"#
            ))
        };
        let list = catalogue();
        let named = |name: &str| *list.iter().find(|m| m.name == name).unwrap();
        let (short, over) = (named("depth-one-short"), named("depth-one-over"));
        let pixels = 8 * 6 * 3;
        assert_eq!(render_mistake(&scene(2), &short), Some(vec![0; pixels]));
        assert_eq!(render_mistake(&scene(2), &over), Some(vec![102; pixels]));
        // Out of [1, 64] the mistake does not apply.
        assert_eq!(render_mistake(&scene(1), &short), None);
        assert_eq!(render_mistake(&scene(64), &over), None);
        assert_eq!(render_mistake(&scene(1), &over), Some(vec![102; pixels]));
    }

    #[test]
    fn unnormalised_sphere_normal_by_hand() {
        // A sphere of radius 2 at the origin and a cylinder: from z = -5 along +z the sphere
        // is met at t = 3, its normal (0, 0, -1) left as P - C = (0, 0, -2); the cylinder's
        // is left alone.
        let scene = scene_of(
            r#"
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 2

[[shapes]]
type = "cylinder"
base = [10, 0, 10]
axis = [0, 0, 1]
height = 2
radius = 3
"#,
        );
        let world = World::new(&scene);
        let ray = Ray::new(DVec3::new(0.0, 0.0, -5.0), DVec3::Z);
        let (j, h) = sphere_normal_unnormalised(&world, &ray, f64::INFINITY).unwrap();
        assert_eq!((j, h.t, h.normal), (0, 3.0, DVec3::new(0.0, 0.0, -2.0)));
        let up = Ray::new(DVec3::new(10.0, 0.0, 5.0), DVec3::Z);
        let (j, h) = sphere_normal_unnormalised(&world, &up, f64::INFINITY).unwrap();
        assert_eq!((j, h.t, h.normal), (1, 5.0, -DVec3::Z));
    }

    #[test]
    fn exponent_scaled_by_hand() {
        // N = E = z, L = (0.6, 0, 0.8): L + E = (0.6, 0, 1.8), (N.H)^2 = 3.24 / 3.6 = 0.9, so
        // Blinn's term at n = 20 is 0.9^10, and at twice the exponent 0.9^20. Phong's
        // R = 2 (N.L) N - L = (-0.6, 0, 0.8), R.E = 0.8: at half the exponent, 0.8^10.
        use crate::trace::formulas::FormulaTable;
        let (n, l, e) = (DVec3::Z, DVec3::new(0.6, 0.0, 0.8), DVec3::Z);
        let chapter = Formulas::CHAPTER;
        assert!((chapter.specular(Specular::Blinn, n, l, e, 20.0) - 0.9f64.powi(10)).abs() < 1e-14);
        let doubled = exponent_scaled(2.0).specular(Specular::Blinn, n, l, e, 20.0);
        assert!((doubled - 0.9f64.powi(20)).abs() < 1e-14, "{doubled}");
        let halved = exponent_scaled(0.5).specular(Specular::Phong, n, l, e, 20.0);
        assert!((halved - 0.8f64.powi(10)).abs() < 1e-14, "{halved}");
        // The chapter's scale leaves the term's bits as they are.
        assert_eq!(
            chapter.specular(Specular::Blinn, n, l, e, 20.0).to_bits(),
            specular_term(Specular::Blinn, n, l, e, 20.0).to_bits()
        );
    }

    #[test]
    fn exponents_shown_by_hand() {
        // Materials: a highlight of n = 20 on two shapes, n = 100 on one, n = 50 without k_s,
        // and n = 8 on no shape. The exponents shown are 20 and 100; none when the model has
        // no specular term.
        let shapes = r#"
[materials.twenty]
ks = 0.5
shininess = 20

[materials.matte]
ks = 0
shininess = 50

[materials.unused]
ks = 0.5
shininess = 8

[materials.hundred]
ks = 0.3
shininess = 100

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "twenty"

[[shapes]]
type = "sphere"
center = [3, 0, 0]
radius = 1
material = "hundred"

[[shapes]]
type = "sphere"
center = [-3, 0, 0]
radius = 1
material = "matte"

[[shapes]]
type = "sphere"
center = [0, 3, 0]
radius = 1
material = "twenty"
"#;
        assert_eq!(shown_exponents(&scene_of(shapes)), [20.0, 100.0]);
        let off = format!("[render]\nspecular = \"none\"\n{shapes}");
        assert_eq!(shown_exponents(&scene_of(&off)), [] as [f64; 0]);
    }

    #[test]
    fn catalogue_has_every_convention_difference_and_unique_names() {
        let list = catalogue();
        assert!(list.len() >= 15);
        let mut names: Vec<_> = list.iter().map(|m| m.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), list.len());
        for (key, chapter) in Conventions::CHAPTER.describe() {
            let differs = Conventions::SIMRENDERER
                .describe()
                .iter()
                .any(|(k, v)| *k == key && *v != chapter);
            let listed = list
                .iter()
                .any(|m| matches!(m.change, Change::Convention(k) if k == key));
            assert_eq!(differs, listed, "{key}");
        }
    }
}
