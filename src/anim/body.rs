//! The body's collision geometry and the upper body's configuration (seed 002 §5; DESIGN.md
//! §5): a capsule on every bone of the built-in actor, posed by forward kinematics from the
//! pose `--bvh-out` writes, their clearance from the obstacles' prisms
//! ([`crate::geom::Prism`]), and the offsets the upper-body planner adds to the database's
//! motion ([`UpperConfig`]).
//!
//! The capsules run between the actor's joints, one per bone of the exported skeleton: the
//! pelvis from the hips to the waist joint (it holds the hips' short bones to the legs), the
//! torso from the waist joint to the base of the neck, the neck, the head from the base of the
//! skull to the top of the head (its rounded end at the top, so the actor stands 1.75 m tall),
//! each collarbone from the waist joint to the shoulder, each upper arm from the shoulder to the
//! elbow, each forearm from the elbow to the middle of the hand, and each thigh, shin and foot
//! (ankle to toe). Their radii ([`TORSO_RADIUS_M`] …) are an adult's; with the shoulders 0.36 m
//! apart the arms' capsules make the body 0.46 m wide at the shoulders, and turned side-on the
//! chest is 0.22 m deep.

use glam::{DQuat, DVec3};

use super::actor::{
    CHEST, HEAD, LEFT_ARM, LEFT_FOOT, LEFT_FORE_ARM, LEFT_LEG, LEFT_UP_LEG, NECK, RIGHT_ARM, RIGHT_FOOT,
    RIGHT_FORE_ARM, RIGHT_LEG, RIGHT_UP_LEG,
};
use super::skeleton::{Pose, Skeleton};
use crate::geom::{Aabb, Capsule, Prism};

/// Radius of the torso's capsule, metres.
pub const TORSO_RADIUS_M: f64 = 0.11;
/// Radius of the head's capsule, metres.
pub const HEAD_RADIUS_M: f64 = 0.09;
/// Radius of an upper arm's capsule, metres.
pub const UPPER_ARM_RADIUS_M: f64 = 0.05;
/// Radius of a forearm's capsule, metres.
pub const FOREARM_RADIUS_M: f64 = 0.045;
/// Radius of the neck's capsule, metres.
pub const NECK_RADIUS_M: f64 = 0.06;
/// Radius of a collarbone's capsule, metres.
pub const COLLARBONE_RADIUS_M: f64 = 0.05;
/// Radius of a thigh's capsule, metres.
pub const THIGH_RADIUS_M: f64 = 0.07;
/// Radius of a shin's capsule, metres.
pub const SHIN_RADIUS_M: f64 = 0.05;
/// Radius of a foot's capsule, metres.
pub const FOOT_RADIUS_M: f64 = 0.04;

/// A part of the body: one bone of the exported skeleton.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// Hips to the waist joint.
    Pelvis,
    /// Waist to the base of the neck.
    Torso,
    /// Base of the neck to the base of the skull.
    Neck,
    /// Base of the skull to the top of the head.
    Head,
    /// Waist joint to shoulder; 0 left, 1 right.
    Collarbone(usize),
    /// Shoulder to elbow; 0 left, 1 right.
    UpperArm(usize),
    /// Elbow to hand; 0 left, 1 right.
    Forearm(usize),
    /// Hip to knee; 0 left, 1 right.
    Thigh(usize),
    /// Knee to ankle; 0 left, 1 right.
    Shin(usize),
    /// Ankle to toe; 0 left, 1 right.
    Foot(usize),
}

impl Part {
    /// A leg's part (what the upper-body planner cannot move).
    pub fn is_leg(self) -> bool {
        matches!(self, Part::Thigh(_) | Part::Shin(_) | Part::Foot(_))
    }
}

/// Which capsules [`UpperBody::place`] builds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Parts {
    /// Every bone's: the trunk's, both arms' and both legs'.
    All,
    /// The pelvis, the torso, the neck, the head, the collarbones and the shoulder joints (what
    /// the waist moves; the arms' capsules shrunk to balls at the shoulders).
    Trunk,
    /// One arm's two capsules; 0 left, 1 right.
    Arm(usize),
    /// The trunk's and both arms' (what the waist moves, the arms with it).
    TrunkAndArms,
    /// Both legs' thighs, shins and feet (no offset moves them).
    Legs,
}

