//! The grouped shadow test of an area light (pass 2 of [`super`]'s passes): the shadow rays
//! of its N points from one shading point, tested object by object. Each candidate object
//! that may block one of them ([`crate::world::World::shadow_candidates`]) is met by every
//! point it has not blocked yet, opaque objects first, then the transparent ones in
//! ascending order, their filters multiplied in ([`crate::world::World::filter_color`],
//! [`filter_through`]): the objects, order and products of [`crate::trace::Reference`]'s
//! `shadow_filter` for each point. Before the exact test, the candidate's cones of
//! directions sort the points into sure hits, sure misses and the undecided ([`verdicts`]),
//! and a candidate whose cone misses the light's whole cone is passed over.
//!
//! The open points of each verdict are listed without a branch per point: with AVX-512,
//! from every point's marks, sixteen points a vector packed by a compress instruction
//! ([`sort_by_verdict`]); else from the list of open points, one index written a point
//! ([`sort_open_by_verdict`]). [`Packing`] names the two ways; the tests check they give
//! the same lists.

use super::{AreaScratch, Facing, Lanes};
use crate::math::Ray;
use crate::shading::filter_through;
use crate::shape::{Fan, Shape, Verdict, fan_verdicts, occludes_undecided};
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
    /// shortcuts, all together ([`fan_verdicts`]: for a box, a cone or a cylinder the whole exact test),
    /// and what is still undecided its exact test.
    pub(super) fn shadow_points(
        &mut self,
        candidates: &[Candidate],
        at: &Surface,
        light: (DVec3, f64),
        towards: usize,
        packing: Packing,
        s: &mut AreaScratch,
    ) {
        let world = self.world;
        let objects = &world.scene.objects;
        let cones = world.skips.on(Skip::BoundingSpheres);
        let rays = towards as u64;
        self.counts.shadow += rays;
        self.counts
            .saved
            .count(Skip::ShadowCandidates, rays * (objects.len() - candidates.len()) as u64);
        if towards == 0 {
            return;
        }
        let first = s
            .facing
            .iter()
            .position(|&f| f == Facing::Towards)
            .expect("a point faces the surface");
        // Every open point faces the surface, so every shadow ray leaves from the same
        // offset origin (the offset's side is the side of the light: see `offset_origin`).
        let origin = at.ray_along(s.lanes.to_light(first)).origin;
        let (center, radius) = light;
        // The directions from the shading point (as in `incidences`) to every light point.
        let light_cone = direction_cone(at.point, center, radius);
        let mut rejects = 0;
        let len = s.lanes.dist.len();
        // How many points face the surface and are not blocked yet (the open points).
        let mut open = towards;
        // Opaque candidates, then transparent ones, each in ascending order.
        let transparent = |c: &&Candidate| world.filters_shadows(c.object);
        let opaque = candidates.iter().filter(|c| !transparent(c));
        let walk = self.walks_transparent();
        let see_through = candidates.iter().filter(|c| walk && transparent(c));
        for c in opaque.chain(see_through) {
            if open == 0 {
                // Every shadow ray is blocked: no later candidate meets one.
                break;
            }
            let shape = &objects[c.object].shape;
            if let (true, Shape::Plane(plane)) = (cones, shape)
                && plane.misses_segments_to(origin, center, radius)
            {
                // A plane that none of the segments to the light's ball can cross.
                rejects += open as u64;
                continue;
            }
            if cones && c.object == at.object && at.n == at.outward && shape.is_convex() {
                // Rays leaving a convex surface outward, from origins offset past its
                // rounding error, never meet it again (tests/self_intersection.rs).
                rejects += open as u64;
                continue;
            }
            if let (true, Some(light), Some(cone)) = (cones, light_cone, c.cone)
                && cones_apart(light, cone)
            {
                // No direction towards the light meets the candidate's bounding sphere: every
                // verdict below would be a miss (two thirds of the candidates of the soft
                // shadows' shading points).
                rejects += open as u64;
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
            s.hits.resize(len + 1, 0);
            s.tests.resize(len + 1, 0);
            let (mut hits, mut tests) = match packing {
                Packing::OneByOne => sort_open_by_verdict(&s.open, &s.verdict, &mut s.hits, &mut s.tests),
                Packing::Compress => sort_by_verdict(&s.facing, &s.blocked, &s.verdict, &mut s.hits, &mut s.tests),
            };
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
            // The fan's hits join the list and its undecided rays stay in `tests`, without a
            // branch per ray (the pattern is random); then the exact test of each undecided
            // ray, in ascending order. The order of `hits` does not matter: each of its points
            // is marked on its own.
            // Slices taken once: through the vectors, their pointers are loaded again after
            // every store.
            let (hit_list, test_list, said) = (&mut s.hits[..], &mut s.tests[..tests], &s.fan[..tests]);
            let mut undecided = 0;
            for k in 0..tests {
                let (i, verdict) = (test_list[k], said[k]);
                // `hits <= open` and `undecided <= k`: in bounds.
                hit_list[hits] = i;
                hits += usize::from(verdict == Verdict::Hit);
                test_list[undecided] = i;
                undecided += usize::from(verdict == Verdict::Test);
            }
            for k in 0..undecided {
                let i = s.tests[k] as usize;
                s.hits[hits] = i as u32;
                hits += usize::from(occludes_undecided(shape, &fan, lanes.to_light(i), lanes.dist[i]));
            }
            let opaque = !world.filters_shadows(c.object);
            if hits > 0 && !(opaque && s.blocked_unread) {
                s.ensure_filter(len);
            }
            let met = &s.hits[..hits];
            if opaque {
                let (blocked, filter) = (&mut s.blocked[..], &mut s.filter[..]);
                if s.blocked_unread {
                    for &i in met {
                        blocked[i as usize] = true;
                    }
                } else {
                    for &i in met {
                        filter[i as usize] = DVec3::ZERO;
                        blocked[i as usize] = true;
                    }
                }
                // Each of them was open.
                open -= hits;
                if packing == Packing::OneByOne && hits > 0 {
                    let (list, blocked) = (&mut s.open[..], &s.blocked[..]);
                    let mut kept = 0;
                    for k in 0..list.len() {
                        let i = list[k];
                        // `kept <= k`: in bounds.
                        list[kept] = i;
                        kept += usize::from(!blocked[i as usize]);
                    }
                    s.open.truncate(kept);
                }
            } else {
                let color = world.filter_color(c.object);
                s.tinted |= hits > 0;
                // Each channel compared, no branch (a product is rarely 0).
                let mut zero_product = false;
                let filters = &mut s.filter[..];
                for &i in met {
                    let i = i as usize;
                    let f = filter_through(filters[i], color);
                    filters[i] = f;
                    zero_product |= (f.x == 0.0) & (f.y == 0.0) & (f.z == 0.0);
                }
                s.zero_product |= zero_product;
                if !s.crossed.is_empty() {
                    for &i in met {
                        s.crossed[i as usize].push(c.object);
                    }
                }
            }
        }
        if !walk {
            self.counts.saved.count(Skip::OpaqueOnly, open as u64);
        }
        self.counts.saved.count(Skip::BoundingSpheres, rejects);
    }
}

