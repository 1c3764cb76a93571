//! The tracer that renders: the recursion of [`super::reference`], computed to the same bits
//! with three kinds of speed-up, each beside the reference function it must equal.
//!
//! - **One-pass families.** With `K > 1` [`Member`]s it traces the images of a family
//!   ([`crate::family`]) together: each ray once, each member's radiance with exactly the
//!   operations a render of that member's scene alone does (`Tracer::radiance` is
//!   [`Reference`]'s `radiance` per member, `Tracer::local` its `local`). Every function
//!   takes the bit mask of the members it works for and returns `[DVec3; K]`.
//! - **Area lights in vector lanes** (`area`, src/trace/fast/area.rs): an area light's N
//!   points taken together in arrays, their shadow rays tested candidate by candidate
//!   (src/trace/fast/area/grouped.rs); they equal [`Reference`]'s `local` summing N point
//!   lights.
//! - **Skips** ([`crate::skips`]): the shadow rays, object tests and secondary rays whose
//!   result is known without them (a surface facing away, a light that is black, a zero
//!   weight, an object that cannot be in the way). Each can be switched off, and none
//!   changes a pixel (tests/skips.rs).
//!
//! Every step can be reported to a [`Recorder`] (what `lumiere probe` shows).
//!
//! [`Reference`]: super::Reference

use super::{LightShare, NoRecord, RayCounts, RayKind, Recorder, SampleKey, Surface, caustic_share, point_light_terms};
use crate::light::{Incidence, Light, aperture_share};
use crate::material::Material;
use crate::math::{Ray, reflect, refract};
use crate::scene::ShadingModel;
use crate::shading::{ambient, beneath_notice, faces_away, local_weight, no_light, shadow_filter, transmission_weight};
use crate::shape::padded_radius;
use crate::skips::Skip;
use crate::world::{Candidate, World};
use glam::DVec3;

mod area;

/// How one light (or light point) stands towards a surface point, before any shadow ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
enum Facing {
    /// No light arrives: the surface point is exactly at the light.
    NoLight,
    /// The light is black here (outside a spot's cone): no shadow ray.
    Black,
    /// `N.L <= 0`: the surface faces away; no diffuse nor specular term.
    Away,
    /// `N.L > 0`: lit unless a shadow ray is blocked.
    Towards,
}

impl Facing {
    /// The decision for a light that arrives (`arrives`: not at distance 0), black or not
    /// (`black`: its colour before the shadow test is zero and the unlit skip is on), at an
    /// angle of cosine `n_dot_l`.
    /// Selects, not branches: the area lights' lane loop ([`area`]) compiles to vector
    /// instructions only so.
    #[inline(always)]
    fn of(arrives: bool, black: bool, n_dot_l: f64) -> Facing {
        let lit = if faces_away(n_dot_l) {
            Facing::Away
        } else {
            Facing::Towards
        };
        let unblack = if black { Facing::Black } else { lit };
        if arrives { unblack } else { Facing::NoLight }
    }
}

/// What sets one image of a one-pass family apart (see [`crate::family`]): its recursion
/// depth, its adaptive-depth bounds, the number of points it takes of the family's area
/// light, its shading (model, and materials whose colours, `k_r`, `k_t` and `n` are the
/// world's), and which of the world's lights it has. A plain render has one member, the
/// world's own.
#[derive(Clone, Copy, Debug)]
pub struct Member<'w> {
    pub depth: u32,
    /// `remaining_bound` of this member's scene (see [`World::remaining_bound`]).
    pub remaining_bound: &'w [f64],
    /// The family's area light (index) and this member's count `N`: its first `N` points.
    pub area_count: Option<(usize, u32)>,
    pub shading: ShadingModel,
    /// The member's materials, indexed as the world's.
    pub materials: &'w [Material],
    /// The world's lights this member's scene has, one bit per light index (ambient lights
    /// aside: see `ambient`); a light of index 64 or more belongs to every member.
    pub lights: u64,
    /// The sum of this member's ambient lights' colours, `L_a`.
    pub ambient: DVec3,
}

impl<'w> Member<'w> {
    /// The member of a plain render of `world`.
    pub fn of(world: &'w World) -> Self {
        Member {
            depth: world.scene.settings.depth,
            remaining_bound: &world.remaining_bound,
            area_count: None,
            shading: world.scene.settings.shading,
            materials: &world.scene.materials,
            lights: u64::MAX,
            ambient: world.ambient,
        }
    }

