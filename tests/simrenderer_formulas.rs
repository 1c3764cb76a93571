//! The unit tests SIMRenderer's teacher gives students for the routines they complete
//! (`SIlluminationTest`: Lambert and Blinn; `SGeometricalOpticsTest`: refraction), their
//! inputs and expected values as the lab sources list them, reproduced by lumiere's own
//! formulas under SIMRenderer's conventions: a material without plasticity has metal
//! highlights (m = 1, so the specular colour is the material's), `d` is the direction the
//! light travels (`L = -d`), `E = -v`, and `eta = n1 / n2`. Each value is held to the
//! listed digits: equal, or within 1e-15 of it relatively.

use glam::DVec3;
use lumiere::conventions::Conventions;
use lumiere::math::refract;
use lumiere::shading::{blinn, diffuse, lambert, specular, specular_tint};

fn unit(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z).normalize()
}

/// Each channel of `got` is `expected`'s, to 1e-15 relatively (exactly where it is 0).
fn assert_close(got: DVec3, expected: [f64; 3]) {
    for (g, e) in got.to_array().into_iter().zip(expected) {
        assert!(
            g == e || (g - e).abs() <= 1e-15 * e.abs(),
            "got {got:?}, expected {expected:?}"
        );
    }
}

/// SIMRenderer's Lambert term for a light of colour `light` and a material of colour
/// `material` (`S_d`, as the test passes it): `L k_d S max(N.L, 0)` with `k_d S` = `material`.
fn lambert_term(light: DVec3, material: DVec3, n: DVec3, d: DVec3) -> DVec3 {
    diffuse(light, 1.0, material, n.dot(-d))
}

/// SIMRenderer's Blinn term: `L k_s [m S + (1 - m)] max(N.H, 0)^n` with `k_s` 1 and the
/// metal factor of a material without plasticity under SIMRenderer's conventions.
fn blinn_term(light: DVec3, material: DVec3, n: DVec3, d: DVec3, v: DVec3, exponent: f64) -> DVec3 {
    let m = Conventions::SIMRENDERER.default_highlight.metal();
    specular(light, 1.0, specular_tint(m, material), blinn(n, -d, -v, exponent))
}

#[test]
fn lambert_1_to_3() {
    // 1: normal incidence, white and black light.
    let (n, d) = (DVec3::Z, DVec3::NEG_Z);
    let material = DVec3::new(0.6, 0.5, 0.2);
    assert_eq!(lambert_term(DVec3::ONE, material, n, d), material);
    assert_eq!(lambert_term(DVec3::ZERO, material, n, d), DVec3::ZERO);
    // 2.
    let light = DVec3::new(0.2, 0.3, 0.4);
    let material = DVec3::new(0.9, 0.8, 0.7);
    let n = unit(2.3, 4.5, 8.7);
    assert_close(
        lambert_term(light, material, n, unit(-1.2, -5.6, -2.4)),
        [0.1407100214802341, 0.18761336197364545, 0.21888225563591968],
    );
    // 3: the light behind the surface.
    let behind = unit(1.2, 5.6, 2.4);
    assert!(n.dot(-behind) < 0.0 && lambert(n.dot(-behind)) == 0.0);
    assert_eq!(lambert_term(light, material, n, behind), DVec3::ZERO);
}

#[test]
fn blinn_1_to_3() {
    // 1: the light and the eye along the normal, exponent 6.9.
    let (n, d) = (DVec3::Z, DVec3::NEG_Z);
    let material = DVec3::new(0.6, 0.5, 0.2);
    assert_eq!(blinn_term(DVec3::ONE, material, n, d, d, 6.9), material);
    assert_eq!(blinn_term(DVec3::ZERO, material, n, d, d, 6.9), DVec3::ZERO);
    // 2.
    let light = DVec3::new(0.2, 0.3, 0.4);
    let material = DVec3::new(0.9, 0.8, 0.7);
    let n = unit(2.3, 4.5, 8.7);
    let v = unit(4.5, -8.4, -3.0);
    assert_close(
        blinn_term(light, material, n, unit(-1.2, -5.6, -2.4), v, 3.2),
        [0.05624968851560261, 0.07499958468747013, 0.08749951546871515],
    );
    // 3: the light behind: the half vector faces away from the normal.
    assert_eq!(blinn_term(light, material, n, unit(1.2, 5.6, 2.4), v, 3.2), DVec3::ZERO);
}

#[test]
fn refraction_1_and_2() {
    let eta = 1.3 / 1.8;
    // 1: along the normal, the ray goes on unbent.
    let v = unit(2.3, -2.5, 7.9);
    assert_close(refract(v, -v, eta).unwrap(), v.to_array());
    // 2.
    let v = unit(2.3, -2.5, 0.0);
    let n = unit(1.1, 2.9, 0.0);
    assert_close(
        refract(v, n, eta).unwrap(),
        [0.3329180135506553, -0.942955776403902, 0.0],
    );
}
