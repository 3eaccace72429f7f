//! The FuzzyLite Language (FLL): import and export of whole engines, so fuzzylite engines
//! load unchanged and strider's layered controllers (seed 000 §3.1) can be taken elsewhere.
//!
//! The importer reads `Engine:`, `InputVariable:`, `OutputVariable:` and `RuleBlock:`
//! sections of `key: value` lines, `#` comments, and the legacy keys of older fuzzylite
//! files (`accumulation`, `lock-valid`, `activation` naming a T-norm). Every error carries
//! the line and column. The exporter writes numbers with full precision, so export followed
//! by import gives back the same engine.

use super::engine::{
    Activation, Defuzzifier, Engine, EngineError, InputVariable, Item, NamedTerm, OutputVariable, RuleBlock,
    WeightedKind,
};
use super::norm::{SNorm, TNorm, key};
use super::rule::{Rule, Vocabulary};
use super::term::Term;
use crate::diagnostic::SourceError;
use crate::lex::{number, parse_number};

enum Section {
    None,
    Engine,
    Input(usize),
    Output(usize),
    Block(usize),
}

struct PendingRule {
    block: usize,
    text: String,
    line: usize,
    col: usize,
}

/// Where each part of the engine was defined: `(line, column)` of its key.
#[derive(Default)]
struct Places {
    inputs: Vec<(usize, usize)>,
    outputs: Vec<(usize, usize)>,
    input_terms: Vec<Vec<(usize, usize)>>,
    output_terms: Vec<Vec<(usize, usize)>>,
    blocks: Vec<(usize, usize)>,
    rules: Vec<Vec<(usize, usize)>>,
    /// `(output, variable, term, line, column)` of each `Function` term's formula.
    formulas: Vec<(bool, usize, usize, usize, usize)>,
}

impl Places {
    fn of(&self, item: Option<Item>) -> (usize, usize) {
        let found = match item {
            None => None,
            Some(Item::Input(i)) => self.inputs.get(i),
            Some(Item::Output(i)) => self.outputs.get(i),
            Some(Item::Term { output: false, variable, term }) => {
                self.input_terms.get(variable).and_then(|t| t.get(term))
            }
            Some(Item::Term { output: true, variable, term }) => {
                self.output_terms.get(variable).and_then(|t| t.get(term))
            }
            Some(Item::Block(b)) => self.blocks.get(b),
            Some(Item::Rule { block, rule }) => self.rules.get(block).and_then(|r| r.get(rule)),
        };
        found.copied().unwrap_or((0, 0))
    }

    fn error(&self, file: &str, e: EngineError) -> SourceError {
        let (line, col) = self.of(e.at);
        SourceError::new(file, line, col, e.message)
    }
}

