//! How far a walker can still get (beyond seed 002, whose planner admits it is incomplete): an
//! exhaustive, memoised search over the same step set as the window, so the planner never
//! commits to a step after which the goal — or, when the goal cannot be reached at all, the
//! furthest reachable foothold — is out of reach.
//!
//! A state is the pair of footholds (rear, front) as micrometre offsets from the start; a step
//! depends on nothing else (the rear foot swings past the front one). Steps only go forward,
//! so states form a directed acyclic graph and a depth-first search with "alive" and "dead"
//! marks is exact. The target is fixed once, from the start: the goal when some sequence of
//! steps reaches it, else the furthest foothold any sequence reaches. A relaxation over single
//! footholds (footholds, height limits and double support only, no swing) bounds that target
//! from above cheaply, so the exhaustive search runs to the end only when the swing itself is
//! what blocks the way.

use std::collections::{BTreeSet, HashMap, HashSet};

use super::FootstepParams;
use super::foothold::{Sole, StepFailure, height_change, sole_at};
use super::legs::{Swing, can_stand};
use super::step::{StepSet, check_soles, position_m};
use crate::ground::GroundProfile;

/// Footholds (rear, front), micrometres from the start.
pub(crate) type State = (i64, i64);

/// The ground, the parameters and a cache of where soles can stand.
#[derive(Clone)]
pub(crate) struct StepModel<'a> {
    pub(crate) ground: &'a GroundProfile,
    pub(crate) params: FootstepParams,
    pub(crate) start_m: f64,
    soles: HashMap<i64, Result<Sole, StepFailure>>,
}

impl<'a> StepModel<'a> {
    pub(crate) fn new(ground: &'a GroundProfile, params: FootstepParams, start_m: f64) -> Self {
        StepModel { ground, params, start_m, soles: HashMap::new() }
    }

    /// Position of a foothold, metres.
    pub(crate) fn x_of(&self, offset_um: i64) -> f64 {
        position_m(self.start_m, offset_um)
    }

    /// Takes `sole` as the sole at a foothold, as it is (a foot already planted there).
    pub(crate) fn plant(&mut self, offset_um: i64, sole: Sole) {
        self.soles.insert(offset_um, Ok(Sole { x_m: self.x_of(offset_um), ..sole }));
    }

    /// The sole at a foothold (cached).
    pub(crate) fn sole(&mut self, offset_um: i64) -> Result<Sole, StepFailure> {
        if let Some(s) = self.soles.get(&offset_um) {
            return *s;
        }
        let s = sole_at(self.ground, &self.params, self.x_of(offset_um));
        self.soles.insert(offset_um, s);
        s
    }

    /// The checks of a step from `from` to `to` that do not depend on the swing: a necessary
    /// condition of every step onto `to` from a stance at `from`.
    fn relaxed(&mut self, from: i64, to: i64) -> Result<(), StepFailure> {
        let b = self.sole(from)?;
        let c = self.sole(to)?;
        height_change(&self.params, &b, &c)?;
        can_stand(&self.params, &b, &c)
    }

    /// The whole step: the foot at `lift_off` swings past `stance` to `touch_down`.
    pub(crate) fn step(&mut self, lift_off: i64, stance: i64, touch_down: i64) -> Result<Swing, StepFailure> {
        let c = self.sole(touch_down)?;
        let a = self.sole(lift_off)?;
        let b = self.sole(stance)?;
        check_soles(self.ground, &self.params, a, b, c)
    }
}

/// What the walker must keep within reach.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Target {
    /// A foothold at or beyond the goal.
    Goal,
    /// The furthest foothold any sequence of steps reaches (the goal cannot be reached).
    Offset(i64),
}

/// One state being expanded by the depth-first search.
struct Frame {
    state: State,
    children: Vec<i64>,
    next: usize,
}

/// The memoised search; see the [module docs](self).
#[derive(Clone)]
pub(crate) struct Reachability {
    pub(crate) target: Target,
    goal_m: f64,
    /// Step indices, the preferred step first, then by distance from it (longer first).
    order: Vec<usize>,
    alive: HashSet<State>,
    dead: HashSet<State>,
    /// For a foothold, the next footholds making alive states with it.
    alive_from: HashMap<i64, Vec<i64>>,
    best_seen: i64,
}

