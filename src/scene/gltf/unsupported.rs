//! The refusal for required extensions glint cannot honour: every missing extension named
//! in one line, with a way to convert the file for the ones that have a known fix.

use super::LoadError;
use super::source::{Origin, SUPPORTED_EXTENSIONS};

/// What to do about one unsupported extension, where there is something better to say
/// than "re-export without it".
fn advice(extension: &str) -> Option<&'static str> {
    Some(match extension {
        "EXT_meshopt_compression" => {
            "meshopt-compressed geometry: rebuild glint with its `meshopt` feature (on by default; it needs \
             a C++ compiler), or decompress with `gltfpack -i IN.glb -o OUT.glb` (no `-c`)"
        }
        _ => return None,
    })
}

/// `A`, `A and B`, `A, B and C`.
fn join_names(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_string(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// The error for a file whose `extensionsRequired` lists `missing` (non-empty), naming them
/// all so that one round of conversion fixes the file.
pub fn error(missing: &[&str], origin: Origin<'_>) -> LoadError {
    let extension = match missing {
        [one] => format!("extension {one}"),
        several => format!("extensions {}", join_names(several)),
    };
    let mut hints: Vec<String> = missing
        .iter()
        .filter_map(|e| advice(e).map(|a| format!("{e} is {a}")))
        .collect();
    if hints.len() < missing.len() {
        hints.push("re-export the scene without the others".to_string());
    }
    LoadError::UnsupportedExtension {
        path: origin.file.to_path_buf(),
        extension,
        supported: SUPPORTED_EXTENSIONS.join(", "),
        advice: hints.join("; "),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn every_missing_extension_is_named_on_one_line() {
        let options = crate::scene::gltf::LoadOptions::default();
        let origin = Origin {
            file: Path::new("x.glb"),
            files: crate::scene::gltf::source::Files::None,
            options: &options,
        };
        let message = error(&["EXT_meshopt_compression", "EXT_bar", "EXT_foo"], origin).to_string();
        assert!(!message.contains('\n'));
        assert!(
            message.contains("requires extensions EXT_meshopt_compression, EXT_bar and EXT_foo")
        );
        assert!(message.contains("gltfpack") && message.contains("without the others"));
        let single = error(&["EXT_foo"], origin).to_string();
        assert!(single.contains("requires extension EXT_foo,"));
    }
}
