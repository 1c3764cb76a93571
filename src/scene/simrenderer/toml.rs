//! Writing a [`Scene`] in lumiere's TOML scene format (scenes/README.md): every table the
//! TOML reader reads back to the same scene. Objects are written one `[[shapes]]` entry
//! each (a model's or a mesh's triangles one by one); the conventions as the nearer preset
//! and the switches that differ from it. A transformed shape whose shape is itself
//! transformed (SIMRenderer's nested `geometry` blocks) is refused: a TOML shape has one
//! transform.

use super::exact::{self, unit_once, unit_twice};
use super::writer::{Format, Writer};
use super::{Refused, Written, object_label};
use crate::area_light::AreaShape;
use crate::decimal::number;
use crate::film::Normalization;
use crate::interference::Aperture;
use crate::light::{Attenuation, Light};
use crate::material::Material;
use crate::scene::{Scene, Specular};
use crate::shape::{NormalInterpolation, Shape, SmoothTriangle, Transform, Triangle};
use glam::DVec3;

fn num(x: f64) -> String {
    number(x, "inf")
}

fn vec3(v: DVec3) -> String {
    format!("[{}, {}, {}]", num(v.x), num(v.y), num(v.z))
}

/// A triangle's `p0`, `p1` and `p2` lines.
fn triangle_points(t: &Triangle) -> Vec<String> {
    let [a, b, c] = t.points();
    vec![
        format!("p0 = {}", vec3(a)),
        format!("p1 = {}", vec3(b)),
        format!("p2 = {}", vec3(c)),
    ]
}

/// A TOML basic string.
fn quoted(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 || c == '\u{7f}' => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A key: bare when TOML allows it, else quoted.
fn key(s: &str) -> String {
    if !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
        s.to_string()
    } else {
        quoted(s)
    }
}

fn attenuation(a: &Attenuation) -> String {
    format!(
        "{{ constant = {}, linear = {}, quadratic = {} }}",
        num(a.constant),
        num(a.linear),
        num(a.quadratic)
    )
}

/// The name of a serialised unit variant (`"fibonacci"`, `"per_sample"`).
fn variant(v: &impl serde::Serialize) -> String {
    match serde_json::to_value(v) {
        Ok(serde_json::Value::String(s)) => s,
        other => format!("{other:?}"),
    }
}

/// The scene as a TOML scene file; `source` names where it came from (in the header
/// comment).
pub fn to_toml(scene: &Scene, source: &str) -> Result<Written, Refused> {
    let mut w = Writer::<Toml>::new();
    w.line(format!("# Scene written by lumiere from {source}."));
    w.line("");
    w.settings(scene);
    w.materials(scene);
    w.objects(scene);
    w.lights(scene);
    w.finish()
}

/// lumiere's TOML scene files.
struct Toml;

impl Format for Toml {
    const NAME: &'static str = "the TOML format";
    fn vec3(v: DVec3) -> String {
        vec3(v)
    }
}

impl Writer<Toml> {
    fn settings(&mut self, scene: &Scene) {
        let s = &scene.settings;
        let c = &scene.camera;
        self.line("[image]");
        self.line(format!("width = {}", s.width));
        self.line(format!("height = {}", s.height));
        self.line(format!("samples_per_pixel = {}", s.samples_per_pixel));
        self.line(format!("seed = {}", s.seed));
        self.line("");
        self.line("[camera]");
        self.line(format!("position = {}", vec3(c.position)));
        self.line(format!("look_at = {}", vec3(c.look_at)));
        let up = self.direction(|| "camera.up".into(), c.up, unit_once);
        self.line(format!("up = {up}"));
        self.line(format!("vfov = {}", num(c.vfov_deg)));
        self.line("");
        self.line("[render]");
        self.line(format!("depth = {}", s.depth));
        self.line(format!("ambient = {}", s.shading.ambient));
        self.line(format!("diffuse = {}", s.shading.diffuse));
        let specular = match s.shading.specular {
            Specular::Blinn => "blinn",
            Specular::Phong => "phong",
            Specular::None => "none",
        };
        self.line(format!("specular = \"{specular}\""));
        if s.shading.no_light {
            self.line("no_light = true");
        }
        self.line(format!("shadows = {}", s.shadows));
        self.line(format!("background = {}", vec3(s.background)));
        if s.color_normalization == Normalization::DivisionFactor {
            self.line("color_normalization = \"division_factor\"");
        }
        self.line(format!("adaptive_threshold = {}", num(s.adaptive_threshold)));
        self.line("");
        // The nearer preset, then the switches that differ from it.
        let (preset, switches) = s.conventions.nearer_preset();
        self.line("[conventions]");
        self.line(format!("preset = \"{preset}\""));
        for (k, v) in switches {
            match k {
                "near" | "far" => self.line(format!("{k} = {v}")),
                _ => self.line(format!("{k} = \"{v}\"")),
            }
        }
        self.line("");
    }

