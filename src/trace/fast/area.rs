//! One area light at one shading point, its N points taken together (chapter 7.4b,
//! `L_multi = (1/N) sum_i L_point_i`). Four passes over the points:
//!
//! 1. the incidence of every point: `L_i`, `d_i`, `A(d_i)`, `N.L_i`, and how it faces the
//!    surface ([`incidences`]);
//! 2. the shadow rays of the points facing the surface, tested
//!    object by object ([`grouped`]: each candidate object against every point it has not
//!    blocked yet, opaque objects first, then the transparent ones in ascending order
//!    multiplying their colours in);
//! 3. the diffuse and specular terms of every point ([`shares`]);
//! 4. in point order, the recorder's events and the running sum.
//!
//! Without a recorder, passes 3 and 4 are one ([`lane_sum`]: the terms of a block of
//! points, then their sum), and a candidate whose cone of directions misses the light's
//! is passed over before pass 2 looks at its points.
//!
//! Passes 1 and 3 are straight loops over coordinate arrays that compile to vector
//! instructions, in versions for AVX-512 and AVX2 chosen at run time (`multiversion`):
//! the same IEEE operations on each lane whatever the vector width (Rust never fuses a
//! multiply and an add), so the same bits on every machine; pass 3's specular power is
//! taken in the loop that computes the cosine ([`pow_each_of`]), and pass 4 marks and
//! counts the points that add in byte loops of the same kind ([`mark_adds`],
//! [`count_facing`]). Each point's arithmetic is that
//! of a lone point light: the loops call, point by point or channel by channel, the
//! formulas a point light is shaded with ([`point_incidence`]'s [`direction_to`] and
//! [`arriving`], [`blinn`]'s or [`phong`]'s cosines, [`diffuse`], [`specular`]), and the
//! tests below check the bits. Each shadow ray meets the same objects in the same order as
//! [`Tracer::shadow_filter`] would test them, and the sum runs in point order: the result
//! and the counts are exactly those of N separate point lights, and the radiance that of
//! [`crate::trace::Reference`]'s `local`, which sums the N point lights one by one
//! (tests/reference.rs, tests/soft_shadows.rs and the tests below).
//!
//! [`point_incidence`]: crate::light::point_incidence
//! [`blinn`]: crate::shading::blinn
//! [`phong`]: crate::shading::phong

use super::{Facing, LightShare, Recorder, Surface, Tracer, below_horizon, members_of};
use crate::area_light::{AreaLight, PointSet};
use crate::light::{Attenuation, Incidence, arriving, direction_to};
use crate::material::{Material, Reflectance};
use crate::scene::{ShadingModel, Specular};
use crate::shading::{
    blinn_cosine, blinn_cosine_squared, blinn_defined, diffuse, half_of_even, half_vector_test_needed, phong_cosine,
    pow_each_of, specular,
};
use crate::shape::Verdict;
use crate::skips::Skip;
use crate::trace::diffuse_coefficient;
use crate::world::Candidate;
use glam::DVec3;
use multiversion::multiversion;

mod grouped;

use grouped::Packing;

/// Per-point values of the current area light at the current shading point, one array
/// entry per light point, reused from one shading point to the next.
#[derive(Default)]
pub(super) struct AreaScratch {
    lanes: Lanes,
    facing: Vec<Facing>,
    /// Shadow filter of each point: 1 unshadowed, 0 blocked, else the product of colours;
    /// filled with 1 only when first written at a shading point ([`AreaScratch::ensure_filter`]).
    /// Where `blocked_unread`, the filters of points blocked by an opaque object are left
    /// as they are (`blocked` tells them).
    filter: Vec<DVec3>,
    /// Whether pass 4 never reads the filter of a point an opaque object blocks: without a
    /// recorder, with the blocked-shading and back-facing skips on, a blocked point adds
    /// nothing and only the points that add have their filters read. Then an opaque
    /// candidate's hits only mark `blocked`, and the filters are filled with 1 only when a
    /// transparent object meets a shadow ray.
    blocked_unread: bool,
    /// Whether `filter` holds this shading point's filters (else every one is 1).
    filter_ready: bool,
    /// Whether an opaque object blocks the point's shadow ray.
    blocked: Vec<bool>,
    /// For [`Packing::OneByOne`] only: the points whose shadow ray is still open (facing,
    /// not blocked yet).
    open: Vec<u32>,
    /// The open points that meet the current candidate, and those its cones leave
    /// undecided (then only those that meet its bounding sphere, for a costly shape
    /// without cones), for its fan verdicts and exact test.
    hits: Vec<u32>,
    tests: Vec<u32>,
    /// Whether each point adds to the sum (facing, not blocked).
    adds: Vec<bool>,
    /// How each point would face the surface with a member's own colour `L / N`.
    member_facing: Vec<Facing>,
    /// Whether some point's transparent colours multiplied to exactly 0 (so `blocked` does
    /// not tell all the points whose filter is 0).
    zero_product: bool,
    /// Whether a transparent object met some point's shadow ray (so some filter is neither
    /// 0 nor 1).
    tinted: bool,
    /// The current candidate's verdict on each point's shadow ray.
    verdict: Vec<Verdict>,
    /// The candidate's own verdicts on the rays of `tests` ([`fan_verdicts`]).
    fan: Vec<Verdict>,
    /// For a recorder only (else empty): the transparent objects each point's shadow ray
    /// crosses.
    crossed: Vec<Vec<usize>>,
    candidates: Vec<Candidate>,
}

impl AreaScratch {
    /// Fills the `len` filters with 1, unless this shading point's are already there: where
    /// no shadow ray is blocked, nothing writes the 24 bytes a point of a fill.
    fn ensure_filter(&mut self, len: usize) {
        if !self.filter_ready {
            self.filter.clear();
            self.filter.resize(len, DVec3::ONE);
            self.filter_ready = true;
        }
    }
}

