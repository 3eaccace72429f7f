//! The upper-body planner (seed 002 §5; DESIGN.md §5): once the lower body's motion is fixed,
//! the waist and then each arm are planned, in that order, in configuration-time space so the
//! character bends under a low bar, twists past shelves and keeps its arms off what stands
//! beside the path.
//!
//! **Objective (§5.1).** Each part's preferred motion is the database's: the waist as the
//! clips hold it (erect) and the arms swinging against the legs. A configuration is an offset
//! from that motion ([`UpperConfig`]: waist bend and twist, each arm's shoulder flex, abduction
//! and twist and elbow bend), so the objective is the zero offset at every frame, and where
//! nothing is in the way the planned motion is the database's unchanged.
//!
//! **CT-roadmap (§5.2).** A node is a configuration at a frame time of the coming motion (the
//! pelvis trajectory of the interval about to play, sampled at the animation's frame rate, and
//! [`LOOK_AHEAD_S`] more going on with its mean motion, at [`LOOK_AHEAD_MIN_SPEED_MPS`] at
//! least, so a bend starts before the bar is reached). Configurations lie on a lattice whose spacing is the most a part may move in one
//! frame ([`WAIST_STEP_DEG`], [`ARM_STEP_DEG`]), so an edge joins a node only to neighbours at
//! the next frame, forward in time. The roadmap starts from the common moves — toward the
//! objective, holding, and one joint a step either way — and the best-first search takes the
//! free one closest to the objective. When every such advance fails, the roadmap grows: nodes
//! a distance `r` away that move two joints at once. When those fail too, the search
//! backtracks to the node before (Fig. 5). Every node is tried once. The waist is planned with
//! the torso and head; each arm then with its two capsules, the waist's plan fixed.
//!
//! **Collision.** Capsules ([`crate::anim::body`]) against the vertical prisms of the
//! obstacles ([`crate::geom::Prism`], exact signed distances), keeping [`MARGIN_M`]. The
//! waist's plan must be free over the whole look-ahead (ending where the waist joint itself
//! would run into something, which no bend or twist helps): a bend begun too late cannot be
//! made up, so a step that would lead there is refused while there is still room. The arms'
//! plans must be free over the interval and follow the look-ahead as far as it goes. When no plan exists the step is refused and the character does something else or
//! stands (seed 002 §3.2).
//!
//! The planner is pure and deterministic: plain vectors, a set used only for membership,
//! candidates in a fixed order.

use std::collections::HashSet;
use std::fmt;

use glam::DVec2;

use crate::anim::Pose;
use crate::anim::body::{Part, Parts, UpperBody, UpperConfig, UpperFrame};
use crate::geom::{Aabb, Capsule, Prism, Shape, SpatialIndex};
use crate::world::Obstacle;

/// Deepest forward bend of the waist, degrees.
pub const WAIST_BEND_MAX_DEG: f64 = 75.0;
/// Deepest backward lean of the waist, degrees.
pub const WAIST_LEAN_MAX_DEG: f64 = 10.0;
/// Largest twist of the waist either way, degrees.
pub const WAIST_TWIST_MAX_DEG: f64 = 90.0;
/// Most the waist moves in one frame (per joint), degrees: 180°/s at 60 frames/s.
pub const WAIST_STEP_DEG: f64 = 3.0;
/// Most an arm joint moves in one frame, degrees: 240°/s at 60 frames/s.
pub const ARM_STEP_DEG: f64 = 4.0;
/// Each arm's offsets from the database's motion, degrees, lowest and highest: shoulder flex
/// (forward), abduction (outward), twist, elbow bend.
pub const ARM_RANGE_DEG: [(f64, f64); 4] = [(-60.0, 100.0), (-12.0, 80.0), (-60.0, 60.0), (-20.0, 120.0)];
/// Room every capsule keeps from the obstacles, metres.
pub const MARGIN_M: f64 = 0.005;
/// Room the axis of every bone of the legs keeps from the obstacles over an interval, metres.
pub const LEG_ROOM_M: f64 = 0.01;
/// How far past the interval's end the planner looks ahead, seconds.
pub const LOOK_AHEAD_S: f64 = 1.0;
/// The look-ahead goes on at least this fast, metres per second (a walking pace), so even at
/// a crawl it reaches a bar from as far away as a bend must begin: bending down carries the
/// head some 0.6 m forward, so a bend begun with the bar that close is too late.
pub const LOOK_AHEAD_MIN_SPEED_MPS: f64 = 1.0;
/// Nodes one part's search may try before giving up.
pub const MAX_NODES: usize = 40_000;
/// Obstacles farther than this from the hips in the plan view cannot touch the upper body,
/// metres (the hand's reach with the waist bent, rounded up).
pub const NEAR_M: f64 = 1.3;

