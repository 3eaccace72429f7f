//! The RL animation controller's policy (seed 000 §3.2.2–3.2.3; DESIGN.md §3): an MDP whose
//! state is (interval now ending, speed error, direction error), whose actions are the
//! candidates at that switch point (natural successor and its K neighbours), with deterministic
//! transitions, the reward of Eq. 4 and the update of Eq. 5, learned from (turn, speed) tasks
//! sampled over the fuzzy planner's output ranges — once, for every environment.
//!
//! The continuous errors are sampled on a grid per interval table; at run time the agent's
//! state is matched to the nearest sampled state that learning visited, in the table of the
//! interval now playing, and the best-valued action is taken.
//!
//! Training runs in rounds of [`ROUND`] episodes: every episode of a round acts on the values
//! at the start of the round (so episodes of one round run in parallel), and their updates are
//! applied in episode order. The result depends only on the seed and the number of rounds, not
//! on the number of threads, and a run resumed from a checkpoint continues exactly as if it had
//! not stopped.

use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::db::{Database, Fnv};
use crate::geom::wrap_angle;
use crate::rng;

/// Episodes per training round.
pub const ROUND: u64 = 64;

/// Where the continuous state parameters are sampled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateGrid {
    /// Samples of the speed error (odd, so 0 is one of them) (9).
    pub speed_cells: usize,
    /// Speed errors span `[-speed_range, speed_range]`, metres per second (2).
    pub speed_range: f64,
    /// Samples of the direction error over `[-π, π)` (16, every 22.5°).
    pub direction_cells: usize,
}

