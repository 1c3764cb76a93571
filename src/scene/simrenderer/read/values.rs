//! The readers of one line's value (a point, a direction, a number or an integer in a range,
//! a colour, scale factors, angles), each refusing a value out of its range at the value's
//! column; and `unit`, which makes a direction unit.

use crate::limits;
use crate::scene::rules::{self, Syntax::SimRenderer};
use crate::scene::simrenderer::lex::{self, Line, ValueError};
use glam::DVec3;

/// A direction made unit as the TOML format makes it (divided by its length).
pub(super) fn unit(v: DVec3) -> DVec3 {
    v / v.length()
}

fn value_error<T>(column: usize, message: String) -> Result<T, ValueError> {
    Err(ValueError { column, message })
}

/// The value a rule ([`rules`]) passed, or its message at the line's value.
fn placed<T>(l: &Line, checked: Result<T, String>) -> Result<T, ValueError> {
    checked.or_else(|m| value_error(l.value_column, m))
}

/// A point: finite coordinates of magnitude at most [`crate::limits::MAX_COORDINATE`].
pub(super) fn point(l: &Line) -> Result<DVec3, ValueError> {
    placed(l, rules::point(lex::vector(l.value, l.value_column)?, SimRenderer))
}

/// A direction: a point of non-zero length (not yet made unit).
pub(super) fn direction(l: &Line) -> Result<DVec3, ValueError> {
    placed(l, rules::direction(lex::vector(l.value, l.value_column)?, SimRenderer))
}

/// Texture coordinates `u v`, each finite within the coordinates' range.
pub(super) fn uv(l: &Line) -> Result<[f64; 2], ValueError> {
    let [u, v] = lex::pair(l.value, l.value_column)?;
    let m = limits::MAX_COORDINATE;
    placed(l, rules::number_in(u, -m, m))?;
    placed(l, rules::number_in(v, -m, m))?;
    Ok([u, v])
}

/// A number in `[lo, hi]`.
pub(super) fn number_in(l: &Line, lo: f64, hi: f64) -> Result<f64, ValueError> {
    let (x, written) = lex::number_as_written(l.value, l.value_column)?;
    rules::number_in(x, lo, hi).or_else(|m| value_error(l.value_column, format!("{m}, got {written}")))
}

/// A number in `(0, hi]`.
pub(super) fn positive(l: &Line, hi: f64) -> Result<f64, ValueError> {
    let (x, written) = lex::number_as_written(l.value, l.value_column)?;
    rules::positive(x, hi).or_else(|m| value_error(l.value_column, format!("{m}, got {written}")))
}

/// The far clipping plane: a number above 0, `Infinity` for none.
pub(super) fn far(l: &Line) -> Result<f64, ValueError> {
    let (x, written) = lex::number_as_written(l.value, l.value_column)?;
    if x.is_nan() || x <= 0.0 {
        return value_error(
            l.value_column,
            format!("must be a number above 0 (Infinity: no limit), got {written}"),
        );
    }
    Ok(x)
}

/// An integer in `[lo, hi]`.
pub(super) fn int_in(l: &Line, lo: i32, hi: i32) -> Result<i32, ValueError> {
    let n = lex::integer(l.value, l.value_column)?;
    match i32::try_from(n) {
        Ok(n) if (lo..=hi).contains(&n) => Ok(n),
        _ => value_error(l.value_column, format!("must be an integer in [{lo}, {hi}], got {n}")),
    }
}

/// A colour with each channel in `[0, hi]`.
pub(super) fn color(l: &Line, hi: f64) -> Result<DVec3, ValueError> {
    placed(l, rules::color(lex::color(l.value, l.value_column)?, hi, SimRenderer))
}

/// Scale factors of magnitude in [`crate::limits::MIN_SCALE`, `crate::limits::MAX_SCALE`]
/// (negative ones mirror).
pub(super) fn scale_factors(l: &Line) -> Result<DVec3, ValueError> {
    placed(
        l,
        rules::scale_factors(lex::vector(l.value, l.value_column)?, SimRenderer),
    )
}

/// Angles in degrees, each in [-360, 360].
pub(super) fn angles(l: &Line) -> Result<DVec3, ValueError> {
    placed(l, rules::angles(lex::vector(l.value, l.value_column)?, SimRenderer))
}
