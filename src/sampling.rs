//! Seeded random streams. Every random choice draws from its own ChaCha8 stream keyed by
//! `(seed, purpose, index)`, so no result depends on thread count, tile order, or what else
//! was rendered before.
//!
//! [`Stream`] is rand_chacha's ChaCha8 generator, which computes four blocks of 16 words
//! at a time. [`ShortStream`] reads the same words but computes each block alone when it is
//! first read ([`chacha8_block`]): a pixel's jitter reads one block (4 samples x 2 numbers x
//! 2 words) from a stream of its own, so the other three would be computed for nothing.
//! The renderer starts the streams of a row's pixels 8 at a time, their first blocks
//! computed side by side in vector lanes ([`ShortStream::first_blocks`]).

use multiversion::multiversion;
use rand_chacha::ChaCha8Rng;
use rand_core::{Rng, SeedableRng};

/// What a stream is for; part of the key, so streams of different purposes never overlap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u64)]
pub enum Purpose {
    /// Sub-pixel jitter: index = pixel; sample `k` reads words `4k .. 4k + 4`.
    PixelJitter = 1,
    /// Light points of an area light: index = light number (fixed mode) or
    /// `pixel << 16 | sample` combined with the light (per-sample mode).
    LightPoints = 2,
    /// Anything a test or a generator draws.
    Generator = 3,
    /// Caustic photons: index = photon number; the emitter, the direction, then one number
    /// per bounce ([`crate::caustics`]).
    Photons = 4,
}

/// One random stream.
#[derive(Clone, Debug)]
pub struct Stream(ChaCha8Rng);

impl Stream {
    /// The stream for `(seed, purpose, index)`.
    pub fn new(seed: u64, purpose: Purpose, index: u64) -> Self {
        let mut key = [0u8; 32];
        for (bytes, word) in key.chunks_exact_mut(4).zip(key_words(seed, purpose)) {
            bytes.copy_from_slice(&word.to_le_bytes());
        }
        let mut rng = ChaCha8Rng::from_seed(key);
        rng.set_stream(index);
        Stream(rng)
    }

    /// The same stream, positioned `words` 32-bit words from its start (each
    /// [`Stream::next_f64`] takes two words).
    pub fn skip_words(mut self, words: u128) -> Self {
        self.0.set_word_pos(words);
        self
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        unit_interval(self.0.next_u64())
    }
}

/// The ChaCha key of `(seed, purpose)` as little-endian 32-bit words: the seed, the
/// purpose, then zeros.
fn key_words(seed: u64, purpose: Purpose) -> [u32; 8] {
    let purpose = purpose as u64;
    [
        seed as u32,
        (seed >> 32) as u32,
        purpose as u32,
        (purpose >> 32) as u32,
        0,
        0,
        0,
        0,
    ]
}

