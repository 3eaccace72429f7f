//! `strider experiment SCRIPT`: Rhai scripts that drive whole experiments (seed 000 §4-style
//! comparisons): load maps or generate seeded worlds, build, edit or load rule sets, run
//! episodes and batches, and read their metrics.
//!
//! ```rhai
//! let base = default_rules();                      // array of fuzzy engines
//! let s = run_batch("semi", 100, 42, base);        // density or a map, episodes, seed, rules
//! print(`success ${s.success_rate}`);
//! let m = load_map("maps/u_trap.rhai");
//! let e = run_episode(m, base, 0, 1);              // map, rules, task, seed
//! print(`reached ${e.reached} ratio ${e.path_ratio}`);
//! let s = snapshot(m, base, 1, "snapshots/u_trap"); // map, rules, seed, golden directory
//! print(s.report);
//! ```
//! `snapshot` takes the same map forms as `load_map` (or a loaded map) and an optional options
//! map (`every`, `width`, `height`, `tolerance`, `update`, `body`, `episode`, `side`); it runs
//! [`crate::snapshot::check_episode`] like `strider snapshot` and returns `passed`, `updated`,
//! `frames`, `changed`, `divergence_s` (`()` when the trajectories agree) and `report`. A
//! script whose snapshots did not all match exits with code 1. `reproduce_table1` runs seed
//! 000's Table 1 as `strider reproduce table1` does ([`register_table1`]).
//! The functions here do file IO and run simulations, so they live with the front-ends and
//! are registered on top of the one hardened script engine. `print` and `debug` go to the log,
//! stderr, as the script runs (so the log is kept when the script fails), never to stdout;
//! each line is prefixed with the script's file (and `debug`'s with its line). A script runs at most
//! [`MAX_SCRIPT_EPISODES`] episodes in all.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::Arc;

use anyhow::anyhow;
use clap::Args;
use rhai::{Array, Dynamic, EvalAltResult, Map};

use crate::experiment::{self, EpisodeRecord, Field, Summary};
use crate::fuzzy::Engine;
use crate::load::{
    self, BodyArgs, BodyKind, Failure, MapSource, MapSpec, Outcome, builtin_database, job, load_animation,
};
use crate::maps::generate::Density;
use crate::maps::kind::{self, WorldKind};
use crate::reproduce::{self, Environment, Report, Table1Options};
use crate::scenario::Scenario;
use crate::script::fuzzy_api::{self, EngineHandle};
use crate::script::{Limits, ScriptLog, hardened_engine, script_error};
use crate::sim::{ControllerParams, LayeredController, StepParameters};
use crate::snapshot::{self, Settings, Tolerance};

type Res<T> = Result<T, Box<EvalAltResult>>;

/// A scenario (world and tasks) held by a script.
#[derive(Debug, Clone)]
pub struct ScenarioHandle(pub(crate) Arc<Scenario>);

/// `strider experiment` options.
#[derive(Debug, Args)]
pub struct ExperimentArgs {
    /// The experiment script.
    pub script: PathBuf,
}

fn engines(rules: &Array) -> Res<Vec<Engine>> {
    rules
        .iter()
        .enumerate()
        .map(|(i, r)| {
            r.clone().try_cast::<EngineHandle>().map(|h| fuzzy_api::engine_of(&h)).ok_or_else(|| {
                format!("rules item {} is {}, not a fuzzy engine", i + 1, crate::script::value_kind(r)).into()
            })
        })
        .collect()
}

fn controller(rules: &Array) -> Res<LayeredController> {
    let list = engines(rules)?;
    for e in &list {
        e.validate().map_err(|err| -> Box<EvalAltResult> { format!("engine '{}': {}", e.name, err.message).into() })?;
    }
    LayeredController::new(&list, ControllerParams::default()).map_err(Into::into)
}

fn rules_array(engines: Vec<Engine>) -> Array {
    engines.into_iter().map(|e| Dynamic::from(fuzzy_api::handle_of(e))).collect()
}