/// Coordinate arrays of the per-point quantities (pass 1 and 3 outputs).
#[derive(Default)]
struct Lanes {
    /// Unit direction to the light point, `L_i`.
    lx: Vec<f64>,
    ly: Vec<f64>,
    lz: Vec<f64>,
    /// Distance to the light point, `d_i` (the shadow ray's `t_max`).
    dist: Vec<f64>,
    /// Attenuation `A(d_i)`.
    atten: Vec<f64>,
    /// `N.L_i`.
    n_dot_l: Vec<f64>,
    /// Specular term `spec_i` (Blinn or Phong).
    spec: Vec<f64>,
    /// Diffuse and specular terms, by channel.
    diffuse: [Vec<f64>; 3],
    specular: [Vec<f64>; 3],
}

impl Lanes {
    fn resize(&mut self, n: usize) {
        for v in [
            &mut self.lx,
            &mut self.ly,
            &mut self.lz,
            &mut self.dist,
            &mut self.atten,
            &mut self.n_dot_l,
            &mut self.spec,
        ] {
            v.resize(n, 0.0);
        }
        for v in self.diffuse.iter_mut().chain(self.specular.iter_mut()) {
            v.resize(n, 0.0);
        }
    }

    fn to_light(&self, i: usize) -> DVec3 {
        DVec3::new(self.lx[i], self.ly[i], self.lz[i])
    }

    /// Point `i`'s incidence, as [`crate::light::point_incidence`] gives it.
    fn incidence(&self, i: usize, point_color: DVec3) -> Incidence {
        let a = self.atten[i];
        Incidence {
            to_light: self.to_light(i),
            distance: self.dist[i],
            attenuation: a,
            spot: 1.0,
            color: arriving(point_color, a, 1.0),
        }
    }
}

/// Pass 1: for every light point `q_i`, the direction and distance of
/// [`direction_to`], the attenuation `A(d_i)` and `N.L_i`: [`point_incidence`]'s formulas,
/// point by point; and in the same loop, pass 2's first step, how each point of colour
/// `point_color` faces the surface ([`Facing::of`], as [`facings`] decides it), while the
/// loop waits on its square root and divisions. A point at distance 0 gets NaN directions
/// (no light arrives from it; see [`Facing`]). Returns how many points face the surface,
/// face away and are black.
#[multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn incidences(
    points: &PointSet,
    (p, n): (DVec3, DVec3),
    att: &Attenuation,
    (point_color, unlit_skip): (DVec3, bool),
    out: &mut Lanes,
    facing: &mut [Facing],
) -> [u64; 3] {
    match ZeroColour::of(point_color) {
        ZeroColour::Brightest(b) => incidences_where(points, (p, n), att, out, facing, move |a| {
            unlit_skip & brightest_zero(b, a)
        }),
        ZeroColour::Channels(c) => incidences_where(points, (p, n), att, out, facing, move |a| {
            unlit_skip & channels_zero(c, a)
        }),
    }
}

/// [`incidences`] with `black(A_i)` telling whether point `i` is black. Inlined into each
/// of its versions.
#[inline(always)]
fn incidences_where(
    points: &PointSet,
    (p, n): (DVec3, DVec3),
    att: &Attenuation,
    out: &mut Lanes,
    facing: &mut [Facing],
    black: impl Fn(f64) -> bool,
) -> [u64; 3] {
    let len = points.len();
    let (xs, ys, zs) = (&points.x[..len], &points.y[..len], &points.z[..len]);
    let (lx, ly, lz) = (&mut out.lx[..len], &mut out.ly[..len], &mut out.lz[..len]);
    let (dist, atten, ndl) = (&mut out.dist[..len], &mut out.atten[..len], &mut out.n_dot_l[..len]);
    let facing = &mut facing[..len];
    let mut counts = [0u64; 3];
    for i in 0..len {
        let (l, d) = direction_to(DVec3::new(xs[i], ys[i], zs[i]), p);
        let a = att.factor(d);
        let n_dot_l = n.dot(l);
        lx[i] = l.x;
        ly[i] = l.y;
        lz[i] = l.z;
        dist[i] = d;
        atten[i] = a;
        ndl[i] = n_dot_l;
        let f = Facing::of(d != 0.0, black(a), n_dot_l);
        facing[i] = f;
        for (count, kind) in counts.iter_mut().zip([Facing::Towards, Facing::Away, Facing::Black]) {
            *count += u64::from(f == kind);
        }
    }
    counts
}

/// How a point's colour `L / N * A` is tested for zero ([`facings`]).
#[derive(Clone, Copy)]
enum ZeroColour {
    /// No channel of `L / N` negative or NaN: the colour is zero exactly when its brightest
    /// channel `max_k L_k` times `A` is (a rounded product does not grow in magnitude when
    /// a factor shrinks, so `|fl(L_k A)| <= |fl(max_k L_k A)|` for every channel `k`, and an
    /// `A` that is NaN or infinite makes neither zero): one product and one comparison a
    /// point, not three.
    Brightest(f64),
    /// Otherwise every channel is compared.
    Channels(DVec3),
}

impl ZeroColour {
    fn of(point_color: DVec3) -> ZeroColour {
        // Every channel compared (a NaN fails), not `min_element`, which passes NaN by.
        if point_color.cmpge(DVec3::ZERO).all() {
            ZeroColour::Brightest(point_color.max_element())
        } else {
            ZeroColour::Channels(point_color)
        }
    }
}

#[inline(always)]
fn brightest_zero(brightest: f64, a: f64) -> bool {
    arriving(brightest, a, 1.0) == 0.0
}

/// Each channel compared, no branch.
#[inline(always)]
fn channels_zero(point_color: DVec3, a: f64) -> bool {
    let c = arriving(point_color, a, 1.0);
    (c.x == 0.0) & (c.y == 0.0) & (c.z == 0.0)
}

