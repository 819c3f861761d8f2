//! A light BVH: chooses one of many emissive triangles with probability roughly proportional
//! to its contribution at a shading point, after pbrt-v4's BVH light sampler and Cycles' light
//! tree (own implementation).
//!
//! # Bounds
//!
//! Every node bounds its lights by a box, their total power `Φ`, and an orientation cone: an
//! axis `w` and a half-angle `θ_o` containing every light's normal (for two-sided lights the
//! normal and its negation count as one, see below). An area light emits up to `θ_e = π/2`
//! from its normal.
//!
//! # Importance
//!
//! For a shading point `p` with normal `n` (zero if unknown), a node's importance is a
//! conservative bound on what its lights can deliver:
//!
//! ```text
//! I(p, n) = Φ · cos θ' · cos θ_i' / d²      (0 when θ' ≥ θ_e)
//! θ'   = max(0, θ_w − θ_o − θ_b)
//! θ_i' = max(0, θ_i − θ_b)                  (the factor is 1 when n = 0)
//! ```
//!
//! where `c` is the box centre, `d² = max(|p − c|², r²)` with `r` the radius of the box's
//! bounding sphere, `θ_w` the angle between `w` and `p − c` (between ±`w` for a two-sided
//! node: `cos θ_w = |w · (p − c)| / |p − c|`), `θ_b` the half-angle of the bounding sphere as
//! seen from `p` (π inside it), and `θ_i` the angle between `n` and `p − c` (absolute cosine,
//! so both sides of a surface are served). Each angle is only ever reduced, so `I > 0`
//! wherever some light of the node can reach `p`, which keeps light selection unbiased.
//!
//! # Sampling and probability
//!
//! From the root, an interior node sends the walk to child `a` with probability
//! `I_a / (I_a + I_b)` (a leaf holds one light). The probability of light `k` is the product
//! of these ratios along its path; [`LightBvh::pmf`] recomputes it from the leaf up through
//! parent links, so it is exact for any depth, and equals what [`LightBvh::sample`] used.
//!
//! # Build
//!
//! Top-down, binned (12 bins per axis over the centroids), minimising pbrt's surface area
//! orientation heuristic `Σ_child Φ · M_Ω · area(box)`, times the box's aspect factor along the
//! split axis, where `M_Ω = 2π(1 − cos θ_o) + π/2 · (2θ_w sin θ_o − cos(θ_o − 2θ_w) −
//! 2θ_o sin θ_o + cos θ_o)`, `θ_w = min(θ_o + θ_e, π)`, measures the cone of directions the
//! node's lights emit into. Ranges that cannot be split are halved by index.

use super::area::TriangleLight;
use crate::sampling::distribution::ONE_MINUS_EPSILON;
use glam::Vec3;
use std::f32::consts::{FRAC_PI_2, PI};

/// Bins per axis in the build.
const BINS: usize = 12;

/// What the tree needs of a group of lights sampled as one leaf (a placed emitter's copy):
/// world bounds, the cone of its normals, whether any side emits backwards, and its power.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterBounds {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
    /// Unit axis of the normals' cone.
    pub axis: Vec3,
    /// Cosine of the cone's half-angle (−1: every direction).
    pub cos_theta: f32,
    /// Whether some light in it emits from both faces.
    pub two_sided: bool,
    /// Cosine of the emission half-angle `θ_e` around each normal: 0 (π/2) for area lights,
    /// the outer cone's cosine for a spot light, −1 for a point light.
    pub cos_theta_e: f32,
    /// Total power (W).
    pub power: f32,
}

impl ClusterBounds {
    /// The bounds of a point light at `position` with power `power` (4π × the luminance of
    /// its intensity): a point emitting in every direction.
    pub fn point(position: Vec3, power: f32) -> Self {
        Self {
            min: position,
            max: position,
            axis: Vec3::Z,
            cos_theta: -1.0,
            two_sided: false,
            cos_theta_e: -1.0,
            power,
        }
    }

    /// The bounds of a spot light at `position` shining along the unit `direction` within the
    /// cone of cosine `cos_outer`.
    pub fn spot(position: Vec3, direction: Vec3, cos_outer: f32, power: f32) -> Self {
        Self {
            min: position,
            max: position,
            axis: direction,
            cos_theta: 1.0,
            two_sided: false,
            cos_theta_e: cos_outer.clamp(-1.0, 1.0),
            power,
        }
    }

