//! Seeded random worlds at the three densities of seed 000 Fig 2: *sparse*, *semi-cluttered*
//! and *cluttered* (DESIGN.md §1).
//!
//! A world is a [`AREA_SIZE_M`] × [`AREA_SIZE_M`] square (`[0, 20] × [0, 20]` metres) closed by
//! four boundary walls, holding boxes (random yaw) and cylinders in three size classes: small
//! 0.4–0.6 m, medium 0.8–1.2 m and large 1.6–2.4 m (box sides, cylinder diameters). The number
//! of obstacles is 8, 20 or 40 ([`Density::obstacle_count`]). The start lies 1.5–3 m from the
//! lower-left corner on both axes with a random heading; the goal lies as far from the opposite
//! corner. Every obstacle keeps at least `agent_radius + 0.5` m from the start and the goal; an
//! obstacle that cannot be placed so in [`PLACEMENT_TRIES`] draws is left out.
//!
//! **Solvable by construction.** After placement, [`connected`] checks that a disc of the agent
//! radius can go from start to goal: the area is covered by a grid of [`GRID_CELL_M`] cells, a
//! cell is free when the clearance at its centre is at least `agent_radius + GRID_MARGIN_M`, and
//! free cells are flood-filled through their four side neighbours. Neighbouring free centres are
//! 0.1 m apart, so every point between them keeps a clearance of at least the agent radius: a
//! path found on the grid is a real path for the disc. When the goal is not reached, the two
//! flood fills (from the start and from the goal) are compared and the obstacle nearest to both
//! frontiers (smallest sum of distances, lowest index on ties) is dropped, and the check runs
//! again, until the goal is reached. Walls are never dropped; with no obstacle left the area is
//! open, so the loop ends.
//!
//! Determinism: every number comes from `rng::stream(seed, 0, STREAM)` through
//! [`rng::uniform`]/[`rng::unit`] in a fixed order; no hash maps, no clock.

use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;

use glam::DVec2;
use rand_chacha::ChaCha8Rng;

use crate::rng;
use crate::scenario::{DEFAULT_AGENT_RADIUS, Scenario};
use crate::world::obstacle::DEFAULT_Z;
use crate::world::{Obstacle, ObstacleShape, Pose, Task, World};

/// Side of the square area, metres.
pub const AREA_SIZE_M: f64 = 20.0;

/// Thickness of the boundary walls just outside the area, metres.
pub const WALL_THICKNESS_M: f64 = 0.5;

/// Free space every obstacle keeps around the start and the goal beyond the agent radius, metres.
pub const CLEAR_MARGIN_M: f64 = 0.5;

/// Side of a cell of the connectivity grid, metres.
pub const GRID_CELL_M: f64 = 0.1;

/// Extra clearance beyond the agent radius a grid cell centre needs to be free, metres.
pub const GRID_MARGIN_M: f64 = 0.05;

/// Random draws allowed to place one obstacle away from the start and the goal.
pub const PLACEMENT_TRIES: usize = 100;

/// The generator's random stream id (see [`rng::stream`]).
const STREAM: u64 = 0x6d61_7073;

/// Size classes: (smallest, largest) box side or cylinder diameter, metres.
const SIZE_CLASSES: [(f64, f64); 3] = [(0.4, 0.6), (0.8, 1.2), (1.6, 2.4)];

/// How full a random world is (seed 000 Fig 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Density {
    /// Few obstacles (8).
    Sparse,
    /// Semi-cluttered (20 obstacles).
    Semi,
    /// Cluttered (40 obstacles).
    Cluttered,
}

impl Density {
    /// All densities, sparsest first.
    pub const ALL: [Density; 3] = [Density::Sparse, Density::Semi, Density::Cluttered];

    /// Number of obstacles placed (before any is dropped to keep the world solvable).
    pub fn obstacle_count(self) -> usize {
        match self {
            Density::Sparse => 8,
            Density::Semi => 20,
            Density::Cluttered => 40,
        }
    }

    /// The name accepted by [`FromStr`]: `sparse`, `semi` or `cluttered`.
    pub fn name(self) -> &'static str {
        match self {
            Density::Sparse => "sparse",
            Density::Semi => "semi",
            Density::Cluttered => "cluttered",
        }
    }
}

impl fmt::Display for Density {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A density name that is not `sparse`, `semi` or `cluttered`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown density `{0}` (expected sparse, semi or cluttered)")]
pub struct ParseDensityError(pub String);

impl FromStr for Density {
    type Err = ParseDensityError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "sparse" => Ok(Density::Sparse),
            "semi" | "semi-cluttered" => Ok(Density::Semi),
            "cluttered" => Ok(Density::Cluttered),
            other => Err(ParseDensityError(other.to_string())),
        }
    }
}

