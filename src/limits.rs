//! Limits on what a scene or a command line may ask for, so an absurd request gets a clear
//! error instead of exhausting memory. Shared by scene validation and command-line overrides.

/// Largest image side.
pub const MAX_DIMENSION: u32 = 16_384;
/// Largest pixel count (the film holds 24 bytes a pixel: 32 Mpixel is 768 MiB).
pub const MAX_PIXELS: u64 = 1 << 25;
/// Largest samples per pixel (the sample index must fit 16 bits of the stream index).
pub const MAX_SAMPLES: u32 = 1024;
/// Largest recursion depth.
pub const MAX_DEPTH: u32 = 64;
/// Most worker threads (each holds a stack; far beyond any machine's cores).
pub const MAX_THREADS: usize = 1024;
/// Most shapes in a scene.
pub const MAX_OBJECTS: usize = 4_000_000;
/// Most lights in a scene.
pub const MAX_LIGHTS: usize = 10_000;
/// Most points in one area light (each is a shadow ray per shading point).
pub const MAX_LIGHT_POINTS: u32 = 100_000;
/// Most points over all area lights of a scene: a `fixed` light keeps its points in memory
/// (24 bytes each, so 240 MB at the limit) and every point is a shadow ray per shading point.
/// Without it, 10 000 lights of 100 000 points would ask for about 30 GB.
pub const MAX_TOTAL_LIGHT_POINTS: u64 = 10_000_000;
/// Most oscillators in one aperture light (each is a sine and a cosine per shading point);
/// they count towards [`MAX_TOTAL_LIGHT_POINTS`] too.
pub const MAX_OSCILLATORS: u64 = 100_000;
/// Most instants in an aperture light's time average over one period.
pub const MAX_PERIOD_ITERATION: u32 = 100_000;
/// Largest coordinate magnitude (beyond it f64 hit points lose all sub-unit precision).
pub const MAX_COORDINATE: f64 = 1e9;
/// Most triangles in one mesh file (each is an object, so [`MAX_OBJECTS`] bounds the
/// scene's total too).
pub const MAX_MESH_TRIANGLES: usize = MAX_OBJECTS;
/// Most bytes read from one input file: a scene, a mesh, an image, a shard. More than the
/// other limits let any of them need (a mesh of 4 000 000 triangles is about 250 MB of
/// `.obj`, a shard of [`MAX_PIXELS`] pixels 768 MiB), and a bound on what a device that
/// never ends (`/dev/zero`) can make lumiere hold.
pub const MAX_FILE_BYTES: u64 = 1 << 30;
/// Smallest magnitude of a transform's scale factor (and of the singular values of its
/// matrix): below it a shape's local error bounds and sizes are stretched out of scale.
pub const MIN_SCALE: f64 = 1e-6;
/// Largest magnitude of a transform's scale factor (and of its matrix's entries).
pub const MAX_SCALE: f64 = 1e6;
/// Largest light colour channel.
pub const MAX_LIGHT: f64 = 1e6;
/// Largest specular exponent.
pub const MAX_SHININESS: f64 = 1e6;
/// Largest index of refraction.
pub const MAX_IOR: f64 = 10.0;
/// Most photons of a caustic pass (each is stored in 48 bytes: 480 MB at the limit).
pub const MAX_PHOTONS: u64 = 10_000_000;
/// Most specular bounces of a photon.
pub const MAX_PHOTON_BOUNCES: u32 = 64;
/// Default number of specular bounces of a photon.
pub const DEFAULT_PHOTON_BOUNCES: u32 = 8;
/// Default radius of the caustic estimate (scene units: a tenth of the reference scene's
/// spheres' radius).
pub const DEFAULT_PHOTON_RADIUS: f64 = 0.075;
/// Largest adaptive depth control threshold, in 8-bit levels (a difference of every level).
pub const MAX_ADAPTIVE_THRESHOLD: f64 = 255.0;
/// Largest factor of the figures' image size (`lumiere figures --scale`).
pub const MAX_FIGURE_SCALE: f64 = 4.0;
/// Default adaptive depth control threshold, in 8-bit levels.
pub const DEFAULT_ADAPTIVE_THRESHOLD: f64 = 0.25;

