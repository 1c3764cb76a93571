//! Converting scenes between lumiere's TOML format and SIMRenderer's: the reference scene
//! and the course's figure scenes that both formats can say come back as the same scene
//! value and image; what SIMRenderer cannot say is refused by name; `lumiere convert` and
//! `lumiere figures --export-scenes` write what they say and nothing else.

use crate::common::*;
use lumiere::conventions::Conventions;
use lumiere::figures::files;
use lumiere::scene::simrenderer::{self, Options, differences};
use lumiere::scene::{self, Scene};

/// `scene` written as SIMRenderer and read back over its own conventions.
fn through_simrenderer(scene: &Scene) -> Result<(Scene, Vec<String>), String> {
    through_simrenderer_in(scene, "back.txt")
}

/// [`through_simrenderer`], the text read back as the file `file` (a texture's path is
/// relative to its folder).
fn through_simrenderer_in(scene: &Scene, file: &str) -> Result<(Scene, Vec<String>), String> {
    let written = simrenderer::to_simrenderer(scene, "test", "test").map_err(|e| e.to_string())?;
    let options = Options {
        lenient: false,
        conventions: scene.settings.conventions,
    };
    let back = simrenderer::parse(&written.text, file, &options).unwrap();
    assert_eq!(back.warnings, [], "{}", written.text);
    Ok((back.scene, written.notes))
}

/// `scene` written as TOML and read back.
fn through_toml(scene: &Scene) -> Scene {
    through_toml_in(scene, "back.toml", &[])
}

/// [`through_toml`], the text read back as the file `file`, the writer's notes `notes`.
fn through_toml_in(scene: &Scene, file: &str, notes: &[String]) -> Scene {
    let written = simrenderer::to_toml(scene, "test").unwrap();
    assert_eq!(written.notes, notes);
    scene::parse(&written.text, file).unwrap_or_else(|e| panic!("{e}\n{}", written.text))
}

fn pixels(scene: &Scene) -> Vec<u8> {
    render_small(scene, 32, 24, 1, 2).to_rgb8()
}

#[test]
fn the_reference_scene_comes_back_to_the_bit() {
    let original = scene("reference.toml");
    let (sim, notes) = through_simrenderer(&original).unwrap();
    assert_eq!(notes, Vec::<String>::new());
    assert_eq!(sim, original);
    let toml = through_toml(&sim);
    assert_eq!(toml, original);
    assert_eq!(pixels(&toml), pixels(&original));
}

