//! The one loading layer of the front-ends: `strider run`, `render`, `snapshot`, the live view
//! and experiment scripts all read maps, rules and bodies here. A map argument is parsed once
//! into a [`MapSpec`]; loaders return the value or a [`SourceError`] naming the file (and line
//! and column where there is one), together with what the script printed, so each front-end
//! decides where that output goes (stderr for the command line, the log panel for the live
//! view). The agents' body ([`BodyArgs`]: the disc, or the animated character with a database
//! directory and a policy) is loaded by [`load_animation`]; database directories
//! (`database.json` + `clips/*.bvh`) are read and written by [`load_database`] and
//! [`save_database`]. A [`Failure`] says whether the input was at fault or the task failed.
//!
//! Below the command line and the live view, above the simulation and the script host: files
//! are read through [`crate::files`].

use std::io;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, anyhow};
use clap::{Args, ValueEnum};
use serde::{Deserialize, Serialize};

use crate::anim::bvh::{self, BvhOptions};
use crate::anim::player::{PlayerParams, TransitionKind};
use crate::anim::policy::{LearnParams, Policy, StateGrid, Strategy};
use crate::anim::{Clip, Database, DbParams, IntervalSpec, Skeleton};
use crate::builtin::{DEFAULT_MAP, DEFAULT_MAP_FILE, DEFAULT_RULES, DEFAULT_RULES_FILE};
use crate::diagnostic::SourceError;
use crate::experiment::{Job, world_seed};
use crate::files::{self, write_atomic};
use crate::footstep::PlannerMode;
use crate::fuzzy::Engine;
use crate::maps::kind::{self, WorldKind};
use crate::maps::{barn, movingai, text};
use crate::scenario::Scenario;
use crate::script::{self, Limits, ScriptLog};
use crate::sim::{Animation, AnimationHandle, ControllerParams, LayeredController};

/// A failure of a command, with the exit code it maps to.
#[derive(Debug)]
pub enum Failure {
    /// Usage, file or script error (exit 2).
    Input(anyhow::Error),
    /// The command ran but its task or check failed (exit 1).
    Task(anyhow::Error),
}

impl From<anyhow::Error> for Failure {
    fn from(e: anyhow::Error) -> Self {
        Failure::Input(e)
    }
}

impl From<io::Error> for Failure {
    fn from(e: io::Error) -> Self {
        Failure::Input(e.into())
    }
}

impl From<SourceError> for Failure {
    fn from(e: SourceError) -> Self {
        Failure::Input(e.into())
    }
}

/// Result of a command.
pub type Outcome = Result<(), Failure>;

/// Which world a command runs.
#[derive(Debug, Clone, PartialEq)]
pub enum MapSpec {
    /// The built-in default scenario (Fig 2 b of the fuzzy + RL paper).
    BuiltIn,
    /// A map file: `.rhai`, `.txt`/`.world`, or a MovingAI `.map` with its scenario file
    /// (`scen`, default `FILE.map.scen`).
    File {
        /// The map file.
        path: PathBuf,
        /// The MovingAI scenario file given by hand.
        scen: Option<PathBuf>,
    },
    /// Seeded random worlds of a kind (`random:KIND`), one per episode.
    Random(WorldKind),
}

/// The environment variable naming the folder of benchmark data (`movingai/`, `barn/`), which
/// `movingai:NAME` and `barn:NAME` maps are read from.
pub const DATA_ENV: &str = "STRIDER_DATA";

/// The folder of benchmark data when [`DATA_ENV`] is not set (relative to the current one).
pub const DEFAULT_DATA_DIR: &str = "data";

/// The benchmark sets a map argument names by prefix (`SET:NAME`), each a folder of the data
/// folder, with the extension a name without one gets.
const DATA_SETS: [(&str, &str); 2] = [("movingai", "map"), ("barn", "world")];

/// Where benchmark data named `SET:NAME` (`movingai:random512-20-0`, `barn:world_0`, `barn:`
/// for the whole folder) lives: `NAME` in the folder `SET` of the data folder ([`DATA_ENV`], by
/// default [`DEFAULT_DATA_DIR`]), with the set's extension when `NAME` has none and is no
/// folder. `None` for an argument that names no set.
pub fn data_path(arg: &str) -> Option<PathBuf> {
    let (set, ext) = DATA_SETS.iter().find(|(set, _)| arg.strip_prefix(set).is_some_and(|r| r.starts_with(':')))?;
    let name = &arg[set.len() + 1..];
    let root = std::env::var_os(DATA_ENV)
        .filter(|d| !d.is_empty())
        .map_or_else(|| PathBuf::from(DEFAULT_DATA_DIR), PathBuf::from);
    let path = root.join(set).join(name);
    if name.is_empty() || path.is_dir() || path.extension().is_some() {
        return Some(path);
    }
    Some(path.with_extension(ext))
}

