//! Length units of outline files. Everything inside the crate is SI (metres); files may be in
//! m, mm, µm or image pixels of a known size. Conversion happens once, at the edge, in
//! [`crate::outline`].

use serde::{Deserialize, Serialize};

use crate::error::OutlineError;

/// Length unit of the coordinates in an outline file.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Units {
    /// Metres.
    M,
    /// Millimetres (the default when a file declares nothing).
    Mm,
    /// Micrometres.
    Um,
    /// Image pixels of side `metres_per_px` metres.
    Px { metres_per_px: f64 },
}

impl Units {
    /// Length of one unit in metres.
    pub fn metres_per_unit(&self) -> f64 {
        match self {
            Units::M => 1.0,
            Units::Mm => 1e-3,
            Units::Um => 1e-6,
            Units::Px { metres_per_px } => *metres_per_px,
        }
    }

    /// Parse a units name: `m`, `mm`, `um`, `µm` (micro sign U+00B5 or Greek mu U+03BC),
    /// `micron`/`microns`, `px`; also the long forms `metre(s)`, `meter(s)`, `millimetre(s)`,
    /// `millimeter(s)`, `micrometre(s)`, `micrometer(s)`, `pixel(s)`. Case-insensitive.
    ///
    /// `px` needs `px_scale` (metres per pixel), otherwise [`OutlineError::PxWithoutScale`].
    /// Errors carry an empty file name; the outline reader fills it in with
    /// [`OutlineError::with_file`].
    pub fn parse(s: &str, px_scale: Option<f64>) -> Result<Units, OutlineError> {
        let t = s.trim().to_lowercase();
        let u = match t.as_str() {
            "m" | "metre" | "metres" | "meter" | "meters" => Units::M,
            "mm" | "millimetre" | "millimetres" | "millimeter" | "millimeters" => Units::Mm,
            "um" | "µm" | "μm" | "micron" | "microns" | "micrometre" | "micrometres"
            | "micrometer" | "micrometers" => Units::Um,
            "px" | "pixel" | "pixels" => match px_scale {
                None => {
                    return Err(OutlineError::PxWithoutScale {
                        file: String::new(),
                        pos: None,
                    })
                }
                Some(v) if !(v.is_finite() && v > 0.0) => {
                    return Err(OutlineError::BadScale {
                        file: String::new(),
                        pos: None,
                        value: v,
                    })
                }
                Some(v) => Units::Px { metres_per_px: v },
            },
            _ => {
                return Err(OutlineError::UnknownUnits {
                    file: String::new(),
                    pos: None,
                    text: s.trim().to_string(),
                })
            }
        };
        Ok(u)
    }

    /// Short name: `"m"`, `"mm"`, `"um"`, or `"px"` (the pixel size is not part of the name).
    pub fn name(&self) -> String {
        match self {
            Units::M => "m",
            Units::Mm => "mm",
            Units::Um => "um",
            Units::Px { .. } => "px",
        }
        .to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_all_names() {
        for (s, u) in [
            ("m", Units::M),
            ("M", Units::M),
            ("metres", Units::M),
            ("mm", Units::Mm),
            (" mm ", Units::Mm),
            ("um", Units::Um),
            ("µm", Units::Um),
            ("μm", Units::Um),
            ("micron", Units::Um),
        ] {
            assert_eq!(Units::parse(s, None).unwrap(), u, "{s}");
        }
        assert_eq!(
            Units::parse("px", Some(2.5e-5)).unwrap(),
            Units::Px {
                metres_per_px: 2.5e-5
            }
        );
    }

    #[test]
    fn scale_factors() {
        assert_eq!(Units::M.metres_per_unit(), 1.0);
        assert_eq!(Units::Mm.metres_per_unit(), 1e-3);
        assert_eq!(Units::Um.metres_per_unit(), 1e-6);
        assert_eq!(Units::Px { metres_per_px: 0.5 }.metres_per_unit(), 0.5);
        assert_eq!(Units::Px { metres_per_px: 0.5 }.name(), "px");
        assert_eq!(Units::Um.name(), "um");
    }

    #[test]
    fn errors() {
        assert!(matches!(
            Units::parse("px", None),
            Err(OutlineError::PxWithoutScale { .. })
        ));
        assert!(matches!(
            Units::parse("px", Some(-1.0)),
            Err(OutlineError::BadScale { .. })
        ));
        let e = Units::parse("furlong", None)
            .unwrap_err()
            .with_file("a.csv");
        assert!(matches!(e, OutlineError::UnknownUnits { .. }));
        let msg = e.to_string();
        assert!(msg.contains("a.csv") && msg.contains("furlong"), "{msg}");
    }
}
