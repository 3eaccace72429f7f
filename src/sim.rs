//! The navigation loop (seed 000 §3.1, §4): agents sense the world, the layered fuzzy
//! controller commands a turn and a speed, bodies move, metrics accumulate — at a fixed time
//! step, deterministically.
//!
//! [`Simulation::step`] takes everything it needs from its arguments and fields: no clock, no
//! global RNG, no hash-order dependence, so the same scenario, rules and seed give the same
//! trajectory bit for bit. Several agents may share a world; each sees the others as discs.

pub mod animated;
pub mod body;
pub mod controller;
pub mod failure;
pub mod follow;
pub mod footing;
pub mod memory;
pub mod sense;
pub mod side_on;
pub mod upper_body;

use glam::DVec2;

pub use animated::{AnimatedBody, Animation, AnimationHandle, Tracking, TrackingFigures, measure_tracking};
pub use body::{Body, Command, DiscLimits, KinematicDisc, OpenSpace, Space, StepOutcome};

pub use controller::{ControllerParams, FollowState, LayeredController, Mode, NavInputs, within_reach};
pub use follow::Side;
pub use memory::{Memory, MemoryParams};

use crate::world::{SectorLayout, Sensed, Task, World};
use sense::{goal_visible, heading_to_goal, obstacle_goal_distance, scan};

/// Fixed parameters of a simulation. Every field documents its default.
#[derive(Debug, Clone, PartialEq)]
pub struct StepParameters {
    /// Time step, seconds (0.05).
    pub dt_s: f64,
    /// Rays of the all-around scan that picks the heading toward the goal (72, every 5°).
    pub scan_rays: usize,
    /// The scan is refreshed every this many steps (4).
    pub scan_every: usize,
    /// Sensor sectors and range (right, front, left; 5 m).
    pub layout: SectorLayout,
    /// Limits of each agent's disc body (see [`DiscLimits`]); the radius applies to animated
    /// bodies too.
    pub limits: DiscLimits,
    /// What agents remember of what they sense (see [`MemoryParams`]).
    pub memory: MemoryParams,
    /// When set, agents are animated characters driven by this database and policy instead of
    /// kinematic discs (none).
    pub animation: Option<AnimationHandle>,
    /// A clock lent by a front-end to time footstep planning on uneven terrain (none: not
    /// timed). Only the timing figures read it; the motion never does.
    pub stopwatch: Option<footing::StopwatchHandle>,
    /// Whether animated characters record every frame they play ([`AnimatedBody::motion`];
    /// false). Recording never changes the motion.
    pub record_motion: bool,
}

impl Default for StepParameters {
    fn default() -> Self {
        StepParameters {
            dt_s: 0.05,
            scan_rays: 72,
            scan_every: 4,
            layout: SectorLayout::three(),
            limits: DiscLimits::default(),
            memory: MemoryParams::default(),
            animation: None,
            stopwatch: None,
            record_motion: false,
        }
    }
}

/// How an agent's episode ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Inside the goal radius.
    Reached,
    /// Time limit passed.
    TimedOut,
    /// The body cannot get to the goal: what it cannot pass under or step across leaves no way
    /// round (the reason is [`Agent::refusal`]). Decided at the start, before any step.
    Refused,
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
    /// Stalled steps: the body had to shorten or refuse a step because it would have hit
    /// something, or stood (or turned on the spot) against a command to move because nothing
    /// ahead was clear.
    pub stalled_steps: u32,
    /// Steps taken.
    pub steps: u32,
    /// Times boundary following started.
    pub follows: u32,
    /// The first step that ended overlapping something: when, where and what.
    pub first_collision: Option<failure::Contact>,
}

