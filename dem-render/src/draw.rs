//! Drawing a [`Picture`] into a PNG with tiny-skia: anti-aliased discs, bonds, walls, an
//! outline, a scale bar, a legend or colour bar and the caption (text in the 8×8 bitmap font of
//! `font8x8`, scaled up whole pixels).
//!
//! Layout: the content (its bounding box, or `--view`) fills the width less a margin, at one
//! scale in x and y, and is at most twice as tall as wide (a taller one is scaled down and
//! centred); below it a footer holds the scale bar, the legend and the caption lines.

use crate::error::RenderError;
use crate::picture::{sig, Disc, Kind, Picture};
use std::collections::{BTreeMap, HashMap};
use tiny_skia::{
    Color, FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, PixmapPaint, Rect, Stroke,
    Transform,
};

/// How discs are coloured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorBy {
    /// By grain (rigid clump, bonded clump or specimen grain): touching grains get different
    /// colours of [`PALETTE`]; one-disc grains are plain where others have several discs.
    Grain,
    /// By bond group: bonds in their group's colour over grey discs (darker: no intact bond).
    Group,
    /// By speed |v| on a colour scale, with a colour bar.
    Speed,
    /// By material: material k has `PALETTE[k % PALETTE.len()]`.
    Material,
}

/// Drawing options.
#[derive(Clone, Debug)]
pub struct Options {
    /// Image width (px).
    pub width: u32,
    /// Disc colouring.
    pub color: ColorBy,
    /// Draw intact bonds.
    pub bonds: bool,
    /// Draw broken bonds (red).
    pub broken: bool,
    /// Region drawn `[xmin, xmax, ymin, ymax]` (m); `None`: the content's bounding box.
    pub view: Option<[f64; 4]>,
    /// Top of the speed scale (m/s); `None`: the largest speed.
    pub speed_max: Option<f64>,
    /// Write 24-bit RGB instead of 256 palette colours.
    pub rgb: bool,
}

/// Where model coordinates land in the image: pixel column `c0 + s·x`, row `r0 − s·y` (x, y
/// in metres; pixel (i, j) covers columns i..i+1, rows j..j+1).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// Pixels per metre.
    pub s: f64,
    /// Column of x = 0.
    pub c0: f64,
    /// Row of y = 0.
    pub r0: f64,
}

/// A drawn image.
pub struct Rendered {
    /// The PNG file's bytes.
    pub png: Vec<u8>,
    /// Width and height (px).
    pub width: u32,
    /// Height (px).
    pub height: u32,
    /// The model-to-pixel map of the content area.
    pub frame: Frame,
    /// Time spent encoding the PNG (s), of the whole call.
    pub encode_s: f64,
}

/// Distinct colours for categories (grains, materials, bond groups): Tableau 10 without its
/// grey (walls are grey).
pub const PALETTE: [[u8; 3]; 9] = [
    [0x1f, 0x77, 0xb4],
    [0xff, 0x7f, 0x0e],
    [0x2c, 0xa0, 0x2c],
    [0xd6, 0x27, 0x28],
    [0x94, 0x67, 0xbd],
    [0x8c, 0x56, 0x4b],
    [0xe3, 0x77, 0xc2],
    [0xbc, 0xbd, 0x22],
    [0x17, 0xbe, 0xcf],
];

/// [`grain_colours`]' index of a one-disc grain among clumps.
pub const PLAIN: usize = usize::MAX - 1;

/// Colour of a [`grain_colours`] index: a palette entry, or light beige-grey for [`PLAIN`].
pub fn grain_colour(k: usize) -> [u8; 3] {
    PALETTE.get(k).copied().unwrap_or(PLAIN_DISC)
}

const PLAIN_DISC: [u8; 3] = [0xdc, 0xd6, 0xcc];

/// Background (white).
pub const BACKGROUND: [u8; 3] = [255, 255, 255];
const WALL: [u8; 3] = [0x70, 0x70, 0x70];
const TOOL: [u8; 3] = [0x38, 0x38, 0x38];
const INK: [u8; 3] = [0x20, 0x20, 0x20];
const BROKEN: [u8; 3] = [0xe4, 0x1a, 0x1c];
const BONDED_DISC: [u8; 3] = [0xd4, 0xd4, 0xd4];
const LOOSE_DISC: [u8; 3] = [0x9a, 0x9a, 0x9a];
const GRAIN_FILL: [u8; 3] = [0xf3, 0xe9, 0xd2];

/// Viridis at 0, ¼, ½, ¾, 1 (interpolated linearly between).
const VIRIDIS: [[u8; 3]; 5] = [
    [0x44, 0x01, 0x54],
    [0x3b, 0x52, 0x8b],
    [0x21, 0x91, 0x8c],
    [0x5e, 0xc9, 0x62],
    [0xfd, 0xe7, 0x25],
];

/// The speed scale's colour at `f` ∈ [0, 1].
pub fn viridis(f: f64) -> [u8; 3] {
    let f = if f.is_finite() {
        f.clamp(0.0, 1.0)
    } else {
        1.0
    };
    let t = f * 4.0;
    let k = (t.floor() as usize).min(3);
    let u = t - k as f64;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    [0, 1, 2].map(|c| (a[c] as f64 + u * (b[c] as f64 - a[c] as f64)).round() as u8)
}

