//! No import circle between source files of different top-level modules, in any crate of the
//! workspace (issue 23): the CI check that keeps the module graph one-way (e.g. `bond` imports
//! `contact`, never back, see docs/dem-core-design.md).
//!
//! An edge f → g when file f names a path `crate::a::b::…`, `super::…` or `self::…` (in `use`
//! lines or inline, `{…}` groups included) that resolves to file g: the deepest of `a/b.rs`,
//! `a/b/mod.rs`, `a.rs`, `a/mod.rs` that exists. Comments and the `#[cfg(test)] mod tests`
//! tail of a file are left out; so are `tests/`, `benches/` and `examples/` folders. A circle
//! (a strongly connected set of two or more files) whose files lie in two or more top-level
//! modules (the first component of the path under `src/`) fails the test; a circle inside one
//! module folder is printed, not counted.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// One crate's sources: path under `src/` (with `/`, e.g. `bond/kernel.rs`) → text.
type Sources = BTreeMap<String, String>;

/// The text with the `#[cfg(test)] mod tests` tail and the comments removed.
fn strip(text: &str) -> String {
    let mut t = text;
    // The test tail: `#[cfg(test)]`, whitespace, `mod tests`, whitespace, `{` … to the end.
    let mut from = 0;
    while let Some(k) = t[from..].find("#[cfg(test)]") {
        let at = from + k;
        let rest = t[at + "#[cfg(test)]".len()..].trim_start();
        let is_tail = rest
            .strip_prefix("mod")
            .filter(|r| r.starts_with(char::is_whitespace))
            .map(|r| r.trim_start())
            .and_then(|r| r.strip_prefix("tests"))
            .is_some_and(|r| r.trim_start().starts_with('{'));
        if is_tail {
            t = &t[..at];
            break;
        }
        from = at + 1;
    }
    // Line comments (doc comments included) and block comments.
    let mut out = String::with_capacity(t.len());
    let b = t.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
                    depth += 1;
                    i += 2;
                } else if b[i] == b'*' && b.get(i + 1) == Some(&b'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            out.push(' ');
        } else {
            let c = t[i..].chars().next().unwrap();
            out.push(c);
            i += c.len_utf8();
        }
    }
    out
}

fn ident_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// The paths of a use tree starting at `s[*i]` (after a `::`): `a::b::C`, `a::{b, c::D}`,
/// nested groups. Each path is a list of segments; parsing stops at anything else.
fn tree(s: &[u8], i: &mut usize, prefix: &[String], out: &mut Vec<Vec<String>>) {
    let skip_ws = |i: &mut usize| {
        while *i < s.len() && s[*i].is_ascii_whitespace() {
            *i += 1;
        }
    };
    let mut path = prefix.to_vec();
    loop {
        skip_ws(i);
        if *i < s.len() && s[*i] == b'{' {
            *i += 1;
            loop {
                skip_ws(i);
                if *i >= s.len() {
                    return;
                }
                if s[*i] == b'}' {
                    *i += 1;
                    return;
                }
                if s[*i] == b',' {
                    *i += 1;
                    continue;
                }
                let before = *i;
                tree(s, i, &path, out);
                if *i == before {
                    // Not a path (e.g. `*`): skip one character.
                    *i += 1;
                }
            }
        }
        let start = *i;
        while *i < s.len() && ident_char(s[*i]) {
            *i += 1;
        }
        if *i == start {
            out.push(path);
            return;
        }
        path.push(String::from_utf8_lossy(&s[start..*i]).into_owned());
        if s[*i..].starts_with(b"::") {
            *i += 2;
        } else {
            out.push(path);
            return;
        }
    }
}

/// The module path of a file (`bond/kernel.rs` → [bond, kernel]; `bond/mod.rs` → [bond];
/// `lib.rs`, `main.rs` → []).
fn module_of(file: &str) -> Vec<String> {
    let mut parts: Vec<String> = file
        .trim_end_matches(".rs")
        .split('/')
        .map(str::to_string)
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    if parts.len() == 1 && (parts[0] == "lib" || parts[0] == "main") {
        parts.clear();
    }
    parts
}

/// The file a module path names: the deepest prefix with a file.
fn resolve(src: &Sources, parts: &[String]) -> Option<String> {
    let mut best = None;
    for k in 1..=parts.len() {
        let base = parts[..k].join("/");
        for cand in [format!("{base}.rs"), format!("{base}/mod.rs")] {
            if src.contains_key(&cand) {
                best = Some(cand);
            }
        }
    }
    best
}

