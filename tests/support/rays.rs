//! Helpers shared by the integration tests: ray generators with fixed seeds.

#![allow(dead_code)]

use glam::{Vec3, vec3};
use glint::accel::Ray;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// SplitMix64: a small deterministic generator, so a test needs no seed file.
pub struct SplitMix(pub u64);

impl SplitMix {
    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1), on a 2⁻²⁴ grid.
    pub fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [−r, r].
    pub fn signed(&mut self, r: f32) -> f32 {
        (self.unit() * 2.0 - 1.0) * r
    }
}

/// Bounds of a set of points.
pub fn bounds(points: impl IntoIterator<Item = Vec3>) -> (Vec3, Vec3) {
    points.into_iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}

/// A pinhole camera's rays over a `w × h` grid, looking at the centre of `(lo, hi)` from outside
/// along `view_dir`, with a field of view that frames the bounding sphere.
pub fn camera_rays(lo: Vec3, hi: Vec3, view_dir: Vec3, w: usize, h: usize) -> Vec<Ray> {
    let centre = (lo + hi) * 0.5;
    let radius = (hi - lo).length() * 0.5;
    let forward = view_dir.normalize();
    let eye = centre - forward * radius * 3.0;
    let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
    let up = right.cross(forward);
    let half = (radius / (radius * 3.0)).atan().tan() * 1.1;
    let mut rays = Vec::with_capacity(w * h);
    for j in 0..h {
        for i in 0..w {
            let x = ((i as f32 + 0.5) / w as f32 * 2.0 - 1.0) * half;
            let y = (1.0 - (j as f32 + 0.5) / h as f32 * 2.0) * half;
            rays.push(Ray::new(eye, (forward + right * x + up * y).normalize()));
        }
    }
    rays
}

/// `n` rays with origins uniform in the box and directions uniform on the sphere.
pub fn random_rays(lo: Vec3, hi: Vec3, n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let o = vec3(
                rng.random_range(lo.x..=hi.x),
                rng.random_range(lo.y..=hi.y),
                rng.random_range(lo.z..=hi.z),
            );
            let z: f32 = rng.random_range(-1.0..=1.0);
            let phi: f32 = rng.random_range(0.0..std::f32::consts::TAU);
            let r = (1.0 - z * z).max(0.0).sqrt();
            Ray::new(o, vec3(r * phi.cos(), r * phi.sin(), z))
        })
        .collect()
}

/// The largest distance from a point of `a` to its nearest point of `b` (one side of the
/// Hausdorff distance), by brute force.
pub fn one_sided_hausdorff(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter()
        .map(|p| {
            b.iter()
                .map(|q| p.distance(*q))
                .fold(f32::INFINITY, f32::min)
        })
        .fold(0.0, f32::max)
}
