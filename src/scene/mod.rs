//! The scene glint renders: world-space meshes, materials, textures, cameras and lights.
//!
//! Loaders (glTF in [`gltf`]) flatten the node hierarchy into this form once, at load; the
//! renderer never walks a hierarchy. Units: lengths in scene units (glTF metres), light
//! intensities radiometric (see [`Light`]).

pub mod defaults;
pub mod demo;
pub mod features;
pub mod gltf;
pub mod ktx2_decode;
pub mod layers;
pub mod light_spec;
pub mod procedural_texture;
mod source;
pub mod tangents;
pub mod texels;
pub mod texture_decode;

use glam::{Affine2, Mat4, Vec2, Vec3, Vec4};

pub use crate::accel::Placement;
pub use features::SceneFeatures;
pub use procedural_texture::ProceduralTexture;
pub use source::SceneSource;

/// A scene ready to render.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Triangle meshes in world space; a mesh's index is its geometry id in the ray backends.
    pub meshes: Vec<Mesh>,
    /// Materials referenced by `Mesh::material`.
    pub materials: Vec<Material>,
    /// Decoded textures referenced by `TextureRef::texture`.
    pub textures: Vec<Texture>,
    /// Cameras in the order of the source file's camera nodes.
    pub cameras: Vec<Camera>,
    /// Punctual lights.
    pub lights: Vec<Light>,
    /// What annotations say about each glTF node drawn with a mesh, by node index (empty for
    /// scenes made in code): see [`NodeInfo`].
    pub nodes: Vec<Option<NodeInfo>>,
}

/// A glTF node that draws a mesh, as per-instance annotations name it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeInfo {
    /// The node's name, if it has one.
    pub name: Option<String>,
    /// The glTF mesh index it draws.
    pub mesh: u32,
    /// That mesh's name, if it has one.
    pub mesh_name: Option<String>,
    /// The string `extras.category` of the node, if it has one.
    pub category: Option<String>,
    /// World from node (the node's and its parents' transforms at the rendered time).
    pub world_from_node: glam::Mat4,
}

/// One triangle mesh (one glTF primitive of one node, or of every node and instance that
/// shares it), in world space or, with `instances`, in object space.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    /// Where it came from, for messages (e.g. `node "Wheel" / mesh 3 / primitive 0`).
    pub name: String,
    /// World-space vertex positions.
    pub positions: Vec<Vec3>,
    /// Three vertex indices per triangle, counter-clockwise front faces.
    pub indices: Vec<[u32; 3]>,
    /// World-space unit shading normals per vertex, if the source has them.
    pub normals: Option<Vec<Vec3>>,
    /// World-space tangents (xyz) with handedness (w), if the source has them.
    pub tangents: Option<Vec<Vec4>>,
    /// TEXCOORD_0 and TEXCOORD_1.
    pub texcoords: [Option<Vec<Vec2>>; 2],
    /// COLOR_0 as linear RGBA.
    pub colors: Option<Vec<Vec4>>,
    /// Index into `Scene::materials`.
    pub material: usize,
    /// Index of the glTF node that instances it, for the `instance_id` AOV; `None` for
    /// meshes made in code. Every primitive of the node's mesh carries the node's index. A
    /// mesh with `instances` reports each placement's own node instead.
    pub node: Option<u32>,
    /// Where the mesh is drawn. Empty: once, and the positions, normals and tangents above are
    /// in world space. Otherwise they are in object space and the mesh is drawn once per
    /// placement (EXT_mesh_gpu_instancing, or a mesh several nodes share): the ray backends
    /// keep one structure for it, and shading carries each hit to world space.
    pub instances: Vec<Placement>,
}

impl Mesh {
    /// The placement a hit on copy `instance` names, or `None` for a mesh in world space.
    #[inline]
    pub fn placement(&self, instance: u32) -> Option<&Placement> {
        self.instances.get(instance as usize)
    }

    /// The node the `instance_id` AOV reports for copy `instance`.
    #[inline]
    pub fn node_of(&self, instance: u32) -> Option<u32> {
        match self.placement(instance) {
            Some(placement) => placement.node,
            None => self.node,
        }
    }

    /// How many copies are drawn (1 without placements).
    #[inline]
    pub fn copies(&self) -> usize {
        self.instances.len().max(1)
    }

