//! The motion that poses the actor at any time (seed 002 §4.1 walk generation on level ground,
//! §4 legs planned in the sagittal plane; DESIGN.md §3–4): the path on the ground, the
//! footfalls (where and when each foot is on the ground), the pelvis's progress along the path,
//! its height, heading and sway, the swing foot's Bezier curve, and the upper body.
//!
//! A footfall is one stay of a foot on the ground. The heel touches first (toes up), the foot
//! rolls down about the heel point to flat, stays flat, then the heel rises and the foot rolls
//! over the toe tip until the toe leaves. Whichever point carries the foot — the heel, then the
//! toe tip — stays exactly where it touched: the leg is solved so that this point, not the
//! ankle, is on target.
//!
//! The pelvis height follows the knee: from heel strike to mid-stance the leading leg's knee
//! follows its key frames (nearly straight at heel strike, bent in loading response, nearly
//! straight at mid-stance; deeply bent at mid-stance when running) and the pelvis sits where
//! that knee puts it; from there to the next heel strike a cubic Hermite curve bridges to the
//! height the next leg will take, while the trailing foot's heel rises just enough for its knee
//! to follow its own key frames (heel-off, then toe-off). Walking, the pelvis thus vaults over
//! the straight stance leg, highest near mid-stance and lowest in double support; running, it
//! is lowest at mid-stance and flies in between.
//!
//! The actor's hips cannot twist, so a planted foot turns with the pelvis. The pelvis heading
//! therefore changes only while every planted foot stands on one point with the other one well
//! off the ground — on the heel early in its rocker, on the toe once the heel has risen —
//! and stays still while a foot is flat: the body turns in bursts around the foot plants, and
//! no planted point slides.
//!
//! The swing foot goes from the toe's lift-off point to the next heel strike along a cubic
//! Bezier curve in the sagittal plane of its step (progress, height) whose two inner control
//! points are raised, straight above its ends so that lift-off and touch-down are vertical; on
//! the ground the step bends outward around the stance foot when needed, or toward a chosen
//! point (to step around the other foot on a chosen side).
//!
//! Turning starts and stops pivot on the ball of a foot: its heel is raised on purpose (at
//! least a prescribed pitch) so the body can turn about its toe, the pelvis leaves its path to
//! follow the feet (a drift over time), and the heading eases in and out of each turn the feet
//! allow.

use glam::{DQuat, DVec2, DVec3};

use super::curves::{Bezier, KeyCurve, Ramp, hermite};
use super::gait::Gait;
use super::leg::{FootTarget, MAX_REACH_M, Rig, SIDES, pitch_for_reach, place_leg, reach_of_knee, sole_point};
use super::{FRAME_RATE_HZ, STANDING_PELVIS_M};
use crate::anim::actor::{self, ANKLE_HEIGHT_M, FOOT_FORWARD_M, HEEL_BACK_M, HEEL_POINT, HIP_HALF_WIDTH_M, TOE_POINT};
use crate::anim::clip::{Clip, Ground};
use crate::anim::skeleton::Pose;
use crate::geom::smoothstep;

/// A time before anything happens, seconds: feet planted "forever".
pub(crate) const NEVER_BEFORE: f64 = -1.0e9;
/// A time after everything, seconds.
pub(crate) const NEVER_AFTER: f64 = 1.0e9;

/// Largest toes-down pitch of a planted foot, radians.
const MAX_PITCH_RAD: f64 = 1.3;
/// Pitch of a foot on its toe above which its heel is high enough for the foot to turn about the
/// toe without the heel sweeping the ground, radians (the heel about 3.6 cm up).
const PIVOT_PITCH_RAD: f64 = 0.17;
/// Toes-up pitch of a foot on its heel above which its toe is high enough for the foot to turn
/// about the heel, radians.
const HEEL_PIVOT_PITCH_RAD: f64 = 0.14;
/// Height the toe and heel keep above the ground in mid-swing, metres.
const SWING_CLEARANCE_M: f64 = 0.03;
/// Elbow flexion standing still, radians.
pub(crate) const REST_ELBOW_RAD: f64 = 0.12;
/// Shoulder abduction standing still, radians.
pub(crate) const REST_ARM_ABDUCTION_RAD: f64 = 0.07;
/// Time step of the heading table, seconds.
const YAW_DT: f64 = 1.0 / 480.0;

// ---------------------------------------------------------------------------------------------
// Path and progress

