//! serde's words for a value's kind, said as a scene file says them: a deserialisation error
//! names Rust types (`u32`, `f64`, `struct FileImage`, `map`); the file's reader speaks of
//! whole numbers with their range, numbers, tables and arrays.

/// `message` (a serde error's text) with its Rust type names replaced by the file's words.
pub fn plain(message: &str) -> String {
    let mut m = message.replace("` as i128", "`").replace("` as u128", "`");
    for (rust, file) in [
        ("invalid type: map,", "invalid type: table,"),
        ("invalid type: sequence,", "invalid type: array,"),
    ] {
        m = m.replace(rust, file);
    }
    let Some((head, expected)) = m.rsplit_once(", expected ") else {
        return m;
    };
    let whole = |max: u128| format!("a whole number in [0, {max}]");
    let said = match expected {
        "u8" => whole(u8::MAX.into()),
        "u16" => whole(u16::MAX.into()),
        "u32" => whole(u32::MAX.into()),
        "u64" => whole(u64::MAX.into()),
        "usize" => whole(usize::MAX as u128),
        // A field whose own range is checked after: that range is what its error names.
        "i64" | "i128" => "a whole number".to_string(),
        "f64" | "f32" => "a number".to_string(),
        "a sequence" => "an array".to_string(),
        e if e.starts_with("struct ") => "a table".to_string(),
        _ => return m,
    };
    format!("{head}, expected {said}")
}

#[cfg(test)]
mod tests {
    use super::plain;

    #[test]
    fn rust_types_become_the_files_words() {
        assert_eq!(
            plain("invalid value: integer `-4`, expected u32"),
            "invalid value: integer `-4`, expected a whole number in [0, 4294967295]"
        );
        assert_eq!(
            plain("invalid type: integer `99999999999999999999` as i128, expected u64"),
            "invalid type: integer `99999999999999999999`, expected a whole number in [0, 18446744073709551615]"
        );
        assert_eq!(
            plain("invalid type: floating point `12.5`, expected i128"),
            "invalid type: floating point `12.5`, expected a whole number"
        );
        assert_eq!(
            plain("invalid type: string \"0.5\", expected f64"),
            "invalid type: string \"0.5\", expected a number"
        );
        assert_eq!(
            plain("invalid type: integer `5`, expected struct FileImage"),
            "invalid type: integer `5`, expected a table"
        );
        assert_eq!(
            plain("invalid type: map, expected a sequence"),
            "invalid type: table, expected an array"
        );
        assert_eq!(
            plain("invalid type: sequence, expected a boolean"),
            "invalid type: array, expected a boolean"
        );
    }

    #[test]
    fn other_messages_are_kept() {
        for m in [
            "invalid length 2, expected an array of length 3",
            "unknown field `size`, expected one of `shape`, `center`",
            "missing field `radius`",
            "invalid type: integer `5`, expected a string",
        ] {
            assert_eq!(plain(m), m);
        }
    }
}
