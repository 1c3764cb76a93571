//! Split renders for more than one machine: `--shard K/N` renders the rows
//! `[K H / N, (K + 1) H / N)` of an image and writes their exact f64 radiance; `merge` puts
//! the N shards together into the image a one-machine render writes, bit for bit (every
//! pixel is independent and its random streams depend only on the seed and the pixel).
//!
//! Shard file, in this order:
//!
//! 1. the line `LUMIERE-SHARD-2` (16 bytes with its `\n`);
//! 2. one line of JSON, the [`ShardHeader`], ending in `\n`;
//! 3. the pixels of its rows, row by row, as little-endian f64 RGB triples (24 bytes a pixel);
//! 4. the checksum: the CRC-32 (IEEE 802.3, as `crc32fast` computes it) of every byte of
//!    1 to 3, as 4 little-endian bytes.
//!
//! [`decode`] checks the checksum before it reads the header, so a damaged byte anywhere
//! after the first line is refused as a checksum mismatch: CRC-32 detects every error
//! within 4 consecutive bytes (checksum included), so every flipped bit and damaged byte. A
//! `LUMIERE-SHARD-1` file (the same layout without the checksum) is refused: it must be
//! rendered again.

use crate::film::{Film, Normalization, fnv1a64};
use crate::limits;
use crate::scene::Scene;
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::ops::Range;
use std::str::FromStr;

/// The first line of a shard file.
const MAGIC: &[u8] = b"LUMIERE-SHARD-2\n";
/// The first line of a shard file of the format without a checksum.
const MAGIC_V1: &[u8] = b"LUMIERE-SHARD-1\n";
/// What every first line of a shard format starts with.
const MAGIC_FAMILY: &[u8] = b"LUMIERE-SHARD-";
/// Bytes of the trailing checksum.
const CHECKSUM_LEN: usize = 4;
/// Bytes of one pixel (three f64).
const PIXEL_LEN: usize = 24;
/// Most shards of one image (`K/N` with `N` at most this).
pub const MAX_SHARDS: u32 = 65_536;

/// The extension a shard file must have: a shard is not an image, and a name such as
/// `part0.png` would pass it off as one.
pub const EXTENSION: &str = "shard";

/// Checks that `path` names a shard file (`.shard`, any case).
pub fn check_path(path: &std::path::Path) -> Result<(), String> {
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case(EXTENSION) => Ok(()),
        _ => Err(format!(
            "{}: with --shard the output is a shard file for `lumiere merge`, not an image: its name must end in .{EXTENSION}",
            path.display()
        )),
    }
}

/// Which part of the image: shard `index` of `count` (`K/N` on the command line, 0-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShardSpec {
    pub index: u32,
    pub count: u32,
}

impl FromStr for ShardSpec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let err = || format!("expected K/N with 0 <= K < N <= {MAX_SHARDS} (e.g. 0/4), got {s:?}");
        let (k, n) = s.split_once('/').ok_or_else(err)?;
        let (index, count): (u32, u32) = (
            k.trim().parse().map_err(|_| err())?,
            n.trim().parse().map_err(|_| err())?,
        );
        if count == 0 || count > MAX_SHARDS || index >= count {
            return Err(err());
        }
        Ok(ShardSpec { index, count })
    }
}

impl ShardSpec {
    /// The rows of an image of `height` this shard renders (possibly none).
    pub fn rows(&self, height: u32) -> Range<u32> {
        let at = |k: u32| (k as u64 * height as u64 / self.count as u64) as u32;
        at(self.index)..at(self.index + 1)
    }
}

/// What a shard file says about itself; shards merge only when all agree.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShardHeader {
    pub width: u32,
    pub height: u32,
    pub shard: u32,
    pub shards: u32,
    pub rows: [u32; 2],
    /// FNV-1a 64 of the scene as JSON (settings included): shards of different scenes,
    /// seeds or sizes cannot be mixed.
    pub scene_hash: String,
    /// How the merged image's colours go to 8 bits (absent: each channel clamped).
    #[serde(default, skip_serializing_if = "Normalization::is_clamp_channel")]
    pub color_normalization: Normalization,
}

