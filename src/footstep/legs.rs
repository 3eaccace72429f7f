//! The legs of one step (seed 002 §4.1, Fig 4): key frames for level ground, uphill and
//! downhill, the swing ankle on a cubic Bezier curve whose control points are raised until the
//! swinging sole clears the ground profile, the pelvis height following the terrain, and
//! two-link inverse kinematics with the knees bending forward. A failure (no clear swing within
//! the lift limit, a leg out of reach) goes back to the footstep planner.
//!
//! A step moves the rear foot from its foothold (lift-off) past the supporting foot (stance) to
//! the next foothold (touch-down), over a phase `t` from 0 to 1:
//!
//! - **Swing.** The sole's centre follows the cubic Bezier curve `P0 P1 P2 P3` with `P0` the
//!   lift-off foothold, `P3` the touch-down foothold and `P1`, `P2` straight above them at one
//!   control height `H`: the foot leaves and lands vertically and moves forward in between.
//!   `H` starts [`FootstepParams::swing_lift_m`] above the higher foothold; since the curve's
//!   height is linear in `H` (`z(t) = z0 (1−t)³ + z3 t³ + 3t(1−t) H`), the raise that clears the
//!   ground is solved at each of [`SWING_SAMPLES`] samples and the largest is kept. The pitch of
//!   the sole turns smoothly from the lift-off ground's to the touch-down ground's. Clear means
//!   that at every sample the whole sole is at least the clearance above the ground under it,
//!   and its heel and toe above the ground they sweep over on the way from the previous sample
//!   and to the next; the clearance is a quarter of its full value at the first and last
//!   samples and reaches it a fifth of the way in.
//! - **Key frames of the pelvis.** At lift-off and touch-down (double support) the hip is midway
//!   between the ankles, as high as both legs allow with the supporting knee at its mid-stance
//!   flexion; at mid-swing it is over the supporting foot. Level ground: the hip rises over the
//!   supporting leg and comes down again. Uphill (the touch-down foothold is higher): the front
//!   leg bends first — the hip stays low while the swinging leg lifts its foot onto the step,
//!   and rises once it is planted. Downhill: the rear leg bends first — the supporting knee
//!   lowers the hip early, before the front foot reaches down. Between key frames heights are
//!   interpolated smoothly, and at every moment the hip is lowered where a leg could not
//!   otherwise reach (the pelvis follows the terrain).
//! - **Legs.** The knee is placed by two-link inverse kinematics in the sagittal plane, ahead of
//!   the hip–ankle line; a leg fails when its ankle is farther than the straight leg reaches or
//!   closer than the largest knee flexion allows.

use glam::DVec2;

use super::foothold::{Sole, StepFailure};
use super::{FootstepParams, LegGeometry};
use crate::geom::smoothstep;
use crate::ground::GroundProfile;

/// Samples at which a swing is checked and the phases `i / SWING_SAMPLES` its curve is
/// reported at.
pub const SWING_SAMPLES: usize = 24;

/// Height difference between the stance and touch-down footholds below which a step counts as
/// level, metres.
pub const LEVEL_TOLERANCE_M: f64 = 0.03;

/// The key-frame set a step uses (seed 002 Fig 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepKind {
    /// Level ground.
    Level,
    /// Up: the front leg bends first.
    Uphill,
    /// Down: the rear leg bends first.
    Downhill,
}

impl StepKind {
    /// `"level"`, `"uphill"` or `"downhill"`.
    pub fn name(self) -> &'static str {
        match self {
            StepKind::Level => "level",
            StepKind::Uphill => "uphill",
            StepKind::Downhill => "downhill",
        }
    }
}

/// The joints of one leg in the sagittal plane, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LegPose {
    /// Hip joint.
    pub hip: DVec2,
    /// Knee.
    pub knee: DVec2,
    /// Ankle.
    pub ankle: DVec2,
    /// Heel end of the sole.
    pub heel: DVec2,
    /// Toe end of the sole.
    pub toe: DVec2,
}

/// Both legs at one moment of a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepPose {
    /// Phase of the step, 0 (lift-off) to 1 (touch-down).
    pub phase: f64,
    /// The swinging leg.
    pub swing: LegPose,
    /// The supporting leg.
    pub stance: LegPose,
}

