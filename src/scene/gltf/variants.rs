//! KHR_materials_variants: named alternative materials per primitive. `--variant NAME`
//! ([`SceneSelection::variant`](super::SceneSelection::variant)) picks one; each primitive
//! whose `mappings` list that variant renders the mapped material, every other primitive its
//! own. Without a name, every primitive renders its default `material`, as the extension says.

use super::LoadError;
use super::source::Origin;

/// The variant names of `document`, in file order (empty without the extension).
pub fn names(document: &::gltf::Document) -> Vec<String> {
    document
        .variants()
        .map(|variants| variants.map(|v| v.name().to_string()).collect())
        .unwrap_or_default()
}

/// The index of the variant `name` names, or an error listing the file's variants; `None`
/// when no name is given.
pub fn select(
    document: &::gltf::Document,
    name: Option<&str>,
    origin: Origin<'_>,
) -> Result<Option<u32>, LoadError> {
    let Some(name) = name else {
        return Ok(None);
    };
    let names = names(document);
    match names.iter().position(|n| n == name) {
        Some(index) => Ok(u32::try_from(index).ok()),
        None => Err(LoadError::UnknownVariant {
            path: origin.file.to_path_buf(),
            name: name.to_string(),
            available: if names.is_empty() {
                "the file has no KHR_materials_variants variants".to_string()
            } else {
                let quoted: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
                format!("its variants are {}", quoted.join(", "))
            },
        }),
    }
}

/// The material `primitive` (of mesh `mesh`) renders under `variant`: the mapped one where a
/// mapping lists the variant, else `None` (the primitive's own material). A mapping to a
/// material the file lacks is an error naming the primitive.
pub fn material(
    primitive: &::gltf::Primitive<'_>,
    mesh: usize,
    variant: Option<u32>,
    origin: Origin<'_>,
) -> Result<Option<usize>, LoadError> {
    let Some(variant) = variant else {
        return Ok(None);
    };
    let Some(mapping) = primitive
        .mappings()
        .find(|m| m.variants().contains(&variant))
    else {
        return Ok(None);
    };
    // The gltf crate gives its default material (no index) for an index out of range.
    match mapping.material().index() {
        Some(index) => Ok(Some(index)),
        None => Err(LoadError::Invalid {
            path: origin.file.to_path_buf(),
            message: format!(
                "mesh {mesh} / primitive {}: KHR_materials_variants maps variant {variant} to a \
                 material that does not exist (the file is corrupt; re-export it)",
                primitive.index()
            ),
        }),
    }
}
