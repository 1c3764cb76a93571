//! A word of a command line that the program prints for the user to run (the `probe`,
//! `diagnose` and `render` lines of `compare` and `diagnose`, the `figures` command of a
//! set's provenance), quoted as the user's shell reads it.

use std::borrow::Cow;

/// The shell a printed command line is written for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shell {
    /// sh, bash, zsh: a word is taken as it is when it holds only letters, digits and
    /// `-_./,:=+@%` and does not start with `=` (which zsh expands), else between single
    /// quotes, a `'` in it written `'\''`.
    Posix,
    /// Windows' cmd and PowerShell: a word is taken as it is when it holds only letters,
    /// digits and `-_./\:=+`, else between double quotes (a Windows path holds no `"`).
    /// Inside them cmd still expands `%NAME%` and PowerShell `$NAME`: a path holding those
    /// must be typed by hand.
    Windows,
}

impl Shell {
    /// The shell of the platform the program runs on.
    pub const HOST: Shell = if cfg!(windows) { Shell::Windows } else { Shell::Posix };

    /// `word` as one word of this shell's command line.
    pub fn word(self, word: &str) -> Cow<'_, str> {
        let specials = match self {
            Shell::Posix => "-_./,:=+@%",
            Shell::Windows => "-_./\\:=+",
        };
        let plain = !word.is_empty()
            && (self != Shell::Posix || !word.starts_with('='))
            && word.chars().all(|c| c.is_alphanumeric() || specials.contains(c));
        if plain {
            return Cow::Borrowed(word);
        }
        Cow::Owned(match self {
            Shell::Posix => format!("'{}'", word.replace('\'', r"'\''")),
            Shell::Windows => format!("\"{word}\""),
        })
    }
}

/// `word` as one word of a command line for the shell of the platform the program runs on.
pub fn word(word: &str) -> Cow<'_, str> {
    Shell::HOST.word(word)
}

#[cfg(test)]
mod tests {
    use super::Shell::{Posix, Windows};

    #[test]
    fn plain_words_stay_as_they_are() {
        for w in ["scenes/figures/lighting/01-ambient.toml", "a-b_c.d,e:f=g+h", "été.png"] {
            assert_eq!(Posix.word(w), w);
        }
        assert_eq!(Posix.word("50%@2x.png"), "50%@2x.png");
        assert_eq!(Windows.word(r"C:\cours\scène.toml"), r"C:\cours\scène.toml");
    }

    #[test]
    fn posix_words_are_single_quoted_with_quotes_closed_and_reopened() {
        assert_eq!(Posix.word(""), "''");
        assert_eq!(Posix.word("my image.png"), "'my image.png'");
        assert_eq!(Posix.word("$HOME/a;b"), "'$HOME/a;b'");
        assert_eq!(Posix.word("Jo's lab/x.png"), r"'Jo'\''s lab/x.png'");
        assert_eq!(Posix.word(r"a\b"), r"'a\b'");
        assert_eq!(Posix.word("=cmd"), "'=cmd'");
        assert_eq!(Posix.word("a=b"), "a=b");
    }

    #[test]
    fn windows_words_are_double_quoted() {
        assert_eq!(Windows.word(""), "\"\"");
        assert_eq!(Windows.word(r"C:\Mes images\x.png"), r#""C:\Mes images\x.png""#);
        // PowerShell reads `a,b` as an array and `@x` as splatting; cmd `%x%` as a variable.
        assert_eq!(Windows.word("a,b.png"), "\"a,b.png\"");
        assert_eq!(Windows.word("@x.png"), "\"@x.png\"");
        assert_eq!(Windows.word("50%.png"), "\"50%.png\"");
        assert_eq!(Windows.word("Jo's.png"), "\"Jo's.png\"");
    }
}
