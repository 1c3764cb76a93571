//! Hostile input, as a proptest harness: mutated scene files (of a scene with every shape
//! (spherical cap and lens included),
//! a transform in each of its forms, a mesh, every light kind including area lights, and
//! `[[generate]]` tables) and random text must
//! give a scene, a located error, or (a required table deleted or cut off) an error naming
//! each missing table, never a panic; random valid scenes (with random area lights) must
//! render without a panic and with no NaN or infinity in any pixel. The suite runs 256
//! cases per property; the long run, 50 000 cases per property in about 10 s:
//! `PROPTEST_CASES=50000 nice -n 10 cargo test --release --test suite -- fuzz:: --skip
//! simrenderer_fuzz` (see BENCHMARKS.md).

use crate::common::mutate::{apply, mutation};
use lumiere::render::render;
use lumiere::scene::{self};
use lumiere::world::World;
use proptest::prelude::*;

/// A scene using every section, shape and light kind: area lights of each shape, placement
/// and mode (few points, so that each case stays fast), and a small `[[generate]]` table.
const VALID: &str = r#"[image]
width = 8
height = 6
samples_per_pixel = 1
seed = 3

[camera]
position = [0, -8, 5]
look_at = [0, 1, 0]
up = [0, 0, 1]
vfov = 60

[render]
depth = 3
specular = "phong"
adaptive_threshold = 0.25

[materials.glass]
color = [0.9, 0.9, 1]
kt = 0.8
kr = 0.1
n = 1.5

[materials.mirror]
kr = 0.9
m = 1

[[shapes]]
type = "plane"
point = [0, 0, 0]
normal = [0, 0, 1]

[[shapes]]
type = "sphere"
center = [1, -2, 1]
radius = 1
material = "glass"

[[shapes]]
type = "box"
center = [0, 0, 3]
size = [2, 2, 2]
rotation = [10, 20, 30]

[[shapes]]
type = "cone"
base = [-3, -3, 0]
axis = [0, 0.2, 1]
height = 2.5
radius = 1

[[shapes]]
type = "cylinder"
base = [-5, 9, 0]
height = 3
radius = 1

[[shapes]]
type = "torus"
center = [4, 3, 2]
axis = [1, 0, 1]
major_radius = 1.5
minor_radius = 0.5

[[shapes]]
type = "disk"
center = [0, 5, 0.01]
normal = [0, 0, 1]
radius = 2

[[shapes]]
type = "rectangle"
corner = [-4, 6, 0]
edge1 = [8, 0, 0]
edge2 = [0, 0, 4]
material = "mirror"

[[shapes]]
type = "mirror_pair"
hinge = [6, 6, 0]
opening = 60
length = 2
height = 2
material = "mirror"

[[shapes]]
type = "triangle"
p0 = [-2, 2, 0]
p1 = [0, 2, 0]
p2 = [-1, 2, 2]

[[shapes]]
type = "tube"
start = [2, 2, 1]
end = [4, 2, 1.5]
radius = 0.5
material = "glass"

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
transform = { scale = [0.5, 1, 1.5], rotation = [10, 20, 30], translation = [-2, -2, 1.5] }

[[shapes]]
type = "torus"
center = [0, 0, 0]
major_radius = 1
minor_radius = 0.25

[shapes.transform]
matrix = [[1, 0.5, 0, 3], [0, 1, 0, -3], [0, 0, 2, 1]]

[[shapes]]
type = "spherical_cap"
center = [-6, 0, 2]
normal = [0, -1, 0.5]
radius = 1
curvature = -1.5
material = "glass"

[[shapes]]
type = "lens"
base = [5, -4, 1]
axis = [0, 1, 0.2]
thickness = 0.5
radius = 1
curvature1 = 2
curvature2 = -3
material = "glass"

[[shapes]]
type = "mesh"
file = "scenes/icosahedron.obj"
name = "gem"
material = "mirror"
transform = { scale = [0.5, 0.5, -0.5], translation = [0, -4, 1] }

[[lights]]
type = "ambient"
color = [0.5, 0.5, 0.5]

[[lights]]
type = "directional"
direction = [1, 1, -1]

[[lights]]
type = "point"
position = [0, 0, 10]
attenuation = { constant = 1, linear = 0.1, quadratic = 0.01 }

