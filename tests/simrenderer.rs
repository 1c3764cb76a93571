//! SIMRenderer scene files read by lumiere: every keyword and alias of the hand-written
//! fixtures in tests/fixtures/simrenderer/ read to the values written there; the chapter's
//! reference scene in SIMRenderer's format giving the scene and the bytes of its TOML twin;
//! errors located and named, warnings under `--lenient`; the two formats told apart.

use crate::common::*;
use glam::DVec3;
use lumiere::conventions::{Conventions, SamplePosition};
use lumiere::light::{Attenuation, Light, PointLight};
use lumiere::material::{Material, TermColors};
use lumiere::scene::simrenderer::{self, Options, Parsed};
use lumiere::scene::{self, Format, LoadOptions, ShadingModel, Specular};
use lumiere::shape::{Cone, Cuboid, Cylinder, Disk, Plane, Shape, Sphere, Torus, Transform, Triangle};
use std::path::PathBuf;

fn fixture(name: &str) -> PathBuf {
    repo("tests/fixtures/simrenderer").join(name)
}

fn read(name: &str) -> Parsed {
    simrenderer::load(&fixture(name), &Options::default()).unwrap()
}

fn parse(text: &str) -> Result<Parsed, scene::SceneError> {
    simrenderer::parse(text, "lab.txt", &Options::default())
}

/// The error of `text`, as printed.
fn error(text: &str) -> String {
    match parse(text) {
        Ok(_) => panic!("no error for:\n{text}"),
        Err(e) => e.to_string(),
    }
}

fn lenient(text: &str) -> Parsed {
    let options = Options {
        lenient: true,
        ..Options::default()
    };
    simrenderer::parse(text, "lab.txt", &options).unwrap()
}

fn warnings(p: &Parsed) -> Vec<String> {
    p.warnings.iter().map(|w| w.to_string()).collect()
}

fn unit(v: [f64; 3]) -> DVec3 {
    let v = DVec3::from(v);
    v / v.length()
}

