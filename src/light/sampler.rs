//! One light sampler over every light of a render: it chooses the one light a path vertex
//! samples and draws that light's sample, and it answers the density with which it would
//! have drawn a direction that a BSDF-sampled ray found (for multiple importance sampling).
//!
//! # Which light
//!
//! Lights fall in two kinds, and a path vertex takes one sample of each kind it has:
//! - **finite** lights: point and spot lights in a light BVH of their own
//!   ([`LightBvh::over`]) and the emissive triangles ([`AreaLights`], by power or by their own
//!   light BVH). Together they are one tree whose root splits punctual lights from emissive
//!   ones: the two sides are chosen in proportion to their importance at the shading point
//!   (the same bound on `Φ cos θ / d²` the trees use inside, see [`super::light_bvh`]), and
//!   each side then descends its own tree ([`LightSampler::sample_finite`]);
//! - **infinite** lights: directional lights and the environment, one chosen uniformly
//!   ([`LightSampler::sample_infinite`]).
//!
//! Taking one sample of each kind rather than choosing between the kinds was measured
//! (docs/lights.md): choosing the environment or the emitters with probability ½ each
//! (pbrt-v4's rule for infinite lights beside its BVH) halved the efficiency at equal error on
//! the demo (emissive panel under an HDRI, 16 spp: 1/(time × relMSE) 28.1 → 17.4) and on
//! DamagedHelmet under studio.exr (444 → 204): the two kinds light different parts of a scene
//! and neither sample serves the other's. Every light has one selection probability within
//! its kind, the product along the choices; 64 lamps still cost one shadow ray, not 64.
//!
//! **Few delta lights are split, not chosen.** A scene with at most [`DELTA_SPLIT_MAX`] point,
//! spot and directional lights samples each of them at every vertex ([`LightSampler::delta`],
//! probability 1, one shadow ray each): a delta light's sample has no variance but for its
//! visibility, so for a lamp or two the exhaustive estimate is exact where a chosen one would
//! be noisy, at the same cost. Past that count they join the tree (points and spots) and the
//! infinite lights (directional ones).
//!
//! # Random numbers
//!
//! Each kind's sample takes `u_choice` (one dimension, only when there is a choice to make:
//! more than one light of the kind, or emissive triangles, which choose their triangle with
//! it) and `u` (two dimensions, only for emissive triangles or an environment). So a scene
//! with up to four delta lights, emitters and an environment consumes the dimensions it did
//! before this sampler existed, in the same order, and renders the same bytes.
//!
//! # Estimator
//!
//! A delta light's sample carries its irradiance and its discrete selection probability; an
//! area or environment sample its solid-angle density times its selection probability.
//! Dividing by them keeps next-event estimation unbiased: every light that can contribute at
//! a point has a positive probability there (`tests/transport/light_sampler.rs` checks the sum over 64
//! point lights, 16 spots, an emissive mesh and an environment against each light's own
//! integral).

use super::area::{AreaLights, AreaSample};
use super::environment::{EnvSample, EnvSampling, EnvironmentLight};
use super::light_bvh::{ClusterBounds, LightBvh};
use super::{GeneralLight, LightSet, PunctualLight, ShadowTarget, Unlit};
use crate::color::luminance;
use glam::{Vec2, Vec3};
use std::borrow::Cow;
use std::f32::consts::PI;

/// Delta-light counts up to which every delta light is sampled at every vertex (see the
/// module doc); more join the light tree and one is chosen.
pub const DELTA_SPLIT_MAX: usize = 4;

/// A light sample, as the integrator turns it into a shadow ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightSample {
    /// A point, spot or directional light.
    Delta {
        /// Unit direction toward the light.
        wi: Vec3,
        /// Irradiance on a surface facing `wi` (W/m²), before visibility.
        irradiance: Vec3,
        /// Where the shadow ray goes.
        target: ShadowTarget,
        /// The probability with which the sampler chose this light.
        probability: f32,
    },
    /// A point on an emissive triangle; its `pdf` includes the selection probability.
    Area(AreaSample),
    /// An environment direction; its `pdf` includes the selection probability.
    Environment(EnvSample),
}

