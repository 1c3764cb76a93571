//! Maps between field paths (`shapes[3].radius`) and positions in the TOML text, both ways:
//! a validation error found after deserialisation is located from its path ([`locate`]),
//! and a deserialisation error, which only knows its span, is named from it ([`path_at`]).

use std::fmt;
use std::ops::Range;
use toml::de::{DeTable, DeValue};

/// One step of a field path.
#[derive(Clone, Debug, PartialEq)]
pub enum Seg {
    Key(String),
    Index(usize),
}

/// A path into the scene file, e.g. `shapes[3].radius`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FieldPath(pub Vec<Seg>);

impl FieldPath {
    pub fn key(&self, k: &str) -> FieldPath {
        let mut p = self.clone();
        p.0.push(Seg::Key(k.to_string()));
        p
    }

    pub fn index(&self, i: usize) -> FieldPath {
        let mut p = self.clone();
        p.0.push(Seg::Index(i));
        p
    }
}

impl fmt::Display for FieldPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, seg) in self.0.iter().enumerate() {
            match seg {
                Seg::Key(k) if i == 0 => write!(f, "{k}")?,
                Seg::Key(k) => write!(f, ".{k}")?,
                Seg::Index(n) => write!(f, "[{n}]")?,
            }
        }
        Ok(())
    }
}

/// A value that is wrong, before it is located in the file.
#[derive(Debug)]
pub struct FieldError {
    pub path: FieldPath,
    pub message: String,
    /// The number the message is about, shown after it as `, got X`: X as the file writes
    /// it at `path`, or [`crate::limits::short`] of it when the file does not (a default).
    pub got: Option<f64>,
}

/// How a message shows the number `x` read at `path`: as written there when the text at
/// `path` is that number (`1e-7`, `1_000`, `+5`), else the shorter of its decimal and
/// exponent forms.
pub fn written(text: &str, path: &FieldPath, x: f64) -> String {
    let same = |w: &str| {
        w.replace('_', "")
            .parse::<f64>()
            .is_ok_and(|v| v == x || (v.is_nan() && x.is_nan()))
    };
    value_text(text, path)
        .filter(|w| same(w))
        .map_or_else(|| crate::limits::short(x), str::to_string)
}

/// The text of the value at exactly `path`, when the file has one there.
fn value_text<'t>(text: &'t str, path: &FieldPath) -> Option<&'t str> {
    let root = DeTable::parse(text).ok()?;
    let mut table: Option<&DeTable> = Some(root.get_ref());
    let mut value: Option<&DeValue> = None;
    let mut span = None;
    for seg in &path.0 {
        let next = match (seg, table, value) {
            (Seg::Key(k), Some(t), _) => t.get(k.as_str()),
            (Seg::Index(i), _, Some(DeValue::Array(a))) => a.get(*i),
            _ => None,
        }?;
        span = Some(next.span());
        value = Some(next.get_ref());
        table = match next.get_ref() {
            DeValue::Table(t) => Some(t),
            _ => None,
        };
    }
    text.get(span?)
}

/// 1-based line and column of byte offset `offset` in `text`.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// The line where the key at `span` (a key TOML refused as given twice) was given first: for
/// a table header given twice, its first header; for a key, the same key (dotted or quoted as
/// written, TOML's own reading) earlier in the same table. The text before the key's line is
/// parsed for the first key's position. `None` when that text does not parse, or the key is
/// inside an inline table.
pub fn first_given(text: &str, span: Range<usize>) -> Option<usize> {
    let line_start = text.get(..span.start)?.rfind('\n').map_or(0, |i| i + 1);
    let this = text[line_start..].lines().next()?.trim();
    let before = &text[..line_start];
    let root = DeTable::parse(before).ok()?;
    let is_header = |l: &str| l.starts_with('[');
    let (table, key) = if is_header(this) {
        (Vec::new(), header_path(this)?)
    } else {
        let table = match before.lines().rev().map(str::trim).find(|l| is_header(l)) {
            Some(header) => header_path(header)?,
            None => Vec::new(),
        };
        // The key as written, up to the end of its part TOML refused, given a value.
        let written = format!("{} = 0", text.get(line_start..span.end)?);
        (table, dotted_path(DeTable::parse(&written).ok()?.get_ref(), false))
    };
    let (last, parents) = key.split_last()?;
    let mut at = root.get_ref();
    // Into a table, or the last entry of an array of tables.
    for k in table.iter().chain(parents) {
        at = match at.get(k.as_str())?.get_ref() {
            DeValue::Table(t) => t,
            DeValue::Array(a) => match a.last()?.get_ref() {
                DeValue::Table(t) => t,
                _ => return None,
            },
            _ => return None,
        };
    }
    let (first, _) = at.get_key_value(last.as_str())?;
    Some(line_col(text, first.span().start).0)
}

/// The keys of a table header line (`[a."b"]` or `[[a]]`), as TOML reads them.
fn header_path(line: &str) -> Option<Vec<String>> {
    Some(dotted_path(DeTable::parse(line).ok()?.get_ref(), true))
}

/// The keys a one-entry document nests: a dotted key's parts, down to a value that is not a
/// table (`tables_end`: down to an empty table, or into an array of tables' one entry).
fn dotted_path(mut table: &DeTable, tables_end: bool) -> Vec<String> {
    let mut path = Vec::new();
    while let Some((k, v)) = table.iter().next() {
        path.push(k.get_ref().to_string());
        table = match v.get_ref() {
            DeValue::Table(t) if tables_end || !t.is_empty() => t,
            DeValue::Array(a) if tables_end => match a.first().map(|e| e.get_ref()) {
                Some(DeValue::Table(t)) => t,
                _ => break,
            },
            _ => break,
        };
    }
    path
}

