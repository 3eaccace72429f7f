//! What a running simulation looks like as a [`Scene`]: the one conversion used by PNG frames
//! and the terminal view, so both show the same thing.

use glam::{DVec2, DVec3};

use super::poses::{StripPose, strip_pose};
use super::scene::{AgentView, Scene, Verdict};
use super::side_view::{SideLegs, SideView};
use crate::footstep::{Foot, Foothold, GroundPiece, LegPose, Sole, StepPose};
use crate::sim::footing::{Footing, PlayedStep};
use crate::sim::{AnimatedBody, Body, Outcome, Simulation};

/// How far ahead of the foot joint (ankle) a drawn footprint's centre lies, metres.
const FOOT_CENTRE_AHEAD_M: f64 = 0.07;

/// The scene of `sim` now: obstacles, goals, and every agent with its start, trail and sensor
/// sectors; once every agent is done, how the episode ended; a legend.
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
                walks: a.body.animated().is_some(),
                start: Some(a.task.start.position),
                label: None,
            }
        })
        .collect();
    let goals = sim.agents.iter().map(|a| (a.task.goal, a.task.goal_radius)).collect();
    Scene { world: &sim.world, agents, goals, view: None, caption, outcome: verdict(sim), legend: true }
}

/// How the episode of `sim` ended, once every agent is done: for one agent what happened to
/// it (the goal reached and the path's length, or how it failed), for several how many reached
/// their goals.
pub fn verdict(sim: &Simulation) -> Option<Verdict> {
    if sim.agents.is_empty() || !sim.all_done() {
        return None;
    }
    let clean = |a: &crate::sim::Agent| a.outcome == Some(Outcome::Reached) && a.metrics.collisions == 0;
    if let [a] = sim.agents.as_slice() {
        let m = &a.metrics;
        let mut text = match a.outcome? {
            Outcome::Reached => format!("goal reached, path {:.2} m", m.path_length_m),
            Outcome::TimedOut => {
                let short = (a.body.pose().position.distance(a.task.goal) - a.task.goal_radius).max(0.0);
                format!("timed out {short:.2} m from the goal")
            }
            Outcome::Refused => "refused: no way round for the body".to_string(),
        };
        if m.collisions > 0 {
            text += &format!(", {} collision(s)", m.collisions);
        }
        return Some(Verdict { text, success: clean(a) });
    }
    let reached = sim.agents.iter().filter(|a| clean(a)).count();
    Some(Verdict {
        text: format!("{reached} of {} agents reached their goals cleanly", sim.agents.len()),
        success: reached == sim.agents.len(),
    })
}

/// The animated character's current pose for the side-view strip, in its ground frame, with
/// its head and feet outlined.
pub fn strip_pose_of(body: &AnimatedBody, caption: String) -> StripPose {
    let db = &body.animation().db;
    let mut pose = body.world_pose();
    body.player().ground().transform_pose(&mut pose, true);
    strip_pose(&db.skeleton, &pose, &db.feet, caption)
}

/// Which way a strip of the upper body looks at the character.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StripView {
    /// From its left: forward to the right, up (a bend shows).
    Side,
    /// From ahead: its left to the right, up (a twist shows).
    Front,
}

/// Half the width of the slice of the world a strip shows obstacles from, metres: for the
/// side view what lies this far either side of the character's path, for the front view what
/// lies this far ahead of and behind its hips.
const SLICE_HALF_M: f64 = 0.35;

