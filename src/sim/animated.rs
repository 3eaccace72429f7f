//! The animated body (seed 000 §3.2; DESIGN.md §3): the navigation loop drives the character
//! through the animation database. The fuzzy planner's turn rate and speed become the RL
//! controller's task: a desired heading — where the commanded turn rate would bring the heading
//! within [`HEADING_HORIZON_S`], re-aimed at every step, since the planner closes the loop — and
//! a desired speed. At every switch point the trained policy picks the next interval from the state
//! (interval now ending, speed error, direction error); the played root motion moves the body.
//!
//! The body keeps the disc invariant: when the root motion of a step would end inside an
//! obstacle, the step slides (turned up to 60° either way), is shortened, or is refused, and the
//! character's ground reference is corrected accordingly.

use std::sync::Arc;

use glam::DVec2;

use super::body::{Body, Command, StepOutcome, slide};
use crate::anim::player::{Chooser, PlaybackMetrics, Player, PlayerParams};
use crate::anim::policy::{Errors, Policy};
use crate::anim::{Database, Ground};
use crate::geom::wrap_angle;
use crate::world::Pose;

/// Largest direction error the desired heading may run ahead of the character, radians.
pub const MAX_DIRECTION_ERROR: f64 = 0.9 * std::f64::consts::PI;
/// The desired heading is where the commanded turn rate leads within this time, seconds.
pub const HEADING_HORIZON_S: f64 = 1.0;

/// A database with its trained policy and playback parameters, shared by every agent.
#[derive(Debug)]
pub struct Animation {
    /// The database.
    pub db: Database,
    /// The policy trained on it.
    pub policy: Policy,
    /// Playback parameters.
    pub player: PlayerParams,
}

/// A shared [`Animation`]; equal when it is the same one.
#[derive(Debug, Clone)]
pub struct AnimationHandle(pub Arc<Animation>);

impl PartialEq for AnimationHandle {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// Command tracking of an animated body.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Tracking {
    /// Σ squared distance between the commanded path and the root path, m².
    pub sq_distance: f64,
    /// Σ squared direction error, rad².
    pub sq_direction: f64,
    /// Σ squared speed error, (m/s)².
    pub sq_speed: f64,
    /// Samples (steps).
    pub samples: u64,
}

impl Tracking {
    /// RMS distance between the commanded path (the commands integrated from the root at the
    /// last switch point) and the root path, metres.
    pub fn rms_path_m(&self) -> f64 {
        (self.sq_distance / self.samples.max(1) as f64).sqrt()
    }
    /// RMS direction error, radians.
    pub fn rms_direction(&self) -> f64 {
        (self.sq_direction / self.samples.max(1) as f64).sqrt()
    }
    /// RMS speed error, m/s.
    pub fn rms_speed(&self) -> f64 {
        (self.sq_speed / self.samples.max(1) as f64).sqrt()
    }
}

/// A character driven by the animation database.
#[derive(Debug, Clone)]
pub struct AnimatedBody {
    anim: Arc<Animation>,
    player: Player,
    radius: f64,
    desired_heading: f64,
    command: Command,
    speed: f64,
    commanded: Ground,
    switches: u64,
    /// Command tracking so far.
    pub tracking: Tracking,
}

struct PolicyChooser<'a> {
    policy: &'a Policy,
    command: Command,
    desired: f64,
}

impl Chooser for PolicyChooser<'_> {
    fn choose(&mut self, db: &Database, ending: usize, heading: f64) -> usize {
        let errors = Errors {
            speed: self.command.speed - db.intervals[ending].speed,
            direction: wrap_angle(self.desired - heading),
        };
        self.policy.choose(ending, errors)
    }
}

impl AnimatedBody {
    /// A character standing at `pose` in the slowest interval of the database.
    pub fn new(anim: Arc<Animation>, pose: Pose, radius: f64) -> AnimatedBody {
        let db = &anim.db;
        let start = (0..db.intervals.len())
            .min_by(|&a, &b| db.intervals[a].speed.total_cmp(&db.intervals[b].speed))
            .unwrap_or(0);
        let at = Ground { x: pose.position.x, y: pose.position.y, yaw: pose.yaw };
        let player = Player::new(db, start, at, anim.player);
        AnimatedBody {
            player,
            radius,
            desired_heading: pose.yaw,
            command: Command::default(),
            speed: 0.0,
            commanded: at,
            switches: 0,
            tracking: Tracking::default(),
            anim,
        }
    }

