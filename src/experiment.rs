//! Episodes and batches: run navigation tasks to completion and measure them the way seed 000
//! §4 compares planners (success, time, path length against the optimal path, clearance,
//! collisions), in parallel across episodes without giving up determinism.
//!
//! Invariant: a batch's records come back in episode order and each episode depends only on
//! its scenario, rules and seed, so results are identical whatever the thread count.

use std::sync::{Arc, Mutex, OnceLock};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::plan;
use crate::scenario::{BARN_SPEED_MPS, Scenario};
use crate::sim::{LayeredController, Outcome, Simulation, StepParameters};
use crate::world::World;

/// The measurements of one episode. [`EpisodeRecord::fields`] lists them in order; JSON and CSV
/// are both written from that list, so the two formats always carry the same fields. A record
/// reads back from its JSON object (`strider merge`): the fields' names are the JSON keys,
/// missing figures are `None`, and JSON's `null` for an infinite clearance is infinity again.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EpisodeRecord {
    /// Episode number within the batch.
    pub episode: usize,
    /// Scenario name.
    pub scenario: String,
    /// Task index within the scenario.
    pub task: usize,
    /// Seed of the episode (a string in JSON: [`Field::Key`]).
    #[serde(deserialize_with = "key_from_string")]
    pub seed: u64,
    /// Goal reached within the time limit.
    pub reached: bool,
    /// Steps that ended overlapping an obstacle or agent, and times a bone of the upper body
    /// went into an obstacle ([`EpisodeRecord::upper_body_collisions`]).
    pub collisions: u32,
    /// Simulated time until the goal or the time limit, seconds.
    pub time_s: f64,
    /// Distance travelled, metres.
    pub path_length_m: f64,
    /// Shortest collision-free path for the agent's disc into the goal circle (the shortest
    /// path to the goal point less the goal radius), metres (`None`: no path exists).
    pub optimal_length_m: Option<f64>,
    /// `path_length_m / optimal_length_m` for reached episodes.
    pub path_ratio: Option<f64>,
    /// Smallest gap between the agent and any obstacle, metres.
    #[serde(deserialize_with = "infinite_when_null")]
    pub min_clearance_m: f64,
    /// Simulation steps taken.
    pub steps: u32,
    /// Stalled steps: the body refused or shortened a step because it would have hit
    /// something, or stood against a command to move because nothing ahead was clear.
    pub stalls: u32,
    /// Times boundary following started.
    pub boundary_follows: u32,
    /// Animated body only: mean horizontal slide of contact feet, centimetres per 60 Hz frame.
    pub foot_skating_cm_per_frame: Option<f64>,
    /// Animated body only: Σ contact weight of the skating measure (to weigh episodes).
    pub contact_weight: Option<f64>,
    /// Animated body only: foot plants (touch-down to lift-off).
    pub plants: Option<u64>,
    /// Animated body only: plants whose heel or toe slid 2 cm or more.
    pub sliding_plants: Option<u64>,
    /// Animated body only: mean pose distance (Eq. 1) at transitions between intervals.
    pub transition_cost: Option<f64>,
    /// Animated body only: transitions (switches to other than the clip's next interval).
    pub transitions: Option<u64>,
    /// Animated body only: largest joint jerk within 0.25 s of a transition, m/s³.
    pub peak_switch_jerk_mps3: Option<f64>,
    /// Animated body only: RMS distance between the commanded path (commands integrated from
    /// the root at each switch point) and the root path, metres.
    pub tracking_rms_m: Option<f64>,
    /// Animated body only: RMS difference between the commanded heading and the heading, degrees.
    pub heading_rms_deg: Option<f64>,
    /// Animated body only: RMS difference between the commanded and the actual speed, m/s.
    pub speed_rms_mps: Option<f64>,
    /// Worlds with a benchmark reference (BARN): the BARN metric, `success · OT / clip(AT,
    /// 2·OT, 8·OT)` with OT the reference path at 2 m/s (at most 0.5).
    pub barn_score: Option<f64>,
    /// The same with OT the reference path at the run's walking speed ([`walking_speed`]).
    pub barn_score_walking: Option<f64>,
    /// Animated body on uneven terrain: footholds the terrain does not support (whole sole on
    /// ground at the planned height); must be 0.
    pub invalid_footholds: Option<u32>,
    /// Animated body on uneven terrain: steps planned by the footstep planner.
    pub footsteps_planned: Option<u64>,
    /// Animated body on uneven terrain, when the run lends a stopwatch
    /// ([`StepParameters::stopwatch`]): 99th percentile of the planning time per step, ms.
    pub footstep_planning_ms_p99: Option<f64>,
    /// Animated body among obstacles its upper body can touch: least clearance of the upper
    /// body's capsules from them over the frames played, metres (absent when nothing came
    /// within a metre).
    pub upper_body_min_clearance_m: Option<f64>,
    /// Animated body: times a bone of its upper body (the axis of one of the planner's
    /// capsules) went into an obstacle; counted in `collisions` too.
    pub upper_body_collisions: Option<u32>,
    /// Animated body: deepest forward bend of the waist the upper-body planner added, degrees.
    pub max_waist_bend_deg: Option<f64>,
    /// Animated body: largest waist twist the upper-body planner added, degrees.
    pub max_waist_twist_deg: Option<f64>,
    /// Animated body: switch points at which the upper body refused a step the legs could take.
    pub upper_body_refused_steps: Option<u64>,
    /// Animated body among such obstacles, when the run lends a stopwatch: upper-body planning
    /// time per frame played, ms.
    pub upper_body_ms_per_frame: Option<f64>,
    /// Why the body could not get to the goal at all, when no way round what it cannot pass
    /// under or step across exists ([`crate::sim::Outcome::Refused`]).
    #[serde(default)]
    pub refusal: Option<String>,
}

