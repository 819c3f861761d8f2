//! The fuzz targets: each a library function of glint called over bytes, in process, with the
//! small budgets of [`budgets`] so that an allocation the budgets do not bound stands out
//! against the binary's allocation cap.
//!
//! | target | what it calls |
//! |---|---|
//! | `gltf` | `scene::gltf::load_from_memory` on a bundle (a `.gltf` or `.glb` and its external files), sampled at a time for half the inputs, then the obvhs BVH over small results |
//! | `ktx2` | `scene::ktx2_decode::decode_ktx2` (the container checks and the Basis Universal transcoder) |
//! | `meshopt` | one EXT_meshopt_compression buffer view made from the input's header and bytes, loaded as a GLB (glint's precondition checks, then meshoptimizer's decoders and filters) |
//! | `image` | `scene::texture_decode::decode_image` (PNG, JPEG, WebP: the format is sniffed) |
//! | `env` | `light::environment::read_env_image` (Radiance `.hdr`, OpenEXR `.exr`) on a file in a RAM folder |
//! | `jobs` | `batch::jobs::parse_file` (job TOML, defaults, sweeps, frames) with the command line's option parser, then `check` of the first jobs |
//! | `lights` | `scene::light_spec::parse_lights_toml`, and `parse_light` on each line |
//! | `draco` | one KHR_draco_mesh_compression primitive over the input's bytes, loaded as a GLB |

#![allow(dead_code)] // The binary and the tests use different parts.

use super::engine::{Outcome, Shape, Target, bundle};
use glint::scene::gltf::{LoadOptions, MemoryFiles, SceneSelection};
use std::path::{Path, PathBuf};

/// The name errors of the glTF-based targets must start with.
pub const LABEL: &str = "fuzz.gltf";

/// The budgets every target runs under: small, so that a declared size the budgets should have
/// refused shows up as an allocation over the cap instead of passing as a legitimate one.
pub mod budgets {
    /// Texels per texture image (256 × 256).
    pub const TEXTURE_PIXELS: u64 = 1 << 16;
    /// Texels per environment map.
    pub const ENV_PIXELS: u64 = 1 << 16;
    /// Jobs per job file.
    pub const JOBS: usize = 2000;
    /// Bytes of decoded geometry (vertices and indices) per scene.
    pub const GEOMETRY_BYTES: u64 = 16 << 20;
}

/// Meshes with at most this many triangles also get an obvhs BVH (cheap at this size).
const BVH_TRIANGLES: usize = 4096;

/// Every target, in the order `fuzz all` runs them.
pub fn all() -> &'static [Target] {
    TARGETS
}

/// The target called `name`.
pub fn by_name(name: &str) -> Option<&'static Target> {
    TARGETS.iter().find(|t| t.name == name)
}

