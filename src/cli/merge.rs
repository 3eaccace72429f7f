//! `strider merge`: joins what the shards of a run printed (`strider run --shard I/N`, JSON or
//! CSV) into what the whole run prints, byte for byte: the episodes in order and, for JSON, the
//! summary of them all.
//!
//! Invariant: the shards together must hold every episode of the run once, `0..n`; a missing
//! or repeated episode is an error naming it, never a quietly smaller run.

use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use anyhow::anyhow;
use clap::Args;

use crate::diagnostic::SourceError;
use crate::experiment::{self, EpisodeRecord};
use crate::files;
use crate::load::{Failure, Outcome};

use super::run::{DataFormat, write_records};

/// `strider merge` options.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The outputs of `strider run --shard I/N` for every I, all JSON or all CSV, any order.
    #[arg(required = true, num_args = 1..)]
    pub files: Vec<PathBuf>,
}

/// A whole run joined from its shards.
#[derive(Debug, Clone, PartialEq)]
pub enum MergedRun {
    /// The episodes of JSON outputs, in episode order.
    Json(Vec<EpisodeRecord>),
    /// The CSV header and the rows of CSV outputs, in episode order, and how many of them
    /// missed the goal or collided.
    Csv {
        /// The header line.
        header: String,
        /// The rows.
        rows: Vec<String>,
        /// Rows of failed episodes.
        failed: usize,
    },
}

impl MergedRun {
    /// What the whole run prints.
    pub fn write(&self, out: &mut impl Write) -> io::Result<()> {
        match self {
            MergedRun::Json(records) => write_records(out, DataFormat::Json, &experiment::summarize(records), records),
            MergedRun::Csv { header, rows, .. } => {
                if rows.is_empty() {
                    return Ok(());
                }
                writeln!(out, "{header}")?;
                rows.iter().try_for_each(|r| writeln!(out, "{r}"))
            }
        }
    }

    /// Episodes of the run.
    pub fn len(&self) -> usize {
        match self {
            MergedRun::Json(records) => records.len(),
            MergedRun::Csv { rows, .. } => rows.len(),
        }
    }

    /// True when the run has no episodes.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Episodes that missed the goal or collided (`strider run` exits 1 when there are any).
    pub fn failed(&self) -> usize {
        match self {
            MergedRun::Json(records) => records.iter().filter(|r| !r.reached || r.collisions > 0).count(),
            MergedRun::Csv { failed, .. } => *failed,
        }
    }
}

/// Joins the outputs `parts` (file name, text) of a run's shards. JSON outputs start with `{`;
/// anything else is CSV. Errors name the file, line and column.
pub fn merge(parts: &[(String, String)]) -> Result<MergedRun, SourceError> {
    let is_json = |text: &str| text.trim_start().starts_with('{');
    let Some((first, _)) = parts.first() else {
        return Err(SourceError::new("strider merge", 0, 0, "no outputs to merge"));
    };
    let json = is_json(&parts[0].1);
    if let Some((file, _)) = parts.iter().find(|(_, t)| is_json(t) != json) {
        let (a, b) = if json { ("JSON", "CSV") } else { ("CSV", "JSON") };
        return Err(SourceError::new(
            file,
            1,
            1,
            format!("{first} is {a} but this is {b}: merge outputs of one format"),
        ));
    }
    if json { merge_json(parts).map(MergedRun::Json) } else { merge_csv(parts) }
}

#[derive(serde::Deserialize)]
struct RunOutput {
    episodes: Vec<EpisodeRecord>,
    #[allow(dead_code)]
    summary: serde::de::IgnoredAny,
}

fn merge_json(parts: &[(String, String)]) -> Result<Vec<EpisodeRecord>, SourceError> {
    let mut numbered = Vec::new();
    for (file, text) in parts {
        let output: RunOutput = serde_json::from_str(text).map_err(|e| {
            SourceError::new(file, e.line(), e.column(), format!("not the JSON output of strider run: {e}"))
        })?;
        numbered.extend(output.episodes.into_iter().map(|r| (r.episode, file.as_str(), r)));
    }
    let order = check_episodes(numbered.iter().map(|(i, f, _)| (*i, *f)).collect())?;
    let mut slots: Vec<Option<EpisodeRecord>> = numbered.into_iter().map(|(_, _, r)| Some(r)).collect();
    Ok(order.into_iter().filter_map(|k| slots[k].take()).collect())
}