/// A [`Field::Key`] as JSON holds it: a string of decimal digits.
fn key_from_string<'de, D: serde::Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
    let text = String::deserialize(d)?;
    text.parse().map_err(|_| serde::de::Error::custom(format!("expected a seed (decimal digits), found \"{text}\"")))
}

/// JSON writes a non-finite number as `null`; a clearance is never NaN, so `null` is infinity
/// (nothing within range).
fn infinite_when_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
}

/// One value of an [`EpisodeRecord`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Field<'a> {
    /// A count.
    Count(u64),
    /// A 64-bit key (a seed): JSON writes it as a string of its digits, since readers that
    /// hold numbers as doubles (jq, JavaScript, …) change integers above 2^53; CSV and scripts
    /// get the digits.
    Key(u64),
    /// A measurement.
    Number(f64),
    /// Yes or no.
    Flag(bool),
    /// A name.
    Text(&'a str),
    /// Not measured in this episode (the disc body has no animation figures).
    Missing,
}

impl From<Option<f64>> for Field<'_> {
    fn from(x: Option<f64>) -> Self {
        x.map_or(Field::Missing, Field::Number)
    }
}

impl From<Option<u64>> for Field<'_> {
    fn from(x: Option<u64>) -> Self {
        x.map_or(Field::Missing, Field::Count)
    }
}

impl EpisodeRecord {
    /// Every field, named, in the order output formats list them.
    pub fn fields(&self) -> [(&'static str, Field<'_>); 36] {
        use Field::{Count, Flag, Key, Number, Text};
        [
            ("episode", Count(self.episode as u64)),
            ("scenario", Text(&self.scenario)),
            ("task", Count(self.task as u64)),
            ("seed", Key(self.seed)),
            ("reached", Flag(self.reached)),
            ("collisions", Count(u64::from(self.collisions))),
            ("time_s", Number(self.time_s)),
            ("path_length_m", Number(self.path_length_m)),
            ("optimal_length_m", self.optimal_length_m.into()),
            ("path_ratio", self.path_ratio.into()),
            ("min_clearance_m", Number(self.min_clearance_m)),
            ("steps", Count(u64::from(self.steps))),
            ("stalls", Count(u64::from(self.stalls))),
            ("boundary_follows", Count(u64::from(self.boundary_follows))),
            ("foot_skating_cm_per_frame", self.foot_skating_cm_per_frame.into()),
            ("contact_weight", self.contact_weight.into()),
            ("plants", self.plants.into()),
            ("sliding_plants", self.sliding_plants.into()),
            ("transition_cost", self.transition_cost.into()),
            ("transitions", self.transitions.into()),
            ("peak_switch_jerk_mps3", self.peak_switch_jerk_mps3.into()),
            ("tracking_rms_m", self.tracking_rms_m.into()),
            ("heading_rms_deg", self.heading_rms_deg.into()),
            ("speed_rms_mps", self.speed_rms_mps.into()),
            ("barn_score", self.barn_score.into()),
            ("barn_score_walking", self.barn_score_walking.into()),
            ("invalid_footholds", self.invalid_footholds.map(u64::from).into()),
            ("footsteps_planned", self.footsteps_planned.into()),
            ("footstep_planning_ms_p99", self.footstep_planning_ms_p99.into()),
            ("upper_body_min_clearance_m", self.upper_body_min_clearance_m.into()),
            ("upper_body_collisions", self.upper_body_collisions.map(u64::from).into()),
            ("max_waist_bend_deg", self.max_waist_bend_deg.into()),
            ("max_waist_twist_deg", self.max_waist_twist_deg.into()),
            ("upper_body_refused_steps", self.upper_body_refused_steps.into()),
            ("upper_body_ms_per_frame", self.upper_body_ms_per_frame.into()),
            ("refusal", self.refusal.as_deref().map_or(Field::Missing, Text)),
        ]
    }
}