/// `sin x / x`.
fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-6 { 1.0 - x * x / 6.0 } else { x.sin() / x }
}

/// The displacement after `u` metres along a circle arc of curvature `k` starting at heading `h`.
fn advance(h: f64, k: f64, u: f64) -> DVec2 {
    let half = 0.5 * k * u;
    u * sinc(half) * DVec2::from_angle(h + half)
}

/// A path on the ground made of arcs of one step length each (constant curvature within a step),
/// parametrised by arclength; step `k` covers `[k·L, (k+1)·L)`, with `s = 0` at the origin facing
/// +X.
#[derive(Debug, Clone)]
pub(crate) struct Path {
    step: f64,
    first: i64,
    segments: Vec<(DVec2, f64, f64)>,
}

impl Path {
    /// Segment `k` turns by `turns[k]` radians (clamped to the ends of `turns`), covering steps
    /// `-margin .. turns.len() + margin` of `step` metres.
    pub(crate) fn new(step: f64, turns: &[f64], margin: i64) -> Path {
        let n = turns.len() as i64;
        let turn = |k: i64| if turns.is_empty() { 0.0 } else { turns[k.clamp(0, n - 1) as usize] };
        let mut fwd = vec![(DVec2::ZERO, 0.0, turn(0) / step)];
        for k in 0..n + margin {
            let (p, h, c) = fwd[k as usize];
            fwd.push((p + advance(h, c, step), h + c * step, turn(k + 1) / step));
        }
        let mut back = Vec::new();
        let (mut p, mut h) = (DVec2::ZERO, 0.0);
        for k in (-margin..0).rev() {
            let c = turn(k) / step;
            h -= c * step;
            p -= advance(h, c, step);
            back.push((p, h, c));
        }
        back.reverse();
        back.extend(fwd);
        Path { step, first: -margin, segments: back }
    }

    /// A straight path along +X.
    pub(crate) fn straight() -> Path {
        Path::new(1.0, &[0.0], 4)
    }

    /// Point and heading at arclength `s`.
    pub(crate) fn at(&self, s: f64) -> (DVec2, f64) {
        let k = ((s / self.step).floor() as i64).clamp(self.first, self.first + self.segments.len() as i64 - 1);
        let (p, h, c) = self.segments[(k - self.first) as usize];
        let u = s - k as f64 * self.step;
        (p + advance(h, c, u), h + c * u)
    }

    /// The ground point `offset` metres beside the path at arclength `s`, to the left for
    /// `side` = +1 and to the right for −1.
    pub(crate) fn beside(&self, s: f64, side: f64, offset: f64) -> DVec2 {
        let (p, h) = self.at(s);
        p + side * offset * DVec2::from_angle(h).perp()
    }
}

/// Pelvis arclength over time: speed `v0` until `t0`, then a smoothstep change of speed to `v1`
/// over `ramp` seconds, then `v1`; at `t0` the pelvis is at `s0`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Progress {
    pub t0: f64,
    pub s0: f64,
    pub v0: f64,
    pub v1: f64,
    pub ramp: f64,
}

impl Progress {
    /// Constant speed `v`, at `s0` at time 0.
    pub(crate) fn steady(s0: f64, v: f64) -> Progress {
        Progress { t0: 0.0, s0, v0: v, v1: v, ramp: 0.0 }
    }

    /// Arclength at `t`, metres.
    pub(crate) fn at(self, t: f64) -> f64 {
        let dt = t - self.t0;
        if dt <= 0.0 || self.ramp <= 0.0 {
            let v = if dt <= 0.0 { self.v0 } else { self.v1 };
            return self.s0 + v * dt;
        }
        let x = (dt / self.ramp).min(1.0);
        // ∫ smoothstep = x³ − x⁴/2.
        let s = self.s0 + self.v0 * x * self.ramp + (self.v1 - self.v0) * self.ramp * (x * x * x - 0.5 * x * x * x * x);
        s + self.v1 * (dt - self.ramp).max(0.0)
    }
}

// ---------------------------------------------------------------------------------------------
// Footfalls

/// How a planted foot pitches after its support window.
#[derive(Debug, Clone)]
pub(crate) enum Late {
    /// The heel rises just enough for the knee to follow the footfall's knee curve.
    Solve,
    /// A prescribed toes-down pitch over time, radians.
    Pitch(KeyCurve),
    /// At least the prescribed pitch (radians), more where the knee needs it as with
    /// [`Late::Solve`]: a heel raised on purpose, to pivot on the ball of the foot.
    AtLeast(KeyCurve),
}

