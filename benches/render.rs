//! Whole renders through the library: the first figure of a few course sets at a quarter of
//! their size (what the linear scan serves), and the generated scenes of 1 000 and
//! 1 000 000 spheres at 200 x 150 (what the BVH serves; the scene is loaded and the BVH built
//! once, outside the timing). The full-size 800 x 600 comparison of the two sphere scenes,
//! with build time and memory, is the `lumiere render ... --stats` run in BENCHMARKS.md.
//!
//! `cargo bench --bench render -- --warm-up-time 1 --measurement-time 3`

use criterion::{Criterion, SamplingMode, criterion_group, criterion_main};
use lumiere::figures::{registry, render_figure};
use lumiere::render::render;
use lumiere::scene::load;
use lumiere::world::World;
use std::path::Path;

fn figures(c: &mut Criterion) {
    let mut g = c.benchmark_group("figure");
    g.sample_size(10);
    for set in registry()
        .expect("the figure files load")
        .into_iter()
        .filter(|s| ["lighting", "mirrors", "prism", "shading"].contains(&s.name.as_str()))
    {
        let first = set.figures[0].clone();
        g.bench_function(format!("{}/{}@0.25", set.name, first.stem), |b| {
            b.iter(|| render_figure(first.clone(), 0.25))
        });
    }
    g.finish();
}

fn spheres(c: &mut Criterion) {
    let mut g = c.benchmark_group("spheres");
    g.sample_size(10).sampling_mode(SamplingMode::Flat);
    for name in ["spheres-1k", "spheres-1m"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.toml"));
        let mut scene = load(&path).expect("the scene loads");
        scene.settings.width = 200;
        scene.settings.height = 150;
        let world = World::new(&scene);
        g.bench_function(format!("{name}@200x150"), |b| b.iter(|| render(&world, &|| {})));
    }
    g.finish();
}

criterion_group!(benches, figures, spheres);
criterion_main!(benches);
