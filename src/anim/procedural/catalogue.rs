//! The clip catalogue of the built-in animation database (seed 002 §4.1 walk generation;
//! DESIGN.md §3–4): every clip starts on a foot plant and its intervals — foot plant to foot
//! plant, as the database cuts them — are distinct motions. Every clip with a side has its
//! exact left–right mirror, named with `left`/`right` swapped, or with an `_r` suffix (the
//! mirror starts on the other foot) for clips without a side in their name.
//!
//! | clips | what for |
//! |---|---|
//! | `{gait}_straight` | the steady gait straight ahead, one stride (two steps) from a left plant; symmetric (its right step mirrors its left one), so one clip serves both feet |
//! | `{gait}_left{d}`, `{gait}_right{d}` | the steady gait turning `d`° per step, six steps: slow walk 15, 30, 45, 60 (and `slow_walk_sharp_left90`, `slow_walk_sharp_right90`: 90° per step); walk 15, 30, 45, 60; jog 15, 30, 45; run 10, 20, 30; sprint 5, 10, 15 |
//! | `{gait}_left90`, `{gait}_right90` | a 90° turn between two straight steps on each side, over two steps (walks and jog), four (run) or six (sprint) |
//! | `walk_start`, `slow_walk_start` (`_r`) | standing still to the steady gait: the left foot (right for `_r`) takes a half step, the other a full one |
//! | `walk_stop`, `slow_walk_stop` (`_r`) | from a left (right) plant of the steady gait to standing in two steps: a half step, then the feet side by side |
//! | `{gait}_start_left45`, `{gait}_start_left90` (`_right45`, `_right90`) | slow walk and walk: standing still to the steady gait heading 45° or 90° to the left (right) of where the body stood: it pivots on the ball of the right (left) foot while the left (right) foot steps out in the new direction, then the other foot takes a full step; ends on a right (left) plant |
//! | `{gait}_stop_left90` (`_right90`) | slow walk and walk: from a left (right) plant of the steady gait to standing turned 90° toward the planted foot in one step — a spin turn: the body pivots on the ball of the planted foot while the other leg swings around and lands beside it |
//! | `{gait}_stop_step_right90` (`_step_left90`) | from a left (right) plant to standing turned 90° away from the planted foot in two steps — a step turn: the body pivots 45° on the ball of the planted foot while the other foot steps out in the new direction, then 45° on the ball of that foot while the first one closes beside it |
//! | `{gait}_stop_left180` (`_right180`) | from a left (right) plant to standing turned 180° toward the planted foot in two steps: a spin turn of 90° on the planted foot, then 90° more on the ball of the other foot while the first one steps around behind it |
//! | `slow_walk_to_walk`, `walk_to_slow_walk` (`_r`) | two steps from a left (right) plant of one walk to a left (right) plant of the other |
//! | `pivot_left45`, `pivot_left90`, `pivot_left135` (`_right…`) | turning on the spot from standing to standing: the inside foot steps while the body pivots on the ball of the other foot, then the feet close (with turn warping, 15° to 200°) |
//! | `side_step_left` (`_right`), `step_back` (`_r`) | from standing to standing 0.3 m to the left (right) or back, facing the same way: the leading foot steps out, the other follows to stand beside it |
//! | `idle` | standing still, breathing; symmetric |
//!
//! Start, stop and pivot clips, turning or not, begin or end exactly in the idle's first pose
//! (turned by their angle), and starts, stops and speed changes begin or end exactly in a plant
//! of the steady gaits, so the database's natural successors join them without a jump. The
//! hips cannot twist: turning starts and stops turn the body only while each planted foot
//! stands on its ball (or its heel) alone, and every planted heel or toe stays where it is
//! while it carries weight.

use std::f64::consts::PI;

use glam::DVec2;
use rayon::prelude::*;

use super::curves::{KeyCurve, Ramp};
use super::gait::Gait;
use super::motion::{
    Footfall, Height, Late, Layer, Motion, NEVER_AFTER, NEVER_BEFORE, Path, Progress, Window, on_frame, standing_knee,
};
use super::{FRAME_RATE_HZ, STANDING_PELVIS_M};
use crate::anim::actor::{self, FOOT_FORWARD_M, HIP_HALF_WIDTH_M};
use crate::anim::clip::{Clip, mirror_pairs};

/// Steps per turning clip of the default database.
pub const DEFAULT_STEPS: usize = 6;

/// Steps per straight clip of the default database: one stride, so that its two intervals are
/// each other's mirror and nothing in the database repeats.
pub const STRAIGHT_STEPS: usize = 2;

/// How far a side step or a step back moves the body, metres.
pub const SHUFFLE_M: f64 = 0.3;

/// Depth of the pelvis's breathing bob when standing, metres.
const BREATH_M: f64 = 0.004;

fn sane_rate(frame_rate: f64) -> f64 {
    if frame_rate.is_finite() && frame_rate >= 1.0 { frame_rate.min(1000.0) } else { FRAME_RATE_HZ }
}

/// The support windows of footfalls `ks`: each from touch-down to its release.
fn leg_windows(feet: &[Footfall], ks: impl IntoIterator<Item = usize>) -> Vec<Window> {
    ks.into_iter().map(|k| Window { t0: feet[k].t_on, t1: feet[k].t_release, height: Height::Leg(k) }).collect()
}

