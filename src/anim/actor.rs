//! The built-in character (seed 002 §3.1, Fig. 1; DESIGN.md §3): the 22-DOF digital actor.
//!
//! The root (`Hips`) translates in three dimensions and turns on the standing plane (4 DOF); the
//! waist (`Chest`) bends forward and twists (2 DOF); each arm has a 3-DOF shoulder and a 1-DOF
//! elbow (4 DOF); each leg has a 2-DOF hip, a knee and an ankle (4 DOF). The neck (`Neck`, from
//! the base of the neck to the base of the skull) and the head (`Head`, from there to the top of
//! the head) ride on the chest without channels of their own. 4 + 2 + 2·4 + 2·4 = 22.
//!
//! Invariants: the bind pose stands on level ground (z = 0) facing +X, legs straight, arms
//! hanging, with each toe tip on the ground and the top of the head about 1.75 m up; left joints are on +Y and every right joint mirrors
//! its left partner (Y negated), so [`mirror_pairs`](super::clip::mirror_pairs) pairs them by name.
//!
//! A joint's local rotation is the product of rotations about its channel axes in channel order
//! (the hip is `Ry(flex)·Rx(abduction)`, the shoulder `Ry·Rx·Rz`, the waist `Ry·Rz`, the knee,
//! elbow and ankle `Ry`); the root's rotation is a yaw about Z. Signs follow the right-hand rule
//! in the Z-up, X-forward frame: a positive rotation about Y tips +Z toward +X and +X toward −Z,
//! so a limb hanging down (−Z) swings *backward*. Hence flexing the hip or the shoulder forward
//! and bending the elbow are negative Y rotations, bending the knee is positive, lifting the toes
//! is negative and pointing them is positive, and a positive waist bend leans the chest forward.
//! A positive rotation about X moves a hanging limb toward +Y (abduction for the left side,
//! adduction for the right).

use glam::DVec3;

use super::skeleton::{Channel, Joint, Skeleton};

/// The root: pelvis centre. Channels X, Y, Z position and Z rotation.
pub const HIPS: &str = "Hips";
/// The waist, above the pelvis. Channels Y (bend forward) and Z (twist) rotation.
pub const CHEST: &str = "Chest";
/// The base of the neck (seventh cervical vertebra); no channels.
pub const NECK: &str = "Neck";
/// The base of the skull, at the top of the neck; no channels. Its end site is the top of the
/// head.
pub const HEAD: &str = "Head";
/// Left shoulder. Channels Y (flex), X (abduction), Z (twist) rotation.
pub const LEFT_ARM: &str = "LeftArm";
/// Left elbow. Channel Y rotation. Its end site is the hand.
pub const LEFT_FORE_ARM: &str = "LeftForeArm";
/// Right shoulder. Channels Y (flex), X (adduction), Z (twist) rotation.
pub const RIGHT_ARM: &str = "RightArm";
/// Right elbow. Channel Y rotation. Its end site is the hand.
pub const RIGHT_FORE_ARM: &str = "RightForeArm";
/// Left hip. Channels Y (flex) and X (abduction) rotation.
pub const LEFT_UP_LEG: &str = "LeftUpLeg";
/// Left knee. Channel Y rotation.
pub const LEFT_LEG: &str = "LeftLeg";
/// Left ankle. Channel Y rotation. Its end site is the toe tip.
pub const LEFT_FOOT: &str = "LeftFoot";
/// Right hip. Channels Y (flex) and X (adduction) rotation.
pub const RIGHT_UP_LEG: &str = "RightUpLeg";
/// Right knee. Channel Y rotation.
pub const RIGHT_LEG: &str = "RightLeg";
/// Right ankle. Channel Y rotation. Its end site is the toe tip.
pub const RIGHT_FOOT: &str = "RightFoot";

