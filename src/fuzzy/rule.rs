//! Fuzzy rules in the FuzzyLite rule grammar, used by FLL files and Rhai scripts alike
//! (seed 000 §3.1: the rule bases of the goal-seeking, obstacle-avoidance and speed layers).
//!
//! ```text
//! rule        := "if" antecedent "then" conclusion ("and" conclusion)* ("with" number)?
//! antecedent  := conjunction ("or" conjunction)*
//! conjunction := factor ("and" factor)*
//! factor      := "(" antecedent ")" | input "is" hedge* (term | "any")
//! conclusion  := output "is" hedge* term
//! ```
//! `and` binds tighter than `or`; both associate to the left. Hedges apply right to left
//! (`very not near` = very(not(near))). Invariant: a parsed [`Rule`] only holds indices that
//! exist in the variables it was parsed against, nests parentheses at most [`MAX_NESTING`]
//! deep and holds at most [`MAX_PROPOSITIONS`] propositions, so every walk over it (parsing,
//! compiling, printing, dropping) has bounded depth whatever the input text.

use std::collections::BTreeMap;

use super::norm::Hedge;
use super::variable::{InputVariable, OutputVariable};

/// Deepest nesting of parentheses in a rule's antecedent.
pub const MAX_NESTING: usize = 64;

/// Most propositions (`variable is term`) in one rule's antecedent.
pub const MAX_PROPOSITIONS: usize = 1024;

/// A condition over input variables (and output variables, whose degree is that of a term in
/// the output's fuzzy set as built by the rules evaluated before).
#[derive(Debug, Clone, PartialEq)]
pub enum Antecedent {
    /// `variable is hedges term`.
    Proposition(Proposition),
    /// Both sides, combined with the block's conjunction.
    And(Box<Antecedent>, Box<Antecedent>),
    /// Either side, combined with the block's disjunction.
    Or(Box<Antecedent>, Box<Antecedent>),
}

/// Which variable a proposition reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VariableRef {
    /// Input variable by index: the membership of its value.
    Input(usize),
    /// Output variable by index: the activation degree of a term in its fuzzy output so far.
    Output(usize),
}

/// `variable is hedges term` inside an antecedent.
#[derive(Debug, Clone, PartialEq)]
pub struct Proposition {
    /// The variable read.
    pub variable: VariableRef,
    /// Hedges in the order written (applied last to first).
    pub hedges: Vec<Hedge>,
    /// Index of the term; `None` for `is any`.
    pub term: Option<usize>,
}

/// `output is hedges term` in a rule's consequent.
#[derive(Debug, Clone, PartialEq)]
pub struct Conclusion {
    /// Index of the output variable.
    pub variable: usize,
    /// Hedges in the order written (applied last to first to the activation degree).
    pub hedges: Vec<Hedge>,
    /// Index of the output term.
    pub term: usize,
}

/// One rule: antecedent, conclusions and weight.
#[derive(Debug, Clone, PartialEq)]
pub struct Rule {
    /// The condition.
    pub antecedent: Antecedent,
    /// What the rule asserts, one or more outputs.
    pub consequent: Vec<Conclusion>,
    /// Weight multiplying the activation degree (`with w`, default 1).
    pub weight: f64,
}

/// A rule that failed to parse: `col` is the 1-based character column within the rule text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RuleError {
    /// 1-based character column where the problem starts.
    pub col: usize,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for RuleError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "column {}: {}", self.col, self.message)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Token<'a> {
    text: &'a str,
    col: usize,
}

fn tokenize(text: &str) -> Vec<Token<'_>> {
    let mut tokens = Vec::new();
    let mut start: Option<(usize, usize)> = None; // (byte, col)
    let mut col = 0;
    for (byte, ch) in text.char_indices() {
        col += 1;
        let is_paren = ch == '(' || ch == ')';
        if ch.is_whitespace() || is_paren {
            if let Some((b, c)) = start.take() {
                tokens.push(Token { text: &text[b..byte], col: c });
            }
            if is_paren {
                tokens.push(Token { text: &text[byte..byte + 1], col });
            }
        } else if start.is_none() {
            start = Some((byte, col));
        }
    }
    if let Some((b, c)) = start {
        tokens.push(Token { text: &text[b..], col: c });
    }
    tokens
}

