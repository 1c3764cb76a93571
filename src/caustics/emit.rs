//! Where photons leave from. Every light but the ambient ones is split into emitters, one
//! per light point (a point light, a spot, each point of an area light, or a directional
//! light) and per *target*: a bounded object that reflects or refracts (`k_r > 0` or
//! `k_t > 0`). A point emitter aims uniformly into the cone of directions that meets the
//! target's bounding sphere; a directional one sends parallel rays through the disk the
//! sphere shows the light. An emitter is chosen with probability proportional to the power
//! its target intercepts, so each light's share follows its power; a photon whose first hit
//! is not its emitter's target is dropped (another emitter covers it), which keeps the
//! estimate unbiased where cones overlap.
//!
//! Units: a photon carries flux in the course's light units, so that photons landing
//! without being focused add up to the irradiance the chapter's diffuse term sees,
//! `A C_theta L cos(theta)` per unit area. A point source spreads its flux over `1 / s^2`
//! at distance `s`; its photon's flux is scaled by `A(s) s^2` where it lands
//! ([`Spread::factor`]), `s` the length of the whole path.
//!
//! Unbounded objects (planes) cannot be aimed at: they send no caustic photons. The points
//! of a `per_sample` area light are taken as its `fixed` points would be.

use crate::light::{Attenuation, Light};
use crate::math::{Frame, Ray, other_leg};
use crate::sampling::Stream;
use crate::scene::Scene;
use crate::shading::{largest_spot_factor, spot_factor};
use glam::DVec3;
use std::f64::consts::PI;

/// How a photon's flux falls off along its path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Spread {
    /// From a point: `A(s) s^2` at path length `s` (the `1 / s^2` of the spherical wave front
    /// replaced by the light's own attenuation `A`).
    Point(Attenuation),
    /// From a directional light: parallel rays, no fall-off.
    Parallel,
}

impl Spread {
    /// The factor at path length `s`.
    pub fn factor(&self, s: f64) -> f64 {
        match self {
            Spread::Point(a) => a.factor(s) * s * s,
            Spread::Parallel => 1.0,
        }
    }
}

/// A spot's cone: unit orientation, `cos(theta / 2)`, `C_min`, `C_max`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Cone {
    orientation: DVec3,
    cos_half: f64,
    c_min: f64,
    c_max: f64,
}

#[derive(Clone, Debug, PartialEq)]
enum Source {
    /// A point at `position`, aimed into the cone (`frame`'s z axis, `cos_max`) of the target.
    Point {
        position: DVec3,
        attenuation: Attenuation,
        spot: Option<Cone>,
        frame: Frame,
        cos_max: f64,
    },
    /// Parallel rays along `direction`, through the disk of `radius` about `center` seen from
    /// the light, starting `far` behind it (beyond every bounded object).
    Directional {
        direction: DVec3,
        frame: Frame,
        center: DVec3,
        radius: f64,
        far: f64,
    },
}

/// One light point aimed at one target.
#[derive(Clone, Debug, PartialEq)]
struct Emitter {
    source: Source,
    target: usize,
    /// Flux it sends at its target, before a spot's factor: `L omega` for a point (omega the
    /// cone's solid angle), `L pi r^2` for a directional light.
    emitted: DVec3,
}

/// The start of a photon's path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Start {
    pub ray: Ray,
    /// Flux of the photon as it leaves.
    pub flux: DVec3,
    pub spread: Spread,
    /// The object its first hit must be.
    pub target: usize,
}

/// The emitters of a scene and their cumulative selection weights.
#[derive(Clone, Debug, Default)]
pub struct Emitters {
    emitters: Vec<Emitter>,
    /// `cumulative[k]`: the sum of the weights of emitters `0..=k`.
    cumulative: Vec<f64>,
}

