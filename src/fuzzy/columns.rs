//! Many rows at once: [`Inference::process_columns`] evaluates an engine on columns of inputs
//! (one value per row) and writes columns of outputs, with the same results, bit for bit, as
//! [`Inference::process`] called row after row (the inference of seed 000 §3.1, for arrays of
//! inputs from Python and batch tools).
//!
//! Rows go in chunks of [`CHUNK`]. When every enabled rule block fires by general activation,
//! every proposition reads an input and no `Function` term's formula reads an output (the
//! common case: nothing depends on the outputs of the row before or of the same row), a chunk is
//! evaluated column by column: the clamped inputs, each proposition's membership (the term's
//! kind matched once per column, [`Term::membership_column`]), each rule's degree, each one a
//! tight loop over the chunk. Each element is computed by the same
//! operations in the same order as the scalar evaluation, so only the loop order changes.
//! Then:
//!
//! - a weighted output (Takagi-Sugeno, Tsukamoto) on which no term is concluded twice is
//!   folded column by column too: its activations come in rule order whatever the row, so the
//!   sums `Σ degree · z` and `Σ degree` add the same terms in the same order as the scalar
//!   fold (a rule that did not fire is skipped per row, not added as zero); a conclusion
//!   without hedges reads the rule's degrees in place, a constant term is folded without a
//!   column of its values, and the results are finished in one loop unless the output keeps
//!   its previous value;
//! - a Takagi-Sugeno output of constant and linear terms some of which are concluded twice
//!   gets its linear terms' values column by column, then merges and folds its activations
//!   row by row as the scalar evaluation records and folds them;
//! - every other output (integral ones, other weighted ones with repeated terms) is finished
//!   row by row from the degrees of the chunk, through the same recording and defuzzification
//!   code as the scalar evaluation.
//!
//! Engines outside that case run [`Inference::process`] row by row. Rows are evaluated in
//! order, so an output that keeps its previous value (lock-previous) sees the row before.

use std::ops::Range;

use super::defuzz;
use super::engine::{Activation, Defuzzifier, Engine, OutputVariable, WeightedKind};
use super::inference::{
    Condition, FIRING_THRESHOLD, Fuzzify, Inference, Prop, antecedent, apply_hedges, clamp_input, combine, defuzzify,
    finish_output, input_proposition, start_step, trigger,
};
use super::norm::{Hedge, SNorm, TNorm};
use super::rule::VariableRef;
use super::term::Term;

/// Rows per chunk: each proposition and rule degree is a column of this many values.
const CHUNK: usize = 256;

/// How [`Inference::process_columns`] evaluates an engine.
struct Plan {
    /// Propositions and rule degrees are computed column by column (see the module docs).
    columnar: bool,
    /// Per output, when it is folded column by column: its `(rule, conclusion)` activations in
    /// the order the rules record them.
    weighted: Vec<Option<Vec<(usize, usize)>>>,
    /// Per output, when it is a Takagi-Sugeno output of constant and linear terms some of which
    /// are concluded more than once: the same order, for [`Inference::merged_rows`].
    merged: Vec<Option<Vec<(usize, usize)>>>,
}

/// One chunk's work: rows `span` of `inputs` into `outputs`.
struct Chunk<'a, 'o> {
    plan: &'a Plan,
    scratch: &'a mut Scratch,
    inputs: &'a [&'a [f64]],
    outputs: &'a mut [&'o mut [f64]],
    span: Range<usize>,
}

/// Scratch columns, `CHUNK` values each.
struct Scratch {
    /// Clamped inputs, one column per input.
    x: Vec<f64>,
    /// One column per proposition.
    props: Vec<f64>,
    /// One column per rule.
    degrees: Vec<f64>,
    /// A weighted output's running `Σ degree · z` and `Σ degree`, the hedged degree and `z`.
    sum: Vec<f64>,
    weights: Vec<f64>,
    hedged: Vec<f64>,
    z: Vec<f64>,
    /// A merged output's linear terms' values, one column per term.
    zs: Vec<f64>,
    /// A merged output's activated terms in one row, `(term, degree)`.
    list: Vec<(usize, f64)>,
}

