//! `strider reproduce table1`: seed 000 §4's Table 1, extended (see [`crate::reproduce`]).

use std::sync::Arc;

use clap::{Args, Subcommand, ValueEnum};
use rhai::{Array, Dynamic, EvalAltResult, Map};

use super::experiment::{EpisodeBudget, ScenarioHandle, controller, failure_text};
use crate::files::outln;
use crate::load::{Failure, Outcome};
use crate::maps::generate::Density;
use crate::reproduce::{self, Environment, Report, Table1Options};

type Res<T> = Result<T, Box<EvalAltResult>>;

/// Experiments of the papers, reproduced.
#[derive(Debug, Subcommand)]
pub enum ReproduceCommand {
    /// Table 1 of seed 000: the pure-RL planner (trained per environment) against fuzzy + RL
    /// (trained once), in the sparse, semi-cluttered and cluttered environments of Fig 2.
    Table1(Table1Args),
}

/// Output format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// A table.
    Text,
    /// `{"environments": [{"name", "pure_rl": {…}, "fuzzy_rl": {…}}, …]}`.
    Json,
}

/// Options of `reproduce table1`.
#[derive(Debug, Args)]
pub struct Table1Args {
    /// Seed of every random stream (tasks, worlds, exploration).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub format: Format,
    /// Held-out starts and goals per environment.
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u64).range(1..=10_000))]
    pub held_out: u64,
    /// Unseen random worlds per environment.
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u64).range(1..=10_000))]
    pub unseen: u64,
    /// Most pure-RL training episodes per environment.
    #[arg(long, default_value_t = 300_000, value_parser = clap::value_parser!(u64).range(1..=100_000_000))]
    pub max_episodes: u64,
    /// Episodes the fuzzy + RL policy is trained for (once).
    #[arg(long, default_value_t = 1_000_000, value_parser = clap::value_parser!(u64).range(1..=100_000_000))]
    pub fuzzy_episodes: u64,
}

/// Progress on stderr.
struct Stderr;

impl Report for Stderr {
    fn phase(&self, env: &str, what: &str) {
        eprintln!("[{env}] {what}");
    }

    fn round(&self, env: &str, episodes: u64, success: f64) {
        eprintln!("[{env}] pure RL: {episodes} episodes, held-out success {:.1} %", 100.0 * success);
    }
}

/// Runs a `reproduce` subcommand.
pub fn run(command: ReproduceCommand) -> Outcome {
    let ReproduceCommand::Table1(a) = command;
    let db = crate::load::builtin_database()?;
    let controller = super::run::load_controller(None)?;
    let environments = reproduce::fig2_environments().map_err(|e| Failure::Input(anyhow::anyhow!(e)))?;
    let options = Table1Options {
        seed: a.seed,
        held_out: a.held_out as usize,
        unseen: a.unseen as usize,
        max_episodes: a.max_episodes,
        fuzzy_episodes: a.fuzzy_episodes,
        ..Table1Options::default()
    };
    let table = reproduce::run(&db, &controller, &environments, options, &Stderr);
    let written = match a.format {
        Format::Text => outln!("{}", table.to_text().trim_end()),
        Format::Json => outln!("{}", serde_json::to_string_pretty(&table).map_err(anyhow::Error::from)?),
    };
    written.map_err(|e| Failure::Input(e.into()))
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
pub fn register(engine: &mut rhai::Engine, budget: &EpisodeBudget) {
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
        let db = crate::load::builtin_database().map_err(failure_text)?;
        let table = reproduce::run(&db, &c, &environments, options, &Quiet);
        let value = serde_json::to_value(&table).map_err(|e| -> Box<EvalAltResult> { e.to_string().into() })?;
        json_to_dynamic(&value).try_cast::<Map>().ok_or_else(|| "internal: the table is not a map".into())
    });
}
