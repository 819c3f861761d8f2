//! `[[sweep]]`: one table that expands into many jobs.
//!
//! - A key given a list of values (`spp = [1, 4, 16]`) is swept: one job per value. Keys that
//!   take a list anyway (`light`, `aov`) are not swept.
//! - `orbit = { frames = K, center = [x, y, z], radius = R, height = H, up = [0, 1, 0],
//!   yfov = RADIANS }` is a turntable: K cameras on a circle of radius R around `center`,
//!   lifted H along `up`, looking at `center`. Frame k sits at angle 2πk/K, turning right-handed
//!   about `up` from the `+Z` side (the side a glTF camera looks from by default; for
//!   `up` along Z it starts from `+X`).
//!
//! Several swept keys give their cartesian product: keys in alphabetical order, the first
//! varying slowest, the orbit's frame fastest. The `output` names each job through
//! placeholders: `{key}` is the job's value (for `scene`, the file's stem), `{frame}` the
//! frame number, and `{key:03}` pads a number with zeros to 3 digits. Every key that takes
//! more than one value must appear in the output, so that no two jobs write the same file.

use glam::Vec3;
use std::f32::consts::TAU;
use toml::{Table, Value};

/// One job of a sweep.
#[derive(Clone, Debug)]
pub struct Variant {
    /// The job's keys, without lists or `orbit`.
    pub table: Table,
    /// What distinguishes it, e.g. `spp=4, frame=2`.
    pub label: String,
}

/// A swept dimension: its placeholder name and its values (with the text each puts in the
/// output name).
struct Dimension {
    key: String,
    values: Vec<(Value, String)>,
}

/// Expands one `[[sweep]]` table. `is_list_option` says which keys take a list as their value.
pub fn expand(
    table: &Table,
    is_list_option: impl Fn(&str) -> bool,
) -> Result<Vec<Variant>, String> {
    let mut base = Table::new();
    let mut dimensions = Vec::new();
    for (key, value) in table {
        match (key.as_str(), value) {
            ("orbit", _) => {}
            (k, Value::Array(items)) if !is_list_option(k) => {
                if items.is_empty() {
                    return Err(format!("key \"{k}\": the list of values to sweep is empty"));
                }
                let values = items
                    .iter()
                    .map(|v| (v.clone(), placeholder_text(k, v)))
                    .collect();
                dimensions.push(Dimension {
                    key: k.to_string(),
                    values,
                });
            }
            _ => {
                base.insert(key.clone(), value.clone());
            }
        }
    }
    let frames = match table.get("orbit") {
        None => None,
        Some(Value::Table(orbit)) => {
            if table.contains_key("camera") {
                return Err("has both orbit and camera: the orbit places the camera".into());
            }
            let cameras = orbit_cameras(orbit).map_err(|m| format!("key \"orbit\": {m}"))?;
            Some(cameras)
        }
        Some(_) => {
            return Err("key \"orbit\" must be a table { frames, center, radius, ... }".into());
        }
    };
    if let Some(cameras) = frames {
        dimensions.push(Dimension {
            key: "frame".into(),
            values: cameras
                .into_iter()
                .enumerate()
                .map(|(k, camera)| (camera, k.to_string()))
                .collect(),
        });
    }

    let output = match base.get("output") {
        Some(Value::String(s)) => Some(s.clone()),
        _ => None,
    };
    if let Some(output) = &output {
        for d in dimensions.iter().filter(|d| d.values.len() > 1) {
            if !has_placeholder(output, &d.key) {
                return Err(format!(
                    "output \"{output}\" must contain {{{}}}: the sweep gives {} values of {}, \
                     and each needs its own file",
                    d.key,
                    d.values.len(),
                    d.key
                ));
            }
        }
    }

    // Each variant: its table and the (key, text) of every swept dimension.
    let mut variants: Vec<(Table, Vec<(&str, &str)>)> = vec![(base, Vec::new())];
    for d in &dimensions {
        let mut next = Vec::with_capacity(variants.len() * d.values.len());
        for (table, texts) in &variants {
            for (value, text) in &d.values {
                let mut table = table.clone();
                let target = if d.key == "frame" { "camera" } else { &d.key };
                table.insert(target.to_string(), value.clone());
                let mut texts = texts.clone();
                texts.push((d.key.as_str(), text.as_str()));
                next.push((table, texts));
            }
        }
        variants = next;
    }
    variants
        .into_iter()
        .map(|(mut table, texts)| {
            if let Some(output) = &output {
                let mut name = output.clone();
                for (key, text) in &texts {
                    name = fill(&name, key, text)?;
                }
                table.insert("output".into(), Value::String(name));
            }
            let label = texts
                .iter()
                .map(|(key, text)| format!("{key}={text}"))
                .collect::<Vec<_>>()
                .join(", ");
            Ok(Variant { table, label })
        })
        .collect()
}

