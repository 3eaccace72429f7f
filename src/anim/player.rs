//! Playing the animation database (seed 000 §3.2, §3.2.2): intervals one after another, the
//! next one picked at each switch point among the candidates, transitions by cross-fade (source
//! weight 1→0, destination 0→1 over a fixed time, started at the start of the destination
//! interval) or by inertialization (the pose offset at the switch decays by a critically damped
//! spring), and root motion integrated frame by frame so the character's path is continuous.
//!
//! Root motion lives in [`RootMotion`], a small state that playback and look-ahead share: at a
//! switch point a [`Chooser`] can ask, for any candidate, for the exact world path the root
//! would take ([`SwitchPoint::path`]), blend included, before anything is played.
//!
//! **Foot locking** (seed 002 §4.1's two-link leg IK): while the database says a foot is on the
//! ground, its contact point (heel, or toe once the heel lifts) is held where it touched down.
//! Blends and corrections that would move it are undone by a two-bone IK of hip and knee, the
//! foot keeping its animated orientation — or, for a leg with the actor's channels (hip about Y
//! then X, knee and ankle about Y: no twist), within those channels, so that a written BVH file
//! shows what was played, the foot turning as the hip lets it about the point held; at lift-off the correction fades out over
//! [`PlayerParams::release_s`]. A planted foot whose heading turns (a blend between a turn on
//! the spot and a step) pivots on its toe with the heel lifted, as a person does — the actor's
//! hip cannot turn a flat foot on the ground. So switching intervals never slides or teleports
//! a planted foot.
//!
//! The player also measures what a viewer would notice: foot skating at the heel and toe
//! contact points (horizontal slide `d` per frame weighted by `2 − 2^(h/H)` while the point is
//! below `H` = [`CONTACT_HEIGHT_M`]), the share of foot plants sliding 2 cm or more
//! ([`PERCEPTIBLE_SLIDE_CM`]), the pose distance at each switch, peak joint jerk around
//! switches, and footprints.

use glam::{DQuat, DVec2, DVec3};

use super::clip::Ground;
use super::db::{Database, contact_bit, point_positions};
use super::skeleton::Pose;
use super::warp::{Warp, WarpLimits};
use crate::geom::{smoothstep, wrap_angle};

/// How one interval hands over to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TransitionKind {
    /// Cross-fade (the paper's choice).
    #[default]
    CrossFade,
    /// Inertialization.
    Inertialize,
}

/// Playback parameters. Every field documents its default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayerParams {
    /// Transition kind (cross-fade).
    pub transition: TransitionKind,
    /// Cross-fade time, seconds (0.2).
    pub blend_s: f64,
    /// Cross-fade time of an early switch (something unexpected mid-interval), seconds (0.1).
    pub early_blend_s: f64,
    /// Half-life of the inertialization offset, seconds (0.08).
    pub halflife_s: f64,
    /// Playback frame rate, frames per second (60).
    pub frame_rate: f64,
    /// Hold planted feet with leg IK (true).
    pub foot_locking: bool,
    /// Time over which a foot's lock correction fades out after lift-off, seconds (0.12).
    pub release_s: f64,
}

impl Default for PlayerParams {
    fn default() -> Self {
        PlayerParams {
            transition: TransitionKind::CrossFade,
            blend_s: 0.2,
            early_blend_s: 0.1,
            halflife_s: 0.08,
            frame_rate: 60.0,
            foot_locking: true,
            release_s: 0.12,
        }
    }
}

/// Height below which a contact point counts for the skating measure, metres (2.5 cm).
pub const CONTACT_HEIGHT_M: f64 = 0.025;
/// A foot plant sliding this much or more is perceptible, centimetres.
pub const PERCEPTIBLE_SLIDE_CM: f64 = 2.0;
/// Window around a switch in which joint jerk is watched, seconds.
pub const JERK_WINDOW_S: f64 = 0.25;
/// Frames between the points a look-ahead path records while a cross-fade is blending.
const BLEND_PATH_EVERY: usize = 3;

/// A foot plant seen during playback.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Footprint {
    /// Where the foot joint came down (ground plane), metres.
    pub x: f64,
    /// Where the foot joint came down (ground plane), metres.
    pub y: f64,
    /// Character heading then, radians.
    pub yaw: f64,
    /// 0 left, 1 right.
    pub foot: u8,
}

/// Measurements of a playback so far.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlaybackMetrics {
    /// Frames played.
    pub frames: u64,
    /// Σ weight × horizontal slide of the heel and toe points, centimetres.
    pub skate_weighted_cm: f64,
    /// Σ contact weight.
    pub contact_weight: f64,
    /// Foot plants completed (touch-down to lift-off).
    pub plants: u64,
    /// Plants whose contact points slid [`PERCEPTIBLE_SLIDE_CM`] or more.
    pub sliding_plants: u64,
    /// Switch points passed.
    pub switches: u64,
    /// Early switches (mid-interval, something unexpected ahead).
    pub early_switches: u64,
    /// Switches to something other than the clip's own next interval.
    pub transitions: u64,
    /// Σ pose distance (Eq. 1) between what was playing and what starts, over transitions.
    pub transition_cost: f64,
    /// Largest joint jerk within [`JERK_WINDOW_S`] of a transition, m/s³.
    pub peak_switch_jerk: f64,
    /// Largest joint jerk anywhere, m/s³.
    pub peak_jerk: f64,
}

impl PlaybackMetrics {
    /// Mean slide of contact points per frame, centimetres (0 without contact).
    pub fn foot_skating_cm_per_frame(&self) -> f64 {
        if self.contact_weight > 0.0 { self.skate_weighted_cm / self.contact_weight } else { 0.0 }
    }

    /// Share of completed plants that slid less than [`PERCEPTIBLE_SLIDE_CM`] (1 without plants).
    pub fn steady_plant_share(&self) -> f64 {
        if self.plants > 0 { 1.0 - self.sliding_plants as f64 / self.plants as f64 } else { 1.0 }
    }

    /// Mean pose distance at transitions (0 without any).
    pub fn mean_transition_cost(&self) -> f64 {
        if self.transitions > 0 { self.transition_cost / self.transitions as f64 } else { 0.0 }
    }