/// Byte offset of the value at `path`, or of the nearest enclosing value that exists
/// (a defaulted field points at its table).
pub fn locate(text: &str, path: &FieldPath) -> usize {
    let Ok(root) = DeTable::parse(text) else {
        return 0;
    };
    let mut best = root.span().start;
    let mut table: Option<&DeTable> = Some(root.get_ref());
    let mut value: Option<&DeValue> = None;
    for seg in &path.0 {
        let next = match (seg, table, value) {
            (Seg::Key(k), Some(t), _) => t.get(k.as_str()),
            (Seg::Index(i), _, Some(DeValue::Array(a))) => a.get(*i),
            _ => None,
        };
        let Some(next) = next else { break };
        best = next.span().start;
        value = Some(next.get_ref());
        table = match next.get_ref() {
            DeValue::Table(t) => Some(t),
            _ => None,
        };
    }
    best
}

/// The path of the deepest key or value whose span holds all of `span` (empty when only the
/// whole document does, e.g. for a missing top-level table).
pub fn path_at(text: &str, span: Range<usize>) -> FieldPath {
    let Ok(root) = DeTable::parse(text) else {
        return FieldPath::default();
    };
    let mut path = FieldPath::default();
    within_table(root.get_ref(), &span, &mut path);
    path
}

fn holds(outer: &Range<usize>, inner: &Range<usize>) -> bool {
    outer.start <= inner.start && inner.end <= outer.end
}

/// Extends `path` into `table` as deep as `span` goes; whether it went in at all.
fn within_table(table: &DeTable, span: &Range<usize>, path: &mut FieldPath) -> bool {
    for (key, value) in table.iter() {
        path.0.push(Seg::Key(key.get_ref().to_string()));
        if holds(&key.span(), span) || within_value(value.get_ref(), span, path) || holds(&value.span(), span) {
            return true;
        }
        path.0.pop();
    }
    false
}

fn within_value(value: &DeValue, span: &Range<usize>, path: &mut FieldPath) -> bool {
    match value {
        DeValue::Table(t) => within_table(t, span, path),
        DeValue::Array(a) => a.iter().enumerate().any(|(i, item)| {
            path.0.push(Seg::Index(i));
            // An entry of an array of tables spans only its header: look inside it first.
            let found = within_value(item.get_ref(), span, path) || holds(&item.span(), span);
            if !found {
                path.0.pop();
            }
            found
        }),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_key_given_twice_is_found_where_it_was_first_given() {
        let text = "[camera]\nvfov = 60\nup = [0, 0, 1]\nvfov = 70\n";
        let span = |t: &str, at: usize, key: &str| t[at..].find(key).map(|i| at + i..at + i + key.len()).unwrap();
        assert_eq!(first_given(text, span(text, 30, "vfov")), Some(2));
        // The same key in another table is not the first of this one.
        let text = "[image]\nseed = 1\n[camera]\nseed = 2\nseed = 3\n";
        assert_eq!(first_given(text, span(text, 34, "seed")), Some(4));
        // A table given twice: its first header.
        let text = "[camera]\nvfov = 60\n\n[camera]\n";
        assert_eq!(first_given(text, span(text, 10, "camera")), Some(1));
        // A dotted key (TOML's span is its last part, `c` of `b.c`) and a quoted one are
        // read as TOML reads them.
        let text = "[a]\nb.c = 1\nx = 0\nb . \"c\" = 2\n";
        assert_eq!(first_given(text, span(text, 18, "\"c\"")), Some(2));
        let text = "[camera]\nvfov = 60\n\"vfov\" = 70\n";
        assert_eq!(first_given(text, span(text, 19, "\"vfov\"")), Some(2));
        // A header given twice in an array of tables' entry, and a table's key given again
        // in the next entry is not a duplicate of the first entry's.
        let text = "[[shapes]]\n[shapes.m]\nk = 1\n[shapes.m]\n";
        assert_eq!(first_given(text, span(text, 29, "m")), Some(2));
        // A key inside an inline table is not followed.
        let text = "[a]\nx = { y = 1, y = 2 }\n";
        assert_eq!(first_given(text, span(text, 17, "y")), None);
    }

    use super::*;

    #[test]
    fn finds_nested_fields() {
        let text =
            "[image]\nwidth = 10\n\n[[shapes]]\ntype = \"sphere\"\n\n[[shapes]]\ntype = \"sphere\"\nradius = -1\n";
        let p = FieldPath::default().key("shapes").index(1).key("radius");
        assert_eq!(p.to_string(), "shapes[1].radius");
        assert_eq!(line_col(text, locate(text, &p)), (9, 10));
        // A missing field points at its table's header.
        let missing = FieldPath::default().key("shapes").index(0).key("center");
        assert_eq!(line_col(text, locate(text, &missing)).0, 4);
    }

    #[test]
    fn names_the_deepest_field_holding_a_span() {
        let text = "[image]\nwidth = 10\n\n[[shapes]]\ntype = \"sphere\"\n\n[[shapes]]\ncenter = [1, \"x\", 3]\n";
        let at = |needle: &str| {
            let start = text.find(needle).unwrap();
            path_at(text, start..start + needle.len()).to_string()
        };
        assert_eq!(at("\"x\""), "shapes[1].center[1]");
        assert_eq!(at("center"), "shapes[1].center");
        assert_eq!(at("10"), "image.width");
        // An entry of an array of tables is known by its header.
        assert_eq!(at("[[shapes]]"), "shapes[0]");
        assert_eq!(path_at(text, 0..text.len()).to_string(), "");
    }
}
