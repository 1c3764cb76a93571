//! Damaged shard files: every damaged byte of a small shard is refused by the decoder, a
//! proptest harness feeds the shard reader and `merge` random bytes, flipped bits, cut and
//! lengthened files, forged headers with a right checksum and shards of other renders mixed
//! in (no panic, every damaged or mixed set refused, every complete set merged to the
//! one-machine render), and `lumiere merge` refuses a shard with one flipped bit (exit 2,
//! the file named, nothing written).

use crate::common::*;
use glam::DVec3;
use lumiere::film::Film;
use lumiere::render::{render, render_rows};
use lumiere::scene::{self, Scene};
use lumiere::shard::{self, ShardHeader, ShardSpec};
use lumiere::world::World;
use proptest::prelude::*;
use proptest::sample::Index;
use std::fs;
use std::sync::OnceLock;

/// Bytes of the first line of a shard file.
const MAGIC_LEN: usize = 16;

/// A tiny scene: a plane, two spheres (one a mirror), an ambient and a point light.
const TINY: &str = r#"[image]
width = 4
height = 6
samples_per_pixel = 1
seed = 5

[camera]
position = [0, -6, 3]
look_at = [0, 0, 1]

[render]
depth = 2

[materials.mirror]
kr = 0.8

[[shapes]]
type = "plane"
point = [0, 0, 0]
normal = [0, 0, 1]

[[shapes]]
type = "sphere"
center = [0, 0, 1]
radius = 1

[[shapes]]
type = "sphere"
center = [1.5, 1, 0.5]
radius = 0.5
material = "mirror"

[[lights]]
type = "ambient"
color = [0.2, 0.2, 0.2]

[[lights]]
type = "point"
position = [2, -3, 5]
"#;

fn tiny(width: u32, height: u32, seed: u64) -> Scene {
    let mut s = scene::parse(TINY, "tiny.toml").unwrap();
    s.settings.width = width;
    s.settings.height = height;
    s.settings.seed = seed;
    s
}

/// The shard `spec` of `scene`, its rows rendered on their own as `render --shard` does.
fn shard_file(scene: &Scene, spec: ShardSpec) -> Vec<u8> {
    let world = World::new(scene);
    let (pixels, _) = render_rows(&world, spec.rows(scene.settings.height), &|| {}, None);
    shard::encode(scene, spec, &pixels)
}

/// The stored checksum of a shard file and the one its other bytes give.
fn checksums(bytes: &[u8]) -> (u32, u32) {
    let (body, stored) = bytes.split_at(bytes.len() - 4);
    (u32::from_le_bytes(stored.try_into().unwrap()), crc32fast::hash(body))
}

#[test]
fn every_damaged_byte_of_a_small_shard_is_refused() {
    // Shard 1/2 of a 4 x 6 image: rows 3..6, 4 x 3 pixels.
    let scene = tiny(4, 6, 5);
    let spec = ShardSpec { index: 1, count: 2 };
    let good = shard_file(&scene, spec);
    let (header, pixels) = shard::decode(&good, "s.shard").unwrap();
    assert_eq!((header.rows, pixels.len()), ([3, 6], 12));
    // The file is its first line, the header line, 288 bytes of pixels and 4 of checksum.
    let header_line = good[MAGIC_LEN..].iter().position(|&b| b == b'\n').unwrap() + 1;
    assert_eq!(good.len(), MAGIC_LEN + header_line + 12 * 24 + 4);
    let (stored, computed) = checksums(&good);
    assert_eq!(stored, computed);
    let whole = render(&World::new(&scene), &|| {}).0;
    let want: Vec<DVec3> = whole.pixels[12..].to_vec();
    assert_eq!(pixels, want);

    // Each of the 8 single-bit flips of every byte, and every byte inverted.
    let masks = [0x01, 0x02, 0x04, 0x08, 0x10, 0x20, 0x40, 0x80, 0xff];
    let mut refused = 0;
    for at in 0..good.len() {
        for mask in masks {
            let mut bad = good.clone();
            bad[at] ^= mask;
            let e = shard::decode(&bad, "s.shard").expect_err("a damaged shard must be refused");
            if at < MAGIC_LEN {
                assert!(
                    e == "s.shard: not a lumiere shard file"
                        || e.starts_with("s.shard: a shard file of a format this lumiere does not read")
                        || e.starts_with("s.shard: a LUMIERE-SHARD-1 file"),
                    "byte {at} ^ {mask:#04x}: {e}"
                );
            } else {
                let (expected, found) = checksums(&bad);
                let head = format!(
                    "s.shard: checksum mismatch: expected CRC-32 {expected:08x} (stored in the file), found {found:08x}"
                );
                let tail = ": the shard is damaged, render it again";
                // A damaged header that still reads may describe another size: the message
                // gives both sizes then.
                let note = e
                    .strip_prefix(&head)
                    .and_then(|e| e.strip_suffix(tail))
                    .unwrap_or_else(|| panic!("byte {at} ^ {mask:#04x}: {e}"));
                let size = format!("; the file has {} bytes where its header describes ", good.len());
                assert!(
                    note.is_empty() || (at < MAGIC_LEN + header_line && note.starts_with(&size)),
                    "byte {at} ^ {mask:#04x}: {e}"
                );
            }
            refused += 1;
        }
    }
    assert_eq!(refused, good.len() * masks.len());
}

