//! Lights given on the command line (`--light`) or in a small TOML lights file.
//!
//! # `--light` values
//! A type, then `key=value` pairs, separated by `:`; vectors are comma-separated.
//!
//! | type          | keys (required in bold)                                                        |
//! |---------------|---------------------------------------------------------------------------------|
//! | `point`       | **position**, **intensity** (W/sr), color, range                               |
//! | `spot`        | **position**, **direction**, **intensity** (W/sr), inner, outer (°), color, range |
//! | `directional` | **direction** (the way the light travels), **irradiance** (W/m²), color        |
//!
//! `color` is linear RGB (default 1,1,1) and multiplies the intensity or irradiance; `range`
//! (scene units) cuts the light off beyond that distance; spot cone angles default to
//! inner 0° and outer 45° (KHR_lights_punctual's defaults). Examples:
//! `point:position=1,2,3:intensity=50:color=1,0.9,0.8:range=10`,
//! `spot:position=0,4,0:direction=0,-1,0:intensity=80:inner=20:outer=30`,
//! `directional:direction=0,-1,0:irradiance=3`.
//!
//! # Lights file
//! TOML with one `[[light]]` table per light, the same keys, `type` naming the kind and
//! arrays for vectors:
//! ```toml
//! [[light]]
//! type = "point"
//! position = [1, 2, 3]
//! intensity = 50
//! color = [1, 0.9, 0.8]
//! ```

use super::Light;
use glam::Vec3;
use serde::Deserialize;
use std::path::Path;

/// A light description that could not be understood; the message names the bad key and the
/// expected format.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct LightSpecError(pub String);

/// Spot cone angles when not given (KHR_lights_punctual's defaults), degrees.
const DEFAULT_INNER_DEGREES: f32 = 0.0;
const DEFAULT_OUTER_DEGREES: f32 = 45.0;

/// The kinds of light, as written in a spec or file.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
enum Kind {
    Point,
    Spot,
    Directional,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Point => "point",
            Kind::Spot => "spot",
            Kind::Directional => "directional",
        }
    }

    /// The keys this kind accepts; the first ones listed are required.
    fn keys(self) -> (&'static [&'static str], &'static [&'static str]) {
        match self {
            Kind::Point => (&["position", "intensity"], &["color", "range"]),
            Kind::Spot => (
                &["position", "direction", "intensity"],
                &["inner", "outer", "color", "range"],
            ),
            Kind::Directional => (&["direction", "irradiance"], &["color"]),
        }
    }

    fn format(self) -> &'static str {
        match self {
            Kind::Point => "point:position=X,Y,Z:intensity=W_PER_SR[:color=R,G,B][:range=DIST]",
            Kind::Spot => {
                "spot:position=X,Y,Z:direction=X,Y,Z:intensity=W_PER_SR[:inner=DEG][:outer=DEG][:color=R,G,B][:range=DIST]"
            }
            Kind::Directional => "directional:direction=X,Y,Z:irradiance=W_PER_M2[:color=R,G,B]",
        }
    }
}

/// One light's parameters, from either syntax, before validation.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(rename = "type")]
    kind: Option<Kind>,
    position: Option<[f32; 3]>,
    direction: Option<[f32; 3]>,
    intensity: Option<f32>,
    irradiance: Option<f32>,
    color: Option<[f32; 3]>,
    range: Option<f32>,
    inner: Option<f32>,
    outer: Option<f32>,
}

