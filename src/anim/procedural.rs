//! Procedural key-frame locomotion for the built-in actor (seed 002 §4.1 on level ground;
//! DESIGN.md §3–4): the clips of the default animation database.
//!
//! As in seed 002 §4.1, each step is described by key frames — contact (heel strike), loading
//! (foot flat), mid-stance, toe-off and passing — and the motion between them is interpolated:
//! joint angles and pelvis offsets by shape-preserving cubics through the key values, the free
//! (swing) ankle along a cubic Bezier curve from lift-off to the next footprint whose two inner
//! control points are raised by the swing height. As in seed 002 §4 the legs are planned in the
//! sagittal plane of the path (arclength and height) and laid back onto the path: footprints
//! are placed along a straight or constant-curvature path (the heading turns by a fixed angle
//! per step), alternating feet, each one beside the path, and the swing foot follows the path
//! too, so it passes beside the planted foot even in tight turns. The pelvis follows the path at
//! the gait speed with a vertical bob and a lateral sway toward the stance foot, and its yaw is
//! the path heading. While a foot is on the ground its ankle joint stays exactly where it
//! landed: the hip (flex and abduction) and the knee are solved by analytic two-link inverse
//! kinematics, and the ankle pitches the foot — toes up at heel strike, flat through stance,
//! toes down after lift-off as far as the toe clears the ground. Arms swing opposite to the legs
//! with a slight elbow bend and the waist twists against the pelvis.
//!
//! Every clip of a steady gait starts on a left-foot plant and lasts an even number of steps,
//! so its last frame, taken relative to its ground reference ([`Ground`]), is its first frame:
//! the clip repeats seamlessly. Start and stop clips join standing still to that same phase.
//!
//! Simplified with respect to the seed: only level ground (no uphill and downhill key frames, no
//! Bezier adjustment against a ground profile, no footstep search); the ankle, not the heel or
//! the toe, is the point held fixed during stance, so the foot pitches about the ankle and the
//! heel does not rise before lift-off; the actor's hips cannot rotate about the vertical, so a
//! planted foot turns with the pelvis when walking on a curve; the mean pelvis height is set
//! as high as the planted legs can reach their footprints (nearly straight at heel strike and
//! lift-off), which gives a bent-knee stance, deeper when running; where the leg is too short
//! for the swing curve (briefly, just after lift-off and before heel strike) the straight leg
//! points at it instead. Everything is deterministic.

use std::f64::consts::PI;

use glam::{DQuat, DVec2, DVec3};

use super::actor::{self, ANKLE_HEIGHT_M, FOOT_FORWARD_M, HIP_HALF_WIDTH_M, PELVIS_HEIGHT_M, SHIN_M, THIGH_M};
use super::clip::{Clip, Ground, mirror_pairs};
use super::skeleton::{Pose, Skeleton};
use crate::geom::{smoothstep, wrap_angle};

/// Frame rate of the default clips, frames per second.
pub const FRAME_RATE_HZ: f64 = 60.0;

/// Pelvis height when standing still, metres: the knees slightly unlocked.
pub const STANDING_PELVIS_M: f64 = PELVIS_HEIGHT_M - 0.002;

/// Longest hip-to-ankle distance used while a foot is planted, as a fraction of the leg length
/// (the knee keeps about 5° of flexion).
const REACH: f64 = 0.999;

/// A locomotion style: speed, cadence and the amplitudes of the key frames.
#[derive(Debug, Clone, PartialEq)]
pub struct Gait {
    /// Name, the prefix of clip names (`walk` gives `walk_straight`, …).
    pub name: String,
    /// Forward speed of the pelvis, m/s.
    pub speed_mps: f64,
    /// Time from one foot plant to the next (of the other foot), seconds; a stride is two steps.
    pub step_time_s: f64,
    /// Fraction of a stride each foot is on the ground: above 0.5 walking with double support,
    /// below 0.5 running with a flight phase.
    pub duty_factor: f64,
    /// Height the two inner Bezier control points of the swing ankle are raised, metres.
    pub swing_height_m: f64,
    /// Amplitude of the pelvis's vertical bob, metres: highest at mid-stance when walking,
    /// lowest at mid-stance when running.
    pub bob_m: f64,
    /// Amplitude of the pelvis's lateral sway toward the stance foot, metres.
    pub sway_m: f64,
    /// Lateral distance of each footprint from the path, metres.
    pub foot_offset_m: f64,
    /// Amplitude of the shoulders' forward–backward swing, radians.
    pub arm_swing_rad: f64,
    /// Elbow flexion with the arm swung back, radians (more when it swings forward).
    pub elbow_rad: f64,
    /// Forward lean of the waist, radians.
    pub lean_rad: f64,
    /// Amplitude of the waist's twist against the pelvis, radians.
    pub twist_rad: f64,
    /// Toes-up pitch of the foot at heel strike, radians.
    pub heel_strike_rad: f64,
    /// Toes-down pitch of the foot after lift-off, radians (less if the toe would touch the
    /// ground).
    pub toe_off_rad: f64,
}

/// Why a gait cannot be generated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GaitError {
    /// A parameter is out of its range or not finite.
    #[error("gait '{gait}': {field} = {value} is out of range ({range})")]
    OutOfRange {
        /// The gait's name.
        gait: String,
        /// The parameter.
        field: &'static str,
        /// Its value.
        value: f64,
        /// The accepted range.
        range: &'static str,
    },
}

impl Gait {
    /// Slow walk: 0.8 m/s, 100 steps per minute, 0.48 m steps.
    pub fn slow_walk() -> Gait {
        Gait {
            name: "slow_walk".into(),
            speed_mps: 0.8,
            step_time_s: 0.6,
            duty_factor: 0.64,
            swing_height_m: 0.08,
            bob_m: 0.025,
            sway_m: 0.03,
            foot_offset_m: HIP_HALF_WIDTH_M,
            arm_swing_rad: 0.15,
            elbow_rad: 0.2,
            lean_rad: 0.02,
            twist_rad: 0.03,
            heel_strike_rad: 0.15,
            toe_off_rad: 0.35,
        }
    }

    /// Shuffle: 0.2 m/s, short 0.12 m steps for turning on the spot.
    pub fn shuffle() -> Gait {
        Gait {
            name: "shuffle".into(),
            speed_mps: 0.2,
            step_time_s: 0.6,
            duty_factor: 0.7,
            swing_height_m: 0.06,
            bob_m: 0.01,
            sway_m: 0.02,
            foot_offset_m: HIP_HALF_WIDTH_M,
            arm_swing_rad: 0.05,
            elbow_rad: 0.2,
            lean_rad: 0.0,
            twist_rad: 0.02,
            heel_strike_rad: 0.05,
            toe_off_rad: 0.15,
        }
    }

    /// Walk: 1.35 m/s, about 124 steps per minute, 0.65 m steps.
    pub fn walk() -> Gait {
        Gait {
            name: "walk".into(),
            speed_mps: 1.35,
            step_time_s: 29.0 / 60.0,
            duty_factor: 0.6,
            swing_height_m: 0.11,
            bob_m: 0.04,
            sway_m: 0.025,
            foot_offset_m: HIP_HALF_WIDTH_M,
            arm_swing_rad: 0.3,
            elbow_rad: 0.3,
            lean_rad: 0.04,
            twist_rad: 0.06,
            heel_strike_rad: 0.2,
            toe_off_rad: 0.5,
        }
    }

    /// Jog: 2.5 m/s, about 164 steps per minute, 0.92 m steps, short flight phases.
    pub fn jog() -> Gait {
        Gait {
            name: "jog".into(),
            speed_mps: 2.5,
            step_time_s: 22.0 / 60.0,
            duty_factor: 0.4,
            swing_height_m: 0.16,
            bob_m: 0.03,
            sway_m: 0.015,
            foot_offset_m: 0.075,
            arm_swing_rad: 0.45,
            elbow_rad: 1.2,
            lean_rad: 0.08,
            twist_rad: 0.1,
            heel_strike_rad: 0.15,
            toe_off_rad: 0.6,
        }
    }

