//! COCO's run-length encoding of binary masks, as pycocotools reads and writes it: the mask in
//! column-major order (down the first column, then the next), as alternating run lengths that
//! start with a run of zeros (possibly empty), and those counts packed into the compact ASCII
//! string of pycocotools' `rleToString` (5 bits a character, offset 48, each count after the
//! second stored as the difference from the count two before it).
//!
//! No Rust crate implements this; it is small, and `python/tests/test_coco.py` checks it
//! against pycocotools.

use serde::{Deserialize, Serialize};

/// A binary mask in COCO's compressed RLE: `{"size": [height, width], "counts": "..."}`.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Rle {
    /// `[height, width]` in pixels (COCO's order).
    pub size: [u32; 2],
    /// The packed run lengths (see the module documentation).
    pub counts: String,
}

impl Rle {
    /// Encodes the mask of a `width × height` image whose set pixels are `pixels`, given as
    /// column-major indices (`x · height + y`) in increasing order.
    pub fn from_column_major(width: u32, height: u32, pixels: &[u64]) -> Self {
        let total = u64::from(width) * u64::from(height);
        let mut runs = Vec::new();
        let mut at = 0u64; // the next index not yet in a run
        let mut i = 0;
        while i < pixels.len() {
            let start = pixels[i];
            let mut end = start + 1;
            i += 1;
            while i < pixels.len() && pixels[i] == end {
                end += 1;
                i += 1;
            }
            runs.push(start - at); // zeros
            runs.push(end - start); // ones
            at = end;
        }
        if at < total || runs.is_empty() {
            runs.push(total - at);
        }
        Self {
            size: [height, width],
            counts: pack(&runs),
        }
    }

    /// The run lengths, zeros first; `None` if `counts` is not a valid packed string.
    pub fn runs(&self) -> Option<Vec<u64>> {
        unpack(&self.counts)
    }

    /// The set pixels as column-major indices; `None` if the counts are invalid or do not add
    /// up to the size.
    pub fn column_major_pixels(&self) -> Option<Vec<u64>> {
        let runs = self.runs()?;
        let total = u64::from(self.size[0]) * u64::from(self.size[1]);
        let mut out = Vec::new();
        let mut at = 0u64;
        for (k, &run) in runs.iter().enumerate() {
            if k % 2 == 1 {
                out.extend(at..at.checked_add(run)?);
            }
            at = at.checked_add(run)?;
        }
        (at == total).then_some(out)
    }
}

/// pycocotools' `rleToString`.
fn pack(runs: &[u64]) -> String {
    let mut s = String::new();
    for (i, &run) in runs.iter().enumerate() {
        let mut x = run as i64;
        if i > 2 {
            x -= runs[i - 2] as i64;
        }
        loop {
            let mut c = (x & 0x1f) as u8;
            x >>= 5;
            let more = if c & 0x10 != 0 { x != -1 } else { x != 0 };
            if more {
                c |= 0x20;
            }
            s.push(char::from(c + 48));
            if !more {
                break;
            }
        }
    }
    s
}

/// pycocotools' `rleFrString`; `None` on characters it could not have written.
fn unpack(s: &str) -> Option<Vec<u64>> {
    let bytes = s.as_bytes();
    let mut runs: Vec<i64> = Vec::new();
    let mut p = 0;
    while p < bytes.len() {
        let mut x: i64 = 0;
        let mut k = 0u32;
        loop {
            let c = i64::from(bytes.get(p)?.checked_sub(48)?);
            if c > 0x3f || k > 12 {
                return None;
            }
            x |= (c & 0x1f) << (5 * k);
            p += 1;
            k += 1;
            if c & 0x20 == 0 {
                if c & 0x10 != 0 {
                    x |= -1i64 << (5 * k);
                }
                break;
            }
        }
        if runs.len() > 2 {
            x += runs[runs.len() - 2];
        }
        runs.push(x);
    }
    runs.into_iter().map(|r| u64::try_from(r).ok()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_masks_of_every_shape() {
        // Empty, full, first pixel, last pixel, scattered, long runs (multi-character counts).
        let (w, h) = (37u32, 29u32);
        let total = u64::from(w * h);
        let cases: Vec<Vec<u64>> = vec![
            vec![],
            (0..total).collect(),
            vec![0],
            vec![total - 1],
            (0..total).filter(|i| i % 7 == 3 || i % 11 == 0).collect(),
            (100..900).collect(),
        ];
        for pixels in cases {
            let rle = Rle::from_column_major(w, h, &pixels);
            assert_eq!(rle.column_major_pixels(), Some(pixels));
        }
    }

    #[test]
    fn matches_a_known_pycocotools_string() {
        // pycocotools.mask.encode of a 3 × 3 Fortran array with the middle column set:
        // runs [3, 3, 3], which it writes as "333".
        let rle = Rle::from_column_major(3, 3, &[3, 4, 5]);
        assert_eq!(rle.counts, "333");
        assert_eq!(rle.runs(), Some(vec![3, 3, 3]));
        assert_eq!(rle.size, [3, 3]);
    }

    #[test]
    fn refuses_garbage() {
        let bad = Rle {
            size: [2, 2],
            counts: "\u{1}".into(),
        };
        assert_eq!(bad.runs(), None);
        let short = Rle::from_column_major(2, 2, &[1]);
        let mismatched = Rle {
            size: [3, 3],
            ..short
        };
        assert_eq!(mismatched.column_major_pixels(), None);
    }
}