/// The import edges of one crate: file → the files it names.
fn edges(src: &Sources) -> BTreeMap<String, BTreeSet<String>> {
    let mut e = BTreeMap::new();
    for (file, text) in src {
        let text = strip(text);
        let s = text.as_bytes();
        let here = module_of(file);
        let mut targets = BTreeSet::new();
        let mut i = 0;
        while i < s.len() {
            let boundary = i == 0 || (!ident_char(s[i - 1]) && s[i - 1] != b':');
            let word = |w: &str| boundary && s[i..].starts_with(w.as_bytes());
            let base: Option<(Vec<String>, usize)> = if word("crate::") {
                Some((Vec::new(), "crate::".len()))
            } else if word("self::") {
                Some((here.clone(), "self::".len()))
            } else if word("super::") {
                let mut base = here.clone();
                let mut k = i;
                while s[k..].starts_with(b"super::") {
                    base.pop();
                    k += "super::".len();
                }
                Some((base, k - i))
            } else {
                None
            };
            let Some((base, skip)) = base else {
                i += 1;
                continue;
            };
            i += skip;
            let mut paths = Vec::new();
            tree(s, &mut i, &base, &mut paths);
            for p in paths {
                if let Some(g) = resolve(src, &p) {
                    if g != *file {
                        targets.insert(g);
                    }
                }
            }
        }
        e.insert(file.clone(), targets);
    }
    e
}

/// The strongly connected sets of two or more files (Tarjan), each sorted.
fn circles(e: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct T<'a> {
        e: &'a BTreeMap<String, BTreeSet<String>>,
        idx: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on: BTreeSet<&'a str>,
        out: Vec<Vec<String>>,
    }
    impl<'a> T<'a> {
        fn visit(&mut self, v: &'a str) {
            let n = self.idx.len();
            self.idx.insert(v, n);
            self.low.insert(v, n);
            self.stack.push(v);
            self.on.insert(v);
            for w in self.e.get(v).into_iter().flatten() {
                let w = w.as_str();
                if !self.idx.contains_key(w) {
                    self.visit(w);
                    let l = self.low[v].min(self.low[w]);
                    self.low.insert(v, l);
                } else if self.on.contains(w) {
                    let l = self.low[v].min(self.idx[w]);
                    self.low.insert(v, l);
                }
            }
            if self.low[v] == self.idx[v] {
                let mut comp = Vec::new();
                loop {
                    let w = self.stack.pop().unwrap();
                    self.on.remove(w);
                    comp.push(w.to_string());
                    if w == v {
                        break;
                    }
                }
                if comp.len() > 1 {
                    comp.sort();
                    self.out.push(comp);
                }
            }
        }
    }
    let mut t = T {
        e,
        idx: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in e.keys() {
        if !t.idx.contains_key(v.as_str()) {
            t.visit(v);
        }
    }
    t.out.sort();
    t.out
}

/// The top-level modules a circle spans.
fn modules(circle: &[String]) -> BTreeSet<String> {
    circle
        .iter()
        .map(|f| {
            f.split('/')
                .next()
                .unwrap()
                .trim_end_matches(".rs")
                .to_string()
        })
        .collect()
}

/// The circles of one crate's sources that span two or more top-level modules.
fn cross_module(src: &Sources) -> Vec<Vec<String>> {
    circles(&edges(src))
        .into_iter()
        .filter(|c| modules(c).len() > 1)
        .collect()
}

/// Every `.rs` file under `dir`, keyed by its path under `src` (with `/`).
fn read_tree(src: &Path, dir: &Path, out: &mut Sources) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            read_tree(src, &p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            let rel = p.strip_prefix(src).unwrap();
            let key = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join("/");
            out.insert(key, std::fs::read_to_string(&p).unwrap());
        }
    }
}

/// The `src/` folders of every crate under `dir` (a folder with `Cargo.toml` and `src/`),
/// skipping `target`, hidden folders, `tests`, `benches` and `examples`.
fn crates(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    if dir.join("Cargo.toml").is_file() && dir.join("src").is_dir() {
        out.push(dir.join("src"));
    }
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .collect();
    entries.sort();
    for p in entries {
        let name = p.file_name().unwrap().to_string_lossy();
        let skip = name.starts_with('.')
            || ["target", "tests", "benches", "examples", "src"].contains(&name.as_ref());
        if !skip {
            crates(&p, out);
        }
    }
}

