//! The pure reinforcement-learning motion planner that seed 000 §4 (Table 1) compares the
//! fuzzy + RL planner against.
//!
//! It plays the same animation database as the character (the same intervals, candidates and
//! cross-fades), but one table does everything the layered planner splits between the fuzzy
//! rules and the 3-parameter policy: at every switch point it picks the next interval from a
//! state that holds the goal **and the nearby obstacles**. It is trained per world, with SARSA
//! (Eq. 5) and an ε-greedy choice, and must be retrained for every environment — which is the
//! point Table 1 makes.
//!
//! ## State (documented discretisation)
//! - the interval playing (one parameter; the candidates depend on it);
//! - the goal: its direction relative to the heading (8 sectors of 45°) and its distance
//!   (4 rings: < 1.5, < 4, < 10, ≥ 10 m) — two parameters;
//! - the free distance straight ahead of the character's disc (3 classes: < 1, < 2.5, ≥ 2.5 m)
//!   — one parameter;
//! - for each of the `k` nearest obstacles within [`SENSE_RANGE_M`] of the root (nearest
//!   surface first), three parameters: its bearing relative to the heading (8 sectors), the
//!   distance to its surface (3 rings: < 0.6, < 1.5, ≥ 1.5 m) and its orientation and shape
//!   class (round or compact; elongated with its long side facing the character; elongated
//!   edge-on). A missing obstacle is a class of its own.
//!
//! So the state has `4 + 3k` parameters: `k` = 0, 2 and 4 give the 4 / 10 / 16 of Table 1 for
//! the sparse, semi-cluttered and cluttered environments ([`PureRlParams::for_density`]).
//!
//! A table over so many cells is mostly empty: a state seen for the first time starts from the
//! values of its **coarse** state (the same interval, goal and free distance ahead, without the
//! obstacles), a second table trained alongside on every step — tabular back-off, so that the
//! baseline goes toward the goal from its first episode and learns the obstacles where it
//! meets them.
//!
//! ## Episodes
//! From a switch point the chosen candidate's root path ([`SwitchPoint::path`], cross-fade
//! included) is played; the episode ends with a collision (the body's disc overlaps an
//! obstacle anywhere along it: reward [`PureRlParams::collision_reward`]), on arrival (the path
//! enters the goal circle: [`PureRlParams::arrival_reward`]) or after
//! [`PureRlParams::max_decisions`] choices. Otherwise the reward is the progress toward the goal
//! in metres less a small cost per second. Everything is deterministic for a seed: the
//! exploration stream is [`crate::rng::stream`]`(seed, episode, 0xba5e)`.

use std::collections::BTreeMap;

use glam::DVec2;
use rand_chacha::ChaCha8Rng;
use rand_core::RngCore;

use crate::anim::player::{Choice, Player, PlayerParams, SwitchPoint};
use crate::anim::{Database, Ground};
use crate::geom::wrap_angle;
use crate::world::{Task, World};

/// Obstacles farther than this from the root (to their surface) are not in the state, metres.
pub const SENSE_RANGE_M: f64 = 4.0;

const GOAL_SECTORS: u64 = 8;
const GOAL_RINGS: [f64; 3] = [1.5, 4.0, 10.0];
const AHEAD_CLASSES: [f64; 2] = [1.0, 2.5];
const OBSTACLE_SECTORS: u64 = 8;
const OBSTACLE_RINGS: [f64; 2] = [0.6, 1.5];
/// Round or compact; long side facing; edge-on; none.
const SHAPE_CLASSES: u64 = 4;

/// Learning and state parameters of the pure-RL planner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PureRlParams {
    /// Obstacles in the state.
    pub obstacles: usize,
    /// Learning rate α.
    pub alpha: f64,
    /// Discount γ per decision.
    pub gamma: f64,
    /// Exploration rate at the start of training, decayed to [`Self::epsilon_min`].
    pub epsilon: f64,
    /// Smallest exploration rate.
    pub epsilon_min: f64,
    /// Episodes over which ε halves.
    pub epsilon_half_life: f64,
    /// Reward for reaching the goal.
    pub arrival_reward: f64,
    /// Reward for a collision (the episode ends).
    pub collision_reward: f64,
    /// Cost per second of motion.
    pub time_cost: f64,
    /// Choices per episode before it is cut off.
    pub max_decisions: usize,
    /// Radius of the body's disc, metres.
    pub radius: f64,
}

