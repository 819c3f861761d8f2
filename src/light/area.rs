//! Area lights: every triangle of an emissive mesh, sampled for next-event estimation.
//!
//! # Emission
//!
//! Triangle `k` emits the constant radiance `Le_k` (W/(m²·sr)) from its front face (the side
//! its counter-clockwise winding faces, unit normal `n_l = normalize((p₁ − p₀) × (p₂ − p₀))`),
//! or from both faces when two-sided. For a textured emitter `Le_k` is the caller's average of
//! the emission over the triangle: it only steers the sampling (any positive value would keep
//! the estimator unbiased), while the integrator evaluates the true emission at the sampled
//! point. Its power is
//!
//! ```text
//! Φ_k = π · A_k · Y(Le_k) · (2 if two-sided else 1)
//! ```
//!
//! with `A_k` the area and `Y` the Rec. 709 luminance.
//!
//! # Sampling
//!
//! A light is chosen with probability `P(k)` by the [`LightSelector`]: in proportion to
//! `Φ_k` (a [`Distribution1D`]) or, for many lights, by the light BVH of
//! [`light_bvh`](super::light_bvh), which also weighs distance and orientation from the shading
//! point. A point `x` on it is then uniform by area (density `1/A_k`), and the density of the
//! direction `ω = (x − p)/|x − p|` at the shading point `p` is, with respect to solid angle,
//!
//! ```text
//! p(ω) = P(k) · |x − p|² / (A_k · |cos θ_l|),     cos θ_l = n_l · (−ω)
//! ```
//!
//! Large or near triangles are instead sampled uniformly over the solid angle they subtend
//! (Arvo 1995, [`spherical_triangle`]) when that solid angle Ω lies in
//! [`SOLID_ANGLE_RANGE`]: then `p(ω) = P(k) / Ω`, which removes the variance of
//! `|x − p|² / |cos θ_l|` close to big emitters. Tiny ones (where the spherical construction
//! loses precision, and area sampling is nearly uniform in solid angle anyway) and nearly
//! full-hemisphere ones stay with area sampling. The choice depends only on `p` and the
//! triangle, so [`AreaLights::pdf`] makes the same one.
//!
//! [`AreaLights::pdf`] returns the same density for a point a BSDF-sampled ray hit, for MIS.
//! Points on the back of a one-sided emitter emit nothing: [`AreaLights::sample`] returns
//! `None` for them, and `pdf` returns 0 there.

use super::light_bvh::{ClusterBounds, LightBvh};
use super::placed_emitters::Cluster;
use crate::accel::Placement;
use crate::color::LUMINANCE;
use crate::sampling::distribution::Distribution1D;
use crate::sampling::triangle::{spherical_triangle, spherical_triangle_area, uniform_triangle};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The solid angles (sr) for which a triangle is sampled by solid angle rather than by area.
pub const SOLID_ANGLE_RANGE: (f32, f32) = (3e-4, 6.0);

/// One emissive mesh as the constructor sees it: its triangles, where they are drawn, and
/// whether both faces emit. A mesh that emits nothing is passed with no triangles (so mesh
/// indices stay those of the scene).
#[derive(Clone, Copy, Debug)]
pub struct EmitterMesh<'a> {
    /// Vertex positions: world space, or object space with `instances`.
    pub positions: &'a [Vec3],
    /// Three vertex indices per triangle, counter-clockwise front faces.
    pub indices: &'a [[u32; 3]],
    /// Whether the back face emits too (glTF `doubleSided`).
    pub two_sided: bool,
    /// Where the mesh is drawn (see [`crate::scene::Mesh::instances`]); empty: once, as given.
    /// Each copy's triangles become lights of their own, in world space; of a placed mesh
    /// only the triangles whose average emission is non-zero are stored, so that a thousand
    /// copies of a mostly dark emitter do not hold a thousand copies of its dark triangles
    /// (a BSDF-sampled ray still finds those, with MIS weight 1, exactly as it finds a
    /// stored zero-power triangle).
    pub instances: &'a [Placement],
}

