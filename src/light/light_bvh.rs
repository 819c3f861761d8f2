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
//! parent links, so it is exact for any depth, and equals what [`LightBvh::sample`] used: both
//! take each step through one function (`LightBvh::step`).
//!
//! # Layout
//!
//! The walk reads nodes, nothing else, and a node stores what the importance needs rather than
//! what the build needs: the sphere's centre `c` and `r²`, the cone's axis, `cos θ_o` and
//! `sin θ_o`, `cos θ_e`, `Φ`, and one link word (leaf and two-sided flags over a 30-bit child
//! or light index), 48 bytes. A node's two children sit side by side (the first at an odd
//! index), so a step reads one contiguous pair; parent links, needed only by `pmf`, live in
//! an array of their own. The importance is the same function of the same stored numbers as
//! when the nodes held boxes: a point inside a node's bounding sphere returns `Φ / r²` at once
//! (every angle factor is exactly 1 there), and `|n|` is taken once per walk, not per node.
//! A normal that is not finite counts as unknown.
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
        Node::new(&Bounds::from_cluster(self), true, 0).importance(&Query::new(p, n))
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

/// Most entries (lights and clusters) a tree is built over: a node's link keeps two flag bits
/// above a 30-bit index, and a tree over `n` entries has `2n − 1` nodes. Past it
/// [`LightBvh::with_clusters`] builds nothing (an [`AreaLights`](super::AreaLights) then chooses
/// by power).
pub const MAX_ENTRIES: usize = 1 << 29;

/// A node's link: set for a leaf.
const LEAF: u32 = 1 << 31;
/// A node's link: set when some light in it emits from both faces.
const TWO_SIDED: u32 = 1 << 30;
/// A node's link: the index (first child, or light) below the flags.
const INDEX: u32 = TWO_SIDED - 1;

/// A node as the walk reads it: what the importance needs, computed once at build (48 bytes;
/// see "Layout" in the module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(16))]
struct Node {
    /// Centre `c` of the bounding box.
    centre: Vec3,
    /// Squared radius `r²` of the box's bounding sphere.
    r2: f32,
    /// Axis `w` of the normals' cone.
    axis: Vec3,
    /// `cos θ_o`.
    cos_o: f32,
    /// `sin θ_o`.
    sin_o: f32,
    /// `cos θ_e` where it excludes some directions; −∞ for `θ_e = π` (point lights).
    cos_e: f32,
    /// Total power `Φ`.
    power: f32,
    /// [`LEAF`] and [`TWO_SIDED`] flags over the first child's index (interior) or the
    /// light's (leaf).
    link: u32,
}

/// The shading point of one walk, with what every node's importance shares.
#[derive(Clone, Copy, Debug)]
struct Query {
    p: Vec3,
    n: Vec3,
    /// `|n|`, when `n` is usable (non-zero, finite, measurable length); else `None` and the
    /// normal's factor is 1.
    n_len: Option<f32>,
}

impl Query {
    #[inline]
    fn new(p: Vec3, n: Vec3) -> Self {
        let len = n.length();
        Self {
            p,
            n,
            n_len: (n != Vec3::ZERO && len.is_finite() && len > 0.0).then_some(len),
        }
    }
}

impl Node {
    /// The node holding what `b` bounds; `link` carries the index (flags are added here).
    fn new(b: &Bounds, leaf: bool, index: u32) -> Self {
        let centre = 0.5 * (b.min + b.max);
        let r2 = (0.5 * (b.max - b.min)).length_squared();
        let cos_o = b.cone.cos_theta;
        let mut link = index & INDEX;
        if leaf {
            link |= LEAF;
        }
        if b.two_sided {
            link |= TWO_SIDED;
        }
        Node {
            centre,
            r2,
            axis: b.cone.axis,
            cos_o,
            sin_o: (1.0 - cos_o * cos_o).max(0.0).sqrt(),
            cos_e: if b.cos_theta_e > -1.0 {
                b.cos_theta_e
            } else {
                f32::NEG_INFINITY
            },
            power: b.power,
            link,
        }
    }

    #[inline]
    fn is_leaf(&self) -> bool {
        self.link & LEAF != 0
    }

    /// The first child's index (interior) or the light's (leaf).
    #[inline]
    fn index(&self) -> usize {
        (self.link & INDEX) as usize
    }