    /// Adds another playback's counts and sums (peaks take the larger).
    pub fn absorb(&mut self, o: &PlaybackMetrics) {
        self.frames += o.frames;
        self.skate_weighted_cm += o.skate_weighted_cm;
        self.contact_weight += o.contact_weight;
        self.plants += o.plants;
        self.sliding_plants += o.sliding_plants;
        self.switches += o.switches;
        self.early_switches += o.early_switches;
        self.transitions += o.transitions;
        self.transition_cost += o.transition_cost;
        self.peak_switch_jerk = self.peak_switch_jerk.max(o.peak_switch_jerk);
        self.peak_jerk = self.peak_jerk.max(o.peak_jerk);
    }
}

/// The source of a cross-fade: its clip keeps playing while its weight falls.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Source {
    clip: usize,
    frame: f64,
    elapsed: f64,
    /// Blend time, seconds.
    span: f64,
    /// Ground of the source clip at `frame` (clip coordinates).
    ground: Ground,
    /// The warp the source played with.
    warp: Warp,
    /// The interval the source was playing (its frames may run past its end).
    interval: usize,
}

/// Root motion of a playback: the interval playing, where in it, the character's ground
/// reference in the world, and the source of a blend. Playback and look-ahead step the same
/// state, so a predicted path is the path that will be played.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RootMotion {
    interval: usize,
    frame: f64,
    /// Ground reference of the playing clip at `frame` (clip coordinates).
    clip_ground: Ground,
    /// The character's ground reference in the world.
    world: Ground,
    source: Option<Source>,
    /// The warp of the interval playing.
    warp: Warp,
}

impl RootMotion {
    /// Starts interval `next` right here (this frame, clip ground and world reference are the
    /// switch point): the clip playing becomes the source of a cross-fade of `blend_s` seconds
    /// (with 0, any blend still running goes on); `next` plays with `warp`.
    fn begin(&mut self, db: &Database, next: usize, blend_s: f64, warp: Warp) {
        if blend_s > 0.0 {
            let clip = db.intervals[self.interval].clip;
            self.source = Some(Source {
                clip,
                frame: self.frame,
                elapsed: 0.0,
                span: blend_s,
                ground: self.clip_ground,
                warp: self.warp,
                interval: self.interval,
            });
        }
        self.warp = warp;
        let nv = &db.intervals[next];
        self.interval = next;
        self.frame = nv.start as f64;
        self.clip_ground = db.ground(nv.clip, self.frame);
    }

    /// Plays `dt` seconds within the interval playing (stopping at its end), blending the root
    /// motion with a cross-fade's source.
    fn advance_by(&mut self, db: &Database, dt: f64) {
        let iv = &db.intervals[self.interval];
        let ft = db.clips[iv.clip].frame_time;
        let before = self.frame;
        self.frame = (self.frame + dt / ft).min(iv.end as f64);
        let g = db.ground(iv.clip, self.frame);
        let share = db.bend_share(self.interval, before, self.frame);
        let mut delta = self.warp.apply(self.clip_ground.to_local(g), share);
        self.clip_ground = g;
        if let Some(s) = &mut self.source {
            s.elapsed += dt;
            let sft = db.clips[s.clip].frame_time;
            let last = (db.clips[s.clip].frames.len() - 1) as f64;
            let before = s.frame;
            s.frame = (s.frame + dt / sft).min(last);
            let sg = db.ground(s.clip, s.frame);
            let sd = s.warp.apply(s.ground.to_local(sg), db.bend_share(s.interval, before, s.frame));
            s.ground = sg;
            // The travel blends; the heading turns as the destination turns, so an interval
            // turns by its own (warped) yaw whatever it follows.
            let w = smoothstep((s.elapsed / s.span).min(1.0));
            delta = Ground { x: sd.x + (delta.x - sd.x) * w, y: sd.y + (delta.y - sd.y) * w, yaw: delta.yaw };
            if s.elapsed >= s.span {
                self.source = None;
            }
        }
        self.world = self.world.then(delta);
    }

    /// Plays one frame of `h` seconds. When it passes the end of the interval playing, the
    /// frame is split there: `switch` is asked, at the switch point, for the next interval and
    /// its blend time, and the rest of the frame plays in it. Returns `(ending, next)` then.
    fn step(
        &mut self,
        db: &Database,
        h: f64,
        switch: &mut dyn FnMut(&RootMotion) -> (usize, f64, Warp),
    ) -> Option<(usize, usize)> {
        let iv = &db.intervals[self.interval];
        let ft = db.clips[iv.clip].frame_time;
        if self.frame + h / ft < iv.end as f64 - 1e-9 {
            self.advance_by(db, h);
            return None;
        }
        let to_end = ((iv.end as f64 - self.frame) * ft).clamp(0.0, h);
        self.advance_by(db, to_end);
        let ending = self.interval;
        let (next, blend_s, warp) = switch(self);
        self.begin(db, next, blend_s, warp);
        if h - to_end > 0.0 {
            self.advance_by(db, h - to_end);
        }
        Some((ending, next))
    }

    /// The cross-fade weight of the destination now (1 without a blend).
    fn weight(&self) -> f64 {
        self.source.map_or(1.0, |s| smoothstep((s.elapsed / s.span).clamp(0.0, 1.0)))
    }

    /// The relative pose now: the interval's, blended with a cross-fade's source.
    fn relative_pose(&self, db: &Database) -> Pose {
        let mut out = Pose { root: DVec3::ZERO, rotations: Vec::new() };
        self.relative_pose_into(db, &mut out, &mut Pose { root: DVec3::ZERO, rotations: Vec::new() });
        out
    }

    /// [`relative_pose`](Self::relative_pose) into `out`, with `source` for the cross-fade's
    /// source pose (both reused without allocating).
    fn relative_pose_into(&self, db: &Database, out: &mut Pose, source: &mut Pose) {
        let iv = &db.intervals[self.interval];
        db.relative_pose_into(iv.clip, self.frame, out);
        if let Some(s) = &self.source {
            db.relative_pose_into(s.clip, s.frame, source);
            out.blend_after(source, self.weight());
        }
    }

