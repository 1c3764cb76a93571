//! The grouped shadow test of an area light (pass 2 of [`super`]'s passes): the shadow rays
//! of its N points from one shading point, tested object by object. Each candidate object
//! that may block one of them ([`crate::world::World::shadow_candidates`]) is met by every
//! point it has not blocked yet, opaque objects first, then the transparent ones in
//! ascending order, their filters multiplied in ([`transparent_filter`], [`filter_through`]): the objects, order
//! and products of [`crate::trace::Reference`]'s `shadow_filter` for each point. Before the
//! exact test, the candidate's cones of directions sort the points into sure hits, sure
//! misses and the undecided ([`verdicts`]), and a candidate whose cone misses the light's
//! whole cone is passed over.

use super::{AreaScratch, Lanes};
use crate::math::Ray;
use crate::shading::{filter_through, transparent_filter};
use crate::shape::{Fan, Shape, Verdict, fan_verdicts};
use crate::skips::Skip;
use crate::trace::Surface;
use crate::trace::fast::{Tracer, segment_meets_sphere};
use crate::world::{Candidate, cones_apart, direction_cone};
use glam::DVec3;
use multiversion::multiversion;

impl<const K: usize> Tracer<'_, '_, K> {
    /// Pass 2 of the module doc: the shadow rays of the open points against the candidate
    /// objects, each ray meeting the objects in the order [`Tracer::shadow_filter`] uses
    /// (opaque ones until one blocks, then every transparent one in ascending order), with
    /// the same counts. For each candidate, a lane loop first sorts every point's direction
    /// by the candidate's cones ([`verdicts`]); the undecided ones get the candidate's own
    /// shortcuts, all together ([`fan_verdicts`]: for a box or a cone the whole exact test),
    /// and what is still undecided its exact test.
    pub(super) fn shadow_points(
        &mut self,
        candidates: &[Candidate],
        at: &Surface,
        light: (DVec3, f64),
        s: &mut AreaScratch,
    ) {
        let world = self.world;
        let objects = &world.scene.objects;
        let cones = world.skips.on(Skip::BoundingSpheres);
        let rays = s.open.len() as u64;
        self.counts.shadow += rays;
        self.counts
            .saved
            .count(Skip::ShadowCandidates, rays * (objects.len() - candidates.len()) as u64);
        let Some(&first) = s.open.first() else {
            return;
        };
        // Every open point faces the surface, so every shadow ray leaves from the same
        // offset origin (the offset's side is the side of the light: see `offset_origin`).
        let origin = at.ray_along(s.lanes.to_light(first as usize)).origin;
        let (center, radius) = light;
        // The directions from the shading point (as in `incidences`) to every light point.
        let light_cone = direction_cone(at.point, center, radius);
        let mut rejects = 0;
        let len = s.lanes.dist.len();
        // Opaque candidates, then transparent ones, each in ascending order.
        let transparent = |c: &&Candidate| world.filters_shadows(c.object);
        let opaque = candidates.iter().filter(|c| !transparent(c));
        let walk = self.walks_transparent();
        let see_through = candidates.iter().filter(|c| walk && transparent(c));
        for c in opaque.chain(see_through) {
            let shape = &objects[c.object].shape;
            if let (true, Shape::Plane(plane)) = (cones, shape)
                && plane.misses_segments_to(origin, center, radius)
            {
                // A plane that none of the segments to the light's ball can cross.
                rejects += s.open.len() as u64;
                continue;
            }
            if cones && c.object == at.object && at.n == at.outward && shape.is_convex() {
                // Rays leaving a convex surface outward, from origins offset past its
                // rounding error, never meet it again (tests/self_intersection.rs).
                rejects += s.open.len() as u64;
                continue;
            }
            if let (true, Some(light), Some(cone)) = (cones, light_cone, c.cone)
                && cones_apart(light, cone)
            {
                // No direction towards the light meets the candidate's bounding sphere: every
                // verdict below would be a miss (two thirds of the candidates of the soft
                // shadows' shading points).
                rejects += s.open.len() as u64;
                continue;
            }
            s.verdict.resize(len, Verdict::Test);
            match c.cone {
                Some(cone) if cones => verdicts(&s.lanes, cone, c.sure, &mut s.verdict),
                _ if cones && c.object == at.object && at.n == -at.outward && shape.is_convex_solid() && {
                    let (o_center, o_radius) = world.bounding_spheres[c.object].expect("solids are bounded");
                    (center - o_center).length() > (radius + o_radius) * (1.0 + 1e-9)
                } =>
                {
                    // From the inside of a convex solid's surface, towards a light wholly
                    // outside the solid's bounding sphere: every ray crosses the far side
                    // before reaching its light point (the exact tests agree: the origin is
                    // offset inside, so the far root is positive; tests/skips.rs).
                    s.verdict.fill(Verdict::Hit)
                }
                _ => s.verdict.fill(Verdict::Test),
            }
            let sphere =
                world.bounding_spheres[c.object].filter(|_| cones && c.cone.is_none() && world.costly[c.object]);
            // The open points the cones say meet the candidate, and those they leave
            // undecided, listed without a branch per point (the pattern is random).
            let open = s.open.len();
            s.hits.resize(open + 1, 0);
            s.tests.resize(open + 1, 0);
            let (mut hits, mut tests) = sort_by_verdict(&s.open, &s.verdict, &mut s.hits, &mut s.tests);
            rejects += (open - tests) as u64;
            if let Some((center, radius)) = sphere {
                // The undecided rays that meet the candidate's bounding sphere.
                let mut kept = 0;
                for k in 0..tests {
                    let i = s.tests[k];
                    let ray = Ray::new(origin, s.lanes.to_light(i as usize));
                    // `kept <= k`: in bounds.
                    s.tests[kept] = i;
                    kept += usize::from(segment_meets_sphere(&ray, s.lanes.dist[i as usize], center, radius));
                }
                rejects += (tests - kept) as u64;
                tests = kept;
            }
            let lanes = &s.lanes;
            let fan = Fan {
                origin,
                x: &lanes.lx,
                y: &lanes.ly,
                z: &lanes.lz,
                reach: &lanes.dist,
            };
            s.fan.resize(open, Verdict::Test);
            fan_verdicts(shape, &fan, &s.tests[..tests], &mut s.fan);
            for k in 0..tests {
                let i = s.tests[k];
                let met = match s.fan[k] {
                    Verdict::Hit => true,
                    Verdict::Miss => false,
                    Verdict::Test => shape.occludes(
                        &Ray::new(origin, lanes.to_light(i as usize)),
                        0.0,
                        lanes.dist[i as usize],
                    ),
                };
                // `hits <= open`: in bounds.
                s.hits[hits] = i;
                hits += usize::from(met);
            }
            if hits > 0 {
                s.ensure_filter(len);
            }
            let met = &s.hits[..hits];
            if !world.filters_shadows(c.object) {
                for &i in met {
                    s.filter[i as usize] = DVec3::ZERO;
                    s.blocked[i as usize] = true;
                }
                if hits > 0 {
                    let (list, blocked) = (&mut s.open[..], &s.blocked[..]);
                    let mut kept = 0;
                    for k in 0..open {
                        let i = list[k];
                        // `kept <= k`: in bounds.
                        list[kept] = i;
                        kept += usize::from(!blocked[i as usize]);
                    }
                    s.open.truncate(kept);
                }
            } else {
                let mat = world.material_of(c.object);
                let color = transparent_filter(world.scene.settings.conventions.shadow_filter, mat.kt, mat.color);
                s.tinted |= hits > 0;
                for &i in met {
                    let i = i as usize;
                    s.filter[i] = filter_through(s.filter[i], color);
                    s.zero_product |= s.filter[i] == DVec3::ZERO;
                    if let Some(list) = s.crossed.get_mut(i) {
                        list.push(c.object);
                    }
                }
            }
        }
        if !walk {
            self.counts.saved.count(Skip::OpaqueOnly, s.open.len() as u64);
        }
        self.counts.saved.count(Skip::BoundingSpheres, rejects);
    }
}

