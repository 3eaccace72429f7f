//! Skeletons and poses (seed 000 §3.2.1, DESIGN.md §3): a joint hierarchy whose root carries
//! translation and rotation and whose other joints carry rotation only, as unit quaternions
//! relative to the bind pose; no scale.
//!
//! Frame: metres, Z up, X forward, Y to the left — the simulator's ground plane is XY. BVH
//! files (Y up) are converted on import and export (`bvh.rs`).

use glam::{DQuat, DVec3};

/// Degrees of freedom a joint exposes in files (BVH channels), in this crate's Z-up frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Channel {
    /// Translation along X.
    XPosition,
    /// Translation along Y.
    YPosition,
    /// Translation along Z.
    ZPosition,
    /// Rotation about X.
    XRotation,
    /// Rotation about Y.
    YRotation,
    /// Rotation about Z.
    ZRotation,
}

impl Channel {
    /// True for the three translation channels.
    pub fn is_position(self) -> bool {
        matches!(self, Channel::XPosition | Channel::YPosition | Channel::ZPosition)
    }
}

/// One joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// Name, unique in its skeleton.
    pub name: String,
    /// Index of the parent joint; `None` for the root (joint 0 only).
    pub parent: Option<usize>,
    /// Position relative to the parent in the bind pose, metres.
    pub offset: DVec3,
    /// Channels this joint exposes, in file order (rotations apply in this order, intrinsic).
    pub channels: Vec<Channel>,
    /// Tip of a leaf joint (BVH `End Site`), relative to the joint.
    pub end_site: Option<DVec3>,
}

/// A joint hierarchy. Invariant (checked by [`Skeleton::new`]): joint 0 is the only root and
/// every parent comes before its children.
#[derive(Debug, Clone, PartialEq)]
pub struct Skeleton {
    joints: Vec<Joint>,
}

/// Why a joint list is not a skeleton.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SkeletonError {
    /// No joints at all.
    #[error("a skeleton needs at least one joint")]
    Empty,
    /// A joint other than the first has no parent, or the first has one.
    #[error("joint '{0}' must be the only root")]
    Root(String),
    /// A parent index does not come before its child.
    #[error("joint '{0}' names a parent that does not come before it")]
    ParentOrder(String),
    /// Two joints share a name.
    #[error("two joints are named '{0}'")]
    DuplicateName(String),
    /// An offset is not finite.
    #[error("joint '{0}' has a non-finite offset")]
    NonFinite(String),
}

impl Skeleton {
    /// Checks the invariants and builds the skeleton.
    pub fn new(joints: Vec<Joint>) -> Result<Skeleton, SkeletonError> {
        if joints.is_empty() {
            return Err(SkeletonError::Empty);
        }
        for (i, j) in joints.iter().enumerate() {
            match (i, j.parent) {
                (0, None) => {}
                (0, Some(_)) | (_, None) => return Err(SkeletonError::Root(j.name.clone())),
                (_, Some(p)) if p >= i => return Err(SkeletonError::ParentOrder(j.name.clone())),
                _ => {}
            }
            if !j.offset.is_finite() || j.end_site.is_some_and(|e| !e.is_finite()) {
                return Err(SkeletonError::NonFinite(j.name.clone()));
            }
            if joints[..i].iter().any(|o| o.name == j.name) {
                return Err(SkeletonError::DuplicateName(j.name.clone()));
            }
        }
        Ok(Skeleton { joints })
    }

    /// The joints, parents first.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// Number of joints.
    pub fn len(&self) -> usize {
        self.joints.len()
    }

    /// Always false: a skeleton has a root.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Index of the joint called `name`.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// Depth of each joint in the hierarchy (root 0).
    pub fn depths(&self) -> Vec<usize> {
        let mut d = vec![0; self.joints.len()];
        for (i, j) in self.joints.iter().enumerate() {
            if let Some(p) = j.parent {
                d[i] = d[p] + 1;
            }
        }
        d
    }

    /// Length of the bone each joint swings: its longest child offset or end site, metres.
    pub fn bone_lengths(&self) -> Vec<f64> {
        let mut l: Vec<f64> = self.joints.iter().map(|j| j.end_site.map_or(0.0, |e| e.length())).collect();
        for j in &self.joints {
            if let Some(p) = j.parent {
                l[p] = l[p].max(j.offset.length());
            }
        }
        l
    }

    /// Reach of each joint: the largest bind-pose distance from it to a descendant joint or end
    /// site, metres.
    pub fn reaches(&self) -> Vec<f64> {
        let p = self.positions(&self.bind_pose());
        let mut globals = Vec::with_capacity(self.len());
        self.globals(&self.bind_pose(), &mut globals);
        let mut r = vec![0.0f64; self.len()];
        for i in (0..self.len()).rev() {
            let tip = self.tip(&globals, i);
            r[i] = r[i].max(tip.distance(p[i]));
            // Walk up: every ancestor reaches this joint's tip too.
            let mut a = self.joints[i].parent;
            while let Some(k) = a {
                r[k] = r[k].max(tip.distance(p[k])).max(p[i].distance(p[k]));
                a = self.joints[k].parent;
            }
        }
        r
    }

