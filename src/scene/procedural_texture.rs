//! Procedural textures as scene data: what pattern a material's procedural base colour has,
//! where it is evaluated and with which colours and seed (read from glTF `extras` by
//! [`super::gltf`]). Their evaluation, band-limited by the pixel's footprint, is
//! [`crate::texture::noise`].

use glam::Vec3;

/// What a procedural texture computes.
#[derive(Clone, Debug, PartialEq)]
pub enum Pattern {
    /// Alternating squares (cubes in 3-D) of side 1 / frequency.
    Checker,
    /// Smoothly interpolated random lattice values.
    Value,
    /// Perlin gradient noise.
    Perlin,
    /// `Σ aᵢ · Perlin(fᵢ · p)` over the listed `(amplitude aᵢ, relative frequency fᵢ)` octaves.
    Mixed(Vec<Octave>),
}

/// One term of [`Pattern::Mixed`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Octave {
    /// Amplitude aᵢ.
    pub amplitude: f32,
    /// Frequency fᵢ, relative to the texture's `frequency`.
    pub frequency: f32,
}

/// Where a procedural texture is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Domain {
    /// Texture coordinates `TEXCOORD_n` (n = 0 or 1) as the point `(u, v, 0)`.
    Uv(usize),
    /// World-space position.
    World,
}

/// A procedural texture (a material's base colour, from its glTF `extras`).
#[derive(Clone, Debug, PartialEq)]
pub struct ProceduralTexture {
    /// The pattern.
    pub pattern: Pattern,
    /// Where it is evaluated.
    pub domain: Domain,
    /// Cycles per domain unit: the domain point is multiplied by it.
    pub frequency: f32,
    /// Linear RGB at pattern value 0 and 1.
    pub colors: [Vec3; 2],
    /// Seed of the noise lattice.
    pub seed: u64,
}
