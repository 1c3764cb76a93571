//! Caustics by photon mapping: Jensen's two passes ("Realistic Image Synthesis Using Photon
//! Mapping", 2001) restricted to caustic paths, light -> one or more specular bounces (`k_r`,
//! `k_t`) -> a diffuse surface, the light a Whitted tracer's straight shadow rays cannot
//! find. Off unless the scene has a `[caustics]` table.
//!
//! 1. [`emit`]: the lights' emitters, one per light point and specular target, each chosen in
//!    proportion to the power its target intercepts.
//! 2. [`path`]: each photon through reflections and refractions, with the intersection core
//!    and the laws of [`crate::math`] that rays use, stored where it lands on a diffuse
//!    surface after at least one bounce that turned it.
//! 3. [`map`]: the photons sorted into a grid of cells, and the density estimate that reads
//!    the irradiance they bring to a shading point.
//!
//! Determinism: photon `i` draws from its own stream `(seed, photons, i)` (the `[caustics]`
//! table's `seed`, else the image's); photons are traced
//! in parallel in fixed chunks whose results are joined in index order, and the map sorts
//! them by cell then index; so the map, and every estimate, are the same bits for any thread
//! count or shard split.

pub mod emit;
pub mod map;
pub mod path;

pub use map::{Estimate, Photon, PhotonMap};

use crate::accel::Accel;
use crate::sampling::{Purpose, Stream};
use crate::scene::{CausticSettings, Scene};
use rayon::prelude::*;

/// Photons traced by one task: a fixed size, so the chunks (and the order they are joined
/// in) do not depend on the thread count.
const CHUNK: u64 = 1 << 14;

/// The photon map of `scene` with the caustic settings `settings`, its photons traced
/// through `accel` (the scene's intersection core).
pub fn build(scene: &Scene, accel: &Accel, settings: &CausticSettings) -> PhotonMap {
    let emitters = emit::Emitters::of(scene);
    let n = settings.photons;
    let seed = settings.seed.unwrap_or(scene.settings.seed);
    let chunks = n.div_ceil(CHUNK);
    let stored: Vec<Vec<Photon>> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut out = Vec::new();
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                let mut rng = Stream::new(seed, Purpose::Photons, i);
                if let Some(start) = emitters.emit(&mut rng, n) {
                    path::trace(scene, accel, start, settings.bounces, &mut rng, &mut out);
                }
            }
            out
        })
        .collect();
    PhotonMap::build(stored.concat(), settings.radius, settings.filter, n)
}
