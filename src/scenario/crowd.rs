//! A crowd: many agents in one world, run together as one episode (SteerSuite's test cases,
//! crowds in text and Rhai worlds, the seeded crowd generators of [`crate::maps::crowd`]).
//! Plain data with its validation; moving the agents is the simulation's.
//!
//! Every agent has a start pose, a radius, an initial speed and a sequence of goals done in
//! order. A goal ends when it is achieved or when its duration has passed, whichever comes
//! first, and the agent moves on to the next; SteerSuite's semantics, goal by goal:
//!
//! | goal | SteerSuite element | the agent… | achieved when |
//! |------|--------------------|------------|---------------|
//! | [`GoalKind::SeekPoint`] | `seekStaticTarget` | walks to the point | its centre is within its own radius of the point |
//! | [`GoalKind::FleePoint`] | `fleeStaticTarget` | walks away from the point | never: the duration ends it |
//! | [`GoalKind::SeekAgent`] | `seekDynamicTarget` | follows another agent | its disc touches that agent's (centres at most the sum of the radii apart) |
//! | [`GoalKind::FleeAgent`] | `fleeDynamicTarget` | walks away from another agent | never |
//! | [`GoalKind::SeekRegion`] | `seekAxisAlignedBoxRegion` | walks to the target point | its centre is inside the box |
//! | [`GoalKind::Flow`] | `flowStaticDirection` | walks along a direction | never |
//! | [`GoalKind::FlowDynamic`] | `flowDynamicDirection` | follows the crowd's flow of a kind | never |
//! | [`GoalKind::Idle`] | `idle` | stands | never |
//!
//! Each goal has a desired speed (m/s, the speed the agent keeps while it is free to) and a
//! duration (s). An agent that has ended its last goal leaves the world, as in SteerSuite,
//! unless the crowd keeps arrived agents standing ([`Crowd::stay_on_arrival`]).
//!
//! SteerBench's score of an episode (its "composite02" technique) is, averaged over the
//! agents, `50 · collisions + time enabled + Σ ½|v|² + Σ |Δv/Δt|`: the agent's distinct
//! collisions (a contact with one other agent or obstacle counts once however long it lasts;
//! a new contact after a separation counts again), the time it spent in the world, and over
//! its steps the kinetic energy per unit mass of its velocity and the magnitude of its
//! acceleration (the change of velocity between consecutive steps over the step).
//!
//! [`Crowd::tasks`] gives each agent a [`Task`] so that code reading a scenario's tasks keeps
//! working: from the agent's start to its last static target (see [`Crowd::stand_in_target`]),
//! with the agent's radius as goal radius and the sum of its goals' durations (at most
//! [`Task::MAX_TIME_LIMIT_S`]) as time limit.
//!
//! Invariant: a crowd that passed [`Crowd::validate`] has 1 to [`MAX_AGENTS`] agents, finite
//! poses and points, radii in (0, [`MAX_AGENT_RADIUS_M`]], speeds in [0,
//! [`MAX_SPEED_MPS`]], at least one goal per agent with a positive duration, references to
//! other existing agents only, and no agent overlapping an obstacle at its start.

use glam::DVec2;

use crate::world::obstacle::Band;
use crate::world::{Obstacle, Pose, Task, World};

/// Most agents a crowd may hold (SteerSuite's largest published cases have 5,000).
pub const MAX_AGENTS: usize = 10_000;
/// Largest agent radius, metres: far above a person (SteerSuite's agents are 0.5 m).
pub const MAX_AGENT_RADIUS_M: f64 = 5.0;
/// Largest initial or desired speed, m/s: above a sprinter's.
pub const MAX_SPEED_MPS: f64 = 15.0;
/// A typical walking speed, m/s (SteerSuite's cases use 1.3): the desired speed of the agents
/// a crowd text world makes of its `start`/`goal` pairs.
pub const DEFAULT_DESIRED_SPEED_MPS: f64 = 1.3;
/// Largest coordinate of a point or a start, metres (as [`crate::scenario::MAX_COORDINATE_M`]).
const MAX_COORDINATE_M: f64 = 100_000.0;

/// A crowd of agents sharing one world.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Crowd {
    /// The agents, in order; goals name other agents by their index here.
    pub agents: Vec<CrowdAgent>,
    /// Whether an agent that ended its last goal stays standing in the world (`false`, the
    /// default: it leaves, as in SteerSuite).
    pub stay_on_arrival: bool,
}

