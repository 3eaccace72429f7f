//! The sagittal side view of seed 002 Fig 6 and Fig 8 (a)/(b) (DESIGN.md §4, §6): the ground
//! profile (solid ground filled down to a common floor, gaps left open with a dark band below
//! them, vertical steps as they are), the footholds (each sole a thick line in its foot's
//! colour, with a mark under its centre), and the legs (hip–knee–ankle–heel–toe of both legs)
//! sampled through each swing, earlier poses faded. Left leg blue, right leg red, as in the
//! skeleton strip of [`super::poses`]; the goal is a green line, a stop a vermillion cross over
//! the last foothold.
//!
//! Pure: [`draw_side_view`] draws on any [`Painter`] (the PNG one, or the terminal canvas) and
//! returns the transform it used, so tests can look up the pixel of a profile point.
//! Non-finite coordinates are skipped, never drawn.

use glam::DVec2;
use tiny_skia::Pixmap;

use super::png::{MAX_SIDE_PX, PngPainter};
use super::scene::{Painter, Rgba, palette};
use crate::footstep::{Foot, Foothold, GroundPiece, PlannedStep, Sole, StepPose};

/// Colour of the left leg and its footholds.
pub const LEFT: Rgba = Rgba::rgb(40, 110, 200);
/// Colour of the right leg and its footholds.
pub const RIGHT: Rgba = Rgba::rgb(200, 70, 50);
/// Fill of solid ground.
pub const GROUND_FILL: Rgba = palette::TERRAIN_RAISED;
/// Outline of the ground.
pub const GROUND_EDGE: Rgba = palette::TERRAIN_EDGE;
/// The band marking a gap (no foothold).
pub const GAP: Rgba = palette::TERRAIN_HOLE;

/// Pixels per metre of a side view rendered by [`render_side_view`] (less when the profile
/// would be wider than [`MAX_SIDE_PX`]).
pub const PX_PER_M: f64 = 160.0;
/// Margin around the drawing, pixels.
const MARGIN_PX: f64 = 12.0;
/// Room for the caption at the top, pixels.
const CAPTION_PX: f64 = 14.0;
/// Depth of the ground drawn below its lowest point, metres.
const FLOOR_DEPTH_M: f64 = 0.25;

/// Both legs at one moment of a step, and which foot swings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SideLegs {
    /// The swinging foot.
    pub swinging: Foot,
    /// The legs (profile coordinates: X along the path, Z up).
    pub pose: StepPose,
}

/// Everything a side view shows, in profile coordinates (metres: X along the path, Z up).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SideView {
    /// Solid ground, pieces in increasing X; wherever none covers X there is a gap.
    pub ground: Vec<GroundPiece>,
    /// Footholds in order.
    pub footholds: Vec<Foothold>,
    /// Leg poses, drawn in order (the last one opaque, the others faded).
    pub legs: Vec<SideLegs>,
    /// The goal, if any.
    pub goal_m: Option<f64>,
    /// Foot length, metres (the drawn soles).
    pub foot_length_m: f64,
    /// Whether the walk stopped at the last foothold.
    pub stopped: bool,
    /// Caption at the top left.
    pub caption: Option<String>,
}

impl SideView {
    /// The side view of a walk over `ground`: its footholds, and each step's legs at the
    /// phases `i / poses_per_step` (`i < poses_per_step`) plus the last step's touch-down.
    pub fn of_walk(
        ground: &[GroundPiece],
        footholds: &[Foothold],
        steps: &[PlannedStep],
        poses_per_step: usize,
    ) -> Self {
        let n = poses_per_step.max(1);
        let mut legs = Vec::new();
        for s in steps {
            legs.extend((0..n).map(|i| SideLegs { swinging: s.foot, pose: s.swing.pose_at(i as f64 / n as f64) }));
        }
        if let Some(s) = steps.last() {
            legs.push(SideLegs { swinging: s.foot, pose: s.swing.pose_at(1.0) });
        }
        SideView {
            ground: ground.to_vec(),
            footholds: footholds.to_vec(),
            legs,
            foot_length_m: crate::footstep::FootstepParams::default().leg.foot_length_m(),
            ..SideView::default()
        }
    }

