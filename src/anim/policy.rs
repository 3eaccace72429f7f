//! The RL animation controller's policy (seed 000 §3.2.2–3.2.3; DESIGN.md §3): an MDP whose
//! state is (interval now ending, speed error, direction error), whose actions are the
//! candidates at that switch point (natural successor, its K neighbours, and the stop and
//! turns on the spot the database adds), with deterministic transitions, the reward of Eq. 4
//! and the update of Eq. 5, learned from (turn, speed) tasks sampled over the fuzzy planner's
//! output ranges — once, for every environment.
//!
//! The continuous errors are sampled on a grid per interval table (speed error every 0.25 m/s,
//! direction error every 10°). Learning follows sampled episodes one after another: at each
//! visited state every candidate's value is updated by Eq. 5 from the deterministic model (a
//! full backup: the candidate's reward and the discounted best value of the state it leads to),
//! then an ε-greedy choice moves the episode on. Values are shared between a state and its
//! left–right mirror (the mirror interval, the negated direction error, the mirrored
//! candidate), so the policy turns left exactly as it turns right. At run time the agent's
//! state is matched to the nearest sampled state that learning visited, in the table of the
//! interval now playing, and candidates are ranked by value; the caller takes the best one it
//! may (the animated body skips candidates whose path is not clear).
//!
//! Baselines for comparison ([`Strategy`]): the natural successor only, a random candidate,
//! and the one-step greedy rule (the best `α·w + β·T` now). [`evaluate`] scores any of them on
//! held-out tasks by the discounted return of Eq. 4–5 and by task success.
//!
//! Training is sequential and depends only on the seed and the number of episodes: a run
//! resumed from a checkpoint continues exactly as if it had not stopped.

use rand_chacha::ChaCha8Rng;

use super::db::{Database, Fnv};
use super::warp::{Warp, WarpLimits};
use crate::geom::wrap_angle;
use crate::rng;

/// Episodes between progress reports of [`Policy::train`].
pub const ROUND: u64 = 4096;

/// Where the continuous state parameters are sampled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateGrid {
    /// Samples of the speed error (odd, so 0 is one of them) (13).
    pub speed_cells: usize,
    /// Speed errors span `[-speed_range, speed_range]`, metres per second (1.5).
    pub speed_range: f64,
    /// Samples of the direction error over `[-π, π)`, even so that mirrored errors are samples
    /// too (36, every 10°).
    pub direction_cells: usize,
}

impl Default for StateGrid {
    fn default() -> Self {
        StateGrid { speed_cells: 13, speed_range: 1.5, direction_cells: 36 }
    }
}

impl StateGrid {
    /// Number of sampled states per interval.
    pub fn cells(&self) -> usize {
        self.speed_cells * self.direction_cells
    }

    /// The sampled state nearest to the errors.
    pub fn cell(&self, speed_error: f64, direction_error: f64) -> usize {
        let sv = if self.speed_cells > 1 {
            let step = 2.0 * self.speed_range / (self.speed_cells - 1) as f64;
            let x = if speed_error.is_finite() { speed_error } else { 0.0 };
            ((x + self.speed_range) / step).round().clamp(0.0, (self.speed_cells - 1) as f64) as usize
        } else {
            0
        };
        let d = if direction_error.is_finite() { wrap_angle(direction_error) } else { 0.0 };
        let step = std::f64::consts::TAU / self.direction_cells as f64;
        let sd = ((d + std::f64::consts::PI) / step).round() as usize % self.direction_cells;
        sv * self.direction_cells + sd
    }

    /// The errors at a sampled state.
    pub fn value(&self, cell: usize) -> (f64, f64) {
        let (sv, sd) = (cell / self.direction_cells, cell % self.direction_cells);
        let v = if self.speed_cells > 1 {
            -self.speed_range + 2.0 * self.speed_range * sv as f64 / (self.speed_cells - 1) as f64
        } else {
            0.0
        };
        (v, -std::f64::consts::PI + std::f64::consts::TAU * sd as f64 / self.direction_cells as f64)
    }

    /// The sampled state with the same speed error and the negated direction error.
    pub fn mirror(&self, cell: usize) -> usize {
        let (sv, sd) = (cell / self.direction_cells, cell % self.direction_cells);
        sv * self.direction_cells + (self.direction_cells - sd) % self.direction_cells
    }

    /// Distance between two sampled states (speed error in units of `scale` m/s per radian).
    fn distance(&self, a: usize, b: usize, scale: f64) -> f64 {
        let (va, da) = self.value(a);
        let (vb, db) = self.value(b);
        ((va - vb) / scale).powi(2) + wrap_angle(da - db).powi(2)
    }
}

/// Learning parameters. Every field documents its default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LearnParams {
    /// α of Eq. 4, weight of the neighbour similarity `w_a` (0.15).
    pub alpha: f64,
    /// β of Eq. 4, weight of the task score `T(s')` (1).
    pub beta: f64,
    /// λ of Eq. 5, learning rate (0.5); it decays per sampled state with its updates, halving
    /// after 20 and never below a tenth.
    pub learning_rate: f64,
    /// γ of Eq. 5, discount (0.8).
    pub discount: f64,
    /// ε-greedy exploration: probability of a random action (0.3).
    pub exploration: f64,
    /// Intervals played per episode (24).
    pub episode_length: usize,
    /// Probability per interval that the commanded task changes (0.15).
    pub task_change: f64,
    /// Velocity error scale of `T`, m/s (1.5).
    pub speed_tolerance: f64,
    /// Direction error scale of `T`, radians (π).
    pub direction_tolerance: f64,
    /// Share of `T` that scores the direction error alone; the rest scores the velocity error
    /// (0.3).
    pub heading_weight: f64,
    /// Top commanded speed of the planner, m/s (1.5).
    pub planner_speed: f64,
    /// Top commanded turn rate of the planner, rad/s (2.09, 120°/s).
    pub planner_turn: f64,
    /// Share of tasks sampled over the whole database's speed range instead (user control) (0.25).
    pub wide_tasks: f64,
    /// How far each interval may be warped toward the command ([`WarpLimits::default`]); the
    /// model and playback warp alike.
    pub warp: WarpLimits,
}

