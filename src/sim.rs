//! The navigation loop (seed 000 §3.1, §4): agents sense the world, the layered fuzzy
//! controller commands a turn and a speed, bodies move, metrics accumulate — at a fixed time
//! step, deterministically.
//!
//! [`Simulation::step`] takes everything it needs from its arguments and fields: no clock, no
//! global RNG, no hash-order dependence, so the same scenario, rules and seed give the same
//! trajectory bit for bit. Several agents may share a world; each sees the others as discs.

pub mod body;
pub mod controller;

use glam::DVec2;

pub use body::{Body, Command, DiscLimits, KinematicDisc, StepOutcome};
pub use controller::{ControllerParams, LayeredController, Mode, Side};

use crate::world::{SectorLayout, Sensed, Task, World};

/// Fixed parameters of a simulation. Every field documents its default.
#[derive(Debug, Clone, PartialEq)]
pub struct StepParameters {
    /// Time step, seconds (0.05).
    pub dt_s: f64,
    /// Sensor sectors and range (right, front, left; 5 m).
    pub layout: SectorLayout,
    /// Limits of each agent's disc body (see [`DiscLimits`]).
    pub limits: DiscLimits,
}

impl Default for StepParameters {
    fn default() -> Self {
        StepParameters { dt_s: 0.05, layout: SectorLayout::three(), limits: DiscLimits::default() }
    }
}

/// How an agent's episode ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Inside the goal radius.
    Reached,
    /// Time limit passed.
    TimedOut,
}

/// Running measurements of one agent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    /// Simulated time, seconds.
    pub time_s: f64,
    /// Distance travelled, metres.
    pub path_length_m: f64,
    /// Smallest gap between the agent's disc and any obstacle or agent, metres.
    pub min_clearance_m: f64,
    /// Steps that ended with the disc overlapping an obstacle or agent.
    pub collisions: u32,
    /// Steps the body had to shorten or refuse because it would have hit something.
    pub blocked_steps: u32,
    /// Times boundary following started.
    pub follows: u32,
}

/// One agent: body, controller, task, what it sensed last, and its trail.
#[derive(Debug, Clone)]
pub struct Agent {
    /// The body.
    pub body: KinematicDisc,
    /// The navigation controller.
    pub controller: LayeredController,
    /// The task.
    pub task: Task,
    /// What it sensed at the last step.
    pub sensed: Sensed,
    /// The last command.
    pub command: Command,
    /// Positions after every step (the first is the start).
    pub trail: Vec<DVec2>,
    /// Measurements so far.
    pub metrics: Metrics,
    /// Set when the episode of this agent is over.
    pub outcome: Option<Outcome>,
}

/// A world with agents, stepped at a fixed rate.
#[derive(Debug, Clone)]
pub struct Simulation {
    /// The world.
    pub world: World,
    /// The agents, stepped in order.
    pub agents: Vec<Agent>,
    /// Fixed parameters.
    pub params: StepParameters,
    /// Simulated time, seconds.
    pub time_s: f64,
    scratch: Vec<usize>,
    others: Vec<(DVec2, f64)>,
}

impl Simulation {
    /// An empty simulation of `world`.
    pub fn new(world: World, params: StepParameters) -> Simulation {
        Simulation { world, agents: Vec::new(), params, time_s: 0.0, scratch: Vec::new(), others: Vec::new() }
    }

    /// Adds an agent at the task's start with its own copy of `controller`.
    pub fn add_agent(&mut self, task: Task, controller: &LayeredController) {
        let body = KinematicDisc::new(task.start, self.params.limits);
        let mut controller = controller.clone();
        controller.reset();
        let clearance = self.world.clearance(task.start.position, self.params.layout.range, &mut self.scratch)
            - self.params.limits.radius;
        self.agents.push(Agent {
            body,
            controller,
            task,
            sensed: Sensed::default(),
            command: Command::default(),
            trail: vec![task.start.position],
            metrics: Metrics {
                time_s: 0.0,
                path_length_m: 0.0,
                min_clearance_m: clearance,
                collisions: 0,
                blocked_steps: 0,
                follows: 0,
            },
            outcome: None,
        });
    }

