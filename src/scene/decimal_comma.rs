//! Decimals written with a comma (`0,5`), as French writes them. Neither format reads one:
//! TOML refuses it, and SIMRenderer's value tokens split it into two numbers. Both readers
//! name such a word and the number it was likely meant to be.

/// The whole and fractional digits of `word` when it is a decimal written with a comma
/// (`0,5`, `-1,25`); a list written with commas (`1,2,3`) or anything else is not one.
pub fn split(word: &str) -> Option<(&str, &str)> {
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let (whole, fraction) = word.split_once(',')?;
    let unsigned = whole.strip_prefix(['+', '-']).unwrap_or(whole);
    (digits(unsigned) && digits(fraction)).then_some((whole, fraction))
}

/// What to write instead of the decimal comma `whole,fraction`.
pub fn with_point(whole: &str, fraction: &str) -> String {
    format!("a decimal takes a point, {whole}.{fraction}")
}

/// The hint for a TOML syntax error at byte `offset` of `text` when the word there is a
/// decimal written with a comma.
pub fn toml_hint(text: &str, offset: usize) -> Option<String> {
    let part = |c: char| c.is_ascii_digit() || matches!(c, ',' | '+' | '-');
    let (before, after) = (text.get(..offset)?, text.get(offset..)?);
    let word_before = &before[before.trim_end_matches(part).len()..];
    let word_after = &after[..after.len() - after.trim_start_matches(part).len()];
    let word = format!("{word_before}{word_after}");
    let (whole, fraction) = split(&word)?;
    Some(format!("{word:?}: {}", with_point(whole, fraction)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals_are_told_from_lists() {
        assert_eq!(split("0,5"), Some(("0", "5")));
        assert_eq!(split("-1,25"), Some(("-1", "25")));
        assert_eq!(split("1,2,3"), None);
        assert_eq!(split("0.5"), None);
        assert_eq!(split(",5"), None);
        assert_eq!(with_point("-1", "25"), "a decimal takes a point, -1.25");
        // `kt = 0,7`: the TOML error points at the comma.
        let text = "kt = 0,7\n";
        assert_eq!(toml_hint(text, 6), Some("\"0,7\": a decimal takes a point, 0.7".into()));
        assert_eq!(toml_hint("v = [1,2,3]\n", 6), None);
        assert_eq!(toml_hint("k = 1 2\n", 6), None);
        // Words next to characters of several bytes, and offsets inside one, are no decimal.
        assert_eq!(toml_hint("\u{fffc}{", 3), None);
        assert_eq!(toml_hint("\u{fffc}{", 1), None);
        assert_eq!(
            toml_hint("é0,5é", 3),
            Some("\"0,5\": a decimal takes a point, 0.5".into())
        );
    }
}