impl Reachability {
    /// Fixes the target from the walker's first state `root`.
    pub(crate) fn new(model: &mut StepModel<'_>, steps: &StepSet, goal_m: f64, root: State) -> Reachability {
        let init = steps.nominal();
        let mut order: Vec<usize> = (0..steps.len()).collect();
        order.sort_by_key(|&j| (j.abs_diff(init), std::cmp::Reverse(j)));
        let mut r = Reachability {
            target: Target::Goal,
            goal_m,
            order,
            alive: HashSet::new(),
            dead: HashSet::new(),
            alive_from: HashMap::new(),
            best_seen: root.1,
        };
        r.target = r.relaxed_target(model, steps, root.1);
        if r.can_reach(model, steps, root) {
            return r;
        }
        // Every state reachable from the root has been searched: the best foothold seen is the
        // furthest any sequence of steps reaches. Search again for a way to it.
        r.target = Target::Offset(r.best_seen);
        r.alive.clear();
        r.dead.clear();
        r.alive_from.clear();
        r.can_reach(model, steps, root);
        r
    }

    /// Whether a foothold meets the target.
    pub(crate) fn meets(&self, model: &StepModel<'_>, offset_um: i64) -> bool {
        match self.target {
            Target::Goal => model.x_of(offset_um) >= self.goal_m,
            Target::Offset(t) => offset_um >= t,
        }
    }

    /// The target of the relaxation over single footholds: the goal if it reaches it, else the
    /// furthest foothold it reaches (an upper bound of the true one).
    fn relaxed_target(&self, model: &mut StepModel<'_>, steps: &StepSet, from: i64) -> Target {
        let mut seen = HashSet::from([from]);
        let mut queue = BTreeSet::from([from]);
        let mut best = from;
        while let Some(p) = queue.pop_first() {
            if model.x_of(p) >= self.goal_m {
                return Target::Goal;
            }
            best = best.max(p);
            for &s in steps.lengths_um() {
                let n = p + s;
                if !seen.contains(&n) && model.relaxed(p, n).is_ok() {
                    seen.insert(n);
                    queue.insert(n);
                }
            }
        }
        Target::Offset(best)
    }

    /// Next footholds from `front`, in search order: into known alive states first, then onto
    /// footholds known to start one, then the preferred step first.
    fn children(&self, steps: &StepSet, front: i64) -> Vec<i64> {
        let mut c: Vec<(u8, i64)> = self
            .order
            .iter()
            .map(|&j| {
                let n = front + steps.lengths_um()[j];
                let rank = if self.alive.contains(&(front, n)) {
                    0
                } else if self.alive_from.contains_key(&n) {
                    1
                } else {
                    2
                };
                (rank, n)
            })
            .collect();
        c.sort_by_key(|&(rank, _)| rank);
        c.into_iter().map(|(_, n)| n).collect()
    }

    fn mark_alive(&mut self, s: State) {
        if self.alive.insert(s) {
            self.alive_from.entry(s.0).or_default().push(s.1);
        }
    }

    /// Whether some sequence of valid steps from `root` meets the target.
    pub(crate) fn can_reach(&mut self, model: &mut StepModel<'_>, steps: &StepSet, root: State) -> bool {
        if self.meets(model, root.1) || self.alive.contains(&root) {
            return true;
        }
        if self.dead.contains(&root) {
            return false;
        }
        let mut stack = vec![Frame { state: root, children: self.children(steps, root.1), next: 0 }];
        while let Some(top) = stack.last_mut() {
            let Some(&n) = top.children.get(top.next) else {
                let s = top.state;
                stack.pop();
                self.dead.insert(s);
                continue;
            };
            top.next += 1;
            let (a, b) = top.state;
            let child = (b, n);
            if self.dead.contains(&child) || model.step(a, b, n).is_err() {
                continue;
            }
            self.best_seen = self.best_seen.max(n);
            if self.meets(model, n) || self.alive.contains(&child) {
                for f in &stack {
                    let s = f.state;
                    self.mark_alive(s);
                }
                return true;
            }
            let children = self.children(steps, n);
            stack.push(Frame { state: child, children, next: 0 });
        }
        false
    }
}
