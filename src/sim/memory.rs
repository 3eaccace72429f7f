//! What an agent remembers of what it has sensed, and the way to the goal over it (seed 000
//! §3.1 needs no map; TangentBug's local tangent graph already keeps what the sensor shows —
//! this keeps it for the whole episode).
//!
//! The memory is a grid of cells over the plane. Every all-around scan marks the cell of each
//! obstacle point a ray hit — and the cells between the hits of neighbouring rays closer than
//! the disc's width, which must be one surface — and wears down the evidence of the cells the
//! rays crossed freely: a cell is forgotten after [`EVIDENCE`] free crossings with no hit in
//! between (so another agent that walked away is forgotten, while a cell holding the face of a
//! wall, which rays grazing the wall cross, is not). Cells near a marked cell are inflated for
//! the agent's disc: within the hard radius they cannot be crossed, within the soft radius (a
//! clearance margin) they cost more. The way to the goal is an A* path over the grid with unknown cells taken as free
//! (planning with the free-space assumption: each new obstacle either leaves the path clear or
//! is remembered, so the agent never tries the same blocked way twice and, in a finite world,
//! reaches any goal it can reach). The planner's goal seeking then steers toward a waypoint on
//! that path instead of straight at the goal.
//!
//! The path is kept between steps and planned again only when a newly remembered obstacle
//! touches it or the agent strays from it, so a step costs what is near the agent, not the
//! size of the map; a new plan replaces the path only when it is clearly shorter, so two ways
//! round an obstacle of about the same length do not take turns. The waypoint is the farthest
//! point of the path within reach in clear sight, with the margin kept when that leaves one at
//! least a metre ahead. The grid grows as the agent explores. Everything is deterministic: plain
//! vectors, ties broken by cell index.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

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

/// Free crossings of a marked cell (with no hit in between) that clear it: a cell holding part
/// of a wall is crossed by rays grazing the wall, a cell another agent has left is crossed by
/// every ray toward it.
const EVIDENCE: u8 = 3;

/// A new path replaces the current one only when it is shorter by this share of its cost plus
/// [`SWITCH_M`] metres.
const SWITCH_SHARE: f32 = 0.1;

/// See [`SWITCH_SHARE`].
const SWITCH_M: f32 = 1.0;

/// Least distance to a waypoint chosen for keeping the clearance margin, metres.
const MIN_ROOMY_WAYPOINT_M: f64 = 1.0;

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
    /// A ray hit an obstacle in this cell.
    marked: Vec<bool>,
    /// Evidence left for a marked cell: set by a hit, worn down by rays crossing the cell.
    evidence: Vec<u8>,
    /// A ray has ever hit an obstacle in this cell.
    ever: Vec<bool>,
    /// Cells in `ever`.
    known: usize,
    /// Marked cells within the hard radius.
    hard: Vec<u16>,
    /// Marked cells within the soft radius.
    soft: Vec<u16>,
    hard_offsets: Vec<(i64, i64)>,
    soft_offsets: Vec<(i64, i64)>,
    goal: DVec2,
    /// The current path, world points from near the agent to the goal.
    path: Vec<DVec2>,
    /// A newly marked cell lies on or near the path: plan again.
    stale: bool,
    /// Plans made so far.
    pub plans: u32,
    scratch: Search,
}

