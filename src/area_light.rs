//! Area lights made of N point lights (chapter 7.4b, "multiple shadow rays"):
//! `L_multi = (1/N) sum_i L_point_i`, each point with its own attenuation, shadow ray,
//! filtered shadow and specular highlight. Shapes: sphere (center, radius), tube (segment)
//! and window (rectangle: center and two edges). `fixed` mode uses one set of points for
//! the whole image (the chapter's look: N distinct shadows); `per_sample` draws fresh points
//! for every pixel sample from that sample's own stream (noise instead of banding).

use crate::math::half_diagonal;
use crate::placement::{Placement, on_segment, on_sphere, on_square};
use crate::sampling::{Purpose, Stream, sample_index};
use crate::shading::Attenuation;
use glam::DVec3;

/// The shape the points are spread over.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum AreaShape {
    Sphere {
        center: DVec3,
        radius: f64,
    },
    /// The segment from `start` to `end`.
    Tube {
        start: DVec3,
        end: DVec3,
    },
    /// The rectangle `center + s edge1 + t edge2`, `s, t` in [-1/2, 1/2].
    Window {
        center: DVec3,
        edge1: DVec3,
        edge2: DVec3,
    },
}

/// Light points as three coordinate arrays (structure of arrays: the per-point loops of the
/// tracer run over them with vector instructions).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointSet {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<f64>,
}

impl PointSet {
    pub fn from_points(points: &[DVec3]) -> Self {
        PointSet {
            x: points.iter().map(|p| p.x).collect(),
            y: points.iter().map(|p| p.y).collect(),
            z: points.iter().map(|p| p.z).collect(),
        }
    }

    pub fn len(&self) -> usize {
        self.x.len()
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// The points, in order.
    pub fn iter(&self) -> impl Iterator<Item = DVec3> + '_ {
        (0..self.len()).map(|i| DVec3::new(self.x[i], self.y[i], self.z[i]))
    }
}

/// When the points are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PointMode {
    /// One set for the whole image, from the stream `(seed, light points, light index)`.
    Fixed,
    /// A fresh set for each pixel sample, from the stream
    /// `(seed, light points, light index << 48 | pixel << 16 | sample)`.
    PerSample,
}

/// A light made of `count` white-or-coloured points sharing `color / count`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AreaLight {
    pub shape: AreaShape,
    /// N, the number of point lights.
    pub count: u32,
    pub placement: Placement,
    pub mode: PointMode,
    /// The whole light's colour; each point carries `color / N`.
    pub color: DVec3,
    pub attenuation: Attenuation,
}

impl AreaLight {
    /// The N point positions drawn from `rng` (first N of the placement's sequence).
    pub fn points(&self, rng: &mut Stream) -> Vec<DVec3> {
        let n = self.count as usize;
        match &self.shape {
            AreaShape::Sphere { center, radius } => on_sphere(self.placement, n, rng)
                .into_iter()
                .map(|u| *center + *radius * u)
                .collect(),
            AreaShape::Tube { start, end } => on_segment(self.placement, n, rng)
                .into_iter()
                .map(|t| *start + t * (*end - *start))
                .collect(),
            AreaShape::Window { center, edge1, edge2 } => on_square(self.placement, n, rng)
                .into_iter()
                .map(|uv| *center + (uv.x - 0.5) * *edge1 + (uv.y - 0.5) * *edge2)
                .collect(),
        }
    }

    /// The points of a `fixed` light with index `light` in a scene seeded `seed`.
    pub fn fixed_points(&self, seed: u64, light: usize) -> Vec<DVec3> {
        self.points(&mut Stream::new(seed, Purpose::LightPoints, light as u64))
    }

    /// The points of a `per_sample` light for sample `k` of pixel `pixel`.
    pub fn sample_points(&self, seed: u64, light: usize, pixel: u64, k: u32) -> Vec<DVec3> {
        let index = (light as u64) << 48 | sample_index(pixel, k);
        self.points(&mut Stream::new(seed, Purpose::LightPoints, index))
    }

    /// A sphere (center, radius) containing every point the light can place.
    pub fn bounding_sphere(&self) -> (DVec3, f64) {
        match &self.shape {
            AreaShape::Sphere { center, radius } => (*center, *radius),
            AreaShape::Tube { start, end } => (0.5 * (*start + *end), 0.5 * (*end - *start).length()),
            // The farthest corner: `|(+-edge1 +- edge2) / 2|`.
            AreaShape::Window { center, edge1, edge2 } => (*center, half_diagonal(*edge1, *edge2)),
        }
    }

