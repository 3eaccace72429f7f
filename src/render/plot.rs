//! Figures for fuzzy variables and two-input response surfaces.
//!
//! [`plot_variable`] draws the membership functions of one linguistic
//! variable as coloured curves over its universe of discourse, each labelled
//! with its term name near its peak. [`plot_surface`] draws a sampled
//! function `z = f(x, y)` as a heat map with a colour bar.
//!
//! Both functions are total: malformed input (non-finite or empty ranges,
//! NaN samples, missing points, tiny or huge image sizes) yields a sensible
//! figure instead of a panic, and identical input always yields identical
//! pixels.

use super::font::{DESCENT, draw_text, text_height, text_width};
use tiny_skia::{
    Color, FillRule, LineCap, LineJoin, Mask, Paint, PathBuilder, Pixmap, PremultipliedColorU8, Rect, Stroke, Transform,
};

/// Smallest image produced; smaller requests are enlarged to this.
const MIN_SIZE: (u32, u32) = (64, 48);
/// Largest image produced; larger requests are reduced to this.
const MAX_SIDE: u32 = 8192;

/// Curve colours (Okabe–Ito, extended with three Tol colours), used cyclically.
const PALETTE: [(u8, u8, u8); 10] = [
    (0, 114, 178),   // blue
    (213, 94, 0),    // vermillion
    (0, 158, 115),   // bluish green
    (204, 121, 167), // reddish purple
    (230, 159, 0),   // orange
    (86, 180, 233),  // sky blue
    (136, 34, 85),   // wine
    (153, 153, 51),  // olive
    (51, 34, 136),   // indigo
    (0, 0, 0),       // black
];

/// Viridis control points, evenly spaced over [0, 1].
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (71, 45, 123),
    (59, 82, 139),
    (44, 114, 142),
    (33, 144, 140),
    (39, 173, 129),
    (93, 200, 99),
    (170, 220, 50),
    (253, 231, 37),
];

/// Fill colour for cells whose value is NaN.
const NAN_GREY: (u8, u8, u8) = (128, 128, 128);
const INK: (u8, u8, u8) = (0, 0, 0);
const GRID: (u8, u8, u8) = (225, 225, 225);

/// One membership function of a linguistic variable.
#[derive(Debug, Clone, PartialEq)]
pub struct TermCurve {
    /// Term name, written near the curve's peak.
    pub name: String,
    /// Sample points `(x, membership)`, x ascending, membership in [0, 1].
    /// Points with a non-finite coordinate are skipped and break the line.
    pub points: Vec<(f64, f64)>,
}

/// All membership functions of one linguistic variable.
#[derive(Debug, Clone, PartialEq)]
pub struct VariableFigure {
    /// Figure title, drawn centred at the top.
    pub title: String,
    /// Universe of discourse `(min, max)` shown on the x axis.
    pub range: (f64, f64),
    /// Curves in drawing order; colours are assigned by position.
    pub curves: Vec<TermCurve>,
}

/// A function of two inputs sampled on a regular grid.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceFigure {
    /// Figure title, drawn centred at the top.
    pub title: String,
    /// Name of the horizontal input, written under the x axis.
    pub x_name: String,
    /// Range `(first, last)` of the horizontal input.
    pub x_range: (f64, f64),
    /// Number of samples along x (columns).
    pub nx: usize,
    /// Name of the vertical input, written above the y axis.
    pub y_name: String,
    /// Range `(first, last)` of the vertical input; y increases upwards.
    pub y_range: (f64, f64),
    /// Number of samples along y (rows).
    pub ny: usize,
    /// Name of the output, written above the colour bar.
    pub z_name: String,
    /// row-major: values[j * nx + i] is z at x_i = x_range.0 + i*(x_range.1-x_range.0)/(nx-1), y_j likewise; NaN allowed
    pub values: Vec<f64>,
}

