//! The layered fuzzy navigation controller of seed 000 §3.1 (DESIGN.md §2), plus the
//! boundary-following behaviour that keeps a reactive planner out of U-shaped traps.
//!
//! The rule script (default `scripts/nav.rhai`) builds a [`Network`] of fuzzy engines that
//! reads what the agent senses — the free distance `front` (the corridor the disc sweeps
//! straight ahead, from the all-around scan), `left`, `right` (sectors), the `nearest` obstacle
//! in any direction, `balance` (`left - right`, m), `goal_angle` (degrees, positive to the
//! left), `goal_distance` (m), `wall` (free distance to the nearest obstacle), `wall_bearing`
//! (its direction, degrees, +90 = beside the agent on the followed side) and `follow_angle`
//! (degrees from the heading to the boundary follower's direction, positive toward the
//! followed wall) — and outputs `turn` (deg/s; goal seeking masked by obstacle avoidance),
//! `speed` (m/s) and `follow_turn` (deg/s, positive toward the followed wall).
//!
//! Modes (TangentBug-style boundary following): the agent seeks the goal with `turn` until its
//! best distance to the goal has not improved for `stall_time_s`; then it follows the obstacle
//! boundary with `follow_turn`, keeping one contour on a fixed side (the geometric follower of
//! [`super::follow`] picks the direction from the scan), until it is closer to the goal than
//! when it started following and the straight way to the goal is free, or until some free
//! direction leads closer to the goal than any point of the followed wall so far and than the
//! way goal seeking stalled on (TangentBug's leaving rule), or until the wall is lost.
//!
//! The agent remembers where following started (hit points). A stall near an earlier hit point
//! with no progress since is a loop: following then takes the other side, and from the second
//! repeat on only leaves for a point closer to the goal than ever. Coming back to the hit
//! point while following switches side. Inference never calls a script; the memory is a plain
//! list, so runs stay deterministic.

use super::body::Command;
use glam::DVec2;

use super::follow::{FollowParams, FollowStep, follow_direction, swept_ahead};
use crate::fuzzy::{Engine, Network};
use crate::geom::wrap_angle;
use crate::world::Sensed;

/// The inputs the controller provides to the rule network, by name.
pub const PROVIDED_INPUTS: [&str; 10] = [
    "front",
    "left",
    "right",
    "nearest",
    "balance",
    "goal_angle",
    "goal_distance",
    "wall",
    "wall_bearing",
    "follow_angle",
];

/// The outputs the controller needs from the rule network.
pub const REQUIRED_OUTPUTS: [&str; 3] = ["turn", "speed", "follow_turn"];

/// Tuning of the mode switches. Every field documents its default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ControllerParams {
    /// Seconds without progress toward the goal before boundary following starts (4.0).
    pub stall_time_s: f64,
    /// Improvement of the best goal distance that counts as progress, metres (0.25).
    pub progress_m: f64,
    /// Boundary following ends once the goal is this much closer than at its start, metres (0.25).
    pub leave_margin_m: f64,
    /// Boundary following on one side gives up and switches side after this long, seconds
    /// (infinite: coming back to where following started switches side instead).
    pub max_follow_s: f64,
    /// The followed wall counts as seen while the nearest obstacle is nearer than this, metres (2.0).
    pub wall_lost_m: f64,
    /// Boundary following ends when the wall has not been seen for this long, seconds (2.0).
    pub wall_lost_s: f64,
    /// Top speed while following a boundary, metres per second (0.7).
    pub follow_speed_mps: f64,
    /// The geometric boundary follower (see [`FollowParams`]).
    pub follow: FollowParams,
    /// Following that started within this distance of an earlier start, with no progress
    /// since, counts as a repeat; following that comes back within half of it to where it
    /// started switches side, metres (1.0).
    pub hit_radius_m: f64,
}

impl Default for ControllerParams {
    fn default() -> Self {
        ControllerParams {
            stall_time_s: 4.0,
            progress_m: 0.25,
            leave_margin_m: 0.25,
            max_follow_s: f64::INFINITY,
            wall_lost_m: 2.0,
            wall_lost_s: 2.0,
            follow_speed_mps: 0.7,
            follow: FollowParams::default(),
            hit_radius_m: 1.0,
        }
    }
}

/// Which side the followed boundary is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Obstacle on the left.
    Left,
    /// Obstacle on the right.
    Right,
}

/// What the controller is doing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    /// Goal seeking masked by obstacle avoidance.
    Seek,
    /// Following an obstacle boundary.
    Follow {
        /// Side of the obstacle.
        side: Side,
        /// Distance to the goal when following started, metres.
        entry_distance_m: f64,
        /// Simulation time when following started, seconds.
        since_s: f64,
        /// Smallest goal distance seen while following, metres.
        followed_min_m: f64,
        /// Simulation time the followed wall was last seen, seconds.
        wall_seen_s: f64,
        /// Closest approach to the goal reachable in a straight line when following started
        /// (the one goal seeking failed to make), metres.
        stalled_reach_m: f64,
        /// Leave only for a point closer to the goal than ever before (this place has been a
        /// hit point before without progress since).
        strict: bool,
        /// Best goal distance of the episode when following started, metres.
        best_ever_m: f64,
        /// Where following started.
        hit: DVec2,
        /// The agent has been away from `hit` since.
        left_hit: bool,
    },
}

