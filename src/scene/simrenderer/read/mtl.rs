//! A `model`'s materials: its `.mtl` libraries read as SIMRenderer reads them
//! (`SMaterialOBJParser`), and the material each face gets (`SModelOBJLoader`).
//!
//! - A library reads `newmtl NAME`, `Ka`, `Kd`, `Ks` (three numbers each), `Ns` and
//!   `map_Ka`, `map_Kd`, `map_Ks` (an image: the rest of the line); every other line is
//!   skipped. Names and files are the rest of their line.
//! - Numbers are 32-bit floats, as SIMRenderer's `SVertex` and `Ns` hold them, widened to
//!   64 bits: `Kd 0.3` is 0.30000001192092896.
//! - The lines before the first `newmtl` make a material named `default`, and each material
//!   starts from the library defaults: ambient 0.2, diffuse (0.3, 0.7, 0.3), specular 0.2,
//!   shininess 5 (as 32-bit floats).
//! - Over the libraries in file order, the first material of a name is kept. A model whose
//!   file names no library that reads has the `default` material alone.
//! - A face takes the material its last `usemtl` names (`default` before any). A name no
//!   library has gets SIMRenderer's default OpenGL material: ambient 0.1, diffuse
//!   (0.3, 0.7, 0.3), specular 0.05, shininess 5.
//!
//! Such a material (`SOpenGLMaterial`) gives each term its colour, with no coefficient:
//! in lumiere's terms `k_a = k_d = k_s = 1`, `S` the diffuse colour and the ambient and
//! specular colours their own ([`TermColors`]).
//! An image takes its term's whole colour (`STextureOpenGLMaterial`), as a texture
//! material's does.

use crate::material::{Material, TermColors};
use crate::texture::{Texture, TextureMaps, UvFormat};
use glam::DVec3;
use std::path::Path;

/// The `default` material's values before a library changes them (`SMaterialOBJ`).
const LIBRARY_AMBIENT: [f32; 3] = [0.2, 0.2, 0.2];
const LIBRARY_DIFFUSE: [f32; 3] = [0.3, 0.7, 0.3];
const LIBRARY_SPECULAR: [f32; 3] = [0.2, 0.2, 0.2];
const LIBRARY_SHININESS: f32 = 5.0;

/// The images' keywords, in the order of [`LibraryMaterial::maps`].
const MAP_KEYWORDS: [&str; 3] = ["map_Ka", "map_Kd", "map_Ks"];

/// One material of a library, as read.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct LibraryMaterial {
    pub(super) name: String,
    pub(super) ka: DVec3,
    pub(super) kd: DVec3,
    pub(super) ks: DVec3,
    pub(super) ns: f64,
    /// The images of `map_Ka`, `map_Kd`, `map_Ks`, as written, with their lines.
    pub(super) maps: [Option<(String, usize)>; 3],
}

impl Default for LibraryMaterial {
    fn default() -> Self {
        let widen = |c: [f32; 3]| DVec3::new(c[0].into(), c[1].into(), c[2].into());
        LibraryMaterial {
            name: "default".to_string(),
            ka: widen(LIBRARY_AMBIENT),
            kd: widen(LIBRARY_DIFFUSE),
            ks: widen(LIBRARY_SPECULAR),
            ns: LIBRARY_SHININESS.into(),
            maps: [None, None, None],
        }
    }
}

/// A library line SIMRenderer skips with a message and lumiere refuses: where, which
/// keyword, and why. The value before it is kept.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct LineError {
    pub(super) line: usize,
    pub(super) column: usize,
    pub(super) keyword: String,
    pub(super) message: String,
}

impl LineError {
    /// `FILE:LINE:COLUMN: KEYWORD: MESSAGE`.
    pub(super) fn in_file(&self, file: &impl std::fmt::Display) -> String {
        format!(
            "{file}:{}:{}: {}: {}",
            self.line, self.column, self.keyword, self.message
        )
    }
}