impl Default for StateGrid {
    fn default() -> Self {
        StateGrid { speed_cells: 9, speed_range: 2.0, direction_cells: 16 }
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
    /// α of Eq. 4, weight of the neighbour similarity `w_a` (0.1).
    pub alpha: f64,
    /// β of Eq. 4, weight of the task score `T(s')` (1).
    pub beta: f64,
    /// λ of Eq. 5, learning rate (0.25); it decays per sampled state with its updates, halving after
    /// 40 and never below a tenth.
    pub learning_rate: f64,
    /// γ of Eq. 5, discount (0.7).
    pub discount: f64,
    /// ε-greedy exploration: probability of a random action (0.3).
    pub exploration: f64,
    /// Intervals played per episode (24).
    pub episode_length: usize,
    /// Probability per interval that the commanded task changes (0.15).
    pub task_change: f64,
    /// Speed error scale of `T`, m/s (1.5).
    pub speed_tolerance: f64,
    /// Direction error scale of `T`, radians (π).
    pub direction_tolerance: f64,
    /// Top commanded speed of the planner, m/s (1.5).
    pub planner_speed: f64,
    /// Top commanded turn rate of the planner, rad/s (2.09, 120°/s).
    pub planner_turn: f64,
    /// Share of tasks sampled over the whole database's speed range instead (user control) (0.25).
    pub wide_tasks: f64,
}

/// Share of tasks that command a heading change (a direction error, no turn rate) rather than
/// a turn rate.
const HEADING_TASKS: f64 = 0.5;
/// Updates of a sampled state after which its learning rate has halved.
const RATE_HALVING_VISITS: f64 = 40.0;
/// Smallest learning rate, as a share of λ.
const RATE_FLOOR: f64 = 0.1;

impl Default for LearnParams {
    fn default() -> Self {
        LearnParams {
            alpha: 0.05,
            beta: 1.0,
            learning_rate: 0.25,
            discount: 0.8,
            exploration: 0.3,
            episode_length: 24,
            task_change: 0.15,
            speed_tolerance: 1.5,
            direction_tolerance: std::f64::consts::PI,
            planner_speed: 1.5,
            planner_turn: 120f64.to_radians(),
            wide_tasks: 0.25,
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

/// The deterministic transition: the errors after playing interval `a` under `task`, starting
/// with direction error `direction`.
pub fn transition(db: &Database, a: usize, direction: f64, task: Task) -> Errors {
    let iv = &db.intervals[a];
    Errors {
        speed: task.speed - iv.speed,
        direction: (direction + task.turn_rate * iv.duration - iv.turn())
            .clamp(-std::f64::consts::PI, std::f64::consts::PI),
    }
}

/// How well errors meet the command, `T` in `[0, 1]`: 1 with no error, falling linearly in
/// each error (half for speed, half for direction) to 0 at the scale of that error.
pub fn task_score(e: Errors, p: &LearnParams) -> f64 {
    1.0 - 0.5 * (e.speed.abs() / p.speed_tolerance).min(1.0)
        - 0.5 * (e.direction.abs() / p.direction_tolerance).min(1.0)
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
pub const FORMAT_VERSION: u32 = 1;
const MAGIC: &[u8; 8] = b"STRDRPOL";

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
    /// Actions (candidates) per interval.
    actions: Vec<usize>,
    /// Start of each interval's table in `q` (cells × actions values).
    offsets: Vec<usize>,
    /// Action values.
    q: Vec<f32>,
    /// Updates per sampled state (interval × cell).
    visits: Vec<u32>,
    /// For each interval × cell, the nearest sampled state that learning visited.
    nearest: Vec<u32>,
}

/// Progress of a training run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Episodes trained so far.
    pub episodes: u64,
    /// Share of visited states whose best action changed since the previous check.
    pub changed: f64,
}

impl Policy {
    /// An untrained policy for `db`.
    pub fn new(db: &Database, grid: StateGrid, params: LearnParams, seed: u64) -> Policy {
        let actions: Vec<usize> = db.candidates.iter().map(Vec::len).collect();
        let mut offsets = Vec::with_capacity(actions.len());
        let mut total = 0;
        for &a in &actions {
            offsets.push(total);
            total += a * grid.cells();
        }
        let cells = actions.len() * grid.cells();
        // Optimistic start: every action looks as good as the best possible return, so greedy
        // choices try each action before settling.
        let optimistic = ((params.alpha + params.beta) / (1.0 - params.discount).max(1e-3)) as f32;
        let mut p = Policy {
            fingerprint: db.fingerprint(),
            seed,
            episodes: 0,
            grid,
            params,
            actions,
            offsets,
            q: vec![optimistic; total],
            visits: vec![0; cells],
            nearest: Vec::new(),
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

    /// The best candidate (index into `db.candidates[interval]`) in the sampled state nearest
    /// to `errors`, among those learning visited (§3.2.3). Ties go to the earlier candidate,
    /// so an untrained table keeps the natural successor.
    pub fn choose(&self, interval: usize, errors: Errors) -> usize {
        let cells = self.grid.cells();
        let cell = self.nearest[interval * cells + self.grid.cell(errors.speed, errors.direction)] as usize;
        self.best(interval, cell).0
    }

    /// The action values of the state nearest to `errors` (for display).
    pub fn values(&self, interval: usize, errors: Errors) -> &[f32] {
        let cells = self.grid.cells();
        let cell = self.nearest[interval * cells + self.grid.cell(errors.speed, errors.direction)] as usize;
        let a = self.actions[interval];
        let o = self.offsets[interval] + cell * a;
        &self.q[o..o + a]
    }

    fn best(&self, interval: usize, cell: usize) -> (usize, f32) {
        let a = self.actions[interval];
        let o = self.offsets[interval] + cell * a;
        let mut best = (0, self.q[o]);
        for k in 1..a {
            if self.q[o + k] > best.1 {
                best = (k, self.q[o + k]);
            }
        }
        best
    }

    /// Number of sampled states learning visited.
    pub fn visited_states(&self) -> usize {
        self.visits.iter().filter(|&&v| v > 0).count()
    }

    /// Total number of sampled states.
    pub fn states(&self) -> usize {
        self.visits.len()
    }

    /// Trains until `target` episodes (rounded up to whole rounds), calling `progress` after
    /// every round and `checkpoint` every `checkpoint_rounds` rounds.
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
            let start = self.episodes;
            let snapshot = &*self;
            let updates: Vec<Vec<(u32, u32, f32)>> =
                (start..start + ROUND).into_par_iter().map(|ep| snapshot.episode(db, ep)).collect();
            for ups in updates {
                for (interval, idx, target) in ups {
                    let cell = (idx as usize - self.offsets[interval as usize]) / self.actions[interval as usize];
                    let v = &mut self.visits[interval as usize * self.grid.cells() + cell];
                    *v = v.saturating_add(1);
                    // λ decays with the visits of the sampled state, down to a floor.
                    let decay = (1.0 / (1.0 + f64::from(*v) / RATE_HALVING_VISITS)).max(RATE_FLOOR);
                    let lr = (self.params.learning_rate * decay) as f32;
                    let q = &mut self.q[idx as usize];
                    *q = (1.0 - lr) * *q + lr * target;
                }
            }
            self.episodes += ROUND;
            round += 1;
            let now = self.greedy();
            let visited: Vec<usize> = (0..now.len()).filter(|&i| self.visits[i] > 0).collect();
            let changed = visited.iter().filter(|&&i| now[i] != before[i]).count() as f64 / visited.len().max(1) as f64;
            before = now;
            progress(Progress { episodes: self.episodes, changed });
            if checkpoint_rounds > 0 && round.is_multiple_of(checkpoint_rounds) && self.episodes < target {
                self.index_nearest();
                checkpoint(self);
            }
        }
        self.index_nearest();
    }

    /// The best action of every sampled state.
    fn greedy(&self) -> Vec<u16> {
        let cells = self.grid.cells();
        (0..self.visits.len()).map(|i| self.best(i / cells, i % cells).0 as u16).collect()
    }

    /// One training episode against the current values: the updates it makes, as (interval,
    /// index into `q`, target `r + γ·max Q(s′, ·)`).
    fn episode(&self, db: &Database, ep: u64) -> Vec<(u32, u32, f32)> {
        let p = &self.params;
        let mut rng = rng::stream(self.seed, ep, 0x5a25a);
        let n = db.intervals.len();
        let mut task = self.sample_task(db, &mut rng);
        let mut interval = ((rng::unit(&mut rng) * n as f64) as usize).min(n - 1);
        let direction = if rng::unit(&mut rng) < 0.5 {
            rng::uniform(&mut rng, -std::f64::consts::PI, std::f64::consts::PI)
        } else {
            0.0
        };
        let mut e = Errors { speed: task.speed - db.intervals[interval].speed, direction };
        let mut out = Vec::with_capacity(p.episode_length);
        for _ in 0..p.episode_length {
            let cell = self.grid.cell(e.speed, e.direction);
            let na = self.actions[interval];
            let a = if rng::unit(&mut rng) < p.exploration {
                ((rng::unit(&mut rng) * na as f64) as usize).min(na - 1)
            } else {
                self.best(interval, cell).0
            };
            let cand = db.candidates[interval][a];
            let next = transition(db, cand.interval, e.direction, task);
            let reward = p.alpha * cand.weight + p.beta * task_score(next, p);
            let next_cell = self.grid.cell(next.speed, next.direction);
            let future = self.best(cand.interval, next_cell).1 as f64;
            let target = reward + p.discount * future;
            out.push((interval as u32, (self.offsets[interval] + cell * na + a) as u32, target as f32));
            interval = cand.interval;
            e = next;
            if rng::unit(&mut rng) < p.task_change {
                task = self.sample_task(db, &mut rng);
                e.speed = task.speed - db.intervals[interval].speed;
                if task.turn_rate == 0.0 {
                    e.direction = rng::uniform(&mut rng, -std::f64::consts::PI, std::f64::consts::PI);
                }
            }
        }
        out
    }

    fn sample_task(&self, db: &Database, rng: &mut ChaCha8Rng) -> Task {
        let p = &self.params;
        let top = if rng::unit(rng) < p.wide_tasks { db.max_speed().max(p.planner_speed) } else { p.planner_speed };
        let turn_rate =
            if rng::unit(rng) < HEADING_TASKS { 0.0 } else { rng::uniform(rng, -p.planner_turn, p.planner_turn) };
        Task { turn_rate, speed: rng::uniform(rng, 0.0, top) }
    }

    /// Recomputes, for every interval × cell, the nearest visited sampled state (itself when
    /// visited; the cell itself when the interval's table was never visited).
    fn index_nearest(&mut self) {
        let cells = self.grid.cells();
        let scale = self.params.speed_tolerance / self.params.direction_tolerance;
        let grid = self.grid;
        self.nearest = (0..self.actions.len())
            .into_par_iter()
            .flat_map_iter(|i| {
                let visited: Vec<usize> = (0..cells).filter(|&c| self.visits[i * cells + c] > 0).collect();
                (0..cells).map(move |c| {
                    if visited.is_empty() || visited.binary_search(&c).is_ok() {
                        return c as u32;
                    }
                    let mut best = (visited[0], f64::INFINITY);
                    for &v in &visited {
                        let d = grid.distance(c, v, scale);
                        if d < best.1 {
                            best = (v, d);
                        }
                    }
                    best.0 as u32
                })
            })
            .collect();
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
        ] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&(p.episode_length as u32).to_le_bytes());
        b.extend_from_slice(&(self.actions.len() as u32).to_le_bytes());
        for &a in &self.actions {
            b.extend_from_slice(&(a as u32).to_le_bytes());
        }
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
            // A short file fails the checksum too; say which it is when we can tell.
            return Err(PolicyError::Checksum);
        }
        let r = &mut Reader { b: body, at: 12 };
        let (fingerprint, seed, episodes) = (r.u64()?, r.u64()?, r.u64()?);
        let grid =
            StateGrid { speed_cells: r.u32()? as usize, speed_range: r.f64()?, direction_cells: r.u32()? as usize };
        if grid.speed_cells == 0 || grid.direction_cells == 0 || grid.cells() > 1 << 20 || !(grid.speed_range > 0.0) {
            return Err(PolicyError::Malformed("state grid"));
        }
        let mut v = [0.0; 11];
        for x in &mut v {
            *x = r.f64()?;
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
            episode_length: r.u32()? as usize,
        };
        let expected = db.fingerprint();
        if fingerprint != expected {
            return Err(PolicyError::Mismatch { expected, found: fingerprint });
        }
        let n = r.u32()? as usize;
        if n != db.intervals.len() {
            return Err(PolicyError::Malformed("interval count"));
        }
        let mut actions = Vec::with_capacity(n);
        for i in 0..n {
            let a = r.u32()? as usize;
            if a != db.candidates[i].len() {
                return Err(PolicyError::Malformed("action count"));
            }
            actions.push(a);
        }
        let mut offsets = Vec::with_capacity(n);
        let mut total = 0;
        for &a in &actions {
            offsets.push(total);
            total += a * grid.cells();
        }
        let mut q = Vec::with_capacity(total);
        for _ in 0..total {
            q.push(f32::from_le_bytes(r.take::<4>()?));
        }
        let mut visits = Vec::with_capacity(n * grid.cells());
        for _ in 0..n * grid.cells() {
            visits.push(r.u32()?);
        }
        if r.at != body.len() {
            return Err(PolicyError::Malformed("trailing bytes"));
        }
        if q.iter().any(|x| !x.is_finite()) {
            return Err(PolicyError::Malformed("non-finite action value"));
        }
        let mut p =
            Policy { fingerprint, seed, episodes, grid, params, actions, offsets, q, visits, nearest: Vec::new() };
        p.index_nearest();
        Ok(p)
    }
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
    fn grid_cells_round_trip() {
        let g = StateGrid::default();
        for c in 0..g.cells() {
            let (v, d) = g.value(c);
            assert_eq!(g.cell(v, d), c);
        }
        assert_eq!(g.cell(f64::NAN, f64::NAN), g.cell(0.0, 0.0));
        assert_eq!(g.cell(99.0, 0.0), g.cell(2.0, 0.0));
    }