/// Share of tasks that command a heading change (a direction error, no turn rate) rather than
/// a turn rate.
const HEADING_TASKS: f64 = 0.5;
/// Updates of a sampled state after which its learning rate has halved.
const RATE_HALVING_VISITS: f64 = 20.0;
/// Smallest learning rate, as a share of λ.
const RATE_FLOOR: f64 = 0.1;
/// Random stream of training episodes.
const TRAIN_STREAM: u64 = 0x5a25a;
/// Random stream of held-out evaluation tasks (never used in training).
const HELD_OUT_STREAM: u64 = 0x4e1d_0007;

impl Default for LearnParams {
    fn default() -> Self {
        LearnParams {
            alpha: 0.15,
            beta: 1.0,
            learning_rate: 0.5,
            discount: 0.8,
            exploration: 0.3,
            episode_length: 24,
            task_change: 0.15,
            speed_tolerance: 1.5,
            direction_tolerance: std::f64::consts::PI,
            heading_weight: 0.3,
            planner_speed: 1.5,
            planner_turn: 120f64.to_radians(),
            wide_tasks: 0.25,
            warp: WarpLimits::default(),
        }
    }
}

/// A commanded task: turn rate (rad/s, positive left) and speed (m/s).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Task {
    /// Turn rate, radians per second.
    pub turn_rate: f64,
    /// Speed, metres per second.
    pub speed: f64,
}

/// The continuous part of the state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Errors {
    /// Commanded speed minus the speed of the interval playing, m/s.
    pub speed: f64,
    /// Desired heading minus heading, radians in `[-π, π]`.
    pub direction: f64,
}

/// The deterministic transition: the warp interval `a` plays with under `task`, starting with
/// direction error `direction` (toward the desired heading at its end, within `limits`), and
/// the errors after it.
pub fn transition(db: &Database, a: usize, direction: f64, task: Task, limits: &WarpLimits) -> (Warp, Errors) {
    let iv = &db.intervals[a];
    let wanted = direction + task.turn_rate * iv.duration;
    let warp = Warp::toward(iv, db.kinds[a], wanted, task.speed, limits);
    let errors = Errors {
        speed: task.speed - warp.speed(iv),
        direction: (wanted - warp.turn(iv)).clamp(-std::f64::consts::PI, std::f64::consts::PI),
    };
    (warp, errors)
}

/// How well the motion after an interval meets the command, `T` in `[0, 1]`: 1 with no error.
/// The commanded velocity (speed `speed + e.speed` along the desired heading) is compared with
/// the velocity of the interval played (its speed `speed` along the heading, `e.direction`
/// away): their difference, over [`LearnParams::speed_tolerance`], takes
/// `1 − heading_weight` of the score, so that walking briskly the wrong way scores worse than
/// turning first; the direction error alone, over [`LearnParams::direction_tolerance`], takes
/// the rest, so that turning on the spot still counts when the command is to stand and turn.
pub fn task_score(e: Errors, speed: f64, p: &LearnParams) -> f64 {
    let wanted = (speed + e.speed).max(0.0);
    let (s, c) = e.direction.sin_cos();
    let velocity = (wanted - speed * c).hypot(speed * s);
    1.0 - (1.0 - p.heading_weight) * (velocity / p.speed_tolerance).min(1.0)
        - p.heading_weight * (e.direction.abs() / p.direction_tolerance).min(1.0)
}

/// The reward of Eq. 4 for taking candidate `a` after interval `i` with direction error
/// `direction` under `task`, and the errors it leads to.
pub fn reward(db: &Database, p: &LearnParams, i: usize, a: usize, direction: f64, task: Task) -> (f64, Errors) {
    let c = &db.candidates[i][a];
    let (warp, next) = transition(db, c.interval, direction, task, &p.warp);
    (p.alpha * c.weight + p.beta * task_score(next, warp.speed(&db.intervals[c.interval]), p), next)
}

/// How the next interval is picked at a switch point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Strategy {
    /// The learnt policy: the best value in the nearest visited sampled state.
    #[default]
    Learnt,
    /// One-step greedy: the best `α·w + β·T` of the next interval.
    Greedy,
    /// A random candidate.
    Random,
    /// Always the natural successor (then the neighbours, nearest first).
    Successor,
}

impl Strategy {
    /// All strategies, the learnt policy first.
    pub const ALL: [Strategy; 4] = [Strategy::Learnt, Strategy::Greedy, Strategy::Random, Strategy::Successor];

    /// Name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::Learnt => "learnt",
            Strategy::Greedy => "greedy",
            Strategy::Random => "random",
            Strategy::Successor => "successor",
        }
    }
}

/// Why a policy file cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolicyError {
    /// Not a policy file.
    #[error("not a strider policy file (bad magic bytes)")]
    Magic,
    /// Written by another format version.
    #[error("policy file format version {0} is not supported (this build reads version {FORMAT_VERSION})")]
    Version(u32),
    /// Ends early.
    #[error("policy file is truncated")]
    Truncated,
    /// Checksum mismatch.
    #[error("policy file is corrupt (checksum mismatch)")]
    Checksum,
    /// Trained on another database.
    #[error(
        "policy was trained on another animation database (fingerprint {found:016x}, this database {expected:016x}); train it again"
    )]
    Mismatch {
        /// This database's fingerprint.
        expected: u64,
        /// The file's.
        found: u64,
    },
    /// Fields out of range.
    #[error("policy file is malformed: {0}")]
    Malformed(&'static str),
}

/// File format version written by [`Policy::to_bytes`].
pub const FORMAT_VERSION: u32 = 4;

/// Most training episodes a policy may count (about 10¹²: years of training at the rates
/// `strider train` reaches).
pub const MAX_EPISODES: u64 = 1 << 40;

