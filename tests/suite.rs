//! The integration tests: each file of `tests/` is a module of this one binary (its name
//! prefixes its tests' names: `cargo test --release --test suite shadows::`), so that the
//! library's generic code is compiled and linked once for all of them. `determinism.rs` is
//! a binary of its own (Cargo.toml), for CI's debug-build check of that file alone.

mod accel;
mod caustics;
mod cli;
mod common;
mod compare;
mod conventions;
mod culled_scans;
mod diagnose;
mod diagnose_size;
mod exit_codes;
mod family;
mod figures;
mod figures_check;
mod fuzz;
mod generate;
mod geometry;
mod guard;
mod interference;
mod invariance;
mod layers;
mod lenses;
mod located_errors;
mod lock;
mod model_materials;
mod no_light;
mod normalization;
mod output;
mod probe;
mod readme;
mod recursion;
mod reference;
mod review;
mod sampling;
mod scene_tables;
mod self_intersection;
mod shadows;
mod shards;
mod signals;
mod simrenderer;
mod simrenderer_convert;
mod simrenderer_formulas;
mod simrenderer_fuzz;
mod skips;
mod smooth_triangles;
mod soft_shadows;
mod stress;
mod textures;

/// With `autotests` off, a file of `tests/` that is not declared above is never compiled:
/// every one must be a module here, or a test target of Cargo.toml.
#[test]
fn every_test_file_is_compiled() {
    let tests = common::repo("tests");
    let suite = std::fs::read_to_string(tests.join("suite.rs")).unwrap();
    let manifest = std::fs::read_to_string(common::repo("Cargo.toml")).unwrap();
    let mut files = 0;
    for entry in std::fs::read_dir(&tests).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        let name = path.file_stem().unwrap().to_str().unwrap();
        let target = format!("path = \"tests/{name}.rs\"");
        assert!(
            suite.contains(&format!("\nmod {name};\n")) || manifest.contains(&target),
            "tests/{name}.rs is neither a module of tests/suite.rs nor a test target of Cargo.toml"
        );
        files += 1;
    }
    assert!(files >= 40, "{files} test files");
}
