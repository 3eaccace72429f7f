//! What an agent remembers of what it has sensed, and the way to the goal over it (seed 000
//! §3.1 needs no map; TangentBug's local tangent graph already keeps what the sensor shows —
//! this keeps it for the whole episode).
//!
//! The memory is a grid of cells over the plane. Every all-around scan of the world's
//! obstacles marks the cell of each point a ray hit — and the cells between the hits of
//! neighbouring rays closer than the disc's width, which must be one surface. The world's
//! obstacles do not move, so a mark is kept for the whole episode; other agents are left to
//! the reactive layers and never remembered. Cells near a marked cell are inflated for the
//! agent's disc: within the hard radius they cannot be crossed, and within the clearance
//! margin beyond it they cost more the closer they are (in [`BANDS`] steps), so that paths keep
//! to the middle of doors and corridors. The way to the goal is an A* path over the grid with
//! unknown cells taken as free (planning with the free-space assumption: each new obstacle
//! either leaves the path clear or is remembered, so the agent never tries the same blocked
//! way twice and, in a finite world, reaches any goal it can reach). The planner's goal
//! seeking then steers toward a waypoint on that path instead of straight at the goal.
//!
//! The memory is the disc's: a body that needs more room (the character keeps a margin) may
//! be held up where the grid shows a way. An agent held up in one place for long has its range
//! sensor measure the way across the path just ahead, and gaps narrower than its body passes
//! are remembered as obstacles too ([`Memory::close_gaps_ahead`]), so it plans round them.
//!
//! The path is kept between steps and planned again only when a newly remembered obstacle
//! touches it or the agent strays from it; a new plan replaces the path only when it is
//! clearly shorter, so two ways round an obstacle of about the same length do not take turns.
//! The waypoint is the farthest point of the path within reach in clear sight, with the margin
//! kept when that leaves one at least a metre ahead; before a door or corridor narrower than the
//! margin, the agent instead pursues the gap's middle line as its sensor measures it
//! ([`Memory::heading_with`]), so it enters along it. The grid grows as the agent explores.
//! Everything is deterministic: plain vectors, ties broken by cell index.

use dary_heap::QuaternaryHeap;
use std::cmp::Reverse;

use glam::DVec2;

/// Tuning of the memory. Every field documents its default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemoryParams {
    /// Side of a cell, metres (0.125).
    pub cell_m: f64,
    /// Clearance margin beyond the agent's radius that makes a path cost more, metres (0.15).
    pub margin_m: f64,
    /// Extra cost per metre of a path through the margin (4).
    pub margin_cost: f64,
    /// Goal seeking steers to the farthest point of the path this far ahead that is in clear
    /// sight, metres (3.0).
    pub waypoint_m: f64,
    /// Plan again when the agent is farther than this from its path, metres (1.0).
    pub stray_m: f64,
    /// Most cells one plan may expand before giving up (4,000,000).
    pub max_expansions: usize,
}

impl Default for MemoryParams {
    fn default() -> Self {
        MemoryParams {
            cell_m: 0.125,
            margin_m: 0.15,
            margin_cost: 4.0,
            waypoint_m: 3.0,
            stray_m: 1.0,
            max_expansions: 4_000_000,
        }
    }
}

/// A new path replaces the current one only when it is shorter by this share of its cost plus
/// [`SWITCH_M`] metres.
const SWITCH_SHARE: f32 = 0.1;

/// See [`SWITCH_SHARE`].
const SWITCH_M: f32 = 1.0;

/// Least distance to a waypoint chosen for keeping the clearance margin, metres.
const MIN_ROOMY_WAYPOINT_M: f64 = 1.0;

/// Steps of the clearance margin: a cell's extra cost grows by a step per band nearer the
/// obstacle.
const BANDS: u8 = 3;

/// Cells this near the agent do not count for the margin a waypoint's line keeps, metres
/// (standing close to a wall, the agent may still aim along it).
const STRIDE_M: f64 = 0.25;

/// [`Memory::close_gaps_ahead`] looks this far along the path and no nearer, metres.
const AHEAD_MAX_M: f64 = 1.5;

/// See [`AHEAD_MAX_M`].
const AHEAD_MIN_M: f64 = 0.2;

/// How far along the way ahead a narrow part is lined up for, metres.
const LINE_UP_LOOK_M: f64 = 2.5;
/// Length of the way past a gap's entry that gives its line, metres.
const GAP_AXIS_M: f64 = 0.6;
/// How far beyond its own projection on a gap's line the agent aims, metres.
const PURSUIT_M: f64 = 0.6;
/// Least cosine between the path's direction and the line through two measured middles for
/// the latter to be the gap's line (30°).
const SAME_LINE_COS: f64 = 0.866;
/// Widest way across that counts as a gap to line up for, metres.
const GAP_MEASURE_M: f64 = 2.0;

/// Cells added around the known area when the grid grows.
const GROW_CELLS: i64 = 40;

/// Where goal seeking steers: toward a waypoint on the remembered way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aim {
    /// Direction toward the waypoint, absolute radians.
    pub heading: f64,
    /// Length of the remaining way to the goal, metres.
    pub remaining_m: f64,
    /// Distance to the waypoint, metres.
    pub waypoint_m: f64,
}

