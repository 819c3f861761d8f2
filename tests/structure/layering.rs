//! The library's layering, as ARCHITECTURE.md's layer table states it: every top-level module
//! of `src/` sits in one layer, and a module imports only modules of its own layer or below.
//! This test reads the table from ARCHITECTURE.md (so the page and the check cannot drift),
//! finds which top-level modules each file of `src/` names in code (`crate::x`, `super::x`
//! climbing to the crate root, `glint::x` in `main.rs`, grouped `use crate::{a, b}`;
//! comments and string literals do not count), and checks:
//!
//! - every module of `src/` has a row in the table, and every module the table names exists;
//! - no module imports a module of a higher layer ([`KNOWN_SHADING_WING_VIOLATIONS`] excepted,
//!   and that list must not hold an entry that no longer occurs);
//! - the modules' import graph has no cycle (within a layer too);
//! - `clap` is named only by the command line (`src/cli/`, `src/main.rs`): the engine's enums
//!   name themselves with `FromStr`/`Display`, and batch job files reach clap through the
//!   parser the command line passes in.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Upward imports in the shading wing (render, material, light, texture, bsdf) that are being
/// removed, each `from -> to`. The list may only shrink: an entry that no longer occurs fails
/// the test, so that it is deleted as soon as its import is.
const KNOWN_SHADING_WING_VIOLATIONS: &[&str] = &[];

/// The heading of ARCHITECTURE.md's layer table.
const TABLE_HEADER: &str = "| layer | modules |";

/// One import of a top-level module: where it is written.
#[derive(Clone, Debug)]
struct Site {
    file: String,
    line: usize,
}

/// The layer table: module name → layer number (1 is the lowest).
fn layer_table() -> BTreeMap<String, usize> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md");
    let text = std::fs::read_to_string(&path).expect("ARCHITECTURE.md is readable");
    let mut lines = text.lines().skip_while(|l| !l.starts_with(TABLE_HEADER));
    assert!(
        lines.next().is_some(),
        "ARCHITECTURE.md has no layer table (a line starting with `{TABLE_HEADER}`)"
    );
    let mut layers = BTreeMap::new();
    for row in lines.skip(1).take_while(|l| l.starts_with('|')) {
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        let layer: usize = cells
            .get(1)
            .and_then(|c| c.parse().ok())
            .unwrap_or_else(|| panic!("layer table row without a layer number: {row}"));
        let modules = cells.get(2).copied().unwrap_or_default();
        let names: Vec<&str> = modules.split('`').skip(1).step_by(2).collect();
        assert!(!names.is_empty(), "layer {layer} names no `module`: {row}");
        for name in names {
            let name = name.trim_end_matches('/').trim_end_matches(".rs");
            if let Some(before) = layers.insert(name.to_string(), layer) {
                panic!("`{name}` is in layers {before} and {layer} of the table");
            }
        }
    }
    assert!(
        layers.len() > 10,
        "the layer table has {} modules",
        layers.len()
    );
    layers
}

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("src/ is readable") {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module path of a file under `src/`: `render/job.rs` → [render, job], `render/mod.rs` →
/// [render], `main.rs` → [main].
fn module_path(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

/// `text` with comments and the contents of string and character literals blanked out (line
/// breaks kept, so that line numbers stay right).
fn code_only(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let blank = |c: char| if c == '\n' { '\n' } else { ' ' };
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    out.push(blank(chars[i]));
                    i += 1;
                }
            }
        } else if c == 'r'
            && matches!(next, Some('"') | Some('#'))
            && !chars[..i]
                .last()
                .is_some_and(|p| p.is_alphanumeric() || *p == '_')
        {
            // A raw string r"…" or r#"…"#.
            let mut j = i + 1;
            let mut hashes = 0;
            while chars.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if chars.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            let closing: String = std::iter::once('"')
                .chain(std::iter::repeat_n('#', hashes))
                .collect();
            let closing: Vec<char> = closing.chars().collect();
            while j < chars.len() && !chars[j..].starts_with(&closing) {
                out.push(blank(chars[j]));
                j += 1;
            }
            out.push_str("\"\"");
            i = j + closing.len();
        } else if c == '"' {
            out.push('"');
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                if chars[i] == '\\' {
                    out.push(' ');
                    i += 1;
                }
                if let Some(&ch) = chars.get(i) {
                    out.push(blank(ch));
                }
                i += 1;
            }
            out.push('"');
            i += 1;
        } else if c == '\'' {
            // A character literal ('x', '\n', '\u{1F600}') or a lifetime ('a).
            if next == Some('\\') {
                let mut j = i + 2;
                while j < chars.len() && chars[j] != '\'' {
                    j += 1;
                }
                out.push_str("' '");
                i = j + 1;
            } else if chars.get(i + 2) == Some(&'\'') {
                out.push_str("' '");
                i += 3;
            } else {
                out.push(c);
                i += 1;
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// A token of Rust code, as far as paths need: an identifier, `::`, a brace, a comma, or
/// anything else; with its line.
#[derive(Clone, Debug, PartialEq)]
enum Token {
    Ident(String),
    PathSep,
    Open,
    Close,
    Comma,
    Other,
}

fn tokens(code: &str) -> Vec<(Token, usize)> {
    let chars: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut line = 1;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push((Token::Ident(chars[start..i].iter().collect()), line));
        } else if c == ':' && chars.get(i + 1) == Some(&':') {
            out.push((Token::PathSep, line));
            i += 2;
        } else {
            out.push((
                match c {
                    '{' => Token::Open,
                    '}' => Token::Close,
                    ',' => Token::Comma,
                    _ => Token::Other,
                },
                line,
            ));
            i += 1;
        }
    }
    out
}

