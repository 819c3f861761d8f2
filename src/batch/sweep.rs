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
//! - `frames = "A..B"` (end exclusive, like Rust ranges: `"0..120"` is 120 frames, 0 to 119)
//!   or a list of frame numbers, with `fps = F`: an animation, one job per frame k at
//!   `time = k / F` seconds. With an orbit as well, the two must have as many frames and go
//!   together: frame k has the orbit's camera k and the time of the k-th frame number (a
//!   turntable of an animated model).
//!
//! Several swept keys give their cartesian product: keys in alphabetical order, the first
//! varying slowest, the frame (orbit and/or animation) fastest. The `output` names each job through
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

/// A swept dimension: its placeholder name and its values: the keys each sets, with the
/// text it puts in the output name.
struct Dimension {
    key: String,
    values: Vec<(Vec<(String, Value)>, String)>,
}

/// Most frames one sweep may have (as for an orbit).
const MAX_FRAMES: i64 = 1_000_000;

/// Most jobs one job file may hold, its `[[job]]` tables and its sweeps' products together:
/// as many as the longest frame sweep. A file is refused by this count, computed with checked
/// arithmetic before any sweep is expanded, so that a product of a few long lists is never
/// materialised.
pub const MAX_JOBS: usize = 1_000_000;

/// Widest zero padding `{key:0N}` an output may ask for: 255, the longest file name most file
/// systems allow (Rust's formatter itself panics on widths above 65,535).
pub const MAX_PAD_WIDTH: usize = 255;

/// One `[[sweep]]` table, checked but not expanded: its jobs are made one at a time, by index,
/// so that a job file can be checked whole (counts, output names) before any is.
pub struct Sweep {
    /// The keys every job of the sweep shares.
    base: Table,
    /// The swept dimensions, the first varying slowest.
    dimensions: Vec<Dimension>,
    /// The sweep's own `output` template, if it has one.
    output: Option<String>,
    /// How many jobs the sweep gives (the product of the dimensions' lengths).
    len: usize,
}

/// Expands one `[[sweep]]` table. `is_list_option` says which keys take a list as their value.
pub fn expand(
    table: &Table,
    is_list_option: impl Fn(&str) -> bool,
) -> Result<Vec<Variant>, String> {
    let sweep = plan(table, is_list_option)?;
    (0..sweep.len()).map(|index| sweep.variant(index)).collect()
}

