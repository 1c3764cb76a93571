//! The readers of one line's value (a point, a direction, a number or an integer in a range,
//! a colour, scale factors, angles), each refusing a value out of its range at the value's
//! column; and `unit`, which makes a direction unit.

use crate::limits;
use crate::scene::simrenderer::lex::{self, Line, ValueError};
use glam::DVec3;

/// A direction made unit as the TOML format makes it (divided by its length).
pub(super) fn unit(v: DVec3) -> DVec3 {
    v / v.length()
}

fn value_error<T>(column: usize, message: String) -> Result<T, ValueError> {
    Err(ValueError { column, message })
}

/// A point: finite coordinates of magnitude at most [`limits::MAX_COORDINATE`].
pub(super) fn point(l: &Line) -> Result<DVec3, ValueError> {
    let v = lex::vector(l.value, l.value_column)?;
    let m = limits::MAX_COORDINATE;
    if v.iter().any(|c| !c.is_finite() || c.abs() > m) {
        return value_error(
            l.value_column,
            format!("components must be finite numbers in [-{m:e}, {m:e}], got {v:?}"),
        );
    }
    Ok(DVec3::from(v))
}

/// A direction: a point of non-zero length (not yet made unit).
pub(super) fn direction(l: &Line) -> Result<DVec3, ValueError> {
    let d = point(l)?;
    if d.length() <= 1e-12 {
        return value_error(
            l.value_column,
            format!("must be a direction of non-zero length, got {:?}", d.to_array()),
        );
    }
    Ok(d)
}

/// A number in `[lo, hi]`.
pub(super) fn number_in(l: &Line, lo: f64, hi: f64) -> Result<f64, ValueError> {
    let (x, written) = lex::number_as_written(l.value, l.value_column)?;
    if !x.is_finite() || x < lo || x > hi {
        let (lo, hi) = (limits::short(lo), limits::short(hi));
        return value_error(
            l.value_column,
            format!("must be a finite number in [{lo}, {hi}], got {written}"),
        );
    }
    Ok(x)
}

/// A number in `(0, hi]`.
pub(super) fn positive(l: &Line, hi: f64) -> Result<f64, ValueError> {
    let (x, written) = lex::number_as_written(l.value, l.value_column)?;
    if !x.is_finite() || x <= 0.0 || x > hi {
        let hi = limits::short(hi);
        return value_error(
            l.value_column,
            format!("must be a finite number in (0, {hi}], got {written}"),
        );
    }
    Ok(x)
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
    let c = lex::color(l.value, l.value_column)?;
    if c.iter().any(|x| !x.is_finite() || *x < 0.0 || *x > hi) {
        return value_error(
            l.value_column,
            format!(
                "each channel must be a finite number in [0, {}], got {c:?}",
                limits::short(hi)
            ),
        );
    }
    Ok(DVec3::from(c))
}

/// Scale factors of magnitude in [`limits::MIN_SCALE`, `limits::MAX_SCALE`] (negative ones
/// mirror).
pub(super) fn scale_factors(l: &Line) -> Result<DVec3, ValueError> {
    let s = lex::vector(l.value, l.value_column)?;
    let (lo, hi) = (limits::MIN_SCALE, limits::MAX_SCALE);
    if s.iter().any(|x| !x.is_finite() || x.abs() < lo || x.abs() > hi) {
        return value_error(
            l.value_column,
            format!("each factor must be finite, of magnitude in [{lo:e}, {hi:e}] (negative mirrors), got {s:?}"),
        );
    }
    Ok(DVec3::from(s))
}

/// Angles in degrees, each in [-360, 360].
pub(super) fn angles(l: &Line) -> Result<DVec3, ValueError> {
    let a = lex::vector(l.value, l.value_column)?;
    if a.iter().any(|x| !x.is_finite() || x.abs() > 360.0) {
        return value_error(
            l.value_column,
            format!("angles must be finite numbers in [-360, 360] degrees, got {a:?}"),
        );
    }
    Ok(DVec3::from(a))
}