/// Reused A* state (generation stamps avoid clearing the arrays).
#[derive(Debug, Clone, Default)]
struct Search {
    stamp: Vec<u32>,
    generation: u32,
    cost: Vec<f32>,
    parent: Vec<u32>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Open {
    f: f32,
    cell: u32,
}

impl Eq for Open {}

impl Ord for Open {
    fn cmp(&self, other: &Self) -> Ordering {
        // A min-heap on f, ties by cell index.
        other.f.total_cmp(&self.f).then(other.cell.cmp(&self.cell))
    }
}

impl PartialOrd for Open {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

fn disc_offsets(radius_cells: f64) -> Vec<(i64, i64)> {
    let r = radius_cells.ceil() as i64;
    let mut out = Vec::new();
    for dy in -r..=r {
        for dx in -r..=r {
            if ((dx * dx + dy * dy) as f64) <= radius_cells * radius_cells {
                out.push((dx, dy));
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
        // A cell is hard-blocked when a marked cell's centre is within the radius (gaps the
        // disc does not fit through close; doors it fits through stay open), soft within
        // radius + margin.
        let hard_offsets = disc_offsets((radius / c).max(0.0));
        let soft_offsets = disc_offsets((radius + params.margin_m) / c);
        Memory {
            params: MemoryParams { cell_m: c, ..params },
            origin,
            nx,
            ny,
            marked: vec![false; nx * ny],
            evidence: vec![0; nx * ny],
            ever: vec![false; nx * ny],
            known: 0,
            hard: vec![0; nx * ny],
            soft: vec![0; nx * ny],
            hard_offsets,
            soft_offsets,
            goal,
            path: Vec::new(),
            stale: true,
            plans: 0,
            scratch: Search::default(),
        }
    }

    fn cell_of(&self, p: DVec2) -> (i64, i64) {
        let q = (p - self.origin) / self.params.cell_m;
        (q.x.floor() as i64, q.y.floor() as i64)
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
        let mut marked = vec![false; wx * wy];
        let mut ever = vec![false; wx * wy];
        let mut evidence = vec![0u8; wx * wy];
        let mut hard = vec![0u16; wx * wy];
        let mut soft = vec![0u16; wx * wy];
        for y in 0..ny {
            for x in 0..nx {
                let from = (y * nx + x) as usize;
                let to = ((y - lo_y) as usize) * wx + (x - lo_x) as usize;
                marked[to] = self.marked[from];
                ever[to] = self.ever[from];
                evidence[to] = self.evidence[from];
                hard[to] = self.hard[from];
                soft[to] = self.soft[from];
            }
        }
        self.origin -= DVec2::new(-lo_x as f64, -lo_y as f64) * self.params.cell_m;
        (self.nx, self.ny, self.marked, self.ever, self.hard, self.soft) = (wx, wy, marked, ever, hard, soft);
        self.evidence = evidence;
        // Cells the path passes keep their world positions; the plan stays valid.
    }

    /// A ray crossed cell `(i, j)` freely: one less piece of evidence for its obstacle.
    fn wear(&mut self, i: i64, j: i64) {
        let Some(k) = self.index(i, j) else { return };
        if self.marked[k] {
            self.evidence[k] = self.evidence[k].saturating_sub(1);
            if self.evidence[k] == 0 {
                self.mark(i, j, false);
            }
        }
    }

    fn mark(&mut self, i: i64, j: i64, on: bool) {
        let Some(k) = self.index(i, j) else { return };
        if on {
            self.evidence[k] = EVIDENCE;
        }
        if self.marked[k] == on {
            return;
        }
        self.marked[k] = on;
        if on && !self.ever[k] {
            self.ever[k] = true;
            self.known += 1;
        }
        let step: i32 = if on { 1 } else { -1 };
        for &(dx, dy) in &self.hard_offsets {
            if let Some(n) = self.index(i + dx, j + dy) {
                self.hard[n] = (i32::from(self.hard[n]) + step).max(0) as u16;
            }
        }
        for &(dx, dy) in &self.soft_offsets {
            if let Some(n) = self.index(i + dx, j + dy) {
                self.soft[n] = (i32::from(self.soft[n]) + step).max(0) as u16;
            }
        }
        if on && !self.stale {
            // Does the new obstacle come near the path?
            let c = self.centre(i, j);
            let reach = (self.soft_offsets.iter().map(|&(x, y)| x.abs().max(y.abs())).max().unwrap_or(0) as f64 + 1.0)
                * self.params.cell_m;
            if self.path.iter().any(|p| p.distance(c) <= reach) {
                self.stale = true;
            }
        }
    }

    /// Takes in an all-around scan from `from` (ray `i` at absolute angle `2πi/n`, the free
    /// distance of a disc of `radius`, capped at `range`): the obstacle points hit are
    /// remembered, the cells the rays crossed freely are cleared.
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
        // Rays crossing a cell wear its evidence down, hits renew it; all crossings first, so
        // that a ray grazing a cell another ray hits in the same scan does not clear it.
        for (k, &f) in scan.iter().enumerate() {
            if !f.is_finite() {
                continue;
            }
            let dir = DVec2::from_angle(std::f64::consts::TAU * k as f64 / n as f64);
            // Clear the cells crossed freely, stopping a cell short of the hit.
            let clear_to = if f < range { f + radius - 1.5 * c } else { range + radius };
            let mut t = 0.5 * c;
            let mut last = None;
            while t < clear_to {
                let cell = self.cell_of(from + dir * t);
                if last != Some(cell) {
                    self.wear(cell.0, cell.1);
                    last = Some(cell);
                }
                t += 0.5 * c;
            }
        }
        for (k, &f) in scan.iter().enumerate() {
            if f.is_finite() && f < range {
                let dir = DVec2::from_angle(std::f64::consts::TAU * k as f64 / n as f64);
                let (i, j) = self.cell_of(from + dir * (f + radius));
                self.mark(i, j, true);
            }
        }
        // Hits of neighbouring rays closer than the disc's width are one surface (the disc
        // could not pass between them anyway): remember the segment between them.
        for k in 0..n {
            let (a, b) = (scan[k], scan[(k + 1) % n]);
            if !(a < range && b < range) {
                continue;
            }
            let pa = from + DVec2::from_angle(std::f64::consts::TAU * k as f64 / n as f64) * (a + radius);
            let pb = from + DVec2::from_angle(std::f64::consts::TAU * ((k + 1) % n) as f64 / n as f64) * (b + radius);
            let len = pa.distance(pb);
            if len >= 2.0 * radius {
                continue;
            }
            let steps = (len / (0.5 * c)).ceil() as usize;
            for s in 1..steps {
                let (i, j) = self.cell_of(pa + (pb - pa) * (s as f64 / steps as f64));
                self.mark(i, j, true);
            }
        }
    }

    /// Where to steer from `from` along the path to the goal, planned again when needed.
    /// `None` when the goal cannot be reached over what is remembered (or the search gives
    /// up).
    pub fn heading(&mut self, from: DVec2) -> Option<Aim> {
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
        // The waypoint: the farthest point of the path within reach that the disc can go
        // straight to without touching what is remembered (with the margin if it can), so
        // that steering toward it never cuts a corner into a wall; else the next point.
        let mut along = from.distance(self.path[0]);
        let (mut clear, mut roomy) = (None, None);
        let mut prev = self.path[0];
        for &p in &self.path {
            along += prev.distance(p);
            prev = p;
            if along > self.params.waypoint_m {
                break;
            }
            if self.clear_line(from, p, &self.hard) {
                clear = Some(p);
                if self.clear_line(from, p, &self.soft) {
                    roomy = Some(p);
                }
            }
        }
        // A waypoint close by is circled rather than reached: keep the margin only while
        // that leaves one far enough ahead.
        let roomy = roomy.filter(|p| p.distance(from) >= MIN_ROOMY_WAYPOINT_M);
        let waypoint = roomy.or(clear).unwrap_or(self.path[0]);
        let remaining: f64 =
            from.distance(self.path[0]) + self.path.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
        let to = waypoint - from;
        if to.length() < 1e-9 {
            let to = self.goal - from;
            return Some(Aim { heading: to.to_angle(), remaining_m: remaining, waypoint_m: to.length() });
        }
        Some(Aim { heading: to.to_angle(), remaining_m: remaining, waypoint_m: to.length() })
    }

    /// Whether the straight line from `a` to `b` crosses no cell of `blocked` (the hard or soft
    /// inflation; cells the agent already stands in do not count).
    fn clear_line(&self, a: DVec2, b: DVec2, blocked: &[u16]) -> bool {
        let step = 0.5 * self.params.cell_m;
        let n = (a.distance(b) / step).ceil().max(1.0) as usize;
        let here = self.cell_of(a);
        (1..=n).all(|k| {
            let (i, j) = self.cell_of(a + (b - a) * (k as f64 / n as f64));
            (i, j) == here || self.index(i, j).is_none_or(|c| blocked[c] == 0)
        })
    }

    /// A* from `from` to the goal over the grid (unknown cells free, hard cells closed, soft
    /// cells dearer); the path is kept as world points (the goal itself last).
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
        let n = self.nx * self.ny;
        let s = &mut self.scratch;
        if s.stamp.len() != n {
            s.stamp = vec![0; n];
            s.cost = vec![0.0; n];
            s.parent = vec![0; n];
            s.generation = 0;
        }
        s.generation = s.generation.wrapping_add(1);
        if s.generation == 0 {
            s.stamp.iter_mut().for_each(|x| *x = 0);
            s.generation = 1;
        }
        let gen_ = s.generation;
        let c = self.params.cell_m as f32;
        let h = |k: usize| -> f32 {
            let (x, y) = ((k % self.nx) as i64, (k / self.nx) as i64);
            let (dx, dy) = ((x - gi).abs() as f32, (y - gj).abs() as f32);
            c * (dx.max(dy) + (std::f32::consts::SQRT_2 - 1.0) * dx.min(dy))
        };
        let mut open = BinaryHeap::new();
        s.stamp[start] = gen_;
        s.cost[start] = 0.0;
        s.parent[start] = start as u32;
        open.push(Open { f: h(start), cell: start as u32 });
        let mut expanded = 0usize;
        let mut found = false;
        const STEPS: [(i64, i64, f32); 8] = [
            (1, 0, 1.0),
            (-1, 0, 1.0),
            (0, 1, 1.0),
            (0, -1, 1.0),
            (1, 1, std::f32::consts::SQRT_2),
            (1, -1, std::f32::consts::SQRT_2),
            (-1, 1, std::f32::consts::SQRT_2),
            (-1, -1, std::f32::consts::SQRT_2),
        ];
        while let Some(Open { f, cell }) = open.pop() {
            let k = cell as usize;
            let g = s.cost[k];
            if f > g + h(k) + 1e-3 {
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
            let (x, y) = ((k % self.nx) as i64, (k / self.nx) as i64);
            for &(dx, dy, len) in &STEPS {
                let (nx_, ny_) = (x + dx, y + dy);
                if nx_ < 0 || ny_ < 0 || nx_ as usize >= self.nx || ny_ as usize >= self.ny {
                    continue;
                }
                let m = ny_ as usize * self.nx + nx_ as usize;
                // The start may lie in inflated cells (the agent stands close to a wall).
                if self.hard[m] > 0 && m != goal && self.hard[k] == 0 {
                    continue;
                }
                if dx != 0 && dy != 0 {
                    // No squeezing diagonally between two closed cells.
                    let a = y as usize * self.nx + nx_ as usize;
                    let b = ny_ as usize * self.nx + x as usize;
                    if self.hard[a] > 0 && self.hard[b] > 0 {
                        continue;
                    }
                }
                let extra = if self.soft[m] > 0 { self.params.margin_cost as f32 } else { 0.0 };
                let ng = g + c * len * (1.0 + extra);
                if s.stamp[m] != gen_ || ng < s.cost[m] {
                    s.stamp[m] = gen_;
                    s.cost[m] = ng;
                    s.parent[m] = k as u32;
                    open.push(Open { f: ng + h(m), cell: m as u32 });
                }
            }
        }
        if !found {
            return;
        }
        let cost = s.cost[goal];
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
            k = s.parent[k] as usize;
            cells.push(k);
        }
        cells.reverse();
        let nx = self.nx;
        self.path = cells.iter().map(|&k| self.centre((k % nx) as i64, (k / nx) as i64)).collect();
        if let Some(last) = self.path.last_mut() {
            *last = self.goal;
        }
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
            if self.hard[k] > 0 && (i, j) != here {
                return None;
            }
            let extra = if self.soft[k] > 0 { self.params.margin_cost as f32 } else { 0.0 };
            total += prev.distance(p) as f32 * (1.0 + extra);
            prev = p;
        }
        Some(total)
    }

