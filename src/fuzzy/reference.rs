//! A deliberately naive evaluation of an [`Engine`], written straight from the fuzzylite
//! semantics with no precomputation: every rule walks its antecedent tree, every activation
//! is kept separately, and the aggregated set is evaluated term by term at every sample.
//! It is the yardstick the compiled [`crate::fuzzy::Inference`] is tested and benchmarked
//! against (seed 000 §3.1 engines must give the same turn and speed either way).

use super::defuzz::{self, Weighted};
use super::engine::{Defuzzifier, Engine, EngineError};
use super::inference::{apply_hedges, combine, finish_output, record_activation, select_rules};
use super::norm::{Hedge, SNorm, TNorm};
use super::rule::Antecedent;

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
        Ok(Reference { engine: engine.clone(), outputs: vec![f64::NAN; n], previous: vec![f64::NAN; n] })
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
        // (output, term, implication, degree) in firing order.
        let mut activated: Vec<(usize, usize, TNorm, f64)> = Vec::new();
        for block in e.rule_blocks.iter().filter(|b| b.enabled) {
            let mut degrees: Vec<f64> = block
                .rules
                .iter()
                .map(|rule| rule.weight * self.antecedent(&rule.antecedent, block.conjunction, block.disjunction, &inputs))
                .collect();
            let mut fired = vec![false; degrees.len()];
            select_rules(block.activation, &mut degrees, &mut fired, &mut Vec::new());
            for (r, rule) in block.rules.iter().enumerate() {
                if !fired[r] {
                    continue;
                }
                for c in &rule.consequent {
                    if e.outputs[c.variable].enabled {
                        let d = apply_hedges(&c.hedges, degrees[r]);
                        activated.push((c.variable, c.term, block.implication.unwrap_or(TNorm::Minimum), d));
                    }
                }
            }
        }
        for (o, var) in e.outputs.iter().enumerate() {
            if !var.enabled {
                continue;
            }
            let mut mine: Vec<(usize, TNorm, f64)> = Vec::new();
            let weighted = var.defuzzifier.is_some_and(|d| d.resolution().is_none());
            for a in activated.iter().filter(|a| a.0 == o) {
                if weighted {
                    record_activation(&mut mine, var, (a.1, a.2, a.3));
                } else {
                    mine.push((a.1, a.2, a.3));
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
                        Some(defuzz::weighted(kind, &list, &inputs, sum_only))
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
                                        let y = imp.apply(deg, var.terms[t].term.membership(x));
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

    fn antecedent(&self, a: &Antecedent, conj: Option<TNorm>, disj: Option<SNorm>, inputs: &[f64]) -> f64 {
        match a {
            Antecedent::Proposition(p) => {
                let var = &self.engine.inputs[p.variable];
                if !var.enabled {
                    return 0.0;
                }
                let base = match p.term {
                    Some(t) if p.hedges.last() != Some(&Hedge::Any) => {
                        var.terms[t].term.membership_with(inputs[p.variable], inputs)
                    }
                    _ => f64::NAN,
                };
                apply_hedges(&p.hedges, base)
            }
            Antecedent::And(l, r) => {
                let (a, b) = (self.antecedent(l, conj, disj, inputs), self.antecedent(r, conj, disj, inputs));
                combine(a, b, |a, b| conj.unwrap_or(TNorm::Minimum).apply(a, b))
            }
            Antecedent::Or(l, r) => {
                let (a, b) = (self.antecedent(l, conj, disj, inputs), self.antecedent(r, conj, disj, inputs));
                combine(a, b, |a, b| disj.unwrap_or(SNorm::Maximum).apply(a, b))
            }
        }
    }
}
