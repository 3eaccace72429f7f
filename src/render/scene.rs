//! Top-down views of the world in the style of seed 000 Fig 2: obstacles with their convex
//! hulls, goals, agents with their starts, trails, footprints and sensor sectors, a metric grid,
//! a scale bar, a caption with the outcome, and a legend of what the picture shows.
//!
//! There is exactly one drawing routine, [`draw_scene`]. It speaks to a tiny [`Painter`]
//! backend (lines, filled polygons, text, all in pixel coordinates), so the PNG frames
//! ([`super::png::PngPainter`]) and the terminal UI draw the same picture from the same code and
//! can never disagree. [`ViewTransform`] maps world metres (y up) to pixels (y down) and back,
//! so a front-end can also turn mouse clicks into world points.
//!
//! Invariants: drawing is a pure function of the [`Scene`] and the painter size; it never
//! panics, and non-finite input (NaN positions, trail points, distances) is skipped rather than
//! handed to the painter.

use std::f64::consts::TAU;

use glam::DVec2;

use crate::geom::{Aabb, Shape};
use crate::world::{ObstacleShape, World};

/// An 8-bit sRGB colour with straight (not premultiplied) alpha.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rgba {
    /// Red, 0–255.
    pub r: u8,
    /// Green, 0–255.
    pub g: u8,
    /// Blue, 0–255.
    pub b: u8,
    /// Opacity, 0 (transparent) – 255 (opaque).
    pub a: u8,
}

impl Rgba {
    /// An opaque colour.
    pub const fn rgb(r: u8, g: u8, b: u8) -> Rgba {
        Rgba { r, g, b, a: 255 }
    }

    /// The same colour with opacity `a` (0–255).
    pub const fn with_alpha(self, a: u8) -> Rgba {
        Rgba { a, ..self }
    }
}

/// The colours of a scene, chosen for a white background and from the Okabe–Ito set so that
/// the categories stay distinguishable with the common forms of colour blindness.
pub mod palette {
    use super::Rgba;

    /// Background the scene is designed for (white).
    pub const BACKGROUND: Rgba = Rgba::rgb(255, 255, 255);
    /// Grid lines every grid step.
    pub const GRID: Rgba = Rgba::rgb(236, 238, 241);
    /// Grid lines through the world axes (x = 0, y = 0).
    pub const GRID_AXIS: Rgba = Rgba::rgb(212, 216, 222);
    /// Interior of obstacle parts.
    pub const OBSTACLE_FILL: Rgba = Rgba::rgb(184, 192, 204);
    /// Outline of obstacles.
    pub const OBSTACLE_OUTLINE: Rgba = Rgba::rgb(62, 70, 84);
    /// Fill of obstacles above the legs (overhead bars, shelves), which the legs walk under.
    pub const OVERHEAD_FILL: Rgba = Rgba::rgb(184, 192, 204).with_alpha(90);
    /// Seams between the convex parts of a non-convex obstacle.
    pub const OBSTACLE_SEAM: Rgba = Rgba::rgb(150, 159, 173);
    /// Convex hull of a non-convex obstacle (vermillion).
    pub const HULL: Rgba = Rgba::rgb(213, 94, 0);
    /// Goal discs and crosses (bluish green).
    pub const GOAL: Rgba = Rgba::rgb(0, 158, 115);
    /// Path already walked (blue).
    pub const TRAIL: Rgba = Rgba::rgb(0, 114, 178);
    /// Agent disc (orange).
    pub const AGENT: Rgba = Rgba::rgb(230, 159, 0);
    /// Agent disc outline.
    pub const AGENT_OUTLINE: Rgba = Rgba::rgb(120, 80, 0);
    /// Heading line (black).
    pub const HEADING: Rgba = Rgba::rgb(0, 0, 0);
    /// Sensor sector wedges (sky blue); filled with [`SENSOR_ALPHA`].
    pub const SENSOR: Rgba = Rgba::rgb(86, 180, 233);
    /// Opacity of the sensor wedge fill.
    pub const SENSOR_ALPHA: u8 = 56;
    /// Terrain raised above the ground (platforms, slopes, stairs, low obstacles; sand).
    pub const TERRAIN_RAISED: Rgba = Rgba::rgb(226, 212, 180);
    /// Outline of terrain features and the edges of stair treads.
    pub const TERRAIN_EDGE: Rgba = Rgba::rgb(150, 128, 90);
    /// Holes in the ground: no foothold (dark blue-grey).
    pub const TERRAIN_HOLE: Rgba = Rgba::rgb(70, 90, 120);
    /// Footprints (reddish purple).
    pub const FOOTPRINT: Rgba = Rgba::rgb(204, 121, 167);
    /// Outline of the start marker (a square, filled with the background).
    pub const START: Rgba = Rgba::rgb(25, 25, 25);
    /// An outcome that reached the goal cleanly (the goal's bluish green, darkened for text).
    pub const SUCCESS: Rgba = Rgba::rgb(0, 120, 88);
    /// An outcome that did not (vermillion).
    pub const FAILURE: Rgba = Rgba::rgb(213, 94, 0);
    /// Labels, caption and scale bar.
    pub const TEXT: Rgba = Rgba::rgb(25, 25, 25);
}

/// A drawing backend in pixel coordinates: x to the right, y down, origin at the top-left
/// corner, one unit per pixel (or per terminal sub-cell dot).
///
/// Only [`line`](Painter::line), [`fill_polygon`](Painter::fill_polygon) and
/// [`text`](Painter::text) must be implemented; polylines, polygon outlines and circles have
/// default implementations on top of them that a backend may override for nicer joins.
/// Callers never pass non-finite coordinates.
pub trait Painter {
    /// Drawing area `(width, height)`, pixels.
    fn size(&self) -> (f64, f64);

    /// A straight line from `a` to `b` (pixels) of width `width_px`.
    fn line(&mut self, a: DVec2, b: DVec2, color: Rgba, width_px: f64);

    /// Fills the simple polygon `points` (pixels, either orientation, implicitly closed; may be
    /// non-convex).
    fn fill_polygon(&mut self, points: &[DVec2], color: Rgba);

    /// Writes `text` with the top-left corner of its first glyph at `at` (pixels).
    fn text(&mut self, at: DVec2, text: &str, color: Rgba);

    /// Size `(width, height)` in pixels that [`text`](Painter::text) covers for `text`. The
    /// default is the 5×7 bitmap font at scale 1 (6 pixels per character).
    fn text_size(&self, text: &str) -> DVec2 {
        let n = text.chars().count() as f64;
        DVec2::new((6.0 * n - 1.0).max(0.0), 7.0)
    }

    /// Connected line segments through `points` (pixels).
    fn polyline(&mut self, points: &[DVec2], color: Rgba, width_px: f64) {
        for w in points.windows(2) {
            self.line(w[0], w[1], color, width_px);
        }
    }

