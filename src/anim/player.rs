//! Playing the animation database (seed 000 §3.2, §3.2.2): intervals one after another, the
//! next one picked at each switch point among the candidates, transitions by cross-fade (source
//! weight 1→0, destination 0→1 over a fixed time, started at the start of the destination
//! interval) or by inertialization (the pose offset at the switch decays by a critically damped
//! spring), and root motion integrated frame by frame so the character's path is continuous.
//!
//! The player also measures what a viewer would notice: foot skating (horizontal slide of
//! contact feet, at the foot joint, weighted by `2 − 2^(h/H)` below `H` = 2.5 cm), the pose distance at each
//! switch, peak joint jerk around switches, and footprints.

use glam::{DQuat, DVec3};

use super::clip::Ground;
use super::db::Database;
use super::skeleton::Pose;
use crate::geom::smoothstep;

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
    /// Half-life of the inertialization offset, seconds (0.08).
    pub halflife_s: f64,
    /// Playback frame rate, frames per second (60).
    pub frame_rate: f64,
}

impl Default for PlayerParams {
    fn default() -> Self {
        PlayerParams { transition: TransitionKind::CrossFade, blend_s: 0.2, halflife_s: 0.08, frame_rate: 60.0 }
    }
}

/// Height below which a foot counts as in contact for the skating measure, metres (2.5 cm).
pub const CONTACT_HEIGHT_M: f64 = 0.025;
/// Pose distance (Eq. 1) below which a switch continues the motion seamlessly, needing no
/// transition.
pub const SEAMLESS: f64 = 1e-4;
/// Window around a switch in which joint jerk is watched, seconds.
pub const JERK_WINDOW_S: f64 = 0.25;

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
    /// Σ weight × horizontal slide of contact feet, centimetres.
    pub skate_weighted_cm: f64,
    /// Σ contact weight.
    pub contact_weight: f64,
    /// Switch points passed.
    pub switches: u64,
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
    /// Mean slide of contact feet per frame, centimetres (0 without contact).
    pub fn foot_skating_cm_per_frame(&self) -> f64 {
        if self.contact_weight > 0.0 { self.skate_weighted_cm / self.contact_weight } else { 0.0 }
    }

    /// Mean pose distance at transitions (0 without any).
    pub fn mean_transition_cost(&self) -> f64 {
        if self.transitions > 0 { self.transition_cost / self.transitions as f64 } else { 0.0 }
    }
}

#[derive(Debug, Clone)]
struct Source {
    clip: usize,
    frame: f64,
    elapsed: f64,
    ground: Ground,
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

/// What the player decides at a switch point: given the interval that ends, the index of the
/// candidate (in `db.candidates[interval]`) to play next.
pub trait Chooser {
    /// Picks a candidate.
    fn choose(&mut self, db: &Database, ending: usize, heading: f64) -> usize;
}

/// Always the natural successor.
pub struct Natural;

impl Chooser for Natural {
    fn choose(&mut self, _: &Database, _: usize, _: f64) -> usize {
        0
    }
}

/// Plays intervals with transitions and root motion.
#[derive(Debug, Clone)]
pub struct Player {
    /// Parameters.
    pub params: PlayerParams,
    interval: usize,
    frame: f64,
    /// Ground reference of the destination clip at the current frame (clip coordinates).
    clip_ground: Ground,
    world: Ground,
    source: Option<Source>,
    inertial: Option<Inertial>,
    rel: Pose,
    scratch: Pose,
    pose: Pose,
    globals: Vec<(DVec3, DQuat)>,
    history: Vec<Vec<DVec3>>,
    recent_jerk: Vec<f64>,
    since_switch: Option<usize>,
    feet_prev: [Option<DVec3>; 2],
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
        let ground = db.ground(iv.clip, iv.start as f64);
        let rel = db.relative_pose(iv.clip, iv.start as f64);
        let mut p = Player {
            params,
            interval,
            frame: iv.start as f64,
            clip_ground: ground,
            world: at,
            source: None,
            inertial: None,
            scratch: rel.clone(),
            pose: rel.clone(),
            rel,
            globals: Vec::new(),
            history: Vec::new(),
            recent_jerk: Vec::new(),
            since_switch: None,
            feet_prev: [None, None],
            metrics: PlaybackMetrics::default(),
            footprints: Vec::new(),
            played: vec![(0, interval)],
        };
        p.compose(db);
        p
    }

