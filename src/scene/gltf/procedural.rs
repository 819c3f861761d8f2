//! Procedural base colours from a material's glTF `extras`.
//!
//! Format (all keys but `pattern` optional; colours are linear RGB):
//!
//! ```json
//! "extras": { "glint_procedural": {
//!     "pattern": "checker" | "value" | "perlin" | "mixed",
//!     "frequency": 8.0,              // cycles per domain unit (default 1)
//!     "domain": "uv0" | "uv1" | "world",   // default "uv0"
//!     "colors": [[0, 0, 0], [1, 1, 1]],    // at pattern value 0 and 1 (default black, white)
//!     "seed": 0,                     // noise lattice seed (default 0)
//!     "octaves": [[0.5, 1], [0.25, 2], [0.125, 4]]   // "mixed": [amplitude, frequency]
//! } }
//! ```
//!
//! Other keys in `extras` are left alone. A malformed entry is an error naming the material
//! and the key, not a silent fallback.

use super::LoadError;
use super::source::Origin;
use crate::scene::procedural_texture::{Domain, Octave, Pattern, ProceduralTexture};
use glam::Vec3;

/// The `extras` key glint reads.
pub const EXTRAS_KEY: &str = "glint_procedural";

#[derive(serde::Deserialize)]
struct ExtrasJson {
    glint_procedural: Option<ProceduralJson>,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ProceduralJson {
    pattern: String,
    #[serde(default = "one")]
    frequency: f32,
    #[serde(default)]
    domain: Option<String>,
    #[serde(default)]
    colors: Option<[[f32; 3]; 2]>,
    #[serde(default)]
    seed: u64,
    #[serde(default)]
    octaves: Option<Vec<[f32; 2]>>,
}

fn one() -> f32 {
    1.0
}

/// The procedural texture in `extras`, if it has one.
pub fn from_extras(
    extras: &::gltf::json::Extras,
    material: &str,
    origin: Origin<'_>,
) -> Result<Option<ProceduralTexture>, LoadError> {
    let Some(raw) = extras else {
        return Ok(None);
    };
    let invalid = |message: String| LoadError::Invalid {
        path: origin.file.to_path_buf(),
        message: format!("{material}: extras.{EXTRAS_KEY}: {message}"),
    };
    // Extras that are not an object, or have no entry of ours, are not ours to judge.
    let Ok(value) = serde_json::from_str::<serde_json::Value>(raw.get()) else {
        return Ok(None);
    };
    if value.get(EXTRAS_KEY).is_none() {
        return Ok(None);
    }
    let parsed: ExtrasJson = serde_json::from_value(value).map_err(|e| {
        invalid(format!(
            "{e} (see docs/textures.md for the format: pattern, frequency, domain, colors, \
             seed, octaves)"
        ))
    })?;
    let Some(p) = parsed.glint_procedural else {
        return Ok(None);
    };
    let pattern = match p.pattern.as_str() {
        "checker" => Pattern::Checker,
        "value" => Pattern::Value,
        "perlin" => Pattern::Perlin,
        "mixed" => {
            let octaves = p.octaves.as_deref().unwrap_or_default();
            if octaves.is_empty() {
                return Err(invalid(
                    "pattern \"mixed\" needs \"octaves\": [[amplitude, frequency], ...]".into(),
                ));
            }
            if octaves
                .iter()
                .any(|[a, f]| !(a.is_finite() && f.is_finite() && *f > 0.0))
            {
                return Err(invalid(
                    "every octave needs a finite amplitude and a positive frequency".into(),
                ));
            }
            Pattern::Mixed(
                octaves
                    .iter()
                    .map(|&[amplitude, frequency]| Octave {
                        amplitude,
                        frequency,
                    })
                    .collect(),
            )
        }
        other => {
            return Err(invalid(format!(
                "unknown pattern \"{other}\"; use checker, value, perlin or mixed"
            )));
        }
    };
    if !(p.frequency.is_finite() && p.frequency > 0.0) {
        return Err(invalid(format!(
            "frequency {} must be positive and finite",
            p.frequency
        )));
    }
    let domain = match p.domain.as_deref().unwrap_or("uv0") {
        "uv0" => Domain::Uv(0),
        "uv1" => Domain::Uv(1),
        "world" => Domain::World,
        other => {
            return Err(invalid(format!(
                "unknown domain \"{other}\"; use uv0, uv1 or world"
            )));
        }
    };
    let colors = p.colors.unwrap_or([[0.0; 3], [1.0; 3]]);
    if colors
        .iter()
        .flatten()
        .any(|c| !(c.is_finite() && *c >= 0.0))
    {
        return Err(invalid(
            "colors must be two non-negative, finite linear RGB triples".into(),
        ));
    }
    Ok(Some(ProceduralTexture {
        pattern,
        domain,
        frequency: p.frequency,
        colors: colors.map(Vec3::from),
        seed: p.seed,
    }))
}