/// Renders the membership functions of `fig` as a `width`×`height` image.
///
/// The figure has a white background, a title, an x axis with about five
/// tidy ticks over `fig.range`, a y axis with ticks at 0, 0.5 and 1, and one
/// antialiased 2 px polyline per curve with its term name near its peak.
/// If the range is not a finite, non-empty interval only the frame and the
/// title are drawn. Sizes are clamped to at least 64×48.
pub fn plot_variable(fig: &VariableFigure, width: u32, height: u32) -> Pixmap {
    let mut pm = blank_canvas(width, height);
    let (w, h) = (pm.width() as i32, pm.height() as i32);
    let s = text_scale(w, h);
    let th = text_height(s) as i32;
    let pad = 4 * s as i32;
    let tick = 2 * s as i32 + 1;

    let title_bottom = draw_title(&mut pm, &fig.title, s);
    let range = sorted_range(fig.range);
    let xticks = range.map(|(lo, hi)| tick_labels(lo, hi)).unwrap_or_default();
    let ylabels = [(0.0, "0"), (0.5, "0.5"), (1.0, "1")];

    let last_half = xticks.last().map_or(0, |(_, l)| text_width(l, s) as i32 / 2);
    let first_half = xticks.first().map_or(0, |(_, l)| text_width(l, s) as i32 / 2);
    let left = (pad + text_width("0.5", s) as i32 + tick + s as i32).max(first_half + pad);
    let right = w - pad.max(last_half + s as i32);
    let top = title_bottom + pad;
    let bottom = h - (pad / 2 + th + tick + s as i32);
    let area = PlotArea { left, top, right, bottom };
    if !area.usable() {
        draw_fallback_frame(&mut pm, title_bottom, s);
        return pm;
    }
    let Some((lo, hi)) = range else {
        draw_frame(&mut pm, &area, s);
        return pm;
    };

    // Membership axis shows [Y_LO, Y_HI] so curves at 0 and 1 clear the frame.
    const Y_LO: f64 = -0.04;
    const Y_HI: f64 = 1.12;
    let to_px = |x: f64| area.left as f64 + (x - lo) / (hi - lo) * area.width() as f64;
    let to_py = |y: f64| area.bottom as f64 - (y - Y_LO) / (Y_HI - Y_LO) * area.height() as f64;

    // Grid, ticks and tick labels.
    let ink = rgb(INK);
    for (v, label) in &xticks {
        let px = to_px(*v).round() as i32;
        fill_px(&mut pm, px, area.top, 1, area.height(), rgb(GRID));
        fill_px(&mut pm, px, area.bottom, 1, tick, ink);
        let lw = text_width(label, s) as i32;
        draw_text(&mut pm, px - lw / 2, area.bottom + tick + s as i32, label, s, ink);
    }
    for (v, label) in ylabels {
        let py = to_py(v).round() as i32;
        fill_px(&mut pm, area.left, py, area.width(), 1, rgb(GRID));
        fill_px(&mut pm, area.left - tick, py, tick, 1, ink);
        let lw = text_width(label, s) as i32;
        draw_text(&mut pm, area.left - tick - s as i32 - lw, py - th / 2, label, s, ink);
    }

    // Curves, clipped to the plot area.
    let mask = area_mask(&pm, &area);
    for (k, curve) in fig.curves.iter().enumerate() {
        let color = rgb(PALETTE[k % PALETTE.len()]);
        let pts: Vec<Option<(f32, f32)>> = curve
            .points
            .iter()
            .map(|&(x, y)| {
                let finite = x.is_finite() && y.is_finite();
                finite.then(|| (clamp_f32(to_px(x)), clamp_f32(to_py(y))))
            })
            .collect();
        draw_polyline(&mut pm, &pts, color, mask.as_ref());
    }

    // Term names near each curve's peak, avoiding earlier labels.
    let mut placed: Vec<(i32, i32, i32, i32)> = Vec::new();
    for (k, curve) in fig.curves.iter().enumerate() {
        if curve.name.is_empty() {
            continue;
        }
        let Some((px, py)) = peak(&curve.points) else {
            continue;
        };
        let color = rgb(PALETTE[k % PALETTE.len()]);
        let lw = text_width(&curve.name, s) as i32;
        let cx = to_px(px).clamp(-1e6, 1e6) as i32;
        let cy = to_py(py).clamp(-1e6, 1e6) as i32;
        let x = (cx - lw / 2).min(area.right - 2 - lw).max(area.left + 2 + s as i32);
        let base_y = cy - 2 * s as i32 - 1 - th;
        let lo_y = area.top + s as i32 + 1;
        let hi_y = area.bottom - s as i32 - 1 - th;
        let step = th + 2 * s as i32;
        let mut y = base_y.clamp(lo_y, hi_y.max(lo_y));
        for attempt in 0..8 {
            let cand = (base_y + attempt * step).clamp(lo_y, hi_y.max(lo_y));
            if !placed.iter().any(|r| overlaps(*r, (cand, x, lw, th))) {
                y = cand;
                break;
            }
        }
        placed.push((y, x, lw, th));
        let halo = s as i32;
        fill_px_blend(&mut pm, x - halo, y - halo, lw + 2 * halo, th + 2 * halo, Color::from_rgba8(255, 255, 255, 200));
        draw_text(&mut pm, x, y, &curve.name, s, color);
    }

    draw_frame(&mut pm, &area, s);
    pm
}