/// Why no plan was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// The waist found no free way through the interval.
    Waist,
    /// An arm (0 left, 1 right) found none, with the waist's plan.
    Arm(usize),
    /// The legs' motion (the database's, cross-fade included, which no offset of the upper
    /// body changes) carries a bone of a leg into an obstacle.
    Legs,
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Refusal::Waist => write!(f, "the waist cannot bend or twist clear of the obstacles"),
            Refusal::Arm(0) => write!(f, "the left arm cannot keep clear of the obstacles"),
            Refusal::Arm(_) => write!(f, "the right arm cannot keep clear of the obstacles"),
            Refusal::Legs => write!(f, "a leg would step into an obstacle"),
        }
    }
}

/// One obstacle part as the upper body meets it: a convex outline between two heights.
#[derive(Debug, Clone)]
struct Solid {
    shape: Shape,
    aabb: Aabb,
    z_min: f64,
    z_max: f64,
}

/// The obstacles the upper body can touch, indexed in the plan view.
#[derive(Debug, Clone)]
pub struct Solids {
    solids: Vec<Solid>,
    index: SpatialIndex,
}

impl Solids {
    /// The convex parts of `obstacles`.
    pub fn new<'a>(obstacles: impl IntoIterator<Item = &'a Obstacle>) -> Solids {
        let solids: Vec<Solid> = obstacles
            .into_iter()
            .flat_map(|o| {
                o.parts.iter().map(|s| Solid { shape: s.clone(), aabb: s.aabb(), z_min: o.z_min, z_max: o.z_max })
            })
            .collect();
        let boxes: Vec<Aabb> = solids.iter().map(|s| s.aabb).collect();
        Solids { index: SpatialIndex::build(&boxes), solids }
    }

    /// True when there is nothing.
    pub fn is_empty(&self) -> bool {
        self.solids.is_empty()
    }

    /// The least clearance between `capsules` and the solids listed in `near` (indices),
    /// capped at `horizon_m` ([`crate::anim::body::clearance`]).
    fn clearance(&self, capsules: &[(Part, Capsule)], near: &[usize], horizon_m: f64) -> f64 {
        let prisms = near.iter().map(|&i| {
            let s = &self.solids[i];
            (Prism { base: &s.shape, z_min: s.z_min, z_max: s.z_max }, s.aabb)
        });
        crate::anim::body::clearance(capsules, prisms, horizon_m).map_or(horizon_m, |(d, _)| d.min(horizon_m))
    }

    /// The least clearance of `capsules` from every solid near `at` (plan view), capped at
    /// `horizon_m`, metres (negative: that deep inside).
    pub fn clearance_near(
        &self,
        capsules: &[(Part, Capsule)],
        at: DVec2,
        horizon_m: f64,
        near: &mut Vec<usize>,
    ) -> f64 {
        self.index.query_circle(at, NEAR_M + horizon_m, near);
        self.clearance(capsules, near, horizon_m)
    }
}

/// A planned upper-body motion: the offsets at `h`-second steps from the plan's start.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// Offsets at `0, h, 2h, …` seconds.
    pub configs: Vec<UpperConfig>,
    /// Seconds between configurations.
    pub h: f64,
}

impl Plan {
    /// Holding `c` (a plan of one configuration).
    pub fn hold(c: UpperConfig, h: f64) -> Plan {
        Plan { configs: vec![c], h }
    }

    /// The offsets `t` seconds after the plan's start (linear between its steps; the last one
    /// after its end).
    pub fn at(&self, t: f64) -> UpperConfig {
        let Some(last) = self.configs.last() else { return UpperConfig::default() };
        let x = if t.is_finite() && self.h > 0.0 { (t / self.h).max(0.0) } else { 0.0 };
        let i = x.floor() as usize;
        if i + 1 >= self.configs.len() {
            return *last;
        }
        self.configs[i].lerp(&self.configs[i + 1], x - i as f64)
    }
}