/// The first segments of the items of a `{ … }` group starting at `tokens[at]` (the `{`),
/// each with its line.
fn group_heads(tokens: &[(Token, usize)], at: usize) -> Vec<(String, usize)> {
    let mut heads = Vec::new();
    let mut depth = 0;
    let mut expect_head = true;
    for (token, line) in &tokens[at..] {
        match token {
            Token::Open => {
                depth += 1;
                expect_head = depth == 1;
            }
            Token::Close => {
                depth -= 1;
                if depth == 0 {
                    break;
                }
            }
            Token::Comma if depth == 1 => expect_head = true,
            Token::Ident(name) if expect_head && depth == 1 => {
                heads.push((name.clone(), *line));
                expect_head = false;
            }
            _ => expect_head = false,
        }
    }
    heads
}

/// The top-level modules the file `rel` (path under `src/`) names, each with where.
fn imports(rel: &Path, text: &str) -> Vec<(String, usize)> {
    let module = module_path(rel);
    let crate_names: &[&str] = if module == ["main"] {
        &["crate", "glint"]
    } else {
        &["crate"]
    };
    let tokens = tokens(&code_only(text));
    let ident = |i: usize| match tokens.get(i) {
        Some((Token::Ident(name), _)) => Some(name.as_str()),
        _ => None,
    };
    let sep = |i: usize| matches!(tokens.get(i), Some((Token::PathSep, _)));
    let mut found = Vec::new();
    let mut i = 0;
    while i < tokens.len() {
        let start = ident(i);
        let after_sep = i > 0 && sep(i - 1);
        let (base, j): (Vec<String>, usize) = match start {
            Some(name) if crate_names.contains(&name) && sep(i + 1) && !after_sep => {
                (Vec::new(), i + 2)
            }
            Some("super") if sep(i + 1) && !after_sep => {
                let mut base = module.clone();
                let mut j = i;
                while ident(j) == Some("super") && sep(j + 1) {
                    base.pop();
                    j += 2;
                }
                (base, j)
            }
            _ => {
                i += 1;
                continue;
            }
        };
        if let Some(top) = base.first() {
            found.push((top.clone(), tokens[i].1));
        } else if let Some(name) = ident(j) {
            found.push((name.to_string(), tokens[j].1));
        } else if matches!(tokens.get(j), Some((Token::Open, _))) {
            found.extend(group_heads(&tokens, j));
        }
        i = j;
    }
    found
}

