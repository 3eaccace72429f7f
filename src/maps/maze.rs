//! Seeded random mazes (`random:maze`): corridors of one width between thin walls, carved by a
//! randomized depth-first search over square cells, then opened in a few places so that the
//! maze has loops.
//!
//! **Layout.** Each world draws a corridor width in [`CORRIDOR_WIDTH_M`] (the free width
//! between wall faces) and a wall thickness in [`WALL_THICKNESS_M`]; the cell pitch (wall centre
//! line to wall centre line) is their sum. The maze has `n × n` cells with `n` the whole number
//! nearest to [`MAZE_SIZE_M`] divided by the pitch (at least [`MIN_CELLS`]), filling
//! `[0, n · pitch]²` metres with its outer walls centred on the edges. Every wall is an
//! axis-aligned box; collinear neighbouring walls are merged into one.
//!
//! **Carving.** A randomized depth-first search (recursive backtracker, run with an explicit
//! stack) from a random cell opens one wall to an unvisited neighbour at a time: a perfect maze,
//! one way between any two cells, with long winding corridors. Then `max(2, cells /
//! LOOP_CELLS)` more interior walls chosen at random are removed; each removal closes a loop.
//!
//! **Task.** Start and goal are the centres of two cells far apart in the maze graph (a double
//! sweep of breadth-first searches over the final maze); the start heading is random. The time
//! limit is [`TIME_PER_METRE_S`] per metre of the cell route (at least the default of
//! [`Task::new`](crate::world::Task::new)).
//!
//! **Invariants.** Every opening between walls is at least the corridor width, so the 0.3 m
//! disc passes everywhere; each world is still checked with the flood fill of
//! [`connected`](super::generate::connected), a failed draw is redrawn, and after [`ATTEMPTS`]
//! failed draws every interior wall would be left out. Every number comes from
//! `rng::stream(seed, attempt, STREAM)` in a fixed order; no clock, no hash maps.

use std::f64::consts::PI;

use glam::DVec2;
use rand_chacha::ChaCha8Rng;

use super::cells::{aabb_box, bfs, far_pair, index, path_to, shuffle, solvable};
use crate::rng;
use crate::scenario::{DEFAULT_AGENT_RADIUS, Scenario};
use crate::world::{Obstacle, Pose, Task};

/// Range of the corridor width (free space between wall faces), metres.
pub const CORRIDOR_WIDTH_M: (f64, f64) = (2.0, 3.0);

/// Range of the wall thickness (one value per maze), metres.
pub const WALL_THICKNESS_M: (f64, f64) = (0.15, 0.25);

/// Side the maze aims at, metres.
pub const MAZE_SIZE_M: f64 = 20.0;

/// Fewest cells along a side.
pub const MIN_CELLS: usize = 4;

/// One extra wall is removed per this many cells (at least two in all).
pub const LOOP_CELLS: usize = 12;

/// Time allowed per metre of the route through the cell centres, seconds per metre.
pub const TIME_PER_METRE_S: f64 = 10.0;

/// Draws tried before the interior walls are left out.
pub const ATTEMPTS: u64 = 8;

/// The generator's random stream id (see [`rng::stream`]).
const STREAM: u64 = 0x6d61_7a65;

/// The layout of one random maze. Cell `(i, j)` (column `i`, row `j`, row 0 at the bottom) has
/// index `j · cols + i` and covers `[i, i + 1] × [j, j + 1]` pitches.
#[derive(Debug, Clone, PartialEq)]
pub struct Maze {
    /// Cells along x.
    pub cols: usize,
    /// Cells along y.
    pub rows: usize,
    /// Free width of a corridor between wall faces, metres.
    pub corridor_width: f64,
    /// Thickness of every wall, metres.
    pub wall_thickness: f64,
    /// Per cell: whether the wall on its +x side is open (always false on the last column).
    pub open_east: Vec<bool>,
    /// Per cell: whether the wall on its +y side is open (always false on the last row).
    pub open_north: Vec<bool>,
    /// Interior walls removed after carving (each made a loop).
    pub loops: usize,
    /// Whether the interior walls stand (false only for the fallback in the module docs).
    pub interior_walls: bool,
    /// Start cell index.
    pub start_cell: usize,
    /// Goal cell index.
    pub goal_cell: usize,
    /// Start heading, radians.
    pub start_yaw: f64,
    /// Cells from the start to the goal along the fewest moves, both included.
    pub route: Vec<usize>,
}

impl Maze {
    /// Distance between neighbouring wall centre lines, metres.
    pub fn pitch(&self) -> f64 {
        self.corridor_width + self.wall_thickness
    }

    /// Size of the maze between the outer walls' centre lines, metres.
    pub fn size(&self) -> DVec2 {
        DVec2::new(self.cols as f64, self.rows as f64) * self.pitch()
    }

    /// Centre of cell `index`, metres.
    pub fn cell_center(&self, index: usize) -> DVec2 {
        let (i, j) = (index % self.cols.max(1), index / self.cols.max(1));
        DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * self.pitch()
    }