    /// The current path (world points toward the goal), for pictures.
    pub fn path(&self) -> &[DVec2] {
        &self.path
    }

    /// Number of distinct cells where an obstacle has ever been seen (only grows).
    pub fn known(&self) -> usize {
        self.known
    }

    /// Number of cells where an obstacle is remembered.
    pub fn remembered(&self) -> usize {
        self.marked.iter().filter(|&&m| m).count()
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
        let Aim { heading: h, remaining_m: len, .. } = m.heading(DVec2::ZERO).unwrap();
        assert!(h.abs() < 0.2 && (len - 4.0).abs() < 0.5, "{h} {len}");
        // A wall across the way: the path goes round its lower end (nearer).
        m.observe(DVec2::ZERO, &wall_scan(DVec2::ZERO), 0.3, 5.0);
        assert!(m.remembered() > 10);
        let aim = m.heading(DVec2::ZERO).unwrap();
        let (h, len) = (aim.heading, aim.remaining_m);
        assert!(h < -0.3, "heads for the lower end, {h}");
        assert!(len > 4.5, "{len}");
        // Deterministic.
        let mut again = Memory::new(DVec2::ZERO, goal, 0.3, MemoryParams::default());
        again.heading(DVec2::ZERO);
        again.observe(DVec2::ZERO, &wall_scan(DVec2::ZERO), 0.3, 5.0);
        assert_eq!(again.heading(DVec2::ZERO), Some(aim));
        // Looking again with the wall gone clears it, after a few looks (one ray grazing a
        // wall does not).
        m.observe(DVec2::ZERO, &[5.0; 72], 0.3, 5.0);
        assert!(m.remembered() > 10);
        for _ in 1..EVIDENCE {
            m.observe(DVec2::ZERO, &[5.0; 72], 0.3, 5.0);
        }
        // (Cells no ray crosses at the edge of the range may stay.) The way already chosen is
        // kept while it is not much longer than the straight one.
        assert!(m.remembered() < 20, "{}", m.remembered());
        let kept = m.heading(DVec2::ZERO).unwrap();
        assert!(kept.heading < -0.3, "{kept:?}");
        assert!(kept.remaining_m <= 4.0 * (1.0 + f64::from(SWITCH_SHARE)) + f64::from(SWITCH_M), "{kept:?}");
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
            m.mark(i, j, true);
        }
        assert_eq!(m.heading(DVec2::ZERO), None);
    }
}
