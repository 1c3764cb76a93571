//! One-pass families: images whose scenes differ only in their recursion depth, in the
//! number `N` of points of one fixed area light (whose `N` points are the first `N` of one
//! sequence), in their shading (the model, and each material's `k_a`, `k_d`, `k_s`,
//! exponent and metal factor), or, without area lights, in their lights, rendered together. Each ray of the deepest, largest image is
//! traced once, and each shadow ray; each image (a member of the tracer) keeps its own
//! radiance, computed with exactly the operations a render of its scene alone performs, and
//! its own ray counts, so its bytes and counts are those of that render (tests/family.rs).
//! Depth 1 to 10 costs about what depth 10 alone costs; N = 1 ... 1000 shares the
//! incidences and shadow rays of N = 1000, and each N adds only its own shading sum; the
//! slides' 25 shading figures share their rays and shadow rays.
//!
//! Scenes without an area light may also differ in their lights (the lighting, directional,
//! attenuation and spotlight sets, and soft-shadows' hard shadows, are the reference scene
//! under eleven lightings): the family's world has the union of their lights, each member
//! shades with its own, in its own order, and counts only its own lights' shadow rays.
//!
//! Members are what differs; everything that shapes a ray (geometry, camera, image, seed,
//! colours, `k_r`, `k_t`, `n`, the area lights but for that one count) must be equal, or the
//! scenes are not grouped ([`group`]).

use crate::area_light::PointMode;
use crate::light::Light;
use crate::render::{RenderStats, render_rows_members};
use crate::scene::{Scene, ShadingModel, Specular};
use crate::trace::Member;
use crate::world::World;
use glam::DVec3;
use std::sync::atomic::AtomicBool;

/// The most images traced together in one pass (longer families are rendered in passes of
/// this many). A pass has 8 or 16 members, a short family's padded with copies of its last
/// member (which cost nothing: a member whose sum so far and count equal another's reuses it).
pub const MEMBERS_PER_PASS: usize = 16;

/// The scene with what may vary within a family set to zero: the depth, every fixed area
/// light's count, the shading (model; each material's `k_a`, `k_d`, `k_s`, exponent and
/// metal factor, which shape no ray), and, in a scene without area lights, the lights.
/// Scenes that can be traced together have equal keys.
fn key(scene: &Scene) -> Scene {
    let mut key = scene.clone();
    key.settings.depth = 0;
    key.settings.shading = ShadingModel {
        ambient: false,
        diffuse: false,
        specular: Specular::None,
        no_light: false,
    };
    for m in &mut key.materials {
        (m.ka, m.kd, m.ks, m.shininess, m.metal) = (0.0, 0.0, 0.0, 0.0, 0.0);
    }
    if !has_area_light(scene) {
        // Each member shades with its own lights ([`light_union`]).
        key.lights.clear();
    }
    for light in &mut key.lights {
        if let Light::Area(a) = light
            && a.mode == PointMode::Fixed
        {
            a.count = 0;
        }
    }
    key
}

fn has_area_light(scene: &Scene) -> bool {
    scene.lights.iter().any(|l| matches!(l, Light::Area(_)))
}

/// The lights of one world for `members` without area lights, and the lights of each member
/// in it (as [`Member::lights`] bits): each member's lights but the ambient ones, in its
/// order, each matched to the first equal light of the union after the one its previous
/// light matched, or added at the end. So every member's lights keep their order (and each
/// member sums its lights' shares as a render of its scene alone does). `None` past 64 lights.
fn light_union(members: &[&Scene]) -> Option<(Vec<Light>, Vec<u64>)> {
    let mut union: Vec<Light> = Vec::new();
    let mut uses = Vec::with_capacity(members.len());
    for m in members {
        let (mut next, mut bits) = (0, 0u64);
        for light in m.lights.iter().filter(|l| !matches!(l, Light::Ambient { .. })) {
            let index = match union[next..].iter().position(|u| u == light) {
                Some(k) => next + k,
                None => {
                    union.push(light.clone());
                    union.len() - 1
                }
            };
            if index >= 64 {
                return None;
            }
            bits |= 1 << index;
            next = index + 1;
        }
        uses.push(bits);
    }
    Some((union, uses))
}