impl MapSpec {
    /// Reads a map argument: `random:KIND`, benchmark data `movingai:NAME` or `barn:NAME`
    /// ([`data_path`]), or a path; `None` is the built-in scenario.
    pub fn parse(arg: Option<&str>) -> Result<MapSpec, SourceError> {
        let Some(a) = arg else { return Ok(MapSpec::BuiltIn) };
        if let Some(k) = a.strip_prefix("random:") {
            return k.parse().map(MapSpec::Random).map_err(|e| SourceError::new(a, 0, 0, format!("{e}")));
        }
        match data_path(a) {
            Some(path) if !path.exists() => Err(SourceError::new(
                &path.display().to_string(),
                0,
                0,
                format!(
                    "no such file or folder: {a} names benchmark data, read from ${DATA_ENV} (./{DEFAULT_DATA_DIR} when \
                     it is not set); the README's \"Benchmark data\" says where to fetch it"
                ),
            )),
            Some(path) => Ok(MapSpec::file(path)),
            None => Ok(MapSpec::file(a)),
        }
    }

    /// A map file with the default scenario file.
    pub fn file(path: impl Into<PathBuf>) -> MapSpec {
        MapSpec::File { path: path.into(), scen: None }
    }

    /// The same map with a MovingAI scenario file given by hand (kept only for map files; a
    /// `movingai:NAME` scenario is benchmark data, [`data_path`]).
    pub fn with_scen(self, scen: Option<PathBuf>) -> MapSpec {
        let scen = scen.map(|s| s.to_str().and_then(data_path).unwrap_or(s));
        match self {
            MapSpec::File { path, .. } => MapSpec::File { path, scen },
            other => other,
        }
    }

    /// The map file, if any (the file to watch for changes).
    pub fn path(&self) -> Option<&Path> {
        match self {
            MapSpec::File { path, .. } => Some(path),
            _ => None,
        }
    }
}

/// Where the scenarios of a run come from.
#[derive(Debug, Clone)]
pub enum MapSource {
    /// One scenario (its tasks are the episodes).
    Scenario(Arc<Scenario>),
    /// Seeded random worlds of a kind, one per episode.
    Random(WorldKind),
    /// The worlds of a folder, their tasks one after another (a BARN folder, say).
    Batch(Vec<Arc<Scenario>>),
}

/// A loaded value or the error naming the file, with what the script printed (each line
/// prefixed with the file name).
#[derive(Debug)]
pub struct Loaded<T> {
    /// The value or the located error.
    pub result: Result<T, SourceError>,
    /// `print`/`debug` output of the script.
    pub log: Vec<String>,
}

impl<T> Loaded<T> {
    fn of(result: Result<T, SourceError>, file: &str, log: &ScriptLog) -> Loaded<T> {
        Loaded { result, log: log.lines().into_iter().map(|l| format!("{file}: {l}")).collect() }
    }

    /// The value, the script's output written to stderr first (the command line's choice).
    pub fn logged(self) -> Result<T, SourceError> {
        for line in &self.log {
            eprintln!("{line}");
        }
        self.result
    }
}

fn read(path: &Path) -> Result<String, SourceError> {
    files::read_text(path)
}

/// Loads the world of `spec`.
pub fn load_map(spec: &MapSpec) -> Loaded<MapSource> {
    let log = ScriptLog::new();
    let (path, scen) = match spec {
        MapSpec::BuiltIn => {
            let s = script::load_scenario(DEFAULT_MAP, DEFAULT_MAP_FILE, Limits::default(), &log);
            return Loaded::of(s.map(|s| MapSource::Scenario(Arc::new(s))), DEFAULT_MAP_FILE, &log);
        }
        MapSpec::Random(k) => return Loaded { result: Ok(MapSource::Random(*k)), log: Vec::new() },
        MapSpec::File { path, scen } => (path, scen),
    };
    let file = path.display().to_string();
    if path.is_dir() {
        // Each world's messages are named by the world's own file.
        let mut lines = Vec::new();
        let result = load_folder(path, &mut lines).map(MapSource::Batch);
        return Loaded { result, log: lines };
    }
    let scenario = load_file(path, scen.as_deref(), &log);
    Loaded::of(scenario.map(|s| MapSource::Scenario(Arc::new(s))), &file, &log)
}

