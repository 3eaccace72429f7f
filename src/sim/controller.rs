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
//!
//! **The planner drives the body it has.** What the rules command is shaped to what the body
//! can follow ([`Body::turn_limit`]): a turn sharper than the body can make at the commanded
//! speed keeps its curvature at the highest speed where the body can make it, or becomes a
//! turn on the spot. The same rules thus steer the nimble disc and the animated character.
//!
//! The boundary with the rules is typed: [`NavInputs`] holds every value the controller
//! provides, bound to the network's inputs by name once, and the outputs it needs are looked
//! up once.

use std::f64::consts::FRAC_PI_2;

use glam::DVec2;

use super::body::{Body, Command};
use super::follow::{FollowParams, FollowStep, Side, follow_direction, swept_ahead};
use crate::fuzzy::{Engine, Network};
use crate::geom::wrap_angle;
use crate::world::Sensed;

/// Everything the controller provides to the rule network (by the field names).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavInputs {
    /// Free distance of the disc's corridor straight ahead, metres.
    pub front: f64,
    /// Free distance in the left sector, metres.
    pub left: f64,
    /// Free distance in the right sector, metres.
    pub right: f64,
    /// Free distance to the nearest obstacle in any direction, metres.
    pub nearest: f64,
    /// `left - right`, metres.
    pub balance: f64,
    /// Angle to the goal (or to the way toward it), degrees, positive to the left.
    pub goal_angle: f64,
    /// Distance to the goal, metres.
    pub goal_distance: f64,
    /// Free distance to the followed wall (the nearest obstacle), metres.
    pub wall: f64,
    /// Bearing of the followed wall, degrees; +90 = beside the agent on the followed side.
    pub wall_bearing: f64,
    /// Angle from the heading to the boundary follower's direction, degrees, positive toward
    /// the followed wall.
    pub follow_angle: f64,
    /// Free distance of the disc's corridor (with the margin) toward the goal or the way to it,
    /// metres; the sensing range when the goal itself is reachable.
    pub way: f64,
}

impl NavInputs {
    /// The input names the rules may read, in field order.
    pub const NAMES: [&'static str; 11] = [
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
        "way",
    ];

    /// The value named `NAMES[field]`.
    fn get(&self, field: usize) -> f64 {
        [
            self.front,
            self.left,
            self.right,
            self.nearest,
            self.balance,
            self.goal_angle,
            self.goal_distance,
            self.wall,
            self.wall_bearing,
            self.follow_angle,
            self.way,
        ][field]
    }
}

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
    /// While goal seeking faces farther than this from the way to the goal, the agent is still
    /// turning toward it and the stall clock waits, radians (60°).
    pub turning_rad: f64,
    /// Goal seeking steers toward the goal alone (no avoidance) while nothing is nearer than
    /// this, metres (1.0).
    pub open_m: f64,
    /// Room the corridors `front` and `way` keep from obstacles, metres (0.05).
    pub margin_m: f64,
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
            turning_rad: 60f64.to_radians(),
            open_m: 1.0,
            margin_m: 0.05,
        }
    }
}

/// How far the agent still has to go: along the remembered way when there is one, else
/// straight to the goal, metres.
fn to_go(s: &Sensed) -> f64 {
    if s.route_distance.is_finite() { s.route_distance } else { s.goal_distance }
}

/// The state of boundary following.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FollowState {
    /// Side of the obstacle.
    pub side: Side,
    /// Distance still to go (along the remembered way, else straight) when following started, metres.
    pub entry_distance_m: f64,
    /// Simulation time when following started (on this side), seconds.
    pub since_s: f64,
    /// Smallest distance from the goal to the followed wall so far, metres.
    pub followed_min_m: f64,
    /// Simulation time the followed wall was last seen, seconds.
    pub wall_seen_s: f64,
    /// Closest approach to the goal reachable in a straight line when following started
    /// (the one goal seeking failed to make), metres.
    pub stalled_reach_m: f64,
    /// Leave only for a point closer to the goal than ever before (this place has been a hit
    /// point before without progress since).
    pub strict: bool,
    /// Best goal distance of the episode when following started, metres.
    pub best_ever_m: f64,
    /// Where following started (on this side).
    pub hit: DVec2,
    /// The agent has been away from `hit` since.
    pub left_hit: bool,
}

