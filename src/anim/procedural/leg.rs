//! The legs of the procedural walk (seed 002 §4.1, §4: the legs are solved from where the feet
//! go; DESIGN.md §4): the actor's joint indices, analytic two-link leg inverse kinematics, the
//! ankle angle giving the foot a pitch, the foot's heel and toe points, and the placing of a leg
//! so that a chosen point of the foot (heel, toe tip or the ankle's footprint) lands exactly on
//! its target.

use glam::{DQuat, DVec3};

use crate::anim::actor::{self, HEEL_POINT, HIP_HALF_WIDTH_M, SHIN_M, THIGH_M, TOE_POINT};
use crate::anim::skeleton::{Pose, Skeleton};
use crate::geom::wrap_angle;

/// Joint indices of the actor; index 0 of each pair is the left side.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Rig {
    /// The waist.
    pub chest: usize,
    /// Shoulders.
    pub arm: [usize; 2],
    /// Elbows.
    pub fore_arm: [usize; 2],
    /// Hips.
    pub up_leg: [usize; 2],
    /// Knees.
    pub leg: [usize; 2],
    /// Ankles.
    pub foot: [usize; 2],
}

impl Rig {
    /// The indices in `s` (the built-in actor).
    pub(crate) fn of(s: &Skeleton) -> Rig {
        Rig::find(s).expect("the actor has every named joint")
    }

    /// The indices in `s` when it is built like the actor: every named joint present, each
    /// leg a hip, knee and ankle chain with the actor's bone lengths. `None` for any other
    /// skeleton (an imported motion-capture rig).
    pub(crate) fn find(s: &Skeleton) -> Option<Rig> {
        let f = |n: &str| s.find(n);
        use actor::*;
        let rig = Rig {
            chest: f(CHEST)?,
            arm: [f(LEFT_ARM)?, f(RIGHT_ARM)?],
            fore_arm: [f(LEFT_FORE_ARM)?, f(RIGHT_FORE_ARM)?],
            up_leg: [f(LEFT_UP_LEG)?, f(RIGHT_UP_LEG)?],
            leg: [f(LEFT_LEG)?, f(RIGHT_LEG)?],
            foot: [f(LEFT_FOOT)?, f(RIGHT_FOOT)?],
        };
        let j = s.joints();
        let close = |a: DVec3, b: DVec3| (a - b).length() < 1e-6;
        let built_like_the_actor = (0..2).all(|i| {
            let hip = &j[rig.up_leg[i]];
            hip.parent == Some(0)
                && close(hip.offset, DVec3::new(0.0, SIDES[i] * HIP_HALF_WIDTH_M, 0.0))
                && j[rig.leg[i]].parent == Some(rig.up_leg[i])
                && close(j[rig.leg[i]].offset, DVec3::new(0.0, 0.0, -THIGH_M))
                && j[rig.foot[i]].parent == Some(rig.leg[i])
                && close(j[rig.foot[i]].offset, DVec3::new(0.0, 0.0, -SHIN_M))
        });
        built_like_the_actor.then_some(rig)
    }
}

/// Lateral sign of each side: left +1, right −1.
pub(crate) const SIDES: [f64; 2] = [1.0, -1.0];

/// Longest hip-to-ankle distance a leg is asked to reach, metres (the knee keeps about 3°).
pub(crate) const MAX_REACH_M: f64 = 0.9995 * (THIGH_M + SHIN_M);

/// Hip-to-ankle distance with the knee bent by `knee` radians, metres.
pub(crate) fn reach_of_knee(knee: f64) -> f64 {
    (THIGH_M * THIGH_M + SHIN_M * SHIN_M + 2.0 * THIGH_M * SHIN_M * knee.cos()).sqrt()
}