/// Every import of one top-level module by another: (from, to) → sites.
fn module_graph() -> BTreeMap<(String, String), Vec<Site>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    assert!(
        files.len() > 20,
        "found only {} files under src/",
        files.len()
    );
    let mut graph: BTreeMap<(String, String), Vec<Site>> = BTreeMap::new();
    for file in files {
        let rel = file.strip_prefix(&src).expect("under src/").to_path_buf();
        if rel == Path::new("lib.rs") {
            continue;
        }
        let from = module_path(&rel)[0].clone();
        let text = std::fs::read_to_string(&file).expect("source file is readable");
        for (to, line) in imports(&rel, &text) {
            if to != from && to != "self" {
                graph.entry((from.clone(), to)).or_default().push(Site {
                    file: format!("src/{}", rel.display()),
                    line,
                });
            }
        }
    }
    graph
}

/// The top-level modules of `src/`: its folders and files, less `lib.rs`.
fn top_level_modules() -> BTreeSet<String> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    std::fs::read_dir(&src)
        .expect("src/ is readable")
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.is_dir() || p.extension().is_some_and(|e| e == "rs"))
        .map(|p| module_path(p.strip_prefix(&src).expect("under src/"))[0].clone())
        .filter(|m| m != "lib")
        .collect()
}

fn describe(sites: &[Site]) -> String {
    let shown: Vec<String> = sites
        .iter()
        .take(3)
        .map(|s| format!("{}:{}", s.file, s.line))
        .collect();
    let more = sites.len().saturating_sub(3);
    if more > 0 {
        format!("{} and {more} more", shown.join(", "))
    } else {
        shown.join(", ")
    }
}

#[test]
fn every_module_has_a_layer_and_every_layer_module_exists() {
    let layers = layer_table();
    let modules = top_level_modules();
    let missing: Vec<&String> = modules
        .iter()
        .filter(|m| !layers.contains_key(*m))
        .collect();
    assert!(
        missing.is_empty(),
        "modules of src/ missing from ARCHITECTURE.md's layer table: {missing:?}"
    );
    let stale: Vec<&String> = layers.keys().filter(|m| !modules.contains(*m)).collect();
    assert!(
        stale.is_empty(),
        "ARCHITECTURE.md's layer table names modules src/ does not have: {stale:?}"
    );
}

#[test]
fn no_module_imports_a_higher_layer() {
    let layers = layer_table();
    let graph = module_graph();
    let known: BTreeSet<(String, String)> = KNOWN_SHADING_WING_VIOLATIONS
        .iter()
        .map(|entry| {
            let (from, to) = entry
                .split_once(" -> ")
                .unwrap_or_else(|| panic!("known violation {entry:?} is not `from -> to`"));
            (from.to_string(), to.to_string())
        })
        .collect();
    let mut violations = Vec::new();
    let mut seen_known = BTreeSet::new();
    for ((from, to), sites) in &graph {
        let (Some(&lf), Some(&lt)) = (layers.get(from), layers.get(to)) else {
            continue; // Reported by every_module_has_a_layer_and_every_layer_module_exists.
        };
        if lt <= lf {
            continue;
        }
        let edge = (from.clone(), to.clone());
        if known.contains(&edge) {
            seen_known.insert(edge);
        } else {
            violations.push(format!(
                "{from} (layer {lf}) imports {to} (layer {lt}) at {}",
                describe(sites)
            ));
        }
    }
    assert!(
        violations.is_empty(),
        "upward imports (ARCHITECTURE.md's layer table forbids them):\n{}",
        violations.join("\n")
    );
    let stale: Vec<String> = known
        .difference(&seen_known)
        .map(|(from, to)| format!("{from} -> {to}"))
        .collect();
    assert!(
        stale.is_empty(),
        "KNOWN_SHADING_WING_VIOLATIONS lists imports that no longer occur; delete them: {stale:?}"
    );
}

