//! A deliberately naive evaluation of an [`Engine`], written straight from the fuzzylite
//! semantics with no precomputation: every rule walks its antecedent tree, every activation
//! is kept separately, and the aggregated set is evaluated term by term at every sample.
//! It is the yardstick the compiled [`crate::fuzzy::Inference`] is tested and benchmarked
//! against (seed 000 §3.1 engines must give the same turn and speed either way).

use super::defuzz::{self, Weighted};
use super::engine::{Activation, Defuzzifier, Engine, EngineError, RuleBlock};
use super::inference::{
    apply_hedges, combine, finish_output, output_proposition_degree, record_activation, select_rules,
};
use super::norm::{Hedge, SNorm, TNorm};
use super::rule::{Antecedent, VariableRef};

/// Naive evaluator with its own output history (for lock-previous).
#[derive(Debug, Clone)]
pub struct Reference {
    engine: Engine,
    outputs: Vec<f64>,
    previous: Vec<f64>,
}

impl Reference {
    /// Validates `engine` and prepares an evaluator.
    pub fn new(engine: &Engine) -> Result<Reference, EngineError> {
        engine.validate()?;
        let n = engine.outputs.len();
        let mut engine = engine.clone();
        engine.bind_formulas();
        Ok(Reference { engine, outputs: vec![f64::NAN; n], previous: vec![f64::NAN; n] })
    }

    /// Evaluates the engine on `inputs` (one value per input variable).
    pub fn process(&mut self, inputs: &[f64]) -> &[f64] {
        let e = &self.engine;
        let inputs: Vec<f64> = e
            .inputs
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let x = inputs.get(i).copied().unwrap_or(f64::NAN);
                if v.lock_range && !x.is_nan() { x.clamp(v.minimum, v.maximum) } else { x }
            })
            .collect();
        self.previous.copy_from_slice(&self.outputs);
        // Per output: (term, implication, degree) in firing order.
        let mut activated: Vec<Vec<(usize, TNorm, f64)>> = vec![Vec::new(); e.outputs.len()];
        for block in e.rule_blocks.iter().filter(|b| b.enabled) {
            let implication = block.implication.unwrap_or(TNorm::Minimum);
            let fire = |r: usize, degree: f64, activated: &mut Vec<Vec<(usize, TNorm, f64)>>| {
                for c in &block.rules[r].consequent {
                    if e.outputs[c.variable].enabled {
                        activated[c.variable].push((c.term, implication, apply_hedges(&c.hedges, degree)));
                    }
                }
            };
            let mut degrees = vec![0.0; block.rules.len()];
            if block.activation == Activation::General {
                for (r, rule) in block.rules.iter().enumerate() {
                    let d = rule.weight * self.antecedent(&rule.antecedent, block, &inputs, &activated);
                    if d > 0.0 {
                        fire(r, d, &mut activated);
                    }
                }
            } else {
                for (r, rule) in block.rules.iter().enumerate() {
                    degrees[r] = rule.weight * self.antecedent(&rule.antecedent, block, &inputs, &activated);
                }
                let mut fired = vec![false; degrees.len()];
                select_rules(block.activation, &mut degrees, &mut fired, &mut Vec::new());
                for r in (0..degrees.len()).filter(|&r| fired[r]) {
                    fire(r, degrees[r], &mut activated);
                }
            }
        }
        for (o, var) in e.outputs.iter().enumerate() {
            if !var.enabled {
                continue;
            }
            let mut mine: Vec<(usize, TNorm, f64)> = Vec::new();
            let weighted = var.defuzzifier.is_some_and(|d| d.resolution().is_none());
            for &a in &activated[o] {
                if weighted {
                    record_activation(&mut mine, var, a);
                } else {
                    mine.push(a);
                }
            }
            let value = if mine.is_empty() {
                None
            } else {
                match var.defuzzifier {
                    None => None,
                    Some(Defuzzifier::WeightedAverage { kind }) | Some(Defuzzifier::WeightedSum { kind }) => {
                        let list: Vec<Weighted> =
                            mine.iter().map(|&(t, _, d)| Weighted { term: &var.terms[t].term, degree: d }).collect();
                        let sum_only = matches!(var.defuzzifier, Some(Defuzzifier::WeightedSum { .. }));
                        Some(defuzz::weighted(kind, &list, &inputs, &self.outputs, sum_only))
                    }
                    Some(d) => {
                        if var.aggregation.is_none() && mine.len() > 1 {
                            None
                        } else {
                            let n = d.resolution().unwrap_or(0);
                            let mu: Vec<f64> = (0..n)
                                .map(|i| {
                                    let x = defuzz::sample_x(var.minimum, var.maximum, n, i);
                                    let mut m = 0.0;
                                    for &(t, imp, deg) in &mine {
                                        let term = &var.terms[t].term;
                                        let y = imp.apply(deg, term.membership_in(x, &inputs, &self.outputs));
                                        m = match var.aggregation {
                                            Some(agg) => agg.apply(m, y),
                                            None => y,
                                        };
                                    }
                                    m
                                })
                                .collect();
                            Some(defuzz::integral(&d, var.minimum, var.maximum, &mu))
                        }
                    }
                }
            };
            self.outputs[o] = finish_output(var, value, self.previous[o]);
        }
        &self.outputs
    }

    fn antecedent(
        &self,
        a: &Antecedent,
        block: &RuleBlock,
        inputs: &[f64],
        activated: &[Vec<(usize, TNorm, f64)>],
    ) -> f64 {
        match a {
            Antecedent::Proposition(p) => match p.variable {
                VariableRef::Input(i) => {
                    let var = &self.engine.inputs[i];
                    if !var.enabled {
                        return 0.0;
                    }
                    let base = match p.term {
                        Some(t) if p.hedges.last() != Some(&Hedge::Any) => {
                            var.terms[t].term.membership_in(inputs[i], inputs, &self.outputs)
                        }
                        _ => f64::NAN,
                    };
                    apply_hedges(&p.hedges, base)
                }
                VariableRef::Output(o) => {
                    output_proposition_degree(&p.hedges, p.term, &self.engine.outputs[o], &activated[o])
                }
            },
            Antecedent::And(l, r) => {
                let (x, y) =
                    (self.antecedent(l, block, inputs, activated), self.antecedent(r, block, inputs, activated));
                combine(x, y, |x, y| block.conjunction.unwrap_or(TNorm::Minimum).apply(x, y))
            }
            Antecedent::Or(l, r) => {
                let (x, y) =
                    (self.antecedent(l, block, inputs, activated), self.antecedent(r, block, inputs, activated));
                combine(x, y, |x, y| block.disjunction.unwrap_or(SNorm::Maximum).apply(x, y))
            }
        }
    }
}
