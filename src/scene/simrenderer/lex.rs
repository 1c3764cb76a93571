//! SIMRenderer's lexical rules, as its public lab sources read scene files: lines, the
//! keyword that starts each one, comments, lumiere's notes, and the readers of values
//! (numbers, integers, booleans, colours, enumerations, vectors, names). Lines and columns
//! are 1-based, columns counted in characters.
//!
//! - A UTF-8 byte order mark at the start of the file (which Windows editors write) is
//!   skipped: the first line's keyword and columns are those of the text after it.
//! - A line ends at `\n`, `\r\n` or a lone `\r` (Java's `readLine`).
//! - The first token of a line (split on space, tab, form feed) is its keyword, compared
//!   in lower case; the rest of the line, leading blanks removed, is its value.
//! - A line whose first token starts with `#`, `/`, `*`, `-`, `!` or `@` is a comment. A
//!   first token of exactly `/*` starts a comment block, and one of exactly `*/` ends it.
//!   There is no comment at the end of a line: the number readers look at their first
//!   tokens only (`angle 60 degrees` is 60), but a name is the whole rest of the line.
//! - Values are split into tokens at blanks and at `, ( ) [ ] < >`: `1 2 3`, `(1, 2, 3)`
//!   and `<1,2,3>` are the same vector.
//! - Numbers are Java's `Double.valueOf` (`1e-3`, `.5`, `2.`, `1.5f`, `2d`, `Infinity`,
//!   `NaN`; hexadecimal ones are not read here); integers are `Integer.valueOf` (`+7`,
//!   `-3`, no decimal point).
//!
//! lumiere adds one thing SIMRenderer reads as a comment: a line `# lumiere: KEY VALUE`
//! is a [`Note`], which lumiere reads and SIMRenderer ignores (an object's name, the seed;
//! see docs/simrenderer.md).

use crate::scene::decimal_comma;

/// One significant line: its keyword and its value.
#[derive(Clone, Debug, PartialEq)]
pub struct Line<'a> {
    /// 1-based line number.
    pub number: usize,
    /// The keyword in lower case.
    pub keyword: String,
    /// The keyword as written.
    pub written: &'a str,
    /// Column of the keyword.
    pub column: usize,
    /// The rest of the line, leading blanks removed (trailing ones kept: they are part of a
    /// name).
    pub value: &'a str,
    /// Column of the value's first character (one past the line's end when it is empty).
    pub value_column: usize,
}

/// A `# lumiere: KEY VALUE` comment.
#[derive(Clone, Debug, PartialEq)]
pub struct Note<'a> {
    pub number: usize,
    /// Column of `KEY`.
    pub column: usize,
    /// `KEY` as written.
    pub key: &'a str,
    /// What follows `KEY`, blanks trimmed.
    pub value: &'a str,
    /// Column of the value.
    pub value_column: usize,
}

/// A significant line or a note, in file order.
#[derive(Clone, Debug, PartialEq)]
pub enum Item<'a> {
    Line(Line<'a>),
    Note(Note<'a>),
}

/// The characters that separate a line's keyword from its value.
fn is_blank(c: char) -> bool {
    matches!(c, ' ' | '\t' | '\u{c}')
}

/// The characters that separate the tokens of a value.
pub fn is_delimiter(c: char) -> bool {
    matches!(
        c,
        ' ' | '\t' | '\r' | '\n' | '\u{c}' | ',' | '(' | ')' | '[' | ']' | '<' | '>'
    )
}

/// The prefix of a comment note.
const NOTE: &str = "lumiere:";

/// The byte order mark a UTF-8 file may start with.
const BOM: char = '\u{feff}';

/// `text` without its leading byte order mark, if it has one.
fn without_bom(text: &str) -> &str {
    text.strip_prefix(BOM).unwrap_or(text)
}

/// The lines of `text` (a leading byte order mark skipped), split as Java's `readLine`
/// splits them.
pub fn split_lines(text: &str) -> Vec<&str> {
    Lines {
        rest: without_bom(text),
    }
    .collect()
}

/// The lines of a text, one at a time (see [`split_lines`]).
struct Lines<'a> {
    rest: &'a str,
}

