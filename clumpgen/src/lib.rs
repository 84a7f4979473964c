//! Grain outlines to disc clumps with exact mass, centroid and inertia.

pub mod descriptors;
pub mod error;
pub mod outline;
pub mod props;
pub mod synth;
pub mod units;

pub use descriptors::{convex_hull, shape_descriptors, ShapeDescriptors};
pub use error::OutlineError;
pub use outline::{
    find_self_intersection, parse_outline, read_outline, resample, Outline, ReadOptions, SelfHit,
};
pub use props::{polygon_props, PolygonProps};
pub use synth::{scale_to_area, synth_grain, SynthParams};
pub use units::Units;
