//! The report's pages: sections of Markdown with figures (SVG) and data files (JSON), written as
//! `index.md` (figures linked) and a self-contained `index.html` (figures inlined, Markdown
//! rendered by pulldown-cmark with tables).

use crate::error::{Error, Result};
use std::path::Path;

/// A figure: file name in the report folder, caption, SVG text.
#[derive(Debug, Clone)]
pub struct Figure {
    pub file: String,
    pub caption: String,
    pub svg: String,
}

/// One section of the report.
#[derive(Debug, Clone, Default)]
pub struct Section {
    pub title: String,
    pub markdown: String,
    pub figures: Vec<Figure>,
    /// Data files behind the tables and plots: (file name, JSON text).
    pub data: Vec<(String, String)>,
}

/// "12.34 ± 0.56" (mean ± SE, two decimals), with " (n)" when `n` is given; one value, or an
/// SE that is not finite (one seed's "unknown"), prints as "12.34 (n = 1)": the report's
/// tables said "± inf" in one place and "± 0.00 (1)" in another (issue 48).
pub fn pm(mean: f64, se: f64, n: Option<usize>) -> String {
    let m = fixed(mean, 2);
    if n == Some(1) || !se.is_finite() {
        return format!("{m} (n = 1)");
    }
    match n {
        Some(n) => format!("{m} ± {se:.2} ({n})"),
        None => format!("{m} ± {se:.2}"),
    }
}

/// `v` with `decimals` decimals, a value that rounds to zero printed without its sign
/// ("0.00", not "-0.00").
pub fn fixed(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => s,
    }
}

/// Writes `text` to `dir/name` atomically; errors name the file.
pub fn write(dir: &Path, name: &str, text: &str) -> Result<()> {
    let path = dir.join(name);
    clumpgen::io::write_atomic(&path, text.as_bytes()).map_err(Error::io(&path))
}

/// Pretty JSON of report data.
pub fn json<T: serde::Serialize>(v: &T) -> String {
    serde_json::to_string_pretty(v).expect("report data serialises") + "\n"
}

impl Section {
    /// The section's Markdown with its figures linked and its data files listed.
    pub fn to_markdown(&self) -> String {
        let mut s = format!("## {}\n\n{}\n", self.title, self.markdown.trim_end());
        for f in &self.figures {
            s += &format!("\n![{}]({})\n\n*{}*\n", f.caption, f.file, f.caption);
        }
        if !self.data.is_empty() {
            let names: Vec<String> = self
                .data
                .iter()
                .map(|(n, _)| format!("[`{n}`]({n})"))
                .collect();
            s += &format!("\nData: {}\n", names.join(", "));
        }
        s + "\n"
    }

    /// The section as HTML, figures inlined.
    pub fn to_html(&self) -> String {
        let md = format!("## {}\n\n{}\n", self.title, self.markdown);
        let mut s = markdown_to_html(&md);
        for f in &self.figures {
            s += &format!(
                "<figure>{}<figcaption>{}</figcaption></figure>\n",
                f.svg,
                html_escape(&f.caption)
            );
        }
        if !self.data.is_empty() {
            let names: Vec<String> = self
                .data
                .iter()
                .map(|(n, _)| format!("<a href=\"{0}\"><code>{0}</code></a>", html_escape(n)))
                .collect();
            s += &format!("<p>Data: {}</p>\n", names.join(", "));
        }
        s
    }
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// CommonMark with tables to HTML.
pub fn markdown_to_html(md: &str) -> String {
    let mut opts = pulldown_cmark::Options::empty();
    opts.insert(pulldown_cmark::Options::ENABLE_TABLES);
    let parser = pulldown_cmark::Parser::new_ext(md, opts);
    let mut out = String::new();
    pulldown_cmark::html::push_html(&mut out, parser);
    out
}

/// Writes every section's figures and data, `index.md` and `index.html`; returns the Markdown.
pub fn write_report(dir: &Path, title: &str, sections: &[Section]) -> Result<String> {
    std::fs::create_dir_all(dir).map_err(Error::io(dir))?;
    let mut md = format!("# {title}\n\n");
    let mut body = format!("<h1>{}</h1>\n", html_escape(title));
    for s in sections {
        for f in &s.figures {
            write(dir, &f.file, &f.svg)?;
        }
        for (n, t) in &s.data {
            write(dir, n, t)?;
        }
        md += &s.to_markdown();
        body += &s.to_html();
    }
    let html = format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{}</title>\n<style>\
         body{{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em}}\
         table{{border-collapse:collapse;font-size:90%}}td,th{{border:1px solid #bbb;padding:2px 6px}}\
         figure{{margin:1em 0}}figcaption{{font-style:italic}}</style></head><body>\n{}</body></html>\n",
        html_escape(title),
        body
    );
    write(dir, "index.md", &md)?;
    write(dir, "index.html", &html)?;
    Ok(md)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 48: one seed prints the same way in every table, not "± inf" or "± 0.00 (1)".
    #[test]
    fn one_value_prints_as_n_1_everywhere() {
        assert_eq!(pm(14.4, 0.24, Some(5)), "14.40 ± 0.24 (5)");
        assert_eq!(pm(20.9, 2.5, None), "20.90 ± 2.50");
        assert_eq!(pm(14.4, 0.0, Some(1)), "14.40 (n = 1)");
        assert_eq!(pm(20.9, f64::INFINITY, None), "20.90 (n = 1)");
        // A mean that rounds to zero has no sign (the quick report's "-0.00 ± inf").
        assert_eq!(pm(-0.001, f64::INFINITY, None), "0.00 (n = 1)");
    }

    #[test]
    fn zero_prints_without_a_sign() {
        assert_eq!(fixed(-0.004, 2), "0.00");
        assert_eq!(fixed(-0.0, 1), "0.0");
        assert_eq!(fixed(-0.006, 2), "-0.01");
        assert_eq!(fixed(-12.5, 0), "-12");
        assert_eq!(fixed(1.23456, 3), "1.235");
    }

    #[test]
    fn writes_markdown_and_self_contained_html() {
        let dir = std::env::temp_dir().join(format!("page-test-{}", std::process::id()));
        let s = Section {
            title: "T".into(),
            markdown: "| a | b |\n|---|---|\n| 1 | 2 |\n".into(),
            figures: vec![Figure {
                file: "f.svg".into(),
                caption: "cap <1>".into(),
                svg: "<svg></svg>".into(),
            }],
            data: vec![("d.json".into(), "{}".into())],
        };
        let md = write_report(&dir, "R", &[s]).unwrap();
        assert!(md.contains("![cap <1>](f.svg)") && md.contains("[`d.json`](d.json)"));
        let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
        assert!(
            html.contains("<table>")
                && html.contains("<svg></svg>")
                && html.contains("cap &lt;1&gt;")
        );
        assert!(dir.join("f.svg").exists() && dir.join("d.json").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
