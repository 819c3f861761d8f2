//! `glint bench instances`: what two-level instancing saves. One model is drawn at a grid of
//! copies, once as placements of a single stored mesh and once baked into world space, and
//! each backend's build time and structure size are measured for both layouts.
//!
//! The baked layout is built for fewer copies (`flat_count`) when the full count would not
//! fit in memory; its size per copy is then scaled to the full count, which is exact up to
//! the top levels' node counts (a baked scene's size grows linearly with its triangles).

use super::scene::BenchScene;
use crate::accel::{self, AccelError, BackendKind, BuildOptions, Placement, TriangleMesh};
use glam::{Affine3A, Quat, Vec3};
use std::time::Instant;

/// What to measure.
#[derive(Clone, Copy, Debug)]
pub struct InstancesConfig {
    /// Copies drawn as placements.
    pub count: usize,
    /// Copies drawn baked into world space (at most `count`).
    pub flat_count: usize,
    /// Build settings.
    pub options: BuildOptions,
}

/// One build.
#[derive(Clone, Debug, serde::Serialize)]
pub struct InstancesRow {
    /// The backend.
    pub backend: BackendKind,
    /// `placed` or `baked`.
    pub layout: &'static str,
    /// Copies in the structure.
    pub copies: usize,
    /// Triangles drawn.
    pub triangles: usize,
    /// Build time, seconds.
    pub build_seconds: f64,
    /// The structure's bytes as the backend reports them (Embree: its memory monitor; obvhs:
    /// nodes, triangles and ids).
    pub bytes: Option<usize>,
    /// Camera-style rays through the grid that hit something (a check that the structure
    /// answers, not a speed figure).
    pub hits: usize,
}

/// The grid of `count` copies of a model whose bounds are `lo..hi`: rows on the XZ plane,
/// 1.5 model sizes apart, each turned by a different angle about Y.
pub fn grid(count: usize, lo: Vec3, hi: Vec3) -> Vec<Affine3A> {
    let side = (count as f64).sqrt().ceil().max(1.0) as usize;
    let step = (hi - lo).max_element().max(1e-3) * 1.5;
    (0..count)
        .map(|i| {
            let (x, z) = ((i % side) as f32, (i / side) as f32);
            Affine3A::from_rotation_translation(
                Quat::from_rotation_y(i as f32 * 0.618_034 * std::f32::consts::TAU),
                Vec3::new(x * step, 0.0, z * step),
            )
        })
        .collect()
}

/// Rays from above the grid down onto it, `n × n` of them.
fn probe_rays(lo: Vec3, hi: Vec3, n: usize) -> Vec<accel::Ray> {
    let mut rays = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            let (u, v) = ((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            let target = Vec3::new(
                lo.x + (hi.x - lo.x) * u,
                0.5 * (lo.y + hi.y),
                lo.z + (hi.z - lo.z) * v,
            );
            let origin = target + Vec3::new(0.3, 1.0, 0.2) * (hi - lo).length().max(1.0);
            rays.push(accel::Ray::new(origin, target - origin));
        }
    }
    rays
}