static TARGETS: &[Target] = &[
    Target {
        name: "gltf",
        about: "glTF/GLB JSON and buffers, loaded from memory with their external files",
        execute: gltf,
        shape: Shape::Gltf,
        dictionary: GLTF_WORDS,
        max_len: 64 << 10,
    },
    Target {
        name: "ktx2",
        about: "KTX2 containers and their Basis Universal payloads",
        execute: ktx2,
        shape: Shape::Binary,
        dictionary: &[
            b"\xabKTX 20\xbb\r\n\x1a\n",
            b"KTXorientation\0rd\0",
            b"KTXswizzle",
        ],
        max_len: 16 << 10,
    },
    Target {
        name: "meshopt",
        about: "EXT_meshopt_compression buffer views (glint's checks, then meshoptimizer)",
        execute: meshopt,
        shape: Shape::Binary,
        dictionary: &[b"\xa0", b"\xe1", b"\xd1", b"\x00\x00\x00\x00"],
        max_len: 8 << 10,
    },
    Target {
        name: "image",
        about: "PNG, JPEG and WebP texture images",
        execute: image,
        shape: Shape::Binary,
        dictionary: &[
            b"IHDR",
            b"IDAT",
            b"IEND",
            b"PLTE",
            b"tRNS",
            b"acTL",
            b"fcTL",
            b"\xff\xd8\xff",
            b"\xff\xc0",
            b"\xff\xc4",
            b"\xff\xda",
            b"RIFF",
            b"WEBPVP8L",
            b"WEBPVP8 ",
            b"VP8X",
            b"ALPH",
            b"ANIM",
            b"ANMF",
        ],
        max_len: 16 << 10,
    },
    Target {
        name: "env",
        about: "Radiance .hdr and OpenEXR .exr environment maps",
        execute: env,
        shape: Shape::Binary,
        dictionary: &[
            b"#?RADIANCE\n",
            b"FORMAT=32-bit_rle_rgbe\n",
            b"-Y ",
            b" +X ",
            b"\x02\x02",
            b"channels\0chlist\0",
            b"compression\0compression\0",
            b"dataWindow\0box2i\0",
            b"displayWindow\0box2i\0",
            b"lineOrder\0lineOrder\0",
            b"tiles\0tiledesc\0",
            b"type\0string\0",
            b"multipart",
            b"R\0",
            b"G\0",
            b"B\0",
            b"A\0",
        ],
        max_len: 16 << 10,
    },
    Target {
        name: "jobs",
        about: "batch job files (TOML: defaults, jobs, sweeps, frames)",
        execute: jobs,
        shape: Shape::Text,
        dictionary: JOB_WORDS,
        max_len: 4 << 10,
    },
    Target {
        name: "outputs",
        about: "job files of colliding outputs and path spellings, against the output plan",
        execute: outputs,
        shape: Shape::Binary,
        dictionary: &[b"\x00\x01", b"\x02\x03", b"\x10\x11"],
        max_len: 64,
    },
    Target {
        name: "lights",
        about: "light files (TOML) and --light specs",
        execute: lights,
        shape: Shape::Text,
        dictionary: LIGHT_WORDS,
        max_len: 4 << 10,
    },
    Target {
        name: "draco",
        about: "KHR_draco_mesh_compression primitives (the draco-core decoder behind glint's checks)",
        execute: draco,
        shape: Shape::Binary,
        dictionary: &[b"DRACO", b"\x02\x02", b"\x01\x00", b"\xff\xff\xff\x0f"],
        max_len: 16 << 10,
    },
];

const GLTF_WORDS: &[&[u8]] = &[
    b"\"bufferView\":0,",
    b"\"byteOffset\":4294967295,",
    b"\"count\":1000000000,",
    b"\"sparse\":{\"count\":1,\"indices\":{\"bufferView\":0,\"componentType\":5125},\"values\":{\"bufferView\":0}},",
    b"\"uri\":\"data:application/octet-stream;base64,AAAA\",",
    b"\"extensionsRequired\":[\"KHR_draco_mesh_compression\"],",
    b"\"mode\":5,",
    b"\"mode\":6,",
    b"\"skin\":0,",
    b"\"weights\":[1e39],",
    b"\"target\":{\"node\":99,\"path\":\"weights\"},",
    b"\"interpolation\":\"CUBICSPLINE\",",
    b"\"type\":\"MAT4\",",
    b"\"componentType\":5121,",
    b"\"normalized\":true,",
    b"\"KHR_texture_transform\":{\"scale\":[1e39,0]},",
    b"\"EXT_mesh_gpu_instancing\":{\"attributes\":{\"TRANSLATION\":0}},",
    b"\"KHR_materials_volume\":{\"thicknessFactor\":1e39},",
    b"\"children\":[0],",
    b"glTF",
    b"JSON",
    b"BIN\0",
];

const JOB_WORDS: &[&[u8]] = &[
    b"[[job]]\n",
    b"[[sweep]]\n",
    b"[defaults]\n",
    b"scene = \"a.gltf\"\n",
    b"output = \"out/{spp:09999}.png\"\n",
    b"output = \"f{frame}.exr\"\n",
    b"spp = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512]\n",
    b"frames = \"0..1000000\"\n",
    b"frames = { start = 0, end = 99999999, step = 1 }\n",
    b"fps = 1e-39\n",
    b"time = 1e39\n",
    b"width = 65536\n",
    b"height = 65537\n",
    b"output_root = \"..\"\n",
    b"camera = { position = [0, 0, 1], look_at = [0, 0, 0] }\n",
    b"lights = \"../../etc/passwd\"\n",
    b"light = [\"point:0,0,0:1e39\"]\n",
    b"backend = \"bvh\"\n",
    b"aov = [\"depth\", \"normal\"]\n",
    b"{",
    b"}",
    b"\"\"\"",
];

