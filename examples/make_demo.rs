//! Writes `scenes/demo.glb`, the demo scene embedded in glint (`glint render` without a
//! scene renders it).
//!
//! ```text
//! cargo run --example make_demo
//! ```
//!
//! The scene (metres, +Y up): a checker-textured floor, a red and a green box and a blue
//! sphere (diffuse), a mirror sphere (metallic 1, roughness 0), a small warm emissive panel
//! (KHR_materials_emissive_strength), a camera node, and one light of each
//! KHR_lights_punctual type. Intensities are radiometric and chosen so that lit diffuse
//! surfaces have radiances of about 0.1–1 W/(m²·sr): a point light of I W/sr at distance d
//! gives a surface of albedo ρ facing it the radiance ρ/π · I/d².

use glam::{Quat, Vec2, Vec3};
use gltf::json;
use json::validation::{Checked::Valid, USize64};
use std::path::Path;

/// Where the scene is written, relative to the crate root.
const OUTPUT: &str = "scenes/demo.glb";

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

    // Checker texture, embedded as PNG in the binary chunk; nearest filtering keeps the
    // cells crisp when magnified.
    let png = checker_png()?;
    let png_view = b.view(&png, None);
    let image = b.root.push(json::Image {
        buffer_view: Some(png_view),
        mime_type: Some(json::image::MimeType("image/png".into())),
        name: Some("checker".into()),
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let sampler = b.root.push(json::texture::Sampler {
        mag_filter: Some(Valid(json::texture::MagFilter::Nearest)),
        wrap_s: Valid(json::texture::WrappingMode::Repeat),
        wrap_t: Valid(json::texture::WrappingMode::Repeat),
        ..Default::default()
    });
    let texture = b.root.push(json::Texture {
        name: Some("checker".into()),
        sampler: Some(sampler),
        source: image,
        extensions: None,
        extras: Default::default(),
    });

    // Materials. Albedos stay below ~0.8, as real diffuse surfaces do.
    let floor_material = b.material("floor", [0.8, 0.8, 0.8, 1.0], 0.0, 0.9);
    b.root.materials[floor_material.value()]
        .pbr_metallic_roughness
        .base_color_texture = Some(json::texture::Info {
        index: texture,
        tex_coord: 0,
        extensions: None,
        extras: Default::default(),
    });
    let red = b.material("red diffuse", [0.7, 0.12, 0.1, 1.0], 0.0, 1.0);
    let green = b.material("green diffuse", [0.15, 0.55, 0.2, 1.0], 0.0, 1.0);
    let blue = b.material("blue diffuse", [0.12, 0.25, 0.7, 1.0], 0.0, 1.0);
    let mirror = b.material("mirror", [0.95, 0.95, 0.95, 1.0], 1.0, 0.0);
    let emitter = b.material("warm emitter", [0.05, 0.05, 0.05, 1.0], 0.0, 1.0);
    {
        let m = &mut b.root.materials[emitter.value()];
        // Radiance (W/(m²·sr)) = emissiveFactor × emissiveStrength: a few times brighter
        // than the lit surfaces, as a lamp panel is.
        m.emissive_factor = json::material::EmissiveFactor([1.0, 0.6, 0.3]);
        m.double_sided = true;
        m.extensions = Some(json::extensions::material::Material {
            emissive_strength: Some(json::extensions::material::EmissiveStrength {
                emissive_strength: json::extensions::material::EmissiveStrengthFactor(4.0),
            }),
            ..Default::default()
        });
    }

    // Geometry, in object space; nodes place and size it.
    let floor = b.geometry(&quad(FLOOR_HALF_SIZE_M, FLOOR_TEXTURE_REPEATS));
    let cube = b.geometry(&unit_cube());
    let sphere = b.geometry(&unit_sphere(48, 24));
    let panel = b.geometry(&quad(0.5, 1.0));

    let floor_mesh = b.mesh("floor", &floor, floor_material);
    let red_box = b.mesh("red box", &cube, red);
    let green_box = b.mesh("green box", &cube, green);
    let blue_sphere = b.mesh("blue sphere", &sphere, blue);
    let mirror_sphere = b.mesh("mirror sphere", &sphere, mirror);
    let panel_mesh = b.mesh("emissive panel", &panel, emitter);

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
    place(
        &mut b,
        "red box",
        red_box,
        Vec3::new(-1.7, 0.4, 0.6),
        Quat::from_rotation_y(0.5),
        Vec3::splat(0.8),
    );
    place(
        &mut b,
        "green box",
        green_box,
        Vec3::new(1.7, 0.75, -0.9),
        Quat::from_rotation_y(-0.3),
        Vec3::new(0.6, 1.5, 0.6),
    );
    place(
        &mut b,
        "blue sphere",
        blue_sphere,
        Vec3::new(0.6, 0.5, 1.3),
        Quat::IDENTITY,
        Vec3::splat(0.5),
    );
    place(
        &mut b,
        "mirror sphere",
        mirror_sphere,
        Vec3::new(-0.3, 0.9, -1.2),
        Quat::IDENTITY,
        Vec3::splat(0.9),
    );
    // The panel quad lies in the xz plane facing +Y; stand it up facing the camera (+Z).
    place(
        &mut b,
        "emissive panel",
        panel_mesh,
        Vec3::new(0.4, 1.6, -3.0),
        Quat::from_rotation_x(std::f32::consts::FRAC_PI_2),
        Vec3::new(1.4, 1.0, 0.7),
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
    let eye = Vec3::new(0.0, 2.4, 7.0);
    let target = Vec3::new(0.0, 0.7, -0.3);
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
        // A soft fill from above: E = 1 W/m² at normal incidence.
        light(
            "sky fill",
            punctual::Type::Directional,
            [1.0, 0.97, 0.92],
            1.0,
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
    let spot_position = Vec3::new(-2.8, 3.8, 2.2);
    nodes.push(light_node(
        &mut b,
        "point light",
        0,
        Vec3::new(1.8, 2.5, 1.6),
        Vec3::NEG_Y,
    ));
    nodes.push(light_node(
        &mut b,
        "spot light",
        1,
        spot_position,
        Vec3::new(-1.0, 0.3, -0.4) - spot_position,
    ));
    nodes.push(light_node(
        &mut b,
        "sun",
        2,
        Vec3::new(0.0, 6.0, 0.0),
        Vec3::new(0.35, -1.0, -0.45),
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

/// The cube [−0.5, 0.5]³ with flat faces (4 vertices each, outward normals).
fn unit_cube() -> Geometry {
    let mut g = Geometry {
        positions: Vec::new(),
        normals: Vec::new(),
        texcoords: Vec::new(),
        indices: Vec::new(),
    };
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
        let base = u16::try_from(g.positions.len()).unwrap_or(u16::MAX);
        for (s, t) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
            g.positions.push(0.5 * normal + s * u + t * v);
            g.normals.push(normal);
            g.texcoords.push(Vec2::new(s + 0.5, 0.5 - t));
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

/// Writes to a temporary file in the same folder, then renames it into place, so that a
/// reader never sees a half-written scene.
fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let folder = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(folder)?;
    let temporary = path.with_extension("glb.tmp");
    std::fs::write(&temporary, bytes)?;
    std::fs::rename(&temporary, path)
}
