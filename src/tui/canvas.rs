//! The terminal backend of [`draw_scene`](crate::render::scene::draw_scene) (DESIGN.md §6):
//! a [`Painter`] that rasterises the scene into a grid of terminal cells, which a ratatui
//! widget then shows.
//!
//! Each cell is 2×4 "dots" (the braille pattern of Unicode's U+2800 block), so the painter's
//! pixel space is `(2·columns, 4·rows)`. Lines set dots and give the cell their colour; filled
//! polygons are scan-converted at dot resolution (non-zero winding, so simple non-convex
//! polygons work) and paint the cell background where they cover at least half of the cell,
//! or, for opaque colours, the covered dots where they cover less. Text is written as whole
//! characters, one cell per character. Translucent colours are blended over what is below.
//!
//! Invariants: painting never panics and never writes outside the grid, whatever the
//! coordinates (non-finite ones are ignored, huge ones clipped).

use glam::DVec2;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::widgets::Widget;

use crate::render::scene::{Painter, Rgba, palette};

/// Dots per cell across.
pub const DOTS_X: usize = 2;
/// Dots per cell down.
pub const DOTS_Y: usize = 4;

/// Braille bit of the dot at column `x` (0–1) and row `y` (0–3) of a cell.
const BRAILLE_BITS: [[u8; 2]; 4] = [[0x01, 0x08], [0x02, 0x10], [0x04, 0x20], [0x40, 0x80]];

/// An opaque colour, red, green, blue.
type Rgb = [u8; 3];

/// One terminal cell of the canvas.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct CanvasCell {
    /// Background colour.
    bg: Rgb,
    /// Braille dots set (bit layout of [`BRAILLE_BITS`]).
    dots: u8,
    /// Colour of the dots (or of the text character).
    fg: Rgb,
    /// A text character, drawn instead of the dots.
    text: Option<char>,
}

/// A grid of terminal cells that [`draw_scene`](crate::render::scene::draw_scene) paints on,
/// shown by rendering `&TermCanvas` as a ratatui [`Widget`].
#[derive(Debug, Clone)]
pub struct TermCanvas {
    cols: usize,
    rows: usize,
    cells: Vec<CanvasCell>,
    /// Per-cell coverage masks of the polygon being filled (scratch).
    coverage: Vec<u8>,
    /// Edge crossings of one scan line (scratch).
    crossings: Vec<(f64, i32)>,
}

fn rgb(c: Rgba) -> Rgb {
    [c.r, c.g, c.b]
}

/// `c` over `below`, by `c`'s alpha.
fn blend(c: Rgba, below: Rgb) -> Rgb {
    let a = u32::from(c.a);
    let mix = |x: u8, y: u8| ((u32::from(x) * a + u32::from(y) * (255 - a) + 127) / 255) as u8;
    [mix(c.r, below[0]), mix(c.g, below[1]), mix(c.b, below[2])]
}

/// How far apart two colours are (sum of channel differences, 0–765).
fn contrast(a: Rgb, b: Rgb) -> u32 {
    a.iter().zip(&b).map(|(&x, &y)| u32::from(x.abs_diff(y))).sum()
}

impl TermCanvas {
    /// A blank canvas of `cols`×`rows` cells on the scene background (white).
    pub fn new(cols: u16, rows: u16) -> TermCanvas {
        let mut c = TermCanvas { cols: 0, rows: 0, cells: Vec::new(), coverage: Vec::new(), crossings: Vec::new() };
        c.reset(cols, rows);
        c
    }

    /// Clears the canvas to the scene background and resizes it to `cols`×`rows` cells.
    pub fn reset(&mut self, cols: u16, rows: u16) {
        self.cols = usize::from(cols);
        self.rows = usize::from(rows);
        let blank = CanvasCell { bg: rgb(palette::BACKGROUND), dots: 0, fg: rgb(palette::TEXT), text: None };
        self.cells.clear();
        self.cells.resize(self.cols * self.rows, blank);
    }