impl Default for PureRlParams {
    fn default() -> Self {
        PureRlParams {
            obstacles: 2,
            alpha: 0.25,
            gamma: 0.95,
            epsilon: 0.3,
            epsilon_min: 0.02,
            epsilon_half_life: 2000.0,
            arrival_reward: 10.0,
            collision_reward: -10.0,
            time_cost: 0.05,
            max_decisions: 150,
            radius: 0.3,
        }
    }
}

impl PureRlParams {
    /// The parameters whose state size follows Table 1 for a world of this density: `k` = 0,
    /// 2, 4 obstacles for sparse, semi-cluttered and cluttered.
    pub fn for_density(density: crate::maps::generate::Density) -> PureRlParams {
        use crate::maps::generate::Density;
        let obstacles = match density {
            Density::Sparse => 0,
            Density::Semi => 2,
            Density::Cluttered => 4,
        };
        PureRlParams { obstacles, ..PureRlParams::default() }
    }

    /// Number of state parameters: `4 + 3k`.
    pub fn state_parameters(&self) -> usize {
        4 + 3 * self.obstacles
    }

    /// Number of cells a dense table over this state would have for `intervals` intervals.
    pub fn state_cells(&self, intervals: usize) -> f64 {
        let goal = (GOAL_SECTORS * (GOAL_RINGS.len() as u64 + 1)) as f64;
        let ahead = (AHEAD_CLASSES.len() + 1) as f64;
        let per_obstacle = (OBSTACLE_SECTORS * (OBSTACLE_RINGS.len() as u64 + 1) * SHAPE_CLASSES) as f64;
        intervals as f64 * goal * ahead * per_obstacle.powi(self.obstacles as i32)
    }
}

/// How an episode ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ending {
    /// The goal circle was entered.
    Reached,
    /// The body's disc touched an obstacle.
    Collided,
    /// Out of decisions.
    TimedOut,
}

/// The trained table: action values per visited state, keyed by the encoded state.
#[derive(Debug, Clone)]
pub struct PureRl {
    /// Parameters.
    pub params: PureRlParams,
    /// Episodes trained.
    pub episodes: u64,
    table: BTreeMap<u64, Vec<f32>>,
    /// Values of the coarse states (no obstacles), trained alongside: a full state seen for
    /// the first time starts from them.
    coarse: BTreeMap<u64, Vec<f32>>,
}

/// A state: its full key and the key of the same state without the obstacles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct State {
    /// Every parameter.
    pub full: u64,
    /// The interval, the goal and the free distance ahead only.
    pub coarse: u64,
}

impl PureRl {
    /// An untrained table.
    pub fn new(params: PureRlParams) -> PureRl {
        PureRl { params, episodes: 0, table: BTreeMap::new(), coarse: BTreeMap::new() }
    }

    /// Visited states (full and coarse).
    pub fn visited_states(&self) -> usize {
        self.table.len() + self.coarse.len()
    }

    /// Stored action values (full and coarse states).
    pub fn stored_entries(&self) -> usize {
        self.table.values().chain(self.coarse.values()).map(Vec::len).sum()
    }