/// Widest image `--width` accepts (px): with the height at most twice the width, the two
/// RGBA buffers stay under ~600 MB.
pub const MAX_WIDTH: u32 = 6000;

fn background() -> Color {
    Color::from_rgba8(BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 255)
}

fn paint(c: [u8; 3], alpha: u8) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color_rgba8(c[0], c[1], c[2], alpha);
    p.anti_alias = true;
    p
}

fn shade(c: [u8; 3], f: f64) -> [u8; 3] {
    c.map(|v| (v as f64 * f).round().clamp(0.0, 255.0) as u8)
}

/// Bounding box `[xmin, xmax, ymin, ymax]` of everything drawn (finite values only).
pub fn content_box(p: &Picture) -> Option<[f64; 4]> {
    let mut b = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    let mut add = |x: f64, y: f64, r: f64| {
        if x.is_finite() && y.is_finite() && r.is_finite() {
            b[0] = b[0].min(x - r);
            b[1] = b[1].max(x + r);
            b[2] = b[2].min(y - r);
            b[3] = b[3].max(y + r);
        }
    };
    for d in &p.discs {
        add(d.x, d.y, d.r);
    }
    for w in &p.walls {
        for q in &w.points {
            add(q[0], q[1], 0.0);
        }
    }
    for q in p.outline.iter().flatten() {
        add(q[0], q[1], 0.0);
    }
    (b[0] <= b[1] && b[2] <= b[3]).then_some(b)
}

/// A solid rectangle on whole pixels (no anti-aliasing: footer marks and text), at least one
/// pixel wide and high.
fn block(pm: &mut Pixmap, x: f32, y: f32, w: f32, h: f32, c: [u8; 3]) {
    let mut p = paint(c, 255);
    p.anti_alias = false;
    let (x, y) = (x.round(), y.round());
    if let Some(r) = Rect::from_xywh(x, y, w.round().max(1.0), h.round().max(1.0)) {
        pm.fill_rect(r, &p, Transform::identity(), None);
    }
}

/// A "nice" scale bar length (1, 2 or 5 × 10^k m) at most `max` metres.
fn nice_length(max: f64) -> f64 {
    let e = max.log10().floor();
    let base = 10f64.powf(e);
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * base)
        .find(|&l| l <= max)
        .unwrap_or(base)
}

/// Text in the 8×8 font, `k` pixels per font pixel, top-left at (x, y); returns the width.
fn text(pm: &mut Pixmap, x: f32, y: f32, s: &str, k: f32, c: [u8; 3]) -> f32 {
    let p = paint(c, 255);
    let mut pb = PathBuilder::new();
    let (x, y) = (x.round(), y.round());
    let mut cx = x;
    for ch in s.chars() {
        let code = ch as u32;
        let glyph = if code < 128 {
            font8x8::legacy::BASIC_LEGACY[code as usize]
        } else if (0xa0..0x100).contains(&code) {
            font8x8::legacy::LATIN_LEGACY[(code - 0xa0) as usize]
        } else {
            font8x8::legacy::BASIC_LEGACY[b'?' as usize]
        };
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..8 {
                if bits & (1 << col) != 0 {
                    if let Some(r) = Rect::from_xywh(cx + col as f32 * k, y + row as f32 * k, k, k)
                    {
                        pb.push_rect(r);
                    }
                }
            }
        }
        cx += 8.0 * k;
    }
    if let Some(path) = pb.finish() {
        let mut p = p;
        p.anti_alias = false;
        pm.fill_path(&path, &p, FillRule::Winding, Transform::identity(), None);
    }
    cx - x
}

