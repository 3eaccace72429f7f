//! The animated character's upper body among obstacles it can touch (seed 002 §5; DESIGN.md
//! §5): at every switch point, each candidate the navigation finds clear for the legs is
//! planned for the upper body too ([`crate::upper`]) over the motion it would play; a
//! candidate the upper body cannot make free is refused, and the chosen candidate's plan plays
//! with it. The offsets are added to the database's pose in [`super::AnimatedBody::world_pose`],
//! so every front-end and the exported motion show them.
//!
//! Played frames are measured against the obstacles: the least clearance of the capsules, the
//! deepest waist bend and twist. Planning time is measured only when a front-end lends a
//! [`Stopwatch`](super::footing::Stopwatch), and never feeds back into the motion.

use std::sync::Arc;

use glam::DVec2;

use super::footing::StopwatchHandle;
use crate::anim::body::{Part, Parts, UpperBody, UpperConfig};
use crate::anim::player::{Choice, SwitchPoint};
use crate::anim::{Database, Pose, Skeleton};
use crate::geom::Capsule;
use crate::upper::{LOOK_AHEAD_MIN_SPEED_MPS, LOOK_AHEAD_S, Plan, Refusal, Scratch, Solids, UpperPlanner};
use crate::world::Terrain;

/// What the upper body did over an episode.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UpperFigures {
    /// Least clearance of the upper body's capsules from the obstacles over the frames played,
    /// metres (infinite when nothing came within reach).
    pub min_clearance_m: f64,
    /// Deepest forward bend of the waist played, radians.
    pub max_bend_rad: f64,
    /// Largest twist of the waist played either way, radians.
    pub max_twist_rad: f64,
    /// Switch points at which the upper body refused a step the legs could take.
    pub refused_steps: u64,
    /// Times a bone of the upper body went into an obstacle (frames where one is inside after a
    /// frame where none was): its collisions.
    pub collisions: u32,
    /// Whether a bone is inside an obstacle in the last frame measured.
    pub inside: bool,
    /// Plans made.
    pub plans: u64,
    /// Frames played.
    pub frames: u64,
    /// Seconds spent planning, when a stopwatch was lent.
    pub planning_s: Option<f64>,
}

impl Default for UpperFigures {
    fn default() -> Self {
        UpperFigures {
            min_clearance_m: f64::INFINITY,
            max_bend_rad: 0.0,
            max_twist_rad: 0.0,
            refused_steps: 0,
            collisions: 0,
            inside: false,
            plans: 0,
            frames: 0,
            planning_s: None,
        }
    }
}

/// The upper body of an animated character. See the [module docs](self).
#[derive(Debug, Clone)]
pub struct UpperBodyState {
    planner: UpperPlanner,
    solids: Arc<Solids>,
    terrain: Option<Arc<Terrain>>,
    clock: Option<StopwatchHandle>,
    h: f64,
    plan: Plan,
    next: Option<Plan>,
    pending: Option<(Choice, Plan)>,
    refused: Option<Refusal>,
    start: UpperConfig,
    speed: f64,
    poses: Vec<Pose>,
    scratch: Scratch,
    near: Vec<usize>,
    caps: Vec<(Part, Capsule)>,
    figures: UpperFigures,
}

impl UpperBodyState {
    /// The upper body of a character built like the actor (`None` for another skeleton),
    /// among `solids`, on `terrain` when it is not flat, playing at `h`-second frames.
    pub fn new(
        skeleton: &Skeleton,
        solids: Arc<Solids>,
        terrain: Option<Arc<Terrain>>,
        clock: Option<StopwatchHandle>,
        h: f64,
    ) -> Option<UpperBodyState> {
        let body = UpperBody::of(skeleton)?;
        Some(UpperBodyState {
            planner: UpperPlanner::new(body),
            solids,
            terrain,
            clock,
            h,
            plan: Plan::hold(UpperConfig::default(), h),
            next: None,
            pending: None,
            refused: None,
            start: UpperConfig::default(),
            speed: 0.0,
            poses: Vec::new(),
            scratch: Scratch::default(),
            near: Vec::new(),
            caps: Vec::new(),
            figures: UpperFigures::default(),
        })
    }

