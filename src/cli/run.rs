//! `strider run`, `strider gen` and the loading of maps and rule scripts shared by the
//! navigation commands (seed 000 §3.1 navigation, §4 measurements).

mod identity;

use std::io::{self, BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow};
use clap::{Args, ValueEnum};

use crate::anim::bvh::{self, BvhOptions};
use crate::anim::{Clip, Skeleton};
use crate::experiment::{self, EpisodeRecord, Field, Optimum, Progress, Shard};
use crate::files;
use crate::load::{Failure, Outcome, load_map, load_rules};
pub use crate::load::{MapSource, MapSpec, episode_count, job};
use crate::maps::kind::{self, WorldKind};
use crate::maps::text;
use crate::sim::{LayeredController, StepParameters};
pub use identity::RunIdentity;

/// Options shared by `run` and `render`.
#[derive(Debug, Args)]
pub struct MapArgs {
    /// The world: a `.rhai` map, a plain text world (`.txt`), a MovingAI `.map` (each line of
    /// its scenario file one episode), a BARN challenge `world_N.world` (its reference path
    /// `path_N.npy` beside it or in `path_files/`), a folder of worlds (`.world`, `.txt`,
    /// `.rhai`; one batch, in name order), benchmark data `movingai:NAME` or `barn:NAME` (read
    /// from the folder $STRIDER_DATA, by default ./data; `barn:` runs every BARN world), or
    /// `random:KIND` (sparse, semi, cluttered, rooms, maze, grid) for seeded random worlds.
    pub map: String,
    /// MovingAI scenario file (each line one episode; `movingai:NAME` for benchmark data);
    /// default: MAP.scen.
    #[arg(long)]
    pub scen: Option<PathBuf>,
    /// Navigation rules (a `.rhai` script building the layered network); default: built in.
    #[arg(long)]
    pub rules: Option<PathBuf>,
    /// Seed of the run (random worlds and episode seeds).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Most failed episodes whose reasons `strider run` prints.
const MAX_FAILURES_SHOWN: usize = 5;

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
    pub body: crate::load::BodyArgs,
    /// Also write each episode's full motion of the animated character as
    /// `DIR/episode_<N>.bvh`: 60 frames/s, metres, Y up (BVH (X, Y, Z) = world (y, z, x), as
    /// `strider db export`), root OFFSET 0 0 0 with the root position channels holding the
    /// world position (the pelvis height following the terrain).
    #[arg(long, value_name = "DIR")]
    pub bvh_out: Option<PathBuf>,
    /// Run only the I-th of N interleaved slices of the episodes (I, I+N, I+2N, …; numbered
    /// and seeded as in the whole run), for schedulers that split a run: `strider merge`
    /// joins the slices' outputs into what the whole run prints.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
    /// Work out each episode's reference optimum (`optimal_length_m`, the exact shortest path
    /// for the agent's disc, and `path_ratio`); `off` leaves both null (empty in CSV) and the
    /// summary's path ratios null, and saves the time.
    #[arg(long, value_enum, default_value_t = OptimumArg::On)]
    pub optimum: OptimumArg,
}

/// `--optimum on|off`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OptimumArg {
    /// Work it out.
    On,
    /// Leave it out.
    Off,
}

/// Data formats of `strider run`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DataFormat {
    /// `{"summary": …, "episodes": […]}`.
    Json,
    /// One header line and one line per episode.
    Csv,
}

/// Most episodes one run may ask for (the records of a run are kept for its summary).
pub const MAX_EPISODES: usize = 1_000_000;

/// Most worker threads a run may ask for.
pub const MAX_THREADS: usize = 256;

/// The world of `args`, script output to stderr.
pub fn load_map_args(args: &MapArgs) -> Result<MapSource, Failure> {
    let spec = MapSpec::parse(Some(&args.map))?.with_scen(args.scen.clone());
    Ok(load_map(&spec).logged()?)
}

/// The navigation rules of `args` (built-in without `--rules`), script output to stderr.
pub fn load_controller(rules: Option<&Path>) -> Result<LayeredController, Failure> {
    Ok(load_rules(rules).logged()?)
}

/// Checks an episode count against [`MAX_EPISODES`].
pub fn check_episodes(n: usize) -> Result<(), Failure> {
    if !(1..=MAX_EPISODES).contains(&n) {
        return Err(anyhow!("--episodes must be in 1..={MAX_EPISODES}, found {n}").into());
    }
    Ok(())
}

