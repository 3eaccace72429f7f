//! Hand-checked fuzzy engines: each expected value is computed here independently, by hand or
//! by a deliberately naive evaluation written in the test itself.

use strider::fuzzy::engine::Comparison;
use strider::fuzzy::{
    Activation, Defuzzifier, Engine, Inference, InputVariable, Network, OutputVariable, RuleBlock, SNorm, TNorm, Term,
    WeightedKind, fll,
};

fn tri(a: f64, b: f64, c: f64) -> Term {
    Term::Triangle { a, b, c, height: 1.0 }
}

fn ramp(start: f64, end: f64) -> Term {
    Term::Ramp { start, end, height: 1.0 }
}

fn run(engine: &Engine, inputs: &[f64]) -> Vec<f64> {
    let mut inf = Inference::new(engine).expect("valid engine");
    inf.set_inputs(inputs);
    inf.process();
    inf.outputs().to_vec()
}

/// x in [0, 1] with a rising ramp; y in [0, 10] with a falling triangle; one rule.
fn clipped_triangle(resolution: usize, implication: TNorm) -> Engine {
    let mut e = Engine::new("clip");
    e.inputs.push(InputVariable::new("x", 0.0, 1.0).term("a", ramp(0.0, 1.0)));
    let mut y = OutputVariable::new("y", 0.0, 10.0).term("lo", tri(0.0, 0.0, 10.0));
    y.defuzzifier = Some(Defuzzifier::Centroid { resolution });
    e.outputs.push(y);
    let mut b = RuleBlock::mamdani("rules");
    b.implication = Some(implication);
    e.rule_blocks.push(b);
    e.add_rule(0, "if x is a then y is lo").unwrap();
    e
}

#[test]
fn mamdani_centroid_matches_a_naive_sum() {
    for (x, n) in [(0.5, 200), (0.25, 100), (0.9, 37)] {
        let e = clipped_triangle(n, TNorm::Minimum);
        let (mut area, mut moment) = (0.0, 0.0);
        for i in 0..n {
            let yi = (i as f64 + 0.5) * 10.0 / n as f64;
            let mu = f64::min(x, 1.0 - yi / 10.0);
            area += mu;
            moment += mu * yi;
        }
        let got = run(&e, &[x])[0];
        assert!((got - moment / area).abs() < 1e-12, "x={x}: {got} vs {}", moment / area);
    }
}

#[test]
fn larsen_scaling_keeps_the_centroid() {
    // Scaling a set does not move its centroid: the triangle's sampled centroid whatever x.
    let n = 100;
    let e = clipped_triangle(n, TNorm::AlgebraicProduct);
    let (mut area, mut moment) = (0.0, 0.0);
    for i in 0..n {
        let yi = (i as f64 + 0.5) * 10.0 / n as f64;
        area += 1.0 - yi / 10.0;
        moment += (1.0 - yi / 10.0) * yi;
    }
    for x in [0.1, 0.5, 1.0] {
        assert!((run(&e, &[x])[0] - moment / area).abs() < 1e-12);
    }
}

#[test]
fn takagi_sugeno_by_hand() {
    let mut e = Engine::new("ts");
    e.inputs.push(InputVariable::new("x", 0.0, 10.0).term("low", ramp(10.0, 0.0)).term("high", ramp(0.0, 10.0)));
    let mut y = OutputVariable::new("y", -100.0, 100.0)
        .term("flat", Term::Constant { value: 2.0 })
        .term("slope", Term::Linear { coefficients: vec![3.0, 1.0] });
    y.defuzzifier = Some(Defuzzifier::WeightedAverage { kind: WeightedKind::Automatic });
    y.aggregation = None;
    e.outputs.push(y);
    let mut b = RuleBlock::mamdani("ts");
    b.implication = None;
    e.rule_blocks.push(b);
    e.add_rule(0, "if x is low then y is flat").unwrap();
    e.add_rule(0, "if x is high then y is slope").unwrap();
    // x = 4: w_low = 0.6, w_high = 0.4; z = 2 and 3·4 + 1 = 13 → (1.2 + 5.2) / 1.0.
    assert!((run(&e, &[4.0])[0] - 6.4).abs() < 1e-12);
    // Weighted sum: 1.2 + 5.2.
    e.outputs[0].defuzzifier = Some(Defuzzifier::WeightedSum { kind: WeightedKind::TakagiSugeno });
    assert!((run(&e, &[4.0])[0] - 6.4).abs() < 1e-12);
    assert!((run(&e, &[5.0])[0] - (0.5 * 2.0 + 0.5 * 16.0)).abs() < 1e-12);
}

