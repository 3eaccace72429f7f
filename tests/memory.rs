//! The memory invariant of ARCHITECTURE.md: an agent's memory holds only what its own scans of
//! the world's obstacles showed it (never other agents), forgets nothing, and the same scans in
//! the same order give the same path, bit for bit.

use glam::DVec2;
use strider::scenario::Scenario;
use strider::sim::{LayeredController, Simulation, StepParameters};
use strider::world::{Obstacle, ObstacleShape, Pose, Task};

fn controller() -> LayeredController {
    strider::builtin::controller().expect("built-in rules")
}

fn task(from: (f64, f64), yaw: f64, to: (f64, f64)) -> Task {
    Task::new(Pose { position: DVec2::new(from.0, from.1), yaw }, DVec2::new(to.0, to.1))
}

/// Runs the tasks together in `scenario`'s world; returns the known cells of every agent after
/// every step and the agents' memory paths at the end.
fn run(scenario: &Scenario, tasks: &[Task]) -> (Vec<Vec<usize>>, Vec<Vec<DVec2>>) {
    let mut sim = Simulation::new(scenario.world(), StepParameters::default());
    let c = controller();
    for t in tasks {
        sim.add_agent(*t, &c);
    }
    let mut known = Vec::new();
    for _ in 0..600 {
        if sim.all_done() {
            break;
        }
        sim.step();
        known.push(sim.agents.iter().map(|a| a.memory.known()).collect());
    }
    (known, sim.agents.iter().map(|a| a.memory.path().to_vec()).collect())
}

#[test]
fn other_agents_never_enter_the_memory() {
    // Two agents walking head-on across open ground see each other, and remember nothing.
    let s = Scenario::new("open");
    let (known, _) =
        run(&s, &[task((0.0, 0.0), 0.0, (10.0, 0.0)), task((10.0, 0.05), std::f64::consts::PI, (0.0, 0.0))]);
    assert!(known.len() > 20);
    assert!(known.iter().flatten().all(|&k| k == 0), "an agent remembered another");
}

#[test]
fn the_memory_forgets_nothing_and_is_the_same_for_the_same_scans() {
    let mut s = Scenario::new("wall");
    s.obstacles.push(
        Obstacle::build(
            ObstacleShape::Box { center: DVec2::new(5.0, 0.5), width: 0.3, height: 4.0, yaw: 0.0 },
            0.0,
            2.0,
        )
        .unwrap(),
    );
    let tasks = [task((0.0, 0.0), 0.0, (10.0, 0.0)), task((0.0, 3.5), 0.0, (10.0, 3.5))];
    let (known, paths) = run(&s, &tasks);
    assert!(known.last().unwrap()[0] > 0, "the wall was seen");
    for w in known.windows(2) {
        for (a, b) in w[0].iter().zip(&w[1]) {
            assert!(b >= a, "the memory forgot: {a} cells, then {b}");
        }
    }
    assert_eq!(run(&s, &tasks).1, paths, "the same scans gave another path");
}