/// One stay of a foot on the ground.
#[derive(Debug, Clone)]
pub(crate) struct Footfall {
    /// 0 left, 1 right.
    pub side: usize,
    /// Where the ankle stands when the foot is flat, on the ground, metres.
    pub ground: DVec2,
    /// Touch-down, seconds.
    pub t_on: f64,
    /// Toes-up pitch at touch-down, radians (0: the foot lands flat).
    pub strike: f64,
    /// Foot flat, seconds.
    pub t_flat: f64,
    /// End of the footfall's support window (the pelvis height follows its knee until then),
    /// seconds; the late pitch applies from here.
    pub t_release: f64,
    /// Toe-off, seconds.
    pub t_off: f64,
    /// Wanted knee flexion over time, radians.
    pub knee: KeyCurve,
    /// Pitch after `t_release`.
    pub late: Late,
    /// Raise of the inner Bezier control points of the swing ending on this footfall, metres.
    pub swing_height: f64,
    /// Heading of the foot once flat, radians (computed from the pelvis heading unless set).
    pub yaw_flat: Option<f64>,
    /// A ground point the swing ending on this footfall bends toward (the control point of its
    /// quadratic curve on the ground), to go around the other foot on a chosen side; `None`:
    /// straight, bending away from the stance foot only when it passes too close.
    pub via: Option<DVec2>,
    /// When the heel is high enough for the foot to turn about its toe, seconds.
    t_pivot: f64,
}

impl Footfall {
    /// A foot standing flat at `ground` since forever with heading `yaw`, until `t_off` (late
    /// pitch `late` from `t_release`), its knee wanted at `knee`.
    pub(crate) fn standing(
        side: usize,
        ground: DVec2,
        yaw: f64,
        knee: KeyCurve,
        t_release: f64,
        t_off: f64,
        late: Late,
    ) -> Footfall {
        Footfall {
            side,
            ground,
            t_on: NEVER_BEFORE,
            strike: 0.0,
            t_flat: NEVER_BEFORE,
            t_release,
            t_off,
            knee,
            late,
            swing_height: 0.1,
            yaw_flat: Some(yaw),
            via: None,
            t_pivot: NEVER_AFTER,
        }
    }

    /// The footfall of the steady gait `g` touching down at `t_on` with its ankle footprint at
    /// `ground`: heel strike, loading, mid-stance, heel-off and toe-off key frames.
    pub(crate) fn steady(g: &Gait, side: usize, ground: DVec2, t_on: f64) -> Footfall {
        let stance = g.stance_time_s();
        let (flat, release) = if g.is_running() { (0.2, 0.5) } else { (0.17, 0.42) };
        let at = |x: f64| t_on + x * stance;
        let keys: Vec<(f64, f64)> = if g.is_running() {
            vec![(at(0.0), g.knee_strike_rad), (at(0.5), g.knee_load_rad), (at(1.0), g.knee_toe_off_rad)]
        } else {
            let mid = g.knee_mid_rad;
            vec![
                (at(0.0), g.knee_strike_rad),
                (at(0.2), g.knee_load_rad),
                (at(0.42), mid),
                (at(0.62), mid),
                (t_on + g.step_time_s, mid + 0.3 * (g.knee_toe_off_rad - mid)),
                (at(1.0), g.knee_toe_off_rad),
            ]
        };
        Footfall {
            side,
            ground,
            t_on,
            strike: g.heel_strike_rad,
            t_flat: if g.heel_strike_rad > 0.0 { at(flat) } else { t_on },
            t_release: at(release),
            t_off: at(1.0),
            knee: KeyCurve::open(&keys),
            late: Late::Solve,
            swing_height: g.swing_height_m,
            yaw_flat: None,
            via: None,
            t_pivot: NEVER_AFTER,
        }
    }

    fn planted(&self, t: f64) -> bool {
        t >= self.t_on && t <= self.t_off
    }

