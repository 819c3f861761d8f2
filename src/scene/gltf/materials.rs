//! glTF materials → [`Material`]s, and the textures they use → decoded [`Texture`]s.

use super::LoadError;
use super::limits::{self, MAX_EMISSION};
use super::normal_texture::{self, TextureSlot};
use super::source::{Origin, read_uri, view_bytes};
use crate::scene::ktx2_decode::{Ktx2Error, decode_ktx2, is_ktx2, probe};
use crate::scene::texture_decode::{ColorSpace, DecodedImage, decode_image, image_dimensions};
use crate::scene::{MagFilter, Material, Texture, TextureRef, WrapMode};
use glam::{Affine2, Vec2, Vec3, Vec4};
use rayon::prelude::*;
use std::collections::HashMap;
use std::collections::HashSet;

/// Every material of the file, index-aligned, plus the textures they reference.
pub struct Materials {
    /// One per glTF material, in file order.
    pub materials: Vec<Material>,
    /// The textures the materials reference.
    pub textures: Vec<Texture>,
}

/// A texture the materials need: which glTF texture, read in which colour space.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct TextureKey {
    texture: usize,
    space: ColorSpace,
}

/// Converts the document's materials and decodes the textures they use (base colour and
/// emissive, both sRGB; the metallic-roughness and normal maps, linear). Textures no supported channel uses are never decoded.
pub fn load(
    document: &::gltf::Document,
    buffers: &[Vec<u8>],
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
) -> Result<Materials, LoadError> {
    let mut keys: Vec<TextureKey> = Vec::new();
    let mut slots: HashMap<TextureKey, usize> = HashMap::new();
    let mut request = |slot: Option<TextureSlot>, space, channel: &str, material: &str| {
        let info = slot?;
        let mut transform = info.transform;
        if let Some(t) = &transform {
            let values = [t.offset[0], t.offset[1], t.rotation, t.scale[0], t.scale[1]];
            if !values.iter().all(|v| v.is_finite() && v.abs() <= 1e9) {
                warnings.push(format!(
                    "{}: {material}: {channel} texture's KHR_texture_transform has non-finite or absurd \
                     values {values:?}; the transform is ignored",
                    origin.file.display()
                ));
                transform = None;
            }
        }
        let texcoord = transform
            .as_ref()
            .and_then(|t| t.tex_coord)
            .unwrap_or(info.tex_coord) as usize;
        if texcoord > 1 {
            warnings.push(format!(
                "{}: {material}: {channel} texture reads TEXCOORD_{texcoord}; glint keeps TEXCOORD_0 and _1 only, \
                 so the texture is ignored",
                origin.file.display()
            ));
            return None;
        }
        let key = TextureKey {
            texture: info.texture,
            space,
        };
        let next = keys.len();
        let texture = *slots.entry(key).or_insert_with(|| {
            keys.push(key);
            next
        });
        Some(TextureRef {
            texture,
            texcoord,
            transform: transform.map_or(Affine2::IDENTITY, |t| {
                uv_transform(t.offset, t.rotation, t.scale)
            }),
        })
    };

    let mut materials = Vec::with_capacity(document.materials().len());
    // Clamping warnings, merged after `request` (which holds `warnings`) is done.
    let mut clamped = Vec::new();
    for material in document.materials() {
        let label = match (material.index(), material.name()) {
            (Some(i), Some(name)) => format!("material {i} \"{name}\""),
            (Some(i), None) => format!("material {i}"),
            (None, _) => "default material".to_string(),
        };
        let pbr = material.pbr_metallic_roughness();
        let mut factor = |value: f32, lo: f32, hi: f32, name: &str| {
            limits::clamp_factor(
                value,
                lo,
                hi,
                &format!("{label}: {name}"),
                origin,
                &mut clamped,
            )
        };
        // glTF bounds these factors to [0, 1]; a file outside (1e39 parses as +inf) would
        // otherwise put inf or NaN into the film.
        let base = pbr.base_color_factor();
        let base_color = Vec4::new(
            factor(base[0], 0.0, 1.0, "baseColorFactor[0]"),
            factor(base[1], 0.0, 1.0, "baseColorFactor[1]"),
            factor(base[2], 0.0, 1.0, "baseColorFactor[2]"),
            factor(base[3], 0.0, 1.0, "baseColorFactor[3]"),
        );
        let metallic = factor(pbr.metallic_factor(), 0.0, 1.0, "metallicFactor");
        let roughness = factor(pbr.roughness_factor(), 0.0, 1.0, "roughnessFactor");
        let e = material.emissive_factor();
        let emissive_factor = Vec3::new(
            factor(e[0], 0.0, 1.0, "emissiveFactor[0]"),
            factor(e[1], 0.0, 1.0, "emissiveFactor[1]"),
            factor(e[2], 0.0, 1.0, "emissiveFactor[2]"),
        );
        let emissive_strength = factor(
            material.emissive_strength().unwrap_or(1.0),
            0.0,
            MAX_EMISSION,
            "emissiveStrength",
        );
        // KHR_materials_pbrSpecularGlossiness, when present, replaces the core workflow.
        let spec_gloss = material
            .pbr_specular_glossiness()
            .map(|sg| super::specular_glossiness::read(&sg, &label, origin, &mut clamped));
        let surface = super::alpha::read(&material, &label, origin, &mut clamped);
        let layers = super::material_layers::read(
            &material,
            &label,
            origin,
            &mut clamped,
            &mut request,
            document.textures().len(),
        );
        let (base_color, base_texture, metallic, roughness, mr_texture) = match &spec_gloss {
            Some(sg) => (sg.base_color, sg.diffuse_texture, 0.0, sg.roughness, None),
            None => (
                base_color,
                pbr.base_color_texture().map(Into::into),
                metallic,
                roughness,
                pbr.metallic_roughness_texture().map(Into::into),
            ),
        };
        let (ior, specular, specular_color) = match &spec_gloss {
            Some(sg) => (super::specular_glossiness::IOR, 1.0, sg.specular_color),
            None => (
                material.ior().filter(|i| i.is_finite()).unwrap_or(1.5),
                material
                    .specular()
                    .map_or(1.0, |s| s.specular_factor())
                    .clamp(0.0, 1.0),
                material
                    .specular()
                    .map_or(Vec3::ONE, |s| Vec3::from(s.specular_color_factor()))
                    .max(Vec3::ZERO),
            ),
        };
        materials.push(Material {
            name: material
                .name()
                .map_or_else(|| label.clone(), str::to_string),
            base_color,
            base_color_texture: request(
                base_texture,
                ColorSpace::Srgb,
                if spec_gloss.is_some() {
                    "diffuse"
                } else {
                    "base colour"
                },
                &label,
            ),
            metallic,
            roughness,
            metallic_roughness_texture: request(
                mr_texture,
                ColorSpace::Linear,
                "metallic-roughness",
                &label,
            ),
            emissive: emissive_factor * emissive_strength,
            emissive_texture: request(
                material.emissive_texture().map(Into::into),
                ColorSpace::Srgb,
                "emissive",
                &label,
            ),
            double_sided: material.double_sided(),
            procedural: super::procedural::from_extras(material.extras(), &label, origin)?,
            ior,
            specular,
            specular_color,
            // RGB is a colour (sRGB in the file), A the linear glossiness: read as the base
            // colour texture is.
            specular_glossiness_texture: request(
                spec_gloss.and_then(|sg| sg.specular_glossiness_texture),
                ColorSpace::Srgb,
                "specular-glossiness",
                &label,
            ),
            alpha: surface.alpha,
            unlit: surface.unlit,
            normal_texture: normal_texture::read(
                &material,
                &mut request,
                &label,
                origin,
                &mut clamped,
            ),
            clearcoat: layers.clearcoat,
            sheen: layers.sheen,
            transmission: layers.transmission,
            diffuse_transmission: layers.diffuse_transmission,
            volume: layers.volume,
            anisotropy: layers.anisotropy,
        });
    }

    warnings.extend(clamped);
    let textures = decode_textures(document, buffers, &keys, origin, warnings)?;
    Ok(Materials {
        materials,
        textures,
    })
}