/// Hip flexion (Y), hip abduction (X) and knee (Y) angles putting the ankle at `d` from the hip
/// joint, in the pelvis frame; a target out of reach is moved along the hip–target line.
pub(crate) fn leg_ik(d: DVec3) -> (f64, f64, f64) {
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
pub(crate) fn ankle_for_pitch(leg: DQuat, pitch: f64) -> f64 {
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

/// The foot's orientation with heading `yaw` and pitch `pitch` (positive toes down), radians.
pub(crate) fn foot_rotation(yaw: f64, pitch: f64) -> DQuat {
    DQuat::from_rotation_z(yaw) * DQuat::from_rotation_y(pitch)
}

/// A point of the foot in the foot's frame (ankle at the origin), between the toe tip (`0`)
/// and the heel point (`1`).
pub(crate) fn sole_point(heel_weight: f64) -> DVec3 {
    TOE_POINT.lerp(HEEL_POINT, heel_weight)
}

/// The toes-down pitch in `[0, max]` for which the ankle of a foot standing on its toe tip at
/// `toe` (heading `yaw`) lies `reach` from `hip`: 0 when the flat foot is already close enough,
/// `max` when even that pitch is too little. The ankle rises toward the hip as the heel lifts,
/// so the distance falls with the pitch; bisection.
pub(crate) fn pitch_for_reach(hip: DVec3, toe: DVec3, yaw: f64, reach: f64, max: f64) -> f64 {
    let dist = |p: f64| (toe - foot_rotation(yaw, p) * TOE_POINT - hip).length();
    if dist(0.0) <= reach {
        return 0.0;
    }
    if dist(max) >= reach {
        return max;
    }
    let (mut lo, mut hi) = (0.0, max);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if dist(mid) > reach { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

/// Where a foot must go: the point `local` of the foot (in its frame, ankle at the origin) at
/// `point` in the world, with the foot's heading and pitch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FootTarget {
    /// World position of the foot point, metres.
    pub point: DVec3,
    /// The foot point in the foot's frame, metres.
    pub local: DVec3,
    /// Heading, radians.
    pub yaw: f64,
    /// Pitch, radians (positive toes down).
    pub pitch: f64,
    /// Whether the foot is on the ground.
    pub planted: bool,
}

impl FootTarget {
    /// The ankle position this target asks for, metres.
    pub(crate) fn ankle(&self) -> DVec3 {
        self.point - foot_rotation(self.yaw, self.pitch) * self.local
    }
}

/// Sets the hip, knee and ankle of leg `i` in `out` (whose root is already set) so that the
/// foot point of `target` lands on its target with the target's pitch. The actor's hip has no
/// twist, so the foot's heading follows the pelvis up to the small turn that hip abduction
/// gives it; the ankle is moved until the foot point itself, not only the ankle, is on target.
pub(crate) fn place_leg(rig: &Rig, i: usize, target: &FootTarget, out: &mut Pose) {
    let root_rot = out.rotations[0];
    let inv = root_rot.inverse();
    let hip = out.root + root_rot * DVec3::new(0.0, SIDES[i] * HIP_HALF_WIDTH_M, 0.0);
    let mut ankle = target.ankle();
    for _ in 0..12 {
        let (flex, abduction, knee) = leg_ik(inv * (ankle - hip));
        let hip_q = DQuat::from_rotation_y(flex) * DQuat::from_rotation_x(abduction);
        let knee_q = DQuat::from_rotation_y(knee);
        let ankle_q = DQuat::from_rotation_y(ankle_for_pitch(hip_q * knee_q, target.pitch));
        out.rotations[rig.up_leg[i]] = hip_q;
        out.rotations[rig.leg[i]] = knee_q;
        out.rotations[rig.foot[i]] = ankle_q;
        let reached =
            hip + root_rot * (hip_q * (DVec3::new(0.0, 0.0, -THIGH_M) + knee_q * DVec3::new(0.0, 0.0, -SHIN_M)));
        let foot_q = root_rot * hip_q * knee_q * ankle_q;
        let error = target.point - (reached + foot_q * target.local);
        if error.length() < 1e-12 {
            break;
        }
        ankle = reached + error;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert!((reach_of_knee(0.0) - 0.88).abs() < 1e-12 && reach_of_knee(1.0) < 0.8);
    }

    #[test]
    fn only_a_skeleton_built_like_the_actor_has_its_rig() {
        let s = actor::actor();
        assert!(Rig::find(&s).is_some());
        // The same names with a longer shin (an imported rig): not the actor's legs.
        let mut joints = s.joints().to_vec();
        let shin = s.find(actor::LEFT_FOOT).unwrap();
        joints[shin].offset.z -= 0.05;
        assert!(Rig::find(&Skeleton::new(joints).unwrap()).is_none());
        let mut joints = s.joints().to_vec();
        joints[s.find(actor::RIGHT_LEG).unwrap()].name = "RightKnee".into();
        assert!(Rig::find(&Skeleton::new(joints).unwrap()).is_none());
    }

    #[test]
    fn placed_legs_put_the_foot_point_on_target() {
        let s = actor::actor();
        let rig = Rig::of(&s);
        let mut pose = s.bind_pose();
        pose.root = DVec3::new(0.1, 0.02, 0.92);
        pose.rotations[0] = DQuat::from_rotation_z(0.4);
        for (local, pitch, yaw) in [(TOE_POINT, 0.5, 0.45), (HEEL_POINT, -0.25, 0.3), (sole_point(0.5), 0.0, 0.4)] {
            let point = DVec3::new(0.3, 0.1, 0.0);
            let target = FootTarget { point, local, yaw, pitch, planted: true };
            place_leg(&rig, 0, &target, &mut pose);
            let mut g = Vec::new();
            s.globals(&pose, &mut g);
            let (ankle, q) = g[rig.foot[0]];
            assert!((ankle + q * local - point).length() < 1e-7, "{local}: {}", ankle + q * local);
            assert!(((q * DVec3::X).z + pitch.sin()).abs() < 1e-9);
        }
    }

    #[test]
    fn heel_rise_brings_the_ankle_to_the_hip() {
        let hip = DVec3::new(0.3, 0.0, 0.92);
        let toe = DVec3::ZERO;
        let p = pitch_for_reach(hip, toe, 0.0, 0.85, 1.3);
        let ankle = toe - foot_rotation(0.0, p) * TOE_POINT;
        assert!(p > 0.1 && ((ankle - hip).length() - 0.85).abs() < 1e-9, "{p}");
        assert_eq!(pitch_for_reach(DVec3::new(0.0, 0.0, 0.5), toe, 0.0, 0.85, 1.3), 0.0);
        assert_eq!(pitch_for_reach(DVec3::new(3.0, 0.0, 0.5), toe, 0.0, 0.85, 1.3), 1.3);
    }
}