/// The steady gait along a path turning by `turns[k]` at step `k`: footprint `k` (left for even
/// `k`) touches down at `k` step times, the left one at time 0 on the origin.
fn steady(gait: &Gait, turns: &[f64]) -> Motion {
    let (st, len) = (gait.step_time_s, gait.step_length_m());
    let n = turns.len() as i64;
    let path = Path::new(len, turns, 6);
    let feet: Vec<Footfall> = (-4..=n + 4)
        .map(|k| {
            let side = k.rem_euclid(2) as usize;
            let ground = path.beside(k as f64 * len, [1.0, -1.0][side], gait.foot_offset_m);
            Footfall::steady(gait, side, ground, k as f64 * st)
        })
        .collect();
    let windows = leg_windows(&feet, 0..feet.len());
    let progress = Progress::steady(-gait.strike_distance_m(), gait.speed_mps);
    let layers = vec![Layer::new(gait, 0.0, Ramp::constant(1.0))];
    Motion::new(path, progress, feet, windows, layers).finish(0.0, n as f64 * st)
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
    m.render(0.0, turns.len() as f64 * gait.step_time_s, sane_rate(frame_rate), name)
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

/// The knee curve of a foot standing still: slightly less bent than standing, so that standing
/// feet stay flat.
fn standing_knee_curve() -> KeyCurve {
    KeyCurve::constant(standing_knee() - 0.01)
}

/// From standing (feet side by side under the hips) to the steady gait: the left foot lifts
/// its heel and takes a half step, the right one a full step; the clip ends on that right plant,
/// whose pose is the steady gait's. Its first frame is the first frame of [`idle_clip`].
pub fn start_clip(gait: &Gait) -> Clip {
    let (m, end) = start_motion(gait);
    m.render(0.0, end, FRAME_RATE_HZ, &format!("{}_start", gait.name))
}

fn start_motion(gait: &Gait) -> (Motion, f64) {
    let (st, len, v, d) = (gait.step_time_s, gait.step_length_m(), gait.speed_mps, gait.strike_distance_m());
    let path = Path::straight();
    let swing = 2.0 * st * (1.0 - gait.duty_factor);
    let lift = 0.36;
    let t_l1 = on_frame(lift + swing);
    let t_r1 = t_l1 + st;
    let first = 0.5 * len;
    // The pelvis starts moving at t0 and reaches the gait speed at the right plant, where it
    // must be where the steady gait has it.
    let ramp = 2.0 * (first + len - d) / v;
    let t0 = t_r1 - ramp;
    let progress = Progress { t0, s0: 0.0, v0: 0.0, v1: v, ramp };
    let side = |i: usize| [1.0, -1.0][i];
    let stand = standing_knee_curve();
    let ds = (2.0 * gait.duty_factor - 1.0).max(0.0) * st;
    let mut r0 = Footfall::standing(
        1,
        path.beside(0.0, side(1), HIP_HALF_WIDTH_M),
        0.0,
        KeyCurve::open(&[
            (0.0, standing_knee() - 0.01),
            (lift, standing_knee() - 0.01),
            (t_l1 - 0.1, gait.knee_mid_rad),
            (t_l1, gait.knee_mid_rad + 0.3 * (gait.knee_toe_off_rad - gait.knee_mid_rad)),
            (t_l1 + ds, gait.knee_toe_off_rad),
        ]),
        0.0,
        t_l1 + ds,
        Late::Solve,
    );
    r0.swing_height = gait.swing_height_m;
    let l0 = Footfall::standing(
        0,
        path.beside(0.0, side(0), HIP_HALF_WIDTH_M),
        0.0,
        stand,
        0.0,
        lift,
        Late::Pitch(KeyCurve::open(&[(0.1, 0.0), (lift, 0.55)])),
    );
    let l1 = Footfall::steady(gait, 0, path.beside(first, side(0), gait.foot_offset_m), t_l1);
    let r1 = Footfall::steady(gait, 1, path.beside(first + len, side(1), gait.foot_offset_m), t_r1);
    let l2 = Footfall::steady(gait, 0, path.beside(first + 2.0 * len, side(0), gait.foot_offset_m), t_r1 + st);
    let feet = vec![l0, r0, l1, r1, l2];
    let mut windows =
        vec![Window { t0: NEVER_BEFORE, t1: 0.2, height: Height::Level(KeyCurve::constant(STANDING_PELVIS_M)) }];
    windows.extend(leg_windows(&feet, [2, 3, 4]));
    let layers = vec![Layer::new(gait, t_l1, Ramp::new(0.15, t_r1, 0.0, 1.0))];
    let mut m = Motion::new(path, progress, feet, windows, layers);
    // The weight goes over the right foot before the left one lifts.
    m.shift = KeyCurve::open(&[(0.0, 0.0), (0.3, -0.025), (t_l1, 0.0)]);
    (m.finish(0.0, t_r1), t_r1)
}

/// From standing (feet side by side under the hips) to the steady gait heading `turn_rad` from
/// where it stood (positive to the left; the mirror clip turns to the right): the body pivots on
/// the ball of the right foot while the left foot lifts and steps out in the new direction, then
/// the right foot takes a full step; the clip ends on that right plant, whose pose is the steady
/// gait's. Its first frame is the first frame of [`idle_clip`].
pub fn turning_start_clip(gait: &Gait, turn_rad: f64, name: &str) -> Clip {
    let (m, end) = turning_start_motion(gait, turn_rad.abs());
    let clip = m.render(0.0, end, FRAME_RATE_HZ, name);
    if turn_rad < 0.0 { clip.mirrored(&mirror_pairs(&actor::actor()), name.into()) } else { clip }
}

fn turning_start_motion(gait: &Gait, turn: f64) -> (Motion, f64) {
    let (st, len, v, d) = (gait.step_time_s, gait.step_length_m(), gait.speed_mps, gait.strike_distance_m());
    // The path runs along +X; the body stands turned by −turn and turns onto it.
    let path = Path::straight();
    let (_, side_0) = axes(-turn);
    let swing = 2.0 * st * (1.0 - gait.duty_factor);
    let lift = 0.36;
    let t_l1 = on_frame(lift + swing + 0.1 * turn / (PI / 2.0));
    let t_r1 = t_l1 + st;
    let first = 0.5 * len;
    // The pelvis starts moving at t0 and reaches the gait speed at the right plant, where it
    // must be where the steady gait has it.
    let ramp = 2.0 * (first + len - d) / v;
    let t0 = t_r1 - ramp;
    let progress = Progress { t0, s0: 0.0, v0: 0.0, v1: v, ramp };
    let stand = standing_knee() - 0.01;
    let ds = (2.0 * gait.duty_factor - 1.0).max(0.0) * st;
    // The right heel rises just enough for the foot to turn about its ball.
    let pivot = 0.22;
    let turn_a = 0.22;
    let mut r0 = Footfall::standing(
        1,
        -HIP_HALF_WIDTH_M * side_0,
        -turn,
        KeyCurve::open(&[
            (0.0, stand),
            (lift, stand),
            (t_l1 - 0.1, gait.knee_mid_rad),
            (t_l1, gait.knee_mid_rad + 0.3 * (gait.knee_toe_off_rad - gait.knee_mid_rad)),
            (t_l1 + ds, gait.knee_toe_off_rad),
        ]),
        0.0,
        t_l1 + ds,
        Late::AtLeast(KeyCurve::open(&[(0.05, 0.0), (turn_a, pivot)])),
    );
    r0.swing_height = gait.swing_height_m;
    let l0 = Footfall::standing(
        0,
        HIP_HALF_WIDTH_M * side_0,
        -turn,
        KeyCurve::constant(stand),
        0.0,
        lift,
        Late::Pitch(KeyCurve::open(&[(0.08, 0.0), (lift, 0.55)])),
    );
    let l1 = Footfall::steady(gait, 0, path.beside(first, 1.0, gait.foot_offset_m), t_l1);
    let r1 = Footfall::steady(gait, 1, path.beside(first + len, -1.0, gait.foot_offset_m), t_r1);
    let l2 = Footfall::steady(gait, 0, path.beside(first + 2.0 * len, 1.0, gait.foot_offset_m), t_r1 + st);
    let feet = vec![l0, r0, l1, r1, l2];
    let mut windows =
        vec![Window { t0: NEVER_BEFORE, t1: 0.2, height: Height::Level(KeyCurve::constant(STANDING_PELVIS_M)) }];
    windows.extend(leg_windows(&feet, [2, 3, 4]));
    let layers = vec![Layer::new(gait, t_l1, Ramp::new(0.15, t_r1, 0.0, 1.0))];
    let mut m = Motion::new(path, progress, feet, windows, layers);
    m.turn = KeyCurve::open(&[(turn_a, -turn), (t_l1 - 0.02, 0.0)]);
    // The weight goes over the right foot before the left one lifts.
    m.shift = KeyCurve::open(&[(0.0, 0.0), (0.3, -0.025), (t_l1, 0.0)]);
    (m.finish(0.0, t_r1), t_r1)
}

/// From a left plant of the steady gait to standing in two steps: the right foot takes a half
/// step, the left one closes beside it and the pelvis comes to rest over both. The first frame
/// is the steady gait's left plant; the last one is the first frame of [`idle_clip`].
pub fn stop_clip(gait: &Gait) -> Clip {
    let (m, end) = stop_motion(gait);
    m.render(0.0, end, FRAME_RATE_HZ, &format!("{}_stop", gait.name))
}

fn stop_motion(gait: &Gait) -> (Motion, f64) {
    let (st, len, v, d) = (gait.step_time_s, gait.step_length_m(), gait.speed_mps, gait.strike_distance_m());
    let path = Path::straight();
    let side = |i: usize| [1.0, -1.0][i];
    let last = 0.5 * len;
    let stance = gait.stance_time_s();
    let swing = 2.0 * st * (1.0 - gait.duty_factor);
    let t_l2 = on_frame(stance + swing);
    let end = on_frame(t_l2 + 0.3);
    // The pelvis slows down to stop over the feet.
    let ramp = 0.8 * t_l2;
    let t0 = (last + d) / v - 0.5 * ramp;
    let progress = Progress { t0, s0: -d + v * t0, v0: v, v1: 0.0, ramp };
    let stand = standing_knee() - 0.01;
    let r_prev = Footfall::steady(gait, 1, path.beside(-len, side(1), gait.foot_offset_m), -st);
    let l0 = Footfall::steady(gait, 0, path.beside(0.0, side(0), gait.foot_offset_m), 0.0);
    let mut r1 = Footfall::steady(gait, 1, path.beside(last, side(1), HIP_HALF_WIDTH_M), st);
    r1.strike *= 0.7;
    r1.t_off = NEVER_AFTER;
    r1.knee =
        KeyCurve::open(&[(st, gait.knee_strike_rad), (st + 0.2 * stance, 0.8 * gait.knee_load_rad), (t_l2, stand)]);
    let mut l2 = Footfall::standing(
        0,
        path.beside(last, side(0), HIP_HALF_WIDTH_M),
        0.0,
        KeyCurve::constant(stand),
        NEVER_AFTER,
        NEVER_AFTER,
        Late::Solve,
    );
    l2.t_on = t_l2;
    l2.t_flat = t_l2;
    l2.yaw_flat = None;
    l2.swing_height = 0.6 * gait.swing_height_m;
    let feet = vec![r_prev, l0, r1, l2];
    let mut windows = leg_windows(&feet, [1, 2]);
    windows.push(Window {
        t0: end - 0.1,
        t1: NEVER_AFTER,
        height: Height::Level(KeyCurve::constant(STANDING_PELVIS_M)),
    });
    let layers = vec![Layer::new(gait, 0.0, Ramp::new(0.25 * st, end - 0.05, 1.0, 0.0))];
    let m = Motion::new(path, progress, feet, windows, layers);
    (m.finish(0.0, end), end)
}

/// Two steps from a left plant of gait `a` to a left plant of gait `b` (walks): the right
/// foot's step is between the two, the left one's is `b`'s. The first frame is `a`'s left
/// plant, the last one `b`'s.
pub fn speed_change_clip(a: &Gait, b: &Gait) -> Clip {
    let (m, end) = speed_change_motion(a, b);
    m.render(0.0, end, FRAME_RATE_HZ, &format!("{}_to_{}", a.name, b.name))
}

fn speed_change_motion(a: &Gait, b: &Gait) -> (Motion, f64) {
    let path = Path::straight();
    let side = |i: usize| [1.0, -1.0][i];
    let t_r1 = on_frame(0.5 * (a.step_time_s + b.step_time_s));
    let t_l2 = t_r1 + b.step_time_s;
    let (da, db) = (a.strike_distance_m(), b.strike_distance_m());
    let (t0, ramp) = (0.1 * t_l2, 0.8 * t_l2);
    // Where the left foot lands so that the pelvis, changing speed over the ramp, is where the
    // steady gait b has it at that plant.
    let s0 = -da + a.speed_mps * t0;
    let s_end = s0 + 0.5 * (a.speed_mps + b.speed_mps) * ramp + b.speed_mps * (t_l2 - t0 - ramp);
    let pos_l2 = s_end + db;
    let pos_r1 = pos_l2 - b.step_length_m();
    let progress = Progress { t0, s0, v0: a.speed_mps, v1: b.speed_mps, ramp };
    let feet = vec![
        Footfall::steady(a, 1, path.beside(-a.step_length_m(), side(1), a.foot_offset_m), -a.step_time_s),
        Footfall::steady(a, 0, path.beside(0.0, side(0), a.foot_offset_m), 0.0),
        Footfall::steady(b, 1, path.beside(pos_r1, side(1), b.foot_offset_m), t_r1),
        Footfall::steady(b, 0, path.beside(pos_l2, side(0), b.foot_offset_m), t_l2),
        Footfall::steady(b, 1, path.beside(pos_l2 + b.step_length_m(), side(1), b.foot_offset_m), t_l2 + b.step_time_s),
    ];
    let windows = leg_windows(&feet, 0..feet.len());
    let layers = vec![
        Layer::new(a, 0.0, Ramp::new(t0, t0 + ramp, 1.0, 0.0)),
        Layer::new(b, t_l2, Ramp::new(t0, t0 + ramp, 0.0, 1.0)),
    ];
    let m = Motion::new(path, progress, feet, windows, layers);
    (m.finish(0.0, t_l2), t_l2)
}

/// How a turning stop turns: which foot the body pivots on, to which side, how far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TurningStop {
    /// A spin turn to the left by 90°: the body pivots on the ball of the planted left foot
    /// while the right leg swings around and lands beside it.
    SpinLeft90,
    /// A step turn to the right by 90°: the body pivots on the ball of the planted left foot
    /// while the right foot steps out in the new direction, then the left foot closes beside it.
    StepRight90,
    /// A turn to the left by 180°: a spin turn on the left foot (90°), then a step turn on the
    /// ball of the right foot (90°) while the left foot steps around behind it.
    Left180,
}