    /// Whether this member's scene has the world's light `index` and shades with it (not
    /// under the `no_light` model).
    fn has_light(&self, index: usize) -> bool {
        !self.shading.no_light && (index >= 64 || self.lights >> index & 1 == 1)
    }

    /// Whether this member shades every surface as `other` does.
    fn shades_as(&self, other: &Member) -> bool {
        self.shading == other.shading && self.materials == other.materials
    }
}

/// The members of a bit mask of `K` members, in order.
fn members_of<const K: usize>(mask: u32) -> impl Iterator<Item = usize> {
    (0..K).filter(move |&j| mask >> j & 1 == 1)
}

/// Traces rays in a world; one per thread (it keeps counters and scratch space). With
/// `K > 1` members it traces the images of a one-pass family together: each ray once, each
/// member's radiance with exactly the operations a render of that member's scene alone does.
pub struct Tracer<'w, 's, const K: usize = 1> {
    pub world: &'w World<'s>,
    /// Rays and skipped work. With `K > 1`, only what the members share at a hit (shadow rays,
    /// skips); the rest is in `member_counts`.
    pub counts: RayCounts,
    /// With `K > 1`, each member's counts (its image's manifest).
    pub member_counts: [RayCounts; K],
    pub members: [Member<'w>; K],
    /// Per member, the shadow rays counted in `counts` that the member's own scene does not
    /// cast (rays towards its area light's points beyond `N`, or towards lights it does not
    /// have), for the current hit.
    shadow_excess: [u64; K],
    /// For each of the world's lights, the members that have it, as bits.
    light_members: Vec<u32>,
    /// For each member, the first member of the family that shades as it does: the members of a
    /// hit with the same twin share their light shares (copied from the first of them).
    shading_twin: [usize; K],
    /// Set when a member could not be traced exactly with the others (a light point black for
    /// one member's `L / N` and not another's): the family must be rendered image by image.
    pub diverged: bool,
    /// The pixel index and sample being traced (keys the points of `per_sample` lights).
    pub sample_key: SampleKey,
    /// Scratch list of transparent objects crossed by a shadow ray.
    crossed: Vec<usize>,
    /// Scratch space of the current area light's points, boxed: taken out and put back at
    /// every area light, its 600 bytes of vectors stay where they are.
    area: Option<Box<area::AreaScratch>>,
}

impl<'w, 's> Tracer<'w, 's> {
    pub fn new(world: &'w World<'s>) -> Self {
        Tracer::with_members(world, [Member::of(world)])
    }

