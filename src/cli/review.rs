//! `lumiere review-snapshots`: one summary line per pending snapshot; its labelled sheet
//! and the review page (shared with `lumiere figures --check`) written by the library.

use super::CliError;
use clap::Args;
use lumiere::review::{ReviewError, review, summary};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ReviewArgs {
    /// Folder of the insta snapshots.
    #[arg(long, default_value = "snapshots")]
    pub dir: PathBuf,
    /// Folder for the sheets (in its `snapshots/`) and the review page `index.html`, which
    /// also lists the figure changes found by `lumiere figures --check` (created if missing).
    #[arg(long, default_value = "target/review")]
    pub out: PathBuf,
}

pub fn run(args: &ReviewArgs) -> Result<(), CliError> {
    let reviewed = review(&args.dir, &args.out).map_err(|e| match e {
        ReviewError::Read(m) => CliError::BadInput(m),
        ReviewError::Encode(m) => CliError::Failed(m),
        ReviewError::Write(w) => CliError::from(w),
    })?;
    if reviewed.is_empty() {
        println!("no pending snapshots (*.snap.new) in {}", args.dir.display());
    }
    for r in &reviewed {
        println!("{}", summary(r));
    }
    if !reviewed.is_empty() {
        println!("review page: {}", args.out.join("index.html").display());
        println!(
            "accept them: `cargo insta accept` (without cargo-insta: README, \"Reviewing snapshot changes\"); reject them: `rm {}`",
            args.dir.join("*.snap.new*").display()
        );
    }
    Ok(())
}