    /// True when every agent's episode is over.
    pub fn all_done(&self) -> bool {
        self.agents.iter().all(|a| a.outcome.is_some())
    }

    /// Advances every unfinished agent by one time step.
    pub fn step(&mut self) {
        let dt = self.params.dt_s;
        let t = self.time_s;
        // Sense and decide with everybody at their positions at time t.
        for i in 0..self.agents.len() {
            if self.agents[i].outcome.is_some() {
                continue;
            }
            self.others.clear();
            for (j, other) in self.agents.iter().enumerate() {
                if j != i {
                    self.others.push((other.body.pose().position, other.body.radius()));
                }
            }
            let agent = &mut self.agents[i];
            let pose = agent.body.pose();
            let radius = agent.body.radius();
            self.world.sense(
                pose.position,
                pose.yaw,
                radius,
                agent.task.goal,
                &self.params.layout,
                &self.others,
                &mut self.scratch,
                &mut agent.sensed,
            );
            let visible = goal_visible(&self.world, pose.position, agent.task.goal, radius, &self.params.layout, &mut self.scratch);
            agent.command = agent.controller.command(&agent.sensed, visible, t);
        }
        // Move in order; each body may only stand where it overlaps nothing.
        for i in 0..self.agents.len() {
            if self.agents[i].outcome.is_some() {
                continue;
            }
            self.others.clear();
            for (j, other) in self.agents.iter().enumerate() {
                if j != i {
                    self.others.push((other.body.pose().position, other.body.radius()));
                }
            }
            let Simulation { world, agents, params, scratch, others, .. } = self;
            let agent = &mut agents[i];
            let radius = agent.body.radius();
            let mut free = |p: DVec2| {
                world.is_free(p, radius, scratch) && others.iter().all(|&(c, r)| c.distance(p) >= r + radius)
            };
            let step = agent.body.step(agent.command, dt, &mut free);
            let m = &mut agent.metrics;
            m.time_s = t + dt;
            m.path_length_m += step.moved_m;
            m.blocked_steps += u32::from(step.blocked);
            m.follows = agent.controller.follow_count();
            let p = agent.body.pose().position;
            let mut gap = world.clearance(p, params.layout.range, scratch) - radius;
            for &(c, r) in others.iter() {
                gap = gap.min(c.distance(p) - r - radius);
            }
            m.min_clearance_m = m.min_clearance_m.min(gap);
            if gap < -1e-9 {
                m.collisions += 1;
            }
            agent.trail.push(p);
            if p.distance(agent.task.goal) <= agent.task.goal_radius {
                agent.outcome = Some(Outcome::Reached);
            } else if m.time_s >= agent.task.time_limit_s {
                agent.outcome = Some(Outcome::TimedOut);
            }
        }
        self.time_s = t + dt;
    }
}

/// How far ahead the straight way to the goal must be free to count as open, metres.
pub const GOAL_LOOKAHEAD_M: f64 = 2.0;

/// True when a disc of `radius` could move straight from `from` toward `goal` over the next
/// `min(distance, range, GOAL_LOOKAHEAD_M)` metres without touching an obstacle (three
/// parallel rays).
pub fn goal_visible(
    world: &World,
    from: DVec2,
    goal: DVec2,
    radius: f64,
    layout: &SectorLayout,
    scratch: &mut Vec<usize>,
) -> bool {
    let d = from.distance(goal);
    if d <= 1e-9 {
        return true;
    }
    let dir = (goal - from) / d;
    let reach = d.min(layout.range).min(GOAL_LOOKAHEAD_M);
    let side = dir.perp() * radius;
    [from, from + side, from - side].iter().all(|&o| world.ray_cast(o, dir, reach, scratch).is_none())
}