/// How each point faces the surface, [`Facing::of`] as a lane loop, for points whose
/// incidences are already in `lanes`. A point is black when its colour `L / N * A` is zero
/// (and the unlit skip is on: [`ZeroColour`]). Returns how many points face the surface,
/// face away and are black (counted after, in byte loops: [`count_facing`]).
#[multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn facings(lanes: &Lanes, point_color: DVec3, unlit_skip: bool, out: &mut [Facing]) -> [u64; 3] {
    match ZeroColour::of(point_color) {
        ZeroColour::Brightest(b) => facings_where(lanes, out, move |a| unlit_skip & brightest_zero(b, a)),
        ZeroColour::Channels(c) => facings_where(lanes, out, move |a| unlit_skip & channels_zero(c, a)),
    }
}

/// [`facings`] with `black(A_i)` telling whether point `i` is black. Inlined into each of
/// its versions.
#[inline(always)]
fn facings_where(lanes: &Lanes, out: &mut [Facing], black: impl Fn(f64) -> bool) -> [u64; 3] {
    let len = out.len();
    let (dist, atten, n_dot_l) = (&lanes.dist[..len], &lanes.atten[..len], &lanes.n_dot_l[..len]);
    for i in 0..len {
        out[i] = Facing::of(dist[i] != 0.0, black(atten[i]), n_dot_l[i]);
    }
    let out = &*out;
    [Facing::Towards, Facing::Away, Facing::Black].map(|kind| count_facing(out, kind))
}

/// Pass 3's first step: for every point, the specular term `spec_i`: Blinn's
/// `max(N.H, 0)^n` or Phong's `max(R.E, 0)^n`, computed as [`crate::shading::blinn`] and
/// [`crate::shading::phong`] compute them (their cosines point by point, each raised to
/// the power in the same loop for the small integer exponents, else the power of every
/// point at once: [`pow_each_of`]).
#[multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn speculars(lanes: &mut Lanes, len: usize, n: DVec3, eye: DVec3, mat: &Material, model: ShadingModel) {
    let Lanes {
        lx,
        ly,
        lz,
        n_dot_l,
        spec,
        ..
    } = lanes;
    let (lx, ly, lz, n_dot_l) = (&lx[..len], &ly[..len], &lz[..len], &n_dot_l[..len]);
    let spec = &mut spec[..len];
    // Closures that hold the slices themselves (`move`), not references to them: the
    // compiler then knows their lengths in `pow_each_of`'s loop and vectorizes it.
    let to_light = move |i: usize| DVec3::new(lx[i], ly[i], lz[i]);
    match model.specular {
        Specular::None => spec.fill(0.0),
        Specular::Blinn if let Some(m) = half_of_even(mat.shininess) => {
            pow_each_of(spec, f64::from(m), move |i| blinn_cosine_squared(n, to_light(i) + eye));
        }
        Specular::Blinn => {
            pow_each_of(spec, mat.shininess, move |i| blinn_cosine(n, to_light(i) + eye));
            if half_vector_test_needed(mat.shininess) {
                for (i, spec) in spec.iter_mut().enumerate() {
                    *spec = blinn_defined(to_light(i) + eye, *spec);
                }
            }
        }
        Specular::Phong => {
            pow_each_of(spec, mat.shininess, move |i| {
                phong_cosine(n, to_light(i), eye, n_dot_l[i])
            });
        }
    }
}

/// What the diffuse and specular shares of one surface point's reflectance and shading
/// model take, by channel: the point's colour `L / N`, `k_d` (0 without the diffuse term),
/// `S`, `k_s` and the tint `m S + (1 - m)` ([`Material::reflectance`]).
struct ShareFactors {
    point: [f64; 3],
    kd: f64,
    color: [f64; 3],
    ks: f64,
    tint: [f64; 3],
}

impl ShareFactors {
    fn new(point_color: DVec3, refl: &Reflectance, model: ShadingModel) -> Self {
        ShareFactors {
            point: point_color.to_array(),
            kd: diffuse_coefficient(model, refl),
            color: refl.diffuse.to_array(),
            ks: refl.ks,
            tint: refl.tint.to_array(),
        }
    }

    /// Channel `c`'s [`diffuse`] and [`specular`] shares of a point with attenuation
    /// `atten`, shadow filter `filter`, `N.L` and specular term `spec`.
    #[inline(always)]
    fn terms(&self, c: usize, atten: f64, filter: f64, n_dot_l: f64, spec: f64) -> (f64, f64) {
        let light = arriving(self.point[c], atten, 1.0) * filter;
        (
            diffuse(light, self.kd, self.color[c], n_dot_l),
            specular(light, self.ks, self.tint[c], spec),
        )
    }
}

/// Pass 3's second step, for a recorder: for the first `len` points, each of colour
/// `point_color`, `A L filter [k_d S N.L]` and `A L filter [k_s [m S + (1 - m)] spec]` by
/// channel ([`ShareFactors::terms`]). Values for points that do not face the surface are
/// computed and ignored.
fn shares(
    lanes: &mut Lanes,
    len: usize,
    point_color: DVec3,
    filter: &[DVec3],
    refl: &Reflectance,
    model: ShadingModel,
) {
    let Lanes {
        atten,
        n_dot_l,
        spec,
        diffuse,
        specular,
        ..
    } = lanes;
    let factors = ShareFactors::new(point_color, refl, model);
    for i in 0..len {
        for c in 0..3 {
            (diffuse[c][i], specular[c][i]) = factors.terms(c, atten[i], filter[i][c], n_dot_l[i], spec[i]);
        }
    }
}

