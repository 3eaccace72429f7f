//! The fuzzy engine description: linguistic variables, rule blocks, operators and
//! defuzzifiers (seed 000 §3.1; DESIGN.md §2). Plain data: FLL files, Rhai scripts and Rust
//! code all build an [`Engine`], [`Engine::validate`] checks it, and
//! [`crate::fuzzy::Inference`] runs it.
//!
//! Invariant: an engine that passed [`Engine::validate`] has unique variable names, unique
//! term names per variable, ranges that are not inverted (and of some width where an integral defuzzifier samples
//! them), and every rule refers to existing variables
//! and terms; evaluating it never panics, whatever the inputs.

pub use super::variable::{DEFAULT_RESOLUTION, Defuzzifier, InputVariable, NamedTerm, OutputVariable, WeightedKind};

use super::formula::{Formula, Slot};
use super::norm::{SNorm, TNorm, key};
use super::rule::Rule;
use super::term::Term;

/// How a rule block chooses which rules fire (fuzzylite's activation methods).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Activation {
    /// Every rule with a positive activation degree fires.
    General,
    /// The first `rules` rules (in order) with degree > 0 and ≥ `threshold` fire.
    First {
        /// How many rules at most.
        rules: usize,
        /// Minimum activation degree.
        threshold: f64,
    },
    /// The last `rules` rules (in reverse order) with degree > 0 and ≥ `threshold` fire.
    Last {
        /// How many rules at most.
        rules: usize,
        /// Minimum activation degree.
        threshold: f64,
    },
    /// The `rules` rules with the highest positive degrees fire.
    Highest {
        /// How many rules at most.
        rules: usize,
    },
    /// The `rules` rules with the lowest positive degrees fire.
    Lowest {
        /// How many rules at most.
        rules: usize,
    },
    /// Every rule fires with its degree divided by the sum of all degrees.
    Proportional,
    /// Rules whose degree compares true against `value` fire.
    Threshold {
        /// The comparison.
        comparison: Comparison,
        /// The threshold.
        value: f64,
    },
}

/// Comparison operator of [`Activation::Threshold`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Comparison {
    /// `==`
    Equal,
    /// `!=`
    NotEqual,
    /// `<`
    Less,
    /// `<=`
    LessOrEqual,
    /// `>`
    Greater,
    /// `>=`
    GreaterOrEqual,
}

impl Comparison {
    /// The operator as written in FLL.
    pub fn symbol(self) -> &'static str {
        match self {
            Comparison::Equal => "==",
            Comparison::NotEqual => "!=",
            Comparison::Less => "<",
            Comparison::LessOrEqual => "<=",
            Comparison::Greater => ">",
            Comparison::GreaterOrEqual => ">=",
        }
    }

    /// Parses an operator.
    pub fn from_symbol(s: &str) -> Option<Comparison> {
        [
            Comparison::Equal,
            Comparison::NotEqual,
            Comparison::Less,
            Comparison::LessOrEqual,
            Comparison::Greater,
            Comparison::GreaterOrEqual,
        ]
        .into_iter()
        .find(|c| c.symbol() == s)
    }

    /// `degree <op> value`.
    pub fn holds(self, degree: f64, value: f64) -> bool {
        match self {
            Comparison::Equal => degree == value,
            Comparison::NotEqual => degree != value,
            Comparison::Less => degree < value,
            Comparison::LessOrEqual => degree <= value,
            Comparison::Greater => degree > value,
            Comparison::GreaterOrEqual => degree >= value,
        }
    }
}