/// One world file of any kind `strider run` reads.
fn load_file(path: &Path, scen: Option<&Path>, log: &ScriptLog) -> Result<Scenario, SourceError> {
    let file = path.display().to_string();
    match path.extension().and_then(|e| e.to_str()) {
        Some("rhai") => read(path).and_then(|src| script::load_scenario(&src, &file, Limits::default(), log)),
        Some("world") => read(path).and_then(|src| {
            if src.trim_start().starts_with('<') { load_barn(path, &src, log) } else { text::parse(&src, &file) }
        }),
        Some("txt") => read(path).and_then(|src| text::parse(&src, &file)),
        Some("map") => load_movingai(path, scen),
        _ => Err(SourceError::new(
            &file,
            0,
            0,
            "expected a .rhai map, a .txt world, a BARN .world, a MovingAI .map, a folder of worlds, or random:KIND",
        )),
    }
}

/// A BARN challenge world (Gazebo SDF) and its reference path `path_N.npy`, looked for beside
/// it and in `path_files/` beside it (the challenge's own layout); without one the world has no
/// BARN score, which the log says.
fn load_barn(path: &Path, text: &str, log: &ScriptLog) -> Result<Scenario, SourceError> {
    let file = path.display().to_string();
    let name = path.file_stem().map_or_else(|| "world".to_string(), |s| s.to_string_lossy().into_owned());
    let dir = path.parent().unwrap_or(Path::new("."));
    let number = name.rsplit('_').next().filter(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
    let found = number.and_then(|n| {
        let want = format!("path_{n}.npy");
        [dir.join(&want), dir.join("path_files").join(&want)].into_iter().find(|p| p.is_file())
    });
    let cells = match &found {
        Some(p) => {
            let bytes = files::read_bytes(p)?;
            Some(barn::parse_path(&bytes, &p.display().to_string())?)
        }
        None => {
            log.push("no path_N.npy beside it or in path_files/: no BARN score".to_string());
            None
        }
    };
    barn::parse_world(text, &file, &name, cells.as_deref())
}

/// Every world of a folder (`.world`, `.txt`, `.rhai`; not MovingAI maps, which need their
/// scenario files), in name order with numbers compared as numbers ([`natural_order`]: `world_2`
/// before `world_10`); each world's script output and warnings go to `log`, named by its file.
fn load_folder(dir: &Path, log: &mut Vec<String>) -> Result<Vec<Arc<Scenario>>, SourceError> {
    let file = dir.display().to_string();
    let entries = std::fs::read_dir(dir).map_err(|e| SourceError::new(&file, 0, 0, format!("cannot read: {e}")))?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && matches!(p.extension().and_then(|e| e.to_str()), Some("world" | "txt" | "rhai")))
        .collect();
    let name = |p: &PathBuf| p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    paths.sort_by(|a, b| natural_order(&name(a), &name(b)));
    if paths.is_empty() {
        return Err(SourceError::new(&file, 0, 0, "a folder of worlds needs .world, .txt or .rhai files; it has none"));
    }
    if paths.len() > MAX_FOLDER_WORLDS {
        return Err(SourceError::new(&file, 0, 0, format!("{} worlds: at most {MAX_FOLDER_WORLDS}", paths.len())));
    }
    paths
        .iter()
        .map(|p| {
            let world_log = ScriptLog::new();
            let loaded = Loaded::of(load_file(p, None, &world_log), &p.display().to_string(), &world_log);
            log.extend(loaded.log);
            loaded.result.map(Arc::new)
        })
        .collect()
}

