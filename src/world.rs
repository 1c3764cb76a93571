//! A scene ready to render: the camera for the image's aspect, the intersection core, the
//! points of fixed area lights, and the per-scene bounds the tracer needs at every hit. The
//! tracer asks it for closest hits and shadow-ray hits ([`World::closest`],
//! [`World::any_hit`], [`World::each_hit`], and in a linearly scanned world both shadow
//! questions at once, [`World::shadow_scan`]) rather than reaching into the core. `along`
//! holds the objects' balls as each directional light's shadow rays see them.

use crate::accel::{Accel, AccelChoice};
use crate::area_light::{PointMode, PointSet};
use crate::camera::Camera;
use crate::caustics::{self, PhotonMap};
use crate::light::Light;
use crate::material::Material;
use crate::math::{Ray, other_leg};
use crate::scene::{Object, SampleGrid, Scene};
use crate::shading::transparent_filter;
use crate::shape::{Shape, SurfaceHit, misses_bounding_sphere};
use crate::skips::{Skip, Skips};
use along::BallsAlong;
use glam::DVec3;
use std::borrow::Cow;

mod along;

/// An object that may block some shadow ray from one shading point (see
/// [`World::shadow_candidates`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate {
    pub object: usize,
    /// The cone of directions from the shading point that meet the object's bounding
    /// sphere: unit axis and cosine of its half-angle (a ray whose direction `d` has
    /// `d.axis < cos` misses the object). `None` for unbounded objects and when the point
    /// is inside the sphere.
    pub cone: Option<(DVec3, f64)>,
    /// The cone of directions from the shading point that surely pass through a ball
    /// inside the object, and the distance past which that ball is wholly behind the point:
    /// unit axis, cosine of the half-angle (narrowed by a relative 1e-9), and reach. A ray
    /// whose direction `d` has `d.axis > cos` and whose segment is longer than the reach
    /// enters the object: it surely meets its surface. `None` when the object has no inner
    /// ball or the point may be inside the object.
    pub sure: Option<(DVec3, f64, f64)>,
}

/// The cone of directions from `p` meeting the ball (`center`, `radius`), widened by a
/// relative 1e-9 so rounding never excludes a direction that meets it; `None` if `p` is
/// (nearly) inside the ball.
pub(crate) fn direction_cone(p: DVec3, center: DVec3, radius: f64) -> Option<(DVec3, f64)> {
    let to_center = center - p;
    let dist = to_center.length();
    let padded = radius * (1.0 + 1e-9) + 1e-9 * dist;
    if padded >= dist {
        return None;
    }
    let sin = padded / dist;
    Some((to_center / dist, (1.0 - sin * sin).sqrt() - 1e-12))
}

/// Whether two cones of directions (unit axis, cosine of the half-angle, as
/// [`direction_cone`] gives them) share no direction: the angle between their axes exceeds
/// the sum of their half-angles, `a.b < cos(alpha + beta) = cos a cos b - sin a sin b`, by
/// a margin of 1e-9 far above the rounding of a unit direction's dot product. Only for
/// half-angles below 90 degrees (else `false`).
pub(crate) fn cones_apart((a, cos_a): (DVec3, f64), (b, cos_b): (DVec3, f64)) -> bool {
    if cos_a <= 0.0 || cos_b <= 0.0 {
        return false;
    }
    let (sin_a, sin_b) = (other_leg(cos_a), other_leg(cos_b));
    a.dot(b) < cos_a * cos_b - sin_a * sin_b - 1e-9
}

/// The cone of directions from `p` that pass through the ball (`center`, `radius`), shrunk
/// by a relative 1e-9 (and `slack`) so rounding never includes a direction that misses it,
/// with the reach `|center - p| + radius`; `None` when nothing is left after shrinking.
fn sure_cone(p: DVec3, center: DVec3, radius: f64, slack: f64) -> Option<(DVec3, f64, f64)> {
    let to_center = center - p;
    let dist = to_center.length();
    let shrunk = radius * (1.0 - 1e-9) - 1e-9 * dist - slack;
    if shrunk <= 0.0 || shrunk >= dist {
        return None;
    }
    let sin = shrunk / dist;
    let reach = (dist + radius) * (1.0 + 1e-9) + slack;
    Some((to_center / dist, (1.0 - sin * sin).sqrt() + 1e-12, reach))
}

