//! A minimal PNG encoder: 8-bit RGB, no interlacing, no compression.
//!
//! The file is the 8-byte signature followed by three chunks:
//! - `IHDR`: width, height, bit depth 8, colour type 2 (RGB), the default
//!   compression, filter and interlace methods;
//! - `IDAT`: a zlib stream (RFC 1950) of the scanlines, each prefixed by filter type
//!   0 ("None"); the deflate data (RFC 1951) is a run of *stored* blocks of at most
//!   65,535 bytes, closed by the Adler-32 of the uncompressed scanlines;
//! - `IEND`.
//!
//! Every chunk ends with the CRC-32 (ISO 3309, polynomial `0xEDB88320` reflected) of
//! its type and data, computed with a table built at compile time. Stored blocks keep
//! the encoder a few dozen lines long and trivially correct, at the price of size:
//! a 900×600 chart is about 1.6 MB. Any PNG reader accepts it.

/// The 8 bytes every PNG file starts with.
pub(crate) const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1A, b'\n'];

/// Largest payload of one stored deflate block.
const MAX_STORED: usize = 65_535;

/// Encodes `rgb` (row-major, 3 bytes per pixel, `width * height * 3` bytes) as a PNG.
///
/// # Panics
/// If `rgb` has the wrong length or a dimension is 0 (callers in this module size
/// their buffers themselves, so this is a bug, not a user mistake).
pub(crate) fn encode_rgb(width: u32, height: u32, rgb: &[u8]) -> Vec<u8> {
    assert!(width > 0 && height > 0, "PNG dimensions must be positive");
    let row_len = width as usize * 3;
    assert_eq!(rgb.len(), row_len * height as usize, "RGB buffer size");

    // Scanlines, each with its filter-type byte (0 = None).
    let mut raw = Vec::with_capacity((row_len + 1) * height as usize);
    for row in rgb.chunks_exact(row_len) {
        raw.push(0);
        raw.extend_from_slice(row);
    }

    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]); // depth, colour type RGB, compression, filter, interlace

    let mut out = Vec::with_capacity(raw.len() + raw.len() / MAX_STORED * 5 + 64);
    out.extend_from_slice(&SIGNATURE);
    write_chunk(&mut out, b"IHDR", &ihdr);
    write_chunk(&mut out, b"IDAT", &zlib_stored(&raw));
    write_chunk(&mut out, b"IEND", &[]);
    out
}

/// Appends one chunk: length, type, data, CRC-32 of type and data.
fn write_chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    let len = u32::try_from(data.len()).expect("PNG chunk larger than 2^32 bytes");
    out.extend_from_slice(&len.to_be_bytes());
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32_update(crc32_update(!0, kind), data);
    out.extend_from_slice(&(!crc).to_be_bytes());
}

/// A zlib stream holding `data` in stored (uncompressed) deflate blocks.
fn zlib_stored(data: &[u8]) -> Vec<u8> {
    let blocks = data.len().div_ceil(MAX_STORED).max(1);
    let mut out = Vec::with_capacity(data.len() + blocks * 5 + 6);
    // CMF: deflate, 32 KiB window; FLG: no dictionary, level "fastest", and
    // FCHECK so that CMF * 256 + FLG is a multiple of 31 (0x7801 = 31 * 991).
    out.extend_from_slice(&[0x78, 0x01]);
    if data.is_empty() {
        out.extend_from_slice(&[1, 0, 0, 0xFF, 0xFF]);
    }
    let mut chunks = data.chunks(MAX_STORED).peekable();
    while let Some(chunk) = chunks.next() {
        let last = chunks.peek().is_none();
        // BFINAL in bit 0, BTYPE = 00 (stored) in bits 1-2, the rest of the byte is
        // padding up to the byte boundary where LEN starts.
        out.push(u8::from(last));
        let len = chunk.len() as u16;
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&(!len).to_le_bytes());
        out.extend_from_slice(chunk);
    }
    out.extend_from_slice(&adler32(data).to_be_bytes());
    out
}

