//! `strider reproduce table1`: seed 000 §4's Table 1, extended (see [`crate::reproduce`]).

use clap::{Args, Subcommand, ValueEnum};

use crate::files::outln;
use crate::load::{Failure, Outcome};
use crate::reproduce::{self, Report, Table1Options};

/// Experiments of the papers, reproduced.
#[derive(Debug, Subcommand)]
pub enum ReproduceCommand {
    /// Table 1 of the fuzzy + RL paper: the pure-RL planner (trained per environment) against fuzzy + RL
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
