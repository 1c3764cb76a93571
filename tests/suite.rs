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
mod output;
mod probe;
mod readme;
mod recursion;
mod reference;
mod review;
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
mod soft_shadows;
mod stress;
mod textures;
