//! The portable float map (PFM) reader: the format `lumiere render -o X.pfm` writes
//! ([`crate::output::encode_pfm`]). A header of four whitespace-separated ASCII words,
//! `PF` (colour, 3 floats a pixel) or `Pf` (grey, 1 float), the width, the height and the
//! scale, whose sign gives the byte order of the floats (negative: little-endian,
//! positive: big-endian); one whitespace byte; then the rows of 32-bit floats from the
//! bottom of the image to the top. Every malformed file is an error naming what is wrong,
//! never a panic, and nothing is allocated before the data's length is known to match.

/// A decoded PFM image: RGB floats, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Pfm {
    pub width: u32,
    pub height: u32,
    /// 3 for `PF`, 1 for `Pf`.
    pub channels: u8,
    /// The header's scale (its sign was the byte order; its magnitude is not applied).
    pub scale: f32,
    /// `width * height * 3` floats, RGB interleaved (a grey file's value in all three), row 0
    /// at the top.
    pub rgb: Vec<f32>,
}

/// Whether `bytes` start like a PFM file: `PF` or `Pf` then whitespace.
pub fn looks_like_pfm(bytes: &[u8]) -> bool {
    matches!(bytes, [b'P', b'F' | b'f', w, ..] if w.is_ascii_whitespace())
}