fn opt(x: Option<f64>) -> Dynamic {
    x.map_or(Dynamic::UNIT, Dynamic::from_float)
}

/// An episode record as a script map: every field of [`EpisodeRecord::fields`], `()` where
/// there is no value.
fn record_map(r: &EpisodeRecord) -> Map {
    r.fields()
        .iter()
        .map(|(name, f)| {
            let v = match *f {
                Field::Count(n) => Dynamic::from_int(i64::try_from(n).unwrap_or(i64::MAX)),
                // A script's integers are 64-bit signed: a seed is kept whole as its digits.
                Field::Key(n) => Dynamic::from(n.to_string()),
                Field::Number(x) => Dynamic::from_float(x),
                Field::Flag(b) => Dynamic::from_bool(b),
                Field::Text(t) => Dynamic::from(t.to_string()),
                Field::Missing => Dynamic::UNIT,
            };
            ((*name).into(), v)
        })
        .collect()
}

fn summary_map(s: &Summary) -> Map {
    let mut m = Map::new();
    m.insert("episodes".into(), Dynamic::from_int(s.episodes as i64));
    m.insert("reached".into(), Dynamic::from_int(s.reached as i64));
    m.insert("success_rate".into(), Dynamic::from_float(s.success_rate));
    m.insert("median_path_ratio".into(), opt(s.median_path_ratio));
    m.insert("p90_path_ratio".into(), opt(s.p90_path_ratio));
    m.insert("collisions".into(), Dynamic::from_int(s.collisions as i64));
    m.insert("min_clearance_m".into(), Dynamic::from_float(s.min_clearance_m));
    m
}

fn seed_of(seed: i64) -> Res<u64> {
    u64::try_from(seed).map_err(|_| format!("seed must be ≥ 0, found {seed}").into())
}

/// Most episodes one experiment script may run in all (`run_episode` and `run_batch`
/// together): the operation limit counts a native call as one operation, so this budget is
/// what stops a script that loops over episodes.
pub const MAX_SCRIPT_EPISODES: u64 = 20_000;

/// The episodes a script has left to run (see [`MAX_SCRIPT_EPISODES`]).
#[derive(Debug, Clone)]
pub struct EpisodeBudget(Rc<RefCell<u64>>);

impl Default for EpisodeBudget {
    fn default() -> Self {
        EpisodeBudget::new(MAX_SCRIPT_EPISODES)
    }
}

impl EpisodeBudget {
    /// A budget of `episodes`.
    pub fn new(episodes: u64) -> Self {
        EpisodeBudget(Rc::new(RefCell::new(episodes)))
    }

    /// Takes `n` episodes from the budget, or fails without taking any.
    pub(crate) fn spend(&self, n: u64) -> Res<()> {
        let mut left = self.0.borrow_mut();
        if n > *left {
            return Err(
                format!("the script would run more episodes than its budget ({} left, {n} asked)", *left).into()
            );
        }
        *left -= n;
        Ok(())
    }
}

fn batch(source: &MapSource, episodes: i64, seed: i64, rules: &Array, budget: &EpisodeBudget) -> Res<Map> {
    let n = usize::try_from(episodes)
        .ok()
        .filter(|n| *n > 0)
        .ok_or_else(|| -> Box<EvalAltResult> { format!("episodes must be at least 1, found {episodes}").into() })?;
    budget.spend(n as u64)?;
    let c = controller(rules)?;
    let seed = seed_of(seed)?;
    let make = |i: usize| job(source, i, seed);
    let records = experiment::run_batch_of(n, &make, &c, &StepParameters::default(), &|| {});
    Ok(summary_map(&experiment::summarize(&records)))
}

