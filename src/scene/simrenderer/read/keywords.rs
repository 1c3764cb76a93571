//! The format's keyword table: every keyword with its French aliases, the keywords each
//! block takes, the values of its enumerations, and the defaults a file leaves to SIMRenderer
//! (the grey material of an unknown name, the seed).

use crate::material::Material;
use crate::scene::{ShadingModel, Specular};
use std::collections::HashMap;
use std::sync::LazyLock;

/// Every keyword: its canonical name, then its aliases.
const KEYWORDS: &[&[&str]] = &[
    &["end", "fin"],
    // Top-level blocks.
    &["camera"],
    &["viewport"],
    &["raytracer"],
    &["primitive"],
    &["material", "blinn_material", "color_material", "materiel"],
    &["texture_material", "texture_materiel"],
    &["ambient_light", "lumiere_ambiante"],
    &["directional_light", "lumiere_directionnelle"],
    &["point_light", "lumiere_ponctuelle"],
    &["linear_aperture_light"],
    &["rectangular_aperture_light"],
    &["elliptical_aperture_light"],
    &["aperture_mask_light"],
    &["model"],
    // Geometries.
    &["sphere"],
    &["plane", "plan"],
    &["disk", "disque"],
    &["triangle"],
    &["btriangle"],
    &["tube"],
    &["cylinder", "cylindre"],
    &["cone"],
    &["cube"],
    &["torus", "tore"],
    &["spherical_cap", "calotte_spherique"],
    &["lens", "lentille"],
    &["geometry", "geometrie"],
    // Values.
    &["position"],
    &["look_at"],
    &["up", "haut"],
    &["angle"],
    &["near_clipping_plane"],
    &["far_clipping_plane"],
    &["width", "largeur"],
    &["height", "hauteur"],
    &["image_file_name", "nom_fichier_image"],
    &["task"],
    &["sampling"],
    &["recursive_level"],
    &["reflexion_algorithm", "algorithme_reflexion"],
    &["pixel_coordinate", "coordonnee_pixel"],
    &["space", "espace"],
    &["color_normalization"],
    &["name", "nom"],
    &["color", "couleur"],
    &["ka"],
    &["kd"],
    &["ks"],
    &["kr"],
    &["kt"],
    &["shininess", "brillance"],
    &["plasticity", "p"],
    &["refractive_index", "n"],
    &["material_name", "nom_materiel"],
    &["ray", "rayon"],
    &["normal", "normale"],
    &["point"],
    &["size", "taille"],
    &["major_radius"],
    &["minor_radius"],
    &["scale", "homothetie"],
    &["rotation"],
    &["translation"],
    &["file", "fichier"],
    &["uv_format"],
    &["uv"],
    &["orientation"],
    &["amplification"],
    &["constant_attenuator"],
    &["linear_attenuator"],
    &["quadratic_attenuator"],
    &["wave_length", "longueur_onde"],
    &["period_iteration"],
    &["nb_oscillator"],
    &["front", "devant"],
    &["mask", "masque"],
    // The caps' and lenses' curvature, and a texture material's images.
    &["curvature", "courbure"],
    &["texture_ka"],
    &["texture_kd"],
    &["texture_ks"],
];

/// The canonical name of a keyword (lower case), or `None` when SIMRenderer has no such
/// keyword.
pub fn canonical(keyword: &str) -> Option<&'static str> {
    static BY_NAME: LazyLock<HashMap<&'static str, &'static str>> = LazyLock::new(|| {
        KEYWORDS
            .iter()
            .flat_map(|names| names.iter().map(|n| (*n, names[0])))
            .collect()
    });
    BY_NAME.get(keyword).copied()
}

