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
use crate::world::{Obstacle, Task, Terrain, World};

/// Default agent radius, metres.
pub const DEFAULT_AGENT_RADIUS: f64 = 0.3;

/// Largest start or goal coordinate, metres: worlds are at most 200 km across.
pub const MAX_COORDINATE_M: f64 = 100_000.0;

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
