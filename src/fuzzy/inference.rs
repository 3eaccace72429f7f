//! Running an engine: the fast, compiled inference used everywhere in strider (seed 000 §3.1).
//!
//! [`Inference::new`] validates an [`Engine`] and compiles it: propositions used by several
//! rules are evaluated once (plain triangles and trapezoids inline, without the general
//! membership dispatch), an antecedent that is one proposition or a chain of one connective
//! (`a and b and c`) is folded left to right without a stack, others become small postfix
//! programs, and every output term of an integral output is pre-sampled at the defuzzifier's
//! sample points together with the index span where it is non-zero. With maximum
//! aggregation, activations of the same output term are grouped first
//! (`max(T(d₁, μ), T(d₂, μ)) = T(max(d₁, d₂), μ)` for any T-norm; each conclusion knows its
//! `(term, implication)` slot, so grouping is a lookup), so each output term is folded in
//! once, and only over its support. Those shortcuts hold for degrees in `[0, 1]`; a step where
//! some degree leaves it (weights above 1, unbounded sums) is folded activation by activation
//! in firing order over every sample.
//!
//! `Function` terms run their compiled formulas with the names bound to this engine's inputs
//! and outputs (on the inference's own copy of the engine). An output term whose formula reads
//! a variable is sampled again when its output is defuzzified; a sample that is not finite
//! (a formula's NaN or infinity) sends its output down the firing-order fold as well.
//!
//! The centroid under maximum aggregation with minimum or product implication — the common
//! Mamdani and Larsen engines — has two paths when every sample of the output's terms is finite
//! and non-negative (so `max` folds the implied terms in any order to the same aggregate):
//! terms that overlap little are folded one at a time over their own support, the widest
//! written first, and the last fold also sums area and moment, so only the samples outside
//! that term are read again; terms that overlap heavily (their supports add up to at least
//! twice the span per four terms) are read four at a time over the whole span (zero outside
//! their support), one pass per four terms, then summed. A single term is summed straight from
//! its samples. Sums run in four independent lanes (one vector register, see `lanes`), so
//! they differ from the sequential sum only by rounding.
//!
//! On x86-64 processors with AVX2, aggregation and defuzzification run a copy of the same code
//! compiled for AVX2 (four doubles per vector instruction), chosen at run time, whose sums keep
//! their four lanes in one AVX2 register explicitly; Rust never fuses or reorders
//! floating-point operations, so both copies give the same bits.
//!
//! Semantics follow fuzzylite: a rule's degree is `weight · antecedent`; a rule fires when
//! its degree is positive (NaN never fires); an output on which no rule fired, or whose
//! result is undefined, takes its previous value (lock-previous) or its default value. Results agree with the naive
//! [`crate::fuzzy::reference`] evaluation to within floating-point rounding.
//!
//! Invariant: `process` allocates nothing and never panics.

use super::defuzz::{self, Weighted};
use super::engine::{Activation, Defuzzifier, Engine, EngineError, InputVariable, OutputVariable};
use super::lanes::{
    Implication, Minimum, Product, implied_into, implied_sums, max_into, max_sums, max4_into, max4_sums, sums,
};
use super::norm::{Hedge, SNorm, TNorm};
use super::rule::{Antecedent, VariableRef};
use super::term::Term;

/// Propositions with activation degree at or below this do not fire.
pub const FIRING_THRESHOLD: f64 = 0.0;

#[derive(Debug, Clone, PartialEq)]
pub(super) struct Prop {
    pub(super) source: VariableRef,
    pub(super) term: Option<usize>,
    pub(super) hedges: Vec<Hedge>,
}

/// How a proposition on an input is fuzzified.
#[derive(Debug, Clone, Copy)]
pub(super) enum Fuzzify {
    /// A plain triangle or trapezoid `(a, b, c, d, height)` of an enabled input, no hedges
    /// (a triangle is the trapezoid with `b = c`: both formulas give the same values).
    Trapezoid { input: usize, a: f64, b: f64, c: f64, d: f64, height: f64 },
    /// Anything else: the term's own membership, then the hedges.
    General,
}

#[derive(Debug, Clone, Copy)]
pub(super) enum Op {
    Load(u32),
    And,
    Or,
}

/// A rule's antecedent: most are one proposition or a left-to-right chain of one connective
/// (`a and b and c`), folded without a stack; others run their postfix program.
#[derive(Debug, Clone)]
pub(super) enum Condition {
    Chain { props: std::ops::Range<usize>, and: bool },
    Program,
}

#[derive(Debug, Clone)]
pub(super) struct CompiledRule {
    pub(super) program: std::ops::Range<usize>,
    pub(super) antecedent: Condition,
    pub(super) conclusions: std::ops::Range<usize>,
    pub(super) weight: f64,
}

#[derive(Debug, Clone)]
pub(super) struct CompiledConclusion {
    pub(super) output: usize,
    pub(super) term: usize,
    pub(super) hedges: Vec<Hedge>,
    /// Index of `(term, implication)` among the pairs concluded on this output.
    pub(super) slot: usize,
}

#[derive(Debug, Clone)]
pub(super) struct CompiledBlock {
    pub(super) enabled: bool,
    pub(super) conjunction: TNorm,
    pub(super) disjunction: SNorm,
    pub(super) implication: TNorm,
    pub(super) activation: Activation,
    pub(super) rules: std::ops::Range<usize>,
}