    /// Encodes the state at switch point `at` (see the module docs).
    pub fn state(&self, world: &World, at: &SwitchPoint, goal: DVec2, scratch: &mut Vec<usize>) -> State {
        let g = at.ground;
        let here = DVec2::new(g.x, g.y);
        let to_goal = goal - here;
        let sector = |angle: f64, n: u64| -> u64 {
            let a = wrap_angle(angle - g.yaw) + std::f64::consts::PI;
            ((a / std::f64::consts::TAU * n as f64).floor() as u64).min(n - 1)
        };
        let ring = |d: f64, edges: &[f64]| edges.iter().filter(|&&e| d >= e).count() as u64;
        let mut key = at.ending as u64;
        key = key * GOAL_SECTORS + sector(to_goal.to_angle(), GOAL_SECTORS);
        key = key * (GOAL_RINGS.len() as u64 + 1) + ring(to_goal.length(), &GOAL_RINGS);
        let heading = DVec2::from_angle(g.yaw);
        let ahead = free_ahead(world, here, heading, self.params.radius, AHEAD_CLASSES[1], scratch);
        key = key * (AHEAD_CLASSES.len() as u64 + 1) + ring(ahead, &AHEAD_CLASSES);
        let coarse = key;
        if self.params.obstacles > 0 {
            // The nearest obstacles by the distance to their surface.
            world.parts_near(here, SENSE_RANGE_M, scratch);
            let mut near: Vec<(f64, usize)> = Vec::new();
            for &p in scratch.iter() {
                let obstacle = world.parts()[p].obstacle;
                let d = world.parts()[p].shape.distance(here);
                if d <= SENSE_RANGE_M {
                    match near.iter_mut().find(|(_, o)| *o == obstacle) {
                        Some(e) => e.0 = e.0.min(d),
                        None => near.push((d, obstacle)),
                    }
                }
            }
            near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let cells = OBSTACLE_SECTORS * (OBSTACLE_RINGS.len() as u64 + 1) * SHAPE_CLASSES;
            for k in 0..self.params.obstacles {
                key = key.wrapping_mul(cells);
                let Some(&(d, o)) = near.get(k) else {
                    key = key.wrapping_add(cells - 1);
                    continue;
                };
                let obb = &world.obstacles()[o].obb;
                let to = obb.center - here;
                let long = obb.half_extents.x.max(obb.half_extents.y);
                let short = obb.half_extents.x.min(obb.half_extents.y);
                let shape = if long < 1.5 * short {
                    0
                } else {
                    // Axis of the long side against the line of sight.
                    let axis = if obb.half_extents.x >= obb.half_extents.y {
                        obb.yaw
                    } else {
                        obb.yaw + 0.5 * std::f64::consts::PI
                    };
                    let across = (DVec2::from_angle(axis).perp_dot(to.normalize_or_zero())).abs();
                    if across > std::f64::consts::FRAC_1_SQRT_2 { 1 } else { 2 }
                };
                let cell = (sector(to.to_angle(), OBSTACLE_SECTORS) * (OBSTACLE_RINGS.len() as u64 + 1)
                    + ring(d, &OBSTACLE_RINGS))
                    * SHAPE_CLASSES
                    + shape;
                key = key.wrapping_add(cell);
            }
        }
        State { full: key, coarse }
    }

    fn values(&self, state: State) -> Option<&[f32]> {
        self.table.get(&state.full).or_else(|| self.coarse.get(&state.coarse)).map(Vec::as_slice)
    }

    /// The greedy choice among `n` candidates (lowest index on ties; the natural successor,
    /// candidate 0, in a state never visited).
    pub fn greedy(&self, state: State, n: usize) -> usize {
        match self.values(state) {
            Some(v) => (0..n.min(v.len())).fold(0, |best, a| if v[a] > v[best] { a } else { best }),
            None => 0,
        }
    }

    fn choose(&self, state: State, n: usize, epsilon: f64, rng: &mut ChaCha8Rng) -> usize {
        if crate::rng::unit(rng) < epsilon {
            (rng.next_u64() % n.max(1) as u64) as usize
        } else {
            self.greedy(state, n)
        }
    }

