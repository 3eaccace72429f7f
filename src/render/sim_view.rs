//! What a running simulation looks like as a [`Scene`]: the one conversion used by PNG frames
//! and the terminal view, so both show the same thing.

use super::scene::{AgentView, Scene};
use crate::sim::{Body, Simulation};

/// The scene of `sim` now: obstacles, goals, and every agent with trail and sensor sectors.
pub fn scene_of<'a>(sim: &'a Simulation, caption: Option<String>) -> Scene<'a> {
    let layout = &sim.params.layout;
    let agents = sim
        .agents
        .iter()
        .map(|a| {
            let pose = a.body.pose();
            let sectors = (a.sensed.sectors.len() == layout.len())
                .then(|| (layout.edges.clone(), a.sensed.sectors.clone(), layout.range));
            AgentView {
                position: pose.position,
                yaw: pose.yaw,
                radius: a.body.radius(),
                trail: a.trail.clone(),
                sectors,
                footprints: Vec::new(),
                label: None,
            }
        })
        .collect();
    let goals = sim.agents.iter().map(|a| (a.task.goal, a.task.goal_radius)).collect();
    Scene { world: &sim.world, agents, goals, view: None, caption }
}
