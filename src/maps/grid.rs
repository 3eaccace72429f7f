//! Seeded random grid maps (`random:grid`) in the manner of the MovingAI random benchmarks: a
//! square of 1 m cells, some blocked at random, with start and goal on free cells far apart.
//!
//! **Layout.** The grid has [`GRID_CELLS`] × [`GRID_CELLS`] cells of 1 m (so the world is
//! `[0, 20]²` metres). A fraction of the cells drawn in [`BLOCKED_FRACTION`] (rounded to whole
//! cells) is blocked, chosen by a shuffle of all cells. The scenario is built the way
//! [`movingai`] builds imported maps ([`movingai::scenario_from`]): blocked
//! cells merged into a few axis-aligned boxes, four 1 m walls just outside the grid, cell
//! `(x, y)` (row 0 at the top) covering `[x, x+1] × [H−1−y, H−y]` metres.
//!
//! **Connectivity.** For a disc of 0.3 m, two free cells are joined exactly when a chain of
//! free cells sharing sides links them: a 1 m gap leaves 0.5 m of clearance on its centre line,
//! and two blocked cells touching at a corner leave no gap at all, so diagonal steps between
//! corner-touching blocks do not count. [`free_components`] labels these chains.
//!
//! **Task.** Start and goal lie on the centres of two cells of the largest component, far apart
//! (a double sweep of breadth-first searches over side-sharing free cells). The task's optimal
//! length is the 8-connected grid distance without corner cutting (diagonal √2), and its time
//! limit is [`movingai::TIME_PER_METRE_S`] per metre of it (at least
//! [`movingai::MIN_TIME_LIMIT_S`]), as for imported maps.
//!
//! **Invariants.** Every world is checked with the flood fill of
//! [`connected`](super::generate::connected); a draw whose largest component has a single cell
//! or that fails the check is redrawn, and after [`ATTEMPTS`] failed draws the grid is left
//! without blocked cells. Every number comes from `rng::stream(seed, attempt, STREAM)` in a fixed
//! order; no clock, no hash maps.

use glam::DVec2;
use rand_chacha::ChaCha8Rng;

use super::cells::{far_pair, index, shuffle, solvable};
use super::movingai::{self, Grid, ScenLine};
use crate::rng;
use crate::scenario::Scenario;

/// Cells along each side of the grid (1 m each).
pub const GRID_CELLS: usize = 20;

/// Range of the fraction of blocked cells.
pub const BLOCKED_FRACTION: (f64, f64) = (0.10, 0.25);

/// Draws tried before the grid is left without blocked cells.
pub const ATTEMPTS: u64 = 8;

/// The generator's random stream id (see [`rng::stream`]).
const STREAM: u64 = 0x6772_6964;

/// One random grid map and its task.
#[derive(Debug, Clone, PartialEq)]
pub struct RandomGrid {
    /// The cells (row 0 at the top).
    pub grid: Grid,
    /// Start cell `(x, y)`.
    pub start: (usize, usize),
    /// Goal cell `(x, y)`.
    pub goal: (usize, usize),
    /// Fewest moves between side-sharing free cells from start to goal.
    pub moves: usize,
    /// 8-connected grid distance from start to goal without corner cutting, metres.
    pub optimal_length: f64,
}

impl RandomGrid {
    /// The scenario (see the [module docs](self)), agent radius 0.3 m.
    pub fn scenario(&self, name: &str) -> Scenario {
        let line = ScenLine {
            line: 0,
            cols: [0; 9],
            bucket: 0,
            map: name.to_string(),
            map_width: self.grid.width(),
            map_height: self.grid.height(),
            start: self.start,
            goal: self.goal,
            optimal_length: self.optimal_length,
        };
        movingai::scenario_from(&self.grid, &[line], name)
    }
}

/// For every cell (row-major, row 0 at the top), the component of free cells joined through
/// shared sides it belongs to, numbered from 0 in scan order; `None` for blocked cells.
pub fn free_components(grid: &Grid) -> Vec<Option<usize>> {
    let adj = adjacency(grid);
    let mut label: Vec<Option<usize>> = vec![None; adj.len()];
    let mut next = 0;
    for k in 0..adj.len() {
        if label[k].is_some() || grid.is_blocked(k % grid.width(), k / grid.width()) {
            continue;
        }
        label[k] = Some(next);
        let mut stack = vec![k];
        while let Some(c) = stack.pop() {
            for &m in &adj[c] {
                if label[m].is_none() {
                    label[m] = Some(next);
                    stack.push(m);
                }
            }
        }
        next += 1;
    }
    label
}

/// Side-sharing free neighbours of every cell (none for blocked cells).
fn adjacency(grid: &Grid) -> Vec<Vec<usize>> {
    let (w, h) = (grid.width(), grid.height());
    (0..w * h)
        .map(|k| {
            let (x, y) = (k % w, k / w);
            if grid.is_blocked(x, y) {
                return Vec::new();
            }
            let mut out = Vec::with_capacity(4);
            for (dx, dy) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
                let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                if nx >= 0 && ny >= 0 && !grid.is_blocked(nx as usize, ny as usize) {
                    out.push(ny as usize * w + nx as usize);
                }
            }
            out
        })
        .collect()
}

