//! Where the live view's world and rules come from, and hot reload (DESIGN.md §6): maps and
//! rule scripts are loaded with their script output captured for the log panel (never
//! printed: stdout and stderr belong to the terminal UI), and files are watched by polling
//! their modification time.
//!
//! Invariant: a failed load returns the error and changes nothing, so a broken edit leaves
//! the last good version running.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use crate::builtin::{DEFAULT_MAP, DEFAULT_MAP_FILE, DEFAULT_RULES, DEFAULT_RULES_FILE};
use crate::experiment::world_seed;
use crate::maps::kind::{self, WorldKind};
use crate::maps::{movingai, text};
use crate::scenario::Scenario;
use crate::script::{Limits, ScriptLog, fuzzy_api, map_api};
use crate::sim::{ControllerParams, LayeredController};

/// Which world the view shows.
#[derive(Debug, Clone, PartialEq)]
pub enum MapSpec {
    /// The built-in default scenario (seed 000 Fig 2 b).
    BuiltIn,
    /// A map file (`.rhai`, `.txt`, or MovingAI `.map` with `FILE.map.scen`).
    File(PathBuf),
    /// A seeded random world of a kind (`random:KIND`).
    Random(WorldKind),
}

impl MapSpec {
    /// Reads a map argument: `random:KIND` or a path; `None` is the built-in scenario.
    pub fn parse(arg: Option<&str>) -> Result<MapSpec, String> {
        match arg {
            None => Ok(MapSpec::BuiltIn),
            Some(a) => match a.strip_prefix("random:") {
                Some(d) => d.parse().map(MapSpec::Random).map_err(|e| format!("{e}")),
                None => Ok(MapSpec::File(PathBuf::from(a))),
            },
        }
    }

    /// The file to watch for changes, if any.
    pub fn path(&self) -> Option<&Path> {
        match self {
            MapSpec::File(p) => Some(p),
            _ => None,
        }
    }
}

/// Output of a load: the value or the error text (with `file:line:col`), plus the lines
/// the script printed.
#[derive(Debug)]
pub struct Loaded<T> {
    /// The loaded value or the error message.
    pub result: Result<T, String>,
    /// `print`/`debug` output of the script, prefixed with the file name.
    pub log: Vec<String>,
}

fn read(path: &Path) -> Result<String, String> {
    crate::cli::files::read_text(path).map_err(|e| e.to_string())
}

/// Loads the scenario of `spec`; random worlds use the run seed `seed` the way `strider run`
/// does for its first episode.
pub fn load_scenario(spec: &MapSpec, seed: u64) -> Loaded<Scenario> {
    let log = ScriptLog::new();
    let (result, file) = match spec {
        MapSpec::BuiltIn => (
            map_api::load_scenario(DEFAULT_MAP, DEFAULT_MAP_FILE, Limits::default(), &log).map_err(|e| e.to_string()),
            DEFAULT_MAP_FILE.to_string(),
        ),
        MapSpec::Random(k) => (Ok(kind::generate(*k, world_seed(seed, 0))), String::new()),
        MapSpec::File(path) => {
            let file = path.display().to_string();
            let result = read(path).and_then(|src| match path.extension().and_then(|e| e.to_str()) {
                Some("rhai") => map_api::load_scenario(&src, &file, Limits::default(), &log).map_err(|e| e.to_string()),
                Some("txt") | Some("world") => text::parse(&src, &file).map_err(|e| e.to_string()),
                Some("map") => {
                    let scen = PathBuf::from(format!("{file}.scen"));
                    let scen_src = read(&scen)?;
                    movingai::load(&src, &file, &scen_src, &scen.display().to_string()).map_err(|e| e.to_string())
                }
                _ => Err(format!("{file}: expected a .rhai map, a .txt world, a MovingAI .map, or random:KIND")),
            });
            (result, file)
        }
    };
    Loaded { result, log: log.lines().into_iter().map(|l| format!("{file}: {l}")).collect() }
}

/// Loads the navigation rules from `path` (the built-in rules when `None`).
pub fn load_rules(path: Option<&Path>) -> Loaded<LayeredController> {
    let (source, file) = match path {
        Some(p) => match read(p) {
            Ok(s) => (s, p.display().to_string()),
            Err(e) => return Loaded { result: Err(e), log: Vec::new() },
        },
        None => (DEFAULT_RULES.to_string(), DEFAULT_RULES_FILE.to_string()),
    };
    let log = ScriptLog::new();
    let result = fuzzy_api::load_engines(&source, &file, Limits::default(), &log).map_err(|e| e.to_string()).and_then(
        |engines| LayeredController::new(&engines, ControllerParams::default()).map_err(|m| format!("{file}: {m}")),
    );
    Loaded { result, log: log.lines().into_iter().map(|l| format!("{file}: {l}")).collect() }
}

/// Watches one file by its modification time.
#[derive(Debug, Clone)]
pub struct Watched {
    path: PathBuf,
    stamp: Option<SystemTime>,
}

impl Watched {
    /// Starts watching `path` from its current state.
    pub fn new(path: &Path) -> Watched {
        Watched { path: path.to_path_buf(), stamp: mtime(path) }
    }

    /// The watched path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// True (once) when the file's modification time changed since the last call.
    pub fn changed(&mut self) -> bool {
        let now = mtime(&self.path);
        if now != self.stamp && now.is_some() {
            self.stamp = now;
            true
        } else {
            false
        }
    }
}

fn mtime(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}