/// Buffers the planner reuses from plan to plan.
#[derive(Debug, Clone, Default)]
pub struct Scratch {
    frames: Vec<UpperFrame>,
    near: Vec<Vec<usize>>,
    crowded: Vec<bool>,
    targets2: Vec<[i32; 2]>,
    targets4: Vec<[i32; 4]>,
    reach: Vec<u128>,
    query: Vec<usize>,
    caps: Vec<(Part, Capsule)>,
    visited2: HashSet<(u32, [i16; 2])>,
    visited4: HashSet<(u32, [i16; 4])>,
}

/// A lattice of configurations of one part: `unit` radians per step, bounds in steps.
struct Lattice<const D: usize> {
    lo: [i32; D],
    hi: [i32; D],
    unit: [f64; D],
}

impl<const D: usize> Lattice<D> {
    fn new(range_deg: [(f64, f64); D], step_deg: f64) -> Lattice<D> {
        Lattice {
            lo: range_deg.map(|(lo, _)| (lo / step_deg).ceil() as i32),
            hi: range_deg.map(|(_, hi)| (hi / step_deg).floor() as i32),
            unit: [step_deg.to_radians(); D],
        }
    }

    fn snap(&self, v: [f64; D]) -> [i32; D] {
        std::array::from_fn(|k| {
            let x = if v[k].is_finite() { (v[k] / self.unit[k]).round() } else { 0.0 };
            (x.clamp(f64::from(self.lo[k]), f64::from(self.hi[k]))) as i32
        })
    }

    fn value(&self, c: [i32; D]) -> [f64; D] {
        std::array::from_fn(|k| f64::from(c[k]) * self.unit[k])
    }

    fn inside(&self, c: &[i32; D]) -> bool {
        (0..D).all(|k| (self.lo[k]..=self.hi[k]).contains(&c[k]))
    }

    /// Squared distance between two configurations, in steps.
    fn cost(c: &[i32; D], to: &[i32; D]) -> i64 {
        c.iter().zip(to).map(|(&x, &y)| i64::from(x - y) * i64::from(x - y)).sum()
    }

    /// The moves from `c`, in the order the search tries them: the roadmap's common moves
    /// (toward `to`, holding, one joint a step) closest to `to` first, then the grown nodes
    /// (two joints at once), likewise.
    fn moves(&self, c: [i32; D], to: &[i32; D], out: &mut Vec<[i32; D]>) {
        out.clear();
        out.push(std::array::from_fn(|k| c[k] + (to[k] - c[k]).signum()));
        out.push(c);
        for k in 0..D {
            for d in [-1, 1] {
                let mut n = c;
                n[k] += d;
                out.push(n);
            }
        }
        let common = out.len();
        for i in 0..D {
            for j in i + 1..D {
                for (di, dj) in [(-1, -1), (-1, 1), (1, -1), (1, 1)] {
                    let mut n = c;
                    n[i] += di;
                    n[j] += dj;
                    out.push(n);
                }
            }
        }
        out[..common].sort_by_key(|n| Self::cost(n, to));
        out[common..].sort_by_key(|n| Self::cost(n, to));
    }

