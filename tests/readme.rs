//! Every command README.md shows is run here, in order, in a scratch directory (with the
//! repository's `scenes/` and `tests/fixtures/` linked and `figures/lighting/` copied in),
//! and must succeed.
//! `cargo` lines are the build and test steps themselves; `parallel` lines are expanded as
//! GNU parallel would. Only the commands in `SHRUNK` are changed, to keep the suite fast.
//! A bare ``` block right after a ```sh block is an excerpt of the output of that block's
//! last command: its lines must be the command's real output (see `assert_excerpt`).

use crate::common::*;
use std::path::Path;
use std::process::Command;

/// Commands too slow for the suite at full size, and what runs instead.
const SHRUNK: [(&str, &str); 2] = [
    // Re-renders every set at full size (about a minute): the lighting set is checked here,
    // tests/figures.rs checks it too, and the full check is a documented maintainer command.
    ("lumiere figures --check", "lumiere figures lighting --check"),
    (
        "lumiere figures mirrors prism",
        "lumiere figures mirrors prism --scale 0.05",
    ),
];

/// The `cargo` commands the README may show.
const CARGO: [&str; 4] = [
    "cargo build --release",
    "cargo test --release",
    "cargo run --release -- figures",
    // The debug-build check of .ci/run (README, "Tests and CI").
    "cargo test --test determinism reference_scene_hash_is_pinned",
];

/// A command of the README's ```sh blocks, without its trailing comment, and the output
/// excerpt shown after it, if any.
struct Step {
    command: String,
    excerpt: Option<Vec<String>>,
}

/// The commands of the README's ```sh blocks, in order, each with its output excerpt: the
/// lines of a bare ``` block that follows a ```sh block with only blank lines between
/// belong to that block's last command.
fn steps() -> Vec<Step> {
    let text = std::fs::read_to_string(repo("README.md")).unwrap();
    let mut steps: Vec<Step> = Vec::new();
    // The fence language of the open block, if one is open.
    let mut open: Option<String> = None;
    // Whether the last closed block was ```sh with nothing but blank lines since.
    let mut after_sh = false;
    for line in text.lines() {
        if let Some(fence) = line.strip_prefix("```") {
            match open.take() {
                Some(lang) => after_sh = lang == "sh",
                None => {
                    let lang = fence.trim().to_string();
                    if lang.is_empty() && after_sh {
                        steps.last_mut().expect("a command").excerpt = Some(Vec::new());
                    }
                    open = Some(if lang.is_empty() && after_sh {
                        "excerpt".into()
                    } else {
                        lang
                    });
                }
            }
            continue;
        }
        match open.as_deref() {
            Some("sh") => {
                let cmd = line.split("  #").next().unwrap().trim();
                if !cmd.is_empty() {
                    steps.push(Step {
                        command: cmd.to_string(),
                        excerpt: None,
                    });
                }
            }
            Some("excerpt") => {
                let excerpt = steps.last_mut().and_then(|s| s.excerpt.as_mut()).unwrap();
                excerpt.push(line.to_string());
            }
            Some(_) => {}
            None => after_sh &= line.trim().is_empty(),
        }
    }
    steps
}