/// A run made ready: its arguments checked, its map, rules and body loaded.
pub struct PreparedRun {
    /// Where the episodes' worlds come from.
    pub source: MapSource,
    /// The navigation rules.
    pub controller: LayeredController,
    /// The agents' parameters (the body, a wall stopwatch for the timing figures).
    pub params: StepParameters,
    /// The run's seed.
    pub seed: u64,
    /// The episodes to run: the whole run's, or its shard's.
    pub episodes: Vec<usize>,
    /// What identifies the run, for a shard's output (`None` for a whole run).
    pub identity: Option<RunIdentity>,
    /// Whether the episodes' reference optimum is worked out.
    pub optimum: Optimum,
}

impl PreparedRun {
    /// Checks `args` (counts, flag combinations) and loads what the run needs, script output
    /// to stderr; nothing runs yet.
    pub fn new(args: &RunArgs) -> Result<PreparedRun, Failure> {
        if let Some(n) = args.episodes {
            check_episodes(n)?;
        }
        if let Some(t) = args.threads
            && !(1..=MAX_THREADS).contains(&t)
        {
            return Err(anyhow!("--threads must be in 1..={MAX_THREADS}, found {t}").into());
        }
        if args.bvh_out.is_some() && args.body.body == crate::load::BodyKind::Disc {
            return Err(anyhow!(
                "--bvh-out writes the animated character's motion; it cannot be used with --body disc"
            )
            .into());
        }
        let source = load_map_args(&args.map)?;
        let controller = load_controller(args.map.rules.as_deref())?;
        let count = episode_count(&source, args.episodes);
        check_episodes(count)?;
        let params = StepParameters {
            animation: crate::load::load_animation(&args.body)?,
            stopwatch: Some(wall_stopwatch()),
            record_motion: args.bvh_out.is_some(),
            ..StepParameters::default()
        };
        let episodes = args.shard.unwrap_or(Shard::WHOLE).episodes(count);
        let identity = match args.shard {
            Some(shard) => Some(RunIdentity::new(
                (&args.map.map, &source),
                (args.map.rules.as_deref(), &controller),
                &args.body,
                args.map.seed,
                count,
                shard,
            )?),
            None => None,
        };
        let optimum = match args.optimum {
            OptimumArg::On => Optimum::On,
            OptimumArg::Off => Optimum::Off,
        };
        Ok(PreparedRun { source, controller, params, seed: args.map.seed, episodes, identity, optimum })
    }

    /// Runs `episodes` (some of [`PreparedRun::episodes`]) in parallel on the current rayon
    /// pool and returns their records in that order; `progress` and `each` as for
    /// [`experiment::run_episodes_each`].
    pub fn run(
        &self,
        episodes: &[usize],
        progress: &(dyn Fn(Progress) + Sync),
        each: &(dyn Fn(&experiment::Episode) + Sync),
    ) -> Vec<EpisodeRecord> {
        let make = |i: usize| job(&self.source, i, self.seed);
        experiment::run_episodes_each(episodes, &make, &self.controller, &self.params, self.optimum, progress, each)
    }
}

/// The worker threads of a run: `threads`, or all cores.
pub fn thread_pool(threads: Option<usize>) -> anyhow::Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| anyhow!("cannot start worker threads: {e}"))
}