    /// The closed outline of `points` (pixels).
    fn stroke_polygon(&mut self, points: &[DVec2], color: Rgba, width_px: f64) {
        if points.len() < 2 {
            return;
        }
        self.polyline(points, color, width_px);
        if points.len() > 2 {
            self.line(points[points.len() - 1], points[0], color, width_px);
        }
    }

    /// A circle outline around `center` of `radius_px` pixels, as a polygon whose segment count
    /// grows with the radius.
    fn circle(&mut self, center: DVec2, radius_px: f64, color: Rgba, width_px: f64) {
        let pts = circle_points(center, radius_px);
        self.stroke_polygon(&pts, color, width_px);
    }

    /// A filled disc around `center` of `radius_px` pixels.
    fn fill_circle(&mut self, center: DVec2, radius_px: f64, color: Rgba) {
        let pts = circle_points(center, radius_px);
        self.fill_polygon(&pts, color);
    }

    /// A small round marker (radius 2 pixels) at `at`.
    fn dot(&mut self, at: DVec2, color: Rgba) {
        self.fill_circle(at, 2.0, color);
    }
}

/// Points of a regular polygon approximating a circle: about one vertex per 3 pixels of
/// circumference, between 8 and 512 vertices.
fn circle_points(center: DVec2, radius_px: f64) -> Vec<DVec2> {
    let r = if radius_px.is_finite() { radius_px.max(0.0) } else { 0.0 };
    let n = (TAU * r / 3.0).ceil().clamp(8.0, 512.0) as usize;
    (0..n).map(|i| center + DVec2::from_angle(TAU * i as f64 / n as f64) * r).collect()
}

/// How to draw one agent.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AgentView {
    /// Centre of the agent's disc, metres. A non-finite position hides the agent.
    pub position: DVec2,
    /// Heading, radians counter-clockwise from +x.
    pub yaw: f64,
    /// Disc radius, metres.
    pub radius: f64,
    /// Positions walked so far, oldest first, metres; non-finite points break the line.
    pub trail: Vec<DVec2>,
    /// Sensor sectors: `(edges, free, range)` with `n + 1` ascending edge angles in radians
    /// relative to the heading, `n` free distances in metres measured from the disc (as in
    /// [`crate::world::Sensed::sectors`]), and the sensing range in metres.
    pub sectors: Option<(Vec<f64>, Vec<f64>, f64)>,
    /// Footprints: centre (metres) and yaw (radians) of each foot placement.
    pub footprints: Vec<(DVec2, f64)>,
    /// The body walks (the animated character): the legend lists footprints whether or not
    /// any are drawn yet.
    pub walks: bool,
    /// Where the agent started, metres (drawn as a square).
    pub start: Option<DVec2>,
    /// Text written next to the agent.
    pub label: Option<String>,
}

/// How the episode a scene shows ended, written after its caption.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Verdict {
    /// What happened ("goal reached, path 18.27 m", "timed out, 4.37 m from the goal").
    pub text: String,
    /// The goal was reached cleanly (written in green, otherwise in vermillion).
    pub success: bool,
}

/// Everything [`draw_scene`] draws. Plain data, built fresh for each frame.
#[derive(Debug, Clone)]
pub struct Scene<'a> {
    /// Obstacles (and their hulls) to draw.
    pub world: &'a World,
    /// Agents, drawn in order (later ones on top).
    pub agents: Vec<AgentView>,
    /// Goals: centre and radius, metres.
    pub goals: Vec<(DVec2, f64)>,
    /// World region to show, metres. `None` fits the world bounds, goals, agents (with their
    /// sensor reach), trails and footprints with a margin ([`Scene::auto_view`]).
    pub view: Option<Aabb>,
    /// Text written centred at the top.
    pub caption: Option<String>,
    /// How the episode ended, once it has: written after the caption.
    pub outcome: Option<Verdict>,
    /// A legend of what the picture shows, in a band along the bottom (the PNG frames; the
    /// terminal view has its own panels).
    pub legend: bool,
}

/// Length of a drawn footprint, metres.
pub const FOOT_LENGTH_M: f64 = 0.26;
/// Width of a drawn footprint, metres.
pub const FOOT_WIDTH_M: f64 = 0.10;
/// Margin added around the fitted region when [`Scene::view`] is `None`, metres.
pub const AUTO_MARGIN_M: f64 = 0.5;

impl Scene<'_> {
    /// The same scene drawn over `world` (another copy of the same world, kept longer).
    pub fn in_world(self, world: &World) -> Scene<'_> {
        let Scene { world: _, agents, goals, view, caption, outcome, legend } = self;
        Scene { world, agents, goals, view, caption, outcome, legend }
    }

    /// The region [`draw_scene`] shows when [`Scene::view`] is `None`: the bounding box of the
    /// world, goals, agents with their sensor reach, trails and footprints, grown by
    /// [`AUTO_MARGIN_M`], metres. A scene with nothing in it shows 10 m × 10 m around the origin.
    pub fn auto_view(&self) -> Aabb {
        let mut acc: Option<Aabb> = self.world.bounds().filter(|b| b.min.is_finite() && b.max.is_finite());
        let mut add = |b: Aabb| {
            if b.min.is_finite() && b.max.is_finite() {
                acc = Some(acc.map_or(b, |a| a.union(&b)));
            }
        };
        for &(c, r) in &self.goals {
            add(Aabb::around(c, finite_len(r)));
        }
        for a in &self.agents {
            let reach = a.sectors.as_ref().map_or(0.0, |(_, free, range)| {
                free.iter().copied().filter(|d| d.is_finite()).fold(0.0, f64::max).min(finite_len(*range))
            });
            add(Aabb::around(a.position, finite_len(a.radius) + reach));
            if let Some(start) = a.start {
                add(Aabb::around(start, finite_len(a.radius)));
            }
            for &p in &a.trail {
                add(Aabb::around(p, 0.0));
            }
            for &(p, _) in &a.footprints {
                add(Aabb::around(p, FOOT_LENGTH_M / 2.0));
            }
        }
        match acc {
            Some(b) => b.expanded(AUTO_MARGIN_M),
            None => Aabb::around(DVec2::ZERO, 5.0),
        }
    }
}

/// A finite non-negative length, 0 otherwise.
fn finite_len(v: f64) -> f64 {
    if v.is_finite() { v.max(0.0) } else { 0.0 }
}

/// Uniform world → pixel mapping: metres are square, world y points up, pixel y points down.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewTransform {
    /// Pixels per metre (finite, positive).
    scale: f64,
    /// World point shown at `pixel_center`, metres.
    world_center: DVec2,
    /// Pixel the world centre maps to.
    pixel_center: DVec2,
}