/// How one pass renders a family: its world's scene, the area light whose count varies
/// (if any), and the lights each member has ([`Member::lights`]).
struct Plan {
    scene: Scene,
    light: Option<usize>,
    lights: Vec<u64>,
}

/// The [`Plan`] of `members`, whose [`key`]s are equal; `Err` if one pass cannot render them.
fn plan(members: &[&Scene]) -> Result<Plan, ()> {
    if members.iter().any(|m| has_area_light(m)) {
        // Equal keys: every member has the same lights, but for area light counts.
        let light = varying_light(members)?;
        return Ok(Plan {
            scene: largest_scene(members, light),
            light,
            lights: vec![u64::MAX; members.len()],
        });
    }
    let (lights, uses) = light_union(members).ok_or(())?;
    let mut scene = largest_scene(members, None);
    scene.lights = lights;
    Ok(Plan {
        scene,
        light: None,
        lights: uses,
    })
}

/// The count of fixed area light `index` in `scene`, if it is one.
fn count_of(scene: &Scene, index: usize) -> Option<u32> {
    match &scene.lights[index] {
        Light::Area(a) if a.mode == PointMode::Fixed => Some(a.count),
        _ => None,
    }
}

/// Groups `scenes` (by index, each group ascending, groups in order of their first member)
/// into families that one pass can render: equal but for depth, shading, and the count of at
/// most one fixed area light, whose points for every member's count are a prefix of the
/// largest count's, or, without area lights, their lights. A scene that fits no family is a
/// group of its own.
pub fn group(scenes: &[&Scene]) -> Vec<Vec<usize>> {
    let keys: Vec<Scene> = scenes.iter().map(|s| key(s)).collect();
    let mut groups: Vec<Vec<usize>> = Vec::new();
    'next: for i in 0..scenes.len() {
        for g in &mut groups {
            let mut members: Vec<&Scene> = g.iter().map(|&m| scenes[m]).collect();
            members.push(scenes[i]);
            // A scene with caustics renders alone: its photons depend on its lights.
            let alone = members.iter().any(|m| m.settings.caustics.is_some());
            if !alone && keys[g[0]] == keys[i] && plan(&members).is_ok() {
                g.push(i);
                continue 'next;
            }
        }
        groups.push(vec![i]);
    }
    groups
}

/// The one area light whose count varies among `members` (`None` if none does), or `Err`
/// when more than one does or a member's points are not a prefix of the largest set.
fn varying_light(members: &[&Scene]) -> Result<Option<usize>, ()> {
    let first = members[0];
    let varying: Vec<usize> = (0..first.lights.len())
        .filter(|&i| members.iter().any(|m| count_of(m, i) != count_of(first, i)))
        .collect();
    match varying[..] {
        [] => Ok(None),
        [index] => {
            let largest = largest_scene(members, Some(index));
            let Light::Area(big) = &largest.lights[index] else {
                unreachable!("fixed area light")
            };
            let all = big.fixed_points(largest.settings.seed, index);
            let prefixes = members.iter().all(|m| match &m.lights[index] {
                Light::Area(a) => a.fixed_points(m.settings.seed, index)[..] == all[..a.count as usize],
                _ => false,
            });
            if prefixes { Ok(Some(index)) } else { Err(()) }
        }
        _ => Err(()),
    }
}

/// The scene of the family's world: the deepest depth and the largest count.
fn largest_scene(members: &[&Scene], light: Option<usize>) -> Scene {
    let mut scene = members[0].clone();
    scene.settings.depth = members.iter().map(|m| m.settings.depth).max().unwrap_or(0);
    if let Some(index) = light {
        let most = members.iter().filter_map(|m| count_of(m, index)).max().unwrap_or(0);
        if let Light::Area(a) = &mut scene.lights[index] {
            a.count = most;
        }
    }
    scene
}

