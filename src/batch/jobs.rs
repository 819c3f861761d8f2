//! The job file: TOML with an optional `[defaults]` table, `[[job]]` tables and `[[sweep]]`
//! tables (see [`super::sweep`]), read into a list of [`Job`]s.
//!
//! A job's keys are the long options of `glint render` with `_` for `-` (`max_depth`,
//! `time_budget`, ...), plus `scene`, `output` and `camera` (an index, or a table
//! `{ position, look_at, up, yfov }`). Each job is turned into the argument list it stands
//! for and handed to an [`OptionParser`]: the command line's, which parses it with the same
//! clap definition as `glint render`, so a job accepts exactly the options and values `glint
//! render` accepts, and every option added to `glint render` is a job key at once. (Batch sits
//! below the command line and knows no clap: the parser is passed in.) Relative paths
//! (`scene`, `output`, `lights`, `asset_root`, `env`, and the top-level `output_root`) are
//! relative to the job file.

use super::sweep;
use crate::job::{CameraChoice, EnvironmentSource, LightSource, SceneSource};
use glam::Vec3;
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use toml::{Table, Value};

/// One render of a batch.
#[derive(Clone, Debug)]
pub struct Job {
    /// Position in the expanded job list (from 0): what `--shard` and the report use.
    pub index: usize,
    /// Where the job comes from, for messages: `[[job]] 2`, `[[sweep]] 0, spp=4`.
    pub origin: String,
    /// The render: its options, paths already resolved against the job file's folder, and
    /// the placed camera if the job has one.
    pub render: crate::job::Job,
}

impl Job {
    /// The scene file (always set: a job must name one).
    pub fn scene(&self) -> &Path {
        match &self.render.scene {
            SceneSource::File(path) => path,
            SceneSource::Demo => Path::new(""),
        }
    }

    /// The output file (always set: a job must name one).
    pub fn output(&self) -> &Path {
        self.render
            .output
            .as_ref()
            .map_or(Path::new(""), |o| o.path.as_path())
    }
}

/// What kind of value a render option takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OptionKind {
    /// A switch: `true` gives it, `false` leaves it out.
    Flag,
    /// One value.
    Value,
    /// Any number of values: an array is its value, not a sweep over values.
    List,
}

/// The render options a job's keys stand for, as the command line defines them: `glint
/// batch` turns each job table into `glint render`'s long options and asks this to parse them.
/// The command line implements it with `glint render`'s own clap definition
/// (`cli::job_options::RenderOptions`), so that batch, a lower layer, needs no clap and the
/// two spellings cannot drift.
pub trait OptionParser {
    /// What option `--name` takes (`name` spelled with `-`); `None` if there is no such option.
    fn kind(&self, name: &str) -> Option<OptionKind>;
    /// Every option's name, spelled with `-`, for the message about an unknown key.
    fn names(&self) -> Vec<String>;
    /// The render that `scene` and the long options `args` stand for. The error is one line
    /// naming the option at fault.
    fn parse(&self, scene: Option<&Path>, args: &[String]) -> Result<crate::job::Job, String>;
}

/// A perspective camera placed by the job file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraOverride {
    /// Camera position, world space.
    pub position: Vec3,
    /// The point the camera looks at.
    pub look_at: Vec3,
    /// The world direction that appears up in the image.
    pub up: Vec3,
    /// Vertical field of view in radians; `None` keeps the scene camera's (or the default
    /// camera's) field of view.
    pub yfov_radians: Option<f32>,
}

