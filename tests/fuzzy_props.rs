//! Property tests of the fuzzy engine over randomly generated engines: the compiled inference
//! agrees with the naive reference (on engines of every family, and on Mamdani engines of
//! triangles and trapezoids of every width, the shape the compiled centroid is tuned for),
//! outputs stay in range, monotone rule bases give monotone outputs, and FLL export/import
//! preserves behaviour.

use proptest::prelude::*;
use rand_chacha::ChaCha8Rng;
use strider::fuzzy::reference::Reference;
use strider::fuzzy::{
    Activation, Defuzzifier, Engine, Hedge, Inference, InputVariable, OutputVariable, RuleBlock, SNorm, TNorm, Term,
    WeightedKind, fll,
};
use strider::rng::{stream, uniform, unit};

fn pick<T: Copy>(rng: &mut ChaCha8Rng, items: &[T]) -> T {
    items[((unit(rng) * items.len() as f64) as usize).min(items.len() - 1)]
}

/// A `Function` term on `[lo, hi]`: a bump, a bell, a step or a raised cosine of `x`, its
/// centre sometimes moved by one of the variables `names`.
fn function_term(rng: &mut ChaCha8Rng, lo: f64, hi: f64, names: &[String]) -> Term {
    let c = uniform(rng, lo, hi);
    let w = uniform(rng, 0.1, 0.5) * (hi - lo);
    let h = uniform(rng, 0.3, 1.0);
    let centre = if names.is_empty() || unit(rng) < 0.4 {
        format!("{c}")
    } else {
        let k = ((unit(rng) * names.len() as f64) as usize).min(names.len() - 1);
        format!("({c} + {} / 10)", names[k])
    };
    let formula = match (unit(rng) * 4.0) as usize {
        0 => format!("max(0, 1 - fabs(x - {centre}) / {w})"),
        1 => format!("{h} * exp(-((x - {centre}) / {w})^2 / 2)"),
        2 => format!("lt(x, {centre}) * 0.25 + ge(x, {centre}) * min(1, fabs(x - {centre}) / {w})"),
        _ => format!("{h} * (1 + cos(pi * min(1, fabs(x - {centre}) / {w}))) / 2"),
    };
    Term::function(&formula).unwrap_or_else(|e| panic!("{formula}: {e:?}"))
}

/// A random term on `[lo, hi]`; a `Function` may read the variables `names`.
fn random_term(rng: &mut ChaCha8Rng, lo: f64, hi: f64, names: &[String]) -> Term {
    if unit(rng) < 0.1 {
        return function_term(rng, lo, hi, names);
    }
    let mut xs: Vec<f64> = (0..4).map(|_| uniform(rng, lo, hi)).collect();
    xs.sort_by(f64::total_cmp);
    let height = if unit(rng) < 0.2 { uniform(rng, 0.3, 1.0) } else { 1.0 };
    let span = hi - lo;
    match (unit(rng) * 9.0) as usize {
        0 => Term::Triangle { a: xs[0], b: xs[1], c: xs[3], height },
        6 if unit(rng) < 0.5 => Term::Arc { start: xs[0], end: xs[3], height },
        6 => Term::Arc { start: xs[3], end: xs[0], height },
        7 => Term::SemiEllipse { start: xs[0], end: xs[3], height },
        8 => Term::Binary { start: xs[1], direction: pick(rng, &[f64::INFINITY, f64::NEG_INFINITY]), height },
        1 => Term::Trapezoid { a: xs[0], b: xs[1], c: xs[2], d: xs[3], height },
        2 => Term::Gaussian { mean: xs[1], sd: uniform(rng, 0.05, 0.4) * span, height },
        3 => Term::Bell { center: xs[1], width: uniform(rng, 0.05, 0.4) * span, slope: uniform(rng, 0.5, 3.0), height },
        4 => Term::PiShape { bottom_left: xs[0], top_left: xs[1], top_right: xs[2], bottom_right: xs[3], height },
        _ => Term::Ramp { start: xs[0], end: xs[3], height },
    }
}

