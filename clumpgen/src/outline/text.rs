//! Parsers for the two outline file formats, producing raw points in input units.
//!
//! * Text (CSV, whitespace or tab separated): one `x y` pair per line, fields separated by
//!   commas, semicolons, spaces or tabs; `#` starts a comment (whole line or trailing); an
//!   optional header line (fields that are not numbers, e.g. `x,y`) before the first point;
//!   a comment `units: <name>` declares the units and `metres_per_px: <value>` the pixel size
//!   (the first declaration of each counts).
//! * JSON: `{"units": "mm", "metres_per_px": 1e-4, "points": [[x, y], ...]}`; `units` and
//!   `metres_per_px` are optional, other keys are ignored.

use serde::Deserialize;

use crate::error::{OutlineError, Pos};

/// Points as read, in input units and file order, with where each came from.
#[derive(Debug, Default)]
pub(crate) struct RawOutline {
    pub points: Vec<[f64; 2]>,
    pub pos: Vec<Pos>,
    /// Declared units name and where it was declared.
    pub units: Option<(String, Pos)>,
    /// Declared pixel size (metres per pixel) and where.
    pub metres_per_px: Option<(f64, Pos)>,
}

/// If `comment` contains `key` followed by optional blanks and `:` or `=`, the rest after that.
fn value_after_key<'a>(comment: &'a str, keys: &[&str]) -> Option<&'a str> {
    // ASCII lowercasing keeps byte offsets, so indices into `hay` are valid in `comment`.
    let hay = comment.to_ascii_lowercase();
    for key in keys {
        let mut from = 0;
        while let Some(k) = hay[from..].find(key) {
            let start = from + k;
            let before_ok = start == 0
                || !hay[..start]
                    .chars()
                    .next_back()
                    .is_some_and(|c| c.is_alphanumeric() || c == '_');
            let rest = &comment[start + key.len()..];
            let trimmed = rest.trim_start();
            if before_ok && (trimmed.starts_with(':') || trimmed.starts_with('=')) {
                return Some(trimmed[1..].trim_start());
            }
            from = start + key.len();
        }
    }
    None
}

fn scan_comment(raw: &mut RawOutline, comment: &str, pos: Pos) -> Result<(), OutlineError> {
    if raw.units.is_none() {
        if let Some(v) = value_after_key(comment, &["units", "unit"]) {
            let tok: String = v.chars().take_while(|c| c.is_alphabetic()).collect();
            raw.units = Some((tok, pos));
        }
    }
    if raw.metres_per_px.is_none() {
        if let Some(v) = value_after_key(comment, &["metres_per_px", "meters_per_px", "m_per_px"]) {
            let tok: String = v
                .chars()
                .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-'))
                .collect();
            let val: f64 = tok.parse().map_err(|_| OutlineError::BadScale {
                file: String::new(),
                pos: Some(pos),
                value: f64::NAN,
            })?;
            raw.metres_per_px = Some((val, pos));
        }
    }
    Ok(())
}

/// At most this many characters of an input line are echoed in an error.
const ECHO_CHARS: usize = 120;

/// `s`, or its first [`ECHO_CHARS`] characters and its length when longer (issue 48 D13: a line
/// of 800,000 fields was echoed whole, 1.6 MB on stderr).
fn excerpt(s: &str) -> String {
    let n = s.chars().count();
    if n <= ECHO_CHARS {
        return s.to_string();
    }
    let head: String = s.chars().take(ECHO_CHARS).collect();
    format!("{head}… ({n} characters in all)")
}

/// Parse a text (CSV / whitespace / tab) outline. Errors carry an empty file name.
pub(crate) fn parse_text(text: &str) -> Result<RawOutline, OutlineError> {
    let mut raw = RawOutline::default();
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut header_seen = false;
    for (i, line) in text.lines().enumerate() {
        let lineno = i + 1;
        let (data, comment) = match line.find('#') {
            Some(k) => (&line[..k], Some(&line[k + 1..])),
            None => (line, None),
        };
        if let Some(c) = comment {
            scan_comment(&mut raw, c, Pos::Line(lineno))?;
        }
        let data = data.trim();
        if data.is_empty() {
            continue;
        }
        let fields: Vec<&str> = data
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let parsed: Vec<Result<f64, _>> = fields.iter().map(|f| f.parse::<f64>()).collect();
        let none_numeric = parsed.iter().all(|r| r.is_err());
        if none_numeric && !header_seen && raw.points.is_empty() {
            header_seen = true;
            continue;
        }
        let bad = |reason: String| OutlineError::Unparsable {
            file: String::new(),
            line: lineno,
            text: excerpt(line),
            reason,
        };
        if fields.len() != 2 {
            return Err(bad(format!(
                "expected 2 numbers (x y), found {} fields",
                fields.len()
            )));
        }
        let mut xy = [0.0; 2];
        for k in 0..2 {
            match &parsed[k] {
                Ok(v) => xy[k] = *v,
                Err(_) => return Err(bad(format!("{:?} is not a number", excerpt(fields[k])))),
            }
        }
        if !(xy[0].is_finite() && xy[1].is_finite()) {
            return Err(OutlineError::NonFinite {
                file: String::new(),
                pos: Pos::Line(lineno),
                text: excerpt(line),
            });
        }
        raw.points.push(xy);
        raw.pos.push(Pos::Line(lineno));
    }
    Ok(raw)
}