/// Runs `command` (a `lumiere` line) in `dir`; it must succeed. Returns its stdout.
fn run(dir: &Path, command: &str) -> String {
    let words: Vec<&str> = command.split_whitespace().collect();
    assert_eq!(words[0], "lumiere", "{command}");
    let out = Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(&words[1..])
        .current_dir(dir)
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "README command failed: {command}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// An excerpt is runs of lines separated by `...` lines (output left out). Each run must
/// appear as consecutive whole lines of `output`, the runs in order.
fn assert_excerpt(command: &str, output: &str, excerpt: &[String]) {
    let out: Vec<&str> = output.lines().collect();
    let mut from = 0;
    for run in excerpt.split(|l| l == "...").filter(|r| !r.is_empty()) {
        let at = (from..=out.len().saturating_sub(run.len()))
            .find(|&i| out[i..i + run.len()].iter().zip(run).all(|(a, b)| a == b))
            .unwrap_or_else(|| {
                panic!(
                    "README's output of `{command}` is stale: these lines are not in the real output \
                     (after line {from}):\n{}\n--- real output:\n{output}",
                    run.join("\n")
                )
            });
        from = at + run.len();
    }
}

#[test]
fn every_readme_command_runs() {
    let dir = temp_dir("readme");
    std::os::unix::fs::symlink(repo("scenes"), dir.join("scenes")).unwrap();
    std::fs::create_dir_all(dir.join("tests")).unwrap();
    std::os::unix::fs::symlink(repo("tests/fixtures"), dir.join("tests/fixtures")).unwrap();
    let lighting = dir.join("figures/lighting");
    std::fs::create_dir_all(&lighting).unwrap();
    for f in std::fs::read_dir(repo("figures/lighting")).unwrap() {
        let f = f.unwrap().path();
        std::fs::copy(&f, lighting.join(f.file_name().unwrap())).unwrap();
    }
    let tmp = format!("{}/", dir.join("tmp").display());
    std::fs::create_dir_all(dir.join("tmp")).unwrap();
    let mut ran = 0;
    let mut excerpts = 0;
    for step in steps() {
        let line = step
            .command
            .replace("./target/release/lumiere", "lumiere")
            .replace("/tmp/", &tmp);
        assert!(
            step.excerpt.is_none() || !(line.starts_with("cargo ") || line.starts_with("parallel ")),
            "an output excerpt after `{line}` cannot be checked"
        );
        if line.starts_with("cargo ") {
            assert!(
                CARGO.contains(&line.as_str()),
                "unexpected cargo line in README: {line}"
            );
            // `cargo test --test FILE NAME` passes when no test matches NAME: the test must
            // exist, or the check it stands for (the debug build's in .ci/run) is gone.
            if let ["cargo", "test", "--test", file, name] = line.split_whitespace().collect::<Vec<_>>()[..] {
                let source = std::fs::read_to_string(repo(&format!("tests/{file}.rs"))).unwrap();
                assert!(
                    source.contains(&format!("fn {name}()")),
                    "README: no test {name} in tests/{file}.rs"
                );
            }
            continue;
        }
        let line = SHRUNK
            .iter()
            .find(|(from, _)| *from == line)
            .map_or(line.clone(), |(_, to)| to.to_string());
        if let Some(rest) = line.strip_prefix("parallel ") {
            let (template, args) = rest.split_once(" ::: ").unwrap();
            for arg in args.split_whitespace() {
                run(&dir, &template.replace("{}", arg));
                ran += 1;
            }
            continue;
        }
        let output = run(&dir, &line);
        ran += 1;
        if let Some(excerpt) = &step.excerpt {
            assert_excerpt(&line, &output, excerpt);
            excerpts += 1;
        }
    }
    assert!(ran >= 15, "only {ran} commands found in README.md");
    // The probe trace of "Why is this pixel this colour?".
    assert!(excerpts >= 1, "no output excerpt found in README.md");
    // The walkthrough's point: the reference scene re-rendered equals the figure exactly.
    let o = Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(["compare", "mine.png", "preview/lighting/03-ambient-directional.png"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&o.stdout).contains("max difference     0 levels"));
    // The README's last reference.png is the merge of 8 shards: it must equal a one-machine render.
    run(&dir, "lumiere render scenes/reference.toml -o whole.png");
    assert_eq!(
        std::fs::read(dir.join("reference.png")).unwrap(),
        std::fs::read(dir.join("whole.png")).unwrap()
    );
}

/// The names the scene reader accepts for one choice, as its error for `bad` lists them:
/// the quoted names of `must be "a", "b" or "c", got "bad"`.
fn accepted(scene: &str) -> Vec<String> {
    let e = lumiere::scene::parse(scene, "s.toml").unwrap_err().to_string();
    let (list, _) = e
        .split_once(", got \"bad\"")
        .unwrap_or_else(|| panic!("not a list of the accepted names: {e}"));
    let names: Vec<String> = list.split('"').skip(1).step_by(2).map(String::from).collect();
    assert!(names.len() >= 2, "{e}");
    names
}

/// The text of the section of `readme` whose heading starts with `heading` (`## Shapes`),
/// up to the next heading of its level or above.
fn section<'t>(readme: &'t str, heading: &str) -> &'t str {
    let start = readme
        .find(&format!("\n{heading}"))
        .unwrap_or_else(|| panic!("no section {heading}"));
    let level = heading.split(' ').next().unwrap();
    let rest = &readme[start + 1..];
    let end = rest[1..]
        .match_indices("\n#")
        .map(|(i, _)| i + 1)
        .find(|&i| {
            // A heading, not a comment line of a code block (`# ...`).
            let marks = rest[i + 1..].split(' ').next().unwrap_or("");
            marks.len() >= 2 && marks.len() <= level.len() && marks.chars().all(|c| c == '#')
        })
        .unwrap_or(rest.len());
    &rest[..end]
}