/// Why a job file cannot be used. Every message names the file; per-job errors name the job
/// and the key.
#[derive(Debug, thiserror::Error)]
pub enum JobFileError {
    /// The file cannot be read.
    #[error("cannot read job file {path}: {source}")]
    Io {
        /// The job file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file is not valid TOML.
    #[error("{path} is not valid TOML: {message}")]
    Syntax {
        /// The job file.
        path: PathBuf,
        /// The parser's message, with line and column.
        message: String,
    },
    /// Something is wrong in one table of the file.
    #[error("{path}: {origin}: {message}")]
    Job {
        /// The job file.
        path: PathBuf,
        /// `[defaults]`, `[[job]] 2`, `[[sweep]] 0`, or `the file`.
        origin: String,
        /// What is wrong and how to fix it.
        message: String,
    },
}

/// Keys that set a whole batch, not a job.
const BATCH_ONLY: [&str; 2] = ["threads", "quiet"];

/// A job file read: its jobs and the settings of the whole batch.
#[derive(Clone, Debug)]
pub struct JobFile {
    /// The expanded jobs.
    pub jobs: Vec<Job>,
    /// The top-level `output_root = "DIR"` (resolved against the job file's folder): the
    /// folder outputs must resolve inside, instead of the job file's folder.
    pub output_root: Option<PathBuf>,
    /// Every file the jobs write and read ([`plan_jobs`]); `glint batch` adds its report and
    /// COCO file to it before anything renders.
    pub plan: crate::output::OutputPlan,
}

/// Reads and expands the job file at `path`, its options parsed by `options`.
pub fn load(path: &Path, options: &dyn OptionParser) -> Result<Vec<Job>, JobFileError> {
    load_file(path, options).map(|file| file.jobs)
}

/// Reads the job file at `path`: its jobs and its batch settings.
pub fn load_file(path: &Path, options: &dyn OptionParser) -> Result<JobFile, JobFileError> {
    // Checked before opening: opening a FIFO would block until a writer appears.
    crate::output::plan::require_regular(path, "the job file").map_err(|e| JobFileError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e.0),
    })?;
    let text = std::fs::read_to_string(path).map_err(|source| JobFileError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_file(&text, path, options)
}

/// Expands the job file text `text` (read from `path`, which anchors relative paths), its
/// options parsed by `options`.
pub fn parse(
    text: &str,
    path: &Path,
    options: &dyn OptionParser,
) -> Result<Vec<Job>, JobFileError> {
    parse_file(text, path, options).map(|file| file.jobs)
}