/// Offsets the upper-body planner adds to the database's upper-body motion, radians. All zero
/// is the database's motion unchanged.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct UpperConfig {
    /// The waist: bend forward, twist to the left (about the spine).
    pub waist: [f64; 2],
    /// Each arm (0 left, 1 right): flex forward at the shoulder, abduction (outward), twist
    /// (the upper arm turned outward), elbow bend.
    pub arms: [[f64; 4]; 2],
}

impl UpperConfig {
    /// The waist's local rotation offset.
    pub fn waist_rotation(&self) -> DQuat {
        DQuat::from_rotation_y(self.waist[0]) * DQuat::from_rotation_z(self.waist[1])
    }

    /// Arm `side`'s shoulder and elbow rotation offsets (mirrored for the right arm).
    pub fn arm_rotations(&self, side: usize) -> (DQuat, DQuat) {
        let s = if side == 0 { 1.0 } else { -1.0 };
        let [flex, abduction, twist, elbow] = self.arms[side];
        let shoulder =
            DQuat::from_rotation_y(-flex) * DQuat::from_rotation_x(s * abduction) * DQuat::from_rotation_z(-s * twist);
        (shoulder, DQuat::from_rotation_y(-elbow))
    }

    /// Linear interpolation toward `other` by `t ∈ [0, 1]`.
    pub fn lerp(&self, other: &UpperConfig, t: f64) -> UpperConfig {
        let l = |a: f64, b: f64| a + (b - a) * t;
        UpperConfig {
            waist: [l(self.waist[0], other.waist[0]), l(self.waist[1], other.waist[1])],
            arms: [0, 1].map(|s| [0, 1, 2, 3].map(|k| l(self.arms[s][k], other.arms[s][k]))),
        }
    }
}

/// The upper body's joints in one frame: the hips' global placement and the database's local
/// rotations of the joints above them (see [`UpperBody::frame`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UpperFrame {
    hips: (DVec3, DQuat),
    chest: DQuat,
    neck: DQuat,
    head: DQuat,
    arm: [DQuat; 2],
    fore_arm: [DQuat; 2],
    up_leg: [DQuat; 2],
    leg: [DQuat; 2],
    foot: [DQuat; 2],
}

impl UpperFrame {
    /// Where the hips are, world.
    pub fn hips(&self) -> DVec3 {
        self.hips.0
    }
}

/// The joints the capsules hang on and the bones between them, found once per skeleton.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UpperBody {
    chest: usize,
    neck: usize,
    head: usize,
    arm: [usize; 2],
    fore_arm: [usize; 2],
    chest_offset: DVec3,
    neck_offset: DVec3,
    head_offset: DVec3,
    head_tip: DVec3,
    arm_offset: [DVec3; 2],
    fore_arm_offset: [DVec3; 2],
    hand_tip: [DVec3; 2],
    up_leg: [usize; 2],
    leg: [usize; 2],
    foot: [usize; 2],
    up_leg_offset: [DVec3; 2],
    leg_offset: [DVec3; 2],
    foot_offset: [DVec3; 2],
    toe_tip: [DVec3; 2],
}

impl UpperBody {
    /// The body of `skeleton`, when it has the actor's named joints in the actor's hierarchy
    /// (the chest and the legs on the root, the neck and the arms on the chest; `None` for an
    /// imported rig).
    pub fn of(skeleton: &Skeleton) -> Option<UpperBody> {
        let f = |n: &str| skeleton.find(n);
        let j = skeleton.joints();
        let (chest, neck, head) = (f(CHEST)?, f(NECK)?, f(HEAD)?);
        let (arm, fore_arm) = ([f(LEFT_ARM)?, f(RIGHT_ARM)?], [f(LEFT_FORE_ARM)?, f(RIGHT_FORE_ARM)?]);
        let (up_leg, leg, foot) =
            ([f(LEFT_UP_LEG)?, f(RIGHT_UP_LEG)?], [f(LEFT_LEG)?, f(RIGHT_LEG)?], [f(LEFT_FOOT)?, f(RIGHT_FOOT)?]);
        let chained = j[chest].parent == Some(0)
            && j[neck].parent == Some(chest)
            && j[head].parent == Some(neck)
            && (0..2).all(|s| j[arm[s]].parent == Some(chest) && j[fore_arm[s]].parent == Some(arm[s]))
            && (0..2).all(|s| {
                j[up_leg[s]].parent == Some(0)
                    && j[leg[s]].parent == Some(up_leg[s])
                    && j[foot[s]].parent == Some(leg[s])
            });
        if !chained {
            return None;
        }
        Some(UpperBody {
            chest,
            neck,
            head,
            arm,
            fore_arm,
            chest_offset: j[chest].offset,
            neck_offset: j[neck].offset,
            head_offset: j[head].offset,
            head_tip: j[head].end_site?,
            arm_offset: arm.map(|a| j[a].offset),
            fore_arm_offset: fore_arm.map(|a| j[a].offset),
            hand_tip: [j[fore_arm[0]].end_site?, j[fore_arm[1]].end_site?],
            up_leg,
            leg,
            foot,
            up_leg_offset: up_leg.map(|a| j[a].offset),
            leg_offset: leg.map(|a| j[a].offset),
            foot_offset: foot.map(|a| j[a].offset),
            toe_tip: [j[foot[0]].end_site?, j[foot[1]].end_site?],
        })
    }