/// An emissive mesh that cannot be used as a light.
#[derive(Debug, thiserror::Error)]
pub enum AreaLightError {
    /// A triangle names a vertex the mesh does not have.
    #[error(
        "area light: mesh {mesh}, triangle {triangle}: vertex index {index} is out of range ({vertices} vertices); fix the mesh's index accessor"
    )]
    Index {
        /// Mesh index.
        mesh: usize,
        /// Triangle index in the mesh.
        triangle: usize,
        /// The bad vertex index.
        index: u32,
        /// Vertices the mesh has.
        vertices: usize,
    },
    /// The emission of a triangle is negative or not finite.
    #[error(
        "area light: mesh {mesh}, triangle {triangle}: emitted radiance {radiance} must be finite and non-negative; fix the material's emissiveFactor, KHR_materials_emissive_strength or emissive texture"
    )]
    Radiance {
        /// Mesh index.
        mesh: usize,
        /// Triangle index in the mesh.
        triangle: usize,
        /// The value given.
        radiance: Vec3,
    },
    /// More triangles than a `u32` can index.
    #[error("area light: {count} emissive triangles are more than 2³² − 1")]
    TooMany {
        /// How many.
        count: usize,
    },
}

/// One emissive triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleLight {
    /// Vertex 0.
    pub p0: Vec3,
    /// `p₁ − p₀`.
    pub e1: Vec3,
    /// `p₂ − p₀`.
    pub e2: Vec3,
    /// Unit geometric normal of the winding (zero for a degenerate triangle).
    pub normal: Vec3,
    /// Area (m²).
    pub area: f32,
    /// Average emitted radiance.
    pub le: Vec3,
    /// Whether both faces emit.
    pub two_sided: bool,
    /// Mesh index.
    pub mesh: u32,
    /// Which copy of a placed mesh (0 otherwise).
    pub instance: u32,
    /// Triangle index in the mesh.
    pub triangle: u32,
}

impl TriangleLight {
    /// `Φ = π A Y(Le)`, doubled when two-sided; 0 for a degenerate triangle.
    pub fn power(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        PI * self.area * self.le.dot(LUMINANCE) * sides
    }

    /// The centroid.
    pub fn centroid(&self) -> Vec3 {
        self.p0 + (self.e1 + self.e2) / 3.0
    }

    /// The three vertices.
    pub fn vertices(&self) -> [Vec3; 3] {
        [self.p0, self.p0 + self.e1, self.p0 + self.e2]
    }
}

/// A point sampled on an area light, seen from a shading point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaSample {
    /// Mesh index (as passed to the constructor: the scene's).
    pub mesh: u32,
    /// Which copy of a placed mesh (0 otherwise).
    pub instance: u32,
    /// Triangle index in the mesh.
    pub triangle: u32,
    /// Barycentrics of `point` for vertices 0, 1, 2 (to evaluate an emissive texture).
    pub barycentrics: [f32; 3],
    /// The point on the light.
    pub point: Vec3,
    /// Unit geometric normal of the triangle's winding.
    pub normal: Vec3,
    /// Unit direction from the shading point to `point`.
    pub wi: Vec3,
    /// Distance from the shading point to `point`.
    pub distance: f32,
    /// Density of `wi` with respect to solid angle at the shading point, the light's selection
    /// probability included.
    pub pdf: f32,
    /// The triangle's average emitted radiance (exact for an untextured emitter).
    pub le: Vec3,
}

/// How a light is chosen.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum SelectionMode {
    /// In proportion to power, independent of the shading point.
    #[default]
    Power,
    /// The light BVH (importance from power, distance and orientation); the better choice for
    /// many emitters (see docs/lights.md for the measured gain).
    Bvh,
}

/// The light-selection strategy of an [`AreaLights`].
#[derive(Clone, Debug)]
pub enum LightSelector {
    /// A power CDF.
    Power(Distribution1D),
    /// A light BVH.
    Bvh(LightBvh),
}