/// Height of the pelvis (root) above the ground in the bind pose, metres.
pub const PELVIS_HEIGHT_M: f64 = 0.95;
/// Lateral distance of each hip joint from the pelvis centre, metres.
pub const HIP_HALF_WIDTH_M: f64 = 0.09;
/// Hip to knee, metres.
pub const THIGH_M: f64 = 0.45;
/// Knee to ankle, metres.
pub const SHIN_M: f64 = 0.43;
/// Height of the ankle joint above the ground when standing, metres.
pub const ANKLE_HEIGHT_M: f64 = PELVIS_HEIGHT_M - THIGH_M - SHIN_M;
/// Forward distance from the ankle joint to the toe tip, metres.
pub const FOOT_FORWARD_M: f64 = 0.19;
/// Backward distance from the ankle joint to the heel point on the sole (straight under the
/// back of the heel), metres.
pub const HEEL_BACK_M: f64 = 0.05;
/// The heel point (on the sole, straight under the back of the heel) relative to the ankle joint
/// in the foot's bind frame, metres.
pub const HEEL_POINT: DVec3 = DVec3::new(-HEEL_BACK_M, 0.0, -ANKLE_HEIGHT_M);
/// The toe tip (the foot's end site) relative to the ankle joint in the foot's bind frame, metres.
pub const TOE_POINT: DVec3 = DVec3::new(FOOT_FORWARD_M, 0.0, -ANKLE_HEIGHT_M);
/// Pelvis to waist joint, metres.
pub const WAIST_M: f64 = 0.12;
/// Waist joint to the base of the neck, metres.
pub const SPINE_M: f64 = 0.43;
/// Base of the neck to the base of the skull, metres.
pub const NECK_M: f64 = 0.10;
/// Base of the skull to the top of the head, metres.
pub const HEAD_M: f64 = 0.15;
/// Height of the shoulders above the waist joint, metres.
pub const SHOULDER_RISE_M: f64 = 0.38;
/// Lateral distance of each shoulder from the spine, metres.
pub const SHOULDER_HALF_WIDTH_M: f64 = 0.18;
/// Shoulder to elbow, metres.
pub const UPPER_ARM_M: f64 = 0.29;
/// Elbow to the middle of the hand, metres.
pub const FOREARM_M: f64 = 0.33;

/// The actor's degrees of freedom: root 4, waist 2, arms 2·4, legs 2·4.
pub const DOF: usize = 22;

fn joint(name: &str, parent: usize, offset: DVec3, channels: &[Channel], end_site: Option<DVec3>) -> Joint {
    Joint { name: name.into(), parent: Some(parent), offset, channels: channels.to_vec(), end_site }
}

/// The built-in 22-DOF actor of seed 002 Fig. 1, an adult about 1.75 m tall, in the Z-up frame
/// (X forward, Y left). Joint order, parents first: `Hips`, `Chest`, `Neck`, `Head`, `LeftArm`,
/// `LeftForeArm`, `RightArm`, `RightForeArm`, `LeftUpLeg`, `LeftLeg`, `LeftFoot`, `RightUpLeg`,
/// `RightLeg`, `RightFoot`.
pub fn actor() -> Skeleton {
    use Channel::{XPosition, XRotation, YPosition, YRotation, ZPosition, ZRotation};
    let mut joints = vec![Joint {
        name: HIPS.into(),
        parent: None,
        offset: DVec3::new(0.0, 0.0, PELVIS_HEIGHT_M),
        channels: vec![XPosition, YPosition, ZPosition, ZRotation],
        end_site: None,
    }];
    joints.push(joint(CHEST, 0, DVec3::new(0.0, 0.0, WAIST_M), &[YRotation, ZRotation], None));
    joints.push(joint(NECK, 1, DVec3::new(0.0, 0.0, SPINE_M), &[], None));
    joints.push(joint(HEAD, 2, DVec3::new(0.0, 0.0, NECK_M), &[], Some(DVec3::new(0.0, 0.0, HEAD_M))));
    for (arm, fore_arm, side) in [(LEFT_ARM, LEFT_FORE_ARM, 1.0), (RIGHT_ARM, RIGHT_FORE_ARM, -1.0)] {
        let shoulder = joints.len();
        joints.push(joint(
            arm,
            1,
            DVec3::new(0.0, side * SHOULDER_HALF_WIDTH_M, SHOULDER_RISE_M),
            &[YRotation, XRotation, ZRotation],
            None,
        ));
        joints.push(joint(
            fore_arm,
            shoulder,
            DVec3::new(0.0, 0.0, -UPPER_ARM_M),
            &[YRotation],
            Some(DVec3::new(0.0, 0.0, -FOREARM_M)),
        ));
    }
    for (up_leg, leg, foot, side) in
        [(LEFT_UP_LEG, LEFT_LEG, LEFT_FOOT, 1.0), (RIGHT_UP_LEG, RIGHT_LEG, RIGHT_FOOT, -1.0)]
    {
        let hip = joints.len();
        joints.push(joint(up_leg, 0, DVec3::new(0.0, side * HIP_HALF_WIDTH_M, 0.0), &[YRotation, XRotation], None));
        joints.push(joint(leg, hip, DVec3::new(0.0, 0.0, -THIGH_M), &[YRotation], None));
        joints.push(joint(foot, hip + 1, DVec3::new(0.0, 0.0, -SHIN_M), &[YRotation], Some(TOE_POINT)));
    }
    Skeleton::new(joints).expect("the built-in actor is a valid skeleton")
}

