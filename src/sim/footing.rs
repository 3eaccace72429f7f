//! The animated character on uneven terrain (seed 002 §3.2, §4; DESIGN.md §4): at each step the
//! database's interval gives the nominal step, and the footstep planner adapts it to the ground.
//!
//! At every switch to a moving interval, [`Footing::decide`] cuts the terrain with the
//! character's sagittal plane (a vertical plane along its heading through the front foot) into
//! a [`GroundProfile`] reaching [`HORIZON_M`] ahead, and runs the [`FootstepPlanner`] from the
//! two feet planted now with the interval's step (mean speed × duration) as the nominal one.
//! The step it returns places the next foothold, and the interval's root motion is scaled by
//! the adapted step over the nominal one; the pelvis height follows the ground along the
//! planned legs ([`Swing::pose_at`]). When the planner stops — no sequence of steps reaches
//! further — the character stands (its root holds) and [`Footing::stopped`] says why; it never
//! takes an invalid foothold. Intervals that stay in place, or whose step is shorter than
//! half the shortest step, keep the feet where they are.
//!
//! Every foothold taken is checked again against the terrain itself
//! ([`Footing::invalid_footholds`], which must stay 0). Planning is deterministic; its time is
//! measured only when a front-end lends a [`Stopwatch`], and never feeds back into the motion.

use std::sync::Arc;

use glam::DVec2;

use crate::anim::{Database, Ground};
use crate::footstep::{
    Decision, Foot, FootstepParams, FootstepPlanner, GroundProfile, PlannerMode, Sole, StopReason, Swing,
};
use crate::world::Terrain;

/// How far ahead of the front foot the ground profile reaches, metres.
pub const HORIZON_M: f64 = 5.0;
/// Points along each sole at which a foothold is checked against the terrain.
const SOLE_SAMPLES: usize = 9;

/// A clock a front-end may lend the footing to time its planning (seconds, any origin). The
/// simulation never reads it for anything else.
pub trait Stopwatch: Send + Sync {
    /// Seconds since some fixed instant.
    fn now_s(&self) -> f64;
}

/// A shared [`Stopwatch`]; equal when it is the same one.
#[derive(Clone)]
pub struct StopwatchHandle(pub Arc<dyn Stopwatch>);

impl std::fmt::Debug for StopwatchHandle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("StopwatchHandle")
    }
}

impl PartialEq for StopwatchHandle {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// A foothold in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldFoothold {
    /// Which foot.
    pub foot: Foot,
    /// The sole's centre, metres.
    pub position: DVec2,
    /// Ground height under it, metres.
    pub z_m: f64,
    /// Direction the foot points, radians.
    pub yaw: f64,
}

/// The step being played: the legs planned in the sagittal plane through `origin` along `dir`.
#[derive(Debug, Clone)]
pub struct PlayedStep {
    /// The planned legs (profile coordinates: X along `dir` from `origin`, Z the height).
    pub swing: Swing,
    /// Where the profile starts, metres.
    pub origin: DVec2,
    /// The profile's direction (unit).
    pub dir: DVec2,
    /// The profile the step was planned on.
    pub profile: GroundProfile,
    /// The planner's window of steps (metres), its first one being this step.
    pub window_m: Vec<f64>,
}

/// The feet of an animated character on uneven terrain. See the [module docs](self).
#[derive(Debug, Clone)]
pub struct Footing {
    terrain: Arc<Terrain>,
    params: FootstepParams,
    clock: Option<StopwatchHandle>,
    rear: WorldFoothold,
    front: WorldFoothold,
    /// Root translation scale of the interval playing.
    scale: f64,
    played: Option<PlayedStep>,
    stopped: Option<String>,
    footholds: Vec<WorldFoothold>,
    invalid: u32,
    planning_s: Vec<f64>,
    plans: u64,
}

impl Footing {
    /// Feet side by side at `at` on `terrain`.
    pub fn new(terrain: Arc<Terrain>, params: FootstepParams, at: Ground, clock: Option<StopwatchHandle>) -> Footing {
        let p = DVec2::new(at.x, at.y);
        let z = terrain.height(p);
        let left = WorldFoothold { foot: Foot::Left, position: p, z_m: z, yaw: at.yaw };
        let right = WorldFoothold { foot: Foot::Right, ..left };
        Footing {
            terrain,
            params,
            clock,
            rear: left,
            front: right,
            scale: 1.0,
            played: None,
            stopped: None,
            footholds: vec![left, right],
            invalid: 0,
            planning_s: Vec::new(),
            plans: 0,
        }
    }

    /// The root translation scale of the interval playing (adapted step / nominal step; 0 while
    /// stopped).
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// Why the character stands, while the planner finds no step.
    pub fn stopped(&self) -> Option<&str> {
        self.stopped.as_deref()
    }

    /// Every foothold taken, the two of the initial stance first.
    pub fn footholds(&self) -> &[WorldFoothold] {
        &self.footholds
    }

    /// Footholds the terrain itself does not support (whole sole on ground, at the planned
    /// height): must be 0.
    pub fn invalid_footholds(&self) -> u32 {
        self.invalid
    }

    /// Planning times measured (seconds), one per planned step, when a stopwatch was lent.
    pub fn planning_times_s(&self) -> &[f64] {
        &self.planning_s
    }