    /// An upper bound on what the lights inside can deliver at `p` with normal `n` (zero if
    /// unknown): the importance of the module doc. Positive wherever some light can reach `p`.
    #[inline]
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        Bounds::from_cluster(self).importance(p, n)
    }

    /// The smallest bounds holding both.
    pub fn union(&self, other: &ClusterBounds) -> ClusterBounds {
        let b = Bounds::union(&Bounds::from_cluster(self), &Bounds::from_cluster(other));
        ClusterBounds {
            min: b.min,
            max: b.max,
            axis: b.cone.axis,
            cos_theta: b.cone.cos_theta,
            two_sided: b.two_sided,
            cos_theta_e: b.cos_theta_e,
            power: b.power,
        }
    }
}

/// The cone (unit axis, cosine of the half-angle) holding the normals of `lights` (those of
/// non-degenerate ones), or `None` when none has a normal.
pub fn normal_cone(lights: &[TriangleLight]) -> Option<(Vec3, f32)> {
    lights
        .iter()
        .filter(|l| l.normal != Vec3::ZERO)
        .map(|l| Cone {
            axis: l.normal,
            cos_theta: 1.0,
        })
        .reduce(Cone::union)
        .map(|c| (c.axis, c.cos_theta))
}

/// An orientation cone: unit `axis`, `cos θ_o` of its half-angle (−1 for every direction).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Cone {
    axis: Vec3,
    cos_theta: f32,
}

impl Cone {
    /// The smallest cone (of this construction) holding both.
    fn union(a: Cone, b: Cone) -> Cone {
        let (ta, tb) = (
            a.cos_theta.clamp(-1.0, 1.0).acos(),
            b.cos_theta.clamp(-1.0, 1.0).acos(),
        );
        let td = a.axis.dot(b.axis).clamp(-1.0, 1.0).acos();
        if (td + tb).min(PI) <= ta {
            return a;
        }
        if (td + ta).min(PI) <= tb {
            return b;
        }
        let theta = (ta + td + tb) / 2.0;
        if theta >= PI {
            return Cone {
                axis: a.axis,
                cos_theta: -1.0,
            };
        }
        // Turn a's axis toward b's by θ − θ_a.
        let turn = theta - ta;
        let ortho = a.axis.cross(b.axis);
        if ortho.length_squared() < 1e-12 {
            return Cone {
                axis: a.axis,
                cos_theta: -1.0,
            };
        }
        let axis = glam::Quat::from_axis_angle(ortho.normalize(), turn) * a.axis;
        Cone {
            axis: axis.normalize(),
            cos_theta: theta.cos(),
        }
    }
}

/// What a node bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Bounds {
    min: Vec3,
    max: Vec3,
    power: f32,
    cone: Cone,
    two_sided: bool,
    /// Cosine of the emission half-angle around the cone (0: area lights' π/2).
    cos_theta_e: f32,
}

impl Bounds {
    fn from_cluster(c: &ClusterBounds) -> Self {
        Bounds {
            min: c.min,
            max: c.max,
            power: c.power,
            cone: Cone {
                axis: c.axis,
                cos_theta: c.cos_theta,
            },
            two_sided: c.two_sided,
            cos_theta_e: c.cos_theta_e,
        }
    }

    fn of(light: &TriangleLight, power: f32) -> Self {
        let [a, b, c] = light.vertices();
        Self {
            min: a.min(b).min(c),
            max: a.max(b).max(c),
            power,
            cone: Cone {
                axis: light.normal,
                cos_theta: 1.0,
            },
            two_sided: light.two_sided,
            cos_theta_e: 0.0,
        }
    }

    fn union(a: &Bounds, b: &Bounds) -> Bounds {
        Bounds {
            min: a.min.min(b.min),
            max: a.max.max(b.max),
            power: a.power + b.power,
            cone: Cone::union(a.cone, b.cone),
            two_sided: a.two_sided || b.two_sided,
            cos_theta_e: a.cos_theta_e.min(b.cos_theta_e),
        }
    }