    /// Triangles drawn: the mesh's count times its copies.
    #[inline]
    pub fn drawn_triangles(&self) -> usize {
        self.indices.len() * self.copies()
    }

    /// The world-space corners of the triangle with `vertices` on copy `instance`.
    #[inline]
    pub fn world_triangle(&self, instance: u32, vertices: [u32; 3]) -> Option<[Vec3; 3]> {
        self.corners(vertices, self.placement(instance))
    }

    /// The corners of the triangle with `vertices` as stored, carried to world space by
    /// `placement` when given; `None` if an index is out of range.
    #[inline]
    pub fn corners(&self, vertices: [u32; 3], placement: Option<&Placement>) -> Option<[Vec3; 3]> {
        let [a, b, c] = vertices.map(|i| self.positions.get(i as usize).copied());
        let corners = [a?, b?, c?];
        Some(match placement {
            Some(p) => corners.map(|v| p.point(v)),
            None => corners,
        })
    }

    /// World-space bounds of the vertices of all copies exactly as drawn, or `None` without
    /// vertices: each vertex through each placement, where [`world_bounds`](Self::world_bounds)
    /// transforms the object-space box (whose corners lie outside a rotated mesh). Copies
    /// that share a linear part (rotation, scale) share the work; past
    /// [`EXACT_BOUNDS_BUDGET`] vertex transforms the placed boxes are used instead (a
    /// million instances of a large mesh), which contain the exact bounds.
    pub fn exact_world_bounds(&self) -> Option<(Vec3, Vec3)> {
        self.positions.first()?;
        let fold = |points: &mut dyn Iterator<Item = Vec3>| {
            points.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p), hi.max(p))
            })
        };
        if self.instances.is_empty() {
            return Some(fold(&mut self.positions.iter().copied()));
        }
        if self.positions.len().saturating_mul(self.instances.len()) > EXACT_BOUNDS_BUDGET {
            return self.world_bounds();
        }
        // Bounds of the linearly transformed vertices, per distinct linear part: a placement
        // adds its translation to them.
        let mut linear_bounds: Vec<(glam::Mat3A, (Vec3, Vec3))> = Vec::new();
        let mut out = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for placement in &self.instances {
            let affine = placement.world_from_object();
            let linear = affine.matrix3;
            let (lo, hi) = match linear_bounds.iter().find(|(m, _)| *m == linear) {
                Some((_, b)) => *b,
                None => {
                    let b = fold(&mut self.positions.iter().map(|p| linear * *p));
                    linear_bounds.push((linear, b));
                    b
                }
            };
            let t = Vec3::from(affine.translation);
            out = (out.0.min(lo + t), out.1.max(hi + t));
        }
        Some(out)
    }

    /// World-space bounds of all copies (each copy's object-space box, placed), or `None`
    /// without vertices; they contain [`exact_world_bounds`](Self::exact_world_bounds).
    pub fn world_bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut points = self.positions.iter().copied();
        let first = points.next()?;
        let (lo, hi) = points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
        if self.instances.is_empty() {
            return Some((lo, hi));
        }
        self.instances
            .iter()
            .map(|p| p.bounds(lo, hi))
            .reduce(|(alo, ahi), (blo, bhi)| (alo.min(blo), ahi.max(bhi)))
    }
}

/// How many vertex transforms [`Mesh::exact_world_bounds`] spends on one mesh's copies before
/// it takes the placed boxes instead (about 0.1 s of one core).
pub const EXACT_BOUNDS_BUDGET: usize = 1 << 26;