impl<'a> Iterator for Lines<'a> {
    type Item = &'a str;
    fn next(&mut self) -> Option<&'a str> {
        if self.rest.is_empty() {
            return None;
        }
        let (line, skip) = match self.rest.find(['\n', '\r']) {
            Some(i) if self.rest[i..].starts_with("\r\n") => (&self.rest[..i], i + 2),
            Some(i) => (&self.rest[..i], i + 1),
            None => (self.rest, self.rest.len()),
        };
        self.rest = &self.rest[skip..];
        Some(line)
    }
}

/// Column (1-based, in characters) of byte offset `at` of `line`.
fn column_of(line: &str, at: usize) -> usize {
    line[..at].chars().count() + 1
}

/// The significant lines and notes of `text`, in order, comments and blank lines left out
/// (and a leading byte order mark).
pub fn items(text: &str) -> Items<'_> {
    Items {
        lines: Lines {
            rest: without_bom(text),
        },
        number: 0,
        in_block_comment: false,
        open_comment: None,
    }
}

/// A block comment the file leaves open at its end, which makes the rest of the file a
/// comment (SIMRenderer reads it so): where it opens and the lines it holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OpenComment {
    pub line: usize,
    pub column: usize,
    /// Whether its opening line also writes `*/` (`/* a title */`), which closes nothing:
    /// only a line whose first token is `*/` does.
    pub closed_on_its_line: bool,
    /// The first and last lines inside it with something written on them, if any.
    pub held: Option<(usize, usize)>,
}

/// The iterator of [`items`]: one line read at a time, so a file of millions of lines is
/// never held as items.
pub struct Items<'a> {
    lines: Lines<'a>,
    number: usize,
    in_block_comment: bool,
    open_comment: Option<OpenComment>,
}

impl Items<'_> {
    /// The block comment open where the lines read so far end (at the file's end, one the
    /// file never closes).
    pub fn open_comment(&self) -> Option<OpenComment> {
        self.open_comment.filter(|_| self.in_block_comment)
    }
}

impl<'a> Iterator for Items<'a> {
    type Item = Item<'a>;
    fn next(&mut self) -> Option<Item<'a>> {
        loop {
            let line = self.lines.next()?;
            self.number += 1;
            let number = self.number;
            let Some(start) = line.find(|c: char| !is_blank(c)) else {
                continue;
            };
            let end = line[start..].find(is_blank).map_or(line.len(), |n| start + n);
            let first = &line[start..end];
            if self.in_block_comment {
                self.in_block_comment = first != "*/";
                if let Some(open) = &mut self.open_comment {
                    open.held = Some((open.held.map_or(number, |h| h.0), number));
                }
                continue;
            }
            if first == "/*" {
                self.in_block_comment = true;
                self.open_comment = Some(OpenComment {
                    line: number,
                    column: column_of(line, start),
                    closed_on_its_line: line[end..].contains("*/"),
                    held: None,
                });
                continue;
            }
            if first.starts_with(['#', '/', '*', '-', '!', '@']) {
                match note(line, number, start) {
                    Some(note) => return Some(Item::Note(note)),
                    None => continue,
                }
            }
            let value_start = line[end..].find(|c: char| !is_blank(c)).map_or(line.len(), |n| end + n);
            return Some(Item::Line(Line {
                number,
                keyword: first.to_lowercase(),
                written: first,
                column: column_of(line, start),
                value: &line[value_start..],
                value_column: column_of(line, value_start),
            }));
        }
    }
}