#[derive(Deserialize)]
struct JsonOutline {
    #[serde(default)]
    units: Option<String>,
    #[serde(default)]
    metres_per_px: Option<f64>,
    points: Vec<[f64; 2]>,
}

/// Parse a JSON outline. Errors carry an empty file name.
pub(crate) fn parse_json(text: &str) -> Result<RawOutline, OutlineError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let j: JsonOutline = serde_json::from_str(text).map_err(|e| OutlineError::Json {
        file: String::new(),
        line: e.line(),
        column: e.column(),
        reason: e.to_string(),
    })?;
    // serde_json rejects NaN/Infinity literals and out-of-range numbers, but check anyway.
    for (k, p) in j.points.iter().enumerate() {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return Err(OutlineError::NonFinite {
                file: String::new(),
                pos: Pos::Point(k),
                text: format!("[{}, {}]", p[0], p[1]),
            });
        }
    }
    let n = j.points.len();
    Ok(RawOutline {
        points: j.points,
        pos: (0..n).map(Pos::Point).collect(),
        units: j.units.map(|u| (u, Pos::Line(1))),
        metres_per_px: j.metres_per_px.map(|v| (v, Pos::Line(1))),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comment_keys() {
        assert_eq!(
            value_after_key(" gravel, UTM in metres; grain 0; units: m", &["units"]),
            Some("m")
        );
        assert_eq!(value_after_key("units=mm", &["units"]), Some("mm"));
        assert_eq!(value_after_key("these units are mm", &["units"]), None);
        assert_eq!(value_after_key("subunits: mm", &["units"]), None);
    }

    #[test]
    fn text_formats() {
        let r = parse_text("x,y\n0,0\n1, 0 # trailing\n\n1\t1\n0 1\n0;0.5\n").unwrap();
        assert_eq!(r.points.len(), 5);
        assert_eq!(r.pos[2], Pos::Line(5));
        assert_eq!(r.points[4], [0.0, 0.5]);
        let r = parse_text("# units: um\n# metres_per_px = 2.5e-5\n0 0\n").unwrap();
        assert_eq!(r.units.as_ref().unwrap().0, "um");
        assert_eq!(r.metres_per_px.unwrap().0, 2.5e-5);
    }

    #[test]
    fn crlf_and_byte_order_mark() {
        let r = parse_text("\u{feff}x,y\r\n0,0\r\n1,0\r\n1,1\r\n").unwrap();
        assert_eq!(r.points, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]);
    }

    /// Issue 48 D13: a line of 800,000 fields is refused with its field count and an excerpt,
    /// not echoed whole; so is one huge bad field.
    #[test]
    fn a_huge_line_is_echoed_in_part() {
        let line = vec!["1"; 800_000].join(",");
        let e = parse_text(&format!("0,0\n{line}\n"))
            .unwrap_err()
            .to_string();
        assert!(e.len() < 600, "{} bytes", e.len());
        assert!(
            e.contains("found 800000 fields") && e.contains("1599999 characters in all"),
            "{e}"
        );
        let e = parse_text(&format!("0,0\n1,{}\n", "x".repeat(1_000_000)))
            .unwrap_err()
            .to_string();
        assert!(
            e.len() < 800 && e.contains("1000000 characters in all"),
            "{e}"
        );
        // Short lines are echoed as they are.
        let e = parse_text("0,0\n1,2,3\n").unwrap_err().to_string();
        assert!(
            e.contains("1,2,3") && !e.contains("characters in all"),
            "{e}"
        );
    }

    #[test]
    fn second_header_is_an_error() {
        let e = parse_text("x,y\nX,Y\n0,0\n").unwrap_err();
        assert!(matches!(e, OutlineError::Unparsable { line: 2, .. }), "{e}");
        let e = parse_text("0,0\nx,y\n").unwrap_err();
        assert!(matches!(e, OutlineError::Unparsable { line: 2, .. }), "{e}");
    }
}