/// A surface material, from glTF's metallic-roughness model. See docs/materials.md for how it maps
/// to glint's BRDFs: [`Material::diffuse_weight`] and [`Material::mirror_weight`].
#[derive(Clone, Debug)]
pub struct Material {
    /// Name, for messages.
    pub name: String,
    /// Linear base colour factor (RGBA).
    pub base_color: Vec4,
    /// Base colour texture (sRGB-encoded in the file, decoded to linear at load).
    pub base_color_texture: Option<TextureRef>,
    /// Metalness in [0, 1].
    pub metallic: f32,
    /// Perceptual roughness in [0, 1].
    pub roughness: f32,
    /// `metallicRoughnessTexture` (linear): blue multiplies `metallic`, green `roughness`.
    pub metallic_roughness_texture: Option<TextureRef>,
    /// Emitted radiance factor (W/(m²·sr)), `emissiveFactor × emissive_strength`.
    pub emissive: Vec3,
    /// Emissive texture (sRGB in the file, linear here), multiplied by `emissive`.
    pub emissive_texture: Option<TextureRef>,
    /// Whether back faces are shaded. A single-sided material's back faces are culled for
    /// camera rays, as glTF specifies, and absorb every other ray (see `docs/alpha.md`).
    pub double_sided: bool,
    /// A procedural base colour (from the material's glTF `extras`), multiplied into ρ like
    /// a base colour texture.
    pub procedural: Option<ProceduralTexture>,
    /// KHR_materials_ior: the dielectric's index of refraction (1.5 without the extension).
    pub ior: f32,
    /// KHR_materials_specular `specularFactor` (1 without it): scales the dielectric
    /// specular lobe; 0 leaves a pure Lambertian diffuse.
    pub specular: f32,
    /// KHR_materials_specular `specularColorFactor` (white without it): tints f0.
    pub specular_color: Vec3,
    /// KHR_materials_pbrSpecularGlossiness `specularGlossinessTexture` (RGB: specular colour,
    /// sRGB in the file and linear here; A: glossiness, linear). At a hit its RGB multiplies
    /// `specular_color` and the roughness is `1 − (1 − roughness) · A` (the material's
    /// `roughness` is `1 − glossinessFactor`). `None` for metallic-roughness materials.
    pub specular_glossiness_texture: Option<TextureRef>,
    /// KHR_materials_clearcoat, if the material has it.
    pub clearcoat: Option<layers::Clearcoat>,
    /// KHR_materials_sheen, if the material has it.
    pub sheen: Option<layers::Sheen>,
    /// KHR_materials_transmission, if the material has it.
    pub transmission: Option<layers::Transmission>,
    /// KHR_materials_diffuse_transmission, if the material has it with a non-zero factor.
    pub diffuse_transmission: Option<layers::DiffuseTransmission>,
    /// KHR_materials_volume, if the material has it (meaningful with transmission or diffuse
    /// transmission only).
    pub volume: Option<layers::Volume>,
    /// KHR_materials_anisotropy, if the material has it with a non-zero strength.
    pub anisotropy: Option<layers::Anisotropy>,
    /// glTF `normalTexture` and its `scale` (see [`crate::material::normal_map`]).
    pub normal_texture: Option<NormalTextureRef>,
    /// glTF `alphaMode` (with `alphaCutoff`): how the coverage α = baseColorFactor.a ×
    /// baseColorTexture.a × COLOR_0.a hides the surface (see `docs/alpha.md`).
    pub alpha: AlphaMode,
    /// KHR_materials_unlit: the surface shows its base colour as emitted radiance and neither
    /// reflects nor is lit.
    pub unlit: bool,
}

/// glTF's `alphaMode`: what the coverage α of a surface point means.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AlphaMode {
    /// α is ignored: the surface is opaque (glTF's default).
    #[default]
    Opaque,
    /// The surface exists where α ≥ `cutoff` and is absent elsewhere (cut-outs).
    Mask {
        /// glTF `alphaCutoff` (0.5 when the file gives none).
        cutoff: f32,
    },
    /// The surface covers a fraction α of the point: a ray crosses it with probability 1 − α.
    Blend,
}

/// Roughness at or below which a metallic surface is a perfect mirror.
pub const MIRROR_MAX_ROUGHNESS: f32 = 0.0;

impl Default for Material {
    fn default() -> Self {
        // glTF's default material: white, fully metallic, fully rough, single-sided.
        Self {
            name: "default".into(),
            base_color: Vec4::ONE,
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            double_sided: false,
            procedural: None,
            ior: 1.5,
            specular: 1.0,
            specular_color: Vec3::ONE,
            specular_glossiness_texture: None,
            alpha: AlphaMode::Opaque,
            unlit: false,
            normal_texture: None,
            clearcoat: None,
            sheen: None,
            transmission: None,
            diffuse_transmission: None,
            volume: None,
            anisotropy: None,
        }
    }
}