impl Emitters {
    /// The emitters of `scene`: the point-like lights' (points, spots, each point of an area
    /// light) in light order, then the directional lights'; each light's by target in object
    /// order.
    pub fn of(scene: &Scene) -> Emitters {
        let targets: Vec<(usize, DVec3, f64)> = scene
            .objects
            .iter()
            .enumerate()
            .filter(|(_, o)| {
                let m = &scene.materials[o.material()];
                m.kr > 0.0 || m.kt > 0.0
            })
            .filter_map(|(i, o)| o.shape.bounding_sphere().map(|(c, r)| (i, c, r)))
            .collect();
        // Beyond every bounded object: where a directional photon starts.
        let far = 2.0
            * scene
                .objects
                .iter()
                .filter_map(|o| o.shape.bounding_sphere())
                .map(|(c, r)| c.length() + r)
                .fold(1.0, f64::max);
        let mut emitters = Vec::new();
        let mut weights = Vec::new();
        let mut point = |position: DVec3, color: DVec3, attenuation: Attenuation, spot: Option<Cone>| {
            for &(target, center, radius) in &targets {
                let to_center = center - position;
                let dist = to_center.length();
                let (axis, cos_max) = if dist > radius {
                    let sin = radius / dist;
                    (to_center / dist, other_leg(sin))
                } else {
                    (DVec3::Z, -1.0)
                };
                let omega = 2.0 * PI * (1.0 - cos_max);
                let peak = spot.map_or(1.0, |s| largest_spot_factor(s.c_min, s.c_max));
                let reach = dist.max(radius);
                // The flux the target intercepts, at most: what sets the emitter's share.
                weights.push(color.element_sum() * peak * omega * attenuation.factor(reach) * reach * reach);
                emitters.push(Emitter {
                    source: Source::Point {
                        position,
                        attenuation,
                        spot,
                        frame: Frame::from_z(axis),
                        cos_max,
                    },
                    target,
                    emitted: color * omega,
                });
            }
        };
        let mut directional = Vec::new();
        for (index, light) in scene.lights.iter().enumerate() {
            match light {
                Light::Point(p) => point(p.position, p.color, p.attenuation, None),
                Light::Spot(s) => point(
                    s.position,
                    s.color,
                    s.attenuation,
                    Some(Cone {
                        orientation: s.orientation,
                        cos_half: s.cos_half,
                        c_min: s.c_min,
                        c_max: s.c_max,
                    }),
                ),
                Light::Area(a) => {
                    for q in a.fixed_points(scene.settings.seed, index) {
                        point(q, a.point_color(), a.attenuation, None);
                    }
                }
                Light::Directional { direction, color } => directional.push((*direction, *color)),
                // The ambient light has no position or direction to send photons from.
                _ => {}
            }
        }
        for (direction, color) in directional {
            for &(target, center, radius) in &targets {
                let area = PI * radius * radius;
                weights.push(color.element_sum() * area);
                emitters.push(Emitter {
                    source: Source::Directional {
                        direction,
                        frame: Frame::from_z(direction),
                        center,
                        radius,
                        far: far + center.length(),
                    },
                    target,
                    emitted: color * area,
                });
            }
        }
        let mut sum = 0.0;
        let cumulative = weights
            .iter()
            .map(|w| {
                sum += w;
                sum
            })
            .collect();
        Emitters { emitters, cumulative }
    }

    /// Whether no emitter sends any light.
    pub fn is_empty(&self) -> bool {
        self.cumulative.last().is_none_or(|&t| t <= 0.0)
    }