impl TurningStop {
    /// The heading change, radians (positive to the left).
    pub fn turn_rad(self) -> f64 {
        match self {
            TurningStop::SpinLeft90 => PI / 2.0,
            TurningStop::StepRight90 => -PI / 2.0,
            TurningStop::Left180 => PI,
        }
    }

    /// The clip name for `gait`; the mirror clip swaps `left` and `right`.
    pub fn name(self, gait: &Gait) -> String {
        let g = &gait.name;
        match self {
            TurningStop::SpinLeft90 => format!("{g}_stop_left90"),
            TurningStop::StepRight90 => format!("{g}_stop_step_right90"),
            TurningStop::Left180 => format!("{g}_stop_left180"),
        }
    }
}

/// From a left plant of the steady gait (a walk) to standing turned by `kind`'s angle: the body
/// slows down over one or two steps while it pivots on the ball of a planted foot, and the feet
/// end side by side. The first frame is the steady gait's left plant; the last one is the first
/// frame of [`idle_clip`], turned.
pub fn turning_stop_clip(gait: &Gait, kind: TurningStop) -> Clip {
    let (m, end) = turning_stop_motion(gait, kind);
    m.render(0.0, end, FRAME_RATE_HZ, &kind.name(gait))
}

/// The heading `yaw` as a unit vector and the one to its left.
fn axes(yaw: f64) -> (DVec2, DVec2) {
    let f = DVec2::from_angle(yaw);
    (f, f.perp())
}

/// Where the ankle of a foot whose toe tip stays at `toe` stands (flat) with heading `yaw`.
fn ankle_under_toe(toe: DVec2, yaw: f64) -> DVec2 {
    toe - FOOT_FORWARD_M * DVec2::from_angle(yaw)
}

/// The steps of a turning stop: the body turns by `first` (radians, positive to the left) on
/// the ball of the left foot while the right foot swings to land `ahead` metres in front of the
/// turned left foot and a hip width to its right; with `second`, it then turns by that much on
/// the ball of the right foot while the left foot swings — bending toward `via` (relative to
/// the right foot's landing, in its frame) — to land beside it.
struct StopPlan {
    first: f64,
    ahead: f64,
    second: Option<(f64, Option<DVec2>)>,
}

impl TurningStop {
    fn plan(self) -> StopPlan {
        match self {
            TurningStop::SpinLeft90 => StopPlan { first: PI / 2.0, ahead: 0.0, second: None },
            TurningStop::StepRight90 => StopPlan { first: -PI / 4.0, ahead: 0.35, second: Some((-PI / 4.0, None)) },
            // The left foot goes around behind the right heel, which swings the other way.
            TurningStop::Left180 => {
                StopPlan { first: PI / 2.0, ahead: 0.1, second: Some((PI / 2.0, Some(DVec2::new(-0.15, -0.1)))) }
            }
        }
    }
}

/// How far behind the toe tip the pelvis stands over a foot pivoting on its ball, metres.
const OVER_BALL_M: f64 = 0.12;

/// A pelvis track on the ground as drift curves: through `keys` (time, point, velocity) by cubic
/// Hermite pieces, standing still after the last key; before the first key, `before` (the
/// pelvis moving at the first key's velocity).
fn track(keys: &[(f64, DVec2, DVec2)], before: DVec2) -> [KeyCurve; 2] {
    [0, 1].map(|i| {
        let k: Vec<(f64, f64, f64)> = keys.iter().map(|&(t, p, v)| (t, p[i] - before[i], v[i])).collect();
        KeyCurve::with_slopes(&k)
    })
}

fn turning_stop_motion(gait: &Gait, kind: TurningStop) -> (Motion, f64) {
    let plan = kind.plan();
    let (st, len, v, d) = (gait.step_time_s, gait.step_length_m(), gait.speed_mps, gait.strike_distance_m());
    let path = Path::straight();
    let off = gait.foot_offset_m;
    let stance = gait.stance_time_s();
    let stand = standing_knee() - 0.01;
    let landing = standing_knee() + 0.08;
    let pivot = 0.3;
    let w = 2.0 * HIP_HALF_WIDTH_M;
    let hip = HIP_HALF_WIDTH_M;
    // Step 1: the left heel strikes at the origin; its heel rises and the body pivots on its
    // ball while the right foot swings.
    let toe_l = DVec2::new(FOOT_FORWARD_M, off);
    let (heel_up, turn_a) = (on_frame(0.45 * st), on_frame(0.6 * st));
    let t_r1 = on_frame(1.3 * st);
    let r_prev = Footfall::steady(gait, 1, path.beside(-len, -1.0, off), -st);
    let mut l0 = Footfall::steady(gait, 0, DVec2::new(0.0, off), 0.0);
    l0.t_release = l0.t_release.min(heel_up);
    let left_1 = ankle_under_toe(toe_l, plan.first);
    let (fwd_1, side_1) = axes(plan.first);
    let right_1 = left_1 + plan.ahead * fwd_1 - w * side_1;
    let mut r1 = Footfall::steady(gait, 1, right_1, t_r1);
    r1.strike *= 0.7;
    r1.swing_height = 0.8 * gait.swing_height_m;
    r1.t_off = NEVER_AFTER;
    let mut turn = vec![(turn_a, 0.0), (t_r1 - 0.02, plan.first)];
    let mut feet = vec![r_prev];
    // The pelvis: from the steady gait at the left plant through `keys` to standing.
    let start = (0.0, DVec2::new(-d, 0.0), DVec2::new(v, 0.0));
    let (end, keys) = if let Some((second, via)) = plan.second {
        // Step 2: the right heel rises and the body pivots on its ball while the left foot
        // swings to land beside it.
        let t_off = on_frame(t_r1 + 0.25 * st);
        let (heel_up2, turn_a2) = (on_frame(r1.t_flat + 0.05), on_frame(t_off + 0.1 * st));
        let t_l2 = on_frame(t_off + 1.0 * st);
        let end = on_frame(t_l2 + 0.45);
        let toe_r = right_1 + FOOT_FORWARD_M * fwd_1;
        let heading = plan.first + second;
        let right_2 = ankle_under_toe(toe_r, heading);
        let (_, side_2) = axes(heading);
        let left_2 = right_2 + w * side_2;
        l0.late = Late::AtLeast(KeyCurve::open(&[(heel_up, 0.0), (turn_a, pivot)]));
        l0.t_off = t_off;
        l0.knee = KeyCurve::open(&[
            (0.0, gait.knee_strike_rad),
            (0.2 * stance, gait.knee_load_rad),
            (0.42 * stance, gait.knee_mid_rad),
            (t_r1, gait.knee_mid_rad),
            (t_off, gait.knee_toe_off_rad),
        ]);
        r1.late = Late::AtLeast(KeyCurve::open(&[
            (heel_up2, 0.0),
            (turn_a2, pivot),
            (t_l2 + 0.05, pivot),
            (t_l2 + 0.3, 0.0),
        ]));
        r1.t_release = heel_up2;
        r1.knee = KeyCurve::open(&[
            (t_r1, landing),
            (t_r1 + 0.2 * stance, landing + 0.05),
            (t_off, gait.knee_mid_rad),
            (t_l2, gait.knee_mid_rad),
            (end - 0.15, stand),
        ]);
        let mut l2 = Footfall::steady(gait, 0, left_2, t_l2);
        l2.strike *= 0.5;
        l2.swing_height = 0.7 * gait.swing_height_m;
        l2.via = via.map(|p| right_1 + p.x * fwd_1 + p.y * side_1);
        l2.t_off = NEVER_AFTER;
        l2.knee = KeyCurve::open(&[(t_l2, landing), (t_l2 + 0.2 * stance, landing + 0.03), (end - 0.15, stand)]);
        turn.extend([(turn_a2, plan.first), (t_l2 - 0.02, heading)]);
        feet.extend([l0, r1, l2]);
        // Over the ball of the right foot while it pivots, then back between the feet.
        let turn_curve = KeyCurve::open(&turn);
        let over = |t: f64| {
            let (f, s) = axes(turn_curve.at(t));
            toe_r - OVER_BALL_M * f + hip * s
        };
        let h = 1e-4;
        let orbit = |t: f64| (t, over(t), (over(t + h) - over(t - h)) / (2.0 * h));
        let mid = 0.5 * (turn_a2 + t_l2);
        (end, vec![start, orbit(mid), (end - 0.1, left_2 - hip * side_2, DVec2::ZERO)])
    } else {
        let pelvis_end = left_1 - hip * side_1;
        // Standing still once the left heel is down.
        let end = on_frame((t_r1 + 0.45).max(r1.t_flat + 0.4));
        l0.late = Late::AtLeast(KeyCurve::open(&[
            (heel_up, 0.0),
            (turn_a, pivot),
            (r1.t_flat + 0.05, pivot),
            (r1.t_flat + 0.3, 0.0),
        ]));
        l0.t_off = NEVER_AFTER;
        l0.knee = KeyCurve::open(&[
            (0.0, gait.knee_strike_rad),
            (0.2 * stance, gait.knee_load_rad),
            (0.42 * stance, gait.knee_mid_rad),
            (t_r1, gait.knee_mid_rad),
            (end - 0.15, stand),
        ]);
        r1.knee = KeyCurve::open(&[(t_r1, landing), (t_r1 + 0.2 * stance, landing + 0.05), (end - 0.15, stand)]);
        feet.extend([l0, r1]);
        (end, vec![start, (end - 0.1, pelvis_end, DVec2::ZERO)])
    };
    // The path only sets the pelvis moving before the clip; from the left plant on, the track
    // takes it.
    let progress = Progress { t0: 0.0, s0: -d, v0: v, v1: 0.0, ramp: 0.0 };
    let mut windows = leg_windows(&feet, 1..feet.len());
    windows.push(Window {
        t0: end - 0.1,
        t1: NEVER_AFTER,
        height: Height::Level(KeyCurve::constant(STANDING_PELVIS_M)),
    });
    let layers = vec![Layer::new(gait, 0.0, Ramp::new(0.25 * st, end - 0.05, 1.0, 0.0))];
    let mut m = Motion::new(path, progress, feet, windows, layers);
    m.turn = KeyCurve::open(&turn);
    m.ease = true;
    m.drift = track(&keys, DVec2::new(-d, 0.0));
    (m.finish(0.0, end), end)
}