/// Renders `fig` as a heat map of z over (x, y) with a colour bar.
///
/// Each grid sample fills the cell of pixels nearest to it, coloured with a
/// viridis colour map scaled to the finite minimum and maximum of the
/// values; NaN samples (and samples missing because `values` is too short)
/// are mid-grey. The y axis points upwards. If a range is not finite and
/// non-empty, or the grid is empty, only the frame and the title are drawn.
/// Sizes are clamped to at least 64×48.
pub fn plot_surface(fig: &SurfaceFigure, width: u32, height: u32) -> Pixmap {
    let mut pm = blank_canvas(width, height);
    let (w, h) = (pm.width() as i32, pm.height() as i32);
    let s = text_scale(w, h);
    let si = s as i32;
    let th = text_height(s) as i32;
    let pad = 4 * si;
    let tick = 2 * si + 1;
    let ink = rgb(INK);

    let title_bottom = draw_title(&mut pm, &fig.title, s);
    let xr = valid_range(fig.x_range);
    let yr = valid_range(fig.y_range);
    let cells = fig.nx.checked_mul(fig.ny).filter(|&n| n > 0);
    let ok = xr.is_some() && yr.is_some() && cells.is_some();

    let xticks = xr.map(|r| tick_labels(r.0.min(r.1), r.0.max(r.1))).unwrap_or_default();
    let yticks = yr.map(|r| tick_labels(r.0.min(r.1), r.0.max(r.1))).unwrap_or_default();
    let finite = if ok { finite_extent(fig.values.iter().take(cells.unwrap_or(0))) } else { None };
    let (zmin_label, zmax_label) = match finite {
        Some((a, b)) if a < b => (format_value(a), format_value(b)),
        Some((a, _)) => (String::new(), format_value(a)),
        None => (String::new(), "NaN".to_string()),
    };

    let ytick_w = yticks.iter().map(|(_, l)| text_width(l, s) as i32).max().unwrap_or(0);
    let bar_label_w = text_width(&zmin_label, s).max(text_width(&zmax_label, s)) as i32;
    let bar_w = 4 * si + 4;
    let bar_gap = 4 * si + 2;
    let z_name_w = text_width(&fig.z_name, s) as i32;
    let bar_block = (bar_w + si + 2 + bar_label_w).max(z_name_w.min(w / 4));
    let last_half = xticks.last().map_or(0, |(_, l)| text_width(l, s) as i32 / 2);

    let left = pad + ytick_w + tick + si;
    let right = w - pad - bar_block - bar_gap.max(last_half);
    let top = title_bottom + pad / 2 + th + descent(s) + th / 2 + 2 * si;
    let bottom = h - (si + descent(s) + 2 * th + tick + 3 * si);
    let area = PlotArea { left, top, right, bottom };
    if !area.usable() {
        draw_fallback_frame(&mut pm, title_bottom, s);
        return pm;
    }

    // Axis names: y above the axis, x centred below the tick labels, z above the bar.
    let name_y = area.top - th / 2 - 2 * si - descent(s) - th;
    draw_text(&mut pm, (area.left - ytick_w / 2).max(si), name_y, &fig.y_name, s, ink);
    let xw = text_width(&fig.x_name, s) as i32;
    let x_name_x = (area.left + area.width() / 2 - xw / 2).max(si);
    draw_text(&mut pm, x_name_x, h - si - descent(s) - th, &fig.x_name, s, ink);
    let bar_x = area.right + bar_gap;
    let z_name_x = (bar_x + bar_w / 2 - z_name_w / 2).min(w - si - z_name_w).max(bar_x - bar_gap / 2);
    draw_text(&mut pm, z_name_x, name_y, &fig.z_name, s, ink);

    let (Some(xr), Some(yr), true) = (xr, yr, ok) else {
        draw_frame(&mut pm, &area, s);
        return pm;
    };

    // Heat map: every pixel takes the colour of its nearest grid sample.
    let (nx, ny) = (fig.nx, fig.ny);
    let (aw, ah) = (area.width() as f64, area.height() as f64);
    let column: Vec<usize> = (0..area.width()).map(|dx| nearest_index((f64::from(dx) + 0.5) / aw, nx)).collect();
    for dy in 0..area.height() {
        let py = area.top + dy;
        if py < 0 || py >= h {
            continue;
        }
        let j = nearest_index(1.0 - (f64::from(dy) + 0.5) / ah, ny);
        let row = py as usize * w as usize;
        for (dx, &i) in column.iter().enumerate() {
            let px = area.left + dx as i32;
            if px < 0 || px >= w {
                continue;
            }
            let z = fig.values.get(j * nx + i).copied().unwrap_or(f64::NAN);
            let c = z_colour(z, finite);
            pm.pixels_mut()[row + px as usize] = opaque(c);
        }
    }

    // Ticks and labels; positions follow the sample order of each range.
    for (v, label) in &xticks {
        let px = area.left + ((v - xr.0) / (xr.1 - xr.0) * aw).round() as i32;
        fill_px(&mut pm, px, area.bottom, 1, tick, ink);
        let lw = text_width(label, s) as i32;
        draw_text(&mut pm, px - lw / 2, area.bottom + tick + si, label, s, ink);
    }
    for (v, label) in &yticks {
        let py = area.bottom - ((v - yr.0) / (yr.1 - yr.0) * ah).round() as i32;
        fill_px(&mut pm, area.left - tick, py, tick, 1, ink);
        let lw = text_width(label, s) as i32;
        draw_text(&mut pm, area.left - tick - si - lw, py - th / 2, label, s, ink);
    }
    draw_frame(&mut pm, &area, s);

    // Colour bar: top is the maximum; grey when there is no finite value,
    // one flat colour when all finite values are equal.
    let bar = PlotArea { left: bar_x, top: area.top, right: bar_x + bar_w, bottom: area.bottom };
    let bh = f64::from(bar.height().max(1));
    for dy in 0..bar.height() {
        let c = match finite {
            None => NAN_GREY,
            Some((a, b)) if a == b => viridis(0.5),
            Some(_) => viridis(1.0 - (f64::from(dy) + 0.5) / bh),
        };
        fill_px(&mut pm, bar.left, bar.top + dy, bar_w, 1, rgb(c));
    }
    draw_frame(&mut pm, &bar, s);
    let label_x = bar.right + si + 2;
    match finite {
        Some((a, b)) if a < b => {
            draw_text(&mut pm, label_x, bar.top, &zmax_label, s, ink);
            draw_text(&mut pm, label_x, bar.bottom - th, &zmin_label, s, ink);
        }
        _ => {
            let mid = bar.top + bar.height() / 2 - th / 2;
            draw_text(&mut pm, label_x, mid, &zmax_label, s, ink);
        }
    }
    pm
}

