//! Reference optimal paths among obstacles grown by the agent radius (DESIGN.md §1).
//!
//! Navigation runs are judged by the path-length ratio of seed 000 §4: the length the agent
//! actually travelled divided by the length of the shortest collision-free path. This module
//! computes that denominator, exactly. A disc-shaped agent of radius `r` is collision-free
//! exactly when its centre stays out of the interior of every obstacle part grown by `r` (the
//! Minkowski sum with a disc: circles get radius `radius + r`, polygons get rounded corners),
//! so the problem is a shortest path for a point among the grown parts.
//!
//! Method: the tangent visibility graph (`visibility.rs`). The grown parts are bounded by
//! straight edges and circular arcs, the *rims* (`rim.rs`): a circle of radius `r` at every
//! polygon corner, of which the arc between its two edges' normals is on the boundary, and
//! each grown disc's circle. A shortest path is taut: straight legs, each tangent to a rim at
//! both ends, joined by arcs along the rims, and a leg along a grown straight edge is the
//! tangent of its two corners' rims. Legs are the rims' bitangents in closed form; a rim's
//! *free arcs* are where no other grown part covers it, and a path may run along a rim only
//! within one free arc. A* over the points where legs meet rims, with the straight-line
//! distance to the goal as its heuristic (consistent: an arc is longer than its chord, so the
//! result is Dijkstra's), finds the shortest route; a rim's legs are looked for the first time
//! a search reaches it and kept for every later search (the graph of a world is built once,
//! as far as searches need it), and looking for them walks the obstacles nearest first and
//! skips those hidden behind nearer ones, so it costs what is in sight, not the size of the
//! map. The world's parts are indexed with [`crate::geom::SpatialIndex`] over their grown
//! boxes; a segment test visits the boxes along the segment front to back and stops at the
//! first part that blocks it.
//!
//! Accuracy: the length is the shortest among paths that keep `r − ε` from every part (the
//! tolerance `ε` of [`Planner`]), up to rounding (within 1e-9 relative): legs and arcs are in
//! closed form, and blocking is decided against the exact grown shapes.
//!
//! Invariants:
//! - A returned [`Path`] starts at the start, ends at the goal, and every leg and arc keeps at
//!   least `agent_radius - tolerance` metres from every world part.
//! - `Path::length` is the sum of its straight legs and arcs.
//! - Results are deterministic and do not depend on what earlier searches in the same world
//!   found (a rim's legs are the same whenever they are found): no hashing, ties in the
//!   search broken by state index.
//! - Skipping hidden obstacles never changes a result (test
//!   `hiding_what_is_behind_nearer_obstacles_changes_no_leg`).
//! - Nothing panics on bad input: non-finite points or radii give `None`.
//!
//! Units: metres, radians.

mod clearance;
pub(crate) use clearance::point_segment_distance;
mod rim;
mod visibility;

use std::cell::OnceCell;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::DVec2;

use crate::world::World;
use clearance::Clearance;
use rim::{Spot, Turn};
use visibility::{Graph, Leg, Legs, RimId};

/// A shortest path: straight legs joined by arcs along the rims it bends round.
#[derive(Debug, Clone, PartialEq)]
pub struct Path {
    /// The start, then where the path meets and where it leaves each rim it bends round
    /// ([`Path::bends`], in order), then the goal, metres: leg `i` runs straight from point
    /// `2i` to point `2i + 1`, bend `i` along its rim from point `2i + 1` to point `2i + 2`.
    pub points: Vec<DVec2>,
    /// The rims the path bends round, in order.
    pub bends: Vec<Bend>,
    /// Total length of the legs and arcs, metres.
    pub length: f64,
}

/// A stretch of a [`Path`] along a rim: an arc of a grown obstacle's boundary (for a point
/// agent round a polygon corner, a turn on the spot).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bend {
    /// Centre of the rim, metres.
    pub center: DVec2,
    /// Radius of the rim, metres (0: a corner of a polygon for a point agent).
    pub radius: f64,
    /// Angle turned through, radians: positive counter-clockwise.
    pub sweep: f64,
}