impl Material {
    /// Whether the metallic part is a perfect mirror (roughness at most
    /// [`MIRROR_MAX_ROUGHNESS`]) rather than diffuse.
    pub fn has_mirror_lobe(&self) -> bool {
        self.metallic > 0.0 && self.roughness <= MIRROR_MAX_ROUGHNESS
    }

    /// Weight of the Lambertian lobe: the share of the base colour reflected diffusely.
    /// `1 − metallic` for a mirror-like metal, 1 for a rough one (its metallic part is
    /// approximated as diffuse, since glint has no glossy BRDF).
    pub fn diffuse_weight(&self) -> f32 {
        if self.has_mirror_lobe() {
            1.0 - self.metallic
        } else {
            1.0
        }
    }

    /// Weight of the mirror lobe: `metallic` for a mirror-like metal, else 0.
    pub fn mirror_weight(&self) -> f32 {
        if self.has_mirror_lobe() {
            self.metallic
        } else {
            0.0
        }
    }
}

/// A reference from a material to a texture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into `Scene::textures`.
    pub texture: usize,
    /// Which TEXCOORD_n set to read (0 or 1).
    pub texcoord: usize,
    /// KHR_texture_transform, applied to the texture coordinates (identity if absent).
    pub transform: Affine2,
}

/// A material's normal map: a tangent-space normal texture (linear RGB, each channel
/// `(c + 1) / 2`) and glTF's `scale`, which multiplies the decoded normal's x and y before it
/// is renormalised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalTextureRef {
    /// The texture (decoded linearly: normal maps are data, not colour).
    pub texture: TextureRef,
    /// glTF `normalTexture.scale` (1 without it).
    pub scale: f32,
}

/// How texture coordinates outside [0, 1] wrap (glTF sampler wrap modes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum WrapMode {
    /// Tile.
    #[default]
    Repeat,
    /// Tile, mirroring every other copy.
    MirroredRepeat,
    /// Clamp to the edge texels.
    ClampToEdge,
}

/// Magnification filter from the glTF sampler.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum MagFilter {
    /// Nearest texel.
    Nearest,
    /// Bilinear.
    #[default]
    Linear,
}

/// A decoded texture: texels at the file's precision that read as linear RGBA, row-major,
/// top row first.
#[derive(Clone, Debug)]
pub struct Texture {
    /// Name or URI, for messages.
    pub name: String,
    /// Width in texels (≥ 1).
    pub width: u32,
    /// Height in texels (≥ 1).
    pub height: u32,
    /// The texels (compact storage; [`texels::Texels::texel`] reads one as linear RGBA).
    pub texels: texels::Texels,
    /// Horizontal wrap mode.
    pub wrap_s: WrapMode,
    /// Vertical wrap mode.
    pub wrap_t: WrapMode,
    /// Magnification filter.
    pub mag_filter: MagFilter,
}

/// A camera: where it is and how it projects.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Name, for messages.
    pub name: String,
    /// The glTF node index holding the camera; `None` for a camera made in code.
    pub node: Option<u32>,
    /// glTF `znear`: the near clip distance, scene units; `None` for a camera made in code
    /// ([`DEFAULT_ZNEAR`] then stands in where a near plane is needed). Rays start at the
    /// camera regardless: the planes only enter the camera sidecar's OpenGL projection.
    pub znear: Option<f32>,
    /// glTF `zfar`: the far clip distance; `None`: infinite (a perspective camera without
    /// `zfar`, or a camera made in code).
    pub zfar: Option<f32>,
    /// Camera-to-world transform (rigid; the camera looks down its −Z with +Y up, as in glTF).
    pub world_from_camera: Mat4,
    /// The projection.
    pub projection: Projection,
}

/// The near clip distance of a camera without one (made in code), scene units.
pub const DEFAULT_ZNEAR: f32 = 0.01;

impl Camera {
    /// A perspective camera at `eye` looking at `target`, with `up` appearing up in the image:
    /// the one place glint builds a look-at frame (see [`Camera::looking_along`]).
    pub fn look_at(name: &str, eye: Vec3, target: Vec3, up: Vec3, projection: Projection) -> Self {
        Self::looking_along(name, eye, (target - eye).normalize(), up, projection)
    }