/// Passes 3 (second step) and 4 at once, without a recorder: `color` plus, in point order,
/// the diffuse and specular terms ([`ShareFactors::terms`]) of the points that add (`adds`:
/// facing the surface and not blocked; a blocked point adds exactly 0, and with the
/// blocked-shading skip nothing at all), each point of colour `point_color`. `filter`:
/// the shadow filters, `None` when every point that adds has filter 1 (`x * 1 = x`).
///
/// The sum's additions must run in point order, one after the other (3 cycles each). The
/// terms are computed [`SUM_BLOCK`] points at a time, four per vector, into a block that
/// stays in the L1 cache, then summed from it, rather than written to six arrays of terms
/// in memory and read back.
#[multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn lane_sum(
    color: DVec3,
    lanes: &Lanes,
    point_color: DVec3,
    filter: Option<&[DVec3]>,
    adds: &[bool],
    refl: &Reflectance,
    model: ShadingModel,
) -> DVec3 {
    let len = adds.len();
    let factors = ShareFactors::new(point_color, refl, model);
    let (atten, n_dot_l, spec) = (&lanes.atten[..len], &lanes.n_dot_l[..len], &lanes.spec[..len]);
    let mut sum = color;
    let terms = SumTerms {
        factors: &factors,
        atten,
        n_dot_l,
        spec,
        adds,
    };
    // Set once per call, not per block (a memset of 1.5 KB each time).
    let mut total = [[0.0; SUM_BLOCK]; 3];
    for start in (0..len).step_by(SUM_BLOCK) {
        let block = SUM_BLOCK.min(len - start);
        sum = match filter {
            Some(f) => terms.add(start, block, |i, c| f[i][c], &mut total, sum),
            None => terms.add(start, block, |_, _| 1.0, &mut total, sum),
        };
    }
    sum
}

impl<const K: usize> Tracer<'_, '_, K> {
    /// Adds to `color` (each member of `mask`), point after point, the share of area light
    /// `index` at the surface `at`, after the horizon test and the search for the objects
    /// that can block any of its shadow rays.
    /// Never inlined into [`Tracer::local`]: there the setup of its scratch space would run
    /// at every hit of every scene, with an area light or not; one call per area light and
    /// hit costs nothing beside its `N` points.
    #[inline(never)]
    pub(super) fn add_area_light<R: Recorder>(
        &mut self,
        color: &mut [DVec3; K],
        mask: u32,
        index: usize,
        area: &AreaLight,
        at: &Surface,
        rec: &mut R,
    ) {
        let world = self.world;
        let skips = world.skips;
        let mut s = self.area.take().unwrap_or_default();
        let points = world.area_points(index, self.sample_key.pixel, self.sample_key.sample);
        let points = &*points;
        let (center, radius) = area.bounding_sphere();
        if skips.on(Skip::Horizon) && below_horizon(at.point, at.n, center, radius) {
            self.counts.saved.count(Skip::Horizon, points.len() as u64);
            rec.below_horizon(index);
        } else {
            // Only objects near the hull of this point and the light can block any of its N
            // shadow rays: find them once, not N times (exact: see `shadow_candidates`).
            let mut candidates = std::mem::take(&mut s.candidates);
            let culled = skips.on(Skip::ShadowCandidates);
            if culled {
                world.shadow_candidates(at.point, center, radius, 4.0 * at.err, &mut candidates);
            }
            let shadowing = culled.then_some(candidates.as_slice());
            let light = (area, (center, radius));
            self.add_area_points(color, mask, index, points, light, at, shadowing, &mut s, rec);
            s.candidates = candidates;
        }
        self.area = Some(s);
    }