    /// The upper body's joints in `pose` (in the pose's frame: world, for a world pose).
    pub fn frame(&self, pose: &Pose) -> UpperFrame {
        let r = &pose.rotations;
        UpperFrame {
            hips: (pose.root, r[0]),
            chest: r[self.chest],
            neck: r[self.neck],
            head: r[self.head],
            arm: self.arm.map(|a| r[a]),
            fore_arm: self.fore_arm.map(|a| r[a]),
            up_leg: self.up_leg.map(|a| r[a]),
            leg: self.leg.map(|a| r[a]),
            foot: self.foot.map(|a| r[a]),
        }
    }

    /// Where the waist joint is in frame `f` (no offset moves it).
    pub fn waist(&self, f: &UpperFrame) -> DVec3 {
        f.hips.0 + f.hips.1 * self.chest_offset
    }

    /// Adds the offsets `c` to `pose`'s waist and arms (all zero leaves it as it is, bit for
    /// bit).
    pub fn apply(&self, pose: &mut Pose, c: &UpperConfig) {
        if *c == UpperConfig::default() {
            return;
        }
        let r = &mut pose.rotations;
        r[self.chest] = (r[self.chest] * c.waist_rotation()).normalize();
        for side in 0..2 {
            let (shoulder, elbow) = c.arm_rotations(side);
            r[self.arm[side]] = (r[self.arm[side]] * shoulder).normalize();
            r[self.fore_arm[side]] = (r[self.fore_arm[side]] * elbow).normalize();
        }
    }

    /// The capsules `which` of frame `f` with the offsets `c`, into `out` (cleared first).
    pub fn place(&self, f: &UpperFrame, c: &UpperConfig, which: Parts, out: &mut Vec<(Part, Capsule)>) {
        out.clear();
        let (hp, hq) = f.hips;
        let chest_p = hp + hq * self.chest_offset;
        let chest_q = hq * f.chest * c.waist_rotation();
        if matches!(which, Parts::All | Parts::Trunk | Parts::TrunkAndArms) {
            let neck_p = chest_p + chest_q * self.neck_offset;
            let neck_q = chest_q * f.neck;
            let head_p = neck_p + neck_q * self.head_offset;
            let head_q = neck_q * f.head;
            let tip = head_p + head_q * self.head_tip;
            let axis = (tip - head_p).normalize_or_zero();
            let top = tip - axis * HEAD_RADIUS_M;
            out.push((Part::Torso, Capsule { a: chest_p, b: neck_p, radius: TORSO_RADIUS_M }));
            out.push((Part::Head, Capsule { a: head_p, b: top, radius: HEAD_RADIUS_M }));
            out.push((Part::Pelvis, Capsule { a: hp, b: chest_p, radius: TORSO_RADIUS_M }));
            out.push((Part::Neck, Capsule { a: neck_p, b: head_p, radius: NECK_RADIUS_M }));
            for side in 0..2 {
                let shoulder = chest_p + chest_q * self.arm_offset[side];
                out.push((Part::Collarbone(side), Capsule { a: chest_p, b: shoulder, radius: COLLARBONE_RADIUS_M }));
            }
        }
        if which == Parts::Trunk {
            // The shoulders ride on the waist: their joints, as balls of the upper arm's radius.
            for side in 0..2 {
                let shoulder = chest_p + chest_q * self.arm_offset[side];
                out.push((Part::UpperArm(side), Capsule { a: shoulder, b: shoulder, radius: UPPER_ARM_RADIUS_M }));
            }
        }
        for side in 0..2 {
            if !matches!(which, Parts::All | Parts::TrunkAndArms) && which != Parts::Arm(side) {
                continue;
            }
            let (so, eo) = c.arm_rotations(side);
            let shoulder = chest_p + chest_q * self.arm_offset[side];
            let arm_q = chest_q * f.arm[side] * so;
            let elbow = shoulder + arm_q * self.fore_arm_offset[side];
            let hand = elbow + arm_q * f.fore_arm[side] * eo * self.hand_tip[side];
            out.push((Part::UpperArm(side), Capsule { a: shoulder, b: elbow, radius: UPPER_ARM_RADIUS_M }));
            out.push((Part::Forearm(side), Capsule { a: elbow, b: hand, radius: FOREARM_RADIUS_M }));
        }
        if matches!(which, Parts::All | Parts::Legs) {
            for side in 0..2 {
                let hip = hp + hq * self.up_leg_offset[side];
                let thigh_q = hq * f.up_leg[side];
                let knee = hip + thigh_q * self.leg_offset[side];
                let shin_q = thigh_q * f.leg[side];
                let ankle = knee + shin_q * self.foot_offset[side];
                let toe = ankle + shin_q * f.foot[side] * self.toe_tip[side];
                out.push((Part::Thigh(side), Capsule { a: hip, b: knee, radius: THIGH_RADIUS_M }));
                out.push((Part::Shin(side), Capsule { a: knee, b: ankle, radius: SHIN_RADIUS_M }));
                out.push((Part::Foot(side), Capsule { a: ankle, b: toe, radius: FOOT_RADIUS_M }));
            }
        }
    }