/// 8-connected grid distance between two cells, diagonal steps only when both side cells are
/// free (Dijkstra); `None` when they are not connected.
pub fn octile_length(grid: &Grid, from: (usize, usize), to: (usize, usize)) -> Option<f64> {
    let (w, h) = (grid.width(), grid.height());
    if grid.is_blocked(from.0, from.1) || grid.is_blocked(to.0, to.1) {
        return None;
    }
    let n = w * h;
    let mut dist = vec![f64::INFINITY; n];
    let mut done = vec![false; n];
    dist[from.1 * w + from.0] = 0.0;
    let target = to.1 * w + to.0;
    loop {
        let mut best: Option<usize> = None;
        for k in 0..n {
            if !done[k] && dist[k].is_finite() && best.is_none_or(|b| dist[k] < dist[b]) {
                best = Some(k);
            }
        }
        let k = best?;
        if k == target {
            return Some(dist[k]);
        }
        done[k] = true;
        let (x, y) = ((k % w) as i64, (k / w) as i64);
        let free = |x: i64, y: i64| x >= 0 && y >= 0 && !grid.is_blocked(x as usize, y as usize);
        for dy in -1i64..=1 {
            for dx in -1i64..=1 {
                if (dx, dy) == (0, 0) || !free(x + dx, y + dy) {
                    continue;
                }
                let diagonal = dx != 0 && dy != 0;
                if diagonal && !(free(x + dx, y) && free(x, y + dy)) {
                    continue;
                }
                let m = (y + dy) as usize * w + (x + dx) as usize;
                let d = dist[k] + if diagonal { std::f64::consts::SQRT_2 } else { 1.0 };
                if d < dist[m] {
                    dist[m] = d;
                }
            }
        }
    }
}

/// The grid map of `seed` (see the [module docs](self)).
pub fn random_grid(seed: u64) -> RandomGrid {
    for attempt in 0..ATTEMPTS {
        if let Some(g) = draw(&mut rng::stream(seed, attempt, STREAM), true)
            && solvable(&g.scenario(""), DVec2::ZERO, DVec2::splat(GRID_CELLS as f64))
        {
            return g;
        }
    }
    // With no blocked cell the grid is one component of 400 cells, so the draw succeeds.
    draw(&mut rng::stream(seed, 0, STREAM), false).unwrap_or_else(|| unreachable!("an open grid is one component"))
}

/// The `random:grid` world of `seed`, named `random-grid-SEED`.
pub fn grid_world(seed: u64) -> Scenario {
    random_grid(seed).scenario(&format!("random-grid-{seed}"))
}

/// One grid drawn from `rng` (no blocked cells unless `block`); `None` when its largest
/// component has a single cell.
fn draw(rng: &mut ChaCha8Rng, block: bool) -> Option<RandomGrid> {
    let n = GRID_CELLS * GRID_CELLS;
    let fraction = rng::uniform(rng, BLOCKED_FRACTION.0, BLOCKED_FRACTION.1);
    let count = if block { ((fraction * n as f64).round() as usize).min(n) } else { 0 };
    let mut order: Vec<usize> = (0..n).collect();
    shuffle(rng, &mut order);
    let mut blocked = vec![false; n];
    for &k in &order[..count] {
        blocked[k] = true;
    }
    let grid = Grid::new(GRID_CELLS, GRID_CELLS, blocked)?;
    let label = free_components(&grid);
    let mut sizes: Vec<usize> = Vec::new();
    for l in label.iter().flatten() {
        if *l >= sizes.len() {
            sizes.resize(l + 1, 0);
        }
        sizes[*l] += 1;
    }
    let biggest = (0..sizes.len()).max_by(|&a, &b| sizes[a].cmp(&sizes[b]).then(b.cmp(&a)))?;
    let members: Vec<usize> = (0..n).filter(|&k| label[k] == Some(biggest)).collect();
    if members.len() < 2 {
        return None;
    }
    let first = members[index(rng, members.len())];
    let (mut a, mut b, moves) = far_pair(&adjacency(&grid), first);
    if rng::unit(rng) < 0.5 {
        std::mem::swap(&mut a, &mut b);
    }
    let cell = |k: usize| (k % GRID_CELLS, k / GRID_CELLS);
    let (start, goal) = (cell(a), cell(b));
    let optimal_length = octile_length(&grid, start, goal)?;
    Some(RandomGrid { grid, start, goal, moves, optimal_length })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_of(rows: &[&str]) -> Grid {
        let blocked = rows.iter().flat_map(|r| r.chars().map(|c| c == '@')).collect();
        Grid::new(rows[0].len(), rows.len(), blocked).unwrap()
    }

    #[test]
    fn corner_touching_blocks_separate() {
        // A diagonal of blocked cells cuts the square in two.
        let g = grid_of(&["..@", ".@.", "@.."]);
        let label = free_components(&g);
        assert_eq!(label[0], label[1]);
        assert_ne!(label[0], label[5]);
        assert_eq!(label[2], None);
        assert_eq!(octile_length(&g, (0, 0), (2, 2)), None);
        let open = grid_of(&["...", ".@.", "..."]);
        assert_eq!(octile_length(&open, (0, 0), (2, 2)), Some(4.0));
        assert_eq!(octile_length(&open, (0, 0), (1, 0)), Some(1.0));
        let clear = grid_of(&["...", "...", "..."]);
        assert_eq!(octile_length(&clear, (0, 0), (2, 2)), Some(2.0 * std::f64::consts::SQRT_2));
    }

    #[test]
    fn blocked_share_and_far_ends() {
        for seed in 0..50 {
            let g = random_grid(seed);
            let share = g.grid.blocked_count() as f64 / (GRID_CELLS * GRID_CELLS) as f64;
            assert!(share >= BLOCKED_FRACTION.0 - 0.01 && share <= BLOCKED_FRACTION.1 + 0.01, "seed {seed}: {share}");
            let label = free_components(&g.grid);
            let at = |(x, y): (usize, usize)| label[y * GRID_CELLS + x];
            assert!(at(g.start).is_some() && at(g.start) == at(g.goal), "seed {seed}");
            assert!(g.moves >= GRID_CELLS, "seed {seed}: only {} moves apart", g.moves);
            assert!(g.optimal_length <= g.moves as f64 + 1e-9);
        }
    }
}
