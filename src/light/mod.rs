//! Punctual lights (KHR_lights_punctual) evaluated at a surface point, in radiometric units.
//!
//! Each light type lives in its own module and implements [`PunctualLight`]: given a surface
//! point it returns the direction toward the light, the irradiance the light would deliver on
//! a surface facing it (W/m²), and where a shadow ray must go, or why it cannot contribute
//! there at all (outside its cone, beyond its range), in which case no shadow ray is traced.
//!
//! | type | parameters (units) | irradiance on a facing surface at distance d |
//! |---|---|---|
//! | [`PointLight`] | position, intensity I (W/sr), range | I · W(d) / d² |
//! | [`SpotLight`] | as point, plus direction, cos inner, cos outer | I · s(cosφ) · W(d) / d² |
//! | [`DirectionalLight`] | direction of travel, irradiance E (W/m²) | E |
//!
//! W is the range window of [`range`] and s the cone falloff of [`spot`]. [`LightSet`]
//! validates a render's punctual lights once; [`LightSampler`] is the one interface the
//! integrators sample every light through (punctual, emissive triangles in [`area`], the
//! environment in [`environment`]).

pub mod area;
pub mod directional;
pub mod emission_average;
pub mod environment;
pub mod light_bvh;
pub mod placed_emitters;
pub mod point;
pub mod range;
pub mod sampler;
pub mod spot;

pub use area::{AreaLights, AreaSample, EmitterMesh};
pub use directional::DirectionalLight;
pub use environment::{EnvSample, EnvironmentError, EnvironmentLight};
pub use point::PointLight;
pub use range::{Bounded, RangeWindow, Unbounded};
pub use sampler::{LightSample, LightSampler, NoLightSample};
pub use spot::SpotLight;

use crate::scene::Light;
use glam::Vec3;

/// Luminous efficacy used to turn photometric light units into radiometric ones (lm/W): the
/// constant that defines the candela. glTF gives intensities in candela (point, spot) and lux
/// (directional); glint's lights are in W/sr and W/m², so `--photometric` divides by this.
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Which units a scene's light intensities are in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LightUnits {
    /// W/sr and W/m², used as they are (glint's default).
    #[default]
    Radiometric,
    /// cd and lx: divided by [`LUMENS_PER_WATT`].
    Photometric,
}

impl LightUnits {
    /// The factor that turns an intensity in these units into radiometric units.
    pub fn to_radiometric(self) -> f32 {
        match self {
            LightUnits::Radiometric => 1.0,
            LightUnits::Photometric => 1.0 / LUMENS_PER_WATT,
        }
    }
}

/// Where the shadow ray of a light sample goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShadowTarget {
    /// A segment to this point (point and spot lights).
    Point(Vec3),
    /// A ray to infinity along the sample's `wi` (directional lights).
    Infinity,
}

/// What a light delivers at a surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Incident {
    /// Unit direction from the surface point toward the light.
    pub wi: Vec3,
    /// Irradiance on a surface perpendicular to `wi` (W/m²), before visibility.
    pub irradiance: Vec3,
    /// Where to test visibility.
    pub target: ShadowTarget,
}

/// Why a light contributes nothing at a point, known without tracing a ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unlit {
    /// The point is outside a spot light's outer cone.
    OutsideCone,
    /// The point is at or beyond the light's range.
    BeyondRange,
    /// The point coincides with the light (the direction is undefined); also when d² under- or
    /// overflows `f32`.
    AtLight,
}

/// A light that can be evaluated at a surface point.
pub trait PunctualLight: Send + Sync {
    /// The light's contribution at `p`, or why there is none.
    fn incident(&self, p: Vec3) -> Result<Incident, Unlit>;
}

/// A punctual light of any type (a branch on the type and a range window, infinite without
/// a range). Gives the same values as the typed lights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GeneralLight {
    /// A point light with a (possibly infinite) range.
    Point(PointLight<Bounded>),
    /// A spot light with a (possibly infinite) range.
    Spot(SpotLight<Bounded>),
    /// A directional light.
    Directional(DirectionalLight),
}

impl PunctualLight for GeneralLight {
    #[inline]
    fn incident(&self, p: Vec3) -> Result<Incident, Unlit> {
        match self {
            GeneralLight::Point(light) => light.incident(p),
            GeneralLight::Spot(light) => light.incident(p),
            GeneralLight::Directional(light) => light.incident(p),
        }
    }
}

/// A light in the scene that cannot be used.
#[derive(Debug, thiserror::Error)]
#[error("light {index} ({kind}): {reason}; fix the light in the scene file or the --light value")]
pub struct LightError {
    /// Index in `Scene::lights`.
    pub index: usize,
    /// Light type.
    pub kind: &'static str,
    /// What is wrong.
    pub reason: String,
}

/// A render's punctual lights, validated and in radiometric units, in scene order; the
/// [`LightSampler`] chooses among them.
#[derive(Clone, Debug, Default)]
pub struct LightSet {
    /// The lights that can contribute (black ones are dropped).
    pub lights: Vec<GeneralLight>,
}