/// A scene ready to render: the camera for the image's aspect, the acceleration structure,
/// and per-scene constants the tracer needs at every hit.
pub struct World<'s> {
    pub scene: &'s Scene,
    pub camera: Camera,
    /// The intersection core; queried through [`World::closest`], [`World::any_hit`] and
    /// [`World::each_hit`].
    accel: Accel,
    /// Wall time of building `accel`, in seconds.
    pub accel_seconds: f64,
    /// Sum of the ambient lights' colours `L_a`.
    pub ambient: DVec3,
    /// The cells of a pixel its samples are placed in
    /// ([`Settings::sample_grid`](crate::scene::Settings::sample_grid)), made
    /// once for the render rather than for each pixel.
    pub sample_grid: SampleGrid,
    /// Whether any object is transparent (else shadow rays need no filtered walk).
    pub has_transparent: bool,
    /// Whether any material has images (else no hit needs texture coordinates).
    pub has_textures: bool,
    /// `remaining_bound[level]`: the most (largest channel) a ray traced at `level` can
    /// return, counting every level it may still recurse to; used by adaptive depth control.
    pub remaining_bound: Vec<f64>,
    /// For each light, the points of a `fixed` area light (empty for other lights).
    pub light_points: Vec<PointSet>,
    /// Bounding sphere (center, radius) of each object; `None` for unbounded ones. Built only
    /// for a scene that reads it: one with an area light ([`World::shadow_candidates`]) or a
    /// costly object (the sphere test before its exact test); empty otherwise.
    pub bounding_spheres: Vec<Option<(DVec3, f64)>>,
    /// A ball inside each object's solid ([`Shape::inner_ball`]); built only for a scene
    /// with an area light, empty otherwise.
    pub inner_balls: Vec<Option<(DVec3, f64)>>,
    /// Whether an object's exact test costs more than a ray-sphere test (boxes, cylinders,
    /// cones, tori), so a bounding-sphere test first pays off.
    pub costly: Vec<bool>,
    /// The shortcuts switched on (all by default; tests switch them off one at a time).
    pub skips: Skips,
    /// The caustic photons, when the scene has a `[caustics]` table.
    pub photons: Option<PhotonMap>,
    /// Wall time of tracing the photons and building their map, in seconds.
    pub photon_seconds: f64,
    /// Per object, whether it lets shadow rays through, filtering them by its colour
    /// ([`World::filters_shadows`]).
    see_through: Vec<bool>,
    /// For a world scanned linearly, the objects that block shadow rays with their
    /// `shadow_balls`, in object order: the first scan of [`World::shadow_scan`].
    opaque_balls: Vec<(usize, (DVec3, f64))>,
    /// Likewise the objects that filter shadow rays ([`World::filters_shadows`]): its second
    /// scan.
    see_through_balls: Vec<(usize, (DVec3, f64))>,
    /// For a world scanned linearly, the two lists' balls seen along each directional
    /// light's shadow rays ([`BallsAlong`]), for [`World::shadow_scan`].
    balls_along: Vec<BallsAlong>,
    /// For a world scanned linearly, per object the cone of directions from the camera's
    /// eye that meet its bounding sphere ([`direction_cone`]): unit axis and cosine of the
    /// half-angle, a camera ray `d` with `d.axis < cos` misses the object
    /// ([`World::closest_camera`]). For a flat object (whose own test costs a dot product
    /// and a division), an unbounded one, or an eye inside the sphere, the cone of every
    /// direction (cosine `-inf`). Empty for a BVH world, whose boxes cull already.
    eye_cones: Vec<(DVec3, f64)>,
    /// For a world scanned linearly, per object the ball a shadow, reflected or refracted
    /// ray is tested against before the object ([`World::shadow_any_hit`],
    /// [`World::shadow_each_hit`], [`World::closest_secondary`]): its
    /// bounding sphere, or for a flat or unbounded object one of infinite radius (that no
    /// ray misses). Empty for a BVH world.
    shadow_balls: Vec<(DVec3, f64)>,
}

