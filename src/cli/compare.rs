//! `lumiere compare`: two images' differences, printed as text or JSON, an optional
//! heat-map, and exit 1 when some pixel differs by more than the tolerance.

use super::{CliError, check_output};
use clap::Args;
use lumiere::compare::{compare_rgb8, heat_map, load_rgb8};
use lumiere::film::{WriteError, write_atomic};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct CompareArgs {
    /// Your image.
    pub a: PathBuf,
    /// The reference image (same size).
    pub b: PathBuf,
    /// Largest per-channel difference (8-bit levels) that still counts as equal.
    #[arg(long, default_value_t = 0)]
    pub tolerance: u8,
    /// Write a heat-map of the differences (black equal, blue small, red, white >= 16 levels).
    #[arg(long)]
    pub heatmap: Option<PathBuf>,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &CompareArgs) -> Result<(), CliError> {
    let (wa, ha, a) = load_rgb8(&args.a).map_err(CliError::BadInput)?;
    let (wb, hb, b) = load_rgb8(&args.b).map_err(CliError::BadInput)?;
    if (wa, ha) != (wb, hb) {
        return Err(CliError::BadInput(format!(
            "the images differ in size: {} is {wa} x {ha}, {} is {wb} x {hb}",
            args.a.display(),
            args.b.display()
        )));
    }
    let c = compare_rgb8(&a, &b, wa, ha, args.tolerance);
    if let Some(path) = &args.heatmap {
        if check_output(path, &args.a)? != lumiere::output::Format::Png {
            return Err(CliError::BadInput(format!(
                "{}: the heat-map must be a .png",
                path.display()
            )));
        }
        let png = lumiere::film::encode_png(wa, ha, &heat_map(&a, &b, 16))
            .map_err(|e| CliError::Failed(format!("cannot encode the heat-map: {e}")))?;
        write_atomic(path, &png).map_err(|e| WriteError::new(path, "cannot write", e))?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&c).unwrap_or_default());
    } else {
        let total = wa as u64 * ha as u64;
        println!("size               {wa} x {ha}");
        println!("max difference     {} levels", c.max_diff);
        println!("RMS difference     {:.4} levels", c.rms);
        println!("PSNR               {:.2} dB", c.psnr_db);
        println!(
            "differing pixels   {} of {total} ({:.4} %) beyond {} levels",
            c.differing_pixels,
            100.0 * c.differing_pixels as f64 / total as f64,
            c.tolerance
        );
    }
    if c.differing_pixels > 0 {
        return Err(CliError::Failed(format!(
            "{} pixels differ by more than {} levels",
            c.differing_pixels, args.tolerance
        )));
    }
    Ok(())
}
