//! Placed emitters sampled copy by copy: a mesh stored once and drawn at many placements
//! (`scene::Mesh::instances`) whose material emits.
//!
//! Storing a light per triangle per copy makes memory and the light-BVH build grow with the
//! copies. When every placement is a similarity (rotation, uniform scale `s`, mirror,
//! translation), a copy's triangles keep their relative areas (each scaled by `s²`) and their
//! relative emitted powers, so one choice table serves every copy:
//!
//! ```text
//! P(copy c, triangle t | p) = P_sel(c | p) · Φ_t / Φ,    Φ = Σ_t Φ_t (object space)
//! ```
//!
//! `P_sel` is the scene's light selector (power or light BVH) over the copies as whole
//! entries, each with its world bounds, its normals' cone and power `s²·Φ`. The point on the
//! chosen triangle is then sampled exactly as for any other triangle light, on the triangle
//! carried to world space. `pdf` recomputes the same product, so the estimator stays unbiased;
//! what is lost is only the light BVH's spatial choice *within* a copy. A placed mesh with a
//! non-similar placement keeps a light per triangle per copy (`area`).

use super::area::TriangleLight;
use super::light_bvh::{ClusterBounds, normal_cone};
use crate::accel::Placement;
use crate::sampling::distribution::Distribution1D;
use glam::Vec3;

/// Relative tolerance on a placement's columns being orthogonal and of equal length.
const SIMILARITY_TOLERANCE: f32 = 1e-4;

/// `s²` of a similarity placement (its area scale), or `None` for any other.
pub fn area_scale(placement: &Placement) -> Option<f32> {
    let m = placement.linear();
    let (a, b, c) = (m.x_axis, m.y_axis, m.z_axis);
    let s2 = a.length_squared();
    if !(s2 > 0.0 && s2.is_finite()) {
        return None;
    }
    let close = |x: f32, y: f32| (x - y).abs() <= SIMILARITY_TOLERANCE * s2;
    (close(b.length_squared(), s2)
        && close(c.length_squared(), s2)
        && close(a.dot(b), 0.0)
        && close(b.dot(c), 0.0)
        && close(c.dot(a), 0.0))
    .then_some(s2)
}

/// One placed emissive mesh sampled copy by copy.
#[derive(Clone, Debug)]
pub struct Cluster {
    /// Its glowing triangles in object space (`instance` 0).
    lights: Vec<TriangleLight>,
    /// Per triangle of the mesh, its index in `lights` (`u32::MAX`: dark, not stored).
    local: Vec<u32>,
    /// Chooses among `lights` by object-space power.
    choice: Distribution1D,
    /// `Φ`, the object-space power of all its triangles.
    power: f32,
    copies: Vec<Placement>,
    /// `s²` per copy.
    area_scales: Vec<f32>,
    /// Object-space bounds and normal cone, for the light BVH.
    lo: Vec3,
    hi: Vec3,
    cone: (Vec3, f32),
    two_sided: bool,
}