impl<'s> World<'s> {
    /// The world with the acceleration structure `auto` picks.
    pub fn new(scene: &'s Scene) -> Self {
        World::with_accel(scene, AccelChoice::Auto)
    }

    /// The world with the chosen acceleration structure (the image does not depend on it).
    pub fn with_accel(scene: &'s Scene, choice: AccelChoice) -> Self {
        let s = &scene.settings;
        let camera = Camera::new(
            scene.camera.position,
            scene.camera.look_at,
            scene.camera.up,
            scene.camera.vfov_deg,
            s.width as f64 / s.height as f64,
        );
        let ambient = scene.ambient();
        let see_through: Vec<bool> = scene
            .objects
            .iter()
            .map(|o| lets_shadows_through(scene, &scene.materials[o.material()]))
            .collect();
        let has_transparent = see_through.iter().any(|&t| t);
        let costly: Vec<bool> = scene
            .objects
            .iter()
            .map(|o| {
                matches!(
                    o.shape,
                    Shape::Cuboid(_)
                        | Shape::Cylinder(_)
                        | Shape::Cone(_)
                        | Shape::Torus(_)
                        | Shape::Transformed(_)
                        | Shape::SphericalCap(_)
                        | Shape::Lens(_)
                )
            })
            .collect();
        let has_area_light = scene.lights.iter().any(|l| matches!(l, Light::Area(_)));
        let has_textures = scene.materials.iter().any(|m| m.images().is_some());
        let start = std::time::Instant::now();
        let accel = Accel::build_with(&scene.objects, choice);
        let accel_seconds = start.elapsed().as_secs_f64();
        let start = std::time::Instant::now();
        let photons = s.caustics.as_ref().map(|c| caustics::build(scene, &accel, c));
        let photon_seconds = start.elapsed().as_secs_f64();
        let caustic_bound = photons.as_ref().map(PhotonMap::irradiance_bound);
        // A plane's, rectangle's, disk's or triangle's own test is as cheap as a ball's.
        let ball = |o: &Object| {
            let flat = matches!(
                o.shape,
                Shape::Plane(_) | Shape::Rectangle(_) | Shape::Disk(_) | Shape::Triangle(_) | Shape::SmoothTriangle(_)
            );
            o.shape.bounding_sphere().filter(|_| !flat)
        };
        let linear = matches!(accel, Accel::Linear(_));
        let eye_cones = match linear {
            true => scene
                .objects
                .iter()
                .map(|o| {
                    ball(o)
                        .and_then(|(center, radius)| direction_cone(camera.position, center, radius))
                        .unwrap_or((DVec3::ZERO, f64::NEG_INFINITY))
                })
                .collect(),
            false => Vec::new(),
        };
        let shadow_balls = match linear {
            true => scene
                .objects
                .iter()
                .map(|o| ball(o).unwrap_or((DVec3::ZERO, f64::INFINITY)))
                .collect(),
            false => Vec::new(),
        };
        let (see_through_balls, opaque_balls): (Vec<_>, Vec<_>) = shadow_balls
            .iter()
            .enumerate()
            .map(|(i, &ball)| (i, ball))
            .partition(|&(i, _)| see_through[i]);
        let balls_along = scene
            .lights
            .iter()
            .filter_map(|light| match light {
                Light::Directional { .. } if linear => {
                    let to_light = light.incidence(DVec3::ZERO)?.to_light;
                    BallsAlong::new(to_light, &opaque_balls, &see_through_balls)
                }
                _ => None,
            })
            .collect();
        World {
            balls_along,
            opaque_balls,
            see_through_balls,
            eye_cones,
            shadow_balls,
            photons,
            photon_seconds,
            see_through,
            scene,
            camera,
            accel,
            accel_seconds,
            ambient,
            sample_grid: s.sample_grid(),
            has_transparent,
            has_textures,
            remaining_bound: remaining_bounds(scene, ambient, caustic_bound),
            light_points: scene
                .lights
                .iter()
                .enumerate()
                .map(|(i, l)| match l {
                    Light::Area(a) if a.mode == PointMode::Fixed => PointSet::from_points(&a.fixed_points(s.seed, i)),
                    _ => PointSet::default(),
                })
                .collect(),
            bounding_spheres: if has_area_light || costly.contains(&true) {
                scene.objects.iter().map(|o| o.shape.bounding_sphere()).collect()
            } else {
                Vec::new()
            },
            inner_balls: if has_area_light {
                scene.objects.iter().map(|o| o.shape.inner_ball()).collect()
            } else {
                Vec::new()
            },
            costly,
            skips: Skips::all(),
        }
    }

