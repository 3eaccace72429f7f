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

    /// Longest time limit a task may have, seconds (one day of simulated time).
    pub const MAX_TIME_LIMIT_S: f64 = 86_400.0;

    /// A task from `start` to `goal` with default radius and a time limit scaled to the
    /// straight-line distance (10 s per metre, at least 60 s, at most [`Task::MAX_TIME_LIMIT_S`]).
    pub fn new(start: Pose, goal: DVec2) -> Task {
        let d = start.position.distance(goal);
        let time_limit_s = (d * 10.0).clamp(60.0, Self::MAX_TIME_LIMIT_S);
        Task { start, goal, goal_radius: Self::DEFAULT_GOAL_RADIUS, time_limit_s }
    }
}
