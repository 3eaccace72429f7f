//! `Inference::process` allocates nothing (ARCHITECTURE.md, the fuzzy engine's invariant):
//! a counting allocator watches this thread while engines of every family run on varied
//! inputs, NaN and infinities included.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use strider::fuzzy::{Activation, Defuzzifier, Engine, Inference, InputVariable, OutputVariable, RuleBlock, Term};
use strider::fuzzy::{NamedTerm, WeightedKind, fll};
use strider::script::{Limits, ScriptLog, load_engines};

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> u64 {
    ALLOCATIONS.with(Cell::get)
}

/// A Takagi-Sugeno engine with 40 constant output terms, all fired at once (more than the
/// 16 activations the weighted defuzzifier handles per piece), and a Highest activation.
fn wide_sugeno() -> Engine {
    let mut e = Engine::new("wide");
    let mut x = InputVariable::new("x", 0.0, 1.0);
    x.terms.push(NamedTerm { name: "up".into(), term: Term::Ramp { start: 0.0, end: 1.0, height: 1.0 } });
    e.inputs.push(x);
    let mut o = OutputVariable::new("o", 0.0, 40.0);
    o.defuzzifier = Some(Defuzzifier::WeightedAverage { kind: WeightedKind::TakagiSugeno });
    for k in 0..40 {
        o.terms.push(NamedTerm { name: format!("t{k}"), term: Term::Constant { value: k as f64 } });
    }
    e.outputs.push(o);
    let mut b = RuleBlock::mamdani("r");
    b.activation = Activation::Highest { rules: 30 };
    e.rule_blocks.push(b);
    for k in 0..40 {
        e.add_rule(0, &format!("if x is up then o is t{k} with {}", 0.5 + k as f64 / 100.0)).unwrap();
    }
    e.validate().unwrap();
    e
}

#[test]
fn process_allocates_nothing() {
    let root = env!("CARGO_MANIFEST_DIR");
    let mut engines = vec![wide_sugeno()];
    let tipper = std::fs::read_to_string(format!("{root}/tests/fixtures/fuzzy/tipper.fll")).unwrap();
    engines.push(fll::import(&tipper, "tipper.fll").unwrap());
    // The benchmark engines: narrow terms, wide overlapping terms, most rules firing at once.
    for name in ["narrow", "wide", "crowded"] {
        let text = std::fs::read_to_string(format!("{root}/benches/fixtures/{name}.fll")).unwrap();
        engines.push(fll::import(&text, name).unwrap());
    }
    for script in ["scripts/simple_nav.rhai", "scripts/nav.rhai"] {
        let text = std::fs::read_to_string(format!("{root}/{script}")).unwrap();
        engines.extend(load_engines(&text, script, Limits::default(), &ScriptLog::new()).unwrap());
    }
    // Formulas: on inputs, on a Takagi-Sugeno output and on a Mamdani output sampled again
    // at every step (it reads the output defuzzified before it).
    let formulas = std::fs::read_to_string(format!("{root}/tests/fuzz_corpus/fll/function.fll")).unwrap();
    engines.push(fll::import(&formulas, "function.fll").unwrap());
    let specials = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -1e300, 0.0];
    for engine in &engines {
        let mut inference = Inference::new(engine).unwrap();
        let n = engine.inputs.len();
        let mut row = vec![0.0; n];
        let mut rows = Vec::new();
        for k in 0..400usize {
            for (i, v) in row.iter_mut().enumerate() {
                let var = &engine.inputs[i];
                let t = ((k * 7 + i * 13) % 101) as f64 / 100.0;
                *v = if k % 37 == 5 {
                    specials[(k + i) % specials.len()]
                } else {
                    var.minimum + t * (var.maximum - var.minimum)
                };
            }
            rows.push(row.clone());
        }
        // One warm-up pass, then none may allocate.
        inference.set_inputs(&rows[0]);
        inference.process();
        let before = allocations();
        for r in &rows {
            inference.set_inputs(r);
            inference.process();
        }
        let during = allocations() - before;
        assert_eq!(during, 0, "engine '{}' allocated {during} times in {} inferences", engine.name, rows.len());
    }
}
