//! The `type` key of `[[shapes]]` and `[[lights]]` entries, lifted out of each entry before
//! deserialisation: `{ type = "sphere", radius = 1 }` becomes `{ sphere = { radius = 1 } }`.
//!
//! Why: serde's internally tagged enums (`#[serde(tag = "type")]`) buffer the whole entry
//! before choosing the variant, and the buffer keeps no positions: every error inside an
//! entry would point at the first entry of the array and name no field. An externally
//! tagged enum is deserialised straight from the parsed document, so each unknown key,
//! wrong type or wrong length keeps its own span. The lifted key carries the span of the
//! `type` value, the lifted table the span of the entry.

use super::locate::{FieldError, FieldPath};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// Rewrites every entry of the array `key` of `root` (if present and an array; anything
/// else is left to the deserialiser's own error) as `{ <type> = <entry without type> }`.
/// `types` are the allowed values of `type`; an entry that is not a table, or whose `type`
/// is missing, not a string or not allowed, is an error naming the allowed ones.
pub fn lift(root: &mut DeTable<'_>, key: &str, types: &[&str]) -> Result<(), FieldError> {
    let Some(array) = root.get_mut(key) else {
        return Ok(());
    };
    let DeValue::Array(entries) = array.get_mut() else {
        return Ok(());
    };
    let array_path = FieldPath::default().key(key);
    for (i, entry) in entries.iter_mut().enumerate() {
        let path = array_path.index(i);
        let span = entry.span();
        let DeValue::Table(table) = entry.get_mut() else {
            return Err(FieldError {
                path,
                message: format!("must be a table ([[{key}]]), got {}", entry.get_ref().type_str()),
                got: None,
            });
        };
        let expected = || format!("must be {}", one_of(types));
        let Some(tag) = table.remove("type") else {
            return Err(FieldError {
                path: path.key("type"),
                message: format!("missing; {}", expected()),
                got: None,
            });
        };
        let name = match tag.get_ref() {
            DeValue::String(s) if types.contains(&s.as_ref()) => s.clone(),
            DeValue::String(s) => {
                return Err(FieldError {
                    path: path.key("type"),
                    message: format!("{}, got {:?}", expected(), s.as_ref()),
                    got: None,
                });
            }
            other => {
                return Err(FieldError {
                    path: path.key("type"),
                    message: format!("{}, got {}", expected(), other.type_str()),
                    got: None,
                });
            }
        };
        let fields = std::mem::take(table);
        let mut lifted = DeTable::new();
        lifted.insert(
            Spanned::new(tag.span(), name),
            Spanned::new(span.clone(), DeValue::Table(fields)),
        );
        *entry = Spanned::new(span, DeValue::Table(lifted));
    }
    Ok(())
}

/// `"a"`, `"a" or "b"`, `"a", "b" or "c"`: the allowed values as in every other message.
pub fn one_of(names: &[&str]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    match quoted.split_last() {
        None => String::new(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_read_as_prose() {
        assert_eq!(one_of(&["a"]), "\"a\"");
        assert_eq!(one_of(&["a", "b"]), "\"a\" or \"b\"");
        assert_eq!(one_of(&["a", "b", "c"]), "\"a\", \"b\" or \"c\"");
    }

    #[test]
    fn the_tag_becomes_the_key() {
        let text = "[[shapes]]\ntype = \"sphere\"\nradius = 1\n";
        let mut root = DeTable::parse(text).unwrap().into_inner();
        lift(&mut root, "shapes", &["sphere"]).unwrap();
        let entry = root["shapes"].get_ref().as_array().unwrap()[0].get_ref();
        let (key, inner) = entry.as_table().unwrap().iter().next().unwrap();
        assert_eq!(key.get_ref(), "sphere");
        // The lifted key points at the `type` value.
        assert_eq!(&text[key.span()], "\"sphere\"");
        let fields = inner.get_ref().as_table().unwrap();
        assert_eq!(
            fields.keys().map(|k| k.get_ref().as_ref()).collect::<Vec<_>>(),
            ["radius"]
        );
    }

    #[test]
    fn a_bad_tag_names_the_allowed_types() {
        let bad = |text: &str| {
            let mut root = DeTable::parse(text).unwrap().into_inner();
            let e = lift(&mut root, "shapes", &["sphere", "box"]).unwrap_err();
            format!("{}: {}", e.path, e.message)
        };
        assert_eq!(
            bad("[[shapes]]\ntype = \"sphear\"\n"),
            "shapes[0].type: must be \"sphere\" or \"box\", got \"sphear\""
        );
        assert_eq!(
            bad("[[shapes]]\ntype = \"box\"\n[[shapes]]\nradius = 1\n"),
            "shapes[1].type: missing; must be \"sphere\" or \"box\""
        );
        assert_eq!(
            bad("[[shapes]]\ntype = 3\n"),
            "shapes[0].type: must be \"sphere\" or \"box\", got integer"
        );
        assert_eq!(
            bad("shapes = [1]\n"),
            "shapes[0]: must be a table ([[shapes]]), got integer"
        );
    }
}