/// The note of a comment line `# lumiere: KEY VALUE` (the `#` at byte `start`), if it is one.
fn note(line: &str, number: usize, start: usize) -> Option<Note<'_>> {
    let after_hash = line[start..].strip_prefix('#')?;
    let offset = start + 1 + (after_hash.len() - after_hash.trim_start().len());
    let rest = line[offset..].strip_prefix(NOTE)?;
    let key_at = offset + NOTE.len() + (rest.len() - rest.trim_start().len());
    let key_end = line[key_at..]
        .find(char::is_whitespace)
        .map_or(line.len(), |n| key_at + n);
    let value_at = line[key_end..]
        .find(|c: char| !c.is_whitespace())
        .map_or(line.len(), |n| key_end + n);
    Some(Note {
        number,
        column: column_of(line, key_at),
        key: &line[key_at..key_end],
        value: line[value_at..].trim_end(),
        value_column: column_of(line, value_at),
    })
}

/// One token of a value and its column.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Token<'a> {
    pub text: &'a str,
    pub column: usize,
}

/// The tokens of `value`, whose first character is at `column`.
pub fn tokens(value: &str, column: usize) -> Vec<Token<'_>> {
    let mut out = Vec::new();
    let mut start: Option<(usize, usize)> = None;
    for (k, (i, c)) in value.char_indices().enumerate() {
        match (is_delimiter(c), start) {
            (true, Some((s, col))) => {
                out.push(Token {
                    text: &value[s..i],
                    column: col,
                });
                start = None;
            }
            (false, None) => start = Some((i, column + k)),
            _ => {}
        }
    }
    if let Some((s, col)) = start {
        out.push(Token {
            text: &value[s..],
            column: col,
        });
    }
    out
}

/// Why a value could not be read: the column to point at and the message.
#[derive(Clone, Debug, PartialEq)]
pub struct ValueError {
    pub column: usize,
    pub message: String,
}

fn value_error<T>(column: usize, message: String) -> Result<T, ValueError> {
    Err(ValueError { column, message })
}

/// A number as Java's `Double.valueOf` reads it (decimal forms only), or `None`.
pub fn java_double(s: &str) -> Option<f64> {
    let unsigned = s.strip_prefix(['+', '-']).unwrap_or(s);
    match unsigned {
        "NaN" => return Some(f64::NAN),
        "Infinity" => {
            return Some(if s.starts_with('-') {
                f64::NEG_INFINITY
            } else {
                f64::INFINITY
            });
        }
        _ => {}
    }
    let body = unsigned.strip_suffix(['f', 'F', 'd', 'D']).unwrap_or(unsigned);
    let (mantissa, exponent) = match body.find(['e', 'E']) {
        Some(i) => (&body[..i], Some(&body[i + 1..])),
        None => (body, None),
    };
    let (whole, fraction) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let digits = |t: &str| t.bytes().all(|b| b.is_ascii_digit());
    let mantissa_ok = digits(whole) && digits(fraction) && !(whole.is_empty() && fraction.is_empty());
    let exponent_ok = exponent.is_none_or(|e| {
        let e = e.strip_prefix(['+', '-']).unwrap_or(e);
        !e.is_empty() && digits(e)
    });
    if !mantissa_ok || !exponent_ok {
        return None;
    }
    let sign = if s.starts_with('-') { "-" } else { "" };
    format!("{sign}{body}").parse().ok()
}

/// An integer as Java's `Integer.valueOf` reads it, or `None`.
pub fn java_int(s: &str) -> Option<i32> {
    whole(s).and_then(|n| i32::try_from(n).ok())
}

/// An integer written as Java writes one (an optional sign, then digits) of up to 38 digits,
/// whatever Java's range, or `None`.
fn whole(s: &str) -> Option<i128> {
    let digits = s.strip_prefix(['+', '-']).unwrap_or(s);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    s.strip_prefix('+').unwrap_or(s).parse().ok()
}

/// A boolean word (true, vrai, yes, oui, on; false, faux, no, non, off; in any case) or an
/// integer (0 is false), or `None`.
pub fn boolean(s: &str) -> Option<bool> {
    match s.to_lowercase().as_str() {
        "true" | "vrai" | "yes" | "oui" | "on" => Some(true),
        "false" | "faux" | "no" | "non" | "off" => Some(false),
        _ => java_int(s).map(|n| n != 0),
    }
}

