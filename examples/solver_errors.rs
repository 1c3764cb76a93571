//! Prints the torus solver comparison's accuracy half (BENCHMARKS.md, "Numerical
//! stability"): every quartic method on every torus ray family of the stress campaign.
//! `cargo run --release --example solver_errors -- 2000`

use lumiere::shape::QuarticMethod;
use lumiere::stress::{Family, run_cell, table};

fn main() {
    let n = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(2000);
    for method in [
        QuarticMethod::Isolator,
        QuarticMethod::Ferrari,
        QuarticMethod::OrellanaDeMichele,
    ] {
        let rows: Vec<_> = Family::ALL
            .iter()
            .map(|&f| run_cell("torus", f, n, 7, method))
            .collect();
        println!("{method:?}\n{}", table(&rows));
    }
}
