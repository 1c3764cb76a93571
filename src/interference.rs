//! Interference lights (SIMRenderer's aperture lights): N coherent point oscillators of one
//! wavelength spread over a slit (linear), a rectangle, an ellipse or the open texels of a
//! mask image. At a point, the light's relative intensity is the time average of the
//! squared superposition of the oscillators' waves, divided by N². Its colour comes from
//! its wavelength. The facts, read in SIMRenderer's public sources, are these (the class
//! that states each one is named; scenes/README.md lists them with the keywords):
//!
//! - Each oscillator `j` at `o_j` sends `y_j(P, t) = sin(k r_j - ω t)` with
//!   `r_j = |P - o_j|`, amplitude 1 whatever the distance, `k = 2π / λ`, λ the wavelength
//!   in nm times 1e-9: scene lengths are metres (`SWave`, `SOscillator`,
//!   `SLinearApertureLight`).
//! - The relative intensity averages `(Σ_j y_j)²` over one period at `period_iteration`
//!   equally spaced instants `t_i = i T / period_iteration` and divides by N², N counting
//!   the oscillators built (`SWaveOptics.interferenceAverageWaveValue`,
//!   `SAbstractInterferenceLight.getRelativeIntensity`). With `S = Σ_j sin(k r_j)` and
//!   `C = Σ_j cos(k r_j)`, `Σ_j y_j(t_i) = S cos θ_i - C sin θ_i` with `θ_i = 2π i /
//!   period_iteration`; for 3 instants or more the average is `(S² + C²) / 2` exactly,
//!   so one oscillator gives 1/2 everywhere and N in phase give 1/2 as well. With no
//!   oscillator (a mask with no open texel) it is 0.
//! - A linear aperture's N oscillators run from its first end to its second, evenly
//!   spaced, both ends included; one oscillator sits at the middle (`SLinearApertureLight`).
//! - A planar aperture (rectangle, ellipse, mask) lies in the plane through its centre
//!   normal to `front`; `up` is made normal to `front` as `(front × up) × front`, and
//!   `right = front × up`. `nb_oscillator` oscillators run along its shorter side
//!   (`height` when the sides are equal), spacing `s = side / (N - 1)`; the other side has
//!   `ceil(other / s) + 1` of them, spaced to fill it exactly. The grid starts at the corner
//!   `center - right width/2 - up height/2`; a rectangle keeps every grid point, an ellipse
//!   those with `(x - w/2)² / (w/2)² + (y - h/2)² / (h/2)² <= 1 + 1e-10`, a mask those whose
//!   texel is pure white. One oscillator sits at the centre when the shape keeps that point
//!   (`SAbstractPlanarApertureLight`, `SEllipticalApertureLight`, `SGeometricUtil`,
//!   `SApertureMaskLight`).
//! - A mask texel for grid point `(x, y)` is column `floor(u (W - 1))`, row
//!   `floor(v (H - 1))` of the W x H image, `u = x / width`, `v = y / height`, row 0 at the
//!   top of the image: the image's top row falls on the aperture's lower edge (along
//!   `-up`). Coordinates beyond 1 wrap (`STexture`, `SVectorUV`, `STextureImageIOLoader`).
//! - The light's colour is the sRGB colour of its wavelength, 380 to 780 nm: the CIE 1931
//!   colour matching functions by the multi-lobe Gaussian fit of Wyman, Sloan and Shirley
//!   ("Simple Analytic Approximations to the CIE XYZ Color Matching Functions", JCGT 2(2),
//!   2013), then XYZ to linear sRGB (IEC 61966-2-1), each channel clamped to [0, 1] and
//!   encoded with the sRGB transfer curve (`SWaveOptics.wavelengthToSColor`).
//! - What the light adds at a point is `colour × amplification × A(d) × I(P)`, `A` the
//!   point-light attenuation at the distance `d` to the aperture's centre: no Lambert
//!   factor, no highlight, whatever the material. The point gets nothing when its normal
//!   faces away from the centre, or when the shadow ray towards the centre is black (an
//!   opaque object in the way, or transparent ones whose filter leaves none of the
//!   light's colour); transparent objects do not tint it
//!   (`SAbstractShader.shadeWithInterferenceLight`, `SShadowRay`).

