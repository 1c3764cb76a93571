//! The light blocks: ambient, directional and point lights, and the interference lights of
//! an aperture (a slit, a rectangle, an ellipse, a mask), each with SIMRenderer's defaults.

use super::keywords::{AMBIENT, APERTURE_MASK, DIRECTIONAL, LINEAR_APERTURE, PLANAR_APERTURE, POINT};
use super::values::{color, direction, int_in, number_in, point, positive, unit};
use super::{At, Reader, at, at_value};
use crate::interference::{Aperture, ApertureLight, Invalid, Mask, Planar, VISIBLE_NM};
use crate::light::{Attenuation, Light, PointLight};
use crate::limits;
use crate::scene::SceneError;
use crate::scene::rules::Syntax::SimRenderer;
use crate::scene::simrenderer::lex::{self, Line};
use glam::DVec3;
use std::collections::BTreeMap;

/// What every point and interference light reads alike: its amplification and its three
/// attenuators, SIMRenderer's defaults 1 and none.
struct Emission {
    amplification: f64,
    attenuation: Attenuation,
}

impl Emission {
    const DEFAULT: Emission = Emission {
        amplification: 1.0,
        attenuation: Attenuation::NONE,
    };
}

impl<'a> Reader<'a> {
    /// Reads `amplification` or one of the attenuators (`k`, a keyword of the light's list)
    /// into `emission`; `None` after a problem, the value before it kept.
    fn emission_value(
        &mut self,
        block: &str,
        l: &Line<'a>,
        k: &str,
        emission: &mut Emission,
    ) -> Result<Option<()>, SceneError> {
        if k == "amplification" {
            let read = self.value(block, l, number_in(l, 0.0, limits::MAX_LIGHT))?;
            return Ok(read.map(|a| emission.amplification = a));
        }
        let read = self.value(block, l, number_in(l, 0.0, 1e12))?;
        Ok(read.map(|x| match k {
            "constant_attenuator" => emission.attenuation.constant = x,
            "linear_attenuator" => emission.attenuation.linear = x,
            _ => emission.attenuation.quadratic = x,
        }))
    }

    /// Whether the attenuators leave the light finite: all three at 0 is a problem, at the
    /// constant attenuator's line or else at `place`, and the light is dropped.
    fn attenuation_allowed(
        &mut self,
        emission: &Emission,
        lines: &BTreeMap<&str, At>,
        place: &At,
    ) -> Result<bool, SceneError> {
        let a = emission.attenuation;
        if a.constant + a.linear + a.quadratic != 0.0 {
            return Ok(true);
        }
        let here = lines
            .get("constant_attenuator")
            .cloned()
            .unwrap_or_else(|| place.clone());
        let m = "the constant, linear and quadratic attenuators cannot all be 0".to_string();
        self.problem(&here, m, "the light is dropped")?;
        Ok(false)
    }

    pub(super) fn light(&mut self, open: &Line<'a>, kind: &str) -> Result<Option<Light>, SceneError> {
        let block = open.keyword.clone();
        let keywords = match kind {
            "ambient_light" => AMBIENT,
            "directional_light" => DIRECTIONAL,
            _ => POINT,
        };
        let mut color = DVec3::ONE;
        let mut orientation = DVec3::NEG_Z;
        let mut position = DVec3::ZERO;
        let mut emission = Emission::DEFAULT;
        let mut lines: BTreeMap<&str, At> = BTreeMap::new();
        while let Some((k, l)) = self.next_key(&block, keywords, None)? {
            let read = match k {
                "color" => self
                    .value(&block, &l, self::color(&l, limits::MAX_LIGHT))?
                    .map(|c| color = c),
                "orientation" => self.value(&block, &l, direction(&l))?.map(|d| orientation = d),
                "position" => self.value(&block, &l, point(&l))?.map(|p| position = p),
                _ => self.emission_value(&block, &l, k, &mut emission)?,
            };
            if read.is_some() {
                lines.insert(k, at(&l, &block));
            }
        }
        let place = at(open, "scene");
        let dropped = "the light is dropped";
        Ok(Some(match kind {
            "ambient_light" => Light::Ambient { color },
            "directional_light" => Light::Directional {
                direction: unit(orientation),
                color,
            },
            _ => {
                if !self.attenuation_allowed(&emission, &lines, &place)? {
                    return Ok(None);
                }
                // The amplification is folded into the colour.
                let amplified = color * emission.amplification;
                if amplified.max_element() > limits::MAX_LIGHT {
                    let here = lines.get("amplification").cloned().unwrap_or(place);
                    let m = format!(
                        "the colour times the amplification must stay at most {:e} per channel, got {}",
                        limits::MAX_LIGHT,
                        SimRenderer.vector(&amplified.to_array())
                    );
                    self.problem(&here, m, dropped)?;
                    return Ok(None);
                }
                Light::Point(PointLight {
                    position,
                    color: amplified,
                    attenuation: emission.attenuation,
                })
            }
        }))
    }

