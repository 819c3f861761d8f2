//! What a scene requires, known once at load, so that per-hit work it does not need is never
//! done (no texture-coordinate interpolation without textures, no reflection rays without
//! mirrors, no cone test without spot lights).

use super::{Light, Scene};

/// The features a scene uses. Computed by [`SceneFeatures::of`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneFeatures {
    /// At least one point light.
    pub point_lights: bool,
    /// At least one spot light.
    pub spot_lights: bool,
    /// At least one directional light.
    pub directional_lights: bool,
    /// At least one light with a finite range.
    pub light_ranges: bool,
    /// At least one material with a base colour, emissive, metallic-roughness, normal or
    /// KHR_materials layer texture, or a procedural one.
    pub textures: bool,
    /// At least one material with a mirror lobe.
    pub mirrors: bool,
    /// At least one emissive material.
    pub emission: bool,
    /// At least one mesh with vertex colours.
    pub vertex_colors: bool,
    /// At least one mesh with shading normals.
    pub shading_normals: bool,
    /// At least one single-sided material (back faces must be detected).
    pub single_sided: bool,
    /// At least one material with alphaMode MASK or BLEND (hits need an alpha test).
    pub alpha: bool,
    /// At least one material with a normal map, clear-coat normal map or anisotropy (hits
    /// build tangent frames; implies
    /// `textures`).
    pub normal_maps: bool,
    /// At least one material with KHR_materials layers (clear coat, sheen, transmission,
    /// diffuse transmission):
    /// both integrators shade it with the layered BSDF, so the direct integrator runs the path
    /// kernel's delta-only mode for such scenes.
    pub layered_materials: bool,
    /// Placed copies of meshes stored once (0 when every mesh is drawn once, baked).
    pub placed_copies: usize,
    /// Triangles stored, each placed mesh once.
    pub stored_triangles: usize,
    /// Triangles drawn, each placed copy counted.
    pub drawn_triangles: usize,
}

impl SceneFeatures {
    /// Scans the scene once.
    pub fn of(scene: &Scene) -> Self {
        let mut f = SceneFeatures::default();
        for light in &scene.lights {
            match light {
                Light::Point { range, .. } => {
                    f.point_lights = true;
                    f.light_ranges |= range.is_some();
                }
                Light::Spot { range, .. } => {
                    f.spot_lights = true;
                    f.light_ranges |= range.is_some();
                }
                Light::Directional { .. } => f.directional_lights = true,
            }
        }
        // Only materials that some mesh uses count.
        let mut used = vec![false; scene.materials.len()];
        for mesh in &scene.meshes {
            if let Some(slot) = used.get_mut(mesh.material) {
                *slot = true;
            }
            f.vertex_colors |= mesh.colors.is_some();
            f.shading_normals |= mesh.normals.is_some();
            f.placed_copies += mesh.instances.len();
            f.stored_triangles += mesh.indices.len();
            f.drawn_triangles += mesh.drawn_triangles();
        }
        for (material, _) in scene.materials.iter().zip(&used).filter(|(_, u)| **u) {
            f.textures |=
                material.base_color_texture.is_some() || material.emissive_texture.is_some();
            f.textures |= material.procedural.is_some();
            f.textures |= material.metallic_roughness_texture.is_some();
            f.textures |= super::layers::any_texture(
                material.clearcoat.as_ref(),
                material.sheen.as_ref(),
                material.transmission.as_ref(),
                material.diffuse_transmission.as_ref(),
            );
            f.mirrors |= material.has_mirror_lobe();
            f.emission |= material.emissive != glam::Vec3::ZERO;
            f.single_sided |= !material.double_sided;
            f.alpha |= material.alpha != super::AlphaMode::Opaque;
            f.normal_maps |= material.normal_texture.is_some()
                || material
                    .clearcoat
                    .is_some_and(|c| c.normal_texture.is_some())
                || material.anisotropy.is_some();
            f.textures |= material.anisotropy.is_some_and(|a| a.texture.is_some());
            f.layered_materials |= material.clearcoat.is_some()
                || material.sheen.is_some()
                || material.transmission.is_some()
                || material.diffuse_transmission.is_some();
        }
        f.textures |= f.normal_maps;
        f
    }
}