/// Reads an FLL engine from `text`; `file` names it in errors. The engine is validated.
pub fn import(text: &str, file: &str) -> Result<Engine, SourceError> {
    let mut engine = Engine::default();
    let mut section = Section::None;
    let mut rules: Vec<PendingRule> = Vec::new();
    let mut seen_engine = false;
    let mut places = Places::default();
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    for (ln, raw) in text.lines().enumerate() {
        let line_no = ln + 1;
        let line = match raw.find('#') {
            Some(i) => &raw[..i],
            None => raw,
        };
        if line.trim().is_empty() {
            continue;
        }
        let indent = line.len() - line.trim_start().len();
        let content = line.trim();
        let col_of = |byte_in_line: usize| raw[..byte_in_line].chars().count() + 1;
        let err = |byte_in_line: usize, msg: String| SourceError::new(file, line_no, col_of(byte_in_line), msg);
        let Some(colon) = content.find(':') else {
            return Err(err(indent, format!("expected 'key: value', found '{content}'")));
        };
        let key = content[..colon].trim();
        let value = content[colon + 1..].trim();
        let value_byte = indent + colon + 1 + (content[colon + 1..].len() - content[colon + 1..].trim_start().len());
        let words: Vec<&str> = value.split_whitespace().collect();
        let value_err = |msg: String| err(value_byte, msg);
        let boolean = || -> Result<bool, SourceError> {
            match value {
                "true" => Ok(true),
                "false" => Ok(false),
                _ => Err(value_err(format!("expected true or false, found '{value}'"))),
            }
        };
        let name_value = || -> Result<String, SourceError> {
            if value.is_empty() || words.len() > 1 {
                Err(value_err(format!("expected a single name, found '{value}'")))
            } else {
                Ok(value.to_string())
            }
        };
        match key {
            "Engine" => {
                if seen_engine {
                    return Err(err(indent, "a second 'Engine:' section; one file holds one engine".into()));
                }
                seen_engine = true;
                engine.name = value.to_string();
                section = Section::Engine;
                continue;
            }
            "InputVariable" => {
                places.inputs.push((line_no, col_of(indent)));
                places.input_terms.push(Vec::new());
                engine.inputs.push(InputVariable::new(&name_value()?, f64::NEG_INFINITY, f64::INFINITY));
                section = Section::Input(engine.inputs.len() - 1);
                continue;
            }
            "OutputVariable" => {
                places.outputs.push((line_no, col_of(indent)));
                places.output_terms.push(Vec::new());
                let mut v = OutputVariable::new(&name_value()?, f64::NEG_INFINITY, f64::INFINITY);
                v.aggregation = None;
                v.defuzzifier = None;
                engine.outputs.push(v);
                section = Section::Output(engine.outputs.len() - 1);
                continue;
            }
            "RuleBlock" => {
                places.blocks.push((line_no, col_of(indent)));
                places.rules.push(Vec::new());
                let mut b = RuleBlock::mamdani(value);
                b.conjunction = None;
                b.disjunction = None;
                b.implication = None;
                engine.rule_blocks.push(b);
                section = Section::Block(engine.rule_blocks.len() - 1);
                continue;
            }
            _ => {}
        }
        match section {
            Section::None => {
                return Err(err(indent, format!("'{key}' outside any section; start with 'Engine: NAME'")));
            }
            Section::Engine => match key {
                "description" => engine.description = value.to_string(),
                _ => return Err(err(indent, format!("unknown key '{key}' in Engine section"))),
            },
            Section::Input(i) => {
                let v = &mut engine.inputs[i];
                match key {
                    "description" => v.description = value.to_string(),
                    "enabled" => v.enabled = boolean()?,
                    "range" => (v.minimum, v.maximum) = range(&words).map_err(value_err)?,
                    "lock-range" => v.lock_range = boolean()?,
                    "term" => {
                        let (t, formula_at) = term(value).map_err(|(at, m)| err(value_byte + at, m))?;
                        if let Some(at) = formula_at {
                            places.formulas.push((false, i, v.terms.len(), line_no, col_of(value_byte + at)));
                        }
                        v.terms.push(t);
                        places.input_terms[i].push((line_no, col_of(indent)));
                    }
                    _ => return Err(err(indent, format!("unknown key '{key}' in InputVariable section"))),
                }
            }
            Section::Output(i) => {
                let v = &mut engine.outputs[i];
                match key {
                    "description" => v.description = value.to_string(),
                    "enabled" => v.enabled = boolean()?,
                    "range" => (v.minimum, v.maximum) = range(&words).map_err(value_err)?,
                    "lock-range" => v.lock_range = boolean()?,
                    "aggregation" | "accumulation" => v.aggregation = snorm(value).map_err(value_err)?,
                    "defuzzifier" => {
                        v.defuzzifier = match words.as_slice() {
                            [] | ["none"] => None,
                            [name] => Some(Defuzzifier::from_name(name, None).map_err(value_err)?),
                            [name, p] => Some(Defuzzifier::from_name(name, Some(p)).map_err(value_err)?),
                            _ => return Err(value_err(format!("expected 'NAME [PARAMETER]', found '{value}'"))),
                        }
                    }
                    "default" => {
                        v.default_value = parse_number(value)
                            .ok_or_else(|| value_err(format!("expected a number, found '{value}'")))?
                    }
                    "lock-previous" | "lock-valid" => v.lock_previous = boolean()?,
                    "term" => {
                        let (t, formula_at) = term(value).map_err(|(at, m)| err(value_byte + at, m))?;
                        if let Some(at) = formula_at {
                            places.formulas.push((true, i, v.terms.len(), line_no, col_of(value_byte + at)));
                        }
                        v.terms.push(t);
                        places.output_terms[i].push((line_no, col_of(indent)));
                    }
                    _ => return Err(err(indent, format!("unknown key '{key}' in OutputVariable section"))),
                }
            }
            Section::Block(i) => {
                let b = &mut engine.rule_blocks[i];
                match key {
                    "description" => b.description = value.to_string(),
                    "enabled" => b.enabled = boolean()?,
                    "conjunction" => b.conjunction = tnorm(value).map_err(value_err)?,
                    "disjunction" => b.disjunction = snorm(value).map_err(value_err)?,
                    "implication" => b.implication = tnorm(value).map_err(value_err)?,
                    "activation" => match words.as_slice() {
                        [] | ["none"] => b.activation = Activation::General,
                        [name, params @ ..] => match Activation::from_parts(name, params) {
                            Ok(a) => b.activation = a,
                            // Files from fuzzylite 5 and older name the implication here.
                            Err(e) => match (TNorm::from_name(name), params) {
                                (Some(t), []) => b.implication = Some(t),
                                _ => return Err(value_err(e)),
                            },
                        },
                    },
                    "rule" => rules.push(PendingRule {
                        block: i,
                        text: value.to_string(),
                        line: line_no,
                        col: col_of(value_byte),
                    }),
                    _ => return Err(err(indent, format!("unknown key '{key}' in RuleBlock section"))),
                }
            }
        }
    }
    if !seen_engine {
        return Err(SourceError::new(file, 1, 1, "no 'Engine:' section found"));
    }
    // Variables are validated before rules are parsed, so that rule errors name real problems.
    // (Rule-block checks wait for the rules.)
    // A formula's unknown name is pointed at where the formula reads it.
    for &(output, variable, term, line, col) in &places.formulas {
        let terms = if output { &engine.outputs[variable].terms } else { &engine.inputs[variable].terms };
        let Some(f) = terms.get(term).and_then(|t| t.term.formula()) else { continue };
        if engine.check_formula(f).is_err() {
            let known = |n: &str| n != "x" && (engine.input_index(n).is_some() || engine.output_index(n).is_some());
            if let Some(k) = f.names().iter().position(|n| !known(n)) {
                let at = col + f.name_columns().get(k).copied().unwrap_or(1) - 1;
                return Err(SourceError::new(
                    file,
                    line,
                    at,
                    format!(
                        "term '{}': the formula reads '{}', which is no input or output variable of the engine",
                        terms[term].name,
                        f.names()[k]
                    ),
                ));
            }
        }
    }
    let mut variables_only = engine.clone();
    variables_only.rule_blocks.clear();
    variables_only.validate().map_err(|e| places.error(file, e))?;
    let names = Vocabulary::new(&engine.inputs, &engine.outputs);
    for r in rules {
        let rule = Rule::parse_in(&r.text, &names)
            .map_err(|e| SourceError::new(file, r.line, r.col + e.col - 1, e.message))?;
        engine.rule_blocks[r.block].rules.push(rule);
        places.rules[r.block].push((r.line, r.col));
    }
    engine.validate().map_err(|e| places.error(file, e))?;
    Ok(engine)
}