    /// Appends to `out` the world positions of the root over the rest of the interval playing,
    /// starting with where it is: every few frames while blending, then at the interval's
    /// sweep frames ([`Database::sweep_frames`]) — consecutive points at most about
    /// [`super::db::SWEEP_SPACING_M`] apart — ending at its end.
    fn path(mut self, db: &Database, h: f64, out: &mut Vec<DVec2>) -> Ground {
        out.push(DVec2::new(self.world.x, self.world.y));
        let end = db.intervals[self.interval].end as f64;
        let mut k = 0;
        while self.source.is_some() && self.frame < end - 1e-9 {
            self.advance_by(db, h);
            k += 1;
            if k % BLEND_PATH_EVERY == 0 || self.source.is_none() {
                out.push(DVec2::new(self.world.x, self.world.y));
            }
        }
        let iv = &db.intervals[self.interval];
        let (mut world, mut frame) = (self.world, self.frame);
        // On a kept frame (or the start), the motion to the next one is the database's.
        let mut kept = frame == iv.start as f64;
        for (&f, &(step, share)) in db.sweep_frames(self.interval).iter().zip(db.sweep_steps(self.interval)) {
            if (f as f64) > frame + 1e-9 {
                let (d, share) = if kept {
                    (step, share)
                } else {
                    let at = db.ground(iv.clip, frame);
                    (at.to_local(db.ground(iv.clip, f as f64)), db.bend_share(self.interval, frame, f as f64))
                };
                world = world.then(self.warp.apply(d, share));
                frame = f as f64;
                kept = true;
                out.push(DVec2::new(world.x, world.y));
            } else {
                kept = (f as f64) == frame;
            }
        }
        world
    }
}

/// A switch point: the interval ending, the character's ground reference there, and the root
/// motion state from which any candidate's path can be predicted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwitchPoint {
    /// The interval that ends (or, for an early switch, is cut short).
    pub ending: usize,
    /// The character's ground reference at the switch, world.
    pub ground: Ground,
    /// True for an early switch in the middle of an interval.
    pub early: bool,
    /// The feet on the ground at the switch: which point (0 heel, 1 toe) is held and where
    /// (world, horizontal).
    pub planted: [Option<(usize, DVec2)>; 2],
    root: RootMotion,
    blend_s: f64,
    h: f64,
}

impl SwitchPoint {
    /// The warp of the interval ending here.
    pub fn warp(&self) -> Warp {
        self.root.warp
    }

    /// The warp that brings candidate `choice` started here closest to turning by `direction`
    /// radians (the desired heading less the heading here) at `speed` m/s, within `limits`
    /// ([`Warp::toward`]).
    pub fn warp_toward(&self, db: &Database, choice: usize, direction: f64, speed: f64, limits: &WarpLimits) -> Warp {
        let next = db.candidates[self.ending][choice].interval;
        Warp::toward(&db.intervals[next], db.kinds[next], direction, speed, limits)
    }

    fn started(&self, db: &Database, choice: Choice) -> RootMotion {
        let (choice, warp) = (choice.candidate, choice.warp);
        let c = &db.candidates[self.ending][choice];
        let mut r = self.root;
        r.begin(db, c.interval, if c.seamless && !self.early { 0.0 } else { self.blend_s }, warp);
        r
    }

    /// Appends to `out` the world path of the root if candidate `choice` (an index into
    /// `db.candidates[self.ending]`) starts here: the switch point first, then points at most
    /// about [`super::db::SWEEP_SPACING_M`] apart to its end, the cross-fade included — the
    /// path playback would take. Returns the switch point where it ends (as [`Self::then`]
    /// gives it, the end taken from the path's points).
    pub fn path(&self, db: &Database, choice: Choice, out: &mut Vec<DVec2>) -> SwitchPoint {
        let started = self.started(db, choice);
        let end = started.path(db, self.h, out);
        let iv = &db.intervals[started.interval];
        if started.source.is_some() && (iv.end - iv.start) as f64 * db.clips[iv.clip].frame_time <= self.blend_s {
            // A blend outlasting the interval: played frame by frame.
            return self.then(db, choice);
        }
        self.ended(
            db,
            RootMotion {
                interval: started.interval,
                frame: iv.end as f64,
                clip_ground: db.ground(iv.clip, iv.end as f64),
                world: end,
                source: None,
                warp: started.warp,
            },
        )
    }

    /// The switch point where `root` (at the end of its interval) ends up.
    fn ended(&self, db: &Database, root: RootMotion) -> SwitchPoint {
        SwitchPoint {
            ending: root.interval,
            ground: root.world,
            early: false,
            planted: planted_at(db.feet_at(root.interval, true), root.world),
            root,
            blend_s: self.blend_s,
            h: self.h,
        }
    }

    /// The world poses playback would show every `h` seconds if candidate `choice` starts
    /// here, into `out`: the switch point first, then to the end of the candidate's interval
    /// (cross-fades blended as playback blends them; foot locking, which moves only the feet,
    /// left out), then `extra_s` seconds more in its last pose, going on straight ahead at its
    /// end heading at the interval's mean speed or `min_speed` if faster (the character may
    /// walk on faster after a slow interval) — the motion the upper-body planner looks ahead
    /// over.
    /// Returns how many of the poses lie within the interval.
    pub fn poses(&self, db: &Database, choice: Choice, extra_s: f64, min_speed: f64, out: &mut Vec<Pose>) -> usize {
        let mut root = self.started(db, choice);
        let iv = &db.intervals[root.interval];
        let ft = db.clips[iv.clip].frame_time;
        let end = iv.end as f64;
        let pose_of = |root: &RootMotion| root.relative_pose(db);
        let place = |mut rel: Pose, at: Ground| {
            at.transform_pose(&mut rel, false);
            rel
        };
        out.clear();
        out.push(place(pose_of(&root), root.world));
        while root.frame < end - 1e-9 {
            root.advance_by(db, self.h.min((end - root.frame) * ft));
            out.push(place(pose_of(&root), root.world));
        }
        let own = out.len();
        let extra = (extra_s / self.h).round().max(0.0) as usize;
        if extra > 0 {
            let last = pose_of(&root);
            let (a, b) = (db.ground(iv.clip, iv.start as f64), db.ground(iv.clip, end));
            let span = (end - iv.start as f64) * ft;
            let d = root.warp.apply(a.to_local(b), 1.0);
            let rate = if span > 0.0 { 1.0 / span } else { 0.0 };
            let length = d.x.hypot(d.y);
            let at_least = min_speed.max(0.0) * span;
            // Straight on at the interval's end heading: the navigation steers the character
            // along its way, so neither a turn nor a step's sideways sway goes on (carried on
            // for a second, either would put the look-ahead off a narrow way the character
            // keeps to).
            let travel = if length > 0.0 || !db.kinds[root.interval].in_place { length.max(at_least) } else { 0.0 };
            for k in 1..=extra {
                let s = k as f64 * self.h * rate;
                let at = root.world.then(Ground { x: travel * s, y: 0.0, yaw: 0.0 });
                out.push(place(last.clone(), at));
            }
        }
        own
    }

