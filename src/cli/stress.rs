//! `lumiere stress`: the numerical stress campaign's table, as Markdown or JSON.

use super::CliError;
use clap::Args;
use lumiere::stress::{campaign, table};

/// Most rays per cell the command accepts.
const MAX_RAYS: usize = 10_000_000;

/// Options of `lumiere stress`.
#[derive(Args, Debug, Clone)]
pub struct StressArgs {
    #[arg(
        long,
        default_value_t = 2000,
        help = format!("Rays per (shape, family) cell, in [1, {MAX_RAYS}]"),
        value_parser = rays,
        allow_negative_numbers = true
    )]
    pub rays: usize,
    #[arg(
        long,
        default_value_t = 7,
        help = format!("Seed of the campaign's random streams, in [0, {}]", u64::MAX),
        value_parser = super::numbers::seed,
        allow_negative_numbers = true
    )]
    pub seed: u64,
    /// Print the table as JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// `--rays`' value parser.
fn rays(text: &str) -> Result<usize, String> {
    lumiere::limits::check_count(lumiere::limits::Whole::parse(text), MAX_RAYS)
}

pub fn run(args: &StressArgs) -> Result<(), CliError> {
    let rows = campaign(args.rays, args.seed);
    if args.json {
        let text = serde_json::to_string_pretty(&rows).map_err(|e| CliError::Failed(e.to_string()))?;
        println!("{text}");
    } else {
        print!("{}", table(&rows));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_counts_are_checked_by_the_parser() {
        assert_eq!((rays("1"), rays("10000000")), (Ok(1), Ok(10_000_000)));
        for bad in ["0", "10000001"] {
            assert_eq!(rays(bad), Err(format!("must be in [1, 10000000], got {bad}")));
        }
    }
}