#[test]
fn every_keyword_reads_to_the_value_written() {
    let parsed = read("keywords.txt");
    let s = &parsed.scene;
    // camera: position, look_at, up (made unit), angle; the clipping planes are conventions.
    assert_eq!(s.camera.position, DVec3::new(0.0, -8.0, 5.0));
    assert_eq!(s.camera.look_at, DVec3::new(0.0, 1.0, 0.0));
    assert_eq!(s.camera.up, DVec3::Z);
    assert_eq!(s.camera.vfov_deg, 45.0);
    // viewport, raytracer.
    let t = &s.settings;
    assert_eq!(
        (t.width, t.height, t.samples_per_pixel, t.depth, t.seed),
        (64, 48, 4, 5, 42)
    );
    assert_eq!(
        t.shading,
        ShadingModel {
            ambient: true,
            diffuse: true,
            specular: Specular::Phong,
            no_light: false
        }
    );
    assert!(t.shadows);
    assert_eq!(t.background, DVec3::ZERO);
    assert_eq!(t.adaptive_threshold, 0.0);
    let mut conventions = Conventions::SIMRENDERER;
    conventions.sample_position = SamplePosition::Jittered;
    conventions.near = 0.5;
    conventions.far = 250.0;
    assert_eq!(t.conventions, conventions);
    // Lights, in file order; the amplification folded into the point light's colour.
    assert_eq!(
        s.lights,
        vec![
            Light::Ambient {
                color: DVec3::splat(0.2)
            },
            Light::Ambient { color: DVec3::ZERO },
            Light::Directional {
                direction: unit([1.0, 1.0, -1.0]),
                color: DVec3::ONE
            },
            Light::Point(PointLight {
                position: DVec3::new(0.0, 0.0, 10.0),
                color: DVec3::new(1.0, 0.5, 2.0),
                attenuation: Attenuation {
                    constant: 1.0,
                    linear: 0.1,
                    quadratic: 0.01
                }
            }),
        ]
    );
    // Materials: the built-in default first, then by name; "none" and "unknown" are
    // SIMRenderer's grey default, a material without p takes the highlight of the
    // conventions (SIMRenderer's: metal, m = 1). The model's file names no library: its
    // faces take SIMRenderer's library default, named after the model.
    assert_eq!(
        s.material_names,
        [
            "default",
            "blue tile",
            "glass",
            "leaf",
            "model#12/default",
            "none",
            "red",
            "unknown"
        ]
    );
    let metal = |color: [f64; 3]| Material {
        color: DVec3::from(color),
        metal: 1.0,
        ..Material::default()
    };
    let glass = Material {
        color: DVec3::new(0.9, 0.9, 1.0),
        ka: 0.1,
        kd: 0.3,
        ks: 0.6,
        shininess: 50.0,
        metal: 0.75,
        kr: 0.1,
        kt: 0.8,
        ior: 1.5,
        term_colors: None,
    };
    // SIMRenderer's `SMaterialOBJ` default as 32-bit floats: each term its colour, k = 1.
    let f32_grey = |x: f32| DVec3::splat(x.into());
    let library_default = Material {
        color: DVec3::new(0.3f32.into(), 0.7f32.into(), 0.3f32.into()),
        ka: 1.0,
        kd: 1.0,
        ks: 1.0,
        shininess: 5.0,
        metal: 1.0,
        term_colors: TermColors::of(Some(f32_grey(0.2)), Some(f32_grey(0.2)), None),
        ..Material::default()
    };
    let grey = Material {
        color: DVec3::ONE,
        ka: 0.2,
        kd: 0.6,
        ks: 0.7,
        shininess: 20.0,
        metal: 0.0,
        kr: 0.0,
        kt: 0.0,
        ior: 1.0,
        term_colors: None,
    };
    assert_eq!(
        s.materials,
        vec![
            metal([1.0, 1.0, 1.0]),
            metal([0.0, 0.0, 1.0]),
            glass,
            metal([0.0, 1.0, 0.0]),
            library_default,
            grey.clone(),
            metal([1.0, 0.0, 0.0]),
            grey
        ]
    );
    assert_eq!(s.metal_given, [false, false, true, false, false, true, false, true]);
    // Objects: one per primitive, named <kind>#<index>; the model's 4 triangles.
    let (glass, red, blue, model, none, unknown) = (2, 6, 1, 4, 5, 7);
    let v = DVec3::new;
    let expected = [
        ("sphere#0", Shape::Sphere(Sphere::new(v(1.0, -2.0, 1.0), 1.0)), glass),
        (
            "plane#1",
            Shape::Plane(Box::new(Plane::new(DVec3::ZERO, DVec3::Z))),
            red,
        ),
        (
            "disk#2",
            Shape::Disk(Box::new(Disk::new(v(0.0, 5.0, 0.01), DVec3::Z, 2.0))),
            blue,
        ),
        (
            "triangle#3",
            Shape::Triangle(Triangle::new(v(-2.0, 2.0, 0.0), v(0.0, 2.0, 0.0), v(-1.0, 2.0, 2.0))),
            red,
        ),
        (
            "tube#4",
            Shape::Cylinder(Box::new(Cylinder::tube(v(2.0, 2.0, 1.0), DVec3::X, 2.0, 0.5))),
            glass,
        ),
        (
            "cylinder#5",
            Shape::Cylinder(Box::new(Cylinder::new(v(-5.0, 9.0, 0.0), DVec3::Z, 3.0, 1.0))),
            red,
        ),
        (
            "cone#6",
            Shape::Cone(Box::new(Cone::new(v(-3.0, -3.0, 0.0), DVec3::Z, 2.5, 1.0))),
            red,
        ),
        (
            "box#7",
            Shape::Cuboid(Box::new(Cuboid::new(v(0.0, 0.0, 3.0), DVec3::splat(2.0), DVec3::ZERO))),
            red,
        ),
        (
            "torus#8",
            Shape::Torus(Box::new(Torus::new(v(4.0, 3.0, 2.0), DVec3::Z, 1.5, 0.5))),
            red,
        ),
        (
            "sphere#9",
            Transform::from_parts(v(0.5, 1.0, 1.5), v(10.0, 20.0, 30.0), v(-2.0, -2.0, 1.5))
                .apply(Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0))),
            glass,
        ),
        ("sphere#10", Shape::Sphere(Sphere::new(v(0.0, 0.0, 20.0), 1.0)), unknown),
        ("sphere#11", Shape::Sphere(Sphere::new(v(0.0, 0.0, 30.0), 1.0)), none),
    ];
    assert_eq!(s.objects.len(), expected.len() + 4);
    for (o, (name, shape, material)) in s.objects.iter().zip(expected) {
        assert_eq!(
            (s.name_of(o).as_str(), &o.shape, o.material()),
            (name, &shape, material)
        );
    }
    // The model: scaled by 2, turned 90 degrees about z (x -> y, y -> -x), moved by (1, 1, 0).
    let corners = [v(1.0, 1.0, 0.0), v(1.0, 3.0, 0.0), v(-1.0, 1.0, 0.0), v(1.0, 1.0, 2.0)];
    let faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    for (k, face) in faces.iter().enumerate() {
        let o = &s.objects[12 + k];
        assert_eq!(
            (s.name_of(o).to_string(), o.material()),
            (format!("model#12/{k}"), model)
        );
        let Shape::Triangle(t) = &o.shape else { panic!("{o:?}") };
        for (p, i) in t.points().iter().zip(face) {
            assert!((*p - corners[*i]).length() < 1e-14, "{p} {}", corners[*i]);
        }
    }
    // What SIMRenderer accepts and logs: the undefined materials, the model's.
    let shown = fixture("keywords.txt").display().to_string();
    assert_eq!(
        warnings(&parsed),
        [
            format!(
                "{shown}:180:1: primitive.material_name: no material is named \"unknown\"; it gets SIMRenderer's grey default material (ambient 0.2, diffuse 0.6, specular 0.7)"
            ),
            format!(
                "{shown}:186:1: scene.primitive: no material is named \"none\" (a primitive without material_name takes the material named \"none\"); it gets SIMRenderer's grey default material (ambient 0.2, diffuse 0.6, specular 0.7)"
            ),
        ]
    );
}

