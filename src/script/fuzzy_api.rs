//! The Rhai builder API for fuzzy engines (seed 000 §3.1 rule sets as scripts).
//!
//! ```rhai
//! let e = fuzzy_engine("nav");
//! let d = e.input("distance", 0.0, 5.0);
//! d.term("near", "trapezoid", [0.0, 0.0, 0.5, 1.5]);
//! let turn = e.output("turn", -45.0, 45.0);
//! turn.term("left", "triangle", [-45.0, -45.0, 0.0]).defuzzifier("centroid", 200).default_value(0.0);
//! let b = e.rule_block("avoid");
//! b.rule("if distance is near then turn is left");
//! e
//! ```
//! Term kinds, operators, defuzzifiers and activation methods take their FLL names
//! (case-insensitive, `_` allowed). Rules use the FLL grammar and are checked when added.
//! A script ends with an engine or an array of engines (layered, see
//! [`crate::fuzzy::Network`]).

use std::cell::RefCell;
use std::rc::Rc;

use rhai::{Array, Dynamic, EvalAltResult, ImmutableString, NativeCallContext};

use crate::fuzzy::fll;
use crate::fuzzy::variable::range_overflow;
use crate::fuzzy::{
    Activation, Defuzzifier, Engine, InputVariable, NamedTerm, OutputVariable, RuleBlock, SNorm, TNorm, Term,
};

type Shared = Rc<RefCell<Engine>>;
type Res<T> = Result<T, Box<EvalAltResult>>;

/// A fuzzy engine under construction in a script.
#[derive(Debug, Clone)]
pub struct EngineHandle(Shared);

/// An input or output variable of an [`EngineHandle`].
#[derive(Debug, Clone)]
pub struct VariableHandle {
    engine: Shared,
    output: bool,
    index: usize,
}

/// A rule block of an [`EngineHandle`].
#[derive(Debug, Clone)]
pub struct BlockHandle {
    engine: Shared,
    index: usize,
}

fn fail<T>(message: String) -> Res<T> {
    Err(message.into())
}

/// A number from a script value: float, integer, or the strings `nan`, `inf`, `-inf`.
fn number(value: &Dynamic, what: &str) -> Res<f64> {
    if let Ok(f) = value.as_float() {
        return Ok(f);
    }
    if let Ok(i) = value.as_int() {
        return Ok(i as f64);
    }
    if let Some(s) = value.clone().try_cast::<ImmutableString>()
        && let Some(v) = crate::lex::parse_number(&s)
    {
        return Ok(v);
    }
    fail(format!("{what} must be a number, found {}", value.type_name()))
}

/// A term whose parameter is text: a `function` and its formula.
fn formula_term(name: &str, kind: &str, formula: &str) -> Res<Term> {
    if crate::fuzzy::norm::key(kind) != "function" {
        return fail(format!(
            "term '{name}': a {kind} term takes an array of numbers; only a function takes a formula"
        ));
    }
    Term::function(formula).or_else(|e| fail(format!("term '{name}': column {} of the formula: {}", e.col, e.message)))
}

fn numbers(values: &Array, what: &str) -> Res<Vec<f64>> {
    values.iter().enumerate().map(|(i, v)| number(v, &format!("{what} {}", i + 1))).collect()
}

fn tnorm(name: &str) -> Res<Option<TNorm>> {
    if name == "none" {
        return Ok(None);
    }
    match TNorm::from_name(name) {
        Some(t) => Ok(Some(t)),
        None => fail(format!("unknown T-norm '{name}'")),
    }
}

fn snorm(name: &str) -> Res<Option<SNorm>> {
    if name == "none" {
        return Ok(None);
    }
    match SNorm::from_name(name) {
        Some(s) => Ok(Some(s)),
        None => fail(format!("unknown S-norm '{name}'")),
    }
}

impl VariableHandle {
    fn with_output<T>(&self, what: &str, f: impl FnOnce(&mut OutputVariable) -> Res<T>) -> Res<T> {
        if !self.output {
            let name = self.engine.borrow().inputs[self.index].name.clone();
            return fail(format!("'{what}' applies to output variables; '{name}' is an input"));
        }
        f(&mut self.engine.borrow_mut().outputs[self.index])
    }