const LIGHT_WORDS: &[&[u8]] = &[
    b"[[light]]\n",
    b"type = \"spot\"\n",
    b"type = \"point\"\n",
    b"type = \"directional\"\n",
    b"type = \"sphere\"\n",
    b"position = [0, 1e39, 0]\n",
    b"direction = [0, 0, 0]\n",
    b"intensity = 1e39\n",
    b"power = -1\n",
    b"color = [1, 1, 1]\n",
    b"temperature = 0\n",
    b"cone = 1e39\n",
    b"inner = 90\n",
    b"outer = 0\n",
    b"unit = \"lm\"\n",
    b"radius = 1e-45\n",
    b"point:0,0,0:1e39\n",
    b"spot:0,0,0:0,0,-1:30:45:10\n",
];

/// The load options of the glTF-based targets: the fuzz budgets.
pub fn load_options() -> LoadOptions {
    LoadOptions {
        max_texture_pixels: budgets::TEXTURE_PIXELS,
        max_geometry_bytes: budgets::GEOMETRY_BYTES,
        ..LoadOptions::default()
    }
}

/// Loads a GLB or `.gltf` with its in-memory files, checks the error names the file, and
/// builds the obvhs BVH over a small result.
fn load(main: &[u8], files: &MemoryFiles, time: Option<f32>) -> Outcome {
    let selection = SceneSelection {
        scene: None,
        time,
        variant: None,
    };
    match glint::scene::gltf::load_from_memory(main, LABEL, files, &selection, &load_options()) {
        Err(err) => {
            let message = err.to_string();
            if message.starts_with(LABEL) {
                Outcome::Refused(message)
            } else {
                Outcome::Broken(format!("an error that does not name the file: {message}"))
            }
        }
        Ok(loaded) => {
            let scene = &loaded.scene;
            let triangles: usize = scene.meshes.iter().map(|m| m.indices.len()).sum();
            if triangles <= BVH_TRIANGLES {
                let meshes = scene.triangle_meshes();
                if let Err(err) =
                    glint::accel::build(glint::accel::BackendKind::Bvh, &meshes, Default::default())
                {
                    return Outcome::Broken(format!(
                        "a loaded scene the BVH refuses (the loader should have): {err}"
                    ));
                }
            }
            let mut summary = format!(
                "{} meshes {} materials {} textures {} lights {} cameras",
                scene.meshes.len(),
                scene.materials.len(),
                scene.textures.len(),
                scene.lights.len(),
                scene.cameras.len()
            );
            for warning in &loaded.warnings {
                summary.push('|');
                summary.push_str(warning);
            }
            Outcome::Accepted(summary)
        }
    }
}

/// `gltf`: a bundle of a glTF or GLB and its external files.
pub fn gltf(input: &[u8]) -> Outcome {
    let (main, parts) = bundle::split(input);
    let mut files = MemoryFiles::new();
    for (name, bytes) in parts {
        files.insert(name, bytes.to_vec());
    }
    // Half the inputs also sample their animations (`--time`).
    let time = (xxhash_rust::xxh3::xxh3_64(input) & 1 == 1).then_some(0.37);
    load(main, &files, time)
}

/// `ktx2`: a KTX2 file decoded as a colour texture (odd lengths) or a data texture.
pub fn ktx2(input: &[u8]) -> Outcome {
    use glint::scene::texture_decode::ColorSpace;
    let space = if input.len() % 2 == 1 {
        ColorSpace::Srgb
    } else {
        ColorSpace::Linear
    };
    match glint::scene::ktx2_decode::decode_ktx2(input, space, budgets::TEXTURE_PIXELS) {
        Ok((image, notes)) => Outcome::Accepted(format!(
            "{}x{} {}",
            image.width,
            image.height,
            notes.join("|")
        )),
        Err(err) => Outcome::Refused(err.to_string()),
    }
}

/// `image`: a PNG, JPEG or WebP (sniffed) decoded as a colour texture. The decoder's message
/// is what the loader puts in its texture error: on one line.
pub fn image(input: &[u8]) -> Outcome {
    use glint::scene::texture_decode::{ColorSpace, decode_image};
    match decode_image(input, ColorSpace::Srgb, budgets::TEXTURE_PIXELS) {
        Ok(image) => Outcome::Accepted(format!("{}x{}", image.width, image.height)),
        Err(err) => Outcome::Refused(glint::scene::gltf::one_line(&err.to_string())),
    }
}

/// The meshopt view header: mode, filter, stride (bytes), count (u32, little endian).
pub const MESHOPT_HEADER: usize = 7;