    /// The interval playing.
    pub fn interval(&self) -> usize {
        self.interval
    }

    /// Seconds into the interval playing.
    pub fn time_in_interval(&self, db: &Database) -> f64 {
        let iv = &db.intervals[self.interval];
        (self.frame - iv.start as f64) * db.clips[iv.clip].frame_time
    }

    /// The character's ground reference in the world.
    pub fn ground(&self) -> Ground {
        self.world
    }

    /// Moves the character's ground reference (root motion corrected by the world).
    pub fn set_ground(&mut self, g: Ground) {
        self.world = g;
    }

    /// The current pose in the world.
    pub fn pose(&self) -> &Pose {
        &self.pose
    }

    /// True while a transition is blending.
    pub fn blending(&self) -> bool {
        self.source.is_some() || self.inertial.is_some()
    }

    /// Plays one frame (`1 / frame_rate` seconds), asking `chooser` at switch points.
    pub fn advance_frame(&mut self, db: &Database, chooser: &mut dyn Chooser) {
        let h = 1.0 / self.params.frame_rate;
        let iv = &db.intervals[self.interval];
        let ft = db.clips[iv.clip].frame_time;
        let mut next_frame = self.frame + h / ft;
        let mut delta;
        if next_frame >= iv.end as f64 - 1e-9 {
            // Switch point: finish this interval, then start the chosen one.
            let over = (next_frame - iv.end as f64).max(0.0) * ft;
            let end_ground = db.ground(iv.clip, iv.end as f64);
            let to_end = self.clip_ground.to_local(end_ground);
            let ending = self.interval;
            let choice = chooser.choose(db, ending, self.world.then(to_end).yaw).min(db.candidates[ending].len() - 1);
            let next = db.candidates[ending][choice].interval;
            let nv = &db.intervals[next];
            // The clip's own next frames, or a start that continues the pose seamlessly (a
            // cyclic clip wrapping around), need no transition.
            let natural = (nv.clip == iv.clip && nv.start == iv.end)
                || db.pose_distance(
                    &db.relative_pose(iv.clip, iv.end as f64),
                    db.samples(next).first().expect("samples"),
                ) < SEAMLESS;
            self.metrics.switches += 1;
            self.played.push((self.metrics.frames, next));
            if !natural {
                self.start_transition(db, ending, next, over);
            }
            self.interval = next;
            let nft = db.clips[nv.clip].frame_time;
            next_frame = nv.start as f64 + over / nft;
            let start_ground = db.ground(nv.clip, nv.start as f64);
            let g = db.ground(nv.clip, next_frame);
            delta = to_end.then(start_ground.to_local(g));
            self.clip_ground = g;
        } else {
            let g = db.ground(iv.clip, next_frame);
            delta = self.clip_ground.to_local(g);
            self.clip_ground = g;
        }
        self.frame = next_frame;
        let iv = &db.intervals[self.interval];
        self.rel = db.relative_pose(iv.clip, self.frame);
        // Blend with the source of a cross-fade: pose and root motion alike.
        if let Some(s) = &mut self.source {
            s.elapsed += h;
            let sft = db.clips[s.clip].frame_time;
            let last = (db.clips[s.clip].frames.len() - 1) as f64;
            s.frame = (s.frame + h / sft).min(last);
            let g = db.ground(s.clip, s.frame);
            let sd = s.ground.to_local(g);
            s.ground = g;
            let w = smoothstep((s.elapsed / self.params.blend_s).min(1.0));
            self.scratch = db.relative_pose(s.clip, s.frame);
            let dst = std::mem::replace(&mut self.rel, self.scratch.clone());
            self.rel.blend_from(&self.scratch, &dst, w);
            delta = Ground {
                x: sd.x + (delta.x - sd.x) * w,
                y: sd.y + (delta.y - sd.y) * w,
                yaw: sd.yaw + crate::geom::wrap_angle(delta.yaw - sd.yaw) * w,
            };
            if s.elapsed >= self.params.blend_s {
                self.source = None;
            }
        }
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
        self.world = self.world.then(delta);
        self.metrics.frames += 1;
        self.compose(db);
    }