#[test]
fn no_rule_fired_gives_default_or_previous_never_a_panic() {
    let mut e = clipped_triangle(100, TNorm::Minimum);
    e.outputs[0].default_value = 7.0;
    assert_eq!(run(&e, &[0.0]), vec![7.0]);
    e.outputs[0].default_value = f64::NAN;
    assert!(run(&e, &[0.0])[0].is_nan());
    assert!(run(&e, &[f64::NAN])[0].is_nan());
    e.outputs[0].lock_previous = true;
    let mut inf = Inference::new(&e).unwrap();
    inf.set_inputs(&[0.5]);
    inf.process();
    let fired = inf.outputs()[0];
    assert!(fired.is_finite());
    for x in [0.0, f64::NAN, -3.0] {
        inf.set_inputs(&[x]);
        inf.process();
        assert_eq!(inf.outputs()[0], fired, "x={x}");
    }
    // An engine with no rules at all.
    let mut bare = clipped_triangle(100, TNorm::Minimum);
    bare.rule_blocks[0].rules.clear();
    bare.outputs[0].default_value = 1.5;
    assert_eq!(run(&bare, &[0.3]), vec![1.5]);
}

#[test]
fn lock_range_clamps_inputs_and_outputs() {
    let mut e = clipped_triangle(100, TNorm::Minimum);
    e.inputs[0].lock_range = true;
    assert_eq!(run(&e, &[5.0]), run(&e, &[1.0]));
    e.outputs[0].default_value = 50.0;
    e.outputs[0].lock_range = true;
    assert_eq!(run(&e, &[0.0]), vec![10.0]);
}

/// Four rules with degrees 0.1, 0.6, 0.3, 0.6 on constant outputs 1, 10, 100, 1000.
fn activation_engine(activation: Activation) -> Engine {
    let mut e = Engine::new("act");
    for (i, d) in [0.1, 0.6, 0.3, 0.6].iter().enumerate() {
        e.inputs.push(InputVariable::new(&format!("x{i}"), 0.0, 1.0).term("t", Term::Constant { value: *d }));
    }
    let mut y = OutputVariable::new("y", 0.0, 2000.0);
    for (i, v) in [1.0, 10.0, 100.0, 1000.0].iter().enumerate() {
        y = y.term(&format!("c{i}"), Term::Constant { value: *v });
    }
    y.defuzzifier = Some(Defuzzifier::WeightedSum { kind: WeightedKind::TakagiSugeno });
    y.aggregation = None;
    e.outputs.push(y);
    let mut b = RuleBlock::mamdani("b");
    b.activation = activation;
    e.rule_blocks.push(b);
    for i in 0..4 {
        e.add_rule(0, &format!("if x{i} is t then y is c{i}")).unwrap();
    }
    e
}

#[test]
fn activation_methods_by_hand() {
    let cases = [
        (Activation::General, 0.1 + 6.0 + 30.0 + 600.0),
        (Activation::First { rules: 2, threshold: 0.2 }, 6.0 + 30.0),
        (Activation::Last { rules: 1, threshold: 0.0 }, 600.0),
        (Activation::Highest { rules: 2 }, 6.0 + 600.0),
        (Activation::Lowest { rules: 2 }, 0.1 + 30.0),
        (Activation::Proportional, (0.1 + 6.0 + 30.0 + 600.0) / 1.6),
        (Activation::Threshold { comparison: Comparison::Less, value: 0.5 }, 0.1 + 30.0),
    ];
    for (activation, expected) in cases {
        let e = activation_engine(activation);
        let got = run(&e, &[0.0; 4])[0];
        assert!((got - expected).abs() < 1e-9, "{activation:?}: {got} vs {expected}");
    }
}

#[test]
fn rule_readout_reports_degrees_and_firing() {
    let e = activation_engine(Activation::Highest { rules: 1 });
    let mut inf = Inference::new(&e).unwrap();
    inf.process();
    let fired: Vec<(usize, f64, bool)> = inf.rule_activations().map(|r| (r.rule, r.degree, r.fired)).collect();
    assert_eq!(fired, vec![(0, 0.1, false), (1, 0.6, true), (2, 0.3, false), (3, 0.6, false)]);
}