/// Compares two file names with their runs of digits compared as numbers (`world_9`,
/// `world_0010`, `world_100`; `a2b10` before `a10b2`), the rest character by character; names
/// equal so (`w_7`, `w_07`) fall back to plain order, so that the order is total.
pub fn natural_order(a: &str, b: &str) -> std::cmp::Ordering {
    /// The name in runs: digits (as the number's digits, leading zeros dropped) or one
    /// other character.
    fn runs(s: &str) -> impl Iterator<Item = (bool, &str)> {
        let mut rest = s;
        std::iter::from_fn(move || {
            let first = rest.chars().next()?;
            let len = if first.is_ascii_digit() {
                rest.bytes().position(|c| !c.is_ascii_digit()).unwrap_or(rest.len())
            } else {
                first.len_utf8()
            };
            let (run, tail) = rest.split_at(len);
            rest = tail;
            Some((first.is_ascii_digit(), run))
        })
    }
    /// A number before any other character, shorter numbers first.
    fn key((digits, run): (bool, &str)) -> (bool, usize, &str) {
        let run = if digits { run.trim_start_matches('0') } else { run };
        (!digits, if digits { run.len() } else { 0 }, run)
    }
    runs(a).map(key).cmp(runs(b).map(key)).then_with(|| a.cmp(b))
}

/// Most worlds a folder may hold.
const MAX_FOLDER_WORLDS: usize = 100_000;

fn load_movingai(path: &Path, scen: Option<&Path>) -> Result<Scenario, SourceError> {
    let file = path.display().to_string();
    let scen_path = scen.map_or_else(|| PathBuf::from(format!("{file}.scen")), Path::to_path_buf);
    let scen_file = scen_path.display().to_string();
    if !scen_path.exists() {
        return Err(match scen {
            Some(_) => SourceError::new(&scen_file, 0, 0, "the scenario file given with --scen does not exist"),
            None => SourceError::new(
                &file,
                0,
                0,
                format!("a MovingAI map needs its scenario file ({scen_file} does not exist): give --scen FILE"),
            ),
        });
    }
    movingai::load(&read(path)?, &file, &read(&scen_path)?, &scen_file)
}

/// The scenario the live view shows for `spec`: a random world is the one `strider run` plays
/// as its first episode with the run seed `seed`.
pub fn load_scenario(spec: &MapSpec, seed: u64) -> Loaded<Scenario> {
    let loaded = load_map(spec);
    Loaded { result: loaded.result.map(|s| (*job(&s, 0, seed).scenario).clone()), log: loaded.log }
}

/// Loads the fuzzy engines of a rule script (the built-in rules when `path` is `None`).
pub fn load_engines(path: Option<&Path>) -> Loaded<Vec<Engine>> {
    let log = ScriptLog::new();
    let (source, file) = match path {
        Some(p) => match read(p) {
            Ok(s) => (s, p.display().to_string()),
            Err(e) => return Loaded { result: Err(e), log: Vec::new() },
        },
        None => (DEFAULT_RULES.to_string(), DEFAULT_RULES_FILE.to_string()),
    };
    let result = script::load_engines(&source, &file, Limits::default(), &log);
    Loaded::of(result, &file, &log)
}

/// Loads the navigation rules of a rule script (the built-in rules when `path` is `None`).
pub fn load_rules(path: Option<&Path>) -> Loaded<LayeredController> {
    let file = path.map_or_else(|| DEFAULT_RULES_FILE.to_string(), |p| p.display().to_string());
    let loaded = load_engines(path);
    let result = loaded.result.and_then(|engines| {
        LayeredController::new(&engines, ControllerParams::default()).map_err(|m| SourceError::new(&file, 0, 0, m))
    });
    Loaded { result, log: loaded.log }
}

/// How many episodes a run of `source` has: `episodes`, or one per task (one for random
/// worlds).
pub fn episode_count(source: &MapSource, episodes: Option<usize>) -> usize {
    match source {
        MapSource::Scenario(s) => episodes.unwrap_or(s.tasks.len()),
        MapSource::Random(_) => episodes.unwrap_or(1),
        MapSource::Batch(b) => episodes.unwrap_or(b.iter().map(|s| s.tasks.len()).sum()),
    }
}

/// Episode `i` of a run of `source` seeded with `seed`; a random world is generated here, so
/// a run makes each world when its episode starts, not all of them before the first.
pub fn job(source: &MapSource, i: usize, seed: u64) -> Job {
    let ws = world_seed(seed, i);
    match source {
        MapSource::Scenario(s) => Job { scenario: s.clone(), task: i % s.tasks.len(), seed: ws },
        MapSource::Random(k) => Job { scenario: Arc::new(kind::generate(*k, ws)), task: 0, seed: ws },
        MapSource::Batch(b) => {
            // The batch's tasks in order, round again past the last.
            let total: usize = b.iter().map(|s| s.tasks.len()).sum::<usize>().max(1);
            let mut k = i % total;
            let mut at = 0;
            while at + 1 < b.len() && k >= b[at].tasks.len() {
                k -= b[at].tasks.len();
                at += 1;
            }
            Job { scenario: b[at].clone(), task: k, seed: ws }
        }
    }
}

