//! The animated character on uneven terrain (seed 002 §3.2, §4; DESIGN.md §4): at each step the
//! database's interval gives the nominal step, and the footstep planner adapts it to the ground.
//!
//! At every switch to a moving interval, [`Footing::decide`] cuts the terrain with the
//! character's sagittal plane (a vertical plane along its heading through the front foot) into
//! a [`GroundProfile`] reaching [`HORIZON_M`] ahead, and runs the [`FootstepPlanner`] from the
//! two feet planted now with the interval's step (mean speed × duration) as the nominal one.
//! The step it returns places the next foothold. While the interval plays, the root follows
//! the planned hip along the step's line ([`Footing::root_at`]; across the line and in heading
//! it moves as the interval does), and the legs are the planned ones: the swinging sole on
//! its Bezier curve, two-link inverse kinematics, the pelvis height following the ground
//! ([`Footing::pose_legs`], [`Swing::pose_at`]); the upper body is the database's. When the
//! planner stops — no sequence of steps reaches further — the character stands (its root
//! holds, its feet on their footholds) and [`Footing::stopped`] says why; it never takes an
//! invalid foothold. Intervals that stay in place, or whose step is shorter than
//! half the shortest step, keep the feet where they are.
//!
//! Every foothold taken is checked again against the terrain itself
//! ([`Footing::invalid_footholds`], which must stay 0). Planning is deterministic; its time is
//! measured only when a front-end lends a [`Stopwatch`], and never feeds back into the motion.

use std::sync::Arc;

use glam::{DVec2, DVec3};

use crate::anim::actor::HIP_HALF_WIDTH_M;
use crate::anim::procedural::leg::{FootTarget, MAX_REACH_M, Rig, SIDES, place_leg, sole_point};
use crate::anim::skeleton::heading;
use crate::anim::{Database, Ground, Pose, Skeleton};
use crate::footstep::{
    Decision, Foot, FootstepParams, FootstepPlanner, GroundProfile, PlannerMode, Sole, StopReason, Swing,
};
use crate::world::Terrain;

/// How far ahead of the front foot the ground profile reaches, metres.
pub const HORIZON_M: f64 = 5.0;
/// Points along each sole at which a foothold is checked against the terrain.
const SOLE_SAMPLES: usize = 9;
/// Half the width of a sole, metres: each foot stands on a strip this far either side of its
/// line, half the hip width out from the path.
pub const FOOT_HALF_WIDTH_M: f64 = 0.05;
/// Largest difference in height across the feet's strip that still counts as one foothold
/// (a sole resting on ground that falls away sideways), metres.
pub const ACROSS_TOLERANCE_M: f64 = 0.03;

/// Offsets to the left of the path of the lines under the edges of both soles, metres.
fn sole_edges() -> [f64; 4] {
    let (h, w) = (HIP_HALF_WIDTH_M, FOOT_HALF_WIDTH_M);
    [-(h + w), -(h - w), h - w, h + w]
}

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
    /// Pitch of the sole along `yaw`, radians, positive toes up.
    pub pitch_rad: f64,
}

impl WorldFoothold {
    /// Where the middle of the sole rests: half the hip width out from the path, on the
    /// foot's side.
    pub fn sole_centre(&self) -> DVec2 {
        let side = if self.foot == Foot::Left { 1.0 } else { -1.0 };
        self.position + DVec2::from_angle(self.yaw).perp() * (side * HIP_HALF_WIDTH_M)
    }
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
    /// Where the swinging foot lifts off, in the world.
    pub lift_off: WorldFoothold,
}

/// The feet of an animated character on uneven terrain. See the [module docs](self).
#[derive(Debug, Clone)]
pub struct Footing {
    terrain: Arc<Terrain>,
    params: FootstepParams,
    clock: Option<StopwatchHandle>,
    rear: WorldFoothold,
    front: WorldFoothold,
    played: Option<PlayedStep>,
    stopped: Option<String>,
    mode: PlannerMode,
    footholds: Vec<WorldFoothold>,
    invalid: u32,
    planning_s: Vec<f64>,
    plans: u64,
}

