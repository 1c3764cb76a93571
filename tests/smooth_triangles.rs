//! Triangles with vertex normals: SIMRenderer's `btriangle` and the TOML triangle's
//! `normals`. The normal at a hit is the vertices' weighted by its barycentric
//! coordinates, kept as it is (SIMRenderer's `linear`) or made unit (`normalized`).
//!
//! The scenes: the triangle (-1, -1, 0), (2, -1, 0), (-1, 2, 0), whose centroid is the
//! origin, seen from (0, 0, 5) with the middle pixel's ray through the origin, lit straight
//! down by a white directional light, diffuse only (`k_d` 1, white). Its vertex normals
//! (0, 0, 1), (1, 0, 1) / sqrt 2 and (0, 1, 1) / sqrt 2 weigh 1/3 each at the centroid:
//! `N = (1 / (3 sqrt 2), 1 / (3 sqrt 2), (1 + sqrt 2) / 3)`, so the diffuse term `N . L` is
//! `(1 + sqrt 2) / 3 = 0.80474`, 205 in 8 bits, under `linear`; `|N| = 0.87104` and
//! `N . L / |N| = 0.92388`, 236, under `normalized`; the flat triangle's is 1, 255.

use crate::common::{lumiere, lumiere_ok, temp_dir, write_in};
use lumiere::scene;
use lumiere::shape::{NormalInterpolation, Shape};
use std::path::Path;

const SIMRENDERER: &str = "camera\nposition 0 0 5\nlook_at 0 0 0\nup 0 1 0\nend\n\
viewport\nwidth 21\nheight 21\nend\n\
raytracer\nreflexion_algorithm diffuse\nend\n\
directional_light\ncolor 1 1 1\norientation 0 0 -1\nend\n\
material\nname white\ncolor 1 1 1\nkd 1\nend\n\
primitive\nmaterial_name white\nbtriangle\n\
point -1 -1 0\npoint 2 -1 0\npoint -1 2 0\n\
normal 0 0 1\nnormal 1 0 1\nnormal 0 1 1\n\
uv 0 0\nuv 1 0\nuv 0 1\n\
end\nend\n";

/// The TOML scene, with the triangle's `extra` lines.
fn toml(extra: &str) -> String {
    format!(
        "[image]\nwidth = 21\nheight = 21\nsamples_per_pixel = 1\n\
         [camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nvfov = 60\n\
         [render]\nambient = false\nspecular = \"none\"\n\
         [conventions]\nsample_position = \"center\"\n\
         [materials.white]\ncolor = [1, 1, 1]\nkd = 1\n\
         [[shapes]]\ntype = \"triangle\"\np0 = [-1, -1, 0]\np1 = [2, -1, 0]\np2 = [-1, 2, 0]\nmaterial = \"white\"\n{extra}\
         [[lights]]\ntype = \"directional\"\ncolor = [1, 1, 1]\ndirection = [0, 0, -1]\n"
    )
}

const NORMALS: &str = "normals = [[0, 0, 1], [1, 0, 1], [0, 1, 1]]\n";

/// The middle pixel of `scene`'s render.
fn middle(dir: &Path, scene: &str) -> [u8; 3] {
    let png = dir.join(format!(
        "{}.png",
        Path::new(scene).file_stem().unwrap().to_str().unwrap()
    ));
    lumiere_ok(&["render", scene, "-o", png.to_str().unwrap(), "-q"]);
    image::open(&png).unwrap().to_rgb8().get_pixel(10, 10).0
}