    /// The offsets `t` seconds into the interval playing.
    pub fn offsets(&self, t: f64) -> UpperConfig {
        self.plan.at(t)
    }

    /// The body planned for.
    pub fn planner_body(&self) -> &UpperBody {
        self.planner.body()
    }

    /// The figures so far.
    pub fn figures(&self) -> UpperFigures {
        self.figures
    }

    /// Why the last candidate refused was refused, if one was at the last switch point.
    pub fn refusal(&self) -> Option<Refusal> {
        self.refused
    }

    /// A choice begins at a switch point where the offsets are `start`.
    pub fn begin_choice(&mut self, start: UpperConfig) {
        self.start = start;
        self.pending = None;
        self.refused = None;
    }

    /// Plans choice `a` at `at` (looking ahead as if walking on at `speed`, and at
    /// [`LOOK_AHEAD_MIN_SPEED_MPS`] at least): true when the upper body can play it.
    pub fn admits(&mut self, db: &Database, at: &SwitchPoint, a: Choice, speed: f64) -> bool {
        self.speed = speed.max(LOOK_AHEAD_MIN_SPEED_MPS);
        match self.plan_for(db, at, a, LOOK_AHEAD_S) {
            Ok(plan) => {
                self.pending = Some((a, plan));
                true
            }
            Err(r) => {
                self.refused = Some(r);
                false
            }
        }
    }

    /// For the last resort, when no choice is admitted: plans choice `a` at `at` over its own
    /// interval alone (no look-ahead). `Ok` when the upper body keeps clear while it plays (the
    /// plan is kept for the choice); else the least clearance of the upper body over the
    /// interval with the offsets held, metres, for choosing the least bad (minus infinity when
    /// the legs would step into something).
    pub fn settles(&mut self, db: &Database, at: &SwitchPoint, a: Choice) -> Result<(), f64> {
        match self.plan_for(db, at, a, 0.0) {
            Ok(plan) => {
                self.pending = Some((a, plan));
                Ok(())
            }
            // Legs that would step into something are the worst of all.
            Err(Refusal::Legs) => Err(f64::NEG_INFINITY),
            Err(_) => {
                let (body, caps, near) = (self.planner.body(), &mut self.caps, &mut self.near);
                let least = self.poses.iter().fold(f64::INFINITY, |least, p| {
                    body.place(&body.frame(p), &self.start, Parts::TrunkAndArms, caps);
                    least.min(self.solids.clearance_near(caps, DVec2::new(p.root.x, p.root.y), 1.0, near))
                });
                Err(least)
            }
        }
    }

    /// The choice `a` was made: its plan plays from the switch. A choice nothing admitted (the
    /// last resort) plays the plan over its own interval if [`UpperBodyState::settles`] found
    /// one — the waist and arms still move out of what the interval brings near — and holds
    /// the offsets only where even that failed.
    pub fn end_choice(&mut self, db: &Database, at: &SwitchPoint, a: Choice) {
        if self.refused.is_some() {
            self.figures.refused_steps += 1;
        }
        let plan = match self.pending.take() {
            Some((b, plan)) if b == a => plan,
            _ => self.plan_for(db, at, a, LOOK_AHEAD_S).unwrap_or_else(|_| Plan::hold(self.start, self.h)),
        };
        self.next = Some(plan);
    }

    /// The player switched: the plan of the choice plays from now.
    pub fn switched(&mut self) {
        if let Some(p) = self.next.take() {
            self.plan = p;
        }
    }

    /// The upper body's plan moves it for something (offsets other than none) now or by `t`
    /// seconds into the plan playing.
    pub fn active(&self, t: f64) -> bool {
        let none = UpperConfig::default();
        self.plan.configs.first().is_some_and(|c| *c != none) || self.offsets(t) != none
    }

