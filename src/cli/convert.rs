//! `lumiere convert`: a scene file written in the other format (lumiere's TOML, or
//! SIMRenderer's keyword blocks), refused by name where that format cannot say something,
//! read back once written to name anything that does not give the same scene to the bit.

use super::{CliError, Reading, Verbosity, check_output_path, noun_for, preset, read_scene};
use clap::Args;
use lumiere::film::{WriteError, write_atomic};
use lumiere::scene::{self, Format, simrenderer};
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// The scene file to read (TOML or SIMRenderer).
    pub input: PathBuf,
    /// The file to write.
    #[arg(short, long)]
    pub output: PathBuf,
    /// The output's format (default: TOML when its name ends in .toml, else SIMRenderer); a
    /// name that would have the file read in the other format is warned about.
    #[arg(long, value_parser = super::format_values())]
    pub to: Option<Format>,
    #[command(flatten)]
    pub reading: Reading,
    /// A SIMRenderer input's conventions under its own settings: a preset, `chapter` or
    /// `simrenderer` (the default).
    #[arg(long, value_name = "PRESET")]
    pub conventions: Option<String>,
}

/// Refuses an output named as an image (`.png`, `.exr`, `.jpg`, ...): convert writes a scene
/// file, and such a name is most often meant for `lumiere render`.
fn check_not_an_image(output: &Path) -> Result<(), CliError> {
    let image = lumiere::output::Format::of(output).is_ok() || image::ImageFormat::from_path(output).is_ok();
    if !image {
        return Ok(());
    }
    let ext = output
        .extension()
        .map_or(String::new(), |e| e.to_string_lossy().into_owned());
    Err(CliError::BadInput(format!(
        "{}: .{ext} names an image, and convert writes a scene file: name it .txt (SIMRenderer) or .toml (lumiere); `lumiere render` writes the image",
        output.display()
    )))
}

/// The output's format: `to`, else by its name.
fn output_format(output: &Path, to: Option<Format>) -> Format {
    to.unwrap_or_else(|| {
        let toml = output
            .extension()
            .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case("toml"));
        if toml { Format::Toml } else { Format::SimRenderer }
    })
}

pub fn run(args: &ConvertArgs, v: Verbosity) -> Result<(), CliError> {
    check_output_path(&args.output, &args.input)?;
    check_not_an_image(&args.output)?;
    let loaded = read_scene(&args.input, &args.reading, preset(args.conventions.as_deref())?)?;
    let scene = &loaded.scene;
    let to = output_format(&args.output, args.to);
    let source = args.input.display().to_string();
    let out = args.output.display().to_string();
    let written = match to {
        Format::Toml => simrenderer::to_toml(scene, &source),
        Format::SimRenderer => {
            let image = args
                .output
                .file_stem()
                .map_or("image".into(), |s| s.to_string_lossy().into_owned());
            simrenderer::to_simrenderer(scene, &source, &image)
        }
    }
    .map_err(|e| CliError::BadInput(format!("{out}: {e}; nothing written")))?;
    // Read back as written, over the same conventions, before anything is on disk.
    let back = match to {
        Format::Toml => scene::parse(&written.text, &out),
        Format::SimRenderer => {
            let options = simrenderer::Options {
                lenient: false,
                conventions: scene.settings.conventions,
            };
            simrenderer::parse(&written.text, &out, &options).map(|p| p.scene)
        }
    }
    .map_err(|e| {
        CliError::Failed(format!(
            "{out}: the scene written does not read back ({e}); nothing written: this is a lumiere bug, please report it"
        ))
    })?;
    write_atomic(&args.output, written.text.as_bytes())
        .map_err(|e| CliError::from(WriteError::new(&args.output, "cannot write", e)))?;
    for note in &written.notes {
        eprintln!("lumiere: warning: {out}: {note}");
    }
    // The name and the text decide the format when the file is read without --format.
    if !matches!(scene::detect(&args.output, &written.text), Ok(read) if read == to) {
        eprintln!(
            "lumiere: warning: {out}: its name does not say the {} format (TOML files end in .toml): read it with --format {}",
            to.name(),
            to.name()
        );
    }
    let differences = simrenderer::differences(scene, &back, 10);
    if !differences.is_empty() {
        eprintln!(
            "lumiere: warning: {out}: reads back as another scene in {}",
            differences.join("; ")
        );
    }
    v.note(|| {
        format!(
            "{out}: {} scene of {} {} and {} {}, from {source}",
            to.name(),
            scene.objects.len(),
            noun_for(scene.objects.len(), "object"),
            scene.lights.len(),
            noun_for(scene.lights.len(), "light")
        )
    });
    Ok(())
}