    /// Colour each point carries: `L / N`.
    pub fn point_color(&self) -> DVec3 {
        self.point_color_of(self.count)
    }

    /// Colour each point carries when the light is taken as `n` points: `L / n`.
    pub fn point_color_of(&self, n: u32) -> DVec3 {
        self.color / n as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere(n: u32, placement: Placement) -> AreaLight {
        AreaLight {
            shape: AreaShape::Sphere {
                center: DVec3::new(0.0, 0.0, 10.0),
                radius: 2.0,
            },
            count: n,
            placement,
            mode: PointMode::Fixed,
            color: DVec3::ONE,
            attenuation: Attenuation::NONE,
        }
    }

    /// The light-shapes figures' tube: from (-2, 0, 10) to (2, 0, 10).
    fn figure_tube(n: u32, placement: Placement) -> AreaLight {
        AreaLight {
            shape: AreaShape::Tube {
                start: DVec3::new(-2.0, 0.0, 10.0),
                end: DVec3::new(2.0, 0.0, 10.0),
            },
            ..sphere(n, placement)
        }
    }

    /// The light-shapes figures' window: center (0, 0, 10), edges (4, 0, 0) and (0, 3, 0).
    fn figure_window(n: u32, placement: Placement) -> AreaLight {
        AreaLight {
            shape: AreaShape::Window {
                center: DVec3::new(0.0, 0.0, 10.0),
                edge1: DVec3::new(4.0, 0.0, 0.0),
                edge2: DVec3::new(0.0, 3.0, 0.0),
            },
            ..sphere(n, placement)
        }
    }

    #[test]
    fn points_lie_on_their_shapes() {
        for p in sphere(64, Placement::Uniform).fixed_points(42, 1) {
            assert!(((p - DVec3::new(0.0, 0.0, 10.0)).length() - 2.0).abs() < 1e-12);
        }
        for p in figure_tube(32, Placement::Stratified).fixed_points(42, 1) {
            assert!(p.x.abs() <= 2.0 && p.y == 0.0 && p.z == 10.0);
        }
        for p in figure_window(32, Placement::Fibonacci).fixed_points(42, 1) {
            assert!(p.x.abs() <= 2.0 && p.y.abs() <= 1.5 && p.z == 10.0);
        }
    }

    #[test]
    fn bounding_spheres_reach_the_farthest_point() {
        // The light-shapes figures' window: corners 2.5 from the center.
        let window = figure_window(400, Placement::Stratified);
        assert_eq!(window.bounding_sphere(), (DVec3::new(0.0, 0.0, 10.0), 2.5));
        // A sheared window: its long diagonal, |(4, 0, 0) + (2, 3, 0)| / 2.
        let sheared = AreaLight {
            shape: AreaShape::Window {
                center: DVec3::ZERO,
                edge1: DVec3::new(4.0, 0.0, 0.0),
                edge2: DVec3::new(2.0, 3.0, 0.0),
            },
            ..window.clone()
        };
        let (_, r) = sheared.bounding_sphere();
        assert_eq!(r, 0.5 * 45f64.sqrt());
        for light in [&window, &sheared] {
            let (c, r) = light.bounding_sphere();
            assert!(light.fixed_points(42, 1).iter().all(|p| (*p - c).length() <= r));
        }
        let tube = figure_tube(400, Placement::Stratified);
        assert_eq!(tube.bounding_sphere(), (DVec3::new(0.0, 0.0, 10.0), 2.0));
    }

    #[test]
    fn fixed_points_depend_only_on_seed_and_light() {
        let l = sphere(10, Placement::Chapter);
        assert_eq!(l.fixed_points(42, 3), l.fixed_points(42, 3));
        assert_ne!(l.fixed_points(42, 3), l.fixed_points(42, 4));
        assert_ne!(l.sample_points(42, 3, 7, 0), l.sample_points(42, 3, 7, 1));
        assert_eq!(l.point_color(), DVec3::splat(0.1));
        // A family member taking 4 of its points: each carries 1 / 4.
        assert_eq!(l.point_color_of(4), DVec3::splat(0.25));
    }
}
