//! The documentation a user reads is self-contained: every relative link in `README.md` and `docs/*.md`
//! names a file of the repository, and a link to a section of a Markdown file (`file.md#section`, or
//! `#section` within the same file) names a heading that file has, by the anchor GitHub derives from it.
//! Links to the web (`https:`, `mailto:`) are not followed; fenced code blocks are not read.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `README.md` and every `docs/*.md`, in name order.
fn documents() -> Vec<PathBuf> {
    let mut docs = vec![root().join("README.md")];
    let mut more: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .expect("docs/ exists")
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    more.sort();
    docs.extend(more);
    docs
}

/// The lines of `text` outside fenced code blocks, with their line numbers.
fn prose(text: &str) -> Vec<(usize, &str)> {
    let mut fenced = false;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        } else if !fenced {
            out.push((i + 1, line));
        }
    }
    out
}

/// The targets of the inline links `[text](target)` on `line`, code spans left out.
fn link_targets(line: &str) -> Vec<&str> {
    let mut targets = Vec::new();
    let mut in_code = false;
    let bytes = line.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'`' => in_code = !in_code,
            b']' if !in_code && bytes.get(i + 1) == Some(&b'(') => {
                if let Some(len) = line[i + 2..].find(')') {
                    targets.push(&line[i + 2..i + 2 + len]);
                    i += 2 + len;
                }
            }
            _ => {}
        }
        i += 1;
    }
    targets
}

/// The anchor GitHub gives a heading: lower case, letters, digits, `-` and `_` kept, spaces to `-`,
/// everything else dropped.
fn anchor(heading: &str) -> String {
    heading
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            '-' | '_' => Some(c),
            c if c.is_alphanumeric() => Some(c),
            _ => None,
        })
        .flat_map(char::to_lowercase)
        .collect()
}

/// The anchors of the headings of the Markdown file `path`.
fn anchors(path: &Path) -> BTreeSet<String> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    prose(&text)
        .into_iter()
        .filter_map(|(_, l)| l.strip_prefix('#').map(|h| anchor(h.trim_start_matches('#').trim())))
        .collect()
}

/// Every broken link of `doc` (a document of the repository at `root`), as `file:line: target (why)`.
fn broken_links(doc: &Path, root: &Path) -> Vec<String> {
    let root = root.canonicalize().expect("the repository exists");
    let text = std::fs::read_to_string(doc).expect("a readable document");
    let dir = doc.parent().expect("a document sits in a directory");
    let mut broken = Vec::new();
    for (n, line) in prose(&text) {
        for target in link_targets(line) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (file, section) = target.split_once('#').unwrap_or((target, ""));
            let path = if file.is_empty() { doc.to_path_buf() } else { dir.join(file) };
            let why = if !path.exists() {
                Some("no such file")
            } else if !path.canonicalize().is_ok_and(|p| p.starts_with(&root)) {
                Some("outside the repository")
            } else if !section.is_empty()
                && path.extension().is_some_and(|e| e == "md")
                && !anchors(&path).contains(section)
            {
                Some("no such section")
            } else {
                None
            };
            if let Some(why) = why {
                broken.push(format!("{}:{n}: {target} ({why})", doc.display()));
            }
        }
    }
    broken
}

#[test]
fn every_link_of_the_docs_names_a_file_and_section_of_the_repository() {
    let docs = documents();
    assert!(docs.len() > 1, "README.md and docs/*.md");
    let broken: Vec<String> = docs.iter().flat_map(|d| broken_links(d, &root())).collect();
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

/// The checker itself: it finds a missing file, a missing section and a link out of the repository,
/// and reads links only outside code.
#[test]
fn the_checker_finds_what_is_broken() {
    assert_eq!(anchor("4.1 Choice policies"), "41-choice-policies");
    assert_eq!(anchor("Synthesis (`codegen synth`)"), "synthesis-codegen-synth");
    assert_eq!(link_targets("see [a](x.md) and `[b](y.md)` and [c](z.md#s)"), vec!["x.md", "z.md#s"]);
    let dir = std::env::temp_dir().join(format!("doc-links-{}", std::process::id()));
    let repo = dir.join("repo");
    std::fs::create_dir_all(&repo).unwrap();
    std::fs::write(dir.join("outside.md"), "# Outside\n").unwrap();
    let doc = repo.join("doc.md");
    std::fs::write(
        &doc,
        "# Title\n[ok](#title) [gone](#nope) [none](missing.md) [out](../outside.md)\n```\n[code](skipped.md)\n```\n",
    )
    .unwrap();
    let broken = broken_links(&doc, &repo);
    std::fs::remove_dir_all(&dir).unwrap();
    let whys: Vec<&str> = broken.iter().map(|b| b.split_once(":2: ").map_or("", |(_, w)| w)).collect();
    assert_eq!(
        whys,
        ["#nope (no such section)", "missing.md (no such file)", "../outside.md (outside the repository)"],
        "{broken:?}"
    );
}
