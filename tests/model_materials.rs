//! A SIMRenderer model's materials: its `.mtl` libraries, read as SIMRenderer reads them
//! (docs/simrenderer.md, "model"). Each face's term has its own colour and no coefficient
//! (SIMRenderer's OpenGL material), so at a point lit straight down and seen straight down
//! (`N.L = N.H = 1`) under a white ambient and a white directional light, the pixel is
//! `Ka + Kd + Ks` under `blinn`.
//!
//! The model: three unit-wide squares side by side in z = 0, x in [-3, -1], [-1, 1] and
//! [1, 3]; the first before any `usemtl`, the second `usemtl red`, the third `usemtl absent`.

use crate::common::{lumiere, lumiere_ok, temp_dir, write_in};
use lumiere::scene::SceneError;
use lumiere::scene::simrenderer::{self, Parsed};
use lumiere::shape::Shape;
use std::path::Path;

const OBJ: &str = "mtllib parts.mtl\n\
v -3 -1 0\nv -1 -1 0\nv -1 1 0\nv -3 1 0\nv 1 -1 0\nv 1 1 0\nv 3 -1 0\nv 3 1 0\n\
f 1 2 3 4\nusemtl red\nf 2 5 6 3\nusemtl absent\nf 5 7 8 6\n";

/// The lines before the first `newmtl` change the library's `default` material (the faces
/// before any `usemtl`); of two materials named `red`, the first is kept.
const MTL: &str = "# parts\nKd 0 0 1\n\
newmtl red\nKa 0.25 0 0\nKd 0.5 0.25 0\nKs 0.125 0.125 0\nNs 10\nillum 2\n\
newmtl red\nKd 0 1 0\n";

/// The scene file, the camera straight above `x` on the axis y = 0.
fn lab(x: f64, extra: &str) -> String {
    format!(
        "camera\nposition {x} 0 5\nlook_at {x} 0 0\nup 0 1 0\nend\n\
         viewport\nwidth 21\nheight 21\nend\n\
         raytracer\nreflexion_algorithm blinn\nend\n\
         ambient_light\ncolor 1 1 1\nend\n\
         directional_light\ncolor 1 1 1\norientation 0 0 -1\nend\n\
         model\nfile parts.obj\n{extra}end\n"
    )
}

/// The SIMRenderer file `lab`, read strictly or under `--lenient`.
fn load_lab(lab: &str, lenient: bool) -> Result<Parsed, SceneError> {
    let options = simrenderer::Options {
        lenient,
        ..Default::default()
    };
    simrenderer::load(Path::new(lab), &options)
}

/// The warnings of a read file, as printed.
fn warnings_of(parsed: &Parsed) -> Vec<String> {
    parsed.warnings.iter().map(|w| w.to_string()).collect()
}

/// The middle pixel of the render of the scene file `scene` (written in `dir`).
fn middle(dir: &Path, scene: &str, args: &[&str]) -> [u8; 3] {
    let png = dir.join(format!(
        "{}.png",
        Path::new(scene).file_stem().unwrap().to_str().unwrap()
    ));
    let mut all = vec!["render", scene, "-o", png.to_str().unwrap(), "-q"];
    all.extend_from_slice(args);
    lumiere_ok(&all);
    image::open(&png).unwrap().to_rgb8().get_pixel(10, 10).0
}

