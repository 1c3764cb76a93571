//! The rules a scene value must meet, written once for both readers (the TOML format's
//! `file::check` and SIMRenderer's `read::values`): each returns the value, or what it must
//! be. The reader places the message on its field or column; for a single number it adds the
//! value as the file writes it (`, got 1e-7`), which only the reader has. A rule on a vector
//! shows it as the reader's format writes one ([`Syntax`]).

use crate::{decimal, limits};
use glam::DVec3;

/// A scene file format's way of writing a vector, for messages to show one as the file
/// at fault would hold it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Syntax {
    /// TOML's array: `[2.0, 0.0, 0.5]`.
    Toml,
    /// SIMRenderer's numbers between blanks, each as its writer writes it (an integer when
    /// it is one, else the shortest decimal that reads back to the same value): `2 0 0.5`,
    /// `0.5 -1 1e-9`, `Infinity`, `NaN`.
    SimRenderer,
}

impl Syntax {
    /// `v` as the format writes it.
    pub fn vector(self, v: &[f64]) -> String {
        match self {
            Syntax::Toml => format!("{v:?}"),
            Syntax::SimRenderer => decimal::numbers(v, "Infinity"),
        }
    }
}

/// What "the transform" of a mesh read from `file` does when it moves the mesh's vertex
/// `v` beyond the coordinates' range ([`crate::shape::mesh::Mesh::transform`]), with `v`
/// as the scene file's `syntax` writes it.
pub fn moved_mesh(file: &impl std::fmt::Display, v: DVec3, syntax: Syntax) -> String {
    let m = limits::MAX_COORDINATE;
    format!(
        "moves a vertex of {file} to {}, beyond the coordinates' range [-{m:e}, {m:e}]",
        syntax.vector(&v.to_array())
    )
}

/// A finite number in `[lo, hi]`.
pub fn number_in(x: f64, lo: f64, hi: f64) -> Result<f64, String> {
    if !x.is_finite() || x < lo || x > hi {
        let (lo, hi) = (limits::short(lo), limits::short(hi));
        return Err(format!("must be a finite number in [{lo}, {hi}]"));
    }
    Ok(x)
}

/// A finite number in `(lo, hi)`, both ends left out.
pub fn number_between(x: f64, lo: f64, hi: f64) -> Result<f64, String> {
    if !x.is_finite() || x <= lo || x >= hi {
        let (lo, hi) = (limits::short(lo), limits::short(hi));
        return Err(format!("must be a finite number in ({lo}, {hi})"));
    }
    Ok(x)
}

/// A finite number in `(0, hi]`.
pub fn positive(x: f64, hi: f64) -> Result<f64, String> {
    if !x.is_finite() || x <= 0.0 || x > hi {
        let hi = limits::short(hi);
        return Err(format!("must be a finite number in (0, {hi}]"));
    }
    Ok(x)
}

/// An adaptive depth control threshold in 8-bit levels: in [0, MAX_ADAPTIVE_THRESHOLD].
pub fn adaptive_threshold(x: f64) -> Result<f64, String> {
    number_in(x, 0.0, limits::MAX_ADAPTIVE_THRESHOLD)
}

/// A point or vector: finite components of magnitude at most [`limits::MAX_COORDINATE`].
pub fn point(v: [f64; 3], syntax: Syntax) -> Result<DVec3, String> {
    let m = limits::MAX_COORDINATE;
    if v.iter().any(|c| !c.is_finite() || c.abs() > m) {
        return Err(format!(
            "components must be finite numbers in [-{m:e}, {m:e}], got {}",
            syntax.vector(&v)
        ));
    }
    Ok(DVec3::from(v))
}

/// A direction: a point of non-zero length (as given, not made unit).
pub fn direction(v: [f64; 3], syntax: Syntax) -> Result<DVec3, String> {
    let d = point(v, syntax)?;
    if d.length() <= 1e-12 {
        return Err(format!(
            "must be a direction of non-zero length, got {}",
            syntax.vector(&v)
        ));
    }
    Ok(d)
}

/// A colour: each channel finite in `[0, hi]`.
pub fn color(v: [f64; 3], hi: f64, syntax: Syntax) -> Result<DVec3, String> {
    if v.iter().any(|c| !c.is_finite() || *c < 0.0 || *c > hi) {
        let hi = limits::short(hi);
        return Err(format!(
            "each channel must be a finite number in [0, {hi}], got {}",
            syntax.vector(&v)
        ));
    }
    Ok(DVec3::from(v))
}

/// Angles in degrees, each finite in [-360, 360].
pub fn angles(v: [f64; 3], syntax: Syntax) -> Result<DVec3, String> {
    if v.iter().any(|a| !a.is_finite() || a.abs() > 360.0) {
        return Err(format!(
            "angles must be finite numbers in [-360, 360] degrees, got {}",
            syntax.vector(&v)
        ));
    }
    Ok(DVec3::from(v))
}