/// The leg motion of one step, planned and checked; evaluate it at any phase.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Swing {
    leg: LegGeometry,
    /// Where the swinging foot lifts off.
    pub lift_off: Sole,
    /// The supporting foot.
    pub stance: Sole,
    /// Where the swinging foot lands.
    pub touch_down: Sole,
    /// Which key frames the step uses.
    pub kind: StepKind,
    /// Height of the Bezier curve's two inner control points, metres.
    pub control_height_m: f64,
    /// Their height before any raising, metres.
    pub nominal_control_height_m: f64,
    /// Hip heights at the key frames (lift-off, mid-swing, touch-down), before the reach caps.
    hip_keys: [f64; 3],
    /// Hip positions along X at lift-off and touch-down.
    hip_x: [f64; 2],
}

/// The ankle of a foot whose sole is `sole`.
pub fn ankle_of(leg: &LegGeometry, sole: &Sole) -> DVec2 {
    let local = DVec2::new(-0.5 * (leg.toe_forward_m - leg.heel_back_m), leg.ankle_height_m);
    sole.centre() + DVec2::from_angle(sole.pitch_rad).rotate(local)
}

/// The knee of a leg from `hip` to `ankle`: two-link inverse kinematics, the knee ahead of the
/// hip–ankle line (a human knee). A target out of reach is met by the straight leg pointing at
/// it.
pub fn knee_of(leg: &LegGeometry, hip: DVec2, ankle: DVec2) -> DVec2 {
    let (a, b) = (leg.thigh_m, leg.shin_m);
    let d = ankle - hip;
    let len = d.length();
    let u = if len > 1e-12 { d / len } else { DVec2::new(0.0, -1.0) };
    let r = len.clamp((a - b).abs() + 1e-9, a + b);
    let cos = ((a * a + r * r - b * b) / (2.0 * a * r)).clamp(-1.0, 1.0);
    hip + a * DVec2::from_angle(cos.acos()).rotate(u)
}

/// The hip height over two planted ankles at double support (the hip midway between them), or
/// why the legs cannot span them.
fn double_support(leg: &LegGeometry, a: DVec2, b: DVec2, phase: f64) -> Result<f64, StepFailure> {
    let walk = leg.reach_m(leg.stance_knee_deg);
    let dx = 0.5 * (b.x - a.x).abs();
    if dx >= walk {
        return Err(StepFailure::OutOfReach { phase, distance_m: dx });
    }
    let rise = (walk * walk - dx * dx).sqrt();
    let z = (a.y + rise).min(b.y + rise);
    let x = 0.5 * (a.x + b.x);
    for ankle in [a, b] {
        let distance_m = DVec2::new(x, z).distance(ankle);
        if distance_m < leg.min_reach_m() {
            return Err(StepFailure::OutOfReach { phase, distance_m });
        }
    }
    Ok(z)
}

/// Whether two planted footholds one step apart can both carry the hip (the touch-down key
/// frame, which depends on nothing else): a necessary condition of every step onto `to`.
pub fn can_stand(params: &FootstepParams, from: &Sole, to: &Sole) -> Result<(), StepFailure> {
    let leg = &params.leg;
    double_support(leg, ankle_of(leg, from), ankle_of(leg, to), 1.0).map(|_| ())
}

/// The clearance the swinging sole keeps at the sample at phase `t` (0 < t < 1): a quarter of
/// the full value at the first and last samples, growing to the full value a fifth of the way
/// in (the least clearance covers the curve's sag between samples).
fn clearance_at(params: &FootstepParams, t: f64) -> f64 {
    params.swing_clearance_m * (6.0 * t * (1.0 - t)).clamp(0.25, 1.0)
}

