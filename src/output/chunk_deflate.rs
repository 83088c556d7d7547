//! A step field's chunk filtered as HDF5's shuffle and deflate filters would filter it, here
//! instead of in the library, and stored as it is (`native::hdf5_chunk`). What a reader
//! finds is what HDF5's own filters write, a zlib stream (RFC 1950) of shuffled bytes, read back
//! through the same pipeline by h5py, meshio or ParaView. What differs is the cost: libdeflate
//! compresses at level 1 about twice as fast as the system zlib that HDF5's filter calls, and
//! the byte planes that no compression can shrink (the low bytes of the mantissas, whose byte
//! values are all about equally frequent) are copied into the stream as stored blocks instead of
//! being searched for matches that are not there: half the compression time again, for the same
//! size (docs/performance.md, "Results that take no time"). A chunk whose bytes are all zero is
//! not stored at all: a reader gets the dataset's fill value, zero.

use libdeflater::{adler32, CompressionLvl, Compressor};

/// A byte plane whose bytes carry more than this many bits of (order-0) entropy is stored, not
/// compressed: deflate gains nothing on it. On the pull-out's fields (docs/performance.md) 7.98
/// gave the same file as compressing every plane in half the time; 7.95, 3 % larger.
const STORED_ENTROPY: f64 = 7.98;
/// The most bytes a stored block holds (RFC 1951, 3.2.4).
const STORED_BLOCK: usize = 65_535;

/// Shuffles and deflates chunks, reusing its buffers from one chunk to the next.
pub struct ChunkDeflater {
    compressor: Compressor,
    shuffled: Vec<u8>,
    deflated: Vec<u8>,
}

impl ChunkDeflater {
    /// A deflater at `level` (1 to 12; HDF5's deflate filter reads any).
    ///
    /// # Errors
    /// A message when libdeflate has no such level.
    pub fn new(level: u8) -> Result<Self, String> {
        let level = CompressionLvl::new(i32::from(level)).map_err(|e| format!("deflate level {level}: {e:?}"))?;
        Ok(ChunkDeflater { compressor: Compressor::new(level), shuffled: Vec::new(), deflated: Vec::new() })
    }

    /// The chunk of `len` values whose first ones are `values` (each its `S` bytes as the
    /// dataset's type stores them; the rest zero, as HDF5 pads a chunk at a dataset's edge),
    /// shuffled (byte `j` of value `i` at `j · len + i`, as HDF5's shuffle filter puts it) and
    /// deflated into a zlib stream: the leading planes that cannot be compressed as stored
    /// blocks, the rest compressed. `None` when every byte is zero.
    ///
    /// # Errors
    /// A message when `values` holds more than `len` values.
    pub fn deflate<const S: usize>(&mut self, values: &[[u8; S]], len: usize) -> Result<Option<&[u8]>, String> {
        if values.len() > len {
            return Err(format!("more than {len} values for a chunk of {len}"));
        }
        // (or-ed together without an early exit, which the compiler vectorises)
        if values.as_flattened().iter().fold(0, |any, &b| any | b) == 0 {
            return Ok(None);
        }
        // plane by plane: byte j of every value, the padding left zero
        self.shuffled.clear();
        self.shuffled.resize(len * S, 0);
        for (j, plane) in self.shuffled.chunks_exact_mut(len).enumerate() {
            for (to, value) in plane.iter_mut().zip(values) {
                *to = value[j];
            }
        }
        let stored = len * self.shuffled.chunks_exact(len).take_while(|plane| entropy(plane) > STORED_ENTROPY).count();
        let (raw, compressed) = self.shuffled.split_at(stored);
        self.deflated.clear();
        // zlib's header: deflate with a 32 KiB window, the fastest level, no dictionary (a
        // multiple of 31 as a big-endian number)
        self.deflated.extend_from_slice(&[0x78, 0x01]);
        // the stored blocks, none of them the last: a byte for BFINAL = 0 and BTYPE = 00 (the
        // block starts on a byte), then LEN and its one's complement, little-endian
        for block in raw.chunks(STORED_BLOCK) {
            let n = block.len() as u16;
            self.deflated.push(0);
            self.deflated.extend_from_slice(&n.to_le_bytes());
            self.deflated.extend_from_slice(&(!n).to_le_bytes());
            self.deflated.extend_from_slice(block);
        }
        if compressed.is_empty() {
            // an empty last stored block
            self.deflated.extend_from_slice(&[1, 0, 0, 0xff, 0xff]);
        } else {
            // libdeflate's blocks, starting on the byte after the stored ones, the last marked
            // BFINAL
            let at = self.deflated.len();
            self.deflated.resize(at + self.compressor.deflate_compress_bound(compressed.len()), 0);
            let n = self
                .compressor
                .deflate_compress(compressed, &mut self.deflated[at..])
                .map_err(|e| format!("deflating a chunk of {len} values: {e:?}"))?;
            self.deflated.truncate(at + n);
        }
        // the Adler-32 checksum of the whole chunk, big-endian
        self.deflated.extend_from_slice(&adler32(&self.shuffled).to_be_bytes());
        Ok(Some(&self.deflated))
    }
}