/// Scale factors of magnitude in [[`limits::MIN_SCALE`], [`limits::MAX_SCALE`]] (a negative
/// one mirrors).
pub fn scale_factors(v: [f64; 3], syntax: Syntax) -> Result<DVec3, String> {
    let (lo, hi) = (limits::MIN_SCALE, limits::MAX_SCALE);
    if v.iter().any(|s| !s.is_finite() || s.abs() < lo || s.abs() > hi) {
        return Err(format!(
            "each factor must be finite, of magnitude in [{lo:e}, {hi:e}] (negative mirrors), got {}",
            syntax.vector(&v)
        ));
    }
    Ok(DVec3::from(v))
}

#[cfg(test)]
mod tests {
    use super::Syntax::{SimRenderer, Toml};
    use super::*;

    #[test]
    fn a_mesh_moved_out_of_range_is_named_with_its_vertex_as_the_file_writes_it() {
        let v = DVec3::new(1.001e9, 0.0, -0.5);
        let range = "beyond the coordinates' range [-1e9, 1e9]";
        assert_eq!(
            moved_mesh(&"cube.obj", v, Toml),
            format!("moves a vertex of cube.obj to [1001000000.0, 0.0, -0.5], {range}")
        );
        assert_eq!(
            moved_mesh(&"cube.obj", v, SimRenderer),
            format!("moves a vertex of cube.obj to 1001000000 0 -0.5, {range}")
        );
    }

    #[test]
    fn each_rule_says_its_range() {
        assert_eq!(number_in(0.5, 0.0, 1.0), Ok(0.5));
        assert_eq!(
            number_in(f64::NAN, 0.0, 1.0),
            Err("must be a finite number in [0, 1]".to_string())
        );
        assert_eq!(number_between(179.9, 0.0, 180.0), Ok(179.9));
        for x in [0.0, 180.0, f64::NAN] {
            assert_eq!(
                number_between(x, 0.0, 180.0),
                Err("must be a finite number in (0, 180)".to_string())
            );
        }
        assert_eq!(positive(1e9, 1e9), Ok(1e9));
        assert_eq!(
            positive(0.0, 1e9),
            Err("must be a finite number in (0, 1e9]".to_string())
        );
        assert_eq!(point([1e9, -1e9, 0.0], Toml), Ok(DVec3::new(1e9, -1e9, 0.0)));
        assert_eq!(
            point([2e9, 0.0, 0.0], Toml),
            Err("components must be finite numbers in [-1e9, 1e9], got [2000000000.0, 0.0, 0.0]".to_string())
        );
        assert_eq!(direction([0.0, 0.0, 2.0], Toml), Ok(DVec3::new(0.0, 0.0, 2.0)));
        assert_eq!(
            direction([1e-13, 0.0, 0.0], Toml),
            Err("must be a direction of non-zero length, got [1e-13, 0.0, 0.0]".to_string())
        );
        assert_eq!(
            color([1.0, -1.0, 1.0], 1e6, Toml),
            Err("each channel must be a finite number in [0, 1e6], got [1.0, -1.0, 1.0]".to_string())
        );
        assert_eq!(angles([-360.0, 0.0, 360.0], Toml), Ok(DVec3::new(-360.0, 0.0, 360.0)));
        assert_eq!(
            angles([0.0, f64::INFINITY, 0.0], Toml),
            Err("angles must be finite numbers in [-360, 360] degrees, got [0.0, inf, 0.0]".to_string())
        );
        assert_eq!(scale_factors([-1.0, 1e-6, 1e6], Toml), Ok(DVec3::new(-1.0, 1e-6, 1e6)));
        assert_eq!(
            scale_factors([0.0, 1.0, 1.0], Toml),
            Err(
                "each factor must be finite, of magnitude in [1e-6, 1e6] (negative mirrors), got [0.0, 1.0, 1.0]"
                    .to_string()
            )
        );
    }

    #[test]
    fn a_vector_is_shown_as_its_format_writes_it() {
        let v = [0.5, -1.0, 1e-9];
        assert_eq!(Toml.vector(&v), "[0.5, -1.0, 1e-9]");
        assert_eq!(SimRenderer.vector(&v), "0.5 -1 1e-9");
        // Words Java's Double.valueOf reads back: Infinity, NaN; -0 keeps its sign.
        let odd = [f64::NEG_INFINITY, f64::NAN, -0.0];
        assert_eq!(SimRenderer.vector(&odd), "-Infinity NaN -0.0");
        assert_eq!(
            point([2e9, 0.1, 0.0], SimRenderer),
            Err("components must be finite numbers in [-1e9, 1e9], got 2000000000 0.1 0".to_string())
        );
        assert_eq!(
            color([1.2, 1.0, 1.0], 1.0, SimRenderer),
            Err("each channel must be a finite number in [0, 1], got 1.2 1 1".to_string())
        );
    }
}