/// Registers the experiment functions on a script engine; relative paths resolve from `base`.
/// The episodes they run are taken from `budget`.
pub fn register(engine: &mut rhai::Engine, base: &Path, budget: &EpisodeBudget) {
    engine.register_type_with_name::<ScenarioHandle>("Scenario");
    let dir = base.to_path_buf();
    engine.register_fn("load_map", move |path: &str| -> Res<ScenarioHandle> {
        if path.starts_with("random:") {
            return Err(format!("'{path}' is a generator; use random_world").into());
        }
        match load::load_map(&MapSpec::file(dir.join(path))).logged() {
            Ok(MapSource::Scenario(s)) => Ok(ScenarioHandle(s)),
            Ok(MapSource::Random(_)) => Err(format!("'{path}' is a generator; use random_world").into()),
            Ok(MapSource::Batch(_)) => Err(format!("'{path}' is a folder of worlds; load one of them").into()),
            Err(e) => Err(e.to_string().into()),
        }
    });
    engine.register_fn("random_world", |name: &str, seed: i64| -> Res<ScenarioHandle> {
        let k: WorldKind = name.parse().map_err(|e| -> Box<EvalAltResult> { format!("{e}").into() })?;
        Ok(ScenarioHandle(Arc::new(kind::generate(k, seed_of(seed)?))))
    });
    engine.register_fn("name", |s: &mut ScenarioHandle| s.0.name.clone());
    engine.register_fn("tasks", |s: &mut ScenarioHandle| s.0.tasks.len() as i64);
    engine.register_fn("default_rules", || -> Res<Array> {
        let list = load::load_engines(None).logged().map_err(|e| -> Box<EvalAltResult> { e.to_string().into() })?;
        Ok(rules_array(list))
    });
    let dir = base.to_path_buf();
    engine.register_fn("load_rules", move |path: &str| -> Res<Array> {
        let list = load::load_engines(Some(&dir.join(path)))
            .logged()
            .map_err(|e| -> Box<EvalAltResult> { e.to_string().into() })?;
        Ok(rules_array(list))
    });
    let b = budget.clone();
    engine.register_fn("run_episode", move |s: &mut ScenarioHandle, rules: Array, task: i64, seed: i64| -> Res<Map> {
        let t = usize::try_from(task).ok().filter(|t| *t < s.0.tasks.len()).ok_or_else(|| -> Box<EvalAltResult> {
            format!("task {task} out of range (the map has {})", s.0.tasks.len()).into()
        })?;
        b.spend(1)?;
        let c = controller(&rules)?;
        let mut params = StepParameters::default();
        params.limits.radius = s.0.agent_radius;
        let e = experiment::run_episode(&s.0, &s.0.world(), t, &c, &params, 0, seed_of(seed)?);
        Ok(record_map(&e.record))
    });
    let b = budget.clone();
    engine.register_fn("run_batch", move |name: &str, episodes: i64, seed: i64, rules: Array| -> Res<Map> {
        let k: WorldKind = name.parse().map_err(|e| -> Box<EvalAltResult> { format!("{e}").into() })?;
        batch(&MapSource::Random(k), episodes, seed, &rules, &b)
    });
    let b = budget.clone();
    engine.register_fn("run_batch", move |s: ScenarioHandle, episodes: i64, seed: i64, rules: Array| -> Res<Map> {
        batch(&MapSource::Scenario(s.0), episodes, seed, &rules, &b)
    });
    engine.register_fn("table", |rows: Array| table(&rows, TABLE_DECIMALS));
    engine.register_fn("table", |rows: Array, decimals: i64| table(&rows, decimals));
}

/// Decimals `table(rows)` writes numbers with.
const TABLE_DECIMALS: i64 = 3;