/// One agent of a crowd.
#[derive(Debug, Clone, PartialEq)]
pub struct CrowdAgent {
    /// Its name (may be empty); SteerSuite's goals name their dynamic targets by it.
    pub name: String,
    /// Where it starts and which way it faces.
    pub start: Pose,
    /// Radius of its disc, metres.
    pub radius_m: f64,
    /// Speed along its heading at the start, m/s.
    pub speed_mps: f64,
    /// Its goals, done in order.
    pub goals: Vec<Goal>,
}

/// One goal of an agent's sequence.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Goal {
    /// What the agent does.
    pub kind: GoalKind,
    /// The speed it keeps while free to, m/s.
    pub desired_speed_mps: f64,
    /// The longest it spends on this goal before moving on, seconds.
    pub duration_s: f64,
}

/// What an agent does during one goal (see the [module docs](self) for when each ends).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GoalKind {
    /// Walk to a point.
    SeekPoint(DVec2),
    /// Walk away from a point.
    FleePoint(DVec2),
    /// Follow the agent of this index.
    SeekAgent(usize),
    /// Walk away from the agent of this index.
    FleeAgent(usize),
    /// Walk to `target`; achieved inside the axis-aligned box `min`–`max`.
    SeekRegion {
        /// The point walked to, metres.
        target: DVec2,
        /// The box's lower corner, metres.
        min: DVec2,
        /// The box's upper corner, metres.
        max: DVec2,
    },
    /// Walk along a direction (not necessarily of unit length, never zero).
    Flow(DVec2),
    /// Follow the crowd's flow of a kind.
    FlowDynamic(FlowKind),
    /// Stand.
    Idle,
}

/// The kinds of dynamic flow of SteerSuite's `flowDynamicDirection`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FlowKind {
    /// Go where the neighbours go (`FOLLOW_CROWD`).
    FollowCrowd,
    /// Flocking (`BOIDS`).
    Boids,
    /// Advection by a velocity field (`ADVECT`).
    Advect,
    /// Left to the steering (`OTHER`).
    Other,
}

impl FlowKind {
    /// Every kind.
    pub const ALL: [FlowKind; 4] = [FlowKind::FollowCrowd, FlowKind::Boids, FlowKind::Advect, FlowKind::Other];

    /// The name in text worlds and scripts: `follow_crowd`, `boids`, `advect` or `other`.
    pub fn name(self) -> &'static str {
        match self {
            FlowKind::FollowCrowd => "follow_crowd",
            FlowKind::Boids => "boids",
            FlowKind::Advect => "advect",
            FlowKind::Other => "other",
        }
    }

    /// The kind named `name` (text worlds' and scripts' names, or SteerSuite's upper-case
    /// ones).
    pub fn parse(name: &str) -> Option<FlowKind> {
        FlowKind::ALL.into_iter().find(|k| k.name().eq_ignore_ascii_case(name))
    }
}

impl GoalKind {
    /// The keyword of this kind in text worlds and the name of its Rhai function: `seek`,
    /// `flee`, `seek_agent`, `flee_agent`, `seek_region`, `flow`, `flow_dynamic` or `idle`.
    pub fn keyword(&self) -> &'static str {
        match self {
            GoalKind::SeekPoint(_) => "seek",
            GoalKind::FleePoint(_) => "flee",
            GoalKind::SeekAgent(_) => "seek_agent",
            GoalKind::FleeAgent(_) => "flee_agent",
            GoalKind::SeekRegion { .. } => "seek_region",
            GoalKind::Flow(_) => "flow",
            GoalKind::FlowDynamic(_) => "flow_dynamic",
            GoalKind::Idle => "idle",
        }
    }

    /// Every keyword of [`GoalKind::keyword`].
    pub const KEYWORDS: [&'static str; 8] =
        ["seek", "flee", "seek_agent", "flee_agent", "seek_region", "flow", "flow_dynamic", "idle"];

    /// The fixed point this goal walks to, if it has one.
    pub fn static_target(&self) -> Option<DVec2> {
        match *self {
            GoalKind::SeekPoint(p) | GoalKind::SeekRegion { target: p, .. } => Some(p),
            _ => None,
        }
    }
}

impl Crowd {
    /// The point an agent's [`Task`] leads to: the target of its last goal that walks to a
    /// fixed point ([`GoalKind::SeekPoint`], [`GoalKind::SeekRegion`]), or its start when none
    /// does (an agent that only flees, flows, follows or stands).
    pub fn stand_in_target(agent: &CrowdAgent) -> DVec2 {
        agent.goals.iter().rev().find_map(|g| g.kind.static_target()).unwrap_or(agent.start.position)
    }