/// KHR_texture_transform as an affine map on texture coordinates, uv' = T · R · S · uv.
///
/// R is the rotation in glTF's UV space, whose v axis points down:
/// R = [[cos r, sin r], [−sin r, cos r]] (rows). The extension's GLSL listing shows the
/// transpose, which contradicts its own worked example and the sample model
/// TextureTransformTest (glTF issue #1563); the example and the implementations agree on
/// this form, which rotates by −r in a y-up frame.
pub fn uv_transform(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> Affine2 {
    Affine2::from_scale_angle_translation(Vec2::from(scale), -rotation, Vec2::from(offset))
}

/// Decodes each (texture, colour space) the materials need, each (image, colour space)
/// once, in parallel, and attaches each texture's sampler settings. A KHR_texture_basisu
/// texture reads its KTX2 image when that image can be used, else its core `source`
/// (see [`super::basisu`]).
fn decode_textures(
    document: &::gltf::Document,
    buffers: &[Vec<u8>],
    keys: &[TextureKey],
    origin: Origin<'_>,
    warnings: &mut Vec<String>,
) -> Result<Vec<Texture>, LoadError> {
    let textures: Vec<::gltf::Texture<'_>> = document.textures().collect();
    let images: Vec<::gltf::Image<'_>> = document.images().collect();
    let mut encoded: Encoded<'_> = HashMap::new();
    // The image each needed texture reads, with the encoded bytes read up front (I/O is
    // sequential; decoding is the expensive part and runs in parallel).
    let mut chosen: HashMap<usize, usize> = HashMap::new();
    // Images read as KTX2 whatever their first bytes say (a KHR_texture_basisu image in use).
    let mut ktx2_images: HashSet<usize> = HashSet::new();
    for key in keys {
        if chosen.contains_key(&key.texture) {
            continue;
        }
        // Validation guarantees texture indices are in range; `keys` holds only such indices.
        let texture = &textures[key.texture];
        let core = texture.source().index();
        let mut image = core;
        match super::basisu::basisu_image(texture, images.len()) {
            // No fallback: the KTX2 image is the texture's only image.
            Some(ktx2) if ktx2 == core => {
                ktx2_images.insert(ktx2);
            }
            Some(ktx2) => {
                read_image(&images, buffers, origin, ktx2, &mut encoded)?;
                // Read just above.
                let (label, bytes) = &encoded[&ktx2];
                match probe(bytes) {
                    Ok(_) => {
                        image = ktx2;
                        ktx2_images.insert(ktx2);
                    }
                    Err(problem) => warnings.push(format!(
                        "{}: texture {}: its {} {label} cannot be used ({problem}); the fallback {} is used instead",
                        origin.file.display(),
                        key.texture,
                        super::basisu::EXTENSION,
                        image_label(&texture.source()),
                    )),
                }
            }
            None => {}
        }
        read_image(&images, buffers, origin, image, &mut encoded)?;
        chosen.insert(key.texture, image);
    }
    let as_ktx2 =
        |image_index: usize, bytes: &[u8]| ktx2_images.contains(&image_index) || is_ktx2(bytes);
    // Each key's texture was given an image above.
    let image_of = |key: &TextureKey| chosen[&key.texture];
    // The first texture reading each image, to name it in KTX2 errors.
    let mut texture_of_image: HashMap<usize, usize> = HashMap::new();
    for key in keys {
        texture_of_image.entry(image_of(key)).or_insert(key.texture);
    }

    // The distinct (image, colour space) pairs.
    let mut image_keys: Vec<(usize, ColorSpace)> =
        keys.iter().map(|k| (image_of(k), k.space)).collect();
    image_keys.sort_by_key(|&(image, space)| (image, space == ColorSpace::Linear));
    image_keys.dedup();
    let ktx2_error = |image_index: usize, label: &str, problem: Ktx2Error| LoadError::Basisu {
        path: origin.file.to_path_buf(),
        texture: format!(
            "texture {}",
            texture_of_image.get(&image_index).copied().unwrap_or(0)
        ),
        image: label.to_string(),
        problem: problem.to_string(),
    };
    // Sizes from the headers, against the budgets, before anything is decoded.
    let mut total_pixels: u64 = 0;
    for &(image_index, _) in &image_keys {
        // Every image key's bytes were read above (or the load already failed).
        let (label, bytes) = &encoded[&image_index];
        let pixels = if as_ktx2(image_index, bytes) {
            check_ktx2_size(bytes, origin).map_err(|p| ktx2_error(image_index, label, p))?
        } else {
            check_image_size(bytes, label, origin)?
        };
        total_pixels = total_pixels.saturating_add(pixels);
        let budget = origin.options.max_total_texture_pixels();
        if total_pixels > budget {
            return Err(LoadError::Texture {
                path: origin.file.to_path_buf(),
                image: label.clone(),
                message: format!(
                    "the scene's textures add up to more than {budget} texels (4 × --max-texture-pixels); \
                     raise --max-texture-pixels or downscale the textures"
                ),
            });
        }
    }
    let max_pixels = origin.options.max_texture_pixels;
    let decoded: Vec<((usize, ColorSpace), DecodedImage, Vec<String>)> = image_keys
        .par_iter()
        .map(|&(image_index, space)| {
            // Every image key's bytes were read above (or the load already failed).
            let (label, bytes) = &encoded[&image_index];
            if as_ktx2(image_index, bytes) {
                return decode_ktx2(bytes, space, max_pixels)
                    .map(|(image, notes)| {
                        let notes = notes
                            .into_iter()
                            .map(|note| {
                                format!(
                                    "{}: {label} ({}): {note}",
                                    origin.file.display(),
                                    super::basisu::EXTENSION
                                )
                            })
                            .collect();
                        ((image_index, space), image, notes)
                    })
                    .map_err(|problem| ktx2_error(image_index, label, problem));
            }
            decode_image(bytes, space, max_pixels)
                .map(|image| ((image_index, space), image, Vec::new()))
                .map_err(|err| LoadError::Texture {
                    path: origin.file.to_path_buf(),
                    image: label.clone(),
                    message: super::error::one_line(&err.to_string()),
                })
        })
        .collect::<Result<_, _>>()?;
    let mut by_key: HashMap<(usize, ColorSpace), DecodedImage> = HashMap::new();
    for (key, image, notes) in decoded {
        warnings.extend(notes);
        by_key.insert(key, image);
    }

    Ok(keys
        .iter()
        .map(|key| {
            let texture = &textures[key.texture];
            let image_index = image_of(key);
            // Decoded above for every key's (image, colour space).
            let pixels = &by_key[&(image_index, key.space)];
            let sampler = texture.sampler();
            Texture {
                name: image_label(&images[image_index]),
                width: pixels.width,
                height: pixels.height,
                // Shares the decoded storage (no copy).
                texels: pixels.texels.clone(),
                wrap_s: wrap_mode(sampler.wrap_s()),
                wrap_t: wrap_mode(sampler.wrap_t()),
                mag_filter: match sampler.mag_filter() {
                    Some(::gltf::texture::MagFilter::Nearest) => MagFilter::Nearest,
                    Some(::gltf::texture::MagFilter::Linear) | None => MagFilter::Linear,
                },
            }
        })
        .collect())
}

/// Each image's label and encoded bytes, by image index.
type Encoded<'a> = HashMap<usize, (String, std::borrow::Cow<'a, [u8]>)>;