impl Cluster {
    /// The cluster of a placed mesh whose object-space triangle lights are `triangles` (one
    /// per mesh triangle, dark ones included), or `None` when some placement is not a
    /// similarity or nothing glows.
    pub fn new(triangles: Vec<TriangleLight>, copies: &[Placement]) -> Option<Self> {
        let area_scales: Vec<f32> = copies.iter().map(area_scale).collect::<Option<_>>()?;
        let mut local = Vec::with_capacity(triangles.len());
        let mut lights = Vec::new();
        for light in triangles {
            if light.power() > 0.0 && light.power().is_finite() {
                // Fits: a mesh has fewer than u32::MAX triangles.
                local.push(lights.len() as u32);
                lights.push(light);
            } else {
                local.push(u32::MAX);
            }
        }
        let powers: Vec<f32> = lights.iter().map(TriangleLight::power).collect();
        let choice = Distribution1D::new(&powers)?;
        let power = powers.iter().sum();
        let cone = normal_cone(&lights)?;
        let (lo, hi) = lights.iter().flat_map(TriangleLight::vertices).fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        );
        Some(Self {
            two_sided: lights.iter().any(|l| l.two_sided),
            lights,
            local,
            choice,
            power,
            copies: copies.to_vec(),
            area_scales,
            lo,
            hi,
            cone,
        })
    }

    /// Number of copies.
    pub fn copies(&self) -> usize {
        self.copies.len()
    }

    /// The emitted power of copy `copy`, `s²·Φ`.
    pub fn copy_power(&self, copy: usize) -> f32 {
        self.area_scales.get(copy).map_or(0.0, |s2| s2 * self.power)
    }

    /// Copy `copy` as one leaf of the light BVH.
    pub fn copy_bounds(&self, copy: usize) -> Option<ClusterBounds> {
        let placement = self.copies.get(copy)?;
        let (min, max) = placement.bounds(self.lo, self.hi);
        let axis = placement.normal(self.cone.0).normalize_or_zero();
        Some(ClusterBounds {
            min,
            max,
            // A similarity keeps angles, so the cone keeps its half-angle.
            axis: if axis == Vec3::ZERO { Vec3::Z } else { axis },
            cos_theta: if axis == Vec3::ZERO {
                -1.0
            } else {
                self.cone.1
            },
            two_sided: self.two_sided,
            cos_theta_e: 0.0,
            power: self.copy_power(copy),
        })
    }

    /// Chooses a glowing triangle with the uniform `u`: `(index in the cluster, probability)`.
    #[inline]
    pub fn choose(&self, u: f32) -> (usize, f32) {
        let (local, pmf, _) = self.choice.sample_discrete(u);
        (local, pmf)
    }

    /// The cluster index and choice probability of the mesh's triangle `triangle`, if it
    /// glows.
    #[inline]
    pub fn local_of(&self, triangle: u32) -> Option<(usize, f32)> {
        match *self.local.get(triangle as usize)? {
            u32::MAX => None,
            local => Some((local as usize, self.choice.pmf(local as usize))),
        }
    }

    /// Triangle `local` of copy `copy` as a world-space light (its front side carried over
    /// by the placement, as the ray backends carry the geometric normal).
    #[inline]
    pub fn world_light(&self, copy: usize, local: usize) -> Option<TriangleLight> {
        let (placement, s2) = (self.copies.get(copy)?, *self.area_scales.get(copy)?);
        let light = self.lights.get(local)?;
        Some(TriangleLight {
            p0: placement.point(light.p0),
            e1: placement.vector(light.e1),
            e2: placement.vector(light.e2),
            normal: placement.normal(light.normal).normalize_or_zero(),
            area: light.area * s2,
            // Fits: copies are counted in u32 by the scene's placements.
            instance: copy as u32,
            ..*light
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Affine3A, Mat4, Quat};

    fn triangle(p0: Vec3, e1: Vec3, e2: Vec3, le: f32, t: u32) -> TriangleLight {
        let cross = e1.cross(e2);
        TriangleLight {
            p0,
            e1,
            e2,
            normal: cross.normalize(),
            area: 0.5 * cross.length(),
            le: Vec3::splat(le),
            two_sided: false,
            mesh: 3,
            instance: 0,
            triangle: t,
        }
    }

    #[test]
    fn only_similarities_make_clusters_and_world_lights_match_baked_triangles() {
        let tris = vec![
            triangle(Vec3::ZERO, Vec3::X, Vec3::Y, 2.0, 0),
            triangle(Vec3::Z, Vec3::X, Vec3::Y, 0.0, 1),
            triangle(Vec3::ONE, Vec3::Y * 2.0, Vec3::Z, 1.0, 2),
        ];
        let similar = Mat4::from_scale_rotation_translation(
            Vec3::new(-2.0, 2.0, 2.0),
            Quat::from_rotation_y(0.6),
            Vec3::new(1.0, 2.0, 3.0),
        );
        let place = |m: Mat4| Placement::new(Affine3A::from_mat4(m), None).unwrap();
        let stretched = place(Mat4::from_scale(Vec3::new(1.0, 2.0, 1.0)));
        assert!(Cluster::new(tris.clone(), &[place(similar), stretched]).is_none());
        let cluster = Cluster::new(tris.clone(), &[place(Mat4::IDENTITY), place(similar)]).unwrap();
        assert_eq!(cluster.local_of(1), None, "dark triangles are not stored");
        let (l2, q2) = cluster.local_of(2).unwrap();
        let (_, q0) = cluster.local_of(0).unwrap();
        assert!((q0 + q2 - 1.0).abs() < 1e-6);
        assert!((q0 / q2 - tris[0].power() / tris[2].power()).abs() < 1e-5);
        assert!((cluster.copy_power(1) - 4.0 * (tris[0].power() + tris[2].power())).abs() < 1e-3);
        let w = cluster.world_light(1, l2).unwrap();
        let [a, b, c] = tris[2].vertices().map(|v| similar.transform_point3(v));
        let baked_area = 0.5 * (b - a).cross(c - a).length();
        assert!((w.area - baked_area).abs() < 1e-4 * baked_area);
        for (x, y) in w.vertices().iter().zip([a, b, c]) {
            assert!(x.distance(y) < 1e-5);
        }
        // The mirror re-winds the world triangle; the light's normal stays the carried front.
        assert!(w.normal.dot((b - a).cross(c - a)) < 0.0);
        assert_eq!((w.instance, w.triangle), (1, 2));
        let bounds = cluster.copy_bounds(1).unwrap();
        for v in w.vertices() {
            assert!(v.cmpge(bounds.min - 1e-5).all() && v.cmple(bounds.max + 1e-5).all());
        }
    }
}