impl Params {
    fn present_keys(&self) -> Vec<&'static str> {
        let mut keys = Vec::new();
        let mut note = |present: bool, key| {
            if present {
                keys.push(key);
            }
        };
        note(self.position.is_some(), "position");
        note(self.direction.is_some(), "direction");
        note(self.intensity.is_some(), "intensity");
        note(self.irradiance.is_some(), "irradiance");
        note(self.color.is_some(), "color");
        note(self.range.is_some(), "range");
        note(self.inner.is_some(), "inner");
        note(self.outer.is_some(), "outer");
        keys
    }

    /// Checks keys and values and builds the light (intensity × colour).
    fn into_light(self) -> Result<Light, String> {
        let Some(kind) = self.kind else {
            return Err("missing the light type: point, spot or directional".into());
        };
        let (required, optional) = kind.keys();
        for key in self.present_keys() {
            if !required.contains(&key) && !optional.contains(&key) {
                return Err(format!(
                    "key '{key}' does not apply to a {} light; expected {}",
                    kind.name(),
                    kind.format()
                ));
            }
        }
        let present = self.present_keys();
        if let Some(key) = required.iter().find(|k| !present.contains(k)) {
            return Err(format!("missing '{key}'; expected {}", kind.format()));
        }
        let color = Vec3::from(self.color.unwrap_or([1.0; 3]));
        if !(color.is_finite() && color.min_element() >= 0.0) {
            return Err("'color' must be three finite, non-negative numbers".into());
        }
        let non_negative = |key: &str, v: Option<f32>| match v {
            Some(v) if v >= 0.0 && v.is_finite() => Ok(v),
            Some(v) => Err(format!(
                "'{key}' is {v}; it must be finite and non-negative"
            )),
            None => Ok(0.0),
        };
        let range = match self.range {
            Some(r) if r > 0.0 => Some(r),
            Some(r) => return Err(format!("'range' is {r}; it must be positive")),
            None => None,
        };
        let position = |p: Option<[f32; 3]>| {
            let p = Vec3::from(p.unwrap_or_default());
            if p.is_finite() {
                Ok(p)
            } else {
                Err("'position' must be three finite numbers".to_string())
            }
        };
        let direction = |d: Option<[f32; 3]>| {
            let d = Vec3::from(d.unwrap_or_default());
            match d.try_normalize() {
                Some(d) => Ok(d),
                None => Err(format!(
                    "'direction' is {d}; it must be a non-zero finite vector"
                )),
            }
        };
        Ok(match kind {
            Kind::Point => Light::Point {
                position: position(self.position)?,
                intensity: color * non_negative("intensity", self.intensity)?,
                range,
            },
            Kind::Spot => {
                let inner = self.inner.unwrap_or(DEFAULT_INNER_DEGREES);
                let outer = self.outer.unwrap_or(DEFAULT_OUTER_DEGREES);
                if !(0.0 <= inner && inner < outer && outer <= 90.0) {
                    return Err(format!(
                        "cone angles inner={inner} and outer={outer} (degrees) must satisfy 0 ≤ inner < outer ≤ 90"
                    ));
                }
                Light::Spot {
                    position: position(self.position)?,
                    direction: direction(self.direction)?,
                    intensity: color * non_negative("intensity", self.intensity)?,
                    range,
                    cos_inner: inner.to_radians().cos(),
                    cos_outer: outer.to_radians().cos(),
                }
            }
            Kind::Directional => Light::Directional {
                direction: direction(self.direction)?,
                irradiance: color * non_negative("irradiance", self.irradiance)?,
            },
        })
    }
}

