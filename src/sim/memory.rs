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
//! to the middle of doors and corridors. The way to the goal is a shortest way over the grid
//! with unknown cells taken as free (planning with the free-space assumption: each new obstacle
//! either leaves the path clear or is remembered, so the agent never tries the same blocked
//! way twice and, in a finite world, reaches any goal it can reach). The search is D* Lite
//! ([`replan`]): it runs from the goal toward the agent once, and afterwards a newly marked
//! cell repairs only the distances it changes, so a plan costs what changed, not the distance
//! to the goal. The planner's goal seeking then steers toward a waypoint on that way instead
//! of straight at the goal.
//!
//! The memory is the disc's: a body that needs more room (the character keeps a margin) may
//! be held up where the grid shows a way. An agent held up in one place for long has its range
//! sensor measure the way across the path just ahead, and gaps narrower than its body passes
//! are remembered as obstacles too ([`Memory::close_gaps_ahead`]), so it plans round them.
//! A body with a narrower stance (a character side-on) has the cells only that stance crosses
//! marked [`NARROW`] instead of closed ([`Memory::with_narrowest`]): the way goes through them
//! at a high cost, and the loop has the body pass such a gap in that stance.
//!
//! The first [`KEPT_M`] of the way are kept as a path between steps (topped up from the
//! search's distances as the agent goes; beyond, the way is the search's best) and planned
//! again only when a newly remembered obstacle touches the path or the agent strays from it;
//! a new plan replaces the path only when it is clearly shorter than the kept path and the best
//! way on from its end, so two ways round an obstacle of about the same length do not take
//! turns. The remaining length is the path's plus the search's cost of the way on.
//! The waypoint is the farthest point of the path within reach in clear sight, with the margin
//! kept when that leaves one at least a metre ahead; before a door or corridor narrower than the
//! margin, the agent instead pursues the gap's middle line as its sensor measures it
//! ([`Memory::heading_with`]), so it enters along it. The grid grows as the agent explores.
//! Everything is deterministic: plain vectors, integer costs, ties broken as [`replan`] says.

mod replan;

use glam::DVec2;

use replan::{BAND, HARD, MARKED, NARROW, Replanner, UNIT};

use super::side_on::Gap;

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
    /// Most cells one plan may take from the search's queue before giving up for this step
    /// (4,000,000; the next plan goes on from there).
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
/// Rays over each half turn that find the nearest obstacle point on either side of the way when
/// a gap is measured.
const SIDE_RAYS: usize = 12;
/// Widest way across that counts as a gap to line up for, metres.
const GAP_MEASURE_M: f64 = 2.0;

/// Length of the way ahead kept as points, metres; beyond, the way follows the search's
/// distances, which repairs keep up to date.
const KEPT_M: f64 = 12.0;

/// The kept way is extended when less than this much of it is left, metres.
const REFILL_M: f64 = 6.0;

/// Cells added around the known area when the grid grows.
const GROW_CELLS: i64 = 48;

/// A side of the grid grows by at least its size over this when it grows.
const GROW_SHARE: i64 = 4;

/// Where goal seeking steers: toward a waypoint on the remembered way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aim {
    /// Direction toward the waypoint, absolute radians.
    pub heading: f64,
    /// Length of the remaining way to the goal, metres.
    pub remaining_m: f64,
    /// Distance to the waypoint, metres.
    pub waypoint_m: f64,
    /// The waypoint lines the agent up for a narrow part of the way just ahead (a gap, a door,
    /// a corridor) that the way goes through ([`Memory::heading_with`]).
    pub through_gap: bool,
    /// That narrow part as the range sensor measured it: its throat's middle, the way through
    /// and the width across.
    pub gap: Option<Gap>,
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
    /// The agent's radius, metres.
    radius: f64,
    /// A cell whose centre lies this near a remembered point is closed to the walking disc,
    /// metres ([`CLOSE_GIVE_CELLS`]).
    closed_within: f64,
    /// A cell whose centre lies this near a remembered point is closed to the body's narrowest
    /// stance, metres (`closed_within` unless [`Memory::with_narrowest`]); between the two it is
    /// [`NARROW`].
    hard_within: f64,
    /// Hits of neighbouring rays nearer each other than this are one surface, metres (none: the
    /// disc's width).
    join_m: Option<f64>,
    /// Cells a marked cell's inflation may reach, to a side.
    reach_cells: i64,
    /// How near (squared, metres², a little wide for rounding) a remembered point must come to
    /// a cell's centre to change the cell, by the cell's state (its byte in `cells`); below
    /// zero for a cell no point can change.
    change_within: Box<[f64; 256]>,
    /// The cells a point may change, by where it lies in its cell.
    stamps: std::sync::Arc<Stamps>,
    /// A new mark this near the path makes it stale, metres (radius, margin and a cell).
    stale_m: f64,
    goal: DVec2,
    /// The way ahead, world points from near the agent: to the goal, or [`KEPT_M`] of it,
    /// the rest left to the search's distances.
    path: Vec<DVec2>,
    /// Whether the path ends at the goal.
    complete: bool,
    /// Cost of the way on from the path's last point when it does not end at the goal,
    /// metres.
    tail_m: f64,
    /// Corners of a box holding every point of the path (the path only shrinks between
    /// plans and extensions).
    path_box: (DVec2, DVec2),
    /// The last search found no way to the goal.
    failed: bool,
    /// A newly marked cell lies on or near the path: plan again.
    stale: bool,
    /// Plans made so far.
    pub plans: u32,
    planner: Replanner,
}