/// Renders of the tiny scene, each split into shards: two sizes, two seeds, two shard
/// counts, so that every pair differs in scene, size or shard count.
struct Split {
    film: Film,
    files: Vec<Vec<u8>>,
}

fn splits() -> &'static [Split] {
    static SPLITS: OnceLock<Vec<Split>> = OnceLock::new();
    SPLITS.get_or_init(|| {
        [(4, 3, 5, 2), (5, 4, 5, 3), (4, 3, 6, 2), (4, 3, 5, 3), (3, 5, 6, 1)]
            .into_iter()
            .map(|(w, h, seed, n)| {
                let scene = tiny(w, h, seed);
                let files = (0..n)
                    .map(|index| shard_file(&scene, ShardSpec { index, count: n }))
                    .collect();
                let film = render(&World::new(&scene), &|| {}).0;
                Split { film, files }
            })
            .collect()
    })
}

/// Every shard file of every split, as (split, shard) pairs.
fn every_file() -> Vec<(usize, usize)> {
    let s = splits();
    (0..s.len())
        .flat_map(|i| (0..s[i].files.len()).map(move |k| (i, k)))
        .collect()
}

/// What `lumiere merge` does with files: decode each, then merge.
fn merge_files(files: &[(String, Vec<u8>)]) -> Result<Film, String> {
    let mut decoded = Vec::new();
    for (name, bytes) in files {
        let (h, pixels) = shard::decode(bytes, name)?;
        decoded.push((name.clone(), h, pixels));
    }
    shard::merge(decoded)
}

/// How a complete set of shards is spoilt before the merge.
#[derive(Clone, Debug)]
enum Spoil {
    Nothing,
    Drop(Index),
    Repeat(Index),
    AddForeign(Index),
    ReplaceWithForeign(Index, Index),
    FlipBit(Index, Index),
    Cut(Index, Index),
}

fn spoil() -> impl Strategy<Value = Spoil> {
    prop_oneof![
        2 => Just(Spoil::Nothing),
        1 => any::<Index>().prop_map(Spoil::Drop),
        1 => any::<Index>().prop_map(Spoil::Repeat),
        1 => any::<Index>().prop_map(Spoil::AddForeign),
        1 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Spoil::ReplaceWithForeign(a, b)),
        1 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Spoil::FlipBit(a, b)),
        1 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Spoil::Cut(a, b)),
    ]
}

/// A file size for a value that is either small, at a limit, or anything.
fn side() -> impl Strategy<Value = u32> {
    prop_oneof![4 => 1u32..=6, 1 => Just(0u32), 1 => Just(16_385u32), 1 => any::<u32>()]
}