    /// Run: 3.6 m/s, 180 steps per minute, 1.2 m steps.
    pub fn run() -> Gait {
        Gait {
            name: "run".into(),
            speed_mps: 3.6,
            step_time_s: 20.0 / 60.0,
            duty_factor: 0.32,
            swing_height_m: 0.25,
            bob_m: 0.02,
            sway_m: 0.01,
            foot_offset_m: 0.065,
            arm_swing_rad: 0.6,
            elbow_rad: 1.35,
            lean_rad: 0.12,
            twist_rad: 0.12,
            heel_strike_rad: 0.12,
            toe_off_rad: 0.8,
        }
    }

    /// Sprint: 5.5 m/s, about 212 steps per minute, 1.56 m steps.
    pub fn sprint() -> Gait {
        Gait {
            name: "sprint".into(),
            speed_mps: 5.5,
            step_time_s: 17.0 / 60.0,
            duty_factor: 0.25,
            swing_height_m: 0.35,
            bob_m: 0.015,
            sway_m: 0.008,
            foot_offset_m: 0.05,
            arm_swing_rad: 0.8,
            elbow_rad: 1.45,
            lean_rad: 0.2,
            twist_rad: 0.15,
            heel_strike_rad: 0.05,
            toe_off_rad: 0.9,
        }
    }

    /// The five presets, slowest first.
    pub fn presets() -> Vec<Gait> {
        vec![Gait::slow_walk(), Gait::walk(), Gait::jog(), Gait::run(), Gait::sprint()]
    }

    /// Distance from one footprint to the next along the path, metres.
    pub fn step_length_m(&self) -> f64 {
        self.speed_mps * self.step_time_s
    }

    /// Steps per minute.
    pub fn cadence_spm(&self) -> f64 {
        60.0 / self.step_time_s
    }

    /// True when the feet leave the ground together at times (duty factor below 0.5).
    pub fn is_running(&self) -> bool {
        self.duty_factor < 0.5
    }

