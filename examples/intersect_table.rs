//! Prints the BENCHMARKS.md tables of `cargo bench --bench intersect` from the estimates
//! criterion left in `target/criterion`: rays per second per core for each configuration
//! with the ratios BVH / linear and BVH / obvhs, build times, and the crossover scenes.
//!
//! `cargo run --release --example intersect_table`

use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// (group, function) -> (mean seconds per iteration, elements per iteration).
type Results = BTreeMap<(String, String), (f64, f64)>;

fn collect(dir: &Path, out: &mut Results) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            if p.ends_with("new") {
                read(&p, out);
            } else {
                collect(&p, out);
            }
        }
    }
}

fn read(dir: &Path, out: &mut Results) {
    let json =
        |name: &str| -> Option<Value> { serde_json::from_str(&std::fs::read_to_string(dir.join(name)).ok()?).ok() };
    let (Some(b), Some(e)) = (json("benchmark.json"), json("estimates.json")) else {
        return;
    };
    let group = b["group_id"].as_str().unwrap_or_default().to_string();
    let function = match (b["function_id"].as_str(), b["value_str"].as_str()) {
        (Some(f), Some(v)) => format!("{f}/{v}"),
        (Some(f), None) => f.to_string(),
        _ => String::new(),
    };
    let seconds = e["mean"]["point_estimate"].as_f64().unwrap_or(f64::NAN) * 1e-9;
    let elements = b["throughput"]["Elements"].as_f64().unwrap_or(1.0);
    out.insert((group, function), (seconds, elements));
}

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/criterion");
    let mut r = Results::new();
    collect(&root, &mut r);
    let rate = |g: &str, f: &str| r.get(&(g.to_string(), f.to_string())).map(|(s, n)| n / s);
    // Rays per second, in millions; three significant digits for the slow linear rows.
    let m = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{:.3}", x / 1e6));
    let sig = |x: Option<f64>| {
        x.map_or("-".to_string(), |x| {
            let x = x / 1e6;
            let decimals = (2 - x.log10().floor() as i32).max(3) as usize;
            format!("{x:.decimals$}")
        })
    };
    let ratio = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) if a / b >= 100.0 => format!("{:.0}", a / b),
        (Some(a), Some(b)) => format!("{:.2}", a / b),
        _ => "-".to_string(),
    };
    println!(
        "| query | objects | N | rays | linear (Mrays/s) | BVH (Mrays/s) | obvhs (Mrays/s) | BVH / linear | BVH / obvhs |"
    );
    println!("|---|---|---:|---|---:|---:|---:|---:|---:|");
    for query in ["closest", "any"] {
        for kind in ["spheres", "mixed"] {
            for n in [8, 64, 1_000, 100_000, 1_000_000] {
                for rays in ["coherent", "incoherent"] {
                    let g = format!("{query}/{kind}/{n}/{rays}");
                    let (l, b, o) = (rate(&g, "linear"), rate(&g, "bvh"), rate(&g, "obvhs"));
                    if b.is_none() {
                        continue;
                    }
                    println!(
                        "| {query} | {kind} | {n} | {rays} | {} | {} | {} | {} | {} |",
                        sig(l),
                        m(b),
                        m(o),
                        ratio(b, l),
                        ratio(b, o)
                    );
                }
            }
        }
    }
    println!();
    println!("| objects | N | BVH build (ms) | BVH (M objects/s) | obvhs build (ms) | obvhs / BVH time |");
    println!("|---|---:|---:|---:|---:|---:|");
    for kind in ["spheres", "mixed"] {
        for n in [8, 64, 1_000, 100_000, 1_000_000] {
            let g = format!("build/{kind}");
            let time = |f: &str| r.get(&(g.clone(), format!("{f}/{n}"))).map(|(s, _)| *s);
            let (b, o) = (time("bvh"), time("obvhs"));
            let ms = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{:.3}", x * 1e3));
            println!(
                "| {kind} | {n} | {} | {} | {} | {} |",
                ms(b),
                b.map_or("-".to_string(), |b| format!("{:.1}", n as f64 / b / 1e6)),
                ms(o),
                ratio(o, b)
            );
        }
    }
    println!();
    println!("| N (+ floor plane) | linear (Mrays/s) | BVH (Mrays/s) | BVH / linear |");
    println!("|---:|---:|---:|---:|");
    for n in [2, 4, 8, 12, 16, 24, 32, 48, 64] {
        let g = format!("crossover/{n}");
        let (l, b) = (rate(&g, "linear"), rate(&g, "bvh"));
        println!("| {n} | {} | {} | {} |", m(l), m(b), ratio(b, l));
    }
}