/// `table(rows)`, `table(rows, decimals)`: rows (arrays of cells) as aligned columns, one line
/// each, two spaces apart; numbers rounded to `decimals` places and aligned right, whole
/// numbers as they are, `()` (a figure not measured) as `-`, everything else as its text,
/// aligned left.
fn table(rows: &Array, decimals: i64) -> Res<String> {
    let decimals = usize::try_from(decimals)
        .ok()
        .filter(|d| *d <= 12)
        .ok_or_else(|| -> Box<EvalAltResult> { format!("table: decimals must be 0..=12, found {decimals}").into() })?;
    let mut cells: Vec<Vec<(String, bool)>> = Vec::new();
    for row in rows {
        let row = row.clone().try_cast::<Array>().ok_or("table: each row must be an array of cells")?;
        cells.push(
            row.iter()
                .map(|c| {
                    if let Ok(x) = c.as_float() {
                        (format!("{x:.decimals$}"), true)
                    } else if let Ok(n) = c.as_int() {
                        (n.to_string(), true)
                    } else if c.is_unit() {
                        ("-".to_string(), true)
                    } else {
                        (c.to_string(), false)
                    }
                })
                .collect(),
        );
    }
    let columns = cells.iter().map(Vec::len).max().unwrap_or(0);
    let width = |k: usize| cells.iter().filter_map(|r| r.get(k)).map(|(t, _)| t.chars().count()).max().unwrap_or(0);
    let widths: Vec<usize> = (0..columns).map(width).collect();
    let lines: Vec<String> = cells
        .iter()
        .map(|row| {
            let line: Vec<String> = row
                .iter()
                .zip(&widths)
                .map(|((text, number), &w)| if *number { format!("{text:>w$}") } else { format!("{text:<w$}") })
                .collect();
            line.join("  ").trim_end().to_string()
        })
        .collect();
    Ok(lines.join("\n"))
}

/// Reports of the snapshots that did not match while an experiment script ran.
#[derive(Debug, Clone, Default)]
pub struct SnapshotFailures(Rc<RefCell<Vec<String>>>);

impl SnapshotFailures {
    /// The reports, in the order the snapshots ran.
    pub fn reports(&self) -> Vec<String> {
        self.0.borrow().clone()
    }
}

/// What a script's options map asks of a snapshot.
struct SnapshotOptions {
    settings: Settings,
    body: BodyKind,
    episode: usize,
}

fn snapshot_options(options: &Map) -> Res<SnapshotOptions> {
    let mut o = SnapshotOptions { settings: Settings::default(), body: BodyKind::Animated, episode: 0 };
    let count = |key: &str, v: &Dynamic, max: i64| -> Res<i64> {
        v.as_int()
            .ok()
            .filter(|n| (0..=max).contains(n))
            .ok_or_else(|| format!("snapshot option '{key}' must be an integer in 0..={max}, found {v}").into())
    };
    for (key, v) in options {
        match key.as_str() {
            "every" => o.settings.every = count(key, v, i64::from(u32::MAX))? as usize,
            "width" => o.settings.size.0 = count(key, v, 8192)?.max(16) as u32,
            "height" => o.settings.size.1 = count(key, v, 8192)?.max(16) as u32,
            "tolerance" => o.settings.tolerance = Tolerance::channel(count(key, v, 255)? as u8),
            "episode" => o.episode = count(key, v, i64::from(u32::MAX))? as usize,
            "update" | "side" => {
                let b = v.as_bool().map_err(|_| format!("snapshot option '{key}' must be true or false, found {v}"))?;
                if key == "update" { o.settings.update = b } else { o.settings.side = b }
            }
            "body" => {
                o.body = match v.clone().into_string().as_deref() {
                    Ok("animated") => BodyKind::Animated,
                    Ok("disc") => BodyKind::Disc,
                    _ => {
                        return Err(
                            format!("snapshot option 'body' must be \"animated\" or \"disc\", found {v}").into()
                        );
                    }
                }
            }
            other => {
                return Err(format!(
                    "unknown snapshot option '{other}' (every, width, height, tolerance, update, body, episode, side)"
                )
                .into());
            }
        }
    }
    Ok(o)
}

