//! What a running simulation looks like as a [`Scene`]: the one conversion used by PNG frames
//! and the terminal view, so both show the same thing.

use glam::DVec2;

use super::poses::{StripPose, strip_pose};
use super::scene::{AgentView, Scene};
use crate::sim::{AnimatedBody, Body, Simulation};

/// How far ahead of the foot joint (ankle) a drawn footprint's centre lies, metres.
const FOOT_CENTRE_AHEAD_M: f64 = 0.07;

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
                // On uneven terrain: the footholds the footstep planner chose (seed 002 §4.2).
                footprints: a.body.animated().map_or_else(Vec::new, |b| match b.footing() {
                    Some(f) => f.footholds().iter().map(|h| (h.position, h.yaw)).collect(),
                    None => b
                        .player()
                        .footprints
                        .iter()
                        .map(|f| (DVec2::new(f.x, f.y) + DVec2::from_angle(f.yaw) * FOOT_CENTRE_AHEAD_M, f.yaw))
                        .collect(),
                }),
                label: None,
            }
        })
        .collect();
    let goals = sim.agents.iter().map(|a| (a.task.goal, a.task.goal_radius)).collect();
    Scene { world: &sim.world, agents, goals, view: None, caption }
}

/// The animated character's current pose for the side-view strip, in its ground frame, with
/// its head and feet outlined.
pub fn strip_pose_of(body: &AnimatedBody, caption: String) -> StripPose {
    let db = &body.animation().db;
    let mut pose = body.player().pose().clone();
    body.player().ground().transform_pose(&mut pose, true);
    strip_pose(&db.skeleton, &pose, &db.feet, caption)
}
