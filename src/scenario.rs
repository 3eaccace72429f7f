//! A scenario: a world description plus the navigation tasks to run in it and the agent's
//! size (seed 000 §4, Fig 2 environments; DESIGN.md §1). Map files of every format (Rhai
//! maps, the plain text world format, MovingAI grids) become a [`Scenario`], which is
//! validated before anything runs.
//!
//! Invariant: a scenario that passed [`Scenario::validate`] has finite coordinates, at least
//! one task, and every start and goal lies outside every obstacle grown by the agent radius.

pub mod crowd;

use glam::DVec2;

use crate::geom::Shape;
use crate::world::obstacle::Band;
use crate::world::terrain::TerrainFeature;
use crate::world::{Obstacle, ObstacleShape, Task, Terrain, World};

/// Default agent radius, metres.
pub const DEFAULT_AGENT_RADIUS: f64 = 0.3;

/// Largest start or goal coordinate, metres: worlds are at most 200 km across.
pub const MAX_COORDINATE_M: f64 = 100_000.0;

/// Most obstacles a world may hold, and most terrain features: far beyond any map (a BARN
/// world has a few hundred cylinders), and few enough that what a world costs to build, index
/// and plan over stays bounded. Text worlds, BARN worlds and map scripts count what they read
/// with a [`WorldBudget`]; a MovingAI map is bounded by its cells.
pub const MAX_OBSTACLES: usize = 100_000;

/// Most convex parts the obstacles and terrain features of a world may have together (a
/// `poly` outline has as many as it splits into): the reference planner keeps some 70 corners
/// for each, so this keeps its graph within a gigabyte or two.
pub const MAX_PARTS: usize = 200_000;

/// Most outline points (`convex` and `poly`) the obstacles and terrain features of a world
/// may have together; one outline has at most
/// [`MAX_OUTLINE_POINTS`](crate::world::obstacle::MAX_OUTLINE_POINTS).
pub const MAX_POINTS: usize = 1_000_000;

/// What a world read so far holds, counted against [`MAX_OBSTACLES`], [`MAX_PARTS`] and
/// [`MAX_POINTS`] as each obstacle or terrain feature is built (the cost of building one is
/// bounded by its outline), so an oversized world is refused at the item that overflows it.
#[derive(Debug, Clone, Copy, Default)]
pub struct WorldBudget {
    obstacles: usize,
    features: usize,
    parts: usize,
    points: usize,
}

impl WorldBudget {
    /// Counts an obstacle; the error says which bound it passes.
    pub fn obstacle(&mut self, o: &Obstacle) -> Result<(), String> {
        self.obstacles += 1;
        if self.obstacles > MAX_OBSTACLES {
            return Err(format!("more than {MAX_OBSTACLES} obstacles"));
        }
        self.outline(&o.shape, o.parts.len())
    }

    /// Counts a terrain feature; the error says which bound it passes.
    pub fn feature(&mut self, f: &TerrainFeature) -> Result<(), String> {
        self.features += 1;
        if self.features > MAX_OBSTACLES {
            return Err(format!("more than {MAX_OBSTACLES} terrain features"));
        }
        self.outline(&f.shape, f.parts().len())
    }

    fn outline(&mut self, shape: &ObstacleShape, parts: usize) -> Result<(), String> {
        self.parts += parts;
        if self.parts > MAX_PARTS {
            return Err(format!(
                "more than {MAX_PARTS} convex parts in all (a `poly` counts the pieces it splits into)"
            ));
        }
        self.points += match shape {
            ObstacleShape::Convex { points } => points.len(),
            ObstacleShape::Polygon { outline } => outline.len(),
            ObstacleShape::Box { .. } | ObstacleShape::Cylinder { .. } => 0,
        };
        if self.points > MAX_POINTS {
            return Err(format!("more than {MAX_POINTS} outline points in all"));
        }
        Ok(())
    }
}