impl Plan {
    /// The plan for a compiled engine.
    fn new(inference: &Inference) -> Plan {
        let Inference { engine, props, rules, conclusions, blocks, .. } = inference;
        let columnar = blocks.iter().all(|b| !b.enabled || b.activation == Activation::General)
            && props.iter().all(|p| matches!(p.source, VariableRef::Input(_)))
            && !engine.formulas_read_outputs();
        let (weighted, merged) = engine
            .outputs
            .iter()
            .enumerate()
            .map(|(o, var)| {
                let Some(Defuzzifier::WeightedAverage { kind } | Defuzzifier::WeightedSum { kind }) = var.defuzzifier
                else {
                    return (None, None);
                };
                if !columnar || !var.enabled {
                    return (None, None);
                }
                let order: Vec<(usize, usize)> = blocks
                    .iter()
                    .filter(|b| b.enabled)
                    .flat_map(|b| b.rules.clone())
                    .flat_map(|i| rules[i].conclusions.clone().map(move |c| (i, c)))
                    .filter(|&(_, c)| conclusions[c].output == o)
                    .collect();
                let once = order.iter().enumerate().all(|(k, &(_, c))| {
                    order[..k].iter().all(|&(_, earlier)| conclusions[earlier].term != conclusions[c].term)
                });
                let values = order.iter().all(|&(_, c)| {
                    let term = &var.terms[conclusions[c].term].term;
                    matches!(term, Term::Constant { .. } | Term::Linear { .. }) && !tsukamoto(kind, term)
                });
                match (once, values) {
                    (true, _) => (Some(order), None),
                    (false, true) => (None, Some(order)),
                    (false, false) => (None, None),
                }
            })
            .unzip();
        Plan { columnar, weighted, merged }
    }
}

impl Inference {
    /// Evaluates one row per index: `inputs[i][r]` is input `i` of row `r` (a missing column,
    /// or one too short, reads as NaN) and `outputs[o][r]` receives output `o`. The rows are
    /// as many as the shortest output column. The same as [`Inference::set_inputs`] and [`Inference::process`] row
    /// after row, bit for bit; afterwards the inference holds the last row's state.
    pub fn process_columns(&mut self, inputs: &[&[f64]], outputs: &mut [&mut [f64]]) {
        let rows = outputs.iter().map(|c| c.len()).min().unwrap_or(0);
        let plan = Plan::new(self);
        if !plan.columnar {
            for r in 0..rows {
                for (i, x) in self.inputs.iter_mut().enumerate() {
                    *x = inputs.get(i).and_then(|c| c.get(r)).copied().unwrap_or(f64::NAN);
                }
                self.process();
                for (column, &y) in outputs.iter_mut().zip(&self.outputs) {
                    column[r] = y;
                }
            }
            return;
        }
        let terms = plan.merged.iter().zip(&self.engine.outputs).filter(|(m, _)| m.is_some());
        let terms = terms.map(|(_, var)| var.terms.len()).max().unwrap_or(0);
        let mut scratch = Scratch::new(self.inputs.len(), self.props.len(), self.rules.len(), terms);
        for start in (0..rows).step_by(CHUNK) {
            let span = start..(start + CHUNK).min(rows);
            self.chunk(Chunk { plan: &plan, scratch: &mut scratch, inputs, outputs, span });
        }
    }