/// Turning on the spot by `turn_rad` (positive to the left) from standing to standing: the
/// inside foot lifts and steps while the body pivots on the ball of the other foot, then the
/// other foot steps beside it. The pelvis stays within a few centimetres of where it stood.
pub fn pivot_clip(turn_rad: f64, name: &str) -> Clip {
    let (m, end) = pivot_motion(turn_rad.abs());
    let clip = m.render(0.0, end, FRAME_RATE_HZ, name);
    if turn_rad < 0.0 { clip.mirrored(&mirror_pairs(&actor::actor()), name.into()) } else { clip }
}

fn pivot_motion(turn: f64) -> (Motion, f64) {
    let path = Path::straight();
    let stand = standing_knee_curve();
    let (lift_l, land_l) = (0.3, on_frame(0.75));
    let (lift_r, land_r) = (land_l + 0.15, on_frame(land_l + 0.5));
    let end = on_frame(land_r + 0.3);
    let beside = |side: f64| DVec2::from_angle(turn).perp() * side * HIP_HALF_WIDTH_M;
    let l0 = Footfall::standing(
        0,
        DVec2::new(0.0, HIP_HALF_WIDTH_M),
        0.0,
        stand.clone(),
        0.0,
        lift_l,
        Late::Pitch(KeyCurve::open(&[(0.08, 0.0), (lift_l, 0.5)])),
    );
    let r0 = Footfall::standing(
        1,
        DVec2::new(0.0, -HIP_HALF_WIDTH_M),
        0.0,
        stand.clone(),
        0.0,
        lift_r,
        Late::Pitch(KeyCurve::open(&[(0.05, 0.0), (0.3, 0.42), (land_l, 0.42), (lift_r, 0.6)])),
    );
    let flat = |side: usize, at: DVec2, t: f64| {
        let mut f = Footfall::standing(
            side,
            at,
            turn,
            stand.clone(),
            NEVER_AFTER,
            NEVER_AFTER,
            Late::Pitch(KeyCurve::constant(0.0)),
        );
        f.t_on = t;
        f.t_flat = t;
        f.strike = 0.0;
        f.swing_height = 0.12;
        f
    };
    let feet = vec![l0, r0, flat(0, beside(1.0), land_l), flat(1, beside(-1.0), land_r)];
    let dip = STANDING_PELVIS_M - 0.015;
    let level = KeyCurve::open(&[(0.0, STANDING_PELVIS_M), (0.3, dip), (land_r, dip), (end - 0.05, STANDING_PELVIS_M)]);
    let windows = vec![Window { t0: NEVER_BEFORE, t1: NEVER_AFTER, height: Height::Level(level) }];
    let mut m = Motion::new(path, Progress::steady(0.0, 0.0), feet, windows, Vec::new());
    m.turn = KeyCurve::open(&[(lift_l, 0.0), (land_l - 0.05, turn)]);
    // The weight over the pivoting foot, then over the landed one.
    m.shift = KeyCurve::open(&[
        (0.0, 0.0),
        (0.25, -0.02),
        (land_l - 0.1, -0.02),
        (lift_r, 0.02),
        (land_r - 0.05, 0.02),
        (end - 0.05, 0.0),
    ]);
    (m.finish(0.0, end), end)
}

/// A step from standing to standing that moves the body by `offset` (metres, in the frame it
/// stands in: +x forward, +y left) without turning: the left foot lifts and steps by `offset`
/// while the weight stays over the right one, then the right foot follows to stand beside it
/// and the pelvis settles over both. Side steps (`offset` across) and a step back (`offset`
/// behind) in tight places; the mirror clip leads with the right foot.
pub fn shuffle_clip(offset: DVec2, name: &str) -> Clip {
    let (m, end) = shuffle_motion(offset);
    m.render(0.0, end, FRAME_RATE_HZ, name)
}

fn shuffle_motion(offset: DVec2) -> (Motion, f64) {
    let stand = standing_knee_curve();
    let (lift_l, land_l) = (0.25, on_frame(0.7));
    let (lift_r, land_r) = (land_l + 0.12, on_frame(land_l + 0.5));
    let end = on_frame(land_r + 0.3);
    let home = |side: f64| DVec2::new(0.0, side * HIP_HALF_WIDTH_M);
    let l0 = Footfall::standing(
        0,
        home(1.0),
        0.0,
        stand.clone(),
        0.0,
        lift_l,
        Late::Pitch(KeyCurve::open(&[(0.08, 0.0), (lift_l, 0.3)])),
    );
    let r0 = Footfall::standing(
        1,
        home(-1.0),
        0.0,
        stand.clone(),
        0.0,
        lift_r,
        Late::Pitch(KeyCurve::open(&[(land_l, 0.0), (lift_r, 0.3)])),
    );
    let flat = |side: usize, at: DVec2, t: f64| {
        let mut f = Footfall::standing(
            side,
            at,
            0.0,
            stand.clone(),
            NEVER_AFTER,
            NEVER_AFTER,
            Late::Pitch(KeyCurve::constant(0.0)),
        );
        f.t_on = t;
        f.t_flat = t;
        f.strike = 0.0;
        f.swing_height = 0.08;
        f
    };
    let feet = vec![l0, r0, flat(0, home(1.0) + offset, land_l), flat(1, home(-1.0) + offset, land_r)];
    let dip = STANDING_PELVIS_M - 0.015;
    let level = KeyCurve::open(&[(0.0, STANDING_PELVIS_M), (0.3, dip), (land_r, dip), (end - 0.05, STANDING_PELVIS_M)]);
    let windows = vec![Window { t0: NEVER_BEFORE, t1: NEVER_AFTER, height: Height::Level(level) }];
    let mut m = Motion::new(Path::straight(), Progress::steady(0.0, 0.0), feet, windows, Vec::new());
    // The pelvis follows the feet: over the right one while the left swings, between both once
    // the left has landed, then over the left one while the right swings, then between them.
    let over_r = DVec2::new(0.0, -0.02);
    let over_l = offset + DVec2::new(0.0, 0.02);
    let mid = 0.5 * offset;
    m.drift = track(
        &[
            (0.0, DVec2::ZERO, DVec2::ZERO),
            (lift_l, over_r, DVec2::ZERO),
            (land_l - 0.05, over_r, DVec2::ZERO),
            (0.5 * (land_l - 0.05 + lift_r), mid, 1.5 * offset / (lift_r - land_l + 0.05)),
            (lift_r, over_l, DVec2::ZERO),
            (land_r - 0.05, over_l, DVec2::ZERO),
            (end - 0.05, offset, DVec2::ZERO),
        ],
        DVec2::ZERO,
    );
    (m.finish(0.0, end), end)
}

/// Standing still for `seconds` (at least one frame) with both feet planted under the hips and a
/// slight breathing bob of the pelvis (a whole number of breaths of about four seconds, so the
/// clip repeats seamlessly).
pub fn idle_clip(seconds: f64) -> Clip {
    let seconds = if seconds.is_finite() { seconds.clamp(1.0 / FRAME_RATE_HZ, 3600.0) } else { 4.0 };
    let breaths = (seconds / 4.0).round().max(1.0);
    let n = 16 * breaths as usize;
    let breath = |j: usize| 0.5 * (1.0 - (2.0 * PI * breaths * j as f64 / n as f64).cos());
    let keys: Vec<(f64, f64)> =
        (0..=n).map(|j| (seconds * j as f64 / n as f64, STANDING_PELVIS_M - BREATH_M * breath(j))).collect();
    let lean: Vec<(f64, f64)> = (0..=n).map(|j| (seconds * j as f64 / n as f64, 0.01 * breath(j))).collect();
    let stand = standing_knee_curve();
    let foot = |side: usize, y: f64| {
        Footfall::standing(side, DVec2::new(0.0, y), 0.0, stand.clone(), NEVER_AFTER, NEVER_AFTER, Late::Solve)
    };
    let feet = vec![foot(0, HIP_HALF_WIDTH_M), foot(1, -HIP_HALF_WIDTH_M)];
    let windows = vec![Window { t0: NEVER_BEFORE, t1: NEVER_AFTER, height: Height::Level(KeyCurve::open(&keys)) }];
    let mut m = Motion::new(Path::straight(), Progress::steady(0.0, 0.0), feet, windows, Vec::new());
    m.lean = KeyCurve::open(&lean);
    let m = m.finish(0.0, seconds);
    let frames = (seconds * FRAME_RATE_HZ).round().max(1.0);
    m.render(0.0, seconds, frames / seconds, "idle")
}

/// Turn angles per step of the turning clips of a gait, degrees, and how many steps its 90° turn
/// takes: the faster the gait, the gentler its turns.
fn turn_set(gait: &Gait) -> (&'static [u32], usize) {
    match gait.name.as_str() {
        "slow_walk" => (&[15, 30, 45, 60, 90], 2),
        "walk" => (&[15, 30, 45, 60], 2),
        _ if gait.speed_mps > 4.5 => (&[5, 10, 15], 6),
        _ if gait.speed_mps > 3.0 => (&[10, 20, 30], 4),
        _ => (&[15, 30, 45], 2),
    }
}

/// `name` with `left` and `right` swapped: the name of its mirror clip.
fn swap_sides(name: &str) -> String {
    name.replace("left", "\u{0}").replace("right", "left").replace('\u{0}', "right")
}