#[test]
fn the_module_graph_has_no_cycle() {
    let graph = module_graph();
    let known: BTreeSet<(String, String)> = KNOWN_SHADING_WING_VIOLATIONS
        .iter()
        .filter_map(|e| e.split_once(" -> "))
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    let mut edges: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for (from, to) in graph.keys() {
        if !known.contains(&(from.clone(), to.clone())) {
            edges.entry(from).or_default().push(to);
        }
    }
    let cycles = strongly_connected(&edges)
        .into_iter()
        .filter(|component| component.len() > 1)
        .map(|component| {
            let cycle = cycle_within(&edges, &component);
            let steps: Vec<String> = cycle
                .windows(2)
                .map(|w| {
                    let sites = &graph[&(w[0].to_string(), w[1].to_string())];
                    format!("{} -> {} ({})", w[0], w[1], describe(sites))
                })
                .collect();
            steps.join("\n  ")
        })
        .collect::<Vec<_>>();
    assert!(
        cycles.is_empty(),
        "import cycles among the top-level modules of src/:\n  {}",
        cycles.join("\n\n  ")
    );
}

/// Import cycles among the submodules of `render/` that exist today, each as its set of
/// modules (a strongly connected component of the graph that [`render_graph`] builds). The
/// list may only shrink: a cycle among other modules, or one that grows a known set, fails
/// [`render_has_no_new_import_cycle`], and so does an entry that is no longer a cycle. Issue
/// 33 asks for none. The six-module circle it named (wavefront, visibility, ids, amodal,
/// ground_truth, film) went when the AOV value types moved to `render::aov`; what is left is
/// the visibility rules' reading of the `TileContext` that holds them.
const KNOWN_RENDER_CYCLES: &[&[&str]] = &[&["visibility", "wavefront"]];

/// The submodules of `render` that a file under `src/render/` names in code, each with its
/// line: `super::x`, `super::{x, y}`, `crate::render::x` and `crate::render::{x, y}`, where `x`
/// is a file of `render/`. Items of `render/mod.rs` itself (`super::Integrator`) do not count:
/// the module root is the facade every submodule may read.
fn render_imports(rel: &Path, text: &str, submodules: &BTreeSet<String>) -> Vec<(String, usize)> {
    let module = module_path(rel);
    let tokens = tokens(&code_only(text));
    let ident = |i: usize| match tokens.get(i) {
        Some((Token::Ident(name), _)) => Some(name.as_str()),
        _ => None,
    };
    let sep = |i: usize| matches!(tokens.get(i), Some((Token::PathSep, _)));
    let mut found = Vec::new();
    let mut i = 0;
    while i < tokens.len() {
        let after_sep = i > 0 && sep(i - 1);
        // Where the path names a child of `render` (the index of that segment), if it does.
        let child_at = match ident(i) {
            Some("crate") if sep(i + 1) && !after_sep => {
                (ident(i + 2) == Some("render") && sep(i + 3)).then_some(i + 4)
            }
            Some("super") if sep(i + 1) && !after_sep => {
                let mut base = module.clone();
                let mut j = i;
                while ident(j) == Some("super") && sep(j + 1) {
                    base.pop();
                    j += 2;
                }
                (base == ["render"]).then_some(j)
            }
            _ => None,
        };
        let Some(j) = child_at else {
            i += 1;
            continue;
        };
        let heads = match tokens.get(j) {
            Some((Token::Ident(name), line)) => vec![(name.clone(), *line)],
            Some((Token::Open, _)) => group_heads(&tokens, j),
            _ => Vec::new(),
        };
        found.extend(
            heads
                .into_iter()
                .filter(|(name, _)| submodules.contains(name)),
        );
        i = j;
    }
    found
}