impl Swing {
    /// Plans the legs of the step that moves the foot at `lift_off` past `stance` to
    /// `touch_down` over `ground`: the swing curve raised until clear, the pelvis key frames,
    /// the reach of both legs checked at every sample.
    pub fn plan(
        ground: &GroundProfile,
        params: &FootstepParams,
        lift_off: Sole,
        stance: Sole,
        touch_down: Sole,
    ) -> Result<Swing, StepFailure> {
        let leg = params.leg;
        let (a, b, c) = (ankle_of(&leg, &lift_off), ankle_of(&leg, &stance), ankle_of(&leg, &touch_down));
        let h0 = double_support(&leg, a, b, 0.0)?;
        let h1 = double_support(&leg, b, c, 1.0)?;
        let rise = touch_down.z_m - stance.z_m;
        let kind = if rise > LEVEL_TOLERANCE_M {
            StepKind::Uphill
        } else if rise < -LEVEL_TOLERANCE_M {
            StepKind::Downhill
        } else {
            StepKind::Level
        };
        let hip_x = [0.5 * (a.x + b.x), 0.5 * (b.x + c.x)];
        let walk = leg.reach_m(leg.stance_knee_deg);
        let dx_mid = (0.5 * (hip_x[0] + hip_x[1]) - b.x).abs().min(walk);
        let over_stance = b.y + (walk * walk - dx_mid * dx_mid).sqrt();
        let mid = match kind {
            StepKind::Level => over_stance,
            StepKind::Uphill => over_stance.min(h0 + 0.25 * (h1 - h0)),
            StepKind::Downhill => over_stance.min(h1 + 0.25 * (h0 - h1)),
        };
        let top = lift_off.z_m.max(touch_down.z_m);
        let nominal = top + params.swing_lift_m;
        let mut swing = Swing {
            leg,
            lift_off,
            stance,
            touch_down,
            kind,
            control_height_m: nominal,
            nominal_control_height_m: nominal,
            hip_keys: [h0, mid, h1],
            hip_x,
        };
        let length = leg.foot_length_m();
        let mut needed = nominal;
        let phase = |i: usize| i as f64 / SWING_SAMPLES as f64;
        for i in 1..SWING_SAMPLES {
            let t = phase(i);
            let (x, base, pitch) = swing.curve_without_lift(t);
            let (behind, ahead) =
                (x - swing.curve_without_lift(phase(i - 1)).0, swing.curve_without_lift(phase(i + 1)).0 - x);
            let (half, rise) = (0.5 * length * pitch.cos(), 0.5 * length * pitch.sin());
            // The ground under the sole, and the ground the heel and toe sweep over, at their
            // heights, on the way from the previous sample and to the next: the sole keeps clear
            // between samples too.
            let contact = ground
                .max_above_line(x - half, x + half, x, 0.0, pitch.tan())
                .max(ground.max_above_line(x - half - behind, x - half, x, -rise, 0.0))
                .max(ground.max_above_line(x + half, x + half + ahead, x, rise, 0.0));
            let lift = (contact + clearance_at(params, t) - base) / (3.0 * t * (1.0 - t));
            needed = needed.max(lift);
        }
        if needed - top > params.max_swing_lift_m {
            return Err(StepFailure::SwingBlocked { needed_m: needed - top });
        }
        swing.control_height_m = needed;
        for i in 0..=SWING_SAMPLES {
            swing.hip_at(i as f64 / SWING_SAMPLES as f64)?;
        }
        Ok(swing)
    }

    /// The centre's X, its height without the control points' term, and the pitch, at `t`.
    fn curve_without_lift(&self, t: f64) -> (f64, f64, f64) {
        let (p0, p3) = (self.lift_off, self.touch_down);
        if t >= 1.0 {
            return (p3.x_m, p3.z_m, p3.pitch_rad);
        }
        let u = 1.0 - t;
        let x = p0.x_m + (p3.x_m - p0.x_m) * t * t * (3.0 - 2.0 * t);
        let base = p0.z_m * u * u * u + p3.z_m * t * t * t;
        let pitch = p0.pitch_rad + (p3.pitch_rad - p0.pitch_rad) * smoothstep(t);
        (x, base, pitch)
    }

    /// The swinging sole at phase `t` (0 lift-off, 1 touch-down).
    pub fn sole_at(&self, t: f64) -> Sole {
        let t = t.clamp(0.0, 1.0);
        let (x_m, base, pitch_rad) = self.curve_without_lift(t);
        Sole { x_m, z_m: base + 3.0 * t * (1.0 - t) * self.control_height_m, pitch_rad }
    }

    /// The lowest point of the swinging sole at phase `t`.
    pub fn lowest_point(&self, t: f64) -> DVec2 {
        let sole = self.sole_at(t);
        let length = self.leg.foot_length_m();
        let (heel, toe) = (sole.heel(length), sole.toe(length));
        if heel.y <= toe.y { heel } else { toe }
    }

    /// The lowest point of the sole at the phases `i / SWING_SAMPLES`, lift-off to touch-down.
    pub fn lowest_points(&self) -> Vec<DVec2> {
        (0..=SWING_SAMPLES).map(|i| self.lowest_point(i as f64 / SWING_SAMPLES as f64)).collect()
    }