    /// The extent drawn, `(x0, z0)`–`(x1, z1)` metres: the ground, the footholds, the goal and
    /// the legs, with some room above.
    pub fn bounds(&self) -> (DVec2, DVec2) {
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        let mut add = |p: DVec2| {
            if p.is_finite() {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        };
        for g in &self.ground {
            add(DVec2::new(g.x0_m, g.z0_m));
            add(DVec2::new(g.x1_m, g.z1_m));
        }
        for f in &self.footholds {
            add(DVec2::new(f.sole.x_m, f.sole.z_m));
        }
        for l in &self.legs {
            for leg in [l.pose.swing, l.pose.stance] {
                for p in [leg.hip, leg.knee, leg.ankle, leg.heel, leg.toe] {
                    add(p);
                }
            }
        }
        if let Some(g) = self.goal_m.filter(|g| g.is_finite()) {
            lo.x = lo.x.min(g);
            hi.x = hi.x.max(g);
        }
        if !lo.is_finite() || !hi.is_finite() {
            return (DVec2::new(0.0, 0.0), DVec2::new(1.0, 1.0));
        }
        // Room for a standing figure when no legs are drawn, and the floor under the ground.
        let top = if self.legs.is_empty() { hi.y + 1.0 } else { hi.y + 0.15 };
        let half_foot = 0.5 * self.foot_length_m.max(0.0);
        (DVec2::new(lo.x - half_foot - 0.1, lo.y - FLOOR_DEPTH_M), DVec2::new(hi.x + half_foot + 0.1, top))
    }
}

/// Maps profile metres (X right, Z up) to pixels (y down).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SideTransform {
    /// Pixel of the profile origin.
    pub origin_px: DVec2,
    /// Pixels per metre.
    pub scale: f64,
}

impl SideTransform {
    /// The pixel of profile point `p`.
    pub fn to_pixel(&self, p: DVec2) -> DVec2 {
        DVec2::new(self.origin_px.x + p.x * self.scale, self.origin_px.y - p.y * self.scale)
    }
}

/// The transform fitting `view` into a `size` painter, keeping the aspect ratio.
pub fn side_transform(view: &SideView, size: (f64, f64)) -> SideTransform {
    let (lo, hi) = view.bounds();
    let extent = (hi - lo).max(DVec2::splat(1e-3));
    let avail = DVec2::new(size.0 - 2.0 * MARGIN_PX, size.1 - 2.0 * MARGIN_PX - CAPTION_PX).max(DVec2::ONE);
    let scale = (avail.x / extent.x).min(avail.y / extent.y);
    // Centred horizontally, the floor on the bottom margin.
    let used_w = extent.x * scale;
    let origin_px = DVec2::new(MARGIN_PX + 0.5 * (avail.x - used_w) - lo.x * scale, size.1 - MARGIN_PX + lo.y * scale);
    SideTransform { origin_px, scale }
}

fn foot_colour(foot: Foot) -> Rgba {
    match foot {
        Foot::Left => LEFT,
        Foot::Right => RIGHT,
    }
}