    /// A camera at `eye` looking along the unit vector `forward`. glTF cameras look down
    /// their −Z with +Y up, so the frame's columns are right = forward × up (normalised),
    /// true up = right × forward, and back = −forward. `up` must not be parallel to `forward`.
    pub fn looking_along(
        name: &str,
        eye: Vec3,
        forward: Vec3,
        up: Vec3,
        projection: Projection,
    ) -> Self {
        let right = forward.cross(up).normalize();
        let true_up = right.cross(forward);
        Self {
            name: name.to_string(),
            node: None,
            znear: None,
            zfar: None,
            world_from_camera: Mat4::from_cols(
                right.extend(0.0),
                true_up.extend(0.0),
                (-forward).extend(0.0),
                eye.extend(1.0),
            ),
            projection,
        }
    }
}

/// glTF camera projections.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Perspective with vertical field of view `yfov` (radians) and an optional aspect ratio
    /// (width / height); without one the image's aspect is used.
    Perspective {
        /// Vertical field of view in radians.
        yfov: f32,
        /// Width / height, if the file fixes it.
        aspect_ratio: Option<f32>,
    },
    /// Orthographic with half-width `xmag` and half-height `ymag` in scene units.
    Orthographic {
        /// Half the view's width.
        xmag: f32,
        /// Half the view's height.
        ymag: f32,
    },
}

/// A punctual light (KHR_lights_punctual) in radiometric units.
///
/// glTF's `intensity` is taken as radiant intensity I in W/sr for point and spot lights and as
/// irradiance E in W/m² (on a surface facing the light) for directional lights; `color ×
/// intensity` is stored here. A point light's flux is Φ = 4πI.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Emits I (W/sr) equally in all directions.
    Point {
        /// World-space position.
        position: Vec3,
        /// Radiant intensity per channel, W/sr.
        intensity: Vec3,
        /// Distance beyond which the light has no effect (KHR_lights_punctual `range`).
        range: Option<f32>,
    },
    /// A point light restricted to a cone with a smooth falloff between the inner and outer
    /// cone angles.
    Spot {
        /// World-space position.
        position: Vec3,
        /// Unit direction the cone points to.
        direction: Vec3,
        /// Radiant intensity on the axis, W/sr.
        intensity: Vec3,
        /// Distance beyond which the light has no effect.
        range: Option<f32>,
        /// cos(innerConeAngle): full intensity inside.
        cos_inner: f32,
        /// cos(outerConeAngle): zero outside.
        cos_outer: f32,
    },
    /// A light at infinity.
    Directional {
        /// Unit direction the light travels.
        direction: Vec3,
        /// Irradiance on a surface facing the light, W/m², per channel.
        irradiance: Vec3,
    },
}

impl Scene {
    /// Axis-aligned world bounds of all vertices of every copy, or `None` for an empty scene.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.meshes
            .iter()
            .filter_map(Mesh::world_bounds)
            .reduce(|(alo, ahi), (blo, bhi)| (alo.min(blo), ahi.max(bhi)))
    }

    /// The exact bounds of every vertex as drawn ([`Mesh::exact_world_bounds`]), or `None`
    /// without vertices: the box the default camera frames.
    pub fn exact_bounds(&self) -> Option<(Vec3, Vec3)> {
        self.meshes
            .iter()
            .filter_map(Mesh::exact_world_bounds)
            .reduce(|(alo, ahi), (blo, bhi)| (alo.min(blo), ahi.max(bhi)))
    }

    /// Triangles drawn, every placed copy counted.
    pub fn triangle_count(&self) -> usize {
        self.meshes
            .iter()
            .map(|m| m.indices.len() * m.copies())
            .sum()
    }

    /// Triangles stored: a placed mesh counted once.
    pub fn unique_triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.indices.len()).sum()
    }

    /// The meshes as the ray backends take them.
    pub fn triangle_meshes(&self) -> Vec<crate::accel::TriangleMesh<'_>> {
        self.meshes
            .iter()
            .map(|m| crate::accel::TriangleMesh {
                positions: &m.positions,
                indices: &m.indices,
                instances: &m.instances,
            })
            .collect()
    }
}