use crate::film::srgb_encode;
use crate::limits;
use crate::shading::Attenuation;
use crate::texture::{repeat, texel_index};
use glam::DVec3;
use std::f64::consts::TAU;

/// SIMRenderer's visible range, in nm: the wavelengths a light's colour is defined for.
pub const VISIBLE_NM: (f64, f64) = (380.0, 780.0);

/// `SMath.EPSILON`: how far past 1 an ellipse's equation may go and keep a point.
const ON_ELLIPSE: f64 = 1e-10;

/// A planar aperture's frame and size as the scene gives them (`front` and `up` need not
/// be unit nor orthogonal: [`Planar::frame`] makes them so).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Planar {
    pub center: DVec3,
    pub front: DVec3,
    pub up: DVec3,
    pub width: f64,
    pub height: f64,
}

impl Planar {
    /// `(right, up)`, unit and orthogonal: `front` normalised, `up = (front × up) × front`
    /// normalised, `right = front × up`. `None` when `up` is parallel to `front`.
    pub fn frame(&self) -> Option<(DVec3, DVec3)> {
        let front = self.front.try_normalize()?;
        let up = front.cross(self.up).cross(front).try_normalize()?;
        let right = front.cross(up).try_normalize()?;
        Some((right, up))
    }
}

/// A mask image: which texels are open (pure white, 255 255 255), row 0 at the top.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Mask {
    /// The file as the scene names it.
    pub file: String,
    pub width: u32,
    pub height: u32,
    #[serde(skip)]
    pub open: Vec<bool>,
}

impl Mask {
    /// Reads a mask image (any format the image crate reads here: PNG, JPEG, BMP, TGA,
    /// PNM, EXR), converted to 8-bit RGB as SIMRenderer's Java image reader does.
    pub fn read(path: &std::path::Path, file: &str) -> Result<Mask, String> {
        let (width, height, rgb) = crate::texture::read_rgb8(path, "mask image")?;
        Ok(Mask {
            file: file.to_string(),
            width,
            height,
            open: rgb.chunks_exact(3).map(|p| p == [255, 255, 255]).collect(),
        })
    }

    /// Whether the texel at texture coordinates `(u, v)` is open (`STexture.getSColor`
    /// with the top-left origin, coordinates outside [0, 1] wrapped by repetition).
    fn open_at(&self, u: f64, v: f64) -> bool {
        self.open[texel_index(self.width, self.height, (repeat(u), repeat(v)))]
    }
}

/// Where the oscillators are.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "aperture", rename_all = "snake_case")]
pub enum Aperture {
    /// A slit from `start` to `end`.
    Linear {
        start: DVec3,
        end: DVec3,
    },
    Rectangular(Planar),
    Elliptical(Planar),
    /// A rectangle whose oscillators are kept where the mask is white (`None`: SIMRenderer's
    /// `none`, every one kept).
    Mask {
        planar: Planar,
        mask: Option<Mask>,
    },
}

impl Aperture {
    /// The point the light is placed at for its shadow ray and attenuation: the slit's
    /// middle, a planar aperture's centre.
    pub fn center(&self) -> DVec3 {
        match self {
            Aperture::Linear { start, end } => 0.5 * *start + 0.5 * *end,
            Aperture::Rectangular(p) | Aperture::Elliptical(p) | Aperture::Mask { planar: p, .. } => p.center,
        }
    }

    /// How many oscillators `nb_oscillator = n` builds before the shape keeps some: the
    /// grid's size for a planar aperture. Bounded before anything is allocated.
    pub fn grid_size(&self, n: u32) -> u64 {
        match self {
            Aperture::Linear { .. } => u64::from(n),
            Aperture::Rectangular(p) | Aperture::Elliptical(p) | Aperture::Mask { planar: p, .. } => {
                let (nx, ny, _, _) = grid(p, n);
                nx.saturating_mul(ny)
            }
        }
    }