#[derive(Debug, Clone)]
pub(super) struct CompiledOutput {
    /// `terms × resolution` samples (integral outputs only).
    samples: Vec<f64>,
    /// Non-zero sample span per term.
    support: Vec<(usize, usize)>,
    resolution: usize,
    /// Aggregated membership buffer.
    mu: Vec<f64>,
    /// Activated terms this step as `(term, implication, degree)`, see [`record_activation`].
    activated: Vec<(usize, TNorm, f64)>,
    /// Every activation in firing order, kept for the rare step where a degree leaves
    /// `[0, 1]` (weights, unbounded sums) and the shortcuts above no longer hold.
    raw: Vec<(usize, TNorm, f64)>,
    /// Whether some degree in `raw` left `[0, 1]` this step.
    unbounded: bool,
    /// Integral output under maximum aggregation: activations of the same term and
    /// implication are merged (see [`record_activation`]) through `slot_pos`.
    grouped: bool,
    /// Per `(term, implication)` slot, its entry in `activated` this step (`usize::MAX`: none).
    slot_pos: Vec<usize>,
    /// Sample points `xᵢ` of the defuzzifier.
    xs: Vec<f64>,
    /// Every sample of every term is finite and non-negative: `max` then folds the implied
    /// terms in any order to the same aggregate, zero rows change nothing, and the centroid
    /// takes the fast paths of [`CompiledOutput::centroid_of_maximum`].
    plain: bool,
    /// `resolution` zeros: the row of an absent term.
    zeros: Vec<f64>,
    /// `resolution` values of scratch: an implied term.
    implied: Vec<f64>,
    /// Terms whose samples depend on the engine's variables (a [`Term::Function`] naming
    /// some): sampled again at each defuzzification, with the values of that moment.
    dynamic: Vec<usize>,
    /// `plain` over the other terms' samples.
    static_plain: bool,
    /// Some sample is NaN or infinite (a formula's): the implied terms are then folded in
    /// firing order over every sample, as without shortcuts.
    wild: bool,
    /// `wild` over the samples of the terms not in `dynamic`.
    static_wild: bool,
}

/// A compiled engine with its state (input values, output values, rule activations).
#[derive(Debug, Clone)]
pub struct Inference {
    pub(super) engine: Engine,
    pub(super) inputs: Vec<f64>,
    pub(super) outputs: Vec<f64>,
    pub(super) previous: Vec<f64>,
    pub(super) props: Vec<Prop>,
    pub(super) fuzzify: Vec<Fuzzify>,
    pub(super) prop_values: Vec<f64>,
    pub(super) program: Vec<Op>,
    pub(super) chains: Vec<u32>,
    pub(super) rules: Vec<CompiledRule>,
    pub(super) conclusions: Vec<CompiledConclusion>,
    pub(super) blocks: Vec<CompiledBlock>,
    pub(super) degrees: Vec<f64>,
    pub(super) fired: Vec<bool>,
    pub(super) outs: Vec<CompiledOutput>,
    pub(super) stack: Vec<f64>,
    pub(super) order: Vec<usize>,
}

/// How strongly one rule was activated in the last [`Inference::process`].
#[derive(Debug, Clone, PartialEq)]
pub struct RuleActivation {
    /// Index of the rule block.
    pub block: usize,
    /// Index of the rule within the block.
    pub rule: usize,
    /// Activation degree after weight and activation method (NaN when an input was NaN).
    pub degree: f64,
    /// Whether the rule fired (contributed to an output).
    pub fired: bool,
}

/// Rules that fire under `activation`, given their degrees. May rescale `degrees`
/// (proportional activation). `order` is scratch space.
pub(crate) fn select_rules(activation: Activation, degrees: &mut [f64], fired: &mut [bool], order: &mut Vec<usize>) {
    let positive = |d: f64| d > FIRING_THRESHOLD;
    match activation {
        Activation::General => {
            for (f, &d) in fired.iter_mut().zip(degrees.iter()) {
                *f = positive(d);
            }
        }
        Activation::Proportional => {
            let sum: f64 = degrees.iter().filter(|d| positive(**d)).sum();
            for (f, d) in fired.iter_mut().zip(degrees.iter_mut()) {
                *f = positive(*d);
                if *f {
                    *d /= sum;
                }
            }
        }
        Activation::First { rules, threshold } | Activation::Last { rules, threshold } => {
            fired.fill(false);
            let mut count = 0;
            let n = degrees.len();
            for k in 0..n {
                let i = if matches!(activation, Activation::First { .. }) { k } else { n - 1 - k };
                if count < rules && positive(degrees[i]) && degrees[i] >= threshold {
                    fired[i] = true;
                    count += 1;
                }
            }
        }
        Activation::Highest { rules } | Activation::Lowest { rules } => {
            fired.fill(false);
            order.clear();
            order.extend((0..degrees.len()).filter(|&i| positive(degrees[i])));
            // Rule order is kept among equal degrees.
            // (An unstable sort broken by rule index: the same order, without the buffer a
            // stable sort allocates.)
            if matches!(activation, Activation::Highest { .. }) {
                order.sort_unstable_by(|&a, &b| degrees[b].total_cmp(&degrees[a]).then(a.cmp(&b)));
            } else {
                order.sort_unstable_by(|&a, &b| degrees[a].total_cmp(&degrees[b]).then(a.cmp(&b)));
            }
            for &i in order.iter().take(rules) {
                fired[i] = true;
            }
        }
        Activation::Threshold { comparison, value } => {
            for (f, &d) in fired.iter_mut().zip(degrees.iter()) {
                *f = positive(d) && comparison.holds(d, value);
            }
        }
    }
}

/// The crisp value of an output after defuzzification. An undefined result (`None`: no rule
/// fired; or NaN) becomes the previous value under lock-previous when that is a number, else
/// the default value; then lock-range clamps.
pub(crate) fn finish_output(out: &OutputVariable, value: Option<f64>, previous: f64) -> f64 {
    let mut v = value.unwrap_or(f64::NAN);
    if v.is_nan() && out.lock_previous {
        v = previous;
    }
    if v.is_nan() {
        v = out.default_value;
    }
    if out.lock_range && !v.is_nan() { v.clamp(out.minimum, out.maximum) } else { v }
}