/// Adler-32 (RFC 1950) of `data`.
pub(crate) fn adler32(data: &[u8]) -> u32 {
    const MOD: u32 = 65_521;
    // 5552 is the largest run for which the sums cannot overflow a u32.
    let (mut a, mut b) = (1u32, 0u32);
    for run in data.chunks(5552) {
        for &byte in run {
            a += u32::from(byte);
            b += a;
        }
        a %= MOD;
        b %= MOD;
    }
    (b << 16) | a
}

/// Continues a CRC-32 over `data`; start with `!0` and invert the result.
pub(crate) fn crc32_update(mut crc: u32, data: &[u8]) -> u32 {
    for &byte in data {
        crc = CRC_TABLE[((crc ^ u32::from(byte)) & 0xFF) as usize] ^ (crc >> 8);
    }
    crc
}

/// CRC-32 of `data` (the value stored in a PNG chunk).
#[cfg(test)]
pub(crate) fn crc32(data: &[u8]) -> u32 {
    !crc32_update(!0, data)
}

static CRC_TABLE: [u32; 256] = crc_table();

const fn crc_table() -> [u32; 256] {
    let mut table = [0u32; 256];
    let mut n = 0;
    while n < 256 {
        let mut c = n as u32;
        let mut k = 0;
        while k < 8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
            k += 1;
        }
        table[n] = c;
        n += 1;
    }
    table
}