    /// Every bone's capsule of `pose` (in the pose's frame: world, for a world pose), into `out`.
    pub fn capsules(&self, pose: &Pose, out: &mut Vec<(Part, Capsule)>) {
        self.place(&self.frame(pose), &UpperConfig::default(), Parts::All, out);
    }
}

/// The least clearance between any of `capsules` and any of `prisms` (each with the bounding
/// box of its outline), metres (negative: that deep inside), and the part of the body where it
/// is; `None` without prisms. Pairs whose bounding boxes lie farther apart than `horizon_m`
/// are skipped (their clearance is at least that), so a clearance reported at or above
/// `horizon_m` means only "at least".
pub fn clearance<'a>(
    capsules: &[(Part, Capsule)],
    prisms: impl IntoIterator<Item = (Prism<'a>, Aabb)>,
    horizon_m: f64,
) -> Option<(f64, Part)> {
    let mut best: Option<(f64, Part)> = None;
    for (prism, b) in prisms {
        for &(part, c) in capsules {
            let reach = c.radius + horizon_m;
            let (lo, hi) = (c.a.min(c.b), c.a.max(c.b));
            if lo.x - reach > b.max.x
                || hi.x + reach < b.min.x
                || lo.y - reach > b.max.y
                || hi.y + reach < b.min.y
                || lo.z - reach > prism.z_max
                || hi.z + reach < prism.z_min
            {
                continue;
            }
            let d = prism.capsule_clearance(&c);
            if best.is_none_or(|(m, _)| d < m) {
                best = Some((d, part));
            }
        }
    }
    best
}