    fn materials(&mut self, scene: &Scene) {
        let highlight = scene.settings.conventions.default_highlight.metal();
        for (i, (name, m)) in scene.material_names.iter().zip(&scene.materials).enumerate() {
            let builtin = Material {
                metal: highlight,
                ..Material::default()
            };
            // The built-in default is the reader's own.
            if i == 0 && !scene.metal_given[0] && *m == builtin {
                continue;
            }
            self.line(format!("[materials.{}]", key(name)));
            self.line(format!("color = {}", vec3(m.color)));
            self.line(format!("ka = {}", num(m.ka)));
            self.line(format!("kd = {}", num(m.kd)));
            self.line(format!("ks = {}", num(m.ks)));
            self.line(format!("shininess = {}", num(m.shininess)));
            if scene.metal_given[i] {
                self.line(format!("m = {}", num(m.metal)));
            }
            self.line(format!("kr = {}", num(m.kr)));
            self.line(format!("kt = {}", num(m.kt)));
            self.line(format!("n = {}", num(m.ior)));
            for (key, c) in [
                ("ambient_color", m.ambient_color()),
                ("specular_color", m.specular_color()),
            ] {
                if let Some(c) = c {
                    self.line(format!("{key} = {}", vec3(c)));
                }
            }
            if let Some(maps) = m.images() {
                for (key, t) in [
                    ("texture_ka", &maps.ambient),
                    ("texture_kd", &maps.diffuse),
                    ("texture_ks", &maps.specular),
                ] {
                    if let Some(t) = t {
                        self.line(format!("{key} = {}", quoted(&t.file)));
                    }
                }
                if maps.uv_format != crate::texture::UvFormat::OriginUvTopLeft {
                    self.line(format!("uv_format = \"{}\"", maps.uv_format.name()));
                }
                self.notes.push(format!(
                    "materials[{i}] {name:?}: its images are named as the source names them: keep them in the same place beside the written file"
                ));
            }
            self.line("");
        }
    }

    fn objects(&mut self, scene: &Scene) {
        for (i, o) in scene.objects.iter().enumerate() {
            let label = object_label(scene, i);
            let (inner, transform) = match &o.shape {
                Shape::Transformed(t) => (&t.shape, Some(&t.transform)),
                shape => (shape, None),
            };
            if let Shape::Transformed(_) = inner {
                self.refused.push(format!(
                    "{label}: a transformed shape in a transform (nested geometry blocks); a TOML shape has one transform"
                ));
                continue;
            }
            let fields = self.shape(&label, inner);
            self.line("[[shapes]]");
            self.line(format!("type = \"{}\"", inner.kind()));
            let name = scene.name_of(o);
            if name != format!("{}#{i}", o.shape.kind()) {
                self.line(format!("name = {}", quoted(&name)));
            }
            for f in fields {
                self.line(f);
            }
            if o.material != 0 {
                self.line(format!("material = {}", quoted(&scene.material_names[o.material()])));
            }
            if let Some(t) = transform {
                let t = self.transform(&label, t);
                self.line(format!("transform = {t}"));
            }
            self.line("");
        }
    }