    /// Steps planned so far.
    pub fn plans(&self) -> u64 {
        self.plans
    }

    /// The step playing, when it was planned.
    pub fn played(&self) -> Option<&PlayedStep> {
        self.played.as_ref()
    }

    /// The parameters.
    pub fn params(&self) -> &FootstepParams {
        &self.params
    }

    /// Height of the ground under the pelvis at `progress` (0–1) through the step playing:
    /// the planned pelvis less its standing height, or the front foothold's height, metres.
    pub fn ground_height_m(&self, progress: f64) -> f64 {
        match &self.played {
            Some(p) => {
                let pose = p.swing.pose_at(progress.clamp(0.0, 1.0));
                pose.stance.hip.y - self.params.leg.hip_height_m
            }
            None => self.front.z_m,
        }
    }

    /// A new interval starts at `root`: plans its step (see the [module docs](self)).
    pub fn decide(&mut self, db: &Database, interval: usize, root: Ground) {
        let iv = &db.intervals[interval];
        let nominal = iv.speed * iv.duration;
        self.played = None;
        if db.kinds[interval].in_place || !(nominal >= 0.5 * self.params.step_min_m) {
            self.scale = 1.0;
            self.stopped = None;
            return;
        }
        let started = self.clock.as_ref().map(|c| c.0.now_s());
        let outcome = self.plan(nominal, root.yaw);
        if let (Some(c), Some(t0)) = (&self.clock, started) {
            self.planning_s.push((c.0.now_s() - t0).max(0.0));
        }
        self.plans += 1;
        match outcome {
            Ok((step, played)) => {
                self.scale = step / nominal;
                self.stopped = None;
                self.played = Some(played);
            }
            Err(reason) => {
                self.scale = 0.0;
                self.stopped = Some(reason);
            }
        }
    }

    /// Plans one step of nominal length `nominal` along `yaw`: the adapted step length, or why
    /// there is none.
    fn plan(&mut self, nominal: f64, yaw: f64) -> Result<(f64, PlayedStep), String> {
        let dir = DVec2::from_angle(yaw);
        let origin = self.front.position;
        let rear_m = (self.rear.position - origin).dot(dir).min(0.0);
        let from = rear_m - self.params.step_max_m;
        let Some(profile) = self.terrain.profile(origin, dir, from, HORIZON_M) else {
            return Err("no ground ahead".into());
        };
        let goal_m = HORIZON_M - self.params.leg.foot_length_m();
        let next = self.rear.foot;
        let planner =
            FootstepPlanner::from_stance(&profile, rear_m, 0.0, next, goal_m, self.params, PlannerMode::Window)
                .or_else(|_| {
                    FootstepPlanner::from_stance(&profile, 0.0, 0.0, next, goal_m, self.params, PlannerMode::Window)
                });
        let mut planner = match planner {
            Ok(p) => p,
            Err(e) => return Err(e.to_string()),
        };
        match planner.next_step(nominal) {
            Decision::Step(s) => {
                let x = s.swing.touch_down.x_m;
                let foothold =
                    WorldFoothold { foot: s.foot, position: origin + dir * x, z_m: s.swing.touch_down.z_m, yaw };
                if !self.supported(&s.swing.touch_down, origin, dir) {
                    self.invalid += 1;
                }
                self.rear = self.front;
                self.front = foothold;
                self.footholds.push(foothold);
                Ok((x, PlayedStep { swing: s.swing, origin, dir, profile: profile.clone(), window_m: s.window_m }))
            }
            // The goal lies beyond the horizon, so it is never reached from the front foot.
            Decision::Reached => Err("the ground profile ends within reach".into()),
            Decision::Stopped(reason) => Err(describe(&reason)),
        }
    }

    /// Whether the terrain holds the whole sole `sole` (profile coordinates along `dir` from
    /// `origin`; the sole's horizontal span is the foot length, as the planner's): ground under every point of it, nowhere above it, and under its heel and
    /// toe (a sole may bridge a hollow, never a hole, a bump or a vertical step).
    fn supported(&self, sole: &Sole, origin: DVec2, dir: DVec2) -> bool {
        const TOLERANCE_M: f64 = 1e-6;
        let l = self.params.leg.foot_length_m();
        // The sole spans [x − L/2, x + L/2] along the profile, on the line of its pitch.
        let ground = |u: f64| {
            let dx = (u - 0.5) * l;
            let z = sole.z_m + dx * sole.pitch_rad.tan();
            self.terrain.ground(origin + dir * (sole.x_m + dx)).map(|g| g - z)
        };
        // The ends: on the ground (just inside, should an edge lie exactly there).
        let inside = TOLERANCE_M / l;
        let end = |u: f64, v: f64| [u, v].into_iter().any(|w| ground(w).is_some_and(|d| d.abs() <= TOLERANCE_M));
        end(0.0, inside)
            && end(1.0, 1.0 - inside)
            && (1..SOLE_SAMPLES - 1).all(|k| {
                let u = k as f64 / (SOLE_SAMPLES - 1) as f64;
                ground(u).is_some_and(|d| d <= TOLERANCE_M)
            })
    }
}

fn describe(reason: &StopReason) -> String {
    reason.to_string()
}
