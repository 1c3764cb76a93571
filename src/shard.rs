//! Split renders for more than one machine: `--shard K/N` renders the rows
//! `[K H / N, (K + 1) H / N)` of an image and writes their exact f64 radiance; `merge` puts
//! the N shards together into the image a one-machine render writes, bit for bit (every
//! pixel is independent and its random streams depend only on the seed and the pixel).
//!
//! Shard file: the line `LUMIERE-SHARD-1`, one line of JSON (the [`ShardHeader`]), then
//! the pixels of its rows as little-endian f64 RGB triples.

use crate::film::{Film, pixel_hash};
use crate::scene::Scene;
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::ops::Range;
use std::str::FromStr;

const MAGIC: &[u8] = b"LUMIERE-SHARD-1\n";

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
        let err = || format!("expected K/N with 0 <= K < N <= 65536 (e.g. 0/4), got {s:?}");
        let (k, n) = s.split_once('/').ok_or_else(err)?;
        let (index, count): (u32, u32) = (
            k.trim().parse().map_err(|_| err())?,
            n.trim().parse().map_err(|_| err())?,
        );
        if count == 0 || count > 65_536 || index >= count {
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
}

/// The identity of a scene for merging.
pub fn scene_hash(scene: &Scene) -> String {
    format!("{:016x}", pixel_hash(&serde_json::to_vec(scene).unwrap_or_default()))
}

/// Encodes the rows `spec.rows(height)` of a render.
pub fn encode(scene: &Scene, spec: ShardSpec, pixels: &[DVec3]) -> Vec<u8> {
    let rows = spec.rows(scene.settings.height);
    let header = ShardHeader {
        width: scene.settings.width,
        height: scene.settings.height,
        shard: spec.index,
        shards: spec.count,
        rows: [rows.start, rows.end],
        scene_hash: scene_hash(scene),
    };
    let mut out = MAGIC.to_vec();
    out.extend(serde_json::to_vec(&header).unwrap_or_default());
    out.push(b'\n');
    for p in pixels {
        for c in [p.x, p.y, p.z] {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    out
}

/// Decodes a shard file (`name` is used in errors).
pub fn decode(bytes: &[u8], name: &str) -> Result<(ShardHeader, Vec<DVec3>), String> {
    let rest = bytes
        .strip_prefix(MAGIC)
        .ok_or_else(|| format!("{name}: not a lumiere shard file"))?;
    let end = rest
        .iter()
        .position(|&b| b == b'\n')
        .ok_or_else(|| format!("{name}: truncated header"))?;
    let header: ShardHeader =
        serde_json::from_slice(&rest[..end]).map_err(|e| format!("{name}: bad shard header: {e}"))?;
    let data = &rest[end + 1..];
    let [start, stop] = header.rows;
    let expected = (stop.saturating_sub(start)) as usize * header.width as usize * 24;
    if start > stop || stop > header.height || data.len() != expected {
        return Err(format!(
            "{name}: holds {} bytes of pixels, rows {start}..{stop} of width {} need {expected}",
            data.len(),
            header.width
        ));
    }
    let pixels = data
        .chunks_exact(24)
        .map(|c| {
            let f = |i: usize| f64::from_le_bytes(c[i * 8..i * 8 + 8].try_into().unwrap_or_default());
            DVec3::new(f(0), f(1), f(2))
        })
        .collect();
    Ok((header, pixels))
}

/// Assembles decoded shards (any order) into the full film. Every shard `0..N` must be
/// present once, all of the same scene and size.
pub fn merge(shards: Vec<(String, ShardHeader, Vec<DVec3>)>) -> Result<Film, String> {
    let first = shards.first().ok_or("no shard files given")?.1.clone();
    let mut seen = vec![false; first.shards as usize];
    let mut film = Film::new(first.width, first.height);
    for (name, h, pixels) in shards {
        if (h.width, h.height, h.shards, &h.scene_hash) != (first.width, first.height, first.shards, &first.scene_hash)
        {
            return Err(format!(
                "{name}: belongs to another render (scene, size or shard count differ)"
            ));
        }
        let spec = ShardSpec {
            index: h.shard,
            count: h.shards,
        };
        let rows = spec.rows(h.height);
        if h.shard >= h.shards || [rows.start, rows.end] != h.rows {
            return Err(format!("{name}: inconsistent header"));
        }
        if std::mem::replace(&mut seen[h.shard as usize], true) {
            return Err(format!("{name}: shard {}/{} given twice", h.shard, h.shards));
        }
        let at = rows.start as usize * h.width as usize;
        film.pixels[at..at + pixels.len()].copy_from_slice(&pixels);
    }
    if let Some(missing) = seen.iter().position(|s| !s) {
        return Err(format!("shard {missing}/{} is missing", first.shards));
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

    #[test]
    fn parses_k_of_n() {
        assert_eq!("2/7".parse(), Ok(ShardSpec { index: 2, count: 7 }));
        assert!("7/7".parse::<ShardSpec>().is_err());
        assert!("1/0".parse::<ShardSpec>().is_err());
        assert!("x".parse::<ShardSpec>().is_err());
    }
}