impl Path {
    /// Points along the path at most `step_m` metres apart (along arcs, following them), from
    /// the start to the goal.
    pub fn sampled(&self, step_m: f64) -> Vec<DVec2> {
        let step = if step_m > 0.0 { step_m } else { f64::INFINITY };
        let mut out = vec![self.points[0]];
        let line = |a: DVec2, b: DVec2, out: &mut Vec<DVec2>| {
            let n = (a.distance(b) / step).ceil().clamp(1.0, 1e6) as usize;
            out.extend((1..=n).map(|i| a.lerp(b, i as f64 / n as f64)));
        };
        for (i, bend) in self.bends.iter().enumerate() {
            let (a, b) = (self.points[2 * i], self.points[2 * i + 1]);
            line(a, b, &mut out);
            let from = (b - bend.center).y.atan2((b - bend.center).x);
            let n = (bend.radius * bend.sweep.abs() / step).ceil().clamp(1.0, 1e6) as usize;
            out.extend(
                (1..n).map(|k| bend.center + DVec2::from_angle(from + bend.sweep * k as f64 / n as f64) * bend.radius),
            );
            out.push(self.points[2 * i + 2]);
        }
        let k = self.points.len();
        line(self.points[k - 2], self.points[k - 1], &mut out);
        out
    }
}

