//! The rays the intersection benches share (benches/intersect.rs, benches/embree.rs and
//! benches/paired), so that they measure the same rays.

use glam::DVec3;
use lumiere::camera::Camera;
use lumiere::math::Ray;
use lumiere::sampling::{Purpose, Stream};

/// `camera`'s rays through the centres of a `side` x `side` image's pixels, row by row.
pub fn camera_rays(camera: &Camera, side: u32) -> Vec<Ray> {
    (0..side * side)
        .map(|i| camera.ray((i % side) as f64 + 0.5, (i / side) as f64 + 0.5, side, side))
        .collect()
}

/// `count` rays for the slab of scenes/spheres-1k.toml and spheres-1m.toml: origins uniform
/// in the slab's box grown by 2 ([-12, 12]^2 x [-2, 3]), directions uniform on the sphere.
pub fn incoherent_rays(count: usize) -> Vec<Ray> {
    let mut s = Stream::new(17, Purpose::Generator, 0);
    (0..count)
        .map(|_| {
            let mut u = || s.next_f64();
            let o = DVec3::new(24.0 * u() - 12.0, 24.0 * u() - 12.0, 5.0 * u() - 2.0);
            let z = 2.0 * u() - 1.0;
            let phi = std::f64::consts::TAU * u();
            let r = (1.0 - z * z).sqrt();
            Ray::new(o, DVec3::new(r * libm::cos(phi), r * libm::sin(phi), z))
        })
        .collect()
}
