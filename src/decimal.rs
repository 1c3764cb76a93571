//! Numbers as the files lumiere reads write them, so that a message shows a value as the file
//! at fault would hold it and a writer's value reads back to the same bits: SIMRenderer's
//! scene files (`Infinity`), TOML scene files and Wavefront `.obj` files (`inf`, as Rust's
//! number parser, which reads both, accepts it back).

/// `x` as a file writes it: an integer when it is one (below `1e15`), else the shortest
/// decimal that reads back to the same bits; `inf` and `-inf` as `infinity` says
/// (SIMRenderer's `Infinity`, TOML's and OBJ's `inf`), not a number as `NaN`.
pub fn number(x: f64, infinity: &str) -> String {
    if x.is_infinite() {
        return if x > 0.0 {
            infinity.to_string()
        } else {
            format!("-{infinity}")
        };
    }
    if x == x.trunc() && x.abs() < 1e15 && !(x == 0.0 && x.is_sign_negative()) {
        return format!("{}", x as i64);
    }
    format!("{x:?}")
}

/// `values` as [`number`]s between blanks, as SIMRenderer's vectors and OBJ's statements
/// write them: `2 0 0.5`, `NaN 0 -inf`.
pub fn numbers(values: &[f64], infinity: &str) -> String {
    values
        .iter()
        .map(|&x| number(x, infinity))
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shortest_decimals_that_read_back() {
        assert_eq!(number(3.0, "inf"), "3");
        assert_eq!(number(-0.0, "inf"), "-0.0");
        assert_eq!(number(0.85, "inf"), "0.85");
        assert_eq!(number(1e-7, "Infinity"), "1e-7");
        assert_eq!(number(f64::INFINITY, "Infinity"), "Infinity");
        assert_eq!(number(1e300, "inf"), "1e300");
        // From 1e15, an integer keeps the fraction Rust writes (its exponent form from 1e16).
        assert_eq!(number(999_999_999_999_999.0, "inf"), "999999999999999");
        assert_eq!(number(1e15, "inf"), "1000000000000000.0");
        assert_eq!(number(1e16, "inf"), "1e16");
        assert_eq!(
            numbers(&[f64::NAN, 2e9, f64::NEG_INFINITY, 0.1 + 0.2], "inf"),
            "NaN 2000000000 -inf 0.30000000000000004"
        );
        // Each reads back, by Rust's parser, to the same bits (NaN to a NaN).
        for x in [0.1 + 0.2, -0.0, 1e-7, 1e300, 5e-324, f64::INFINITY, f64::NEG_INFINITY] {
            let back: f64 = number(x, "inf").parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x}");
        }
        assert!(number(f64::NAN, "inf").parse::<f64>().unwrap().is_nan());
    }
}