/// Renders the members of one family (at most [`MEMBERS_PER_PASS`], as [`group`] formed them) in one
/// pass: each member's 8-bit RGB pixels and stats, or `None` when cancelled, when the
/// members diverged, or when one pass cannot hold them (a slice of a longer family may need
/// more than 64 lights where the whole did not, or one scene have more than 64): then render
/// them one by one.
pub fn render(members: &[&Scene], cancel: &AtomicBool) -> Option<Vec<(Vec<u8>, RenderStats)>> {
    assert!(
        !members.is_empty() && members.len() <= MEMBERS_PER_PASS,
        "1 to {MEMBERS_PER_PASS} members"
    );
    if members.len() <= 8 {
        render_pass::<8>(members, cancel)
    } else {
        render_pass::<MEMBERS_PER_PASS>(members, cancel)
    }
}

/// [`render`] with `K` members.
fn render_pass<const K: usize>(members: &[&Scene], cancel: &AtomicBool) -> Option<Vec<(Vec<u8>, RenderStats)>> {
    let Ok(Plan {
        scene: largest,
        light,
        lights,
    }) = plan(members)
    else {
        return None;
    };
    let world = World::new(&largest);
    let bounds: Vec<Vec<f64>> = members.iter().map(|m| World::remaining_bounds_of(m)).collect();
    let views: [Member; K] = std::array::from_fn(|j| {
        let m = j.min(members.len() - 1);
        Member {
            depth: members[m].settings.depth,
            remaining_bound: &bounds[m],
            area_count: light.and_then(|index| count_of(members[m], index).map(|n| (index, n))),
            shading: members[m].settings.shading,
            materials: &members[m].materials,
            lights: lights[m],
            ambient: members[m].ambient(),
        }
    });
    let h = largest.settings.height;
    let normalization = largest.settings.color_normalization;
    let quantise = |c: [DVec3; K]| c.map(|c| crate::film::rgb8(c, normalization));
    let (pixels, stats) = render_rows_members(&world, views, 0..h, &|| {}, Some(cancel), quantise);
    if cancel.load(std::sync::atomic::Ordering::Relaxed) || stats[0].diverged {
        return None;
    }
    let images = (0..members.len())
        .map(|j| {
            let rgb = pixels.iter().flat_map(|p| p[j]).collect();
            (rgb, stats[j].clone())
        })
        .collect();
    Some(images)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn directional(x: f64) -> Light {
        Light::Directional {
            direction: DVec3::new(x, 1.0, -1.0),
            color: DVec3::ONE,
        }
    }

    fn reference_with(lights: Vec<Light>) -> Scene {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/reference.toml");
        let mut scene = crate::scene::load(&path).expect("the reference scene loads");
        scene.lights = lights;
        scene
    }

    #[test]
    fn the_light_union_keeps_each_members_order() {
        // [a, b], [b, a], [a, a, b]: b after a matches a's b; a after b is a new entry; the
        // second a of [a, a, b] matches that one, and its b comes after it, new again.
        let (a, b) = (directional(1.0), directional(-1.0));
        let ambient = Light::Ambient { color: DVec3::ONE };
        let scenes = [
            reference_with(vec![ambient.clone(), a.clone(), b.clone()]),
            reference_with(vec![b.clone(), ambient, a.clone()]),
            reference_with(vec![a.clone(), a.clone(), b.clone()]),
        ];
        let (union, bits) = light_union(&scenes.iter().collect::<Vec<_>>()).unwrap();
        assert_eq!(union, vec![a.clone(), b.clone(), a, b]);
        assert_eq!(bits, vec![0b0011, 0b0110, 0b1101]);
    }

    #[test]
    fn past_64_lights_there_is_no_pass_and_no_panic() {
        let lights = |from: usize, to: usize| (from..to).map(|i| directional(i as f64)).collect::<Vec<_>>();
        let (first, second) = (reference_with(lights(0, 40)), reference_with(lights(40, 80)));
        assert_eq!(light_union(&[&first]).map(|(u, _)| u.len()), Some(40));
        assert!(light_union(&[&first, &second]).is_none());
        // So `group` keeps them apart, and a slice of a family (or one scene) that needs more
        // than 64 lights is not rendered in a pass: `render` says so instead of panicking.
        assert_eq!(group(&[&first, &second]), vec![vec![0], vec![1]]);
        let many = reference_with(lights(0, 65));
        assert!(render(&[&many], &AtomicBool::new(false)).is_none());
        assert_eq!(
            light_union(&[&reference_with(lights(0, 64))]).map(|(u, _)| u.len()),
            Some(64)
        );
    }
}
