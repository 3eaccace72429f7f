//! The animation controller's MDP (seed 000 §3.2) for `strider/AnimationControl-v0`: at each
//! switch point the next interval is chosen among the candidates the SARSA policy ranks; the
//! state is what that policy sees (interval, speed error, direction error), the transitions
//! are the policy's deterministic model (each candidate warped as playback warps it) and the
//! reward is Eq. 4. Commanded tasks are sampled and changed as in training.

use std::path::PathBuf;

use pyo3::prelude::*;
use rand_chacha::ChaCha8Rng;

use strider::anim::policy::{self, Errors, Task};
use strider::load::{BodyArgs, BodyKind, load_animation};
use strider::rng;
use strider::sim::AnimationHandle;

use crate::{StriderError, error};

/// Random stream of the MDP's episodes (apart from training's and evaluation's).
const MDP_STREAM: u64 = 0x3d9_6e17;

/// The animation MDP over a database and its trained policy.
#[pyclass(module = "strider._strider")]
pub struct AnimationMdp {
    animation: AnimationHandle,
    rng: ChaCha8Rng,
    interval: usize,
    errors: Errors,
    task: Task,
}

impl AnimationMdp {
    fn actions(&self) -> usize {
        self.animation.0.db.policy_actions[self.interval]
    }
}

#[pymethods]
impl AnimationMdp {
    /// The MDP of the animation database `db` (default: built in) and its `policy` (default:
    /// the shipped one).
    #[new]
    #[pyo3(signature = (db=None, policy=None))]
    fn new(py: Python<'_>, db: Option<PathBuf>, policy: Option<PathBuf>) -> PyResult<Self> {
        let args = BodyArgs { body: BodyKind::Animated, db, policy, ..BodyArgs::default() };
        let animation = py
            .detach(|| load_animation(&args))
            .map_err(error(py))?
            .ok_or_else(|| StriderError::new_err("no animation for this body"))?;
        let mut mdp = AnimationMdp {
            animation,
            rng: rng::stream(0, 0, MDP_STREAM),
            interval: 0,
            errors: Errors::default(),
            task: Task::default(),
        };
        mdp.reset(0);
        Ok(mdp)
    }

    /// Starts an episode seeded with `seed`: a sampled task, a random interval playing, and
    /// half the time a random direction error (as training starts its episodes).
    fn reset(&mut self, seed: u64) {
        let a = &self.animation.0;
        let n = a.db.intervals.len();
        self.rng = rng::stream(seed, 0, MDP_STREAM);
        self.task = policy::sample_task(&a.db, &a.policy.params, &mut self.rng);
        self.interval = ((rng::unit(&mut self.rng) * n as f64) as usize).min(n - 1);
        let turned = rng::unit(&mut self.rng) < 0.5;
        let direction =
            if turned { rng::uniform(&mut self.rng, -std::f64::consts::PI, std::f64::consts::PI) } else { 0.0 };
        self.errors = Errors { speed: self.task.speed - a.db.intervals[self.interval].speed, direction };
    }

    /// Plays candidate `action` of the interval playing; an action past the candidates the
    /// policy ranks (see `action_mask`) plays the natural successor (candidate 0). Returns the
    /// reward of Eq. 4 and whether the action was masked. The task changes afterwards with
    /// the training's probability.
    fn step(&mut self, action: usize) -> (f64, bool) {
        let masked = action >= self.actions();
        let a = if masked { 0 } else { action };
        let anim = &self.animation.0;
        let (db, p) = (&anim.db, &anim.policy.params);
        let (reward, next) = policy::reward(db, p, self.interval, a, self.errors.direction, self.task);
        self.errors = next;
        self.interval = db.candidates[self.interval][a].interval;
        if rng::unit(&mut self.rng) < p.task_change {
            // The interval playing keeps the speed its warp gave it.
            let played = self.task.speed - self.errors.speed;
            self.task = policy::sample_task(db, p, &mut self.rng);
            self.errors.speed = self.task.speed - played;
            if self.task.turn_rate == 0.0 {
                self.errors.direction = rng::uniform(&mut self.rng, -std::f64::consts::PI, std::f64::consts::PI);
            }
        }
        (reward, masked)
    }

    /// The state the SARSA policy sees: (interval, speed error m/s, direction error rad).
    fn state(&self) -> (usize, f64, f64) {
        (self.interval, self.errors.speed, self.errors.direction)
    }

    /// The commanded task: (turn rate rad/s, speed m/s).
    fn task(&self) -> (f64, f64) {
        (self.task.turn_rate, self.task.speed)
    }

    /// Which of the `max_actions` actions are candidates the policy ranks after the interval
    /// playing.
    fn action_mask(&self) -> Vec<bool> {
        let n = self.actions();
        (0..self.max_actions()).map(|a| a < n).collect()
    }

    /// The action strider's trained SARSA policy takes in this state.
    fn sarsa_action(&self) -> usize {
        self.animation.0.policy.choose(self.interval, self.errors)
    }

    /// Number of intervals in the database.
    #[getter]
    fn intervals(&self) -> usize {
        self.animation.0.db.intervals.len()
    }

    /// The most candidates any interval has (the size of the action space).
    #[getter]
    fn max_actions(&self) -> usize {
        self.animation.0.db.policy_actions.iter().copied().max().unwrap_or(1).max(1)
    }

    /// Intervals per training episode.
    #[getter]
    fn episode_length(&self) -> usize {
        self.animation.0.policy.params.episode_length
    }

    /// A bound on the speed error's magnitude, m/s: the top commanded speed plus the top
    /// speed of an interval warped its most (1.25×), with room to spare.
    #[getter]
    fn speed_bound(&self) -> f64 {
        let a = &self.animation.0;
        let top_interval = a.db.intervals.iter().map(|i| i.speed).fold(0.0, f64::max);
        a.db.max_speed().max(a.policy.params.planner_speed) + 1.5 * top_interval
    }
}