/// Lists the points of `open` whose verdict is a hit in `hits` and those left to the exact
/// test in `tests` (each at least `open.len() + 1` long), without a branch per point (the
/// pattern is random); returns how many of each. A function of its own: inside the
/// caller, the counts lived on the stack.
#[inline(never)]
fn sort_by_verdict(open: &[u32], verdict: &[Verdict], hits: &mut [u32], tests: &mut [u32]) -> (usize, usize) {
    let (mut hit_count, mut test_count) = (0, 0);
    for &i in open {
        let v = verdict[i as usize];
        // `hit_count, test_count <= k < open.len() + 1`: in bounds.
        hits[hit_count] = i;
        hit_count += usize::from(v == Verdict::Hit);
        tests[test_count] = i;
        test_count += usize::from(v == Verdict::Test);
    }
    (hit_count, test_count)
}

/// The verdict of a candidate's cones (`cone`: axis and cosine of the bounding cone;
/// `sure`: axis, cosine and reach of the cone through the inner ball, see
/// [`Candidate::sure`]) on the shadow ray towards every point, as a lane loop.
#[multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn verdicts(lanes: &Lanes, (axis, cos): (DVec3, f64), sure: Option<(DVec3, f64, f64)>, out: &mut [Verdict]) {
    let len = out.len();
    let (lx, ly, lz, dist) = (&lanes.lx[..len], &lanes.ly[..len], &lanes.lz[..len], &lanes.dist[..len]);
    // Without an inner ball, a cone nothing passes (cos > 1) and an unreachable reach.
    let (sure_axis, sure_cos, reach) = sure.unwrap_or((DVec3::Z, 2.0, f64::INFINITY));
    for i in 0..len {
        // `DVec3::dot` order, as the scalar test would compute it.
        let outer = lx[i] * axis.x + ly[i] * axis.y + lz[i] * axis.z;
        let inner = lx[i] * sure_axis.x + ly[i] * sure_axis.y + lz[i] * sure_axis.z;
        // Every comparison made and the verdict selected: a condition on the load of
        // `dist` would compile to a masked load (slow on AMD cores).
        let sure = (dist[i] > reach) & (inner > sure_cos);
        let miss = outer < cos;
        out[i] = Verdict::of(sure & !miss, miss);
    }
}

