//! PNG frames of the top-down view (seed 000 Fig 2 style): a [`Painter`] backend over a
//! [`tiny_skia::Pixmap`].
//!
//! The picture itself comes from [`draw_scene`], the same routine the terminal UI uses, so a
//! PNG frame and the terminal view always agree; this module only knows how to put antialiased
//! lines, filled polygons and bitmap-font text into pixels. Nothing here touches the file
//! system: [`encode`] returns the PNG bytes and the caller decides where they go.

use glam::DVec2;
use tiny_skia::{Color, FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, Stroke, Transform};

use super::font::{draw_text, text_height, text_width};
use super::scene::{Painter, Rgba, Scene, draw_scene, palette};

/// Largest image side produced, pixels; larger requests are reduced to this.
pub const MAX_SIDE_PX: u32 = 8192;

/// Reads a picture size as a command line gives it, `WIDTHxHEIGHT` (for example `800x600`),
/// each side in 16..=[`MAX_SIDE_PX`] pixels.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("expected WIDTHxHEIGHT, found '{s}'"))?;
    let w: u32 = w.parse().map_err(|_| format!("bad width '{w}'"))?;
    let h: u32 = h.parse().map_err(|_| format!("bad height '{h}'"))?;
    if !(16..=MAX_SIDE_PX).contains(&w) || !(16..=MAX_SIDE_PX).contains(&h) {
        return Err(format!("size {w}x{h} is outside 16..{MAX_SIDE_PX}"));
    }
    Ok((w, h))
}

/// A [`Painter`] drawing into an RGBA pixmap with antialiased strokes and fills and the
/// built-in 5×7 bitmap font for text.
#[derive(Debug, Clone)]
pub struct PngPainter {
    pixmap: Pixmap,
    text_scale: u32,
}

impl PngPainter {
    /// A white `width`×`height` canvas (pixels, each side clamped to 1..=[`MAX_SIDE_PX`]).
    pub fn new(width: u32, height: u32) -> PngPainter {
        let (w, h) = (width.clamp(1, MAX_SIDE_PX), height.clamp(1, MAX_SIDE_PX));
        let mut pixmap = Pixmap::new(w, h).expect("clamped pixmap size is valid");
        let bg = palette::BACKGROUND;
        pixmap.fill(Color::from_rgba8(bg.r, bg.g, bg.b, bg.a));
        PngPainter { pixmap, text_scale: text_scale_for(w, h) }
    }

    /// Integer scale of the bitmap font (1 = 5×7 pixel glyphs); chosen from the image size.
    pub fn text_scale(&self) -> u32 {
        self.text_scale
    }

    /// Sets the integer scale of the bitmap font (0 is treated as 1).
    pub fn set_text_scale(&mut self, scale: u32) {
        self.text_scale = scale.max(1);
    }

    /// The pixels drawn so far.
    pub fn pixmap(&self) -> &Pixmap {
        &self.pixmap
    }

    /// The finished image.
    pub fn into_pixmap(self) -> Pixmap {
        self.pixmap
    }

    fn paint(color: Rgba) -> Paint<'static> {
        let mut paint = Paint::default();
        paint.set_color_rgba8(color.r, color.g, color.b, color.a);
        paint.anti_alias = true;
        paint
    }

    fn stroke_path(&mut self, points: &[DVec2], close: bool, color: Rgba, width_px: f64) {
        if points.len() < 2 || !(width_px.is_finite() && width_px > 0.0) {
            return;
        }
        let mut pb = PathBuilder::new();
        for (i, p) in points.iter().enumerate() {
            let Some((x, y)) = to_f32(*p) else { return };
            if i == 0 { pb.move_to(x, y) } else { pb.line_to(x, y) }
        }
        if close {
            pb.close();
        }
        let Some(path) = pb.finish() else { return };
        let stroke = Stroke {
            width: width_px as f32,
            line_cap: LineCap::Round,
            line_join: LineJoin::Round,
            ..Stroke::default()
        };
        self.pixmap.stroke_path(&path, &Self::paint(color), &stroke, Transform::identity(), None);
    }
}

/// Font scale for an image: 1 below about 520 px on the short side, growing up to 4.
fn text_scale_for(w: u32, h: u32) -> u32 {
    (w.min(h * 4 / 3) / 520 + 1).clamp(1, 4)
}

/// `p` as f32 pixels, if finite after conversion.
fn to_f32(p: DVec2) -> Option<(f32, f32)> {
    let (x, y) = (p.x as f32, p.y as f32);
    (x.is_finite() && y.is_finite()).then_some((x, y))
}

impl Painter for PngPainter {
    fn size(&self) -> (f64, f64) {
        (f64::from(self.pixmap.width()), f64::from(self.pixmap.height()))
    }

    fn line(&mut self, a: DVec2, b: DVec2, color: Rgba, width_px: f64) {
        self.stroke_path(&[a, b], false, color, width_px);
    }

    fn fill_polygon(&mut self, points: &[DVec2], color: Rgba) {
        if points.len() < 3 {
            return;
        }
        let mut pb = PathBuilder::new();
        for (i, p) in points.iter().enumerate() {
            let Some((x, y)) = to_f32(*p) else { return };
            if i == 0 { pb.move_to(x, y) } else { pb.line_to(x, y) }
        }
        pb.close();
        if let Some(path) = pb.finish() {
            self.pixmap.fill_path(&path, &Self::paint(color), FillRule::Winding, Transform::identity(), None);
        }
    }

    fn text(&mut self, at: DVec2, text: &str, color: Rgba) {
        if !at.is_finite() {
            return;
        }
        let x = at.x.round().clamp(-1e9, 1e9) as i32;
        let y = at.y.round().clamp(-1e9, 1e9) as i32;
        let c = Color::from_rgba8(color.r, color.g, color.b, color.a);
        draw_text(&mut self.pixmap, x, y, text, self.text_scale, c);
    }

    fn text_size(&self, text: &str) -> DVec2 {
        DVec2::new(f64::from(text_width(text, self.text_scale)), f64::from(text_height(self.text_scale)))
    }

    fn polyline(&mut self, points: &[DVec2], color: Rgba, width_px: f64) {
        self.stroke_path(points, false, color, width_px);
    }

    fn stroke_polygon(&mut self, points: &[DVec2], color: Rgba, width_px: f64) {
        self.stroke_path(points, points.len() > 2, color, width_px);
    }
}

/// Renders `scene` as a `width`×`height` image (pixels, each side clamped to
/// 1..=[`MAX_SIDE_PX`]) on a white background.
pub fn render_png(scene: &Scene, width: u32, height: u32) -> Pixmap {
    let mut painter = PngPainter::new(width, height);
    draw_scene(scene, &mut painter);
    painter.into_pixmap()
}

/// Encodes `pixmap` as PNG bytes (8-bit RGBA).
pub fn encode(pixmap: &Pixmap) -> Result<Vec<u8>, String> {
    pixmap.encode_png().map_err(|e| format!("PNG encoding failed: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::World;

    #[test]
    fn renders_and_encodes() {
        let world = World::new(Vec::new());
        let scene = Scene {
            world: &world,
            agents: vec![],
            goals: vec![],
            view: None,
            caption: Some("x".into()),
            outcome: None,
            legend: true,
        };
        let pm = render_png(&scene, 64, 48);
        let bytes = encode(&pm).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        assert_eq!(PngPainter::new(100_000, 0).size(), (f64::from(MAX_SIDE_PX), 1.0));
    }
}