    /// The motion along one joint `k` alone (the others held at the objective) that stays
    /// free from `start` for as many frames up to `k_max` as any can, and among those the one
    /// nearest the objective: every value reachable at each frame, one step a frame, kept as a
    /// bit set (exact on that line of the lattice), then the path back from the last frame
    /// reached, nearest the objective at each frame. Returns the frames reached and the path.
    fn line(
        &self,
        k: usize,
        start: i32,
        k_max: usize,
        crowded: &[bool],
        legal: &mut dyn FnMut(usize, [i32; D]) -> bool,
        reach: &mut Vec<u128>,
    ) -> Vec<i32> {
        let (lo, hi) = (self.lo[k], self.hi[k]);
        let n = (hi - lo + 1).clamp(1, 128) as u32;
        let full = if n == 128 { u128::MAX } else { (1u128 << n) - 1 };
        let bit = |v: i32| 1u128 << (v - lo);
        reach.clear();
        reach.push(bit(start.clamp(lo, hi)));
        for t in 1..=k_max {
            let prev = reach[t - 1];
            let grown = (prev | (prev << 1) | (prev >> 1)) & full;
            let mut next = 0u128;
            if crowded[t] {
                let mut rest = grown;
                while rest != 0 {
                    let b = rest.trailing_zeros() as i32;
                    rest &= rest - 1;
                    let mut c = [0; D];
                    c[k] = lo + b;
                    if legal(t, c) {
                        next |= 1u128 << b;
                    }
                }
            } else {
                next = grown;
            }
            if next == 0 {
                break;
            }
            reach.push(next);
        }
        // Back from the last frame reached: the value nearest the objective each time.
        let nearest = |set: u128, around: Option<i32>| -> i32 {
            let mut best: Option<i32> = None;
            let mut rest = set;
            while rest != 0 {
                let v = lo + rest.trailing_zeros() as i32;
                rest &= rest - 1;
                if around.is_some_and(|a| (v - a).abs() > 1) {
                    continue;
                }
                if best.is_none_or(|b| v.abs() < b.abs()) {
                    best = Some(v);
                }
            }
            best.unwrap_or(around.unwrap_or(0))
        };
        let mut path = vec![0; reach.len()];
        let mut later = None;
        for t in (0..reach.len()).rev() {
            let v = nearest(reach[t], later);
            path[t] = v;
            later = Some(v);
        }
        path
    }

    /// The configurations the search steers toward, one per frame `0..=k_max`: the best of
    /// the one-joint motions ([`Lattice::line`]) — the one going deepest in time, then the one
    /// nearest the objective — so that a part starts moving early enough to be where it must
    /// be when it must (a bend begins before the bar is reached). Where it ends before
    /// `k_max`, the objective.
    fn targets(
        &self,
        start: [i32; D],
        k_max: usize,
        crowded: &[bool],
        legal: &mut dyn FnMut(usize, [i32; D]) -> bool,
        reach: &mut Vec<u128>,
        out: &mut Vec<[i32; D]>,
    ) {
        let mut best: Option<(usize, i64, usize, Vec<i32>)> = None;
        for (k, &from) in start.iter().enumerate() {
            let path = self.line(k, from, k_max, crowded, legal, reach);
            let deviation: i64 = path.iter().map(|&v| i64::from(v).abs()).sum();
            if best.as_ref().is_none_or(|b| path.len() > b.0 || (path.len() == b.0 && deviation < b.1)) {
                best = Some((path.len(), deviation, k, path));
            }
        }
        out.clear();
        out.resize(k_max + 1, [0; D]);
        if let Some((_, _, k, path)) = best {
            for (t, v) in path.into_iter().enumerate() {
                out[t][k] = v;
            }
        }
    }
}

/// Best-first search of the CT-roadmap of one part from `start` (at frame 0) steering toward
/// `targets` (one per frame): a path of lattice configurations, one per frame, as deep as
/// `k_max` if it can be, else as deep as it got if that is at least `k_min`.
fn search<const D: usize>(
    lattice: &Lattice<D>,
    start: [i32; D],
    targets: &[[i32; D]],
    k_min: usize,
    k_max: usize,
    visited: &mut HashSet<(u32, [i16; D])>,
    legal: &mut dyn FnMut(usize, [i32; D]) -> bool,
) -> Option<Vec<[i32; D]>> {
    visited.clear();
    let mut stack: Vec<([i32; D], usize)> = vec![(start, 0)];
    let mut best: Vec<[i32; D]> = vec![start];
    let mut moves = Vec::new();
    let mut nodes = 0usize;
    while let Some(&(c, next)) = stack.last() {
        let t = stack.len() - 1;
        if t >= k_max {
            return Some(stack.iter().map(|s| s.0).collect());
        }
        lattice.moves(c, &targets[t + 1], &mut moves);
        let mut i = next;
        let mut advanced = None;
        while i < moves.len() {
            let n = moves[i];
            i += 1;
            if !lattice.inside(&n) || !visited.insert((t as u32 + 1, n.map(|x| x as i16))) {
                continue;
            }
            nodes += 1;
            if legal(t + 1, n) {
                advanced = Some(n);
                break;
            }
            if nodes >= MAX_NODES {
                break;
            }
        }
        if let Some(top) = stack.last_mut() {
            top.1 = i;
        }
        match advanced {
            Some(n) => {
                stack.push((n, 0));
                if stack.len() > best.len() {
                    best.clear();
                    best.extend(stack.iter().map(|s| s.0));
                }
            }
            None if nodes >= MAX_NODES => break,
            None => {
                stack.pop();
            }
        }
    }
    (best.len() > k_min).then_some(best)
}

