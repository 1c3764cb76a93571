//! Light sources of chapter 7.4b: ambient, directional, point and spotlight, with the area
//! lights of N points and SIMRenderer's interference (aperture) lights. For a shading
//! point each light yields the direction and distance to test with a shadow ray and the
//! light colour arriving there before shadowing (colour x attenuation x spot factor; for an
//! aperture light, colour x amplification x attenuation x relative intensity).

use crate::math::length;
pub use crate::shading::Attenuation;
use crate::shading::{Channels, largest_spot_factor, spot_factor};
use glam::DVec3;

/// A point light (also one point of an area light).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PointLight {
    pub position: DVec3,
    pub color: DVec3,
    pub attenuation: Attenuation,
}

/// A spotlight: a point light restricted to a cone of opening `theta` around `orientation`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SpotLight {
    pub position: DVec3,
    /// Unit central orientation `o`.
    pub orientation: DVec3,
    /// Opening angle `theta` in degrees, in [0, 180].
    pub angle_deg: f64,
    /// `cos(theta / 2)`, precomputed.
    pub cos_half: f64,
    pub c_min: f64,
    pub c_max: f64,
    pub color: DVec3,
    pub attenuation: Attenuation,
}

impl SpotLight {
    pub fn new(
        position: DVec3,
        orientation: DVec3,
        angle_deg: f64,
        c_min: f64,
        c_max: f64,
        color: DVec3,
        attenuation: Attenuation,
    ) -> Self {
        SpotLight {
            position,
            orientation: orientation.normalize(),
            angle_deg,
            cos_half: libm::cos(angle_deg.to_radians() * 0.5),
            c_min,
            c_max,
            color,
            attenuation,
        }
    }
}

/// Every kind of light.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Light {
    /// Uniform ambient light `L_a`; counted once, however many lights there are.
    Ambient {
        color: DVec3,
    },
    /// Light from a constant unit direction `d` (`L = -d`), no attenuation, no position.
    Directional {
        direction: DVec3,
        color: DVec3,
    },
    Point(PointLight),
    Spot(SpotLight),
    /// N point lights spread over a sphere, tube or window (see [`crate::area_light`]).
    Area(crate::area_light::AreaLight),
    /// Coherent oscillators over an aperture (see [`crate::interference`]): shadowed from
    /// its centre, it adds its arriving light whatever the material.
    Aperture(crate::interference::ApertureLight),
}

/// What one light point sends towards a shading point, before the shadow test.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Incidence {
    /// Unit vector from the shading point to the light, `L`.
    pub to_light: DVec3,
    /// Distance to the light (`t_max` of the shadow ray); infinite for directional lights.
    pub distance: f64,
    /// Attenuation factor `A` (1 for directional lights).
    pub attenuation: f64,
    /// Spot factor `C_theta` (1 for lights that are not spots).
    pub spot: f64,
    /// `A C_theta L`, the colour reaching the point if nothing is in the way (for an
    /// aperture light, `L amplification A I`).
    pub color: DVec3,
}

impl Light {
    /// Incidence at `p`, or `None` for ambient lights and for a point exactly at the light.
    /// Outside a spot's cone the incidence is black (spot factor 0). Area lights
    /// have one incidence per point: see [`point_incidence`].
    #[inline]
    pub fn incidence(&self, p: DVec3) -> Option<Incidence> {
        self.incidence_with(p, spot_factor)
    }

    /// [`Light::incidence`] with a spotlight's angular factor computed by `spot` (the
    /// chapter's [`spot_factor`], or another falloff's with the same arguments).
    #[inline(always)]
    pub fn incidence_with(&self, p: DVec3, spot: fn(f64, f64, f64, f64) -> f64) -> Option<Incidence> {
        match self {
            Light::Ambient { .. } | Light::Area(_) => None,
            Light::Directional { direction, color } => Some(Incidence {
                to_light: -*direction,
                distance: f64::INFINITY,
                attenuation: 1.0,
                spot: 1.0,
                color: *color,
            }),
            Light::Point(l) => point_incidence(l.position, l.color, &l.attenuation, p, 1.0),
            Light::Spot(s) => {
                let to_p = p - s.position;
                let dist = to_p.length();
                if dist == 0.0 {
                    return None;
                }
                // d = (r_inter - r_lum) / |r_inter - r_lum|
                // Outside the cone c = 0: the light arrives black (the tracer skips it).
                let c = spot(s.orientation.dot(to_p / dist), s.cos_half, s.c_min, s.c_max);
                point_incidence(s.position, s.color, &s.attenuation, p, c)
            }
            Light::Aperture(a) => {
                let (to_light, distance) = direction_to(a.aperture.center(), p);
                if distance == 0.0 {
                    return None;
                }
                Some(Incidence {
                    to_light,
                    distance,
                    attenuation: a.attenuation.factor(distance),
                    spot: 1.0,
                    color: a.arriving(p, distance),
                })
            }
        }
    }