    /// Measures a frame played (`pose` with the offsets `c` applied).
    pub fn measure(&mut self, pose: &Pose, c: &UpperConfig) {
        let f = &mut self.figures;
        f.frames += 1;
        f.max_bend_rad = f.max_bend_rad.max(c.waist[0]);
        f.max_twist_rad = f.max_twist_rad.max(c.waist[1].abs());
        self.planner.body().capsules(pose, &mut self.caps);
        let at = DVec2::new(pose.root.x, pose.root.y);
        // The legs are the footstep planner's (a sole on a kerb's top has its capsule's skin in
        // the kerb): the clearance is that of the parts the upper-body planner moves, which
        // `place` lists before the legs.
        let legs = self.caps.iter().position(|(p, _)| p.is_leg()).unwrap_or(self.caps.len());
        let d = self.solids.clearance_near(&self.caps[..legs], at, 1.0, &mut self.near);
        if d < 1.0 {
            f.min_clearance_m = f.min_clearance_m.min(d);
        }
        // A bone (a capsule's axis), legs included, in an obstacle.
        let from = if d < 0.0 { 0 } else { legs };
        for (part, c) in &mut self.caps[from..] {
            // The head's capsule ends its radius short of the top of the head, its bone's end.
            if *part == Part::Head {
                c.b += (c.b - c.a).normalize_or_zero() * c.radius;
            }
            c.radius = 0.0;
        }
        let inside =
            from < self.caps.len() && self.solids.clearance_near(&self.caps[from..], at, 1.0, &mut self.near) < 0.0;
        if inside && !f.inside {
            f.collisions += 1;
        }
        f.inside = inside;
    }

    /// Plans choice `a` at `at` over its interval and `look_ahead_s` seconds more.
    fn plan_for(&mut self, db: &Database, at: &SwitchPoint, a: Choice, look_ahead_s: f64) -> Result<Plan, Refusal> {
        let started = self.clock.as_ref().map(|c| c.0.now_s());
        let own = at.poses(db, a, look_ahead_s, self.speed, &mut self.poses);
        if let Some(t) = &self.terrain {
            for p in &mut self.poses {
                p.root.z += t.height(DVec2::new(p.root.x, p.root.y));
            }
        }
        let plan = self.planner.plan(&self.solids, &self.poses, own, self.h, &self.start, &mut self.scratch);
        self.figures.plans += 1;
        if let (Some(c), Some(t0)) = (&self.clock, started) {
            *self.figures.planning_s.get_or_insert(0.0) += (c.0.now_s() - t0).max(0.0);
        }
        plan
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::{Obstacle, ObstacleShape};

    #[test]
    fn a_bone_going_into_an_obstacle_is_a_collision_once_per_entry() {
        let s = crate::anim::actor::actor();
        // A shelf through the chest of the actor standing at the origin, and one far away.
        let slab = |x: f64| {
            let shape = ObstacleShape::Box { center: DVec2::new(x, 0.0), width: 0.05, height: 1.0, yaw: 0.0 };
            Obstacle::build(shape, 1.2, 1.3).unwrap()
        };
        let near = Arc::new(Solids::new(&[slab(0.0)]));
        let mut u = UpperBodyState::new(&s, near, None, None, 1.0 / 60.0).unwrap();
        let pose = s.bind_pose();
        let c = UpperConfig::default();
        u.measure(&pose, &c);
        u.measure(&pose, &c);
        assert_eq!((u.figures().collisions, u.figures().inside), (1, true));
        // Out of it (the same body 5 m away), then in again.
        let mut away = pose.clone();
        away.root.x -= 5.0;
        u.measure(&away, &c);
        assert!(!u.figures().inside);
        u.measure(&pose, &c);
        assert_eq!(u.figures().collisions, 2);
        // Capsules grazing a solid with their skin only are no collision: a slab beside the chest.
        let beside = Arc::new(Solids::new(&[slab(0.105)]));
        let mut v = UpperBodyState::new(&s, beside, None, None, 1.0 / 60.0).unwrap();
        v.measure(&pose, &c);
        assert!(v.figures().min_clearance_m < 0.0, "{}", v.figures().min_clearance_m);
        assert_eq!(v.figures().collisions, 0);
    }
}