impl ViewTransform {
    /// Fits `view` (metres) into a `size` = `(width, height)` pixel area leaving `margin_px`
    /// pixels on every side, keeping the aspect ratio and centring the view.
    pub fn from_view(view: Aabb, size: (f64, f64), margin_px: f64) -> ViewTransform {
        let m = finite_len(margin_px);
        let (w, h) = (finite_len(size.0), finite_len(size.1));
        ViewTransform::fit(view, DVec2::new(m, m), DVec2::new(w - m, h - m))
    }

    /// Fits `view` (metres) into the pixel rectangle from `min_px` (top-left) to `max_px`
    /// (bottom-right), keeping the aspect ratio and centring the view.
    ///
    /// Degenerate input still gives a usable transform: a zero-size view is shown as 1 m
    /// across (or its non-zero side decides the scale), a non-finite view is replaced by a
    /// 10 m box around the origin, and an empty rectangle is treated as 1 pixel wide.
    pub fn fit(view: Aabb, min_px: DVec2, max_px: DVec2) -> ViewTransform {
        let view = if view.min.is_finite() && view.max.is_finite() { view } else { Aabb::around(DVec2::ZERO, 5.0) };
        let lo = view.min.min(view.max);
        let hi = view.min.max(view.max);
        let extent = hi - lo;
        let (min_px, max_px) =
            if min_px.is_finite() && max_px.is_finite() { (min_px, max_px) } else { (DVec2::ZERO, DVec2::ONE) };
        let avail = (max_px - min_px).max(DVec2::ONE);
        let tiny = 1e-9;
        let scale = match (extent.x > tiny, extent.y > tiny) {
            (true, true) => (avail.x / extent.x).min(avail.y / extent.y),
            (true, false) => avail.x / extent.x,
            (false, true) => avail.y / extent.y,
            (false, false) => avail.x.min(avail.y),
        };
        let scale = if scale.is_finite() && scale > 0.0 { scale.clamp(1e-12, 1e12) } else { 1.0 };
        ViewTransform { scale, world_center: (lo + hi) * 0.5, pixel_center: (min_px + max_px) * 0.5 }
    }

    /// Pixels per metre.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The pixel (x right, y down) showing world point `p` (metres).
    pub fn to_pixel(&self, p: DVec2) -> DVec2 {
        let d = (p - self.world_center) * self.scale;
        DVec2::new(self.pixel_center.x + d.x, self.pixel_center.y - d.y)
    }

    /// The world point (metres) shown at pixel `px`; the inverse of [`ViewTransform::to_pixel`].
    pub fn to_world(&self, px: DVec2) -> DVec2 {
        let d = px - self.pixel_center;
        self.world_center + DVec2::new(d.x, -d.y) / self.scale
    }

    /// A length of `metres` in pixels.
    pub fn length_to_pixels(&self, metres: f64) -> f64 {
        metres * self.scale
    }

    /// The world region (metres) covered by a `size` = `(width, height)` pixel area.
    pub fn visible_world(&self, size: (f64, f64)) -> Aabb {
        let a = self.to_world(DVec2::new(0.0, size.1));
        let b = self.to_world(DVec2::new(size.0, 0.0));
        Aabb::new(a.min(b), a.max(b))
    }
}

/// Maps world point `p` (metres) to pixels with `transform`; see [`ViewTransform::to_pixel`].
pub fn world_to_pixel(transform: &ViewTransform, p: DVec2) -> DVec2 {
    transform.to_pixel(p)
}

/// The transform [`draw_scene`] uses for `scene` on a painter of `size` pixels: the view (or
/// [`Scene::auto_view`]) fitted below the caption line (and with a legend, the outcome's line
/// under it, kept whether or not the episode has ended, so all its frames are framed alike) and
/// above the legend's band, with a margin for the scale bar.
pub fn scene_transform(scene: &Scene, size: (f64, f64), text_height_px: f64) -> ViewTransform {
    let view = scene.view.unwrap_or_else(|| scene.auto_view());
    let (w, h) = (finite_len(size.0), finite_len(size.1));
    let th = finite_len(text_height_px);
    let pad = (th * 0.75).max(4.0).min(w.min(h) * 0.1);
    let legend = Legend::of(scene, (w, h), th);
    let lines = if legend.is_some() {
        2.0
    } else if scene.caption.is_some() || scene.outcome.is_some() {
        1.0
    } else {
        0.0
    };
    let top = pad + lines * (th + pad);
    let band = legend.map_or(0.0, |l| l.height);
    ViewTransform::fit(view, DVec2::new(pad, top.min(h * 0.3)), DVec2::new(w - pad, h - pad - band))
}

/// What a legend entry shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Key {
    Agent,
    Goal,
    Start,
    Trail,
    Footprints,
    Sensors,
    Obstacle,
    Hull,
    Overhead,
    Raised,
    Hole,
}

impl Key {
    fn label(self) -> &'static str {
        match self {
            Key::Agent => "agent, heading",
            Key::Goal => "goal",
            Key::Start => "start",
            Key::Trail => "path walked",
            Key::Footprints => "footsteps",
            Key::Sensors => "sensor sectors",
            Key::Obstacle => "obstacle",
            Key::Hull => "convex hull",
            Key::Overhead => "overhead (walked under)",
            Key::Raised => "raised ground",
            Key::Hole => "hole",
        }
    }
}

/// The legend of a scene laid out in rows along the bottom of the picture.
#[derive(Debug, Clone, PartialEq)]
struct Legend {
    /// Each entry and the left edge of its swatch, pixels, by row.
    rows: Vec<Vec<(Key, f64)>>,
    /// Height of the band, pixels.
    height: f64,
    /// Height of a row, pixels.
    row: f64,
    /// Width of a swatch, pixels.
    swatch: f64,
}

/// A legend shows only in pictures at least this wide and high, pixels.
const LEGEND_MIN_SIDE_PX: f64 = 160.0;