/// Input `in{i}` on `[-5, 5]` with two to `2 + extra` random terms (a `Function` among them
/// may read the variables `names`).
fn random_input(rng: &mut ChaCha8Rng, i: usize, extra: f64, names: &[String]) -> InputVariable {
    let mut v = InputVariable::new(&format!("in{i}"), -5.0, 5.0);
    for t in 0..2 + (unit(rng) * extra) as usize {
        v = v.term(&format!("t{t}"), random_term(rng, -5.0, 5.0, names));
    }
    v
}

/// A random valid Mamdani/Larsen-style engine with integral outputs, or a Takagi-Sugeno one.
fn random_engine(seed: u64) -> Engine {
    let rng = &mut stream(seed, 0, 0);
    let mut e = Engine::new("random");
    let n_in = 1 + (unit(rng) * 3.0) as usize;
    let sugeno = unit(rng) < 0.25;
    let n_out = 1 + (unit(rng) * 2.0) as usize;
    // Formulas read any variable: inputs, and outputs (earlier ones as defuzzified in the same
    // step, the others as they were after the step before).
    let names: Vec<String> = (0..n_in).map(|i| format!("in{i}")).chain((0..n_out).map(|o| format!("out{o}"))).collect();
    for i in 0..n_in {
        e.inputs.push(random_input(rng, i, 3.0, &names));
    }
    for o in 0..n_out {
        let mut v = OutputVariable::new(&format!("out{o}"), 0.0, 10.0);
        for t in 0..2 + (unit(rng) * 3.0) as usize {
            let term = if sugeno && unit(rng) < 0.2 {
                let k = ((unit(rng) * names.len() as f64) as usize).min(names.len() - 1);
                let (a, b) = (uniform(rng, -2.0, 2.0), uniform(rng, -2.0, 2.0));
                Term::function(&format!("{a} * {} + {b} * x + sin(x)", names[k])).unwrap()
            } else if sugeno {
                Term::Linear { coefficients: (0..=n_in).map(|_| uniform(rng, -2.0, 2.0)).collect() }
            } else {
                random_term(rng, 0.0, 10.0, &names)
            };
            v = v.term(&format!("t{t}"), term);
        }
        let resolution = 10 + (unit(rng) * 300.0) as usize;
        v.defuzzifier = Some(if sugeno {
            pick(
                rng,
                &[
                    Defuzzifier::WeightedAverage { kind: WeightedKind::TakagiSugeno },
                    Defuzzifier::WeightedSum { kind: WeightedKind::Automatic },
                ],
            )
        } else {
            pick(
                rng,
                &[
                    Defuzzifier::Centroid { resolution },
                    Defuzzifier::Bisector { resolution },
                    Defuzzifier::SmallestOfMaximum { resolution },
                    Defuzzifier::LargestOfMaximum { resolution },
                    Defuzzifier::MeanOfMaximum { resolution },
                ],
            )
        });
        v.aggregation = Some(pick(rng, &SNorm::ALL));
        v.default_value = if unit(rng) < 0.5 { f64::NAN } else { uniform(rng, 0.0, 10.0) };
        v.lock_previous = unit(rng) < 0.3;
        e.outputs.push(v);
    }
    let mut block = RuleBlock::mamdani("rules");
    block.conjunction = Some(pick(rng, &TNorm::ALL));
    block.disjunction = Some(pick(rng, &SNorm::ALL));
    block.implication = Some(pick(rng, &TNorm::ALL));
    block.activation = pick(
        rng,
        &[
            Activation::General,
            Activation::General,
            Activation::Highest { rules: 2 },
            Activation::First { rules: 3, threshold: 0.1 },
            Activation::Proportional,
        ],
    );
    e.rule_blocks.push(block);
    let hedges = ["", "", "", "not ", "very ", "somewhat ", "extremely ", "seldom "];
    for _ in 0..1 + (unit(rng) * 12.0) as usize {
        let props = 1 + (unit(rng) * 3.0) as usize;
        let mut text = String::from("if ");
        for p in 0..props {
            if p > 0 {
                text.push_str(pick(rng, &[" and ", " or "]));
            }
            let i = (unit(rng) * n_in as f64) as usize;
            let t = (unit(rng) * e.inputs[i].terms.len() as f64) as usize;
            text.push_str(&format!("in{i} is {}t{t}", pick(rng, &hedges)));
        }
        let o = (unit(rng) * n_out as f64) as usize;
        let t = (unit(rng) * e.outputs[o].terms.len() as f64) as usize;
        text.push_str(&format!(" then out{o} is t{t}"));
        if unit(rng) < 0.3 {
            text.push_str(&format!(" with {}", uniform(rng, 0.0, 1.0)));
        }
        e.add_rule(0, &text).unwrap_or_else(|err| panic!("{text}: {err}"));
    }
    e
}