[[lights]]
type = "spot"
position = [0, 0, 10]
direction = [0, 0, -1]
angle = 70
c_min = 0.2

[[lights]]
type = "area"
shape = "sphere"
center = [2, -2, 8]
radius = 1
points = 4
placement = "chapter"
mode = "fixed"
attenuation = { quadratic = 0.005 }

[[lights]]
type = "area"
shape = "tube"
start = [-3, 0, 9]
end = [3, 1, 9]
points = 3
placement = "stratified"
mode = "per_sample"

[[lights]]
type = "area"
shape = "window"
center = [0, 4, 7]
edge1 = [2, 0, 0]
edge2 = [0, 1, 0.5]
points = 5
placement = "fibonacci"
mode = "fixed"
color = [0.5, 0.4, 0.3]

[[lights]]
type = "area"
shape = "sphere"
center = [-4, -4, 6]
radius = 0.5
points = 2
placement = "uniform"
mode = "per_sample"

[[generate]]
kind = "mixed"
count = 5
seed = 1
min = [-6, -6, 0]
max = [6, 6, 3]
radius = [0.2, 0.5]
materials = ["glass", "default"]

[[generate]]
kind = "triangles"
count = 5
seed = 2
min = [-6, -6, 0]
max = [6, 6, 3]
radius = [0.2, 0.5]
"#;

fn hostile_value() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "nan",
            "inf",
            "-inf",
            "-1",
            "0",
            "1e308",
            "-1e308",
            "5e-324",
            "18446744073709551615",
            "-9223372036854775808",
            "\"\"",
            "[]",
            "[0, 0, 0]",
            "[nan, 1, 1]",
            "[1e300, 1e300, 1e300]",
            "[1, 2]",
            "true",
            "{}",
            "\"sphere\"",
            "[0, 0, 1e-300]",
            "1e9",
            "4294967296",
            "65536",
            "180.0000001",
            "100000",
            "100001",
            "4000000",
            "-0.0",
            // Valid names in the wrong place: another type, shape, placement or mode.
            "\"area\"",
            "\"tube\"",
            "\"window\"",
            "\"torus\"",
            "\"mirror_pair\"",
            "\"fibonacci\"",
            "\"per_sample\"",
            "\"mixed\"",
            "\"triangle\"",
            "\"triangles\"",
            "\"mesh\"",
            "\"scenes/icosahedron.obj\"",
            "\"scenes/reference.toml\"",
            "\"scenes\"",
            "1e-7",
            "[-1, 1, 1]",
            "[1e-6, 1e6, 1]",
            "{ scale = [0, 1, 1] }",
            "{ matrix = [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]] }",
            "{ matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1e-7, 0]] }",
            "[[1, 0, 0, 1e9], [0, 1, 0, 0], [0, 0, 1, 0]]",
            "{ rotation = [0, 0, 90], translation = [1e9, 0, 0] }",
        ])
        .prop_map(str::to_string),
        any::<f64>().prop_map(|x| format!("{x:e}")),
        any::<i64>().prop_map(|x| x.to_string()),
        "[a-z_]{0,10}".prop_map(|s| format!("\"{s}\"")),
    ]
}

/// One valid area light: a random shape (sphere, tube or window), placement, mode and 1 to 8
/// points. Tube ends differ by at least 1e-3 and window edges are orthogonal, so that every
/// light passes validation.
fn area_light() -> impl Strategy<Value = String> {
    (
        0usize..3,
        prop::sample::select(vec!["chapter", "uniform", "stratified", "fibonacci"]),
        prop::sample::select(vec!["fixed", "per_sample"]),
        1u32..9,
        (-20.0..20.0f64, -20.0..20.0f64, 1.0..30.0f64),
        (0.0..3.0f64, 1e-3..5.0f64, 1e-3..5.0f64),
        (0.0..std::f64::consts::TAU, -1.0..1.0f64),
    )
        .prop_map(|(shape, placement, mode, points, (x, y, z), (r, a, b), (turn, tilt))| {
            let (cos, sin) = (turn.cos(), turn.sin());
            let geometry = match shape {
                0 => format!("shape = \"sphere\"\ncenter = [{x}, {y}, {z}]\nradius = {r}"),
                1 => format!(
                    "shape = \"tube\"\nstart = [{x}, {y}, {z}]\nend = [{}, {}, {}]",
                    x + a * cos,
                    y + a * sin,
                    z + tilt
                ),
                _ => format!(
                    "shape = \"window\"\ncenter = [{x}, {y}, {z}]\nedge1 = [{}, {}, 0]\nedge2 = [{}, {}, {tilt}]",
                    a * cos,
                    a * sin,
                    -b * sin,
                    b * cos
                ),
            };
            format!(
                "[[lights]]\ntype = \"area\"\n{geometry}\npoints = {points}\nplacement = \"{placement}\"\n\
                 mode = \"{mode}\"\nattenuation = {{ quadratic = 0.01 }}\n"
            )
        })
}

