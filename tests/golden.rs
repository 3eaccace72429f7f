//! Golden-image tests for the top-down scene renderer (seed 000 Fig 2-style views).
//!
//! Each test renders a [`Scene`] with [`render_png`] — the same `draw_scene` routine the
//! terminal UI uses — and compares it with `tests/golden/{name}.png` through
//! [`snapshot::check_image`], the comparison behind `strider snapshot`. A pixel counts as
//! equal when every channel differs by at most 8; a test fails when more than 0.1 % of the
//! pixels differ, writing the actual image and a diff image (differing pixels red over a faded
//! copy) to `target/golden-failures/`.
//!
//! Regenerate the golden files with `UPDATE_GOLDEN=1 cargo test --test golden` (or
//! `STRIDER_UPDATE_GOLDEN=1`), then look at them before committing.

use std::path::{Path, PathBuf};

use glam::DVec2;
use strider::geom::Aabb;
use strider::render::png::render_png;
use strider::render::scene::{AgentView, Scene, Verdict};
use strider::render::side_view::SideTransform;
use strider::snapshot::{self, Tolerance};
use strider::world::{Obstacle, ObstacleShape, SectorLayout, Sensed, World};
use tiny_skia::Pixmap;

/// Pixels may differ by 8 per channel; at most 0.1 % of them may differ more.
const TOLERANCE: Tolerance = Tolerance { channel: 8, changed_share: 0.001 };

fn golden_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests").join("golden").join(format!("{name}.png"))
}

fn failure_dir() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("target"));
    target.join("golden-failures")
}

/// Compares `actual` with `tests/golden/{name}.png`, or rewrites the golden file when
/// `UPDATE_GOLDEN=1` or `STRIDER_UPDATE_GOLDEN=1` is set. Panics with the paths of the written
/// actual and diff images on a mismatch.
fn assert_matches_golden(name: &str, actual: &Pixmap) {
    let path = golden_path(name);
    if std::env::var("UPDATE_GOLDEN").is_ok_and(|v| v == "1") || snapshot::update_requested() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        snapshot::write_png(&path, actual).unwrap();
        return;
    }
    if !path.exists() {
        panic!(
            "golden file {} is missing; run `UPDATE_GOLDEN=1 cargo test --test golden` and look at the result",
            path.display()
        );
    }
    let dir = failure_dir();
    std::fs::create_dir_all(&dir).unwrap();
    let result = snapshot::check_image(&path, actual, &TOLERANCE, &dir).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(
        result.matches(),
        "{name}: rendering does not match {}:\n  {result}\n  \
         (if the change is intended: UPDATE_GOLDEN=1 cargo test --test golden)",
        path.display()
    );
}

fn obstacle(shape: ObstacleShape) -> Obstacle {
    Obstacle::build(shape, 0.0, 2.0).unwrap()
}

/// A yawed box, a cylinder and a non-convex L-shaped polygon.
fn demo_world() -> World {
    World::new(vec![
        obstacle(ObstacleShape::Box { center: DVec2::new(4.5, 3.2), width: 2.0, height: 1.0, yaw: 0.5 }),
        obstacle(ObstacleShape::Cylinder { center: DVec2::new(7.0, -0.6), radius: 0.7 }),
        obstacle(ObstacleShape::Polygon {
            outline: vec![
                DVec2::new(1.5, -4.0),
                DVec2::new(5.0, -4.0),
                DVec2::new(5.0, -3.0),
                DVec2::new(2.5, -3.0),
                DVec2::new(2.5, -0.8),
                DVec2::new(1.5, -0.8),
            ],
        }),
    ])
}