/// Pixel rectangle `[left, right) × [top, bottom)` of a plot panel.
struct PlotArea {
    left: i32,
    top: i32,
    right: i32,
    bottom: i32,
}

impl PlotArea {
    fn width(&self) -> i32 {
        self.right - self.left
    }

    fn height(&self) -> i32 {
        self.bottom - self.top
    }

    fn usable(&self) -> bool {
        self.width() >= 8 && self.height() >= 8 && self.left >= 0 && self.top >= 0
    }
}

/// Outlines the space below the title when no plot area fits.
fn draw_fallback_frame(pm: &mut Pixmap, title_bottom: i32, s: u32) {
    let area =
        PlotArea { left: 2, top: title_bottom + 2, right: pm.width() as i32 - 2, bottom: pm.height() as i32 - 2 };
    if area.width() > 0 && area.height() > 0 {
        draw_frame(pm, &area, s);
    }
}

/// White pixmap of the clamped size.
fn blank_canvas(width: u32, height: u32) -> Pixmap {
    let w = width.clamp(MIN_SIZE.0, MAX_SIDE);
    let h = height.clamp(MIN_SIZE.1, MAX_SIDE);
    let mut pm = Pixmap::new(w, h).expect("clamped pixmap size is valid");
    pm.fill(Color::WHITE);
    pm
}

/// Integer text scale suited to the image size.
fn text_scale(w: i32, h: i32) -> u32 {
    (w.min(h * 4 / 3) / 260).clamp(1, 4) as u32
}

/// Draws the title centred at the top and returns the y just below it.
fn draw_title(pm: &mut Pixmap, title: &str, s: u32) -> i32 {
    let ts = if s >= 2 { s + 1 } else { s };
    let pad = 3 * s as i32;
    let tw = text_width(title, ts) as i32;
    let w = pm.width() as i32;
    let x = if tw + 2 * pad <= w { (w - tw) / 2 } else { pad };
    draw_text(pm, x, pad, title, ts, rgb(INK));
    pad + text_height(ts) as i32 + descent(ts)
}

/// Extra pixels below the baseline used by descending letters at scale `s`.
fn descent(s: u32) -> i32 {
    (DESCENT * s) as i32
}