/// Body of the agents of `run`, `render` and `tui`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum BodyKind {
    /// The animated character, driven by the database and its trained policy.
    #[default]
    Animated,
    /// The kinematic disc.
    Disc,
}

/// Transition kinds on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum TransitionArg {
    /// Cross-fade.
    #[default]
    Crossfade,
    /// Inertialization.
    Inertialize,
}

/// Options choosing the agents' body.
#[derive(Debug, Clone, Args, Default)]
pub struct BodyArgs {
    /// Agent body.
    #[arg(long, value_enum, default_value_t = BodyKind::Animated)]
    pub body: BodyKind,
    /// Animation database directory (default: built-in).
    #[arg(long)]
    pub db: Option<PathBuf>,
    /// Trained policy file (default: the shipped one for the built-in database), or a baseline
    /// that picks the next interval without it: `greedy` (best one-step reward), `random`,
    /// `successor` (the clip's own next interval).
    #[arg(long)]
    pub policy: Option<PathBuf>,
    /// How intervals hand over.
    #[arg(long, value_enum, default_value_t = TransitionArg::Crossfade)]
    pub transition: TransitionArg,
    /// The footstep planner on uneven terrain: `on` adapts every step to the ground, `off`
    /// takes the database's nominal step, stopping before an invalid one (the digital-actor paper's Fig 8).
    #[arg(long, value_enum, default_value_t = Switch::On)]
    pub planner: Switch,
}

/// On or off.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum Switch {
    /// On.
    #[default]
    On,
    /// Off.
    Off,
}

/// The baseline a `--policy` argument names, if it names one.
pub fn baseline(policy: Option<&Path>) -> Option<Strategy> {
    let name = policy?.to_str()?;
    Strategy::ALL.into_iter().find(|s| *s != Strategy::Learnt && s.name() == name)
}

/// The manifest of a database directory.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Manifest {
    /// Always `strider-animation-db`.
    pub format: String,
    /// Format version (1).
    pub version: u32,
    /// Neighbours per interval.
    pub k: usize,
    /// Normalized time samples per interval minus one.
    pub samples: usize,
    /// Clip files, relative to the directory, in database order.
    pub clips: Vec<String>,
    /// Intervals: clip name, first frame, last frame.
    pub intervals: Vec<(String, usize, usize)>,
    /// The foot joints (left, right) when given by hand; empty when found from the skeleton.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub feet: Vec<String>,
}

const MANIFEST: &str = "database.json";
const FORMAT: &str = "strider-animation-db";

/// The built-in database ([`crate::builtin::database`]), its errors as a [`Failure`].
pub fn builtin_database() -> Result<Database, Failure> {
    crate::builtin::database().map_err(|e| anyhow!("built-in animation database: {e}").into())
}

fn read_bvh(path: &Path, scale: f64) -> Result<(Skeleton, Clip), Failure> {
    parse_bvh(path, &files::read_text(path)?, scale)
}

/// Reads one BVH clip (named after its file) at `scale` metres per file unit; warnings go to
/// stderr.
pub fn parse_bvh(path: &Path, text: &str, scale: f64) -> Result<(Skeleton, Clip), Failure> {
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "clip".into());
    let b = bvh::parse(text, &path.display().to_string(), &name, &BvhOptions { scale })?;
    for w in &b.warnings {
        eprintln!("{}: warning: {w}", path.display());
    }
    Ok((b.skeleton, b.clip))
}

/// Whether two skeletons have the same joints, parents and offsets (to 1 µm).
pub fn same_skeleton(a: &Skeleton, b: &Skeleton) -> bool {
    a.len() == b.len()
        && a.joints()
            .iter()
            .zip(b.joints())
            .all(|(x, y)| x.name == y.name && x.parent == y.parent && (x.offset - y.offset).length() < 1e-6)
}

