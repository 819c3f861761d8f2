//! Size budgets checked before allocating: the memory a render may take (`--max-memory`,
//! default [`DEFAULT_MEMORY_FRACTION`] of physical memory) and the size an EXR declares in its
//! header, which glint reads before decoding any pixel (`glint check-gt`, `glint merge`, the
//! batch's resume check). A file of a few hundred bytes can declare 10⁹ pixels; decoding it
//! would end the process on out-of-memory instead of with an error.

use std::path::Path;

/// The default memory budget: this fraction of the machine's physical memory.
pub const DEFAULT_MEMORY_FRACTION: f64 = 0.5;

/// The memory budget when physical memory cannot be read (no `/proc/meminfo`): 8 GiB.
pub const FALLBACK_MEMORY_BUDGET: u64 = 8 << 30;

/// The machine's physical memory in bytes (Linux's `/proc/meminfo`), if known.
pub fn physical_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// The default memory budget: [`DEFAULT_MEMORY_FRACTION`] of physical memory, or
/// [`FALLBACK_MEMORY_BUDGET`] where it cannot be read.
pub fn default_memory_budget() -> u64 {
    physical_memory().map_or(FALLBACK_MEMORY_BUDGET, |m| {
        (m as f64 * DEFAULT_MEMORY_FRACTION) as u64
    })
}

/// Bytes as "1.5 GiB" for messages.
pub fn human_bytes(bytes: u64) -> String {
    let gib = bytes as f64 / (1u64 << 30) as f64;
    if gib >= 1.0 {
        format!("{gib:.1} GiB")
    } else {
        format!("{:.1} MiB", bytes as f64 / (1u64 << 20) as f64)
    }
}

/// What an EXR's header declares, summed over its layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExrSize {
    /// Pixels of the largest layer (data window width × height).
    pub pixels: u64,
    /// Bytes of every channel of every layer, decoded.
    pub bytes: u64,
}

/// Reads the header of the EXR at `path` (only the header) and refuses it when a layer
/// declares more than `max_pixels` pixels, a tile larger than that, or more than
/// `max_bytes` of samples in all: the check glint makes before decoding any EXR it is given.
/// A path that is not a regular file is refused too (a FIFO would block the read). The error
/// is one line naming the file and the sizes.
pub fn check_exr(path: &Path, max_pixels: u64, max_bytes: u64) -> Result<ExrSize, String> {
    super::plan::require_regular(path, "an EXR to read").map_err(|e| e.0)?;
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let mut size = ExrSize {
        pixels: 0,
        bytes: 0,
    };
    for header in meta.headers.iter() {
        let (w, h) = (
            header.layer_size.width() as u64,
            header.layer_size.height() as u64,
        );
        let pixels = w.saturating_mul(h);
        let sample_bytes: u64 = header
            .channels
            .list
            .iter()
            .map(|c| c.sample_type.bytes_per_sample() as u64)
            .sum();
        let tile = match &header.blocks {
            exr::meta::BlockDescription::Tiles(t) => {
                (t.tile_size.width() as u64).saturating_mul(t.tile_size.height() as u64)
            }
            exr::meta::BlockDescription::ScanLines => 0,
        };
        if pixels > max_pixels || tile > max_pixels {
            return Err(format!(
                "{} declares a layer of {w} × {h} pixels{}, more than the {max_pixels} pixels \
                 glint reads; the file is corrupt or not one glint can use",
                path.display(),
                if tile > max_pixels {
                    format!(" in tiles of {tile} pixels")
                } else {
                    String::new()
                }
            ));
        }
        size.pixels = size.pixels.max(pixels);
        size.bytes = size
            .bytes
            .saturating_add(pixels.saturating_mul(sample_bytes));
    }
    if size.bytes > max_bytes {
        return Err(format!(
            "{} declares {} of samples, more than the memory budget of {}; the file is corrupt, \
             or raise the budget with GLINT_MAX_MEMORY=BYTES",
            path.display(),
            human_bytes(size.bytes),
            human_bytes(max_bytes)
        ));
    }
    Ok(size)
}

/// The environment variable that sets the memory budget of commands without
/// `--max-memory` (`check-gt`, `merge`, the batch's resume check): bytes, or a number with a
/// `K`, `M`, `G` or `T` suffix (powers of 1024).
pub const MEMORY_VAR: &str = "GLINT_MAX_MEMORY";

/// The memory budget of commands that read files: [`MEMORY_VAR`] if set and valid, else
/// [`default_memory_budget`].
pub fn memory_budget() -> u64 {
    std::env::var(MEMORY_VAR)
        .ok()
        .and_then(|v| parse_bytes(&v).ok())
        .unwrap_or_else(default_memory_budget)
}

/// Parses a byte count: `1073741824`, `512M`, `16G`, `1.5T` (powers of 1024). Refuses zero,
/// negatives, NaN and values beyond 2^63.
pub fn parse_bytes(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let (number, scale) = match t.char_indices().last() {
        Some((i, c)) if c.is_ascii_alphabetic() => {
            let scale: u64 = match c.to_ascii_uppercase() {
                'K' => 1 << 10,
                'M' => 1 << 20,
                'G' => 1 << 30,
                'T' => 1 << 40,
                'B' => 1,
                _ => {
                    return Err(format!(
                        "'{text}': give bytes, or a number with K, M, G or T"
                    ));
                }
            };
            (&t[..i], scale)
        }
        _ => (t, 1),
    };
    let value: f64 = number
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a byte count (e.g. 8G, 512M)"))?;
    let bytes = value * scale as f64;
    if !(1.0..9.2e18).contains(&bytes) {
        return Err(format!(
            "'{text}': give a positive byte count below 8 EiB (e.g. 8G, 512M)"
        ));
    }
    Ok(bytes as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_counts_parse_and_nonsense_is_refused() {
        assert_eq!(parse_bytes("512M"), Ok(512 << 20));
        assert_eq!(parse_bytes("2g"), Ok(2 << 30));
        assert_eq!(parse_bytes("1000"), Ok(1000));
        for bad in ["0", "-1G", "NaN", "inf", "G", "12Q", "1e30"] {
            assert!(parse_bytes(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_default_budget_is_a_fraction_of_physical_memory() {
        if let Some(m) = physical_memory() {
            let budget = default_memory_budget();
            assert!(budget < m && budget > m / 4, "{budget} of {m}");
        }
    }
}
