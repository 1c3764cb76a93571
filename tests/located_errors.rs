//! Errors inside entries of `[[shapes]]`, `[[lights]]`, `[[generate]]` and `[materials.*]`
//! point at the offending key or value of the right entry and name its field path: unknown
//! fields list the valid ones for the entry's type, wrong types say what was expected, a
//! misspelt `type` lists the allowed types (serde's internally tagged enums would report
//! every such error at the first entry of the array, with no field: see src/scene/tag.rs). An
//! error of a mesh's `.obj` file is placed on its own line and column, alike through both
//! scene formats.

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
fn a_mirror_pairs_opening_leaves_out_both_ends() {
    let scene = |opening: &str| {
        format!(
            "[image]\nwidth = 8\nheight = 6\n[camera]\nposition = [0, -8, 2]\nlook_at = [0, 0, 1]\n\n\
             [[shapes]]\ntype = \"mirror_pair\"\nopening = {opening}\nlength = 2\nheight = 2\n"
        )
    };
    assert!(parse(&scene("179.5"), "s.toml").is_ok());
    for opening in ["0", "180.0", "-30", "nan"] {
        assert_eq!(
            parse(&scene(opening), "s.toml").err().map(|e| e.to_string()),
            Some(format!(
                "s.toml:10:11: shapes[0].opening: must be a finite number in (0, 180), got {opening}"
            ))
        );
    }
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

/// An `.obj` file's error is placed on its line and on the column of the word at fault,
/// its numbers written as an OBJ file writes them, and said alike after a TOML mesh's
/// `file` and a SIMRenderer model's `file`; so are the model's warnings under `--lenient`.
#[test]
fn obj_errors_are_placed_on_their_word_through_both_scene_formats() {
    use lumiere::scene::simrenderer::{self, Options};
    use std::path::Path;
    let dir = crate::common::temp_dir("located-obj");
    let write = |name: &str, text: &str| crate::common::write_in(&dir, name, text);
    let obj = dir.join("m.obj").display().to_string();
    // `file` is on line 9, its value at column 8; the model's on line 2, at column 6.
    let toml = write(
        "s.toml",
        "[image]\nwidth = 8\nheight = 6\n[camera]\nposition = [0, -5, 1]\nlook_at = [0, 0, 0]\n\
         [[shapes]]\ntype = \"mesh\"\nfile = \"m.obj\"\n",
    );
    let lab = write("lab.txt", "model\nfile m.obj\nend\n");
    let toml_error = || lumiere::scene::load(Path::new(&toml)).unwrap_err().to_string();
    let lab_read = |lenient| {
        let options = Options {
            lenient,
            ..Options::default()
        };
        simrenderer::load(Path::new(&lab), &options)
    };
    let square = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let form = "a face's vertex is v, v/vt, v//vn or v/vt/vn, each a whole number";
    // Errors of both readers (SIMRenderer's in strict mode).
    for (text, said) in [
        (
            "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n".to_string(),
            "2:3: vertex 2: coordinates must be finite numbers in [-1e9, 1e9], got NaN 0 0".to_string(),
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 -inf 0.5 2\nf 1 2 3\n".to_string(),
            "3:5: vertex 3: coordinates must be finite numbers in [-1e9, 1e9], got 0 -inf 0.25 (x y z divided by w)"
                .to_string(),
        ),
        (
            format!("{square}v 1 1 x\n"),
            "4:7: vertex 4: `x` is not a number (written x y z, x y z w or x y z r g b)".to_string(),
        ),
        (
            "v 0 0 0 1 0 0\n  v 1 0 0\n".to_string(),
            "2:3: vertex 2: no colour (r g b), unlike vertex 1: give every vertex a colour or none".to_string(),
        ),
        (
            format!("{square}vt 0\nf 1 2 3\n"),
            "4:1: texture coordinates 1: 1 number, written u v".to_string(),
        ),
        (format!("{square}f 1 2 3/1/1/1\n"), format!("4:7: `3/1/1/1`: {form}")),
        (
            format!("{square}f 1 2 3/x\n"),
            format!("4:9: `3/x`: `x` is no index: {form}"),
        ),
        (
            format!("{square}vn 0 0 1\nf 1//1 2 3//1\n"),
            "5:8: 2 of the face's 3 vertices have a normal: give it to all of them or none".to_string(),
        ),
        (
            format!("{square}\tf 1 2\nf 1 2 3\n"),
            "4:2: f: a face needs at least 3 vertices (f v1 v2 v3 ...), got 2".to_string(),
        ),
        (
            format!("{square}f 1 2 9\n"),
            "4:7: f: vertex index 9, but the file has 3".to_string(),
        ),
        (
            format!("{square}\tusemtl\nf 1 2 3\n"),
            "4:2: material parse error".to_string(),
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 2 0 0\n  f 1 2 3\n".to_string(),
            "4:3: the face makes no triangle: its points are on one line".to_string(),
        ),
    ] {
        write("m.obj", &text);
        assert_eq!(
            toml_error(),
            format!("{toml}:9:8: shapes[0].file: {obj}:{said}"),
            "{text}"
        );
        let e = lab_read(false).err().map(|e| e.to_string());
        assert_eq!(e, Some(format!("{lab}:2:6: model.file: {obj}:{said}")), "{text}");
    }
    // A line element: refused in a TOML mesh, skipped with a warning in a model (in both
    // modes), on the keyword `l`.
    let line_element = "4:3: l: a line element (l) is no surface; only faces (f) are read";
    write("m.obj", &format!("{square}  l 1 2\nf 1 2 3\nl 2 3\n"));
    assert_eq!(
        toml_error(),
        format!("{toml}:9:8: shapes[0].file: {obj}:{line_element}")
    );
    let line_warning = format!(
        "{lab}:2:6: model.file: {obj}:{line_element}; the file's 2 line element(s) are skipped, as SIMRenderer's \
         model reader skips them"
    );
    for lenient in [false, true] {
        let warnings: Vec<String> = lab_read(lenient)
            .unwrap()
            .warnings
            .iter()
            .map(|w| w.to_string())
            .collect();
        assert_eq!(warnings, std::slice::from_ref(&line_warning), "lenient {lenient}");
    }
    // Under --lenient, a short face and a face with a texture index out of range are
    // warned of where they are (the short face's keyword, the index); an error that is no
    // statement drops the model, placed as in strict mode.
    write(
        "m.obj",
        &format!("{square}vt 0 0\n f 1 2\nf 1/1 2/1 3/2\nf 1/1 2/1 3/1\n"),
    );
    let warnings: Vec<String> = lab_read(true).unwrap().warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        warnings,
        [
            format!(
                "{lab}:2:6: model.file: {obj}:5:2: f: a face needs at least 3 vertices (f v1 v2 v3 ...), got 2; \
                 the file's 1 face(s) of fewer than 3 vertices are skipped and its others kept, as SIMRenderer's \
                 model reader skips them"
            ),
            format!(
                "{lab}:2:6: model.file: {obj}:6:13: f: texture index 2, but the file has 1; the file's 1 face(s) \
                 with a texture index out of range are kept without texture coordinates, as SIMRenderer's model \
                 reader keeps a face whose texture index passes the file's count"
            ),
        ]
    );
    write("m.obj", &format!("{square}f 1 2 3/1/1/1\n"));
    // (The scene, left without its only block, is then empty: a warning of its own follows.)
    let dropped = lab_read(true).unwrap().warnings[0].to_string();
    assert_eq!(
        dropped,
        format!("{lab}:2:6: model.file: {obj}:4:7: `3/1/1/1`: {form}; the model is dropped")
    );
}