    /// For every cell, the cells one open wall away (−x, +x, −y, +y order).
    pub fn graph(&self) -> Vec<Vec<usize>> {
        let (c, r) = (self.cols, self.rows);
        let open = |a: usize, b: usize| -> bool {
            !self.interior_walls || if b == a + 1 { self.open_east[a] } else { self.open_north[a] }
        };
        (0..c * r)
            .map(|k| {
                let (i, j) = (k % c, k / c);
                let mut out = Vec::with_capacity(4);
                if i > 0 && open(k - 1, k) {
                    out.push(k - 1);
                }
                if i + 1 < c && open(k, k + 1) {
                    out.push(k + 1);
                }
                if j > 0 && open(k - c, k) {
                    out.push(k - c);
                }
                if j + 1 < r && open(k, k + c) {
                    out.push(k + c);
                }
                out
            })
            .collect()
    }

    /// The walls as axis-aligned boxes, each run of standing walls along a grid line one box.
    pub fn obstacles(&self) -> Vec<Obstacle> {
        let (c, r, p) = (self.cols, self.rows, self.pitch());
        let half = 0.5 * self.wall_thickness;
        let mut out = Vec::new();
        // Horizontal lines y = j · p: the wall under row j (the +y wall of row j − 1).
        for j in 0..=r {
            let stands =
                |i: usize| -> bool { j == 0 || j == r || (self.interior_walls && !self.open_north[(j - 1) * c + i]) };
            for (a, b) in runs(c, stands) {
                out.extend(aabb_box(
                    a as f64 * p - half,
                    j as f64 * p - half,
                    b as f64 * p + half,
                    j as f64 * p + half,
                ));
            }
        }
        // Vertical lines x = i · p.
        for i in 0..=c {
            let stands =
                |j: usize| -> bool { i == 0 || i == c || (self.interior_walls && !self.open_east[j * c + i - 1]) };
            for (a, b) in runs(r, stands) {
                out.extend(aabb_box(
                    i as f64 * p - half,
                    a as f64 * p - half,
                    i as f64 * p + half,
                    b as f64 * p + half,
                ));
            }
        }
        out
    }

    /// Length of the route through the cell centres, metres.
    pub fn route_length(&self) -> f64 {
        self.route.len().saturating_sub(1) as f64 * self.pitch()
    }

    /// The scenario: the walls and one task between the centres of the start and goal cells,
    /// agent radius 0.3 m.
    pub fn scenario(&self, name: &str) -> Scenario {
        let mut s = Scenario::new(name);
        s.agent_radius = DEFAULT_AGENT_RADIUS;
        s.obstacles = self.obstacles();
        let start = Pose { position: self.cell_center(self.start_cell), yaw: self.start_yaw };
        let mut task = Task::new(start, self.cell_center(self.goal_cell));
        task.time_limit_s = task.time_limit_s.max(TIME_PER_METRE_S * self.route_length());
        s.tasks.push(task);
        s
    }
}

/// Runs `[a, b)` of consecutive indices in `0..n` for which `stands` holds.
fn runs(n: usize, stands: impl Fn(usize) -> bool) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut from: Option<usize> = None;
    for k in 0..=n {
        match (k < n && stands(k), from) {
            (true, None) => from = Some(k),
            (false, Some(a)) => {
                out.push((a, k));
                from = None;
            }
            _ => {}
        }
    }
    out
}

/// The layout of the maze of `seed` (see the [module docs](self)).
pub fn maze(seed: u64) -> Maze {
    for attempt in 0..ATTEMPTS {
        let m = draw(&mut rng::stream(seed, attempt, STREAM));
        if solvable(&m.scenario(""), DVec2::ZERO, m.size()) {
            return m;
        }
    }
    let mut m = draw(&mut rng::stream(seed, 0, STREAM));
    m.interior_walls = false;
    m
}

/// The `random:maze` world of `seed`, named `random-maze-SEED`.
pub fn maze_world(seed: u64) -> Scenario {
    maze(seed).scenario(&format!("random-maze-{seed}"))
}

/// Opens the wall between neighbouring cells `a` and `b`.
fn open_wall(a: usize, b: usize, east: &mut [bool], north: &mut [bool]) {
    let (lo, hi) = (a.min(b), a.max(b));
    if hi == lo + 1 {
        east[lo] = true;
    } else {
        north[lo] = true;
    }
}