/// Draws `view` on `painter`, fitted to its size; returns the transform used.
pub fn draw_side_view(view: &SideView, painter: &mut dyn Painter) -> SideTransform {
    let size = painter.size();
    let t = side_transform(view, size);
    let (lo, hi) = view.bounds();
    let px = |x: f64, z: f64| t.to_pixel(DVec2::new(x, z));
    let floor = lo.y;
    let width = (t.scale / 60.0).clamp(1.0, 4.0);
    // Ground: each piece filled down to the floor; gaps get a dark band at the floor.
    let pieces: Vec<&GroundPiece> =
        view.ground.iter().filter(|g| [g.x0_m, g.z0_m, g.x1_m, g.z1_m].iter().all(|v| v.is_finite())).collect();
    for g in &pieces {
        let poly = [px(g.x0_m, g.z0_m), px(g.x1_m, g.z1_m), px(g.x1_m, floor), px(g.x0_m, floor)];
        painter.fill_polygon(&poly, GROUND_FILL);
    }
    let band = (0.06 * (hi.y - lo.y)).clamp(0.03, FLOOR_DEPTH_M);
    let mut gap_from = lo.x;
    for g in &pieces {
        if g.x0_m > gap_from + 1e-6 {
            painter.fill_polygon(
                &[px(gap_from, floor + band), px(g.x0_m, floor + band), px(g.x0_m, floor), px(gap_from, floor)],
                GAP,
            );
        }
        gap_from = gap_from.max(g.x1_m);
    }
    if hi.x > gap_from + 1e-6 {
        painter.fill_polygon(
            &[px(gap_from, floor + band), px(hi.x, floor + band), px(hi.x, floor), px(gap_from, floor)],
            GAP,
        );
    }
    // Vertical edges only where the ground breaks (a step or a gap), not between pieces that
    // continue each other.
    let meets = |a: &GroundPiece, b: &GroundPiece| (a.x1_m - b.x0_m).abs() < 1e-6 && (a.z1_m - b.z0_m).abs() < 1e-6;
    for (i, g) in pieces.iter().enumerate() {
        painter.line(px(g.x0_m, g.z0_m), px(g.x1_m, g.z1_m), GROUND_EDGE, 1.5 * width);
        if i == 0 || !meets(pieces[i - 1], g) {
            painter.line(px(g.x0_m, g.z0_m), px(g.x0_m, floor), GROUND_EDGE, 1.0);
        }
        if i + 1 == pieces.len() || !meets(g, pieces[i + 1]) {
            painter.line(px(g.x1_m, g.z1_m), px(g.x1_m, floor), GROUND_EDGE, 1.0);
        }
    }
    // The goal.
    if let Some(goal) = view.goal_m.filter(|g| g.is_finite()) {
        painter.line(px(goal, floor), px(goal, hi.y), palette::GOAL, width);
        painter.text(px(goal, hi.y) + DVec2::new(3.0, 0.0), "goal", palette::GOAL);
    }
    // The legs: far (right) leg first, earlier poses faded.
    let last = view.legs.len().saturating_sub(1);
    for (k, l) in view.legs.iter().enumerate() {
        let alpha = if k == last { 255 } else { 70 };
        let mut legs = [(l.swinging, l.pose.swing), (l.swinging.other(), l.pose.stance)];
        legs.sort_by_key(|(f, _)| *f == Foot::Left);
        for (foot, leg) in legs {
            let pts: Vec<DVec2> = [leg.hip, leg.knee, leg.ankle, leg.heel, leg.toe, leg.ankle]
                .iter()
                .filter(|p| p.is_finite())
                .map(|&p| t.to_pixel(p))
                .collect();
            if pts.len() == 6 {
                painter.polyline(
                    &pts,
                    foot_colour(foot).with_alpha(alpha),
                    if k == last { width } else { 0.7 * width },
                );
            }
        }
        if k == last && l.pose.stance.hip.is_finite() {
            painter.fill_circle(t.to_pixel(l.pose.stance.hip), 1.6 * width, palette::TEXT);
        }
    }
    // The footholds: the sole and a mark under its centre.
    let length = view.foot_length_m;
    for f in &view.footholds {
        let s: Sole = f.sole;
        let (heel, toe, c) = (s.heel(length), s.toe(length), DVec2::new(s.x_m, s.z_m));
        if !(heel.is_finite() && toe.is_finite()) {
            continue;
        }
        let colour = foot_colour(f.foot);
        painter.line(t.to_pixel(heel), t.to_pixel(toe), colour, 2.0 * width);
        let m = t.to_pixel(c);
        let r = 2.0 * width + 1.0;
        painter.fill_polygon(
            &[m + DVec2::new(0.0, 1.0), m + DVec2::new(-r, 1.0 + 1.6 * r), m + DVec2::new(r, 1.0 + 1.6 * r)],
            colour,
        );
    }
    if view.stopped
        && let Some(f) = view.footholds.last()
        && f.sole.x_m.is_finite()
    {
        let c = t.to_pixel(DVec2::new(f.sole.x_m + 0.5 * length, f.sole.z_m + 0.25));
        let r = 0.08 * t.scale;
        painter.line(c - DVec2::splat(r), c + DVec2::splat(r), palette::HULL, 1.5 * width);
        painter.line(c + DVec2::new(-r, r), c + DVec2::new(r, -r), palette::HULL, 1.5 * width);
    }
    if let Some(caption) = &view.caption {
        painter.text(DVec2::new(MARGIN_PX, MARGIN_PX - 4.0), caption, palette::TEXT);
    }
    t
}