#[test]
fn the_figure_scenes_both_formats_can_say_come_back_to_the_bit() {
    let sets = files::load(&repo("scenes/figures")).unwrap();
    let mut exact = Vec::new();
    let mut refused = Vec::new();
    for set in &sets {
        for f in &set.figures {
            let name = format!("{}/{}", set.name, f.stem);
            let file = repo(&format!("scenes/figures/{}/back.txt", set.name));
            match through_simrenderer_in(&f.scene, &file.display().to_string()) {
                Err(e) => refused.push((name, e)),
                Ok((back, notes)) if set.name == "prism" => {
                    // SIMRenderer's cube is axis-aligned: the turned block is a unit cube in
                    // a geometry block, the same box as a transformed shape.
                    assert_eq!(
                        differences(&f.scene, &back, 10),
                        ["objects[1] \"prism\" (box): shape"],
                        "{name}"
                    );
                    assert_eq!(notes.len(), 1, "{name}");
                    assert!(
                        notes[0].starts_with("objects[1] \"prism\" (box): SIMRenderer's cube is an axis-aligned cube")
                    );
                    assert_eq!(through_toml(&back), back, "{name}");
                }
                Ok((back, notes)) if name == "optique/04-lens" => {
                    // The arrow's head is a cone along -z written as SIMRenderer's cone
                    // between two points: its axis comes back within rounding.
                    assert_eq!(
                        (notes, differences(&f.scene, &back, 10)),
                        (
                            vec![
                                "objects[2] \"head\" (cone): its axis reads back within rounding, not to the bit"
                                    .to_string()
                            ],
                            vec!["objects[2] \"head\" (cone): shape".to_string()]
                        ),
                        "{name}"
                    );
                }
                Ok((back, notes)) => {
                    // A texture's image is written under the name the scene gives it, which
                    // the note asks to keep beside the written file.
                    let expected: Vec<String> = if name == "optique/05-textured-sphere" {
                        vec![
                            "materials[2] \"globe\": its images are named as the source names them: keep them in the same place beside the written file".to_string(),
                        ]
                    } else {
                        vec![]
                    };
                    assert_eq!(
                        (&notes, differences(&f.scene, &back, 10)),
                        (&expected, vec![]),
                        "{name}"
                    );
                    assert_eq!(back, f.scene, "{name}");
                    let file = repo(&format!("scenes/figures/{}/back.toml", set.name));
                    assert_eq!(
                        through_toml_in(&back, &file.display().to_string(), &expected),
                        f.scene,
                        "{name}"
                    );
                    exact.push(name);
                }
            }
        }
    }
    // Every figure of lighting, directional, attenuation, shading (but exponents above
    // SIMRenderer's 200) and optique (but the lens figure's cone), and the hard shadow.
    let count = |prefix: &str| exact.iter().filter(|n| n.starts_with(prefix)).count();
    assert_eq!(
        [
            count("lighting/"),
            count("directional/"),
            count("attenuation/"),
            count("shading/"),
            count("soft-shadows/"),
            count("optique/")
        ],
        [3, 4, 2, 21, 1, 4]
    );
    assert_eq!(exact.len(), 35);
    let reasons: Vec<(String, String)> = refused.iter().map(|(n, e)| (n.clone(), e.clone())).collect();
    let reason_of = |name: &str| &reasons.iter().find(|(n, _)| n == name).unwrap().1;
    assert_eq!(
        reason_of("spotlight/01-theta-70"),
        "cannot be written as SIMRenderer: lights[1] (spot): SIMRenderer has no spot light"
    );
    assert_eq!(
        reason_of("soft-shadows/02-soft-200"),
        "cannot be written as SIMRenderer: lights[1] (area): SIMRenderer has no area light"
    );
    assert_eq!(
        reason_of("light-shapes/03-window"),
        "cannot be written as SIMRenderer: lights[1] (area): SIMRenderer has no area light"
    );
    assert_eq!(
        reason_of("mirrors/01-opening-60-depth-01"),
        "cannot be written as SIMRenderer: objects[1] \"mirror A\" (rectangle): SIMRenderer has no rectangle (a mirror pair is two rectangles); objects[2] \"mirror B\" (rectangle): SIMRenderer has no rectangle (a mirror pair is two rectangles)"
    );
    assert_eq!(
        reason_of("shading/13-phong-n512"),
        "cannot be written as SIMRenderer: materials[2] \"sphere\": shininess 512 (SIMRenderer's is in [0, 200])"
    );
    assert_eq!(
        reason_of("caustics/03-ball-lens-1e3"),
        "cannot be written as SIMRenderer: caustics photons = 1000: SIMRenderer has no photon pass"
    );
    // 2 spot, 7 soft shadows, 3 light shapes, 13 mirrors, 4 shading, 6 caustics.
    assert_eq!(refused.len(), 35);
    // The same image, rendered, for one figure of each set that comes back whole.
    // And for the prism, whose block comes back as a transformed cube: the same bytes too.
    for name in [
        "lighting/03-ambient-directional",
        "directional/03-d-0-1--1",
        "attenuation/02-quadratic-0p01",
        "shading/24-metal-0p5",
        "prism/06-depth-05",
    ] {
        let (set, stem) = name.split_once('/').unwrap();
        let f = sets
            .iter()
            .find(|s| s.name == set)
            .unwrap()
            .figures
            .iter()
            .find(|f| f.stem == stem)
            .unwrap();
        let back = through_toml(&through_simrenderer(&f.scene).unwrap().0);
        assert_eq!(pixels(&back), pixels(&f.scene), "{name}");
    }
}

