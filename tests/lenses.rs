//! Lenses and spherical caps through the whole library: a lens images a point source where
//! the thin-lens equation `1/p + 1/q = 1/f` puts it (within 2 %, `f` from the lensmaker's
//! formula), rays traced from the source with the world's own intersection core, the
//! law of refraction of `math::refract` and the material's index; a spherical cap is open
//! at its rim as SIMRenderer leaves it; both read from TOML and from SIMRenderer's format,
//! and convert between them.

use glam::DVec3;
use lumiere::conventions::Conventions;
use lumiere::math::{Ray, hit_point_error, offset_origin, refract};
use lumiere::scene::{self, parse};
use lumiere::shape::Shape;
use lumiere::world::World;

const HEAD: &str = "[image]\nwidth = 8\nheight = 6\n[camera]\nposition = [0, -8, 5]\nlook_at = [0, 0, 0]\n";

/// A biconvex lens of rim radius 1, caps of radius of curvature 10, edge 0.02, centered on
/// the origin along z, in glass of index 1.5.
const THIN_LENS: &str = "[materials.glass]\nkt = 1\nn = 1.5\n\
    [[shapes]]\ntype = \"lens\"\nbase = [0, 0, -0.01]\naxis = [0, 0, 1]\nthickness = 0.02\nradius = 1\n\
    curvature1 = 10\ncurvature2 = 10\nmaterial = \"glass\"\n";

/// Follows `ray` through the scene's transparent objects by the law of refraction until it
/// leaves them all; the last ray, or `None` if it meets nothing or is reflected totally.
fn through(world: &World, mut ray: Ray) -> Option<Ray> {
    let scene = world.scene;
    for _ in 0..8 {
        let Some((object, hit)) = world.closest(&ray) else {
            return Some(ray);
        };
        let material = &scene.materials[scene.objects[object].material()];
        let entering = ray.dir.dot(hit.normal) < 0.0;
        let incident_side = if entering { hit.normal } else { -hit.normal };
        let dir = refract(ray.dir, incident_side, material.eta(entering))?;
        let p = ray.at(hit.t);
        let err = hit_point_error(&ray, hit.t) + scene.objects[object].shape.surface_error(p);
        ray = Ray::new(offset_origin(p, hit.normal, err, dir), dir);
    }
    None
}

#[test]
fn a_lens_images_a_point_where_the_thin_lens_equation_says() {
    let s = parse(&format!("{HEAD}{THIN_LENS}"), "t.toml").unwrap();
    let Shape::Lens(lens) = &s.objects[0].shape else {
        panic!("a lens")
    };
    let f = lens.focal_length(1.5);
    // Thick-lens formula: 1/f = 0.5 (2/10 - 0.5 d / 150), d = 0.02 + 2 (10 - sqrt(99)).
    let d = 0.02 + 2.0 * (10.0 - 99f64.sqrt());
    assert!((f - 1.0 / (0.5 * (0.2 - 0.5 * d / 150.0))).abs() < 1e-12, "{f}");
    let world = World::new(&s);
    for p in [25.0, 30.0, 60.0] {
        let q_expected = 1.0 / (1.0 / f - 1.0 / p);
        let source = DVec3::new(0.0, 0.0, -p);
        // Paraxial rays at heights 0.01 to 0.05 on the lens, in two azimuths: each crosses the
        // axis (x and y both 0) at its image distance.
        let mut crossings = Vec::new();
        for k in 1..=5 {
            let h = 0.01 * k as f64;
            for aim in [DVec3::new(h, 0.0, 0.0), DVec3::new(0.0, -h, 0.0)] {
                let out = through(&world, Ray::new(source, (aim - source).normalize())).unwrap();
                // Where the ray meets the axis: the radial coordinate goes to zero.
                let radial = |v: DVec3| if aim.x != 0.0 { v.x } else { v.y };
                let t = -radial(out.origin) / radial(out.dir);
                let at = out.at(t);
                assert!(at.x.abs() < 1e-12 && at.y.abs() < 1e-12, "{at}");
                crossings.push(at.z);
            }
        }
        let q = crossings.iter().sum::<f64>() / crossings.len() as f64;
        let error = (q - q_expected).abs() / q_expected;
        // Shown with --nocapture: the measured image distances.
        println!(
            "p = {p}: image at q = {q:.6}, thin-lens equation {q_expected:.6}, error {:.4} %",
            100.0 * error
        );
        assert!(
            error < 0.02,
            "p = {p}: image at {q}, the thin-lens equation says {q_expected}"
        );
        // The paraxial rays agree among themselves: they converge (spherical aberration of
        // these heights is far below the 2 %).
        let spread = crossings.iter().fold(0.0f64, |m, z| m.max((z - q).abs()));
        assert!(spread / q < 1e-3, "p = {p}: crossings {crossings:?}");
    }
}