/// A random world of the given density; the same `(density, seed)` always gives the same
/// scenario. One task (start near the lower-left corner, goal near the upper-right one), agent
/// radius 0.3 m. See the [module docs](self) for the construction.
pub fn random_world(density: Density, seed: u64) -> Scenario {
    let mut rng = rng::stream(seed, 0, STREAM);
    let r = DEFAULT_AGENT_RADIUS;
    let start = DVec2::new(rng::uniform(&mut rng, 1.5, 3.0), rng::uniform(&mut rng, 1.5, 3.0));
    let goal =
        DVec2::splat(AREA_SIZE_M) - DVec2::new(rng::uniform(&mut rng, 1.5, 3.0), rng::uniform(&mut rng, 1.5, 3.0));
    let yaw = rng::uniform(&mut rng, -PI, PI);

    let mut placed: Vec<Obstacle> = Vec::new();
    for _ in 0..density.obstacle_count() {
        for _ in 0..PLACEMENT_TRIES {
            let Some(o) = random_obstacle(&mut rng) else { continue };
            let keep = r + CLEAR_MARGIN_M;
            if o.parts.iter().all(|p| p.distance(start) >= keep && p.distance(goal) >= keep) {
                placed.push(o);
                break;
            }
        }
    }

    let walls = boundary_walls();
    let (min, max) = (DVec2::ZERO, DVec2::splat(AREA_SIZE_M));
    loop {
        let world = World::new(walls.iter().chain(&placed).cloned().collect());
        let grid = Occupancy::new(&world, min, max, r);
        let from_start = grid.flood(start);
        if grid.cell(goal).is_some_and(|g| from_start[g]) || placed.is_empty() {
            break;
        }
        let from_goal = grid.flood(goal);
        let fs = grid.frontier(&from_start);
        let fg = grid.frontier(&from_goal);
        let near = |o: &Obstacle, cells: &[DVec2]| -> f64 {
            cells.iter().flat_map(|&c| o.parts.iter().map(move |p| p.distance(c))).fold(f64::INFINITY, f64::min)
        };
        let mut worst = 0;
        let mut worst_d = f64::INFINITY;
        for (i, o) in placed.iter().enumerate() {
            let d = near(o, &fs) + near(o, &fg);
            if d < worst_d {
                worst_d = d;
                worst = i;
            }
        }
        placed.remove(worst);
    }

    let mut scenario = Scenario::new(&format!("random-{density}-{seed}"));
    scenario.agent_radius = r;
    scenario.obstacles = walls;
    scenario.obstacles.extend(placed);
    scenario.tasks.push(Task::new(Pose { position: start, yaw }, goal));
    scenario
}

/// One random box or cylinder somewhere in the area (`None` if the geometry is rejected).
fn random_obstacle(rng: &mut ChaCha8Rng) -> Option<Obstacle> {
    let class = ((rng::unit(rng) * 3.0) as usize).min(2);
    let (lo, hi) = SIZE_CLASSES[class];
    let is_box = rng::unit(rng) < 0.5;
    let shape = if is_box {
        let width = rng::uniform(rng, lo, hi);
        let height = rng::uniform(rng, lo, hi);
        let yaw = rng::uniform(rng, 0.0, PI);
        let center = random_center(rng, 0.5 * width.max(height));
        ObstacleShape::Box { center, width, height, yaw }
    } else {
        let radius = 0.5 * rng::uniform(rng, lo, hi);
        let center = random_center(rng, radius);
        ObstacleShape::Cylinder { center, radius }
    };
    Obstacle::build(shape, DEFAULT_Z.0, DEFAULT_Z.1).ok()
}

fn random_center(rng: &mut ChaCha8Rng, margin: f64) -> DVec2 {
    DVec2::new(rng::uniform(rng, margin, AREA_SIZE_M - margin), rng::uniform(rng, margin, AREA_SIZE_M - margin))
}

/// Four boxes just outside the area.
fn boundary_walls() -> Vec<Obstacle> {
    let (s, t) = (AREA_SIZE_M, WALL_THICKNESS_M);
    [(-t, -t, s + t, 0.0), (-t, s, s + t, s + t), (-t, 0.0, 0.0, s), (s, 0.0, s + t, s)]
        .into_iter()
        .filter_map(|(x0, y0, x1, y1)| {
            let shape = ObstacleShape::Box {
                center: DVec2::new((x0 + x1) * 0.5, (y0 + y1) * 0.5),
                width: x1 - x0,
                height: y1 - y0,
                yaw: 0.0,
            };
            Obstacle::build(shape, DEFAULT_Z.0, DEFAULT_Z.1).ok()
        })
        .collect()
}

/// Whether a disc of `agent_radius` metres can travel from `start` to `goal` inside the box
/// `[min, max]` of `world`, by the grid flood fill described in the [module docs](self)
/// (cells of [`GRID_CELL_M`], free when the clearance at the centre is at least
/// `agent_radius + GRID_MARGIN_M`). `false` when either point is outside the box or on a
/// blocked cell, or for a non-finite input.
pub fn connected(world: &World, min: DVec2, max: DVec2, start: DVec2, goal: DVec2, agent_radius: f64) -> bool {
    if !(min.is_finite() && max.is_finite() && agent_radius.is_finite() && agent_radius >= 0.0) {
        return false;
    }
    let cells = ((max - min) / GRID_CELL_M).ceil();
    if !(cells.x >= 1.0 && cells.y >= 1.0 && cells.x * cells.y <= 1e8) {
        return false;
    }
    let grid = Occupancy::new(world, min, max, agent_radius);
    let reach = grid.flood(start);
    grid.cell(goal).is_some_and(|g| reach[g])
}