/// EXT_meshopt_compression's modes and filters, indexed by the header's bytes (the last of
/// each is not a valid name).
const MESHOPT_MODES: &[&str] = &["ATTRIBUTES", "TRIANGLES", "INDICES", "BOGUS"];
const MESHOPT_FILTERS: &[&str] = &[
    "NONE",
    "OCTAHEDRAL",
    "QUATERNION",
    "EXPONENTIAL",
    "COLOR",
    "BOGUS",
];

/// `meshopt`: a GLB with one compressed buffer view, whose mode, filter, stride and count
/// come from the input's 7-byte header and whose compressed bytes are the rest; an accessor
/// reads the decoded view as POSITION (ATTRIBUTES) or as indices.
pub fn meshopt(input: &[u8]) -> Outcome {
    let Some(header) = input.get(..MESHOPT_HEADER) else {
        return Outcome::Refused("shorter than the header".into());
    };
    let data = &input[MESHOPT_HEADER..];
    let mode = MESHOPT_MODES[usize::from(header[0]) % MESHOPT_MODES.len()];
    let filter = MESHOPT_FILTERS[usize::from(header[1]) % MESHOPT_FILTERS.len()];
    let stride = u64::from(header[2]);
    let count = u64::from(u32::from_le_bytes([
        header[3], header[4], header[5], header[6],
    ]));
    let decoded = count.saturating_mul(stride);
    // Four vertices after the compressed bytes, for index modes.
    let mut bin = data.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let positions_at = bin.len();
    for v in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [1., 1., 0.]] {
        for c in v {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    let compressed = serde_json::json!({
        "buffer": 0, "byteOffset": 0, "byteLength": data.len(), "byteStride": stride,
        "count": count, "mode": mode, "filter": filter
    });
    let mut views = vec![serde_json::json!({
        "buffer": 1, "byteLength": decoded,
        "extensions": {"EXT_meshopt_compression": compressed}
    })];
    let (accessors, attributes, indices) = if mode == "ATTRIBUTES" {
        if stride > 0 {
            views[0]["byteStride"] = stride.into();
        }
        (
            serde_json::json!([{"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
                "min": [-1, -1, -1], "max": [1, 1, 1]}]),
            serde_json::json!({"POSITION": 0}),
            None,
        )
    } else {
        views.push(serde_json::json!({"buffer": 0, "byteOffset": positions_at, "byteLength": 48}));
        let component = if stride == 2 { 5123 } else { 5125 };
        (
            serde_json::json!([
                {"bufferView": 0, "componentType": component, "count": count, "type": "SCALAR"},
                {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}
            ]),
            serde_json::json!({"POSITION": 1}),
            Some(0),
        )
    };
    let mut primitive = serde_json::json!({"attributes": attributes});
    if let Some(i) = indices {
        primitive["indices"] = i.into();
    }
    let json = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["EXT_meshopt_compression"],
        "extensionsRequired": ["EXT_meshopt_compression"],
        "buffers": [
            {"byteLength": bin.len()},
            {"byteLength": decoded, "extensions": {"EXT_meshopt_compression": {"fallback": true}}}
        ],
        "bufferViews": views,
        "accessors": accessors,
        "meshes": [{"primitives": [primitive]}],
        "nodes": [{"mesh": 0}]
    });
    let glb = glb(json.to_string().as_bytes(), &bin);
    load(&glb, &MemoryFiles::new(), None)
}