    /// How freely the foot lets the body turn at `t`: 1 off the ground or on one point with the
    /// other one well up, 0 flat.
    fn turn_freedom(&self, t: f64) -> f64 {
        if !self.planted(t) {
            return 1.0;
        }
        let mut heel = 0.0;
        if self.strike > HEEL_PIVOT_PITCH_RAD && self.t_flat > self.t_on {
            // The toe is up while the pitch, −strike·(1 − smoothstep(x)), stays beyond the limit.
            let limit = 1.0 - HEEL_PIVOT_PITCH_RAD / self.strike;
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..30 {
                let mid = 0.5 * (lo + hi);
                if smoothstep(mid) < limit { lo = mid } else { hi = mid }
            }
            let end = self.t_on + lo * (self.t_flat - self.t_on);
            heel = 1.0 - smoothstep((t - self.t_on) / (end - self.t_on).max(1e-9));
        }
        let toe = smoothstep((t - self.t_pivot) / 0.03);
        heel.max(toe)
    }
}

// ---------------------------------------------------------------------------------------------
// Upper body cycles

/// The periodic key frames of one stride of a gait, as curves over the stride phase (0 = left
/// heel strike, 0.5 = right heel strike).
#[derive(Debug, Clone)]
pub(crate) struct Cycle {
    /// Pelvis lateral offset toward the left, metres.
    sway: KeyCurve,
    /// Left shoulder flexion (Y rotation), radians; the right one is half a stride later.
    arm: KeyCurve,
    /// Left elbow flexion, radians (positive bends).
    elbow: KeyCurve,
    /// Waist twist (Z rotation), radians.
    twist: KeyCurve,
    lean: f64,
}

impl Cycle {
    pub(crate) fn of(g: &Gait) -> Cycle {
        // Mid-stance of the left foot, in stride phase.
        let mid = 0.5 * g.duty_factor;
        // The arms pass each other when the legs do, at mid-stance, and are furthest apart a
        // quarter of a stride earlier and later.
        let lag = mid - 0.25;
        let (a, off) = (g.arm_swing_rad, -0.15 * g.arm_swing_rad);
        Cycle {
            sway: KeyCurve::periodic(&[(mid, g.sway_m), (mid + 0.25, 0.0), (mid + 0.5, -g.sway_m), (mid + 0.75, 0.0)]),
            // Left heel strike (left leg forward): left arm back (positive Y), right arm forward.
            arm: KeyCurve::periodic(&[(lag, off + a), (lag + 0.25, off), (lag + 0.5, off - a), (lag + 0.75, off)]),
            elbow: KeyCurve::periodic(&[(lag, g.elbow_rad), (lag + 0.5, g.elbow_rad + 0.5 * a)]),
            // Left heel strike: the right shoulder forward, the chest turned to the left.
            twist: KeyCurve::periodic(&[
                (lag, g.twist_rad),
                (lag + 0.25, 0.0),
                (lag + 0.5, -g.twist_rad),
                (lag + 0.75, 0.0),
            ]),
            lean: g.lean_rad,
        }
    }
}

/// A gait's upper-body cycle weighed in over time.
#[derive(Debug, Clone)]
pub(crate) struct Layer {
    pub cycle: Cycle,
    /// A time of a left heel strike, seconds.
    pub origin: f64,
    /// Stride time, seconds.
    pub stride: f64,
    pub weight: Ramp,
}

impl Layer {
    pub(crate) fn new(g: &Gait, origin: f64, weight: Ramp) -> Layer {
        Layer { cycle: Cycle::of(g), origin, stride: 2.0 * g.step_time_s, weight }
    }

    fn phase(&self, t: f64) -> f64 {
        (t - self.origin) / self.stride
    }
}

// ---------------------------------------------------------------------------------------------
// The motion

/// Where the pelvis height comes from during a window.
#[derive(Debug, Clone)]
pub(crate) enum Height {
    /// The knee curve of footfall `k` (index into the motion's footfalls).
    Leg(usize),
    /// A curve over time, metres.
    Level(KeyCurve),
}

/// A stretch of time over which the pelvis height has one source; between windows a cubic
/// Hermite curve bridges values and slopes.
#[derive(Debug, Clone)]
pub(crate) struct Window {
    pub t0: f64,
    pub t1: f64,
    pub height: Height,
}

/// The pelvis heading over time, turning only while the feet allow it.
#[derive(Debug, Clone)]
struct YawTable {
    t0: f64,
    /// Cumulative turn freedom, seconds.
    cum: Vec<f64>,
    /// (time, cumulative freedom, heading) where every planted foot is flat.
    anchors: Vec<(f64, f64, f64)>,
}