    fn start_transition(&mut self, db: &Database, ending: usize, next: usize, over: f64) {
        let iv = &db.intervals[ending];
        let nv = &db.intervals[next];
        let src = db.relative_pose(iv.clip, iv.end as f64);
        let dst = db.relative_pose(nv.clip, nv.start as f64);
        self.metrics.transitions += 1;
        self.metrics.transition_cost += db.pose_distance(&src, &dst);
        self.since_switch = Some(0);
        if let Some(&j) = self.recent_jerk.iter().max_by(|a, b| a.total_cmp(b)) {
            self.metrics.peak_switch_jerk = self.metrics.peak_switch_jerk.max(j);
        }
        let ft = db.clips[iv.clip].frame_time;
        match self.params.transition {
            TransitionKind::CrossFade => {
                let frame = iv.end as f64 + over / ft;
                let last = (db.clips[iv.clip].frames.len() - 1) as f64;
                self.source = Some(Source {
                    clip: iv.clip,
                    frame: frame.min(last) - 1.0 / (self.params.frame_rate * ft),
                    elapsed: -1.0 / self.params.frame_rate,
                    ground: db.ground(iv.clip, (frame.min(last) - 1.0 / (self.params.frame_rate * ft)).max(0.0)),
                });
                self.inertial = None;
            }
            TransitionKind::Inertialize => {
                // Offsets between where the motion was going and where it now starts, and
                // their rates from one frame further on both sides.
                let h = 1.0 / self.params.frame_rate;
                let last = (db.clips[iv.clip].frames.len() - 1) as f64;
                let src1 = db.relative_pose(iv.clip, (iv.end as f64 + h / ft).min(last));
                let nft = db.clips[nv.clip].frame_time;
                let dst1 = db.relative_pose(nv.clip, nv.start as f64 + h / nft);
                let off = |a: &Pose, b: &Pose| -> Vec<DVec3> {
                    a.rotations
                        .iter()
                        .zip(&b.rotations)
                        .map(|(&qa, &qb)| shortest(qa * qb.inverse()).to_scaled_axis())
                        .collect()
                };
                let x0 = off(&src, &dst);
                let x1 = off(&src1, &dst1);
                let v0 = x0.iter().zip(&x1).map(|(a, b)| (*b - *a) / h).collect();
                let z0 = src.root.z - dst.root.z;
                let zv0 = ((src1.root.z - dst1.root.z) - z0) / h;
                self.inertial = Some(Inertial { x0, v0, z0, zv0, elapsed: -h });
                self.source = None;
            }
        }
    }

    /// World pose from the relative pose, then the measurements of this frame.
    fn compose(&mut self, db: &Database) {
        self.pose.clone_from(&self.rel);
        self.world.transform_pose(&mut self.pose, false);
        db.skeleton.globals(&self.pose, &mut self.globals);
        let h = 1.0 / self.params.frame_rate;
        for f in 0..2 {
            // Contact and slide of the foot joint (the ankle), the point the clips plant.
            let p = self.globals[db.feet[f]].0;
            let height = p.z - db.foot_floor[f];
            if let Some(prev) = self.feet_prev[f] {
                if height < CONTACT_HEIGHT_M {
                    let w = 2.0 - (height.max(0.0) / CONTACT_HEIGHT_M).exp2();
                    let slide = ((p.x - prev.x).powi(2) + (p.y - prev.y).powi(2)).sqrt() * 100.0;
                    self.metrics.skate_weighted_cm += w * slide;
                    self.metrics.contact_weight += w;
                    if prev.z - db.foot_floor[f] >= CONTACT_HEIGHT_M {
                        self.footprints.push(Footprint { x: p.x, y: p.y, yaw: self.world.yaw, foot: f as u8 });
                    }
                }
            } else if height < CONTACT_HEIGHT_M {
                self.footprints.push(Footprint { x: p.x, y: p.y, yaw: self.world.yaw, foot: f as u8 });
            }
            self.feet_prev[f] = Some(p);
        }
        // Joint jerk by third differences of world positions.
        let positions: Vec<DVec3> = self.globals.iter().map(|g| g.0).collect();
        self.history.push(positions);
        if self.history.len() > 4 {
            self.history.remove(0);
        }
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

fn shortest(q: DQuat) -> DQuat {
    if q.w < 0.0 { -q } else { q }
}