/// Added before truncating a position in cells to take its floor: far more cells than a
/// point's cell lies from the cells it may change.
const CELLS_FLOOR: f64 = 1024.0;

/// [`Memory::change_within`] for a disc of `radius` with a clearance `margin`: a point changes
/// a cell of band `b < BANDS` only when it lies nearer its centre than
/// `radius + (BANDS − b)/BANDS · margin` (the deeper band it then gives), makes a cell neither
/// closed nor [`NARROW`] narrow or closed only nearer than `closed_within`, and closes a narrow
/// cell only nearer than `hard_within`. Widened by a relative and an absolute nanometre, so
/// rounding never leaves out a cell [`Memory::mark`]'s exact test would change.
fn change_within(radius: f64, margin: f64, closed_within: f64, hard_within: f64) -> Box<[f64; 256]> {
    Box::new(std::array::from_fn(|k| {
        let (band, closed, narrow) = (k as u8 & BAND, k as u8 & HARD != 0, k as u8 & NARROW != 0);
        let deeper = (band < BANDS).then(|| radius + f64::from(BANDS - band) * margin / f64::from(BANDS));
        let close = match (closed, narrow) {
            (true, _) => None,
            (false, true) => Some(hard_within),
            (false, false) => Some(closed_within),
        };
        match deeper.into_iter().chain(close).fold(f64::NEG_INFINITY, f64::max) {
            lim if lim > 0.0 => (lim * (1.0 + 1e-9) + 1e-9).powi(2),
            _ => f64::NEG_INFINITY,
        }
    }))
}

/// Extra cost per cell side of a step into a [`NARROW`] cell (a side-on passage takes a stop,
/// two pivots and side steps: the way goes round unless that is about this much longer).
const NARROW_COST: f64 = 40.0;

/// The closing bits a point `d` metres from a cell's centre gives it: [`HARD`] within
/// `hard_within`, [`NARROW`] within `closed_within`.
#[inline(always)]
fn closing(d: f64, closed_within: f64, hard_within: f64) -> u8 {
    if d < hard_within {
        HARD
    } else if d < closed_within {
        NARROW
    } else {
        0
    }
}

/// Sides of the squares a cell is cut into for [`Stamps`].
const STAMP_SIDES: usize = 16;

/// The cells whose centres may lie within a distance of a point, by where the point lies in its
/// cell: for each of the [`STAMP_SIDES`]² squares the cell is cut into, the rows of cells, each
/// as its offset and its first and last column's, relative to the cell whose centre is the
/// nearest below and left of the point. A cell is listed when its centre lies within the
/// distance, widened by a micro-cell, of some point of the square, so every cell within the
/// distance of the point itself is, whatever the rounding.
#[derive(Debug, Clone)]
struct Stamps {
    /// Every square's rows, one square after the other.
    rows: Vec<(i32, i32, i32)>,
    /// Where each square's rows start in `rows`, and where the last one's end.
    start: Vec<u32>,
}

impl Stamps {
    /// The stamps for a distance of `spread` cells.
    fn new(spread: f64) -> Stamps {
        let n = STAMP_SIDES as f64;
        let spread = spread + 1e-6;
        let most = spread.ceil() as i32 + 1;
        // Nearest a centre at offset `d` comes to a point at offsets `lo..=hi` from the cell's.
        let gap = |d: i32, lo: f64, hi: f64| {
            let d = f64::from(d);
            if d < lo {
                lo - d
            } else if d > hi {
                d - hi
            } else {
                0.0
            }
        };
        let mut rows = Vec::new();
        let mut start = vec![0u32];
        for sy in 0..STAMP_SIDES {
            let (ylo, yhi) = (sy as f64 / n - 1e-6, (sy + 1) as f64 / n + 1e-6);
            for sx in 0..STAMP_SIDES {
                let (xlo, xhi) = (sx as f64 / n - 1e-6, (sx + 1) as f64 / n + 1e-6);
                for dj in -most..=most + 1 {
                    let ey = gap(dj, ylo, yhi);
                    let within = |di: i32| gap(di, xlo, xhi).powi(2) + ey * ey < spread * spread;
                    let mut cols = (-most..=most + 1).filter(|&di| within(di));
                    if let Some(lo) = cols.next() {
                        let hi = cols.next_back().unwrap_or(lo);
                        rows.push((dj, lo, hi));
                    }
                }
                start.push(rows.len() as u32);
            }
        }
        Stamps { rows, start }
    }

