//! `strider merge`: joins what the shards of a run printed (`strider run --shard I/N`, JSON or
//! CSV) into what the whole run prints, byte for byte: the episodes in order and, for JSON, the
//! summary of them all.
//!
//! Invariant: the outputs must be exactly one whole run: each carries its run's identity
//! ([`RunIdentity`]), all the same run (worlds, rules, body, seed, episode count, shard count,
//! strider version), every shard `0..N` once, each holding exactly its episodes, every CSV row
//! whole. Anything else is an error naming the file, never a quietly smaller or mixed run.
//! Outputs without an identity (a whole run, or shards of a strider that wrote none) are
//! refused.

use std::collections::BTreeMap;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;

use anyhow::anyhow;
use clap::Args;

use crate::diagnostic::SourceError;
use crate::experiment::{self, EpisodeRecord};
use crate::files;
use crate::load::{Failure, Outcome};

use super::run::{CSV_IDENTITY, DataFormat, MAX_EPISODES, RunIdentity, write_records};

/// `strider merge` options.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The outputs of `strider run --shard I/N` for every I of one run, all JSON or all CSV,
    /// any order.
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
            MergedRun::Json(records) => {
                write_records(out, DataFormat::Json, None, &experiment::summarize(records), records)
            }
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
    let shards: Vec<ShardOutput> = parts
        .iter()
        .map(|(file, text)| if json { read_json(file, text) } else { read_csv(file, text) })
        .collect::<Result<_, _>>()?;
    check_whole_run(&shards)?;
    let mut headers = shards.iter().filter_map(|s| Some((s.header.clone()?, &s.file)));
    let header = headers.next();
    if let Some((h, f)) = &header
        && let Some((_, other)) = headers.find(|(o, _)| o != h)
    {
        return Err(SourceError::new(other, 2, 1, format!("the CSV header differs from {f}'s")));
    }
    let header = header.map(|(h, _)| h).unwrap_or_default();
    let mut episodes: Vec<(usize, Episode)> = shards.into_iter().flat_map(|s| s.episodes).collect();
    episodes.sort_by_key(|(i, _)| *i);
    if json {
        return Ok(MergedRun::Json(
            episodes
                .into_iter()
                .filter_map(|(_, e)| if let Episode::Record(r) = e { Some(*r) } else { None })
                .collect(),
        ));
    }
    let failed = episodes.iter().filter(|(_, e)| matches!(e, Episode::Row { failed: true, .. })).count();
    let rows =
        episodes.into_iter().filter_map(|(_, e)| if let Episode::Row { line, .. } = e { Some(line) } else { None });
    Ok(MergedRun::Csv { header, rows: rows.collect(), failed })
}

/// One episode of a shard's output.
enum Episode {
    /// Its JSON record.
    Record(Box<EpisodeRecord>),
    /// Its CSV row, and whether it missed the goal or collided.
    Row {
        /// The line.
        line: String,
        /// Missed the goal or collided.
        failed: bool,
    },
}

/// What one shard's output holds.
struct ShardOutput {
    /// Its file name.
    file: String,
    /// The run it belongs to.
    identity: RunIdentity,
    /// Its CSV header, if it is CSV and has episodes.
    header: Option<String>,
    /// Its episodes, numbered, in the order written.
    episodes: Vec<(usize, Episode)>,
}

/// The error of an output that carries no run identity.
fn no_identity(file: &str) -> SourceError {
    SourceError::new(
        file,
        1,
        1,
        "carries no run identity: not the output of `strider run --shard I/N` (a whole run's output needs no merging)",
    )
}

#[derive(serde::Deserialize)]
struct RunOutput {
    run: Option<RunIdentity>,
    episodes: Vec<EpisodeRecord>,
    #[allow(dead_code)]
    summary: serde::de::IgnoredAny,
}

fn read_json(file: &str, text: &str) -> Result<ShardOutput, SourceError> {
    let output: RunOutput = serde_json::from_str(text).map_err(|e| {
        SourceError::new(file, e.line(), e.column(), format!("not the JSON output of strider run: {e}"))
    })?;
    let identity = output.run.ok_or_else(|| no_identity(file))?;
    let episodes = output.episodes.into_iter().map(|r| (r.episode, Episode::Record(Box::new(r)))).collect();
    Ok(ShardOutput { file: file.to_string(), identity, header: None, episodes })
}

/// The non-empty lines of `text`, numbered from 1.
fn csv_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines().enumerate().map(|(n, l)| (n + 1, l)).filter(|(_, l)| !l.is_empty())
}