/// An object of [`EpisodeRecord::fields`]: a missing optimal length or path ratio is `null`,
/// other missing figures (the animation and BARN ones) are left out.
impl Serialize for EpisodeRecord {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let fields = self.fields();
        let mut map = serializer.serialize_map(None)?;
        for (name, f) in fields {
            match f {
                Field::Count(v) => map.serialize_entry(name, &v)?,
                Field::Key(v) => map.serialize_entry(name, &v.to_string())?,
                Field::Number(v) => map.serialize_entry(name, &v)?,
                Field::Flag(v) => map.serialize_entry(name, &v)?,
                Field::Text(v) => map.serialize_entry(name, v)?,
                Field::Missing if matches!(name, "optimal_length_m" | "path_ratio") => {
                    map.serialize_entry(name, &None::<f64>)?
                }
                Field::Missing => {}
            }
        }
        map.end()
    }
}

/// Aggregate figures of a batch.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Number of episodes.
    pub episodes: usize,
    /// Episodes that reached the goal.
    pub reached: usize,
    /// `reached / episodes`.
    pub success_rate: f64,
    /// Median path ratio of reached episodes with a known optimum.
    pub median_path_ratio: Option<f64>,
    /// 90th percentile path ratio, same episodes.
    pub p90_path_ratio: Option<f64>,
    /// Total collisions over all episodes.
    pub collisions: u64,
    /// Smallest clearance over all episodes, metres.
    pub min_clearance_m: f64,
    /// Stalled steps over all steps.
    pub stalled_share: f64,
    /// Animated body: foot skating over all episodes (contact-weighted), cm per frame.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub foot_skating_cm_per_frame: Option<f64>,
    /// Animated body: share of all foot plants that slid less than 2 cm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steady_plant_share: Option<f64>,
    /// Animated body: transitions per simulated second.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub transitions_per_s: Option<f64>,
    /// Worlds with a benchmark reference (BARN): mean BARN metric over their episodes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub barn_score: Option<f64>,
    /// The same with the optimal time at the run's walking speed ([`walking_speed`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub barn_score_walking: Option<f64>,
    /// Uneven terrain: invalid footholds over all episodes (must be 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub invalid_footholds: Option<u64>,
    /// Uneven terrain: the largest episode's 99th percentile of the planning time per step, ms.
    pub footstep_planning_ms_p99: Option<f64>,
}

/// A finished episode with its trail (for pictures).
#[derive(Debug, Clone)]
pub struct Episode {
    /// The measurements.
    pub record: EpisodeRecord,
    /// Agent positions after every step.
    pub trail: Vec<glam::DVec2>,
    /// Every frame the animated character played, when [`StepParameters::record_motion`] is
    /// set (see [`crate::sim::AnimatedBody::motion`]); empty otherwise.
    pub motion: Vec<crate::anim::Pose>,
    /// Seconds the steps took (the optimum and the record left out), when the run lends a
    /// stopwatch ([`StepParameters::stopwatch`]): the figure behind a run's stepping rate.
    pub stepping_s: Option<f64>,
    /// Why the episode failed, in words ([`Simulation::failure`]); `None` for a clean success.
    pub failure: Option<String>,
}