#[test]
fn every_french_alias_reads_as_its_keyword() {
    let english = read("keywords.txt").scene;
    let french = read("aliases.txt");
    assert_eq!(french.scene, english);
    assert_eq!(french.warnings.len(), 2);
}

#[test]
fn the_reference_scene_gives_the_scene_and_bytes_of_its_toml_twin() {
    let sim = read("reference.txt");
    assert_eq!(sim.warnings, []);
    let toml = scene::load(&fixture("reference-simrenderer.toml")).unwrap();
    assert_eq!(sim.scene, toml);
    // The same scene, so the same image; rendered anyway, at 80 x 60.
    let a = render_small(&sim.scene, 80, 60, 1, 2).to_rgb8();
    let b = render_small(&toml, 80, 60, 1, 2).to_rgb8();
    assert_eq!(a, b);
    // Lit: the floor under the directional light, the spheres, the cube.
    assert!(a.iter().filter(|&&c| c > 100).count() > 1000);
    // And scene::load tells the format by itself.
    assert_eq!(scene::load(&fixture("reference.txt")).unwrap(), toml);
}

#[test]
fn errors_name_the_line_column_keyword_and_range() {
    for (text, expected) in [
        (
            "camera\nangle 5\nend",
            "lab.txt:2:7: camera.angle: must be a finite number in [10, 170], got 5",
        ),
        (
            "material\nka 1.5\nend",
            "lab.txt:2:4: material.ka: must be a finite number in [0, 1], got 1.5",
        ),
        // The value as written (Java's forms too), not reformatted.
        (
            "camera\nangle 1e-7\nend",
            "lab.txt:2:7: camera.angle: must be a finite number in [10, 170], got 1e-7",
        ),
        (
            "material\nka 1.5f\nend",
            "lab.txt:2:4: material.ka: must be a finite number in [0, 1], got 1.5f",
        ),
        (
            "materiel\nbrillance 250\nfin",
            "lab.txt:2:11: materiel.brillance: must be a finite number in [0, 200], got 250",
        ),
        (
            "material\ncolour 1 0 0\nend",
            "lab.txt:2:1: material.colour: unknown keyword \"colour\"; material's keywords are name (nom), color (couleur), ka, kd, ks, kr, kt, shininess (brillance), plasticity (p), refractive_index (n), end (fin)",
        ),
        (
            "material\nname red\ncamera\nend",
            "lab.txt:3:1: material.camera: \"camera\" is not a keyword of material (a forgotten `end` before it?); material's keywords are name (nom), color (couleur), ka, kd, ks, kr, kt, shininess (brillance), plasticity (p), refractive_index (n), end (fin)",
        ),
        (
            "kamera\n",
            "lab.txt:1:1: scene.kamera: unknown keyword \"kamera\"; the blocks are camera, viewport, raytracer, primitive, material (blinn_material, color_material, materiel), texture_material (texture_materiel), ambient_light (lumiere_ambiante), directional_light (lumiere_directionnelle), point_light (lumiere_ponctuelle), model, linear_aperture_light, rectangular_aperture_light, elliptical_aperture_light, aperture_mask_light, end (fin)",
        ),
        (
            "viewport\nwidth 800.0\nend",
            "lab.txt:2:7: viewport.width: expects an integer, got \"800.0\"",
        ),
        (
            // An integer beyond Java's int is told the keyword's range, not refused as a word.
            "viewport\nwidth 99999999999999999999\nend",
            "lab.txt:2:7: viewport.width: must be an integer in [1, 16384], got 99999999999999999999",
        ),
        (
            "viewport\nwidth 0\nend",
            "lab.txt:2:7: viewport.width: must be an integer in [1, 16384], got 0",
        ),
        (
            "primitive\nsphere\nposition 1 2\nend\nend",
            "lab.txt:3:13: sphere.position: expects 3 numbers x y z, got 2",
        ),
        (
            "primitive\nsphere\nray -1\nend\nend",
            "lab.txt:3:5: sphere.ray: must be a finite number in (0, 1e9], got -1",
        ),
        (
            "point_light\ncolor 1 -1 1\nend",
            "lab.txt:2:7: point_light.color: each channel must be a finite number in [0, 1e6], got 1 -1 1",
        ),
        (
            "material\ncolor 1.2 1 1\nend",
            "lab.txt:2:7: material.color: each channel must be a finite number in [0, 1], got 1.2 1 1",
        ),
        (
            "raytracer\nrecursive_level 65\nend",
            "lab.txt:2:17: raytracer.recursive_level: must be an integer in [1, 64], got 65",
        ),
        (
            "raytracer\npixel_coordinate corner\nend",
            "lab.txt:2:18: raytracer.pixel_coordinate: must be one of top_left (0), top_right (1), bottom_left (2), bottom_right (3), center (4), random (5), got \"corner\"",
        ),
        // What stops SIMRenderer from building an object.
        (
            "camera\nposition 0 0 1\nlook_at 0 0 1\nend",
            "lab.txt:3:1: camera.look_at: must differ from the camera position",
        ),
        (
            "camera\nlook_at 0 1 0\nend",
            "lab.txt:1:1: scene.camera: must not be parallel to the viewing direction (look_at - position)",
        ),
        (
            "camera\nnear_clipping_plane 200\nend",
            "lab.txt:2:1: camera.near_clipping_plane: far_clipping_plane (100) must be at least near_clipping_plane (200)",
        ),
        (
            "primitive\ntriangle\npoint 0 0 0\npoint 1 1 1\npoint 2 2 2\nend\nend",
            "lab.txt:5:1: triangle.point: the points 0 0 0, 1 1 1 and 2 2 2 make no triangle: its points are on one line",
        ),
        (
            "primitive\ncylinder\npoint 1 1 1\npoint 1 1 1\nend\nend",
            "lab.txt:4:1: cylinder.point: the two points 1 1 1 and 1 1 1 must differ (a cylinder needs a length)",
        ),
        (
            "primitive\ntube\npoint 0 0 0\npoint 0 0 1\npoint 0 0 2\nend\nend",
            "lab.txt:5:1: tube.point: a tube takes 2 points; this is one more",
        ),
        (
            "primitive\ntorus\nminor_radius 2\nend\nend",
            "lab.txt:3:1: torus.minor_radius: must be at most major_radius (1) (a self-intersecting spindle torus is not supported), got 2",
        ),
        (
            "primitive\nsphere\nend\nplane\nend\nend",
            "lab.txt:4:1: primitive.plane: a primitive has one geometry; this is a second one (after a sphere)",
        ),
        (
            "primitive\ngeometry\nscale 2 2 2\nend\nend",
            "lab.txt:2:1: primitive.geometry: a geometry block needs one geometry inside it (sphere, plane, ...)",
        ),
        (
            "primitive\ngeometry\nscale 0 1 1\nsphere\nend\nend\nend",
            "lab.txt:3:7: geometry.scale: each factor must be finite, of magnitude in [1e-6, 1e6] (negative mirrors), got 0 1 1",
        ),
        (
            // The centre at z = 9.99e8 is inside, the sphere's top at 1.001e9 is not.
            "primitive\ngeometry\ntranslation 0 0 999000000\nsphere\nray 2000000\nend\nend\nend",
            "lab.txt:2:1: primitive.geometry: the transform moves the shape beyond the coordinates' range [-1e9, 1e9]",
        ),
        (
            "point_light\nconstant_attenuator 0\nend",
            "lab.txt:2:1: point_light.constant_attenuator: the constant, linear and quadratic attenuators cannot all be 0",
        ),
        (
            "material\nkr 0.5\nkt 0.7\nend",
            "lab.txt:3:1: material.kt: kr + kt must be at most 1 in lumiere (no ray may carry more than its parent), got 0.5 + 0.7",
        ),
        (
            "material\nname glass\nend\nmaterial\nname glass\nend",
            "lab.txt:5:1: material.name: a material named \"glass\" is already defined; SIMRenderer keeps the first",
        ),
        (
            "model\nfile missing.obj\nend",
            "lab.txt:2:6: model.file: missing.obj: cannot read the mesh file: No such file or directory (os error 2)",
        ),
        ("model\nend", "lab.txt:1:1: scene.model: a model needs a file (fichier)"),
        (
            // The icosahedron's second vertex, x = 0.5257..., is the first moved past 1e9; its
            // y 0.85065080835204 is the 32-bit float SIMRenderer reads, 0.8506507873535156.
            "model\nfile scenes/icosahedron.obj\ntranslation 1000000000 0 0\nend",
            "lab.txt:1:1: scene.model: the transform moves a vertex of scenes/icosahedron.obj to \
             1000000000.5257311 0.8506507873535156 0, beyond the coordinates' range [-1e9, 1e9]",
        ),
        // lumiere's notes.
        (
            "primitive\n# lumiere: name floor\nend",
            "lab.txt:2:17: primitive.lumiere:name: expects a quoted name such as \"floor\", got \"floor\"",
        ),
        (
            "# lumiere: colour 1\n",
            "lab.txt:1:12: scene.lumiere:colour: unknown lumiere note \"colour\"; the notes are name, seed, adaptive_threshold",
        ),
    ] {
        assert_eq!(error(text), expected, "{text}");
    }
}