/// Per-disc palette index for grain colouring: grains (discs sharing [`Disc::grain`]) that
/// touch get different colours where the palette allows (greedy, least-used colour first,
/// grains in key order, so the same input gives the same picture). Where some grains have
/// several discs, the one-disc grains get [`PLAIN`] instead (`PALETTE` has no such entry: see
/// [`grain_colour`]).
pub fn grain_colours(discs: &[Disc]) -> Vec<usize> {
    let mut index: BTreeMap<u64, usize> = BTreeMap::new();
    for d in discs {
        index.entry(d.grain).or_insert(0);
    }
    for (k, v) in index.values_mut().enumerate() {
        *v = k;
    }
    let g: Vec<usize> = discs.iter().map(|d| index[&d.grain]).collect();
    let n = index.len();
    let mut size = vec![0usize; n];
    for &k in &g {
        size[k] += 1;
    }
    // Where some grains have several discs, one-disc grains are drawn plain so the clumps
    // stand out.
    let plain = size.iter().any(|&m| m > 1);
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n];
    let rmax = discs
        .iter()
        .map(|d| d.r)
        .filter(|r| r.is_finite())
        .fold(0.0, f64::max);
    if rmax > 0.0 {
        let h = 2.2 * rmax;
        let cell = |d: &Disc| ((d.x / h).floor() as i64, (d.y / h).floor() as i64);
        let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for (i, d) in discs.iter().enumerate() {
            if d.x.is_finite() && d.y.is_finite() && d.r.is_finite() {
                grid.entry(cell(d)).or_default().push(i);
            }
        }
        for (&(cx, cy), members) in &grid {
            for dx in -1..=1 {
                for dy in -1..=1 {
                    let Some(other) = grid.get(&(cx + dx, cy + dy)) else {
                        continue;
                    };
                    for &i in members {
                        for &j in other {
                            if j <= i
                                || g[i] == g[j]
                                || (plain && (size[g[i]] == 1 || size[g[j]] == 1))
                            {
                                continue;
                            }
                            let (a, b) = (&discs[i], &discs[j]);
                            let reach = 1.1 * (a.r + b.r);
                            if (a.x - b.x).powi(2) + (a.y - b.y).powi(2) < reach * reach {
                                adj[g[i]].push(g[j]);
                                adj[g[j]].push(g[i]);
                            }
                        }
                    }
                }
            }
        }
    }
    let mut colour = vec![usize::MAX; n];
    let mut used = [0usize; PALETTE.len()];
    for k in 0..n {
        if plain && size[k] == 1 {
            colour[k] = PLAIN;
            continue;
        }
        let mut taken = [false; PALETTE.len()];
        for &m in &adj[k] {
            if colour[m] < PALETTE.len() {
                taken[colour[m]] = true;
            }
        }
        let pick = (0..PALETTE.len())
            .filter(|&c| !taken[c])
            .min_by_key(|&c| (used[c], c))
            .unwrap_or_else(|| {
                (0..PALETTE.len())
                    .min_by_key(|&c| (used[c], c))
                    .unwrap_or(0)
            });
        colour[k] = pick;
        used[pick] += 1;
    }
    g.iter().map(|&k| colour[k]).collect()
}

/// Draws `p` as a PNG.
pub fn render(p: &Picture, o: &Options) -> Result<Rendered, RenderError> {
    let (out, frame) = draw(p, o)?;
    let t = std::time::Instant::now();
    let png = encode_png(&out, o.rgb)?;
    let encode_s = t.elapsed().as_secs_f64();
    Ok(Rendered {
        png,
        width: out.width(),
        height: out.height(),
        frame,
        encode_s,
    })
}

/// Draws `p` into an opaque RGBA image (a frame of an animation, or a PNG's pixels): the
/// content area (the layers below, in this order) and the footer under it.
pub fn draw(p: &Picture, o: &Options) -> Result<(Pixmap, Frame), RenderError> {
    let l = Layout::new(p, o)?;
    let w = o.width;
    let ch = l.ch;
    let mut pm = Pixmap::new(w, ch as u32).ok_or(RenderError::Alloc {
        width: w,
        height: ch as u32,
    })?;
    pm.fill(background());

    // The grain under a template's discs.
    let outline_path = outline_path(p, &l);
    if let Some(path) = &outline_path {
        let id = Transform::identity();
        pm.fill_path(path, &paint(GRAIN_FILL, 255), FillRule::EvenOdd, id, None);
    }
    let speed_top = o.speed_max.unwrap_or_else(|| {
        p.discs
            .iter()
            .map(|d| d.speed)
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max)
    });
    if p.kind == Kind::Template {
        draw_template_discs(&mut pm, p, &l);
    } else {
        draw_discs(&mut pm, p, &l, &DiscColours::new(p, o, speed_top));
    }
    // Bonds: intact (dark, or by group), broken (red, over them).
    let draw_bonds = o.bonds || o.color == ColorBy::Group;
    if draw_bonds {
        draw_intact_bonds(&mut pm, p, o, &l);
    }
    if o.broken {
        draw_cracks(&mut pm, p, &l);
    }
    draw_walls(&mut pm, p, &l);
    draw_marks(&mut pm, p, &l, outline_path.as_ref());
    let out = footer(&pm, p, o, &l, speed_top)?;
    Ok((out, l.frame))
}

/// Where the content lands in the image: the region drawn, the model-to-pixel map, the font
/// and margin sizes, and the discs' median radius on screen (line widths follow from it).
struct Layout {
    /// Region drawn `[xmin, xmax, ymin, ymax]` (m).
    view: [f64; 4],
    /// The model-to-pixel map.
    frame: Frame,
    /// Font pixel size (image pixels per font pixel).
    k: f64,
    /// Margin round the content (px).
    pad: f64,
    /// The view's width (m, at least 1e-12).
    bw: f64,
    /// Height of the content area (px).
    ch: f64,
    /// Median disc radius on screen (px), 4 without discs.
    r_med: f64,
}

