//! Errors inside entries of `[[shapes]]`, `[[lights]]`, `[[generate]]` and `[materials.*]`
//! point at the offending key or value of the right entry and name its field path: unknown
//! fields list the valid ones for the entry's type, wrong types say what was expected, a
//! misspelt `type` lists the allowed types (serde's internally tagged enums would report
//! every such error at the first entry of the array, with no field: see src/scene/tag.rs).

use lumiere::scene::parse;

/// A valid scene; each case breaks one line of it. Line numbers in the expected messages
/// count from `[image]` as line 1.
const GOOD: &str = r#"[image]
width = 16
height = 12
samples_per_pixel = 1

[camera]
position = [0, -8, 5]
look_at = [0, 1, 0]

[materials.red]
color = [1, 0, 0]

[[shapes]]
type = "plane"
point = [0, 0, 0]
normal = [0, 0, 1]

[[shapes]]
type = "sphere"
center = [0, 0, 1]
radius = 1
material = "red"

[[shapes]]
type = "torus"
center = [2, 0, 1]
major_radius = 1
minor_radius = 0.25

[[generate]]
kind = "spheres"
count = 10
min = [-1, -1, 0]
max = [1, 1, 1]
radius = [0.05, 0.1]

[[lights]]
type = "ambient"
color = [0.1, 0.1, 0.1]

[[lights]]
type = "spot"
position = [0, 0, 10]
direction = [0, 0, -1]
angle = 70
attenuation = { quadratic = 0.01 }

[[lights]]
type = "area"
shape = "window"
center = [0, 0, 8]
edge1 = [2, 0, 0]
edge2 = [0, 2, 0]
points = 4
"#;

/// The error message of the scene with the first `from` replaced by `to`.
fn error_after(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "{from:?} is not in the scene");
    parse(&GOOD.replacen(from, to, 1), "s.toml")
        .err()
        .unwrap_or_else(|| panic!("{to:?} was accepted"))
        .to_string()
}

#[test]
fn the_scene_is_valid() {
    let s = parse(GOOD, "s.toml").unwrap();
    assert_eq!((s.objects.len(), s.lights.len()), (13, 3));
}

#[test]
fn unknown_field_in_the_third_shape() {
    assert_eq!(
        error_after("minor_radius = 0.25", "minor_radius = 0.25\nminr_radius = 1"),
        "s.toml:29:1: shapes[2].minr_radius: unknown field `minr_radius`, expected one of \
         `center`, `axis`, `major_radius`, `minor_radius`, `material`, `name`, `transform`"
    );
}

#[test]
fn wrong_type_in_a_light() {
    assert_eq!(
        error_after("angle = 70", "angle = \"0.5\""),
        "s.toml:45:9: lights[1].angle: invalid type: string \"0.5\", expected a number"
    );
}

#[test]
fn wrong_array_length() {
    assert_eq!(
        error_after("center = [0, 0, 1]", "center = [1, 2]"),
        "s.toml:20:10: shapes[1].center: invalid length 2, expected an array of length 3"
    );
}

#[test]
fn too_long_an_array_is_refused_too() {
    assert_eq!(
        error_after("center = [0, 0, 1]", "center = [0, 0, 1, 7]"),
        "s.toml:20:10: shapes[1].center: invalid length 4, expected an array of length 3"
    );
    assert_eq!(
        error_after("color = [1, 0, 0]", "color = [1, 0, 0, 0, 0]"),
        "s.toml:11:9: materials.red.color: invalid length 5, expected an array of length 3"
    );
}

#[test]
fn wrong_type_inside_an_array_names_the_element() {
    assert_eq!(
        error_after("color = [1, 0, 0]", "color = [1, \"0\", 0]"),
        "s.toml:11:13: materials.red.color[1]: invalid type: string \"0\", expected a number"
    );
}

#[test]
fn misspelt_shape_type_lists_the_types() {
    assert_eq!(
        error_after("type = \"sphere\"", "type = \"sphear\""),
        "s.toml:19:8: shapes[1].type: must be \"plane\", \"rectangle\", \"disk\", \"sphere\", \
         \"box\", \"cylinder\", \"cone\", \"mirror_pair\", \"torus\", \"triangle\", \"tube\", \"mesh\", \"spherical_cap\" or \"lens\", \
         got \"sphear\""
    );
}

#[test]
fn misspelt_light_type_lists_the_types() {
    assert_eq!(
        error_after("type = \"spot\"", "type = \"spotlight\""),
        "s.toml:42:8: lights[1].type: must be \"ambient\", \"directional\", \"point\", \"spot\", \
         \"area\", \"linear_aperture\", \"rectangular_aperture\", \"elliptical_aperture\" or \
         \"aperture_mask\", got \"spotlight\""
    );
}

