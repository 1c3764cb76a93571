//! Every row of README.md's exit code table, run through the binary: 0 success, 2 bad input
//! (scene, option, and every error about an output path), 1 failed work (disk full, images
//! or figures that differ), 2 when another `figures` run holds the output folder. The rows
//! this file cannot reproduce are tested elsewhere: a read-only file system (no read-only
//! mount is at hand: `src/cli/error.rs` classifies EROFS), a full disk (ENOSPC, in the same
//! unit test; here a file-size limit fails the write in the same way) and the signals
//! (tests/signals.rs).
#![cfg(unix)]

use crate::common::*;
use std::fs;
use std::path::Path;
use std::process::Output;

/// Exit code, stdout and stderr.
fn result(o: Output) -> (i32, String, String) {
    (
        o.status.code().expect("exited, not killed by a signal"),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Renders the reference scene at 8 x 6, 1 sample, to `out`, with more arguments.
fn render(out: &Path, more: &[&str]) -> (i32, String, String) {
    let scene = repo("scenes/reference.toml");
    let mut args = vec![
        "render",
        scene.to_str().unwrap(),
        "--width",
        "8",
        "--height",
        "6",
        "--spp",
        "1",
        "-q",
    ];
    args.extend_from_slice(more);
    args.extend_from_slice(&["-o", out.to_str().unwrap()]);
    result(lumiere(&args))
}

#[test]
fn success() {
    let dir = temp_dir("exit-ok");
    let (code, _, err) = render(&dir.join("ok.png"), &[]);
    assert_eq!((code, err.as_str()), (0, ""));
    assert!(dir.join("ok.png").is_file());
}

#[test]
fn bad_scene_file() {
    let dir = temp_dir("exit-scene");
    let scene = dir.join("scene.toml");
    let text = "[image]\nwidth = 0\nheight = 10\n[camera]\nposition = [0, -8, 5]\nlook_at = [0, 1, 0]\n";
    fs::write(&scene, text).unwrap();
    let out = dir.join("out.png");
    let (code, _, err) = result(lumiere(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]));
    assert_eq!(code, 2, "{err}");
    assert!(
        err.ends_with("scene.toml:2:9: image.width: must be in [1, 16384] pixels, got 0\n"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn bad_options() {
    let dir = temp_dir("exit-option");
    let out = dir.join("out.png");
    let (code, _, err) = render(&out, &["--depth", "0"]);
    assert_eq!(code, 2);
    assert_eq!(
        first_line(&err),
        "error: invalid value '0' for '--depth <DEPTH>': must be in [1, 64] (1 = no secondary rays), got 0"
    );
    let (code, _, err) = render(&out, &["--accel", "fast"]);
    assert_eq!(code, 2);
    assert!(err.contains("invalid value 'fast' for '--accel <ACCEL>'"), "{err}");
    let (code, _, err) = result(lumiere(&["figures", "--scale", "9", "--out", dir.to_str().unwrap()]));
    assert_eq!(
        (code, first_line(&err)),
        (
            2,
            "error: invalid value '9' for '--scale <SCALE>': must be a finite number in (0, 4], got 9"
        )
    );
    assert_eq!(fs::read_dir(&*dir).unwrap().count(), 0);
}

/// The first line of clap's message (a blank line and a hint to `--help` follow it).
fn first_line(err: &str) -> &str {
    err.lines().next().unwrap_or_default()
}

/// A numeric option out of range is refused by the parser with the option, the range and
/// the value as written, negative or beyond 64 bits alike, and exit 2.
#[test]
fn numeric_options_name_their_range() {
    let dir = temp_dir("exit-ranges");
    let out = dir.join("out.png");
    let (o, scene) = (out.to_str().unwrap(), repo("scenes/reference.toml"));
    let render = |more: &[&'static str]| {
        let mut args = vec!["render", scene.to_str().unwrap(), "-o", o];
        args.extend_from_slice(more);
        args
    };
    let width =
        |v: &str| format!("error: invalid value '{v}' for '--width <WIDTH>': must be in [1, 16384] pixels, got {v}");
    let seed =
        "error: invalid value '-1' for '--seed <SEED>': must be in [0, 18446744073709551615], got -1".to_string();
    let threads =
        |v: &str| format!("error: invalid value '{v}' for '--threads <THREADS>': must be in [1, 1024], got {v}");
    let cases: Vec<(Vec<&str>, String)> = vec![
        (render(&["--width=-4"]), width("-4")),
        (render(&["--width", "-4"]), width("-4")),
        (
            render(&["--width", "99999999999999999999"]),
            width("99999999999999999999"),
        ),
        (render(&["--width", "1e400"]), width("1e400")),
        (render(&["--seed", "-1"]), seed.clone()),
        (render(&["--seed=-1"]), seed),
        (render(&["--threads", "0"]), threads("0")),
        (render(&["--threads", "-1"]), threads("-1")),
        (
            vec!["study", "soft-shadows", "--points", "1,-4,16", "--out", o],
            "error: invalid value '-4' for '--points <POINTS>': must be in [1, 100000], got -4".into(),
        ),
        (
            vec!["compare", o, o, "--tolerance", "-1"],
            "error: invalid value '-1' for '--tolerance <TOLERANCE>': must be in [0, 255], got -1".into(),
        ),
        (
            vec!["figures", "--scale", "5", "--out", o],
            "error: invalid value '5' for '--scale <SCALE>': must be a finite number in (0, 4], got 5".into(),
        ),
    ];
    for (args, line) in cases {
        let (code, _, err) = result(lumiere(&args));
        assert_eq!((code, first_line(&err)), (2, line.as_str()), "{args:?}");
    }
    assert_eq!(fs::read_dir(&*dir).unwrap().count(), 0);
}

#[cfg(target_os = "linux")]
#[test]
fn output_in_a_directory_that_cannot_be_written() {
    // /proc takes no new files, for root too (permission bits do not stop root, so a
    // read-only temporary directory would not do when the tests run as root).
    let (code, _, err) = render(Path::new("/proc/lumiere-exit-code-test.png"), &[]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.starts_with("lumiere: error: /proc/lumiere-exit-code-test.png: cannot write the image: "),
        "{err}"
    );
    let (code, _, err) = result(lumiere(&[
        "figures",
        "lighting",
        "--scale",
        "0.05",
        "--out",
        "/proc/lumiere-figures",
    ]));
    assert_eq!(code, 2, "{err}");
    assert!(err.starts_with("lumiere: error: /proc/lumiere-figures: cannot create the output directory: "));
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 {
        use std::os::unix::fs::PermissionsExt;
        let dir = temp_dir("exit-unwritable");
        let locked = dir.join("locked");
        fs::create_dir(&locked).unwrap();
        fs::set_permissions(&locked, fs::Permissions::from_mode(0o555)).unwrap();
        let (code, _, err) = render(&locked.join("out.png"), &[]);
        fs::set_permissions(&locked, fs::Permissions::from_mode(0o755)).unwrap();
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("cannot write the image: Permission denied"), "{err}");
        assert_eq!(fs::read_dir(&locked).unwrap().count(), 0);
    }
}

#[test]
fn output_is_a_directory() {
    let dir = temp_dir("exit-isdir");
    let taken = dir.join("taken.png");
    fs::create_dir(&taken).unwrap();
    let (code, _, err) = render(&taken, &[]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "lumiere: error: {}: the output is a directory; name a file in it\n",
            taken.display()
        )
    );
    // Nothing written beside it or in it.
    assert_eq!(fs::read_dir(&*dir).unwrap().count(), 1);
    assert_eq!(fs::read_dir(&taken).unwrap().count(), 0);
}

#[test]
fn output_directory_missing() {
    let dir = temp_dir("exit-missing");
    let out = dir.join("no/such/out.png");
    let (code, _, err) = render(&out, &[]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "lumiere: error: {}: the output directory {} does not exist\n",
            out.display(),
            dir.join("no/such").display()
        )
    );
    assert_eq!(fs::read_dir(&*dir).unwrap().count(), 0);
}

#[test]
fn output_directory_is_a_file() {
    let dir = temp_dir("exit-notdir");
    let file = dir.join("file");
    fs::write(&file, "x").unwrap();
    let out = file.join("out.png");
    let (code, _, err) = render(&out, &[]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "lumiere: error: {}: {} is not a directory\n",
            out.display(),
            file.display()
        )
    );
    // The same for a figures folder that is a file.
    let (code, _, err) = result(lumiere(&[
        "figures",
        "lighting",
        "--scale",
        "0.05",
        "--out",
        file.to_str().unwrap(),
    ]));
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!("lumiere: error: --out: {} is a file, not a folder\n", file.display())
    );
    assert_eq!(fs::read(&file).unwrap(), b"x");
}

