//! What an agent must do (seed 000 §3.1): start pose, goal region and time limit.

use glam::DVec2;

/// Position (metres) and heading (radians, counter-clockwise from +X).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Position in the plane, metres.
    pub position: DVec2,
    /// Heading, radians.
    pub yaw: f64,
}

/// A navigation task.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Task {
    /// Where and how the agent starts.
    pub start: Pose,
    /// Goal point, metres.
    pub goal: DVec2,
    /// The goal is reached within this distance of `goal`, metres.
    pub goal_radius: f64,
    /// The episode fails after this much simulated time, seconds.
    pub time_limit_s: f64,
}

impl Task {
    /// Default goal radius, metres.
    pub const DEFAULT_GOAL_RADIUS: f64 = 0.5;

    /// A task from `start` to `goal` with default radius and a time limit scaled to the
    /// straight-line distance (at least 60 s).
    pub fn new(start: Pose, goal: DVec2) -> Task {
        let d = start.position.distance(goal);
        Task { start, goal, goal_radius: Self::DEFAULT_GOAL_RADIUS, time_limit_s: (d * 10.0).max(60.0) }
    }
}
