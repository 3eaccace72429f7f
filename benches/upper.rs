//! Whole-body planning speed (seed 002 §5; the paper reports 14.2 frames/s; the bar:
//! at least 1000 frames/s on one core) on the shipped upper-body scenes (`maps/upper_*.rhai`),
//! walked by the character.
//!
//! Before the divan benchmarks, `main` runs every scene's episode with a stopwatch lent to the
//! planners and prints, per scene and over all of them: the frames played, the upper-body
//! planning time per frame (every candidate planned at every switch point, the look-ahead
//! included), the footstep planning where there is terrain, and the whole simulation loop —
//! sensing, the fuzzy planner, the RL choice, playback, the legs, the upper body and its
//! measurement — as frames per second of wall time. The benchmarks then time whole episodes.

use std::sync::Arc;
use std::time::Instant;

use divan::{Bencher, black_box};
use strider::experiment::run_episode;
use strider::scenario::Scenario;
use strider::script::{Limits, ScriptLog, load_scenario};
use strider::sim::footing::{Stopwatch, StopwatchHandle};
use strider::sim::{AnimationHandle, LayeredController, StepParameters};

const SCENES: [&str; 5] = ["overhead_bar", "shelves", "low_bar", "table", "all"];

struct Wall(Instant);

impl Stopwatch for Wall {
    fn now_s(&self) -> f64 {
        self.0.elapsed().as_secs_f64()
    }
}

fn scene(name: &str) -> Scenario {
    let path = format!("{}/maps/upper_{name}.rhai", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(&path).expect("shipped scene");
    load_scenario(&src, &path, Limits::default(), &ScriptLog::new()).expect("valid scene")
}

fn controller() -> LayeredController {
    strider::builtin::controller().expect("built-in rules")
}

fn params(stopwatch: bool) -> StepParameters {
    StepParameters {
        animation: Some(AnimationHandle(Arc::new(strider::builtin::animation().expect("built-in character")))),
        stopwatch: stopwatch.then(|| StopwatchHandle(Arc::new(Wall(Instant::now())))),
        ..StepParameters::default()
    }
}

fn main() {
    let c = controller();
    let timed = params(true);
    let (mut frames, mut planning_s, mut wall_s) = (0.0, 0.0, 0.0);
    for name in SCENES {
        let s = scene(name);
        let world = s.world();
        let clock = Instant::now();
        let e = run_episode(&s, &world, 0, &c, &timed, 0, 0);
        let elapsed = clock.elapsed().as_secs_f64();
        let r = &e.record;
        let n = r.time_s * 60.0;
        let per_frame_ms = r.upper_body_ms_per_frame.unwrap_or(0.0);
        frames += n;
        planning_s += per_frame_ms * n / 1e3;
        wall_s += elapsed;
        println!(
            "upper_{name}: reached {}, {n:.0} frames; upper-body planning {:.4} ms a frame ({:.0} frames/s); \
             whole loop {:.0} frames/s; bend {:.0}°, twist {:.0}°, least clearance {:.3} m, refused {}",
            r.reached,
            per_frame_ms,
            1e3 / per_frame_ms.max(1e-9),
            n / elapsed,
            r.max_waist_bend_deg.unwrap_or(0.0),
            r.max_waist_twist_deg.unwrap_or(0.0),
            r.upper_body_min_clearance_m.unwrap_or(f64::INFINITY),
            r.upper_body_refused_steps.unwrap_or(0),
        );
    }
    println!(
        "all scenes: {frames:.0} frames; upper-body planning {:.0} frames/s; whole loop (one core) {:.0} frames/s",
        frames / planning_s.max(1e-12),
        frames / wall_s
    );
    divan::main();
}

/// One episode of the all-in-one scene, the whole loop.
#[divan::bench(sample_count = 5)]
fn all_in_one_episode(bencher: Bencher) {
    let (c, p, s) = (controller(), params(false), scene("all"));
    let world = s.world();
    bencher.bench_local(|| black_box(run_episode(&s, &world, 0, &c, &p, 0, 0).record.steps));
}

/// One episode under the overhead bars, the whole loop.
#[divan::bench(sample_count = 5)]
fn overhead_bar_episode(bencher: Bencher) {
    let (c, p, s) = (controller(), params(false), scene("overhead_bar"));
    let world = s.world();
    bencher.bench_local(|| black_box(run_episode(&s, &world, 0, &c, &p, 0, 0).record.steps));
}