    /// The bind pose: root at `offset` of joint 0, every rotation identity.
    pub fn bind_pose(&self) -> Pose {
        Pose { root: self.joints[0].offset, rotations: vec![DQuat::IDENTITY; self.joints.len()] }
    }

    /// Global position and rotation of every joint in `pose` (forward kinematics), into `out`.
    pub fn globals(&self, pose: &Pose, out: &mut Vec<(DVec3, DQuat)>) {
        out.clear();
        for (i, j) in self.joints.iter().enumerate() {
            let g = match j.parent {
                None => (pose.root, pose.rotations[0]),
                Some(p) => {
                    let (pp, pq) = out[p];
                    (pp + pq * j.offset, pq * pose.rotations[i])
                }
            };
            out.push(g);
        }
    }

    /// Global position and rotation of joint `i` in `pose`: what [`Skeleton::globals`] gives for
    /// it, worked out along its chain of parents alone.
    pub fn global_of(&self, pose: &Pose, i: usize) -> (DVec3, DQuat) {
        let mut chain = [0usize; 64];
        let mut depth = 0;
        let mut at = Some(i);
        while let Some(j) = at {
            if depth == chain.len() {
                let mut all = Vec::with_capacity(self.len());
                self.globals(pose, &mut all);
                return all[i];
            }
            chain[depth] = j;
            depth += 1;
            at = self.joints[j].parent;
        }
        let mut g = (pose.root, pose.rotations[0]);
        for &j in chain[..depth].iter().rev().skip(1) {
            let (pp, pq) = g;
            g = (pp + pq * self.joints[j].offset, pq * pose.rotations[j]);
        }
        g
    }

    /// Brings `out`, the [`Skeleton::globals`] of a pose that differs from `pose` only in the
    /// rotations of joint `joint` and the joints below it, up to date with `pose`: only those
    /// joints are worked out again (parents come before their children).
    pub fn globals_below(&self, pose: &Pose, joint: usize, out: &mut [(DVec3, DQuat)]) {
        let (mut small, mut large) = ([false; 256], Vec::new());
        let below: &mut [bool] = if self.len() <= small.len() {
            &mut small
        } else {
            large.resize(self.len(), false);
            &mut large
        };
        for i in joint..self.len() {
            let j = &self.joints[i];
            below[i] = i == joint || j.parent.is_some_and(|p| p >= joint && below[p]);
            if below[i] {
                out[i] = match j.parent {
                    None => (pose.root, pose.rotations[0]),
                    Some(p) => {
                        let (pp, pq) = out[p];
                        (pp + pq * j.offset, pq * pose.rotations[i])
                    }
                };
            }
        }
    }

    /// Global position of every joint in `pose`.
    pub fn positions(&self, pose: &Pose) -> Vec<DVec3> {
        let mut g = Vec::with_capacity(self.len());
        self.globals(pose, &mut g);
        g.into_iter().map(|(p, _)| p).collect()
    }

    /// Global position of the end site of joint `i` if it has one, else of the joint.
    pub fn tip(&self, globals: &[(DVec3, DQuat)], i: usize) -> DVec3 {
        let (p, q) = globals[i];
        self.joints[i].end_site.map_or(p, |e| p + q * e)
    }
}

/// A pose: root position and every joint's rotation relative to the bind pose (joint 0's is the
/// root's global rotation).
#[derive(Debug, Clone, PartialEq)]
pub struct Pose {
    /// Root position, metres.
    pub root: DVec3,
    /// One unit quaternion per joint.
    pub rotations: Vec<DQuat>,
}

impl Pose {
    /// The pose mirrored across the XZ plane: root Y negated, every rotation reflected, and the
    /// rotations of paired joints swapped (`pairs[i]` mirrors joint `i`; see
    /// [`mirror_pairs`](super::clip::mirror_pairs)).
    pub fn mirrored(&self, pairs: &[usize]) -> Pose {
        Pose {
            root: DVec3::new(self.root.x, -self.root.y, self.root.z),
            rotations: pairs.iter().map(|&m| mirror_rotation(self.rotations[m])).collect(),
        }
    }

    /// Interpolates: root linearly, rotations by shortest-arc slerp.
    pub fn lerp(&self, other: &Pose, t: f64) -> Pose {
        let mut out = self.clone();
        out.blend_from(self, other, t);
        out
    }