    /// The ambient colour `L_a` this light adds (zero for other lights).
    pub fn ambient(&self) -> DVec3 {
        match self {
            Light::Ambient { color } => *color,
            _ => DVec3::ZERO,
        }
    }

    /// Largest colour channel this light can deliver at any point (for depth control).
    pub fn max_intensity(&self) -> f64 {
        let (color, atten) = match self {
            Light::Ambient { color } | Light::Directional { color, .. } => (color, None),
            Light::Point(l) => (&l.color, Some(l.attenuation)),
            Light::Spot(s) => (&s.color, Some(s.attenuation)),
            // N points of colour L / N: at most L in all.
            Light::Area(a) => (&a.color, Some(a.attenuation)),
            // The relative intensity is at most 1 (N² / N² at an instant).
            Light::Aperture(a) => return a.color.max_element() * a.amplification * a.attenuation.largest(),
        };
        let spot_max = match self {
            Light::Spot(s) => largest_spot_factor(s.c_min, s.c_max),
            _ => 1.0,
        };
        // A is largest at d = 0 unless C_const = 0, where it is unbounded.
        let a_max = atten.map_or(1.0, |a| a.largest());
        color.max_element() * a_max * spot_max
    }
}

/// Incidence from a point at `light_pos` (chapter 7.4b's point light, `L = -d` with
/// `d = (r_inter - r_lum) / |r_inter - r_lum|`): the direction and distance of
/// [`direction_to`], the attenuation `A(d)` and the colour `A C_theta L` of
/// [`arriving`]. `None` when `p` is at the light.
pub fn point_incidence(light_pos: DVec3, color: DVec3, atten: &Attenuation, p: DVec3, spot: f64) -> Option<Incidence> {
    let (to_light, distance) = direction_to(light_pos, p);
    if distance == 0.0 {
        return None;
    }
    let a = atten.factor(distance);
    Some(Incidence {
        to_light,
        distance,
        attenuation: a,
        spot,
        color: arriving(color, a, spot),
    })
}

/// The unit direction `L = (q - p) / |q - p|` from `p` to the light point `q`, and the
/// distance `|q - p|` (the shadow ray's `t_max`). The division is one reciprocal and three
/// products: an area light of N points pays it N times per shading point. NaN directions
/// when `q = p`.
#[inline(always)]
pub fn direction_to(q: DVec3, p: DVec3) -> (DVec3, f64) {
    let to_light = q - p;
    let distance = length(to_light);
    (to_light * (1.0 / distance), distance)
}

/// What an aperture light of colour `color` adds at a point that faces its centre
/// (`N.L > 0`) and whose shadow ray lets `filter` through: its `arriving` light whole, or
/// nothing when the filtered colour `color × filter` is black. SIMRenderer counts such a
/// point as in shadow only then: a transparent object in the way does not tint the light,
/// and the material does not weigh it.
pub fn aperture_share(color: DVec3, filter: DVec3, arriving: DVec3) -> DVec3 {
    if color * filter == DVec3::ZERO {
        DVec3::ZERO
    } else {
        arriving
    }
}