fn take_snapshot(
    source: &MapSource,
    rules: &Array,
    seed: i64,
    dir: &Path,
    options: &Map,
    failures: &SnapshotFailures,
) -> Res<Map> {
    let o = snapshot_options(options)?;
    let c = controller(rules)?;
    let job = job(source, o.episode, seed_of(seed)?);
    let animation = load_animation(&BodyArgs { body: o.body, ..BodyArgs::default() }).map_err(failure_text)?;
    let episode = snapshot::Episode::new(job.scenario, job.task, job.seed, c, animation);
    let report = snapshot::check_episode(&episode, &o.settings, dir)
        .map_err(|e| -> Box<EvalAltResult> { e.to_string().into() })?;
    if !report.passed() {
        failures.0.borrow_mut().push(report.to_string());
    }
    let mut m = Map::new();
    m.insert("passed".into(), Dynamic::from_bool(report.passed()));
    m.insert("updated".into(), Dynamic::from_bool(report.updated));
    m.insert("frames".into(), Dynamic::from_int(report.frames.len() as i64));
    m.insert("changed".into(), Dynamic::from_int(report.failures().count() as i64));
    m.insert("divergence_s".into(), opt(report.divergence.map(|d| d.time_s)));
    m.insert("report".into(), Dynamic::from(report.to_string()));
    Ok(m)
}

fn failure_text(f: Failure) -> Box<EvalAltResult> {
    match f {
        Failure::Input(e) | Failure::Task(e) => format!("{e:#}").into(),
    }
}

/// Registers `snapshot(map, rules, seed, dir[, options])` on a script engine: `map` is a
/// loaded map or the same strings `load_map` and `random:KIND` take; relative paths resolve
/// from `base`. The returned handle collects the reports of snapshots that did not match.
pub fn register_snapshot(engine: &mut rhai::Engine, base: &Path) -> SnapshotFailures {
    let failures = SnapshotFailures::default();
    let resolve = {
        let base = base.to_path_buf();
        move |path: &str| -> Res<MapSource> {
            let spec = match MapSpec::parse(Some(path)).map_err(|e| -> Box<EvalAltResult> { e.to_string().into() })? {
                MapSpec::File { path, scen } => MapSpec::File { path: base.join(path), scen },
                other => other,
            };
            load::load_map(&spec).logged().map_err(|e| e.to_string().into())
        }
    };
    let (f, b) = (failures.clone(), base.to_path_buf());
    engine.register_fn("snapshot", move |s: ScenarioHandle, rules: Array, seed: i64, dir: &str| {
        take_snapshot(&MapSource::Scenario(s.0), &rules, seed, &b.join(dir), &Map::new(), &f)
    });
    let (f, b) = (failures.clone(), base.to_path_buf());
    engine.register_fn("snapshot", move |s: ScenarioHandle, rules: Array, seed: i64, dir: &str, options: Map| {
        take_snapshot(&MapSource::Scenario(s.0), &rules, seed, &b.join(dir), &options, &f)
    });
    let (f, b, r) = (failures.clone(), base.to_path_buf(), resolve.clone());
    engine.register_fn("snapshot", move |map: &str, rules: Array, seed: i64, dir: &str| {
        take_snapshot(&r(map)?, &rules, seed, &b.join(dir), &Map::new(), &f)
    });
    let (f, b) = (failures.clone(), base.to_path_buf());
    engine.register_fn("snapshot", move |map: &str, rules: Array, seed: i64, dir: &str, options: Map| {
        take_snapshot(&resolve(map)?, &rules, seed, &b.join(dir), &options, &f)
    });
    failures
}

/// Progress of a script's experiment: none (the script prints what it wants).
struct Quiet;

impl Report for Quiet {
    fn phase(&self, _: &str, _: &str) {}
    fn round(&self, _: &str, _: u64, _: f64) {}
}

fn json_to_dynamic(v: &serde_json::Value) -> Dynamic {
    match v {
        serde_json::Value::Null => Dynamic::UNIT,
        serde_json::Value::Bool(b) => Dynamic::from_bool(*b),
        serde_json::Value::Number(n) => match n.as_i64() {
            Some(i) => Dynamic::from_int(i),
            None => Dynamic::from_float(n.as_f64().unwrap_or(f64::NAN)),
        },
        serde_json::Value::String(s) => Dynamic::from(s.clone()),
        serde_json::Value::Array(a) => Dynamic::from_array(a.iter().map(json_to_dynamic).collect()),
        serde_json::Value::Object(o) => {
            Dynamic::from_map(o.iter().map(|(k, v)| (k.as_str().into(), json_to_dynamic(v))).collect())
        }
    }
}