    /// Sets `self` to the interpolation of `a` and `b` at `t` without allocating.
    pub fn blend_from(&mut self, a: &Pose, b: &Pose, t: f64) {
        self.root = a.root.lerp(b.root, t);
        self.rotations.clear();
        self.rotations.extend(a.rotations.iter().zip(&b.rotations).map(|(&qa, &qb)| slerp(qa, qb, t)));
    }

    /// Sets `self` to the interpolation of `a` and itself at `t` (what
    /// [`blend_from`](Self::blend_from)`(a, self, t)` gives), in place.
    pub fn blend_after(&mut self, a: &Pose, t: f64) {
        self.root = a.root.lerp(self.root, t);
        for (q, &qa) in self.rotations.iter_mut().zip(&a.rotations) {
            *q = slerp(qa, *q, t);
        }
    }
}

/// A rotation reflected across the XZ plane.
pub fn mirror_rotation(q: DQuat) -> DQuat {
    DQuat::from_xyzw(-q.x, q.y, -q.z, q.w)
}

/// Shortest-arc spherical interpolation of unit quaternions.
pub fn slerp(a: DQuat, b: DQuat, t: f64) -> DQuat {
    let b = if a.dot(b) < 0.0 { -b } else { b };
    a.slerp(b, t).normalize()
}

/// The arc of [`slerp`] from one rotation to another with what does not depend on the
/// fraction worked out once: [`SlerpArc::at`] gives exactly (bit for bit) what `slerp(a, b, t)`
/// gives, with two sines instead of an arc cosine and three sines. Clip frames are sampled
/// between the same two neighbours again and again, so the database keeps one per joint and
/// frame pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlerpArc {
    from: DQuat,
    /// The end on the near side of `from` (negated when the dot product is negative).
    to: DQuat,
    /// The angle `acos(⟨from, to⟩)`; `None` when the two are too close for it (interpolated
    /// linearly).
    theta: Option<(f64, f64)>,
}

impl SlerpArc {
    /// The arc from `a` to `b`.
    pub fn new(a: DQuat, b: DQuat) -> SlerpArc {
        let to = if a.dot(b) < 0.0 { -b } else { b };
        // The same decisions as `DQuat::slerp` on the same inputs.
        let (to, dot) = {
            let dot = a.dot(to);
            if dot < 0.0 { (-to, -dot) } else { (to, dot) }
        };
        let theta = (!(dot > 1.0 - f64::EPSILON)).then(|| {
            let theta = dot.clamp(-1.0, 1.0).acos();
            (theta, 1.0 / theta.sin())
        });
        SlerpArc { from: a, to, theta }
    }

    /// The rotation at fraction `t` along the arc, equal to `slerp(a, b, t)`.
    pub fn at(&self, t: f64) -> DQuat {
        let q = match self.theta {
            None => (self.from * (1.0 - t) + self.to * t).normalize(),
            Some((theta, inv_sin)) => {
                let (s1, s2) = ((theta * (1.0 - t)).sin(), (theta * t).sin());
                ((self.from * s1) + (self.to * s2)) * inv_sin
            }
        };
        q.normalize()
    }
}

/// The angle between two rotations, `2·acos(|⟨a,b⟩|)`, radians in `[0, π]`.
pub fn angle_between(a: DQuat, b: DQuat) -> f64 {
    2.0 * a.dot(b).abs().min(1.0).acos()
}

/// Heading (yaw about Z) of a rotation: the angle of its forward (+X) axis projected on the
/// ground; 0 when the forward axis points straight up or down.
pub fn heading(q: DQuat) -> f64 {
    let f = q * DVec3::X;
    if f.x == 0.0 && f.y == 0.0 { 0.0 } else { f.y.atan2(f.x) }
}

/// The angle of the twist of `q` about the unit `axis` (swing–twist decomposition), in [-π, π].
pub fn twist(q: DQuat, axis: DVec3) -> f64 {
    let v = DVec3::new(q.x, q.y, q.z).dot(axis);
    let (v, w) = if q.w.is_sign_negative() { (-v, -q.w) } else { (v, q.w) };
    2.0 * v.atan2(w)
}

