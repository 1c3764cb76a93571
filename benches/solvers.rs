//! Time per torus intersection for each quartic solver (the speed half of the comparison in
//! BENCHMARKS.md, "Numerical stability"; the accuracy half is
//! `cargo run --release --example solver_errors`). The rays are the stress campaign's torus
//! families, seed 7: random, far, equatorial and axis rays, and origins on a large torus.
//!
//! `cargo bench --bench solvers -- --warm-up-time 1 --measurement-time 2`

use criterion::{Criterion, criterion_group, criterion_main};
use lumiere::math::Ray;
use lumiere::shape::{QuarticMethod, Shape, Torus};
use lumiere::stress::{Family, cases};
use std::hint::black_box;

fn torus_cases(family: Family) -> Vec<(Torus, Ray, f64)> {
    cases("torus", family, 256, 7)
        .into_iter()
        .map(|(spec, ray, t_min)| match spec.shape() {
            Shape::Torus(t) => (*t, ray, t_min),
            _ => unreachable!("torus cases hold tori"),
        })
        .collect()
}

fn solvers(c: &mut Criterion) {
    for family in [
        Family::Random,
        Family::Far,
        Family::TorusEquator,
        Family::TorusAxis,
        Family::TorusOnSurface,
    ] {
        let set = torus_cases(family);
        let mut group = c.benchmark_group(format!("torus/{}", family.name()));
        group.throughput(criterion::Throughput::Elements(set.len() as u64));
        for method in [
            QuarticMethod::Isolator,
            QuarticMethod::Ferrari,
            QuarticMethod::OrellanaDeMichele,
        ] {
            group.bench_function(format!("{method:?}"), |b| {
                b.iter(|| {
                    let mut hits = 0usize;
                    for (torus, ray, t_min) in &set {
                        hits += torus
                            .intersect_with(method, black_box(ray), *t_min, f64::INFINITY)
                            .is_some() as usize;
                    }
                    hits
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, solvers);
criterion_main!(benches);