fn read_csv(file: &str, text: &str) -> Result<ShardOutput, SourceError> {
    let mut lines = csv_lines(text);
    let identity = match lines.next() {
        Some((n, line)) => match line.strip_prefix(CSV_IDENTITY) {
            Some(id) => serde_json::from_str::<RunIdentity>(id).map_err(|e| {
                SourceError::new(file, n, CSV_IDENTITY.len() + e.column(), format!("not a run identity: {e}"))
            })?,
            None => return Err(no_identity(file)),
        },
        None => return Err(no_identity(file)),
    };
    // strider ends every line; a last line without its end was cut short.
    if !text.ends_with('\n') {
        let n = text.lines().count();
        return Err(SourceError::new(file, n, 1, "the last line has no end: the output was cut short"));
    }
    let mut episodes = Vec::new();
    let Some((_, head)) = lines.next() else {
        return Ok(ShardOutput { file: file.to_string(), identity, header: None, episodes });
    };
    let names: Vec<String> = csv_cells(head);
    let column = |name: &str| {
        names.iter().position(|n| n == name).ok_or_else(|| {
            SourceError::new(file, 2, 1, format!("not the CSV output of strider run: no '{name}' column"))
        })
    };
    let (reached, collisions) = (column("reached")?, column("collisions")?);
    if column("episode")? != 0 {
        return Err(SourceError::new(file, 2, 1, "not the CSV output of strider run: 'episode' is not first"));
    }
    for (n, line) in lines {
        let cells = csv_cells(line);
        if cells.len() != names.len() {
            return Err(SourceError::new(
                file,
                n,
                1,
                format!("the row has {} cells, the header {}: a cut or damaged row", cells.len(), names.len()),
            ));
        }
        let episode = cells[0]
            .parse::<usize>()
            .map_err(|_| SourceError::new(file, n, 1, "expected the episode number as the row's first cell"))?;
        let failed = cells[reached] != "true" || cells[collisions] != "0";
        episodes.push((episode, Episode::Row { line: line.to_string(), failed }));
    }
    Ok(ShardOutput { file: file.to_string(), identity, header: Some(head.to_string()), episodes })
}

/// Checks that `shards` are exactly one whole run: one identity, every shard once, each with
/// exactly its episodes (and one CSV header, checked by the caller's rows being whole).
fn check_whole_run(shards: &[ShardOutput]) -> Result<(), SourceError> {
    let first = &shards[0];
    let bad_shard = |s: &ShardOutput, e: String| SourceError::new(&s.file, 1, 1, e);
    let count = first.identity.shard().map_err(|e| bad_shard(first, e))?.count;
    // Which file holds each shard given (at most one per output, whatever the count says).
    let mut seen: BTreeMap<usize, &str> = BTreeMap::new();
    for s in shards {
        if let Some(why) = first.identity.differs(&s.identity) {
            return Err(bad_shard(s, format!("not a shard of the run in {}: {why}", first.file)));
        }
        if !(1..=MAX_EPISODES).contains(&s.identity.episodes) {
            return Err(bad_shard(
                s,
                format!("a run of {} episodes: strider runs 1 to {MAX_EPISODES}", s.identity.episodes),
            ));
        }
        let shard = s.identity.shard().map_err(|e| bad_shard(s, e))?;
        if let Some(other) = seen.insert(shard.index, &s.file) {
            return Err(bad_shard(s, format!("shard {} is also in {other}: give each shard once", s.identity.shard)));
        }
        let expected = shard.episodes(s.identity.episodes);
        let held: Vec<usize> = s.episodes.iter().map(|(i, _)| *i).collect();
        if held != expected {
            let at = held.iter().zip(&expected).position(|(a, b)| a != b).unwrap_or(held.len().min(expected.len()));
            let what = match (held.get(at), expected.get(at)) {
                (Some(h), Some(e)) => format!("episode {h} where episode {e} belongs"),
                (None, Some(e)) => format!("no episode {e}: the output was cut short"),
                (Some(h), None) => format!("episode {h}, which is not the shard's"),
                (None, None) => "other episodes".to_string(),
            };
            return Err(bad_shard(
                s,
                format!(
                    "shard {} of a run of {} episodes holds {} episodes, not its {}: {what}",
                    s.identity.shard,
                    s.identity.episodes,
                    held.len(),
                    expected.len()
                ),
            ));
        }
    }
    // With fewer shards given than the count, one of the first of them is missing.
    if let Some(missing) = (0..count).find(|i| !seen.contains_key(i)) {
        return Err(SourceError::new(
            &first.file,
            0,
            0,
            format!(
                "shard {missing}/{count} of the run is missing ({} of {count} shards given): merge all the shards of the run",
                seen.len()
            ),
        ));
    }
    Ok(())
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