/// Whether a batch works out each episode's reference optimum (`strider run --optimum`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Optimum {
    /// Work it out: `optimal_length_m` and `path_ratio` are filled in.
    #[default]
    On,
    /// Leave it out: both are missing (`null`).
    Off,
}

/// What a batch reports as it runs, from worker threads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Progress {
    /// An episode has taken this many more steps: every [`STEPS_PER_REPORT`] steps, and the
    /// rest when it ends.
    Steps(u64),
    /// An episode has finished.
    Episode,
}

/// Steps an episode takes between two [`Progress::Steps`] reports.
pub const STEPS_PER_REPORT: u32 = 1000;

/// Runs task `task_index` of `scenario` (in `world`, the scenario's world) to completion.
pub fn run_episode(
    scenario: &Scenario,
    world: &World,
    task_index: usize,
    controller: &LayeredController,
    params: &StepParameters,
    episode: usize,
    seed: u64,
) -> Episode {
    let task = scenario.tasks[task_index];
    let optimal = || plan::shortest_path(world, task.start.position, task.goal, params.limits.radius).map(|p| p.length);
    play(scenario, world, task_index, controller, params, episode, seed, optimal, &|_| {})
}

/// Runs task `task_index` of `scenario` in `world`, with `optimal()` the length of the
/// shortest path to the goal point (`None`: none, or not worked out), which runs alongside
/// the steps when a worker thread is free (it depends on neither, so the results do not
/// depend on the thread count). `stepped` hears of the steps taken as [`Progress::Steps`].
#[allow(clippy::too_many_arguments)]
fn play(
    scenario: &Scenario,
    world: &World,
    task_index: usize,
    controller: &LayeredController,
    params: &StepParameters,
    episode: usize,
    seed: u64,
    optimal: impl FnOnce() -> Option<f64> + Send,
    stepped: &(dyn Fn(u64) + Sync),
) -> Episode {
    let task = scenario.tasks[task_index];
    // The episode ends on entering the goal circle, so the optimum does too: the shortest path
    // to the goal point, less the goal radius (its last leg is straight and crosses the circle).
    let (optimal, (sim, stepping_s)) = rayon::join(
        || optimal().map(|length| (length - task.goal_radius).max(0.0)),
        || {
            let mut sim = Simulation::new(world.clone(), params.clone());
            sim.add_agent(task, controller);
            let started = params.stopwatch.as_ref().map(|w| w.0.now_s());
            let mut since = 0;
            while !sim.all_done() {
                sim.step();
                since += 1;
                if since == STEPS_PER_REPORT {
                    stepped(u64::from(since));
                    since = 0;
                }
            }
            let stepping_s = params.stopwatch.as_ref().zip(started).map(|(w, t0)| (w.0.now_s() - t0).max(0.0));
            if since > 0 {
                stepped(u64::from(since));
            }
            (sim, stepping_s)
        },
    );
    let agent = &sim.agents[0];
    let m = agent.metrics;
    let reached = agent.outcome == Some(Outcome::Reached);
    let animated = agent.body.animated();
    let playback = animated.map(|a| a.metrics());
    let tracking = animated.map(|a| a.tracking);
    let footing = animated.and_then(|a| a.footing());
    let upper = animated.and_then(|a| a.upper_body()).map(|u| u.figures());
    let record = EpisodeRecord {
        episode,
        scenario: scenario.name.clone(),
        task: task_index,
        seed,
        reached,
        collisions: m.collisions + upper.map_or(0, |u| u.collisions),
        time_s: on_step(m.time_s, params.dt_s),
        path_length_m: m.path_length_m,
        optimal_length_m: optimal,
        path_ratio: optimal.filter(|o| reached && *o > 0.0).map(|o| m.path_length_m / o),
        min_clearance_m: m.min_clearance_m,
        steps: m.steps,
        stalls: m.stalled_steps,
        boundary_follows: m.follows,
        foot_skating_cm_per_frame: playback.map(|p| p.foot_skating_cm_per_frame()),
        contact_weight: playback.map(|p| p.contact_weight),
        plants: playback.map(|p| p.plants),
        sliding_plants: playback.map(|p| p.sliding_plants),
        transition_cost: playback.map(|p| p.mean_transition_cost()),
        transitions: playback.map(|p| p.transitions),
        peak_switch_jerk_mps3: playback.map(|p| p.peak_switch_jerk),
        tracking_rms_m: tracking.map(|t| t.rms_path_m()),
        heading_rms_deg: tracking.map(|t| t.rms_direction().to_degrees()),
        speed_rms_mps: tracking.map(|t| t.rms_speed()),
        barn_score: scenario.reference.map(|r| r.score(reached, m.time_s, BARN_SPEED_MPS)),
        barn_score_walking: scenario.reference.map(|r| r.score(reached, m.time_s, walking_speed(params))),
        invalid_footholds: footing.map(|f| f.invalid_footholds()),
        footsteps_planned: footing.map(|f| f.plans()),
        footstep_planning_ms_p99: footing.and_then(|f| p99(f.planning_times_s())).map(|s| s * 1e3),
        upper_body_min_clearance_m: upper.map(|u| u.min_clearance_m).filter(|d| d.is_finite()),
        upper_body_collisions: animated.map(|_| upper.map_or(0, |u| u.collisions)),
        max_waist_bend_deg: animated.map(|_| upper.map_or(0.0, |u| u.max_bend_rad.to_degrees())),
        max_waist_twist_deg: animated.map(|_| upper.map_or(0.0, |u| u.max_twist_rad.to_degrees())),
        upper_body_refused_steps: animated.map(|_| upper.map_or(0, |u| u.refused_steps)),
        upper_body_ms_per_frame: upper.and_then(|u| u.planning_s.map(|s| s * 1e3 / u.frames.max(1) as f64)),
        refusal: agent.refusal.clone(),
    };
    let motion = animated.and_then(|a| a.motion()).map_or_else(Vec::new, <[_]>::to_vec);
    Episode { record, trail: agent.trail.clone(), motion, stepping_s, failure: sim.failure(0) }
}