/// The remembered obstacles and the current path to the goal.
#[derive(Debug, Clone)]
pub struct Memory {
    params: MemoryParams,
    /// Cell (0, 0)'s lower-left corner, world.
    origin: DVec2,
    nx: usize,
    ny: usize,
    /// What is known of each cell: [`MARKED`] when a ray hit an obstacle in it, [`HARD`] when
    /// a marked cell lies within the agent's radius (the cell cannot be crossed), and in the
    /// [`BAND`] bits how deep it lies in the clearance margin of a marked cell (0 outside it,
    /// [`BANDS`] within the innermost band).
    cells: Vec<u8>,
    /// Marked cells.
    known: usize,
    /// The cells a marked cell inflates, as offsets from it: whether each is closed, and its
    /// band of the margin.
    inflation: Vec<(i64, i64, bool, u8)>,
    /// Cells a marked cell's inflation may reach, to a side.
    reach_cells: i64,
    /// A new mark this near the path makes it stale, metres (radius, margin and a cell).
    stale_m: f64,
    goal: DVec2,
    /// The current path, world points from near the agent to the goal.
    path: Vec<DVec2>,
    /// Corners of a box holding every point of the path (the path only shrinks between
    /// plans).
    path_box: (DVec2, DVec2),
    /// The last search found no way to the goal.
    failed: bool,
    /// A newly marked cell lies on or near the path: plan again.
    stale: bool,
    /// Plans made so far.
    pub plans: u32,
    scratch: Search,
}

/// The eight steps of the search: offsets and whether the step is diagonal.
const STEPS: [(i64, i64, bool); 8] = [
    (1, 0, false),
    (-1, 0, false),
    (0, 1, false),
    (0, -1, false),
    (1, 1, true),
    (1, -1, true),
    (-1, 1, true),
    (-1, -1, true),
];

/// The moves a search from `start` to cell `goal` may make over the cells.
struct Moves<'a> {
    cells: &'a [u8],
    nx: i64,
    ny: i64,
    goal: usize,
    start: (i64, i64),
    /// Closed cells the agent may cross to get out of the inflation it stands in: those
    /// within this many cells of the start.
    escape: i64,
}

impl Moves<'_> {
    /// The cell that `step` from cell `(x, y)` enters, if the search may take it.
    #[inline(always)]
    fn step(&self, x: i64, y: i64, (dx, dy, diagonal): (i64, i64, bool)) -> Option<usize> {
        let (mx, my) = (x + dx, y + dy);
        if mx < 0 || my < 0 || mx >= self.nx || my >= self.ny {
            return None;
        }
        let m = (my * self.nx + mx) as usize;
        (self.enterable(m, mx, my, self.cells[m]) && !(diagonal && self.squeezed(x, y, mx, my))).then_some(m)
    }

    /// Whether the search may enter cell `m` at `(mx, my)`, in state `cell`. The agent may
    /// stand in inflated cells (close to a wall): it may leave them, but closed cells are
    /// crossed only within the disc's reach of where it stands, never through a wall.
    #[inline(always)]
    fn enterable(&self, m: usize, mx: i64, my: i64, cell: u8) -> bool {
        cell & HARD == 0
            || m == self.goal
            || (cell & MARKED == 0 && (mx - self.start.0).abs().max((my - self.start.1).abs()) <= self.escape)
    }

    /// Whether a diagonal step from `(x, y)` to `(mx, my)` squeezes between two closed cells.
    #[inline(always)]
    fn squeezed(&self, x: i64, y: i64, mx: i64, my: i64) -> bool {
        self.cells[(y * self.nx + mx) as usize] & self.cells[(my * self.nx + x) as usize] & HARD != 0
    }
}

/// A cell's bit: a ray hit an obstacle in it.
const MARKED: u8 = 0x10;

/// A cell's bit: it cannot be crossed.
const HARD: u8 = 0x20;

/// A cell's bits holding its band of the margin.
const BAND: u8 = 0x03;

/// Reused A* state (generation stamps avoid clearing it).
#[derive(Debug, Clone, Default)]
struct Search {
    nodes: Vec<Node>,
    generation: u32,
    open: QuaternaryHeap<Reverse<u64>>,
}

impl Search {
    /// Starts a search over `n` cells: the stamp its reached cells get, which no cell has yet.
    fn begin(&mut self, n: usize) -> u32 {
        if self.nodes.len() != n {
            self.nodes = vec![Node::default(); n];
            self.generation = 0;
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.nodes.iter_mut().for_each(|x| x.stamp = 0);
            self.generation = 1;
        }
        self.generation
    }
}

/// A cell's state in the search: reached in the search of this generation, at this cost, from
/// this parent.
#[derive(Debug, Clone, Copy, Default)]
struct Node {
    stamp: u32,
    cost: f32,
    parent: u32,
}

/// An open cell of the search as one integer key: its estimate `f` (never negative, so its
/// bits order as the number does) above its index, so that the least key is the least `f`, ties
/// to the lowest cell.
struct Open;

impl Open {
    fn key(f: f32, cell: usize) -> u64 {
        (u64::from(if f > 0.0 { f } else { 0.0 }.to_bits()) << 32) | cell as u64
    }

    fn unkey(key: u64) -> (f32, usize) {
        (f32::from_bits((key >> 32) as u32), (key & 0xffff_ffff) as usize)
    }
}