    /// Size in cells, `(columns, rows)`.
    pub fn cells(&self) -> (u16, u16) {
        (self.cols as u16, self.rows as u16)
    }

    /// The painter pixel (dot) at the centre of cell `(col, row)`.
    pub fn cell_center(col: u16, row: u16) -> DVec2 {
        DVec2::new(f64::from(col) * DOTS_X as f64 + 1.0, f64::from(row) * DOTS_Y as f64 + 2.0)
    }

    /// The character cell `(col, row)` shows (a space, a braille pattern or text), for tests.
    pub fn symbol(&self, col: u16, row: u16) -> Option<char> {
        let c = self.cells.get(usize::from(row) * self.cols + usize::from(col))?;
        Some(match (c.text, c.dots) {
            (Some(t), _) => t,
            (None, 0) => ' ',
            (None, d) => char::from_u32(0x2800 + u32::from(d)).unwrap_or(' '),
        })
    }

    /// Background colour of cell `(col, row)` as `(r, g, b)`, for tests.
    pub fn background(&self, col: u16, row: u16) -> Option<(u8, u8, u8)> {
        let c = self.cells.get(usize::from(row) * self.cols + usize::from(col))?;
        Some((c.bg[0], c.bg[1], c.bg[2]))
    }

    fn dot(&mut self, x: i64, y: i64, color: Rgba) {
        if x < 0 || y < 0 {
            return;
        }
        let (x, y) = (x as usize, y as usize);
        let (col, row) = (x / DOTS_X, y / DOTS_Y);
        if col >= self.cols || row >= self.rows {
            return;
        }
        let cell = &mut self.cells[row * self.cols + col];
        let fg = blend(color, cell.bg);
        // A cell has one dot colour: faint dots (grid lines) give way to stronger ones instead
        // of taking their colour.
        if cell.dots != 0 && contrast(fg, cell.bg) > contrast(cell.fg, cell.bg) + 96 {
            cell.dots = 0;
        }
        cell.dots |= BRAILLE_BITS[y % DOTS_Y][x % DOTS_X];
        cell.fg = fg;
        cell.text = None;
    }

    /// Clips `a`–`b` to the dot area grown by one dot (Liang–Barsky); `None` when outside.
    fn clip(&self, a: DVec2, b: DVec2) -> Option<(DVec2, DVec2)> {
        let (w, h) = self.size();
        let (lo, hi) = (DVec2::splat(-1.0), DVec2::new(w + 1.0, h + 1.0));
        let d = b - a;
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for (p, q) in [(-d.x, a.x - lo.x), (d.x, hi.x - a.x), (-d.y, a.y - lo.y), (d.y, hi.y - a.y)] {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
            } else {
                let r = q / p;
                if p < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
            }
        }
        (t0 <= t1).then(|| (a + d * t0, a + d * t1))
    }
}

impl Painter for TermCanvas {
    fn size(&self) -> (f64, f64) {
        ((self.cols * DOTS_X) as f64, (self.rows * DOTS_Y) as f64)
    }

    fn line(&mut self, a: DVec2, b: DVec2, color: Rgba, width_px: f64) {
        if !(a.is_finite() && b.is_finite()) {
            return;
        }
        let Some((a, b)) = self.clip(a, b) else { return };
        let d = b - a;
        let n = d.x.abs().max(d.y.abs()).ceil().max(1.0) as usize;
        // Strokes of two pixels or more get a second row of dots beside the first.
        let thick = width_px >= 1.75;
        let side = if d.x.abs() >= d.y.abs() { (0, 1) } else { (1, 0) };
        for i in 0..=n {
            let p = a + d * (i as f64 / n as f64);
            let (x, y) = (p.x.floor() as i64, p.y.floor() as i64);
            self.dot(x, y, color);
            if thick {
                self.dot(x + side.0, y + side.1, color);
            }
        }
    }