/// Like [`parse`], with the batch settings.
pub fn parse_file(
    text: &str,
    path: &Path,
    options: &dyn OptionParser,
) -> Result<JobFile, JobFileError> {
    let table: Table = text
        .parse()
        .map_err(|e: toml::de::Error| JobFileError::Syntax {
            path: path.to_path_buf(),
            message: e.to_string().trim_end().replace('\n', " "),
        })?;
    let err = |origin: &str, message: String| JobFileError::Job {
        path: path.to_path_buf(),
        origin: origin.to_string(),
        message,
    };
    for key in table.keys() {
        if !["defaults", "job", "sweep", "output_root"].contains(&key.as_str()) {
            return Err(err(
                "the file",
                format!(
                    "unknown top-level key \"{key}\"; a job file has output_root = \"DIR\" \
                     and [defaults], [[job]] and [[sweep]] tables"
                ),
            ));
        }
    }
    let folder = path.parent().unwrap_or(Path::new(""));
    let output_root = match table.get("output_root") {
        None => None,
        Some(Value::String(dir)) => Some(folder.join(dir)),
        Some(_) => {
            return Err(err(
                "the file",
                "output_root must be a folder path string (written before the first table)".into(),
            ));
        }
    };
    let defaults = match table.get("defaults") {
        None => Table::new(),
        Some(Value::Table(t)) => t.clone(),
        Some(_) => {
            return Err(err(
                "[defaults]",
                "must be a table: write [defaults]".into(),
            ));
        }
    };
    let tables = |name: &str| -> Result<Vec<Table>, JobFileError> {
        match table.get(name) {
            None => Ok(Vec::new()),
            Some(Value::Array(items)) => items
                .iter()
                .map(|item| match item {
                    Value::Table(t) => Ok(t.clone()),
                    _ => Err(err(name, format!("write each entry as a [[{name}]] table"))),
                })
                .collect(),
            Some(_) => Err(err(name, format!("write each entry as a [[{name}]] table"))),
        }
    };
    let context = Context {
        path,
        folder,
        defaults: &defaults,
        options,
        checked: RefCell::default(),
    };
    let job_tables = tables("job")?;
    let sweeps = tables("sweep")?
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let origin = format!("[[sweep]] {i}");
            sweep::plan(t, |key| is_list_option(options, key))
                .map_err(|message| err(&origin, message))
        })
        .collect::<Result<Vec<_>, _>>()?;
    // The whole file is checked before any sweep is expanded: a sweep of a million frames
    // takes minutes and gigabytes to expand, which a file refused anyway must not cost.
    check_job_count(job_tables.len(), &sweeps).map_err(|m| err("the file", m))?;
    if job_tables.is_empty() && sweeps.is_empty() {
        return Err(err(
            "the file",
            "holds no job: add a [[job]] or [[sweep]] table".into(),
        ));
    }
    check_unique_outputs(&job_tables, &sweeps, &defaults, folder, &err)?;
    let mut jobs = Vec::new();
    for (i, job) in job_tables.iter().enumerate() {
        let origin = format!("[[job]] {i}");
        jobs.push(context.job(job, &origin, jobs.len())?);
    }
    for (i, planned) in sweeps.iter().enumerate() {
        let origin = format!("[[sweep]] {i}");
        for index in 0..planned.len() {
            let variant = planned
                .variant(index)
                .map_err(|message| err(&origin, message))?;
            let origin = format!("{origin}, {}", variant.label);
            jobs.push(context.job(&variant.table, &origin, jobs.len())?);
        }
    }
    // The ground truth, on the parsed paths: the output plan catches what the templates
    // alone cannot (an output given as a number, `./a.png` against `a.png`, a symbolic link
    // to a folder, a sidecar shared by `a.png` and `a.exr`, an output that is an input).
    let plan = plan_jobs(&jobs, path).map_err(|(origin, message)| err(&origin, message))?;
    Ok(JobFile {
        jobs,
        output_root,
        plan,
    })
}

/// The output plan of `jobs` read from `job_file`: every job's image and sidecar as outputs,
/// the job file and every job's scene (with its buffers and images), lights files and
/// environment map as inputs. The error names the job at fault and the message.
pub fn plan_jobs(
    jobs: &[Job],
    job_file: &Path,
) -> Result<crate::output::OutputPlan, (String, String)> {
    let mut plan = crate::output::OutputPlan::new();
    plan.input(job_file, "the job file")
        .map_err(|e| ("the file".to_string(), e.to_string()))?;
    // A scene's external files are read once, however many jobs share it.
    let mut scenes = std::collections::HashSet::new();
    for job in jobs {
        let mut render = job.render.clone();
        if let crate::job::SceneSource::File(scene) = &render.scene
            && !scenes.insert(scene.clone())
        {
            render.scene = crate::job::SceneSource::Demo;
        }
        render
            .plan_files(&mut plan, &job.origin)
            .map_err(|e| (job.origin.clone(), e.to_string()))?;
    }
    Ok(plan)
}

/// The message for a job that writes `path`, as the job `first` does.
fn duplicate_output(path: &Path, first: &str) -> String {
    format!(
        "writes {}, as {first} does: give each job its own output (in a sweep, put the swept \
         keys in the name, e.g. \"out-{{spp}}.png\")",
        path.display()
    )
}

/// Refuses a file whose `[[job]]` tables and sweeps together give more than
/// [`sweep::MAX_JOBS`] jobs (counted without expanding any sweep).
fn check_job_count(jobs: usize, sweeps: &[sweep::Sweep]) -> Result<(), String> {
    let total = sweeps
        .iter()
        .try_fold(jobs, |n, s| n.checked_add(s.len()))
        .filter(|&n| n <= sweep::MAX_JOBS);
    match total {
        Some(_) => Ok(()),
        None => Err(format!(
            "its [[job]] tables and sweeps give more than the {} jobs a job file may hold \
             (split it over several job files)",
            sweep::MAX_JOBS
        )),
    }
}

