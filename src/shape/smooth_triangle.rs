//! A triangle with a normal and texture coordinates at each vertex: SIMRenderer's
//! barycentric triangle (`btriangle`, its `SBTriangleGeometry`), which its model reader
//! also makes of every mesh face that has vertex normals or texture coordinates. The ray
//! meets it as it meets the flat [`Triangle`] (the same watertight test, the same `t`);
//! at the hit, of barycentric coordinates `(b0, b1, b2)`, the normal and the texture
//! coordinates are the vertices' weighted by them:
//!
//! `N = b0 N0 + b1 N1 + b2 N2`, `uv = b0 uv0 + b1 uv1 + b2 uv2`.
//!
//! The vertex normals are unit. Between vertex normals that differ, `N` is shorter than 1
//! (at the middle of vertex normals 36 degrees apart, about 0.96). How it is used is the
//! triangle's [`NormalInterpolation`]: made unit (the usual interpolated shading normal),
//! or kept as it is, as SIMRenderer keeps it: its `SBTriangleGeometry.intersection`
//! returns the weighted sum, and its shading takes that as the normal, so the diffuse term
//! is `|N|` times the unit normal's and a Blinn highlight `|N|^n` times (where opposite
//! vertex normals cancel, `N = 0`, made unit it is the face's normal). Which side the ray
//! comes from is the sign of `N . v`, as SIMRenderer's `SRay.getShadingNormal` decides it.
//!
//! The triangle stays flat: its plane, bounds and rounding-error bound are the flat
//! triangle's.

use super::{Aabb, SurfaceHit, Triangle};
use crate::math::Ray;
use glam::DVec3;

/// What becomes of the interpolated normal's length (see the module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalInterpolation {
    /// `N / |N|`.
    #[default]
    Normalized,
    /// `N` as it is, as SIMRenderer shades it.
    Linear,
}

impl NormalInterpolation {
    /// The names scene files give the rules, in order.
    pub const NAMES: [&'static str; 2] = ["normalized", "linear"];

    /// The rule named `name` ([`NormalInterpolation::NAMES`]).
    pub fn from_name(name: &str) -> Option<NormalInterpolation> {
        match name {
            "normalized" => Some(NormalInterpolation::Normalized),
            "linear" => Some(NormalInterpolation::Linear),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            NormalInterpolation::Normalized => "normalized",
            NormalInterpolation::Linear => "linear",
        }
    }
}

/// A flat triangle with a unit normal and texture coordinates at each vertex.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothTriangle {
    pub triangle: Triangle,
    /// Unit normals at `p0`, `p1`, `p2`.
    pub normals: [DVec3; 3],
    /// Texture coordinates at `p0`, `p1`, `p2`.
    pub uvs: [[f64; 2]; 3],
    pub interpolation: NormalInterpolation,
}

impl SmoothTriangle {
    /// The texture coordinates the flat triangle has without vertex data: `(b1, b2)`.
    pub const FLAT_UVS: [[f64; 2]; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];

    /// The triangle with vertex `normals` (made unit here, each divided by its length as
    /// both scene readers make a written direction unit and SIMRenderer's `normalize` does;
    /// `None` when one has no direction) and texture coordinates `uvs`.
    pub fn new(
        triangle: Triangle,
        normals: [DVec3; 3],
        uvs: [[f64; 2]; 3],
        interpolation: NormalInterpolation,
    ) -> Option<SmoothTriangle> {
        let normals = normals.map(|n| n / n.length());
        normals.iter().all(|n| n.is_finite()).then_some(SmoothTriangle {
            triangle,
            normals,
            uvs,
            interpolation,
        })
    }

    /// `b0 x0 + b1 x1 + b2 x2`.
    fn weighted(b: [f64; 3], x: [DVec3; 3]) -> DVec3 {
        b[0] * x[0] + b[1] * x[1] + b[2] * x[2]
    }

    /// The normal at barycentric coordinates `b` (the module doc's `N`, by the rule).
    pub fn normal_at(&self, b: [f64; 3]) -> DVec3 {
        self.by_rule(Self::weighted(b, self.normals), self.interpolation)
    }