/// Every emissive triangle of a scene, with the tables to sample them.
#[derive(Clone, Debug)]
pub struct AreaLights {
    lights: Vec<TriangleLight>,
    /// Per mesh, the index of its first copy in `copy_first`, or `u32::MAX` when it has no
    /// lights.
    mesh_first: Vec<u32>,
    /// Per copy of each mesh, the index of its first triangle in `lights`.
    copy_first: Vec<u32>,
    /// Per placed mesh, each triangle's offset within a copy's lights (`u32::MAX`: not
    /// stored); `None` for a mesh drawn once, which stores all its triangles (zero-power
    /// ones with probability 0), so that triangle `t` is at offset `t`.
    stored: Vec<Option<Vec<u32>>>,
    /// Placed emitters sampled copy by copy (see [`super::placed_emitters`]).
    clusters: Vec<Cluster>,
    /// Per mesh, its index in `clusters`, or `u32::MAX`.
    mesh_cluster: Vec<u32>,
    /// Per cluster, the selector entry of its copy 0 (entries `lights.len()..` are copies).
    cluster_first: Vec<u32>,
    /// Per selector entry past `lights.len()`: (cluster, copy).
    copy_entries: Vec<(u32, u32)>,
    /// `None` when no triangle emits.
    selector: Option<LightSelector>,
    /// The bounds of every light together (for choosing between these and other lights);
    /// with a BVH selector its root holds the same.
    bounds: Option<ClusterBounds>,
    /// Whether triangles in [`SOLID_ANGLE_RANGE`] are sampled by solid angle.
    solid_angle_sampling: bool,
}