    /// One task per agent, in order: start, [`Crowd::stand_in_target`], the agent's radius as
    /// goal radius, and the sum of its goals' durations (at most [`Task::MAX_TIME_LIMIT_S`]) as
    /// time limit.
    pub fn tasks(&self) -> Vec<Task> {
        self.agents
            .iter()
            .map(|a| {
                let total: f64 = a.goals.iter().map(|g| g.duration_s).sum();
                Task {
                    start: a.start,
                    goal: Crowd::stand_in_target(a),
                    goal_radius: a.radius_m,
                    time_limit_s: total.min(Task::MAX_TIME_LIMIT_S),
                }
            })
            .collect()
    }

    /// The smallest agent radius, metres (`None` for no agents).
    pub fn smallest_radius(&self) -> Option<f64> {
        self.agents.iter().map(|a| a.radius_m).reduce(f64::min)
    }

    /// Checks the crowd against the world's `obstacles`; the message names the agent (from 1)
    /// and goal (from 1) at fault. Obstacles the legs pass under or step over
    /// ([`Band::Upper`], [`Band::Ground`]) do not count as overlapping a start.
    pub fn validate(&self, obstacles: &[Obstacle]) -> Result<(), String> {
        let n = self.agents.len();
        if n == 0 {
            return Err("a crowd needs at least one agent".into());
        }
        if n > MAX_AGENTS {
            return Err(format!("{n} agents: a crowd holds at most {MAX_AGENTS}"));
        }
        for (i, a) in self.agents.iter().enumerate() {
            a.check(i, n).map_err(|m| format!("agent {}: {m}", i + 1))?;
        }
        let legs: Vec<usize> = (0..obstacles.len()).filter(|&i| obstacles[i].band() == Band::Legs).collect();
        let walls = World::new(legs.iter().map(|&i| obstacles[i].clone()).collect());
        let mut scratch = Vec::new();
        for (i, a) in self.agents.iter().enumerate() {
            if let Some(o) = overlapped_obstacle(&walls, a.start.position, a.radius_m, &mut scratch) {
                let p = a.start.position;
                return Err(format!(
                    "agent {}: its disc of radius {} m at ({}, {}) overlaps obstacle {}",
                    i + 1,
                    a.radius_m,
                    p.x,
                    p.y,
                    legs[o] + 1
                ));
            }
        }
        Ok(())
    }

    /// The pairs of agents (indices, first the smaller) whose discs overlap at the start by
    /// more than `tolerance_m`, in order. SteerSuite places the agents of its cases as given
    /// even when they overlap (only random positions are drawn clear of others); the readers
    /// report such pairs and leave them to the steering.
    pub fn overlapping_starts(&self, tolerance_m: f64) -> Vec<(usize, usize)> {
        let Some(largest) = self.agents.iter().map(|a| a.radius_m).reduce(f64::max) else { return Vec::new() };
        let cell = (2.0 * largest).max(1e-3);
        let key = |p: DVec2| ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64);
        let mut cells: std::collections::BTreeMap<(i64, i64), Vec<usize>> = std::collections::BTreeMap::new();
        for (i, a) in self.agents.iter().enumerate() {
            cells.entry(key(a.start.position)).or_default().push(i);
        }
        let mut pairs = Vec::new();
        for (i, a) in self.agents.iter().enumerate() {
            let (cx, cy) = key(a.start.position);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for &j in cells.get(&(cx + dx, cy + dy)).map_or(&[][..], Vec::as_slice) {
                        let b = &self.agents[j];
                        if j > i && a.start.position.distance(b.start.position) < a.radius_m + b.radius_m - tolerance_m
                        {
                            pairs.push((i, j));
                        }
                    }
                }
            }
        }
        pairs.sort_unstable();
        pairs
    }
}

/// The first obstacle (its index in `world`) that a disc of `radius` at `p` overlaps.
pub(crate) fn overlapped_obstacle(world: &World, p: DVec2, radius: f64, scratch: &mut Vec<usize>) -> Option<usize> {
    world.parts_near(p, radius, scratch);
    scratch
        .iter()
        .map(|&k| &world.parts()[k])
        .filter(|part| part.shape.distance(p) < radius)
        .map(|part| part.obstacle)
        .min()
}