#[test]
fn scenes_readme_lists_every_object_type_the_reader_accepts() {
    let readme = std::fs::read_to_string(repo("scenes/README.md")).unwrap();
    const HEAD: &str = "[image]\nwidth = 8\nheight = 6\n[camera]\nposition = [0, -5, 0]\nlook_at = [0, 0, 0]\n";
    let cases = [
        ("## Shapes", "[[shapes]]\ntype = \"bad\"\n", "| `{}` |"),
        ("## Lights", "[[lights]]\ntype = \"bad\"\n", "`{}`"),
        (
            "### Area lights",
            "[[lights]]\ntype = \"area\"\nshape = \"bad\"\npoints = 4\n",
            "| `{}` |",
        ),
        (
            "## Generated objects",
            "[[generate]]\nkind = \"bad\"\ncount = 1\nmin = [0, 0, 0]\nmax = [1, 1, 1]\nradius = [0.1, 0.2]\n",
            "`\"{}\"`",
        ),
    ];
    for (heading, entry, written) in cases {
        let text = section(&readme, heading);
        for name in accepted(&format!("{HEAD}{entry}")) {
            let shown = written.replace("{}", &name);
            assert!(text.contains(&shown), "scenes/README.md, {heading}: no {shown}");
        }
    }
}

#[test]
fn scenes_readme_error_examples_are_what_the_reader_prints() {
    let readme = std::fs::read_to_string(repo("scenes/README.md")).unwrap();
    let examples = section(&readme, "## Errors");
    const HEAD: &str = "[image]\nwidth = 8\nheight = 6\n[camera]\nposition = [0, -5, 0]\nlook_at = [0, 0, 0]\n";
    let sphere = |fields: &str| format!("{HEAD}[[shapes]]\ntype = \"sphere\"\n{fields}\n");
    for scene in [
        sphere("center = [0, 0, 0]\nradius = -1"),
        sphere("center = [0, 0]\nradius = 1"),
        format!("{HEAD}[[shapes]]\ntype = \"sphear\"\n"),
        HEAD.replace("width = 8", "width = -4"),
        // The reference scene's vfov (line 15) given again on line 16.
        std::fs::read_to_string(repo("scenes/reference.toml"))
            .unwrap()
            .replace("vfov = 60", "vfov = 60\nvfov = 70"),
    ] {
        let e = lumiere::scene::parse(&scene, "s.toml").unwrap_err().to_string();
        // `s.toml:LINE:COLUMN: FIELD: MESSAGE`: the example's place and entry index differ.
        let message = e.splitn(3, ": ").nth(2).unwrap();
        assert!(
            examples.contains(message),
            "scenes/README.md, ## Errors: no {message:?}"
        );
    }
    // A Latin-1 byte, placed as the reader of either format places it.
    let e = lumiere::scene::text_of(b"[image]\n# lumi\xe8re\n".to_vec(), "s.toml").unwrap_err();
    let shown = e.to_string();
    let message = shown.splitn(3, ": ").nth(2).unwrap();
    assert!(
        examples.contains(message),
        "scenes/README.md, ## Errors: no {message:?}"
    );
    // README's one example, with its field.
    let e = lumiere::scene::parse(&sphere("center = [0, 0, 0]\nradius = -1"), "s.toml").unwrap_err();
    let shown = e.to_string();
    let (_, field_and_message) = shown.split_once(": ").unwrap();
    let readme = std::fs::read_to_string(repo("README.md")).unwrap();
    assert!(
        readme.contains(field_and_message),
        "README.md: no {field_and_message:?}"
    );
}