    /// Into `out` (ascending), the objects that may block a segment from `p` (give or take
    /// `slack`) to any point of the ball of center `c` and radius `r`. Every such segment lies
    /// in the hull of `p` and the ball, whose points are `p + s (c - p) + w`, `|w| <= s r`,
    /// `s` in [0, 1]: an object whose bounding sphere is farther than its radius plus `r`
    /// from the segment `[p, c]` cannot block any. Unbounded objects are always kept.
    pub fn shadow_candidates(&self, p: DVec3, c: DVec3, r: f64, slack: f64, out: &mut Vec<Candidate>) {
        out.clear();
        let axis = c - p;
        let len2 = axis.length_squared();
        for (object, sphere) in self.bounding_spheres.iter().enumerate() {
            let Some((center, radius)) = *sphere else {
                out.push(Candidate {
                    object,
                    cone: None,
                    sure: None,
                });
                continue;
            };
            let s = if len2 > 0.0 {
                ((center - p).dot(axis) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            // Padded by a relative 1e-9: a light point is rounded after it is placed, so
            // it may lie a few ulps outside the light's ball.
            let reach = (radius + r) * (1.0 + 1e-9) + slack;
            if (p + s * axis - center).length_squared() <= reach * reach {
                // Outside the bounding sphere, the point is outside the object.
                let outside = (center - p).length() > radius * (1.0 + 1e-9) + slack;
                out.push(Candidate {
                    object,
                    cone: direction_cone(p, center, radius + slack),
                    sure: self.inner_balls[object]
                        .filter(|_| outside)
                        .and_then(|(c, r)| sure_cone(p, c, r, slack)),
                });
            }
        }
    }

    /// [`World::remaining_bound`] of `scene`, without building its world (for a scene with
    /// caustics, whose photons are not traced here, no bound: every ray is traced).
    pub fn remaining_bounds_of(scene: &Scene) -> Vec<f64> {
        remaining_bounds(scene, scene.ambient(), None)
    }

    /// Whether object `object` lets shadow rays through, filtering their light by its
    /// colour (chapter 7.4b): a transparent object (`k_t > 0`), except, when the scene has
    /// caustics, one whose index is not 1. Light bent by such an object arrives as caustic
    /// photons; letting the shadow ray through too would count it twice. An object of index
    /// 1 bends nothing and keeps the chapter's colour filter.
    pub fn filters_shadows(&self, object: usize) -> bool {
        self.see_through[object]
    }

    pub fn material_of(&self, object: usize) -> &Material {
        &self.scene.materials[self.scene.objects[object].material()]
    }

    /// The colour `S_g` a transparent object filters a shadow ray's light by, under the
    /// scene's conventions ([`transparent_filter`]).
    #[inline]
    pub fn filter_color(&self, object: usize) -> DVec3 {
        let mat = self.material_of(object);
        transparent_filter(self.scene.settings.conventions.shadow_filter, mat.kt, mat.color)
    }

    /// The points of area light `index` (an [`AreaLight`](crate::area_light::AreaLight))
    /// for sample `sample` of pixel `pixel`: the scene's one set for a `fixed` light, a
    /// set drawn for the sample for a `per_sample` one.
    pub fn area_points(&self, index: usize, pixel: u64, sample: u32) -> Cow<'_, PointSet> {
        match &self.scene.lights[index] {
            Light::Area(area) if area.mode == PointMode::PerSample => Cow::Owned(PointSet::from_points(
                &area.sample_points(self.scene.settings.seed, index, pixel, sample),
            )),
            _ => Cow::Borrowed(&self.light_points[index]),
        }
    }

    /// The scene's objects, indexed as every query's answers.
    pub fn objects(&self) -> &'s [Object] {
        &self.scene.objects
    }