/// The light arriving at a point before the shadow test (chapter 7.4b): `A C_theta L` for
/// a light of colour `L`, attenuation `A` and spot factor `C_theta` (1 for lights that are
/// not spots).
#[inline(always)]
pub fn arriving<C: Channels>(color: C, a: f64, spot: f64) -> C {
    color * (a * spot)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_light_attenuates_with_distance() {
        // Light at (0, 0, 10), C_quad 0.01, point at the origin: d = 10, A = 0.5.
        let l = Light::Point(PointLight {
            position: DVec3::new(0., 0., 10.),
            color: DVec3::ONE,
            attenuation: Attenuation {
                constant: 1.0,
                linear: 0.0,
                quadratic: 0.01,
            },
        });
        let i = l.incidence(DVec3::ZERO).unwrap();
        assert_eq!(i.to_light, DVec3::Z);
        assert_eq!(i.distance, 10.0);
        assert_eq!(i.color, DVec3::splat(0.5));
    }

    #[test]
    fn spot_light_cone() {
        // Spot at (0, 0, 10) pointing down, theta = 90 (cos 45 = 0.7071).
        let s = Light::Spot(SpotLight::new(
            DVec3::new(0., 0., 10.),
            -DVec3::Z,
            90.0,
            0.0,
            1.0,
            DVec3::ONE,
            Attenuation::NONE,
        ));
        // Straight below: full intensity.
        assert_eq!(s.incidence(DVec3::ZERO).unwrap().color, DVec3::ONE);
        // 5 off-axis at depth 10: o.d = 10/sqrt(125) = 0.8944272; t = (0.8944272 - 1)/(0.7071068 - 1)
        // = 0.3604481, C = 1 - t = 0.6395519.
        let c = s.incidence(DVec3::new(5., 0., 0.)).unwrap().spot;
        assert!((c - 0.639_551_9).abs() < 1e-7, "{c}");
        // 11 off-axis: o.d = 0.6727 < 0.7071, outside.
        let outside = s.incidence(DVec3::new(11., 0., 0.)).unwrap();
        assert_eq!((outside.spot, outside.color), (0.0, DVec3::ZERO));
    }

    #[test]
    fn an_aperture_light_arrives_whole_unless_its_filtered_colour_is_black() {
        let arriving = DVec3::new(0.25, 0.0, 0.0);
        let red = DVec3::X;
        assert_eq!(aperture_share(red, DVec3::ONE, arriving), arriving);
        // Yellow glass (0.5 0.5 0) leaves some red: the light arrives untinted.
        assert_eq!(aperture_share(red, DVec3::new(0.5, 0.5, 0.0), arriving), arriving);
        // Green glass leaves none; an opaque object none of anything.
        assert_eq!(aperture_share(red, DVec3::Y, arriving), DVec3::ZERO);
        assert_eq!(aperture_share(red, DVec3::ZERO, arriving), DVec3::ZERO);
    }

    #[test]
    fn an_aperture_light_incidence_is_from_its_centre() {
        use crate::interference::{Aperture, ApertureLight};
        // Two oscillators 0.1 mm apart at (0, 0, 1) +- 0.05 mm along x; the point below the
        // middle is equidistant: in phase, I = 1/2. A = 1 / (1 + 1) at d = 1.
        let a = ApertureLight::new(
            Aperture::Linear {
                start: DVec3::new(-5e-5, 0.0, 1.0),
                end: DVec3::new(5e-5, 0.0, 1.0),
            },
            633.0,
            2,
            10,
            3.0,
            Attenuation {
                constant: 1.0,
                linear: 1.0,
                quadratic: 0.0,
            },
        )
        .unwrap();
        let i = Light::Aperture(a.clone()).incidence(DVec3::ZERO).unwrap();
        assert_eq!((i.to_light, i.distance, i.attenuation), (DVec3::Z, 1.0, 0.5));
        let expected = a.color * (3.0 * 0.5 * 0.5);
        assert!((i.color - expected).abs().max_element() < 1e-15, "{}", i.color);
        // The largest channel of the colour (1.055 - 0.055, encoded red) times 3.
        assert_eq!(Light::Aperture(a.clone()).max_intensity(), a.color.max_element() * 3.0);
    }

    #[test]
    fn directional_light_has_no_distance() {
        let d = DVec3::new(1., 1., -1.).normalize();
        let l = Light::Directional {
            direction: d,
            color: DVec3::ONE,
        };
        let i = l.incidence(DVec3::new(123., -4., 0.)).unwrap();
        assert_eq!(i.to_light, -d);
        assert!(i.distance.is_infinite());
        assert_eq!(i.attenuation, 1.0);
    }
}