/// The bytes of the input file at `path`, at most [`MAX_FILE_BYTES`] of them: a longer file
/// (told by its size, before reading) or a device or pipe that gives more is an error that
/// says so, after which nothing more is read.
pub fn read_file(path: &std::path::Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let too_long = |what: String| {
        std::io::Error::new(
            std::io::ErrorKind::FileTooLarge,
            format!("{what} more than the {MAX_FILE_BYTES} bytes read from one file"),
        )
    };
    let file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if meta.is_file() && meta.len() > MAX_FILE_BYTES {
        return Err(too_long(format!("the file has {} bytes,", meta.len())));
    }
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(too_long("it gives".to_string()));
    }
    Ok(bytes)
}

/// Whether every coordinate of `p` is finite and within [`MAX_COORDINATE`].
pub fn within_coordinates(p: glam::DVec3) -> bool {
    p.is_finite() && p.abs().max_element() <= MAX_COORDINATE
}

/// A number as messages show a limit: the shorter of its decimal and exponent forms, the
/// decimal one on a tie (`179`, `0.25`, `1e9`, `1e-6`, `-1e9`).
pub fn short(x: f64) -> String {
    let plain = x.to_string();
    let exponent = format!("{x:e}");
    if exponent.len() < plain.len() { exponent } else { plain }
}

/// A whole number as a reader has it: its value when it fits 128 bits (TOML's integers, a
/// command line's text of any length), and the number as written, which messages show.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Whole {
    value: Option<i128>,
    written: String,
}

impl Whole {
    /// The number `text` writes: one that is not a whole number of 128 bits (`1e400`,
    /// `2.5`, 40 digits, `x`) has no value, so every check refuses it and shows it as written.
    pub fn parse(text: &str) -> Whole {
        Whole {
            value: text.trim().parse().ok(),
            written: text.to_string(),
        }
    }

    /// The value narrowed to `T` when it is in `[lo, hi]`.
    fn within<T: TryFrom<i128> + PartialOrd>(&self, lo: T, hi: T) -> Option<T> {
        let n = T::try_from(self.value?).ok()?;
        (n >= lo && n <= hi).then_some(n)
    }
}

impl std::fmt::Display for Whole {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.written)
    }
}

macro_rules! whole_from {
    ($($t:ty),*) => {$(
        impl From<$t> for Whole {
            fn from(n: $t) -> Whole {
                Whole { value: Some(n.into()), written: n.to_string() }
            }
        }
    )*};
}
whole_from!(i8, i16, i32, i64, i128, u8, u16, u32, u64);

/// An image side of `v` pixels: in [1, MAX_DIMENSION], or the message saying so.
pub fn check_dimension(v: impl Into<Whole>) -> Result<u32, String> {
    let v = v.into();
    v.within(1, MAX_DIMENSION)
        .ok_or_else(|| format!("must be in [1, {MAX_DIMENSION}] pixels, got {v}"))
}

pub fn check_pixel_count(w: u32, h: u32) -> Result<(), String> {
    let n = w as u64 * h as u64;
    if n > MAX_PIXELS {
        return Err(format!(
            "width x height must be at most {MAX_PIXELS} pixels, got {w} x {h} = {n}"
        ));
    }
    Ok(())
}

/// Samples per pixel: any count in [1, MAX_SAMPLES], one in each cell of the pixel's
/// [`SampleGrid`](crate::scene::SampleGrid).
pub fn check_samples(v: impl Into<Whole>) -> Result<u32, String> {
    check_count(v, MAX_SAMPLES)
}