/// A triangle or trapezoid on `[lo, hi]` whose width is `width` times the range (narrow terms
/// for small `width`, wide ones reaching past the range for large), sometimes a shoulder or
/// below full height.
fn sized_term(rng: &mut ChaCha8Rng, lo: f64, hi: f64, width: f64) -> Term {
    let span = hi - lo;
    let w = span * width * uniform(rng, 0.5, 1.5);
    let centre = uniform(rng, lo - 0.1 * span, hi + 0.1 * span);
    let mut xs: Vec<f64> = (0..4).map(|_| centre + w * uniform(rng, -0.5, 0.5)).collect();
    xs.sort_by(f64::total_cmp);
    let height = if unit(rng) < 0.15 { uniform(rng, 0.2, 1.0) } else { 1.0 };
    match (unit(rng) * 8.0) as usize {
        0 => Term::Trapezoid { a: f64::NEG_INFINITY, b: xs[1], c: xs[2], d: xs[3], height },
        1 => Term::Trapezoid { a: xs[0], b: xs[1], c: xs[2], d: f64::INFINITY, height },
        2 => Term::Triangle { a: xs[0], b: xs[0], c: xs[3], height },
        3..=5 => Term::Triangle { a: xs[0], b: xs[1], c: xs[3], height },
        _ => Term::Trapezoid { a: xs[0], b: xs[1], c: xs[2], d: xs[3], height },
    }
}

