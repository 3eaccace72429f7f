//! Seeded random buildings (`random:rooms`): a rectangular floor divided into a grid of rooms
//! joined by doors, so that the way from room to room is long and winding.
//!
//! **Layout.** The floor is `[0, W] × [0, H]` metres with `W` and `H` drawn in
//! [`FLOOR_SIZE_M`]. Each side is split into rooms of [`ROOM_SIZE_M`] (measured between wall
//! centre lines): the number of rooms along a side is drawn among the counts that allow it,
//! then neighbouring rooms trade size at random within the range. Walls are axis-aligned boxes
//! centred on the grid lines, all of one thickness drawn in [`WALL_THICKNESS_M`]; the four outer
//! walls close the floor.
//!
//! **Doors.** The rooms are joined by a random spanning tree of doors grown by a randomized
//! depth-first search (long branches, few shortcuts), plus a few extra doors through walls the
//! tree left closed, which make loops. With probability [`CORRIDOR_CHANCE`] one whole row or
//! column of rooms is a corridor: every wall between its consecutive rooms has a door, and the
//! tree grows from it. A door is a gap of [`DOOR_WIDTH_M`] in the wall between two rooms,
//! keeping at least [`DOOR_JAMB_M`] of wall between its edges and the faces of the crossing
//! walls.
//!
//! **Task.** The start and goal rooms are far apart along the door graph (a double sweep of
//! breadth-first searches finds two rooms at least half the graph's diameter apart, which is at
//! least three doors on the smallest floor); start and goal points are drawn inside their rooms
//! at least [`WALL_CLEARANCE_M`] from every wall. The time limit is [`TIME_PER_METRE_S`] per
//! metre of the route through the door centres (at least the default of
//! [`Task::new`](crate::world::Task::new)).
//!
//! **Invariants.** Every world is checked with the disc flood fill of
//! [`connected`](super::generate::connected) (doors are wider than the agent's disc plus the
//! check's margin, so the check passes by construction); a draw that failed would be redrawn,
//! and after [`ATTEMPTS`] failed draws the interior walls would be left out. Every number comes
//! from `rng::stream(seed, attempt, STREAM)` in a fixed order; no clock, no hash maps.

use std::f64::consts::PI;

use glam::DVec2;
use rand_chacha::ChaCha8Rng;

use super::cells::{aabb_box, bfs, far_pair, index, path_to, shuffle, solid_runs, solvable};
use crate::rng;
use crate::scenario::{DEFAULT_AGENT_RADIUS, Scenario};
use crate::world::{Obstacle, Pose, Task};

/// Range of each side of the floor, metres.
pub const FLOOR_SIZE_M: (f64, f64) = (20.0, 30.0);

/// Range of each side of a room, between wall centre lines, metres.
pub const ROOM_SIZE_M: (f64, f64) = (3.0, 6.0);

/// Range of the wall thickness (one value per building), metres.
pub const WALL_THICKNESS_M: (f64, f64) = (0.15, 0.25);

/// Range of the free width of a door, metres.
pub const DOOR_WIDTH_M: (f64, f64) = (0.9, 1.2);

/// Shortest wall left between a door's edge and the face of a crossing wall, metres.
pub const DOOR_JAMB_M: f64 = 0.3;

/// Least distance from the start or the goal to any wall, metres.
pub const WALL_CLEARANCE_M: f64 = 0.8;

/// Probability that one row or column of rooms is a corridor (doors between all of its rooms).
pub const CORRIDOR_CHANCE: f64 = 0.5;

/// Time allowed per metre of the route through the doors, seconds per metre.
pub const TIME_PER_METRE_S: f64 = 10.0;

/// Draws tried before the interior walls are left out.
pub const ATTEMPTS: u64 = 8;

/// The generator's random stream id (see [`rng::stream`]).
const STREAM: u64 = 0x726f_6f6d;