    /// The intersection core (its name, size and kind, for reports).
    pub fn accel(&self) -> &Accel {
        &self.accel
    }

    /// The closest hit along `ray` (`t > 0`): the object's index and the surface hit; on
    /// equal `t`, the lowest index.
    pub fn closest(&self, ray: &Ray) -> Option<(usize, SurfaceHit)> {
        self.closest_before(ray, f64::INFINITY)
    }

    /// [`World::closest`] among the hits with `t < t_max`.
    pub fn closest_before(&self, ray: &Ray, t_max: f64) -> Option<(usize, SurfaceHit)> {
        self.accel.closest(&self.scene.objects, ray, 0.0, t_max)
    }

    /// [`World::closest_before`] for a camera ray: in a linearly scanned world with the
    /// bounding-sphere shortcut on, for a ray from the eye, an object whose cone of
    /// directions from the eye (`eye_cones`) the ray leaves is not tested. The ray misses its
    /// bounding sphere, so the object too, and the scan's answer (the closest hit, the
    /// lowest index on equal `t`) is the same. A ray from elsewhere (from the image plane, or
    /// any ray a caller traces as a camera ray) is scanned as [`World::closest_secondary`]
    /// scans. Adds the objects not tested to `untested`.
    #[inline(always)]
    pub fn closest_camera(&self, ray: &Ray, t_max: f64, untested: &mut u64) -> Option<(usize, SurfaceHit)> {
        if self.eye_cones.is_empty() || !self.skips.on(Skip::BoundingSpheres) {
            return self.closest_before(ray, t_max);
        }
        if ray.origin != self.camera.position {
            return self.closest_secondary(ray, t_max, untested);
        }
        let objects = &self.scene.objects[..];
        let cones = &self.eye_cones[..objects.len()];
        let mut t_max = t_max;
        let mut best = None;
        for i in 0..objects.len() {
            let (axis, cos) = cones[i];
            if ray.dir.dot(axis) < cos {
                *untested += 1;
                continue;
            }
            if let Some(h) = objects[i].shape.intersect(ray, 0.0, t_max) {
                t_max = h.t;
                best = Some((i, h));
            }
        }
        best
    }

    /// Whether some object that `filter` accepts is hit along `ray` with `0 < t < t_max`.
    pub fn any_hit(&self, ray: &Ray, t_max: f64, filter: &dyn Fn(usize) -> bool) -> bool {
        self.accel.any_hit(&self.scene.objects, ray, 0.0, t_max, filter)
    }

    /// [`World::closest_before`] for a reflected or refracted ray: in a linearly scanned
    /// world with the bounding-sphere skip on, an object whose ball (`shadow_balls`) the ray
    /// misses before the closest hit so far is not tested, as in
    /// [`World::shadow_any_hit`]. The same answer (the closest hit, the lowest index on equal
    /// `t`). Adds the objects not tested to `untested`. The same loop as
    /// [`World::closest_camera`]'s, written out in each: one loop shared through a culling
    /// closure compiles slower (the course figures 1 to 2 % slower on the AMD EPYC).
    #[inline(always)]
    pub fn closest_secondary(&self, ray: &Ray, t_max: f64, untested: &mut u64) -> Option<(usize, SurfaceHit)> {
        if self.shadow_balls.is_empty() || !self.skips.on(Skip::BoundingSpheres) {
            return self.closest_before(ray, t_max);
        }
        let objects = &self.scene.objects[..];
        let balls = &self.shadow_balls[..objects.len()];
        let mut t_max = t_max;
        let mut best = None;
        for i in 0..objects.len() {
            if misses_ball(ray, t_max, balls[i]) {
                *untested += 1;
                continue;
            }
            if let Some(h) = objects[i].shape.intersect(ray, 0.0, t_max) {
                t_max = h.t;
                best = Some((i, h));
            }
        }
        best
    }