fn range(words: &[&str]) -> Result<(f64, f64), String> {
    match words {
        [a, b] => {
            let a = parse_number(a).ok_or_else(|| format!("range minimum '{a}' is not a number"))?;
            let b = parse_number(b).ok_or_else(|| format!("range maximum '{b}' is not a number"))?;
            if a.is_nan() || b.is_nan() {
                return Err("a range bound is NaN".into());
            }
            if a > b {
                return Err(format!("range [{a}, {b}] is inverted"));
            }
            Ok((a, b))
        }
        _ => Err("expected 'range: MINIMUM MAXIMUM'".into()),
    }
}

/// A term from the value of a `term:` line; an error carries the byte offset in `value` it is
/// about. A `Function` term's parameter is the rest of the line, one formula.
fn term(value: &str) -> Result<(NamedTerm, Option<usize>), (usize, String)> {
    let words: Vec<&str> = value.split_whitespace().collect();
    if let [name, class, ..] = words.as_slice()
        && key(class) == "function"
    {
        // The formula starts after the class name.
        let after_name = value.find(name).map_or(0, |at| at + name.len());
        let class_at = after_name + value[after_name..].find(class).unwrap_or(0);
        let rest = &value[class_at + class.len()..];
        let start = class_at + class.len() + (rest.len() - rest.trim_start().len());
        let formula = &value[start..];
        return match Term::function(formula) {
            Ok(term) => Ok((NamedTerm { name: name.to_string(), term }, Some(start))),
            Err(e) => {
                let at = formula.char_indices().nth(e.col.saturating_sub(1)).map_or(formula.len(), |(b, _)| b);
                Err((start + at, format!("term '{name}': {}", e.message)))
            }
        };
    }
    numeric_term(&words).map(|t| (t, None)).map_err(|m| (0, m))
}