/// Whether [`twist`]`(q, axis)` is below zero, told by the sign of the rotation's part along
/// the axis where that decides it (the arc tangent then is neither zero nor rounded to it),
/// without working the angle out.
pub fn twist_is_negative(q: DQuat, axis: DVec3) -> bool {
    let v = DVec3::new(q.x, q.y, q.z).dot(axis);
    let (v, w) = if q.w.is_sign_negative() { (-v, -q.w) } else { (v, q.w) };
    if (0.0..=2.0).contains(&w) && v.abs() >= 1e-290 { v < 0.0 } else { twist(q, axis) < 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sign_of_a_twist_is_told_as_the_angle_tells_it() {
        let mut rng = crate::rng::stream(9, 0, 0);
        let mut unit = || crate::rng::uniform(&mut rng, -1.0, 1.0);
        let axes = [DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(0.6, -0.8, 0.0)];
        for k in 0..20_000 {
            let q = match k % 5 {
                0 => DQuat::from_xyzw(unit(), unit(), unit(), unit()).normalize(),
                1 => DQuat::from_rotation_y(4.0 * unit()),
                2 => DQuat::from_xyzw(unit() * 1e-300, unit() * 1e-300, unit() * 1e-300, unit()),
                3 => DQuat::from_xyzw(unit(), unit(), unit(), 0.0 * unit()),
                _ => DQuat::from_xyzw(unit() * 3.0, unit() * 3.0, unit() * 3.0, unit() * 3.0),
            };
            for axis in axes {
                assert_eq!(twist_is_negative(q, axis), twist(q, axis) < 0.0, "{q:?} {axis}");
            }
        }
        for q in [DQuat::from_xyzw(0.0, -0.0, 0.0, 1.0), DQuat::from_xyzw(0.0, f64::NAN, 0.0, 1.0), -DQuat::IDENTITY] {
            assert_eq!(twist_is_negative(q, DVec3::Y), twist(q, DVec3::Y) < 0.0, "{q:?}");
        }
    }

    #[test]
    fn an_arc_interpolates_exactly_as_slerp() {
        let mut rng = crate::rng::stream(7, 0, 0);
        let mut unit = || crate::rng::uniform(&mut rng, -1.0, 1.0);
        for k in 0..2000 {
            let a = DQuat::from_xyzw(unit(), unit(), unit(), unit()).normalize();
            // Near, far, opposite and identical ends.
            let b = match k % 4 {
                0 => DQuat::from_xyzw(unit(), unit(), unit(), unit()).normalize(),
                1 => (a * DQuat::from_rotation_z(1e-3 * unit())).normalize(),
                2 => -(a * DQuat::from_rotation_x(0.2 * unit())).normalize(),
                _ => a,
            };
            let arc = SlerpArc::new(a, b);
            for t in [0.0, 1.0, 0.5, 0.25 * (unit() + 1.0), 1.0 / 3.0] {
                let (x, y) = (arc.at(t), slerp(a, b, t));
                assert_eq!(x.to_array().map(f64::to_bits), y.to_array().map(f64::to_bits), "{a} {b} {t}");
            }
        }
    }

    fn chain() -> Skeleton {
        Skeleton::new(vec![
            Joint { name: "root".into(), parent: None, offset: DVec3::ZERO, channels: vec![], end_site: None },
            Joint {
                name: "a".into(),
                parent: Some(0),
                offset: DVec3::new(0.0, 0.0, 1.0),
                channels: vec![],
                end_site: Some(DVec3::X),
            },
        ])
        .unwrap()
    }

    #[test]
    fn forward_kinematics_composes_parent_rotations() {
        let s = chain();
        let mut pose = s.bind_pose();
        pose.rotations[0] = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2);
        let mut g = Vec::new();
        s.globals(&pose, &mut g);
        // Z offset rotated +90° about Y points along +X.
        assert!((g[1].0 - DVec3::X).length() < 1e-12);
        // The end site (+X) rotated likewise points along -Z.
        assert!((s.tip(&g, 1) - DVec3::new(1.0, 0.0, -1.0)).length() < 1e-12);
        assert_eq!(s.bone_lengths(), vec![1.0, 1.0]);
        assert_eq!(s.depths(), vec![0, 1]);
    }

    #[test]
    fn invariants_are_checked() {
        let j = |n: &str, p| Joint { name: n.into(), parent: p, offset: DVec3::ZERO, channels: vec![], end_site: None };
        assert_eq!(Skeleton::new(vec![]), Err(SkeletonError::Empty));
        assert!(matches!(Skeleton::new(vec![j("r", None), j("r", Some(0))]), Err(SkeletonError::DuplicateName(_))));
        assert!(matches!(Skeleton::new(vec![j("r", None), j("a", Some(1))]), Err(SkeletonError::ParentOrder(_))));
        assert!(matches!(Skeleton::new(vec![j("r", None), j("a", None)]), Err(SkeletonError::Root(_))));
    }

    #[test]
    fn angles_and_headings() {
        let a = DQuat::from_rotation_z(0.3);
        let b = DQuat::from_rotation_z(-0.2);
        assert!((angle_between(a, b) - 0.5).abs() < 1e-12);
        assert!((angle_between(a, -a)).abs() < 1e-6);
        assert!((heading(a) - 0.3).abs() < 1e-12);
        let m = slerp(a, -b, 0.5);
        assert!((heading(m) - 0.05).abs() < 1e-12);
    }
}