/// A simulated time `t` that is a whole number of steps of `dt` (seconds), as that number
/// times the step: the sum of the steps gathers rounding error in its last digits (16.6 s
/// summed from 0.05 s steps is 16.6000000000001), which records should not show. Rounded to
/// the nanosecond, so any step down to that is kept.
pub fn on_step(t: f64, dt: f64) -> f64 {
    if !(t.is_finite() && dt.is_finite() && dt > 0.0) {
        return t;
    }
    ((t / dt).round() * dt * 1e9).round() / 1e9
}

/// The walking speed of a run, m/s: the top speed the planner commands (the disc's limit,
/// which the character follows too, walking; its database may hold faster gaits it is never
/// asked for).
pub fn walking_speed(params: &StepParameters) -> f64 {
    match &params.animation {
        Some(a) => params.limits.max_speed.min(a.0.db.max_speed()),
        None => params.limits.max_speed,
    }
}

/// One unit of a batch: a scenario, which of its tasks, and the episode seed.
#[derive(Debug, Clone)]
pub struct Job {
    /// The scenario (shared worlds are cheap to clone per job).
    pub scenario: Arc<Scenario>,
    /// Task index.
    pub task: usize,
    /// Episode seed.
    pub seed: u64,
}

/// The seed of episode `i` of a run seeded with `seed` (random worlds are generated from it).
pub fn world_seed(seed: u64, i: usize) -> u64 {
    seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (i as u64)
}

/// Runs `jobs` in parallel (one episode each) and returns records in job order.
/// `progress` is called once per finished episode, from worker threads.
pub fn run_batch(
    jobs: &[Job],
    controller: &LayeredController,
    params: &StepParameters,
    progress: &(dyn Fn() + Sync),
) -> Vec<EpisodeRecord> {
    run_batch_of(jobs.len(), &|i| jobs[i].clone(), controller, params, progress)
}

/// Runs `count` episodes in parallel, episode `i` being `job(i)`, made when the episode starts
/// (so a batch of generated worlds holds only the worlds being run), and returns records in
/// episode order. `progress` is called once per finished episode, from worker threads.
pub fn run_batch_of(
    count: usize,
    job: &(dyn Fn(usize) -> Job + Sync),
    controller: &LayeredController,
    params: &StepParameters,
    progress: &(dyn Fn() + Sync),
) -> Vec<EpisodeRecord> {
    run_batch_each(count, job, controller, params, progress, &|_| {})
}