/// The number in [0, 1) of a random `u64`'s 53 high bits.
#[inline(always)]
pub fn unit_interval(bits: u64) -> f64 {
    (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A row of the ChaCha state: four 32-bit words, added, xored and rotated lane by lane.
type Row = [u32; 4];

/// One 64-byte block of ChaCha8 as rand_chacha's `ChaCha8Rng` computes it, as 16
/// little-endian words: the state is the constant "expand 32-byte k", the 256-bit `key`,
/// the 64-bit block `counter` and the 64-bit `stream` (words 12-13 and 14-15); four double
/// rounds, and the input state added word by word (Bernstein, "ChaCha, a variant of
/// Salsa20", 2008; RFC 8439 section 2.3 reads words 13-15 as a 96-bit nonce instead).
/// The quarter round runs on the four columns side by side (lane `i` of each row is column
/// `i`), then on the four diagonals turned into columns. The compiler keeps the 16 words in
/// general registers: four independent chains of dependent additions, xors and rotations,
/// which run side by side, where one chain of vector operations on rows (SSE2, without a
/// rotation instruction) measured slower in the renderer (+5 % CPU on the reference scene).
#[inline(always)]
pub fn chacha8_block(key: &[u32; 8], counter: u64, stream: u64) -> [u32; 16] {
    let input: [Row; 4] = [
        [0x6170_7865, 0x3320_646e, 0x7962_2d32, 0x6b20_6574],
        [key[0], key[1], key[2], key[3]],
        [key[4], key[5], key[6], key[7]],
        [
            counter as u32,
            (counter >> 32) as u32,
            stream as u32,
            (stream >> 32) as u32,
        ],
    ];
    let mut x = input;
    for _ in 0..4 {
        x = quarter_rounds(x);
        // Lane i of rows b, c, d takes lane i + 1, i + 2, i + 3: the diagonal (x0, x5, x10,
        // x15) and the three after it become columns; then back.
        let [a, b, c, d] = quarter_rounds([x[0], turn(x[1], 1), turn(x[2], 2), turn(x[3], 3)]);
        x = [a, turn(b, 3), turn(c, 2), turn(d, 1)];
    }
    let mut out = [0; 16];
    for (row, (x, input)) in x.iter().zip(&input).enumerate() {
        out[4 * row..4 * row + 4].copy_from_slice(&add(*x, *input));
    }
    out
}

/// The ChaCha quarter round on `N` quarters at once (lane `i` of `a`, `b`, `c`, `d` is
/// quarter `i`): `a += b; d ^= a; d <<<= 16; c += d; b ^= c; b <<<= 12; a += b; d ^= a;
/// d <<<= 8; c += d; b ^= c; b <<<= 7` (RFC 8439 section 2.1).
#[inline(always)]
fn quarter_rounds<const N: usize>([mut a, mut b, mut c, mut d]: [[u32; N]; 4]) -> [[u32; N]; 4] {
    a = add(a, b);
    d = xor_rotate(d, a, 16);
    c = add(c, d);
    b = xor_rotate(b, c, 12);
    a = add(a, b);
    d = xor_rotate(d, a, 8);
    c = add(c, d);
    b = xor_rotate(b, c, 7);
    [a, b, c, d]
}

/// `a + b` in each lane, modulo 2^32.
#[inline(always)]
fn add<const N: usize>(a: [u32; N], b: [u32; N]) -> [u32; N] {
    std::array::from_fn(|i| a[i].wrapping_add(b[i]))
}

/// `(a xor b) <<< n` in each lane.
#[inline(always)]
fn xor_rotate<const N: usize>(a: [u32; N], b: [u32; N], n: u32) -> [u32; N] {
    std::array::from_fn(|i| (a[i] ^ b[i]).rotate_left(n))
}

/// The lanes of `r` turned left by `k`: lane `i` takes lane `i + k mod 4`.
#[inline(always)]
fn turn(r: Row, k: usize) -> Row {
    std::array::from_fn(|i| r[(i + k) % 4])
}

/// How many streams [`chacha8_blocks`] computes side by side.
pub const LANES: usize = 8;

/// Block `counter` of the ChaCha8 streams `streams` of one `key`: for each stream `l`,
/// `out[l]` is [`chacha8_block`]`(key, counter, streams[l])`. The 16 state words are each a
/// vector of the streams' lanes, so the quarter rounds are vector additions, xors and
/// rotations of 8 lanes, compiled for AVX-512 and AVX2 and chosen at run time: a row of
/// pixels' jitter blocks computed 8 pixels at a time.
#[multiversion(targets("x86_64+avx512f+avx512vl", "x86_64+avx2"))]
pub fn chacha8_blocks(key: &[u32; 8], counter: u64, streams: &[u64; LANES]) -> [[u32; 16]; LANES] {
    let constants = [0x6170_7865, 0x3320_646e, 0x7962_2d32, 0x6b20_6574];
    // Word by word in plain loops: `array::from_fn` with a closure compiles to a call a word.
    let mut input = [[0u32; LANES]; 16];
    for w in 0..4 {
        input[w] = [constants[w]; LANES];
    }
    for w in 0..8 {
        input[4 + w] = [key[w]; LANES];
    }
    input[12] = [counter as u32; LANES];
    input[13] = [(counter >> 32) as u32; LANES];
    for l in 0..LANES {
        input[14][l] = streams[l] as u32;
        input[15][l] = (streams[l] >> 32) as u32;
    }
    let mut x = input;
    for _ in 0..4 {
        for i in 0..4 {
            [x[i], x[4 + i], x[8 + i], x[12 + i]] = quarter_rounds([x[i], x[4 + i], x[8 + i], x[12 + i]]);
        }
        // The diagonals (x0, x5, x10, x15) and the three after it.
        for i in 0..4 {
            let (b, c, d) = (4 + (i + 1) % 4, 8 + (i + 2) % 4, 12 + (i + 3) % 4);
            [x[i], x[b], x[c], x[d]] = quarter_rounds([x[i], x[b], x[c], x[d]]);
        }
    }
    let mut out = [[0u32; 16]; LANES];
    for w in 0..16 {
        let sum = add(x[w], input[w]);
        for l in 0..LANES {
            out[l][w] = sum[l];
        }
    }
    out
}

/// The words of [`Stream`] for the same `(seed, purpose, index)`, bit for bit, for streams
/// read for a few words: each block of 16 words is computed alone ([`chacha8_block`]) when
/// the first of its words is read.
#[derive(Clone, Debug)]
pub struct ShortStream {
    key: [u32; 8],
    stream: u64,
    /// The block the next word is read from.
    counter: u64,
    /// Block `counter`'s words, once computed.
    words: [u32; 16],
    /// The next word's position in `words`; 16 when block `counter` is not computed yet.
    next: usize,
}

impl ShortStream {
    /// The stream for `(seed, purpose, index)`: [`Stream::new`]'s key and stream number.
    pub fn new(seed: u64, purpose: Purpose, index: u64) -> Self {
        ShortStream {
            key: key_words(seed, purpose),
            stream: index,
            counter: 0,
            words: [0; 16],
            next: 16,
        }
    }

    /// The streams of `(seed, purpose, index)` for the indices `indices`, each with its
    /// first block already computed, the blocks side by side ([`chacha8_blocks`]).
    pub fn first_blocks(seed: u64, purpose: Purpose, indices: &[u64; LANES]) -> [Self; LANES] {
        let key = key_words(seed, purpose);
        let blocks = chacha8_blocks(&key, 0, indices);
        std::array::from_fn(|l| ShortStream {
            key,
            stream: indices[l],
            counter: 0,
            words: blocks[l],
            next: 0,
        })
    }

    /// The same stream, positioned `words` 32-bit words from its start (as
    /// [`Stream::skip_words`], whose block counter wraps at 2^64 blocks).
    pub fn skip_words(mut self, words: u128) -> Self {
        self.counter = (words / 16) as u64;
        self.next = 16;
        let within = (words % 16) as usize;
        if within != 0 {
            self.refill();
            self.next = within;
        }
        self
    }

    /// Computes block `counter` into `words`.
    #[inline(always)]
    fn refill(&mut self) {
        self.words = chacha8_block(&self.key, self.counter, self.stream);
    }

    /// The next 32-bit word.
    #[inline(always)]
    pub fn next_u32(&mut self) -> u32 {
        if self.next == 16 {
            self.refill();
            self.next = 0;
        }
        let word = self.words[self.next];
        self.next += 1;
        if self.next == 16 {
            self.counter = self.counter.wrapping_add(1);
        }
        word
    }

    /// The next two words as one number, the first in the low half (as rand_core's block
    /// generators read a `u64`).
    #[inline(always)]
    pub fn next_u64(&mut self) -> u64 {
        let low = self.next_u32();
        u64::from(self.next_u32()) << 32 | u64::from(low)
    }

    /// Uniform in [0, 1) with 53 random bits: [`Stream::next_f64`]'s number.
    #[inline(always)]
    pub fn next_f64(&mut self) -> f64 {
        unit_interval(self.next_u64())
    }
}

/// Stream index of a pixel sample: `pixel << 16 | sample` (samples < 65536).
pub fn sample_index(pixel: u64, sample: u32) -> u64 {
    (pixel << 16) | sample as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let a: Vec<f64> = (0..4)
            .scan(Stream::new(42, Purpose::PixelJitter, 7), |s, _| Some(s.next_f64()))
            .collect();
        let b: Vec<f64> = (0..4)
            .scan(Stream::new(42, Purpose::PixelJitter, 7), |s, _| Some(s.next_f64()))
            .collect();
        assert_eq!(a, b);
        let mut other = Stream::new(42, Purpose::PixelJitter, 8);
        assert_ne!(a[0], other.next_f64());
        let mut other = Stream::new(42, Purpose::LightPoints, 7);
        assert_ne!(a[0], other.next_f64());
        assert!(a.iter().all(|x| (0.0..1.0).contains(x)));
    }

    /// rand_chacha's ChaCha8 generator for a raw 256-bit key (as little-endian words),
    /// stream and word position: the reference [`ShortStream`] and [`chacha8_block`] are
    /// held to.
    fn reference_at(key: &[u32; 8], stream: u64, word: u128) -> ChaCha8Rng {
        let mut bytes = [0u8; 32];
        for (chunk, k) in bytes.chunks_exact_mut(4).zip(key) {
            chunk.copy_from_slice(&k.to_le_bytes());
        }
        let mut rng = ChaCha8Rng::from_seed(bytes);
        rng.set_stream(stream);
        rng.set_word_pos(word);
        rng
    }

    #[test]
    fn blocks_are_rand_chachas_words() {
        // 2000 random keys, streams and block counters, the counters including the carry
        // from the low to the high word (2^32 - 1, 2^32) and the last block before 2^64
        // wraps (rand_chacha's word position is 68 bits: block counter and word).
        let mut draw = ChaCha8Rng::seed_from_u64(0x5eed);
        for case in 0..2000u64 {
            let key: [u32; 8] = std::array::from_fn(|_| draw.next_u32());
            let stream = draw.next_u64();
            let counter = match case % 5 {
                0 => u64::from(draw.next_u32() % 4),
                1 => (1 << 32) - 1,
                2 => 1 << 32,
                3 => u64::MAX,
                _ => draw.next_u64(),
            };
            let mut reference = reference_at(&key, stream, u128::from(counter) * 16);
            let want: [u32; 16] = std::array::from_fn(|_| reference.next_u32());
            assert_eq!(
                chacha8_block(&key, counter, stream),
                want,
                "key {key:x?} stream {stream} block {counter}"
            );
        }
    }

    #[test]
    fn side_by_side_blocks_are_each_streams_block() {
        // 500 random keys, each with 8 streams (random, consecutive pixel indices, and the
        // extremes of the two stream words) and block counters as above.
        let mut draw = ChaCha8Rng::seed_from_u64(0xb10c);
        for case in 0..500u64 {
            let key: [u32; 8] = std::array::from_fn(|_| draw.next_u32());
            let base = draw.next_u64() >> (case % 3 * 20);
            let streams: [u64; LANES] = match case % 4 {
                0 => std::array::from_fn(|_| draw.next_u64()),
                1 => std::array::from_fn(|l| base.wrapping_add(l as u64)),
                2 => [0, 1, u32::MAX as u64, 1 << 32, u64::MAX, u64::MAX - 1, base, !base],
                _ => [base; LANES],
            };
            let counter = match case % 5 {
                0 | 4 => 0,
                1 => (1 << 32) - 1,
                2 => u64::MAX,
                _ => draw.next_u64(),
            };
            let blocks = chacha8_blocks(&key, counter, &streams);
            for (l, &stream) in streams.iter().enumerate() {
                assert_eq!(
                    blocks[l],
                    chacha8_block(&key, counter, stream),
                    "key {key:x?} stream {stream}"
                );
            }
        }
    }

    #[test]
    fn first_blocks_start_each_pixels_stream() {
        // The batch's streams read what each stream read alone reads, past its first block.
        let indices: [u64; LANES] = std::array::from_fn(|l| 799 * 600 + 795 + l as u64);
        for (l, mut batched) in ShortStream::first_blocks(42, Purpose::PixelJitter, &indices)
            .into_iter()
            .enumerate()
        {
            let mut alone = ShortStream::new(42, Purpose::PixelJitter, indices[l]);
            for _ in 0..20 {
                assert_eq!(batched.next_f64().to_bits(), alone.next_f64().to_bits(), "lane {l}");
            }
        }
    }

    #[test]
    fn zero_key_block_is_the_published_one() {
        // ChaCha8, key and nonce zero, block 0: the first test vector of
        // draft-strombergson-chacha-test-vectors-01 (TC1, 8 rounds), as bytes.
        let want = "3e00ef2f895f40d67f5bb8e81f09a5a12c840ec3ce9a7f3b181be188ef711a1e\
                    984ce172b9216f419f445367456d5619314a42a3da86b001387bfdb80e0cfe42";
        let bytes: String = chacha8_block(&[0; 8], 0, 0)
            .iter()
            .map(|w| format!("{:08x}", w.swap_bytes()))
            .collect();
        assert_eq!(bytes, want.split_whitespace().collect::<String>());
    }

    #[test]
    fn short_streams_read_streams_words() {
        // Random seeds, every purpose, random pixel-sized and full 64-bit indices; positions
        // at and around block boundaries (15, 16, 17 words; a block after the 4-block
        // buffer of rand_chacha) and random ones; then 40 reads mixing 32- and 64-bit
        // numbers, so the 64-bit ones straddle blocks at odd positions.
        let purposes = [
            Purpose::PixelJitter,
            Purpose::LightPoints,
            Purpose::Generator,
            Purpose::Photons,
        ];
        let mut draw = ChaCha8Rng::seed_from_u64(27);
        for case in 0..4000u64 {
            let seed = if case % 3 == 0 { case } else { draw.next_u64() };
            let purpose = purposes[(case % 4) as usize];
            let index = if case % 2 == 0 {
                u64::from(draw.next_u32() % 480_000)
            } else {
                draw.next_u64()
            };
            let start = match case % 8 {
                0 => 0,
                1 => 15,
                2 => 16,
                3 => 17,
                4 => 63,
                5 => 64,
                6 => u128::from(draw.next_u32()),
                _ => u128::from(draw.next_u64()) << 4 | u128::from(draw.next_u32() % 16),
            };
            let mut want = Stream::new(seed, purpose, index).skip_words(start).0;
            let mut got = if start == 0 {
                ShortStream::new(seed, purpose, index)
            } else {
                ShortStream::new(seed, purpose, index).skip_words(start)
            };
            for read in 0..40 {
                if (read + case) % 3 == 0 {
                    assert_eq!(got.next_u32(), want.next_u32(), "case {case} read {read}");
                } else {
                    assert_eq!(got.next_u64(), want.next_u64(), "case {case} read {read}");
                }
            }
        }
    }

    #[test]
    fn short_streams_give_the_jitter_numbers() {
        // A pixel's jitter as the renderer reads it: 4 samples x 2 numbers from the start,
        // and sample k alone from word 4k; both the f64 of `Stream`, to the bit.
        for pixel in [0u64, 1, 799, 479_999, 1 << 40] {
            let mut want = Stream::new(42, Purpose::PixelJitter, pixel);
            let mut got = ShortStream::new(42, Purpose::PixelJitter, pixel);
            for _ in 0..8 {
                assert_eq!(got.next_f64().to_bits(), want.next_f64().to_bits());
            }
            for k in 0..9u128 {
                let mut want = Stream::new(7, Purpose::PixelJitter, pixel).skip_words(4 * k);
                let mut got = ShortStream::new(7, Purpose::PixelJitter, pixel).skip_words(4 * k);
                for _ in 0..2 {
                    let x = got.next_f64();
                    assert_eq!(x.to_bits(), want.next_f64().to_bits());
                    assert!((0.0..1.0).contains(&x));
                }
            }
        }
    }
}