/// One agent: body, controller, task, what it sensed last, and its trail.
#[derive(Debug, Clone)]
pub struct Agent {
    /// The body.
    pub body: AgentBody,
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
    /// Why the body cannot get to the goal ([`Outcome::Refused`]).
    pub refusal: Option<String>,
    /// When set, the agent follows this command (a user driving it, seed 002 §3.1) instead
    /// of its controller's; the controller still runs, so its state stays current.
    pub manual: Option<Command>,
    /// What the controller commanded at the last step (equal to `command` unless `manual`).
    pub autopilot: Command,
    /// What the agent remembers of what it has sensed, and its way to the goal over it.
    pub memory: Memory,
    /// Direction the agent heads for to approach the goal (absolute, radians): toward the
    /// waypoint of the way it remembers, else (no way known) the goal itself when the way is
    /// open or the most promising free direction of the scan.
    pub heading_to_goal: f64,
    /// Length of the remembered way to the goal, metres (infinite when none is known).
    pub route_m: f64,
    /// Distance to the waypoint goal seeking steers at (infinite when heading for the goal).
    pub aim_m: f64,
    /// The remembered way goes through a narrow part just ahead, lined up for.
    pub through_gap: bool,
    /// Closest approach to the goal reachable in a straight line from the last scan, metres.
    pub reachable_goal_distance: f64,
    /// Distance from the goal to the nearest obstacle point the last scan saw, metres.
    pub obstacle_goal_distance: f64,
    /// Where the agent last moved [`STUCK_MOVE_M`] away from, and when (seconds): an agent that
    /// stays that near for [`STUCK_S`] closes the gaps just ahead of it that its body does not
    /// pass through.
    progress: (DVec2, f64),
    /// Middles of the gaps where a side-on passage gave up once.
    side_on_failed: Vec<DVec2>,
    scan: Vec<f64>,
    /// The last scan of the world's obstacles alone (no other agents).
    walls: Vec<f64>,
}

impl Agent {
    /// The agent's last all-around scan: the free distance for its disc along each of
    /// [`StepParameters::scan_rays`] rays (ray `i` at `2πi/n` from the world's X axis), metres
    /// (empty before the first step).
    pub fn scan(&self) -> &[f64] {
        &self.scan
    }
}

/// An agent's body: a kinematic disc or an animated character.
#[derive(Debug, Clone)]
pub enum AgentBody {
    /// Kinematic disc.
    Disc(KinematicDisc),
    /// Character driven by the animation database.
    Animated(Box<AnimatedBody>),
}

impl AgentBody {
    /// The animated character, if this is one.
    pub fn animated(&self) -> Option<&AnimatedBody> {
        match self {
            AgentBody::Animated(a) => Some(a),
            AgentBody::Disc(_) => None,
        }
    }

    /// The animated character, if this is one, to change.
    pub fn animated_mut(&mut self) -> Option<&mut AnimatedBody> {
        match self {
            AgentBody::Animated(a) => Some(a),
            AgentBody::Disc(_) => None,
        }
    }
}

impl Body for AgentBody {
    fn pose(&self) -> crate::world::Pose {
        match self {
            AgentBody::Disc(d) => d.pose(),
            AgentBody::Animated(a) => a.pose(),
        }
    }

    fn speed(&self) -> f64 {
        match self {
            AgentBody::Disc(d) => d.speed(),
            AgentBody::Animated(a) => a.speed(),
        }
    }

    fn radius(&self) -> f64 {
        match self {
            AgentBody::Disc(d) => d.radius(),
            AgentBody::Animated(a) => a.radius(),
        }
    }

    fn turn_limit(&self, speed: f64) -> f64 {
        match self {
            AgentBody::Disc(d) => d.turn_limit(speed),
            AgentBody::Animated(a) => a.turn_limit(speed),
        }
    }

    fn passage_m(&self) -> f64 {
        match self {
            AgentBody::Disc(d) => d.passage_m(),
            AgentBody::Animated(a) => a.passage_m(),
        }
    }

    fn narrowest_passage_m(&self) -> Option<f64> {
        match self {
            AgentBody::Disc(d) => d.narrowest_passage_m(),
            AgentBody::Animated(a) => a.narrowest_passage_m(),
        }
    }

    fn footprint(&self) -> side_on::Footprint {
        match self {
            AgentBody::Disc(d) => d.footprint(),
            AgentBody::Animated(a) => a.footprint(),
        }
    }

    fn step(&mut self, command: Command, dt: f64, space: &mut dyn Space) -> StepOutcome {
        match self {
            AgentBody::Disc(d) => d.step(command, dt, space),
            AgentBody::Animated(a) => a.step(command, dt, space),
        }
    }
}

/// What an agent's body sees while it moves: the world's obstacles and the other agents' discs.
pub struct Surroundings<'a> {
    /// The world.
    pub world: &'a World,
    /// The other agents (centre, radius).
    pub others: &'a [(DVec2, f64)],
    /// Scratch space for index queries.
    pub scratch: &'a mut Vec<usize>,
}

