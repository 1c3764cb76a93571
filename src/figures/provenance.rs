//! Where a figure comes from, written into its PNG: `tEXt` chunks (keyword, NUL, Latin-1
//! text, as the PNG specification defines them) right after the header chunk, in a fixed
//! order, so the same figure always has the same bytes. Readers that do not know them skip
//! them; [`text_chunks`] reads them back.

/// The keywords, in the order they are written.
pub const KEYWORDS: [&str; 7] = [
    "Title",
    "Software",
    "Scene",
    "Scene hash",
    "Seed",
    "Conventions",
    "Command",
];

/// The PNG signature.
const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// Text as `tEXt` may hold it: printable Latin-1 and newlines; any other character
/// becomes `?`.
fn latin1(text: &str) -> Vec<u8> {
    text.chars()
        .map(|c| match c as u32 {
            0x0a | 0x20..=0x7e | 0xa1..=0xff => c as u32 as u8,
            _ => b'?',
        })
        .collect()
}

fn chunk(kind: &[u8; 4], data: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(data.len() + 12);
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let mut crc = crc32fast::Hasher::new();
    crc.update(kind);
    crc.update(data);
    out.extend_from_slice(&crc.finalize().to_be_bytes());
    out
}

/// `png` with one `tEXt` chunk per `(keyword, text)` inserted after its header chunk.
/// Keywords are 1 to 79 printable Latin-1 characters; `None` if `png` does not start with a
/// PNG signature and header chunk.
pub fn with_text(png: &[u8], texts: &[(&str, &str)]) -> Option<Vec<u8>> {
    // Signature, then IHDR: length 13, so the first chunk ends at 8 + 4 + 4 + 13 + 4 = 33.
    if png.len() < 33 || png[..8] != SIGNATURE || &png[12..16] != b"IHDR" {
        return None;
    }
    let mut out = png[..33].to_vec();
    for (keyword, text) in texts {
        debug_assert!((1..80).contains(&keyword.len()));
        let mut data = latin1(keyword);
        data.push(0);
        data.extend(latin1(text));
        out.extend(chunk(b"tEXt", &data));
    }
    out.extend_from_slice(&png[33..]);
    Some(out)
}

/// The `tEXt` chunks of a PNG, in file order (Latin-1 decoded); `Err` if the bytes are not
/// a sequence of whole PNG chunks after the signature.
pub fn text_chunks(png: &[u8]) -> Result<Vec<(String, String)>, String> {
    if png.len() < 8 || png[..8] != SIGNATURE {
        return Err("not a PNG file (no PNG signature)".into());
    }
    let mut at = 8;
    let mut out = Vec::new();
    while at < png.len() {
        let Some(head) = png.get(at..at + 8) else {
            return Err(format!("a chunk header is cut at byte {at}"));
        };
        let len = u32::from_be_bytes([head[0], head[1], head[2], head[3]]) as usize;
        // Length, type, data and CRC.
        if png.len() < at + 12 + len {
            return Err(format!("a chunk is cut at byte {at}"));
        }
        let data = &png[at + 8..at + 8 + len];
        if &head[4..8] == b"tEXt" {
            let nul = data.iter().position(|&b| b == 0).unwrap_or(data.len());
            let decode = |b: &[u8]| b.iter().map(|&c| c as char).collect::<String>();
            out.push((decode(&data[..nul]), decode(data.get(nul + 1..).unwrap_or_default())));
        }
        at += 12 + len;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_round_trip_and_keep_the_image() {
        let png = crate::film::encode_png(2, 1, &[255, 0, 0, 0, 0, 255]).unwrap();
        let tagged = with_text(&png, &[("Title", "lighting/01-ambient"), ("Seed", "42")]).unwrap();
        assert_eq!(
            text_chunks(&tagged).unwrap(),
            vec![
                ("Title".to_string(), "lighting/01-ambient".to_string()),
                ("Seed".to_string(), "42".to_string())
            ]
        );
        // Each chunk: 4 length + 4 type + keyword, NUL, text + 4 CRC.
        assert_eq!(tagged.len(), png.len() + (12 + 25) + (12 + 7));
        let decoded = image::load_from_memory(&tagged).unwrap().to_rgb8();
        assert_eq!(decoded.into_raw(), vec![255, 0, 0, 0, 0, 255]);
        assert!(text_chunks(&png).unwrap().is_empty());
        assert!(with_text(b"not a png", &[]).is_none());
        assert!(text_chunks(&tagged[..tagged.len() - 3]).is_err());
        // θ is not Latin-1.
        assert_eq!(latin1("θ = 70°"), b"? = 70\xb0");
    }
}
