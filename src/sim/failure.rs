//! Why an episode failed, in words for whoever ran it: seed 000 §4 counts an episode a
//! success only when the goal is reached without a collision, and a failed one says which of
//! the three ways it failed — refused at the start (no way round for the body), timed out (how
//! far from the goal, and how near it came), or collided (the first time: when, where, how
//! deep and into what).
//!
//! The first collision is recorded as the episode runs ([`Contact`], kept in the agent's
//! metrics); nothing here changes what an agent does.

use glam::DVec2;

use super::body::Footprint;
use crate::world::{Obstacle, World};

/// The first step an agent ended overlapping an obstacle or another agent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Simulated time at the end of that step, seconds.
    pub time_s: f64,
    /// Where the agent stood, metres.
    pub position: DVec2,
    /// How far it overlapped, metres.
    pub depth_m: f64,
    /// What it overlapped.
    pub with: Touched,
}

/// What an agent overlapped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Touched {
    /// The navigation world's obstacle of this index ([`World::obstacles`]).
    Obstacle(usize),
    /// The agent of this index.
    Agent(usize),
}

/// What the body of agent `me`, whose extent is `footprint`, overlaps most deeply: an obstacle
/// of `world` or one of `others` (the other agents' discs, centre and radius, in agent order
/// with `me` left out).
pub fn touched(
    world: &World,
    footprint: Footprint,
    others: &[(DVec2, f64)],
    me: usize,
    scratch: &mut Vec<usize>,
) -> Touched {
    let (a, b, radius) = match footprint {
        Footprint::Disc { centre, radius } => (centre, centre, radius),
        Footprint::Capsule { a, b, radius } => (a, b, radius),
    };
    let centre = (a + b) / 2.0;
    let reach = radius + a.distance(b) / 2.0;
    world.parts_near(centre, reach, scratch);
    let parts = world.parts();
    let obstacle = scratch
        .iter()
        .map(|&i| (parts[i].shape.segment_distance(a, b), Touched::Obstacle(parts[i].obstacle)))
        .min_by(|x, y| x.0.total_cmp(&y.0));
    let agent = others
        .iter()
        .enumerate()
        .map(|(k, &(c, r))| {
            let index = if k < me { k } else { k + 1 };
            (crate::plan::point_segment_distance(c, a, b) - r, Touched::Agent(index))
        })
        .min_by(|x, y| x.0.total_cmp(&y.0));
    match (obstacle, agent) {
        (Some(o), Some(g)) if g.0 < o.0 => g.1,
        (Some(o), _) => o.1,
        (None, Some(g)) => g.1,
        (None, None) => Touched::Obstacle(0),
    }
}

/// Where `o` stands and how big it is: its bounding box's centre and size.
pub fn where_is(o: &Obstacle) -> String {
    let b = o.hull.aabb();
    let (c, size) = ((b.min + b.max) / 2.0, b.max - b.min);
    format!("at ({:.2}, {:.2}), {:.2} × {:.2} m", c.x, c.y, size.x, size.y)
}

/// A timed-out episode: at `time_s` (the limit `limit_s` passed), the agent at `at` (its trail
/// `trail`, one point per step of `dt_s` from the start) short of the goal circle of `goal`
/// and `goal_radius`.
pub fn timed_out(
    time_s: f64,
    limit_s: f64,
    at: DVec2,
    trail: &[DVec2],
    dt_s: f64,
    goal: DVec2,
    goal_radius: f64,
) -> String {
    let short = |p: DVec2| (p.distance(goal) - goal_radius).max(0.0);
    let nearest = trail.iter().enumerate().map(|(k, &p)| (short(p), k)).min_by(|x, y| x.0.total_cmp(&y.0));
    let mut text =
        format!("timed out after {time_s:.2} s (limit {limit_s:.2} s), {:.2} m from the goal circle", short(at));
    if let Some((d, k)) = nearest
        && d < short(at) - 0.005
    {
        text += &format!(" (nearest {d:.2} m, at {:.2} s)", k as f64 * dt_s);
    }
    text
}

/// A collided episode: `count` steps overlapping something, the first `first`; `upper` times a
/// bone of the upper body went into an obstacle.
pub fn collided(count: u32, first: Option<&Contact>, upper: u32, world: &World) -> String {
    let mut parts = Vec::new();
    if let Some(c) = first {
        let what = match c.with {
            Touched::Obstacle(i) => world
                .obstacles()
                .get(i)
                .map_or_else(|| "an obstacle".to_string(), |o| format!("the obstacle {}", where_is(o))),
            Touched::Agent(i) => format!("agent {i}"),
        };
        let times = if count == 1 { "once".to_string() } else { format!("{count} steps") };
        parts.push(format!(
            "collided {times}, first at {:.2} s at ({:.2}, {:.2}): {:.3} m into {what}",
            c.time_s, c.position.x, c.position.y, c.depth_m
        ));
    }
    if upper > 0 {
        let times = if upper == 1 { "once".to_string() } else { format!("{upper} times") };
        parts.push(format!("a bone of the upper body went into an obstacle {times}"));
    }
    parts.join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::ObstacleShape;

    fn wall(x: f64) -> Obstacle {
        Obstacle::build(ObstacleShape::Box { center: DVec2::new(x, 0.0), width: 0.2, height: 2.0, yaw: 0.0 }, 0.0, 2.0)
            .unwrap()
    }

    #[test]
    fn the_deepest_overlap_is_named() {
        let world = World::new(vec![wall(-3.0), wall(1.0)]);
        let disc = Footprint::Disc { centre: DVec2::new(0.75, 0.0), radius: 0.3 };
        let mut scratch = Vec::new();
        assert_eq!(touched(&world, disc, &[], 0, &mut scratch), Touched::Obstacle(1));
        // Another agent overlapping more deeply than the wall: agent 0 of the others is agent
        // 0, and the second is agent 2 when the one touching is agent 1.
        let others = [(DVec2::new(5.0, 0.0), 0.3), (DVec2::new(0.5, 0.0), 0.3)];
        assert_eq!(touched(&world, disc, &others, 1, &mut scratch), Touched::Agent(2));
        let c = Contact { time_s: 2.5, position: DVec2::new(0.75, 0.0), depth_m: 0.15, with: Touched::Obstacle(1) };
        let text = collided(3, Some(&c), 0, &world);
        assert_eq!(
            text,
            "collided 3 steps, first at 2.50 s at (0.75, 0.00): 0.150 m into the obstacle at (1.00, 0.00), 0.20 × 2.00 m"
        );
    }

    #[test]
    fn a_timeout_says_how_far_and_how_near() {
        let trail = [DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::new(2.0, 0.0), DVec2::new(1.0, 0.0)];
        let text = timed_out(0.15, 0.15, trail[3], &trail, 0.05, DVec2::new(4.0, 0.0), 0.5);
        assert_eq!(
            text,
            "timed out after 0.15 s (limit 0.15 s), 2.50 m from the goal circle (nearest 1.50 m, at 0.10 s)"
        );
        // Nearest at the end: no second figure.
        let text = timed_out(0.1, 0.1, trail[2], &trail[..3], 0.05, DVec2::new(4.0, 0.0), 0.5);
        assert_eq!(text, "timed out after 0.10 s (limit 0.10 s), 1.50 m from the goal circle");
    }
}