impl Space for Surroundings<'_> {
    fn clearance(&mut self, p: DVec2, max: f64) -> f64 {
        let mut c = self.world.clearance(p, max, self.scratch);
        for &(o, r) in self.others {
            c = c.min((o.distance(p) - r).max(0.0));
        }
        c
    }

    fn segment_clearance(&mut self, a: DVec2, b: DVec2, max: f64) -> f64 {
        let mut c = self.world.segment_clearance(a, b, max, self.scratch);
        for &(o, r) in self.others {
            if let Ok(disc) = crate::geom::Shape::circle(o, r) {
                c = c.min(disc.segment_distance(a, b));
            }
        }
        c
    }

    fn changes(&self) -> bool {
        !self.others.is_empty()
    }
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
    /// What the upper bodies of animated agents plan around, built with the first of them.
    solids: Option<std::sync::Arc<crate::upper::Solids>>,
    /// The walls the body's third dimension added to the navigation's world, if any.
    body_walls: Option<Box<BodyWalls>>,
}

/// What a body cannot pass under or step across, made walls of its navigation
/// ([`World::walled_below`], [`World::walled_holes`]), with the world as it was.
#[derive(Debug, Clone)]
struct BodyWalls {
    plain: World,
    walls: Vec<(crate::world::Obstacle, String)>,
}

/// Why `wall` is one for a body that ducks under `clear_under_m` and steps across `step_m`.
fn wall_reason(wall: &crate::world::Obstacle, clear_under_m: f64, step_m: f64) -> String {
    let at = failure::where_is(wall);
    if wall.z_min > 0.0 {
        format!(
            "the obstacle {at}, its underside {:.2} m up, is lower than the character can duck under ({clear_under_m:.2} m) \
             and higher than it can step over",
            wall.z_min
        )
    } else {
        format!("the hole {at} is wider than the longest step ({step_m:.2} m)")
    }
}

impl Simulation {
    /// An empty simulation of `world`.
    pub fn new(world: World, params: StepParameters) -> Simulation {
        // The character walks round what it cannot duck under (standing height without an upper
        // body that ducks) and holes it cannot step across.
        let (world, body_walls) = match &params.animation {
            Some(a) => {
                let clear = crate::upper::duck_height_of(&a.0.db.skeleton)
                    .map_or(crate::world::obstacle::BODY_TOP_M, |d| d + crate::upper::DUCK_ROOM_M);
                let step = world.footsteps.step_max_m;
                let walled = world.clone().walled_below(clear).walled_holes(step);
                // `World::with_walls` appends the walls after the world's own obstacles.
                let walls = walled.obstacles()[world.obstacles().len()..]
                    .iter()
                    .map(|o| (o.clone(), wall_reason(o, clear, step)))
                    .collect::<Vec<_>>();
                (walled, (!walls.is_empty()).then(|| Box::new(BodyWalls { plain: world, walls })))
            }
            None => (world, None),
        };
        Simulation {
            world,
            agents: Vec::new(),
            params,
            time_s: 0.0,
            scratch: Vec::new(),
            others: Vec::new(),
            solids: None,
            body_walls,
        }
    }