/// [`run_batch_of`], handing each finished episode (its record, trail and recorded motion) to
/// `each`, from worker threads, before keeping its record.
pub fn run_batch_each(
    count: usize,
    job: &(dyn Fn(usize) -> Job + Sync),
    controller: &LayeredController,
    params: &StepParameters,
    progress: &(dyn Fn() + Sync),
    each: &(dyn Fn(&Episode) + Sync),
) -> Vec<EpisodeRecord> {
    let episodes: Vec<usize> = (0..count).collect();
    let progress = |p: Progress| {
        if p == Progress::Episode {
            progress();
        }
    };
    run_episodes_each(&episodes, job, controller, params, Optimum::On, &progress, each)
}

/// [`run_batch_each`] over some episodes of a batch only (a [`Shard`]'s, say), each numbered
/// as in the whole batch, with the reference optimum or without, reporting each episode's
/// steps and end to `progress`; records come back in the order of `episodes`.
pub fn run_episodes_each(
    episodes: &[usize],
    job: &(dyn Fn(usize) -> Job + Sync),
    controller: &LayeredController,
    params: &StepParameters,
    optimum: Optimum,
    progress: &(dyn Fn(Progress) + Sync),
    each: &(dyn Fn(&Episode) + Sync),
) -> Vec<EpisodeRecord> {
    // A scenario with several tasks is usually run once per task: its world is built once,
    // by the first episode that needs it, and so is its optimal-path planner, and every
    // episode in it shares both (what one episode's search finds of the planner's graph, the
    // next ones use).
    let shared: Mutex<Vec<(Arc<Scenario>, Arc<Shared>)>> = Mutex::new(Vec::new());
    let shared_of = |scenario: &Arc<Scenario>| -> Option<Arc<Shared>> {
        if scenario.tasks.len() < 2 {
            return None;
        }
        let mut list = shared.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, s)) = list.iter().find(|(s, _)| Arc::ptr_eq(s, scenario)) {
            return Some(s.clone());
        }
        let s = Arc::new(Shared::default());
        list.push((scenario.clone(), s.clone()));
        Some(s)
    };
    let stepped = |n: u64| progress(Progress::Steps(n));
    episodes
        .par_iter()
        .map(|&i| {
            let job = job(i);
            let scenario = &job.scenario;
            let mut p = params.clone();
            p.limits.radius = scenario.agent_radius;
            let task = scenario.tasks[job.task];
            let on = optimum == Optimum::On;
            let e = match shared_of(scenario) {
                Some(s) => {
                    let world = s.world.get_or_init(|| scenario.world());
                    let optimal = || {
                        let planner = s.planner.get_or_init(|| plan::Planner::new(world, p.limits.radius));
                        planner.as_ref()?.shortest_path(task.start.position, task.goal).map(|p| p.length)
                    };
                    play(
                        scenario,
                        world,
                        job.task,
                        controller,
                        &p,
                        i,
                        job.seed,
                        || on.then(optimal).flatten(),
                        &stepped,
                    )
                }
                None => {
                    let world = scenario.world();
                    let optimal = || {
                        plan::shortest_path(&world, task.start.position, task.goal, p.limits.radius).map(|p| p.length)
                    };
                    play(
                        scenario,
                        &world,
                        job.task,
                        controller,
                        &p,
                        i,
                        job.seed,
                        || on.then(optimal).flatten(),
                        &stepped,
                    )
                }
            };
            each(&e);
            progress(Progress::Episode);
            e.record
        })
        .collect()
}

/// What the episodes of one scenario share.
#[derive(Default)]
struct Shared {
    world: OnceLock<World>,
    planner: OnceLock<Option<plan::Planner>>,
}

/// The `index`-th of `count` interleaved slices of a batch: episodes `index`, `index + count`,
/// `index + 2·count`, … (`strider run --shard I/N`). Each episode depends only on the run's
/// seed and its own number, so the shards together make the whole batch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which slice, from 0.
    pub index: usize,
    /// How many slices.
    pub count: usize,
}

impl Shard {
    /// The whole batch as one slice.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// A slice, checked: `index < count`.
    pub fn new(index: usize, count: usize) -> Result<Shard, String> {
        if count == 0 || index >= count {
            return Err(format!("a shard I/N needs 0 <= I < N, found {index}/{count}"));
        }
        Ok(Shard { index, count })
    }

    /// The episodes of a batch of `total` that fall in this slice, in order.
    pub fn episodes(self, total: usize) -> Vec<usize> {
        (self.index..total).step_by(self.count).collect()
    }
}