/// The text a value puts into an output name.
fn placeholder_text(key: &str, value: &Value) -> String {
    match value {
        Value::String(s) if key == "scene" => std::path::Path::new(s)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| s.clone()),
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

fn has_placeholder(template: &str, key: &str) -> bool {
    template.contains(&format!("{{{key}}}")) || template.contains(&format!("{{{key}:"))
}

/// Replaces `{key}` and `{key:0N}` in `template` by `text` (zero-padded to N for the latter).
fn fill(template: &str, key: &str, text: &str) -> Result<String, String> {
    let mut out = template.replace(&format!("{{{key}}}"), text);
    let open = format!("{{{key}:");
    while let Some(start) = out.find(&open) {
        let rest = &out[start + open.len()..];
        let end = rest
            .find('}')
            .ok_or_else(|| format!("output \"{template}\": unclosed {{{key}:"))?;
        let spec = &rest[..end];
        let width: usize = spec
            .strip_prefix('0')
            .and_then(|w| w.parse().ok())
            .ok_or_else(|| {
                format!("output \"{template}\": {{{key}:{spec}}} is not a zero padding like {{{key}:03}}")
            })?;
        let padded = format!("{text:0>width$}");
        out = format!("{}{padded}{}", &out[..start], &rest[end + 1..]);
    }
    Ok(out)
}

/// The camera tables of an orbit.
fn orbit_cameras(orbit: &Table) -> Result<Vec<Value>, String> {
    for key in orbit.keys() {
        if !["frames", "center", "radius", "height", "up", "yfov"].contains(&key.as_str()) {
            return Err(format!(
                "unknown key \"{key}\"; an orbit has frames, center, radius, height, up, yfov"
            ));
        }
    }
    let number = |key: &str| -> Result<Option<f64>, String> {
        match orbit.get(key) {
            None => Ok(None),
            Some(Value::Integer(i)) => Ok(Some(*i as f64)),
            Some(Value::Float(f)) if f.is_finite() => Ok(Some(*f)),
            Some(_) => Err(format!("{key} must be a number")),
        }
    };
    let vector = |key: &str| -> Result<Option<Vec3>, String> {
        let Some(value) = orbit.get(key) else {
            return Ok(None);
        };
        let n: Option<Vec<f32>> = value.as_array().filter(|a| a.len() == 3).and_then(|a| {
            a.iter()
                .map(|v| match v {
                    Value::Integer(i) => Some(*i as f32),
                    Value::Float(f) => Some(*f as f32),
                    _ => None,
                })
                .collect()
        });
        match n {
            Some(n) => Ok(Some(Vec3::new(n[0], n[1], n[2]))),
            None => Err(format!("{key} must be [x, y, z]")),
        }
    };
    let frames = match orbit.get("frames") {
        Some(Value::Integer(k)) if *k >= 1 && *k <= 1_000_000 => *k as usize,
        _ => return Err("needs frames = K, a whole number of at least 1".into()),
    };
    let center = vector("center")?.ok_or("needs center = [x, y, z]")?;
    let radius = number("radius")?.ok_or("needs radius = R (scene units)")? as f32;
    if radius <= 0.0 {
        return Err("radius must be positive".into());
    }
    let height = number("height")?.unwrap_or(0.0) as f32;
    let up = vector("up")?.unwrap_or(Vec3::Y).normalize_or_zero();
    if up == Vec3::ZERO {
        return Err("up must not be the zero vector".into());
    }
    // The start direction: +Z unless up is (nearly) along Z, then +X; made perpendicular.
    let seed = if up.z.abs() < 0.9 { Vec3::Z } else { Vec3::X };
    let e1 = (seed - up * seed.dot(up)).normalize();
    let e2 = up.cross(e1);
    let mut cameras = Vec::with_capacity(frames);
    for k in 0..frames {
        let angle = TAU * k as f32 / frames as f32;
        let position = center + radius * (angle.cos() * e1 + angle.sin() * e2) + height * up;
        let array = |v: Vec3| {
            Value::Array(vec![
                Value::Float(v.x as f64),
                Value::Float(v.y as f64),
                Value::Float(v.z as f64),
            ])
        };
        let mut camera = Table::new();
        camera.insert("position".into(), array(position));
        camera.insert("look_at".into(), array(center));
        camera.insert("up".into(), array(up));
        if let Some(yfov) = number("yfov")? {
            camera.insert("yfov".into(), Value::Float(yfov));
        }
        cameras.push(Value::Table(camera));
    }
    Ok(cameras)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sweep(text: &str) -> Result<Vec<Variant>, String> {
        expand(&text.parse::<Table>().unwrap(), |k| k == "aov")
    }

    #[test]
    fn lists_give_a_cartesian_product_named_by_placeholders() {
        let v = sweep(
            r#"output = "o-{seed}-{spp:03}.png"
               spp = [1, 16]
               seed = [7, 8, 9]
               aov = ["depth"]"#,
        )
        .unwrap();
        let names: Vec<_> = v
            .iter()
            .map(|v| v.table["output"].as_str().unwrap().to_string())
            .collect();
        assert_eq!(
            names,
            [
                "o-7-001.png",
                "o-7-016.png",
                "o-8-001.png",
                "o-8-016.png",
                "o-9-001.png",
                "o-9-016.png"
            ]
        );
        assert!(v.iter().all(|v| v.table["aov"].is_array()));
        assert_eq!(v[1].table["spp"].as_integer(), Some(16));
    }

    #[test]
    fn an_output_without_the_swept_key_is_rejected() {
        let err = sweep("output = \"same.png\"\nspp = [1, 2]").unwrap_err();
        assert!(err.contains("{spp}"), "{err}");
    }

    #[test]
    fn orbit_frames_lie_on_the_circle_and_look_at_the_centre() {
        let v = sweep(
            r#"output = "f{frame:02}.png"
               orbit = { frames = 4, center = [1, 2, 3], radius = 2, height = 0.5 }"#,
        )
        .unwrap();
        assert_eq!(v.len(), 4);
        assert_eq!(v[3].table["output"].as_str(), Some("f03.png"));
        let centre = Vec3::new(1.0, 2.0, 3.0);
        let mut positions = Vec::new();
        for variant in &v {
            let cam = variant.table["camera"].as_table().unwrap();
            let p: Vec<f32> = cam["position"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_float().unwrap() as f32)
                .collect();
            let p = Vec3::new(p[0], p[1], p[2]);
            let offset = p - centre;
            assert!((offset.y - 0.5).abs() < 1e-5);
            assert!((offset.with_y(0.0).length() - 2.0).abs() < 1e-5);
            positions.push(offset.with_y(0.0));
        }
        // Frame 0 on +Z, quarter turns right-handed about +Y: +Z → +X → −Z → −X.
        let expected = [Vec3::Z, Vec3::X, -Vec3::Z, -Vec3::X].map(|d| d * 2.0);
        for (p, e) in positions.iter().zip(expected) {
            assert!(p.distance(e) < 1e-5, "{p} vs {e}");
        }
    }
}
