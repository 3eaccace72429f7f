//! Terrain height over the XY plane (DESIGN.md §1, §4). Flat for now; steps, slopes and gaps
//! for the footstep planner (seed 002 §3.2) extend this type.

use glam::DVec2;

/// Ground height as a function of position.
#[derive(Debug, Clone, Default, PartialEq)]
pub enum Terrain {
    /// Height 0 everywhere.
    #[default]
    Flat,
}

impl Terrain {
    /// Ground height at `p`, metres.
    pub fn height(&self, _p: DVec2) -> f64 {
        match self {
            Terrain::Flat => 0.0,
        }
    }
}