    /// Passes 1 to 4 of the module doc for the light points `points` of `area`, whose
    /// bounding sphere ([`AreaLight::bounding_sphere`]) is `sphere`.
    /// `candidates`, when given, are the only objects that can block their shadow rays;
    /// without them each shadow ray goes through the acceleration structure on its own.
    /// A member whose area light count `N` is set for this light takes the first `N` points,
    /// each of colour `L / N`: passes 1 and 2 are shared, passes 3 and 4 are the member's.
    #[allow(clippy::too_many_arguments)]
    fn add_area_points<R: Recorder>(
        &mut self,
        color: &mut [DVec3; K],
        mask: u32,
        index: usize,
        points: &PointSet,
        (area, sphere): (&AreaLight, (DVec3, f64)),
        at: &Surface,
        candidates: Option<&[Candidate]>,
        s: &mut AreaScratch,
        rec: &mut R,
    ) {
        let len = points.len();
        let point_color = area.point_color();
        s.lanes.resize(len);
        // Pass 1 writes every point's facing: no fill before it.
        s.facing.resize(len, Facing::NoLight);
        let unlit_skip = self.world.skips.on(Skip::Unlit);
        let [towards, away, black] = incidences(
            points,
            (at.point, at.n),
            &area.attenuation,
            (point_color, unlit_skip),
            &mut s.lanes,
            &mut s.facing,
        );
        let packing = Packing::fastest();
        if packing == Packing::OneByOne {
            list_facing(&s.facing, towards as usize, &mut s.open);
        }
        let shadows = self.world.scene.settings.shadows;
        s.filter_ready = false;
        s.blocked_unread =
            !R::RECORDS && self.world.skips.on(Skip::BlockedShading) && self.world.skips.on(Skip::BackFacing);
        s.blocked.clear();
        s.blocked.resize(len, false);
        s.zero_product = false;
        s.tinted = false;
        s.crossed.truncate(if R::RECORDS { len } else { 0 });
        s.crossed.iter_mut().for_each(Vec::clear);
        if R::RECORDS {
            s.crossed.resize_with(len, Vec::new);
        }
        let grouped = match candidates {
            Some(c) if shadows => {
                self.shadow_points(c, at, sphere, towards as usize, packing, s);
                true
            }
            _ => false,
        };
        if !grouped && shadows {
            s.ensure_filter(len);
            // One shadow ray at a time through the acceleration structure, in point order;
            // for a recorder in pass 4, where its events interleave with the others.
            for i in 0..len {
                if s.facing[i] == Facing::Towards && !R::RECORDS {
                    let inc = s.lanes.incidence(i, point_color);
                    s.filter[i] = self.shadow_filter_recorded(at.point, at.outward, at.err, &inc, None, rec);
                }
            }
        }
        // Pass 4, in point order.
        let blocked_shading = self.world.skips.on(Skip::BlockedShading);
        if !R::RECORDS && grouped && self.world.skips.on(Skip::BackFacing) {
            // The same sums and counts as below, without the events (what `not_facing`
            // counts, counted in bulk), member by member: the same terms summed in the same
            // order. The points that add to the sum marked, and everything counted, in loops
            // without a branch per point (their pattern is random) that vectorize. A facing
            // point's filter is 0 where an opaque object blocks it, or (rarely: see
            // `zero_product`) where its transparent colours multiply to 0; comparing every
            // filter instead costs a fifth of an N = 1000 render.
            s.adds.resize(len, false);
            let mut lit = 0u32;
            if s.zero_product {
                let points = s.facing.iter().zip(&s.blocked).zip(&s.filter).zip(&mut s.adds);
                for (((&f, &blocked), filter), add) in points {
                    // A blocked point's filter is 0, or not written (`blocked_unread`).
                    let zero = blocked | (*filter == DVec3::ZERO);
                    *add = (f == Facing::Towards) & !(blocked_shading & zero);
                    lit += u32::from(*add);
                }
            } else {
                lit = mark_adds(&s.facing, &s.blocked, blocked_shading, &mut s.adds);
            }
            let lit = u64::from(lit);
            let blocked = towards - lit;
            let saved = &mut self.counts.saved;
            saved.count(Skip::BlockedShading, blocked);
            saved.count(Skip::BackFacing, away * u64::from(shadows));
            saved.count(Skip::Unlit, black * u64::from(shadows));
            // Lanes with the same count, the same shading and the same sum so far end with
            // the same sum; the specular terms are computed again only for another exponent.
            let bits = |c: DVec3| c.to_array().map(f64::to_bits);
            // (count, shading twin, sum before as bits) and the sum after, per member done.
            let mut done: [Option<(MemberKey, DVec3)>; K] = [None; K];
            let mut speculars_for = None;
            // Every point that adds has filter 1 unless a transparent object tinted one, or
            // blocked points add their 0.
            let filter = (s.filter_ready && (s.tinted || !blocked_shading)).then_some(&s.filter[..]);
            for j in members_of::<K>(mask) {
                let (count, member_color) = self.member_points(j, index, area, len);
                let (model, mat) = self.member_shading(j, at.object);
                let key = (count, self.shading_twin[j], bits(color[j]));
                if let Some(d) = done.iter().flatten().find(|d| d.0 == key) {
                    color[j] = d.1;
                } else if lit > 0 {
                    let exponent = (model.specular, mat.shininess.to_bits());
                    if speculars_for != Some(exponent) {
                        speculars(&mut s.lanes, len, at.n, at.eye, mat, model);
                        speculars_for = Some(exponent);
                    }
                    let refl = at.reflectance(mat);
                    color[j] = lane_sum(color[j], &s.lanes, member_color, filter, &s.adds[..count], &refl, model);
                }
                done[j] = Some((key, color[j]));
                if K > 1 && count < len {
                    if black > 0 {
                        // A member with fewer points sees each brighter (`L / N`) than the
                        // dimmest colour the shared facings used; they can differ only where
                        // that made black points (so the unlit skip is on). If they do, the
                        // family is rendered image by image.
                        s.member_facing.resize(count, Facing::NoLight);
                        facings(&s.lanes, member_color, true, &mut s.member_facing[..count]);
                        self.diverged |= s.member_facing[..count] != s.facing[..count];
                    }
                    let own = count_facing(&s.facing[..count], Facing::Towards);
                    self.shadow_excess[j] += towards - own;
                }
            }
            return;
        }
        debug_assert!(K == 1, "a family is traced without a recorder, with every skip on");
        let color = &mut color[0];
        let (model, mat) = self.member_shading(0, at.object);
        s.ensure_filter(len);
        speculars(&mut s.lanes, len, at.n, at.eye, mat, model);
        shares(&mut s.lanes, len, point_color, &s.filter, &at.reflectance(mat), model);
        for i in 0..len {
            let n_dot_l = s.lanes.n_dot_l[i];
            if s.facing[i] != Facing::Towards {
                let inc = (s.lanes.dist[i] != 0.0).then(|| s.lanes.incidence(i, point_color));
                self.not_facing(index, s.facing[i], inc.as_ref(), n_dot_l, at, candidates, rec);
                continue;
            }
            let inc = s.lanes.incidence(i, point_color);
            if grouped {
                rec.shadow_ray(&at.ray_along(inc.to_light), inc.distance);
                if R::RECORDS && !s.blocked[i] && self.walks_transparent() {
                    rec.shadow_crossed(&s.crossed[i]);
                }
            } else if shadows && R::RECORDS {
                // Traced here, for the events' order; pass 3 has no filter for it.
                let filter = self.shadow_filter_recorded(at.point, at.outward, at.err, &inc, None, rec);
                *color += self.shade(0, index, &inc, n_dot_l, filter, at, rec);
                continue;
            }
            let filter = s.filter[i];
            let (diffuse, specular) = if filter == DVec3::ZERO && blocked_shading {
                self.counts.saved.count(Skip::BlockedShading, 1);
                (DVec3::ZERO, DVec3::ZERO)
            } else {
                let [dr, dg, db] = &s.lanes.diffuse;
                let [sr, sg, sb] = &s.lanes.specular;
                let diffuse = DVec3::new(dr[i], dg[i], db[i]);
                let specular = DVec3::new(sr[i], sg[i], sb[i]);
                *color += diffuse + specular;
                (diffuse, specular)
            };
            if R::RECORDS {
                rec.light(&LightShare {
                    light: index,
                    incidence: inc,
                    n_dot_l,
                    shadow_ray: shadows,
                    filter,
                    diffuse,
                    specular,
                });
            }
        }
    }