    /// The step's length along X, metres.
    pub fn length_m(&self) -> f64 {
        self.touch_down.x_m - self.stance.x_m
    }

    /// The hip's position along X at phase `t` (clamped to `[0, 1]`): from midway between the
    /// lift-off and supporting ankles to midway between the supporting and touch-down ankles.
    pub fn hip_x_at(&self, t: f64) -> f64 {
        self.hip_x[0] + (self.hip_x[1] - self.hip_x[0]) * t.clamp(0.0, 1.0)
    }

    /// The hip at phase `t`: the key frames interpolated, lowered where a leg could not reach;
    /// an error when a foot is out of reach even so, or the hip comes closer to an ankle than
    /// the knee's flexion allows.
    fn hip_at(&self, t: f64) -> Result<DVec2, StepFailure> {
        let leg = &self.leg;
        let [h0, mid, h1] = self.hip_keys;
        let key =
            if t < 0.5 { h0 + (mid - h0) * smoothstep(2.0 * t) } else { mid + (h1 - mid) * smoothstep(2.0 * t - 1.0) };
        let x = self.hip_x_at(t);
        let reach = leg.max_reach_m();
        let ankles = [ankle_of(leg, &self.stance), ankle_of(leg, &self.sole_at(t))];
        let mut z = key;
        for ankle in ankles {
            let dx = (ankle.x - x).abs();
            if dx > reach {
                return Err(StepFailure::OutOfReach { phase: t, distance_m: dx });
            }
            z = z.min(ankle.y + (reach * reach - dx * dx).sqrt());
        }
        let hip = DVec2::new(x, z);
        for ankle in ankles {
            let distance_m = hip.distance(ankle);
            if distance_m < leg.min_reach_m() {
                return Err(StepFailure::OutOfReach { phase: t, distance_m });
            }
        }
        Ok(hip)
    }

    /// The hip at phase `t` (0–1) of the planned step, profile coordinates: what
    /// [`Swing::pose_at`] stands the legs under.
    pub fn hip_pose_at(&self, t: f64) -> DVec2 {
        let t = t.clamp(0.0, 1.0);
        // Every sample was checked when the step was planned; between samples the hip is the
        // same continuous function, so the fallback only guards against rounding.
        self.hip_at(t).unwrap_or_else(|_| DVec2::new(self.hip_x_at(t), self.hip_keys[1]))
    }

    /// Both legs at phase `t` (clamped to `[0, 1]`).
    pub fn pose_at(&self, t: f64) -> StepPose {
        let t = t.clamp(0.0, 1.0);
        let leg = &self.leg;
        let hip = self.hip_pose_at(t);
        let length = leg.foot_length_m();
        let pose = |sole: Sole| {
            let ankle = ankle_of(leg, &sole);
            LegPose { hip, knee: knee_of(leg, hip, ankle), ankle, heel: sole.heel(length), toe: sole.toe(length) }
        };
        StepPose { phase: t, swing: pose(self.sole_at(t)), stance: pose(self.stance) }
    }

    /// Both legs at the phases `i / samples`, lift-off to touch-down (`samples ≥ 1`).
    pub fn poses(&self, samples: usize) -> Vec<StepPose> {
        let n = samples.max(1);
        (0..=n).map(|i| self.pose_at(i as f64 / n as f64)).collect()
    }