#[test]
fn missing_type_points_at_the_entry() {
    assert_eq!(
        error_after("type = \"torus\"\n", ""),
        "s.toml:24:1: shapes[2].type: missing; must be \"plane\", \"rectangle\", \"disk\", \
         \"sphere\", \"box\", \"cylinder\", \"cone\", \"mirror_pair\", \"torus\", \"triangle\", \
         \"tube\", \"mesh\", \"spherical_cap\" or \"lens\""
    );
    assert_eq!(
        error_after("type = \"torus\"", "type = 3"),
        "s.toml:25:8: shapes[2].type: must be \"plane\", \"rectangle\", \"disk\", \"sphere\", \
         \"box\", \"cylinder\", \"cone\", \"mirror_pair\", \"torus\", \"triangle\", \"tube\", \"mesh\", \"spherical_cap\" or \"lens\", \
         got integer"
    );
}

#[test]
fn missing_field_points_at_its_entry() {
    assert_eq!(
        error_after("radius = 1\n", ""),
        "s.toml:18:1: shapes[1]: missing field `radius`"
    );
}

#[test]
fn errors_in_generate_tables() {
    assert_eq!(
        error_after("count = 10", "count = 10\ndensity = 2"),
        "s.toml:33:1: generate[0].density: unknown field `density`, expected one of `kind`, \
         `count`, `seed`, `min`, `max`, `radius`, `materials`"
    );
    assert_eq!(
        error_after("radius = [0.05, 0.1]", "radius = [0.05]"),
        "s.toml:35:10: generate[0].radius: invalid length 1, expected an array of length 2"
    );
    assert_eq!(
        error_after("count = 10", "count = \"10\""),
        "s.toml:32:9: generate[0].count: invalid type: string \"10\", expected a whole number"
    );
}

#[test]
fn errors_in_inline_tables_and_area_lights() {
    assert_eq!(
        error_after("{ quadratic = 0.01 }", "{ quadric = 0.01 }"),
        "s.toml:46:17: lights[1].attenuation.quadric: unknown field `quadric`, expected one of \
         `constant`, `linear`, `quadratic`"
    );
    assert_eq!(
        error_after("points = 4", "points = -4"),
        "s.toml:54:10: lights[2].points: must be in [1, 100000], got -4"
    );
    assert_eq!(
        error_after("points = 4", "points = 4\nradius = 1\nsize = 2"),
        "s.toml:56:1: lights[2].size: unknown field `size`, expected one of `shape`, `center`, \
         `radius`, `start`, `end`, `edge1`, `edge2`, `points`, `placement`, `mode`, `color`, \
         `attenuation`"
    );
}

#[test]
fn errors_in_top_level_tables() {
    assert_eq!(
        error_after("[camera]", "[kamera]"),
        "s.toml:6:2: kamera: unknown field `kamera`, expected one of `image`, `camera`, \
         `render`, `conventions`, `caustics`, `materials`, `shapes`, `lights`, `generate`"
    );
    assert_eq!(
        error_after("height = 12", "height = 12.5"),
        "s.toml:3:10: image.height: invalid type: floating point `12.5`, expected a whole number"
    );
    // serde's Rust types are said in the file's words (a table); a whole number out of its
    // field's range, however large, gets the field's own range.
    assert_eq!(
        error_after(
            "[image]\nwidth = 16\nheight = 12\nsamples_per_pixel = 1\n",
            "image = 5\n"
        ),
        "s.toml:1:9: image: invalid type: integer `5`, expected a table"
    );
    assert_eq!(
        error_after("height = 12", "height = 99999999999999999999"),
        "s.toml:3:10: image.height: must be in [1, 16384] pixels, got 99999999999999999999"
    );
    // A real too large for a double is its field's out-of-range number, as written; a whole
    // number field given one is told it takes a whole number. Two of them on one line are
    // each read so, and the next one's place stays where the file has it.
    assert_eq!(
        error_after("radius = 1\n", "radius = 1e400\n"),
        "s.toml:21:10: shapes[1].radius: must be a finite number in (0, 1e9], got 1e400"
    );
    assert_eq!(
        error_after("angle = 70", "angle = -1_0e400"),
        "s.toml:45:9: lights[1].angle: must be a finite number in [0, 180], got -1_0e400"
    );
    assert_eq!(
        error_after("height = 12", "height = 1e400"),
        "s.toml:3:10: image.height: invalid type: floating point `1e400`, expected a whole number"
    );
    assert_eq!(
        error_after(
            "attenuation = { quadratic = 0.01 }",
            "attenuation = { linear = 1e999, quadratik = 0.01 }"
        ),
        "s.toml:46:33: lights[1].attenuation.quadratik: unknown field `quadratik`, expected one of `constant`, `linear`, `quadratic`"
    );
    // A seed takes every 64-bit unsigned value: its type's range is its own.
    assert_eq!(
        error_after("samples_per_pixel = 1", "samples_per_pixel = 1\nseed = -1"),
        "s.toml:5:8: image.seed: invalid value: integer `-1`, expected a whole number in [0, \
         18446744073709551615]"
    );
    // A key given twice is named where it is given again.
    assert_eq!(
        error_after("height = 12", "height = 12\nheight = 13"),
        "s.toml:4:1: TOML: duplicate key `height`: given first at line 3; a key is given once in its table"
    );
    // Quoted as TOML reads it: `"height"` is `height`.
    assert_eq!(
        error_after("height = 12", "height = 12\n\"height\" = 13"),
        "s.toml:4:1: TOML: duplicate key `\"height\"`: given first at line 3; a key is given once in its table"
    );
    // A missing top-level table has no place in the file: the file and the table are named
    // (more cases in scene_tables.rs).
    assert_eq!(
        error_after("[image]\nwidth = 16\nheight = 12\nsamples_per_pixel = 1\n", ""),
        "s.toml: the file has no [image] table"
    );
}

