//! Seeded crowd generators for experiments: worlds of many agents with their goals, each a
//! [`Crowd`] run as one episode, solvable by construction (every agent's goal is joined to its
//! start through open floor, and no two agents start overlapping). Command lines spell a kind
//! `random:KIND` with an agent count; [`generate`] makes the world of a kind, a count and a
//! seed, named `random-KIND-N-SEED`.
//!
//! - [`CrowdKind::Corridor`]: counterflow, two groups at the two ends of a corridor 6 m wide
//!   between two walls, each agent bound for its mirror image at the other end.
//! - [`CrowdKind::Crossing`]: two flows crossing at right angles where two such corridors meet
//!   (four corner blocks make the cross), one group going east, the other north.
//! - [`CrowdKind::Bottleneck`]: a square room draining through a 1.2 m door in its east wall,
//!   every agent bound for a point outside.
//! - [`CrowdKind::Circle`]: agents evenly spaced on a circle, each bound for the antipode.
//!
//! Agents have the default radius (0.3 m) and walk at 1.3 m/s (1.2–1.4 m/s on the circle, so
//! they do not all meet at once); groups are scattered over a lattice of cells, each agent in
//! its own cell, jittered within it, two thirds of the cells filled, so their discs stay
//! 2 cm apart at least. Every random draw comes from [`rng::stream`] keyed by the seed.

use std::f64::consts::{PI, TAU};
use std::fmt;
use std::str::FromStr;

use glam::DVec2;
use rand_chacha::ChaCha8Rng;
use rand_core::RngCore;

use crate::rng;
use crate::scenario::crowd::{self, Crowd, CrowdAgent, Goal, GoalKind};
use crate::scenario::{DEFAULT_AGENT_RADIUS, Scenario};
use crate::world::obstacle::DEFAULT_Z;
use crate::world::{Obstacle, ObstacleShape, Pose};

/// Radius of the generated agents, metres.
pub const AGENT_RADIUS_M: f64 = DEFAULT_AGENT_RADIUS;
/// Their desired speed, m/s (SteerSuite's cases' walking speed).
pub const DESIRED_SPEED_MPS: f64 = 1.3;
/// How long an agent may take to its goal, seconds (SteerSuite's cases' usual duration).
pub const GOAL_DURATION_S: f64 = 1000.0;
/// Width of the corridors, metres.
pub const CORRIDOR_WIDTH_M: f64 = 6.0;
/// Width of the bottleneck's door, metres.
pub const DOOR_WIDTH_M: f64 = 1.2;
/// Thickness of the walls, metres.
const WALL_M: f64 = 0.4;
/// Room left between two agents' discs in a lattice, metres: cells are `2r + GAP_M` wide.
const GAP_M: f64 = 0.2;
/// Share of a lattice's cells that hold an agent.
const FILL: f64 = 2.0 / 3.0;
/// Open floor between the two groups of a corridor or a crossing, metres.
const MIDDLE_M: f64 = 10.0;
/// Room along the circle per agent, metres.
const CIRCLE_SPACING_M: f64 = 2.0 * AGENT_RADIUS_M + 0.5;
/// The random stream of the generators.
const STREAM: u64 = 0x4352_4F57;

/// A kind of seeded crowd.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CrowdKind {
    /// Counterflow in a corridor.
    Corridor,
    /// Two flows crossing at right angles.
    Crossing,
    /// A room draining through a door.
    Bottleneck,
    /// Agents on a circle, each to the antipode.
    Circle,
}

impl CrowdKind {
    /// Every kind.
    pub const ALL: [CrowdKind; 4] =
        [CrowdKind::Corridor, CrowdKind::Crossing, CrowdKind::Bottleneck, CrowdKind::Circle];

    /// The name accepted by [`FromStr`]: `corridor`, `crossing`, `bottleneck` or `circle`.
    pub fn name(self) -> &'static str {
        match self {
            CrowdKind::Corridor => "corridor",
            CrowdKind::Crossing => "crossing",
            CrowdKind::Bottleneck => "bottleneck",
            CrowdKind::Circle => "circle",
        }
    }
}

impl fmt::Display for CrowdKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A crowd kind name that is none of the accepted ones.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown crowd kind `{0}` (expected corridor, crossing, bottleneck or circle)")]
pub struct ParseCrowdKindError(pub String);

impl FromStr for CrowdKind {
    type Err = ParseCrowdKindError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        CrowdKind::ALL.into_iter().find(|k| k.name() == s).ok_or_else(|| ParseCrowdKindError(s.to_string()))
    }
}

