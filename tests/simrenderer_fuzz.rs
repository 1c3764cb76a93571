//! Hostile SIMRenderer scene files, as a proptest harness (the TOML reader's is
//! tests/fuzz.rs): mutations of a scene that uses every block, geometry and light lumiere
//! reads (a value replaced by a hostile one, a line deleted, repeated or inserted, the text
//! cut or a byte changed) and random text must give a scene or an error at a place in the
//! text (`file:line:column: block.keyword: message`), never a panic; under `--lenient`,
//! always a scene, each warning at such a place. Every scene read renders with no NaN or
//! infinity in any pixel. 256 cases per property; the long run:
//! `PROPTEST_CASES=50000 nice -n 10 cargo test --release --test suite simrenderer_fuzz::`.

use crate::common::mutate::{apply, mutation};
use lumiere::render::render;
use lumiere::scene::simrenderer::{self, Options, lex};
use lumiere::scene::{Scene, SceneError};
use lumiere::world::World;
use proptest::prelude::*;

/// Every block, geometry and light, comments, a note, a model.
const VALID: &str = "# a scene using every block lumiere reads
camera
position 0 -8 5
look_at 0 1 0
haut 0 0 1
angle 60
near_clipping_plane 1
far_clipping_plane 1000
end
viewport
width 8
height 6
image_file_name fuzz
end
raytracer
task 2
sampling 1
recursive_level 3
reflexion_algorithm blinn
pixel_coordinate center
space linear
color_normalization clamp_channel
# lumiere: seed 3
end
ambient_light
color 0.3 0.3 0.3
end
directional_light
color blanc
orientation 1 1 -1
end
point_light
color 1 0.9 0.8
position 0 0 10
amplification 1.5
constant_attenuator 1
linear_attenuator 0.1
quadratic_attenuator 0.01
end
material
name glass
color 0.9 0.9 1
kr 0.1
kt 0.8
n 1.5
p 0.5
end
materiel
nom mirror
couleur 1 1 1
kr 0.9
brillance 80
end
primitive
material_name glass
sphere
position 1 -2 1
ray 1
end
end
primitive
plane
position 0 0 0
normal 0 0 1
end
end
primitive
material_name mirror
disk
position 0 5 0.01
normal 0 0 1
ray 2
end
end
primitive
triangle
point -2 2 0
point 0 2 0
point -1 2 2
end
end
primitive
material_name glass
tube
point 2 2 1
point 4 2 1.5
ray 0.5
end
end
primitive
cylinder
point -5 9 0
point -5 9 3
ray 1
end
end
primitive
cone
point -3 -3 0
point -3 -3 2.5
ray 1
end
end
primitive
# lumiere: name \"cube\"
cube
position 0 0 3
size 2
end
end
primitive
torus
position 4 3 2
normal 1 0 1
major_radius 1.5
minor_radius 0.5
end
end
primitive
material_name glass
geometry
scale 0.5 1 1.5
rotation 10 20 30
translation -2 -2 1.5
geometrie
homothetie 1 1 -1
sphere
end
end
end
end
model
file tests/fixtures/simrenderer/tetrahedron.obj
scale 1 1 2
rotation 0 0 45
translation 0 -4 0
end
";

fn hostile_value() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "",
            "NaN",
            "Infinity",
            "-Infinity",
            "-1",
            "0",
            "1e308",
            "-1e308",
            "5e-324",
            "1e9",
            "1e10",
            "2147483647",
            "2147483648",
            "-2147483649",
            "1 2",
            "(1, 2, 3)",
            "a b c",
            "1e-7",
            "360",
            "361",
            "noir",
            "blanc 2",
            "rouge -1",
            "0 0 0",
            "1e-300 0 0",
            "1e300 1e300 1e300",
            "random",
            "top_right",
            "no_light",
            "division_factor",
            "7",
            "8",
            "-1 1 1",
            "0.5f",
            "1d",
            "0x10",
            "1024",
            "1025",
            "65",
            "169",
            "171",
            "16384",
            "16385",
            "1 1 1 1 1",
            "\"quoted\"",
            "tests/fixtures/simrenderer/tetrahedron.obj",
            "scenes",
            "scenes/icosahedron.obj",
            "scenes/reference.toml",
            "scenes/figures/optique/textured-sphere.png",
            "none",
            "glass",
            "mirror",
            "0.5 0.5 0.5 2",
        ])
        .prop_map(str::to_string),
        any::<f64>().prop_map(|x| format!("{x:e}")),
        any::<i64>().prop_map(|x| x.to_string()),
        (any::<f64>(), any::<f64>(), any::<f64>()).prop_map(|(x, y, z)| format!("{x} {y} {z}")),
        "[a-z_]{0,10}",
    ]
}

/// Every keyword and alias, and a few words SIMRenderer does not know.
fn keyword() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "end",
            "fin",
            "camera",
            "viewport",
            "raytracer",
            "primitive",
            "material",
            "materiel",
            "model",
            "ambient_light",
            "directional_light",
            "point_light",
            "texture_material",
            "linear_aperture_light",
            "rectangular_aperture_light",
            "elliptical_aperture_light",
            "aperture_mask_light",
            "wave_length",
            "nb_oscillator",
            "period_iteration",
            "front",
            "sphere",
            "plane",
            "disk",
            "triangle",
            "btriangle",
            "tube",
            "cylinder",
            "cone",
            "cube",
            "torus",
            "geometry",
            "lens",
            "spherical_cap",
            "position",
            "look_at",
            "up",
            "angle",
            "width",
            "height",
            "sampling",
            "recursive_level",
            "pixel_coordinate",
            "name",
            "color",
            "ka",
            "kt",
            "kr",
            "n",
            "p",
            "shininess",
            "material_name",
            "ray",
            "normal",
            "point",
            "size",
            "major_radius",
            "minor_radius",
            "scale",
            "rotation",
            "translation",
            "file",
            "orientation",
            "amplification",
            "constant_attenuator",
            "curvature",
            "courbure",
            "texture_ka",
            "texture_kd",
            "texture_ks",
            "/*",
            "*/",
            "# lumiere: name",
            "# lumiere: seed",
            "# lumiere: colour",
        ])
        .prop_map(str::to_string),
        "[a-z_]{1,12}",
    ]
}

