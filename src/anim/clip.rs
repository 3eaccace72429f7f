//! Animation clips (seed 000 §3.2): poses sampled at a fixed frame time, played at any time by
//! interpolation (root linearly, joints by slerp), and mirrored left–right.

use glam::{DQuat, DVec3};

use super::skeleton::{Pose, Skeleton, heading};

/// A clip: one pose per frame, all frames the same time apart.
#[derive(Debug, Clone, PartialEq)]
pub struct Clip {
    /// Name (file stem for imported clips).
    pub name: String,
    /// Seconds between frames (> 0).
    pub frame_time: f64,
    /// The frames (at least one).
    pub frames: Vec<Pose>,
}

impl Clip {
    /// Duration from the first frame to the last, seconds.
    pub fn duration(&self) -> f64 {
        (self.frames.len().saturating_sub(1)) as f64 * self.frame_time
    }

    /// The pose at time `t` seconds (clamped to the clip), into `out`.
    pub fn sample_into(&self, t: f64, out: &mut Pose) {
        let f = (t / self.frame_time).clamp(0.0, (self.frames.len() - 1) as f64);
        let i = (f.floor() as usize).min(self.frames.len() - 1);
        let j = (i + 1).min(self.frames.len() - 1);
        out.blend_from(&self.frames[i], &self.frames[j], f - i as f64);
    }

    /// The pose at time `t` seconds (clamped to the clip).
    pub fn sample(&self, t: f64) -> Pose {
        let mut p = self.frames[0].clone();
        self.sample_into(t, &mut p);
        p
    }

    /// The pose at fractional frame `f` (clamped).
    pub fn sample_frame(&self, f: f64) -> Pose {
        self.sample(f * self.frame_time)
    }

    /// The clip mirrored across the sagittal (XZ) plane: every position's Y negated, every
    /// rotation reflected, and the rotations of paired joints swapped (`pairs[i]` is the joint
    /// mirroring joint `i`, itself for joints on the middle line).
    pub fn mirrored(&self, pairs: &[usize], name: String) -> Clip {
        let frames = self.frames.iter().map(|p| p.mirrored(pairs)).collect();
        Clip { name, frame_time: self.frame_time, frames }
    }
}

/// For each joint, the joint that mirrors it, paired by name: `Left…`/`Right…`, `left_…`/
/// `right_…` and a leading `L`/`R` before a capital (`LHipJoint`/`RHipJoint`). Joints without a
/// partner mirror themselves.
pub fn mirror_pairs(skeleton: &Skeleton) -> Vec<usize> {
    let swap = |n: &str| -> Option<String> {
        for (a, b) in [("Left", "Right"), ("Right", "Left"), ("left", "right"), ("right", "left")] {
            if n.contains(a) {
                return Some(n.replacen(a, b, 1));
            }
        }
        let mut c = n.chars();
        match (c.next(), c.next()) {
            (Some('L'), Some(s)) if s.is_uppercase() => Some(format!("R{}", &n[1..])),
            (Some('R'), Some(s)) if s.is_uppercase() => Some(format!("L{}", &n[1..])),
            _ => None,
        }
    };
    (0..skeleton.len()).map(|i| swap(&skeleton.joints()[i].name).and_then(|n| skeleton.find(&n)).unwrap_or(i)).collect()
}

/// Where a pose stands on the ground: the root's horizontal position and heading.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Ground {
    /// Horizontal root position, metres.
    pub x: f64,
    /// Horizontal root position, metres.
    pub y: f64,
    /// Heading, radians.
    pub yaw: f64,
}

impl Ground {
    /// The ground reference of `pose` whose root's forward axis is `forward` in the bind pose.
    pub fn of(pose: &Pose, forward_offset: f64) -> Ground {
        Ground { x: pose.root.x, y: pose.root.y, yaw: heading(pose.rotations[0]) - forward_offset }
    }

    /// This reference composed with `local` (a reference expressed in this one's frame).
    pub fn then(self, local: Ground) -> Ground {
        let (s, c) = self.yaw.sin_cos();
        Ground {
            x: self.x + c * local.x - s * local.y,
            y: self.y + s * local.x + c * local.y,
            yaw: self.yaw + local.yaw,
        }
    }

