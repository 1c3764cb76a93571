//! A `[[generate]]` table: [`FileGenerate`], checked into the [`Generate`] that places its
//! random objects.

use super::check::{Check, Whole, Xyz, fail, placed, positive, vec3};
use super::material::material_index;
use crate::limits;
use crate::scene::generate::{Generate, GenerateKind};
use crate::scene::locate::FieldPath;
use serde::Deserialize;

/// A `[[generate]]` table: `count` random objects in a box (see `scene/generate.rs`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileGenerate {
    kind: String,
    count: Whole,
    #[serde(default)]
    seed: u64,
    min: Xyz,
    max: Xyz,
    radius: [f64; 2],
    #[serde(default)]
    materials: Vec<String>,
}

impl FileGenerate {
    pub(super) fn validate(&self, path: &FieldPath, material_names: &[String]) -> Check<Generate> {
        let Some(kind) = GenerateKind::parse(&self.kind) else {
            return fail(
                &path.key("kind"),
                format!("must be \"spheres\", \"mixed\" or \"triangles\", got {:?}", self.kind),
            );
        };
        let count = placed(&path.key("count"), limits::check_count(self.count, limits::MAX_OBJECTS))?;
        let min = vec3(&path.key("min"), self.min)?;
        let max = vec3(&path.key("max"), self.max)?;
        if !min.cmplt(max).all() {
            return fail(
                &path.key("max"),
                format!(
                    "must exceed min in every component, got min {:?}, max {:?}",
                    self.min, self.max
                ),
            );
        }
        let r = path.key("radius");
        let lo = positive(&r, self.radius[0], limits::MAX_COORDINATE)?;
        let hi = positive(&r, self.radius[1], limits::MAX_COORDINATE)?;
        if lo > hi {
            return fail(
                &r,
                format!(
                    "must be [smallest, largest] with smallest <= largest, got {:?}",
                    self.radius
                ),
            );
        }
        let materials = if self.materials.is_empty() {
            vec![0]
        } else {
            self.materials
                .iter()
                .map(|m| material_index(&path.key("materials"), m, material_names))
                .collect::<Check<Vec<_>>>()?
        };
        Ok(Generate {
            kind,
            count,
            seed: self.seed,
            min,
            max,
            radius: (lo, hi),
            materials,
        })
    }
}