/// Records one activation of an output term. Weighted outputs keep one entry per term,
/// merged with the aggregation (a plain sum without one); integral outputs under maximum
/// aggregation merge entries of the same term and implication by their maximum, which gives
/// the same aggregate because every T-norm is monotone on `[0, 1]` (degrees outside it, from
/// weights or unbounded sums, are kept apart).
pub(crate) fn record_activation(list: &mut Vec<(usize, TNorm, f64)>, var: &OutputVariable, new: (usize, TNorm, f64)) {
    let weighted = var.defuzzifier.is_some_and(|d| d.resolution().is_none());
    if weighted {
        if let Some(e) = list.iter_mut().find(|e| e.0 == new.0) {
            e.2 = var.aggregation.unwrap_or(SNorm::UnboundedSum).apply(e.2, new.2);
            return;
        }
    } else if var.aggregation == Some(SNorm::Maximum)
        && (0.0..=1.0).contains(&new.2)
        && let Some(e) = list.iter_mut().find(|e| e.0 == new.0 && e.1 == new.1 && (0.0..=1.0).contains(&e.2))
    {
        if new.2 > e.2 {
            e.2 = new.2;
        }
        return;
    }
    list.push(new);
}

/// `hedges` applied last to first.
#[inline]
pub(crate) fn apply_hedges(hedges: &[Hedge], mut x: f64) -> f64 {
    for h in hedges.iter().rev() {
        x = h.apply(x);
    }
    x
}

/// Combines two antecedent degrees; NaN on either side gives NaN.
#[inline]
pub(crate) fn combine(a: f64, b: f64, op: impl FnOnce(f64, f64) -> f64) -> f64 {
    if a.is_nan() || b.is_nan() { f64::NAN } else { op(a, b) }
}

impl Inference {
    /// Validates and compiles `engine` (its formulas bound to its variables).
    pub fn new(engine: &Engine) -> Result<Inference, EngineError> {
        engine.validate()?;
        let mut bound = engine.clone();
        bound.bind_formulas();
        let engine = &bound;
        let mut props: Vec<Prop> = Vec::new();
        let mut program = Vec::new();
        let mut rules = Vec::new();
        let mut conclusions = Vec::new();
        let mut blocks = Vec::new();
        fn emit(a: &Antecedent, props: &mut Vec<Prop>, program: &mut Vec<Op>) {
            match a {
                Antecedent::Proposition(p) => {
                    let prop = Prop { source: p.variable, term: p.term, hedges: p.hedges.clone() };
                    let idx = props.iter().position(|q| *q == prop).unwrap_or_else(|| {
                        props.push(prop);
                        props.len() - 1
                    });
                    program.push(Op::Load(idx as u32));
                }
                Antecedent::And(l, r) => {
                    emit(l, props, program);
                    emit(r, props, program);
                    program.push(Op::And);
                }
                Antecedent::Or(l, r) => {
                    emit(l, props, program);
                    emit(r, props, program);
                    program.push(Op::Or);
                }
            }
        }
        let mut max_depth = 1;
        let mut chains = Vec::new();
        // Per output, the `(term, implication)` pairs its conclusions name.
        let mut pairs: Vec<Vec<(usize, TNorm)>> = vec![Vec::new(); engine.outputs.len()];
        for block in &engine.rule_blocks {
            let start = rules.len();
            let implication = block.implication.unwrap_or(TNorm::Minimum);
            for rule in &block.rules {
                let p0 = program.len();
                emit(&rule.antecedent, &mut props, &mut program);
                let c0 = conclusions.len();
                for c in &rule.consequent {
                    let known = &mut pairs[c.variable];
                    let slot = known.iter().position(|&k| k == (c.term, implication)).unwrap_or_else(|| {
                        known.push((c.term, implication));
                        known.len() - 1
                    });
                    conclusions.push(CompiledConclusion {
                        output: c.variable,
                        term: c.term,
                        hedges: c.hedges.clone(),
                        slot,
                    });
                }
                max_depth = max_depth.max(program.len() - p0);
                let antecedent = chain(&program[p0..], &mut chains);
                rules.push(CompiledRule {
                    program: p0..program.len(),
                    antecedent,
                    conclusions: c0..conclusions.len(),
                    weight: rule.weight,
                });
            }
            blocks.push(CompiledBlock {
                enabled: block.enabled,
                conjunction: block.conjunction.unwrap_or(TNorm::Minimum),
                disjunction: block.disjunction.unwrap_or(SNorm::Maximum),
                implication,
                activation: block.activation,
                rules: start..rules.len(),
            });
        }
        let mut outs: Vec<CompiledOutput> = engine.outputs.iter().map(compile_output).collect();
        // Room for every activation one step can record, so `process` never allocates.
        let mut per_output = vec![0usize; outs.len()];
        for c in &conclusions {
            per_output[c.output] += 1;
        }
        for ((out, n), known) in outs.iter_mut().zip(per_output).zip(&pairs) {
            out.raw.reserve(n);
            out.activated.reserve(n);
            out.slot_pos = vec![usize::MAX; known.len()];
        }
        let fuzzify = props.iter().map(|p| fuzzify_plan(engine, p)).collect();
        let n_rules = rules.len();
        Ok(Inference {
            engine: engine.clone(),
            inputs: vec![f64::NAN; engine.inputs.len()],
            outputs: vec![f64::NAN; engine.outputs.len()],
            previous: vec![f64::NAN; engine.outputs.len()],
            prop_values: vec![0.0; props.len()],
            props,
            fuzzify,
            program,
            chains,
            rules,
            conclusions,
            blocks,
            degrees: vec![0.0; n_rules],
            fired: vec![false; n_rules],
            outs,
            stack: Vec::with_capacity(max_depth),
            order: Vec::with_capacity(n_rules),
        })
    }