impl Legend {
    /// The legend of `scene` on a picture of `size` whose text is `th` pixels high: the entries
    /// its world and agents can show (what the world holds and what can move, whether or not it
    /// has yet: so every frame of an episode has the same legend and the same framing), in rows
    /// that fit the width. `None` when the scene asks for none or the picture is too small.
    fn of(scene: &Scene, size: (f64, f64), th: f64) -> Option<Legend> {
        use crate::world::terrain::FeatureKind;
        let (w, h) = size;
        if !scene.legend || w < LEGEND_MIN_SIDE_PX || h < LEGEND_MIN_SIDE_PX || th <= 0.0 {
            return None;
        }
        let world = scene.world;
        let agents = !scene.agents.is_empty();
        let features = world.terrain.features();
        let keys = [
            (Key::Agent, agents),
            (Key::Goal, !scene.goals.is_empty()),
            (Key::Start, scene.agents.iter().any(|a| a.start.is_some())),
            (Key::Trail, agents),
            (Key::Footprints, scene.agents.iter().any(|a| a.walks || !a.footprints.is_empty())),
            (Key::Sensors, scene.agents.iter().any(|a| a.sectors.is_some())),
            (Key::Obstacle, !world.obstacles().is_empty()),
            (Key::Hull, world.obstacles().iter().any(|o| o.parts.len() > 1)),
            (Key::Overhead, !world.overhead.is_empty()),
            (Key::Raised, features.iter().any(|f| f.kind != FeatureKind::Hole)),
            (Key::Hole, features.iter().any(|f| f.kind == FeatureKind::Hole)),
        ];
        // The bitmap font advances 6 pixels of every 7 of its height per character.
        let text_w = |t: &str| (6.0 * t.chars().count() as f64 - 1.0) * th / 7.0;
        let pad = (th * 0.75).max(4.0);
        let (swatch, gap, spacing) = (th * 2.4, th * 0.6, th * 1.6);
        let mut rows: Vec<Vec<(Key, f64)>> = vec![Vec::new()];
        let mut x = pad;
        for (key, shown) in keys {
            if !shown {
                continue;
            }
            let width = swatch + gap + text_w(key.label());
            if x > pad && x + width > w - pad {
                rows.push(Vec::new());
                x = pad;
            }
            rows.last_mut()?.push((key, x));
            x += width + spacing;
        }
        let row = th * 1.8;
        let height = rows.len() as f64 * row + pad;
        (height <= h * 0.3).then_some(Legend { rows, height, row, swatch })
    }
}

/// Draws `scene` onto `painter`, fitted to the painter's size.
///
/// Drawing order (later on top): grid lines every 1 m or 5 m (coarser when zoomed out),
/// terrain features in their order (raised ground in sand with its outline and stair tread
/// edges, holes in dark blue-grey), obstacle parts filled and outlined, the convex hull of non-convex obstacles (thin dashed),
/// obstacles above the legs (overhead bars, shelves) filled translucent and outlined,
/// goal discs with a cross, trails, footprints, sensor sector wedges (from the agent's disc to
/// the sensed free distance, translucent), start markers, agent discs with heading lines, agent
/// labels, a scale bar in the bottom-left corner of the view, the caption and the outcome centred
/// at the top, and the legend in a band along the bottom.
pub fn draw_scene(scene: &Scene, painter: &mut dyn Painter) {
    let size = painter.size();
    let size = (finite_len(size.0), finite_len(size.1));
    let th = painter.text_size("M").y;
    let tf = scene_transform(scene, size, th);
    let legend = Legend::of(scene, size, th);
    let bottom = size.1 - legend.as_ref().map_or(0.0, |l| l.height);
    let mut d = Drawer { p: painter, tf, size, bottom };
    d.grid();
    for f in scene.world.terrain.features() {
        d.terrain(f);
    }
    for o in scene.world.obstacles() {
        d.obstacle(o, palette::OBSTACLE_FILL);
    }
    for o in &scene.world.overhead {
        d.obstacle(o, palette::OVERHEAD_FILL);
    }
    for &(c, r) in &scene.goals {
        d.goal(c, r);
    }
    let agents: Vec<&AgentView> = scene.agents.iter().filter(|a| a.position.is_finite()).collect();
    for a in &agents {
        d.trail(&a.trail);
    }
    for a in &agents {
        if let Some(start) = a.start {
            d.start(start, a.radius);
        }
    }
    for a in &agents {
        for &(c, yaw) in &a.footprints {
            d.footprint(c, yaw);
        }
    }
    for a in &agents {
        if let Some((edges, free, range)) = &a.sectors {
            d.sectors(a, edges, free, *range);
        }
    }
    for a in &agents {
        d.agent(a);
    }
    for a in &agents {
        if let Some(label) = &a.label {
            d.label(a, label);
        }
    }
    d.scale_bar();
    if scene.caption.is_some() || scene.outcome.is_some() {
        d.caption(scene.caption.as_deref(), scene.outcome.as_ref(), legend.is_some());
    }
    if let Some(legend) = &legend {
        d.legend(legend, th);
    }
}

/// Pixel widths of the strokes.
const THIN_PX: f64 = 1.0;
const OUTLINE_PX: f64 = 1.5;
const TRAIL_PX: f64 = 2.0;

/// Smallest on-screen spacing of grid lines, pixels.
const MIN_GRID_PX: f64 = 10.0;

/// Whether `a`–`b` (either direction) is an edge of the closed `outline`; such hull edges are
/// already drawn as the obstacle's boundary.
fn is_outline_edge(outline: &[DVec2], a: DVec2, b: DVec2) -> bool {
    let n = outline.len();
    let near = |p: DVec2, q: DVec2| p.distance_squared(q) <= 1e-18;
    (0..n).any(|i| {
        let (p, q) = (outline[i], outline[(i + 1) % n]);
        (near(p, a) && near(q, b)) || (near(p, b) && near(q, a))
    })
}

/// Draws the parts of a scene with one transform.
struct Drawer<'p> {
    p: &'p mut dyn Painter,
    tf: ViewTransform,
    size: (f64, f64),
    /// The bottom of the view's area (the legend's band lies below), pixels.
    bottom: f64,
}