impl Activation {
    /// The FLL class name.
    pub fn name(&self) -> &'static str {
        match self {
            Activation::General => "General",
            Activation::First { .. } => "First",
            Activation::Last { .. } => "Last",
            Activation::Highest { .. } => "Highest",
            Activation::Lowest { .. } => "Lowest",
            Activation::Proportional => "Proportional",
            Activation::Threshold { .. } => "Threshold",
        }
    }

    /// Builds an activation method from its FLL name and parameters.
    pub fn from_parts(name: &str, params: &[&str]) -> Result<Activation, String> {
        let count = |i: usize| -> Result<usize, String> {
            match params.get(i) {
                None => Ok(1),
                Some(p) => p
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.fract() == 0.0 && *v >= 0.0 && *v < 1e9)
                    .map(|v| v as usize)
                    .ok_or_else(|| format!("number of rules must be a whole number ≥ 0, found '{p}'")),
            }
        };
        let number = |i: usize, default: f64| -> Result<f64, String> {
            match params.get(i) {
                None => Ok(default),
                Some(p) => crate::lex::parse_number(p)
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| format!("expected a finite number, found '{p}'")),
            }
        };
        let max_params = |n: usize| -> Result<(), String> {
            if params.len() > n { Err(format!("activation {name} takes at most {n} parameters")) } else { Ok(()) }
        };
        Ok(match key(name).as_str() {
            "general" => {
                max_params(0)?;
                Activation::General
            }
            "first" => {
                max_params(2)?;
                Activation::First { rules: count(0)?, threshold: number(1, 0.0)? }
            }
            "last" => {
                max_params(2)?;
                Activation::Last { rules: count(0)?, threshold: number(1, 0.0)? }
            }
            "highest" => {
                max_params(1)?;
                Activation::Highest { rules: count(0)? }
            }
            "lowest" => {
                max_params(1)?;
                Activation::Lowest { rules: count(0)? }
            }
            "proportional" => {
                max_params(0)?;
                Activation::Proportional
            }
            "threshold" => {
                max_params(2)?;
                let (comparison, value) = match params {
                    [] => (Comparison::Greater, 0.0),
                    [_] => (Comparison::GreaterOrEqual, number(0, 0.0)?),
                    [op, _] => (
                        Comparison::from_symbol(op).ok_or_else(|| format!("unknown comparison '{op}'"))?,
                        number(1, 0.0)?,
                    ),
                    _ => return Err(format!("activation {name} takes at most 2 parameters")),
                };
                Activation::Threshold { comparison, value }
            }
            _ => return Err(format!("unknown activation method '{name}'")),
        })
    }

    /// The FLL parameters after the class name.
    pub fn parameters(&self) -> String {
        match self {
            Activation::General | Activation::Proportional => String::new(),
            Activation::First { rules, threshold } | Activation::Last { rules, threshold } => {
                format!("{rules} {}", crate::lex::number(*threshold))
            }
            Activation::Highest { rules } | Activation::Lowest { rules } => rules.to_string(),
            Activation::Threshold { comparison, value } => {
                format!("{} {}", comparison.symbol(), crate::lex::number(*value))
            }
        }
    }
}

/// A set of rules sharing operators.
#[derive(Debug, Clone, PartialEq)]
pub struct RuleBlock {
    /// Name of the block.
    pub name: String,
    /// Free text.
    pub description: String,
    /// A disabled block fires no rules.
    pub enabled: bool,
    /// Operator for `and` (needed when a rule uses `and`).
    pub conjunction: Option<TNorm>,
    /// Operator for `or` (needed when a rule uses `or`).
    pub disjunction: Option<SNorm>,
    /// How a rule's degree cuts its conclusion's term (Mamdani: minimum, Larsen: product).
    pub implication: Option<TNorm>,
    /// Which rules fire.
    pub activation: Activation,
    /// The rules, in order.
    pub rules: Vec<Rule>,
}

/// A complete fuzzy inference system.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Engine {
    /// Name of the engine.
    pub name: String,
    /// Free text.
    pub description: String,
    /// Input variables, in data-file order.
    pub inputs: Vec<InputVariable>,
    /// Output variables, in data-file order.
    pub outputs: Vec<OutputVariable>,
    /// Rule blocks, evaluated in order.
    pub rule_blocks: Vec<RuleBlock>,
}