    /// The engine this inference runs.
    pub fn engine(&self) -> &Engine {
        &self.engine
    }

    /// Sets input `index` (out-of-range indices are ignored).
    pub fn set_input(&mut self, index: usize, value: f64) {
        if let Some(v) = self.inputs.get_mut(index) {
            *v = value;
        }
    }

    /// Sets the input called `name`; false if there is none.
    pub fn set_input_by_name(&mut self, name: &str, value: f64) -> bool {
        match self.engine.input_index(name) {
            Some(i) => {
                self.inputs[i] = value;
                true
            }
            None => false,
        }
    }

    /// Sets all inputs at once (extra values are ignored, missing ones keep their value).
    pub fn set_inputs(&mut self, values: &[f64]) {
        for (dst, src) in self.inputs.iter_mut().zip(values) {
            *dst = *src;
        }
    }

    /// Current input values.
    pub fn inputs(&self) -> &[f64] {
        &self.inputs
    }

    /// Output values of the last [`Inference::process`] (NaN before the first).
    pub fn outputs(&self) -> &[f64] {
        &self.outputs
    }

    /// The value of the output called `name`.
    pub fn output_by_name(&self, name: &str) -> Option<f64> {
        self.engine.output_index(name).map(|i| self.outputs[i])
    }

    /// Forgets output history (lock-previous) and sets every value to NaN.
    pub fn reset(&mut self) {
        self.inputs.fill(f64::NAN);
        self.outputs.fill(f64::NAN);
        self.previous.fill(f64::NAN);
        self.degrees.fill(0.0);
        self.fired.fill(false);
    }

    /// Rule activations of the last [`Inference::process`], in block and rule order.
    pub fn rule_activations(&self) -> impl Iterator<Item = RuleActivation> + '_ {
        self.blocks.iter().enumerate().flat_map(move |(b, block)| {
            block.rules.clone().enumerate().map(move |(r, i)| RuleActivation {
                block: b,
                rule: r,
                degree: self.degrees[i],
                fired: self.fired[i],
            })
        })
    }

    /// Membership degree of every term of input `index` at its current value.
    pub fn input_memberships(&self, index: usize) -> Vec<f64> {
        let var = &self.engine.inputs[index];
        let x = self.inputs[index];
        var.terms.iter().map(|t| t.term.membership_in(x, &self.inputs, &self.outputs)).collect()
    }

    /// Runs one inference: fuzzify, fire rules, aggregate, defuzzify.
    pub fn process(&mut self) {
        let Inference {
            engine,
            inputs,
            outputs,
            previous,
            props,
            fuzzify,
            prop_values,
            program,
            chains,
            rules,
            conclusions,
            blocks,
            degrees,
            fired,
            outs,
            stack,
            order,
        } = self;
        // Fuzzify: lock-range clamps inputs, then every distinct input proposition is evaluated
        // once. Propositions on outputs are evaluated when a rule reads them.
        for (x, var) in inputs.iter_mut().zip(&engine.inputs) {
            *x = clamp_input(var, *x);
        }
        for ((value, prop), plan) in prop_values.iter_mut().zip(props.iter()).zip(fuzzify.iter()) {
            if let Fuzzify::Trapezoid { input, a, b, c, d, height } = *plan {
                *value = trapezoid(inputs.get(input).copied().unwrap_or(f64::NAN), a, b, c, d, height);
            } else if let VariableRef::Input(i) = prop.source {
                *value = input_proposition(engine, prop, i, inputs, outputs);
            }
        }
        start_step(outs);
        previous.copy_from_slice(outputs);
        // Rules, block by block. General activation fires rule by rule, so a rule reading an
        // output sees the rules before it; the other methods select among all degrees first.
        for block in blocks.iter() {
            let range = block.rules.clone();
            if !block.enabled {
                degrees[range.clone()].fill(0.0);
                fired[range].fill(false);
                continue;
            }
            let load = |p: u32, outs: &[CompiledOutput]| -> f64 {
                let p = p as usize;
                match props[p].source {
                    VariableRef::Input(_) => prop_values[p],
                    VariableRef::Output(o) => output_proposition(&props[p], &engine.outputs[o], &outs[o]),
                }
            };
            let general = block.activation == Activation::General;
            for i in range.clone() {
                let rule = &rules[i];
                let value = antecedent(rule, block, chains, program, stack, |p| load(p, outs));
                degrees[i] = rule.weight * value;
                if general {
                    fired[i] = degrees[i] > FIRING_THRESHOLD;
                    if fired[i] {
                        trigger(engine, &conclusions[rule.conclusions.clone()], block.implication, degrees[i], outs);
                    }
                }
            }
            if !general {
                select_rules(block.activation, &mut degrees[range.clone()], &mut fired[range.clone()], order);
                for i in range.filter(|&i| fired[i]) {
                    trigger(engine, &conclusions[rules[i].conclusions.clone()], block.implication, degrees[i], outs);
                }
            }
        }
        defuzzify(engine, outs, inputs, outputs, previous, |_| true);
    }
}

/// `x` clamped to the range of `var` under lock-range (NaN stays NaN).
#[inline]
pub(super) fn clamp_input(var: &InputVariable, x: f64) -> f64 {
    if var.lock_range && !x.is_nan() { x.clamp(var.minimum, var.maximum) } else { x }
}

/// Degree of `prop` on input `i` (a disabled input gives 0) through the term's own membership
/// (a formula reading the current `inputs` and `outputs`) and the hedges.
pub(super) fn input_proposition(engine: &Engine, prop: &Prop, i: usize, inputs: &[f64], outputs: &[f64]) -> f64 {
    let var = &engine.inputs[i];
    if !var.enabled {
        return 0.0;
    }
    let base = match prop.term {
        Some(t) if prop.hedges.last() != Some(&Hedge::Any) => {
            var.terms[t].term.membership_in(inputs[i], inputs, outputs)
        }
        _ => f64::NAN,
    };
    apply_hedges(&prop.hedges, base)
}

