//! `lumiere merge`: the shard files of a split render assembled into the one image a single
//! machine would have written.

use super::{CliError, Verbosity, check_output, signals};
use clap::Args;
use lumiere::film::{WriteError, write_atomic};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The shard files (any order), all N of one render.
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// Output image: .png, .pfm or .exr.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Encode PNG output with the sRGB transfer function.
    #[arg(long)]
    pub srgb: bool,
}

pub fn run(args: &MergeArgs, v: Verbosity) -> Result<(), CliError> {
    signals::catch();
    let format = check_output(&args.output, &args.shards[0])?;
    let mut shards = Vec::new();
    for path in &args.shards {
        let name = path.display().to_string();
        let bytes =
            lumiere::limits::read_file(path).map_err(|e| CliError::BadInput(format!("{name}: cannot read: {e}")))?;
        let (header, pixels) = lumiere::shard::decode(&bytes, &name).map_err(CliError::BadInput)?;
        shards.push((name, header, pixels));
    }
    let film = lumiere::shard::merge(shards).map_err(CliError::BadInput)?;
    v.note(|| {
        format!(
            "merged {} shards into {} x {}",
            args.shards.len(),
            film.width,
            film.height
        )
    });
    let bytes = lumiere::output::encode(&film, format, args.srgb)
        .map_err(|e| CliError::Failed(format!("cannot encode the image: {e}")))?;
    // A signal during the reading or the merge: the image is not written.
    if let Some(signal) = signals::received() {
        return Err(CliError::Interrupted(signal));
    }
    write_atomic(&args.output, &bytes).map_err(|e| WriteError::new(&args.output, "cannot write the image", e))?;
    Ok(())
}