/// Renders `view` at [`PX_PER_M`] (less when that would be wider than [`MAX_SIDE_PX`]), with
/// its caption; returns the image and the transform used.
pub fn render_side_view(view: &SideView) -> (Pixmap, SideTransform) {
    let (lo, hi) = view.bounds();
    let extent = hi - lo;
    let max = f64::from(MAX_SIDE_PX) - 2.0 * MARGIN_PX;
    let scale = PX_PER_M.min(max / extent.x.max(1e-3)).min(max / extent.y.max(1e-3));
    let w = (extent.x * scale + 2.0 * MARGIN_PX).ceil().max(64.0) as u32;
    let h = (extent.y * scale + 2.0 * MARGIN_PX + CAPTION_PX).ceil().max(48.0) as u32;
    let mut painter = PngPainter::new(w, h);
    painter.set_text_scale(1);
    let t = draw_side_view(view, &mut painter);
    (painter.into_pixmap(), t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::footstep::{FootstepParams, PlannerMode, planner::walk};
    use crate::ground::parse;

    fn colour_at(pm: &Pixmap, p: DVec2) -> (u8, u8, u8) {
        let c = pm.pixel(p.x.round() as u32, p.y.round() as u32).unwrap().demultiply();
        (c.red(), c.green(), c.blue())
    }

    #[test]
    fn ground_is_filled_and_gaps_are_open() {
        let course = parse("start 0\ngoal 2\nground -0.5 0 1 0\nground 1.5 0.2 3 0.2\n", "t.profile").unwrap();
        let view = SideView { ground: course.ground.pieces().to_vec(), foot_length_m: 0.24, ..SideView::default() };
        let (pm, t) = render_side_view(&view);
        let under = |x: f64, z: f64| colour_at(&pm, t.to_pixel(DVec2::new(x, z)));
        let fill = (GROUND_FILL.r, GROUND_FILL.g, GROUND_FILL.b);
        assert_eq!(under(0.5, -0.1), fill);
        assert_eq!(under(2.0, 0.1), fill);
        // Above the gap's floor band it is background.
        assert_eq!(under(1.25, -0.05), (255, 255, 255));
        assert_eq!(under(1.25, view.bounds().0.y + 0.01), (GAP.r, GAP.g, GAP.b));
    }

    #[test]
    fn draws_each_foothold_in_its_foot_colour() {
        let course = parse("start 0\ngoal 2\nground -0.5 0 3 0\n", "t.profile").unwrap();
        let w = walk(&course, FootstepParams::default(), PlannerMode::Window).unwrap();
        let view = SideView::of_walk(course.ground.pieces(), &w.footholds, &w.steps, 4);
        assert_eq!(view.legs.len(), 4 * w.steps.len() + 1);
        let (pm, t) = render_side_view(&view);
        for f in &w.footholds[2..] {
            let c = colour_at(&pm, t.to_pixel(DVec2::new(f.sole.x_m, f.sole.z_m)) + DVec2::new(0.0, 4.0));
            let want = foot_colour(f.foot);
            assert_eq!(c, (want.r, want.g, want.b), "foothold at {}", f.sole.x_m);
        }
    }
}
