//! Measures the variance the light BVH saves against the power CDF on a scene of many small
//! emitters: a 32 × 32 grid of small emissive quads (2048 triangles) 2 m over a 32 m floor,
//! with random radiance, and receivers on the floor. At each receiver, the irradiance
//! E = ∫ Le cos θ dω is estimated by light sampling alone (no occlusion, as in the tests)
//! with N samples per selector; the per-sample variances are compared.
//!
//! `cargo run --release --example light_sampler_variance [N] [GRID]` (GRID × GRID quads over
//! the same 32 m, default 32)

use glam::{Vec2, Vec3};
use glint::light::area::{AreaLights, EmitterMesh, SelectionMode};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100_000);
    let grid: usize = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(32);
    // The grid always spans 32 m, so fewer emitters are farther apart.
    let spacing = 32.0 / grid as f32;
    let (size, height) = (0.1f32, 2.0f32);
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    let mut rng = Pcg64::seed_from_u64(1);
    let mut le = Vec::new();
    let half = grid as f32 * spacing / 2.0;
    for i in 0..grid {
        for j in 0..grid {
            let c = Vec3::new(i as f32 * spacing - half, height, j as f32 * spacing - half);
            let (x, z) = (Vec3::X * size / 2.0, Vec3::Z * size / 2.0);
            let b = positions.len() as u32;
            // Facing down (−Y): counter-clockwise seen from below.
            positions.extend([c - x - z, c + x - z, c + x + z, c - x + z]);
            indices.push([b, b + 1, b + 2]);
            indices.push([b, b + 2, b + 3]);
            let radiance = 0.5 + 4.5 * rng.random::<f32>();
            le.push(Vec3::splat(radiance));
            le.push(Vec3::splat(radiance));
        }
    }
    let mesh = EmitterMesh {
        positions: &positions,
        indices: &indices,
        two_sided: false,
        instances: &[],
    };
    let radiance = |_: u32, t: u32| le[t as usize];
    // Area sampling only here, so that the selectors are compared alone; the solid-angle
    // sampling of near triangles is measured separately below.
    let power = AreaLights::with_selection(&[mesh], radiance, SelectionMode::Power)?
        .with_solid_angle_sampling(false);
    let bvh = AreaLights::with_selection(&[mesh], radiance, SelectionMode::Bvh)?
        .with_solid_angle_sampling(false);
    let receivers = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.3, 0.0, -0.4),
        Vec3::new(8.2, 0.0, 3.1),
        Vec3::new(-12.5, 0.0, 12.5),
        Vec3::new(15.5, 0.0, 0.0),
        Vec3::new(-15.9, 0.0, -15.9),
        Vec3::new(20.0, 0.0, 5.0),
        Vec3::new(-30.0, 0.0, -2.0),
    ];
    println!(
        "{} emissive triangles, {n} samples per receiver and selector\n",
        indices.len()
    );
    println!(
        "| receiver | E (power CDF) | E (light BVH) | variance (power) | variance (BVH) | ratio |"
    );
    println!("|---|---|---|---|---|---|");
    let mut log_ratio = 0.0f64;
    let mut times = [0.0f64; 2];
    for (r, &p) in receivers.iter().enumerate() {
        let mut stats = [(0.0f64, 0.0f64); 2];
        for (k, lights) in [&power, &bvh].into_iter().enumerate() {
            let mut rng = Pcg64::seed_from_u64(100 + r as u64);
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            let start = std::time::Instant::now();
            for _ in 0..n {
                let value = lights
                    .sample(
                        p,
                        Vec3::Y,
                        rng.random(),
                        Vec2::new(rng.random(), rng.random()),
                    )
                    .map_or(0.0, |s| {
                        f64::from(s.le.x * Vec3::Y.dot(s.wi).max(0.0) / s.pdf)
                    });
                sum += value;
                sum2 += value * value;
            }
            times[k] += start.elapsed().as_secs_f64();
            let mean = sum / n as f64;
            let var = (sum2 / n as f64 - mean * mean) * n as f64 / (n as f64 - 1.0);
            stats[k] = (mean, var);
        }
        let ratio = stats[0].1 / stats[1].1;
        log_ratio += ratio.ln();
        println!(
            "| ({:.1}, {:.1}) | {:.5} | {:.5} | {:.4e} | {:.4e} | {:.1} |",
            p.x, p.z, stats[0].0, stats[1].0, stats[0].1, stats[1].1, ratio
        );
    }
    let per = |t: f64| t / (n * receivers.len()) as f64 * 1e9;
    println!(
        "\ngeometric mean variance ratio (power / BVH): {:.1}",
        (log_ratio / receivers.len() as f64).exp()
    );
    println!(
        "time per sample: power CDF {:.0} ns, light BVH {:.0} ns",
        per(times[0]),
        per(times[1])
    );
    if grid == 32 {
        near_emitters(n)?;
    }
    Ok(())
}

