//! Writing a [`Scene`] as a SIMRenderer scene file: every setting, light, material and
//! object it can say, in the blocks and keywords [`super::read`] reads back to the same
//! scene; everything it cannot say refused by name ([`Refused`]). A scene under conventions
//! SIMRenderer does not have gets a comment at the top listing them, and how lumiere
//! renders the file as the original.

use super::exact::{self, unit_once, unit_twice};
use super::writer::{Format, Writer};
use super::{DEFAULT_SEED, Refused, Written, object_label};
use crate::conventions::{Conventions, SamplePosition};
use crate::decimal::number;
use crate::film::Normalization;
use crate::interference::{Aperture, ApertureLight};
use crate::light::Light;
use crate::material::Material;
use crate::scene::rules::Syntax;
use crate::scene::{Scene, ShadingModel, Specular};
use crate::shape::{Cuboid, NormalInterpolation, Shape};
use glam::DVec3;

/// The file's number for `x` (`Infinity` for an infinite one).
fn num(x: f64) -> String {
    number(x, "Infinity")
}

fn vec3(v: DVec3) -> String {
    Syntax::SimRenderer.vector(&v.to_array())
}

/// `reflexion_algorithm`'s name for a shading model, if SIMRenderer has it.
fn algorithm(model: &ShadingModel) -> Option<&'static str> {
    if model.no_light {
        return Some("no_light");
    }
    Some(match (model.ambient, model.diffuse, model.specular) {
        (true, false, Specular::None) => "ambient",
        (false, true, Specular::None) => "diffuse",
        (false, false, Specular::Phong) => "phong_specular",
        (false, false, Specular::Blinn) => "blinn_specular",
        (true, true, Specular::None) => "no_specular",
        (true, true, Specular::Phong) => "phong",
        (true, true, Specular::Blinn) => "blinn",
        _ => return None,
    })
}

/// The switches SIMRenderer has no keyword for, where `c` differs from SIMRenderer's, as
/// `(key, value here, SIMRenderer's value)`.
pub fn foreign_conventions(c: &Conventions) -> Vec<(&'static str, String, String)> {
    let theirs = Conventions::SIMRENDERER.describe();
    c.describe()
        .into_iter()
        .zip(theirs)
        .filter(|((key, _), _)| !matches!(*key, "sample_position" | "near" | "far"))
        .filter(|((_, mine), (_, theirs))| mine != theirs)
        .map(|((key, mine), (_, theirs))| (key, mine, theirs))
        .collect()
}

/// Why a material name cannot be written (SIMRenderer takes the rest of the line, leading
/// blanks removed, as the name).
fn bad_name(name: &str) -> Option<&'static str> {
    if name.is_empty() {
        Some("an empty name")
    } else if name.starts_with(char::is_whitespace) {
        Some("a name that starts with a blank (SIMRenderer removes it)")
    } else if name.contains(['\n', '\r']) {
        Some("a name with a line break")
    } else {
        None
    }
}

/// The scene as a SIMRenderer file; `source` names where it came from (in the header
/// comment) and `image` is the viewport's `image_file_name`.
pub fn to_simrenderer(scene: &Scene, source: &str, image: &str) -> Result<Written, Refused> {
    let mut w = Writer::<SimRenderer>::new();
    w.header(scene, source);
    w.settings(scene, image);
    w.lights(scene);
    w.materials(scene);
    w.objects(scene);
    w.finish()
}

/// SIMRenderer's scene files.
struct SimRenderer;

impl Format for SimRenderer {
    const NAME: &'static str = "SIMRenderer";
    fn vec3(v: DVec3) -> String {
        vec3(v)
    }
}