/// What the controller is doing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    /// Goal seeking masked by obstacle avoidance.
    Seek,
    /// Following an obstacle boundary.
    Follow(FollowState),
}

/// The layered controller with its mode state.
#[derive(Debug, Clone)]
pub struct LayeredController {
    network: Network,
    /// For each network input, which field of [`NavInputs`] feeds it.
    slots: Vec<usize>,
    /// Where the network puts `turn`, `speed` and `follow_turn`.
    outputs: [usize; 3],
    inputs: Vec<f64>,
    /// Mode-switch tuning.
    pub params: ControllerParams,
    mode: Mode,
    best_distance: f64,
    last_progress_s: f64,
    last_t_s: f64,
    follows: u32,
    last_side: Option<Side>,
    best_ever: f64,
    hits: Vec<Hit>,
    /// `Sensed::known_obstacles` at the last step.
    known: usize,
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
            match NavInputs::NAMES.iter().position(|p| *p == name) {
                Some(i) => slots.push(i),
                None => {
                    return Err(format!(
                        "the rules read input '{name}', which navigation does not provide (it provides: {})",
                        NavInputs::NAMES.join(", ")
                    ));
                }
            }
        }
        let mut outputs = [0usize; 3];
        for (slot, name) in outputs.iter_mut().zip(REQUIRED_OUTPUTS) {
            *slot =
                network.output_index(name).ok_or_else(|| format!("the rules must produce an output named '{name}'"))?;
        }
        let n = slots.len();
        Ok(LayeredController {
            network,
            slots,
            outputs,
            inputs: vec![0.0; n],
            params,
            mode: Mode::Seek,
            best_distance: f64::INFINITY,
            last_progress_s: 0.0,
            last_t_s: 0.0,
            follows: 0,
            last_side: None,
            best_ever: f64::INFINITY,
            hits: Vec::new(),
            known: 0,
        })
    }

    /// Forgets the mode history (new episode).
    pub fn reset(&mut self) {
        self.mode = Mode::Seek;
        self.best_distance = f64::INFINITY;
        self.last_progress_s = 0.0;
        self.last_t_s = 0.0;
        self.follows = 0;
        self.last_side = None;
        self.best_ever = f64::INFINITY;
        self.hits.clear();
        self.known = 0;
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

    /// The command for what the agent senses at time `t_s`, shaped to what `body` can follow;
    /// `goal_visible()` says whether the straight way to the goal is free (asked only while
    /// following a boundary, when leaving it depends on that).
    pub fn command(&mut self, s: &Sensed, goal_visible: impl FnOnce() -> bool, t_s: f64, body: &dyn Body) -> Command {
        let p = self.params;
        // Progress is measured along the remembered way when there is one (walking away from
        // the goal toward a door is progress), else straight to the goal. Seeing an obstacle
        // never seen before is progress too: the way is planned again over it, and a finite
        // world has finitely many to see (the completeness of planning with the free-space
        // assumption), so only an agent that learns nothing and gets no closer is stalled.
        let to_go = to_go(s);
        let learnt = s.known_obstacles > self.known;
        self.known = s.known_obstacles;
        if learnt || to_go < self.best_distance - p.progress_m || self.best_distance.is_infinite() {
            self.best_distance = to_go;
            self.last_progress_s = t_s;
        } else if self.mode == Mode::Seek && s.goal_angle.abs() > p.turning_rad {
            // Still turning toward the way to the goal: no progress is expected yet, so the
            // stall clock waits (a body that turns slowly is not stalled).
            self.last_progress_s += t_s - self.last_t_s;
        }
        self.last_t_s = t_s;
        self.best_ever = self.best_ever.min(s.goal_distance);
        let (left, right) = (s.sectors[2], s.sectors[0]);
        // The corridors keep the margin, or half the room there is when the agent stands closer
        // (a corridor that starts inside the margin would be shut whichever way it went, and
        // avoidance would hold the agent where it stands; with half the room, a way that
        // leaves the near obstacle about sideways is open, as the body can take it). Committed to a narrow
        // part of the remembered way (lined up for it), they are the disc's own: a gap the way
        // goes through may leave less than the margin to either side, and measured with it,
        // the gap would look shut and avoidance would turn the agent one way and the other in
        // front of it.
        let margin = if s.through_gap { 0.0 } else { p.margin_m.min(0.5 * s.nearest.max(0.0)) };
        // Ahead, what matters is the corridor the disc sweeps (so that it can pass doors
        // barely wider than itself), not the nearest point of a wide sector.
        let front = swept_ahead(&s.scan, s.heading, s.radius, margin, s.range).unwrap_or(s.sectors[1]);
        // Free up to the point steered at (a waypoint of the remembered way, or the goal) is
        // as good as free to the end of the range.
        let aim = s.aim_distance.min(s.goal_distance).min(s.range);
        let (way, clear_to_aim) = match swept_ahead(&s.scan, s.heading + s.goal_angle, s.radius, margin, s.range) {
            Some(free) if free < aim => (free, false),
            _ => (s.range, true),
        };
        let mut followed: Option<(Side, Option<FollowStep>)> = None;
        self.mode = match self.mode {
            Mode::Seek if t_s - self.last_progress_s > p.stall_time_s && !s.route_distance.is_finite() => {
                Mode::Follow(self.start_following(s, t_s))
            }
            Mode::Seek => Mode::Seek,
            Mode::Follow(f) => {
                let step = follow_direction(&s.scan, s.heading, f.side, s.radius, s.range, &p.follow);
                followed = Some((f.side, step));
                self.keep_following(f, step, s, goal_visible, t_s)
            }
        };
        // The followed wall is the nearest obstacle; its bearing is mirrored for the right side
        // so that +90° always means "beside the agent on the followed side".
        let bearing = s.nearest_bearing.to_degrees();
        let side = match self.mode {
            Mode::Follow(f) => Some(f.side),
            Mode::Seek => None,
        };
        let mirror = |a: f64| if side == Some(Side::Right) { -a } else { a };
        // The follower's direction relative to the heading, degrees, mirrored like the bearing;
        // with the wall out of sight, turn toward its side to find it again.
        let follow = match (side, followed) {
            (Some(side), Some((done, step))) if done == side => step,
            (Some(side), _) => follow_direction(&s.scan, s.heading, side, s.radius, s.range, &p.follow),
            (None, _) => None,
        };
        let follow_angle = match (side, follow) {
            (None, _) => 0.0,
            (Some(_), Some(f)) => mirror(wrap_angle(f.direction - s.heading).to_degrees()),
            (Some(_), None) => 60.0,
        };
        let nav = NavInputs {
            front,
            left,
            right,
            nearest: s.nearest,
            balance: left - right,
            goal_angle: s.goal_angle.to_degrees(),
            goal_distance: s.goal_distance,
            wall: s.nearest,
            wall_bearing: mirror(bearing),
            follow_angle,
            way,
        };
        for (dst, &slot) in self.inputs.iter_mut().zip(&self.slots) {
            *dst = nav.get(slot);
        }
        self.network.process(&self.inputs);
        let out = |k: usize| Some(self.network.output_at(self.outputs[k])).filter(|v| v.is_finite()).unwrap_or(0.0);
        // The direction steered toward: the follower's; when seeking with nothing near or
        // with the way clear up to the point aimed at (the turn is goal seeking's), the goal or
        // the way toward it.
        let toward = match side {
            None => (s.nearest >= p.open_m || clear_to_aim).then_some(s.heading + s.goal_angle),
            Some(_) => follow.map(|f| f.direction),
        };
        let (speed, turn_deg) = match side {
            None => (out(1), out(0)),
            Some(side) => {
                // Turn first, then go: full speed within 30° of the follower's direction,
                // none beyond 90°; slower as the way ahead shortens.
                let align = ((90.0 - follow_angle.abs()) / 60.0).clamp(0.0, 1.0);
                let room = follow.map_or(0.3, |f| (f.free_m * 1.5).max(0.15));
                let turn = if side == Side::Left { out(2) } else { -out(2) };
                (p.follow_speed_mps.min(room) * align, turn)
            }
        };
        let mut turn_rate = turn_deg.to_radians();
        // Shut ahead (the disc cannot go on at all): avoidance has nothing left to steer round,
        // and weighed against goal seeking it may hold the heading where the two cancel, the
        // agent standing still for good. Turning on the spot touches nothing, so the agent turns
        // toward the way, at least as fast as closes the angle in `SHUT_TURN_S`.
        if side.is_none() && front <= SHUT_M && s.goal_angle.abs() > SHUT_ALIGNED_RAD {
            let toward_way = s.goal_angle / SHUT_TURN_S;
            if turn_rate * s.goal_angle.signum() < toward_way.abs() {
                turn_rate = toward_way;
            }
        }
        // Arriving: a goal inside the circle the body turns on is orbited, never reached. When
        // the point aimed at is the goal itself, turn at least as tightly as the circle through
        // it (within_reach slows the body down if it must to make that turn).
        if side.is_none() && clear_to_aim && s.aim_distance.is_finite() && s.aim_distance >= s.goal_distance - 1e-6 {
            let bearing = s.goal_angle.clamp(-FRAC_PI_2, FRAC_PI_2);
            let needed = 2.0 * bearing.sin() / s.goal_distance.max(1e-6);
            if needed.abs() * speed > turn_rate.abs() {
                turn_rate = needed * speed;
            }
        }
        within_reach(Command { turn_rate, speed, toward }, body)
    }

    /// Starts following the boundary after a stall. The first time, the side away from the
    /// goal's side (the obstacle stays on the other side); later, the side used before, so
    /// repeated stalls in one trap keep going around it the same way. A stall where following
    /// started before, with no progress since, is a loop: the other side this time, and after
    /// that only leave for a point closer to the goal than ever.
    fn start_following(&mut self, s: &Sensed, t_s: f64) -> FollowState {
        let p = self.params;
        let best_ever = self.best_ever;
        let repeats = self
            .hits
            .iter()
            .filter(|h| h.at.distance(s.position) < p.hit_radius_m && best_ever > h.best_ever_m - p.progress_m);
        let (count, last) = repeats.fold((0usize, None), |(n, _), h| (n + 1, Some(h.side)));
        let side = match last {
            Some(side) => other(side),
            None => self.last_side.unwrap_or(if s.goal_angle >= 0.0 { Side::Right } else { Side::Left }),
        };
        self.hits.push(Hit { at: s.position, side, best_ever_m: best_ever });
        self.last_side = Some(side);
        self.follows += 1;
        FollowState {
            side,
            entry_distance_m: to_go(s),
            since_s: t_s,
            followed_min_m: s.obstacle_goal_distance.min(s.goal_distance),
            wall_seen_s: t_s,
            stalled_reach_m: s.reachable_goal_distance,
            strict: count >= 2,
            best_ever_m: best_ever,
            hit: s.position,
            left_hit: false,
        }
    }

    /// One step of boundary following: leave (TangentBug's rule, the goal closer than at the
    /// start, or the wall lost), switch side (back at the hit point), or go on.
    fn keep_following(
        &mut self,
        f: FollowState,
        step: Option<FollowStep>,
        s: &Sensed,
        goal_visible: impl FnOnce() -> bool,
        t_s: f64,
    ) -> Mode {
        let p = self.params;
        // TangentBug: the closest the followed wall has come to the goal (its nearest points
        // on the followed side), against the closest free point reachable in a straight line.
        let wall_goal = match step {
            Some(w) => (s.position + DVec2::from_angle(w.wall_direction) * (w.wall_m + s.radius)).distance(s.goal),
            None => s.obstacle_goal_distance,
        };
        let followed_min_m = f.followed_min_m.min(wall_goal);
        // A way closer than the one goal seeking stalled on.
        let mut bound = followed_min_m.min(f.stalled_reach_m);
        if f.strict {
            bound = bound.min(f.best_ever_m);
        }
        let reachable = s.reachable_goal_distance < bound - p.leave_margin_m;
        let away = s.position.distance(f.hit);
        let back_at_hit = f.left_hit && away < p.hit_radius_m * 0.5;
        let left_hit = (f.left_hit && !back_at_hit) || away > p.hit_radius_m * 2.0;
        let seen = match step {
            Some(w) => w.wall_m < p.wall_lost_m,
            None => s.scan.is_empty() && s.nearest < p.wall_lost_m,
        };
        let wall_seen_s = if seen { t_s } else { f.wall_seen_s };
        let entry = if f.strict { f.entry_distance_m.min(f.best_ever_m) } else { f.entry_distance_m };
        // Closer along the remembered way than at the start (or, with none, straight to a
        // visible goal).
        let closer = to_go(s) < entry - p.leave_margin_m && (s.route_distance.is_finite() || goal_visible());
        if closer || reachable || t_s - wall_seen_s > p.wall_lost_s {
            self.last_progress_s = t_s;
            self.best_distance = to_go(s);
            Mode::Seek
        } else if t_s - f.since_s > p.max_follow_s || back_at_hit {
            Mode::Follow(FollowState {
                side: other(f.side),
                since_s: t_s,
                followed_min_m,
                wall_seen_s,
                hit: s.position,
                left_hit: false,
                ..f
            })
        } else {
            Mode::Follow(FollowState { followed_min_m, wall_seen_s, left_hit, ..f })
        }
    }
}