#[test]
fn the_interpolated_normal_shades_the_centroid() {
    let dir = temp_dir("smooth-triangles");
    let flat = write_in(&dir, "flat.toml", &toml(""));
    let normalized = write_in(&dir, "normalized.toml", &toml(NORMALS));
    let linear = write_in(
        &dir,
        "linear.toml",
        &toml(&format!("{NORMALS}normal_interpolation = \"linear\"\n")),
    );
    let lab = write_in(&dir, "lab.txt", SIMRENDERER);
    assert_eq!(middle(&dir, &flat), [255; 3]);
    assert_eq!(middle(&dir, &normalized), [236; 3]);
    assert_eq!(middle(&dir, &linear), [205; 3]);
    // SIMRenderer's pixel corner, at an odd width, is the image's middle: the same ray.
    assert_eq!(middle(&dir, &lab), [205; 3]);
    // probe says how the normal was made: |N| = sqrt(1/18 + 1/18 + (1 + sqrt 2)^2 / 9)
    // = 0.871042, and N.L its z, 0.804738.
    let text = lumiere_ok(&["probe", &linear, "--pixel", "10,10"]);
    assert!(
        text.contains(
            "      point (0.000000, 0.000000, 0.000000), normal (0.235702, 0.235702, 0.804738)\n      normal interpolated from the vertices' (linear): length 0.871042, kept, as SIMRenderer's btriangle keeps it\n"
        ),
        "{text}"
    );
    assert!(text.contains("N.L 0.804738,"), "{text}");
    let json: serde_json::Value =
        serde_json::from_str(&lumiere_ok(&["probe", &normalized, "--pixel", "10,10", "--json"])).unwrap();
    let hit = &json["samples"][0]["ray"]["hit"];
    assert_eq!(hit["vertex_normals"]["interpolation"], "normalized");
    let length = hit["vertex_normals"]["length"].as_f64().unwrap();
    assert!((length - 0.8710419765842512).abs() < 1e-12, "{length}");
    let s = scene::load(Path::new(&lab)).unwrap();
    let Shape::SmoothTriangle(t) = &s.objects[0].shape else {
        panic!("a btriangle reads as a smooth triangle: {:?}", s.objects[0].shape);
    };
    assert_eq!(t.interpolation, NormalInterpolation::Linear);
    assert_eq!(t.uvs, [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    // Divided by its length, as SIMRenderer's `normalize` does.
    let r = 1.0 / 2f64.sqrt();
    assert_eq!(t.normals[1].to_array(), [r, 0.0, r]);
}

/// Texture coordinates interpolate too: probe prints the hit's normal, and both formats
/// carry the vertex data through `convert` to the same render.
#[test]
fn convert_carries_the_vertex_data_both_ways() {
    let dir = temp_dir("smooth-triangles-convert");
    let lab = write_in(&dir, "lab.txt", SIMRENDERER);
    let toml_path = dir.join("lab.toml");
    lumiere_ok(&["convert", &lab, "-o", toml_path.to_str().unwrap()]);
    let written = std::fs::read_to_string(&toml_path).unwrap();
    assert!(
        written.contains("normals = [[0, 0, 1], [1, 0, 1], [0, 1, 1]]\n"),
        "{written}"
    );
    assert!(written.contains("normal_interpolation = \"linear\"\n"), "{written}");
    // (0, 0), (1, 0), (0, 1) are the flat triangle's own coordinates: not written.
    assert!(!written.contains("uvs"), "{written}");
    assert_eq!(middle(&dir, toml_path.to_str().unwrap()), [205; 3]);
    let back = dir.join("back.txt");
    lumiere_ok(&["convert", toml_path.to_str().unwrap(), "-o", back.to_str().unwrap()]);
    let back_text = std::fs::read_to_string(&back).unwrap();
    assert!(
        back_text.contains("btriangle\npoint  -1 -1 0\npoint  2 -1 0\npoint  -1 2 0\nnormal 0 0 1\nnormal 1 0 1\nnormal 0 1 1\nuv     0 0\nuv     1 0\nuv     0 1\nend\n"),
        "{back_text}"
    );
    assert_eq!(
        scene::load(&back).unwrap().objects,
        scene::load(Path::new(&lab)).unwrap().objects
    );
    // A normalized smooth triangle has no SIMRenderer form.
    let normalized = write_in(&dir, "normalized.toml", &toml(NORMALS));
    let o = lumiere(&["convert", &normalized, "-o", dir.join("n.txt").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("keeps the interpolated normal's length"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn bad_vertex_data_is_refused_where_it_is() {
    let dir = temp_dir("smooth-triangles-bad");
    let cases = [
        (
            "normals = [[0, 0, 1], [0, 0, 0], [0, 1, 1]]\n",
            "shapes[0].normals[1]: must be a direction of non-zero length, got [0.0, 0.0, 0.0]",
        ),
        (
            "normal_interpolation = \"linear\"\n",
            "shapes[0].normal_interpolation: applies to a triangle with vertex normals or uvs; this one has neither",
        ),
        (
            "uvs = [[0, 0], [1, 0], [0, 1]]\nnormal_interpolation = \"smooth\"\n",
            "shapes[0].normal_interpolation: must be \"normalized\" or \"linear\", got \"smooth\"",
        ),
    ];
    for (i, (extra, message)) in cases.iter().enumerate() {
        let path = write_in(&dir, &format!("bad{i}.toml"), &toml(extra));
        let e = scene::load(Path::new(&path)).unwrap_err().to_string();
        assert!(e.ends_with(message), "{e}");
    }
    // SIMRenderer: a fourth normal, and a btriangle inside a geometry wrapper.
    let four = SIMRENDERER.replace("normal 0 1 1\n", "normal 0 1 1\nnormal 1 1 1\n");
    let path = write_in(&dir, "four.txt", &four);
    let o = lumiere(&["render", &path, "-o", dir.join("four.png").to_str().unwrap()]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains(":31:1: ") && e.contains("a btriangle takes 3 normals (one a vertex); this is one more"),
        "{e}"
    );
    let wrapped = SIMRENDERER
        .replace("btriangle\n", "geometry\nbtriangle\n")
        .replace("end\nend\n", "end\nend\nend\n");
    let path = write_in(&dir, "wrapped.txt", &wrapped);
    let o = lumiere(&["render", &path, "-o", dir.join("wrapped.png").to_str().unwrap()]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("SIMRenderer does not transform a btriangle"), "{e}");
}

/// An octahedron of smooth triangles whose vertex normals point away from its centre (a
/// coarse sphere), over a half-mirror floor, under a point light: both tracers give the
/// same bits under each rule and each highlight, and the linear rule's image is darker
/// than the normalized one's where the octahedron is lit (`|N| < 1` inside a face).
#[test]
fn both_tracers_agree_on_smooth_triangles() {
    use lumiere::render::{render, render_reference};
    use lumiere::world::World;
    let faces = [
        ([1, 0, 0], [0, 1, 0], [0, 0, 1]),
        ([0, 1, 0], [-1, 0, 0], [0, 0, 1]),
        ([-1, 0, 0], [0, -1, 0], [0, 0, 1]),
        ([0, -1, 0], [1, 0, 0], [0, 0, 1]),
        ([0, 1, 0], [1, 0, 0], [0, 0, -1]),
        ([-1, 0, 0], [0, 1, 0], [0, 0, -1]),
        ([0, -1, 0], [-1, 0, 0], [0, 0, -1]),
        ([1, 0, 0], [0, -1, 0], [0, 0, -1]),
    ];
    let v = |p: [i32; 3]| format!("[{}, {}, {}]", p[0], p[1], p[2] + 1);
    let n = |p: [i32; 3]| format!("[{}, {}, {}]", p[0], p[1], p[2]);
    let dir = temp_dir("smooth-triangles-tracers");
    let mut lit = Vec::new();
    for (rule, specular) in [("linear", "blinn"), ("normalized", "phong"), ("linear", "phong")] {
        let mut text = format!(
            "[image]\nwidth = 48\nheight = 36\nsamples_per_pixel = 4\n\
             [camera]\nposition = [2, -5, 3]\nlook_at = [0, 0, 0.8]\nup = [0, 0, 1]\nvfov = 45\n\
             [render]\ndepth = 3\nspecular = \"{specular}\"\n\
             [materials.shiny]\ncolor = [0.9, 0.5, 0.2]\nks = 0.6\nshininess = 30\n\
             [materials.floor]\ncolor = [1, 1, 1]\nkd = 0.5\nkr = 0.5\n\
             [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nmaterial = \"floor\"\n\
             [[lights]]\ntype = \"ambient\"\ncolor = [0.2, 0.2, 0.2]\n\
             [[lights]]\ntype = \"point\"\nposition = [3, -4, 5]\ncolor = [1, 1, 1]\n"
        );
        for (a, b, c) in faces {
            text += &format!(
                "[[shapes]]\ntype = \"triangle\"\np0 = {}\np1 = {}\np2 = {}\nnormals = [{}, {}, {}]\n\
                 normal_interpolation = \"{rule}\"\nmaterial = \"shiny\"\n",
                v(a),
                v(b),
                v(c),
                n(a),
                n(b),
                n(c)
            );
        }
        let path = write_in(&dir, &format!("{rule}-{specular}.toml"), &text);
        let scene = scene::load(Path::new(&path)).unwrap();
        let world = World::new(&scene);
        let (fast, stats) = render(&world, &|| {});
        let (reference, _) = render_reference(&world, &|| {});
        assert!(stats.counts.reflection > 0);
        for (a, b) in fast.pixels.iter().zip(&reference.pixels) {
            assert_eq!(a.to_array().map(f64::to_bits), b.to_array().map(f64::to_bits), "{path}");
        }
        lit.push(fast.pixels);
    }
    let (linear, normalized) = (&lit[2], &lit[1]);
    let darker = linear
        .iter()
        .zip(normalized)
        .filter(|(l, n)| l.element_sum() < n.element_sum() - 1e-3)
        .count();
    let brighter = linear
        .iter()
        .zip(normalized)
        .filter(|(l, n)| l.element_sum() > n.element_sum() + 1e-12)
        .count();
    // Darker on over a hundred pixels; brighter on a few, where a face's reflected ray, whose
    // direction the normal's length changes, meets something brighter.
    assert!(
        darker > 100 && brighter * 20 < darker,
        "{darker} darker, {brighter} brighter"
    );
}

/// A SIMRenderer model whose faces give vertex normals and texture coordinates is made of
/// smooth triangles, as SIMRenderer's model reader builds `SBTriangleGeometry` for them; a
/// face without them stays flat; the model's transform turns the normals by `A^-T`. A TOML
/// mesh does so with `normal_interpolation`.
#[test]
fn a_model_with_vertex_normals_is_smooth() {
    let dir = temp_dir("smooth-triangles-model");
    let obj = "v -1 -1 0\nv 2 -1 0\nv -1 2 0\nv 5 5 0\n\
               vn 0 0 1\nvn 1 0 1\nvn 0 1 1\n\
               vt 0 0\nvt 1 0\nvt 0 1\n\
               f 1/1/1 2/2/2 3/3/3\nf 2 4 3\n";
    write_in(&dir, "two.obj", obj);
    let lab = |extra: &str| {
        SIMRENDERER.replace(
            "primitive\nmaterial_name white\nbtriangle\n\
             point -1 -1 0\npoint 2 -1 0\npoint -1 2 0\n\
             normal 0 0 1\nnormal 1 0 1\nnormal 0 1 1\n\
             uv 0 0\nuv 1 0\nuv 0 1\n\
             end\nend\n",
            &format!("model\nfile two.obj\n{extra}end\n"),
        )
    };
    // The model's file names no material library: its triangles take SIMRenderer's library
    // default, diffuse (0.3, 0.7, 0.3) as 32-bit floats, so the centroid's diffuse term is
    // (0.3, 0.7, 0.3) (1 + sqrt 2) / 3 = (0.24142, 0.56332, 0.24142): 62 144 62.
    let plain = write_in(&dir, "model.txt", &lab(""));
    let s = scene::load(Path::new(&plain)).unwrap();
    assert!(matches!(s.objects[0].shape, Shape::SmoothTriangle(_)));
    assert!(matches!(s.objects[1].shape, Shape::Triangle(_)));
    assert_eq!(middle(&dir, &plain), [62, 144, 62]);
    // Scaled by 2 along z: the plane z = 0 stays, the normals (0, 0, 1), (2, 0, 1) / sqrt 5
    // and (0, 2, 1) / sqrt 5 give (0.3, 0.7, 0.3) (1 + 2 / sqrt 5) / 3: 48 113 48.
    let scaled = write_in(&dir, "scaled.txt", &lab("scale 1 1 2\n"));
    assert_eq!(middle(&dir, &scaled), [48, 113, 48]);
    // A TOML mesh uses the normals only when asked, under the rule it names.
    let mesh = |extra: &str| {
        toml("").replace(
            "[[shapes]]\ntype = \"triangle\"\np0 = [-1, -1, 0]\np1 = [2, -1, 0]\np2 = [-1, 2, 0]\nmaterial = \"white\"\n",
            &format!("[[shapes]]\ntype = \"mesh\"\nfile = \"two.obj\"\nmaterial = \"white\"\n{extra}"),
        )
    };
    for (name, extra, value) in [
        ("flat", "", 255),
        ("normalized", "normal_interpolation = \"normalized\"\n", 236),
        ("linear", "normal_interpolation = \"linear\"\n", 205),
    ] {
        let path = write_in(&dir, &format!("mesh-{name}.toml"), &mesh(extra));
        assert!(scene::load(Path::new(&path)).unwrap().objects.len() == 2);
        assert_eq!(middle(&dir, &path), [value; 3], "{name}");
    }
    let bad = write_in(&dir, "mesh-bad.toml", &mesh("normal_interpolation = \"phong\"\n"));
    let e = scene::load(Path::new(&bad)).unwrap_err().to_string();
    assert!(
        e.ends_with("shapes[0].normal_interpolation: must be \"normalized\" or \"linear\", got \"phong\""),
        "{e}"
    );
    // A face that gives some of its vertices a normal is refused on its first vertex unlike
    // the face's first.
    write_in(&dir, "mixed.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2 3\n");
    let mixed = write_in(&dir, "mixed.txt", &lab("").replace("two.obj", "mixed.obj"));
    let e = scene::load(Path::new(&mixed)).unwrap_err().to_string();
    assert!(
        e.contains("mixed.obj:5:8: 1 of the face's 3 vertices has a normal: give it to all of them or none"),
        "{e}"
    );
}