/// Forgets the activations of the previous step.
pub(super) fn start_step(outs: &mut [CompiledOutput]) {
    for out in outs.iter_mut() {
        out.activated.clear();
        out.raw.clear();
        out.unbounded = false;
        out.slot_pos.fill(usize::MAX);
    }
}

/// The degree of `rule`'s antecedent, its propositions read through `load`.
#[inline]
pub(super) fn antecedent(
    rule: &CompiledRule,
    block: &CompiledBlock,
    chains: &[u32],
    program: &[Op],
    stack: &mut Vec<f64>,
    load: impl Fn(u32) -> f64,
) -> f64 {
    match &rule.antecedent {
        Condition::Chain { props: chain, and } => {
            let chain = &chains[chain.clone()];
            let mut acc = chain.first().map_or(f64::NAN, |&p| load(p));
            for &p in chain.iter().skip(1) {
                let b = load(p);
                acc = if *and {
                    combine(acc, b, |a, b| block.conjunction.apply(a, b))
                } else {
                    combine(acc, b, |a, b| block.disjunction.apply(a, b))
                };
            }
            acc
        }
        Condition::Program => {
            stack.clear();
            for op in &program[rule.program.clone()] {
                let v = match *op {
                    Op::Load(p) => load(p),
                    Op::And => {
                        let b = stack.pop().unwrap_or(f64::NAN);
                        let a = stack.pop().unwrap_or(f64::NAN);
                        combine(a, b, |a, b| block.conjunction.apply(a, b))
                    }
                    Op::Or => {
                        let b = stack.pop().unwrap_or(f64::NAN);
                        let a = stack.pop().unwrap_or(f64::NAN);
                        combine(a, b, |a, b| block.disjunction.apply(a, b))
                    }
                };
                stack.push(v);
            }
            stack.pop().unwrap_or(f64::NAN)
        }
    }
}

/// Records the `conclusions` of a rule that fired with `degree` on their (enabled) outputs.
pub(super) fn trigger(
    engine: &Engine,
    conclusions: &[CompiledConclusion],
    implication: TNorm,
    degree: f64,
    outs: &mut [CompiledOutput],
) {
    for c in conclusions {
        let var = &engine.outputs[c.output];
        if !var.enabled {
            continue;
        }
        let new = (c.term, implication, apply_hedges(&c.hedges, degree));
        let out = &mut outs[c.output];
        out.raw.push(new);
        let unit = (0.0..=1.0).contains(&new.2);
        out.unbounded |= !unit;
        if out.grouped && unit {
            // The first in-range entry of this term and implication, as in
            // `record_activation`, found through its slot.
            match out.slot_pos.get(c.slot).copied() {
                Some(k) if k < out.activated.len() => {
                    let e = &mut out.activated[k];
                    if new.2 > e.2 {
                        e.2 = new.2;
                    }
                }
                _ => {
                    if let Some(k) = out.slot_pos.get_mut(c.slot) {
                        *k = out.activated.len();
                    }
                    out.activated.push(new);
                }
            }
        } else if out.grouped {
            out.activated.push(new);
        } else {
            record_activation(&mut out.activated, var, new);
        }
    }
}

/// Defuzzifies the enabled outputs `wanted` accepts from the activations recorded this step
/// into `outputs` (an output with none, or an undefined result, falls back as
/// [`finish_output`] says).
pub(super) fn defuzzify(
    engine: &Engine,
    outs: &mut [CompiledOutput],
    inputs: &[f64],
    outputs: &mut [f64],
    previous: &[f64],
    wanted: impl Fn(usize) -> bool,
) {
    for (o, var) in engine.outputs.iter().enumerate() {
        if !var.enabled || !wanted(o) {
            continue;
        }
        let out = &mut outs[o];
        let value = if out.activated.is_empty() {
            None
        } else {
            match var.defuzzifier {
                None => None,
                Some(d @ (Defuzzifier::WeightedAverage { kind } | Defuzzifier::WeightedSum { kind })) => {
                    let sum_only = matches!(d, Defuzzifier::WeightedSum { .. });
                    // Sixteen activations at a time from the stack, summed in order.
                    let mut list = [Weighted { term: &var.terms[0].term, degree: 0.0 }; 16];
                    let mut acc = (0.0, 0.0);
                    for chunk in out.activated.chunks(list.len()) {
                        for (slot, a) in list.iter_mut().zip(chunk) {
                            *slot = Weighted { term: &var.terms[a.0].term, degree: a.2 };
                        }
                        acc = defuzz::weighted_fold(kind, &list[..chunk.len()], inputs, outputs, acc);
                    }
                    Some(defuzz::weighted_result(acc, sum_only))
                }
                Some(d) => {
                    if var.aggregation.is_none() && out.activated.len() > 1 {
                        None
                    } else {
                        if !out.dynamic.is_empty() {
                            out.resample(var, inputs, outputs);
                        }
                        Some(out.aggregate_and_defuzzify(&d, var))
                    }
                }
            }
        };
        outputs[o] = finish_output(var, value, previous[o]);
    }
}

/// Degree of `output is hedges term` from the activations recorded so far: the term's
/// activations combined with the output's aggregation (a plain sum without one).
pub(crate) fn output_proposition_degree(
    hedges: &[Hedge],
    term: Option<usize>,
    var: &OutputVariable,
    activated: &[(usize, TNorm, f64)],
) -> f64 {
    if !var.enabled {
        return 0.0;
    }
    let base = match term {
        Some(t) if hedges.last() != Some(&Hedge::Any) => {
            let aggregation = var.aggregation.unwrap_or(SNorm::UnboundedSum);
            activated.iter().filter(|a| a.0 == t).fold(0.0, |acc, a| aggregation.apply(acc, a.2))
        }
        _ => f64::NAN,
    };
    apply_hedges(hedges, base)
}