/// The family an engine belongs to, inferred from its operators and defuzzifiers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EngineKind {
    /// Integral defuzzifiers with minimum implication.
    Mamdani,
    /// Integral defuzzifiers with product implication.
    Larsen,
    /// Weighted defuzzifiers over constant/linear terms.
    TakagiSugeno,
    /// Weighted defuzzifiers over monotonic terms.
    Tsukamoto,
    /// Integral and weighted outputs in the same engine.
    Hybrid,
    /// None of the above.
    Unknown,
}

/// What is wrong with an engine.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct EngineError {
    /// Human-readable explanation naming the variable, term, block or rule.
    pub message: String,
    /// The part of the engine at fault, when there is one (so that importers can point at
    /// the line that defined it).
    pub at: Option<Item>,
}

/// A part of an [`Engine`], by index.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Item {
    /// An input variable.
    Input(usize),
    /// An output variable.
    Output(usize),
    /// A term of an input (`output == false`) or output variable.
    Term {
        /// Whether the variable is an output.
        output: bool,
        /// Index of the variable.
        variable: usize,
        /// Index of the term within it.
        term: usize,
    },
    /// A rule block.
    Block(usize),
    /// A rule of a rule block.
    Rule {
        /// Index of the block.
        block: usize,
        /// Index of the rule within it.
        rule: usize,
    },
}

impl EngineError {
    /// An error about no part in particular.
    pub fn new(message: impl Into<String>) -> Self {
        EngineError { message: message.into(), at: None }
    }

    /// The same error, blamed on `item` unless it already names a part.
    fn at(self, item: Item) -> Self {
        EngineError { at: self.at.or(Some(item)), ..self }
    }
}

fn err<T>(message: String) -> Result<T, EngineError> {
    Err(EngineError::new(message))
}

impl RuleBlock {
    /// A Mamdani block: minimum / maximum / minimum, general activation, no rules.
    pub fn mamdani(name: &str) -> Self {
        RuleBlock {
            name: name.to_string(),
            description: String::new(),
            enabled: true,
            conjunction: Some(TNorm::Minimum),
            disjunction: Some(SNorm::Maximum),
            implication: Some(TNorm::Minimum),
            activation: Activation::General,
            rules: Vec::new(),
        }
    }
}

fn check_name(what: &str, name: &str) -> Result<(), EngineError> {
    let ok = !name.is_empty()
        && name.chars().all(|c| c.is_alphanumeric() || c == '_' || c == '.')
        && !matches!(
            name,
            "if" | "then" | "and" | "or" | "with" | "is" | "any" | "not" | "very" | "somewhat" | "extremely" | "seldom"
        );
    if ok {
        Ok(())
    } else {
        err(format!("{what} name '{name}' is not valid: use letters, digits, '_' or '.', and no rule keyword or hedge"))
    }
}

fn check_range(what: &str, name: &str, min: f64, max: f64) -> Result<(), EngineError> {
    if min.is_nan() || max.is_nan() {
        return err(format!("{what} '{name}' has a NaN range bound"));
    }
    if min > max {
        return err(format!("{what} '{name}' has an inverted range [{min}, {max}]"));
    }
    if let Some(m) = super::variable::range_overflow(min, max) {
        return err(format!("{what} '{name}': {m}"));
    }
    Ok(())
}

/// The index of the first of `names` that repeats one before it (or one of `taken`), found in
/// `O(n log n)`.
fn first_repeat<'a>(
    taken: impl IntoIterator<Item = &'a str>,
    names: impl IntoIterator<Item = &'a str>,
) -> Option<usize> {
    let mut seen: std::collections::BTreeSet<&str> = taken.into_iter().collect();
    names.into_iter().position(|n| !seen.insert(n))
}