impl Layout {
    /// The content (its bounding box, or `o.view`) fills the width less a margin, at one scale
    /// in x and y, at most twice as tall as wide.
    fn new(p: &Picture, o: &Options) -> Result<Layout, RenderError> {
        let w = o.width;
        if w == 0 || w > MAX_WIDTH {
            return Err(RenderError::Width {
                width: w,
                max: MAX_WIDTH,
            });
        }
        let view = match o.view {
            Some(v) => v,
            None => content_box(p).ok_or(RenderError::Empty)?,
        };
        let wf = w as f64;
        // Font pixel size: 8 px text up to 700 px wide, 16 px up to 1400, …
        let k = (wf / 700.0).ceil().max(1.0);
        let pad = (wf / 50.0).round().max(6.0);
        let (bw, bh) = (
            (view[1] - view[0]).max(1e-12),
            (view[3] - view[2]).max(1e-12),
        );
        let mut s = (wf - 2.0 * pad).max(1.0) / bw;
        if bh * s > 2.0 * wf {
            s = 2.0 * wf / bh;
        }
        let ch = (bh * s + 2.0 * pad).ceil().max(1.0);
        let frame = Frame {
            s,
            c0: 0.5 * (wf - bw * s) - view[0] * s,
            r0: pad + view[3] * s,
        };
        // Radii on screen: median, for line widths.
        let mut radii: Vec<f64> = p
            .discs
            .iter()
            .map(|d| d.r * s)
            .filter(|r| r.is_finite())
            .collect();
        radii.sort_by(f64::total_cmp);
        let r_med = radii.get(radii.len() / 2).copied().unwrap_or(4.0);
        Ok(Layout {
            view,
            frame,
            k,
            pad,
            bw,
            ch,
            r_med,
        })
    }

    /// Pixel column of x (m).
    fn col(&self, x: f64) -> f32 {
        (self.frame.c0 + self.frame.s * x) as f32
    }

    /// Pixel row of y (m).
    fn row(&self, y: f64) -> f32 {
        (self.frame.r0 - self.frame.s * y) as f32
    }

    /// A finite disc of positive radius that reaches into the view.
    fn visible(&self, d: &Disc) -> bool {
        let view = self.view;
        d.x.is_finite()
            && d.y.is_finite()
            && d.r.is_finite()
            && d.r > 0.0
            && d.x + d.r >= view[0]
            && d.x - d.r <= view[1]
            && d.y + d.r >= view[2]
            && d.y - d.r <= view[3]
    }

    /// Width of a bond line (px).
    fn bond_width(&self) -> f32 {
        (0.12 * self.r_med).clamp(0.8, 3.0 * self.k) as f32
    }
}

/// A round-capped, round-joined stroke `width` px wide.
fn line(width: f32) -> Stroke {
    Stroke {
        width,
        line_cap: LineCap::Round,
        line_join: LineJoin::Round,
        ..Stroke::default()
    }
}

/// A polyline through `pts` (m) in pixels (open; the caller may close it).
fn polyline(l: &Layout, pts: &[[f64; 2]]) -> PathBuilder {
    let mut pb = PathBuilder::new();
    for (i, q) in pts.iter().enumerate() {
        if i == 0 {
            pb.move_to(l.col(q[0]), l.row(q[1]));
        } else {
            pb.line_to(l.col(q[0]), l.row(q[1]));
        }
    }
    pb
}

/// A template's grain outline as a closed path, if it has one.
fn outline_path(p: &Picture, l: &Layout) -> Option<tiny_skia::Path> {
    p.outline.as_ref().and_then(|pts| {
        let mut pb = polyline(l, pts);
        pb.close();
        pb.finish()
    })
}

/// Disc colours for [`Options::color`] (not for templates: each of their discs has its own).
struct DiscColours {
    color: ColorBy,
    /// [`grain_colours`] where colouring by grain.
    grain: Option<Vec<usize>>,
    /// Whether each disc has an intact bond.
    intact_of: Vec<bool>,
    /// Top of the speed scale (m/s).
    speed_top: f64,
}

impl DiscColours {
    fn new(p: &Picture, o: &Options, speed_top: f64) -> DiscColours {
        let intact_of: Vec<bool> = {
            let mut v = vec![false; p.discs.len()];
            for b in p.bonds.iter().filter(|b| b.intact) {
                v[b.i] = true;
                v[b.j] = true;
            }
            v
        };
        let grain = (o.color == ColorBy::Grain).then(|| grain_colours(&p.discs));
        DiscColours {
            color: o.color,
            grain,
            intact_of,
            speed_top,
        }
    }

    /// The colour of disc `i`, `d`.
    fn of(&self, i: usize, d: &Disc) -> [u8; 3] {
        match self.color {
            ColorBy::Grain => grain_colour(self.grain.as_ref().map_or(0, |g| g[i])),
            ColorBy::Material => PALETTE[d.material as usize % PALETTE.len()],
            ColorBy::Group => {
                if self.intact_of[i] {
                    BONDED_DISC
                } else {
                    LOOSE_DISC
                }
            }
            ColorBy::Speed => {
                // 64 steps, so discs of one step are drawn as one path.
                let f = if self.speed_top > 0.0 {
                    d.speed / self.speed_top
                } else {
                    0.0
                };
                viridis((f.clamp(0.0, 1.0) * 63.0).round() / 63.0)
            }
        }
    }
}

/// A template's discs: few, and overlapping by design, so each is translucent with its edge and
/// a centre dot.
fn draw_template_discs(pm: &mut Pixmap, p: &Picture, l: &Layout) {
    let (k, s, id) = (l.k, l.frame.s, Transform::identity());
    let edge = Stroke {
        width: (1.5 * k) as f32,
        ..Stroke::default()
    };
    for (i, d) in p.discs.iter().enumerate().filter(|(_, d)| l.visible(d)) {
        let c = PALETTE[i % PALETTE.len()];
        if let Some(path) = PathBuilder::from_circle(l.col(d.x), l.row(d.y), (d.r * s) as f32) {
            pm.fill_path(&path, &paint(c, 120), FillRule::Winding, id, None);
            pm.stroke_path(&path, &paint(shade(c, 0.7), 255), &edge, id, None);
        }
        if let Some(dot) = PathBuilder::from_circle(l.col(d.x), l.row(d.y), (1.5 * k) as f32) {
            pm.fill_path(
                &dot,
                &paint(shade(c, 0.6), 255),
                FillRule::Winding,
                id,
                None,
            );
        }
    }
}