    fn fill_polygon(&mut self, points: &[DVec2], color: Rgba) {
        if points.len() < 3 || points.iter().any(|p| !p.is_finite()) {
            return;
        }
        let (w, h) = self.size();
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for &p in points {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        // Dot rows and cell span touched, clipped to the canvas.
        let y0 = (lo.y - 0.5).ceil().max(0.0);
        let y1 = (hi.y - 0.5).floor().min(h - 1.0);
        let x0 = (lo.x - 0.5).ceil().max(0.0);
        let x1 = (hi.x - 0.5).floor().min(w - 1.0);
        if y0 > y1 || x0 > x1 {
            return;
        }
        let (y0, y1, x0, x1) = (y0 as usize, y1 as usize, x0 as usize, x1 as usize);
        let (c0, c1, r0, r1) = (x0 / DOTS_X, x1 / DOTS_X, y0 / DOTS_Y, y1 / DOTS_Y);
        let span = c1 - c0 + 1;
        self.coverage.clear();
        self.coverage.resize(span * (r1 - r0 + 1), 0);
        let mut crossings = std::mem::take(&mut self.crossings);
        for y in y0..=y1 {
            let yc = y as f64 + 0.5;
            crossings.clear();
            for (i, &p) in points.iter().enumerate() {
                let q = points[(i + 1) % points.len()];
                if (p.y <= yc) != (q.y <= yc) {
                    let x = p.x + (yc - p.y) / (q.y - p.y) * (q.x - p.x);
                    crossings.push((x, if q.y > p.y { 1 } else { -1 }));
                }
            }
            crossings.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut winding = 0;
            for k in 0..crossings.len() {
                winding += crossings[k].1;
                if winding == 0 || k + 1 == crossings.len() {
                    continue;
                }
                // Dots whose centre lies in [start, end).
                let start = (crossings[k].0 - 0.5).ceil().max(x0 as f64);
                let end = ((crossings[k + 1].0 - 0.5).ceil() - 1.0).min(x1 as f64);
                if start > end {
                    continue;
                }
                for x in start as usize..=end as usize {
                    let idx = (y / DOTS_Y - r0) * span + (x / DOTS_X - c0);
                    self.coverage[idx] |= BRAILLE_BITS[y % DOTS_Y][x % DOTS_X];
                }
            }
        }
        self.crossings = crossings;
        let opaque = color.a >= 128;
        for r in r0..=r1 {
            for c in c0..=c1 {
                let mask = self.coverage[(r - r0) * span + (c - c0)];
                if mask == 0 {
                    continue;
                }
                let cell = &mut self.cells[r * self.cols + c];
                if mask.count_ones() >= 4 {
                    cell.bg = blend(color, cell.bg);
                    if opaque {
                        cell.dots &= !mask;
                    }
                } else if opaque && cell.text.is_none() {
                    cell.dots |= mask;
                    cell.fg = blend(color, cell.bg);
                }
            }
        }
    }

    fn text(&mut self, at: DVec2, text: &str, color: Rgba) {
        if !at.is_finite() {
            return;
        }
        let row = (at.y / DOTS_Y as f64).round();
        let col = (at.x / DOTS_X as f64).round();
        if !(0.0..self.rows as f64).contains(&row) {
            return;
        }
        let row = row as usize;
        for (i, ch) in text.chars().enumerate() {
            let c = col + i as f64;
            if !(0.0..self.cols as f64).contains(&c) {
                continue;
            }
            let cell = &mut self.cells[row * self.cols + c as usize];
            cell.text = Some(ch);
            cell.fg = blend(color, cell.bg);
        }
    }

    fn text_size(&self, text: &str) -> DVec2 {
        DVec2::new((text.chars().count() * DOTS_X) as f64, DOTS_Y as f64)
    }
}

impl Widget for &TermCanvas {
    fn render(self, area: Rect, buf: &mut Buffer) {
        let area = area.intersection(buf.area);
        for row in 0..area.height.min(self.rows as u16) {
            for col in 0..area.width.min(self.cols as u16) {
                let c = &self.cells[usize::from(row) * self.cols + usize::from(col)];
                let Some(cell) = buf.cell_mut((area.x + col, area.y + row)) else { continue };
                let ch = match (c.text, c.dots) {
                    (Some(t), _) => t,
                    (None, 0) => ' ',
                    (None, d) => char::from_u32(0x2800 + u32::from(d)).unwrap_or(' '),
                };
                cell.set_char(ch)
                    .set_fg(Color::Rgb(c.fg[0], c.fg[1], c.fg[2]))
                    .set_bg(Color::Rgb(c.bg[0], c.bg[1], c.bg[2]));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BLACK: Rgba = Rgba::rgb(0, 0, 0);

    #[test]
    fn size_is_in_dots() {
        let c = TermCanvas::new(10, 5);
        assert_eq!(c.size(), (20.0, 20.0));
        assert_eq!(c.text_size("abc"), DVec2::new(6.0, 4.0));
    }

    #[test]
    fn horizontal_line_sets_top_dots() {
        let mut c = TermCanvas::new(4, 2);
        c.line(DVec2::new(0.0, 0.0), DVec2::new(7.9, 0.0), BLACK, 1.0);
        for col in 0..4 {
            assert_eq!(c.symbol(col, 0), Some('\u{2809}'));
        }
        assert_eq!(c.symbol(0, 1), Some(' '));
    }

    #[test]
    fn wild_coordinates_are_ignored_or_clipped() {
        let mut c = TermCanvas::new(4, 2);
        c.line(DVec2::new(-1e300, 3.0), DVec2::new(1e300, 3.0), BLACK, 1.0);
        c.line(DVec2::new(f64::NAN, 0.0), DVec2::new(1.0, 1.0), BLACK, 1.0);
        c.fill_polygon(&[DVec2::new(-1e300, -1e300), DVec2::new(1e300, -1e300), DVec2::new(0.0, 1e300)], BLACK);
        c.text(DVec2::new(-100.0, 0.0), "far away", BLACK);
        c.text(DVec2::new(f64::INFINITY, 0.0), "x", BLACK);
        assert_eq!(c.background(3, 1), Some((0, 0, 0)));
    }

    #[test]
    fn non_convex_fill_leaves_the_notch_empty() {
        // A U opening upward, 12×12 cells: the notch (columns 4–7, rows 0–7) stays white.
        let mut c = TermCanvas::new(12, 12);
        let u =
            [(0.0, 0.0), (8.0, 0.0), (8.0, 32.0), (16.0, 32.0), (16.0, 0.0), (24.0, 0.0), (24.0, 48.0), (0.0, 48.0)];
        let pts: Vec<DVec2> = u.iter().map(|&(x, y)| DVec2::new(x, y)).collect();
        c.fill_polygon(&pts, BLACK);
        assert_eq!(c.background(1, 1), Some((0, 0, 0)));
        assert_eq!(c.background(5, 2), Some((255, 255, 255)));
        assert_eq!(c.background(5, 10), Some((0, 0, 0)));
        assert_eq!(c.background(10, 1), Some((0, 0, 0)));
    }

    #[test]
    fn translucent_fill_blends() {
        let mut c = TermCanvas::new(2, 2);
        c.fill_polygon(
            &[DVec2::new(0.0, 0.0), DVec2::new(4.0, 0.0), DVec2::new(4.0, 8.0), DVec2::new(0.0, 8.0)],
            BLACK.with_alpha(128),
        );
        assert_eq!(c.background(0, 0), Some((127, 127, 127)));
    }

    #[test]
    fn text_writes_characters() {
        let mut c = TermCanvas::new(10, 2);
        c.text(DVec2::new(2.0, 4.0), "5 m", BLACK);
        assert_eq!(c.symbol(1, 1), Some('5'));
        assert_eq!(c.symbol(3, 1), Some('m'));
    }
}