/// Draws the rectangle outline of `area`.
fn draw_frame(pm: &mut Pixmap, area: &PlotArea, s: u32) {
    let lw = if s >= 3 { 2 } else { 1 };
    let ink = rgb(INK);
    let (l, t, r, b) = (area.left, area.top, area.right, area.bottom);
    fill_px(pm, l - lw, t - lw, r - l + 2 * lw, lw, ink);
    fill_px(pm, l - lw, b, r - l + 2 * lw, lw, ink);
    fill_px(pm, l - lw, t, lw, b - t, ink);
    fill_px(pm, r, t, lw, b - t, ink);
}

/// Fills an integer pixel rectangle with an opaque colour (clipped).
fn fill_px(pm: &mut Pixmap, x: i32, y: i32, w: i32, h: i32, color: Color) {
    let x0 = x.max(0);
    let y0 = y.max(0);
    let x1 = x.saturating_add(w).min(pm.width() as i32);
    let y1 = y.saturating_add(h).min(pm.height() as i32);
    if x0 >= x1 || y0 >= y1 {
        return;
    }
    let stride = pm.width() as usize;
    let c = color.premultiply().to_color_u8();
    let pixels = pm.pixels_mut();
    for py in y0..y1 {
        let row = py as usize * stride;
        pixels[row + x0 as usize..row + x1 as usize].fill(c);
    }
}

/// Fills a pixel rectangle with a possibly translucent colour.
fn fill_px_blend(pm: &mut Pixmap, x: i32, y: i32, w: i32, h: i32, color: Color) {
    if let Some(rect) = Rect::from_xywh(x as f32, y as f32, w as f32, h as f32) {
        let mut paint = Paint::default();
        paint.set_color(color);
        paint.anti_alias = false;
        pm.fill_rect(rect, &paint, Transform::identity(), None);
    }
}

/// Clip mask covering the inside of `area`.
fn area_mask(pm: &Pixmap, area: &PlotArea) -> Option<Mask> {
    let mut mask = Mask::new(pm.width(), pm.height())?;
    let rect = Rect::from_ltrb(area.left as f32, area.top as f32, area.right as f32, area.bottom as f32)?;
    let path = PathBuilder::from_rect(rect);
    mask.fill_path(&path, FillRule::Winding, false, Transform::identity());
    Some(mask)
}

/// Strokes runs of consecutive points; `None` breaks the line. Isolated
/// points are drawn as dots.
fn draw_polyline(pm: &mut Pixmap, pts: &[Option<(f32, f32)>], color: Color, mask: Option<&Mask>) {
    let mut paint = Paint::default();
    paint.set_color(color);
    paint.anti_alias = true;
    let stroke = Stroke { width: 2.0, line_cap: LineCap::Round, line_join: LineJoin::Round, ..Stroke::default() };
    for run in pts.split(Option::is_none) {
        let run: Vec<(f32, f32)> = run.iter().flatten().copied().collect();
        match run.as_slice() {
            [] => {}
            [(x, y)] => {
                if let Some(dot) = PathBuilder::from_circle(*x, *y, 2.0) {
                    pm.fill_path(&dot, &paint, FillRule::Winding, Transform::identity(), mask);
                }
            }
            [(x0, y0), rest @ ..] => {
                let mut pb = PathBuilder::new();
                pb.move_to(*x0, *y0);
                for (x, y) in rest {
                    pb.line_to(*x, *y);
                }
                if let Some(path) = pb.finish() {
                    pm.stroke_path(&path, &paint, &stroke, Transform::identity(), mask);
                }
            }
        }
    }
}

/// First finite point of maximal membership.
fn peak(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    points.iter().copied().filter(|(x, y)| x.is_finite() && y.is_finite()).fold(None, |best: Option<(f64, f64)>, p| {
        match best {
            Some(b) if b.1 >= p.1 => Some(b),
            _ => Some(p),
        }
    })
}

fn overlaps(a: (i32, i32, i32, i32), b: (i32, i32, i32, i32)) -> bool {
    let (ay, ax, aw, ah) = a;
    let (by, bx, bw, bh) = b;
    ax < bx + bw + 2 && bx < ax + aw + 2 && ay < by + bh + 1 && by < ay + ah + 1
}

/// Keeps mapped coordinates in a range the rasteriser handles well.
fn clamp_f32(v: f64) -> f32 {
    v.clamp(-1e6, 1e6) as f32
}

/// The range as `(first, last)` if both ends and the span are finite and non-zero.
fn valid_range(r: (f64, f64)) -> Option<(f64, f64)> {
    let span = r.1 - r.0;
    (r.0.is_finite() && r.1.is_finite() && span.is_finite() && span != 0.0).then_some(r)
}

