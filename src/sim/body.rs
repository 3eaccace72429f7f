//! The agent's body for navigation (seed 000 §3.1): a kinematic disc with turn-rate and
//! acceleration limits, behind the [`Body`] trait so the animation controller (seed 000 §3.2)
//! can drive the same loop with animation root motion.
//!
//! Bodies see the world through a [`Space`]: the clearance of a point, and of the segment a
//! disc would sweep — the obstacles and the other agents alike.
//!
//! Invariant: a body never moves into an obstacle. A step of the disc whose end position is not
//! free slides: the same step turned up to 60° to either side (its speed keeps only the
//! component along the heading); failing that it is shortened (halved up to four times) and, if
//! still blocked, not taken: the body only turns and its speed drops to zero.

use glam::DVec2;

use crate::world::Pose;

/// What the planner asks of the body for one step.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Command {
    /// Heading change rate, radians per second, positive to the left.
    pub turn_rate: f64,
    /// Forward speed, metres per second.
    pub speed: f64,
    /// The direction the planner steers toward, when it has one (absolute, radians): the turn
    /// brings the heading there and no further. Bodies that act in larger steps than the
    /// planner's (an animated character) use it not to overshoot.
    pub toward: Option<f64>,
}

/// What happened during one step.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepOutcome {
    /// Distance travelled, metres.
    pub moved_m: f64,
    /// True when the step had to be shortened or refused because it would hit something.
    pub blocked: bool,
    /// True when the body was commanded to move but stood still because what it wanted to do
    /// next was blocked (an animated character's look-ahead refusing its candidates).
    pub held: bool,
}

impl StepOutcome {
    /// A stalled step: blocked, or held in place against the command.
    pub fn stalled(&self) -> bool {
        self.blocked || self.held
    }
}

/// The body's extent in the plane (the side-on capsule: [`super::side_on`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Footprint {
    /// The walking disc.
    Disc {
        /// Centre.
        centre: DVec2,
        /// Radius, metres.
        radius: f64,
    },
    /// Side-on: a capsule along the shoulders.
    Capsule {
        /// One end of its axis.
        a: DVec2,
        /// The other end.
        b: DVec2,
        /// Radius, metres.
        radius: f64,
    },
}

/// Half the length of the side-on capsule's axis, along the shoulders, metres.
pub const SIDE_ON_HALF_AXIS_M: f64 = 0.31;
/// Radius of the side-on capsule, metres: half the body's depth, chest to back and heel to toe.
pub const SIDE_ON_RADIUS_M: f64 = 0.15;
/// How far ahead of the root the side-on capsule's axis lies, metres (the feet reach forward).
pub const SIDE_ON_FORWARD_M: f64 = 0.095;

impl Footprint {
    /// The side-on capsule of a body whose ground reference is `g`.
    pub fn side_on(g: crate::anim::Ground) -> Footprint {
        let f = DVec2::from_angle(g.yaw);
        let c = DVec2::new(g.x, g.y) + f * SIDE_ON_FORWARD_M;
        let l = f.perp() * SIDE_ON_HALF_AXIS_M;
        Footprint::Capsule { a: c - l, b: c + l, radius: SIDE_ON_RADIUS_M }
    }

    /// Room between it and the nearest thing in `space` (negative: overlapping, down to its
    /// radius), looked for up to `max` metres.
    pub fn room(&self, space: &mut dyn Space, max: f64) -> f64 {
        match *self {
            Footprint::Disc { centre, radius } => space.clearance(centre, max + radius) - radius,
            Footprint::Capsule { a, b, radius } => space.segment_clearance(a, b, max + radius) - radius,
        }
    }
}

/// What a body can see of its surroundings: obstacles and other agents, as clearances.
pub trait Space {
    /// Distance from `p` to the nearest obstacle or other agent (0 inside), capped at `max`,
    /// metres.
    fn clearance(&mut self, p: DVec2, max: f64) -> f64;
    /// Distance from the segment `a`–`b` to the nearest obstacle or other agent (0 when it
    /// touches one), capped at `max`, metres.
    fn segment_clearance(&mut self, a: DVec2, b: DVec2, max: f64) -> f64;
    /// True when something in it can move (other agents), so that a path checked clear may not
    /// stay clear.
    fn changes(&self) -> bool;
}

/// Open ground: nothing anywhere.
#[derive(Debug, Clone, Copy, Default)]
pub struct OpenSpace;

impl Space for OpenSpace {
    fn clearance(&mut self, _: DVec2, max: f64) -> f64 {
        max
    }
    fn segment_clearance(&mut self, _: DVec2, _: DVec2, max: f64) -> f64 {
        max
    }
    fn changes(&self) -> bool {
        false
    }
}

