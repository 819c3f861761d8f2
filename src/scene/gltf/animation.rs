//! Animations sampled at one time: the pose `--time SECONDS` renders.
//!
//! Every channel of every animation is sampled at time `t` (seconds); a later channel
//! targeting the same node property overrides an earlier one. Before the first keyframe a
//! channel holds its first value, after the last its last value (glTF leaves this to the
//! implementation; clamping is what viewers do). With keyframes `tₖ ≤ t < tₖ₊₁`,
//! `td = tₖ₊₁ − tₖ` and `u = (t − tₖ) / td`, the interpolations are glTF's:
//!
//! - STEP: `vₖ`;
//! - LINEAR: `(1 − u)·vₖ + u·vₖ₊₁`; for rotations the spherical interpolation
//!   `sin(a(1−u))/sin(a)·qₖ + s·sin(au)/sin(a)·qₖ₊₁` with `a = acos|qₖ·qₖ₊₁|` and `s` the sign
//!   of the dot product (the shorter arc);
//! - CUBICSPLINE, with in-tangents `aₖ` and out-tangents `bₖ` stored around each value:
//!   `(2u³−3u²+1)·vₖ + td(u³−2u²+u)·bₖ + (−2u³+3u²)·vₖ₊₁ + td(u³−u²)·aₖ₊₁`, rotations then
//!   normalised.
//!
//! Output values may be normalized integers (rotations and weights), read as glTF defines.

use super::LoadError;
use super::accessors::{self, Layout};
use super::quantization;
use super::source::Origin;
use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::animation::{Interpolation, Property};
use glam::{Quat, Vec3, Vec4};
use std::collections::HashMap;

/// A node's animated properties at the sampled time; `None` keeps the file's value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodePose {
    /// Animated translation.
    pub translation: Option<Vec3>,
    /// Animated rotation (unit quaternion).
    pub rotation: Option<Quat>,
    /// Animated scale.
    pub scale: Option<Vec3>,
    /// Animated morph-target weights.
    pub weights: Option<Vec<f32>>,
}

/// The animated properties of every node some channel targets.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pose {
    nodes: HashMap<usize, NodePose>,
}

impl Pose {
    /// The rest pose: nothing animated.
    pub fn rest() -> Pose {
        Pose::default()
    }

    /// The animated properties of node `index`, if any channel targets it.
    pub fn node(&self, index: usize) -> Option<&NodePose> {
        self.nodes.get(&index)
    }
}

const fn layout(dimensions: Dimensions, data_type: DataType, normalized: bool) -> Layout {
    Layout {
        dimensions,
        data_type,
        normalized,
    }
}
const INPUT: &[Layout] = &[layout(Dimensions::Scalar, DataType::F32, false)];
const VEC3_OUT: &[Layout] = &[layout(Dimensions::Vec3, DataType::F32, false)];
const ROTATION_OUT: &[Layout] = &[
    layout(Dimensions::Vec4, DataType::F32, false),
    layout(Dimensions::Vec4, DataType::I8, true),
    layout(Dimensions::Vec4, DataType::U8, true),
    layout(Dimensions::Vec4, DataType::I16, true),
    layout(Dimensions::Vec4, DataType::U16, true),
];
const WEIGHTS_OUT: &[Layout] = &[
    layout(Dimensions::Scalar, DataType::F32, false),
    layout(Dimensions::Scalar, DataType::I8, true),
    layout(Dimensions::Scalar, DataType::U8, true),
    layout(Dimensions::Scalar, DataType::I16, true),
    layout(Dimensions::Scalar, DataType::U16, true),
];

/// An accessor's elements, flattened to floats.
fn read_flat(accessor: &::gltf::Accessor<'_>, buffers: &[Vec<u8>]) -> Vec<f32> {
    match accessor.dimensions() {
        Dimensions::Scalar => quantization::read::<1>(accessor, buffers).concat(),
        Dimensions::Vec2 => quantization::read::<2>(accessor, buffers).concat(),
        Dimensions::Vec3 => quantization::read::<3>(accessor, buffers).concat(),
        _ => quantization::read::<4>(accessor, buffers).concat(),
    }
}