#[test]
fn what_lumiere_does_not_model_is_refused_by_name() {
    for (text, expected) in [
        (
            "primitive\ngeometry\nbtriangle\nend\nend\nend",
            "lab.txt:3:1: geometry.btriangle: SIMRenderer does not transform a btriangle (its SBTriangleGeometry.transform is not implemented); give its points and normals where they are",
        ),
        // A refractive index of 0 (SIMRenderer's value for an opaque material) on a
        // transparent material: at the index's own value, as written, whichever comes first.
        (
            "material\nname glass\nkt 0.5\n  n 0\nend",
            "lab.txt:4:5: material.n: must be above 0 for a transparent material (kt > 0), got 0",
        ),
        (
            "material\nname glass\nrefractive_index 0.0\nkt 0.5\nend",
            "lab.txt:3:18: material.refractive_index: must be above 0 for a transparent material (kt > 0), got 0.0",
        ),
        (
            "material\nname glass\nn 20\nend",
            "lab.txt:3:3: material.n: must be a finite number in [0, 10], got 20",
        ),
        (
            "raytracer\nsampling 1025\nend",
            "lab.txt:2:10: raytracer.sampling: must be an integer in [1, 1024], got 1025",
        ),
    ] {
        assert_eq!(error(text), expected, "{text}");
    }
}

