//! Set `shading`, the IFT3355 slides (scenes/shading.toml: one sphere, one point light, grey
//! floor): ambient, diffuse, specular and combined terms; the Phong (R.E)^n and Blinn
//! (N.H)^n exponent sweeps n = 2 ... 512; metal versus plastic m = 0, 0.5, 1.

use crate::figures::{Figure, base_scene};
use crate::scene::{Scene, ShadingModel, Specular};

pub const EXPONENTS: [f64; 9] = [2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0, 512.0];

fn with_model(ambient: bool, diffuse: bool, specular: Specular) -> Scene {
    let mut s = base_scene("shading");
    s.settings.shading = ShadingModel {
        ambient,
        diffuse,
        specular,
    };
    s
}

/// The sphere's material is the scene's material "sphere".
fn sphere_material(scene: &mut Scene) -> &mut crate::material::Material {
    let i = scene
        .material_names
        .iter()
        .position(|n| n == "sphere")
        .expect("material sphere");
    &mut scene.materials[i]
}

pub fn figures() -> Vec<Figure> {
    let mut figures = vec![
        Figure::new(1, "ambient", "Ambiante", with_model(true, false, Specular::None)),
        Figure::new(2, "diffuse", "Diffuse", with_model(false, true, Specular::None)),
        Figure::new(3, "specular", "Spéculaire", with_model(false, false, Specular::Blinn)),
        Figure::new(4, "combined", "Combinée", with_model(true, true, Specular::Blinn)),
    ];
    for (model, name) in [(Specular::Phong, "phong"), (Specular::Blinn, "blinn")] {
        for n in EXPONENTS {
            let mut scene = with_model(true, true, model);
            sphere_material(&mut scene).shininess = n;
            let label = if model == Specular::Phong { "Phong" } else { "Blinn" };
            figures.push(Figure::new(
                figures.len() + 1,
                &format!("{name}-n{n}"),
                format!("{label}, n = {n}"),
                scene,
            ));
        }
    }
    for (m, caption) in [(0.0, "m = 0 (plastique)"), (0.5, "m = 0.5"), (1.0, "m = 1 (métal)")] {
        let mut scene = with_model(true, true, Specular::Blinn);
        sphere_material(&mut scene).metal = m;
        figures.push(Figure::new(
            figures.len() + 1,
            &format!("metal-{m}").replace('.', "p"),
            caption,
            scene,
        ));
    }
    figures
}