    /// The importance `I(p, n)` of the module doc.
    #[inline]
    fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        let centre = 0.5 * (self.min + self.max);
        let r2 = (0.5 * (self.max - self.min)).length_squared();
        let to_p = p - centre;
        let dist2 = to_p.length_squared();
        let d2 = dist2.max(r2);
        if d2.is_nan() || d2 <= 0.0 {
            return 0.0;
        }
        let wi = if dist2 > 0.0 {
            to_p / dist2.sqrt()
        } else {
            Vec3::ZERO
        };
        // θ_b: the bounding sphere seen from p (everything when p is inside it).
        let (cos_b, sin_b) = if dist2 <= r2 {
            (-1.0, 0.0)
        } else {
            let s2 = r2 / dist2;
            ((1.0 - s2).max(0.0).sqrt(), s2.sqrt())
        };
        let mut cos_w = self.cone.axis.dot(wi);
        if self.two_sided {
            cos_w = cos_w.abs();
        }
        let sin_w = (1.0 - cos_w * cos_w).max(0.0).sqrt();
        let cos_o = self.cone.cos_theta;
        let sin_o = (1.0 - cos_o * cos_o).max(0.0).sqrt();
        // cos max(0, θ_w − θ_o), then cos max(0, that − θ_b).
        let (cos_x, sin_x) = if cos_w >= cos_o {
            (1.0, 0.0)
        } else {
            (
                cos_w * cos_o + sin_w * sin_o,
                (sin_w * cos_o - cos_w * sin_o).max(0.0),
            )
        };
        let cos_p = if cos_x >= cos_b {
            1.0
        } else {
            cos_x * cos_b + sin_x * sin_b
        };
        // Nothing beyond θ_e (π/2 for area lights: the tangent plane). A point light's
        // θ_e = π excludes nothing.
        if cos_p <= self.cos_theta_e && self.cos_theta_e > -1.0 {
            return 0.0;
        }
        let mut importance = self.power * cos_p / d2;
        if n != Vec3::ZERO && dist2 > 0.0 {
            let cos_i = n.dot(wi).abs() / n.length();
            let cos_ip = if cos_i >= cos_b {
                1.0
            } else {
                let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
                (cos_i * cos_b + sin_i * sin_b).max(0.0)
            };
            importance *= cos_ip;
        }
        importance
    }

    /// The build's cost measure `Φ · M_Ω · area(box)`.
    fn cost(&self) -> f32 {
        let theta_o = self.cone.cos_theta.clamp(-1.0, 1.0).acos();
        let theta_e = if self.cos_theta_e == 0.0 {
            FRAC_PI_2
        } else {
            self.cos_theta_e.clamp(-1.0, 1.0).acos()
        };
        let theta_w = (theta_o + theta_e).min(PI);
        let (sin_o, cos_o) = theta_o.sin_cos();
        let m_omega = 2.0 * PI * (1.0 - cos_o)
            + FRAC_PI_2
                * (2.0 * theta_w * sin_o - (theta_o - 2.0 * theta_w).cos() - 2.0 * theta_o * sin_o
                    + cos_o);
        let e = self.max - self.min;
        let area = 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
        self.power * m_omega * area
    }
}

#[derive(Clone, Copy, Debug)]
enum Kind {
    /// Indices of the two children in `nodes`.
    Interior([u32; 2]),
    /// Index of the light (in the `AreaLights` list).
    Leaf(u32),
}

#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Bounds,
    kind: Kind,
    /// `u32::MAX` for the root.
    parent: u32,
}

/// The light BVH over an [`AreaLights`](super::AreaLights) list (see the module doc).
#[derive(Clone, Debug)]
pub struct LightBvh {
    nodes: Vec<Node>,
    /// Per light, its leaf node, or `u32::MAX` for a light with no power (never chosen).
    leaf_of: Vec<u32>,
}

struct Item {
    bounds: Bounds,
    centroid: Vec3,
    light: u32,
}

impl LightBvh {
    /// Builds the tree over the lights with positive `powers[k]`; `None` when there is none.
    pub fn new(lights: &[TriangleLight], powers: &[f32]) -> Option<Self> {
        Self::with_clusters(lights, powers, &[])
    }

