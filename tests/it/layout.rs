//! The module list of docs/layout.md is the source tree: every module under `src/` with the first line of
//! its `//!` doc, in the order of the folders. `NCGEAR_BLESS=1 cargo test --release layout`
//! rewrites the block from the tree. The README stays short: at most 250 lines.

use std::fs;
use std::path::{Path, PathBuf};

const BEGIN: &str = "<!-- modules:begin (generated from the //! lines; tests/it/layout.rs) -->";
const END: &str = "<!-- modules:end -->";

/// Files over this many lines of code must be named in docs/layout.md with a reason.
const MAX_LINES: usize = 500;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `(module path, file)` for every module file under `dir`, depth first, `mod.rs` first.
fn modules(dir: &Path, prefix: &str, out: &mut Vec<(String, PathBuf)>) {
    let mut entries: Vec<PathBuf> = fs::read_dir(dir)
        .expect("src is readable")
        .map(|e| e.expect("dir entry").path())
        .collect();
    entries.sort();
    if let Some(m) = entries.iter().find(|p| p.ends_with("mod.rs")) {
        out.push((prefix.to_string(), m.clone()));
    }
    for p in &entries {
        let name = p.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
        let path = if prefix.is_empty() {
            name.to_string()
        } else {
            format!("{prefix}::{name}")
        };
        if p.is_dir() {
            modules(p, &path, out);
        } else if p.extension().is_some_and(|e| e == "rs")
            && !["mod", "lib", "main"].contains(&name)
        {
            out.push((path, p.clone()));
        }
    }
}

/// The first sentence of a file's `//!` doc (its first paragraph, up to the first full stop).
fn purpose(file: &Path) -> String {
    let text = fs::read_to_string(file).expect("module file is readable");
    let para: Vec<&str> = text
        .lines()
        .skip_while(|l| !l.starts_with("//!"))
        .map_while(|l| l.strip_prefix("//!").map(str::trim))
        .take_while(|l| !l.is_empty())
        .collect();
    let para = para.join(" ");
    let end = para.find(". ").map_or(para.len(), |i| i + 1);
    para[..end].trim_end_matches(['.', ':']).trim().to_string()
}

/// Lines that are neither blank nor comments.
fn code_lines(file: &Path) -> usize {
    fs::read_to_string(file)
        .expect("module file is readable")
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with("//"))
        .count()
}

fn expected_block() -> String {
    let mut list = Vec::new();
    modules(&root().join("src"), "", &mut list);
    let mut s = String::new();
    for (module, file) in list.iter().filter(|(m, _)| !m.is_empty()) {
        let depth = module.matches("::").count();
        s.push_str(&format!(
            "{}- `{module}`: {}\n",
            "  ".repeat(depth),
            purpose(file)
        ));
    }
    s
}

#[test]
fn readme_module_list_matches_the_source_tree() {
    let readme_path = root().join("docs/layout.md");
    let readme = fs::read_to_string(&readme_path).expect("docs/layout.md");
    let (Some(b), Some(e)) = (readme.find(BEGIN), readme.find(END)) else {
        panic!("docs/layout.md has no generated module list ({BEGIN} … {END})");
    };
    let current = &readme[b + BEGIN.len()..e];
    let want = format!("\n{}", expected_block());
    if current != want {
        if std::env::var_os("NCGEAR_BLESS").is_some() {
            let updated = format!("{}{BEGIN}{want}{}", &readme[..b], &readme[e..]);
            fs::write(&readme_path, updated).expect("docs/layout.md writable");
            return;
        }
        panic!(
            "docs/layout.md's module list is out of date; run NCGEAR_BLESS=1 cargo test --release layout. Expected:\n{want}"
        );
    }
}

#[test]
fn every_module_says_what_it_is_for() {
    let mut list = Vec::new();
    modules(&root().join("src"), "", &mut list);
    let missing: Vec<&str> = list
        .iter()
        .filter(|(m, f)| !m.is_empty() && purpose(f).is_empty())
        .map(|(m, _)| m.as_str())
        .collect();
    assert!(
        missing.is_empty(),
        "modules without a //! line: {missing:?}"
    );
}

#[test]
fn long_files_are_explained_in_the_readme() {
    let readme = fs::read_to_string(root().join("docs/layout.md")).expect("docs/layout.md");
    let mut list = Vec::new();
    modules(&root().join("src"), "", &mut list);
    let unexplained: Vec<String> = list
        .iter()
        .filter(|(_, f)| code_lines(f) > MAX_LINES)
        .map(|(_, f)| f.strip_prefix(root()).unwrap_or(f).display().to_string())
        .filter(|rel| !readme.contains(&format!("`{rel}`")))
        .collect();
    assert!(
        unexplained.is_empty(),
        "files over {MAX_LINES} lines of code not explained in docs/layout.md: {unexplained:?}"
    );
}

/// The README is the front door — what it is, the two commands, one example per command, links
/// into docs/ — and stays short enough to read: at most 250 lines; every docs/ page it links exists.
#[test]
fn the_readme_is_short_and_its_links_resolve() {
    let readme = fs::read_to_string(root().join("README.md")).expect("README.md");
    let lines = readme.lines().count();
    assert!(
        lines <= 250,
        "README.md has {lines} lines (at most 250: the rest belongs in docs/)"
    );
    let mut missing = Vec::new();
    for part in readme.split("](").skip(1) {
        let target = part.split([')', '#']).next().unwrap_or_default();
        if !target.is_empty() && !target.starts_with("http") && !root().join(target).exists() {
            missing.push(target.to_string());
        }
    }
    assert!(
        missing.is_empty(),
        "README.md links to missing files: {missing:?}"
    );
}
