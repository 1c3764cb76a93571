//! Edits of a valid scene file's text for the hostile-input fuzz tests, in both formats: a
//! line holds a key and its value apart by a separator (`" = "` in lumiere's TOML, one space
//! in SIMRenderer's files).

use proptest::prelude::*;

/// One edit of the valid scene's text.
#[derive(Clone, Debug)]
pub enum Mutation {
    /// Replace the value of the `line`-th line that has one.
    Value(usize, String),
    DeleteLine(usize),
    DuplicateLine(usize),
    /// Insert `key value` (joined by the separator) after a line: unknown keys, repeated
    /// keys.
    Insert(usize, String, String),
    Truncate(usize),
    Byte(usize, u8),
}

/// Edits whose values come from `value` and inserted keys from `key`, an insertion drawn
/// `insert_weight` times as often as a deleted line.
pub fn mutation<V: Strategy<Value = String> + 'static>(
    value: fn() -> V,
    key: impl Strategy<Value = String> + 'static,
    insert_weight: u32,
) -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), value()).prop_map(|(l, v)| Mutation::Value(l, v)),
        1 => any::<usize>().prop_map(Mutation::DeleteLine),
        1 => any::<usize>().prop_map(Mutation::DuplicateLine),
        insert_weight => (any::<usize>(), key, value()).prop_map(|(l, k, v)| Mutation::Insert(l, k, v)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
        1 => (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Byte(i, b)),
    ]
}

/// `text` after the edit `m`, a key and its value apart by `separator`.
pub fn apply(text: &str, m: &Mutation, separator: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let n = lines.len();
    match m {
        Mutation::Value(l, v) => {
            let valued: Vec<usize> = (0..n).filter(|&i| lines[i].contains(separator)).collect();
            let i = valued[l % valued.len()];
            let key = lines[i].split(separator).next().unwrap_or_default().to_string();
            lines[i] = format!("{key}{separator}{v}");
        }
        Mutation::DeleteLine(l) => {
            lines.remove(l % n);
        }
        Mutation::DuplicateLine(l) => {
            let line = lines[l % n].clone();
            lines.insert(l % n, line);
        }
        Mutation::Insert(l, k, v) => lines.insert(l % n + 1, format!("{k}{separator}{v}")),
        Mutation::Truncate(i) => {
            let mut t = lines.join("\n");
            let mut cut = i % (t.len() + 1);
            while !t.is_char_boundary(cut) {
                cut -= 1;
            }
            t.truncate(cut);
            return t;
        }
        Mutation::Byte(i, b) => {
            let mut bytes = lines.join("\n").into_bytes();
            let at = i % bytes.len();
            bytes[at] = *b;
            return String::from_utf8_lossy(&bytes).into_owned();
        }
    }
    lines.join("\n")
}