fn output_proposition(prop: &Prop, var: &OutputVariable, out: &CompiledOutput) -> f64 {
    output_proposition_degree(&prop.hedges, prop.term, var, &out.activated)
}

/// The stack-free form of an antecedent's postfix `program` when it is one proposition or a
/// left-to-right chain of one connective (`L L op L op …`); its propositions go to `chains`.
fn chain(program: &[Op], chains: &mut Vec<u32>) -> Condition {
    let start = chains.len();
    let Some((&Op::Load(first), rest)) = program.split_first() else {
        return Condition::Program;
    };
    chains.push(first);
    let mut and = None;
    for pair in rest.chunks(2) {
        match *pair {
            [Op::Load(p), op @ (Op::And | Op::Or)]
                if *and.get_or_insert(matches!(op, Op::And)) == matches!(op, Op::And) =>
            {
                chains.push(p);
            }
            _ => {
                chains.truncate(start);
                return Condition::Program;
            }
        }
    }
    Condition::Chain { props: start..chains.len(), and: and.unwrap_or(true) }
}

/// How proposition `prop` is fuzzified (see [`Fuzzify`]).
fn fuzzify_plan(engine: &Engine, prop: &Prop) -> Fuzzify {
    let (VariableRef::Input(i), Some(t), true) = (prop.source, prop.term, prop.hedges.is_empty()) else {
        return Fuzzify::General;
    };
    let var = &engine.inputs[i];
    if !var.enabled {
        return Fuzzify::General;
    }
    match var.terms[t].term {
        Term::Triangle { a, b, c, height } => Fuzzify::Trapezoid { input: i, a, b, c: b, d: c, height },
        Term::Trapezoid { a, b, c, d, height } => Fuzzify::Trapezoid { input: i, a, b, c, d, height },
        _ => Fuzzify::General,
    }
}

/// Membership of `x` in the trapezoid `(a, b, c, d)` times `height`, with the formulas of
/// [`Term::membership`] for triangles and trapezoids (infinite `a` or `d` make shoulders).
#[inline]
fn trapezoid(x: f64, a: f64, b: f64, c: f64, d: f64, height: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    height * super::term::trapezoid(x, a, b, c, d)
}

fn compile_output(var: &OutputVariable) -> CompiledOutput {
    let resolution = var.defuzzifier.and_then(|d| d.resolution()).unwrap_or(0);
    let mut samples = Vec::with_capacity(resolution * var.terms.len());
    let mut support = Vec::with_capacity(var.terms.len());
    for t in &var.terms {
        let start = samples.len();
        samples.extend(
            (0..resolution).map(|i| t.term.membership(defuzz::sample_x(var.minimum, var.maximum, resolution, i))),
        );
        let row = &samples[start..];
        let lo = row.iter().position(|y| *y != 0.0).unwrap_or(resolution);
        let hi = row.iter().rposition(|y| *y != 0.0).map_or(lo, |i| i + 1);
        support.push((lo, hi));
    }
    let dynamic: Vec<usize> = if resolution > 0 {
        var.terms.iter().enumerate().filter(|(_, t)| t.term.depends_on_inputs()).map(|(i, _)| i).collect()
    } else {
        Vec::new()
    };
    let static_plain = samples
        .chunks(resolution.max(1))
        .enumerate()
        .filter(|(t, _)| !dynamic.contains(t))
        .all(|(_, row)| row.iter().all(|s| s.is_finite() && *s >= 0.0));
    let static_wild = samples
        .chunks(resolution.max(1))
        .enumerate()
        .filter(|(t, _)| !dynamic.contains(t))
        .any(|(_, row)| row.iter().any(|s| !s.is_finite()));
    CompiledOutput {
        support,
        resolution,
        dynamic,
        static_plain,
        wild: static_wild,
        static_wild,
        mu: vec![0.0; resolution],
        activated: Vec::with_capacity(var.terms.len()),
        raw: Vec::new(),
        unbounded: false,
        grouped: resolution > 0 && var.aggregation == Some(SNorm::Maximum),
        slot_pos: Vec::new(),
        xs: (0..resolution).map(|i| defuzz::sample_x(var.minimum, var.maximum, resolution, i)).collect(),
        plain: samples.iter().all(|s| s.is_finite() && *s >= 0.0),
        zeros: vec![0.0; resolution],
        implied: vec![0.0; resolution],
        samples,
    }
}

impl CompiledOutput {
    /// Samples the terms that read the engine's variables again, at their current values
    /// (`inputs`, and `outputs` as far as they are defuzzified this step), with their
    /// supports and whether every sample is still plain.
    fn resample(&mut self, var: &OutputVariable, inputs: &[f64], outputs: &[f64]) {
        let n = self.resolution;
        let mut plain = self.static_plain;
        let mut wild = self.static_wild;
        for &t in &self.dynamic {
            let (Some(row), Some(term)) = (self.samples.get_mut(t * n..(t + 1) * n), var.terms.get(t)) else {
                continue;
            };
            for (y, &x) in row.iter_mut().zip(&self.xs) {
                *y = term.term.membership_in(x, inputs, outputs);
            }
            plain &= row.iter().all(|s| s.is_finite() && *s >= 0.0);
            wild |= row.iter().any(|s| !s.is_finite());
            let lo = row.iter().position(|y| *y != 0.0).unwrap_or(n);
            let hi = row.iter().rposition(|y| *y != 0.0).map_or(lo, |i| i + 1);
            if let Some(s) = self.support.get_mut(t) {
                *s = (lo, hi);
            }
        }
        self.plain = plain;
        self.wild = wild;
    }

