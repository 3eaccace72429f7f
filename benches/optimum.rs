//! The reference optimum (`strider::plan`): the exact shortest path for the agent's disc on a
//! 512 × 512 MovingAI-style map (one cell a metre, a fifth of the cells blocked at random, read
//! through the MovingAI importer, which merges blocked cells into boxes), and on the generated
//! worlds of a `random:cluttered` batch.
//!
//! - `first_search_512`: a planner made for the map and one search across it, as the first
//!   line of a run pays it (the rims' legs are found as the search reaches them);
//! - `later_search_512`: the same search again on a planner that has answered it, as later
//!   lines pay where earlier ones went;
//! - `cluttered_world`: planner and search on each world of a 20-world `random:cluttered`
//!   batch, as every episode of such a batch pays it.

use divan::{Bencher, black_box};
use glam::DVec2;
use strider::maps::kind::{self, WorldKind};
use strider::plan::{Planner, shortest_path};
use strider::scenario::Scenario;
use strider::world::World;

fn main() {
    divan::main();
}

/// Side of the map, cells (metres).
const SIDE: usize = 512;

/// The map: one cell in five blocked, from a fixed linear congruential stream; corners kept
/// free for the scenario's lines, which cross the map from corner to corner.
fn map() -> Scenario {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 33).is_multiple_of(5)
    };
    let mut text = format!("type octile\nheight {SIDE}\nwidth {SIDE}\nmap\n");
    for y in 0..SIDE {
        for x in 0..SIDE {
            let corner = !(3..SIDE - 3).contains(&x) && !(3..SIDE - 3).contains(&y);
            text.push(if next() && !corner { '@' } else { '.' });
        }
        text.push('\n');
    }
    let far = SIDE - 2;
    let scen = format!(
        "version 1\n0\tb.map\t{SIDE}\t{SIDE}\t1\t1\t{far}\t{far}\t700\n0\tb.map\t{SIDE}\t{SIDE}\t{far}\t1\t1\t{far}\t700\n"
    );
    strider::maps::movingai::load(&text, "b.map", &scen, "b.map.scen").expect("a valid map")
}

/// The map's world and its first line's start and goal.
fn setup() -> (World, f64, DVec2, DVec2) {
    let s = map();
    let t = s.tasks[0];
    (s.world(), s.agent_radius, t.start.position, t.goal)
}

#[divan::bench(sample_count = 3)]
fn first_search_512(bencher: Bencher) {
    let (world, r, a, b) = setup();
    bencher.bench_local(|| black_box(shortest_path(&world, a, b, r).map(|p| p.length)));
}

#[divan::bench(sample_count = 5)]
fn later_search_512(bencher: Bencher) {
    let (world, r, a, b) = setup();
    let planner = Planner::new(&world, r).expect("a valid radius");
    eprintln!(
        "512 × 512: {} rims, first line {:?} m",
        planner.rim_count(),
        planner.shortest_path(a, b).map(|p| p.length)
    );
    bencher.bench_local(|| black_box(planner.shortest_path(a, b).map(|p| p.length)));
}

#[divan::bench(sample_count = 5)]
fn cluttered_world(bencher: Bencher) {
    let worlds: Vec<(World, Scenario)> = (0..20)
        .map(|i| {
            let s = kind::generate(WorldKind::Cluttered, strider::experiment::world_seed(1, i));
            (s.world(), s)
        })
        .collect();
    bencher.bench_local(|| {
        for (world, s) in &worlds {
            let t = s.tasks[0];
            black_box(shortest_path(world, t.start.position, t.goal, s.agent_radius).map(|p| p.length));
        }
    });
}