#[test]
fn storage_exhausted_while_writing() {
    use std::os::unix::process::CommandExt;
    // A file-size limit of 1 KiB makes the write of the 200 x 150 PNG (about 20 KB) fail
    // partway, as a full disk does: failed work, exit 1, and the partial temporary file is
    // removed. (A full disk itself, ENOSPC, is classified in src/cli/error.rs's unit test.)
    let dir = temp_dir("exit-full");
    let out = dir.join("out.png");
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_lumiere"));
    command
        .args(["render", repo("scenes/reference.toml").to_str().unwrap()])
        .args(["--width", "200", "--height", "150", "--spp", "1", "-q", "-o"])
        .arg(&out);
    // SAFETY: only async-signal-safe calls between fork and exec. SIGXFSZ at its default
    // action (ending the process): lumiere ignores it itself, so that a write past the
    // limit fails with EFBIG.
    unsafe {
        command.pre_exec(|| {
            libc::signal(libc::SIGXFSZ, libc::SIG_DFL);
            let limit = libc::rlimit {
                rlim_cur: 1024,
                rlim_max: 1024,
            };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let (code, _, err) = result(command.output().unwrap());
    assert_eq!(code, 1, "{err}");
    assert!(
        err.starts_with(&format!(
            "lumiere: error: {}: cannot write the image: File too large",
            out.display()
        )),
        "{err}"
    );
    assert_eq!(fs::read_dir(&*dir).unwrap().count(), 0);
}

#[test]
fn images_differ() {
    let dir = temp_dir("exit-compare");
    let (a, b) = (dir.join("a.png"), dir.join("b.png"));
    fs::write(&a, lumiere::film::encode_png(2, 1, &[0, 0, 0, 9, 9, 9]).unwrap()).unwrap();
    fs::write(&b, lumiere::film::encode_png(2, 1, &[0, 0, 0, 9, 9, 12]).unwrap()).unwrap();
    let (code, out, err) = result(lumiere(&["compare", a.to_str().unwrap(), b.to_str().unwrap()]));
    assert_eq!(code, 1);
    assert!(
        out.contains("differing pixels   1 of 2 (50.0000 %) beyond 0 levels"),
        "{out}"
    );
    assert_eq!(
        err,
        "lumiere: error: 1 of 2 pixels (50.0000 %) differ by more than 0 levels; allowed: 0 % (--max-fraction 0)\n"
    );
    let (code, _, _) = result(lumiere(&[
        "compare",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--tolerance",
        "3",
    ]));
    assert_eq!(code, 0);
}

#[test]
fn figures_differ_from_their_manifests() {
    let dir = temp_dir("exit-check");
    let d = dir.to_str().unwrap();
    let (code, _, err) = result(lumiere(&["figures", "lighting", "--scale", "0.05", "-q", "--out", d]));
    assert_eq!(code, 0, "{err}");
    let review = dir.join("review");
    let r = review.to_str().unwrap();
    let (code, out, _) = result(lumiere(&["figures", "lighting", "--check", "--out", d, "--review", r]));
    assert_eq!(
        (code, out.as_str()),
        (0, "lighting     ok (at scale 0.05, as its manifest records)\n")
    );
    // One manifest hash changed: that figure differs.
    let path = dir.join("lighting/manifest.json");
    let mut manifest: serde_json::Value = serde_json::from_slice(&fs::read(&path).unwrap()).unwrap();
    let entry = &mut manifest["images"][0];
    let (file, hash) = (
        entry["file"].as_str().unwrap().to_string(),
        entry["pixel_hash"].as_str().unwrap().to_string(),
    );
    entry["pixel_hash"] = "fnv1a64:0000000000000000".into();
    fs::write(&path, serde_json::to_string_pretty(&manifest).unwrap()).unwrap();
    let (code, out, err) = result(lumiere(&["figures", "lighting", "--check", "--out", d, "--review", r]));
    assert_eq!(code, 1);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines[0],
        format!("lighting/{file}: pixel hash {hash}, its manifest says fnv1a64:0000000000000000")
    );
    assert_eq!(
        lines[1],
        format!("lighting/manifest.json: differs from its regenerated self in images[{file}].pixel_hash")
    );
    assert_eq!(
        lines[2..],
        [
            "lighting     DIFFERS (at scale 0.05, as its manifest records)",
            &format!("review page: {r}/index.html")
        ]
    );
    assert_eq!(
        err,
        format!(
            "lumiere: error: 2 problems: the figures on disk differ from their sets (`lumiere figures lighting --scale 0.05 --out {d}` regenerates them; a change made on purpose is accepted as docs/figures.md, \"Changing a figure on purpose\", says)\n"
        )
    );
}

#[test]
fn output_folder_locked_by_another_run() {
    // This test holds the lock the way a running `lumiere figures` does.
    let dir = temp_dir("exit-lock");
    let lock = fs::File::create(dir.join(".lumiere-figures.lock")).unwrap();
    lock.lock().unwrap();
    fs::write(
        dir.join(".lumiere-figures.lock"),
        "pid 4242: lumiere figures (held by a test)\n",
    )
    .unwrap();
    let d = dir.to_str().unwrap();
    let (code, _, err) = result(lumiere(&["figures", "lighting", "--scale", "0.05", "--out", d]));
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "lumiere: error: {d}: another lumiere figures run is writing into this folder \
             (pid 4242: lumiere figures (held by a test)); run again when it has ended, or choose another --out\n"
        )
    );
    // Nothing was written, and the holder's lock file is left to it.
    let names: Vec<_> = fs::read_dir(&*dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, [".lumiere-figures.lock"]);
    drop(lock);
}

