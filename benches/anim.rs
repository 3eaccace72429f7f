//! Animation controller speed (issue bars): choosing the next interval, clearance checks
//! included, ≤ 5 µs; neighbour preprocessing ≤ 50 ms for 200 intervals and ≤ 2 s for 2,000;
//! training to a stable policy ≤ 60 s on a 2-core machine.

use std::sync::Arc;

use divan::{Bencher, black_box};
use glam::DQuat;
use strider::anim::policy::{LearnParams, Policy, StateGrid};
use strider::anim::{Clip, Database, DbParams, actor, procedural};
use strider::sim::{
    AnimatedBody, Animation, AnimationHandle, Body, Command, OpenSpace, Simulation, StepParameters, Surroundings,
};
use strider::world::Pose;

fn main() {
    divan::main();
}

fn database() -> Database {
    strider::builtin::database().expect("built-in database")
}

/// The default clips repeated `copies` times, each copy's joints turned by a small distinct
/// rotation so no two intervals are equal.
fn many_clips(copies: usize) -> Vec<Clip> {
    let base = procedural::default_clips();
    let mut out = Vec::new();
    for k in 0..copies {
        for c in &base {
            let mut c = c.clone();
            c.name = format!("{}_{k}", c.name);
            let twist = DQuat::from_rotation_y(0.01 * k as f64) * DQuat::from_rotation_x(0.007 * k as f64);
            for f in &mut c.frames {
                for q in f.rotations.iter_mut().skip(1) {
                    *q = (twist * *q).normalize();
                }
            }
            out.push(c);
        }
    }
    out
}

/// Choosing the next interval at a switch point the way a character navigating a cluttered
/// world does: ranking the candidates (the learnt values at the exact state) and checking the
/// clearance of the best ones' paths (and of a stop after them) until one is clear. The
/// characters are taken from a real run at many moments.
#[divan::bench]
fn choose_next_interval(bencher: Bencher) {
    let anim = AnimationHandle(Arc::new(strider::builtin::animation().expect("built-in character")));
    let scenario = strider::maps::generate::random_world(strider::maps::generate::Density::Cluttered, 7);
    let world = scenario.world();
    let controller = strider::builtin::controller().expect("built-in rules");
    let params = StepParameters { animation: Some(anim), ..StepParameters::default() };
    let mut sim = Simulation::new(world.clone(), params);
    sim.add_agent(scenario.tasks[0], &controller);
    let mut bodies: Vec<AnimatedBody> = Vec::new();
    for step in 0..2000 {
        if sim.all_done() {
            break;
        }
        if step % 7 == 0 {
            bodies.push(sim.agents[0].body.animated().expect("animated").clone());
        }
        sim.step();
    }
    let mut scratch = Vec::new();
    let mut k = 0usize;
    bencher.bench_local(|| {
        k = (k + 1) % bodies.len();
        let mut space = Surroundings { world: &world, others: &[], scratch: &mut scratch };
        black_box(bodies[k].choose_next(&mut space))
    });
}

/// A policy trained briefly on the built-in database.
fn trained_policy() -> Policy {
    let db = database();
    let mut policy = Policy::new(&db, StateGrid::default(), LearnParams::default(), 1);
    policy.train(&db, 20_000, 0, &mut |_| {}, &mut |_| {});
    policy
}

/// Building the built-in database (~290 intervals): contacts, intervals, samples, K nearest
/// neighbours, candidates.
#[divan::bench(sample_count = 10)]
fn neighbours_builtin(bencher: Bencher) {
    let clips = procedural::default_clips();
    bencher.bench_local(|| black_box(Database::build(clips.clone(), actor::actor(), DbParams::default(), None)));
}

/// Building a database of about 2,000 intervals.
#[divan::bench(sample_count = 3)]
fn neighbours_2000(bencher: Bencher) {
    let clips = many_clips(10);
    let count =
        Database::build(clips.clone(), actor::actor(), DbParams::default(), None).expect("database").intervals.len();
    assert!(count >= 2000, "{count} intervals");
    bencher.bench_local(|| {
        let db = Database::build(clips.clone(), actor::actor(), DbParams::default(), None).expect("database");
        assert!(db.intervals.len() >= 2000, "{} intervals", db.intervals.len());
        black_box(db)
    });
}

/// Training the default policy (1,000,000 episodes, the `strider train` default).
#[divan::bench(sample_count = 1)]
fn train_default(bencher: Bencher) {
    let db = database();
    bencher.bench_local(|| {
        let mut policy = Policy::new(&db, StateGrid::default(), LearnParams::default(), 1);
        policy.train(&db, 1_000_000, 0, &mut |_| {}, &mut |_| {});
        black_box(policy)
    });
}

/// One simulation step of an animated character (3 frames at 60 Hz, choices included).
#[divan::bench]
fn animated_step(bencher: Bencher) {
    let anim = Arc::new(Animation::new(database(), trained_policy()));
    let mut body = AnimatedBody::new(anim, Pose { position: glam::DVec2::ZERO, yaw: 0.0 }, 0.3);
    let mut k = 0u32;
    bencher.bench_local(|| {
        k += 1;
        let c = Command { turn_rate: if k % 80 < 40 { 0.5 } else { -0.5 }, speed: 1.2, toward: None };
        black_box(body.step(c, 0.05, &mut OpenSpace))
    });
}
