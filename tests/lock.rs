//! One `lumiere figures` run at a time in an output folder: a second run on a folder that
//! a running one writes into is refused (exit 2) with the holder's pid and command line,
//! and the first completes as if alone; a lock file left by a run that ended without
//! removing it is taken over.

use crate::common::*;
use std::fs;
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

const LOCK: &str = ".lumiere-figures.lock";

/// The folder's entries, by name, sorted.
fn names(dir: &std::path::Path) -> Vec<String> {
    let mut n: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    n.sort();
    n
}

#[test]
fn a_second_run_is_refused_while_the_first_completes() {
    let out = temp_dir("lock-concurrent");
    let bin = env!("CARGO_BIN_EXE_lumiere");
    let first_args = [
        "figures",
        "lighting",
        "mirrors",
        "--scale",
        "0.5",
        "--threads",
        "1",
        "--out",
    ];
    // On one thread the lighting set takes about 0.3 s, the mirrors about 1.6 s: the second
    // run starts when the lighting set is reported written, while the mirrors render.
    let mut first = Command::new(bin)
        .args(first_args)
        .arg(&*out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(first.stdout.take().unwrap()).lines();
    let line = lines.next().unwrap().unwrap();
    assert!(line.starts_with("lighting "), "{line}");

    let second = lumiere(&[
        "figures",
        "lighting",
        "--scale",
        "0.05",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(second.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&second.stderr),
        format!(
            "lumiere: error: {0}: another lumiere figures run is writing into this folder (pid {1}: {bin} {2} {0}); \
             run again when it has ended, or choose another --out\n",
            out.display(),
            first.id(),
            first_args.join(" ")
        )
    );

    let rest: Vec<String> = lines.map(Result::unwrap).collect();
    let o = first.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(rest[0].starts_with("mirrors "), "{rest:?}");
    // Both sets are the first run's (400 x 300, not the refused run's 40 x 30), the gallery
    // is written with the run's times, and neither the lock file nor a temporary file is left.
    for set in ["lighting", "mirrors"] {
        let manifest: serde_json::Value =
            serde_json::from_slice(&fs::read(out.join(set).join("manifest.json")).unwrap()).unwrap();
        assert_eq!(manifest["scale"], 0.5);
        for entry in manifest["images"].as_array().unwrap() {
            let png = image::open(out.join(set).join(entry["file"].as_str().unwrap())).unwrap();
            assert_eq!((png.width(), png.height()), (400, 300));
        }
    }
    assert_eq!(names(&out), ["index.html", "lighting", "mirrors", "timings.json"]);
}

#[test]
fn a_lock_file_left_behind_is_taken_over() {
    // A run killed outright (SIGKILL) leaves its lock file, but the lock itself ends with
    // its process: the next run takes the file over and removes it at its end.
    let out = temp_dir("lock-stale");
    fs::write(out.join(LOCK), "pid 1: lumiere figures (ended)\n").unwrap();
    let o = lumiere(&[
        "figures",
        "lighting",
        "--scale",
        "0.05",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(names(&out), ["index.html", "lighting", "timings.json"]);
}