/// Where a job of the file comes from, for the duplicate-output message.
#[derive(Clone, Copy)]
enum JobSource {
    /// `[[job]] N`.
    Job(usize),
    /// Job `index` of `[[sweep]] N`.
    Sweep(usize, usize),
}

/// Refuses two jobs that write the same file, from the tables and the sweeps' output
/// templates alone (no sweep is expanded). An output that is not a string is left to the
/// check on the parsed jobs.
fn check_unique_outputs(
    job_tables: &[Table],
    sweeps: &[sweep::Sweep],
    defaults: &Table,
    folder: &Path,
    err: &dyn Fn(&str, String) -> JobFileError,
) -> Result<(), JobFileError> {
    let default_output = defaults.get("output").and_then(Value::as_str);
    let describe = |source: JobSource| -> String {
        match source {
            JobSource::Job(i) => format!("[[job]] {i}"),
            JobSource::Sweep(s, index) => {
                let label = sweeps[s]
                    .variant(index)
                    .map(|v| v.label)
                    .unwrap_or_default();
                format!("[[sweep]] {s}, {label}")
            }
        }
    };
    let mut seen: std::collections::HashMap<PathBuf, JobSource> = Default::default();
    let mut record = |name: &str, source: JobSource| -> Result<(), JobFileError> {
        let path = folder.join(name);
        match seen.get(&path) {
            Some(&first) => Err(err(
                &describe(source),
                duplicate_output(&path, &describe(first)),
            )),
            None => {
                seen.insert(path, source);
                Ok(())
            }
        }
    };
    for (i, table) in job_tables.iter().enumerate() {
        if let Some(name) = table.get("output").map_or(default_output, Value::as_str) {
            record(name, JobSource::Job(i))?;
        }
    }
    for (s, planned) in sweeps.iter().enumerate() {
        for index in 0..planned.len() {
            let own = planned
                .output(index)
                .map_err(|message| err(&format!("[[sweep]] {s}"), message))?;
            let fallback = if planned.sets("output") {
                None
            } else {
                default_output
            };
            if let Some(name) = own.as_deref().or(fallback) {
                record(name, JobSource::Sweep(s, index))?;
            }
        }
    }
    Ok(())
}

/// Whether option `key` takes a list of values (`light`, `aov`), so that an array is its
/// value rather than a sweep over values.
fn is_list_option(options: &dyn OptionParser, key: &str) -> bool {
    options.kind(&key.replace('_', "-")) == Some(OptionKind::List)
}

struct Context<'a> {
    path: &'a Path,
    folder: &'a Path,
    defaults: &'a Table,
    options: &'a dyn OptionParser,
    /// The arguments of each (key, value text) already checked, for the next job.
    checked: RefCell<HashMap<(String, String), Vec<String>>>,
}