/// The names rules refer to, indexed once for any number of rules: the variables by name and
/// each variable's terms by name (the first of a name, as a search in order would find it), so
/// parsing a rule costs what it says, not the size of the engine.
#[derive(Debug, Clone)]
pub struct Vocabulary<'v> {
    inputs: &'v [InputVariable],
    outputs: &'v [OutputVariable],
    input_index: BTreeMap<&'v str, usize>,
    output_index: BTreeMap<&'v str, usize>,
    input_terms: Vec<BTreeMap<&'v str, usize>>,
    output_terms: Vec<BTreeMap<&'v str, usize>>,
}

/// `names` indexed by name, the first of each name kept.
fn first_of<'v>(names: impl Iterator<Item = &'v str>) -> BTreeMap<&'v str, usize> {
    let mut index = BTreeMap::new();
    for (i, n) in names.enumerate() {
        index.entry(n).or_insert(i);
    }
    index
}

impl<'v> Vocabulary<'v> {
    /// The names of these variables and their terms.
    pub fn new(inputs: &'v [InputVariable], outputs: &'v [OutputVariable]) -> Self {
        let terms = |ts: &'v [super::variable::NamedTerm]| first_of(ts.iter().map(|t| t.name.as_str()));
        Vocabulary {
            inputs,
            outputs,
            input_index: first_of(inputs.iter().map(|v| v.name.as_str())),
            output_index: first_of(outputs.iter().map(|v| v.name.as_str())),
            input_terms: inputs.iter().map(|v| terms(&v.terms)).collect(),
            output_terms: outputs.iter().map(|v| terms(&v.terms)).collect(),
        }
    }

    /// The name, the terms and the term index of a variable.
    fn variable(&self, v: VariableRef) -> (&'v str, &'v [super::variable::NamedTerm], &BTreeMap<&'v str, usize>) {
        match v {
            VariableRef::Input(i) => (&self.inputs[i].name, &self.inputs[i].terms, &self.input_terms[i]),
            VariableRef::Output(o) => (&self.outputs[o].name, &self.outputs[o].terms, &self.output_terms[o]),
        }
    }
}

struct Parser<'a, 'v, 'n> {
    tokens: Vec<Token<'a>>,
    pos: usize,
    end_col: usize,
    depth: usize,
    propositions: usize,
    names: &'n Vocabulary<'v>,
}