/// The free cells of the connectivity grid.
struct Occupancy {
    min: DVec2,
    nx: usize,
    ny: usize,
    free: Vec<bool>,
}

impl Occupancy {
    fn new(world: &World, min: DVec2, max: DVec2, agent_radius: f64) -> Occupancy {
        let nx = ((max.x - min.x) / GRID_CELL_M).ceil().max(0.0) as usize;
        let ny = ((max.y - min.y) / GRID_CELL_M).ceil().max(0.0) as usize;
        let need = agent_radius + GRID_MARGIN_M;
        let mut free = vec![true; nx * ny];
        if nx == 0 || ny == 0 {
            return Occupancy { min, nx, ny, free };
        }
        // A cell is blocked when some part lies nearer than `need` to its centre: the same rule
        // as `world.clearance(centre, need) < need`, found by visiting, for each part, only the
        // cells whose centres lie in its bounding box grown by `need`.
        let span = |lo: f64, hi: f64, origin: f64, n: usize| -> Option<(usize, usize)> {
            let first = ((lo - need - origin) / GRID_CELL_M - 0.5).floor().max(0.0);
            let last = ((hi + need - origin) / GRID_CELL_M - 0.5).ceil().min(n as f64 - 1.0);
            (first <= last).then_some((first as usize, last as usize))
        };
        for part in world.parts() {
            let b = part.shape.aabb();
            let (Some((i0, i1)), Some((j0, j1))) =
                (span(b.min.x, b.max.x, min.x, nx), span(b.min.y, b.max.y, min.y, ny))
            else {
                continue;
            };
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let k = j * nx + i;
                    if free[k] && part.shape.distance(Self::center_of(min, i, j)) < need {
                        free[k] = false;
                    }
                }
            }
        }
        Occupancy { min, nx, ny, free }
    }

    fn center_of(min: DVec2, i: usize, j: usize) -> DVec2 {
        min + DVec2::new((i as f64 + 0.5) * GRID_CELL_M, (j as f64 + 0.5) * GRID_CELL_M)
    }

    /// Index of the cell holding `p`, if inside the grid.
    fn cell(&self, p: DVec2) -> Option<usize> {
        let q = (p - self.min) / GRID_CELL_M;
        if !(q.x >= 0.0 && q.y >= 0.0) {
            return None;
        }
        let (i, j) = (q.x.floor() as usize, q.y.floor() as usize);
        (i < self.nx && j < self.ny).then_some(j * self.nx + i)
    }

    fn neighbours(&self, k: usize) -> impl Iterator<Item = usize> + use<> {
        let (i, j, nx, ny) = (k % self.nx, k / self.nx, self.nx, self.ny);
        [(i > 0).then(|| k - 1), (i + 1 < nx).then(|| k + 1), (j > 0).then(|| k - nx), (j + 1 < ny).then(|| k + nx)]
            .into_iter()
            .flatten()
    }

    /// Free cells reachable from the cell holding `p` (none when that cell is blocked).
    fn flood(&self, p: DVec2) -> Vec<bool> {
        let mut seen = vec![false; self.free.len()];
        let Some(first) = self.cell(p).filter(|&c| self.free[c]) else {
            return seen;
        };
        seen[first] = true;
        let mut stack = vec![first];
        while let Some(k) = stack.pop() {
            for n in self.neighbours(k) {
                if self.free[n] && !seen[n] {
                    seen[n] = true;
                    stack.push(n);
                }
            }
        }
        seen
    }

    /// Centres of the reached cells that touch an unreached cell.
    fn frontier(&self, reached: &[bool]) -> Vec<DVec2> {
        (0..reached.len())
            .filter(|&k| reached[k] && self.neighbours(k).any(|n| !reached[n]))
            .map(|k| Self::center_of(self.min, k % self.nx, k / self.nx))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn occupancy_is_the_clearance_rule() {
        // Rotated boxes, cylinders and walls, some reaching past the grid.
        for (density, seed) in [(Density::Cluttered, 3), (Density::Semi, 8), (Density::Sparse, 1)] {
            let world = random_world(density, seed).world();
            let (min, max) = (DVec2::new(-0.73, -1.0), DVec2::new(AREA_SIZE_M + 0.5, AREA_SIZE_M - 2.0));
            for r in [0.0, 0.3, 0.61] {
                let grid = Occupancy::new(&world, min, max, r);
                let need = r + GRID_MARGIN_M;
                let mut scratch = Vec::new();
                let mut blocked = 0;
                for j in 0..grid.ny {
                    for i in 0..grid.nx {
                        let c = Occupancy::center_of(min, i, j);
                        let free = world.clearance(c, need, &mut scratch) >= need;
                        assert_eq!(grid.free[j * grid.nx + i], free, "{density} seed {seed} r {r} at {c}");
                        blocked += usize::from(!free);
                    }
                }
                assert!(blocked > 0);
            }
        }
    }
}
