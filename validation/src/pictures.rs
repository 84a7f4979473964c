//! The report's pictures: the three specimen types and one cut of each at three moments, as
//! S0's figures 3–5 show them (issue 24). They are drawn by `dem render` from one Table 2 cut per
//! method (`scripts/cut-pictures.sh`: seed 1, a_p = 1 mm, v = 2 m/s, L = 10 mm) and committed as
//! `docs/pictures/cut-<method>-<k>.png` (k = 0 the specimen, 1 and 2 a third and two thirds of
//! the travel, 3 the end); this section lays them out as one SVG figure with the PNGs inlined
//! (base64 `data:` URIs), so `index.md` and the self-contained `index.html` both show them.
//!
//! The pictures are read, not made, here: a cut of each method costs ~12 min of CPU (the
//! improved one 514 s), too long for the quick report. A missing or unreadable picture is named
//! in the section, which then says how to make it; the report does not fail for it.

use crate::error::{Error, Result};
use crate::page::{Figure, Section};
use base64::Engine as _;
use std::path::Path;

/// The specimen types, as the picture files name them, with their row labels.
const METHODS: [(&str, &str); 3] = [
    ("traditional", "traditional"),
    ("orc", "ORC"),
    ("improved", "improved ORC"),
];

/// Column labels: k = 0 … 3.
const MOMENTS: [&str; 4] = [
    "specimen",
    "1/3 of the cut",
    "2/3 of the cut",
    "end (broken bonds red)",
];

/// Width of one picture in the figure (px).
const CELL_W: f64 = 262.0;
/// Room for the row labels on the left and the column labels on top (px).
const LEFT: f64 = 24.0;
const TOP: f64 = 22.0;
const GAP: f64 = 6.0;

/// Width and height of a PNG from its IHDR chunk; an error names the file.
pub fn png_size(bytes: &[u8], file: &str) -> Result<(u32, u32)> {
    const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    if bytes.len() < 24 || bytes[..8] != SIGNATURE || &bytes[12..16] != b"IHDR" {
        return Err(Error::NotPng {
            file: file.to_string(),
        });
    }
    let be = |k: usize| u32::from_be_bytes(bytes[k..k + 4].try_into().expect("4 bytes"));
    let (w, h) = (be(16), be(20));
    if w == 0 || h == 0 {
        return Err(Error::PngSize {
            file: file.to_string(),
            width: w,
            height: h,
        });
    }
    Ok((w, h))
}

/// One picture: its PNG bytes and size (px), or `None` where it could not be read.
type Cell = Option<(Vec<u8>, (u32, u32))>;

/// The pictures section from the PNGs in `dir`.
pub fn section(dir: &Path) -> Section {
    let mut cells = Vec::new();
    let mut problems = Vec::new();
    for (m, _) in METHODS {
        for k in 0..MOMENTS.len() {
            let path = dir.join(format!("cut-{m}-{k}.png"));
            let file = path.display().to_string();
            match std::fs::read(&path)
                .map_err(Error::io(&path))
                .and_then(|b| png_size(&b, &file).map(|s| (b, s)))
            {
                Ok(c) => cells.push(Some(c)),
                Err(e) => {
                    problems.push(e.to_string());
                    cells.push(None);
                }
            }
        }
    }
    let mut markdown = String::from(
        "The three specimen types (S0's figure 3) and one cut of each at a third, two thirds \
         and the end of its travel (S0's figures 4–5): Si3N4 specimens 20 × 10 mm of the Table \
         2 plan (seed 1; the ORC and improved-ORC specimens with S0's few irregular grains), cut \
         1 mm deep at 2 m/s over 10 mm. Discs coloured by grain: in the traditional specimen \
         every disc is a grain; in the ORC (rigid clusters) and improved-ORC (bonded clumps) \
         specimens the irregular grains are coloured and the single-disc grains grey. Intact \
         bonds black; broken bonds red in the last column (a snapshot does not keep where a \
         bond broke, the final checkpoint does); the tool and the slot walls as lines, the \
         tool filled in the last column. Drawn by `dem render` from the runs' VTK snapshots and final \
         checkpoints (`scripts/cut-pictures.sh RUNS_DIR`, which reruns the three cuts in ~12 \
         min of CPU and redraws the pictures in `docs/pictures/`).\n",
    );
    if !problems.is_empty() {
        markdown += &format!(
            "\n**{} of {} pictures could not be read** (make them with \
             `scripts/cut-pictures.sh RUNS_DIR {}`):\n\n",
            problems.len(),
            cells.len(),
            dir.display()
        );
        for p in &problems {
            markdown += &format!("- {p}\n");
        }
    }
    let figures = if problems.len() == cells.len() {
        vec![]
    } else {
        vec![Figure {
            file: "cut_pictures.svg".into(),
            caption: "One cut of each specimen type at three moments (rows: traditional, ORC, \
                      improved ORC; columns: the specimen, 1/3 and 2/3 of the travel, the end)"
                .into(),
            svg: grid(&cells),
        }]
    };
    Section {
        title: "Specimens and cuts, pictures".into(),
        markdown,
        figures,
        data: vec![],
    }
}