/// Parses one `--light` value (format in the module documentation).
pub fn parse_light(spec: &str) -> Result<Light, LightSpecError> {
    let fail = |problem: String| LightSpecError(format!("--light '{spec}': {problem}"));
    let mut fields = spec.split(':');
    let kind_text = fields.next().unwrap_or_default().trim();
    let kind = match kind_text {
        "point" => Kind::Point,
        "spot" => Kind::Spot,
        "directional" => Kind::Directional,
        other => {
            return Err(fail(format!(
                "unknown light type '{other}'; expected point, spot or directional, e.g. {}",
                Kind::Point.format()
            )));
        }
    };
    let mut params = Params {
        kind: Some(kind),
        ..Params::default()
    };
    for field in fields {
        let Some((key, value)) = field.split_once('=') else {
            return Err(fail(format!(
                "'{field}' is not key=value; expected {}",
                kind.format()
            )));
        };
        let (key, value) = (key.trim(), value.trim());
        let scalar = || {
            value
                .parse::<f32>()
                .map_err(|_| fail(format!("'{key}' must be a number, got '{value}'")))
        };
        let vector = || {
            let parts: Vec<&str> = value.split(',').collect();
            let numbers: Option<Vec<f32>> =
                parts.iter().map(|p| p.trim().parse::<f32>().ok()).collect();
            match numbers.as_deref() {
                Some(&[x, y, z]) => Ok([x, y, z]),
                _ => Err(fail(format!(
                    "'{key}' must be three comma-separated numbers X,Y,Z, got '{value}'"
                ))),
            }
        };
        let slot_taken = match key {
            "position" => params.position.replace(vector()?).is_some(),
            "direction" => params.direction.replace(vector()?).is_some(),
            "color" => params.color.replace(vector()?).is_some(),
            "intensity" => params.intensity.replace(scalar()?).is_some(),
            "irradiance" => params.irradiance.replace(scalar()?).is_some(),
            "range" => params.range.replace(scalar()?).is_some(),
            "inner" => params.inner.replace(scalar()?).is_some(),
            "outer" => params.outer.replace(scalar()?).is_some(),
            other => {
                return Err(fail(format!(
                    "unknown key '{other}'; expected {}",
                    kind.format()
                )));
            }
        };
        if slot_taken {
            return Err(fail(format!("'{key}' is given twice")));
        }
    }
    params.into_light().map_err(fail)
}

/// The lights file's top level: `[[light]]` tables.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightsFile {
    #[serde(default)]
    light: Vec<Params>,
}

/// Reads a lights file (format in the module documentation).
pub fn load_lights_file(path: &Path) -> Result<Vec<Light>, LightSpecError> {
    let text = std::fs::read_to_string(path).map_err(|err| {
        LightSpecError(format!(
            "{}: cannot read the lights file: {err}",
            path.display()
        ))
    })?;
    parse_lights_toml(&text, &path.display().to_string())
}