/// `name (alias, alias)` for each canonical keyword, as messages list them.
pub(super) fn listed(keywords: &[&str]) -> String {
    keywords
        .iter()
        .map(|k| match KEYWORDS.iter().find(|names| names[0] == *k) {
            Some(names) if names.len() > 1 => format!("{k} ({})", names[1..].join(", ")),
            _ => k.to_string(),
        })
        .chain(std::iter::once("end (fin)".to_string()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The blocks a scene file is made of, every one read.
pub const TOP_BLOCKS: &[&str] = &[
    "camera",
    "viewport",
    "raytracer",
    "primitive",
    "material",
    "texture_material",
    "ambient_light",
    "directional_light",
    "point_light",
    "model",
    "linear_aperture_light",
    "rectangular_aperture_light",
    "elliptical_aperture_light",
    "aperture_mask_light",
];

/// What a `geometry` wrapper holds: its transform's keywords, then [`GEOMETRIES`].
pub(super) const WRAPPER: &[&str] = &[
    "scale",
    "rotation",
    "translation",
    "sphere",
    "plane",
    "disk",
    "triangle",
    "tube",
    "cylinder",
    "cone",
    "cube",
    "torus",
    "geometry",
    "btriangle",
    "spherical_cap",
    "lens",
];

/// The geometry blocks of a primitive or a `geometry` wrapper.
pub(super) const GEOMETRIES: &[&str] = WRAPPER.split_at(3).1;

pub(super) const CAMERA: &[&str] = &[
    "position",
    "look_at",
    "up",
    "angle",
    "near_clipping_plane",
    "far_clipping_plane",
];
pub(super) const VIEWPORT: &[&str] = &["width", "height", "image_file_name"];
pub(super) const RAYTRACER: &[&str] = &[
    "task",
    "sampling",
    "recursive_level",
    "reflexion_algorithm",
    "pixel_coordinate",
    "space",
    "color_normalization",
];
pub(super) const MATERIAL: &[&str] = &[
    "name",
    "color",
    "ka",
    "kd",
    "ks",
    "kr",
    "kt",
    "shininess",
    "plasticity",
    "refractive_index",
];
/// A texture material's keywords: a material's and its three images.
pub(super) const TEXTURE_MATERIAL: &[&str] = &[
    "name",
    "color",
    "ka",
    "kd",
    "ks",
    "kr",
    "kt",
    "shininess",
    "plasticity",
    "refractive_index",
    "texture_ka",
    "texture_kd",
    "texture_ks",
];
pub(super) const MODEL: &[&str] = &["file", "scale", "rotation", "translation", "uv_format"];
pub(super) const AMBIENT: &[&str] = &["color"];
pub(super) const DIRECTIONAL: &[&str] = &["color", "orientation"];
pub(super) const POINT: &[&str] = &[
    "color",
    "position",
    "amplification",
    "constant_attenuator",
    "linear_attenuator",
    "quadratic_attenuator",
];
/// An interference light's keywords (`SAbstractInterferenceLight` and its attenuated-light
/// base): the slit's two ends are its `position` (or `point`) lines.
pub(super) const LINEAR_APERTURE: &[&str] = &[
    "color",
    "position",
    "point",
    "amplification",
    "constant_attenuator",
    "linear_attenuator",
    "quadratic_attenuator",
    "wave_length",
    "period_iteration",
    "nb_oscillator",
];
/// A planar aperture's keywords (`SAbstractPlanarApertureLight`); a mask light's add `mask`.
pub(super) const PLANAR_APERTURE: &[&str] = &[
    "color",
    "position",
    "amplification",
    "constant_attenuator",
    "linear_attenuator",
    "quadratic_attenuator",
    "wave_length",
    "period_iteration",
    "nb_oscillator",
    "front",
    "up",
    "width",
    "height",
];
pub(super) const APERTURE_MASK: &[&str] = &[
    "color",
    "position",
    "amplification",
    "constant_attenuator",
    "linear_attenuator",
    "quadratic_attenuator",
    "wave_length",
    "period_iteration",
    "nb_oscillator",
    "front",
    "up",
    "width",
    "height",
    "mask",
];

/// `reflexion_algorithm`'s values, in SIMRenderer's order (the index is the number).
pub const REFLEXION_ALGORITHMS: [&str; 8] = [
    "no_light",
    "ambient",
    "diffuse",
    "phong_specular",
    "blinn_specular",
    "no_specular",
    "phong",
    "blinn",
];
/// A model's `uv_format` values, in SIMRenderer's order (`STexture.UV_FORMAT`).
pub const UV_FORMATS: [&str; 3] = ["default", "origin_uv_top_left", "origin_uv_bottom_left"];

/// `pixel_coordinate`'s values.
pub const PIXEL_COORDINATES: [&str; 6] = [
    "top_left",
    "top_right",
    "bottom_left",
    "bottom_right",
    "center",
    "random",
];
pub(super) const SPACES: [&str; 3] = ["linear", "voxel", "multi_voxel"];
pub(super) const COLOR_NORMALIZATIONS: [&str; 2] = ["clamp_channel", "division_factor"];

/// The shading model of each `reflexion_algorithm`, by its number.
pub fn shading_of(algorithm: usize) -> Option<ShadingModel> {
    let m = |ambient, diffuse, specular| {
        Some(ShadingModel {
            ambient,
            diffuse,
            specular,
            no_light: false,
        })
    };
    match algorithm {
        0 => Some(ShadingModel::NO_LIGHT),
        1 => m(true, false, Specular::None),
        2 => m(false, true, Specular::None),
        3 => m(false, false, Specular::Phong),
        4 => m(false, false, Specular::Blinn),
        5 => m(true, true, Specular::None),
        6 => m(true, true, Specular::Phong),
        7 => m(true, true, Specular::Blinn),
        _ => None,
    }
}

/// SIMRenderer's material for a name no material has: ambient 0.2, diffuse 0.6, specular
/// 0.7 grey, shininess 20. As a lumiere material: white, `k_a` 0.2, `k_d` 0.6, `k_s` 0.7;
/// with a white colour the metal factor changes nothing, and `m = 0` is given so that no
/// convention changes it either.
pub fn grey_default() -> Material {
    Material {
        kd: 0.6,
        ks: 0.7,
        ..Material::default()
    }
}

/// The seed of a file that gives none (lumiere's default, as in TOML files).
pub const DEFAULT_SEED: u64 = 42;
