//! Clap value parsers for the engine's enums, which name themselves with `FromStr` and
//! `Display` (the engine knows no clap): the accepted names are listed in `--help` and in the
//! error for a wrong one, as clap lists its own enums' values.

use crate::render::{BrdfModel, Integrator};
use crate::texture::TextureFilter;
use clap::builder::{PossibleValuesParser, TypedValueParser};

/// `--integrator`: `path` or `direct`.
pub fn integrator() -> impl TypedValueParser<Value = Integrator> {
    PossibleValuesParser::new(Integrator::ALL.map(Integrator::name))
        .try_map(|name| name.parse::<Integrator>())
}

/// `--texture-filter`: `nearest`, `bilinear`, `bicubic`, `trilinear` or `anisotropic`.
pub fn texture_filter() -> impl TypedValueParser<Value = TextureFilter> {
    PossibleValuesParser::new(TextureFilter::ALL.map(TextureFilter::name))
        .try_map(|name| name.parse::<TextureFilter>())
}

/// `--brdf`: `compensated` (energy-conserving, the default) or `spec` (glTF Appendix B).
pub fn brdf() -> impl TypedValueParser<Value = BrdfModel> {
    PossibleValuesParser::new(BrdfModel::ALL.map(BrdfModel::name))
        .try_map(|name| name.parse::<BrdfModel>())
}

/// A tolerance, threshold or weight: a finite number ≥ 0 (NaN, infinities and negatives are
/// refused where the option is parsed: a NaN tolerance would call every comparison a pass).
pub fn tolerance(text: &str) -> Result<f64, String> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(format!("'{text}': give a finite number ≥ 0"))
    }
}

/// A strictly positive finite number (a time step, a scale): NaN, infinities, zero and
/// negatives are refused.
pub fn positive(text: &str) -> Result<f64, String> {
    let value = tolerance(text)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(format!("'{text}': give a finite number > 0"))
    }
}

/// A byte count for `--max-memory`: `8G`, `512M`, bytes.
pub fn bytes(text: &str) -> Result<u64, String> {
    crate::output::budget::parse_bytes(text)
}

/// Most worker threads `--threads` accepts: more than any machine glint runs on has cores,
/// and few enough that the pool starts at once (an absurd count took tens of seconds to fail).
pub const MAX_THREADS: usize = 1024;

/// `--threads`: 0 (every core) to [`MAX_THREADS`], checked before any work.
pub fn threads(text: &str) -> Result<usize, String> {
    let n: usize = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a thread count (0 uses every core)"))?;
    if n > MAX_THREADS {
        return Err(format!(
            "{n} threads is above the limit of {MAX_THREADS}; give 0 to use every core"
        ));
    }
    Ok(n)
}
