//! Animation controller speed (issue bars): choosing the next interval ≤ 5 µs; neighbour
//! preprocessing ≤ 50 ms for 200 intervals and ≤ 2 s for 2,000; training to a stable policy
//! ≤ 60 s on a 2-core machine.

use std::sync::Arc;

use divan::{Bencher, black_box};
use glam::DQuat;
use strider::anim::policy::{Errors, LearnParams, Policy, StateGrid};
use strider::anim::{Clip, Database, DbParams, actor, procedural};
use strider::sim::{AnimatedBody, Animation, Body, Command};
use strider::world::Pose;

fn main() {
    divan::main();
}

fn database() -> Database {
    Database::build(procedural::default_clips(), actor::actor(), DbParams::default(), None).expect("built-in database")
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

/// Choosing the next interval at a switch point: nearest sampled state, best action.
#[divan::bench]
fn choose_next_interval(bencher: Bencher) {
    let db = database();
    let mut policy = Policy::new(&db, StateGrid::default(), LearnParams::default(), 1);
    policy.train(&db, 6400, 0, &mut |_| {}, &mut |_| {});
    let n = db.intervals.len();
    let mut k = 0usize;
    bencher.bench_local(|| {
        k = (k + 7) % n;
        let e = Errors { speed: (k % 13) as f64 * 0.2 - 1.2, direction: (k % 17) as f64 * 0.3 - 2.4 };
        black_box(policy.choose(black_box(k), e))
    });
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
    let db = database();
    let mut policy = Policy::new(&db, StateGrid::default(), LearnParams::default(), 1);
    policy.train(&db, 6400, 0, &mut |_| {}, &mut |_| {});
    let anim = Arc::new(Animation { db, policy, player: Default::default() });
    let mut body = AnimatedBody::new(anim, Pose { position: glam::DVec2::ZERO, yaw: 0.0 }, 0.3);
    let mut k = 0u32;
    bencher.bench_local(|| {
        k += 1;
        let c = Command { turn_rate: if k % 80 < 40 { 0.5 } else { -0.5 }, speed: 1.2 };
        black_box(body.step(c, 0.05, &mut |_| true))
    });
}