    /// The oscillators' positions for `nb_oscillator = n` (n >= 1), in SIMRenderer's
    /// order; `None` when a planar aperture's `up` is parallel to its `front`.
    pub fn oscillators(&self, n: u32) -> Option<Vec<DVec3>> {
        match self {
            Aperture::Linear { start, end } => Some(if n == 1 {
                vec![self.center()]
            } else {
                let axis = *end - *start;
                let spacing = axis.length() / f64::from(n - 1);
                let dir = axis.normalize();
                (0..n).map(|i| *start + dir * (f64::from(i) * spacing)).collect()
            }),
            Aperture::Rectangular(p) => planar_oscillators(p, n, |_, _| true),
            Aperture::Elliptical(p) => planar_oscillators(p, n, |x, y| {
                let (a, b) = (p.width / 2.0, p.height / 2.0);
                let value =
                    (x - a) * (x - a) / (p.width * p.width / 4.0) + (y - b) * (y - b) / (p.height * p.height / 4.0);
                value <= 1.0 + ON_ELLIPSE
            }),
            Aperture::Mask { planar: p, mask } => planar_oscillators(p, n, |x, y| {
                mask.as_ref().is_none_or(|m| m.open_at(x / p.width, y / p.height))
            }),
        }
    }
}

/// A planar grid for `nb_oscillator = n >= 2`: `(nx, ny, spacing x, spacing y)`, `n` along
/// the shorter side (`height` when equal).
fn grid(p: &Planar, n: u32) -> (u64, u64, f64, f64) {
    if n < 2 {
        return (1, 1, 0.0, 0.0);
    }
    let n = u64::from(n);
    let others = |short: f64, long: f64| {
        let spacing = short / (n - 1) as f64;
        let count = (long / spacing).ceil() + 1.0;
        let count = if count.is_finite() && count < 1e18 {
            count as u64
        } else {
            u64::MAX
        };
        (spacing, count, long / (count.max(2) - 1) as f64)
    };
    if p.width < p.height {
        let (sx, ny, sy) = others(p.width, p.height);
        (n, ny, sx, sy)
    } else {
        let (sy, nx, sx) = others(p.height, p.width);
        (nx, n, sx, sy)
    }
}

/// The grid points `(x, y)` of a planar aperture (from its lower-left corner, x along
/// `right`, y along `up`) that `keep` admits, as world points, x outer and y inner.
fn planar_oscillators(p: &Planar, n: u32, keep: impl Fn(f64, f64) -> bool) -> Option<Vec<DVec3>> {
    let (right, up) = p.frame()?;
    if n == 1 {
        return Some(if keep(p.width / 2.0, p.height / 2.0) {
            vec![p.center]
        } else {
            Vec::new()
        });
    }
    let (nx, ny, sx, sy) = grid(p, n);
    let corner = p.center + right * (-p.width / 2.0) + up * (-p.height / 2.0);
    let mut out = Vec::new();
    for i in 0..nx {
        for j in 0..ny {
            let (x, y) = (i as f64 * sx, j as f64 * sy);
            if keep(x, y) {
                out.push(corner + right * x + up * y);
            }
        }
    }
    Some(out)
}

/// An interference light: its aperture, its wave, and what is derived from them (its colour
/// and its oscillators).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ApertureLight {
    pub aperture: Aperture,
    /// λ in nm, in [`VISIBLE_NM`].
    pub wavelength_nm: f64,
    /// `nb_oscillator`: along the slit, or along a planar aperture's shorter side.
    pub oscillator_count: u32,
    /// Instants the time average takes over one period.
    pub period_iteration: u32,
    pub amplification: f64,
    pub attenuation: Attenuation,
    /// The colour of the wavelength ([`wavelength_color`]).
    pub color: DVec3,
    #[serde(skip)]
    pub oscillators: Vec<DVec3>,
}