/// The recursion depth: in [1, MAX_DEPTH], 1 for no secondary rays.
pub fn check_depth(v: impl Into<Whole>) -> Result<u32, String> {
    let v = v.into();
    v.within(1, MAX_DEPTH)
        .ok_or_else(|| format!("must be in [1, {MAX_DEPTH}] (1 = no secondary rays), got {v}"))
}

/// A count in [1, `most`], narrowed to `most`'s type.
pub fn check_count<T>(v: impl Into<Whole>, most: T) -> Result<T, String>
where
    T: TryFrom<i128> + PartialOrd + From<u8> + std::fmt::Display,
{
    check_whole(v, T::from(1), most)
}

/// A whole number in [`lo`, `hi`], narrowed to their type: a seed's range is its type's,
/// `[0, u64::MAX]`.
pub fn check_whole<T>(v: impl Into<Whole>, lo: T, hi: T) -> Result<T, String>
where
    T: TryFrom<i128> + PartialOrd + std::fmt::Display,
{
    let v = v.into();
    let message = format!("must be in [{lo}, {hi}], got {v}");
    v.within(lo, hi).ok_or(message)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_numbers_are_checked_as_written_and_narrowed() {
        assert_eq!(check_dimension(16_384), Ok(16_384));
        assert_eq!(
            check_dimension(-4),
            Err("must be in [1, 16384] pixels, got -4".to_string())
        );
        let huge: i128 = 99_999_999_999_999_999_999;
        assert_eq!(
            check_dimension(huge),
            Err("must be in [1, 16384] pixels, got 99999999999999999999".to_string())
        );
        for good in [1, 2, 3, 6, 7, 1021, 1024] {
            assert_eq!(check_samples(good), Ok(good as u32));
        }
        for bad in [0, 1025, 1089, -1] {
            assert_eq!(check_samples(bad), Err(format!("must be in [1, 1024], got {bad}")));
        }
        assert_eq!(check_depth(64), Ok(64));
        assert_eq!(
            check_depth(65),
            Err("must be in [1, 64] (1 = no secondary rays), got 65".to_string())
        );
        assert_eq!(check_count(4_000_000, MAX_OBJECTS), Ok(4_000_000usize));
        assert_eq!(
            check_count(0, MAX_OBJECTS),
            Err("must be in [1, 4000000], got 0".to_string())
        );
        assert_eq!(check_count(-1, 64u32), Err("must be in [1, 64], got -1".to_string()));
        assert_eq!(
            check_count(u64::MAX, 64u32),
            Err(format!("must be in [1, 64], got {}", u64::MAX))
        );
        assert_eq!(check_whole(u64::MAX, 0, u64::MAX), Ok(u64::MAX));
        assert_eq!(
            check_whole(-1, 0, u64::MAX),
            Err("must be in [0, 18446744073709551615], got -1".to_string())
        );
    }

    #[test]
    fn written_numbers_are_checked_and_shown_as_written() {
        assert_eq!(check_dimension(Whole::parse("+16384")), Ok(16_384));
        let forty = "9".repeat(40);
        for text in ["1e400", "2.5", "", "x", forty.as_str()] {
            assert_eq!(
                check_dimension(Whole::parse(text)),
                Err(format!("must be in [1, 16384] pixels, got {text}"))
            );
        }
        assert_eq!(check_whole(Whole::parse("-0"), 0u8, 255), Ok(0));
    }

    #[test]
    fn limits_are_shown_short() {
        for (x, shown) in [
            (179.0, "179"),
            (0.25, "0.25"),
            (100.0, "100"),
            (1e6, "1e6"),
            (MAX_COORDINATE, "1e9"),
            (-MAX_COORDINATE, "-1e9"),
            (MIN_SCALE, "1e-6"),
            (1e12, "1e12"),
            (0.0, "0"),
        ] {
            assert_eq!(short(x), shown);
        }
    }
}