/// A random 2-input / 2-output Mamdani engine of 15 rules over triangles and trapezoids:
/// term widths from narrow to wider than the range, minimum or product implication, maximum
/// aggregation, centroid at a random resolution. Most rules are conjunctions of two inputs;
/// some use `or`, hedges, nested antecedents, weights or conclude several terms.
fn mamdani_engine(seed: u64) -> Engine {
    let rng = &mut stream(seed, 1, 0);
    let mut e = Engine::new("mamdani");
    let width = pick(rng, &[0.02, 0.08, 0.2, 0.5, 0.9, 1.5]);
    let ranges = [(-5.0, 5.0), (0.0, 100.0)];
    for (i, (lo, hi)) in ranges.into_iter().enumerate() {
        let mut v = InputVariable::new(&format!("in{i}"), lo, hi);
        for t in 0..2 + (unit(rng) * 5.0) as usize {
            v = v.term(&format!("t{t}"), sized_term(rng, lo, hi, width));
        }
        e.inputs.push(v);
    }
    let resolution = pick(rng, &[1, 3, 10, 37, 100, 200, 201, 500, 1000]);
    for (o, (lo, hi)) in [(0.0, 10.0), (-300.0, 300.0)].into_iter().enumerate() {
        let mut v = OutputVariable::new(&format!("out{o}"), lo, hi);
        for t in 0..2 + (unit(rng) * 15.0) as usize {
            let w = width * uniform(rng, 0.5, 2.0);
            v = v.term(&format!("t{t}"), sized_term(rng, lo, hi, w));
        }
        v.defuzzifier = Some(Defuzzifier::Centroid { resolution });
        v.aggregation = Some(SNorm::Maximum);
        v.default_value = f64::NAN;
        e.outputs.push(v);
    }
    let mut block = RuleBlock::mamdani("rules");
    block.implication = Some(if unit(rng) < 0.7 { TNorm::Minimum } else { TNorm::AlgebraicProduct });
    e.rule_blocks.push(block);
    let prop = |rng: &mut ChaCha8Rng, e: &Engine, i: usize| {
        let t = (unit(rng) * e.inputs[i].terms.len() as f64) as usize;
        let hedge = if unit(rng) < 0.05 { pick(rng, &["very ", "not ", "somewhat "]) } else { "" };
        format!("in{i} is {hedge}t{t}")
    };
    let conclusion = |rng: &mut ChaCha8Rng, e: &Engine, o: usize| {
        let t = (unit(rng) * e.outputs[o].terms.len() as f64) as usize;
        format!("out{o} is t{t}")
    };
    for _ in 0..15 {
        let (a, b) = (prop(rng, &e, 0), prop(rng, &e, 1));
        let antecedent = match (unit(rng) * 10.0) as usize {
            0 => format!("{a} or {b}"),
            1 => {
                let c = prop(rng, &e, 0);
                format!("{a} and ({b} or {c})")
            }
            2 => a,
            _ => format!("{a} and {b}"),
        };
        let (c0, c1) = (conclusion(rng, &e, 0), conclusion(rng, &e, 1));
        let mut text = format!("if {antecedent} then {c0} and {c1}");
        if unit(rng) < 0.1 {
            let extra = conclusion(rng, &e, 1);
            text.push_str(&format!(" and {extra}"));
        }
        if unit(rng) < 0.1 {
            let w = uniform(rng, 0.1, 1.0);
            text.push_str(&format!(" with {w}"));
        }
        e.add_rule(0, &text).unwrap_or_else(|err| panic!("{text}: {err}"));
    }
    e
}