/// The crowd of `kind` with `agents` agents (1 to [`crowd::MAX_AGENTS`]) for `seed`, named
/// `random-KIND-N-SEED`; the same arguments always give the same scenario.
pub fn generate(kind: CrowdKind, agents: usize, seed: u64) -> Result<Scenario, String> {
    if !(1..=crowd::MAX_AGENTS).contains(&agents) {
        return Err(format!("a crowd has 1 to {} agents, not {agents}", crowd::MAX_AGENTS));
    }
    let mut rng = rng::stream(seed, agents as u64, STREAM);
    let (obstacles, members) = match kind {
        CrowdKind::Corridor => corridor(&mut rng, agents),
        CrowdKind::Crossing => crossing(&mut rng, agents),
        CrowdKind::Bottleneck => bottleneck(&mut rng, agents),
        CrowdKind::Circle => circle(&mut rng, agents),
    };
    let mut scenario = Scenario::new(&format!("random-{kind}-{agents}-{seed}"));
    scenario.obstacles = obstacles
        .into_iter()
        .map(|shape| Obstacle::build(shape, DEFAULT_Z.0, DEFAULT_Z.1).expect("generated walls are valid"))
        .collect();
    let agents = members
        .into_iter()
        .map(|(start, goal, speed)| CrowdAgent {
            name: String::new(),
            start: Pose { position: start, yaw: (goal - start).to_angle() },
            radius_m: AGENT_RADIUS_M,
            speed_mps: 0.0,
            goals: vec![Goal {
                kind: GoalKind::SeekPoint(goal),
                desired_speed_mps: speed,
                duration_s: GOAL_DURATION_S,
            }],
        })
        .collect();
    scenario.set_crowd(Crowd { agents, stay_on_arrival: false });
    Ok(scenario)
}

/// An agent: start, goal, desired speed.
type Member = (DVec2, DVec2, f64);

/// Width of a lattice cell, metres.
const PITCH_M: f64 = 2.0 * AGENT_RADIUS_M + GAP_M;

/// `n` points in distinct cells of a lattice of `cols` × `rows` cells of [`PITCH_M`] whose
/// lower corner is `origin`, each jittered within its cell so that discs stay apart.
fn scatter(rng: &mut ChaCha8Rng, n: usize, origin: DVec2, cols: usize, rows: usize) -> Vec<DVec2> {
    let mut cells: Vec<usize> = (0..cols * rows).collect();
    debug_assert!(cells.len() >= n);
    let jitter = 0.45 * GAP_M;
    (0..n)
        .map(|k| {
            let pick = k + (rng.next_u64() % (cells.len() - k) as u64) as usize;
            cells.swap(k, pick);
            let (c, r) = (cells[k] % cols, cells[k] / cols);
            let centre = origin + PITCH_M * DVec2::new(c as f64 + 0.5, r as f64 + 0.5);
            centre + DVec2::new(rng::uniform(rng, -jitter, jitter), rng::uniform(rng, -jitter, jitter))
        })
        .collect()
}

/// How many lattice columns `n` agents need in `rows` rows.
fn columns(n: usize, rows: usize) -> usize {
    ((n as f64 / FILL / rows as f64).ceil() as usize).max(1)
}

/// A box from its lower and upper corners.
fn wall(min: DVec2, max: DVec2) -> ObstacleShape {
    let size = max - min;
    ObstacleShape::Box { center: 0.5 * (min + max), width: size.x, height: size.y, yaw: 0.0 }
}

/// Rows of agents across a corridor, and the lattice's length along it for `n` agents.
fn corridor_lattice(n: usize) -> (usize, usize, f64) {
    let rows = (CORRIDOR_WIDTH_M / PITCH_M).floor() as usize;
    let cols = columns(n, rows);
    (rows, cols, cols as f64 * PITCH_M)
}

fn corridor(rng: &mut ChaCha8Rng, n: usize) -> (Vec<ObstacleShape>, Vec<Member>) {
    let (east, west) = (n.div_ceil(2), n / 2);
    let (rows, cols, length) = corridor_lattice(east);
    let end = MIDDLE_M / 2.0 + length + 1.0;
    let y0 = -0.5 * rows as f64 * PITCH_M;
    let half = CORRIDOR_WIDTH_M / 2.0;
    let walls = vec![
        wall(DVec2::new(-end, half), DVec2::new(end, half + WALL_M)),
        wall(DVec2::new(-end, -half - WALL_M), DVec2::new(end, -half)),
    ];
    let mut members = Vec::with_capacity(n);
    for p in scatter(rng, east, DVec2::new(-MIDDLE_M / 2.0 - length, y0), cols, rows) {
        members.push((p, DVec2::new(-p.x, p.y), DESIRED_SPEED_MPS));
    }
    for p in scatter(rng, west, DVec2::new(MIDDLE_M / 2.0, y0), cols, rows) {
        members.push((p, DVec2::new(-p.x, p.y), DESIRED_SPEED_MPS));
    }
    (walls, members)
}