    /// An interference light (`crate::interference`), SIMRenderer's defaults: wave_length
    /// 550 nm, nb_oscillator 2, period_iteration 10, amplification 1, no attenuation; a
    /// slit from (0, 0, 0) to (0, 0.0001, 0); a planar aperture at the origin, front
    /// (0, 0, 1), up (0, 1, 0), 0.001 by 0.001, a mask `none` (every oscillator kept).
    pub(super) fn aperture_light(&mut self, open: &Line<'a>, kind: &str) -> Result<Option<Light>, SceneError> {
        let block = open.keyword.clone();
        let keywords = match kind {
            "linear_aperture_light" => LINEAR_APERTURE,
            "aperture_mask_light" => APERTURE_MASK,
            _ => PLANAR_APERTURE,
        };
        let mut ends = [DVec3::ZERO, DVec3::new(0.0, 1e-4, 0.0)];
        let mut ends_read = 0;
        let mut planar = Planar {
            center: DVec3::ZERO,
            front: DVec3::Z,
            up: DVec3::Y,
            width: 1e-3,
            height: 1e-3,
        };
        let mut mask: Option<Mask> = None;
        let (mut wavelength, mut count, mut steps) = (550.0, 2, 10);
        let mut emission = Emission::DEFAULT;
        let mut lines: BTreeMap<&str, At> = BTreeMap::new();
        while let Some((k, l)) = self.next_key(&block, keywords, None)? {
            let here = at(&l, &block);
            let read = match k {
                "color" => {
                    if self.value(&block, &l, self::color(&l, limits::MAX_LIGHT))?.is_some() {
                        let m = "an interference light's colour comes from its wave_length: SIMRenderer replaces this colour"
                            .to_string();
                        self.warn(&here, m);
                    }
                    None
                }
                "position" | "point" if kind == "linear_aperture_light" => {
                    let Some(p) = self.value(&block, &l, point(&l))? else {
                        continue;
                    };
                    if ends_read == 2 {
                        let m = "a slit has two ends, already given".to_string();
                        self.problem(&here, m, "the line is skipped")?;
                        continue;
                    }
                    if ends_read == 1 && p == ends[0] {
                        let m = format!(
                            "the second end must differ from the first, {}",
                            SimRenderer.vector(&p.to_array())
                        );
                        self.problem(&here, m, "the line is skipped")?;
                        continue;
                    }
                    ends[ends_read] = p;
                    ends_read += 1;
                    Some(())
                }
                "position" => self.value(&block, &l, point(&l))?.map(|p| planar.center = p),
                "front" => self.value(&block, &l, direction(&l))?.map(|d| planar.front = unit(d)),
                "up" => self.value(&block, &l, direction(&l))?.map(|d| planar.up = unit(d)),
                "width" | "height" => self.value(&block, &l, positive(&l, limits::MAX_COORDINATE))?.map(|x| {
                    if k == "width" {
                        planar.width = x;
                    } else {
                        planar.height = x;
                    }
                }),
                "mask" => {
                    let Some(file) = self.value(&block, &l, lex::name(l.value, l.value_column))? else {
                        continue;
                    };
                    if file == "none" {
                        mask = None;
                        Some(())
                    } else {
                        match Mask::read(&self.dir.join(&file), &file) {
                            Ok(m) => {
                                mask = Some(m);
                                Some(())
                            }
                            Err(m) => {
                                let place = at_value(&l, &block, l.value_column);
                                self.problem(&place, m, "the mask before it is kept")?;
                                None
                            }
                        }
                    }
                }
                "wave_length" => self
                    .value(&block, &l, number_in(&l, VISIBLE_NM.0, VISIBLE_NM.1))?
                    .map(|x| wavelength = x),
                "period_iteration" => self
                    .value(&block, &l, int_in(&l, 1, limits::MAX_PERIOD_ITERATION as i32))?
                    .map(|n| steps = n as u32),
                "nb_oscillator" => self
                    .value(&block, &l, int_in(&l, 1, limits::MAX_OSCILLATORS as i32))?
                    .map(|n| count = n as u32),
                _ => self.emission_value(&block, &l, k, &mut emission)?,
            };
            if read.is_some() {
                lines.insert(k, here);
            }
        }
        let place = at(open, "scene");
        let dropped = "the light is dropped";
        if !self.attenuation_allowed(&emission, &lines, &place)? {
            return Ok(None);
        }
        let aperture = match kind {
            "linear_aperture_light" => {
                if ends[0] == ends[1] {
                    let here = lines.get("position").or(lines.get("point")).cloned().unwrap_or(place);
                    let m = format!(
                        "the slit's ends must differ: the first is SIMRenderer's default second end {}",
                        SimRenderer.vector(&ends[1].to_array())
                    );
                    self.problem(&here, m, dropped)?;
                    return Ok(None);
                }
                Aperture::Linear {
                    start: ends[0],
                    end: ends[1],
                }
            }
            "rectangular_aperture_light" => Aperture::Rectangular(planar),
            "elliptical_aperture_light" => Aperture::Elliptical(planar),
            _ => Aperture::Mask { planar, mask },
        };
        match ApertureLight::new(
            aperture,
            wavelength,
            count,
            steps,
            emission.amplification,
            emission.attenuation,
        ) {
            Ok(light) => Ok(Some(Light::Aperture(light))),
            Err(invalid) => {
                let (key, m) = match invalid {
                    Invalid::Wavelength(m) => ("wave_length", m),
                    Invalid::Oscillators(m) => ("nb_oscillator", m),
                    Invalid::PeriodIteration(m) => ("period_iteration", m),
                    Invalid::Up(m) => ("up", m),
                };
                let here = lines.get(key).or(lines.get("front")).cloned().unwrap_or(place);
                self.problem(&here, format!("{key} {m}"), dropped)?;
                Ok(None)
            }
        }
    }
}