/// Renders a parsed scene at 6 x 4, 1 sample, depth at most 4, and checks every pixel.
fn render_tiny(mut s: scene::Scene) {
    s.settings.width = 6;
    s.settings.height = 4;
    s.settings.samples_per_pixel = 1;
    s.settings.depth = s.settings.depth.min(4);
    let world = World::new(&s);
    let (film, stats) = render(&world, &|| {});
    assert_eq!(stats.counts.non_finite, 0);
    assert!(film.pixels.iter().all(|p| p.is_finite()));
}

#[test]
fn the_fuzz_seed_scene_is_valid() {
    let s = scene::parse(VALID, "fuzz.toml").unwrap();
    // 11 entries of one object, a mirror pair, 20 mesh triangles and 5 + 5 generated.
    assert_eq!((s.objects.len(), s.lights.len()), (46, 8));
    render_tiny(s);
}

proptest! {
    #[test]
    fn mutated_scenes_give_a_scene_or_a_located_error(m in mutation(hostile_value, "[a-z_]{1,12}", 1)) {
        let text = apply(VALID, &m, " = ");
        match scene::parse(&text, "fuzz.toml") {
            Ok(s) => render_tiny(s),
            Err(scene::SceneError::MissingTables { file, tables }) => {
                // Exactly the required tables that the TOML lacks at its top level, where every
                // top-level key is one of the format's (an unknown one is a located error).
                let root = text.parse::<toml::Table>().map_err(|e| TestCaseError::fail(e.to_string()))?;
                let known = ["image", "camera", "render", "materials", "shapes", "lights", "generate"];
                prop_assert!(root.keys().all(|k| known.contains(&k.as_str())), "{:?}", root.keys().collect::<Vec<_>>());
                let lacked: Vec<&str> = ["image", "camera"].into_iter().filter(|t| !root.contains_key(*t)).collect();
                prop_assert_eq!(file, "fuzz.toml");
                prop_assert_eq!(tables, lacked);
            }
            Err(e) => {
                let msg = e.to_string();
                // file:line:column: field: message, at a place inside the text.
                let mut parts = msg.splitn(4, ':');
                prop_assert_eq!(parts.next(), Some("fuzz.toml"));
                let line = parts.next().and_then(|l| l.parse::<usize>().ok());
                let column = parts.next().and_then(|c| c.parse::<usize>().ok());
                let (Some(line), Some(column)) = (line, column) else {
                    return Err(TestCaseError::fail(msg));
                };
                let shown = line.checked_sub(1).and_then(|i| text.split('\n').nth(i)).map(|l| l.chars().count());
                prop_assert!(shown.is_some_and(|n| column >= 1 && column <= n + 1), "{}", msg);
                // ` field: message`, the field never empty.
                let rest = parts.next().unwrap_or_default();
                prop_assert!(rest.starts_with(' ') && rest[1..].split(": ").next().is_some_and(|f| !f.is_empty() && !f.contains(' ')), "{}", msg);
            }
        }
    }

    #[test]
    fn random_text_never_panics(text in "\\PC{0,300}") {
        let _ = scene::parse(&text, "random.toml");
    }

    #[test]
    fn random_valid_scenes_render_finite(
        centers in prop::collection::vec((-50.0..50.0f64, -50.0..50.0f64, -5.0..20.0f64), 1..6),
        sizes in prop::collection::vec(1e-3..10.0f64, 6),
        axis in (-1.0..1.0f64, -1.0..1.0f64, 0.05..1.0f64),
        kind in prop::collection::vec(0usize..11, 6),
        kr in 0.0..0.5f64,
        kt in 0.0..0.5f64,
        n in 0.2..3.0f64,
        light in (-20.0..20.0f64, -20.0..20.0f64, 1.0..30.0f64),
        camera in (-30.0..30.0f64, -30.0..-1.0f64, 0.5..30.0f64),
        areas in prop::collection::vec(area_light(), 0..4),
    ) {
        let (ax, ay, az) = axis;
        let mut text = format!(
            "[image]\nwidth = 6\nheight = 4\nsamples_per_pixel = 1\n[camera]\nposition = [{}, {}, {}]\nlook_at = [0, 0, 0]\n\
             [render]\ndepth = 4\n[materials.m]\nkr = {kr}\nkt = {kt}\nn = {n}\n\
             [[lights]]\ntype = \"ambient\"\n[[lights]]\ntype = \"point\"\nposition = [{}, {}, {}]\n\
             [[lights]]\ntype = \"spot\"\nposition = [{}, {}, {}]\ndirection = [0, 0, -1]\nangle = 90\n",
            camera.0, camera.1, camera.2, light.0, light.1, light.2, light.0, light.1, light.2
        );
        for (i, (x, y, z)) in centers.iter().enumerate() {
            let (r, h) = (sizes[i], sizes[(i + 1) % 6]);
            text += &match kind[i] {
                0 => format!("[[shapes]]\ntype = \"sphere\"\ncenter = [{x}, {y}, {z}]\nradius = {r}\nmaterial = \"m\"\n"),
                1 => format!("[[shapes]]\ntype = \"box\"\ncenter = [{x}, {y}, {z}]\nsize = [{r}, {h}, {r}]\nrotation = [{x}, {y}, {z}]\nmaterial = \"m\"\n"),
                2 => format!("[[shapes]]\ntype = \"cone\"\nbase = [{x}, {y}, {z}]\naxis = [{ax}, {ay}, {az}]\nheight = {h}\nradius = {r}\nmaterial = \"m\"\n"),
                3 => format!("[[shapes]]\ntype = \"cylinder\"\nbase = [{x}, {y}, {z}]\naxis = [{ax}, {ay}, {az}]\nheight = {h}\nradius = {r}\nmaterial = \"m\"\n"),
                4 => format!("[[shapes]]\ntype = \"torus\"\ncenter = [{x}, {y}, {z}]\naxis = [{ax}, {ay}, {az}]\nmajor_radius = {}\nminor_radius = {}\nmaterial = \"m\"\n", r.max(h), r.min(h)),
                6 => format!("[[shapes]]\ntype = \"triangle\"\np0 = [{x}, {y}, {z}]\np1 = [{}, {y}, {z}]\np2 = [{}, {}, {}]\nmaterial = \"m\"\n", x + r, x + ax, y + h, z + az),
                7 => format!("[[shapes]]\ntype = \"tube\"\nstart = [{x}, {y}, {z}]\nend = [{}, {}, {}]\nradius = {r}\nmaterial = \"m\"\n", x + ax * h, y + ay * h, z + az * h),
                9 => format!("[[shapes]]\ntype = \"spherical_cap\"\ncenter = [{x}, {y}, {z}]\nnormal = [{ax}, {ay}, {az}]\nradius = {r}\ncurvature = {}\nmaterial = \"m\"\n", if kt > 0.25 { -r - h } else { r + h }),
                10 => format!("[[shapes]]\ntype = \"lens\"\nbase = [{x}, {y}, {z}]\naxis = [{ax}, {ay}, {az}]\nthickness = {}\nradius = {r}\ncurvature1 = {}\ncurvature2 = {}\nmaterial = \"m\"\n", h + r, r + h, if kr > 0.25 { -r - h } else { r }),
                8 => format!("[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\ntransform = {{ scale = [{r}, {h}, 1], rotation = [{x}, {y}, {z}], translation = [{x}, {y}, {z}] }}\n"),
                _ => format!("[[shapes]]\ntype = \"disk\"\ncenter = [{x}, {y}, {z}]\nnormal = [{ax}, {ay}, {az}]\nradius = {r}\nmaterial = \"m\"\n"),
            };
        }
        text += "[[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n";
        text += &areas.concat();
        let s = scene::parse(&text, "generated.toml").map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        render_tiny(s);
    }
}