/// A world description with its tasks.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// Name (file stem or generator description).
    pub name: String,
    /// The obstacles.
    pub obstacles: Vec<Obstacle>,
    /// Navigation tasks; each is one episode.
    pub tasks: Vec<Task>,
    /// Radius of the agent's disc, metres.
    pub agent_radius: f64,
    /// A benchmark's reference for the tasks (a BARN challenge world), if any.
    pub reference: Option<Reference>,
    /// The ground: flat, or with platforms, slopes, stairs and holes (seed 002 §3.2).
    pub terrain: Terrain,
    /// The footstep planner's parameters for the characters of this map (seed 002 §4.2).
    pub footsteps: crate::footstep::FootstepParams,
    /// The crowd, when the agents of this world run together as one episode (`None`: each
    /// task is an episode of its own). Its tasks are [`crowd::Crowd::tasks`] ([`Scenario::set_crowd`]).
    pub crowd: Option<crowd::Crowd>,
}

/// Speed at which a BARN reference path is walked for the challenge's optimal time, m/s.
pub const BARN_SPEED_MPS: f64 = 2.0;

/// A benchmark's reference for a scenario's tasks: the BARN challenge's reference path. Its
/// score for an episode is `success · OT / clip(AT, 2·OT, 8·OT)`, with AT the time taken and OT
/// the reference path's length at a reference speed ([`Reference::score`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reference {
    /// Length of the reference path, metres.
    pub path_length_m: f64,
}

impl Reference {
    /// The BARN metric of an episode that took `time_s` seconds (`reached` or not), with the
    /// optimal time OT the reference path's length at `speed_mps`: `OT / clip(AT, 2·OT, 8·OT)`
    /// when reached, else 0. The challenge itself uses [`BARN_SPEED_MPS`]; at most 0.5.
    pub fn score(&self, reached: bool, time_s: f64, speed_mps: f64) -> f64 {
        let ot = self.path_length_m / speed_mps;
        if !reached || !(ot > 0.0) || !time_s.is_finite() {
            return 0.0;
        }
        ot / time_s.clamp(2.0 * ot, 8.0 * ot)
    }
}

impl Scenario {
    /// An empty scenario with the default agent radius.
    pub fn new(name: &str) -> Scenario {
        Scenario {
            name: name.to_string(),
            obstacles: Vec::new(),
            tasks: Vec::new(),
            agent_radius: DEFAULT_AGENT_RADIUS,
            reference: None,
            terrain: Terrain::Flat,
            footsteps: Default::default(),
            crowd: None,
        }
    }

    /// Makes the scenario a crowd: its tasks become the crowd's ([`crowd::Crowd::tasks`], one
    /// per agent) and its agent radius the smallest of the crowd's radii.
    pub fn set_crowd(&mut self, crowd: crowd::Crowd) {
        self.tasks = crowd.tasks();
        self.agent_radius = crowd.smallest_radius().unwrap_or(self.agent_radius);
        self.crowd = Some(crowd);
    }

    /// The world the tasks run in, its obstacles sorted into three bands ([`Band`]):
    /// obstacles low enough to step onto or over ([`Obstacle::is_low`]) are part of its terrain,
    /// not walls; obstacles above the legs ([`Band::Upper`]) are the upper body's
    /// ([`World::overhead`]); the rest are the navigation's walls.
    pub fn world(&self) -> World {
        let terrain = self.terrain.with_low_obstacles(&self.obstacles);
        let band = |b: Band| self.obstacles.iter().filter(move |o| o.band() == b).cloned();
        let mut world = World::new(band(Band::Legs).collect());
        world.overhead = band(Band::Upper).collect();
        world.terrain = terrain;
        world.footsteps = self.footsteps;
        world
    }

