//! Triangles, tubes, transforms and meshes through the scene format: the example scene
//! (`scenes/geometry.toml`) reads and renders; hits computed by hand through the whole
//! pipeline (file, world, closest hit); every new field's bad values give a located error
//! naming what is allowed; mesh files are read relative to the scene file, and their errors
//! name the `.obj` file, line and column; a mirroring transform keeps a mesh's normals outward.

use crate::common::*;
use glam::DVec3;
use lumiere::math::Ray;
use lumiere::render::render;
use lumiere::scene::transform::Similarity;
use lumiere::scene::{self, SceneError, parse};
use lumiere::shape::Shape;
use lumiere::world::World;

const HEAD: &str = "[image]\nwidth = 8\nheight = 6\n[camera]\nposition = [0, -8, 5]\nlook_at = [0, 0, 0]\n";

/// The error message of `HEAD` followed by `shapes`.
fn error(shapes: &str) -> String {
    match parse(&format!("{HEAD}{shapes}"), "t.toml") {
        Ok(_) => panic!("parsed without error:\n{shapes}"),
        Err(e) => e.to_string(),
    }
}

fn scene_of(shapes: &str) -> scene::Scene {
    parse(&format!("{HEAD}{shapes}"), "t.toml").unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_example_scene_reads_and_renders() {
    let s = scene("geometry.toml");
    // Floor, triangle, tube, ellipsoid and the icosahedron's 20 triangles.
    assert_eq!(s.objects.len(), 24);
    let kinds: Vec<&str> = s.objects.iter().take(4).map(|o| o.shape.kind()).collect();
    assert_eq!(kinds, ["plane", "triangle", "tube", "sphere"]);
    assert!(matches!(s.objects[3].shape, Shape::Transformed(_)));
    assert_eq!(s.name_of(&s.objects[4]), "gem/0");
    assert_eq!(s.name_of(&s.objects[23]), "gem/19");
    let film = render_small(&s, 80, 60, 1, 2);
    assert!(film.pixels.iter().all(|p| p.is_finite()));
}

#[test]
fn hits_by_hand_through_the_format() {
    let s = scene_of(
        "[[shapes]]\ntype = \"triangle\"\np0 = [0, 0, 1]\np1 = [2, 0, 1]\np2 = [0, 2, 1]\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n\
         transform = { scale = [2, 1, 0.5], translation = [10, 0, 0] }\n\
         [[shapes]]\ntype = \"tube\"\nstart = [0, 10, 0]\nend = [0, 10, 4]\nradius = 1\n",
    );
    let world = World::new(&s);
    let hit = |o: [f64; 3], d: [f64; 3]| {
        world
            .closest(&Ray::new(DVec3::from(o), DVec3::from(d).normalize()))
            .map(|(i, h)| (i, h.t, h.normal))
    };
    // The triangle at (0.5, 0.5, 1) from z = 5: t = 4, normal +z by the right-hand rule.
    assert_eq!(hit([0.5, 0.5, 5.], [0., 0., -1.]), Some((0, 4.0, DVec3::Z)));
    // The ellipsoid (semi-axes 2, 1, 0.5 around (10, 0, 0)) from above at x = 11: the
    // surface z = 0.5 sqrt(1 - 1/4) = sqrt(3) / 4; the gradient (2 (x - 10) / 4, 0,
    // 2 z / 0.25) = (1/2, 0, 2 sqrt(3)) is the normal.
    let (i, t, n) = hit([11., 0., 5.], [0., 0., -1.]).unwrap();
    assert_eq!(i, 1);
    assert!((t - (5.0 - 3f64.sqrt() / 4.0)).abs() < 1e-14, "{t}");
    assert!(
        (n - DVec3::new(0.5, 0.0, 2.0 * 3f64.sqrt()).normalize()).length() < 1e-14,
        "{n}"
    );
    // The tube from inside, at its axis, towards +x: the inner wall at t = 1; down the axis
    // from above it has no cap to stop the ray, which meets nothing.
    assert_eq!(hit([0., 10., 2.], [1., 0., 0.]), Some((2, 1.0, DVec3::X)));
    assert_eq!(hit([0., 10., 9.], [0., 0., -1.]), None);
}

#[test]
fn caps_and_lenses_by_hand_through_the_format() {
    // A convex cap over the disk of radius 3 at z = 1 (curvature 5: its sphere's center at
    // z = -3, its apex at z = 2), a lens along x from x = 10 (edge 2, radius 3, a convex cap
    // of curvature 5 at x = 10 and a concave one of curvature -5 at x = 12, 1 deep), and the
    // same cap turned by a transform.
    let s = scene_of(
        "[[shapes]]\ntype = \"spherical_cap\"\ncenter = [0, 0, 1]\nradius = 3\ncurvature = 5\n\
         [[shapes]]\ntype = \"lens\"\nbase = [10, 0, 0]\naxis = [1, 0, 0]\nthickness = 2\nradius = 3\n\
         curvature1 = 5\ncurvature2 = -5\n\
         [[shapes]]\ntype = \"spherical_cap\"\ncenter = [0, 0, 0]\nradius = 3\ncurvature = 5\n\
         transform = { rotation = [90, 0, 0], translation = [0, 20, 0] }\n",
    );
    assert_eq!(
        s.objects.iter().map(|o| o.shape.kind()).collect::<Vec<_>>(),
        ["spherical_cap", "lens", "spherical_cap"]
    );
    let world = World::new(&s);
    let hit = |o: [f64; 3], d: [f64; 3]| {
        world
            .closest(&Ray::new(DVec3::from(o), DVec3::from(d).normalize()))
            .map(|(i, h)| (i, h.t, h.normal))
    };
    // The cap's apex from above; from below, the open rim lets the ray through to the
    // dome's inside, the same point and normal.
    assert_eq!(hit([0., 0., 9.], [0., 0., -1.]), Some((0, 7.0, DVec3::Z)));
    assert_eq!(hit([0., 0., -2.], [0., 0., 1.]), Some((0, 4.0, DVec3::Z)));
    // The lens along its axis from x = 5: cap 1's apex at x = 9 (normal -x, its sphere's
    // center at x = 14); from inside at x = 10.5, the hollow's bottom at x = 11 (its sphere's
    // center at x = 16), the normal out of the lens into the hollow, +x.
    assert_eq!(hit([5., 0., 0.], [1., 0., 0.]), Some((1, 4.0, -DVec3::X)));
    let (i, t, n) = hit([10.5, 0., 0.], [1., 0., 0.]).unwrap();
    assert_eq!((i, n), (1, DVec3::X));
    assert!((t - 0.5).abs() < 1e-12, "{t}");
    // The edge at y = 3 from above (x = 11, z = 0 is inside the edge's length): t = 7.
    assert_eq!(hit([11., 10., 0.], [0., -1., 0.]), Some((1, 7.0, DVec3::Y)));
    // The turned cap bulges along -y (the normal +z turned 90 degrees about x): its apex at
    // y = 20 - 1 seen from y = 10.
    let (i, t, n) = hit([0., 10., 0.], [0., 1., 0.]).unwrap();
    assert_eq!(i, 2);
    assert!((t - 9.0).abs() < 1e-12 && (n + DVec3::Y).length() < 1e-12, "{t} {n}");
}

#[test]
fn new_fields_give_located_errors() {
    let sphere = "[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n";
    let cases = [
        (
            format!("{sphere}transform = {{ scale = [1, 0, 2] }}\n"),
            "t.toml:11:23: shapes[0].transform.scale: each factor must be finite, of magnitude in [1e-6, 1e6] \
             (negative mirrors), got [1.0, 0.0, 2.0]",
        ),
        (
            format!("{sphere}transform = {{ scale = [1, 1, 2e6] }}\n"),
            "t.toml:11:23: shapes[0].transform.scale: each factor must be finite, of magnitude in [1e-6, 1e6] \
             (negative mirrors), got [1.0, 1.0, 2000000.0]",
        ),
        (
            format!("{sphere}[shapes.transform]\nrotation = [0, 400, 0]\n"),
            "t.toml:12:12: shapes[0].transform.rotation: angles must be finite numbers in [-360, 360] degrees, got [0.0, 400.0, 0.0]",
        ),
        (
            format!("{sphere}transform = {{ translation = [0, 0, 2e9] }}\n"),
            "t.toml:11:29: shapes[0].transform.translation: components must be finite numbers in [-1e9, 1e9], \
             got [0.0, 0.0, 2000000000.0]",
        ),
        (
            format!("{sphere}transform = {{ translation = [0, 0, 1e9] }}\n"),
            "t.toml:11:13: shapes[0].transform: moves the shape beyond the coordinates' range [-1e9, 1e9]",
        ),
        (
            format!(
                "{sphere}transform = {{ scale = [2, 2, 2], matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]] }}\n"
            ),
            "t.toml:11:23: shapes[0].transform.scale: scale does not go with matrix (the matrix is the whole transform)",
        ),
        (
            format!("{sphere}transform = {{ matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [1, 1, 0, 0]] }}\n"),
            "t.toml:11:24: shapes[0].transform.matrix: the 3x3 part must be invertible, its inverse's entries in \
             [-1e6, 1e6] (no factor below 1e-6), got [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [1.0, 1.0, 0.0, 0.0]]",
        ),
        (
            format!("{sphere}transform = {{ matrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1]] }}\n"),
            "t.toml:11:53: shapes[0].transform.matrix[2]: invalid length 3, expected an array of length 4",
        ),
        (
            format!("{sphere}transform = {{ matrix = [[1, 0, 0, 0], [0, 1e7, 0, 0], [0, 0, 1, 0]] }}\n"),
            "t.toml:11:39: shapes[0].transform.matrix[1]: must be [a, b, c, d] with a, b, c finite in [-1e6, 1e6] \
             and d (the translation) in [-1e9, 1e9], got [0.0, 10000000.0, 0.0, 0.0]",
        ),
        (
            format!("{sphere}transform = {{ shear = 1 }}\n"),
            "t.toml:11:15: shapes[0].transform.shear: unknown field `shear`, expected one of `scale`, `rotation`, \
             `translation`, `matrix`",
        ),
        (
            "[[shapes]]\ntype = \"triangle\"\np0 = [0, 0, 0]\np1 = [1, 1, 1]\np2 = [3, 3, 3]\n".to_string(),
            "t.toml:11:6: shapes[0].p2: p0 [0.0, 0.0, 0.0], p1 [1.0, 1.0, 1.0] and p2 [3.0, 3.0, 3.0] make no \
             triangle: its points are on one line",
        ),
        (
            // The sine of the angle at p0, 5e-7, becomes 5e-13 under the scale.
            "[[shapes]]\ntype = \"triangle\"\np0 = [0, 0, 0]\np1 = [1, 0, 0]\np2 = [1, 5e-7, 0]\n\
             transform = { scale = [1, 1e-6, 1] }\n"
                .to_string(),
            "t.toml:12:13: shapes[0].transform: makes the triangle degenerate: its points are on one line",
        ),
        (
            "[[shapes]]\ntype = \"tube\"\nstart = [1, 2, 3]\nend = [1, 2, 3]\nradius = 1\n".to_string(),
            "t.toml:10:7: shapes[0].end: must differ from start [1.0, 2.0, 3.0] (a tube needs a length), got [1.0, 2.0, 3.0]",
        ),
        (
            "[[shapes]]\ntype = \"tube\"\nstart = [1, 2, 3]\nend = [1, 2, 4]\nradius = 0\n".to_string(),
            "t.toml:11:10: shapes[0].radius: must be a finite number in (0, 1e9], got 0",
        ),
        (
            "[[shapes]]\ntype = \"mesh\"\nfile = \"no-such.obj\"\n".to_string(),
            "t.toml:9:8: shapes[0].file: no-such.obj: cannot read the mesh file: No such file or directory (os error 2)",
        ),
        (
            "[[shapes]]\ntype = \"mesh\"\nfile = \"scenes/icosahedron.obj\"\nmaterial = \"wood\"\n".to_string(),
            "t.toml:10:12: shapes[0].material: unknown material \"wood\"; defined: default",
        ),
    ];
    for (shapes, want) in cases {
        assert_eq!(error(&shapes), want, "{shapes}");
    }
}

/// A scene and an `.obj` file in a directory of their own.
fn mesh_scene(dir: &std::path::Path, obj: &str, extra: &str) -> std::path::PathBuf {
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::write(dir.join("meshes/m.obj"), obj).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(
        &path,
        format!("{HEAD}[[shapes]]\ntype = \"mesh\"\nname = \"m\"\nfile = \"meshes/m.obj\"\n{extra}"),
    )
    .unwrap();
    path
}

const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

#[test]
fn mesh_files_are_read_relative_to_the_scene_file() {
    let dir = temp_dir("mesh-relative");
    let path = mesh_scene(&dir, SQUARE, "");
    let s = scene::load(&path).unwrap();
    assert_eq!(s.objects.len(), 2);
    assert_eq!(
        (s.name_of(&s.objects[0]).as_str(), s.name_of(&s.objects[1]).as_str()),
        ("m/0", "m/1")
    );
    // The same text parsed as if it lay elsewhere looks for the mesh there.
    let text = std::fs::read_to_string(&path).unwrap();
    let e = parse(&text, "elsewhere/scene.toml").unwrap_err().to_string();
    assert!(
        e.starts_with("elsewhere/scene.toml:10:8: shapes[0].file: elsewhere/meshes/m.obj: cannot read the mesh file"),
        "{e}"
    );
}

#[test]
fn mesh_errors_name_the_obj_file_and_the_line_and_column() {
    let dir = temp_dir("mesh-errors");
    let obj = dir.join("meshes/m.obj").display().to_string();
    let scene = dir.join("scene.toml").display().to_string();
    for (text, place, message) in [
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n",
            "4:1",
            "f: a face needs at least 3 vertices (f v1 v2 v3 ...), got 2",
        ),
        (
            "v 0 0 0\n# a comment\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n",
            "3:7",
            "vertex 2: coordinates must be finite numbers in [-1e9, 1e9], got 1 0 NaN",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 2 0 0\n f 1 2 3\n",
            "4:2",
            "the face makes no triangle: its points are on one line",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 one 0\nf 1 2 3\n",
            "3:5",
            "vertex 3: `one` is not a number (written x y z, x y z w or x y z r g b)",
        ),
        (
            "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf\t1\t2\t99999999999999999999\r\n",
            "4:7",
            "`99999999999999999999` is no index: a face's vertex is v, v/vt, v//vn or v/vt/vn, each a whole number",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
            "4:7",
            "f: vertex index 9, but the file has 3",
        ),
    ] {
        let path = mesh_scene(&dir, text, "");
        let e = scene::load(&path).unwrap_err();
        assert!(
            matches!(
                e,
                SceneError::Invalid {
                    line: 10,
                    column: 8,
                    ..
                }
            ),
            "{e}"
        );
        assert_eq!(
            e.to_string(),
            format!("{scene}:10:8: shapes[0].file: {obj}:{place}: {message}")
        );
    }
    // A transform that squashes a face flat names the face's line too: the sine of the
    // angle at the first vertex, 5e-7, becomes 5e-13.
    let thin = "v 0 0 0\nv 1 0 0\nv 1 5e-7 0\nf 1 2 3\n";
    let path = mesh_scene(&dir, thin, "transform = { scale = [1, 1e-6, 1] }\n");
    assert_eq!(
        scene::load(&path).unwrap_err().to_string(),
        format!(
            "{scene}:10:8: shapes[0].file: {obj}:4:1: the face makes no triangle after the transform: its points are on one line"
        )
    );
    // A transform that moves a vertex beyond the coordinates' range names that vertex, on
    // the transform's field: (1, 0, 0) scaled by 1e6 then moved by 1e9 along x.
    let path = mesh_scene(
        &dir,
        SQUARE,
        "transform = { scale = [1e6, 1, 1], translation = [1e9, 0, 0] }\n",
    );
    assert_eq!(
        scene::load(&path).unwrap_err().to_string(),
        format!(
            "{scene}:11:13: shapes[0].transform: moves a vertex of {obj} to [1001000000.0, 0.0, 0.0], beyond the coordinates' range [-1e9, 1e9]"
        )
    );
}

