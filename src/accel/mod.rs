//! Ray queries over a scene's objects: the closest hit (camera, reflection and refraction
//! rays), any hit among objects a filter accepts (opaque shadow tests), and every object hit
//! in a range (transparent shadow filtering). Two cores answer them, with the same hits to
//! the bit: the linear scan (every object, every ray) and a BVH. The closest and any hit
//! have packet forms too, for up to [`PACKET`] neighbouring rays at once, which the BVH
//! walks together. The scene picks the BVH
//! from [`CROSSOVER`] bounded objects on (measured, BENCHMARKS.md), unless told otherwise.

mod build;
mod bvh;
mod leaf;
mod linear;
mod node;
mod packet;
mod sift;
mod wide;

pub use bvh::{Bvh, Kernel};
pub use linear::Linear;
pub use packet::PACKET;

use crate::math::Ray;
use crate::scene::Object;
use crate::shape::SurfaceHit;

/// Fewest bounded objects for which `auto` picks the BVH: below it the linear scan is as
/// fast or faster (BENCHMARKS.md, "Crossover: when `auto` picks the BVH").
pub const CROSSOVER: usize = 16;

/// Which core to use (`--accel`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AccelChoice {
    /// The linear scan, [`Linear`].
    Linear,
    /// The BVH, [`Bvh`].
    Bvh,
    /// The BVH for scenes of at least [`CROSSOVER`] bounded objects, else the linear scan.
    #[default]
    Auto,
}

impl AccelChoice {
    pub const ALL: [AccelChoice; 3] = [AccelChoice::Linear, AccelChoice::Bvh, AccelChoice::Auto];

    /// The name on the command line (`--accel NAME`) and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            AccelChoice::Linear => "linear",
            AccelChoice::Bvh => "bvh",
            AccelChoice::Auto => "auto",
        }
    }

    /// What the choice does, in one line of the command line's help (`auto`'s with the
    /// number [`CROSSOVER`] holds).
    pub fn help(self) -> String {
        match self {
            AccelChoice::Linear => "Test every object for every ray".into(),
            AccelChoice::Bvh => "Bounding volume hierarchy (binned SAH, f32 boxes)".into(),
            AccelChoice::Auto => format!("The BVH from {CROSSOVER} bounded objects on, else the linear scan"),
        }
    }
}

impl std::str::FromStr for AccelChoice {
    type Err = String;

    /// Parses a [`name`](AccelChoice::name).
    fn from_str(s: &str) -> Result<Self, String> {
        AccelChoice::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| format!("unknown intersection core {s:?}; expected linear, bvh or auto"))
    }
}

/// The acceleration structure chosen for a scene.
#[derive(Clone, Debug)]
pub enum Accel {
    Linear(Linear),
    Bvh(Bvh),
}

impl Accel {
    /// The core `auto` picks for these objects.
    pub fn build(objects: &[Object]) -> Self {
        Accel::build_with(objects, AccelChoice::Auto)
    }

    pub fn build_with(objects: &[Object], choice: AccelChoice) -> Self {
        let bvh = match choice {
            AccelChoice::Linear => false,
            AccelChoice::Bvh => true,
            AccelChoice::Auto => objects.iter().filter(|o| o.shape.bounds().is_some()).count() >= CROSSOVER,
        };
        if bvh {
            Accel::Bvh(Bvh::new(objects))
        } else {
            Accel::Linear(Linear::new(objects.len()))
        }
    }

    /// `linear` or `bvh`.
    pub fn name(&self) -> &'static str {
        match self {
            Accel::Linear(_) => "linear",
            Accel::Bvh(_) => "bvh",
        }
    }

    /// Bytes held by the structure (nothing for the linear scan).
    pub fn bytes(&self) -> usize {
        match self {
            Accel::Linear(_) => 0,
            Accel::Bvh(b) => b.bytes(),
        }
    }

    /// Closest hit with `t_min < t < t_max`: object index and surface hit. On equal `t`, the
    /// lowest object index.
    pub fn closest(&self, objects: &[Object], ray: &Ray, t_min: f64, t_max: f64) -> Option<(usize, SurfaceHit)> {
        match self {
            Accel::Linear(l) => l.closest(objects, ray, t_min, t_max),
            Accel::Bvh(b) => b.closest(objects, ray, t_min, t_max),
        }
    }

    /// True when some object accepted by `filter` is hit with `t_min < t < t_max`.
    pub fn any_hit(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
    ) -> bool {
        match self {
            Accel::Linear(l) => l.any_hit(objects, ray, t_min, t_max, filter),
            Accel::Bvh(b) => b.any_hit(objects, ray, t_min, t_max, filter),
        }
    }

    /// [`Accel::closest`] for each of `rays` (at most [`PACKET`]), into `out` (as long as
    /// `rays`): the BVH walks rays whose directions share an octant together
    /// ([`Bvh::closest_packet`]), with each ray's answer to the bit.
    pub fn closest_packet(
        &self,
        objects: &[Object],
        rays: &[Ray],
        t_min: f64,
        t_max: f64,
        out: &mut [Option<(usize, SurfaceHit)>],
    ) {
        match self {
            Accel::Linear(l) => {
                for (ray, out) in rays.iter().zip(out) {
                    *out = l.closest(objects, ray, t_min, t_max);
                }
            }
            Accel::Bvh(b) => b.closest_packet(objects, rays, t_min, t_max, out),
        }
    }

    /// [`Accel::any_hit`] for each of `rays` (at most [`PACKET`]): bit `l` of the answer is
    /// ray `l`'s (see [`Accel::closest_packet`]).
    pub fn any_hit_packet(
        &self,
        objects: &[Object],
        rays: &[Ray],
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
    ) -> u32 {
        match self {
            Accel::Linear(l) => rays.iter().enumerate().fold(0, |hits, (k, ray)| {
                hits | u32::from(l.any_hit(objects, ray, t_min, t_max, filter)) << k
            }),
            Accel::Bvh(b) => b.any_hit_packet(objects, rays, t_min, t_max, filter),
        }
    }

    /// Calls `visit` once for every object accepted by `filter` that the ray hits in
    /// `(t_min, t_max)`, in no particular order.
    pub fn each_hit(
        &self,
        objects: &[Object],
        ray: &Ray,
        t_min: f64,
        t_max: f64,
        filter: &dyn Fn(usize) -> bool,
        visit: &mut dyn FnMut(usize),
    ) {
        match self {
            Accel::Linear(l) => l.each_hit(objects, ray, t_min, t_max, filter, visit),
            Accel::Bvh(b) => b.each_hit(objects, ray, t_min, t_max, filter, visit),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn choices_parse_from_their_names() {
        for c in AccelChoice::ALL {
            assert_eq!(c.name().parse::<AccelChoice>(), Ok(c));
            // The JSON name (manifests, `--json`) is the command-line name.
            assert_eq!(serde_json::to_string(&c).unwrap(), format!("\"{}\"", c.name()));
        }
        let err = "BVH".parse::<AccelChoice>().unwrap_err();
        assert_eq!(err, "unknown intersection core \"BVH\"; expected linear, bvh or auto");
    }
}