/// The lights of a render and how one of them is chosen (see the module doc).
#[derive(Clone, Debug, Default)]
pub struct LightSampler<'a> {
    /// Delta lights sampled at every vertex (at most [`DELTA_SPLIT_MAX`]; then the others
    /// below are empty).
    split: Vec<GeneralLight>,
    /// Point and spot lights, entry `j` of `tree`.
    punctual: Vec<GeneralLight>,
    /// The light BVH over `punctual`.
    tree: Option<LightBvh>,
    /// Directional lights.
    directional: Vec<GeneralLight>,
    /// Emissive triangles (`None` when nothing emits or surfaces are not light-sampled).
    area: Option<Cow<'a, AreaLights>>,
    /// The environment (`None` without one, or when it is not light-sampled).
    environment: Option<&'a EnvironmentLight>,
    /// Which of the environment's distributions its samples come from.
    env_sampling: EnvSampling,
}

impl<'a> LightSampler<'a> {
    /// The sampler over `lights` (punctual), `area` (emissive triangles) and `environment`.
    pub fn new(
        lights: &LightSet,
        area: Option<Cow<'a, AreaLights>>,
        environment: Option<&'a EnvironmentLight>,
    ) -> Self {
        let area = area.filter(|a| !a.is_empty());
        if lights.lights.len() <= DELTA_SPLIT_MAX {
            return Self {
                split: lights.lights.clone(),
                area,
                environment,
                ..Self::default()
            };
        }
        let (directional, punctual): (Vec<GeneralLight>, Vec<GeneralLight>) = lights
            .lights
            .iter()
            .partition(|l| matches!(l, GeneralLight::Directional(_)));
        let bounds: Vec<ClusterBounds> = punctual.iter().map(punctual_bounds).collect();
        let tree = LightBvh::over(&bounds);
        Self {
            split: Vec::new(),
            punctual,
            tree,
            directional,
            area,
            environment,
            env_sampling: EnvSampling::Full,
        }
    }

    /// The same sampler drawing environment directions from `mode` (the full distribution
    /// by default; the compensated one only where BSDF sampling, combined by MIS, also runs at
    /// every vertex that takes a light sample). Builds that distribution now.
    pub fn with_env_sampling(mut self, mode: EnvSampling) -> Self {
        if let Some(env) = self.environment {
            env.prepare(mode);
        }
        self.env_sampling = mode;
        self
    }

    /// Which distribution environment samples come from.
    #[inline]
    pub fn env_sampling(&self) -> EnvSampling {
        self.env_sampling
    }

    /// The emissive triangles, if they are sampled.
    pub fn area(&self) -> Option<&AreaLights> {
        self.area.as_deref()
    }