impl LightSet {
    /// Validates `lights`, scaling intensities by `units.to_radiometric()`. Lights that emit
    /// nothing (zero intensity) are dropped: they can never contribute.
    pub fn new(lights: &[Light], units: LightUnits) -> Result<Self, LightError> {
        let scale = units.to_radiometric();
        let mut set = LightSet::default();
        for (index, light) in lights.iter().enumerate() {
            let kind = match light {
                Light::Point { .. } => "point",
                Light::Spot { .. } => "spot",
                Light::Directional { .. } => "directional",
            };
            let err = |reason: String| LightError {
                index,
                kind,
                reason,
            };
            match *light {
                Light::Point {
                    position,
                    intensity,
                    range,
                } => {
                    check_position(position).map_err(err)?;
                    check_power(intensity, "intensity").map_err(err)?;
                    if intensity == Vec3::ZERO {
                        continue;
                    }
                    let window = match range {
                        Some(r) => Bounded::new(r).map_err(err)?,
                        None => Bounded::from_option(None),
                    };
                    set.lights.push(GeneralLight::Point(PointLight::new(
                        position,
                        intensity * scale,
                        window,
                    )));
                }
                Light::Spot {
                    position,
                    direction,
                    intensity,
                    range,
                    cos_inner,
                    cos_outer,
                } => {
                    check_position(position).map_err(err)?;
                    check_power(intensity, "intensity").map_err(err)?;
                    let direction = check_direction(direction).map_err(err)?;
                    if !(cos_inner.is_finite() && cos_outer.is_finite()) {
                        return Err(err("cone angles are not finite".into()));
                    }
                    if intensity == Vec3::ZERO {
                        continue;
                    }
                    let window = match range {
                        Some(r) => Bounded::new(r).map_err(err)?,
                        None => Bounded::from_option(None),
                    };
                    set.lights.push(GeneralLight::Spot(SpotLight::new(
                        position,
                        direction,
                        intensity * scale,
                        cos_inner,
                        cos_outer,
                        window,
                    )));
                }
                Light::Directional {
                    direction,
                    irradiance,
                } => {
                    let direction = check_direction(direction).map_err(err)?;
                    check_power(irradiance, "irradiance").map_err(err)?;
                    if irradiance == Vec3::ZERO {
                        continue;
                    }
                    set.lights
                        .push(GeneralLight::Directional(DirectionalLight::new(
                            direction,
                            irradiance * scale,
                        )));
                }
            }
        }
        Ok(set)
    }

    /// Number of lights that can contribute.
    pub fn len(&self) -> usize {
        self.lights.len()
    }

    /// Whether no light can contribute.
    pub fn is_empty(&self) -> bool {
        self.lights.is_empty()
    }
}

fn check_position(position: Vec3) -> Result<(), String> {
    if position.is_finite() {
        Ok(())
    } else {
        Err(format!("position {position} is not finite"))
    }
}

fn check_power(value: Vec3, what: &str) -> Result<(), String> {
    if value.is_finite() && value.min_element() >= 0.0 {
        Ok(())
    } else {
        Err(format!("{what} {value} must be finite and non-negative"))
    }
}

fn check_direction(direction: Vec3) -> Result<Vec3, String> {
    let unit = direction.normalize_or_zero();
    if unit == Vec3::ZERO {
        Err(format!("direction {direction} has no length"))
    } else {
        Ok(unit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lights_are_validated_and_scaled() {
        let lights = [
            Light::Point {
                position: Vec3::Y,
                intensity: Vec3::splat(683.0),
                range: None,
            },
            Light::Point {
                position: Vec3::Y,
                intensity: Vec3::ONE,
                range: Some(2.0),
            },
            Light::Directional {
                direction: -Vec3::Y * 3.0,
                irradiance: Vec3::ZERO,
            },
        ];
        let set = LightSet::new(&lights, LightUnits::Photometric).unwrap();
        assert_eq!(set.len(), 2, "a black light is dropped");
        assert!(matches!(set.lights[1], GeneralLight::Point(_)));
        let e = set.lights[0].incident(Vec3::ZERO).unwrap().irradiance;
        assert!((e - Vec3::ONE).abs().max_element() < 1e-6);
    }

    #[test]
    fn unusable_lights_are_errors_naming_the_light() {
        let lights = [Light::Spot {
            position: Vec3::ZERO,
            direction: Vec3::ZERO,
            intensity: Vec3::ONE,
            range: None,
            cos_inner: 1.0,
            cos_outer: 0.5,
        }];
        let err = LightSet::new(&lights, LightUnits::Radiometric).unwrap_err();
        assert_eq!(err.index, 0);
        assert!(err.to_string().contains("spot"));
        let negative = [Light::Point {
            position: Vec3::ZERO,
            intensity: -Vec3::ONE,
            range: None,
        }];
        assert!(LightSet::new(&negative, LightUnits::Radiometric).is_err());
        let bad_range = [Light::Point {
            position: Vec3::ZERO,
            intensity: Vec3::ONE,
            range: Some(0.0),
        }];
        assert!(LightSet::new(&bad_range, LightUnits::Radiometric).is_err());
    }
}
