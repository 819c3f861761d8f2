//! Partial renders: one image's samples split into index ranges that render apart (on other
//! machines) and merge into the image a single render with the same seed gives.
//!
//! The position of sample `s` of a pixel depends only on (seed, pixel, s, spp) (see
//! [`super::sampler`]), so a render restricted to `A..B` traces exactly the samples that the
//! full render traces at those indices. A part keeps the per-pixel *sums* over its samples and
//! their *weight* (the sample count, as the box filter weighs every sample 1); merging adds
//! sums and weights and divides once.
//!
//! Exactness: the full render adds a pixel's contributions one by one in f32; a merge adds
//! each part's f32 sum in f64. The two differ only by rounding, at most `γ(n) · Σ` for a
//! pixel whose n non-negative contributions add to Σ (γ(n) = nε/(1 − nε), ε = 2⁻²⁴), i.e.
//! a relative difference below `n · 6e-8`.

use super::{Aovs, Film, Image, RenderError, RenderInputs, RenderSettings, RenderStats};
use super::{Progress, render_film};
use glam::Vec3;
use std::ops::Range;

/// One part of a split render: sums over the samples `samples` of every pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct PartialImage {
    /// Samples per pixel of the whole render (fixes the strata of every sample).
    pub spp: u32,
    /// Seed of the whole render.
    pub seed: u64,
    /// The sample indices this part holds.
    pub samples: Range<u32>,
    /// Σ radiance over the part's samples, W/(m²·sr) per sample.
    pub radiance_sum: Image<Vec3>,
    /// Σ of each selected AOV over the part's samples.
    pub aov_sums: Aovs,
    /// Σ of the sample weights per pixel (the sample count under the box filter).
    pub weight: Image<f32>,
}

/// Why parts cannot be merged.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// Nothing to merge.
    #[error("no partial images to merge")]
    Empty,
    /// Two parts disagree on a property of the whole render.
    #[error(
        "part {index} has {what} {found} but part 0 has {expected}: all parts must come from \
         the same render command with different --sample-range or --shard values"
    )]
    Mismatch {
        /// Index of the offending part, in the order given.
        index: usize,
        /// What differs (size, spp, seed, channels).
        what: &'static str,
        /// Its value in the offending part.
        found: String,
        /// Its value in part 0.
        expected: String,
    },
    /// Two parts hold the same sample.
    #[error("samples {first:?} and {second:?} overlap: a sample would count twice; drop one part")]
    Overlap {
        /// One range.
        first: Range<u32>,
        /// The range overlapping it.
        second: Range<u32>,
    },
    /// Some samples are in no part.
    #[error(
        "samples {missing:?} of 0..{spp} are in no part: render them with --sample-range \
         {}..{} and merge again", missing.start, missing.end
    )]
    Missing {
        /// The first gap.
        missing: Range<u32>,
        /// Samples per pixel of the whole render.
        spp: u32,
    },
}

/// Renders only the samples in `samples` and returns their sums and weights.
pub fn render_partial(
    inputs: &RenderInputs<'_>,
    settings: &RenderSettings,
    samples: Range<u32>,
    progress: Option<Progress<'_>>,
) -> Result<(PartialImage, RenderStats), RenderError> {
    let (film, stats): (Film, RenderStats) =
        render_film(inputs, settings, samples.clone(), progress)?;
    let (radiance_sum, aov_sums, weight) = film.into_sums();
    Ok((
        PartialImage {
            spp: settings.spp,
            seed: settings.seed,
            samples,
            radiance_sum,
            aov_sums,
            weight,
        },
        stats,
    ))
}

/// Shard `index` of `count` of `spp` samples: the contiguous range
/// `⌊index·spp/count⌋ .. ⌊(index+1)·spp/count⌋`, so the shards partition `0..spp` with sizes
/// differing by at most one. Empty when `count > spp` leaves this shard nothing.
pub fn shard_samples(spp: u32, index: u32, count: u32) -> Range<u32> {
    let bound = |i: u32| (i as u64 * spp as u64 / count.max(1) as u64) as u32;
    bound(index)..bound(index + 1)
}