    fn edit(&self, f: impl FnOnce(&mut String, &mut bool, &mut bool, &mut Vec<NamedTerm>)) {
        let mut e = self.engine.borrow_mut();
        if self.output {
            let v = &mut e.outputs[self.index];
            f(&mut v.description, &mut v.enabled, &mut v.lock_range, &mut v.terms);
        } else {
            let v = &mut e.inputs[self.index];
            f(&mut v.description, &mut v.enabled, &mut v.lock_range, &mut v.terms);
        }
    }
}

fn new_variable(e: &mut EngineHandle, name: &str, min: Dynamic, max: Dynamic, output: bool) -> Res<VariableHandle> {
    let (min, max) = (number(&min, "range minimum")?, number(&max, "range maximum")?);
    if !(min.is_finite() && max.is_finite()) || min >= max {
        return fail(format!("variable '{name}': range [{min}, {max}] must be finite and not empty or inverted"));
    }
    if let Some(m) = range_overflow(min, max) {
        return fail(format!("variable '{name}': {m}"));
    }
    let mut engine = e.0.borrow_mut();
    if engine.inputs.iter().any(|v| v.name == name) || engine.outputs.iter().any(|v| v.name == name) {
        return fail(format!("a variable named '{name}' already exists"));
    }
    let index = if output {
        let v = OutputVariable::new(name, min, max);
        if let Some(m) = v.sum_overflow() {
            return fail(format!("variable '{name}': {m}"));
        }
        engine.outputs.push(v);
        engine.outputs.len() - 1
    } else {
        engine.inputs.push(InputVariable::new(name, min, max));
        engine.inputs.len() - 1
    };
    Ok(VariableHandle { engine: e.0.clone(), output, index })
}

/// Gives output `o` the defuzzifier `d`, refused when its sums would overflow over the range.
fn set_defuzzifier(o: &mut OutputVariable, d: Option<Defuzzifier>) -> Res<()> {
    o.defuzzifier = d;
    match o.sum_overflow() {
        Some(m) => fail(format!("variable '{}': {m}", o.name)),
        None => Ok(()),
    }
}

