//! FLIP, the perceptual difference of two images (Andersson, Nilsson, Akenine-Möller,
//! Oskarsson, Åström and Fairchild, "FLIP: A Difference Evaluator for Alternating Images",
//! HPG 2020), computed by NVIDIA's C++ reference implementation through the `nv-flip`
//! crate: LDR-FLIP, per pixel in [0, 1], at the FLIP tool's default viewing condition
//! (a 0.7 m wide 3840-pixel monitor seen from 0.7 m: 67.02 pixels per degree).
//!
//! LDR-FLIP reads both images as sRGB-encoded. lumiere's PNGs hold linear values with no
//! gamma, but a viewer shows them as sRGB, so the metric weighs the differences a person
//! sees on the screen. Its colour pipeline compares the images filtered by the contrast
//! sensitivity of the eye in a Hunt-adjusted L*a*b* (HyAB distance); its feature pipeline
//! compares edges and points; FLIP is the colour difference raised to `1 - feature
//! difference`. A difference confined to single pixels along an edge scores low; a shift of
//! every colour scores high.

/// FLIP's default pixels per degree of visual angle: a monitor 0.7 m wide, 3840 pixels
/// across, seen from 0.7 m (`0.7 x 3840 / 0.7 x pi / 180`).
pub fn pixels_per_degree() -> f32 {
    nv_flip::pixels_per_degree(0.7, 3840.0, 0.7)
}

/// The FLIP value of every pixel (row-major), of `test` against `reference`: interleaved
/// RGB8 buffers of `width * height` pixels.
pub fn flip_map(reference: &[u8], test: &[u8], width: u32, height: u32) -> Vec<f32> {
    let n = width as usize * height as usize;
    assert!(reference.len() == 3 * n && test.len() == 3 * n && n > 0, "sizes");
    let r = nv_flip::FlipImageRgb8::with_data(width, height, reference);
    let t = nv_flip::FlipImageRgb8::with_data(width, height, test);
    nv_flip::flip(r, t, pixels_per_degree()).to_vec()
}

/// The FLIP values as a heat-map in the magma colour map of the FLIP tool (black 0,
/// purple, orange, pale yellow 1): interleaved RGB8.
pub fn flip_heat_map(values: &[f32], width: u32, height: u32) -> Vec<u8> {
    let map = nv_flip::FlipImageFloat::with_data(width, height, values);
    map.apply_color_lut(&nv_flip::magma_lut()).to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::level_value;
    use crate::film::srgb_decode;

    /// An sRGB-encoded 8-bit level as linear light (IEC 61966-2-1).
    fn linear(level: u8) -> f64 {
        srgb_decode(level_value(level))
    }

    /// CIELAB (D65 white) of linear sRGB, Hunt-adjusted: `a` and `b` scaled by `0.01 L`.
    fn hunt_lab(rgb: [f64; 3]) -> [f64; 3] {
        let m = [
            [0.412_456_4, 0.357_576_1, 0.180_437_5],
            [0.212_672_9, 0.715_152_2, 0.072_175_0],
            [0.019_333_9, 0.119_192_0, 0.950_304_1],
        ];
        let xyz = m.map(|row| row[0] * rgb[0] + row[1] * rgb[1] + row[2] * rgb[2]);
        let white = m.map(|row| row[0] + row[1] + row[2]);
        let f = |t: f64| {
            let d: f64 = 6.0 / 29.0;
            if t > d * d * d {
                libm::cbrt(t)
            } else {
                t / (3.0 * d * d) + 4.0 / 29.0
            }
        };
        let [fx, fy, fz] = [0, 1, 2].map(|i| f(xyz[i] / white[i]));
        let l = 116.0 * fy - 16.0;
        [l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)]
    }

    /// HyAB distance `|dL| + sqrt(da^2 + db^2)` raised to FLIP's `q_c = 0.7`.
    fn hyab_q(p: [f64; 3], q: [f64; 3]) -> f64 {
        let d = (p[0] - q[0]).abs() + ((p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
        libm::pow(d, 0.7)
    }

    /// LDR-FLIP of two uniform images of colours `a` and `b` (sRGB levels), from the paper's
    /// formulas: the contrast-sensitivity filters leave a uniform image unchanged and the
    /// edge and point detectors find nothing, so FLIP is the colour difference alone, the
    /// Hunt-adjusted HyAB distance to the power 0.7, mapped so that `p_c = 0.4` of the largest
    /// difference (pure green against pure blue) goes to `p_t = 0.95`.
    fn uniform_flip(a: [u8; 3], b: [u8; 3]) -> f64 {
        let e = hyab_q(hunt_lab(a.map(linear)), hunt_lab(b.map(linear)));
        let cmax = hyab_q(hunt_lab([0.0, 1.0, 0.0]), hunt_lab([0.0, 0.0, 1.0]));
        let (pc, pt) = (0.4, 0.95);
        if e < pc * cmax {
            pt / (pc * cmax) * e
        } else {
            pt + (e - pc * cmax) / (cmax - pc * cmax) * (1.0 - pt)
        }
    }

    #[test]
    fn uniform_images_match_the_papers_colour_pipeline() {
        let pairs = [
            ([0, 0, 0], [255, 255, 255]),
            ([128, 128, 128], [140, 128, 128]),
            ([200, 40, 40], [40, 200, 40]),
            ([10, 20, 30], [12, 20, 30]),
            ([255, 230, 25], [150, 75, 200]),
        ];
        for (a, b) in pairs {
            let (w, h) = (9, 7);
            let img = |c: [u8; 3]| c.repeat(w * h);
            let map = flip_map(&img(a), &img(b), w as u32, h as u32);
            let expected = uniform_flip(a, b);
            for v in map {
                assert!(
                    (v as f64 - expected).abs() < 2e-5,
                    "{a:?} {b:?}: {v} against {expected}"
                );
            }
        }
        // Black against white, worked by hand: HyAB 100, 100^0.7 = 25.119; green (L 87.73,
        // Hunt-adjusted a -75.61, b 72.98) against blue (32.30, 25.58, -34.84): HyAB 203.30,
        // to the power 0.7: 41.275; 25.119 lies above 0.4 x 41.275 = 16.510, so FLIP =
        // 0.95 + (25.119 - 16.510) / (41.275 - 16.510) x 0.05 = 0.96738.
        assert!((uniform_flip([0, 0, 0], [255, 255, 255]) - 0.967_38).abs() < 1e-5);
        let same = flip_map(&[90; 27], &[90; 27], 3, 3);
        assert_eq!(same, [0.0; 9]);
    }

    #[test]
    fn default_viewing_condition() {
        assert!((pixels_per_degree() - 67.020_645).abs() < 1e-5);
    }
}