/// How pass 2 lists the open points of each verdict.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Packing {
    /// From the list of open points ([`AreaScratch::open`], kept by dropping the blocked
    /// ones), each point's index written and the list's end moved on by 0 or 1
    /// ([`sort_open_by_verdict`]): on any machine.
    OneByOne,
    /// From every point's facing, blocked mark and verdict, sixteen points at a time, their
    /// indices packed by one compress instruction ([`sort_by_verdict`]): with AVX-512.
    Compress,
}

impl Packing {
    /// The faster way on this machine: [`Packing::Compress`] where it has AVX-512 (and the
    /// features that come with it on every such x86-64 core: `pulp`'s `V4`).
    pub(super) fn fastest() -> Packing {
        #[cfg(target_arch = "x86_64")]
        if pulp::x86::V4::is_available() {
            return Packing::Compress;
        }
        Packing::OneByOne
    }
}

/// Lists the points of `open` whose verdict is a hit in `hits` and those left to the exact
/// test in `tests` (each at least `open.len() + 1` long), without a branch per point (the
/// pattern is random); returns how many of each. A function of its own: inside the
/// caller, the counts lived on the stack.
#[inline(never)]
fn sort_open_by_verdict(open: &[u32], verdict: &[Verdict], hits: &mut [u32], tests: &mut [u32]) -> (usize, usize) {
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

/// Lists the open points (facing the surface, not blocked: `facing`, `blocked`) whose
/// verdict is a hit in `hits` and those left to the exact test in `tests` (each at least
/// `verdict.len() + 1` long), in ascending order, without a branch per point (the pattern
/// is random); returns how many of each: the lists of [`sort_open_by_verdict`], without
/// the list of open points. With AVX-512, sixteen points at a time
/// ([`sort_compressed`]); the points past the last whole sixteen, and every point
/// otherwise, one by one.
fn sort_by_verdict(
    facing: &[Facing],
    blocked: &[bool],
    verdict: &[Verdict],
    hits: &mut [u32],
    tests: &mut [u32],
) -> (usize, usize) {
    let len = verdict.len();
    let (facing, blocked) = (&facing[..len], &blocked[..len]);
    let (start, (mut hit_count, mut test_count)) = sort_compressed(facing, blocked, verdict, hits, tests);
    for i in start..len {
        let v = verdict[i];
        let open = (facing[i] == Facing::Towards) & !blocked[i];
        // `hit_count, test_count <= i < len + 1`: in bounds.
        hits[hit_count] = i as u32;
        hit_count += usize::from(open & (v == Verdict::Hit));
        tests[test_count] = i as u32;
        test_count += usize::from(open & (v == Verdict::Test));
    }
    (hit_count, test_count)
}

/// [`sort_by_verdict`] for the points of the whole blocks of sixteen, where the machine
/// has AVX-512 (else for none): returns where the blocks end and the two counts. In each
/// block, byte comparisons of the three arrays make one bit mask per list, and one
/// compress instruction (`vpcompressd`) packs the indices a mask selects into a vector
/// stored whole: two vector stores for sixteen points instead of two stores a point. The
/// intrinsics are called through `pulp`'s tokens, which check the CPU's features once and
/// run the loop in a function compiled with them.
#[cfg(target_arch = "x86_64")]
fn sort_compressed(
    facing: &[Facing],
    blocked: &[bool],
    verdict: &[Verdict],
    hits: &mut [u32],
    tests: &mut [u32],
) -> (usize, (usize, usize)) {
    use pulp::bytemuck::cast;
    use std::arch::x86_64::__m128i;
    const LANES: usize = 16;
    let Some(simd) = pulp::x86::V4::try_new() else {
        return (0, (0, 0));
    };
    simd.vectorize(|| {
        let (sse2, avx512f) = (simd.sse2, simd.avx512f);
        let (towards, zero) = (sse2._mm_set1_epi8(Facing::Towards as i8), sse2._mm_set1_epi8(0));
        let (hit, test) = (
            sse2._mm_set1_epi8(Verdict::Hit as i8),
            sse2._mm_set1_epi8(Verdict::Test as i8),
        );
        let mut index = avx512f._mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
        let step = avx512f._mm512_set1_epi32(LANES as i32);
        let (mut hit_count, mut test_count) = (0, 0);
        let blocks = facing.chunks_exact(LANES).zip(blocked.chunks_exact(LANES));
        for ((f, b), v) in blocks.zip(verdict.chunks_exact(LANES)) {
            let f: __m128i = cast::<[u8; LANES], _>(std::array::from_fn(|l| f[l] as u8));
            let b: __m128i = cast::<[u8; LANES], _>(std::array::from_fn(|l| u8::from(b[l])));
            let v: __m128i = cast::<[u8; LANES], _>(std::array::from_fn(|l| v[l] as u8));
            // Facing (`f` equal to `Towards`) and not blocked (`b` zero): `0xff` bytes.
            let open = sse2._mm_and_si128(sse2._mm_cmpeq_epi8(f, towards), sse2._mm_cmpeq_epi8(b, zero));
            let mask = |want| sse2._mm_movemask_epi8(sse2._mm_and_si128(open, sse2._mm_cmpeq_epi8(v, want))) as u16;
            let (hit_mask, test_mask) = (mask(hit), mask(test));
            // `hit_count, test_count <=` the block's first point: the 16 stores are in bounds.
            let packed: [u32; LANES] = cast(avx512f._mm512_maskz_compress_epi32(hit_mask, index));
            hits[hit_count..hit_count + LANES].copy_from_slice(&packed);
            hit_count += hit_mask.count_ones() as usize;
            let packed: [u32; LANES] = cast(avx512f._mm512_maskz_compress_epi32(test_mask, index));
            tests[test_count..test_count + LANES].copy_from_slice(&packed);
            test_count += test_mask.count_ones() as usize;
            index = avx512f._mm512_add_epi32(index, step);
        }
        (verdict.len() / LANES * LANES, (hit_count, test_count))
    })
}

/// Without x86-64, no block is packed at once.
#[cfg(not(target_arch = "x86_64"))]
fn sort_compressed(_: &[Facing], _: &[bool], _: &[Verdict], _: &mut [u32], _: &mut [u32]) -> (usize, (usize, usize)) {
    (0, (0, 0))
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
    use super::super::tests::lanes_of;
    use super::*;
    use crate::area_light::PointSet;
    use crate::sampling::unit_interval;
    use crate::shading::Attenuation;
    use rand_chacha::ChaCha8Rng;
    use rand_core::{Rng, SeedableRng};

    /// The open points of each verdict, point by point from the definition.
    fn lists_by_definition(facing: &[Facing], blocked: &[bool], verdict: &[Verdict]) -> [Vec<u32>; 2] {
        [Verdict::Hit, Verdict::Test].map(|want| {
            (0..verdict.len() as u32)
                .filter(|&i| {
                    let i = i as usize;
                    facing[i] == Facing::Towards && !blocked[i] && verdict[i] == want
                })
                .collect()
        })
    }

    /// Both lists, packed in the given way: for [`Packing::OneByOne`] from the list of
    /// open points that pass 2 keeps.
    fn sorted(facing: &[Facing], blocked: &[bool], verdict: &[Verdict], packing: Packing) -> [Vec<u32>; 2] {
        let len = verdict.len();
        let (mut hits, mut tests) = (vec![u32::MAX; len + 1], vec![u32::MAX; len + 1]);
        let (h, t) = match packing {
            Packing::OneByOne => {
                let towards = facing.iter().filter(|&&f| f == Facing::Towards).count();
                let mut open = Vec::new();
                super::super::list_facing(facing, towards, &mut open);
                open.retain(|&i| !blocked[i as usize]);
                sort_open_by_verdict(&open, verdict, &mut hits, &mut tests)
            }
            Packing::Compress => sort_by_verdict(facing, blocked, verdict, &mut hits, &mut tests),
        };
        hits.truncate(h);
        tests.truncate(t);
        [hits, tests]
    }

    /// Eighteen points (a block of sixteen and two more), listed by hand: facing but for
    /// points 2 (away) and 16 (no light), points 5 and 17 blocked, verdicts miss, hit,
    /// test in turn. The hits are the open points `i = 1 mod 3`, the tests those with
    /// `i = 2 mod 3` (2, 5 and 17 are not open).
    #[test]
    fn open_points_are_sorted_by_verdict() {
        let facing: Vec<Facing> = (0..18)
            .map(|i| match i {
                2 => Facing::Away,
                16 => Facing::NoLight,
                _ => Facing::Towards,
            })
            .collect();
        let blocked: Vec<bool> = (0..18).map(|i| i == 5 || i == 17).collect();
        let verdict: Vec<Verdict> = (0..18)
            .map(|i| [Verdict::Miss, Verdict::Hit, Verdict::Test][i % 3])
            .collect();
        for packing in [Packing::OneByOne, Packing::Compress] {
            let [hits, tests] = sorted(&facing, &blocked, &verdict, packing);
            assert_eq!(hits, [1, 4, 7, 10, 13], "{packing:?}");
            assert_eq!(tests, [8, 11, 14], "{packing:?}");
        }
    }

    /// Packed sixteen points at a time or one by one from the list of open points, the
    /// lists are those of the definition, for lengths around the blocks of sixteen and
    /// random facings, blocked marks and verdicts (every point open, and a mixed pattern).
    /// Where the machine has AVX-512, the packed way does take every whole block.
    #[test]
    fn packed_lists_are_the_one_by_one_lists() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let kinds = [Facing::NoLight, Facing::Black, Facing::Away, Facing::Towards];
        let verdicts = [Verdict::Miss, Verdict::Hit, Verdict::Test];
        let mut mixed_lists = 0;
        for len in [0, 1, 15, 16, 17, 31, 32, 33, 250, 1000] {
            for all_open in [true, false] {
                let facing: Vec<Facing> = (0..len)
                    .map(|_| {
                        if all_open {
                            Facing::Towards
                        } else {
                            kinds[(rng.next_u64() % 4) as usize]
                        }
                    })
                    .collect();
                let blocked: Vec<bool> = (0..len).map(|_| !all_open && rng.next_u64() % 4 == 0).collect();
                let verdict: Vec<Verdict> = (0..len).map(|_| verdicts[(rng.next_u64() % 3) as usize]).collect();
                let want = lists_by_definition(&facing, &blocked, &verdict);
                mixed_lists += usize::from(!all_open && want.iter().all(|l| l.len() > len / 20));
                for packing in [Packing::OneByOne, Packing::Compress] {
                    assert_eq!(
                        sorted(&facing, &blocked, &verdict, packing),
                        want,
                        "{len} points, {packing:?}"
                    );
                }
                #[cfg(target_arch = "x86_64")]
                if Packing::fastest() == Packing::Compress {
                    let (mut hits, mut tests) = (vec![0; len + 1], vec![0; len + 1]);
                    let (end, _) = sort_compressed(&facing, &blocked, &verdict, &mut hits, &mut tests);
                    assert_eq!(end, len / 16 * 16);
                }
            }
        }
        assert!(mixed_lists >= 2, "mixed patterns with both lists long: {mixed_lists}");
    }

    /// When the light's cone of directions and a candidate's share none
    /// ([`crate::world::cones_apart`]), the cones' verdict on every light point is a miss:
    /// skipping the candidate changes nothing.
    #[test]
    fn cones_apart_means_every_verdict_misses() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut uniform = |lo: f64, hi: f64| lo + (hi - lo) * unit_interval(rng.next_u64());
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
            let att = Attenuation {
                constant: 1.0,
                linear: 0.0,
                quadratic: 0.0,
            };
            let lanes = lanes_of(&PointSet::from_points(&points), (p, DVec3::Z), &att, DVec3::ONE);
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