/// One agent walking from the lower left along a curve, with footprints on alternating
/// sides and three sensor sectors computed from the world.
fn demo_scene(world: &World) -> Scene<'_> {
    let goal = DVec2::new(9.0, 1.5);
    let trail: Vec<DVec2> = (0..=40)
        .map(|i| {
            let t = f64::from(i) / 40.0;
            DVec2::new(-1.0 + 4.5 * t, -1.0 + 1.6 * (t * std::f64::consts::PI * 0.9).sin())
        })
        .collect();
    let position = *trail.last().unwrap();
    let before = trail[trail.len() - 2];
    let yaw = (position - before).to_angle();
    let mut footprints = Vec::new();
    for (k, w) in trail.windows(2).enumerate().step_by(4) {
        let dir = (w[1] - w[0]).normalize();
        let side = if (k / 4).is_multiple_of(2) { 1.0 } else { -1.0 };
        footprints.push((w[0] + dir.perp() * 0.11 * side, dir.to_angle()));
    }
    let layout = SectorLayout::three();
    let mut sensed = Sensed::default();
    let radius = 0.3;
    world.sense(position, yaw, radius, goal, &layout, &[], &mut Vec::new(), &mut sensed);
    Scene {
        world,
        agents: vec![AgentView {
            position,
            yaw,
            radius,
            trail,
            sectors: Some((layout.edges.clone(), sensed.sectors.clone(), layout.range)),
            footprints,
            walks: true,
            start: Some(DVec2::new(-1.0, -1.0)),
            label: Some("agent 1".into()),
        }],
        goals: vec![(goal, 0.5)],
        view: None,
        caption: Some("box, cylinder, L-shape, 3 sectors".into()),
        outcome: Some(Verdict { text: "timed out 1.20 m from the goal".into(), success: false }),
        legend: true,
    }
}

#[test]
fn scene_with_obstacles_and_agent() {
    let world = demo_world();
    assert_matches_golden("scene_640x480", &render_png(&demo_scene(&world), 640, 480));
}

#[test]
fn same_scene_other_size() {
    let world = demo_world();
    assert_matches_golden("scene_300x400", &render_png(&demo_scene(&world), 300, 400));
}

#[test]
fn empty_world_one_agent() {
    let world = World::new(Vec::new());
    let scene = Scene {
        world: &world,
        agents: vec![AgentView {
            position: DVec2::new(0.5, 0.0),
            yaw: 1.0,
            radius: 0.3,
            trail: vec![DVec2::new(-1.5, -1.0), DVec2::new(-0.5, -0.8), DVec2::new(0.5, 0.0)],
            sectors: None,
            footprints: vec![],
            walks: false,
            start: None,
            label: None,
        }],
        goals: vec![],
        view: Some(Aabb::new(DVec2::new(-3.0, -2.0), DVec2::new(3.0, 2.0))),
        caption: None,
        outcome: None,
        legend: false,
    };
    assert_matches_golden("empty_world", &render_png(&scene, 320, 240));
}

/// A whole navigation episode (the U-shaped trap), final frame: pins the planner's behaviour.
#[test]
fn u_trap_episode_final_frame() {
    use strider::render::sim_view::scene_of;
    use strider::script::{Limits, ScriptLog, load_scenario};
    use strider::sim::{Simulation, StepParameters};
    let log = ScriptLog::new();
    let scenario =
        load_scenario(include_str!("../maps/u_trap.rhai"), "maps/u_trap.rhai", Limits::default(), &log).unwrap();
    let controller = strider::builtin::controller().unwrap();
    let mut sim = Simulation::new(scenario.world(), StepParameters::default());
    sim.add_agent(scenario.tasks[0], &controller);
    while !sim.all_done() {
        sim.step();
    }
    let pixmap = strider::render::png::render_png(&scene_of(&sim, Some("u_trap".into())), 480, 360);
    assert_matches_golden("u_trap_final", &pixmap);
}

/// An animated character crossing the sparse map: footprints on the trajectory, and the side
/// view of its first poses.
#[test]
fn animated_character_footprints_and_poses() {
    use std::sync::Arc;
    use strider::builtin;
    use strider::render::png::PngPainter;
    use strider::render::poses::draw_strip;
    use strider::render::sim_view::{scene_of, strip_pose_of};
    use strider::script::{Limits, ScriptLog, load_scenario};
    use strider::sim::{AnimationHandle, Simulation, StepParameters};

    let log = ScriptLog::new();
    let scenario = load_scenario(include_str!("../maps/sparse.rhai"), "sparse.rhai", Limits::default(), &log).unwrap();
    let controller = builtin::controller().unwrap();
    let animation = AnimationHandle(Arc::new(builtin::animation().unwrap()));
    let params = StepParameters { animation: Some(animation), ..StepParameters::default() };
    let mut sim = Simulation::new(scenario.world(), params);
    sim.add_agent(scenario.tasks[0], &controller);
    let mut strip = Vec::new();
    for step in 0..400 {
        if step >= 40 && step % 5 == 0 && strip.len() < 8 {
            strip.push(strip_pose_of(sim.agents[0].body.animated().unwrap(), format!("{step}")));
        }
        sim.step();
    }
    assert!(!sim.agents[0].body.animated().unwrap().player().footprints.is_empty());
    assert_matches_golden("animated_sparse", &render_png(&scene_of(&sim, Some("animated".into())), 480, 480));
    let mut painter = PngPainter::new(800, 240);
    draw_strip(&strip, &mut painter);
    assert_matches_golden("animated_poses", painter.pixmap());
}