    /// As [`new`](Self::new), with `clusters` as further leaves: entry `lights.len() + j` is
    /// cluster `j` (a placed emitter's copy, sampled as a whole).
    pub fn with_clusters(
        lights: &[TriangleLight],
        powers: &[f32],
        clusters: &[ClusterBounds],
    ) -> Option<Self> {
        let mut items: Vec<Item> = lights
            .iter()
            .zip(powers)
            .enumerate()
            .filter(|(_, (l, w))| **w > 0.0 && w.is_finite() && l.area > 0.0)
            .map(|(k, (l, &w))| Item {
                bounds: Bounds::of(l, w),
                centroid: l.centroid(),
                // Fits: AreaLights holds fewer than u32::MAX lights.
                light: k as u32,
            })
            .collect();
        items.extend(
            clusters
                .iter()
                .enumerate()
                .filter(|(_, c)| c.power > 0.0 && c.power.is_finite())
                .map(|(j, c)| Item {
                    bounds: Bounds::from_cluster(c),
                    centroid: 0.5 * (c.min + c.max),
                    // Fits: AreaLights holds fewer than u32::MAX entries.
                    light: (lights.len() + j) as u32,
                }),
        );
        if items.is_empty() {
            return None;
        }
        let mut nodes: Vec<Node> = Vec::with_capacity(2 * items.len());
        let mut leaf_of = vec![u32::MAX; lights.len() + clusters.len()];
        // (start, end, parent, which child of the parent): an explicit stack, so that a
        // degenerate (deep) tree cannot overflow the call stack.
        let mut stack = vec![(0usize, items.len(), u32::MAX, 0usize)];
        while let Some((start, end, parent, side)) = stack.pop() {
            let range = &mut items[start..end];
            let bounds = range[1..]
                .iter()
                .fold(range[0].bounds, |acc, it| Bounds::union(&acc, &it.bounds));
            // Fits: at most 2 × (u32::MAX − 1) − 1 nodes would be needed only for more lights
            // than AreaLights allows; the tree has 2n − 1 nodes for n lights.
            let index = nodes.len() as u32;
            if let Some(p) = nodes.get_mut(parent as usize)
                && let Kind::Interior(children) = &mut p.kind
            {
                children[side] = index;
            }
            if range.len() == 1 {
                leaf_of[range[0].light as usize] = index;
                nodes.push(Node {
                    bounds,
                    kind: Kind::Leaf(range[0].light),
                    parent,
                });
                continue;
            }
            let mid = start + split(range, &bounds);
            nodes.push(Node {
                bounds,
                kind: Kind::Interior([u32::MAX; 2]),
                parent,
            });
            stack.push((mid, end, index, 1));
            stack.push((start, mid, index, 0));
        }
        Some(Self { nodes, leaf_of })
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// A tree over `entries` alone (point and spot lights): entry `j` is light `j`.
    pub fn over(entries: &[ClusterBounds]) -> Option<Self> {
        Self::with_clusters(&[], &[], entries)
    }

    /// The root's importance at `p` with normal `n`: what the whole tree can deliver there
    /// (an upper bound, positive wherever some light can reach `p`).
    #[inline]
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        self.nodes
            .first()
            .map_or(0.0, |root| root.bounds.importance(p, n))
    }

    /// Chooses a light for the point `p` with normal `n` (zero if unknown) with the uniform
    /// `u`: `(light index, probability)`, or `None` when no light can reach `p`.
    pub fn sample(&self, p: Vec3, n: Vec3, u: f32) -> Option<(usize, f32)> {
        self.sample_with_rest(p, n, u)
            .map(|(light, pmf, _)| (light, pmf))
    }

    /// As [`sample`](Self::sample), also returning `u` rescaled within the chosen leaf's
    /// share: uniform in `[0, 1)` again, for a choice inside the leaf (a cluster's triangle).
    pub fn sample_with_rest(&self, p: Vec3, n: Vec3, u: f32) -> Option<(usize, f32, f32)> {
        let mut u = f64::from(u);
        let mut pmf = 1.0f64;
        let mut node = 0usize;
        loop {
            let current = self.nodes.get(node)?;
            match current.kind {
                Kind::Leaf(light) => {
                    if node == 0 && !positive(current.bounds.importance(p, n)) {
                        return None;
                    }
                    return Some((
                        light as usize,
                        pmf as f32,
                        (u as f32).min(ONE_MINUS_EPSILON),
                    ));
                }
                Kind::Interior([a, b]) => {
                    let ia = self.nodes.get(a as usize)?.bounds.importance(p, n);
                    let ib = self.nodes.get(b as usize)?.bounds.importance(p, n);
                    let (pa, pb) = child_probabilities(ia, ib)?;
                    if u < pa {
                        u /= pa;
                        pmf *= pa;
                        node = a as usize;
                    } else {
                        u = ((u - pa) / pb).min(1.0 - f64::EPSILON);
                        pmf *= pb;
                        node = b as usize;
                    }
                }
            }
        }
    }