/// The value's first token, or an error saying what was expected.
fn first<'a>(value: &'a str, column: usize, what: &str) -> Result<Token<'a>, ValueError> {
    match tokens(value, column).first() {
        Some(t) => Ok(*t),
        None => value_error(column, format!("expects {what}, got nothing")),
    }
}

/// The first word of `value` that reads as a decimal written with a comma
/// ([`decimal_comma::split`]): the comma splits it into two numbers, as in SIMRenderer.
/// Its column and the hint to give.
pub fn decimal_comma(value: &str, column: usize) -> Option<(usize, String)> {
    value.split(|c| is_delimiter(c) && c != ',').find_map(|word| {
        let (whole, fraction) = decimal_comma::split(word)?;
        let offset = word.as_ptr() as usize - value.as_ptr() as usize;
        let hint = format!(
            "{word:?} reads as two numbers, {whole} and {fraction}: a comma separates numbers (as in SIMRenderer); {}",
            decimal_comma::with_point(whole, fraction)
        );
        Some((column + value[..offset].chars().count(), hint))
    })
}

/// The number that starts `value`.
pub fn number(value: &str, column: usize) -> Result<f64, ValueError> {
    number_as_written(value, column).map(|(x, _)| x)
}

/// The number that starts `value`, and its text as the file writes it (for messages).
pub fn number_as_written(value: &str, column: usize) -> Result<(f64, &str), ValueError> {
    let t = first(value, column, "a number")?;
    java_double(t.text).map_or_else(
        || value_error(t.column, format!("expects a number, got {:?}", t.text)),
        |x| Ok((x, t.text)),
    )
}

/// The integer that starts `value`, of any size up to 38 digits: Java's `int` range is
/// the caller's to check, so that an integer too large for it is told the range it must
/// be in.
pub fn integer(value: &str, column: usize) -> Result<i128, ValueError> {
    let t = first(value, column, "an integer")?;
    whole(t.text).map_or_else(
        || value_error(t.column, format!("expects an integer, got {:?}", t.text)),
        Ok,
    )
}

/// The three numbers that start `value`.
pub fn vector(value: &str, column: usize) -> Result<[f64; 3], ValueError> {
    numbers(value, column, "x y z")
}

/// The two numbers that start `value`: texture coordinates `u v`.
pub fn pair(value: &str, column: usize) -> Result<[f64; 2], ValueError> {
    numbers(value, column, "u v")
}

/// The `N` numbers that start `value`, named `names` in the message when some are missing.
fn numbers<const N: usize>(value: &str, column: usize, names: &str) -> Result<[f64; N], ValueError> {
    let tokens = tokens(value, column);
    let mut v = [0.0; N];
    for (k, slot) in v.iter_mut().enumerate() {
        let Some(t) = tokens.get(k) else {
            let at = tokens.last().map_or(column, |t| t.column + t.text.chars().count());
            return value_error(at, format!("expects {N} numbers {names}, got {}", tokens.len()));
        };
        *slot = java_double(t.text).map_or_else(
            || value_error(t.column, format!("expects a number, got {:?}", t.text)),
            Ok,
        )?;
    }
    Ok(v)
}

/// The named colours, in English and French.
pub const COLOR_NAMES: [(&str, [f64; 3]); 10] = [
    ("black", [0.0, 0.0, 0.0]),
    ("noir", [0.0, 0.0, 0.0]),
    ("white", [1.0, 1.0, 1.0]),
    ("blanc", [1.0, 1.0, 1.0]),
    ("red", [1.0, 0.0, 0.0]),
    ("rouge", [1.0, 0.0, 0.0]),
    ("green", [0.0, 1.0, 0.0]),
    ("vert", [0.0, 1.0, 0.0]),
    ("blue", [0.0, 0.0, 1.0]),
    ("bleu", [0.0, 0.0, 1.0]),
];