    /// How many of area light `index`'s `len` points member `j` takes, and the colour `L / N`
    /// each of them carries for it: all of them, unless the member sets its own count.
    fn member_points(&self, j: usize, index: usize, area: &AreaLight, len: usize) -> (usize, DVec3) {
        match self.members[j].area_count {
            Some((light, count)) if light == index && (count as usize) < len => {
                (count as usize, area.point_color_of(count))
            }
            _ => (len, area.point_color()),
        }
    }

    /// Whether an unblocked shadow ray goes on to find the transparent objects it crosses
    /// (not when the scene has none and the opaque-only shortcut is on).
    fn walks_transparent(&self) -> bool {
        self.world.has_transparent || !self.world.skips.on(Skip::OpaqueOnly)
    }
}

/// What [`lane_sum`] reads, for its blocks of points.
struct SumTerms<'a> {
    factors: &'a ShareFactors,
    atten: &'a [f64],
    n_dot_l: &'a [f64],
    spec: &'a [f64],
    adds: &'a [bool],
}

/// How many points [`lane_sum`] takes at a time: their terms fit in the L1 cache.
const SUM_BLOCK: usize = 64;

impl SumTerms<'_> {
    /// Adds to `sum` the terms of the points `start .. start + len` (`len <= SUM_BLOCK`)
    /// that add, in point order, with point `i`'s filter in channel `c` `filter(i, c)`.
    /// Inlined into each of [`lane_sum`]'s versions, with its target features.
    #[inline(always)]
    fn add(
        &self,
        start: usize,
        len: usize,
        filter: impl Fn(usize, usize) -> f64,
        total: &mut [[f64; SUM_BLOCK]; 3],
        sum: DVec3,
    ) -> DVec3 {
        let block = start..start + len;
        let (atten, n_dot_l) = (&self.atten[block.clone()], &self.n_dot_l[block.clone()]);
        let (spec, adds) = (&self.spec[block.clone()], &self.adds[block]);
        // The terms, a loop over the points that vectorizes...
        for (c, total) in total.iter_mut().enumerate() {
            for l in 0..len {
                let (d, s) = self
                    .factors
                    .terms(c, atten[l], filter(start + l, c), n_dot_l[l], spec[l]);
                // A point that does not add adds `+0`: all bits cleared, not a product with
                // 0 (NaN for an infinite term), and no branch on a random pattern. Adding
                // `+0` leaves every sum but `-0` unchanged, and these sums start at `+0`
                // (`DVec3::ZERO`), which in round-to-nearest no addition turns into `-0`.
                total[l] = f64::from_bits((d + s).to_bits() & 0u64.wrapping_sub(u64::from(adds[l])));
            }
        }
        // ... then the sums, one addition after the other, in registers.
        let [tr, tg, tb] = &*total;
        let (mut r, mut g, mut b) = (sum.x, sum.y, sum.z);
        for l in 0..len {
            r += tr[l];
            g += tg[l];
            b += tb[l];
        }
        DVec3::new(r, g, b)
    }
}

/// Marks in `adds` the points that add to the sum: those facing the surface, but for
/// the blocked ones (`blocked`) when `skip_blocked`; returns how many. A lane loop over
/// bytes, in versions for AVX-512 and AVX2 chosen at run time (64 or 32 points a vector).
#[multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn mark_adds(facing: &[Facing], blocked: &[bool], skip_blocked: bool, adds: &mut [bool]) -> u32 {
    let len = facing.len();
    let (blocked, adds) = (&blocked[..len], &mut adds[..len]);
    let mut count = 0;
    for i in 0..len {
        adds[i] = (facing[i] == Facing::Towards) & !(skip_blocked & blocked[i]);
    }
    // Counted in bytes, a few vectors' worth at a time (at most 255 a byte lane).
    for chunk in adds.chunks(128) {
        count += u32::from(chunk.iter().fold(0u8, |n, &a| n + u8::from(a)));
    }
    count
}

/// How many of `facing` are `kind`; as [`mark_adds`], a lane loop over bytes (counted in
/// bytes, a few vectors' worth at a time: at most 255 a byte lane).
#[multiversion(targets("x86_64+avx512f", "x86_64+avx2"))]
fn count_facing(facing: &[Facing], kind: Facing) -> u64 {
    let mut count = 0;
    for chunk in facing.chunks(128) {
        count += u64::from(chunk.iter().fold(0u8, |n, &f| n + u8::from(f == kind)));
    }
    count
}

/// Lists in `open` the `towards` points facing the surface, without a branch per point
/// (their pattern is random). A function of its own: inlined into its caller, the list's
/// pointer is reloaded from the stack at every point.
#[inline(never)]
fn list_facing(facing: &[Facing], towards: usize, open: &mut Vec<u32>) {
    if towards == facing.len() {
        // Every point, as for most surfaces that see the whole light.
        open.clear();
        open.extend(0..facing.len() as u32);
        return;
    }
    open.resize(facing.len() + 1, 0);
    let mut count = 0;
    for (i, &f) in facing.iter().enumerate() {
        // `count <= i < len + 1`: in bounds.
        open[count] = i as u32;
        count += usize::from(f == Facing::Towards);
    }
    debug_assert_eq!(count, towards);
    open.truncate(count);
}