    /// The normal at `p`, a point of the triangle, by `rule` (whatever the triangle's own).
    pub fn normal_at_point(&self, p: DVec3, rule: NormalInterpolation) -> DVec3 {
        let (b1, b2) = self.triangle.barycentric(p);
        self.by_rule(Self::weighted([1.0 - b1 - b2, b1, b2], self.normals), rule)
    }

    /// The interpolated `n` by `rule`. Made unit, a sum of opposite vertex normals that
    /// cancels has no direction: the face's normal is taken there.
    fn by_rule(&self, n: DVec3, rule: NormalInterpolation) -> DVec3 {
        match rule {
            NormalInterpolation::Normalized => n.try_normalize().unwrap_or_else(|| self.triangle.normal()),
            NormalInterpolation::Linear => n,
        }
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<SurfaceHit> {
        let (t, b) = self.triangle.crossing(ray, t_min, t_max)?;
        Some(SurfaceHit {
            t,
            normal: self.normal_at(b),
        })
    }

    #[inline]
    pub fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.triangle.occludes(ray, t_min, t_max)
    }

    /// The texture coordinates at `p`, a point of the triangle.
    pub fn uv(&self, p: DVec3) -> (f64, f64) {
        let (b1, b2) = self.triangle.barycentric(p);
        let b = [1.0 - b1 - b2, b1, b2];
        let [u0, u1, u2] = self.uvs;
        (
            b[0] * u0[0] + b[1] * u1[0] + b[2] * u2[0],
            b[0] * u0[1] + b[1] * u1[1] + b[2] * u2[1],
        )
    }

    pub(crate) fn surface_error(&self, p: DVec3) -> f64 {
        self.triangle.surface_error(p)
    }

    pub fn bounds(&self) -> Option<Aabb> {
        self.triangle.bounds()
    }
}

