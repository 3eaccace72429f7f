//! Frame cost of the live terminal view (issue bar: ≥ 60 frames per second with 100 agents on
//! a 200×60 terminal including their simulation, i.e. at most 16.7 ms for a frame and a
//! simulation step). One frame is the whole screen: the world drawn by `draw_scene` into the
//! terminal canvas, every panel, and ratatui's diff into a `TestBackend`. The simulation step
//! is of all 100 agents, discs or animated characters (the live view steps the simulation at
//! most once per frame: 20 steps a second at real time).

use std::sync::Arc;

use divan::Bencher;
use glam::DVec2;
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use strider::maps::generate::{Density, random_world};
use strider::sim::AnimationHandle;
use strider::tui::{App, Config, MapSpec, ui};
use strider::world::{Pose, Task};

fn main() {
    divan::main();
}

/// A semi-cluttered random world with `n` agents on a grid of free start points, all heading
/// for the world's goal, after two seconds of simulation (trails and sensors filled in).
fn app_with_agents(n: usize, animation: Option<AnimationHandle>) -> App {
    let controller = strider::builtin::controller().expect("built-in rules");
    let mut scenario = random_world(Density::Semi, 7);
    let goal = scenario.tasks[0].goal;
    let world = scenario.world();
    let bounds = world.bounds().expect("obstacles");
    let mut scratch = Vec::new();
    let mut tasks = Vec::new();
    let (mut x, mut y) = (bounds.min.x + 0.5, bounds.min.y + 0.5);
    while tasks.len() < n && y < bounds.max.y {
        let p = DVec2::new(x, y);
        if world.is_free(p, scenario.agent_radius + 0.2, &mut scratch) && p.distance(goal) > 2.0 {
            tasks.push(Task::new(Pose { position: p, yaw: 0.0 }, goal));
        }
        x += 1.0;
        if x > bounds.max.x {
            x = bounds.min.x + 0.5;
            y += 1.0;
        }
    }
    assert_eq!(tasks.len(), n, "not enough free start points");
    scenario.tasks = tasks;
    let mut app = App::new(
        Config { map: MapSpec::Random(Density::Semi.into()), rules: None, seed: 7, animation },
        scenario,
        controller,
    );
    for _ in 0..40 {
        app.sim.step();
    }
    app
}

/// One full frame with 100 agents on 200×60 cells; 33 ms = 30 frames per second.
#[divan::bench]
fn frame_100_agents_200x60(bencher: Bencher) {
    let mut app = app_with_agents(100, None);
    let mut terminal = Terminal::new(TestBackend::new(200, 60)).expect("test terminal");
    bencher.bench_local(|| {
        terminal.draw(|f| ui::draw(f, &mut app)).expect("draw");
    });
}

/// The built-in animated character.
fn character() -> AnimationHandle {
    AnimationHandle(Arc::new(strider::builtin::animation().expect("built-in character")))
}

/// A simulation step of 100 agents and a full frame of them on 200×60 cells, from the same
/// state every time; 16.7 ms = 60 frames per second.
fn frame_and_step(bencher: Bencher, animation: Option<AnimationHandle>) {
    let mut app = app_with_agents(100, animation);
    let start = app.sim.clone();
    let mut terminal = Terminal::new(TestBackend::new(200, 60)).expect("test terminal");
    bencher.with_inputs(|| start.clone()).bench_local_values(|mut sim| {
        std::mem::swap(&mut app.sim, &mut sim);
        app.sim.step();
        terminal.draw(|f| ui::draw(f, &mut app)).expect("draw");
        std::mem::swap(&mut app.sim, &mut sim);
        sim
    });
}

/// [`frame_and_step`] with discs.
#[divan::bench]
fn frame_and_step_100_discs_200x60(bencher: Bencher) {
    frame_and_step(bencher, None);
}

/// [`frame_and_step`] with animated characters (the default body).
#[divan::bench]
fn frame_and_step_100_characters_200x60(bencher: Bencher) {
    frame_and_step(bencher, Some(character()));
}
