//! Every section reference in the code, tests, scripts, examples and docs names a file of the
//! repository and a section that exists there: `docs/math/chain.md §6.2` needs `docs/math/chain.md`
//! with a heading `## 6.2 …` (any level). A reference list continues with the same file
//! (`docs/math/chain.md §3.1, §14`, `§9–§10`, `§A.7/§A.8`). A section sign with no file before it
//! is an error, except inside `docs/math/`, where it means the file itself. No file names a work
//! item ("issue" and a number) or a numbered source document ("seed" and a zero-padded number).

use std::fs;
use std::path::{Path, PathBuf};

/// The section sign, spelled out so that this file holds no reference itself.
const SECTION: char = '\u{a7}';

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Text files under the scanned folders (and the README), repository-relative.
fn scanned_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = fs::read_dir(dir) else {
            return;
        };
        let mut entries: Vec<PathBuf> = entries.map(|e| e.expect("dir entry").path()).collect();
        entries.sort();
        for p in entries {
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or_default();
            if p.is_dir() {
                if !matches!(name, "target" | ".git" | "__pycache__" | ".venv") {
                    walk(&p, out);
                }
            } else if [".rs", ".md", ".py", ".toml", ".sh", ".txt"]
                .iter()
                .any(|ext| name.ends_with(ext))
                && name != "Cargo.lock"
            {
                out.push(p);
            }
        }
    }
    let root = root();
    let mut files = Vec::new();
    for dir in [
        "src", "tests", "scripts", "benches", "examples", "python", "docs",
    ] {
        walk(&root.join(dir), &mut files);
    }
    files.push(root.join("README.md"));
    files
        .into_iter()
        .map(|p| p.strip_prefix(&root).expect("under the root").to_path_buf())
        .collect()
}

/// A section id right after the sign: `6`, `6.2`, `12.3`, `A`, `B.10` (a trailing full stop is
/// punctuation).
fn section_id(after: &str) -> Option<String> {
    let mut chars = after.char_indices().peekable();
    let mut end = 0;
    match chars.peek() {
        Some(&(_, c)) if c.is_ascii_digit() => {}
        Some(&(_, c)) if c.is_ascii_uppercase() => {
            chars.next();
            end = c.len_utf8();
            // A letter alone or followed by `.digits`.
            if after[end..].starts_with(|c: char| c.is_ascii_alphanumeric()) {
                return None;
            }
        }
        _ => return None,
    }
    for (i, c) in chars {
        if c.is_ascii_digit() || c == '.' {
            end = i + 1;
        } else {
            break;
        }
    }
    let id = after[..end].trim_end_matches('.');
    (!id.is_empty()).then(|| id.to_string())
}

/// The `docs/….md` path that ends right before `pos` (followed by one space), if any.
fn path_before(text: &str, pos: usize) -> Option<String> {
    let head = text[..pos].strip_suffix(' ')?;
    if !head.ends_with(".md") {
        return None;
    }
    let start = head
        .rfind(|c: char| c.is_whitespace() || "`([\"'".contains(c))
        .map_or(0, |i| i + 1);
    let path = &head[start..];
    path.starts_with("docs/").then(|| path.to_string())
}

/// Glue between two references of one list: `, `, `–`, `/`, ` and `, ` or `, `..`.
fn is_glue(gap: &str) -> bool {
    let g = gap.trim();
    matches!(g, "" | "," | "–" | "/" | "and" | "or" | ".." | ", and")
}

/// Whether `file` has a heading whose text starts with the section id.
fn has_heading(file: &str, id: &str) -> bool {
    file.lines().any(|l| {
        let rest = l.trim_start_matches('#');
        rest.len() < l.len()
            && rest
                .strip_prefix(' ')
                .and_then(|r| r.strip_prefix(id))
                .is_some_and(|r| r.is_empty() || r.starts_with(' '))
    })
}