/// The import graph among the files of `src/render/` (less its root `mod.rs`).
fn render_graph() -> BTreeMap<(String, String), Vec<Site>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/render");
    let mut files = Vec::new();
    rust_files(&dir, &mut files);
    let src = dir.parent().expect("src/").to_path_buf();
    let rels: Vec<PathBuf> = files
        .iter()
        .map(|f| f.strip_prefix(&src).expect("under src/").to_path_buf())
        .filter(|rel| module_path(rel).len() == 2)
        .collect();
    let submodules: BTreeSet<String> = rels.iter().map(|rel| module_path(rel)[1].clone()).collect();
    assert!(
        submodules.len() > 10,
        "found only {submodules:?} in src/render/"
    );
    let mut graph: BTreeMap<(String, String), Vec<Site>> = BTreeMap::new();
    for rel in rels {
        let from = module_path(&rel)[1].clone();
        let text = std::fs::read_to_string(src.join(&rel)).expect("source file is readable");
        for (to, line) in render_imports(&rel, &text, &submodules) {
            if to != from {
                graph.entry((from.clone(), to)).or_default().push(Site {
                    file: format!("src/{}", rel.display()),
                    line,
                });
            }
        }
    }
    graph
}

#[test]
fn render_has_no_new_import_cycle() {
    let graph = render_graph();
    let mut edges: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for (from, to) in graph.keys() {
        edges.entry(from).or_default().push(to);
    }
    let known: Vec<BTreeSet<&str>> = KNOWN_RENDER_CYCLES
        .iter()
        .map(|c| c.iter().copied().collect())
        .collect();
    let components: Vec<Vec<&str>> = strongly_connected(&edges)
        .into_iter()
        .filter(|component| component.len() > 1)
        .collect();
    let new: Vec<String> = components
        .iter()
        .filter(|component| {
            let set: BTreeSet<&str> = component.iter().copied().collect();
            !known.iter().any(|k| set.is_subset(k))
        })
        .map(|component| {
            let cycle = cycle_within(&edges, component);
            let steps: Vec<String> = cycle
                .windows(2)
                .map(|w| {
                    let sites = &graph[&(w[0].to_string(), w[1].to_string())];
                    format!("{} -> {} ({})", w[0], w[1], describe(sites))
                })
                .collect();
            format!("{{{}}}: {}", component.join(", "), steps.join("\n    "))
        })
        .collect();
    assert!(
        new.is_empty(),
        "import cycles among the submodules of src/render/ (beyond KNOWN_RENDER_CYCLES):\n  {}",
        new.join("\n\n  ")
    );
    let stale: Vec<String> = known
        .iter()
        .filter(|k| {
            !components
                .iter()
                .any(|c| c.iter().copied().collect::<BTreeSet<&str>>() == **k)
        })
        .map(|k| format!("{k:?}"))
        .collect();
    assert!(
        stale.is_empty(),
        "KNOWN_RENDER_CYCLES lists sets that are no longer exactly a cycle of src/render/; \
         shrink them to today's: {stale:?}"
    );
}

#[test]
fn the_render_import_parser_finds_children_of_render() {
    let submodules: BTreeSet<String> = ["film", "wavefront", "stats"]
        .map(String::from)
        .into_iter()
        .collect();
    let text = r#"
        use super::film::TileSums; // super::stats in a comment
        use super::{wavefront::{self, Pass}, Integrator};
        use crate::render::stats::RayCounts;
        use crate::light::film;
        fn f() -> &'static str { "super::stats" }
    "#;
    let found: Vec<String> = render_imports(Path::new("render/path.rs"), text, &submodules)
        .into_iter()
        .map(|(m, _)| m)
        .collect();
    assert_eq!(found, ["film", "wavefront", "stats"]);
}