    /// The hip height at the lift-off, mid-swing and touch-down key frames, metres.
    pub fn hip_key_heights_m(&self) -> [f64; 3] {
        self.hip_keys
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::footstep::foothold::sole_at;
    use crate::ground::GroundPiece;

    fn ground(pieces: &[(f64, f64, f64, f64)]) -> GroundProfile {
        GroundProfile::new(
            pieces.iter().map(|&(x0_m, z0_m, x1_m, z1_m)| GroundPiece { x0_m, z0_m, x1_m, z1_m }).collect(),
        )
        .unwrap()
    }

    fn plan(g: &GroundProfile, xs: [f64; 3]) -> Result<Swing, StepFailure> {
        let p = FootstepParams::default();
        let [a, b, c] = xs.map(|x| sole_at(g, &p, x).unwrap());
        Swing::plan(g, &p, a, b, c)
    }

    #[test]
    fn flat_ground_gives_the_nominal_level_step() {
        let g = ground(&[(0.0, 0.0, 5.0, 0.0)]);
        let s = plan(&g, [1.0, 1.65, 2.3]).unwrap();
        assert_eq!(s.kind, StepKind::Level);
        assert_eq!(s.control_height_m, s.nominal_control_height_m);
        assert_eq!(s.sole_at(0.0).centre(), DVec2::new(1.0, 0.0));
        assert_eq!(s.sole_at(1.0).centre(), DVec2::new(2.3, 0.0));
        let [h0, mid, h1] = s.hip_key_heights_m();
        assert!((h0 - h1).abs() < 1e-12 && mid > h0, "the hip rises over the supporting leg: {h0} {mid}");
    }

    #[test]
    fn knees_bend_forward_and_bones_keep_their_lengths() {
        let g = ground(&[(0.0, 0.0, 2.0, 0.0), (2.0, 0.3, 5.0, 0.3)]);
        let s = plan(&g, [1.2, 1.75, 2.4]).unwrap();
        assert_eq!(s.kind, StepKind::Uphill);
        let leg = LegGeometry::default();
        for pose in s.poses(48) {
            for l in [pose.swing, pose.stance] {
                assert!((l.knee.distance(l.hip) - leg.thigh_m).abs() < 1e-9);
                assert!((l.knee.distance(l.ankle) - leg.shin_m).abs() < 1e-9, "{l:?}");
                let side = (l.ankle - l.hip).perp_dot(l.knee - l.hip);
                assert!(side >= -1e-12, "the knee bends backward at {}: {l:?}", pose.phase);
            }
        }
    }

    #[test]
    fn the_swing_is_raised_over_a_block() {
        let g = ground(&[(0.0, 0.0, 5.0, 0.0)]);
        let flat = plan(&g, [1.0, 1.5, 2.2]).unwrap();
        let g = ground(&[(0.0, 0.0, 1.3, 0.0), (1.3, 0.3, 1.9, 0.3), (1.9, 0.0, 5.0, 0.0)]);
        let s = plan(&g, [1.0, 1.6, 2.2]).unwrap();
        assert!(s.control_height_m > flat.control_height_m + 0.3, "{}", s.control_height_m);
        for i in 1..(8 * SWING_SAMPLES) {
            let t = i as f64 / (8 * SWING_SAMPLES) as f64;
            let low = s.lowest_point(t);
            if (1.3..=1.9).contains(&low.x) {
                assert!(low.y > 0.3, "through the block at {t}: {low}");
            }
        }
    }

    #[test]
    fn too_high_or_too_far_fails() {
        let g = ground(&[(0.0, 0.0, 1.6, 0.0), (1.6, 1.2, 1.8, 1.2), (1.8, 0.0, 5.0, 0.0)]);
        assert!(matches!(plan(&g, [1.0, 1.45, 2.2]), Err(StepFailure::SwingBlocked { .. })));
        let g = ground(&[(0.0, 0.0, 5.0, 0.0)]);
        assert!(matches!(plan(&g, [0.5, 1.0, 3.0]), Err(StepFailure::OutOfReach { .. })));
    }

    #[test]
    fn uphill_and_downhill_use_their_key_frames() {
        let flat = plan(&ground(&[(0.0, 0.0, 5.0, 0.0)]), [1.2, 1.8, 2.45]).unwrap();
        let level_mid = flat.hip_key_heights_m()[1];
        let g = ground(&[(0.0, 0.0, 2.0, 0.0), (2.0, 0.2, 5.0, 0.2)]);
        let up = plan(&g, [1.2, 1.8, 2.45]).unwrap();
        assert_eq!(up.kind, StepKind::Uphill);
        let [h0, mid, _] = up.hip_key_heights_m();
        assert!(mid < level_mid - 0.03 && mid <= h0 + 0.01, "uphill: the hip stays low while the front leg lifts");
        let bend = |s: &Swing| {
            let l = s.pose_at(0.5).swing;
            l.hip.distance(l.ankle)
        };
        assert!(bend(&up) < bend(&flat) - 0.05, "uphill: the front (swinging) leg bends more");
        let g = ground(&[(0.0, 0.2, 2.0, 0.2), (2.0, 0.0, 5.0, 0.0)]);
        let down = plan(&g, [1.2, 1.8, 2.45]).unwrap();
        assert_eq!(down.kind, StepKind::Downhill);
        let [h0, mid, h1] = down.hip_key_heights_m();
        assert!(h1 < h0 && mid < h1 + 0.5 * (h0 - h1), "downhill: the hip comes down early");
    }
}