impl AreaLights {
    /// Builds the lights from `meshes`, where `le(mesh, triangle)` is the average emitted
    /// radiance of that triangle (called once per triangle of a mesh with triangles),
    /// choosing lights by power.
    pub fn new(
        meshes: &[EmitterMesh<'_>],
        le: impl Fn(u32, u32) -> Vec3,
    ) -> Result<Self, AreaLightError> {
        Self::with_selection(meshes, le, SelectionMode::Power)
    }

    /// As [`new`](Self::new), choosing lights by `mode`.
    pub fn with_selection(
        meshes: &[EmitterMesh<'_>],
        le: impl Fn(u32, u32) -> Vec3,
        mode: SelectionMode,
    ) -> Result<Self, AreaLightError> {
        let count: usize = meshes
            .iter()
            .map(|m| m.indices.len().saturating_mul(m.instances.len().max(1)))
            .fold(0usize, usize::saturating_add);
        if meshes.len() >= u32::MAX as usize {
            return Err(AreaLightError::TooMany { count });
        }
        let mut lights = Vec::new();
        let mut mesh_first = Vec::with_capacity(meshes.len());
        let mut copy_first = Vec::new();
        let mut stored = Vec::with_capacity(meshes.len());
        let mut clusters: Vec<Cluster> = Vec::new();
        let mut mesh_cluster: Vec<u32> = Vec::new();
        for (m, mesh) in meshes.iter().enumerate() {
            if mesh.indices.is_empty() {
                mesh_first.push(u32::MAX);
                stored.push(None);
                continue;
            }
            let mut corners = Vec::with_capacity(mesh.indices.len());
            let mut radiances = Vec::with_capacity(mesh.indices.len());
            for (t, tri) in mesh.indices.iter().enumerate() {
                let vertex = |i: u32| {
                    mesh.positions
                        .get(i as usize)
                        .copied()
                        .ok_or(AreaLightError::Index {
                            mesh: m,
                            triangle: t,
                            index: i,
                            vertices: mesh.positions.len(),
                        })
                };
                corners.push([vertex(tri[0])?, vertex(tri[1])?, vertex(tri[2])?]);
                let radiance = le(m as u32, t as u32);
                if !(radiance.is_finite() && radiance.min_element() >= 0.0) {
                    return Err(AreaLightError::Radiance {
                        mesh: m,
                        triangle: t,
                        radiance,
                    });
                }
                radiances.push(radiance);
            }
            // A placed mesh whose placements are all similarities is sampled copy by copy.
            if !mesh.instances.is_empty() {
                let object: Vec<TriangleLight> = corners
                    .iter()
                    .zip(&radiances)
                    .enumerate()
                    .map(|(t, (&[p0, p1, p2], &le))| {
                        triangle_light(p0, p1, p2, le, mesh.two_sided, m as u32, 0, t as u32)
                    })
                    .collect();
                if let Some(cluster) = Cluster::new(object, mesh.instances) {
                    mesh_first.push(u32::MAX);
                    stored.push(None);
                    mesh_cluster.resize(m, u32::MAX);
                    // Fits: fewer clusters than meshes, and meshes.len() < u32::MAX.
                    mesh_cluster.push(clusters.len() as u32);
                    clusters.push(cluster);
                    continue;
                }
            }
            // Other placed meshes keep only their glowing triangles; see
            // `EmitterMesh::instances`.
            let map = (!mesh.instances.is_empty()).then(|| {
                let mut next = 0u32;
                radiances
                    .iter()
                    .map(|r| {
                        if *r == Vec3::ZERO {
                            u32::MAX
                        } else {
                            next += 1;
                            next - 1
                        }
                    })
                    .collect::<Vec<u32>>()
            });
            let per_copy = match &map {
                Some(map) => map.iter().filter(|&&o| o != u32::MAX).count(),
                None => mesh.indices.len(),
            };
            let copies = mesh.instances.len().max(1);
            let total = lights.len().saturating_add(per_copy.saturating_mul(copies));
            if total >= u32::MAX as usize {
                return Err(AreaLightError::TooMany { count: total });
            }
            lights.reserve(per_copy * copies);
            // Fits: copy_first.len() ≤ lights.len() < u32::MAX (each copy has a light).
            mesh_first.push(copy_first.len() as u32);
            for copy in 0..copies {
                let placement = mesh.instances.get(copy);
                copy_first.push(lights.len() as u32);
                for (t, (&[p0, p1, p2], &radiance)) in corners.iter().zip(&radiances).enumerate() {
                    if map.as_ref().is_some_and(|map| map[t] == u32::MAX) {
                        continue;
                    }
                    let [p0, p1, p2] = match placement {
                        Some(placement) => [p0, p1, p2].map(|p| placement.point(p)),
                        None => [p0, p1, p2],
                    };
                    let mut light = triangle_light(
                        p0,
                        p1,
                        p2,
                        radiance,
                        mesh.two_sided,
                        m as u32,
                        copy as u32,
                        t as u32,
                    );
                    // A mirroring placement turns the winding: the emitting side is the
                    // object-space front, carried over, not the world-space winding's.
                    if placement.is_some_and(Placement::mirrored) {
                        light.normal = -light.normal;
                    }
                    lights.push(light);
                }
            }
            stored.push(map);
        }
        mesh_cluster.resize(meshes.len(), u32::MAX);
        let mut powers: Vec<f32> = lights.iter().map(TriangleLight::power).collect();
        let mut cluster_first = Vec::with_capacity(clusters.len());
        let mut copy_entries = Vec::new();
        for (k, cluster) in clusters.iter().enumerate() {
            let first = lights.len() + copy_entries.len();
            if first.saturating_add(cluster.copies()) >= u32::MAX as usize {
                return Err(AreaLightError::TooMany { count: first });
            }
            cluster_first.push(first as u32);
            for copy in 0..cluster.copies() {
                copy_entries.push((k as u32, copy as u32));
                powers.push(cluster.copy_power(copy));
            }
        }
        let bounds = lights
            .iter()
            .zip(&powers)
            .filter(|(l, w)| **w > 0.0 && w.is_finite() && l.area > 0.0)
            .map(|(l, &w)| triangle_bounds(l, w))
            .chain(
                copy_entries
                    .iter()
                    .zip(&powers[lights.len()..])
                    .filter(|(_, w)| **w > 0.0 && w.is_finite())
                    .filter_map(|(&(k, c), _)| clusters[k as usize].copy_bounds(c as usize)),
            )
            .reduce(|a, b| a.union(&b));
        let selector = match mode {
            SelectionMode::Power => Distribution1D::new(&powers).map(LightSelector::Power),
            SelectionMode::Bvh => {
                let bounds: Vec<_> = copy_entries
                    .iter()
                    .filter_map(|&(k, c)| clusters[k as usize].copy_bounds(c as usize))
                    .collect();
                // Every copy has bounds (its placement exists), so entries stay aligned.
                debug_assert_eq!(bounds.len(), copy_entries.len());
                // Past the tree's MAX_ENTRIES (no tree), the power CDF still chooses.
                LightBvh::with_clusters(&lights, &powers[..lights.len()], &bounds)
                    .map(LightSelector::Bvh)
                    .or_else(|| Distribution1D::new(&powers).map(LightSelector::Power))
            }
        };
        Ok(Self {
            lights,
            mesh_first,
            copy_first,
            stored,
            clusters,
            mesh_cluster,
            cluster_first,
            copy_entries,
            selector,
            bounds,
            solid_angle_sampling: true,
        })
    }

    /// Builds the lights of a scene: meshes whose material has a non-zero emissive factor,
    /// two-sided when the material is double-sided; `le(mesh, triangle)` gives each
    /// triangle's average emission (the factor times the emissive texture's average over it).
    pub fn from_scene(
        scene: &crate::scene::Scene,
        le: impl Fn(u32, u32) -> Vec3,
        mode: SelectionMode,
    ) -> Result<Self, AreaLightError> {
        let meshes: Vec<EmitterMesh<'_>> = scene
            .meshes
            .iter()
            .map(|mesh| {
                let material = scene.materials.get(mesh.material);
                let emits = material.is_some_and(|m| m.emissive.max_element() > 0.0);
                EmitterMesh {
                    positions: &mesh.positions,
                    indices: if emits { &mesh.indices } else { &[] },
                    two_sided: material.is_some_and(|m| m.double_sided),
                    instances: &mesh.instances,
                }
            })
            .collect();
        Self::with_selection(&meshes, le, mode)
    }

    /// An upper bound on what these lights together deliver at `p` with normal `n` (zero if
    /// unknown), in the light BVH's importance units: how a light sampler weighs them against
    /// other lights. Positive wherever some light can reach `p`.
    #[inline]
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        match (&self.selector, &self.bounds) {
            (Some(LightSelector::Bvh(bvh)), _) => bvh.importance(p, n),
            (Some(_), Some(bounds)) => bounds.importance(p, n),
            _ => 0.0,
        }
    }

    /// Whether nothing emits (no light to sample; an integrator skips next-event estimation
    /// for area lights).
    pub fn is_empty(&self) -> bool {
        self.selector.is_none()
    }

    /// The stored triangles (every triangle of each emissive mesh drawn once, zero-power ones
    /// included, and the glowing triangles of each copy of a placed emitter that is not
    /// sampled copy by copy; see [`super::placed_emitters`]).
    pub fn lights(&self) -> &[TriangleLight] {
        &self.lights
    }

    /// Total emitted power `Σ Φ_k` (W), for choosing between area lights and other lights.
    pub fn total_power(&self) -> f32 {
        let clustered: f32 = self
            .copy_entries
            .iter()
            .map(|&(k, c)| self.clusters[k as usize].copy_power(c as usize))
            .sum();
        self.lights.iter().map(TriangleLight::power).sum::<f32>() + clustered
    }

    /// The light index of triangle `triangle` of copy `instance` of mesh `mesh`, if it is
    /// stored.
    #[inline]
    pub fn light_index(&self, mesh: u32, instance: u32, triangle: u32) -> Option<usize> {
        let slot = *self.mesh_first.get(mesh as usize)?;
        if slot == u32::MAX {
            return None;
        }
        let first = *self.copy_first.get(slot as usize + instance as usize)?;
        let offset = match self.stored.get(mesh as usize)? {
            Some(map) => match *map.get(triangle as usize)? {
                u32::MAX => return None,
                offset => offset,
            },
            None => triangle,
        };
        let index = first as usize + offset as usize;
        let light = self.lights.get(index)?;
        // Guards against an index past the end of its own mesh or copy.
        (light.mesh == mesh && light.instance == instance && light.triangle == triangle)
            .then_some(index)
    }

    /// The probability that the selector chooses light `index` for the shading point `p` with
    /// normal `n`.
    #[inline]
    pub fn selection_pmf(&self, p: Vec3, n: Vec3, index: usize) -> f32 {
        match &self.selector {
            None => 0.0,
            Some(LightSelector::Power(d)) => d.pmf(index),
            Some(LightSelector::Bvh(bvh)) => bvh.pmf(p, n, index),
        }
    }

    /// Chooses a light for the shading point `p` (normal `n`, zero if unknown) with `u`:
    /// `(index, probability)`. Indices from `lights().len()` on are copies of placed
    /// emitters, sampled as a whole.
    #[inline]
    pub fn select(&self, p: Vec3, n: Vec3, u: f32) -> Option<(usize, f32)> {
        self.select_with_rest(p, n, u).map(|(i, pmf, _)| (i, pmf))
    }

    /// As [`select`](Self::select), with `u` rescaled within the chosen entry's share.
    #[inline]
    fn select_with_rest(&self, p: Vec3, n: Vec3, u: f32) -> Option<(usize, f32, f32)> {
        match self.selector.as_ref()? {
            LightSelector::Power(d) => Some(d.sample_discrete(u)),
            LightSelector::Bvh(bvh) => bvh.sample_with_rest(p, n, u),
        }
    }

    /// The light a selector entry names with the rest `u` of its choice: a stored light, or
    /// a placed emitter's copy's triangle carried to world space, with the probability of
    /// the triangle within the copy.
    #[inline]
    fn entry_light(
        &self,
        index: usize,
        u: f32,
    ) -> Option<(std::borrow::Cow<'_, TriangleLight>, f32)> {
        if let Some(light) = self.lights.get(index) {
            return Some((std::borrow::Cow::Borrowed(light), 1.0));
        }
        let &(k, copy) = self.copy_entries.get(index - self.lights.len())?;
        let cluster = self.clusters.get(k as usize)?;
        let (local, q) = cluster.choose(u);
        Some((
            std::borrow::Cow::Owned(cluster.world_light(copy as usize, local)?),
            q,
        ))
    }

    /// Samples a point on a light for the shading point `p` with normal `n` (zero for
    /// "unknown"): `u_select` chooses the light, `u` the point on it. `None` when nothing
    /// emits, the chosen point faces away (one-sided) or coincides with `p`.
    #[inline]
    pub fn sample(&self, p: Vec3, n: Vec3, u_select: f32, u: Vec2) -> Option<AreaSample> {
        let (index, pmf, rest) = self.select_with_rest(p, n, u_select)?;
        let (light, q) = self.entry_light(index, rest)?;
        let light = light.as_ref();
        let pmf = pmf * q;
        if pmf <= 0.0 {
            return None;
        }
        if let Some((dirs, omega)) = self.spherical(light, p) {
            // Facing away from p: no emission toward it.
            if !light.two_sided && light.normal.dot(p - light.p0) <= 0.0 {
                return None;
            }
            let wi = spherical_triangle(dirs[0], dirs[1], dirs[2], u)?;
            let denom = light.normal.dot(wi);
            let t = light.normal.dot(light.p0 - p) / denom;
            if !(t > 0.0 && t.is_finite()) {
                return None;
            }
            let point = p + t * wi;
            return Some(AreaSample {
                mesh: light.mesh,
                instance: light.instance,
                triangle: light.triangle,
                barycentrics: barycentrics(light, point),
                point,
                normal: light.normal,
                wi,
                distance: t,
                pdf: pmf / omega,
                le: light.le,
            });
        }
        let b = uniform_triangle(u);
        let point = light.p0 + b[1] * light.e1 + b[2] * light.e2;
        let d = point - p;
        let dist2 = d.length_squared();
        if !(dist2 > 0.0 && dist2.is_finite()) {
            return None;
        }
        let distance = dist2.sqrt();
        let wi = d / distance;
        let cos_l = -wi.dot(light.normal);
        if cos_l == 0.0 || (!light.two_sided && cos_l < 0.0) {
            return None;
        }
        Some(AreaSample {
            mesh: light.mesh,
            instance: light.instance,
            triangle: light.triangle,
            barycentrics: b,
            point,
            normal: light.normal,
            wi,
            distance,
            pdf: pmf * dist2 / (light.area * cos_l.abs()),
            le: light.le,
        })
    }

    /// Turns solid-angle sampling of large or near triangles on (the default) or off (area
    /// sampling only; for measuring what it buys).
    pub fn with_solid_angle_sampling(mut self, on: bool) -> Self {
        self.solid_angle_sampling = on;
        self
    }

    /// The unit directions from `p` to the vertices and the solid angle, when `light` is to be
    /// sampled by solid angle from `p`.
    #[inline]
    fn spherical(&self, light: &TriangleLight, p: Vec3) -> Option<([Vec3; 3], f32)> {
        if !self.solid_angle_sampling {
            return None;
        }
        let [a, b, c] = light.vertices();
        let dirs = [
            (a - p).try_normalize()?,
            (b - p).try_normalize()?,
            (c - p).try_normalize()?,
        ];
        let omega = spherical_triangle_area(dirs[0], dirs[1], dirs[2]);
        (SOLID_ANGLE_RANGE.0..=SOLID_ANGLE_RANGE.1)
            .contains(&omega)
            .then_some((dirs, omega))
    }

    /// The solid-angle density with which [`sample`](Self::sample), called at `p` with normal
    /// `n`, returns `point` on triangle `triangle` of mesh `mesh`: for MIS when a BSDF-sampled
    /// ray hits an emitter there. 0 for a triangle that is not a light, a zero-power one, or
    /// the back of a one-sided one. (The brief's `light_normal` argument is not needed: the
    /// stored geometric normal is what `sample` uses.)
    #[inline]
    pub fn pdf(
        &self,
        p: Vec3,
        n: Vec3,
        (mesh, instance, triangle): (u32, u32, u32),
        point: Vec3,
    ) -> f32 {
        let (light, pmf) = match self.mesh_cluster.get(mesh as usize) {
            Some(&k) if k != u32::MAX => {
                let (Some(cluster), Some(&first)) = (
                    self.clusters.get(k as usize),
                    self.cluster_first.get(k as usize),
                ) else {
                    return 0.0;
                };
                let Some((local, q)) = cluster.local_of(triangle) else {
                    return 0.0;
                };
                let Some(light) = cluster.world_light(instance as usize, local) else {
                    return 0.0;
                };
                let entry = first as usize + instance as usize;
                (
                    std::borrow::Cow::Owned(light),
                    self.selection_pmf(p, n, entry) * q,
                )
            }
            _ => {
                let Some(index) = self.light_index(mesh, instance, triangle) else {
                    return 0.0;
                };
                (
                    std::borrow::Cow::Borrowed(&self.lights[index]),
                    self.selection_pmf(p, n, index),
                )
            }
        };
        let light = light.as_ref();
        if let Some((_, omega)) = self.spherical(light, p) {
            if !light.two_sided && light.normal.dot(p - light.p0) <= 0.0 {
                return 0.0;
            }
            return pmf / omega;
        }
        let d = point - p;
        let dist2 = d.length_squared();
        if !(dist2 > 0.0 && dist2.is_finite()) {
            return 0.0;
        }
        let cos_l = -d.dot(light.normal) / dist2.sqrt();
        if cos_l == 0.0 || (!light.two_sided && cos_l < 0.0) {
            return 0.0;
        }
        pmf * dist2 / (light.area * cos_l.abs())
    }
}

/// The light of triangle `p0 p1 p2` with average radiance `le`: its normal follows the
/// winding, and a degenerate triangle gets zero area and normal (zero power).
#[allow(clippy::too_many_arguments)]
fn triangle_light(
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
    le: Vec3,
    two_sided: bool,
    mesh: u32,
    instance: u32,
    triangle: u32,
) -> TriangleLight {
    let (e1, e2) = (p1 - p0, p2 - p0);
    let cross = e1.cross(e2);
    let area = 0.5 * cross.length();
    let ok = area.is_finite() && area > 0.0;
    TriangleLight {
        p0,
        e1,
        e2,
        normal: if ok { cross.normalize() } else { Vec3::ZERO },
        area: if ok { area } else { 0.0 },
        le,
        two_sided,
        mesh,
        instance,
        triangle,
    }
}

/// Barycentrics of `point` (on the plane of `light`) for its vertices 0, 1, 2, clamped into
/// the triangle (the point is inside up to rounding).
fn barycentrics(light: &TriangleLight, point: Vec3) -> [f32; 3] {
    let q = point - light.p0;
    let (d00, d01, d11) = (
        light.e1.dot(light.e1),
        light.e1.dot(light.e2),
        light.e2.dot(light.e2),
    );
    let (d20, d21) = (q.dot(light.e1), q.dot(light.e2));
    let denom = d00 * d11 - d01 * d01;
    if denom <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let b1 = ((d11 * d20 - d01 * d21) / denom).clamp(0.0, 1.0);
    let b2 = ((d00 * d21 - d01 * d20) / denom).clamp(0.0, 1.0 - b1);
    [1.0 - b1 - b2, b1, b2]
}

/// The light BVH's bounds of one triangle light of power `power`.
fn triangle_bounds(light: &TriangleLight, power: f32) -> ClusterBounds {
    let [a, b, c] = light.vertices();
    ClusterBounds {
        min: a.min(b).min(c),
        max: a.max(b).max(c),
        axis: if light.normal == Vec3::ZERO {
            Vec3::Z
        } else {
            light.normal
        },
        cos_theta: if light.normal == Vec3::ZERO {
            -1.0
        } else {
            1.0
        },
        two_sided: light.two_sided,
        cos_theta_e: 0.0,
        power,
    }
}