proptest! {
    #[test]
    fn random_bytes_are_refused(bytes in prop::collection::vec(any::<u8>(), 0..2048), magic in any::<bool>()) {
        let mut file = if magic { b"LUMIERE-SHARD-2\n".to_vec() } else { Vec::new() };
        file.extend(bytes);
        prop_assert!(shard::decode(&file, "r.shard").is_err());
    }

    #[test]
    fn flipped_bits_are_refused(which in any::<Index>(), flips in prop::collection::vec(any::<Index>(), 1..=3)) {
        // On files of at most 2 KB, CRC-32 (IEEE) has a Hamming distance of at least 4: it
        // detects every error of 1 to 3 bits, wherever they are.
        let files = every_file();
        let (i, k) = files[which.index(files.len())];
        let good = &splits()[i].files[k];
        prop_assert!(good.len() <= 2048);
        let mut at: Vec<usize> = flips.iter().map(|f| f.index(good.len() * 8)).collect();
        at.sort_unstable();
        at.dedup();
        let mut bad = good.clone();
        for b in &at {
            bad[b / 8] ^= 1 << (b % 8);
        }
        let e = shard::decode(&bad, "f.shard").unwrap_err();
        prop_assert!(at[0] < MAGIC_LEN * 8 || e.starts_with("f.shard: checksum mismatch: expected CRC-32 "), "{}", e);
    }

    #[test]
    fn cut_or_lengthened_shards_are_refused(
        which in any::<Index>(),
        cut in any::<Index>(),
        extra in prop::collection::vec(any::<u8>(), 1..64),
    ) {
        let files = every_file();
        let (i, k) = files[which.index(files.len())];
        let good = &splits()[i].files[k];
        let short = &good[..cut.index(good.len())];
        prop_assert!(shard::decode(short, "c.shard").is_err());
        let mut long = good.clone();
        long.extend(extra);
        prop_assert!(shard::decode(&long, "l.shard").is_err());
    }

    #[test]
    fn forged_headers_with_a_right_checksum_never_panic(
        width in side(),
        height in side(),
        shards in prop_oneof![4 => 1u32..=4, 1 => Just(0u32), 1 => Just(65_537u32), 1 => any::<u32>()],
        shard_index in prop_oneof![4 => 0u32..4, 1 => any::<u32>()],
        rows in prop_oneof![3 => Just(None), 1 => any::<[u32; 2]>().prop_map(Some)],
        pixels in prop_oneof![3 => Just(None), 1 => (0usize..100).prop_map(Some)],
    ) {
        // What a render would write for these numbers, in u64 so that nothing overflows.
        let own_rows = |k: u32| (k as u64 * height as u64 / shards.max(1) as u64) as u32;
        let rows = rows.unwrap_or([own_rows(shard_index), own_rows(shard_index.saturating_add(1))]);
        let count = rows[1].saturating_sub(rows[0]) as u64 * width as u64;
        let pixels = pixels.unwrap_or(count.min(100) as usize);
        let valid = (1..=16_384).contains(&width)
            && (1..=16_384).contains(&height)
            && width as u64 * height as u64 <= 1 << 25
            && (1..=65_536).contains(&shards)
            && shard_index < shards
            && rows == [own_rows(shard_index), own_rows(shard_index + 1)]
            && pixels as u64 == count;
        let h = ShardHeader {
            width,
            height,
            shard: shard_index,
            shards,
            rows,
            scene_hash: "5".repeat(16),
            color_normalization: Default::default(),
        };
        let mut file = b"LUMIERE-SHARD-2\n".to_vec();
        file.extend(serde_json::to_vec(&h).unwrap());
        file.push(b'\n');
        file.extend((0..pixels * 3).flat_map(|i| (i as f64).to_le_bytes()));
        let crc = crc32fast::hash(&file);
        file.extend(crc.to_le_bytes());
        let decoded = shard::decode(&file, "h.shard");
        prop_assert_eq!(decoded.is_ok(), valid, "{:?}", decoded.as_ref().err());
        if let Ok((got, px)) = decoded {
            prop_assert_eq!(&got, &h);
            prop_assert_eq!(px.len(), pixels);
            // One shard merges alone exactly when it is the whole image.
            let merged = shard::merge(vec![("h.shard".into(), got, px)]);
            prop_assert_eq!(merged.is_ok(), shards == 1);
        }
    }

    #[test]
    fn merge_accepts_exactly_the_complete_sets(
        which in any::<Index>(),
        order in any::<prop::sample::Selector>(),
        spoil in spoil(),
    ) {
        let all = splits();
        let i = which.index(all.len());
        let mut files: Vec<(String, Vec<u8>)> = all[i]
            .files
            .iter()
            .enumerate()
            .map(|(k, f)| (format!("s{i}-{k}.shard"), f.clone()))
            .collect();
        // Any order: shuffle by repeated selection.
        let mut shuffled = Vec::new();
        while !files.is_empty() {
            let pick = order.select(0..files.len());
            shuffled.push(files.remove(pick));
        }
        let mut files = shuffled;
        let foreign = |x: &Index| {
            let others: Vec<_> = every_file().into_iter().filter(|&(j, _)| j != i).collect();
            let (j, k) = others[x.index(others.len())];
            (format!("s{j}-{k}.shard"), all[j].files[k].clone())
        };
        let n = files.len();
        match &spoil {
            Spoil::Nothing => {}
            Spoil::Drop(x) => {
                files.remove(x.index(n));
            }
            Spoil::Repeat(x) => {
                let f = files[x.index(n)].clone();
                files.push(f);
            }
            Spoil::AddForeign(x) => files.push(foreign(x)),
            Spoil::ReplaceWithForeign(x, y) => files[x.index(n)] = foreign(y),
            Spoil::FlipBit(x, b) => {
                let f = &mut files[x.index(n)].1;
                let b = b.index(f.len() * 8);
                f[b / 8] ^= 1 << (b % 8);
            }
            Spoil::Cut(x, c) => {
                let f = &mut files[x.index(n)].1;
                let len = c.index(f.len());
                f.truncate(len);
            }
        }
        match merge_files(&files) {
            Ok(film) => {
                prop_assert!(matches!(spoil, Spoil::Nothing), "{:?} accepted", spoil);
                prop_assert_eq!((film.width, film.height), (all[i].film.width, all[i].film.height));
                prop_assert_eq!(radiance_bits(&film.pixels), radiance_bits(&all[i].film.pixels));
            }
            Err(e) => prop_assert!(!matches!(spoil, Spoil::Nothing), "complete set refused: {}", e),
        }
    }
}