fn field<T: Clone + 'static>(m: &Map, key: &str, what: &str) -> Res<T> {
    m.get(key)
        .and_then(|v| v.clone().try_cast::<T>())
        .ok_or_else(|| format!("environment: `{key}` must be {what}").into())
}

fn count(options: &Map, key: &str, default: u64, max: u64) -> Res<u64> {
    match options.get(key) {
        None => Ok(default),
        Some(v) => v
            .as_int()
            .ok()
            .and_then(|i| u64::try_from(i).ok())
            .filter(|i| (1..=max).contains(i))
            .ok_or_else(|| format!("option `{key}` must be an integer in 1..={max}").into()),
    }
}

/// Registers `reproduce_table1(environments, options, rules)` on an experiment engine:
/// `environments` is an array of `#{name, map, density, obstacles}` (`map` from `load_map`,
/// `density` one of "sparse", "semi", "cluttered" for the unseen worlds, `obstacles` the
/// pure-RL state's `k`); `options` may set `seed`, `held_out`, `unseen`, `max_episodes`,
/// `fuzzy_episodes`, `round`; `rules` are the fuzzy + RL planner's rules. Returns the table as
/// a map shaped like `strider reproduce table1 --format json`. The simulated episodes of the
/// fuzzy + RL planner count against the script's episode budget.
pub fn register_table1(engine: &mut rhai::Engine, budget: &EpisodeBudget) {
    let budget = budget.clone();
    engine.register_fn("reproduce_table1", move |envs: Array, options: Map, rules: Array| -> Res<Map> {
        let mut environments = Vec::new();
        for e in &envs {
            let m =
                e.clone().try_cast::<Map>().ok_or("each environment must be a map #{name, map, density, obstacles}")?;
            let name: rhai::ImmutableString = field(&m, "name", "a string")?;
            let map: ScenarioHandle = field(&m, "map", "a map from load_map")?;
            let density: rhai::ImmutableString = field(&m, "density", "\"sparse\", \"semi\" or \"cluttered\"")?;
            let density = match density.as_str() {
                "sparse" => Density::Sparse,
                "semi" => Density::Semi,
                "cluttered" => Density::Cluttered,
                other => return Err(format!("environment `{name}`: unknown density `{other}`").into()),
            };
            let obstacles: i64 = field(&m, "obstacles", "an integer")?;
            let obstacles =
                usize::try_from(obstacles).ok().filter(|k| *k <= 8).ok_or_else(|| -> Box<EvalAltResult> {
                    format!("environment `{name}`: obstacles must be 0..=8").into()
                })?;
            environments.push(Environment { name: name.to_string(), scenario: Arc::clone(&map.0), density, obstacles });
        }
        let defaults = Table1Options::default();
        let options = Table1Options {
            seed: match options.get("seed") {
                None => defaults.seed,
                Some(v) => v.as_int().ok().and_then(|i| u64::try_from(i).ok()).ok_or("option `seed` must be ≥ 0")?,
            },
            held_out: count(&options, "held_out", defaults.held_out as u64, 10_000)? as usize,
            unseen: count(&options, "unseen", defaults.unseen as u64, 10_000)? as usize,
            max_episodes: count(&options, "max_episodes", defaults.max_episodes, 10_000_000)?,
            fuzzy_episodes: count(&options, "fuzzy_episodes", defaults.fuzzy_episodes, 10_000_000)?,
            round: count(&options, "round", defaults.round, 10_000_000)?,
            ..defaults
        };
        budget.spend(((options.held_out + options.unseen) * environments.len()) as u64)?;
        let c = controller(&rules)?;
        let db = builtin_database().map_err(failure_text)?;
        let table = reproduce::run(&db, &c, &environments, options, &Quiet);
        let value = serde_json::to_value(&table).map_err(|e| -> Box<EvalAltResult> { e.to_string().into() })?;
        json_to_dynamic(&value).try_cast::<Map>().ok_or_else(|| "internal: the table is not a map".into())
    });
}