/// A door: an opening in the wall between two neighbouring rooms.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Door {
    /// The two rooms it joins, lower index first (rooms are numbered `row · cols + col`).
    pub rooms: (usize, usize),
    /// Centre of the opening, on the wall's centre line, metres.
    pub center: DVec2,
    /// Free width of the opening along the wall, metres.
    pub width: f64,
    /// Whether the wall runs along y (the rooms are side by side along x).
    pub along_y: bool,
}

/// The layout of one random building.
#[derive(Debug, Clone, PartialEq)]
pub struct Building {
    /// Wall centre lines across x, from 0 to the floor width, metres (`cols + 1` values).
    pub xs: Vec<f64>,
    /// Wall centre lines across y, from 0 to the floor depth, metres (`rows + 1` values).
    pub ys: Vec<f64>,
    /// Thickness of every wall, metres.
    pub wall_thickness: f64,
    /// The doors: the spanning tree's first, then the extra ones.
    pub doors: Vec<Door>,
    /// Number of doors in the spanning tree (the first ones of [`Building::doors`]).
    pub tree_doors: usize,
    /// The rooms of the corridor, in order along it (empty when there is none).
    pub corridor: Vec<usize>,
    /// Whether the interior walls stand (false only for the fallback described in the module
    /// docs).
    pub interior_walls: bool,
    /// Start pose: position (metres) and heading (radians).
    pub start: Pose,
    /// Goal point, metres.
    pub goal: DVec2,
    /// Rooms from the start's to the goal's along the fewest doors, both included.
    pub route: Vec<usize>,
    /// Length of the polyline from the start through the route's door centres to the goal,
    /// metres.
    pub route_length: f64,
}

impl Building {
    /// Number of rooms along x.
    pub fn cols(&self) -> usize {
        self.xs.len().saturating_sub(1)
    }

    /// Number of rooms along y.
    pub fn rows(&self) -> usize {
        self.ys.len().saturating_sub(1)
    }

    /// Floor size (width along x, depth along y), metres.
    pub fn size(&self) -> DVec2 {
        DVec2::new(self.xs.last().copied().unwrap_or(0.0), self.ys.last().copied().unwrap_or(0.0))
    }

    /// The room holding point `p` (between wall centre lines), if any.
    pub fn room_at(&self, p: DVec2) -> Option<usize> {
        let i = self.xs.windows(2).position(|w| p.x >= w[0] && p.x < w[1])?;
        let j = self.ys.windows(2).position(|w| p.y >= w[0] && p.y < w[1])?;
        Some(j * self.cols() + i)
    }

    /// For every room, the rooms one door away (in door order).
    pub fn door_graph(&self) -> Vec<Vec<usize>> {
        door_graph(self.cols() * self.rows(), &self.doors)
    }

    /// The walls as axis-aligned boxes: one box per unbroken run of wall along a grid line.
    pub fn obstacles(&self) -> Vec<Obstacle> {
        let half = 0.5 * self.wall_thickness;
        let (cols, rows) = (self.cols(), self.rows());
        let mut out = Vec::new();
        for (k, &x) in self.xs.iter().enumerate() {
            if !self.interior_walls && k != 0 && k != cols {
                continue;
            }
            let gaps: Vec<(f64, f64)> = self
                .doors
                .iter()
                .filter(|d| d.along_y && d.rooms.0 % cols.max(1) + 1 == k)
                .map(|d| (d.center.y - 0.5 * d.width, d.center.y + 0.5 * d.width))
                .collect();
            for (a, b) in solid_runs(self.ys[0] - half, self.ys[rows] + half, &gaps) {
                out.extend(aabb_box(x - half, a, x + half, b));
            }
        }
        for (k, &y) in self.ys.iter().enumerate() {
            if !self.interior_walls && k != 0 && k != rows {
                continue;
            }
            let gaps: Vec<(f64, f64)> = self
                .doors
                .iter()
                .filter(|d| !d.along_y && d.rooms.0 / cols.max(1) + 1 == k)
                .map(|d| (d.center.x - 0.5 * d.width, d.center.x + 0.5 * d.width))
                .collect();
            for (a, b) in solid_runs(self.xs[0] - half, self.xs[cols] + half, &gaps) {
                out.extend(aabb_box(a, y - half, b, y + half));
            }
        }
        out
    }