    /// The environment, if it is sampled.
    pub fn environment(&self) -> Option<&'a EnvironmentLight> {
        self.environment
    }

    /// The delta lights sampled at every vertex (each with probability 1), in scene order:
    /// their samples at `p`, or why a light does not reach it.
    #[inline]
    pub fn delta(&self, p: Vec3) -> impl Iterator<Item = Result<LightSample, NoLightSample>> + '_ {
        self.split
            .iter()
            .map(move |light| delta_sample(light, p, 1.0))
    }

    /// Whether there is no light to sample.
    pub fn is_empty(&self) -> bool {
        self.split.is_empty() && !self.has_finite() && self.infinite_count() == 0
    }

    /// The kinds a vertex samples besides the [`delta`](Self::delta) lights (finite first,
    /// then infinite), each with whether its sample needs `u_choice` and `u`.
    #[inline]
    pub fn kinds(&self) -> [Option<Kind>; 2] {
        let finite = self.has_finite().then(|| Kind {
            finite: true,
            needs_choice: self.area.is_some() || self.punctual.len() > 1,
            needs_position: self.area.is_some(),
        });
        let n_inf = self.infinite_count();
        let infinite = (n_inf > 0).then(|| Kind {
            finite: false,
            needs_choice: n_inf > 1,
            needs_position: self.environment.is_some(),
        });
        [finite, infinite]
    }

    #[inline]
    fn infinite_count(&self) -> usize {
        self.directional.len() + usize::from(self.environment.is_some())
    }

    #[inline]
    fn has_finite(&self) -> bool {
        self.tree.is_some() || self.area.is_some()
    }

    /// The probability that the finite tree's root goes to the punctual side (`punctual`) or
    /// the emissive side at `p`, `n`: 1 when only that side exists.
    #[inline]
    fn side_probability(&self, p: Vec3, n: Vec3, punctual: bool) -> f32 {
        match (&self.tree, &self.area) {
            (Some(tree), Some(area)) => {
                let (ip, ia) = (tree.importance(p, n), area.importance(p, n));
                let sum = ip + ia;
                if !(sum > 0.0 && sum.is_finite()) {
                    return 0.0;
                }
                if punctual { ip / sum } else { ia / sum }
            }
            (Some(_), None) => f32::from(u8::from(punctual)),
            (None, Some(_)) => f32::from(u8::from(!punctual)),
            (None, None) => 0.0,
        }
    }

    /// One sample of `kind` (from [`kinds`](Self::kinds)) for the point `p` with shading
    /// normal `n`.
    #[inline]
    pub fn sample(
        &self,
        kind: Kind,
        p: Vec3,
        n: Vec3,
        u_choice: f32,
        u: Vec2,
    ) -> Result<LightSample, NoLightSample> {
        if kind.finite {
            self.sample_finite(p, n, u_choice, u)
        } else {
            self.sample_infinite(p, u_choice, u)
        }
    }

    /// One sample of the finite lights (point, spot, emissive triangles; see the module doc),
    /// or why there is none: the chosen delta light does not reach `p` (outside its cone,
    /// beyond its range), or no light could be drawn.
    #[inline]
    pub fn sample_finite(
        &self,
        p: Vec3,
        n: Vec3,
        u_choice: f32,
        u: Vec2,
    ) -> Result<LightSample, NoLightSample> {
        let pp = self.side_probability(p, n, true);
        let pa = self.side_probability(p, n, false);
        let (punctual, probability, rest) = if pa <= 0.0 {
            (true, pp, u_choice)
        } else if pp <= 0.0 {
            (false, pa, u_choice)
        } else if u_choice < pp {
            (true, pp, (u_choice / pp).min(ONE_BELOW))
        } else {
            (false, pa, ((u_choice - pp) / pa).min(ONE_BELOW))
        };
        positive(probability)?;
        if punctual {
            let (j, pmf) = if self.punctual.len() == 1 {
                (0, 1.0)
            } else {
                self.tree
                    .as_ref()
                    .and_then(|tree| tree.sample(p, n, rest))
                    .ok_or(NoLightSample::None)?
            };
            let light = self.punctual.get(j).ok_or(NoLightSample::None)?;
            delta_sample(light, p, probability * pmf)
        } else {
            let mut ls = self
                .area
                .as_ref()
                .and_then(|area| area.sample(p, n, rest, u))
                .ok_or(NoLightSample::None)?;
            ls.pdf *= probability;
            positive(ls.pdf).map(|_| LightSample::Area(ls))
        }
    }

    /// One sample of the infinite lights (directional lights, the environment), chosen
    /// uniformly.
    #[inline]
    pub fn sample_infinite(
        &self,
        p: Vec3,
        u_choice: f32,
        u: Vec2,
    ) -> Result<LightSample, NoLightSample> {
        let n = self.infinite_count();
        if n == 0 {
            return Err(NoLightSample::None);
        }
        let k = ((u_choice * n as f32) as usize).min(n - 1);
        let probability = 1.0 / n as f32;
        match self.directional.get(k) {
            Some(light) => delta_sample(light, p, probability),
            None => {
                let mut es = self
                    .environment
                    .and_then(|env| env.sample_with(u, self.env_sampling))
                    .ok_or(NoLightSample::None)?;
                es.pdf *= probability;
                positive(es.pdf).map(|_| LightSample::Environment(es))
            }
        }
    }

    /// The density with which [`sample_finite`](Self::sample_finite) at `p`, `n` draws the
    /// point `point` of emissive triangle `(mesh, instance, triangle)`, per solid angle at `p`.
    #[inline]
    pub fn area_pdf(&self, p: Vec3, n: Vec3, triangle: (u32, u32, u32), point: Vec3) -> f32 {
        let Some(area) = &self.area else {
            return 0.0;
        };
        let side = self.side_probability(p, n, false);
        if side <= 0.0 {
            return 0.0;
        }
        side * area.pdf(p, n, triangle, point)
    }

    /// The density with which [`sample_infinite`](Self::sample_infinite) draws the
    /// environment direction `dir` (unit), per solid angle.
    #[inline]
    pub fn environment_pdf(&self, dir: Vec3) -> f32 {
        match self.environment {
            Some(env) => env.pdf_with(dir, self.env_sampling) / self.infinite_count() as f32,
            None => 0.0,
        }
    }

    /// The sampler's density for an environment direction whose own density under the
    /// environment's map is `env_pdf` (from [`EnvironmentLight::radiance_and_pdf_with`] and
    /// [`env_sampling`](Self::env_sampling)): the
    /// same as [`environment_pdf`](Self::environment_pdf) without looking the direction up
    /// again.
    #[inline]
    pub fn environment_pdf_of(&self, env_pdf: f32) -> f32 {
        match self.environment {
            Some(_) => env_pdf / self.infinite_count() as f32,
            None => 0.0,
        }
    }
}