#[cfg(test)]
mod tests {
    use super::super::incidences;
    use super::*;
    use crate::area_light::PointSet;
    use crate::shading::Attenuation;
    use rand_chacha::ChaCha8Rng;
    use rand_core::{Rng, SeedableRng};

    /// When the light's cone of directions and a candidate's share none
    /// ([`crate::world::cones_apart`]), the cones' verdict on every light point is a miss:
    /// skipping the candidate changes nothing.
    #[test]
    fn cones_apart_means_every_verdict_misses() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut uniform = |lo: f64, hi: f64| lo + (hi - lo) * (rng.next_u64() >> 11) as f64 * 2f64.powi(-53);
        let (mut apart, mut near) = (0, 0);
        for _ in 0..2000 {
            let p = DVec3::new(uniform(-6.0, 6.0), uniform(-6.0, 6.0), uniform(0.0, 4.0));
            let (center, radius) = (
                DVec3::new(uniform(-1.0, 1.0), uniform(-1.0, 1.0), 10.0),
                uniform(0.5, 3.0),
            );
            // Points on the light's sphere, the chapter's placement, rounded as placed.
            let points: Vec<DVec3> = (0..64)
                .map(|_| {
                    let (theta, phi) = (uniform(0.0, std::f64::consts::PI), uniform(0.0, std::f64::consts::TAU));
                    center + radius * DVec3::new(phi.cos() * theta.sin(), phi.sin() * theta.sin(), theta.cos())
                })
                .collect();
            let object = (
                DVec3::new(uniform(-6.0, 6.0), uniform(-6.0, 6.0), uniform(0.0, 9.0)),
                uniform(0.1, 2.0),
            );
            let (Some(light), Some(cone)) = (direction_cone(p, center, radius), direction_cone(p, object.0, object.1))
            else {
                continue;
            };
            if !cones_apart(light, cone) {
                near += 1;
                continue;
            }
            apart += 1;
            let mut lanes = Lanes::default();
            lanes.resize(points.len());
            let att = Attenuation {
                constant: 1.0,
                linear: 0.0,
                quadratic: 0.0,
            };
            incidences(&PointSet::from_points(&points), p, DVec3::Z, &att, &mut lanes);
            let mut verdict = vec![Verdict::Test; points.len()];
            verdicts(&lanes, cone, None, &mut verdict);
            assert!(
                verdict.iter().all(|&v| v == Verdict::Miss),
                "p {p}, light {light:?}, cone {cone:?}"
            );
        }
        assert!(apart > 300 && near > 100, "both cases met: {apart} apart, {near} not");
    }
}