#[cfg(test)]
mod tests {
    use glam::DQuat;

    use super::*;
    use crate::anim::clip::mirror_pairs;

    #[test]
    fn has_twenty_two_degrees_of_freedom() {
        let s = actor();
        let dof: usize = s.joints().iter().map(|j| j.channels.len()).sum();
        assert_eq!(dof, DOF);
        assert_eq!(dof, 22);
        let rotations = |n: &str| s.joints()[s.find(n).unwrap()].channels.len();
        assert_eq!(s.joints()[0].channels.len(), 4);
        assert_eq!(rotations(CHEST), 2);
        assert_eq!(rotations(LEFT_ARM) + rotations(LEFT_FORE_ARM), 4);
        assert_eq!(rotations(RIGHT_UP_LEG) + rotations(RIGHT_LEG) + rotations(RIGHT_FOOT), 4);
    }

    #[test]
    fn bind_pose_stands_on_the_ground_facing_forward() {
        let s = actor();
        let pose = s.bind_pose();
        let mut g = Vec::new();
        s.globals(&pose, &mut g);
        let at = |n: &str| g[s.find(n).unwrap()].0;
        let hips = at(HIPS);
        assert!((0.93..=0.95).contains(&hips.z));
        for (foot, up_leg, side) in [(LEFT_FOOT, LEFT_UP_LEG, 1.0), (RIGHT_FOOT, RIGHT_UP_LEG, -1.0)] {
            let i = s.find(foot).unwrap();
            let ankle = g[i].0;
            assert!((0.07 - 1e-9..=0.08).contains(&ankle.z), "ankle at {}", ankle.z);
            let toe = s.tip(&g, i);
            assert!(toe.z.abs() < 1e-12 && toe.x > ankle.x, "toe at {toe}");
            assert!((at(up_leg).y - side * 0.09).abs() < 1e-12);
        }
        assert!((at(LEFT_LEG).z - (hips.z - 0.45)).abs() < 1e-12);
        let head = s.tip(&g, s.find(HEAD).unwrap());
        assert!((1.70..1.80).contains(&head.z), "head top at {}", head.z);
        assert!((at(HEAD).z - at(NECK).z - 0.1).abs() < 1e-12, "a 10 cm neck");
        assert_eq!(s.joints()[s.find(HEAD).unwrap()].parent, s.find(NECK));
        assert!(g.iter().all(|(p, _)| p.z >= 0.0));
    }

    #[test]
    fn left_and_right_mirror_each_other() {
        let s = actor();
        let pairs = mirror_pairs(&s);
        let pos = s.positions(&s.bind_pose());
        for (i, &m) in pairs.iter().enumerate() {
            assert_eq!(s.joints()[i].channels, s.joints()[m].channels);
            assert!((pos[m] - DVec3::new(pos[i].x, -pos[i].y, pos[i].z)).length() < 1e-12);
        }
        assert_eq!(pairs[s.find(LEFT_FOOT).unwrap()], s.find(RIGHT_FOOT).unwrap());
    }

    #[test]
    fn sign_conventions() {
        let s = actor();
        let mut pose = s.bind_pose();
        let (hip, knee, ankle) = (s.find(LEFT_UP_LEG).unwrap(), s.find(LEFT_LEG).unwrap(), s.find(LEFT_FOOT).unwrap());
        // Flexing the hip forward is a negative Y rotation: the knee comes in front of the hip.
        pose.rotations[hip] = DQuat::from_rotation_y(-0.5);
        // Bending the knee is positive: the ankle goes behind the knee.
        pose.rotations[knee] = DQuat::from_rotation_y(1.0);
        let p = s.positions(&pose);
        assert!(p[knee].x > p[hip].x + 0.2);
        assert!(p[ankle].x < p[knee].x);
        // A positive X rotation abducts the left leg.
        pose.rotations[hip] = DQuat::from_rotation_x(0.3);
        pose.rotations[knee] = DQuat::IDENTITY;
        assert!(s.positions(&pose)[knee].y > p[hip].y + 0.1);
        // Bending the elbow is negative: the hand comes forward.
        let elbow = s.find(LEFT_FORE_ARM).unwrap();
        pose.rotations[elbow] = DQuat::from_rotation_y(-1.0);
        let mut g = Vec::new();
        s.globals(&pose, &mut g);
        assert!(s.tip(&g, elbow).x > g[elbow].0.x + 0.2);
    }
}
