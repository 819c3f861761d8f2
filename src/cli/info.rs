//! `glint info FILE`: what a glTF file holds for writing jobs against it
//! ([`crate::scene::gltf::info`]), as text or (`--json`) as one JSON object on stdout.

use super::CliError;
use crate::scene::gltf::LoadOptions;
use crate::scene::gltf::info::{FileInfo, inspect};
use std::fmt::Write as _;
use std::path::PathBuf;

/// Arguments of `glint info`.
#[derive(clap::Args, Debug, Clone)]
pub struct InfoArgs {
    /// The .gltf or .glb file.
    pub file: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs `glint info`: the description on stdout; a file that cannot be read or parsed is the
/// loader's one-line error.
pub fn run(args: InfoArgs) -> Result<(), CliError> {
    let info = inspect(&args.file, &LoadOptions::default()).map_err(CliError::from_display)?;
    let text = if args.json {
        serde_json::to_string_pretty(&info).map_err(CliError::from_display)?
    } else {
        text(&info)
    };
    println!("{text}");
    Ok(())
}

/// `"name"`, or nothing.
fn named(name: &Option<String>) -> String {
    name.as_ref()
        .map_or_else(String::new, |n| format!(" \"{n}\""))
}

/// `a, b, c`, or `none`.
fn list(items: &[String]) -> String {
    if items.is_empty() {
        "none".to_string()
    } else {
        items.join(", ")
    }
}

/// The human-readable description.
fn text(info: &FileInfo) -> String {
    let mut out = String::new();
    // Writing to a String cannot fail.
    let _ = writeln!(out, "{}", info.file);
    let default = info
        .default_scene
        .map_or_else(|| "none".to_string(), |s| s.to_string());
    let _ = writeln!(out, "scenes: {} (default {default})", info.scenes.len());
    for s in &info.scenes {
        let _ = writeln!(out, "  {}{}: {} nodes", s.index, named(&s.name), s.nodes);
    }
    let _ = writeln!(out, "cameras: {}", info.cameras.len());
    for c in &info.cameras {
        let fov = c
            .yfov
            .map_or_else(String::new, |y| format!(", yfov {y:.4} rad"));
        let _ = writeln!(
            out,
            "  {}{}: {}{fov} (node {})",
            c.index,
            named(&c.name),
            c.kind,
            c.node
        );
    }
    let _ = writeln!(out, "lights: {}", info.lights.len());
    for l in &info.lights {
        let _ = writeln!(
            out,
            "  light {}{}: {} (node {})",
            l.light,
            named(&l.name),
            l.kind,
            l.node
        );
    }
    let _ = writeln!(out, "animations: {}", info.animations.len());
    for a in &info.animations {
        let range = match (a.start, a.end) {
            (Some(s), Some(e)) => format!("{s} to {e} s"),
            _ => "time range unknown".to_string(),
        };
        let _ = writeln!(
            out,
            "  {}{}: {range}, {} channels",
            a.index,
            named(&a.name),
            a.channels
        );
    }
    let quoted: Vec<String> = info.variants.iter().map(|v| format!("\"{v}\"")).collect();
    let _ = writeln!(out, "variants: {}", list(&quoted));
    let _ = writeln!(out, "extensions read: {}", list(&info.extensions.read));
    let _ = writeln!(
        out,
        "extensions ignored: {}",
        list(&info.extensions.ignored)
    );
    let _ = writeln!(
        out,
        "extensions refused: {}",
        list(&info.extensions.refused)
    );
    let _ = write!(
        out,
        "triangles: {} (default scene); meshes {}, materials {}, textures {}, images {}",
        info.triangles, info.meshes, info.materials, info.textures, info.images
    );
    out
}