    /// Photon number `i`'s start, one of `n` photons in all, from its stream `rng`: an
    /// emitter chosen by weight, a direction (or a point of the disk) uniform in its cone,
    /// and the flux `emitted / (p n)` for the emitter's probability `p`, times a spot's
    /// factor in that direction. `None` when no emitter sends light.
    pub fn emit(&self, rng: &mut Stream, n: u64) -> Option<Start> {
        let total = *self.cumulative.last()?;
        if total <= 0.0 {
            return None;
        }
        let pick = rng.next_f64() * total;
        let k = self
            .cumulative
            .partition_point(|&c| c <= pick)
            .min(self.emitters.len() - 1);
        let weight = self.cumulative[k] - if k == 0 { 0.0 } else { self.cumulative[k - 1] };
        let e = &self.emitters[k];
        let share = e.emitted * (total / (weight * n as f64));
        let (u, v) = (rng.next_f64(), rng.next_f64());
        let (ray, spot, spread) = match &e.source {
            Source::Point {
                position,
                attenuation,
                spot,
                frame,
                cos_max,
            } => {
                let dir = frame.to_world(in_cone(*cos_max, u, v));
                let factor = spot.map_or(1.0, |s| {
                    spot_factor(s.orientation.dot(dir), s.cos_half, s.c_min, s.c_max)
                });
                (Ray::new(*position, dir), factor, Spread::Point(*attenuation))
            }
            Source::Directional {
                direction,
                frame,
                center,
                radius,
                far,
            } => {
                let (x, y) = in_disk(*radius, u, v);
                let origin = *center + frame.to_world(DVec3::new(x, y, 0.0)) - *direction * *far;
                (Ray::new(origin, *direction), 1.0, Spread::Parallel)
            }
        };
        Some(Start {
            ray,
            flux: share * spot,
            spread,
            target: e.target,
        })
    }
}

/// A direction uniform in the cone of half-angle `acos(cos_max)` about +z, from two uniform
/// numbers: `cos(theta) = 1 - u (1 - cos_max)`, `phi = 2 pi v` (uniform in solid angle,
/// since `d omega = d cos(theta) d phi`).
pub fn in_cone(cos_max: f64, u: f64, v: f64) -> DVec3 {
    let cos = 1.0 - u * (1.0 - cos_max);
    let sin = other_leg(cos);
    let phi = 2.0 * PI * v;
    DVec3::new(sin * libm::cos(phi), sin * libm::sin(phi), cos)
}

/// A point uniform in the disk of radius `r` about the origin: `rho = r sqrt(u)`,
/// `phi = 2 pi v` (uniform in area, since `dA = rho d rho d phi`).
pub fn in_disk(r: f64, u: f64, v: f64) -> (f64, f64) {
    let rho = r * u.sqrt();
    let phi = 2.0 * PI * v;
    (rho * libm::cos(phi), rho * libm::sin(phi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Purpose;

    #[test]
    fn directions_fill_the_cone_and_points_the_disk() {
        let mut rng = Stream::new(1, Purpose::Generator, 0);
        let cos_max = 0.8;
        let (mut inside_half, mut n) = (0, 0);
        for _ in 0..20_000 {
            let d = in_cone(cos_max, rng.next_f64(), rng.next_f64());
            assert!((d.length() - 1.0).abs() < 1e-12 && d.z >= cos_max - 1e-12);
            // Uniform in solid angle: the cap cos >= 0.9 holds (1 - 0.9) / (1 - 0.8) = half.
            inside_half += usize::from(d.z >= 0.9);
            n += 1;
        }
        let f = inside_half as f64 / n as f64;
        assert!((f - 0.5).abs() < 0.015, "{f}");
        // Uniform in area: the disk of radius r / 2 holds a quarter of the points.
        let quarter = (0..20_000)
            .filter(|_| {
                let (x, y) = in_disk(2.0, rng.next_f64(), rng.next_f64());
                assert!(x.hypot(y) <= 2.0);
                x.hypot(y) < 1.0
            })
            .count();
        assert!((quarter as f64 / 20_000.0 - 0.25).abs() < 0.015, "{quarter}");
    }

    #[test]
    fn spread_follows_the_attenuation_along_the_path() {
        // A(d) = 1 / (1 + 0.5 d + 0.25 d^2) at d = 2: 1 / 3, times d^2 = 4.
        let a = Attenuation {
            constant: 1.0,
            linear: 0.5,
            quadratic: 0.25,
        };
        assert!((Spread::Point(a).factor(2.0) - 4.0 / 3.0).abs() < 1e-15);
        assert_eq!(Spread::Parallel.factor(123.0), 1.0);
    }
}
