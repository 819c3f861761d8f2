//! Writes `scenes/demo.glb`, the demo scene embedded in glint (`glint render` without a
//! scene renders it).
//!
//! ```text
//! cargo run --example make_demo
//! ```
//!
//! It also writes `scenes/demo-env.hdr`, the environment `scripts/demo.sh` renders the demo
//! under: `../shared/env/studio.hdr` (CC0) averaged down to 256×128 (skipped, keeping the
//! committed file, where that source is absent).
//!
//! The scene (metres, +Y up) shows what glint renders: a checker-textured floor; two rows of
//! metal-rough spheres (gold with metallic 1 in front, red dielectric behind on a plinth, each
//! at roughness 0 … 0.9; roughness 0 is the mirror); a tiled wall whose tiles are only a
//! normal map (MikkTSpace tangents are generated at load); a perforated screen cut by an
//! alpha MASK; a warm emissive panel (KHR_materials_emissive_strength) lighting its
//! surroundings; a camera node; and one light of each KHR_lights_punctual type. All textures
//! are generated here. Intensities are radiometric and chosen so that lit diffuse surfaces
//! have radiances of about 0.1–1 W/(m²·sr): a point light of I W/sr at distance d gives a
//! surface of albedo ρ facing it the radiance ρ/π · I/d².

use glam::{Quat, Vec2, Vec3};
use gltf::json;
use json::validation::{Checked::Valid, USize64};
use std::path::Path;

/// Where the scene is written, relative to the crate root.
const OUTPUT: &str = "scenes/demo.glb";

/// The demo's environment map (written next to the scene; `scripts/demo.sh` passes it as
/// `--env`) and the CC0 original it is downscaled from.
const ENV_OUTPUT: &str = "scenes/demo-env.hdr";
const ENV_SOURCE: &str = "../shared/env/studio.hdr";

/// The sphere rows: roughness of each column, radius and centre spacing in metres.
const SPHERE_ROUGHNESS: [f32; 5] = [0.0, 0.2, 0.4, 0.6, 0.9];
const SPHERE_RADIUS_M: f32 = 0.3;
const SPHERE_SPACING_M: f32 = 0.8;
/// Height of the plinth that raises the back row of spheres.
const PLINTH_HEIGHT_M: f32 = 0.35;

/// Tiles of the normal-mapped wall: texture repeats per metre (4 tiles per repeat).
const TILES_PER_METRE: f32 = 1.0;
/// Lattice cells across the alpha-cut screen's quad (one hole per cell).
const LATTICE_REPEATS: f32 = 8.0;

/// Checker texture: size in texels and cells per side.
const CHECKER_TEXELS: u32 = 64;
const CHECKER_CELLS: u32 = 8;

/// Floor half-size in metres, and how many times the checker texture repeats across it.
const FLOOR_HALF_SIZE_M: f32 = 4.0;
const FLOOR_TEXTURE_REPEATS: f32 = 2.0;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let glb = build_demo()?;
    let path = root.join(OUTPUT);
    write_atomically(&path, &glb)?;
    println!("wrote {} ({} bytes)", path.display(), glb.len());
    if !write_environment(root)? {
        println!("{ENV_SOURCE} not found: kept {ENV_OUTPUT} as it is");
    }
    Ok(())
}

/// Geometry of one mesh, in object space.
struct Geometry {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    texcoords: Vec<Vec2>,
    indices: Vec<u16>,
}

/// Accumulates the document and its single binary buffer.
struct Builder {
    root: json::Root,
    bin: Vec<u8>,
}