    /// Rows `span`, column by column (the engine is columnar). On x86-64 processors with AVX2
    /// the same code is compiled for it and chosen at run time, with the same results bit for
    /// bit (see `CompiledOutput::aggregate_and_defuzzify`).
    fn chunk(&mut self, job: Chunk<'_, '_>) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor runs AVX2 instructions, checked just above.
            return unsafe { self.chunk_avx2(job) };
        }
        self.chunk_here(job)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn chunk_avx2(&mut self, job: Chunk<'_, '_>) {
        self.chunk_here(job)
    }

    #[inline(always)]
    fn chunk_here(&mut self, Chunk { plan, scratch: s, inputs, outputs, span }: Chunk<'_, '_>) {
        let n = span.len();
        // Inputs, clamped.
        for (i, var) in self.engine.inputs.iter().enumerate() {
            let x = &mut s.x[i * CHUNK..i * CHUNK + n];
            let c = inputs.get(i).copied().unwrap_or(&[]);
            let have = c.len().clamp(span.start, span.end) - span.start;
            for (x, &v) in x.iter_mut().zip(&c[span.start..span.start + have]) {
                *x = clamp_input(var, v);
            }
            x[have..].fill(f64::NAN);
        }
        // Propositions.
        for (p, (prop, plan)) in self.props.iter().zip(&self.fuzzify).enumerate() {
            let values = &mut s.props[p * CHUNK..p * CHUNK + n];
            match (*plan, prop.source) {
                (Fuzzify::Trapezoid { input, a, b, c, d, height }, _) => {
                    trapezoid_column(&s.x[input * CHUNK..input * CHUNK + n], values, [a, b, c, d], height);
                }
                (Fuzzify::General, VariableRef::Input(i)) => {
                    if !self.engine.inputs[i].enabled {
                        values.fill(0.0);
                    } else if let Some(term) = shape_term(&self.engine, prop, i) {
                        // The term's own membership of the input, column by column, then the
                        // hedges.
                        term.membership_column(&s.x[i * CHUNK..i * CHUNK + n], values);
                        if !prop.hedges.is_empty() {
                            for v in values.iter_mut() {
                                *v = apply_hedges(&prop.hedges, *v);
                            }
                        }
                    } else {
                        for (k, v) in values.iter_mut().enumerate() {
                            for (j, x) in self.inputs.iter_mut().enumerate() {
                                *x = s.x[j * CHUNK + k];
                            }
                            *v = input_proposition(&self.engine, prop, i, &self.inputs, &self.outputs);
                        }
                    }
                }
                (Fuzzify::General, VariableRef::Output(_)) => values.fill(f64::NAN),
            }
        }
        // Rule degrees.
        for block in &self.blocks {
            for i in block.rules.clone() {
                let rule = &self.rules[i];
                let degrees = &mut s.degrees[i * CHUNK..i * CHUNK + n];
                if !block.enabled {
                    degrees.fill(0.0);
                    continue;
                }
                match &rule.antecedent {
                    Condition::Chain { props, and } => {
                        let chain = &self.chains[props.clone()];
                        let first = chain.first().map_or(0, |&p| p as usize);
                        degrees.copy_from_slice(&s.props[first * CHUNK..first * CHUNK + n]);
                        for &p in chain.iter().skip(1) {
                            let b = &s.props[p as usize * CHUNK..p as usize * CHUNK + n];
                            connect(degrees, b, *and, block.conjunction, block.disjunction);
                        }
                    }
                    Condition::Program => {
                        for (k, d) in degrees.iter_mut().enumerate() {
                            let load = |p: u32| s.props[p as usize * CHUNK + k];
                            *d = antecedent(rule, block, &self.chains, &self.program, &mut self.stack, load);
                        }
                    }
                }
                for d in degrees.iter_mut() {
                    *d *= rule.weight;
                }
            }
        }
        // Weighted outputs folded column by column.
        for (o, order) in plan.weighted.iter().enumerate() {
            let Some(order) = order else { continue };
            let var = &self.engine.outputs[o];
            let Some(d @ (Defuzzifier::WeightedAverage { kind } | Defuzzifier::WeightedSum { kind })) = var.defuzzifier
            else {
                continue;
            };
            let (sum, weights) = (&mut s.sum[..n], &mut s.weights[..n]);
            sum.fill(0.0);
            weights.fill(0.0);
            for &(i, c) in order {
                let degrees = &s.degrees[i * CHUNK..i * CHUNK + n];
                let conclusion = &self.conclusions[c];
                let hedged: &[f64] = if conclusion.hedges.is_empty() {
                    degrees
                } else {
                    let hedged = &mut s.hedged[..n];
                    for (h, &d) in hedged.iter_mut().zip(degrees) {
                        *h = apply_hedges(&conclusion.hedges, d);
                    }
                    hedged
                };
                let term = &var.terms[conclusion.term].term;
                match term {
                    Term::Constant { value } if !tsukamoto(kind, term) => {
                        accumulate_constant(sum, weights, degrees, hedged, *value);
                    }
                    _ => {
                        let z = &mut s.z[..n];
                        weighted_values(kind, term, hedged, &s.x, &mut self.inputs, z);
                        accumulate(sum, weights, degrees, hedged, z);
                    }
                }
            }
            let sum_only = matches!(d, Defuzzifier::WeightedSum { .. });
            let column = &mut outputs[o][span.clone()];
            if !var.lock_previous && (!var.lock_range || var.minimum <= var.maximum) {
                finish_weighted(var, sum_only, sum, weights, column);
                if let Some(&last) = column.last() {
                    self.outputs[o] = last;
                }
            } else {
                let mut previous = self.outputs[o];
                for ((y, &sum), &weight) in column.iter_mut().zip(sum.iter()).zip(weights.iter()) {
                    previous = finish_output(var, Some(defuzz::weighted_result((sum, weight), sum_only)), previous);
                    *y = previous;
                }
                self.outputs[o] = previous;
            }
        }
        for (o, order) in plan.merged.iter().enumerate() {
            if let Some(order) = order {
                self.merged_rows(o, order, s, &mut outputs[o][span.clone()]);
            }
        }
        for (o, var) in self.engine.outputs.iter().enumerate() {
            if !var.enabled {
                outputs[o][span.clone()].fill(self.outputs[o]);
            }
        }
        // The other outputs, row by row from the degrees.
        let by_row = |o: usize| {
            plan.weighted.get(o).is_none_or(Option::is_none) && plan.merged.get(o).is_none_or(Option::is_none)
        };
        let rows_needed = self.engine.outputs.iter().enumerate().any(|(o, v)| v.enabled && by_row(o));
        // The state after the chunk is its last row's: inputs and degrees always, the rest
        // when some output is finished row by row.
        for k in 0..n {
            let last = k + 1 == n;
            if !rows_needed && !last {
                continue;
            }
            for (j, x) in self.inputs.iter_mut().enumerate() {
                *x = s.x[j * CHUNK + k];
            }
            for (i, (d, f)) in self.degrees.iter_mut().zip(self.fired.iter_mut()).enumerate() {
                *d = s.degrees[i * CHUNK + k];
                *f = *d > FIRING_THRESHOLD;
            }
            if !rows_needed {
                continue;
            }
            start_step(&mut self.outs);
            self.previous.copy_from_slice(&self.outputs);
            for block in self.blocks.iter().filter(|b| b.enabled) {
                for i in block.rules.clone().filter(|&i| self.fired[i]) {
                    let conclusions = &self.conclusions[self.rules[i].conclusions.clone()];
                    trigger(&self.engine, conclusions, block.implication, self.degrees[i], &mut self.outs);
                }
            }
            defuzzify(&self.engine, &mut self.outs, &self.inputs, &mut self.outputs, &self.previous, by_row);
            for ((o, column), var) in outputs.iter_mut().enumerate().zip(&self.engine.outputs) {
                if var.enabled && by_row(o) {
                    column[span.start + k] = self.outputs[o];
                }
            }
        }
    }
}

