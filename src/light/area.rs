//! STUB (replaced by the light-sampling branch): emissive triangles chosen by power.

use glam::{Vec2, Vec3};

/// One emissive triangle.
#[derive(Clone, Copy, Debug)]
struct Emitter {
    mesh: u32,
    triangle: u32,
    p: [Vec3; 3],
    n: Vec3,
    area: f32,
    two_sided: bool,
}

/// The scene's emissive triangles.
#[derive(Clone, Debug, Default)]
pub struct AreaLights {
    emitters: Vec<Emitter>,
    cdf: Vec<f32>,
    index: std::collections::HashMap<(u32, u32), usize>,
}

/// A point drawn on an emitter.
#[derive(Clone, Copy, Debug)]
pub struct AreaSample {
    /// Mesh index.
    pub mesh: u32,
    /// Triangle index.
    pub triangle: u32,
    /// Barycentrics.
    pub barycentrics: [f32; 3],
    /// The point.
    pub point: Vec3,
    /// Unit geometric normal of the triangle's winding.
    pub normal: Vec3,
    /// Unit direction from the shading point to `point`.
    pub wi: Vec3,
    /// Distance to `point`.
    pub distance: f32,
    /// Solid-angle density including the selection probability.
    pub pdf: f32,
}

impl AreaLights {
    /// Builds from the scene: `le(mesh, tri)` average emitted radiance, `two_sided(mesh)`.
    pub fn new(
        scene: &crate::scene::Scene,
        le: impl Fn(usize, usize) -> Vec3,
        two_sided: impl Fn(usize) -> bool,
    ) -> Self {
        let mut s = Self::default();
        let mut total = 0.0;
        for (mi, mesh) in scene.meshes.iter().enumerate() {
            for (ti, tri) in mesh.indices.iter().enumerate() {
                let l = le(mi, ti);
                if l.max_element() <= 0.0 {
                    continue;
                }
                let p = tri.map(|i| mesh.positions[i as usize]);
                let c = (p[1] - p[0]).cross(p[2] - p[0]);
                let area = 0.5 * c.length();
                if area <= 0.0 {
                    continue;
                }
                let ts = two_sided(mi);
                let power = (l.x + l.y + l.z) * area * if ts { 2.0 } else { 1.0 };
                total += power;
                s.index.insert((mi as u32, ti as u32), s.emitters.len());
                s.emitters.push(Emitter {
                    mesh: mi as u32,
                    triangle: ti as u32,
                    p,
                    n: c.normalize(),
                    area,
                    two_sided: ts,
                });
                s.cdf.push(total);
            }
        }
        for c in &mut s.cdf {
            *c /= total;
        }
        s
    }
    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.emitters.is_empty()
    }
    fn pmf(&self, i: usize) -> f32 {
        self.cdf[i] - if i == 0 { 0.0 } else { self.cdf[i - 1] }
    }
    /// Draws a point.
    pub fn sample(&self, p: Vec3, _n: Vec3, u_select: f32, u: Vec2) -> Option<AreaSample> {
        let i = self.cdf.partition_point(|&c| c <= u_select).min(self.emitters.len() - 1);
        let e = &self.emitters[i];
        let su = u.x.sqrt();
        let b = [1.0 - su, su * (1.0 - u.y), su * u.y];
        let point = e.p[0] * b[0] + e.p[1] * b[1] + e.p[2] * b[2];
        let d = point - p;
        let dist2 = d.length_squared();
        let distance = dist2.sqrt();
        let wi = d / distance;
        let cos = e.n.dot(-wi).abs();
        if cos <= 0.0 || !wi.is_finite() {
            return None;
        }
        Some(AreaSample {
            mesh: e.mesh,
            triangle: e.triangle,
            barycentrics: b,
            point,
            normal: e.n,
            wi,
            distance,
            pdf: self.pmf(i) * dist2 / (e.area * cos),
        })
    }
    /// Density of `sample` choosing this point.
    pub fn pdf(&self, p: Vec3, _n: Vec3, mesh: u32, triangle: u32, point: Vec3, _ln: Vec3) -> f32 {
        let Some(&i) = self.index.get(&(mesh, triangle)) else {
            return 0.0;
        };
        let e = &self.emitters[i];
        let d = point - p;
        let dist2 = d.length_squared();
        let cos = e.n.dot(d.normalize()).abs();
        if cos <= 0.0 {
            return 0.0;
        }
        let _ = e.two_sided;
        self.pmf(i) * dist2 / (e.area * cos)
    }
}