impl Builder {
    /// Appends bytes as a new buffer view (4-byte aligned, as accessors require).
    fn view(
        &mut self,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: None,
            extras: Default::default(),
        })
    }

    fn accessor(
        &mut self,
        view: json::Index<json::buffer::View>,
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        bounds: Option<(Vec3, Vec3)>,
    ) -> json::Index<json::Accessor> {
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min: bounds.map(|(lo, _)| json::Value::from(lo.to_array().to_vec())),
            max: bounds.map(|(_, hi)| json::Value::from(hi.to_array().to_vec())),
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// Stores a geometry's vertex and index data; returns its primitive's attributes and
    /// index accessor, to be shared by meshes with different materials.
    fn geometry(&mut self, g: &Geometry) -> Attributes {
        use json::accessor::{ComponentType, Type};
        use json::buffer::Target;
        let floats = |v: &mut Vec<u8>, xs: &[f32]| {
            xs.iter()
                .for_each(|x| v.extend_from_slice(&x.to_le_bytes()))
        };
        let mut bytes = Vec::new();
        g.positions
            .iter()
            .for_each(|p| floats(&mut bytes, &p.to_array()));
        let lo = g.positions.iter().copied().fold(Vec3::INFINITY, Vec3::min);
        let hi = g
            .positions
            .iter()
            .copied()
            .fold(Vec3::NEG_INFINITY, Vec3::max);
        let view = self.view(&bytes, Some(Target::ArrayBuffer));
        let position = self.accessor(
            view,
            g.positions.len(),
            ComponentType::F32,
            Type::Vec3,
            Some((lo, hi)),
        );
        bytes.clear();
        g.normals
            .iter()
            .for_each(|n| floats(&mut bytes, &n.to_array()));
        let view = self.view(&bytes, Some(Target::ArrayBuffer));
        let normal = self.accessor(view, g.normals.len(), ComponentType::F32, Type::Vec3, None);
        bytes.clear();
        g.texcoords
            .iter()
            .for_each(|t| floats(&mut bytes, &t.to_array()));
        let view = self.view(&bytes, Some(Target::ArrayBuffer));
        let texcoord = self.accessor(
            view,
            g.texcoords.len(),
            ComponentType::F32,
            Type::Vec2,
            None,
        );
        bytes.clear();
        g.indices
            .iter()
            .for_each(|i| bytes.extend_from_slice(&i.to_le_bytes()));
        let view = self.view(&bytes, Some(Target::ElementArrayBuffer));
        let indices = self.accessor(
            view,
            g.indices.len(),
            ComponentType::U16,
            Type::Scalar,
            None,
        );
        Attributes {
            position,
            normal,
            texcoord,
            indices,
        }
    }

    fn mesh(
        &mut self,
        name: &str,
        geometry: &Attributes,
        material: json::Index<json::Material>,
    ) -> json::Index<json::Mesh> {
        let attributes = [
            (json::mesh::Semantic::Positions, geometry.position),
            (json::mesh::Semantic::Normals, geometry.normal),
            (json::mesh::Semantic::TexCoords(0), geometry.texcoord),
        ]
        .into_iter()
        .map(|(semantic, accessor)| (Valid(semantic), accessor))
        .collect();
        self.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(name.into()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: Default::default(),
                indices: Some(geometry.indices),
                material: Some(material),
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        })
    }

    fn material(
        &mut self,
        name: &str,
        base_color: [f32; 4],
        metallic: f32,
        roughness: f32,
    ) -> json::Index<json::Material> {
        self.root.push(json::Material {
            name: Some(name.into()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(base_color),
                metallic_factor: json::material::StrengthFactor(metallic),
                roughness_factor: json::material::StrengthFactor(roughness),
                ..Default::default()
            },
            ..Default::default()
        })
    }

    /// Embeds PNG bytes as an image and a texture that repeats; `nearest` magnifies without
    /// filtering.
    fn texture(&mut self, name: &str, png: &[u8], nearest: bool) -> json::Index<json::Texture> {
        let view = self.view(png, None);
        let image = self.root.push(json::Image {
            buffer_view: Some(view),
            mime_type: Some(json::image::MimeType("image/png".into())),
            name: Some(name.into()),
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
        let sampler = self.root.push(json::texture::Sampler {
            mag_filter: nearest.then_some(Valid(json::texture::MagFilter::Nearest)),
            wrap_s: Valid(json::texture::WrappingMode::Repeat),
            wrap_t: Valid(json::texture::WrappingMode::Repeat),
            ..Default::default()
        });
        self.root.push(json::Texture {
            name: Some(name.into()),
            sampler: Some(sampler),
            source: image,
            extensions: None,
            extras: Default::default(),
        })
    }

    fn node(&mut self, node: json::Node) -> json::Index<json::Node> {
        self.root.push(node)
    }
}

/// The accessors of one stored geometry.
struct Attributes {
    position: json::Index<json::Accessor>,
    normal: json::Index<json::Accessor>,
    texcoord: json::Index<json::Accessor>,
    indices: json::Index<json::Accessor>,
}

fn build_demo() -> Result<Vec<u8>, Box<dyn std::error::Error>> {
    let mut b = Builder {
        root: json::Root::default(),
        bin: Vec::new(),
    };
    b.root.asset.generator = Some("glint examples/make_demo.rs".into());
    b.root.extensions_used = vec![
        "KHR_lights_punctual".into(),
        "KHR_materials_emissive_strength".into(),
    ];

    // Textures, embedded as PNG in the binary chunk. The checker uses nearest filtering so
    // its cells stay crisp when magnified; the others filter linearly.
    let checker = b.texture("checker", &checker_png()?, true);
    let tiles = b.texture("tile normals", &tile_normal_png()?, false);
    let lattice = b.texture("lattice alpha", &lattice_png()?, false);
    let info = |index| json::texture::Info {
        index,
        tex_coord: 0,
        extensions: None,
        extras: Default::default(),
    };

    // Materials. Albedos stay below ~0.8, as real diffuse surfaces do.
    let floor_material = b.material("floor", [0.8, 0.8, 0.8, 1.0], 0.0, 0.9);
    b.root.materials[floor_material.value()]
        .pbr_metallic_roughness
        .base_color_texture = Some(info(checker));
    let plinth = b.material("plinth", [0.35, 0.36, 0.38, 1.0], 0.0, 0.8);
    // The sphere rows: metallic 1 (gold) and 0 (red plastic), each at these roughnesses.
    // Roughness 0 is the exact mirror end of the same BSDF.
    let sphere_materials: Vec<_> = [(1.0, [0.95, 0.78, 0.45, 1.0]), (0.0, [0.7, 0.1, 0.08, 1.0])]
        .into_iter()
        .flat_map(|(metallic, colour)| {
            SPHERE_ROUGHNESS.map(|roughness| (metallic, colour, roughness))
        })
        .map(|(metallic, colour, roughness)| {
            let kind = if metallic > 0.5 { "gold" } else { "plastic" };
            b.material(&format!("{kind} r{roughness}"), colour, metallic, roughness)
        })
        .collect();
    // Glazed tiles: a normal map of bevelled tiles on a fairly smooth dielectric, so the
    // environment's highlights follow each bevel.
    let tile_wall = b.material("tiled wall", [0.2, 0.35, 0.45, 1.0], 0.0, 0.3);
    b.root.materials[tile_wall.value()].normal_texture = Some(json::material::NormalTexture {
        index: tiles,
        scale: 1.0,
        tex_coord: 0,
        extensions: None,
        extras: Default::default(),
    });
    // A perforated screen: alpha MASK cuts the holes, for camera and shadow rays alike.
    let screen = b.material("lattice screen", [0.25, 0.55, 0.3, 1.0], 0.0, 0.6);
    {
        let m = &mut b.root.materials[screen.value()];
        m.pbr_metallic_roughness.base_color_texture = Some(info(lattice));
        m.alpha_mode = Valid(json::material::AlphaMode::Mask);
        m.alpha_cutoff = Some(json::material::AlphaCutoff(0.5));
        m.double_sided = true;
    }
    let emitter = b.material("warm emitter", [0.05, 0.05, 0.05, 1.0], 0.0, 1.0);
    {
        let m = &mut b.root.materials[emitter.value()];
        // Radiance (W/(m²·sr)) = emissiveFactor × emissiveStrength. A Lambertian panel of
        // radiance L and area A lights a surface at distance d facing it with E ≈ πL·A/(πd²)
        // = L·A/d² for d² ≫ A: 8 × 0.9 m² at 1.5 m gives E ≈ 3.2 W/m² (red channel), a
        // radiance of about 0.8/π × 3.2 ≈ 0.8 on a facing surface: a warm pool of light.
        m.emissive_factor = json::material::EmissiveFactor([1.0, 0.6, 0.3]);
        m.double_sided = true;
        m.extensions = Some(json::extensions::material::Material {
            emissive_strength: Some(json::extensions::material::EmissiveStrength {
                emissive_strength: json::extensions::material::EmissiveStrengthFactor(8.0),
            }),
            ..Default::default()
        });
    }

    // Geometry, in object space; nodes place and size it. Boxes carry texture coordinates
    // in metres (times a density) so that textures keep their aspect on every face.
    let floor = b.geometry(&quad(FLOOR_HALF_SIZE_M, FLOOR_TEXTURE_REPEATS));
    let sphere = b.geometry(&unit_sphere(48, 24));
    let plinth_box = b.geometry(&cuboid(Vec3::new(4.4, PLINTH_HEIGHT_M, 0.7), 1.0));
    let wall_box = b.geometry(&cuboid(Vec3::new(2.0, 1.6, 0.12), TILES_PER_METRE));
    let screen_quad = b.geometry(&quad(0.5, LATTICE_REPEATS));
    let panel = b.geometry(&quad(0.5, 1.0));

    let floor_mesh = b.mesh("floor", &floor, floor_material);
    let plinth_mesh = b.mesh("plinth", &plinth_box, plinth);
    let wall_mesh = b.mesh("tiled wall", &wall_box, tile_wall);
    let screen_mesh = b.mesh("lattice screen", &screen_quad, screen);
    let panel_mesh = b.mesh("emissive panel", &panel, emitter);
    let sphere_meshes: Vec<_> = sphere_materials
        .iter()
        .enumerate()
        .map(|(k, &material)| b.mesh(&format!("sphere {k}"), &sphere, material))
        .collect();

    let mut nodes = Vec::new();
    let mut place = |b: &mut Builder, name: &str, mesh, t: Vec3, r: Quat, s: Vec3| {
        nodes.push(b.node(json::Node {
            name: Some(name.into()),
            mesh: Some(mesh),
            translation: Some(t.to_array()),
            rotation: Some(json::scene::UnitQuaternion(r.to_array())),
            scale: Some(s.to_array()),
            ..Default::default()
        }));
    };
    place(
        &mut b,
        "floor",
        floor_mesh,
        Vec3::ZERO,
        Quat::IDENTITY,
        Vec3::ONE,
    );
    // Metal row on the floor in front, plastic row behind it on a plinth so that both show.
    let columns = SPHERE_ROUGHNESS.len();
    for (k, &mesh) in sphere_meshes.iter().enumerate() {
        let (row, column) = (k / columns, k % columns);
        let x = (column as f32 - 0.5 * (columns - 1) as f32) * SPHERE_SPACING_M;
        let centre = if row == 0 {
            Vec3::new(x, SPHERE_RADIUS_M, 1.5)
        } else {
            Vec3::new(x, PLINTH_HEIGHT_M + SPHERE_RADIUS_M, 0.3)
        };
        place(
            &mut b,
            &format!("sphere {k}"),
            mesh,
            centre,
            Quat::IDENTITY,
            Vec3::splat(SPHERE_RADIUS_M),
        );
    }
    place(
        &mut b,
        "plinth",
        plinth_mesh,
        Vec3::new(0.0, 0.5 * PLINTH_HEIGHT_M, 0.3),
        Quat::IDENTITY,
        Vec3::ONE,
    );
    place(
        &mut b,
        "tiled wall",
        wall_mesh,
        Vec3::new(-1.7, 0.8, -1.5),
        Quat::from_rotation_y(0.35),
        Vec3::ONE,
    );
    // The quads lie in the xz plane facing +Y; stand them up facing the camera (+Z).
    let stand_up = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
    place(
        &mut b,
        "lattice screen",
        screen_mesh,
        Vec3::new(1.8, 0.85, -1.2),
        Quat::from_rotation_y(-0.4) * stand_up,
        Vec3::new(1.8, 1.0, 1.7),
    );
    place(
        &mut b,
        "emissive panel",
        panel_mesh,
        Vec3::new(0.1, 1.05, -2.3),
        stand_up,
        Vec3::new(1.2, 1.0, 0.75),
    );

    // Camera: in front, a little above, looking at the middle of the set.
    let camera = b.root.push(json::Camera {
        name: Some("demo camera".into()),
        orthographic: None,
        perspective: Some(json::camera::Perspective {
            aspect_ratio: None,
            yfov: 40f32.to_radians(),
            zfar: None,
            znear: 0.05,
            extensions: None,
            extras: Default::default(),
        }),
        type_: Valid(json::camera::Type::Perspective),
        extensions: None,
        extras: Default::default(),
    });
    let eye = Vec3::new(0.0, 2.3, 6.2);
    let target = Vec3::new(0.0, 0.55, -0.2);
    nodes.push(b.node(json::Node {
        name: Some("camera".into()),
        camera: Some(camera),
        translation: Some(eye.to_array()),
        rotation: Some(json::scene::UnitQuaternion(
            look_rotation(target - eye).to_array(),
        )),
        ..Default::default()
    }));

    // Lights (radiometric: W/sr for point and spot, W/m² for directional).
    use json::extensions::scene::khr_lights_punctual as punctual;
    let light =
        |name: &str, type_, color: [f32; 3], intensity: f32, spot: Option<punctual::Spot>| {
            punctual::Light {
                color,
                extensions: None,
                extras: Default::default(),
                intensity,
                name: Some(name.into()),
                range: None,
                spot,
                type_: Valid(type_),
            }
        };
    let lights = vec![
        // A floor point 2.5 m below gets E = 8/2.5² ≈ 1.3 W/m², radiance ≈ 0.8/π · 1.3 ≈ 0.3.
        light(
            "warm point",
            punctual::Type::Point,
            [1.0, 0.85, 0.7],
            8.0,
            None,
        ),
        // About 5 m from its target: E ≈ 30/25 = 1.2 W/m² inside the cone.
        light(
            "cool spot",
            punctual::Type::Spot,
            [0.75, 0.85, 1.0],
            30.0,
            Some(punctual::Spot {
                inner_cone_angle: 15f32.to_radians(),
                outer_cone_angle: 25f32.to_radians(),
            }),
        ),
        // A low sun from behind: E = 3 W/m² at normal incidence, radiance ≈ 0.8/π × 3 ≈ 0.8
        // on the floor where it faces the sun.
        light(
            "sun",
            punctual::Type::Directional,
            [1.0, 0.97, 0.92],
            3.0,
            None,
        ),
    ];
    b.root.extensions = Some(json::extensions::root::Root {
        khr_lights_punctual: Some(json::extensions::root::KhrLightsPunctual { lights }),
        ..Default::default()
    });
    let light_node = |b: &mut Builder, name: &str, index: u32, position: Vec3, towards: Vec3| {
        b.node(json::Node {
            name: Some(name.into()),
            translation: Some(position.to_array()),
            rotation: Some(json::scene::UnitQuaternion(
                look_rotation(towards).to_array(),
            )),
            extensions: Some(json::extensions::scene::Node {
                khr_lights_punctual: Some(
                    json::extensions::scene::khr_lights_punctual::KhrLightsPunctual {
                        light: json::Index::new(index),
                    },
                ),
                ..Default::default()
            }),
            ..Default::default()
        })
    };
    // The spot rakes the tiled wall from the front left.
    let spot_position = Vec3::new(-3.2, 3.4, 2.0);
    nodes.push(light_node(
        &mut b,
        "point light",
        0,
        Vec3::new(0.8, 2.5, 2.4),
        Vec3::NEG_Y,
    ));
    nodes.push(light_node(
        &mut b,
        "spot light",
        1,
        spot_position,
        Vec3::new(-1.7, 0.8, -1.5) - spot_position,
    ));
    nodes.push(light_node(
        &mut b,
        "sun",
        2,
        Vec3::new(0.0, 6.0, 0.0),
        // From behind the screen, so that its cut-out shadow falls forwards onto the floor.
        Vec3::new(-0.45, -1.0, 0.6),
    ));

    let scene = b.root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: Some("glint demo".into()),
        nodes,
    });
    b.root.scene = Some(scene);

    while !b.bin.len().is_multiple_of(4) {
        b.bin.push(0);
    }
    b.root.push(json::Buffer {
        byte_length: USize64::from(b.bin.len()),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let mut json_bytes = json::serialize::to_vec(&b.root)?;
    // GLB chunks are 4-byte aligned; JSON pads with spaces.
    while !json_bytes.len().is_multiple_of(4) {
        json_bytes.push(b' ');
    }
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: u32::try_from(12 + 8 + json_bytes.len() + 8 + b.bin.len())?,
        },
        json: json_bytes.into(),
        bin: Some(b.bin.into()),
    };
    Ok(glb.to_vec()?)
}

