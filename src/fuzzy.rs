//! A complete fuzzy inference engine (seed 000 §3.1; DESIGN.md §2): linguistic variables,
//! terms, hedges, T-norms / S-norms, rule blocks, activation methods and defuzzifiers, for
//! Mamdani, Larsen, Takagi-Sugeno, Tsukamoto and hybrid engines, with FLL import/export.
//!
//! Layout: [`engine`] is the plain-data description, [`variable`] its linguistic variables,
//! [`rule`] the rule grammar, [`formula`] the formulas of `Function` terms, [`fll`] the FuzzyLite Language, [`Inference`] the compiled evaluator and [`reference`] a naive one
//! used to check it; `columns` evaluates many rows at once ([`Inference::process_columns`]). Several engines are layered with [`Network`]. The module does no IO.

mod columns;
pub mod defuzz;
pub mod engine;
pub mod fll;
pub mod formula;
pub mod inference;
mod lanes;
pub mod network;
pub mod norm;
pub mod reference;
pub mod rule;
pub mod term;
pub mod variable;

pub use engine::{Activation, Comparison, Engine, EngineError, EngineKind, Item, RuleBlock};
pub use inference::{Inference, RuleActivation};
pub use network::Network;
pub use norm::{Hedge, SNorm, TNorm};
pub use rule::Rule;
pub use term::Term;
pub use variable::{Defuzzifier, InputVariable, NamedTerm, OutputVariable, WeightedKind};