/// One of the kinds of light a vertex samples (see [`LightSampler::kinds`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Kind {
    /// The finite lights (else the infinite ones).
    pub finite: bool,
    /// Whether its sample reads `u_choice`.
    pub needs_choice: bool,
    /// Whether its sample reads `u`.
    pub needs_position: bool,
}

/// Why a [`LightSampler`] drew no sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoLightSample {
    /// The chosen delta light does not reach the point.
    Unlit(Unlit),
    /// No light could be chosen or drawn (none reaches the point, a degenerate sample).
    None,
}

/// `Ok` for a positive density or probability.
#[inline]
fn positive(pdf: f32) -> Result<(), NoLightSample> {
    if pdf > 0.0 {
        Ok(())
    } else {
        Err(NoLightSample::None)
    }
}

/// The largest f32 below 1.
const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

/// A delta light's sample at `p`, chosen with `probability`.
#[inline]
fn delta_sample(
    light: &GeneralLight,
    p: Vec3,
    probability: f32,
) -> Result<LightSample, NoLightSample> {
    let incident = light.incident(p).map_err(NoLightSample::Unlit)?;
    positive(probability)?;
    Ok(LightSample::Delta {
        wi: incident.wi,
        irradiance: incident.irradiance,
        target: incident.target,
        probability,
    })
}

/// The light BVH's bounds of a point or spot light: power `4π · luminance(I)`, as pbrt-v4
/// counts a point light's power.
fn punctual_bounds(light: &GeneralLight) -> ClusterBounds {
    match light {
        GeneralLight::Point(l) => {
            ClusterBounds::point(l.position, 4.0 * PI * luminance(l.intensity).max(0.0))
        }
        GeneralLight::Spot(l) => ClusterBounds::spot(
            l.position,
            l.direction,
            l.cos_outer,
            4.0 * PI * luminance(l.intensity).max(0.0),
        ),
        // Not in the tree: infinite lights are chosen beside it.
        GeneralLight::Directional(_) => ClusterBounds::point(Vec3::ZERO, 0.0),
    }
}