/// The range ordered ascending, if valid.
fn sorted_range(r: (f64, f64)) -> Option<(f64, f64)> {
    valid_range(r).map(|(a, b)| (a.min(b), a.max(b)))
}

/// Index of the grid sample nearest to fraction `f` of the way along `n` samples.
fn nearest_index(f: f64, n: usize) -> usize {
    if n <= 1 {
        return 0;
    }
    let last = (n - 1) as f64;
    (f.clamp(0.0, 1.0) * last).round().clamp(0.0, last) as usize
}

/// Minimum and maximum of the finite values, if any.
fn finite_extent<'a>(values: impl Iterator<Item = &'a f64>) -> Option<(f64, f64)> {
    values.copied().filter(|v| v.is_finite()).fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((a, b)) => Some((a.min(v), b.max(v))),
    })
}

/// Colour of value `z` given the finite extent of all values.
fn z_colour(z: f64, extent: Option<(f64, f64)>) -> (u8, u8, u8) {
    match extent {
        Some((a, b)) if z.is_finite() => {
            let span = b - a;
            if span > 0.0 && span.is_finite() { viridis((z - a) / span) } else { viridis(0.5) }
        }
        _ => NAN_GREY,
    }
}

/// Viridis colour at `t` in [0, 1] (clamped), linearly interpolated.
fn viridis(t: f64) -> (u8, u8, u8) {
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let pos = t * (VIRIDIS.len() - 1) as f64;
    let k = (pos.floor() as usize).min(VIRIDIS.len() - 2);
    let f = pos - k as f64;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    let lerp = |p: u8, q: u8| (f64::from(p) + (f64::from(q) - f64::from(p)) * f).round() as u8;
    (lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2))
}

fn rgb(c: (u8, u8, u8)) -> Color {
    Color::from_rgba8(c.0, c.1, c.2, 255)
}

fn opaque(c: (u8, u8, u8)) -> PremultipliedColorU8 {
    rgb(c).premultiply().to_color_u8()
}

/// About five tidy ticks covering `[lo, hi]`, with their labels.
///
/// If the range splits into four intervals of a short round length starting
/// at `lo` (as in 0..100 or -180..180), those are used so both ends carry a
/// tick; otherwise the step is 1, 2, 2.5 or 5 times a power of ten, chosen
/// to give a tick count closest to five.
fn tick_labels(lo: f64, hi: f64) -> Vec<(f64, String)> {
    let span = hi - lo;
    let raw = span / 4.0;
    if !(raw.is_finite() && raw > 0.0) {
        return Vec::new();
    }
    let step = if is_round(raw) && is_multiple(lo, raw) {
        raw
    } else {
        let mag = 10f64.powf(raw.log10().floor());
        let count = |st: f64| (hi / st + 1e-9).floor() - (lo / st - 1e-9).ceil() + 1.0;
        [0.5, 1.0, 2.0, 2.5, 5.0, 10.0, 20.0]
            .iter()
            .map(|m| m * mag)
            .filter(|&st| st > 0.0 && count(st).is_finite())
            .fold(None, |best: Option<(f64, f64)>, st| {
                let dist = (count(st) - 5.0).abs();
                match best {
                    Some((_, d)) if d < dist => best,
                    _ => Some((st, dist)),
                }
            })
            .map_or(raw, |(st, _)| st)
    };
    let k0 = (lo / step - 1e-9).ceil();
    let k1 = (hi / step + 1e-9).floor();
    if !(k0.is_finite() && k1.is_finite()) || k1 < k0 || k1 - k0 > 20.0 {
        return vec![(lo, format_value(lo)), (hi, format_value(hi))];
    }
    let values: Vec<f64> = (0..=(k1 - k0) as i64).map(|n| (k0 + n as f64) * step).collect();
    let max_abs = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let use_exp = max_abs >= 1e5 || step < 1e-3;
    let decimals = step_decimals(step);
    values
        .into_iter()
        .map(|v| {
            let label = if v.abs() < step * 1e-6 {
                "0".to_string()
            } else if use_exp {
                format_exp(v)
            } else {
                trim_number(format!("{v:.decimals$}"))
            };
            (v, label)
        })
        .collect()
}

/// Whether `v` has at most two significant digits.
fn is_round(v: f64) -> bool {
    let unit = 10f64.powf(v.abs().log10().floor() - 1.0);
    let m = v / unit;
    unit > 0.0 && m.is_finite() && (m - m.round()).abs() < 1e-9 * m.abs().max(1.0)
}

/// Whether `v` is an integer multiple of `step`.
fn is_multiple(v: f64, step: f64) -> bool {
    let k = v / step;
    k.is_finite() && (k - k.round()).abs() < 1e-9 * k.abs().max(1.0)
}

