//! `strider snapshot`: pin an episode's behaviour with PNG frames and a text trajectory, and
//! check it against the goldens later (see [`crate::snapshot`]).
//!
//! Exit codes: 0 when every frame matches (or the goldens were written), 1 when a frame
//! differs, 2 for bad input — missing goldens included, with the command that creates them.

use std::path::PathBuf;

use anyhow::anyhow;
use clap::Args;

use super::run::MapArgs;
use crate::load::{Failure, Outcome};
use crate::render::png::parse_size;
use crate::snapshot::{self, Error, Settings, Spec, Tolerance};

/// `strider snapshot` options.
#[derive(Debug, Args)]
pub struct SnapshotArgs {
    /// Map, scenario, rules and seed.
    #[command(flatten)]
    pub map: MapArgs,
    /// Which episode of the matching `strider run` to snapshot (same map, seed and numbering).
    #[arg(long, default_value_t = 0)]
    pub episode: usize,
    /// A frame every N simulation steps (0: only the final frame).
    #[arg(long, default_value_t = 20)]
    pub every: usize,
    /// Frame size, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x800", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Also pin the side views `render --side` draws, where the map has them: `side.png` (the
    /// legs on the ground profile, on terrain) and `upper_side.png` (the upper body among
    /// obstacles it can touch).
    #[arg(long)]
    pub side: bool,
    /// Agent body.
    #[command(flatten)]
    pub body: crate::load::BodyArgs,
    /// Directory of the golden frames and trajectory.
    #[arg(long)]
    pub golden: PathBuf,
    /// Write the goldens instead of comparing (also: STRIDER_UPDATE_GOLDEN=1).
    #[arg(long)]
    pub update: bool,
    /// Largest difference of any colour channel (0–255) for a pixel to count as unchanged.
    #[arg(long, default_value_t = 0)]
    pub tolerance: u8,
}

/// `args` quoted for a POSIX shell where needed.
fn shell_words(args: impl IntoIterator<Item = String>) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_-./:=,+@%".contains(c);
    args.into_iter()
        .map(|a| if !a.is_empty() && a.chars().all(plain) { a } else { format!("'{}'", a.replace('\'', r"'\''")) })
        .collect::<Vec<_>>()
        .join(" ")
}

/// `strider snapshot`.
pub fn run(args: SnapshotArgs) -> Outcome {
    let spec = Spec {
        map: args.map.map.clone(),
        scen: args.map.scen.clone(),
        rules: args.map.rules.clone(),
        seed: args.map.seed,
        episode: args.episode,
        body: args.body.clone(),
        settings: Settings {
            every: args.every,
            size: args.size,
            side: args.side,
            tolerance: Tolerance::channel(args.tolerance),
            update: args.update,
        },
    };
    let report = match snapshot::check(&spec, &args.golden) {
        Ok(r) => r,
        Err(e @ Error::MissingGoldens { .. }) => {
            let command = shell_words(
                std::iter::once("strider".to_string())
                    .chain(std::env::args().skip(1))
                    .chain(std::iter::once("--update".to_string())),
            );
            return Err(anyhow!("{e}\n  to create them: {command}").into());
        }
        Err(e) => return Err(Failure::Input(e.into())),
    };
    crate::files::outln!("{report}")?;
    if report.passed() {
        Ok(())
    } else {
        let n = report.failures().count();
        Err(Failure::Task(anyhow!(
            "{n} frame(s) differ from the goldens in {}; if the change is intended, run again with --update",
            args.golden.display()
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_are_quoted_for_the_shell() {
        let words = ["strider", "snapshot", "maps/a b.rhai", "--golden", "it's"].map(String::from);
        assert_eq!(shell_words(words), r"strider snapshot 'maps/a b.rhai' --golden 'it'\''s'");
    }
}