fn crossing(rng: &mut ChaCha8Rng, n: usize) -> (Vec<ObstacleShape>, Vec<Member>) {
    let (east, north) = (n.div_ceil(2), n / 2);
    let (rows, cols, length) = corridor_lattice(east);
    let arm = MIDDLE_M / 2.0 + length + 1.0;
    let half = CORRIDOR_WIDTH_M / 2.0;
    let walls = [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)]
        .into_iter()
        .map(|(sx, sy)| {
            let (a, b) = (DVec2::new(sx * half, sy * half), DVec2::new(sx * (half + arm), sy * (half + arm)));
            wall(a.min(b), a.max(b))
        })
        .collect();
    let across = -0.5 * rows as f64 * PITCH_M;
    let mut members = Vec::with_capacity(n);
    for p in scatter(rng, east, DVec2::new(-MIDDLE_M / 2.0 - length, across), cols, rows) {
        members.push((p, DVec2::new(-p.x, p.y), DESIRED_SPEED_MPS));
    }
    // The northbound group: the same lattice turned a quarter.
    for p in scatter(rng, north, DVec2::new(-MIDDLE_M / 2.0 - length, across), cols, rows) {
        let p = DVec2::new(-p.y, p.x);
        members.push((p, DVec2::new(p.x, -p.y), DESIRED_SPEED_MPS));
    }
    (walls, members)
}

fn bottleneck(rng: &mut ChaCha8Rng, n: usize) -> (Vec<ObstacleShape>, Vec<Member>) {
    let side_cells = ((n as f64 / FILL).sqrt().ceil() as usize).max(2);
    let side = side_cells as f64 * PITCH_M + 2.0 * GAP_M;
    let (west, half) = (-side, side / 2.0);
    let door = DOOR_WIDTH_M / 2.0;
    let walls = vec![
        wall(DVec2::new(west - WALL_M, -half - WALL_M), DVec2::new(west, half + WALL_M)),
        wall(DVec2::new(west, half), DVec2::new(0.0, half + WALL_M)),
        wall(DVec2::new(west, -half - WALL_M), DVec2::new(0.0, -half)),
        wall(DVec2::new(0.0, door), DVec2::new(WALL_M, half + WALL_M)),
        wall(DVec2::new(0.0, -half - WALL_M), DVec2::new(WALL_M, -door)),
    ];
    let origin = DVec2::new(west + GAP_M, -half + GAP_M);
    let spread = half.max(2.0) / 2.0;
    let members = scatter(rng, n, origin, side_cells, side_cells)
        .into_iter()
        .map(|p| {
            let goal = DVec2::new(WALL_M + 5.0, rng::uniform(rng, -spread, spread));
            (p, goal, DESIRED_SPEED_MPS)
        })
        .collect();
    (walls, members)
}

fn circle(rng: &mut ChaCha8Rng, n: usize) -> (Vec<ObstacleShape>, Vec<Member>) {
    let radius = (n as f64 * CIRCLE_SPACING_M / TAU).max(4.0);
    let turn = rng::uniform(rng, 0.0, TAU);
    let members = (0..n)
        .map(|i| {
            let a = turn + TAU * i as f64 / n as f64;
            let p = radius * DVec2::from_angle(a);
            let goal = radius * DVec2::from_angle(a + PI);
            (p, goal, rng::uniform(rng, 1.2, 1.4))
        })
        .collect();
    (Vec::new(), members)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::maps::generate::connected;

    #[test]
    fn every_kind_is_valid_seeded_and_solvable() {
        for kind in CrowdKind::ALL {
            assert_eq!(kind.name().parse::<CrowdKind>(), Ok(kind));
            for n in [1, 2, 7, 60, 301] {
                let s = generate(kind, n, 5).unwrap();
                assert_eq!(s.name, format!("random-{kind}-{n}-5"));
                s.validate().unwrap_or_else(|e| panic!("{kind} {n}: {e}"));
                let c = s.crowd.as_ref().unwrap();
                assert_eq!(c.agents.len(), n);
                assert!(c.overlapping_starts(0.01).is_empty(), "{kind} {n}");
                assert_eq!(generate(kind, n, 5).unwrap().crowd, s.crowd, "{kind}: the same seed, the same crowd");
                if n == 60 {
                    assert_ne!(generate(kind, n, 6).unwrap().crowd, s.crowd, "{kind}: another seed, another crowd");
                    // Each agent's goal is reachable from its start for its disc.
                    let world = s.world();
                    let points = s.tasks.iter().flat_map(|t| [t.start.position, t.goal]);
                    let (lo, hi) =
                        points.fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(a, b), p| (a.min(p), b.max(p)));
                    let (lo, hi) = (lo - DVec2::splat(2.0), hi + DVec2::splat(2.0));
                    for t in s.tasks.iter().step_by(7) {
                        assert!(connected(&world, lo, hi, t.start.position, t.goal, AGENT_RADIUS_M), "{kind}: {t:?}");
                    }
                }
            }
        }
        assert!(generate(CrowdKind::Circle, 0, 1).is_err());
        assert!(generate(CrowdKind::Circle, crowd::MAX_AGENTS + 1, 1).is_err());
        assert!("square".parse::<CrowdKind>().unwrap_err().to_string().contains("bottleneck"));
    }
}