/// The materials of library text, in order (the `default` one first), and the lines in
/// error.
pub(super) fn parse_library(text: &str) -> (Vec<LibraryMaterial>, Vec<LineError>) {
    let mut materials = Vec::new();
    let mut errors = Vec::new();
    let mut current = LibraryMaterial::default();
    for (i, line) in text.lines().enumerate() {
        let Some(keyword) = line.split_whitespace().next() else {
            continue;
        };
        let start = line.len() - line.trim_start().len() + keyword.len();
        let rest = line[start..].trim();
        // 1-based, in characters.
        let column = line[..line.len() - line[start..].trim_start().len()].chars().count() + 1;
        let fail = |message: String| LineError {
            line: i + 1,
            column,
            keyword: keyword.to_string(),
            message,
        };
        match keyword {
            "newmtl" => {
                materials.push(std::mem::take(&mut current));
                current.name = rest.to_string();
            }
            "Ka" | "Kd" | "Ks" => match color(rest) {
                Ok(c) => match keyword {
                    "Ka" => current.ka = c,
                    "Kd" => current.kd = c,
                    _ => current.ks = c,
                },
                Err(m) => errors.push(fail(m)),
            },
            "Ns" => match float(rest) {
                Some(n) if (0.0..=crate::limits::MAX_SHININESS).contains(&n) => current.ns = n,
                Some(n) => errors.push(fail(format!(
                    "the shininess must be in [0, {:e}], got {n}",
                    crate::limits::MAX_SHININESS
                ))),
                None => errors.push(fail(format!("expects a number, got {rest:?}"))),
            },
            "map_Ka" | "map_Kd" | "map_Ks" if !rest.is_empty() => {
                let k = MAP_KEYWORDS.iter().position(|k| *k == keyword).unwrap_or(0);
                current.maps[k] = Some((rest.to_string(), i + 1));
            }
            _ => {}
        }
    }
    materials.push(current);
    (materials, errors)
}

/// A number as SIMRenderer reads it: a 32-bit float, widened.
fn float(word: &str) -> Option<f64> {
    word.parse::<f32>().ok().map(f64::from)
}

/// Three numbers in [0, 1].
fn color(rest: &str) -> Result<DVec3, String> {
    let words: Vec<&str> = rest.split_whitespace().collect();
    if words.len() != 3 {
        return Err(format!("expects three numbers r g b, got {rest:?}"));
    }
    let mut c = [0.0; 3];
    for (k, word) in words.iter().enumerate() {
        c[k] = float(word).ok_or_else(|| format!("expects three numbers r g b, `{word}` is not a number"))?;
    }
    if c.iter().any(|x| !(0.0..=1.0).contains(x)) {
        return Err(format!(
            "each channel must be in [0, 1], got {} {} {}",
            c[0], c[1], c[2]
        ));
    }
    Ok(DVec3::from_array(c))
}

/// SIMRenderer's OpenGL material of colours `ka`, `kd`, `ks`, shininess `ns` and `images`,
/// the material's other factors at their defaults (its metal factor shapes no term: the
/// specular colour is given).
pub(super) fn open_gl(ka: DVec3, kd: DVec3, ks: DVec3, ns: f64, images: Option<TextureMaps>) -> Material {
    Material {
        color: kd,
        ka: 1.0,
        kd: 1.0,
        ks: 1.0,
        shininess: ns,
        term_colors: TermColors::of(Some(ka), Some(ks), images),
        ..Material::default()
    }
}

/// SIMRenderer's material for a face whose `usemtl` names no material of the libraries
/// (`SOpenGLMaterial`'s defaults).
pub(super) fn missing_material() -> Material {
    open_gl(
        DVec3::splat(0.1),
        DVec3::new(0.3, 0.7, 0.3),
        DVec3::splat(0.05),
        5.0,
        None,
    )
}