fn check_terms(what: &str, name: &str, terms: &[NamedTerm], output: bool, variable: usize) -> Result<(), EngineError> {
    let repeat = first_repeat([], terms.iter().map(|t| t.name.as_str()));
    for (i, t) in terms.iter().enumerate() {
        let item = Item::Term { output, variable, term: i };
        check_name("term", &t.name).map_err(|e| e.at(item))?;
        if repeat == Some(i) {
            return err(format!("{what} '{name}' has two terms named '{}'", t.name)).map_err(|e| e.at(item));
        }
        if let Err(m) = t.term.check() {
            return err(format!("term '{}' of {what} '{name}': {m}", t.name)).map_err(|e| e.at(item));
        }
    }
    Ok(())
}

impl Engine {
    /// An empty engine with a name.
    pub fn new(name: &str) -> Self {
        Engine { name: name.to_string(), ..Engine::default() }
    }

    /// Index of the input called `name`.
    pub fn input_index(&self, name: &str) -> Option<usize> {
        self.inputs.iter().position(|v| v.name == name)
    }

    /// Index of the output called `name`.
    pub fn output_index(&self, name: &str) -> Option<usize> {
        self.outputs.iter().position(|v| v.name == name)
    }

    /// Parses `text` and appends it to rule block `block`.
    pub fn add_rule(&mut self, block: usize, text: &str) -> Result<(), super::rule::RuleError> {
        let rule = Rule::parse(text, &self.inputs, &self.outputs)?;
        self.rule_blocks[block].rules.push(rule);
        Ok(())
    }

    /// Checks everything [`crate::fuzzy::Inference`] relies on.
    pub fn validate(&self) -> Result<(), EngineError> {
        self.validate_variables()?;
        self.validate_blocks()
    }

    fn validate_variables(&self) -> Result<(), EngineError> {
        let inputs = || self.inputs.iter().map(|v| v.name.as_str());
        let repeat = first_repeat([], inputs());
        for (i, v) in self.inputs.iter().enumerate() {
            self.validate_input(i, v, repeat == Some(i)).map_err(|e| e.at(Item::Input(i)))?;
        }
        let repeat = first_repeat(inputs(), self.outputs.iter().map(|v| v.name.as_str()));
        for (i, v) in self.outputs.iter().enumerate() {
            self.validate_output(i, v, repeat == Some(i)).map_err(|e| e.at(Item::Output(i)))?;
        }
        let inputs = self.inputs.iter().map(|v| &v.terms);
        let outputs = self.outputs.iter().map(|v| &v.terms);
        let all = inputs.enumerate().map(|(i, t)| (false, i, t)).chain(outputs.enumerate().map(|(i, t)| (true, i, t)));
        for (output, variable, terms) in all {
            for (term, t) in terms.iter().enumerate() {
                if let Term::Linear { coefficients } = &t.term
                    && coefficients.len() != self.inputs.len() + 1
                    && coefficients.len() != self.inputs.len()
                {
                    return err(format!(
                        "Linear term '{}' needs {} coefficients (one per input, then an optional constant), found {}",
                        t.name,
                        self.inputs.len(),
                        coefficients.len()
                    ))
                    .map_err(|e| e.at(Item::Term { output, variable, term }));
                }
                if let Term::Function(f) = &t.term {
                    self.check_formula(f).map_err(|m| {
                        EngineError::new(format!("Function term '{}': {m}", t.name)).at(Item::Term {
                            output,
                            variable,
                            term,
                        })
                    })?;
                }
            }
        }
        Ok(())
    }

    /// What a [`Term::Function`]'s formula reads: `x` and the engine's variables by name (no
    /// variable may itself be called `x`).
    pub fn check_formula(&self, f: &Formula) -> Result<(), String> {
        if self.formula_slot("x").is_some() {
            return Err("the engine has a variable named 'x', which formulas reserve for the term's argument".into());
        }
        match f.names().iter().find(|n| self.formula_slot(n).is_none()) {
            Some(n) => Err(format!(
                "the formula '{}' reads '{n}', which is no input or output variable of the engine",
                f.text()
            )),
            None => Ok(()),
        }
    }

    /// The variable a formula's name refers to.
    fn formula_slot(&self, name: &str) -> Option<Slot> {
        match (self.input_index(name), self.output_index(name)) {
            (Some(i), _) => Some(Slot::Input(i as u32)),
            (None, Some(o)) => Some(Slot::Output(o as u32)),
            (None, None) => None,
        }
    }