/// True when a disc of `radius` at `p` overlaps nothing in `space`.
pub fn is_free(space: &mut dyn Space, p: DVec2, radius: f64) -> bool {
    space.clearance(p, radius + 1e-9) >= radius
}

/// Something the navigation loop can drive.
pub trait Body {
    /// Current pose.
    fn pose(&self) -> Pose;
    /// Current forward speed, metres per second.
    fn speed(&self) -> f64;
    /// Radius of the disc the body occupies, metres.
    fn radius(&self) -> f64;
    /// The largest turn rate the body can follow at `speed`, radians per second.
    fn turn_limit(&self, speed: f64) -> f64;
    /// Width of the narrowest gap the body passes through, metres: its disc's unless it keeps
    /// a margin beyond it.
    fn passage_m(&self) -> f64 {
        2.0 * self.radius()
    }
    /// Width of the narrowest gap the body passes in its narrowest stance (a character side-on,
    /// [`super::side_on`]), metres; `None` when it has no other stance than its walking one.
    fn narrowest_passage_m(&self) -> Option<f64> {
        None
    }
    /// The body's extent in the plane now: its disc unless it stands otherwise (a character
    /// side-on, [`super::side_on`]).
    fn footprint(&self) -> Footprint {
        Footprint::Disc { centre: self.pose().position, radius: self.radius() }
    }
    /// Advances by `dt` seconds following `command` through `space`.
    fn step(&mut self, command: Command, dt: f64, space: &mut dyn Space) -> StepOutcome;
}

/// Limits of the kinematic disc. Every field documents its default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscLimits {
    /// Radius, metres (0.3).
    pub radius: f64,
    /// Top forward speed, metres per second (1.5).
    pub max_speed: f64,
    /// Top turn rate, radians per second (2.5, about 143°/s).
    pub max_turn_rate: f64,
    /// Largest speed increase per second, m/s² (2.0).
    pub max_acceleration: f64,
    /// Largest speed decrease per second, m/s² (4.0).
    pub max_deceleration: f64,
    /// Room kept from obstacles and other agents: a step may not end closer than this, or
    /// than the disc already is when it is closer, metres (0.03).
    pub keep_m: f64,
}

impl Default for DiscLimits {
    fn default() -> Self {
        DiscLimits {
            radius: 0.3,
            max_speed: 1.5,
            max_turn_rate: 2.5,
            max_acceleration: 2.0,
            max_deceleration: 4.0,
            keep_m: 0.03,
        }
    }
}

/// Give of the room check, so that moving along a wall at a constant distance is not refused
/// for rounding, metres.
const KEEP_TOLERANCE_M: f64 = 1e-6;

/// A disc that turns and accelerates within limits.
#[derive(Debug, Clone, PartialEq)]
pub struct KinematicDisc {
    pose: Pose,
    speed: f64,
    /// Its limits.
    pub limits: DiscLimits,
}

impl KinematicDisc {
    /// A disc at rest at `pose`.
    pub fn new(pose: Pose, limits: DiscLimits) -> Self {
        KinematicDisc { pose, speed: 0.0, limits }
    }
}

impl Body for KinematicDisc {
    fn pose(&self) -> Pose {
        self.pose
    }

    fn speed(&self) -> f64 {
        self.speed
    }

    fn radius(&self) -> f64 {
        self.limits.radius
    }

    fn turn_limit(&self, _: f64) -> f64 {
        self.limits.max_turn_rate
    }

    /// The disc keeps its room on both sides: a gap narrower than the disc and its room twice
    /// over would have it come closer to a side than the room it keeps.
    fn passage_m(&self) -> f64 {
        2.0 * (self.limits.radius + self.limits.keep_m.max(0.0))
    }

    fn step(&mut self, command: Command, dt: f64, space: &mut dyn Space) -> StepOutcome {
        let l = self.limits;
        // The room to keep: the margin, or what there is now when less (so a disc that stands
        // closer can still move along or away, never nearer).
        let want = l.radius + l.keep_m.max(0.0);
        let now = space.clearance(self.pose.position, want + 1e-9);
        let need = now.min(want).max(l.radius) - KEEP_TOLERANCE_M;
        let free = &mut |p: DVec2| space.clearance(p, need + 1e-9) >= need.max(l.radius);
        let turn = if command.turn_rate.is_finite() { command.turn_rate } else { 0.0 };
        let target = if command.speed.is_finite() { command.speed.clamp(0.0, l.max_speed) } else { 0.0 };
        self.pose.yaw = crate::geom::wrap_angle(self.pose.yaw + turn.clamp(-l.max_turn_rate, l.max_turn_rate) * dt);
        let dv = (target - self.speed).clamp(-l.max_deceleration * dt, l.max_acceleration * dt);
        self.speed = (self.speed + dv).max(0.0);
        let distance = self.speed * dt;
        if distance <= 0.0 {
            return StepOutcome::default();
        }
        match slide(self.pose.position, self.pose.yaw, distance, free) {
            Some((next, moved, turn)) => {
                self.pose.position = next;
                // Sliding keeps only the component along the heading.
                if turn != 0.0 {
                    self.speed *= turn.cos();
                }
                StepOutcome { moved_m: moved, blocked: turn != 0.0 || moved < distance, held: false }
            }
            None => {
                self.speed = 0.0;
                StepOutcome { moved_m: 0.0, blocked: true, held: false }
            }
        }
    }
}