impl<'a> Parser<'a, '_, '_> {
    fn peek(&self) -> Option<Token<'a>> {
        self.tokens.get(self.pos).copied()
    }

    fn next(&mut self, expected: &str) -> Result<Token<'a>, RuleError> {
        let token = self.peek().ok_or_else(|| RuleError {
            col: self.end_col,
            message: format!("expected {expected}, found end of rule"),
        })?;
        self.pos += 1;
        Ok(token)
    }

    fn keyword(&mut self, word: &str) -> Result<(), RuleError> {
        let t = self.next(&format!("'{word}'"))?;
        if t.text == word {
            Ok(())
        } else {
            Err(RuleError { col: t.col, message: format!("expected '{word}', found '{}'", t.text) })
        }
    }

    fn antecedent(&mut self) -> Result<Antecedent, RuleError> {
        let mut left = self.conjunction()?;
        while self.peek().is_some_and(|t| t.text == "or") {
            self.pos += 1;
            let right = self.conjunction()?;
            left = Antecedent::Or(Box::new(left), Box::new(right));
        }
        Ok(left)
    }

    fn conjunction(&mut self) -> Result<Antecedent, RuleError> {
        let mut left = self.factor()?;
        while self.peek().is_some_and(|t| t.text == "and") {
            self.pos += 1;
            let right = self.factor()?;
            left = Antecedent::And(Box::new(left), Box::new(right));
        }
        Ok(left)
    }

    fn factor(&mut self) -> Result<Antecedent, RuleError> {
        let t = self.next("a variable or '('")?;
        if t.text == "(" {
            if self.depth == MAX_NESTING {
                return Err(RuleError {
                    col: t.col,
                    message: format!("parentheses nested deeper than {MAX_NESTING} levels"),
                });
            }
            self.depth += 1;
            let inner = self.antecedent()?;
            self.depth -= 1;
            let close = self.next("')'")?;
            if close.text != ")" {
                return Err(RuleError { col: close.col, message: format!("expected ')', found '{}'", close.text) });
            }
            return Ok(inner);
        }
        let variable = if let Some(&i) = self.names.input_index.get(t.text) {
            VariableRef::Input(i)
        } else if let Some(&o) = self.names.output_index.get(t.text) {
            VariableRef::Output(o)
        } else {
            return Err(RuleError { col: t.col, message: format!("unknown variable '{}'", t.text) });
        };
        self.propositions += 1;
        if self.propositions > MAX_PROPOSITIONS {
            return Err(RuleError {
                col: t.col,
                message: format!("more than {MAX_PROPOSITIONS} propositions in one rule"),
            });
        }
        self.keyword("is")?;
        let (hedges, term) = self.hedged_term(variable, true)?;
        Ok(Antecedent::Proposition(Proposition { variable, hedges, term }))
    }

    /// Reads `hedge* term` (or `hedge* any` when `allow_any`). Term names win over hedge words.
    fn hedged_term(
        &mut self,
        variable: VariableRef,
        allow_any: bool,
    ) -> Result<(Vec<Hedge>, Option<usize>), RuleError> {
        let (var_name, terms, index) = self.names.variable(variable);
        let mut hedges = Vec::new();
        loop {
            let t = self.next(&format!("a term of '{var_name}'"))?;
            if let Some(&i) = index.get(t.text) {
                return Ok((hedges, Some(i)));
            }
            match Hedge::from_name(t.text) {
                Some(Hedge::Any) if allow_any => {
                    hedges.push(Hedge::Any);
                    return Ok((hedges, None));
                }
                Some(Hedge::Any) => {
                    return Err(RuleError { col: t.col, message: "'any' cannot appear in a conclusion".into() });
                }
                Some(h) => hedges.push(h),
                None => {
                    return Err(RuleError {
                        col: t.col,
                        message: format!(
                            "unknown term '{}' for variable '{var_name}' (terms: {})",
                            t.text,
                            terms.iter().map(|t| t.name.as_str()).collect::<Vec<_>>().join(", ")
                        ),
                    });
                }
            }
        }
    }

    fn conclusion(&mut self) -> Result<Conclusion, RuleError> {
        let t = self.next("an output variable")?;
        let variable = self.names.output_index.get(t.text).copied().ok_or_else(|| {
            let message = if self.names.input_index.contains_key(t.text) {
                format!("'{}' is an input variable; conclusions take output variables", t.text)
            } else {
                format!("unknown output variable '{}'", t.text)
            };
            RuleError { col: t.col, message }
        })?;
        self.keyword("is")?;
        let (hedges, term) = self.hedged_term(VariableRef::Output(variable), false)?;
        let term = term.ok_or_else(|| RuleError { col: t.col, message: "missing term".into() })?;
        Ok(Conclusion { variable, hedges, term })
    }
}

impl Rule {
    /// Parses rule text against the engine's variables.
    pub fn parse(text: &str, inputs: &[InputVariable], outputs: &[OutputVariable]) -> Result<Rule, RuleError> {
        Rule::parse_in(text, &Vocabulary::new(inputs, outputs))
    }