/// The way ahead counts as shut when the disc can go on no farther than this, metres.
const SHUT_M: f64 = 0.02;

/// Shut ahead, the agent turns toward the way while it is farther off than this, radians (5°).
const SHUT_ALIGNED_RAD: f64 = 0.087;

/// Shut ahead, the agent turns toward the way at least as fast as closes the angle in this
/// long, seconds.
const SHUT_TURN_S: f64 = 0.5;

/// Speed step of the search for a speed at which the body can make a turn, m/s.
const REACH_SPEED_STEP: f64 = 0.05;

/// `command` shaped to what `body` can follow: a turn sharper than the body can make at the
/// commanded speed keeps its curvature at the highest lower speed where the body can make it,
/// or becomes a turn on the spot at the body's limit there.
pub fn within_reach(command: Command, body: &dyn Body) -> Command {
    let Command { turn_rate, speed, toward } = command;
    if turn_rate.abs() <= body.turn_limit(speed) {
        return command;
    }
    let curvature = turn_rate / speed.max(1e-9);
    let steps = (speed / REACH_SPEED_STEP).ceil() as usize;
    for k in (1..steps).rev() {
        let v = k as f64 * REACH_SPEED_STEP;
        if (curvature * v).abs() <= body.turn_limit(v) {
            return Command { turn_rate: curvature * v, speed: v, toward };
        }
    }
    Command { turn_rate: turn_rate.signum() * turn_rate.abs().min(body.turn_limit(0.0)), speed: 0.0, toward }
}