    /// The importance `I(p, n)` of the module doc.
    #[inline]
    fn importance(&self, q: &Query) -> f32 {
        let to_p = q.p - self.centre;
        let dist2 = to_p.length_squared();
        let r2 = self.r2;
        let d2 = dist2.max(r2);
        if d2.is_nan() || d2 <= 0.0 {
            return 0.0;
        }
        if dist2 <= r2 {
            // Inside the bounding sphere θ_b = π: every angle factor is 1 (the general path
            // below gives exactly this), and only a θ_e of 0 excludes anything.
            return if self.cos_e >= 1.0 {
                0.0
            } else {
                self.power / d2
            };
        }
        // Outside it (or p is NaN: then as the general formula falls out).
        let wi = if dist2 > 0.0 {
            to_p / dist2.sqrt()
        } else {
            Vec3::ZERO
        };
        // θ_b: the bounding sphere seen from p.
        let s2 = r2 / dist2;
        let (cos_b, sin_b) = ((1.0 - s2).max(0.0).sqrt(), s2.sqrt());
        let mut cos_w = self.axis.dot(wi);
        if self.link & TWO_SIDED != 0 {
            cos_w = cos_w.abs();
        }
        let (cos_o, sin_o) = (self.cos_o, self.sin_o);
        // cos max(0, θ_w − θ_o), then cos max(0, that − θ_b).
        let (cos_x, sin_x) = if cos_w >= cos_o {
            (1.0, 0.0)
        } else {
            let sin_w = (1.0 - cos_w * cos_w).max(0.0).sqrt();
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
        // Nothing beyond θ_e (π/2 for area lights: the tangent plane; a point light's θ_e = π
        // excludes nothing, stored as −∞).
        if cos_p <= self.cos_e {
            return 0.0;
        }
        let mut importance = self.power * cos_p / d2;
        if let Some(n_len) = q.n_len
            && dist2 > 0.0
        {
            let cos_i = q.n.dot(wi).abs() / n_len;
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
}

/// The light BVH over an [`AreaLights`](super::AreaLights) list (see the module doc).
#[derive(Clone, Debug)]
pub struct LightBvh {
    /// The root at 0, then children in adjacent pairs (first child at an odd index).
    nodes: Vec<Node>,
    /// Per node, its parent's index (`u32::MAX` for the root): for [`LightBvh::pmf`] alone,
    /// so it stays out of the nodes the walk reads.
    parent: Vec<u32>,
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
        if items.is_empty() || lights.len().saturating_add(clusters.len()) > MAX_ENTRIES {
            return None;
        }
        // Fits: fewer than MAX_ENTRIES entries, so under 2 · MAX_ENTRIES nodes, and every
        // index below fits the link's 30 bits.
        let mut nodes: Vec<Node> = Vec::with_capacity(2 * items.len() - 1);
        let mut parent: Vec<u32> = Vec::with_capacity(2 * items.len() - 1);
        nodes.push(Node::default());
        parent.push(u32::MAX);
        let mut leaf_of = vec![u32::MAX; lights.len() + clusters.len()];
        // (start, end, the node's slot): an explicit stack, so that a degenerate (deep) tree
        // cannot overflow the call stack. A node's slot is reserved by its parent, which
        // places its two children side by side.
        let mut stack = vec![(0usize, items.len(), 0usize)];
        while let Some((start, end, index)) = stack.pop() {
            let range = &mut items[start..end];
            let bounds = range[1..]
                .iter()
                .fold(range[0].bounds, |acc, it| Bounds::union(&acc, &it.bounds));
            if range.len() == 1 {
                leaf_of[range[0].light as usize] = index as u32;
                nodes[index] = Node::new(&bounds, true, range[0].light);
                continue;
            }
            let mid = start + split(range, &bounds);
            let first = nodes.len();
            nodes.extend([Node::default(); 2]);
            parent.extend([index as u32; 2]);
            nodes[index] = Node::new(&bounds, false, first as u32);
            stack.push((mid, end, first + 1));
            stack.push((start, mid, first));
        }
        Some(Self {
            nodes,
            parent,
            leaf_of,
        })
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
            .map_or(0.0, |root| root.importance(&Query::new(p, n)))
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
        let q = Query::new(p, n);
        let mut u = f64::from(u);
        let mut pmf = 1.0f64;
        let mut current = self.nodes.first()?;
        if current.is_leaf() && !positive(current.importance(&q)) {
            return None;
        }
        while !current.is_leaf() {
            let first = current.index();
            let (pa, pb) = self.step(first, &q)?;
            let side = if u < pa {
                u /= pa;
                pmf *= pa;
                first
            } else {
                u = ((u - pa) / pb).min(1.0 - f64::EPSILON);
                pmf *= pb;
                first + 1
            };
            current = self.nodes.get(side)?;
        }
        Some((
            current.index(),
            pmf as f32,
            (u as f32).min(ONE_MINUS_EPSILON),
        ))
    }

    /// The probability that [`sample`](Self::sample) at `p`, `n` chooses light `light`.
    pub fn pmf(&self, p: Vec3, n: Vec3, light: usize) -> f32 {
        let Some(&leaf) = self.leaf_of.get(light) else {
            return 0.0;
        };
        if leaf == u32::MAX {
            return 0.0;
        }
        let q = Query::new(p, n);
        if leaf == 0 {
            // The root is the only node.
            return if positive(self.nodes[0].importance(&q)) {
                1.0
            } else {
                0.0
            };
        }
        let mut node = leaf as usize;
        let mut pmf = 1.0f64;
        while node != 0 {
            // Children pair up as (odd, even): the first child is the odd one.
            let first = node - 1 + node % 2;
            let Some((pa, pb)) = self.step(first, &q) else {
                return 0.0;
            };
            pmf *= if node == first { pa } else { pb };
            if pmf == 0.0 {
                return 0.0;
            }
            node = self.parent[node] as usize;
        }
        pmf as f32
    }

    /// One step of the walk, shared by [`sample`](Self::sample) and [`pmf`](Self::pmf): the
    /// probabilities of descending into the children `first` and `first + 1`, `None` when
    /// neither can contribute.
    #[inline]
    fn step(&self, first: usize, q: &Query) -> Option<(f64, f64)> {
        let [a, b] = self.nodes.get(first..first + 2)? else {
            return None;
        };
        child_probabilities(a.importance(q), b.importance(q))
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
    // `sum < ∞` rather than `is_finite()`: the same test here (NaN fails `> 0` already), and
    // it compiles to one comparison, where `is_finite` on f64 took about 25 instructions a step.
    if !(sum > 0.0 && sum < f64::INFINITY) {
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
    use rand::{Rng, SeedableRng};
    use rand_pcg::Pcg32;

    /// The importance as it was computed from a box (before nodes held the sphere and cone
    /// precomputed): the reference the compact node must reproduce bit for bit.
    fn importance_from_box(b: &Bounds, p: Vec3, n: Vec3) -> f32 {
        let centre = 0.5 * (b.min + b.max);
        let r2 = (0.5 * (b.max - b.min)).length_squared();
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
        let (cos_b, sin_b) = if dist2 <= r2 {
            (-1.0, 0.0)
        } else {
            let s2 = r2 / dist2;
            ((1.0 - s2).max(0.0).sqrt(), s2.sqrt())
        };
        let mut cos_w = b.cone.axis.dot(wi);
        if b.two_sided {
            cos_w = cos_w.abs();
        }
        let sin_w = (1.0 - cos_w * cos_w).max(0.0).sqrt();
        let cos_o = b.cone.cos_theta;
        let sin_o = (1.0 - cos_o * cos_o).max(0.0).sqrt();
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
        if cos_p <= b.cos_theta_e && b.cos_theta_e > -1.0 {
            return 0.0;
        }
        let mut importance = b.power * cos_p / d2;
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

    #[test]
    fn compact_nodes_give_the_box_importance_bit_for_bit() {
        let mut rng = Pcg32::seed_from_u64(33);
        let mut v = |s: f32| Vec3::new(rng.random(), rng.random(), rng.random()) * s - s / 2.0;
        let mut checked = [0usize; 2]; // [inside the sphere, outside]
        for k in 0..200_000 {
            let lo = v(4.0);
            let size = v(1.0).abs() * if k % 7 == 0 { 0.0 } else { 2.0 };
            let axis = v(2.0).normalize_or(Vec3::Z);
            // Cones from a single normal to every direction; θ_e of area, spot and point lights.
            let cos_theta = [1.0, 0.9, 0.3, 0.0, -0.5, -1.0][k % 6];
            let cos_theta_e = [0.0, 0.0, 0.7, -1.0, 1.0][k % 5];
            let b = Bounds {
                min: lo,
                max: lo + size,
                power: 0.1 + (k % 13) as f32,
                cone: Cone { axis, cos_theta },
                two_sided: k % 3 == 0,
                cos_theta_e,
            };
            let p = if k % 11 == 0 { lo + size * 0.5 } else { v(6.0) };
            let n = match k % 4 {
                0 => Vec3::ZERO,
                1 => v(2.0).normalize_or(Vec3::X),
                _ => v(3.0), // not unit: the factor divides by |n|
            };
            let want = importance_from_box(&b, p, n);
            let got = Node::new(&b, k % 2 == 0, 5).importance(&Query::new(p, n));
            assert_eq!(
                got.to_bits(),
                want.to_bits(),
                "{b:?} at {p}, n {n}: {got} vs {want}"
            );
            let c = 0.5 * (b.min + b.max);
            checked[usize::from((p - c).length_squared() > (0.5 * size).length_squared())] += 1;
        }
        assert!(checked[0] > 1000 && checked[1] > 100_000, "{checked:?}");
    }

    #[test]
    fn children_are_adjacent_and_parents_link_back() {
        let lights: Vec<ClusterBounds> = (0..37)
            .map(|k| ClusterBounds::point(Vec3::new(k as f32, (k * k % 7) as f32, 0.0), 1.0))
            .collect();
        let tree = LightBvh::over(&lights).unwrap();
        assert_eq!(tree.node_count(), 2 * lights.len() - 1);
        let mut leaves = vec![false; lights.len()];
        for (i, node) in tree.nodes.iter().enumerate() {
            if node.is_leaf() {
                assert!(!leaves[node.index()], "light {} twice", node.index());
                leaves[node.index()] = true;
                assert_eq!(tree.leaf_of[node.index()] as usize, i);
            } else {
                let first = node.index();
                assert_eq!(first % 2, 1, "first child at an odd index");
                assert_eq!(tree.parent[first] as usize, i);
                assert_eq!(tree.parent[first + 1] as usize, i);
                // A node's power is its children's sum (the build's union).
                let sum = tree.nodes[first].power + tree.nodes[first + 1].power;
                assert!((node.power - sum).abs() <= 1e-5 * sum);
            }
        }
        assert!(leaves.iter().all(|&l| l));
    }

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