/// Plans the upper body of one skeleton among [`Solids`].
#[derive(Debug, Clone)]
pub struct UpperPlanner {
    body: UpperBody,
}

impl UpperPlanner {
    /// A planner for the body `body`.
    pub fn new(body: UpperBody) -> UpperPlanner {
        UpperPlanner { body }
    }

    /// The body planned for.
    pub fn body(&self) -> &UpperBody {
        &self.body
    }

    /// Plans the offsets over `poses` (world poses `h` seconds apart, the first where the plan
    /// starts; the first `own` of them must be kept clear, the rest are looked ahead over) from
    /// the offsets `start`, among `solids`.
    pub fn plan(
        &self,
        solids: &Solids,
        poses: &[Pose],
        own: usize,
        h: f64,
        start: &UpperConfig,
        s: &mut Scratch,
    ) -> Result<Plan, Refusal> {
        let own = own.clamp(1, poses.len().max(1));
        s.frames.clear();
        s.frames.extend(poses.iter().map(|p| self.body.frame(p)));
        s.near.resize_with(poses.len(), Vec::new);
        s.crowded.clear();
        let mut crowded = false;
        for (k, f) in s.frames.iter().enumerate() {
            let at = f.hips().truncate();
            solids.index.query_circle(at, NEAR_M, &mut s.query);
            let near = &mut s.near[k];
            near.clear();
            near.extend(s.query.iter().copied());
            s.crowded.push(!near.is_empty());
            crowded |= !near.is_empty();
        }
        if !crowded || poses.is_empty() {
            return Ok(self.relax(start, poses.len().max(1), h));
        }
        // The look-ahead ends before the first frame whose waist joint is too deep in something
        // for any bend or twist to help.
        let mut k_max = poses.len() - 1;
        for k in own..poses.len() {
            let waist = self.body.waist(&s.frames[k]);
            s.caps.clear();
            s.caps.push((Part::Torso, Capsule { a: waist, b: waist, radius: crate::anim::body::TORSO_RADIUS_M }));
            if solids.clearance(&s.caps, &s.near[k], MARGIN_M) < MARGIN_M {
                k_max = k - 1;
                break;
            }
        }
        // The legs play the database's motion over the interval: a bone of a leg that would go
        // into something (deeper than it starts, if it starts there) refuses the interval, as no
        // plan of the upper body changes it.
        let legs_room = |k: usize, caps: &mut Vec<(Part, Capsule)>| {
            self.body.place(&s.frames[k], &UpperConfig::default(), Parts::Legs, caps);
            caps.iter_mut().for_each(|(_, c)| c.radius = 0.0);
            solids.clearance(caps, &s.near[k], LEG_ROOM_M)
        };
        let legs_need = legs_room(0, &mut s.caps).min(LEG_ROOM_M) - 1e-9;
        if (1..own).any(|k| s.crowded[k] && legs_room(k, &mut s.caps) < legs_need) {
            return Err(Refusal::Legs);
        }
        let k_min = own - 1;
        let waist_lattice = Lattice::<2>::new(
            [(-WAIST_LEAN_MAX_DEG, WAIST_BEND_MAX_DEG), (-WAIST_TWIST_MAX_DEG, WAIST_TWIST_MAX_DEG)],
            WAIST_STEP_DEG,
        );
        let (frames, near, caps, busy) = (&s.frames, &s.near, &mut s.caps, &s.crowded);
        let body = &self.body;
        // A part that starts closer than the margin (the played motion strayed from the plan)
        // may keep what room it has, never less: the plan takes it out rather than leaving it
        // held where it is.
        let room_at_start = |which: Parts, c: &UpperConfig, caps: &mut Vec<(Part, Capsule)>| {
            body.place(&frames[0], c, which, caps);
            solids.clearance(caps, &near[0], MARGIN_M).min(MARGIN_M) - 1e-9
        };
        let arm_lattice = Lattice::<4>::new(ARM_RANGE_DEG, ARM_STEP_DEG);
        let start_cfg = UpperConfig {
            waist: waist_lattice.value(waist_lattice.snap(start.waist)),
            arms: start.arms.map(|a| arm_lattice.value(arm_lattice.snap(a))),
        };
        let arm_need = [0, 1].map(|side| room_at_start(Parts::Arm(side), &start_cfg, caps));
        // The waist is planned first with the arms as the database moves them (so it twists
        // or bends far enough for them too), and if that finds no way, with the shoulders alone
        // (the arms' own plans then have to move them clear).
        let mut waist = None;
        for which in [Parts::TrunkAndArms, Parts::Trunk] {
            let plain = UpperConfig { waist: start_cfg.waist, ..Default::default() };
            let need = room_at_start(which, &plain, caps);
            let mut legal = |t: usize, c: [i32; 2]| {
                let cfg = UpperConfig { waist: waist_lattice.value(c), ..Default::default() };
                body.place(&frames[t], &cfg, which, caps);
                solids.clearance(caps, &near[t], MARGIN_M) >= need
            };
            let start = waist_lattice.snap(start.waist);
            waist_lattice.targets(start, k_max, busy, &mut legal, &mut s.reach, &mut s.targets2);
            // The waist must see its way through the whole look-ahead: a bend begun too late
            // cannot be made up, and a step that leads there is refused while there is time.
            waist = search(&waist_lattice, start, &s.targets2, k_max, k_max, &mut s.visited2, &mut legal);
            if waist.is_some() {
                break;
            }
        }
        let waist = waist.ok_or(Refusal::Waist)?;
        let mut configs: Vec<UpperConfig> =
            waist.iter().map(|&c| UpperConfig { waist: waist_lattice.value(c), ..Default::default() }).collect();
        for (side, need) in arm_need.into_iter().enumerate() {
            let reached = configs.len() - 1;
            let path = {
                let configs = &configs;
                let mut legal = |t: usize, c: [i32; 4]| {
                    let mut cfg = configs[t];
                    cfg.arms[side] = arm_lattice.value(c);
                    body.place(&frames[t], &cfg, Parts::Arm(side), caps);
                    solids.clearance(caps, &near[t], MARGIN_M) >= need
                };
                let start = arm_lattice.snap(start.arms[side]);
                arm_lattice.targets(start, reached, busy, &mut legal, &mut s.reach, &mut s.targets4);
                search(&arm_lattice, start, &s.targets4, k_min, reached, &mut s.visited4, &mut legal)
                    .ok_or(Refusal::Arm(side))?
            };
            configs.truncate(path.len());
            for (cfg, c) in configs.iter_mut().zip(path) {
                cfg.arms[side] = arm_lattice.value(c);
            }
        }
        Ok(Plan { configs, h })
    }

