//! Map importers and world generators: every function here produces a
//! [`Scenario`](crate::scenario::Scenario) (a world plus its navigation tasks), ready for
//! [`Scenario::validate`](crate::scenario::Scenario::validate) and the simulator
//! (DESIGN.md §1).
//!
//! - [`text`]: the plain text world format (`start`, `goal`, `cyl`, `box`, `convex`, `poly`, …),
//!   read and written losslessly; also reads the BARN challenge worlds and the Menge U-trap.
//! - [`barn`]: the BARN challenge's own files, a Gazebo `.world` and its `path_N.npy`.
//! - [`movingai`]: MovingAI grid benchmarks (`.map` + `.scen`); blocked cells are merged into a
//!   few axis-aligned boxes and the map is closed by boundary walls.
//! - [`steersuite`]: SteerSuite's test cases (XML), every agent with its goal sequence as a
//!   [`Crowd`](crate::scenario::crowd::Crowd), random parts drawn from a seed.
//! - [`generate`]: seeded random worlds at the three densities of seed 000 Fig 2 (sparse,
//!   semi-cluttered, cluttered), filled with boxes and cylinders in three sizes each and
//!   solvable by construction.
//! - [`building`]: seeded random buildings, a grid of rooms joined by a random tree of doors
//!   plus a few loops.
//! - [`maze`]: seeded random mazes with 2–3 m corridors, carved depth first, with loops.
//! - [`grid`]: seeded random grid maps of 1 m cells, 10–25 % blocked, in the MovingAI manner.
//! - [`crowd`]: seeded crowds (`corridor`, `crossing`, `bottleneck`, `circle`) of a given
//!   number of agents, each world one episode of all its agents.
//! - [`kind`]: [`WorldKind`], the name of every generator (`random:KIND` on command lines),
//!   and [`kind::generate`], the one entry point to all of them.
//!
//! Units are metres and radians. Every parse error is a [`crate::diagnostic::SourceError`]
//! naming the file, line and column of the offending token; no input makes these functions
//! panic. Everything is deterministic: no clock, no hash-order dependence, and randomness only
//! from [`crate::rng`].

pub mod barn;
pub mod building;
mod cells;
pub mod crowd;
pub mod generate;
pub mod grid;
pub mod kind;
pub mod maze;
pub mod movingai;
pub mod steersuite;
pub mod text;

pub use kind::WorldKind;

use crate::scenario::Scenario;
use crate::world::World;

/// Which end of a task is blocked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TaskEnd {
    Start,
    Goal,
}

/// The first task whose start or goal lies within the agent radius of an obstacle, found with
/// the world's spatial index (the same rule as [`Scenario::validate`], without its linear scan
/// over all obstacles): `(task index, which end, obstacle index)`.
pub(crate) fn first_blocked_task(scenario: &Scenario, world: &World) -> Option<(usize, TaskEnd, usize)> {
    let r = scenario.agent_radius;
    let mut scratch = Vec::new();
    let mut hit = |p: glam::DVec2| -> Option<usize> {
        world.parts_near(p, r, &mut scratch);
        let mut best: Option<usize> = None;
        for &i in scratch.iter() {
            let part = &world.parts()[i];
            // Overhead obstacles leave the legs room: a task may start or end under one.
            let overhead = world.obstacles()[part.obstacle].band() == crate::world::obstacle::Band::Upper;
            if !overhead && part.shape.distance(p) < r && best.is_none_or(|b| part.obstacle < b) {
                best = Some(part.obstacle);
            }
        }
        best
    };
    for (i, t) in scenario.tasks.iter().enumerate() {
        if let Some(o) = hit(t.start.position) {
            return Some((i, TaskEnd::Start, o));
        }
        if let Some(o) = hit(t.goal) {
            return Some((i, TaskEnd::Goal, o));
        }
    }
    None
}