/// Total length of the polyline through `points`, metres (0 for fewer than two points).
pub fn path_length(points: &[DVec2]) -> f64 {
    points.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// Shortest path for a disc of `agent_radius` metres from `start` to `goal` (metres) in `world`.
///
/// `None` when the start or the goal lies in the interior of a grown obstacle, when the two
/// are not connected, or when an input is not finite or the radius is negative. Builds a
/// [`Planner`] for one query; reuse a planner for many queries in the same world.
pub fn shortest_path(world: &World, start: DVec2, goal: DVec2, agent_radius: f64) -> Option<Path> {
    Planner::new(world, agent_radius)?.shortest_path(start, goal)
}

/// The tangent visibility graph of one world for one agent radius, reusable across queries
/// (and threads: what one search finds of the graph, every later one uses).
///
/// Tolerance: a point or segment counts as free when it keeps at least `agent_radius − ε`
/// metres from every part, where `ε = 1e-9 · max(1, largest coordinate magnitude of the
/// world)` metres; [`Planner::tolerance`] reports it.
#[derive(Debug, Clone)]
pub struct Planner {
    clearance: Clearance,
    graph: Graph,
    radius: f64,
    eps: f64,
}

/// A heap entry ordered so that [`BinaryHeap`] pops the smallest cost, then the smallest node.
#[derive(Debug, Clone, Copy)]
struct Entry {
    cost: f64,
    node: usize,
}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.cost.total_cmp(&self.cost).then_with(|| other.node.cmp(&self.node))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Entry {}

/// A state of the search: arrived on a rim by a leg.
#[derive(Debug, Clone, Copy)]
struct State {
    /// Length of the best way found here, metres.
    g: f64,
    /// The state the leg left from (`NONE`: the start).
    prev: usize,
    /// The leg.
    leg: Leg,
    /// The bending whose legs it is one of (`NONE`: the start's, already known clear).
    of: usize,
    closed: bool,
}

/// No state.
const NONE: usize = usize::MAX;

/// A rim and turn the search has bent round: where its legs' states begin, and the arrivals
/// already expanded there (where on the rim, and the length of the way there).
#[derive(Debug)]
struct Bending {
    rim: RimId,
    turn: Turn,
    base: usize,
    done: Vec<(Spot, f64)>,
}

impl Planner {
    /// Grows the parts of `world` by `agent_radius` metres and lays out the rims among them.
    /// `None` for a negative or non-finite radius, or coordinates outside the supported range.
    pub fn new(world: &World, agent_radius: f64) -> Option<Planner> {
        if !(agent_radius.is_finite() && agent_radius >= 0.0) {
            return None;
        }
        let scale = world.bounds().map_or(1.0, |b| b.min.abs().max_element().max(b.max.abs().max_element()).max(1.0));
        let eps = 1e-9 * scale;
        let clearance = Clearance::new(world, agent_radius, eps);
        let graph = Graph::new(&clearance)?;
        Some(Planner { clearance, graph, radius: agent_radius, eps })
    }

    /// The agent radius the planner was built for, metres.
    pub fn agent_radius(&self) -> f64 {
        self.radius
    }

    /// The clearance tolerance `ε`, metres.
    pub fn tolerance(&self) -> f64 {
        self.eps
    }

    /// Number of rims (corners of grown polygons and grown discs).
    pub fn rim_count(&self) -> usize {
        self.graph.rim_count()
    }

    /// Whether a disc of the agent radius centred at `p` (metres) overlaps no part by more than
    /// the tolerance.
    pub fn is_free(&self, p: DVec2) -> bool {
        self.clearance.point_free(p, None, &mut Vec::new())
    }

    /// Shortest path from `start` to `goal` (metres); see [`shortest_path`].
    pub fn shortest_path(&self, start: DVec2, goal: DVec2) -> Option<Path> {
        self.search(start, goal, true)
    }

    /// A* over the points where legs meet rims, with the straight-line distance to the goal as
    /// the heuristic; a rim's legs are found when the search first bends round it (with
    /// `cull`, kept for later searches and found with obstacles hidden behind nearer ones
    /// skipped; without, found afresh looking at every obstacle).
    fn search(&self, start: DVec2, goal: DVec2, cull: bool) -> Option<Path> {
        let (clearance, graph) = (&self.clearance, &self.graph);
        let mut scratch = Vec::new();
        if !clearance.point_free(start, None, &mut scratch) || !clearance.point_free(goal, None, &mut scratch) {
            return None;
        }
        if clearance.segment_clear(start, goal) {
            return Some(Path { points: vec![start, goal], bends: Vec::new(), length: start.distance(goal) });
        }
        let into_goal = graph.legs_to(clearance, goal, cull);
        if into_goal.is_empty() {
            return None;
        }
        let mut states: Vec<State> = graph
            .legs_from(clearance, start, cull)
            .into_iter()
            .map(|leg| State { g: leg.length, prev: NONE, leg, of: NONE, closed: false })
            .collect();
        let mut heap: BinaryHeap<Entry> =
            states.iter().enumerate().map(|(i, s)| Entry { cost: s.g + s.leg.at.distance(goal), node: i }).collect();
        let mut slot = vec![u32::MAX; 2 * graph.rim_count()];
        let mut bendings: Vec<Bending> = Vec::new();
        // Without culling, legs found afresh for this search alone.
        let fresh: Vec<OnceCell<Legs>> =
            (0..if cull { 0 } else { 2 * graph.rim_count() }).map(|_| OnceCell::new()).collect();
        let legs_of = |rim: RimId, turn: Turn| -> &Legs {
            match fresh.get(2 * rim as usize + turn as usize) {
                Some(cell) => cell.get_or_init(|| graph.find_legs(clearance, rim, turn, false)),
                None => graph.legs(clearance, rim, turn),
            }
        };
        // The best way into the goal: its length, the state it left from and the leg's angle.
        let mut best = (f64::INFINITY, NONE, 0.0);
        while let Some(Entry { node, .. }) = heap.pop() {
            if node == NONE {
                break;
            }
            let state = states[node];
            if state.closed {
                continue;
            }
            states[node].closed = true;
            // A leg's clearance is tested when a search first arrives by it.
            if let Some(b) = bendings.get(state.of)
                && !graph.leg_clear(clearance, b.rim, legs_of(b.rim, b.turn), node - b.base)
            {
                continue;
            }
            let (rim, turn) = (state.leg.to, state.leg.turn);
            let free = graph.free(clearance, rim);
            let Some(here) = free.locate(state.leg.arrive) else { continue };
            let radius = graph.circle(clearance, rim).radius;
            let key = 2 * rim as usize + turn as usize;
            if slot[key] == u32::MAX {
                let of = bendings.len();
                slot[key] = of as u32;
                bendings.push(Bending { rim, turn, base: states.len(), done: Vec::new() });
                states.extend(legs_of(rim, turn).list().iter().map(|&leg| State {
                    g: f64::INFINITY,
                    prev: NONE,
                    leg,
                    of,
                    closed: false,
                }));
            }
            let bending = &mut bendings[slot[key] as usize];
            // An arrival that an earlier one reaches along the rim for no more is spent.
            let spent = bending
                .done
                .iter()
                .any(|&(at, g)| free.sweep(at, here, turn).is_some_and(|sweep| g + radius * sweep <= state.g));
            if spent {
                continue;
            }
            bending.done.push((here, state.g));
            let base = bending.base;
            for (i, leg) in legs_of(rim, turn).list().iter().enumerate() {
                let Some(sweep) = free.locate(leg.leave).and_then(|out| free.sweep(here, out, turn)) else { continue };
                let g = state.g + radius * sweep + leg.length;
                let next = &mut states[base + i];
                if g < next.g {
                    next.g = g;
                    next.prev = node;
                    heap.push(Entry { cost: g + leg.at.distance(goal), node: base + i });
                }
            }
            if let Ok(k) = into_goal.binary_search_by(|l| (l.0, l.1).cmp(&(rim, turn))) {
                let (_, _, leave, length) = into_goal[k];
                if let Some(sweep) = free.locate(leave).and_then(|out| free.sweep(here, out, turn)) {
                    let g = state.g + radius * sweep + length;
                    if g < best.0 {
                        best = (g, node, leave);
                        heap.push(Entry { cost: g, node: NONE });
                    }
                }
            }
        }
        let (length, mut at, mut leave) = best;
        if at == NONE {
            return None;
        }
        // Back from the goal: each state's rim, from where its leg met it to where the next
        // leg left it.
        let mut points = vec![goal];
        let mut bends = Vec::new();
        while at != NONE {
            let state = &states[at];
            let rim = graph.circle(clearance, state.leg.to);
            let free = graph.free(clearance, state.leg.to);
            let sweep = free
                .locate(state.leg.arrive)
                .zip(free.locate(leave))
                .and_then(|(a, b)| free.sweep(a, b, state.leg.turn))
                .unwrap_or(0.0);
            points.push(rim.at(leave));
            points.push(state.leg.at);
            bends.push(Bend { center: rim.center, radius: rim.radius, sweep: state.leg.turn.sign() * sweep });
            leave = state.leg.leave;
            at = state.prev;
        }
        points.push(start);
        points.reverse();
        bends.reverse();
        Some(Path { points, bends, length })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::{Obstacle, ObstacleShape};

    #[test]
    fn heap_pops_smallest_cost_then_index() {
        let mut heap = BinaryHeap::new();
        for (cost, node) in [(2.0, 0), (1.0, 5), (1.0, 3), (0.5, 9)] {
            heap.push(Entry { cost, node });
        }
        let order: Vec<usize> = std::iter::from_fn(|| heap.pop()).map(|e| e.node).collect();
        assert_eq!(order, vec![9, 3, 5, 0]);
    }

    #[test]
    fn lengths() {
        assert_eq!(path_length(&[]), 0.0);
        assert_eq!(path_length(&[DVec2::ONE]), 0.0);
        assert_eq!(path_length(&[DVec2::ZERO, DVec2::new(3.0, 4.0), DVec2::new(3.0, 0.0)]), 9.0);
    }

    #[test]
    fn bad_input_gives_none() {
        let world = World::new(vec![
            Obstacle::build(ObstacleShape::Box { center: DVec2::ZERO, width: 2.0, height: 2.0, yaw: 0.0 }, 0.0, 1.0)
                .unwrap(),
        ]);
        let (a, b) = (DVec2::new(-5.0, 0.0), DVec2::new(5.0, 0.0));
        assert!(shortest_path(&world, a, b, f64::NAN).is_none());
        assert!(shortest_path(&world, a, b, -1.0).is_none());
        assert!(shortest_path(&world, DVec2::new(f64::NAN, 0.0), b, 0.3).is_none());
        assert!(shortest_path(&world, a, DVec2::new(0.0, f64::INFINITY), 0.3).is_none());
        // A point agent slides along the box edge.
        let p = shortest_path(&world, a, b, 0.0).unwrap();
        let expected = 2.0 * 17f64.sqrt() + 2.0;
        assert!((p.length - expected).abs() < 1e-12, "{p:?}");
        assert_eq!(p.bends.len(), 2);
        assert!(p.bends.iter().all(|b| b.radius == 0.0));
    }

    /// A small deterministic generator.
    fn xorshift(mut state: u64) -> impl FnMut() -> f64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn hiding_what_is_behind_nearer_obstacles_changes_no_leg() {
        // Dense worlds: boxes touching edge to edge (as map cells merge), overlapping boxes,
        // rotated boxes and cylinders; every rim's legs found skipping occluded obstacles must
        // be exactly those found looking at all of them, and so must the paths.
        let mut next = xorshift(0x1234_5678_9abc_def1);
        let mut found = 0;
        for round in 0..9 {
            let mut obstacles = Vec::new();
            for y in 0..10 {
                for x in 0..10 {
                    if next() < 0.3 {
                        let c = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                        let shape = match round % 3 {
                            0 => ObstacleShape::Box { center: c, width: 1.0, height: 1.0, yaw: 0.0 },
                            1 if next() < 0.5 => ObstacleShape::Cylinder { center: c, radius: 0.2 + 0.4 * next() },
                            _ => ObstacleShape::Box {
                                center: c,
                                width: 0.4 + next(),
                                height: 0.4 + next(),
                                yaw: next() * 3.0,
                            },
                        };
                        obstacles.push(Obstacle::build(shape, 0.0, 1.0).unwrap());
                    }
                }
            }
            let world = World::new(obstacles);
            let radius = [0.3, 0.1, 0.0][round % 3];
            let planner = Planner::new(&world, radius).unwrap();
            for k in 0..planner.rim_count() as RimId {
                for turn in Turn::BOTH {
                    let clear = |cull| {
                        let legs = planner.graph.find_legs(&planner.clearance, k, turn, cull);
                        (0..legs.list().len())
                            .filter(|&i| planner.graph.leg_clear(&planner.clearance, k, &legs, i))
                            .map(|i| legs.list()[i])
                            .collect::<Vec<Leg>>()
                    };
                    assert_eq!(clear(true), clear(false), "round {round}, rim {k}, {turn:?}");
                }
            }
            for _ in 0..6 {
                let a = DVec2::new(next() * 12.0 - 1.0, next() * 12.0 - 1.0);
                let b = DVec2::new(next() * 12.0 - 1.0, next() * 12.0 - 1.0);
                let culled = planner.search(a, b, true);
                let all = planner.search(a, b, false);
                assert_eq!(culled, all, "round {round}");
                found += usize::from(culled.is_some_and(|p| !p.bends.is_empty()));
            }
        }
        assert!(found >= 15, "{found}");
    }

    #[test]
    fn planner_reuse_matches_one_shot() {
        let world = World::new(vec![
            Obstacle::build(ObstacleShape::Cylinder { center: DVec2::ZERO, radius: 1.0 }, 0.0, 1.0).unwrap(),
        ]);
        let planner = Planner::new(&world, 0.3).unwrap();
        assert_eq!(planner.rim_count(), 1);
        assert!(!planner.is_free(DVec2::new(1.2, 0.0)) && planner.is_free(DVec2::new(1.31, 0.0)));
        let (a, b) = (DVec2::new(-4.0, 0.1), DVec2::new(4.0, -0.2));
        assert_eq!(planner.shortest_path(a, b), shortest_path(&world, a, b, 0.3));
    }
}