/// All problems of one file's text: unresolved references and references without a file.
fn problems(rel: &Path, text: &str) -> Vec<String> {
    let own = rel.to_string_lossy().replace('\\', "/");
    let in_math = own.starts_with("docs/math/");
    let mut out = Vec::new();
    for (line_no, line) in text.lines().enumerate() {
        // End of the previous reference on this line, and its file.
        let mut prev: Option<(usize, String)> = None;
        for (pos, _) in line.match_indices(SECTION) {
            let after = &line[pos + SECTION.len_utf8()..];
            let Some(id) = section_id(after) else {
                out.push(format!(
                    "{own}:{}: a section sign without a section number",
                    line_no + 1
                ));
                continue;
            };
            let target = if let Some(p) = path_before(line, pos) {
                Some(p)
            } else if let Some((_, file)) = prev
                .as_ref()
                .filter(|(end, _)| *end <= pos && is_glue(&line[*end..pos]))
            {
                Some(file.clone())
            } else if in_math {
                Some(own.clone())
            } else {
                None
            };
            let Some(target) = target else {
                out.push(format!(
                    "{own}:{}: {SECTION}{id} names no docs file (write `docs/math/….md {SECTION}{id}`)",
                    line_no + 1
                ));
                continue;
            };
            match fs::read_to_string(root().join(&target)) {
                Ok(doc) if has_heading(&doc, &id) => {}
                Ok(_) => out.push(format!(
                    "{own}:{}: {target} has no heading {SECTION}{id}",
                    line_no + 1
                )),
                Err(_) => out.push(format!(
                    "{own}:{}: {target} does not exist ({SECTION}{id})",
                    line_no + 1
                )),
            }
            prev = Some((pos + SECTION.len_utf8() + id.len(), target));
        }
    }
    // Work items are not part of the product: no "issue N" or "issue-N" (any case) in what a
    // newcomer reads; nor the numbered source documents ("seed 001"): name the source itself.
    let lower = text.to_ascii_lowercase();
    for (word, what) in [
        ("issue ", "a work item (\"issue N\")"),
        ("issue-", "a work item (\"issue-N\")"),
        (
            "seed 0",
            "a numbered source document (\"seed 0NN\"): name the source",
        ),
    ] {
        for (i, _) in lower.match_indices(word) {
            let rest = &lower[i + word.len()..];
            if rest.starts_with(|c: char| c.is_ascii_digit()) {
                let line = text[..i].lines().count().max(1);
                out.push(format!(
                    "{own}:{line}: names {what}: say what the code does instead"
                ));
            }
        }
    }
    // The documents the math pages replace are not part of the repository.
    for gone in [
        "design-chain.md",
        "companion-methods",
        "peers-and-cad",
        "shared/spec",
    ] {
        if let Some(i) = text.find(gone) {
            let line = text[..i].lines().count().max(1);
            out.push(format!(
                "{own}:{line}: names `{gone}`, which is not in the repository"
            ));
        }
    }
    out
}

#[test]
fn section_references_resolve_to_headings_in_the_repository() {
    let mut all = Vec::new();
    let mut refs = 0;
    // This file spells the sign and the old names out on purpose (the self-test below).
    let this = Path::new("tests/it/doc_refs.rs");
    for rel in scanned_files().into_iter().filter(|f| f != this) {
        let Ok(text) = fs::read_to_string(root().join(&rel)) else {
            continue;
        };
        refs += text.matches(SECTION).count();
        all.extend(problems(&rel, &text));
    }
    assert!(
        refs > 100,
        "only {refs} section signs found: is the scan looking in the right place?"
    );
    assert!(
        all.is_empty(),
        "{} unresolved section references:\n{}",
        all.len(),
        all.join("\n")
    );
}

#[test]
fn the_reference_checker_catches_broken_references() {
    let p = |text: &str| problems(Path::new("src/x.rs"), text).len();
    assert_eq!(p("// see docs/math/chain.md \u{a7}6.2 and \u{a7}6.4."), 0);
    assert_eq!(p("// see docs/math/chain.md \u{a7}6.2, \u{a7}99.9"), 1);
    assert_eq!(p("// see docs/math/nothere.md \u{a7}1"), 1);
    assert_eq!(p("// spec \u{a7}6.2"), 1);
    assert_eq!(p("// see docs/math/chain.md \u{a7}6.2; text, \u{a7}6.3"), 1);
    assert_eq!(p("// docs/math/companion.md \u{a7}B.10 and \u{a7}B.99"), 1);
    assert_eq!(p("// design-chain.md"), 1);
    assert_eq!(p("// as Issue 18 asked"), 1);
    assert_eq!(p("// the issue 7 reproducer"), 1);
    assert_eq!(p("// an issue of units"), 0);
    assert_eq!(p("// the issue-15 targets"), 1);
    assert_eq!(p("// from seed 001, formula (3)"), 1);
    assert_eq!(p("// campaign seed 1659486911, run #359"), 0);
}
