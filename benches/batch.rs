//! The whole batch a user runs, next to the micro-benchmarks of `nav.rs`: `strider run
//! random:cluttered --episodes 20 --seed 1` on one thread — world generation, the reference
//! optimum, every episode and the summary. The time per iteration divided by the agent-steps it
//! prints gives the batch's agent-steps per second.

use divan::{Bencher, black_box};
use strider::experiment::{self, Job};
use strider::maps::kind::{self, WorldKind};
use strider::sim::{AnimationHandle, LayeredController, StepParameters};

fn main() {
    divan::main();
}

const EPISODES: usize = 20;

fn controller() -> LayeredController {
    strider::builtin::controller().expect("built-in rules")
}

fn batch(params: &StepParameters) -> u64 {
    let c = controller();
    let make = |i: usize| {
        let seed = experiment::world_seed(1, i);
        Job { scenario: std::sync::Arc::new(kind::generate(WorldKind::Cluttered, seed)), task: 0, seed }
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("one thread");
    let records = pool.install(|| experiment::run_batch_of(EPISODES, &make, &c, params, &|| {}));
    black_box(experiment::summarize(&records));
    records.iter().map(|r| u64::from(r.steps)).sum()
}

/// The kinematic disc.
#[divan::bench(sample_count = 3)]
fn cluttered_batch_disc(bencher: Bencher) {
    let params = StepParameters::default();
    eprintln!("disc batch: {} agent-steps per iteration", batch(&params));
    bencher.bench_local(|| batch(&params));
}

/// The animated character (the default body).
#[divan::bench(sample_count = 3)]
fn cluttered_batch_character(bencher: Bencher) {
    let anim = strider::builtin::animation().expect("built-in character");
    let params =
        StepParameters { animation: Some(AnimationHandle(std::sync::Arc::new(anim))), ..StepParameters::default() };
    eprintln!("character batch: {} agent-steps per iteration", batch(&params));
    bencher.bench_local(|| batch(&params));
}