    /// [`World::any_hit`] for a shadow ray: in a linearly scanned world with the
    /// bounding-sphere skip on, an object whose ball (`shadow_balls`) the ray misses on
    /// `(0, t_max)` (`misses_bounding_sphere`, padded so that rounding never rejects a hit)
    /// is not tested: it cannot be hit. Adds the objects not tested to `untested`.
    #[inline]
    pub fn shadow_any_hit(&self, ray: &Ray, t_max: f64, filter: impl Fn(usize) -> bool, untested: &mut u64) -> bool {
        if !self.scans_balls() {
            return self.any_hit(ray, t_max, &filter);
        }
        self.scan_balls(ray, t_max, filter, untested, |_| true)
    }

    /// [`World::each_hit`] for a shadow ray, with the objects whose ball the ray misses not
    /// tested as in [`World::shadow_any_hit`] (added to `untested`); in object order.
    #[inline]
    pub fn shadow_each_hit(
        &self,
        ray: &Ray,
        t_max: f64,
        filter: impl Fn(usize) -> bool,
        mut visit: impl FnMut(usize),
        untested: &mut u64,
    ) {
        if !self.scans_balls() {
            return self.each_hit(ray, t_max, &filter, &mut visit);
        }
        self.scan_balls(ray, t_max, filter, untested, |i| {
            visit(i);
            false
        });
    }

    /// The linear scan of a shadow ray over the objects `filter` accepts, in object order,
    /// skipping those whose ball (`shadow_balls`) it misses (added to `untested`): calls
    /// `hit(i)` for each object it meets on `(0, t_max)` until `hit` returns true, and
    /// returns whether it did.
    #[inline(always)]
    fn scan_balls(
        &self,
        ray: &Ray,
        t_max: f64,
        filter: impl Fn(usize) -> bool,
        untested: &mut u64,
        hit: impl FnMut(usize) -> bool,
    ) -> bool {
        let balls = &self.shadow_balls[..self.scene.objects.len()];
        let entries = (0..balls.len()).filter(|&i| filter(i)).map(|i| (i, i));
        self.scan(
            entries,
            ray,
            t_max,
            untested,
            |i| misses_ball(ray, t_max, balls[i]),
            hit,
        )
    }

    /// Both questions the tracer asks of a shadow ray, in one call: whether an opaque object
    /// blocks it on `(0, t_max)` ([`World::shadow_any_hit`] over the opaque objects), and if
    /// not, into `crossed` (ascending) the objects that filter shadows it meets
    /// ([`World::shadow_each_hit`] over those). Each scan visits only its own objects, and
    /// tests an object exactly only where the ray meets its ball: for an unending ray along
    /// a directional light, by the balls seen along the light (`BallsAlong`), else by
    /// `misses_bounding_sphere`. Adds the objects passed by to `untested` (on a blocked
    /// ray, only the opaque ones before the blocker). Only for a world that
    /// [`World::scans_balls`].
    pub fn shadow_scan(&self, ray: &Ray, t_max: f64, crossed: &mut Vec<usize>, untested: &mut u64) -> bool {
        let along = match t_max == f64::INFINITY {
            true => self.balls_along.iter().find(|along| along.l == ray.dir),
            false => None,
        };
        match along {
            Some(along) => {
                let o = along.origin(ray.origin);
                self.scan_lists(ray, t_max, crossed, untested, |through, k| {
                    o.misses(if through {
                        &along.see_through[k]
                    } else {
                        &along.opaque[k]
                    })
                })
            }
            None => self.scan_lists(ray, t_max, crossed, untested, |through, k| {
                let list = if through {
                    &self.see_through_balls
                } else {
                    &self.opaque_balls
                };
                misses_ball(ray, t_max, list[k].1)
            }),
        }
    }

