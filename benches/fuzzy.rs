//! Fuzzy inference throughput (issue bar: ≥ 1,000,000 inferences per second on one core for
//! the 2-input / 2-output, 15-rule Mamdani engine with centroid at resolution 200, which is
//! strider's default navigation engine `scripts/simple_nav.rhai`).

use divan::{Bencher, black_box};
use strider::fuzzy::reference::Reference;
use strider::fuzzy::{Engine, Inference};
use strider::script::{Limits, ScriptLog, fuzzy_api};

fn main() {
    divan::main();
}

fn nav_engine() -> Engine {
    let source = include_str!("../scripts/simple_nav.rhai");
    fuzzy_api::load_engines(source, "scripts/simple_nav.rhai", Limits::default(), &ScriptLog::new())
        .expect("default navigation script")
        .remove(0)
}

fn inputs(n: usize) -> Vec<[f64; 2]> {
    let mut rng = strider::rng::stream(1, 0, 0);
    (0..n)
        .map(|_| [strider::rng::uniform(&mut rng, 0.0, 5.0), strider::rng::uniform(&mut rng, -180.0, 180.0)])
        .collect()
}

/// One compiled inference (time per iteration; 1 µs = 1,000,000 inferences per second).
#[divan::bench]
fn compiled_nav_inference(bencher: Bencher) {
    let mut inf = Inference::new(&nav_engine()).expect("valid engine");
    let xs = inputs(1024);
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) & 1023;
        inf.set_inputs(black_box(&xs[k]));
        inf.process();
        black_box(inf.outputs()[0])
    });
}

/// The naive reference evaluation of the same engine, for comparison.
#[divan::bench]
fn reference_nav_inference(bencher: Bencher) {
    let mut naive = Reference::new(&nav_engine()).expect("valid engine");
    let xs = inputs(1024);
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) & 1023;
        black_box(naive.process(black_box(&xs[k]))[0])
    });
}