/// The side view of a walk over `maps/profiles/fig8_trap.profile`, with the planner on or off.
fn fig8_side_view(mode: strider::footstep::PlannerMode) -> (strider::footstep::Walk, Pixmap, SideTransform) {
    use strider::footstep::{FootstepParams, walk};
    use strider::render::side_view::{SideView, render_side_view};
    let course =
        strider::ground::parse(include_str!("../maps/profiles/fig8_trap.profile"), "fig8_trap.profile").unwrap();
    let params = FootstepParams::default();
    let w = walk(&course, params, mode).unwrap();
    let mut view = SideView::of_walk(course.ground.pieces(), &w.footholds, &w.steps, 4);
    view.foot_length_m = params.leg.foot_length_m();
    view.goal_m = Some(course.goal_m);
    view.stopped = !w.reached();
    view.caption = Some(format!("fig8 trap: {mode:?}"));
    let (pixmap, t) = render_side_view(&view);
    (w, pixmap, t)
}

/// Pixels in the columns of profile X range `[x0, x1]`, above the ground line, of one of the
/// leg colours.
fn foot_coloured_pixels(pm: &Pixmap, t: &SideTransform, x0: f64, x1: f64) -> usize {
    use strider::render::side_view::{LEFT, RIGHT};
    let (c0, c1) = (t.to_pixel(DVec2::new(x0, 0.0)).x as u32, t.to_pixel(DVec2::new(x1, 0.0)).x as u32);
    let mut n = 0;
    for x in c0..c1.min(pm.width()) {
        for y in 0..pm.height() {
            let c = pm.pixel(x, y).unwrap().demultiply();
            if [LEFT, RIGHT].iter().any(|k| (c.red(), c.green(), c.blue()) == (k.r, k.g, k.b)) {
                n += 1;
            }
        }
    }
    n
}

#[test]
fn side_view_of_the_fig8_trap_shows_both_outcomes() {
    use strider::footstep::PlannerMode;
    // Fig 8 (a): the nominal step walks into the trap and stops before the gap (3.0–3.6 m).
    let (off, off_png, off_t) = fig8_side_view(PlannerMode::Nominal);
    assert!(!off.reached());
    assert!(off.footholds.iter().all(|f| f.sole.x_m < 3.0));
    assert_eq!(foot_coloured_pixels(&off_png, &off_t, 3.6, 6.5), 0, "nothing drawn beyond the gap");
    assert!(foot_coloured_pixels(&off_png, &off_t, 0.0, 3.0) > 200);
    // The stop is marked with a vermillion cross over the last foothold.
    let last = off.footholds.last().unwrap().sole;
    let cross = off_t.to_pixel(DVec2::new(last.x_m + 0.12, last.z_m + 0.25));
    let c = off_png.pixel(cross.x as u32, cross.y as u32).unwrap().demultiply();
    assert_eq!((c.red(), c.green(), c.blue()), (213, 94, 0));
    // Fig 8 (b): the planner shortens the steps before the gap and crosses it.
    let (on, on_png, on_t) = fig8_side_view(PlannerMode::Window);
    assert!(on.reached());
    assert!(on.footholds.iter().any(|f| f.sole.x_m > 3.6));
    assert!(foot_coloured_pixels(&on_png, &on_t, 3.6, 6.5) > 200, "footholds and legs beyond the gap");
    assert_matches_golden("side_fig8_planner_off", &off_png);
    assert_matches_golden("side_fig8_planner_on", &on_png);
}