    /// [`World::shadow_scan`]'s two scans, with `missed(see_through, k)` saying whether the
    /// ray passes by the ball of entry `k` of the see-through list, or of the opaque one.
    #[inline(always)]
    fn scan_lists(
        &self,
        ray: &Ray,
        t_max: f64,
        crossed: &mut Vec<usize>,
        untested: &mut u64,
        missed: impl Fn(bool, usize) -> bool,
    ) -> bool {
        let opaque = list_entries(&self.opaque_balls);
        let blocked = self.scan(opaque, ray, t_max, untested, |k| missed(false, k), |_| true);
        blocked
            || self.scan(
                list_entries(&self.see_through_balls),
                ray,
                t_max,
                untested,
                |k| missed(true, k),
                |i| {
                    crossed.push(i);
                    false
                },
            )
    }

    /// The scan of a shadow ray over `entries` `(k, i)` in their order: tests exactly each
    /// object `i` whose ball `k` the ray does not pass by (`missed(k)`, else counted in
    /// `untested`) and calls `hit(i)` for each object it meets on `(0, t_max)`, until `hit`
    /// returns true; returns whether it did.
    #[inline(always)]
    fn scan(
        &self,
        entries: impl Iterator<Item = (usize, usize)>,
        ray: &Ray,
        t_max: f64,
        untested: &mut u64,
        missed: impl Fn(usize) -> bool,
        mut hit: impl FnMut(usize) -> bool,
    ) -> bool {
        let objects = &self.scene.objects[..];
        for (k, i) in entries {
            if missed(k) {
                *untested += 1;
            } else if objects[i].shape.occludes(ray, 0.0, t_max) && hit(i) {
                return true;
            }
        }
        false
    }

    /// Whether shadow rays are scanned with their balls, passing objects by
    /// ([`World::shadow_any_hit`]): a linearly scanned world with the bounding-sphere skip on.
    pub fn scans_balls(&self) -> bool {
        !self.shadow_balls.is_empty() && self.skips.on(Skip::BoundingSpheres)
    }

    /// Calls `visit` once for every object that `filter` accepts and `ray` hits with
    /// `0 < t < t_max`, in no particular order.
    pub fn each_hit(&self, ray: &Ray, t_max: f64, filter: &dyn Fn(usize) -> bool, visit: &mut dyn FnMut(usize)) {
        self.accel.each_hit(&self.scene.objects, ray, 0.0, t_max, filter, visit)
    }
}

/// The entries `(k, i)` of [`World::scan`] for a list of objects `i` with their balls: the
/// ball of entry `k` is the list's.
fn list_entries(list: &[(usize, (DVec3, f64))]) -> impl Iterator<Item = (usize, usize)> + '_ {
    list.iter().enumerate().map(|(k, &(i, _))| (k, i))
}

/// Whether `ray` misses the ball on `(0, t_max)` ([`misses_bounding_sphere`]); never for a
/// ball of infinite radius, which costs one comparison.
#[inline(always)]
fn misses_ball(ray: &Ray, t_max: f64, ball: (DVec3, f64)) -> bool {
    ball.1 != f64::INFINITY && misses_bounding_sphere(ray, 0.0, t_max, ball)
}

/// [`World::filters_shadows`] for an object of material `m` in `scene`.
fn lets_shadows_through(scene: &Scene, m: &Material) -> bool {
    m.is_transparent() && (scene.settings.caustics.is_none() || !m.bends_light())
}