    #[test]
    fn training_is_deterministic_whatever_the_threads_and_resumable() {
        let (db, a) = trained(256);
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let b = one.install(|| trained(256).1);
        assert_eq!(a.to_bytes(), b.to_bytes());
        // Stop at a checkpoint, reload, go on: the same values as without stopping.
        let mut first = Policy::new(&db, StateGrid::default(), LearnParams::default(), 7);
        let mut saved = Vec::new();
        first.train(&db, 128, 1, &mut |_| {}, &mut |p| saved = p.to_bytes());
        let mut resumed = Policy::from_bytes(&saved, &db).unwrap();
        assert_eq!(resumed.episodes, 64);
        resumed.train(&db, 256, 0, &mut |_| {}, &mut |_| {});
        assert_eq!(resumed.to_bytes(), a.to_bytes());
    }

    #[test]
    fn learning_beats_always_taking_the_successor() {
        let (db, p) = trained(16384);
        let score = |learned: bool| {
            let mut total = 0.0;
            for ep in 0..200u64 {
                let mut rng = rng::stream(99, ep, 1);
                let task =
                    Task { turn_rate: rng::uniform(&mut rng, -0.4, 0.4), speed: rng::uniform(&mut rng, 0.5, 2.0) };
                let mut i = ep as usize % db.intervals.len();
                let mut e = Errors { speed: task.speed - db.intervals[i].speed, direction: 0.0 };
                for _ in 0..12 {
                    let a = if learned { p.choose(i, e) } else { 0 };
                    let next = db.candidates[i][a].interval;
                    e = transition(&db, next, e.direction, task);
                    i = next;
                    total += task_score(e, &p.params);
                }
            }
            total
        };
        let (learned, fixed) = (score(true), score(false));
        assert!(learned > 1.1 * fixed, "learned {learned} fixed {fixed}");
        assert!(p.visited_states() > 0);
    }

    #[test]
    fn bad_files_are_clear_errors() {
        let (db, p) = trained(64);
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