/// Builds one layout and measures it.
fn measure(
    backend: BackendKind,
    layout: &'static str,
    copies: usize,
    meshes: &[TriangleMesh<'_>],
    options: BuildOptions,
    probe: &[accel::Ray],
) -> Result<InstancesRow, AccelError> {
    let start = Instant::now();
    let built = accel::build(backend, meshes, options)?;
    let build_seconds = start.elapsed().as_secs_f64();
    let hits = probe
        .iter()
        .filter(|r| built.intersect(r).is_some())
        .count();
    Ok(InstancesRow {
        backend,
        layout,
        copies,
        triangles: built.triangle_count(),
        build_seconds,
        bytes: built.memory_bytes(),
        hits,
    })
}

/// Measures both layouts on every backend; `progress` gets a line per build.
pub fn run(
    scene: &BenchScene,
    config: &InstancesConfig,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<InstancesRow>, AccelError> {
    let model: Vec<(&[Vec3], &[[u32; 3]])> = scene
        .meshes
        .iter()
        .filter(|m| m.instances.is_empty())
        .map(|m| (m.positions.as_slice(), m.indices.as_slice()))
        .collect();
    let mut points = model.iter().flat_map(|(p, _)| p.iter().copied());
    let Some(first) = points.next() else {
        return Ok(Vec::new());
    };
    let (lo, hi) = points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
    let transforms = grid(config.count, lo, hi);
    let placements: Vec<Placement> = transforms
        .iter()
        .filter_map(|m| Placement::new(*m, None))
        .collect();
    let placed: Vec<TriangleMesh<'_>> = model
        .iter()
        .map(|(positions, indices)| TriangleMesh {
            positions,
            indices,
            instances: &placements,
        })
        .collect();
    let flat_count = config.flat_count.min(config.count);
    let baked: Vec<(Vec<Vec3>, &[[u32; 3]])> = transforms[..flat_count]
        .iter()
        .flat_map(|m| {
            model.iter().map(move |(positions, indices)| {
                (
                    positions.iter().map(|p| m.transform_point3(*p)).collect(),
                    *indices,
                )
            })
        })
        .collect();
    let baked_meshes: Vec<TriangleMesh<'_>> = baked
        .iter()
        .map(|(positions, indices)| TriangleMesh {
            positions,
            indices,
            instances: &[],
        })
        .collect();
    let (glo, ghi) = placements
        .iter()
        .map(|p| p.bounds(lo, hi))
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
        .unwrap_or((lo, hi));
    let probe = probe_rays(glo, ghi, 64);
    let mut rows = Vec::new();
    for &backend in BackendKind::available() {
        for (layout, copies, meshes) in [
            ("placed", placements.len(), &placed),
            ("baked", flat_count, &baked_meshes),
        ] {
            progress(&format!(
                "glint bench instances: {backend}, {copies} {layout} copies"
            ));
            rows.push(measure(
                backend,
                layout,
                copies,
                meshes,
                config.options,
                &probe,
            )?);
        }
    }
    Ok(rows)
}

/// The rows as a table, with each baked layout's bytes scaled to the placed copy count.
pub fn table(rows: &[InstancesRow], count: usize) -> String {
    let mut out = String::from(
        "backend  layout  copies     triangles   build s        MiB  MiB at full count  hits\n",
    );
    for row in rows {
        let mib = |b: f64| b / (1024.0 * 1024.0);
        let bytes = row.bytes.map(|b| b as f64);
        let full = bytes.map(|b| b * count as f64 / row.copies.max(1) as f64);
        let shown = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.1}", mib(v)));
        out.push_str(&format!(
            "{:<8} {:<7} {:>6} {:>13} {:>9.3} {:>10} {:>18} {:>5}\n",
            row.backend.name(),
            row.layout,
            row.copies,
            row.triangles,
            row.build_seconds,
            shown(bytes),
            if row.layout == "baked" {
                shown(full)
            } else {
                shown(bytes)
            },
            row.hits
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placed_copies_cost_far_less_than_baked_ones_and_answer_the_same_probe() {
        let sphere = crate::procedural::displaced_sphere(3, 0.1, 3);
        let scene = BenchScene {
            name: "sphere".into(),
            camera: None,
            meshes: vec![sphere],
        };
        let config = InstancesConfig {
            count: 64,
            flat_count: 64,
            options: BuildOptions::default(),
        };
        let rows = run(&scene, &config, &mut |_| {}).unwrap();
        for pair in rows.chunks(2) {
            let (placed, baked) = (&pair[0], &pair[1]);
            assert_eq!(placed.triangles, baked.triangles);
            assert_eq!(placed.hits, baked.hits, "{:?}", placed.backend);
            assert!(placed.hits > 0);
            // obvhs reports exact bytes; Embree's monitor may see other threads' builds.
            if placed.backend == BackendKind::Bvh {
                let (p, b) = (placed.bytes.unwrap(), baked.bytes.unwrap());
                assert!(p * 8 < b, "placed {p} B vs baked {b} B");
            }
        }
        assert!(table(&rows, 64).contains("placed"));
    }
}