#[test]
fn a_mirror_keeps_a_mesh_outward() {
    // The icosahedron mirrored in x (and moved): every triangle's normal points away from
    // the center, as in the file.
    for scale in ["[1, 1, 1]", "[-1, 1, 1]", "[2, -0.5, 1]"] {
        let s = scene_of(&format!(
            "[[shapes]]\ntype = \"mesh\"\nfile = \"scenes/icosahedron.obj\"\n\
             transform = {{ scale = {scale}, translation = [3, 0, 0] }}\n"
        ));
        assert_eq!(s.objects.len(), 20);
        for o in &s.objects {
            let Shape::Triangle(t) = &o.shape else { panic!("{o:?}") };
            let [a, b, c] = t.points();
            let centroid = (a + b + c) / 3.0;
            assert!(
                t.normal().dot(centroid - DVec3::new(3., 0., 0.)) > 0.0,
                "{scale}: {o:?}"
            );
        }
    }
}

#[test]
fn a_moved_scene_keeps_one_vertex_array_per_mesh() {
    let s = scene_of("[[shapes]]\ntype = \"mesh\"\nfile = \"scenes/icosahedron.obj\"\n");
    let moved = Similarity {
        scale: 2.0,
        offset: DVec3::new(1e5, 0.0, 0.0),
    }
    .scene(&s);
    let arrays: Vec<_> = moved
        .objects
        .iter()
        .map(|o| match &o.shape {
            Shape::Triangle(t) => t.shared().0.clone(),
            other => panic!("{other:?}"),
        })
        .collect();
    assert!(arrays.iter().all(|a| std::sync::Arc::ptr_eq(a, &arrays[0])));
    // Vertex 1 of the file (-0.5257..., 0.8506..., 0) is at twice that plus the offset.
    let Shape::Triangle(t) = &s.objects[0].shape else {
        unreachable!()
    };
    let Shape::Triangle(m) = &moved.objects[0].shape else {
        unreachable!()
    };
    assert_eq!(m.points()[0], t.points()[0] * 2.0 + DVec3::new(1e5, 0.0, 0.0));
}

#[test]
fn generated_triangles_render() {
    let mut s = scene_of(
        "[[generate]]\nkind = \"triangles\"\ncount = 2000\nmin = [-3, -3, 0]\nmax = [3, 3, 2]\nradius = [0.1, 0.3]\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 0, 10]\n",
    );
    assert_eq!(s.objects.len(), 2000);
    assert!(s.objects.iter().all(|o| o.shape.kind() == "triangle"));
    s.settings.width = 40;
    s.settings.height = 30;
    let world = World::new(&s);
    assert_eq!(world.accel().name(), "bvh");
    let (film, stats) = render(&world, &|| {});
    assert_eq!(stats.counts.non_finite, 0);
    // Some pixels see triangles (lit by the point light), some the black background.
    assert!(film.pixels.iter().any(|p| p.max_element() > 0.05));
    assert!(film.pixels.iter().any(|p| p.max_element() == 0.0));
}