impl Footing {
    /// Feet side by side under the pelvis at `at` on `terrain` (the ankles under the hips, so
    /// the soles' centres a little ahead).
    /// `mode` says whether the planner adapts the steps ([`PlannerMode::Window`]) or takes the
    /// nominal one, stopping before one that is invalid ([`PlannerMode::Nominal`], `--planner
    /// off`).
    pub fn new(
        terrain: Arc<Terrain>,
        params: FootstepParams,
        at: Ground,
        clock: Option<StopwatchHandle>,
        mode: PlannerMode,
    ) -> Footing {
        let ahead = 0.5 * (params.leg.toe_forward_m - params.leg.heel_back_m);
        let p = DVec2::new(at.x, at.y) + DVec2::from_angle(at.yaw) * ahead;
        let z = terrain.height(p);
        let left = WorldFoothold { foot: Foot::Left, position: p, z_m: z, yaw: at.yaw, pitch_rad: 0.0 };
        let right = WorldFoothold { foot: Foot::Right, ..left };
        Footing {
            terrain,
            params,
            mode,
            clock,
            rear: left,
            front: right,
            played: None,
            stopped: None,
            footholds: vec![left, right],
            invalid: 0,
            planning_s: Vec::new(),
            plans: 0,
        }
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

    /// Where the root goes `progress` (0–1) through a planned step, from `prev` (the root one
    /// frame earlier) toward `natural` (where the interval's own motion takes it): along the
    /// step's line as far as the planned hip has come, across it as the interval moves, with the
    /// interval's heading. `None` when no step is planned (the interval's motion stands).
    pub fn root_at(&self, progress: f64, prev: Ground, natural: Ground) -> Option<Ground> {
        let p = self.played.as_ref()?;
        let side = p.dir.perp();
        let (from, to) = (DVec2::new(prev.x, prev.y), DVec2::new(natural.x, natural.y));
        let across = (from - p.origin).dot(side) + (to - from).dot(side);
        let at = p.origin + p.dir * p.swing.hip_x_at(progress) + side * across;
        Some(Ground { x: at.x, y: at.y, yaw: natural.yaw })
    }

    /// Puts the legs of `pose` — the database's pose of the built-in actor, its root already
    /// placed in the world over flat ground — on the terrain, `progress` (0–1) through the
    /// interval playing (seed 002 §4.1).
    ///
    /// During a planned step the legs are the planner's: the supporting sole on its foothold,
    /// the swinging sole along its Bezier curve from one foothold to the next, each sole
    /// beside the path ([`WorldFoothold::sole_centre`]) with the ground's pitch, the pelvis at
    /// the planned hip height;
    /// while stopped both soles stay on their footholds; otherwise (intervals in place,
    /// standing) each foot keeps the database's motion raised onto the height of its own
    /// foothold. Without a planned step the pelvis rises by the mean height of the footholds.
    /// Either way the pelvis comes down where a leg could not reach its target, and both legs
    /// are solved by two-link inverse kinematics with the knees forward; the upper body is the
    /// database's. A skeleton not built like the actor (an imported rig) keeps its database
    /// legs, the pelvis raised by the ground under it.
    pub fn pose_legs(&self, skeleton: &Skeleton, pose: &mut Pose, progress: f64) {
        let Some(rig) = Rig::find(skeleton) else {
            pose.root.z += self.ground_height_m(progress);
            return;
        };
        let root_yaw = heading(pose.rotations[0]);
        let by_foot = |foot: usize| if self.rear.foot.index() == foot { self.rear } else { self.front };
        let mut targets =
            [FootTarget { point: DVec3::ZERO, local: DVec3::ZERO, yaw: 0.0, pitch: 0.0, planted: true }; 2];
        let mut hip_z;
        match &self.played {
            Some(p) => {
                let t = progress.clamp(0.0, 1.0);
                let swinging = self.front.foot.index();
                let (from, to) = (p.swing.lift_off.x_m, p.swing.touch_down.x_m);
                for (i, target) in targets.iter_mut().enumerate() {
                    let (sole, at) = if i == swinging {
                        // Along the straight line between the two footholds in the world,
                        // as far as the curve has come along the profile.
                        let sole = p.swing.sole_at(t);
                        let u = if to > from { ((sole.x_m - from) / (to - from)).clamp(0.0, 1.0) } else { t };
                        (sole, p.lift_off.sole_centre().lerp(self.front.sole_centre(), u))
                    } else {
                        (p.swing.stance, self.rear.sole_centre())
                    };
                    *target = FootTarget {
                        point: DVec3::new(at.x, at.y, sole.z_m),
                        local: sole_point(0.5),
                        yaw: root_yaw,
                        pitch: -sole.pitch_rad,
                        planted: i != swinging,
                    };
                }
                hip_z = p.swing.hip_pose_at(t).y;
            }
            None => {
                let mut globals = Vec::with_capacity(skeleton.len());
                skeleton.globals(pose, &mut globals);
                let mut rise = 0.0;
                for (i, target) in targets.iter_mut().enumerate() {
                    let held = by_foot(i);
                    rise += 0.5 * held.z_m;
                    *target = if self.stopped.is_some() {
                        let at = held.sole_centre();
                        FootTarget {
                            point: DVec3::new(at.x, at.y, held.z_m),
                            local: sole_point(0.5),
                            yaw: root_yaw,
                            pitch: -held.pitch_rad,
                            planted: true,
                        }
                    } else {
                        let (ankle, q) = globals[rig.foot[i]];
                        let forward = q * DVec3::X;
                        FootTarget {
                            point: ankle + DVec3::new(0.0, 0.0, held.z_m),
                            local: DVec3::ZERO,
                            yaw: root_yaw,
                            pitch: (-forward.z).clamp(-1.0, 1.0).asin(),
                            planted: true,
                        }
                    };
                }
                hip_z = pose.root.z + rise;
            }
        }
        let rot = pose.rotations[0];
        for (i, target) in targets.iter().enumerate() {
            let hip = pose.root + rot * DVec3::new(0.0, SIDES[i] * HIP_HALF_WIDTH_M, 0.0);
            let ankle = target.ankle();
            // A target farther than the leg reaches in the plan view is pointed at by the
            // straight leg: lowering the pelvis would not bring it closer.
            let flat = (ankle - hip).truncate().length();
            if flat < MAX_REACH_M {
                hip_z = hip_z.min(ankle.z + (MAX_REACH_M * MAX_REACH_M - flat * flat).sqrt());
            }
        }
        pose.root.z = hip_z;
        for (i, target) in targets.iter().enumerate() {
            place_leg(&rig, i, target, pose);
        }
    }

    /// A new interval starts at `root`: plans its step (see the [module docs](self)).
    pub fn decide(&mut self, db: &Database, interval: usize, root: Ground) {
        let iv = &db.intervals[interval];
        let nominal = iv.speed * iv.duration;
        self.played = None;
        if db.kinds[interval].in_place || !(nominal >= 0.5 * self.params.step_min_m) {
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
            Ok(played) => {
                self.stopped = None;
                self.played = Some(played);
            }
            Err(reason) => {
                self.stopped = Some(reason);
            }
        }
    }

    /// Plans one step of nominal length `nominal` along `yaw`, or says why there is none.
    fn plan(&mut self, nominal: f64, yaw: f64) -> Result<PlayedStep, String> {
        let dir = DVec2::from_angle(yaw);
        let origin = self.front.position;
        let rear_m = (self.rear.position - origin).dot(dir).min(0.0);
        let from = rear_m - self.params.step_max_m;
        let Some(profile) = self.terrain.strip_profile(origin, dir, from, HORIZON_M, &sole_edges(), ACROSS_TOLERANCE_M)
        else {
            return Err("no ground ahead".into());
        };
        let goal_m = HORIZON_M - self.params.leg.foot_length_m();
        let next = self.rear.foot;
        let sole = |f: &WorldFoothold, x_m: f64| Sole { x_m, z_m: f.z_m, pitch_rad: f.pitch_rad };
        let (rear, front) = (sole(&self.rear, rear_m), sole(&self.front, 0.0));
        let planner = FootstepPlanner::from_planted(&profile, rear, front, next, goal_m, self.params, self.mode);
        let mut planner = match planner {
            Ok(p) => p,
            Err(e) => return Err(e.to_string()),
        };
        match planner.next_step(nominal) {
            Decision::Step(s) => {
                let x = s.swing.touch_down.x_m;
                let td = s.swing.touch_down;
                let foothold = WorldFoothold {
                    foot: s.foot,
                    position: origin + dir * x,
                    z_m: td.z_m,
                    yaw,
                    pitch_rad: td.pitch_rad,
                };
                if !self.supported(&s.swing.touch_down, s.foot, origin, dir) {
                    self.invalid += 1;
                }
                let lift_off = self.rear;
                self.rear = self.front;
                self.front = foothold;
                self.footholds.push(foothold);
                let played = PlayedStep {
                    swing: s.swing,
                    origin,
                    dir,
                    profile: profile.clone(),
                    window_m: s.window_m,
                    lift_off,
                };
                Ok(played)
            }
            // The goal lies beyond the horizon, so it is never reached from the front foot.
            Decision::Reached => Err("the ground profile ends within reach".into()),
            Decision::Stopped(reason) => Err(describe(&reason)),
        }
    }

    /// Whether the terrain holds the whole sole `sole` of `foot` (profile coordinates along
    /// `dir` from `origin`; the sole's horizontal span is the foot length, as the planner's,
    /// and its width the foot's, half the hip width out on the foot's side): ground under every
    /// point of both its edges, nowhere above it, and under its heel and toe within the
    /// tolerance across the strip (a sole may bridge a hollow, never a hole, a bump or a
    /// vertical step).
    fn supported(&self, sole: &Sole, foot: Foot, origin: DVec2, dir: DVec2) -> bool {
        const ABOVE_M: f64 = 1e-6;
        let l = self.params.leg.foot_length_m();
        let out = if foot == Foot::Left { HIP_HALF_WIDTH_M } else { -HIP_HALF_WIDTH_M };
        [out - FOOT_HALF_WIDTH_M, out + FOOT_HALF_WIDTH_M].into_iter().all(|offset| {
            let line = origin + dir.perp() * offset;
            // The sole spans [x − L/2, x + L/2] along the profile, on the line of its pitch;
            // the ground's height above it there.
            let ground = |u: f64| {
                let dx = (u - 0.5) * l;
                let z = sole.z_m + dx * sole.pitch_rad.tan();
                self.terrain.ground(line + dir * (sole.x_m + dx)).map(|g| g - z)
            };
            // The ends: on the ground (just inside, should an edge lie exactly there).
            let inside = ABOVE_M / l;
            let end = |u: f64, v: f64| {
                [u, v]
                    .into_iter()
                    .any(|w| ground(w).is_some_and(|d| (-ACROSS_TOLERANCE_M - ABOVE_M..=ABOVE_M).contains(&d)))
            };
            end(0.0, inside)
                && end(1.0, 1.0 - inside)
                && (1..SOLE_SAMPLES - 1).all(|k| {
                    let u = k as f64 / (SOLE_SAMPLES - 1) as f64;
                    ground(u).is_some_and(|d| d <= ABOVE_M)
                })
        })
    }
}

fn describe(reason: &StopReason) -> String {
    reason.to_string()
}
