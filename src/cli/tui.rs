//! `strider tui`: the live terminal view of a navigation run (DESIGN.md §6).

use std::path::PathBuf;

use clap::Args;

use crate::load::Outcome;
use crate::tui::{self, Config, MapSpec};

/// `strider tui` options.
#[derive(Debug, Args)]
pub struct TuiArgs {
    /// The world, in any form `strider run` takes (a map file, benchmark data `movingai:NAME`
    /// or `barn:NAME`, `random:KIND`, a folder of worlds: its first); default: the built-in
    /// semi-cluttered scenario.
    pub map: Option<String>,
    /// Navigation rules (a `.rhai` script building the layered network); default: built in.
    #[arg(long)]
    pub rules: Option<PathBuf>,
    /// Seed of the run (random worlds).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Agent body.
    #[command(flatten)]
    pub body: crate::load::BodyArgs,
}

/// `strider tui`.
pub fn run(args: TuiArgs) -> Outcome {
    let map = MapSpec::parse(args.map.as_deref())?;
    let animation = crate::load::load_animation(&args.body)?;
    tui::run(Config { map, rules: args.rules, seed: args.seed, animation })?;
    Ok(())
}

/// `strider` with no command on a terminal: the live view of the built-in default scenario.
pub fn default_scenario() -> Outcome {
    run(TuiArgs { map: None, rules: None, seed: 1, body: crate::load::BodyArgs::default() })
}