impl Inference {
    /// Output `o` (enabled, weighted, of constant and linear Takagi-Sugeno terms) on the
    /// chunk's rows from its degrees: each term's values column by column, then row by row the
    /// activations recorded and folded as the scalar evaluation records and folds them — a term
    /// concluded again merged with the output's aggregation (a sum without one) in the order
    /// of its first activation, then `Σ degree · z` and `Σ degree` in that order.
    fn merged_rows(&mut self, o: usize, order: &[(usize, usize)], s: &mut Scratch, column: &mut [f64]) {
        let var = &self.engine.outputs[o];
        let Some(d @ (Defuzzifier::WeightedAverage { kind } | Defuzzifier::WeightedSum { kind })) = var.defuzzifier
        else {
            return;
        };
        let n = column.len();
        for (t, named) in var.terms.iter().enumerate() {
            if let Term::Linear { .. } = named.term {
                let z = &mut s.zs[t * CHUNK..t * CHUNK + n];
                weighted_values(kind, &named.term, &[], &s.x, &mut self.inputs, z);
            }
        }
        let aggregation = var.aggregation.unwrap_or(SNorm::UnboundedSum);
        let sum_only = matches!(d, Defuzzifier::WeightedSum { .. });
        let mut previous = self.outputs[o];
        for (k, y) in column.iter_mut().enumerate() {
            s.list.clear();
            for &(i, c) in order {
                let degree = s.degrees[i * CHUNK + k];
                if !(degree > FIRING_THRESHOLD) {
                    continue;
                }
                let conclusion = &self.conclusions[c];
                let h = apply_hedges(&conclusion.hedges, degree);
                match s.list.iter_mut().find(|e| e.0 == conclusion.term) {
                    Some(e) => e.1 = aggregation.apply(e.1, h),
                    None => s.list.push((conclusion.term, h)),
                }
            }
            let value = (!s.list.is_empty()).then(|| {
                let (mut sum, mut weights) = (0.0, 0.0);
                for &(t, degree) in &s.list {
                    let z = match var.terms[t].term {
                        Term::Constant { value } => value,
                        _ => s.zs[t * CHUNK + k],
                    };
                    sum += degree * z;
                    weights += degree;
                }
                defuzz::weighted_result((sum, weights), sum_only)
            });
            previous = finish_output(var, value, previous);
            *y = previous;
        }
        self.outputs[o] = previous;
    }
}