/// Where a body at `from` may go instead of `distance` along `heading`: that step if its end is
/// free; else the same step turned 15°, 30°, 45°, 60° to either side (smallest turn first, left
/// before right); else the straight step halved up to four times. Returns the end point, the
/// distance moved and the turn used (radians), or `None` when every try is blocked.
pub fn slide(
    from: DVec2,
    heading: f64,
    distance: f64,
    free: &mut dyn FnMut(DVec2) -> bool,
) -> Option<(DVec2, f64, f64)> {
    for turn_deg in [0.0f64, 15.0, -15.0, 30.0, -30.0, 45.0, -45.0, 60.0, -60.0] {
        let turn = turn_deg.to_radians();
        let next = from + DVec2::from_angle(heading + turn) * distance;
        if free(next) {
            return Some((next, distance, turn));
        }
    }
    let dir = DVec2::from_angle(heading);
    let mut step = distance * 0.5;
    for _ in 0..4 {
        let next = from + dir * step;
        if free(next) {
            return Some((next, step, 0.0));
        }
        step *= 0.5;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_and_guard() {
        let mut d = KinematicDisc::new(Pose { position: DVec2::ZERO, yaw: 0.0 }, DiscLimits::default());
        let out = d.step(Command { turn_rate: 10.0, speed: 10.0, toward: None }, 0.1, &mut OpenSpace);
        assert!((d.pose().yaw - 0.25).abs() < 1e-12);
        assert!((d.speed() - 0.2).abs() < 1e-12);
        assert!((out.moved_m - 0.02).abs() < 1e-12);
        // A wall right ahead: the body stops instead of entering it.
        let before = d.pose().position;
        struct Wall;
        impl Space for Wall {
            fn clearance(&mut self, _: DVec2, _: f64) -> f64 {
                0.0
            }
            fn segment_clearance(&mut self, _: DVec2, _: DVec2, _: f64) -> f64 {
                0.0
            }
            fn changes(&self) -> bool {
                false
            }
        }
        let out = d.step(Command { turn_rate: 0.0, speed: 1.0, toward: None }, 0.1, &mut Wall);
        assert!(out.blocked);
        assert_eq!(d.pose().position, before);
        assert_eq!(d.speed(), 0.0);
    }

    /// A wall along x = 1.
    struct WallAt1;
    impl Space for WallAt1 {
        fn clearance(&mut self, p: DVec2, max: f64) -> f64 {
            (1.0 - p.x).clamp(0.0, max)
        }
        fn segment_clearance(&mut self, a: DVec2, b: DVec2, max: f64) -> f64 {
            (1.0 - a.x.max(b.x)).clamp(0.0, max)
        }
        fn changes(&self) -> bool {
            false
        }
    }

    #[test]
    fn the_disc_keeps_its_room_from_walls() {
        let limits = DiscLimits::default();
        // Driven at a wall: it stops the margin short of touching it.
        let mut d = KinematicDisc::new(Pose { position: DVec2::ZERO, yaw: 0.2 }, limits);
        let mut closest = f64::INFINITY;
        for _ in 0..200 {
            d.step(Command { turn_rate: 0.0, speed: 1.0, toward: None }, 0.05, &mut WallAt1);
            closest = closest.min(1.0 - d.pose().position.x - limits.radius);
        }
        assert!(closest >= limits.keep_m - 1e-5 && closest < limits.keep_m + 0.02, "{closest}");
        // Starting closer than the margin, it can go along the wall but never nearer.
        let x0 = 1.0 - limits.radius - 0.01;
        let mut d = KinematicDisc::new(Pose { position: DVec2::new(x0, 0.0), yaw: 1.4 }, limits);
        for _ in 0..100 {
            d.step(Command { turn_rate: 0.0, speed: 1.0, toward: None }, 0.05, &mut WallAt1);
            assert!(d.pose().position.x <= x0 + 1e-5, "{:?}", d.pose());
        }
        assert!(d.pose().position.y > 0.5, "{:?}", d.pose());
    }
}