fn same(a: f64, b: f64, tol: f64) -> bool {
    (a.is_nan() && b.is_nan()) || a == b || (a - b).abs() <= tol
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    #[test]
    fn compiled_agrees_with_reference(seed in any::<u64>(), xs in prop::collection::vec(-6.0f64..6.0, 8..24)) {
        let e = random_engine(seed);
        let mut fast = Inference::new(&e).unwrap();
        let mut naive = Reference::new(&e).unwrap();
        for row in xs.chunks(e.inputs.len()) {
            let mut input = row.to_vec();
            input.resize(e.inputs.len(), 0.0);
            fast.set_inputs(&input);
            fast.process();
            let expected = naive.process(&input).to_vec();
            for (o, (a, b)) in fast.outputs().iter().zip(&expected).enumerate() {
                prop_assert!(same(*a, *b, 1e-9), "output {o}: {a} vs {b}\n{}", fll::export(&e));
            }
        }
    }

    /// The compiled centroid (terms pre-sampled over their support, merged per term, folded
    /// one at a time or four at a time) agrees with the naive evaluation on Mamdani engines of
    /// triangles and trapezoids of every width and resolution.
    #[test]
    fn compiled_agrees_with_reference_on_mamdani_engines(
        seed in any::<u64>(),
        us in prop::collection::vec(-0.1f64..1.1, 16..32),
    ) {
        let e = mamdani_engine(seed);
        let mut fast = Inference::new(&e).unwrap();
        let mut naive = Reference::new(&e).unwrap();
        for u in us.chunks_exact(2) {
            let input = [-5.0 + 10.0 * u[0], 100.0 * u[1]];
            fast.set_inputs(&input);
            fast.process();
            let expected = naive.process(&input).to_vec();
            for (o, (a, b)) in fast.outputs().iter().zip(&expected).enumerate() {
                let scale = e.outputs[o].maximum - e.outputs[o].minimum;
                prop_assert!(same(*a, *b, 1e-12 * scale), "output {o} at {input:?}: {a} vs {b}\n{}", fll::export(&e));
            }
        }
    }

    #[test]
    fn integral_outputs_stay_in_range(seed in any::<u64>(), xs in prop::collection::vec(-6.0f64..6.0, 3)) {
        let e = random_engine(seed);
        let mut inf = Inference::new(&e).unwrap();
        inf.set_inputs(&xs);
        inf.process();
        for (v, var) in inf.outputs().iter().zip(&e.outputs) {
            if var.defuzzifier.and_then(|d| d.resolution()).is_some() {
                prop_assert!(v.is_nan() || (var.minimum..=var.maximum).contains(v), "{v}");
            }
        }
    }

    #[test]
    fn fll_round_trip_keeps_outputs(seed in any::<u64>(), xs in prop::collection::vec(-6.0f64..6.0, 3)) {
        let e = random_engine(seed);
        let text = fll::export(&e);
        let back = fll::import(&text, "round.fll").unwrap();
        prop_assert_eq!(&fll::export(&back), &text);
        let (mut a, mut b) = (Inference::new(&e).unwrap(), Inference::new(&back).unwrap());
        a.set_inputs(&xs);
        b.set_inputs(&xs);
        a.process();
        b.process();
        for (x, y) in a.outputs().iter().zip(b.outputs()) {
            prop_assert!(same(*x, *y, 0.0), "{x} vs {y}");
        }
    }

    /// Rising inputs map to rising outputs when the rule base is monotone: ordered input
    /// terms map to ordered output terms.
    #[test]
    fn monotone_rule_base_gives_monotone_output(
        cuts in prop::collection::vec(0.5f64..9.5, 3),
        x1 in 0.0f64..10.0,
        x2 in 0.0f64..10.0,
        product in any::<bool>(),
    ) {
        let mut c = cuts.clone();
        c.sort_by(f64::total_cmp);
        let mut e = Engine::new("mono");
        e.inputs.push(
            InputVariable::new("x", 0.0, 10.0)
                .term("low", Term::Trapezoid { a: f64::NEG_INFINITY, b: 0.0, c: c[0], d: c[1], height: 1.0 })
                .term("mid", Term::Triangle { a: c[0], b: c[1], c: c[2], height: 1.0 })
                .term("high", Term::Trapezoid { a: c[1], b: c[2], c: 10.0, d: f64::INFINITY, height: 1.0 }),
        );
        let mut y = OutputVariable::new("y", 0.0, 10.0)
            .term("low", Term::Triangle { a: 0.0, b: 0.0, c: 5.0, height: 1.0 })
            .term("mid", Term::Triangle { a: 2.5, b: 5.0, c: 7.5, height: 1.0 })
            .term("high", Term::Triangle { a: 5.0, b: 10.0, c: 10.0, height: 1.0 });
        y.defuzzifier = Some(Defuzzifier::Centroid { resolution: 200 });
        e.outputs.push(y);
        let mut b = RuleBlock::mamdani("r");
        if product {
            b.implication = Some(TNorm::AlgebraicProduct);
        }
        e.rule_blocks.push(b);
        for t in ["low", "mid", "high"] {
            e.add_rule(0, &format!("if x is {t} then y is {t}")).unwrap();
        }
        let (lo, hi) = if x1 <= x2 { (x1, x2) } else { (x2, x1) };
        let mut inf = Inference::new(&e).unwrap();
        inf.set_inputs(&[lo]);
        inf.process();
        let y_lo = inf.outputs()[0];
        inf.set_inputs(&[hi]);
        inf.process();
        let y_hi = inf.outputs()[0];
        prop_assert!(y_lo <= y_hi + 1e-9, "y({lo}) = {y_lo} > y({hi}) = {y_hi}");
    }

    #[test]
    fn hedges_map_unit_interval_to_itself(x in 0.0f64..=1.0) {
        for h in Hedge::ALL {
            let y = h.apply(x);
            prop_assert!((0.0..=1.0).contains(&y), "{h:?}({x}) = {y}");
        }
    }
}