/// The animated character now for an upper-body strip (seed 002 §5, Fig 9), seen `view`, in its
/// ground frame, with the parts of `obstacles` within a slice of the world around it cut to
/// rectangles of their extent across the view and their heights.
pub fn upper_strip_pose<'a>(
    body: &AnimatedBody,
    obstacles: impl IntoIterator<Item = &'a crate::world::Obstacle>,
    view: StripView,
    caption: String,
) -> StripPose {
    let g = body.player().ground();
    let mut p = strip_pose_of(body, caption);
    let local = |q: DVec2| {
        let d = q - DVec2::new(g.x, g.y);
        let (s, c) = g.yaw.sin_cos();
        DVec2::new(c * d.x + s * d.y, -s * d.x + c * d.y)
    };
    for o in obstacles {
        for part in &o.parts {
            let pts: Vec<DVec2> = match part {
                crate::geom::Shape::Polygon(poly) => poly.vertices().iter().map(|&v| local(v)).collect(),
                crate::geom::Shape::Circle { center, radius } => {
                    let c = local(*center);
                    (0..16).map(|k| c + DVec2::from_angle(k as f64 * std::f64::consts::TAU / 16.0) * *radius).collect()
                }
            };
            let (lo, hi) = pts.iter().fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(l, h), &v| (l.min(v), h.max(v)));
            // Across the view (drawn) and along the line of sight (the slice).
            let ((a0, a1), (s0, s1), reach) = match view {
                StripView::Side => ((lo.x, hi.x), (lo.y, hi.y), 1.2),
                StripView::Front => ((lo.y, hi.y), (lo.x, hi.x), 1.0),
            };
            if s1 < -SLICE_HALF_M || s0 > SLICE_HALF_M || a1 < -reach || a0 > reach {
                continue;
            }
            let (z0, z1) = (o.z_min.max(0.0), o.z_max.min(2.3));
            if z1 > z0 {
                p.boxes.push((DVec2::new(a0.max(-reach), z0), DVec2::new(a1.min(reach), z1)));
            }
        }
    }
    if view == StripView::Front {
        // Seen from ahead: the character's left (+Y) to the right of the picture.
        let turn = |v: DVec3| DVec3::new(v.y, -v.x, v.z);
        p.joints.iter_mut().for_each(|v| *v = turn(*v));
        p.tips.iter_mut().for_each(|(_, v)| *v = turn(*v));
        p.feet.iter_mut().for_each(|(_, o)| o.iter_mut().for_each(|v| *v = turn(*v)));
        if let Some((_, top)) = &mut p.head {
            *top = turn(*top);
        }
    }
    p
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

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::sim::OpenSpace;
    use crate::world::{Obstacle, ObstacleShape, Pose};

    #[test]
    fn a_bar_ahead_is_cut_into_both_views_and_the_front_view_turns_the_body() {
        let animation = Arc::new(crate::builtin::animation().unwrap());
        let mut body = AnimatedBody::new(animation, Pose { position: DVec2::ZERO, yaw: 0.0 }, 0.3);
        body.step(Default::default(), 0.05, &mut OpenSpace);
        let bar = Obstacle::build(
            ObstacleShape::Box { center: DVec2::new(0.3, 0.0), width: 0.1, height: 1.2, yaw: 0.0 },
            1.5,
            1.6,
        )
        .unwrap();
        let far =
            Obstacle::build(ObstacleShape::Cylinder { center: DVec2::new(0.0, 3.0), radius: 0.2 }, 1.5, 1.6).unwrap();
        let side = upper_strip_pose(&body, [&bar, &far], StripView::Side, "s".into());
        let front = upper_strip_pose(&body, [&bar, &far], StripView::Front, "f".into());
        // The bar only (the cylinder lies outside the slice), its depth across the side view
        // and its length across the front one.
        assert_eq!((side.boxes.len(), front.boxes.len()), (1, 1));
        let (lo, hi) = side.boxes[0];
        assert!((lo.x - 0.25).abs() < 0.05 && (hi.x - 0.35).abs() < 0.05 && lo.y == 1.5 && hi.y == 1.6, "{lo} {hi}");
        let (lo, hi) = front.boxes[0];
        assert!((lo.x + 0.6).abs() < 0.05 && (hi.x - 0.6).abs() < 0.05, "{lo} {hi}");
        // Seen from ahead the shoulders lie across the picture; from the side, one behind the other.
        let across = |p: &StripPose| {
            let xs: Vec<f64> = p.joints.iter().map(|v| v.x).collect();
            xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - xs.iter().cloned().fold(f64::INFINITY, f64::min)
        };
        assert!(across(&front) > 0.3 && across(&side) < across(&front), "{} {}", across(&side), across(&front));
    }
}

/// Most moments in an upper-body strip.
const UPPER_POSES: usize = 12;

/// Offsets (radians) from which a moment counts as the upper body moving for obstacles in the
/// upper-body strips.
const UPPER_MOVED_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;

/// Leg poses per step in the side view.
const SIDE_POSES_PER_STEP: usize = 4;

/// Seconds between the moments an upper-body strip may show.
const UPPER_EVERY_S: f64 = 0.25;