    /// The switch point at the end of candidate `choice` started here: where the next choice
    /// after it would be made, with any blend still running.
    pub fn then(&self, db: &Database, choice: Choice) -> SwitchPoint {
        let mut root = self.started(db, choice);
        let iv = &db.intervals[root.interval];
        let ft = db.clips[iv.clip].frame_time;
        while root.frame < iv.end as f64 - 1e-9 {
            root.advance_by(db, self.h.min((iv.end as f64 - root.frame) * ft));
        }
        self.ended(db, root)
    }

    /// How far the start pose of candidate `choice` would put a foot planted now from where it
    /// is held (the largest over the feet planted in both), metres: what foot locking must
    /// bridge.
    pub fn reach_gap(&self, db: &Database, choice: usize) -> f64 {
        let start = db.feet_at(db.candidates[self.ending][choice].interval, false);
        let mut gap = 0.0f64;
        for (f, held) in self.planted.iter().enumerate() {
            if let Some((k, at)) = held
                && start.bits & (contact_bit(f, 0) | contact_bit(f, 1)) != 0
            {
                let p = self.ground.then(Ground { x: start.points[f][*k].x, y: start.points[f][*k].y, yaw: 0.0 });
                gap = gap.max(DVec2::new(p.x, p.y).distance(*at));
            }
        }
        gap
    }
}

/// The feet `feet` (in the ground frame `g`) holds on the ground, in the world.
fn planted_at(feet: &super::db::FeetAt, g: Ground) -> [Option<(usize, DVec2)>; 2] {
    [0, 1].map(|f| {
        (feet.bits & (contact_bit(f, 0) | contact_bit(f, 1)) != 0).then(|| {
            let k = usize::from(feet.points[f][1].z < feet.points[f][0].z);
            let p = g.then(Ground { x: feet.points[f][k].x, y: feet.points[f][k].y, yaw: 0.0 });
            (k, DVec2::new(p.x, p.y))
        })
    })
}

/// A decision at a switch point: the candidate to play next (an index into
/// `db.candidates[at.ending]`) and the warp it plays with.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Choice {
    /// Index of the candidate.
    pub candidate: usize,
    /// Its warp.
    pub warp: Warp,
}

impl From<usize> for Choice {
    /// Candidate `candidate` as recorded.
    fn from(candidate: usize) -> Choice {
        Choice { candidate, warp: Warp::NONE }
    }
}

/// What the player decides at a switch point.
pub trait Chooser {
    /// Picks a candidate and its warp.
    fn choose(&mut self, db: &Database, at: &SwitchPoint) -> Choice;
}

/// Always the natural successor.
pub struct Natural;

impl Chooser for Natural {
    fn choose(&mut self, _: &Database, _: &SwitchPoint) -> Choice {
        Choice::from(0)
    }
}

#[derive(Debug, Clone)]
struct Inertial {
    /// Per joint: offset (scaled axis) and its rate at the switch; index 0 also root height.
    x0: Vec<DVec3>,
    v0: Vec<DVec3>,
    z0: f64,
    zv0: f64,
    elapsed: f64,
}

/// The lock of one foot.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct FootLock {
    /// On the ground now (by the database's contacts).
    down: bool,
    /// Contact point held: 0 heel, 1 toe.
    pivot: usize,
    /// Where the held point stays, world (horizontal).
    anchor: DVec2,
    /// Horizontal correction added to the animated ankle, world.
    correction: DVec2,
    /// Correction at lift-off and time since, while it fades out.
    fading: Option<(DVec2, f64)>,
    /// Slide of the current plant so far, centimetres.
    slide_cm: f64,
    /// Heading of the foot (heel to toe) when it touched down, radians.
    yaw0: f64,
}

/// A planted foot whose heading turns more than this while its heel is down pivots on its toe
/// with the heel lifted, radians (2°)…
const LIFT_FROM_RAD: f64 = 2.0 * std::f64::consts::PI / 180.0;
/// …fully lifted once it has turned this much more, radians (4°)…
const LIFT_SPAN_RAD: f64 = 4.0 * std::f64::consts::PI / 180.0;
/// …to this height of the heel above the toe, metres.
const LIFT_HEEL_M: f64 = 0.03;

/// Plays intervals with transitions and root motion.
#[derive(Debug, Clone)]
pub struct Player {
    /// Parameters.
    pub params: PlayerParams,
    root: RootMotion,
    inertial: Option<Inertial>,
    rel: Pose,
    /// Room for a cross-fade's source pose.
    source_pose: Pose,
    pose: Pose,
    globals: Vec<(DVec3, DQuat)>,
    history: Vec<Vec<DVec3>>,
    recent_jerk: Vec<f64>,
    since_switch: Option<usize>,
    points_prev: Option<[[DVec3; 2]; 2]>,
    locks: [FootLock; 2],
    /// Measurements so far.
    pub metrics: PlaybackMetrics,
    /// Foot plants so far.
    pub footprints: Vec<Footprint>,
    /// Intervals played, in order, with the switch time in frames.
    pub played: Vec<(u64, usize)>,
}