    /// Radiance along a camera ray.
    pub fn trace_camera<R: Recorder>(&mut self, ray: &Ray, rec: &mut R) -> DVec3 {
        self.trace_camera_members(ray, rec)[0]
    }
}

impl<'w, 's, const K: usize> Tracer<'w, 's, K> {
    /// A tracer of the family `members` over `world`, the world of the family's deepest member
    /// with its largest area light count.
    pub fn with_members(world: &'w World<'s>, members: [Member<'w>; K]) -> Self {
        assert!(K >= 1 && K <= u32::BITS as usize, "1 to 32 members");
        Tracer {
            world,
            counts: RayCounts::default(),
            member_counts: [RayCounts::default(); K],
            shading_twin: std::array::from_fn(|j| (0..=j).find(|&i| members[i].shades_as(&members[j])).unwrap_or(j)),
            light_members: (0..world.scene.lights.len())
                .map(|index| {
                    (0..K)
                        .filter(|&j| members[j].has_light(index))
                        .fold(0, |m, j| m | 1 << j)
                })
                .collect(),
            members,
            shadow_excess: [0; K],
            diverged: false,
            sample_key: SampleKey::default(),
            crossed: Vec::new(),
            area: None,
        }
    }

    /// Member `j`'s shading model and its material of `object`.
    fn member_shading(&self, j: usize, object: usize) -> (ShadingModel, &'w Material) {
        let member = &self.members[j];
        (
            member.shading,
            &member.materials[self.world.scene.objects[object].material()],
        )
    }

    /// Every member.
    const ALL: u32 = if K == 32 { u32::MAX } else { (1 << K) - 1 };

    /// Counts `f` for every member of `mask` (in `counts` itself with one member).
    fn count_members(&mut self, mask: u32, f: impl Fn(&mut RayCounts)) {
        if K == 1 {
            f(&mut self.counts);
        } else {
            members_of::<K>(mask).for_each(|j| f(&mut self.member_counts[j]));
        }
    }

    /// Each member's counts: with one member, `counts`; else the member's rays, with the skipped
    /// work of the whole family.
    pub fn member_totals(&self) -> [RayCounts; K] {
        if K == 1 {
            return [self.counts; K];
        }
        self.member_counts.map(|mut c| {
            c.saved = self.counts.saved;
            c
        })
    }

    /// The counts where a member's non-finite samples go.
    pub fn member_counts_mut(&mut self, j: usize) -> &mut RayCounts {
        if K == 1 {
            &mut self.counts
        } else {
            &mut self.member_counts[j]
        }
    }

    /// Radiance of every member along a camera ray.
    pub fn trace_camera_members<R: Recorder>(&mut self, ray: &Ray, rec: &mut R) -> [DVec3; K] {
        self.count_members(Self::ALL, |c| c.camera += 1);
        self.radiance(RayKind::Camera, ray, 1, 1.0, Self::ALL, rec)
    }

    /// Radiance along `ray` at recursion `level` (1 = camera ray), whose contribution to the
    /// pixel is scaled by `weight` (product of the k_r and k_t along the path), for the
    /// members of `mask` (the others' entries are meaningless).
    fn radiance<R: Recorder>(
        &mut self,
        kind: RayKind,
        ray: &Ray,
        level: u32,
        weight: f64,
        mask: u32,
        rec: &mut R,
    ) -> [DVec3; K] {
        rec.ray(kind, ray, level, weight);
        let scene = self.world.scene;
        let conventions = &scene.settings.conventions;
        let t_max = if level == 1 { conventions.far } else { f64::INFINITY };
        let mut untested = 0;
        let closest = if kind == RayKind::Camera {
            self.world.closest_camera(ray, t_max, &mut untested)
        } else {
            self.world.closest_secondary(ray, t_max, &mut untested)
        };
        self.counts.saved.count(Skip::BoundingSpheres, untested);
        let Some((object, hit)) = closest else {
            rec.miss();
            rec.done(scene.settings.background);
            return [scene.settings.background; K];
        };
        let mat = self.world.material_of(object);
        let surface = Surface::hit(self.world, ray, object, &hit);
        rec.hit(object, hit.t, surface.point, hit.normal, surface.entering);
        let mut color = [DVec3::ZERO; K];
        self.local_counted(&surface, mask, rec, &mut color);
        let local = local_weight(conventions.local_weight, mat.kr, mat.kt);
        members_of::<K>(mask).for_each(|j| color[j] *= local);
        rec.local(color[0]);

        // Without the zero-weight skip, rays of weight 0 are traced (and add 0).
        let all = !self.world.skips.on(Skip::ZeroWeight);
        // The members whose depth lets this hit spawn secondary rays.
        let deeper = members_of::<K>(mask)
            .filter(|&j| level < self.members[j].depth)
            .fold(0, |m, j| m | 1 << j);
        if deeper != 0 {
            let mut kr = mat.kr;
            let mut refracted = None;
            if (mat.kt > 0.0 || all) && conventions.refracting.admits(scene.objects[object].shape.is_closed()) {
                match refract(ray.dir, surface.n, mat.eta(surface.entering)) {
                    Some(t) => refracted = Some(t.normalize()),
                    None => {
                        // Total internal reflection: the transmitted energy is reflected, or lost.
                        kr = conventions.total_internal_reflection.reflected_weight(kr, mat.kt);
                        self.count_members(deeper, |c| c.total_internal_reflections += 1);
                        rec.total_internal_reflection();
                    }
                }
            }
            if kr == 0.0 && !all {
                self.counts.saved.count(Skip::ZeroWeight, 1);
            }
            if mat.kt == 0.0 && !all {
                self.counts.saved.count(Skip::ZeroWeight, 1);
            }
            if kr > 0.0 || all {
                let dir = reflect(ray.dir, surface.n).normalize();
                let reflected = self.secondary(RayKind::Reflection, &surface, dir, level, weight * kr, deeper, rec);
                members_of::<K>(deeper).for_each(|j| color[j] += kr * reflected[j]);
            }
            if let Some(dir) = refracted {
                let kt = transmission_weight(conventions.transmission, mat.kt, mat.color, surface.entering);
                let transmitted = self.secondary(
                    RayKind::Refraction,
                    &surface,
                    dir,
                    level,
                    weight * kt.max_element(),
                    deeper,
                    rec,
                );
                members_of::<K>(deeper).for_each(|j| color[j] += kt * transmitted[j]);
            }
        }
        rec.done(color[0]);
        color
    }

    /// Traces a reflected or refracted ray from `from` for the members of `mask` where
    /// adaptive depth control does not find that, with `weight`, it cannot change the 8-bit
    /// result; the members where it is cut off get 0 ([`super::Reference`]'s `secondary`).
    #[allow(clippy::too_many_arguments)]
    fn secondary<R: Recorder>(
        &mut self,
        kind: RayKind,
        from: &Surface,
        dir: DVec3,
        level: u32,
        weight: f64,
        mask: u32,
        rec: &mut R,
    ) -> [DVec3; K] {
        let threshold = self.world.scene.settings.adaptive_threshold;
        let cut = members_of::<K>(mask)
            .filter(|&j| beneath_notice(weight, self.members[j].remaining_bound[level as usize + 1], threshold))
            .fold(0, |m, j| m | 1 << j);
        if cut != 0 {
            self.count_members(cut, |c| c.adaptive_cutoffs += 1);
            rec.cutoff(kind, weight);
        }
        let traced = mask & !cut;
        if traced == 0 {
            return [DVec3::ZERO; K];
        }
        match kind {
            RayKind::Reflection => self.count_members(traced, |c| c.reflection += 1),
            _ => self.count_members(traced, |c| c.refraction += 1),
        }
        let mut radiance = self.radiance(kind, &from.ray_along(dir), level + 1, weight, traced, rec);
        members_of::<K>(cut).for_each(|j| radiance[j] = DVec3::ZERO);
        radiance
    }

    /// [`Tracer::local`] for the members of `mask`, with what it counts added to each member's
    /// counts, less the shadow rays its own scene does not cast (`shadow_excess`: towards
    /// area light points beyond its count, or towards lights it does not have).
    fn local_counted<R: Recorder>(&mut self, at: &Surface, mask: u32, rec: &mut R, color: &mut [DVec3; K]) {
        if K == 1 {
            return self.local(at, mask, rec, color);
        }
        let shadow_before = self.counts.shadow;
        self.local(at, mask, rec, color);
        let shadow = self.counts.shadow - shadow_before;
        for j in members_of::<K>(mask) {
            self.member_counts[j].shadow += shadow - self.shadow_excess[j];
        }
        self.shadow_excess = [0; K];
    }

    /// Local illumination at a hit (slides' full model), with shadow rays:
    /// `L = L_a k_a S + sum_i A_i L_i [k_d S max(N.L_i, 0) + k_s [m S + (1 - m)] spec_i]`,
    /// where an area light counts as its N points of colour `L / N`, then the caustic share
    /// ([`caustic_share`]); for every member of `mask`, each summing in the same order, into
    /// `color` (zero on entry). The member arrays are written in place, not returned: for 16
    /// members each return is a copy of 384 bytes.
    fn local<R: Recorder>(&mut self, at: &Surface, mask: u32, rec: &mut R, color: &mut [DVec3; K]) {
        let scene = self.world.scene;
        for j in members_of::<K>(mask) {
            let (model, mat) = self.member_shading(j, at.object);
            if model.ambient {
                let r = at.reflectance(mat);
                let a = ambient(self.members[j].ambient, r.ka, r.ambient);
                rec.ambient(a);
                color[j] += a;
            } else if model.no_light {
                // No light reaches this member's hits: `has_light` leaves it out of every
                // light's members.
                let r = at.reflectance(mat);
                let c = no_light(r.kd, r.diffuse);
                rec.no_light(c);
                color[j] += c;
            }
        }
        for (index, light) in scene.lights.iter().enumerate() {
            // The members whose scene has this light; the others do not see its shadow rays.
            let lit = mask & self.light_members[index];
            if lit == 0 {
                continue;
            }
            let shadow_before = self.counts.shadow;
            match light {
                Light::Ambient { .. } => {}
                Light::Area(area) => self.add_area_light(color, lit, index, area, at, rec),
                Light::Aperture(a) => {
                    // Its share depends on no member's material or shading: one for all.
                    let share = self.aperture_light(index, a.color, light.incidence(at.point), at, rec);
                    members_of::<K>(lit).for_each(|j| color[j] += share);
                }
                _ => self.add_light_share(color, index, light.incidence(at.point), at, lit, rec),
            }
            if lit != mask {
                let cast = self.counts.shadow - shadow_before;
                members_of::<K>(mask & !lit).for_each(|j| self.shadow_excess[j] += cast);
            }
        }
        if self.world.photons.is_some() {
            for j in members_of::<K>(mask) {
                let (model, mat) = self.member_shading(j, at.object);
                if let Some((term, estimate)) = caustic_share(self.world, model, mat, at) {
                    rec.caustic(term, &estimate);
                    color[j] += term;
                }
            }
        }
    }

    /// Adds to `color` one point light's share at a surface point:
    /// `A L [k_d S max(N.L, 0) + k_s tint spec]` times the shadow filter. Nothing (a share of
    /// 0, and no shadow ray) when no light arrives or when N.L <= 0, where neither the
    /// diffuse nor (slides) the specular term counts. For every member of `mask`: one shadow
    /// ray, each member's shading.
    fn add_light_share<R: Recorder>(
        &mut self,
        color: &mut [DVec3; K],
        index: usize,
        inc: Option<Incidence>,
        at: &Surface,
        mask: u32,
        rec: &mut R,
    ) {
        let n_dot_l = inc.map_or(0.0, |inc| at.n.dot(inc.to_light));
        let mut shares = [DVec3::ZERO; K];
        match (inc, self.facing(inc.as_ref(), n_dot_l)) {
            (Some(inc), Facing::Towards) => {
                let filter = if self.world.scene.settings.shadows {
                    self.shadow_filter_recorded(at.point, at.outward, at.err, &inc, None, rec)
                } else {
                    DVec3::ONE
                };
                // The first member of `mask` of each shading computes its share; the others
                // that shade as it does copy it (the first of all, `shading_twin`, may not
                // be in `mask`: a shallower member past its depth).
                let mut first_of = [usize::MAX; K];
                for j in members_of::<K>(mask) {
                    let twin = self.shading_twin[j];
                    shares[j] = match first_of[twin] {
                        usize::MAX => {
                            first_of[twin] = j;
                            self.shade(j, index, &inc, n_dot_l, filter, at, rec)
                        }
                        first => shares[first],
                    };
                }
            }
            (_, facing) => self.not_facing(index, facing, inc.as_ref(), n_dot_l, at, None, rec),
        }
        members_of::<K>(mask).for_each(|j| color[j] += shares[j]);
    }

    /// An aperture light's share at a surface point ([`super::Reference`]'s
    /// `aperture_light`): its arriving light, whole, when the point faces the aperture's
    /// centre and the shadow ray towards it does not blacken its colour `light`
    /// ([`aperture_share`]).
    fn aperture_light<R: Recorder>(
        &mut self,
        index: usize,
        light: DVec3,
        inc: Option<Incidence>,
        at: &Surface,
        rec: &mut R,
    ) -> DVec3 {
        let n_dot_l = inc.map_or(0.0, |inc| at.n.dot(inc.to_light));
        match (inc, self.facing(inc.as_ref(), n_dot_l)) {
            (Some(inc), Facing::Towards) => {
                let shadows = self.world.scene.settings.shadows;
                let filter = if shadows {
                    self.shadow_filter_recorded(at.point, at.outward, at.err, &inc, None, rec)
                } else {
                    DVec3::ONE
                };
                let share = aperture_share(light, filter, inc.color);
                rec.light(&LightShare {
                    light: index,
                    incidence: inc,
                    n_dot_l,
                    shadow_ray: shadows,
                    filter,
                    diffuse: share,
                    specular: DVec3::ZERO,
                });
                share
            }
            (_, facing) => {
                self.not_facing(index, facing, inc.as_ref(), n_dot_l, at, None, rec);
                DVec3::ZERO
            }
        }
    }

    /// How a light with incidence `inc` (`None`: no light) and `N.L = n_dot_l` stands
    /// towards the surface, before any shadow ray (the skips decide whether a black light
    /// counts as dark).
    fn facing(&self, inc: Option<&Incidence>, n_dot_l: f64) -> Facing {
        let black = inc.is_some_and(|inc| inc.color == DVec3::ZERO) && self.world.skips.on(Skip::Unlit);
        Facing::of(inc.is_some(), black, n_dot_l)
    }

    /// The bookkeeping of a light that adds nothing: the skipped shadow ray counted, or
    /// traced anyway when its skip is off, and the `unlit` event.
    #[allow(clippy::too_many_arguments)]
    fn not_facing<R: Recorder>(
        &mut self,
        index: usize,
        facing: Facing,
        inc: Option<&Incidence>,
        n_dot_l: f64,
        at: &Surface,
        candidates: Option<&[Candidate]>,
        rec: &mut R,
    ) {
        let shadows = self.world.scene.settings.shadows;
        match (facing, inc) {
            (Facing::Away, Some(inc)) => {
                if self.world.skips.on(Skip::BackFacing) {
                    self.counts.saved.count(Skip::BackFacing, u64::from(shadows));
                } else if shadows {
                    self.shadow_filter_recorded(at.point, at.outward, at.err, inc, candidates, &mut NoRecord);
                }
                rec.unlit(index, Some(n_dot_l));
            }
            (Facing::Black, _) => {
                self.counts.saved.count(Skip::Unlit, u64::from(shadows));
                rec.unlit(index, None);
            }
            _ => rec.unlit(index, None),
        }
    }

    /// The share of a light that reaches a surface point facing it (`N.L > 0`), through the
    /// shadow filter `filter`: `A L filter [k_d S N.L + k_s [m S + (1 - m)] spec]`, with member
    /// `member`'s shading.
    #[allow(clippy::too_many_arguments)]
    fn shade<R: Recorder>(
        &mut self,
        member: usize,
        index: usize,
        inc: &Incidence,
        n_dot_l: f64,
        filter: DVec3,
        at: &Surface,
        rec: &mut R,
    ) -> DVec3 {
        let (diffuse, specular) = if filter == DVec3::ZERO && self.world.skips.on(Skip::BlockedShading) {
            // Both terms are products with the arriving light, 0: exactly 0.
            self.counts.saved.count(Skip::BlockedShading, 1);
            (DVec3::ZERO, DVec3::ZERO)
        } else {
            let (model, mat) = self.member_shading(member, at.object);
            point_light_terms(model, mat, at, inc.to_light, n_dot_l, inc.color * filter)
        };
        rec.light(&LightShare {
            light: index,
            incidence: *inc,
            n_dot_l,
            shadow_ray: self.world.scene.settings.shadows,
            filter,
            diffuse,
            specular,
        });
        diffuse + specular
    }

    /// Chapter 7.4b's shadow ray from `point` towards the light: 0 if an opaque object is in
    /// the way, else the product of the colours of the transparent objects crossed, each
    /// counted once however many of its surfaces the ray crosses. `outward` is the surface
    /// normal at `point` and `err` the bound on the point's rounding error.
    pub fn shadow_filter(&mut self, point: DVec3, outward: DVec3, err: f64, inc: &Incidence) -> DVec3 {
        self.shadow_filter_recorded(point, outward, err, inc, None, &mut NoRecord)
    }

    /// [`Tracer::shadow_filter`], reporting the shadow ray to `rec`.
    fn shadow_filter_recorded<R: Recorder>(
        &mut self,
        point: DVec3,
        outward: DVec3,
        err: f64,
        inc: &Incidence,
        candidates: Option<&[Candidate]>,
        rec: &mut R,
    ) -> DVec3 {
        self.counts.shadow += 1;
        let world = self.world;
        let objects = &world.scene.objects;
        let ray = Ray::leaving(point, outward, err, inc.to_light);
        let t_max = inc.distance;
        rec.shadow_ray(&ray, t_max);
        let skips = world.skips;
        if candidates.is_none() && skips.on(Skip::OpaqueOnly) && world.scans_balls() {
            // The common case, scanned in one call: the same tests, answer and counts as the
            // general path below.
            self.crossed.clear();
            let mut untested = 0;
            let blocked = world.shadow_scan(&ray, t_max, &mut self.crossed, &mut untested);
            self.counts.saved.count(Skip::BoundingSpheres, untested);
            if blocked || !world.has_transparent {
                self.counts.saved.count(Skip::OpaqueOnly, u64::from(!blocked));
                return if blocked { DVec3::ZERO } else { DVec3::ONE };
            }
            return self.crossed_filter(rec);
        }
        let opaque = |i: usize| !world.filters_shadows(i);
        let transparent = |i: usize| world.filters_shadows(i);
        if let Some(c) = candidates {
            let not_tested = (objects.len() - c.len()) as u64;
            self.counts.saved.count(Skip::ShadowCandidates, not_tested);
        }
        // Exact test of object `i`, after its bounding sphere where that is cheaper: through
        // the candidate's cone of directions, or a ray-sphere test for costly shapes.
        let sphere_rejects = std::cell::Cell::new(0);
        let cones = skips.on(Skip::BoundingSpheres);
        let meets_sphere = |i: usize| {
            if cones
                && world.costly[i]
                && let Some((center, radius)) = world.bounding_spheres[i]
            {
                return segment_meets_sphere(&ray, t_max, center, radius);
            }
            true
        };
        let meets = |i: usize| {
            if !meets_sphere(i) {
                sphere_rejects.set(sphere_rejects.get() + 1);
                return false;
            }
            objects[i].shape.occludes(&ray, 0.0, t_max)
        };
        let meets_candidate = |c: &Candidate| {
            if cones && let Some((axis, cos)) = c.cone {
                if ray.dir.dot(axis) < cos {
                    sphere_rejects.set(sphere_rejects.get() + 1);
                    return false;
                }
                return objects[c.object].shape.occludes(&ray, 0.0, t_max);
            }
            meets(c.object)
        };
        let mut untested = 0;
        let blocked = match candidates {
            Some(c) => c.iter().any(|c| opaque(c.object) && meets_candidate(c)),
            None if skips.on(Skip::OpaqueOnly) => world.shadow_any_hit(&ray, t_max, opaque, &mut untested),
            None => {
                // Without the any-hit shortcut: visit every opaque hit.
                let mut any = false;
                world.each_hit(&ray, t_max, &opaque, &mut |_| any = true);
                any
            }
        };
        if blocked || (!world.has_transparent && skips.on(Skip::OpaqueOnly)) {
            let saved = &mut self.counts.saved;
            saved.count(Skip::BoundingSpheres, sphere_rejects.get() + untested);
            saved.count(Skip::OpaqueOnly, u64::from(!blocked));
            return if blocked { DVec3::ZERO } else { DVec3::ONE };
        }
        self.crossed.clear();
        let crossed = &mut self.crossed;
        match candidates {
            Some(c) => crossed.extend(
                c.iter()
                    .filter(|c| transparent(c.object) && meets_candidate(c))
                    .map(|c| c.object),
            ),
            None => world.shadow_each_hit(&ray, t_max, transparent, |i| crossed.push(i), &mut untested),
        }
        self.counts
            .saved
            .count(Skip::BoundingSpheres, sphere_rejects.get() + untested);
        // Multiply in object order so the bits do not depend on the traversal order.
        self.crossed.sort_unstable();
        self.crossed_filter(rec)
    }

    /// The shadow filter of the objects in `crossed` (ascending), reported to `rec`: the
    /// product of their colours ([`shadow_filter`]).
    fn crossed_filter<R: Recorder>(&mut self, rec: &mut R) -> DVec3 {
        rec.shadow_crossed(&self.crossed);
        let world = self.world;
        shadow_filter(self.crossed.iter().map(|&i| world.filter_color(i)))
    }
}

/// Whether the whole ball (`center`, `radius`) lies below the tangent plane at `point` with
/// normal `n`, so that N.L < 0 for every light point in it: `n.(c - p) + r < 0`, with a
/// relative margin far above the rounding of N.L (a few ulps of |L|).
fn below_horizon(point: DVec3, n: DVec3, center: DVec3, radius: f64) -> bool {
    let to_center = center - point;
    let margin = 1e-9 * (to_center.length() + radius);
    n.dot(to_center) + radius < -margin
}

/// Whether the segment `o + t d`, `t` in [0, t_max], passes within `radius` of `center`
/// (padded by a relative 1e-9 so rounding never rejects a real hit). `d` is unit length.
fn segment_meets_sphere(ray: &Ray, t_max: f64, center: DVec3, radius: f64) -> bool {
    let to_center = center - ray.origin;
    let t = to_center.dot(ray.dir).clamp(0.0, t_max);
    let reach = padded_radius(radius, to_center);
    (ray.origin + t * ray.dir - center).length_squared() <= reach * reach
}