impl Drawer<'_> {
    fn px(&self, p: DVec2) -> DVec2 {
        self.tf.to_pixel(p)
    }

    fn px_all(&self, pts: &[DVec2]) -> Option<Vec<DVec2>> {
        let v: Vec<DVec2> = pts.iter().map(|&p| self.px(p)).collect();
        v.iter().all(|p| p.is_finite()).then_some(v)
    }

    fn grid(&mut self) {
        let s = self.tf.scale();
        let Some(step) = [1.0, 5.0, 10.0, 50.0, 100.0, 500.0, 1000.0].into_iter().find(|st| st * s >= MIN_GRID_PX)
        else {
            return;
        };
        let vis = self.tf.visible_world(self.size);
        let (w, h) = self.size;
        let first_x = (vis.min.x / step).ceil();
        let first_y = (vis.min.y / step).ceil();
        let nx = ((vis.max.x / step).floor() - first_x + 1.0).clamp(0.0, 4000.0) as i64;
        let ny = ((vis.max.y / step).floor() - first_y + 1.0).clamp(0.0, 4000.0) as i64;
        for i in 0..nx {
            let x = (first_x + i as f64) * step;
            let color = if x == 0.0 { palette::GRID_AXIS } else { palette::GRID };
            let px = self.px(DVec2::new(x, 0.0)).x;
            self.p.line(DVec2::new(px, 0.0), DVec2::new(px, h), color, THIN_PX);
        }
        for j in 0..ny {
            let y = (first_y + j as f64) * step;
            let color = if y == 0.0 { palette::GRID_AXIS } else { palette::GRID };
            let py = self.px(DVec2::new(0.0, y)).y;
            self.p.line(DVec2::new(0.0, py), DVec2::new(w, py), color, THIN_PX);
        }
    }

    fn terrain(&mut self, f: &crate::world::terrain::TerrainFeature) {
        use crate::world::terrain::FeatureKind;
        let fill = if f.kind == FeatureKind::Hole { palette::TERRAIN_HOLE } else { palette::TERRAIN_RAISED };
        for part in f.parts() {
            match part {
                Shape::Polygon(poly) => {
                    if let Some(pts) = self.px_all(poly.vertices()) {
                        self.p.fill_polygon(&pts, fill);
                    }
                }
                Shape::Circle { center, radius } => {
                    let c = self.px(*center);
                    let r = self.tf.length_to_pixels(*radius);
                    if c.is_finite() && r.is_finite() {
                        self.p.fill_circle(c, r, fill);
                    }
                }
            }
            self.shape_outline(part, palette::TERRAIN_EDGE, THIN_PX);
        }
        if let (FeatureKind::Stairs { treads, .. }, ObstacleShape::Box { center, width, height, yaw }) =
            (f.kind, &f.shape)
        {
            let (ax, ay) = (DVec2::from_angle(*yaw), DVec2::from_angle(*yaw).perp());
            for k in 1..treads.min(200) {
                let s = -0.5 * width + width * k as f64 / treads as f64;
                let (a, b) = (*center + ax * s - ay * 0.5 * height, *center + ax * s + ay * 0.5 * height);
                let (a, b) = (self.px(a), self.px(b));
                if a.is_finite() && b.is_finite() {
                    self.p.line(a, b, palette::TERRAIN_EDGE, THIN_PX);
                }
            }
        }
    }

    fn obstacle(&mut self, o: &crate::world::Obstacle, fill: Rgba) {
        for part in &o.parts {
            match part {
                Shape::Polygon(poly) => {
                    if let Some(pts) = self.px_all(poly.vertices()) {
                        self.p.fill_polygon(&pts, fill);
                        if o.parts.len() > 1 {
                            self.p.stroke_polygon(&pts, palette::OBSTACLE_SEAM, THIN_PX);
                        }
                    }
                }
                Shape::Circle { center, radius } => {
                    let c = self.px(*center);
                    let r = self.tf.length_to_pixels(*radius);
                    if c.is_finite() && r.is_finite() {
                        self.p.fill_circle(c, r, fill);
                    }
                }
            }
        }
        // The true boundary: the outline given for polygons, else the single part's outline.
        match (&o.shape, o.parts.as_slice()) {
            (ObstacleShape::Polygon { outline }, _) => {
                if let Some(pts) = self.px_all(outline) {
                    self.p.stroke_polygon(&pts, palette::OBSTACLE_OUTLINE, OUTLINE_PX);
                }
            }
            (_, parts) => {
                for part in parts {
                    self.shape_outline(part, palette::OBSTACLE_OUTLINE, OUTLINE_PX);
                }
            }
        }
        if o.parts.len() > 1
            && let Shape::Polygon(hull) = &o.hull
        {
            let outline: &[DVec2] = match &o.shape {
                ObstacleShape::Polygon { outline } => outline,
                _ => &[],
            };
            let hv = hull.vertices();
            for (i, &a) in hv.iter().enumerate() {
                let b = hv[(i + 1) % hv.len()];
                if !is_outline_edge(outline, a, b) {
                    let (pa, pb) = (self.px(a), self.px(b));
                    if pa.is_finite() && pb.is_finite() {
                        self.dashed(pa, pb, palette::HULL, OUTLINE_PX, 6.0, 4.0);
                    }
                }
            }
        }
    }

    fn shape_outline(&mut self, shape: &Shape, color: Rgba, width: f64) {
        match shape {
            Shape::Polygon(poly) => {
                if let Some(pts) = self.px_all(poly.vertices()) {
                    self.p.stroke_polygon(&pts, color, width);
                }
            }
            Shape::Circle { center, radius } => {
                let c = self.px(*center);
                let r = self.tf.length_to_pixels(*radius);
                if c.is_finite() && r.is_finite() {
                    self.p.circle(c, r, color, width);
                }
            }
        }
    }

    /// A dashed line: `dash` pixels drawn, `gap` pixels skipped, at most 2000 dashes.
    fn dashed(&mut self, a: DVec2, b: DVec2, color: Rgba, width: f64, dash: f64, gap: f64) {
        let len = a.distance(b);
        if !len.is_finite() || len <= 0.0 {
            return;
        }
        let dir = (b - a) / len;
        let period = (dash + gap).max(len / 2000.0);
        let mut t = 0.0;
        while t < len {
            let e = (t + dash).min(len);
            self.p.line(a + dir * t, a + dir * e, color, width);
            t += period;
        }
    }

    fn goal(&mut self, c: DVec2, r: f64) {
        let pc = self.px(c);
        if !pc.is_finite() {
            return;
        }
        let rp = self.tf.length_to_pixels(finite_len(r));
        if rp >= 1.0 {
            self.p.fill_circle(pc, rp, palette::GOAL.with_alpha(48));
            self.p.circle(pc, rp, palette::GOAL, OUTLINE_PX);
        }
        let arm = (rp * 0.6).max(4.0);
        self.p.line(pc - DVec2::new(arm, arm), pc + DVec2::new(arm, arm), palette::GOAL, 2.0);
        self.p.line(pc - DVec2::new(arm, -arm), pc + DVec2::new(arm, -arm), palette::GOAL, 2.0);
    }

    fn trail(&mut self, trail: &[DVec2]) {
        let pts: Vec<Option<DVec2>> = trail.iter().map(|&p| Some(self.px(p)).filter(|q| q.is_finite())).collect();
        for run in pts.split(Option::is_none) {
            let run: Vec<DVec2> = run.iter().flatten().copied().collect();
            self.p.polyline(&run, palette::TRAIL, TRAIL_PX);
        }
    }

    fn footprint(&mut self, c: DVec2, yaw: f64) {
        if !(c.is_finite() && yaw.is_finite()) {
            return;
        }
        let fwd = DVec2::from_angle(yaw) * (FOOT_LENGTH_M / 2.0);
        let side = DVec2::from_angle(yaw).perp() * (FOOT_WIDTH_M / 2.0);
        let corners = [c + fwd + side, c - fwd + side, c - fwd - side, c + fwd - side];
        if let Some(pts) = self.px_all(&corners) {
            self.p.fill_polygon(&pts, palette::FOOTPRINT.with_alpha(110));
            self.p.stroke_polygon(&pts, palette::FOOTPRINT, THIN_PX);
        }
    }

    fn sectors(&mut self, a: &AgentView, edges: &[f64], free: &[f64], range: f64) {
        if !a.yaw.is_finite() {
            return;
        }
        let r = finite_len(a.radius);
        let range = finite_len(range);
        for (k, w) in edges.windows(2).enumerate() {
            let (lo, hi) = (w[0], w[1]);
            if !(lo.is_finite() && hi.is_finite() && lo < hi && hi - lo < TAU) {
                continue;
            }
            let Some(&gap) = free.get(k) else { break };
            let gap = if gap.is_finite() { gap.clamp(0.0, range) } else { range };
            let outer = r + gap;
            let inner_px = self.tf.length_to_pixels(r);
            let outer_px = self.tf.length_to_pixels(outer);
            let n = (((hi - lo) * outer_px / 4.0).ceil() as usize).clamp(2, 256);
            let ang = |i: usize| a.yaw + lo + (hi - lo) * i as f64 / n as f64;
            let mut wedge: Vec<DVec2> = (0..=n).map(|i| a.position + DVec2::from_angle(ang(i)) * r).collect();
            wedge.extend((0..=n).rev().map(|i| a.position + DVec2::from_angle(ang(i)) * outer));
            let Some(pts) = self.px_all(&wedge) else { continue };
            if outer_px - inner_px >= 0.5 {
                self.p.fill_polygon(&pts, palette::SENSOR.with_alpha(palette::SENSOR_ALPHA));
            }
            self.p.stroke_polygon(&pts, palette::SENSOR, THIN_PX);
        }
    }

    fn agent(&mut self, a: &AgentView) {
        let c = self.px(a.position);
        let rp = self.tf.length_to_pixels(finite_len(a.radius)).max(3.0);
        if !(c.is_finite() && rp.is_finite()) {
            return;
        }
        self.p.fill_circle(c, rp, palette::AGENT);
        self.p.circle(c, rp, palette::AGENT_OUTLINE, OUTLINE_PX);
        if a.yaw.is_finite() {
            let tip = c + DVec2::new(a.yaw.cos(), -a.yaw.sin()) * (rp * 2.0).max(rp + 6.0);
            self.p.line(c, tip, palette::HEADING, 2.0);
        }
    }

    fn label(&mut self, a: &AgentView, label: &str) {
        let c = self.px(a.position);
        let rp = self.tf.length_to_pixels(finite_len(a.radius)).max(3.0);
        if !(c.is_finite() && rp.is_finite()) {
            return;
        }
        let ts = self.p.text_size(label);
        let off = rp * std::f64::consts::FRAC_1_SQRT_2 + 3.0;
        self.p.text(DVec2::new(c.x + off, c.y - off - ts.y), label, palette::TEXT);
    }

    fn scale_bar(&mut self) {
        let (w, h) = (self.size.0, self.bottom);
        let s = self.tf.scale();
        let target = (w * 0.2).clamp(30.0, 200.0);
        let mut best = None;
        for exp in -3..=6 {
            for m in [1.0, 2.0, 5.0] {
                let len = m * 10f64.powi(exp);
                if len * s <= target {
                    best = Some(len);
                }
            }
        }
        let Some(len) = best else { return };
        let bar = len * s;
        if !(bar >= 8.0) {
            return;
        }
        let label = if len >= 1.0 { format!("{len:.0} m") } else { format!("{} m", len) };
        let ts = self.p.text_size(&label);
        let pad = (ts.y * 0.75).max(4.0);
        let x0 = pad;
        let y = h - pad - 1.0;
        if x0 + bar.max(ts.x) > w || y - ts.y - 6.0 < 0.0 {
            return;
        }
        let tick = (ts.y * 0.5).max(3.0);
        let bg = palette::BACKGROUND.with_alpha(200);
        let box_min = DVec2::new(x0 - 3.0, y - tick - ts.y - 5.0);
        let box_max = DVec2::new(x0 + bar.max(ts.x) + 3.0, y + 3.0);
        self.p
            .fill_polygon(&[box_min, DVec2::new(box_max.x, box_min.y), box_max, DVec2::new(box_min.x, box_max.y)], bg);
        self.p.line(DVec2::new(x0, y), DVec2::new(x0 + bar, y), palette::TEXT, 2.0);
        self.p.line(DVec2::new(x0, y), DVec2::new(x0, y - tick), palette::TEXT, 1.5);
        self.p.line(DVec2::new(x0 + bar, y), DVec2::new(x0 + bar, y - tick), palette::TEXT, 1.5);
        self.p.text(DVec2::new(x0 + ((bar - ts.x) / 2.0).max(0.0), y - tick - ts.y - 2.0), &label, palette::TEXT);
    }

    /// The caption centred at the top and the outcome: on the line under it (`own_line`), or
    /// after it on the same line.
    fn caption(&mut self, caption: Option<&str>, outcome: Option<&Verdict>, own_line: bool) {
        let caption = caption.unwrap_or_default();
        let outcome_text = outcome.map_or("", |v| v.text.as_str());
        let sep = if own_line || caption.is_empty() || outcome_text.is_empty() { "" } else { "   " };
        let first = if own_line { caption.to_string() } else { format!("{caption}{sep}{outcome_text}") };
        let ts = self.p.text_size(&first);
        let w = self.size.0;
        let pad = (ts.y * 0.75).max(4.0);
        let centred = |width: f64| if width + 2.0 * pad <= w { ((w - width) / 2.0).round() } else { pad.round() };
        let x = centred(ts.x);
        if !caption.is_empty() {
            self.p.text(DVec2::new(x, pad.round()), caption, palette::TEXT);
        }
        let Some(v) = outcome else { return };
        let color = if v.success { palette::SUCCESS } else { palette::FAILURE };
        let at = if own_line {
            DVec2::new(centred(self.p.text_size(&v.text).x), (pad + ts.y + pad * 0.5).round())
        } else {
            let dx = if caption.is_empty() { 0.0 } else { self.p.text_size(&format!("{caption}{sep}")).x + 1.0 };
            DVec2::new((x + dx).round(), pad.round())
        };
        self.p.text(at, &v.text, color);
    }

    /// Where an agent started: a square as wide as its disc (at least 7 pixels), outlined.
    fn start(&mut self, at: DVec2, radius: f64) {
        let c = self.px(at);
        let half = self.tf.length_to_pixels(finite_len(radius)).max(3.5);
        if c.is_finite() && half.is_finite() {
            self.start_marker(c, half);
        }
    }

    fn start_marker(&mut self, c: DVec2, half: f64) {
        let corners = [
            c + DVec2::new(-half, -half),
            c + DVec2::new(half, -half),
            c + DVec2::new(half, half),
            c + DVec2::new(-half, half),
        ];
        self.p.fill_polygon(&corners, palette::BACKGROUND);
        self.p.stroke_polygon(&corners, palette::START, OUTLINE_PX);
    }

    /// The legend's band: each entry's swatch, drawn as the picture draws it, and its label.
    fn legend(&mut self, legend: &Legend, th: f64) {
        let (w, h) = self.size;
        let top = h - legend.height;
        let band = [DVec2::new(0.0, top), DVec2::new(w, top), DVec2::new(w, h), DVec2::new(0.0, h)];
        self.p.fill_polygon(&band, palette::BACKGROUND);
        self.p.line(DVec2::new(0.0, top), DVec2::new(w, top), palette::GRID_AXIS, THIN_PX);
        let pad = (th * 0.75).max(4.0);
        for (r, row) in legend.rows.iter().enumerate() {
            let y = top + pad * 0.5 + legend.row * (r as f64 + 0.5);
            for &(key, x) in row {
                self.swatch(key, DVec2::new(x, y - th / 2.0), DVec2::new(x + legend.swatch, y + th / 2.0));
                let label = DVec2::new((x + legend.swatch + th * 0.6).round(), (y - th / 2.0).round());
                self.p.text(label, key.label(), palette::TEXT);
            }
        }
    }

    /// A legend swatch filling the box `a`–`b` (pixels).
    fn swatch(&mut self, key: Key, a: DVec2, b: DVec2) {
        let c = (a + b) / 2.0;
        let (wd, ht) = (b.x - a.x, b.y - a.y);
        let rect = [a, DVec2::new(b.x, a.y), b, DVec2::new(a.x, b.y)];
        let r = ht / 2.0;
        match key {
            Key::Agent => {
                self.p.fill_circle(c, r, palette::AGENT);
                self.p.circle(c, r, palette::AGENT_OUTLINE, OUTLINE_PX);
                self.p.line(c, c + DVec2::new(wd / 2.0, 0.0), palette::HEADING, 2.0);
            }
            Key::Goal => {
                self.p.fill_circle(c, r, palette::GOAL.with_alpha(48));
                self.p.circle(c, r, palette::GOAL, OUTLINE_PX);
                let arm = r * 0.7;
                self.p.line(c - DVec2::new(arm, arm), c + DVec2::new(arm, arm), palette::GOAL, 2.0);
                self.p.line(c - DVec2::new(arm, -arm), c + DVec2::new(arm, -arm), palette::GOAL, 2.0);
            }
            Key::Start => self.start_marker(c, r * 0.8),
            Key::Trail => self.p.line(DVec2::new(a.x, c.y), DVec2::new(b.x, c.y), palette::TRAIL, TRAIL_PX),
            Key::Footprints => {
                let (fw, fh) = (wd * 0.3, ht * 0.35);
                for f in [DVec2::new(a.x + wd * 0.25, c.y - ht * 0.25), DVec2::new(a.x + wd * 0.7, c.y + ht * 0.25)] {
                    let foot = [
                        f + DVec2::new(-fw, -fh) / 2.0,
                        f + DVec2::new(fw, -fh) / 2.0,
                        f + DVec2::new(fw, fh) / 2.0,
                        f + DVec2::new(-fw, fh) / 2.0,
                    ];
                    self.p.fill_polygon(&foot, palette::FOOTPRINT.with_alpha(110));
                    self.p.stroke_polygon(&foot, palette::FOOTPRINT, THIN_PX);
                }
            }
            Key::Sensors => {
                let wedge = [DVec2::new(a.x, c.y), DVec2::new(b.x, a.y), b];
                self.p.fill_polygon(&wedge, palette::SENSOR.with_alpha(palette::SENSOR_ALPHA));
                self.p.stroke_polygon(&wedge, palette::SENSOR, THIN_PX);
            }
            Key::Obstacle => {
                self.p.fill_polygon(&rect, palette::OBSTACLE_FILL);
                self.p.stroke_polygon(&rect, palette::OBSTACLE_OUTLINE, OUTLINE_PX);
            }
            Key::Hull => self.dashed(DVec2::new(a.x, c.y), DVec2::new(b.x, c.y), palette::HULL, OUTLINE_PX, 6.0, 4.0),
            Key::Overhead => {
                self.p.fill_polygon(&rect, palette::OVERHEAD_FILL);
                self.p.stroke_polygon(&rect, palette::OBSTACLE_OUTLINE, OUTLINE_PX);
            }
            Key::Raised => {
                self.p.fill_polygon(&rect, palette::TERRAIN_RAISED);
                self.p.stroke_polygon(&rect, palette::TERRAIN_EDGE, THIN_PX);
            }
            Key::Hole => {
                self.p.fill_polygon(&rect, palette::TERRAIN_HOLE);
                self.p.stroke_polygon(&rect, palette::TERRAIN_EDGE, THIN_PX);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::Obstacle;

    /// Records calls and checks every coordinate is finite.
    #[derive(Default)]
    struct Recorder {
        lines: usize,
        fills: usize,
        texts: Vec<String>,
    }

    impl Painter for Recorder {
        fn size(&self) -> (f64, f64) {
            (200.0, 100.0)
        }
        fn line(&mut self, a: DVec2, b: DVec2, _: Rgba, w: f64) {
            assert!(a.is_finite() && b.is_finite() && w.is_finite());
            self.lines += 1;
        }
        fn fill_polygon(&mut self, points: &[DVec2], _: Rgba) {
            assert!(points.iter().all(|p| p.is_finite()));
            self.fills += 1;
        }
        fn text(&mut self, at: DVec2, text: &str, _: Rgba) {
            assert!(at.is_finite());
            self.texts.push(text.to_string());
        }
    }

    #[test]
    fn transform_round_trips_and_keeps_aspect() {
        let view = Aabb::new(DVec2::new(-2.0, 1.0), DVec2::new(8.0, 4.0));
        let tf = ViewTransform::from_view(view, (300.0, 200.0), 10.0);
        // 10 m wide into 280 px, 3 m tall into 180 px: width decides.
        assert!((tf.scale() - 28.0).abs() < 1e-12);
        for p in [DVec2::new(-2.0, 1.0), DVec2::new(3.3, -7.1), DVec2::new(1e3, 2e-3)] {
            assert!(tf.to_world(tf.to_pixel(p)).distance(p) < 1e-9);
        }
        // Square metres stay square and y flips.
        let o = tf.to_pixel(DVec2::ZERO);
        let ex = tf.to_pixel(DVec2::X) - o;
        let ey = tf.to_pixel(DVec2::Y) - o;
        assert!((ex.x - 28.0).abs() < 1e-12 && ex.y.abs() < 1e-12);
        assert!((ey.y + 28.0).abs() < 1e-12 && ey.x.abs() < 1e-12);
        // The view is centred and fits inside the margins.
        let a = tf.to_pixel(view.min);
        let b = tf.to_pixel(view.max);
        assert!((a.x - 10.0).abs() < 1e-9 && (b.x - 290.0).abs() < 1e-9);
        assert!(((a.y + b.y) / 2.0 - 100.0).abs() < 1e-9);
        let vis = tf.visible_world((300.0, 200.0));
        assert!(vis.contains_point(view.min) && vis.contains_point(view.max));
    }

    #[test]
    fn degenerate_transforms_are_finite() {
        let nan = DVec2::splat(f64::NAN);
        for view in [
            Aabb::around(DVec2::new(1.0, 2.0), 0.0),
            Aabb::new(nan, nan),
            Aabb::new(DVec2::new(0.0, 0.0), DVec2::new(5.0, 0.0)),
            Aabb::new(DVec2::new(3.0, 3.0), DVec2::new(-3.0, -3.0)),
        ] {
            for size in [(0.0, 0.0), (100.0, 50.0), (f64::NAN, 10.0)] {
                let tf = ViewTransform::from_view(view, size, 5.0);
                assert!(tf.scale().is_finite() && tf.scale() > 0.0);
                let p = DVec2::new(0.5, -0.25);
                assert!(tf.to_world(tf.to_pixel(p)).distance(p) < 1e-6);
            }
        }
    }

    /// The legend lists what the picture can show (the hull only for a non-convex obstacle,
    /// footsteps for a walking body before it has stepped), and a frame looks the same with
    /// its outcome as without: the framing is kept for it.
    #[test]
    fn the_legend_names_what_is_drawn_and_the_framing_holds() {
        #[derive(Default)]
        struct Texts(Vec<String>);
        impl Painter for Texts {
            fn size(&self) -> (f64, f64) {
                (400.0, 400.0)
            }
            fn line(&mut self, _: DVec2, _: DVec2, _: Rgba, _: f64) {}
            fn fill_polygon(&mut self, _: &[DVec2], _: Rgba) {}
            fn text(&mut self, _: DVec2, text: &str, _: Rgba) {
                self.0.push(text.to_string());
            }
        }
        let square = obstacle(ObstacleShape::Box { center: DVec2::new(2.0, 0.0), width: 1.0, height: 1.0, yaw: 0.0 });
        let world = World::new(vec![square]);
        let agent = AgentView {
            position: DVec2::ZERO,
            radius: 0.3,
            walks: true,
            start: Some(DVec2::ZERO),
            ..AgentView::default()
        };
        let mut scene = Scene {
            world: &world,
            agents: vec![agent],
            goals: vec![(DVec2::new(5.0, 0.0), 0.5)],
            view: None,
            caption: Some("demo".into()),
            outcome: None,
            legend: true,
        };
        let mut texts = Texts::default();
        draw_scene(&scene, &mut texts);
        for label in ["agent, heading", "goal", "start", "path walked", "footsteps", "obstacle"] {
            assert!(texts.0.iter().any(|t| t == label), "{label} missing from {:?}", texts.0);
        }
        assert!(!texts.0.iter().any(|t| t == "convex hull" || t == "hole"), "{:?}", texts.0);
        let running = scene_transform(&scene, (400.0, 400.0), 7.0);
        scene.outcome = Some(Verdict { text: "goal reached, path 5.00 m".into(), success: true });
        assert_eq!(scene_transform(&scene, (400.0, 400.0), 7.0), running);
        let mut texts = Texts::default();
        draw_scene(&scene, &mut texts);
        assert!(texts.0.iter().any(|t| t == "goal reached, path 5.00 m"));
        // Without a legend (the terminal view) the band is not kept.
        scene.legend = false;
        assert_ne!(scene_transform(&scene, (400.0, 400.0), 7.0), running);
    }

    fn obstacle(shape: ObstacleShape) -> Obstacle {
        Obstacle::build(shape, 0.0, 2.0).unwrap()
    }

    #[test]
    fn degenerate_scenes_do_not_panic() {
        let empty = World::new(Vec::new());
        let world = World::new(vec![
            obstacle(ObstacleShape::Cylinder { center: DVec2::new(2.0, 0.0), radius: 0.5 }),
            obstacle(ObstacleShape::Polygon {
                outline: vec![
                    DVec2::new(0.0, 0.0),
                    DVec2::new(2.0, 0.0),
                    DVec2::new(2.0, 1.0),
                    DVec2::new(1.0, 1.0),
                    DVec2::new(1.0, 2.0),
                    DVec2::new(0.0, 2.0),
                ],
            }),
        ]);
        let nan = DVec2::splat(f64::NAN);
        let weird = AgentView {
            position: DVec2::new(1.0, f64::NAN),
            yaw: f64::NAN,
            radius: f64::INFINITY,
            trail: vec![nan, DVec2::ONE, nan],
            sectors: Some((vec![0.0, f64::NAN, 1.0], vec![f64::NAN], f64::NAN)),
            footprints: vec![(nan, 0.0)],
            walks: true,
            start: Some(nan),
            label: Some("nan".into()),
        };
        let odd = AgentView {
            position: DVec2::ZERO,
            yaw: f64::NAN,
            radius: -1.0,
            trail: vec![DVec2::ZERO, nan, DVec2::new(f64::INFINITY, 0.0), DVec2::ONE, DVec2::new(2.0, 1.0)],
            sectors: Some((vec![-1.0, 0.0, 1.0, 7.0], vec![1.0, -5.0, f64::INFINITY, 2.0], 3.0)),
            footprints: vec![(DVec2::ONE, f64::NAN)],
            walks: false,
            start: Some(DVec2::new(f64::INFINITY, 0.0)),
            label: Some(String::new()),
        };
        let views = [
            None,
            Some(Aabb::around(DVec2::ONE, 0.0)),
            Some(Aabb::new(nan, nan)),
            Some(Aabb::new(DVec2::splat(-1e300), DVec2::splat(1e300))),
            Some(Aabb::around(DVec2::ZERO, 1e-12)),
        ];
        for w in [&empty, &world] {
            for view in views {
                for agents in [vec![], vec![weird.clone(), odd.clone()]] {
                    let scene = Scene {
                        world: w,
                        agents,
                        goals: vec![(nan, 1.0), (DVec2::ONE, f64::NAN)],
                        view,
                        caption: Some("caption".into()),
                        outcome: Some(Verdict { text: "timed out".into(), success: false }),
                        legend: true,
                    };
                    let mut rec = Recorder::default();
                    draw_scene(&scene, &mut rec);
                    assert!(rec.texts.contains(&"caption".to_string()));
                    let pm = super::super::png::render_png(&scene, 120, 80);
                    assert_eq!((pm.width(), pm.height()), (120, 80));
                    let tiny = super::super::png::render_png(&scene, 0, 0);
                    assert!(tiny.width() >= 1 && tiny.height() >= 1);
                }
            }
        }
        // A NaN agent draws nothing at all of its own.
        let scene = Scene {
            world: &empty,
            agents: vec![weird],
            goals: vec![],
            view: None,
            caption: None,
            outcome: None,
            legend: false,
        };
        let mut rec = Recorder::default();
        draw_scene(&scene, &mut rec);
        assert!(rec.fills <= 1, "only the scale bar backdrop may be filled, got {}", rec.fills);
        assert!(rec.texts.iter().all(|t| t.ends_with(" m")));
    }
}
