//! Layers import one way (DEVELOPERS.md, issue 23): no import circle between source files of
//! different top-level modules in any crate of the workspace. A circle inside one module folder
//! (e.g. `a/x.rs` ↔ `a/y.rs`) is allowed; [`KNOWN`] lists accepted cross-module circles (none
//! since issue 23 item 3 broke dem-core's `bond/*` ↔ `contact/*`).
//!
//! The file graph is the one `../shared/tools/import_circles.py` builds: an edge f → g when f
//! names a path `crate::a::b::…` (or `super::x`) that resolves to file g, the deepest of
//! `a/b.rs`, `a/b/mod.rs`, `a.rs`, `a/mod.rs` that exists; `#[cfg(test)] mod tests { … }` tails and
//! `//` comments are left out. Circles are the strongly connected components (Tarjan).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Cross-module circles accepted, by crate and files (relative to `src/`). Empty since issue 23
/// item 3 broke dem-core's `bond/*` ↔ `contact/*` circle (the contact pass reaches the fused
/// bond stage through `contact::kernel::PairHook`); a circle is accepted only if all its files
/// are in one of these sets.
const KNOWN: &[(&str, &[&str])] = &[];

fn rs_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rs_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The text without its `#[cfg(test)] mod tests { … }` tail and `//` comments.
fn code(text: &str) -> String {
    let mut end = text.len();
    let mut from = 0;
    while let Some(i) = text[from..].find("#[cfg(test)]") {
        let at = from + i;
        let rest = text[at + "#[cfg(test)]".len()..].trim_start();
        if let Some(r) = rest.strip_prefix("mod") {
            let r = r.trim_start();
            if let Some(r) = r.strip_prefix("tests") {
                if r.trim_start().starts_with('{') {
                    end = at;
                    break;
                }
            }
        }
        from = at + 1;
    }
    text[..end]
        .lines()
        .map(|l| l.find("//").map_or(l, |k| &l[..k]))
        .collect::<Vec<_>>()
        .join("\n")
}

fn ident_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// Start positions of `word` not preceded by an identifier character.
fn occurrences<'a>(text: &'a str, word: &'a str) -> impl Iterator<Item = usize> + 'a {
    let b = text.as_bytes();
    text.match_indices(word)
        .map(|(i, _)| i)
        .filter(move |&i| i == 0 || !ident_char(b[i - 1]))
}

/// The identifier at the start of `s` (`[A-Za-z_][A-Za-z0-9_]*`).
fn ident(s: &str) -> &str {
    let b = s.as_bytes();
    if b.first()
        .is_none_or(|&c| !(c.is_ascii_alphabetic() || c == b'_'))
    {
        return "";
    }
    let n = b.iter().take_while(|&&c| ident_char(c)).count();
    &s[..n]
}

fn lowercase_ident(s: &str) -> bool {
    !s.is_empty()
        && s.bytes()
            .next()
            .is_some_and(|c| c.is_ascii_lowercase() || c == b'_')
        && s.bytes()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == b'_')
}

/// The module paths a file names: `crate::a::b::X`, `crate::a::{b, c::D}`, `super::x`.
fn named_paths(text: &str, here: &[String]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for at in occurrences(text, "crate::") {
        let mut rest = &text[at + "crate::".len()..];
        let mut pre: Vec<String> = Vec::new();
        loop {
            if let Some(inner) = rest.strip_prefix('{') {
                let body = &inner[..inner.find('}').unwrap_or(inner.len())];
                for item in body
                    .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':'))
                    .filter(|t| !t.is_empty())
                {
                    let mut p = pre.clone();
                    p.extend(item.split("::").filter(|s| !s.is_empty()).map(String::from));
                    out.push(p);
                }
                break;
            }
            let id = ident(rest);
            if id.is_empty() {
                break;
            }
            if lowercase_ident(id) && rest[id.len()..].starts_with("::") {
                pre.push(id.to_string());
                rest = &rest[id.len() + 2..];
            } else {
                pre.push(id.to_string());
                out.push(pre);
                break;
            }
        }
    }
    // `super` of a/b.rs and of a/b/mod.rs (here = [a, b] for both) is a.
    let parent = &here[..here.len().saturating_sub(1)];
    let mut from = 0;
    for at in occurrences(text, "super::") {
        if at < from {
            continue;
        }
        let id = ident(&text[at + "super::".len()..]);
        from = at + "super::".len() + id.len();
        if lowercase_ident(id) {
            let mut p = parent.to_vec();
            p.push(id.to_string());
            out.push(p);
        }
    }
    out
}

/// The deepest file a module path resolves to.
fn resolve(src: &Path, parts: &[String]) -> Option<PathBuf> {
    let mut best = None;
    for i in 1..=parts.len() {
        let base = parts[..i].iter().fold(src.to_path_buf(), |p, s| p.join(s));
        for cand in [base.with_extension("rs"), base.join("mod.rs")] {
            if cand.is_file() {
                best = Some(cand);
            }
        }
    }
    best
}

