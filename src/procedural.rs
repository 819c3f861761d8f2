//! Procedural meshes generated from a fixed seed, so that every machine builds the same
//! geometry: benchmark scenes and test subjects that need no files.

use glam::{Vec3, vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// An owned triangle mesh.
#[derive(Clone, Debug, Default)]
pub struct OwnedMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Three indices per triangle, counter-clockwise seen from outside.
    pub indices: Vec<[u32; 3]>,
    /// Where it is drawn (empty: once, as given; see [`crate::accel::Placement`]).
    pub instances: Vec<crate::accel::Placement>,
}

impl OwnedMesh {
    /// Borrowed view for the ray backends.
    pub fn as_triangle_mesh(&self) -> crate::accel::TriangleMesh<'_> {
        crate::accel::TriangleMesh {
            positions: &self.positions,
            indices: &self.indices,
            instances: &self.instances,
        }
    }
}

/// The built-in benchmark scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Builtin {
    /// A unit sphere subdivided to `20 · 4^level` triangles, its radius displaced by noise.
    DisplacedSphere,
    /// A square height-field grid with random displacement.
    Terrain,
    /// Triangles of random size and orientation scattered in a cube.
    TriangleSoup,
}

impl Builtin {
    /// All built-in scenes.
    pub const ALL: [Builtin; 3] = [
        Builtin::DisplacedSphere,
        Builtin::Terrain,
        Builtin::TriangleSoup,
    ];

    /// Name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Builtin::DisplacedSphere => "sphere",
            Builtin::Terrain => "terrain",
            Builtin::TriangleSoup => "soup",
        }
    }

    /// The scene at its benchmark size (about 1M triangles each).
    pub fn generate(self, seed: u64) -> OwnedMesh {
        match self {
            Builtin::DisplacedSphere => displaced_sphere(8, 0.05, seed),
            Builtin::Terrain => terrain(724, 0.1, seed),
            Builtin::TriangleSoup => triangle_soup(1_000_000, 0.02, seed),
        }
    }
}

/// An icosphere with `20 · 4^subdivisions` triangles, each vertex's radius scaled by
/// `1 + amplitude · r` with `r` uniform in [−1, 1] from `seed`. Watertight: shared vertices.
pub fn displaced_sphere(subdivisions: u32, amplitude: f32, seed: u64) -> OwnedMesh {
    let t = (1.0 + 5.0f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| vec3(x, y, z).normalize())
    .collect();
    let mut indices: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *midpoints.entry(key).or_insert_with(|| {
                positions.push(((positions[a as usize] + positions[b as usize]) * 0.5).normalize());
                (positions.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(indices.len() * 4);
        for &[a, b, c] in &indices {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        indices = next;
    }
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    for p in &mut positions {
        *p *= 1.0 + amplitude * rng.random_range(-1.0f32..=1.0);
    }
    OwnedMesh {
        positions,
        indices,
        instances: Vec::new(),
    }
}

/// An `n × n` quad grid (2n² triangles) over [−1, 1]² in x–z, heights `amplitude · r` with `r`
/// uniform in [−1, 1]. Faces point up (+y).
pub fn terrain(n: u32, amplitude: f32, seed: u64) -> OwnedMesh {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let side = n + 1;
    let mut positions = Vec::with_capacity((side * side) as usize);
    for j in 0..side {
        for i in 0..side {
            let x = -1.0 + 2.0 * i as f32 / n as f32;
            let z = -1.0 + 2.0 * j as f32 / n as f32;
            positions.push(vec3(x, amplitude * rng.random_range(-1.0f32..=1.0), z));
        }
    }
    let mut indices = Vec::with_capacity((2 * n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let a = j * side + i;
            let b = a + 1;
            let c = a + side;
            let d = c + 1;
            indices.push([a, c, b]);
            indices.push([b, c, d]);
        }
    }
    OwnedMesh {
        positions,
        indices,
        instances: Vec::new(),
    }
}

/// `count` independent triangles with vertices within `size` of a centre uniform in [−1, 1]³.
pub fn triangle_soup(count: usize, size: f32, seed: u64) -> OwnedMesh {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let mut positions = Vec::with_capacity(count * 3);
    let mut indices = Vec::with_capacity(count);
    let uniform3 = |rng: &mut Pcg64Mcg, scale: f32| {
        vec3(
            rng.random_range(-1.0f32..=1.0),
            rng.random_range(-1.0f32..=1.0),
            rng.random_range(-1.0f32..=1.0),
        ) * scale
    };
    for k in 0..count {
        let centre = uniform3(&mut rng, 1.0);
        for _ in 0..3 {
            let p = centre + uniform3(&mut rng, size);
            positions.push(p);
        }
        let base = (3 * k) as u32;
        indices.push([base, base + 1, base + 2]);
    }
    OwnedMesh {
        positions,
        indices,
        instances: Vec::new(),
    }
}