/// `draco`: a GLB whose one primitive is KHR_draco_mesh_compression over the input: the
/// first byte picks the attributes the extension maps (always POSITION; bit 0 adds NORMAL,
/// bit 1 adds TEXCOORD_0 as id 2, bit 2 makes POSITION and NORMAL ids 1 and 0), the rest is
/// the Draco stream.
pub fn draco(input: &[u8]) -> Outcome {
    let Some((&which, data)) = input.split_first() else {
        return Outcome::Refused("empty".into());
    };
    let mut bin = data.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    // Bit 2 swaps the ids of POSITION and NORMAL (Google's encoder writes NORMAL first).
    let (position_id, normal_id) = if which & 4 == 4 { (1, 0) } else { (0, 1) };
    let mut attributes = serde_json::json!({"POSITION": 0});
    let mut ids = serde_json::json!({"POSITION": position_id});
    let mut accessors = vec![serde_json::json!(
        {"componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]}
    )];
    if which & 1 == 1 {
        attributes["NORMAL"] = 1.into();
        ids["NORMAL"] = normal_id.into();
        accessors.push(serde_json::json!({"componentType": 5126, "count": 3, "type": "VEC3"}));
    }
    if which & 2 == 2 {
        let n = accessors.len();
        attributes["TEXCOORD_0"] = n.into();
        ids["TEXCOORD_0"] = (n as u64).into();
        accessors.push(serde_json::json!({"componentType": 5126, "count": 3, "type": "VEC2"}));
    }
    let indices = accessors.len();
    accessors.push(serde_json::json!({"componentType": 5125, "count": 3, "type": "SCALAR"}));
    let json = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_draco_mesh_compression"],
        "extensionsRequired": ["KHR_draco_mesh_compression"],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": [{"buffer": 0, "byteLength": data.len()}],
        "accessors": accessors,
        "meshes": [{"primitives": [{
            "attributes": attributes, "indices": indices,
            "extensions": {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": ids}}
        }]}],
        "nodes": [{"mesh": 0}]
    });
    let glb = glb(json.to_string().as_bytes(), &bin);
    load(&glb, &MemoryFiles::new(), None)
}

/// A GLB of `json` and `bin`, with the chunk lengths and padding glTF requires.
pub fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    super::mutate::glb(json, Some(bin))
}

thread_local! {
    /// The file the `env` target writes each input to (the environment reader reads paths).
    static ENV_FILE: PathBuf = env_file_path();
}

fn env_file_path() -> PathBuf {
    // RAM-backed where the system has one, so that a write costs microseconds.
    let dir = Path::new("/dev/shm");
    let dir = if dir.is_dir() {
        dir.to_path_buf()
    } else {
        std::env::temp_dir()
    };
    let thread = format!("{:?}", std::thread::current().id())
        .chars()
        .filter(char::is_ascii_digit)
        .collect::<String>();
    dir.join(format!("glint-fuzz-env-{}-{thread}", std::process::id()))
}