/// Longest training episode a policy file may ask for, intervals (ten times the default).
pub const MAX_EPISODE_LENGTH: usize = 256;
const MAGIC: &[u8; 8] = b"STRDRPOL";

/// How the sampled states of a database map onto stored values: a state and its mirror share
/// one entry (the canonical one, the smaller of the two by interval then cell).
#[derive(Debug, Clone, PartialEq)]
struct Layout {
    cells: usize,
    /// Per interval × cell: the stored state, and whether it is reached through the mirror.
    slot: Vec<(u32, bool)>,
    /// Per stored state: its interval and cell.
    states: Vec<(u32, u32)>,
    /// Per stored state: where its action values start.
    offsets: Vec<u32>,
    /// Candidates per interval.
    actions: Vec<usize>,
    /// Per interval with a mirror: the mirror's candidate index of each candidate.
    perm: Vec<Vec<u16>>,
    /// Mirror of each interval, where values are shared.
    mirror: Vec<Option<usize>>,
    values: usize,
}

impl Layout {
    fn new(db: &Database, grid: &StateGrid) -> Layout {
        let n = db.intervals.len();
        let cells = grid.cells();
        let actions: Vec<usize> = db.policy_actions.clone();
        let mirror: Vec<Option<usize>> = (0..n)
            .map(|i| {
                db.mirror[i].filter(|&m| {
                    !db.mirror_candidate[i].is_empty() && !db.mirror_candidate[m].is_empty() && actions[m] == actions[i]
                })
            })
            .collect();
        let perm: Vec<Vec<u16>> = (0..n)
            .map(|i| {
                if mirror[i].is_some() {
                    db.mirror_candidate[i].iter().map(|&a| a as u16).collect()
                } else {
                    Vec::new()
                }
            })
            .collect();
        let mut slot = vec![(u32::MAX, false); n * cells];
        let mut states = Vec::new();
        let mut offsets = Vec::new();
        let mut total = 0usize;
        for i in 0..n {
            for c in 0..cells {
                let twin = mirror[i].map(|m| (m, grid.mirror(c)));
                match twin {
                    Some(t) if t < (i, c) => {
                        let (k, _) = slot[t.0 * cells + t.1];
                        slot[i * cells + c] = (k, true);
                    }
                    _ => {
                        slot[i * cells + c] = (states.len() as u32, false);
                        states.push((i as u32, c as u32));
                        offsets.push(total as u32);
                        total += actions[i];
                    }
                }
            }
        }
        Layout { cells, slot, states, offsets, actions, perm, mirror, values: total }
    }

    /// The stored state of interval `i`'s sampled state `c`, and the stored index of each of
    /// its actions.
    fn state(&self, i: usize, c: usize) -> (usize, bool) {
        let (k, m) = self.slot[i * self.cells + c];
        (k as usize, m)
    }

    /// Index into the values of action `a` of interval `i`'s sampled state `c`.
    fn index(&self, i: usize, c: usize, a: usize) -> usize {
        let (k, m) = self.state(i, c);
        let a = if m { self.perm[i][a] as usize } else { a };
        self.offsets[k] as usize + a
    }
}

/// The learned action values, one table per interval.
#[derive(Debug, Clone, PartialEq)]
pub struct Policy {
    /// Fingerprint of the database it belongs to.
    pub fingerprint: u64,
    /// Training seed.
    pub seed: u64,
    /// Episodes trained so far.
    pub episodes: u64,
    /// The state grid.
    pub grid: StateGrid,
    /// Learning parameters.
    pub params: LearnParams,
    layout: Layout,
    /// Action values of the stored states.
    q: Vec<f32>,
    /// Best action value of each stored state.
    best: Vec<f32>,
    /// Updates per stored state.
    visits: Vec<u32>,
    /// For each interval × cell, the nearest sampled state that learning visited.
    nearest: Vec<u32>,
}

/// Progress of a training run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Episodes trained so far.
    pub episodes: u64,
    /// Share of visited states whose best action changed since the previous report.
    pub changed: f64,
}

impl Policy {
    /// An untrained policy for `db`.
    pub fn new(db: &Database, grid: StateGrid, params: LearnParams, seed: u64) -> Policy {
        let layout = Layout::new(db, &grid);
        // Optimistic start: every action looks as good as the best possible return, so greedy
        // choices try each action before settling.
        let optimistic = ((params.alpha + params.beta) / (1.0 - params.discount).max(1e-3)) as f32;
        let n = layout.states.len();
        let mut p = Policy {
            fingerprint: db.fingerprint(),
            seed,
            episodes: 0,
            grid,
            params,
            q: vec![optimistic; layout.values],
            best: vec![optimistic; n],
            visits: vec![0; n],
            nearest: Vec::new(),
            layout,
        };
        p.index_nearest();
        p
    }

    /// Checks that the policy belongs to `db`.
    pub fn check(&self, db: &Database) -> Result<(), PolicyError> {
        let expected = db.fingerprint();
        if expected != self.fingerprint {
            return Err(PolicyError::Mismatch { expected, found: self.fingerprint });
        }
        Ok(())
    }

    fn lookup(&self, interval: usize, errors: Errors) -> usize {
        let cells = self.grid.cells();
        self.nearest[interval * cells + self.grid.cell(errors.speed, errors.direction)] as usize
    }

    /// The value of candidate `a` after `interval` in the sampled state nearest to `errors`.
    pub fn value(&self, interval: usize, errors: Errors, a: usize) -> f32 {
        self.q[self.layout.index(interval, self.lookup(interval, errors), a)]
    }

    /// The learnt value of interval `interval` with errors `errors`: the best action values of
    /// the (up to four) sampled states around the errors that learning visited, interpolated
    /// bilinearly; the nearest visited state's when none around was visited.
    pub fn state_value(&self, interval: usize, errors: Errors) -> f32 {
        self.interpolated(interval, errors)
            .unwrap_or_else(|| self.best[self.layout.state(interval, self.lookup(interval, errors)).0])
    }