/// Discs of one colour as one path (touching discs of a grain merge cleanly). Where discs are
/// big enough, each has a thin darker rim: all discs are first filled in the rim colour, then
/// all again with the rim width less (two fills cost less than half of stroking the circles).
fn draw_discs(pm: &mut Pixmap, p: &Picture, l: &Layout, colours: &DiscColours) {
    let (r_med, s) = (l.r_med, l.frame.s);
    let rim = if r_med >= 4.0 {
        (0.07 * r_med).clamp(0.5, 1.5)
    } else {
        0.0
    };
    let passes: &[(f64, f64)] = if rim > 0.0 {
        &[(0.0, 0.72), (rim, 1.0)]
    } else {
        &[(0.0, 1.0)]
    };
    for &(inset, tone) in passes {
        let mut by_colour: BTreeMap<[u8; 3], PathBuilder> = BTreeMap::new();
        for (i, d) in p.discs.iter().enumerate().filter(|(_, d)| l.visible(d)) {
            let r = d.r * s - inset;
            if r > 0.0 {
                by_colour.entry(colours.of(i, d)).or_default().push_circle(
                    l.col(d.x),
                    l.row(d.y),
                    r as f32,
                );
            }
        }
        for (c, pb) in by_colour {
            if let Some(path) = pb.finish() {
                let c = shade(c, tone);
                pm.fill_path(
                    &path,
                    &paint(c, 255),
                    FillRule::Winding,
                    Transform::identity(),
                    None,
                );
            }
        }
    }
}

/// Intact bonds as lines between the disc centres: dark, or in their group's colour (wider)
/// with `--color group`.
fn draw_intact_bonds(pm: &mut Pixmap, p: &Picture, o: &Options, l: &Layout) {
    let bond_w = l.bond_width();
    let mut by_group: BTreeMap<u16, PathBuilder> = BTreeMap::new();
    for b in p.bonds.iter().filter(|b| b.intact) {
        let (a, c) = (&p.discs[b.i], &p.discs[b.j]);
        // Both ends finite (a non-finite point would void the whole path), one in view.
        let finite = |d: &Disc| d.x.is_finite() && d.y.is_finite();
        if !(finite(a) && finite(c) && (l.visible(a) || l.visible(c))) {
            continue;
        }
        let key = if o.color == ColorBy::Group {
            b.group
        } else {
            0
        };
        let pb = by_group.entry(key).or_default();
        pb.move_to(l.col(a.x), l.row(a.y));
        pb.line_to(l.col(c.x), l.row(c.y));
    }
    for (g, pb) in by_group {
        let (c, width) = if o.color == ColorBy::Group {
            (
                shade(PALETTE[g as usize % PALETTE.len()], 0.9),
                1.6 * bond_w,
            )
        } else {
            (INK, bond_w)
        };
        if let Some(path) = pb.finish() {
            pm.stroke_path(
                &path,
                &paint(c, 230),
                &line(width),
                Transform::identity(),
                None,
            );
        }
    }
}

/// A crack mark where each bond broke: across the line of the two discs' centres (as they are
/// now), as long as the bond was wide; at the bond's middle now where the break point is not
/// known.
fn draw_cracks(pm: &mut Pixmap, p: &Picture, l: &Layout) {
    let view = l.view;
    let mut pb = PathBuilder::new();
    for b in p.bonds.iter().filter(|b| !b.intact) {
        let (a, c) = (&p.discs[b.i], &p.discs[b.j]);
        let (dx, dy) = (c.x - a.x, c.y - a.y);
        let len = dx.hypot(dy);
        if !(len > 0.0 && len.is_finite()) {
            continue;
        }
        let [mx, my] = b.broke_at.unwrap_or([0.5 * (a.x + c.x), 0.5 * (a.y + c.y)]);
        if !(mx >= view[0] && mx <= view[1] && my >= view[2] && my <= view[3]) {
            continue;
        }
        let half = 0.5
            * if b.width > 0.0 {
                b.width
            } else {
                a.r.min(c.r) * 2.0
            };
        let (nx, ny) = (-dy / len * half, dx / len * half);
        pb.move_to(l.col(mx - nx), l.row(my - ny));
        pb.line_to(l.col(mx + nx), l.row(my + ny));
    }
    if let Some(path) = pb.finish() {
        pm.stroke_path(
            &path,
            &paint(BROKEN, 255),
            &line(2.0 * l.bond_width()),
            Transform::identity(),
            None,
        );
    }
}

