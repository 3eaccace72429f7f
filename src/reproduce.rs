//! Seed 000 §4, Table 1, reproduced and extended: the fuzzy + RL planner against the pure-RL
//! planner of [`crate::baseline`] in the three environments of Fig 2.
//!
//! For each environment the pure-RL planner is trained on random starts and goals in that one
//! world until it reaches [`Table1Options::target_success`] on held-out starts and goals in the
//! same world (or runs out of [`Table1Options::max_episodes`]); then both planners are scored
//! on those held-out tasks and on unseen random worlds of the same density. The fuzzy + RL
//! planner uses one policy for every environment, trained once (its training is timed too).
//! Held-out tasks, training tasks and unseen worlds come from separate random streams of the
//! seed, so every figure but the seconds is the same on every run.

use std::sync::Arc;
use std::time::Instant;

use glam::DVec2;
use rayon::prelude::*;
use serde::Serialize;

use crate::anim::Database;
use crate::anim::policy::{LearnParams, Policy, StateGrid};
use crate::baseline::{Ending, PureRl, PureRlParams};
use crate::experiment;
use crate::maps::generate::Density;
use crate::maps::kind::{self, WorldKind};
use crate::scenario::Scenario;
use crate::sim::{Animation, AnimationHandle, LayeredController, StepParameters};
use crate::world::{Pose, Task, World};

/// One environment of the experiment.
#[derive(Debug, Clone)]
pub struct Environment {
    /// Name shown in the table.
    pub name: String,
    /// The world (its obstacles).
    pub scenario: Arc<Scenario>,
    /// The density its unseen worlds are drawn at.
    pub density: Density,
    /// Obstacles in the pure-RL state.
    pub obstacles: usize,
}

/// Knobs of the experiment.
#[derive(Debug, Clone, Copy)]
pub struct Table1Options {
    /// Seed of every stream.
    pub seed: u64,
    /// Held-out tasks per environment.
    pub held_out: usize,
    /// Unseen worlds per environment.
    pub unseen: usize,
    /// Pure-RL episodes between two evaluations.
    pub round: u64,
    /// Pure-RL training stops at this held-out success rate.
    pub target_success: f64,
    /// Most pure-RL training episodes per environment.
    pub max_episodes: u64,
    /// Episodes the fuzzy + RL policy is trained for (once).
    pub fuzzy_episodes: u64,
}

impl Default for Table1Options {
    fn default() -> Self {
        Table1Options {
            seed: 1,
            held_out: 100,
            unseen: 50,
            round: 5_000,
            target_success: 0.9,
            max_episodes: 300_000,
            fuzzy_episodes: 1_000_000,
        }
    }
}

/// One planner's figures in one environment.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct PlannerFigures {
    /// Parameters of its state.
    pub state_parameters: usize,
    /// Entries of a dense table over its state and actions.
    pub table_entries: f64,
    /// Entries it actually stores (visited).
    pub stored_entries: usize,
    /// Training episodes.
    pub training_episodes: u64,
    /// Training time, seconds (for the fuzzy + RL planner: its one training, shared).
    pub training_s: f64,
    /// Success on held-out starts and goals in the training world.
    pub success_rate: f64,
    /// Success on unseen random worlds of the same density.
    pub success_rate_unseen: f64,
    /// Collisions over those episodes.
    pub collisions: usize,
}

/// One row of the table.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct EnvironmentFigures {
    /// Environment name.
    pub name: String,
    /// The pure-RL baseline, trained in this environment.
    pub pure_rl: PlannerFigures,
    /// The fuzzy + RL planner (one policy for all).
    pub fuzzy_rl: PlannerFigures,
}

/// The whole table.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Table1 {
    /// Rows, in the order given.
    pub environments: Vec<EnvironmentFigures>,
}

/// The three environments of Fig 2, as shipped in `maps/`.
pub fn fig2_environments() -> Result<Vec<Environment>, String> {
    let maps = [
        ("sparse", include_str!("../maps/sparse.rhai"), "maps/sparse.rhai", Density::Sparse),
        ("semi_cluttered", include_str!("../maps/semi_cluttered.rhai"), "maps/semi_cluttered.rhai", Density::Semi),
        ("cluttered", include_str!("../maps/cluttered.rhai"), "maps/cluttered.rhai", Density::Cluttered),
    ];
    maps.into_iter()
        .map(|(name, text, file, density)| {
            let log = crate::script::ScriptLog::new();
            let scenario = crate::script::load_scenario(text, file, crate::script::Limits::default(), &log)
                .map_err(|e| e.to_string())?;
            Ok(Environment {
                name: name.to_string(),
                scenario: Arc::new(scenario),
                density,
                obstacles: PureRlParams::for_density(density).obstacles,
            })
        })
        .collect()
}

