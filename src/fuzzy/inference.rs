//! Running an engine: the fast, compiled inference used everywhere in strider (seed 000 §3.1).
//!
//! [`Inference::new`] validates an [`Engine`] and compiles it: propositions used by several
//! rules are evaluated once, antecedents become small postfix programs, and every output
//! term of an integral output is pre-sampled at the defuzzifier's sample points together with
//! the index span where it is non-zero. With maximum aggregation, activations of the same
//! output term are grouped first (`max(T(d₁, μ), T(d₂, μ)) = T(max(d₁, d₂), μ)` for any
//! T-norm), so each output term is folded in once, and only over its support. Those shortcuts
//! hold for degrees in `[0, 1]`; a step where some degree leaves it (weights above 1,
//! unbounded sums) is folded activation by activation in firing order over every sample.
//!
//! Semantics follow fuzzylite: a rule's degree is `weight · antecedent`; a rule fires when
//! its degree is positive (NaN never fires); an output on which no rule fired, or whose
//! result is undefined, takes its previous value (lock-previous) or its default value. Results agree with the naive
//! [`crate::fuzzy::reference`] evaluation to within floating-point rounding.
//!
//! Invariant: `process` allocates nothing and never panics.

use super::defuzz::{self, Weighted};
use super::engine::{Activation, Defuzzifier, Engine, EngineError, OutputVariable};
use super::norm::{Hedge, SNorm, TNorm};
use super::rule::{Antecedent, VariableRef};

/// Propositions with activation degree at or below this do not fire.
pub const FIRING_THRESHOLD: f64 = 0.0;

#[derive(Debug, Clone, PartialEq)]
struct Prop {
    source: VariableRef,
    term: Option<usize>,
    hedges: Vec<Hedge>,
}

#[derive(Debug, Clone, Copy)]
enum Op {
    Load(u32),
    And,
    Or,
}

#[derive(Debug, Clone)]
struct CompiledRule {
    program: std::ops::Range<usize>,
    conclusions: std::ops::Range<usize>,
    weight: f64,
}

#[derive(Debug, Clone)]
struct CompiledConclusion {
    output: usize,
    term: usize,
    hedges: Vec<Hedge>,
}

#[derive(Debug, Clone)]
struct CompiledBlock {
    enabled: bool,
    conjunction: TNorm,
    disjunction: SNorm,
    implication: TNorm,
    activation: Activation,
    rules: std::ops::Range<usize>,
}

#[derive(Debug, Clone)]
struct CompiledOutput {
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
}