/// The benchmark engines (`benches/fixtures/`), at the resolutions they are measured at,
/// agree with the naive evaluation over a grid of inputs.
#[test]
fn benchmark_engines_agree_with_reference() {
    let root = env!("CARGO_MANIFEST_DIR");
    for name in ["narrow", "wide", "crowded"] {
        let text = std::fs::read_to_string(format!("{root}/benches/fixtures/{name}.fll")).unwrap();
        let mut e = fll::import(&text, name).unwrap();
        for resolution in [100, 200, 500] {
            for out in &mut e.outputs {
                out.defuzzifier = Some(Defuzzifier::Centroid { resolution });
            }
            let mut fast = Inference::new(&e).unwrap();
            let mut naive = Reference::new(&e).unwrap();
            let (a, b) = (&e.inputs[0], &e.inputs[1]);
            for i in 0..=60 {
                for j in 0..=60 {
                    let input = [
                        a.minimum + (a.maximum - a.minimum) * i as f64 / 60.0,
                        b.minimum + (b.maximum - b.minimum) * j as f64 / 60.0,
                    ];
                    fast.set_inputs(&input);
                    fast.process();
                    let expected = naive.process(&input).to_vec();
                    for (o, (x, y)) in fast.outputs().iter().zip(&expected).enumerate() {
                        let scale = e.outputs[o].maximum - e.outputs[o].minimum;
                        assert!(
                            same(*x, *y, 1e-12 * scale),
                            "{name} at {resolution}, {input:?}, output {o}: {x} vs {y}"
                        );
                    }
                }
            }
        }
    }
}

/// A random Takagi-Sugeno engine whose output terms are each concluded by one rule (so its
/// outputs are folded column by column in [`Inference::process_columns`]): constant, linear
/// or function terms (formulas of the degree and the inputs), any conjunction and disjunction,
/// hedges, weights, sometimes a second output.
fn sugeno_engine(seed: u64) -> Engine {
    let rng = &mut stream(seed, 2, 0);
    let mut e = Engine::new("sugeno");
    let n_in = 1 + (unit(rng) * 3.0) as usize;
    let names: Vec<String> = (0..n_in).map(|i| format!("in{i}")).collect();
    for i in 0..n_in {
        let mut v = random_input(rng, i, 4.0, &names);
        v.lock_range = unit(rng) < 0.3;
        e.inputs.push(v);
    }
    let mut block = RuleBlock::mamdani("rules");
    block.conjunction = Some(pick(rng, &TNorm::ALL));
    block.disjunction = Some(pick(rng, &SNorm::ALL));
    e.rule_blocks.push(block);
    let rules = 1 + (unit(rng) * 20.0) as usize;
    for o in 0..1 + (unit(rng) * 2.0) as usize {
        let mut v = OutputVariable::new(&format!("out{o}"), -10.0, 10.0);
        for t in 0..rules {
            let term = if unit(rng) < 0.3 {
                Term::Constant { value: uniform(rng, -10.0, 10.0) }
            } else if unit(rng) < 0.2 {
                let k = ((unit(rng) * n_in as f64) as usize).min(n_in - 1);
                let (a, b) = (uniform(rng, -2.0, 2.0), uniform(rng, -2.0, 2.0));
                Term::function(&format!("{a} * in{k} - {b} * x^2 + fmod(in{k}, 1.5)")).unwrap()
            } else {
                let n = n_in + usize::from(unit(rng) < 0.7);
                Term::Linear { coefficients: (0..n).map(|_| uniform(rng, -2.0, 2.0)).collect() }
            };
            v = v.term(&format!("t{t}"), term);
        }
        v.defuzzifier = Some(pick(
            rng,
            &[
                Defuzzifier::WeightedAverage { kind: WeightedKind::TakagiSugeno },
                Defuzzifier::WeightedSum { kind: WeightedKind::Automatic },
            ],
        ));
        v.aggregation = None;
        v.default_value = if unit(rng) < 0.5 { f64::NAN } else { uniform(rng, -10.0, 10.0) };
        v.lock_previous = unit(rng) < 0.3;
        v.lock_range = unit(rng) < 0.3;
        e.outputs.push(v);
    }
    let hedges = ["", "", "", "not ", "very ", "somewhat ", "extremely ", "seldom "];
    for r in 0..rules {
        let mut text = String::from("if ");
        for p in 0..1 + (unit(rng) * 3.0) as usize {
            if p > 0 {
                text.push_str(pick(rng, &[" and ", " or "]));
            }
            let i = (unit(rng) * n_in as f64) as usize;
            let t = (unit(rng) * e.inputs[i].terms.len() as f64) as usize;
            text.push_str(&format!("in{i} is {}t{t}", pick(rng, &hedges)));
        }
        let conclusions: Vec<String> =
            (0..e.outputs.len()).map(|o| format!("out{o} is {}t{r}", pick(rng, &hedges))).collect();
        text.push_str(&format!(" then {}", conclusions.join(" and ")));
        if unit(rng) < 0.3 {
            text.push_str(&format!(" with {}", uniform(rng, 0.0, 1.0)));
        }
        e.add_rule(0, &text).unwrap_or_else(|err| panic!("{text}: {err}"));
    }
    e
}