    /// Binds the variable names of every [`Term::Function`] to this engine's inputs and
    /// outputs (the evaluators do it on their own copy once the engine is validated).
    pub fn bind_formulas(&mut self) {
        let inputs = self.inputs.iter().enumerate().map(|(i, v)| (v.name.clone(), Slot::Input(i as u32)));
        let outputs = self.outputs.iter().enumerate().map(|(o, v)| (v.name.clone(), Slot::Output(o as u32)));
        let table: Vec<(String, Slot)> = inputs.chain(outputs).collect();
        // The first variable of a name, as `formula_slot` finds it.
        let lookup = |name: &str| table.iter().find(|(n, _)| n == name).map(|&(_, s)| s);
        let inputs = self.inputs.iter_mut().flat_map(|v| &mut v.terms);
        let outputs = self.outputs.iter_mut().flat_map(|v| &mut v.terms);
        for t in inputs.chain(outputs) {
            if let Term::Function(f) = &mut t.term {
                f.bind(lookup);
            }
        }
    }

    /// True when some [`Term::Function`] of the engine reads an output variable's value.
    pub fn formulas_read_outputs(&self) -> bool {
        let inputs = self.inputs.iter().flat_map(|v| &v.terms);
        let outputs = self.outputs.iter().flat_map(|v| &v.terms);
        inputs.chain(outputs).any(|t| {
            t.term
                .formula()
                .is_some_and(|f| f.names().iter().any(|n| matches!(self.formula_slot(n), Some(Slot::Output(_)))))
        })
    }

    /// Checks input `v`; `repeated` when an input before it has its name.
    fn validate_input(&self, i: usize, v: &InputVariable, repeated: bool) -> Result<(), EngineError> {
        check_name("input variable", &v.name)?;
        if repeated {
            return err(format!("two input variables are named '{}'", v.name));
        }
        check_range("input variable", &v.name, v.minimum, v.maximum)?;
        check_terms("input variable", &v.name, &v.terms, false, i)
    }

    /// Checks output `v`; `repeated` when an input or an output before it has its name.
    fn validate_output(&self, i: usize, v: &OutputVariable, repeated: bool) -> Result<(), EngineError> {
        check_name("output variable", &v.name)?;
        if repeated {
            return err(format!("two variables are named '{}'", v.name));
        }
        check_range("output variable", &v.name, v.minimum, v.maximum)?;
        check_terms("output variable", &v.name, &v.terms, true, i)?;
        if let Some(d) = v.defuzzifier
            && d.resolution().is_some()
            && !(v.minimum.is_finite() && v.maximum.is_finite() && v.minimum < v.maximum)
        {
            return err(format!(
                "output variable '{}' uses {} and needs a finite range of some width, found [{}, {}]",
                v.name,
                d.name(),
                v.minimum,
                v.maximum
            ));
        }
        if let Some(m) = v.sum_overflow() {
            return err(format!("output variable '{}': {m}", v.name));
        }
        for (ti, t) in v.terms.iter().enumerate() {
            let weighted = match v.defuzzifier {
                Some(Defuzzifier::WeightedAverage { kind } | Defuzzifier::WeightedSum { kind }) => Some(kind),
                _ => None,
            };
            let problem = match weighted {
                Some(kind) => {
                    let ok = match kind {
                        WeightedKind::TakagiSugeno => true,
                        WeightedKind::Tsukamoto => t.term.is_monotonic(),
                        WeightedKind::Automatic => {
                            t.term.is_monotonic()
                                || matches!(t.term, Term::Constant { .. } | Term::Linear { .. } | Term::Function(_))
                        }
                    };
                    (!ok).then(|| {
                        format!(
                            "term '{}' ({}) of output variable '{}' cannot be used by a weighted defuzzifier: \
                             use Constant, Linear or Function terms, or monotonic ones (Ramp, Sigmoid, SShape, ZShape, Concave, Arc)",
                            t.name,
                            t.term.class_name(),
                            v.name
                        )
                    })
                }
                None => matches!(t.term, Term::Linear { .. }).then(|| {
                    format!(
                        "term '{}' of output variable '{}' is Linear, which only a weighted defuzzifier can use",
                        t.name, v.name
                    )
                }),
            };
            if let Some(m) = problem {
                return err(m).map_err(|e| e.at(Item::Term { output: true, variable: i, term: ti }));
            }
        }
        Ok(())
    }