/// Walls, and the tool (a wall named `tool`, as `dem test cutting` names it) darker.
fn draw_walls(pm: &mut Pixmap, p: &Picture, l: &Layout) {
    let id = Transform::identity();
    let wall_w = (0.45 * l.r_med).clamp(2.0, 5.0 * l.k) as f32;
    for wall in &p.walls {
        let mut pb = polyline(l, &wall.points);
        let tool = wall.name == "tool";
        // The tool's faces (clearance, rake) enclose a wedge of its body: filled.
        if tool && wall.points.len() >= 3 {
            pb.close();
        }
        if let Some(path) = pb.finish() {
            let c = if tool { TOOL } else { WALL };
            if tool && wall.points.len() >= 3 {
                pm.fill_path(&path, &paint(TOOL, 200), FillRule::EvenOdd, id, None);
            }
            pm.stroke_path(&path, &paint(c, 255), &line(wall_w), id, None);
        }
    }
}

/// A template's outline on top, and its centroid marks: `+` for the grain's, `x` for the
/// clump's.
fn draw_marks(pm: &mut Pixmap, p: &Picture, l: &Layout, outline: Option<&tiny_skia::Path>) {
    let (k, id) = (l.k, Transform::identity());
    if let Some(path) = outline {
        pm.stroke_path(path, &paint(INK, 255), &line((1.5 * k) as f32), id, None);
    }
    let arm = (5.0 * k) as f32;
    if let Some(c) = p.centroid {
        let (x, y) = (l.col(c[0]), l.row(c[1]));
        let mut pb = PathBuilder::new();
        pb.move_to(x - arm, y);
        pb.line_to(x + arm, y);
        pb.move_to(x, y - arm);
        pb.line_to(x, y + arm);
        if let Some(path) = pb.finish() {
            pm.stroke_path(&path, &paint(INK, 255), &line(k as f32), id, None);
        }
    }
    if let Some(c) = p.clump_centroid {
        let (x, y, a) = (l.col(c[0]), l.row(c[1]), 0.75 * arm);
        let mut pb = PathBuilder::new();
        pb.move_to(x - a, y - a);
        pb.line_to(x + a, y + a);
        pb.move_to(x - a, y + a);
        pb.line_to(x + a, y - a);
        if let Some(path) = pb.finish() {
            pm.stroke_path(&path, &paint(BROKEN, 255), &line(k as f32), id, None);
        }
    }
}

/// The content `pm` with the footer below it: the scale bar, the legend at the right (on a
/// row of its own where it does not fit beside the bar), the caption lines below, wrapped to
/// the width.
fn footer(
    pm: &Pixmap,
    p: &Picture,
    o: &Options,
    l: &Layout,
    speed_top: f64,
) -> Result<Pixmap, RenderError> {
    let (w, pad, ch) = (o.width, l.pad, l.ch);
    let kf = l.k as f32;
    let lh = 11.0 * kf;
    let x0 = pad as f32;
    let len = nice_length(0.25 * l.bw);
    let bar_px = (len * l.frame.s) as f32;
    let bar_label = format!("{} mm", sig(len * 1e3));
    let bar_end = x0 + bar_px + 8.0 * kf * (1 + bar_label.len()) as f32;
    let legend = Legend::new(p, o, speed_top);
    let legend_w = legend.width(kf);
    let right = w as f32 - x0;
    let legend_own_row = legend_w > 0.0 && right - legend_w < bar_end + 16.0 * kf;
    let max_chars = ((w as f32 - 2.0 * x0) / (8.0 * kf)).max(4.0) as usize;
    let caption: Vec<String> = p.caption.iter().flat_map(|t| wrap(t, max_chars)).collect();
    let bar_row = 2.0 * lh;
    let legend_row = if legend_own_row { 1.5 * lh } else { 0.0 };
    let fh =
        (0.5 * pad as f32 + bar_row + legend_row + lh * caption.len() as f32 + 0.5 * pad as f32)
            .ceil();
    let total_h = ch as u32 + fh as u32;
    let mut out = Pixmap::new(w, total_h).ok_or(RenderError::Alloc {
        width: w,
        height: total_h,
    })?;
    out.fill(background());
    out.draw_pixmap(
        0,
        0,
        pm.as_ref(),
        &PixmapPaint::default(),
        Transform::identity(),
        None,
    );
    let y0 = (ch as f32 + 0.25 * pad as f32).round();
    block(&mut out, x0, y0 + 0.5 * lh, bar_px, 3.0 * kf, INK);
    for tick in [x0, x0 + bar_px - kf] {
        block(&mut out, tick, y0 + 0.5 * lh - 3.0 * kf, kf, 9.0 * kf, INK);
    }
    let text_y = y0 + 0.5 * lh - 2.0 * kf;
    text(
        &mut out,
        x0 + bar_px + 8.0 * kf,
        text_y,
        &bar_label,
        kf,
        INK,
    );
    if legend_own_row {
        legend.draw(&mut out, x0, text_y + bar_row, kf);
    } else {
        legend.draw(&mut out, right - legend_w, text_y, kf);
    }
    for (n, line) in caption.iter().enumerate() {
        let y = y0 + bar_row + legend_row + lh * n as f32;
        text(&mut out, x0, y, line, kf, INK);
    }
    Ok(out)
}