/// Why an aperture light cannot be built, by the value at fault.
#[derive(Clone, Debug, PartialEq)]
pub enum Invalid {
    Wavelength(String),
    /// `nb_oscillator`: out of range, or a planar grid too large.
    Oscillators(String),
    PeriodIteration(String),
    /// `up` parallel to `front`.
    Up(String),
}

impl ApertureLight {
    /// The light with its colour and oscillators; [`Invalid`] says which value is out of
    /// range: a wavelength outside [`VISIBLE_NM`], `nb_oscillator` outside [1,
    /// `MAX_OSCILLATORS`] or a planar grid of more than [`limits::MAX_OSCILLATORS`] points,
    /// `period_iteration` outside [1, [`limits::MAX_PERIOD_ITERATION`]], `up` parallel to
    /// `front`.
    pub fn new(
        aperture: Aperture,
        wavelength_nm: f64,
        oscillator_count: impl Into<limits::Whole>,
        period_iteration: impl Into<limits::Whole>,
        amplification: f64,
        attenuation: Attenuation,
    ) -> Result<Self, Invalid> {
        let color = wavelength_color(wavelength_nm).ok_or_else(|| {
            Invalid::Wavelength(format!(
                "must be a visible wavelength, in [{}, {}] nm, got {wavelength_nm}",
                VISIBLE_NM.0, VISIBLE_NM.1
            ))
        })?;
        let most = limits::MAX_OSCILLATORS;
        let oscillator_count: u32 = limits::check_count(oscillator_count, most as u32).map_err(Invalid::Oscillators)?;
        let grid = aperture.grid_size(oscillator_count);
        if grid > most {
            return Err(Invalid::Oscillators(format!(
                "{oscillator_count} along the shorter side make a grid of {grid} oscillators over this aperture, at most {most} are allowed"
            )));
        }
        let period_iteration =
            limits::check_count(period_iteration, limits::MAX_PERIOD_ITERATION).map_err(Invalid::PeriodIteration)?;
        let oscillators = aperture
            .oscillators(oscillator_count)
            .ok_or_else(|| Invalid::Up("must not be parallel to front".to_string()))?;
        Ok(ApertureLight {
            aperture,
            wavelength_nm,
            oscillator_count,
            period_iteration,
            amplification,
            attenuation,
            color,
            oscillators,
        })
    }

    /// `k = 2π / λ` with λ in metres.
    pub fn wavenumber(&self) -> f64 {
        TAU / (self.wavelength_nm * 1e-9)
    }

    /// The relative intensity `I(P)` of the light at `p` ([`relative_intensity`]).
    pub fn relative_intensity(&self, p: DVec3) -> f64 {
        relative_intensity(&self.oscillators, self.wavenumber(), self.period_iteration, p)
    }

    /// What the light adds at `p`, at distance `d` from the aperture's centre, when
    /// nothing blocks it: `colour × amplification × A(d) × I(p)`.
    pub fn arriving(&self, p: DVec3, d: f64) -> DVec3 {
        self.color * (self.amplification * self.attenuation.factor(d) * self.relative_intensity(p))
    }
}

/// The time-averaged squared superposition of the waves `sin(k r_j - ω t)` of oscillators
/// at `oscillators`, over `steps` equally spaced instants of one period, divided by N²:
/// `I = (1 / (steps N²)) Σ_i (S cos θ_i - C sin θ_i)²`, `θ_i = 2π i / steps`,
/// `S = Σ_j sin(k r_j)`, `C = Σ_j cos(k r_j)`, `r_j = |p - o_j|`. 0 without oscillators.
pub fn relative_intensity(oscillators: &[DVec3], k: f64, steps: u32, p: DVec3) -> f64 {
    if oscillators.is_empty() || steps == 0 {
        return 0.0;
    }
    let (mut s, mut c) = (0.0, 0.0);
    for o in oscillators {
        let (sin, cos) = libm::sincos(k * (p - *o).length());
        s += sin;
        c += cos;
    }
    let mut sum = 0.0;
    for i in 0..steps {
        let (sin_t, cos_t) = libm::sincos(TAU * f64::from(i) / f64::from(steps));
        let y = s * cos_t - c * sin_t;
        sum += y * y;
    }
    let n = oscillators.len() as f64;
    sum / f64::from(steps) / (n * n)
}

