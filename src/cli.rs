//! The `strider` command line: flags are parsed and validated here, then handed to the
//! subcommand modules. Data goes to stdout, diagnostics to stderr; exit code 0 means success,
//! 1 a failed task or check, 2 a usage, file or script error. A closed stdout pipe is not an
//! error.

pub mod anim;
pub mod db_strip;
pub mod experiment;
pub mod fuzzy;
pub mod merge;
pub mod render;
pub mod reproduce;
pub mod run;
pub mod snapshot;
pub mod steps;
pub mod tui;

use std::io::{self, IsTerminal, Write};
use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

use crate::load::Failure;

/// strider: fuzzy navigation and character locomotion planning, in a terminal.
#[derive(Debug, Parser)]
#[command(name = "strider", version, about, long_about = None)]
pub struct Cli {
    /// What to do; without a command, strider runs its built-in default scenario.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// Top-level commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Fuzzy engines: evaluate, export, plot, benchmark.
    Fuzzy {
        /// The fuzzy subcommand.
        #[command(subcommand)]
        command: fuzzy::FuzzyCommand,
    },
    /// Run navigation episodes headless and print their measurements.
    Run(run::RunArgs),
    /// Join the outputs of `run --shard I/N` (JSON or CSV) into what the whole run prints.
    Merge(merge::MergeArgs),
    /// Print a seeded random world in the plain text world format.
    Gen(run::GenArgs),
    /// Write top-down PNG frames of an episode.
    Render(render::RenderArgs),
    /// Compare an episode's frames and trajectory with golden snapshots (or write them).
    Snapshot(snapshot::SnapshotArgs),
    /// Run an experiment script (maps, rule sets, episodes, metrics).
    ///
    /// An experiment is a Rhai script that can also call:
    ///   load_map(path)                                 a map file, as for `run` (not a folder or random:KIND)
    ///   random_world(kind, seed)                       a seeded world: sparse, semi, cluttered, rooms, maze, grid
    ///   default_rules(), load_rules(path)              navigation rules: an array of fuzzy engines, edited with
    ///                                                  e.variable(name).set_term(…), e.block(name).rule(…), …
    ///   run_episode(map, rules, task, seed)            one episode: a map of the figures `run` prints for it
    ///   run_batch(kind_or_map, episodes, seed, rules)  a batch's summary: success_rate, median_path_ratio, …
    ///   snapshot(map, rules, seed, dir[, options])     as `strider snapshot`; passed, frames, report, …
    ///   reproduce_table1(environments, options, rules) as `strider reproduce table1`
    ///   table(rows[, decimals])                        rows of cells as aligned columns, numbers rounded
    /// `print` and `debug` write to stderr as the script runs, each line after the script's name.
    /// Examples: scripts/compare_rules.rhai, scripts/reproduce_table1.rhai.
    #[command(verbatim_doc_comment)]
    Experiment(experiment::ExperimentArgs),
    /// Watch, step and drive a navigation run live in the terminal.
    Tui(tui::TuiArgs),
    /// Animation databases: build from BVH, describe, export the built-in clips.
    Db {
        /// The database subcommand.
        #[command(subcommand)]
        command: anim::DbCommand,
    },
    /// Train the RL animation controller's policy (SARSA) on a database.
    Train(anim::TrainArgs),
    /// Reproduce the fuzzy + RL paper's experiment (its Table 1).
    Reproduce {
        /// The experiment.
        #[command(subcommand)]
        command: reproduce::ReproduceCommand,
    },
    /// Plan and walk the footsteps over a 1-D ground profile (`*.profile`).
    Steps(steps::StepsArgs),
}

/// Runs the command line and returns the process exit code.
pub fn main() -> ExitCode {
    let cli = Cli::command().mut_subcommand("tui", |c| c.after_help(tui_keys())).get_matches();
    let cli = Cli::from_arg_matches(&cli).unwrap_or_else(|e| e.exit());
    let result = match cli.command {
        None if io::stdout().is_terminal() && io::stdin().is_terminal() => tui::default_scenario(),
        None => run::default_scenario(),
        Some(Command::Fuzzy { command }) => fuzzy::run(command),
        Some(Command::Run(args)) => run::run(args),
        Some(Command::Merge(args)) => merge::run(args),
        Some(Command::Gen(args)) => run::gen_world(args),
        Some(Command::Render(args)) => render::render(args),
        Some(Command::Snapshot(args)) => snapshot::run(args),
        Some(Command::Experiment(args)) => experiment::run(args),
        Some(Command::Tui(args)) => tui::run(args),
        Some(Command::Db { command }) => anim::db(command),
        Some(Command::Train(args)) => anim::train(args),
        Some(Command::Reproduce { command }) => reproduce::run(command),
        Some(Command::Steps(args)) => steps::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Input(e)) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(Failure::Input(e)) => {
            let _ = writeln!(io::stderr(), "error: {e:#}");
            ExitCode::from(2)
        }
        Err(Failure::Task(e)) => {
            let _ = writeln!(io::stderr(), "failed: {e:#}");
            ExitCode::from(1)
        }
    }
}

/// The live view's keys, for `strider tui --help` (the list its `?` overlay shows).
fn tui_keys() -> String {
    let width = crate::tui::ui::HELP.iter().map(|(k, _)| k.chars().count()).max().unwrap_or(0);
    let keys: Vec<String> =
        crate::tui::ui::HELP.iter().map(|(k, what)| format!("  {k:<width$}  {what}").trim_end().to_string()).collect();
    format!("Keys (also shown by `?` in the view):\n{}", keys.join("\n"))
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| c.downcast_ref::<io::Error>().is_some_and(|io| io.kind() == io::ErrorKind::BrokenPipe))
}