    /// Checks every parameter's range.
    pub fn validate(&self) -> Result<(), GaitError> {
        let fields: [(&'static str, f64, f64, f64, &'static str); 14] = [
            ("speed_mps", self.speed_mps, 0.05, 12.0, "0.05..=12"),
            ("step_time_s", self.step_time_s, 0.1, 2.0, "0.1..=2"),
            ("duty_factor", self.duty_factor, 0.15, 0.9, "0.15..=0.9"),
            ("swing_height_m", self.swing_height_m, 0.0, 0.6, "0..=0.6"),
            ("bob_m", self.bob_m, 0.0, 0.1, "0..=0.1"),
            ("sway_m", self.sway_m, 0.0, 0.1, "0..=0.1"),
            ("foot_offset_m", self.foot_offset_m, 0.0, 0.2, "0..=0.2"),
            ("arm_swing_rad", self.arm_swing_rad, 0.0, 1.5, "0..=1.5"),
            ("elbow_rad", self.elbow_rad, 0.0, 2.0, "0..=2"),
            ("lean_rad", self.lean_rad, -0.3, 0.6, "-0.3..=0.6"),
            ("twist_rad", self.twist_rad, 0.0, 0.5, "0..=0.5"),
            ("heel_strike_rad", self.heel_strike_rad, 0.0, 0.6, "0..=0.6"),
            ("toe_off_rad", self.toe_off_rad, 0.0, 1.5, "0..=1.5"),
            ("step_length_m", self.step_length_m(), 0.05, 2.0, "0.05..=2"),
        ];
        for (field, value, lo, hi, range) in fields {
            if !(value >= lo && value <= hi) {
                return Err(GaitError::OutOfRange { gait: self.name.clone(), field, value, range });
            }
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------------
// Key-frame curves

/// Key values at phases, interpolated by a shape-preserving cubic Hermite curve (tangents are
/// harmonic means of the neighbouring slopes and zero at local extrema, so the curve never
/// overshoots its keys). Periodic curves repeat with period 1; open curves have flat ends.
#[derive(Debug, Clone)]
struct KeyCurve {
    keys: Vec<(f64, f64)>,
    tangents: Vec<f64>,
    periodic: bool,
}

impl KeyCurve {
    /// A curve of period 1 through `keys` (phases taken modulo 1).
    fn periodic(keys: &[(f64, f64)]) -> KeyCurve {
        let mut k: Vec<(f64, f64)> = keys.iter().map(|&(p, v)| (p.rem_euclid(1.0), v)).collect();
        k.sort_by(|a, b| a.0.total_cmp(&b.0));
        KeyCurve::build(k, true)
    }

    /// A curve over `[first phase, last phase]` through `keys` (sorted), constant outside.
    fn open(keys: &[(f64, f64)]) -> KeyCurve {
        KeyCurve::build(keys.to_vec(), false)
    }

    fn build(keys: Vec<(f64, f64)>, periodic: bool) -> KeyCurve {
        let n = keys.len();
        let key = |i: isize| -> (f64, f64) {
            let m = n as isize;
            let (p, v) = keys[i.rem_euclid(m) as usize];
            (p + i.div_euclid(m) as f64, v)
        };
        let tangents = (0..n as isize)
            .map(|i| {
                if !periodic && (i == 0 || i == n as isize - 1) {
                    return 0.0;
                }
                let (p0, v0) = key(i - 1);
                let (p1, v1) = key(i);
                let (p2, v2) = key(i + 1);
                let (d0, d1) = ((v1 - v0) / (p1 - p0), (v2 - v1) / (p2 - p1));
                if d0 * d1 <= 0.0 { 0.0 } else { 2.0 * d0 * d1 / (d0 + d1) }
            })
            .collect();
        KeyCurve { keys, tangents, periodic }
    }

    /// The value at `phase`.
    fn at(&self, phase: f64) -> f64 {
        let n = self.keys.len();
        if n == 1 {
            return self.keys[0].1;
        }
        let (i, j, p0, p1, x) = if self.periodic {
            let x = phase.rem_euclid(1.0);
            match self.keys.iter().rposition(|k| k.0 <= x) {
                Some(i) if i + 1 < n => (i, i + 1, self.keys[i].0, self.keys[i + 1].0, x),
                Some(i) => (i, 0, self.keys[i].0, self.keys[0].0 + 1.0, x),
                None => (n - 1, 0, self.keys[n - 1].0 - 1.0, self.keys[0].0, x),
            }
        } else {
            if phase <= self.keys[0].0 {
                return self.keys[0].1;
            }
            if phase >= self.keys[n - 1].0 {
                return self.keys[n - 1].1;
            }
            let i = self.keys.iter().rposition(|k| k.0 <= phase).unwrap_or(0).min(n - 2);
            (i, i + 1, self.keys[i].0, self.keys[i + 1].0, phase)
        };
        let h = p1 - p0;
        let u = (x - p0) / h;
        let (u2, u3) = (u * u, u * u * u);
        (2.0 * u3 - 3.0 * u2 + 1.0) * self.keys[i].1
            + (u3 - 2.0 * u2 + u) * h * self.tangents[i]
            + (-2.0 * u3 + 3.0 * u2) * self.keys[j].1
            + (u3 - u2) * h * self.tangents[j]
    }
}

/// A weight going from `from` at `t0` to `to` at `t1` along a smoothstep.
#[derive(Debug, Clone, Copy)]
struct Ramp {
    t0: f64,
    t1: f64,
    from: f64,
    to: f64,
}

impl Ramp {
    const ONE: Ramp = Ramp { t0: 0.0, t1: 1.0, from: 1.0, to: 1.0 };

    fn at(self, t: f64) -> f64 {
        let x = if self.t1 > self.t0 { (t - self.t0) / (self.t1 - self.t0) } else { 1.0 };
        self.from + (self.to - self.from) * smoothstep(x)
    }
}

/// The key frames of one stride of a gait, as curves over the stride phase (0 = left heel
/// strike, 0.5 = right heel strike).
#[derive(Debug, Clone)]
struct Cycle {
    /// Pelvis height offset, metres.
    bob: KeyCurve,
    /// Pelvis lateral offset toward the left, metres.
    sway: KeyCurve,
    /// Left shoulder flexion (Y rotation), radians; the right one is half a stride later.
    arm: KeyCurve,
    /// Left elbow flexion, radians (positive bends).
    elbow: KeyCurve,
    /// Waist twist (Z rotation), radians.
    twist: KeyCurve,
    /// Foot pitch over the swing fraction `[0, 1]`, radians (positive toes down).
    swing_pitch: KeyCurve,
}

impl Cycle {
    fn of(g: &Gait) -> Cycle {
        let b = g.duty_factor;
        // Mid-stance of the left foot, in stride phase.
        let mid = b / 2.0;
        // Walking: pelvis highest over the stance foot (vaulting); running: lowest (compression).
        let up = if g.is_running() { -g.bob_m } else { g.bob_m };
        let lag = 0.04;
        let (a, off) = (g.arm_swing_rad, -0.15 * g.arm_swing_rad);
        Cycle {
            // Key frames: mid-stance, mid double support (or mid flight), and again for the other foot.
            bob: if g.is_running() {
                KeyCurve::periodic(&[(mid, up), (mid + 0.25, -up), (mid + 0.5, up), (mid + 0.75, -up)])
            } else {
                // Lowest and level through double support, where one leg or the other is at its
                // longest; rising in an arc to mid-stance, like a vaulting leg.
                let off = b - 0.5;
                let step =
                    [(0.0, -up), (off, -up), (0.5 * (off + mid), 0.4 * up), (mid, up), (0.5 * mid + 0.25, 0.4 * up)];
                let keys: Vec<(f64, f64)> =
                    step.iter().chain(&step).enumerate().map(|(i, &(p, v))| (p + 0.5 * (i / 5) as f64, v)).collect();
                KeyCurve::periodic(&keys)
            },
            sway: KeyCurve::periodic(&[(mid, g.sway_m), (mid + 0.25, 0.0), (mid + 0.5, -g.sway_m), (mid + 0.75, 0.0)]),
            // Left heel strike: left arm back (positive Y); right heel strike: left arm forward.
            arm: KeyCurve::periodic(&[(lag, off + a), (lag + 0.25, off), (lag + 0.5, off - a), (lag + 0.75, off)]),
            elbow: KeyCurve::periodic(&[(lag, g.elbow_rad), (lag + 0.5, g.elbow_rad + 0.5 * a)]),
            // Left heel strike: the right shoulder forward, the chest turned to the left.
            twist: KeyCurve::periodic(&[
                (lag, g.twist_rad),
                (lag + 0.25, 0.0),
                (lag + 0.5, -g.twist_rad),
                (lag + 0.75, 0.0),
            ]),
            // Lift-off (flat), toe-off pitch, passing, heel strike.
            swing_pitch: KeyCurve::open(&[
                (0.0, 0.0),
                (0.3, g.toe_off_rad),
                (0.65, 0.05 * g.toe_off_rad),
                (1.0, -g.heel_strike_rad),
            ]),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Path, footprints and pelvis progress

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
struct Path {
    step: f64,
    /// Index of the first segment.
    first: i64,
    /// Start point, start heading and curvature of each segment.
    segments: Vec<(DVec2, f64, f64)>,
}

impl Path {
    /// Segment `k` turns by `turns[k]` (clamped to the ends of `turns`), covering steps
    /// `-margin .. turns.len() + margin`.
    fn new(step: f64, turns: &[f64], margin: i64) -> Path {
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

    /// Point and heading at arclength `s`.
    fn at(&self, s: f64) -> (DVec2, f64) {
        let k = ((s / self.step).floor() as i64).clamp(self.first, self.first + self.segments.len() as i64 - 1);
        let (p, h, c) = self.segments[(k - self.first) as usize];
        let u = s - k as f64 * self.step;
        (p + advance(h, c, u), h + c * u)
    }

    /// Ankle position of a foot set on footprint `s`, `side` = +1 left, −1 right.
    fn footprint(&self, s: f64, side: f64, offset: f64) -> DVec3 {
        let (p, h) = self.at(s);
        let q = p + side * offset * DVec2::from_angle(h).perp();
        DVec3::new(q.x, q.y, ANKLE_HEIGHT_M)
    }
}

/// One stay of a foot on the ground: where (arclength of the footprint) and when.
#[derive(Debug, Clone, Copy)]
struct Footfall {
    s: f64,
    plant: f64,
    lift: f64,
}

/// Pelvis arclength over time: speed `v0` until `t0`, then a smoothstep change of speed to `v1`
/// over `ramp` seconds, then `v1`; at `t0` the pelvis is at `s0`.
#[derive(Debug, Clone, Copy)]
struct Progress {
    t0: f64,
    s0: f64,
    v0: f64,
    v1: f64,
    ramp: f64,
}

impl Progress {
    fn at(self, t: f64) -> f64 {
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
// The actor's joints and leg inverse kinematics

/// Joint indices of the actor; index 0 of each pair is the left side.
#[derive(Debug, Clone, Copy)]
struct Rig {
    chest: usize,
    arm: [usize; 2],
    fore_arm: [usize; 2],
    up_leg: [usize; 2],
    leg: [usize; 2],
    foot: [usize; 2],
}

impl Rig {
    fn of(s: &Skeleton) -> Rig {
        let f = |n: &str| s.find(n).expect("the actor has every named joint");
        use actor::*;
        Rig {
            chest: f(CHEST),
            arm: [f(LEFT_ARM), f(RIGHT_ARM)],
            fore_arm: [f(LEFT_FORE_ARM), f(RIGHT_FORE_ARM)],
            up_leg: [f(LEFT_UP_LEG), f(RIGHT_UP_LEG)],
            leg: [f(LEFT_LEG), f(RIGHT_LEG)],
            foot: [f(LEFT_FOOT), f(RIGHT_FOOT)],
        }
    }
}

const SIDES: [f64; 2] = [1.0, -1.0];

/// Hip flexion (Y), hip abduction (X) and knee (Y) angles putting the ankle at `d` from the hip
/// joint, in the pelvis frame; a target out of reach is moved along the hip–target line.
fn leg_ik(d: DVec3) -> (f64, f64, f64) {
    let (t, s) = (THIGH_M, SHIN_M);
    let len = d.length();
    let r = len.clamp((t - s).abs() + 1e-9, t + s);
    let d = if len > 0.0 { d * (r / len) } else { DVec3::new(0.0, 0.0, -r) };
    let knee = ((r * r - t * t - s * s) / (2.0 * t * s)).clamp(-1.0, 1.0).acos();
    let l = t + s * knee.cos();
    let abduction = (d.y / l).clamp(-1.0, 1.0).asin();
    let (x, z) = (-s * knee.sin(), -l * abduction.cos());
    let flex = wrap_angle(d.x.atan2(d.z) - x.atan2(z));
    (flex, abduction, knee)
}

/// The ankle angle giving the foot a world pitch of `pitch` (positive toes down) below the leg
/// rotation `leg` (hip · knee, in the pelvis frame).
fn ankle_for_pitch(leg: DQuat, pitch: f64) -> f64 {
    let a = (leg * DVec3::X).z;
    let b = (leg * DVec3::Z).z;
    let r = a.hypot(b);
    let planar = wrap_angle(pitch - (-a).atan2(b));
    if r < 1e-9 {
        return planar;
    }
    let delta = b.atan2(a);
    let c = (-pitch.sin() / r).clamp(-1.0, 1.0).acos();
    let (x1, x2) = (wrap_angle(c - delta), wrap_angle(-c - delta));
    if wrap_angle(x1 - planar).abs() <= wrap_angle(x2 - planar).abs() { x1 } else { x2 }
}

/// The largest toes-down pitch keeping the toe tip above the ground with the ankle at `z`.
fn toe_limit(z: f64) -> f64 {
    let r = FOOT_FORWARD_M.hypot(ANKLE_HEIGHT_M);
    let gamma = ANKLE_HEIGHT_M.atan2(FOOT_FORWARD_M);
    (z / r).clamp(-1.0, 1.0).asin() - gamma
}

// ---------------------------------------------------------------------------------------------
// The motion

/// Where a foot is at one time.
#[derive(Debug, Clone, Copy)]
struct FootTarget {
    ankle: DVec3,
    pitch: f64,
    planted: bool,
}

/// Everything that poses the actor at any time of one clip.
#[derive(Debug, Clone)]
struct Motion {
    gait: Gait,
    cycle: Cycle,
    path: Path,
    /// Stays on the ground of the left and the right foot, in time order.
    feet: [Vec<Footfall>; 2],
    progress: Progress,
    /// A time of a left heel strike of the steady gait (stride phase 0).
    phase_origin: f64,
    /// Mean pelvis height of the steady gait, metres.
    height: f64,
    /// Weight of the steady gait's pelvis height against standing.
    w_height: Ramp,
    /// Weight of the steady gait's sway.
    w_sway: Ramp,
    /// A lateral weight shift of the pelvis toward the left foot, metres, and the weights that
    /// bring it in and out (starting to walk).
    shift_m: f64,
    shift_in: Ramp,
    shift_out: Ramp,
    /// Weight of the steady gait's upper body against standing.
    w_body: Ramp,
}

impl Motion {
    fn stride_phase(&self, t: f64) -> f64 {
        (t - self.phase_origin) / (2.0 * self.gait.step_time_s)
    }

    /// Pelvis position on the ground (with sway) and yaw.
    fn pelvis(&self, t: f64) -> (DVec2, f64) {
        let (p, h) = self.path.at(self.progress.at(t));
        let sway = self.w_sway.at(t) * self.cycle.sway.at(self.stride_phase(t))
            + self.shift_m * self.shift_in.at(t) * self.shift_out.at(t);
        (p + sway * DVec2::from_angle(h).perp(), h)
    }

    /// Pelvis height without the standing blend.
    fn bob(&self, t: f64) -> f64 {
        self.cycle.bob.at(self.stride_phase(t))
    }

    fn pelvis_height(&self, t: f64) -> f64 {
        let w = self.w_height.at(t);
        (1.0 - w) * STANDING_PELVIS_M + w * (self.height + self.bob(t))
    }

    fn foot(&self, i: usize, t: f64) -> FootTarget {
        let g = &self.gait;
        let falls = &self.feet[i];
        let side = SIDES[i];
        let k = falls.iter().rposition(|f| f.plant <= t).unwrap_or(0);
        let f = falls[k];
        if t <= f.lift || k + 1 == falls.len() {
            // Stance: toes up at heel strike, flat from the end of loading.
            let loading = 0.2 * (f.lift - f.plant).min(2.0 * g.duty_factor * g.step_time_s);
            let pitch = -g.heel_strike_rad * (1.0 - smoothstep((t - f.plant) / loading));
            return FootTarget { ankle: self.path.footprint(f.s, side, g.foot_offset_m), pitch, planted: true };
        }
        let next = falls[k + 1];
        let tau = ((t - f.lift) / (next.plant - f.lift)).clamp(0.0, 1.0);
        // The foot leaves the ground briskly and lands gently (more briskly when running).
        let (c0, c1, a1, a2) = if g.is_running() { (1.0, 0.5, 0.05, 0.8) } else { (0.6, 0.3, 0.2, 0.85) };
        let u = ((c0 + c1 - 2.0) * tau + 3.0 - 2.0 * c0 - c1) * tau * tau + c0 * tau;
        // The Bezier curve lives in the sagittal plane of the path (arclength, height), as in
        // seed 002 §4, and is laid back onto the path beside it.
        let (s0, s3, z0, up) = (f.s, next.s, ANKLE_HEIGHT_M, g.swing_height_m);
        let p = [(s0, z0), (s0 + a1 * (s3 - s0), z0 + up), (s0 + a2 * (s3 - s0), z0 + up), (s3, z0)];
        let v = 1.0 - u;
        let w = [v * v * v, 3.0 * v * v * u, 3.0 * v * u * u, u * u * u];
        let (s, z) = (0..4).fold((0.0, 0.0), |(s, z), k| (s + w[k] * p[k].0, z + w[k] * p[k].1));
        let ankle = self.path.footprint(s, side, g.foot_offset_m).truncate().extend(z);
        // The toe clears the ground by up to 2 cm once the foot is on its way.
        let clearance = TOE_CLEARANCE_M * smoothstep(tau / 0.15);
        let pitch = self.cycle.swing_pitch.at(tau).min(toe_limit(ankle.z - clearance));
        FootTarget { ankle, pitch, planted: false }
    }

    /// The highest pelvis the planted feet allow at `t`, metres.
    fn reach_limit(&self, t: f64) -> f64 {
        let (p, yaw) = self.pelvis(t);
        let mut limit = f64::INFINITY;
        for (i, side) in SIDES.into_iter().enumerate() {
            let f = self.foot(i, t);
            if f.planted {
                let hip = p + side * HIP_HALF_WIDTH_M * DVec2::from_angle(yaw).perp();
                let d = (f.ankle.truncate() - hip).length();
                let l = REACH * (THIGH_M + SHIN_M);
                limit = limit.min(f.ankle.z + (l * l - d * d).max(0.0).sqrt());
            }
        }
        limit
    }

    /// Sets the mean pelvis height as high as standing allows but low enough for the planted
    /// legs to reach the ground over `[0, duration]`.
    fn fit_height(&mut self, duration: f64) {
        let n = (duration * 480.0).ceil().max(1.0) as usize;
        self.height = STANDING_PELVIS_M - self.gait.bob_m;
        for j in 0..=n {
            let t = duration * j as f64 / n as f64;
            self.height = self.height.min(self.reach_limit(t) - self.bob(t));
        }
    }

    fn pose(&self, rig: &Rig, t: f64, out: &mut Pose) {
        let g = &self.gait;
        let (p, yaw) = self.pelvis(t);
        out.root = DVec3::new(p.x, p.y, self.pelvis_height(t));
        let root_rot = DQuat::from_rotation_z(yaw);
        out.rotations[0] = root_rot;
        let inv = root_rot.inverse();
        for (i, side) in SIDES.into_iter().enumerate() {
            let f = self.foot(i, t);
            let hip = out.root + root_rot * DVec3::new(0.0, side * HIP_HALF_WIDTH_M, 0.0);
            let (flex, abduction, knee) = leg_ik(inv * (f.ankle - hip));
            let hip_q = DQuat::from_rotation_y(flex) * DQuat::from_rotation_x(abduction);
            let knee_q = DQuat::from_rotation_y(knee);
            let ankle = ankle_for_pitch(hip_q * knee_q, f.pitch);
            out.rotations[rig.up_leg[i]] = hip_q;
            out.rotations[rig.leg[i]] = knee_q;
            out.rotations[rig.foot[i]] = DQuat::from_rotation_y(ankle);
        }
        let w = self.w_body.at(t);
        let phase = self.stride_phase(t);
        out.rotations[rig.chest] =
            DQuat::from_rotation_y(w * g.lean_rad) * DQuat::from_rotation_z(w * self.cycle.twist.at(phase));
        for (i, side) in SIDES.into_iter().enumerate() {
            let ph = phase + 0.5 * i as f64;
            let flex = w * self.cycle.arm.at(ph);
            let elbow = (1.0 - w) * REST_ELBOW_RAD + w * self.cycle.elbow.at(ph);
            let abduction = side * REST_ARM_ABDUCTION_RAD;
            out.rotations[rig.arm[i]] = DQuat::from_rotation_y(flex) * DQuat::from_rotation_x(abduction);
            out.rotations[rig.fore_arm[i]] = DQuat::from_rotation_y(-elbow);
        }
    }

    /// Samples `[0, duration]` into a clip whose first frame stands at the origin facing +X.
    fn render(&self, duration: f64, frame_rate: f64, name: &str) -> Clip {
        let skeleton = actor::actor();
        let rig = Rig::of(&skeleton);
        let n = ((duration * frame_rate).round() as usize).max(1);
        let mut frames = Vec::with_capacity(n + 1);
        let mut pose = skeleton.bind_pose();
        for j in 0..=n {
            self.pose(&rig, duration * j as f64 / n as f64, &mut pose);
            frames.push(pose.clone());
        }
        let origin = Ground::of(&frames[0], 0.0);
        for f in &mut frames {
            origin.transform_pose(f, true);
        }
        Clip { name: name.into(), frame_time: duration / n as f64, frames }
    }
}

/// Height the toe tip keeps above the ground during a swing, metres.
const TOE_CLEARANCE_M: f64 = 0.02;

/// Elbow flexion standing still, radians.
const REST_ELBOW_RAD: f64 = 0.12;
/// Shoulder abduction standing still, radians.
const REST_ARM_ABDUCTION_RAD: f64 = 0.07;

/// The steady gait along a path turning by `turns[k]` at step `k`, from a left plant at time 0
/// (footprint `s = 0`) over `turns.len()` steps.
fn steady(gait: &Gait, turns: &[f64]) -> Motion {
    let (st, len, b) = (gait.step_time_s, gait.step_length_m(), gait.duty_factor);
    let n = turns.len() as i64;
    let path = Path::new(len, turns, 4);
    // Footprint k (left for even k) is planted at k·st and lifted 2β steps later.
    let fall = |k: i64| Footfall { s: k as f64 * len, plant: k as f64 * st, lift: (k as f64 + 2.0 * b) * st };
    let feet = [
        (-2..=n + 2).filter(|k| k % 2 == 0).map(fall).collect(),
        (-3..=n + 3).filter(|k| k % 2 != 0).map(fall).collect(),
    ];
    // The pelvis passes over a footprint at its mid-stance.
    let progress = Progress { t0: 0.0, s0: -b * len, v0: gait.speed_mps, v1: gait.speed_mps, ramp: 0.0 };
    let mut m = Motion {
        gait: gait.clone(),
        cycle: Cycle::of(gait),
        path,
        feet,
        progress,
        phase_origin: 0.0,
        height: 0.0,
        w_height: Ramp::ONE,
        w_sway: Ramp::ONE,
        w_body: Ramp::ONE,
        shift_m: 0.0,
        shift_in: Ramp::ONE,
        shift_out: Ramp::ONE,
    };
    m.fit_height(n as f64 * st);
    m
}

/// The steady gait along a path turning by `turns_rad[k]` radians at step `k`, as a clip that
/// starts on a left-foot plant at the origin facing +X and lasts `turns_rad.len()` steps
/// (rounded up to an even number by repeating the last turn, at least 2). Turns are to the left
/// for positive angles.
pub fn locomotion_path(gait: &Gait, turns_rad: &[f64], frame_rate: f64, name: &str) -> Clip {
    let mut turns: Vec<f64> = turns_rad.iter().map(|t| if t.is_finite() { *t } else { 0.0 }).collect();
    let last = turns.last().copied().unwrap_or(0.0);
    while turns.len() < 2 || !turns.len().is_multiple_of(2) {
        turns.push(last);
    }
    let m = steady(gait, &turns);
    m.render(turns.len() as f64 * gait.step_time_s, sane_rate(frame_rate), name)
}

/// The steady gait over `steps` steps (rounded up to an even number, at least 2) along a path
/// whose heading turns by `turn_per_step_rad` at every step (positive to the left), sampled at
/// `frame_rate` frames per second (rounded so the last frame falls on the final left plant). The
/// clip starts on a left-foot plant at the origin facing +X; its last frame is the first frame
/// of the next repetition. The gait should pass [`Gait::validate`]; other values give a valid
/// but implausible clip (or non-finite numbers for non-finite parameters).
pub fn locomotion(gait: &Gait, turn_per_step_rad: f64, steps: usize, frame_rate: f64, name: &str) -> Clip {
    locomotion_path(gait, &vec![turn_per_step_rad; steps.max(2)], frame_rate, name)
}

fn sane_rate(frame_rate: f64) -> f64 {
    if frame_rate.is_finite() && frame_rate >= 1.0 { frame_rate.min(1000.0) } else { FRAME_RATE_HZ }
}

/// From standing (feet together under the hips, planted) to the steady gait at a left plant:
/// the weight shifts, the right foot takes a half step, the left foot a full one. The last frame
/// equals the first frame of [`locomotion`] with the same gait.
pub fn start_clip(gait: &Gait) -> Clip {
    let (m, end) = start_motion(gait);
    m.render(end, FRAME_RATE_HZ, &format!("{}_start", gait.name))
}

/// The motion of [`start_clip`] and its duration.
fn start_motion(gait: &Gait) -> (Motion, f64) {
    let (st, len, b, v) = (gait.step_time_s, gait.step_length_m(), gait.duty_factor, gait.speed_mps);
    // Time to shift the weight before the pelvis moves, rounded so the clip ends on a frame.
    let end = ((0.6 * st + 2.0 * st) * FRAME_RATE_HZ).round() / FRAME_RATE_HZ;
    let t0 = end - 2.0 * st;
    // The pelvis reaches full speed (after β·L) as the left foot lifts off.
    let lift_left = t0 + 2.0 * b * st;
    let plant_right = end - st;
    let lift_right = (plant_right - (2.0 - 2.0 * b) * st).max(0.5 * t0);
    let far = 1e9;
    let mut m = steady(gait, &[0.0, 0.0]);
    let height = m.height;
    m.path = Path::new(len, &[0.0], 4);
    // After the first two steps the feet carry on in the steady gait.
    let steady = |k: f64, plant: f64| Footfall { s: k * len, plant, lift: plant + 2.0 * b * st };
    m.feet = [
        vec![Footfall { s: 0.0, plant: -far, lift: lift_left }, steady(2.0, end), steady(4.0, end + 2.0 * st)],
        vec![
            Footfall { s: 0.0, plant: -far, lift: lift_right },
            steady(1.0, plant_right),
            steady(3.0, plant_right + 2.0 * st),
        ],
    ];
    m.progress = Progress { t0, s0: 0.0, v0: 0.0, v1: v, ramp: 2.0 * b * st };
    m.phase_origin = end;
    m.height = height;
    m.w_height = Ramp { t0: 0.0, t1: plant_right.min(lift_left), from: 0.0, to: 1.0 };
    // The weight goes over the left foot before the right one lifts, then the sway takes over.
    m.w_sway = Ramp { t0: lift_right, t1: plant_right, from: 0.0, to: 1.0 };
    (m.shift_m, m.shift_in, m.shift_out) = (
        1.5 * gait.sway_m,
        Ramp { t0: 0.0, t1: lift_right, from: 0.0, to: 1.0 },
        Ramp { t0: lift_right, t1: plant_right, from: 1.0, to: 0.0 },
    );
    m.w_body = Ramp { t0: 0.0, t1: end, from: 0.0, to: 1.0 };
    (m, end)
}

/// From a left plant in the steady gait to standing: the right foot steps beside the left one
/// and the pelvis comes to rest over both. The first frame equals the first frame of
/// [`locomotion`]; the last one equals the first frame of [`idle_clip`].
pub fn stop_clip(gait: &Gait) -> Clip {
    let (m, end) = stop_motion(gait);
    m.render(end, FRAME_RATE_HZ, &format!("{}_stop", gait.name))
}

/// The motion of [`stop_clip`] and its duration.
fn stop_motion(gait: &Gait) -> (Motion, f64) {
    let (st, len, b, v) = (gait.step_time_s, gait.step_length_m(), gait.duty_factor, gait.speed_mps);
    let end = ((2.0 * b * st + 0.6 * st) * FRAME_RATE_HZ).round() / FRAME_RATE_HZ;
    let lift_right = (2.0 * b - 1.0) * st;
    let plant_right = lift_right + (2.0 - 2.0 * b) * st;
    let far = 1e9;
    let mut m = steady(gait, &[0.0, 0.0]);
    m.path = Path::new(len, &[0.0], 4);
    m.feet = [
        vec![Footfall { s: 0.0, plant: 0.0, lift: far }],
        vec![Footfall { s: -len, plant: -st, lift: lift_right }, Footfall { s: 0.0, plant: plant_right, lift: far }],
    ];
    // The pelvis stops over the feet after β·L.
    m.progress = Progress { t0: 0.0, s0: -b * len, v0: v, v1: 0.0, ramp: 2.0 * b * st };
    m.w_height = Ramp { t0: lift_right.max(0.0), t1: end, from: 1.0, to: 0.0 };
    m.w_sway = Ramp { t0: 0.5 * plant_right, t1: end, from: 1.0, to: 0.0 };
    m.w_body = Ramp { t0: 0.0, t1: end, from: 1.0, to: 0.0 };
    (m, end)
}

/// Standing still for `seconds` (at least one frame) with both feet planted under the hips and a
/// slight breathing bob of the pelvis (a whole number of breaths of about four seconds, so the
/// clip repeats seamlessly).
pub fn idle_clip(seconds: f64) -> Clip {
    let seconds = if seconds.is_finite() { seconds.clamp(1.0 / FRAME_RATE_HZ, 3600.0) } else { 4.0 };
    let breaths = (seconds / 4.0).round().max(1.0);
    let skeleton = actor::actor();
    let rig = Rig::of(&skeleton);
    // Standing: both feet planted for good, the pelvis at rest, no weight on any gait.
    let mut m = steady(&Gait::slow_walk(), &[0.0, 0.0]);
    let forever = Footfall { s: 0.0, plant: -1e9, lift: 1e9 };
    m.feet = [vec![forever], vec![forever]];
    m.progress = Progress { t0: 0.0, s0: 0.0, v0: 0.0, v1: 0.0, ramp: 0.0 };
    let zero = Ramp { t0: 0.0, t1: 1.0, from: 0.0, to: 0.0 };
    (m.w_height, m.w_sway, m.w_body) = (zero, zero, zero);
    let n = ((seconds * FRAME_RATE_HZ).round() as usize).max(1);
    let mut pose = skeleton.bind_pose();
    let frames = (0..=n)
        .map(|j| {
            let x = j as f64 / n as f64;
            m.pose(&rig, x * seconds, &mut pose);
            let breath = 0.5 * (1.0 - (2.0 * PI * breaths * x).cos());
            pose.root.z -= BREATH_M * breath;
            // The legs follow the pelvis down; the feet stay planted.
            for (i, side) in SIDES.into_iter().enumerate() {
                let hip = pose.root + DVec3::new(0.0, side * HIP_HALF_WIDTH_M, 0.0);
                let ankle = DVec3::new(0.0, side * HIP_HALF_WIDTH_M, ANKLE_HEIGHT_M);
                let (flex, abduction, knee) = leg_ik(ankle - hip);
                let hip_q = DQuat::from_rotation_y(flex) * DQuat::from_rotation_x(abduction);
                let knee_q = DQuat::from_rotation_y(knee);
                pose.rotations[rig.up_leg[i]] = hip_q;
                pose.rotations[rig.leg[i]] = knee_q;
                pose.rotations[rig.foot[i]] = DQuat::from_rotation_y(ankle_for_pitch(hip_q * knee_q, 0.0));
            }
            pose.rotations[rig.chest] = DQuat::from_rotation_y(0.01 * breath);
            pose.clone()
        })
        .collect();
    Clip { name: "idle".into(), frame_time: seconds / n as f64, frames }
}

/// Depth of the pelvis's breathing bob when standing, metres.
const BREATH_M: f64 = 0.004;

/// Turn angles per step of the turning clips of a gait, degrees, and how many steps its 90° turn
/// takes: the faster the gait, the gentler its turns.
fn turn_set(gait: &Gait) -> (&'static [u32], usize) {
    if gait.speed_mps > 4.5 {
        (&[5, 10, 15], 6)
    } else if gait.speed_mps > 3.0 {
        (&[10, 20, 30], 4)
    } else {
        (&[15, 30, 45], 2)
    }
}

/// Steps per clip of the default database.
pub const DEFAULT_STEPS: usize = 6;

/// The default animation database at 60 Hz: for every preset gait a straight clip, left and
/// right turns at three rates (±15°, ±30°, ±45° per step for walking and jogging, ±10–30° for
/// running, ±5–15° for sprinting), and a ±90° turn spread over two steps (four when running, six
/// when sprinting) between two straight steps on each side; start and stop clips for the walk
/// and the slow walk; and a standing idle. Right turns mirror the left ones, so they start on a
/// right-foot plant. Names: `walk_straight`, `walk_left15`, `walk_right15`, `jog_left90`,
/// `walk_start`, `walk_stop`, `idle`, …
pub fn default_clips() -> Vec<Clip> {
    let pairs = mirror_pairs(&actor::actor());
    let mut clips = Vec::new();
    for gait in Gait::presets() {
        let name = &gait.name;
        clips.push(locomotion(&gait, 0.0, DEFAULT_STEPS, FRAME_RATE_HZ, &format!("{name}_straight")));
        let (rates, turn90) = turn_set(&gait);
        for &deg in rates {
            let left = locomotion(
                &gait,
                f64::from(deg).to_radians(),
                DEFAULT_STEPS,
                FRAME_RATE_HZ,
                &format!("{name}_left{deg}"),
            );
            let right = left.mirrored(&pairs, format!("{name}_right{deg}"));
            clips.extend([left, right]);
        }
        let mut turns = vec![0.0; 2];
        turns.extend(std::iter::repeat_n(90f64.to_radians() / turn90 as f64, turn90));
        turns.extend([0.0; 2]);
        let left = locomotion_path(&gait, &turns, FRAME_RATE_HZ, &format!("{name}_left90"));
        let right = left.mirrored(&pairs, format!("{name}_right90"));
        clips.extend([left, right]);
    }
    for gait in [Gait::slow_walk(), Gait::walk()] {
        clips.push(start_clip(&gait));
        clips.push(stop_clip(&gait));
    }
    // Turning on the spot: short shuffling steps that turn the body where it stands.
    let shuffle = Gait::shuffle();
    for deg in [30u32, 45] {
        let left = locomotion(
            &shuffle,
            f64::from(deg).to_radians(),
            DEFAULT_STEPS,
            FRAME_RATE_HZ,
            &format!("shuffle_left{deg}"),
        );
        let right = left.mirrored(&pairs, format!("shuffle_right{deg}"));
        clips.extend([left, right]);
    }
    clips.push(idle_clip(4.0));
    clips
}

#[cfg(test)]
mod tests {
    use glam::EulerRot;

    use super::*;
    use crate::anim::skeleton::{Channel, angle_between, heading};

    /// Global ankle positions and toe tips of both feet in every frame.
    fn feet(clip: &Clip) -> Vec<[(DVec3, DVec3); 2]> {
        let s = actor::actor();
        let rig = Rig::of(&s);
        let mut g = Vec::new();
        clip.frames
            .iter()
            .map(|f| {
                s.globals(f, &mut g);
                [0, 1].map(|i| (g[rig.foot[i]].0, s.tip(&g, rig.foot[i])))
            })
            .collect()
    }

    /// Per frame and foot: planted (at standing ankle height and not moving until the next
    /// frame).
    fn contacts(clip: &Clip) -> Vec<[bool; 2]> {
        let f = feet(clip);
        (0..f.len())
            .map(|j| {
                let k = (j + 1).min(f.len() - 1);
                [0, 1].map(|i| {
                    let (a, b) = (f[j][i].0, f[k][i].0);
                    a.z < ANKLE_HEIGHT_M + 5e-4 && (a - b).truncate().length() < 1e-4
                })
            })
            .collect()
    }

    /// Foot plants (a foot coming to rest on the ground) after the first frame.
    fn plants(clip: &Clip) -> usize {
        let c = contacts(clip);
        c.windows(2).map(|w| (0..2).filter(|&i| w[1][i] && !w[0][i]).count()).sum()
    }

    fn relative(pose: &Pose) -> Pose {
        let mut p = pose.clone();
        Ground::of(pose, 0.0).transform_pose(&mut p, true);
        p
    }

    fn same_relative_pose(a: &Pose, b: &Pose, tol: f64) -> Result<(), String> {
        let (a, b) = (relative(a), relative(b));
        if (a.root - b.root).length() > tol {
            return Err(format!("roots {} vs {}", a.root, b.root));
        }
        for (j, (qa, qb)) in a.rotations.iter().zip(&b.rotations).enumerate() {
            if angle_between(*qa, *qb) > tol {
                return Err(format!("joint {j}: {qa} vs {qb}"));
            }
        }
        Ok(())
    }

    /// Total heading change over a clip, unwrapped frame to frame, radians.
    fn turned(clip: &Clip) -> f64 {
        clip.frames.windows(2).map(|w| wrap_angle(heading(w[1].rotations[0]) - heading(w[0].rotations[0]))).sum()
    }

    #[test]
    fn key_curves_pass_through_their_keys_without_overshoot() {
        let c = KeyCurve::periodic(&[(0.9, -1.0), (0.1, 0.5), (0.3, 1.0), (0.6, 0.0)]);
        for &(p, v) in &[(0.9, -1.0), (0.1, 0.5), (0.3, 1.0), (0.6, 0.0), (1.9, -1.0)] {
            assert!((c.at(p) - v).abs() < 1e-12, "{p}: {}", c.at(p));
        }
        for j in 0..=1000 {
            let v = c.at(j as f64 / 1000.0);
            assert!((-1.0..=1.0).contains(&v));
        }
        // Continuous across the wrap and monotone between keys.
        assert!((c.at(1.0 - 1e-9) - c.at(0.0)).abs() < 1e-6);
        let o = KeyCurve::open(&[(0.0, 0.0), (0.5, 1.0), (1.0, -1.0)]);
        assert_eq!((o.at(-1.0), o.at(0.5), o.at(2.0)), (0.0, 1.0, -1.0));
        assert!((0..100).all(|j| o.at(0.5 * j as f64 / 100.0) <= o.at(0.5 * (j + 1) as f64 / 100.0) + 1e-12));
    }

    #[test]
    fn leg_inverse_kinematics_reaches_its_targets() {
        let s = actor::actor();
        let rig = Rig::of(&s);
        let mut pose = s.bind_pose();
        let hip = s.positions(&pose)[rig.up_leg[0]];
        for &(x, y, z, pitch) in &[
            (0.3, 0.05, -0.75, -0.2),
            (-0.35, -0.04, -0.8, 0.0),
            (0.0, 0.0, -0.6, 0.4),
            (0.2, 0.1, -0.5, 0.6),
            (-0.2, 0.0, -0.4, 0.3),
        ] {
            let d = DVec3::new(x, y, z);
            let (flex, abduction, knee) = leg_ik(d);
            let hip_q = DQuat::from_rotation_y(flex) * DQuat::from_rotation_x(abduction);
            let knee_q = DQuat::from_rotation_y(knee);
            pose.rotations[rig.up_leg[0]] = hip_q;
            pose.rotations[rig.leg[0]] = knee_q;
            pose.rotations[rig.foot[0]] = DQuat::from_rotation_y(ankle_for_pitch(hip_q * knee_q, pitch));
            let mut g = Vec::new();
            s.globals(&pose, &mut g);
            let (ankle, foot_q) = g[rig.foot[0]];
            assert!((ankle - hip - d).length() < 1e-9, "target {d}: reached {}", ankle - hip);
            assert!(knee >= 0.0, "the knee bends backward");
            assert!(((foot_q * DVec3::X).z + pitch.sin()).abs() < 1e-9, "foot pitch for {pitch}");
            // A target in front flexes the hip forward (negative Y): the knee is ahead of the hip.
            if x > 0.1 {
                assert!(flex < 0.0 && g[rig.leg[0]].0.x > hip.x);
            }
        }
        // Out of reach: the straight leg points at the target.
        let (flex, abduction, knee) = leg_ik(DVec3::new(0.5, 0.0, -1.0));
        assert_eq!(knee, 0.0);
        assert!(abduction.abs() < 1e-12 && (flex + 0.5f64.atan2(1.0)).abs() < 1e-12);
    }

    /// Largest distance of a planted ankle from its footprint and of a swinging ankle from its
    /// Bezier curve (where the leg is too short for it) over `[0, duration]`.
    fn ankle_errors(m: &Motion, duration: f64) -> (f64, f64) {
        let s = actor::actor();
        let rig = Rig::of(&s);
        let mut pose = s.bind_pose();
        let (mut planted, mut swing) = (0.0f64, 0.0f64);
        for j in 0..=(duration * 240.0) as usize {
            let t = j as f64 / 240.0;
            m.pose(&rig, t, &mut pose);
            let p = s.positions(&pose);
            for i in 0..2 {
                let f = m.foot(i, t);
                let e = (p[rig.foot[i]] - f.ankle).length();
                if f.planted { planted = planted.max(e) } else { swing = swing.max(e) }
            }
        }
        (planted, swing)
    }

    #[test]
    fn planted_ankles_stay_on_their_footprints() {
        let mut motions = Vec::new();
        for g in Gait::presets() {
            let sharp = if g.is_running() { -0.5 } else { -0.8 };
            for turn in [0.0, 0.25, sharp] {
                motions.push((format!("{} {turn}", g.name), steady(&g, &[turn; 4]), 4.0 * g.step_time_s));
            }
            let (start, stop) = (start_motion(&g), stop_motion(&g));
            motions.push((format!("{} start", g.name), start.0, start.1));
            motions.push((format!("{} stop", g.name), stop.0, stop.1));
        }
        for (name, m, duration) in &motions {
            let (planted, swing) = ankle_errors(m, *duration);
            assert!(planted < 1e-9, "{name}: planted ankle off by {planted} m");
            assert!(swing < 0.05, "{name}: swinging ankle off its curve by {swing} m");
        }
    }

    #[test]
    fn walking_stance_ankles_do_not_slide() {
        let clip = locomotion(&Gait::walk(), 0.0, 6, FRAME_RATE_HZ, "w");
        let f = feet(&clip);
        let (mut sum, mut n) = (0.0, 0);
        for i in 0..2 {
            let lowest = f.iter().map(|p| p[i].0.z).fold(f64::INFINITY, f64::min);
            for w in f.windows(2) {
                let d = (w[1][i].0 - w[0][i].0).truncate().length();
                if w[0][i].0.z < lowest + 0.025 && d < 0.01 {
                    sum += d;
                    n += 1;
                }
            }
        }
        let mean = sum / n as f64;
        assert!(n > 100 && mean < 0.0005, "{n} stance frames slide {mean} m on average");
        // Exactly planted frames do not move at all.
        let c = contacts(&clip);
        let planted: usize = c.iter().map(|c| c.iter().filter(|&&x| x).count()).sum();
        assert!(planted as f64 > 0.55 * 2.0 * clip.frames.len() as f64);
    }

    #[test]
    fn walking_has_double_support_and_running_has_flight() {
        for gait in Gait::presets() {
            let clip = locomotion(&gait, 0.0, 4, FRAME_RATE_HZ, "g");
            let c = contacts(&clip);
            let both = c.iter().filter(|c| c[0] && c[1]).count();
            let none = c.iter().filter(|c| !c[0] && !c[1]).count();
            if gait.is_running() {
                assert!(none > 0 && both == 0, "{}: {none} flight frames, {both} double", gait.name);
            } else {
                assert!(none == 0 && both > 0, "{}: {none} flight frames, {both} double", gait.name);
            }
            // Feet alternate: the left foot plants at the first frame, the right one a step later.
            let step = (gait.step_time_s / clip.frame_time).round() as usize;
            assert!(c[0][0] && c[step][1]);
            assert!(!c[step.saturating_sub(3)][1] || !gait.is_running());
        }
    }

    #[test]
    fn default_clips_are_sane() {
        let clips = default_clips();
        let s = actor::actor();
        let mut names: Vec<&str> = clips.iter().map(|c| c.name.as_str()).collect();
        for n in [
            "walk_straight",
            "walk_left15",
            "walk_right45",
            "jog_left90",
            "sprint_right90",
            "walk_start",
            "walk_stop",
            "slow_walk_start",
            "idle",
        ] {
            assert!(names.contains(&n), "{n} missing");
        }
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), clips.len(), "names are unique");
        let mut steps = 0;
        for clip in &clips {
            assert!(clip.frames.len() > 10 && clip.frame_time > 0.0 && clip.frame_time <= 1.0 / 59.0);
            for (j, f) in clip.frames.iter().enumerate() {
                assert!(f.root.is_finite(), "{} frame {j}", clip.name);
                assert_eq!(f.rotations.len(), s.len());
                for q in &f.rotations {
                    assert!(q.is_finite() && (q.length() - 1.0).abs() < 1e-9, "{} frame {j}: {q}", clip.name);
                }
            }
            for (j, p) in feet(clip).iter().enumerate() {
                for (ankle, toe) in p {
                    assert!(
                        ankle.z >= ANKLE_HEIGHT_M - 1e-9 && toe.z >= -0.001,
                        "{} frame {j}: {ankle} {toe}",
                        clip.name
                    );
                }
                // The swinging foot passes beside the planted one, never through it.
                let apart = (p[0].0 - p[1].0).truncate().length();
                assert!(apart > 0.09, "{} frame {j}: ankles {apart} m apart", clip.name);
            }
            steps += plants(clip);
        }
        assert!(steps >= 200, "{steps} steps");
        assert_eq!(steps, 5 * 7 * DEFAULT_STEPS + 2 * (6 + 6 + 6 + 8 + 10) + 2 * 3 + 4 * DEFAULT_STEPS);
    }

    #[test]
    fn rotations_use_only_the_actor_channels() {
        let s = actor::actor();
        let clips = [locomotion(&Gait::run(), 0.3, 2, 60.0, "r"), start_clip(&Gait::walk()), idle_clip(2.0)];
        for (i, joint) in s.joints().iter().enumerate() {
            let axes: Vec<Channel> = joint.channels.iter().copied().filter(|c| !c.is_position()).collect();
            let (order, used) = match axes.as_slice() {
                [] => (EulerRot::YXZ, 0),
                [Channel::ZRotation] => (EulerRot::ZXY, 1),
                [Channel::YRotation] => (EulerRot::YXZ, 1),
                [Channel::YRotation, Channel::XRotation] => (EulerRot::YXZ, 2),
                [Channel::YRotation, Channel::ZRotation] => (EulerRot::YZX, 2),
                [Channel::YRotation, Channel::XRotation, Channel::ZRotation] => (EulerRot::YXZ, 3),
                other => panic!("unexpected channels {other:?}"),
            };
            for clip in &clips {
                for f in &clip.frames {
                    let q = f.rotations[i];
                    let (a, b, c) = q.to_euler(order);
                    let mut e = [a, b, c];
                    e[used..].iter_mut().for_each(|x| *x = 0.0);
                    let back = DQuat::from_euler(order, e[0], e[1], e[2]);
                    assert!(angle_between(q, back) < 1e-7, "{} in {}: {q}", joint.name, clip.name);
                }
            }
        }
    }

    #[test]
    fn straight_clips_keep_the_gait_speed() {
        for gait in Gait::presets() {
            let clip = locomotion(&gait, 0.0, 6, FRAME_RATE_HZ, "s");
            let (first, last) = (clip.frames[0].root, clip.frames.last().unwrap().root);
            let speed = (last - first).truncate().length() / clip.duration();
            let path: f64 = clip.frames.windows(2).map(|w| (w[1].root - w[0].root).truncate().length()).sum();
            for v in [speed, path / clip.duration()] {
                assert!((v / gait.speed_mps - 1.0).abs() < 0.05, "{}: {v} m/s", gait.name);
            }
            assert!((clip.duration() - 6.0 * gait.step_time_s).abs() < 1e-9);
            assert!((last.y - first.y).abs() < 1e-9, "straight ahead along +X");
        }
    }

    #[test]
    fn turning_clips_turn_by_the_requested_angle() {
        for (gait, deg) in
            [(Gait::walk(), 15.0), (Gait::slow_walk(), -45.0), (Gait::jog(), 30.0), (Gait::sprint(), 10.0)]
        {
            let clip = locomotion(&gait, f64::to_radians(deg), 6, FRAME_RATE_HZ, "t");
            let total = turned(&clip).to_degrees();
            assert!((total - 6.0 * deg).abs() < 1.0, "{}: {total}° for {deg}°/step", gait.name);
        }
        let clips = default_clips();
        let find = |n: &str| clips.iter().find(|c| c.name == n).unwrap();
        for (name, deg) in
            [("walk_left90", 90.0), ("run_right90", -90.0), ("jog_right30", -180.0), ("sprint_left15", 90.0)]
        {
            let total = turned(find(name)).to_degrees();
            assert!((total - deg).abs() < 1.0, "{name}: {total}°");
        }
    }

    #[test]
    fn clips_repeat_seamlessly() {
        for (gait, turn) in [(Gait::walk(), 0.0), (Gait::walk(), 0.5), (Gait::run(), -0.3), (Gait::slow_walk(), 0.78)] {
            let clip = locomotion(&gait, turn, 4, FRAME_RATE_HZ, "p");
            same_relative_pose(&clip.frames[0], clip.frames.last().unwrap(), 1e-6).unwrap();
            // Half-way it is the right foot's turn, not the same pose.
            assert!(same_relative_pose(&clip.frames[0], &clip.frames[clip.frames.len() / 4], 1e-3).is_err());
        }
        for clip in default_clips().iter().filter(|c| !c.name.ends_with("start") && !c.name.ends_with("stop")) {
            same_relative_pose(&clip.frames[0], clip.frames.last().unwrap(), 1e-6)
                .map_err(|e| format!("{}: {e}", clip.name))
                .unwrap();
        }
    }

    #[test]
    fn start_and_stop_join_standing_and_the_gait() {
        let idle = idle_clip(4.0);
        for gait in [Gait::walk(), Gait::slow_walk()] {
            let walk = locomotion(&gait, 0.0, 2, FRAME_RATE_HZ, "w");
            let (start, stop) = (start_clip(&gait), stop_clip(&gait));
            same_relative_pose(&idle.frames[0], &start.frames[0], 1e-6).unwrap();
            same_relative_pose(start.frames.last().unwrap(), &walk.frames[0], 1e-6).unwrap();
            same_relative_pose(&stop.frames[0], &walk.frames[0], 1e-6).unwrap();
            same_relative_pose(stop.frames.last().unwrap(), &idle.frames[0], 1e-6).unwrap();
            assert!((start.frame_time - 1.0 / FRAME_RATE_HZ).abs() < 1e-12);
            assert_eq!((plants(&start), plants(&stop)), (2, 1));
            // Moving forward only, ending (or starting) at the gait speed.
            let v = |c: &Clip, j: usize| (c.frames[j + 1].root.x - c.frames[j].root.x) / c.frame_time;
            assert!((v(&start, start.frames.len() - 2) / gait.speed_mps - 1.0).abs() < 0.05);
            assert!((v(&stop, 0) / gait.speed_mps - 1.0).abs() < 0.05);
            assert!(start.frames.windows(2).chain(stop.frames.windows(2)).all(|w| w[1].root.x >= w[0].root.x - 1e-12));
        }
        assert_eq!(plants(&idle), 0);
        assert!(contacts(&idle).iter().all(|c| c[0] && c[1]));
        same_relative_pose(&idle.frames[0], idle.frames.last().unwrap(), 1e-6).unwrap();
        let z: Vec<f64> = idle.frames.iter().map(|f| f.root.z).collect();
        let (lo, hi) = z.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &z| (a.min(z), b.max(z)));
        assert!(hi - lo > 0.002 && hi - lo < 0.01 && (0.93..=0.95).contains(&hi));
    }

    #[test]
    fn generation_is_deterministic_and_mirrors_pair_up() {
        let (a, b) = (default_clips(), default_clips());
        assert_eq!(a, b);
        let pairs = mirror_pairs(&actor::actor());
        let left = a.iter().find(|c| c.name == "walk_left30").unwrap();
        let right = a.iter().find(|c| c.name == "walk_right30").unwrap();
        assert_eq!(&left.mirrored(&pairs, "walk_right30".into()), right);
        // The mirrored clip starts on a right plant: the left foot lifts off first.
        let c = contacts(right);
        let lift = |i: usize| c.iter().position(|c| !c[i]).unwrap();
        assert!(c[0][1] && lift(0) < lift(1));
    }

    #[test]
    fn gaits_validate() {
        for g in Gait::presets() {
            g.validate().unwrap();
            assert!(g.cadence_spm() > 95.0 && g.cadence_spm() < 230.0);
            assert_eq!(g.is_running(), g.speed_mps > 2.0);
        }
        let mut g = Gait::walk();
        g.duty_factor = f64::NAN;
        assert!(matches!(g.validate(), Err(GaitError::OutOfRange { field: "duty_factor", .. })));
        let speeds: Vec<f64> = Gait::presets().iter().map(|g| g.speed_mps).collect();
        assert_eq!(speeds, [0.8, 1.35, 2.5, 3.6, 5.5]);
        // Odd step counts are rounded up; bad frame rates fall back to 60 Hz.
        let clip = locomotion(&Gait::walk(), 0.0, 3, f64::NAN, "x");
        assert!((clip.duration() - 4.0 * Gait::walk().step_time_s).abs() < 1e-9);
        assert!((clip.frame_time - 1.0 / 60.0).abs() < 1e-9);
    }
}