/// The side views of the first agent's episode (the digital-actor paper's Fig 6, Fig 8 and
/// Fig 9), gathered as the simulation runs: on a map with terrain, every step the character
/// took ([`SideRecorder`]); among obstacles its upper body can touch, the moments it bent,
/// twisted or moved its arms for them, seen from its left and from ahead. `strider render
/// --side/--front` writes them, `strider snapshot --side` pins them.
#[derive(Debug, Clone)]
pub struct SideViews {
    legs: Option<SideRecorder>,
    upper: Option<Vec<(StripPose, StripPose)>>,
    per_pose: usize,
}

/// A picture of the side views: its file name and pixels.
pub type SidePicture = (&'static str, tiny_skia::Pixmap);

impl SideViews {
    /// The side views `sim` (about to run) has to show: the legs on a map with terrain, the
    /// upper body on one with obstacles it can touch.
    pub fn new(sim: &Simulation) -> SideViews {
        SideViews {
            legs: (!sim.world.terrain.is_flat()).then(SideRecorder::default),
            upper: sim.world.upper_body_matters().then(Vec::new),
            per_pose: (UPPER_EVERY_S / sim.params.dt_s).round().max(1.0) as usize,
        }
    }

    /// Whether the map has anything to show from the side.
    pub fn any(&self) -> bool {
        self.legs.is_some() || self.upper.is_some()
    }

    /// Looks at `sim` before its step `step`: the upper body, every [`UPPER_EVERY_S`].
    pub fn before_step(&mut self, sim: &Simulation, step: usize) {
        let (Some(upper), Some(b)) = (&mut self.upper, sim.agents.first().and_then(|a| a.body.animated())) else {
            return;
        };
        if !step.is_multiple_of(self.per_pose) {
            return;
        }
        let c = b.upper_offsets();
        if c.waist.iter().chain(c.arms.iter().flatten()).any(|x| x.abs() > UPPER_MOVED_RAD) {
            // Time, waist bend and twist in degrees.
            let caption =
                format!("{:.2} s b{:.0} t{:+.0}", sim.time_s, c.waist[0].to_degrees(), c.waist[1].to_degrees());
            let solids: Vec<_> = sim.world.solids().collect();
            let pose = |view| upper_strip_pose(b, solids.iter().copied(), view, caption.clone());
            upper.push((pose(StripView::Side), pose(StripView::Front)));
        }
    }

    /// Looks at `sim` after a step: the step the legs play, if it is a new one.
    pub fn after_step(&mut self, sim: &Simulation) {
        if let (Some(legs), Some(f)) =
            (&mut self.legs, sim.agents.first().and_then(|a| a.body.animated()).and_then(|b| b.footing()))
        {
            legs.observe(f);
        }
    }

    /// The upper body kept the database's motion all the way (there is a strip to draw only
    /// when it did not).
    pub fn upper_unmoved(&self) -> bool {
        self.upper.as_ref().is_some_and(Vec::is_empty)
    }

    /// The pictures of the episode `name` of `sim` (run to its end): `side.png` (the legs'
    /// side view) and `upper_side.png` (the upper body from its left) when `side` is asked,
    /// `upper_front.png` (from ahead) when `front` is, each where the map has it to show.
    pub fn pictures(&self, sim: &Simulation, name: &str, side: bool, front: bool) -> Vec<SidePicture> {
        let mut out = Vec::new();
        if let (true, Some(legs)) = (side, &self.legs) {
            let foot = sim.agents.first().and_then(|a| a.body.animated()).and_then(|b| b.footing());
            let mut view = legs.view(foot.map_or(0.0, |f| f.params().leg.foot_length_m()), SIDE_POSES_PER_STEP);
            view.caption = Some(format!("{name}: {} steps, side view", legs.len()));
            out.push(("side.png", super::side_view::render_side_view(&view).0));
        }
        let Some(upper) = self.upper.as_ref().filter(|u| !u.is_empty()) else { return out };
        // At most a dozen moments, evenly spread over those recorded.
        let n = upper.len();
        let picked: Vec<&(StripPose, StripPose)> =
            (0..n.min(UPPER_POSES)).map(|k| &upper[k * n / n.min(UPPER_POSES)]).collect();
        for (wanted, file, from_left) in [(side, "upper_side.png", true), (front, "upper_front.png", false)] {
            if !wanted {
                continue;
            }
            let poses: Vec<StripPose> =
                picked.iter().map(|p| if from_left { p.0.clone() } else { p.1.clone() }).collect();
            let mut painter = super::png::PngPainter::new(160 * poses.len() as u32, 360);
            super::poses::draw_strip(&poses, &mut painter);
            out.push((file, painter.into_pixmap()));
        }
        out
    }
}
