//! The command line as a user meets it: bad scene files and bad paths give a clear error
//! naming the file, line, column and field, exit code 2 (bad input) or 1 (work failed), never
//! a panic, and never a half-written output. Every exit code case: tests/exit_codes.rs.

use crate::common::*;
use std::fs;

/// A small valid scene; tests break one line of it.
const GOOD: &str = r#"[image]
width = 16
height = 12
samples_per_pixel = 1

[camera]
position = [0, -8, 5]
look_at = [0, 1, 0]

[materials.glass]
color = [1, 1, 1]
kt = 0.5
n = 1.5

[[shapes]]
type = "sphere"
center = [0, 0, 1]
radius = 1
material = "glass"

[[shapes]]
type = "cylinder"
base = [2, 0, 0]
axis = [0, 0, 1]
height = 1
radius = 0.5

[[lights]]
type = "spot"
position = [0, 0, 10]
direction = [0, 0, -1]
angle = 70
"#;

/// Writes `text` as a scene, renders it, and returns (exit code, stderr with the scene named
/// `scene.toml`, output existed).
fn run_scene(name: &str, text: &str) -> (i32, String, bool) {
    run_scene_with(name, text, &[])
}

/// [`run_scene`] with more arguments for `render`.
fn run_scene_with(name: &str, text: &str, args: &[&str]) -> (i32, String, bool) {
    let dir = temp_dir(name);
    let scene = dir.join("scene.toml");
    fs::write(&scene, text).unwrap();
    let out = dir.join("out.png");
    let mut all = vec![
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
    ];
    all.extend_from_slice(args);
    let o = lumiere(&all);
    // Messages name the scene as `scene.toml`, without the test's temporary directory.
    let stderr = String::from_utf8_lossy(&o.stderr).replace(&format!("{}/", dir.display()), "");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let leftovers = fs::read_dir(&dir).unwrap().count();
    let existed = out.exists();
    // Only the scene (and a complete output) may be in the directory: no temporary files.
    assert_eq!(
        leftovers,
        1 + existed as usize,
        "temporary files left in {}",
        dir.display()
    );
    (o.status.code().unwrap(), stderr, existed)
}

/// Breaks the scene by replacing `from` with `to`, expects exit 2 and every `needles` in stderr.
fn expect_bad(name: &str, from: &str, to: &str, needles: &[&str]) {
    assert!(GOOD.contains(from), "{from}");
    let (code, stderr, existed) = run_scene(name, &GOOD.replacen(from, to, 1));
    assert_eq!(code, 2, "{stderr}");
    assert!(!existed);
    for n in needles {
        assert!(stderr.contains(n), "expected {n:?} in: {stderr}");
    }
}

#[test]
fn the_good_scene_renders() {
    let (code, stderr, existed) = run_scene("good", GOOD);
    assert_eq!(code, 0, "{stderr}");
    assert!(existed);
}

#[test]
fn syntax_error_names_the_line() {
    expect_bad(
        "syntax",
        "radius = 1\n",
        "radius = = 1\n",
        &["scene.toml:18:10", "TOML"],
    );
}

#[test]
fn unknown_field_is_an_error() {
    expect_bad(
        "unknown",
        "radius = 1\n",
        "radius = 1\nradus = 2\n",
        &[
            "scene.toml:19:1: shapes[0].radus: unknown field `radus`, expected one of `center`, `radius`, `material`, `name`, `transform`\n",
        ],
    );
}

#[test]
fn misspelt_light_type_lists_the_types() {
    expect_bad(
        "light-type",
        "type = \"spot\"",
        "type = \"spott\"",
        &[
            "scene.toml:29:8: lights[0].type: must be \"ambient\", \"directional\", \"point\", \"spot\", \"area\", \"linear_aperture\", \"rectangular_aperture\", \"elliptical_aperture\" or \"aperture_mask\", got \"spott\"\n",
        ],
    );
}

#[test]
fn negative_radius() {
    expect_bad(
        "negative",
        "radius = 1\n",
        "radius = -1\n",
        &["scene.toml:18:10", "shapes[0].radius", "(0,", "got -1"],
    );
}