#[test]
fn lenient_goes_on_as_simrenderer_does_and_says_what_it_did() {
    let text = "camera\nangle 5\nposition 0 0 -5\nend\n\
                material\nname red\ncolour 1 0 0\nka 2\nend\n\
                linear_aperture_light\nwave_length 900\nend\n\
                primitive\nmaterial_name red\nbtriangle\nend\nsphere\nend\nend\n\
                primitive\nsphere\nend\nplane\nend\nend\n\
                raytracer\nsampling 2000\npixel_coordinate random\nend\n";
    let p = lenient(text);
    assert_eq!(
        warnings(&p),
        [
            "lab.txt:2:7: camera.angle: must be a finite number in [10, 170], got 5; the value before it is kept",
            "lab.txt:7:1: material.colour: unknown keyword \"colour\"; material's keywords are name (nom), color (couleur), ka, kd, ks, kr, kt, shininess (brillance), plasticity (p), refractive_index (n), end (fin); the line is skipped",
            "lab.txt:8:4: material.ka: must be a finite number in [0, 1], got 2; the value before it is kept",
            "lab.txt:11:13: linear_aperture_light.wave_length: must be a finite number in [380, 780], got 900; the value before it is kept",
            "lab.txt:17:1: primitive.sphere: a primitive has one geometry; this is a second one (after a btriangle); this geometry is skipped",
            "lab.txt:23:1: primitive.plane: a primitive has one geometry; this is a second one (after a sphere); this geometry is skipped",
            "lab.txt:27:10: raytracer.sampling: must be an integer in [1, 1024], got 2000; the value before it is kept",
            "lab.txt:20:1: scene.primitive: no material is named \"none\" (a primitive without material_name takes the material named \"none\"); it gets SIMRenderer's grey default material (ambient 0.2, diffuse 0.6, specular 0.7)",
        ]
    );
    // A file whose every block is dropped is an empty scene, said as such (not as a file
    // holding no block).
    let dropped = lenient("model\nfile no-such-lumiere-model.obj\nend\n");
    assert_eq!(
        warnings(&dropped)[1],
        "lab.txt:1:1: scene: every block of the file is dropped (the warnings above say why): an empty scene, rendered black, 500 x 500"
    );
    assert_eq!(dropped.scene.objects.len(), 0);
    // Under --lenient, a transparent material's n of 0 is 1, said at the n line.
    let glass = lenient("material\nname glass\nn 0\nkt 0.5\nend\n");
    assert_eq!(
        warnings(&glass),
        ["lab.txt:3:3: material.n: must be above 0 for a transparent material (kt > 0), got 0; n = 1 is used"]
    );
    assert_eq!(glass.scene.materials[1].ior, 1.0);
    let s = &p.scene;
    // The defaults kept: angle 60, ka 0.2, one sample; the camera moved.
    assert_eq!(
        (s.camera.vfov_deg, s.camera.position),
        (60.0, DVec3::new(0.0, 0.0, -5.0))
    );
    assert_eq!(s.materials[1].ka, 0.2);
    assert_eq!(s.settings.samples_per_pixel, 1);
    assert_eq!(s.settings.conventions.sample_position, SamplePosition::Jittered);
    // The first primitive keeps its (default) btriangle, the second its sphere.
    assert_eq!(s.objects.len(), 2);
    assert_eq!(
        [s.name_of(&s.objects[0]), s.name_of(&s.objects[1])],
        ["triangle#0", "sphere#1"]
    );
    // An object SIMRenderer cannot build is dropped with a warning.
    let p = lenient("primitive\ntriangle\npoint 1 1 1\npoint 1 1 1\nend\nend\nprimitive\nsphere\nend\nend");
    assert_eq!(p.scene.objects.len(), 1);
    assert_eq!(
        warnings(&p)[0],
        "lab.txt:4:1: triangle.point: the points 1 1 1, 1 1 1 and 1 1 0 make no triangle: two of its points are equal; the geometry is dropped"
    );
}