/// The file graph of one crate's `src/`: file (relative to `src`) → files it names.
fn graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut files = Vec::new();
    rs_files(src, &mut files);
    let rel = |p: &Path| {
        p.strip_prefix(src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/")
    };
    let mut edges = BTreeMap::new();
    for f in &files {
        let text = code(&std::fs::read_to_string(f).unwrap());
        let r = rel(f);
        let mut here: Vec<String> = r
            .trim_end_matches(".rs")
            .split('/')
            .map(String::from)
            .collect();
        if here.last().is_some_and(|l| l == "mod") {
            here.pop();
        }
        if here == ["lib"] || here == ["main"] {
            here.clear();
        }
        let targets: BTreeSet<String> = named_paths(&text, &here)
            .iter()
            .filter_map(|p| resolve(src, p))
            .filter(|g| g != f)
            .map(|g| rel(&g))
            .collect();
        edges.insert(r, targets);
    }
    edges
}

/// Strongly connected components of two or more files (Tarjan).
fn circles(edges: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct T<'a> {
        edges: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on: BTreeSet<&'a str>,
        out: Vec<Vec<String>>,
    }
    fn visit<'a>(t: &mut T<'a>, v: &'a str) {
        let k = t.index.len();
        t.index.insert(v, k);
        t.low.insert(v, k);
        t.stack.push(v);
        t.on.insert(v);
        for w in t.edges.get(v).into_iter().flatten() {
            let w = w.as_str();
            if !t.index.contains_key(w) {
                visit(t, w);
                let lw = t.low[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if t.on.contains(w) {
                let iw = t.index[w];
                let lv = t.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if t.low[v] == t.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = t.stack.pop().unwrap();
                t.on.remove(w);
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                t.out.push(comp);
            }
        }
    }
    let mut t = T {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in edges.keys() {
        if !t.index.contains_key(v.as_str()) {
            visit(&mut t, v);
        }
    }
    t.out
}

fn top_modules(comp: &[String]) -> BTreeSet<&str> {
    comp.iter()
        .map(|f| f.split('/').next().unwrap().trim_end_matches(".rs"))
        .collect()
}

/// Cross-module circles of `krate` (its `src/` in `src`) not covered by [`KNOWN`].
fn new_circles(krate: &str, src: &Path) -> Vec<String> {
    circles(&graph(src))
        .into_iter()
        .filter(|c| top_modules(c).len() > 1)
        .filter(|c| {
            !KNOWN
                .iter()
                .any(|(k, files)| *k == krate && c.iter().all(|f| files.contains(&f.as_str())))
        })
        .map(|c| format!("{krate}: {}", c.join(" ")))
        .collect()
}

/// The crates of the repository: the folders beside this one with a `Cargo.toml` and a `src/`
/// (so a crate added later is checked too), sorted.
fn crates(root: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("Cargo.toml").is_file() && p.join("src").is_dir())
        .filter_map(|p| p.file_name()?.to_str().map(String::from))
        .collect();
    v.sort();
    v
}

#[test]
fn no_new_import_circle_across_modules() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let found = crates(&root);
    for k in [
        "clumpgen",
        "dem-core",
        "dem-lab",
        "dem-run",
        "dem-render",
        "dem-cli",
        "validation",
    ] {
        assert!(
            found.iter().any(|c| c == k),
            "crate {k} not found: {found:?}"
        );
    }
    let mut bad = Vec::new();
    for k in &found {
        bad.extend(new_circles(k, &root.join(k).join("src")));
    }
    assert!(
        bad.is_empty(),
        "import circles across top-level modules (break them: move the shared part down to a \
         module both import, or pass it in):\n  {}",
        bad.join("\n  ")
    );
}

/// The finder finds: a synthetic crate with a circle across modules (through `crate::` with
/// braces and through `super::`), one inside a module folder, and a test tail that would close
/// another circle but is left out.
#[test]
fn the_finder_finds_a_circle() {
    let dir = std::env::temp_dir().join(format!("dem-circles-{}", std::process::id()));
    let src = dir.join("src");
    std::fs::create_dir_all(src.join("a")).unwrap();
    let w = |f: &str, t: &str| std::fs::write(src.join(f), t).unwrap();
    w("lib.rs", "pub mod a;\npub mod b;\npub mod c;\n");
    w(
        "a/mod.rs",
        "pub mod x;\npub mod y;\nuse crate::b::{Thing, other::Z};\n",
    );
    w("a/x.rs", "use super::y::Y; // crate::c::Nothing\n");
    w("a/y.rs", "use super::x::X;\n");
    w("b.rs", "pub struct Thing;\nfn f() { crate::a::go() }\n");
    w(
        "c.rs",
        "pub struct C;\n#[cfg(test)]\nmod tests {\n    use crate::a::y::Y;\n}\n",
    );
    let found = circles(&graph(&src));
    assert!(
        found.contains(&vec!["a/mod.rs".to_string(), "b.rs".to_string()]),
        "{found:?}"
    );
    assert!(
        found.contains(&vec!["a/x.rs".to_string(), "a/y.rs".to_string()]),
        "{found:?}"
    );
    assert_eq!(found.len(), 2, "{found:?}");
    let new = new_circles("synthetic", &src);
    assert_eq!(new, ["synthetic: a/mod.rs b.rs"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