impl Scratch {
    fn new(inputs: usize, props: usize, rules: usize, terms: usize) -> Scratch {
        let column = || vec![0.0; CHUNK];
        Scratch {
            x: vec![0.0; inputs * CHUNK],
            props: vec![0.0; props * CHUNK],
            degrees: vec![0.0; rules * CHUNK],
            sum: column(),
            weights: column(),
            hedged: column(),
            z: column(),
            zs: vec![0.0; terms * CHUNK],
            list: Vec::with_capacity(terms),
        }
    }
}

/// The term of a proposition on enabled input `i` when its degree is the term's membership of
/// that input alone (then the hedges): not a `Function` or `Linear` term, which read other
/// variables, and no `any` hedge, which ignores the term.
fn shape_term<'e>(engine: &'e Engine, prop: &Prop, i: usize) -> Option<&'e Term> {
    let term = &engine.inputs.get(i)?.terms.get(prop.term?)?.term;
    let reads_others = matches!(term, Term::Function(_) | Term::Linear { .. });
    (!reads_others && prop.hedges.last() != Some(&Hedge::Any)).then_some(term)
}

/// `values[k] = trapezoid(xs[k], a, b, c, d, height)` (the scalar evaluation's formula): every
/// branch computed and one selected, so that the loop runs in vector registers.
#[inline(always)]
fn trapezoid_column(xs: &[f64], values: &mut [f64], [a, b, c, d]: [f64; 4], height: f64) {
    let n = values.len().min(xs.len());
    let (xs, values) = (&xs[..n], &mut values[..n]);
    for k in 0..n {
        let x = xs[k];
        // The rise `(x - a) / (b - a)` or the fall `(d - x) / (d - c)`: one division.
        let (num, den) = if x < b { (x - a, b - a) } else { (d - x, d - c) };
        let slope = num / den;
        let top = ((b <= x) & (x <= c)) | ((a == f64::NEG_INFINITY) & (x < b)) | ((d == f64::INFINITY) & (x > c));
        let y = if top { 1.0 } else { slope };
        let y = if (x < a) | (x > d) { 0.0 } else { y };
        values[k] = if x.is_nan() { f64::NAN } else { height * y };
    }
}

/// `sum[k] += h[k] · z[k]` and `weights[k] += h[k]` where `degrees[k]` fired. Adding zero
/// elsewhere leaves both unchanged, bit for bit: they start at +0 and a sum of doubles is -0
/// only when both terms are, so neither is ever -0.
#[inline(always)]
fn accumulate(sum: &mut [f64], weights: &mut [f64], degrees: &[f64], h: &[f64], z: &[f64]) {
    let n = sum.len().min(weights.len()).min(degrees.len()).min(h.len()).min(z.len());
    let (sum, weights, degrees, h, z) = (&mut sum[..n], &mut weights[..n], &degrees[..n], &h[..n], &z[..n]);
    for k in 0..n {
        let fired = degrees[k] > FIRING_THRESHOLD;
        sum[k] += if fired { h[k] * z[k] } else { 0.0 };
        weights[k] += if fired { h[k] } else { 0.0 };
    }
}

/// `sum[k] += h[k] · value` and `weights[k] += h[k]` where `degrees[k]` fired: [`accumulate`]
/// with every `z[k] = value`.
#[inline(always)]
fn accumulate_constant(sum: &mut [f64], weights: &mut [f64], degrees: &[f64], h: &[f64], value: f64) {
    let n = sum.len().min(weights.len()).min(degrees.len()).min(h.len());
    let (sum, weights, degrees, h) = (&mut sum[..n], &mut weights[..n], &degrees[..n], &h[..n]);
    for k in 0..n {
        let fired = degrees[k] > FIRING_THRESHOLD;
        sum[k] += if fired { h[k] * value } else { 0.0 };
        weights[k] += if fired { h[k] } else { 0.0 };
    }
}