    /// The `key = value` lines of a shape's table (without its transform).
    fn shape(&mut self, label: &str, shape: &Shape) -> Vec<String> {
        let what = || label.to_string();
        match shape {
            Shape::Plane(p) => vec![
                format!("point = {}", vec3(p.point)),
                format!("normal = {}", self.direction(what, p.normal, unit_twice)),
            ],
            Shape::Rectangle(r) => vec![
                format!("corner = {}", vec3(r.corner)),
                format!("edge1 = {}", vec3(r.edge1)),
                format!("edge2 = {}", vec3(r.edge2)),
            ],
            Shape::Disk(d) => vec![
                format!("center = {}", vec3(d.center)),
                format!("normal = {}", self.direction(what, d.normal, unit_twice)),
                format!("radius = {}", num(d.radius)),
            ],
            Shape::Sphere(s) => vec![
                format!("center = {}", vec3(s.center)),
                format!("radius = {}", num(s.radius)),
            ],
            Shape::Cuboid(b) => {
                let (rotation, exact) = exact::box_rotation(b);
                if !exact {
                    self.notes.push(format!(
                        "{label}: its rotation reads back within rounding, not to the bit"
                    ));
                }
                let mut lines = vec![
                    format!("center = {}", vec3(b.center)),
                    format!("size = {}", vec3(b.half_size * 2.0)),
                ];
                if rotation != DVec3::ZERO {
                    lines.push(format!("rotation = {}", vec3(rotation)));
                }
                lines
            }
            Shape::Cylinder(c) if c.open => {
                let (end, exact) = exact::far_end(c.base, c.axis, c.height);
                if !exact {
                    self.notes
                        .push(format!("{label}: its axis reads back within rounding, not to the bit"));
                }
                vec![
                    format!("start = {}", vec3(c.base)),
                    format!("end = {}", vec3(end)),
                    format!("radius = {}", num(c.radius)),
                ]
            }
            Shape::Cylinder(c) => self.capped(label, c.base, c.axis, c.height, c.radius),
            Shape::Cone(c) => self.capped(label, c.base, c.axis, c.height, c.radius),
            Shape::Torus(t) => vec![
                format!("center = {}", vec3(t.center)),
                format!("axis = {}", self.direction(what, t.axis, unit_twice)),
                format!("major_radius = {}", num(t.major)),
                format!("minor_radius = {}", num(t.minor)),
            ],
            Shape::Triangle(t) => triangle_points(t),
            Shape::SmoothTriangle(t) => {
                let mut lines = triangle_points(&t.triangle);
                let normals: Vec<String> = (0..3)
                    .map(|i| self.direction(|| format!("{label}: normal {i}"), t.normals[i], unit_once))
                    .collect();
                lines.push(format!("normals = [{}]", normals.join(", ")));
                if t.uvs != SmoothTriangle::FLAT_UVS {
                    let uvs: Vec<String> = t
                        .uvs
                        .iter()
                        .map(|[u, v]| format!("[{}, {}]", num(*u), num(*v)))
                        .collect();
                    lines.push(format!("uvs = [{}]", uvs.join(", ")));
                }
                if t.interpolation != NormalInterpolation::default() {
                    lines.push(format!("normal_interpolation = \"{}\"", t.interpolation.name()));
                }
                lines
            }
            Shape::SphericalCap(c) => vec![
                format!("center = {}", vec3(c.center)),
                format!("normal = {}", self.direction(what, c.normal, unit_twice)),
                format!("radius = {}", num(c.radius)),
                format!("curvature = {}", num(c.curvature)),
            ],
            Shape::Lens(l) => vec![
                format!("base = {}", vec3(l.base)),
                format!("axis = {}", self.direction(what, l.axis, unit_twice)),
                format!("thickness = {}", num(l.thickness)),
                format!("radius = {}", num(l.radius)),
                format!("curvature1 = {}", num(l.curvature1)),
                format!("curvature2 = {}", num(l.curvature2)),
            ],
            // Refused by the caller.
            Shape::Transformed(_) => Vec::new(),
        }
    }

    fn capped(&mut self, label: &str, base: DVec3, axis: DVec3, height: f64, radius: f64) -> Vec<String> {
        vec![
            format!("base = {}", vec3(base)),
            format!("axis = {}", self.direction(|| label.to_string(), axis, unit_twice)),
            format!("height = {}", num(height)),
            format!("radius = {}", num(radius)),
        ]
    }

    /// An inline `transform` table: its scale, rotation and translation when they give it
    /// back to the bit, else its matrix when that does, else the nearer of the two.
    fn transform(&mut self, label: &str, t: &Transform) -> String {
        let parts = exact::parts(t);
        let inline = |p: &exact::Parts| {
            format!(
                "{{ scale = {}, rotation = {}, translation = {} }}",
                vec3(p.scale),
                vec3(p.rotation),
                vec3(p.translation)
            )
        };
        if let Some(p) = parts.filter(|p| p.exact) {
            return inline(&p);
        }
        let a = t.to_world.matrix3.transpose();
        let b = t.to_world.translation;
        let rows = [
            [a.x_axis.x, a.x_axis.y, a.x_axis.z, b.x],
            [a.y_axis.x, a.y_axis.y, a.y_axis.z, b.y],
            [a.z_axis.x, a.z_axis.y, a.z_axis.z, b.z],
        ];
        if Transform::from_rows(rows).as_ref() != Some(t) {
            self.notes.push(format!(
                "{label}: its transform reads back within rounding, not to the bit"
            ));
            if let Some(p) = parts {
                return inline(&p);
            }
        }
        let row = |r: [f64; 4]| format!("[{}, {}, {}, {}]", num(r[0]), num(r[1]), num(r[2]), num(r[3]));
        format!("{{ matrix = [{}, {}, {}] }}", row(rows[0]), row(rows[1]), row(rows[2]))
    }