#[test]
fn simrenderer_files_come_back_through_toml_and_simrenderer() {
    for name in ["keywords.txt", "aliases.txt", "reference.txt"] {
        let path = repo("tests/fixtures/simrenderer").join(name);
        let original = simrenderer::load(&path, &Options::default()).unwrap().scene;
        assert_eq!(through_toml(&original), original, "{name}");
        if name == "reference.txt" {
            let (back, notes) = through_simrenderer(&original).unwrap();
            assert_eq!((back, notes), (original, vec![]), "{name}");
        } else {
            // The model's faces have an OpenGL material (its own ambient and specular
            // colours), which only a model's .mtl can give in SIMRenderer: a model is
            // written as its triangles, so the writer refuses it by name.
            assert_eq!(
                through_simrenderer(&original).unwrap_err(),
                "cannot be written as SIMRenderer: materials[4] \"model#12/default\": its own ambient_color or specular_color (SIMRenderer gives terms their own colours only in a model's .mtl materials)",
                "{name}"
            );
        }
    }
}

/// The refusal of `to_simrenderer` for the TOML scene `extra` adds to a minimal one.
fn refusal(extra: &str) -> String {
    let text = format!("[image]\nwidth = 8\nheight = 6\n[camera]\nposition = [0, -5, 1]\nlook_at = [0, 0, 0]\n{extra}");
    let scene = scene::parse(&text, "t.toml").unwrap_or_else(|e| panic!("{e}"));
    simrenderer::to_simrenderer(&scene, "t.toml", "t")
        .unwrap_err()
        .to_string()
}

#[test]
fn what_simrenderer_cannot_say_is_refused_by_name() {
    let prefix = "cannot be written as SIMRenderer: ";
    for (extra, reason) in [
        (
            "[[lights]]\ntype = \"spot\"\nposition = [0, 0, 5]\ndirection = [0, 0, -1]\nangle = 60\n",
            "lights[0] (spot): SIMRenderer has no spot light",
        ),
        (
            "[[lights]]\ntype = \"area\"\nshape = \"sphere\"\ncenter = [0, 0, 5]\nradius = 1\npoints = 4\n",
            "lights[0] (area): SIMRenderer has no area light",
        ),
        (
            "[[shapes]]\ntype = \"rectangle\"\nname = \"wall\"\ncorner = [0, 0, 0]\nedge1 = [1, 0, 0]\nedge2 = [0, 1, 0]\n",
            "objects[0] \"wall\" (rectangle): SIMRenderer has no rectangle (a mirror pair is two rectangles)",
        ),
        (
            "[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\ntransform = { matrix = [[1, 0.5, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]] }\n",
            "objects[0] \"sphere#0\" (sphere): its transform shears (a general matrix); SIMRenderer's geometry block scales, rotates and translates",
        ),
        (
            "[conventions]\nsample_position = \"regular\"\n",
            "conventions sample_position regular: SIMRenderer places every sample at the pixel's top_left corner, its center, or at random (with 1 sample, center is the same ray)",
        ),
        (
            "[conventions]\nnear = 5\nfar = 2\n",
            "conventions far 2 below near 5: SIMRenderer's far_clipping_plane is at least its near_clipping_plane",
        ),
        (
            "[render]\ndiffuse = false\n",
            "render shading (ambient true, diffuse false, specular Blinn): SIMRenderer's reflexion_algorithm keeps one term, ambient and diffuse (no_specular), or all three",
        ),
        (
            "[render]\nambient = false\ndiffuse = false\nspecular = \"none\"\n",
            "render shading (ambient false, diffuse false, specular None): SIMRenderer's reflexion_algorithm keeps one term, ambient and diffuse (no_specular), or all three",
        ),
        (
            "[render]\nshadows = false\n",
            "render shadows = false: SIMRenderer always casts shadow rays",
        ),
        (
            "[render]\nbackground = [0, 0, 0.5]\n",
            "render background [0.0, 0.0, 0.5]: SIMRenderer's background is black",
        ),
        (
            "[materials.shiny]\nshininess = 300\n",
            "materials[1] \"shiny\": shininess 300 (SIMRenderer's is in [0, 200])",
        ),
        (
            "[materials.\" padded\"]\n",
            "materials[1] \" padded\": SIMRenderer cannot read a name that starts with a blank (SIMRenderer removes it)",
        ),
        (
            "[materials.\"two\\nlines\"]\n",
            "materials[1] \"two\\nlines\": SIMRenderer cannot read a name with a line break",
        ),
        (
            "[materials.\"\"]\n",
            "materials[1] \"\": SIMRenderer cannot read an empty name",
        ),
    ] {
        assert_eq!(refusal(extra), format!("{prefix}{reason}"), "{extra}");
    }
    // A camera angle outside SIMRenderer's range.
    let text = "[image]\nwidth = 8\nheight = 6\n[camera]\nposition = [0, -5, 1]\nlook_at = [0, 0, 0]\nvfov = 175\n";
    let scene = scene::parse(text, "t.toml").unwrap();
    assert_eq!(
        simrenderer::to_simrenderer(&scene, "t.toml", "t")
            .unwrap_err()
            .to_string(),
        format!("{prefix}camera.vfov 175: SIMRenderer's angle is in [10, 170] degrees")
    );
    // Every reason at once, in order.
    let e = refusal(
        "[render]\nshadows = false\n[[lights]]\ntype = \"spot\"\nposition = [0, 0, 5]\ndirection = [0, 0, -1]\nangle = 60\n",
    );
    assert_eq!(
        e,
        format!(
            "{prefix}render shadows = false: SIMRenderer always casts shadow rays; lights[0] (spot): SIMRenderer has no spot light"
        )
    );
}

