//! Narrow gaps (issue 26): a disc whose remembered way goes through a gap barely wider than
//! itself commits to it — it goes through without turning one way and the other in front of
//! it — however the memory's grid falls across the gap.

use glam::DVec2;
use strider::maps::text;
use strider::sim::{Body, Simulation, StepParameters};

/// A room split by a row of touching posts (0.075 m, as in the BARN worlds) with one gap of
/// `gap` metres centred on `x0`: the only way from the start below the row to the goal above.
fn gap_world(gap: f64, x0: f64, start_x: f64) -> String {
    let mut w = format!("start {} -2.5 1.5708\ngoal {x0} 3\n", x0 + start_x);
    let first = gap / 2.0 + 0.075;
    for k in 0..18 {
        for side in [-1.0, 1.0] {
            w += &format!("cyl {} 0 0.075\n", x0 + side * (first + 0.15 * k as f64));
        }
    }
    for (cx, cy, bw, bh) in [(-3.3, 0.0, 0.2, 8.4), (3.3, 0.0, 0.2, 8.4), (0.0, -4.1, 6.8, 0.2), (0.0, 4.1, 6.8, 0.2)] {
        w += &format!("box {} {cy} {bw} {bh}\n", x0 + cx);
    }
    w
}

/// Runs the disc through the world; returns whether it reached the goal, the steps taken, the
/// collisions, and how often the turn it was commanded changed side (beyond 10°/s) within
/// 1.5 m of the gap.
fn run(world: &str) -> (bool, u32, u32, usize) {
    let scenario = text::parse(world, "gap.txt").unwrap();
    let gap = DVec2::new(scenario.tasks[0].goal.x, 0.0);
    let mut sim = Simulation::new(scenario.world(), StepParameters::default());
    sim.add_agent(scenario.tasks[0], &strider::builtin::controller().unwrap());
    let (mut side, mut flips) = (0.0f64, 0);
    while !sim.all_done() {
        sim.step();
        let a = &sim.agents[0];
        let turn = a.command.turn_rate;
        if a.body.pose().position.distance(gap) < 1.5 && turn.abs() > 10f64.to_radians() {
            if side != 0.0 && turn.signum() != side {
                flips += 1;
            }
            side = turn.signum();
        }
    }
    let a = &sim.agents[0];
    (a.outcome == Some(strider::sim::Outcome::Reached), a.metrics.steps, a.metrics.collisions, flips)
}

#[test]
fn the_disc_commits_to_a_gap_barely_wider_than_itself() {
    // A 0.7 m gap for the 0.6 m disc, approached from either side at an angle, with the grid of
    // the memory falling differently across it each time: through in well under 10 s (the way
    // is 6 m), with no collision and no turning back and forth in front of it.
    let mut bad = Vec::new();
    for x0 in [0.0, 0.03, 0.06, 0.09] {
        for start_x in [1.2, -1.2] {
            let (reached, steps, collisions, flips) = run(&gap_world(0.7, x0, start_x));
            if !(reached && collisions == 0 && steps <= 200 && flips <= 4) {
                bad.push(format!(
                    "gap at x = {x0}, start {start_x} beside it: reached {reached}, {steps} steps, \
                     {collisions} collisions, the turn changed side {flips} times in front of the gap"
                ));
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}
