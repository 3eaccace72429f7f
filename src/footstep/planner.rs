//! The sliding-window footstep planner (seed 002 §4.2) and whole walks over a profile.
//!
//! A configuration is the lengths of the next `n` steps, `q = (s_1..s_n)`, each one of the
//! `m + 1` values of the [`StepSet`]. Starting from `q_init = (s_init, …)` — or, after a step,
//! from the previous window slid by one, `(s_2..s_n, s_init)` — a breadth-first search over
//! the configurations (neighbours differ by one interval in one step) finds an admissible one;
//! a local search then moves to the best admissible neighbour under the energy cost — one step
//! an interval longer or shorter, or an interval moved from one step to another — until no
//! neighbour is better; only `s_1` is executed.
//!
//! A configuration is admissible when each of its steps is valid (the foothold, the height
//! limits, the swing raised until clear, both legs in reach; see
//! [`check_step`](super::check_step)) up to the one that meets the target, and — beyond the paper — when the window does not meet the target,
//! some sequence of steps from its last footholds does: the horizon is widened over the whole
//! visible profile by an exhaustive, memoised search over the same step set. The target is the
//! goal if any sequence of steps reaches it, else the furthest foothold any sequence reaches;
//! there the walker stops and says why. So the planner crosses every profile an exhaustive
//! search crosses, stops only where no sequence of steps reaches further, and never returns an
//! invalid step.
//!
//! The energy of a step: `((s − s_init) / 0.1 m)² + 2 · rise / 0.1 m + drop / 0.1 m +
//! (swing raise beyond the nominal) / 0.1 m` — keep the preferred stride, climb and descend
//! little, lift the foot no higher than needed.
//!
//! Footholds lie on a lattice: the start plus whole micrometres, step lengths being rounded
//! to the micrometre, so positions reached by different sequences compare exactly.

use std::collections::VecDeque;
use std::fmt;

use super::foothold::{Foot, Foothold, Sole, StepFailure};
use super::legs::Swing;
use super::reach::{Reachability, State, StepModel};
use super::step::StepSet;
use super::{FootstepParams, ParamsError};
use crate::ground::{Course, GroundProfile, Hazard, ProfileError};

/// How steps are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlannerMode {
    /// The sliding-window planner (seed 002 §4.2) with the widened horizon.
    Window,
    /// No planning: always the nominal step, stopping before the first invalid one (seed 002
    /// Fig 8 (a)).
    Nominal,
}

/// Why a walker stopped short of the goal.
#[derive(Debug, Clone, PartialEq)]
pub enum StopReason {
    /// No sequence of steps from the step set reaches beyond the current foothold.
    NoFurtherStep {
        /// The front foothold, metres.
        at_m: f64,
        /// The goal, metres.
        goal_m: f64,
        /// What lies ahead.
        ahead: Option<Hazard>,
    },
    /// Without planning: the nominal step is not valid.
    NominalStepInvalid {
        /// The nominal step, metres.
        step_m: f64,
        /// Where it would land, metres.
        x_m: f64,
        /// Why it is not valid.
        failure: StepFailure,
    },
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::NoFurtherStep { at_m, goal_m, ahead } => {
                write!(f, "no sequence of steps reaches beyond x = {at_m:.2} m (goal at {goal_m:.2} m)")?;
                match ahead {
                    Some(h) => write!(f, "; ahead: {h}"),
                    None => Ok(()),
                }
            }
            StopReason::NominalStepInvalid { step_m, x_m, failure } => {
                write!(f, "the nominal step of {step_m:.2} m would land at x = {x_m:.2} m: {failure}")
            }
        }
    }
}