/// The legend: swatches for materials, bond groups, bonds and cracks as drawn, and for speed
/// a colour bar from 0 to `speed_top`.
struct Legend {
    entries: Vec<([u8; 3], String)>,
    speed: Option<String>,
}

/// Width of the speed colour bar in font pixels.
const SPEED_BAR: f32 = 160.0;

impl Legend {
    fn new(p: &Picture, o: &Options, speed_top: f64) -> Legend {
        let mut entries: Vec<([u8; 3], String)> = match o.color {
            ColorBy::Speed | ColorBy::Grain => Vec::new(),
            ColorBy::Material => {
                let mut mats: Vec<u16> = p.discs.iter().map(|d| d.material).collect();
                mats.sort_unstable();
                mats.dedup();
                mats.iter()
                    .map(|&m| {
                        let name = p
                            .materials
                            .get(m as usize)
                            .cloned()
                            .unwrap_or_else(|| format!("material {m}"));
                        (PALETTE[m as usize % PALETTE.len()], name)
                    })
                    .collect()
            }
            ColorBy::Group => {
                let mut v: Vec<([u8; 3], String)> = p
                    .bond_groups
                    .iter()
                    .enumerate()
                    .map(|(g, name)| (shade(PALETTE[g % PALETTE.len()], 0.9), name.clone()))
                    .collect();
                v.push((LOOSE_DISC, "no intact bond".into()));
                v
            }
        };
        if o.bonds && o.color != ColorBy::Group && p.bonds.iter().any(|b| b.intact) {
            entries.push((INK, "bond".into()));
        }
        if o.broken && p.bonds.iter().any(|b| !b.intact) {
            entries.push((BROKEN, "broken bond".into()));
        }
        let speed = (o.color == ColorBy::Speed).then(|| format!("{} m/s", sig(speed_top)));
        Legend { entries, speed }
    }

    /// Width in pixels at font scale `k`.
    fn width(&self, k: f32) -> f32 {
        let entries: f32 = self
            .entries
            .iter()
            .map(|(_, s)| 8.0 * k * (s.chars().count() as f32 + 3.0))
            .sum();
        let bar = self.speed.as_ref().map_or(0.0, |top| {
            SPEED_BAR * k + 8.0 * k * ("speed 0".len() + 1 + top.chars().count()) as f32
        });
        entries + bar
    }

    /// Draws the legend with its left end at `x`, text top at `y`.
    fn draw(&self, out: &mut Pixmap, mut x: f32, y: f32, k: f32) {
        for (c, s) in &self.entries {
            block(out, x, y, 8.0 * k, 8.0 * k, *c);
            x += 12.0 * k;
            x += text(out, x, y, s, k, INK) + 12.0 * k;
        }
        if let Some(top) = &self.speed {
            x += text(out, x, y, "speed 0", k, INK) + 4.0 * k;
            let (bar, steps) = (SPEED_BAR * k, 64);
            for i in 0..steps {
                let c = viridis(i as f64 / (steps - 1) as f64);
                let (a, b) = (
                    (x + bar * i as f32 / steps as f32).round(),
                    (x + bar * (i + 1) as f32 / steps as f32).round(),
                );
                block(out, a, y - k, b - a, 10.0 * k, c);
            }
            text(out, x + bar + 4.0 * k, y, top, k, INK);
        }
    }
}

/// `line` broken at spaces into lines of at most `max` characters (a longer word is cut).
fn wrap(line: &str, max: usize) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    for word in line.split(' ') {
        let (n, w) = (cur.chars().count(), word.chars().count());
        if n > 0 && n + 1 + w > max {
            out.push(std::mem::take(&mut cur));
        }
        if !cur.is_empty() {
            cur.push(' ');
        }
        cur.push_str(word);
        while cur.chars().count() > max {
            let head: String = cur.chars().take(max).collect();
            cur = cur.chars().skip(max).collect();
            out.push(head);
        }
    }
    if !cur.is_empty() || out.is_empty() {
        out.push(cur);
    }
    out
}

/// The image as a PNG: 8-bit indexed (256 colours) unless `rgb`. An image of at most 256
/// colours is stored exactly; otherwise the 256 most frequent colours are kept (the flat
/// colours of discs, walls, text and background are among them, so they stay exact) and every
/// other pixel (anti-aliased edges) takes the nearest kept colour. That makes a picture about
/// a third of its RGB size (a 1,583-disc cut at 1200 px: 270 kB instead of 810 kB) with no
/// visible change.
pub fn encode_png(pm: &Pixmap, rgb: bool) -> Result<Vec<u8>, RenderError> {
    // Everything is drawn over an opaque background, so premultiplied RGBA is plain RGBA.
    let pixels: Vec<[u8; 3]> = pm
        .data()
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    let mut bytes = Vec::new();
    let mut e = png::Encoder::new(&mut bytes, pm.width(), pm.height());
    e.set_depth(png::BitDepth::Eight);
    let data: Vec<u8> = if rgb {
        e.set_color(png::ColorType::Rgb);
        e.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
        pixels.iter().flatten().copied().collect()
    } else {
        let (palette, index) = quantize(&pixels);
        e.set_color(png::ColorType::Indexed);
        e.set_palette(palette.iter().flatten().copied().collect::<Vec<u8>>());
        e.set_filter(png::FilterType::NoFilter);
        index
    };
    e.set_compression(png::Compression::Default);
    let mut wr = e.write_header()?;
    wr.write_image_data(&data)?;
    wr.finish()?;
    Ok(bytes)
}

