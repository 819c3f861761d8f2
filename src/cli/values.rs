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