/// Renders shard `k` of `n` of the reference scene at 64 x 48 with the binary.
fn render_shard(out: &std::path::Path, k: u32, n: u32) {
    let scene = repo("scenes/reference.toml");
    let spec = format!("{k}/{n}");
    let o = lumiere(&[
        "render",
        scene.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "48",
        "--shard",
        &spec,
        "-o",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn merge_refuses_a_shard_with_one_flipped_bit() {
    let dir = temp_dir("flipped");
    let (a, b) = (dir.join("part0.shard"), dir.join("part1.shard"));
    render_shard(&a, 0, 2);
    render_shard(&b, 1, 2);
    let out = dir.join("merged.png");
    let (sa, sb, so) = (a.to_str().unwrap(), b.to_str().unwrap(), out.to_str().unwrap());
    // Undamaged, the two merge.
    let ok = lumiere(&["merge", sa, sb, "-o", so]);
    assert_eq!(ok.status.code(), Some(0), "{}", String::from_utf8_lossy(&ok.stderr));
    fs::remove_file(&out).unwrap();

    // One bit in the middle of the second shard's pixels.
    let mut bytes = fs::read(&b).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x08;
    fs::write(&b, &bytes).unwrap();
    let (expected, found) = checksums(&bytes);
    let o = lumiere(&["merge", sa, sb, "-o", so]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        format!(
            "lumiere: error: {sb}: checksum mismatch: expected CRC-32 {expected:08x} (stored in the file), found \
             {found:08x}: the shard is damaged, render it again\n"
        )
    );
    assert!(o.stdout.is_empty());
    assert!(!out.exists());

    // The same shard cut short: the message gives both sizes.
    bytes[middle] ^= 0x08;
    fs::write(&b, &bytes[..20_000]).unwrap();
    let o = lumiere(&["merge", sa, sb, "-o", so]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    let cut = format!(
        "; the file has 20000 bytes where its header describes {}: the shard is damaged",
        bytes.len()
    );
    assert!(
        err.contains(&format!("{sb}: checksum mismatch: ")) && err.contains(&cut),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn merge_refuses_a_shard_of_the_format_without_checksum() {
    let dir = temp_dir("shardv1");
    let (a, b) = (dir.join("part0.shard"), dir.join("part1.shard"));
    render_shard(&a, 0, 2);
    render_shard(&b, 1, 2);
    // The same shard as an older lumiere wrote it: first line LUMIERE-SHARD-1, no checksum.
    let bytes = fs::read(&a).unwrap();
    assert!(bytes.starts_with(b"LUMIERE-SHARD-2\n"));
    let mut old = b"LUMIERE-SHARD-1\n".to_vec();
    old.extend_from_slice(&bytes[MAGIC_LEN..bytes.len() - 4]);
    fs::write(&a, old).unwrap();
    let out = dir.join("merged.png");
    let o = lumiere(&[
        "merge",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&o.stderr),
        format!(
            "lumiere: error: {}: a LUMIERE-SHARD-1 file, written by an older lumiere (without a checksum): render \
             this shard again with this lumiere\n",
            a.display()
        )
    );
    assert!(!out.exists());
}
