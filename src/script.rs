//! Rhai scripting host: the one hardened Rhai engine constructor of the project, the
//! conversion of script failures into [`SourceError`]s (DESIGN.md §7), and the loaders that
//! run a script and take what it built: [`load_engines`] (fuzzy engines, [`fuzzy_api`]) and
//! [`load_scenario`] (a world and its tasks, [`map_api`]). The host sits above both APIs: it
//! registers them, and they know nothing of it.
//!
//! Scripts only *build* plain Rust data (fuzzy engines, maps and tasks) that the core
//! validates; nothing on a hot path ever calls back into a script.
//!
//! Invariant: every script runs under [`Limits`] (operations, call depth, expression depth,
//! string/array/map sizes, and the memory it holds when a [`MemoryProbe`] is set), without
//! `eval`, without module import, without a clock, and its `print`/`debug` output goes to a
//! [`ScriptLog`], never to stdout.
//!
//! Rhai's sizes bound each value, not how many a script keeps (in variables, or captured by
//! closures), so a script could fill memory with values each within them. The host bounds the
//! sum: the `strider` binary installs an allocator that counts the bytes each thread holds and
//! hands the library a probe of it ([`set_memory_probe`]); before each operation the engine
//! reads it and stops a script holding more than [`Limits::max_memory_bytes`] since it started.

pub mod fuzzy_api;
pub mod map_api;

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::OnceLock;

use crate::diagnostic::SourceError;
use crate::fuzzy::Engine;
use crate::scenario::Scenario;

/// Hard limits for one script run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Maximum number of Rhai operations (an endless loop stops here); default 20,000,000.
    pub max_operations: u64,
    /// Maximum function call depth; default 32.
    pub max_call_levels: usize,
    /// Maximum expression nesting depth (global, in functions); default 64, 32.
    pub max_expr_depths: (usize, usize),
    /// Maximum string length in bytes; default 1 MiB.
    pub max_string_size: usize,
    /// Maximum array length; default 100,000.
    pub max_array_size: usize,
    /// Maximum object map size; default 10,000.
    pub max_map_size: usize,
    /// Most bytes a script may hold on the heap beyond what its thread held when it started,
    /// checked before each operation when a [`MemoryProbe`] is set; default 1 GiB.
    pub max_memory_bytes: u64,
}

/// The bytes the calling thread holds on the heap (allocated less freed), as an allocator
/// installed by the program counts them.
pub type MemoryProbe = fn() -> i64;

/// The probe every script engine reads, set once by the program that counts allocations.
static MEMORY_PROBE: OnceLock<MemoryProbe> = OnceLock::new();

/// Sets the probe that bounds what scripts hold ([`Limits::max_memory_bytes`]); the `strider`
/// binary sets it at start from its counting allocator. False when one was already set.
pub fn set_memory_probe(probe: MemoryProbe) -> bool {
    MEMORY_PROBE.set(probe).is_ok()
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_operations: 20_000_000,
            max_call_levels: 32,
            max_expr_depths: (64, 32),
            max_string_size: 1 << 20,
            max_array_size: 100_000,
            max_map_size: 10_000,
            max_memory_bytes: 1 << 30,
        }
    }
}

/// Lines a script printed with `print` or `debug`, in order.
#[derive(Debug, Clone, Default)]
pub struct ScriptLog(Rc<RefCell<Vec<String>>>);

impl ScriptLog {
    /// A new, empty log.
    pub fn new() -> Self {
        ScriptLog::default()
    }

    /// Appends a line.
    pub fn push(&self, line: String) {
        self.0.borrow_mut().push(line);
    }

    /// Every line so far.
    pub fn lines(&self) -> Vec<String> {
        self.0.borrow().clone()
    }
}

