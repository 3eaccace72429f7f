//! `strider run`, `strider gen` and the loading of maps and rule scripts shared by the
//! navigation commands (seed 000 §3.1 navigation, §4 measurements).

use std::io::{self, BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::anyhow;
use clap::{Args, ValueEnum};

use super::files;
use super::{Failure, Outcome};
use crate::experiment::{self, EpisodeRecord, Job};
use crate::maps::kind::{self, WorldKind};
use crate::maps::{movingai, text};
use crate::scenario::Scenario;
use crate::script::{Limits, ScriptLog, fuzzy_api, map_api};
use crate::sim::{ControllerParams, LayeredController, StepParameters};

pub use crate::builtin::{DEFAULT_MAP, DEFAULT_MAP_FILE, DEFAULT_RULES, DEFAULT_RULES_FILE};

/// Where the scenarios of a run come from.
#[derive(Debug, Clone)]
pub enum MapSource {
    /// One scenario (its tasks are the episodes).
    Scenario(Arc<Scenario>),
    /// Seeded random worlds of a kind, one per episode.
    Random(WorldKind),
}

/// Options shared by `run` and `render`.
#[derive(Debug, Args)]
pub struct MapArgs {
    /// A `.rhai` map, a plain text world (`.txt`), a MovingAI `.map`, or `random:KIND`
    /// (sparse, semi, cluttered, rooms, maze, grid) for seeded random worlds.
    pub map: String,
    /// MovingAI scenario file (each line one episode); default: MAP.scen if it exists.
    #[arg(long)]
    pub scen: Option<PathBuf>,
    /// Navigation rules (a `.rhai` script building the layered network); default: built in.
    #[arg(long)]
    pub rules: Option<PathBuf>,
    /// Seed of the run (random worlds and episode seeds).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// `strider run` options.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Map, scenario, rules and seed.
    #[command(flatten)]
    pub map: MapArgs,
    /// Number of episodes (default: one per task, or 1 for random worlds).
    #[arg(long)]
    pub episodes: Option<usize>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = DataFormat::Json)]
    pub format: DataFormat,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Agent body.
    #[command(flatten)]
    pub body: super::anim::BodyArgs,
}

/// Data formats of `strider run`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DataFormat {
    /// `{"summary": …, "episodes": […]}`.
    Json,
    /// One header line and one line per episode.
    Csv,
}

fn read(path: &Path) -> Result<String, Failure> {
    Ok(files::read_text(path)?)
}

/// Most episodes one run may ask for (the records of a run are kept for its summary).
pub const MAX_EPISODES: usize = 1_000_000;

/// Most worker threads a run may ask for.
pub const MAX_THREADS: usize = 256;

/// Loads a map argument.
pub fn load_map(map: &str, scen: Option<&Path>) -> Result<MapSource, Failure> {
    if let Some(name) = map.strip_prefix("random:") {
        let k: WorldKind = name.parse().map_err(|e| anyhow!("{e}"))?;
        return Ok(MapSource::Random(k));
    }
    let path = Path::new(map);
    let file = path.display().to_string();
    let scenario = match path.extension().and_then(|e| e.to_str()) {
        Some("rhai") => {
            let log = ScriptLog::new();
            let s = map_api::load_scenario(&read(path)?, &file, Limits::default(), &log);
            for line in log.lines() {
                eprintln!("{file}: {line}");
            }
            s?
        }
        Some("txt") | Some("world") => text::parse(&read(path)?, &file)?,
        Some("map") => {
            let scen_path = match scen {
                Some(p) => p.to_path_buf(),
                None => PathBuf::from(format!("{map}.scen")),
            };
            if !scen_path.exists() {
                return Err(match scen {
                    Some(p) => anyhow!("{}: the scenario file given with --scen does not exist", p.display()),
                    None => anyhow!(
                        "{file}: a MovingAI map needs its scenario file ({} does not exist): give --scen FILE",
                        scen_path.display()
                    ),
                }
                .into());
            }
            let scen_file = scen_path.display().to_string();
            movingai::load(&read(path)?, &file, &read(&scen_path)?, &scen_file)?
        }
        _ => {
            return Err(anyhow!("{file}: expected a .rhai map, a .txt world, a MovingAI .map, or random:KIND").into());
        }
    };
    Ok(MapSource::Scenario(Arc::new(scenario)))
}