impl Player {
    /// A player starting interval `interval` with its start on `at` (the character's ground
    /// reference in the world).
    pub fn new(db: &Database, interval: usize, at: Ground, params: PlayerParams) -> Player {
        let iv = &db.intervals[interval];
        let rel = db.relative_pose(iv.clip, iv.start as f64);
        let mut p = Player {
            params,
            root: RootMotion {
                interval,
                frame: iv.start as f64,
                clip_ground: db.ground(iv.clip, iv.start as f64),
                world: at,
                source: None,
                warp: Warp::NONE,
            },
            inertial: None,
            pose: rel.clone(),
            source_pose: rel.clone(),
            rel,
            globals: Vec::new(),
            history: Vec::new(),
            recent_jerk: Vec::new(),
            since_switch: None,
            points_prev: None,
            locks: [FootLock::default(); 2],
            metrics: PlaybackMetrics::default(),
            footprints: Vec::new(),
            played: vec![(0, interval)],
        };
        p.compose(db);
        p
    }

    /// The interval playing.
    pub fn interval(&self) -> usize {
        self.root.interval
    }

    /// The warp of the interval playing.
    pub fn warp(&self) -> Warp {
        self.root.warp
    }

    /// Plays the rest of the interval playing with `warp` instead (what is played stays).
    pub fn rewarp(&mut self, warp: Warp) {
        self.root.warp = warp;
    }

    /// Appends to `out` the world path of the root over the rest of the interval playing if it
    /// went on with `warp` (see [`SwitchPoint::path`]).
    pub fn remaining_path_with(&self, db: &Database, warp: Warp, out: &mut Vec<DVec2>) -> Ground {
        let mut root = self.root;
        root.warp = warp;
        root.path(db, 1.0 / self.params.frame_rate, out)
    }

    /// Seconds into the interval playing.
    pub fn time_in_interval(&self, db: &Database) -> f64 {
        let iv = &db.intervals[self.root.interval];
        (self.root.frame - iv.start as f64) * db.clips[iv.clip].frame_time
    }

    /// Seconds left until the interval playing reaches its switch point.
    pub fn time_to_switch(&self, db: &Database) -> f64 {
        let iv = &db.intervals[self.root.interval];
        (iv.end as f64 - self.root.frame).max(0.0) * db.clips[iv.clip].frame_time
    }

    /// The character's ground reference in the world.
    pub fn ground(&self) -> Ground {
        self.root.world
    }

    /// The current pose in the world.
    pub fn pose(&self) -> &Pose {
        &self.pose
    }

    /// True while a transition is blending.
    pub fn blending(&self) -> bool {
        self.root.source.is_some() || self.inertial.is_some()
    }

    /// Appends to `out` the world path of the root over the rest of the interval playing (see
    /// [`SwitchPoint::path`]).
    pub fn remaining_path(&self, db: &Database, out: &mut Vec<DVec2>) {
        let _ = self.remaining_path_with(db, self.root.warp, out);
    }

    /// The switch point an early switch made now would start from.
    pub fn switch_point_now(&self) -> SwitchPoint {
        SwitchPoint {
            ending: self.root.interval,
            ground: self.root.world,
            early: true,
            planted: self.planted(),
            root: self.root,
            blend_s: self.blend_time(true),
            h: 1.0 / self.params.frame_rate,
        }
    }

    /// The switch point at the end of the interval playing (where the next choice will be made).
    pub fn upcoming_switch(&self, db: &Database) -> SwitchPoint {
        let h = 1.0 / self.params.frame_rate;
        let mut root = self.root;
        let iv = &db.intervals[root.interval];
        let ft = db.clips[iv.clip].frame_time;
        root.advance_by(db, ((iv.end as f64 - root.frame) * ft).max(0.0));
        SwitchPoint {
            ending: root.interval,
            ground: root.world,
            early: false,
            planted: planted_at(db.feet_at(root.interval, true), root.world),
            root,
            blend_s: self.blend_time(false),
            h,
        }
    }

    /// The feet held on the ground now: the held point and where it is held.
    fn planted(&self) -> [Option<(usize, DVec2)>; 2] {
        self.locks.map(|l| l.down.then_some((l.pivot, l.anchor)))
    }

    fn blend_time(&self, early: bool) -> f64 {
        match self.params.transition {
            TransitionKind::CrossFade if early => self.params.early_blend_s,
            TransitionKind::CrossFade => self.params.blend_s,
            TransitionKind::Inertialize => 0.0,
        }
    }

    /// Cuts the interval playing short and starts candidate `choice` of it now, with the short
    /// blend of an early switch. Planted feet stay locked.
    pub fn switch_now(&mut self, db: &Database, choice: Choice) {
        let ending = self.root.interval;
        let c = db.candidates[ending][choice.candidate.min(db.candidates[ending].len() - 1)];
        let src = self.rel.clone();
        let src_next = {
            let iv = &db.intervals[ending];
            let ft = db.clips[iv.clip].frame_time;
            let last = (db.clips[iv.clip].frames.len() - 1) as f64;
            db.relative_pose(iv.clip, (self.root.frame + 1.0 / (self.params.frame_rate * ft)).min(last))
        };
        self.metrics.early_switches += 1;
        self.metrics.switches += 1;
        let blend = self.blend_time(true);
        self.root.begin(db, c.interval, blend, choice.warp);
        self.transition(db, c.interval, &src, &src_next);
        self.refresh_pose(db);
        self.compose(db);
    }

    /// Puts the root back where it was (a safety stop: where the motion led is not free);
    /// planted feet stay locked, so nothing jumps.
    pub fn hold(&mut self, db: &Database, at: Ground) {
        self.root.world = at;
        self.compose(db);
    }

