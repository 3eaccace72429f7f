//! Footstep planning time per step (seed 002 §4.2; the paper reports 30 ms per step; the
//! issue's bar: median ≤ 1 ms and p99 ≤ 5 ms per step) on the shipped profiles
//! (`maps/profiles/*.profile`), with the default window (n = 3, m = 13).
//!
//! Before the divan benchmarks, `main` walks every shipped profile many times with a fresh
//! planner (so the first step's look-ahead is counted), times every call into the planner and
//! prints the median, p99 and largest time per step over all of them. The benchmarks then time
//! one step at a time, cycling through every step of a profile from a copy of the planner as
//! it stood before that step.

use std::path::Path;
use std::time::Instant;

use divan::{Bencher, black_box};
use strider::footstep::{Course, Decision, FootstepParams, FootstepPlanner, PlannerMode};
use strider::ground::parse;

const PROFILES: [&str; 7] = ["stairs", "slope", "stepping_stones", "fig8_trap", "low_blocks", "gap_too_wide", "cliff"];

fn course(name: &str) -> Course {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("maps/profiles").join(format!("{name}.profile"));
    let text = std::fs::read_to_string(&path).expect("shipped profile");
    parse(&text, &path.display().to_string()).expect("valid profile")
}

/// The time of every call into the planner over one walk of `course`, milliseconds.
fn timed_walk(course: &Course, params: FootstepParams) -> Vec<f64> {
    let mut planner = FootstepPlanner::for_course(course, params, PlannerMode::Window).expect("planner");
    let mut times = Vec::new();
    loop {
        let clock = Instant::now();
        let decision = planner.next_step(params.step_init_m);
        times.push(clock.elapsed().as_secs_f64() * 1e3);
        if !matches!(decision, Decision::Step(_)) {
            return times;
        }
    }
}

fn quantile(sorted: &[f64], q: f64) -> f64 {
    sorted[((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len()) - 1]
}

fn main() {
    let params = FootstepParams::default();
    let courses: Vec<Course> = PROFILES.iter().map(|n| course(n)).collect();
    let mut times = Vec::new();
    for _ in 0..200 {
        for c in &courses {
            times.extend(timed_walk(c, params));
        }
    }
    times.sort_by(f64::total_cmp);
    println!(
        "footstep planning per step, {} calls over 200 walks of the {} shipped profiles: median {:.4} ms, \
         p99 {:.4} ms, max {:.4} ms",
        times.len(),
        courses.len(),
        quantile(&times, 0.5),
        quantile(&times, 0.99),
        quantile(&times, 1.0)
    );
    divan::main();
}

/// One planning call, cycling through every step of a shipped profile.
#[divan::bench(args = PROFILES, sample_size = 1, sample_count = 2000)]
fn plan_one_step(bencher: Bencher, name: &str) {
    let params = FootstepParams::default();
    let course = course(name);
    let mut planner = FootstepPlanner::for_course(&course, params, PlannerMode::Window).expect("planner");
    let mut before = vec![planner.clone()];
    while let Decision::Step(_) = planner.next_step(params.step_init_m) {
        before.push(planner.clone());
    }
    let mut k = 0;
    bencher
        .with_inputs(|| {
            k = (k + 1) % before.len();
            before[k].clone()
        })
        .bench_local_values(|mut p| black_box(p.next_step(params.step_init_m)));
}
