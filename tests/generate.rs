//! `[[generate]]` tables: valid tables add their objects; every bad value is a located error
//! (file, line, column, field, allowed range) and exit code 2 on the command line, never a
//! panic.

use crate::common::*;
use lumiere::scene::parse;

const BASE: &str = "[image]\nwidth = 40\nheight = 30\n\n[camera]\nposition = [0, -16, 8]\nlook_at = [0, 0, 0]\n\n[materials.red]\ncolor = [1, 0, 0]\n\n[[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n\n";

/// A scene with one generate table whose lines are `table` (lines 17 on of the file).
fn with_table(table: &str) -> String {
    format!("{BASE}[[generate]]\n{table}\n")
}

const GOOD: &str = "kind = \"mixed\"\ncount = 50\nseed = 3\nmin = [-1, -1, 0]\nmax = [1, 1, 1]\nradius = [0.05, 0.1]\nmaterials = [\"red\", \"default\"]";

/// A serialized scene lists each object as its name, shape and material, the names kept
/// beside the objects as the file gives them or as generated.
#[test]
fn serialized_objects_carry_their_names() {
    let two = with_table(GOOD).replace("[[generate]]", "[[shapes]]\ntype = \"sphere\"\nname = \"ball\"\ncenter = [0, 0, 1]\nradius = 0.5\nmaterial = \"red\"\n\n[[generate]]");
    let s = parse(&(two + "\n[[generate]]\n" + GOOD), "g.toml").unwrap();
    assert_eq!(s.objects.len(), 102);
    // The fields in the struct's order, each object as `{name, shape, material}`.
    let text = serde_json::to_string(&s).unwrap();
    let at: Vec<usize> = [
        "settings",
        "camera",
        "materials",
        "material_names",
        "metal_given",
        "objects",
        "lights",
    ]
    .map(|k| text.find(&format!("\"{k}\":")).unwrap())
    .to_vec();
    assert!(at.windows(2).all(|w| w[0] < w[1]), "{at:?}");
    let ball = r#"{"name":"ball","shape":{"sphere":{"center":[0.0,0.0,1.0],"radius":0.5}},"material":1}"#;
    assert!(text.contains(ball), "{text:.600}");
    let json = serde_json::to_value(&s).unwrap();
    let objects = json["objects"].as_array().unwrap();
    let names: Vec<&str> = [0, 1, 2, 51, 52, 101]
        .map(|i| objects[i]["name"].as_str().unwrap())
        .to_vec();
    assert_eq!(
        names,
        [
            "plane#0",
            "ball",
            "generate[0]#0",
            "generate[0]#49",
            "generate[1]#0",
            "generate[1]#49"
        ]
    );
}

#[test]
fn a_valid_table_adds_its_objects_after_the_shapes() {
    let s = parse(&with_table(GOOD), "g.toml").unwrap();
    assert_eq!(s.objects.len(), 51);
    assert_eq!(s.name_of(&s.objects[0]), "plane#0");
    assert_eq!(s.name_of(&s.objects[1]), "generate[0]#0");
    assert_eq!(s.name_of(&s.objects[50]), "generate[0]#49");
    assert!(s.objects[1..].iter().all(|o| o.material <= 1));
    // Same text, same objects; another seed, other objects.
    assert_eq!(s, parse(&with_table(GOOD), "g.toml").unwrap());
    let other = parse(&with_table(&GOOD.replace("seed = 3", "seed = 4")), "g.toml").unwrap();
    assert_ne!(s.objects, other.objects);
}

#[test]
fn bad_values_are_located_errors() {
    let cases: [(&str, &str, &str); 10] = [
        (
            "count = 50",
            "count = 0",
            "g.toml:19:9: generate[0].count: must be in [1, 4000000], got 0",
        ),
        (
            "count = 50",
            "count = 4000001",
            "generate[0].count: must be in [1, 4000000], got 4000001",
        ),
        (
            "count = 50",
            "count = -3",
            "g.toml:19:9: generate[0].count: must be in [1, 4000000], got -3",
        ),
        (
            "kind = \"mixed\"",
            "kind = \"cubes\"",
            "g.toml:18:8: generate[0].kind: must be \"spheres\", \"mixed\" or \"triangles\", got \"cubes\"",
        ),
        (
            "radius = [0.05, 0.1]",
            "radius = [0.1, 0.05]",
            "generate[0].radius: must be [smallest, largest] with smallest <= largest",
        ),
        (
            "radius = [0.05, 0.1]",
            "radius = [0, 0.1]",
            "generate[0].radius: must be a finite number in (0, 1e9], got 0",
        ),
        (
            "max = [1, 1, 1]",
            "max = [1, -1, 1]",
            "g.toml:22:7: generate[0].max: must exceed min in every component",
        ),
        (
            "min = [-1, -1, 0]",
            "min = [-1, -1, 2e9]",
            "generate[0].min: components must be finite numbers in [-1e9, 1e9]",
        ),
        (
            "materials = [\"red\", \"default\"]",
            "materials = [\"blue\"]",
            "generate[0].materials: unknown material \"blue\"; defined: default, red",
        ),
        (
            "seed = 3",
            "seed = 3\ndensity = 2",
            "g.toml:21:1: generate[0].density: unknown field `density`",
        ),
    ];
    for (from, to, want) in cases {
        let text = with_table(&GOOD.replace(from, to));
        let e = parse(&text, "g.toml").expect_err(to).to_string();
        assert!(e.contains(want), "{to}: got {e}");
    }
}

#[test]
fn the_scene_total_is_limited_too() {
    let table = GOOD.replace("count = 50", "count = 3000000");
    let text = format!("{}[[generate]]\n{table}\n", with_table(&table));
    let e = parse(&text, "g.toml").unwrap_err().to_string();
    assert!(
        e.contains(
            "generate[1].count: the scene would hold 6000001 objects with this table, at most 4000000 are allowed"
        ),
        "{e}"
    );
}

#[test]
fn the_command_line_exits_2_on_a_bad_table() {
    let dir = temp_dir("generate-cli");
    let scene = dir.join("bad.toml");
    std::fs::write(&scene, with_table(&GOOD.replace("count = 50", "count = 0"))).unwrap();
    let o = lumiere(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        dir.join("x.png").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("bad.toml:19:9: generate[0].count: must be in [1, 4000000], got 0"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(!dir.join("x.png").exists());
}