/// `strider experiment`.
pub fn run(args: ExperimentArgs) -> Outcome {
    let file = args.script.display().to_string();
    let source = crate::files::read_text(&args.script)?;
    let log = ScriptLog::new();
    // Experiments may run many episodes; each native call counts as few operations.
    let mut engine = hardened_engine(Limits::default(), &log);
    // `print` and `debug` are the experiment's log: stderr, line by line as the script runs,
    // so nothing is lost when it fails later; stdout stays free for data.
    let f = file.clone();
    engine.on_print(move |s| {
        for line in s.lines() {
            eprintln!("{f}: {line}");
        }
    });
    let f = file.clone();
    engine.on_debug(move |s, _, pos| match pos.line() {
        Some(l) => eprintln!("{f}:{l}: {s}"),
        None => eprintln!("{f}: {s}"),
    });
    let budget = EpisodeBudget::default();
    register(&mut engine, Path::new("."), &budget);
    register_table1(&mut engine, &budget);
    let failures = register_snapshot(&mut engine, Path::new("."));
    let ast = engine.compile(&source).map_err(|e| {
        let pos = e.position();
        anyhow!("{file}:{}:{}: {}", pos.line().unwrap_or(0), pos.position().unwrap_or(0), e.0)
    })?;
    let result = engine.run_ast(&ast).map_err(|e| script_error(&file, &e));
    // Anything a registered function logged (map and rule scripts' output comes through the
    // loaders), kept whether the script succeeded or not.
    for line in log.lines() {
        eprintln!("{file}: {line}");
    }
    result?;
    let failed = failures.reports();
    if !failed.is_empty() {
        return Err(Failure::Task(anyhow!(
            "{} snapshot(s) did not match their goldens:\n{}",
            failed.len(),
            failed.join("\n")
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_align_and_round() {
        let rows: Array = vec![
            Dynamic::from(vec![Dynamic::from("rules"), Dynamic::from("success"), Dynamic::from("ratio")]),
            Dynamic::from(vec![Dynamic::from("default"), Dynamic::from_float(0.99), Dynamic::from_float(1.234567)]),
            Dynamic::from(vec![Dynamic::from("cautious"), Dynamic::from_float(1.0), Dynamic::UNIT]),
        ];
        assert_eq!(
            table(&rows, 3).unwrap(),
            "rules     success  ratio\ndefault     0.990  1.235\ncautious    1.000      -"
        );
        assert_eq!(table(&rows, 1).unwrap().lines().nth(1), Some("default       1.0    1.2"));
        assert!(table(&rows, 13).is_err());
    }

    #[test]
    fn a_script_looping_over_episodes_is_stopped_by_its_budget() {
        let log = ScriptLog::new();
        let mut engine = hardened_engine(Limits::default(), &log);
        let base = Path::new(env!("CARGO_MANIFEST_DIR"));
        register(&mut engine, base, &EpisodeBudget::new(3));
        let script = "let m = load_map(\"maps/open_field.rhai\");\nlet r = default_rules();\nlet n = 0;\n\
                      loop { run_episode(m, r, 0, n); n += 1; }";
        let err = engine.run(script).unwrap_err();
        let err = script_error("loop.rhai", &err);
        assert_eq!(err.line, 4, "{err}");
        assert!(err.message.contains("budget (0 left, 1 asked)"), "{err}");
        let err = engine.run("run_batch(\"semi\", 1000000000, 1, default_rules())").unwrap_err();
        assert!(script_error("b.rhai", &err).message.contains("budget"), "{err}");
    }
}