    /// The learnt values of the visited sampled states around `errors`, interpolated
    /// bilinearly; `None` when none of them was visited.
    fn interpolated(&self, interval: usize, errors: Errors) -> Option<f32> {
        let g = &self.grid;
        let (sv, fv) = if g.speed_cells > 1 {
            let step = 2.0 * g.speed_range / (g.speed_cells - 1) as f64;
            let x = if errors.speed.is_finite() { errors.speed } else { 0.0 };
            let u = ((x + g.speed_range) / step).clamp(0.0, (g.speed_cells - 1) as f64);
            let i = (u.floor() as usize).min(g.speed_cells - 2);
            (i, u - i as f64)
        } else {
            (0, 0.0)
        };
        let d = if errors.direction.is_finite() { wrap_angle(errors.direction) } else { 0.0 };
        let u = (d + std::f64::consts::PI) / (std::f64::consts::TAU / g.direction_cells as f64);
        let sd = (u.floor() as usize) % g.direction_cells;
        let fd = u - u.floor();
        let (mut sum, mut weight) = (0.0f64, 0.0f64);
        for (dv, wv) in [(0, 1.0 - fv), (1, fv)] {
            for (dd, wd) in [(0, 1.0 - fd), (1, fd)] {
                let w = wv * wd;
                if w <= 0.0 || sv + dv >= g.speed_cells {
                    continue;
                }
                let cell = (sv + dv) * g.direction_cells + (sd + dd) % g.direction_cells;
                let (k, _) = self.layout.state(interval, cell);
                if self.visits[k] > 0 {
                    sum += w * f64::from(self.best[k]);
                    weight += w;
                }
            }
        }
        (weight > 0.0).then(|| (sum / weight) as f32)
    }

    /// The value a training target uses for `errors` after `interval`: interpolated among
    /// visited neighbours, else the (optimistic) value of its own sampled state — never the
    /// run-time nearest-state index, so training does not depend on when it was last built.
    fn target_value(&self, interval: usize, errors: Errors) -> f32 {
        self.interpolated(interval, errors).unwrap_or_else(|| {
            let (k, _) = self.layout.state(interval, self.grid.cell(errors.speed, errors.direction));
            self.best[k]
        })
    }

    /// The best candidate (index into `db.candidates[interval]`) in the sampled state nearest
    /// to `errors`, among those learning visited (§3.2.3). Ties go to the earlier candidate,
    /// so an untrained table keeps the natural successor.
    pub fn choose(&self, interval: usize, errors: Errors) -> usize {
        let c = self.lookup(interval, errors);
        self.best_action(interval, c).0
    }

    /// The candidates after `interval`, best value first (ties: earlier candidate first), in
    /// the sampled state nearest to `errors`, into `out`.
    pub fn rank(&self, interval: usize, errors: Errors, out: &mut Vec<usize>) {
        let c = self.lookup(interval, errors);
        out.clear();
        out.extend(0..self.layout.actions[interval]);
        let q = |a: usize| self.q[self.layout.index(interval, c, a)];
        out.sort_by(|&a, &b| q(b).total_cmp(&q(a)).then(a.cmp(&b)));
    }

    /// The action values of the state nearest to `errors` (for display), candidate order.
    pub fn values(&self, interval: usize, errors: Errors) -> Vec<f32> {
        let c = self.lookup(interval, errors);
        (0..self.layout.actions[interval]).map(|a| self.q[self.layout.index(interval, c, a)]).collect()
    }

    fn best_action(&self, interval: usize, cell: usize) -> (usize, f32) {
        let mut best = (0, f32::NEG_INFINITY);
        for a in 0..self.layout.actions[interval] {
            let v = self.q[self.layout.index(interval, cell, a)];
            if v > best.1 {
                best = (a, v);
            }
        }
        best
    }

    /// Number of sampled states learning visited (a state and its mirror count as two).
    pub fn visited_states(&self) -> usize {
        self.layout.slot.iter().filter(|&&(k, _)| self.visits[k as usize] > 0).count()
    }

    /// Total number of sampled states.
    pub fn states(&self) -> usize {
        self.layout.slot.len()
    }

    /// Share of visited sampled states with a mirror where the run-time choice (the learnt
    /// strategy at the state's errors, no turn rate) of the mirrored state is the mirrored
    /// candidate (1 when there are none).
    pub fn mirror_agreement(&self, db: &Database) -> f64 {
        let cells = self.grid.cells();
        let ranker = Ranker { strategy: Strategy::Learnt, policy: self };
        let mut rng = rng::stream(0, 0, 0);
        let (mut order, mut mirrored) = (Vec::new(), Vec::new());
        let (mut n, mut agree) = (0usize, 0usize);
        for i in 0..db.intervals.len() {
            let Some(m) = self.layout.mirror[i] else { continue };
            for c in 0..cells {
                let (k, _) = self.layout.state(i, c);
                if self.visits[k] == 0 {
                    continue;
                }
                n += 1;
                let (speed, direction) = self.grid.value(c);
                let task = Task { turn_rate: 0.0, speed: db.intervals[i].speed + speed };
                ranker.rank(db, i, Errors { speed, direction }, task, &mut rng, &mut order);
                ranker.rank(db, m, Errors { speed, direction: -direction }, task, &mut rng, &mut mirrored);
                agree += usize::from(mirrored[0] == self.layout.perm[i][order[0]] as usize);
            }
        }
        if n == 0 { 1.0 } else { agree as f64 / n as f64 }
    }

    /// Share of the stored action values of visited states never updated from their optimistic
    /// start (0 with full backups; kept as a check).
    pub fn untouched_share(&self) -> f64 {
        let optimistic = ((self.params.alpha + self.params.beta) / (1.0 - self.params.discount).max(1e-3)) as f32;
        let (mut n, mut untouched) = (0usize, 0usize);
        for (k, &v) in self.visits.iter().enumerate() {
            if v == 0 {
                continue;
            }
            let (i, _) = self.layout.states[k];
            let o = self.layout.offsets[k] as usize;
            for a in 0..self.layout.actions[i as usize] {
                n += 1;
                untouched += usize::from(self.q[o + a] == optimistic);
            }
        }
        if n == 0 { 0.0 } else { untouched as f64 / n as f64 }
    }

