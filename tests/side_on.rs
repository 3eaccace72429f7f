//! Side-on passage (issue 26): the character, standing in front of a slot narrower than its
//! shoulders in a full-height wall, pivots side-on, side-steps through and pivots back — with
//! no 2-D collision of the body's real extent and no bone of the played motion inside a wall,
//! checked by forward kinematics with this test's own geometry.

use std::sync::Arc;

use glam::{DVec2, DVec3};
use strider::maps::text;
use strider::sim::side_on::{Gap, Phase};
use strider::sim::{AnimationHandle, Body, Simulation, StepParameters};

/// A room split at x = 0 by a wall 0.2 m thick whose only opening is a slot `width` wide
/// centred on y = 0; the character stands at `start` facing `yaw`.
fn slot_world(width: f64, start: DVec2, yaw: f64) -> (String, Vec<(DVec2, DVec2)>) {
    let len = 3.0 - width / 2.0;
    let c = width / 2.0 + len / 2.0;
    let walls = vec![
        (DVec2::new(0.0, c), DVec2::new(0.2, len)),
        (DVec2::new(0.0, -c), DVec2::new(0.2, len)),
        (DVec2::new(0.0, 3.1), DVec2::new(8.4, 0.2)),
        (DVec2::new(0.0, -3.1), DVec2::new(8.4, 0.2)),
        (DVec2::new(-4.1, 0.0), DVec2::new(0.2, 6.4)),
        (DVec2::new(4.1, 0.0), DVec2::new(0.2, 6.4)),
    ];
    let mut t = format!("start {} {} {yaw}\ngoal 3 0\n", start.x, start.y);
    for (c, s) in &walls {
        t += &format!("box {} {} {} {}\n", c.x, c.y, s.x, s.y);
    }
    (t, walls)
}

/// A point more than a millimetre inside one of the walls (full height).
fn inside(walls: &[(DVec2, DVec2)], p: DVec3) -> bool {
    walls.iter().any(|(c, s)| (p.x - c.x).abs() < s.x / 2.0 - 1e-3 && (p.y - c.y).abs() < s.y / 2.0 - 1e-3)
}

/// The first frame, bone and point (1 cm apart along every bone of every frame played) more
/// than a millimetre inside one of the walls.
fn bone_inside(body: &strider::sim::AnimatedBody, walls: &[(DVec2, DVec2)]) -> Option<(usize, String, DVec3)> {
    let sk = &body.animation().db.skeleton;
    let mut g = Vec::new();
    for (k, pose) in body.motion().unwrap().iter().enumerate() {
        sk.globals(pose, &mut g);
        for (i, j) in sk.joints().iter().enumerate() {
            let mut ends = Vec::new();
            if let Some(p) = j.parent {
                ends.push((g[p].0, g[i].0));
            }
            if j.end_site.is_some() {
                ends.push((g[i].0, sk.tip(&g, i)));
            }
            for (p, q) in ends {
                let n = ((p.distance(q) / 0.01).ceil() as usize).max(1);
                for s in 0..=n {
                    let x = p.lerp(q, s as f64 / n as f64);
                    if inside(walls, x) {
                        return Some((k, j.name.clone(), x));
                    }
                }
            }
        }
    }
    None
}

