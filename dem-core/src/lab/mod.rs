//! Virtual lab tests (uniaxial compression, Brazilian, three-point bending, cutting): scene
//! builders and the analyses that turn their histories into material properties.

pub mod analysis;