#[test]
fn a_nested_geometry_cannot_be_said_in_toml() {
    let text = "primitive\ngeometry\nrotation 0 0 45\ngeometry\nscale 1 2 1\nsphere\nend\nend\nend\nend\n";
    let scene = simrenderer::parse(text, "lab.txt", &Options::default()).unwrap().scene;
    assert_eq!(
        simrenderer::to_toml(&scene, "lab.txt").unwrap_err().to_string(),
        "cannot be written as the TOML format: objects[0] \"sphere#0\" (sphere): a transformed shape in a transform (nested geometry blocks); a TOML shape has one transform"
    );
    // SIMRenderer says it back.
    let (back, notes) = through_simrenderer(&scene).unwrap();
    assert_eq!((back, notes), (scene, vec![]));
}

#[test]
fn a_chapter_scene_says_which_conventions_simrenderer_changes() {
    let written = simrenderer::to_simrenderer(&scene("reference.toml"), "scenes/reference.toml", "reference").unwrap();
    let head: Vec<&str> = written.text.lines().take(12).collect();
    assert_eq!(
        head,
        [
            "# SIMRenderer scene written by lumiere from scenes/reference.toml.",
            "#",
            "# That scene follows conventions SIMRenderer does not have; SIMRenderer, and lumiere",
            "# reading this file, render it with SIMRenderer's:",
            "#   ray_origin: eye in that scene, near_plane in SIMRenderer",
            "#   shadow_filter: color in that scene, kt_color in SIMRenderer",
            "#   transmission: kt in that scene, kt_color_entering in SIMRenderer",
            "#   refracting: transparent in that scene, closed in SIMRenderer",
            "#   total_internal_reflection: reflected in that scene, dropped in SIMRenderer",
            "#   default_highlight: plastic in that scene, metal in SIMRenderer",
            "# lumiere renders it as that scene with the options --conventions chapter",
            "",
        ]
    );
    // The sampling, the clipping planes and the adaptive threshold are said in the file.
    for line in [
        "far_clipping_plane  Infinity",
        "pixel_coordinate    random",
        "sampling            4",
        "# lumiere: adaptive_threshold 0.25",
    ] {
        assert!(written.text.lines().any(|l| l == line), "{line}");
    }
    // Read as SIMRenderer reads it: SIMRenderer's conventions but where the file says.
    let read = simrenderer::parse(&written.text, "r.txt", &Options::default())
        .unwrap()
        .scene;
    let mut expected = Conventions::SIMRENDERER;
    expected.sample_position = lumiere::conventions::SamplePosition::Jittered;
    expected.far = f64::INFINITY;
    assert_eq!(read.settings.conventions, expected);
    // Another mix of switches is named switch by switch.
    let mut s = scene("reference.toml");
    s.set_conventions(Conventions::SIMRENDERER);
    s.settings.conventions.local_weight = lumiere::conventions::LocalWeight::Remaining;
    let written = simrenderer::to_simrenderer(&s, "x", "x").unwrap();
    assert!(written.text.contains(
        "#   local_weight: remaining in that scene, one in SIMRenderer\n# lumiere renders it as that scene with the options --convention local_weight=remaining\n"
    ));
    // SIMRenderer's own conventions need no comment.
    s.set_conventions(Conventions::SIMRENDERER);
    let written = simrenderer::to_simrenderer(&s, "x", "x").unwrap();
    assert!(
        written
            .text
            .starts_with("# SIMRenderer scene written by lumiere from x.\n\ncamera\n")
    );
}