#[test]
fn a_concave_lens_diverges() {
    // Biconcave, curvatures -10, edge 0.2 (the hollows are 0.05 deep each): f < 0, and a ray
    // parallel to the axis leaves it bending away from the axis, seeming to come from the
    // virtual focus at -|f| before the lens.
    let shapes = "[materials.glass]\nkt = 1\nn = 1.5\n\
        [[shapes]]\ntype = \"lens\"\nbase = [0, 0, -0.1]\nthickness = 0.2\nradius = 1\n\
        curvature1 = -10\ncurvature2 = -10\nmaterial = \"glass\"\n";
    let s = parse(&format!("{HEAD}{shapes}"), "t.toml").unwrap();
    let Shape::Lens(lens) = &s.objects[0].shape else {
        panic!("a lens")
    };
    let f = lens.focal_length(1.5);
    assert!(f < -9.0 && f > -11.0, "{f}");
    let world = World::new(&s);
    let out = through(&world, Ray::new(DVec3::new(0.02, 0.0, -5.0), DVec3::Z)).unwrap();
    assert!(out.dir.x > 0.0);
    // Traced back to the axis: z = -|f| within 2 %.
    let z = out.origin.z - out.origin.x * out.dir.z / out.dir.x;
    assert!((z - f).abs() / f.abs() < 0.02, "virtual focus at {z}, f = {f}");
}

#[test]
fn a_spherical_cap_is_open_at_its_rim_as_simrenderer_leaves_it() {
    // A hemisphere (rim radius 1, curvature 1) over the disk at the origin, bulging to +z.
    let shapes = "[materials.glass]\nkt = 1\nn = 1.5\n\
        [[shapes]]\ntype = \"spherical_cap\"\ncenter = [0, 0, 0]\nnormal = [0, 0, 1]\nradius = 1\ncurvature = 1\n\
        material = \"glass\"\n";
    let s = parse(&format!("{HEAD}{shapes}"), "t.toml").unwrap();
    assert!(!s.objects[0].shape.is_closed());
    let world = World::new(&s);
    // Up the axis from below: no flat face at z = 0; the first hit is the dome's inside at
    // z = 1, its normal still away from the sphere's center.
    let (_, hit) = world.closest(&Ray::new(DVec3::new(0.0, 0.0, -5.0), DVec3::Z)).unwrap();
    assert_eq!((hit.t, hit.normal), (6.0, DVec3::Z));
    // Across the disk's plane just below the rim: nothing there to meet.
    assert!(
        world
            .closest(&Ray::new(DVec3::new(-5.0, 0.0, -1e-9), DVec3::X))
            .is_none()
    );
    // A lens is closed: it refracts under SIMRenderer's conventions, an open cap does not.
    let lens = parse(&format!("{HEAD}{THIN_LENS}"), "t.toml").unwrap();
    assert!(lens.objects[0].shape.is_closed());
    let only_closed = Conventions::SIMRENDERER.refracting;
    assert!(only_closed.admits(lens.objects[0].shape.is_closed()));
    assert!(!only_closed.admits(s.objects[0].shape.is_closed()));
}

#[test]
fn bad_caps_and_lenses_give_located_errors() {
    let cases = [
        (
            "[[shapes]]\ntype = \"spherical_cap\"\ncenter = [0, 0, 0]\nradius = 2\ncurvature = 1.5\n",
            "t.toml:11:13: shapes[0].curvature: the radius of curvature must be at least the rim's radius 2 in \
             absolute value, got 1.5",
        ),
        (
            "[[shapes]]\ntype = \"lens\"\nbase = [0, 0, 0]\nthickness = 0.1\nradius = 1\ncurvature1 = -1\ncurvature2 = 5\n",
            "t.toml:13:14: shapes[0].curvature2: the concave caps are 1 deep in all, more than the edge's length 0.1: \
             the lens would be -0.9 thick at its center",
        ),
        (
            "[[shapes]]\ntype = \"lens\"\nbase = [0, 0, 0]\nthickness = -1\nradius = 1\ncurvature1 = 2\ncurvature2 = 2\n",
            "t.toml:10:13: shapes[0].thickness: must be a finite number in [0, 1e9], got -1",
        ),
    ];
    for (shapes, want) in cases {
        match parse(&format!("{HEAD}{shapes}"), "t.toml") {
            Ok(_) => panic!("parsed: {shapes}"),
            Err(e) => assert_eq!(e.to_string(), want),
        }
    }
}

/// The same lens and cap in SIMRenderer's keywords (French aliases and defaults included).
const SIMRENDERER: &str = "camera\nposition 0 -8 5\nlook_at 0 0 0\nend\n\
    material\nname verre\nkt 1\nn 1.5\nend\n\
    primitive\nmaterial_name verre\nlentille\npoint 0 0 -0.01\npoint 0 0 0.01\nrayon 1\ncourbure 10\ncourbure 10\nend\nend\n\
    primitive\nmaterial_name verre\ncalotte_spherique\nposition 3 0 0\nnormale 0 0 1\ncourbure -2\nend\nend\n\
    primitive\nlens\nend\nend\n";