    /// Trains until `target` episodes, calling `progress` every [`ROUND`] episodes and
    /// `checkpoint` every `checkpoint_rounds` rounds.
    pub fn train(
        &mut self,
        db: &Database,
        target: u64,
        checkpoint_rounds: u64,
        progress: &mut dyn FnMut(Progress),
        checkpoint: &mut dyn FnMut(&Policy),
    ) {
        let mut before = self.greedy();
        let mut round = 0u64;
        while self.episodes < target {
            let end = self.episodes.saturating_add(ROUND).min(target);
            for ep in self.episodes..end {
                self.episode(db, ep);
            }
            self.episodes = end;
            round += 1;
            let now = self.greedy();
            let visited: Vec<usize> = (0..now.len()).filter(|&k| self.visits[k] > 0).collect();
            let changed = visited.iter().filter(|&&k| now[k] != before[k]).count() as f64 / visited.len().max(1) as f64;
            before = now;
            progress(Progress { episodes: self.episodes, changed });
            if checkpoint_rounds > 0 && round.is_multiple_of(checkpoint_rounds) && self.episodes < target {
                self.index_nearest();
                checkpoint(self);
            }
        }
        self.index_nearest();
    }

    /// The best action of every stored state.
    fn greedy(&self) -> Vec<u16> {
        self.layout.states.iter().map(|&(i, c)| self.best_action(i as usize, c as usize).0 as u16).collect()
    }

    /// One training episode: at each step, every candidate's value is updated by Eq. 5 from
    /// the deterministic model, then an ε-greedy choice moves on.
    fn episode(&mut self, db: &Database, ep: u64) {
        let p = self.params;
        let mut rng = rng::stream(self.seed, ep, TRAIN_STREAM);
        let n = db.intervals.len();
        let mut task = sample_task(db, &p, &mut rng);
        let mut interval = ((rng::unit(&mut rng) * n as f64) as usize).min(n - 1);
        let direction = if rng::unit(&mut rng) < 0.5 {
            rng::uniform(&mut rng, -std::f64::consts::PI, std::f64::consts::PI)
        } else {
            0.0
        };
        let mut e = Errors { speed: task.speed - db.intervals[interval].speed, direction };
        let mut targets: Vec<(f32, Errors)> = Vec::new();
        for _ in 0..p.episode_length {
            let cell = self.grid.cell(e.speed, e.direction);
            let na = self.layout.actions[interval];
            targets.clear();
            for a in 0..na {
                let (r, next) = reward(db, &p, interval, a, e.direction, task);
                let to = db.candidates[interval][a].interval;
                targets.push(((r + p.discount * f64::from(self.target_value(to, next))) as f32, next));
            }
            let (k, _) = self.layout.state(interval, cell);
            let v = &mut self.visits[k];
            *v = v.saturating_add(1);
            // λ decays with the updates of the sampled state, down to a floor.
            let lr = (p.learning_rate * (1.0 / (1.0 + f64::from(*v) / RATE_HALVING_VISITS)).max(RATE_FLOOR)) as f32;
            for (a, &(t, _)) in targets.iter().enumerate() {
                let idx = self.layout.index(interval, cell, a);
                self.q[idx] += lr * (t - self.q[idx]);
            }
            // A state that is its own mirror: mirrored candidates share one value.
            let (i32_, c32) = self.layout.states[k];
            if self.layout.mirror[interval] == Some(interval) && self.grid.mirror(cell) == cell {
                let o = self.layout.offsets[k] as usize;
                for a in 0..na {
                    let b = self.layout.perm[interval][a] as usize;
                    if b > a {
                        let mean = 0.5 * (self.q[o + a] + self.q[o + b]);
                        self.q[o + a] = mean;
                        self.q[o + b] = mean;
                    }
                }
            }
            self.best[k] = self.best_action(i32_ as usize, c32 as usize).1;
            let a = if rng::unit(&mut rng) < p.exploration {
                ((rng::unit(&mut rng) * na as f64) as usize).min(na - 1)
            } else {
                self.best_action(interval, cell).0
            };
            e = targets[a].1;
            interval = db.candidates[interval][a].interval;
            if rng::unit(&mut rng) < p.task_change {
                // The interval playing keeps the speed its warp gave it.
                let played = task.speed - e.speed;
                task = sample_task(db, &p, &mut rng);
                e.speed = task.speed - played;
                if task.turn_rate == 0.0 {
                    e.direction = rng::uniform(&mut rng, -std::f64::consts::PI, std::f64::consts::PI);
                }
            }
        }
    }

    /// Recomputes, for every interval × cell, the nearest visited sampled state (itself when
    /// visited; the cell itself when the interval's table was never visited). Mirrored states
    /// take the mirror of their twin's answer, so the lookup is symmetric too.
    fn index_nearest(&mut self) {
        let cells = self.grid.cells();
        let scale = self.params.speed_tolerance / self.params.direction_tolerance;
        let n = self.layout.actions.len();
        let mut nearest = vec![0u32; n * cells];
        for i in 0..n {
            let visited: Vec<usize> = (0..cells).filter(|&c| self.visits[self.layout.state(i, c).0] > 0).collect();
            for c in 0..cells {
                if self.layout.state(i, c).1 {
                    continue;
                }
                let pick = if visited.is_empty() || visited.binary_search(&c).is_ok() {
                    c
                } else {
                    let mut best = (visited[0], f64::INFINITY);
                    for &v in &visited {
                        let d = self.grid.distance(c, v, scale);
                        if d < best.1 {
                            best = (v, d);
                        }
                    }
                    best.0
                };
                nearest[i * cells + c] = pick as u32;
                if let Some(m) = self.layout.mirror[i] {
                    let mc = self.grid.mirror(c);
                    if self.layout.state(m, mc).1 {
                        nearest[m * cells + mc] = self.grid.mirror(pick) as u32;
                    }
                }
            }
        }
        self.nearest = nearest;
    }