/// Everything that poses the actor at any time of one clip.
#[derive(Debug, Clone)]
pub(crate) struct Motion {
    pub path: Path,
    pub progress: Progress,
    /// Extra heading over time (turning on the spot), radians.
    pub turn: KeyCurve,
    /// Extra lateral pelvis shift toward its left over time (weight shifts), metres.
    pub shift: KeyCurve,
    /// Extra forward lean of the waist over time (breathing), radians.
    pub lean: KeyCurve,
    /// Extra displacement of the pelvis over time along the world X and Y axes, metres: where
    /// the pelvis leaves its path (settling between feet placed off the path).
    pub drift: [KeyCurve; 2],
    pub feet: Vec<Footfall>,
    pub windows: Vec<Window>,
    pub layers: Vec<Layer>,
    /// Whether the heading eases in and out of each turn the feet let it make (a smoothstep of
    /// the turn's progress) rather than turning at a steady rate while they let it.
    pub ease: bool,
    yaw: Option<YawTable>,
}

impl Motion {
    pub(crate) fn new(
        path: Path,
        progress: Progress,
        feet: Vec<Footfall>,
        windows: Vec<Window>,
        layers: Vec<Layer>,
    ) -> Motion {
        Motion {
            path,
            progress,
            turn: KeyCurve::constant(0.0),
            shift: KeyCurve::constant(0.0),
            lean: KeyCurve::constant(0.0),
            drift: [KeyCurve::constant(0.0), KeyCurve::constant(0.0)],
            feet,
            windows,
            layers,
            ease: false,
            yaw: None,
        }
    }

    /// The heading the pelvis is asked to take: the path's plus the extra turn, radians.
    fn heading_goal(&self, t: f64) -> f64 {
        self.path.at(self.progress.at(t)).1 + self.turn.at(t)
    }

    /// The pelvis heading at `t`, radians.
    pub(crate) fn yaw(&self, t: f64) -> f64 {
        let Some(table) = &self.yaw else { return self.heading_goal(t) };
        let a = &table.anchors;
        if a.is_empty() || t <= a[0].0 || t >= a[a.len() - 1].0 {
            return self.heading_goal(t);
        }
        let k = a.partition_point(|x| x.0 <= t) - 1;
        let (t0, c0, h0) = a[k];
        let (t1, c1, h1) = a[k + 1];
        let x = (t - table.t0) / YAW_DT;
        let j = (x.floor() as usize).min(table.cum.len() - 2);
        let c = table.cum[j] + (x - j as f64) * (table.cum[j + 1] - table.cum[j]);
        let f = if c1 - c0 > 1e-9 {
            let f = ((c - c0) / (c1 - c0)).clamp(0.0, 1.0);
            if self.ease { smoothstep(f) } else { f }
        } else {
            smoothstep((t - t0) / (t1 - t0))
        };
        h0 + (h1 - h0) * f
    }

    /// Computes the foot headings and the heading table over `[t_lo, t_hi]`: call once after
    /// building, before posing.
    pub(crate) fn finish(mut self, t_lo: f64, t_hi: f64) -> Motion {
        // First with headings straight from the goal, then again with the headings found: when
        // each heel has risen enough depends a little on the headings.
        self.yaw = None;
        self.set_foot_headings();
        for _ in 0..3 {
            self.find_pivot_times(t_lo, t_hi);
            self.build_yaw_table(t_lo, t_hi);
            self.set_foot_headings();
        }
        self
    }

    /// Finds when each planted foot's heel has risen enough to turn about its toe.
    fn find_pivot_times(&mut self, t_lo: f64, t_hi: f64) {
        for k in 0..self.feet.len() {
            let f = &self.feet[k];
            let (from, to) = (f.t_release.max(t_lo - 2.0), f.t_off.min(t_hi + 2.0));
            let mut t_pivot = NEVER_AFTER;
            let mut t = from;
            while t <= to {
                if self.late_pitch(k, t) >= PIVOT_PITCH_RAD {
                    t_pivot = t;
                    break;
                }
                t += 1.0 / 240.0;
            }
            self.feet[k].t_pivot = t_pivot;
        }
    }