    fn lights(&mut self, scene: &Scene) {
        for (i, light) in scene.lights.iter().enumerate() {
            self.line("[[lights]]");
            match light {
                Light::Ambient { color } => {
                    self.line("type = \"ambient\"");
                    self.line(format!("color = {}", vec3(*color)));
                }
                Light::Directional { direction, color } => {
                    let d = self.direction(|| format!("lights[{i}] (directional)"), *direction, unit_once);
                    self.line("type = \"directional\"");
                    self.line(format!("direction = {d}"));
                    self.line(format!("color = {}", vec3(*color)));
                }
                Light::Point(p) => {
                    self.line("type = \"point\"");
                    self.line(format!("position = {}", vec3(p.position)));
                    self.line(format!("color = {}", vec3(p.color)));
                    self.line(format!("attenuation = {}", attenuation(&p.attenuation)));
                }
                Light::Spot(s) => {
                    let d = self.direction(|| format!("lights[{i}] (spot)"), s.orientation, unit_twice);
                    self.line("type = \"spot\"");
                    self.line(format!("position = {}", vec3(s.position)));
                    self.line(format!("direction = {d}"));
                    self.line(format!("angle = {}", num(s.angle_deg)));
                    self.line(format!("c_min = {}", num(s.c_min)));
                    self.line(format!("c_max = {}", num(s.c_max)));
                    self.line(format!("color = {}", vec3(s.color)));
                    self.line(format!("attenuation = {}", attenuation(&s.attenuation)));
                }
                Light::Area(a) => {
                    self.line("type = \"area\"");
                    match &a.shape {
                        AreaShape::Sphere { center, radius } => {
                            self.line("shape = \"sphere\"");
                            self.line(format!("center = {}", vec3(*center)));
                            self.line(format!("radius = {}", num(*radius)));
                        }
                        AreaShape::Tube { start, end } => {
                            self.line("shape = \"tube\"");
                            self.line(format!("start = {}", vec3(*start)));
                            self.line(format!("end = {}", vec3(*end)));
                        }
                        AreaShape::Window { center, edge1, edge2 } => {
                            self.line("shape = \"window\"");
                            self.line(format!("center = {}", vec3(*center)));
                            self.line(format!("edge1 = {}", vec3(*edge1)));
                            self.line(format!("edge2 = {}", vec3(*edge2)));
                        }
                    }
                    self.line(format!("points = {}", a.count));
                    self.line(format!("placement = \"{}\"", variant(&a.placement)));
                    self.line(format!("mode = \"{}\"", variant(&a.mode)));
                    self.line(format!("color = {}", vec3(a.color)));
                    self.line(format!("attenuation = {}", attenuation(&a.attenuation)));
                }
                Light::Aperture(a) => {
                    let planar = match &a.aperture {
                        Aperture::Linear { start, end } => {
                            self.line("type = \"linear_aperture\"");
                            self.line(format!("start = {}", vec3(*start)));
                            self.line(format!("end = {}", vec3(*end)));
                            None
                        }
                        Aperture::Rectangular(p) => {
                            self.line("type = \"rectangular_aperture\"");
                            Some(p)
                        }
                        Aperture::Elliptical(p) => {
                            self.line("type = \"elliptical_aperture\"");
                            Some(p)
                        }
                        Aperture::Mask { planar, mask } => {
                            self.line("type = \"aperture_mask\"");
                            let file = mask.as_ref().map_or("none", |m| m.file.as_str());
                            self.line(format!("mask = {}", quoted(file)));
                            if mask.is_some() {
                                self.notes.push(format!(
                                    "lights[{i}] (aperture_mask): its mask {file:?} is named as the source names it, relative to the source's folder"
                                ));
                            }
                            Some(planar)
                        }
                    };
                    if let Some(p) = planar {
                        let front = self.direction(|| format!("lights[{i}] (front)"), p.front, unit_once);
                        let up = self.direction(|| format!("lights[{i}] (up)"), p.up, unit_once);
                        self.line(format!("center = {}", vec3(p.center)));
                        self.line(format!("front = {front}"));
                        self.line(format!("up = {up}"));
                        self.line(format!("width = {}", num(p.width)));
                        self.line(format!("height = {}", num(p.height)));
                    }
                    self.line(format!("wavelength = {}", num(a.wavelength_nm)));
                    self.line(format!("oscillators = {}", a.oscillator_count));
                    self.line(format!("period_iteration = {}", a.period_iteration));
                    self.line(format!("amplification = {}", num(a.amplification)));
                    self.line(format!("attenuation = {}", attenuation(&a.attenuation)));
                }
            }
            self.line("");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_and_strings() {
        assert_eq!(key("grey"), "grey");
        assert_eq!(key("dark-grey_2"), "dark-grey_2");
        assert_eq!(key("my grey"), "\"my grey\"");
        assert_eq!(quoted("a\"b\\c\n\u{7f}é"), "\"a\\\"b\\\\c\\u000A\\u007Fé\"");
        assert_eq!(key(""), "\"\"");
    }
}