#[test]
fn hedges_and_weights_by_hand() {
    let mut e = activation_engine(Activation::General);
    e.rule_blocks[0].rules.clear();
    e.add_rule(0, "if x1 is very t then y is c0 with 0.5").unwrap(); // 0.36 · 0.5 = 0.18
    e.add_rule(0, "if x0 is not t and x2 is somewhat t then y is c1").unwrap(); // min(0.9, √0.3)
    e.add_rule(0, "if x0 is any then y is extremely c2").unwrap(); // 1 → extremely(1) = 1
    let expected = 0.18 * 1.0 + 0.3f64.sqrt().min(0.9) * 10.0 + 100.0;
    assert!((run(&e, &[0.0; 4])[0] - expected).abs() < 1e-12);
}

#[test]
fn outputs_feed_rules_and_engines() {
    // Inside one engine: a later rule reads an earlier output's fuzzy set.
    let mut e = Engine::new("chain");
    e.inputs.push(InputVariable::new("x", 0.0, 1.0).term("a", ramp(0.0, 1.0)));
    let mut y = OutputVariable::new("y", 0.0, 1.0).term("on", Term::Constant { value: 1.0 });
    y.defuzzifier = Some(Defuzzifier::WeightedAverage { kind: WeightedKind::TakagiSugeno });
    let mut z = y.clone();
    z.name = "z".into();
    z.terms[0].term = Term::Constant { value: 0.5 };
    e.outputs.push(y);
    e.outputs.push(z);
    e.rule_blocks.push(RuleBlock::mamdani("first"));
    e.rule_blocks.push(RuleBlock::mamdani("second"));
    e.add_rule(0, "if x is a then y is on").unwrap();
    e.add_rule(1, "if y is very on then z is on").unwrap();
    let mut inf = Inference::new(&e).unwrap();
    inf.set_inputs(&[0.5]);
    inf.process();
    assert_eq!(inf.outputs(), &[1.0, 0.5]);
    let rule = inf.rule_activations().nth(1).unwrap();
    assert_eq!(rule.degree, 0.25);

    // Across engines: a network binds outputs to later inputs by name.
    let mut first = clipped_triangle(100, TNorm::Minimum);
    first.outputs[0].default_value = 0.0;
    let mut second = Engine::new("second");
    second.inputs.push(InputVariable::new("y", 0.0, 10.0).term("big", ramp(0.0, 10.0)));
    let mut w = OutputVariable::new("w", 0.0, 1.0).term("k", Term::Constant { value: 3.0 });
    w.defuzzifier = Some(Defuzzifier::WeightedSum { kind: WeightedKind::TakagiSugeno });
    second.outputs.push(w);
    second.rule_blocks.push(RuleBlock::mamdani("r"));
    second.add_rule(0, "if y is big then w is k").unwrap();
    let mut net = Network::new(&[first.clone(), second]).unwrap();
    assert_eq!(net.input_names().collect::<Vec<_>>(), vec!["x"]);
    net.process(&[0.5]);
    let y = net.output("y").unwrap();
    assert!((net.output("w").unwrap() - 3.0 * y / 10.0).abs() < 1e-12);
    assert_eq!(y, run(&first, &[0.5])[0]);
}

#[test]
fn every_operator_and_defuzzifier_survives_fll() {
    let mut e = clipped_triangle(100, TNorm::Minimum);
    e.add_rule(0, "if x is not a then y is lo with 0.25").unwrap();
    for t in TNorm::ALL {
        for s in SNorm::ALL {
            for d in [
                Defuzzifier::Centroid { resolution: 50 },
                Defuzzifier::Bisector { resolution: 60 },
                Defuzzifier::SmallestOfMaximum { resolution: 70 },
                Defuzzifier::LargestOfMaximum { resolution: 80 },
                Defuzzifier::MeanOfMaximum { resolution: 90 },
            ] {
                e.rule_blocks[0].implication = Some(t);
                e.outputs[0].aggregation = Some(s);
                e.outputs[0].defuzzifier = Some(d);
                let back = fll::import(&fll::export(&e), "x.fll").unwrap();
                assert_eq!(back.rule_blocks, e.rule_blocks);
                assert_eq!(fll::export(&back), fll::export(&e));
                for x in [0.0, 0.3, 0.8] {
                    let (a, b) = (run(&e, &[x])[0], run(&back, &[x])[0]);
                    assert!(a == b || (a.is_nan() && b.is_nan()), "{t:?} {s:?} {d:?} x={x}");
                }
            }
        }
    }
}