/// Samples every animation of `document` at `time` seconds.
pub fn sample(
    document: &::gltf::Document,
    buffers: &[Vec<u8>],
    time: f32,
    origin: Origin<'_>,
) -> Result<Pose, LoadError> {
    let mut pose = Pose::default();
    for animation in document.animations() {
        for channel in animation.channels() {
            let label = format!(
                "animation {} / channel {}",
                animation.index(),
                channel.index()
            );
            let fail = |problem: String| LoadError::Primitive {
                path: origin.file.to_path_buf(),
                primitive: label.clone(),
                problem,
            };
            let sampler = channel.sampler();
            let input = sampler.input();
            let output = sampler.output();
            let property = channel.target().property();
            accessors::check(&input, "input", INPUT, &label, buffers, origin)?;
            let allowed = match property {
                Property::Translation | Property::Scale => VEC3_OUT,
                Property::Rotation => ROTATION_OUT,
                Property::MorphTargetWeights => WEIGHTS_OUT,
            };
            accessors::check(&output, "output", allowed, &label, buffers, origin)?;
            let times = read_flat(&input, buffers);
            if times.iter().any(|t| !t.is_finite()) || times.windows(2).any(|w| w[1] <= w[0]) {
                return Err(fail(format!(
                    "input accessor {}: keyframe times must be finite and strictly increasing (re-export the animation)",
                    input.index()
                )));
            }
            let values = read_flat(&output, buffers);
            let interpolation = sampler.interpolation();
            let per_key = if interpolation == Interpolation::CubicSpline {
                3
            } else {
                1
            };
            let slots = times.len() * per_key;
            let width = match property {
                Property::Translation | Property::Scale => 3,
                Property::Rotation => 4,
                Property::MorphTargetWeights => values.len() / slots.max(1),
            };
            if width == 0 || values.len() != slots * width {
                return Err(fail(format!(
                    "output accessor {} has {} values, which does not fit {} keyframes × {per_key} ({:?})",
                    output.index(),
                    values.len(),
                    times.len(),
                    interpolation
                )));
            }
            let curve = Curve {
                times: &times,
                values: &values,
                width,
                interpolation,
            };
            let is_rotation = property == Property::Rotation;
            let sampled = curve.sample(time, is_rotation);
            let node = pose
                .nodes
                .entry(channel.target().node().index())
                .or_default();
            match property {
                Property::Translation => node.translation = Some(Vec3::from_slice(&sampled)),
                Property::Scale => node.scale = Some(Vec3::from_slice(&sampled)),
                Property::Rotation => {
                    let q = Quat::from_slice(&sampled);
                    if q.length_squared().is_nan() || q.length_squared() <= 0.0 {
                        return Err(fail(format!(
                            "output accessor {} gives a zero or NaN rotation at t = {time}",
                            output.index()
                        )));
                    }
                    node.rotation = Some(q.normalize());
                }
                Property::MorphTargetWeights => node.weights = Some(sampled),
            }
        }
    }
    Ok(pose)
}

/// One sampler's keyframes: `values` holds `width` floats per slot, one slot per keyframe
/// (three for CUBICSPLINE: in-tangent, value, out-tangent).
struct Curve<'a> {
    times: &'a [f32],
    values: &'a [f32],
    width: usize,
    interpolation: Interpolation,
}

