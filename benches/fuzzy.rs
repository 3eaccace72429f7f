//! Fuzzy inference throughput (issue bar: ≥ 1,000,000 inferences per second on one core for
//! 2-input / 2-output, 15-rule Mamdani engines with centroid at resolution 200). Engines:
//! strider's default navigation engine `scripts/simple_nav.rhai`, and the FLL engines of
//! `benches/fixtures/`: `narrow` (narrow terms, few rules fire), `wide` (wide, heavily
//! overlapping terms) and `crowded` (most of the 15 rules fire, each on a term of its own),
//! each at resolutions 100, 200 and 500. Time per iteration is time per inference
//! (1 µs = 1,000,000 inferences per second). `benches/peers/fuzzylite.sh` runs the same
//! engines through fuzzylite (C++) and strider side by side.

use divan::{Bencher, black_box};
use strider::fuzzy::reference::Reference;
use strider::fuzzy::{Defuzzifier, Engine, Inference, fll};
use strider::script::{Limits, ScriptLog, load_engines};

fn main() {
    divan::main();
}

fn nav_engine() -> Engine {
    let source = include_str!("../scripts/simple_nav.rhai");
    load_engines(source, "scripts/simple_nav.rhai", Limits::default(), &ScriptLog::new())
        .expect("default navigation script")
        .remove(0)
}

/// The engine called `name` with every centroid at `resolution`.
fn engine(name: &str, resolution: usize) -> Engine {
    let mut e = match name {
        "nav" => nav_engine(),
        "narrow" => fll::import(include_str!("fixtures/narrow.fll"), "narrow.fll").expect("narrow.fll"),
        "wide" => fll::import(include_str!("fixtures/wide.fll"), "wide.fll").expect("wide.fll"),
        "crowded" => fll::import(include_str!("fixtures/crowded.fll"), "crowded.fll").expect("crowded.fll"),
        _ => panic!("no engine {name}"),
    };
    for out in &mut e.outputs {
        out.defuzzifier = Some(Defuzzifier::Centroid { resolution });
    }
    e
}

/// 1024 input rows spread uniformly over the inputs' ranges.
fn inputs(e: &Engine) -> Vec<Vec<f64>> {
    let mut rng = strider::rng::stream(1, 0, 0);
    (0..1024)
        .map(|_| e.inputs.iter().map(|v| strider::rng::uniform(&mut rng, v.minimum, v.maximum)).collect())
        .collect()
}

/// One compiled inference of an engine at a resolution.
#[divan::bench(args = ["nav", "narrow", "wide", "crowded"], consts = [100, 200, 500])]
fn compiled<const RESOLUTION: usize>(bencher: Bencher, name: &str) {
    let e = engine(name, RESOLUTION);
    let mut inf = Inference::new(&e).expect("valid engine");
    let xs = inputs(&e);
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) & 1023;
        inf.set_inputs(black_box(&xs[k]));
        inf.process();
        black_box(inf.outputs()[0])
    });
}

/// The naive reference evaluation of the navigation engine, for comparison.
#[divan::bench]
fn reference_nav_inference(bencher: Bencher) {
    let e = engine("nav", 200);
    let mut naive = Reference::new(&e).expect("valid engine");
    let xs = inputs(&e);
    let mut k = 0;
    bencher.bench_local(|| {
        k = (k + 1) & 1023;
        black_box(naive.process(black_box(&xs[k]))[0])
    });
}
