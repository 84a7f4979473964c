//! The report's section on issue 47: which dampings pass the invariance contracts, the speed
//! exponent n of F ∝ vⁿ and the depth trend against Huang & Detournay's length (K_IC/σ_c)².
//!
//! The contracts are `dem-core/tests/invariance.rs` (run by `cargo test`); their figures are
//! stated in docs/cutting.md. The two studies are long runs (hours of CPU: seeds 1–5 at five
//! speeds and two dampings, five depths), made by `scripts/damping-frame-runs.sh` and
//! `scripts/depth-runs.sh` into `<report>/studies/{damping-frame,depth}/` and committed; their
//! tables and plots are written beside them by `scripts/damping_frame_study.py` and
//! `scripts/depth_study.py` (`summary.md`, `speed.png`, `depth.png`). This section reads those
//! files, as the pictures section reads its PNGs: it makes nothing, and a folder without them
//! (the quick report's) gets a note saying how to make them, not a failure.

use crate::page::{Figure, Section};
use crate::pictures::png_size;
use base64::Engine as _;
use std::path::Path;

/// The two studies: folder under `<report>/studies`, plot, what the plot shows, the command
/// that writes the summary and plot.
const STUDIES: [(&str, &str, &str, &str); 2] = [
    (
        "damping-frame",
        "speed.png",
        "Window-mean main force against cutting speed, PFC local damping (lab frame) and local \
         damping in the fragment frame, seeds 1–5",
        "python3 scripts/damping_frame_study.py docs/report/studies/damping-frame --plot \
         docs/report/studies/damping-frame/speed.png > docs/report/studies/damping-frame/summary.md",
    ),
    (
        "depth",
        "depth.png",
        "Window-mean main force against depth of cut, fragment frame, against F ∝ a_p and \
         F ∝ √a_p and the model's (K_IC/σ_c)²",
        "python3 scripts/depth_study.py docs/report/studies/depth --coarse-l5-d1 \
         docs/report/studies/damping-frame --plot docs/report/studies/depth/depth.png > \
         docs/report/studies/depth/summary.md",
    ),
];

/// Which damping passes which contract (dem-core/tests/invariance.rs; figures in
/// docs/cutting.md, "The contracts").
const CONTRACTS: &str = "\
| contract (`dem-core/tests/invariance.rs`) | fragment frame (the cutting default) | PFC local damping, lab frame |
|---|---|---|
| (a) Galilean: a scene and its copy with every body given +U agree | passes (round-off) | fails |
| (b) pushed bonded block: force = μN within 2 % at 0.25–4 m/s, both frames | passes | fails in the lab frame (10.0 → 15.1 kN) |
| (c) a free bonded fragment keeps its momentum | passes (round-off) | fails |
| (d) bonded pair: decay √((1−α)/(1+α)) per half period, at rest and moving | passes | at rest only |
";

/// The section from `<out>/studies`.
pub fn section(out: &Path) -> Section {
    let mut md = String::from(
        "Issue 47 (docs/cutting.md, \"Damping and the frame of reference\"): PFC local damping \
         F_d = −α|F| sgn(v) acts on each disc's velocity in the frame the scene is written in \
         and drags anything in steady motion; local damping in the frame of each disc's bonded \
         fragment leaves rigid motion alone. The cutting test's default is the fragment frame \
         since 2026-12-02 (decision log there). The other lab tests (UCS, bending, Brazilian, \
         SENB, column, crush) keep PFC's: their specimens do not translate.\n\n",
    );
    md += CONTRACTS;
    md += "\n";
    let mut figures = Vec::new();
    for (dir, png, caption, command) in STUDIES {
        let folder = out.join("studies").join(dir);
        match std::fs::read_to_string(folder.join("summary.md")) {
            Ok(text) => {
                md += &format!("Runs: `studies/{dir}/` (its README); tables by `{command}`.\n\n");
                md += &demote(&text);
                // `demote` drops the last newline: end the study's last paragraph here.
                md += "\n\n";
            }
            Err(_) => {
                md += &format!(
                    "The study `studies/{dir}/` is not in this report's folder (a long run, \
                     committed with the full report); its tables and plot: `{command}`.\n\n"
                );
                continue;
            }
        }
        let path = folder.join(png);
        let file = path.display().to_string();
        match std::fs::read(&path)
            .map_err(|e| e.to_string())
            .and_then(|b| {
                png_size(&b, &file)
                    .map(|s| (b, s))
                    .map_err(|e| e.to_string())
            }) {
            Ok((bytes, (w, h))) => figures.push(Figure {
                file: format!("{dir}_{}", png.replace(".png", ".svg")),
                caption: caption.to_string(),
                svg: wrap_png(&bytes, w, h),
            }),
            Err(e) => md += &format!("(plot not read: {e})\n\n"),
        }
    }
    Section {
        title: "Damping, frame of reference, speed and depth trends (issue 47)".into(),
        markdown: md,
        figures,
        data: vec![],
    }
}

/// Headings one level down (a study's `###` stays under this section's `##`), the first line
/// of a summary that is its own `#` title dropped.
fn demote(text: &str) -> String {
    text.lines()
        .filter(|l| !l.starts_with("# "))
        .map(|l| {
            if l.starts_with("##") && !l.starts_with("###") {
                format!("#{l}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// An SVG showing the PNG at its size (inlined as a `data:` URI).
fn wrap_png(bytes: &[u8], w: u32, h: u32) -> String {
    let b64 = base64::engine::general_purpose::STANDARD.encode(bytes);
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\"><image width=\"{w}\" height=\"{h}\" \
         href=\"data:image/png;base64,{b64}\"/></svg>\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Without the study folders the section says how to make them; with a summary and a
    /// plot it carries the tables (headings under the section's) and the plot inlined.
    #[test]
    fn reads_the_committed_summaries_and_plots() {
        let dir = std::env::temp_dir().join(format!("dem-damping-studies-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let s = section(&dir);
        assert!(s.figures.is_empty());
        assert_eq!(
            s.markdown.matches("is not in this report's folder").count(),
            2
        );
        assert!(s.markdown.contains("| (a) Galilean"));
        let f = dir.join("studies/depth");
        std::fs::create_dir_all(&f).unwrap();
        std::fs::write(
            f.join("summary.md"),
            "## Depth\n\n| a | b |\n|---|---|\n| 1 | 2 |\n",
        )
        .unwrap();
        // A 1 × 1 PNG header is all png_size reads.
        let mut png = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 13];
        png.extend(b"IHDR");
        png.extend(1u32.to_be_bytes());
        png.extend(1u32.to_be_bytes());
        std::fs::write(f.join("depth.png"), &png).unwrap();
        let s = section(&dir);
        assert!(s.markdown.contains("### Depth\n") && s.markdown.contains("| 1 | 2 |"));
        assert_eq!(s.figures.len(), 1);
        assert!(s.figures[0].svg.contains("data:image/png;base64,"));
        assert_eq!(
            s.markdown.matches("is not in this report's folder").count(),
            1
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