/// A checking decoder for what [`encode_rgb`] writes, for the tests: it verifies the
/// signature, every chunk's CRC, the IHDR fields, the zlib header, each stored
/// block's `LEN`/`NLEN`, the Adler-32, the scanline count and size and the filter
/// bytes, and returns `(width, height, rgb)`.
#[cfg(test)]
pub(crate) fn decode_checked(bytes: &[u8]) -> Result<(u32, u32, Vec<u8>), String> {
    fn be32(b: &[u8]) -> u32 {
        u32::from_be_bytes([b[0], b[1], b[2], b[3]])
    }
    if bytes.len() < 8 || bytes[..8] != SIGNATURE {
        return Err("bad signature".into());
    }
    let mut pos = 8;
    let mut chunks: Vec<([u8; 4], &[u8])> = Vec::new();
    while pos < bytes.len() {
        if pos + 12 > bytes.len() {
            return Err(format!("truncated chunk header at {pos}"));
        }
        let len = be32(&bytes[pos..]) as usize;
        let kind: [u8; 4] = bytes[pos + 4..pos + 8].try_into().unwrap();
        let end = pos + 8 + len;
        if end + 4 > bytes.len() {
            return Err(format!(
                "truncated chunk {:?}",
                String::from_utf8_lossy(&kind)
            ));
        }
        let stored_crc = be32(&bytes[end..]);
        let crc = crc32(&bytes[pos + 4..end]);
        if crc != stored_crc {
            return Err(format!(
                "CRC mismatch in {:?}",
                String::from_utf8_lossy(&kind)
            ));
        }
        chunks.push((kind, &bytes[pos + 8..end]));
        pos = end + 4;
    }
    let names: Vec<&[u8; 4]> = chunks.iter().map(|(k, _)| k).collect();
    if names.first() != Some(&b"IHDR") || names.last() != Some(&b"IEND") {
        return Err(format!("chunk order {names:?}"));
    }
    let ihdr = chunks[0].1;
    if ihdr.len() != 13 || ihdr[8..] != [8, 2, 0, 0, 0] {
        return Err(format!("unexpected IHDR {ihdr:?}"));
    }
    let (width, height) = (be32(ihdr), be32(&ihdr[4..]));
    let zlib: Vec<u8> = chunks
        .iter()
        .filter(|(k, _)| k == b"IDAT")
        .flat_map(|(_, d)| d.iter().copied())
        .collect();
    if zlib.len() < 6
        || (u32::from(zlib[0]) * 256 + u32::from(zlib[1])) % 31 != 0
        || zlib[0] & 0x0F != 8
    {
        return Err("bad zlib header".into());
    }
    let mut raw = Vec::new();
    let mut p = 2;
    loop {
        let header = *zlib.get(p).ok_or("missing block header")?;
        if header & 0b110 != 0 {
            return Err(format!("block type {} is not stored", (header >> 1) & 3));
        }
        let field = zlib.get(p + 1..p + 5).ok_or("truncated LEN")?;
        let len = u16::from_le_bytes([field[0], field[1]]);
        let nlen = u16::from_le_bytes([field[2], field[3]]);
        if len != !nlen {
            return Err("NLEN is not the complement of LEN".into());
        }
        let data = zlib
            .get(p + 5..p + 5 + len as usize)
            .ok_or("truncated block")?;
        raw.extend_from_slice(data);
        p += 5 + len as usize;
        if header & 1 == 1 {
            break;
        }
    }
    let trailer = zlib.get(p..p + 4).ok_or("missing Adler-32")?;
    if be32(trailer) != adler32(&raw) {
        return Err("Adler-32 mismatch".into());
    }
    if p + 4 != zlib.len() {
        return Err("bytes after the zlib stream".into());
    }
    let row = 1 + width as usize * 3;
    if raw.len() != height as usize * row {
        return Err(format!(
            "{} bytes of scanlines, expected {}",
            raw.len(),
            height as usize * row
        ));
    }
    let mut rgb = Vec::with_capacity(width as usize * height as usize * 3);
    for line in raw.chunks_exact(row) {
        if line[0] != 0 {
            return Err(format!("filter type {}", line[0]));
        }
        rgb.extend_from_slice(&line[1..]);
    }
    Ok((width, height, rgb))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksums_match_published_values() {
        assert_eq!(crc32(b""), 0);
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        assert_eq!(crc32(b"IEND"), 0xAE42_6082);
        assert_eq!(adler32(b""), 1);
        assert_eq!(adler32(b"Wikipedia"), 0x11E6_0398);
        // Long input: the deferred modulo must not overflow.
        let big = vec![0xFFu8; 100_000];
        let (mut a, mut b) = (1u64, 0u64);
        for &x in &big {
            a = (a + u64::from(x)) % 65_521;
            b = (b + a) % 65_521;
        }
        assert_eq!(adler32(&big), ((b << 16) | a) as u32);
    }

    #[test]
    fn round_trip_through_the_checking_decoder() {
        // 150 × 200 × 3 + 200 filter bytes > 65,535: several stored blocks.
        let (w, h) = (150u32, 200u32);
        let rgb: Vec<u8> = (0..w * h * 3).map(|i| (i * 7 % 251) as u8).collect();
        let png = encode_rgb(w, h, &rgb);
        assert_eq!(&png[..8], &SIGNATURE);
        let (dw, dh, back) = decode_checked(&png).unwrap();
        assert_eq!((dw, dh), (w, h));
        assert_eq!(back, rgb);
    }

    #[test]
    fn tiny_image_and_exact_block_boundary() {
        let png = encode_rgb(1, 1, &[1, 2, 3]);
        assert_eq!(decode_checked(&png).unwrap(), (1, 1, vec![1, 2, 3]));
        // One row of exactly 65,535 bytes: 21,845 pixels minus the filter byte.
        let w = 21_844;
        let rgb = vec![9u8; w * 3];
        let z = zlib_stored(&[0u8; MAX_STORED]);
        assert_eq!(z.len(), 2 + 5 + MAX_STORED + 4);
        let png = encode_rgb(w as u32, 1, &rgb);
        assert_eq!(decode_checked(&png).unwrap().2, rgb);
    }

    #[test]
    fn decoder_rejects_corruption() {
        let mut png = encode_rgb(2, 2, &[0; 12]);
        let n = png.len();
        png[n - 20] ^= 1; // inside IDAT
        assert!(decode_checked(&png).unwrap_err().contains("CRC"));
    }
}