/// The cells a marked cell inflates for a disc of `radius` with a clearance `margin` (cells of
/// side `c`): closed when its centre lies within the radius of the marked cell's, and in band
/// [`BANDS`] (innermost) down to 1 across the margin beyond.
fn inflation(radius: f64, margin: f64, c: f64) -> Vec<(i64, i64, bool, u8)> {
    let reach = ((radius + margin) / c).ceil() as i64;
    let mut out = Vec::new();
    for dy in -reach..=reach {
        for dx in -reach..=reach {
            let d = ((dx * dx + dy * dy) as f64).sqrt() * c;
            if d < radius + margin {
                let beyond = ((d - radius).max(0.0) / margin.max(1e-9) * f64::from(BANDS)).floor();
                let band = BANDS - beyond.clamp(0.0, f64::from(BANDS - 1)) as u8;
                out.push((dx, dy, d < radius, band));
            }
        }
    }
    out
}

impl Memory {
    /// An empty memory for an agent of `radius` metres going from `start` to `goal`.
    pub fn new(start: DVec2, goal: DVec2, radius: f64, params: MemoryParams) -> Memory {
        let c = params.cell_m.max(0.01);
        let lo = start.min(goal);
        let hi = start.max(goal);
        let pad = GROW_CELLS as f64 * c;
        let origin = ((lo - DVec2::splat(pad)) / c).floor() * c;
        let nx = (((hi.x + pad - origin.x) / c).ceil() as usize).max(1);
        let ny = (((hi.y + pad - origin.y) / c).ceil() as usize).max(1);
        // A cell is closed when a marked cell's centre lies within the radius of its own (gaps
        // the disc does not fit through close; doors it fits through stay open), dearer within
        // radius + margin.
        let reach_cells = ((radius.max(0.0) + params.margin_m.max(0.0)) / c).ceil() as i64 + 1;
        Memory {
            params: MemoryParams { cell_m: c, ..params },
            origin,
            nx,
            ny,
            cells: vec![0; nx * ny],
            known: 0,
            inflation: inflation(radius.max(0.0), params.margin_m.max(0.0), c),
            reach_cells,
            stale_m: radius.max(0.0) + params.margin_m + c,
            goal,
            path: Vec::new(),
            path_box: (DVec2::ZERO, DVec2::ZERO),
            failed: false,
            stale: true,
            plans: 0,
            scratch: Search::default(),
        }
    }

    fn cell_of(&self, p: DVec2) -> (i64, i64) {
        let q = (p - self.origin) / self.params.cell_m;
        (crate::geom::floor_i64(q.x), crate::geom::floor_i64(q.y))
    }

    fn centre(&self, i: i64, j: i64) -> DVec2 {
        self.origin + (DVec2::new(i as f64, j as f64) + 0.5) * self.params.cell_m
    }

    fn index(&self, i: i64, j: i64) -> Option<usize> {
        (i >= 0 && j >= 0 && (i as usize) < self.nx && (j as usize) < self.ny)
            .then(|| j as usize * self.nx + i as usize)
    }

    /// Grows the grid so that cell `(i, j)` is inside it with room around.
    fn include(&mut self, i: i64, j: i64) {
        if i >= 1 && j >= 1 && (i as usize) + 1 < self.nx && (j as usize) + 1 < self.ny {
            return;
        }
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        let lo_x = (i - GROW_CELLS).min(0);
        let lo_y = (j - GROW_CELLS).min(0);
        let hi_x = (i + GROW_CELLS + 1).max(nx);
        let hi_y = (j + GROW_CELLS + 1).max(ny);
        let (wx, wy) = ((hi_x - lo_x) as usize, (hi_y - lo_y) as usize);
        let mut cells = vec![0u8; wx * wy];
        for y in 0..ny {
            let from = (y * nx) as usize;
            let to = ((y - lo_y) as usize) * wx + (-lo_x) as usize;
            cells[to..to + nx as usize].copy_from_slice(&self.cells[from..from + nx as usize]);
        }
        self.origin -= DVec2::new(-lo_x as f64, -lo_y as f64) * self.params.cell_m;
        (self.nx, self.ny, self.cells) = (wx, wy, cells);
        // Cells the path passes keep their world positions; the plan stays valid.
    }

    /// Remembers an obstacle at `p` (in its cell).
    fn mark(&mut self, p: DVec2) {
        if !p.is_finite() {
            return;
        }
        let (i, j) = self.cell_of(p);
        let Some(k) = self.index(i, j) else { return };
        if self.cells[k] & MARKED != 0 {
            return;
        }
        self.cells[k] |= MARKED;
        self.known += 1;
        for &(dx, dy, closed, band) in &self.inflation {
            let Some(n) = self.index(i + dx, j + dy) else { continue };
            let cell = &mut self.cells[n];
            *cell = (*cell & !BAND) | (*cell & BAND).max(band) | if closed { HARD } else { 0 };
        }
        if !self.stale {
            // Does the new obstacle come near the path?
            let q = self.centre(i, j);
            // Off the path's box by more than the distance (and rounding), it is near no point.
            let (lo, hi) = self.path_box;
            let off = (lo - q).max(q - hi).max_element();
            if off <= self.stale_m + 1e-9 && self.path.iter().any(|p| p.distance(q) <= self.stale_m) {
                self.stale = true;
            }
        }
    }