impl CrowdAgent {
    /// The agent a crowd makes of a world's task: unnamed, of `radius_m`, at rest, seeking the
    /// task's goal at [`DEFAULT_DESIRED_SPEED_MPS`] for the task's time limit.
    pub fn from_task(task: &Task, radius_m: f64) -> CrowdAgent {
        let seek = Goal {
            kind: GoalKind::SeekPoint(task.goal),
            desired_speed_mps: DEFAULT_DESIRED_SPEED_MPS,
            duration_s: task.time_limit_s,
        };
        CrowdAgent { name: String::new(), start: task.start, radius_m, speed_mps: 0.0, goals: vec![seek] }
    }

    /// Checks one agent (index `me` of `n`).
    fn check(&self, me: usize, n: usize) -> Result<(), String> {
        let p = self.start.position;
        if !(p.is_finite() && self.start.yaw.is_finite()) {
            return Err("its start is not a finite number".into());
        }
        if p.abs().max_element() > MAX_COORDINATE_M {
            return Err(format!("its start ({}, {}) is farther than {MAX_COORDINATE_M} m from the origin", p.x, p.y));
        }
        if !(self.radius_m > 0.0 && self.radius_m <= MAX_AGENT_RADIUS_M) {
            return Err(format!("radius must be above 0 and at most {MAX_AGENT_RADIUS_M} m, found {}", self.radius_m));
        }
        if !(self.speed_mps >= 0.0 && self.speed_mps <= MAX_SPEED_MPS) {
            return Err(format!("initial speed must be from 0 to {MAX_SPEED_MPS} m/s, found {}", self.speed_mps));
        }
        if self.goals.is_empty() {
            return Err("no goal: give it at least one".into());
        }
        for (k, g) in self.goals.iter().enumerate() {
            g.check(me, n).map_err(|m| format!("goal {} ({}): {m}", k + 1, g.kind.keyword()))?;
        }
        Ok(())
    }
}