impl std::str::FromStr for Shard {
    type Err = String;

    /// `I/N`, e.g. `0/4` for the first of four slices.
    fn from_str(s: &str) -> Result<Shard, String> {
        let parse =
            |t: &str| t.trim().parse::<usize>().map_err(|_| format!("expected a shard I/N such as 0/4, found '{s}'"));
        let (i, n) = s.split_once('/').ok_or_else(|| format!("expected a shard I/N such as 0/4, found '{s}'"))?;
        Shard::new(parse(i)?, parse(n)?)
    }
}

/// The 99th percentile of `xs` (nearest rank), `None` when empty.
pub fn p99(xs: &[f64]) -> Option<f64> {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let rank = ((v.len() as f64 * 0.99).ceil() as usize).max(1);
    v.get(rank - 1).copied()
}

fn mean(xs: impl Iterator<Item = f64>) -> Option<f64> {
    let (sum, n) = xs.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    (n > 0).then(|| sum / n as f64)
}

/// Aggregates records.
pub fn summarize(records: &[EpisodeRecord]) -> Summary {
    let reached = records.iter().filter(|r| r.reached).count();
    let mut ratios: Vec<f64> = records.iter().filter_map(|r| r.path_ratio).collect();
    ratios.sort_by(f64::total_cmp);
    let quantile = |q: f64| -> Option<f64> {
        if ratios.is_empty() {
            None
        } else {
            let i = ((ratios.len() - 1) as f64 * q).round() as usize;
            Some(ratios[i])
        }
    };
    Summary {
        episodes: records.len(),
        reached,
        success_rate: if records.is_empty() { 0.0 } else { reached as f64 / records.len() as f64 },
        median_path_ratio: quantile(0.5),
        p90_path_ratio: quantile(0.9),
        collisions: records.iter().map(|r| u64::from(r.collisions)).sum(),
        min_clearance_m: records.iter().map(|r| r.min_clearance_m).fold(f64::INFINITY, f64::min),
        // Summed from +0, so that no episodes share 0, not -0 (f64's `sum` starts at -0).
        stalled_share: records.iter().map(|r| f64::from(r.stalls)).fold(0.0, |a, b| a + b)
            / records.iter().map(|r| f64::from(r.steps)).sum::<f64>().max(1.0),
        foot_skating_cm_per_frame: {
            let (s, w) =
                records.iter().fold((0.0, 0.0), |(s, w), r| match (r.foot_skating_cm_per_frame, r.contact_weight) {
                    (Some(k), Some(c)) => (s + k * c, w + c),
                    _ => (s, w),
                });
            (w > 0.0).then(|| s / w)
        },
        steady_plant_share: {
            let (p, slid) = records
                .iter()
                .fold((0u64, 0u64), |(p, s), r| (p + r.plants.unwrap_or(0), s + r.sliding_plants.unwrap_or(0)));
            (p > 0).then(|| 1.0 - slid as f64 / p as f64)
        },
        barn_score: mean(records.iter().filter_map(|r| r.barn_score)),
        barn_score_walking: mean(records.iter().filter_map(|r| r.barn_score_walking)),
        invalid_footholds: records.iter().filter_map(|r| r.invalid_footholds).map(u64::from).reduce(|a, b| a + b),
        footstep_planning_ms_p99: records.iter().filter_map(|r| r.footstep_planning_ms_p99).reduce(f64::max),
        transitions_per_s: {
            let n: u64 = records.iter().filter_map(|r| r.transitions).sum();
            let t: f64 = records.iter().filter(|r| r.transitions.is_some()).map(|r| r.time_s).sum();
            (t > 0.0).then(|| n as f64 / t)
        },
    }
}

#[cfg(test)]
mod tests {
    use super::on_step;

    #[test]
    fn times_are_whole_steps() {
        let mut t = 0.0;
        for _ in 0..332 {
            t += 0.05;
        }
        assert_ne!(t, 16.6);
        assert_eq!(on_step(t, 0.05), 16.6);
        assert_eq!(on_step(0.0, 0.05), 0.0);
        assert_eq!(on_step(63.24999999999854, 0.05), 63.25);
        assert_eq!(on_step(1.0 / 3.0, 1.0 / 3.0), 0.333333333);
    }
}