/// Why a planner cannot be set up.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    /// Bad parameters.
    #[error("footstep parameters: {0}")]
    Params(#[from] ParamsError),
    /// Bad start or goal.
    #[error("{0}")]
    Course(#[from] ProfileError),
    /// The feet cannot stand at the start.
    #[error("the feet cannot stand at the start (x = {x_m}): {failure}")]
    Start {
        /// The start, metres.
        x_m: f64,
        /// Why.
        failure: StepFailure,
    },
}

/// A step the planner chose.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedStep {
    /// The swinging foot.
    pub foot: Foot,
    /// Its legs, from lift-off to touch-down.
    pub swing: Swing,
    /// The configuration it is the first step of, metres (just the step without planning).
    pub window_m: Vec<f64>,
    /// Configurations the search queued or evaluated (0 without planning).
    pub configurations: usize,
}

/// What the planner says at a step.
#[derive(Debug, Clone, PartialEq)]
pub enum Decision {
    /// Take this step (it is already recorded as taken).
    Step(PlannedStep),
    /// A foothold is at or beyond the goal.
    Reached,
    /// The walker stops here.
    Stopped(StopReason),
}

/// The verdict of a prefix of steps in the window.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cell {
    Unknown,
    Invalid,
    Valid { energy: f64, meets: bool },
}

/// Tables of one window search, reused from step to step (only touched entries are reset).
#[derive(Debug, Clone)]
struct WindowTable {
    radix: usize,
    cells: Vec<Vec<Cell>>,
    touched_cells: Vec<(usize, usize)>,
    verdict: Vec<Option<Option<f64>>>,
    visited: Vec<bool>,
    touched: Vec<usize>,
}

impl WindowTable {
    fn new(radix: usize, n: usize) -> WindowTable {
        let cells = (1..=n).map(|i| vec![Cell::Unknown; radix.pow(i as u32)]).collect();
        let size = radix.pow(n as u32);
        WindowTable {
            radix,
            cells,
            touched_cells: Vec::new(),
            verdict: vec![None; size],
            visited: vec![false; size],
            touched: Vec::new(),
        }
    }

    fn reset(&mut self) {
        for &(level, i) in &self.touched_cells {
            self.cells[level][i] = Cell::Unknown;
        }
        for &i in &self.touched {
            self.verdict[i] = None;
            self.visited[i] = false;
        }
        self.touched_cells.clear();
        self.touched.clear();
    }

    fn index(&self, q: &[usize]) -> usize {
        q.iter().rev().fold(0, |acc, &j| acc * self.radix + j)
    }

    fn touch(&mut self, i: usize) {
        if self.verdict[i].is_none() && !self.visited[i] {
            self.touched.push(i);
        }
    }
}

/// What one window search needs besides its tables.
struct Search<'m, 'g> {
    model: &'m mut StepModel<'g>,
    reach: &'m mut Reachability,
    steps: &'m StepSet,
    state: State,
    nominal_m: f64,
}

impl Search<'_, '_> {
    /// The energy of `q` when admissible.
    fn evaluate(&mut self, table: &mut WindowTable, q: &[usize]) -> Option<f64> {
        let idx = table.index(q);
        if let Some(v) = table.verdict[idx] {
            return v;
        }
        table.touch(idx);
        let (mut a, mut b) = self.state;
        let (mut prefix, mut scale, mut cost) = (0, 1, 0.0);
        let mut verdict = None;
        let mut complete = true;
        for (level, &j) in q.iter().enumerate() {
            prefix += j * scale;
            scale *= table.radix;
            let n = b + self.steps.lengths_um()[j];
            if table.cells[level][prefix] == Cell::Unknown {
                let cell = match self.model.step(a, b, n) {
                    Ok(swing) => Cell::Valid {
                        energy: energy(&swing, self.steps.length_m(j), self.nominal_m),
                        meets: self.reach.meets(self.model, n),
                    },
                    Err(_) => Cell::Invalid,
                };
                table.cells[level][prefix] = cell;
                table.touched_cells.push((level, prefix));
            }
            match table.cells[level][prefix] {
                Cell::Valid { energy, meets } => {
                    cost += energy;
                    if meets {
                        verdict = Some(cost);
                        complete = false;
                        break;
                    }
                }
                _ => {
                    complete = false;
                    break;
                }
            }
            (a, b) = (b, n);
        }
        if complete && self.reach.can_reach(self.model, self.steps, (a, b)) {
            verdict = Some(cost);
        }
        table.verdict[idx] = Some(verdict);
        verdict
    }