    /// Nothing near: every part returns toward the objective as fast as it may, over `frames`.
    fn relax(&self, start: &UpperConfig, frames: usize, h: f64) -> Plan {
        let (w, a) = (WAIST_STEP_DEG.to_radians(), ARM_STEP_DEG.to_radians());
        let toward = |x: f64, step: f64| if x.abs() <= step { 0.0 } else { x - step * x.signum() };
        let mut c = *start;
        let mut configs = Vec::with_capacity(frames);
        configs.push(c);
        for _ in 1..frames {
            c.waist = c.waist.map(|x| toward(x, w));
            c.arms = c.arms.map(|arm| arm.map(|x| toward(x, a)));
            configs.push(c);
        }
        Plan { configs, h }
    }
}

/// The lowest the top of the built-in actor's body can be brought by bending the waist fully,
/// standing, metres (the duck height).
pub fn duck_height_m() -> f64 {
    duck_height_of(&crate::anim::actor::actor()).unwrap_or(f64::NAN)
}

/// [`duck_height_m`] of a skeleton the upper-body planner knows (`None` for any other).
pub fn duck_height_of(s: &crate::anim::Skeleton) -> Option<f64> {
    let body = UpperBody::of(s)?;
    let bent = UpperConfig { waist: [WAIST_BEND_MAX_DEG.to_radians(), 0.0], ..Default::default() };
    let mut caps = Vec::new();
    body.place(&body.frame(&s.bind_pose()), &bent, Parts::Trunk, &mut caps);
    Some(crate::anim::body::top(&caps))
}