/// A compiled engine with its state (input values, output values, rule activations).
#[derive(Debug, Clone)]
pub struct Inference {
    engine: Engine,
    inputs: Vec<f64>,
    outputs: Vec<f64>,
    previous: Vec<f64>,
    props: Vec<Prop>,
    prop_values: Vec<f64>,
    program: Vec<Op>,
    rules: Vec<CompiledRule>,
    conclusions: Vec<CompiledConclusion>,
    blocks: Vec<CompiledBlock>,
    degrees: Vec<f64>,
    fired: Vec<bool>,
    outs: Vec<CompiledOutput>,
    stack: Vec<f64>,
    order: Vec<usize>,
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
    /// Validates and compiles `engine`.
    pub fn new(engine: &Engine) -> Result<Inference, EngineError> {
        engine.validate()?;
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
        for block in &engine.rule_blocks {
            let start = rules.len();
            for rule in &block.rules {
                let p0 = program.len();
                emit(&rule.antecedent, &mut props, &mut program);
                let c0 = conclusions.len();
                for c in &rule.consequent {
                    conclusions.push(CompiledConclusion { output: c.variable, term: c.term, hedges: c.hedges.clone() });
                }
                max_depth = max_depth.max(program.len() - p0);
                rules.push(CompiledRule {
                    program: p0..program.len(),
                    conclusions: c0..conclusions.len(),
                    weight: rule.weight,
                });
            }
            blocks.push(CompiledBlock {
                enabled: block.enabled,
                conjunction: block.conjunction.unwrap_or(TNorm::Minimum),
                disjunction: block.disjunction.unwrap_or(SNorm::Maximum),
                implication: block.implication.unwrap_or(TNorm::Minimum),
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
        for (out, n) in outs.iter_mut().zip(per_output) {
            out.raw.reserve(n);
            out.activated.reserve(n);
        }
        let n_rules = rules.len();
        Ok(Inference {
            engine: engine.clone(),
            inputs: vec![f64::NAN; engine.inputs.len()],
            outputs: vec![f64::NAN; engine.outputs.len()],
            previous: vec![f64::NAN; engine.outputs.len()],
            prop_values: vec![0.0; props.len()],
            props,
            program,
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
        var.terms.iter().map(|t| t.term.membership_with(x, &self.inputs)).collect()
    }

    /// Runs one inference: fuzzify, fire rules, aggregate, defuzzify.
    pub fn process(&mut self) {
        let Inference {
            engine,
            inputs,
            outputs,
            previous,
            props,
            prop_values,
            program,
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
            if var.lock_range && !x.is_nan() {
                *x = x.clamp(var.minimum, var.maximum);
            }
        }
        for (value, prop) in prop_values.iter_mut().zip(props.iter()) {
            if let VariableRef::Input(i) = prop.source {
                let var = &engine.inputs[i];
                *value = if !var.enabled {
                    0.0
                } else {
                    let base = match prop.term {
                        Some(t) if prop.hedges.last() != Some(&Hedge::Any) => {
                            var.terms[t].term.membership_with(inputs[i], inputs)
                        }
                        _ => f64::NAN,
                    };
                    apply_hedges(&prop.hedges, base)
                };
            }
        }
        for out in outs.iter_mut() {
            out.activated.clear();
            out.raw.clear();
        }
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
            let trigger = |i: usize, degree: f64, outs: &mut Vec<CompiledOutput>| {
                for c in &conclusions[rules[i].conclusions.clone()] {
                    let var = &engine.outputs[c.output];
                    if var.enabled {
                        let new = (c.term, block.implication, apply_hedges(&c.hedges, degree));
                        let out = &mut outs[c.output];
                        out.raw.push(new);
                        record_activation(&mut out.activated, var, new);
                    }
                }
            };
            let general = block.activation == Activation::General;
            for i in range.clone() {
                let rule = &rules[i];
                stack.clear();
                for op in &program[rule.program.clone()] {
                    let v = match *op {
                        Op::Load(p) => {
                            let prop = &props[p as usize];
                            match prop.source {
                                VariableRef::Input(_) => prop_values[p as usize],
                                VariableRef::Output(o) => output_proposition(prop, &engine.outputs[o], &outs[o]),
                            }
                        }
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
                degrees[i] = rule.weight * stack.pop().unwrap_or(f64::NAN);
                if general {
                    fired[i] = degrees[i] > FIRING_THRESHOLD;
                    if fired[i] {
                        trigger(i, degrees[i], outs);
                    }
                }
            }
            if !general {
                select_rules(block.activation, &mut degrees[range.clone()], &mut fired[range.clone()], order);
                for i in range.filter(|&i| fired[i]) {
                    trigger(i, degrees[i], outs);
                }
            }
        }
        // Defuzzify.
        for (o, var) in engine.outputs.iter().enumerate() {
            if !var.enabled {
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
                            acc = defuzz::weighted_fold(kind, &list[..chunk.len()], inputs, acc);
                        }
                        Some(defuzz::weighted_result(acc, sum_only))
                    }
                    Some(d) => {
                        if var.aggregation.is_none() && out.activated.len() > 1 {
                            None
                        } else {
                            Some(out.aggregate_and_defuzzify(&d, var))
                        }
                    }
                }
            };
            outputs[o] = finish_output(var, value, previous[o]);
        }
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
    CompiledOutput {
        samples,
        support,
        resolution,
        mu: vec![0.0; resolution],
        activated: Vec::with_capacity(var.terms.len()),
        raw: Vec::new(),
    }
}

impl CompiledOutput {
    fn aggregate_and_defuzzify(&mut self, d: &Defuzzifier, var: &OutputVariable) -> f64 {
        if self.raw.iter().any(|a| !(0.0..=1.0).contains(&a.2)) {
            return self.aggregate_in_firing_order(d, var);
        }
        let n = self.resolution;
        let (mut lo, mut hi) = (n, 0);
        for a in &self.activated {
            let (l, h) = self.support[a.0];
            lo = lo.min(l);
            hi = hi.max(h);
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
        let whole = !matches!(d, Defuzzifier::Centroid { .. });
        if whole {
            self.mu.fill(0.0);
        } else {
            self.mu[lo..hi].fill(0.0);
        }
        let aggregation = var.aggregation.unwrap_or(SNorm::Maximum);
        for &(term, implication, d) in &self.activated {
            let (l, h) = self.support[term];
            let row = &self.samples[term * n + l..term * n + h];
            let mu = &mut self.mu[l..h];
            match (implication, aggregation) {
                (TNorm::Minimum, SNorm::Maximum) => {
                    for (m, &s) in mu.iter_mut().zip(row) {
                        let v = if d < s { d } else { s };
                        *m = if *m > v { *m } else { v };
                    }
                }
                (TNorm::AlgebraicProduct, SNorm::Maximum) => {
                    for (m, &s) in mu.iter_mut().zip(row) {
                        let v = d * s;
                        *m = if *m > v { *m } else { v };
                    }
                }
                (imp, agg) => {
                    for (m, &s) in mu.iter_mut().zip(row) {
                        *m = agg.apply(*m, imp.apply(d, s));
                    }
                }
            }
        }
        if whole {
            defuzz::integral(d, var.minimum, var.maximum, &self.mu)
        } else {
            centroid_span(var.minimum, var.maximum, n, &self.mu[lo..hi], lo)
        }
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

/// Centroid over a span of samples starting at index `offset` (samples outside are zero).
fn centroid_span(minimum: f64, maximum: f64, n: usize, mu: &[f64], offset: usize) -> f64 {
    let dx = (maximum - minimum) / n as f64;
    let (mut area, mut moment) = (0.0, 0.0);
    for (k, &y) in mu.iter().enumerate() {
        let x = minimum + ((offset + k) as f64 + 0.5) * dx;
        area += y;
        moment += y * x;
    }
    moment / area
}