impl Context<'_> {
    fn job(&self, table: &Table, origin: &str, index: usize) -> Result<Job, JobFileError> {
        let mut merged = self.defaults.clone();
        for (k, v) in table {
            merged.insert(k.clone(), v.clone());
        }
        let key_error = |key: &str, message: String| JobFileError::Job {
            path: self.path.to_path_buf(),
            origin: origin.to_string(),
            message: format!("key \"{key}\": {message}"),
        };
        let mut argv: Vec<String> = Vec::new();
        let mut camera = None;
        let mut scene = None;
        for (key, value) in &merged {
            match key.as_str() {
                "scene" => match value {
                    Value::String(s) => scene = Some(s.clone()),
                    other => {
                        return Err(key_error(
                            key,
                            format!("must be a file path string, not {}", other.type_str()),
                        ));
                    }
                },
                "camera" => match value {
                    Value::Integer(i) if *i >= 0 => {
                        argv.extend(["--camera".into(), i.to_string()]);
                    }
                    Value::Table(t) => {
                        camera = Some(camera_override(t).map_err(|m| key_error(key, m))?);
                    }
                    _ => {
                        return Err(key_error(
                            key,
                            "must be a camera index (0, 1, ...) or a table { position = [x, y, \
                             z], look_at = [x, y, z], up = [x, y, z], yfov = RADIANS }"
                                .into(),
                        ));
                    }
                },
                k if BATCH_ONLY.contains(&k) => {
                    return Err(key_error(
                        key,
                        format!("applies to the whole batch: pass --{k} to glint batch"),
                    ));
                }
                _ => {
                    // A sweep's jobs share most keys: each (key, value) is turned into
                    // arguments and checked once (a parse builds the whole command).
                    let memo_key = (key.clone(), value.to_string());
                    let cached = self.checked.borrow().get(&memo_key).cloned();
                    let single = match cached {
                        Some(single) => single,
                        None => {
                            let single = self
                                .option_args(key, value)
                                .map_err(|m| key_error(key, m))?;
                            // Parsed alone first, so that a bad value is blamed on its key.
                            self.options
                                .parse(None, &single)
                                .map_err(|m| key_error(key, m))?;
                            self.checked.borrow_mut().insert(memo_key, single.clone());
                            single
                        }
                    };
                    argv.extend(single);
                }
            }
        }
        let scene = scene.ok_or_else(|| {
            key_error(
                "scene",
                "missing: every job needs a scene (set it in the job or in [defaults])".into(),
            )
        })?;
        if !merged.contains_key("output") {
            return Err(key_error(
                "output",
                "missing: every job needs an output file (.png, or .exr)".into(),
            ));
        }
        let mut render = self
            .options
            .parse(Some(&self.folder.join(scene)), &argv)
            .map_err(|message| JobFileError::Job {
                path: self.path.to_path_buf(),
                origin: origin.to_string(),
                message,
            })?;
        self.resolve_paths(&mut render);
        if let Some(placed) = camera {
            render.camera = CameraChoice::LookAt {
                name: format!("{origin} camera"),
                position: placed.position,
                target: placed.look_at,
                up: placed.up,
                yfov: placed.yfov_radians,
            };
        }
        Ok(Job {
            index,
            origin: origin.to_string(),
            render,
        })
    }

    /// Makes the render's relative paths (output, lights file, asset root, environment map)
    /// relative to the job file's folder; the scene is joined to it before parsing.
    fn resolve_paths(&self, render: &mut crate::job::Job) {
        let resolve = |p: &mut PathBuf| {
            if p.is_relative() {
                *p = self.folder.join(&*p);
            }
        };
        if let Some(output) = &mut render.output {
            resolve(&mut output.path);
        }
        for light in &mut render.lights {
            if let LightSource::File(path) = light {
                resolve(path);
            }
        }
        if let Some(root) = &mut render.load_options.asset_root {
            resolve(root);
        }
        if let Some(EnvironmentSource::File { path, .. }) = &mut render.environment {
            resolve(path);
        }
    }

    /// The command-line arguments that `key = value` stands for.
    fn option_args(&self, key: &str, value: &Value) -> Result<Vec<String>, String> {
        // `scene` is the job's file; the scene index (`--scene N`) is the key `scene_index`.
        let name = match key {
            "scene_index" => "scene".to_string(),
            k => k.replace('_', "-"),
        };
        let Some(kind) = self.options.kind(&name) else {
            let mut known: Vec<String> = self
                .options
                .names()
                .into_iter()
                .map(|l| match l.as_str() {
                    "scene" => "scene_index".to_string(),
                    l => l.replace('-', "_"),
                })
                .filter(|l| !BATCH_ONLY.contains(&l.as_str()))
                .collect();
            known.extend(["scene".into(), "camera".into()]);
            known.sort();
            return Err(format!(
                "unknown key; the job keys are {}",
                known.join(", ")
            ));
        };
        let flag = format!("--{name}");
        if kind == OptionKind::Flag {
            return match value {
                Value::Boolean(true) => Ok(vec![flag]),
                Value::Boolean(false) => Ok(Vec::new()),
                other => Err(format!("must be true or false, not {}", other.type_str())),
            };
        }
        let scalar = |v: &Value| match v {
            Value::String(s) => Ok(s.clone()),
            Value::Integer(i) => Ok(i.to_string()),
            Value::Float(f) => Ok(f.to_string()),
            Value::Boolean(b) => Ok(b.to_string()),
            other => Err(format!("must be a value, not {}", other.type_str())),
        };
        match value {
            Value::Array(items) => {
                let mut out = Vec::new();
                for item in items {
                    out.extend([flag.clone(), scalar(item)?]);
                }
                Ok(out)
            }
            v => Ok(vec![flag, scalar(v)?]),
        }
    }
}