#[test]
fn zero_length_axis() {
    expect_bad(
        "axis",
        "axis = [0, 0, 1]",
        "axis = [0, 0, 0]",
        &["scene.toml:24:8", "shapes[1].axis", "non-zero length"],
    );
}

#[test]
fn nan_is_rejected() {
    expect_bad(
        "nan",
        "position = [0, 0, 10]",
        "position = [0, nan, 10]",
        &["lights[0].position", "finite"],
    );
}

#[test]
fn spot_angle_outside_0_180() {
    expect_bad(
        "theta",
        "angle = 70",
        "angle = 190",
        &["scene.toml:32:9", "lights[0].angle", "[0, 180]", "got 190"],
    );
}

#[test]
fn vfov_has_one_range_in_every_message() {
    // 0 is refused as negative and too wide angles are, with the one range (0, 179].
    for (vfov, got) in [("0", "0"), ("-5", "-5"), ("180", "180"), ("inf", "inf")] {
        expect_bad(
            &format!("vfov{got}"),
            "look_at = [0, 1, 0]\n",
            &format!("look_at = [0, 1, 0]\nvfov = {vfov}\n"),
            &[&format!(
                "scene.toml:9:8: camera.vfov: must be a finite number in (0, 179], got {got}\n"
            )],
        );
    }
    let (code, stderr, _) = run_scene(
        "vfov179",
        &GOOD.replacen("look_at = [0, 1, 0]\n", "look_at = [0, 1, 0]\nvfov = 179\n", 1),
    );
    assert_eq!(code, 0, "{stderr}");
}

#[test]
fn refractive_index_must_be_positive() {
    expect_bad(
        "ior",
        "n = 1.5",
        "n = 0",
        &["scene.toml:13:5", "materials.glass.n", "(0, 10]"],
    );
    expect_bad("ior-neg", "n = 1.5", "n = -1.3", &["materials.glass.n", "got -1.3"]);
}

#[test]
fn absurd_resolution_is_refused() {
    expect_bad("huge", "width = 16", "width = 100000", &["image.width", "[1, 16384]"]);
    expect_bad(
        "spp",
        "samples_per_pixel = 1",
        "samples_per_pixel = 0",
        &["image.samples_per_pixel", "[1, 1024]", "got 0"],
    );
}

/// The good scene with `text` appended after its last line.
fn with_more(text: &str) -> String {
    format!("{GOOD}{text}")
}

/// Expects exit 2 and exactly `line` (plus a newline) as the error on stderr.
fn expect_error(name: &str, scene: &str, args: &[&str], line: &str) {
    let (code, stderr, existed) = run_scene_with(name, scene, args);
    assert_eq!((code, existed), (2, false), "{stderr}");
    assert_eq!(stderr, format!("lumiere: error: {line}\n"));
}

#[test]
fn depth_limit() {
    let (code, stderr, existed) = run_scene_with("depth-flag", GOOD, &["--depth", "100000"]);
    assert_eq!((code, existed), (2, false), "{stderr}");
    assert!(
        stderr.starts_with(
            "error: invalid value '100000' for '--depth <DEPTH>': must be in [1, 64] (1 = no secondary rays), got 100000\n"
        ),
        "{stderr}"
    );
    let scene = GOOD.replace("[materials.glass]", "[render]\ndepth = 100000\n\n[materials.glass]");
    expect_error(
        "depth-file",
        &scene,
        &[],
        "scene.toml:11:9: render.depth: must be in [1, 64] (1 = no secondary rays), got 100000",
    );
}

#[test]
fn pixel_and_sample_limits() {
    let scene = GOOD.replace("width = 16\nheight = 12", "width = 16384\nheight = 16384");
    let too_many = "width x height must be at most 33554432 pixels, got 16384 x 16384 = 268435456";
    expect_error(
        "pixels-file",
        &scene,
        &[],
        &format!("scene.toml:2:9: image.width: {too_many}"),
    );
    expect_error(
        "pixels-flags",
        GOOD,
        &["--width", "16384", "--height", "16384"],
        &format!("--width/--height: {too_many}"),
    );
    expect_error(
        "spp-file",
        &GOOD.replace("samples_per_pixel = 1", "samples_per_pixel = 2025"),
        &[],
        "scene.toml:4:21: image.samples_per_pixel: must be in [1, 1024], got 2025",
    );
}

