//! `lumiere stress`: the numerical stress campaign's table, as Markdown or JSON.

use super::CliError;
use clap::Args;
use lumiere::stress::{campaign, table};

/// Most rays per cell the command accepts.
const MAX_RAYS: usize = 10_000_000;

/// Options of `lumiere stress`.
#[derive(Args, Debug, Clone)]
pub struct StressArgs {
    /// Rays per (shape, family) cell.
    #[arg(long, default_value_t = 2000)]
    pub rays: usize,
    /// Seed of the campaign's random streams.
    #[arg(long, default_value_t = 7)]
    pub seed: u64,
    /// Print the table as JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &StressArgs) -> Result<(), CliError> {
    if args.rays == 0 || args.rays > MAX_RAYS {
        return Err(CliError::BadInput(format!(
            "--rays: must be in [1, {MAX_RAYS}], got {}",
            args.rays
        )));
    }
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
    fn bad_ray_counts_are_rejected() {
        for rays in [0, 10_000_001] {
            let err = run(&StressArgs {
                rays,
                seed: 1,
                json: false,
            })
            .unwrap_err();
            assert_eq!(err.exit_code(), 2);
            assert_eq!(err.to_string(), format!("--rays: must be in [1, 10000000], got {rays}"));
        }
    }
}
