//! SIGINT (Ctrl-C), SIGTERM and SIGHUP sent to a running `lumiere render` and `lumiere
//! figures`: the exit code is 128 + the signal's number, the message says what was left,
//! no output or temporary file (`.NAME.tmp-PID`) is left, each figure set is wholly old or
//! wholly new and the gallery shows the sets written; a second signal ends a run that
//! waits where the first is not seen.
#![cfg(unix)]

use crate::common::*;
use std::collections::BTreeMap;
use std::fs;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, Stdio};

/// The signals, their exit codes and how the error message says the run was stopped.
const SIGNALS: [(i32, i32, &str); 3] = [
    (libc::SIGINT, 130, "interrupted;"),
    (libc::SIGTERM, 143, "interrupted by SIGTERM;"),
    (libc::SIGHUP, 129, "interrupted by SIGHUP;"),
];

fn send(child: &Child, signal: i32) {
    // SAFETY: sending a signal to our own child process, which has not been waited for.
    assert_eq!(unsafe { libc::kill(child.id() as i32, signal) }, 0);
}

/// Every file of a folder (not recursive), by name.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fs::read_dir(dir)
        .unwrap()
        .map(|f| {
            let f = f.unwrap();
            (f.file_name().into_string().unwrap(), fs::read(f.path()).unwrap())
        })
        .collect()
}

#[test]
fn a_signal_stops_a_render_and_leaves_no_file() {
    for (signal, code, how) in SIGNALS {
        let dir = temp_dir(&format!("signal-render-{signal}"));
        let out = dir.join("prism.png");
        // The prism at 800 x 600, 36 samples, depth 20, on one thread: about 6 s of rendering.
        // `-v` prints the scene summary once the scene is loaded and the handler installed,
        // just before the rows are rendered: the signal lands while they are.
        let mut child = Command::new(env!("CARGO_BIN_EXE_lumiere"))
            .args(["-v", "render", repo("scenes/prism.toml").to_str().unwrap(), "-o"])
            .arg(&out)
            .args(["--spp", "36", "--threads", "1"])
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stderr = BufReader::new(child.stderr.take().unwrap());
        let mut first = String::new();
        stderr.read_line(&mut first).unwrap();
        assert!(first.contains("800 x 600 pixels, 36 samples"), "{first}");
        send(&child, signal);
        let status = child.wait().unwrap();
        let mut rest = String::new();
        std::io::Read::read_to_string(&mut stderr, &mut rest).unwrap();
        assert_eq!(status.code(), Some(code), "{rest}");
        assert_eq!(rest, format!("lumiere: error: {how} no output was written\n"));
        // Neither the image nor its temporary file.
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 0);
    }
}

/// Checks that `dir` holds one complete figure set: its manifest's images, each PNG's
/// pixels hashing to the manifest's hash at the manifest's size, and the contact sheet.
fn assert_complete_set(dir: &Path, width: u32, height: u32) {
    let set = files(dir);
    let manifest: serde_json::Value = serde_json::from_slice(&set["manifest.json"]).unwrap();
    let images = manifest["images"].as_array().unwrap();
    assert!(!images.is_empty());
    for entry in images {
        let file = entry["file"].as_str().unwrap();
        let png = image::load_from_memory(&set[file]).unwrap().to_rgb8();
        assert_eq!((png.width(), png.height()), (width, height), "{file}");
        let hash = format!("fnv1a64:{:016x}", lumiere::film::fnv1a64(png.as_raw()));
        assert_eq!(entry["pixel_hash"], hash.as_str(), "{file}");
    }
    // The images, the contact sheet and the manifest; nothing else.
    assert_eq!(set.len(), images.len() + 2, "{:?}", set.keys());
    assert!(set.contains_key("contact-sheet.png"));
}

#[test]
fn a_signal_leaves_each_figure_set_wholly_old_or_wholly_new() {
    let out = temp_dir("signal-figures");
    let o = lumiere(&[
        "figures",
        "soft-shadows",
        "--scale",
        "0.05",
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let old_soft = files(&out.join("soft-shadows"));
    let old_index = fs::read(out.join("index.html")).unwrap();
    for (signal, code, how) in SIGNALS {
        let _ = fs::remove_dir_all(out.join("lighting"));
        // At scale 0.5 on one thread the lighting set takes about 0.3 s, the soft shadows
        // (N up to 1000 light points) about 6 s: the signal, sent when the lighting set is
        // reported written, lands while the soft shadows render.
        let mut child = Command::new(env!("CARGO_BIN_EXE_lumiere"))
            .args([
                "figures",
                "lighting",
                "soft-shadows",
                "--scale",
                "0.5",
                "--threads",
                "1",
            ])
            .arg("--out")
            .arg(&*out)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
        let first = lines.next().unwrap().unwrap();
        assert!(first.starts_with("lighting "), "{first}");
        send(&child, signal);
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(code), "{err}");
        // The soft shadows on disk are at scale 0.05, which the warning says before the run.
        assert_eq!(
            err,
            format!(
                "lumiere: warning: {}/soft-shadows holds the set at scale 0.05; this run writes it at scale 0.5\n\
                 lumiere: error: {how} figure set \"soft-shadows\" and the sets after it were left as they were; \
                 complete: [lighting]\n",
                out.display()
            )
        );
        // The set written before the signal is whole and new; the one being rendered is the
        // old one, byte for byte; the gallery shows both, as `figures --check` expects it;
        // no temporary file.
        assert_complete_set(&out.join("lighting"), 400, 300);
        assert_eq!(files(&out.join("soft-shadows")), old_soft);
        let index = fs::read_to_string(out.join("index.html")).unwrap();
        assert_ne!(index.as_bytes(), old_index);
        assert_eq!(
            index,
            lumiere::figures::gallery::index_html(&out, &lumiere::figures::registry().unwrap(), &[])
        );
        assert!(index.contains("<h2 id=\"lighting\">") && index.contains("<h2 id=\"soft-shadows\">"));
        let mut names: Vec<_> = fs::read_dir(&*out).unwrap().map(|f| f.unwrap().file_name()).collect();
        names.sort();
        assert_eq!(names, ["index.html", "lighting", "soft-shadows", "timings.json"]);
    }
}

/// Whether process `pid` has a handler for `signal` (its `SigCgt` mask in /proc).
fn catches(pid: u32, signal: i32) -> bool {
    let status = fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("SigCgt:"))
        .and_then(|mask| u64::from_str_radix(mask.trim(), 16).ok())
        .is_some_and(|mask| mask >> (signal - 1) & 1 == 1)
}

#[test]
fn a_second_signal_ends_a_run_blocked_on_a_pipe() {
    let dir = temp_dir("signal-twice");
    let fifo = dir.join("shard.fifo");
    let c_path = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a NUL-terminated path and a mode.
    assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0);
    let out = dir.join("merged.png");
    // `merge` opens the pipe, which no one writes: it waits there, where no flag is polled.
    let mut child = Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(["merge", fifo.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    while !catches(child.id(), libc::SIGINT) {
        assert!(started.elapsed().as_secs() < 30, "no handler installed");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    send(&child, libc::SIGINT);
    // The first only asks to stop: the run still waits on the pipe.
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert!(child.try_wait().unwrap().is_none());
    send(&child, libc::SIGINT);
    let ended = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if ended.elapsed().as_secs() >= 30 {
            child.kill().unwrap();
            panic!("the second SIGINT did not end the run");
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    };
    assert_eq!(status.code(), Some(130));
    assert!(!out.exists());
}