    /// Aggregates the activations recorded this step and defuzzifies them. On x86-64
    /// processors with AVX2 the same code is compiled for it (four doubles per vector
    /// instruction instead of two) and chosen at run time: the operations and their order
    /// are the same (no fused multiply-add, sums in the same lanes), so is every result, bit
    /// for bit.
    fn aggregate_and_defuzzify(&mut self, d: &Defuzzifier, var: &OutputVariable) -> f64 {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor runs AVX2 instructions, checked just above.
            return unsafe { self.aggregate_and_defuzzify_avx2(d, var) };
        }
        self.aggregate_and_defuzzify_here::<false>(d, var)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn aggregate_and_defuzzify_avx2(&mut self, d: &Defuzzifier, var: &OutputVariable) -> f64 {
        self.aggregate_and_defuzzify_here::<true>(d, var)
    }

    #[inline(always)]
    fn aggregate_and_defuzzify_here<const AVX2: bool>(&mut self, d: &Defuzzifier, var: &OutputVariable) -> f64 {
        if self.unbounded || self.wild {
            return self.aggregate_in_firing_order(d, var);
        }
        let n = self.resolution;
        let (mut lo, mut hi) = (n, 0);
        for a in &self.activated {
            let (l, h) = self.support[a.0];
            if l < h {
                lo = lo.min(l);
                hi = hi.max(h);
            }
        }
        if lo >= hi {
            // Every activated term is zero at every sample: no area.
            return if matches!(d, Defuzzifier::Centroid { .. }) {
                f64::NAN
            } else {
                self.mu.fill(0.0);
                defuzz::integral(d, var.minimum, var.maximum, &self.mu)
            };
        }
        let aggregation = var.aggregation.unwrap_or(SNorm::Maximum);
        if self.plain && matches!(d, Defuzzifier::Centroid { .. }) && aggregation == SNorm::Maximum {
            let same = |imp: TNorm| self.activated.iter().all(|a| a.1 == imp);
            if same(TNorm::Minimum) {
                return self.centroid_of_maximum::<AVX2, Minimum>(lo, hi);
            }
            if same(TNorm::AlgebraicProduct) {
                return self.centroid_of_maximum::<AVX2, Product>(lo, hi);
            }
        }
        let whole = !matches!(d, Defuzzifier::Centroid { .. });
        if whole {
            self.mu.fill(0.0);
        } else {
            self.mu[lo..hi].fill(0.0);
        }
        for &(term, implication, d) in &self.activated {
            let (l, h) = self.support[term];
            let row = &self.samples[term * n + l..term * n + h];
            let mu = &mut self.mu[l..h];
            match (implication, aggregation) {
                (TNorm::Minimum, SNorm::Maximum) => max_into::<Minimum>(mu, row, d),
                (TNorm::AlgebraicProduct, SNorm::Maximum) => max_into::<Product>(mu, row, d),
                (imp, agg) => {
                    // The implied term first, then folded in: two loops, each with its norm
                    // fixed, so that both run in vector registers.
                    let implied = &mut self.implied[..mu.len()];
                    imply_into(implied, row, d, imp);
                    aggregate_into(mu, implied, agg);
                }
            }
        }
        if whole {
            defuzz::integral(d, var.minimum, var.maximum, &self.mu)
        } else {
            let (area, moment) = sums::<AVX2>(&self.mu[lo..hi], &self.xs[lo..hi]);
            moment / area
        }
    }

    /// Centroid of the maximum of the activated terms, each implied by `imp(degree, sample)`
    /// (the same implication for all), over samples `lo..hi`, the union of their supports.
    /// The widest term is written first, the others folded in with `max`, and the last fold
    /// (of the next widest) also sums area and moment, so the aggregate is traversed once more
    /// only outside that term's support. A single term is summed straight from its samples.
    ///
    /// When the terms overlap so much that reading every term over the whole span costs less,
    /// the terms are instead taken four at a time over `lo..hi` (zero outside their support),
    /// one pass per four terms, the last one summing: see [`CompiledOutput::centroid_dense`].
    #[inline(always)]
    fn centroid_of_maximum<const AVX2: bool, I: Implication>(&mut self, lo: usize, hi: usize) -> f64 {
        let n = self.resolution;
        let count = self.activated.len();
        let span = |t: usize| self.support[t].1 - self.support[t].0;
        // Memory traffic per sample: about three accesses per term and sample of its support
        // one term at a time, six per sample of the span per four terms at once.
        let covered: usize = self.activated.iter().map(|a| span(a.0)).sum();
        if 2 * count.div_ceil(4) * (hi - lo) <= covered {
            return self.centroid_dense::<AVX2, I>(lo, hi);
        }
        let Some(widest) = (0..count).max_by_key(|&k| span(self.activated[k].0)) else {
            return f64::NAN;
        };
        let row = |t: usize| {
            let (l, h) = self.support[t];
            (l, h, &self.samples[t * n + l..t * n + h])
        };
        // The next widest is folded last; with no other term of non-empty support, the
        // widest alone is the aggregate.
        let last = (0..count).filter(|&k| k != widest).max_by_key(|&k| span(self.activated[k].0));
        let (term, _, d) = self.activated[widest];
        let (l, h, first) = row(term);
        let Some(last) = last.filter(|&k| span(self.activated[k].0) > 0) else {
            let (area, moment) = implied_sums::<AVX2, I>(first, &self.xs[l..h], d);
            return moment / area;
        };
        self.mu[lo..l].fill(0.0);
        implied_into::<I>(&mut self.mu[l..h], first, d);
        self.mu[h..hi].fill(0.0);
        for k in (0..count).filter(|&k| k != widest && k != last) {
            let (term, _, d) = self.activated[k];
            let (l, h, r) = row(term);
            max_into::<I>(&mut self.mu[l..h], r, d);
        }
        let (term, _, d) = self.activated[last];
        let (l, h, r) = row(term);
        let (a0, m0) = sums::<AVX2>(&self.mu[lo..l], &self.xs[lo..l]);
        let (a1, m1) = max_sums::<AVX2, I>(&self.mu[l..h], r, &self.xs[l..h], d);
        let (a2, m2) = sums::<AVX2>(&self.mu[h..hi], &self.xs[h..hi]);
        (m0 + m1 + m2) / (a0 + a1 + a2)
    }
    /// Centroid of the maximum of the implied activated terms over `lo..hi`, four terms per
    /// pass over the span (absent ones as zero rows at degree 0).
    #[inline(always)]
    fn centroid_dense<const AVX2: bool, I: Implication>(&mut self, lo: usize, hi: usize) -> f64 {
        let CompiledOutput { samples, resolution: n, mu, activated, xs, zeros, .. } = self;
        let n = *n;
        let span = hi - lo;
        let count = activated.len();
        let xs = &xs[lo..hi];
        let group = |g: usize| {
            let mut rows: [&[f64]; 4] = [&zeros[..span]; 4];
            let mut degrees = [0.0; 4];
            for j in 0..4 {
                if let Some(&(t, _, d)) = activated.get(4 * g + j) {
                    rows[j] = &samples[t * n + lo..t * n + hi];
                    degrees[j] = d;
                }
            }
            (rows, degrees)
        };
        let mu = &mut mu[lo..hi];
        let groups = count.div_ceil(4);
        for g in 0..groups {
            let (rows, degrees) = group(g);
            // The last pass sums what it would write.
            let (area, moment) = match (g == 0, g + 1 == groups) {
                (true, false) => {
                    max4_into::<true, I>(mu, rows, degrees);
                    continue;
                }
                (false, false) => {
                    max4_into::<false, I>(mu, rows, degrees);
                    continue;
                }
                (true, true) => max4_sums::<AVX2, true, I>(mu, rows, degrees, xs),
                (false, true) => max4_sums::<AVX2, false, I>(mu, rows, degrees, xs),
            };
            return moment / area;
        }
        let (area, moment) = sums::<AVX2>(mu, xs);
        moment / area
    }
}