    /// The policy as bytes: magic, version, header, tables, FNV-1a checksum.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut b = Vec::with_capacity(64 + self.q.len() * 4 + self.visits.len() * 4);
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        for v in [self.fingerprint, self.seed, self.episodes] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&(self.grid.speed_cells as u32).to_le_bytes());
        b.extend_from_slice(&self.grid.speed_range.to_le_bytes());
        b.extend_from_slice(&(self.grid.direction_cells as u32).to_le_bytes());
        let p = &self.params;
        for v in [
            p.alpha,
            p.beta,
            p.learning_rate,
            p.discount,
            p.exploration,
            p.task_change,
            p.speed_tolerance,
            p.direction_tolerance,
            p.planner_speed,
            p.planner_turn,
            p.wide_tasks,
            p.heading_weight,
            p.warp.turn_scale.0,
            p.warp.turn_scale.1,
            p.warp.spot_scale.0,
            p.warp.spot_scale.1,
            p.warp.bend_rad,
            p.warp.stride.0,
            p.warp.stride.1,
            p.warp.min_speed_mps,
        ] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&(p.episode_length as u32).to_le_bytes());
        b.extend_from_slice(&(self.layout.states.len() as u32).to_le_bytes());
        b.extend_from_slice(&(self.q.len() as u32).to_le_bytes());
        for &q in &self.q {
            b.extend_from_slice(&q.to_le_bytes());
        }
        for &v in &self.visits {
            b.extend_from_slice(&v.to_le_bytes());
        }
        let mut h = Fnv::default();
        h.bytes(&b);
        b.extend_from_slice(&h.0.to_le_bytes());
        b
    }

    /// Reads a policy written by [`Policy::to_bytes`] and checks it against `db`.
    pub fn from_bytes(bytes: &[u8], db: &Database) -> Result<Policy, PolicyError> {
        if bytes.len() < 12 || &bytes[..8] != MAGIC {
            return Err(PolicyError::Magic);
        }
        let mut r = Reader { b: bytes, at: 8 };
        let version = r.u32()?;
        if version != FORMAT_VERSION {
            return Err(PolicyError::Version(version));
        }
        if bytes.len() < 20 {
            return Err(PolicyError::Truncated);
        }
        let body = &bytes[..bytes.len() - 8];
        let mut h = Fnv::default();
        h.bytes(body);
        if h.0.to_le_bytes() != bytes[bytes.len() - 8..] {
            // A short file fails the checksum too.
            return Err(PolicyError::Checksum);
        }
        let r = &mut Reader { b: body, at: 12 };
        let (fingerprint, seed, episodes) = (r.u64()?, r.u64()?, r.u64()?);
        if episodes > MAX_EPISODES {
            return Err(PolicyError::Malformed("episode count"));
        }
        let grid =
            StateGrid { speed_cells: r.u32()? as usize, speed_range: r.f64()?, direction_cells: r.u32()? as usize };
        if grid.speed_cells == 0
            || grid.direction_cells == 0
            || !grid.direction_cells.is_multiple_of(2)
            || grid.cells() > 1 << 20
            || !(grid.speed_range > 0.0)
        {
            return Err(PolicyError::Malformed("state grid"));
        }
        let mut v = [0.0; 20];
        for x in &mut v {
            *x = r.f64()?;
        }
        let episode_length = r.u32()? as usize;
        if episode_length == 0 || episode_length > MAX_EPISODE_LENGTH {
            return Err(PolicyError::Malformed("episode length"));
        }
        let params = LearnParams {
            alpha: v[0],
            beta: v[1],
            learning_rate: v[2],
            discount: v[3],
            exploration: v[4],
            task_change: v[5],
            speed_tolerance: v[6],
            direction_tolerance: v[7],
            planner_speed: v[8],
            planner_turn: v[9],
            wide_tasks: v[10],
            heading_weight: v[11],
            warp: WarpLimits {
                turn_scale: (v[12], v[13]),
                spot_scale: (v[14], v[15]),
                bend_rad: v[16],
                stride: (v[17], v[18]),
                min_speed_mps: v[19],
            },
            episode_length,
        };
        if !params.warp.valid() {
            return Err(PolicyError::Malformed("warp limits"));
        }
        let expected = db.fingerprint();
        if fingerprint != expected {
            return Err(PolicyError::Mismatch { expected, found: fingerprint });
        }
        let layout = Layout::new(db, &grid);
        if r.u32()? as usize != layout.states.len() {
            return Err(PolicyError::Malformed("state count"));
        }
        if r.u32()? as usize != layout.values {
            return Err(PolicyError::Malformed("value count"));
        }
        let expect = layout.values * 4 + layout.states.len() * 4;
        if body.len() - r.at != expect {
            return Err(PolicyError::Malformed("table size"));
        }
        let mut q = Vec::with_capacity(layout.values);
        for _ in 0..layout.values {
            q.push(f32::from_le_bytes(r.take::<4>()?));
        }
        let mut visits = Vec::with_capacity(layout.states.len());
        for _ in 0..layout.states.len() {
            visits.push(r.u32()?);
        }
        if q.iter().any(|x| !x.is_finite()) {
            return Err(PolicyError::Malformed("non-finite action value"));
        }
        let n = layout.states.len();
        let mut p = Policy {
            fingerprint,
            seed,
            episodes,
            grid,
            params,
            layout,
            q,
            best: vec![0.0; n],
            visits,
            nearest: Vec::new(),
        };
        for k in 0..n {
            let (i, c) = p.layout.states[k];
            p.best[k] = p.best_action(i as usize, c as usize).1;
        }
        p.index_nearest();
        Ok(p)
    }
}