/// The sRGB colour of light of wavelength `nm` (in [`VISIBLE_NM`], else `None`): the CIE
/// 1931 matching functions by Wyman, Sloan and Shirley's multi-lobe fit (JCGT 2(2), 2013),
/// XYZ to linear sRGB by IEC 61966-2-1's matrix, clamped to [0, 1], then the sRGB transfer
/// curve.
pub fn wavelength_color(nm: f64) -> Option<DVec3> {
    if !(VISIBLE_NM.0..=VISIBLE_NM.1).contains(&nm) {
        return None;
    }
    // One lobe: a Gaussian of height `a` at `mu`, of inverse widths `below` and `above`.
    let lobe = |a: f64, mu: f64, below: f64, above: f64| {
        let t = (nm - mu) * if nm < mu { below } else { above };
        a * libm::exp(-0.5 * t * t)
    };
    let x =
        lobe(0.362, 442.0, 0.0624, 0.0374) + lobe(1.056, 599.8, 0.0264, 0.0323) - lobe(0.065, 501.1, 0.0490, 0.0382);
    let y = lobe(0.821, 568.8, 0.0213, 0.0247) + lobe(0.286, 530.9, 0.0613, 0.0322);
    let z = lobe(1.217, 437.0, 0.0845, 0.0278) + lobe(0.681, 459.0, 0.0385, 0.0725);
    let linear = DVec3::new(
        3.2406255 * x + -1.537208 * y + -0.4986286 * z,
        -0.9689307 * x + 1.8757561 * y + 0.0415175 * z,
        0.0557101 * x + -0.2040211 * y + 1.0569959 * z,
    );
    Some(linear.to_array().map(srgb_encode).into())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn planar(width: f64, height: f64) -> Planar {
        Planar {
            center: DVec3::new(0.0, 0.0, 1.0),
            front: DVec3::Z,
            up: DVec3::Y,
            width,
            height,
        }
    }

    #[test]
    fn one_oscillator_gives_one_half_everywhere() {
        let o = [DVec3::ZERO];
        let k = TAU / 500e-9;
        for p in [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.3, -0.2, 2.7),
            DVec3::new(1e-4, 0.0, 0.5),
        ] {
            for steps in [3, 4, 10, 37] {
                let i = relative_intensity(&o, k, steps, p);
                assert!((i - 0.5).abs() < 1e-15, "{steps} steps at {p}: {i}");
            }
        }
    }

    #[test]
    fn two_oscillators_follow_the_cosine_law() {
        // Two in-phase sources: I = (2 + 2 cos(k Δr)) / (2 · 4) = cos²(k Δr / 2) / 2.
        let (a, b) = (DVec3::new(0.0, -5e-5, 0.0), DVec3::new(0.0, 5e-5, 0.0));
        let k = TAU / 600e-9;
        for y in [0.0, 1e-3, 2.5e-3, 3e-3, 7.1e-3] {
            let p = DVec3::new(0.0, y, 1.0);
            let dr = (p - a).length() - (p - b).length();
            let expected = 0.5 * (k * dr / 2.0).cos().powi(2);
            let got = relative_intensity(&[a, b], k, 10, p);
            assert!((got - expected).abs() < 1e-9, "y = {y}: {got} against {expected}");
        }
    }

    #[test]
    fn one_or_two_instants_give_the_instantaneous_value() {
        // SIMRenderer's sum at t = 0 (and t = T/2, the same square): (Σ sin k r_j)² / N².
        let o = [DVec3::ZERO, DVec3::new(0.0, 1e-4, 0.0)];
        let k = TAU / 550e-9;
        let p = DVec3::new(0.0, 1.3e-3, 1.0);
        let s: f64 = o.iter().map(|q| (k * (p - *q).length()).sin()).sum();
        for steps in [1, 2] {
            let got = relative_intensity(&o, k, steps, p);
            assert!((got - s * s / 4.0).abs() < 1e-9, "{steps}: {got}");
        }
    }

    #[test]
    fn slit_oscillators_are_evenly_spaced_end_to_end() {
        let slit = Aperture::Linear {
            start: DVec3::new(0.0, -1.0, 0.0),
            end: DVec3::new(0.0, 1.0, 0.0),
        };
        let o = slit.oscillators(5).unwrap();
        let ys: Vec<f64> = o.iter().map(|p| p.y).collect();
        assert_eq!(ys, [-1.0, -0.5, 0.0, 0.5, 1.0]);
        assert_eq!(slit.oscillators(1).unwrap(), [DVec3::ZERO]);
    }

    #[test]
    fn planar_grids_count_along_the_shorter_side() {
        // width 2, height 1, N = 3 along the height: spacing 0.5, ceil(2 / 0.5) + 1 = 5
        // across: a 5 x 3 grid from the corner (-1, -0.5).
        let r = Aperture::Rectangular(planar(2.0, 1.0));
        let o = r.oscillators(3).unwrap();
        assert_eq!(o.len(), 15);
        assert_eq!(r.grid_size(3), 15);
        // right = front × up = Z × Y = -X: the first point is at x = +1.
        assert_eq!(o[0], DVec3::new(1.0, -0.5, 1.0));
        assert_eq!(o[14], DVec3::new(-1.0, 0.5, 1.0));
        // An ellipse of the same box keeps the points with value <= 1: of the 5 x 3 grid,
        // (x - 1)² + 4 (y - 0.5)² <= 1 keeps the middle row (5) and the top and bottom
        // rows' middle point: 7.
        let e = Aperture::Elliptical(planar(2.0, 1.0));
        assert_eq!(e.oscillators(3).unwrap().len(), 7);
        // One oscillator: the centre.
        assert_eq!(e.oscillators(1).unwrap(), [DVec3::new(0.0, 0.0, 1.0)]);
    }

    #[test]
    fn a_mask_keeps_the_white_texels_top_row_at_the_lower_edge() {
        // A 2 x 2 mask, white only at the top-left texel: of a 2 x 2 grid (N = 2, square),
        // the point (x, y) = (0, 0) (u = v = 0: column 0, row 0) is the only one kept.
        let mask = Mask {
            file: "m.png".into(),
            width: 2,
            height: 2,
            open: vec![true, false, false, false],
        };
        let a = Aperture::Mask {
            planar: planar(1.0, 1.0),
            mask: Some(mask),
        };
        let o = a.oscillators(2).unwrap();
        // The corner center - right/2 - up/2 with right = -X: (0.5, -0.5, 1).
        assert_eq!(o, [DVec3::new(0.5, -0.5, 1.0)]);
    }

    #[test]
    fn wavelength_colours() {
        assert!(wavelength_color(379.9).is_none() && wavelength_color(780.1).is_none());
        // 633 nm is red, 530 nm green, 460 nm blue: the dominant channel.
        let red = wavelength_color(633.0).unwrap();
        assert!(red.x > 0.9 && red.y < 0.3 && red.z < 0.1, "{red}");
        let green = wavelength_color(530.0).unwrap();
        assert!(green.y > green.x && green.y > green.z, "{green}");
        let blue = wavelength_color(460.0).unwrap();
        assert!(blue.z > blue.x && blue.z > blue.y, "{blue}");
        // By hand at 550 nm: x̄ = 0.4337, ȳ = 0.9945, z̄ = 0.0088 (the fit's lobes), linear
        // sRGB (-0.1276, 1.4455, -0.1695) clamped to (0, 1, 0), encoded (0, 1.055 - 0.055, 0):
        // 0.9999999999999999 in f64, as in SIMRenderer's double arithmetic.
        assert_eq!(wavelength_color(550.0).unwrap(), DVec3::new(0.0, 1.055 - 0.055, 0.0));
    }
}