#[test]
fn what_simrenderer_accepts_is_read_as_it_reads_it() {
    // A missing `end` at the end of the file closes every block; a top-level `end` stops
    // the scene; a name keeps its trailing blanks.
    let p = parse("material\nname red \ncolor rouge\nprimitive\n").unwrap_err();
    assert_eq!(
        p.to_string(),
        "lab.txt:4:1: material.primitive: \"primitive\" is not a keyword of material (a forgotten `end` before it?); material's keywords are name (nom), color (couleur), ka, kd, ks, kr, kt, shininess (brillance), plasticity (p), refractive_index (n), end (fin)"
    );
    let p = parse(
        "material\nname red \ncolor rouge\nend\nprimitive\nmaterial_name red\nsphere\nend\nend\nend\nprimitive\nsphere",
    )
    .unwrap();
    assert_eq!(p.scene.objects.len(), 1);
    assert_eq!(p.scene.material_names, ["default", "red", "red "]);
    assert_eq!(p.scene.objects[0].material, 1, "\"red\" is not \"red \"");
    assert_eq!(
        warnings(&p),
        [
            "lab.txt:10:1: scene.end: SIMRenderer stops reading the scene at this top-level end: everything after it is ignored, from line 11 (\"primitive\") on",
            "lab.txt:6:1: primitive.material_name: no material is named \"red\" (note the blanks: a material is named \"red \"); it gets SIMRenderer's grey default material (ambient 0.2, diffuse 0.6, specular 0.7)",
        ]
    );
    // Nothing but defaults: SIMRenderer's camera at the origin looking along +z with y up,
    // 500 x 500, one sample, depth 1, Blinn. An empty file (or one of comments) is such a
    // scene, and warned: a wrong or unsaved file renders black.
    let p = parse("").unwrap();
    let empty = "lab.txt:1:1: scene: the file holds no block (camera, viewport, raytracer, material, primitive, model or light): an empty scene, which SIMRenderer renders black, 500 x 500";
    assert_eq!(warnings(&p), [empty]);
    assert_eq!(warnings(&parse("# my scene\n\n").unwrap()), [empty]);
    assert_eq!(warnings(&parse("raytracer\nend").unwrap()), Vec::<String>::new());
    let s = p.scene;
    assert_eq!(
        (s.camera.position, s.camera.look_at, s.camera.up, s.camera.vfov_deg),
        (DVec3::ZERO, DVec3::Z, DVec3::Y, 60.0)
    );
    assert_eq!((s.settings.width, s.settings.height), (500, 500));
    assert_eq!((s.settings.samples_per_pixel, s.settings.depth), (1, 1));
    assert_eq!(s.settings.shading, ShadingModel::default());
    assert_eq!(s.settings.conventions, Conventions::SIMRENDERER);
    // A second camera block replaces the first whole; a material without a name is "none".
    let s = parse("camera\nangle 30\nposition 1 2 3\nend\ncamera\nangle 40\nend\nmaterial\nkd 0.5\nend\nprimitive\nsphere\nend\nend")
        .unwrap();
    assert_eq!((s.scene.camera.vfov_deg, s.scene.camera.position), (40.0, DVec3::ZERO));
    assert_eq!(s.scene.material_names, ["default", "none"]);
    assert_eq!(s.scene.materials[1].kd, 0.5);
    assert_eq!(s.warnings, []);
    // Sampling without random pixel coordinates: the same ray, as SIMRenderer warns.
    let p = parse("raytracer\nsampling 4\nend").unwrap();
    assert_eq!(p.scene.settings.samples_per_pixel, 4);
    assert_eq!(
        warnings(&p),
        ["lab.txt:2:1: raytracer.sampling: sampling 4 without pixel_coordinate random traces the same ray 4 times"]
    );
    // Lone carriage returns end lines, as Java reads them.
    let s = parse("camera\rangle 30\r\nend").unwrap().scene;
    assert_eq!(s.camera.vfov_deg, 30.0);
    // A block comment that is never closed makes the rest of the file a comment: warned at
    // its opening, the */ written on that line named.
    let p = parse("/* my scene */\ncamera\nangle 30\n\nend\n").unwrap();
    assert_eq!(p.scene.camera.vfov_deg, 60.0);
    assert_eq!(
        warnings(&p),
        [
            "lab.txt:1:1: scene./*: this block comment is never closed, so lines 2 to 5 are read as a comment, as SIMRenderer reads them: only a line whose first word is */ closes it, not the */ later on this line",
            empty,
        ]
    );
    let p = parse("camera\nend\n  /*\nprimitive\n").unwrap();
    assert_eq!(
        warnings(&p),
        [
            "lab.txt:3:3: scene./*: this block comment is never closed, so line 4 is read as a comment, as SIMRenderer reads them: only a line whose first word is */ closes it"
        ]
    );
    // Closed, or open with nothing written after it: no warning.
    assert_eq!(parse("/* a\n*/\ncamera\nend\n").unwrap().warnings, []);
    assert_eq!(parse("camera\nend\n/*\n\n").unwrap().warnings, []);
}

#[test]
fn lumiere_notes_name_objects_and_set_the_seed() {
    let s = parse(
        "raytracer\n# lumiere: seed 7\n# lumiere: adaptive_threshold 0.5\nend\nprimitive\n# lumiere: name \"the \\\"floor\\\"\"\nplane\nend\nend",
    )
    .unwrap()
    .scene;
    assert_eq!((s.settings.seed, s.settings.adaptive_threshold), (7, 0.5));
    assert_eq!(s.name_of(&s.objects[0]), "the \"floor\"");
}

#[test]
fn the_conventions_preset_goes_under_the_files_settings() {
    let chapter = Options {
        conventions: Conventions::CHAPTER,
        ..Options::default()
    };
    let s = simrenderer::load(&fixture("reference.txt"), &chapter).unwrap().scene;
    let mut expected = Conventions::CHAPTER;
    expected.sample_position = SamplePosition::Center;
    expected.far = 1000.0;
    assert_eq!(s.settings.conventions, expected);
    // A material without p takes the preset's highlight: plastic under the chapter's.
    let s = simrenderer::parse("material\nname a\nend\nmaterial\nname b\np 0\nend", "lab.txt", &chapter)
        .unwrap()
        .scene;
    assert_eq!((s.materials[1].metal, s.materials[2].metal), (0.0, 1.0));
}

