//! Every relative link in README.md, ARCHITECTURE.md and docs/*.md, every repository path a
//! page names in backticks, and every repository path named in a doc comment in `src/` exists,
//! so that moving or deleting a file cannot leave a page or a doc comment pointing at nothing.

use std::path::{Path, PathBuf};

/// The repository's root.
fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The top-level folders whose paths pages and doc comments name (`src/…`, `tests/…`).
const TOP_LEVEL: [&str; 9] = [
    "src/",
    "tests/",
    "docs/",
    "scripts/",
    "tools/",
    "examples/",
    "ffi/",
    "python/",
    "scenes/",
];

/// A place a page or a comment names, and where it names it.
struct Reference {
    target: String,
    from: String,
}

/// The pages checked: README.md, ARCHITECTURE.md and every Markdown page in docs/.
fn pages(root: &Path) -> Vec<PathBuf> {
    let mut pages = vec![root.join("README.md"), root.join("ARCHITECTURE.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .expect("docs/ exists")
        .map(|e| e.expect("read docs/").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    pages
}

/// The targets of the inline links and images (`[text](target)`, `![alt](target)`) and of the
/// reference definitions (`[name]: target`) of a Markdown page, outside fenced code blocks.
fn markdown_links(text: &str) -> Vec<(usize, String)> {
    let mut links = Vec::new();
    let mut fenced = false;
    for (n, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let end = after.find(')').unwrap_or(after.len());
            links.push((n + 1, after[..end].to_string()));
            rest = &after[end..];
        }
        let trimmed = line.trim_start();
        if trimmed.starts_with('[')
            && let Some(close) = trimmed.find("]: ")
        {
            links.push((n + 1, trimmed[close + 3..].trim().to_string()));
        }
    }
    links
}

/// The repository paths named in `text`: words that begin with a top-level folder, up to the
/// first character that cannot be part of a path, without trailing punctuation. Placeholders
/// (`tests/fuzz-corpus/TARGET/`), patterns (`*`, `{…}`, `<…>`) and paths outside the repository
/// (`../shared/…`) are not names of files and are left out.
fn named_paths(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    for top in TOP_LEVEL {
        let mut from = 0;
        while let Some(at) = text[from..].find(top) {
            let start = from + at;
            from = start + top.len();
            let before = text[..start].chars().next_back();
            if before.is_some_and(|c| c.is_alphanumeric() || "_-./:".contains(c)) {
                continue; // part of a longer path or word (`../shared/scenes/`, `python/tests/`'s tail)
            }
            let len = text[start..]
                .find(|c: char| !(c.is_alphanumeric() || "_-./".contains(c)))
                .unwrap_or(text.len() - start);
            let path = text[start..start + len].trim_end_matches(['.', ',']);
            let placeholder = path.split('/').any(|part| {
                part.len() > 1 && part.chars().all(|c| c.is_ascii_uppercase() || c == '_')
            });
            let pattern = text[start + len..].starts_with(['*', '{', '<', '[']);
            if !placeholder && !pattern && path.len() > top.len() {
                found.push(path.to_string());
            }
        }
    }
    found
}

/// The spans of `text` between backticks.
fn code_spans(text: &str) -> Vec<&str> {
    text.split('`').skip(1).step_by(2).collect()
}

/// Every reference of the pages: their relative links, resolved from the page's folder, and
/// the repository paths they name in backticks, resolved from the root.
fn page_references(root: &Path) -> Vec<Reference> {
    let mut references = Vec::new();
    for page in pages(root) {
        let text = std::fs::read_to_string(&page).expect("read a page");
        let name = page
            .strip_prefix(root)
            .expect("under the root")
            .display()
            .to_string();
        let folder = page.parent().expect("a page has a folder");
        for (line, link) in markdown_links(&text) {
            let link = link.split_whitespace().next().unwrap_or("");
            let path = link.split('#').next().unwrap_or("");
            if path.is_empty() || path.contains("://") || path.starts_with("mailto:") {
                continue;
            }
            let target = folder.join(urlencoding_decode(path));
            let target = target
                .strip_prefix(root)
                .map_or(target.clone(), Path::to_path_buf);
            references.push(Reference {
                target: target.display().to_string(),
                from: format!("{name}:{line} (link)"),
            });
        }
        for (n, line) in text.lines().enumerate() {
            for span in code_spans(line) {
                for path in named_paths(span) {
                    references.push(Reference {
                        target: path,
                        from: format!("{name}:{}", n + 1),
                    });
                }
            }
        }
    }
    references
}

/// `%20` and the like, as a Markdown link may write a space.
fn urlencoding_decode(path: &str) -> String {
    urlencoding::decode(path).map_or_else(|_| path.to_string(), |p| p.into_owned())
}

/// The repository paths named in the doc comments (`///`, `//!`) of every Rust file in `src/`.
fn doc_comment_references(root: &Path) -> Vec<Reference> {
    let mut files = Vec::new();
    let mut folders = vec![root.join("src")];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).expect("read a folder of src/") {
            let path = entry.expect("an entry of src/").path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    let mut references = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(&file).expect("read a source file");
        let name = file
            .strip_prefix(root)
            .expect("under the root")
            .display()
            .to_string();
        for (n, line) in text.lines().enumerate() {
            let line = line.trim_start();
            if !(line.starts_with("///") || line.starts_with("//!")) {
                continue;
            }
            for path in named_paths(line) {
                references.push(Reference {
                    target: path,
                    from: format!("{name}:{}", n + 1),
                });
            }
        }
    }
    references
}

/// The references whose target does not exist, each as `TARGET (named at PAGE:LINE)`.
fn dangling(root: &Path, references: Vec<Reference>) -> Vec<String> {
    references
        .into_iter()
        .filter(|r| !root.join(&r.target).exists())
        .map(|r| format!("{} (named at {})", r.target, r.from))
        .collect()
}

#[test]
fn pages_link_only_to_files_that_exist() {
    let root = root();
    let references = page_references(&root);
    assert!(
        references.len() > 100,
        "only {} references found: is the scan broken?",
        references.len()
    );
    let missing = dangling(&root, references);
    assert!(
        missing.is_empty(),
        "dangling links or paths in the pages:\n{missing:#?}"
    );
}

#[test]
fn doc_comments_name_only_files_that_exist() {
    let root = root();
    let references = doc_comment_references(&root);
    assert!(
        references.len() > 10,
        "only {} paths found: is the scan broken?",
        references.len()
    );
    let missing = dangling(&root, references);
    assert!(
        missing.is_empty(),
        "doc comments in src/ naming files that do not exist:\n{missing:#?}"
    );
}

#[test]
fn the_scan_finds_links_and_paths_and_leaves_out_the_rest() {
    let page = "See [the guide](docs/guide.md#top), ![a](images/a.png) and \
                [x](https://example.org).\n```\n[not](a-link.md)\n```\n[ref]: docs/ref.md\n";
    let links: Vec<String> = markdown_links(page).into_iter().map(|(_, l)| l).collect();
    assert_eq!(
        links,
        [
            "docs/guide.md#top",
            "images/a.png",
            "https://example.org",
            "docs/ref.md"
        ]
    );
    let paths = named_paths(
        "`src/output/atomic.rs`, tests/fuzz-corpus/TARGET/, ../shared/scenes/x.glb, \
         target/debug/deps/embree_lifetimes-*, python/tests/test_glint.py.",
    );
    assert_eq!(
        paths,
        ["src/output/atomic.rs", "python/tests/test_glint.py"]
    );
    // A dangling reference is reported.
    let missing = dangling(
        &root(),
        vec![Reference {
            target: "docs/no-such-page.md".into(),
            from: "here".into(),
        }],
    );
    assert_eq!(missing.len(), 1);
}