fn other(side: Side) -> Side {
    match side {
        Side::Left => Side::Right,
        Side::Right => Side::Left,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{KinematicDisc, Space, StepOutcome};
    use crate::world::Pose;

    /// A body that turns at most 1 rad/s at 1 m/s and faster when slower (2 rad/s standing).
    struct Slow;

    impl Body for Slow {
        fn pose(&self) -> Pose {
            Pose { position: DVec2::ZERO, yaw: 0.0 }
        }
        fn speed(&self) -> f64 {
            0.0
        }
        fn radius(&self) -> f64 {
            0.3
        }
        fn turn_limit(&self, speed: f64) -> f64 {
            2.0 - speed.clamp(0.0, 1.0)
        }
        fn step(&mut self, _: Command, _: f64, _: &mut dyn Space) -> StepOutcome {
            StepOutcome::default()
        }
    }

    #[test]
    fn commands_are_shaped_to_the_body() {
        // Within reach: unchanged.
        let c = Command { turn_rate: 0.5, speed: 1.0, toward: None };
        assert_eq!(within_reach(c, &Slow), c);
        // Too sharp at 1 m/s: the same curvature (1.5 rad/m) at the highest speed that can make
        // it (1.5·v ≤ 2 − v, v ≤ 0.8).
        let c = within_reach(Command { turn_rate: 1.5, speed: 1.0, toward: None }, &Slow);
        assert!((c.turn_rate / c.speed - 1.5).abs() < 1e-9 && c.speed <= 0.8 + 1e-9 && c.speed > 0.7, "{c:?}");
        // Sharper than anything while moving: a turn on the spot at the standing limit.
        let c = within_reach(Command { turn_rate: -50.0, speed: 0.5, toward: None }, &Slow);
        assert_eq!(c, Command { turn_rate: -2.0, speed: 0.0, toward: None });
        // The disc turns 2.5 rad/s at any speed: a sharper command keeps its curvature.
        let disc = KinematicDisc::new(Pose { position: DVec2::ZERO, yaw: 0.0 }, Default::default());
        let c = within_reach(Command { turn_rate: 3.0, speed: 1.0, toward: None }, &disc);
        assert!(c.turn_rate <= 2.5 && (c.turn_rate / c.speed - 3.0).abs() < 1e-9, "{c:?}");
    }
}
