//! # lumiere
//!
//! A seeded, deterministic Whitted ray tracer: the reference answer for a course on
//! ray-traced illumination (chapter 7.4b "L'illumination avancée dans un ray tracer" and
//! the IFT3355 slides "shading 1"). For a scene and a seed it produces one exact answer.
//!
//! Module map, from the maths up:
//! - [`math`]: rays, frames, reflection and refraction laws, ray-origin offsets.
//! - [`solve`]: the stable quadratic and the quartic root isolator.
//! - [`shape`]: plane, rectangle, disk, sphere, box, cylinder, cone, torus.
//! - [`accel`]: closest-hit / any-hit queries over a scene's objects.
//! - [`material`], [`light`], [`shading`]: the course's parameters and formulas.
//! - [`area_light`], [`placement`]: N-point area lights and where their points go.
//! - [`camera`], [`sampling`]: pinhole camera, seeded random streams.
//! - [`scene`]: the scene model and its TOML file format with located errors.
//! - [`trace`]: Whitted recursion with filtered shadow rays and a step recorder.
//! - [`render`], [`film`], [`output`]: parallel deterministic rendering, quantisation,
//!   atomic PNG / PFM / EXR output.
//! - [`compare`]: image differences (max, RMS, PSNR, heat-map) for `lumiere compare`.
//! - [`family`]: images that differ only in depth, an area light's count or shading,
//!   rendered in one pass (each image's bytes those of its own render).
//! - [`figures`]: the course's figure sets, manifests, contact sheets and gallery.
//! - [`shard`]: split renders (`--shard K/N`) and their bit-identical merge.
//! - [`probe`]: `lumiere probe`, the recorded ray tree of one pixel.
//! - [`review`]: `lumiere review-snapshots`, old | new | difference sheets of pending snapshots.
//! - [`cli`]: the `lumiere` command line.
//! - [`stress`]: the numerical stress campaign against double-double references.
//! - [`study`]: `lumiere study soft-shadows`, render time against error of area lights.

pub mod accel;
pub mod area_light;
pub mod camera;
pub mod cli;
pub mod compare;
pub mod family;
pub mod figures;
pub mod film;
pub mod light;
pub mod limits;
pub mod material;
pub mod math;
pub mod output;
pub mod placement;
pub mod probe;
pub mod render;
pub mod review;
pub mod sampling;
pub mod scene;
pub mod shading;
pub mod shape;
pub mod shard;
pub mod skips;
pub mod solve;
pub mod stress;
pub mod study;
pub mod trace;
pub mod world;

/// The renderer version recorded in manifests.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
