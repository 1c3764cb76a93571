//! A shape's `transform` table: [`FileTransform`], its checks ([`transform_of`]) and the
//! shape it moves ([`moved`]).

use super::check::{Check, Xyz, angles, fail, placed, vec3};
use crate::limits;
use crate::scene::locate::FieldPath;
use crate::scene::rules;
use crate::shape::{Shape, Transform};
use serde::Deserialize;

/// `world = T Rz Ry Rx S local`, or `world = [A | b] local`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FileTransform {
    scale: Option<Xyz>,
    rotation: Option<Xyz>,
    translation: Option<Xyz>,
    /// Rows `[a, b, c, d]` of the 3x4 matrix `[A | b]`.
    matrix: Option<[[f64; 4]; 3]>,
}

/// The checked transform of a shape's `transform` table at `path`, `None` when absent or
/// the identity: scale factors of magnitude in [`limits::MIN_SCALE`, `limits::MAX_SCALE`]
/// (negative ones mirror), angles in [-360, 360] degrees, a translation within the
/// coordinates' range; or a `matrix` (alone) whose 3x3 part and its inverse have entries
/// of magnitude at most `MAX_SCALE`, with a translation column within the range.
pub(super) fn transform_of(path: &FieldPath, t: Option<FileTransform>) -> Check<Option<Transform>> {
    let Some(t) = t else { return Ok(None) };
    let (lo, hi) = (limits::MIN_SCALE, limits::MAX_SCALE);
    let transform = if let Some(rows) = t.matrix {
        for (key, given) in [
            ("scale", t.scale.is_some()),
            ("rotation", t.rotation.is_some()),
            ("translation", t.translation.is_some()),
        ] {
            if given {
                return fail(
                    &path.key(key),
                    format!("{key} does not go with matrix (the matrix is the whole transform)"),
                );
            }
        }
        let m = path.key("matrix");
        for (r, row) in rows.iter().enumerate() {
            let linear = &row[..3];
            if linear.iter().any(|a| !a.is_finite() || a.abs() > hi)
                || !(row[3].is_finite() && row[3].abs() <= limits::MAX_COORDINATE)
            {
                return fail(
                    &m.index(r),
                    format!(
                        "must be [a, b, c, d] with a, b, c finite in [-{hi:e}, {hi:e}] and d (the translation) in [-{c:e}, {c:e}], got {row:?}",
                        c = limits::MAX_COORDINATE
                    ),
                );
            }
        }
        match Transform::from_rows(rows) {
            Some(t)
                if t.to_local
                    .to_cols_array()
                    .iter()
                    .all(|a| a.is_finite() && a.abs() <= 1.0 / lo) =>
            {
                t
            }
            _ => {
                return fail(
                    &m,
                    format!(
                        "the 3x3 part must be invertible, its inverse's entries in [-{:e}, {:e}] (no factor below {lo:e}), got {rows:?}",
                        1.0 / lo,
                        1.0 / lo
                    ),
                );
            }
        }
    } else {
        let scale = placed(
            &path.key("scale"),
            rules::scale_factors(t.scale.map_or([1.0; 3], |s| s.0), rules::Syntax::Toml),
        )?;
        let rotation = angles(&path.key("rotation"), t.rotation.unwrap_or_default())?;
        let translation = vec3(&path.key("translation"), t.translation.unwrap_or_default())?;
        Transform::from_parts(scale, rotation, translation)
    };
    Ok((!transform.is_identity()).then_some(transform))
}

/// `shape` through `t`, refused at `path` (the `transform` field) in the words of
/// [`Transform::apply_within_limits`].
pub(super) fn moved(path: &FieldPath, t: &Transform, shape: Shape) -> Check<Shape> {
    t.apply_within_limits(shape).or_else(|m| fail(path, m))
}