/// One entry of the catalogue: how to make a clip and, when it has a side, its mirror's name.
enum Entry {
    Straight(Gait),
    Turn(Gait, u32),
    Turn90(Gait, usize),
    Start(Gait),
    Stop(Gait),
    TurningStart(Gait, u32),
    TurningStop(Gait, TurningStop),
    Speed(Gait, Gait),
    Pivot(u32),
    /// A step by an offset from standing to standing (named, with its mirror's name).
    Shuffle(&'static str, DVec2, &'static str),
    Idle,
}

impl Entry {
    /// The clip and the name of its mirror (`None` for symmetric clips).
    fn make(&self) -> (Clip, Option<String>) {
        match self {
            Entry::Straight(g) => {
                (locomotion(g, 0.0, STRAIGHT_STEPS, FRAME_RATE_HZ, &format!("{}_straight", g.name)), None)
            }
            Entry::Turn(g, deg) => {
                // A 90° turn at every step is sharp, and its name must not clash with the 90°
                // turn clips.
                let sharp = if *deg == 90 { "sharp_" } else { "" };
                let name = format!("{}_{sharp}left{deg}", g.name);
                (
                    locomotion(g, f64::from(*deg).to_radians(), DEFAULT_STEPS, FRAME_RATE_HZ, &name),
                    Some(format!("{}_{sharp}right{deg}", g.name)),
                )
            }
            Entry::Turn90(g, steps) => {
                let mut turns = vec![0.0; 2];
                turns.extend(std::iter::repeat_n(90f64.to_radians() / *steps as f64, *steps));
                turns.extend([0.0; 2]);
                let name = format!("{}_left90", g.name);
                (locomotion_path(g, &turns, FRAME_RATE_HZ, &name), Some(format!("{}_right90", g.name)))
            }
            Entry::Start(g) => (start_clip(g), Some(format!("{}_start_r", g.name))),
            Entry::Stop(g) => (stop_clip(g), Some(format!("{}_stop_r", g.name))),
            Entry::TurningStart(g, deg) => {
                let name = format!("{}_start_left{deg}", g.name);
                (
                    turning_start_clip(g, f64::from(*deg).to_radians(), &name),
                    Some(format!("{}_start_right{deg}", g.name)),
                )
            }
            Entry::TurningStop(g, k) => (turning_stop_clip(g, *k), Some(swap_sides(&k.name(g)))),
            Entry::Speed(a, b) => (speed_change_clip(a, b), Some(format!("{}_to_{}_r", a.name, b.name))),
            Entry::Pivot(deg) => {
                let name = format!("pivot_left{deg}");
                (pivot_clip(f64::from(*deg).to_radians(), &name), Some(format!("pivot_right{deg}")))
            }
            Entry::Shuffle(name, offset, mirror) => (shuffle_clip(*offset, name), Some((*mirror).into())),
            Entry::Idle => (idle_clip(4.0), None),
        }
    }
}

/// The default animation database at 60 Hz (see the module documentation for the list): the
/// five preset gaits straight and turning, their 90° turns, starts, stops (straight and
/// turning) and speed changes of the walks, pivot turns on the spot and the idle, each clip with
/// a side followed by its mirror. Generated in parallel, deterministically (the order and content do not depend on the
/// number of threads).
pub fn default_clips() -> Vec<Clip> {
    let mut entries = Vec::new();
    for gait in Gait::presets() {
        entries.push(Entry::Straight(gait.clone()));
        let (rates, turn90) = turn_set(&gait);
        for &deg in rates {
            entries.push(Entry::Turn(gait.clone(), deg));
        }
        entries.push(Entry::Turn90(gait, turn90));
    }
    for gait in [Gait::slow_walk(), Gait::walk()] {
        entries.push(Entry::Start(gait.clone()));
        entries.push(Entry::Stop(gait.clone()));
        for deg in [45, 90] {
            entries.push(Entry::TurningStart(gait.clone(), deg));
        }
        for k in [TurningStop::SpinLeft90, TurningStop::StepRight90, TurningStop::Left180] {
            entries.push(Entry::TurningStop(gait.clone(), k));
        }
    }
    entries.push(Entry::Speed(Gait::slow_walk(), Gait::walk()));
    entries.push(Entry::Speed(Gait::walk(), Gait::slow_walk()));
    entries.push(Entry::Pivot(45));
    entries.push(Entry::Pivot(90));
    entries.push(Entry::Pivot(135));
    entries.push(Entry::Shuffle("side_step_left", DVec2::new(0.0, SHUFFLE_M), "side_step_right"));
    entries.push(Entry::Shuffle("step_back", DVec2::new(-SHUFFLE_M, 0.0), "step_back_r"));
    entries.push(Entry::Idle);
    let pairs = mirror_pairs(&actor::actor());
    let made: Vec<Vec<Clip>> = entries
        .par_iter()
        .map(|e| {
            let (clip, mirror) = e.make();
            match mirror {
                Some(name) => {
                    let m = clip.mirrored(&pairs, name);
                    vec![clip, m]
                }
                None => vec![clip],
            }
        })
        .collect();
    made.into_iter().flatten().collect()
}

/// Longest interval of standing in the built-in database, seconds: a standing character can
/// start moving at the end of any of them.
pub const STAND_INTERVAL_S: f64 = 0.5;

/// The foot-plant intervals of generated clips: the generator sets every planted heel or toe
/// exactly on the ground, so a foot is down in a frame where its heel or toe is within a
/// micrometre of it, and intervals run from plant to plant (longer than a second split evenly,
/// standing longer than [`STAND_INTERVAL_S`] too, plants closer than 0.15 s merged), exactly
/// where the generator put them.
pub fn default_intervals(clips: &[Clip]) -> Vec<crate::anim::IntervalSpec> {
    let s = actor::actor();
    let feet = [s.find(actor::LEFT_FOOT), s.find(actor::RIGHT_FOOT)].map(|f| f.expect("the actor has feet"));
    let mut g = Vec::new();
    let mut out = Vec::new();
    for c in clips {
        let mut down = [vec![false; c.frames.len()], vec![false; c.frames.len()]];
        for (j, f) in c.frames.iter().enumerate() {
            s.globals(f, &mut g);
            for (k, &foot) in feet.iter().enumerate() {
                let (ankle, q) = g[foot];
                let lowest = (ankle + q * actor::HEEL_POINT).z.min((ankle + q * actor::TOE_POINT).z);
                down[k][j] = lowest <= 1e-6;
            }
        }
        let min = (0.15 / c.frame_time).round() as usize;
        let max = (1.0 / c.frame_time).round() as usize;
        let stand = (STAND_INTERVAL_S / c.frame_time).round().max(1.0) as usize;
        let b = crate::anim::db::plant_boundaries(&down, min, max);
        for w in b.windows(2) {
            let (a, e) = (w[0].0, w[1].0);
            // Standing throughout: pieces no longer than a stand interval.
            let standing = (a..=e).all(|j| down[0][j] && down[1][j]);
            let parts = if standing { (e - a).div_ceil(stand) } else { 1 };
            for p in 0..parts {
                let (s0, s1) = (a + (e - a) * p / parts, a + (e - a) * (p + 1) / parts);
                out.push(crate::anim::IntervalSpec { clip: c.name.clone(), start: s0, end: s1 });
            }
        }
    }
    out
}

/// The built-in animation database: [`default_clips`] cut at their exact foot plants
/// ([`default_intervals`]), contacts at the actor's heel and toe, default parameters.
pub fn default_database() -> Result<crate::anim::Database, crate::anim::DbError> {
    let clips = default_clips();
    let intervals = default_intervals(&clips);
    let params = crate::anim::DbParams { contacts: contact_params(), ..Default::default() };
    crate::anim::Database::build(clips, actor::actor(), params, Some(&intervals))
}

/// The contact detection of the built-in database: the actor's heel and toe points.
pub fn contact_params() -> crate::anim::db::ContactParams {
    crate::anim::db::ContactParams { points: Some([actor::HEEL_POINT, actor::TOE_POINT]), ..Default::default() }
}

#[cfg(test)]
pub(crate) mod tests {
    use glam::{DQuat, DVec2, DVec3, EulerRot};

    use super::*;
    use crate::anim::actor::{ANKLE_HEIGHT_M, HEEL_POINT};
    use crate::anim::clip::Ground;
    use crate::anim::procedural::leg::Rig;
    use crate::anim::skeleton::{Channel, Pose, angle_between, heading};
    use crate::geom::wrap_angle;

    /// Height below which a point counts as on the ground for skating, metres.
    const SKATE_H: f64 = 0.025;

    /// Toe tip and heel point of both feet in every frame: `[foot][0 toe, 1 heel]`.
    pub(crate) fn sole_points(clip: &Clip) -> Vec<[[DVec3; 2]; 2]> {
        let s = actor::actor();
        let rig = Rig::of(&s);
        let mut g = Vec::new();
        clip.frames
            .iter()
            .map(|f| {
                s.globals(f, &mut g);
                [0, 1].map(|i| {
                    let (ankle, q) = g[rig.foot[i]];
                    [s.tip(&g, rig.foot[i]), ankle + q * HEEL_POINT]
                })
            })
            .collect()
    }

    /// Foot skating of a clip played alone, centimetres per frame: the horizontal slide `d` of
    /// the toe tip and the heel point from frame to frame, weighted by `2 − 2^(h/H)` while the
    /// point is below `H` = 2.5 cm, over the sum of the weights.
    pub(crate) fn skating_cm(clip: &Clip) -> f64 {
        let p = sole_points(clip);
        let (mut sum, mut weight) = (0.0, 0.0);
        for w in p.windows(2) {
            for (before, after) in w[0].iter().zip(&w[1]) {
                for (&a, &b) in before.iter().zip(after) {
                    let h = 0.5 * (a.z + b.z);
                    if h < SKATE_H {
                        let wt = 2.0 - 2f64.powf(h.max(0.0) / SKATE_H);
                        sum += wt * 100.0 * (b - a).truncate().length();
                        weight += wt;
                    }
                }
            }
        }
        if weight > 0.0 { sum / weight } else { 0.0 }
    }

    /// Knee flexion of leg `i` in `pose`, radians.
    pub(crate) fn knee(pose: &Pose, i: usize) -> f64 {
        let rig = Rig::of(&actor::actor());
        let q = pose.rotations[rig.leg[i]];
        2.0 * q.y.atan2(q.w)
    }