fn numeric_term(words: &[&str]) -> Result<NamedTerm, String> {
    match words {
        [name, class, params @ ..] => {
            let values = params
                .iter()
                .map(|p| parse_number(p).ok_or_else(|| format!("term '{name}': parameter '{p}' is not a number")))
                .collect::<Result<Vec<f64>, String>>()?;
            let term = Term::from_parameters(class, &values).map_err(|e| format!("term '{name}': {e}"))?;
            term.check().map_err(|e| format!("term '{name}': {e}"))?;
            Ok(NamedTerm { name: name.to_string(), term })
        }
        _ => Err("expected 'term: NAME CLASS PARAMETERS…'".into()),
    }
}

fn tnorm(value: &str) -> Result<Option<TNorm>, String> {
    if value.is_empty() || value == "none" {
        return Ok(None);
    }
    TNorm::from_name(value).map(Some).ok_or_else(|| {
        let all: Vec<&str> = TNorm::ALL.iter().map(|t| t.name()).collect();
        format!("unknown T-norm '{value}' (known: {}, none)", all.join(", "))
    })
}

fn snorm(value: &str) -> Result<Option<SNorm>, String> {
    if value.is_empty() || value == "none" {
        return Ok(None);
    }
    SNorm::from_name(value).map(Some).ok_or_else(|| {
        let all: Vec<&str> = SNorm::ALL.iter().map(|s| s.name()).collect();
        format!("unknown S-norm '{value}' (known: {}, none)", all.join(", "))
    })
}

fn or_none(name: Option<&str>) -> &str {
    name.unwrap_or("none")
}

fn write_term(out: &mut String, t: &NamedTerm) {
    out.push_str(&format!("  term: {} {}", t.name, t.term.class_name()));
    if let Some(f) = t.term.formula() {
        out.push(' ');
        out.push_str(&one_line(f.text()));
        out.push('\n');
        return;
    }
    for p in t.term.parameters() {
        out.push(' ');
        out.push_str(&number(p));
    }
    out.push('\n');
}

/// Free text (a name or a description a script gave) on one line: a line break in it is
/// written as a space, so the file reads back.
fn one_line(text: &str) -> String {
    text.replace(['\n', '\r'], " ")
}

