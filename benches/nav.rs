//! Navigation step throughput (issue bar: ≥ 300,000 agent-steps per second on one core for
//! sensing + fuzzy control on the cluttered map `maps/cluttered.rhai`).

use divan::{Bencher, black_box};
use strider::scenario::Scenario;
use strider::script::{Limits, ScriptLog, load_scenario};
use strider::sim::{LayeredController, Simulation, StepParameters};

fn main() {
    divan::main();
}

fn setup() -> (Scenario, LayeredController) {
    let log = ScriptLog::new();
    let scenario =
        load_scenario(include_str!("../maps/cluttered.rhai"), "maps/cluttered.rhai", Limits::default(), &log)
            .expect("cluttered map");
    (scenario, strider::builtin::controller().expect("built-in rules"))
}

/// One agent-step: sensing, the all-around scan (amortised), fuzzy control and the move.
/// Time per iteration; 3.3 µs = 300,000 agent-steps per second.
#[divan::bench]
fn agent_step_cluttered(bencher: Bencher) {
    let (scenario, controller) = setup();
    let mut sim = Simulation::new(scenario.world(), StepParameters::default());
    sim.add_agent(scenario.tasks[0], &controller);
    let fresh = sim.clone();
    bencher.bench_local(|| {
        if sim.all_done() {
            sim = fresh.clone();
        }
        sim.step();
        black_box(sim.time_s)
    });
}

/// Sensing and fuzzy control alone (no scan, no move), the controller's inner loop.
#[divan::bench]
fn sense_and_control_cluttered(bencher: Bencher) {
    let (scenario, mut controller) = setup();
    let world = scenario.world();
    let task = scenario.tasks[0];
    let params = StepParameters::default();
    let mut scratch = Vec::new();
    let mut sensed = strider::world::Sensed::default();
    let mut t = 0.0;
    let body = strider::sim::KinematicDisc::new(task.start, params.limits);
    bencher.bench_local(|| {
        let p = task.start.position + glam::DVec2::new(3.0 * (t * 0.1f64).sin(), 3.0 * (t * 0.13f64).cos());
        world.sense(p, t * 0.2, 0.3, task.goal, &params.layout, &[], &mut scratch, &mut sensed);
        let c = controller.command(&sensed, || false, t, &body);
        t += 0.05;
        black_box(c)
    });
}