    /// Per frame and foot: on the ground (toe or heel below 1 mm).
    fn grounded(clip: &Clip) -> Vec<[bool; 2]> {
        sole_points(clip).iter().map(|p| [0, 1].map(|i| p[i][0].z < 1e-3 || p[i][1].z < 1e-3)).collect()
    }

    fn relative(pose: &Pose) -> Pose {
        let mut p = pose.clone();
        Ground::of(pose, 0.0).transform_pose(&mut p, true);
        p
    }

    /// The pose relative to its ground reference equals `b`'s within `tol` (metres, radians).
    pub(crate) fn same_relative_pose(a: &Pose, b: &Pose, tol: f64) -> Result<(), String> {
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

    fn frame(clip: &Clip, t: f64) -> usize {
        ((t / clip.frame_time).round() as usize).min(clip.frames.len() - 1)
    }

    fn find<'a>(clips: &'a [Clip], name: &str) -> &'a Clip {
        clips.iter().find(|c| c.name == name).unwrap_or_else(|| panic!("{name} missing"))
    }

    /// Pelvis heights of a clip, metres.
    fn heights(c: &Clip) -> Vec<f64> {
        c.frames.iter().map(|f| f.root.z).collect()
    }

    #[test]
    fn walking_knees_and_pelvis_follow_human_gait() {
        let clips = default_clips();
        for g in [Gait::slow_walk(), Gait::walk()] {
            let c = find(&clips, &format!("{}_straight", g.name));
            let stride = 2.0 * g.step_time_s;
            let at = |t: f64| knee(&c.frames[frame(c, t)], 0).to_degrees();
            let (hs, load, mid, off) = (at(0.0), at(0.12 * stride), at(0.25 * stride), at(g.stance_time_s()));
            let peak = (frame(c, g.stance_time_s())..frame(c, stride))
                .map(|j| knee(&c.frames[j], 0).to_degrees())
                .fold(0.0, f64::max);
            eprintln!(
                "{}: knee at heel strike {hs:.1}°, loading {load:.1}°, mid-stance {mid:.1}°, toe-off {off:.1}°, swing peak {peak:.1}°",
                g.name
            );
            assert!((0.0..=8.0).contains(&hs), "{}: heel strike {hs}", g.name);
            assert!((12.0..=20.0).contains(&load), "{}: loading {load}", g.name);
            assert!(mid <= 10.0, "{}: mid-stance {mid}", g.name);
            assert!((30.0..=45.0).contains(&off), "{}: toe-off {off}", g.name);
            assert!((55.0..=70.0).contains(&peak), "{}: swing peak {peak}", g.name);
            // The knee stays nearly straight from mid-stance to heel-off.
            let terminal = (frame(c, 0.25 * stride)..frame(c, 0.4 * stride))
                .map(|j| knee(&c.frames[j], 0).to_degrees())
                .fold(0.0, f64::max);
            assert!(terminal <= 10.0, "{}: terminal stance {terminal}", g.name);
            // The pelvis vaults over the stance leg: highest near mid-stance, lowest in double
            // support.
            let z = heights(c);
            let step = frame(c, g.step_time_s);
            let one = &z[..=step];
            let hi = one.iter().cloned().enumerate().fold((0, 0.0), |a, (j, z)| if z > a.1 { (j, z) } else { a });
            let lo = one.iter().cloned().enumerate().fold((0, 9.0), |a, (j, z)| if z < a.1 { (j, z) } else { a });
            let phase = |j: usize| j as f64 * c.frame_time / stride;
            let ds = (2.0 * g.duty_factor - 1.0) + 0.02;
            eprintln!(
                "{}: pelvis {:.3} m at {:.0} % of the stride, {:.3} m at {:.0} %",
                g.name,
                hi.1,
                100.0 * phase(hi.0),
                lo.1,
                100.0 * phase(lo.0)
            );
            assert!((0.15..=0.35).contains(&phase(hi.0)), "{}: highest at {}", g.name, phase(hi.0));
            assert!(phase(lo.0) <= ds || phase(lo.0) >= 0.48, "{}: lowest at {}", g.name, phase(lo.0));
            let range = hi.1 - lo.1;
            if g.name == "walk" {
                assert!((0.03..=0.05).contains(&(range + 1e-4)), "walk pelvis moves {range} m");
            }
            assert!(hi.1 <= STANDING_PELVIS_M + 0.005);
        }
    }

    #[test]
    fn feet_strike_with_the_heel_and_leave_from_the_toe() {
        let clips = default_clips();
        for g in [Gait::slow_walk(), Gait::walk()] {
            let c = find(&clips, &format!("{}_straight", g.name));
            let p = sole_points(c);
            let s = actor::actor();
            let rig = Rig::of(&s);
            let mut globals = Vec::new();
            let mut pitch = |j: usize| {
                s.globals(&c.frames[j], &mut globals);
                -(globals[rig.foot[0]].1 * DVec3::X).z.asin()
            };
            // Heel strike: toes up 10–20°, heel on the ground, toe above it.
            let up = -pitch(0).to_degrees();
            assert!((10.0..=20.0).contains(&up), "{}: toes up {up}°", g.name);
            assert!(p[0][0][1].z.abs() < 1e-9 && p[0][0][0].z > 0.04);
            // Foot flat by 10–15 % of the stride.
            let stride = 2.0 * g.step_time_s;
            let flat = (0..c.frames.len()).find(|&j| p[j][0][0].z < 1e-6).unwrap();
            let flat_phase = flat as f64 * c.frame_time / stride;
            assert!((0.05..=0.15).contains(&flat_phase), "{}: flat at {flat_phase}", g.name);
            // Heel-off after mid-stance, while the toe stays planted; toe-off at the end of stance.
            let heel_off = (flat..c.frames.len()).find(|&j| p[j][0][1].z > 0.005).unwrap();
            let toe_off = (heel_off..c.frames.len()).find(|&j| p[j][0][0].z > 0.005).unwrap();
            let (ho, to) = (heel_off as f64 * c.frame_time / stride, toe_off as f64 * c.frame_time / stride);
            eprintln!(
                "{}: foot flat at {:.0} %, heel-off at {:.0} %, toe-off at {:.0} % of the stride",
                g.name,
                100.0 * flat_phase,
                100.0 * ho,
                100.0 * to
            );
            assert!(ho > 0.25 && ho < to - 0.1, "{}: heel-off at {ho}, toe-off at {to}", g.name);
            assert!((to - g.duty_factor).abs() < 0.03, "{}: toe-off at {to}", g.name);
            // While the heel rises the toe does not move.
            for j in heel_off..toe_off {
                if p[j + 1][0][0].z < 1e-6 {
                    assert!((p[j + 1][0][0] - p[j][0][0]).length() < 1e-6, "{} frame {j}", g.name);
                }
            }
            // While the heel carries the foot it does not move.
            for j in 0..flat - 1 {
                assert!((p[j + 1][0][1] - p[j][0][1]).length() < 1e-4, "{} frame {j}", g.name);
            }
        }
    }

    #[test]
    fn running_flies_and_sinks_at_mid_stance() {
        let clips = default_clips();
        for g in [Gait::jog(), Gait::run(), Gait::sprint()] {
            let c = find(&clips, &format!("{}_straight", g.name));
            let on = grounded(c);
            let flight = on.iter().filter(|o| !o[0] && !o[1]).count();
            let steps = STRAIGHT_STEPS;
            // Every step has its flight.
            let mut flights = 0;
            for w in on.windows(2) {
                if (w[0][0] || w[0][1]) && !w[1][0] && !w[1][1] {
                    flights += 1;
                }
            }
            assert!(flights >= steps - 1 && on.iter().all(|o| !(o[0] && o[1])), "{}: {flights} flights", g.name);
            let mid = knee(&c.frames[frame(c, 0.5 * g.stance_time_s())], 0).to_degrees();
            let z = heights(c);
            let mean = z.iter().sum::<f64>() / z.len() as f64;
            let stance: Vec<f64> = z[..=frame(c, g.stance_time_s())].to_vec();
            let lowest =
                stance.iter().cloned().enumerate().fold((0, 9.0), |a, (j, z)| if z < a.1 { (j, z) } else { a }).0;
            let at = lowest as f64 * c.frame_time / g.stance_time_s();
            eprintln!(
                "{}: {flight} flight frames, knee at mid-stance {mid:.1}°, pelvis mean {mean:.3} m, lowest at {:.0} % of stance",
                g.name,
                100.0 * at
            );
            assert!((35.0..=45.0).contains(&mid), "{}: mid-stance knee {mid}", g.name);
            assert!((0.3..=0.75).contains(&at), "{}: lowest at {at} of stance", g.name);
            if g.name != "sprint" {
                assert!(STANDING_PELVIS_M - mean < 0.06, "{}: mean pelvis {mean}", g.name);
            }
        }
    }

    #[test]
    fn arms_swing_opposite_to_the_legs() {
        let clips = default_clips();
        let s = actor::actor();
        let rig = Rig::of(&s);
        let mut elbows = Vec::new();
        for g in Gait::presets() {
            let c = find(&clips, &format!("{}_straight", g.name));
            let mut same = 0;
            let mut mean_elbow = 0.0;
            for f in &c.frames {
                let p = s.positions(f);
                let mut g2 = Vec::new();
                s.globals(f, &mut g2);
                let (lf, rf) = (p[rig.foot[0]], p[rig.foot[1]]);
                // Ahead relative to the pelvis heading.
                let fwd = DQuat::from_rotation_z(heading(f.rotations[0])) * DVec3::X;
                let legs = (lf - rf).dot(fwd);
                // Shoulder flexion: forward is negative.
                let flex = |i: usize| {
                    let q = f.rotations[rig.arm[i]];
                    2.0 * q.y.atan2(q.w)
                };
                let arms = flex(1) - flex(0);
                if legs.abs() > 0.3 && arms.abs() > 0.03 && legs * arms > 0.0 {
                    same += 1;
                }
                mean_elbow += 2.0 * (-f.rotations[rig.fore_arm[0]].y).atan2(f.rotations[rig.fore_arm[0]].w);
            }
            assert_eq!(same, 0, "{}: arms with the legs in {same} frames", g.name);
            elbows.push(mean_elbow / c.frames.len() as f64);
        }
        // More elbow bend when running.
        assert!(elbows[2] > 2.0 * elbows[1] && elbows[4] >= elbows[3], "{elbows:?}");
    }

    #[test]
    fn no_clip_skates() {
        for c in &default_clips() {
            let s = skating_cm(c);
            eprintln!("{:<26} skating {s:.4} cm/frame", c.name);
            // The sharp 90°-per-step slow walk turns so fast that its toes still slide a little
            // while the heels come down.
            let limit = if c.name.contains("sharp") { 0.05 } else { 0.03 };
            assert!(s <= limit, "{}: toe and heel skate {s:.4} cm per frame", c.name);
        }
    }

    #[test]
    fn every_clip_has_its_exact_mirror() {
        let clips = default_clips();
        let pairs = mirror_pairs(&actor::actor());
        let swap = |n: &str| -> String {
            if n.contains("left") {
                n.replace("left", "right")
            } else if n.contains("right") {
                n.replace("right", "left")
            } else if let Some(b) = n.strip_suffix("_r") {
                b.to_string()
            } else {
                format!("{n}_r")
            }
        };
        let mut names: Vec<&str> = clips.iter().map(|c| c.name.as_str()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), clips.len(), "names are unique");
        for c in &clips {
            if c.name.ends_with("_straight") || c.name == "idle" {
                // Symmetric: the right steps mirror the left ones.
                let m = c.mirrored(&pairs, c.name.clone());
                let n = c.frames.len() - 1;
                let half = if c.name == "idle" { 0 } else { n / STRAIGHT_STEPS };
                for j in 0..=n - half {
                    same_relative_pose(&c.frames[j + half], &m.frames[j], 1e-6)
                        .map_err(|e| format!("{} {j}: {e}", c.name))
                        .unwrap();
                }
                continue;
            }
            let other = find(&clips, &swap(&c.name));
            assert_eq!(&c.mirrored(&pairs, other.name.clone()), other, "{} mirrors {}", c.name, other.name);
        }
    }

    #[test]
    fn starts_stops_speed_changes_and_pivots_join_their_neighbours() {
        let clips = default_clips();
        let idle = find(&clips, "idle");
        let standing = &idle.frames[0];
        let last = |c: &Clip| c.frames.last().unwrap().clone();
        for g in ["slow_walk", "walk"] {
            let steady = find(&clips, &format!("{g}_straight"));
            let step = (steady.frames.len() - 1) / STRAIGHT_STEPS;
            let (left, right) = (&steady.frames[0], &steady.frames[step]);
            for (suffix, first_plant, other_plant) in [("", left, right), ("_r", right, left)] {
                let start = find(&clips, &format!("{g}_start{suffix}"));
                same_relative_pose(standing, &start.frames[0], 1e-6).unwrap();
                same_relative_pose(&last(start), other_plant, 1e-6)
                    .map_err(|e| format!("{g}_start{suffix}: {e}"))
                    .unwrap();
                let stop = find(&clips, &format!("{g}_stop{suffix}"));
                same_relative_pose(&stop.frames[0], first_plant, 1e-6)
                    .map_err(|e| format!("{g}_stop{suffix}: {e}"))
                    .unwrap();
                same_relative_pose(&last(stop), standing, 1e-6).map_err(|e| format!("{g}_stop{suffix}: {e}")).unwrap();
                // Stops take at most two steps; everything moves forward only.
                assert!(stop.duration() < 2.0 * 2.0 * Gait::walk().step_time_s + 0.6);
                for c in [start, stop] {
                    assert!(
                        c.frames.windows(2).all(|w| (w[1].root - w[0].root).truncate().dot(glam::DVec2::X) >= -1e-9),
                        "{}",
                        c.name
                    );
                }
            }
        }
        for (a, b) in [("slow_walk", "walk"), ("walk", "slow_walk")] {
            let (fa, fb) = (find(&clips, &format!("{a}_straight")), find(&clips, &format!("{b}_straight")));
            let (sa, sb) = ((fa.frames.len() - 1) / STRAIGHT_STEPS, (fb.frames.len() - 1) / STRAIGHT_STEPS);
            for (suffix, ja, jb) in [("", 0, 0), ("_r", sa, sb)] {
                let c = find(&clips, &format!("{a}_to_{b}{suffix}"));
                same_relative_pose(&c.frames[0], &fa.frames[ja], 1e-6).map_err(|e| format!("{}: {e}", c.name)).unwrap();
                same_relative_pose(&last(c), &fb.frames[jb], 1e-6).map_err(|e| format!("{}: {e}", c.name)).unwrap();
            }
        }
        for side in ["left", "right"] {
            for deg in [45.0, 90.0, 135.0] {
                let c = find(&clips, &format!("pivot_{side}{deg}"));
                same_relative_pose(standing, &c.frames[0], 1e-6).unwrap();
                same_relative_pose(&last(c), standing, 1e-6).map_err(|e| format!("{}: {e}", c.name)).unwrap();
                let sign = if side == "left" { 1.0 } else { -1.0 };
                let total = turned(c).to_degrees();
                assert!((total - sign * deg).abs() < 0.5, "{}: {total}°", c.name);
                // The pelvis stays where it stood: within 3 cm over each step.
                let start = c.frames[0].root.truncate();
                let far = c.frames.iter().map(|f| (f.root.truncate() - start).length()).fold(0.0, f64::max);
                assert!(far < 0.03, "{}: the pelvis moves {far} m", c.name);
            }
        }
    }

    #[test]
    fn side_steps_and_steps_back_move_the_body_without_turning_it() {
        let clips = default_clips();
        let standing = &find(&clips, "idle").frames[0];
        for (name, to) in [
            ("side_step_left", glam::DVec2::new(0.0, SHUFFLE_M)),
            ("side_step_right", glam::DVec2::new(0.0, -SHUFFLE_M)),
            ("step_back", glam::DVec2::new(-SHUFFLE_M, 0.0)),
            ("step_back_r", glam::DVec2::new(-SHUFFLE_M, 0.0)),
        ] {
            let c = find(&clips, name);
            let last = c.frames.last().unwrap();
            same_relative_pose(standing, &c.frames[0], 1e-6).unwrap();
            same_relative_pose(last, standing, 1e-6).map_err(|e| format!("{name}: {e}")).unwrap();
            let moved = (last.root - c.frames[0].root).truncate();
            assert!((moved - to).length() < 1e-3, "{name}: moved {moved}");
            assert!(turned(c).abs() < 1e-6, "{name}: turned {}", turned(c));
            // Never more than a few centimetres beyond the way between its ends.
            let dir = to.normalize();
            for f in &c.frames {
                let along = (f.root - c.frames[0].root).truncate().dot(dir);
                assert!((-0.03..=SHUFFLE_M + 0.03).contains(&along), "{name}: {along}");
            }
        }
    }

    #[test]
    fn clips_repeat_seamlessly_and_turn_as_asked() {
        let clips = default_clips();
        for c in &clips {
            let cyclic = !["start", "stop", "_to_", "pivot", "step"].iter().any(|k| c.name.contains(k));
            if cyclic {
                // Turning runs repeat to a tenth of a milliradian: their heading schedule is found
                // numerically.
                // Turning runs repeat to a milliradian: their heading schedule is found
                // numerically.
                let running = c.name.starts_with("run") || c.name.starts_with("sprint");
                let tol = if c.name.contains("straight") || !running { 1e-6 } else { 1e-3 };
                same_relative_pose(&c.frames[0], c.frames.last().unwrap(), tol)
                    .map_err(|e| format!("{}: {e}", c.name))
                    .unwrap();
            }
            assert!(c.frames.len() > 10 && (c.frame_time - 1.0 / FRAME_RATE_HZ).abs() < 1e-9);
            for (j, f) in c.frames.iter().enumerate() {
                assert!(f.root.is_finite(), "{} frame {j}", c.name);
                for q in &f.rotations {
                    assert!(q.is_finite() && (q.length() - 1.0).abs() < 1e-9, "{} frame {j}: {q}", c.name);
                }
            }
            // Feet never go below the ground, and never through each other.
            for (j, p) in sole_points(c).iter().enumerate() {
                for foot in p {
                    assert!(foot[0].z > -1e-6 && foot[1].z > -1e-6, "{} frame {j}: {foot:?}", c.name);
                }
            }
        }
        for (name, deg) in [
            ("walk_left90", 90.0),
            ("run_right90", -90.0),
            ("jog_right30", -180.0),
            ("sprint_left15", 90.0),
            ("walk_left60", 360.0),
            ("slow_walk_sharp_right90", -540.0),
        ] {
            let total = turned(find(&clips, name)).to_degrees();
            assert!((total - deg).abs() < 1.0, "{name}: {total}°");
        }
        let walk = locomotion(&Gait::walk(), 0.0, 4, FRAME_RATE_HZ, "w");
        // Half-way it is the right foot's turn, not the same pose.
        assert!(same_relative_pose(&walk.frames[0], &walk.frames[walk.frames.len() / 4], 1e-3).is_err());
        let (first, end) = (walk.frames[0].root, walk.frames.last().unwrap().root);
        assert!(((end - first).length() / walk.duration() / 1.35 - 1.0).abs() < 0.02);
    }

    #[test]
    fn rotations_use_only_the_actor_channels() {
        let s = actor::actor();
        let clips = [
            locomotion(&Gait::run(), 0.3, 2, 60.0, "r"),
            start_clip(&Gait::walk()),
            pivot_clip(1.0, "p"),
            turning_start_clip(&Gait::walk(), -1.2, "s"),
            turning_stop_clip(&Gait::slow_walk(), TurningStop::Left180),
            turning_stop_clip(&Gait::walk(), TurningStop::StepRight90),
        ];
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

    /// The turning starts and stops of walk `g`: name, where the first and the last frame are
    /// ("idle": the idle's first pose; "left", "right": the steady gait's left or right plant)
    /// and the turn, degrees.
    fn turning_clips(g: &str) -> Vec<(String, &'static str, &'static str, f64)> {
        vec![
            (format!("{g}_stop_left90"), "left", "idle", 90.0),
            (format!("{g}_stop_right90"), "right", "idle", -90.0),
            (format!("{g}_stop_step_right90"), "left", "idle", -90.0),
            (format!("{g}_stop_step_left90"), "right", "idle", 90.0),
            (format!("{g}_stop_left180"), "left", "idle", 180.0),
            (format!("{g}_stop_right180"), "right", "idle", -180.0),
            (format!("{g}_start_left45"), "idle", "right", 45.0),
            (format!("{g}_start_left90"), "idle", "right", 90.0),
            (format!("{g}_start_right45"), "idle", "left", -45.0),
            (format!("{g}_start_right90"), "idle", "left", -90.0),
        ]
    }

    /// Touch-downs after the first frame: frames where a foot's heel or toe reaches the ground.
    fn touch_downs(clip: &Clip) -> usize {
        let on = grounded(clip);
        on.windows(2).map(|w| (0..2).filter(|&i| w[1][i] && !w[0][i]).count()).sum()
    }

    #[test]
    fn turning_starts_and_stops_join_their_neighbours_and_turn_as_named() {
        let clips = default_clips();
        let standing = &find(&clips, "idle").frames[0];
        for g in ["slow_walk", "walk"] {
            let steady = find(&clips, &format!("{g}_straight"));
            let step = (steady.frames.len() - 1) / STRAIGHT_STEPS;
            let pose = |at: &str| match at {
                "idle" => standing,
                "left" => &steady.frames[0],
                _ => &steady.frames[step],
            };
            for (name, from, to, deg) in turning_clips(g) {
                let c = find(&clips, &name);
                let (first, last) = (&c.frames[0], c.frames.last().unwrap());
                same_relative_pose(first, pose(from), 1e-6).map_err(|e| format!("{name} starts: {e}")).unwrap();
                same_relative_pose(last, pose(to), 1e-6).map_err(|e| format!("{name} ends: {e}")).unwrap();
                // Joined within 1e-6 means the pose relative to its ground reference; the
                // ground references themselves turn by the named angle.
                let total = turned(c).to_degrees();
                let ends = wrap_angle(heading(last.rotations[0]) - heading(first.rotations[0])).to_degrees();
                eprintln!("{name:<26} turns {total:8.3}° (ground reference {ends:8.3}°), {} frames", c.frames.len());
                assert!((total - deg).abs() <= 1.0, "{name}: turned {total}°");
                assert!(wrap_angle((ends - deg).to_radians()).abs() <= 1f64.to_radians(), "{name}: {ends}°");
                // Stops take one or two steps after their plant; starts two.
                let steps = touch_downs(c);
                if from == "idle" {
                    assert_eq!(steps, 2, "{name}");
                } else {
                    assert!((1..=2).contains(&steps), "{name}: {steps} steps");
                }
            }
            let gait = if g == "walk" { Gait::walk() } else { Gait::slow_walk() };
            for k in [TurningStop::SpinLeft90, TurningStop::StepRight90, TurningStop::Left180] {
                let total = turned(find(&clips, &k.name(&gait)));
                assert!((total - k.turn_rad()).abs() < 1e-6, "{k:?}: {total}");
            }
        }
    }

    #[test]
    fn turning_starts_and_stops_turn_only_on_one_point_of_each_planted_foot() {
        // The hips cannot twist: while the body turns, every foot on the ground stands on its
        // heel or its toe alone, the other point well up.
        let clips = default_clips();
        for g in ["slow_walk", "walk"] {
            for (name, ..) in turning_clips(g) {
                let c = find(&clips, &name);
                let p = sole_points(c);
                let mut turning = 0;
                for (j, w) in c.frames.windows(2).enumerate() {
                    if wrap_angle(heading(w[1].rotations[0]) - heading(w[0].rotations[0])).abs() < 1e-9 {
                        continue;
                    }
                    turning += 1;
                    for q in [&p[j], &p[j + 1]] {
                        for (i, foot) in q.iter().enumerate() {
                            let (low, high) = (foot[0].z.min(foot[1].z), foot[0].z.max(foot[1].z));
                            assert!(
                                low > 1e-6 || high > 0.02,
                                "{name} frame {j}: foot {i} flat while turning {foot:?}"
                            );
                        }
                    }
                }
                assert!(turning > 10, "{name}");
            }
        }
    }

    #[test]
    fn turning_starts_and_stops_move_like_a_person() {
        let clips = default_clips();
        for gait in [Gait::slow_walk(), Gait::walk()] {
            for (name, ..) in turning_clips(&gait.name) {
                let c = find(&clips, &name);
                let dt = c.frame_time;
                let v: Vec<DVec2> = c.frames.windows(2).map(|w| (w[1].root - w[0].root).truncate() / dt).collect();
                let speed = v.iter().map(|v| v.length()).fold(0.0, f64::max);
                let accel = v.windows(2).map(|w| (w[1] - w[0]).length() / dt).fold(0.0, f64::max);
                let yaw_rate = c
                    .frames
                    .windows(2)
                    .map(|w| wrap_angle(heading(w[1].rotations[0]) - heading(w[0].rotations[0])).abs() / dt)
                    .fold(0.0, f64::max)
                    .to_degrees();
                let z = heights(c);
                let (lo, hi) = (z.iter().cloned().fold(9.0, f64::min), z.iter().cloned().fold(0.0, f64::max));
                // Touch-down and lift-off: the touching point's horizontal over vertical motion
                // in the four frames before it touches down and after it lifts off.
                let p = sole_points(c);
                let on = grounded(c);
                let mut steep: f64 = 0.0;
                for i in 0..2 {
                    for j in 4..p.len() - 4 {
                        for (near, far) in [(j - 1, j - 4), (j + 1, j + 4)] {
                            if on[j][i] && !on[near][i] {
                                let k = if p[j][i][0].z < 1e-3 { 0 } else { 1 };
                                let (a, b) = (p[far][i][k], p[j][i][k]);
                                steep = steep.max((b - a).truncate().length() / (a.z - b.z).abs().max(1e-6));
                            }
                        }
                    }
                }
                // Feet pass each other without touching.
                let apart = p
                    .iter()
                    .map(|q| {
                        segment_distance(
                            [q[0][0].truncate(), q[0][1].truncate()],
                            [q[1][0].truncate(), q[1][1].truncate()],
                        )
                    })
                    .fold(9.0, f64::min);
                eprintln!(
                    "{name:<26} pelvis up to {speed:.2} m/s, {accel:.2} m/s², {lo:.3}–{hi:.3} m; turning up to {yaw_rate:.0}°/s; feet {apart:.3} m apart; touch-down and lift-off {steep:.2} horizontal per vertical"
                );
                assert!(speed <= 1.02 * gait.speed_mps, "{name}: {speed} m/s");
                assert!(accel <= 4.0, "{name}: {accel} m/s²");
                assert!(yaw_rate <= 450.0, "{name}: {yaw_rate}°/s");
                assert!(lo >= STANDING_PELVIS_M - 0.04 && hi <= STANDING_PELVIS_M + 0.01, "{name}: {lo}–{hi} m");
                assert!(steep <= 0.5, "{name}: touch-down or lift-off {steep}");
                assert!(apart >= 0.06, "{name}: feet {apart} m apart");
            }
        }
    }

    /// Shortest distance between two segments in the plane (that do not cross).
    fn segment_distance(a: [DVec2; 2], b: [DVec2; 2]) -> f64 {
        let to = |p: DVec2, s: [DVec2; 2]| {
            let d = s[1] - s[0];
            let u = ((p - s[0]).dot(d) / d.length_squared().max(1e-12)).clamp(0.0, 1.0);
            (s[0] + u * d - p).length()
        };
        to(a[0], b).min(to(a[1], b)).min(to(b[0], a)).min(to(b[1], a))
    }

    #[test]
    fn turning_starts_and_stops_are_cut_at_their_foot_plants() {
        let clips = default_clips();
        let intervals = default_intervals(&clips);
        for g in ["slow_walk", "walk"] {
            for (name, ..) in turning_clips(g) {
                let c = find(&clips, &name);
                let mine: Vec<_> = intervals.iter().filter(|i| i.clip == name).collect();
                assert!(mine.len() >= 2, "{name}: {} intervals", mine.len());
                assert_eq!((mine[0].start, mine[mine.len() - 1].end), (0, c.frames.len() - 1), "{name}");
                assert!(mine.windows(2).all(|w| w[0].end == w[1].start), "{name}");
                // Every cut is a frame where a foot has just come down (or both stand).
                let on = grounded(c);
                for iv in &mine[1..] {
                    let j = iv.start;
                    assert!((0..2).any(|i| on[j][i] && !on[j - 1][i]) || on[j][0] && on[j][1], "{name} cut at {j}");
                }
            }
        }
        let db = default_database().unwrap();
        assert_eq!(db.clips.len(), clips.len());
        assert_eq!(db.intervals.len(), intervals.len());
    }

    #[test]
    fn generation_is_deterministic_and_gives_the_database_enough_steps() {
        let (a, b) = (default_clips(), default_clips());
        assert_eq!(a, b);
        let db = crate::anim::Database::build(a, actor::actor(), crate::anim::DbParams::default(), None).unwrap();
        assert!(db.intervals.len() > 200, "{} intervals", db.intervals.len());
        // Odd step counts are rounded up; bad frame rates fall back to 60 Hz.
        let clip = locomotion(&Gait::walk(), 0.0, 3, f64::NAN, "x");
        assert!((clip.duration() - 4.0 * Gait::walk().step_time_s).abs() < 1e-9);
        assert!((clip.frame_time - 1.0 / 60.0).abs() < 1e-9);
        let _ = ANKLE_HEIGHT_M;
    }
}