    /// Plays one frame (`1 / frame_rate` seconds), asking `chooser` at switch points.
    pub fn advance_frame(&mut self, db: &Database, chooser: &mut dyn Chooser) {
        let h = 1.0 / self.params.frame_rate;
        let blend_s = self.blend_time(false);
        let mut seamless = true;
        let before = self.root;
        let planted = self.planted();
        let switched = self.root.step(db, h, &mut |root| {
            let point = SwitchPoint {
                ending: root.interval,
                ground: root.world,
                early: false,
                planted,
                root: *root,
                blend_s,
                h,
            };
            let cands = &db.candidates[root.interval];
            let choice = chooser.choose(db, &point);
            let c = cands[choice.candidate.min(cands.len() - 1)];
            seamless = c.seamless;
            (c.interval, if c.seamless { 0.0 } else { blend_s }, choice.warp)
        });
        if let Some((ending, next)) = switched {
            self.metrics.switches += 1;
            if seamless {
                self.played.push((self.metrics.frames, next));
            } else {
                let iv = &db.intervals[ending];
                let ft = db.clips[iv.clip].frame_time;
                let last = (db.clips[iv.clip].frames.len() - 1) as f64;
                let src = db.relative_pose(iv.clip, iv.end as f64);
                let src_next = db.relative_pose(iv.clip, (iv.end as f64 + h / ft).min(last));
                let _ = before;
                self.transition(db, next, &src, &src_next);
            }
        }
        self.refresh_pose(db);
        self.metrics.frames += 1;
        self.compose(db);
    }

    /// Bookkeeping of a transition to `next` from the pose `src` (and the one a frame later,
    /// `src_next`): cost, jerk window, and the inertialization offsets.
    fn transition(&mut self, db: &Database, next: usize, src: &Pose, src_next: &Pose) {
        let h = 1.0 / self.params.frame_rate;
        let nv = &db.intervals[next];
        let dst = db.relative_pose(nv.clip, nv.start as f64);
        self.metrics.transitions += 1;
        self.metrics.transition_cost += db.pose_distance(src, &dst);
        self.since_switch = Some(0);
        if let Some(&j) = self.recent_jerk.iter().max_by(|a, b| a.total_cmp(b)) {
            self.metrics.peak_switch_jerk = self.metrics.peak_switch_jerk.max(j);
        }
        self.played.push((self.metrics.frames, next));
        self.inertial = None;
        if self.params.transition == TransitionKind::Inertialize {
            let dst1 = db.relative_pose(nv.clip, nv.start as f64 + h / db.clips[nv.clip].frame_time);
            let off = |a: &Pose, b: &Pose| -> Vec<DVec3> {
                a.rotations
                    .iter()
                    .zip(&b.rotations)
                    .map(|(&qa, &qb)| shortest(qa * qb.inverse()).to_scaled_axis())
                    .collect()
            };
            let x0 = off(src, &dst);
            let x1 = off(src_next, &dst1);
            let v0 = x0.iter().zip(&x1).map(|(a, b)| (*b - *a) / h).collect();
            let z0 = src.root.z - dst.root.z;
            let zv0 = ((src_next.root.z - dst1.root.z) - z0) / h;
            self.inertial = Some(Inertial { x0, v0, z0, zv0, elapsed: -h });
        }
    }

    /// The relative pose of this frame: the destination, blended with a cross-fade's source or
    /// offset by inertialization.
    fn refresh_pose(&mut self, db: &Database) {
        let h = 1.0 / self.params.frame_rate;
        self.root.relative_pose_into(db, &mut self.rel, &mut self.source_pose);
        if let Some(k) = &mut self.inertial {
            k.elapsed += h;
            let y = 2.0 * std::f64::consts::LN_2 / self.params.halflife_s;
            let t = k.elapsed;
            let decay = (-y * t).exp();
            for (i, q) in self.rel.rotations.iter_mut().enumerate() {
                let x = (k.x0[i] + (k.v0[i] + k.x0[i] * y) * t) * decay;
                *q = (DQuat::from_scaled_axis(x) * *q).normalize();
            }
            self.rel.root.z += (k.z0 + (k.zv0 + k.z0 * y) * t) * decay;
            if t > 6.0 * self.params.halflife_s {
                self.inertial = None;
            }
        }
    }

    /// Which feet the database has on the ground now: the destination's contacts, or during a
    /// cross-fade the side with the larger weight.
    fn contacts_now(&self, db: &Database) -> u8 {
        let iv = &db.intervals[self.root.interval];
        let dst = db.contacts(iv.clip, self.root.frame);
        match &self.root.source {
            Some(s) if self.root.weight() < 0.5 => db.contacts(s.clip, s.frame),
            _ => dst,
        }
    }