    /// Takes in an all-around scan of the world's obstacles from `from` (ray `i` at absolute
    /// angle `2πi/n`, the distance to the first hit less `radius`, capped at `range`): the
    /// obstacle points hit are remembered.
    pub fn observe(&mut self, from: DVec2, scan: &[f64], radius: f64, range: f64) {
        let n = scan.len();
        if n == 0 || !from.is_finite() {
            return;
        }
        let (ci, cj) = self.cell_of(from);
        let reach = ((range + radius) / self.params.cell_m).ceil() as i64 + 1;
        self.include(ci - reach, cj - reach);
        let (ci, cj) = self.cell_of(from);
        self.include(ci + reach, cj + reach);
        let c = self.params.cell_m;
        let fan = super::sense::Fan::of(n);
        for (k, &f) in scan.iter().enumerate() {
            if f.is_finite() && f < range {
                self.mark(from + fan.rays[k] * (f + radius));
            }
        }
        // Hits of neighbouring rays closer than the disc's width are one surface (the disc
        // could not pass between them anyway): remember the segment between them.
        for k in 0..n {
            let (a, b) = (scan[k], scan[(k + 1) % n]);
            if !(a < range && b < range) {
                continue;
            }
            let pa = from + fan.rays[k] * (a + radius);
            let pb = from + fan.rays[(k + 1) % n] * (b + radius);
            let len = pa.distance(pb);
            if len >= 2.0 * radius {
                continue;
            }
            let steps = (len / (0.5 * c)).ceil() as usize;
            for s in 1..steps {
                self.mark(pa + (pb - pa) * (s as f64 / steps as f64));
            }
        }
    }

    /// Where to steer from `from` along the path to the goal, planned again when needed.
    /// `sight(heading)` is how far the agent sees its way free along an absolute heading now
    /// (infinite when nothing limits it): a waypoint beyond it is taken only when no waypoint
    /// in sight is left. `None` when the goal cannot be reached over what is remembered (or
    /// the search gives up).
    pub fn heading(&mut self, from: DVec2, sight: impl Fn(f64) -> f64) -> Option<Aim> {
        self.heading_with(from, sight, |_, _| f64::INFINITY)
    }