    /// The heading table: the heading turns toward its goal only while the feet let it.
    fn build_yaw_table(&mut self, t_lo: f64, t_hi: f64) {
        let (lo, hi) = (t_lo - 3.0, t_hi + 3.0);
        let n = ((hi - lo) / YAW_DT).ceil() as usize + 1;
        let freedom: Vec<f64> =
            (0..n).map(|j| self.feet.iter().map(|f| f.turn_freedom(lo + j as f64 * YAW_DT)).product()).collect();
        let mut cum = vec![0.0; n];
        for j in 1..n {
            cum[j] = cum[j - 1] + 0.5 * (freedom[j - 1] + freedom[j]) * YAW_DT;
        }
        let mut anchors = Vec::new();
        let mut j = 0;
        while j < n {
            if freedom[j] > 1e-12 {
                j += 1;
                continue;
            }
            let start = j;
            while j < n && freedom[j] <= 1e-12 {
                j += 1;
            }
            if start == 0 || j == n {
                // Cut by the table's ends: its middle is unknown.
                continue;
            }
            let mid = (start + j - 1) / 2;
            let t = lo + mid as f64 * YAW_DT;
            anchors.push((t, cum[mid], self.heading_goal(t)));
        }
        self.yaw = Some(YawTable { t0: lo, cum, anchors });
    }

    fn set_foot_headings(&mut self) {
        for k in 0..self.feet.len() {
            if self.feet[k].yaw_flat.is_none() || self.yaw.is_some() && self.feet[k].t_on > NEVER_BEFORE {
                let y = self.yaw(self.feet[k].t_flat);
                self.feet[k].yaw_flat = Some(y);
            }
        }
    }

    /// Pelvis position on the ground and heading.
    pub(crate) fn pelvis(&self, t: f64) -> (DVec2, f64) {
        let (p, _) = self.path.at(self.progress.at(t));
        let yaw = self.yaw(t);
        let sway: f64 = self
            .layers
            .iter()
            .map(|l| {
                let w = l.weight.at(t);
                if w == 0.0 { 0.0 } else { w * l.cycle.sway.at(l.phase(t)) }
            })
            .sum::<f64>()
            + self.shift.at(t);
        let drift = DVec2::new(self.drift[0].at(t), self.drift[1].at(t));
        (p + drift + sway * DVec2::from_angle(yaw).perp(), yaw)
    }

    fn hip(&self, side: usize, pelvis: (DVec2, f64), z: f64) -> DVec3 {
        let q = pelvis.0 + SIDES[side] * HIP_HALF_WIDTH_M * DVec2::from_angle(pelvis.1).perp();
        q.extend(z)
    }

    fn toe_point(&self, k: usize) -> DVec3 {
        let f = &self.feet[k];
        (f.ground + FOOT_FORWARD_M * DVec2::from_angle(f.yaw_flat.unwrap_or(0.0))).extend(0.0)
    }

    fn heel_point(&self, k: usize) -> DVec3 {
        let f = &self.feet[k];
        (f.ground - HEEL_BACK_M * DVec2::from_angle(f.yaw_flat.unwrap_or(0.0))).extend(0.0)
    }

    /// The pitch of a planted foot after its support window, radians.
    fn late_pitch(&self, k: usize, t: f64) -> f64 {
        let f = &self.feet[k];
        match &f.late {
            Late::Pitch(c) => c.at(t).clamp(0.0, MAX_PITCH_RAD),
            Late::Solve => self.solved_pitch(k, t),
            Late::AtLeast(c) => c.at(t).clamp(0.0, MAX_PITCH_RAD).max(self.solved_pitch(k, t)),
        }
    }

    /// The pitch of planted footfall `k` on its toe at which its knee follows its knee curve,
    /// radians.
    fn solved_pitch(&self, k: usize, t: f64) -> f64 {
        let f = &self.feet[k];
        let pelvis = self.pelvis(t);
        let hip = self.hip(f.side, pelvis, self.pelvis_height(t));
        let reach = reach_of_knee(f.knee.at(t)).min(MAX_REACH_M);
        pitch_for_reach(hip, self.toe_point(k), pelvis.1, reach, MAX_PITCH_RAD)
    }

    /// Where planted footfall `k` is at `t`.
    fn planted_target(&self, k: usize, t: f64) -> FootTarget {
        let f = &self.feet[k];
        if t < f.t_release {
            return self.early_target(k, t);
        }
        let pitch = self.late_pitch(k, t);
        FootTarget { point: self.toe_point(k), local: TOE_POINT, yaw: self.yaw(t), pitch, planted: true }
    }