    /// The player (pose, footprints, playback metrics).
    pub fn player(&self) -> &Player {
        &self.player
    }

    /// The shared animation.
    pub fn animation(&self) -> &Animation {
        &self.anim
    }

    /// The direction error and speed error the policy sees now.
    pub fn errors(&self) -> Errors {
        let db = &self.anim.db;
        Errors {
            speed: self.command.speed - db.intervals[self.player.interval()].speed,
            direction: wrap_angle(self.desired_heading - self.player.ground().yaw),
        }
    }

    /// Playback measurements.
    pub fn metrics(&self) -> PlaybackMetrics {
        self.player.metrics
    }
}

impl Body for AnimatedBody {
    fn pose(&self) -> Pose {
        let g = self.player.ground();
        Pose { position: DVec2::new(g.x, g.y), yaw: wrap_angle(g.yaw) }
    }

    fn speed(&self) -> f64 {
        self.speed
    }

    fn radius(&self) -> f64 {
        self.radius
    }

    fn step(&mut self, command: Command, dt: f64, free: &mut dyn FnMut(DVec2) -> bool) -> StepOutcome {
        let turn = if command.turn_rate.is_finite() { command.turn_rate } else { 0.0 };
        let speed = if command.speed.is_finite() { command.speed.max(0.0) } else { 0.0 };
        self.command = Command { turn_rate: turn, speed };
        let before = self.player.ground();
        self.desired_heading = before.yaw + (turn * HEADING_HORIZON_S).clamp(-MAX_DIRECTION_ERROR, MAX_DIRECTION_ERROR);
        let frames = ((dt * self.player.params.frame_rate) + 1e-9).floor().max(1.0) as usize;
        let anim = Arc::clone(&self.anim);
        for _ in 0..frames {
            let mut chooser =
                PolicyChooser { policy: &anim.policy, command: self.command, desired: self.desired_heading };
            self.player.advance_frame(&anim.db, &mut chooser);
        }
        let after = self.player.ground();
        let from = DVec2::new(before.x, before.y);
        let step = DVec2::new(after.x, after.y) - from;
        let distance = step.length();
        let mut outcome = StepOutcome { moved_m: distance, blocked: false };
        if distance > 0.0 && !free(from + step) {
            outcome.blocked = true;
            let (to, moved) = slide(from, step.y.atan2(step.x), distance, free).map_or((from, 0.0), |(p, d, _)| (p, d));
            outcome.moved_m = moved;
            self.player.set_ground(Ground { x: to.x, y: to.y, yaw: after.yaw });
        }
        self.speed = outcome.moved_m / dt;
        // Tracking: the commanded unicycle from the root at the last switch point.
        let g = self.player.ground();
        if self.player.metrics.switches != self.switches {
            self.switches = self.player.metrics.switches;
            self.commanded = g;
        } else {
            let c = &mut self.commanded;
            c.yaw += turn * dt;
            c.x += speed * dt * c.yaw.cos();
            c.y += speed * dt * c.yaw.sin();
        }
        let t = &mut self.tracking;
        t.sq_distance += (self.commanded.x - g.x).powi(2) + (self.commanded.y - g.y).powi(2);
        t.sq_direction += wrap_angle(self.desired_heading - g.yaw).powi(2);
        t.sq_speed += (speed - self.speed).powi(2);
        t.samples += 1;
        outcome
    }
}

/// Command tracking figures of an animated character on open ground (DESIGN.md §3).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct TrackingFigures {
    /// Seconds from a commanded 90° heading change (left, while walking) until the heading is
    /// within 10° of it.
    pub turn_left_90_s: f64,
    /// The same to the right.
    pub turn_right_90_s: f64,
    /// Seconds from a commanded speed change (slow walk to walk) until the speed over the last
    /// half second is within 10 % of it.
    pub speed_up_s: f64,
    /// The same from walk to slow walk.
    pub slow_down_s: f64,
    /// RMS distance between the commanded path and the root path over a 60 s run of varied
    /// commands from the planner's ranges, metres.
    pub rms_path_m: f64,
    /// Foot skating over all of the above, cm per frame.
    pub foot_skating_cm_per_frame: f64,
    /// Mean pose distance at transitions over all of the above.
    pub transition_cost: f64,
}