#[test]
fn simrenderer_files_read_lenses_and_caps_and_convert_both_ways() {
    let opts = scene::simrenderer::Options::default();
    let parsed = scene::simrenderer::parse(SIMRENDERER, "lab.txt", &opts).unwrap();
    let s = &parsed.scene;
    let Shape::Lens(l) = &s.objects[0].shape else {
        panic!("{:?}", s.objects[0].shape)
    };
    assert_eq!((l.base, l.axis, l.radius), (DVec3::new(0.0, 0.0, -0.01), DVec3::Z, 1.0));
    assert_eq!((l.thickness, l.curvature1, l.curvature2), (0.02, 10.0, 10.0));
    let Shape::SphericalCap(c) = &s.objects[1].shape else {
        panic!("{:?}", s.objects[1].shape)
    };
    // The disk's default radius 1 with curvature -2.
    assert_eq!(
        (c.center, c.normal, c.radius, c.curvature),
        (DVec3::new(3.0, 0.0, 0.0), DVec3::Z, 1.0, -2.0)
    );
    // A lens of defaults: from (0, 0, 0) to (0, 0, 1), radius 1, both curvatures 1.
    let Shape::Lens(d) = &s.objects[2].shape else {
        panic!("{:?}", s.objects[2].shape)
    };
    assert_eq!(
        (d.base, d.thickness, d.radius, d.curvature1, d.curvature2),
        (DVec3::ZERO, 1.0, 1.0, 1.0, 1.0)
    );
    // To TOML and back, and to SIMRenderer and back: the same shapes to the bit.
    let toml = scene::simrenderer::to_toml(s, "lab.txt").unwrap();
    let back = parse(&toml.text, "back.toml").unwrap();
    let shapes = |s: &scene::Scene| s.objects.iter().map(|o| o.shape.clone()).collect::<Vec<_>>();
    assert_eq!(shapes(&back), shapes(s));
    let text = scene::simrenderer::to_simrenderer(&back, "back.toml", "image").unwrap();
    let again = scene::simrenderer::parse(&text.text, "again.txt", &opts).unwrap();
    assert_eq!(shapes(&again.scene), shapes(s));
}

#[test]
fn simrenderer_errors_on_lenses_and_caps_name_the_line() {
    let opts = scene::simrenderer::Options::default();
    let cases = [
        (
            "primitive\nspherical_cap\nray 2\ncurvature 1\nend\nend\n",
            "bad.txt:4:1: spherical_cap.curvature: the radius of curvature must be at least the rim's radius 2 in absolute value, got 1",
        ),
        (
            "primitive\nlens\ncurvature 2\ncurvature 2\ncurvature 3\nend\nend\n",
            "bad.txt:5:1: lens.curvature: a lens takes 2 curvatures (cap 1's, then cap 2's); this is one more",
        ),
    ];
    for (text, want) in cases {
        match scene::simrenderer::parse(text, "bad.txt", &opts) {
            Ok(_) => panic!("parsed: {text}"),
            Err(e) => assert_eq!(e.to_string(), want),
        }
    }
}

#[test]
fn the_optique_lens_figure_images_its_arrow_where_the_thick_lens_equations_say() {
    // The lens of scenes/figures/optique/04-lens.toml alone: axis +y, edge 0.1, radius 1.2, caps of
    // curvature 3, glass n = 1.5; the arrow's foot on the axis at p = 9 before its center.
    let mut s = scene::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/figures/optique/04-lens.toml"
    )))
    .unwrap();
    let names = s.names.clone();
    s.objects.retain(|o| names.get(o.name) == "lens");
    let Shape::Lens(lens) = &s.objects[0].shape else {
        panic!("a lens")
    };
    let n = 1.5;
    let f = lens.focal_length(n);
    // Thickness on the axis d = 0.1 + 2 (3 - sqrt(9 - 1.44)); the principal planes (Hecht,
    // "Optics", 6.2) at h1 = -f (n - 1) d / (n R2) from the first vertex and
    // h2 = -f (n - 1) d / (n R1) from the second, along the light, R1 = 3, R2 = -3; p and q
    // are measured from them.
    let cap = 3.0 - (9.0f64 - 1.44).sqrt();
    let d = 0.1 + 2.0 * cap;
    let (v1, v2) = (-0.05 - cap, 0.05 + cap);
    let (h1, h2) = (v1 - f * (n - 1.0) * d / (n * -3.0), v2 - f * (n - 1.0) * d / (n * 3.0));
    let p = h1 + 9.0;
    let image = h2 + 1.0 / (1.0 / f - 1.0 / p);
    assert!(
        (f - 3.1036).abs() < 1e-4 && (image - 4.8567).abs() < 1e-4,
        "f {f}, image at y = {image}"
    );
    let world = World::new(&s);
    let source = DVec3::new(0.0, -9.0, 0.0);
    let mut crossings = Vec::new();
    for k in 1..=5 {
        let aim = DVec3::new(0.0, 0.0, 0.01 * k as f64);
        let out = through(&world, Ray::new(source, (aim - source).normalize())).unwrap();
        crossings.push(out.origin.y - out.origin.z * out.dir.y / out.dir.z);
    }
    let y = crossings.iter().sum::<f64>() / crossings.len() as f64;
    println!("optique lens: image at y = {y:.6}, thick-lens equations {image:.6}");
    assert!(
        (y - image).abs() / image < 0.005,
        "image at {y}, expected {image}: {crossings:?}"
    );
}