/// The project's Rhai engine: limits applied, `eval` disabled, output routed to `log`, and
/// strider's script API registered.
pub fn hardened_engine(limits: Limits, log: &ScriptLog) -> rhai::Engine {
    let mut engine = rhai::Engine::new();
    engine
        .set_max_operations(limits.max_operations)
        .set_max_call_levels(limits.max_call_levels)
        .set_max_expr_depths(limits.max_expr_depths.0, limits.max_expr_depths.1)
        .set_max_string_size(limits.max_string_size)
        .set_max_array_size(limits.max_array_size)
        .set_max_map_size(limits.max_map_size)
        .set_max_variables(10_000)
        .set_max_functions(1_000)
        .set_strict_variables(true)
        .disable_symbol("eval");
    if let Some(&probe) = MEMORY_PROBE.get() {
        let (start, max) = (probe(), i64::try_from(limits.max_memory_bytes).unwrap_or(i64::MAX));
        engine.on_progress(move |_| {
            (probe().saturating_sub(start) > max).then(|| {
                format!("script holds more than {} MiB, its memory limit", limits.max_memory_bytes >> 20).into()
            })
        });
    }
    let print_log = log.clone();
    engine.on_print(move |s| print_log.push(s.to_string()));
    let debug_log = log.clone();
    engine.on_debug(move |s, source, pos| {
        let at = match (source, pos.line()) {
            (Some(src), Some(l)) => format!("{src}:{l}: "),
            (None, Some(l)) => format!("line {l}: "),
            _ => String::new(),
        };
        debug_log.push(format!("{at}{s}"));
    });
    fuzzy_api::register(&mut engine);
    map_api::register(&mut engine);
    engine
}

/// What a script value is, in the words of the script API (`a world`, `a fuzzy engine`, `an
/// integer`…), for messages about a script that returned or passed the wrong thing.
pub fn value_kind(value: &rhai::Dynamic) -> String {
    if value.is::<map_api::MapHandle>() {
        return "a world (the result of a map script)".into();
    }
    if value.is::<fuzzy_api::EngineHandle>() {
        return "a fuzzy engine".into();
    }
    let name = match value.type_name() {
        "i64" => "integer",
        "f64" => "number",
        "bool" => "boolean",
        "()" => "nothing (unit)",
        "char" => "character",
        other => other.rsplit("::").next().unwrap_or(other),
    };
    let article = if name.starts_with(['a', 'e', 'i', 'o', 'u']) { "an" } else { "a" };
    if name.starts_with("nothing") { name.to_string() } else { format!("{article} {name}") }
}

/// Converts a Rhai failure into a located error in `file`.
pub fn script_error(file: &str, err: &rhai::EvalAltResult) -> SourceError {
    let pos = err.position();
    // Errors raised inside registered functions carry the call site; unwrap nested calls so
    // the message says what went wrong rather than which wrapper failed.
    let mut inner = err;
    while let rhai::EvalAltResult::ErrorInFunctionCall(_, _, e, _) = inner {
        inner = e;
    }
    let message = match inner {
        rhai::EvalAltResult::ErrorRuntime(value, _) => value.to_string(),
        rhai::EvalAltResult::ErrorTooManyOperations(_) => {
            "script exceeded its operation limit (an endless loop?)".to_string()
        }
        // Stopped by the host (its memory limit): the reason is the token.
        rhai::EvalAltResult::ErrorTerminated(reason, _) => reason.to_string(),
        other => {
            // Rhai appends the position to its messages; the position is reported separately.
            let text = other.to_string();
            match text.rfind(" (line ") {
                Some(i) => text[..i].to_string(),
                None => text,
            }
        }
    };
    let inner_pos = inner.position();
    let pos = if inner_pos.is_none() { pos } else { inner_pos };
    SourceError::new(file, pos.line().unwrap_or(0), pos.position().unwrap_or(0), message)
}

