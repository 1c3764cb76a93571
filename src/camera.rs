//! Pinhole camera: position, look-at point, up vector, vertical field of view.

use crate::math::Ray;
use glam::DVec3;

#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub position: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    /// Vertical field of view in degrees.
    pub vfov_deg: f64,
    // Derived frame: forward, right, true up, scaled by the image-plane half extents.
    forward: DVec3,
    right: DVec3,
    upward: DVec3,
}

impl Camera {
    /// `up` must not be parallel to the viewing direction (checked by scene validation).
    /// `aspect` is width / height.
    pub fn new(position: DVec3, look_at: DVec3, up: DVec3, vfov_deg: f64, aspect: f64) -> Self {
        let forward = (look_at - position).normalize();
        let right = forward.cross(up).normalize();
        let true_up = right.cross(forward);
        let half_h = libm::tan(vfov_deg.to_radians() * 0.5);
        Camera {
            position,
            look_at,
            up,
            vfov_deg,
            forward,
            right: right * half_h * aspect,
            upward: true_up * half_h,
        }
    }

    /// The ray through image position `(x, y)` in pixels (continuous: pixel `i` spans
    /// `[i, i + 1)`), for an image `width` x `height` with row 0 at the top.
    pub fn ray(&self, x: f64, y: f64, width: u32, height: u32) -> Ray {
        Ray::new(self.position, self.through(x, y, width, height).normalize())
    }

    /// The ray through image position `(x, y)` that starts where it crosses the image plane
    /// at distance `near` in front of the eye (SIMRenderer's camera rays): the same
    /// direction as [`Camera::ray`], from `eye + near p`, with `p` the position on the plane
    /// at distance 1.
    pub fn ray_from_plane(&self, x: f64, y: f64, width: u32, height: u32, near: f64) -> Ray {
        let p = self.through(x, y, width, height);
        Ray::new(self.position + near * p, p.normalize())
    }

    /// Image position `(x, y)` on the image plane at distance 1 in front of the eye, from it.
    fn through(&self, x: f64, y: f64, width: u32, height: u32) -> DVec3 {
        let u = 2.0 * x / width as f64 - 1.0;
        let v = 1.0 - 2.0 * y / height as f64;
        self.forward + u * self.right + v * self.upward
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn center_and_corner_rays() {
        // Looking along +y, vfov 90: half height 1; square image so half width 1.
        let c = Camera::new(DVec3::ZERO, DVec3::Y, DVec3::Z, 90.0, 1.0);
        let center = c.ray(50.0, 50.0, 100, 100);
        assert!((center.dir - DVec3::Y).length() < 1e-15);
        // Top-left corner: direction (-1, 1, 1)/sqrt3.
        let corner = c.ray(0.0, 0.0, 100, 100);
        assert!((corner.dir - DVec3::new(-1., 1., 1.).normalize()).length() < 1e-15);
        // From the near plane at 2: the corner ray starts at 2 (-1, 1, 1), its direction
        // unchanged; the center one at (0, 2, 0).
        let from_plane = c.ray_from_plane(0.0, 0.0, 100, 100, 2.0);
        assert!((from_plane.origin - DVec3::new(-2., 2., 2.)).length() < 1e-15);
        assert_eq!(from_plane.dir, corner.dir);
        assert!((c.ray_from_plane(50.0, 50.0, 100, 100, 2.0).origin - DVec3::new(0., 2., 0.)).length() < 1e-15);
    }
}