/// `out[i] = imp(d, row[i])`, one loop per T-norm.
#[inline(always)]
fn imply_into(out: &mut [f64], row: &[f64], d: f64, imp: TNorm) {
    #[inline(always)]
    fn each(out: &mut [f64], row: &[f64], f: impl Fn(f64) -> f64) {
        for (o, &s) in out.iter_mut().zip(row) {
            *o = f(s);
        }
    }
    match imp {
        TNorm::Minimum => each(out, row, |s| TNorm::Minimum.apply(d, s)),
        TNorm::AlgebraicProduct => each(out, row, |s| TNorm::AlgebraicProduct.apply(d, s)),
        TNorm::BoundedDifference => each(out, row, |s| TNorm::BoundedDifference.apply(d, s)),
        TNorm::DrasticProduct => each(out, row, |s| TNorm::DrasticProduct.apply(d, s)),
        TNorm::EinsteinProduct => each(out, row, |s| TNorm::EinsteinProduct.apply(d, s)),
        TNorm::HamacherProduct => each(out, row, |s| TNorm::HamacherProduct.apply(d, s)),
        TNorm::NilpotentMinimum => each(out, row, |s| TNorm::NilpotentMinimum.apply(d, s)),
    }
}

/// `mu[i] = agg(mu[i], ys[i])`, one loop per S-norm.
#[inline(always)]
fn aggregate_into(mu: &mut [f64], ys: &[f64], agg: SNorm) {
    #[inline(always)]
    fn each(mu: &mut [f64], ys: &[f64], f: impl Fn(f64, f64) -> f64) {
        for (m, &y) in mu.iter_mut().zip(ys) {
            *m = f(*m, y);
        }
    }
    match agg {
        SNorm::Maximum => each(mu, ys, |m, y| SNorm::Maximum.apply(m, y)),
        SNorm::AlgebraicSum => each(mu, ys, |m, y| SNorm::AlgebraicSum.apply(m, y)),
        SNorm::BoundedSum => each(mu, ys, |m, y| SNorm::BoundedSum.apply(m, y)),
        SNorm::DrasticSum => each(mu, ys, |m, y| SNorm::DrasticSum.apply(m, y)),
        SNorm::EinsteinSum => each(mu, ys, |m, y| SNorm::EinsteinSum.apply(m, y)),
        SNorm::HamacherSum => each(mu, ys, |m, y| SNorm::HamacherSum.apply(m, y)),
        SNorm::NilpotentMaximum => each(mu, ys, |m, y| SNorm::NilpotentMaximum.apply(m, y)),
        SNorm::NormalizedSum => each(mu, ys, |m, y| SNorm::NormalizedSum.apply(m, y)),
        SNorm::UnboundedSum => each(mu, ys, |m, y| SNorm::UnboundedSum.apply(m, y)),
    }
}

impl CompiledOutput {
    /// The aggregate folded activation by activation, in firing order, over every sample:
    /// exact whatever the degrees.
    fn aggregate_in_firing_order(&mut self, d: &Defuzzifier, var: &OutputVariable) -> f64 {
        let n = self.resolution;
        for (i, m) in self.mu.iter_mut().enumerate() {
            let mut acc = 0.0;
            for &(term, implication, degree) in &self.raw {
                let y = implication.apply(degree, self.samples[term * n + i]);
                acc = match var.aggregation {
                    Some(agg) => agg.apply(acc, y),
                    None => y,
                };
            }
            *m = acc;
        }
        defuzz::integral(d, var.minimum, var.maximum, &self.mu)
    }
}