/// Runs the scripted tracking tests on open ground; a time of 10 s means the command was not met
/// within 10 s.
pub fn measure_tracking(anim: &Arc<Animation>, walk_speed: f64, slow_speed: f64) -> TrackingFigures {
    const DT: f64 = 0.05;
    const CAP_S: f64 = 10.0;
    let start = Pose { position: DVec2::ZERO, yaw: 0.0 };
    let mut skate = (0.0, 0.0);
    let mut cost = (0.0, 0u64);
    let mut account = |b: &AnimatedBody| {
        let m = b.metrics();
        skate.0 += m.skate_weighted_cm;
        skate.1 += m.contact_weight;
        cost.0 += m.transition_cost;
        cost.1 += m.transitions;
    };
    let settle = |b: &mut AnimatedBody, speed: f64| {
        for _ in 0..(4.0 / DT) as usize {
            b.step(Command { turn_rate: 0.0, speed }, DT, &mut |_| true);
        }
    };
    // A commanded heading change: the command is the turn rate that would close the remaining
    // heading error within the horizon, as a planner steering to a fixed heading commands.
    let mut turn = |sign: f64| {
        let mut b = AnimatedBody::new(anim.clone(), start, 0.3);
        settle(&mut b, walk_speed);
        let target = b.player.ground().yaw + sign * std::f64::consts::FRAC_PI_2;
        let mut t = 0.0;
        while wrap_angle(target - b.player.ground().yaw).abs() > 10f64.to_radians() && t < CAP_S {
            let turn_rate = wrap_angle(target - b.player.ground().yaw) / HEADING_HORIZON_S;
            b.step(Command { turn_rate, speed: walk_speed }, DT, &mut |_| true);
            t += DT;
        }
        account(&b);
        t
    };
    let (turn_left_90_s, turn_right_90_s) = (turn(1.0), turn(-1.0));
    let mut speed = |from: f64, to: f64| {
        let mut b = AnimatedBody::new(anim.clone(), start, 0.3);
        settle(&mut b, from);
        let window = (0.5 / DT) as usize;
        let mut recent: Vec<f64> = Vec::new();
        let mut t = 0.0;
        loop {
            let out = b.step(Command { turn_rate: 0.0, speed: to }, DT, &mut |_| true);
            t += DT;
            recent.push(out.moved_m);
            if recent.len() > window {
                recent.remove(0);
            }
            let v = recent.iter().sum::<f64>() / (recent.len() as f64 * DT);
            if (recent.len() == window && (v - to).abs() <= 0.1 * to) || t >= CAP_S {
                break;
            }
        }
        account(&b);
        t
    };
    let (speed_up_s, slow_down_s) = (speed(slow_speed, walk_speed), speed(walk_speed, slow_speed));
    // Varied commands: a new (turn, speed) every 2 s, from a fixed stream.
    let mut b = AnimatedBody::new(anim.clone(), start, 0.3);
    let mut rng = crate::rng::stream(2024, 0, 7);
    let mut command = Command::default();
    for k in 0..(60.0 / DT) as usize {
        if k % 40 == 0 {
            command = Command {
                turn_rate: crate::rng::uniform(&mut rng, -0.8, 0.8),
                speed: crate::rng::uniform(&mut rng, slow_speed, walk_speed),
            };
        }
        b.step(command, DT, &mut |_| true);
    }
    account(&b);
    let rms_path_m = b.tracking.rms_path_m();
    TrackingFigures {
        turn_left_90_s,
        turn_right_90_s,
        speed_up_s,
        slow_down_s,
        rms_path_m,
        foot_skating_cm_per_frame: if skate.1 > 0.0 { skate.0 / skate.1 } else { 0.0 },
        transition_cost: if cost.1 > 0 { cost.0 / cost.1 as f64 } else { 0.0 },
    }
}