/// Decodes a PFM file. The error says what is wrong, without the file's name.
pub fn decode_pfm(bytes: &[u8]) -> Result<Pfm, String> {
    let channels: u8 = match bytes {
        [b'P', b'F', ..] => 3,
        [b'P', b'f', ..] => 1,
        _ => return Err("not a PFM file: it must start with `PF` (colour) or `Pf` (grey)".into()),
    };
    let mut at = 2;
    let mut word = |name: &str| -> Result<&[u8], String> {
        let start = at + bytes[at..].iter().take_while(|b| b.is_ascii_whitespace()).count();
        if start == at {
            return Err(format!("PFM header: expected whitespace before the {name}"));
        }
        let len = bytes[start..].iter().take_while(|b| !b.is_ascii_whitespace()).count();
        if len == 0 {
            return Err(format!(
                "PFM header: the file ends before the {name} (the header is `PF` or `Pf`, width, height, scale)"
            ));
        }
        if len > 40 {
            return Err(format!(
                "PFM header: the {name} is not a number (more than 40 characters)"
            ));
        }
        at = start + len;
        Ok(&bytes[start..at])
    };
    let side = |w: &[u8], name: &str| -> Result<u32, String> {
        let text = String::from_utf8_lossy(w);
        match text.parse::<u32>() {
            Ok(v) if v > 0 && w.iter().all(u8::is_ascii_digit) => Ok(v),
            _ => Err(format!(
                "PFM header: the {name} `{text}` must be a whole number in [1, {}]",
                u32::MAX
            )),
        }
    };
    let width = side(word("width")?, "width")?;
    let height = side(word("height")?, "height")?;
    let scale_word = word("scale")?;
    let scale_text = String::from_utf8_lossy(scale_word);
    let scale = match scale_text.parse::<f32>() {
        Ok(s) if s.is_finite() && s != 0.0 => s,
        _ => {
            return Err(format!(
                "PFM header: the scale `{scale_text}` must be a finite non-zero number (negative: little-endian floats, positive: big-endian)"
            ));
        }
    };
    // One whitespace byte ends the header.
    match bytes.get(at) {
        Some(b) if b.is_ascii_whitespace() => at += 1,
        _ => return Err("PFM header: the file ends after the scale, with no pixel data".into()),
    }
    let data = &bytes[at..];
    let floats = (width as u64) * (height as u64) * channels as u64;
    let expected = floats * 4;
    if data.len() as u64 != expected {
        return Err(format!(
            "PFM pixel data: {width} x {height} pixels of {channels} float(s) take {expected} bytes after the header, the file has {}",
            data.len()
        ));
    }
    let little = scale < 0.0;
    let value = |i: usize| {
        let b: [u8; 4] = [data[4 * i], data[4 * i + 1], data[4 * i + 2], data[4 * i + 3]];
        if little {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        }
    };
    let (w, h, c) = (width as usize, height as usize, channels as usize);
    let mut rgb = Vec::with_capacity(w * h * 3);
    // The file's last row is the image's top row.
    for row in (0..h).rev() {
        for x in 0..w {
            let first = (row * w + x) * c;
            if c == 3 {
                rgb.extend([value(first), value(first + 1), value(first + 2)]);
            } else {
                let v = value(first);
                rgb.extend([v, v, v]);
            }
        }
    }
    Ok(Pfm {
        width,
        height,
        channels,
        scale,
        rgb,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::Film;
    use glam::DVec3;

    #[test]
    fn reads_what_lumiere_writes() {
        let mut film = Film::new(2, 2);
        film.pixels = vec![
            DVec3::new(0.0, 0.25, 0.5),
            DVec3::new(1.0, 2.5, -1.0),
            DVec3::new(0.125, 0.75, 3.0),
            DVec3::new(0.5, 0.5, 0.5),
        ];
        let pfm = decode_pfm(&crate::output::encode_pfm(&film)).unwrap();
        assert_eq!((pfm.width, pfm.height, pfm.channels, pfm.scale), (2, 2, 3, -1.0));
        let expected: Vec<f32> = film
            .pixels
            .iter()
            .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect();
        assert_eq!(pfm.rgb, expected);
    }

    #[test]
    fn big_endian_grey() {
        // 1 x 2 grey, positive scale: big-endian; the file's first row is the bottom one.
        let mut b = b"Pf\n1 2\n1.0\n".to_vec();
        b.extend(0.25f32.to_be_bytes());
        b.extend(0.75f32.to_be_bytes());
        let pfm = decode_pfm(&b).unwrap();
        assert_eq!(pfm.channels, 1);
        assert_eq!(pfm.rgb, [0.75, 0.75, 0.75, 0.25, 0.25, 0.25]);
    }

    #[test]
    fn malformed_headers_say_what_is_wrong() {
        let px = [0u8; 12];
        let file = |header: &str| [header.as_bytes(), &px].concat();
        let cases: [(&[u8], &str); 10] = [
            (b"P6\n1 1\n255\n", "must start with `PF`"),
            (b"PF", "expected whitespace before the width"),
            (b"PF\n", "the file ends before the width"),
            (b"PF\n0 1\n-1.0\n", "the width `0` must be a whole number"),
            (b"PF\n-3 1\n-1.0\n", "the width `-3`"),
            (b"PF\n1 x\n-1.0\n", "the height `x`"),
            (b"PF\n1 1\n0.0\n", "the scale `0.0` must be a finite non-zero number"),
            (b"PF\n1 1\nnan\n", "the scale `nan`"),
            (b"PF\n1 1\n-1.0", "no pixel data"),
            (
                b"PF\n99999 99999\n-1.0\n",
                "take 119997600012 bytes after the header, the file has 0",
            ),
        ];
        for (bytes, message) in cases {
            let e = decode_pfm(bytes).unwrap_err();
            assert!(e.contains(message), "{:?}: {e}", String::from_utf8_lossy(bytes));
        }
        // One float too few, one too many.
        let e = decode_pfm(&file("PF\n1 1\n-1.0\n")[..14]).unwrap_err();
        assert!(e.contains("take 12 bytes after the header, the file has 2"), "{e}");
        let mut long = file("PF\n1 1\n-1.0\n");
        long.extend([0, 0, 0, 0]);
        assert!(decode_pfm(&long).unwrap_err().contains("the file has 16"));
        assert!(decode_pfm(&file("PF\n1 1\n-1.0\n")).is_ok());
    }
}