#[test]
fn the_format_is_told_by_name_then_by_first_keyword() {
    let dir = temp_dir("simrenderer-format");
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let load = |path: &PathBuf| scene::load_with(path, &LoadOptions::default());
    // Any name: SIMRenderer when the first keyword opens a block (comments first are fine).
    let lab = write("lab.scene", "# my lab\n\nCAMERA\nangle 30\nend\n");
    assert_eq!(load(&lab).unwrap().format, Format::SimRenderer);
    // A TOML scene not named .toml: the error says so.
    let toml = write("scene.txt", "[image]\nwidth = 8\nheight = 6\n");
    assert_eq!(
        load(&toml).unwrap_err().to_string(),
        format!(
            "{}:1:1: format: cannot tell the scene's format: the file is not named .toml and its first keyword \"[image]\" opens none of SIMRenderer's blocks (camera, viewport, raytracer, primitive, material, texture_material, ambient_light, directional_light, point_light, model, linear_aperture_light, rectangular_aperture_light, elliptical_aperture_light, aperture_mask_light); it looks like TOML: name it .toml, or pass --format toml",
            toml.display()
        )
    );
    let forced = LoadOptions {
        format: Some(Format::Toml),
        ..LoadOptions::default()
    };
    assert!(
        scene::load_with(&toml, &forced)
            .unwrap_err()
            .to_string()
            .contains("the file has no [camera] table")
    );
    // A SIMRenderer scene named .toml: TOML's error, and a hint.
    let misnamed = write("lab.toml", "camera\nangle 30\nend\n");
    let e = load(&misnamed).unwrap_err().to_string();
    assert!(
        e.ends_with(
            "(the file starts like a SIMRenderer scene: read it with --format simrenderer, or name it other than .toml)"
        ),
        "{e}"
    );
    let forced = LoadOptions {
        format: Some(Format::SimRenderer),
        ..LoadOptions::default()
    };
    assert_eq!(
        scene::load_with(&misnamed, &forced).unwrap().scene.camera.vfov_deg,
        30.0
    );
    // A file starting with a UTF-8 byte order mark (Windows editors write one): the mark is
    // skipped, for telling the format and for reading; the first line's columns are those
    // after it.
    let bom = write("bom.txt", "\u{feff}camera\nangle 30\nend\n");
    let loaded = load(&bom).unwrap();
    assert_eq!(loaded.format, Format::SimRenderer);
    assert_eq!(loaded.scene.camera.vfov_deg, 30.0);
    let bom_typo = write("bom-typo.txt", "\u{feff}CAMERA\nangle 30\nend\nkamera\n");
    assert!(load(&bom_typo).unwrap_err().to_string().starts_with(&format!(
        "{}:4:1: scene.kamera: unknown keyword \"kamera\";",
        bom_typo.display()
    )));
    assert_eq!(
        error("\u{feff}kamera\n"),
        error("kamera\n"),
        "the mark is not part of the first keyword"
    );
    let out = lumiere(&[
        "render",
        bom.to_str().unwrap(),
        "-o",
        dir.join("bom.png").to_str().unwrap(),
        "--width",
        "8",
        "--height",
        "6",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(dir.join("bom.png").is_file());
}

#[test]
fn the_command_line_reads_simrenderer_files() {
    let dir = temp_dir("simrenderer-cli");
    let reference = fixture("reference.txt");
    let png = dir.join("ref.png");
    let out = lumiere(&[
        "render",
        reference.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--width",
        "40",
        "--height",
        "30",
        "-q",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.stderr.is_empty());
    // The same bytes as the TOML twin.
    let twin = dir.join("twin.png");
    let toml = fixture("reference-simrenderer.toml");
    let out = lumiere(&[
        "render",
        toml.to_str().unwrap(),
        "-o",
        twin.to_str().unwrap(),
        "--width",
        "40",
        "--height",
        "30",
        "-q",
    ]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(std::fs::read(&png).unwrap(), std::fs::read(&twin).unwrap());
    // An error: exit 2, located; --lenient: a warning, and the render goes on.
    let lab = dir.join("lab.txt");
    std::fs::write(
        &lab,
        "camera\nangle 200\nend\nprimitive\nsphere\nposition 0 0 5\nend\nend\n",
    )
    .unwrap();
    let args = |extra: &[&str]| {
        let mut a = vec![
            "render",
            lab.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--width",
            "8",
            "--height",
            "6",
        ];
        a.extend_from_slice(extra);
        lumiere(&a)
    };
    let out = args(&[]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).trim(),
        format!(
            "lumiere: error: {}:2:7: camera.angle: must be a finite number in [10, 170], got 200",
            lab.display()
        )
    );
    let out = args(&["--lenient"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(
        String::from_utf8_lossy(&out.stderr).starts_with(&format!(
            "lumiere: warning: {}:2:7: camera.angle: must be a finite number in [10, 170], got 200; the value before it is kept\n",
            lab.display()
        )),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // SIMRenderer's conventions with the file's pixel_coordinate and far plane, named after
    // SIMRenderer's preset.
    let probe = |extra: &[&str]| {
        let mut a = vec![
            "probe",
            reference.to_str().unwrap(),
            "--pixel",
            "10,10",
            "--width",
            "20",
            "--height",
            "15",
        ];
        a.extend_from_slice(extra);
        lumiere(&a)
    };
    let text = String::from_utf8_lossy(&probe(&[]).stdout).into_owned();
    assert!(
        text.contains("\nconventions simrenderer with sample_position = center, far = 1000\n"),
        "{text}"
    );
    // --conventions chapter: the file's pixel_coordinate and far plane over the chapter's.
    let out = probe(&["--conventions", "chapter"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("conventions chapter with sample_position = center, far = 1000\n"),
        "{text}"
    );
}

#[test]
fn the_grey_default_material_gives_simrenderers_greys() {
    let m = simrenderer::grey_default();
    // S_a = k_a S, S_d = k_d S, S_s = k_s [m S + (1 - m)] with S white, for any m.
    assert_eq!(m.color * m.ka, DVec3::splat(0.2));
    assert_eq!(m.color * m.kd, DVec3::splat(0.6));
    // Shininess 20, opaque and matte, with no texture.
    assert_eq!((m.shininess, m.kr, m.kt, m.metal), (20.0, 0.0, 0.0, 0.0));
    assert!(m.term_colors.is_none());
    for metal in [0.0, 0.5, 1.0] {
        let tint = lumiere::shading::specular_tint(metal, m.color);
        assert_eq!(tint * m.ks, DVec3::splat(0.7));
    }
}

#[test]
fn a_decimal_comma_is_named_where_it_splits_a_number() {
    let text = std::fs::read_to_string(fixture("reference.txt")).unwrap();
    // `kd 0,8` reads kd 0 (the comma separates numbers, as in SIMRenderer): a warning at the
    // word, the scene otherwise the reference's.
    let kd = text.replacen("kd 0.8", "kd  0,8", 1);
    let parsed = parse(&kd).unwrap();
    assert_eq!(
        warnings(&parsed),
        [
            "lab.txt:47:5: material.kd: \"0,8\" reads as two numbers, 0 and 8: a comma separates numbers (as in SIMRenderer); a decimal takes a point, 0.8"
        ]
    );
    let reference = read("reference.txt").scene;
    let changed: Vec<(f64, f64)> = reference
        .materials
        .iter()
        .zip(&parsed.scene.materials)
        .filter(|(r, p)| r != p)
        .map(|(r, p)| (r.kd, p.kd))
        .collect();
    assert_eq!(changed, [(0.8, 0.0)]);
    // Where the split makes the value wrong, the error gives the same hint.
    let color = text.replacen("color     0.85 0.85 0.85", "color     0,85 0,85 0,85", 1);
    let e = error(&color);
    assert!(
        e.starts_with("lab.txt:45:")
            && e.ends_with("; \"0,85\" reads as two numbers, 0 and 85: a comma separates numbers (as in SIMRenderer); a decimal takes a point, 0.85"),
        "{e}"
    );
    // A vector written with commas is no decimal.
    let listed = text.replacen("position            0.0 -8.0 5.0", "position <0,-8,5>", 1);
    let parsed = parse(&listed).unwrap();
    assert_eq!(parsed.warnings, []);
    assert_eq!(parsed.scene.camera.position, DVec3::new(0.0, -8.0, 5.0));
}

#[test]
fn every_pixel_coordinate_is_a_sample_position() {
    for (value, expected) in [
        ("top_left", SamplePosition::Corner),
        ("top_right", SamplePosition::TopRight),
        ("bottom_left", SamplePosition::BottomLeft),
        ("bottom_right", SamplePosition::BottomRight),
        ("center", SamplePosition::Center),
        ("random", SamplePosition::Jittered),
        ("2", SamplePosition::BottomLeft),
    ] {
        let text = format!("raytracer\npixel_coordinate {value}\nend\n");
        let parsed = parse(&text).unwrap_or_else(|e| panic!("{value}: {e}"));
        assert_eq!(parsed.scene.settings.conventions.sample_position, expected, "{value}");
    }
}

/// A message shows a vector as the file at fault writes one: SIMRenderer's numbers between
/// blanks (each the shortest that reads back), TOML's array.
#[test]
fn a_vector_in_a_message_is_written_as_its_file_writes_it() {
    assert_eq!(
        error("primitive\nsphere\nposition 0.5 -1e-9 2e9\nend\nend"),
        "lab.txt:3:10: sphere.position: components must be finite numbers in [-1e9, 1e9], got 0.5 -1e-9 2000000000"
    );
    let toml = "[image]\nwidth = 4\nheight = 3\n\
        [camera]\nposition = [0, -5, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\n\
        [[shapes]]\ntype = \"sphere\"\ncenter = [0.5, -1e-9, 2e9]\nradius = 1\n";
    assert_eq!(
        scene::parse(toml, "scene.toml").unwrap_err().to_string(),
        "scene.toml:10:10: shapes[0].center: components must be finite numbers in [-1e9, 1e9], got [0.5, -1e-9, 2000000000.0]"
    );
}