/// Number of decimals needed to print multiples of `step` exactly.
fn step_decimals(step: f64) -> usize {
    (0..=9)
        .find(|&d| {
            let scaled = step * 10f64.powi(d as i32);
            (scaled - scaled.round()).abs() < 1e-6 * scaled.max(1.0)
        })
        .unwrap_or(9)
}

/// Short label for an arbitrary value: three significant digits, or
/// exponent form for very large or small magnitudes.
fn format_value(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if a == 0.0 {
        return "0".to_string();
    }
    if !(1e-3..1e5).contains(&a) {
        return format_exp(v);
    }
    let d = (2 - a.log10().floor() as i32).clamp(0, 6) as usize;
    trim_number(format!("{v:.d$}"))
}

/// Exponent form such as `1e+03` or `-2.5e-04`.
fn format_exp(v: f64) -> String {
    let s = format!("{v:.2e}");
    let Some((mant, exp)) = s.split_once('e') else {
        return s;
    };
    let mant = trim_number(mant.to_string());
    let exp: i32 = exp.parse().unwrap_or(0);
    let sign = if exp < 0 { '-' } else { '+' };
    format!("{mant}e{sign}{:02}", exp.abs())
}

/// Drops trailing zeros after a decimal point and normalises `-0`.
fn trim_number(mut s: String) -> String {
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" { "0".to_string() } else { s }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle(name: &str, a: f64, b: f64, c: f64) -> TermCurve {
        TermCurve { name: name.to_string(), points: vec![(a, 0.0), (b, 1.0), (c, 0.0)] }
    }

    fn three_terms() -> VariableFigure {
        VariableFigure {
            title: "temperature".to_string(),
            range: (0.0, 100.0),
            curves: vec![
                triangle("cold", 0.0, 0.0, 50.0),
                triangle("warm", 0.0, 50.0, 100.0),
                triangle("hot", 50.0, 100.0, 100.0),
            ],
        }
    }

    fn surface(nx: usize, ny: usize, values: Vec<f64>) -> SurfaceFigure {
        SurfaceFigure {
            title: "control surface".to_string(),
            x_name: "error".to_string(),
            x_range: (-1.0, 1.0),
            nx,
            y_name: "delta".to_string(),
            y_range: (0.0, 10.0),
            ny,
            z_name: "output".to_string(),
            values,
        }
    }

    fn has_colour(pm: &Pixmap, c: (u8, u8, u8)) -> bool {
        pm.pixels().iter().any(|p| p.alpha() == 255 && (p.red(), p.green(), p.blue()) == c)
    }

    #[test]
    fn variable_plot_has_each_curve_colour() {
        let pm = plot_variable(&three_terms(), 480, 320);
        assert_eq!((pm.width(), pm.height()), (480, 320));
        for c in &PALETTE[..3] {
            assert!(has_colour(&pm, *c), "missing colour {c:?}");
        }
        assert!(!has_colour(&pm, PALETTE[3]));
    }

    #[test]
    fn surface_nan_cell_is_grey() {
        let mut values: Vec<f64> = (0..12).map(f64::from).collect();
        values[5] = f64::NAN;
        let pm = plot_surface(&surface(4, 3, values), 400, 300);
        assert_eq!((pm.width(), pm.height()), (400, 300));
        assert!(has_colour(&pm, NAN_GREY));
        assert!(has_colour(&pm, VIRIDIS[0]));
        assert!(has_colour(&pm, VIRIDIS[8]));
    }

    #[test]
    fn output_is_deterministic() {
        let a = plot_variable(&three_terms(), 300, 200);
        let b = plot_variable(&three_terms(), 300, 200);
        assert_eq!(a.data(), b.data());
        let v: Vec<f64> = (0..30).map(|k| f64::from(k).sin()).collect();
        let a = plot_surface(&surface(6, 5, v.clone()), 300, 200);
        let b = plot_surface(&surface(6, 5, v), 300, 200);
        assert_eq!(a.data(), b.data());
    }

    #[test]
    fn degenerate_variables_do_not_panic() {
        let nan = f64::NAN;
        let inf = f64::INFINITY;
        let ranges = [
            (0.0, 1.0),
            (1.0, 1.0),
            (nan, 1.0),
            (0.0, inf),
            (-inf, inf),
            (f64::MAX, -f64::MAX),
            (5.0, -5.0),
            (0.0, 1e-300),
            (1e9, 1e9 + 1.0),
            (-1e12, 1e12),
        ];
        let curves = vec![
            TermCurve { name: String::new(), points: vec![] },
            TermCurve { name: "one".into(), points: vec![(0.5, 0.5)] },
            TermCurve { name: "nan".into(), points: vec![(nan, nan), (0.2, nan), (0.3, 1.0), (inf, 0.0)] },
            TermCurve { name: "wild".into(), points: vec![(-1e300, 5.0), (1e300, -3.0), (0.5, 1e308)] },
            TermCurve { name: "ünïcødé\n\t".into(), points: vec![(0.0, 1.0), (1.0, 1.0)] },
        ];
        for range in ranges {
            for (w, h) in [(0, 0), (1, 1), (64, 48), (100, 1000), (3000, 20), (500, 400)] {
                let fig = VariableFigure {
                    title: "a rather long title that will not fit in a tiny image".into(),
                    range,
                    curves: curves.clone(),
                };
                let pm = plot_variable(&fig, w, h);
                assert!(pm.width() >= 64 && pm.height() >= 48);
            }
        }
        let empty = VariableFigure { title: String::new(), range: (0.0, 1.0), curves: vec![] };
        let pm = plot_variable(&empty, 0, 0);
        assert_eq!((pm.width(), pm.height()), (64, 48));
        let pm = plot_variable(&empty, u32::MAX, u32::MAX);
        assert_eq!((pm.width(), pm.height()), (MAX_SIDE, MAX_SIDE));
    }

    #[test]
    fn degenerate_surfaces_do_not_panic() {
        let nan = f64::NAN;
        let cases = vec![
            surface(0, 0, vec![]),
            surface(1, 1, vec![3.0]),
            surface(1, 5, vec![1.0, 2.0]),
            surface(3, 3, vec![nan; 9]),
            surface(3, 3, vec![2.0; 9]),
            surface(2, 2, vec![f64::INFINITY, -f64::INFINITY, 1.0, nan]),
            surface(usize::MAX, 2, vec![1.0]),
            surface(2, 2, vec![1e300, -1e300, 0.0, 1.0]),
            SurfaceFigure { x_range: (nan, 1.0), ..surface(2, 2, vec![0.0; 4]) },
            SurfaceFigure { y_range: (2.0, 2.0), ..surface(2, 2, vec![0.0; 4]) },
            SurfaceFigure { x_range: (1.0, -1.0), y_range: (1e-9, 0.0), ..surface(2, 2, vec![0.0, 1.0, 2.0, 3.0]) },
        ];
        for fig in &cases {
            for (w, h) in [(0, 0), (64, 48), (90, 60), (400, 300)] {
                let pm = plot_surface(fig, w, h);
                assert!(pm.width() >= 64 && pm.height() >= 48);
            }
        }
        let pm = plot_surface(&cases[3], 400, 300);
        assert!(has_colour(&pm, NAN_GREY));
    }

    #[test]
    fn tick_labels_are_tidy() {
        let labels = |lo, hi| -> Vec<String> { tick_labels(lo, hi).into_iter().map(|(_, l)| l).collect() };
        assert_eq!(labels(0.0, 10.0), ["0", "2.5", "5", "7.5", "10"]);
        assert_eq!(labels(-180.0, 180.0), ["-180", "-90", "0", "90", "180"]);
        assert_eq!(labels(0.0, 1.0), ["0", "0.25", "0.5", "0.75", "1"]);
        assert_eq!(labels(-0.3, 0.3), ["-0.3", "-0.15", "0", "0.15", "0.3"]);
        assert_eq!(labels(0.0, 4000.0), ["0", "1000", "2000", "3000", "4000"]);
        assert_eq!(labels(0.0, 4e5), ["0", "1e+05", "2e+05", "3e+05", "4e+05"]);
        assert_eq!(labels(0.0, 255.0), ["0", "50", "100", "150", "200", "250"]);
        assert_eq!(labels(0.0, 7.0), ["0", "2", "4", "6"]);
        assert_eq!(labels(1.0, 1.001).len(), 5);
        assert_eq!(format_value(0.5), "0.5");
        assert_eq!(format_value(-90.0), "-90");
        assert_eq!(format_value(1234.5678), "1235");
        assert_eq!(format_value(0.012345), "0.0123");
        assert_eq!(format_value(2.5e-5), "2.5e-05");
        assert_eq!(format_value(-0.0), "0");
    }

    #[test]
    fn viridis_endpoints() {
        assert_eq!(viridis(0.0), VIRIDIS[0]);
        assert_eq!(viridis(1.0), VIRIDIS[8]);
        assert_eq!(viridis(f64::NAN), VIRIDIS[0]);
        assert_eq!(viridis(0.5), VIRIDIS[4]);
    }
}