    /// The scenario: the walls and one task from the start to the goal, agent radius 0.3 m.
    pub fn scenario(&self, name: &str) -> Scenario {
        let mut s = Scenario::new(name);
        s.agent_radius = DEFAULT_AGENT_RADIUS;
        s.obstacles = self.obstacles();
        let mut task = Task::new(self.start, self.goal);
        task.time_limit_s = task.time_limit_s.max(TIME_PER_METRE_S * self.route_length);
        s.tasks.push(task);
        s
    }
}

/// The layout of the building of `seed` (see the [module docs](self)).
pub fn building(seed: u64) -> Building {
    for attempt in 0..ATTEMPTS {
        let b = draw(&mut rng::stream(seed, attempt, STREAM));
        if solvable(&b.scenario(""), DVec2::ZERO, b.size()) {
            return b;
        }
    }
    let mut b = draw(&mut rng::stream(seed, 0, STREAM));
    b.interior_walls = false;
    b
}

/// The `random:rooms` world of `seed`, named `random-rooms-SEED`.
pub fn rooms_world(seed: u64) -> Scenario {
    building(seed).scenario(&format!("random-rooms-{seed}"))
}

/// Wall centre lines splitting `[0, length]` into rooms of [`ROOM_SIZE_M`].
fn split(rng: &mut ChaCha8Rng, length: f64) -> Vec<f64> {
    let (lo, hi) = ROOM_SIZE_M;
    let fewest = ((length / hi).ceil() as usize).max(1);
    let most = ((length / lo).floor() as usize).max(fewest);
    let n = fewest + index(rng, most - fewest + 1);
    let mut sizes = vec![length / n as f64; n];
    for _ in 0..2 {
        for i in 0..n - 1 {
            let low = (lo - sizes[i]).max(sizes[i + 1] - hi);
            let high = (hi - sizes[i]).min(sizes[i + 1] - lo);
            if low < high {
                let d = rng::uniform(rng, low, high);
                sizes[i] += d;
                sizes[i + 1] -= d;
            }
        }
    }
    let mut lines = Vec::with_capacity(n + 1);
    let mut at = 0.0;
    lines.push(at);
    for s in &sizes[..n - 1] {
        at += s;
        lines.push(at);
    }
    lines.push(length);
    lines
}

/// The rooms next to `room` through a wall, in a fixed order (−x, +x, −y, +y).
fn neighbours(room: usize, cols: usize, rows: usize) -> Vec<usize> {
    let (i, j) = (room % cols, room / cols);
    let mut out = Vec::with_capacity(4);
    if i > 0 {
        out.push(room - 1);
    }
    if i + 1 < cols {
        out.push(room + 1);
    }
    if j > 0 {
        out.push(room - cols);
    }
    if j + 1 < rows {
        out.push(room + cols);
    }
    out
}

fn door_graph(rooms: usize, doors: &[Door]) -> Vec<Vec<usize>> {
    let mut adj = vec![Vec::new(); rooms];
    for d in doors {
        let (a, b) = d.rooms;
        if a < rooms && b < rooms {
            adj[a].push(b);
            adj[b].push(a);
        }
    }
    adj
}