/// Loads a database directory.
pub fn load_database(dir: &Path) -> Result<Database, Failure> {
    let path = dir.join(MANIFEST);
    let text = files::read_text(&path)?;
    let m: Manifest = serde_json::from_str(&text)
        .map_err(|e| SourceError::new(&path.display().to_string(), e.line(), e.column(), e.to_string()))?;
    if m.format != FORMAT || m.version != 1 {
        return Err(anyhow!("{}: not a version 1 {FORMAT} manifest", path.display()).into());
    }
    let mut skeleton: Option<Skeleton> = None;
    let mut clips = Vec::new();
    for file in &m.clips {
        let (s, c) = read_bvh(&dir.join(file), 1.0)?;
        match &skeleton {
            Some(k) if !same_skeleton(k, &s) => {
                return Err(anyhow!("{file}: its skeleton differs from the first clip's").into());
            }
            Some(_) => {}
            None => skeleton = Some(s),
        }
        clips.push(c);
    }
    let skeleton = skeleton.ok_or_else(|| anyhow!("{}: no clips", path.display()))?;
    let specs: Vec<IntervalSpec> =
        m.intervals.iter().map(|(c, s, e)| IntervalSpec { clip: c.clone(), start: *s, end: *e }).collect();
    let mut params = DbParams { k: m.k, samples: m.samples, ..DbParams::default() };
    params.contacts.feet = m.feet.clone();
    Database::build(clips, skeleton, params, Some(&specs)).map_err(|e| anyhow!("{}: {e}", path.display()).into())
}

/// Writes `db` as the database directory `dir`, as a whole ([`files::replace_dir`]): a new
/// directory, then put in place of the old one. What is at `dir` must be nothing, an empty
/// folder or a strider database holding nothing but what its manifest names; anything else is
/// refused, naming what strider did not write. `feet` as for [`save_database_with_feet`].
pub fn write_database(db: &Database, dir: &Path, feet: &[String]) -> Result<(), Failure> {
    let mut ours = database_files(dir);
    if !ours.is_empty() {
        ours.push(PathBuf::from("clips"));
    }
    let owned = |rel: &Path| ours.iter().any(|o| o == rel);
    files::replace_dir(dir, &owned, files::Others::Refuse, |tmp| save_database_with_feet(db, tmp, feet))
}

/// The files of the database directory `dir`, relative to it: its manifest and the clip files
/// the manifest names, in its order; none when `dir` holds no strider database manifest.
pub fn database_files(dir: &Path) -> Vec<PathBuf> {
    let Ok(text) = files::read_text(&dir.join(MANIFEST)) else { return Vec::new() };
    match serde_json::from_str::<Manifest>(&text) {
        Ok(m) if m.format == FORMAT => {
            std::iter::once(PathBuf::from(MANIFEST)).chain(m.clips.iter().map(PathBuf::from)).collect()
        }
        _ => Vec::new(),
    }
}

/// Writes `db` as a database directory.
pub fn save_database(db: &Database, dir: &Path) -> Result<(), Failure> {
    save_database_with_feet(db, dir, &[])
}