/// At most 256 colours for `pixels`: the most frequent ones (ties by colour, so the result is
/// deterministic), each pixel mapped to the nearest (squared RGB distance). Exact when the
/// image has 256 colours or fewer.
pub fn quantize(pixels: &[[u8; 3]]) -> (Vec<[u8; 3]>, Vec<u8>) {
    let mut counts: HashMap<[u8; 3], usize> = HashMap::new();
    for p in pixels {
        *counts.entry(*p).or_insert(0) += 1;
    }
    let mut by_count: Vec<([u8; 3], usize)> = counts.into_iter().collect();
    by_count.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let palette: Vec<[u8; 3]> = by_count.iter().take(256).map(|c| c.0).collect();
    let mut nearest: HashMap<[u8; 3], u8> = palette
        .iter()
        .enumerate()
        .map(|(k, c)| (*c, k as u8))
        .collect();
    let index = pixels
        .iter()
        .map(|c| {
            *nearest.entry(*c).or_insert_with(|| {
                let d = |q: &[u8; 3]| -> i32 {
                    (0..3).map(|k| (q[k] as i32 - c[k] as i32).pow(2)).sum()
                };
                (0..palette.len())
                    .min_by_key(|&k| d(&palette[k]))
                    .unwrap_or(0) as u8
            })
        })
        .collect();
    (palette, index)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn disc(x: f64, grain: u64) -> Disc {
        Disc {
            x,
            y: 0.0,
            r: 0.5,
            speed: 0.0,
            material: 0,
            grain,
        }
    }

    #[test]
    fn touching_grains_get_different_colours_and_one_grain_one_colour() {
        // A row of grains 0,0,1,2,2,3: neighbours differ, discs of a grain agree.
        let d: Vec<Disc> = [0, 0, 1, 2, 2, 3]
            .iter()
            .enumerate()
            .map(|(i, &g)| disc(i as f64, g))
            .collect();
        let c = grain_colours(&d);
        assert_eq!(c[0], c[1]);
        assert_eq!(c[3], c[4]);
        assert_ne!(c[1], c[2]);
        assert_ne!(c[2], c[3]);
        assert_ne!(c[4], c[5]);
        assert_eq!(c, grain_colours(&d), "deterministic");
        // Among clumps, one-disc grains are plain; without clumps every disc has a colour.
        assert_eq!((c[2], c[5]), (PLAIN, PLAIN));
        assert!(c[0] < PALETTE.len() && c[3] < PALETTE.len());
        let singles: Vec<Disc> = (0..4).map(|i| disc(i as f64, i)).collect();
        let c = grain_colours(&singles);
        assert!(c.iter().all(|&k| k < PALETTE.len()), "{c:?}");
        assert!(c.windows(2).all(|w| w[0] != w[1]), "{c:?}");
    }

    #[test]
    fn nice_lengths_and_the_speed_scale() {
        assert_eq!(nice_length(7.3e-3), 5e-3);
        assert!((nice_length(0.0042) - 0.002).abs() < 1e-15);
        assert!((nice_length(1.0e-3) - 1e-3).abs() < 1e-15);
        assert_eq!(viridis(0.0), VIRIDIS[0]);
        assert_eq!(viridis(1.0), VIRIDIS[4]);
        assert_eq!(viridis(f64::NAN), VIRIDIS[4]);
        assert_eq!(viridis(0.5), VIRIDIS[2]);
    }

    #[test]
    fn captions_wrap_at_spaces() {
        assert_eq!(wrap("ab cd ef", 5), vec!["ab cd", "ef"]);
        assert_eq!(wrap("abcdefgh", 3), vec!["abc", "def", "gh"]);
        assert_eq!(wrap("", 3), vec![""]);
        assert!(wrap("x y z w v u t s", 4)
            .iter()
            .all(|l| l.chars().count() <= 4));
    }

    #[test]
    fn quantize_keeps_few_colours_exactly_and_frequent_ones_among_many() {
        let px: Vec<[u8; 3]> = vec![[1, 2, 3], [9, 9, 9], [1, 2, 3]];
        let (pal, idx) = quantize(&px);
        let back: Vec<[u8; 3]> = idx.iter().map(|&k| pal[k as usize]).collect();
        assert_eq!(back, px);
        // 300 colours: the frequent white stays exact, a rare colour maps to a near one.
        let mut px: Vec<[u8; 3]> = vec![[255, 255, 255]; 1000];
        px.extend((0..300u32).map(|k| [(k % 256) as u8, (k / 256) as u8 * 100, 7]));
        let (pal, idx) = quantize(&px);
        assert_eq!(pal.len(), 256);
        assert_eq!(pal[idx[0] as usize], [255, 255, 255]);
        for (p, &k) in px.iter().zip(&idx) {
            let q = pal[k as usize];
            let d: i32 = (0..3).map(|c| (p[c] as i32 - q[c] as i32).pow(2)).sum();
            assert!(d <= 100 * 100, "{p:?} -> {q:?}");
        }
    }
}