    /// The probability that [`sample`](Self::sample) at `p`, `n` chooses light `light`.
    pub fn pmf(&self, p: Vec3, n: Vec3, light: usize) -> f32 {
        let Some(&leaf) = self.leaf_of.get(light) else {
            return 0.0;
        };
        if leaf == u32::MAX {
            return 0.0;
        }
        let mut node = leaf as usize;
        let mut pmf = 1.0f64;
        loop {
            let parent = self.nodes[node].parent;
            if parent == u32::MAX {
                if node == 0
                    && matches!(self.nodes[0].kind, Kind::Leaf(_))
                    && !positive(self.nodes[0].bounds.importance(p, n))
                {
                    return 0.0;
                }
                return pmf as f32;
            }
            let Kind::Interior([a, b]) = self.nodes[parent as usize].kind else {
                // A parent is always interior (the build links children only to interiors).
                return 0.0;
            };
            let ia = self.nodes[a as usize].bounds.importance(p, n);
            let ib = self.nodes[b as usize].bounds.importance(p, n);
            let Some((pa, pb)) = child_probabilities(ia, ib) else {
                return 0.0;
            };
            pmf *= if a as usize == node { pa } else { pb };
            if pmf == 0.0 {
                return 0.0;
            }
            node = parent as usize;
        }
    }
}

/// Whether an importance is a positive number (not 0, not NaN).
#[inline]
fn positive(x: f32) -> bool {
    x > 0.0
}

/// The probabilities of descending into each child, `None` when neither can contribute.
#[inline]
fn child_probabilities(ia: f32, ib: f32) -> Option<(f64, f64)> {
    let (ia, ib) = (f64::from(ia), f64::from(ib));
    let sum = ia + ib;
    if !(sum > 0.0 && sum.is_finite()) {
        return None;
    }
    Some((ia / sum, ib / sum))
}

/// Reorders `items` and returns the split position (in `1..len`) by the binned SAOH of the
/// module doc, or the middle when no plane separates the centroids.
fn split(items: &mut [Item], bounds: &Bounds) -> usize {
    let (cmin, cmax) = items.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), it| (lo.min(it.centroid), hi.max(it.centroid)),
    );
    let extent = bounds.max - bounds.min;
    let max_extent = extent.max_element();
    let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, bins on the left)
    for axis in 0..3 {
        let (lo, hi) = (cmin[axis], cmax[axis]);
        if hi.is_nan() || lo.is_nan() || hi <= lo {
            continue;
        }
        let bin_of = |c: Vec3| (((c[axis] - lo) / (hi - lo) * BINS as f32) as usize).min(BINS - 1);
        let mut bins: [Option<Bounds>; BINS] = [None; BINS];
        for it in items.iter() {
            let b = &mut bins[bin_of(it.centroid)];
            *b = Some(match b {
                Some(acc) => Bounds::union(acc, &it.bounds),
                None => it.bounds,
            });
        }
        let aspect = if extent[axis] > 0.0 {
            max_extent / extent[axis]
        } else {
            1.0
        };
        for left in 1..BINS {
            let merge = |range: &[Option<Bounds>]| {
                range.iter().flatten().fold(None, |acc: Option<Bounds>, b| {
                    Some(acc.map_or(*b, |a| Bounds::union(&a, b)))
                })
            };
            let (Some(l), Some(r)) = (merge(&bins[..left]), merge(&bins[left..])) else {
                continue;
            };
            let cost = aspect * (l.cost() + r.cost());
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, left));
            }
        }
    }
    if let Some((_, axis, left)) = best {
        let (lo, hi) = (cmin[axis], cmax[axis]);
        let mut i = 0;
        for j in 0..items.len() {
            let bin =
                (((items[j].centroid[axis] - lo) / (hi - lo) * BINS as f32) as usize).min(BINS - 1);
            if bin < left {
                items.swap(i, j);
                i += 1;
            }
        }
        if i > 0 && i < items.len() {
            return i;
        }
    }
    items.len() / 2
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_union_contains_both_axes() {
        let a = Cone {
            axis: Vec3::Y,
            cos_theta: 1.0,
        };
        let b = Cone {
            axis: Vec3::X,
            cos_theta: 1.0,
        };
        let u = Cone::union(a, b);
        for axis in [Vec3::Y, Vec3::X] {
            assert!(u.axis.dot(axis) >= u.cos_theta - 1e-5);
        }
        assert!((u.cos_theta - std::f32::consts::FRAC_PI_4.cos()).abs() < 1e-5);
        let opposite = Cone::union(
            a,
            Cone {
                axis: -Vec3::Y,
                cos_theta: 1.0,
            },
        );
        assert_eq!(opposite.cos_theta, -1.0);
    }
}