    /// World pose from the relative pose, foot locking, then the measurements of this frame.
    fn compose(&mut self, db: &Database) {
        self.pose.clone_from(&self.rel);
        self.root.world.transform_pose(&mut self.pose, false);
        db.skeleton.globals(&self.pose, &mut self.globals);
        let h = 1.0 / self.params.frame_rate;
        let bits = self.contacts_now(db);
        let points = point_positions(&self.globals, db.feet, &db.contact_points);
        let mut changed = [false; 2];
        for (f, pts) in points.iter().enumerate() {
            let down = bits & (contact_bit(f, 0) | contact_bit(f, 1)) != 0;
            let height = |k: usize| pts[k].z - db.point_floor[f][k];
            let (heel, toe) = (pts[0], pts[1]);
            let along = (toe - heel).truncate();
            let yaw = along.y.atan2(along.x);
            let lock = &mut self.locks[f];
            // A turn of the planted foot: pivot on the toe with the heel lifted, as a person
            // does (the actor's hip cannot turn the foot on the ground).
            let mut lift = None;
            if down {
                let lower = usize::from(height(1) < height(0));
                if !lock.down {
                    // Touch-down: hold the lower point where it is (plus any correction still
                    // fading from the last plant, so nothing jumps).
                    let c = lock.fading.map_or(DVec2::ZERO, |(c, t)| c * (1.0 - t / self.params.release_s).max(0.0));
                    *lock = FootLock {
                        down: true,
                        pivot: lower,
                        anchor: pts[lower].truncate() + c,
                        correction: c,
                        fading: None,
                        slide_cm: 0.0,
                        yaw0: yaw,
                    };
                    let ankle = self.globals[db.feet[f]].0;
                    self.footprints.push(Footprint {
                        x: ankle.x + c.x,
                        y: ankle.y + c.y,
                        yaw: self.root.world.yaw,
                        foot: f as u8,
                    });
                }
                let turned = wrap_angle(yaw - lock.yaw0).abs();
                let u = smoothstep((turned - LIFT_FROM_RAD) / LIFT_SPAN_RAD);
                let flat = height(1) < height(0) + 0.01;
                let pivot = if u > 0.0 && flat { 1 } else { lower };
                if pivot != lock.pivot && (u > 0.0 || (height(lock.pivot) - height(lower)) > 0.003) {
                    // The foot rolls onto its other point: hold that one from here on.
                    lock.anchor = pts[pivot].truncate() + lock.correction;
                    lock.pivot = pivot;
                }
                lock.correction = lock.anchor - pts[lock.pivot].truncate();
                if u > 0.0 && flat {
                    lift = heel_lift(heel, toe, u);
                }
            } else if lock.down {
                self.metrics.plants += 1;
                if lock.slide_cm >= PERCEPTIBLE_SLIDE_CM {
                    self.metrics.sliding_plants += 1;
                }
                *lock = FootLock { fading: Some((lock.correction, 0.0)), ..FootLock::default() };
            } else if let Some((c, t)) = lock.fading {
                let t = t + h;
                lock.fading = (t < self.params.release_s).then_some((c, t));
                lock.correction = c * (1.0 - smoothstep(t / self.params.release_s));
            } else {
                lock.correction = DVec2::ZERO;
            }
            if self.params.foot_locking && (lock.correction.length_squared() > 1e-12 || lift.is_some()) {
                let (ankle, q) = self.globals[db.feet[f]];
                let (target, rot) = match lift {
                    Some(r) => (toe + r * (ankle - toe), r * q),
                    None => (ankle, q),
                };
                let mut target = target + lock.correction.extend(0.0);
                leg_ik(db, &mut self.pose, &self.globals, db.feet[f], target, rot);
                // A leg that cannot twist turns its foot as the hip lets it, not as asked: the
                // held point is then put back where it is held, moving the ankle by what it missed.
                if lock.down {
                    for _ in 0..HELD_POINT_PASSES {
                        // The held point as `point_positions` puts it, from the foot's own chain.
                        let (ankle, q) = db.skeleton.global_of(&self.pose, db.feet[f]);
                        let now = ankle + q * db.contact_points[f][lock.pivot];
                        let miss = lock.anchor - now.truncate();
                        if miss.length_squared() < 1e-8 {
                            break;
                        }
                        target += miss.extend(0.0);
                        leg_ik(db, &mut self.pose, &self.globals, db.feet[f], target, rot);
                    }
                }
                changed[f] = true;
            }
        }
        // Foot locking turned only the joints of a leg's hip, knee and ankle.
        for f in 0..2 {
            if changed[f] {
                let joints = db.skeleton.joints();
                let hip = joints[db.feet[f]].parent.and_then(|knee| joints[knee].parent).unwrap_or(0);
                db.skeleton.globals_below(&self.pose, hip, &mut self.globals);
            }
        }
        self.measure(db, h);
    }

    fn measure(&mut self, db: &Database, h: f64) {
        // Skating at the heel and toe points.
        let points = point_positions(&self.globals, db.feet, &db.contact_points);
        if let Some(prev) = self.points_prev {
            for f in 0..2 {
                let mut frame_slide = 0.0f64;
                for k in 0..2 {
                    let height = points[f][k].z - db.point_floor[f][k];
                    if height < CONTACT_HEIGHT_M {
                        let w = 2.0 - (height.max(0.0) / CONTACT_HEIGHT_M).exp2();
                        let d = (points[f][k] - prev[f][k]).truncate().length() * 100.0;
                        self.metrics.skate_weighted_cm += w * d;
                        self.metrics.contact_weight += w;
                        frame_slide = frame_slide.max(w * d);
                    }
                }
                if self.locks[f].down {
                    self.locks[f].slide_cm += frame_slide;
                }
            }
        }
        self.points_prev = Some(points);
        // Joint jerk by third differences of world positions.
        // The oldest of four frames makes room for this one.
        let mut positions = if self.history.len() >= 4 { self.history.remove(0) } else { Vec::new() };
        positions.clear();
        positions.extend(self.globals.iter().map(|g| g.0));
        self.history.push(positions);
        if self.history.len() == 4 {
            let [a, b, c, d] = [&self.history[0], &self.history[1], &self.history[2], &self.history[3]];
            let mut peak = 0.0f64;
            for i in 0..a.len() {
                let j = (d[i] - 3.0 * c[i] + 3.0 * b[i] - a[i]) / (h * h * h);
                peak = peak.max(j.length());
            }
            self.metrics.peak_jerk = self.metrics.peak_jerk.max(peak);
            let window = (JERK_WINDOW_S * self.params.frame_rate).round() as usize;
            self.recent_jerk.push(peak);
            if self.recent_jerk.len() > window {
                self.recent_jerk.remove(0);
            }
            if let Some(n) = self.since_switch {
                self.metrics.peak_switch_jerk = self.metrics.peak_switch_jerk.max(peak);
                self.since_switch = if n + 1 >= window { None } else { Some(n + 1) };
            }
        }
    }
}

/// The rotation about the toe that lifts the heel to `u × LIFT_HEEL_M` above the toe (none when
/// it is that high already).
fn heel_lift(heel: DVec3, toe: DVec3, u: f64) -> Option<DQuat> {
    let v = heel - toe;
    let len = v.length();
    let want = u * LIFT_HEEL_M;
    if len < 1e-6 || v.z >= want {
        return None;
    }
    let phi = (want / len).clamp(-1.0, 1.0).asin() - (v.z / len).clamp(-1.0, 1.0).asin();
    let axis = DVec3::new(-v.y, v.x, 0.0).normalize_or_zero();
    if axis == DVec3::ZERO {
        return None;
    }
    // Turn the way that raises the heel.
    let r = DQuat::from_axis_angle(axis, phi);
    Some(if (r * v).z >= v.z { r } else { DQuat::from_axis_angle(axis, -phi) })
}