/// The order-0 entropy of `bytes` in bits a byte: 8 when every byte value is equally frequent.
fn entropy(bytes: &[u8]) -> f64 {
    // four tables counted in turn, so that a run of one byte value does not wait on its own
    // last count
    let mut counts = [[0u32; 256]; 4];
    let mut quads = bytes.chunks_exact(4);
    for q in &mut quads {
        for (table, &b) in counts.iter_mut().zip(q) {
            table[usize::from(b)] += 1;
        }
    }
    for &b in quads.remainder() {
        counts[0][usize::from(b)] += 1;
    }
    let n = bytes.len() as f64;
    (0..256)
        .map(|v| counts.iter().map(|table| table[v]).sum::<u32>())
        .filter(|&c| c > 0)
        .map(|c| {
            let p = f64::from(c) / n;
            -p * p.log2()
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    fn bytes_of<T: Copy, const S: usize>(values: &[T], bytes: fn(T) -> [u8; S]) -> Vec<[u8; S]> {
        values.iter().map(|&v| bytes(v)).collect()
    }

    /// Inflate with zlib (flate2), as HDF5's filter does, and undo the shuffle.
    fn unfilter<const S: usize>(deflated: &[u8], len: usize) -> Vec<[u8; S]> {
        let mut shuffled = Vec::new();
        flate2::read::ZlibDecoder::new(deflated).read_to_end(&mut shuffled).unwrap();
        assert_eq!(shuffled.len(), len * S);
        (0..len).map(|i| std::array::from_fn(|j| shuffled[j * len + i])).collect()
    }

    #[test]
    fn a_chunk_comes_back_through_zlib_and_the_unshuffle_padded_with_zeros() {
        let values: Vec<f32> = (0..1000).map(|i| (i as f32 * 0.37).sin() * 1e-3).collect();
        let mut deflater = ChunkDeflater::new(1).unwrap();
        let deflated = deflater.deflate(&bytes_of(&values, f32::to_ne_bytes), 1200).unwrap().unwrap().to_vec();
        let back: Vec<f32> = unfilter::<4>(&deflated, 1200).into_iter().map(f32::from_ne_bytes).collect();
        assert_eq!(&back[..1000], &values[..]);
        assert!(back[1000..].iter().all(|&v| v.to_bits() == 0));
        // the buffers reused for a second chunk of another width
        let doubles = [1.5f64, -2.25, 0.0, 1e-300];
        let deflated = deflater.deflate(&bytes_of(&doubles, f64::to_ne_bytes), 4).unwrap().unwrap().to_vec();
        let back: Vec<f64> = unfilter::<8>(&deflated, 4).into_iter().map(f64::from_ne_bytes).collect();
        assert_eq!(back, doubles);
    }

    /// Values whose low bytes are noise (a linear congruential generator's bits), so that the
    /// leading planes are stored and the rest compressed, or every plane stored.
    fn noisy(n: usize, scale: f64) -> Vec<f64> {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        (0..n)
            .map(|i| {
                x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                1.0 + (i as f64 * 1e-4).sin() + scale * ((x >> 11) as f64 / (1u64 << 53) as f64)
            })
            .collect()
    }

    #[test]
    fn incompressible_planes_are_stored_and_the_stream_still_inflates_to_the_chunk() {
        let mut deflater = ChunkDeflater::new(1).unwrap();
        // double precision: the low planes noise, the exponent's compressible
        let values = noisy(100_000, 1e-3);
        let deflated = deflater.deflate(&bytes_of(&values, f64::to_ne_bytes), 100_000).unwrap().unwrap().to_vec();
        // the stored blocks are there: a stored block's header follows zlib's
        assert_eq!(&deflated[..3], &[0x78, 0x01, 0x00], "the first plane stored");
        let back: Vec<f64> = unfilter::<8>(&deflated, 100_000).into_iter().map(f64::from_ne_bytes).collect();
        assert_eq!(back, values);
        // smaller than the chunk, larger than its compressible planes could make it
        assert!(deflated.len() < 8 * 100_000, "{}", deflated.len());
        // every plane noise: all stored, ending with an empty last block
        let bits: Vec<u32> = noisy(70_000, 1.0).iter().map(|v| (v.to_bits() >> 7) as u32).collect();
        let deflated = deflater.deflate(&bytes_of(&bits, u32::to_ne_bytes), 70_000).unwrap().unwrap().to_vec();
        let back: Vec<u32> = unfilter::<4>(&deflated, 70_000).into_iter().map(u32::from_ne_bytes).collect();
        assert_eq!(back, bits);
    }

    #[test]
    fn entropy_is_eight_bits_for_all_byte_values_alike_and_zero_for_one() {
        let all: Vec<u8> = (0..=255u8).cycle().take(256 * 40).collect();
        assert!((entropy(&all) - 8.0).abs() < 1e-12);
        assert_eq!(entropy(&[7u8; 100]), 0.0);
        let two: Vec<u8> = [0u8, 1].iter().copied().cycle().take(1000).collect();
        assert!((entropy(&two) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_chunk_of_zeros_is_not_stored_but_a_negative_zero_is() {
        let mut deflater = ChunkDeflater::new(1).unwrap();
        assert!(deflater.deflate(&bytes_of(&[0.0f32; 50], f32::to_ne_bytes), 64).unwrap().is_none());
        let mut signed = [0.0f32; 50];
        signed[7] = -0.0;
        assert!(deflater.deflate(&bytes_of(&signed, f32::to_ne_bytes), 64).unwrap().is_some());
    }

    #[test]
    fn more_values_than_the_chunk_holds_is_an_error() {
        let mut deflater = ChunkDeflater::new(1).unwrap();
        let err = deflater.deflate(&bytes_of(&[1.0f64; 5], f64::to_ne_bytes), 4).unwrap_err();
        assert!(err.contains("more than 4"), "{err}");
        assert!(ChunkDeflater::new(13).is_err());
    }
}