/// Writes `db` as a database directory whose manifest names the foot joints `feet` (when they
/// were given by hand, so reloading finds the same ones).
pub fn save_database_with_feet(db: &Database, dir: &Path, feet: &[String]) -> Result<(), Failure> {
    let clips_dir = dir.join("clips");
    std::fs::create_dir_all(&clips_dir).with_context(|| format!("cannot create {}", clips_dir.display()))?;
    let mut files = Vec::new();
    for c in &db.clips {
        let file = format!("clips/{}.bvh", c.name);
        let text = bvh::write(&db.skeleton, c, &BvhOptions::default());
        let path = dir.join(&file);
        write_atomic(&path, text.as_bytes()).with_context(|| format!("cannot write {}", path.display()))?;
        files.push(file);
    }
    let m = Manifest {
        format: FORMAT.into(),
        version: 1,
        k: db.params.k,
        samples: db.params.samples,
        clips: files,
        intervals: db.intervals.iter().map(|i| (db.clips[i.clip].name.clone(), i.start, i.end)).collect(),
        feet: feet.to_vec(),
    };
    let json = serde_json::to_string_pretty(&m).map_err(|e| anyhow!("{e}"))?;
    let path = dir.join(MANIFEST);
    write_atomic(&path, json.as_bytes()).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

/// The animation the agents of `run`, `render` and `tui` use, or `None` for discs.
pub fn load_animation(b: &BodyArgs) -> Result<Option<AnimationHandle>, Failure> {
    if b.body == BodyKind::Disc {
        return Ok(None);
    }
    let db = match &b.db {
        Some(d) => load_database(d)?,
        None => builtin_database()?,
    };
    let strategy = baseline(b.policy.as_deref()).unwrap_or(Strategy::Learnt);
    let policy = match (&b.policy, &b.db) {
        // A baseline needs no trained values: an untrained table gives it α, β and γ.
        (Some(_), _) if strategy != Strategy::Learnt => {
            Policy::new(&db, StateGrid::default(), LearnParams::default(), 0)
        }
        (Some(p), _) => {
            let bytes = files::read_bytes(p)?;
            Policy::from_bytes(&bytes, &db).map_err(|e| anyhow!("{}: {e}", p.display()))?
        }
        (None, None) => {
            crate::builtin::policy(&db).map_err(|e| anyhow!("{}: {e}", crate::builtin::DEFAULT_POLICY_FILE))?
        }
        (None, Some(d)) => {
            return Err(anyhow!(
                "{}: give its policy with --policy FILE (train one with `strider train --db {} --out FILE`)",
                d.display(),
                d.display()
            )
            .into());
        }
    };
    let transition = match b.transition {
        TransitionArg::Crossfade => TransitionKind::CrossFade,
        TransitionArg::Inertialize => TransitionKind::Inertialize,
    };
    Ok(Some(AnimationHandle(Arc::new(
        Animation::new(db, policy)
            .with_player(PlayerParams { transition, ..PlayerParams::default() })
            .with_strategy(strategy)
            .with_footsteps(match b.planner {
                Switch::On => PlannerMode::Window,
                Switch::Off => PlannerMode::Nominal,
            }),
    ))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_arguments_parse_once_into_a_spec() {
        assert_eq!(MapSpec::parse(None).unwrap(), MapSpec::BuiltIn);
        assert_eq!(MapSpec::parse(Some("random:maze")).unwrap(), MapSpec::Random(WorldKind::Maze));
        assert_eq!(
            MapSpec::parse(Some("a.map")).unwrap().with_scen(Some("b.scen".into())),
            MapSpec::File { path: "a.map".into(), scen: Some("b.scen".into()) }
        );
        let e = MapSpec::parse(Some("random:castle")).unwrap_err();
        assert_eq!(e.file, "random:castle");
    }

    #[test]
    fn folders_run_in_name_order_with_numbers_as_numbers() {
        let mut names = vec!["world_100", "world_0010", "world_9", "a10b2", "a2b10", "w_07", "w_7", "b", "a", "world_"];
        names.sort_by(|a, b| natural_order(a, b));
        assert_eq!(names, ["a", "a2b10", "a10b2", "b", "w_07", "w_7", "world_", "world_9", "world_0010", "world_100"]);
    }

    #[test]
    fn errors_name_the_file_and_script_output_is_returned() {
        let dir = std::env::temp_dir().join(format!("strider-load-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let map = dir.join("m.rhai");
        std::fs::write(
            &map,
            "print(\"hello\");\nlet m = world(\"w\");\nm.start(0.0, 0.0, 0.0);\nm.goal(5.0, 0.0, 0.5);\nm",
        )
        .unwrap();
        let loaded = load_map(&MapSpec::file(&map));
        assert!(loaded.result.is_ok());
        assert_eq!(loaded.log, vec![format!("{}: hello", map.display())]);
        let bad = dir.join("bad.rhai");
        std::fs::write(&bad, "let m = world(\"w\");\nm.box(1.0, 1.0);\nm").unwrap();
        let e = load_map(&MapSpec::file(&bad)).result.unwrap_err();
        assert_eq!((e.file.as_str(), e.line), (bad.to_str().unwrap(), 2), "{e}");
        let e = load_map(&MapSpec::file(dir.join("x.map"))).result.unwrap_err();
        assert!(e.to_string().contains("x.map.scen"), "{e}");
        let e = load_map(&MapSpec::file(dir.join("x.map")).with_scen(Some(dir.join("y.scen")))).result.unwrap_err();
        assert!(e.file.ends_with("y.scen"), "{e}");
        let e = load_rules(Some(&map)).result.unwrap_err();
        assert!(e.to_string().contains("is this a map given as rules?"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
