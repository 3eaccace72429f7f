//! Layered controllers: several engines where outputs of earlier engines feed inputs of later
//! ones by name (seed 000 §3.1: the goal-seeking layer masked by the obstacle-avoidance layer,
//! plus a separate speed layer).
//!
//! Invariant: stages run in the order given; an input is bound to the most recent earlier
//! output of the same name, or else to a network input. Output names are unique.

use super::engine::{Engine, EngineError};
use super::inference::Inference;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Source {
    External(usize),
    Stage(usize, usize),
}

/// Engines evaluated in sequence, wired by variable names.
#[derive(Debug, Clone)]
pub struct Network {
    stages: Vec<Inference>,
    bindings: Vec<Vec<Source>>,
    input_names: Vec<String>,
    output_names: Vec<(String, usize, usize)>,
}

impl Network {
    /// Wires `engines` together. Fails if an engine is invalid or two outputs share a name.
    pub fn new(engines: &[Engine]) -> Result<Network, EngineError> {
        let mut stages = Vec::new();
        let mut bindings = Vec::new();
        let mut input_names: Vec<String> = Vec::new();
        let mut output_names: Vec<(String, usize, usize)> = Vec::new();
        for (s, engine) in engines.iter().enumerate() {
            stages.push(Inference::new(engine)?);
            let mut bind = Vec::new();
            for var in &engine.inputs {
                let source = match output_names.iter().rev().find(|(n, _, _)| *n == var.name) {
                    Some(&(_, st, o)) => Source::Stage(st, o),
                    None => {
                        let i = input_names.iter().position(|n| *n == var.name).unwrap_or_else(|| {
                            input_names.push(var.name.clone());
                            input_names.len() - 1
                        });
                        Source::External(i)
                    }
                };
                bind.push(source);
            }
            bindings.push(bind);
            for (o, var) in engine.outputs.iter().enumerate() {
                if output_names.iter().any(|(n, _, _)| *n == var.name) {
                    return Err(EngineError::new(format!("two engines of the network output '{}'", var.name)));
                }
                output_names.push((var.name.clone(), s, o));
            }
        }
        Ok(Network { stages, bindings, input_names, output_names })
    }

    /// Names of the network's external inputs, in first-use order.
    pub fn input_names(&self) -> impl Iterator<Item = &str> {
        self.input_names.iter().map(String::as_str)
    }

    /// Names of every output of every stage, in stage order.
    pub fn output_names(&self) -> impl Iterator<Item = &str> {
        self.output_names.iter().map(|(n, _, _)| n.as_str())
    }

    /// The compiled stages (for rule readouts).
    pub fn stages(&self) -> &[Inference] {
        &self.stages
    }

    /// Runs every stage on `inputs` (one per [`Network::input_names`]; missing ones are NaN).
    pub fn process(&mut self, inputs: &[f64]) {
        for s in 0..self.stages.len() {
            for (i, source) in self.bindings[s].iter().enumerate() {
                let value = match *source {
                    Source::External(k) => inputs.get(k).copied().unwrap_or(f64::NAN),
                    Source::Stage(st, o) => self.stages[st].outputs()[o],
                };
                self.stages[s].set_input(i, value);
            }
            self.stages[s].process();
        }
    }

    /// Runs every stage on one row per index: `inputs[k][r]` is network input `k` of row `r`
    /// (a missing column reads as NaN) and `outputs[o][r]` receives output `o` (in
    /// [`Network::output_names`] order). Each stage evaluates all rows, column by column where
    /// it can ([`Inference::process_columns`]), before the next reads its outputs. The same as
    /// [`Network::process`] row after row, bit for bit.
    pub fn process_columns(&mut self, inputs: &[&[f64]], outputs: &mut [&mut [f64]]) {
        let mut first = 0;
        for (s, stage) in self.stages.iter_mut().enumerate() {
            let count = stage.engine().outputs.len();
            let Some((earlier, rest)) = outputs.split_at_mut_checked(first) else { return };
            let Some(own) = rest.get_mut(..count) else { return };
            let columns: Vec<&[f64]> = self.bindings[s]
                .iter()
                .map(|source| match *source {
                    Source::External(k) => inputs.get(k).copied().unwrap_or(&[]),
                    Source::Stage(st, o) => {
                        let at = self.output_names.iter().position(|&(_, s, i)| (s, i) == (st, o));
                        at.and_then(|at| earlier.get(at)).map_or(&[][..], |c| &c[..])
                    }
                })
                .collect();
            stage.process_columns(&columns, own);
            first += count;
        }
    }

    /// Where output `name` is, for [`Network::output_at`].
    pub fn output_index(&self, name: &str) -> Option<usize> {
        self.output_names.iter().position(|(n, _, _)| n == name)
    }

    /// The value of the output at `index` ([`Network::output_index`]) after the last
    /// [`Network::process`].
    pub fn output_at(&self, index: usize) -> f64 {
        let (_, s, o) = self.output_names[index];
        self.stages[s].outputs()[o]
    }

    /// The value of output `name` after the last [`Network::process`].
    pub fn output(&self, name: &str) -> Option<f64> {
        self.output_names.iter().find(|(n, _, _)| n == name).map(|&(_, s, o)| self.stages[s].outputs()[o])
    }
}