/// Writes `engine` as FLL.
pub fn export(engine: &Engine) -> String {
    let mut s = String::new();
    let line = |s: &mut String, key: &str, value: &str| {
        s.push_str(&format!("  {key}: {}\n", one_line(value)));
    };
    s.push_str(&format!("Engine: {}\n", one_line(&engine.name)));
    if !engine.description.is_empty() {
        line(&mut s, "description", &engine.description);
    }
    for v in &engine.inputs {
        s.push_str(&format!("InputVariable: {}\n", v.name));
        if !v.description.is_empty() {
            line(&mut s, "description", &v.description);
        }
        line(&mut s, "enabled", &v.enabled.to_string());
        line(&mut s, "range", &format!("{} {}", number(v.minimum), number(v.maximum)));
        line(&mut s, "lock-range", &v.lock_range.to_string());
        for t in &v.terms {
            write_term(&mut s, t);
        }
    }
    for v in &engine.outputs {
        s.push_str(&format!("OutputVariable: {}\n", v.name));
        if !v.description.is_empty() {
            line(&mut s, "description", &v.description);
        }
        line(&mut s, "enabled", &v.enabled.to_string());
        line(&mut s, "range", &format!("{} {}", number(v.minimum), number(v.maximum)));
        line(&mut s, "lock-range", &v.lock_range.to_string());
        line(&mut s, "aggregation", or_none(v.aggregation.map(SNorm::name)));
        let defuzzifier = match v.defuzzifier {
            None => "none".to_string(),
            Some(d @ (Defuzzifier::WeightedAverage { kind } | Defuzzifier::WeightedSum { kind })) => {
                let k = match kind {
                    WeightedKind::Automatic => "Automatic",
                    WeightedKind::TakagiSugeno => "TakagiSugeno",
                    WeightedKind::Tsukamoto => "Tsukamoto",
                };
                format!("{} {k}", d.name())
            }
            Some(d) => format!("{} {}", d.name(), d.resolution().unwrap_or_default()),
        };
        line(&mut s, "defuzzifier", &defuzzifier);
        line(&mut s, "default", &number(v.default_value));
        line(&mut s, "lock-previous", &v.lock_previous.to_string());
        for t in &v.terms {
            write_term(&mut s, t);
        }
    }
    for b in &engine.rule_blocks {
        s.push_str(&format!("RuleBlock: {}\n", one_line(&b.name)));
        if !b.description.is_empty() {
            line(&mut s, "description", &b.description);
        }
        line(&mut s, "enabled", &b.enabled.to_string());
        line(&mut s, "conjunction", or_none(b.conjunction.map(TNorm::name)));
        line(&mut s, "disjunction", or_none(b.disjunction.map(SNorm::name)));
        line(&mut s, "implication", or_none(b.implication.map(TNorm::name)));
        let params = b.activation.parameters();
        let activation = if params.is_empty() {
            b.activation.name().to_string()
        } else {
            format!("{} {params}", b.activation.name())
        };
        line(&mut s, "activation", &activation);
        for r in &b.rules {
            line(&mut s, "rule", &r.to_text(&engine.inputs, &engine.outputs));
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "\
Engine: tipper
  description: a small Mamdani engine # with a comment
InputVariable: service
  enabled: true
  range: 0.000 10.000
  lock-range: false
  term: poor Gaussian 0.000 1.500
  term: good Gaussian 5.000 1.500
  term: excellent Gaussian 10.000 1.500
OutputVariable: tip
  enabled: true
  range: 0.000 30.000
  lock-range: false
  accumulation: Maximum
  defuzzifier: Centroid 200
  default: nan
  lock-valid: false
  term: cheap Triangle 0.000 5.000 10.000
  term: average Triangle 10.000 15.000 20.000
  term: generous Triangle 20.000 25.000 30.000
RuleBlock: rules
  enabled: true
  conjunction: Minimum
  disjunction: Maximum
  activation: Minimum
  rule: if service is poor then tip is cheap
  rule: if service is good then tip is average
  rule: if service is excellent then tip is generous with 0.5
";

    #[test]
    fn names_and_descriptions_with_line_breaks_are_written_on_one_line() {
        let mut e = import(SMALL, "d.fll").unwrap();
        e.name = "goal seeking\nav".into();
        e.description = "goal seeking\nmasked by\r\nobstacle nearness".into();
        e.inputs[0].description = "first\rsecond".into();
        let back = import(&export(&e), "export.fll").unwrap();
        assert_eq!(back.name, "goal seeking av");
        assert_eq!(back.description, "goal seeking masked by  obstacle nearness");
        assert_eq!(back.inputs[0].description, "first second");
    }

    #[test]
    fn imports_legacy_and_round_trips() {
        let e = import(SMALL, "tipper.fll").unwrap();
        assert_eq!(e.name, "tipper");
        assert_eq!(e.rule_blocks[0].implication, Some(TNorm::Minimum));
        assert_eq!(e.outputs[0].aggregation, Some(SNorm::Maximum));
        assert_eq!(e.outputs[0].defuzzifier, Some(Defuzzifier::Centroid { resolution: 200 }));
        assert_eq!(e.rule_blocks[0].rules[2].weight, 0.5);
        let again = import(&export(&e), "again.fll").unwrap();
        assert_eq!(e.inputs, again.inputs);
        assert_eq!(e.rule_blocks, again.rule_blocks);
        assert_eq!(e.outputs[0].terms, again.outputs[0].terms);
    }

    #[test]
    fn errors_name_line_and_column() {
        let bad = SMALL.replace("if service is good then", "if service is goood then");
        let err = import(&bad, "t.fll").unwrap_err();
        assert_eq!((err.line, err.col), (27, 23), "{err}");
        assert!(err.to_string().starts_with("t.fll:27:23: unknown term 'goood'"), "{err}");
        let bad = SMALL.replace("range: 0.000 30.000", "range: 30 0");
        let err = import(&bad, "t.fll").unwrap_err();
        assert_eq!((err.line, err.col), (12, 10), "{err}");
        let bad = SMALL.replace("Gaussian 5.000 1.500", "Gaussian 5.000 x");
        let err = import(&bad, "t.fll").unwrap_err();
        assert_eq!(err.line, 8);
        assert!(err.message.contains("'x'"), "{err}");
        let bad = SMALL.replace("  enabled: true\n  range: 0.000 10.000", "  enabled: yes\n  range: 0.000 10.000");
        assert_eq!(import(&bad, "t.fll").unwrap_err().line, 4);
        assert!(import("just words", "t.fll").is_err());
        assert!(import("", "t.fll").is_err());
        let dup = SMALL.replace("term: good Gaussian", "term: poor Gaussian");
        assert!(import(&dup, "t.fll").unwrap_err().message.contains("two terms"));
    }

    /// The 1-based line of the first line of `text` that contains `needle`.
    fn line_of(text: &str, needle: &str) -> usize {
        text.lines().position(|l| l.contains(needle)).unwrap() + 1
    }

    #[test]
    fn validation_errors_name_the_line_that_defined_the_part() {
        let dup = SMALL.replace("OutputVariable: tip", "InputVariable: service\nOutputVariable: tip");
        let err = import(&dup, "t.fll").unwrap_err();
        assert_eq!((err.line, err.col), (line_of(&dup, "OutputVariable") - 1, 1), "{err}");
        let no_implication = SMALL.replace("  activation: Minimum\n", "");
        let err = import(&no_implication, "t.fll").unwrap_err();
        assert_eq!(err.line, line_of(&no_implication, "if service is poor"), "{err}");
        assert!(err.message.contains("implication"), "{err}");
        let no_range = SMALL.replace("  range: 0.000 30.000\n", "");
        let err = import(&no_range, "t.fll").unwrap_err();
        assert_eq!((err.line, err.col), (line_of(&no_range, "OutputVariable"), 1), "{err}");
        assert!(err.message.contains("finite range"), "{err}");
        let linear = SMALL
            .replace("defuzzifier: Centroid 200", "defuzzifier: WeightedAverage TakagiSugeno")
            .replace("term: average Triangle 10.000 15.000 20.000", "term: average Linear 1 2 3 4");
        let err = import(&linear, "t.fll").unwrap_err();
        assert_eq!((err.line, err.col), (line_of(&linear, "Linear 1 2 3 4"), 3), "{err}");
        assert!(err.message.contains("coefficients"), "{err}");
        let dup_block = format!("{SMALL}RuleBlock: rules\n");
        let err = import(&dup_block, "t.fll").unwrap_err();
        assert_eq!(err.line, dup_block.lines().count(), "{err}");
    }

    const FUNCTIONS: &str = "\
Engine: functions
InputVariable: inputX
  enabled: true
  range: 0.000 10.000
  lock-range: false
  term: near Function  1 - min(fabs(x - 5) / 5, 1)
  term: far Triangle 0 5 10
OutputVariable: fx
  enabled: true
  range: -1.000 1.000
  lock-range: false
  aggregation: none
  defuzzifier: WeightedAverage
  default: nan
  lock-previous: false
  term: fx Function sin(inputX)/inputX
OutputVariable: diff
  enabled: true
  range: -1.000 1.000
  lock-range: false
  aggregation: Maximum
  defuzzifier: Centroid 100
  default: nan
  lock-previous: false
  term: diff Function fabs(fx - inputX / 10) * (1 - x^2) + 0.1 * x # a comment
RuleBlock:
  enabled: true
  implication: Minimum
  activation: General
  rule: if inputX is near then fx is fx and diff is diff
";

    #[test]
    fn function_terms_round_trip_with_their_formula_text() {
        let e = import(FUNCTIONS, "f.fll").unwrap();
        let text = |t: &Term| t.formula().map(|f| f.text().to_string());
        assert_eq!(text(&e.inputs[0].terms[0].term).as_deref(), Some("1 - min(fabs(x - 5) / 5, 1)"));
        assert_eq!(text(&e.outputs[1].terms[0].term).as_deref(), Some("fabs(fx - inputX / 10) * (1 - x^2) + 0.1 * x"));
        let out = export(&e);
        assert!(out.contains("  term: fx Function sin(inputX)/inputX\n"), "{out}");
        assert!(out.contains("  term: near Function 1 - min(fabs(x - 5) / 5, 1)\n"), "{out}");
        let again = import(&out, "again.fll").unwrap();
        assert_eq!(
            (&e.inputs, &e.outputs[0].terms, &e.outputs[1].terms),
            (&again.inputs, &again.outputs[0].terms, &again.outputs[1].terms)
        );
        assert_eq!(export(&again), out);
    }

    #[test]
    fn function_terms_read_the_values_of_the_step() {
        use crate::fuzzy::{Inference, reference::Reference};
        let e = import(FUNCTIONS, "f.fll").unwrap();
        let mut fast = Inference::new(&e).unwrap();
        let mut naive = Reference::new(&e).unwrap();
        for x in [2.0, 7.5, 0.0, 5.0] {
            fast.set_inputs(&[x]);
            fast.process();
            let want = naive.process(&[x]).to_vec();
            // `near` fires with 1 - |x - 5| / 5; `fx` is its formula at that degree.
            let degree = 1.0 - (x - 5.0f64).abs() / 5.0;
            let fx = x.sin() / x;
            let got = fast.outputs()[0];
            assert!(got.to_bits() == fx.to_bits() || (got.is_nan() && fx.is_nan()), "at {x}: {got} vs {fx}");
            // `diff` is the centroid of max(0, min(degree, a·(1 − s²) + s/10)) (aggregated from 0)
            // over the samples s, where a reads `fx` as just defuzzified.
            let a = (fx - x / 10.0).abs();
            let (mut area, mut moment) = (0.0, 0.0);
            for i in 0..100 {
                let s = -1.0 + (i as f64 + 0.5) * 0.02;
                let mu = 0f64.max(degree.min(a * (1.0 - s.powf(2.0)) + 0.1 * s));
                area += mu;
                moment += mu * s;
            }
            let diff = moment / area;
            let got = fast.outputs()[1];
            assert!(diff.is_nan() == got.is_nan() && (diff.is_nan() || (got - diff).abs() < 1e-12), "{got} vs {diff}");
            let close = |(a, b): (&f64, &f64)| (a.is_nan() && b.is_nan()) || (a - b).abs() < 1e-12;
            assert!(want.iter().zip(fast.outputs()).all(close), "{want:?} vs {:?}", fast.outputs());
        }
    }

    #[test]
    fn bad_formulas_are_located_errors() {
        let at = |from: &str, to: &str| {
            let bad = FUNCTIONS.replace(from, to);
            let err = import(&bad, "f.fll").unwrap_err();
            let line = line_of(&bad, to);
            let col = bad.lines().nth(line - 1).unwrap().chars().count();
            assert_eq!(err.line, line, "{to}: {err}");
            (err, col)
        };
        // Unbalanced: pointed at the unclosed call.
        let (err, _) = at("sin(inputX)/inputX", "sin(inputX/inputX");
        assert_eq!(err.col, 21, "{err}");
        assert!(err.message.contains("never closed"), "{err}");
        let (err, _) = at("sin(inputX)/inputX", "sin(inputX))/inputX");
        assert_eq!(err.col, 32, "{err}");
        let (err, _) = at("sin(inputX)/inputX", "sine(inputX)/inputX");
        assert_eq!(err.col, 21, "{err}");
        assert!(err.message.contains("unknown function 'sine'"), "{err}");
        let (err, _) = at("sin(inputX)/inputX", "pow(inputX)/inputX");
        assert!(err.message.contains("takes 2 arguments"), "{err}");
        // An unknown variable, found once every variable is known.
        let (err, _) = at("sin(inputX)/inputX", "sin(inputX)/inputY");
        assert_eq!(err.col, 33, "{err}");
        assert!(err.message.contains("'inputY'"), "{err}");
        let (err, end) = at("term: fx Function sin(inputX)/inputX", "term: fx Function");
        assert_eq!(err.col, end + 1, "{err}");
        assert!(err.message.contains("empty"), "{err}");
        let renamed = FUNCTIONS.replace("InputVariable: inputX", "InputVariable: x").replace("inputX", "x");
        let err = import(&renamed, "f.fll").unwrap_err();
        assert!(err.message.contains("named 'x'"), "{err}");
    }

    #[test]
    fn nonsense_terms_and_thresholds_are_located_errors() {
        for (from, to) in [
            ("Triangle 10.000 15.000 20.000", "Triangle -inf 15 inf"),
            ("Gaussian 5.000 1.500", "Gaussian 5 inf"),
            ("Triangle 10.000 15.000 20.000", "Triangle 10 15 20 inf"),
            ("Triangle 10.000 15.000 20.000", "Triangle 10 15 20 -1"),
            ("Triangle 10.000 15.000 20.000", "Constant inf"),
            ("Triangle 10.000 15.000 20.000", "Discrete 10 0 15 1 20"),
            ("activation: Minimum", "activation: Threshold >= nan"),
        ] {
            let bad = SMALL.replace(from, to);
            let err = import(&bad, "t.fll").unwrap_err();
            assert_eq!(err.line, line_of(&bad, to), "{to}: {err}");
            assert!(err.col > 1, "{to}: {err}");
        }
        let bom = format!("\u{feff}{SMALL}");
        assert!(import(&bom, "t.fll").is_ok());
    }
}