/// A task sampled over the planner's ranges (or, for a share, the database's whole speed
/// range).
pub fn sample_task(db: &Database, p: &LearnParams, rng: &mut ChaCha8Rng) -> Task {
    let top = if rng::unit(rng) < p.wide_tasks { db.max_speed().max(p.planner_speed) } else { p.planner_speed };
    let turn_rate =
        if rng::unit(rng) < HEADING_TASKS { 0.0 } else { rng::uniform(rng, -p.planner_turn, p.planner_turn) };
    Task { turn_rate, speed: rng::uniform(rng, 0.0, top) }
}

/// A way of ranking the candidates at a switch point: a [`Strategy`] over a policy.
#[derive(Debug)]
pub struct Ranker<'a> {
    /// The strategy.
    pub strategy: Strategy,
    /// The learnt policy (also gives α, β and the tolerances to the greedy rule).
    pub policy: &'a Policy,
}

impl Ranker<'_> {
    /// The candidates after `interval`, best first, into `out`; `task` is what is commanded
    /// (for the greedy rule), `rng` the stream of the random strategy.
    pub fn rank(
        &self,
        db: &Database,
        interval: usize,
        errors: Errors,
        task: Task,
        rng: &mut ChaCha8Rng,
        out: &mut Vec<usize>,
    ) {
        let na = db.policy_actions[interval];
        out.clear();
        match self.strategy {
            Strategy::Learnt => {
                // Eq. 5's target at the exact state: the candidate's reward now plus the
                // discounted learnt value of the sampled state it leads to.
                out.extend(0..na);
                let p = &self.policy.params;
                let score: Vec<f64> = (0..na)
                    .map(|a| {
                        let (r, next) = reward(db, p, interval, a, errors.direction, task);
                        r + p.discount * f64::from(self.policy.state_value(db.candidates[interval][a].interval, next))
                    })
                    .collect();
                out.sort_by(|&a, &b| score[b].total_cmp(&score[a]).then(a.cmp(&b)));
            }
            Strategy::Successor => out.extend(0..na),
            Strategy::Greedy => {
                out.extend(0..na);
                let p = &self.policy.params;
                let score: Vec<f64> = (0..na).map(|a| reward(db, p, interval, a, errors.direction, task).0).collect();
                out.sort_by(|&a, &b| score[b].total_cmp(&score[a]).then(a.cmp(&b)));
            }
            Strategy::Random => {
                out.extend(0..na);
                // Fisher–Yates with the caller's stream.
                for k in (1..na).rev() {
                    let j = ((rng::unit(rng) * (k + 1) as f64) as usize).min(k);
                    out.swap(k, j);
                }
            }
        }
    }
}

/// Scores of a strategy on held-out episodes of the training MDP.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Evaluation {
    /// Mean discounted return of Eq. 4–5 per episode.
    pub mean_return: f64,
    /// Share of tasks met: within [`MET_SPEED_MPS`] and [`MET_DIRECTION_RAD`] of the command
    /// when the task changes or the episode ends.
    pub task_success: f64,
}

/// Speed error within which a task counts as met, m/s.
pub const MET_SPEED_MPS: f64 = 0.25;
/// Direction error within which a task counts as met, radians (15°).
pub const MET_DIRECTION_RAD: f64 = 15.0 * std::f64::consts::PI / 180.0;