    /// Where planted footfall `k` is at `t` with its pitch as before its release: on the heel,
    /// then flat.
    fn early_target(&self, k: usize, t: f64) -> FootTarget {
        let f = &self.feet[k];
        let yaw = self.yaw(t);
        if t < f.t_flat && f.strike > 0.0 {
            let x = (t - f.t_on) / (f.t_flat - f.t_on);
            let pitch = -f.strike * (1.0 - smoothstep(x));
            return FootTarget { point: self.heel_point(k), local: HEEL_POINT, yaw, pitch, planted: true };
        }
        FootTarget { point: self.toe_point(k), local: TOE_POINT, yaw, pitch: 0.0, planted: true }
    }

    /// The pelvis height footfall `k`'s knee curve asks for at `t` (its pitch as before its
    /// release), metres.
    fn leg_height(&self, k: usize, t: f64) -> f64 {
        let f = &self.feet[k];
        let ankle = self.early_target(k, t).ankle();
        let hip = self.hip(f.side, self.pelvis(t), 0.0);
        let d2 = (hip - ankle).truncate().length_squared();
        let r = reach_of_knee(f.knee.at(t));
        ankle.z + (r * r - d2).max(0.0).sqrt()
    }

    fn window_height(&self, w: &Window, t: f64) -> f64 {
        match &w.height {
            Height::Leg(k) => self.leg_height(*k, t),
            Height::Level(c) => c.at(t),
        }
    }

    /// Pelvis height at `t`, metres.
    pub(crate) fn pelvis_height(&self, t: f64) -> f64 {
        let ws = &self.windows;
        let Some(j) = ws.iter().position(|w| w.t1 >= t) else {
            return ws.last().map_or(STANDING_PELVIS_M, |w| self.window_height(w, t));
        };
        if t >= ws[j].t0 || j == 0 {
            return self.window_height(&ws[j], t);
        }
        let (a, b) = (&ws[j - 1], &ws[j]);
        let h = 1e-4;
        let (za, zb) = (self.window_height(a, a.t1), self.window_height(b, b.t0));
        // Leaving level or rising, never falling: a falling start would dip below both ends.
        let da = ((za - self.window_height(a, a.t1 - h)) / h).max(0.0);
        // Arriving level or descending, never rising, for the same reason (a dip would buckle
        // the stance knee).
        let db = ((self.window_height(b, b.t0 + h) - zb) / h).min(0.0);
        hermite(t, a.t1, b.t0, za, zb, da, db)
    }

    /// Where the swinging foot of `side` is at `t`, between footfalls `from` and `to`.
    fn swing_target(&self, from: usize, to: usize, t: f64) -> FootTarget {
        let (a, b) = (&self.feet[from], &self.feet[to]);
        let tau = ((t - a.t_off) / (b.t_on - a.t_off)).clamp(0.0, 1.0);
        let (p0, p3) = (self.toe_point(from), self.heel_point(to));
        // On the ground: a quadratic curve bulging away from the stance foot when the straight
        // line would pass too close to it.
        let mid_t = 0.5 * (a.t_off + b.t_on);
        let other = self.feet.iter().find(|f| f.side != a.side && f.planted(mid_t));
        let (g0, g3) = (p0.truncate(), p3.truncate());
        let mut m = b.via.unwrap_or(0.5 * (g0 + g3));
        if let (None, Some(o)) = (b.via, other) {
            let dir = (g3 - g0).normalize_or_zero();
            let rel = o.ground - g0;
            let along = rel.dot(dir).clamp(0.0, (g3 - g0).length());
            let closest = g0 + dir * along;
            let away = (closest - o.ground).normalize_or(SIDES[a.side] * dir.perp());
            let gap = (closest - o.ground).length();
            let want = 1.6 * HIP_HALF_WIDTH_M;
            if gap < want {
                m += 2.0 * (want - gap) * away;
            }
        }
        let bez = Bezier { points: [(0.0, 0.0), (0.0, b.swing_height), (1.0, b.swing_height), (1.0, 0.0)] };
        let (p, z) = bez.at(tau);
        // Along the ground the foot eases out of and into its footprints once more, so that it
        // leaves and lands vertically: the last centimetres of height come with almost no
        // horizontal motion.
        let p = smoothstep(p);
        let ground = (1.0 - p) * (1.0 - p) * g0 + 2.0 * (1.0 - p) * p * m + p * p * g3;
        let heel = smoothstep(tau);
        let lift = self.late_pitch(from, a.t_off);
        let pitch_curve = KeyCurve::open(&[(0.0, lift), (0.5, 0.0), (0.85, -b.strike), (1.0, -b.strike)]);
        let mut pitch = pitch_curve.at(tau);
        // Keep the toe and the heel off the ground away from the ends.
        let clearance = SWING_CLEARANCE_M * smoothstep(tau / 0.12) * smoothstep((1.0 - tau) / 0.12);
        let foot = FOOT_FORWARD_M + HEEL_BACK_M;
        let room = (z - clearance).max(0.0);
        if heel > 0.0 {
            pitch = pitch.min((room / (foot * heel)).min(1.0).asin());
        }
        if heel < 1.0 {
            pitch = pitch.max(-(room / (foot * (1.0 - heel))).min(1.0).asin());
        }
        FootTarget { point: ground.extend(z), local: sole_point(heel), yaw: self.yaw(t), pitch, planted: false }
    }