    /// The neighbours of `q`: one step one interval shorter or longer.
    fn neighbours(radix: usize, q: &[usize]) -> impl Iterator<Item = Vec<usize>> + '_ {
        (0..q.len()).flat_map(move |i| {
            [q[i].checked_sub(1), Some(q[i] + 1).filter(|&j| j < radix)].into_iter().flatten().map(move |j| {
                let mut r = q.to_vec();
                r[i] = j;
                r
            })
        })
    }

    /// The configurations with one interval moved from one step to another: the same
    /// distance covered with the lengths shared differently.
    fn transfers(radix: usize, q: &[usize]) -> impl Iterator<Item = Vec<usize>> + '_ {
        let n = q.len();
        (0..n)
            .flat_map(move |i| (0..n).map(move |k| (i, k)))
            .filter(move |&(i, k)| i != k && q[i] + 1 < radix && q[k] > 0)
            .map(move |(i, k)| {
                let mut r = q.to_vec();
                r[i] += 1;
                r[k] -= 1;
                r
            })
    }

    /// Breadth-first search from `q0` for an admissible configuration, then local search.
    fn run(&mut self, table: &mut WindowTable, q0: Vec<usize>) -> Option<(Vec<usize>, usize)> {
        table.reset();
        let radix = table.radix;
        let mut queue = VecDeque::from([q0.clone()]);
        let i0 = table.index(&q0);
        table.touch(i0);
        table.visited[i0] = true;
        let mut found = None;
        while let Some(q) = queue.pop_front() {
            if let Some(cost) = self.evaluate(table, &q) {
                found = Some((q, cost));
                break;
            }
            for nb in Self::neighbours(radix, &q) {
                let i = table.index(&nb);
                if !table.visited[i] {
                    table.touch(i);
                    table.visited[i] = true;
                    queue.push_back(nb);
                }
            }
        }
        let (mut q, mut cost) = found?;
        loop {
            let mut best: Option<(Vec<usize>, f64)> = None;
            for nb in Self::neighbours(radix, &q).chain(Self::transfers(radix, &q)) {
                if let Some(c) = self.evaluate(table, &nb)
                    && c < cost - 1e-12
                    && best.as_ref().is_none_or(|(_, b)| c < *b)
                {
                    best = Some((nb, c));
                }
            }
            match best {
                Some((nb, c)) => (q, cost) = (nb, c),
                None => break,
            }
        }
        Some((q, table.touched.len()))
    }
}

/// The energy of a step; see the [module docs](self).
fn energy(swing: &Swing, step_m: f64, nominal_m: f64) -> f64 {
    const UNIT_M: f64 = 0.1;
    let stride = (step_m - nominal_m) / UNIT_M;
    let rise = swing.touch_down.z_m - swing.stance.z_m;
    let raise = swing.control_height_m - swing.nominal_control_height_m;
    stride * stride + (2.0 * rise.max(0.0) + (-rise).max(0.0) + raise.max(0.0)) / UNIT_M
}

/// The footstep planner over one ground profile: call [`next_step`](Self::next_step) with the
/// nominal step of each new step (the animation's interval gives it); the planner keeps the
/// footholds taken so far and the window to slide. A clone continues independently.
#[derive(Clone)]
pub struct FootstepPlanner<'g> {
    model: StepModel<'g>,
    steps: StepSet,
    goal_m: f64,
    mode: PlannerMode,
    state: State,
    next_foot: Foot,
    footholds: Vec<Foothold>,
    reach: Option<Reachability>,
    carry: Option<Vec<usize>>,
    table: Option<WindowTable>,
}