/// A colour: `r g b`, `r g b a`, or a name (black/noir, white/blanc, red/rouge, green/vert,
/// blue/bleu) optionally followed by an alpha. The alpha, when a number follows, must be in
/// [0, 1] and is not used (lumiere's images have no transparency).
pub fn color(value: &str, column: usize) -> Result<[f64; 3], ValueError> {
    let tokens = tokens(value, column);
    let Some(head) = tokens.first() else {
        return value_error(column, "expects a colour r g b or a name, got nothing".into());
    };
    let lower = head.text.to_lowercase();
    let (rgb, next) = match COLOR_NAMES.iter().find(|(name, _)| *name == lower) {
        Some((_, rgb)) => (*rgb, 1),
        None if java_double(head.text).is_none() => {
            let names: Vec<&str> = COLOR_NAMES.iter().map(|(n, _)| *n).collect();
            return value_error(
                head.column,
                format!(
                    "expects a colour r g b or one of {}, got {:?}",
                    names.join(", "),
                    head.text
                ),
            );
        }
        None => (vector(value, column)?, 3),
    };
    if let Some(alpha) = tokens
        .get(next)
        .and_then(|t| java_double(t.text).map(|a| (a, t.column)))
        && !(0.0..=1.0).contains(&alpha.0)
    {
        return value_error(
            alpha.1,
            format!("the alpha after the colour must be in [0, 1], got {}", alpha.0),
        );
    }
    Ok(rgb)
}