    /// Where the foot of `side` is at `t`.
    pub(crate) fn foot_target(&self, side: usize, t: f64) -> FootTarget {
        let mine: Vec<usize> = (0..self.feet.len()).filter(|&k| self.feet[k].side == side).collect();
        let k = mine.iter().rposition(|&k| self.feet[k].t_on <= t).unwrap_or(0);
        let f = mine[k];
        if t <= self.feet[f].t_off || k + 1 == mine.len() {
            return self.planted_target(f, t.min(self.feet[f].t_off));
        }
        self.swing_target(f, mine[k + 1], t)
    }

    /// Poses the actor at `t` into `out`.
    pub(crate) fn pose(&self, rig: &Rig, t: f64, out: &mut Pose) {
        let (p, yaw) = self.pelvis(t);
        out.root = p.extend(self.pelvis_height(t));
        out.rotations[0] = DQuat::from_rotation_z(yaw);
        for i in 0..2 {
            place_leg(rig, i, &self.foot_target(i, t), out);
        }
        let (mut w, mut twist, mut lean) = (0.0, 0.0, self.lean.at(t));
        let mut arm = [0.0; 2];
        let mut elbow = [0.0; 2];
        for l in &self.layers {
            let lw = l.weight.at(t);
            if lw == 0.0 {
                continue;
            }
            let ph = l.phase(t);
            w += lw;
            twist += lw * l.cycle.twist.at(ph);
            lean += lw * l.cycle.lean;
            for i in 0..2 {
                arm[i] += lw * l.cycle.arm.at(ph + 0.5 * i as f64);
                elbow[i] += lw * l.cycle.elbow.at(ph + 0.5 * i as f64);
            }
        }
        out.rotations[rig.chest] = DQuat::from_rotation_y(lean) * DQuat::from_rotation_z(twist);
        for (i, side) in SIDES.into_iter().enumerate() {
            let e = (1.0 - w) * REST_ELBOW_RAD + elbow[i];
            out.rotations[rig.arm[i]] =
                DQuat::from_rotation_y(arm[i]) * DQuat::from_rotation_x(side * REST_ARM_ABDUCTION_RAD);
            out.rotations[rig.fore_arm[i]] = DQuat::from_rotation_y(-e);
        }
    }

    /// Samples `[t0, t1]` at `frame_rate` into a clip whose first frame stands at the origin
    /// facing +X.
    pub(crate) fn render(&self, t0: f64, t1: f64, frame_rate: f64, name: &str) -> Clip {
        let skeleton = actor::actor();
        let rig = Rig::of(&skeleton);
        let duration = t1 - t0;
        let n = ((duration * frame_rate).round() as usize).max(1);
        let mut frames = Vec::with_capacity(n + 1);
        let mut pose = skeleton.bind_pose();
        for j in 0..=n {
            self.pose(&rig, t0 + duration * j as f64 / n as f64, &mut pose);
            frames.push(pose.clone());
        }
        let origin = Ground::of(&frames[0], 0.0);
        for f in &mut frames {
            origin.transform_pose(f, true);
        }
        Clip { name: name.into(), frame_time: duration / n as f64, frames }
    }
}

/// Standing: the pelvis height and the knee flexion with both feet flat under the hips.
pub(crate) fn standing_knee() -> f64 {
    let d = STANDING_PELVIS_M - ANKLE_HEIGHT_M;
    let (t, s) = (actor::THIGH_M, actor::SHIN_M);
    ((d * d - t * t - s * s) / (2.0 * t * s)).clamp(-1.0, 1.0).acos()
}

/// Rounds a time to the default frame grid, seconds.
pub(crate) fn on_frame(t: f64) -> f64 {
    (t * FRAME_RATE_HZ).round() / FRAME_RATE_HZ
}