/// `out[k]` = the weighted average (or sum) of `sums[k]` and `weights[k]`, finished as
/// [`finish_output`] finishes it for an output without lock-previous: NaN (no weight) becomes
/// the default value, then lock-range clamps (`minimum ≤ maximum`) as `f64::clamp` does.
#[inline(always)]
fn finish_weighted(var: &OutputVariable, sum_only: bool, sums: &[f64], weights: &[f64], out: &mut [f64]) {
    let (default, lock, lo, hi) = (var.default_value, var.lock_range, var.minimum, var.maximum);
    for ((y, &s), &w) in out.iter_mut().zip(sums).zip(weights) {
        let v = if !(w > 0.0) {
            f64::NAN
        } else if sum_only {
            s
        } else {
            s / w
        };
        let v = if v.is_nan() { default } else { v };
        let clamped = if v < lo { lo } else { v };
        let clamped = if clamped > hi { hi } else { clamped };
        *y = if lock && !v.is_nan() { clamped } else { v };
    }
}

/// Whether a weighted defuzzifier of `kind` takes `term` as Tsukamoto's (its inverse at the
/// degree) rather than Takagi-Sugeno's (its value), as [`defuzz::weighted_fold`] decides.
fn tsukamoto(kind: WeightedKind, term: &Term) -> bool {
    match kind {
        WeightedKind::Tsukamoto => true,
        WeightedKind::TakagiSugeno => false,
        WeightedKind::Automatic => term.is_monotonic(),
    }
}

/// `acc[k] = combine(acc[k], b[k], op)` with `op` the conjunction (`and`) or the disjunction,
/// the common norms inlined.
#[inline(always)]
fn connect(acc: &mut [f64], b: &[f64], and: bool, conjunction: TNorm, disjunction: SNorm) {
    match (and, conjunction, disjunction) {
        (true, TNorm::Minimum, _) => fold(acc, b, |a, b| TNorm::Minimum.apply(a, b)),
        (true, TNorm::AlgebraicProduct, _) => fold(acc, b, |a, b| TNorm::AlgebraicProduct.apply(a, b)),
        (true, t, _) => fold(acc, b, |a, b| t.apply(a, b)),
        (false, _, SNorm::Maximum) => fold(acc, b, |a, b| SNorm::Maximum.apply(a, b)),
        (false, _, SNorm::AlgebraicSum) => fold(acc, b, |a, b| SNorm::AlgebraicSum.apply(a, b)),
        (false, _, s) => fold(acc, b, |a, b| s.apply(a, b)),
    }
}

#[inline(always)]
fn fold(acc: &mut [f64], b: &[f64], op: impl Fn(f64, f64) -> f64 + Copy) {
    for (a, &b) in acc.iter_mut().zip(b) {
        *a = combine(*a, b, op);
    }
}

/// The value `z` a weighted defuzzifier multiplies by each degree in `degrees`, as
/// [`defuzz::weighted_fold`] computes it; `x` holds the chunk's input columns, `row` is room
/// for one row of them.
#[inline(always)]
fn weighted_values(kind: WeightedKind, term: &Term, degrees: &[f64], x: &[f64], row: &mut [f64], z: &mut [f64]) {
    match term {
        _ if tsukamoto(kind, term) => term.tsukamoto_column(degrees, z),
        Term::Constant { value } => z.fill(*value),
        // A formula at the degree, over the row's inputs (a columnar engine's formulas read no
        // output).
        Term::Function(f) => {
            for (k, (z, &d)) in z.iter_mut().zip(degrees).enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = x.get(j * CHUNK + k).copied().unwrap_or(f64::NAN);
                }
                *z = f.eval(d, row, &[]);
            }
        }
        Term::Linear { coefficients } => {
            // Σ cᵢ·xᵢ in coefficient order, the constant (times 1) last, as `membership_with`.
            let n = z.len();
            z.fill(0.0);
            for (i, c) in coefficients.iter().enumerate() {
                match x.get(i * CHUNK..i * CHUNK + n) {
                    Some(xs) => {
                        for (z, &x) in z.iter_mut().zip(xs) {
                            *z += c * x;
                        }
                    }
                    None => {
                        for z in z.iter_mut() {
                            *z += c * 1.0;
                        }
                    }
                }
            }
        }
        _ => {
            for (z, &d) in z.iter_mut().zip(degrees) {
                *z = term.membership(d);
            }
        }
    }
}