    /// Plays one episode of `task` in `world`; with `learn`, explores with the current ε and
    /// updates the table (SARSA), else plays greedily. Returns how it ended and the decisions.
    pub fn episode(
        &mut self,
        db: &Database,
        world: &World,
        task: &Task,
        learn: bool,
        seed: u64,
        index: u64,
    ) -> (Ending, usize) {
        let mut rng = crate::rng::stream(seed, index, 0xba5e);
        let start = (0..db.intervals.len())
            .min_by(|&a, &b| db.intervals[a].speed.total_cmp(&db.intervals[b].speed).then(a.cmp(&b)))
            .unwrap_or(0);
        let ground = Ground { x: task.start.position.x, y: task.start.position.y, yaw: task.start.yaw };
        let mut at = Player::new(db, start, ground, PlayerParams::default()).upcoming_switch(db);
        let epsilon = if learn {
            (self.params.epsilon * 0.5f64.powf(self.episodes as f64 / self.params.epsilon_half_life))
                .max(self.params.epsilon_min)
        } else {
            0.0
        };
        let mut scratch = Vec::new();
        let mut path = Vec::new();
        let n_of = |at: &SwitchPoint| db.candidates[at.ending].len();
        let mut state = self.state(world, &at, task.goal, &mut scratch);
        let mut action = self.choose(state, n_of(&at), epsilon, &mut rng);
        let mut ending = Ending::TimedOut;
        let mut decisions = 0;
        let p = self.params;
        while decisions < p.max_decisions {
            decisions += 1;
            let before = DVec2::new(at.ground.x, at.ground.y).distance(task.goal);
            path.clear();
            at.path(db, Choice::from(action), &mut path);
            let mut outcome = None;
            for &q in &path {
                if !world.is_free(q, p.radius, &mut scratch) {
                    outcome = Some(Ending::Collided);
                    break;
                }
                if q.distance(task.goal) <= task.goal_radius {
                    outcome = Some(Ending::Reached);
                    break;
                }
            }
            let interval = db.candidates[at.ending][action].interval;
            let next = at.then(db, Choice::from(action));
            let after = DVec2::new(next.ground.x, next.ground.y).distance(task.goal);
            let reward = match outcome {
                Some(Ending::Collided) => p.collision_reward,
                Some(Ending::Reached) => p.arrival_reward,
                _ => (before - after) - p.time_cost * db.intervals[interval].duration,
            };
            if let Some(end) = outcome {
                if learn {
                    self.update(state, action, n_of(&at), reward, None);
                }
                ending = end;
                break;
            }
            let next_state = self.state(world, &next, task.goal, &mut scratch);
            let next_action = self.choose(next_state, n_of(&next), epsilon, &mut rng);
            if learn {
                self.update(state, action, n_of(&at), reward, Some((next_state, next_action)));
            }
            at = next;
            state = next_state;
            action = next_action;
        }
        if learn {
            self.episodes += 1;
        }
        (ending, decisions)
    }

    /// SARSA: `Q(s, a) += α (r + γ Q(s', a') − Q(s, a))` (no bootstrap at the end), for the
    /// full state (created from the coarse one's values) and for the coarse state.
    fn update(&mut self, state: State, action: usize, n: usize, reward: f64, next: Option<(State, usize)>) {
        let (alpha, gamma) = (self.params.alpha, self.params.gamma);
        let next_full = next.map(|(s, a)| self.values(s).and_then(|v| v.get(a)).copied().unwrap_or(0.0));
        let next_coarse = next.map(|(s, a)| self.coarse.get(&s.coarse).and_then(|v| v.get(a)).copied().unwrap_or(0.0));
        let seed = self.coarse.get(&state.coarse).cloned().unwrap_or_default();
        let learn = |v: &mut Vec<f32>, next: Option<f32>| {
            if v.len() < n {
                v.resize(n, 0.0);
            }
            let target = reward + next.map_or(0.0, |q| gamma * f64::from(q));
            let q = &mut v[action];
            *q += (alpha * (target - f64::from(*q))) as f32;
        };
        if self.params.obstacles > 0 {
            learn(self.table.entry(state.full).or_insert(seed), next_full);
        }
        learn(self.coarse.entry(state.coarse).or_default(), next_coarse);
    }
}

/// Free distance (up to `max`) a disc of `radius` can move from `p` along the unit `dir`.
fn free_ahead(world: &World, p: DVec2, dir: DVec2, radius: f64, max: f64, scratch: &mut Vec<usize>) -> f64 {
    let steps = 10;
    for k in 1..=steps {
        let d = max * k as f64 / steps as f64;
        if !world.sweep_is_free(p, p + dir * d, radius, scratch) {
            return max * (k - 1) as f64 / steps as f64;
        }
    }
    max
}
