//! Renders a scene with one named mistake of `lumiere diagnose`'s catalogue
//! (src/diagnose/mistakes.rs), as a student's ray tracer with that mistake would: the
//! deliberately wrong image of README's "Checking your ray tracer"
//! (tests/fixtures/diagnose/phong-for-blinn.png) is made so.
//!
//! `cargo run --release --example mistake_image -- SCENE MISTAKE OUT.png WIDTH HEIGHT`
//!
//! The scene is rendered at WIDTH x HEIGHT with one sample at each pixel's centre
//! (`sample_position = center`). `lumiere diagnose --list` lists the mistakes.

use lumiere::diagnose::mistakes::catalogue;
use lumiere::diagnose::render_mistake;
use lumiere::film::{encode_png, write_atomic};
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let list = catalogue();
    let [scene, name, out, width, height] = &args[..] else {
        return Err(
            "usage: mistake_image SCENE MISTAKE OUT.png WIDTH HEIGHT (`lumiere diagnose --list` lists the mistakes)"
                .into(),
        );
    };
    let mistake = list
        .iter()
        .find(|m| m.name == name)
        .ok_or_else(|| format!("no mistake {name:?} (`lumiere diagnose --list` lists them)"))?;
    let mut scene = lumiere::scene::load(Path::new(scene))?;
    scene.settings.width = width.parse()?;
    scene.settings.height = height.parse()?;
    scene.settings.samples_per_pixel = 1;
    let mut conventions = scene.settings.conventions;
    conventions.set("sample_position", "center")?;
    scene.set_conventions(conventions);
    let rgb = render_mistake(&scene, mistake).ok_or("the mistake does not apply to this scene")?;
    write_atomic(
        Path::new(out),
        &encode_png(scene.settings.width, scene.settings.height, &rgb)?,
    )?;
    Ok(())
}
