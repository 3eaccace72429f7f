//! Every seeded world generator under one name: [`WorldKind`] lists them (the three obstacle
//! densities of [`generate`](super::generate), buildings of [`building`], mazes of [`maze`] and
//! grid maps of [`grid`]), and [`generate`] makes the world of a kind and a seed. Command lines
//! spell a kind `random:KIND`.
//!
//! Every kind keeps the same promises: the world is closed by walls, its one task's start and
//! goal are joined for the 0.3 m agent disc (checked with
//! [`connected`](super::generate::connected)), the same `(kind, seed)` always gives the same
//! scenario, and the scenario is named `random-KIND-SEED`.

use std::fmt;
use std::str::FromStr;

use super::generate::{Density, random_world};
use super::{building, grid, maze};
use crate::scenario::Scenario;

/// A kind of seeded random world.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum WorldKind {
    /// Few obstacles (8) in a 20 m square ([`Density::Sparse`]).
    Sparse,
    /// Semi-cluttered: 20 obstacles in a 20 m square ([`Density::Semi`]).
    Semi,
    /// Cluttered: 40 obstacles in a 20 m square ([`Density::Cluttered`]).
    Cluttered,
    /// A building: a 20–30 m floor of 3–6 m rooms joined by 0.9–1.2 m doors.
    Rooms,
    /// A maze with 2–3 m corridors and a few loops, about 20 m a side.
    Maze,
    /// A 20 × 20 grid of 1 m cells, 10–25 % of them blocked.
    Grid,
}

impl WorldKind {
    /// Every kind, the three densities first.
    pub const ALL: [WorldKind; 6] =
        [WorldKind::Sparse, WorldKind::Semi, WorldKind::Cluttered, WorldKind::Rooms, WorldKind::Maze, WorldKind::Grid];

    /// The name accepted by [`FromStr`] and used in scenario names: `sparse`, `semi`,
    /// `cluttered`, `rooms`, `maze` or `grid`.
    pub fn name(self) -> &'static str {
        match self {
            WorldKind::Sparse => "sparse",
            WorldKind::Semi => "semi",
            WorldKind::Cluttered => "cluttered",
            WorldKind::Rooms => "rooms",
            WorldKind::Maze => "maze",
            WorldKind::Grid => "grid",
        }
    }

    /// The obstacle density of the three open-clutter kinds, `None` for the others.
    pub fn density(self) -> Option<Density> {
        match self {
            WorldKind::Sparse => Some(Density::Sparse),
            WorldKind::Semi => Some(Density::Semi),
            WorldKind::Cluttered => Some(Density::Cluttered),
            WorldKind::Rooms | WorldKind::Maze | WorldKind::Grid => None,
        }
    }
}

impl From<Density> for WorldKind {
    fn from(d: Density) -> WorldKind {
        match d {
            Density::Sparse => WorldKind::Sparse,
            Density::Semi => WorldKind::Semi,
            Density::Cluttered => WorldKind::Cluttered,
        }
    }
}

impl fmt::Display for WorldKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A world kind name that is none of the accepted ones.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown world kind `{0}` (expected sparse, semi, cluttered, rooms, maze or grid)")]
pub struct ParseWorldKindError(pub String);

impl FromStr for WorldKind {
    type Err = ParseWorldKindError;

    /// Accepts `sparse`, `semi` (or `semi-cluttered`), `cluttered`, `rooms`, `maze` and `grid`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "rooms" => Ok(WorldKind::Rooms),
            "maze" => Ok(WorldKind::Maze),
            "grid" => Ok(WorldKind::Grid),
            other => other.parse::<Density>().map(WorldKind::from).map_err(|_| ParseWorldKindError(other.to_string())),
        }
    }
}

/// The world of `kind` for `seed`, named `random-KIND-SEED`; the same arguments always give
/// the same scenario.
pub fn generate(kind: WorldKind, seed: u64) -> Scenario {
    match kind {
        WorldKind::Sparse => random_world(Density::Sparse, seed),
        WorldKind::Semi => random_world(Density::Semi, seed),
        WorldKind::Cluttered => random_world(Density::Cluttered, seed),
        WorldKind::Rooms => building::rooms_world(seed),
        WorldKind::Maze => maze::maze_world(seed),
        WorldKind::Grid => grid::grid_world(seed),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for k in WorldKind::ALL {
            assert_eq!(k.name().parse::<WorldKind>(), Ok(k));
            assert_eq!(k.to_string(), k.name());
        }
        assert_eq!("semi-cluttered".parse::<WorldKind>(), Ok(WorldKind::Semi));
        let e = "castle".parse::<WorldKind>().unwrap_err().to_string();
        assert!(e.contains("castle") && e.contains("rooms"), "{e}");
        assert!("Maze".parse::<WorldKind>().is_err());
        for d in Density::ALL {
            assert_eq!(WorldKind::from(d).density(), Some(d));
        }
    }

    #[test]
    fn names_say_kind_and_seed() {
        for k in WorldKind::ALL {
            assert_eq!(generate(k, 17).name, format!("random-{k}-17"));
        }
    }
}