/// The layered controller with its mode state.
#[derive(Debug, Clone)]
pub struct LayeredController {
    network: Network,
    /// For each network input, which provided value feeds it.
    slots: Vec<usize>,
    inputs: Vec<f64>,
    /// Mode-switch tuning.
    pub params: ControllerParams,
    mode: Mode,
    best_distance: f64,
    last_progress_s: f64,
    follows: u32,
    last_side: Option<Side>,
    best_ever: f64,
    hits: Vec<Hit>,
}

/// Where boundary following started, on which side, and the best goal distance by then.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Hit {
    at: DVec2,
    side: Side,
    best_ever_m: f64,
}

impl LayeredController {
    /// Builds the controller from the rule script's engines; the message names any input the
    /// network reads that the controller does not provide, or a missing output.
    pub fn new(engines: &[Engine], params: ControllerParams) -> Result<LayeredController, String> {
        let network = Network::new(engines).map_err(|e| e.message)?;
        let mut slots = Vec::new();
        for name in network.input_names() {
            match PROVIDED_INPUTS.iter().position(|p| *p == name) {
                Some(i) => slots.push(i),
                None => {
                    return Err(format!(
                        "the rules read input '{name}', which navigation does not provide (it provides: {})",
                        PROVIDED_INPUTS.join(", ")
                    ));
                }
            }
        }
        for out in REQUIRED_OUTPUTS {
            if network.output(out).is_none() {
                return Err(format!("the rules must produce an output named '{out}'"));
            }
        }
        let n = slots.len();
        Ok(LayeredController {
            network,
            slots,
            inputs: vec![0.0; n],
            params,
            mode: Mode::Seek,
            best_distance: f64::INFINITY,
            last_progress_s: 0.0,
            follows: 0,
            last_side: None,
            best_ever: f64::INFINITY,
            hits: Vec::new(),
        })
    }

    /// Forgets the mode history (new episode).
    pub fn reset(&mut self) {
        self.mode = Mode::Seek;
        self.best_distance = f64::INFINITY;
        self.last_progress_s = 0.0;
        self.follows = 0;
        self.last_side = None;
        self.best_ever = f64::INFINITY;
        self.hits.clear();
    }

    /// The current mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The rule network (for readouts of inputs, outputs and fired rules).
    pub fn network(&self) -> &Network {
        &self.network
    }

    /// How many times boundary following started.
    pub fn follow_count(&self) -> u32 {
        self.follows
    }

