//! A scene file's text, in either format: the file must be UTF-8, and a byte that is not
//! (an accent saved as Latin-1 or Windows-1252, often in a comment) is an error at its line
//! and column, as any other error in the file.

use super::SceneError;
use super::locate::line_col;
use crate::limits;
use std::path::Path;

/// The text of the scene file at `path` ([`text_of`] its bytes).
pub fn read_text(path: &Path) -> Result<String, SceneError> {
    let bytes = limits::read_file(path).map_err(|source| SceneError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    text_of(bytes, &path.display().to_string())
}

/// Scene text from the bytes of `file`: UTF-8, or an error at the line and column of the
/// first byte that is not.
pub fn text_of(bytes: Vec<u8>, file: &str) -> Result<String, SceneError> {
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let at = e.utf8_error().valid_up_to();
        // The text before the byte is valid UTF-8.
        let before = std::str::from_utf8(&bytes[..at]).unwrap_or_default();
        let (line, column) = line_col(before, at);
        SceneError::Invalid {
            file: file.to_string(),
            line,
            column,
            field: "encoding".to_string(),
            message: format!(
                "byte 0x{:02X} is not UTF-8 (an accent saved as Latin-1 or Windows-1252 reads so); save the file as UTF-8",
                bytes[at]
            ),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_byte_not_utf8_is_located() {
        let dir = std::env::temp_dir().join(format!("lumiere-read-text-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("latin1.txt");
        // "# matériau" in Latin-1 on line 2, after "é" in UTF-8 on line 1.
        std::fs::write(&path, b"# d\xc3\xa9but\n# mat\xe9riau\ncamera\nend\n").unwrap();
        assert_eq!(
            read_text(&path).unwrap_err().to_string(),
            format!(
                "{}:2:6: encoding: byte 0xE9 is not UTF-8 (an accent saved as Latin-1 or Windows-1252 reads so); save the file as UTF-8",
                path.display()
            )
        );
        std::fs::write(&path, "# début\ncamera\nend\n").unwrap();
        assert_eq!(read_text(&path).unwrap(), "# début\ncamera\nend\n");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