    /// `other` expressed in this reference's frame.
    pub fn to_local(self, other: Ground) -> Ground {
        let (s, c) = self.yaw.sin_cos();
        let (dx, dy) = (other.x - self.x, other.y - self.y);
        Ground { x: c * dx + s * dy, y: -s * dx + c * dy, yaw: crate::geom::wrap_angle(other.yaw - self.yaw) }
    }

    /// The rotation about Z by this heading.
    pub fn rotation(self) -> DQuat {
        DQuat::from_rotation_z(self.yaw)
    }

    /// Moves `pose` from this reference's frame to the world (or back, with `inverse`).
    pub fn transform_pose(self, pose: &mut Pose, inverse: bool) {
        let r = self.rotation();
        if inverse {
            let d = pose.root - DVec3::new(self.x, self.y, 0.0);
            pose.root = r.inverse() * d;
            pose.rotations[0] = r.inverse() * pose.rotations[0];
        } else {
            pose.root = r * pose.root + DVec3::new(self.x, self.y, 0.0);
            pose.rotations[0] = r * pose.rotations[0];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::anim::skeleton::Joint;

    fn skeleton() -> Skeleton {
        let j = |n: &str, p, y: f64| Joint {
            name: n.into(),
            parent: p,
            offset: DVec3::new(0.0, y, 0.0),
            channels: vec![],
            end_site: None,
        };
        Skeleton::new(vec![
            j("Hips", None, 0.0),
            j("LeftUpLeg", Some(0), 0.1),
            j("RightUpLeg", Some(0), -0.1),
            j("LHipJoint", Some(0), 0.0),
            j("RHipJoint", Some(0), 0.0),
        ])
        .unwrap()
    }

    #[test]
    fn pairs_by_name() {
        assert_eq!(mirror_pairs(&skeleton()), vec![0, 2, 1, 4, 3]);
    }

    #[test]
    fn mirroring_twice_is_identity_and_reflects_positions() {
        let s = skeleton();
        let pairs = mirror_pairs(&s);
        let mut pose = s.bind_pose();
        pose.root = DVec3::new(1.0, 2.0, 0.9);
        pose.rotations[0] = DQuat::from_rotation_z(0.4);
        pose.rotations[1] = DQuat::from_rotation_x(0.3) * DQuat::from_rotation_y(0.2);
        let clip = Clip { name: "c".into(), frame_time: 0.1, frames: vec![pose.clone()] };
        let m = clip.mirrored(&pairs, "m".into());
        assert_eq!(m.frames[0].root, DVec3::new(1.0, -2.0, 0.9));
        assert!((heading(m.frames[0].rotations[0]) + 0.4).abs() < 1e-12);
        // The left leg's rotation went to the right leg, reflected; positions of the mirrored
        // skeleton are the reflected positions.
        let p = s.positions(&pose);
        let q = s.positions(&m.frames[0]);
        assert!((q[2] - DVec3::new(p[1].x, -p[1].y, p[1].z)).length() < 1e-12);
        let back = m.mirrored(&pairs, "b".into());
        assert_eq!(back.frames[0].root, pose.root);
        for (a, b) in back.frames[0].rotations.iter().zip(&pose.rotations) {
            assert!((*a - *b).length() < 1e-15);
        }
    }

    #[test]
    fn sampling_interpolates_between_frames() {
        let s = skeleton();
        let mut a = s.bind_pose();
        let mut b = s.bind_pose();
        a.root = DVec3::ZERO;
        b.root = DVec3::new(1.0, 0.0, 0.0);
        b.rotations[1] = DQuat::from_rotation_x(1.0);
        let clip = Clip { name: "c".into(), frame_time: 0.5, frames: vec![a, b] };
        let p = clip.sample(0.25);
        assert!((p.root.x - 0.5).abs() < 1e-12);
        assert!((crate::anim::skeleton::angle_between(p.rotations[1], DQuat::IDENTITY) - 0.5).abs() < 1e-12);
        assert_eq!(clip.sample(9.0).root.x, 1.0);
        assert_eq!(clip.duration(), 0.5);
    }

    #[test]
    fn ground_frames_round_trip() {
        let g = Ground { x: 1.0, y: -2.0, yaw: 0.7 };
        let o = Ground { x: 3.0, y: 0.5, yaw: -1.1 };
        let back = g.then(g.to_local(o));
        assert!((back.x - o.x).abs() < 1e-12 && (back.y - o.y).abs() < 1e-12 && (back.yaw - o.yaw).abs() < 1e-12);
    }
}
