//! The checks of a file's values, each error placed on its field: numbers in a range,
//! points, directions, colours, angles, the edges of a rectangle, the name of a normal
//! interpolation and counts summed over an array; [`Whole`], a whole number before its
//! range is checked; [`Xyz`], the three numbers the file writes for a point, a direction,
//! a colour or angles; and the serde defaults that several tables share.

use crate::scene::locate::{FieldError, FieldPath};
use crate::scene::rules::{self, Syntax::Toml};
use crate::shape::NormalInterpolation;
use glam::DVec3;
use serde::Deserialize;

/// A value that passed its checks, or the error placed on its field.
pub(super) type Check<T> = Result<T, FieldError>;

/// An error at `path`.
pub(super) fn fail<T>(path: &FieldPath, message: impl Into<String>) -> Check<T> {
    Err(FieldError {
        path: path.clone(),
        message: message.into(),
        got: None,
    })
}

/// `message`, followed by `, got X` with X the number `x` as the file writes it.
fn fail_got<T>(path: &FieldPath, message: String, x: f64) -> Check<T> {
    Err(FieldError {
        path: path.clone(),
        message,
        got: Some(x),
    })
}

/// A whole-number field as the file writes it: any integer TOML gives (beyond 64 bits
/// too), so that the field's own range, not its storage type's, is what an error names.
pub(super) type Whole = i128;

/// The value a rule passed (one of [`rules`], or of [`crate::limits`] for a whole number),
/// or the rule's message at `path`.
pub(super) fn placed<T>(path: &FieldPath, checked: Result<T, String>) -> Check<T> {
    checked.or_else(|m| fail(path, m))
}

/// A finite number within `[lo, hi]`.
pub(super) fn in_range(path: &FieldPath, x: f64, lo: f64, hi: f64) -> Check<f64> {
    rules::number_in(x, lo, hi).or_else(|m| fail_got(path, m, x))
}

/// A finite number within `(lo, hi)`.
pub(super) fn between(path: &FieldPath, x: f64, lo: f64, hi: f64) -> Check<f64> {
    rules::number_between(x, lo, hi).or_else(|m| fail_got(path, m, x))
}

/// Three numbers, no more and no fewer: a point, a direction, a colour or angles as the file
/// writes them (`[x, y, z]`). A longer or shorter array is an error on its value.
#[derive(Clone, Copy, Default, PartialEq)]
pub(super) struct Xyz(pub(super) [f64; 3]);

impl std::fmt::Debug for Xyz {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl std::ops::Deref for Xyz {
    type Target = [f64; 3];
    fn deref(&self) -> &[f64; 3] {
        &self.0
    }
}

impl From<Xyz> for DVec3 {
    fn from(v: Xyz) -> DVec3 {
        DVec3::from(v.0)
    }
}

impl<'de> Deserialize<'de> for Xyz {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Three;
        impl<'de> serde::de::Visitor<'de> for Three {
            type Value = Xyz;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an array of length 3")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Xyz, A::Error> {
                let mut v = [0.0; 3];
                for (i, c) in v.iter_mut().enumerate() {
                    *c = seq
                        .next_element()?
                        .ok_or_else(|| serde::de::Error::invalid_length(i, &self))?;
                }
                let mut extra = 0;
                while seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
                    extra += 1;
                }
                if extra > 0 {
                    return Err(serde::de::Error::invalid_length(3 + extra, &self));
                }
                Ok(Xyz(v))
            }
        }
        deserializer.deserialize_seq(Three)
    }
}

/// A finite number `> 0` and at most `hi`.
pub(super) fn positive(path: &FieldPath, x: f64, hi: f64) -> Check<f64> {
    rules::positive(x, hi).or_else(|m| fail_got(path, m, x))
}

/// A point or vector with finite components of magnitude at most `limits::MAX_COORDINATE`.
pub(super) fn vec3(path: &FieldPath, v: Xyz) -> Check<DVec3> {
    placed(path, rules::point(v.0, Toml))
}

/// A direction: finite and of non-zero length; returned normalised.
pub(super) fn direction(path: &FieldPath, v: Xyz) -> Check<DVec3> {
    let d = placed(path, rules::direction(v.0, Toml))?;
    Ok(d / d.length())
}

/// A colour: each channel finite in `[0, hi]`.
pub(super) fn color(path: &FieldPath, v: Xyz, hi: f64) -> Check<DVec3> {
    placed(path, rules::color(v.0, hi, Toml))
}

/// Angles in degrees, each finite in [-360, 360].
pub(super) fn angles(path: &FieldPath, v: Xyz) -> Check<DVec3> {
    placed(path, rules::angles(v.0, Toml))
}

/// The two edges of a rectangle or window (`edge1`, `edge2` of the entry at `path`): each of
/// non-zero length and not parallel, else the surface is a segment or a point.
pub(super) fn spanning_edges(path: &FieldPath, edge1: Xyz, edge2: Xyz) -> Check<(DVec3, DVec3)> {
    let e1 = vec3(&path.key("edge1"), edge1)?;
    let e2 = vec3(&path.key("edge2"), edge2)?;
    for (key, e, raw) in [("edge1", e1, edge1), ("edge2", e2, edge2)] {
        // The length, not the components: a length that underflows to 0 cannot be normalised.
        if e.length() == 0.0 {
            return fail(&path.key(key), format!("must have a non-zero length, got {raw:?}"));
        }
    }
    if e1.normalize().cross(e2.normalize()).length() <= 1e-12 {
        return fail(
            &path.key("edge2"),
            format!("must not be parallel to edge1 {edge1:?}, got {edge2:?}"),
        );
    }
    Ok((e1, e2))
}

/// `start` plus the running sum of `counts` (one per entry of the array at `path`) must stay
/// at most `max`; else an error at field `key` of the entry that passes it, saying the scene
/// would hold that many `what`.
pub(super) fn running_total(
    path: &FieldPath,
    key: &str,
    start: u64,
    counts: impl IntoIterator<Item = u64>,
    max: u64,
    what: &str,
) -> Check<()> {
    let mut total = start;
    for (i, n) in counts.into_iter().enumerate() {
        total += n;
        if total > max {
            return fail(
                &path.index(i).key(key),
                format!("the scene would hold {total} {what}, at most {max} are allowed"),
            );
        }
    }
    Ok(())
}

/// `[1, 1, 1]`: white.
pub(super) fn one() -> Xyz {
    Xyz([1.0; 3])
}

/// `[0, 0, 1]`: the camera's up, a shape's axis or normal, an aperture's front.
pub(super) fn plus_z() -> Xyz {
    Xyz([0.0, 0.0, 1.0])
}

/// The rule named `name` at `path` (a triangle's or a mesh's `normal_interpolation`).
pub(super) fn normal_interpolation(path: &FieldPath, name: &str) -> Check<NormalInterpolation> {
    NormalInterpolation::from_name(name).map_or_else(
        || {
            let names: Vec<String> = NormalInterpolation::NAMES.iter().map(|n| format!("{n:?}")).collect();
            fail(path, format!("must be {}, got {name:?}", names.join(" or ")))
        },
        Ok,
    )
}