fn merge_csv(parts: &[(String, String)]) -> Result<MergedRun, SourceError> {
    let mut header: Option<(String, &str)> = None;
    let mut numbered: Vec<(usize, &str, &str, bool)> = Vec::new();
    for (file, text) in parts {
        let mut lines = text.lines().enumerate().filter(|(_, l)| !l.is_empty());
        let Some((_, head)) = lines.next() else { continue };
        match &header {
            Some((h, f)) if h != head => {
                return Err(SourceError::new(file, 1, 1, format!("the CSV header differs from {f}'s")));
            }
            Some(_) => {}
            None => header = Some((head.to_string(), file)),
        }
        let names: Vec<&str> = head.split(',').collect();
        let column = |name: &str| {
            names.iter().position(|n| *n == name).ok_or_else(|| {
                SourceError::new(file, 1, 1, format!("not the CSV output of strider run: no '{name}' column"))
            })
        };
        let (reached, collisions) = (column("reached")?, column("collisions")?);
        if column("episode")? != 0 {
            return Err(SourceError::new(file, 1, 1, "not the CSV output of strider run: 'episode' is not first"));
        }
        for (n, line) in lines {
            let cells = csv_cells(line);
            let episode = cells.first().and_then(|c| c.parse::<usize>().ok()).ok_or_else(|| {
                SourceError::new(file, n + 1, 1, "expected the episode number as the row's first cell")
            })?;
            let cell = |k: usize| cells.get(k).map(String::as_str).unwrap_or("");
            let failed = cell(reached) != "true" || cell(collisions) != "0";
            numbered.push((episode, file.as_str(), line, failed));
        }
    }
    let order = check_episodes(numbered.iter().map(|(i, f, _, _)| (*i, *f)).collect())?;
    let rows: Vec<String> = order.iter().map(|&k| numbered[k].2.to_string()).collect();
    let failed = numbered.iter().filter(|r| r.3).count();
    Ok(MergedRun::Csv { header: header.map(|(h, _)| h).unwrap_or_default(), rows, failed })
}

/// The cells of a CSV line as `strider run` writes it (a cell with a comma or quote is quoted,
/// its quotes doubled).
fn csv_cells(line: &str) -> Vec<String> {
    let mut cells = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        let cell = cells.last_mut().expect("one cell at least");
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                chars.next();
                cell.push('"');
            }
            '"' => quoted = !quoted,
            ',' if !quoted => cells.push(String::new()),
            _ => cell.push(c),
        }
    }
    cells
}

/// The positions of `numbered` (episode, file) in episode order, checking that the episodes
/// are exactly `0..n`, each once.
fn check_episodes(numbered: Vec<(usize, &str)>) -> Result<Vec<usize>, SourceError> {
    let n = numbered.len();
    let mut at: Vec<Option<usize>> = vec![None; n];
    for (k, &(episode, file)) in numbered.iter().enumerate() {
        let Some(slot) = at.get_mut(episode) else {
            return Err(SourceError::new(
                file,
                0,
                0,
                format!("episode {episode} is beyond the {n} episodes the outputs hold: is a shard missing?"),
            ));
        };
        if let Some(other) = *slot {
            return Err(SourceError::new(
                file,
                0,
                0,
                format!("episode {episode} is also in {}: give each shard once", numbered[other].1),
            ));
        }
        *slot = Some(k);
    }
    // n records, each in 0..n, none twice: every slot is filled.
    Ok(at.into_iter().flatten().collect())
}

/// `strider merge`.
pub fn run(args: MergeArgs) -> Outcome {
    let mut parts = Vec::new();
    for path in &args.files {
        parts.push((path.display().to_string(), files::read_text(path)?));
    }
    let merged = merge(&parts)?;
    let mut out = BufWriter::new(io::stdout().lock());
    merged.write(&mut out)?;
    out.flush()?;
    match merged.failed() {
        0 => Ok(()),
        failed => Err(Failure::Task(anyhow!("{failed} of {} episodes did not reach the goal cleanly", merged.len()))),
    }
}