/// One of `names` (in any case) or its index in `names`.
pub fn enumeration(value: &str, column: usize, names: &[&str]) -> Result<usize, ValueError> {
    let listed = || {
        names
            .iter()
            .enumerate()
            .map(|(i, n)| format!("{n} ({i})"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let t = first(value, column, "a name or its number")?;
    let lower = t.text.to_lowercase();
    if let Some(i) = names.iter().position(|n| *n == lower) {
        return Ok(i);
    }
    match java_int(t.text) {
        Some(i) if i >= 0 && (i as usize) < names.len() => Ok(i as usize),
        _ => value_error(t.column, format!("must be one of {}, got {:?}", listed(), t.text)),
    }
}

/// A name: the whole value, trailing blanks included (SIMRenderer compares names exactly).
pub fn name(value: &str, column: usize) -> Result<String, ValueError> {
    if value.is_empty() {
        return value_error(column, "expects a name, got nothing".into());
    }
    Ok(value.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(text: &str) -> Vec<(usize, String, &str)> {
        items(text)
            .filter_map(|i| match i {
                Item::Line(l) => Some((l.number, l.keyword, l.value)),
                Item::Note(_) => None,
            })
            .collect()
    }

    #[test]
    fn keywords_values_and_comments() {
        let text =
            "Camera\n  POSITION  1 2 3 \n# c\n/ c\n* c\n- c\n! c\n@ c\n/*\nangle 1\n*/ tail\r\nangle\t60 degrees\rend";
        assert_eq!(
            lines(text),
            vec![
                (1, "camera".to_string(), ""),
                (2, "position".to_string(), "1 2 3 "),
                (12, "angle".to_string(), "60 degrees"),
                (13, "end".to_string(), ""),
            ]
        );
        // `/*x` is a line comment: it opens no block.
        assert_eq!(lines("/*x\nend").len(), 1);
        // A negative number as a value is no comment.
        assert_eq!(lines("position -1 -2 -3")[0].2, "-1 -2 -3");
    }

    #[test]
    fn notes_are_comments_lumiere_reads() {
        let all: Vec<Item> =
            items("primitive\n# lumiere: name \"floor\"\n#lumiere: seed 7\n# lumiere:\n# lumierex: seed 1").collect();
        let notes: Vec<(usize, &str, &str, usize)> = all
            .iter()
            .filter_map(|i| match i {
                Item::Note(n) => Some((n.number, n.key, n.value, n.column)),
                Item::Line(_) => None,
            })
            .collect();
        assert_eq!(
            notes,
            vec![(2, "name", "\"floor\"", 12), (3, "seed", "7", 11), (4, "", "", 11)]
        );
    }

    #[test]
    fn tokens_and_their_columns() {
        let t = tokens("(1, 2,3) <4>", 5);
        let got: Vec<(&str, usize)> = t.iter().map(|t| (t.text, t.column)).collect();
        assert_eq!(got, vec![("1", 6), ("2", 9), ("3", 11), ("4", 15)]);
        assert_eq!(vector("[1 2 3]", 1), Ok([1.0, 2.0, 3.0]));
        assert_eq!(vector("<1,2,3> extra", 1), Ok([1.0, 2.0, 3.0]));
        assert_eq!(
            vector("1 2", 10),
            Err(ValueError {
                column: 13,
                message: "expects 3 numbers x y z, got 2".into()
            })
        );
        assert_eq!(
            vector("1 two 3", 1),
            Err(ValueError {
                column: 3,
                message: "expects a number, got \"two\"".into()
            })
        );
    }

    #[test]
    fn decimal_commas_are_told_from_lists() {
        assert_eq!(
            decimal_comma("0,5", 4),
            Some((
                4,
                "\"0,5\" reads as two numbers, 0 and 5: a comma separates numbers (as in SIMRenderer); a decimal takes a point, 0.5".into()
            ))
        );
        assert_eq!(decimal_comma("1 -2,25 3", 10).map(|(c, _)| c), Some(12));
        assert_eq!(decimal_comma("<1,2,3>", 1), None);
        assert_eq!(decimal_comma("1, 2, 3", 1), None);
        assert_eq!(decimal_comma("0.5 1e3", 1), None);
        assert_eq!(decimal_comma("file_0,5.png", 1), None);
    }

    #[test]
    fn java_numbers() {
        for (s, x) in [
            ("1", 1.0),
            ("-2.5", -2.5),
            ("+.5", 0.5),
            ("2.", 2.0),
            ("1e-3", 1e-3),
            ("1E+3", 1e3),
            ("1.5f", 1.5),
            ("2D", 2.0),
            ("Infinity", f64::INFINITY),
            ("-Infinity", f64::NEG_INFINITY),
        ] {
            assert_eq!(java_double(s), Some(x), "{s}");
        }
        assert!(java_double("NaN").unwrap().is_nan());
        for s in [
            "", ".", "e5", "1e", "inf", "infinity", "nan", "1,5", "0x10", "1.5ff", "--1", "1 2",
        ] {
            assert_eq!(java_double(s), None, "{s}");
        }
        assert_eq!(java_int("+7"), Some(7));
        assert_eq!(java_int("-3"), Some(-3));
        for s in ["1.0", "", "+", "2147483648", "1e3"] {
            assert_eq!(java_int(s), None, "{s}");
        }
    }

    #[test]
    fn booleans_colours_enumerations_names() {
        for s in ["true", "VRAI", "yes", "oui", "on", "1", "-4"] {
            assert_eq!(boolean(s), Some(true), "{s}");
        }
        for s in ["false", "faux", "No", "non", "off", "0"] {
            assert_eq!(boolean(s), Some(false), "{s}");
        }
        assert_eq!(boolean("maybe"), None);
        assert_eq!(color("Rouge", 1), Ok([1.0, 0.0, 0.0]));
        assert_eq!(color("bleu 0.5", 1), Ok([0.0, 0.0, 1.0]));
        assert_eq!(color("0.1 0.2 0.3 1", 1), Ok([0.1, 0.2, 0.3]));
        assert_eq!(color("(0.1, 0.2, 0.3) opaque", 1), Ok([0.1, 0.2, 0.3]));
        assert_eq!(color("white 2", 1).unwrap_err().column, 7);
        assert!(color("pink", 1).unwrap_err().message.contains("black, noir, white"));
        let names = ["linear", "voxel", "multi_voxel"];
        assert_eq!(enumeration("VOXEL", 1, &names), Ok(1));
        assert_eq!(enumeration("2", 1, &names), Ok(2));
        assert_eq!(
            enumeration("3", 1, &names).unwrap_err().message,
            "must be one of linear (0), voxel (1), multi_voxel (2), got \"3\""
        );
        assert_eq!(name("my sphere  ", 1), Ok("my sphere  ".to_string()));
        assert!(name("", 4).is_err());
    }
}