/// Reads image `image_index`'s encoded bytes into `encoded` (once).
fn read_image<'a>(
    images: &[::gltf::Image<'a>],
    buffers: &'a [Vec<u8>],
    origin: Origin<'_>,
    image_index: usize,
    encoded: &mut Encoded<'a>,
) -> Result<(), LoadError> {
    if encoded.contains_key(&image_index) {
        return Ok(());
    }
    // `image_index` came from a texture's source (which validation checked) or from a
    // KHR_texture_basisu index checked against the image count.
    let Some(image) = images.get(image_index) else {
        return Err(LoadError::Invalid {
            path: origin.file.to_path_buf(),
            message: format!(
                "image {image_index} does not exist (the file is corrupt; re-export it)"
            ),
        });
    };
    let label = image_label(image);
    let bytes = match image.source() {
        ::gltf::image::Source::View { view, .. } => {
            std::borrow::Cow::Borrowed(view_bytes(&view, buffers, &label, origin)?)
        }
        ::gltf::image::Source::Uri { uri, .. } => read_uri(uri, &label, origin)?,
    };
    encoded.insert(image_index, (label, bytes));
    Ok(())
}

/// A KTX2 image's texel count from its header, refused when over `--max-texture-pixels`.
fn check_ktx2_size(bytes: &[u8], origin: Origin<'_>) -> Result<u64, Ktx2Error> {
    let info = probe(bytes)?;
    let pixels = u64::from(info.width) * u64::from(info.height);
    let max = origin.options.max_texture_pixels;
    if pixels > max {
        return Err(Ktx2Error::TooLarge {
            width: info.width,
            height: info.height,
            pixels,
            max,
        });
    }
    Ok(pixels)
}