/// Upper bound of what a ray at each level (1-based, index 0 unused) can return: a local
/// bound `B = max(L_a) max(k_a) + sum_i max(L_i) max(k_d + k_s)` (or the background if
/// larger), each `k` the largest its term takes ([`Material::largest_coefficients`]: 1 under
/// an image), plus `K = max(k_r + k_t)` times the bound one level deeper.
/// With caustics, `caustic_bound` bounds the irradiance of the photon map's estimates.
fn remaining_bounds(scene: &Scene, ambient: DVec3, caustic_bound: Option<f64>) -> Vec<f64> {
    let mats = &scene.materials;
    let max_of = |f: &dyn Fn(&Material) -> f64| mats.iter().map(f).fold(0.0, f64::max);
    let direct: f64 = scene
        .lights
        .iter()
        .filter(|l| !matches!(l, Light::Ambient { .. }))
        .map(Light::max_intensity)
        .sum();
    let local = if scene.settings.shading.no_light {
        // The diffuse colour `k_d S` alone.
        max_of(&Material::largest_diffuse)
    } else {
        // Each term's colour is at most 1, its coefficient the largest it takes.
        ambient.max_element() * max_of(&|m| m.largest_coefficients()[0])
            + direct * max_of(&|m| m.largest_coefficients()[1..].iter().sum())
    }
    .max(scene.settings.background.max_element());
    let k = max_of(&|m| m.kr + m.kt);
    let depth = scene.settings.depth as usize;
    let local = match (scene.settings.caustics, caustic_bound) {
        (None, _) => local,
        // The caustic share `E k_d S` is at most the map's bound on `E` times the largest
        // `k_d S`.
        (Some(_), Some(e)) => local + e * max_of(&Material::largest_diffuse),
        // Not known before the photons are traced: adaptive depth control cuts no ray.
        (Some(_), None) => f64::INFINITY,
    };
    let mut bound = vec![0.0; depth + 2];
    for level in (1..=depth).rev() {
        bound[level] = local + k * bound[level + 1];
    }
    bound
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cones_apart_when_the_angle_exceeds_the_half_angles() {
        // Two cones of half-angle 30 degrees: apart when their axes are more than 60
        // degrees apart.
        let half = 30f64.to_radians().cos();
        let axis_at = |deg: f64| DVec3::new(deg.to_radians().sin(), 0.0, deg.to_radians().cos());
        assert!(cones_apart((DVec3::Z, half), (axis_at(60.001), half)));
        assert!(!cones_apart((DVec3::Z, half), (axis_at(59.999), half)));
        assert!(!cones_apart((DVec3::Z, half), (axis_at(60.0), half)));
        assert!(cones_apart((DVec3::Z, half), (-DVec3::Z, half)));
        // Half-angles of 90 degrees or more are never apart.
        assert!(!cones_apart((DVec3::Z, 0.0), (-DVec3::Z, 0.99)));
        // Every direction of one ball's cone misses the other's: a ball of radius 1 at
        // distance 2 (30 degrees) on +z and one on an axis 61 degrees away.
        let p = DVec3::new(0.3, -0.2, 0.1);
        let (a, b) = (p + 2.0 * DVec3::Z, p + 2.0 * axis_at(61.0));
        let (ca, cb) = (direction_cone(p, a, 1.0).unwrap(), direction_cone(p, b, 1.0).unwrap());
        assert!(cones_apart(ca, cb));
        assert!(!cones_apart(
            ca,
            direction_cone(p, p + 2.0 * axis_at(59.0), 1.0).unwrap()
        ));
    }

    #[test]
    fn direction_cones_bracket_the_ball() {
        // A ball of radius 1 seen from 2 away: half-angle 30 degrees.
        let (p, c) = (DVec3::ZERO, DVec3::new(0.0, 0.0, 2.0));
        let (axis, cos) = direction_cone(p, c, 1.0).unwrap();
        let (sure_axis, sure_cos, reach) = sure_cone(p, c, 1.0, 0.0).unwrap();
        assert_eq!((axis, sure_axis), (DVec3::Z, DVec3::Z));
        let half = 30f64.to_radians().cos();
        assert!(cos < half && half - cos < 1e-8, "{cos}");
        assert!(sure_cos > half && sure_cos - half < 1e-8, "{sure_cos}");
        assert!((reach - 3.0).abs() < 1e-8);
        // Directions just inside the sure cone meet the ball; just outside the outer cone
        // they miss it (distance from the center to the line > radius).
        for (angle, meets) in [(29.999_99, true), (30.000_01, false)] {
            let a = f64::to_radians(angle);
            let d = DVec3::new(a.sin(), 0.0, a.cos());
            let miss_distance = (c - d * c.dot(d)).length();
            assert_eq!(miss_distance < 1.0, meets);
            assert_eq!(d.dot(sure_axis) > sure_cos, meets);
            assert_eq!(d.dot(axis) >= cos, meets);
        }
        // From inside the ball there is no cone.
        assert_eq!(direction_cone(c, c, 1.0), None);
        assert_eq!(sure_cone(c + DVec3::X * 0.5, c, 1.0, 0.0), None);
    }
}