/// Registers the fuzzy builder API on `engine`.
pub fn register(engine: &mut rhai::Engine) {
    engine
        .register_type_with_name::<EngineHandle>("FuzzyEngine")
        .register_type_with_name::<VariableHandle>("FuzzyVariable")
        .register_type_with_name::<BlockHandle>("RuleBlock");

    engine.register_fn("fuzzy_engine", |name: &str| EngineHandle(Rc::new(RefCell::new(Engine::new(name)))));
    engine.register_fn("description", |e: &mut EngineHandle, text: &str| {
        e.0.borrow_mut().description = text.to_string();
        e.clone()
    });
    engine.register_fn(
        "input",
        |e: &mut EngineHandle, name: &str, min: Dynamic, max: Dynamic| -> Res<VariableHandle> {
            new_variable(e, name, min, max, false)
        },
    );
    engine.register_fn(
        "output",
        |e: &mut EngineHandle, name: &str, min: Dynamic, max: Dynamic| -> Res<VariableHandle> {
            new_variable(e, name, min, max, true)
        },
    );
    engine.register_fn("rule_block", |e: &mut EngineHandle, name: &str| -> Res<BlockHandle> {
        let mut engine = e.0.borrow_mut();
        if engine.rule_blocks.iter().any(|b| b.name == name) {
            return fail(format!("a rule block named '{name}' already exists"));
        }
        engine.rule_blocks.push(RuleBlock::mamdani(name));
        Ok(BlockHandle { engine: e.0.clone(), index: engine.rule_blocks.len() - 1 })
    });
    engine.register_fn("to_fll", |e: &mut EngineHandle| fll::export(&e.0.borrow()));
    engine.register_fn("name", |e: &mut EngineHandle| e.0.borrow().name.clone());
    engine.register_fn("variable", |e: &mut EngineHandle, name: &str| -> Res<VariableHandle> {
        let engine = e.0.borrow();
        if let Some(index) = engine.input_index(name) {
            return Ok(VariableHandle { engine: e.0.clone(), output: false, index });
        }
        if let Some(index) = engine.output_index(name) {
            return Ok(VariableHandle { engine: e.0.clone(), output: true, index });
        }
        fail(format!("engine '{}' has no variable named '{name}'", engine.name))
    });
    engine.register_fn("block", |e: &mut EngineHandle, name: &str| -> Res<BlockHandle> {
        let engine = e.0.borrow();
        match engine.rule_blocks.iter().position(|b| b.name == name) {
            Some(index) => Ok(BlockHandle { engine: e.0.clone(), index }),
            None => fail(format!("engine '{}' has no rule block named '{name}'", engine.name)),
        }
    });

    // Variables.
    engine.register_fn(
        "term",
        |v: &mut VariableHandle, name: &str, kind: &str, params: Array| -> Res<VariableHandle> {
            let values = numbers(&params, &format!("parameter of term '{name}'"))?;
            let term = Term::from_parameters(kind, &values)
                .and_then(|t| t.check().map(|()| t))
                .map_err(|e| format!("term '{name}': {e}"))?;
            let mut duplicate = false;
            v.edit(|_, _, _, terms| {
                duplicate = terms.iter().any(|t| t.name == name);
                if !duplicate {
                    terms.push(NamedTerm { name: name.to_string(), term });
                }
            });
            if duplicate {
                return fail(format!("the variable already has a term named '{name}'"));
            }
            Ok(v.clone())
        },
    );
    engine.register_fn(
        "set_term",
        |v: &mut VariableHandle, name: &str, kind: &str, params: Array| -> Res<VariableHandle> {
            let values = numbers(&params, &format!("parameter of term '{name}'"))?;
            let term = Term::from_parameters(kind, &values)
                .and_then(|t| t.check().map(|()| t))
                .map_err(|e| format!("term '{name}': {e}"))?;
            v.edit(|_, _, _, terms| match terms.iter_mut().find(|t| t.name == name) {
                Some(t) => t.term = term,
                None => terms.push(NamedTerm { name: name.to_string(), term }),
            });
            Ok(v.clone())
        },
    );
    // Function terms: the parameter is the formula's text.
    engine.register_fn(
        "term",
        |v: &mut VariableHandle, name: &str, kind: &str, formula: &str| -> Res<VariableHandle> {
            let term = formula_term(name, kind, formula)?;
            let mut duplicate = false;
            v.edit(|_, _, _, terms| {
                duplicate = terms.iter().any(|t| t.name == name);
                if !duplicate {
                    terms.push(NamedTerm { name: name.to_string(), term });
                }
            });
            if duplicate {
                return fail(format!("the variable already has a term named '{name}'"));
            }
            Ok(v.clone())
        },
    );
    engine.register_fn(
        "set_term",
        |v: &mut VariableHandle, name: &str, kind: &str, formula: &str| -> Res<VariableHandle> {
            let term = formula_term(name, kind, formula)?;
            v.edit(|_, _, _, terms| match terms.iter_mut().find(|t| t.name == name) {
                Some(t) => t.term = term,
                None => terms.push(NamedTerm { name: name.to_string(), term }),
            });
            Ok(v.clone())
        },
    );
    engine.register_fn("description", |v: &mut VariableHandle, text: &str| {
        v.edit(|d, _, _, _| *d = text.to_string());
        v.clone()
    });
    engine.register_fn("enabled", |v: &mut VariableHandle, on: bool| {
        v.edit(|_, e, _, _| *e = on);
        v.clone()
    });
    engine.register_fn("lock_range", |v: &mut VariableHandle, on: bool| {
        v.edit(|_, _, l, _| *l = on);
        v.clone()
    });
    engine.register_fn("aggregation", |v: &mut VariableHandle, name: &str| -> Res<VariableHandle> {
        v.with_output("aggregation", |o| {
            o.aggregation = snorm(name)?;
            Ok(())
        })?;
        Ok(v.clone())
    });
    engine.register_fn("defuzzifier", |v: &mut VariableHandle, name: &str| -> Res<VariableHandle> {
        v.with_output("defuzzifier", |o| {
            set_defuzzifier(o, if name == "none" { None } else { Some(Defuzzifier::from_name(name, None)?) })
        })?;
        Ok(v.clone())
    });
    engine.register_fn("defuzzifier", |v: &mut VariableHandle, name: &str, param: Dynamic| -> Res<VariableHandle> {
        let param = if param.is_string() {
            param.into_string().unwrap_or_default()
        } else {
            let r = number(&param, "defuzzifier parameter")?;
            format!("{r}")
        };
        v.with_output("defuzzifier", |o| set_defuzzifier(o, Some(Defuzzifier::from_name(name, Some(&param))?)))?;
        Ok(v.clone())
    });
    engine.register_fn("default_value", |v: &mut VariableHandle, value: Dynamic| -> Res<VariableHandle> {
        let x = number(&value, "default value")?;
        v.with_output("default_value", |o| {
            o.default_value = x;
            Ok(())
        })?;
        Ok(v.clone())
    });
    engine.register_fn("lock_previous", |v: &mut VariableHandle, on: bool| -> Res<VariableHandle> {
        v.with_output("lock_previous", |o| {
            o.lock_previous = on;
            Ok(())
        })?;
        Ok(v.clone())
    });

    // Rule blocks.
    fn block_edit(b: &BlockHandle, f: impl FnOnce(&mut RuleBlock) -> Res<()>) -> Res<BlockHandle> {
        f(&mut b.engine.borrow_mut().rule_blocks[b.index])?;
        Ok(b.clone())
    }
    engine.register_fn("description", |b: &mut BlockHandle, text: &str| {
        block_edit(b, |r| {
            r.description = text.to_string();
            Ok(())
        })
    });
    engine.register_fn("enabled", |b: &mut BlockHandle, on: bool| {
        block_edit(b, |r| {
            r.enabled = on;
            Ok(())
        })
    });
    engine.register_fn("conjunction", |b: &mut BlockHandle, name: &str| {
        block_edit(b, |r| {
            r.conjunction = tnorm(name)?;
            Ok(())
        })
    });
    engine.register_fn("disjunction", |b: &mut BlockHandle, name: &str| {
        block_edit(b, |r| {
            r.disjunction = snorm(name)?;
            Ok(())
        })
    });
    engine.register_fn("implication", |b: &mut BlockHandle, name: &str| {
        block_edit(b, |r| {
            r.implication = tnorm(name)?;
            Ok(())
        })
    });
    engine.register_fn("activation", |b: &mut BlockHandle, name: &str| {
        block_edit(b, |r| {
            r.activation = Activation::from_parts(name, &[])?;
            Ok(())
        })
    });
    engine.register_fn("activation", |b: &mut BlockHandle, name: &str, params: Array| {
        let words: Vec<String> = params.iter().map(|p| p.to_string()).collect();
        let refs: Vec<&str> = words.iter().map(String::as_str).collect();
        block_edit(b, |r| {
            r.activation = Activation::from_parts(name, &refs)?;
            Ok(())
        })
    });
    fn add_rule(b: &BlockHandle, text: &str) -> Res<()> {
        let mut engine = b.engine.borrow_mut();
        engine.add_rule(b.index, text).map_err(|e| format!("rule \"{text}\", column {}: {}", e.col, e.message).into())
    }
    engine.register_fn("rule", |b: &mut BlockHandle, text: &str| -> Res<BlockHandle> {
        add_rule(b, text)?;
        Ok(b.clone())
    });
    engine.register_fn("rules", |ctx: NativeCallContext, b: &mut BlockHandle, texts: Array| -> Res<BlockHandle> {
        for (i, t) in texts.iter().enumerate() {
            let Some(text) = t.clone().try_cast::<ImmutableString>() else {
                return Err(EvalAltResult::ErrorRuntime(
                    format!("rule {} must be a string, found {}", i + 1, t.type_name()).into(),
                    ctx.call_position(),
                )
                .into());
            };
            add_rule(b, &text)?;
        }
        Ok(b.clone())
    });
}