/// Parses the text of a lights file; `label` names it in errors.
pub fn parse_lights_toml(text: &str, label: &str) -> Result<Vec<Light>, LightSpecError> {
    let file: LightsFile = toml::from_str(text).map_err(|err| {
        // toml's message spans several lines (it quotes the source); keep one. The message
        // itself may hold the file's own line breaks (a bad value quoted back).
        let message = crate::scene::gltf::one_line(err.message());
        let location = err
            .span()
            .map(|span| {
                let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
                format!(" at line {line}")
            })
            .unwrap_or_default();
        LightSpecError(format!(
            "{label}: invalid lights file{location}: {message} (expected [[light]] tables with type = \"point\" | \"spot\" | \"directional\")"
        ))
    })?;
    file.light
        .into_iter()
        .enumerate()
        .map(|(i, params)| {
            params
                .into_light()
                .map_err(|problem| LightSpecError(format!("{label}: light {}: {problem}", i + 1)))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_spec_carries_intensity_times_colour() {
        let light =
            parse_light("point:position=1,2,3:intensity=50:color=1,0.9,0.8:range=10").unwrap();
        assert_eq!(
            light,
            Light::Point {
                position: Vec3::new(1.0, 2.0, 3.0),
                intensity: Vec3::new(50.0, 45.0, 40.0),
                range: Some(10.0),
            }
        );
    }

    #[test]
    fn spot_spec_converts_degrees_to_cosines_and_normalises() {
        let light =
            parse_light("spot:position=0,4,0:direction=0,-2,0:intensity=80:inner=20:outer=30")
                .unwrap();
        let Light::Spot {
            direction,
            cos_inner,
            cos_outer,
            intensity,
            range,
            ..
        } = light
        else {
            panic!("expected a spot light")
        };
        assert_eq!(direction, Vec3::NEG_Y);
        assert!((cos_inner - 20f32.to_radians().cos()).abs() < 1e-6);
        assert!((cos_outer - 30f32.to_radians().cos()).abs() < 1e-6);
        assert_eq!(intensity, Vec3::splat(80.0));
        assert_eq!(range, None);
    }

    #[test]
    fn spot_defaults_are_the_extensions() {
        let Light::Spot {
            cos_inner,
            cos_outer,
            ..
        } = parse_light("spot:position=0,0,0:direction=1,0,0:intensity=1").unwrap()
        else {
            panic!("expected a spot light")
        };
        assert_eq!(cos_inner, 1.0);
        assert!((cos_outer - std::f32::consts::FRAC_PI_4.cos()).abs() < 1e-6);
    }

    #[test]
    fn directional_spec() {
        let light =
            parse_light("directional:direction=0,-1,0:irradiance=3:color=1,0.5,0.25").unwrap();
        assert_eq!(
            light,
            Light::Directional {
                direction: Vec3::NEG_Y,
                irradiance: Vec3::new(3.0, 1.5, 0.75),
            }
        );
    }

    /// Each bad spec fails with a message naming the offending key or value.
    #[test]
    fn bad_specs_name_the_problem() {
        let cases = [
            ("lamp:position=0,0,0", "unknown light type 'lamp'"),
            ("point:position=0,0:intensity=1", "'position' must be three"),
            ("point:position=0,0,0", "missing 'intensity'"),
            (
                "point:position=0,0,0:intensity=abc",
                "'intensity' must be a number",
            ),
            (
                "point:position=0,0,0:intensity=1:power=2",
                "unknown key 'power'",
            ),
            (
                "point:position=0,0,0:intensity=1:irradiance=2",
                "'irradiance' does not apply to a point",
            ),
            ("point:position=0,0,0:intensity=-1", "'intensity' is -1"),
            (
                "point:position=0,0,0:intensity=1:intensity=2",
                "'intensity' is given twice",
            ),
            (
                "spot:position=0,0,0:direction=0,0,0:intensity=1",
                "'direction'",
            ),
            (
                "spot:position=0,0,0:direction=0,0,1:intensity=1:inner=40:outer=30",
                "inner=40 and outer=30",
            ),
            ("directional:direction=0,-1,0", "missing 'irradiance'"),
            ("point:position", "not key=value"),
            ("point:position=0,0,0:intensity=1:range=0", "'range' is 0"),
        ];
        for (spec, expected) in cases {
            let err = parse_light(spec).expect_err(spec).to_string();
            assert!(err.contains(expected), "{spec}: {err}");
            assert!(err.contains(spec), "message should quote the spec: {err}");
        }
    }

    #[test]
    fn lights_file_matches_the_spec_syntax() {
        let text = r#"
            [[light]]
            type = "point"
            position = [1, 2, 3]
            intensity = 50
            color = [1, 0.9, 0.8]
            range = 10

            [[light]]
            type = "directional"
            direction = [0, -1, 0]
            irradiance = 3
        "#;
        let lights = parse_lights_toml(text, "lights.toml").unwrap();
        assert_eq!(lights.len(), 2);
        assert_eq!(
            lights[0],
            parse_light("point:position=1,2,3:intensity=50:color=1,0.9,0.8:range=10").unwrap()
        );
        assert_eq!(
            lights[1],
            parse_light("directional:direction=0,-1,0:irradiance=3").unwrap()
        );
    }

    #[test]
    fn bad_lights_files_name_file_light_and_key() {
        let unknown =
            "[[light]]\ntype = \"point\"\nposition = [0, 0, 0]\nintensity = 1\nwatts = 3\n";
        let err = parse_lights_toml(unknown, "my.toml")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("my.toml") && err.contains("watts") && err.contains("line 5"),
            "{err}"
        );
        let missing = "[[light]]\ntype = \"spot\"\nposition = [0, 0, 0]\nintensity = 1\n";
        let err = parse_lights_toml(missing, "my.toml")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("my.toml: light 1: missing 'direction'"),
            "{err}"
        );
        let bad_type = "[[light]]\ntype = \"area\"\n";
        let err = parse_lights_toml(bad_type, "my.toml")
            .unwrap_err()
            .to_string();
        assert!(err.contains("area"), "{err}");
        let err = load_lights_file(Path::new("/nonexistent/lights.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("/nonexistent/lights.toml") && err.contains("cannot read"),
            "{err}"
        );
    }
}