impl serde::Serialize for SmoothTriangle {
    /// As the triangle's three points, then the vertex data and the rule's name.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let [p0, p1, p2] = self.triangle.points();
        let mut st = s.serialize_struct("SmoothTriangle", 6)?;
        st.serialize_field("p0", &p0)?;
        st.serialize_field("p1", &p1)?;
        st.serialize_field("p2", &p2)?;
        st.serialize_field("normals", &self.normals)?;
        st.serialize_field("uvs", &self.uvs)?;
        st.serialize_field("normal_interpolation", self.interpolation.name())?;
        st.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SIMRenderer's own test of `SBTriangleGeometry` (`intersectionTest3b`, `3c`): the
    /// triangle (1, 1, 0), (1, -1, 0), (-1, 0, 0) with unit normals along (0, 0, 1),
    /// (1, 1, 1) and (0, 1, 1), hit at the origin from (0, 0, 1) along -z. The origin's
    /// barycentric coordinates are (1/4, 1/4, 1/2), so
    /// `N = (0, 0, 1)/4 + (1, 1, 1)/(4 sqrt 3) + (0, 1, 1)/(2 sqrt 2)`, the values its test
    /// expects; uv0..2 = (0, 0), (1, 1), (0, 1) give (1/4, 3/4).
    #[test]
    fn simrenderer_test_values() {
        let t = Triangle::new(
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(-1.0, 0.0, 0.0),
        );
        let normals = [DVec3::Z, DVec3::ONE, DVec3::new(0.0, 1.0, 1.0)];
        let uvs = [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let ray = Ray::new(DVec3::Z, -DVec3::Z);
        let linear = SmoothTriangle::new(t.clone(), normals, uvs, NormalInterpolation::Linear).unwrap();
        let hit = linear.intersect(&ray, 0.0, f64::INFINITY).unwrap();
        assert_eq!(hit.t, 1.0);
        let expected = DVec3::new(0.14433756729740646, 0.4978909578906803, 0.7478909578906803);
        assert!((hit.normal - expected).length() < 1e-15, "{}", hit.normal);
        let (u, v) = linear.uv(ray.at(hit.t));
        assert!((u - 0.25).abs() < 1e-15 && (v - 0.75).abs() < 1e-15, "({u}, {v})");
        let unit = SmoothTriangle::new(t, normals, uvs, NormalInterpolation::Normalized).unwrap();
        let n = unit.intersect(&ray, 0.0, f64::INFINITY).unwrap().normal;
        assert!((n - expected / expected.length()).length() < 1e-15);
    }

    /// SIMRenderer's `intersectionTest4b`: a triangle built around the hit point
    /// r = (3.4, 6.7, 3.5) from the base b1 = (-7.8, 3.1, 4.9), b2 = (1.7, -2.6, 9.3),
    /// p0 = r - 2.5 b1 - 1.8 b2, p1 = r - 1.5 b1 + 2.8 b2, p2 = r + 3.7 b1 + 0.7 b2, hit at
    /// t = 5.9 by a ray from r - 5.9 v along v = (-7.5, 3.8, -4.2) (not unit: SIMRenderer's
    /// rays need not be). Its expected normal and uv, to within rounding.
    #[test]
    fn simrenderer_general_triangle() {
        let r = DVec3::new(3.4, 6.7, 3.5);
        let (b1, b2) = (DVec3::new(-7.8, 3.1, 4.9), DVec3::new(1.7, -2.6, 9.3));
        let t = Triangle::new(
            r - 2.5 * b1 - 1.8 * b2,
            r - 1.5 * b1 + 2.8 * b2,
            r + 3.7 * b1 + 0.7 * b2,
        );
        let normals = [DVec3::Z, DVec3::ONE, DVec3::new(0.0, 1.0, 1.0)];
        let uvs = [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let s = SmoothTriangle::new(t, normals, uvs, NormalInterpolation::Linear).unwrap();
        let v = DVec3::new(-7.5, 3.8, -4.2);
        // lumiere's rays are unit: the same line, parameter scaled by |v|.
        let ray = Ray::new(r - 5.9 * v, v.normalize());
        let hit = s.intersect(&ray, 0.0, f64::INFINITY).unwrap();
        assert!((hit.t / v.length() - 5.9).abs() < 1e-12, "{}", hit.t);
        let expected = DVec3::new(0.10894657270257797, 0.3725490237982545, 0.8110578631525966);
        assert!((hit.normal - expected).length() < 1e-13, "{}", hit.normal);
        let (u, w) = s.uv(ray.at(hit.t));
        assert!((u - 0.18870099923136155).abs() < 1e-13 && (w - 0.5614911606456578).abs() < 1e-13);
    }

    /// Equal vertex normals give that normal everywhere (to rounding), under both rules,
    /// and a point at a vertex gets that vertex's normal and coordinates.
    #[test]
    fn equal_normals_and_vertices() {
        let t = Triangle::new(DVec3::ZERO, DVec3::X, DVec3::Y);
        let n = DVec3::new(0.0, 0.6, 0.8);
        let s = SmoothTriangle::new(t, [n; 3], SmoothTriangle::FLAT_UVS, NormalInterpolation::Linear).unwrap();
        for b in [[0.2, 0.3, 0.5], [1.0 / 3.0; 3]] {
            assert!((s.normal_at(b) - n).length() < 1e-15);
        }
        assert_eq!(s.normal_at([0.0, 1.0, 0.0]), n);
        assert_eq!(s.uv(DVec3::new(0.25, 0.5, 0.0)), (0.25, 0.5));
    }

    /// Opposite vertex normals cancel on a line of the face: there the normalized rule takes
    /// the face's normal (no NaN), and the linear rule keeps the zero vector SIMRenderer
    /// shades with (no light).
    #[test]
    fn normals_that_cancel() {
        let t = Triangle::new(DVec3::ZERO, DVec3::X, DVec3::Y);
        let normals = [DVec3::Z, -DVec3::Z, DVec3::Z];
        let b = [0.25, 0.5, 0.25];
        let unit = SmoothTriangle::new(
            t.clone(),
            normals,
            SmoothTriangle::FLAT_UVS,
            NormalInterpolation::Normalized,
        );
        assert_eq!(unit.unwrap().normal_at(b), DVec3::Z);
        let linear = SmoothTriangle::new(t, normals, SmoothTriangle::FLAT_UVS, NormalInterpolation::Linear);
        assert_eq!(linear.unwrap().normal_at(b), DVec3::ZERO);
    }

    #[test]
    fn a_normal_without_direction_is_refused() {
        let t = Triangle::new(DVec3::ZERO, DVec3::X, DVec3::Y);
        let normals = [DVec3::Z, DVec3::ZERO, DVec3::Z];
        assert!(SmoothTriangle::new(t, normals, SmoothTriangle::FLAT_UVS, NormalInterpolation::Linear).is_none());
    }
}