/// Variance of area sampling against solid-angle sampling for large emitters close to the
/// receiver at the origin (normal +Y): a disk (1024-triangle fan) and a 2-triangle rectangle.
fn near_emitters(n: usize) -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "\n| emitter | E (area) | E (solid angle) | variance (area) | variance (solid angle) | ratio |"
    );
    println!("|---|---|---|---|---|---|");
    let disk = |r: f32, h: f32| {
        let mut positions = vec![Vec3::new(0.0, h, 0.0)];
        let segments = 1024u32;
        for i in 0..segments {
            let phi = std::f32::consts::TAU * i as f32 / segments as f32;
            positions.push(Vec3::new(r * phi.cos(), h, r * phi.sin()));
        }
        let indices: Vec<[u32; 3]> = (0..segments)
            .map(|i| [0, 1 + i, 1 + (i + 1) % segments])
            .collect();
        (positions, indices)
    };
    let rect = |a: f32, b: f32, h: f32| {
        let (x, z) = (a / 2.0, b / 2.0);
        let positions = vec![
            Vec3::new(-x, h, -z),
            Vec3::new(x, h, -z),
            Vec3::new(x, h, z),
            Vec3::new(-x, h, z),
        ];
        (positions, vec![[0, 1, 2], [0, 2, 3]])
    };
    let cases = [
        ("disk r 2 at 0.5", disk(2.0, 0.5)),
        ("disk r 1 at 1", disk(1.0, 1.0)),
        ("rectangle 2 × 0.5 at 0.7", rect(2.0, 0.5, 0.7)),
        ("rectangle 1 × 1 at 1", rect(1.0, 1.0, 1.0)),
    ];
    for (name, (positions, indices)) in cases {
        let mesh = EmitterMesh {
            positions: &positions,
            indices: &indices,
            two_sided: false,
            instances: &[],
        };
        let mut stats = [(0.0f64, 0.0f64); 2];
        for (k, solid) in [false, true].into_iter().enumerate() {
            let lights =
                AreaLights::new(&[mesh], |_, _| Vec3::ONE)?.with_solid_angle_sampling(solid);
            let mut rng = Pcg64::seed_from_u64(7);
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let value = lights
                    .sample(
                        Vec3::ZERO,
                        Vec3::Y,
                        rng.random(),
                        Vec2::new(rng.random(), rng.random()),
                    )
                    .map_or(0.0, |s| f64::from(Vec3::Y.dot(s.wi).max(0.0) / s.pdf));
                sum += value;
                sum2 += value * value;
            }
            let mean = sum / n as f64;
            stats[k] = (
                mean,
                (sum2 / n as f64 - mean * mean) * n as f64 / (n as f64 - 1.0),
            );
        }
        println!(
            "| {name} | {:.5} | {:.5} | {:.4e} | {:.4e} | {:.1} |",
            stats[0].0,
            stats[1].0,
            stats[0].1,
            stats[1].1,
            stats[0].1 / stats[1].1
        );
    }
    Ok(())
}