impl<'g> FootstepPlanner<'g> {
    /// A planner for a walker standing with both feet at `start_m` on `ground`, walking toward
    /// `goal_m`.
    pub fn new(
        ground: &'g GroundProfile,
        start_m: f64,
        goal_m: f64,
        params: FootstepParams,
        mode: PlannerMode,
    ) -> Result<FootstepPlanner<'g>, PlanError> {
        params.validate()?;
        if !start_m.is_finite() || !goal_m.is_finite() || goal_m < start_m {
            return Err(PlanError::Course(ProfileError::Course(format!(
                "start {start_m} and goal {goal_m} must be finite with the goal not before the start"
            ))));
        }
        let mut model = StepModel::new(ground, params, start_m);
        let sole = model.sole(0).map_err(|failure| PlanError::Start { x_m: start_m, failure })?;
        let footholds = vec![Foothold { foot: Foot::Left, sole }, Foothold { foot: Foot::Right, sole }];
        Ok(FootstepPlanner {
            model,
            steps: StepSet::new(&params),
            goal_m,
            mode,
            state: (0, 0),
            next_foot: Foot::Left,
            footholds,
            reach: None,
            carry: None,
            table: None,
        })
    }

    /// A planner for a walker already under way on `ground`: its rear foot at `rear_m`, the
    /// front one at `front_m` (not behind it), `next` the foot to swing next (the rear one),
    /// walking toward `goal_m`. Footholds lie on the lattice of whole micrometres from the rear
    /// foot.
    #[allow(clippy::too_many_arguments)]
    pub fn from_stance(
        ground: &'g GroundProfile,
        rear_m: f64,
        front_m: f64,
        next: Foot,
        goal_m: f64,
        params: FootstepParams,
        mode: PlannerMode,
    ) -> Result<FootstepPlanner<'g>, PlanError> {
        let mut planner = FootstepPlanner::new(ground, rear_m, goal_m.max(rear_m), params, mode)?;
        if !(front_m.is_finite() && front_m >= rear_m) {
            return Err(PlanError::Course(ProfileError::Course(format!(
                "the front foot ({front_m}) must not be behind the rear one ({rear_m})"
            ))));
        }
        let b = ((front_m - rear_m) * 1e6).round() as i64;
        let sole = planner.model.sole(b).map_err(|failure| PlanError::Start { x_m: front_m, failure })?;
        planner.state = (0, b);
        planner.next_foot = next;
        planner.footholds = vec![planner.footholds[0], Foothold { foot: next.other(), sole }];
        planner.footholds[0].foot = next;
        Ok(planner)
    }

    /// A planner for a walker whose feet are planted now: `rear` (the foot to swing next,
    /// `next`) and `front` (not behind it), walking toward `goal_m` on `ground`. The planted
    /// soles are taken as they are: they were valid footholds when they were planted, though
    /// the ground along a new heading may not hold them any more. Footholds lie on the lattice
    /// of whole micrometres from the rear foot.
    #[allow(clippy::too_many_arguments)]
    pub fn from_planted(
        ground: &'g GroundProfile,
        rear: Sole,
        front: Sole,
        next: Foot,
        goal_m: f64,
        params: FootstepParams,
        mode: PlannerMode,
    ) -> Result<FootstepPlanner<'g>, PlanError> {
        params.validate()?;
        let finite = [rear.x_m, rear.z_m, rear.pitch_rad, front.x_m, front.z_m, front.pitch_rad, goal_m];
        if !finite.iter().all(|v| v.is_finite()) || front.x_m < rear.x_m {
            return Err(PlanError::Course(ProfileError::Course(format!(
                "planted feet at {} and {} and goal {goal_m} must be finite, the front foot not behind the rear one",
                rear.x_m, front.x_m
            ))));
        }
        let mut model = StepModel::new(ground, params, rear.x_m);
        let b = ((front.x_m - rear.x_m) * 1e6).round() as i64;
        model.plant(0, rear);
        model.plant(b, front);
        let at = |offset: i64, foot: Foot, model: &mut StepModel| {
            model
                .sole(offset)
                .map(|sole| Foothold { foot, sole })
                .map_err(|failure| PlanError::Start { x_m: model.x_of(offset), failure })
        };
        let footholds = vec![at(0, next, &mut model)?, at(b, next.other(), &mut model)?];
        Ok(FootstepPlanner {
            model,
            steps: StepSet::new(&params),
            goal_m: goal_m.max(rear.x_m),
            mode,
            state: (0, b),
            next_foot: next,
            footholds,
            reach: None,
            carry: None,
            table: None,
        })
    }

    /// A planner for `course` (its ground, start and goal).
    pub fn for_course(
        course: &'g Course,
        params: FootstepParams,
        mode: PlannerMode,
    ) -> Result<FootstepPlanner<'g>, PlanError> {
        FootstepPlanner::new(&course.ground, course.start_m, course.goal_m, params, mode)
    }

    /// The footholds so far, the two of the initial stance first.
    pub fn footholds(&self) -> &[Foothold] {
        &self.footholds
    }

    /// The parameters.
    pub fn params(&self) -> &FootstepParams {
        &self.model.params
    }

    /// The step set.
    pub fn step_set(&self) -> &StepSet {
        &self.steps
    }

    /// Whether the front foothold is at or beyond the goal.
    pub fn reached(&self) -> bool {
        self.model.x_of(self.state.1) >= self.goal_m
    }

    /// Plans and takes the next step, `nominal_step_m` being the preferred one (snapped to the
    /// step set); or says the goal is reached, or why the walker stops.
    pub fn next_step(&mut self, nominal_step_m: f64) -> Decision {
        if self.reached() {
            return Decision::Reached;
        }
        let params = self.model.params;
        let j_init = params.step_index(nominal_step_m);
        let (a, b) = self.state;
        if self.mode == PlannerMode::Nominal {
            let n = b + self.steps.lengths_um()[j_init];
            return match self.model.step(a, b, n) {
                Ok(swing) => self.take(n, swing, vec![j_init], 0),
                Err(failure) => Decision::Stopped(StopReason::NominalStepInvalid {
                    step_m: self.steps.length_m(j_init),
                    x_m: self.model.x_of(n),
                    failure,
                }),
            };
        }
        let reach = match &mut self.reach {
            Some(r) => r,
            None => self.reach.insert(Reachability::new(&mut self.model, &self.steps, self.goal_m, self.state)),
        };
        let n = params.window_steps;
        let table = self.table.get_or_insert_with(|| WindowTable::new(self.steps.len(), n));
        let chosen = if reach.meets(&self.model, b) {
            None
        } else {
            let q0 = match self.carry.take() {
                Some(mut q) => {
                    q.push(j_init);
                    q
                }
                None => vec![j_init; n],
            };
            let mut search = Search {
                model: &mut self.model,
                reach,
                steps: &self.steps,
                state: self.state,
                nominal_m: self.steps.length_m(j_init),
            };
            search.run(table, q0)
        };
        let Some((q, configurations)) = chosen else {
            let at_m = self.model.x_of(b);
            let ahead = self.model.ground.next_hazard(at_m, params.max_slope_deg);
            return Decision::Stopped(StopReason::NoFurtherStep { at_m, goal_m: self.goal_m, ahead });
        };
        let next = b + self.steps.lengths_um()[q[0]];
        match self.model.step(a, b, next) {
            Ok(swing) => {
                self.carry = Some(q[1..].to_vec());
                self.take(next, swing, q, configurations)
            }
            // Unreachable: admissible configurations have valid steps. Stop rather than move.
            Err(failure) => Decision::Stopped(StopReason::NominalStepInvalid {
                step_m: self.steps.length_m(q[0]),
                x_m: self.model.x_of(next),
                failure,
            }),
        }
    }

    fn take(&mut self, next: i64, swing: Swing, q: Vec<usize>, configurations: usize) -> Decision {
        let foot = self.next_foot;
        self.footholds.push(Foothold { foot, sole: swing.touch_down });
        self.state = (self.state.1, next);
        self.next_foot = foot.other();
        let window_m = q.iter().map(|&j| self.steps.length_m(j)).collect();
        Decision::Step(PlannedStep { foot, swing, window_m, configurations })
    }
}

