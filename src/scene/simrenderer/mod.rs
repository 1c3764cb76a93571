//! SIMRenderer's scene format (the keyword-block files of the course's Java ray tracer that
//! students complete, as its public lab sources read them): its lexical rules ([`lex`]),
//! reading a file into a [`crate::scene::Scene`] ([`parse`], `read/`), and writing a
//! scene in that format or in lumiere's TOML one ([`to_simrenderer`], [`to_toml`]),
//! losslessly where the format can say the thing and refusing, by name, what it cannot
//! (`exact.rs` finds what to write so that values read back to the bit). The format, its
//! mapping to lumiere and what the writers refuse are documented in docs/simrenderer.md.

/// The values the writers write so that they read back to the bit.
mod exact;
pub mod lex;
mod read;
mod toml;
mod write;
mod writer;

pub use read::{
    DEFAULT_SEED, Options, PIXEL_COORDINATES, Parsed, REFLEXION_ALGORITHMS, TOP_BLOCKS, canonical, grey_default, load,
    parse, shading_of,
};
pub use toml::to_toml;
pub use write::to_simrenderer;

use crate::scene::Scene;

/// Something the reader did or met that the user should know: an error it went past under
/// `lenient` (saying what it did instead), or a surprise SIMRenderer accepts silently.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{file}:{line}:{column}: {field}: {message}")]
pub struct Warning {
    pub file: String,
    pub line: usize,
    pub column: usize,
    /// `block.keyword`, as the file writes them.
    pub field: String,
    pub message: String,
}

/// A scene written as text, and what in it will not read back to the same bits (each
/// naming the object or setting, and why).
#[derive(Clone, Debug, PartialEq)]
pub struct Written {
    pub text: String,
    pub notes: Vec<String>,
}

/// What a format cannot say of a scene: every such thing, each naming the object, light or
/// setting and why.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("cannot be written as {format}: {}", .reasons.join("; "))]
pub struct Refused {
    /// "SIMRenderer" or "the TOML format".
    pub format: &'static str,
    pub reasons: Vec<String>,
}

/// `name (kind)` of an object, as messages name it.
fn object_label(scene: &Scene, i: usize) -> String {
    let o = &scene.objects[i];
    format!("objects[{i}] {:?} ({})", scene.name_of(o), o.shape.kind())
}

/// Where `got` differs from `expected`, each part named (settings and camera by field,
/// materials, objects and lights by index and name); at most `most` of them, then a count.
pub fn differences(expected: &Scene, got: &Scene, most: usize) -> Vec<String> {
    let mut out = Vec::new();
    let (a, b) = (&expected.settings, &got.settings);
    let settings = [
        ("width", a.width != b.width),
        ("height", a.height != b.height),
        ("samples_per_pixel", a.samples_per_pixel != b.samples_per_pixel),
        ("seed", a.seed != b.seed),
        ("depth", a.depth != b.depth),
        ("shading", a.shading != b.shading),
        ("shadows", a.shadows != b.shadows),
        ("background", a.background != b.background),
        ("adaptive_threshold", a.adaptive_threshold != b.adaptive_threshold),
        ("conventions", a.conventions != b.conventions),
    ];
    out.extend(
        settings
            .iter()
            .filter(|(_, d)| *d)
            .map(|(k, _)| format!("settings.{k}")),
    );
    let (a, b) = (&expected.camera, &got.camera);
    let camera = [
        ("position", a.position != b.position),
        ("look_at", a.look_at != b.look_at),
        ("up", a.up != b.up),
        ("vfov", a.vfov_deg != b.vfov_deg),
    ];
    out.extend(camera.iter().filter(|(_, d)| *d).map(|(k, _)| format!("camera.{k}")));
    let count = |what: &str, x: usize, y: usize| format!("{what}: {x} written, {y} read back");
    if expected.materials.len() != got.materials.len() || expected.material_names != got.material_names {
        out.push(count("materials", expected.materials.len(), got.materials.len()));
    } else {
        for (i, name) in expected.material_names.iter().enumerate() {
            if expected.materials[i] != got.materials[i] || expected.metal_given[i] != got.metal_given[i] {
                out.push(format!("materials[{i}] {name:?}"));
            }
        }
    }
    if expected.objects.len() != got.objects.len() {
        out.push(count("objects", expected.objects.len(), got.objects.len()));
    } else {
        for (i, (x, y)) in expected.objects.iter().zip(&got.objects).enumerate() {
            let parts: Vec<&str> = [
                ("name", expected.name_of(x) != got.name_of(y)),
                ("shape", x.shape != y.shape),
                ("material", x.material != y.material),
            ]
            .iter()
            .filter(|(_, d)| *d)
            .map(|(k, _)| *k)
            .collect();
            if !parts.is_empty() {
                out.push(format!("{}: {}", object_label(expected, i), parts.join(", ")));
            }
        }
    }
    if expected.lights.len() != got.lights.len() {
        out.push(count("lights", expected.lights.len(), got.lights.len()));
    } else {
        for (i, (x, y)) in expected.lights.iter().zip(&got.lights).enumerate() {
            if x != y {
                out.push(format!("lights[{i}]"));
            }
        }
    }
    if out.len() > most {
        let rest = out.len() - most;
        out.truncate(most);
        out.push(format!("and {rest} more"));
    }
    out
}