/// Removes the `env` input files a worker with process id `pid` left (one that died cannot).
pub fn remove_env_files_of(pid: u32) {
    let prefix = format!("glint-fuzz-env-{pid}-");
    for dir in [Path::new("/dev/shm").to_path_buf(), std::env::temp_dir()] {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            if entry.file_name().to_string_lossy().starts_with(&prefix) {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}

/// Removes this thread's `env` input file.
pub fn remove_env_file() {
    ENV_FILE.with(|path| {
        let _ = std::fs::remove_file(path);
    });
}

/// `env`: an environment map read from a file holding the input.
pub fn env(input: &[u8]) -> Outcome {
    ENV_FILE.with(|path| {
        if let Err(err) = std::fs::write(path, input) {
            return Outcome::Broken(format!("cannot write {}: {err}", path.display()));
        }
        match glint::light::environment::read_env_image(path, budgets::ENV_PIXELS) {
            Ok(image) => Outcome::Accepted(format!("{}x{}", image.width, image.height)),
            Err(err) => Outcome::Refused(err.to_string()),
        }
    })
}

/// `jobs`: a batch job file, expanded (each job parsed by the command line's option parser),
/// and its first jobs checked.
/// A file whose sweeps give more than [`budgets::JOBS`] jobs is skipped (counted from the
/// sweeps' plans, as the parser counts them before expanding): each job costs a full
/// command-line parse, about 0.1 ms, so a legitimate million-job file takes minutes.
pub fn jobs(input: &[u8]) -> Outcome {
    let text = String::from_utf8_lossy(input);
    if let Ok(table) = text.parse::<toml::Table>()
        && let Some(toml::Value::Array(sweeps)) = table.get("sweep")
    {
        let total: usize = sweeps
            .iter()
            .filter_map(toml::Value::as_table)
            .filter_map(|t| glint::batch::sweep::plan(t, |k| matches!(k, "light" | "aov")).ok())
            .map(|plan| plan.len())
            .fold(0, usize::saturating_add);
        if total > budgets::JOBS {
            return Outcome::Refused(format!("over the fuzz budget of {} jobs", budgets::JOBS));
        }
    }
    let path = Path::new("/glint-fuzz/jobs.toml");
    let options = glint::cli::job_options::RenderOptions;
    match glint::batch::jobs::parse_file(&text, path, &options) {
        Err(err) => Outcome::Refused(err.to_string()),
        Ok(file) => {
            let mut summary = format!("{} jobs", file.jobs.len());
            for job in file.jobs.iter().take(8) {
                if let Err(err) = job.render.check() {
                    let message = err.to_string();
                    if message.contains('\n') {
                        return Outcome::Broken(format!("a multi-line job error: {message}"));
                    }
                    summary.push('|');
                    summary.push_str(&message);
                }
            }
            Outcome::Accepted(summary)
        }
    }
}

/// The output spellings the `outputs` target draws from: one file spelled several ways, its
/// PNG/EXR twin (whose sidecar is the same `a.json`), and distinct files.
const SPELLINGS: &[&str] = &[
    "a.png",
    "./a.png",
    "sub/../a.png",
    "sub/./../a.png",
    "a.exr",
    "sub/a.png",
    "sub/x/../a.png",
    "b.png",
    "./b.exr",
    "jobs.png",
];

/// `outputs`: a job file of up to 8 jobs whose outputs (and sidecar flags) the input bytes
/// pick from [`SPELLINGS`], read from `/glint-fuzz/a.json` (so that the sidecar of `a.png`
/// is the job file). The oracle: the file parses exactly when no two planned files (images,
/// sidecars, the job file) are one path after `.` and `..` are applied, and a refusal for a
/// collision is one line.
pub fn outputs(input: &[u8]) -> Outcome {
    let folder = Path::new("/glint-fuzz");
    let job_file = folder.join("a.json");
    let mut text = String::from("[defaults]\nscene = \"scene.glb\"\n");
    // Lexical normalisation: the folder does not exist, so no link can intervene.
    let normal = |p: &Path| -> PathBuf {
        let mut out = PathBuf::new();
        for c in p.components() {
            match c {
                std::path::Component::CurDir => {}
                std::path::Component::ParentDir => {
                    out.pop();
                }
                c => out.push(c),
            }
        }
        out
    };
    let mut files = vec![normal(&job_file)];
    let mut collide = false;
    for pair in input.chunks(2).take(8) {
        let spelling = SPELLINGS[pair[0] as usize % SPELLINGS.len()];
        let sidecar = pair.get(1).is_some_and(|b| b & 1 == 1);
        text.push_str(&format!(
            "[[job]]\noutput = \"{spelling}\"\nsidecar = {sidecar}\n"
        ));
        let image = normal(&folder.join(spelling));
        let mut mine = vec![image.clone()];
        if sidecar {
            mine.push(image.with_extension("json"));
        }
        for f in mine {
            collide |= files.contains(&f);
            files.push(f);
        }
    }
    if input.len() < 2 {
        return Outcome::Refused("fewer than 2 bytes: no job".into());
    }
    let options = glint::cli::job_options::RenderOptions;
    match glint::batch::jobs::parse_file(&text, &job_file, &options) {
        Ok(file) if collide => Outcome::Broken(format!(
            "{} jobs accepted though two planned files are one: {text:?}",
            file.jobs.len()
        )),
        Ok(file) => Outcome::Accepted(format!("{} jobs", file.jobs.len())),
        Err(err) => {
            let message = err.to_string();
            let collision = message.contains("twice") || message.contains("which glint reads");
            if message.contains('\n') {
                Outcome::Broken(format!("a multi-line refusal: {message}"))
            } else if collision && !collide {
                Outcome::Broken(format!("refused without a collision: {message}; {text:?}"))
            } else {
                // A collision (in the plan's words, or the template check's), or another
                // reason found first.
                Outcome::Refused(message)
            }
        }
    }
}

/// `lights`: a lights file, and each of its lines as a `--light` spec.
pub fn lights(input: &[u8]) -> Outcome {
    use glint::scene::light_spec::{parse_light, parse_lights_toml};
    let text = String::from_utf8_lossy(input);
    let mut summary = String::new();
    for line in text.lines().take(16) {
        match parse_light(line) {
            Ok(_) => summary.push_str("ok|"),
            Err(err) => {
                let message = err.to_string();
                if message.contains('\n') {
                    return Outcome::Broken(format!("a multi-line --light error: {message}"));
                }
                summary.push_str(&message);
                summary.push('|');
            }
        }
    }
    match parse_lights_toml(&text, "lights.toml") {
        Ok(lights) => Outcome::Accepted(format!("{} lights {summary}", lights.len())),
        Err(err) => Outcome::Refused(format!("{err} {summary}")),
    }
}