#[test]
fn input_file_too_long() {
    let dir = temp_dir("exit-too-long");
    // Sparse files one byte over the limit: refused from their size, before any is read.
    let long = |name: &str| {
        let path = dir.join(name);
        fs::File::create(&path).unwrap().set_len((1 << 30) + 1).unwrap();
        path.display().to_string()
    };
    let said = |file: &str, action: &str| {
        format!(
            "lumiere: error: {file}: {action}: the file has 1073741825 bytes, more than the 1073741824 bytes read from one file\n"
        )
    };
    let out = dir.join("out.png").display().to_string();
    let (scene, image, shard) = (long("s.toml"), long("i.png"), long("p.shard"));
    for (args, message) in [
        (
            vec!["render", &scene, "-o", &out],
            said(&scene, "cannot read the scene file"),
        ),
        (vec!["compare", &image, &image], said(&image, "cannot read the file")),
        (vec!["merge", &shard, "-o", &out], said(&shard, "cannot read")),
    ] {
        let (code, stdout, err) = result(lumiere(&args));
        assert_eq!((code, stdout.as_str(), err), (2, "", message), "{args:?}");
    }
    assert!(!dir.join("out.png").exists());
}

#[test]
fn the_readme_table_names_these_tests() {
    let readme = fs::read_to_string(repo("README.md")).unwrap();
    let this = fs::read_to_string(repo("tests/exit_codes.rs")).unwrap();
    let rows: Vec<&str> = readme
        .lines()
        .skip_while(|l| !l.starts_with("| Case | Example | Exit code | Test |"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .collect();
    assert_eq!(rows.len(), 15, "{rows:?}");
    let mut named = 0;
    for row in rows {
        let test = row.trim_end_matches('|').rsplit('|').next().unwrap();
        // Test functions are the backquoted words without a path separator or a dot.
        for name in test.split('`').skip(1).step_by(2) {
            if !name.contains(['/', '.']) {
                assert!(this.contains(&format!("fn {name}()")), "README names no test {name}");
                named += 1;
            }
        }
    }
    assert_eq!(named, 13);
}