/// Loads the navigation rules (built-in when `rules` is `None`).
pub fn load_controller(rules: Option<&Path>) -> Result<LayeredController, Failure> {
    let (source, file) = match rules {
        Some(p) => (read(p)?, p.display().to_string()),
        None => (DEFAULT_RULES.to_string(), DEFAULT_RULES_FILE.to_string()),
    };
    let log = ScriptLog::new();
    let engines = fuzzy_api::load_engines(&source, &file, Limits::default(), &log);
    for line in log.lines() {
        eprintln!("{file}: {line}");
    }
    LayeredController::new(&engines?, ControllerParams::default()).map_err(|m| anyhow!("{file}: {m}").into())
}

pub use crate::experiment::world_seed;

/// How many episodes a run of `source` has: `episodes`, or one per task (one for random
/// worlds).
pub fn episode_count(source: &MapSource, episodes: Option<usize>) -> usize {
    match source {
        MapSource::Scenario(s) => episodes.unwrap_or(s.tasks.len()),
        MapSource::Random(_) => episodes.unwrap_or(1),
    }
}

/// Episode `i` of a run of `source` seeded with `seed`; a random world is generated here, so
/// a run makes each world when its episode starts, not all of them before the first.
pub fn job(source: &MapSource, i: usize, seed: u64) -> Job {
    let ws = world_seed(seed, i);
    match source {
        MapSource::Scenario(s) => Job { scenario: s.clone(), task: i % s.tasks.len(), seed: ws },
        MapSource::Random(k) => Job { scenario: Arc::new(kind::generate(*k, ws)), task: 0, seed: ws },
    }
}

/// Checks an episode count against [`MAX_EPISODES`].
pub fn check_episodes(n: usize) -> Result<(), Failure> {
    if !(1..=MAX_EPISODES).contains(&n) {
        return Err(anyhow!("--episodes must be in 1..={MAX_EPISODES}, found {n}").into());
    }
    Ok(())
}

/// `strider run`.
pub fn run(args: RunArgs) -> Outcome {
    if let Some(n) = args.episodes {
        check_episodes(n)?;
    }
    if let Some(t) = args.threads
        && !(1..=MAX_THREADS).contains(&t)
    {
        return Err(anyhow!("--threads must be in 1..={MAX_THREADS}, found {t}").into());
    }
    let source = load_map(&args.map.map, args.map.scen.as_deref())?;
    let controller = load_controller(args.map.rules.as_deref())?;
    let count = episode_count(&source, args.episodes);
    check_episodes(count)?;
    let params = StepParameters {
        animation: super::anim::load_animation(&args.body)?,
        stopwatch: Some(wall_stopwatch()),
        ..StepParameters::default()
    };
    let bar = if count > 1 && io::stderr().is_terminal() {
        let b = indicatif::ProgressBar::new(count as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} episodes, {elapsed} elapsed, eta {eta}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Some(b)
    } else {
        None
    };
    let progress = || {
        if let Some(b) = &bar {
            b.inc(1);
        }
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .map_err(|e| anyhow!("cannot start worker threads: {e}"))?;
    let seed = args.map.seed;
    let make = |i: usize| job(&source, i, seed);
    let records = pool.install(|| experiment::run_batch_of(count, &make, &controller, &params, &progress));
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let summary = experiment::summarize(&records);
    let mut out = BufWriter::new(io::stdout().lock());
    match args.format {
        DataFormat::Json => {
            let doc = serde_json::json!({ "summary": summary, "episodes": records });
            // The io error keeps its kind, so a closed pipe is seen as one.
            serde_json::to_writer_pretty(&mut out, &doc).map_err(io::Error::from)?;
            writeln!(out)?;
        }
        DataFormat::Csv => write_csv(&mut out, &records)?,
    }
    out.flush()?;
    let failed = records.iter().filter(|r| !r.reached || r.collisions > 0).count();
    if failed > 0 {
        return Err(Failure::Task(anyhow!("{failed} of {} episodes did not reach the goal cleanly", records.len())));
    }
    Ok(())
}

fn opt(x: Option<f64>) -> String {
    x.map_or_else(String::new, |v| format!("{v}"))
}

/// The wall clock, lent to the simulation to time footstep planning (the figures only).
pub fn wall_stopwatch() -> crate::sim::footing::StopwatchHandle {
    struct Wall(std::time::Instant);
    impl crate::sim::footing::Stopwatch for Wall {
        fn now_s(&self) -> f64 {
            self.0.elapsed().as_secs_f64()
        }
    }
    crate::sim::footing::StopwatchHandle(std::sync::Arc::new(Wall(std::time::Instant::now())))
}

fn write_csv(out: &mut impl Write, records: &[EpisodeRecord]) -> io::Result<()> {
    writeln!(
        out,
        "episode,scenario,task,seed,reached,collisions,time_s,path_length_m,optimal_length_m,path_ratio,min_clearance_m,stalls,boundary_follows,foot_skating_cm_per_frame,transition_cost,tracking_rms_m,barn_score,barn_score_walking,invalid_footholds,footstep_planning_ms_p99"
    )?;
    for r in records {
        writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.episode,
            r.scenario,
            r.task,
            r.seed,
            r.reached,
            r.collisions,
            r.time_s,
            r.path_length_m,
            opt(r.optimal_length_m),
            opt(r.path_ratio),
            r.min_clearance_m,
            r.stalls,
            r.boundary_follows,
            opt(r.foot_skating_cm_per_frame),
            opt(r.transition_cost),
            opt(r.tracking_rms_m),
            opt(r.barn_score),
            opt(r.barn_score_walking),
            r.invalid_footholds.map_or(String::new(), |n| n.to_string()),
            opt(r.footstep_planning_ms_p99)
        )?;
    }
    Ok(())
}