    /// Parses rule text against the names of an engine's variables, indexed once for many rules.
    pub fn parse_in(text: &str, names: &Vocabulary<'_>) -> Result<Rule, RuleError> {
        let tokens = tokenize(text);
        let end_col = text.chars().count() + 1;
        let mut p = Parser { tokens, pos: 0, end_col, depth: 0, propositions: 0, names };
        p.keyword("if")?;
        let antecedent = p.antecedent()?;
        p.keyword("then")?;
        let mut consequent = vec![p.conclusion()?];
        let mut weight = 1.0;
        while let Some(t) = p.peek() {
            p.pos += 1;
            match t.text {
                "and" => consequent.push(p.conclusion()?),
                "with" => {
                    let w = p.next("a weight")?;
                    weight =
                        w.text.parse::<f64>().ok().filter(|v| v.is_finite() && *v >= 0.0).ok_or_else(|| RuleError {
                            col: w.col,
                            message: format!("weight must be a finite number ≥ 0, found '{}'", w.text),
                        })?;
                    if let Some(extra) = p.peek() {
                        return Err(RuleError {
                            col: extra.col,
                            message: format!("unexpected '{}' after the weight", extra.text),
                        });
                    }
                }
                other => {
                    return Err(RuleError {
                        col: t.col,
                        message: format!("expected 'and' or 'with', found '{other}'"),
                    });
                }
            }
        }
        Ok(Rule { antecedent, consequent, weight })
    }

    /// Writes the rule back in the grammar above, with parentheses only where needed.
    pub fn to_text(&self, inputs: &[InputVariable], outputs: &[OutputVariable]) -> String {
        let mut s = String::from("if ");
        write_antecedent(&mut s, &self.antecedent, inputs, outputs, false);
        s.push_str(" then ");
        for (i, c) in self.consequent.iter().enumerate() {
            if i > 0 {
                s.push_str(" and ");
            }
            let var = &outputs[c.variable];
            s.push_str(&var.name);
            s.push_str(" is ");
            for h in &c.hedges {
                s.push_str(h.name());
                s.push(' ');
            }
            s.push_str(&var.terms[c.term].name);
        }
        if self.weight != 1.0 {
            s.push_str(&format!(" with {}", crate::lex::number(self.weight)));
        }
        s
    }

    /// True when the antecedent uses `and` (needs a conjunction operator).
    pub fn uses_and(&self) -> bool {
        fn walk(a: &Antecedent) -> bool {
            match a {
                Antecedent::Proposition(_) => false,
                Antecedent::And(..) => true,
                Antecedent::Or(l, r) => walk(l) || walk(r),
            }
        }
        walk(&self.antecedent)
    }

    /// True when the antecedent uses `or` (needs a disjunction operator).
    pub fn uses_or(&self) -> bool {
        fn walk(a: &Antecedent) -> bool {
            match a {
                Antecedent::Proposition(_) => false,
                Antecedent::Or(..) => true,
                Antecedent::And(l, r) => walk(l) || walk(r),
            }
        }
        walk(&self.antecedent)
    }
}