impl Curve<'_> {
    fn slot(&self, index: usize) -> &[f32] {
        let start = index * self.width;
        self.values.get(start..start + self.width).unwrap_or(&[])
    }

    /// The value at keyframe `k` (the middle of a cubic spline's triplet).
    fn value(&self, k: usize) -> Vec<f32> {
        match self.interpolation {
            Interpolation::CubicSpline => self.slot(3 * k + 1).to_vec(),
            _ => self.slot(k).to_vec(),
        }
    }

    fn sample(&self, t: f32, rotation: bool) -> Vec<f32> {
        let last = self.times.len().saturating_sub(1);
        // Keyframe k with tₖ ≤ t < tₖ₊₁, clamped to the ends.
        let after = self.times.partition_point(|&tk| tk <= t);
        if after == 0 {
            return self.value(0);
        }
        if after > last {
            return self.value(last);
        }
        let k = after - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let td = t1 - t0;
        let u = (t - t0) / td;
        match self.interpolation {
            Interpolation::Step => self.value(k),
            Interpolation::Linear => {
                let (a, b) = (self.slot(k), self.slot(k + 1));
                if rotation {
                    slerp(Vec4::from_slice(a), Vec4::from_slice(b), u)
                        .to_array()
                        .to_vec()
                } else {
                    a.iter()
                        .zip(b)
                        .map(|(a, b)| (1.0 - u) * a + u * b)
                        .collect()
                }
            }
            Interpolation::CubicSpline => {
                let v0 = self.slot(3 * k + 1);
                let b0 = self.slot(3 * k + 2);
                let a1 = self.slot(3 * (k + 1));
                let v1 = self.slot(3 * (k + 1) + 1);
                let (u2, u3) = (u * u, u * u * u);
                let h00 = 2.0 * u3 - 3.0 * u2 + 1.0;
                let h10 = td * (u3 - 2.0 * u2 + u);
                let h01 = -2.0 * u3 + 3.0 * u2;
                let h11 = td * (u3 - u2);
                let mut out: Vec<f32> = (0..self.width)
                    .map(|c| h00 * v0[c] + h10 * b0[c] + h01 * v1[c] + h11 * a1[c])
                    .collect();
                if rotation {
                    let q = Vec4::from_slice(&out).normalize_or_zero();
                    out = q.to_array().to_vec();
                }
                out
            }
        }
    }
}

/// Spherical linear interpolation of unit quaternions (as xyzw vectors) along the shorter
/// arc, as the glTF spec writes it; nearly equal quaternions fall back to a normalised lerp
/// (sin(a) → 0 would divide by zero).
fn slerp(a: Vec4, b: Vec4, u: f32) -> Vec4 {
    let dot = a.dot(b);
    let s = if dot < 0.0 { -1.0 } else { 1.0 };
    let angle = dot.abs().min(1.0).acos();
    if angle < 1e-4 {
        return (a * (1.0 - u) + b * (s * u)).normalize_or_zero();
    }
    let sin = angle.sin();
    a * ((angle * (1.0 - u)).sin() / sin) + b * (s * (angle * u).sin() / sin)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve<'a>(times: &'a [f32], values: &'a [f32], width: usize, i: Interpolation) -> Curve<'a> {
        Curve {
            times,
            values,
            width,
            interpolation: i,
        }
    }

    #[test]
    fn step_linear_and_clamping() {
        let times = [1.0, 2.0, 4.0];
        let values = [0.0, 10.0, 30.0];
        let step = curve(&times, &values, 1, Interpolation::Step);
        assert_eq!(step.sample(1.99, false), vec![0.0]);
        assert_eq!(step.sample(2.0, false), vec![10.0]);
        let linear = curve(&times, &values, 1, Interpolation::Linear);
        assert_eq!(linear.sample(3.0, false), vec![20.0]);
        assert_eq!(linear.sample(0.0, false), vec![0.0]);
        assert_eq!(linear.sample(9.0, false), vec![30.0]);
    }

    #[test]
    fn cubic_spline_hits_keys_and_follows_tangents() {
        // One dimension, keys (0 → 0) and (2 → 1), tangents 0 except b₀ = 1.
        let times = [0.0, 2.0];
        let values = [0.0, 0.0, 1.0, /* key 1: */ 0.0, 1.0, 0.0];
        let c = curve(&times, &values, 1, Interpolation::CubicSpline);
        assert_eq!(c.sample(0.0, false), vec![0.0]);
        assert_eq!(c.sample(2.0, false), vec![1.0]);
        // u = 0.5: h00 = 0.5, h10 = td·0.125 = 0.25, h01 = 0.5, h11 = −0.25.
        let mid = c.sample(1.0, false)[0];
        assert!((mid - (0.25 + 0.5)).abs() < 1e-6, "{mid}");
    }

    #[test]
    fn slerp_takes_the_short_arc_at_constant_speed() {
        let a = Quat::IDENTITY;
        let b = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
        let half = slerp(Vec4::from(a), Vec4::from(b), 0.5);
        let expected = Quat::from_rotation_z(std::f32::consts::FRAC_PI_4);
        assert!((half - Vec4::from(expected)).length() < 1e-6);
        // −b is the same rotation: the result must be too (up to sign).
        let flipped = slerp(Vec4::from(a), -Vec4::from(b), 0.5);
        assert!((flipped - Vec4::from(expected)).length() < 1e-6);
    }
}