    fn validate_blocks(&self) -> Result<(), EngineError> {
        // Unnamed blocks never repeat one another.
        let mut seen = std::collections::BTreeSet::new();
        let repeat = self.rule_blocks.iter().position(|b| !b.name.is_empty() && !seen.insert(b.name.as_str()));
        for (bi, block) in self.rule_blocks.iter().enumerate() {
            if repeat == Some(bi) {
                return err(format!("two rule blocks are named '{}'", block.name)).map_err(|e| e.at(Item::Block(bi)));
            }
            for (ri, rule) in block.rules.iter().enumerate() {
                self.validate_rule(block, ri, rule).map_err(|e| e.at(Item::Rule { block: bi, rule: ri }))?;
            }
        }
        Ok(())
    }

    fn validate_rule(&self, block: &RuleBlock, ri: usize, rule: &Rule) -> Result<(), EngineError> {
        let where_ = || format!("rule {} of rule block '{}'", ri + 1, block.name);
        if rule.uses_and() && block.conjunction.is_none() {
            return err(format!("{} uses 'and' but the block has no conjunction", where_()));
        }
        if rule.uses_or() && block.disjunction.is_none() {
            return err(format!("{} uses 'or' but the block has no disjunction", where_()));
        }
        if !(rule.weight.is_finite() && rule.weight >= 0.0) {
            return err(format!("{} has weight {}, expected a finite number ≥ 0", where_(), rule.weight));
        }
        if !self.rule_indices_valid(rule) {
            return err(format!("{} refers to a variable or term that does not exist", where_()));
        }
        for c in &rule.consequent {
            let out = &self.outputs[c.variable];
            let integral = out.defuzzifier.is_some_and(|d| d.resolution().is_some());
            if integral && block.implication.is_none() {
                return err(format!(
                    "{} concludes on '{}', whose {} defuzzifier needs an implication operator in the block",
                    where_(),
                    out.name,
                    out.defuzzifier.map(|d| d.name()).unwrap_or_default()
                ));
            }
        }
        Ok(())
    }

    fn rule_indices_valid(&self, rule: &Rule) -> bool {
        use super::rule::{Antecedent, VariableRef};
        fn walk(e: &Engine, a: &Antecedent) -> bool {
            match a {
                Antecedent::Proposition(p) => {
                    let terms = match p.variable {
                        VariableRef::Input(i) => e.inputs.get(i).map(|v| v.terms.len()),
                        VariableRef::Output(o) => e.outputs.get(o).map(|v| v.terms.len()),
                    };
                    terms.is_some_and(|n| p.term.is_none_or(|t| t < n))
                }
                Antecedent::And(l, r) | Antecedent::Or(l, r) => walk(e, l) && walk(e, r),
            }
        }
        walk(self, &rule.antecedent)
            && rule
                .consequent
                .iter()
                .all(|c| c.variable < self.outputs.len() && c.term < self.outputs[c.variable].terms.len())
    }