/// Scores `strategy` on `episodes` held-out episodes of the training MDP: episodes drawn exactly
/// as training draws them (start interval, task, direction error, task changes, length), from
/// a random stream training never uses, identical for every strategy. Returns the discounted
/// return of Eq. 4 with the policy's α, β, γ, and task success.
pub fn evaluate(db: &Database, policy: &Policy, strategy: Strategy, episodes: u64, seed: u64) -> Evaluation {
    let p = &policy.params;
    let ranker = Ranker { strategy, policy };
    let (mut total, mut tasks, mut met) = (0.0, 0u64, 0u64);
    let mut order = Vec::new();
    let n = db.intervals.len();
    let on_command = |e: Errors| e.speed.abs() <= MET_SPEED_MPS && e.direction.abs() <= MET_DIRECTION_RAD;
    for ep in 0..episodes {
        let mut rng = rng::stream(seed, ep, HELD_OUT_STREAM);
        let mut choice_rng = rng::stream(seed, ep, HELD_OUT_STREAM + 1);
        let mut task = sample_task(db, p, &mut rng);
        let mut interval = ((rng::unit(&mut rng) * n as f64) as usize).min(n - 1);
        let direction = if rng::unit(&mut rng) < 0.5 {
            rng::uniform(&mut rng, -std::f64::consts::PI, std::f64::consts::PI)
        } else {
            0.0
        };
        let mut e = Errors { speed: task.speed - db.intervals[interval].speed, direction };
        let (mut ret, mut discount) = (0.0, 1.0);
        for _ in 0..p.episode_length {
            ranker.rank(db, interval, e, task, &mut choice_rng, &mut order);
            let a = order[0];
            let (r, next) = reward(db, p, interval, a, e.direction, task);
            ret += discount * r;
            discount *= p.discount;
            interval = db.candidates[interval][a].interval;
            e = next;
            if rng::unit(&mut rng) < p.task_change {
                tasks += 1;
                met += u64::from(on_command(e));
                // The interval playing keeps the speed its warp gave it.
                let played = task.speed - e.speed;
                task = sample_task(db, p, &mut rng);
                e.speed = task.speed - played;
                if task.turn_rate == 0.0 {
                    e.direction = rng::uniform(&mut rng, -std::f64::consts::PI, std::f64::consts::PI);
                }
            }
        }
        tasks += 1;
        met += u64::from(on_command(e));
        total += ret;
    }
    Evaluation { mean_return: total / episodes.max(1) as f64, task_success: met as f64 / tasks.max(1) as f64 }
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], PolicyError> {
        let s = self.b.get(self.at..self.at + N).ok_or(PolicyError::Truncated)?;
        self.at += N;
        Ok(s.try_into().expect("slice of length N"))
    }
    fn u32(&mut self) -> Result<u32, PolicyError> {
        Ok(u32::from_le_bytes(self.take()?))
    }
    fn u64(&mut self) -> Result<u64, PolicyError> {
        Ok(u64::from_le_bytes(self.take()?))
    }
    fn f64(&mut self) -> Result<f64, PolicyError> {
        let v = f64::from_le_bytes(self.take()?);
        if v.is_finite() { Ok(v) } else { Err(PolicyError::Malformed("non-finite parameter")) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::anim::db::tests::database;

    fn trained(episodes: u64) -> (Database, Policy) {
        let db = database();
        let mut p = Policy::new(&db, StateGrid::default(), LearnParams::default(), 7);
        p.train(&db, episodes, 0, &mut |_| {}, &mut |_| {});
        (db, p)
    }

    #[test]
    fn grid_cells_round_trip_and_mirror() {
        let g = StateGrid::default();
        for c in 0..g.cells() {
            let (v, d) = g.value(c);
            assert_eq!(g.cell(v, d), c);
            let (mv, md) = g.value(g.mirror(c));
            assert_eq!(mv, v);
            assert!(wrap_angle(md + d).abs() < 1e-9, "{d} mirrors to {md}");
            assert_eq!(g.mirror(g.mirror(c)), c);
        }
        assert_eq!(g.cell(f64::NAN, f64::NAN), g.cell(0.0, 0.0));
        assert_eq!(g.cell(99.0, 0.0), g.cell(1.5, 0.0));
        // Direction samples every 10°.
        assert!((g.value(1).1 - g.value(0).1 - 10f64.to_radians()).abs() < 1e-12);
    }

    #[test]
    fn episode_counts_and_lengths_beyond_the_limits_are_malformed() {
        let (db, p) = trained(ROUND);
        let rewrite = |at: usize, field: &[u8]| {
            let mut b = p.to_bytes();
            b[at..at + field.len()].copy_from_slice(field);
            let n = b.len() - 8;
            let mut h = Fnv::default();
            h.bytes(&b[..n]);
            b[n..].copy_from_slice(&h.0.to_le_bytes());
            Policy::from_bytes(&b, &db)
        };
        assert!(rewrite(28, &ROUND.to_le_bytes()).is_ok());
        assert_eq!(rewrite(28, &u64::MAX.to_le_bytes()).unwrap_err(), PolicyError::Malformed("episode count"));
        assert_eq!(rewrite(212, &(1u32 << 16).to_le_bytes()).unwrap_err(), PolicyError::Malformed("episode length"));
        assert_eq!(rewrite(148, &(-1.0f64).to_le_bytes()).unwrap_err(), PolicyError::Malformed("warp limits"));
    }

    #[test]
    fn training_is_deterministic_and_resumable() {
        let (db, a) = trained(3 * ROUND);
        let hash = |b: Vec<u8>| {
            let mut h = Fnv::default();
            h.bytes(&b);
            h.0
        };
        assert_eq!(hash(a.to_bytes()), hash(trained(3 * ROUND).1.to_bytes()));
        // Stop at a checkpoint, reload, go on: the same values as without stopping.
        let mut first = Policy::new(&db, StateGrid::default(), LearnParams::default(), 7);
        let mut saved = Vec::new();
        first.train(&db, 2 * ROUND, 1, &mut |_| {}, &mut |p| saved = p.to_bytes());
        let mut resumed = Policy::from_bytes(&saved, &db).unwrap();
        assert_eq!(resumed.episodes, ROUND);
        resumed.train(&db, 3 * ROUND, 0, &mut |_| {}, &mut |_| {});
        assert_eq!(hash(resumed.to_bytes()), hash(a.to_bytes()));
    }

    #[test]
    fn learning_beats_the_baselines_on_held_out_tasks() {
        let (db, p) = trained(40 * ROUND);
        let score = |s| evaluate(&db, &p, s, 400, 99);
        let learnt = score(Strategy::Learnt);
        for s in [Strategy::Successor, Strategy::Random] {
            let other = score(s);
            assert!(learnt.mean_return > 1.1 * other.mean_return, "{learnt:?} vs {s:?} {other:?}");
        }
        // This small database turns less per interval than a sampled state is wide, and warping
        // brings most tasks within reach of one interval, so the learnt values (read at the
        // nearest sampled state) add little to the exact reward of the next interval: within
        // 1.5 % of greedy (the built-in database's policy must beat it outright; see
        // tests/anim.rs).
        let greedy = score(Strategy::Greedy);
        assert!(learnt.mean_return >= 0.985 * greedy.mean_return, "{learnt:?} vs greedy {greedy:?}");
        assert!(p.visited_states() > 0);
        assert_eq!(p.untouched_share(), 0.0);
    }

    #[test]
    fn bad_files_are_clear_errors() {
        let (db, p) = trained(ROUND);
        let bytes = p.to_bytes();
        assert_eq!(Policy::from_bytes(&bytes, &db).unwrap(), p);
        assert_eq!(Policy::from_bytes(b"hello world, not a policy", &db), Err(PolicyError::Magic));
        let mut v = bytes.clone();
        v[8] = 9;
        assert_eq!(Policy::from_bytes(&v, &db), Err(PolicyError::Version(9)));
        let mut c = bytes.clone();
        c[100] ^= 1;
        assert_eq!(Policy::from_bytes(&c, &db), Err(PolicyError::Checksum));
        assert_eq!(Policy::from_bytes(&bytes[..bytes.len() / 2], &db), Err(PolicyError::Checksum));
        let other = Database::build(
            db.clips.clone(),
            db.skeleton.clone(),
            crate::anim::db::DbParams { k: 3, ..db.params.clone() },
            Some(&crate::anim::db::tests::manual(&db)),
        )
        .unwrap();
        assert!(matches!(Policy::from_bytes(&bytes, &other), Err(PolicyError::Mismatch { .. })));
    }
}