    /// Adds an agent at the task's start with its own copy of `controller`.
    pub fn add_agent(&mut self, task: Task, controller: &LayeredController) {
        let body = match &self.params.animation {
            None => AgentBody::Disc(KinematicDisc::new(task.start, self.params.limits)),
            Some(a) => {
                let mut body = AnimatedBody::new(a.0.clone(), task.start, self.params.limits.radius);
                if !self.world.terrain.is_flat() {
                    let terrain = std::sync::Arc::new(self.world.terrain.clone());
                    let at = body.player().ground();
                    body.set_footing(footing::Footing::new(
                        terrain,
                        self.world.footsteps,
                        at,
                        self.params.stopwatch.clone(),
                        a.0.footsteps,
                    ));
                }
                if self.world.upper_body_matters() {
                    let solids = self
                        .solids
                        .get_or_insert_with(|| std::sync::Arc::new(crate::upper::Solids::new(self.world.solids())));
                    let terrain =
                        (!self.world.terrain.is_flat()).then(|| std::sync::Arc::new(self.world.terrain.clone()));
                    let h = 1.0 / a.0.player.frame_rate;
                    if let Some(upper) = upper_body::UpperBodyState::new(
                        &a.0.db.skeleton,
                        std::sync::Arc::clone(solids),
                        terrain,
                        self.params.stopwatch.clone(),
                        h,
                    ) {
                        body.set_upper_body(upper);
                    }
                }
                if self.params.record_motion {
                    body.record_motion();
                }
                AgentBody::Animated(Box::new(body))
            }
        };
        let refusal = self.refusal(&task);
        let mut controller = controller.clone();
        controller.reset();
        let clearance = self.world.clearance(task.start.position, self.params.layout.range, &mut self.scratch)
            - self.params.limits.radius;
        let mut memory = Memory::new(task.start.position, task.goal, self.params.limits.radius, self.params.memory);
        if let Some(narrowest) = body.narrowest_passage_m() {
            memory = memory.with_narrowest(narrowest);
        }
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
                stalled_steps: 0,
                steps: 0,
                follows: 0,
                first_collision: None,
            },
            outcome: refusal.is_some().then_some(Outcome::Refused),
            refusal,
            manual: None,
            autopilot: Command::default(),
            memory,
            heading_to_goal: 0.0,
            route_m: f64::INFINITY,
            aim_m: f64::INFINITY,
            through_gap: false,
            reachable_goal_distance: f64::INFINITY,
            obstacle_goal_distance: f64::INFINITY,
            progress: (task.start.position, 0.0),
            side_on_failed: Vec::new(),
            scan: Vec::new(),
            walls: Vec::new(),
        });
    }

    /// Why a body starting `task` cannot get to its goal, when walls of its own close every
    /// way there that the plain world leaves open: the walls the plain world's shortest way
    /// goes through, described.
    fn refusal(&self, task: &Task) -> Option<String> {
        let bw = self.body_walls.as_deref()?;
        let (from, to, r) = (task.start.position, task.goal, self.params.limits.radius);
        if crate::plan::shortest_path(&self.world, from, to, r).is_some() {
            return None;
        }
        let way = crate::plan::shortest_path(&bw.plain, from, to, r)?;
        let across = |o: &crate::world::Obstacle| {
            way.points.windows(2).any(|w| o.parts.iter().any(|p| p.segment_distance(w[0], w[1]) < r))
        };
        let mut reasons: Vec<&str> = bw.walls.iter().filter(|(o, _)| across(o)).map(|(_, why)| why.as_str()).collect();
        if reasons.is_empty() {
            reasons = bw.walls.iter().map(|(_, why)| why.as_str()).collect();
        }
        Some(format!("no way round for the character: {}", reasons.join("; ")))
    }

    /// Why agent `i`'s episode failed, in words ([`failure`]): refused (why), timed out (how
    /// far from the goal) and collided (the first time: when, where, into what); `None` while
    /// it runs, when it reached its goal without a collision, or when there is no agent `i`.
    pub fn failure(&self, i: usize) -> Option<String> {
        let a = self.agents.get(i)?;
        let upper = a.body.animated().and_then(|b| b.upper_body()).map_or(0, |u| u.figures().collisions);
        let mut why = Vec::new();
        match a.outcome? {
            Outcome::Refused => why.push(a.refusal.clone().unwrap_or_else(|| "refused".into())),
            Outcome::TimedOut => why.push(failure::timed_out(
                a.metrics.time_s,
                a.task.time_limit_s,
                a.body.pose().position,
                &a.trail,
                self.params.dt_s,
                a.task.goal,
                a.task.goal_radius,
            )),
            Outcome::Reached => {}
        }
        if a.metrics.collisions > 0 || upper > 0 {
            why.push(failure::collided(a.metrics.collisions, a.metrics.first_collision.as_ref(), upper, &self.world));
        }
        (!why.is_empty()).then(|| why.join("; "))
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
            discs_except(&self.agents, i, &mut self.others);
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
            let step_index = (t / dt).round() as usize;
            if agent.scan.is_empty() || step_index.is_multiple_of(self.params.scan_every.max(1)) {
                scan(
                    &self.world,
                    pose.position,
                    radius,
                    self.params.scan_rays,
                    self.params.layout.range,
                    &self.others,
                    &mut self.scratch,
                    &mut agent.scan,
                    &mut agent.walls,
                );
                (agent.heading_to_goal, agent.reachable_goal_distance) =
                    heading_to_goal(&agent.scan, pose.position, agent.task.goal, radius, self.params.layout.range);
                agent.memory.observe(pose.position, &agent.walls, radius, self.params.layout.range);
                agent.route_m = f64::INFINITY;
                agent.aim_m = f64::INFINITY;
                agent.through_gap = false;
                let range = self.params.layout.range;
                let margin = agent.controller.params.margin_m;
                let scan = &agent.scan;
                let sight = |h: f64| match follow::swept_ahead(scan, h, radius, margin, range) {
                    Some(f) if f < range => f,
                    _ => f64::INFINITY,
                };
                let world = &self.world;
                let scratch = &mut self.scratch;
                let span = |p: DVec2, d: &[DVec2], out: &mut [f64]| world.ray_casts(p, d, range, scratch, out);
                let reach = |h: f64| match follow::swept_ahead(scan, h, radius, 0.0, range) {
                    Some(f) if f < range => f,
                    _ => f64::INFINITY,
                };
                if let Some(aim) = agent.memory.heading_with(pose.position, sight, span, reach) {
                    agent.heading_to_goal = aim.heading;
                    agent.route_m = aim.remaining_m;
                    agent.aim_m = aim.waypoint_m;
                    agent.through_gap = aim.through_gap;
                    if let Some(gap) = aim.gap {
                        side_on_ahead(agent, gap);
                    }
                }
                // A side-on passage that gave up twice at the same gap: the gap is closed and the
                // next plan goes round.
                if let Some(gap) = agent.body.animated_mut().and_then(AnimatedBody::take_failed_side_on) {
                    if agent.side_on_failed.iter().any(|p| p.distance(gap.centre) < SIDE_ON_SAME_GAP_M) {
                        agent.memory.seal(gap.centre);
                    } else {
                        agent.side_on_failed.push(gap.centre);
                    }
                }
                // A way the body has not been able to follow for long may lead through a gap
                // it does not fit through (the memory closes gaps at the disc's own width; a
                // character keeps a margin beyond it): such gaps just ahead are remembered as
                // closed, and the next plan goes round.
                let (anchor, since) = &mut agent.progress;
                if pose.position.distance(*anchor) > STUCK_MOVE_M {
                    (*anchor, *since) = (pose.position, t);
                } else if t - *since > STUCK_S {
                    let keep = agent.task.goal_radius + STUCK_GOAL_M;
                    let passage = agent.body.passage_m();
                    // The range sensor measures the way across, both sides.
                    let world = &self.world;
                    let scratch = &mut self.scratch;
                    let width = |p: DVec2, across: DVec2| -> f64 {
                        [across, -across]
                            .iter()
                            .map(|&d| world.ray_cast(p, d, passage, scratch).unwrap_or(passage))
                            .sum()
                    };
                    agent.memory.close_gaps_ahead(pose.position, passage, keep, width);
                    *since = t;
                }
                agent.obstacle_goal_distance =
                    obstacle_goal_distance(&agent.scan, pose.position, agent.task.goal, radius, FOLLOWED_REACH_M);
            }
            agent.sensed.scan.clone_from(&agent.scan);
            agent.sensed.reachable_goal_distance = agent.reachable_goal_distance;
            agent.sensed.obstacle_goal_distance = agent.obstacle_goal_distance;
            agent.sensed.route_distance = agent.route_m;
            agent.sensed.aim_distance = agent.aim_m;
            agent.sensed.through_gap = agent.through_gap;
            agent.sensed.known_obstacles = agent.memory.known();
            agent.sensed.goal_angle = crate::geom::wrap_angle(agent.heading_to_goal - pose.yaw);
            // Whether the straight way to the goal is open, cast only when the controller asks.
            let (world, layout, scratch, goal) = (&self.world, &self.params.layout, &mut self.scratch, agent.task.goal);
            let visible = || goal_visible(world, pose.position, goal, radius, layout, scratch);
            agent.autopilot = agent.controller.command(&agent.sensed, visible, t, &agent.body);
            agent.command = agent.manual.unwrap_or(agent.autopilot);
        }
        // Move in order; each body may only stand where it overlaps nothing.
        for i in 0..self.agents.len() {
            if self.agents[i].outcome.is_some() {
                continue;
            }
            discs_except(&self.agents, i, &mut self.others);
            let Simulation { world, agents, params, scratch, others, .. } = self;
            let agent = &mut agents[i];
            let radius = agent.body.radius();
            let mut space = Surroundings { world, others, scratch };
            let step = agent.body.step(agent.command, dt, &mut space);
            let m = &mut agent.metrics;
            m.time_s = t + dt;
            m.path_length_m += step.moved_m;
            m.stalled_steps += u32::from(step.stalled());
            m.steps += 1;
            m.follows = agent.controller.follow_count();
            let p = agent.body.pose().position;
            let footprint = agent.body.footprint();
            let gap = match footprint {
                side_on::Footprint::Capsule { a, b, radius } => {
                    let mut gap = world.segment_clearance(a, b, params.layout.range, scratch) - radius;
                    for &(c, r) in others.iter() {
                        gap = gap.min(crate::plan::point_segment_distance(c, a, b) - r - radius);
                    }
                    gap
                }
                side_on::Footprint::Disc { .. } => {
                    let mut gap = world.clearance(p, params.layout.range, scratch) - radius;
                    for &(c, r) in others.iter() {
                        gap = gap.min(c.distance(p) - r - radius);
                    }
                    gap
                }
            };
            m.min_clearance_m = m.min_clearance_m.min(gap);
            if gap < -1e-9 {
                m.collisions += 1;
                if m.first_collision.is_none() {
                    let with = failure::touched(world, footprint, others, i, scratch);
                    m.first_collision = Some(failure::Contact { time_s: m.time_s, position: p, depth_m: -gap, with });
                }
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

/// A narrow part of the way this near ahead (its throat's middle, along the way through it) is
/// passed side-on, metres, and farther by [`SIDE_ON_STOP_S`] at the body's speed (it stops
/// first).
const SIDE_ON_START_M: f64 = 1.0;

/// See [`SIDE_ON_START_M`], seconds.
const SIDE_ON_STOP_S: f64 = 0.6;

/// ... when the spot where it comes to a stand lies off the way through the gap's middle by no
/// more than this share of its distance along it and [`SIDE_ON_OFF_M`] (the manoeuvre side-steps
/// onto the way from there; farther off, the walking line-up brings it nearer first).
const SIDE_ON_OFF_SHARE: f64 = 0.6;

/// See [`SIDE_ON_OFF_SHARE`], metres.
const SIDE_ON_OFF_M: f64 = 0.3;

/// A gap narrower than the walking disc and this much is passed side-on even where the
/// remembered way through it is open to the walking disc, metres.
const SIDE_ON_WALK_SLACK_M: f64 = 0.1;

/// Gaps whose middles lie this near each other are the same, metres.
const SIDE_ON_SAME_GAP_M: f64 = 0.3;

/// The remembered way crosses cells only the narrowest stance crosses this near ahead, metres.
const SIDE_ON_LOOK_M: f64 = 2.0;

/// The way ahead of `agent`, at `at`, goes through `gap`: when the remembered way there is open
/// only to the body's narrowest stance and the gap is just ahead, the body passes it in that
/// stance (a character side-on, [`side_on`]) — or, measured too narrow even for that, the gap
/// is closed and the next plan goes round.
fn side_on_ahead(agent: &mut Agent, gap: side_on::Gap) {
    let Some(narrowest) = agent.body.narrowest_passage_m() else { return };
    let tight = gap.width < 2.0 * agent.body.radius() + SIDE_ON_WALK_SLACK_M;
    if gap.width >= agent.body.passage_m() || !(tight || agent.memory.narrow_ahead(SIDE_ON_LOOK_M)) {
        return;
    }
    let pose = agent.body.pose();
    let along = (gap.centre - pose.position).dot(gap.through);
    let stopping = SIDE_ON_STOP_S * agent.body.speed();
    if !(along > 0.0 && along <= SIDE_ON_START_M + stopping) {
        return;
    }
    // Where it comes to a stand, going on as it heads now.
    let to = gap.centre - (pose.position + DVec2::from_angle(pose.yaw) * stopping);
    let (along, off) = (to.dot(gap.through), to.perp_dot(gap.through).abs());
    if gap.width < narrowest {
        agent.memory.seal(gap.centre);
    } else if along > 0.0
        && off <= SIDE_ON_OFF_SHARE * along + SIDE_ON_OFF_M
        && let Some(body) = agent.body.animated_mut()
    {
        body.pass_side_on(gap);
    }
}

/// An agent that has stayed within [`STUCK_MOVE_M`] of a place for this long closes the gaps
/// just ahead of it that its body does not pass through, seconds.
pub const STUCK_S: f64 = 15.0;

/// See [`STUCK_S`], metres.
pub const STUCK_MOVE_M: f64 = 0.5;

/// The way is never closed this near the goal circle, metres (an agent circling its goal is
/// not held up by a gap).
const STUCK_GOAL_M: f64 = 1.0;

/// Obstacle points within this free distance count as the boundary being followed, metres.
pub const FOLLOWED_REACH_M: f64 = 1.2;

/// The discs (centre, radius) of every agent but `i`, into `out`.
fn discs_except(agents: &[Agent], i: usize, out: &mut Vec<(DVec2, f64)>) {
    out.clear();
    out.extend(
        agents.iter().enumerate().filter(|(j, _)| *j != i).map(|(_, a)| (a.body.pose().position, a.body.radius())),
    );
}