/// A random task in `world` inside `area`: start and goal free for a disc of `radius` with
/// 0.2 m to spare, at least 4 m apart, the start facing a random way.
pub fn random_task(world: &World, area: (DVec2, DVec2), radius: f64, seed: u64, index: u64, stream: u64) -> Task {
    let mut rng = crate::rng::stream(seed, index, stream);
    let mut scratch = Vec::new();
    let mut point = |rng: &mut rand_chacha::ChaCha8Rng| loop {
        let p = DVec2::new(crate::rng::uniform(rng, area.0.x, area.1.x), crate::rng::uniform(rng, area.0.y, area.1.y));
        if world.is_free(p, radius + 0.2, &mut scratch) {
            return p;
        }
    };
    loop {
        let start = point(&mut rng);
        let goal = point(&mut rng);
        if start.distance(goal) >= 4.0 {
            let yaw = crate::rng::uniform(&mut rng, -std::f64::consts::PI, std::f64::consts::PI);
            return Task::new(Pose { position: start, yaw }, goal);
        }
    }
}

/// The area tasks are drawn from: the world's bounds, or the scenario's own start and goal
/// box when it has no obstacles.
fn area_of(scenario: &Scenario, world: &World) -> (DVec2, DVec2) {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for t in &scenario.tasks {
        for p in [t.start.position, t.goal] {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    if let Some(b) = world.bounds() {
        lo = lo.min(b.min);
        hi = hi.max(b.max);
    }
    (lo, hi)
}

/// What [`run`] reports while it works.
pub trait Report: Sync {
    /// A phase started (`what`), in environment `env`.
    fn phase(&self, env: &str, what: &str);
    /// Pure-RL training in `env` reached `episodes` with held-out success `success`.
    fn round(&self, env: &str, episodes: u64, success: f64);
}

/// Runs the whole experiment; the fuzzy + RL planner navigates with `controller`.
pub fn run(
    db: &Database,
    controller: &LayeredController,
    environments: &[Environment],
    options: Table1Options,
    report: &dyn Report,
) -> Table1 {
    // The fuzzy + RL planner: one policy, trained once.
    report.phase("all", "training the fuzzy + RL policy once");
    let clock = Instant::now();
    let mut policy = Policy::new(db, StateGrid::default(), LearnParams::default(), options.seed);
    policy.train(db, options.fuzzy_episodes, u64::MAX, &mut |_| {}, &mut |_| {});
    let fuzzy_training_s = clock.elapsed().as_secs_f64();
    let fuzzy_entries = (policy.states() * db.candidates.iter().map(Vec::len).max().unwrap_or(0)) as f64;
    let fuzzy_stored = policy.visited_states();
    let fuzzy_episodes = policy.episodes;
    let animation = AnimationHandle(Arc::new(Animation::new(db.clone(), policy)));
    let params = StepParameters { animation: Some(animation), ..StepParameters::default() };

    let rows: Vec<EnvironmentFigures> = environments
        .par_iter()
        .map(|env| {
            let world = env.scenario.world();
            let radius = env.scenario.agent_radius;
            let area = area_of(&env.scenario, &world);
            let held_out: Vec<Task> =
                (0..options.held_out as u64).map(|i| random_task(&world, area, radius, options.seed, i, 2)).collect();
            let unseen_kind = WorldKind::from(env.density);
            let unseen: Vec<Arc<Scenario>> = (0..options.unseen)
                .map(|i| Arc::new(kind::generate(unseen_kind, experiment::world_seed(options.seed ^ 0x7ab1e, i))))
                .collect();

            // The pure-RL planner, trained here until it succeeds on the held-out tasks.
            report.phase(&env.name, "training the pure-RL planner");
            let rl_params = PureRlParams { obstacles: env.obstacles, radius, ..PureRlParams::default() };
            let mut rl = PureRl::new(rl_params);
            let clock = Instant::now();
            let (mut success, mut own_collisions) = (0.0, 0);
            while rl.episodes < options.max_episodes {
                let end = (rl.episodes + options.round).min(options.max_episodes);
                while rl.episodes < end {
                    let task = random_task(&world, area, radius, options.seed, rl.episodes, 1);
                    let index = rl.episodes;
                    rl.episode(db, &world, &task, true, options.seed, index);
                }
                (success, own_collisions) = score(&mut rl, db, &world, &held_out, options.seed);
                report.round(&env.name, rl.episodes, success);
                if success >= options.target_success {
                    break;
                }
            }
            let training_s = clock.elapsed().as_secs_f64();
            let mut unseen_reached = 0;
            let mut unseen_collisions = 0;
            for s in &unseen {
                let w = s.world();
                let (r, c) = score(&mut rl, db, &w, &s.tasks, options.seed);
                unseen_reached += usize::from(r >= 1.0);
                unseen_collisions += c;
            }
            let pure_rl = PlannerFigures {
                state_parameters: rl_params.state_parameters(),
                table_entries: rl_params.state_cells(db.intervals.len())
                    * db.candidates.iter().map(Vec::len).max().unwrap_or(0) as f64,
                stored_entries: rl.stored_entries(),
                training_episodes: rl.episodes,
                training_s,
                success_rate: success,
                success_rate_unseen: unseen_reached as f64 / unseen.len().max(1) as f64,
                collisions: own_collisions + unseen_collisions,
            };

            // The fuzzy + RL planner on the same tasks, in the real simulation.
            report.phase(&env.name, "scoring the fuzzy + RL planner");
            let mut own = (*env.scenario).clone();
            own.tasks = held_out.clone();
            let own = Arc::new(own);
            let jobs: Vec<experiment::Job> = (0..held_out.len())
                .map(|t| experiment::Job { scenario: own.clone(), task: t, seed: options.seed })
                .chain(unseen.iter().map(|s| experiment::Job { scenario: s.clone(), task: 0, seed: options.seed }))
                .collect();
            let records = experiment::run_batch(&jobs, controller, &params, &|| {});
            let (mine, others) = records.split_at(held_out.len());
            let rate =
                |r: &[experiment::EpisodeRecord]| r.iter().filter(|e| e.reached).count() as f64 / r.len().max(1) as f64;
            let fuzzy_rl = PlannerFigures {
                state_parameters: 3,
                table_entries: fuzzy_entries,
                stored_entries: fuzzy_stored,
                training_episodes: fuzzy_episodes,
                training_s: fuzzy_training_s,
                success_rate: rate(mine),
                success_rate_unseen: rate(others),
                collisions: records.iter().map(|e| e.collisions as usize).sum(),
            };
            EnvironmentFigures { name: env.name.clone(), pure_rl, fuzzy_rl }
        })
        .collect();
    Table1 { environments: rows }
}

/// Greedy success rate of `rl` on `tasks` in `world`, and the collisions.
fn score(rl: &mut PureRl, db: &Database, world: &World, tasks: &[Task], seed: u64) -> (f64, usize) {
    let mut reached = 0;
    let mut collisions = 0;
    for (i, task) in tasks.iter().enumerate() {
        match rl.episode(db, world, task, false, seed, i as u64).0 {
            Ending::Reached => reached += 1,
            Ending::Collided => collisions += 1,
            Ending::TimedOut => {}
        }
    }
    (reached as f64 / tasks.len().max(1) as f64, collisions)
}

impl Table1 {
    /// The table as text, one block per environment.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        out.push_str(
            "environment      planner    state  table entries    stored  train episodes  train s  success  unseen  collisions\n",
        );
        for e in &self.environments {
            for (name, p) in [("pure RL", &e.pure_rl), ("fuzzy+RL", &e.fuzzy_rl)] {
                out.push_str(&format!(
                    "{:<16} {:<9} {:>6} {:>14.3e} {:>9} {:>15} {:>8.1} {:>7.1}% {:>6.1}% {:>11}\n",
                    e.name,
                    name,
                    p.state_parameters,
                    p.table_entries,
                    p.stored_entries,
                    p.training_episodes,
                    p.training_s,
                    100.0 * p.success_rate,
                    100.0 * p.success_rate_unseen,
                    p.collisions
                ));
            }
        }
        out
    }
}
