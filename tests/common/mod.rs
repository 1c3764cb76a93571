//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod mutate;

use lumiere::compare::load_rgb8;
use lumiere::figures::provenance;
use lumiere::film::{Film, encode_png};
use lumiere::render::render;
use lumiere::scene::{self, Scene};
use lumiere::world::World;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Path of a file in the repository.
pub fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// Loads a scene from `scenes/`.
pub fn scene(name: &str) -> Scene {
    scene::load(&repo(&format!("scenes/{name}"))).expect("scene loads")
}

/// Renders at a reduced size on a pool of `threads` workers.
pub fn render_small(scene: &Scene, width: u32, height: u32, spp: u32, threads: usize) -> Film {
    let mut scene = scene.clone();
    scene.settings.width = width;
    scene.settings.height = height;
    scene.settings.samples_per_pixel = spp;
    let world = World::new(&scene);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| render(&world, &|| {})).0
}

/// Every channel of `pixels` as its bits, to compare radiances exactly.
pub fn radiance_bits(pixels: &[glam::DVec3]) -> Vec<u64> {
    pixels.iter().flat_map(|p| p.to_array()).map(f64::to_bits).collect()
}

/// Runs the `lumiere` binary with `args`.
pub fn lumiere(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(args)
        .output()
        .expect("lumiere runs")
}

/// `lumiere args` that must succeed: its standard output (its error in the panic otherwise).
pub fn lumiere_ok(args: &[&str]) -> String {
    let o = lumiere(args);
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Writes `text` to `dir/name`; its path as a string, for a command line.
pub fn write_in(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// Generates the lighting set at scale 0.05 (40 x 30) into `dir/figures`: the output,
/// which succeeded.
pub fn generate_lighting(dir: &Path) -> Output {
    let out = dir.join("figures");
    let o = lumiere(&[
        "figures",
        "lighting",
        "--scale",
        "0.05",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

/// `lumiere figures lighting --check` on `dir/figures`, the review folder `dir/review`:
/// the output, and its stdout as text.
pub fn check_lighting(dir: &Path) -> (Output, String) {
    check_lighting_in(&dir.join("figures"), &dir.join("review"))
}

/// `lumiere figures lighting --check` on `out`, the review folder `review`: the output, and
/// its stdout as text.
pub fn check_lighting_in(out: &Path, review: &Path) -> (Output, String) {
    let o = lumiere(&[
        "figures",
        "lighting",
        "--check",
        "--out",
        out.to_str().unwrap(),
        "--review",
        review.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    (o, stdout)
}

/// Rewrites the PNG `path` with its pixels (RGB8, rows of its width) changed by `edit`,
/// its provenance texts kept: its width, height, and pixels before and after.
pub fn edit_png_keeping_provenance(path: &Path, edit: impl FnOnce(&mut [u8], u32)) -> (u32, u32, Vec<u8>, Vec<u8>) {
    let png = std::fs::read(path).unwrap();
    let (w, h, before) = load_rgb8(path).unwrap();
    let mut after = before.clone();
    edit(&mut after, w);
    let texts = provenance::text_chunks(&png).unwrap();
    let texts: Vec<(&str, &str)> = texts.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
    std::fs::write(
        path,
        provenance::with_text(&encode_png(w, h, &after).unwrap(), &texts).unwrap(),
    )
    .unwrap();
    (w, h, before, after)
}

/// A fresh empty directory for one test (`lumiere-test-<name>-<pid>` in the system's
/// temporary directory), removed when the test passes: a failing test (one that panics)
/// leaves it behind to be looked at.
pub fn temp_dir(name: &str) -> TempDir {
    let dir = std::env::temp_dir().join(format!("lumiere-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    TempDir(dir)
}

/// See [`temp_dir`]; derefs to the directory's path.
pub struct TempDir(PathBuf);

impl std::ops::Deref for TempDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for TempDir {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// insta settings that store snapshots in the top-level `snapshots/` folder.
pub fn snapshot_settings() -> insta::Settings {
    let mut s = insta::Settings::clone_current();
    s.set_snapshot_path(repo("snapshots"));
    s.set_prepend_module_to_snapshot(false);
    s
}

/// Figure set `name` checked as `lumiere figures NAME --check` does, against the committed
/// files of `figures/` (the working folder of the tests is the repository's root): one line
/// per problem, none when every file is what a fresh render makes.
pub fn committed_set_mismatches(name: &str) -> Vec<String> {
    use lumiere::figures::{self, Reuse, Run, check};
    let sets = figures::registry().expect("the figure files load");
    let set = sets.iter().find(|s| s.name == name).expect("the set exists");
    let run = Run {
        scale: check::recorded_scale(Path::new(figures::DEFAULT_OUT), name, 1.0),
        ..Run::default()
    };
    let review = temp_dir(&format!("committed-{name}"));
    let checked = check::check_set(set, &run, &mut Reuse::default(), &review).expect("the set renders");
    checked.problems.iter().map(|p| p.to_string()).collect()
}