impl Writer<SimRenderer> {
    fn header(&mut self, scene: &Scene, source: &str) {
        self.line(format!("# SIMRenderer scene written by lumiere from {source}."));
        let foreign = foreign_conventions(&scene.settings.conventions);
        if foreign.is_empty() {
            self.line("");
            return;
        }
        self.line("#");
        self.line("# That scene follows conventions SIMRenderer does not have; SIMRenderer, and lumiere");
        self.line("# reading this file, render it with SIMRenderer's:");
        for (key, mine, theirs) in &foreign {
            self.line(format!("#   {key}: {mine} in that scene, {theirs} in SIMRenderer"));
        }
        let mut chapter = Conventions::CHAPTER;
        let c = &scene.settings.conventions;
        (chapter.sample_position, chapter.near, chapter.far) = (c.sample_position, c.near, c.far);
        let options = if chapter == *c {
            "--conventions chapter".to_string()
        } else {
            foreign
                .iter()
                .map(|(key, mine, _)| format!("--convention {key}={mine}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        self.line(format!("# lumiere renders it as that scene with the options {options}"));
        self.line("");
    }

    fn settings(&mut self, scene: &Scene, image: &str) {
        let s = &scene.settings;
        let c = &scene.camera;
        let conv = &s.conventions;
        if !(10.0..=170.0).contains(&c.vfov_deg) {
            self.refused.push(format!(
                "camera.vfov {}: SIMRenderer's angle is in [10, 170] degrees",
                c.vfov_deg
            ));
        }
        if conv.far < conv.near {
            self.refused.push(format!(
                "conventions far {} below near {}: SIMRenderer's far_clipping_plane is at least its near_clipping_plane",
                conv.far, conv.near
            ));
        }
        self.line("camera");
        self.line(format!("position            {}", vec3(c.position)));
        self.line(format!("look_at             {}", vec3(c.look_at)));
        let up = self.direction(|| "camera.up".into(), c.up, unit_once);
        self.line(format!("up                  {up}"));
        self.line(format!("angle               {}", num(c.vfov_deg)));
        self.line(format!("near_clipping_plane {}", num(conv.near)));
        self.line(format!("far_clipping_plane  {}", num(conv.far)));
        self.line("end");
        self.line("");
        self.line("viewport");
        self.line(format!("width           {}", s.width));
        self.line(format!("height          {}", s.height));
        self.line(format!("image_file_name {image}"));
        self.line("end");
        self.line("");
        let pixel = match conv.sample_position {
            SamplePosition::Corner => "top_left",
            SamplePosition::TopRight => "top_right",
            SamplePosition::BottomLeft => "bottom_left",
            SamplePosition::BottomRight => "bottom_right",
            SamplePosition::Center => "center",
            SamplePosition::Jittered => "random",
            SamplePosition::Regular => {
                self.refused.push(
                    "conventions sample_position regular: SIMRenderer places every sample at the pixel's top_left corner, its center, or at random (with 1 sample, center is the same ray)".to_string(),
                );
                "center"
            }
        };
        let shading = algorithm(&s.shading).unwrap_or_else(|| {
            self.refused.push(format!(
                "render shading (ambient {}, diffuse {}, specular {:?}): SIMRenderer's reflexion_algorithm keeps one term, ambient and diffuse (no_specular), or all three",
                s.shading.ambient, s.shading.diffuse, s.shading.specular
            ));
            "blinn"
        });
        if !s.shadows {
            self.refused
                .push("render shadows = false: SIMRenderer always casts shadow rays".to_string());
        }
        if let Some(c) = &s.caustics {
            self.refused.push(format!(
                "caustics photons = {}: SIMRenderer has no photon pass",
                c.photons
            ));
        }
        if s.background != DVec3::ZERO {
            self.refused.push(format!(
                "render background {:?}: SIMRenderer's background is black",
                s.background.to_array()
            ));
        }
        self.line("raytracer");
        self.line(format!("sampling            {}", s.samples_per_pixel));
        self.line(format!("recursive_level     {}", s.depth));
        self.line(format!("reflexion_algorithm {shading}"));
        self.line(format!("pixel_coordinate    {pixel}"));
        if s.color_normalization == Normalization::DivisionFactor {
            self.line("color_normalization division_factor");
        }
        // What lumiere needs and SIMRenderer does not read, as comments it skips.
        if s.seed != DEFAULT_SEED {
            self.line(format!("# lumiere: seed {}", s.seed));
        }
        if s.adaptive_threshold != 0.0 {
            self.line(format!("# lumiere: adaptive_threshold {}", num(s.adaptive_threshold)));
        }
        self.line("end");
        self.line("");
    }

    fn lights(&mut self, scene: &Scene) {
        for (i, light) in scene.lights.iter().enumerate() {
            match light {
                Light::Ambient { color } => {
                    self.line("ambient_light");
                    self.line(format!("color {}", vec3(*color)));
                }
                Light::Directional { direction, color } => {
                    let d = self.direction(|| format!("lights[{i}] (directional)"), *direction, unit_once);
                    self.line("directional_light");
                    self.line(format!("color       {}", vec3(*color)));
                    self.line(format!("orientation {d}"));
                }
                Light::Point(p) => {
                    self.line("point_light");
                    self.line(format!("color                {}", vec3(p.color)));
                    self.line(format!("position             {}", vec3(p.position)));
                    self.line(format!("constant_attenuator  {}", num(p.attenuation.constant)));
                    self.line(format!("linear_attenuator    {}", num(p.attenuation.linear)));
                    self.line(format!("quadratic_attenuator {}", num(p.attenuation.quadratic)));
                }
                Light::Spot(_) => {
                    self.refused
                        .push(format!("lights[{i}] (spot): SIMRenderer has no spot light"));
                    continue;
                }
                Light::Area(_) => {
                    self.refused
                        .push(format!("lights[{i}] (area): SIMRenderer has no area light"));
                    continue;
                }
                Light::Aperture(a) => self.aperture_light(i, a),
            }
            self.line("end");
            self.line("");
        }
    }

    /// An interference light's block, its keywords in SIMRenderer's order (the slit's two
    /// ends as its two `position` lines).
    fn aperture_light(&mut self, i: usize, a: &ApertureLight) {
        let block = match &a.aperture {
            Aperture::Linear { .. } => "linear_aperture_light",
            Aperture::Rectangular(_) => "rectangular_aperture_light",
            Aperture::Elliptical(_) => "elliptical_aperture_light",
            Aperture::Mask { .. } => "aperture_mask_light",
        };
        self.line(block);
        self.line(format!("amplification        {}", num(a.amplification)));
        self.line(format!("constant_attenuator  {}", num(a.attenuation.constant)));
        self.line(format!("linear_attenuator    {}", num(a.attenuation.linear)));
        self.line(format!("quadratic_attenuator {}", num(a.attenuation.quadratic)));
        self.line(format!("wave_length          {} nm", num(a.wavelength_nm)));
        self.line(format!("period_iteration     {}", a.period_iteration));
        self.line(format!("nb_oscillator        {}", a.oscillator_count));
        match &a.aperture {
            Aperture::Linear { start, end } => {
                self.line(format!("position             {}", vec3(*start)));
                self.line(format!("position             {}", vec3(*end)));
            }
            Aperture::Rectangular(p) | Aperture::Elliptical(p) | Aperture::Mask { planar: p, .. } => {
                let front = self.direction(|| format!("lights[{i}] ({block}) front"), p.front, unit_once);
                let up = self.direction(|| format!("lights[{i}] ({block}) up"), p.up, unit_once);
                self.line(format!("position             {}", vec3(p.center)));
                self.line(format!("front                {front}"));
                self.line(format!("up                   {up}"));
                self.line(format!("height               {}", num(p.height)));
                self.line(format!("width                {}", num(p.width)));
            }
        }
        if let Aperture::Mask { mask: Some(m), .. } = &a.aperture {
            self.line(format!("mask                 {}", m.file));
            self.notes.push(format!(
                "lights[{i}] ({block}): its mask {:?} is named as the source names it, relative to the source's folder",
                m.file
            ));
        }
    }

    fn materials(&mut self, scene: &Scene) {
        let highlight = scene.settings.conventions.default_highlight.metal();
        for (i, (name, m)) in scene.material_names.iter().zip(&scene.materials).enumerate() {
            let given = scene.metal_given[i];
            // The built-in default, when no object uses it, is the reader's own.
            let builtin = Material {
                metal: highlight,
                ..Material::default()
            };
            if i == 0 && !given && *m == builtin && scene.objects.iter().all(|o| o.material != 0) {
                continue;
            }
            if let Some(why) = bad_name(name) {
                self.refused
                    .push(format!("materials[{i}] {name:?}: SIMRenderer cannot read {why}"));
                continue;
            }
            if m.ambient_color().is_some() || m.specular_color().is_some() {
                self.refused.push(format!(
                    "materials[{i}] {name:?}: its own ambient_color or specular_color (SIMRenderer gives terms their own colours only in a model's .mtl materials)"
                ));
            }
            if m.shininess > 200.0 {
                self.refused.push(format!(
                    "materials[{i}] {name:?}: shininess {} (SIMRenderer's is in [0, 200])",
                    m.shininess
                ));
            }
            self.line(if m.images().is_some() {
                "texture_material"
            } else {
                "material"
            });
            self.line(format!("name      {name}"));
            self.line(format!("color     {}", vec3(m.color)));
            self.line(format!("ka        {}", num(m.ka)));
            self.line(format!("kd        {}", num(m.kd)));
            self.line(format!("ks        {}", num(m.ks)));
            self.line(format!("shininess {}", num(m.shininess)));
            if given {
                let (p, exact) = exact::plasticity(m.metal);
                if !exact {
                    self.notes.push(format!(
                        "materials[{i}] {name:?}: m = {} is written as p = 1 - m = {}, which reads back within rounding, not to the bit",
                        m.metal,
                        num(p)
                    ));
                }
                self.line(format!("p         {}", num(p)));
            }
            self.line(format!("kr        {}", num(m.kr)));
            self.line(format!("kt        {}", num(m.kt)));
            self.line(format!("n         {}", num(m.ior)));
            if let Some(maps) = m.images() {
                if maps.uv_format != crate::texture::UvFormat::OriginUvTopLeft {
                    self.refused.push(format!(
                        "materials[{i}] {name:?}: uv_format {} (SIMRenderer's texture materials read their images from the top-left corner; only a model sets another format)",
                        maps.uv_format.name()
                    ));
                }
                for (key, t) in [
                    ("texture_ka", &maps.ambient),
                    ("texture_kd", &maps.diffuse),
                    ("texture_ks", &maps.specular),
                ] {
                    self.line(format!("{key} {}", t.as_ref().map_or("none", |t| t.file.as_str())));
                }
                self.notes.push(format!(
                    "materials[{i}] {name:?}: its images are named as the source names them: keep them in the same place beside the written file"
                ));
            }
            self.line("end");
            self.line("");
        }
    }

    fn objects(&mut self, scene: &Scene) {
        for (i, o) in scene.objects.iter().enumerate() {
            let label = object_label(scene, i);
            let mut block = String::new();
            if !self.shape(&label, &o.shape, &mut block) {
                continue;
            }
            self.line("primitive");
            let name = scene.name_of(o);
            if name != format!("{}#{i}", o.shape.kind()) {
                let quoted = serde_json::to_string(&name).unwrap_or_default();
                self.line(format!("# lumiere: name {quoted}"));
            }
            self.line(format!("material_name {}", scene.material_names[o.material()]));
            self.out.push_str(&block);
            self.line("end");
            self.line("");
        }
    }

    /// The geometry block of `shape` into `out`; false when SIMRenderer cannot say it.
    fn shape(&mut self, label: &str, shape: &Shape, out: &mut String) -> bool {
        let mut put = |s: String| {
            out.push_str(&s);
            out.push('\n');
        };
        match shape {
            Shape::Plane(p) => {
                let n = self.direction(|| label.to_string(), p.normal, unit_twice);
                put(format!("plane\nposition {}\nnormal   {n}\nend", vec3(p.point)));
            }
            Shape::Disk(d) => {
                let n = self.direction(|| label.to_string(), d.normal, unit_twice);
                put(format!(
                    "disk\nposition {}\nnormal   {n}\nray      {}\nend",
                    vec3(d.center),
                    num(d.radius)
                ));
            }
            Shape::Sphere(s) => put(format!(
                "sphere\nposition {}\nray      {}\nend",
                vec3(s.center),
                num(s.radius)
            )),
            Shape::Cuboid(b) => self.cuboid(label, b, &mut put),
            Shape::SphericalCap(c) => {
                let n = self.direction(|| label.to_string(), c.normal, unit_twice);
                put(format!(
                    "spherical_cap\nposition  {}\nnormal    {n}\nray       {}\ncurvature {}\nend",
                    vec3(c.center),
                    num(c.radius),
                    num(c.curvature)
                ));
            }
            Shape::Lens(l) => {
                if l.thickness == 0.0 {
                    self.refused.push(format!(
                        "{label}: a lens without an edge (SIMRenderer's lens runs between two different points)"
                    ));
                    return false;
                }
                let (end, exact) = exact::far_end(l.base, l.axis, l.thickness);
                if !exact {
                    self.notes
                        .push(format!("{label}: its axis reads back within rounding, not to the bit"));
                }
                put(format!(
                    "lens\npoint     {}\npoint     {}\nray       {}\ncurvature {}\ncurvature {}\nend",
                    vec3(l.base),
                    vec3(end),
                    num(l.radius),
                    num(l.curvature1),
                    num(l.curvature2)
                ));
            }
            Shape::Cylinder(c) => {
                let (end, exact) = exact::far_end(c.base, c.axis, c.height);
                if !exact {
                    self.notes
                        .push(format!("{label}: its axis reads back within rounding, not to the bit"));
                }
                let kind = if c.open { "tube" } else { "cylinder" };
                put(format!(
                    "{kind}\npoint {}\npoint {}\nray   {}\nend",
                    vec3(c.base),
                    vec3(end),
                    num(c.radius)
                ));
            }
            Shape::Cone(c) => {
                let (apex, exact) = exact::far_end(c.base, c.axis, c.height);
                if !exact {
                    self.notes
                        .push(format!("{label}: its axis reads back within rounding, not to the bit"));
                }
                put(format!(
                    "cone\npoint {}\npoint {}\nray   {}\nend",
                    vec3(c.base),
                    vec3(apex),
                    num(c.radius)
                ));
            }
            Shape::Torus(t) => {
                let n = self.direction(|| label.to_string(), t.axis, unit_twice);
                put(format!(
                    "torus\nposition     {}\nnormal       {n}\nmajor_radius {}\nminor_radius {}\nend",
                    vec3(t.center),
                    num(t.major),
                    num(t.minor)
                ));
            }
            Shape::Triangle(t) => {
                let [a, b, c] = t.points();
                put(format!(
                    "triangle\npoint {}\npoint {}\npoint {}\nend",
                    vec3(a),
                    vec3(b),
                    vec3(c)
                ));
            }
            Shape::SmoothTriangle(t) => {
                if t.interpolation != NormalInterpolation::Linear {
                    self.refused.push(format!(
                        "{label}: SIMRenderer's btriangle keeps the interpolated normal's length (normal_interpolation = \"linear\"); this triangle's is \"{}\"",
                        t.interpolation.name()
                    ));
                    return false;
                }
                let [a, b, c] = t.triangle.points();
                let mut lines = vec![
                    "btriangle".to_string(),
                    format!("point  {}", vec3(a)),
                    format!("point  {}", vec3(b)),
                    format!("point  {}", vec3(c)),
                ];
                for (i, n) in t.normals.iter().enumerate() {
                    let n = self.direction(|| format!("{label}: normal {i}"), *n, unit_once);
                    lines.push(format!("normal {n}"));
                }
                for [u, v] in t.uvs {
                    lines.push(format!("uv     {} {}", num(u), num(v)));
                }
                lines.push("end".to_string());
                put(lines.join("\n"));
            }
            Shape::Rectangle(_) => {
                self.refused.push(format!(
                    "{label}: SIMRenderer has no rectangle (a mirror pair is two rectangles)"
                ));
                return false;
            }
            Shape::Transformed(t) => {
                let Some(p) = exact::parts(&t.transform) else {
                    self.refused.push(format!(
                        "{label}: its transform shears (a general matrix); SIMRenderer's geometry block scales, rotates and translates"
                    ));
                    return false;
                };
                if !p.exact {
                    self.notes.push(format!(
                        "{label}: its transform reads back within rounding, not to the bit"
                    ));
                }
                let mut inner = String::new();
                if !self.shape(label, &t.shape, &mut inner) {
                    return false;
                }
                put(format!(
                    "geometry\nscale       {}\nrotation    {}\ntranslation {}\n{inner}end",
                    vec3(p.scale),
                    vec3(p.rotation),
                    vec3(p.translation)
                ));
            }
        }
        true
    }

    /// A box: SIMRenderer's `cube` when it is an axis-aligned cube, else a unit cube in a
    /// `geometry` block that scales it to the box's sides, rotates and moves it (the same
    /// box, which lumiere reads back as a transformed shape).
    fn cuboid(&mut self, label: &str, b: &Cuboid, put: &mut impl FnMut(String)) {
        let size = b.half_size * 2.0;
        if size.x == size.y && size.y == size.z && Cuboid::new(b.center, size, DVec3::ZERO) == *b {
            put(format!(
                "cube\nposition {}\nsize     {}\nend",
                vec3(b.center),
                num(size.x)
            ));
            return;
        }
        let (rotation, exact) = exact::box_rotation(b);
        self.notes.push(format!(
            "{label}: SIMRenderer's cube is an axis-aligned cube; this box is written as a unit cube scaled, rotated{} and moved in a geometry block, the same box, which lumiere reads back as a transformed shape",
            if exact { "" } else { " (within rounding)" }
        ));
        put(format!(
            "# {label}: a unit cube scaled to the box's sides, rotated and moved\ngeometry\nscale       {}\nrotation    {}\ntranslation {}\ncube\nposition 0 0 0\nsize     1\nend\nend",
            vec3(size),
            vec3(rotation),
            vec3(b.center)
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_reflexion_algorithm_has_its_model() {
        for i in 0..8 {
            let m = super::super::shading_of(i).unwrap();
            assert_eq!(algorithm(&m), Some(super::super::REFLEXION_ALGORITHMS[i]));
        }
        assert_eq!(super::super::shading_of(0), Some(ShadingModel::NO_LIGHT));
        assert_eq!(super::super::shading_of(8), None);
        let model = |ambient, specular| ShadingModel {
            ambient,
            diffuse: false,
            specular,
            no_light: false,
        };
        assert_eq!(algorithm(&model(true, Specular::Blinn)), None);
        assert_eq!(algorithm(&model(false, Specular::None)), None);
    }

    #[test]
    fn the_chapter_conventions_simrenderer_lacks() {
        let keys: Vec<&str> = foreign_conventions(&Conventions::CHAPTER)
            .into_iter()
            .map(|(k, _, _)| k)
            .collect();
        assert_eq!(
            keys,
            [
                "ray_origin",
                "shadow_filter",
                "transmission",
                "refracting",
                "total_internal_reflection",
                "default_highlight"
            ]
        );
        assert!(foreign_conventions(&Conventions::SIMRENDERER).is_empty());
    }
}