/// One maze drawn from `rng`, not yet checked.
fn draw(rng: &mut ChaCha8Rng) -> Maze {
    let width = rng::uniform(rng, CORRIDOR_WIDTH_M.0, CORRIDOR_WIDTH_M.1);
    let t = rng::uniform(rng, WALL_THICKNESS_M.0, WALL_THICKNESS_M.1);
    let n = ((MAZE_SIZE_M / (width + t)).round() as usize).max(MIN_CELLS);
    let (cols, rows) = (n, n);
    let cells = cols * rows;
    let mut open_east = vec![false; cells];
    let mut open_north = vec![false; cells];
    let neighbours = |k: usize| -> Vec<usize> {
        let (i, j) = (k % cols, k / cols);
        let mut out = Vec::with_capacity(4);
        if i > 0 {
            out.push(k - 1);
        }
        if i + 1 < cols {
            out.push(k + 1);
        }
        if j > 0 {
            out.push(k - cols);
        }
        if j + 1 < rows {
            out.push(k + cols);
        }
        out
    };

    // Recursive backtracker.
    let first = index(rng, cells);
    let mut visited = vec![false; cells];
    visited[first] = true;
    let mut stack = vec![first];
    while let Some(&top) = stack.last() {
        let free: Vec<usize> = neighbours(top).into_iter().filter(|&m| !visited[m]).collect();
        if free.is_empty() {
            stack.pop();
            continue;
        }
        let next = free[index(rng, free.len())];
        open_wall(top, next, &mut open_east, &mut open_north);
        visited[next] = true;
        stack.push(next);
    }

    // Loops: remove some interior walls still standing.
    let mut standing: Vec<(usize, usize)> = (0..cells)
        .flat_map(|k| {
            let (i, j) = (k % cols, k / cols);
            let east = (i + 1 < cols && !open_east[k]).then_some((k, k + 1));
            let north = (j + 1 < rows && !open_north[k]).then_some((k, k + cols));
            [east, north].into_iter().flatten()
        })
        .collect();
    shuffle(rng, &mut standing);
    let loops = (cells / LOOP_CELLS).max(2).min(standing.len());
    for &(a, b) in &standing[..loops] {
        open_wall(a, b, &mut open_east, &mut open_north);
    }

    let mut m = Maze {
        cols,
        rows,
        corridor_width: width,
        wall_thickness: t,
        open_east,
        open_north,
        loops,
        interior_walls: true,
        start_cell: 0,
        goal_cell: 0,
        start_yaw: 0.0,
        route: Vec::new(),
    };
    let graph = m.graph();
    let (mut from, mut to, _) = far_pair(&graph, index(rng, cells));
    if rng::unit(rng) < 0.5 {
        std::mem::swap(&mut from, &mut to);
    }
    m.start_cell = from;
    m.goal_cell = to;
    m.start_yaw = rng::uniform(rng, -PI, PI);
    m.route = path_to(&bfs(&graph, from).1, to);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn carving_makes_a_tree_then_loops() {
        for seed in 0..50 {
            let m = maze(seed);
            assert!(m.interior_walls, "seed {seed} fell back to an open square");
            let cells = m.cols * m.rows;
            let graph = m.graph();
            let edges: usize = graph.iter().map(Vec::len).sum::<usize>() / 2;
            // A spanning tree has cells − 1 passages; each removed wall adds one loop.
            assert_eq!(edges, cells - 1 + m.loops, "seed {seed}");
            assert!(m.loops >= 2);
            assert!(bfs(&graph, 0).0.iter().all(Option::is_some), "seed {seed}: a cell is walled in");
            for k in 0..cells {
                assert!(!(k % m.cols == m.cols - 1 && m.open_east[k]));
                assert!(!(k / m.cols == m.rows - 1 && m.open_north[k]));
            }
        }
    }

    #[test]
    fn sizes_within_ranges() {
        for seed in 0..50 {
            let m = maze(seed);
            assert!((CORRIDOR_WIDTH_M.0..=CORRIDOR_WIDTH_M.1).contains(&m.corridor_width));
            assert!((WALL_THICKNESS_M.0..=WALL_THICKNESS_M.1).contains(&m.wall_thickness));
            let side = m.size().x;
            assert!(side > MAZE_SIZE_M - m.pitch() && side < MAZE_SIZE_M + m.pitch(), "seed {seed}: side {side}");
        }
    }

    #[test]
    fn start_and_goal_far_apart() {
        for seed in 0..50 {
            let m = maze(seed);
            let (dist, _) = bfs(&m.graph(), m.start_cell);
            let far = dist.iter().flatten().copied().max().unwrap();
            let d = dist[m.goal_cell].unwrap();
            assert_eq!(m.route.len(), d + 1);
            // The double sweep finds a pair at least half as far apart as the farthest cell.
            assert!(2 * d >= far, "seed {seed}: {d} of {far}");
            // Moves between cells are at least their grid distance, so the farthest pair is at
            // least 2 (n − 1) apart.
            assert!(d + 1 >= m.cols, "seed {seed}: only {d} cells apart");
        }
    }

    #[test]
    fn runs_of_standing_walls() {
        assert_eq!(runs(5, |_| true), [(0, 5)]);
        assert_eq!(runs(5, |k| k != 2), [(0, 2), (3, 5)]);
        assert_eq!(runs(3, |_| false), Vec::<(usize, usize)>::new());
    }
}