    /// [`Memory::heading`] with `span(p, unit)`, how far the way is free from `p` along `unit`
    /// (the range sensor's measure; infinite when nothing is near), which puts the line a gap
    /// is entered along through the middle of the gap as measured, not of the grid's cells.
    pub fn heading_with(
        &mut self,
        from: DVec2,
        sight: impl Fn(f64) -> f64,
        span: impl FnMut(DVec2, DVec2) -> f64,
    ) -> Option<Aim> {
        let near = self
            .path
            .iter()
            .enumerate()
            .map(|(k, p)| (k, p.distance_squared(from)))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        let strayed = near.is_none_or(|(_, d)| d.sqrt() > self.params.stray_m);
        if self.stale || strayed {
            self.plan(from, !strayed);
        }
        let start = self
            .path
            .iter()
            .enumerate()
            .map(|(k, p)| (k, p.distance_squared(from)))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))?
            .0;
        // Drop what is behind.
        self.path.drain(..start);
        // A narrow part of the way ahead (a door, a corridor) is entered along its own line;
        // elsewhere the waypoint is the farthest one in sight.
        let waypoint = match self.line_up(from, span) {
            Some(p) => p,
            None => self.farthest_waypoint(from, sight),
        };
        let remaining: f64 =
            from.distance(self.path[0]) + self.path.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
        let to = waypoint - from;
        if to.length() < 1e-9 {
            let to = self.goal - from;
            return Some(Aim { heading: to.to_angle(), remaining_m: remaining, waypoint_m: to.length() });
        }
        Some(Aim { heading: to.to_angle(), remaining_m: remaining, waypoint_m: to.length() })
    }

    /// The waypoint: the farthest point of the path within reach that the disc can go straight
    /// to from `from` without touching what is remembered (with the margin if it can), so that
    /// steering toward it never cuts a corner into a wall; else the next point.
    fn farthest_waypoint(&self, from: DVec2, sight: impl Fn(f64) -> f64) -> DVec2 {
        let mut along = from.distance(self.path[0]);
        let mut prev = self.path[0];
        let reach = self
            .path
            .iter()
            .position(|&p| {
                along += prev.distance(p);
                prev = p;
                along > self.params.waypoint_m
            })
            .unwrap_or(self.path.len());
        // The farthest point in clear sight, and the farthest at least
        // [`MIN_ROOMY_WAYPOINT_M`] away, free in sight, whose line keeps the whole margin, or
        // its outer bands. Looked for from the far end: the first roomy point settles it.
        let (mut clear, mut roomy, mut kept) = (None, None, None);
        for &p in self.path[..reach].iter().rev() {
            let Some(depth) = self.line_depth(from, p) else { continue };
            clear.get_or_insert(p);
            if depth != 0 && (depth >= BANDS || kept.is_some()) {
                continue;
            }
            let to = p - from;
            if p.distance(from) >= MIN_ROOMY_WAYPOINT_M && sight(to.to_angle()) >= to.length() {
                kept.get_or_insert(p);
                if depth == 0 {
                    roomy = Some(p);
                    break;
                }
            }
        }
        // A waypoint close by is circled rather than reached: keep the margin only while
        // that leaves one far enough ahead.
        roomy.or(kept).or(clear).unwrap_or(self.path[0])
    }

    /// The band of the margin the cell holding `p` lies in (0 outside it or off the grid).
    fn depth_at(&self, p: DVec2) -> u8 {
        let (i, j) = self.cell_of(p);
        self.index(i, j).map_or(0, |c| self.cells[c] & BAND)
    }

    /// Where an agent at `from` steers for the narrow part of its way ahead (a door, a
    /// corridor): the first point of the path within [`LINE_UP_LOOK_M`] whose cell lies in the
    /// margin of remembered obstacles is the gap's entry (the agent's own spot when it is in
    /// the gap already), the path over the next [`GAP_AXIS_M`] gives the gap's direction, and
    /// `span` measures the way across the entry, which puts the gap's line through its middle.
    /// The agent pursues that line: it aims at the point of the line [`PURSUIT_M`] beyond its
    /// own projection on it, so it comes onto the line in front of the gap, along it, and
    /// passes through the middle — steering continuously, never one way and then the other.
    /// `None` when no gap measured narrower than [`GAP_MEASURE_M`] lies ahead or the point is
    /// not in clear sight over what is remembered.
    fn line_up(&self, from: DVec2, mut span: impl FnMut(DVec2, DVec2) -> f64) -> Option<DVec2> {
        let mut along = from.distance(self.path[0]);
        let mut entry = None;
        for (k, &p) in self.path.iter().enumerate() {
            if k > 0 {
                along += self.path[k - 1].distance(p);
            }
            if along > LINE_UP_LOOK_M {
                break;
            }
            if self.depth_at(p) > 0 {
                entry = Some(k);
                break;
            }
        }
        let k = entry?;
        let e = self.path[k];
        let mut axis_end = e;
        let mut run = 0.0;
        for w in self.path[k..].windows(2) {
            run += w[0].distance(w[1]);
            axis_end = w[1];
            if run >= GAP_AXIS_M {
                break;
            }
        }
        let dir = (axis_end - e).normalize_or_zero();
        if dir == DVec2::ZERO || run < 2.0 * self.params.cell_m {
            return None;
        }
        // The middle of the gap as measured across it, at the entry and (in a corridor) a
        // little further on: the line through both is the gap's, whatever cells the path takes.
        let mut middle = |p: DVec2| {
            let across = dir.perp();
            let (l, r) = (span(p, across), span(p, -across));
            (l + r < GAP_MEASURE_M).then(|| p + across * (0.5 * (l - r)))
        };
        let centre = middle(e)?;
        let line = match middle(e + dir * GAP_AXIS_M) {
            Some(further) if (further - centre).normalize_or_zero().dot(dir) > SAME_LINE_COS => {
                (further - centre).normalize()
            }
            _ => dir,
        };
        let target = centre + line * (line.dot(from - centre) + PURSUIT_M);
        self.line_depth(from, target).map(|_| target)
    }

    /// Closes the gaps just ahead of an agent at `from` that has not been able to follow its
    /// way: the points of the path between [`AHEAD_MIN_M`] and [`AHEAD_MAX_M`] along it where
    /// the way across the path is narrower than `passage` metres (`width(p, across)` measures
    /// it, `across` a unit vector) are remembered as obstacles, so the next plan goes round.
    /// Only points in the margin of remembered obstacles are measured, and the last `keep_m`
    /// before the goal are left as they are. True when something was closed.
    pub fn close_gaps_ahead(
        &mut self,
        from: DVec2,
        passage: f64,
        keep_m: f64,
        mut width: impl FnMut(DVec2, DVec2) -> f64,
    ) -> bool {
        let mut along = 0.0;
        let mut prev = from;
        let mut close = Vec::new();
        for (k, &p) in self.path.iter().enumerate() {
            along += prev.distance(p);
            prev = p;
            if along > AHEAD_MAX_M {
                break;
            }
            if along < AHEAD_MIN_M || p.distance(self.goal) <= keep_m {
                continue;
            }
            let (i, j) = self.cell_of(p);
            if self.index(i, j).is_none_or(|c| self.cells[c] & BAND == 0) {
                continue;
            }
            let next = self.path.get(k + 1).copied().unwrap_or(self.goal);
            let dir = (next - self.path[k.saturating_sub(1)]).normalize_or_zero();
            if dir != DVec2::ZERO && width(p, dir.perp()) < passage {
                close.push(p);
            }
        }
        for &p in &close {
            self.mark(p);
        }
        self.stale |= !close.is_empty();
        !close.is_empty()
    }

    /// The deepest band of the margin the straight line from `a` to `b` crosses, or `None`
    /// when it crosses a closed cell (the cell the agent stands in does not count, nor, for
    /// the margin, cells within the agent's first stride).
    fn line_depth(&self, a: DVec2, b: DVec2) -> Option<u8> {
        let step = 0.5 * self.params.cell_m;
        let n = (a.distance(b) / step).ceil().max(1.0) as usize;
        let here = self.cell_of(a);
        let mut depth = 0;
        for k in 1..=n {
            let q = a + (b - a) * (k as f64 / n as f64);
            let (i, j) = self.cell_of(q);
            if (i, j) == here {
                continue;
            }
            let Some(c) = self.index(i, j) else { continue };
            if self.cells[c] & HARD != 0 {
                return None;
            }
            if q.distance(a) > STRIDE_M {
                depth = depth.max(self.cells[c] & BAND);
            }
        }
        Some(depth)
    }

    /// A* from `from` to the goal over the grid (unknown cells free, hard cells closed, cells
    /// in the margin dearer); the path is kept as world points (the goal itself last).
    fn plan(&mut self, from: DVec2, keep: bool) {
        self.plans += 1;
        self.stale = false;
        let old = std::mem::take(&mut self.path);
        let (gi, gj) = self.cell_of(self.goal);
        self.include(gi, gj);
        let (si, sj) = self.cell_of(from);
        self.include(si, sj);
        let (gi, gj) = self.cell_of(self.goal);
        let (si, sj) = self.cell_of(from);
        let (Some(start), Some(goal)) = (self.index(si, sj), self.index(gi, gj)) else { return };
        let c = self.params.cell_m as f32;
        let octile = |x: i64, y: i64| -> f32 {
            let (dx, dy) = ((x - gi).abs() as f32, (y - gj).abs() as f32);
            c * (dx.max(dy) + (std::f32::consts::SQRT_2 - 1.0) * dx.min(dy))
        };
        // No way is shorter than the straight octile distance (every step of the search costs
        // at least its length): when the kept way is within the switching allowance of that,
        // no new plan could replace it, and the search is skipped.
        if keep
            && let Some(old_cost) = self.path_cost(from, &old)
            && old_cost <= octile(si, sj) * (1.0 - 1e-4) * (1.0 + SWITCH_SHARE) + SWITCH_M
        {
            self.path = old;
            return;
        }
        // After a search that found no way, the next is likely to find none either: a plain
        // flood over the same moves tells at a fraction of the search's cost.
        if self.failed && !self.reaches(start, goal, (si, sj)) {
            return;
        }
        let s = &mut self.scratch;
        let gen_ = s.begin(self.nx * self.ny);
        let (nodes, open) = (&mut s.nodes, &mut s.open);
        open.clear();
        nodes[start] = Node { stamp: gen_, cost: 0.0, parent: start as u32 };
        open.push(Reverse(Open::key(octile(si, sj), start)));
        // Closed cells the agent may cross to get out of the inflation it stands in.
        let escape = self.reach_cells;
        // The cost of a straight and of a diagonal step into a cell of each band.
        let margin_cost = self.params.margin_cost as f32 / f32::from(BANDS);
        let step_cost: [[f32; 2]; BAND as usize + 1] = std::array::from_fn(|band| {
            let extra = margin_cost * f32::from(band as u8);
            [c * 1.0 * (1.0 + extra), c * std::f32::consts::SQRT_2 * (1.0 + extra)]
        });
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        let cells = &self.cells;
        let grid = Moves { cells, nx, ny, goal, start: (si, sj), escape };
        let mut expanded = 0usize;
        let mut found = false;
        while let Some(Reverse(key)) = open.pop() {
            let (f, k) = Open::unkey(key);
            let g = nodes[k].cost;
            let (x, y) = ((k as i64) % nx, (k as i64) / nx);
            if f > g + octile(x, y) + 1e-3 {
                continue; // an outdated entry
            }
            if k == goal {
                found = true;
                break;
            }
            expanded += 1;
            if expanded > self.params.max_expansions {
                break;
            }
            for &(dx, dy, diagonal) in &STEPS {
                let (mx, my) = (x + dx, y + dy);
                if mx < 0 || my < 0 || mx >= nx || my >= ny {
                    continue;
                }
                let m = (my * nx + mx) as usize;
                let cell = cells[m];
                if !grid.enterable(m, mx, my, cell) || (diagonal && grid.squeezed(x, y, mx, my)) {
                    continue;
                }
                let ng = g + step_cost[usize::from(cell & BAND)][usize::from(diagonal)];
                let node = &mut nodes[m];
                if node.stamp != gen_ || ng < node.cost {
                    *node = Node { stamp: gen_, cost: ng, parent: k as u32 };
                    open.push(Reverse(Open::key(ng + octile(mx, my), m)));
                }
            }
        }
        self.failed = !found;
        if !found {
            return;
        }
        let cost = self.scratch.nodes[goal].cost;
        // Two ways round an obstacle often cost about the same: keep going the way already
        // chosen unless the new one is clearly shorter, so that the agent does not swing
        // between them.
        if keep
            && let Some(old_cost) = self.path_cost(from, &old)
            && old_cost <= cost * (1.0 + SWITCH_SHARE) + SWITCH_M
        {
            self.path = old;
            return;
        }
        let s = &mut self.scratch;
        let mut cells = vec![goal];
        let mut k = goal;
        while k != start {
            k = s.nodes[k].parent as usize;
            cells.push(k);
        }
        cells.reverse();
        let nx = self.nx;
        self.path = cells.iter().map(|&k| self.centre((k % nx) as i64, (k / nx) as i64)).collect();
        if let Some(last) = self.path.last_mut() {
            *last = self.goal;
        }
        self.path_box =
            self.path.iter().fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    }

    /// Whether the search from cell `start` (at `(si, sj)`) can reach cell `goal` at all.
    #[inline(never)]
    fn reaches(&mut self, start: usize, goal: usize, (si, sj): (i64, i64)) -> bool {
        let s = &mut self.scratch;
        let stamp = s.begin(self.nx * self.ny);
        let nx = self.nx as i64;
        let grid =
            Moves { cells: &self.cells, nx, ny: self.ny as i64, goal, start: (si, sj), escape: self.reach_cells };
        // Depth first, the steps toward the goal tried first: where there is a way, it is
        // usually found about as fast as it is long.
        let (gx, gy) = ((goal as i64 % nx - si) as f64, (goal as i64 / nx - sj) as f64);
        let mut steps = STEPS;
        steps.sort_by(|a, b| (a.0 as f64 * gx + a.1 as f64 * gy).total_cmp(&(b.0 as f64 * gx + b.1 as f64 * gy)));
        s.nodes[start].stamp = stamp;
        let mut todo = vec![start];
        while let Some(k) = todo.pop() {
            if k == goal {
                return true;
            }
            let (x, y) = ((k as i64) % nx, (k as i64) / nx);
            for &step in &steps {
                if let Some(m) = grid.step(x, y, step)
                    && s.nodes[m].stamp != stamp
                {
                    s.nodes[m].stamp = stamp;
                    todo.push(m);
                }
            }
        }
        false
    }

    /// Extra cost per metre of crossing cell `k` (its depth in the margin).
    fn margin_cost(&self, k: usize) -> f32 {
        self.params.margin_cost as f32 * f32::from(self.cells[k] & BAND) / f32::from(BANDS)
    }

    /// Cost of following `path` from `from` under what is remembered now (as the search counts
    /// it), or `None` when it crosses a closed cell.
    fn path_cost(&self, from: DVec2, path: &[DVec2]) -> Option<f32> {
        let here = self.cell_of(from);
        let mut prev = from;
        let mut total = 0.0f32;
        for &p in path {
            let (i, j) = self.cell_of(p);
            let k = self.index(i, j)?;
            if self.cells[k] & HARD != 0 && (i, j) != here {
                return None;
            }
            let extra = self.margin_cost(k);
            total += prev.distance(p) as f32 * (1.0 + extra);
            prev = p;
        }
        Some(total)
    }

    /// The current path (world points toward the goal), for pictures.
    pub fn path(&self) -> &[DVec2] {
        &self.path
    }

    /// Number of cells where an obstacle is remembered (only grows).
    pub fn known(&self) -> usize {
        self.known
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scan of a wall along x = 2 from y = −1 to y = 5 seen from `from`, radius 0.3.
    fn wall_scan(from: DVec2) -> Vec<f64> {
        (0..72)
            .map(|i| {
                let dir = DVec2::from_angle(std::f64::consts::TAU * i as f64 / 72.0);
                if dir.x > 1e-9 {
                    let t = (2.0 - from.x) / dir.x;
                    let y = from.y + dir.y * t;
                    if (-1.0..=5.0).contains(&y) { (t - 0.3).clamp(0.0, 5.0) } else { 5.0 }
                } else {
                    5.0
                }
            })
            .collect()
    }

    #[test]
    fn remembered_walls_bend_the_way_to_the_goal() {
        let goal = DVec2::new(4.0, 0.0);
        let mut m = Memory::new(DVec2::ZERO, goal, 0.3, MemoryParams::default());
        // Nothing known: straight at the goal.
        let Aim { heading: h, remaining_m: len, .. } = m.heading(DVec2::ZERO, |_| f64::INFINITY).unwrap();
        assert!(h.abs() < 0.2 && (len - 4.0).abs() < 0.5, "{h} {len}");
        // A wall across the way: the path goes round its lower end (nearer).
        m.observe(DVec2::ZERO, &wall_scan(DVec2::ZERO), 0.3, 5.0);
        assert!(m.known() > 10);
        let aim = m.heading(DVec2::ZERO, |_| f64::INFINITY).unwrap();
        let (h, len) = (aim.heading, aim.remaining_m);
        assert!(h < -0.3, "heads for the lower end, {h}");
        assert!(len > 4.5, "{len}");
        // Deterministic.
        let mut again = Memory::new(DVec2::ZERO, goal, 0.3, MemoryParams::default());
        again.heading(DVec2::ZERO, |_| f64::INFINITY);
        again.observe(DVec2::ZERO, &wall_scan(DVec2::ZERO), 0.3, 5.0);
        assert_eq!(again.heading(DVec2::ZERO, |_| f64::INFINITY), Some(aim));
        // The world's obstacles do not move: looking again with nothing in sight forgets
        // nothing, and the way still goes round.
        let known = m.known();
        m.observe(DVec2::ZERO, &[5.0; 72], 0.3, 5.0);
        assert_eq!(m.known(), known);
        let kept = m.heading(DVec2::ZERO, |_| f64::INFINITY).unwrap();
        assert!(kept.heading < -0.3, "{kept:?}");
    }

    #[test]
    fn an_agent_against_a_wall_does_not_plan_through_it() {
        // Standing inside the wall's inflation, the agent may step out of it, but not cross
        // the wall whose far side it has never seen.
        let from = DVec2::new(1.78, 0.0);
        let goal = DVec2::new(4.0, 0.0);
        let mut m = Memory::new(from, goal, 0.3, MemoryParams::default());
        for k in 0..=48 {
            m.mark(DVec2::new(2.05, -1.0 + 0.125 * k as f64));
        }
        let aim = m.heading(from, |_| f64::INFINITY).unwrap();
        assert!(aim.remaining_m > 3.0, "{aim:?}");
        assert!(m.path().iter().all(|p| p.x < 1.9 || p.x > 2.2 || p.y < -1.0 || p.y > 5.0), "{:?}", m.path());
    }

    #[test]
    fn the_flood_finds_a_way_exactly_when_the_search_does() {
        let mut rng = crate::rng::stream(11, 0, 0);
        let mut unit = || crate::rng::unit(&mut rng);
        let goal = DVec2::new(4.0, 0.0);
        let (mut ways, mut none) = (0, 0);
        for _ in 0..60 {
            let mut m = Memory::new(DVec2::ZERO, goal, 0.3, MemoryParams::default());
            // A broken ring round the goal and scattered marks.
            let gap = unit() * std::f64::consts::TAU;
            let width = if unit() < 0.5 { 0.0 } else { 0.3 + unit() };
            for k in 0..400 {
                let a = std::f64::consts::TAU * k as f64 / 400.0;
                if (a - gap).rem_euclid(std::f64::consts::TAU) >= width {
                    m.mark(goal + DVec2::from_angle(a) * 1.5);
                }
            }
            for _ in 0..40 {
                m.mark(DVec2::new(unit() * 8.0 - 2.0, unit() * 8.0 - 4.0));
            }
            for _ in 0..5 {
                let from = DVec2::new(unit() * 8.0 - 2.0, unit() * 8.0 - 4.0);
                let (si, sj) = m.cell_of(from);
                m.include(si, sj);
                let (gi, gj) = m.cell_of(goal);
                m.include(gi, gj);
                let (si, sj) = m.cell_of(from);
                let (gi, gj) = m.cell_of(goal);
                let (start, end) = (m.index(si, sj).unwrap(), m.index(gi, gj).unwrap());
                let flood = m.reaches(start, end, (si, sj));
                m.failed = false;
                m.plan(from, false);
                assert_eq!(flood, !m.path.is_empty(), "from {from}");
                if flood {
                    ways += 1
                } else {
                    none += 1
                }
                // Once a search has found nothing, the next one goes by the flood.
                if !flood {
                    assert!(m.failed);
                    m.plan(from, false);
                    assert!(m.path.is_empty());
                }
            }
        }
        assert!(ways > 20 && none > 20, "{ways} {none}");
    }

    #[test]
    fn a_gap_too_narrow_for_the_body_is_closed_and_a_wide_one_kept() {
        // A wall along x = 2 with a 0.7 m gap at y ∈ [-0.35, 0.35] (the disc of radius 0.3
        // fits; a body that needs 0.85 m does not), and a way round its upper end.
        let from = DVec2::new(1.0, 0.0);
        let goal = DVec2::new(4.0, 0.0);
        let wall = |m: &mut Memory, gap: f64| {
            for k in 0..=128 {
                let y = -5.0 + 0.0625 * k as f64;
                if y.abs() > gap / 2.0 && y < 3.0 {
                    m.mark(DVec2::new(2.05, y));
                }
            }
        };
        let width = |gap: f64| move |p: DVec2, _: DVec2| if (p.x - 2.05).abs() < 0.3 { gap } else { 10.0 };
        let mut m = Memory::new(from, goal, 0.3, MemoryParams::default());
        wall(&mut m, 0.7);
        let through = m.heading(from, |_| f64::INFINITY).unwrap();
        assert!(through.remaining_m < 3.5, "through the gap: {through:?}");
        // The body fits: nothing is closed, the way stays.
        assert!(!m.close_gaps_ahead(from, 0.6, 0.5, width(0.7)));
        assert_eq!(m.heading(from, |_| f64::INFINITY), Some(through));
        // It does not: the gap is closed and the way goes round the wall's upper end.
        let known = m.known();
        assert!(m.close_gaps_ahead(from, 0.85, 0.5, width(0.7)));
        assert!(m.known() > known);
        let round = m.heading(from, |_| f64::INFINITY).unwrap();
        assert!(round.remaining_m > 5.0, "round the wall: {round:?}");
        assert!(m.path().iter().all(|p| (p.x - 2.05).abs() > 0.2 || p.y > 2.9), "{:?}", m.path());
        // In the open nothing is closed, however narrow the sensor says it is.
        let mut open = Memory::new(from, goal, 0.3, MemoryParams::default());
        open.heading(from, |_| f64::INFINITY);
        assert!(!open.close_gaps_ahead(from, 0.85, 0.5, |_, _| 0.0));
    }

    #[test]
    fn an_enclosed_goal_has_no_way() {
        // A ring of obstacle points around the goal, remembered from inside and out.
        let goal = DVec2::new(3.0, 0.0);
        let mut m = Memory::new(DVec2::ZERO, goal, 0.3, MemoryParams { max_expansions: 200_000, ..Default::default() });
        for k in 0..200 {
            let p = goal + DVec2::from_angle(std::f64::consts::TAU * k as f64 / 200.0) * 1.0;
            let (i, j) = m.cell_of(p);
            m.include(i, j);
            m.mark(p);
        }
        assert_eq!(m.heading(DVec2::ZERO, |_| f64::INFINITY), None);
    }
}
