//! The numeric options' value parsers: each reads the text as a whole number of any size or
//! as a real and checks it against the limit the rest of the program applies (src/limits.rs,
//! the scene rules), so clap refuses a value out of range naming the option, the range and
//! the value as written, with exit 2. A list option (`--points 1,4,16`) is split by clap
//! and each element is read here, so the message names the bad one.

use lumiere::limits::{self, Whole};
use lumiere::scene::rules;

/// `text` as a real checked by `rule`; the message ends with the value as written.
pub fn real(text: &str, rule: impl Fn(f64) -> Result<f64, String>) -> Result<f64, String> {
    let x = text.trim().parse().unwrap_or(f64::NAN);
    rule(x).map_err(|m| format!("{m}, got {text}"))
}

/// An image side in pixels.
pub fn dimension(text: &str) -> Result<u32, String> {
    limits::check_dimension(Whole::parse(text))
}

/// Samples per pixel.
pub fn samples(text: &str) -> Result<u32, String> {
    limits::check_samples(Whole::parse(text))
}

/// A recursion depth.
pub fn depth(text: &str) -> Result<u32, String> {
    limits::check_depth(Whole::parse(text))
}

/// A seed: any 64-bit unsigned number.
pub fn seed(text: &str) -> Result<u64, String> {
    limits::check_whole(Whole::parse(text), 0, u64::MAX)
}

/// A number of worker threads.
pub fn threads(text: &str) -> Result<usize, String> {
    limits::check_count(Whole::parse(text), limits::MAX_THREADS)
}

/// A difference in 8-bit levels.
pub fn levels(text: &str) -> Result<u8, String> {
    limits::check_whole(Whole::parse(text), 0, u8::MAX)
}

/// A number of things to list, none included.
pub fn how_many(text: &str) -> Result<usize, String> {
    limits::check_whole(Whole::parse(text), 0, usize::MAX)
}

/// An adaptive depth control threshold in 8-bit levels.
pub fn adaptive_threshold(text: &str) -> Result<f64, String> {
    real(text, rules::adaptive_threshold)
}

/// A most number of pixels judged.
pub fn pixel_count(text: &str) -> Result<usize, String> {
    limits::check_count(Whole::parse(text), usize::MAX)
}

/// A sample's index in a pixel (whether the pixel has it is known with the scene).
pub fn sample(text: &str) -> Result<u32, String> {
    limits::check_whole(Whole::parse(text), 0, u32::MAX)
}

/// The figures' image size factor.
pub fn figure_scale(text: &str) -> Result<f64, String> {
    real(text, |x| rules::positive(x, limits::MAX_FIGURE_SCALE))
}

/// A fraction in [0, 1].
pub fn fraction(text: &str) -> Result<f64, String> {
    real(text, |x| rules::number_in(x, 0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each parser's lowest and highest value, and the values one beyond each.
    #[test]
    fn edges() {
        assert_eq!(dimension("1"), Ok(1));
        assert_eq!(dimension("16384"), Ok(16_384));
        assert_eq!(dimension("0"), Err("must be in [1, 16384] pixels, got 0".into()));
        assert_eq!(
            dimension("16385"),
            Err("must be in [1, 16384] pixels, got 16385".into())
        );
        assert_eq!(samples("1"), Ok(1));
        assert_eq!(samples("1024"), Ok(1024));
        for bad in ["0", "1025"] {
            assert_eq!(
                samples(bad),
                Err(format!(
                    "must be a perfect square (1, 4, 9, 16, ...) in [1, 1024], got {bad}"
                ))
            );
        }
        assert_eq!((depth("1"), depth("64")), (Ok(1), Ok(64)));
        assert_eq!(
            depth("0"),
            Err("must be in [1, 64] (1 = no secondary rays), got 0".into())
        );
        assert_eq!(
            depth("65"),
            Err("must be in [1, 64] (1 = no secondary rays), got 65".into())
        );
        assert_eq!((seed("0"), seed("18446744073709551615")), (Ok(0), Ok(u64::MAX)));
        for bad in ["-1", "18446744073709551616"] {
            assert_eq!(
                seed(bad),
                Err(format!("must be in [0, 18446744073709551615], got {bad}"))
            );
        }
        assert_eq!((threads("1"), threads("1024")), (Ok(1), Ok(1024)));
        for bad in ["0", "1025"] {
            assert_eq!(threads(bad), Err(format!("must be in [1, 1024], got {bad}")));
        }
        assert_eq!((levels("0"), levels("255")), (Ok(0), Ok(255)));
        for bad in ["-1", "256"] {
            assert_eq!(levels(bad), Err(format!("must be in [0, 255], got {bad}")));
        }
        assert_eq!(how_many("0"), Ok(0));
        assert_eq!(how_many("-1"), Err(format!("must be in [0, {}], got -1", usize::MAX)));
        assert_eq!((fraction("0"), fraction("1")), (Ok(0.0), Ok(1.0)));
        for bad in ["-1e-300", "1.0000000000000002", "NaN", "inf", "half"] {
            assert_eq!(
                fraction(bad),
                Err(format!("must be a finite number in [0, 1], got {bad}"))
            );
        }
    }

    #[test]
    fn any_text_reaches_the_range() {
        for text in ["-4", "99999999999999999999", "1e400", "2.5", "", "x"] {
            assert_eq!(
                dimension(text),
                Err(format!("must be in [1, 16384] pixels, got {text}"))
            );
        }
    }
}