#[test]
fn each_face_takes_its_usemtl_material() {
    let dir = temp_dir("model-materials");
    write_in(&dir, "parts.obj", OBJ);
    write_in(&dir, "parts.mtl", MTL);
    // The library's default: Ka 0.2, Kd (0, 0, 1), Ks 0.2 (0.2 as a 32-bit float,
    // 0.20000000298): (0.4, 0.4, 1.4) clamped, 102 102 255.
    let default = write_in(&dir, "default.txt", &lab(-2.0, ""));
    assert_eq!(middle(&dir, &default, &[]), [102, 102, 255]);
    // red (the first of the name): (0.25 + 0.5 + 0.125, 0.25 + 0.125, 0) = (0.875, 0.375, 0):
    // 223.1, 95.6, 0.
    let red = write_in(&dir, "red.txt", &lab(0.0, ""));
    assert_eq!(middle(&dir, &red, &[]), [223, 96, 0]);
    // A name no library has: SIMRenderer's default OpenGL material, Ka 0.1, Kd (0.3, 0.7,
    // 0.3), Ks 0.05: (0.45, 0.85, 0.45), 114.75 and 216.75; a warning names it.
    let absent = write_in(&dir, "absent.txt", &lab(2.0, ""));
    assert_eq!(middle(&dir, &absent, &[]), [115, 217, 115]);
    let out = lumiere(&["render", &absent, "-o", dir.join("w.png").to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(
            "parts.obj: no material library of the model has the material \"absent\"; its faces get SIMRenderer's default OpenGL material (ambient 0.1, diffuse (0.3, 0.7, 0.3), specular 0.05, shininess 5)"
        ),
        "{stderr}"
    );
    // `convert` writes the model's materials into TOML (ka = kd = ks = 1, the colours its
    // own): the TOML scene renders the same bytes, every pixel, off the highlight's centre
    // too (red's exponent Ns 10).
    for scene in [&default, &red, &absent] {
        let toml = dir.join(format!(
            "{}.toml",
            Path::new(scene).file_stem().unwrap().to_str().unwrap()
        ));
        lumiere_ok(&["convert", scene, "-o", toml.to_str().unwrap(), "-q"]);
        let text = std::fs::read_to_string(&toml).unwrap();
        let from_lab = dir.join("lab.png");
        let from_toml = dir.join("toml.png");
        lumiere_ok(&["render", scene, "-o", from_lab.to_str().unwrap(), "-q"]);
        lumiere_ok(&[
            "render",
            toml.to_str().unwrap(),
            "-o",
            from_toml.to_str().unwrap(),
            "-q",
        ]);
        assert_eq!(
            std::fs::read(&from_lab).unwrap(),
            std::fs::read(&from_toml).unwrap(),
            "{text}"
        );
    }
    // probe names the face's material and its own colours.
    let probed = lumiere_ok(&["probe", &red, "--pixel", "10,10"]);
    assert!(
        probed.contains(
            "      material \"model#0/red\" has its own colours (SIMRenderer's OpenGL material), ambient colour C_a (0.250000, 0.000000, 0.000000), specular colour C_s (0.125000, 0.125000, 0.000000)\n"
        ),
        "{probed}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&lumiere_ok(&["probe", &red, "--pixel", "10,10", "--json"])).unwrap();
    let own = &json["samples"][0]["ray"]["hit"]["own_colors"];
    assert_eq!(own["material"], "model#0/red", "{json}");
    assert_eq!(own["ambient"], serde_json::json!([0.25, 0.0, 0.0]));
    assert_eq!(own["specular"], serde_json::json!([0.125, 0.125, 0.0]));
    let red_toml = std::fs::read_to_string(dir.join("red.toml")).unwrap();
    assert!(
        red_toml.contains(
            "[materials.\"model#0/red\"]\ncolor = [0.5, 0.25, 0]\nka = 1\nkd = 1\nks = 1\nshininess = 10\nkr = 0\nkt = 0\nn = 1\nambient_color = [0.25, 0, 0]\nspecular_color = [0.125, 0.125, 0]\n"
        ),
        "{red_toml}"
    );
}

#[test]
fn a_model_without_library_takes_the_library_default() {
    let dir = temp_dir("model-materials-none");
    write_in(&dir, "parts.obj", &OBJ.replace("mtllib parts.mtl\n", ""));
    // Every face: Ka 0.2, Kd (0.3, 0.7, 0.3), Ks 0.2 as 32-bit floats: (0.7, 1.1, 0.7),
    // 178.5 + (a hair: 0.3 and 0.2 round up as floats) and 255. The absent name gets the
    // OpenGL default as before.
    let default = write_in(&dir, "default.txt", &lab(-2.0, ""));
    assert_eq!(middle(&dir, &default, &[]), [179, 255, 179]);
    let red = write_in(&dir, "red.txt", &lab(0.0, ""));
    assert_eq!(middle(&dir, &red, &[]), [115, 217, 115]);
}

#[test]
fn a_diffuse_image_gives_the_term_its_texel() {
    let dir = temp_dir("model-materials-image");
    // A 3 x 3 image: its top row red, green, blue, the rest white.
    let mut img = image::RgbImage::from_pixel(3, 3, image::Rgb([255, 255, 255]));
    for (x, c) in [[255, 0, 0], [0, 255, 0], [0, 0, 255]].into_iter().enumerate() {
        img.put_pixel(x as u32, 0, image::Rgb(c));
    }
    // The model, its library and image in a folder of their own beside the scene.
    let models = dir.join("models");
    std::fs::create_dir(&models).unwrap();
    img.save(models.join("grid.png")).unwrap();
    write_in(
        &models,
        "square.obj",
        "mtllib looks.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl tiled\nf 1/1 2/2 3/3 4/4\n",
    );
    write_in(
        &models,
        "looks.mtl",
        "newmtl tiled\nKa 0 0 0\nKs 0 0 0\nmap_Kd grid.png\n",
    );
    // Seen at (0.5, -0.5): texture coordinates (0.75, 0.25), the texel of column
    // floor(0.75 x 2) = 1 and row floor(0.25 x 2) = 0 from the top (green), or of row
    // floor((1 - 0.25) x 2) = 1 (white) with the origin at the bottom left.
    let scene = |format: &str| {
        lab(0.5, format)
            .replace(
                "position 0.5 0 5\nlook_at 0.5 0 0",
                "position 0.5 -0.5 5\nlook_at 0.5 -0.5 0",
            )
            .replace("parts.obj", "models/square.obj")
    };
    let top = write_in(&dir, "top.txt", &scene(""));
    assert_eq!(middle(&dir, &top, &[]), [0, 255, 0]);
    let bottom = write_in(&dir, "bottom.txt", &scene("uv_format origin_uv_bottom_left\n"));
    assert_eq!(middle(&dir, &bottom, &[]), [255, 255, 255]);
    // In TOML, the image is named from the scene's folder, and the render is the same.
    let toml = dir.join("bottom.toml");
    lumiere_ok(&["convert", &bottom, "-o", toml.to_str().unwrap(), "-q"]);
    let text = std::fs::read_to_string(&toml).unwrap();
    assert!(
        text.contains("texture_kd = \"models/grid.png\"\nuv_format = \"origin_uv_bottom_left\"\n"),
        "{text}"
    );
    assert_eq!(middle(&dir, toml.to_str().unwrap(), &[]), [255, 255, 255]);
}

#[test]
fn a_library_line_in_error_is_located() {
    let dir = temp_dir("model-materials-errors");
    write_in(&dir, "parts.obj", OBJ);
    write_in(&dir, "parts.mtl", &MTL.replace("Kd 0.5 0.25 0", "Kd 2 0.25 0"));
    let red = write_in(&dir, "red.txt", &lab(0.0, ""));
    let png = dir.join("red.png");
    let out = lumiere(&["render", &red, "-o", png.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let library = dir.join("parts.mtl").display().to_string();
    assert!(
        stderr.contains(&format!(
            "red.txt:21:6: model.file: {library}:5:4: Kd: each channel must be in [0, 1], got 2 0.25 0"
        )),
        "{stderr}"
    );
    assert!(!png.exists());
    // Under --lenient, SIMRenderer's way: the line is skipped, the value before it kept
    // (the library default's diffuse (0.3, 0.7, 0.3)): (0.25 + 0.3 + 0.125, 0.7 + 0.125,
    // 0.3) = (0.675, 0.825, 0.3), 172.1, 210.4, 76.5 (0.3 a hair above as a float: 77).
    assert_eq!(middle(&dir, &red, &["--lenient"]), [172, 210, 77]);
    // An image that does not read: the term keeps its colour under --lenient.
    write_in(&dir, "parts.mtl", &MTL.replace("Ns 10", "Ns 10\nmap_Kd gone.png"));
    let out = lumiere(&["render", &red, "-o", png.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!("{library}:8: map_Kd: ")) && stderr.contains("gone.png: cannot read the texture"),
        "{stderr}"
    );
    assert_eq!(middle(&dir, &red, &["--lenient"]), [223, 96, 0]);
    // A uv_format SIMRenderer does not have.
    let sideways = write_in(&dir, "sideways.txt", &lab(0.0, "uv_format sideways\n"));
    let out = lumiere(&["render", &sideways, "-o", png.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(
            "sideways.txt:22:11: model.uv_format: must be one of default (0), origin_uv_top_left (1), origin_uv_bottom_left (2), got \"sideways\""
        ),
        "{stderr}"
    );
    // A library that does not read, or is not a .mtl file.
    for (line, said) in [
        ("mtllib gone.mtl", "mtllib \"gone.mtl\": cannot read it"),
        (
            "mtllib parts.obj",
            "mtllib \"parts.obj\": a material library is a .mtl file",
        ),
    ] {
        write_in(&dir, "parts.obj", &OBJ.replace("mtllib parts.mtl", line));
        let out = lumiere(&["render", &red, "-o", png.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(&format!("parts.obj:1: {said}")), "{stderr}");
        // Skipped under --lenient: no library, every face the library default.
        assert_eq!(middle(&dir, &red, &["--lenient"]), [115, 217, 115]);
    }
}

#[test]
fn the_toml_colours_are_checked() {
    let dir = temp_dir("model-materials-toml");
    let scene = |extra: &str| {
        format!(
            "[image]\nwidth = 8\nheight = 6\n[camera]\nposition = [0, -5, 1]\nlook_at = [0, 0, 0]\n\
             [materials.lamp]\n{extra}\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"lamp\"\n"
        )
    };
    for (extra, said) in [
        ("ambient_color = [0, 1.5, 0]", "materials.lamp.ambient_color"),
        (
            "specular_color = [0.5, 0.5, 0.5]\nm = 1",
            "materials.lamp.m: shapes the specular colour m S + (1 - m), which specular_color gives: give one of them",
        ),
    ] {
        let path = write_in(&dir, "lamp.toml", &scene(extra));
        let out = lumiere(&["render", &path, "-o", dir.join("x.png").to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(said), "{stderr}");
    }
}

/// SIMRenderer's model reader holds a file's numbers as 32-bit floats (`SVertex`): the
/// vertices, normals and texture coordinates are those floats.
#[test]
fn a_models_numbers_are_32_bit_floats() {
    let dir = temp_dir("model-materials-floats");
    write_in(
        &dir,
        "parts.obj",
        "v 0.1 0 0\nv 1 0.3 0\nv 0 1 0.7\nvt 0.1 0.2\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n",
    );
    let red = write_in(&dir, "red.txt", &lab(0.0, ""));
    let scene = lumiere::scene::load(Path::new(&red)).unwrap();
    let Shape::SmoothTriangle(t) = &scene.objects[0].shape else {
        panic!("{:?}", scene.objects[0].shape)
    };
    let points = t.triangle.points();
    assert_eq!(points[0].x, 0.10000000149011612);
    assert_eq!(points[1].y, 0.30000001192092896);
    assert_eq!(points[2].z, 0.699999988079071);
    assert_eq!(t.uvs[0], [0.10000000149011612, 0.20000000298023224]);
}

/// A face that makes no triangle (collinear corners) is an error; under --lenient it is
/// skipped and the model's other triangles kept, as SIMRenderer's model reader skips it.
#[test]
fn a_flat_face_is_skipped_under_lenient() {
    let dir = temp_dir("model-materials-flat");
    write_in(
        &dir,
        "parts.obj",
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n",
    );
    let red = write_in(&dir, "red.txt", &lab(0.0, ""));
    let out = lumiere(&["render", &red, "-o", dir.join("x.png").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("parts.obj:5:1: the face makes no triangle"), "{stderr}");
    let parsed = load_lab(&red, true).unwrap();
    assert_eq!(parsed.scene.objects.len(), 1);
    let Shape::Triangle(t) = &parsed.scene.objects[0].shape else {
        panic!("{:?}", parsed.scene.objects[0].shape)
    };
    assert_eq!(t.points()[2], glam::DVec3::Y);
    assert!(
        parsed.warnings[0]
            .message
            .ends_with("; the 1 triangle(s) that make none are skipped, as SIMRenderer skips them"),
        "{:?}",
        parsed.warnings
    );
}

/// SIMRenderer's model reader skips a line element (`l`) without a word, and a face of
/// fewer than 3 vertices with a message: lumiere warns at the first line element in both
/// modes, refuses a short face on its line and column, and under --lenient skips it and
/// keeps the model's other faces.
#[test]
fn line_elements_and_short_faces_are_skipped_as_simrenderer_skips_them() {
    let dir = temp_dir("model-materials-skips");
    write_in(&dir, "parts.mtl", MTL);
    let obj = dir.join("parts.obj").display().to_string();
    // The three squares, the last red too (no warning of a missing material), with a line
    // element on line 11 and a second on line 13.
    let with_lines = OBJ
        .replace("usemtl absent\n", "")
        .replace("usemtl red\n", "l 1 2 3\nusemtl red\n  l 2 5\n");
    let red = write_in(&dir, "red.txt", &lab(0.0, ""));
    let line_warning = format!(
        "{red}:21:6: model.file: {obj}:11:1: l: a line element (l) is no surface; only faces (f) are read; \
         the file's 2 line element(s) are skipped, as SIMRenderer's model reader skips them"
    );
    // Line elements: the model's 3 squares (6 triangles), one warning, in strict mode.
    write_in(&dir, "parts.obj", &with_lines);
    let parsed = load_lab(&red, false).unwrap();
    assert_eq!(parsed.scene.objects.len(), 6);
    let warnings = warnings_of(&parsed);
    assert_eq!(warnings, std::slice::from_ref(&line_warning));
    // A 2-vertex face on line 14: refused in strict mode on its line and column, naming the form.
    write_in(&dir, "parts.obj", &with_lines.replace("  l 2 5\n", "  l 2 5\nf 2 5\n"));
    let e = load_lab(&red, false).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!("{red}:21:6: model.file: {obj}:14:1: f: a face needs at least 3 vertices (f v1 v2 v3 ...), got 2")
    );
    // Under --lenient: skipped, the other faces kept; the red square renders as without it.
    let parsed = load_lab(&red, true).unwrap();
    assert_eq!(parsed.scene.objects.len(), 6);
    let warnings = warnings_of(&parsed);
    assert_eq!(
        warnings,
        [
            line_warning,
            format!(
                "{red}:21:6: model.file: {obj}:14:1: f: a face needs at least 3 vertices (f v1 v2 v3 ...), got 2; \
                 the file's 1 face(s) of fewer than 3 vertices are skipped and its others kept, as SIMRenderer's \
                 model reader skips them"
            )
        ]
    );
    assert_eq!(middle(&dir, &red, &["--lenient"]), [223, 96, 0]);
}

/// A face with a vertex index past the file's count, which SIMRenderer's model reader skips
/// (`SPolygonOBJ.buildVertexList` leaves it no vertex, `SModelOBJLoader.load` counts it in
/// error): refused in strict mode on its line and column; under --lenient skipped with the
/// model's other faces kept. A texture index past the count keeps the face without texture
/// coordinates, as SIMRenderer keeps it.
#[test]
fn a_face_with_an_index_out_of_range_is_skipped_under_lenient() {
    let dir = temp_dir("model-materials-indices");
    write_in(&dir, "parts.mtl", MTL);
    let obj = dir.join("parts.obj").display().to_string();
    // The three squares, the last red too, and on line 13 a triangle of vertex 9 of 8.
    let squares = OBJ.replace("usemtl absent\n", "");
    let past = squares.replace("f 2 5 6 3\n", "f 2 5 6 3\nf 2 5 9\n");
    write_in(&dir, "parts.obj", &past);
    let red = write_in(&dir, "red.txt", &lab(0.0, ""));
    let e = load_lab(&red, false).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!("{red}:21:6: model.file: {obj}:13:7: f: vertex index 9, but the file has 8")
    );
    let vertex_warning = format!(
        "{red}:21:6: model.file: {obj}:13:7: f: vertex index 9, but the file has 8; the file's 1 face(s) \
         with a vertex index out of range are skipped and its others kept, as SIMRenderer's model reader \
         skips a face whose vertex index passes the file's count"
    );
    let parsed = load_lab(&red, true).unwrap();
    assert_eq!(parsed.scene.objects.len(), 6);
    let warnings = warnings_of(&parsed);
    assert_eq!(warnings, std::slice::from_ref(&vertex_warning));
    assert_eq!(middle(&dir, &red, &["--lenient"]), [223, 96, 0]);
    // The red square's face with texture index 2 of 1 (the `vt` on line 15): kept, flat.
    write_in(
        &dir,
        "parts.obj",
        &format!("{}vt 0 0\n", past.replace("f 2 5 6 3\n", "f 2/1 5/1 6/1 3/2\n")),
    );
    let e = load_lab(&red, false).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!("{red}:21:6: model.file: {obj}:12:17: f: texture index 2, but the file has 1")
    );
    let parsed = load_lab(&red, true).unwrap();
    assert_eq!(parsed.scene.objects.len(), 6);
    assert!(
        parsed
            .scene
            .objects
            .iter()
            .all(|o| matches!(o.shape, Shape::Triangle(_))),
        "{:?}",
        parsed.scene.objects
    );
    let warnings = warnings_of(&parsed);
    assert_eq!(
        warnings,
        [
            vertex_warning,
            format!(
                "{red}:21:6: model.file: {obj}:12:17: f: texture index 2, but the file has 1; the file's 1 face(s) \
                 with a texture index out of range are kept without texture coordinates, as SIMRenderer's model \
                 reader keeps a face whose texture index passes the file's count"
            )
        ]
    );
    assert_eq!(middle(&dir, &red, &["--lenient"]), [223, 96, 0]);
}

/// SIMRenderer's model reader reads a face's index without its sign (`SFace` splits its
/// words on `-`), so `-3` is vertex 3; lumiere reads it as OBJ does, counting back from the
/// last vertex read, and warns in both modes at the first such face.
#[test]
fn a_negative_index_is_read_as_obj_reads_it_with_a_warning() {
    let dir = temp_dir("model-materials-relative");
    write_in(&dir, "parts.mtl", MTL);
    let obj = dir.join("parts.obj").display().to_string();
    // Vertices 1 to 3 far off to the side, 4 to 6 a triangle around the origin: line 9 is
    // (4 5 6) as OBJ reads it, (3 2 1) as SIMRenderer does; line 10 (1 2 3) and (1 2 4).
    write_in(
        &dir,
        "parts.obj",
        "mtllib parts.mtl\nv 5 5 0\nv 6 5 0\nv 5 6 0\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\n\
         usemtl red\nf -3 -2 -1\nf 1 2 -4\n",
    );
    let red = write_in(&dir, "red.txt", &lab(0.0, ""));
    let warning = format!(
        "{red}:21:6: model.file: {obj}:9:3: f: vertex index -3 counts back from the last vertex read (a relative \
         index); SIMRenderer's model reader reads an index without its sign (-3 as 3), so its image of this model \
         differs from lumiere's, which reads the file's 2 face(s) with a negative index as OBJ defines them"
    );
    for lenient in [false, true] {
        let parsed = load_lab(&red, lenient).unwrap();
        let warnings = warnings_of(&parsed);
        assert_eq!(warnings, std::slice::from_ref(&warning), "lenient {lenient}");
        let Shape::Triangle(t) = &parsed.scene.objects[0].shape else {
            panic!("{:?}", parsed.scene.objects[0].shape)
        };
        assert_eq!(
            t.points(),
            [
                glam::DVec3::new(-1.0, -1.0, 0.0),
                glam::DVec3::new(1.0, -1.0, 0.0),
                glam::DVec3::Y
            ]
        );
    }
    // The middle pixel is in the triangle (4 5 6), red.
    assert_eq!(middle(&dir, &red, &[]), [223, 96, 0]);
}