/// The material a library material gives, its images read from `dir` (the library's
/// folder, `scene_dir` the scene file's: an image is named by its path from there, as a
/// texture material's image is) and placed by `uv_format`; with the images that do not
/// read, each as its line in the library, its keyword and why (the term then keeps its
/// colour).
pub(super) fn library_material(
    m: &LibraryMaterial,
    dir: &Path,
    scene_dir: &Path,
    uv_format: UvFormat,
) -> (Material, Vec<(usize, &'static str, String)>) {
    let mut errors = Vec::new();
    let mut images: [Option<Texture>; 3] = [None, None, None];
    for ((slot, map), keyword) in images.iter_mut().zip(&m.maps).zip(MAP_KEYWORDS) {
        if let Some((file, line)) = map {
            let path = dir.join(file);
            let name = path.strip_prefix(scene_dir).unwrap_or(&path).display().to_string();
            match Texture::load(&path, &name) {
                Ok(t) => *slot = Some(t),
                Err(message) => errors.push((*line, keyword, message)),
            }
        }
    }
    let maps = images.iter().any(Option::is_some).then(|| {
        let [ambient, diffuse, specular] = images;
        TextureMaps {
            ambient,
            diffuse,
            specular,
            uv_format,
        }
    });
    (open_gl(m.ka, m.kd, m.ks, m.ns, maps), errors)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_32_bit_floats_and_the_first_material_is_the_default() {
        let (m, errors) = parse_library("# comment\nKd 1 0 0\nnewmtl red\nKd 0.3 0.5 1\nNs 96.078431\nillum 2\n");
        assert_eq!(errors, vec![]);
        assert_eq!(m.len(), 2);
        // The lines before the first newmtl change the default material.
        assert_eq!(m[0].name, "default");
        assert_eq!(m[0].kd, DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(m[0].ka, DVec3::splat(0.20000000298023224));
        // A new material starts from the library's defaults, not from the one before.
        assert_eq!(m[1].name, "red");
        assert_eq!(m[1].kd, DVec3::new(0.30000001192092896, 0.5, 1.0));
        assert_eq!(m[1].ks, DVec3::splat(0.20000000298023224));
        assert_eq!(m[1].ns, 96.07843017578125);
        assert_eq!(m[1].maps, [None, None, None]);
    }

    #[test]
    fn names_and_images_are_the_rest_of_their_line() {
        let (m, errors) = parse_library("newmtl  my wood \nmap_Kd  wood grain.png \nmap_Ks\n");
        assert_eq!(errors, vec![]);
        assert_eq!(m[1].name, "my wood");
        assert_eq!(m[1].maps, [None, Some(("wood grain.png".to_string(), 2)), None]);
    }

    #[test]
    fn bad_lines_are_located_and_keep_the_value_before() {
        let (m, errors) = parse_library("newmtl a\n  Kd 0.5 0.5\nKs 2 0 0\nNs shiny\nKa 0.1 x 0\n");
        assert_eq!(
            m[1].kd,
            DVec3::new(0.30000001192092896, 0.699999988079071, 0.30000001192092896)
        );
        assert_eq!(m[1].ks, DVec3::splat(0.20000000298023224));
        let said: Vec<String> = errors.iter().map(|e| e.in_file(&"a.mtl")).collect();
        assert_eq!(
            said,
            vec![
                "a.mtl:2:6: Kd: expects three numbers r g b, got \"0.5 0.5\"",
                "a.mtl:3:4: Ks: each channel must be in [0, 1], got 2 0 0",
                "a.mtl:4:4: Ns: expects a number, got \"shiny\"",
                "a.mtl:5:4: Ka: expects three numbers r g b, `x` is not a number",
            ]
        );
    }

    #[test]
    fn an_open_gl_material_gives_each_term_its_colour() {
        let m = open_gl(
            DVec3::splat(0.1),
            DVec3::new(0.3, 0.7, 0.3),
            DVec3::splat(0.05),
            5.0,
            None,
        );
        let r = m.reflectance(|| (0.0, 0.0));
        assert_eq!((r.ka, r.kd, r.ks), (1.0, 1.0, 1.0));
        assert_eq!(r.ambient, DVec3::splat(0.1));
        assert_eq!(r.diffuse, DVec3::new(0.3, 0.7, 0.3));
        assert_eq!(r.tint, DVec3::splat(0.05));
        assert_eq!(missing_material(), m);
    }
}