    /// [`Stamps::new`], made once for each distance and shared (every agent of a run has the
    /// same).
    fn shared(spread: f64) -> std::sync::Arc<Stamps> {
        static MADE: std::sync::Mutex<Vec<(u64, std::sync::Arc<Stamps>)>> = std::sync::Mutex::new(Vec::new());
        let mut made = MADE.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, stamps)) = made.iter().find(|(bits, _)| *bits == spread.to_bits()) {
            return stamps.clone();
        }
        let stamps = std::sync::Arc::new(Stamps::new(spread));
        made.push((spread.to_bits(), stamps.clone()));
        stamps
    }

    /// The rows for a point `(u, v)` cells right of and above its cell's centre (each about
    /// in `[0, 1)`).
    #[inline]
    fn rows(&self, u: f64, v: f64) -> &[(i32, i32, i32)] {
        let side = |w: f64| ((w * STAMP_SIDES as f64) as usize).min(STAMP_SIDES - 1);
        let k = side(v) * STAMP_SIDES + side(u);
        &self.rows[self.start[k] as usize..self.start[k + 1] as usize]
    }
}

/// A cell is closed when its centre lies within the disc's radius less this share of a cell of
/// a point seen: a gap three quarters of a cell wider than the disc (0.69 m for the 0.6 m disc)
/// then always keeps a cell centre open across it, however the grid falls, and stays open. A
/// gap down to a quarter of a cell narrower than the disc may look open; an agent held up
/// there closes it ([`Memory::close_gaps_ahead`]).
const CLOSE_GIVE_CELLS: f64 = 0.125;

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
        let closed_within = radius.max(0.0) - CLOSE_GIVE_CELLS * c;
        let within = change_within(radius.max(0.0), params.margin_m.max(0.0), closed_within, closed_within);
        // The widest distance a point changes a cell from (an empty cell's): the same for every
        // stance (`with_narrowest` only narrows what closes a narrow cell).
        let stamps = Stamps::shared(within[0].max(0.0).sqrt() / c);
        Memory {
            params: MemoryParams { cell_m: c, ..params },
            origin,
            nx,
            ny,
            cells: vec![0; nx * ny],
            known: 0,
            radius: radius.max(0.0),
            closed_within,
            hard_within: closed_within,
            join_m: None,
            reach_cells,
            change_within: within,
            stamps,
            stale_m: radius.max(0.0) + params.margin_m + c,
            goal,
            path: Vec::new(),
            complete: false,
            tail_m: 0.0,
            path_box: (DVec2::ZERO, DVec2::ZERO),
            failed: false,
            stale: true,
            plans: 0,
            planner: Replanner::new(replan::step_costs(params.margin_cost, BANDS, NARROW_COST)),
        }
    }

    /// The memory of a body whose narrowest stance passes gaps down to `passage_m` wide (a
    /// character side-on): cells the walking disc may not cross but that stance may are
    /// [`NARROW`] instead of closed, and cost [`NARROW_COST`] more per cell side, so the way
    /// goes through such a gap only when going round is much longer. A gap a cell wider than
    /// `passage_m` always keeps a cell centre open to it, however the grid falls. Only hits of
    /// neighbouring rays nearer each other than `passage_m` are taken as one surface.
    pub fn with_narrowest(mut self, passage_m: f64) -> Memory {
        let c = self.params.cell_m;
        self.hard_within = (0.5 * (passage_m - c)).clamp(0.0, self.closed_within.max(0.0));
        self.join_m = Some(passage_m.max(0.0));
        self.change_within =
            change_within(self.radius, self.params.margin_m.max(0.0), self.closed_within, self.hard_within);
        self
    }

    /// Whether the way ahead from the path's start to `within_m` along it crosses a [`NARROW`] cell.
    pub fn narrow_ahead(&self, within_m: f64) -> bool {
        let mut along = 0.0;
        for (k, &p) in self.path.iter().enumerate() {
            if k > 0 {
                along += self.path[k - 1].distance(p);
            }
            if along > within_m {
                break;
            }
            let (i, j) = self.cell_of(p);
            if self.index(i, j).is_some_and(|c| self.cells[c] & NARROW != 0 && self.cells[c] & HARD == 0) {
                return true;
            }
        }
        false
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
        // A side grows by a share of the grid as well, so that an agent exploring far from
        // where it started copies the grid a number of times that grows only with the log of
        // its size.
        let (gx, gy) = (GROW_CELLS.max(nx / GROW_SHARE), GROW_CELLS.max(ny / GROW_SHARE));
        let lo_x = (i - gx).min(0);
        let lo_y = (j - gy).min(0);
        let hi_x = (i + gx + 1).max(nx);
        let hi_y = (j + gy + 1).max(ny);
        let (wx, wy) = ((hi_x - lo_x) as usize, (hi_y - lo_y) as usize);
        let mut cells = vec![0u8; wx * wy];
        for y in 0..ny {
            let from = (y * nx) as usize;
            let to = ((y - lo_y) as usize) * wx + (-lo_x) as usize;
            cells[to..to + nx as usize].copy_from_slice(&self.cells[from..from + nx as usize]);
        }
        self.origin -= DVec2::new(-lo_x as f64, -lo_y as f64) * self.params.cell_m;
        self.planner.grow(self.nx, self.ny, wx, wy, ((-lo_x) as usize, (-lo_y) as usize));
        (self.nx, self.ny, self.cells) = (wx, wy, cells);
        // Cells the path passes keep their world positions; the plan stays valid.
    }

    /// Remembers an obstacle at `p`: its cell is marked, and the cells around are closed or
    /// dearer by their centres' distance from `p` itself (not from the marked cell's centre,
    /// which may lie most of a cell away from what was seen).
    fn mark(&mut self, p: DVec2) {
        if !p.is_finite() {
            return;
        }
        let (i, j) = self.cell_of(p);
        let Some(k) = self.index(i, j) else { return };
        let mut changed = self.cells[k] & MARKED == 0;
        if changed {
            self.cells[k] |= MARKED;
            self.known += 1;
            self.planner.changed(k);
        }
        let c = self.params.cell_m;
        let (radius, margin) = (self.radius, self.params.margin_m.max(0.0));
        let (closed_within, hard_within) = (self.closed_within, self.hard_within);
        // Most cells around a surface seen again are already as deep as this point makes
        // them: a cell can only change within the distance its state still allows
        // (`self.change_within`, squared, a little wide for rounding), so the exact band is
        // worked out only for cells nearer than that. Only the cells whose centres may lie
        // within the widest of those distances (an empty cell's) are visited, row by row as
        // the stamp for where `p` lies in its cell lists them.
        let reach = self.reach_cells;
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        let (ox, oy) = (self.origin.x, self.origin.y);
        // `p` in cells from the centre of cell 0 (`cells_floor` is the floor near the grid).
        let (fx, fy) = ((p.x - ox) / c - 0.5, (p.y - oy) / c - 0.5);
        let cells_floor = |x: f64| (x + CELLS_FLOOR) as i64 - CELLS_FLOOR as i64;
        let (i0, j0) = (cells_floor(fx), cells_floor(fy));
        let rows = ((j - reach).max(0), (j + reach).min(ny - 1));
        let (cols_lo, cols_hi) = ((i - reach).max(0), (i + reach).min(nx - 1));
        let Memory { cells, planner, change_within, stamps, .. } = self;
        for &(dj, dlo, dhi) in stamps.rows(fx - i0 as f64, fy - j0 as f64) {
            let jj = j0 + i64::from(dj);
            if jj < rows.0 || jj > rows.1 {
                continue;
            }
            // The same centre as `self.centre(_, jj)`, and the same distance as `distance`.
            let qy = (oy + (jj as f64 + 0.5) * c) - p.y;
            let qy2 = qy * qy;
            let lo = (i0 + i64::from(dlo)).max(cols_lo);
            let hi = (i0 + i64::from(dhi)).min(cols_hi);
            if lo > hi {
                continue;
            }
            let row = jj as usize * nx as usize;
            // A first test of the whole row at once, with the centres stepped from the row's
            // first (rounding far below the nanometre `change_within` leaves) and no branch,
            // gives the cells that may change; the exact test follows for those alone, with
            // each centre as `self.centre` gives it.
            let qx_lo = (ox + (lo as f64 + 0.5) * c) - p.x;
            let span = &mut cells[row + lo as usize..=row + hi as usize];
            for (chunk, part) in span.chunks_mut(64).enumerate() {
                let mut near = 0u64;
                for (at, &cell) in part.iter().enumerate() {
                    let qx = qx_lo + (chunk * 64 + at) as f64 * c;
                    near |= u64::from(qx * qx + qy2 < change_within[usize::from(cell)]) << at;
                }
                while near != 0 {
                    let at = near.trailing_zeros() as usize;
                    near &= near - 1;
                    let cell = &mut part[at];
                    let old = *cell;
                    let within = change_within[usize::from(old)];
                    let ii = lo + (chunk * 64 + at) as i64;
                    let qx = (ox + (ii as f64 + 0.5) * c) - p.x;
                    let d2 = qx * qx + qy2;
                    if !(d2 < within) {
                        continue;
                    }
                    let d = d2.sqrt();
                    if d >= radius + margin {
                        continue;
                    }
                    // `(x as u8)` is `x.floor()` for the non-negative `x` here (and 0 for NaN, as
                    // the clamp of a NaN floor gives).
                    let beyond = ((d - radius).max(0.0) / margin.max(1e-9) * f64::from(BANDS)) as u8;
                    let band = BANDS - beyond.min(BANDS - 1);
                    let new = (old & !BAND) | (old & BAND).max(band) | closing(d, closed_within, hard_within);
                    if new != old {
                        *cell = new;
                        planner.changed(row + ii as usize);
                        changed = true;
                    }
                }
            }
        }
        if changed && !self.stale {
            // Does what changed come near the path?
            let (lo, hi) = self.path_box;
            // Off the path's box by more than the distance (and rounding), it is near no point.
            let off = (lo - p).max(p - hi).max_element();
            // The distance is worked out only for a point whose squared distance leaves it in
            // doubt.
            let (near2, far2) = ((self.stale_m * (1.0 - 1e-9)).powi(2), (self.stale_m * (1.0 + 1e-9)).powi(2));
            let near = |q: &DVec2| {
                let d2 = q.distance_squared(p);
                d2 <= near2 || (d2 <= far2 && q.distance(p) <= self.stale_m)
            };
            if off <= self.stale_m + 1e-9 && self.path.iter().any(near) {
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
            if len >= self.join_m.unwrap_or(2.0 * radius) {
                continue;
            }
            let steps = (len / (0.5 * c)).ceil() as usize;
            self.mark_between(pa, pb, steps);
        }
    }

    /// [`Memory::mark`] of the points `pa + (pb − pa)·s/steps`, `s` in `1..steps`, one after
    /// the other (with the stamps, cheaper than visiting the cells around the whole segment at
    /// once).
    fn mark_between(&mut self, pa: DVec2, pb: DVec2, steps: usize) {
        for s in 1..steps {
            self.mark(pa + (pb - pa) * (s as f64 / steps as f64));
        }
    }

    /// Where to steer from `from` along the path to the goal, planned again when needed.
    /// `sight(heading)` is how far the agent sees its way free along an absolute heading now
    /// (infinite when nothing limits it): a waypoint beyond it is taken only when no waypoint
    /// in sight is left. `None` when the goal cannot be reached over what is remembered (or
    /// the search gives up).
    pub fn heading(&mut self, from: DVec2, sight: impl Fn(f64) -> f64) -> Option<Aim> {
        self.heading_with(from, sight, |_, _, out: &mut [f64]| out.fill(f64::INFINITY), |_| f64::INFINITY)
    }

    /// [`Memory::heading`] with `span(p, units, out)`, how far the way is free from `p` along
    /// each of `units` into `out` (the range sensor's measure; infinite when nothing is near),
    /// which puts the line a gap
    /// is entered along through the middle of the gap as measured, not of the grid's cells, and
    /// `reach(heading)`, how far the bare disc can go straight along an absolute heading now
    /// (infinite when nothing limits it), which decides whether an agent standing in the
    /// inflation of a gap's post can go straight onto the gap's line.
    pub fn heading_with(
        &mut self,
        from: DVec2,
        sight: impl Fn(f64) -> f64,
        span: impl FnMut(DVec2, &[DVec2], &mut [f64]),
        reach: impl Fn(f64) -> f64,
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
        // Drop what is behind, and look far enough ahead.
        self.path.drain(..start);
        self.refill(from);
        if self.path.is_empty() {
            return None;
        }
        // A narrow part of the way ahead (a door, a corridor) is entered along its own line;
        // elsewhere the waypoint is the farthest one in sight.
        let (waypoint, gap) = match self.line_up(from, span, &reach) {
            Some((p, gap)) => (p, Some(gap)),
            None => (self.farthest_waypoint(from, sight, &reach), None),
        };
        let through_gap = gap.is_some();
        let remaining: f64 =
            from.distance(self.path[0]) + self.path.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>() + self.tail_m;
        let to = waypoint - from;
        if to.length() < 1e-9 {
            let to = self.goal - from;
            return Some(Aim {
                heading: to.to_angle(),
                remaining_m: remaining,
                waypoint_m: to.length(),
                through_gap,
                gap,
            });
        }
        Some(Aim { heading: to.to_angle(), remaining_m: remaining, waypoint_m: to.length(), through_gap, gap })
    }

    /// The waypoint: the farthest point of the path within reach that the disc can go straight
    /// to from `from` without touching what is remembered (with the margin if it can), so that
    /// steering toward it never cuts a corner into a wall; else the next point.
    fn farthest_waypoint(&self, from: DVec2, sight: impl Fn(f64) -> f64, bare: &impl Fn(f64) -> f64) -> DVec2 {
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
            let Some(depth) = self.sight_depth(from, p, bare, HARD | NARROW) else { continue };
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
    /// the gap already), and over the path's next [`GAP_AXIS_M`] `span` (rays) finds the
    /// nearest obstacle points on either side of the way: where they are closest together is
    /// the gap's throat, and the gap's line runs square to them through their middle. The
    /// agent pursues that line: it aims at the point of the line [`PURSUIT_M`] beyond its own
    /// projection on it, so it comes onto the line in front of the gap, along it, and passes
    /// through the middle — steering continuously, never one way and then the other. `None`
    /// when no gap measured narrower than [`GAP_MEASURE_M`] lies ahead or the point is not in
    /// clear sight (over what is remembered, or, out of the inflation the agent stands in, by
    /// `reach`).
    fn line_up(
        &self,
        from: DVec2,
        mut span: impl FnMut(DVec2, &[DVec2], &mut [f64]),
        reach: &impl Fn(f64) -> f64,
    ) -> Option<(DVec2, Gap)> {
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
        // The middle of the gap as measured across it, at its narrowest over the path's first
        // [`GAP_AXIS_M`] past the entry (the throat: between two posts the rays across the
        // entry may pass them both) and (in a corridor) a little further on: the line through
        // both is the gap's, whatever cells the path takes.
        // The gap as the range sensor measures it from a point of the way: the nearest
        // obstacle point on either side of the path (rays over each half turn), the way across
        // between the two. Rays square to the path alone would miss a thin row of posts the
        // grid's path crosses aslant.
        let units: [DVec2; 2 * (SIDE_RAYS + 1)] = std::array::from_fn(|k| {
            let (side, k) = if k <= SIDE_RAYS { (dir.perp(), k) } else { (-dir.perp(), k - SIDE_RAYS - 1) };
            let turn = std::f64::consts::PI * (k as f64 / SIDE_RAYS as f64 - 0.5);
            DVec2::from_angle(turn).rotate(side)
        });
        let mut spans = [0.0; 2 * (SIDE_RAYS + 1)];
        let mut measure = |p: DVec2| {
            span(p, &units, &mut spans);
            let mut near = [None::<DVec2>; 2];
            for (s, n) in near.iter_mut().enumerate() {
                for k in s * (SIDE_RAYS + 1)..(s + 1) * (SIDE_RAYS + 1) {
                    let (u, d) = (units[k], spans[k]);
                    if d.is_finite() && n.is_none_or(|q: DVec2| d < q.distance(p)) {
                        *n = Some(p + u * d);
                    }
                }
            }
            let [Some(l), Some(r)] = near else { return None };
            let w = l.distance(r);
            (w < GAP_MEASURE_M && w > 1e-9).then(|| (w, 0.5 * (l + r), (l - r) / w))
        };
        let mut throat: Option<(f64, DVec2, DVec2, DVec2)> = None;
        let mut run = 0.0;
        for (j, &p) in self.path[k..].iter().enumerate() {
            if j > 0 {
                run += self.path[k + j - 1].distance(p);
            }
            if run > GAP_AXIS_M {
                break;
            }
            if let Some((w, m, across)) = measure(p)
                && throat.is_none_or(|(best, ..)| w < best - 1e-9)
            {
                throat = Some((w, m, p, across));
            }
        }
        let (width, centre, at, across) = throat?;
        // The gap's line is square to the way across it, pointing the way the path goes.
        let square = if across.perp().dot(dir) >= 0.0 { across.perp() } else { -across.perp() };
        let line = match measure(at + square * GAP_AXIS_M) {
            Some((_, further, _)) if (further - centre).normalize_or_zero().dot(square) > SAME_LINE_COS => {
                (further - centre).normalize()
            }
            _ => square,
        };
        let target = centre + line * (line.dot(from - centre) + PURSUIT_M);
        // The agent may stand in the inflation of the gap's posts.
        // The gap itself is crossed square to its throat (the line beyond may bend away).
        // A gap open only to the body's narrowest stance is lined up for all the same.
        self.sight_depth(from, target, &reach, HARD).map(|_| (target, Gap { centre, through: square, width }))
    }

    /// [`Memory::line_depth`] for an agent at `from` that may stand in or beside the inflation
    /// of what it remembers, where the way out crosses closed cells (as the search lets it, near
    /// where it stands): a line that crosses closed cells only there, never a remembered
    /// obstacle, and that the disc, as its sensor shows it now (`reach`, as for
    /// [`Memory::heading_with`]), goes straight along to `to`, counts as clear, deep in the
    /// margin. A cell is closed to the line when it has any of the bits `closed` ([`HARD`], and
    /// [`NARROW`] for a line the walking disc follows).
    fn sight_depth(&self, from: DVec2, to: DVec2, reach: &impl Fn(f64) -> f64, closed: u8) -> Option<u8> {
        self.line_depth(from, to, closed).or_else(|| {
            let d = to - from;
            (self.escapes(from, to, closed) && reach(d.to_angle()) >= d.length()).then_some(BANDS)
        })
    }

    /// Whether the straight line from `a` to `b` crosses closed cells only within the search's
    /// escape reach of `a`'s cell and none where an obstacle was seen.
    fn escapes(&self, a: DVec2, b: DVec2, closed: u8) -> bool {
        let step = 0.5 * self.params.cell_m;
        let n = (a.distance(b) / step).ceil().max(1.0) as usize;
        let here = self.cell_of(a);
        (1..=n).all(|k| {
            let (i, j) = self.cell_of(a + (b - a) * (k as f64 / n as f64));
            let Some(c) = self.index(i, j) else { return true };
            let cell = self.cells[c];
            let near = (i - here.0).abs().max((j - here.1).abs()) <= self.reach_cells;
            cell & closed == 0 || (near && cell & MARKED == 0)
        })
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
            if dir != DVec2::ZERO {
                let w = width(p, dir.perp());
                if w < passage {
                    close.push((p, w));
                }
            }
        }
        for &(p, w) in &close {
            if self.join_m.is_some_and(|narrowest| w < narrowest) {
                self.seal(p);
            } else {
                self.mark(p);
            }
        }
        self.stale |= !close.is_empty();
        !close.is_empty()
    }

    /// Remembers an obstacle at `p` ([`Memory::mark`]) and closes every cell the walking disc
    /// may not cross for it, even to the body's narrowest stance: a gap measured too narrow for
    /// that stance as well.
    pub fn seal(&mut self, p: DVec2) {
        self.mark(p);
        let (i, j) = self.cell_of(p);
        let reach = (self.closed_within.max(0.0) / self.params.cell_m).ceil() as i64 + 1;
        for jj in j - reach..=j + reach {
            for ii in i - reach..=i + reach {
                let Some(k) = self.index(ii, jj) else { continue };
                if self.cells[k] & HARD == 0 && self.centre(ii, jj).distance(p) < self.closed_within {
                    self.cells[k] |= HARD;
                    self.planner.changed(k);
                    self.stale = true;
                }
            }
        }
    }

    /// The deepest band of the margin the straight line from `a` to `b` crosses, or `None`
    /// when it crosses a closed cell (the cell the agent stands in does not count, nor, for
    /// the margin, cells within the agent's first stride).
    fn line_depth(&self, a: DVec2, b: DVec2, closed: u8) -> Option<u8> {
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
            if self.cells[c] & closed != 0 {
                return None;
            }
            if q.distance(a) > STRIDE_M {
                depth = depth.max(self.cells[c] & BAND);
            }
        }
        Some(depth)
    }

    /// Plans the way from `from` to the goal over the grid (unknown cells free, hard cells
    /// closed, cells in the margin dearer): the search settles the agent's cell, and the path
    /// follows its distances for [`KEPT_M`] (the goal itself last when it gets there). With
    /// `keep`, the current way (its path, then the search's best way on from the path's end)
    /// stays unless the new one is clearly shorter.
    fn plan(&mut self, from: DVec2, keep: bool) {
        self.plans += 1;
        self.stale = false;
        let old = std::mem::take(&mut self.path);
        let (gi, gj) = self.cell_of(self.goal);
        self.include(gi, gj);
        let (si, sj) = self.cell_of(from);
        self.include(si, sj);
        let (gi, gj) = self.cell_of(self.goal);
        let start = self.cell_of(from);
        if !self.planner.ready() {
            self.planner.begin(self.nx, self.ny, (gi, gj), start, self.reach_cells);
        }
        // After a search that found no way, the next is likely to find none either: a plain
        // flood over the same moves tells at a fraction of the search's cost.
        if self.failed && !self.planner.reaches(&self.cells, start) {
            return;
        }
        // No way is shorter than the straight octile distance: when the kept way reaches the
        // goal within the switching allowance of that, no new plan could replace it, and the
        // search waits for a plan that could.
        let (gi, gj) = self.cell_of(self.goal);
        let octile = {
            let (dx, dy) = ((start.0 - gi).abs() as f64, (start.1 - gj).abs() as f64);
            self.params.cell_m * (dx.max(dy) + (std::f64::consts::SQRT_2 - 1.0) * dx.min(dy))
        } as f32;
        if keep
            && self.complete
            && !old.is_empty()
            && let Some(old_cost) = self.path_cost(from, &old)
            && old_cost <= octile * (1.0 - 2e-4) * (1.0 + SWITCH_SHARE) + SWITCH_M
        {
            self.path = old;
            return;
        }
        let budget = self.params.max_expansions;
        let Some(cost) = self.planner.settle(&self.cells, start, start, budget) else {
            self.failed = true;
            return;
        };
        self.failed = false;
        let cost = self.metres(cost) as f32;
        // Two ways round an obstacle often cost about the same: keep going the way already
        // chosen unless the new one is clearly shorter, so that the agent does not swing
        // between them.
        if keep
            && let Some(old_cost) = self.way_cost(from, &old)
            && old_cost <= cost * (1.0 + SWITCH_SHARE) + SWITCH_M
        {
            self.path = old;
            return;
        }
        self.path.clear();
        self.complete = false;
        self.extend(start);
    }

    /// Metres of `cost` units of the search.
    fn metres(&self, cost: u32) -> f64 {
        f64::from(cost) * self.params.cell_m / f64::from(UNIT)
    }

    /// Cost of following `path` from `from` and then the search's best way on from its end
    /// (as the search counts it), or `None` when it crosses a closed cell or no way goes on.
    fn way_cost(&mut self, from: DVec2, path: &[DVec2]) -> Option<f32> {
        let along = self.path_cost(from, path)?;
        if self.complete {
            return Some(along);
        }
        let end = self.cell_of(*path.last()?);
        self.index(end.0, end.1)?;
        let on = self.planner.settle(&self.cells, self.cell_of(from), end, self.params.max_expansions)?;
        Some(along + self.metres(on) as f32)
    }

    /// Extends the path from the settled cell `end` (its last point's, or the agent's when it is
    /// empty) along the search's distances to [`KEPT_M`] of way, or to the goal.
    fn extend(&mut self, end: (i64, i64)) {
        let most = (KEPT_M / self.params.cell_m).ceil() as usize;
        // The way goes on as its last step went.
        let heading = match self.path[..] {
            [.., a, b] => {
                let ((ai, aj), (bi, bj)) = (self.cell_of(a), self.cell_of(b));
                Some((bi - ai, bj - aj)).filter(|&(di, dj)| di.abs() <= 1 && dj.abs() <= 1 && (di, dj) != (0, 0))
            }
            _ => None,
        };
        let cells = self.planner.descend(&self.cells, end, most.saturating_sub(self.path.len()), heading);
        let skip = usize::from(!self.path.is_empty());
        let nx = self.nx;
        for &k in &cells[skip..] {
            self.path.push(self.centre((k % nx) as i64, (k / nx) as i64));
        }
        let last = *cells.last().unwrap_or(&0);
        let (gi, gj) = self.cell_of(self.goal);
        self.complete = self.index(gi, gj) == Some(last);
        self.tail_m = if self.complete { 0.0 } else { self.metres(self.planner.distance(last)) };
        if self.complete
            && let Some(p) = self.path.last_mut()
        {
            *p = self.goal;
        }
        self.path_box =
            self.path.iter().fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    }

    /// Tops the path up to [`KEPT_M`] when less than [`REFILL_M`] of it is left and it does
    /// not reach the goal; a way that no longer goes on is planned again.
    fn refill(&mut self, from: DVec2) {
        if self.complete || self.path.is_empty() {
            return;
        }
        let left: f64 = from.distance(self.path[0]) + self.path.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
        if left >= REFILL_M {
            return;
        }
        let end = self.cell_of(self.path[self.path.len() - 1]);
        let agent = self.cell_of(from);
        if self.index(end.0, end.1).is_none() || self.index(agent.0, agent.1).is_none() {
            return;
        }
        match self.planner.settle(&self.cells, agent, end, self.params.max_expansions) {
            Some(_) => self.extend(end),
            None => self.plan(from, false),
        }
    }

    /// Extra cost per metre of crossing cell `k` (its depth in the margin).
    fn margin_cost(&self, k: usize) -> f32 {
        let narrow = if self.cells[k] & NARROW != 0 { NARROW_COST as f32 } else { 0.0 };
        self.params.margin_cost as f32 * f32::from(self.cells[k] & BAND) / f32::from(BANDS) + narrow
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
    fn a_stamp_lists_every_cell_within_its_distance() {
        let mut rng = crate::rng::stream(13, 0, 0);
        let mut unit = || crate::rng::unit(&mut rng);
        for spread in [0.4, 1.0, 3.6, 5.3] {
            let stamps = Stamps::new(spread);
            for _ in 0..2000 {
                let (u, v) = (unit(), unit());
                let rows = stamps.rows(u, v);
                for dj in -8..=9 {
                    for di in -8..=9 {
                        let (x, y) = (f64::from(di) - u, f64::from(dj) - v);
                        let listed = rows.iter().any(|&(j, lo, hi)| j == dj && (lo..=hi).contains(&di));
                        assert!(listed || x * x + y * y >= spread * spread, "{spread} {u} {v} {di} {dj}");
                    }
                }
            }
        }
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
                m.index(si, sj).unwrap();
                m.index(gi, gj).unwrap();
                if !m.planner.ready() {
                    m.planner.begin(m.nx, m.ny, (gi, gj), (si, sj), m.reach_cells);
                }
                let flood = m.planner.reaches(&m.cells, (si, sj));
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