/// `strider run`.
pub fn run(args: RunArgs) -> Outcome {
    let prepared = PreparedRun::new(&args)?;
    let count = prepared.episodes.len();
    let params = &prepared.params;
    // The motion files' directory and skeleton, checked before any episode runs.
    let motion_out = match (&args.bvh_out, &params.animation) {
        (Some(dir), Some(anim)) => {
            std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
            files::check_writable(&dir.join("episode_0.bvh"))?;
            Some((dir.clone(), world_skeleton(&anim.0.db.skeleton)?, 1.0 / anim.0.player.frame_rate))
        }
        _ => None,
    };
    // A motion file that cannot be written is reported after the results, which it does not
    // touch; the other files are still written.
    let write_failures: std::sync::Mutex<Vec<(usize, anyhow::Error)>> = std::sync::Mutex::new(Vec::new());
    let stepping: std::sync::Mutex<f64> = std::sync::Mutex::new(0.0);
    // The first failed episodes (by number) with why they failed, and how many failed.
    let failures: std::sync::Mutex<(Vec<(usize, String)>, usize)> = std::sync::Mutex::new((Vec::new(), 0));
    let each = |e: &experiment::Episode| {
        *stepping.lock().unwrap_or_else(|p| p.into_inner()) += e.stepping_s.unwrap_or(0.0);
        if let Some(why) = &e.failure {
            let line = format!("episode {} ({}): {why}", e.record.episode, e.record.scenario);
            let (first, count) = &mut *failures.lock().unwrap_or_else(|p| p.into_inner());
            first.push((e.record.episode, line));
            first.sort();
            first.truncate(MAX_FAILURES_SHOWN);
            *count += 1;
        }
        let Some((dir, skeleton, frame_time)) = &motion_out else { return };
        let path = dir.join(format!("episode_{}.bvh", e.record.episode));
        let clip =
            Clip { name: format!("episode_{}", e.record.episode), frame_time: *frame_time, frames: e.motion.clone() };
        let text = bvh::write(skeleton, &clip, &BvhOptions::default());
        if let Err(err) =
            files::write_atomic(&path, text.as_bytes()).with_context(|| format!("cannot write {}", path.display()))
        {
            write_failures.lock().unwrap_or_else(|p| p.into_inner()).push((e.record.episode, err));
        }
    };
    // On a terminal, the episodes done and the steps taken (a long episode moves the count
    // on), on stderr; never on stdout, never when stderr is not a terminal.
    let bar = io::stderr().is_terminal().then(|| {
        let b = indicatif::ProgressBar::new(count as u64);
        // One episode has no rate to tell its end by.
        let eta = if count > 1 { ", eta {eta}" } else { "" };
        let template = format!("{{bar:40}} {{pos}}/{{len}} episodes, {{msg}}, {{elapsed}} elapsed{eta}");
        b.set_style(
            indicatif::ProgressStyle::with_template(&template)
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b.set_message("0 agent-steps");
        b.enable_steady_tick(std::time::Duration::from_millis(250));
        b
    });
    let taken = std::sync::atomic::AtomicU64::new(0);
    let progress = |p: Progress| {
        let Some(b) = &bar else { return };
        match p {
            Progress::Steps(n) => {
                let total = taken.fetch_add(n, std::sync::atomic::Ordering::Relaxed) + n;
                b.set_message(format!("{} agent-steps", indicatif::HumanCount(total)));
            }
            Progress::Episode => b.inc(1),
        }
    };
    let pool = thread_pool(args.threads)?;
    let clock = std::time::Instant::now();
    let records = pool.install(|| prepared.run(&prepared.episodes, &progress, &each));
    let elapsed = clock.elapsed().as_secs_f64();
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let summary = experiment::summarize(&records);
    // The whole batch's throughput (worlds, optima and episodes), for the user on stderr.
    let steps: u64 = records.iter().map(|r| u64::from(r.steps)).sum();
    // And the steps alone (no world generation, optimum or record), per thread: what a step
    // of the simulation costs.
    let stepping = stepping.into_inner().unwrap_or_else(|p| p.into_inner());
    eprintln!(
        "{} episodes, {steps} agent-steps in {elapsed:.2} s: {:.0} agent-steps/s on {} thread(s); \
         the steps alone: {:.0} agent-steps/s per thread",
        records.len(),
        steps as f64 / elapsed.max(1e-9),
        pool.current_num_threads(),
        steps as f64 / stepping.max(1e-9)
    );
    let mut out = BufWriter::new(io::stdout().lock());
    write_records(&mut out, args.format, prepared.identity.as_ref(), &summary, &records)?;
    out.flush()?;
    let failed = records.iter().filter(|r| !r.reached || r.collisions > 0).count();
    let (first, count) = failures.into_inner().unwrap_or_else(|p| p.into_inner());
    for (_, line) in &first {
        eprintln!("{line}");
    }
    if count > first.len() {
        eprintln!("… and {} more failed episodes", count - first.len());
    }
    let not_reached =
        (failed > 0).then(|| format!("{failed} of {} episodes did not reach the goal cleanly", records.len()));
    let mut write_failures = write_failures.into_inner().unwrap_or_else(|p| p.into_inner());
    if let (false, Some((dir, _, _))) = (write_failures.is_empty(), &motion_out) {
        write_failures.sort_by_key(|(episode, _)| *episode);
        for (_, err) in write_failures.iter().take(MAX_FAILURES_SHOWN) {
            eprintln!("error: {err:#}");
        }
        if write_failures.len() > MAX_FAILURES_SHOWN {
            eprintln!("… and {} more motion files not written", write_failures.len() - MAX_FAILURES_SHOWN);
        }
        let also = not_reached.map_or_else(String::new, |m| format!("; {m}"));
        return Err(Failure::Input(anyhow!(
            "{} of {} motion files could not be written to {} (the results above are complete){also}",
            write_failures.len(),
            records.len(),
            dir.display()
        )));
    }
    match not_reached {
        Some(m) => Err(Failure::Task(anyhow!(m))),
        None => Ok(()),
    }
}

/// The character's skeleton for world-motion files: the root's offset moved into its position
/// channels (OFFSET 0 0 0), so that they hold the world position.
fn world_skeleton(skeleton: &Skeleton) -> anyhow::Result<Skeleton> {
    let mut joints = skeleton.joints().to_vec();
    if let Some(root) = joints.first_mut() {
        root.offset = glam::DVec3::ZERO;
    }
    Skeleton::new(joints).map_err(|e| anyhow!("cannot export the skeleton: {e}"))
}

/// The start of the first line of a shard's CSV output, before its [`RunIdentity`] as JSON.
pub const CSV_IDENTITY: &str = "# strider run: ";

/// Writes a run's episode records and summary in `format`: JSON `{"summary": …, "episodes":
/// […]}`, or CSV with one header line and one line per episode. Both list the fields of
/// [`EpisodeRecord::fields`] (CSV leaves the cells of missing values empty). A shard's output
/// also carries its run's `identity`: JSON as `"run"`, CSV as a first line [`CSV_IDENTITY`] and
/// the identity as JSON. The io error keeps its kind, so a closed pipe is seen as one.
pub fn write_records(
    out: &mut impl Write,
    format: DataFormat,
    identity: Option<&RunIdentity>,
    summary: &experiment::Summary,
    records: &[EpisodeRecord],
) -> io::Result<()> {
    match format {
        DataFormat::Json => {
            let mut doc = serde_json::json!({ "summary": summary, "episodes": records });
            if let Some(id) = identity {
                doc["run"] = serde_json::to_value(id).map_err(io::Error::from)?;
            }
            serde_json::to_writer_pretty(&mut *out, &doc).map_err(io::Error::from)?;
            writeln!(out)
        }
        DataFormat::Csv => {
            if let Some(id) = identity {
                writeln!(out, "{CSV_IDENTITY}{}", serde_json::to_string(id).map_err(io::Error::from)?)?;
            }
            let Some(first) = records.first() else { return Ok(()) };
            let header: Vec<&str> = first.fields().iter().map(|(name, _)| *name).collect();
            writeln!(out, "{}", header.join(","))?;
            for r in records {
                let cells: Vec<String> = r.fields().iter().map(|(_, f)| csv_cell(f)).collect();
                writeln!(out, "{}", cells.join(","))?;
            }
            Ok(())
        }
    }
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

fn csv_cell(f: &Field) -> String {
    match f {
        Field::Count(v) | Field::Key(v) => v.to_string(),
        Field::Number(v) => v.to_string(),
        Field::Flag(v) => v.to_string(),
        Field::Text(t) if t.contains([',', '"', '\n', '\r']) => format!("\"{}\"", t.replace('"', "\"\"")),
        Field::Text(t) => t.to_string(),
        Field::Missing => String::new(),
    }
}

/// `strider gen` options.
#[derive(Debug, Args)]
pub struct GenArgs {
    /// A map to print resolved as a text world, every random draw made with `--seed` (a
    /// SteerSuite `.xml` case, a `.txt` or `.rhai` world, `random:KIND`), instead of `--kind`.
    #[arg(conflicts_with = "kind", required_unless_present = "kind")]
    pub map: Option<String>,
    /// World kind: sparse, semi, cluttered, rooms, maze or grid (`--density` is an alias).
    #[arg(long, alias = "density")]
    pub kind: Option<String>,
    /// Seed of the world.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// `strider gen`: prints a seeded random world, or a map with its random draws made, in the
/// plain text format. A crowd whose agents start overlapping is printed with a note on stderr.
pub fn gen_world(args: GenArgs) -> Outcome {
    let scenario = match (&args.map, &args.kind) {
        (Some(map), _) if map.ends_with(".xml") => {
            let text = files::read_text(Path::new(map))?;
            crate::maps::steersuite::parse(&text, map, args.seed)?
        }
        (Some(map), _) => crate::load::load_scenario(&MapSpec::parse(Some(map))?, args.seed).logged()?,
        (None, kind) => {
            let k: WorldKind = kind.as_deref().unwrap_or_default().parse().map_err(|e| anyhow!("{e}"))?;
            kind::generate(k, args.seed)
        }
    };
    if let Some(c) = &scenario.crowd {
        for (i, j) in c.overlapping_starts(0.0) {
            eprintln!("note: agents {} and {} start overlapping", i + 1, j + 1);
        }
    }
    files::write_stdout(format_args!("{}", text::write(&scenario)))?;
    Ok(())
}

/// `strider` with no command: runs the default navigation rules on the built-in
/// semi-cluttered map and prints the episode's measurements.
pub fn default_scenario() -> Outcome {
    let scenario = crate::load::load_scenario(&MapSpec::BuiltIn, 0).logged()?;
    let controller = load_controller(None)?;
    let world = scenario.world();
    let mut params = StepParameters {
        animation: crate::load::load_animation(&crate::load::BodyArgs::default())?,
        ..StepParameters::default()
    };
    params.limits.radius = scenario.agent_radius;
    let e = experiment::run_episode(&scenario, &world, 0, &controller, &params, 0, 0);
    let r = &e.record;
    let mut out = BufWriter::new(io::stdout().lock());
    writeln!(
        out,
        "strider: layered fuzzy navigation with the RL-animated character on the built-in '{}' world (Fig 2 b of the fuzzy + RL paper)",
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
    writeln!(
        out,
        "Watch it: strider render maps/semi_cluttered.rhai --gif semi_cluttered.gif (or --out frames/ for PNGs)"
    )?;
    out.flush()?;
    if r.reached && r.collisions == 0 { Ok(()) } else { Err(Failure::Task(anyhow!("the default scenario failed"))) }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(animated: bool) -> EpisodeRecord {
        let a = |x: f64| animated.then_some(x);
        let n = |x: u64| animated.then_some(x);
        EpisodeRecord {
            episode: 3,
            scenario: "a, \"b\"".into(),
            task: 1,
            seed: 9,
            reached: true,
            collisions: 0,
            time_s: 12.5,
            path_length_m: 20.0,
            optimal_length_m: Some(19.0),
            path_ratio: None,
            min_clearance_m: 0.25,
            steps: 250,
            stalls: 2,
            boundary_follows: 1,
            foot_skating_cm_per_frame: a(0.1),
            contact_weight: a(0.9),
            plants: n(40),
            sliding_plants: n(1),
            transition_cost: a(0.02),
            transitions: n(30),
            peak_switch_jerk_mps3: a(5.0),
            tracking_rms_m: a(0.05),
            heading_rms_deg: a(3.0),
            speed_rms_mps: a(0.1),
            barn_score: a(0.7),
            barn_score_walking: a(0.6),
            invalid_footholds: animated.then_some(0),
            footsteps_planned: n(12),
            footstep_planning_ms_p99: a(0.2),
            upper_body_min_clearance_m: a(0.05),
            upper_body_collisions: animated.then_some(0),
            max_waist_bend_deg: a(60.0),
            max_waist_twist_deg: a(80.0),
            upper_body_refused_steps: n(0),
            upper_body_ms_per_frame: a(0.1),
            refusal: animated.then(|| "no way round, for the format's sake".into()),
        }
    }

    #[test]
    fn csv_and_json_carry_the_same_fields() {
        let records = [record(true), record(false)];
        let summary = experiment::summarize(&records);
        let mut json = Vec::new();
        write_records(&mut json, DataFormat::Json, None, &summary, &records).unwrap();
        let doc: serde_json::Value = serde_json::from_slice(&json).unwrap();
        let keys: Vec<String> = doc["episodes"][0].as_object().unwrap().keys().cloned().collect();
        let mut csv = Vec::new();
        write_records(&mut csv, DataFormat::Csv, None, &summary, &records).unwrap();
        let csv = String::from_utf8(csv).unwrap();
        let mut lines = csv.lines();
        let mut header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
        assert_eq!(header.len(), 36);
        header.sort();
        let mut keys = keys;
        keys.sort();
        assert_eq!(header, keys, "the animated record's JSON object and the CSV header differ");
        // The disc's record leaves the animation figures out of JSON and their cells empty.
        let disc = doc["episodes"][1].as_object().unwrap();
        assert!(!disc.contains_key("plants") && disc["path_ratio"].is_null());
        let rows: Vec<&str> = lines.collect();
        assert_eq!(rows.len(), 2);
        assert!(rows[0].starts_with("3,\"a, \"\"b\"\"\",1,9,true,0,12.5,20,19,,0.25,250,2,1,0.1,"), "{}", rows[0]);
        assert!(rows[1].ends_with(",,,,,,,,,,,,,,,"), "{}", rows[1]);
    }
}