/// Reads `{ position, look_at, up, yfov }`.
fn camera_override(t: &Table) -> Result<CameraOverride, String> {
    for key in t.keys() {
        if !["position", "look_at", "up", "yfov"].contains(&key.as_str()) {
            return Err(format!(
                "unknown camera key \"{key}\"; use position, look_at, up, yfov (radians)"
            ));
        }
    }
    let vector = |key: &str| -> Result<Option<Vec3>, String> {
        let Some(value) = t.get(key) else {
            return Ok(None);
        };
        let items = value.as_array().filter(|a| a.len() == 3);
        let numbers: Option<Vec<f32>> = items.and_then(|a| a.iter().map(number).collect());
        let limit = crate::accel::MAX_COORDINATE;
        // Points get glTF's bound; `up` is a direction, whose length does not matter.
        let bounded = key != "up";
        match numbers {
            Some(n)
                if n.iter()
                    .all(|x| x.is_finite() && (!bounded || x.abs() <= limit)) =>
            {
                Ok(Some(Vec3::new(n[0], n[1], n[2])))
            }
            Some(n) if n.iter().all(|x| x.is_finite()) => Err(format!(
                "camera {key} {n:?} lies beyond ±{limit:e}, where f32 rays lose all precision \
                 (the bound glTF cameras get)"
            )),
            _ => Err(format!("camera {key} must be [x, y, z] (three numbers)")),
        }
    };
    let position = vector("position")?.ok_or("the camera table needs position = [x, y, z]")?;
    let look_at = vector("look_at")?.ok_or("the camera table needs look_at = [x, y, z]")?;
    let up = vector("up")?.unwrap_or(Vec3::Y);
    let yfov_radians = match t.get("yfov") {
        None => None,
        Some(v) => match number(v) {
            Some(y) if y > 0.0 && y < std::f32::consts::PI => Some(y),
            _ => return Err("camera yfov must be an angle in radians in (0, π)".into()),
        },
    };
    check_frame(position, look_at, up)?;
    Ok(CameraOverride {
        position,
        look_at,
        up,
        yfov_radians,
    })
}

/// Rejects a camera that looks nowhere or along its up vector.
pub(crate) fn check_frame(position: Vec3, look_at: Vec3, up: Vec3) -> Result<(), String> {
    let forward = look_at - position;
    if forward.length_squared() == 0.0 {
        return Err("camera position and look_at are the same point".into());
    }
    if forward.normalize().cross(up.normalize_or_zero()).length() < 1e-4 {
        return Err("camera up is parallel to the view direction; pick another up".into());
    }
    Ok(())
}

fn number(v: &Value) -> Option<f32> {
    match v {
        Value::Integer(i) => Some(*i as f32),
        Value::Float(f) => Some(*f as f32),
        _ => None,
    }
}