/// Compiles and runs `source` (named `file` in errors) and returns its final value.
pub fn run(source: &str, file: &str, limits: Limits, log: &ScriptLog) -> Result<rhai::Dynamic, SourceError> {
    let engine = hardened_engine(limits, log);
    let ast = engine.compile(source).map_err(|e| {
        let pos = e.position();
        let text = e.0.to_string();
        SourceError::new(file, pos.line().unwrap_or(0), pos.position().unwrap_or(0), text)
    })?;
    engine.eval_ast::<rhai::Dynamic>(&ast).map_err(|e| script_error(file, &e))
}

/// Runs a script that builds fuzzy engines and returns them, validated.
pub fn load_engines(source: &str, file: &str, limits: Limits, log: &ScriptLog) -> Result<Vec<Engine>, SourceError> {
    let value = run(source, file, limits, log)?;
    let engines = engines_from(value).map_err(|m| SourceError::new(file, 0, 0, m))?;
    for e in &engines {
        e.validate().map_err(|err| SourceError::new(file, 0, 0, format!("engine '{}': {}", e.name, err.message)))?;
    }
    Ok(engines)
}

/// The engines a script's final value holds: one engine, or an array of engines.
pub fn engines_from(value: rhai::Dynamic) -> Result<Vec<Engine>, String> {
    if let Some(e) = value.clone().try_cast::<fuzzy_api::EngineHandle>() {
        return Ok(vec![fuzzy_api::engine_of(&e)]);
    }
    if let Some(items) = value.clone().try_cast::<rhai::Array>() {
        let mut out = Vec::new();
        for (i, item) in items.into_iter().enumerate() {
            match item.clone().try_cast::<fuzzy_api::EngineHandle>() {
                Some(e) => out.push(fuzzy_api::engine_of(&e)),
                None => {
                    return Err(format!(
                        "item {} of the returned array is {}, not a fuzzy engine",
                        i + 1,
                        value_kind(&item)
                    ));
                }
            }
        }
        if !out.is_empty() {
            return Ok(out);
        }
    }
    let hint = if value.is::<map_api::MapHandle>() { " (is this a map given as rules?)" } else { "" };
    Err(format!("the script must end with a fuzzy engine or an array of them, found {}{hint}", value_kind(&value)))
}

/// Runs a map script and returns its validated scenario.
pub fn load_scenario(source: &str, file: &str, limits: Limits, log: &ScriptLog) -> Result<Scenario, SourceError> {
    let value = run(source, file, limits, log)?;
    let handle = value.clone().try_cast::<map_api::MapHandle>().ok_or_else(|| {
        SourceError::new(file, 0, 0, format!("the script must end with a world, found {}", value_kind(&value)))
    })?;
    handle.scenario(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endless_loop_is_stopped_with_a_location() {
        let log = ScriptLog::new();
        let limits = Limits { max_operations: 100_000, ..Limits::default() };
        let err = run("let x = 0;\nloop { x += 1; }", "loop.rhai", limits, &log).unwrap_err();
        assert_eq!(err.file, "loop.rhai");
        assert_eq!(err.line, 2);
        assert!(err.message.contains("operation limit"), "{err}");
    }

    #[test]
    fn print_goes_to_the_log_and_eval_is_gone() {
        let log = ScriptLog::new();
        let value = run("print(\"hello\"); debug(1); 0", "p.rhai", Limits::default(), &log).unwrap();
        assert_eq!(value.as_int(), Ok(0));
        assert_eq!(log.lines()[0], "hello");
        assert_eq!(log.lines().len(), 2);
        let err = run("eval(\"1\")", "e.rhai", Limits::default(), &log).unwrap_err();
        assert_eq!(err.line, 1, "{err}");
    }

    #[test]
    fn syntax_errors_name_line_and_column() {
        let log = ScriptLog::new();
        let err = run("let a = 1;\nlet b = ;", "s.rhai", Limits::default(), &log).unwrap_err();
        assert_eq!((err.line, err.col), (2, 9), "{err}");
        let err = run("fn f(n) { f(n + 1) }\nf(0)", "r.rhai", Limits::default(), &log).unwrap_err();
        assert!(err.line >= 1, "{err}");
    }
}