/// How a walk ended.
#[derive(Debug, Clone, PartialEq)]
pub enum WalkOutcome {
    /// A foothold is at or beyond the goal.
    Reached,
    /// Stopped short, for this reason.
    Stopped(StopReason),
}

/// A whole walk over a course.
#[derive(Debug, Clone, PartialEq)]
pub struct Walk {
    /// Footholds in order, the two of the initial stance first.
    pub footholds: Vec<Foothold>,
    /// The steps, in order.
    pub steps: Vec<PlannedStep>,
    /// How it ended.
    pub outcome: WalkOutcome,
}

impl Walk {
    /// Whether the goal was reached.
    pub fn reached(&self) -> bool {
        self.outcome == WalkOutcome::Reached
    }
}

/// Walks `course` from start to goal (or as far as the steps go) with the nominal step of
/// `params`.
pub fn walk(course: &Course, params: FootstepParams, mode: PlannerMode) -> Result<Walk, PlanError> {
    let mut planner = FootstepPlanner::for_course(course, params, mode)?;
    let mut steps = Vec::new();
    let outcome = loop {
        match planner.next_step(params.step_init_m) {
            Decision::Step(s) => steps.push(s),
            Decision::Reached => break WalkOutcome::Reached,
            Decision::Stopped(r) => break WalkOutcome::Stopped(r),
        }
    };
    Ok(Walk { footholds: planner.footholds().to_vec(), steps, outcome })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ground::{GroundPiece, parse};

    fn course(text: &str) -> Course {
        parse(text, "t.profile").unwrap()
    }

    #[test]
    fn flat_ground_is_walked_with_the_nominal_step() {
        let c = course("start 0\ngoal 5\nground -1 0 7 0\n");
        for mode in [PlannerMode::Window, PlannerMode::Nominal] {
            let w = walk(&c, FootstepParams::default(), mode).unwrap();
            assert!(w.reached());
            assert_eq!(w.footholds.len(), 2 + 8);
            for (i, s) in w.steps.iter().enumerate() {
                assert!((s.swing.length_m() - 0.65).abs() < 1e-9, "step {i}: {}", s.swing.length_m());
                assert_eq!(s.swing.control_height_m, s.swing.nominal_control_height_m);
                assert_eq!(s.foot, if i % 2 == 0 { Foot::Left } else { Foot::Right });
            }
        }
    }

    #[test]
    fn planted_feet_are_taken_as_they_are() {
        // The front foot overhangs a gap along this profile (the walker turned since it was
        // planted): a stance on the profile alone is refused, the planted one is not, and the
        // steps from it are checked as usual.
        let c = course("start 0\ngoal 5\nground -1 0 0.05 0\nground 0.2 0 7 0\n");
        let p = FootstepParams::default();
        let stance = FootstepPlanner::from_stance(&c.ground, -0.6, 0.0, Foot::Left, 4.0, p, PlannerMode::Window);
        assert!(matches!(stance, Err(PlanError::Start { .. })));
        let rear = Sole { x_m: -0.6, z_m: 0.0, pitch_rad: 0.0 };
        let front = Sole { x_m: 0.0, ..rear };
        let mut planner =
            FootstepPlanner::from_planted(&c.ground, rear, front, Foot::Left, 4.0, p, PlannerMode::Window).unwrap();
        assert_eq!(planner.footholds()[1].sole, front);
        assert_eq!(planner.footholds()[0].foot, Foot::Left);
        let Decision::Step(s) = planner.next_step(0.65) else { panic!("no step") };
        assert_eq!(s.foot, Foot::Left);
        assert!(s.swing.touch_down.x_m >= 0.2 + 0.12 - 1e-9, "{:?}", s.swing.touch_down);
        let bad = Sole { x_m: f64::NAN, ..rear };
        assert!(FootstepPlanner::from_planted(&c.ground, bad, front, Foot::Left, 4.0, p, PlannerMode::Window).is_err());
        assert!(
            FootstepPlanner::from_planted(&c.ground, front, rear, Foot::Left, 4.0, p, PlannerMode::Window).is_err()
        );
    }

    #[test]
    fn the_window_slides() {
        let c = course("start 0\ngoal 5\nground -1 0 7 0\n");
        let mut p = FootstepPlanner::for_course(&c, FootstepParams::default(), PlannerMode::Window).unwrap();
        let Decision::Step(s) = p.next_step(0.65) else { panic!() };
        assert_eq!(s.window_m.len(), 3);
        assert!(s.configurations >= 1);
        // A shorter nominal step: the slid window (0.65, 0.65, 0.5) is where the search
        // starts, and the energy pulls every step to the new preference.
        let Decision::Step(s) = p.next_step(0.5) else { panic!() };
        assert!((s.window_m[0] - 0.5).abs() < 1e-9, "{:?}", s.window_m);
    }

    #[test]
    fn the_fig8_trap_needs_the_planner() {
        let c = course("start 0\ngoal 6\nground -1 0 3 0\nground 3.6 0 8 0\n");
        let off = walk(&c, FootstepParams::default(), PlannerMode::Nominal).unwrap();
        assert!(!off.reached());
        assert!(off.footholds.last().unwrap().sole.x_m < 3.0);
        let WalkOutcome::Stopped(StopReason::NominalStepInvalid { .. }) = off.outcome else { panic!() };
        let on = walk(&c, FootstepParams::default(), PlannerMode::Window).unwrap();
        assert!(on.reached(), "{:?}", on.outcome);
    }

    #[test]
    fn the_widened_horizon_sees_what_the_window_does_not() {
        // A window of one step cannot see the gap coming; the exhaustive look-ahead does, and
        // the walker shortens its steps well before the edge.
        let c = course("start 0\ngoal 6\nground -1 0 3 0\nground 3.6 0 8 0\n");
        let params = FootstepParams { window_steps: 1, ..FootstepParams::default() };
        let w = walk(&c, params, PlannerMode::Window).unwrap();
        assert!(w.reached(), "{:?}", w.outcome);
        assert!(w.footholds.iter().any(|f| (2.82..=2.88).contains(&f.sole.x_m)));
    }

    #[test]
    fn a_gap_too_wide_stops_at_the_edge_with_a_reason() {
        let c = course("start 0\ngoal 6\nground -1 0 3 0\nground 4.2 0 8 0\n");
        let w = walk(&c, FootstepParams::default(), PlannerMode::Window).unwrap();
        let WalkOutcome::Stopped(reason) = &w.outcome else { panic!() };
        let last = w.footholds.last().unwrap().sole.x_m;
        assert!((2.83..=2.88).contains(&last), "the furthest foothold before the edge: {last}");
        let text = reason.to_string();
        assert!(text.contains("a gap from x = 3.00 m to 4.20 m"), "{text}");
    }

    #[test]
    fn a_bad_start_is_an_error() {
        let g = GroundProfile::new(vec![GroundPiece { x0_m: 0.0, z0_m: 0.0, x1_m: 1.0, z1_m: 0.0 }]).unwrap();
        let e = FootstepPlanner::new(&g, 0.05, 1.0, FootstepParams::default(), PlannerMode::Window).err().unwrap();
        assert!(matches!(e, PlanError::Start { .. }), "{e}");
        let bad = FootstepParams { intervals: 0, ..FootstepParams::default() };
        let e = FootstepPlanner::new(&g, 0.5, 1.0, bad, PlannerMode::Window).err().unwrap();
        assert!(e.to_string().contains("intervals = 0"), "{e}");
    }
}