fn write_antecedent(
    s: &mut String,
    a: &Antecedent,
    inputs: &[InputVariable],
    outputs: &[OutputVariable],
    inside_and: bool,
) {
    match a {
        Antecedent::Proposition(p) => {
            let (name, terms) = match p.variable {
                VariableRef::Input(i) => (&inputs[i].name, &inputs[i].terms),
                VariableRef::Output(o) => (&outputs[o].name, &outputs[o].terms),
            };
            s.push_str(name);
            s.push_str(" is");
            for h in &p.hedges {
                s.push(' ');
                s.push_str(h.name());
            }
            if let Some(t) = p.term {
                s.push(' ');
                s.push_str(&terms[t].name);
            }
        }
        Antecedent::And(l, r) => {
            write_antecedent(s, l, inputs, outputs, true);
            s.push_str(" and ");
            // Right operand of a left-associative chain needs parentheses if it is itself an And.
            let needs = matches!(**r, Antecedent::And(..));
            if needs {
                s.push('(');
            }
            write_antecedent(s, r, inputs, outputs, true);
            if needs {
                s.push(')');
            }
        }
        Antecedent::Or(l, r) => {
            if inside_and {
                s.push('(');
            }
            write_antecedent(s, l, inputs, outputs, false);
            s.push_str(" or ");
            let needs = matches!(**r, Antecedent::Or(..));
            if needs {
                s.push('(');
            }
            write_antecedent(s, r, inputs, outputs, false);
            if needs {
                s.push(')');
            }
            if inside_and {
                s.push(')');
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fuzzy::engine::tests::two_by_two;

    #[test]
    fn parses_precedence_and_hedges() {
        let e = two_by_two();
        let r = Rule::parse(
            "if distance is near or angle is very not left and angle is any then turn is right with 0.8",
            &e.inputs,
            &e.outputs,
        )
        .unwrap();
        assert_eq!(r.weight, 0.8);
        match &r.antecedent {
            Antecedent::Or(l, r) => {
                assert!(matches!(**l, Antecedent::Proposition(_)));
                match &**r {
                    Antecedent::And(a, b) => {
                        let Antecedent::Proposition(a) = &**a else { panic!() };
                        assert_eq!(a.hedges, vec![Hedge::Very, Hedge::Not]);
                        let Antecedent::Proposition(b) = &**b else { panic!() };
                        assert_eq!(b.term, None);
                    }
                    other => panic!("{other:?}"),
                }
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn round_trips_through_text() {
        let e = two_by_two();
        for text in [
            "if distance is near then turn is left",
            "if (distance is near or distance is far) and angle is left then turn is right and speed is slow",
            "if distance is near or (angle is left or angle is right) then turn is somewhat right with 0.5",
            "if distance is near and (angle is left and angle is not right) then speed is fast",
        ] {
            let r = Rule::parse(text, &e.inputs, &e.outputs).unwrap();
            let again = Rule::parse(&r.to_text(&e.inputs, &e.outputs), &e.inputs, &e.outputs).unwrap();
            assert_eq!(r, again, "{text}");
        }
    }

    #[test]
    fn errors_name_the_column() {
        let e = two_by_two();
        let err = Rule::parse("if distance is nearr then turn is left", &e.inputs, &e.outputs).unwrap_err();
        assert_eq!(err.col, 16);
        assert!(err.message.contains("nearr"));
        let err = Rule::parse("if sped is slow then turn is left", &e.inputs, &e.outputs).unwrap_err();
        assert_eq!(err.col, 4);
        let ok = Rule::parse("if speed is slow then turn is left", &e.inputs, &e.outputs).unwrap();
        let Antecedent::Proposition(p) = &ok.antecedent else { panic!() };
        assert_eq!(p.variable, VariableRef::Output(1));
        let err = Rule::parse("if distance is near then", &e.inputs, &e.outputs).unwrap_err();
        assert_eq!(err.col, 25);
        let err = Rule::parse("if (distance is near then turn is left", &e.inputs, &e.outputs).unwrap_err();
        assert!(err.message.contains("')'"), "{err}");
        let err = Rule::parse("if distance is near then turn is left with x", &e.inputs, &e.outputs).unwrap_err();
        assert_eq!(err.col, 44);
    }

    #[test]
    fn deep_nesting_and_long_rules_are_errors_not_stack_overflows() {
        let e = two_by_two();
        let n = 10_000;
        let text = format!("if {}distance is near{} then turn is left", "(".repeat(n), ")".repeat(n));
        let err = Rule::parse(&text, &e.inputs, &e.outputs).unwrap_err();
        assert_eq!(err.col, 4 + MAX_NESTING, "{err}");
        assert!(err.message.contains("nested deeper"), "{err}");
        let ok = format!("if {}distance is near{} then turn is left", "(".repeat(8), ")".repeat(8));
        assert!(Rule::parse(&ok, &e.inputs, &e.outputs).is_ok());
        let long = format!("if distance is near{} then turn is left", " and distance is far".repeat(n));
        let err = Rule::parse(&long, &e.inputs, &e.outputs).unwrap_err();
        assert!(err.message.contains("propositions"), "{err}");
    }
}