#[test]
fn clap_lives_only_in_the_command_line() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut offenders = Vec::new();
    for file in files {
        let rel = file.strip_prefix(&src).expect("under src/").to_path_buf();
        if rel.starts_with("cli") || rel == Path::new("main.rs") {
            continue;
        }
        let text = std::fs::read_to_string(&file).expect("source file is readable");
        for (token, line) in tokens(&code_only(&text)) {
            if token == Token::Ident("clap".into()) {
                offenders.push(format!("src/{}:{line}", rel.display()));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "clap outside the command line (src/cli/, src/main.rs): {}",
        offenders.join(", ")
    );
}

/// Tarjan's strongly connected components of `edges`.
fn strongly_connected<'a>(edges: &BTreeMap<&'a str, Vec<&'a str>>) -> Vec<Vec<&'a str>> {
    struct State<'a> {
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        components: Vec<Vec<&'a str>>,
    }
    fn visit<'a>(v: &'a str, edges: &BTreeMap<&'a str, Vec<&'a str>>, s: &mut State<'a>) {
        let n = s.index.len();
        s.index.insert(v, n);
        s.low.insert(v, n);
        s.stack.push(v);
        s.on_stack.insert(v);
        for &w in edges.get(v).into_iter().flatten() {
            if !s.index.contains_key(w) {
                visit(w, edges, s);
                let low = s.low[v].min(s.low[w]);
                s.low.insert(v, low);
            } else if s.on_stack.contains(w) {
                let low = s.low[v].min(s.index[w]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                component.push(w);
                if w == v {
                    break;
                }
            }
            s.components.push(component);
        }
    }
    let mut state = State {
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        components: Vec::new(),
    };
    let nodes: BTreeSet<&str> = edges
        .iter()
        .flat_map(|(from, tos)| std::iter::once(*from).chain(tos.iter().copied()))
        .collect();
    for v in nodes {
        if !state.index.contains_key(v) {
            visit(v, edges, &mut state);
        }
    }
    state.components
}

/// One cycle through the first node of `component` (a strongly connected component of more
/// than one node), as the list of its nodes with the first repeated at the end.
fn cycle_within<'a>(
    edges: &BTreeMap<&'a str, Vec<&'a str>>,
    component: &[&'a str],
) -> Vec<&'a str> {
    let members: BTreeSet<&str> = component.iter().copied().collect();
    let start = component[0];
    // Breadth-first from the start's successors back to the start, inside the component.
    let mut previous: BTreeMap<&str, &str> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([start]);
    while let Some(v) = queue.pop_front() {
        for &w in edges.get(v).into_iter().flatten() {
            if !members.contains(w) || previous.contains_key(w) {
                continue;
            }
            previous.insert(w, v);
            if w == start {
                let mut path = vec![start];
                let mut at = v;
                while at != start {
                    path.push(at);
                    at = previous[at];
                }
                path.push(start);
                path.reverse();
                return path;
            }
            queue.push_back(w);
        }
    }
    component.to_vec()
}

#[test]
fn the_import_parser_reads_paths_as_rustc_does() {
    let rel = Path::new("render/job.rs");
    let text = r#"
        use crate::accel::Ray; // crate::bench in a comment
        use super::{film, Film};
        use crate::{light::LightSet, scene::{Mesh, Scene}};
        /* crate::cli in a block comment */
        fn f() -> &'static str { let _ = crate::output::write(); "crate::batch" }
        fn g<'a>(x: &'a str) { let _c = '"'; super::super::texture::lookup(x); }
        pub(crate) fn h() {}
    "#;
    let found: Vec<String> = imports(rel, text).into_iter().map(|(m, _)| m).collect();
    assert_eq!(
        found,
        ["accel", "render", "light", "scene", "output", "texture"],
        "parsed from:\n{text}"
    );
    let main: Vec<String> = imports(
        Path::new("main.rs"),
        "use glint::cli::X; glint::panics::f();",
    )
    .into_iter()
    .map(|(m, _)| m)
    .collect();
    assert_eq!(main, ["cli", "panics"]);
}