#[test]
fn any_sample_count_in_range_renders() {
    let six = GOOD.replace("samples_per_pixel = 1", "samples_per_pixel = 6");
    assert_eq!(run_scene("spp-file-6", &six), (0, String::new(), true));
    assert_eq!(
        run_scene_with("spp-flag-2", GOOD, &["--spp", "2"]),
        (0, String::new(), true)
    );
    for bad in ["0", "1025"] {
        let (code, stderr, existed) = run_scene_with("spp-flag-out", GOOD, &["--spp", bad]);
        assert_eq!((code, existed), (2, false), "{stderr}");
        let message = format!("must be in [1, 1024], got {bad}");
        assert!(
            stderr.starts_with(&format!("error: invalid value '{bad}' for '--spp <SPP>': {message}\n")),
            "{stderr}"
        );
        expect_error(
            "spp-file-out",
            &GOOD.replace("samples_per_pixel = 1", &format!("samples_per_pixel = {bad}")),
            &[],
            &format!("scene.toml:4:21: image.samples_per_pixel: {message}"),
        );
    }
}

#[test]
fn object_count_limit_fails_at_validation() {
    // Validation adds up the counts before a single object is generated: this fails at
    // once instead of allocating four million objects first.
    let table = |count: &str| {
        with_more(&format!(
            "\n[[generate]]\nkind = \"spheres\"\ncount = {count}\nmin = [-1, -1, 0]\nmax = [1, 1, 1]\nradius = [0.05, 0.1]\n"
        ))
    };
    expect_error(
        "objects-total",
        &table("4000000"),
        &[],
        "scene.toml:36:9: generate[0].count: the scene would hold 4000002 objects with this table, at most 4000000 are allowed",
    );
    expect_error(
        "objects-huge",
        &table("18446744073709551615"),
        &[],
        "scene.toml:36:9: generate[0].count: must be in [1, 4000000], got 18446744073709551615",
    );
}

#[test]
fn light_count_limit() {
    let scene = with_more(&"[[lights]]\ntype = \"ambient\"\n".repeat(10_000));
    expect_error(
        "lights",
        &scene,
        &[],
        "scene.toml:28:1: lights: at most 10000 lights, got 10001",
    );
}

/// An area light entry with `fields` (one `key = value` a line).
fn area_light(fields: &str) -> String {
    format!("\n[[lights]]\ntype = \"area\"\n{fields}\n")
}

#[test]
fn light_point_limits() {
    expect_error(
        "points",
        &with_more(&area_light(
            "shape = \"sphere\"\ncenter = [0, 0, 5]\nradius = 1\npoints = 100001",
        )),
        &[],
        "scene.toml:39:10: lights[1].points: must be in [1, 100000], got 100001",
    );
    // 100 lights of 100 000 points are allowed; the 101st passes the total.
    let full = "[[lights]]\ntype = \"area\"\nshape = \"sphere\"\ncenter = [0, 0, 5]\nradius = 1\npoints = 100000\n";
    expect_error(
        "total-points",
        &with_more(&full.repeat(101)),
        &[],
        "scene.toml:638:10: lights[101].points: the scene would hold 10100000 light points with this light, at most 10000000 are allowed",
    );
}