    /// The command for what the agent senses at time `t_s`; `goal_visible` says whether the
    /// straight way to the goal is free.
    pub fn command(&mut self, s: &Sensed, goal_visible: bool, t_s: f64) -> Command {
        let p = self.params;
        if s.goal_distance < self.best_distance - p.progress_m || self.best_distance.is_infinite() {
            self.best_distance = s.goal_distance;
            self.last_progress_s = t_s;
        }
        self.best_ever = self.best_ever.min(s.goal_distance);
        let (left, right) = (s.sectors[2], s.sectors[0]);
        // Ahead, what matters is the corridor the disc sweeps (so that it can pass doors
        // barely wider than itself), not the nearest point of a wide sector.
        let front = swept_ahead(&s.scan, s.heading, s.radius, s.range).unwrap_or(s.sectors[1]);
        let mut followed: Option<(Side, Option<FollowStep>)> = None;
        match self.mode {
            Mode::Seek => {
                if t_s - self.last_progress_s > p.stall_time_s {
                    // The first time, turn toward the goal's side (the obstacle stays on the other
                    // side); later, keep the side used before, so repeated stalls in one trap
                    // keep going around it the same way. A stall where following started before,
                    // with no progress since, is a loop: take the other side this time, and
                    // after that only leave for a point closer to the goal than ever.
                    let best_ever = self.best_ever;
                    let repeats = self.hits.iter().filter(|h| {
                        h.at.distance(s.position) < p.hit_radius_m && best_ever > h.best_ever_m - p.progress_m
                    });
                    let (count, last) = repeats.fold((0usize, None), |(n, _), h| (n + 1, Some(h.side)));
                    let side = match last {
                        Some(side) => other(side),
                        None => self.last_side.unwrap_or(if s.goal_angle >= 0.0 { Side::Right } else { Side::Left }),
                    };
                    let strict = count >= 2;
                    self.hits.push(Hit { at: s.position, side, best_ever_m: best_ever });
                    self.last_side = Some(side);
                    self.follows += 1;
                    self.mode = Mode::Follow {
                        side,
                        entry_distance_m: s.goal_distance,
                        since_s: t_s,
                        followed_min_m: s.obstacle_goal_distance.min(s.goal_distance),
                        wall_seen_s: t_s,
                        stalled_reach_m: s.reachable_goal_distance,
                        strict,
                        best_ever_m: best_ever,
                        hit: s.position,
                        left_hit: false,
                    };
                }
            }
            Mode::Follow {
                side,
                entry_distance_m,
                since_s,
                followed_min_m,
                wall_seen_s,
                stalled_reach_m,
                strict,
                best_ever_m,
                hit,
                left_hit,
            } => {
                let step = follow_direction(&s.scan, s.heading, side, s.radius, s.range, &p.follow);
                followed = Some((side, step));
                // TangentBug: the closest the followed wall has come to the goal (its nearest
                // points on the followed side), against the closest free point reachable in a
                // straight line.
                let wall_goal = match step {
                    Some(f) => {
                        let at = s.position + DVec2::from_angle(f.wall_direction) * (f.wall_m + s.radius);
                        at.distance(s.goal)
                    }
                    _ => s.obstacle_goal_distance,
                };
                let followed_min_m = followed_min_m.min(wall_goal);
                // A way closer than the one goal seeking stalled on.
                let mut bound = followed_min_m.min(stalled_reach_m);
                if strict {
                    bound = bound.min(best_ever_m);
                }
                let reachable = s.reachable_goal_distance < bound - p.leave_margin_m;
                let away = s.position.distance(hit);
                let back_at_hit = left_hit && away < p.hit_radius_m * 0.5;
                let left_hit = (left_hit && !back_at_hit) || away > p.hit_radius_m * 2.0;
                let seen = match step {
                    Some(f) => f.wall_m < p.wall_lost_m,
                    None => s.scan.is_empty() && s.nearest < p.wall_lost_m,
                };
                let wall_seen_s = if seen { t_s } else { wall_seen_s };
                let entry = if strict { entry_distance_m.min(best_ever_m) } else { entry_distance_m };
                let closer = s.goal_distance < entry - p.leave_margin_m && goal_visible;
                if closer || reachable || t_s - wall_seen_s > p.wall_lost_s {
                    self.mode = Mode::Seek;
                    self.last_progress_s = t_s;
                    self.best_distance = s.goal_distance;
                } else if t_s - since_s > p.max_follow_s || back_at_hit {
                    self.mode = Mode::Follow {
                        side: other(side),
                        entry_distance_m,
                        since_s: t_s,
                        followed_min_m,
                        wall_seen_s,
                        stalled_reach_m,
                        strict,
                        best_ever_m,
                        hit: s.position,
                        left_hit: false,
                    };
                } else {
                    self.mode = Mode::Follow {
                        side,
                        entry_distance_m,
                        since_s,
                        followed_min_m,
                        wall_seen_s,
                        stalled_reach_m,
                        strict,
                        best_ever_m,
                        hit,
                        left_hit,
                    };
                }
            }
        }
        // The followed wall is the nearest obstacle; its bearing is mirrored for the right side
        // so that +90° always means "beside the agent on the followed side".
        let bearing = s.nearest_bearing.to_degrees();
        let wall_bearing = match self.mode {
            Mode::Follow { side: Side::Right, .. } => -bearing,
            _ => bearing,
        };
        // The follower's direction relative to the heading, degrees, mirrored like the bearing;
        // with the wall out of sight, turn toward its side to find it again.
        let follow = match (self.mode, followed) {
            (Mode::Follow { side, .. }, Some((done, step))) if done == side => step,
            (Mode::Follow { side, .. }, _) => follow_direction(&s.scan, s.heading, side, s.radius, s.range, &p.follow),
            (Mode::Seek, _) => None,
        };
        let follow_angle = match (self.mode, follow) {
            (Mode::Seek, _) => 0.0,
            (Mode::Follow { side, .. }, Some(f)) => {
                let a = wrap_angle(f.direction - s.heading).to_degrees();
                if side == Side::Right { -a } else { a }
            }
            (Mode::Follow { .. }, None) => 60.0,
        };
        let provided = [
            front,
            left,
            right,
            s.nearest,
            left - right,
            s.goal_angle.to_degrees(),
            s.goal_distance,
            s.nearest,
            wall_bearing,
            follow_angle,
        ];
        for (dst, &slot) in self.inputs.iter_mut().zip(&self.slots) {
            *dst = provided[slot];
        }
        self.network.process(&self.inputs);
        let out = |name: &str| self.network.output(name).filter(|v| v.is_finite()).unwrap_or(0.0);
        let speed = match self.mode {
            Mode::Seek => out("speed"),
            Mode::Follow { .. } => {
                // Turn first, then go: full speed within 30° of the follower's direction,
                // none beyond 90°; slower as the way ahead shortens.
                let align = ((90.0 - follow_angle.abs()) / 60.0).clamp(0.0, 1.0);
                let room = follow.map_or(0.3, |f| (f.free_m * 1.5).max(0.15));
                p.follow_speed_mps.min(room) * align
            }
        };
        let turn_deg = match self.mode {
            Mode::Seek => out("turn"),
            Mode::Follow { side: Side::Left, .. } => out("follow_turn"),
            Mode::Follow { side: Side::Right, .. } => -out("follow_turn"),
        };
        Command { turn_rate: turn_deg.to_radians(), speed }
    }
}

fn other(side: Side) -> Side {
    match side {
        Side::Left => Side::Right,
        Side::Right => Side::Left,
    }
}