/// One building drawn from `rng`, not yet checked.
fn draw(rng: &mut ChaCha8Rng) -> Building {
    let t = rng::uniform(rng, WALL_THICKNESS_M.0, WALL_THICKNESS_M.1);
    let width = rng::uniform(rng, FLOOR_SIZE_M.0, FLOOR_SIZE_M.1);
    let depth = rng::uniform(rng, FLOOR_SIZE_M.0, FLOOR_SIZE_M.1);
    let xs = split(rng, width);
    let ys = split(rng, depth);
    let (cols, rows) = (xs.len() - 1, ys.len() - 1);
    let n = cols * rows;

    let corridor: Vec<usize> = if rng::unit(rng) < CORRIDOR_CHANCE {
        if rng::unit(rng) < 0.5 {
            let j = index(rng, rows);
            (0..cols).map(|i| j * cols + i).collect()
        } else {
            let i = index(rng, cols);
            (0..rows).map(|j| j * cols + i).collect()
        }
    } else {
        Vec::new()
    };

    // Spanning tree: the corridor's chain, then a randomized depth-first search from it.
    let mut pairs: Vec<(usize, usize)> = corridor.windows(2).map(|w| (w[0], w[1])).collect();
    let mut visited = vec![false; n];
    let mut stack: Vec<usize> = if corridor.is_empty() { vec![index(rng, n)] } else { corridor.clone() };
    shuffle(rng, &mut stack);
    for &r in &stack {
        visited[r] = true;
    }
    while let Some(&top) = stack.last() {
        let free: Vec<usize> = neighbours(top, cols, rows).into_iter().filter(|&m| !visited[m]).collect();
        if free.is_empty() {
            stack.pop();
            continue;
        }
        let next = free[index(rng, free.len())];
        visited[next] = true;
        pairs.push((top, next));
        stack.push(next);
    }
    let tree_doors = pairs.len();

    // Extra doors through walls the tree left closed.
    let mut closed: Vec<(usize, usize)> = (0..n)
        .flat_map(|a| neighbours(a, cols, rows).into_iter().filter(move |&b| b > a).map(move |b| (a, b)))
        .filter(|&(a, b)| !pairs.iter().any(|&(p, q)| (p, q) == (a, b) || (q, p) == (a, b)))
        .collect();
    shuffle(rng, &mut closed);
    let extra = 2 + index(rng, 1 + n / 12);
    pairs.extend(closed.into_iter().take(extra));

    let half = 0.5 * t;
    let doors: Vec<Door> = pairs
        .iter()
        .map(|&(p, q)| {
            let (a, b) = (p.min(q), p.max(q));
            let width = rng::uniform(rng, DOOR_WIDTH_M.0, DOOR_WIDTH_M.1);
            let along_y = b == a + 1;
            let (i, j) = (a % cols, a / cols);
            // The wall's span between the crossing walls' faces, and its centre line.
            let (lo, hi, line) = if along_y {
                (ys[j] + half, ys[j + 1] - half, xs[i + 1])
            } else {
                (xs[i] + half, xs[i + 1] - half, ys[j + 1])
            };
            let margin = DOOR_JAMB_M + 0.5 * width;
            let c = rng::uniform(rng, lo + margin, hi - margin);
            let center = if along_y { DVec2::new(line, c) } else { DVec2::new(c, line) };
            Door { rooms: (a, b), center, width, along_y }
        })
        .collect();

    let adj = door_graph(n, &doors);
    let (mut from, mut to, _) = far_pair(&adj, index(rng, n));
    if rng::unit(rng) < 0.5 {
        std::mem::swap(&mut from, &mut to);
    }
    let start = point_in(rng, &xs, &ys, from, t);
    let goal = point_in(rng, &xs, &ys, to, t);
    let yaw = rng::uniform(rng, -PI, PI);
    let (_, parent) = bfs(&adj, from);
    let route = path_to(&parent, to);
    let mut corners = vec![start];
    for w in route.windows(2) {
        let key = (w[0].min(w[1]), w[0].max(w[1]));
        if let Some(d) = doors.iter().find(|d| d.rooms == key) {
            corners.push(d.center);
        }
    }
    corners.push(goal);
    let route_length = crate::plan::path_length(&corners);

    Building {
        xs,
        ys,
        wall_thickness: t,
        doors,
        tree_doors,
        corridor,
        interior_walls: true,
        start: Pose { position: start, yaw },
        goal,
        route,
        route_length,
    }
}