#[test]
fn numbers_out_of_range_are_shown_as_written_and_limits_short() {
    // The value as the file writes it, not reformatted (1e-7 is not 0.0000001, 1e300 not
    // 301 digits); the limits in their shorter form (1e9, not 1000000000).
    for (to, expected) in [
        (
            "radius = 1e-400",
            "s.toml:21:10: shapes[1].radius: must be a finite number in (0, 1e9], got 1e-400",
        ),
        (
            "radius = 1e300",
            "s.toml:21:10: shapes[1].radius: must be a finite number in (0, 1e9], got 1e300",
        ),
        (
            "radius = -1_000.50",
            "s.toml:21:10: shapes[1].radius: must be a finite number in (0, 1e9], got -1_000.50",
        ),
        (
            "radius = -inf",
            "s.toml:21:10: shapes[1].radius: must be a finite number in (0, 1e9], got -inf",
        ),
    ] {
        assert_eq!(error_after("radius = 1\n", &format!("{to}\n")), expected);
    }
    assert_eq!(
        error_after("angle = 70", "angle = 2E2"),
        "s.toml:45:9: lights[1].angle: must be a finite number in [0, 180], got 2E2"
    );
    assert_eq!(
        error_after("color = [1, 0, 0]", "color = [1, 0, 0]\nka = 1.0000001e0"),
        "s.toml:12:6: materials.red.ka: must be a finite number in [0, 1], got 1.0000001e0"
    );
}

#[test]
fn a_decimal_comma_is_named() {
    // TOML refuses `0,25`; the message says what was likely meant. A list is left alone.
    assert_eq!(
        error_after("minor_radius = 0.25", "minor_radius = 0,25"),
        "s.toml:28:17: TOML: unexpected key or value, expected newline, `#`; \"0,25\": a decimal takes a point, 0.25"
    );
    assert!(
        !error_after("center = [0, 0, 1]", "center = [0,0,1,]]").contains("decimal"),
        "a list is not a decimal"
    );
}

#[test]
fn bytes_that_are_not_utf8_are_placed_on_their_line_and_column() {
    let dir = crate::common::temp_dir("located-utf8");
    // A Latin-1 `è` in a TOML comment, and `é` in a SIMRenderer one; a UTF-8 `è` is read.
    let toml = GOOD.replacen("radius = 1\n", "radius = 1 # lumi\u{e8}re\n", 1);
    let latin1: Vec<u8> = toml.chars().map(|c| c as u32 as u8).collect();
    let simrenderer = b"camera\n  position 0 0 0 # cam\xe9ra\nend\n";
    for (name, bytes, place, byte) in [
        ("s.toml", &latin1[..], "21:18", "E8"),
        ("s.txt", &simrenderer[..], "2:23", "E9"),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let o = crate::common::lumiere(&[
            "render",
            path.to_str().unwrap(),
            "-o",
            dir.join("out.png").to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2));
        assert_eq!(
            String::from_utf8_lossy(&o.stderr),
            format!(
                "lumiere: error: {}:{place}: encoding: byte 0x{byte} is not UTF-8 (an accent saved as Latin-1 or Windows-1252 reads so); save the file as UTF-8\n",
                path.display()
            )
        );
    }
    assert!(!dir.join("out.png").exists());
    assert!(parse(&toml, "s.toml").is_ok());
}