/// Two-bone leg IK: puts the ankle `foot` of `pose` (world pose, globals `g`) at `target`
/// (world) by turning its hip and knee, the knee staying in the plane it bends in, and gives the
/// foot the world orientation `foot_rot`. A target out of reach is approached as far as the leg
/// goes.
fn leg_ik(db: &Database, pose: &mut Pose, g: &[(DVec3, DQuat)], foot: usize, target: DVec3, foot_rot: DQuat) {
    let joints = db.skeleton.joints();
    let Some(knee) = joints[foot].parent else { return };
    let Some(hip) = joints[knee].parent else { return };
    let hip_parent_rot = joints[hip].parent.map_or(DQuat::IDENTITY, |p| g[p].1);
    if hinged_leg(&joints[hip], &joints[knee], &joints[foot]) {
        hinged_leg_ik(pose, g, [hip, knee, foot], hip_parent_rot, target, foot_rot, [&joints[knee], &joints[foot]]);
        return;
    }
    let (hp, kp, ap) = (g[hip].0, g[knee].0, g[foot].0);
    let (l1, l2) = ((kp - hp).length(), (ap - kp).length());
    if l1 < 1e-6 || l2 < 1e-6 {
        return;
    }
    let to_t = target - hp;
    let d = to_t.length().clamp((l1 - l2).abs() + 1e-6, l1 + l2 - 1e-6);
    let u = if to_t.length() > 1e-9 { to_t / to_t.length() } else { (ap - hp).normalize_or_zero() };
    // The knee's side: where it is now, off the hip–target line (else forward of the pelvis).
    let mut pole = (kp - hp) - u * (kp - hp).dot(u);
    if pole.length_squared() < 1e-10 {
        pole = g[0].1 * DVec3::X;
        pole -= u * pole.dot(u);
    }
    let pole = pole.normalize_or_zero();
    let a = (l1 * l1 - l2 * l2 + d * d) / (2.0 * d);
    let knee_to = hp + u * a + pole * (l1 * l1 - a * a).max(0.0).sqrt();
    let ankle_to = hp + u * d;
    let hip_rot = DQuat::from_rotation_arc((kp - hp) / l1, (knee_to - hp).normalize()) * g[hip].1;
    let knee_rot0 = hip_rot * pose.rotations[knee];
    let ankle_now = knee_to + knee_rot0 * joints[foot].offset;
    let knee_rot = DQuat::from_rotation_arc(
        (ankle_now - knee_to).normalize_or(DVec3::NEG_Z),
        (ankle_to - knee_to).normalize_or(DVec3::NEG_Z),
    ) * knee_rot0;
    pose.rotations[hip] = (hip_parent_rot.inverse() * hip_rot).normalize();
    pose.rotations[knee] = (hip_rot.inverse() * knee_rot).normalize();
    pose.rotations[foot] = (knee_rot.inverse() * foot_rot).normalize();
}

/// Whether a leg has the channels of the built-in actor's (seed 002 Fig. 1): a hip turning
/// about Y then X, a knee and an ankle about Y, the thigh and the shin along −Z. Such a leg has
/// no twist at the hip, so its IK must not ask for one: a written BVH could not carry it.
fn hinged_leg(hip: &super::skeleton::Joint, knee: &super::skeleton::Joint, foot: &super::skeleton::Joint) -> bool {
    use super::skeleton::Channel::{XRotation, YRotation};
    let down = |o: DVec3| o.z < 0.0 && o.truncate().length() <= 1e-9 * o.length();
    let rotations = |j: &super::skeleton::Joint, want: &[super::skeleton::Channel]| {
        j.channels.iter().copied().filter(|c| !c.is_position()).eq(want.iter().copied())
    };
    rotations(hip, &[YRotation, XRotation])
        && rotations(knee, &[YRotation])
        && rotations(foot, &[YRotation])
        && down(knee.offset)
        && down(foot.offset)
}

/// Two-link IK within a [`hinged_leg`]'s channels: the hip's Y and X angles and the knee's Y
/// angle put the ankle exactly on `target` (the knee bending the way it bends now), and the
/// ankle's Y angle gives the foot the pitch of `foot_rot` (its twist about the ankle's axis).
/// Every rotation is a product of the leg's own channels, so what is shown is what a written
/// BVH file holds.
fn hinged_leg_ik(
    pose: &mut Pose,
    g: &[(DVec3, DQuat)],
    [hip, knee, foot]: [usize; 3],
    pelvis: DQuat,
    target: DVec3,
    foot_rot: DQuat,
    [knee_joint, foot_joint]: [&super::skeleton::Joint; 2],
) {
    let (l1, l2) = (knee_joint.offset.length(), foot_joint.offset.length());
    if l1 < 1e-6 || l2 < 1e-6 {
        return;
    }
    let t = pelvis.inverse() * (target - g[hip].0);
    let d = t.length().clamp((l1 - l2).abs() + 1e-6, l1 + l2 - 1e-6);
    let t = if t.length() > 1e-9 { t * (d / t.length()) } else { DVec3::new(0.0, 0.0, -d) };
    // The knee: its angle from the law of cosines, on the side it bends now (forward: the shin
    // swings back for a positive angle).
    let back = super::skeleton::twist_is_negative(pose.rotations[knee], DVec3::Y);
    let c = ((d * d - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)).clamp(-1.0, 1.0).acos() * if back { -1.0 } else { 1.0 };
    // The ankle in the hip's frame, in its XZ plane; X then Y at the hip take it to the target.
    let (px, pz) = (-l2 * c.sin(), -l1 - l2 * c.cos());
    let b = (-t.y / pz).clamp(-1.0, 1.0).asin();
    let a = t.x.atan2(t.z) - px.atan2(pz * b.cos());
    let hip_rot = DQuat::from_rotation_y(a) * DQuat::from_rotation_x(b);
    let knee_rot = DQuat::from_rotation_y(c);
    let above = pelvis * hip_rot * knee_rot;
    let e = super::skeleton::twist(above.inverse() * foot_rot, DVec3::Y);
    pose.rotations[hip] = hip_rot;
    pose.rotations[knee] = knee_rot;
    pose.rotations[foot] = DQuat::from_rotation_y(e);
}

/// Passes that put a planted foot's held point back after its leg's IK ([`hinged_leg_ik`] turns
/// the foot as the hip lets it).
const HELD_POINT_PASSES: usize = 3;

fn shortest(q: DQuat) -> DQuat {
    if q.w < 0.0 { -q } else { q }
}
