//! # lumiere
//!
//! A seeded, deterministic Whitted ray tracer: the reference answer for a course on
//! ray-traced illumination (chapter 7.4b "L'illumination avancée dans un ray tracer" and
//! the IFT3355 slides "shading 1"). For a scene and a seed it produces one exact answer.
//!
//! Module map, in layers from the maths up; a module imports only from its own layer or
//! the ones below:
//! 1. [`math`] (rays, frames, the laws of reflection and refraction, ray-origin offsets),
//!    [`text`] (captions drawn into images), [`solve`] (the stable quadratic, the quartic root isolator), [`conventions`] (where
//!    the course's two renderers disagree, as named switches), [`shading`] (the formulas
//!    of the slides and the chapter, each once), [`material`], [`texture`] (image textures
//!    of texture materials), [`sampling`] (seeded random
//!    streams), [`skips`] (the renderer's named shortcuts), [`limits`], [`decimal`] (numbers
//!    as the files lumiere reads write them), [`film`], [`compare`], [`shell`] (the words of
//!    a printed command line, quoted for the shell).
//! 2. [`shape`] (plane, rectangle, disk, sphere, box, cylinder, cone, torus, triangle,
//!    spherical cap, lens, transformed; each with its texture coordinates), [`camera`],
//!    [`placement`], [`output`], [`review`].
//! 3. [`area_light`] (N-point area lights), [`interference`] (aperture lights: coherent
//!    oscillators, their relative intensity, a wavelength's colour), [`stress`] (the
//!    numerical stress campaign).
//! 4. [`light`] (ambient, directional, point, spot, area and aperture lights; what reaches
//!    a point).
//! 5. [`scene`]: the scene model, its TOML file format and SIMRenderer's (read and written),
//!    with located errors.
//! 6. [`accel`] (closest-hit and any-hit queries over a scene's objects: the linear scan or
//!    a BVH), [`shard`] (split renders and their bit-identical merge), [`caustics`] (the
//!    photon pass: emission, specular paths through the intersection core, the photon map and
//!    its density estimate).
//! 7. [`world`]: a scene ready to render (camera, intersection core, light points, bounds;
//!    `world::along`, the objects' balls seen along a directional light).
//! 8. [`trace`]: the Whitted recursion, as the chapter reads ([`trace::reference`], through
//!    the table of formulas [`trace::formulas`]) and as it renders ([`trace::fast`]), to the
//!    same bits.
//! 9. [`render`]: pixels in parallel, deterministic for any thread count.
//! 10. [`family`] (images that differ only in depth, lights, an area light's count or
//!     shading, rendered in one pass), [`probe`] (the recorded ray tree of one pixel),
//!     [`edges`] (the pixels whose footprint spans a boundary, from the recorded paths),
//!     [`layers`] (each pixel's terms, recorded: ambient, diffuse, specular, reflected,
//!     transmitted, shadow filters, object, normal, depth).
//! 11. [`figures`]: the course's figure sets, manifests, contact sheets and gallery;
//!     [`diagnose`]: what is most likely wrong in a student's image (gains per term, a
//!     catalogue of named mistakes rendered and ranked, the HTML report).
//! 12. [`study`]: render time against error of area lights; [`caustic_study`]: of the
//!     caustic pass, over photon counts and estimate radii.
//!
//! The command line (clap's options, printing, progress bars, exit codes, Ctrl-C) lives in
//! the binary, `src/main.rs` and `src/cli/`: the library's functions return data and errors,
//! and print nothing on stdout.
//!
//! Rendering a scene file at a reduced size into a PNG:
//!
//! ```
//! use lumiere::render::render;
//! use lumiere::scene::{self, Overrides};
//! use lumiere::world::World;
//! use std::path::Path;
//!
//! let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/reference.toml");
//! let mut scene = scene::load(&file)?;
//! let small = Overrides { width: Some(40), height: Some(30), spp: Some(1), ..Overrides::default() };
//! small.apply(&mut scene)?;
//! let (film, stats) = render(&World::new(&scene), &|| {});
//! assert_eq!(stats.counts.camera, 40 * 30);
//!
//! let png = std::env::temp_dir().join(format!("lumiere-doc-{}.png", std::process::id()));
//! lumiere::film::write_atomic(&png, &film.encode_png()?)?;
//! let (width, height, rgb) = lumiere::compare::load_rgb8(&png)?;
//! std::fs::remove_file(&png)?;
//! assert_eq!((width, height), (40, 30));
//! assert_eq!(rgb.len(), 40 * 30 * 3);
//! // The same pixels as the film: the file holds the render.
//! assert_eq!(rgb, film.to_rgb8());
//! // Lit: the reference scene's spheres are not all black.
//! assert!(rgb.iter().any(|&c| c > 100));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod accel;
pub mod area_light;
pub mod camera;
pub mod caustic_study;
pub mod caustics;
pub mod compare;
pub mod conventions;
pub mod decimal;
pub mod diagnose;
pub mod edges;
pub mod family;
pub mod figures;
pub mod film;
pub mod interference;
pub mod layers;
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
pub mod shell;
pub mod skips;
pub mod solve;
pub mod stress;
pub mod study;
pub mod text;
pub mod texture;
pub mod trace;
pub mod world;

/// The renderer version recorded in manifests.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