#[test]
fn degenerate_area_lights_and_rectangles() {
    expect_error(
        "rectangle",
        &with_more("\n[[shapes]]\ntype = \"rectangle\"\ncorner = [0, 0, 0]\nedge1 = [1, 0, 0]\nedge2 = [2, 0, 0]\n"),
        &[],
        "scene.toml:38:9: shapes[2].edge2: must not be parallel to edge1 [1.0, 0.0, 0.0], got [2.0, 0.0, 0.0]",
    );
    expect_error(
        "tube",
        &with_more(&area_light(
            "shape = \"tube\"\nstart = [0, 0, 5]\nend = [0, 0, 5]\npoints = 4",
        )),
        &[],
        "scene.toml:38:7: lights[1].end: must differ from start [0.0, 0.0, 5.0] (a tube of zero length is a point: use a sphere of radius 0)",
    );
    let window = |e1: &str, e2: &str| {
        with_more(&area_light(&format!(
            "shape = \"window\"\ncenter = [0, 0, 5]\nedge1 = {e1}\nedge2 = {e2}\npoints = 4"
        )))
    };
    expect_error(
        "window-zero",
        &window("[0, 0, 0]", "[0, 1, 0]"),
        &[],
        "scene.toml:38:9: lights[1].edge1: must have a non-zero length, got [0.0, 0.0, 0.0]",
    );
    expect_error(
        "window-parallel",
        &window("[1, 0, 0]", "[-2, 0, 0]"),
        &[],
        "scene.toml:39:9: lights[1].edge2: must not be parallel to edge1 [1.0, 0.0, 0.0], got [-2.0, 0.0, 0.0]",
    );
}

#[test]
fn unknown_material_lists_the_defined_ones() {
    expect_bad(
        "material",
        "material = \"glass\"",
        "material = \"glas\"",
        &["shapes[0].material", "glass"],
    );
}

