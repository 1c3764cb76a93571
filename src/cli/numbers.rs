//! The numeric options' value parsers: each reads the text as a whole number of any size or
//! as a real and checks it against the limit the rest of the program applies (src/limits.rs,
//! the scene rules), so clap refuses a value out of range naming the option, the range and
//! the value as written, with exit 2. A list option (`--points 1,4,16`) is split by clap
//! and each element is read here, so the message names the bad one.
//!
//! An option's help states its range from the constants its parser checks (`help =
//! format!(..)` on the field: a doc comment cannot name a constant); a test here reads the
//! range out of every numeric option's help and checks it against the parser.

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

/// A fraction in [0, 1]. A percentage (`0.5%`) is refused with the fraction it stands for.
pub fn fraction(text: &str) -> Result<f64, String> {
    real(text, |x| rules::number_in(x, 0.0, 1.0)).map_err(|m| {
        let percent = text.trim().strip_suffix('%').and_then(|p| p.trim().parse::<f64>().ok());
        match percent {
            Some(p) if p.is_finite() => format!("{m}: a fraction, not a percentage ({p} % is {})", p / 100.0),
            _ => m,
        }
    })
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
        assert_eq!((samples("1"), samples("2"), samples("1024")), (Ok(1), Ok(2), Ok(1024)));
        for bad in ["0", "1025"] {
            assert_eq!(samples(bad), Err(format!("must be in [1, 1024], got {bad}")));
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
        // A percentage, as the text prints fractions, is named with its fraction.
        assert_eq!(
            fraction("0.5%"),
            Err("must be a finite number in [0, 1], got 0.5%: a fraction, not a percentage (0.5 % is 0.005)".into())
        );
        assert_eq!(
            fraction(" 1 %"),
            Err("must be a finite number in [0, 1], got  1 %: a fraction, not a percentage (1 % is 0.01)".into())
        );
        assert_eq!(fraction("%"), Err("must be a finite number in [0, 1], got %".into()));
    }

    /// A range a help states: its bounds as written and whether the low one is excluded
    /// (`(0, 4]`); the high one is always included.
    #[derive(Debug)]
    struct Stated {
        lo: String,
        hi: Option<String>,
        open_lo: bool,
    }

    /// The first range `help` states: `[lo, hi]`, `(lo, hi]`, or `at least lo` (up to the
    /// type's largest value).
    fn stated_range(help: &str) -> Option<Stated> {
        let is_number = |t: &str| t.parse::<f64>().is_ok();
        let bracketed = help.char_indices().find_map(|(i, c)| {
            let open_lo = match c {
                '[' => false,
                '(' => true,
                _ => return None,
            };
            let (inner, _) = help[i + 1..].split_once(']')?;
            let (lo, hi) = inner.split_once(", ")?;
            (is_number(lo) && is_number(hi)).then(|| Stated {
                lo: lo.to_string(),
                hi: Some(hi.to_string()),
                open_lo,
            })
        });
        let at_least = || {
            let (_, rest) = help.split_once("at least ")?;
            let lo: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
            (!lo.is_empty()).then_some(Stated {
                lo,
                hi: None,
                open_lo: false,
            })
        };
        bracketed.or_else(at_least)
    }

    /// The largest value of a whole-number option's type, or `None` for a real option.
    fn largest_whole(arg: &clap::Arg) -> Option<i128> {
        use std::any::TypeId;
        let id = arg.get_value_parser().type_id();
        [
            (TypeId::of::<u8>(), u8::MAX as i128),
            (TypeId::of::<u32>(), u32::MAX as i128),
            (TypeId::of::<u64>(), u64::MAX as i128),
            (TypeId::of::<usize>(), usize::MAX as i128),
        ]
        .into_iter()
        .find_map(|(t, max)| (id == t).then_some(max))
    }

    fn is_real(arg: &clap::Arg) -> bool {
        arg.get_value_parser().type_id() == std::any::TypeId::of::<f64>()
    }

    /// The texts to try against a stated range: those the parser must accept (the lowest
    /// and highest values) and those it must refuse (one beyond each, the next
    /// representable number for a real).
    fn trial_values(range: &Stated, largest_whole: Option<i128>) -> (Vec<String>, Vec<String>) {
        let mut accepted = Vec::new();
        let mut refused = Vec::new();
        if let Some(max) = largest_whole {
            let lo: i128 = range.lo.parse().unwrap();
            let hi: i128 = range.hi.as_ref().map_or(max, |h| h.parse().unwrap());
            let lowest = if range.open_lo { lo + 1 } else { lo };
            accepted.extend([lowest, hi].map(|n| n.to_string()));
            refused.extend([lowest - 1, hi + 1].map(|n| n.to_string()));
        } else {
            let lo: f64 = range.lo.parse().unwrap();
            let hi: f64 = range
                .hi
                .as_ref()
                .expect("a real's range has a high bound")
                .parse()
                .unwrap();
            let lowest = if range.open_lo { lo.next_up() } else { lo };
            accepted.extend([lowest, hi].map(|x| x.to_string()));
            refused.extend([lowest.next_down(), hi.next_up()].map(|x| x.to_string()));
        }
        (accepted, refused)
    }

    /// Every numeric option of `cmd` and its subcommands, named with the command's path
    /// (`study caustics --radii`).
    fn numeric_options(cmd: &clap::Command, path: &str, out: &mut Vec<(String, clap::Command, clap::Arg)>) {
        let path = format!("{path} {}", cmd.get_name()).trim().to_string();
        for arg in cmd.get_arguments() {
            if largest_whole(arg).is_some() || is_real(arg) {
                let name = format!("{path} --{}", arg.get_long().unwrap());
                out.push((name, cmd.clone(), arg.clone()));
            }
        }
        for sub in cmd.get_subcommands() {
            numeric_options(sub, &path, out);
        }
    }

    /// Each numeric option's help states the range its parser checks: the parser accepts
    /// the range's edges and refuses one beyond each. An option whose help states no
    /// range takes its type's every value (0 to the largest).
    #[test]
    fn helps_state_the_ranges_their_parsers_check() {
        let cli = <crate::cli::Cli as clap::CommandFactory>::command();
        let mut options = Vec::new();
        for sub in cli.get_subcommands() {
            numeric_options(sub, "", &mut options);
        }
        let mut wrong = Vec::new();
        let mut unstated = Vec::new();
        for (name, cmd, arg) in &options {
            let help = arg.get_help().map(|h| h.to_string()).unwrap_or_default();
            let range = stated_range(&help).unwrap_or_else(|| {
                unstated.push(name.clone());
                Stated {
                    lo: "0".into(),
                    hi: None,
                    open_lo: false,
                }
            });
            // The parser refuses a value with a `ValueValidation` error; other errors (a
            // required argument missing) come after the value is read.
            let parses = |text: &str| {
                let option = format!("--{}={text}", arg.get_long().unwrap());
                let parsed = cmd.clone().try_get_matches_from([cmd.get_name(), &option]);
                parsed.map_or_else(|e| e.kind() != clap::error::ErrorKind::ValueValidation, |_| true)
            };
            let (accepted, refused) = trial_values(&range, largest_whole(arg));
            for text in accepted.iter().filter(|t| !parses(t)) {
                wrong.push(format!("{name}: {text} refused; the help says {help:?}"));
            }
            for text in refused.iter().filter(|t| parses(t)) {
                wrong.push(format!("{name}: {text} accepted; the help says {help:?}"));
            }
        }
        assert!(wrong.is_empty(), "{wrong:#?}");
        assert_eq!(unstated, ["compare --worst", "diagnose --top", "probe --sample"]);
        let checked: Vec<_> = options.iter().map(|(name, _, _)| name).collect();
        for kind in [
            "render --width",
            "render --adaptive-threshold",
            "figures --scale",
            "compare --max-flip",
            "diagnose --max-pixels",
            "study caustics --radii",
            "study soft-shadows --reference-points",
            "stress --rays",
        ] {
            assert!(checked.iter().any(|c| *c == kind), "{kind} not found in {checked:?}");
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