impl ShardHeader {
    /// Checks that the header describes a shard a render writes: an image within the size
    /// limits of a scene, shard K of N with K < N <= [`MAX_SHARDS`], and the rows of shard K.
    pub fn check(&self) -> Result<ShardSpec, String> {
        for (what, v) in [("width", self.width), ("height", self.height)] {
            limits::check_dimension(v).map_err(|e| format!("bad shard header: {what} {e}"))?;
        }
        limits::check_pixel_count(self.width, self.height).map_err(|e| format!("bad shard header: {e}"))?;
        if self.shards == 0 || self.shards > MAX_SHARDS || self.shard >= self.shards {
            return Err(format!(
                "bad shard header: shard {}/{} is not K/N with 0 <= K < N <= {MAX_SHARDS}",
                self.shard, self.shards
            ));
        }
        let spec = ShardSpec {
            index: self.shard,
            count: self.shards,
        };
        let rows = spec.rows(self.height);
        if self.rows != [rows.start, rows.end] {
            return Err(format!(
                "bad shard header: rows {}..{} are not those of shard {}/{} of {} rows ({}..{})",
                self.rows[0], self.rows[1], self.shard, self.shards, self.height, rows.start, rows.end
            ));
        }
        Ok(spec)
    }

    /// How many pixels the shard's rows hold.
    pub fn pixel_count(&self) -> usize {
        self.rows[1].saturating_sub(self.rows[0]) as usize * self.width as usize
    }
}

/// The identity of a scene for merging.
pub fn scene_hash(scene: &Scene) -> String {
    format!("{:016x}", fnv1a64(&serde_json::to_vec(scene).unwrap_or_default()))
}

