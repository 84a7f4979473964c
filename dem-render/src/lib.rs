//! dem-render: pictures and animations of the workspace's files, as `dem render` draws them.
//! A checkpoint (`dem.checkpoint/1`, JSON or binary), a `last-good-state.json`, a specimen file
//! (`dem.specimen/1`), a clump template (`clumpgen.template/1` or `/2`) or a VTK disc snapshot
//! (`snap-*.vtp`, with the `walls-*.vtp` beside it) becomes one PNG; a `snapshots.pvd` series
//! becomes an animated GIF (or an MP4 through ffmpeg). dem-cli parses the flags into a [`Job`]
//! and prints what [`run`] returns; nothing here knows of the command line beyond the flag names
//! in messages.
//!
//! ```text
//! error    RenderError: every message names the file (or --out FILE, a field, an array) and why
//! picture  Picture: discs, bonds, walls, an outline, caption lines, in metres; caption helpers
//! vtk      snap-*.vtp, walls-*.vtp, snapshots.pvd read back (ASCII, inline or appended base64)
//! load     any input file → Picture, the kind told by its `schema` field (or its .vtp name)
//! draw     Picture + Options → pixels (tiny-skia) → PNG (256 palette colours, or RGB)
//! anim     Pictures of a series → frames of one view and speed scale → GIF or MP4
//! job      input → load → draw → write, the output path chosen and checked (never an input)
//! ```
//!
//! Each module uses only those listed before it.
//!
//! **Geometry.** The content (its bounding box, or [`Options::view`]) fills the width less a
//! margin at one scale `s` (px/m) in x and y, at most twice as tall as wide; model point
//! (x, y) m lands at column `c0 + s·x`, row `r0 − s·y` ([`Frame`]). Below it a footer holds a
//! scale bar (1, 2 or 5 × 10^k m), the legend and the caption (an 8×8 bitmap font).
//!
//! **Colours.** Categories (grains, materials, bond groups) take [`PALETTE`], Tableau 10 without
//! its grey (walls are grey, the tool darker); touching grains get different entries
//! ([`grain_colours`]). Speed |v| maps linearly from 0 to the top of the scale onto
//! [`viridis`] in 64 steps. Broken bonds are red crack marks.
//!
//! ```
//! use dem_render::{ColorBy, Disc, Kind, Options, Picture};
//!
//! let disc = |x: f64, grain| Disc { x, y: 0.0, r: 1e-3, speed: 0.0, material: 0, grain };
//! let p = Picture {
//!     kind: Kind::Specimen,
//!     discs: vec![disc(0.0, 0), disc(2e-3, 1)],
//!     bonds: Vec::new(),
//!     bond_groups: Vec::new(),
//!     materials: Vec::new(),
//!     walls: Vec::new(),
//!     outline: None,
//!     centroid: None,
//!     clump_centroid: None,
//!     caption: vec!["two discs".into()],
//!     notes: Vec::new(),
//! };
//! let o = Options {
//!     width: 200,
//!     color: ColorBy::Grain,
//!     bonds: false,
//!     broken: false,
//!     view: None,
//!     speed_max: None,
//!     rgb: false,
//! };
//! let r = dem_render::render(&p, &o)?;
//! assert_eq!(r.width, 200);
//! assert!(r.png.starts_with(b"\x89PNG"));
//! # Ok::<(), dem_render::RenderError>(())
//! ```

mod anim;
mod draw;
mod error;
mod job;
mod load;
mod picture;
mod vtk;

pub use anim::{animate, ffmpeg, union_view, Format};
pub use draw::{
    content_box, draw, encode_png, grain_colour, grain_colours, render, viridis, ColorBy, Frame,
    Options, Rendered, BACKGROUND, MAX_WIDTH, PALETTE, PLAIN,
};
pub use error::RenderError;
pub use job::{default_out, run, Job, Written};
pub use load::{load, KINDS};
pub use picture::{Bond, Disc, Kind, Picture, WallLine};
pub use vtk::{load_vtp, read_pvd};
