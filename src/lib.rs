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
//! - [`camera`], [`sampling`]: pinhole camera, seeded random streams.
//! - [`scene`]: the scene model and its TOML file format with located errors.
//! - [`trace`]: Whitted recursion with filtered shadow rays and a step recorder.
//! - [`render`], [`film`]: parallel deterministic rendering, quantisation, atomic output.
//! - [`cli`]: the `lumiere` command line.
//! - [`stress`]: the numerical stress campaign against double-double references.

pub mod accel;
pub mod camera;
pub mod cli;
pub mod film;
pub mod light;
pub mod limits;
pub mod material;
pub mod math;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod shading;
pub mod shape;
pub mod solve;
pub mod stress;
pub mod trace;

/// The renderer version recorded in manifests.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