/// A random Takagi-Sugeno engine of constant and linear output terms that several rules
/// conclude (so that [`Inference::process_columns`] merges their activations row by row), with
/// hedges on the conclusions, weights, and any aggregation or none.
fn merged_engine(seed: u64) -> Engine {
    let rng = &mut stream(seed, 4, 0);
    let mut e = Engine::new("merged");
    let n_in = 1 + (unit(rng) * 3.0) as usize;
    let names: Vec<String> = (0..n_in).map(|i| format!("in{i}")).collect();
    for i in 0..n_in {
        let mut v = random_input(rng, i, 4.0, &names);
        v.lock_range = unit(rng) < 0.3;
        e.inputs.push(v);
    }
    let mut block = RuleBlock::mamdani("rules");
    block.conjunction = Some(pick(rng, &TNorm::ALL));
    block.disjunction = Some(pick(rng, &SNorm::ALL));
    e.rule_blocks.push(block);
    let terms = 1 + (unit(rng) * 4.0) as usize;
    for o in 0..1 + (unit(rng) * 2.0) as usize {
        let mut v = OutputVariable::new(&format!("out{o}"), -10.0, 10.0);
        for t in 0..terms {
            let term = if unit(rng) < 0.4 {
                Term::Constant { value: uniform(rng, -10.0, 10.0) }
            } else {
                let n = n_in + usize::from(unit(rng) < 0.7);
                Term::Linear { coefficients: (0..n).map(|_| uniform(rng, -2.0, 2.0)).collect() }
            };
            v = v.term(&format!("t{t}"), term);
        }
        v.defuzzifier = Some(pick(
            rng,
            &[
                Defuzzifier::WeightedAverage { kind: WeightedKind::TakagiSugeno },
                Defuzzifier::WeightedSum { kind: WeightedKind::Automatic },
            ],
        ));
        v.aggregation = if unit(rng) < 0.5 { None } else { Some(pick(rng, &SNorm::ALL)) };
        v.default_value = if unit(rng) < 0.5 { f64::NAN } else { uniform(rng, -10.0, 10.0) };
        v.lock_previous = unit(rng) < 0.3;
        v.lock_range = unit(rng) < 0.3;
        e.outputs.push(v);
    }
    let hedges = ["", "", "", "not ", "very ", "somewhat ", "extremely ", "seldom "];
    for _ in 0..2 + (unit(rng) * 12.0) as usize {
        let mut text = String::from("if ");
        for p in 0..1 + (unit(rng) * 3.0) as usize {
            if p > 0 {
                text.push_str(pick(rng, &[" and ", " or "]));
            }
            let i = (unit(rng) * n_in as f64) as usize;
            let t = (unit(rng) * e.inputs[i].terms.len() as f64) as usize;
            text.push_str(&format!("in{i} is {}t{t}", pick(rng, &hedges)));
        }
        let conclusions: Vec<String> = (0..e.outputs.len())
            .map(|o| format!("out{o} is {}t{}", pick(rng, &hedges), (unit(rng) * terms as f64) as usize))
            .collect();
        text.push_str(&format!(" then {}", conclusions.join(" and ")));
        if unit(rng) < 0.3 {
            text.push_str(&format!(" with {}", uniform(rng, 0.0, 1.0)));
        }
        e.add_rule(0, &text).unwrap_or_else(|err| panic!("{text}: {err}"));
    }
    e
}

