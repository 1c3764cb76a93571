//! `lumiere probe`: the ray tree of one pixel, printed as text or JSON.

use super::{CliError, Overrides, load_scene};
use clap::Args;
use lumiere::probe::{format_text, probe_with};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ProbeArgs {
    /// The scene file: TOML, or SIMRenderer's format (see scenes/README.md).
    pub scene: PathBuf,
    /// The pixel, `X,Y`, from the top-left corner (0,0) of the image.
    #[arg(long, value_parser = parse_pixel, allow_hyphen_values = true)]
    pub pixel: (u32, u32),
    /// Trace only sample K (0-based) instead of every sample of the pixel.
    #[arg(long, value_name = "K", value_parser = super::numbers::sample, allow_negative_numbers = true)]
    pub sample: Option<u32>,
    /// Print the tree as JSON (exact floats) instead of text (6 decimals).
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub overrides: Overrides,
}

/// Parses `X,Y` into a pixel position.
fn parse_pixel(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected X,Y with two non-negative integers (e.g. 80,60), got {s:?}");
    let (x, y) = s.split_once(',').ok_or_else(bad)?;
    let x = x.trim().parse().map_err(|_| bad())?;
    let y = y.trim().parse().map_err(|_| bad())?;
    Ok((x, y))
}

/// Loads the scene, probes the pixel, prints text or JSON.
pub fn run(args: &ProbeArgs) -> Result<(), CliError> {
    let scene = load_scene(&args.scene, &args.overrides)?;
    let (x, y) = args.pixel;
    let p = probe_with(&scene, x, y, args.sample, args.overrides.accel).map_err(CliError::BadInput)?;
    if args.json {
        let json =
            serde_json::to_string_pretty(&p).map_err(|e| CliError::Failed(format!("cannot write the JSON: {e}")))?;
        println!("{json}");
    } else {
        println!("scene {}", args.scene.display());
        print!("{}", format_text(&p));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_argument() {
        assert_eq!(parse_pixel("80,60"), Ok((80, 60)));
        assert_eq!(parse_pixel(" 3 , 4 "), Ok((3, 4)));
        assert!(parse_pixel("80").is_err());
        assert!(parse_pixel("-1,2").is_err());
        assert!(parse_pixel("a,b").is_err());
    }
}
