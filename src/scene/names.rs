//! The objects' names, kept beside the objects rather than in them: an [`Object`] holds a
//! 4-byte [`NameKey`] in what would otherwise be padding, and [`ObjectNames`] turns it
//! into the name. A generated object's name, `generate[<table>]#<i>`, is made when asked
//! for; the names a file gives, and the default names of the objects it lists
//! (`<kind>#<index>`, `<mesh>/<k>`...), are held as text.
//!
//! [`Object`]: super::Object

use compact_str::{CompactString, format_compact};

/// Where [`ObjectNames`] finds an object's name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct NameKey(u32);

/// The top bit of a key marks a generated object; the rest counts the generated objects
/// of all tables, in table order.
const GENERATED: u32 = 1 << 31;

impl NameKey {
    /// The key of an object made outside a scene file (tests, benches): its name is empty.
    pub const UNNAMED: NameKey = NameKey(u32::MAX);
}

impl Default for NameKey {
    fn default() -> Self {
        NameKey::UNNAMED
    }
}

/// The names of a scene's objects, by [`NameKey`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ObjectNames {
    /// The names held as text, key `k` at `given[k]`.
    given: Vec<CompactString>,
    /// Per `[[generate]]` table, in file order, the count of generated objects before it:
    /// a generated key's table is the last whose start is not above it.
    table_starts: Vec<u32>,
    /// Generated objects of all tables.
    generated: u32,
}

impl ObjectNames {
    /// Holds `name` and returns its key.
    pub fn add(&mut self, name: impl Into<CompactString>) -> NameKey {
        let key = self.given.len() as u32;
        assert!(key < GENERATED - 1, "more named objects than keys");
        self.given.push(name.into());
        NameKey(key)
    }

    /// Opens the next `[[generate]]` table of `count` objects; returns the key of its first
    /// object, the `i`-th object's key being `first + i` ([`NameKey::nth`]).
    pub fn add_table(&mut self, count: usize) -> NameKey {
        let start = self.generated;
        self.generated = u32::try_from(count)
            .ok()
            .and_then(|c| start.checked_add(c))
            .filter(|&end| end < GENERATED)
            .expect("more generated objects than keys");
        self.table_starts.push(start);
        NameKey(GENERATED | start)
    }

    /// The name of the object whose key is `key`: empty for [`NameKey::UNNAMED`] or a key
    /// this table did not give.
    pub fn get(&self, key: NameKey) -> CompactString {
        if key.0 & GENERATED == 0 {
            return self.given.get(key.0 as usize).cloned().unwrap_or_default();
        }
        let n = key.0 & !GENERATED;
        if key == NameKey::UNNAMED || n >= self.generated {
            return CompactString::default();
        }
        let table = self.table_starts.partition_point(|&s| s <= n) - 1;
        format_compact!("generate[{table}]#{}", n - self.table_starts[table])
    }
}

impl NameKey {
    /// The key `i` places after this one: the `i`-th object of a generated table whose
    /// first key is `self`.
    pub fn nth(self, i: usize) -> NameKey {
        NameKey(self.0 + i as u32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_by_key() {
        let mut names = ObjectNames::default();
        let floor = names.add("floor");
        let first = names.add_table(3);
        let sphere = names.add("sphere#4");
        let second = names.add_table(2);
        assert_eq!(names.get(floor), "floor");
        assert_eq!(names.get(sphere), "sphere#4");
        assert_eq!(names.get(first), "generate[0]#0");
        assert_eq!(names.get(first.nth(2)), "generate[0]#2");
        assert_eq!(names.get(second), "generate[1]#0");
        assert_eq!(names.get(second.nth(1)), "generate[1]#1");
        // Keys it did not give name nothing.
        assert_eq!(names.get(second.nth(2)), "");
        assert_eq!(names.get(NameKey::UNNAMED), "");
        assert_eq!(names.get(NameKey(2)), "");
    }

    /// An empty table takes no key: the next table's first object is its own `#0`.
    #[test]
    fn empty_tables_keep_their_numbers() {
        let mut names = ObjectNames::default();
        names.add_table(0);
        let second = names.add_table(1);
        assert_eq!(names.get(second), "generate[1]#0");
    }
}