/// A point of `room` at least [`WALL_CLEARANCE_M`] from its walls.
fn point_in(rng: &mut ChaCha8Rng, xs: &[f64], ys: &[f64], room: usize, t: f64) -> DVec2 {
    let cols = xs.len() - 1;
    let (i, j) = (room % cols, room / cols);
    let m = 0.5 * t + WALL_CLEARANCE_M;
    DVec2::new(rng::uniform(rng, xs[i] + m, xs[i + 1] - m), rng::uniform(rng, ys[j] + m, ys[j + 1] - m))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rooms_and_walls_within_their_ranges() {
        for seed in 0..50 {
            let b = building(seed);
            assert!(b.interior_walls, "seed {seed} fell back to an open floor");
            let size = b.size();
            for s in [size.x, size.y] {
                assert!((FLOOR_SIZE_M.0..=FLOOR_SIZE_M.1).contains(&s), "seed {seed}: floor side {s}");
            }
            for lines in [&b.xs, &b.ys] {
                for w in lines.windows(2) {
                    let room = w[1] - w[0];
                    assert!(room > ROOM_SIZE_M.0 - 1e-9 && room < ROOM_SIZE_M.1 + 1e-9, "seed {seed}: room {room}");
                }
            }
            assert!((WALL_THICKNESS_M.0..=WALL_THICKNESS_M.1).contains(&b.wall_thickness));
            let n = b.cols() * b.rows();
            assert_eq!(b.tree_doors, n - 1, "a spanning tree has one door fewer than rooms");
            assert!(b.doors.len() > b.tree_doors, "seed {seed}: no loop");
            // The tree alone joins every room.
            let (dist, _) = bfs(&door_graph(n, &b.doors[..b.tree_doors]), 0);
            assert!(dist.iter().all(Option::is_some), "seed {seed}");
            for d in &b.doors {
                assert!((DOOR_WIDTH_M.0..=DOOR_WIDTH_M.1).contains(&d.width));
                assert_eq!(b.room_at(d.center - if d.along_y { DVec2::X } else { DVec2::Y } * 0.5), Some(d.rooms.0));
                assert_eq!(b.room_at(d.center + if d.along_y { DVec2::X } else { DVec2::Y } * 0.5), Some(d.rooms.1));
            }
            for w in b.corridor.windows(2) {
                let key = (w[0].min(w[1]), w[0].max(w[1]));
                assert!(b.doors[..b.tree_doors].iter().any(|d| d.rooms == key), "seed {seed}: corridor not open");
            }
        }
    }

    #[test]
    fn start_and_goal_are_rooms_apart() {
        for seed in 0..50 {
            let b = building(seed);
            let (s, g) = (b.room_at(b.start.position).unwrap(), b.room_at(b.goal).unwrap());
            assert_eq!((b.route[0], *b.route.last().unwrap()), (s, g));
            assert!(b.route.len() >= 4, "seed {seed}: only {} doors apart", b.route.len() - 1);
            let (dist, _) = bfs(&b.door_graph(), s);
            assert_eq!(dist[g], Some(b.route.len() - 1));
            assert!(b.route_length >= b.start.position.distance(b.goal));
        }
    }

    #[test]
    fn split_covers_the_side() {
        let mut r = rng::stream(3, 0, 1);
        for k in 0..200 {
            let length = 20.0 + 0.05 * k as f64;
            let lines = split(&mut r, length);
            assert_eq!((lines[0], *lines.last().unwrap()), (0.0, length));
            assert!(lines.windows(2).all(|w| w[1] - w[0] > 3.0 - 1e-9 && w[1] - w[0] < 6.0 + 1e-9), "{lines:?}");
        }
    }
}