    /// Which family the engine belongs to.
    pub fn kind(&self) -> EngineKind {
        let mut integral = false;
        let mut ts = false;
        let mut tsukamoto = false;
        for o in &self.outputs {
            match o.defuzzifier {
                Some(d) if d.resolution().is_some() => integral = true,
                Some(_) => {
                    if o.terms.iter().all(|t| t.term.is_monotonic()) && !o.terms.is_empty() {
                        tsukamoto = true
                    } else {
                        ts = true
                    }
                }
                None => {}
            }
        }
        match (integral, ts || tsukamoto) {
            (true, true) => EngineKind::Hybrid,
            (true, false) => {
                let product = self.rule_blocks.iter().all(|b| b.implication == Some(TNorm::AlgebraicProduct));
                if product && !self.rule_blocks.is_empty() { EngineKind::Larsen } else { EngineKind::Mamdani }
            }
            (false, true) => {
                if tsukamoto && !ts {
                    EngineKind::Tsukamoto
                } else {
                    EngineKind::TakagiSugeno
                }
            }
            (false, false) => EngineKind::Unknown,
        }
    }

    /// Total number of rules over all blocks.
    pub fn rule_count(&self) -> usize {
        self.rule_blocks.iter().map(|b| b.rules.len()).sum()
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A small engine used by unit tests across the fuzzy module.
    pub(crate) fn two_by_two() -> Engine {
        let tri = |a, b, c| Term::Triangle { a, b, c, height: 1.0 };
        let mut e = Engine::new("test");
        e.inputs.push(
            InputVariable::new("distance", 0.0, 4.0).term("near", tri(0.0, 0.0, 2.0)).term("far", tri(1.0, 4.0, 4.0)),
        );
        e.inputs.push(
            InputVariable::new("angle", -90.0, 90.0)
                .term("left", tri(-90.0, -90.0, 0.0))
                .term("ahead", tri(-45.0, 0.0, 45.0))
                .term("right", tri(0.0, 90.0, 90.0)),
        );
        e.outputs.push(
            OutputVariable::new("turn", -60.0, 60.0)
                .term("left", tri(-60.0, -60.0, 0.0))
                .term("right", tri(0.0, 60.0, 60.0)),
        );
        e.outputs.push(
            OutputVariable::new("speed", 0.0, 2.0).term("slow", tri(0.0, 0.0, 1.0)).term("fast", tri(0.5, 2.0, 2.0)),
        );
        e.rule_blocks.push(RuleBlock::mamdani("main"));
        e
    }

    #[test]
    fn validation_catches_bad_engines() {
        let mut e = two_by_two();
        assert!(e.validate().is_ok());
        e.inputs[1].name = "distance".into();
        assert!(e.validate().unwrap_err().message.contains("two input variables"));
        let mut e = two_by_two();
        e.outputs[0].minimum = 100.0;
        assert!(e.validate().unwrap_err().message.contains("inverted"));
        // A range of one point is an input's business (fuzzylite reads such files), but an
        // integral defuzzifier has nothing to sample over it.
        let mut e = two_by_two();
        e.inputs[0].maximum = e.inputs[0].minimum;
        assert!(e.validate().is_ok());
        let mut e = two_by_two();
        e.outputs[0].maximum = e.outputs[0].minimum;
        assert!(e.validate().unwrap_err().message.contains("of some width"));
        let mut e = two_by_two();
        e.outputs[1].terms[1].name = "slow".into();
        assert!(e.validate().unwrap_err().message.contains("two terms"));
        let mut e = two_by_two();
        e.add_rule(0, "if distance is near and angle is left then turn is right").unwrap();
        e.rule_blocks[0].conjunction = None;
        assert!(e.validate().unwrap_err().message.contains("conjunction"));
        let mut e = two_by_two();
        e.inputs[0].name = "if".into();
        assert!(e.validate().is_err());
    }

    #[test]
    fn activation_parsing() {
        assert_eq!(
            Activation::from_parts("First", &["2", "0.1"]).unwrap(),
            Activation::First { rules: 2, threshold: 0.1 }
        );
        assert_eq!(
            Activation::from_parts("Threshold", &[">", "0.3"]).unwrap(),
            Activation::Threshold { comparison: Comparison::Greater, value: 0.3 }
        );
        assert!(Activation::from_parts("Highest", &["x"]).is_err());
        assert!(Activation::from_parts("Nope", &[]).is_err());
    }
}