/// What makes two members' sums of one area light equal: their point count, their shading
/// (its first member) and the bits of their sums before it.
type MemberKey = (usize, usize, [u64; 3]);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::point_incidence;
    use crate::sampling::unit_interval;
    use crate::shading::{blinn, phong, specular_tint};
    use rand_chacha::ChaCha8Rng;
    use rand_core::{Rng, SeedableRng};

    /// Pass 1's lanes for `set` seen from `p` with normal `n`, after checking that the
    /// facings decided in its loop are those [`facings`] decides from the lanes, for the
    /// unlit skip on and off.
    pub(super) fn lanes_of(set: &PointSet, (p, n): (DVec3, DVec3), att: &Attenuation, point_color: DVec3) -> Lanes {
        let mut lanes = Lanes::default();
        lanes.resize(set.len());
        for unlit_skip in [true, false] {
            let mut fused = vec![Facing::NoLight; set.len()];
            let counts = incidences(set, (p, n), att, (point_color, unlit_skip), &mut lanes, &mut fused);
            let mut apart = vec![Facing::NoLight; set.len()];
            assert_eq!(counts, facings(&lanes, point_color, unlit_skip, &mut apart));
            assert_eq!(fused, apart);
        }
        lanes
    }

    /// Passes 1 and 3 give, bit for bit, what the one-light formulas give point by point.
    #[test]
    fn lanes_are_the_point_light_formulas_bit_for_bit() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut uniform = |lo: f64, hi: f64| lo + (hi - lo) * unit_interval(rng.next_u64());
        let mut points = Vec::new();
        for _ in 0..257 {
            points.push(DVec3::new(uniform(-5.0, 5.0), uniform(-5.0, 5.0), uniform(0.0, 12.0)));
        }
        let set = PointSet::from_points(&points);
        let att = Attenuation {
            constant: 1.0,
            linear: 0.3,
            quadratic: 0.005,
        };
        let p = DVec3::new(0.3, -1.7, 0.2);
        let n = DVec3::new(0.1, -0.2, 1.0).normalize();
        let eye = DVec3::new(-0.3, -0.8, 0.6).normalize();
        let point_color = DVec3::new(0.01, 0.02, 0.005);
        let filter: Vec<DVec3> = (0..points.len())
            .map(|i| [DVec3::ONE, DVec3::ZERO, DVec3::new(0.6, 0.27, 0.08)][i % 3])
            .collect();
        for (model_specular, metal, shininess) in [
            (Specular::Blinn, 0.0, 20.0),
            (Specular::Blinn, 1.0, 21.0),
            (Specular::Blinn, 0.0, 0.0),
            (Specular::Phong, 0.5, 7.5),
        ] {
            let mat = Material {
                color: DVec3::new(0.85, 0.5, 0.2),
                metal,
                shininess,
                ..Material::default()
            };
            let model = ShadingModel {
                ambient: true,
                diffuse: true,
                specular: model_specular,
                no_light: false,
            };
            let lanes = &mut lanes_of(&set, (p, n), &att, point_color);
            speculars(lanes, points.len(), n, eye, &mat, model);
            shares(
                lanes,
                points.len(),
                point_color,
                &filter,
                &mat.reflectance(|| (0.0, 0.0)),
                model,
            );
            for (i, &q) in points.iter().enumerate() {
                let inc = point_incidence(q, point_color, &att, p, 1.0).unwrap();
                assert_eq!(lanes.incidence(i, point_color), inc, "point {i}");
                let n_dot_l = n.dot(inc.to_light);
                assert_eq!(lanes.n_dot_l[i], n_dot_l);
                let spec = match model_specular {
                    Specular::Blinn => blinn(n, inc.to_light, eye, shininess),
                    _ => phong(n, inc.to_light, eye, shininess),
                };
                let light = inc.color * filter[i];
                let tint = specular_tint(mat.metal, mat.color);
                let diffuse = diffuse(light, mat.kd, mat.color, n_dot_l);
                let spec_term = specular(light, mat.ks, tint, spec);
                let [dr, dg, db] = &lanes.diffuse;
                let [sr, sg, sb] = &lanes.specular;
                assert_eq!(DVec3::new(dr[i], dg[i], db[i]), diffuse, "point {i}");
                assert_eq!(DVec3::new(sr[i], sg[i], sb[i]), spec_term, "point {i}");
            }
        }
    }

    /// [`facings`] decides every point as [`Facing::of`] does with the colour `L / N * A`
    /// compared channel by channel, for colours with zero, tiny and negative channels and
    /// attenuations that make a channel underflow, zero, NaN or infinite.
    #[test]
    fn facings_are_the_channel_by_channel_decision() {
        let tiny = f64::from_bits(1); // the least subnormal
        let atten = [
            1.0,
            0.5,
            0.0,
            -0.0,
            1e-300,
            1e-310,
            tiny,
            f64::MIN_POSITIVE,
            f64::NAN,
            f64::INFINITY,
            3e-8,
        ];
        let colors = [
            DVec3::new(0.01, 0.02, 0.005),
            DVec3::new(0.0, 1e-10, 0.0),
            DVec3::new(1e-10, 1e-300, 2e-300),
            DVec3::ZERO,
            DVec3::new(tiny, 0.0, 0.5 * f64::MIN_POSITIVE),
            DVec3::new(-0.25, 0.0, 1e-300),
            DVec3::new(0.3, f64::NAN, 0.0),
        ];
        let len = atten.len() * 3;
        let mut lanes = Lanes::default();
        lanes.resize(len);
        for i in 0..len {
            lanes.atten[i] = atten[i % atten.len()];
            lanes.dist[i] = [1.0, 0.0, 2.5][i / atten.len()];
            lanes.n_dot_l[i] = [0.5, -0.5, 0.0][(i / 2) % 3];
        }
        for color in colors {
            for unlit_skip in [true, false] {
                let mut out = vec![Facing::NoLight; len];
                let counts = facings(&lanes, color, unlit_skip, &mut out);
                let mut want_counts = [0; 3];
                for (i, &got) in out.iter().enumerate() {
                    let c = arriving(color, lanes.atten[i], 1.0);
                    let zero = c.x == 0.0 && c.y == 0.0 && c.z == 0.0;
                    let want = Facing::of(lanes.dist[i] != 0.0, unlit_skip && zero, lanes.n_dot_l[i]);
                    assert_eq!(got, want, "colour {color}, A = {:e}", lanes.atten[i]);
                    for (k, f) in [Facing::Towards, Facing::Away, Facing::Black].into_iter().enumerate() {
                        want_counts[k] += u64::from(want == f);
                    }
                }
                assert_eq!(counts, want_counts, "colour {color}");
            }
        }
        // The black points are there to be found: a colour of 1e-300 under A = 1e-300.
        let mut out = vec![Facing::NoLight; len];
        let [_, _, black] = facings(&lanes, DVec3::splat(1e-300), true, &mut out);
        assert!(black > 0);
    }

    /// [`mark_adds`] and [`count_facing`] give, for counts past a byte and lengths past
    /// their chunks of 128, the marks and counts of the point-by-point definitions: every
    /// point facing and none blocked (all 300 add), and a mixed pattern with and without
    /// the blocked points skipped.
    #[test]
    fn adds_are_marked_and_counted_as_point_by_point() {
        let all = vec![Facing::Towards; 300];
        let mut adds = vec![false; 300];
        assert_eq!(mark_adds(&all, &[false; 300], true, &mut adds), 300);
        assert!(adds.iter().all(|&a| a));
        assert_eq!(count_facing(&all, Facing::Towards), 300);
        assert_eq!(count_facing(&all[..129], Facing::Towards), 129);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let kinds = [Facing::NoLight, Facing::Black, Facing::Away, Facing::Towards];
        let facing: Vec<Facing> = (0..1000).map(|_| kinds[(rng.next_u64() % 4) as usize]).collect();
        let blocked: Vec<bool> = (0..1000).map(|_| rng.next_u64() % 3 == 0).collect();
        for skip_blocked in [true, false] {
            let want: Vec<bool> = (0..1000)
                .map(|i| facing[i] == Facing::Towards && !(skip_blocked && blocked[i]))
                .collect();
            let mut adds = vec![true; 1000];
            let count = mark_adds(&facing, &blocked, skip_blocked, &mut adds);
            assert_eq!(adds, want);
            assert_eq!(count as usize, want.iter().filter(|&&a| a).count());
            assert!(count > 100 && count < 400, "a mixed pattern: {count} of 1000");
        }
        for len in [0, 1, 127, 128, 129, 1000] {
            for kind in kinds {
                let want = facing[..len].iter().filter(|&&f| f == kind).count() as u64;
                assert_eq!(count_facing(&facing[..len], kind), want, "{len} points, {kind:?}");
            }
        }
    }

    /// The fused pass 3 and 4 ([`lane_sum`]) gives the bits of [`shares`] followed by a
    /// sum in point order of the points that add, with and without the filters, for a
    /// count that is not a multiple of the block or of a vector.
    #[test]
    fn lane_sum_is_shares_summed_in_point_order() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut uniform = |lo: f64, hi: f64| lo + (hi - lo) * unit_interval(rng.next_u64());
        let len = 2 * SUM_BLOCK + 37;
        let points: Vec<DVec3> = (0..len)
            .map(|_| DVec3::new(uniform(-5.0, 5.0), uniform(-5.0, 5.0), uniform(0.0, 12.0)))
            .collect();
        let adds: Vec<bool> = (0..len).map(|_| uniform(0.0, 1.0) < 0.7).collect();
        let set = PointSet::from_points(&points);
        let att = Attenuation {
            constant: 1.0,
            linear: 0.0,
            quadratic: 0.005,
        };
        let (p, n) = (DVec3::new(0.3, -1.7, 0.2), DVec3::new(0.1, -0.2, 1.0).normalize());
        let eye = DVec3::new(-0.3, -0.8, 0.6).normalize();
        let point_color = DVec3::splat(1.0 / len as f64);
        let mat = Material {
            color: DVec3::new(0.85, 0.5, 0.2),
            ..Material::default()
        };
        let model = ShadingModel {
            ambient: true,
            diffuse: true,
            specular: Specular::Blinn,
            no_light: false,
        };
        let tinted: Vec<DVec3> = (0..len)
            .map(|i| [DVec3::ONE, DVec3::ZERO, DVec3::new(0.6, 0.27, 0.08)][i % 3])
            .collect();
        let mut lanes = lanes_of(&set, (p, n), &att, point_color);
        speculars(&mut lanes, len, n, eye, &mat, model);
        let start = DVec3::new(0.25, 0.125, 0.0);
        for filter in [Some(&tinted[..]), None] {
            let ones = vec![DVec3::ONE; len];
            shares(
                &mut lanes,
                len,
                point_color,
                filter.unwrap_or(&ones),
                &mat.reflectance(|| (0.0, 0.0)),
                model,
            );
            let [dr, dg, db] = &lanes.diffuse;
            let [sr, sg, sb] = &lanes.specular;
            let mut want = start;
            for i in (0..len).filter(|&i| adds[i]) {
                want += DVec3::new(dr[i] + sr[i], dg[i] + sg[i], db[i] + sb[i]);
            }
            let got = lane_sum(
                start,
                &lanes,
                point_color,
                filter,
                &adds,
                &mat.reflectance(|| (0.0, 0.0)),
                model,
            );
            assert_eq!(got.to_array().map(f64::to_bits), want.to_array().map(f64::to_bits));
            assert!(got.x > start.x + 1e-3, "the points add light: {got}");
        }
    }
}
