//! What a running simulation looks like as a [`Scene`]: the one conversion used by PNG frames
//! and the terminal view, so both show the same thing.

use glam::DVec2;

use super::poses::{StripPose, strip_pose};
use super::scene::{AgentView, Scene};
use super::side_view::{SideLegs, SideView};
use crate::footstep::{Foot, Foothold, GroundPiece, LegPose, Sole, StepPose};
use crate::sim::footing::{Footing, PlayedStep};
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

/// The side view of an animated character's walk on uneven terrain (seed 002 Fig 6): the steps
/// it played, gathered while the simulation runs ([`SideRecorder::observe`] after each step),
/// unrolled along the path into one strip ([`SideRecorder::view`]).
///
/// Each step was planned in its own sagittal plane, whose X axis starts at the supporting foot;
/// the strip puts step `k`'s supporting foot at the sum of the earlier steps' lengths and shows
/// of each step's profile the part from its supporting foot to its touch-down (the first step
/// from behind its lift-off, the last one [`SIDE_AHEAD_M`] beyond its touch-down).
#[derive(Debug, Clone, Default)]
pub struct SideRecorder {
    steps: Vec<(Foot, PlayedStep)>,
    plans: u64,
    stopped: bool,
}

/// How far the side view shows the ground beyond the last touch-down, metres.
pub const SIDE_AHEAD_M: f64 = 1.5;

impl SideRecorder {
    /// Records the step `footing` plays, if it is a new one.
    pub fn observe(&mut self, footing: &Footing) {
        self.stopped = footing.stopped().is_some();
        if footing.plans() == self.plans {
            return;
        }
        self.plans = footing.plans();
        if let (Some(p), Some(last)) = (footing.played(), footing.footholds().last()) {
            self.steps.push((last.foot, p.clone()));
        }
    }

    /// Steps recorded.
    pub fn len(&self) -> usize {
        self.steps.len()
    }

    /// Whether no step was recorded.
    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }

    /// The strip: ground, footholds and legs (`poses_per_step` per step) unrolled along the path.
    pub fn view(&self, foot_length_m: f64, poses_per_step: usize) -> SideView {
        let n = poses_per_step.max(1);
        let mut view = SideView { foot_length_m, stopped: self.stopped, ..SideView::default() };
        let mut at = 0.0;
        let count = self.steps.len();
        for (k, (foot, p)) in self.steps.iter().enumerate() {
            let s = &p.swing;
            let shift = at - s.stance.x_m;
            let moved = |mut sole: Sole| {
                sole.x_m += shift;
                sole
            };
            let lo = if k == 0 { s.lift_off.x_m - foot_length_m } else { s.stance.x_m };
            let hi = if k + 1 == count { s.touch_down.x_m + SIDE_AHEAD_M } else { s.touch_down.x_m };
            for g in p.profile.pieces() {
                let (x0, x1) = (g.x0_m.max(lo), g.x1_m.min(hi));
                if x1 > x0 {
                    view.ground.push(GroundPiece {
                        x0_m: x0 + shift,
                        z0_m: g.height_at(x0),
                        x1_m: x1 + shift,
                        z1_m: g.height_at(x1),
                    });
                }
            }
            if k == 0 {
                view.footholds.push(Foothold { foot: *foot, sole: moved(s.lift_off) });
                view.footholds.push(Foothold { foot: foot.other(), sole: moved(s.stance) });
            }
            view.footholds.push(Foothold { foot: *foot, sole: moved(s.touch_down) });
            let offset = DVec2::new(shift, 0.0);
            let shifted = |l: LegPose| LegPose {
                hip: l.hip + offset,
                knee: l.knee + offset,
                ankle: l.ankle + offset,
                heel: l.heel + offset,
                toe: l.toe + offset,
            };
            let phases = if k + 1 == count { n + 1 } else { n };
            for i in 0..phases {
                let pose = s.pose_at(i as f64 / n as f64);
                view.legs.push(SideLegs {
                    swinging: *foot,
                    pose: StepPose { phase: pose.phase, swing: shifted(pose.swing), stance: shifted(pose.stance) },
                });
            }
            at += s.length_m();
        }
        view
    }
}