/// `strider gen` options.
#[derive(Debug, Args)]
pub struct GenArgs {
    /// World kind: sparse, semi, cluttered, rooms, maze or grid (`--density` is an alias).
    #[arg(long, alias = "density")]
    pub kind: String,
    /// Seed of the world.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// `strider gen`: prints a seeded random world in the plain text format.
pub fn gen_world(args: GenArgs) -> Outcome {
    let k: WorldKind = args.kind.parse().map_err(|e| anyhow!("{e}"))?;
    let scenario = kind::generate(k, args.seed);
    files::write_stdout(format_args!("{}", text::write(&scenario)))?;
    Ok(())
}

/// `strider` with no command: runs the default navigation rules on the built-in
/// semi-cluttered map and prints the episode's measurements.
pub fn default_scenario() -> Outcome {
    let log = ScriptLog::new();
    let scenario = map_api::load_scenario(DEFAULT_MAP, DEFAULT_MAP_FILE, Limits::default(), &log)?;
    let controller = load_controller(None)?;
    let world = scenario.world();
    let mut params = StepParameters {
        animation: super::anim::load_animation(&super::anim::BodyArgs::default())?,
        ..StepParameters::default()
    };
    params.limits.radius = scenario.agent_radius;
    let e = experiment::run_episode(&scenario, &world, 0, &controller, &params, 0, 0);
    let r = &e.record;
    let mut out = BufWriter::new(io::stdout().lock());
    writeln!(
        out,
        "strider: layered fuzzy navigation with the RL-animated character on the built-in '{}' world (seed 000 Fig 2 b)",
        r.scenario
    )?;
    writeln!(out, "  reached the goal:  {}", if r.reached { "yes" } else { "no" })?;
    writeln!(out, "  time:              {:.2} s", r.time_s)?;
    writeln!(
        out,
        "  path length:       {:.2} m (optimal {})",
        r.path_length_m,
        r.optimal_length_m.map_or("none".into(), |o| format!("{o:.2} m"))
    )?;
    writeln!(out, "  path ratio:        {}", r.path_ratio.map_or("-".into(), |x| format!("{x:.3}")))?;
    writeln!(out, "  min clearance:     {:.3} m", r.min_clearance_m)?;
    writeln!(out, "  collisions:        {}", r.collisions)?;
    writeln!(out, "  boundary follows:  {}", r.boundary_follows)?;
    if let (Some(skate), Some(cost), Some(track)) = (r.foot_skating_cm_per_frame, r.transition_cost, r.tracking_rms_m) {
        writeln!(
            out,
            "  animated character: foot skating {skate:.3} cm/frame, transition cost {cost:.4}, tracking RMS {track:.3} m"
        )?;
    }
    writeln!(out, "Pictures: strider render maps/semi_cluttered.rhai --out frames/ --poses")?;
    out.flush()?;
    if r.reached && r.collisions == 0 { Ok(()) } else { Err(Failure::Task(anyhow!("the default scenario failed"))) }
}
