//! The upper body's collision geometry (seed 002 §5; DESIGN.md §5): capsules for the torso, the
//! head, the upper arms and the forearms of the built-in actor, posed by forward kinematics,
//! and their clearance from the obstacles' prisms ([`crate::geom::Prism`]).
//!
//! The capsules run between the actor's joints: the torso from the waist joint to the base of
//! the neck, the head from there to the top of the head, each upper arm from the shoulder to
//! the elbow and each forearm from the elbow to the middle of the hand. Their radii
//! ([`TORSO_RADIUS_M`] …) are an adult's; with the shoulders 0.36 m apart the arms' capsules
//! make the body 0.46 m wide at the shoulders.

use super::actor::{CHEST, HEAD, LEFT_ARM, LEFT_FORE_ARM, NECK, RIGHT_ARM, RIGHT_FORE_ARM};
use super::skeleton::{Pose, Skeleton};
use crate::geom::{Capsule, Prism};
use crate::world::Obstacle;

/// Radius of the torso's capsule, metres.
pub const TORSO_RADIUS_M: f64 = 0.13;
/// Radius of the head's capsule, metres.
pub const HEAD_RADIUS_M: f64 = 0.09;
/// Radius of an upper arm's capsule, metres.
pub const UPPER_ARM_RADIUS_M: f64 = 0.05;
/// Radius of a forearm's capsule, metres.
pub const FOREARM_RADIUS_M: f64 = 0.045;

/// A part of the upper body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// Waist to the base of the neck.
    Torso,
    /// Base of the neck to the top of the head.
    Head,
    /// Shoulder to elbow; 0 left, 1 right.
    UpperArm(usize),
    /// Elbow to hand; 0 left, 1 right.
    Forearm(usize),
}

/// The joints the capsules hang on, found once per skeleton.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UpperBody {
    chest: usize,
    neck: usize,
    head: usize,
    arm: [usize; 2],
    fore_arm: [usize; 2],
}

impl UpperBody {
    /// The upper body of `skeleton`, when it has the actor's named joints (`None` for an
    /// imported rig).
    pub fn of(skeleton: &Skeleton) -> Option<UpperBody> {
        let f = |n: &str| skeleton.find(n);
        Some(UpperBody {
            chest: f(CHEST)?,
            neck: f(NECK)?,
            head: f(HEAD)?,
            arm: [f(LEFT_ARM)?, f(RIGHT_ARM)?],
            fore_arm: [f(LEFT_FORE_ARM)?, f(RIGHT_FORE_ARM)?],
        })
    }

    /// The six capsules of `pose` (in the pose's frame: world, for a world pose), into `out`.
    pub fn capsules(&self, skeleton: &Skeleton, pose: &Pose, out: &mut Vec<(Part, Capsule)>) {
        let mut g = Vec::with_capacity(skeleton.len());
        skeleton.globals(pose, &mut g);
        let at = |i: usize| g[i].0;
        out.clear();
        out.push((Part::Torso, Capsule { a: at(self.chest), b: at(self.neck), radius: TORSO_RADIUS_M }));
        out.push((Part::Head, Capsule { a: at(self.head), b: skeleton.tip(&g, self.head), radius: HEAD_RADIUS_M }));
        for side in 0..2 {
            let (shoulder, elbow) = (at(self.arm[side]), at(self.fore_arm[side]));
            out.push((Part::UpperArm(side), Capsule { a: shoulder, b: elbow, radius: UPPER_ARM_RADIUS_M }));
            let hand = skeleton.tip(&g, self.fore_arm[side]);
            out.push((Part::Forearm(side), Capsule { a: elbow, b: hand, radius: FOREARM_RADIUS_M }));
        }
    }
}

/// The least clearance between any of `capsules` and any part of `obstacles`, metres
/// (negative: that deep inside), and the part of the body where it is; `None` without
/// obstacles. Parts farther apart than `horizon_m` in the plan view are skipped (their
/// clearance is at least that).
pub fn clearance(capsules: &[(Part, Capsule)], obstacles: &[Obstacle], horizon_m: f64) -> Option<(f64, Part)> {
    let mut best: Option<(f64, Part)> = None;
    for o in obstacles {
        for base in &o.parts {
            let prism = Prism { base, z_min: o.z_min, z_max: o.z_max };
            let b = base.aabb();
            for &(part, c) in capsules {
                let reach = c.radius + horizon_m;
                let (lo, hi) = (c.a.min(c.b).truncate(), c.a.max(c.b).truncate());
                if lo.x - reach > b.max.x || hi.x + reach < b.min.x || lo.y - reach > b.max.y || hi.y + reach < b.min.y
                {
                    continue;
                }
                let d = prism.capsule_clearance(&c);
                if best.is_none_or(|(m, _)| d < m) {
                    best = Some((d, part));
                }
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
    use crate::world::ObstacleShape;

    fn standing() -> (Skeleton, Vec<(Part, Capsule)>) {
        let s = actor::actor();
        let body = UpperBody::of(&s).unwrap();
        let mut caps = Vec::new();
        body.capsules(&s, &s.bind_pose(), &mut caps);
        (s, caps)
    }

    #[test]
    fn the_standing_actor_is_an_adult() {
        let (_, caps) = standing();
        assert_eq!(caps.len(), 6);
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
        let (d, part) = clearance(&caps, &[bar(2.0)], 1.0).unwrap();
        assert_eq!(part, Part::Head);
        assert!((d - (2.0 - top(&caps))).abs() < 1e-9, "{d}");
        let (d, _) = clearance(&caps, &[bar(1.2)], 1.0).unwrap();
        assert!(d < -0.1, "a bar at 1.2 m goes through the body: {d}");
        // A shelf beside the shoulder, at chest height, 0.1 m clear of the arm.
        let shelf = Obstacle::build(
            ObstacleShape::Box { center: DVec2::new(0.0, 0.18 + 0.05 + 0.1 + 0.5), width: 1.0, height: 1.0, yaw: 0.0 },
            1.0,
            1.6,
        )
        .unwrap();
        let (d, part) = clearance(&caps, &[shelf], 1.0).unwrap();
        assert!(matches!(part, Part::UpperArm(0) | Part::Forearm(0)), "{part:?}");
        assert!((d - 0.1).abs() < 0.01, "{d}");
        assert!(clearance(&caps, &[], 1.0).is_none());
    }
}