/// The engine a handle holds (a copy).
pub fn engine_of(handle: &EngineHandle) -> Engine {
    handle.0.borrow().clone()
}

/// A handle around an engine, for scripts.
pub fn handle_of(engine: Engine) -> EngineHandle {
    EngineHandle(Rc::new(RefCell::new(engine)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::SourceError;
    use crate::script::{Limits, ScriptLog, load_engines};

    #[test]
    fn infinite_ranges_and_terms_are_located_errors() {
        let load = |body: &str| {
            let src = format!("let e = fuzzy_engine(\"x\");\n{body}\ne");
            load_engines(&src, "inf.rhai", Limits::default(), &ScriptLog::new())
        };
        let err = load("let d = e.input(\"d\", 0, \"inf\");").unwrap_err();
        assert_eq!(err.line, 2, "{err}");
        assert!(err.message.contains("finite"), "{err}");
        let err = load("let d = e.input(\"d\", 0, 1);\nd.set_term(\"a\", \"gaussian\", [5, \"inf\"]);").unwrap_err();
        assert_eq!(err.line, 3, "{err}");
        let err = load("let d = e.input(\"d\", 0, 1);\nd.term(\"a\", \"triangle\", [0, 1, 2, 3]);").unwrap_err();
        assert!(err.message.contains("height"), "{err}");
        let deep = format!(
            "let d = e.input(\"d\", 0, 1);\nd.term(\"a\", \"triangle\", [0, 0, 1]);\n\
             let o = e.output(\"o\", 0, 1);\no.term(\"b\", \"triangle\", [0, 0, 1]);\n\
             let b = e.rule_block(\"r\");\nb.rule(\"if {}d is a{} then o is b\");",
            "(".repeat(10_000),
            ")".repeat(10_000)
        );
        let err = load(&deep).unwrap_err();
        assert!(err.message.contains("nested deeper"), "{err}");
    }

    #[test]
    fn function_terms_take_a_formula() {
        let load = |body: &str| {
            let src = format!(
                "let e = fuzzy_engine(\"f\");\nlet d = e.input(\"d\", 0, 1);\n{body}\n\
                 let o = e.output(\"o\", 0, 1);\no.term(\"b\", \"triangle\", [0, 0.5, 1]);\ne"
            );
            load_engines(&src, "f.rhai", Limits::default(), &ScriptLog::new())
        };
        let engines = load("d.term(\"a\", \"Function\", \"1 - x * d\");").unwrap();
        assert_eq!(engines[0].inputs[0].terms[0].term, Term::function("1 - x * d").unwrap());
        let err = load("d.term(\"a\", \"function\", \"1 - sin(x\");").unwrap_err();
        assert_eq!(err.line, 3, "{err}");
        assert!(err.message.contains("column 5 of the formula") && err.message.contains("never closed"), "{err}");
        let err = load("d.term(\"a\", \"function\", \"1 - y\");").unwrap_err();
        assert!(err.message.contains("'y'"), "{err}");
        let err = load("d.set_term(\"a\", \"triangle\", \"1 - x\");").unwrap_err();
        assert!(err.message.contains("array of numbers"), "{err}");
    }

    const SCRIPT: &str = r#"
let e = fuzzy_engine("demo");
let d = e.input("distance", 0, 4);
d.term("near", "triangle", [0, 0, 2]).term("far", "Triangle", [1.0, 4.0, 4.0]);
let t = e.output("turn", -60, 60);
t.term("left", "triangle", [-60, -60, 0]).term("right", "triangle", [0, 60, 60]);
t.defuzzifier("centroid", 200).default_value("nan").lock_previous(true);
let b = e.rule_block("main");
b.activation("highest", [1]);
b.rules(["if distance is near then turn is left", "if distance is far then turn is right with 0.5"]);
e
"#;

    fn load(src: &str) -> Result<Vec<Engine>, SourceError> {
        load_engines(src, "t.rhai", Limits::default(), &ScriptLog::new())
    }

    #[test]
    fn builds_an_engine() {
        let engines = load(SCRIPT).unwrap();
        let e = &engines[0];
        assert_eq!(e.inputs[0].terms.len(), 2);
        assert_eq!(e.outputs[0].defuzzifier, Some(Defuzzifier::Centroid { resolution: 200 }));
        assert!(e.outputs[0].lock_previous);
        assert_eq!(e.rule_blocks[0].activation, Activation::Highest { rules: 1 });
        assert_eq!(e.rule_blocks[0].rules[1].weight, 0.5);
    }

    #[test]
    fn rule_errors_point_at_the_call() {
        let bad = SCRIPT.replace("if distance is far then", "if distance is farr then");
        let err = load(&bad).unwrap_err();
        assert_eq!(err.line, 10, "{err}");
        assert!(err.message.contains("farr") && err.message.contains("column 16"), "{err}");
        let bad = SCRIPT.replace("\"triangle\", [0, 0, 2]", "\"triangle\", [0, 0]");
        let err = load(&bad).unwrap_err();
        assert_eq!(err.line, 4, "{err}");
        let bad = SCRIPT.replace("e.input(\"distance\", 0, 4)", "e.input(\"distance\", 4, 0)");
        assert!(load(&bad).unwrap_err().message.contains("inverted"));
        let bad = SCRIPT.replace("\ne\n", "\n42\n");
        assert!(load(&bad).unwrap_err().message.contains("must end with a fuzzy engine"));
        let bad = SCRIPT.replace("t.defuzzifier(\"centroid\", 200)", "d.defuzzifier(\"centroid\", 200)");
        assert!(load(&bad).unwrap_err().message.contains("input"));
    }
}