/// The SVG grid: one row per method, one column per moment; a missing picture is a grey box.
fn grid(cells: &[Cell]) -> String {
    let cols = MOMENTS.len();
    let height = |c: &Cell| match c {
        Some((_, (w, h))) => CELL_W * f64::from(*h) / f64::from(*w),
        None => CELL_W * 0.6,
    };
    let rows: Vec<f64> = cells
        .chunks(cols)
        .map(|r| r.iter().map(height).fold(0.0, f64::max))
        .collect();
    let width = LEFT + cols as f64 * (CELL_W + GAP);
    let total = TOP + rows.iter().map(|h| h + GAP).sum::<f64>();
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{total:.0}\" \
         viewBox=\"0 0 {width:.0} {total:.0}\" font-family=\"sans-serif\" font-size=\"13\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    for (k, label) in MOMENTS.iter().enumerate() {
        let x = LEFT + k as f64 * (CELL_W + GAP) + CELL_W / 2.0;
        s += &format!("<text x=\"{x:.1}\" y=\"15\" text-anchor=\"middle\">{label}</text>\n");
    }
    let mut y = TOP;
    for (r, (row, h)) in cells.chunks(cols).zip(&rows).enumerate() {
        let cy = y + h / 2.0;
        s += &format!(
            "<text transform=\"translate(16 {cy:.1}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n",
            METHODS[r].1
        );
        for (k, c) in row.iter().enumerate() {
            let x = LEFT + k as f64 * (CELL_W + GAP);
            match c {
                Some((bytes, _)) => {
                    let b64 = base64::engine::general_purpose::STANDARD.encode(bytes);
                    s += &format!(
                        "<image x=\"{x:.1}\" y=\"{y:.1}\" width=\"{CELL_W:.0}\" height=\"{:.1}\" \
                         href=\"data:image/png;base64,{b64}\"/>\n",
                        height(c)
                    );
                }
                None => {
                    s += &format!(
                        "<rect x=\"{x:.1}\" y=\"{y:.1}\" width=\"{CELL_W:.0}\" height=\"{:.1}\" \
                         fill=\"#eee\"/><text x=\"{:.1}\" y=\"{cy:.1}\" \
                         text-anchor=\"middle\">missing</text>\n",
                        height(c),
                        x + CELL_W / 2.0
                    );
                }
            }
        }
        y += h + GAP;
    }
    s + "</svg>\n"
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The start of a PNG of `w` x `h` px: its signature and IHDR chunk (all that is read here).
    fn tiny_png(w: u32, h: u32) -> Vec<u8> {
        let mut b = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
        b.extend_from_slice(&13u32.to_be_bytes());
        b.extend_from_slice(b"IHDR");
        b.extend_from_slice(&w.to_be_bytes());
        b.extend_from_slice(&h.to_be_bytes());
        b.extend_from_slice(&[8, 0, 0, 0, 0, 0, 0, 0, 0]);
        b
    }

    #[test]
    fn png_size_reads_the_header_and_refuses_other_files() {
        assert_eq!(png_size(&tiny_png(600, 364), "a.png").unwrap(), (600, 364));
        let e = png_size(b"GIF89a......................", "b.png")
            .unwrap_err()
            .to_string();
        assert!(e.contains("b.png") && e.contains("not a PNG"), "{e}");
        let e = png_size(&tiny_png(0, 5), "c.png").unwrap_err().to_string();
        assert!(e.contains("c.png: PNG of 0 x 5"), "{e}");
    }

    /// The committed pictures all load; with some missing the section names each and still
    /// shows the others; with none there is no figure.
    #[test]
    fn section_inlines_the_pictures_and_names_missing_ones() {
        let pictures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/pictures");
        let s = section(&pictures);
        assert!(!s.markdown.contains("could not be read"), "{}", s.markdown);
        let svg = &s.figures[0].svg;
        assert_eq!(svg.matches("data:image/png;base64,").count(), 12);
        let dir = std::env::temp_dir().join(format!("dem-pictures-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("cut-orc-2.png"), tiny_png(600, 364)).unwrap();
        std::fs::write(dir.join("cut-orc-3.png"), b"not a picture").unwrap();
        let s = section(&dir);
        assert!(s.markdown.contains("11 of 12 pictures could not be read"));
        assert!(
            s.markdown.contains("cut-orc-3.png: not a PNG"),
            "{}",
            s.markdown
        );
        assert!(s.markdown.contains("cut-improved-0.png"), "{}", s.markdown);
        let svg = &s.figures[0].svg;
        assert_eq!(svg.matches("data:image/png").count(), 1);
        assert_eq!(svg.matches(">missing</text>").count(), 11);
        std::fs::remove_dir_all(&dir).unwrap();
        let s = section(&dir);
        assert!(s.figures.is_empty() && s.markdown.contains("12 of 12"));
    }
}