/// Encodes the rows `spec.rows(height)` of a render, checksum included.
pub fn encode(scene: &Scene, spec: ShardSpec, pixels: &[DVec3]) -> Vec<u8> {
    let rows = spec.rows(scene.settings.height);
    let header = ShardHeader {
        width: scene.settings.width,
        height: scene.settings.height,
        shard: spec.index,
        shards: spec.count,
        rows: [rows.start, rows.end],
        scene_hash: scene_hash(scene),
        color_normalization: scene.settings.color_normalization,
    };
    let mut out = MAGIC.to_vec();
    out.extend(serde_json::to_vec(&header).unwrap_or_default());
    out.push(b'\n');
    for p in pixels {
        for c in [p.x, p.y, p.z] {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    let checksum = crc32fast::hash(&out);
    out.extend_from_slice(&checksum.to_le_bytes());
    out
}

/// Decodes a shard file (`name` is used in errors). Refuses a file of another format, a
/// damaged one (checksum mismatch), and one whose header or size is not that of a shard.
pub fn decode(bytes: &[u8], name: &str) -> Result<(ShardHeader, Vec<DVec3>), String> {
    if bytes.starts_with(MAGIC_V1) {
        return Err(format!(
            "{name}: a LUMIERE-SHARD-1 file, written by an older lumiere (without a checksum): \
             render this shard again with this lumiere"
        ));
    }
    if !bytes.starts_with(MAGIC) {
        return Err(if bytes.starts_with(MAGIC_FAMILY) {
            format!(
                "{name}: a shard file of a format this lumiere does not read (its first line is not \
                 LUMIERE-SHARD-2): render this shard again with this lumiere"
            )
        } else {
            format!("{name}: not a lumiere shard file")
        });
    }
    let Some((sealed, stored)) = bytes
        .len()
        .checked_sub(CHECKSUM_LEN)
        .filter(|&n| n >= MAGIC.len())
        .map(|n| bytes.split_at(n))
    else {
        return Err(format!(
            "{name}: truncated: {} bytes, too few for a shard file",
            bytes.len()
        ));
    };
    let mut stored_le = [0; CHECKSUM_LEN];
    stored_le.copy_from_slice(stored);
    let expected = u32::from_le_bytes(stored_le);
    let found = crc32fast::hash(sealed);
    if found != expected {
        return Err(format!(
            "{name}: checksum mismatch: expected CRC-32 {expected:08x} (stored in the file), found \
             {found:08x}{}: the shard is damaged, render it again",
            size_note(bytes.len(), &sealed[MAGIC.len()..])
        ));
    }
    let (header, data) = split_header(&sealed[MAGIC.len()..]).map_err(|e| format!("{name}: {e}"))?;
    header.check().map_err(|e| format!("{name}: {e}"))?;
    let [start, stop] = header.rows;
    let expected = header.pixel_count() * PIXEL_LEN;
    if data.len() != expected {
        return Err(format!(
            "{name}: holds {} bytes of pixels, rows {start}..{stop} of width {} need {expected}",
            data.len(),
            header.width
        ));
    }
    let pixels = data
        .chunks_exact(PIXEL_LEN)
        .map(|c| {
            let mut f = [0.0; 3];
            for (f, b) in f.iter_mut().zip(c.chunks_exact(8)) {
                let mut le = [0; 8];
                le.copy_from_slice(b);
                *f = f64::from_le_bytes(le);
            }
            DVec3::from_array(f)
        })
        .collect();
    Ok((header, pixels))
}

/// The header line (without its magic) parsed, and the bytes after it.
fn split_header(body: &[u8]) -> Result<(ShardHeader, &[u8]), String> {
    let end = body.iter().position(|&b| b == b'\n').ok_or("truncated header")?;
    let header = serde_json::from_slice(&body[..end]).map_err(|e| format!("bad shard header: {e}"))?;
    Ok((header, &body[end + 1..]))
}

/// For a checksum mismatch: the file's size against the size its header gives, when the
/// header can be read and the two differ (a shard cut short or with bytes appended).
fn size_note(len: usize, body: &[u8]) -> String {
    let Ok((header, data)) = split_header(body) else {
        return String::new();
    };
    let described = (len - data.len()) as u64
        + header.rows[1].saturating_sub(header.rows[0]) as u64 * header.width as u64 * PIXEL_LEN as u64;
    if described == len as u64 {
        return String::new();
    }
    format!("; the file has {len} bytes where its header describes {described}")
}

/// Assembles decoded shards (any order) into the full film. Every shard `0..N` must be
/// present once, all of the same scene and size.
pub fn merge(shards: Vec<(String, ShardHeader, Vec<DVec3>)>) -> Result<Film, String> {
    let first = shards.first().ok_or("no shard files given")?.1.clone();
    let mut seen = vec![false; first.shards.min(MAX_SHARDS) as usize];
    for (name, h, pixels) in &shards {
        h.check().map_err(|e| format!("{name}: {e}"))?;
        if (h.width, h.height, h.shards, &h.scene_hash) != (first.width, first.height, first.shards, &first.scene_hash)
        {
            return Err(format!(
                "{name}: belongs to another render (scene, size or shard count differ)"
            ));
        }
        if pixels.len() != h.pixel_count() {
            return Err(format!(
                "{name}: holds {} pixels, rows {}..{} of width {} need {}",
                pixels.len(),
                h.rows[0],
                h.rows[1],
                h.width,
                h.pixel_count()
            ));
        }
        if std::mem::replace(&mut seen[h.shard as usize], true) {
            return Err(format!("{name}: shard {}/{} given twice", h.shard, h.shards));
        }
    }
    if let Some(missing) = seen.iter().position(|s| !s) {
        return Err(format!("shard {missing}/{} is missing", first.shards));
    }
    // Every header is checked and every shard present once: the rows tile the film.
    let mut film = Film::new(first.width, first.height);
    film.normalization = first.color_normalization;
    for (_, h, pixels) in shards {
        let at = h.rows[0] as usize * h.width as usize;
        film.pixels[at..at + pixels.len()].copy_from_slice(&pixels);
    }
    Ok(film)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_cover_the_image_once() {
        // 10 rows in 3 shards: [0, 3), [3, 6), [6, 10).
        let rows: Vec<_> = (0..3).map(|k| ShardSpec { index: k, count: 3 }.rows(10)).collect();
        assert_eq!(rows, vec![0..3, 3..6, 6..10]);
        // More shards than rows: some are empty.
        assert_eq!(ShardSpec { index: 0, count: 7 }.rows(3), 0..0);
    }

    #[test]
    fn shard_files_end_in_shard() {
        assert_eq!(check_path(std::path::Path::new("out/part0.shard")), Ok(()));
        assert_eq!(check_path(std::path::Path::new("PART0.SHARD")), Ok(()));
        for bad in ["x.png", "x.shard.png", "shard", "x.exr"] {
            let e = check_path(std::path::Path::new(bad)).unwrap_err();
            assert!(
                e.starts_with(&format!("{bad}: with --shard")) && e.ends_with("must end in .shard"),
                "{e}"
            );
        }
    }

    fn header(width: u32, height: u32, shard: u32, shards: u32) -> ShardHeader {
        let rows = ShardSpec {
            index: shard,
            count: shards.max(1),
        }
        .rows(height);
        ShardHeader {
            width,
            height,
            shard,
            shards,
            rows: [rows.start, rows.end],
            scene_hash: "0123456789abcdef".into(),
            color_normalization: Normalization::ClampChannel,
        }
    }

    /// A shard file of `h` with `pixels`, in the layout of the module doc.
    fn file(h: &ShardHeader, pixels: &[f64]) -> Vec<u8> {
        let mut out = b"LUMIERE-SHARD-2\n".to_vec();
        out.extend(serde_json::to_vec(h).unwrap());
        out.push(b'\n');
        out.extend(pixels.iter().flat_map(|c| c.to_le_bytes()));
        let crc = crc32fast::hash(&out);
        out.extend(crc.to_le_bytes());
        out
    }

    #[test]
    fn decode_reads_the_documented_layout_bit_for_bit() {
        // Shard 1/2 of a 2 x 2 image: row 1 only, 2 pixels; values that a text format loses.
        let h = header(2, 2, 1, 2);
        assert_eq!(h.rows, [1, 2]);
        let values = [0.1, -0.0, 1e-310, f64::MAX, 0.5, 2.0, f64::MIN_POSITIVE, 3.25, -7.0];
        let (got, pixels) = decode(&file(&h, &values[..6]), "a.shard").unwrap();
        assert_eq!(got, h);
        let bits: Vec<u64> = pixels.iter().flat_map(|p| p.to_array()).map(f64::to_bits).collect();
        assert_eq!(bits, values[..6].iter().map(|v| v.to_bits()).collect::<Vec<_>>());
        // One pixel too many or too few, sealed with a right checksum: refused all the same.
        for n in [3, 9] {
            let e = decode(&file(&h, &values[..n]), "a.shard").unwrap_err();
            assert_eq!(
                e,
                format!("a.shard: holds {} bytes of pixels, rows 1..2 of width 2 need 48", n * 8)
            );
        }
    }

    #[test]
    fn a_damaged_or_old_file_is_refused_before_its_header_is_read() {
        let good = file(&header(2, 3, 0, 1), &[0.25; 18]);
        let mut bad = good.clone();
        bad[40] ^= 0x04;
        let crc = |b: &[u8]| crc32fast::hash(&b[..b.len() - 4]);
        let stored = u32::from_le_bytes(good[good.len() - 4..].try_into().unwrap());
        assert_eq!(stored, crc(&good));
        assert_eq!(
            decode(&bad, "b.shard").unwrap_err(),
            format!(
                "b.shard: checksum mismatch: expected CRC-32 {stored:08x} (stored in the file), found {:08x}: \
                 the shard is damaged, render it again",
                crc(&bad)
            )
        );
        let mut v1 = b"LUMIERE-SHARD-1\n".to_vec();
        v1.extend_from_slice(&good[16..good.len() - 4]);
        let e = decode(&v1, "old.shard").unwrap_err();
        assert!(
            e.starts_with("old.shard: a LUMIERE-SHARD-1 file, written by an older lumiere"),
            "{e}"
        );
        let e = decode(b"LUMIERE-SHARD-9\n{}\n", "new.shard").unwrap_err();
        assert!(e.contains("a shard file of a format this lumiere does not read"), "{e}");
        assert_eq!(
            decode(&good[..19], "c.shard").unwrap_err(),
            "c.shard: truncated: 19 bytes, too few for a shard file"
        );
        assert_eq!(
            decode(b"P6\n", "d.shard").unwrap_err(),
            "d.shard: not a lumiere shard file"
        );
    }

    #[test]
    fn headers_of_no_render_are_refused() {
        assert_eq!(header(4, 6, 1, 2).check(), Ok(ShardSpec { index: 1, count: 2 }));
        let refused = [
            (header(0, 6, 0, 1), "width must be in [1, 16384] pixels, got 0"),
            (
                header(4, 16_385, 0, 1),
                "height must be in [1, 16384] pixels, got 16385",
            ),
            (
                header(16_384, 16_384, 0, 1),
                "width x height must be at most 33554432 pixels",
            ),
            (header(4, 6, 0, 0), "shard 0/0 is not K/N with 0 <= K < N <= 65536"),
            (header(4, 6, 2, 2), "shard 2/2 is not K/N"),
            (header(4, 6, 0, 65_537), "shard 0/65537 is not K/N"),
            (
                ShardHeader {
                    rows: [0, 4],
                    ..header(4, 6, 0, 2)
                },
                "rows 0..4 are not those of shard 0/2 of 6 rows (0..3)",
            ),
        ];
        for (h, message) in refused {
            let e = h.check().unwrap_err();
            assert!(e.starts_with("bad shard header: ") && e.contains(message), "{e}");
            // Sealed with a right checksum, such a file is refused, and so is its merge.
            let pixels = vec![0.0; h.pixel_count().min(64) * 3];
            let d = decode(&file(&h, &pixels), "h.shard").unwrap_err();
            assert!(d.starts_with("h.shard: bad shard header: "), "{d}");
            let m = merge(vec![("h.shard".into(), h, vec![DVec3::ZERO; 4])]).unwrap_err();
            assert!(m.starts_with("h.shard: bad shard header: "), "{m}");
        }
    }

    #[test]
    fn parses_k_of_n() {
        assert_eq!("2/7".parse(), Ok(ShardSpec { index: 2, count: 7 }));
        assert!("7/7".parse::<ShardSpec>().is_err());
        assert!("1/0".parse::<ShardSpec>().is_err());
        assert!("x".parse::<ShardSpec>().is_err());
    }
}