/// The image's texel count from its header, refused when over `--max-texture-pixels`.
fn check_image_size(bytes: &[u8], label: &str, origin: Origin<'_>) -> Result<u64, LoadError> {
    let fail = |message: String| LoadError::Texture {
        path: origin.file.to_path_buf(),
        image: label.to_string(),
        message,
    };
    let (width, height) =
        image_dimensions(bytes).map_err(|err| fail(super::error::one_line(&err.to_string())))?;
    let pixels = u64::from(width) * u64::from(height);
    let max = origin.options.max_texture_pixels;
    if pixels > max {
        return Err(fail(format!(
            "it is {width}×{height} = {pixels} texels, over the budget of {max} \
             (raise it with --max-texture-pixels {pixels}, or downscale the image)"
        )));
    }
    Ok(pixels)
}

fn image_label(image: &::gltf::Image<'_>) -> String {
    match (image.source(), image.name()) {
        (::gltf::image::Source::Uri { uri, .. }, _) if !uri.starts_with("data:") => {
            format!("image {} \"{uri}\"", image.index())
        }
        (_, Some(name)) => format!("image {} \"{name}\"", image.index()),
        _ => format!("image {}", image.index()),
    }
}

fn wrap_mode(mode: ::gltf::texture::WrappingMode) -> WrapMode {
    match mode {
        ::gltf::texture::WrappingMode::Repeat => WrapMode::Repeat,
        ::gltf::texture::WrappingMode::MirroredRepeat => WrapMode::MirroredRepeat,
        ::gltf::texture::WrappingMode::ClampToEdge => WrapMode::ClampToEdge,
    }
}