#[test]
fn no_import_circle_across_modules_in_the_workspace() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let mut dirs = Vec::new();
    crates(root, &mut dirs);
    // The workspace's members at least (and the fuzz crate beside them).
    for member in ["clumpgen", "dem-core", "dem-cli", "validation"] {
        assert!(dirs.contains(&root.join(member).join("src")), "{member}");
    }
    let mut bad = Vec::new();
    let mut files = 0;
    for src in &dirs {
        let mut s = Sources::new();
        read_tree(src, src, &mut s);
        files += s.len();
        let name = src.parent().unwrap().strip_prefix(root).unwrap().display();
        for c in circles(&edges(&s)) {
            let m: Vec<_> = modules(&c).into_iter().collect();
            let what = if m.len() > 1 {
                "CROSS-MODULE"
            } else {
                "in-module"
            };
            let line = format!(
                "{name}: {what} circle of {} files across {}: {}",
                c.len(),
                m.join(","),
                c.join(" ")
            );
            println!("{line}");
            if m.len() > 1 {
                bad.push(line);
            }
        }
    }
    assert!(files > 100, "read {files} files: is the workspace there?");
    assert!(
        bad.is_empty(),
        "import circles between files of different modules (make imports go one way; see \
         docs/dem-core-design.md):\n{}",
        bad.join("\n")
    );
}

fn sources(files: &[(&str, &str)]) -> Sources {
    files
        .iter()
        .map(|(p, t)| (p.to_string(), t.to_string()))
        .collect()
}

#[test]
fn a_circle_across_two_modules_is_found() {
    // bond/fused.rs → contact/kernel.rs (a `use` group) → bond/fused.rs (an inline path).
    let s = sources(&[
        ("lib.rs", "pub mod bond;\npub mod contact;\n"),
        ("bond/mod.rs", "pub mod fused;\n"),
        (
            "bond/fused.rs",
            "use crate::contact::{kernel::{Cols, BLOCK}, PairKin};\n",
        ),
        ("contact/mod.rs", "pub mod kernel;\npub struct PairKin;\n"),
        (
            "contact/kernel.rs",
            "pub const BLOCK: usize = 64;\nfn f(v: &crate::bond::fused::View) {}\n",
        ),
    ]);
    assert_eq!(
        cross_module(&s),
        vec![vec![
            "bond/fused.rs".to_string(),
            "contact/kernel.rs".into()
        ]]
    );
    // One way only: no circle.
    let mut one_way = s.clone();
    one_way.insert(
        "contact/kernel.rs".into(),
        "pub const BLOCK: usize = 64;\n".into(),
    );
    assert!(cross_module(&one_way).is_empty());
}

#[test]
fn super_paths_resolve_from_the_file_and_mod_rs() {
    // a/x.rs: super:: is `a`; a/mod.rs: super:: is the crate root; super::super:: climbs two;
    // self:: in b/y.rs is b::y.
    let s = sources(&[
        ("lib.rs", ""),
        ("a/mod.rs", "use super::c::Z;\n"),
        ("a/x.rs", "use super::super::b::y::Z;\n"),
        ("b/mod.rs", ""),
        ("b/y.rs", "use crate::a::x;\nuse self::inner::Q;\n"),
        ("b/y/inner.rs", "use super::super::super::a::X;\n"),
        ("c.rs", "pub struct Z;\n"),
    ]);
    let e = edges(&s);
    assert_eq!(e["a/mod.rs"], BTreeSet::from(["c.rs".to_string()]));
    assert_eq!(e["a/x.rs"], BTreeSet::from(["b/y.rs".to_string()]));
    assert_eq!(
        e["b/y.rs"],
        BTreeSet::from(["a/x.rs".to_string(), "b/y/inner.rs".into()])
    );
    assert_eq!(e["b/y/inner.rs"], BTreeSet::from(["a/mod.rs".to_string()]));
    assert_eq!(
        cross_module(&s),
        vec![vec!["a/x.rs".to_string(), "b/y.rs".into()]]
    );
}

#[test]
fn comments_test_tails_and_in_module_circles_do_not_count() {
    let s = sources(&[
        ("lib.rs", ""),
        // A doc link, a comment and a test tail naming the other module: no edges.
        (
            "a.rs",
            "//! See [`crate::b::f`].\n/* crate::b::f */ fn g() {}\n\
             #[cfg(test)]\nmod tests {\n    use crate::b::f;\n}\n",
        ),
        ("b.rs", "use crate::a::g;\n"),
        // A circle inside one module folder is not counted.
        ("c/mod.rs", "use self::d::D;\n"),
        ("c/d.rs", "use super::E;\n"),
    ]);
    let e = edges(&s);
    assert!(e["a.rs"].is_empty());
    assert_eq!(
        circles(&e),
        vec![vec!["c/d.rs".to_string(), "c/mod.rs".into()]]
    );
    assert!(cross_module(&s).is_empty());
}