/// Renders a scene at 6 x 4, 1 sample, depth at most 4, and checks every pixel.
fn render_tiny(mut s: Scene) -> Result<(), TestCaseError> {
    s.settings.width = 6;
    s.settings.height = 4;
    s.settings.samples_per_pixel = 1;
    s.settings.depth = s.settings.depth.min(4);
    let (film, stats) = render(&World::new(&s), &|| {});
    prop_assert_eq!(stats.counts.non_finite, 0);
    prop_assert!(film.pixels.iter().all(|p| p.is_finite()));
    Ok(())
}

/// `message` is `fuzz.txt:LINE:COLUMN: FIELD: ...` at a place inside `text` (lines split as
/// SIMRenderer splits them), its field non-empty and without blanks.
fn assert_placed(message: &str, text: &str) -> Result<(), TestCaseError> {
    let mut parts = message.splitn(4, ':');
    prop_assert_eq!(parts.next(), Some("fuzz.txt"), "{}", message);
    let line = parts.next().and_then(|l| l.parse::<usize>().ok());
    let column = parts.next().and_then(|c| c.parse::<usize>().ok());
    let (Some(line), Some(column)) = (line, column) else {
        return Err(TestCaseError::fail(message.to_string()));
    };
    let lines = lex::split_lines(text);
    // An empty text's line 1 is empty.
    let shown = line
        .checked_sub(1)
        .and_then(|i| lines.get(i))
        .map(|l| l.chars().count())
        .or((line == 1 && lines.is_empty()).then_some(0));
    prop_assert!(shown.is_some_and(|n| column >= 1 && column <= n + 1), "{}", message);
    let rest = parts.next().unwrap_or_default();
    prop_assert!(
        rest.starts_with(' ')
            && rest[1..]
                .split(": ")
                .next()
                .is_some_and(|f| !f.is_empty() && !f.contains([' ', '\t'])),
        "{}",
        message
    );
    Ok(())
}

#[test]
fn the_fuzz_seed_scene_is_valid() {
    let p = simrenderer::parse(VALID, "fuzz.txt", &Options::default()).unwrap();
    // 10 primitives and the tetrahedron's 4 triangles; 3 lights.
    assert_eq!((p.scene.objects.len(), p.scene.lights.len()), (14, 3));
    // The plane's material: SIMRenderer's grey.
    assert_eq!(p.warnings.len(), 1, "{:?}", p.warnings);
    render_tiny(p.scene).unwrap();
}

proptest! {
    #[test]
    fn mutated_files_give_a_scene_or_a_placed_error(m in mutation(hostile_value, keyword(), 2)) {
        let text = apply(VALID, &m, " ");
        match simrenderer::parse(&text, "fuzz.txt", &Options::default()) {
            Ok(p) => {
                for w in &p.warnings {
                    assert_placed(&w.to_string(), &text)?;
                }
                render_tiny(p.scene)?;
            }
            Err(SceneError::Invalid { .. }) => {}
            Err(e) => return Err(TestCaseError::fail(format!("not a located error: {e}"))),
        }
        if let Err(e) = simrenderer::parse(&text, "fuzz.txt", &Options::default()) {
            assert_placed(&e.to_string(), &text)?;
        }
    }

    #[test]
    fn lenient_always_gives_a_scene_and_placed_warnings(m in mutation(hostile_value, keyword(), 2)) {
        let text = apply(VALID, &m, " ");
        let options = Options { lenient: true, ..Options::default() };
        let p = simrenderer::parse(&text, "fuzz.txt", &options).map_err(|e| TestCaseError::fail(e.to_string()))?;
        for w in &p.warnings {
            assert_placed(&w.to_string(), &text)?;
        }
        render_tiny(p.scene)?;
    }

    #[test]
    fn random_text_never_panics(text in "\\PC{0,300}") {
        let _ = simrenderer::parse(&text, "random.txt", &Options::default());
        let options = Options { lenient: true, ..Options::default() };
        let _ = simrenderer::parse(&text, "random.txt", &options);
    }

    #[test]
    fn random_lines_of_keywords_never_panic(lines in prop::collection::vec((keyword(), hostile_value()), 0..40)) {
        let text: String = lines.iter().map(|(k, v)| format!("{k} {v}\n")).collect();
        let options = Options { lenient: true, ..Options::default() };
        let p = simrenderer::parse(&text, "fuzz.txt", &options).map_err(|e| TestCaseError::fail(e.to_string()))?;
        for w in &p.warnings {
            assert_placed(&w.to_string(), &text)?;
        }
        render_tiny(p.scene)?;
        if let Err(e) = simrenderer::parse(&text, "fuzz.txt", &Options::default()) {
            assert_placed(&e.to_string(), &text)?;
        }
    }
}