/// The rotation that turns a node's −Z (where glTF cameras and lights point) towards
/// `direction`, keeping its +Y as close to world up as possible.
fn look_rotation(direction: Vec3) -> Quat {
    let back = -direction.normalize();
    let up_hint = if back.y.abs() > 0.99 {
        Vec3::NEG_Z
    } else {
        Vec3::Y
    };
    let right = up_hint.cross(back).normalize();
    let up = back.cross(right);
    Quat::from_mat3(&glam::Mat3::from_cols(right, up, back))
}

/// A square in the xz plane, facing +Y, of half-size `half` with texture coordinates
/// running 0..`repeats`.
fn quad(half: f32, repeats: f32) -> Geometry {
    let corners = [(-1.0, 1.0), (1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)];
    Geometry {
        positions: corners
            .iter()
            .map(|&(x, z)| Vec3::new(x * half, 0.0, z * half))
            .collect(),
        normals: vec![Vec3::Y; 4],
        texcoords: corners
            .iter()
            .map(|&(x, z)| Vec2::new((x + 1.0) * 0.5 * repeats, (1.0 - z) * 0.5 * repeats))
            .collect(),
        // Counter-clockwise seen from +Y.
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

/// A box of the given size centred on the origin, with flat faces (4 vertices each, outward
/// normals) and texture coordinates of `uv_per_metre` per metre along each face.
fn cuboid(size: Vec3, uv_per_metre: f32) -> Geometry {
    let mut g = Geometry {
        positions: Vec::new(),
        normals: Vec::new(),
        texcoords: Vec::new(),
        indices: Vec::new(),
    };
    let half = 0.5 * size;
    for normal in [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ] {
        // Two axes spanning the face, with u × v = normal so the face winds outwards.
        let u = if normal.y.abs() > 0.5 {
            Vec3::X
        } else {
            Vec3::Y.cross(normal)
        };
        let v = normal.cross(u);
        // Face extents in metres along u and v (the axes are unit coordinate axes).
        let (width, height) = ((u * size).length(), (v * size).length());
        let base = u16::try_from(g.positions.len()).unwrap_or(u16::MAX);
        for (s, t) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
            g.positions
                .push(normal * half + s * width * u + t * height * v);
            g.normals.push(normal);
            g.texcoords.push(Vec2::new(
                (s + 0.5) * width * uv_per_metre,
                (0.5 - t) * height * uv_per_metre,
            ));
        }
        g.indices
            .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    g
}

/// A UV sphere of radius 1 with `segments` around and `rings` from pole to pole.
fn unit_sphere(segments: u16, rings: u16) -> Geometry {
    let mut g = Geometry {
        positions: Vec::new(),
        normals: Vec::new(),
        texcoords: Vec::new(),
        indices: Vec::new(),
    };
    for ring in 0..=rings {
        let v = f32::from(ring) / f32::from(rings);
        let theta = v * std::f32::consts::PI;
        for segment in 0..=segments {
            let u = f32::from(segment) / f32::from(segments);
            let phi = u * std::f32::consts::TAU;
            let p = Vec3::new(
                theta.sin() * phi.sin(),
                theta.cos(),
                theta.sin() * phi.cos(),
            );
            g.positions.push(p);
            g.normals.push(p);
            g.texcoords.push(Vec2::new(u, v));
        }
    }
    let row = segments + 1;
    for ring in 0..rings {
        for segment in 0..segments {
            let a = ring * row + segment;
            let b = a + row;
            // Counter-clockwise seen from outside.
            g.indices.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    g
}

/// A two-tone checker as PNG bytes (sRGB codes of a light and a mid grey).
fn checker_png() -> Result<Vec<u8>, image::ImageError> {
    let cell = CHECKER_TEXELS / CHECKER_CELLS;
    let image = image::RgbImage::from_fn(CHECKER_TEXELS, CHECKER_TEXELS, |x, y| {
        if (x / cell + y / cell).is_multiple_of(2) {
            image::Rgb([225, 225, 220])
        } else {
            image::Rgb([110, 112, 118])
        }
    });
    let mut png = Vec::new();
    image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
    Ok(png)
}

/// Bevelled square tiles as a tangent-space normal map (PNG, linear, glTF's convention: red
/// = +X along increasing u, green = +Y towards decreasing v, i.e. up in the image). The height
/// of a tile rises over a bevel of width `BEVEL` from each grout line and is flat inside, so
/// the normal tilts (by atan `SLOPE`) only near the edges; grout is flat too.
fn tile_normal_png() -> Result<Vec<u8>, image::ImageError> {
    const SIZE: u32 = 128;
    const CELLS: u32 = 4;
    const GROUT: f32 = 0.04;
    const BEVEL: f32 = 0.1;
    const SLOPE: f32 = 0.8;
    // Height along one axis of a cell (t in [0, 1)) and its derivative (per cell width).
    let profile = |t: f32| -> (f32, f32) {
        let edge = t.min(1.0 - t) - GROUT;
        if edge <= 0.0 {
            (0.0, 0.0)
        } else if edge < BEVEL {
            (edge / BEVEL, if t < 0.5 { 1.0 } else { -1.0 } / BEVEL)
        } else {
            (1.0, 0.0)
        }
    };
    let image = image::RgbImage::from_fn(SIZE, SIZE, |x, y| {
        let cell = |p: u32| ((p as f32 + 0.5) / SIZE as f32 * CELLS as f32).fract();
        let (hx, dx) = profile(cell(x));
        let (hy, dy) = profile(cell(y));
        // The tile's height is the lower of the two profiles (a bevelled square); its slope
        // comes from whichever profile is lower.
        let (dhdx, dhdy) = if hx < hy { (dx, 0.0) } else { (0.0, dy) };
        // The bevel's slope is SLOPE (rise over run): n ∝ (−∂h/∂x, +∂h/∂y, 1) with y growing
        // down the image, and ∂h/∂t = ±1/BEVEL on the bevel.
        let k = SLOPE * BEVEL;
        let n = Vec3::new(-dhdx * k, dhdy * k, 1.0).normalize();
        let code = |c: f32| (((c * 0.5 + 0.5) * 255.0).round()).clamp(0.0, 255.0) as u8;
        image::Rgb([code(n.x), code(n.y), code(n.z)])
    });
    let mut png = Vec::new();
    image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
    Ok(png)
}

/// A perforated lattice as RGBA PNG: round holes (alpha 0) in a grid, with a lighter rim
/// around each hole in the colour channels. Alpha is 0 or 255, so the MASK cut-off only
/// decides where the filtered edge falls.
fn lattice_png() -> Result<Vec<u8>, image::ImageError> {
    const SIZE: u32 = 64;
    const HOLE_RADIUS: f32 = 0.36;
    let image = image::RgbaImage::from_fn(SIZE, SIZE, |x, y| {
        let offset = |p: u32| (p as f32 + 0.5) / SIZE as f32 - 0.5;
        let r = offset(x).hypot(offset(y));
        if r < HOLE_RADIUS {
            image::Rgba([0, 0, 0, 0])
        } else if r < HOLE_RADIUS + 0.06 {
            image::Rgba([255, 255, 255, 255])
        } else {
            image::Rgba([200, 200, 200, 255])
        }
    });
    let mut png = Vec::new();
    image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
    Ok(png)
}

/// Writes the demo's environment map: `../shared/env/studio.hdr` (CC0, 1024×512) averaged
/// over 4×4 blocks to 256×128, which keeps the mean radiance (and so the light it casts)
/// while the file stays small. Returns false, writing nothing, where the source is absent
/// (the committed copy is then kept).
fn write_environment(root: &Path) -> Result<bool, Box<dyn std::error::Error>> {
    const FACTOR: u32 = 4;
    let source = root.join(ENV_SOURCE);
    if !source.exists() {
        return Ok(false);
    }
    let full = image::open(&source)?.to_rgb32f();
    let (width, height) = (full.width() / FACTOR, full.height() / FACTOR);
    let mut texels = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let mut sum = [0.0f64; 3];
            for dy in 0..FACTOR {
                for dx in 0..FACTOR {
                    let p = full.get_pixel(x * FACTOR + dx, y * FACTOR + dy);
                    for (s, c) in sum.iter_mut().zip(p.0) {
                        *s += f64::from(c.max(0.0));
                    }
                }
            }
            let n = f64::from(FACTOR * FACTOR);
            texels.push(image::Rgb(sum.map(|s| (s / n) as f32)));
        }
    }
    let mut bytes = Vec::new();
    image::codecs::hdr::HdrEncoder::new(&mut bytes).encode(
        &texels,
        width as usize,
        height as usize,
    )?;
    write_atomically(&root.join(ENV_OUTPUT), &bytes)?;
    println!("wrote {} ({} bytes)", ENV_OUTPUT, bytes.len());
    Ok(true)
}

/// Writes to a temporary file in the same folder, then renames it into place, so that a
/// reader never sees a half-written scene.
fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let folder = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(folder)?;
    let temporary = path.with_extension("glb.tmp");
    std::fs::write(&temporary, bytes)?;
    std::fs::rename(&temporary, path)
}