/// `rows` rows of inputs for `engine` from `seed`: mostly within the ranges, some outside,
/// some NaN.
fn input_columns(engine: &Engine, seed: u64, rows: usize) -> Vec<Vec<f64>> {
    let rng = &mut stream(seed, 3, 0);
    let columns = engine.inputs.iter().map(|v| {
        let span = v.maximum - v.minimum;
        (0..rows)
            .map(|_| match (unit(rng) * 40.0) as usize {
                0 => f64::NAN,
                1..=3 => uniform(rng, v.minimum - span, v.maximum + span),
                _ => uniform(rng, v.minimum, v.maximum),
            })
            .collect::<Vec<f64>>()
    });
    columns.collect()
}

/// Column-wise evaluation gives, bit for bit, what row-by-row evaluation gives.
fn assert_columns_equal_rows(engine: &Engine, seed: u64, rows: usize) {
    let columns = input_columns(engine, seed, rows);
    let mut scalar = Inference::new(engine).unwrap();
    let mut batch = scalar.clone();
    let mut out = vec![vec![0.0; rows]; engine.outputs.len()];
    let inputs: Vec<&[f64]> = columns.iter().map(Vec::as_slice).collect();
    let mut outputs: Vec<&mut [f64]> = out.iter_mut().map(Vec::as_mut_slice).collect();
    batch.process_columns(&inputs, &mut outputs);
    let mut row = vec![0.0; engine.inputs.len()];
    for r in 0..rows {
        for (x, c) in row.iter_mut().zip(&columns) {
            *x = c[r];
        }
        scalar.set_inputs(&row);
        scalar.process();
        for (o, &want) in scalar.outputs().iter().enumerate() {
            let got = out[o][r];
            assert!(
                got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                "row {r} {row:?}, output {o}: columns give {got}, rows {want}\n{}",
                fll::export(engine)
            );
        }
    }
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
    assert_eq!(bits(batch.inputs()), bits(scalar.inputs()), "inputs after the last row");
    for (o, (a, b)) in batch.outputs().iter().zip(scalar.outputs()).enumerate() {
        assert!(a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()), "output {o} after the last row");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// `process_columns` equals `process` row by row on engines of every family, over several
    /// chunks of rows.
    #[test]
    fn columns_equal_rows(seed in any::<u64>(), rows in 0usize..700) {
        assert_columns_equal_rows(&random_engine(seed), seed, rows);
        assert_columns_equal_rows(&mamdani_engine(seed), seed, rows);
        assert_columns_equal_rows(&sugeno_engine(seed), seed, rows);
        assert_columns_equal_rows(&merged_engine(seed), seed, rows);
    }
}

/// The same on the engines the repository ships: the fixtures (formulas reading outputs among
/// them), the benchmark engines and every engine of the navigation scripts.
#[test]
fn shipped_engines_columns_equal_rows() {
    let root = env!("CARGO_MANIFEST_DIR");
    let mut engines = Vec::new();
    let shipped = [
        "tests/fixtures/fuzzy/tipper.fll",
        "tests/fuzz_corpus/fll/function.fll",
        "benches/fixtures/narrow.fll",
        "benches/fixtures/wide.fll",
        "benches/fixtures/crowded.fll",
        "scripts/nav.rhai",
        "scripts/simple_nav.rhai",
    ];
    for path in shipped {
        engines.extend(strider::cli::fuzzy::load_engines(&std::path::Path::new(root).join(path), None).unwrap());
    }
    assert!(engines.len() >= 6);
    for (k, engine) in engines.iter().enumerate() {
        assert_columns_equal_rows(engine, k as u64, 2000);
    }
}