/// The highest point of the capsules, metres (for the duck height).
pub fn top(capsules: &[(Part, Capsule)]) -> f64 {
    capsules.iter().map(|(_, c)| c.a.z.max(c.b.z) + c.radius).fold(f64::NEG_INFINITY, f64::max)
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::*;
    use crate::anim::actor::{self, SHOULDER_HALF_WIDTH_M};
    use crate::world::{Obstacle, ObstacleShape};

    /// The prisms of `obstacles`' parts with their bounding boxes, for [`clearance`].
    fn prisms(obstacles: &[Obstacle]) -> impl Iterator<Item = (Prism<'_>, Aabb)> {
        obstacles
            .iter()
            .flat_map(|o| o.parts.iter().map(|base| (Prism { base, z_min: o.z_min, z_max: o.z_max }, base.aabb())))
    }

    fn standing() -> (Skeleton, Vec<(Part, Capsule)>) {
        let s = actor::actor();
        let body = UpperBody::of(&s).unwrap();
        let mut caps = Vec::new();
        body.capsules(&s.bind_pose(), &mut caps);
        (s, caps)
    }

    #[test]
    fn the_standing_actor_is_an_adult() {
        let (_, caps) = standing();
        assert_eq!(caps.len(), 16);
        let t = top(&caps);
        assert!((1.70..=1.85).contains(&t), "top {t}");
        let arm = caps.iter().find(|(p, _)| *p == Part::UpperArm(0)).unwrap().1;
        assert!((arm.a.y - SHOULDER_HALF_WIDTH_M).abs() < 1e-12 && (arm.a.z - 1.45).abs() < 0.03, "{arm:?}");
        let torso = caps[0].1;
        assert!(torso.a.z < torso.b.z && torso.b.z > 1.4);
    }

    #[test]
    fn clearance_sees_a_bar_overhead_and_a_shelf_at_the_chest() {
        let (_, caps) = standing();
        let bar = |z_min: f64| {
            Obstacle::build(ObstacleShape::Box { center: DVec2::ZERO, width: 0.1, height: 3.0, yaw: 0.0 }, z_min, 2.5)
                .unwrap()
        };
        let (d, part) = clearance(&caps, prisms(&[bar(2.0)]), 1.0).unwrap();
        assert_eq!(part, Part::Head);
        assert!((d - (2.0 - top(&caps))).abs() < 1e-9, "{d}");
        let (d, _) = clearance(&caps, prisms(&[bar(1.2)]), 1.0).unwrap();
        assert!(d < -0.1, "a bar at 1.2 m goes through the body: {d}");
        // A shelf beside the shoulder, at chest height, 0.1 m clear of the arm.
        let shelf = Obstacle::build(
            ObstacleShape::Box { center: DVec2::new(0.0, 0.18 + 0.05 + 0.1 + 0.5), width: 1.0, height: 1.0, yaw: 0.0 },
            1.0,
            1.6,
        )
        .unwrap();
        let (d, part) = clearance(&caps, prisms(&[shelf]), 1.0).unwrap();
        // The shoulder is nearest: the collarbone's end and the upper arm's start, at one distance.
        assert!(matches!(part, Part::Collarbone(0) | Part::UpperArm(0) | Part::Forearm(0)), "{part:?}");
        assert!((d - 0.1).abs() < 0.01, "{d}");
        assert!(clearance(&caps, prisms(&[]), 1.0).is_none());
    }

    #[test]
    fn placed_offsets_are_the_offsets_applied_to_the_pose() {
        let s = actor::actor();
        let body = UpperBody::of(&s).unwrap();
        let mut pose = s.bind_pose();
        pose.root = DVec3::new(1.0, -2.0, 0.9);
        pose.rotations[0] = DQuat::from_rotation_z(0.7);
        let c = UpperConfig { waist: [0.5, -0.8], arms: [[0.3, 0.2, -0.4, 1.1], [-0.2, 0.6, 0.3, 0.4]] };
        let (mut placed, mut applied) = (Vec::new(), Vec::new());
        body.place(&body.frame(&pose), &c, Parts::All, &mut placed);
        body.apply(&mut pose, &c);
        body.capsules(&pose, &mut applied);
        for ((pa, a), (pb, b)) in placed.iter().zip(&applied) {
            assert_eq!(pa, pb);
            assert!((a.a - b.a).length() < 1e-12 && (a.b - b.b).length() < 1e-12, "{pa:?}");
        }
        // The parts asked for, in the same order.
        body.place(&body.frame(&pose), &c, Parts::Arm(1), &mut placed);
        assert_eq!(placed.iter().map(|p| p.0).collect::<Vec<_>>(), [Part::UpperArm(1), Part::Forearm(1)]);
    }

    #[test]
    fn bending_lowers_the_head_and_twisting_narrows_the_shoulders() {
        let (s, caps) = standing();
        let body = UpperBody::of(&s).unwrap();
        let pose = s.bind_pose();
        let f = body.frame(&pose);
        let mut out = Vec::new();
        body.place(&f, &UpperConfig { waist: [75f64.to_radians(), 0.0], ..Default::default() }, Parts::All, &mut out);
        assert!(top(&out) < top(&caps) - 0.4, "bent top {}", top(&out));
        // The width above the legs (which the waist does not turn).
        let width = |caps: &[(Part, Capsule)]| {
            let ys = caps
                .iter()
                .filter(|(p, _)| !p.is_leg())
                .flat_map(|(_, c)| [c.a.y + c.radius, c.b.y + c.radius, c.a.y - c.radius, c.b.y - c.radius]);
            let (lo, hi) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), y| (l.min(y), h.max(y)));
            hi - lo
        };
        let quarter = UpperConfig { waist: [0.0, std::f64::consts::FRAC_PI_2], ..Default::default() };
        body.place(&f, &quarter, Parts::All, &mut out);
        assert!((width(&caps) - 0.46).abs() < 0.01, "{}", width(&caps));
        assert!((width(&out) - 2.0 * TORSO_RADIUS_M).abs() < 1e-9, "side-on {}", width(&out));
    }
}