impl Goal {
    /// Checks one goal of agent `me` of `n`.
    fn check(&self, me: usize, n: usize) -> Result<(), String> {
        if !(self.desired_speed_mps >= 0.0 && self.desired_speed_mps <= MAX_SPEED_MPS) {
            return Err(format!(
                "desired speed must be from 0 to {MAX_SPEED_MPS} m/s, found {}",
                self.desired_speed_mps
            ));
        }
        if !(self.duration_s > 0.0 && self.duration_s.is_finite()) {
            return Err(format!("duration must be a positive number of seconds, found {}", self.duration_s));
        }
        let point = |p: DVec2| -> Result<(), String> {
            if !p.is_finite() || p.abs().max_element() > MAX_COORDINATE_M {
                return Err(format!("the point ({}, {}) is not finite or beyond {MAX_COORDINATE_M} m", p.x, p.y));
            }
            Ok(())
        };
        match self.kind {
            GoalKind::SeekPoint(p) | GoalKind::FleePoint(p) => point(p)?,
            GoalKind::SeekAgent(j) | GoalKind::FleeAgent(j) => {
                if j >= n {
                    return Err(format!("it names agent {}, but the crowd has {n}", j + 1));
                }
                if j == me {
                    return Err("an agent cannot follow or flee itself".into());
                }
            }
            GoalKind::SeekRegion { target, min, max } => {
                point(target)?;
                point(min)?;
                point(max)?;
                if min.x > max.x || min.y > max.y {
                    return Err(format!(
                        "the region's lower corner ({}, {}) is above its upper corner ({}, {})",
                        min.x, min.y, max.x, max.y
                    ));
                }
            }
            GoalKind::Flow(d) => {
                if !(d.is_finite() && d.length() > 0.0) {
                    return Err(format!("the direction ({}, {}) must be finite and not zero", d.x, d.y));
                }
            }
            GoalKind::FlowDynamic(_) | GoalKind::Idle => {}
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::ObstacleShape;

    fn agent(x: f64, y: f64, goals: Vec<Goal>) -> CrowdAgent {
        CrowdAgent {
            name: String::new(),
            start: Pose { position: DVec2::new(x, y), yaw: 0.0 },
            radius_m: 0.5,
            speed_mps: 0.0,
            goals,
        }
    }

    fn seek(x: f64, y: f64, duration_s: f64) -> Goal {
        Goal { kind: GoalKind::SeekPoint(DVec2::new(x, y)), desired_speed_mps: 1.3, duration_s }
    }

    #[test]
    fn tasks_lead_to_the_last_static_target() {
        let flee = Goal { kind: GoalKind::FleeAgent(0), desired_speed_mps: 1.0, duration_s: 5.0 };
        let crowd = Crowd {
            agents: vec![
                agent(0.0, 0.0, vec![seek(5.0, 0.0, 10.0), seek(5.0, 5.0, 20.0)]),
                agent(3.0, 3.0, vec![seek(1.0, 1.0, 1e30), flee]),
                agent(-3.0, 3.0, vec![Goal { kind: GoalKind::Idle, desired_speed_mps: 0.0, duration_s: 4.0 }]),
            ],
            stay_on_arrival: false,
        };
        crowd.validate(&[]).unwrap();
        let t = crowd.tasks();
        assert_eq!((t[0].goal, t[0].goal_radius, t[0].time_limit_s), (DVec2::new(5.0, 5.0), 0.5, 30.0));
        assert_eq!((t[1].goal, t[1].time_limit_s), (DVec2::new(1.0, 1.0), Task::MAX_TIME_LIMIT_S));
        assert_eq!((t[2].goal, t[2].time_limit_s), (DVec2::new(-3.0, 3.0), 4.0));
        assert_eq!(crowd.smallest_radius(), Some(0.5));
    }

    #[test]
    fn validation_names_the_agent_and_goal() {
        let ok = || agent(0.0, 0.0, vec![seek(1.0, 0.0, 5.0)]);
        let bad = |f: &dyn Fn(&mut CrowdAgent)| {
            let mut a = ok();
            f(&mut a);
            Crowd { agents: vec![ok(), a], stay_on_arrival: false }.validate(&[]).unwrap_err()
        };
        assert!(bad(&|a| a.radius_m = 0.0).starts_with("agent 2: radius"));
        assert!(bad(&|a| a.radius_m = 6.0).contains("radius"));
        assert!(bad(&|a| a.speed_mps = -1.0).contains("initial speed"));
        assert!(bad(&|a| a.start.position.x = f64::NAN).contains("finite"));
        assert!(bad(&|a| a.goals.clear()).contains("no goal"));
        assert!(bad(&|a| a.goals[0].duration_s = 0.0).contains("goal 1 (seek): duration"));
        assert!(bad(&|a| a.goals[0].desired_speed_mps = 20.0).contains("desired speed"));
        assert!(bad(&|a| a.goals[0].kind = GoalKind::SeekAgent(1)).contains("itself"));
        assert!(bad(&|a| a.goals[0].kind = GoalKind::FleeAgent(7)).contains("names agent 8"));
        assert!(bad(&|a| a.goals[0].kind = GoalKind::Flow(DVec2::ZERO)).contains("not zero"));
        let region = GoalKind::SeekRegion { target: DVec2::ZERO, min: DVec2::ONE, max: DVec2::ZERO };
        assert!(bad(&|a| a.goals[0].kind = region).contains("lower corner"));
        assert!(Crowd::default().validate(&[]).unwrap_err().contains("at least one agent"));
    }

    #[test]
    fn starts_inside_walls_are_refused_and_overlaps_reported() {
        let wall = Obstacle::build(
            ObstacleShape::Box { center: DVec2::new(0.0, 2.0), width: 4.0, height: 1.0, yaw: 0.0 },
            0.0,
            1.0,
        )
        .unwrap();
        let low =
            Obstacle::build(ObstacleShape::Cylinder { center: DVec2::new(5.0, 0.0), radius: 1.0 }, 0.0, 0.2).unwrap();
        let crowd = |y: f64| Crowd {
            agents: vec![agent(0.0, y, vec![seek(9.0, 0.0, 5.0)]), agent(5.0, 0.0, vec![seek(9.0, 0.0, 5.0)])],
            stay_on_arrival: false,
        };
        // The low cylinder is ground to step onto, not a wall.
        crowd(0.9).validate(&[low.clone(), wall.clone()]).unwrap();
        let e = crowd(1.2).validate(&[low, wall]).unwrap_err();
        assert!(e.starts_with("agent 1:") && e.contains("obstacle 2"), "{e}");
        let mut c = crowd(0.0);
        c.agents.push(agent(0.9, 0.0, vec![seek(1.0, 1.0, 1.0)]));
        c.agents.push(agent(5.0, 1.0, vec![seek(1.0, 1.0, 1.0)]));
        assert_eq!(c.overlapping_starts(1e-9), vec![(0, 2)]);
        assert_eq!(c.overlapping_starts(0.2), Vec::<(usize, usize)>::new());
    }
}