#[test]
fn missing_scene_file() {
    let o = lumiere(&["render", "no/such/scene.toml", "-o", "/tmp/x.png"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no/such/scene.toml: cannot read"));
}

#[test]
fn bad_output_paths_leave_nothing() {
    let dir = temp_dir("outpath");
    let scene = dir.join("scene.toml");
    fs::write(&scene, GOOD).unwrap();
    let s = scene.to_str().unwrap();
    // Missing directory: refused before rendering.
    let o = lumiere(&["render", s, "-o", dir.join("nope/out.png").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    // The output path is an existing directory: refused before rendering (exit 2), nothing
    // left behind.
    let blocked = dir.join("taken.png");
    fs::create_dir(&blocked).unwrap();
    let o = lumiere(&["render", s, "-o", blocked.to_str().unwrap(), "--quiet"]);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("taken.png: the output is a directory"));
    let names: Vec<_> = fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 2, "{names:?}");
    // Not a PNG name, or the input itself: refused.
    let o = lumiere(&["render", s, "-o", s]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(fs::read_to_string(&scene).unwrap(), GOOD);
}

#[test]
fn overrides_are_checked() {
    let o = lumiere(&["render", "scenes/reference.toml", "-o", "/tmp/x.png", "--spp", "1025"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("'--spp <SPP>': must be in [1, 1024], got 1025"));
    let o = lumiere(&["render", "scenes/reference.toml", "-o", "/tmp/x.png", "--threads", "0"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn render_overrides_and_stats() {
    let dir = temp_dir("stats");
    let out = dir.join("r.png");
    let o = lumiere(&[
        "render",
        repo("scenes/reference.toml").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "40",
        "--height",
        "30",
        "--spp",
        "1",
        "--stats",
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(0));
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (40, 30));
    // One camera ray per pixel sample: 40 x 30 x 1.
    assert!(String::from_utf8_lossy(&o.stdout).contains("camera rays   1200\n"));
}

#[test]
fn compare_reports_differences_and_exits_by_tolerance() {
    let dir = temp_dir("compare");
    let a = dir.join("a.png");
    let b = dir.join("b.png");
    // 2 x 1 images; the second pixel differs by (3, 0, 4).
    let write = |p: &std::path::Path, px: &[u8]| {
        fs::write(p, lumiere::film::encode_png(2, 1, px).unwrap()).unwrap();
    };
    write(&a, &[10, 20, 30, 100, 100, 100]);
    write(&b, &[10, 20, 30, 103, 100, 96]);
    let (sa, sb) = (a.to_str().unwrap(), b.to_str().unwrap());
    let heat = dir.join("heat.png");
    let o = lumiere(&["compare", sa, sb, "--json", "--heatmap", heat.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["metrics"]["max"], 4);
    assert_eq!(json["metrics"]["beyond_tolerance"], 1);
    assert!((json["metrics"]["rms"].as_f64().unwrap() - (25.0f64 / 6.0).sqrt()).abs() < 1e-12);
    let heat = image::open(&heat).unwrap().to_rgb8();
    assert_eq!(heat.get_pixel(0, 0).0, [0, 0, 0]);
    assert_ne!(heat.get_pixel(1, 0).0, [0, 0, 0]);
    // Within a tolerance of 4 levels: success.
    let o = lumiere(&["compare", sa, sb, "--tolerance", "4"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stdout).contains("max difference     4 levels"));
    // Different sizes, or not an image: bad input.
    let c = dir.join("c.png");
    fs::write(&c, lumiere::film::encode_png(1, 1, &[0, 0, 0]).unwrap()).unwrap();
    assert_eq!(lumiere(&["compare", sa, c.to_str().unwrap()]).status.code(), Some(2));
    assert_eq!(lumiere(&["compare", sa, "Cargo.toml"]).status.code(), Some(2));
}

#[test]
fn completions_and_help_for_every_command() {
    let o = lumiere(&["completions", "bash"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stdout).contains("_lumiere()"));
    assert_eq!(lumiere(&["completions", "tcsh"]).status.code(), Some(2));
    let help = lumiere(&["--help"]);
    let text = String::from_utf8_lossy(&help.stdout);
    // Every subcommand's help has examples.
    for cmd in text
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
    {
        let name = cmd.split_whitespace().next().unwrap();
        if name == "help" {
            continue;
        }
        let sub = lumiere(&[name, "--help"]);
        assert_eq!(sub.status.code(), Some(0), "{name}");
        assert!(
            String::from_utf8_lossy(&sub.stdout).contains("Example"),
            "{name} --help has no example"
        );
    }
}

#[test]
fn accel_help_gives_the_crossover_used() {
    let n = lumiere::accel::CROSSOVER;
    let o = lumiere(&["render", "--help"]);
    assert_eq!(o.status.code(), Some(0));
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(
        help.contains(&format!(
            "- auto:   The BVH from {n} bounded objects on, else the linear scan\n"
        )),
        "{help}"
    );
    assert!(!help.contains("CROSSOVER"), "{help}");
    // The README states the same number.
    let readme = std::fs::read_to_string(repo("README.md")).unwrap();
    assert!(
        readme
            .replace('\n', " ")
            .contains(&format!("the BVH from {n} bounded objects on")),
        "README.md does not give the crossover {n}"
    );
}

/// The usage line(s) of a help or error text: from `Usage: ` to the first blank line.
fn usage(text: &str) -> String {
    let start = text.find("Usage: ").unwrap_or_else(|| panic!("no usage in {text}"));
    text[start..].split("\n\n").next().unwrap().to_string()
}

#[test]
fn usage_lines_say_what_is_required() {
    // render: an image (-o), layers (--layers) or both; -o alone is not required.
    let render_usage = "Usage: lumiere render [OPTIONS] <--output <OUTPUT>|--layers <OUT.exr|DIR/>> <SCENE>";
    let help = lumiere(&["render", "--help"]);
    assert_eq!(usage(&String::from_utf8_lossy(&help.stdout)), render_usage);
    let scene = repo("scenes/reference.toml");
    let o = lumiere(&["render", scene.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.starts_with(
            "error: the following required arguments were not provided:\n  <--output <OUTPUT>|--layers <OUT.exr|DIR/>>\n"
        ),
        "{err}"
    );
    assert_eq!(
        usage(&err),
        "Usage: lumiere render <--output <OUTPUT>|--layers <OUT.exr|DIR/>> <SCENE>"
    );
    // diagnose: a scene and images, or --list; the same usage in the help and the errors.
    let diagnose_usage =
        "Usage: lumiere diagnose [OPTIONS] <SCENE> <IMAGE>...\n       lumiere diagnose --list [--json]";
    let help = lumiere(&["diagnose", "--help"]);
    assert_eq!(usage(&String::from_utf8_lossy(&help.stdout)), diagnose_usage);
    for args in [
        &["diagnose"][..],
        &["diagnose", scene.to_str().unwrap()],
        &["diagnose", "--list", "x"],
    ] {
        let o = lumiere(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert_eq!(usage(&String::from_utf8_lossy(&o.stderr)), diagnose_usage, "{args:?}");
    }
}

#[test]
fn verbose_notes_go_to_stderr_and_json_stats_to_stdout() {
    let dir = temp_dir("verbose");
    let out = dir.join("v.png");
    let scene = repo("scenes/reference.toml");
    let o = lumiere(&[
        "-v",
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "20",
        "--height",
        "10",
        "--spp",
        "1",
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("7 objects, 2 lights; 20 x 10 pixels"), "{stderr}");
    assert!(stderr.contains("wrote"));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["rays"]["camera"], 200);
    // --quiet and --verbose together are refused.
    assert_eq!(
        lumiere(&["-q", "-v", "render", "x.toml", "-o", "y.png"]).status.code(),
        Some(2)
    );
}

#[test]
fn counts_of_one_are_said_in_the_singular() {
    let dir = temp_dir("singular");
    let scene = dir.join("one.toml");
    fs::write(
        &scene,
        "[image]\nwidth = 4\nheight = 3\n[camera]\nposition = [0, -5, 0]\nlook_at = [0, 0, 0]\n\
         [[lights]]\ntype = \"point\"\nposition = [0, -5, 5]\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n",
    )
    .unwrap();
    let (scene, out) = (scene.to_str().unwrap(), dir.join("one.png"));
    let o = lumiere(&["-v", "render", scene, "-o", out.to_str().unwrap(), "--stats"]);
    assert_eq!(o.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains(": 1 object, 1 light; 4 x 3 pixels"), "{stderr}");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("intersection core: linear over 1 object, "), "{stdout}");
    let lab = dir.join("one.txt");
    let o = lumiere(&["-v", "convert", scene, "-o", lab.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("one.txt: simrenderer scene of 1 object and 1 light, from "),
        "{stderr}"
    );
}

/// Every `.rs` file under `dir`, recursively.
fn rust_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn the_library_holds_no_command_line() {
    // Option parsing, printing, progress bars and signal handling belong to the binary
    // (src/main.rs and src/cli/); the library's modules return data.
    let mut files = Vec::new();
    rust_files(&repo("src"), &mut files);
    let library: Vec<_> = files
        .iter()
        .filter(|p| !p.starts_with(repo("src/cli")) && **p != repo("src/main.rs"))
        .collect();
    assert!(library.len() > 40, "{library:?}");
    for path in library {
        let text = fs::read_to_string(path).unwrap();
        for (i, line) in text.lines().enumerate() {
            let code = line.trim_start();
            if code.starts_with("//") {
                continue;
            }
            for word in [
                "clap::",
                "use clap",
                "indicatif",
                "ctrlc",
                "signal_hook",
                "println!",
                "print!(",
            ] {
                assert!(!code.contains(word), "{}:{}: {line}", path.display(), i + 1);
            }
        }
    }
    let lib = fs::read_to_string(repo("src/lib.rs")).unwrap();
    assert!(!lib.contains("mod cli"), "src/lib.rs declares the command line");
    assert!(
        fs::read_to_string(repo("src/main.rs"))
            .unwrap()
            .contains("\nmod cli;\n")
    );
}

#[test]
fn a_byte_not_utf8_is_located_in_either_format() {
    let dir = temp_dir("cli-latin1");
    let out = dir.join("out.png");
    // "matériau" saved as Latin-1 in a comment, on line 2 of each.
    for (name, bytes) in [
        ("scene.toml", &b"[image]\n# mat\xe9riau\nwidth = 4\n"[..]),
        ("lab.txt", &b"camera\n# mat\xe9riau\nend\n"[..]),
    ] {
        let path = dir.join(name);
        fs::write(&path, bytes).unwrap();
        let o = lumiere(&["render", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "-q"]);
        assert_eq!(o.status.code(), Some(2));
        assert_eq!(
            String::from_utf8_lossy(&o.stderr).trim(),
            format!(
                "lumiere: error: {}:2:6: encoding: byte 0xE9 is not UTF-8 (an accent saved as Latin-1 or Windows-1252 reads so); save the file as UTF-8",
                path.display()
            )
        );
        assert!(!out.exists());
    }
}