    /// Checks the scenario; the message says which task or obstacle is wrong.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.agent_radius.is_finite() && self.agent_radius > 0.0) {
            return Err(format!("agent radius must be a positive number, found {}", self.agent_radius));
        }
        if let Some(c) = &self.crowd {
            c.validate(&self.obstacles).map_err(|m| format!("crowd: {m}"))?;
        }
        if self.tasks.is_empty() {
            return Err("no task: give a start and a goal".into());
        }
        let inside = |p: DVec2| -> Option<usize> {
            // Overhead obstacles leave the legs room: a task may start or end under one.
            self.obstacles.iter().position(|o| {
                o.band() != Band::Upper && o.parts.iter().any(|s: &Shape| s.distance(p) < self.agent_radius)
            })
        };
        for (i, t) in self.tasks.iter().enumerate() {
            let n = i + 1;
            if !(t.start.position.is_finite() && t.start.yaw.is_finite() && t.goal.is_finite()) {
                return Err(format!("task {n}: start or goal is not a finite number"));
            }
            if !(t.goal_radius.is_finite() && t.goal_radius > 0.0) {
                return Err(format!("task {n}: goal radius must be positive, found {}", t.goal_radius));
            }
            if !(t.time_limit_s.is_finite() && t.time_limit_s > 0.0 && t.time_limit_s <= Task::MAX_TIME_LIMIT_S) {
                return Err(format!(
                    "task {n}: time limit must be positive and at most {} s, found {}",
                    Task::MAX_TIME_LIMIT_S,
                    t.time_limit_s
                ));
            }
            for (what, p) in [("start", t.start.position), ("goal", t.goal)] {
                if p.abs().max_element() > MAX_COORDINATE_M {
                    return Err(format!(
                        "task {n}: the {what} ({}, {}) is farther than {MAX_COORDINATE_M} m from the origin along an axis",
                        p.x, p.y
                    ));
                }
            }
            if t.goal_radius > MAX_COORDINATE_M {
                return Err(format!("task {n}: goal radius {} is larger than {MAX_COORDINATE_M} m", t.goal_radius));
            }
            if let Some(o) = inside(t.start.position) {
                return Err(format!(
                    "task {n}: the start ({}, {}) is inside obstacle {} (grown by the agent radius {} m)",
                    t.start.position.x,
                    t.start.position.y,
                    o + 1,
                    self.agent_radius
                ));
            }
            if let Some(o) = inside(t.goal) {
                return Err(format!(
                    "task {n}: the goal ({}, {}) is inside obstacle {} (grown by the agent radius {} m)",
                    t.goal.x,
                    t.goal.y,
                    o + 1,
                    self.agent_radius
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::obstacle::{DEFAULT_Z, MAX_OUTLINE_POINTS};

    fn build(shape: ObstacleShape) -> Obstacle {
        Obstacle::build(shape, DEFAULT_Z.0, DEFAULT_Z.1).unwrap()
    }

    /// How many copies of `o` a world takes before its budget refuses one, and the message.
    fn copies_taken(o: &Obstacle) -> (usize, String) {
        let mut budget = WorldBudget::default();
        let mut n = 0;
        loop {
            match budget.obstacle(o) {
                Ok(()) => n += 1,
                Err(m) => return (n, m),
            }
        }
    }

    #[test]
    fn a_world_budget_counts_obstacles_parts_and_points() {
        let cylinder = build(ObstacleShape::Cylinder { center: DVec2::ZERO, radius: 1.0 });
        let (n, m) = copies_taken(&cylinder);
        assert_eq!(n, MAX_OBSTACLES, "{m}");
        assert!(m.contains("obstacles"), "{m}");
        // A comb of 1,000 teeth splits into some 1,000 convex parts.
        let mut outline = vec![DVec2::new(0.0, 0.0)];
        for t in 0..1000 {
            let x = 2.0 * t as f64;
            outline.extend([
                DVec2::new(x, 1.0),
                DVec2::new(x, 3.0),
                DVec2::new(x + 1.0, 3.0),
                DVec2::new(x + 1.0, 1.0),
            ]);
        }
        outline.extend([DVec2::new(2000.0, 1.0), DVec2::new(2000.0, 0.0)]);
        let comb = build(ObstacleShape::Polygon { outline });
        let (n, m) = copies_taken(&comb);
        assert_eq!(n, MAX_PARTS / comb.parts.len(), "{m}");
        assert!(m.contains("convex parts"), "{m}");
        // A convex outline is one part but all its points.
        let points: Vec<DVec2> = (0..MAX_OUTLINE_POINTS)
            .map(|i| DVec2::from_angle(std::f64::consts::TAU * i as f64 / MAX_OUTLINE_POINTS as f64) * 100.0)
            .collect();
        let round = build(ObstacleShape::Convex { points });
        let (n, m) = copies_taken(&round);
        assert_eq!(n, MAX_POINTS / MAX_OUTLINE_POINTS, "{m}");
        assert!(m.contains("outline points"), "{m}");
    }
}