/// Checks one `[[sweep]]` table without expanding it: its keys, its frames, its output
/// template (every swept key named, paddings at most [`MAX_PAD_WIDTH`]) and its job count (at
/// most [`MAX_JOBS`]). `is_list_option` says which keys take a list as their value.
pub fn plan(table: &Table, is_list_option: impl Fn(&str) -> bool) -> Result<Sweep, String> {
    let mut base = Table::new();
    let mut dimensions = Vec::new();
    for (key, value) in table {
        match (key.as_str(), value) {
            ("orbit" | "frames" | "fps", _) => {}
            (k, Value::Array(items)) if !is_list_option(k) => {
                if items.is_empty() {
                    return Err(format!("key \"{k}\": the list of values to sweep is empty"));
                }
                let values = items
                    .iter()
                    .map(|v| (vec![(k.to_string(), v.clone())], placeholder_text(k, v)))
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
    if let Some(frame) = frame_dimension(table)? {
        dimensions.push(frame);
    }
    let output = match base.get("output") {
        Some(Value::String(s)) => Some(s.clone()),
        _ => None,
    };
    if let Some(output) = &output {
        check_template(output, &dimensions)?;
    }
    let len = job_count(&dimensions)?;
    Ok(Sweep {
        base,
        dimensions,
        output,
        len,
    })
}

/// The frame dimension of an orbit and/or `frames`, if the sweep has either.
fn frame_dimension(table: &Table) -> Result<Option<Dimension>, String> {
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
    let animation = animation_frames(table)?;
    let values = match (frames, animation) {
        (None, None) => return Ok(None),
        (Some(cameras), None) => cameras
            .into_iter()
            .enumerate()
            .map(|(k, camera)| (vec![("camera".to_string(), camera)], k.to_string()))
            .collect(),
        (None, Some(times)) => times
            .into_iter()
            .map(|(frame, time)| {
                let mut values = vec![("time".to_string(), time)];
                values.extend(frame_interval(table));
                (values, frame.to_string())
            })
            .collect(),
        (Some(cameras), Some(times)) => {
            if cameras.len() != times.len() {
                return Err(format!(
                    "the orbit has {} frames but frames gives {}: with both, frame k takes \
                     the orbit's camera k and the animation's frame k, so give them as many",
                    cameras.len(),
                    times.len()
                ));
            }
            cameras
                .into_iter()
                .zip(times)
                .map(|(camera, (frame, time))| {
                    (
                        [("camera".to_string(), camera), ("time".to_string(), time)]
                            .into_iter()
                            .chain(frame_interval(table))
                            .collect(),
                        frame.to_string(),
                    )
                })
                .collect()
        }
    };
    Ok(Some(Dimension {
        key: "frame".into(),
        values,
    }))
}

/// Checks an output template against the sweep's dimensions: every key with more than one
/// value appears, and every `{key:0N}` of a swept key is closed and pads to at most
/// [`MAX_PAD_WIDTH`].
fn check_template(output: &str, dimensions: &[Dimension]) -> Result<(), String> {
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
    for d in dimensions {
        let open = format!("{{{}:", d.key);
        let mut rest = output;
        while let Some(start) = rest.find(&open) {
            rest = &rest[start + open.len()..];
            let end = rest
                .find('}')
                .ok_or_else(|| format!("output \"{output}\": unclosed {open}"))?;
            pad_width(output, &d.key, &rest[..end])?;
            rest = &rest[end + 1..];
        }
    }
    Ok(())
}

/// The width of a zero padding `spec` (`03` in `{key:03}`), at most [`MAX_PAD_WIDTH`].
fn pad_width(template: &str, key: &str, spec: &str) -> Result<usize, String> {
    let width: usize = spec
        .strip_prefix('0')
        .and_then(|w| w.parse().ok())
        .ok_or_else(|| {
            format!(
                "output \"{template}\": {{{key}:{spec}}} is not a zero padding like {{{key}:03}}"
            )
        })?;
    if width > MAX_PAD_WIDTH {
        return Err(format!(
            "output \"{template}\": {{{key}:{spec}}} pads key \"{key}\" to width {width}, more than \
             the {MAX_PAD_WIDTH} glint accepts (no file name is longer); use a width like {{{key}:04}}"
        ));
    }
    Ok(width)
}

/// The number of jobs `dimensions` give (their product), refused above [`MAX_JOBS`]; computed
/// with checked arithmetic, so that no product overflows.
fn job_count(dimensions: &[Dimension]) -> Result<usize, String> {
    let count = dimensions
        .iter()
        .try_fold(1usize, |n, d| n.checked_mul(d.values.len()));
    match count {
        Some(count) if count <= MAX_JOBS => Ok(count),
        _ => {
            let factors: Vec<String> = dimensions
                .iter()
                .map(|d| format!("{} ({})", d.key, d.values.len()))
                .collect();
            let total = count.map_or_else(|| "more than 2^64".to_string(), |n| n.to_string());
            Err(format!(
                "gives {total} jobs ({}), more than the {MAX_JOBS} a job file may hold \
                 (sweep fewer values, or split the sweep over several job files)",
                factors.join(" × ")
            ))
        }
    }
}

impl Sweep {
    /// How many jobs the sweep gives.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the sweep gives no job (never: every swept list has a value).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The value index of each dimension for job `index` (the last dimension fastest).
    fn digits(&self, mut index: usize) -> Vec<usize> {
        let mut digits = vec![0; self.dimensions.len()];
        for (digit, d) in digits.iter_mut().zip(&self.dimensions).rev() {
            let n = d.values.len().max(1);
            *digit = index % n;
            index /= n;
        }
        digits
    }

    /// The (key, text) of every dimension for job `index`.
    fn texts(&self, index: usize) -> Vec<(&str, &str)> {
        self.dimensions
            .iter()
            .zip(self.digits(index))
            .map(|(d, k)| (d.key.as_str(), d.values[k].1.as_str()))
            .collect()
    }

    /// Whether the sweep sets `key` itself (in every job, or swept), rather than leaving it
    /// to `[defaults]`.
    pub fn sets(&self, key: &str) -> bool {
        self.base.contains_key(key) || self.dimensions.iter().any(|d| d.key == key)
    }

    /// The output name of job `index`: the sweep's template filled, or the swept `output`
    /// value; `None` when the sweep names no output as a string.
    pub fn output(&self, index: usize) -> Result<Option<String>, String> {
        let Some(output) = &self.output else {
            let swept = self
                .dimensions
                .iter()
                .zip(self.digits(index))
                .find_map(|(d, k)| {
                    d.values[k]
                        .0
                        .iter()
                        .find(|(key, _)| key == "output")
                        .and_then(|(_, value)| value.as_str().map(str::to_string))
                });
            return Ok(swept);
        };
        let mut name = output.clone();
        for (key, text) in self.texts(index) {
            name = fill(&name, key, text)?;
        }
        Ok(Some(name))
    }

    /// Job `index` (from 0 to [`Sweep::len`]) of the sweep.
    pub fn variant(&self, index: usize) -> Result<Variant, String> {
        let mut table = self.base.clone();
        for (d, k) in self.dimensions.iter().zip(self.digits(index)) {
            for (key, value) in &d.values[k].0 {
                table.insert(key.clone(), value.clone());
            }
        }
        if self.output.is_some()
            && let Some(name) = self.output(index)?
        {
            table.insert("output".into(), Value::String(name));
        }
        let label = self
            .texts(index)
            .iter()
            .map(|(key, text)| format!("{key}={text}"))
            .collect::<Vec<_>>()
            .join(", ");
        Ok(Variant { table, label })
    }
}

/// The `flow-dt` an animation sweep gives each job: one frame, `1 / fps` seconds, unless the
/// sweep sets `flow-dt` itself.
fn frame_interval(table: &Table) -> Option<(String, Value)> {
    if table.contains_key("flow-dt") || table.contains_key("flow_dt") {
        return None;
    }
    let fps = match table.get("fps")? {
        Value::Integer(f) => *f as f64,
        Value::Float(f) => *f,
        _ => return None,
    };
    Some(("flow-dt".to_string(), Value::Float(1.0 / fps)))
}

/// The frames of `frames` and `fps`, as (frame number, `time` value), if the sweep has them.
fn animation_frames(table: &Table) -> Result<Option<Vec<(i64, Value)>>, String> {
    let Some(frames) = table.get("frames") else {
        if table.contains_key("fps") {
            return Err("key \"fps\" without frames: add frames = \"0..N\"".into());
        }
        return Ok(None);
    };
    if table.contains_key("time") {
        return Err(
            "has both frames and time: frames sets each job's time (frame / fps); drop time".into(),
        );
    }
    let bad_frames = || {
        format!(
            "key \"frames\" must be a range \"A..B\" (end exclusive: \"0..120\" is frames 0 to \
             119) or a list of frame numbers, with 0 ≤ A < B and at most {MAX_FRAMES} frames"
        )
    };
    let numbers: Vec<i64> = match frames {
        Value::String(text) => {
            let (a, b) = text.split_once("..").ok_or_else(bad_frames)?;
            let (a, b): (i64, i64) = (
                a.trim().parse().map_err(|_| bad_frames())?,
                b.trim().parse().map_err(|_| bad_frames())?,
            );
            if a < 0 || b <= a || b - a > MAX_FRAMES {
                return Err(bad_frames());
            }
            (a..b).collect()
        }
        Value::Array(items) if !items.is_empty() && items.len() as i64 <= MAX_FRAMES => items
            .iter()
            .map(|v| v.as_integer().filter(|&k| k >= 0))
            .collect::<Option<Vec<i64>>>()
            .ok_or_else(bad_frames)?,
        _ => return Err(bad_frames()),
    };
    let fps = match table.get("fps") {
        Some(Value::Integer(f)) if *f > 0 => *f as f64,
        Some(Value::Float(f)) if f.is_finite() && *f > 0.0 => *f,
        _ => {
            return Err(
                "frames needs fps = F, the frames per second (a positive number, e.g. 24)".into(),
            );
        }
    };
    Ok(Some(
        numbers
            .into_iter()
            .map(|k| (k, Value::Float(k as f64 / fps)))
            .collect(),
    ))
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
        let width = pad_width(template, key, &rest[..end])?;
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
    fn paddings_and_products_are_checked_before_expanding() {
        let err = sweep("output = \"o{spp:070000}.png\"\nspp = [1, 2]").unwrap_err();
        assert!(err.contains("\"spp\"") && err.contains("70000"), "{err}");
        assert!(sweep("output = \"o{spp:0255}.png\"\nspp = [1, 2]").is_ok());
        let thousand: Vec<String> = (0..1000).map(|i| i.to_string()).collect();
        let list = thousand.join(", ");
        let err = plan(
            &format!("output = \"{{a}}{{b}}{{c}}\"\na = [{list}]\nb = [{list}]\nc = [{list}]")
                .parse::<Table>()
                .unwrap(),
            |_| false,
        )
        .err()
        .unwrap();
        assert!(err.contains("1000000000 jobs"), "{err}");
    }

    #[test]
    fn jobs_made_by_index_follow_the_expansion_order() {
        let planned = plan(
            &"output = \"{a}-{b}\"\na = [1, 2]\nb = [3, 4, 5]"
                .parse::<Table>()
                .unwrap(),
            |_| false,
        )
        .unwrap();
        assert_eq!(planned.len(), 6);
        let names: Vec<String> = (0..6)
            .map(|i| planned.output(i).unwrap().unwrap())
            .collect();
        assert_eq!(names, ["1-3", "1-4", "1-5", "2-3", "2-4", "2-5"]);
        assert_eq!(planned.variant(4).unwrap().label, "a=2, b=4");
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

    #[test]
    fn frames_sweep_times_at_the_frame_rate() {
        let v = sweep(
            r#"output = "a_{frame:04}.png"
               frames = "10..13"
               fps = 24"#,
        )
        .unwrap();
        let names: Vec<_> = v
            .iter()
            .map(|v| v.table["output"].as_str().unwrap())
            .collect();
        assert_eq!(names, ["a_0010.png", "a_0011.png", "a_0012.png"]);
        let times: Vec<f64> = v
            .iter()
            .map(|v| v.table["time"].as_float().unwrap())
            .collect();
        for (t, k) in times.iter().zip(10..) {
            assert!((t - k as f64 / 24.0).abs() < 1e-12);
        }
        assert!(
            v.iter()
                .all(|v| !v.table.contains_key("frames") && !v.table.contains_key("fps"))
        );
        let listed = sweep("output = \"b{frame}.png\"\nframes = [0, 48]\nfps = 24.0").unwrap();
        assert_eq!(listed[1].table["time"].as_float(), Some(2.0));
    }

    #[test]
    fn frames_with_an_orbit_go_together_and_bad_frames_are_refused() {
        let v = sweep(
            r#"output = "t{frame}.png"
               frames = "0..4"
               fps = 2
               orbit = { frames = 4, center = [0, 0, 0], radius = 1 }"#,
        )
        .unwrap();
        assert_eq!(v.len(), 4);
        assert_eq!(v[3].table["time"].as_float(), Some(1.5));
        assert!(v[3].table["camera"].is_table());
        for bad in [
            "output = \"x{frame}.png\"\nframes = \"0..3\"",
            "output = \"x{frame}.png\"\nframes = \"3..3\"\nfps = 1",
            "output = \"x{frame}.png\"\nframes = \"0..3\"\nfps = 0",
            "output = \"x{frame}.png\"\nframes = \"0..3\"\nfps = 1\ntime = 2",
            "output = \"x.png\"\nframes = \"0..3\"\nfps = 1",
            "output = \"x{frame}.png\"\nfps = 1",
            "output = \"x{frame}.png\"\nframes = \"0..3\"\nfps = 1\norbit = { frames = 2, center = [0, 0, 0], radius = 1 }",
        ] {
            assert!(sweep(bad).is_err(), "accepted: {bad}");
        }
    }
}