#[test]
fn the_character_passes_slots_narrower_than_its_shoulders_side_on() {
    let anim = AnimationHandle(Arc::new(strider::builtin::animation().unwrap()));
    let controller = strider::builtin::controller().unwrap();
    let mut bad = Vec::new();
    for width in [0.46, 0.50, 0.55, 0.60] {
        for (start, yaw) in
            [(DVec2::new(-0.6, 0.0), 0.0), (DVec2::new(-0.65, 0.08), -0.35), (DVec2::new(-0.6, -0.06), 0.3)]
        {
            let (world, walls) = slot_world(width, start, yaw);
            let scenario = text::parse(&world, "slot.txt").unwrap();
            let params = StepParameters { animation: Some(anim.clone()), record_motion: true, ..Default::default() };
            let mut sim = Simulation::new(scenario.world(), params);
            sim.add_agent(scenario.tasks[0], &controller);
            let gap = Gap { centre: DVec2::ZERO, through: DVec2::X, width };
            sim.agents[0].body.animated_mut().unwrap().pass_side_on(gap);
            let mut steps = 0;
            while steps < 1200 && sim.agents[0].body.animated().unwrap().side_on().is_some_and(|m| m.active()) {
                sim.step();
                steps += 1;
            }
            let a = &sim.agents[0];
            let body = a.body.animated().unwrap();
            let phase = body.side_on_phase();
            let at = a.body.pose().position;
            let bone_in = bone_inside(body, &walls);
            let motion = body.motion().unwrap();
            eprintln!(
                "slot {width} from {start} at {yaw}: {phase:?} in {:.1} s at ({:.2}, {:.2}), collisions {}, \
                 {} frames, bone inside {bone_in:?}",
                a.metrics.time_s,
                at.x,
                at.y,
                a.metrics.collisions,
                motion.len()
            );
            if phase != Some(Phase::Done) || at.x < 0.35 || a.metrics.collisions != 0 || bone_in.is_some() {
                bad.push(format!(
                    "slot {width} from {start}: {phase:?} at {at}, collisions {}, bone {bone_in:?}",
                    a.metrics.collisions
                ));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// A room split at x = 0 by a full-height wall `depth` thick whose only opening is a slot
/// `width` wide centred on y = `cy`, with the character at `start` facing `yaw` and the goal at
/// `goal` on the other side.
fn walled_slot(width: f64, depth: f64, cy: f64, start: DVec2, yaw: f64, goal: DVec2) -> (String, Vec<(DVec2, DVec2)>) {
    let (above, below) = (3.0 - (cy + width / 2.0), (cy - width / 2.0) + 3.0);
    let walls = vec![
        (DVec2::new(0.0, 3.0 - above / 2.0), DVec2::new(depth, above)),
        (DVec2::new(0.0, -3.0 + below / 2.0), DVec2::new(depth, below)),
        (DVec2::new(0.0, 3.1), DVec2::new(8.4, 0.2)),
        (DVec2::new(0.0, -3.1), DVec2::new(8.4, 0.2)),
        (DVec2::new(-4.1, 0.0), DVec2::new(0.2, 6.4)),
        (DVec2::new(4.1, 0.0), DVec2::new(0.2, 6.4)),
    ];
    let mut t = format!("start {} {} {yaw}\ngoal {} {}\n", start.x, start.y, goal.x, goal.y);
    for (c, s) in &walls {
        t += &format!("box {} {} {} {}\n", c.x, c.y, s.x, s.y);
    }
    (t, walls)
}

/// Navigation alone takes the character through slots 0.46–0.60 m wide: its memory keeps
/// such a slot open to its side-on stance, and it turns side-on in front of it, side-steps
/// through and walks on — every goal reached, no collision, no bone inside a wall.
#[test]
fn navigation_takes_the_character_side_on_through_slots_narrower_than_its_shoulders() {
    let anim = AnimationHandle(Arc::new(strider::builtin::animation().unwrap()));
    let controller = strider::builtin::controller().unwrap();
    let mut bad = Vec::new();
    let cases = [
        (0.46, 0.2, 0.0, DVec2::new(-3.0, 0.0), 0.0, DVec2::new(3.0, 0.0)),
        (0.50, 0.15, 0.8, DVec2::new(-3.0, -1.5), 0.6, DVec2::new(3.0, 1.5)),
        (0.55, 0.25, -1.0, DVec2::new(-2.5, 1.8), -1.2, DVec2::new(2.5, -2.0)),
        (0.60, 0.1, 0.4, DVec2::new(-3.2, 2.2), 3.0, DVec2::new(3.0, -0.5)),
        // Stopped where the smallest pivot overshoots the facing wanted either way.
        (0.478, 0.148, -1.49, DVec2::new(-2.44, -1.23), 2.89, DVec2::new(1.83, 2.19)),
    ];
    for (width, depth, cy, start, yaw, goal) in cases {
        let (world, walls) = walled_slot(width, depth, cy, start, yaw, goal);
        let scenario = text::parse(&world, "slot.txt").unwrap();
        let params = StepParameters { animation: Some(anim.clone()), record_motion: true, ..Default::default() };
        let mut sim = Simulation::new(scenario.world(), params);
        sim.add_agent(scenario.tasks[0], &controller);
        while !sim.all_done() {
            sim.step();
        }
        let a = &sim.agents[0];
        let body = a.body.animated().unwrap();
        let bone_in = bone_inside(body, &walls);
        eprintln!(
            "slot {width} ({depth} deep at y {cy}): {:?} in {:.1} s, collisions {}, bone inside {bone_in:?}",
            a.outcome, a.metrics.time_s, a.metrics.collisions
        );
        if a.outcome != Some(strider::sim::Outcome::Reached) || a.metrics.collisions != 0 || bone_in.is_some() {
            bad.push(format!(
                "slot {width} at y {cy}: {:?}, collisions {}, bone {bone_in:?}",
                a.outcome, a.metrics.collisions
            ));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// A field of posts with no way through for the character: the side-on passages it tries
/// between them find no step to take, and each gives up instead of handing its phases round for
/// ever — the episode ends (timed out, no collision). The episode runs on a thread so that a
/// manoeuvre that never hands back fails the test rather than hanging it.
#[test]
fn a_side_on_passage_with_no_step_to_take_gives_up() {
    let text = include_str!("fixtures/maps/side_on_posts.txt");
    let (done_tx, done) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let anim = AnimationHandle(Arc::new(strider::builtin::animation().unwrap()));
        let controller = strider::builtin::controller().unwrap();
        let scenario = text::parse(text, "side_on_posts.txt").unwrap();
        let params = StepParameters { animation: Some(anim), ..Default::default() };
        let mut sim = Simulation::new(scenario.world(), params);
        sim.add_agent(scenario.tasks[0], &controller);
        let mut side_on = false;
        while !sim.all_done() {
            sim.step();
            side_on |= sim.agents[0].body.animated().is_some_and(|b| b.side_on().is_some());
        }
        let a = &sim.agents[0];
        let _ = done_tx.send((a.outcome, a.metrics.collisions, side_on));
    });
    let (outcome, collisions, side_on) =
        done.recv_timeout(std::time::Duration::from_secs(120)).expect("the episode never ended");
    assert!(side_on, "no side-on passage was tried");
    assert_eq!(outcome, Some(strider::sim::Outcome::TimedOut));
    assert_eq!(collisions, 0);
}