/// Room a ducking body keeps under an overhead obstacle, metres: an obstacle whose underside
/// is lower than the duck height and this is a wall for the character's navigation.
pub const DUCK_ROOM_M: f64 = 0.05;

#[cfg(test)]
mod tests {
    use glam::{DQuat, DVec3};

    use super::*;
    use crate::anim::actor;
    use crate::world::ObstacleShape;

    const H: f64 = 1.0 / 60.0;

    /// The bind pose walking along +X at `speed` from `x0`, `n` frames.
    fn walk(x0: f64, speed: f64, n: usize) -> Vec<Pose> {
        let s = actor::actor();
        (0..n)
            .map(|k| {
                let mut p = s.bind_pose();
                p.root = DVec3::new(x0 + speed * H * k as f64, 0.0, p.root.z);
                p.rotations[0] = DQuat::IDENTITY;
                p
            })
            .collect()
    }

    fn bar(x: f64, z_min: f64, depth: f64) -> Obstacle {
        Obstacle::build(
            ObstacleShape::Box { center: DVec2::new(x, 0.0), width: depth, height: 2.0, yaw: 0.0 },
            z_min,
            z_min + 0.1,
        )
        .unwrap()
    }

    fn planner() -> UpperPlanner {
        UpperPlanner::new(UpperBody::of(&actor::actor()).unwrap())
    }

    /// Every planned frame keeps the margin, by the capsules of the poses with the offsets
    /// applied.
    fn assert_clear(poses: &[Pose], plan: &Plan, solids: &Solids) {
        let p = planner();
        let mut caps = Vec::new();
        let mut near = Vec::new();
        for (k, c) in plan.configs.iter().enumerate() {
            let mut pose = poses[k].clone();
            p.body().apply(&mut pose, c);
            p.body().capsules(&pose, &mut caps);
            let d = solids.clearance_near(&caps, pose.root.truncate(), 1.0, &mut near);
            assert!(d >= MARGIN_M - 1e-9, "frame {k}: clearance {d} with {c:?}");
        }
    }

    #[test]
    fn the_actor_ducks_to_a_metre_and_a_third() {
        let d = duck_height_m();
        assert!((1.25..1.35).contains(&d), "duck height {d}");
    }

    #[test]
    fn nothing_near_leaves_the_database_motion_alone() {
        let solids = Solids::new(&[bar(50.0, 1.45, 0.1)]);
        let poses = walk(0.0, 1.3, 40);
        let plan = planner().plan(&solids, &poses, 30, H, &UpperConfig::default(), &mut Scratch::default()).unwrap();
        assert!(plan.configs.iter().all(|c| *c == UpperConfig::default()));
    }

    #[test]
    fn the_waist_bends_under_a_bar_and_straightens_after_it() {
        let bar = bar(1.5, 1.45, 0.1);
        let solids = Solids::new([&bar]);
        let p = planner();
        let mut s = Scratch::default();
        let mut c = UpperConfig::default();
        let mut deepest = 0.0f64;
        // Walk 3 m in intervals of 30 frames, each planned with 30 frames of look-ahead.
        for i in 0..7 {
            let poses = walk(i as f64 * 30.0 * H * 1.3, 1.3, 91);
            let plan = p.plan(&solids, &poses, 31, H, &c, &mut s).unwrap_or_else(|r| panic!("interval {i}: {r}"));
            assert!(plan.configs.len() >= 31);
            assert_clear(&poses, &plan, &solids);
            deepest = plan.configs[..31].iter().fold(deepest, |d, c| d.max(c.waist[0]));
            c = plan.configs[30];
        }
        assert!(deepest > 50f64.to_radians(), "deepest bend {}°", deepest.to_degrees());
        assert!(c.waist[0] < 1e-9, "erect again: {c:?}");
    }
}