#[test]
fn lumiere_convert_writes_what_reads_back_or_nothing() {
    let dir = temp_dir("simrenderer-convert");
    let path = |name: &str| dir.join(name).display().to_string();
    let run = |args: &[&str]| {
        let out = lumiere(args);
        (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let reference = repo("scenes/reference.toml").display().to_string();
    // TOML to SIMRenderer by the output's name, and back to TOML over the chapter's
    // conventions: the same scene.
    assert_eq!(
        run(&["convert", &reference, "-o", &path("r.txt")]),
        (Some(0), String::new())
    );
    assert_eq!(
        run(&[
            "convert",
            &path("r.txt"),
            "-o",
            &path("r.toml"),
            "--conventions",
            "chapter"
        ]),
        (Some(0), String::new())
    );
    assert_eq!(scene::load(&dir.join("r.toml")).unwrap(), scene("reference.toml"));
    // --to overrides the name; same-format conversion is allowed. A name that would have the
    // file read in the other format (or not at all) is warned about.
    assert_eq!(
        run(&["convert", &reference, "-o", &path("r.sim"), "--to", "toml"]),
        (
            Some(0),
            format!(
                "lumiere: warning: {}: its name does not say the toml format (TOML files end in .toml): read it with --format toml\n",
                path("r.sim")
            )
        )
    );
    assert!(std::fs::read_to_string(dir.join("r.sim")).unwrap().contains("[image]"));
    assert_eq!(
        run(&["convert", &reference, "-o", &path("s.toml"), "--to", "simrenderer"]),
        (
            Some(0),
            format!(
                "lumiere: warning: {}: its name does not say the simrenderer format (TOML files end in .toml): read it with --format simrenderer\n",
                path("s.toml")
            )
        )
    );
    let sim = std::fs::read_to_string(dir.join("s.toml")).unwrap();
    assert!(matches!(
        scene::detect(std::path::Path::new("s.txt"), &sim),
        Ok(scene::Format::SimRenderer)
    ));
    // A refusal: exit 2, nothing written.
    let spot = repo("scenes/figures/spotlight/01-theta-70.toml").display().to_string();
    let (code, err) = run(&["convert", &spot, "-o", &path("spot.txt")]);
    assert_eq!(code, Some(2));
    assert_eq!(
        err.trim(),
        format!(
            "lumiere: error: {}: cannot be written as SIMRenderer: lights[1] (spot): SIMRenderer has no spot light; nothing written",
            path("spot.txt")
        )
    );
    assert!(!dir.join("spot.txt").exists());
    // What does not come back to the bit is named.
    let prism = repo("scenes/figures/prism/02-depth-01.toml").display().to_string();
    let (code, err) = run(&["convert", &prism, "-o", &path("prism.txt")]);
    assert_eq!(code, Some(0));
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 2, "{err}");
    assert!(lines[0].starts_with(&format!(
        "lumiere: warning: {}: objects[1] \"prism\" (box): SIMRenderer's cube is an axis-aligned cube",
        path("prism.txt")
    )));
    assert_eq!(
        lines[1],
        format!(
            "lumiere: warning: {}: reads back as another scene in objects[1] \"prism\" (box): shape",
            path("prism.txt")
        )
    );
    // A SIMRenderer file with an error, and with --lenient.
    let lab = dir.join("lab.txt");
    std::fs::write(&lab, "raytracer\nsampling 2000\nend\nprimitive\nsphere\nend\nend\n").unwrap();
    let (code, err) = run(&["convert", &path("lab.txt"), "-o", &path("lab.toml")]);
    assert_eq!(code, Some(2), "{err}");
    assert!(!dir.join("lab.toml").exists());
    let (code, err) = run(&["convert", &path("lab.txt"), "-o", &path("lab.toml"), "--lenient"]);
    assert_eq!(code, Some(0));
    assert!(err.starts_with(&format!(
        "lumiere: warning: {}:2:10: raytracer.sampling:",
        path("lab.txt")
    )));
    assert!(dir.join("lab.toml").exists());
    // An image's name is refused before anything is read: exit 2, nothing written.
    for name in ["lab.png", "lab.exr", "lab.jpg"] {
        let (code, err) = run(&["convert", &path("lab.txt"), "-o", &path(name)]);
        let ext = name.rsplit('.').next().unwrap();
        assert_eq!(
            (code, err.trim()),
            (
                Some(2),
                format!(
                    "lumiere: error: {}: .{ext} names an image, and convert writes a scene file: name it .txt (SIMRenderer) or .toml (lumiere); `lumiere render` writes the image",
                    path(name)
                )
                .as_str()
            )
        );
        assert!(!dir.join(name).exists());
    }
    // The input is never the output.
    let (code, err) = run(&["convert", &path("lab.txt"), "-o", &path("lab.txt")]);
    assert_eq!(
        (code, err.trim()),
        (
            Some(2),
            format!(
                "lumiere: error: {}: the output would overwrite the input",
                path("lab.txt")
            )
            .as_str()
        )
    );
}

#[test]
fn figures_export_scenes_in_either_format() {
    let dir = temp_dir("simrenderer-export");
    let out = dir.join("out");
    let scenes = repo("scenes/figures");
    let run = |format: &str| {
        let o = lumiere(&[
            "figures",
            "lighting",
            "mirrors",
            "--scenes",
            scenes.to_str().unwrap(),
            "--export-scenes",
            out.to_str().unwrap(),
            "--format",
            format,
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).unwrap()
    };
    let text = run("simrenderer");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 15, "{text}");
    assert_eq!(
        lines[0],
        format!(
            "lighting       3 scenes written, 0 skipped  {}",
            out.join("lighting").display()
        )
    );
    assert!(lines[1].starts_with(
        "skipped mirrors/01-opening-60-depth-01: cannot be written as SIMRenderer: objects[1] \"mirror A\" (rectangle)"
    ));
    assert_eq!(
        lines[14],
        "mirrors        0 scenes written, 13 skipped  (no folder made)"
    );
    assert!(!out.join("mirrors").exists());
    // A file where the folder should be: refused by its option before anything is written.
    let file = dir.join("file.txt");
    std::fs::write(&file, "").unwrap();
    let o = lumiere(&[
        "figures",
        "lighting",
        "--scenes",
        scenes.to_str().unwrap(),
        "--export-scenes",
        file.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr).trim(),
        format!(
            "lumiere: error: --export-scenes: {} is a file, not a folder",
            file.display()
        )
    );
    assert!(o.stdout.is_empty());
    // Each scene written reads back as its figure's, over the figure's conventions.
    let sets = files::load(&scenes).unwrap();
    for f in &sets.iter().find(|s| s.name == "lighting").unwrap().figures {
        let path = out.join("lighting").join(format!("{}.txt", f.stem));
        let options = Options {
            lenient: false,
            conventions: Conventions::CHAPTER,
        };
        assert_eq!(simrenderer::load(&path, &options).unwrap().scene, f.scene, "{}", f.stem);
    }
    // TOML: the figure's own file.
    run("toml");
    let file = "lighting/01-ambient.toml";
    assert_eq!(
        std::fs::read(out.join(file)).unwrap(),
        std::fs::read(scenes.join(file)).unwrap()
    );
    assert_eq!(std::fs::read_dir(out.join("mirrors")).unwrap().count(), 13);
}