/// Parses `A..B` (end exclusive) into a sample range.
pub fn parse_sample_range(text: &str) -> Result<Range<u32>, String> {
    let (a, b) = text
        .split_once("..")
        .ok_or_else(|| format!("'{text}' is not a range: write START..END, e.g. 0..16"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<u32>()
            .map_err(|_| format!("'{s}' in '{text}' is not a sample index (0, 1, 2, ...)"))
    };
    let range = parse(a)?..parse(b)?;
    if range.is_empty() {
        return Err(format!("'{text}' holds no sample: END must exceed START"));
    }
    Ok(range)
}

/// Merges parts into the resolved image and AOVs: per pixel, Σ sums / Σ weights, added in f64
/// in the order of the parts' first sample (so the result does not depend on the order the
/// parts are given in). The parts must come from one render and cover `0..spp` exactly once.
pub fn merge(parts: &[PartialImage]) -> Result<(Image<Vec3>, Aovs), MergeError> {
    let first = parts.first().ok_or(MergeError::Empty)?;
    for (index, part) in parts.iter().enumerate().skip(1) {
        let mismatch = |what, found: String, expected: String| {
            Err(MergeError::Mismatch {
                index,
                what,
                found,
                expected,
            })
        };
        let size = |p: &PartialImage| format!("{}×{}", p.radiance_sum.width, p.radiance_sum.height);
        if size(part) != size(first) {
            return mismatch("size", size(part), size(first));
        }
        if part.spp != first.spp {
            return mismatch("spp", part.spp.to_string(), first.spp.to_string());
        }
        if part.seed != first.seed {
            return mismatch("seed", part.seed.to_string(), first.seed.to_string());
        }
        let channels = |p: &PartialImage| {
            let a = &p.aov_sums;
            format!(
                "albedo {}, normal {}, depth {}, alpha {}",
                a.albedo.is_some(),
                a.normal.is_some(),
                a.depth.is_some(),
                a.alpha.is_some()
            )
        };
        if channels(part) != channels(first) {
            return mismatch("AOVs", channels(part), channels(first));
        }
    }
    let mut order: Vec<&PartialImage> = parts.iter().collect();
    order.sort_by_key(|p| (p.samples.start, p.samples.end));
    let mut covered = 0..0;
    for part in &order {
        if part.samples.start < covered.end {
            return Err(MergeError::Overlap {
                first: covered,
                second: part.samples.clone(),
            });
        }
        if part.samples.start > covered.end {
            return Err(MergeError::Missing {
                missing: covered.end..part.samples.start,
                spp: first.spp,
            });
        }
        covered = part.samples.clone();
    }
    if covered.end < first.spp {
        return Err(MergeError::Missing {
            missing: covered.end..first.spp,
            spp: first.spp,
        });
    }

    let weight = resolve(&order, |p| Some(&p.weight), |&w| [w as f64]);
    let weights: Vec<f64> = weight.iter().map(|w| w[0]).collect();
    let (width, height) = (first.radiance_sum.width, first.radiance_sum.height);
    let vec3 = |sums: Vec<[f64; 3]>| Image {
        width,
        height,
        pixels: sums
            .iter()
            .zip(&weights)
            .map(|(s, &w)| {
                let inv = if w > 0.0 { 1.0 / w } else { 0.0 };
                Vec3::new(
                    (s[0] * inv) as f32,
                    (s[1] * inv) as f32,
                    (s[2] * inv) as f32,
                )
            })
            .collect(),
    };
    let as3 = |v: &Vec3| [v.x as f64, v.y as f64, v.z as f64];
    let radiance = vec3(resolve(&order, |p| Some(&p.radiance_sum), as3));
    let aov3 = |pick: fn(&PartialImage) -> Option<&Image<Vec3>>| {
        pick(first).map(|_| vec3(resolve(&order, pick, as3)))
    };
    let albedo = aov3(|p| p.aov_sums.albedo.as_ref());
    let normal = aov3(|p| p.aov_sums.normal.as_ref());
    let aov1 = |pick: fn(&PartialImage) -> Option<&Image<f32>>| {
        pick(first).map(|_| {
            let sums = resolve(&order, pick, |&d| [d as f64]);
            Image {
                width,
                height,
                pixels: sums
                    .iter()
                    .zip(&weights)
                    .map(|(s, &w)| if w > 0.0 { (s[0] / w) as f32 } else { 0.0 })
                    .collect(),
            }
        })
    };
    let depth = aov1(|p| p.aov_sums.depth.as_ref());
    let alpha = aov1(|p| p.aov_sums.alpha.as_ref());
    Ok((
        radiance,
        Aovs {
            albedo,
            normal,
            depth,
            alpha,
            ..Aovs::default()
        },
    ))
}

/// Per-pixel f64 sums of one channel group over the parts, in the parts' order.
fn resolve<T, const N: usize>(
    parts: &[&PartialImage],
    pick: impl Fn(&PartialImage) -> Option<&Image<T>>,
    widen: impl Fn(&T) -> [f64; N],
) -> Vec<[f64; N]> {
    let mut sums: Vec<[f64; N]> = Vec::new();
    for part in parts {
        let Some(image) = pick(part) else { continue };
        if sums.is_empty() {
            sums = vec![[0.0; N]; image.pixels.len()];
        }
        for (sum, value) in sums.iter_mut().zip(&image.pixels) {
            for (s, v) in sum.iter_mut().zip(widen(value)) {
                *s += v;
            }
        }
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_samples() {
        for spp in [1, 2, 7, 16, 100] {
            for count in 1..=9 {
                let mut next = 0;
                for index in 0..count {
                    let r = shard_samples(spp, index, count);
                    assert_eq!(r.start, next, "spp {spp} shard {index}/{count}");
                    assert!(r.len() as u32 <= spp.div_ceil(count));
                    next = r.end;
                }
                assert_eq!(next, spp);
            }
        }
    }

    #[test]
    fn sample_ranges_parse_and_reject() {
        assert_eq!(parse_sample_range("4..16"), Ok(4..16));
        assert!(parse_sample_range("4").is_err());
        assert!(parse_sample_range("5..5").is_err());
        assert!(parse_sample_range("a..3").is_err());
    }

    fn part(samples: Range<u32>, value: f32) -> PartialImage {
        let n = samples.len() as f32;
        PartialImage {
            spp: 4,
            seed: 1,
            samples,
            radiance_sum: Image::filled(2, 1, Vec3::splat(value * n)),
            aov_sums: Aovs::default(),
            weight: Image::filled(2, 1, n),
        }
    }

    #[test]
    fn merge_weights_parts_by_their_samples() {
        let (image, _) = merge(&[part(1..4, 2.0), part(0..1, 6.0)]).unwrap();
        // (3 samples of 2 + 1 sample of 6) / 4 = 3.
        assert_eq!(image.pixels, vec![Vec3::splat(3.0); 2]);
        assert!(matches!(
            merge(&[part(0..2, 1.0), part(1..4, 1.0)]),
            Err(MergeError::Overlap { .. })
        ));
        assert!(matches!(
            merge(&[part(0..1, 1.0), part(2..4, 1.0)]),
            Err(MergeError::Missing { missing, .. }) if missing == (1..2)
        ));
        let mut other_seed = part(1..4, 1.0);
        other_seed.seed = 2;
        assert!(matches!(
            merge(&[part(0..1, 1.0), other_seed]),
            Err(MergeError::Mismatch { what: "seed", .. })
        ));
    }
}
